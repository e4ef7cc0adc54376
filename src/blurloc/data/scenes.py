"""The seven indoor scenes of the stand-in, named after the 7-Scenes ones.

World frame: metres, z up, floor at z = 0. Each scene is a room of textured planes with
furniture made of boxes, lit by a few lamps, and has its own character: a chessboard on a table
(chess), a brick fireplace (fire), a small desk corner with a head (heads), desks and screens
(office), a pumpkin on a cabinet (pumpkin), a long kitchen (redkitchen), a staircase (stairs).
Its surfaces are tiled photographs, or painted with a real room's edges added
(:func:`make_scene`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .layout import SCENE_NAMES
from .render import Light, Quad, Scene
from .textures import PAINTED

Vec = tuple[float, float, float]

# Tints (linear-light multipliers) that give grey photographs a material colour.
WOOD = (0.75, 0.48, 0.26)
PLASTER = (0.85, 0.82, 0.75)
CARPET = (0.45, 0.5, 0.6)
TERRACOTTA = (0.9, 0.45, 0.3)
STEEL = (0.7, 0.72, 0.75)
ORANGE = (1.0, 0.45, 0.08)
DARK = (0.18, 0.18, 0.2)


def _quad(
    origin: Vec,
    edge_u: Vec,
    edge_v: Vec,
    texture: str,
    metres_per_tile: float | None = None,
    tint: Vec = (1.0, 1.0, 1.0),
) -> Quad:
    """A quad whose texture tiles every ``metres_per_tile`` (None: stretched once over it)."""
    if metres_per_tile is None:
        repeat = (1.0, 1.0)
    else:
        repeat = (
            float(np.linalg.norm(edge_u)) / metres_per_tile,
            float(np.linalg.norm(edge_v)) / metres_per_tile,
        )
    return Quad(
        tuple(map(float, origin)),
        tuple(map(float, edge_u)),
        tuple(map(float, edge_v)),
        texture,
        repeat,
        tint,
    )


def room(
    width: float,
    depth: float,
    height: float,
    floor: tuple,
    walls: tuple,
    ceiling: tuple = ("gravel", 1.0, PLASTER),
) -> list[Quad]:
    """Floor, ceiling and four walls of a room spanning [0, width] x [0, depth] x [0, height].

    ``floor``, ``walls`` and ``ceiling`` are (texture, metres per tile, tint).
    """
    w, d, h = width, depth, height
    return [
        _quad((0, 0, 0), (w, 0, 0), (0, d, 0), *floor),
        _quad((0, 0, h), (w, 0, 0), (0, d, 0), *ceiling),
        _quad((0, 0, h), (w, 0, 0), (0, 0, -h), *walls),  # y = 0
        _quad((w, d, h), (-w, 0, 0), (0, 0, -h), *walls),  # y = d
        _quad((0, d, h), (0, -d, 0), (0, 0, -h), *walls),  # x = 0
        _quad((w, 0, h), (0, d, 0), (0, 0, -h), *walls),  # x = w
    ]


def box(
    corner: Vec,
    size: Vec,
    texture: str,
    metres_per_tile: float | None = 0.5,
    tint: Vec = (1.0, 1.0, 1.0),
    bottom: bool = False,
) -> list[Quad]:
    """An axis-aligned box from ``corner`` (min x, y, z) of ``size``; bottom face optional."""
    x, y, z = corner
    sx, sy, sz = size
    faces = [
        _quad((x, y, z + sz), (sx, 0, 0), (0, sy, 0), texture, metres_per_tile, tint),  # top
        _quad((x, y, z + sz), (sx, 0, 0), (0, 0, -sz), texture, metres_per_tile, tint),
        _quad((x + sx, y + sy, z + sz), (-sx, 0, 0), (0, 0, -sz), texture, metres_per_tile, tint),
        _quad((x, y + sy, z + sz), (0, -sy, 0), (0, 0, -sz), texture, metres_per_tile, tint),
        _quad((x + sx, y, z + sz), (0, sy, 0), (0, 0, -sz), texture, metres_per_tile, tint),
    ]
    if bottom:
        faces.append(_quad((x, y, z), (sx, 0, 0), (0, sy, 0), texture, metres_per_tile, tint))
    return faces


def wall_picture(
    center: Vec,
    normal_axis: str,
    width: float,
    height: float,
    texture: str,
    tint: Vec = (1.0, 1.0, 1.0),
    offset: float = 0.005,
) -> Quad:
    """A picture hung ``offset`` metres in front of a wall; ``normal_axis`` is the wall's
    inward normal."""
    cx, cy, cz = center
    axis = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0)}[normal_axis]
    ox, oy, oz = (offset * a for a in axis)
    if normal_axis in ("+y", "-y"):
        sign = 1 if normal_axis == "+y" else -1
        edge_u = (sign * width, 0, 0)
    else:
        sign = -1 if normal_axis == "+x" else 1
        edge_u = (0, sign * width, 0)
    origin = (cx + ox - edge_u[0] / 2, cy + oy - edge_u[1] / 2, cz + oz + height / 2)
    return _quad(origin, edge_u, (0, 0, -height), texture, None, tint)


def _lights(*positions: Vec, power: float = 3.2) -> tuple[Light, ...]:
    return tuple(Light(tuple(map(float, p)), power) for p in positions)


def chess() -> Scene:
    """A chessboard with pieces on a wooden table in the middle of a room."""
    quads = room(5.0, 4.0, 2.6, ("gravel", 0.6, CARPET), ("brick", 0.8, PLASTER))
    quads += box((1.9, 1.6, 0.0), (1.2, 0.8, 0.74), "grass", 0.4, WOOD)
    quads.append(_quad((2.275, 1.775, 0.742), (0.45, 0, 0), (0, 0.45, 0), "checker", None))
    rng = np.random.default_rng(7)
    for i in range(8):
        col, row = rng.integers(0, 8, size=2)
        tint = (0.9, 0.88, 0.8) if i % 2 else (0.08, 0.07, 0.06)
        height = 0.04 + 0.03 * rng.random()
        quads += box(
            (2.285 + col * 0.05625, 1.785 + row * 0.05625, 0.742),
            (0.036, 0.036, height),
            "moon",
            None,
            tint,
        )
    quads += [
        wall_picture((2.5, 3.99, 1.5), "-y", 1.2, 0.8, "chelsea"),
        wall_picture((4.99, 2.0, 1.4), "-x", 1.0, 1.0, "colorwheel"),
        wall_picture((0.01, 2.0, 1.5), "+x", 1.2, 0.8, "astronaut"),
    ]
    quads += box((0.2, 3.4, 0.0), (1.2, 0.45, 1.6), "grass", 0.4, WOOD)
    return Scene(
        "chess",
        tuple(quads),
        _lights((2.5, 2.0, 2.4), (1.0, 0.8, 2.3)),
    )


def fire() -> Scene:
    """A brick fireplace with a dark hearth and a mantelpiece carrying a clock and a picture."""
    quads = room(4.5, 4.0, 2.7, ("gravel", 0.5, TERRACOTTA), ("brick", 0.7, PLASTER))
    quads += box((1.4, 3.5, 0.0), (1.7, 0.5, 1.1), "brick", 0.5, TERRACOTTA)
    quads.append(_quad((1.85, 3.495, 0.75), (0.8, 0, 0), (0, 0, -0.75), "hubble", None, DARK))
    quads += box((1.3, 3.4, 1.1), (1.9, 0.6, 0.08), "grass", 0.3, WOOD)
    quads += box((1.6, 3.6, 1.18), (0.3, 0.12, 0.3), "moon", None, STEEL)
    quads.append(_quad((1.6, 3.595, 1.48), (0.3, 0, 0), (0, 0, -0.3), "clock", None))
    quads.append(wall_picture((2.25, 3.99, 1.85), "-y", 0.9, 0.6, "coffee"))
    quads += box((0.3, 2.6, 0.0), (0.9, 0.9, 0.45), "coins", 0.45, (0.6, 0.2, 0.2))
    quads.append(wall_picture((0.01, 1.8, 1.5), "+x", 1.0, 0.7, "rocket"))
    return Scene(
        "fire",
        tuple(quads),
        _lights((2.2, 2.0, 2.5), (3.8, 0.8, 2.0)),
    )


def heads() -> Scene:
    """A small desk corner: a desk against two walls, a head, a screen and a mat; seen close."""
    quads = room(2.2, 2.0, 2.5, ("gravel", 0.5, CARPET), ("gravel", 0.9, PLASTER))
    quads += box((0.9, 1.2, 0.0), (1.3, 0.8, 0.72), "grass", 0.35, WOOD)
    quads += box((1.55, 1.55, 0.72), (0.2, 0.22, 0.26), "astronaut", None)
    quads += box((1.0, 1.8, 0.72), (0.45, 0.08, 0.32), "page", None)
    quads.append(_quad((1.1, 1.3, 0.722), (0.35, 0, 0), (0, 0.3, 0), "coins", None))
    quads.append(wall_picture((1.55, 1.99, 1.3), "-y", 0.6, 0.4, "ihc"))
    quads.append(wall_picture((2.19, 1.5, 1.2), "-x", 0.5, 0.5, "chelsea"))
    return Scene(
        "heads",
        tuple(quads),
        _lights((1.2, 1.0, 2.3), power=2.4),
    )


def office() -> Scene:
    """An office: two desks with screens and papers, a bookshelf, a window-like poster."""
    quads = room(6.0, 5.0, 2.7, ("gravel", 0.4, CARPET), ("gravel", 1.0, PLASTER))
    for x in (1.0, 3.4):
        quads += box((x, 3.6, 0.0), (1.6, 0.8, 0.74), "grass", 0.4, WOOD)
        quads += box((x + 0.5, 4.1, 0.74), (0.6, 0.06, 0.4), "text", None)
        quads.append(_quad((x + 0.15, 3.7, 0.742), (0.3, 0, 0), (0, 0.21, 0), "page", None))
    quads += box((0.1, 1.2, 0.0), (0.4, 1.6, 2.0), "colorwheel", 0.5)
    quads.append(wall_picture((3.0, 4.99, 1.7), "-y", 1.6, 0.9, "rocket"))
    quads.append(wall_picture((5.99, 2.5, 1.5), "-x", 1.0, 0.8, "camera"))
    quads += box((2.0, 2.2, 0.0), (0.5, 0.5, 0.45), "coins", None, DARK)
    return Scene(
        "office",
        tuple(quads),
        _lights((2.0, 2.5, 2.6), (4.5, 3.0, 2.6)),
    )


def pumpkin() -> Scene:
    """A pumpkin on a cabinet, with shelves and posters around it."""
    quads = room(4.0, 4.0, 2.6, ("gravel", 0.5, (0.5, 0.45, 0.4)), ("brick", 1.2, (0.7, 0.75, 0.8)))
    quads += box((1.4, 3.3, 0.0), (1.2, 0.6, 0.9), "grass", 0.4, WOOD)
    quads += box((1.8, 3.45, 0.9), (0.36, 0.34, 0.3), "coffee", None, ORANGE)
    quads += box((0.1, 2.6, 0.0), (0.5, 1.3, 1.8), "colorwheel", 0.6, (0.8, 0.8, 0.8))
    quads.append(wall_picture((2.0, 3.99, 1.75), "-y", 1.0, 0.7, "ihc"))
    quads.append(wall_picture((3.99, 2.2, 1.4), "-x", 0.9, 0.9, "hubble"))
    quads += box((3.0, 3.3, 0.0), (0.8, 0.6, 1.2), "brick", 0.4, STEEL)
    return Scene(
        "pumpkin",
        tuple(quads),
        _lights((2.0, 2.0, 2.5), (0.8, 1.0, 2.3)),
    )


def redkitchen() -> Scene:
    """A long kitchen: a row of red cabinets under a tiled splashback, wall cabinets, a fridge."""
    red = (0.75, 0.12, 0.1)
    quads = room(7.0, 3.0, 2.6, ("checker", 0.6, (0.6, 0.6, 0.6)), ("gravel", 1.0, PLASTER))
    quads += box((0.5, 2.4, 0.0), (5.2, 0.6, 0.88), "brick", 0.6, red)
    quads += box((0.5, 2.35, 0.88), (5.2, 0.65, 0.04), "moon", 0.6, STEEL)
    quads.append(
        _quad((0.5, 2.995, 1.5), (5.2, 0, 0), (0, 0, -0.58), "checker", 0.15, (0.9, 0.9, 0.85))
    )
    quads += box((0.5, 2.65, 1.5), (5.2, 0.35, 0.7), "brick", 0.6, red)
    quads += box((5.9, 2.25, 0.0), (0.8, 0.75, 1.9), "moon", 0.8, STEEL)
    quads.append(_quad((2.6, 2.6, 0.925), (0.4, 0, 0), (0, 0.3, 0), "coffee", None))
    quads.append(wall_picture((0.01, 1.5, 1.5), "+x", 1.0, 0.8, "chelsea"))
    quads += box((2.5, 0.0, 0.0), (1.5, 0.5, 0.9), "grass", 0.4, WOOD)
    return Scene(
        "redkitchen",
        tuple(quads),
        _lights((1.8, 1.5, 2.5), (5.0, 1.5, 2.5)),
    )


def stairs() -> Scene:
    """A staircase between two walls: repetitive steps, seen from its foot."""
    quads = room(2.4, 6.0, 4.0, ("gravel", 0.5, TERRACOTTA), ("brick", 0.8, (0.75, 0.75, 0.7)))
    step_depth, step_height = 0.28, 0.18
    for i in range(12):
        y = 2.0 + i * step_depth
        quads.append(
            _quad(
                (0.4, y, (i + 1) * step_height),
                (1.6, 0, 0),
                (0, step_depth, 0),
                "gravel",
                0.4,
                (0.55, 0.5, 0.45),
            )
        )
        quads.append(
            _quad(
                (0.4, y, (i + 1) * step_height),
                (1.6, 0, 0),
                (0, 0, -step_height),
                "grass",
                0.4,
                WOOD,
            )
        )
    quads.append(wall_picture((2.39, 3.5, 2.2), "-x", 0.8, 0.6, "astronaut"))
    quads.append(wall_picture((0.01, 2.5, 1.8), "+x", 0.7, 0.5, "rocket"))
    return Scene(
        "stairs",
        tuple(quads),
        _lights((1.2, 1.5, 3.5), (1.2, 4.5, 3.8)),
    )


# The painted look: flat paint on the rooms' surfaces, and what gives real rooms their edges.

SKIRTING = (0.3, 0.22, 0.16)
FRAME = (0.1, 0.09, 0.08)


def framed_picture(
    center: Vec, normal_axis: str, width: float, height: float, border: float = 0.04
) -> Quad:
    """A dark frame ``border`` metres wide around a picture of the given size (2 mm behind it)."""
    size = (width + 2 * border, height + 2 * border)
    return wall_picture(center, normal_axis, *size, "flat", FRAME, offset=0.003)


def skirting(width: float, depth: float, height: float = 0.08) -> list[Quad]:
    """Skirting boards ``height`` metres high along the four walls of a room (1 cm in front)."""
    w, d, h, e = width, depth, height, 0.01
    return [
        _quad((0, e, h), (w, 0, 0), (0, 0, -h), "flat", None, SKIRTING),
        _quad((w, d - e, h), (-w, 0, 0), (0, 0, -h), "flat", None, SKIRTING),
        _quad((e, d, h), (0, -d, 0), (0, 0, -h), "flat", None, SKIRTING),
        _quad((w - e, 0, h), (0, d, 0), (0, 0, -h), "flat", None, SKIRTING),
    ]


def clutter(table: Vec, size: Vec, count: int, seed: int) -> list[Quad]:
    """``count`` small boxes of flat colours standing on a table top at ``table`` (min x, y and
    the top's z) of ``size`` (x, y; z unused)."""
    rng = np.random.default_rng(seed)
    colours = [(0.85, 0.85, 0.82), (0.05, 0.05, 0.06), (0.7, 0.12, 0.08), (0.12, 0.25, 0.55),
               (0.9, 0.7, 0.15), (0.05, 0.05, 0.06), (0.2, 0.45, 0.25)]  # fmt: skip
    quads = []
    for _ in range(count):
        side = rng.uniform(0.06, 0.2, size=2)
        x, y = (rng.uniform(0, 1, size=2) * (np.asarray(size[:2]) - side)) + table[:2]
        tint = colours[rng.integers(len(colours))]
        quads += box((x, y, table[2]), (*side, rng.uniform(0.04, 0.22)), "flat", None, tint)
    return quads


def _furnishings(name: str) -> list[Quad]:
    """What the painted look adds to scene ``name``: frames round its pictures, skirting, doors,
    windows, bookshelves and small objects, all on walls or on furniture (the camera's paths
    keep clear of the photographed rooms' geometry, which they leave unchanged)."""
    if name == "chess":
        return [
            *skirting(5.0, 4.0),
            framed_picture((2.5, 3.99, 1.5), "-y", 1.2, 0.8),
            framed_picture((4.99, 2.0, 1.4), "-x", 1.0, 1.0),
            framed_picture((0.01, 2.0, 1.5), "+x", 1.2, 0.8),
            wall_picture((4.99, 3.3, 1.0), "-x", 0.9, 2.0, "door", offset=0.012),
            wall_picture((4.1, 3.99, 1.5), "-y", 1.0, 1.1, "window", offset=0.012),
            wall_picture((0.8, 3.395, 0.8), "-y", 1.1, 1.5, "books", offset=0.0),
            *clutter((1.95, 1.62, 0.74), (0.3, 0.7, 0), 6, 1),
            *clutter((2.8, 1.62, 0.74), (0.28, 0.7, 0), 6, 2),
        ]
    if name == "fire":
        return [
            *skirting(4.5, 4.0),
            framed_picture((2.25, 3.99, 1.85), "-y", 0.9, 0.6),
            framed_picture((0.01, 1.8, 1.5), "+x", 1.0, 0.7),
            wall_picture((3.8, 3.99, 1.1), "-y", 1.0, 1.8, "books", offset=0.012),
            wall_picture((0.7, 3.99, 1.5), "-y", 1.0, 1.0, "window", offset=0.012),
            wall_picture((4.49, 2.0, 1.0), "-x", 0.9, 2.0, "door", offset=0.012),
            *clutter((2.0, 3.5, 1.18), (1.1, 0.4, 0), 6, 3),
        ]
    if name == "heads":
        return [
            *skirting(2.2, 2.0),
            framed_picture((1.55, 1.99, 1.3), "-y", 0.6, 0.4),
            framed_picture((2.19, 1.5, 1.2), "-x", 0.5, 0.5),
            wall_picture((0.45, 1.99, 1.5), "-y", 0.7, 1.2, "books", offset=0.012),
            wall_picture((0.01, 1.0, 1.5), "+x", 0.8, 0.9, "window", offset=0.012),
            *box((1.0, 1.62, 0.72), (0.4, 0.14, 0.02), "flat", None, DARK),
            *clutter((1.8, 1.25, 0.72), (0.35, 0.7, 0), 6, 4),
        ]
    if name == "office":
        return [
            *skirting(6.0, 5.0),
            framed_picture((3.0, 4.99, 1.7), "-y", 1.6, 0.9),
            framed_picture((5.99, 2.5, 1.5), "-x", 1.0, 0.8),
            wall_picture((0.505, 2.0, 1.0), "+x", 1.6, 2.0, "books", offset=0.0),
            wall_picture((5.2, 4.99, 1.5), "-y", 1.0, 1.1, "window", offset=0.012),
            wall_picture((5.99, 4.2, 1.0), "-x", 0.9, 2.0, "door", offset=0.012),
            *box((1.55, 3.75, 0.74), (0.45, 0.15, 0.02), "flat", None, DARK),
            *box((3.95, 3.75, 0.74), (0.45, 0.15, 0.02), "flat", None, DARK),
            *clutter((2.2, 3.65, 0.74), (0.35, 0.7, 0), 6, 5),
            *clutter((4.6, 3.65, 0.74), (0.35, 0.7, 0), 6, 6),
        ]
    if name == "pumpkin":
        return [
            *skirting(4.0, 4.0),
            framed_picture((2.0, 3.99, 1.75), "-y", 1.0, 0.7),
            framed_picture((3.99, 2.2, 1.4), "-x", 0.9, 0.9),
            wall_picture((0.605, 3.25, 0.9), "+x", 1.2, 1.7, "books", offset=0.0),
            wall_picture((3.99, 1.0, 1.0), "-x", 0.9, 2.0, "door", offset=0.012),
            wall_picture((3.4, 3.99, 1.85), "-y", 0.7, 0.8, "window", offset=0.012),
            *clutter((1.45, 3.35, 0.9), (0.3, 0.5, 0), 4, 7),
            *clutter((2.2, 3.35, 0.9), (0.35, 0.5, 0), 4, 8),
        ]
    if name == "redkitchen":
        red = (0.75, 0.12, 0.1)
        doors = [
            wall_picture((0.8 + 0.65 * i, 2.395, 0.46), "-y", 0.6, 0.8, "door", red, offset=0.0)
            for i in range(8)
        ]
        doors += [
            wall_picture((0.8 + 0.65 * i, 2.645, 1.85), "-y", 0.6, 0.66, "door", red, offset=0.0)
            for i in range(8)
        ]
        return [
            *skirting(7.0, 3.0),
            framed_picture((0.01, 1.5, 1.5), "+x", 1.0, 0.8),
            *doors,
            *clutter((0.6, 2.45, 0.92), (1.8, 0.3, 0), 6, 9),
            *clutter((3.2, 2.45, 0.92), (2.3, 0.3, 0), 6, 10),
        ]
    return [  # stairs
        *skirting(2.4, 6.0),
        framed_picture((2.39, 3.5, 2.2), "-x", 0.8, 0.6),
        framed_picture((0.01, 2.5, 1.8), "+x", 0.7, 0.5),
        wall_picture((1.2, 5.99, 3.16), "-y", 0.9, 2.0, "door", offset=0.012),
        wall_picture((0.01, 4.5, 2.9), "+x", 0.9, 1.0, "window", offset=0.012),
        wall_picture((2.39, 1.0, 1.3), "-x", 0.8, 1.6, "books", offset=0.012),
    ]


def _paint(quad: Quad) -> Quad:
    """``quad`` with a painted texture in place of a photograph in PAINTED."""
    if quad.texture not in PAINTED:
        return quad
    return replace(quad, texture=f"painted-{quad.texture}")


SCENES = {
    "chess": chess,
    "fire": fire,
    "heads": heads,
    "office": office,
    "pumpkin": pumpkin,
    "redkitchen": redkitchen,
    "stairs": stairs,
}


@dataclass(frozen=True)
class CameraRegion:
    """Where a scene's handheld camera walks and what it looks at (world frame, metres).

    The camera stays inside ``center ± half_extent`` (reached through ``tanh``, so the edges
    are rare) and looks at a point inside ``focus ± focus_half_extent``, shifted by
    ``gaze_follow`` times the camera's own offset from ``center`` (someone walking along a
    kitchen looks at what is in front of them). The regions are chosen so that predicting the
    mean training pose misses by about as much as it does on the real 7-Scenes scene of the
    same name (:data:`REAL_MEAN_POSE_BASELINE`).
    """

    center: Vec
    half_extent: Vec
    focus: Vec
    focus_half_extent: Vec
    gaze_follow: float = 0.0


CAMERA_REGIONS = {
    "chess": CameraRegion(
        (2.5, 0.95, 1.3), (1.6, 0.45, 0.3), (2.5, 2.0, 0.85), (0.5, 0.4, 0.2), gaze_follow=0.4
    ),
    "fire": CameraRegion((2.3, 1.4, 1.3), (1.0, 0.6, 0.3), (2.25, 3.4, 1.0), (1.7, 0.3, 0.4)),
    "heads": CameraRegion((1.35, 0.8, 1.15), (0.55, 0.35, 0.3), (1.5, 1.6, 0.9), (0.35, 0.2, 0.15)),
    "office": CameraRegion((3.0, 1.7, 1.4), (1.3, 0.6, 0.35), (3.0, 3.5, 1.0), (2.2, 0.8, 0.5)),
    "pumpkin": CameraRegion((2.0, 1.5, 1.3), (1.1, 0.6, 0.3), (2.0, 3.4, 1.0), (1.6, 0.3, 0.4)),
    "redkitchen": CameraRegion(
        (3.2, 1.2, 1.45), (2.0, 0.35, 0.3), (3.2, 2.6, 1.0), (1.6, 0.2, 0.3), gaze_follow=0.5
    ),
    "stairs": CameraRegion((1.2, 0.9, 1.4), (0.55, 0.4, 0.4), (1.2, 3.2, 1.3), (1.0, 1.0, 1.2)),
}

#: Median error (metres, degrees) of predicting the mean training pose for every test frame,
#: computed from the published poses of the real 7-Scenes (all 43,000 frames).
REAL_MEAN_POSE_BASELINE = {
    "chess": (0.82, 23.0),
    "fire": (0.77, 35.1),
    "heads": (0.45, 22.7),
    "office": (0.92, 48.7),
    "pumpkin": (0.78, 34.2),
    "redkitchen": (1.35, 35.2),
    "stairs": (0.52, 25.9),
}


def camera_region(name: str) -> CameraRegion:
    """The walking and gaze region of the stand-in scene called ``name``."""
    if name not in CAMERA_REGIONS:
        raise ValueError(f"unknown scene {name!r}; choose from {', '.join(SCENE_NAMES)}")
    return CAMERA_REGIONS[name]


def make_scene(name: str, content: str = "painted") -> Scene:
    """The stand-in scene called ``name`` (one of :data:`SCENE_NAMES`).

    Parameters
    ----------
    name : str
        The scene.
    content : str
        "photographs": rooms of tiled photographs (gravel, grass, brick); "painted": the same
        rooms with those surfaces painted flat (a weak texture left,
        :data:`~blurloc.data.render.PAINT_DETAIL`), plus what gives real rooms their strong
        edges: frames round the pictures, skirting, doors, windows, bookshelves, small objects.

    Returns
    -------
    Scene
        The scene.
    """
    if name not in SCENES:
        raise ValueError(f"unknown scene {name!r}; choose from {', '.join(SCENE_NAMES)}")
    if content not in ("painted", "photographs"):
        raise ValueError(f"unknown scene content {content!r}; choose painted or photographs")
    scene = SCENES[name]()
    if content == "photographs":
        return scene
    quads = (*map(_paint, scene.quads), *_furnishings(name))
    return Scene(scene.name, quads, scene.lights, scene.ambient, scene.min_clearance_m)
