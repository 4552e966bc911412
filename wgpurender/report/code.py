"""The code on the report's page: for each step, the lines that make it on the wgpu path and on the raw path.

A stage's feature is its class's own ``setup`` (what it creates) and ``record`` (what it records each
frame), on each path; a scene's is the renderer's frame and scene-pass recording on each path. The
lines are taken from the source with :mod:`inspect`, highlighted with Pygments (a well-kept
highlighter: the report opens from disk with no script, so highlighting is done here, to static
HTML), and linked to a full highlighted listing of the file written beside the page
(``code/<path>.html#L-<line>``), so the site stays self-contained when it is copied elsewhere.
"""

from __future__ import annotations

import inspect
import textwrap
from dataclasses import dataclass
from pathlib import Path

from pygments import highlight
from pygments.formatters import HtmlFormatter
from pygments.lexers import PythonLexer

from wgpurender.concepts import resolve

REPO_ROOT = Path(__file__).resolve().parents[2]
STYLE = "friendly"
CSS_CLASS = "hl"
PATHS = {"wgpu": "wgpurender.wgpu_path.", "raw": "wgpurender.raw_path."}
# What makes a scene on each path: the frame (passes in order) and the scene pass (the draws).
SCENE_CODE = {
    "wgpu": ("scene.frame:SceneRenderer.record", "scene.scene_pass:ScenePassRenderer.record"),
    "raw": ("scene.frame:SceneFrame.record", "scene.scene_subpass:SceneSubpass.record"),
}
STAGE_METHODS = ("setup", "record")  # each where the stage class defines it itself
# Pygments wraps each excerpt line in <span id="LINE-n">; the ids become data-line attributes (one page holds the
# same function's excerpt in several steps, and ids must be unique), and the CSS wraps each long line under itself
# with its number hanging at the left, so no line is cut at a projector's 1280 px.
LINE_MARK = "excerpt-line"


@dataclass(frozen=True)
class Excerpt:
    """Some lines of one function, highlighted; ``path`` is relative to the repository."""

    location: str  # module:attr, without the package prefix
    path: str
    first: int
    last: int
    html: str
    source: str = ""  # the dedented lines, for the step-to-step diff (report/diffs.py)

    @property
    def listing(self) -> str:
        """The link to the highlighted file beside the page, at the first line."""
        return f"{listing_name(self.path)}#L-{self.first}"


def listing_name(path: str) -> str:
    return f"code/{path}.html"


def stage_locations(wgpu_cls: type | None, raw_cls: type | None) -> dict[str, list[str]]:
    """``module:Class.method`` of each stage class's own setup and record, per path."""
    out = {}
    for side, cls in (("wgpu", wgpu_cls), ("raw", raw_cls)):
        if cls is None:
            continue
        module = cls.__module__.removeprefix(PATHS[side])
        out[side] = [f"{module}:{cls.__name__}.{m}" for m in STAGE_METHODS if m in vars(cls)]
    return out


def scene_locations() -> dict[str, list[str]]:
    return {side: list(locs) for side, locs in SCENE_CODE.items()}


def excerpt(side: str, location: str) -> Excerpt:
    """The highlighted source of ``location`` (relative to the path's package), numbered as in the file."""
    obj = resolve(PATHS[side] + location)
    lines, first = inspect.getsourcelines(obj)
    path = Path(inspect.getsourcefile(obj)).resolve().relative_to(REPO_ROOT).as_posix()
    code = textwrap.dedent("".join(lines))
    formatter = HtmlFormatter(style=STYLE, cssclass=CSS_CLASS, linenos="inline", linenostart=first,
                              linespans=LINE_MARK)
    text = highlight(code, PythonLexer(), formatter)
    text = text.replace(f'<span id="{LINE_MARK}-', '<span class="line" data-line="')
    return Excerpt(location, path, first, first + len(lines) - 1, text, code)


def excerpts(locations: dict[str, list[str]]) -> dict[str, list[Excerpt]]:
    return {side: [excerpt(side, loc) for loc in locs] for side, locs in locations.items()}


def listing(path: str) -> str:
    """A whole file as a highlighted HTML page whose lines have anchors L-1, L-2, ..."""
    source = (REPO_ROOT / path).read_text(encoding="utf-8")
    formatter = HtmlFormatter(style=STYLE, cssclass=CSS_CLASS, linenos="table", lineanchors="L", anchorlinenos=True,
                              full=True, title=path)
    return highlight(source, PythonLexer(), formatter)


def style_css() -> str:
    return HtmlFormatter(style=STYLE, cssclass=CSS_CLASS).get_style_defs(f".{CSS_CLASS}")
