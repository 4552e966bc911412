"""FXAA (the project's FXAA 3.11-style quality path) written again in float64 numpy, vectorised over pixels.

The algorithm as documented in shaders_wgsl/post_fxaa.wgsl's header, step for step: local contrast on
luma = sqrt(Rec. 709 luminance) with the 4 neighbours (early exit below the threshold), the sub-pixel
blend amount from the 3x3 average, the edge direction from second differences, the edge search (12 steps
of 1, 1, 1, 1, 1, 1.5, 2, 2, 2, 2, 4, 8 pixels, bilinear samples half a pixel across the edge), and one
bilinear fetch shifted across the edge. Texel reads clamp to the edge; the sampler is bilinear with
clamp-to-edge addressing. Nothing is imported from the renderer.
"""

from __future__ import annotations

import numpy as np

LUMA_709 = np.array([0.2126, 0.7152, 0.0722])  # ITU-R BT.709 luminance weights
STEPS = (1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0)


def luma(rgb: np.ndarray, weights: np.ndarray = LUMA_709) -> np.ndarray:
    return np.sqrt(np.maximum(rgb @ weights, 0.0))


def bilinear(img: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Sample (H, W, C) at normalised (u, v) like a linear, clamp-to-edge sampler (texel centres at i + 0.5)."""
    h, w = img.shape[:2]
    x, y = u * w - 0.5, v * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    xi0, yi0 = np.clip(x0.astype(int), 0, w - 1), np.clip(y0.astype(int), 0, h - 1)
    xi1, yi1 = np.clip(x0.astype(int) + 1, 0, w - 1), np.clip(y0.astype(int) + 1, 0, h - 1)
    top = img[yi0, xi0] * (1 - fx) + img[yi0, xi1] * fx
    bottom = img[yi1, xi0] * (1 - fx) + img[yi1, xi1] * fx
    return top * (1 - fy) + bottom * fy


def fxaa(img: np.ndarray, subpix: float = 0.75, edge_threshold: float = 0.166,
         edge_threshold_min: float = 0.0833, weights: np.ndarray = LUMA_709) -> np.ndarray:
    """FXAA of a linear (H, W, 4) image; returns (H, W, 4) float64 (alpha kept)."""
    img = np.asarray(img, np.float64)
    h, w = img.shape[:2]
    L = luma(img[..., :3], weights)  # noqa: N806
    pad = np.pad(L, 1, mode="edge")

    def at(dx: int, dy: int) -> np.ndarray:
        return pad[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]

    l_m, l_n, l_s, l_w, l_e = L, at(0, -1), at(0, 1), at(-1, 0), at(1, 0)
    l_max = np.maximum.reduce([l_m, l_n, l_s, l_w, l_e])
    l_min = np.minimum.reduce([l_m, l_n, l_s, l_w, l_e])
    rng = l_max - l_min
    edge = ~(rng < np.maximum(edge_threshold_min, l_max * edge_threshold))
    l_nw, l_ne, l_sw, l_se = at(-1, -1), at(1, -1), at(-1, 1), at(1, 1)

    safe_range = np.where(rng > 0.0, rng, 1.0)  # only edge pixels (range > 0) use the result
    average = (2.0 * (l_n + l_s + l_w + l_e) + (l_nw + l_ne + l_sw + l_se)) / 12.0
    sub_a = np.clip(np.abs(average - l_m) / safe_range, 0.0, 1.0)
    sub_b = (3.0 - 2.0 * sub_a) * sub_a * sub_a
    sub_offset = sub_b * sub_b * subpix

    change_y = np.abs(l_nw - 2 * l_w + l_sw) + 2 * np.abs(l_n - 2 * l_m + l_s) + np.abs(l_ne - 2 * l_e + l_se)
    change_x = np.abs(l_nw - 2 * l_n + l_ne) + 2 * np.abs(l_w - 2 * l_m + l_e) + np.abs(l_sw - 2 * l_s + l_se)
    horizontal = change_y >= change_x
    l_neg = np.where(horizontal, l_n, l_w)
    l_pos = np.where(horizontal, l_s, l_e)
    grad_neg, grad_pos = np.abs(l_neg - l_m), np.abs(l_pos - l_m)
    inv = np.array([1.0 / w, 1.0 / h])
    across = np.where(horizontal, inv[1], inv[0])
    neg_side = grad_neg >= grad_pos
    across = np.where(neg_side, -across, across)
    l_edge = np.where(neg_side, 0.5 * (l_neg + l_m), 0.5 * (l_pos + l_m))
    grad_scaled = 0.25 * np.maximum(grad_neg, grad_pos)

    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    u, v = xs * inv[0], ys * inv[1]
    along_u, along_v = np.where(horizontal, inv[0], 0.0), np.where(horizontal, 0.0, inv[1])
    edge_u = np.where(horizontal, u, u + 0.5 * across)
    edge_v = np.where(horizontal, v + 0.5 * across, v)

    def luma_uv(uu, vv):
        return luma(bilinear(img[..., :3], uu, vv), weights)

    ua, va = edge_u - along_u, edge_v - along_v
    ub, vb = edge_u + along_u, edge_v + along_v
    end_a, end_b = luma_uv(ua, va) - l_edge, luma_uv(ub, vb) - l_edge
    done_a, done_b = np.abs(end_a) >= grad_scaled, np.abs(end_b) >= grad_scaled
    for step in STEPS[1:]:
        go_a, go_b = ~done_a, ~done_b
        ua, va = np.where(go_a, ua - along_u * step, ua), np.where(go_a, va - along_v * step, va)
        ub, vb = np.where(go_b, ub + along_u * step, ub), np.where(go_b, vb + along_v * step, vb)
        end_a = np.where(go_a, luma_uv(ua, va) - l_edge, end_a)
        end_b = np.where(go_b, luma_uv(ub, vb) - l_edge, end_b)
        done_a |= go_a & (np.abs(end_a) >= grad_scaled)
        done_b |= go_b & (np.abs(end_b) >= grad_scaled)

    dist_a = np.where(horizontal, u - ua, v - va)
    dist_b = np.where(horizontal, ub - u, vb - v)
    nearer_a = dist_a < dist_b
    dist = np.minimum(dist_a, dist_b)
    edge_length = dist_a + dist_b
    centre_below = l_m < l_edge
    end_below = np.where(nearer_a, end_a < 0.0, end_b < 0.0)
    offset = np.where(end_below != centre_below, 0.5 - dist / np.maximum(edge_length, 1e-12), 0.0)
    offset = np.maximum(offset, sub_offset)

    final_u = np.where(horizontal, u, u + offset * across)
    final_v = np.where(horizontal, v + offset * across, v)
    out = img.copy()
    out[..., :3] = np.where(edge[..., None], bilinear(img[..., :3], final_u, final_v), img[..., :3])
    return out
