"""Headless Chromium over the DevTools pipe, for reading exported pages back (``verify --implementations browser``
and the tests): one browser for many pages, WebGPU on (``--enable-unsafe-webgpu``: Dawn on SwiftShader, no GPU
needed) or off.

    with Chromium() as browser:
        tab = browser.open(Path("page/index.html"))
        frame = tab.evaluate("window.wgpurender.capture()")   # awaits promises, returns by value

No Python dependency: Chromium reads JSON commands from fd 3 and writes replies and events to fd 4, each
message ended by a NUL byte (``--remote-debugging-pipe``).
"""

from __future__ import annotations

import base64
import json
import os
import select
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from wgpurender.core.errors import UserError

NAMES = ("chromium", "chromium-browser", "google-chrome")


def find_chromium() -> str | None:
    return next((p for p in map(shutil.which, NAMES) if p), None)


class DevToolsPipe:
    """Chromium's DevTools protocol over ``--remote-debugging-pipe``: JSON commands out, replies and events in."""

    def __init__(self, write_fd: int, read_fd: int) -> None:
        self.write_fd, self.read_fd = write_fd, read_fd
        self.buffer = b""
        self.next_id = 0
        self.events: list[dict] = []

    def send(self, method: str, params: dict | None = None, session: str | None = None, timeout: float = 120.0):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.write_fd, json.dumps(message).encode() + b"\0")
        while True:
            reply = self.receive(timeout)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def receive(self, timeout: float) -> dict:
        deadline = time.monotonic() + timeout
        while b"\0" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self.read_fd], [], [], left)[0]:
                raise TimeoutError("no answer from Chromium")
            chunk = os.read(self.read_fd, 1 << 20)
            if not chunk:
                raise RuntimeError("Chromium closed the DevTools pipe")
            self.buffer += chunk
        message, _, self.buffer = self.buffer.partition(b"\0")
        return json.loads(message)

    def wait_event(self, method: str, timeout: float = 120.0) -> dict:
        deadline = time.monotonic() + timeout
        for event in self.events:
            if event.get("method") == method:
                return event
        while True:
            event = self.receive(max(0.0, deadline - time.monotonic()))
            self.events.append(event)
            if event.get("method") == method:
                return event


class Page:
    def __init__(self, pipe: DevToolsPipe, session: str, target: str) -> None:
        self.pipe, self.session, self.target = pipe, session, target

    def close(self) -> None:
        self.pipe.send("Target.closeTarget", {"targetId": self.target})

    def evaluate(self, expression: str, timeout: float = 300.0):
        reply = self.pipe.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                    "returnByValue": True}, session=self.session, timeout=timeout)
        if "exceptionDetails" in reply:
            details = reply["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text", "")
            raise RuntimeError(f"page error: {text}")
        return reply["result"].get("value")

    def capture(self, options: str = "") -> np.ndarray:
        """``window.wgpurender.capture(options)`` as an (H, W, 4) uint8 array."""
        frame = self.evaluate(f"window.wgpurender.capture({options})")
        rgba = np.frombuffer(base64.b64decode(frame["rgba"]), np.uint8)
        return rgba.reshape(frame["height"], frame["width"], 4)

    def mouse(self, kind: str, x: float, y: float, buttons: int = 1) -> None:
        self.pipe.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left",
                                                    "buttons": buttons, "clickCount": 1}, session=self.session)

    def errors(self) -> list[str]:
        """Console errors, uncaught exceptions and the browser's error log entries so far."""
        out = []
        for ev in self.pipe.events:
            method, params = ev.get("method"), ev.get("params", {})
            if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                out.append("console: " + " ".join(str(a.get("value", a.get("description", "")))
                                                  for a in params["args"]))
            elif method == "Runtime.exceptionThrown":
                out.append("exception: " + params.get("exceptionDetails", {}).get("text", ""))
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
                out.append(f"log: {params['entry'].get('text', '')}")
        return out


class Chromium:
    """A headless Chromium for the duration of a ``with`` block."""

    def __init__(self, webgpu: bool = True) -> None:
        self.webgpu = webgpu

    def __enter__(self) -> Chromium:
        exe = find_chromium()
        if exe is None:
            raise UserError("chromium is not installed (Debian: apt-get install chromium)")
        to_r, self._to_w = os.pipe()
        self._from_r, from_w = os.pipe()

        def fds() -> None:  # in the child: the protocol's fds are 3 (commands) and 4 (replies)
            commands, replies = os.dup(to_r), os.dup(from_w)
            os.dup2(commands, 3)
            os.dup2(replies, 4)

        self._profile = tempfile.TemporaryDirectory(prefix="wgpurender-chromium-")
        flags = ["--enable-unsafe-webgpu"] if self.webgpu else []
        args = [exe, "--headless=new", "--no-sandbox", "--no-first-run", "--hide-scrollbars", *flags,
                "--remote-debugging-pipe", f"--user-data-dir={self._profile.name}", "about:blank"]
        self.proc = subprocess.Popen(args, preexec_fn=fds, close_fds=False, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        os.close(to_r)
        os.close(from_w)
        self.pipe = DevToolsPipe(self._to_w, self._from_r)
        return self

    def version(self) -> str:
        return self.pipe.send("Browser.getVersion").get("product", "")

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
        return Page(self.pipe, session, target)

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
