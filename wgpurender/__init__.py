"""wgpurender: the Vulkan course's rendering steps on wgpu-py, with a raw-Vulkan reference path.

The Python API (see :mod:`wgpurender.api`)::

    import wgpurender as w
    img = w.render("triangle", size=(320, 240))    # .pixels, .save(path), .timings, shown inline in Jupyter
    ref = w.reference("triangle", size=(320, 240))
    w.compare(ref, img)                            # PSNR, max difference, FLIP

Importing the package is cheap: the API's names load on first use, and wgpu (or vulkan) is imported
only when a name that needs it is used.
"""

from wgpurender.core.errors import UserError

__version__ = "0.1.0"  # the one home of the version: pyproject.toml reads it (tool.setuptools.dynamic)

_API = ("Image", "render", "reference", "compare", "heatmap", "side_by_side", "plan", "explain", "stage_names",
        "reference_stage_names", "export")
__all__ = ["UserError", "__version__", *_API]


def __getattr__(name: str):
    """Load the API on first use of one of its names (PEP 562): ``import wgpurender`` stays cheap."""
    if name in _API:
        from wgpurender import api

        return getattr(api, name)
    raise AttributeError(f"module 'wgpurender' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_API})
