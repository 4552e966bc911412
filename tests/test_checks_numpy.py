"""core/checks.py without importing numpy until a check needs it (issue 31.5).

The backend check runs before the device is started on a thread (wgpu_path/device/context.start_context); numpy
(~50 ms to import on lavapipe's host) is then imported while the device is made. numpy's values are still
checked as before: its bool is a bool (and not a number), its arrays of two whole numbers a size.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wgpurender.core import checks
from wgpurender.core.errors import UserError

REPO = Path(__file__).resolve().parent.parent


def test_the_backend_check_imports_no_numpy():
    code = ("import sys\nfrom wgpurender.core import checks\n"
            "print(checks.backend('vulkan'), 'numpy' in sys.modules)")
    path = os.pathsep.join([str(REPO), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, PYTHONPATH=path))
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["Vulkan", "False"]


def test_numpy_values_are_checked_as_before():
    assert checks.flag(np.bool_(True), "x") is True and checks.flag(np.False_, "x") is False
    with pytest.raises(UserError, match="must be True or False"):
        checks.flag(1, "x")
    with pytest.raises(UserError, match="must be a number"):
        checks.number(np.bool_(True), "t")
    assert checks.number(np.float32(1.5), "t") == 1.5
    assert checks.size(np.array([32, 24])) == (32, 24)
    with pytest.raises(UserError, match="malformed size"):
        checks.size(np.array([32.5, 24.0]))
