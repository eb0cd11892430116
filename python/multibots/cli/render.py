"""``multibots render``: export a replay to MP4 or GIF (needs the ``render`` extra)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from multibots.cli._common import finite_flag, whole_flag

#: Frames a replay may hold (docs/limits.md).
MAX_FRAMES = 1 << 40

__all__ = ["render"]


def render(
    replay: Path = typer.Argument(..., metavar="REPLAY", help="The replay (.mbr) to export."),
    out: Path = typer.Option(..., "--out", "-o", help="Output file: .mp4 or .gif."),
    fps: int = typer.Option(30, "--fps", help="Video frames per second.", parser=whole_flag("--fps", 1, 120),
                            metavar="INT"),
    start: int = typer.Option(0, "--from", help="First replay frame (step) to export.",
                              parser=whole_flag("--from", 0, MAX_FRAMES), metavar="INT"),
    end: Optional[int] = typer.Option(None, "--to", help="Last replay frame (step) to export (default: the last).",
                                      parser=whole_flag("--to", 0, MAX_FRAMES), metavar="INT"),
    scale: float = typer.Option(1.0, "--scale", help="Pixels per warehouse px (0.25 to 4).",
                                parser=finite_flag("--scale"), metavar="NUMBER"),
    every: int = typer.Option(1, "--every", help="Export every K-th step (1 = every step).",
                              parser=whole_flag("--every", 1, MAX_FRAMES), metavar="INT"),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
) -> None:
    """Export a replay to MP4 or GIF, drawn exactly as the viewer page draws it.

    Needs the 'render' extra (pip install 'multibots[render]') and a Chromium.
    """
    from multibots.render import render as export

    info = export(replay, out, fps=fps, start=start, end=end, scale=scale, every=every, progress=not quiet)
    print(f"wrote {info['path']}: {info['frames']} frames, {info['width']}x{info['height']}, {info['fps']} fps")
