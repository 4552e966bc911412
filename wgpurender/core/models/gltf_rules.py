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
    check_accessors(document)
    check_node_graph(document)
    check_primitives(document)


def check_accessors(document: dict) -> None:
    for i, acc in enumerate(document.get("accessors", [])):
        if acc["type"] not in ACCESSOR_TYPES:
            raise ValueError(f"$.accessors[{i}].type must be one of {', '.join(ACCESSOR_TYPES)}, got {acc['type']!r}")
        if acc["componentType"] not in COMPONENT_NAMES:
            raise ValueError(f"$.accessors[{i}].componentType must be one of "
                             f"{', '.join(map(str, COMPONENT_NAMES))}, got {acc['componentType']}")


def check_node_graph(document: dict) -> None:
    """Nodes form disjoint trees: a node that is its own child (or descendant), or has two parents, is refused."""
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
    for start in range(len(nodes)):  # walk up: a cycle never reaches a root
        seen, node = {start}, start
        while node in parent:
            node = parent[node]
            if node in seen:
                raise ValueError(f"$.nodes[{start}]: the node hierarchy has a cycle through node {node}; "
                                 "nodes must form trees")
            seen.add(node)


def _semantic_rule(name: str) -> tuple[tuple[str, ...], tuple[int, ...]] | None:
    for pattern, types, components in SEMANTICS:
        if re.fullmatch(pattern, name):
            return types, components
    return None  # application-specific (_NAME) or unknown: not read by us or trimesh


def check_primitives(document: dict) -> None:
    accessors = document.get("accessors", [])
    for m, mesh in enumerate(document.get("meshes", [])):
        for p, prim in enumerate(mesh["primitives"]):
            where = f"$.meshes[{m}].primitives[{p}]"
            _check_attributes(accessors, prim, where)
            if "indices" in prim:
                _check_accessor(accessors[prim["indices"]], ("SCALAR",), INDEX_COMPONENTS, f"{where}.indices")


def _check_attributes(accessors: list[Any], prim: dict, where: str) -> None:
    counts = {}
    for name, index in prim["attributes"].items():
        rule = _semantic_rule(name)
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
