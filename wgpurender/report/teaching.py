"""The report's "what each knob is for" section: the cases where a knob matters, against their truths.

Drawn from the run's own measurements (report/extras.py): the still-frame sweep's MSAA and filter rows with the
explanation of why a still frame ranks them as it does, the shimmer measure under slow motion
(bench/accuracy_shimmer.py), and the HDR target on a bright light (bench/accuracy_hdr.py, among the hard cases).
The words come from bench/accuracy_teaching.py, the same text docs/accuracy.md carries.
"""

from __future__ import annotations

from html import escape as e

from wgpurender.bench.accuracy_teaching import HDR, SHIMMER, STILL_FRAME


def _still_rows(measured) -> str:
    keep = {("msaa", "1"), ("msaa", "4"), ("filter", "nearest"), ("filter", "linear"), ("filter", "trilinear")}
    cells = [f"<tr><td>{e(p.group)}</td><td>{e(p.setting)}</td><td>{p.flip:.4f}</td></tr>"
             for p in measured.accuracy if (p.group, p.setting) in keep]
    return ('<table class="teaching-still"><tr><th>knob</th><th>setting</th><th>FLIP, final scene, still</th></tr>'
            + "".join(cells) + "</table>") if cells else ""


def _shimmer_rows(measured) -> str:
    cells = [f'<tr data-group="{e(r.section)}" data-setting="{e(r.setting)}"><td>{e(r.section)}</td>'
             f"<td>{e(r.setting)}</td><td>{r.shimmer:.4f}</td><td>{r.still_error:.4f}</td></tr>"
             for r in measured.shimmer]
    return ('<table class="teaching-shimmer"><tr><th>case</th><th>setting</th><th>shimmer</th>'
            "<th>still error</th></tr>" + "".join(cells) + "</table>") if cells else ""


def _hdr_rows(measured) -> str:
    cells = [f"<tr><td>{e(p.setting)}</td><td>{p.flip:.4f}</td><td>{p.psnr:.2f}</td></tr>"
             for p in measured.hard_cases if p.group == "HDR target"]
    return ('<table class="teaching-hdr"><tr><th>scene image</th><th>FLIP</th><th>PSNR dB</th></tr>'
            + "".join(cells) + "</table>") if cells else ""


def section(measured) -> str:
    """The HTML section (``measured``: report/extras.Measured, or None when accuracy was not measured)."""
    if measured is None:
        return ('<section id="teaching"><h2>What each knob is for</h2><p class="note">Not measured in this build.'
                "</p></section>")
    size = getattr(measured, "shimmer_size", None)
    where = f" ({size[0]}x{size[1]}, {measured.shimmer_frames} frames)" if size else ""
    return "\n".join([
        '<section id="teaching"><h2>What each knob is for</h2>',
        f"<h3>A still frame</h3><p>{e(STILL_FRAME)}</p>", _still_rows(measured),
        f"<h3>Shimmer under slow motion{e(where)}</h3><p>{e(SHIMMER)}</p>", _shimmer_rows(measured),
        f"<h3>The HDR target on a bright light</h3><p>{e(HDR)}</p>", _hdr_rows(measured),
        "</section>"])
