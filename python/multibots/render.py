"""Export a replay to MP4 or GIF with the viewer's own drawing code.

The page (``multibots/viewer/static``) is opened in headless Chromium in its export mode
(``?render=1``), each frame is drawn by the same ``draw.js`` the live page uses, read back
as PNG and encoded: GIF with Pillow (streamed, one fixed palette), MP4 (H.264) with the
ffmpeg that ``imageio-ffmpeg`` ships (or one on PATH). Output is written to a temporary
name and renamed when complete (``multibots._io``).

Playwright and imageio-ffmpeg come with the ``render`` extra (``pip install
'multibots[render]'``); without them :func:`render` raises :class:`MissingExtraError`.
"""

from __future__ import annotations

import base64
import io
import math
import os
import shutil
import struct
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional

from multibots import _args
from multibots._io import atomic_target, check_outputs
from multibots.exceptions import InputError, MissingExtraError, RenderError
from multibots.replay import Replay

__all__ = ["render", "RenderError", "chromium_path", "CHROMIUM_ARGS", "plan_frames"]

CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--font-render-hinting=none", "--force-color-profile=srgb"]
_BATCH = 8


def chromium_path() -> str:
    """The Chromium to drive: $MULTIBOTS_CHROMIUM, else Debian's chromium on PATH."""
    env = os.environ.get("MULTIBOTS_CHROMIUM")
    if env:
        return env
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return found
    if os.path.exists("/usr/bin/chromium"):
        return "/usr/bin/chromium"
    raise RenderError("no Chromium found: install Debian's chromium (make browser) or set MULTIBOTS_CHROMIUM")


def ffmpeg_path() -> str:
    """The ffmpeg that imageio-ffmpeg ships (the ``render`` extra), else one on PATH."""
    try:
        import imageio_ffmpeg
    except ImportError:
        imageio_ffmpeg = None
    if imageio_ffmpeg is not None:
        try:
            return imageio_ffmpeg.get_ffmpeg_exe()
        except RuntimeError:  # a platform without a bundled binary: look on PATH
            pass
    found = shutil.which("ffmpeg")
    if found:
        return found
    raise MissingExtraError("multibots render (MP4)", "render")


# ---------------------------------------------------------------------- encoders
#: Colours the page draws with (draw.js COLOURS): they always get exact palette entries.
FIXED_COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#8c8c8c", "#c51b8a", "#111111", "#ff8c00",
                 "#2b2b2b", "#ffffff", "#f1f1ec", "#1b1b1b", "#8a939c", "#1f4e9c", "#6a2c91",
                 "#ffd23f", "#6b5200", "#20242a", "#ffbf00", "#3a4048", "#b9c0c8", "#1d2228",
                 "#c9c9c2", "#000000", "#2b6cb0", "#f2c9a0", "#10243e", "#c81e1e", "#e6a000"]


def _hex(c: str) -> tuple:
    return tuple(int(c[i:i + 2], 16) for i in (1, 3, 5))


class GifWriter:
    """A streaming GIF89a writer with one global palette: the page's fixed colours (exact),
    then the first frame's most common other colours; every pixel maps to its exact colour
    when the palette has it, else to the nearest entry (no dithering, so flat colours stay
    exact). After the first frame, unchanged pixels are written as transparent and each frame
    is cropped to the region that changed, which keeps files small."""

    TRANSPARENT = 255

    def __init__(self, path: str, fps: int) -> None:
        self.fh = open(path, "wb")
        self.delay_ms = max(10, int(round(100.0 / fps)) * 10)
        self.palette: Any = None
        self.prev: Any = None
        self.prev_rgb: Any = None
        self.frames = 0

    def _build_palette(self, keys: Any, counts: Any) -> None:
        import numpy as np

        fixed = [_hex(c) for c in FIXED_COLOURS]
        fixed_keys = [(r << 16) | (g << 8) | b for r, g, b in fixed]
        order = np.argsort(-counts, kind="stable")
        chosen = list(dict.fromkeys(fixed_keys))
        for k in keys[order].tolist():
            if len(chosen) >= self.TRANSPARENT:
                break
            if k not in chosen:
                chosen.append(k)
        while len(chosen) < 256:
            chosen.append(0)
        self.palette = np.array(chosen[:256], dtype=np.int64)
        rgb = np.stack([(self.palette >> 16) & 255, (self.palette >> 8) & 255, self.palette & 255], axis=1)
        self.palette_rgb = rgb[: self.TRANSPARENT].astype(np.int32)
        self.lookup = {int(k): i for i, k in enumerate(self.palette[: self.TRANSPARENT].tolist())}

    def _indices(self, arr: Any) -> Any:
        """Palette index of every pixel, through a 2^24-entry lookup table filled lazily:
        exact colours from the palette, any other colour its nearest entry. Only pixels
        that changed since the previous frame are looked up."""
        import numpy as np

        if self.prev_rgb is not None and self.prev_rgb.shape == arr.shape:
            ne = arr != self.prev_rgb
            moved = ne[..., 0] | ne[..., 1] | ne[..., 2]
            idx = self.prev.copy()
            if moved.any():
                sub = arr[moved]
                keys = (sub[:, 0].astype(np.int32) << 16) | (sub[:, 1].astype(np.int32) << 8) | sub[:, 2]
                idx[moved] = self._lookup(keys)
            return idx
        keys = (arr[..., 0].astype(np.int32) << 16) | (arr[..., 1].astype(np.int32) << 8) | arr[..., 2]
        if self.palette is None:
            uniq, counts = np.unique(keys.ravel(), return_counts=True)
            self._build_palette(uniq, counts)
            self.lut = np.zeros(1 << 24, dtype=np.uint8)
            self.known = np.zeros(1 << 24, dtype=bool)
            for k, i in self.lookup.items():
                self.lut[k] = i
                self.known[k] = True
        return self._lookup(keys.ravel()).reshape(keys.shape)

    def _lookup(self, flat: Any) -> Any:
        import numpy as np

        new = flat[~self.known[flat]]
        if len(new):
            u = np.unique(new)
            cols = np.stack([(u >> 16) & 255, (u >> 8) & 255, u & 255], axis=1).astype(np.int32)
            for j in range(0, len(u), 4096):
                d = ((cols[j:j + 4096, None, :] - self.palette_rgb[None, :, :]) ** 2).sum(axis=2)
                self.lut[u[j:j + 4096]] = d.argmin(axis=1).astype(np.uint8)
            self.known[u] = True
        return self.lut[flat]

    def add(self, im: Any) -> None:
        import numpy as np
        from PIL import GifImagePlugin, Image

        arr = np.asarray(im.convert("RGB"))
        first = self.palette is None
        idx = self._indices(arr)
        if first:
            h, w = idx.shape
            self.size = (w, h)
            flat = bytes(np.stack([(self.palette >> 16) & 255, (self.palette >> 8) & 255,
                                   self.palette & 255], axis=1).astype(np.uint8).ravel())
            self.fh.write(b"GIF89a" + struct.pack("<HHBBB", w, h, 0xF7, 0, 0) + flat)
            self.fh.write(b"!\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00")  # loop forever
        if (idx.shape[1], idx.shape[0]) != self.size:
            raise RenderError(f"frame size changed from {self.size} to {(idx.shape[1], idx.shape[0])}")
        params: Dict[str, Any] = {"duration": self.delay_ms}
        x0 = y0 = 0
        part = idx
        if self.prev is not None:
            changed = idx != self.prev
            rows = np.flatnonzero(changed.max(axis=1))
            if len(rows):
                cols = np.flatnonzero(changed[rows[0]:rows[-1] + 1].max(axis=0))
                y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
            else:
                y0, y1, x0, x1 = 0, 1, 0, 1
            part = np.where(changed[y0:y1, x0:x1], idx[y0:y1, x0:x1], self.TRANSPARENT).astype(np.uint8)
            params.update(transparency=self.TRANSPARENT, disposal=1)
        self.prev = idx
        self.prev_rgb = arr
        img = Image.frombytes("P", (part.shape[1], part.shape[0]), part.tobytes())
        for chunk in GifImagePlugin.getdata(img, offset=(x0, y0), **params):
            self.fh.write(chunk)
        self.frames += 1

    def close(self) -> None:
        if not self.fh.closed:
            self.fh.write(b";")
            self.fh.close()

    def abort(self) -> None:
        if not self.fh.closed:
            self.fh.close()


class Mp4Writer:
    """H.264 in MP4 through an ffmpeg subprocess reading raw RGB frames from a pipe."""

    def __init__(self, path: str, fps: int) -> None:
        self.path = path
        self.fps = fps
        self.proc: Optional[subprocess.Popen] = None
        self.frames = 0

    def add(self, im: Any) -> None:
        rgb = im.convert("RGB")
        if self.proc is None:
            w, h = rgb.size
            self.size = rgb.size
            cmd = [ffmpeg_path(), "-hide_banner", "-loglevel", "error", "-y",
                   "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}", "-r", str(self.fps), "-i", "-",
                   "-an", "-c:v", "libx264", "-preset", "medium", "-crf", "18", "-pix_fmt", "yuv420p",
                   "-threads", "1", "-movflags", "+faststart", "-map_metadata", "-1",
                   "-fflags", "+bitexact", "-flags:v", "+bitexact", "-f", "mp4", self.path]
            self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                         stderr=subprocess.PIPE)
        if rgb.size != self.size:
            raise RenderError(f"frame size changed from {self.size} to {rgb.size}")
        try:
            self.proc.stdin.write(rgb.tobytes())  # type: ignore[union-attr]
        except BrokenPipeError:
            raise RenderError("ffmpeg stopped: " + self._stderr()) from None
        self.frames += 1

    def _stderr(self) -> str:
        if self.proc is None or self.proc.stderr is None:
            return ""
        err = self.proc.stderr.read().decode("utf-8", "replace").strip()
        return err.splitlines()[-1] if err else f"exit code {self.proc.returncode}"

    def close(self) -> None:
        if self.proc is None:
            raise RenderError("no frames to encode")
        self.proc.stdin.close()  # type: ignore[union-attr]
        code = self.proc.wait()
        if code != 0:
            raise RenderError("ffmpeg failed: " + self._stderr())

    def abort(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


# ---------------------------------------------------------------------- export
def plan_frames(frames: int, start: int = 0, end: Optional[int] = None, every: int = 1) -> List[int]:
    """The replay frames an export holds: start, start+every, ... up to end (inclusive)."""
    last = frames - 1
    end = last if end is None else end
    if not 0 <= start <= last:
        raise InputError(f"--from {start}: must be from 0 to {last} (the replay's last frame)")
    if not start <= end <= last:
        raise InputError(f"--to {end}: must be from {start} (--from) to {last} (the replay's last frame)")
    if every < 1:
        raise InputError(f"--every {every}: must be at least 1")
    return list(range(start, end + 1, every))


def _loop_running() -> bool:
    import asyncio

    try:
        asyncio.get_running_loop()
        return True
    except RuntimeError:
        return False


def render(replay: "os.PathLike[str] | str", out: "os.PathLike[str] | str", fps: int = 30, start: int = 0,
           end: Optional[int] = None, scale: float = 1.0, every: int = 1, progress: bool = True,
           on_frame: Optional[Callable[[int, int], None]] = None) -> Dict[str, Any]:
    """Export ``replay`` to ``out`` (.mp4 or .gif). Returns {path, frames, width, height, fps,
    origin, scale}: ``origin`` and ``scale`` map warehouse px to image pixels.

    Raises ReplayError for an unreadable replay, InputError (a ValueError) for bad options,
    MissingExtraError without the ``render`` extra and RenderError when the browser or encoder
    cannot run; all are :class:`multibots.MultibotsError`. Safe to call where an asyncio loop (or another
    Playwright session) is running: the browser is then driven from a worker thread.
    """
    kw = dict(fps=fps, start=start, end=end, scale=scale, every=every, progress=progress, on_frame=on_frame)
    if not _loop_running():
        return _render(replay, out, **kw)
    import threading

    box: Dict[str, Any] = {}

    def work() -> None:
        try:
            box["result"] = _render(replay, out, **kw)
        except BaseException as exc:  # re-raised in the caller's thread
            box["error"] = exc

    t = threading.Thread(target=work, name="multibots-render")
    t.start()
    t.join()
    if "error" in box:
        raise box["error"]
    return box["result"]


def _render(replay: "os.PathLike[str] | str", out: "os.PathLike[str] | str", fps: int = 30, start: int = 0,
           end: Optional[int] = None, scale: float = 1.0, every: int = 1, progress: bool = True,
           on_frame: Optional[Callable[[int, int], None]] = None) -> Dict[str, Any]:
    replay = _args.path("replay", replay)  # type: ignore[assignment]
    out = _args.path("out", out)  # type: ignore[assignment]
    kind = out.suffix.lower()
    if kind not in (".mp4", ".gif"):
        raise InputError(f"--out {out}: the file name must end in .mp4 or .gif")
    if not isinstance(fps, int) or not 1 <= fps <= 120:
        raise InputError(f"--fps {fps}: must be a whole number from 1 to 120")
    if not (isinstance(scale, (int, float)) and math.isfinite(scale) and 0.25 <= scale <= 4):
        raise InputError(f"--scale {scale}: must be from 0.25 to 4")
    if out.parent and not out.parent.exists():
        raise InputError(f"--out {out}: the folder {out.parent} does not exist")
    check_outputs([("out", out)], [("replay", Path(replay))])
    with Replay(replay) as rp:
        frames = plan_frames(rp.frames, start, end, every)
    if kind == ".mp4":
        ffmpeg_path()  # fail early, before starting a browser
    try:
        import playwright.sync_api  # noqa: F401 - checked here, used by _draw
    except ImportError:
        raise MissingExtraError("multibots render", "render") from None
    exe = chromium_path()
    blink_every = max(1, round(fps * 0.4)) * every
    bar = _progress(len(frames), str(out)) if progress else None
    try:
        with atomic_target(out, suffix=f".partial{kind}") as tmp:
            writer: Any = GifWriter(str(tmp), fps) if kind == ".gif" else Mp4Writer(str(tmp), fps)
            try:
                size, origin = _draw(replay, exe, scale, frames, blink_every, writer, bar, on_frame)
                writer.close()
            except BaseException:
                writer.abort()
                raise
    finally:
        if bar:
            bar.close()
    return {"path": str(out), "frames": len(frames), "width": size["width"], "height": size["height"], "fps": fps,
            "origin": (origin["x"], origin["y"]), "scale": origin["scale"]}


def _draw(replay: "os.PathLike[str] | str", exe: str, scale: float, frames: List[int], blink_every: int,
          writer: Any, bar: Any, on_frame: Optional[Callable[[int, int], None]]) -> Any:
    """Draws every frame in the page and hands it to ``writer``; returns (size, origin)."""
    from PIL import Image
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import sync_playwright

    from multibots.viewer.server import Viewer

    with Viewer.for_replay(str(replay), host="127.0.0.1", port=0) as viewer:
        with sync_playwright() as pw:
            try:
                browser = pw.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
            except PlaywrightError as exc:
                raise RenderError(f"cannot start Chromium at {exe}: {str(exc).splitlines()[0]}") from None
            try:
                page = browser.new_page(viewport={"width": 800, "height": 600}, device_scale_factor=1)
                errors: List[str] = []
                page.on("pageerror", lambda e: errors.append(str(e)))
                page.goto(f"{viewer.url}?render=1&scale={scale:g}")
                page.wait_for_function("() => window.mbViewer && window.mbViewer.ready", timeout=60000)
                size = page.evaluate("() => window.mbViewer.size()")
                origin = page.evaluate("() => window.mbViewer.worldToClient(0, 0)")
                done = 0

                def decode(url: str) -> Any:
                    with Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))) as im:
                        return im.convert("RGB")

                def consume(futures: List[Any]) -> None:
                    nonlocal done
                    for fut in futures:
                        writer.add(fut.result())
                        done += 1
                        if bar:
                            bar.advance()
                        if on_frame:
                            on_frame(done, len(frames))

                # PNGs are decoded in worker threads while the browser draws the next batch
                with ThreadPoolExecutor(max_workers=2) as pool:
                    pending: List[Any] = []
                    for b in range(0, len(frames), _BATCH):
                        batch = frames[b:b + _BATCH]
                        urls = page.evaluate("([f, k]) => window.mbViewer.renderFrames(f, k)",
                                             [batch, blink_every])
                        if errors:
                            raise RenderError(f"the page failed: {errors[0]}")
                        consume(pending)
                        pending = [pool.submit(decode, u) for u in urls]
                    consume(pending)
            finally:
                browser.close()
    return size, origin


class _progress:
    def __init__(self, total: int, label: str) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        self.p = Progress(TextColumn("[bold]render[/bold] {task.description}"), BarColumn(),
                          MofNCompleteColumn(), TimeRemainingColumn(), console=Console(stderr=True))
        self.p.start()
        self.task = self.p.add_task(label, total=total)

    def advance(self) -> None:
        self.p.advance(self.task)

    def close(self) -> None:
        self.p.stop()
