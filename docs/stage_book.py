"""Stage the book's sources for MkDocs in the repository's own layout.

The book's entry page is the README; beside it go the pages of ``docs/``, the executed
notebooks and every file those pages link to (figures, their tables, ``LICENSE``, ...), each at
the path it has in the repository, so every relative link resolves in the book as it does in
the repository. The one link that cannot, the README's link to the built book itself, is
pointed at the entry page. Where Debian's ``libjs-mathjax`` is installed, the parts of
MathJax 2 that typeset the notebooks' TeX go to ``assets/mathjax/`` (about 2 MB), so the
equations render without fetching anything; without it they show as TeX source. A notebook
figure's alternative text (``metadata["image/png"]["alt"]`` of its output, which the notebook
renderer of the book does not read) is carried into the page as the image's ``alt``.

Usage: ``python docs/stage_book.py build/book-src`` (``make docs`` runs it, then MkDocs).
"""

from __future__ import annotations

import argparse
import html
import json
import re
import shutil
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[1]
#: The Markdown pages of the book, relative to the repository.
PAGE_PATTERNS = ("README.md", "docs/*.md")
#: The executed notebooks of the last full run, one book page each.
NOTEBOOK_PATTERN = "notebooks/executed/*.ipynb"
#: Where the README links the built book; in the book that page is the README itself.
BOOK_ENTRY_LINK = "build/site/index.html"
#: Debian's MathJax 2 (package ``libjs-mathjax``), and the parts the notebooks' pages load.
MATHJAX_SOURCE = Path("/usr/share/javascript/mathjax")
MATHJAX_PARTS = (
    "MathJax.js",
    "config/TeX-AMS_CHTML.js",
    "extensions",
    "jax/element",
    "jax/input/TeX",
    "jax/output/CommonHTML",
    "fonts/HTML-CSS/TeX/woff",
)
MATHJAX_TARGET = Path("assets/mathjax")
MARKDOWN_LINK = re.compile(r"\]\(([^)\s]+)\)")


def markdown_pages(repository: Path = REPOSITORY) -> list[Path]:
    """List the Markdown pages of the book.

    Parameters
    ----------
    repository : Path
        The repository's root.

    Returns
    -------
    list of Path
        The README, then the pages of ``docs/`` in name order.
    """
    return [page for pattern in PAGE_PATTERNS for page in sorted(repository.glob(pattern))]


def relative_link_targets(page: Path) -> list[str]:
    """Return the relative link targets of a Markdown page, without their ``#`` anchors.

    Parameters
    ----------
    page : Path
        A Markdown file.

    Returns
    -------
    list of str
        Each link or image target that is neither a URL, an e-mail address nor an anchor on
        the same page, as written (relative to the page's folder), in the order they appear.
    """
    targets = []
    for target in MARKDOWN_LINK.findall(page.read_text(encoding="utf-8")):
        if re.match(r"[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue
        targets.append(target.split("#", 1)[0])
    return targets


def stage_mathjax(out: Path, source: Path = MATHJAX_SOURCE) -> bool:
    """Copy the parts of MathJax 2 that typeset TeX as CommonHTML into the book.

    Parameters
    ----------
    out : Path
        The staged book's folder; MathJax goes to ``assets/mathjax/`` inside it.
    source : Path
        An installed MathJax 2 (Debian's ``libjs-mathjax`` by default).

    Returns
    -------
    bool
        Whether MathJax was found and copied.
    """
    if not (source / "MathJax.js").is_file():
        return False
    for part in MATHJAX_PARTS:
        origin, destination = source / part, out / MATHJAX_TARGET / part
        destination.parent.mkdir(parents=True, exist_ok=True)
        if origin.is_dir():
            shutil.copytree(origin, destination, symlinks=False)
        else:
            shutil.copy2(origin, destination)
    return True


def images_with_alt(notebook: dict) -> dict:
    """Give every PNG output that has alternative text an HTML form ``<img alt=...>`` too.

    The book's notebook renderer shows an output's HTML before its PNG, and its PNG template
    drops the ``alt`` that the output's metadata carries; the HTML form keeps it.

    Parameters
    ----------
    notebook : dict
        An executed notebook (nbformat 4 JSON); changed in place.

    Returns
    -------
    dict
        The same notebook.
    """
    for cell in notebook.get("cells", []):
        for output in cell.get("outputs", []):
            data = output.get("data", {})
            alt = output.get("metadata", {}).get("image/png", {}).get("alt")
            if "image/png" in data and alt and "text/html" not in data:
                png = "".join(data["image/png"]).replace("\n", "")
                data["text/html"] = (f'<img src="data:image/png;base64,{png}" '
                                     f'alt="{html.escape(alt, quote=True)}">')  # fmt: skip
    return notebook


def stage(out: Path, repository: Path = REPOSITORY) -> list[Path]:
    """Copy the book's pages, notebooks and linked files into a fresh folder.

    Parameters
    ----------
    out : Path
        The folder to stage into; emptied first.
    repository : Path
        The repository's root.

    Returns
    -------
    list of Path
        The staged files, relative to ``out``.

    Raises
    ------
    FileNotFoundError
        If a page links to a file that does not exist (links into ``build/`` excepted: the
        book itself is built there).
    """
    if out.exists():
        shutil.rmtree(out)
    sources = markdown_pages(repository) + sorted(repository.glob(NOTEBOOK_PATTERN))
    for page in markdown_pages(repository):
        for target in relative_link_targets(page):
            path = (page.parent / target).resolve()
            if path.relative_to(repository).parts[0] == "build":
                continue
            if not path.is_file():
                raise FileNotFoundError(f"{page.relative_to(repository)} links to {target}")
            sources.append(path)
    staged = []
    for source in dict.fromkeys(sources):
        relative = source.relative_to(repository)
        destination = out / relative
        destination.parent.mkdir(parents=True, exist_ok=True)
        if relative.match(NOTEBOOK_PATTERN):
            notebook = images_with_alt(json.loads(source.read_text(encoding="utf-8")))
            destination.write_text(json.dumps(notebook, indent=1, ensure_ascii=False) + "\n",
                                   encoding="utf-8")  # fmt: skip
        else:
            shutil.copy2(source, destination)
        staged.append(relative)
    readme = out / "README.md"
    readme.write_text(
        readme.read_text(encoding="utf-8").replace(f"]({BOOK_ENTRY_LINK})", "](README.md)"),
        encoding="utf-8",
    )
    return staged


def main() -> None:
    """Stage the book into the folder given on the command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="folder to stage into (emptied first)")
    out = parser.parse_args().out
    staged = stage(out)
    mathjax = "with MathJax" if stage_mathjax(out) else "without MathJax (TeX shown as source)"
    print(f"staged {len(staged)} files, {mathjax}")


if __name__ == "__main__":
    main()
