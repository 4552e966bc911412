"""The report's HTML: one page, inline CSS, no script, images as PNG files beside it.

Every value is escaped; the page needs nothing from the network (no fonts, no CDN).
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from wgpurender.concepts import Concept
from wgpurender.report import teaching
from wgpurender.report.code import style_css
from wgpurender.report.concept_rows import locate
from wgpurender.report.steps import HEATMAP_GAIN, Step

GENERATOR_MARK = '<meta name="generator" content="wgpurender report">'

CSS = """
body { font: 15px/1.45 system-ui, sans-serif; margin: 0 auto; max-width: 1240px; padding: 0 18px 40px;
       color: #1d1f23; background: #fbfbfa; }
h1 { margin: 22px 0 4px; } h2 { margin-top: 34px; border-bottom: 2px solid #d8d8d4; padding-bottom: 4px; }
h4 { margin: 6px 0 4px; }
nav a { margin-right: 10px; white-space: nowrap; }
.meta { color: #555; font-size: 13px; }
.step { margin-top: 26px; }
.images { display: flex; gap: 14px; flex-wrap: wrap; align-items: flex-start; }
figure { margin: 0; } figcaption { font-size: 13px; color: #444; max-width: var(--shot-width); }
figure img { border: 1px solid #ccc; image-rendering: pixelated; width: var(--shot-width); height: auto; display: block;
             background: repeating-conic-gradient(#ddd 0 25%, #fff 0 50%) 0 0 / 16px 16px; }  /* alpha shows */
figure a.full { display: block; position: relative; cursor: zoom-in; }
.heat .verdict { position: absolute; left: 0; right: 0; top: 40%; text-align: center; color: #fff;
                 font-weight: 600; text-shadow: 0 0 3px #000; }
.lanes { display: flex; width: var(--shot-width); font-size: 11px; color: #333; line-height: 1.2; margin-top: 2px; }
.lanes span { border-left: 2px solid #888; padding: 0 3px; box-sizing: border-box; font-weight: 600; }
.lane-legend { font-size: 12px; color: #333; max-width: var(--shot-width); }
.scale img { width: auto; border: 1px solid #ccc; image-rendering: pixelated; }
.scale .ticks { display: flex; font-size: 11px; color: #444; }
.scale .ticks span { width: 24px; text-align: center; }
.note { background: #fff4e0; border-left: 3px solid #e0a030; padding: 6px 10px; font-size: 13px; max-width: 640px; }
table { border-collapse: collapse; margin: 8px 0; font-size: 13px; }
td, th { border: 1px solid #d4d4d0; padding: 3px 6px; vertical-align: top; text-align: left; }
th { background: #efefec; }
code, pre { font-family: ui-monospace, monospace; font-size: 12px; }
pre { background: #f1f1ee; padding: 8px; overflow-x: auto; }
pre.plan-text { white-space: pre-wrap; overflow-wrap: anywhere; }
details summary { cursor: pointer; color: #333; }
.loc { white-space: nowrap; } .loc small { color: #666; }
.code { display: grid; grid-template-columns: minmax(0, 1fr) minmax(0, 1fr); gap: 12px; margin: 10px 0; }
.code-side { min-width: 0; }
.excerpt { margin-bottom: 8px; border: 1px solid #ddd; background: #f8f8f8; }
.excerpt .source { display: block; font-size: 12px; padding: 2px 6px; background: #ecece8; }
.excerpt .hl pre { margin: 0; padding: 6px; font-size: 11.5px; line-height: 1.35; max-height: 420px; overflow: auto;
                   background: transparent; }
.hl .linenos { color: #999; padding-right: 6px; }
.excerpt .hl pre { white-space: pre-wrap; overflow-wrap: anywhere; }  /* long lines wrap under themselves */
.excerpt .hl .line { display: block; padding-left: 6ch; text-indent: -6ch; }
.excerpt .hl .line .linenos { display: inline-block; width: 5ch; text-indent: 0; text-align: right;
                              padding-right: 1ch; }
pre.diff { white-space: pre-wrap; overflow-wrap: anywhere; font-size: 11.5px; line-height: 1.35; margin: 0; }
pre.diff .add { background: #dcf5dc; } pre.diff .del { background: #f8dcdc; } pre.diff .hunk { color: #36c; }
pre.diff .file { color: #666; }
.diff-none { font-size: 12px; color: #555; margin: 2px 0; }
figure.plot figcaption { max-width: 760px; }
"""


def e(text: object) -> str:
    return html.escape(str(text))


def page(title: str, meta: str, steps: Sequence[Step], images: dict[str, dict[str, str]], scale: tuple[str, list[int]],
         closing: str, shot_width: int = 240) -> str:
    """The whole document; ``images[step.key]`` maps wgpu/raw/heat to file names."""
    nav = " ".join(f'<a href="#{e(s.key)}">{e(s.title)}</a>' for s in steps)
    body = "\n".join(section(s, images.get(s.key, {}), scale) for s in steps)
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
{GENERATOR_MARK}
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{e(title)}</title>
<style>:root {{ --shot-width: {shot_width}px; }}{CSS}{style_css()}</style>
</head>
<body>
<h1>{e(title)}</h1>
<p class="meta">{meta}</p>
<nav>{nav} <a href="#accuracy">accuracy</a> <a href="#hard-cases">hard cases</a> <a href="#teaching">knobs</a></nav>
{body}
{closing}
</body>
</html>
"""


def section(step: Step, files: dict[str, str], scale: tuple[str, list[int]]) -> str:
    words = "".join(f"<p>{e(p)}</p>" for p in step.words[:1])
    more = "".join(f"<pre>{e(p)}</pre>" if p.lstrip().startswith("-") else f"<p>{e(p)}</p>" for p in step.words[1:])
    if more:
        words += f"<details><summary>more from the source</summary>{more}</details>"
    plan = (f'<details class="plan"><summary>render plan (<code>--explain</code>)</summary>'
            f'<pre class="plan-text">{e(step.plan)}</pre></details>') if step.plan else ""
    links = "".join(f'<a href="{e(href)}">{e(text)}</a> ' for text, href in step.links)
    if step.missing:
        shots = f'<p class="note missing">{e(step.missing)}</p>'
    else:
        shots = f"""<div class="images">
{_figure(files, "wgpu (WGSL, wgpu-py)", step.wgpu_note, step, "wgpu")}
{_figure(files, "raw Vulkan (GLSL, vulkan binding)", step.raw_note, step, "raw")}
{_heat(files.get("heat"), scale, step)}
</div>
{_numbers(step)}"""
    return f"""<section class="step" id="{e(step.key)}" data-step="{e(step.key)}">
<h2>{e(step.title)} <small class="meta">{e(step.course_step)}</small></h2>
<p><strong>{e(step.summary)}</strong></p>
{words}
{_credits(step.credits)}
{f'<p class="links">{links}</p>' if links else ""}
{_try_it(step)}
{shots}
{_live(files)}
{_code(step)}
{plan}
{_concepts(step.concepts)}
</section>"""


def _credits(lines: list[str]) -> str:
    """The attribution of the files a step shows that the project did not make (CC BY: wherever they appear)."""
    return "".join(f'<p class="credit"><small>Credit: {e(line)}</small></p>' for line in lines)


def _try_it(step: Step) -> str:
    """The learner's way in: the step's exercise (docs/exercises.md), when it has one."""
    from wgpurender.exercises.catalogue import exercise_command

    command = exercise_command(step.key)
    return f'<p class="try">try it: <code>{e(command)}</code> (docs/exercises.md)</p>' if command else ""


def _live(files: dict[str, str]) -> str:
    """The link to the step's live page (wgpurender export), or why there is none."""
    if "live" in files:
        return (f'<p class="live"><a href="{e(files["live"])}">Run this step live in your browser</a> '
                "(WebGPU: the same WGSL, pipelines and data, replayed by the browser)</p>")
    return f'<p class="live"><small>No live page: {e(files["live_note"])}</small></p>' if "live_note" in files else ""


def _size(step: Step) -> str:
    image = step.wgpu if step.wgpu is not None else step.raw
    return f"{image.shape[1]}x{image.shape[0]}" if image is not None else ""


def _lanes(step: Step) -> str:
    """Short tags under the image's parts (A, 1, 2, ...) and a legend naming what each part samples with."""
    if not step.lanes:
        return ""
    tags = ["A"] + [str(k) for k in range(1, len(step.lanes))]
    spans = "".join(f'<span class="lane" style="width: {100 * share:.1f}%">{tag}</span>'
                    for tag, (_, share) in zip(tags, step.lanes, strict=True))
    legend = "; ".join(f"<b>{tag}</b> {e(text)}" for tag, (text, _) in zip(tags, step.lanes, strict=True))
    return f'<div class="lanes">{spans}</div><div class="lane-legend caption">{legend}</div>'


def _figure(files: dict[str, str], caption: str, note: str, step: Step, kind: str) -> str:
    """One path's image; the click opens its render at twice the size (``KIND_large``), else the image itself."""
    name = files.get(kind)
    if name is None:
        return (f'<figure class="shot" data-image="{kind}"><figcaption class="caption">{e(caption)}</figcaption>'
                f'<p class="note">{e(note or "not rendered")}</p></figure>')
    large = files.get(f"{kind}_large")
    image = step.large.get(kind)
    click = f"click: {image.shape[1]}x{image.shape[0]}" if large else "click: full size"
    return (f'<figure class="shot" data-image="{kind}"><a class="full" href="{e(large or name)}" title="{click}">'
            f'<img src="{e(name)}" alt="{e(caption)}"></a>{_lanes(step)}'
            f'<figcaption class="caption">{e(caption)}, {_size(step)} ({click})</figcaption></figure>')


def _heat(name: str | None, scale: tuple[str, list[int]], step: Step) -> str:
    if name is None:
        return ""
    scale_file, levels = scale
    c = step.comparison
    identical = c is not None and c.max_abs == 0
    ticks = "".join(f"<span>{'0' if k == 0 else k}{'+' if k == levels[-1] else ''}</span>" for k in levels)
    if identical:
        verdict = '<span class="verdict">identical</span>'
        caption = "|wgpu - raw|: identical, no pixel differs (the heatmap is all black)"
    else:
        verdict = ""
        caption = (f"|wgpu - raw|, largest channel, amplified &times;{HEATMAP_GAIN:.0f}: a 1/255 difference shows "
                   f"as {HEATMAP_GAIN:.0f}/255; largest here {c.max_abs}/255" if c else "|wgpu - raw|")
    return f"""<figure class="shot heat" data-image="heat"><a class="full" href="{e(name)}" title="full size">
<img src="{e(name)}" alt="difference heatmap">{verdict}</a>
<figcaption class="caption">{caption}</figcaption>
<div class="scale"><img src="{e(scale_file)}" alt="heatmap scale"><div class="ticks">{ticks}</div>
<figcaption class="caption">scale: difference in 1/255 steps, 0 = identical (black)</figcaption></div></figure>"""


def _code(step: Step) -> str:
    if not step.code:
        return ""
    sides = []
    for side, label in (("wgpu", "wgpu path"), ("raw", "raw-Vulkan path")):
        parts = [f'<div class="excerpt"><a class="source" href="{e(x.listing)}">{e(x.path)}:{x.first}-{x.last}'
                 f'</a>{x.html}</div>' for x in step.code.get(side, [])]
        body = "".join(parts) or f'<p class="note">no {label} code for this step</p>'
        sides.append(f'<div class="code-side" data-path="{side}"><h4>{label}</h4>{body}</div>')
    return (f'<details class="code-block" open><summary>the code that makes this step, both paths side by side'
            f'</summary><div class="code" id="{e(step.key)}-code">{"".join(sides)}</div>{_diffs(step)}</details>')


DIFF_CLASSES = (("+++", "file"), ("---", "file"), ("@@", "hunk"), ("+", "add"), ("-", "del"))


def _diff_line(line: str) -> str:
    kind = next((cls for mark, cls in DIFF_CLASSES if line.startswith(mark)), "same")
    return f'<span class="{kind}">{e(line)}</span>'


def _diffs(step: Step) -> str:
    """Per path, what changed in the code from the previous step (report/diffs.py), side by side."""
    sides = []
    for side, label in (("wgpu", "wgpu path"), ("raw", "raw-Vulkan path")):
        d = step.diffs.get(side)
        if d is None:
            body = f'<p class="diff-none">{label}: the first step with code here</p>'
        elif not d.lines:
            body = f'<p class="diff-none">{label}: the same code as {e(d.previous)}</p>'
        else:
            body = (f'<details class="diff"><summary>{label}: what changed from {e(d.previous)} '
                    f'(+{d.added} / -{d.removed} lines)</summary>'
                    f'<pre class="diff">{chr(10).join(_diff_line(x) for x in d.lines)}</pre></details>')
        sides.append(f'<div class="code-side diff-side" data-path="{side}">{body}</div>')
    return f'<div class="code diffs">{"".join(sides)}</div>'


def _ms(value: float | None) -> str:
    return "n/a" if value is None else f"{value:.3f} ms"


def _metric(key: str, label: str, *cells: str) -> str:
    values = "".join(f'<td class="value">{c}</td>' for c in cells)
    span = ' colspan="2"' if len(cells) == 1 else ""
    return f'<tr data-metric="{key}"><th class="label">{label}</th>{values.replace("<td", "<td" + span, 1)}</tr>'


def _numbers(step: Step) -> str:
    rows = []
    c = step.comparison
    if c is not None:
        psnr = "identical (inf)" if c.psnr == float("inf") else f"{c.psnr:.2f} dB"
        rows += [_metric("psnr", "PSNR", psnr), _metric("flip", "FLIP (mean)", f"{c.flip_mean:.5f}"),
                 _metric("max-diff", "max difference", f"{c.max_abs}/255; pixels over 1/255: {100 * c.over_1:.3f}%")]
    wgpu, raw = step.timing.get("wgpu"), step.timing.get("raw")
    if wgpu or raw:
        rows.append('<tr><th></th><th class="label">wgpu</th><th class="label">raw Vulkan</th></tr>')
        rows.append(_metric("gpu-ms", "GPU time (median)", _ms(wgpu and wgpu.gpu_ms), _ms(raw and raw.gpu_ms)))
        rows.append(_metric("frame-ms", "frame time (median)", _ms(wgpu and wgpu.frame_ms), _ms(raw and raw.frame_ms)))
    return f'<table class="metrics">{"".join(rows)}</table>' if rows else ""


def _locations(locations: Sequence[str], note: str) -> str:
    if not locations:
        return f"<small>({e(note or 'nothing')})</small>"
    items = []
    for loc in locations:
        where = locate(loc)
        items.append(f'<div class="loc"><code>{e(where.text)}</code><br><small>{e(where.where)}</small></div>')
    return "".join(items)


def _concepts(rows: Sequence[Concept]) -> str:
    if not rows:
        return ""
    body = "".join(
        f"<tr><td>{e(r.name)}</td><td>{'<br>'.join(e(v) for v in r.vulkan)}</td>"
        f"<td>{_locations(r.raw, r.raw_note)}</td><td>{'<br>'.join(e(w) for w in r.wgpu)}</td>"
        f"<td>{_locations(r.wgpu_where, '')}</td><td>{e(r.differs)}</td></tr>"
        for r in rows)
    return ("<details><summary>Vulkan &rarr; wgpu concepts of this step, with the code on both paths</summary>"
            "<table><tr><th>concept</th><th>Vulkan</th><th>raw path</th><th>wgpu</th><th>wgpu path</th>"
            f"<th>what differs</th></tr>{body}</table></details>")


def closing(measured) -> str:
    """The accuracy and hard-case sections from the run's own measurements (report/extras.py)."""
    from wgpurender.report.extras import number

    if measured is None:
        return ('<section id="accuracy"><h2>Accuracy: error against cost</h2><p class="note">Not measured in this '
                'build (accuracy=False).</p></section><section id="hard-cases"><h2>Hard cases against exact answers'
                '</h2><p class="note">Not measured in this build.</p></section>' + teaching.section(None))
    m = measured
    source = (f"Measured in this run ({e(m.when)}, {e(m.adapter)}, {m.size[0]}x{m.size[1]}, a quick variant: "
              f"{m.seconds:.0f} s). Full runs with more frames: docs/accuracy.md (<code>wgpurender bench accuracy"
              f"</code>) and docs/numerics.md.")
    parts = [f'<section id="accuracy" data-measured="{e(m.when)}"><h2>Accuracy: error against cost</h2>'
             f'<p class="meta source">{source}</p>']
    if m.plot:
        parts.append(f'<figure class="plot"><a class="full" href="{e(m.plot)}"><img src="{e(m.plot)}" '
                     f'alt="accuracy Pareto plot" style="width: 760px"></a><figcaption class="caption">Each quality '
                     f'knob of final.toml swept alone: FLIP against the 8x-supersampled ground truth, against '
                     f'{m.timer} time per frame; the Pareto front joins the settings no other beats on both.'
                     f'</figcaption></figure>')
    else:
        parts.append('<p class="note">The plot needs matplotlib (pip install \'wgpurender[bench]\'); the numbers '
                     'are below.</p>')
    parts.append(_points_table("accuracy-points", ("knob", "setting", "FLIP", "PSNR dB", f"{m.timer} ms", "Pareto"),
                               [(p, "yes" if p.pareto else "") for p in m.accuracy], number))
    parts.append('</section><section id="hard-cases"><h2>Hard cases against exact answers</h2>'
                 f'<p class="meta source">{source}</p><p>Thin slivers and sub-pixel triangles against their exact '
                 'coverage, a plane at a grazing angle against the float64 integral of the texture over each pixel, '
                 'and two planes 1e-4 apart far away against the image they must give: what each setting gets '
                 'wrong, and what it costs.</p>')
    parts.append(_points_table("hard-cases", ("case", "setting", "FLIP", "PSNR dB", f"{m.timer} ms"),
                               [(p, None) for p in m.hard_cases], number))
    parts.append("</section>")
    parts.append(teaching.section(m))
    return "\n".join(parts)


def _points_table(css: str, header: tuple[str, ...], points, number) -> str:
    rows = []
    for p, extra in points:
        cells = [e(p.group), e(p.setting), number(p.flip, 4), number(p.psnr, 2), number(p.ms, 2)]
        if extra is not None:
            cells.append(extra)
        rows.append(f'<tr data-group="{e(p.group)}" data-setting="{e(p.setting)}">'
                    + "".join(f'<td class="c{k}">{c}</td>' for k, c in enumerate(cells)) + "</tr>")
    head = "".join(f"<th>{e(h)}</th>" for h in header)
    return f'<table class="{css}"><tr>{head}</tr>{"".join(rows)}</table>'
