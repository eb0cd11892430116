"""``multibots view`` and ``multibots render``: added to the main typer app by ``register(app)``."""

from __future__ import annotations

import errno
import ipaddress
import os
import sys
import threading
import webbrowser
from pathlib import Path
from typing import List, Optional

import typer

DEFAULT_PORT = 8765


def _fail(message: str, code: int = 2) -> "typer.Exit":
    """Print a one-line error to stderr; the caller raises the returned Exit."""
    line = " ".join(str(message).split())
    print(f"multibots: error: {line}", file=sys.stderr)
    return typer.Exit(code)


def _parse_cells(value: str, flag: str) -> List[int]:
    items = [v.strip() for v in value.split(",")]
    if not items or any(not v or not v.lstrip("-").isdigit() for v in items):
        raise _fail(f"{flag} {value!r}: expected comma-separated cell ids, such as 11,8,39")
    return [int(v) for v in items]


def _parse_names(value: str, flag: str) -> List[str]:
    items = [v.strip() for v in value.split(",")]
    if not items or any(not v for v in items):
        raise _fail(f"{flag} {value!r}: expected comma-separated node names, such as A,B,C")
    return items


def _check_host(host: str) -> str:
    if host == "localhost":
        return "127.0.0.1"
    try:
        ipaddress.ip_address(host)
    except ValueError:
        raise _fail(f"--host {host!r}: expected an IP address such as 127.0.0.1") from None
    return host


def _has_display() -> bool:
    """A graphical browser can be opened here (not a text browser in this terminal)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def _open_browser(url: str, port: int) -> None:
    if not _has_display():
        print(f"  no display here: open the URL in a browser; from another machine, forward the port"
              f" first (ssh -L {port}:127.0.0.1:{port} THIS-HOST)", flush=True)
        return

    def go() -> None:
        try:
            webbrowser.open(url, new=2)
        except Exception:  # no browser is not an error: the URL is printed
            pass

    threading.Thread(target=go, daemon=True).start()


def _make_viewer(factory, host: str, port: Optional[int]):  # type: ignore[no-untyped-def]
    """Bind the requested port; the default port falls back to a free one if taken."""
    try:
        return factory(host=host, port=DEFAULT_PORT if port is None else port)
    except OSError as exc:
        if port is None and exc.errno in (errno.EADDRINUSE, errno.EACCES):
            return factory(host=host, port=0)
        raise _fail(f"--port {port if port is not None else DEFAULT_PORT}: cannot listen on {host} ({exc.strerror})") from None


def _stop_on_sigterm() -> None:
    """`kill` stops the server as Ctrl-C does (cleanly, exit code 0)."""
    import signal

    def handler(signum, frame):  # type: ignore[no-untyped-def]
        raise KeyboardInterrupt

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, handler)


def _serve(viewer, what: str, no_browser: bool) -> None:  # type: ignore[no-untyped-def]
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


def register(app: typer.Typer) -> None:
    """Add the ``view`` and ``render`` commands to ``app``."""

    @app.command("view")
    def view(
        path: Optional[Path] = typer.Argument(
            None, metavar="REPLAY|SCENARIO", show_default=False,
            help="A replay (.mbr) to play, or with --live a scenario (.toml) to run."),
        live: bool = typer.Option(False, "--live", help="Run a simulation and stream it to the page."),
        port: Optional[int] = typer.Option(None, "--port", help=f"Port to listen on (default {DEFAULT_PORT}, or a free one if taken)."),
        host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on. Only change it if you mean to share the viewer."),
        no_browser: bool = typer.Option(False, "--no-browser", help="Print the URL; do not open a browser."),
        allow_host: List[str] = typer.Option([], "--allow-host", help="Also accept this Host name (behind a proxy that renames the host, such as a cloud IDE's port forwarding); repeatable.", show_default=False),
        speed: float = typer.Option(1.0, "--speed", help="Live: starting speed, 0.25 to 64 (1x = 30 steps per second)."),
        paused: bool = typer.Option(False, "--paused", help="Live: start paused."),
        robots: Optional[int] = typer.Option(None, "--robots", help="Live quick run: number of robots."),
        goods: Optional[str] = typer.Option(None, "--goods", help="Live quick run: cells to fetch, in order, e.g. 11,8,39."),
        starts: Optional[str] = typer.Option(None, "--starts", help="Live quick run: start nodes, e.g. A,B,C."),
        unload: Optional[str] = typer.Option(None, "--unload", help="Live quick run: the unloading zone (default M).", show_default=False),
        margin: Optional[float] = typer.Option(None, "--margin", help="Live quick run: collision margin, px (default 0).", show_default=False),
        step_limit: Optional[int] = typer.Option(None, "--step-limit", help="Live quick run: step limit (default 100000).", show_default=False),
    ) -> None:
        """Watch a run in the browser: a recorded replay, or --live a simulation as it runs."""
        host = _check_host(host)
        if port is not None and not 0 <= port <= 65535:
            raise _fail(f"--port {port}: must be from 0 to 65535")
        from .server import Viewer

        if not live:
            quick = [robots, goods, starts, unload, margin, step_limit]
            if any(v is not None for v in quick):
                raise _fail("--robots, --goods, --starts, --unload, --margin and --step-limit need --live")
            if path is None:
                raise _fail("give a REPLAY file to play, or --live with a SCENARIO.toml or --robots/--goods")
            from ..replay import Replay, ReplayError

            try:
                Replay(path).close()  # check it before binding anything
            except ReplayError as exc:
                hint = " (to run a scenario, add --live)" if str(path).endswith(".toml") else ""
                raise _fail(f"{exc}{hint}") from None
            viewer = _make_viewer(lambda **kw: Viewer.for_replay(str(path), allow_hosts=tuple(allow_host), **kw),
                                  host, port)
            _serve(viewer, f"replay {path}", no_browser)
            return

        if not 0.25 <= speed <= 64:
            raise _fail(f"--speed {speed}: must be from 0.25 to 64")
        sim, name = _live_simulation(path, robots, goods, starts, unload, margin, step_limit)
        viewer = _make_viewer(
            lambda **kw: Viewer.for_simulation(sim, name=name, speed=speed, paused=paused,
                                               allow_hosts=tuple(allow_host), **kw), host, port)
        _serve(viewer, name, no_browser)

    @app.command("render")
    def render_cmd(
        replay: Path = typer.Argument(..., metavar="REPLAY", help="The replay (.mbr) to export."),
        out: Path = typer.Option(..., "--out", "-o", help="Output file: .mp4 or .gif."),
        fps: int = typer.Option(30, "--fps", help="Video frames per second."),
        start: int = typer.Option(0, "--from", help="First replay frame (step) to export."),
        end: Optional[int] = typer.Option(None, "--to", help="Last replay frame (step) to export (default: the last)."),
        scale: float = typer.Option(1.0, "--scale", help="Pixels per warehouse px (0.25 to 4)."),
        every: int = typer.Option(1, "--every", help="Export every K-th step (1 = every step)."),
        quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
    ) -> None:
        """Export a replay to MP4 or GIF, drawn exactly as the viewer page draws it."""
        from ..render import RenderError, render
        from ..replay import ReplayError

        try:
            info = render(replay, out, fps=fps, start=start, end=end, scale=scale, every=every,
                          progress=not quiet)
        except (ReplayError, ValueError) as exc:
            raise _fail(str(exc)) from None
        except RenderError as exc:
            raise _fail(str(exc), code=1) from None
        print(f"wrote {info['path']}: {info['frames']} frames, {info['width']}x{info['height']}, {info['fps']} fps")


def _live_simulation(path, robots, goods, starts, unload, margin, step_limit):  # type: ignore[no-untyped-def]
    """The Simulation to stream: a scenario file, the quick-run flags of `multibots run`, or a
    file with flags on top (the same rules as `run`)."""
    import multibots

    errors = (getattr(multibots, "MultibotsError", ValueError), ValueError)
    if path is not None and not Path(path).is_file():
        raise _fail(f"{path}: no such scenario file")
    if robots is not None and robots < 1:
        raise _fail(f"--robots {robots}: must be at least 1")
    if step_limit is not None and step_limit < 1:
        raise _fail(f"--step-limit {step_limit}: must be at least 1")
    if margin is not None and not margin >= 0:
        raise _fail(f"--margin {margin}: must be 0 or more")
    try:
        try:
            from ..cli import BadInput, quick_scenario
        except ImportError:  # the main CLI is not there: build the scenario here
            BadInput, quick_scenario = ValueError, _quick_scenario
        try:
            scenario = quick_scenario(None if path is None else Path(path), robots, goods, starts, unload,
                                      margin, step_limit)
        except BadInput as exc:
            raise _fail(str(exc)) from None
        if path is not None:
            name = f"live: {Path(path).name}"
        else:
            try:
                d = scenario.to_dict()
                name = f"live: {d.get('layout', 'paper')}, {d.get('robots')} robots, {len(d.get('tasks') or [])} goods"
            except Exception:
                name = "live"
        sim = multibots.Simulation(scenario)
    except typer.Exit:
        raise
    except errors as exc:
        raise _fail(str(exc)) from None
    except OSError as exc:
        raise _fail(f"{path}: {exc.strerror}") from None
    return sim, name


def _quick_scenario(path, robots, goods, starts, unload, margin, step_limit):  # type: ignore[no-untyped-def]
    import multibots

    if path is not None:
        if any(v is not None for v in (robots, goods, starts, unload, margin, step_limit)):
            raise ValueError("give either a SCENARIO.toml or the quick-run flags, not both")
        return multibots.Scenario.from_toml(str(path))
    if goods is None:
        raise ValueError("--live needs a SCENARIO.toml or the quick-run flags (at least --goods)")
    kw = dict(robots=3 if robots is None else robots, goods=_parse_cells(goods, "--goods"))
    if starts is not None:
        kw["starts"] = _parse_names(starts, "--starts")
    if unload is not None:
        kw["unload"] = unload
    if margin is not None:
        kw["margin"] = margin
    if step_limit is not None:
        kw["step_limit"] = step_limit
    return multibots.Scenario.paper(**kw)
