"""wgpurender: the Vulkan course's rendering steps on wgpu-py, with a raw-Vulkan reference path."""

from .errors import UserError

__all__ = ["UserError"]
__version__ = "0.1.0"
