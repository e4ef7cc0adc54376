"""Imports of the package point down its layers and form no cycle.

Run as a script (``python tests/test_import_layers.py``) it prints every module's imports of
other blurloc modules and the edges that break the layering (none expected).
"""

from __future__ import annotations

import ast
import graphlib
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[1] / "src" / "blurloc"

#: Layers from the bottom up; a module may import modules of its own layer or of lower ones.
#: A name stands for the module and everything under it; the longest matching name wins.
LAYERS = (
    (
        "errors",
        "image_headers",
        "files",
        "images",
        "processes",
        "poses",
        "paper",
        "intervals",
        "tables",
        "config",
        "stored",
    ),
    ("geometry",),
    ("blur", "metrics"),
    ("deconv",),
    ("video_wiener",),
    ("batch_deblur",),
    ("data", "trajectory"),
    ("models", "checkpoints"),
    ("train.config", "train.datasets", "train.loop"),
    ("inference",),
    ("train",),
    ("experiments",),
    ("plots",),
    ("reproduction", "publish", "runner", "notebook", "cli"),
)


def module_name(path: Path) -> str:
    """Dotted name of a module file of the package (``blurloc.blur.kernels``)."""
    parts = path.relative_to(PACKAGE_DIR.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(path: Path) -> set[str]:
    """The blurloc modules a module file imports (relative imports resolved)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if node.module is None:  # ``from . import name``: the submodules (or the package)
                found |= {f"{target}.{alias.name}" for alias in node.names}
            else:
                found.add(target)
        elif isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
    return {target for target in found if target.split(".")[0] == "blurloc"}


def import_graph() -> dict[str, set[str]]:
    """Every module of the package and the blurloc modules it imports."""
    return {module_name(path): imported_modules(path) for path in PACKAGE_DIR.rglob("*.py")}


def layer(module: str) -> int:
    """Index in LAYERS of a module (by its longest listed prefix); the package itself is 0."""
    relative = module.removeprefix("blurloc").removeprefix(".")
    best, best_length = 0, -1
    for index, names in enumerate(LAYERS):
        for name in names:
            if (relative == name or relative.startswith(name + ".")) and len(name) > best_length:
                best, best_length = index, len(name)
    return best


def upward_edges(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Imports from a module to one of a higher layer."""
    return sorted(
        (module, target)
        for module, targets in graph.items()
        for target in targets
        if layer(target) > layer(module)
    )


def test_every_module_has_a_layer() -> None:
    listed = {name for names in LAYERS for name in names}
    top_level = {module_name(path).split(".")[1] for path in PACKAGE_DIR.rglob("*.py")
                 if path.parent != PACKAGE_DIR or path.name != "__init__.py"}  # fmt: skip
    assert top_level <= {name.split(".")[0] for name in listed}


def test_imports_point_down() -> None:
    assert upward_edges(import_graph()) == []


def test_imports_form_no_cycle() -> None:
    graphlib.TopologicalSorter(import_graph()).prepare()  # raises CycleError on a cycle


def test_layering_catches_an_upward_import() -> None:
    graph = {"blurloc.blur.kernels": {"blurloc.data.synth"}, "blurloc.data.synth": set()}
    assert upward_edges(graph) == [("blurloc.blur.kernels", "blurloc.data.synth")]


if __name__ == "__main__":
    graph = import_graph()
    for module in sorted(graph, key=lambda name: (layer(name), name)):
        targets = ", ".join(sorted(target.removeprefix("blurloc.") for target in graph[module]))
        print(f"[{layer(module):2d}] {module.removeprefix('blurloc.')} -> {targets}")
    print("upward edges:", upward_edges(graph) or "none")
