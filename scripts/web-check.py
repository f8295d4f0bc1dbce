#!/usr/bin/env python3
"""Runs the spvg demo page's check in headless Chromium and saves a screenshot.

Started by scripts/web-check.sh, which builds and serves the page. Chromium runs
headless with WebGPU on SwiftShader, its console on stderr (saved to --log), and is
driven over the DevTools protocol on a pipe (--remote-debugging-pipe; the standard
library only): open URL, print the page's console lines, wait for the line that starts
with "SPVG-WEB " (PASS or FAIL), capture the whole page as a PNG, close.

With --first-run URL, the browser first opens that page (the interactive page, a fresh
profile, so nothing cached) and waits for its first-run line, "spvg-web: first frame
shown N ms after page load", before it opens the check. The check's own first frame comes
after it converges its reference, so it is not the page's first-run time. Both lines are
repeated at the end.

Exit status: 0 when the line says PASS, 1 on FAIL, a timeout, or a browser that ends
early.
"""

import argparse
import base64
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import time


class Browser:
    """Chromium with the DevTools protocol on fds 3 (commands in) and 4 (replies out)."""

    def __init__(self, chromium, width, height, log):
        self.profile = tempfile.mkdtemp(prefix="spvg-web-chromium-")
        cmd_r, self.cmd_w = os.pipe()
        self.out_r, out_w = os.pipe()
        flags = [
            "--headless=new",
            "--no-sandbox",
            "--enable-unsafe-webgpu",
            "--use-webgpu-adapter=swiftshader",
            "--enable-logging=stderr",
            f"--user-data-dir={self.profile}",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            f"--window-size={width},{height}",
            "--remote-debugging-pipe",
            "about:blank",
        ]
        # The protocol's pipe is fds 3 and 4 of the browser; bash puts them there.
        script = 'exec "$0" "$@" 3<&{} 4>&{}'.format(cmd_r, out_w)
        self.proc = subprocess.Popen(
            ["bash", "-c", script, chromium, *flags],
            pass_fds=(cmd_r, out_w),
            stdout=log,
            stderr=log,
        )
        os.close(cmd_r)
        os.close(out_w)
        self.buffer = b""
        self.next_id = 0
        self.events = []

    def _read(self, deadline):
        """The next message from the browser; None once the pipe closes."""
        while b"\0" not in self.buffer:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError
            ready, _, _ = select.select([self.out_r], [], [], remaining)
            if not ready:
                raise TimeoutError
            chunk = os.read(self.out_r, 1 << 16)
            if not chunk:
                return None
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, params=None, session=None, timeout=60):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.cmd_w, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            reply = self._read(deadline)
            if reply is None:
                raise RuntimeError(f"the browser ended during {method}")
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def event(self, deadline):
        if self.events:
            return self.events.pop(0)
        return self._read(deadline)

    def close(self):
        try:
            self.call("Browser.close", timeout=10)
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


def console_text(event):
    """The text of a console call or an uncaught exception; None for other events."""
    method = event.get("method")
    params = event.get("params", {})
    if method == "Runtime.consoleAPICalled":
        return " ".join(
            str(a.get("value", a.get("description", ""))) for a in params.get("args", [])
        )
    if method == "Runtime.exceptionThrown":
        details = params.get("exceptionDetails", {})
        exception = details.get("exception", {})
        return "uncaught: " + exception.get("description", details.get("text", ""))
    return None


def is_error(event):
    """Whether an event is an uncaught exception or a console.error call."""
    method = event.get("method")
    if method == "Runtime.exceptionThrown":
        return True
    return (
        method == "Runtime.consoleAPICalled"
        and event.get("params", {}).get("type") == "error"
    )


# Seconds the first-run page gets to show its first frame.
FIRST_RUN_TIMEOUT = 180


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("url")
    parser.add_argument("--chromium", default="chromium")
    parser.add_argument("--screenshot", help="the PNG to write")
    parser.add_argument("--log", default=os.devnull, help="Chromium's stderr goes here")
    parser.add_argument("--timeout", type=float, default=900.0)
    parser.add_argument("--first-run", help="a page to time to its first frame first")
    parser.add_argument("--width", type=int, default=1000)
    parser.add_argument("--height", type=int, default=620)
    args = parser.parse_args()

    start = time.monotonic()
    with open(args.log, "wb") as log:
        browser = Browser(args.chromium, args.width, args.height, log)
        verdict = None
        first_frame = None
        first_run = None
        try:
            targets = browser.call("Target.getTargets")["targetInfos"]
            page = next(t["targetId"] for t in targets if t["type"] == "page")
            session = browser.call(
                "Target.attachToTarget", {"targetId": page, "flatten": True}
            )["sessionId"]
            browser.call("Runtime.enable", session=session)
            browser.call("Page.enable", session=session)
            browser.call(
                "Emulation.setDeviceMetricsOverride",
                {
                    "width": args.width,
                    "height": args.height,
                    "deviceScaleFactor": 1,
                    "mobile": False,
                },
                session=session,
            )
            deadline = start + args.timeout
            if args.first_run:
                # Bounded on its own: a page that fails or stalls here costs the check at
                # most FIRST_RUN_TIMEOUT s, and the check still runs (and judges).
                browser.call("Page.navigate", {"url": args.first_run}, session=session)
                first_deadline = min(deadline, time.monotonic() + FIRST_RUN_TIMEOUT)
                try:
                    while first_run is None:
                        event = browser.event(first_deadline)
                        if event is None:
                            break
                        text = console_text(event)
                        if text is None:
                            continue
                        print(f"page (first run): {text}", flush=True)
                        if text.startswith("spvg-web: first frame shown "):
                            first_run = text[len("spvg-web: ") :]
                        elif is_error(event):
                            break
                except TimeoutError:
                    print(
                        f"web-check: no first frame from {args.first_run} within "
                        f"{FIRST_RUN_TIMEOUT} s",
                        flush=True,
                    )
            browser.call("Page.navigate", {"url": args.url}, session=session)
            while verdict is None:
                event = browser.event(deadline)
                if event is None:
                    print("web-check: the browser ended before the page's verdict", flush=True)
                    break
                text = console_text(event)
                if text is None:
                    continue
                print(f"page: {text}", flush=True)
                if text.startswith("spvg-web: first frame shown "):
                    first_frame = text[len("spvg-web: ") :]
                if text.startswith("SPVG-WEB "):
                    verdict = text
            if verdict is not None and args.screenshot:
                # The whole page, not only the window: the frame-time graph and the
                # stats sit below the panels.
                size = browser.call("Page.getLayoutMetrics", session=session)["cssContentSize"]
                shot = browser.call(
                    "Page.captureScreenshot",
                    {
                        "format": "png",
                        "captureBeyondViewport": True,
                        "clip": {
                            "x": 0,
                            "y": 0,
                            "width": size["width"],
                            "height": size["height"],
                            "scale": 1,
                        },
                    },
                    session=session,
                )
                os.makedirs(os.path.dirname(os.path.abspath(args.screenshot)), exist_ok=True)
                with open(args.screenshot, "wb") as f:
                    f.write(base64.b64decode(shot["data"]))
                print(f"web-check: screenshot {args.screenshot}", flush=True)
        except TimeoutError:
            print(f"web-check: no verdict within {args.timeout:.0f} s", flush=True)
        finally:
            browser.close()
    elapsed = time.monotonic() - start
    if first_run is not None:
        print(f"web-check: first run (the interactive page): {first_run}", flush=True)
    if first_frame is not None:
        print(f"web-check: in the check (after its reference): {first_frame}", flush=True)
    print(f"web-check: browser run {elapsed:.1f} s", flush=True)
    return 0 if verdict is not None and verdict.startswith("SPVG-WEB PASS ") else 1


if __name__ == "__main__":
    sys.exit(main())
