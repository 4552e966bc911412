"""glTF 2.0 geometry read by the project itself: the node graph, and every primitive's attributes and indices.

Nothing here goes through trimesh: positions, normals, TEXCOORD_n, TANGENT, COLOR_0 and indices all come from
:func:`wgpurender.core.models.gltf_io.read_accessor` (byteStride, normalized integer types and sparse accessors
supported), node transforms from the file's ``matrix`` or ``translation``/``rotation``/``scale``.

What is not drawn is said, never dropped silently: :func:`geometry_notes` lists it for ``--explain``
(points and lines primitives, unused texture coordinate sets); skins are posed (gltf_skin.py), animations sampled
at the scene's time (gltf_animation.py).
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files.input_files import MAX_MODEL_VERTICES, MAX_MODEL_VERTICES_ENV, env_limit
from wgpurender.core.models import gltf_compression, gltf_extensions, gltf_rules, gltf_skin
from wgpurender.core.models.gltf_io import GltfDocument, read_accessor

TRIANGLE_MODES = {4: "TRIANGLES", 5: "TRIANGLE_STRIP", 6: "TRIANGLE_FAN"}
SKIPPED_MODES = {0: "POINTS", 1: "LINES", 2: "LINE_LOOP", 3: "LINE_STRIP"}  # drawn with TOPOLOGIES
# glTF mode -> the list topology it is drawn with (strips and loops are turned into lists at load)
TOPOLOGIES = {0: "point-list", 1: "line-list", 2: "line-list", 3: "line-list", 4: "triangle-list",
              5: "triangle-list", 6: "triangle-list"}
FLOAT = 5126
# Texture coordinate slots a mesh carries at most: vertex attributes uv, uv1..uv4 (locations 2, 5-8 of scene.wgsl;
# with the 7 per-instance attributes at 9-15 they fill WebGPU's 16); core/plan/model.EXTRA_UV_SLOTS is the 4 beyond
# the first. A material's 8 textures could ask for more; one past the last is ignored by name.
MAX_UV_SLOTS = 5


@dataclass
class PrimitiveGeometry:
    """One triangle primitive's arrays, in its mesh's own space (mesh_primitives pairs it with the world matrix)."""

    positions: np.ndarray  # (N, 3) float64
    faces: np.ndarray  # (F, 3) int64, counter-clockwise front faces
    normals: np.ndarray | None
    uvs: np.ndarray | None  # (N, 2), glTF convention: v = 0 at the top; the first slot of uv_slots
    tangents: np.ndarray | None  # (N, 4)
    colors: np.ndarray | None  # (N, 4) linear RGBA
    material: int | None
    where: str  # e.g. "mesh 0 'box' primitive 1 (node 3)"
    topology: str = "triangle-list"  # faces (F, 3); "line-list": (F, 2) segments; "point-list": (F, 1)
    extra_uvs: tuple[np.ndarray | None, ...] = ()  # (N, 2) each: the material's coordinate slots 1.. (uv_slots)
    joints: tuple[np.ndarray, ...] = ()  # JOINTS_0, JOINTS_1, ...: (N, 4) each, for a skin (gltf_skin.py)
    weights: tuple[np.ndarray, ...] = ()  # WEIGHTS_0, ...: (N, 4) each


def node_matrix(node: dict) -> np.ndarray:
    """A node's local matrix: ``matrix`` (column-major) or T @ R @ S from translation, rotation (x, y, z, w), scale."""
    if "matrix" in node:
        return np.asarray(node["matrix"], np.float64).reshape(4, 4).T
    x, y, z, w = node.get("rotation", (0.0, 0.0, 0.0, 1.0))
    q = np.array([x, y, z, w], np.float64)
    norm = np.linalg.norm(q)
    x, y, z, w = q / norm if norm > 0 else (0.0, 0.0, 0.0, 1.0)
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = rot * np.asarray(node.get("scale", (1.0, 1.0, 1.0)), np.float64)[None, :]
    m[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return m


def root_nodes(doc: GltfDocument) -> list[int]:
    """The nodes the file asks to draw (gltf_rules.root_nodes)."""
    return gltf_rules.root_nodes(doc.json)


def node_worlds(doc: GltfDocument) -> list[tuple[np.ndarray, int, dict]]:
    """(world matrix, node index, node) for every node of the drawn scene, depth first in file order (a forest:
    gltf_rules refused loops and second parents when the document was read). Lights and cameras are placed so."""
    nodes = doc.json.get("nodes", [])
    out = []
    stack = [(index, np.eye(4)) for index in reversed(root_nodes(doc))] if nodes else []
    while stack:
        index, parent = stack.pop()
        world = parent @ node_matrix(nodes[index])
        out.append((world, index, nodes[index]))
        stack.extend((child, world) for child in reversed(nodes[index].get("children", [])))
    return out


def placed_meshes(doc: GltfDocument) -> list[tuple[np.ndarray, int, int]]:
    """(world matrix, mesh index, node index) for every node that places a mesh, depth first in file order.
    The graph is a forest with unique roots (gltf_rules refuses loops, second parents and repeated roots before
    this runs), so each node is visited once; a second visit is still refused rather than followed."""
    nodes = doc.json.get("nodes", [])
    if not nodes:
        return [(np.eye(4), i, -1) for i in range(len(doc.json.get("meshes", [])))]
    out: list[tuple[np.ndarray, int, int]] = []
    stack = [(index, np.eye(4)) for index in reversed(root_nodes(doc))]
    visited: set[int] = set()
    while stack:
        index, parent = stack.pop()
        if index in visited:
            raise UserError(f"malformed glTF file {doc.path}: node {index} is reached twice (a cycle or a second "
                            "parent); nodes must form trees: re-export the file")
        visited.add(index)
        node = nodes[index]
        world = parent @ node_matrix(node)
        if "mesh" in node:
            out.extend((placement, node["mesh"], index) for placement in _instances(doc, node, world))
        for child in reversed(node.get("children", [])):
            stack.append((child, world))
    return out


def _instances(doc: GltfDocument, node: dict, world: np.ndarray) -> list[np.ndarray]:
    """The world matrices a node places its mesh at: its own, or one per EXT_mesh_gpu_instancing instance
    (world @ T @ R @ S of each instance), expanded here into placements of the one mesh."""
    ext = node.get("extensions", {}).get(gltf_extensions.INSTANCING)
    if not isinstance(ext, dict) or not ext.get("attributes"):
        return [world]
    attrs = ext["attributes"]
    arrays = {k: read_accessor(doc, attrs[k]).astype(np.float64) if k in attrs else None
              for k in ("TRANSLATION", "ROTATION", "SCALE")}
    if all(a is None for a in arrays.values()):
        return [world]
    counts = {len(a) for a in arrays.values() if a is not None}
    if len(counts) != 1:
        raise UserError(f"malformed glTF file {doc.path}: {gltf_extensions.INSTANCING} attributes of a node have "
                        f"different counts {sorted(counts)}; each needs one element per instance")
    matrices = gltf_extensions.instance_matrices(arrays["TRANSLATION"], arrays["ROTATION"], arrays["SCALE"])
    return list(world @ matrices)


def _attribute(doc: GltfDocument, prim: dict, name: str, where: str) -> np.ndarray | None:
    """An attribute through the project's accessor reader, as float64. Accessor and component types were checked
    with the document (gltf_rules.py); integer attributes must be normalized unless KHR_mesh_quantization allows
    plain integers for the semantic (POSITION and TEXCOORD: its table lists both forms)."""
    index = prim.get("attributes", {}).get(name)
    if index is None:
        return None
    acc = doc.json["accessors"][index]
    if acc.get("componentType") != FLOAT and not acc.get("normalized", False):
        semantic = name.split("_", 1)[0] if name.startswith("TEXCOORD_") else name
        if not gltf_extensions.uses(doc.json, gltf_extensions.QUANTIZATION) or semantic not in ("POSITION",
                                                                                              "TEXCOORD"):
            raise UserError(f"glTF file {doc.path}: {where} {name} has integer components that are not "
                            "normalized; glTF allows that only for POSITION and TEXCOORD with "
                            "KHR_mesh_quantization in extensionsUsed: fix or re-export the file")
    return read_accessor(doc, index).astype(np.float64)


def _faces(doc: GltfDocument, prim: dict, count: int) -> np.ndarray:
    """Triangles of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN primitive, counter-clockwise as the file means."""
    if "indices" in prim:  # SCALAR unsigned integers: checked with the document (gltf_rules.py)
        idx = read_accessor(doc, prim["indices"]).reshape(-1).astype(np.int64)
    else:
        idx = np.arange(count, dtype=np.int64)
    mode = prim.get("mode", 4)
    if mode in SKIPPED_MODES:
        return _points_and_lines(idx, mode)
    if mode == 4:
        return idx[: len(idx) // 3 * 3].reshape(-1, 3)
    n = max(len(idx) - 2, 0)
    i = np.arange(n)
    if mode == 5:  # strip: triangle i is (i, i+1, i+2), every odd one turned around to keep the winding
        odd = (i % 2).astype(bool)
        a, b = np.where(odd, idx[i + 1], idx[i]), np.where(odd, idx[i], idx[i + 1])
        return np.stack([a, b, idx[i + 2]], axis=1)
    return np.stack([idx[i + 1], idx[i + 2], np.full(n, idx[0]) if n else idx[:0]], axis=1)  # fan around idx[0]


def _points_and_lines(idx: np.ndarray, mode: int) -> np.ndarray:
    """POINTS as (N, 1); LINES, LINE_STRIP and LINE_LOOP as (segments, 2) of a line list."""
    if mode == 0:
        return idx.reshape(-1, 1)
    if mode == 1:
        return idx[: len(idx) // 2 * 2].reshape(-1, 2)
    ends = np.append(idx[1:], idx[:1]) if mode == 2 and len(idx) > 2 else idx[1:]  # a loop closes on its first
    return np.stack([idx[: len(ends)], ends], axis=1)


def texture_infos(doc: GltfDocument, material: int | None) -> list[dict]:
    """A material's textureInfo objects: the normal textures first (generated tangents follow the mesh's first
    coordinate slot, and a normal map needs tangents of its own coordinates), then base colour,
    metallic-roughness, emissive, occlusion, then KHR_materials_clearcoat's two others."""
    if material is None:
        return []
    mat = doc.json.get("materials", [])[material]
    coat = mat.get("extensions", {}).get(gltf_extensions.CLEARCOAT)
    coat = coat if isinstance(coat, dict) else {}
    infos = [mat.get("normalTexture"), mat.get("pbrMetallicRoughness", {}).get("baseColorTexture"),
             mat.get("pbrMetallicRoughness", {}).get("metallicRoughnessTexture"), mat.get("emissiveTexture"),
             mat.get("occlusionTexture")]
    infos[1:1] = [coat.get("clearcoatNormalTexture")]  # the other normal map: right after the base's
    infos += [coat.get("clearcoatTexture"), coat.get("clearcoatRoughnessTexture")]
    spec_gloss = mat.get("extensions", {}).get("KHR_materials_pbrSpecularGlossiness")  # converted at load
    if isinstance(spec_gloss, dict):  # (core/scene/gltf_specgloss.py): sampled on diffuse's coordinates, else its own
        infos += [spec_gloss.get("diffuseTexture"), spec_gloss.get("specularGlossinessTexture")]
    return [i for i in infos if isinstance(i, dict)]


def uv_slots(doc: GltfDocument, material: int | None) -> list[tuple[int, dict | None, tuple]]:
    """The texture coordinates a material's mesh carries, one slot per distinct (TEXCOORD set,
    KHR_texture_transform) its textures sample with, in :func:`texture_infos` order: (set, transform or None,
    transform key); at most :data:`MAX_UV_SLOTS` (a texture past them samples nothing: gltf_materials ignores it
    by name). The transform is applied to the slot's coordinates at load
    (affine: interpolating transformed coordinates equals transforming interpolated ones), so each texture samples
    its own set with its own transform, and the shader only picks a slot per texture (the plan's ``<map>_uv<k>``
    variant flags): a material whose textures all sample alike carries one slot and costs nothing more."""
    slots: list[tuple[int, dict | None, tuple]] = []
    for info in texture_infos(doc, material):
        if len(slots) == MAX_UV_SLOTS:
            break
        texcoord, key = gltf_extensions.texture_uv_choice(info)
        if all((s, k) != (texcoord, key) for s, _, k in slots):
            transform = info.get("extensions", {}).get(gltf_extensions.TEXTURE_TRANSFORM)
            slots.append((texcoord, transform if isinstance(transform, dict) else None, key))
    return slots or [(0, None, ())]


def texture_slot(doc: GltfDocument, material: int, info: dict) -> int | None:
    """The slot of :func:`uv_slots` one of the material's textureInfos samples with (None: past the last)."""
    choice = gltf_extensions.texture_uv_choice(info)
    choices = [(s, k) for s, _, k in uv_slots(doc, material)]
    return choices.index(choice) if choice in choices else None


def _morph(doc: GltfDocument, prim: dict, weights, where: str, positions, normals, tangents):
    """POSITION, NORMAL and TANGENT with the default morph weights applied (``weights``: the node's, else the
    mesh's; none given means all 0, the base pose)."""
    targets = prim["targets"]
    weights = list(weights or ())
    if weights and len(weights) != len(targets):
        raise UserError(f"malformed glTF file {doc.path}: {where} has {len(targets)} morph targets but "
                        f"{len(weights)} weights; give one weight per target")
    if not any(weights):
        return positions, normals, tangents
    deltas = {name: [_attribute(doc, {"attributes": t}, name, where) for t in targets]
              for name in ("POSITION", "NORMAL", "TANGENT")}
    for name, arrays in deltas.items():
        for k, delta in enumerate(arrays):
            if delta is not None and len(delta) != len(positions):
                raise UserError(f"malformed glTF file {doc.path}: {where} morph target {k} {name} has {len(delta)} "
                                f"elements, the primitive {len(positions)} vertices; give every target one per vertex")
    return (gltf_extensions.morphed(positions, deltas["POSITION"], weights),
            gltf_extensions.morphed(normals, deltas["NORMAL"], weights),
            gltf_extensions.morphed(tangents, deltas["TANGENT"], weights))


def primitive_geometry(doc: GltfDocument, prim: dict, where: str, weights=None) -> PrimitiveGeometry | None:
    """One primitive's triangles (or points, or line segments: ``topology``) and attributes in its mesh's own
    space (the caller applies the node's world matrix)."""
    mode = prim.get("mode", 4)
    if mode not in TOPOLOGIES:
        raise UserError(f"malformed glTF file {doc.path}: {where} has mode {mode}; glTF 2.0 modes are 0..6")
    material = prim.get("material")
    slots = uv_slots(doc, material)
    uv_names = [f"TEXCOORD_{s}" for s, _, _ in slots]
    names = ("POSITION", "NORMAL", *dict.fromkeys(uv_names), "TANGENT", "COLOR_0")
    draco = gltf_compression.uses_draco(doc, prim)  # else its uncompressed fallback accessors
    if draco:
        decoded, draco_faces = gltf_compression.draco_attributes(doc, prim, where)
        arrays = {name: decoded.get(name) for name in names}
    else:
        arrays = {name: _attribute(doc, prim, name, where) for name in names}
    positions = arrays.pop("POSITION")
    if positions is None:
        raise UserError(f"malformed glTF file {doc.path}: {where} has no POSITION attribute (glTF requires it)")
    count = len(positions)
    for name, array in arrays.items():
        if array is not None and len(array) != count:
            raise UserError(f"malformed glTF file {doc.path}: {where} {name} has {len(array)} elements, "
                            f"POSITION {count}")
    if prim.get("targets"):  # a Draco primitive's targets are plain accessors in its decoded vertex order
        positions, arrays["NORMAL"], arrays["TANGENT"] = _morph(doc, prim, weights, where, positions,
                                                                arrays["NORMAL"], arrays["TANGENT"])
    uvs = [_slot_uvs(arrays[name], transform) for name, (_, transform, _) in zip(uv_names, slots, strict=True)]
    faces = draco_faces if draco else _faces(doc, prim, count)
    if len(faces) and (faces.min() < 0 or faces.max() >= count):
        raise UserError(f"malformed glTF file {doc.path}: {where} has indices outside 0..{count - 1}")
    colors = arrays["COLOR_0"]
    if colors is not None and colors.shape[1] == 3:
        colors = np.concatenate([colors, np.ones((count, 1))], axis=1)
    joints, weights = _skin_sets(doc, prim, decoded if draco else None)
    geometry = PrimitiveGeometry(positions, faces, arrays["NORMAL"], uvs[0], arrays["TANGENT"], colors,
                                 material, where, TOPOLOGIES[mode], tuple(uvs[1:]), joints, weights)
    return flat_shaded(geometry) if geometry.normals is None and geometry.topology == "triangle-list" else geometry


def _skin_sets(doc: GltfDocument, prim: dict, decoded: dict | None) -> tuple[tuple, tuple]:
    """(JOINTS_0.., WEIGHTS_0..) of a primitive, every set it has (a Draco primitive's decoded ones)."""
    attributes, joints, weights = prim.get("attributes", {}), [], []
    for k in range(len(attributes)):
        names = f"JOINTS_{k}", f"WEIGHTS_{k}"
        if not any(n in attributes for n in names):
            break
        for name, out in zip(names, (joints, weights), strict=True):
            if name in attributes:
                array = decoded[name] if decoded and name in decoded else read_accessor(doc, attributes[name])
                out.append(np.asarray(array, np.float64))
    return tuple(joints), tuple(weights)  # one element per vertex each: gltf_rules checked the counts


def _slot_uvs(uvs: np.ndarray | None, transform: dict | None) -> np.ndarray | None:
    """One slot's coordinates: the set's values under the slot's KHR_texture_transform (a copy: two slots may
    read one set)."""
    if uvs is None or transform is None:
        return uvs
    return gltf_extensions.transform_uvs(uvs, transform)


def flat_shaded(g: PrimitiveGeometry) -> PrimitiveGeometry:
    """glTF 2.0, 3.7.2.1: "When normals are not specified, client implementations MUST calculate flat normals and
    the provided tangents (if present) MUST be ignored." Each triangle gets its own three vertices with its face
    normal (counter-clockwise front); smooth vertex normals would round a cube's edges."""
    corners = g.faces.reshape(-1)
    tri = g.positions[g.faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # unnormalised: build_mesh normalises
    uvs = None if g.uvs is None else g.uvs[corners]
    extra_uvs = tuple(None if a is None else a[corners] for a in g.extra_uvs)
    colors = None if g.colors is None else g.colors[corners]
    faces = np.arange(len(corners), dtype=np.int64).reshape(-1, 3)
    return PrimitiveGeometry(g.positions[corners], faces, np.repeat(normal, 3, axis=0), uvs, None, colors,
                             g.material, g.where, extra_uvs=extra_uvs, joints=tuple(a[corners] for a in g.joints),
                             weights=tuple(a[corners] for a in g.weights))


def mesh_primitives(doc: GltfDocument) -> list[tuple[np.ndarray, str, PrimitiveGeometry]]:
    """(world matrix, node label, geometry) of every primitive the file's scene places (triangles, points and
    line segments: ``geometry.topology``). A primitive placed many times (nodes, EXT_mesh_gpu_instancing) is read
    once per set of morph weights; the placed vertices (instances multiply them) are bounded like the file's own."""
    check_something_to_draw(doc)
    meshes = doc.json.get("meshes", [])
    out, read, placed, skins = [], {}, 0, {}
    limit = env_limit(MAX_MODEL_VERTICES_ENV, MAX_MODEL_VERTICES)
    nodes = doc.json.get("nodes", [])
    for world, mesh_index, node_index in placed_meshes(doc):
        mesh = meshes[mesh_index]
        name = f" '{mesh['name']}'" if mesh.get("name") else ""
        weights = nodes[node_index].get("weights", mesh.get("weights")) if node_index >= 0 else mesh.get("weights")
        for p, prim in enumerate(mesh.get("primitives", [])):
            where = f"mesh {mesh_index}{name} primitive {p}" + (f" (node {node_index})" if node_index >= 0 else "")
            key = (mesh_index, p, json.dumps(weights))
            if key not in read:
                read[key] = primitive_geometry(doc, prim, where, weights)
            geometry = read[key]
            if geometry is not None and node_index >= 0 and "skin" in nodes[node_index]:
                geometry = posed_skin(doc, node_index, geometry, skins)
            if geometry is not None and len(geometry.faces):
                placed += len(geometry.positions)
                if placed > limit:
                    raise UserError(f"{doc.path}: its nodes and instances place over {limit} vertices, more than "
                                    f"the model limit allows; raise ${MAX_MODEL_VERTICES_ENV} if the model is real")
                out.append((world, f"node {node_index} mesh {mesh_index}{name}", geometry))
    return out


def posed_skin(doc: GltfDocument, node: int, g: PrimitiveGeometry, cache: dict) -> PrimitiveGeometry:
    """A skinned node's primitive with its vertices posed by the skin's joints (gltf_skin.py), in the node's own
    space like any primitive; ``cache`` keeps the node globals and each node's joint matrices."""
    if "globals" not in cache:
        nodes = doc.json["nodes"]
        cache["globals"] = gltf_skin.global_matrices(nodes, [node_matrix(n) for n in nodes])
    if node not in cache:
        cache[node] = gltf_skin.joint_matrices(doc, doc.json["nodes"][node]["skin"], node, cache["globals"])
    if not g.joints:
        raise UserError(f"malformed glTF file {doc.path}: {g.where} is skinned (its node has a skin) but has no "
                        "JOINTS_0/WEIGHTS_0; fix or re-export the file")
    where = f"malformed glTF file {doc.path}: {g.where}"
    m = gltf_skin.blend(list(g.joints), list(g.weights), cache[node], where)
    positions, normals, tangents = gltf_skin.skinned(g.positions, g.normals, g.tangents, m)
    return dataclasses.replace(g, positions=positions, normals=normals, tangents=tangents)


DRAWN_MODES = TRIANGLE_MODES  # the modes a file needs one of: points and lines are drawn only beside triangles
MODE_NAMES = {**SKIPPED_MODES, **TRIANGLE_MODES}


def check_something_to_draw(doc: GltfDocument) -> None:
    """Refuse, in one line, a file whose scene places no mesh or only primitives of modes not drawn (points,
    lines): it would render an empty image with exit 0. Both the mesh loader and the file's materials ask here."""
    placed = gltf_rules.mesh_placements(doc.json)
    if not placed:
        raise UserError(f"glTF file {doc.path}: nothing to draw: its scene places no mesh (no node of the drawn "
                        "scene has a 'mesh'); add the mesh's node to the scene's nodes and re-export")
    meshes = doc.json.get("meshes", [])
    modes = {prim.get("mode", 4) for m in placed for prim in meshes[m]["primitives"]}
    if not modes & set(DRAWN_MODES):
        found = ", ".join(MODE_NAMES.get(m, str(m)) for m in sorted(modes))
        raise UserError(f"glTF file {doc.path}: nothing to draw: its placed primitives are {found} only, and "
                        f"wgpurender draws {', '.join(MODE_NAMES[m] for m in DRAWN_MODES)} (points and lines only "
                        "beside them); export faces")


def geometry_notes(doc: GltfDocument) -> list[str]:
    """What the file has that is not drawn, one line each (for ``--explain``)."""
    notes, gltf = [], doc.json
    skinned = {node["mesh"] for node in gltf.get("nodes", []) if "skin" in node and "mesh" in node}
    for mi, mesh in enumerate(gltf.get("meshes", [])):
        for pi, prim in enumerate(mesh.get("primitives", [])):
            mode = prim.get("mode", 4)
            if mode in SKIPPED_MODES:
                notes.append(f"mesh {mi} primitive {pi}: {SKIPPED_MODES[mode]} primitive drawn unlit as a "
                             f"{TOPOLOGIES[mode]} of 1-pixel {'points' if mode == 0 else 'lines'} (points and lines "
                             "have no surface to light)")
            used = {f"TEXCOORD_{s}" for s, _, _ in uv_slots(doc, prim.get("material"))}
            extra = sorted(a for a in prim.get("attributes", {}) if a.startswith("TEXCOORD_") and a not in used)
            extra += sorted(a for a in prim.get("attributes", {})
                            if (a.startswith(("JOINTS_", "WEIGHTS_")) and mi not in skinned)
                            or (a.startswith("COLOR_") and a != "COLOR_0"))
            if extra:
                notes.append(f"mesh {mi} primitive {pi}: attribute(s) {', '.join(extra)} ignored")
    return notes
