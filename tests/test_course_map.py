"""The course map (wgpurender/course_map.py): one row per course step, generated from the code, kept current.

The map's columns are found by reading the code; the checks here come from elsewhere: the files exist, the
WGSL column is what each wgpu stage actually loads when it renders (shaders.recording_loads on a real device)
and the GLSL column what each raw stage compiles, docs/course-map.md is the generator's output, and the course
texts it names are the ones ../shared/course indexes (where that folder exists: the map never reads it).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from wgpurender import course_map as cm
from wgpurender.core.course.steps import COURSE, COURSE_TEXTS

REPO = Path(__file__).resolve().parents[1]
SHARED_COURSE = REPO.parent / "shared" / "course"


@pytest.fixture(scope="module")
def rows():
    return cm.course_map()


def test_one_row_per_step_in_course_order_step_6_last(rows):
    assert [r.step.number for r in rows] == [s.number for s in COURSE]
    assert rows[-1].step.number == "6" and rows[-1].step.scene == "final"


def test_every_named_file_exists_and_every_step_is_on_both_paths_with_a_reference_and_tests(rows):
    for r in rows:
        named = [*r.wgpu, *r.wgsl, *r.raw, *r.glsl, *r.data, *r.reference, *r.tests]
        assert r.wgpu and r.raw and r.reference and r.tests and r.texts, r.step
        missing = [p for p in named if not (REPO / p).is_file()]
        assert not missing, (r.step.stage, missing)
    final = rows[-1]
    assert "assets/scenes/final.toml" in final.data and "shaders_wgsl/scene.wgsl" in final.wgsl
    assert "shaders_glsl/scene.frag" in final.glsl and "tests/test_wheel.py" in final.tests


def test_the_wgsl_column_is_what_each_stage_loads(rows, ctx):
    """Independent of the map's source reading: record the WGSL files a stage loads while it renders a frame."""
    from wgpurender.wgpu_path.device.gpu_cache import clear_caches
    from wgpurender.wgpu_path.device.shaders import recording_loads
    from wgpurender.wgpu_path.render import render_stage

    for r in rows:
        if r.step.scene is not None:
            continue
        clear_caches(ctx.device)  # a pipeline cached by an earlier test would load nothing
        with recording_loads() as loaded:
            render_stage(r.step.stage, (32, 24), None, None, 0.0, ctx)
        assert {p.name for p in loaded} == {Path(p).name for p in r.wgsl}, (r.step.stage, loaded, r.wgsl)


@pytest.mark.skipif(shutil.which("glslc") is None, reason="glslc not installed (apt install glslc)")
def test_the_glsl_column_is_what_each_raw_stage_compiles(rows, monkeypatch):
    """The raw path's counterpart: every GLSL file a raw stage turns into a shader module while it renders."""
    from wgpurender.raw_path import render_reference
    from wgpurender.raw_path.device import shaders as glsl

    loaded: set[str] = set()
    real = glsl.glsl_path
    monkeypatch.setattr(glsl, "glsl_path", lambda name: loaded.add(name) or real(name))
    for r in rows:
        if r.step.scene is not None:
            continue
        loaded.clear()
        render_reference(r.step.stage, (32, 24))
        assert loaded == {Path(p).name for p in r.glsl}, (r.step.stage, loaded, r.glsl)


def test_the_doc_is_the_generated_map():
    doc = (REPO / "docs" / "course-map.md").read_text(encoding="utf-8")
    assert doc == cm.course_map_doc(), "regenerate: python -m wgpurender.course_map > docs/course-map.md"


def test_stages_map_prints_the_table(capsys):
    from wgpurender.cli import main

    assert main(["stages", "--map"]) == 0
    out = capsys.readouterr().out
    assert out == cm.course_map_markdown()
    assert len([line for line in out.splitlines() if line.startswith("| **")]) == len(COURSE)


def test_the_map_needs_neither_tests_nor_the_course_texts(monkeypatch, tmp_path):
    """Where tests/ is absent (an installed wheel) the column says so; ../shared is never read."""
    monkeypatch.setattr(cm, "TESTS", tmp_path / "no-tests")
    text = cm.course_map_markdown()
    assert text.count("(tests/ is in the repository, not in the wheel)") == len(COURSE)
    assert "000_875fa49d9f08787a.txt" in text


@pytest.mark.skipif(not SHARED_COURSE.is_dir(), reason="../shared/course not present (the course texts)")
def test_the_named_course_texts_are_the_ones_the_course_folder_indexes():
    index = (SHARED_COURSE / "README.md").read_text(encoding="utf-8")
    for entry in COURSE_TEXTS.values():
        name = entry.split(" ")[0]
        assert (SHARED_COURSE / name).is_file() and name in index, name


def test_bundled_scenes_are_found_by_name_and_never_shadow_a_stage(tmp_path, monkeypatch):
    """`render final` is step 6's scene; a stage's name stays a stage even if a bundled scene took it."""
    from wgpurender.core.course.formats import is_scene_file
    from wgpurender.core.course.steps import stage_steps
    from wgpurender.core.files import assets

    assert is_scene_file("final") and assets.resolve_scene("final") == REPO / "assets" / "scenes" / "final.toml"
    assert assets.resolve_scene("assets/scenes/unlit.toml").is_file()
    assert not any(is_scene_file(s.stage) for s in stage_steps())
    scenes = tmp_path / "assets" / "scenes"
    scenes.mkdir(parents=True)
    (scenes / "triangle.toml").write_text("")
    monkeypatch.setattr(assets, "assets_dir", lambda: tmp_path / "assets")
    assert assets.bundled_scene("triangle") is not None and not is_scene_file("triangle")
    assert not is_scene_file("no-such-scene") and is_scene_file("anything.toml")
