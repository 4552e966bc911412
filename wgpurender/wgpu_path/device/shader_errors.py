"""Pipeline errors from user-supplied shaders as one clear line.

With ``$WGPURENDER_SHADERS`` pointing at a folder of edited WGSL files, a shader can compile and still not fit
its pipeline: an entry point renamed, a binding moved. wgpu then raises a ``GPUValidationError`` whose text says
(over several lines) which pipeline (its label is the shader file's name) and what did not match. Without that
variable the shaders are the project's own, so such an error is a bug and stays a traceback.
"""

from __future__ import annotations

import os
import re

from wgpurender.core.errors import UserError

SHADER_DIR_ENV = "WGPURENDER_SHADERS"  # the same variable wgpurender.wgpu_path.device.shaders reads
_LABEL = re.compile(r"label = '([^']*)'")


def as_user_error(err: BaseException) -> UserError | None:
    """A UserError naming the shader file and the mismatch, or None when ``err`` is not a shader mismatch."""
    folder = os.environ.get(SHADER_DIR_ENV)
    if not folder or type(err).__name__ not in ("GPUValidationError", "GPUPipelineError", "GPUError"):
        return None
    text = str(err)
    labels = _LABEL.findall(text)
    shader = next((label for label in labels if label.endswith(".wgsl")), labels[0] if labels else "a shader")
    causes = [line.strip() for line in text.splitlines() if line.strip()]
    problem = "; ".join(causes[-2:]) if causes else type(err).__name__
    return UserError(f"shader {shader} (from ${SHADER_DIR_ENV}={folder}) does not fit its pipeline: {problem}; "
                     "keep the entry points and @group/@binding declarations of the original in shaders_wgsl/")
