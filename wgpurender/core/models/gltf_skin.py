"""glTF 2.0 skins posed on the CPU at load (glTF 2.0, 3.7.3): linear blend skinning with numpy, API-free.

Both paths upload the vertices this module poses, so they draw the same pose. For a mesh node ``n`` with skin
``s``, joint ``j``'s matrix is ``inverse(global(n)) @ global(joint j) @ inverseBindMatrix j``; a vertex blends
the matrices its JOINTS_k name with its WEIGHTS_k (every set k the primitive has; weights normalized to sum 1),
and the node's own world matrix is applied after, as for any mesh, which cancels the inverse: the skinned mesh
lands where its joints put it, the node's transform ignored, as the specification requires. Normals move by the
blended matrix's inverse transpose (its cofactor matrix, times the sign of its determinant: defined even where a
blend is singular), tangents by the matrix itself.
"""

from __future__ import annotations

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.models.gltf_io import GltfDocument, read_accessor
from wgpurender.core.view import transforms


def global_matrices(nodes: list[dict], local: list[np.ndarray]) -> np.ndarray:
    """(N, 4, 4): every node's global matrix, parent @ local down each tree (gltf_rules refused loops and second
    parents, so each node has at most one parent)."""
    parent = {child: i for i, node in enumerate(nodes) for child in node.get("children", [])}
    out: list[np.ndarray | None] = [None] * len(nodes)
    for start in range(len(nodes)):
        chain, node = [], start
        while node is not None and out[node] is None:
            chain.append(node)
            node = parent.get(node)
        above = np.eye(4) if node is None else out[node]
        for i in reversed(chain):
            above = out[i] = above @ local[i]
    return np.array(out, dtype=np.float64).reshape(-1, 4, 4)


def joint_matrices(doc: GltfDocument, skin_index: int, mesh_node: int, globals_: np.ndarray) -> np.ndarray:
    """(J, 4, 4): inverse(global(mesh node)) @ global(joint) @ inverseBindMatrix, per joint of the skin."""
    skin = doc.json["skins"][skin_index]
    joints = skin["joints"]
    where = f"malformed glTF file {doc.path}: skin {skin_index}"
    if "inverseBindMatrices" in skin:
        raw = read_accessor(doc, skin["inverseBindMatrices"]).astype(np.float64)
        if raw.shape[1] != 16 or len(raw) < len(joints):
            raise UserError(f"{where}: inverseBindMatrices needs one MAT4 per joint ({len(joints)}), got "
                            f"{len(raw)} of {raw.shape[1]} components; fix or re-export the file")
        inverse_bind = raw[: len(joints)].reshape(-1, 4, 4).transpose(0, 2, 1)  # stored column-major
    else:
        inverse_bind = np.broadcast_to(np.eye(4), (len(joints), 4, 4))
    singular = np.flatnonzero(transforms.flat(inverse_bind) | ~np.all(np.isfinite(inverse_bind), axis=(1, 2)))
    if len(singular):
        raise UserError(f"{where}: the inverse bind matrix of joint {int(singular[0])} (node "
                        f"{joints[int(singular[0])]}) is singular or not finite, so its bind pose is undefined; "
                        "fix or re-export the file")
    return np.linalg.inv(globals_[mesh_node]) @ globals_[joints] @ inverse_bind


def blend(joints: list[np.ndarray], weights: list[np.ndarray], matrices: np.ndarray, where: str) -> np.ndarray:
    """(V, 4, 4): each vertex's matrix, its joints' matrices weighted (the weights normalized to sum 1)."""
    if len(joints) != len(weights) or any(len(j) != len(w) for j, w in zip(joints, weights, strict=False)):
        raise UserError(f"{where} has {len(joints)} JOINTS_n and {len(weights)} WEIGHTS_n set(s) of different sizes; "
                        "each JOINTS_n needs its WEIGHTS_n with one value per vertex: fix or re-export the file")
    index = np.concatenate(joints, axis=1).astype(np.int64)
    weight = np.concatenate(weights, axis=1).astype(np.float64)
    if index.size and (index.min() < 0 or index.max() >= len(matrices)):
        raise UserError(f"{where} names joint {int(index.max())}, but its skin has {len(matrices)} joints "
                        f"(0..{len(matrices) - 1}); fix or re-export the file")
    total = weight.sum(axis=1, keepdims=True)
    if not np.all(np.isfinite(weight)) or np.any(weight < 0) or np.any(total <= 0):
        raise UserError(f"{where} has a vertex whose WEIGHTS_n are negative, not finite or all 0 (glTF needs "
                        "weights >= 0 summing to 1); fix or re-export the file")
    weight = weight / total
    blended = np.zeros((len(index), 4, 4))
    for k in range(index.shape[1]):  # one influence slot at a time: (V, 4, 4) at most, not (V, slots, 4, 4)
        blended += weight[:, k, None, None] * matrices[index[:, k]]
    return blended


def skinned(positions: np.ndarray, normals: np.ndarray | None, tangents: np.ndarray | None, m: np.ndarray):
    """Positions, normals and tangents moved by their per-vertex matrices ``m`` (V, 4, 4)."""
    rot = m[:, :3, :3]
    out_positions = np.einsum("vij,vj->vi", rot, positions) + m[:, :3, 3]
    sign = np.sign(transforms.determinants3(rot))
    out_normals = out_tangents = None
    if normals is not None:
        a, b, c = rot[:, :, 0], rot[:, :, 1], rot[:, :, 2]
        cofactor = np.stack([np.cross(b, c), np.cross(c, a), np.cross(a, b)], axis=2)  # det x inverse transpose
        out_normals = np.einsum("vij,vj->vi", cofactor, normals) * np.where(sign < 0, -1.0, 1.0)[:, None]
    if tangents is not None:
        xyz = np.einsum("vij,vj->vi", rot, tangents[:, :3])
        out_tangents = np.concatenate([xyz, tangents[:, 3:] * np.where(sign < 0, -1.0, 1.0)[:, None]], axis=1)
    return out_positions, out_normals, out_tangents
