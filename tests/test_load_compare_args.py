"""benchmarks/load_compare.py's command line (issue 31.3's load probe): a bad argument is one line and exit 2,
before any GPU work. Before, a count that was no number or a KNOB without '=' was a traceback, and an option it did
not know (a misspelt --split) was dropped: the run wrote no split and said nothing."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parent.parent / "benchmarks" / "load_compare.py"


def _module():
    spec = importlib.util.spec_from_file_location("load_compare", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_documented_forms_are_read():
    args = _module().arguments
    assert args(["load2", "10000", "o.csv", "warm", "--split=s.csv"]) == (
        "load2", 10000, Path("o.csv"), "warm", Path("s.csv"), None, {})
    assert args(["m", "7", "o.csv", "cold", "mesh_workers=off", "--max-workers=8"]) == (
        "m", 7, Path("o.csv"), "cold", None, 8, {"mesh_workers": "off"})
    assert args(["m", "7", "o.csv"])[3] == "cold"
    assert args(["m", "7", "o.csv", "warm", "--scene=batched"])[6] == {"--scene": "batched"}  # main takes it out


def test_the_batched_scene_is_n_models_of_one_file_each_at_its_grid_place(tmp_path):
    from wgpurender.bench import scale
    from wgpurender.core.scene.load import load_scene

    module = _module()
    models = load_scene(module.batched_scene(tmp_path, 7)).models
    assert len(models) == 7 and {m.path for m in models} == {(tmp_path / "cube.obj").resolve()}
    places = [[row[3] for row in m.transform.matrix[:3]] for m in models]
    assert places == scale.grid_offsets(7).tolist()


@pytest.mark.parametrize(("argv", "words"), [
    (["m", "ten", "o.csv"], "N 'ten'"), (["m", "0", "o.csv"], "N '0'"), (["m", "1\u00b2", "o.csv"], "N '1"),
    (["m", "5"], "LABEL, N and OUT.csv are required"), (["m", "5", "o.csv", "hot"], "cache mode 'hot'"),
    (["m", "5", "o.csv", "cold", "mesh_workers"], "'mesh_workers': give KNOB=VALUE"),
    (["m", "5", "o.csv", "cold", "--spilt=s.csv"], "unknown option '--spilt'"),
    (["m", "5", "o.csv", "cold", "--max-workers=x"], "--max-workers=x"),
    (["m", "5", "o.csv", "cold", "--max-workers=0"], "--max-workers=0"),
    (["m", "5", "o.csv", "cold", "--split="], "'--split='"),
    (["m", "5", "o.csv", "cold", "--scene=instanced"], "--scene=instanced: give distinct or batched"),
    (["a,b", "5", "o.csv"], "without commas")])
def test_a_bad_argument_is_refused(argv, words):
    with pytest.raises(ValueError, match=None) as caught:
        _module().arguments(argv)
    assert words in str(caught.value) and "\n" not in str(caught.value)


def test_the_script_says_it_in_one_line_with_exit_2(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SCRIPT.parent.parent),
                                                      *filter(None, [os.environ.get("PYTHONPATH")])]))
    out = tmp_path / "o.csv"
    proc = subprocess.run([sys.executable, str(SCRIPT), "m", "ten", str(out)], capture_output=True, text=True,
                          env=env, timeout=120)
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert proc.returncode == 2 and len(lines) == 1 and lines[0].startswith("load_compare: N 'ten'"), proc.stderr
    assert not out.exists()
