"""``multibots view``: watch a recorded replay, or ``--live`` a run as it happens, in the browser."""

from __future__ import annotations

import errno
import ipaddress
import os
import signal
import sys
import threading
import webbrowser
from pathlib import Path
from typing import Any, Callable, List, Optional

import typer

from multibots.cli._common import (
    ALLOW_CODE,
    GOODS,
    MARGIN,
    ROBOTS,
    RULES,
    STARTS,
    STEP_LIMIT,
    TRAFFIC,
    UNLOAD,
    check_code,
    finite_flag,
    quick_scenario,
    whole_flag,
)
from multibots.exceptions import InputError, ReplayError

__all__ = ["DEFAULT_PORT", "view"]

DEFAULT_PORT = 8765


def view(
    path: Optional[Path] = typer.Argument(
        None, metavar="REPLAY|SCENARIO", show_default=False,
        help="A replay (.mbr) to play, or with --live a scenario (.toml) to run.",
    ),
    live: bool = typer.Option(False, "--live", help="Run a simulation and stream it to the page."),
    port: Optional[int] = typer.Option(
        None, "--port", help=f"Port to listen on (default {DEFAULT_PORT}, or a free one if taken).",
        parser=whole_flag("--port", 0, 65535), metavar="INT",
    ),
    host: str = typer.Option(
        "127.0.0.1", "--host", metavar="ADDRESS",
        help="Address to listen on. Only change it if you mean to share the viewer."
    ),
    no_browser: bool = typer.Option(False, "--no-browser", help="Print the URL; do not open a browser."),
    allow_host: List[str] = typer.Option(
        [], "--allow-host", show_default=False,
        help="Also accept this Host name (behind a proxy that renames the host, such as a cloud IDE's port "
        "forwarding); repeatable.",
    ),
    speed: float = typer.Option(1.0, "--speed", help="Live: starting speed, 0.25 to 64 (1x = 30 steps per second).",
                                parser=finite_flag("--speed"), metavar="NUMBER"),
    paused: bool = typer.Option(False, "--paused", help="Live: start paused."),
    robots: Optional[str] = ROBOTS,
    goods: Optional[str] = GOODS,
    starts: Optional[str] = STARTS,
    unload: Optional[str] = UNLOAD,
    margin: Optional[str] = MARGIN,
    step_limit: Optional[str] = STEP_LIMIT,
    rules: Optional[str] = RULES,
    traffic: Optional[str] = TRAFFIC,
    allow_code: bool = ALLOW_CODE,
) -> None:
    """Watch a run in the browser: a recorded replay, or --live a simulation as it runs."""
    host = _check_host(host)
    if port is not None and not 0 <= port <= 65535:
        raise InputError(f"--port {port}: must be from 0 to 65535")
    from multibots.viewer.server import Viewer

    if not live:
        quick = [robots, goods, starts, unload, margin, step_limit]
        if any(v is not None for v in quick):
            raise InputError("--robots, --goods, --starts, --unload, --margin and --step-limit need --live")
        if path is None:
            raise InputError("give a REPLAY file to play, or --live with a SCENARIO.toml or --robots/--goods")
        from multibots.replay import Replay
        from multibots.viewer.server import ReplaySource

        try:
            # Opened once, checked before binding anything, and served as opened: the path is
            # not looked up again (a file put in its place later is not served).
            replay = Replay(path)
        except ReplayError as exc:
            hint = " (to run a scenario, add --live)" if str(path).endswith(".toml") else ""
            raise ReplayError(f"{exc}{hint}") from None
        try:
            viewer = _make_viewer(
                lambda **kw: Viewer(ReplaySource(replay), allow_hosts=tuple(allow_host), **kw), host, port
            )
        except BaseException:
            replay.close()
            raise
        _serve(viewer, f"replay {path}", no_browser)
        return

    if not 0.25 <= speed <= 64:
        raise InputError(f"--speed {speed}: must be from 0.25 to 64")
    sim, name = _live_simulation(path, robots, goods, starts, unload, margin, step_limit, rules, traffic, allow_code)
    viewer = _make_viewer(
        lambda **kw: Viewer.for_simulation(
            sim, name=name, speed=speed, paused=paused, allow_hosts=tuple(allow_host), **kw
        ),
        host,
        port,
    )
    _serve(viewer, name, no_browser)


def _check_host(host: str) -> str:
    if host == "localhost":
        return "127.0.0.1"
    try:
        ipaddress.ip_address(host)
    except ValueError:
        raise InputError(f"--host {host!r}: expected an IP address such as 127.0.0.1") from None
    return host


def _live_simulation(
    path: Optional[Path], robots: Optional[str], goods: Optional[str], starts: Optional[str],
    unload: Optional[str], margin: Optional[str], step_limit: Optional[str], rules: Optional[str] = None,
    traffic: Optional[str] = None, allow_code: bool = False,
) -> tuple[Any, str]:
    """The Simulation to stream, built by the rules of ``multibots run``, and its name."""
    from multibots.simulation import Simulation

    check_code(path, allow_code)
    scenario = quick_scenario(path, robots, goods, starts, unload, margin, step_limit, rules, traffic)
    if path is not None:
        name = f"live: {path.name}"
    else:
        d = scenario.to_dict()
        layout = d["layout"] if isinstance(d["layout"], str) else "layout"
        name = f"live: {layout}, {d['robots']} robots, {len(scenario.cells)} goods"
    return Simulation(scenario), name


def _has_display() -> bool:
    """A graphical browser can be opened here (not a text browser in this terminal)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def _open_browser(url: str, port: int) -> None:
    if not _has_display():
        print(
            f"  no display here: open the URL in a browser; from another machine, forward the port"
            f" first (ssh -L {port}:127.0.0.1:{port} THIS-HOST)",
            flush=True,
        )
        return

    def go() -> None:
        try:
            webbrowser.open(url, new=2)
        except Exception:
            pass

    threading.Thread(target=go, daemon=True).start()


def _make_viewer(factory: Callable[..., Any], host: str, port: Optional[int]) -> Any:
    """Binds the requested port; the default port falls back to a free one if taken."""
    try:
        return factory(host=host, port=DEFAULT_PORT if port is None else port)
    except OSError as exc:
        if port is None and exc.errno in (errno.EADDRINUSE, errno.EACCES):
            return factory(host=host, port=0)
        shown = port if port is not None else DEFAULT_PORT
        raise InputError(f"--port {shown}: cannot listen on {host} ({exc.strerror})") from None


def _stop_on_sigterm() -> None:
    """`kill` stops the server as Ctrl-C does (cleanly, exit code 0)."""

    def handler(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, handler)


def _serve(viewer: Any, what: str, no_browser: bool) -> None:
    _stop_on_sigterm()
    try:
        url = viewer.url
        print(f"MultiBots viewer: {what}")
        print(f"  {url}   (Ctrl-C to stop)", flush=True)
        if viewer.host not in ("127.0.0.1", "::1", "localhost"):
            print(f"  note: listening on {viewer.host}, not only this machine", file=sys.stderr)
        if not no_browser:
            _open_browser(url, viewer.port)
        viewer.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        viewer.close()
