"""A small renderer for scenes of textured rectangles, in linear light.

Scenes are made of rectangles (quads) carrying textures (:mod:`blurloc.data.textures`:
photographs, painted walls, drawn patterns, each a mip pyramid). The surface seen at each pixel
is the nearest quad along the pixel's ray ``K^-1 (u, v, 1)`` (so the ray parameter of a hit is
its z-depth); it is shaded with a few point lights (Lambert, inverse-square falloff) and
textured with mip-mapped bilinear lookups, so that distant surfaces do not alias.
:func:`render_poses` rasterises the quads for many poses at once (each quad's depth and texture
coordinates are a homography of the pixel coordinates); :func:`render_reference` casts every
ray at every quad, the slow and plain definition the fast one is tested against.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache

import cv2
import numpy as np

from .textures import MIP_LEVELS, texture_pyramid

_REMAP_CHUNK = 32_000  # cv2.remap maps must stay below 32767 per side: sample in chunks
_NEAR = 1e-3  # metres: nearer surfaces are not seen
_NO_HIT = 255  # quad index of pixels that see no surface (quad indices are uint8)


@dataclass(frozen=True)
class Quad:
    """A textured rectangle ``origin + a * edge_u + b * edge_v`` for a, b in [0, 1].

    ``repeat`` is how many times the texture tiles along (u, v); ``tint`` multiplies the albedo.
    """

    origin: tuple[float, float, float]
    edge_u: tuple[float, float, float]
    edge_v: tuple[float, float, float]
    texture: str
    repeat: tuple[float, float] = (1.0, 1.0)
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def __post_init__(self) -> None:
        u, v = np.asarray(self.edge_u, float), np.asarray(self.edge_v, float)
        if np.linalg.norm(u) == 0 or np.linalg.norm(v) == 0:
            raise ValueError("quad edges must have non-zero length")
        if abs(u @ v) > 1e-9 * np.linalg.norm(u) * np.linalg.norm(v):
            raise ValueError("quad edges must be perpendicular")


@dataclass(frozen=True)
class Light:
    """A point light; ``power`` is the irradiance at 1 m on a surface facing it."""

    position: tuple[float, float, float]
    power: float


@dataclass(frozen=True)
class Scene:
    """Quads, lights and an ambient term, and how close a handheld camera may come to a surface.

    Where the camera walks and looks is :data:`blurloc.data.scenes.CAMERA_REGIONS`.
    """

    name: str
    quads: tuple[Quad, ...]
    lights: tuple[Light, ...]
    ambient: float = 0.35
    min_clearance_m: float = 0.3  # the camera keeps at least this far from every surface
    arrays: dict = field(default_factory=dict, compare=False, repr=False)

    def quad_arrays(self) -> dict[str, np.ndarray]:
        """Stacked quad geometry (computed once)."""
        if not self.arrays:
            origin = np.array([q.origin for q in self.quads], float)
            edge_u = np.array([q.edge_u for q in self.quads], float)
            edge_v = np.array([q.edge_v for q in self.quads], float)
            normal = np.cross(edge_u, edge_v)
            normal /= np.linalg.norm(normal, axis=1, keepdims=True)
            corners = np.stack(
                [origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v], 1
            )
            self.arrays.update(
                origin=origin,
                corners=corners,
                normal=normal,
                edge_u=edge_u,
                edge_v=edge_v,
                u_axis=edge_u / (edge_u**2).sum(axis=1, keepdims=True),
                v_axis=edge_v / (edge_v**2).sum(axis=1, keepdims=True),
                length_u=np.linalg.norm(edge_u, axis=1),
                length_v=np.linalg.norm(edge_v, axis=1),
            )
        return self.arrays

    def clearance(self, points: np.ndarray) -> np.ndarray:
        """Distance (metres) from each point (N, 3) to the nearest surface; negative outside
        the scene's bounding box (the room)."""
        arrays = self.quad_arrays()
        points = np.asarray(points, float).reshape(-1, 3)
        relative = points[:, None, :] - arrays["origin"]
        a = np.clip((relative * arrays["u_axis"]).sum(axis=2), 0, 1)[..., None]
        b = np.clip((relative * arrays["v_axis"]).sum(axis=2), 0, 1)[..., None]
        closest = arrays["origin"] + a * arrays["edge_u"] + b * arrays["edge_v"]
        distance = np.linalg.norm(points[:, None, :] - closest, axis=2).min(axis=1)
        corners = arrays["corners"].reshape(-1, 3)
        inside = np.all((points >= corners.min(axis=0)) & (points <= corners.max(axis=0)), axis=1)
        return np.where(inside, distance, -distance)


def _sample(
    texture: np.ndarray, x: np.ndarray, y: np.ndarray, border: int = cv2.BORDER_WRAP
) -> np.ndarray:
    """Bilinear lookups (n, 3) of ``texture`` at float32 pixel coordinates (n,) (wrapping by
    default)."""
    x, y = np.asarray(x, np.float32), np.asarray(y, np.float32)
    out = np.empty((x.size, 3), np.float32)
    for first in range(0, x.size, _REMAP_CHUNK):
        part = slice(first, first + _REMAP_CHUNK)
        out[part] = cv2.remap(
            texture, x[None, part], y[None, part], cv2.INTER_LINEAR, borderMode=border
        )[0]
    return out


def _mip_level(footprint: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mip level below each pixel's footprint (texels of level 0 per pixel, (n,)) and the
    weight (n,) of the level above it in the trilinear blend."""
    level = np.clip(np.log2(np.maximum(footprint, 1e-6)), 0, MIP_LEVELS - 1)
    base = np.minimum(np.floor(level).astype(np.int32), MIP_LEVELS - 2)
    return base, (level - base).astype(np.float32)


_ATLAS_PAD = 2  # texels of wrapped border around each level in an atlas


@cache
def _mip_atlas(
    name: str, tint: tuple[float, float, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A texture's mip levels (times ``tint``) side by side in one image, each with a wrapped
    border, with the atlas column of each level's texel 0 and each level's scale from level 0.

    About 1.6 MB each; the seven scenes use 35 (texture, tint) pairs (51 MB per process).
    """
    levels = [level * np.asarray(tint, np.float32) for level in texture_pyramid(name)]
    pad = _ATLAS_PAD
    tiles = [cv2.copyMakeBorder(level, pad, pad, pad, pad, cv2.BORDER_WRAP) for level in levels]
    widths = np.array([tile.shape[1] for tile in tiles])
    columns = np.concatenate([[0], np.cumsum(widths)])
    atlas = np.zeros((tiles[0].shape[0], columns[-1], 3), np.float32)
    for tile, column in zip(tiles, columns, strict=False):
        atlas[: tile.shape[0], column : column + tile.shape[1]] = tile
    scales = 2.0 ** -np.arange(len(levels))
    return atlas, (columns[:-1] + pad).astype(np.float32), scales.astype(np.float32)


def _albedo(quad: Quad, tex_x: np.ndarray, tex_y: np.ndarray, footprint: np.ndarray) -> np.ndarray:
    """Trilinear (mip-mapped bilinear) albedo (n, 3) of a quad (its texture times its tint) at
    texel coordinates of level 0 (n,), for footprints (n,) of level-0 texels per pixel.

    The same lookups as ``_sample`` on two wrapping levels, made in one remap per level from
    the texture's atlas: coordinates are wrapped into level 0 (every level has the same
    period) and scaled into each pixel's level.
    """
    atlas, columns, scales = _mip_atlas(quad.texture, quad.tint)
    height, width = texture_pyramid(quad.texture)[0].shape[:2]
    base, fraction = _mip_level(footprint)
    x = tex_x - np.floor(tex_x * np.float32(1 / width)) * np.float32(width)
    y = tex_y - np.floor(tex_y * np.float32(1 / height)) * np.float32(height)
    low, high = int(base.min()), int(base.max())
    lod = low if low == high else base
    scale, column = np.take(scales, lod), np.take(columns, lod) - np.float32(0.5)
    row = np.float32(_ATLAS_PAD - 0.5)
    fine = _sample(atlas, x * scale + column, y * scale + row, cv2.BORDER_REPLICATE)
    column += scale * np.float32(width) + np.float32(2 * _ATLAS_PAD)  # the next level's
    scale = scale * np.float32(0.5)
    coarse = _sample(atlas, x * scale + column, y * scale + row, cv2.BORDER_REPLICATE)
    count = fraction.size  # cv2.blendLinear: per-pixel weights over a (1, count) image
    return cv2.blendLinear(
        coarse.reshape(1, count, 3), fine.reshape(1, count, 3), fraction[None], 1 - fraction[None]
    ).reshape(count, 3)


def _shading_constants(scene: Scene) -> dict[str, np.ndarray]:
    """Per-quad constants of the shading (computed once per scene).

    With ``P = origin + a edge_u + b edge_v`` a point of a quad and ``d = L - origin`` for a
    light at L, ``|L - P|^2 = |d|^2 - 2a (d . edge_u) - 2b (d . edge_v) + a^2 |edge_u|^2 +
    b^2 |edge_v|^2`` (the edges are perpendicular) and ``(L - P) . normal = d . normal``.
    """
    arrays = scene.quad_arrays()
    if "light_offset" not in arrays:
        lights = np.array([lamp.position for lamp in scene.lights], float).reshape(-1, 3)
        offset = lights[None] - arrays["origin"][:, None]  # (quads, lights, 3)
        texel = []
        for quad in scene.quads:
            height, width = texture_pyramid(quad.texture)[0].shape[:2]
            texel.append((quad.repeat[0] * width, quad.repeat[1] * height))
        texel = np.array(texel, float)
        arrays.update(
            light_offset=(offset**2).sum(axis=2),
            light_along_u=-2 * (offset * arrays["edge_u"][:, None]).sum(axis=2),
            light_along_v=-2 * (offset * arrays["edge_v"][:, None]).sum(axis=2),
            light_normal=(offset * arrays["normal"][:, None]).sum(axis=2),
            light_power=np.array([lamp.power for lamp in scene.lights], float),
            texels=texel,
            texels_per_metre=np.sqrt(
                texel[:, 0] / arrays["length_u"] * texel[:, 1] / arrays["length_v"]
            ),
        )
    return arrays


@cache
def _ray_lengths(width: int, height: int, fx: float, fy: float, cx: float, cy: float) -> np.ndarray:
    """Length of each pixel's ray ``K^-1 (u, v, 1)`` (height * width,) float32."""
    u, v = np.meshgrid((np.arange(width) - cx) / fx, (np.arange(height) - cy) / fy)
    return np.sqrt(1.0 + u**2 + v**2).astype(np.float32).ravel()


def _quad_boxes(corners: np.ndarray, camera: np.ndarray, width: int, height: int) -> np.ndarray:
    """Pixel box (u0, v0, u1, v1), columns [u0, u1) and rows [v0, v1), of each quad seen from
    any of the poses, (quads, 4) int.

    ``corners`` is (poses, quads, 4, 3) in camera coordinates. Each quad is clipped to the
    near plane (its corners in front plus its edges' crossings of the plane), so a quad that
    reaches behind the camera covers only the part of the image it can be seen in.
    """
    following = np.roll(corners, -1, axis=2)
    z, z_next = corners[..., 2], following[..., 2]
    front = z > _NEAR
    crossing = front != (z_next > _NEAR)
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction = (_NEAR - z) / (z_next - z)
        crossings = corners + fraction[..., None] * (following - corners)
    points = np.concatenate([corners, crossings], axis=2)
    valid = np.concatenate([front, crossing], axis=2)[..., None]
    depth = np.where(valid, np.maximum(points[..., 2:], _NEAR), 1.0)
    pixels = points[..., :2] / depth * camera[[0, 1], [0, 1]] + camera[:2, 2]
    low = np.where(valid, pixels, np.inf).min(axis=(0, 2))
    high = np.where(valid, pixels, -np.inf).max(axis=(0, 2))
    size = np.array([width, height])
    low = np.clip(np.floor(low), 0, size)
    high = np.clip(np.ceil(high) + 1, 0, size)
    return np.concatenate([low, high], axis=1).astype(int)


def _ray_dot(vectors: np.ndarray, camera: np.ndarray) -> np.ndarray:
    """Coefficients (a, b, c) with ``ray . w = a u + b v + c`` for the pixel rays
    ``K^-1 (u, v, 1)`` and camera-frame vectors ``w`` (..., 3); returns (..., 3)."""
    a = vectors[..., 0] / camera[0, 0]
    b = vectors[..., 1] / camera[1, 1]
    return np.stack([a, b, vectors[..., 2] - a * camera[0, 2] - b * camera[1, 2]], axis=-1)


def _affine(coefficients: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``a u + b v + c`` over the pixel grid u (w,) x v (h,) for each row of (poses, 3)."""
    a, b, c = coefficients.astype(np.float32).T
    return (a[:, None] * u)[:, None, :] + (b[:, None] * v + c[:, None])[:, :, None]


def render_poses(
    scene: Scene, poses: np.ndarray, camera: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Render ``scene`` from several camera-to-world poses at once (rasterising its planes).

    Every quad is a plane, so over the image its inverse depth and its texture coordinates
    divided by depth are affine in the pixel coordinates: a quad's depth and (a, b)
    coordinates at each pixel of its projected box are a ratio of affine functions (a
    homography), evaluated for all poses in one pass, then depth-tested into a z-buffer. Only
    the visible pixels are then shaded, once, quad by quad: Lambert point lights with
    inverse-square falloff (in closed form over the quad's coordinates) times a mip-mapped
    bilinear texture lookup. The images equal those of :func:`render_reference` (the same
    surfaces, light and texture filter) up to float32 rounding (and the rare pixel whose ray
    grazes the edge of a quad).

    Parameters
    ----------
    scene : Scene
        What to render (at most 255 quads).
    poses : np.ndarray
        (poses, 4, 4) camera-to-world poses, metres.
    camera : np.ndarray
        (3, 3) intrinsics, pixels.
    width, height : int
        Image size, pixels.

    Returns
    -------
    images : np.ndarray
        (poses, height, width, 3) float32 linear-light RGB.
    depths : np.ndarray
        (poses, height, width) float32 z-depth, metres; 0 where no surface is hit.
    """
    arrays = _shading_constants(scene)
    quads = len(scene.quads)
    if quads > _NO_HIT:
        raise ValueError(f"at most {_NO_HIT} quads can be rendered, got {quads}")
    poses = np.asarray(poses, float).reshape(-1, 4, 4)
    count, pixels = poses.shape[0], width * height
    zbuffer, nearest, coord_u, coord_v, offset_n = _rasterize(arrays, poses, camera, width, height)

    # Shade the visible pixels of each quad (all poses together), in order of quad.
    nearest = nearest.ravel()
    order = np.argsort(nearest, kind="stable")  # a radix sort: stays ordered by pose, pixel
    slots = _NO_HIT + 1  # quad indices and no hit
    key = (
        nearest.reshape(count, pixels) + np.arange(0, count * slots, slots, dtype=np.int32)[:, None]
    )
    per_pose = np.bincount(key.ravel(), minlength=count * slots).reshape(count, slots)[:, :quads]
    bounds = np.concatenate([[0], np.cumsum(per_pose.sum(axis=0))])
    ray_length = np.tile(_ray_lengths(width, height, *camera[[0, 1, 0, 1], [0, 1, 2, 2]]), count)
    zbuffer = zbuffer.ravel()
    depths, coord_u, coord_v, ray_length = (
        np.take(values.ravel(), order) for values in (zbuffer, coord_u, coord_v, ray_length)
    )
    focal = np.sqrt(camera[0, 0] * camera[1, 1])
    shaded = np.zeros((count * pixels, 3), np.float32)  # in quad order; no surface: black
    for index, quad in enumerate(scene.quads):
        visible = slice(bounds[index], bounds[index + 1])
        if bounds[index] == bounds[index + 1]:
            continue
        a, b = coord_u[visible] + np.float32(0.5), coord_v[visible] + np.float32(0.5)
        # the lit side of the plane is the camera's, and |ray . normal| = |offset_n| / t
        sides = np.sign(offset_n[:, index]).astype(np.float32)
        if (sides != sides[0]).any():
            sides = np.repeat(sides, per_pose[:, index])
        else:
            sides = sides[0]
        light = _quad_light(arrays, index, a, b, sides, scene.ambient)
        distance = depths[visible] * ray_length[visible]  # along the ray
        offset = np.repeat(np.abs(offset_n[:, index]).astype(np.float32), per_pose[:, index])
        cosine = np.maximum(offset / distance, np.float32(0.05))
        if quad.texture == "flat":  # every texel of every level is 1: the albedo is the tint
            np.multiply(np.float32(quad.tint), light[:, None], out=shaded[visible])
            continue
        footprint = distance * np.float32(arrays["texels_per_metre"][index] / focal)
        footprint /= np.sqrt(cosine)
        texels = arrays["texels"][index].astype(np.float32)
        albedo = _albedo(quad, a * texels[0], b * texels[1], footprint)
        np.multiply(albedo, light[:, None], out=shaded[visible])
    back = np.empty(order.size, np.intp)
    back[order] = np.arange(order.size)
    image = np.take(shaded, back, axis=0)

    depth = np.where(nearest < _NO_HIT, zbuffer, np.float32(0))
    return image.reshape(count, height, width, 3), depth.reshape(count, height, width)


def _rasterize(
    arrays: dict[str, np.ndarray], poses: np.ndarray, camera: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Z-buffer the quads of ``arrays`` (from :func:`_shading_constants`) for every pose.

    Returns the nearest surface's depth (poses, height, width) float32 (inf where none), its
    quad index (uint8, ``_NO_HIT`` where none), its centred coordinates ``a - 1/2`` and
    ``b - 1/2`` (float32), and the camera's signed distance from each quad's plane
    (poses, quads).
    """
    count = poses.shape[0]
    rotation, eye = poses[:, :3, :3], poses[:, :3, 3]

    # Planes in each camera: ray . w for the normal and both texture axes, and the camera's
    # offset from each quad's origin along them.
    def in_camera(vectors: np.ndarray) -> np.ndarray:
        return np.einsum("qj,sjk->sqk", vectors, rotation)

    relative = eye[:, None] - arrays["origin"][None]  # (poses, quads, 3)
    offset_n = (relative * arrays["normal"]).sum(axis=2)
    offset_u = (relative * arrays["u_axis"]).sum(axis=2)
    offset_v = (relative * arrays["v_axis"]).sum(axis=2)
    facing = _ray_dot(in_camera(arrays["normal"]), camera)
    # (a - 1/2) and (b - 1/2) times ray . normal: the quad is |a - 1/2|, |b - 1/2| <= 1/2
    numerator_u = (offset_u[..., None] - 0.5) * facing - offset_n[..., None] * _ray_dot(
        in_camera(arrays["u_axis"]), camera
    )
    numerator_v = (offset_v[..., None] - 0.5) * facing - offset_n[..., None] * _ray_dot(
        in_camera(arrays["v_axis"]), camera
    )
    corners = np.einsum("sqcj,sjk->sqck", arrays["corners"][None] - eye[:, None, None], rotation)
    boxes = _quad_boxes(corners, camera, width, height)

    zbuffer = np.full((count, height, width), np.inf, np.float32)
    nearest = np.full((count, height, width), _NO_HIT, np.uint8)
    coord_u = np.zeros((count, height, width), np.float32)
    coord_v = np.zeros((count, height, width), np.float32)
    columns, rows = np.arange(width, dtype=np.float32), np.arange(height, dtype=np.float32)
    for index, (u0, v0, u1, v1) in enumerate(boxes):
        if u0 >= u1 or v0 >= v1:
            continue
        u, v = columns[u0:u1], rows[v0:v1]
        with np.errstate(divide="ignore", invalid="ignore"):
            inverse = 1.0 / _affine(facing[:, index], u, v)
        depth = (-offset_n[:, index, None, None]).astype(np.float32) * inverse
        a = _affine(numerator_u[:, index], u, v) * inverse
        b = _affine(numerator_v[:, index], u, v) * inverse
        window = (slice(None), slice(v0, v1), slice(u0, u1))
        closer = (depth > _NEAR) & (depth < zbuffer[window])
        closer &= np.maximum(np.abs(a), np.abs(b)) <= 0.5
        np.copyto(zbuffer[window], depth, where=closer)
        np.copyto(nearest[window], index, where=closer)
        np.copyto(coord_u[window], a, where=closer)
        np.copyto(coord_v[window], b, where=closer)
    return zbuffer, nearest, coord_u, coord_v, offset_n


def _quad_light(
    arrays: dict[str, np.ndarray],
    index: int,
    a: np.ndarray,
    b: np.ndarray,
    sides: np.ndarray | np.float32,
    ambient: float,
) -> np.ndarray:
    """Light (n,) float32 reaching points (a, b) (n,) of quad ``index`` on its ``sides`` (+1 or
    -1, per point or for all): ambient plus Lambert point lights with inverse-square falloff,
    in closed form over the quad's coordinates (see :func:`_shading_constants`).
    """
    square = a * a * np.float32(arrays["length_u"][index] ** 2)
    square += b * b * np.float32(arrays["length_v"][index] ** 2)
    light = np.float32(ambient)
    for lamp, power in enumerate(arrays["light_power"]):
        lambert = np.maximum(sides * np.float32(arrays["light_normal"][index, lamp]), 0)
        distance2 = a * np.float32(arrays["light_along_u"][index, lamp])
        distance2 += b * np.float32(arrays["light_along_v"][index, lamp])
        distance2 += np.float32(arrays["light_offset"][index, lamp])
        distance2 += square
        falloff = np.sqrt(distance2)
        falloff *= np.maximum(distance2, np.float32(0.25))
        light = light + (np.float32(power) * lambert) / falloff
    return light


def surface_depth(
    scene: Scene, pose: np.ndarray, camera: np.ndarray, pixels: np.ndarray
) -> np.ndarray:
    """Z-depth of the surface seen at a few pixels: their rays cast at every quad at once.

    Parameters
    ----------
    scene : Scene
        What the camera sees.
    pose : np.ndarray
        (4, 4) camera-to-world pose, metres.
    camera : np.ndarray
        (3, 3) intrinsics, pixels.
    pixels : np.ndarray
        (N, 2) pixel coordinates (u, v).

    Returns
    -------
    np.ndarray
        (N,) z-depth, metres; 0 where no surface is hit.
    """
    arrays = scene.quad_arrays()
    pixels = np.asarray(pixels, float).reshape(-1, 2)
    rays = (
        np.column_stack([(pixels - camera[:2, 2]) / camera[[0, 1], [0, 1]], np.ones(len(pixels))])
        @ pose[:3, :3].T
    )  # unit z-component in the camera frame: ray parameter = z-depth
    relative = pose[:3, 3] - arrays["origin"]  # (quads, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = -(relative * arrays["normal"]).sum(axis=1) / (rays @ arrays["normal"].T)
        a = (relative * arrays["u_axis"]).sum(axis=1) + depth * (rays @ arrays["u_axis"].T)
        b = (relative * arrays["v_axis"]).sum(axis=1) + depth * (rays @ arrays["v_axis"].T)
        hit = (depth > _NEAR) & (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1)
    nearest = np.where(hit, depth, np.inf).min(axis=1)
    return np.where(np.isfinite(nearest), nearest, 0.0)


def render(
    scene: Scene, pose: np.ndarray, camera: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Render ``scene`` from one camera-to-world ``pose`` (:func:`render_poses` of one pose).

    Parameters
    ----------
    scene : Scene
        What to render.
    pose : np.ndarray
        (4, 4) camera-to-world pose, metres.
    camera : np.ndarray
        (3, 3) intrinsics, pixels.
    width, height : int
        Image size, pixels.

    Returns
    -------
    image : np.ndarray
        (height, width, 3) float32 linear-light RGB.
    depth : np.ndarray
        (height, width) float32 z-depth, metres; 0 where no surface is hit.
    """
    images, depths = render_poses(scene, pose[None], camera, width, height)
    return images[0], depths[0]


def render_reference(
    scene: Scene, pose: np.ndarray, camera: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Render ``scene`` by casting every pixel's ray at every quad (the reference renderer).

    Slow but plain: each ray is intersected with each quad whose projected bounding box holds
    it, and the nearest hit is shaded. :func:`render_poses` must give the same images; the
    tests and ``benchmarks/bench_synth.py`` compare the two.

    Parameters
    ----------
    scene : Scene
        What to render.
    pose : np.ndarray
        (4, 4) camera-to-world pose, metres.
    camera : np.ndarray
        (3, 3) intrinsics, pixels.
    width, height : int
        Image size, pixels.

    Returns
    -------
    image : np.ndarray
        (height, width, 3) float32 linear-light RGB.
    depth : np.ndarray
        (height, width) z-depth, metres; 0 where no surface is hit.
    """
    arrays = scene.quad_arrays()
    rotation, eye = pose[:3, :3], pose[:3, 3]
    u, v = np.meshgrid(np.arange(width), np.arange(height))
    rays_camera = np.stack(
        [
            (u - camera[0, 2]) / camera[0, 0],
            (v - camera[1, 2]) / camera[1, 1],
            np.ones_like(u, float),
        ],
        axis=-1,
    )
    # world directions with unit z-component in the camera frame; float32 is ample at metres
    rays = (rays_camera @ rotation.T).astype(np.float32)
    zbuffer, nearest, hit_u, hit_v = _cast_rays(arrays, rays, pose, camera)

    rays = rays.reshape(-1, 3)
    nearest = nearest.ravel()
    hit_depth = zbuffer.ravel()
    hit_u, hit_v = hit_u.ravel(), hit_v.ravel()
    hit = nearest >= 0
    image = np.zeros((rays.shape[0], 3), np.float32)
    focal = np.sqrt(camera[0, 0] * camera[1, 1])
    ray_length = np.linalg.norm(rays, axis=1)
    order = np.argsort(nearest, kind="stable")
    bounds = np.searchsorted(nearest[order], np.arange(len(scene.quads) + 1))
    for index, quad in enumerate(scene.quads):
        mask = order[bounds[index] : bounds[index + 1]]
        if mask.size == 0:
            continue
        t = hit_depth[mask]
        points = eye + t[:, None] * rays[mask]
        quad_normal = arrays["normal"][index]
        facing = rays[mask] @ quad_normal
        surface_normal = np.where(facing[:, None] > 0, -quad_normal, quad_normal)

        light = np.full(t.shape, scene.ambient)
        for lamp in scene.lights:
            to_light = np.asarray(lamp.position) - points
            distance2 = (to_light**2).sum(axis=1)
            lambert = np.clip((to_light * surface_normal).sum(axis=1), 0, None) / np.sqrt(distance2)
            light += lamp.power * lambert / np.maximum(distance2, 0.25)

        cosine = np.abs(facing) / ray_length[mask]
        albedo = _reference_albedo(
            quad,
            hit_u[mask],
            hit_v[mask],
            t * ray_length[mask] / focal / np.sqrt(np.maximum(cosine, 0.05)),
            arrays["length_u"][index],
            arrays["length_v"][index],
        )
        image[mask] = albedo * np.asarray(quad.tint, np.float32) * light[:, None].astype(np.float32)

    depth_image = np.where(hit, hit_depth, 0.0).reshape(height, width)
    return image.reshape(height, width, 3), depth_image


def _cast_rays(
    arrays: dict[str, np.ndarray], rays: np.ndarray, pose: np.ndarray, camera: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Nearest hit of each ray (height, width, 3) from ``pose`` among the quads of ``arrays``.

    Each quad is intersected only with the rays inside its projected bounding box (all rays
    when it crosses the camera plane). Returns the hit's depth (float32, inf where none), its
    quad index (-1 where none) and its coordinates (a, b) on the quad (float32), each
    (height, width).
    """
    height, width = rays.shape[:2]
    rotation, eye = pose[:3, :3], pose[:3, 3]
    near = _NEAR
    zbuffer = np.full((height, width), np.inf, np.float32)
    nearest = np.full((height, width), -1)
    hit_u = np.zeros((height, width), np.float32)
    hit_v = np.zeros((height, width), np.float32)
    corners_camera = (arrays["corners"] - eye) @ rotation  # (quads, 4, 3)
    for index in range(len(corners_camera)):
        z = corners_camera[index, :, 2]
        if (z <= near).all():
            continue
        if (z > near).all():
            uv = corners_camera[index, :, :2] / z[:, None] * [camera[0, 0], camera[1, 1]]
            uv += camera[:2, 2]
            u0, v0 = np.maximum(np.floor(uv.min(axis=0)).astype(int), 0)
            u1, v1 = np.ceil(uv.max(axis=0)).astype(int) + 1
            u1, v1 = min(u1, width), min(v1, height)
            if u0 >= u1 or v0 >= v1:
                continue
        else:
            u0, v0, u1, v1 = 0, 0, width, height
        window = rays[v0:v1, u0:u1]
        normal = arrays["normal"][index].astype(np.float32)
        u_axis = arrays["u_axis"][index].astype(np.float32)
        v_axis = arrays["v_axis"][index].astype(np.float32)
        relative = eye - arrays["origin"][index]
        with np.errstate(divide="ignore", invalid="ignore"):
            depth = np.float32(-relative @ normal) / (window @ normal)
        coord_u = np.float32(relative @ u_axis) + depth * (window @ u_axis)
        coord_v = np.float32(relative @ v_axis) + depth * (window @ v_axis)
        closer = (depth > near) & (depth < zbuffer[v0:v1, u0:u1])
        closer &= (coord_u >= 0) & (coord_u <= 1) & (coord_v >= 0) & (coord_v <= 1)
        zbuffer[v0:v1, u0:u1][closer] = depth[closer]
        nearest[v0:v1, u0:u1][closer] = index
        hit_u[v0:v1, u0:u1][closer] = coord_u[closer]
        hit_v[v0:v1, u0:u1][closer] = coord_v[closer]
    return zbuffer, nearest, hit_u, hit_v


def _reference_albedo(
    quad: Quad,
    coord_u: np.ndarray,
    coord_v: np.ndarray,
    metres_per_pixel: np.ndarray,
    length_u: float,
    length_v: float,
) -> np.ndarray:
    """Untinted trilinear albedo (n, 3) of ``quad`` at its coordinates (a, b) (n,), looked up
    level by level in its texture pyramid, for pixel footprints of ``metres_per_pixel`` (n,)
    on a quad of sides ``length_u`` x ``length_v`` metres.
    """
    pyramid = texture_pyramid(quad.texture)
    tex_h, tex_w = pyramid[0].shape[:2]
    tex_x = coord_u * quad.repeat[0] * tex_w
    tex_y = coord_v * quad.repeat[1] * tex_h
    texels_per_metre = np.sqrt(
        quad.repeat[0] * tex_w / length_u * quad.repeat[1] * tex_h / length_v
    )
    base, fraction = _mip_level(metres_per_pixel * texels_per_metre)
    fraction = fraction[:, None]
    albedo = np.empty((coord_u.size, 3), np.float32)
    for lod in np.unique(base):
        sel = base == lod
        fine = _sample(pyramid[lod], tex_x[sel] / 2**lod - 0.5, tex_y[sel] / 2**lod - 0.5)
        coarse = _sample(
            pyramid[lod + 1],
            tex_x[sel] / 2 ** (lod + 1) - 0.5,
            tex_y[sel] / 2 ** (lod + 1) - 0.5,
        )
        albedo[sel] = (1 - fraction[sel]) * fine + fraction[sel] * coarse
    return albedo
