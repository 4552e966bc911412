"""The report's HTML: one page, inline CSS, no script, images as PNG files beside it.

Every value is escaped; the page needs nothing from the network (no fonts, no CDN).
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from wgpurender.concepts import Concept
from wgpurender.report.concept_rows import locate
from wgpurender.report.steps import Step

GENERATOR_MARK = '<meta name="generator" content="wgpurender report">'

CSS = """
body { font: 15px/1.45 system-ui, sans-serif; margin: 0 auto; max-width: 1180px; padding: 0 18px 40px;
       color: #1d1f23; background: #fbfbfa; }
h1 { margin: 22px 0 4px; } h2 { margin-top: 34px; border-bottom: 2px solid #d8d8d4; padding-bottom: 4px; }
nav a { margin-right: 10px; white-space: nowrap; }
.meta { color: #555; font-size: 13px; }
.step { margin-top: 26px; }
.images { display: flex; gap: 14px; flex-wrap: wrap; align-items: flex-start; }
figure { margin: 0; } figcaption { font-size: 13px; color: #444; }
figure img { border: 1px solid #ccc; image-rendering: pixelated; width: 240px; height: auto; display: block;
             background: repeating-conic-gradient(#ddd 0 25%, #fff 0 50%) 0 0 / 16px 16px; }  /* alpha shows */
.scale img { width: auto; border: 1px solid #ccc; image-rendering: pixelated; }
.scale .ticks { display: flex; font-size: 11px; color: #444; }
.scale .ticks span { width: 24px; text-align: center; }
.note { background: #fff4e0; border-left: 3px solid #e0a030; padding: 6px 10px; font-size: 13px; max-width: 520px; }
table { border-collapse: collapse; margin: 8px 0; font-size: 13px; }
td, th { border: 1px solid #d4d4d0; padding: 3px 6px; vertical-align: top; text-align: left; }
th { background: #efefec; }
code, pre { font-family: ui-monospace, monospace; font-size: 12px; }
pre { background: #f1f1ee; padding: 8px; overflow-x: auto; }
details summary { cursor: pointer; color: #333; }
.loc { white-space: nowrap; } .loc small { color: #666; }
"""


def e(text: object) -> str:
    return html.escape(str(text))


def page(title: str, meta: str, steps: Sequence[Step], images: dict[str, dict[str, str]], scale: tuple[str, list[int]],
         closing: str) -> str:
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
<style>{CSS}</style>
</head>
<body>
<h1>{e(title)}</h1>
<p class="meta">{meta}</p>
<nav>{nav} <a href="#accuracy">accuracy</a> <a href="#hard-cases">hard cases</a></nav>
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
    plan = f"<details open><summary>render plan (<code>--explain</code>)</summary><pre>{e(step.plan)}</pre></details>" \
        if step.plan else ""
    return f"""<section class="step" id="{e(step.key)}">
<h2>{e(step.title)} <small class="meta">{e(step.course_step)}</small></h2>
<p><strong>{e(step.summary)}</strong></p>
{words}
<div class="images">
{_figure(files.get("wgpu"), "wgpu (WGSL, wgpu-py)", step.wgpu_note)}
{_figure(files.get("raw"), "raw Vulkan (GLSL, vulkan binding)", step.raw_note)}
{_heat(files.get("heat"), scale)}
</div>
{_live(files)}
{_numbers(step)}
{plan}
{_concepts(step.concepts)}
</section>"""


def _live(files: dict[str, str]) -> str:
    """The link to the step's live page (wgpurender export), or why there is none."""
    if "live" in files:
        return (f'<p class="live"><a href="{e(files["live"])}">Run this step live in your browser</a> '
                "(WebGPU: the same WGSL, pipelines and data, replayed by the browser)</p>")
    return f'<p class="live"><small>No live page: {e(files["live_note"])}</small></p>' if "live_note" in files else ""


def _figure(name: str | None, caption: str, note: str) -> str:
    if name is None:
        return f'<figure><figcaption>{e(caption)}</figcaption><p class="note">{e(note or "not rendered")}</p></figure>'
    return f'<figure><img src="{e(name)}" alt="{e(caption)}"><figcaption>{e(caption)}</figcaption></figure>'


def _heat(name: str | None, scale: tuple[str, list[int]]) -> str:
    if name is None:
        return ""
    scale_file, levels = scale
    ticks = "".join(f"<span>{k}{'+' if k == levels[-1] else ''}</span>" for k in levels)
    return f"""<figure><img src="{e(name)}" alt="difference heatmap">
<figcaption>difference |wgpu - raw|, largest channel</figcaption>
<div class="scale"><img src="{e(scale_file)}" alt="heatmap scale"><div class="ticks">{ticks}</div>
<figcaption>scale: difference in 1/255 steps</figcaption></div></figure>"""


def _ms(value: float | None) -> str:
    return "n/a" if value is None else f"{value:.3f} ms"


def _numbers(step: Step) -> str:
    rows = []
    c = step.comparison
    if c is not None:
        psnr = "identical (inf)" if c.psnr == float("inf") else f"{c.psnr:.2f} dB"
        rows.append(f"<tr><th>PSNR</th><td colspan=2>{psnr}</td></tr>"
                    f"<tr><th>FLIP (mean)</th><td colspan=2>{c.flip_mean:.5f}</td></tr>"
                    f"<tr><th>max difference</th><td colspan=2>{c.max_abs}/255; pixels over 1/255: "
                    f"{100 * c.over_1:.3f}%</td></tr>")
    wgpu, raw = step.timing.get("wgpu"), step.timing.get("raw")
    if wgpu or raw:
        rows.append("<tr><th></th><th>wgpu</th><th>raw Vulkan</th></tr>")
        rows.append(f"<tr><th>GPU time (median)</th><td>{_ms(wgpu and wgpu.gpu_ms)}</td>"
                    f"<td>{_ms(raw and raw.gpu_ms)}</td></tr>")
        rows.append(f"<tr><th>frame time (median)</th><td>{_ms(wgpu and wgpu.frame_ms)}</td>"
                    f"<td>{_ms(raw and raw.frame_ms)}</td></tr>")
    return f"<table>{''.join(rows)}</table>" if rows else ""


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


def closing(pareto: str | None, hard: tuple[list[str], list[list[str]], str] | None) -> str:
    parts = ['<section id="accuracy"><h2>Accuracy: error against cost</h2>']
    if pareto:
        parts.append(f'<p>The accuracy suite\'s knobs (docs/accuracy.md) as error against frame time; the Pareto '
                     f'front is the settings no other setting beats on both.</p><figure><img src="{e(pareto)}" '
                     f'alt="accuracy Pareto plot" style="width: 720px"></figure>')
    else:
        parts.append('<p class="note">docs/img/accuracy_pareto.png is missing: run <code>wgpurender bench '
                     'accuracy</code> to make it.</p>')
    parts.append('</section><section id="hard-cases"><h2>Numerical hard cases, naive against ours</h2>')
    if hard:
        header, rows, intro = hard
        parts.append(f"<p>{intro}</p><table><tr>{''.join(f'<th>{h}</th>' for h in header)}</tr>")
        parts += [f"<tr>{''.join(f'<td>{c}</td>' for c in row)}</tr>" for row in rows]
        parts.append("</table><p>From docs/numerics.md; <code>python benchmarks/hardcases_report.py</code> "
                     "prints this machine's numbers.</p>")
    else:
        parts.append('<p class="note">docs/numerics.md has no measured table.</p>')
    parts.append("</section>")
    return "\n".join(parts)
