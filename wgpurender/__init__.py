"""wgpurender: the Vulkan course's rendering steps on wgpu-py, with a raw-Vulkan reference path.

The Python API (see :mod:`wgpurender.api`)::

    import wgpurender as w
    img = w.render("triangle", size=(320, 240))    # .pixels, .save(path), .timings, shown inline in Jupyter
    ref = w.reference("triangle", size=(320, 240))
    w.compare(ref, img)                            # PSNR, max difference, FLIP

Importing the package is cheap: the API's names load on first use, and wgpu (or vulkan) is imported
only when a name that needs it is used.
"""

import importlib
import sys
import types

from .errors import UserError

__version__ = "0.1.0"  # the one home of the version: pyproject.toml reads it (tool.setuptools.dynamic)

_API = ("Image", "reference", "heatmap", "side_by_side", "explain", "stage_names", "reference_stage_names")
# API functions named like a submodule (render.py, compare.py): the submodule is made callable, so that
# wgpurender.render(...) is the API while wgpurender.render.render_stage stays the module's function.
_CALLABLE = {"render": "render", "compare": "compare"}
__all__ = ["UserError", "__version__", *_API, *_CALLABLE]


class _CallableModule(types.ModuleType):
    """A submodule that is also an API function (``wgpurender.render`` -> :func:`wgpurender.api.render`)."""

    def __call__(self, *args, **kwargs):
        from . import api

        return getattr(api, _CALLABLE[self.__name__.rpartition(".")[2]])(*args, **kwargs)


class _Package(types.ModuleType):
    def __setattr__(self, name: str, value) -> None:
        # the import system binds a submodule to its package by setattr: make render/compare callable then
        if name in _CALLABLE and type(value) is types.ModuleType:
            value.__class__ = _CallableModule
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


def __getattr__(name: str):
    """Load the API on first use of one of its names (PEP 562)."""
    if name in _CALLABLE:
        importlib.import_module(f"{__name__}.{name}")  # binds it, callable, through _Package.__setattr__
        return sys.modules[__name__].__dict__[name]
    if name in _API:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'wgpurender' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_API, *_CALLABLE})
