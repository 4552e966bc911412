"""glTF 2.0 rules beyond the JSON shapes (gltf_schema.py): the node graph and the accessor each semantic needs.

Checked before trimesh reads the file, as Khronos' glTF-Validator does (its issue codes in brackets):

- the nodes form disjoint trees: no node is its own descendant [NODE_LOOP], none has two parents
  [NODE_PARENT_OVERRIDE]; trimesh raised a ValueError for a node that lists itself as a child;
- each attribute semantic has the accessor type and component type the specification lists (glTF 2.0, 3.7.2.1
  "Meshes: overview") [MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT]: a SCALAR POSITION ended in numpy's
  "cannot reshape"; indices are SCALAR unsigned integers [MESH_PRIMITIVE_INDICES_ACCESSOR_INVALID_FORMAT];
- every attribute of a primitive has as many elements as its POSITION [MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT];
- accessor types and component types are ones the specification names.

Each failure is a ValueError naming its JSON path; gltf_io turns it into the user's one line.
"""

from __future__ import annotations

import re
from typing import Any

from wgpurender.core.models import gltf_extensions

FLOAT, BYTE, UBYTE, SHORT, USHORT, UINT = 5126, 5120, 5121, 5122, 5123, 5125
COMPONENT_NAMES = {BYTE: "BYTE", UBYTE: "UNSIGNED_BYTE", SHORT: "SHORT", USHORT: "UNSIGNED_SHORT",
                   UINT: "UNSIGNED_INT", FLOAT: "FLOAT"}
ACCESSOR_TYPES = ("SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4")

# semantic pattern -> (accessor types, component types); normalized integer formats are listed as the integers
SEMANTICS = (
    (r"POSITION", ("VEC3",), (FLOAT,)),
    (r"NORMAL", ("VEC3",), (FLOAT,)),
    (r"TANGENT", ("VEC4",), (FLOAT,)),
    (r"TEXCOORD_\d+", ("VEC2",), (FLOAT, UBYTE, USHORT)),
    (r"COLOR_\d+", ("VEC3", "VEC4"), (FLOAT, UBYTE, USHORT)),
    (r"JOINTS_\d+", ("VEC4",), (UBYTE, USHORT)),
    (r"WEIGHTS_\d+", ("VEC4",), (FLOAT, UBYTE, USHORT)),
)
INDEX_COMPONENTS = (UBYTE, USHORT, UINT)


def check_rules(document: dict) -> None:
    """Raise ValueError("$.path: ...") at the first rule ``document`` (already schema-checked) breaks."""
    check_buffer_views(document)
    check_accessors(document)
    check_images(document)
    check_node_graph(document)
    check_scene_roots(document)
    check_primitives(document)


COMPONENT_BYTES = {BYTE: 1, UBYTE: 1, SHORT: 2, USHORT: 2, UINT: 4, FLOAT: 4}
TYPE_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
SPARSE_INDEX_COMPONENTS = INDEX_COMPONENTS  # unsigned, as indices


def check_buffer_views(document: dict) -> None:
    """byteStride is a multiple of 4 in 4..252 (bufferView.schema.json) [BUFFER_VIEW_INVALID_BYTE_STRIDE]."""
    for i, view in enumerate(document.get("bufferViews", [])):
        stride = view.get("byteStride")
        if stride is not None and not (4 <= stride <= 252 and stride % 4 == 0):
            raise ValueError(f"$.bufferViews[{i}].byteStride must be a multiple of 4 in 4..252, got {stride}")


def check_accessors(document: dict) -> None:
    views = document.get("bufferViews", [])
    for i, acc in enumerate(document.get("accessors", [])):
        if acc["type"] not in ACCESSOR_TYPES:
            raise ValueError(f"$.accessors[{i}].type must be one of {', '.join(ACCESSOR_TYPES)}, got {acc['type']!r}")
        if acc["componentType"] not in COMPONENT_NAMES:
            raise ValueError(f"$.accessors[{i}].componentType must be one of "
                             f"{', '.join(map(str, COMPONENT_NAMES))}, got {acc['componentType']}")
        size = COMPONENT_BYTES[acc["componentType"]] * TYPE_WIDTHS[acc["type"]]
        stride = views[acc["bufferView"]].get("byteStride") if "bufferView" in acc else None
        if stride is not None and stride < size:  # [ACCESSOR_TOO_LONG / BUFFER_VIEW_TOO_SHORT_STRIDE]
            raise ValueError(f"$.bufferViews[{acc['bufferView']}].byteStride {stride} is below the {size}-byte "
                             f"element of $.accessors[{i}]: elements would overlap")
        if "sparse" in acc:
            _check_sparse(acc, f"$.accessors[{i}].sparse")


def _check_sparse(acc: dict, where: str) -> None:
    sparse = acc["sparse"]
    if not 1 <= sparse["count"] <= acc["count"]:
        raise ValueError(f"{where}.count must be in 1..{acc['count']} (the accessor's count), got {sparse['count']}")
    component = sparse["indices"]["componentType"]
    if component not in SPARSE_INDEX_COMPONENTS:
        raise ValueError(f"{where}.indices.componentType must be 5121, 5123 or 5125 (unsigned), got {component}")


def check_images(document: dict) -> None:
    """An image has exactly one of uri and bufferView (image.schema.json: oneOf)."""
    for i, image in enumerate(document.get("images", [])):
        if ("uri" in image) == ("bufferView" in image):
            raise ValueError(f"$.images[{i}] needs exactly one of 'uri' and 'bufferView', "
                             f"got {'both' if 'uri' in image else 'neither'}")


def check_node_graph(document: dict) -> None:
    """Nodes form disjoint trees: a node that is its own child (or descendant), or has two parents, is refused.
    Linear in the number of nodes: each node is walked up from once, stopping at a node already known to be in a
    tree (a 20,000-node chain was walked 20,000 times before)."""
    nodes = document.get("nodes", [])
    parent: dict[int, int] = {}
    for i, node in enumerate(nodes):
        for j, child in enumerate(node.get("children", [])):
            if child == i:
                raise ValueError(f"$.nodes[{i}].children[{j}] = {i}: a node cannot be its own child")
            if child in parent and parent[child] != i:
                raise ValueError(f"$.nodes[{i}].children[{j}] = {child}: node {child} already has the parent "
                                 f"{parent[child]}; a node has at most one parent")
            parent[child] = i
    in_tree: set[int] = set()  # nodes whose walk up reached a root
    for start in range(len(nodes)):
        walk, node = {start}, start
        while node in parent and node not in in_tree:
            node = parent[node]
            if node in walk:
                raise ValueError(f"$.nodes[{start}]: the node hierarchy has a cycle through node {node}; "
                                 "nodes must form trees")
            walk.add(node)
        in_tree |= walk


def check_scene_roots(document: dict) -> None:
    """A scene lists root nodes, each once (scene.schema.json: uniqueItems) [SCENE_NON_ROOT_NODE]: a child listed
    as a root, or a root listed twice, would place its whole subtree again (quadratic in a long chain)."""
    children = {c for node in document.get("nodes", []) for c in node.get("children", [])}
    for s, scene in enumerate(document.get("scenes", [])):
        seen: set[int] = set()
        for k, node in enumerate(scene.get("nodes", [])):
            if node in children or node in seen:
                why = "is the child of another node" if node in children else "is listed twice"
                raise ValueError(f"$.scenes[{s}].nodes[{k}] = {node} {why}; a scene lists each root node once")
            seen.add(node)


def _semantic_rule(name: str) -> tuple[tuple[str, ...], tuple[int, ...]] | None:
    for pattern, types, components in SEMANTICS:
        if re.fullmatch(pattern, name):
            return types, components
    return None  # application-specific (_NAME) or unknown: not read by us or trimesh


def check_primitives(document: dict) -> None:
    accessors = document.get("accessors", [])
    quantized = gltf_extensions.uses(document, gltf_extensions.QUANTIZATION)
    for m, mesh in enumerate(document.get("meshes", [])):
        for p, prim in enumerate(mesh["primitives"]):
            where = f"$.meshes[{m}].primitives[{p}]"
            _check_attributes(accessors, prim, where, quantized)
            if "indices" in prim:
                _check_accessor(accessors[prim["indices"]], ("SCALAR",), INDEX_COMPONENTS, f"{where}.indices")


def _check_attributes(accessors: list[Any], prim: dict, where: str, quantized: bool = False) -> None:
    counts = {}
    for name, index in prim["attributes"].items():
        rule = _semantic_rule(name)
        widened = gltf_extensions.quantized_components(name) if quantized else None
        if rule is not None and widened is not None:  # KHR_mesh_quantization's table replaces the core one
            rule = (rule[0], widened)
        if rule is not None:
            _check_accessor(accessors[index], *rule, f"{where}.attributes.{name}")
        counts[name] = accessors[index]["count"]
    if "POSITION" in counts:
        for name, count in counts.items():
            if count != counts["POSITION"]:
                raise ValueError(f"{where}.attributes.{name} has {count} elements, POSITION {counts['POSITION']}: "
                                 "every attribute of a primitive needs one element per vertex")


def _check_accessor(acc: dict, types: tuple[str, ...], components: tuple[int, ...], where: str) -> None:
    if acc["type"] not in types:
        raise ValueError(f"{where} must be an accessor of type {' or '.join(types)}, got {acc['type']}")
    if acc["componentType"] not in components:
        names = " or ".join(COMPONENT_NAMES[c] for c in components)
        raise ValueError(f"{where} must have componentType {names}, got "
                         f"{COMPONENT_NAMES.get(acc['componentType'], acc['componentType'])}")


def root_nodes(document: dict) -> list[int]:
    """The nodes the file asks to draw: those of ``scene`` (or scene 0); without scenes, every node no other node
    lists as a child; without nodes, none (meshes are then placed once each)."""
    scenes = document.get("scenes", [])
    if scenes:
        return list(scenes[document.get("scene", 0)].get("nodes", []))
    children = {c for node in document.get("nodes", []) for c in node.get("children", [])}
    return [i for i in range(len(document.get("nodes", []))) if i not in children]


def mesh_placements(document: dict) -> dict[int, int]:
    """mesh index -> how many nodes of the drawn scene place it (instancing by nodes), linear in the nodes (the
    graph is a forest with unique roots: check_node_graph, check_scene_roots)."""
    nodes = document.get("nodes", [])
    if not nodes:
        return dict.fromkeys(range(len(document.get("meshes", []))), 1)
    placed: dict[int, int] = {}
    stack = list(root_nodes(document))
    while stack:
        node = nodes[stack.pop()]
        if "mesh" in node:
            placed[node["mesh"]] = placed.get(node["mesh"], 0) + 1
        stack.extend(node.get("children", []))
    return placed


def declared_vertices(document: dict) -> int:
    """Vertices and indices the drawn scene asks for, from the accessors' declared counts (nothing read): per
    placed primitive its POSITION count plus its indices count, times the nodes that place its mesh."""
    accessors, meshes = document.get("accessors", []), document.get("meshes", [])
    total = 0
    for mesh, times in mesh_placements(document).items():
        for prim in meshes[mesh]["primitives"]:
            used = [prim["attributes"].get("POSITION"), prim.get("indices")]
            total += times * sum(accessors[a]["count"] for a in used if a is not None)
    return total


def check_budget(document: dict, limit: int) -> None:
    """Refuse a document whose drawn scene declares more than ``limit`` vertices and indices, before any copy."""
    total = declared_vertices(document)
    if total > limit:
        raise BudgetError(f"its scene declares {total:,} vertices and indices (node instancing counted), over the "
                          f"limit of {limit:,}")


class BudgetError(ValueError):
    """A document over the vertex budget (not malformed: the user may raise the limit)."""
