"""Open a page in headless Chromium over the DevTools protocol (--remote-debugging-pipe) and report what happened.

Also the README's screenshot of the report (``make report-screenshot`` runs it)::

    cd tests && ../.venv/bin/python browser.py /tmp/site/index.html ../docs/img/report.png 3d 1100x1240

No Python dependency: Chromium reads JSON commands from fd 3 and writes replies and events
to fd 4, each message ended by a NUL byte. :func:`open_page` loads a file:// URL, waits for
the load event, and returns every <img>'s natural width, the console errors (console.error,
uncaught exceptions, and the browser's own log errors such as a failed resource load) and a
PNG screenshot of the viewport.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from wgpurender.webpage.chromium import DevToolsPipe

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")


def chromium() -> str | None:
    return next((p for p in map(shutil.which, CHROMIUM_NAMES) if p), None)


@dataclass
class PageReport:
    images: list[dict] = field(default_factory=list)  # {"src", "complete", "width"}
    errors: list[str] = field(default_factory=list)
    screenshot: bytes = b""
    values: dict = field(default_factory=dict)  # the results of the ``evaluate`` expressions, by name


def _errors(events: list[dict]) -> list[str]:
    out = []
    for ev in events:
        method, params = ev.get("method"), ev.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            out.append("console: " + " ".join(str(a.get("value", a.get("description", ""))) for a in params["args"]))
        elif method == "Runtime.exceptionThrown":
            out.append("exception: " + params.get("exceptionDetails", {}).get("text", ""))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            entry = params["entry"]
            out.append(f"log: {entry.get('text', '')} {entry.get('url', '')}".strip())
    return out


def open_page(path: Path, size: tuple[int, int] = (1200, 900), timeout: float = 90.0,
              scroll_to: str | None = None, evaluate: dict[str, str] | None = None) -> PageReport:
    """Load ``path`` in headless Chromium; what loaded, what went wrong, and a screenshot (of the element with
    id ``scroll_to`` scrolled to the top, when given). ``evaluate``: name -> JavaScript expression, run in the page
    before the screenshot; their JSON-able results come back in ``values``."""
    exe = chromium()
    if exe is None:
        raise FileNotFoundError("chromium is not installed (apt-get install chromium)")
    to_chrome_r, to_chrome_w = os.pipe()
    from_chrome_r, from_chrome_w = os.pipe()

    def fds() -> None:  # in the child: Chromium's protocol fds are 3 (commands) and 4 (replies)
        commands, replies = os.dup(to_chrome_r), os.dup(from_chrome_w)  # above 4, so dup2 never meets itself
        os.dup2(commands, 3)  # dup2 makes them inheritable: they survive the exec
        os.dup2(replies, 4)

    with tempfile.TemporaryDirectory(prefix="wgpurender-chromium-") as profile:
        args = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--hide-scrollbars",
                "--remote-debugging-pipe", f"--user-data-dir={profile}", "about:blank"]
        proc = subprocess.Popen(args, preexec_fn=fds, close_fds=False, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        pipe = DevToolsPipe(to_chrome_w, from_chrome_r)
        try:
            return _inspect(pipe, path, size, timeout, scroll_to, evaluate or {})
        finally:
            try:
                pipe.send("Browser.close", timeout=10)
            except (RuntimeError, TimeoutError, OSError):
                pass
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            os.close(to_chrome_w)
            os.close(from_chrome_r)


def _inspect(pipe: DevToolsPipe, path: Path, size: tuple[int, int], timeout: float, scroll_to: str | None,
             evaluate: dict[str, str]) -> PageReport:
    target = pipe.send("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = pipe.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    for domain in ("Page", "Runtime", "Log"):
        pipe.send(f"{domain}.enable", session=session)
    pipe.send("Emulation.setDeviceMetricsOverride",
              {"width": size[0], "height": size[1], "deviceScaleFactor": 1, "mobile": False}, session=session)
    pipe.events.clear()
    pipe.send("Page.navigate", {"url": Path(path).resolve().as_uri()}, session=session)
    pipe.wait_event("Page.loadEventFired", timeout)
    images = pipe.send("Runtime.evaluate", {
        "expression": "JSON.stringify(Array.from(document.images, i => "
                      "({src: i.getAttribute('src'), complete: i.complete, width: i.naturalWidth})))",
        "returnByValue": True}, session=session)["result"]["value"]
    values = {name: pipe.send("Runtime.evaluate", {"expression": expr, "returnByValue": True, "awaitPromise": True},
                              session=session)["result"].get("value") for name, expr in evaluate.items()}
    if scroll_to:
        scroll = f"document.getElementById({json.dumps(scroll_to)}).scrollIntoView()"
        pipe.send("Runtime.evaluate", {"expression": scroll}, session=session)
    shot = pipe.send("Page.captureScreenshot", {"format": "png"}, session=session)["data"]
    return PageReport(json.loads(images), _errors(pipe.events), base64.b64decode(shot), values)


if __name__ == "__main__":
    import sys

    page, png, *rest = sys.argv[1:]
    anchor = rest[0] if rest else None
    width, height = (int(v) for v in rest[1].split("x")) if len(rest) > 1 else (1100, 860)
    Path(png).write_bytes(open_page(Path(page), (width, height), scroll_to=anchor).screenshot)
