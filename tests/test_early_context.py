"""The device made on a thread while the rest is imported (context.start_context, issue 31.5).

``wgpurender render`` and the API's ``render`` start making the process's context before they import the renderer,
and ``get_context`` takes what the thread made. Each case runs in a fresh interpreter: one process has one wgpu
instance, and the point is what happens from process start.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from helpers import one_line_refusal

REPO = Path(__file__).resolve().parent.parent


def _python(code: str, *args: str, validation: bool = True) -> subprocess.CompletedProcess:
    path = [str(REPO), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path))
    if not validation:
        env.pop("WGPURENDER_VALIDATION", None)
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=240, env=env)


def test_the_context_made_on_the_thread_is_the_one_get_context_returns_and_draws_the_same_pixels(tmp_path):
    """Made on the thread (named, so it can be seen), taken once, kept; its stage 3d equals this process's."""
    code = (
        "import sys, threading\n"
        "import numpy as np\n"
        "from wgpurender.wgpu_path.device import context as c\n"
        "real, seen = c._make_context, []\n"
        "def spy(backend):\n"
        "    seen.append((threading.current_thread().name, sys.getswitchinterval()))\n"
        "    return real(backend)\n"
        "c._make_context = spy\n"
        "real_import = c._import_backend\n"
        "def import_spy():\n"
        "    seen.append(('backend imported on', threading.current_thread().name))\n"
        "    real_import()\n"
        "c._import_backend = import_spy\n"
        "c.start_context()\n"
        "early = c._early['Vulkan']\n"
        "from wgpurender.wgpu_path.render import render_stage\n"
        "ctx = c.get_context()\n"
        "assert ctx is early.ctx and c.get_context() is ctx and c.get_context('vulkan') is ctx\n"
        "print(seen, sys.getswitchinterval())\n"
        "np.save(sys.argv[1], render_stage('3d', (64, 48), ctx=ctx).pixels)\n"
    )
    out = _python(code, str(tmp_path / "early.npy"))
    assert out.returncode == 0, out.stderr[-2000:]
    # wgpu-py's backend imported first in the caller's thread (Python work: the thread begins with the driver);
    # the context made once, on the thread, with the short switch interval; Python's default back once it finished
    first = "('backend imported on', 'MainThread')"
    assert out.stdout.strip().startswith(f"[{first}, ('wgpurender-context', 0.0005)")
    assert out.stdout.strip().endswith("] 0.005") and out.stdout.count("('wgpurender-context', 0.0005)") == 1
    from wgpurender.wgpu_path.render import render_stage

    here = render_stage("3d", (64, 48)).pixels
    early = np.load(tmp_path / "early.npy")
    assert early.shape == (48, 64, 4) and len(np.unique(here.reshape(-1, 4), axis=0)) > 2
    np.testing.assert_array_equal(early, here)  # same machine, same run: exact


def test_an_error_on_the_thread_is_raised_by_get_context():
    """No Metal adapter on this machine: the thread's UserError reaches the caller of get_context."""
    code = (
        "from wgpurender.core.errors import UserError\n"
        "from wgpurender.wgpu_path.device import context as c\n"
        "c.start_context('metal')\n"
        "try:\n"
        "    c.get_context('metal')\n"
        "except UserError as e:\n"
        "    print('refused:', e)\n"
    )
    out = _python(code)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.startswith("refused: no Metal adapter found"), out.stdout


def test_a_bad_backend_name_is_refused_in_the_callers_thread_before_any_thread_starts():
    code = (
        "import threading\n"
        "from wgpurender.core.errors import UserError\n"
        "from wgpurender.wgpu_path.device import context as c\n"
        "try:\n"
        "    c.start_context('vulkann')\n"
        "except UserError as e:\n"
        "    print(threading.active_count(), e)\n"
    )
    out = _python(code)
    assert out.returncode == 0, out.stderr[-2000:]
    count, message = out.stdout.split(" ", 1)
    assert count == "1" and "vulkann" in message


def test_the_cli_refuses_a_missing_backend_in_one_line_with_the_device_started_early(tmp_path):
    """`render` starts the context on a thread; its error still ends the command with one line and exit 2."""
    target = tmp_path / "x.png"
    out = subprocess.run([sys.executable, "-m", "wgpurender", "render", "3d", "-o", str(target), "--size",
                          "32x24", "--backend", "metal"], capture_output=True, text=True, timeout=240,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(
                             [str(REPO), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))])))
    one_line_refusal(out.returncode, out.stderr, "no Metal adapter found")
    assert not target.exists()


def test_a_process_that_stops_while_the_device_is_being_made_waits_for_it_then_exits_with_its_own_code():
    """Bad input found after the start: the process waits for the thread at exit (not killed in the driver's
    code), then exits 2. The thread here takes 0.5 s more and says when it is done."""
    code = (
        "import sys, time\n"
        "from wgpurender.wgpu_path.device import context as c\n"
        "real = c._make_context\n"
        "def slow(backend):\n"
        "    ctx = real(backend)\n"
        "    time.sleep(0.5)\n"
        "    print('made', flush=True)\n"
        "    return ctx\n"
        "c._make_context = slow\n"
        "c.start_context()\n"
        "sys.exit(2)\n"
    )
    out = _python(code)
    assert out.returncode == 2, (out.returncode, out.stderr[-2000:])
    assert out.stdout == "made\n" and out.stderr == ""


def _spied(call: str) -> str:
    """Run ``call`` in a fresh process; print how many contexts were started early and how many made in all."""
    return (
        "from wgpurender.wgpu_path.device import context as c\n"
        "starts, makes = [], []\n"
        "real_start, real_make = c._EarlyContext.__init__, c._make_context\n"
        "def start(self, backend):\n"
        "    starts.append(backend)\n"
        "    real_start(self, backend)\n"
        "def make(backend):\n"
        "    makes.append(backend)\n"
        "    return real_make(backend)\n"
        "c._EarlyContext.__init__, c._make_context = start, make\n"
        f"{call}\n"
        "print(starts, makes)\n"
    )


def test_the_apis_render_and_the_startup_child_make_the_device_early_and_only_once():
    """What ``wgpurender render`` calls, and what bench perf's startup family times, start it on the thread; a
    second start while it is being made, or once it is made, starts nothing."""
    for call in ("import wgpurender as w; w.render('3d', size=(32, 24))",
                 "from wgpurender.bench.startup_child import child; child('wgpu', 'triangle', (32, 24), 0.0)",
                 "c.start_context(); c.start_context('vulkan'); c.get_context(); c.start_context()"):
        out = _python(_spied(call))
        assert out.returncode == 0, out.stderr[-2000:]
        assert out.stdout.strip() == "['Vulkan'] ['Vulkan']", (call, out.stdout)


def test_two_contexts_made_early_at_once_leave_pythons_switch_interval_as_it_was():
    """'auto' and 'vulkan' started together (one instance serves both): two threads, each with the short
    interval while it works; once both are done the interval is Python's default again, whichever ends last."""
    code = (
        "import sys\n"
        "from wgpurender.wgpu_path.device import context as c\n"
        "c.start_context('auto')\n"
        "c.start_context('vulkan')\n"
        "a, v = c.get_context('auto'), c.get_context('vulkan')\n"
        "print(a is not v, sys.getswitchinterval())\n"
    )
    # without the validation layer: with it, two Vulkan instances in one process end in SIGSEGV at exit on
    # NVIDIA's driver, made early or not (docs/backends.md); the switch interval is what this test is about
    out = _python(code, validation=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["True", "0.005"]
