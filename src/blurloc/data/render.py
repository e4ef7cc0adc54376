"""A small ray caster for scenes of textured rectangles, in linear light.

Scenes are made of rectangles (quads) carrying photographs bundled with scikit-image as
textures. Each pixel's ray is intersected with every quad (vectorised in NumPy); the nearest hit
is shaded with a few point lights (Lambert, inverse-square falloff) and textured with mip-mapped
bilinear lookups, so that distant surfaces do not alias. Rays are ``K^-1 (u, v, 1)``, so the ray
parameter of a hit is its z-depth.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache

import cv2
import numpy as np
import skimage.data

GAMMA = 2.2
MIP_LEVELS = 5
_MAX_TEXTURE_SIDE = 256
_REMAP_ROW = 1024  # cv2.remap maps must stay below 32767 per side: sample in rows of this width


def srgb_to_linear(image: np.ndarray) -> np.ndarray:
    """[0, 1] gamma-encoded intensities to linear light (gamma 2.2, as the GoPro benchmark)."""
    return np.power(np.clip(image, 0.0, 1.0), GAMMA)


def linear_to_srgb(image: np.ndarray) -> np.ndarray:
    """Linear light to [0, 1] gamma-encoded intensities (clipped: the sensor saturates)."""
    return np.power(np.clip(image, 0.0, 1.0), 1.0 / GAMMA)


def _checkerboard(squares: int = 8, square_px: int = 32) -> np.ndarray:
    board = (np.indices((squares, squares)).sum(axis=0) % 2).astype(np.float32)
    board = np.kron(board, np.ones((square_px, square_px), np.float32))
    return 0.12 + 0.76 * board


_PHOTOS = {
    "astronaut": skimage.data.astronaut,
    "brick": skimage.data.brick,
    "camera": skimage.data.camera,
    "chelsea": skimage.data.chelsea,
    "clock": skimage.data.clock,
    "coffee": skimage.data.coffee,
    "coins": skimage.data.coins,
    "colorwheel": skimage.data.colorwheel,
    "grass": skimage.data.grass,
    "gravel": skimage.data.gravel,
    "hubble": skimage.data.hubble_deep_field,
    "ihc": skimage.data.immunohistochemistry,
    "moon": skimage.data.moon,
    "page": skimage.data.page,
    "rocket": skimage.data.rocket,
    "text": skimage.data.text,
}
TEXTURE_NAMES = (*sorted(_PHOTOS), "checker")


@cache
def texture_pyramid(name: str) -> tuple[np.ndarray, ...]:
    """Mip pyramid (linear-light float32 RGB, halving sizes) of a named texture."""
    if name == "checker":
        image = _checkerboard()
    elif name in _PHOTOS:
        image = _PHOTOS[name]().astype(np.float32) / 255.0
    else:
        raise ValueError(f"unknown texture {name!r}; choose from {TEXTURE_NAMES}")
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    image = srgb_to_linear(image[..., :3]).astype(np.float32)
    scale = _MAX_TEXTURE_SIDE / max(image.shape[:2])
    if scale < 1:
        size = (round(image.shape[1] * scale), round(image.shape[0] * scale))
        image = cv2.resize(image, size, interpolation=cv2.INTER_AREA)
    levels = [np.ascontiguousarray(image)]
    for _ in range(MIP_LEVELS - 1):
        levels.append(cv2.pyrDown(levels[-1], borderType=cv2.BORDER_WRAP))
    return tuple(levels)


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
    """Quads, lights and an ambient term, plus where a handheld camera looks from and at."""

    name: str
    quads: tuple[Quad, ...]
    lights: tuple[Light, ...]
    camera_center: tuple[float, float, float]
    focus: tuple[float, float, float]
    ambient: float = 0.35
    wander_s: float = 0.8  # correlation time of the handheld path (smaller: tighter path)
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


def _sample(texture: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Bilinear, wrapping lookups of ``texture`` at float pixel coordinates (any count)."""
    count = x.size
    rows = -(-count // _REMAP_ROW)
    map_x = np.zeros(rows * _REMAP_ROW, np.float32)
    map_y = np.zeros(rows * _REMAP_ROW, np.float32)
    map_x[:count], map_y[:count] = x, y
    map_x, map_y = map_x.reshape(rows, _REMAP_ROW), map_y.reshape(rows, _REMAP_ROW)
    out = cv2.remap(texture, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)
    return out.reshape(-1, 3)[:count]


def render(
    scene: Scene, pose: np.ndarray, camera: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Render ``scene`` from a camera-to-world ``pose``.

    Returns the linear-light RGB image (height, width, 3) float32 and the z-depth (metres,
    0 where no surface is hit).
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

    # Z-buffer over quads; each quad is intersected only with the rays inside its projected
    # bounding box (all rays when it crosses the camera plane).
    near = 1e-3
    zbuffer = np.full((height, width), np.inf, np.float32)
    nearest = np.full((height, width), -1)
    hit_u = np.zeros((height, width), np.float32)
    hit_v = np.zeros((height, width), np.float32)
    corners_camera = (arrays["corners"] - eye) @ rotation  # (quads, 4, 3)
    for index in range(len(scene.quads)):
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

        pyramid = texture_pyramid(quad.texture)
        tex_h, tex_w = pyramid[0].shape[:2]
        tex_x = hit_u[mask] * quad.repeat[0] * tex_w
        tex_y = hit_v[mask] * quad.repeat[1] * tex_h
        texels_per_metre = np.sqrt(
            quad.repeat[0]
            * tex_w
            / arrays["length_u"][index]
            * quad.repeat[1]
            * tex_h
            / arrays["length_v"][index]
        )
        cosine = np.abs(facing) / ray_length[mask]
        footprint = (
            t * ray_length[mask] / focal / np.sqrt(np.maximum(cosine, 0.05)) * texels_per_metre
        )
        level = np.clip(np.log2(np.maximum(footprint, 1e-6)), 0, MIP_LEVELS - 1)
        base = np.minimum(np.floor(level).astype(int), MIP_LEVELS - 2)
        fraction = (level - base)[:, None]
        albedo = np.empty((t.size, 3), np.float32)
        for lod in np.unique(base):
            sel = base == lod
            fine = _sample(pyramid[lod], tex_x[sel] / 2**lod - 0.5, tex_y[sel] / 2**lod - 0.5)
            coarse = _sample(
                pyramid[lod + 1],
                tex_x[sel] / 2 ** (lod + 1) - 0.5,
                tex_y[sel] / 2 ** (lod + 1) - 0.5,
            )
            albedo[sel] = (1 - fraction[sel]) * fine + fraction[sel] * coarse
        image[mask] = albedo * np.asarray(quad.tint, np.float32) * light[:, None].astype(np.float32)

    depth_image = np.where(hit, hit_depth, 0.0).reshape(height, width)
    return image.reshape(height, width, 3), depth_image
