"""The glTF 2.0 metallic-roughness BRDF (Appendix B) in float64 numpy, written from the spec's formulas for the
tests to check both render paths against; nothing here comes from the renderer.

The masking-shadowing term is the height-correlated Smith form, written here as Heitz (2014) gives it,
G2 = 1 / (1 + Lambda(v) + Lambda(l)) with Lambda(x) = (sqrt(1 + alpha^2 tan^2 theta_x) - 1) / 2 and
V = G2 / (4 n.l n.v), not in the shaders' pre-divided 0.5 / (...) form: the two agree only if both are right.
Its limit at n.v -> 0 is 1 / (2 alpha n.l), reached here by evaluating at n.v = 1e-12.

Units: the renderer's lights are such that intensity 1 straight onto a white Lambertian surface gives 1, so the
reflected radiance is pi * f * E * n.l (shaders_wgsl/pbr.wgsl's header states the same).
"""

from __future__ import annotations

import numpy as np

DIELECTRIC_F0 = 0.04  # the spec: "a dielectric ... f0 = 0.04" (ior 1.5)
MIN_ROUGHNESS = 0.045  # the clamp pbr.wgsl documents (alpha 0.002); None below: the naive formulas


def _dot(a, b) -> np.ndarray:
    return np.sum(np.asarray(a, np.float64) * np.asarray(b, np.float64), axis=-1)


def unit(v) -> np.ndarray:
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def ggx(n_dot_h, alpha) -> np.ndarray:
    """Trowbridge-Reitz: alpha^2 chi+(n.h) / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)."""
    a2 = alpha * alpha
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(n_dot_h > 0, a2 / (np.pi * (n_dot_h**2 * (a2 - 1) + 1) ** 2), 0.0)


def smith_lambda(cos_theta, alpha) -> np.ndarray:
    c = np.maximum(cos_theta, 1e-12)
    tan2 = (1 - c * c) / (c * c)
    return (np.sqrt(1 + alpha * alpha * tan2) - 1) / 2


def visibility(n_dot_l, n_dot_v, alpha) -> np.ndarray:
    """Height-correlated Smith G2 / (4 n.l n.v)."""
    g2 = 1 / (1 + smith_lambda(n_dot_l, alpha) + smith_lambda(n_dot_v, alpha))
    return g2 / (4 * np.maximum(n_dot_l, 1e-12) * np.maximum(n_dot_v, 1e-12))


def schlick(f0, v_dot_h) -> np.ndarray:
    return f0 + (1 - f0) * (1 - v_dot_h)[..., None] ** 5


def brdf(n, to_light, v, base, metallic, roughness, min_roughness: float | None = MIN_ROUGHNESS) -> np.ndarray:
    """f(l, v) (..., 3), l = ``to_light``: mix(dielectric, metal, metallic) as Appendix B writes it, with
    dielectric = mix(base / pi, D V, F(0.04)) and metal = D V F(base)."""
    n, lt, v = np.broadcast_arrays(unit(n), unit(to_light), unit(v))
    h = unit(lt + v)
    n_dot_l = np.clip(_dot(n, lt), 0, 1)
    n_dot_v = np.clip(_dot(n, v), 0, 1)
    n_dot_h, v_dot_h = np.clip(_dot(n, h), 0, 1), np.clip(_dot(v, h), 0, 1)
    r = np.float64(roughness) if min_roughness is None else np.clip(roughness, min_roughness, 1.0)
    alpha = r * r
    with np.errstate(divide="ignore", invalid="ignore"):
        specular = (ggx(n_dot_h, alpha) * visibility(n_dot_l, n_dot_v, alpha))[..., None]
    base = np.asarray(base, np.float64)
    f_dielectric = schlick(np.full(3, DIELECTRIC_F0), v_dot_h)
    dielectric = (1 - f_dielectric) * base / np.pi + f_dielectric * specular
    metal = specular * schlick(base, v_dot_h)
    f = (1 - metallic) * dielectric + metallic * metal
    return np.where((n_dot_l > 0)[..., None], f, 0.0)


def radiance(n, to_light, v, base, metallic, roughness, irradiance=1.0, **kw) -> np.ndarray:
    """pi * f * E * n.l (the renderer's light units)."""
    n_dot_l = np.clip(_dot(unit(n), unit(to_light)), 0, 1)[..., None]
    return np.pi * brdf(n, to_light, v, base, metallic, roughness, **kw) * np.asarray(irradiance, np.float64) * n_dot_l


def pixel_rays(size: tuple[int, int], fov_y: float) -> np.ndarray:
    """Unit view-space directions (H, W, 3) through each pixel centre of a camera looking down -z."""
    w, h = size
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    t = np.tan(np.radians(fov_y) / 2)
    return unit(np.stack([(xs / w * 2 - 1) * t * w / h, (1 - ys / h * 2) * t, -np.ones_like(xs)], axis=-1))


def plane_hits(eye, rays, normal) -> np.ndarray:
    """Where each ray from ``eye`` meets the plane through the origin with ``normal`` (H, W, 3)."""
    eye = np.asarray(eye, np.float64)
    t = -_dot(normal, eye) / _dot(rays, normal)
    return eye + t[..., None] * rays


# -- KHR_materials_clearcoat -----------------------------------------------------------------------------------------
# The extension's layering, written from its README: coated = mix(base, layer, clearcoat * Fc) with the layer
# specular_brdf(alpha = clearcoatRoughness^2) = D V (no Fresnel of its own), and
# Fc = f0 + (1 - f0) (1 - |N.V|)^5 on the coat's normal, f0 = ((1 - ior) / (1 + ior))^2 at ior 1.5.
CLEARCOAT_IOR = 1.5


def clearcoat_fresnel(nc, v) -> np.ndarray:
    f0 = ((1 - CLEARCOAT_IOR) / (1 + CLEARCOAT_IOR)) ** 2
    return f0 + (1 - f0) * (1 - np.clip(np.abs(_dot(unit(nc), unit(v))), 0, 1)) ** 5


def coat_radiance(nc, to_light, v, roughness, irradiance=1.0, min_roughness: float | None = MIN_ROUGHNESS):
    """The layer's pi D V E (nc.l) (..., 3) in the renderer's light units, on the coat's normal."""
    nc, lt, v = np.broadcast_arrays(unit(nc), unit(to_light), unit(v))
    h = unit(lt + v)
    n_dot_l, n_dot_v = np.clip(_dot(nc, lt), 0, 1), np.clip(_dot(nc, v), 0, 1)
    r = np.float64(roughness) if min_roughness is None else np.clip(roughness, min_roughness, 1.0)
    alpha = r * r
    with np.errstate(divide="ignore", invalid="ignore"):
        layer = ggx(np.clip(_dot(nc, h), 0, 1), alpha) * visibility(n_dot_l, n_dot_v, alpha)
    lit = np.where(n_dot_l > 0, np.pi * layer * n_dot_l, 0.0)
    return lit[..., None] * np.asarray(irradiance, np.float64)


def coated(base, coat, nc, v, clearcoat) -> np.ndarray:
    """base (1 - c Fc) + coat c Fc: the base layer's radiance (lights, ambient, emission) under the coat's."""
    w = (np.asarray(clearcoat, np.float64) * clearcoat_fresnel(nc, v))[..., None]
    return np.asarray(base, np.float64) * (1 - w) + np.asarray(coat, np.float64) * w


def split_sum(n_dot_v, roughness, f0, cells: int = 1024, turns: int = 64) -> np.ndarray:
    """The integral of F(f0, v.h) D V (n.l) over the hemisphere of l for a uniform sky of radiance 1 (what a split
    sum stands for): a midpoint rule over the GGX half-vector distribution, u in (0, 1) mapped to tan^2 theta_h =
    alpha^2 u / (1 - u) (density D (n.h)), so dw_l = 4 (v.h) dw_h gives the mean of F V (n.l) 4 (v.h) / (n.h)."""
    r = np.clip(roughness, MIN_ROUGHNESS, 1.0)
    alpha = r * r
    u = (np.arange(cells) + 0.5) / cells
    phi = (np.arange(turns) + 0.5) / turns * 2 * np.pi
    cos_h = 1 / np.sqrt(1 + alpha * alpha * u / (1 - u))
    sin_h = np.sqrt(1 - cos_h**2)
    h = np.stack([np.outer(sin_h, np.cos(phi)), np.outer(sin_h, np.sin(phi)), np.outer(cos_h, np.ones(turns))], -1)
    v = np.array([np.sqrt(1 - n_dot_v**2), 0.0, n_dot_v])
    v_dot_h = h @ v
    lt = 2 * v_dot_h[..., None] * h - v
    n_dot_l = lt[..., 2]
    fresnel = f0 + (1 - f0) * (1 - np.clip(v_dot_h, 0, 1)) ** 5
    with np.errstate(divide="ignore", invalid="ignore"):
        value = fresnel * visibility(np.clip(n_dot_l, 0, 1), n_dot_v, alpha) * n_dot_l * 4 * v_dot_h / h[..., 2]
    return float(np.where((n_dot_l > 0) & (v_dot_h > 0), value, 0.0).mean())
