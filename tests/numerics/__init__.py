"""Numerically careful building blocks, each with a naive counterpart that the hard-case tests show failing.

- :mod:`.quaternions`: quaternion <-> matrix (Shepperd's branch, stable near 180 degrees), renormalisation, slerp,
  re-orthonormalisation of drifting rotation matrices.
- :mod:`.camera_relative`: compose model-view in float64 so float32 never sees world coordinates of 1e6.
- :mod:`.gpu_eval`: run a small compute shader over storage buffers and read the result back.
- :mod:`.depth_planes`: the depth-precision scene (two nearly coincident planes) with a chosen depth format / reverse-Z.
- :mod:`.coverage`: flat-colour triangles at 1x or 4x MSAA, for coverage-vs-area tests.
- :mod:`.normals`: the cofactor normal matrix scaled for float32, and analytic normals of scaled rotations.
- :mod:`.lit`: a lit, normal-mapped mesh rendered into rgba32float (NaN shows there), safe or plain normalize.
- :mod:`.uv_tiling`: per-mesh integer UV shift in float64, and a probe of interpolated/sampled texel coordinates.

See docs/numerics.md for what each hard case proves and the tolerances.
"""
