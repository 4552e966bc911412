"""One headless Chromium for many pages, with WebGPU on or off, driven over the DevTools pipe (browser.py's _Pipe).

    with Chromium(webgpu=True) as browser:
        page = browser.open(Path("out/page/index.html"))
        frame = page.evaluate("window.wgpurender.capture()")   # awaits promises, returns by value

WebGPU: ``--headless=new --enable-unsafe-webgpu`` gives Dawn on SwiftShader (no GPU needed;
shared/notes/facts.md). Without the flag ``navigator.gpu`` gives no adapter.
"""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
from pathlib import Path

from browser import _errors, _Pipe, chromium


class Page:
    def __init__(self, pipe: _Pipe, session: str) -> None:
        self.pipe, self.session = pipe, session

    def evaluate(self, expression: str, timeout: float = 120.0):
        reply = self.pipe.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                    "returnByValue": True}, session=self.session, timeout=timeout)
        if "exceptionDetails" in reply:
            details = reply["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text", "")
            raise RuntimeError(f"page error: {text}")
        return reply["result"].get("value")

    def mouse(self, kind: str, x: float, y: float, buttons: int = 1) -> None:
        self.pipe.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left",
                                                    "buttons": buttons, "clickCount": 1}, session=self.session)

    def errors(self) -> list[str]:
        return _errors(self.pipe.events)


class Chromium:
    def __init__(self, webgpu: bool = True) -> None:
        self.webgpu = webgpu

    def __enter__(self) -> Chromium:
        exe = chromium()
        if exe is None:
            raise FileNotFoundError("chromium is not installed (apt-get install chromium)")
        to_r, self._to_w = os.pipe()
        self._from_r, from_w = os.pipe()

        def fds() -> None:
            commands, replies = os.dup(to_r), os.dup(from_w)
            os.dup2(commands, 3)
            os.dup2(replies, 4)

        self._profile = tempfile.TemporaryDirectory(prefix="wgpurender-webgpu-")
        flags = ["--enable-unsafe-webgpu"] if self.webgpu else []
        args = [exe, "--headless=new", "--no-sandbox", "--no-first-run", "--hide-scrollbars", *flags,
                "--remote-debugging-pipe", f"--user-data-dir={self._profile.name}", "about:blank"]
        self.proc = subprocess.Popen(args, preexec_fn=fds, close_fds=False, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        os.close(to_r)
        os.close(from_w)
        self.pipe = _Pipe(self.proc, self._to_w, self._from_r)
        return self

    def open(self, path: Path, size: tuple[int, int] = (900, 900), timeout: float = 120.0) -> Page:
        target = self.pipe.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.pipe.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            self.pipe.send(f"{domain}.enable", session=session)
        self.pipe.send("Emulation.setDeviceMetricsOverride",
                       {"width": size[0], "height": size[1], "deviceScaleFactor": 1, "mobile": False}, session=session)
        self.pipe.events.clear()
        self.pipe.send("Page.navigate", {"url": Path(path).resolve().as_uri()}, session=session)
        self.pipe.wait_event("Page.loadEventFired", timeout)
        return Page(self.pipe, session)

    def __exit__(self, *exc) -> None:
        try:
            self.pipe.send("Browser.close", timeout=10)
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_w)
        os.close(self._from_r)
        self._profile.cleanup()


if __name__ == "__main__":  # python browser_session.py PAGE.html: print the adapter and a capture's size
    import sys

    with Chromium() as browser:
        page = browser.open(Path(sys.argv[1]))
        print(json.dumps(page.evaluate("window.wgpurender.ready.then(() => window.wgpurender.adapter)")))
        frame = page.evaluate("window.wgpurender.capture()")
        print(frame["width"], frame["height"], len(frame["rgba"]), page.errors())
