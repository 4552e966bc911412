"""The wheel works on its own: built from the repository, installed into a fresh venv, run from a temp folder.

Nothing a wheel user needs may come from the checkout (shaders were once found through the
repository root, so ``pip install .`` rendered nothing). The wheel is built offline
(``--no-build-isolation``: the test extra has setuptools>=77) from a copy of the files a build
reads, installed with ``--no-deps`` into a fresh venv that sees the running interpreter's packages
(the dependencies: its site-packages and its other sys.path folders, such as a PYTHONPATH, but never
the checkout) through a .pth file, which puts them after the venv's own site-packages, and then run
from an empty temp folder with no shader override set.

The wheel is the whole course: the scenes, models, textures, reference images and the notebook ship in it,
so a bundled scene renders by name, and verify, report, bench perf --quick, reference and the notebook run
from the empty folder. About 2.5 min on the shared 2-core machine under load (alone: report ~15 s, bench perf
--quick ~10 s, the notebook ~7 s).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import venv
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

REPO = Path(__file__).resolve().parent.parent
BUILD_INPUTS = ("pyproject.toml", "setup.py", "MANIFEST.in", "README.md", "wgpurender", "shaders_wgsl", "shaders_glsl",
                "assets", "examples", "docs")
# what the wheel must carry of assets/ (make_assets.py is the generator, not data)
COURSE_DATA = ("scenes", "models", "textures", "reference")

# The first triangle's vertices and colours (course step 2a), written out here: NDC, y up, linear RGB.
TRIANGLE_NDC = np.array([[-0.8, -0.7], [0.7, -0.5], [-0.1, 0.8]])
TRIANGLE_RGB = np.eye(3)


def _srgb8(linear: np.ndarray) -> np.ndarray:
    """IEC 61966-2-1 encoding to 8 bits (the default target is rgba8unorm-srgb)."""
    x = np.asarray(linear, dtype=np.float64)
    return np.round(255 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055))


def _check_triangle_centre(image: np.ndarray) -> None:
    """The pixel nearest the centroid has the barycentric mix of the vertex colours at its centre (within 1/255)."""
    h, w = image.shape[:2]
    cx, cy = TRIANGLE_NDC.mean(axis=0)
    px, py = int((cx + 1) / 2 * w), int((1 - cy) / 2 * h)
    centre = np.array([(px + 0.5) / w * 2 - 1, 1 - (py + 0.5) / h * 2])  # the pixel centre in NDC
    a, b, c = TRIANGLE_NDC
    weights = np.linalg.solve(np.array([b - a, c - a]).T, centre - a)
    bary = np.array([1 - weights.sum(), *weights])
    expected = _srgb8(bary @ TRIANGLE_RGB)
    assert np.abs(image[py, px, :3].astype(int) - expected).max() <= 1, (image[py, px], expected)


def _dependency_paths() -> list[str]:
    """Where this interpreter finds the dependencies: its site-packages and every other sys.path folder
    (e.g. PYTHONPATH=/tmp/site on the device machine), except any that holds a wgpurender package (the
    checkout) and the repository's tests: the venv must import wgpurender from the wheel or not at all."""
    paths = [sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"], *sys.path]
    keep = []
    for entry in paths:
        folder = Path(entry or ".").resolve()
        if (folder.is_dir() and not (folder / "wgpurender").exists() and folder not in (REPO, REPO / "tests")
                and str(folder) not in keep):
            keep.append(str(folder))
    return keep


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> dict:
    """Build the wheel, install it into a fresh venv; the venv's paths and a clean environment."""
    root = tmp_path_factory.mktemp("wheel")
    src = root / "src"
    src.mkdir()
    for name in BUILD_INPUTS:
        if (REPO / name).is_dir():
            shutil.copytree(REPO / name, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        else:
            shutil.copy2(REPO / name, src / name)
    pip = [sys.executable, "-m", "pip"]
    subprocess.run([*pip, "wheel", "-q", "--no-build-isolation", "--no-deps", "--no-index", str(src),
                    "-w", str(root / "dist")], check=True, capture_output=True, text=True)
    wheel = next((root / "dist").glob("wgpurender-*.whl"))
    env_dir = root / "venv"
    venv.create(env_dir, with_pip=False)
    python = env_dir / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          check=True, capture_output=True, text=True).stdout.strip()
    (Path(site) / "_test_venv_packages.pth").write_text("\n".join(_dependency_paths()) + "\n")
    env = {k: v for k, v in os.environ.items()
           if k not in ("WGPURENDER_SHADERS", "WGPURENDER_GLSL", "PYTHONPATH", "VIRTUAL_ENV")}
    # without PYTHONPATH: a checkout on it would make pip find wgpurender 'already installed'
    subprocess.run([*pip, "--python", str(python), "install", "-q", "--no-deps", "--no-index", str(wheel)],
                   check=True, capture_output=True, text=True, env=env)
    env["XDG_CACHE_HOME"] = str(root / "cache")  # a cold SPIR-V cache: the raw path must compile from the wheel
    cwd = root / "cwd"
    cwd.mkdir()
    return {"wheel": wheel, "python": python, "bin": env_dir / "bin", "env": env, "cwd": cwd, "cache": root / "cache"}


def _run(installed: dict, *args: str) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(a) for a in args], cwd=installed["cwd"], env=installed["env"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{args} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
    return proc


def test_the_wheel_carries_every_shader(installed):
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for folder, kind in (("shaders_wgsl", "wgsl"), ("shaders_glsl", "glsl")):
        expected = {f"wgpurender/_shaders/{kind}/{p.name}" for p in (REPO / folder).iterdir() if p.is_file()}
        assert expected and expected <= names, sorted(expected - names)


def test_the_wheel_carries_the_whole_course(installed):
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    expected = {f"wgpurender/_assets/{p.relative_to(REPO / 'assets').as_posix()}"
                for folder in COURSE_DATA for p in (REPO / "assets" / folder).rglob("*") if p.is_file()}
    expected.add("wgpurender/_examples/course_tour.ipynb")
    assert len(expected) > 20 and expected <= names, sorted(expected - names)


def test_the_wheel_carries_the_attribution_of_the_tutorial_files(installed):
    """The wheel ships the tutorial scenes, so the CC BY attribution of the files they read ships too."""
    from wgpurender.core.files.credits import all_credits

    assert "wgpurender/_assets/credits.toml" in zipfile.ZipFile(installed["wheel"]).namelist()
    code = ("from wgpurender.core.scene.credits import scene_credits; "
            "from wgpurender.core.files.assets import bundled_scene; "
            "print(scene_credits(bundled_scene('vulkan_tutorial_28'))[0].line())")
    assert _run(installed, installed["python"], "-c", code).stdout.strip() == all_credits()[0].line()


def test_the_installed_package_is_not_the_checkout(installed):
    out = _run(installed, installed["python"], "-c", "import wgpurender; print(wgpurender.__file__)").stdout
    assert Path(out.strip()).is_relative_to(installed["python"].parent.parent), out
    assert not Path(out.strip()).is_relative_to(REPO)


def test_render_triangle_from_the_wheel(installed):
    _run(installed, installed["bin"] / "wgpurender", "render", "triangle", "-o", "t.png")
    image = np.asarray(Image.open(installed["cwd"] / "t.png"))
    assert image.shape == (600, 800, 4)
    _check_triangle_centre(image)
    assert (image[0, 0, :3] == 0).all() and (image[-1, -1, :3] == 0).all()  # the black clear outside


def test_render_final_scene_from_the_wheel_matches_the_checkout(installed, ctx):
    """The bundled scene by name (step 6, the final model), from an empty folder. Same machine, same run: the
    wheel's render is bit-identical to this process's (checkout) render of the repository's file."""
    from wgpurender.wgpu_path.render import render_any

    scene = REPO / "assets" / "scenes" / "final.toml"
    _run(installed, installed["bin"] / "wgpurender", "render", "final", "-o", "f.png", "--size", "320x240")
    image = np.asarray(Image.open(installed["cwd"] / "f.png"))
    assert image.shape == (240, 320, 4)
    assert image[..., :3].std() > 20  # a lit scene, not a flat clear
    here = render_any(str(scene), size=(320, 240), anisotropy="auto").pixels  # what the CLI's render defaults to
    assert np.array_equal(image, here)


def test_python_api_from_the_wheel(installed):
    code = "import wgpurender as w; r = w.render('triangle', size=(64, 48)); print(r.pixels.shape)"
    assert _run(installed, installed["python"], "-c", code).stdout.strip() == "(48, 64, 4)"


@pytest.mark.skipif(shutil.which("glslc") is None, reason="glslc not installed (apt install glslc)")
def test_raw_path_from_the_wheel_uses_the_spirv_it_ships(installed):
    _run(installed, installed["bin"] / "wgpurender", "reference", "triangle", "-o", "r.png", "--size", "64x48")
    image = np.asarray(Image.open(installed["cwd"] / "r.png"))
    assert image.shape == (48, 64, 4)
    _check_triangle_centre(image)
    # the wheel's SPIR-V, made from this very GLSL when the wheel was built: nothing compiled into the user's cache
    assert not list((installed["cache"] / "wgpurender" / "spirv").glob("*.spv"))
    # a bundled scene by name on the raw path: the final model with the post chain its subpass runs
    _run(installed, installed["bin"] / "wgpurender", "reference", "final_subpass", "-o", "s.png", "--size", "64x48")
    scene = np.asarray(Image.open(installed["cwd"] / "s.png"))
    assert scene.shape == (48, 64, 4) and scene[..., :3].std() > 10


def test_raw_path_from_the_wheel_with_no_glslc_on_path(installed, tmp_path):
    """A pip user has no glslc: the wheel's SPIR-V (one file per variant of shaders_glsl/variants.txt, named by
    the hash of its source) draws a stage and the final scene, and nothing is compiled into the user's cache."""
    from wgpurender.core.shaders.spirv_names import VARIANTS_FILE, included, read_variants, spirv_name

    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    glsl = REPO / "shaders_glsl"
    for file_name, defines in read_variants((glsl / VARIANTS_FILE).read_text()):
        source = (glsl / file_name).read_bytes() + included(glsl / file_name)
        shipped = f"wgpurender/_shaders/spirv/{spirv_name(file_name, source, defines)}"
        assert shipped in names, (file_name, defines)
    env = dict(installed["env"], PATH=str(installed["bin"]), XDG_CACHE_HOME=str(tmp_path / "cache"))
    bare = dict(installed, env=env)
    _run(bare, installed["bin"] / "wgpurender", "reference", "triangle", "-o", "t.png", "--size", "64x48")
    _check_triangle_centre(np.asarray(Image.open(installed["cwd"] / "t.png")))
    _run(bare, installed["bin"] / "wgpurender", "reference", "final", "-o", "f.png", "--size", "64x48")
    assert np.asarray(Image.open(installed["cwd"] / "f.png"))[..., :3].std() > 10
    assert not list((tmp_path / "cache").rglob("*.spv")), "compiled without glslc?"


def test_a_bundled_scene_by_its_repository_path_and_through_the_api(installed):
    """assets/scenes/unlit.toml from a folder that has no assets/: the wheel's copy; w.render('final') too."""
    _run(installed, installed["bin"] / "wgpurender", "render", "assets/scenes/unlit.toml", "-o", "u.png",
         "--size", "64x48")
    assert np.asarray(Image.open(installed["cwd"] / "u.png")).shape == (48, 64, 4)
    code = "import wgpurender as w; r = w.render('final', size=(64, 48)); print(r.pixels.shape, r.plan.msaa)"
    assert _run(installed, installed["python"], "-c", code).stdout.split() == ["(48,", "64,", "4)", "4"]


def test_stages_and_the_course_map_from_the_wheel(installed):
    stages = _run(installed, installed["bin"] / "wgpurender", "stages").stdout
    assert "course step 6:" in stages and stages.splitlines()[-2].startswith("final ")
    course_map = _run(installed, installed["bin"] / "wgpurender", "stages", "--map").stdout
    rows = [line for line in course_map.splitlines() if line.startswith("| **")]
    assert len(rows) == 10 and rows[-1].startswith("| **6** `final`")
    assert all("(tests/ is in the repository, not in the wheel)" in row for row in rows)


@pytest.mark.skipif(shutil.which("glslc") is None, reason="glslc not installed (apt install glslc)")
def test_verify_quick_from_the_wheel(installed):
    """The committed reference images travel in the wheel: every check runs, none is skipped for a missing file."""
    out = _run(installed, installed["bin"] / "wgpurender", "verify", "--quick").stdout
    for row in ("stage    triangle", "stage    3d", "scene    unlit"):
        assert f"{row}" in out and "vs committed" in out, out
    assert "0 skipped" in out and not any(line.lstrip().lower().startswith("skip") for line in out.splitlines()), out


@pytest.mark.skipif(shutil.which("glslc") is None, reason="glslc not installed (apt install glslc)")
def test_report_from_the_wheel_has_every_step_and_scene(installed):
    from wgpurender.core.course.steps import stage_steps

    _run(installed, installed["bin"] / "wgpurender", "report", "-o", "r")
    page = (installed["cwd"] / "r" / "index.html").read_text()
    scenes = ["unlit", "retro", "brick", "final_subpass", "final"]  # the repository's scenes (not the tutorial's)
    for name in [s.stage for s in stage_steps()] + scenes:
        assert f"{name}_wgpu.png" in page, name
        assert (installed["cwd"] / "r" / f"{name}_wgpu.png").is_file(), name
    assert '<table class="accuracy-points">' in page and '<table class="hard-cases">' in page  # measured in the run


def test_bench_perf_quick_from_the_wheel_measures_the_scenes(installed):
    _run(installed, installed["bin"] / "wgpurender", "bench", "perf", "--quick", "--no-raw", "--out", "b")
    rows = (installed["cwd"] / "b" / "results.csv").read_text().splitlines()
    scenes = {row.split(",")[1] for row in rows if row.startswith("scene,")}
    assert {"final", "final_subpass"} <= scenes, scenes
    assert "not found" not in (installed["cwd"] / "b" / "report.md").read_text()


@pytest.mark.skipif(shutil.which("glslc") is None, reason="glslc not installed (apt install glslc)")
def test_the_notebook_from_the_wheel(installed):
    """The notebook shipped in the wheel, copied into the empty folder, runs on a kernel of the venv's python."""
    pytest.importorskip("nbformat", reason="nbformat is not installed (pip install -e '.[test]')")
    pytest.importorskip("nbclient", reason="nbclient is not installed (pip install -e '.[test]')")
    nb = installed["cwd"] / "tour.ipynb"
    code = ("import shutil, nbformat, nbclient; from wgpurender.core.files.assets import notebook_path; "
            f"shutil.copy(notebook_path(), {str(nb)!r}); nb = nbformat.read({str(nb)!r}, as_version=4); "
            "nbclient.NotebookClient(nb, timeout=300, kernel_name='python3').execute(); "
            "print(sum('final_subpass' in o.get('text', '') for c in nb.cells for o in c.get('outputs', [])))")
    assert int(_run(installed, installed["python"], "-c", code).stdout.split()[-1]) >= 1


def test_grading_a_class_of_ten_submissions_with_the_wheels_pytest_plugin(installed):
    """The plugin from the wheel's pytest11 entry point, in the empty folder, two xdist workers: 10 generated
    submissions (the 3c solution, the 1b starter, 8 mistakes drawn with a fixed seed), one folder per step. Each
    verdict is right, one line each, the HTML page lists them all, and the exit status says some failed."""
    import random

    from wgpurender.exercises import source
    from wgpurender.exercises.catalogue import EXERCISES, exercise

    rows = [(ex, m) for ex in EXERCISES if ex.path == "wgpu" and not ex.shader for m in ex.mistakes]  # stages: fast
    seeded = random.Random(29).sample(rows, 8)
    submissions = installed["cwd"] / "class"
    expected = {}

    def submit(step: str, name: str, text: str, verdict: str) -> None:
        (submissions / step).mkdir(parents=True, exist_ok=True)
        (submissions / step / f"{name}.py").write_text(text)
        expected[f"{name}.py"] = verdict

    submit("3c", "solution", source.solution_source(exercise("3c", "wgpu")), "PASS")
    submit("1b", "starter", source.starter_source(exercise("1b", "wgpu")), "FAIL")
    for ex, mistake in seeded:
        submit(ex.step, f"mistake_{ex.step}_{mistake.key}", source.mistake_source(ex, mistake),
               f"FAIL: your image matches '{mistake.title}'")
    proc = subprocess.run([str(installed["python"]), "-m", "pytest", "-p", "no:cacheprovider", "-n", "2",
                           "--wgpurender-step", "folder", "--wgpurender-html", "grades.html", "class"],
                          cwd=installed["cwd"], env=installed["env"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    grades = proc.stdout.split("wgpurender grades")[1].splitlines()
    for name, verdict in expected.items():
        lines = [line for line in grades if line.startswith(f"{name}: step")]
        assert len(lines) == 1 and verdict in lines[0], (name, lines)
    page = (installed["cwd"] / "grades.html").read_text()
    assert page.count('<tr class="') == 10 and "1 of 10 passed" in page
    assert page.count("<img ") >= 9  # each rendered submission's image and heatmap


def test_a_starters_own_test_runs_with_the_wheels_fixture(installed):
    """`wgpurender exercise 2a` from the wheel, then pytest on the folder it wrote: the wgpurender_check fixture
    fails the untouched starter with the check's report (exit status 1, the diagnosis in the output)."""
    _run(installed, installed["bin"] / "wgpurender", "exercise", "2a", "-o", "starter-2a")
    proc = subprocess.run([str(installed["python"]), "-m", "pytest", "-p", "no:cacheprovider", "starter-2a"],
                          cwd=installed["cwd"], env=installed["env"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "1 failed" in proc.stdout and "your image matches 'nothing drawn" in proc.stdout, proc.stdout
