"""The shapes the glTF 2.0 schema requires of the JSON we (and trimesh) read, checked before anything reads it.

Not the whole schema (https://github.com/KhronosGroup/glTF/tree/main/specification/2.0/schema): only the
properties this project or trimesh touch, with their JSON types, required properties, and indices into other
arrays. A file that breaks one gets one message naming its JSON path, e.g.
``$.buffers[0].uri must be a string, got 5``, instead of a TypeError deep inside a loader.

A schema here is a small value: a Python type (``str``, ``bool``), ``INT`` (a non-negative integer), ``NUM``
(a finite number), ``NONNEG`` (a finite number >= 0), ``Ref("meshes")`` (an index into that top-level array),
``Arr(item, n)`` (an array, of length n when given), ``Map(value)`` (an object with any keys), or
``Obj(props, required)``. The ``extensions`` of every object is an object of objects (glTFProperty.schema.json).

Why not the official JSON schema with the ``jsonschema`` package (issue 28, item 11): it would be a new
dependency plus ~40 vendored schema files, its messages are multi-line and name schema paths rather than the
file's, and it cannot check what most often breaks a loader here: an index past the end of another array
(``Ref``), or the cross-field rules of gltf_rules.py (byteStride against the element size, sparse counts, a
scene's roots). The properties we and trimesh read are checked here with one-line messages naming the JSON path.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Ref:
    target: str  # top-level array the index points into


@dataclass(frozen=True)
class Arr:
    item: Any
    length: int | None = None
    nonempty: bool = False


@dataclass(frozen=True)
class Map:
    value: Any


@dataclass(frozen=True)
class Obj:
    props: dict
    required: tuple[str, ...] = ()


INT, NUM, NONNEG = "non-negative integer", "number", "non-negative number"
TEXTURE_INFO = Obj({"index": Ref("textures"), "texCoord": INT}, ("index",))
SPARSE = Obj({"count": INT, "indices": Obj({"bufferView": Ref("bufferViews"), "byteOffset": INT,
                                            "componentType": INT}, ("bufferView", "componentType")),
              "values": Obj({"bufferView": Ref("bufferViews"), "byteOffset": INT}, ("bufferView",))},
             ("count", "indices", "values"))
MATERIAL_EXTENSIONS = Obj({"KHR_materials_emissive_strength": Obj({"emissiveStrength": NONNEG}),
                           "KHR_materials_unlit": Obj({}),
                           "KHR_materials_clearcoat": Obj({
                               "clearcoatFactor": NONNEG, "clearcoatTexture": TEXTURE_INFO,
                               "clearcoatRoughnessFactor": NONNEG, "clearcoatRoughnessTexture": TEXTURE_INFO,
                               "clearcoatNormalTexture": Obj({"index": Ref("textures"), "texCoord": INT, "scale": NUM},
                                                             ("index",))})})
PRIMITIVE = Obj({"attributes": Map(Ref("accessors")), "indices": Ref("accessors"), "material": Ref("materials"),
                 "mode": INT, "targets": Arr(Map(Ref("accessors")))}, ("attributes",))
# a channel's sampler indexes its own animation's samplers: checked where it is read (gltf_animation.channels)
ANIMATION_CHANNEL = Obj({"sampler": INT, "target": Obj({"node": Ref("nodes"), "path": str}, ("path",))},
                        ("sampler", "target"))
ANIMATION_SAMPLER = Obj({"input": Ref("accessors"), "output": Ref("accessors"), "interpolation": str},
                        ("input", "output"))
DOCUMENT = Obj({
    "asset": Obj({"version": str, "generator": str}),
    "extensionsUsed": Arr(str), "extensionsRequired": Arr(str),
    "scene": Ref("scenes"),
    "scenes": Arr(Obj({"nodes": Arr(Ref("nodes")), "name": str})),
    "nodes": Arr(Obj({"mesh": Ref("meshes"), "children": Arr(Ref("nodes")), "matrix": Arr(NUM, 16),
                      "translation": Arr(NUM, 3), "rotation": Arr(NUM, 4), "scale": Arr(NUM, 3), "name": str,
                      "camera": Ref("cameras"), "skin": Ref("skins"), "weights": Arr(NUM)})),
    "meshes": Arr(Obj({"primitives": Arr(PRIMITIVE, nonempty=True), "name": str}, ("primitives",))),
    "accessors": Arr(Obj({"bufferView": Ref("bufferViews"), "byteOffset": INT, "componentType": INT,
                          "normalized": bool, "count": INT, "type": str, "min": Arr(NUM), "max": Arr(NUM),
                          "name": str, "sparse": SPARSE}, ("componentType", "count", "type"))),
    "bufferViews": Arr(Obj({"buffer": Ref("buffers"), "byteOffset": INT, "byteLength": INT, "byteStride": INT,
                            "target": INT, "name": str}, ("buffer", "byteLength"))),
    "buffers": Arr(Obj({"uri": str, "byteLength": INT, "name": str}, ("byteLength",))),
    "materials": Arr(Obj({
        "name": str, "normalTexture": TEXTURE_INFO, "occlusionTexture": TEXTURE_INFO,
        "emissiveTexture": TEXTURE_INFO, "emissiveFactor": Arr(NUM, 3), "alphaMode": str, "alphaCutoff": NONNEG,
        "doubleSided": bool, "extensions": MATERIAL_EXTENSIONS,
        "pbrMetallicRoughness": Obj({"baseColorFactor": Arr(NUM, 4), "baseColorTexture": TEXTURE_INFO,
                                     "metallicFactor": NUM, "roughnessFactor": NUM,
                                     "metallicRoughnessTexture": TEXTURE_INFO}),
    })),
    "textures": Arr(Obj({"source": Ref("images"), "sampler": Ref("samplers"), "name": str})),
    "images": Arr(Obj({"uri": str, "bufferView": Ref("bufferViews"), "mimeType": str, "name": str})),
    "samplers": Arr(Obj({"magFilter": INT, "minFilter": INT, "wrapS": INT, "wrapT": INT, "name": str})),
    "cameras": Arr(Obj({"type": str})),
    "skins": Arr(Obj({"joints": Arr(Ref("nodes"), nonempty=True), "inverseBindMatrices": Ref("accessors"),
                      "skeleton": Ref("nodes"), "name": str}, ("joints",))),
    "animations": Arr(Obj({"name": str, "channels": Arr(ANIMATION_CHANNEL, nonempty=True),
                           "samplers": Arr(ANIMATION_SAMPLER, nonempty=True)}, ("channels", "samplers"))),
})

EXTENSIONS = Map(Obj({}))

_TYPE_NAMES = {dict: "an object", list: "an array", str: "a string", bool: "a boolean", int: "an integer",
               float: "a number", type(None): "null"}


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else f"{_TYPE_NAMES.get(type(value), type(value).__name__)}"


def check(document: Any) -> None:
    """Raise ValueError("$.path: what is wrong") at the first place ``document`` breaks the schema."""
    _check(document, DOCUMENT, "$", document)


def _check(value: Any, schema: Any, where: str, root: dict) -> None:
    if isinstance(schema, Obj):
        if not isinstance(value, dict):
            raise ValueError(f"{where} must be an object, got {_show(value)}")
        for name in schema.required:
            if name not in value:
                raise ValueError(f"{where} needs the property '{name}'")
        for name, sub in schema.props.items():
            if name in value:
                _check(value[name], sub, f"{where}.{name}", root)
        if "extensions" in value:  # every glTF property: an object of extension objects (glTFProperty.schema.json)
            _check(value["extensions"], EXTENSIONS, f"{where}.extensions", root)
    elif isinstance(schema, Arr):
        if not isinstance(value, list):
            raise ValueError(f"{where} must be an array, got {_show(value)}")
        if schema.length is not None and len(value) != schema.length:
            raise ValueError(f"{where} must have {schema.length} elements, got {len(value)}")
        if schema.nonempty and not value:
            raise ValueError(f"{where} must not be empty")
        for i, item in enumerate(value):
            _check(item, schema.item, f"{where}[{i}]", root)
    elif isinstance(schema, Map):
        if not isinstance(value, dict):
            raise ValueError(f"{where} must be an object, got {_show(value)}")
        for name, item in value.items():
            _check(item, schema.value, f"{where}.{name}", root)
    elif isinstance(schema, Ref):
        _check(value, INT, where, root)
        target = root.get(schema.target, [])
        if not isinstance(target, list):
            return  # the target's own check says what is wrong with it
        size = len(target)
        if value >= size:
            raise ValueError(f"{where} = {value} points past the end of $.{schema.target} ({size} entries)")
    elif schema == INT:
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ValueError(f"{where} must be a non-negative integer, got {_show(value)}")
    elif schema in (NUM, NONNEG):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{where} must be a finite number, got {_show(value)}")
        if schema == NONNEG and value < 0:
            raise ValueError(f"{where} must not be negative, got {_show(value)}")
    elif not isinstance(value, schema) or (schema is not bool and isinstance(value, bool)):
        raise ValueError(f"{where} must be {_TYPE_NAMES[schema]}, got {_show(value)}")
