"""An FXAA pass run over an edge list (issue 31.6): three dispatches in one compute pass, one image.

The shaders and why are in wgpurender/bench/fxaa_variants/edge_wgsl.py: ``cs_mark`` writes every pixel off edges
and lists the edge pixels, ``cs_size`` turns the list's length into ``cs_edges``' indirect workgroup counts (and zeroes
the count for the next frame), ``cs_edges`` runs FXAA's edge search on the listed pixels only. The runner has
:class:`~wgpurender.wgpu_path.post.passes.ComputePass`'s calls (encode, dispatch, bound, copy), so a benchmark
or the chain can take it in that one's place. Its buffers: the count (8 bytes), the indirect arguments (12)
and the list, 4 bytes a pixel of the target (an image of edges only fits).
"""

from __future__ import annotations

from collections.abc import Callable

import wgpu

from wgpurender.bench.fxaa_variants.edge_wgsl import SIZE_WGSL, edge_list_source
from wgpurender.core.errors import UserError
from wgpurender.core.plan import PostPass
from wgpurender.wgpu_path.device.gpu_cache import device_cache
from wgpurender.wgpu_path.device.shaders import create_shader_module
from wgpurender.wgpu_path.post.passes import COMPUTE, ComputePass, PlannedPass
from wgpurender.wgpu_path.post.shaders import dispatch_groups, shape_of, srgb_constant

STORAGE = wgpu.BufferUsage.STORAGE
MAX_SIDE = 1 << 16  # a listed pixel packs x and y in 16 bits each


class EdgeListPass(PlannedPass):
    """FXAA (and the per-pixel steps after it) of a planned compute pass, its edge search over a list."""

    stage = COMPUTE

    def __init__(self, device: wgpu.GPUDevice, p: PostPass, shape: tuple[int, int, int] | None = None) -> None:
        if p.path != "compute" or p.steps[p.prelude].effect != "fxaa":
            raise ValueError(f"post pass {p.effect!r} on the {p.path} path has no FXAA to run over an edge list")
        super().__init__(device, p, shape, "")
        constants = {"SRGB_ENCODE": srgb_constant(p)} if any(s.effect == "srgb" for s in p.steps) else {}
        self.mark, self.edges = (device_cache(device, "post-pipelines").get(
            (self.key, "compute", entry, p.output_format), lambda e=entry: device.create_compute_pipeline(
                label=f"post-{p.effect}-{e}", layout=self.layout,
                compute={"module": self.module(), "entry_point": e, "constants": constants}))
            for entry in ("cs_mark", "cs_edges"))
        self.size_pipeline = device_cache(device, "post-pipelines").get(("edge-list", "cs_size"), lambda: (
            device.create_compute_pipeline(label="post-edge-list-size", layout="auto", compute={
                "module": create_shader_module(device, "post_edge_size.wgsl (generated)", SIZE_WGSL),
                "entry_point": "cs_size"})))
        self.count = device.create_buffer(label="post-edge-count", size=8, usage=STORAGE | wgpu.BufferUsage.COPY_SRC)
        self.args = device.create_buffer(label="post-edge-args", size=12, usage=STORAGE | wgpu.BufferUsage.INDIRECT)
        self.size_group = device.create_bind_group(
            label="post-edge-size", layout=self.size_pipeline.get_bind_group_layout(0),
            entries=[{"binding": 0, "resource": {"buffer": self.count, "offset": 0, "size": 8}},
                     {"binding": 1, "resource": {"buffer": self.args, "offset": 0, "size": 12}}])
        self.lists: dict[tuple[int, int], wgpu.GPUBuffer] = {}  # the list per target size (one, usually)

    def make_source(self, p: PostPass, shape, tiled) -> str:
        return edge_list_source(p, shape)

    def _entries(self) -> list[dict]:
        storage = {"type": "storage"}
        return super()._entries() + [
            {"binding": 3, "visibility": COMPUTE, "storage_texture": {
                "access": "write-only", "format": self.p.output_format, "view_dimension": "2d"}},
            {"binding": 4, "visibility": COMPUTE, "buffer": storage},
            {"binding": 5, "visibility": COMPUTE, "buffer": storage}]

    def _list(self, size: tuple[int, int]) -> wgpu.GPUBuffer:
        if size not in self.lists:
            if max(size) >= MAX_SIDE:
                raise UserError(f"post pass {self.p.effect!r}: an edge list holds images up to {MAX_SIDE - 1} "
                                f"pixels a side, not {size[0]}x{size[1]}; set post_path = \"fragment\"")
            self.lists.clear()
            self.lists[size] = self.device.create_buffer(label="post-edge-list", size=4 * size[0] * size[1],
                                                         usage=STORAGE)
        return self.lists[size]

    def _group(self, source: wgpu.GPUTexture, target: wgpu.GPUTexture) -> wgpu.GPUBindGroup:
        edges = self._list((target.size[0], target.size[1]))
        return self.groups.get((source, target), lambda: self.device.create_bind_group(
            label=f"post-{self.p.effect}-edges", layout=self.mark.get_bind_group_layout(0),
            entries=self._group_entries(source) + [
                {"binding": 3, "resource": target.create_view()},
                {"binding": 4, "resource": {"buffer": self.count, "offset": 0, "size": 8}},
                {"binding": 5, "resource": {"buffer": edges, "offset": 0, "size": edges.size}}]))

    def bound(self, source: wgpu.GPUTexture,
              target: wgpu.GPUTexture) -> Callable[[wgpu.GPUComputePassEncoder], None]:
        """The three dispatches between these textures, everything but the calls made now."""
        self.check(source, target)
        group, size_group = self._group(source, target), self.size_group
        mark, size_pipeline, edges, args = self.mark, self.size_pipeline, self.edges, self.args
        x, y = dispatch_groups((target.size[0], target.size[1]), shape_of(self.p, self.shape))

        def dispatch(compute_pass: wgpu.GPUComputePassEncoder) -> None:
            compute_pass.set_pipeline(mark)
            compute_pass.set_bind_group(0, group)
            compute_pass.dispatch_workgroups(x, y, 1)
            compute_pass.set_pipeline(size_pipeline)
            compute_pass.set_bind_group(0, size_group)
            compute_pass.dispatch_workgroups(1, 1, 1)
            compute_pass.set_pipeline(edges)
            compute_pass.set_bind_group(0, group)
            compute_pass.dispatch_workgroups_indirect(args, 0)

        return dispatch

    def dispatch(self, compute_pass: wgpu.GPUComputePassEncoder, source: wgpu.GPUTexture,
                 target: wgpu.GPUTexture) -> None:
        self.bound(source, target)(compute_pass)

    def encode(self, encoder: wgpu.GPUCommandEncoder, source: wgpu.GPUTexture, target: wgpu.GPUTexture,
               copy_to: wgpu.GPUTexture | None = None, timestamp_writes: dict | None = None) -> None:
        compute_pass = encoder.begin_compute_pass(label=f"post-{self.p.effect}-edges",
                                                  timestamp_writes=timestamp_writes)
        self.dispatch(compute_pass, source, target)
        compute_pass.end()
        if copy_to is not None:
            self.copy(encoder, target, copy_to)

    copy = staticmethod(ComputePass.copy)

    def listed(self) -> int:
        """The edge pixels the last run listed (a benchmark's and the tests' read-back; waits for the GPU)."""
        return int.from_bytes(self.device.queue.read_buffer(self.count, 4, 4), "little")


__all__ = ["EdgeListPass"]
