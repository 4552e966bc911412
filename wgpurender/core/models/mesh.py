"""Triangle meshes from OBJ (+MTL), glTF/GLB, PLY and STL files, loaded through trimesh into plain numpy arrays.

UV convention of :class:`Mesh` (the glTF / Vulkan / wgpu one): u = 0 at the left, **v = 0 at the TOP** of the
image, so ``uv * (width, height)`` addresses texels with row 0 being the first row of the PNG, which is also
texel row 0 of a wgpu texture written from that PNG. Per format:

- glTF/GLB stores exactly this convention. glTF files do not go through trimesh at all: the node graph and every
  attribute (POSITION, NORMAL, TEXCOORD_n, TANGENT, COLOR_0, indices) are read by the project's own accessor
  reader (gltf_geometry.py, gltf_io.read_accessor: byteStride, normalized integers, sparse accessors).
  trimesh still reads OBJ, PLY and STL.
- OBJ and PLY store v = 0 at the BOTTOM; trimesh passes them through, we convert with v -> 1 - v.
- STL has no UVs (uvs are zeros, ``has_uvs`` False).

Tangents (N, 4) follow tangents.py (glTF convention, w = handedness). They come from the file's TANGENT when it
has one, otherwise they are generated; vertices shared by mirrored and unmirrored triangles are split first.

Everything is vectorised: no Python loop runs per vertex or per triangle (a 1M-triangle binary PLY loads in
seconds).
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError
from wgpurender.core.files import read_jail
from wgpurender.core.files.input_files import check_file_size, input_file
from wgpurender.core.models import gltf_animation, gltf_geometry, gltf_io
from wgpurender.core.models.gltf_animation import Pose
from wgpurender.core.models.tangents import (
    area_weighted_normals,
    face_uv_frames,
    split_mirrored_vertices,
    vertex_tangents,
)
from wgpurender.core.view import transforms

SUPPORTED = {".obj": "obj", ".gltf": "gltf", ".glb": "glb", ".ply": "ply", ".stl": "stl", ".fbx": "fbx"}
CONVERT_HINT = (
    "convert it to glTF: in Blender, File > Import the file, then File > Export > glTF 2.0 (.glb); "
    "or with assimp: `assimp export {name} {stem}.glb`"
)
UNSUPPORTED = {".blend": "Blender", ".3ds": "3DS", ".max": "3ds Max", ".c4d": "Cinema 4D",
               ".usd": "USD", ".usdz": "USDZ", ".usda": "USD", ".usdc": "USD"}
log = logging.getLogger(__name__)


@dataclass(frozen=True)
class MeshPart:
    """A run of triangles (or points, or line segments: ``topology``) drawn with one material of the model file:
    ``material`` indexes the file's materials (glTF; None = the primitive names none), ``first_index`` /
    ``index_count`` count indices in :meth:`Mesh.index_bytes` (3 per triangle, 2 per segment, 1 per point)."""

    material: int | None
    first_index: int
    index_count: int
    topology: str = "triangle-list"


@dataclass
class Mesh:
    """An indexed triangle mesh in plain arrays, ready for vertex/index buffers.

    positions (N, 3) float32; normals (N, 3) float32 unit; uvs (N, 2) float32, v = 0 at the top of the image
    (zeros when the file has none: ``has_uvs`` False); tangents (N, 4) float32 or None; indices (F, 3) uint16 when
    the largest index is below 65535, else uint32 (``index_format`` names the wgpu format); colors (N, 4) float32
    linear RGBA (glTF COLOR_0) or None; parts: the triangles of each file material, contiguous, in index order;
    extra_uvs: coordinate slots 1.. ((N, 2) float32 each, or None where no part has that slot), same convention as
    uvs: a glTF material whose textures sample several sets or transforms (gltf_geometry.uv_slots).
    """

    positions: np.ndarray
    normals: np.ndarray
    uvs: np.ndarray
    indices: np.ndarray
    tangents: np.ndarray | None = None
    has_uvs: bool = True
    tangents_source: str | None = None  # "file", "generated" or None
    source: Path | None = None
    colors: np.ndarray | None = None
    parts: tuple[MeshPart, ...] = ()
    extra_indices: np.ndarray | None = None  # glTF points and line segments, flat, after the triangles' indices
    extra_uvs: tuple[np.ndarray | None, ...] = ()  # coordinate slots 1.. (glTF materials sampling several)

    @property
    def vertex_count(self) -> int:
        return len(self.positions)

    @property
    def triangle_count(self) -> int:
        return len(self.indices)

    @property
    def index_format(self) -> str:
        """The wgpu IndexFormat matching ``indices.dtype``."""
        return "uint16" if self.indices.dtype == np.uint16 else "uint32"

    def index_bytes(self) -> bytes:
        """Indices as bytes, zero-padded to a multiple of 4 (queue.write_buffer needs it; draw only F*3 of them)."""
        data = self.all_indices().tobytes()
        return data + b"\0" * (-len(data) % 4)

    def all_indices(self) -> np.ndarray:
        """Every index, flat: the triangles', then the glTF points' and line segments' (``parts`` address both)."""
        if self.extra_indices is None:
            return np.ascontiguousarray(self.indices).reshape(-1)
        return np.concatenate([self.indices.reshape(-1), self.extra_indices.astype(self.indices.dtype)])

    def attribute(self, name: str) -> np.ndarray:
        """A vertex attribute as the scene shaders read it: position, normal, uv, tangent, color (white without
        COLOR_0) or uv<k> (coordinate slot k >= 1)."""
        if name.startswith("uv") and name[2:].isdigit():
            return self.extra_uvs[int(name[2:]) - 1]
        if name == "color" and self.colors is None:
            return np.ones((self.vertex_count, 4), np.float32)
        return getattr(self, _ATTRIBUTE_FIELDS[name])  # a table, not a dict made per call (10k meshes x 3)

    def vertex_data(self) -> np.ndarray:
        """Interleaved (N, 12) float32: position xyz @0, normal xyz @12, uv @24, tangent xyzw @32; stride 48 bytes."""
        tangents = self.tangents if self.tangents is not None else np.zeros((self.vertex_count, 4), np.float32)
        return np.ascontiguousarray(np.concatenate([self.positions, self.normals, self.uvs, tangents], axis=1),
                                    dtype=np.float32)


_ATTRIBUTE_FIELDS = {"position": "positions", "normal": "normals", "uv": "uvs", "tangent": "tangents",
                     "color": "colors"}


def index_range(mesh: Mesh, draw) -> tuple[int, int]:
    """(first index, index count) a plan Draw covers: the mesh part of its file material (``draw.part``, -1 for
    primitives without one), or the whole mesh when ``part`` is None."""
    if draw.part is None:
        return 0, int(mesh.indices.size)
    wanted = None if draw.part < 0 else draw.part
    topology = getattr(draw, "topology", "triangle-list")
    for part in mesh.parts:
        if part.material == wanted and part.topology == topology:
            return part.first_index, part.index_count
    raise UserError(f"{draw.label}: the model file has no {topology} with material {draw.part}")


def index_dtype(max_index: int) -> type:
    """uint16 when every index fits below 65535 (0xFFFF is kept free: it is the strip-restart value), else uint32."""
    return np.uint16 if max_index < 65535 else np.uint32


def build_mesh(
    positions: np.ndarray,
    indices: np.ndarray,
    normals: np.ndarray | None = None,
    uvs: np.ndarray | None = None,
    tangents: np.ndarray | None = None,
    *,
    generate_tangents: bool = True,
    source: str | os.PathLike | None = None,
    colors: np.ndarray | None = None,
    parts: tuple[MeshPart, ...] = (),
    extra_uvs: tuple[np.ndarray | None, ...] = (),
) -> Mesh:
    """Validate arrays and complete them into a :class:`Mesh` (the vectorised pipeline every loader ends in).

    uvs must already be in the Mesh convention (v = 0 at the top). Missing normals become area-weighted vertex
    normals (zero or non-finite file normals are replaced the same way). Missing tangents are generated when
    ``generate_tangents``; vertices shared by triangles of opposite UV handedness are split for that.
    """
    what = f"mesh {source}" if source is not None else "mesh"
    positions = np.asarray(positions, np.float64).reshape(-1, 3)
    indices = np.asarray(indices).reshape(-1, 3).astype(np.int64)
    if len(positions) == 0 or len(indices) == 0:
        raise UserError(f"{what} is empty: {len(positions)} vertices, {len(indices)} triangles "
                        "(faces with fewer than 3 vertices, lines and points are not triangles)")
    _check_gpu_range(what, "vertex position", positions, MAX_COORDINATE)
    if indices.min() < 0 or indices.max() >= len(positions):
        raise UserError(f"{what} has triangle indices outside 0..{len(positions) - 1}; the file is malformed")
    for label, array, width in (("normals", normals, 3), ("uvs", uvs, 2), ("tangents", tangents, 4),
                                ("colors", colors, 4), *(("uvs", a, 2) for a in extra_uvs)):
        if array is not None and np.shape(array) != (len(positions), width):
            raise UserError(f"{what}: {label} have shape {np.shape(array)}, expected ({len(positions)}, {width})")
    has_uvs = uvs is not None
    uvs = np.zeros((len(positions), 2)) if uvs is None else np.asarray(uvs, np.float64).reshape(-1, 2)
    _check_gpu_range(what, "texture coordinate", uvs, FLOAT32_MAX)
    extra_uvs = tuple(None if a is None else np.asarray(a, np.float64) for a in extra_uvs)
    for array in extra_uvs:
        if array is not None:
            _check_gpu_range(what, "texture coordinate", array, FLOAT32_MAX)
    normals = _complete_normals(positions, indices, normals)

    tangents_source = None
    if tangents is not None:
        tangents = np.asarray(tangents, np.float64).reshape(-1, 4)
        tangents = _checked_tangents(tangents, positions, normals, uvs, indices)
        tangents_source = "file"
    elif generate_tangents:
        _, _, _, handed = face_uv_frames(positions, uvs, indices)
        indices, src = split_mirrored_vertices(indices, handed, len(positions))
        if len(src) != len(positions):
            positions, normals, uvs = positions[src], normals[src], uvs[src]
            colors = None if colors is None else np.asarray(colors)[src]
            extra_uvs = tuple(None if a is None else a[src] for a in extra_uvs)
        tangents = vertex_tangents(positions, normals, uvs, indices)
        tangents_source = "generated"

    return Mesh(
        positions=positions.astype(np.float32),
        normals=normals.astype(np.float32),
        uvs=uvs.astype(np.float32),
        indices=np.ascontiguousarray(indices.astype(index_dtype(int(indices.max())))),
        tangents=None if tangents is None else tangents.astype(np.float32),
        has_uvs=has_uvs,
        tangents_source=tangents_source,
        source=None if source is None else Path(source),
        colors=None if colors is None else _checked_colors(what, colors),
        parts=tuple(parts),
        extra_uvs=tuple(None if a is None else a.astype(np.float32) for a in extra_uvs),
    )


FLOAT32_MAX = float(np.finfo(np.float32).max)
MAX_COORDINATE = 1e18  # squared distances stay finite in the GPU's float32 (sqrt(3.4e38) = 1.8e19)


def _check_gpu_range(what: str, label: str, values: np.ndarray, limit: float) -> None:
    """Values must be finite in float32, the type the GPU gets (a float64 check misses 1e39), and within limit."""
    with np.errstate(all="ignore"):
        wide = np.asarray(values, np.float64)
        bad = ~np.isfinite(wide.astype(np.float32)) | (np.abs(wide) > limit)
    if np.any(bad):
        rows = int(np.count_nonzero(np.any(bad.reshape(len(wide), -1), axis=1)))
        worst = wide[bad][0]
        raise UserError(f"{what} has {rows} {label}(s) that are NaN or infinite, or beyond {limit:.3g}, in float32 "
                        f"(the GPU's type), e.g. {worst:g}; fix the model or scale it down before export")


def _checked_colors(what: str, colors: np.ndarray) -> np.ndarray:
    """Vertex colours as float32; NaN or infinite ones are refused (the GPU would blend them into every pixel)."""
    colors = np.asarray(colors, np.float64)
    if not np.all(np.isfinite(colors)):
        raise UserError(f"{what} has vertex colours (COLOR_0) that are NaN or infinite; fix the model")
    return colors.astype(np.float32)


def _complete_normals(positions: np.ndarray, indices: np.ndarray, normals: np.ndarray | None) -> np.ndarray:
    computed = None
    if normals is not None:
        normals = np.asarray(normals, np.float64).reshape(-1, 3)
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        good = np.isfinite(length[:, 0]) & (length[:, 0] > 1e-12)
        if np.all(good):
            return normals / length
        computed = area_weighted_normals(positions, indices).astype(np.float64)
        return np.where(good[:, None], normals / np.where(good[:, None], length, 1.0), computed)
    return area_weighted_normals(positions, indices).astype(np.float64)


def _checked_tangents(
    tangents: np.ndarray, positions: np.ndarray, normals: np.ndarray, uvs: np.ndarray, indices: np.ndarray
) -> np.ndarray:
    """File tangents, normalised, w snapped to +-1; rows that are zero or non-finite are replaced by generated ones."""
    xyz = tangents[:, :3]
    length = np.linalg.norm(xyz, axis=1, keepdims=True)
    good = np.isfinite(length[:, 0]) & (length[:, 0] > 1e-12) & np.isfinite(tangents[:, 3])
    w = np.where(tangents[:, 3:] < 0, -1.0, 1.0)
    out = np.concatenate([xyz / np.where(good[:, None], length, 1.0), w], axis=1)
    if not np.all(good):
        out[~good] = vertex_tangents(positions, normals, uvs, indices)[~good]
    return out


@dataclass
class _Part:
    """One placed piece of geometry, already in world space."""

    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None
    uvs: np.ndarray | None
    tangents: np.ndarray | None
    colors: np.ndarray | None = None
    material: int | None = None
    topology: str = "triangle-list"
    extra_uvs: tuple[np.ndarray | None, ...] = ()  # a glTF material's coordinate slots 1.. (gltf_geometry.uv_slots)


def load_mesh(path: str | os.PathLike, *, generate_tangents: bool = True, pose: Pose | None = None) -> Mesh:
    """Load a model file into one :class:`Mesh` (all its meshes and nodes merged, node transforms applied).

    The geometry only: a model file's materials are the scene's (core/scene/file_materials.py reads them once,
    when the scene loads); ``Mesh.parts`` says which triangles each file material covers.
    ``pose``: a glTF file's animation sampled at a time (core/models/gltf_animation.py); None: its nodes as
    written. Skins are posed either way (core/models/gltf_skin.py).
    Raises UserError for missing, unsupported, malformed or empty files and for non-finite positions.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in UNSUPPORTED:
        kind = UNSUPPORTED[suffix]
        raise UserError(f"cannot load {path}: {kind} files are not supported (wgpurender cannot read {kind}); "
                        + CONVERT_HINT.format(name=path.name, stem=path.stem))
    if suffix not in SUPPORTED:
        raise UserError(f"cannot load {path}: unknown model format '{suffix or path.name}' "
                        f"(supported: {', '.join(SUPPORTED)})")
    check_file_size(input_file(path, "model file"), "model file")
    file_type = SUPPORTED[suffix]
    if pose is not None and file_type not in ("gltf", "glb"):
        raise UserError(f"cannot pose {path}: only glTF files have animations (remove 'time' and 'animation')")
    if file_type in ("gltf", "glb"):
        parts = _gltf_parts(path, pose)
    elif file_type == "fbx":
        parts = _fbx_parts(path)
    else:
        parts = _simple_obj_parts(path) if file_type == "obj" else None
        if parts is None:
            if file_type == "obj":
                check_obj_records(path)
            parts = _trimesh_parts(path, file_type)
    return mesh_of_parts(path, parts, generate_tangents)


def mesh_of_parts(path: Path, parts: list[_Part], generate_tangents: bool) -> Mesh:
    """The one :class:`Mesh` of a file's placed parts (the end of every loader: checked, completed, tangents)."""
    if not parts:
        raise UserError(f"mesh {path} is empty: no triangles found (faces with fewer than 3 vertices, lines and "
                        "points are not triangles)")
    others = [p for p in parts if p.topology != "triangle-list"]
    parts = [p for p in parts if p.topology == "triangle-list"]
    if not parts:
        raise UserError(f"mesh {path} has only points and lines, no triangles; wgpurender draws points and lines "
                        "beside a model's triangles: add a surface or export the triangles too")
    positions, faces, normals, uvs, tangents, colors, mesh_parts, extra_uvs = _concatenate(parts)
    mesh = build_mesh(positions, faces, normals, uvs, tangents, generate_tangents=generate_tangents,
                      source=path, colors=colors, parts=mesh_parts, extra_uvs=extra_uvs)
    return _with_points_and_lines(mesh, others) if others else mesh


def _with_points_and_lines(mesh: Mesh, others: list[_Part]) -> Mesh:
    """Append glTF points and line segments: their vertices after the triangles' (normal +z, white colour,
    zero UVs where the file has none: they are drawn unlit), their indices after the triangles' indices, one
    part per (material, topology) in material order."""
    others = sorted(others, key=lambda p: (p.topology, -1 if p.material is None else p.material))
    count = mesh.vertex_count
    flat, parts, first = [], list(mesh.parts), int(mesh.indices.size)
    colors = mesh.colors
    if colors is None and any(p.colors is not None for p in others):
        colors = np.ones((count, 4), np.float32)  # the triangles' white, beside the points' or lines' COLOR_0
    arrays = {"positions": [mesh.positions], "normals": [mesh.normals], "uvs": [mesh.uvs],
              "tangents": [mesh.tangents], "colors": [colors]}
    arrays.update({f"uv{k}": [a] for k, a in enumerate(mesh.extra_uvs, start=1)})
    for p in others:
        n = len(p.positions)
        arrays["positions"].append(p.positions)
        arrays["normals"].append(np.tile([0.0, 0.0, 1.0], (n, 1)))
        arrays["uvs"].append(p.uvs if p.uvs is not None else np.zeros((n, 2)))
        arrays["tangents"].append(np.tile([1.0, 0.0, 0.0, 1.0], (n, 1)))
        arrays["colors"].append(p.colors if p.colors is not None else np.ones((n, 4)))
        for k in range(1, len(mesh.extra_uvs) + 1):
            arrays[f"uv{k}"].append(np.zeros((n, 2)))  # drawn unlit and untextured beside the triangles' slots
        flat.append(np.asarray(p.faces, np.int64).reshape(-1) + count)
        size = int(flat[-1].size)
        last = parts[-1] if parts else None
        if last is not None and (last.material, last.topology) == (p.material, p.topology):
            parts[-1] = MeshPart(p.material, last.first_index, last.index_count + size, p.topology)
        else:
            parts.append(MeshPart(p.material, first, size, p.topology))
        first += size
        count += n
    _check_gpu_range(f"mesh {mesh.source}", "vertex position", np.concatenate(arrays["positions"][1:]),
                     MAX_COORDINATE)
    dtype = index_dtype(count - 1)
    joined = {k: np.concatenate(v).astype(np.float32) for k, v in arrays.items() if v[0] is not None}
    return Mesh(joined["positions"], joined["normals"], joined["uvs"], mesh.indices.astype(dtype),
                joined.get("tangents"), mesh.has_uvs, mesh.tangents_source, mesh.source,
                joined.get("colors"), tuple(parts), np.concatenate(flat).astype(dtype),
                tuple(joined.get(f"uv{k}") for k in range(1, len(mesh.extra_uvs) + 1)))


OBJ_RECORDS = {"v": (3, "x y z"), "vt": (2, "u v"), "vn": (3, "x y z")}  # least numbers each record needs


def check_obj_records(path: Path) -> None:
    """Vertex records of an OBJ file carry enough numbers: trimesh fails with an IndexError (or reads a wrong
    array) on ``vt 0.5``. Raises ``FILE:LINE: ...`` for the first bad record."""
    with read_jail.open_checked(path) as f:
        for number, raw in enumerate(f, start=1):
            tokens = raw.split(b"#", 1)[0].split()
            if not tokens or tokens[0] not in (b"v", b"vt", b"vn"):
                continue
            kind = tokens[0].decode()
            need, form = OBJ_RECORDS[kind]
            try:
                values = [float(t) for t in tokens[1:]]
            except ValueError:
                values = None
            if values is None or len(values) < need:
                written = raw.decode("utf-8", "replace").strip()
                raise UserError(f"{path}:{number}: OBJ record {written[:60]!r} needs {need} numbers "
                                f"('{kind} {form}'); fix the line or re-export the model")


def _load_scene(path: Path, file_type: str, **kwargs):
    import trimesh

    try:
        # process=False: no vertex merging, so per-corner UVs and normals survive; maintain_order must stay False
        # for OBJ (trimesh 5.2 then keys vertices by position index only and loses per-corner UVs).
        with read_jail.open_checked(path) as f:  # the file the scene's check let through, not one swapped in
            return trimesh.load_scene(file_obj=f, file_type=file_type, process=False,
                                      resolver=_jailed_resolver(path), **kwargs)
    except UserError:
        raise
    except Exception as err:  # trimesh raises many types for bad files; the user needs only the file and reason
        detail = str(err).strip().splitlines()[0] if str(err).strip() else ""
        reason = f"{type(err).__name__}: {detail}" if detail else type(err).__name__
        raise UserError(f"cannot read {path} as {file_type.upper()}: the file is malformed ({reason})") from None


def _jailed_resolver(path: Path):
    """trimesh's resolver for the files a model names (an MTL, a PLY's TextureFile), through read_jail: OBJ and PLY
    are loaded with skip_materials, so this is the guard should trimesh ever ask."""
    from trimesh.resolvers import FilePathResolver

    class JailedResolver(FilePathResolver):
        def get(self, name: str) -> bytes:
            return read_jail.read_checked(read_jail.model_file(path, name, "a file trimesh asked for", encoded=False))

    return JailedResolver(str(path))


def _placed(scene):
    """(transform (4, 4), geometry name, Trimesh) for every node that places a triangle mesh, in graph order."""
    import trimesh

    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        geom = scene.geometry.get(name)
        if isinstance(geom, trimesh.Trimesh) and len(geom.faces) > 0:
            yield np.asarray(transform, np.float64), name, geom


def _file_normals(geom) -> np.ndarray | None:
    """Vertex normals the file supplied, or None. trimesh computes normals lazily on access; only normals given
    at construction sit in its cache beforehand, so look there instead of touching ``geom.vertex_normals``."""
    return np.asarray(geom.vertex_normals, np.float64) if "vertex_normals" in geom._cache else None


def _trimesh_parts(path: Path, file_type: str) -> list[_Part]:
    kwargs = {"skip_materials": True} if file_type in ("obj", "ply") else {}
    scene = _load_scene(path, file_type, **kwargs)
    parts = []
    for transform, name, geom in _placed(scene):
        uv = getattr(geom.visual, "uv", None)
        if uv is not None and len(uv) == len(geom.vertices):
            uv = np.asarray(uv, np.float64).copy()
            uv[:, 1] = 1.0 - uv[:, 1]  # OBJ / PLY: v = 0 at the bottom -> Mesh convention, v = 0 at the top
        else:
            uv = None
        parts.append(_place(transform, geom.vertices, geom.faces, _file_normals(geom), uv, None, str(path), name))
    return parts


def _simple_obj_parts(path: Path) -> list[_Part] | None:
    """The one part of a simple OBJ file (core/models/obj_simple.py: the arrays trimesh's path gives, without its
    scene machinery), or None when the file is not that simple."""
    from wgpurender.core.models import obj_simple

    return _simple_part(obj_simple.read(path))


def simple_obj_parts(data: bytes) -> list[_Part] | None:
    """:func:`_simple_obj_parts` of a file's bytes (the parse cache, core/models/obj_cached.py, read them)."""
    from wgpurender.core.models import obj_simple

    return _simple_part(obj_simple.parse(data))


def _simple_part(read) -> list[_Part] | None:
    if read is None:
        return None
    positions, faces, normals, uvs = read
    uvs = uvs.copy()
    uvs[:, 1] = 1.0 - uvs[:, 1]  # OBJ: v = 0 at the bottom -> Mesh convention, v = 0 at the top
    return [_Part(positions, faces, normals, uvs, None)]


def posed_mesh(path: str | os.PathLike, doc: gltf_io.GltfDocument, pose: Pose, *,
               generate_tangents: bool = True) -> Mesh:
    """:func:`load_mesh` of a glTF file already read and checked (``doc``, its parsed document) at ``pose``: the
    window's playback re-poses a drawn model each frame without reading and parsing its file again."""
    return mesh_of_parts(Path(path), _gltf_parts(Path(path), pose, doc), generate_tangents)


def _gltf_parts(path: Path, pose: Pose | None = None, doc: gltf_io.GltfDocument | None = None) -> list[_Part]:
    """Every triangle primitive the file's scene places, read by gltf_geometry (no trimesh), in world space, the
    nodes posed at ``pose`` (gltf_animation.posed) and skins applied; ``doc``: the file's document, read already."""
    doc = gltf_animation.posed(doc if doc is not None else gltf_io.read_document(path), pose)
    parts = []
    for world, node, geometry in gltf_geometry.mesh_primitives(doc):
        g = geometry
        part = _place(world, g.positions, g.faces, g.normals, g.uvs, g.tangents, str(path), node)
        part.colors, part.material, part.topology, part.extra_uvs = g.colors, g.material, g.topology, g.extra_uvs
        parts.append(part)
    return parts


def _fbx_parts(path: Path) -> list[_Part]:
    """Every triangle mesh an FBX file's node tree places, in world space (core/models/fbx.py: assimp, axes, units),
    with its material index: the scene draws each of the file's materials over its own triangles
    (core/scene/fbx_materials.py)."""
    from wgpurender.core.models import fbx

    placed, _ = fbx.load_fbx(path)
    parts = []
    for world, positions, faces, normals, uvs, name, material in placed:
        parts.append(_place(world, positions, faces, normals, uvs, None, str(path), name))
        parts[-1].material = material
    return parts


def _place(transform, vertices, faces, normals, uvs, tangents, where: str = "model", node: str = "?") -> _Part:
    """Apply a node transform: positions by the matrix, normals by the inverse transpose of its 3x3 (renormalised
    later), tangent xyz by the 3x3; when the transform mirrors (det < 0) w is negated and the winding reversed."""
    positions = np.asarray(vertices, np.float64)
    faces = np.asarray(faces, np.int64)
    if not np.allclose(transform, np.eye(4)):
        m = transform[:3, :3]
        with np.errstate(all="ignore"):
            det = np.linalg.det(m)
        if not np.all(np.isfinite(transform.astype(np.float32))) or not np.isfinite(det):
            raise UserError(f"{where}: the node placing mesh '{node}' has a transform beyond float32's range "
                            "(e.g. a 1e308 matrix); fix the node's matrix, translation, rotation or scale")
        if transforms.flat(m):
            raise UserError(f"{where}: the node placing mesh '{node}' has a singular transform (determinant "
                            f"{det:.3g}: a scale of 0 on some axis, or a flat matrix), which flattens the mesh and "
                            "leaves its normals undefined; give every axis a non-zero scale")
        positions = positions @ m.T + transform[:3, 3]
        if normals is not None:
            normals = normals @ np.linalg.inv(m)  # rows: (M^-T n)^T, the inverse transpose keeps them outward
        if tangents is not None:
            xyz = np.asarray(tangents[:, :3], np.float64) @ m.T
            tangents = np.concatenate([xyz, np.asarray(tangents[:, 3:], np.float64) * np.sign(det)], axis=1)
        if det < 0:
            faces = faces[:, ::-1]
    return _Part(positions, faces, normals, uvs, tangents)


def _concatenate(parts: list[_Part]):
    """One set of arrays from several parts, grouped by material (stable: file order within a material), and the
    index range of each material; a part without normals/uvs/colours gets computed, zero or white ones."""
    parts = sorted(parts, key=lambda p: -1 if p.material is None else p.material)
    offsets = np.cumsum([0] + [len(p.positions) for p in parts[:-1]])
    positions = np.concatenate([p.positions for p in parts])
    faces = np.concatenate([p.faces + o for p, o in zip(parts, offsets, strict=True)])
    normals = None
    if any(p.normals is not None for p in parts):
        normals = np.concatenate([p.normals if p.normals is not None else area_weighted_normals(p.positions, p.faces)
                                  for p in parts])
    uvs = None
    if any(p.uvs is not None for p in parts):
        uvs = np.concatenate([p.uvs if p.uvs is not None else np.zeros((len(p.positions), 2)) for p in parts])
    extra_uvs = tuple(_slot(parts, k) for k in range(max(len(p.extra_uvs) for p in parts)))
    colors = None
    if any(p.colors is not None for p in parts):
        colors = np.concatenate([p.colors if p.colors is not None else np.ones((len(p.positions), 4)) for p in parts])
    # tangents from the file only when every part has them; otherwise all are generated consistently
    tangents = np.concatenate([p.tangents for p in parts]) if all(p.tangents is not None for p in parts) else None
    mesh_parts, first = [], 0
    for p in parts:
        count = 3 * len(p.faces)
        if mesh_parts and mesh_parts[-1].material == p.material:
            mesh_parts[-1] = MeshPart(p.material, mesh_parts[-1].first_index, mesh_parts[-1].index_count + count)
        else:
            mesh_parts.append(MeshPart(p.material, first, count))
        first += count
    return positions, faces, normals, uvs, tangents, colors, tuple(mesh_parts), extra_uvs


def _slot(parts: list[_Part], k: int) -> np.ndarray | None:
    """Coordinate slot k + 1 of every part: zeros for the parts whose materials have fewer slots (they never read
    it); None when no part has it."""
    arrays = [p.extra_uvs[k] if k < len(p.extra_uvs) else None for p in parts]
    if all(a is None for a in arrays):
        return None
    return np.concatenate([a if a is not None else np.zeros((len(p.positions), 2)) for a, p in zip(arrays, parts,
                                                                                                     strict=True)])
