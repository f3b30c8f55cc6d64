"""Headless Chromium driven through the Chrome DevTools Protocol, for the HTML report tests.

A small synchronous client: :class:`Browser` starts ``chromium --headless`` with a debugging
port, attaches to its page over a websocket (tornado's client, installed with the ``cluster``
extra through Dask's ``distributed``), and offers what the tests need: open a file, evaluate
JavaScript, move and click the mouse, take a PNG screenshot, and the console errors and
uncaught exceptions seen so far.
"""

from __future__ import annotations

import asyncio
import base64
import json
import os
import shutil
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path
from typing import Any

from tornado.websocket import WebSocketClientConnection, websocket_connect

BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def find_browser() -> str | None:
    """The Chromium on PATH (None: none)."""
    return next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)


class Browser:
    """One headless Chromium with one page; use as a context manager."""

    def __init__(self, executable: str, width: int = 1500, height: int = 1100) -> None:
        self.profile = tempfile.mkdtemp(prefix="cnc-chromium-")
        self.proc = subprocess.Popen(
            [
                executable,
                "--headless=new",
                "--no-sandbox",
                "--no-first-run",
                "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader",
                "--ignore-gpu-blocklist",
                f"--window-size={width},{height}",
                "--remote-debugging-port=0",
                f"--user-data-dir={self.profile}",
                "about:blank",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        self.loop = asyncio.new_event_loop()
        self.errors: list[str] = []
        self._id = 0
        self._ws: WebSocketClientConnection | None = None
        try:
            port = self._port()
            url = self._page_socket(port)
            self._ws = self.loop.run_until_complete(self._connect(url))
            for domain in ("Page", "Runtime", "Log"):
                self.send(f"{domain}.enable")
        except BaseException:
            self.close()
            raise

    @staticmethod
    async def _connect(url: str) -> WebSocketClientConnection:
        return await websocket_connect(url, max_message_size=1 << 28)

    def _port(self) -> int:
        marker = os.path.join(self.profile, "DevToolsActivePort")
        end = time.monotonic() + 30
        while time.monotonic() < end:
            if os.path.exists(marker):
                text = Path(marker).read_text(encoding="ascii").split()
                if text:
                    return int(text[0])
            time.sleep(0.05)
        raise RuntimeError("Chromium did not open its debugging port")

    @staticmethod
    def _page_socket(port: int) -> str:
        end = time.monotonic() + 30
        while time.monotonic() < end:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list") as r:
                pages = [t for t in json.load(r) if t.get("type") == "page"]
            if pages:
                return str(pages[0]["webSocketDebuggerUrl"])
            time.sleep(0.05)
        raise RuntimeError("Chromium has no page")

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self._ws is not None:
            self._ws.close()
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.loop.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def _event(self, msg: dict[str, Any]) -> None:
        method, params = msg.get("method"), msg.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") == "error":
            self.errors.append(" ".join(str(a.get("value", a)) for a in params.get("args", [])))
        elif method == "Runtime.exceptionThrown":
            self.errors.append(json.dumps(params.get("exceptionDetails", {}))[:2000])
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            self.errors.append(str(params["entry"].get("text")))

    async def _call(self, method: str, params: dict[str, Any], timeout: float) -> dict[str, Any]:
        assert self._ws is not None
        self._id += 1
        mine = self._id
        await self._ws.write_message(json.dumps({"id": mine, "method": method, "params": params}))
        while True:
            raw = await asyncio.wait_for(self._ws.read_message(), timeout)
            if raw is None:
                raise RuntimeError("Chromium closed the connection")
            msg = json.loads(raw)
            if msg.get("id") == mine:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return dict(msg.get("result", {}))
            self._event(msg)

    def send(self, method: str, params: dict[str, Any] | None = None, timeout: float = 60) -> Any:
        """One CDP command; its result."""
        return self.loop.run_until_complete(self._call(method, params or {}, timeout))

    def pump(self, seconds: float) -> None:
        """Let the page run ``seconds``, collecting its events."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.eval("0")
            time.sleep(0.05)

    def eval(self, expr: str, timeout: float = 60) -> Any:
        """``expr`` evaluated in the page (promises awaited); its value."""
        res = self.send(
            "Runtime.evaluate",
            {"expression": expr, "returnByValue": True, "awaitPromise": True},
            timeout,
        )
        if "exceptionDetails" in res:
            raise RuntimeError(f"{expr}: {res['exceptionDetails']}")
        return res.get("result", {}).get("value")

    def open(self, url: str, ready: str = "true", timeout: float = 400) -> None:
        """Load ``url`` and wait until ``ready`` (JavaScript) is true (a page too busy to
        answer is asked again until ``timeout``)."""
        self.send("Page.navigate", {"url": url})
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                if self.eval(f"document.readyState === 'complete' && !!({ready})", 30):
                    return
            except (RuntimeError, TimeoutError):
                pass
            time.sleep(0.1)
        raise TimeoutError(f"{url}: not ready after {timeout} s ({ready})")

    def mouse(self, kind: str, x: float, y: float) -> None:
        """A mouse event at page coordinates (``mouseMoved``, ``mousePressed``, ...)."""
        params: dict[str, Any] = {"type": kind, "x": x, "y": y}
        if kind != "mouseMoved":
            params.update(button="left", clickCount=1)
        self.send("Input.dispatchMouseEvent", params)

    def screenshot(self, full_page: bool = False) -> bytes:
        """The page as PNG bytes (the whole page with ``full_page``)."""
        params: dict[str, Any] = {"format": "png"}
        if full_page:
            size = self.eval("[document.documentElement.scrollWidth, document.body.scrollHeight]")
            params["clip"] = {"x": 0, "y": 0, "width": size[0], "height": size[1], "scale": 1}
            params["captureBeyondViewport"] = True
        return base64.b64decode(self.send("Page.captureScreenshot", params)["data"])
