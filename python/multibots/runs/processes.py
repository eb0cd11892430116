"""Worker processes for studies with Python strategies: stopped at once on Ctrl-C or an error,
and never left behind when the study's process is killed.

Python strategies run in processes (the GIL would serialise them in threads). Two things go
wrong with a plain :class:`~concurrent.futures.ProcessPoolExecutor`: a worker busy in a
strategy that spins or sleeps ignores the shutdown, so Ctrl-C waits for it (forever, for a
spin); and after ``kill -9`` of the study the workers (and the resource tracker they hold
open) keep running. :func:`process_pool` terminates the workers when its block ends early,
and each worker watches its parent and exits when the parent is gone.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor

__all__ = ["process_pool"]

#: How often a worker checks that the study's process still exists, seconds.
WATCH_INTERVAL = 0.5


def _watch_parent(parent: int) -> None:
    def watch() -> None:
        while True:
            # Re-parented (the study was killed): nobody will read our results.
            if os.getppid() != parent:
                os._exit(1)
            time.sleep(WATCH_INTERVAL)

    threading.Thread(target=watch, name="multibots-watch-parent", daemon=True).start()


@contextlib.contextmanager
def process_pool(workers: int) -> Iterator[ProcessPoolExecutor]:
    """A pool of ``workers`` spawned processes.

    When the block raises (Ctrl-C included), queued jobs are cancelled and running workers
    are terminated rather than awaited; finished results are the caller's to keep. On a normal
    exit the pool shuts down as usual.
    """
    # spawn, not fork: the parent may run a progress thread; the child gets sys.path.
    ctx = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_watch_parent,
                               initargs=(os.getpid(),))
    try:
        yield pool
    except BaseException:
        procs = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            with contextlib.suppress(Exception):
                p.terminate()
        for p in procs:
            with contextlib.suppress(Exception):
                p.join(timeout=5)
        raise
    else:
        pool.shutdown(wait=True)
