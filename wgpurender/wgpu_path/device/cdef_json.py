"""cffi's parse of wgpu.h as JSON: data that cannot run code when it is loaded (issue 28.8).

The parse was cached as a pickle, loaded at every start: anyone who could write the cache folder ran code as the
user. The parser's state is a graph of ``cffi.model`` types (shared and, through structs, cyclic) over strings,
integers, tuples, dicts and sets. Here each model object becomes one row of a table, ``{"c": class, "a":
attributes}``, referenced as ``{"r": index}``; containers are tagged (``{"t": [...]}`` a tuple, ``{"l": ...}``
a list, ``{"s": ...}`` a set, ``{"d": [[key, value], ...]}`` a dict). Loading makes each object with
``object.__new__`` of a class from ``cffi.model`` only (checked against an allow-list, never imported by name
from the file) and fills its ``__dict__``: no constructor, no ``__setstate__``, no import runs.
"""

from __future__ import annotations

import json

import cffi.model as model

SCALARS = (str, int, float, bool, type(None))
ALLOWED = {name: cls for name, cls in vars(model).items()
           if isinstance(cls, type) and issubclass(cls, model.BaseTypeByIdentity) and cls.__module__ == model.__name__}


class Unsupported(ValueError):
    """A value of a type the format does not carry (the parse is then not cached)."""


def dumps(state: dict) -> bytes:
    table: list[dict] = []
    index: dict[int, int] = {}

    def enc(value):
        if isinstance(value, SCALARS):
            return value
        if isinstance(value, tuple):
            return {"t": [enc(v) for v in value]}
        if isinstance(value, list):
            return {"l": [enc(v) for v in value]}
        if isinstance(value, (set, frozenset)):
            return {"s": [enc(v) for v in value]}
        if isinstance(value, dict):
            return {"d": [[enc(k), enc(v)] for k, v in value.items()]}
        cls = type(value)
        if ALLOWED.get(cls.__name__) is not cls or hasattr(value, "__slots__") and not hasattr(value, "__dict__"):
            raise Unsupported(f"cannot store a {cls.__module__}.{cls.__name__}")
        if id(value) not in index:
            index[id(value)] = len(table)
            row: dict = {"c": cls.__name__}
            table.append(row)
            row["a"] = {name: enc(v) for name, v in vars(value).items()}
        return {"r": index[id(value)]}

    top = {name: enc(value) for name, value in state.items()}
    return json.dumps({"objects": table, "state": top}, separators=(",", ":")).encode()


def loads(data: bytes) -> dict:
    """The state :func:`dumps` stored; ValueError (or KeyError/TypeError) for anything else."""
    doc = json.loads(data)
    rows = doc["objects"]
    objects = [object.__new__(ALLOWED[row["c"]]) for row in rows]

    def dec(value):
        if isinstance(value, SCALARS):
            return value
        (tag, inner), = value.items()
        if tag == "r":
            return objects[inner]
        if tag == "d":
            return {dec(k): dec(v) for k, v in inner}
        items = [dec(v) for v in inner]
        return {"t": tuple, "l": list, "s": set}[tag](items)

    for obj, row in zip(objects, rows, strict=True):  # every object filled before any is hashed (sets, keys)
        obj.__dict__.update({str(name): dec(v) for name, v in row["a"].items()})
    return {str(name): dec(value) for name, value in doc["state"].items()}
