"""The meshes a plan draws, loaded once each and checked against what each draw's shader variant reads.

Both paths upload the same triangles, so what is loaded (tangents only where a variant drawing the model has a
normal map; geometry only: the materials are the scene's, read when it loads) and what a draw may ask of its mesh
(uvs for textures, tangents for a normal map) is decided here, once; each path turns a :class:`Mesh` into its own
buffers (wgpu_path/scene/resources.py, raw_path/scene/resources.py).
"""

from __future__ import annotations

import functools

from wgpurender.core.errors import UserError
from wgpurender.core.models.mesh import Mesh, index_range
from wgpurender.core.models.obj_cached import load_mesh
from wgpurender.core.plan.mesh_loading import MIN_FILES, obj_keys
from wgpurender.core.plan.model import Draw, RenderPlan


class PlanMeshes:
    """``mesh_for(draw)`` and ``index_range(draw)``, for one plan."""

    def __init__(self, plan: RenderPlan) -> None:
        self.plan = plan
        self._meshes: dict[tuple, Mesh] = {}
        self._needs_tangents = {d.mesh_key for d in plan.scene_pass.draws
                                if "tangent" in plan.variant(d.variant_key).vertex_attributes}
        # cache entries are written by workers, or here for a small scene: writing thousands from this process
        # cost more than the parses they save (core/models/obj_cached._load)
        models = plan.scene.models if plan.scene is not None else None  # each knows its file's format
        self._obj_keys = obj_keys(plan.scene_pass.draws, models)  # the OBJ files, worked out once per plan
        self._store = len({path for path, _ in self._obj_keys}) < MIN_FILES
        self._reading = None  # the workers' reads, when started ahead (start_reading)

    def mesh(self, key: tuple) -> Mesh:
        """The loaded mesh of a draw's ``mesh_key`` (its file and pose); tangents only when a variant drawing it
        has a normal map. With worker processes in the plan (``mesh_workers``), the first call reads every OBJ
        file of the plan through them."""
        if key not in self._meshes:
            if self.plan.mesh_workers and not self._meshes:
                self._read_in_workers()
            if key not in self._meshes:  # through the parse cache (core/models/obj_cached.py)
                path, pose = key
                self._meshes[key] = load_mesh(path, generate_tangents=key in self._needs_tangents, pose=pose,
                                              store=self._store)
        return self._meshes[key]

    def start_reading(self) -> None:
        """With worker processes in the plan, hand them every OBJ file of the plan now, so that they read while
        the caller sets up what needs no mesh; the first :meth:`mesh` call takes what they read (and raises the
        first refusal in draw order, as when they are started there). Nothing without workers."""
        if self.plan.mesh_workers and not self._meshes and self._reading is None:
            from wgpurender.core.models import mesh_workers, obj_cached

            jobs = [(key[0], key in self._needs_tangents) for key in self._obj_keys if key[1] is None]
            self._reading = mesh_workers.Reading(jobs, self.plan.mesh_workers, obj_cached.folder())

    def posed(self, key: tuple, pose) -> Mesh:
        """The mesh of ``key`` (a glTF model's file and the pose it was drawn in) re-posed at ``pose``, loaded by
        the same rule as :meth:`mesh` (tangents where a variant drawing it reads them), not cached: the window's
        playback (core/scene/playback.py) rewrites the drawn vertices with it each frame, from the parsed document
        the scene's load read (not the file again)."""
        from wgpurender.core.models.mesh import posed_mesh
        from wgpurender.core.scene.gltf_materials import document  # read once while the file is unchanged

        return posed_mesh(key[0], document(str(key[0])), pose, generate_tangents=key in self._needs_tangents)

    def turned(self, key: tuple, mesh: Mesh) -> bool:
        """Make re-posed ``mesh`` the mesh of ``key`` (buffers made from now on hold it) and say whether its
        indices differ from the one before (a node's mirroring turned its winding: core/models/mesh._place)."""
        before = self.mesh(key).index_bytes()
        self._meshes[key] = mesh
        return mesh.index_bytes() != before

    def _read_in_workers(self) -> None:
        """The plan's OBJ files, in draw order, read by core/models/mesh_workers.py; a file that is not a simple
        OBJ is left to :func:`load_mesh` (the general loader)."""
        self.start_reading()
        reading, self._reading = self._reading, None
        for (path, _), mesh in reading.finish().items():
            if mesh is not None:
                self._meshes[(path, None)] = mesh

    def mesh_for(self, draw: Draw) -> Mesh:
        """The draw's mesh, checked against the vertex attributes its variant reads (UserError names what is
        missing)."""
        attributes = self.plan.variant(draw.variant_key).vertex_attributes
        mesh = self.mesh(draw.mesh_key)
        if "uv" in attributes and not mesh.has_uvs:
            raise UserError(f"{draw.label}: its {draw.material_label} samples textures, but the model file has no "
                            "texture coordinates: export it with UVs, or use a material without maps")
        for k in _uv_slots(attributes):
            if len(mesh.extra_uvs) < k or mesh.extra_uvs[k - 1] is None:
                raise UserError(f"{draw.label}: its {draw.material_label} samples a set of texture coordinates "
                                "that the model file does not have: give the primitive the TEXCOORD_n its texCoord "
                                "names")
        if "tangent" in attributes and mesh.tangents is None:
            raise UserError(f"{draw.label}: no tangents could be made for its normal map")
        return mesh

    def index_range(self, draw: Draw) -> tuple[int, int]:
        """(first index, index count) of the triangles a draw covers: its file material's part, or all."""
        return index_range(self.mesh(draw.mesh_key), draw)


@functools.cache  # per attribute set, not per draw (10k draws)
def _uv_slots(attributes: tuple[str, ...]) -> tuple[int, ...]:
    """The coordinate slots k >= 1 a variant reads (its ``uv<k>`` attributes)."""
    return tuple(int(a[2:]) for a in attributes if a.startswith("uv") and a[2:].isdigit())


def changed_rows(before, after) -> tuple[int, int]:
    """(first, end) of the rows of ``after`` (a re-posed mesh's interleaved vertices) that differ from ``before``
    (the ones on the GPU; None or another shape: all of them): the one range a playback frame writes, so the
    parts of a model that stand still are not uploaded again; (0, 0) when nothing moved."""
    import numpy as np

    if before is None or before.shape != after.shape:
        return 0, len(after)
    moved = np.flatnonzero(np.any(before != after, axis=1))
    return (int(moved[0]), int(moved[-1]) + 1) if len(moved) else (0, 0)


BUFFER_ALIGN = 4  # set_vertex_buffer's and set_index_buffer's offsets, and a buffer's size, are multiples of 4


def buffer_places(sizes: list[tuple[int, int]], limit: int, names: list[str],
                  strides: list[int] | None = None) -> list[tuple[int, int, int]]:
    """Where each mesh goes when a scene's meshes share vertex and index buffers: (buffer pair, vertex offset,
    index offset) per mesh of ``sizes`` ((vertex bytes, index bytes), in draw order), each at a 4-byte aligned
    offset. A new pair starts when the mesh would take the vertex or the index buffer past ``limit`` bytes (the
    device's max-buffer-size; these buffers are never bound as storage, so no binding limit applies). One mesh
    larger than the limit cannot be drawn from one buffer: UserError naming it (``names``, beside ``sizes``).
    ``strides``: each mesh's vertex stride (bytes, a multiple of 4): its vertices then start on a whole vertex of
    it, so a draw can name them by base vertex from the buffer bound at 0."""
    plain = _places_in_one_pair(sizes, limit, strides)
    if plain is not None:
        return plain
    places, pair, vertex_end, index_end = [], 0, 0, 0
    for k, ((vertex, index), name) in enumerate(zip(sizes, names, strict=True)):
        vertex, index = (-(-n // BUFFER_ALIGN) * BUFFER_ALIGN for n in (vertex, index))
        if max(vertex, index) > limit:
            raise UserError(f"mesh {name} needs a {max(vertex, index)}-byte vertex or index buffer, more than this "
                            f"device's max-buffer-size ({limit} bytes): split the model into smaller meshes")
        step = strides[k] if strides else BUFFER_ALIGN
        start = -(-vertex_end // step) * step
        if start + vertex > limit or index_end + index > limit:
            pair, start, index_end = pair + 1, 0, 0
        places.append((pair, start, index_end))
        vertex_end, index_end = start + vertex, index_end + index
    return places


def _places_in_one_pair(sizes: list[tuple[int, int]], limit: int,
                        strides: list[int] | None) -> list[tuple[int, int, int]] | None:
    """:func:`buffer_places`' answer as one array pass where it is plain: one stride for every mesh, each mesh's
    aligned vertex bytes a whole number of it (so each mesh starts where the one before ends) and all of them
    within one pair (so no mesh is over the limit either); None otherwise (the loop decides). A scene of 10k mesh
    files: two running sums instead of 10k steps (issue 31.3)."""
    import numpy as np

    if not sizes or (strides and (min(strides) != max(strides) or len(strides) != len(sizes))):
        return None
    step = strides[0] if strides else BUFFER_ALIGN
    aligned = -(-np.array(sizes, dtype=np.int64).reshape(-1, 2) // BUFFER_ALIGN) * BUFFER_ALIGN
    if (aligned[:, 0] % step).any() or aligned.sum(axis=0).max() > limit:
        return None
    starts = (np.cumsum(aligned, axis=0) - aligned).tolist()
    return [(0, vertex, index) for vertex, index in starts]
