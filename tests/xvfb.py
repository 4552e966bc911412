"""A private Xvfb for the window tests: started on a display number it picks itself, stopped by PID.

Where Xvfb is installed but cannot start (e.g. an unpacked .deb that misses a shared library on the
device machine) the tests skip with Xvfb's own message, as they do where it is not installed. Once a
display is up, every failure is the test's.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from collections.abc import Iterator

import pytest


def private_display() -> Iterator[str]:
    """Yield ':N' for a fresh Xvfb (use as the body of a pytest fixture)."""
    read_fd, write_fd = os.pipe()
    with tempfile.TemporaryFile() as errors:
        proc = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "640x480x24", "-nolisten", "tcp"],
                                pass_fds=(write_fd,), stdout=subprocess.DEVNULL, stderr=errors)
        os.close(write_fd)
        with os.fdopen(read_fd) as pipe:
            number = pipe.readline().strip()  # empty: Xvfb closed the pipe, i.e. it exited
        if not number:
            try:
                code = proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                pytest.fail("Xvfb is running but did not report a display number")
            errors.seek(0)
            said = errors.read().decode(errors="replace").strip().splitlines()
            pytest.skip(f"Xvfb cannot start here (exit status {code}): " + (" / ".join(said[-3:]) or "no message"))
        try:
            yield f":{number}"
        finally:
            proc.terminate()
            proc.wait(timeout=10)


@pytest.fixture(scope="module", name="display")
def xvfb_display() -> Iterator[str]:
    """The fixture ``display`` (import ``xvfb_display`` into a test module): a private Xvfb for that module."""
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (apt-get install xvfb)")
    yield from private_display()
