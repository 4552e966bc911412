"""The wgpu path: every course step and the final scene on wgpu-py (the subject of the course).

It imports the core and wgpu, never the raw path (tests/test_layering.py checks it).
"""

from wgpurender.wgpu_path.binding import install as _install_binding

_install_binding()  # $WGPURENDER_BINDING=dawn: wgpudawn becomes ``wgpu`` before any module here imports it
