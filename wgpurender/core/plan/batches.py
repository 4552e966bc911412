"""Instanced draws: the plan batches draws that differ only in where they are.

Two draws become one instanced draw when they draw the same mesh (model file and file-material part) with the
same pipeline (variant, winding, cull, blend) and the same material values (textures, samplers, factors): the
GPU then repeats one ``draw_indexed`` / ``vkCmdDrawIndexed`` ``instance_count`` times, and each instance reads
its world matrix from the scene's ONE Object storage buffer at ``instance_index`` (which starts at the draw's
``first_instance``). A model with ``instances`` (core/scene/instances.py) is such a batch by itself; several
``[[models]]`` of the same mesh and material are merged into one.

Not batched: alpha-blended draws (glTF BLEND draws last in scene order; merging would reorder them). Opaque
batches keep the order of their first draw; draws inside a batch keep scene order, so only exact depth ties
between different batches can resolve differently from scene order (documented in docs/scenes.md).

:func:`instance_blocks` packs every instance's Object block (world, normal matrix, mirror sign; 128 bytes, the
same layout as a std140 uniform or std430 storage struct), the bytes both paths upload.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from wgpurender.core.plan.model import Draw, material_numbers
from wgpurender.core.scene import Placements
from wgpurender.core.view.transforms import determinants3

OBJECT_BYTES = 128  # world (64) + normal matrix as 3 padded columns (48) + mirror (4) + padding (12)


def batch_key(draw: Draw, blend: bool) -> tuple:
    """What must be equal for two draws to be one instanced draw; a blended draw's key is unique to it."""
    if blend:
        return ("blend", id(draw))
    return (draw.mesh_key, draw.part, draw.pipeline_key, draw.material_key())


def batch_draws(draws: list[Draw], blend_of: dict[str, bool]) -> list[Draw]:
    """Merge draws with equal :func:`batch_key` (first appearance decides the order) and number their instances."""
    groups: dict[tuple, list[Draw]] = {}
    materials, _ = material_numbers(draws)  # batch_key's material_key, hashed once per material (10k draws)
    for d, material in zip(draws, materials, strict=True):
        key = ("blend", id(d)) if blend_of[d.pipeline_key] else (d.mesh_key, d.part, d.pipeline_key, material)
        groups.setdefault(key, []).append(d)  # batch_key's grouping
    out, first = [], 0
    for members in groups.values():
        merged = _merge(members)
        out.append(_starting_at(merged, first))
        first += merged.instance_count
    return out


def _starting_at(draw: Draw, first: int) -> Draw:
    """``dataclasses.replace(draw, first_instance=first)`` without its __init__ (Draw has no __post_init__): a
    shallow copy of its fields with that one set (``copy.copy`` goes through ``__reduce_ex__``: ~10x dearer than
    this, for the 10k draws of a scene of distinct meshes)."""
    if draw.first_instance == first:
        return draw
    if hasattr(draw, "__post_init__"):  # then only __init__ makes a Draw right
        return dataclasses.replace(draw, first_instance=first)
    moved = object.__new__(type(draw))
    moved.__dict__.update(draw.__dict__, first_instance=first)  # a frozen dataclass: set past its __setattr__
    return moved


def _merge(members: list[Draw]) -> Draw:
    head = members[0]
    if len(members) == 1:
        return head
    worlds = stacked_worlds(members)
    models = ", ".join(d.label.split(" '")[0] for d in members[:3]) + (
        f" and {len(members) - 3} more" if len(members) > 3 else "")
    why = (f"{len(members)} draws ({models}) share mesh '{head.model_path.name}', pipeline {head.pipeline_key} "
           f"and {head.material_label}'s values: one draw of {len(worlds)} instances")
    label = f"{head.label} + {len(members) - 1} more"
    return dataclasses.replace(head, label=label, worlds=Placements.of(worlds, why), batch=why)


def instanced(draw: Draw, worlds: np.ndarray, description: str) -> Draw:
    """A model's own copies (its ``instances`` block) as one draw of ``len(worlds)`` instances."""
    if len(worlds) == 1:
        return dataclasses.replace(draw, transform=tuple(tuple(float(v) for v in r) for r in worlds[0]))
    why = f"{draw.label} has {len(worlds)} copies ({description}): one draw of {len(worlds)} instances"
    return dataclasses.replace(draw, transform=tuple(tuple(float(v) for v in r) for r in worlds[0]),
                               worlds=Placements.of(worlds, why), batch=why)


def normal_matrices(worlds: np.ndarray) -> np.ndarray:
    """(N, 3, 3) cofactor matrices, sign-corrected: :func:`wgpurender.core.view.transforms.normal_matrix` for N."""
    m = worlds[:, :3, :3]
    cof = np.cross(m[:, [1, 2, 0]], m[:, [2, 0, 1]])
    det = np.einsum("ij,ij->i", m[:, 0], cof[:, 0])
    return np.where((det >= 0)[:, None, None], cof, -cof)


def stacked_worlds(draws: list[Draw] | tuple[Draw, ...]) -> np.ndarray:
    """(total instances, 4, 4) float64: every draw's :meth:`Draw.world_matrices`, in order. A run of draws with
    one ``transform`` each is converted by ONE ``np.array`` (a scene of 10k distinct models made 10k small
    arrays and a 10k-piece concatenation here, issue 31.3)."""
    pieces, run = [], []
    for d in draws:
        if d.worlds is None:
            run.append(d.transform)
            continue
        if run:
            pieces.append(np.array(run, dtype=np.float64).reshape(-1, 4, 4))
            run = []
        pieces.append(d.world_matrices())
    if run:
        pieces.append(np.array(run, dtype=np.float64).reshape(-1, 4, 4))
    return np.concatenate(pieces) if pieces else np.zeros((0, 4, 4))


def instance_blocks(draws: list[Draw] | tuple[Draw, ...]) -> np.ndarray:
    """(total instances, 32) float32: each instance's Object block, in ``first_instance`` order."""
    worlds = stacked_worlds(draws)
    out = np.zeros((len(worlds), OBJECT_BYTES // 4), dtype=np.float32)
    out[:, :16] = worlds.transpose(0, 2, 1).reshape(-1, 16)  # column-major, as the shaders read a mat4
    normals = normal_matrices(worlds).transpose(0, 2, 1)  # columns
    for c in range(3):
        out[:, 16 + 4 * c: 19 + 4 * c] = normals[:, c]
    out[:, 28] = np.where(determinants3(worlds) >= 0, 1.0, -1.0)
    return out
