"""An empty input path is refused as empty, not as the current folder.

``wgpurender compare "" b.png`` (an unset shell variable: compare "$REF" b.png) said "cannot read image .: it
is a directory": Path("") is ".", so the message named a folder the user never gave.
"""

from __future__ import annotations

import numpy as np
import pytest

from wgpurender.cli import main
from wgpurender.core.errors import UserError
from wgpurender.core.files.imageio import load_png, save_png


def test_compare_with_an_empty_path(capsys, tmp_path):
    b = save_png(tmp_path / "b.png", np.zeros((2, 2, 4), np.uint8))
    assert main(["compare", "", str(b)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "empty" in err[0] and "directory" not in err[0]


def test_load_png_with_an_empty_path():
    with pytest.raises(UserError, match="no image given: the path is empty"):
        load_png("")
