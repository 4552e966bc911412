"""Join results.json (run.py) with verdicts.toml (the judgement of each image against its README) into
results.csv, and lay the images side by side in contact sheets (wgpu | raw | pygfx per sample).

Usage: python docs/runs/2026-11-27-heldout-khronos/table.py OUT_DIR SAMPLES_DIR [--after]
"""

from __future__ import annotations

import csv
import json
import sys
import tomllib
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from probes import PROBES  # noqa: E402
from samples import LICENCES, NO_SHEET  # noqa: E402

THUMB, ROWS_PER_SHEET, LABEL = 128, 10, 240
COLUMNS = ("file", "feature", "right render (README)", "wgpurender wgpu", "wgpurender raw", "pygfx",
           "verdict by", "notes", "wgpu: disclosed as ignored", "licence", "pixels off wgpu vs pygfx",
           "pixels off wgpu vs raw")


def sheet(out: Path, keys: list[str], results: dict, index: int) -> Path:
    image = Image.new("RGB", (LABEL + 3 * THUMB, THUMB // 4 + len(keys) * THUMB), "white")
    draw = ImageDraw.Draw(image)
    for c, name in enumerate(("wgpu", "raw", "pygfx")):
        draw.text((LABEL + c * THUMB + 4, 8), name, fill="black")
    for r, key in enumerate(keys):
        top = THUMB // 4 + r * THUMB
        draw.multiline_text((4, top + 4), key.replace("/", "\n"), fill="black")
        for c, name in enumerate(("wgpu", "raw", "pygfx")):
            shot = out / "shots" / key.replace("/", "-") / f"{name}.png"
            if shot.exists():
                image.paste(Image.open(shot).convert("RGB").resize((THUMB, THUMB)), (LABEL + c * THUMB, top))
            else:
                draw.text((LABEL + c * THUMB + 4, top + THUMB // 2), f"rc {results[key][name]['rc']}", fill="red")
    path = out / f"sheet-{index}.png"
    image.save(path, optimize=True)
    return path


def off_share(out: Path, key: str, a: str, b: str) -> str:
    """Share of pixels whose largest channel difference between two renderers' images passes 64/255: a pointer to
    look at, not a verdict (the two renderers light and antialias differently)."""
    folder = out / "shots" / key.replace("/", "-")
    if not (folder / f"{a}.png").exists() or not (folder / f"{b}.png").exists():
        return ""
    one, two = (np.asarray(Image.open(folder / f"{n}.png").convert("RGB")).astype(int) for n in (a, b))
    return f"{(np.abs(one - two).max(axis=-1) > 64).mean():.3f}"


def probe(out: Path, samples: Path, key: str, res: dict, name: str) -> tuple[str, str] | None:
    """The sample's pixel probe on one renderer's image: (verdict, what was measured), None without a probe."""
    shot = out / "shots" / key.replace("/", "-") / f"{name}.png"
    sample = key.split("/")[0]
    if sample not in PROBES or not shot.exists():
        return None
    image = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    ok, text = PROBES[sample](image, samples / res["file"], res["camera"], image.shape[0])
    return ("right" if ok else "wrong"), text


def verdict(out: Path, samples: Path, key: str, res: dict, judged: dict, name: str) -> tuple[str, str]:
    """A refusal is its own verdict; then the probe where the sample has one; else the judgement by eye."""
    if res[name]["rc"]:
        line = (res[name]["error"].splitlines() or ["?"])[-1]
        return judged.get(name, f"refused: {line}"), line
    found = probe(out, samples, key, res, name)
    if found is not None:  # a failed probe of a drop the renderer disclosed stays that drop
        disclosed = judged.get(name) in ("drops-disclosed", "drops-silent")
        return (judged[name] if found[0] == "wrong" and disclosed else found[0]), found[1]
    return judged.get(name, "unjudged"), ""


def scrub(out: Path, samples: Path) -> dict:
    """results.json without this machine's folders: paths in messages become relative to the samples folder."""
    text = (out / "results.json").read_text()
    for folder in {str(samples), str(samples.resolve())}:
        text = text.replace(folder.rstrip("/") + "/", "")
    (out / "results.json").write_text(text)
    return json.loads(text)


def main(out: Path, samples: Path, after: bool) -> int:
    results = scrub(out, samples)
    verdicts = tomllib.loads((HERE / "verdicts.toml").read_text())
    changed = verdicts.pop("after")
    if after:  # the verdicts that changed with this branch's fixes, over the rest
        verdicts = {key: {**value, **changed.get(key, {})} for key, value in verdicts.items()}
    rows = []
    for key, res in results.items():
        v = verdicts.get(key, {})
        cells = {name: verdict(out, samples, key, res, v, name) for name in ("wgpu", "raw", "pygfx")}
        by = "probe" if res["file"].split("/")[0] in PROBES else "eye"
        measured = "; ".join(f"{name}: {text}" for name, (_, text) in cells.items() if text and by == "probe")
        rows.append([res["file"], res["feature"], res["right"], cells["wgpu"][0], cells["raw"][0], cells["pygfx"][0],
                     by, "; ".join(x for x in (v.get("notes", ""), measured) if x),
                     " | ".join(res["wgpu"]["ignored"]) or (res["wgpu"]["error"].splitlines() or [""])[-1],
                     LICENCES[key.split("/")[0]], off_share(out, key, "wgpu", "pygfx"),
                     off_share(out, key, "wgpu", "raw")])
    with (out / "results.csv").open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(COLUMNS)
        writer.writerows(rows)
    keys = [key for key in results if key.split("/")[0] not in NO_SHEET]
    for i in range(0, len(keys), ROWS_PER_SHEET):
        sheet(out, keys[i:i + ROWS_PER_SHEET], results, i // ROWS_PER_SHEET + 1)
    counts = {}
    for row in rows:
        for col, name in ((3, "wgpu"), (4, "raw"), (5, "pygfx")):
            counts.setdefault(name, {}).setdefault(row[col], 0)
            counts[name][row[col]] += 1
    print(json.dumps(counts, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(Path(sys.argv[1]), Path(sys.argv[2]), "--after" in sys.argv[3:]))
