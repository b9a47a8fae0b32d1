"""Designs in a child process, so an app's thread that waits for one never competes with it for the GIL.

`DesignProcess` starts one Python process the first time it runs a design and
keeps it for the next ones. The child is a plain subprocess (`python -c`, with
the parent's sys.path) rather than a multiprocessing one: it needs neither the
parent's main module nor multiprocessing's resource tracker, which cannot start
under an app that has replaced sys.stderr (Textual does). A design's progress
comes back through a pipe as it runs, its result or its failure as pickled data
(the same `DesignResult` that `design_motion` returns in process, bit for bit).
Stopping a design kills the process, which is prompt whatever the optimiser is
doing; the next design starts a fresh one. `close()` kills it too, and a child
whose parent died exits at its next progress report or when it waits for work.

The caller's thread only waits on the pipe, so an app can run
`DesignProcess.run` in a worker thread and keep its event loop free.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from .design import DesignCancelled, DesignError, DesignResult, DesignSpec, design_motion

PROGRESS_SECONDS = 1.0
"""Least time between two progress reports of the child (a start takes about 10 ms).

Each report wakes the parent's waiting thread and, in the app, repaints the progress readout; Textual paces
its next frame a 60th of a second later, so a key pressed just after one waits for it. Five reports a second
put the explorer's p95 key latency while a design runs at 2.8-4.9x its idle figure, one at 1.0-1.4x
(benchmarks/README.md, 2026-11-23)."""
POLL_SECONDS = 1.0
"""How often a waiting `run` checks its `cancelled()` callback when no report arrives (`stop()` is prompt)."""


class DesignFailed(RuntimeError):
    """The optimiser failed in its process (an exception or the process dying); the message is one line."""


def serve(requests: int, replies: int) -> None:
    """The child's loop on two pipe descriptors: take the design function, then specs; reply to each until EOF."""
    import time
    from multiprocessing.connection import Connection

    inbox, outbox = Connection(requests, writable=False), Connection(replies, readable=False)
    reported = 0.0
    try:
        function = inbox.recv()

        def progress(done: int, total: int) -> None:
            nonlocal reported
            if time.monotonic() - reported >= PROGRESS_SECONDS or done == total:
                reported = time.monotonic()
                outbox.send(("progress", done, total))  # BrokenPipeError when the parent is gone: the child ends

        while True:
            spec = inbox.recv()  # EOFError when the parent closed its end or died
            reported = -PROGRESS_SECONDS  # the first start of every design is reported
            try:
                reply = ("done", function(spec, progress=progress))
            except DesignError as error:
                reply = ("error", str(error))
            except (BrokenPipeError, EOFError):
                raise
            except Exception as error:  # noqa: BLE001 - any failure goes back to the parent as one line
                reply = ("failed", f"{type(error).__name__}: {error}".splitlines()[0])
            outbox.send(reply)
    except (BrokenPipeError, EOFError):
        return


class DesignProcess:
    """One child process that runs designs on request; `run` blocks its calling thread, `stop` kills the child."""

    def __init__(self, function: Callable[..., DesignResult] = design_motion) -> None:
        """Prepare (the process starts at the first `run`).

        Parameters
        ----------
        function
            What the child calls as ``function(spec, progress=...)``: `design_motion`, or a stand-in
            importable by name (tests).
        """
        self.function = function
        self._lock = threading.Lock()
        self._child = None
        """The live child: (subprocess.Popen, connection to it, connection from it), or None."""
        self._busy = False
        """True while a `run` uses the child."""

    @property
    def pid(self) -> int | None:
        """The child's process id while it runs, else None."""
        child = self._child
        return child[0].pid if child is not None and child[0].poll() is None else None

    def _claim(self):
        """The child for one run, starting it if needed.

        A child still busy with an earlier run (whose caller gave up on it) is killed first: its
        messages would otherwise reach this run.
        """
        with self._lock:
            if self._busy or self._child is None or self._child[0].poll() is not None:
                self._forget_and_kill()
                self._child = self._start()
            self._busy = True
            return self._child

    def _start(self):
        """Start the child: `serve` on two pipes, with this process's sys.path, output to /dev/null."""
        import os
        import subprocess
        import sys
        from multiprocessing.connection import Connection

        requests_read, requests_write = os.pipe()
        replies_read, replies_write = os.pipe()
        bootstrap = (f"import sys; sys.path[:] = {sys.path!r}; from jointid.studies.design_process import serve; "
                     f"serve({requests_read}, {replies_write})")
        try:
            # Its own session: Ctrl+C in the terminal is the parent's to handle, and the child's output
            # (warnings, a crash) never lands on an app's screen.
            process = subprocess.Popen([sys.executable, "-c", bootstrap], pass_fds=(requests_read, replies_write),
                                       stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                       stderr=subprocess.DEVNULL, start_new_session=True)
        except OSError as error:
            for descriptor in (requests_read, requests_write, replies_read, replies_write):
                os.close(descriptor)
            raise DesignFailed(f"could not start the design process: {error}") from None
        os.close(requests_read)
        os.close(replies_write)
        outbox, inbox = Connection(requests_write, readable=False), Connection(replies_read, writable=False)
        outbox.send(self.function)
        return process, outbox, inbox

    def _forget_and_kill(self) -> None:
        """Kill the child, wait for it, and forget it (callers hold the lock).

        A run waiting on the child's pipe closes that pipe itself: closing it under the run's wait could
        hand its file descriptor to the next child's pipe.
        """
        child, busy = self._child, self._busy
        self._child, self._busy = None, False
        if child is None:
            return
        process, outbox, inbox = child
        process.kill()
        process.wait()
        outbox.close()
        if not busy:
            inbox.close()

    def run(
        self,
        spec: DesignSpec,
        *,
        progress: Callable[[int, int], None] | None = None,
        cancelled: Callable[[], bool] | None = None,
    ) -> DesignResult:
        """Design in the child: `design_motion(spec)`'s result; DesignCancelled, DesignError or DesignFailed.

        `progress(done, total)` runs in the calling thread as starts finish (at most every
        PROGRESS_SECONDS, and after the last). `cancelled()` is checked at each report and every
        POLL_SECONDS; a True kills the child (DesignCancelled). `stop()` from another thread does so at once.
        """
        child = self._claim()
        process, outbox, inbox = child
        try:
            outbox.send(spec)
            while True:
                if cancelled is not None and cancelled():
                    self._stop(child)
                    raise DesignCancelled("design cancelled")
                if not inbox.poll(POLL_SECONDS):
                    continue
                message = inbox.recv()
                kind = message[0]
                if kind == "progress":
                    if progress is not None:
                        progress(message[1], message[2])
                    continue
                with self._lock:
                    if self._child is child:
                        self._busy = False  # the child waits for the next request
                if kind == "done":
                    return message[1]
                if kind == "error":
                    raise DesignError(message[1])
                raise DesignFailed(f"the optimiser failed: {message[1]}")
        except (EOFError, OSError):  # the child died: killed by stop() or a newer run, or by something else
            with self._lock:
                stopped = self._child is not child
            self._stop(child)
            if stopped or (cancelled is not None and cancelled()):
                raise DesignCancelled("design cancelled") from None
            raise DesignFailed(f"the optimiser's process stopped (exit status {process.returncode})") from None
        finally:
            with self._lock:
                if self._child is not child:  # killed: the pipe it waited on is this run's to close
                    inbox.close()

    def _stop(self, child) -> None:
        """Kill `child` if it is still the current one (a newer run may have replaced it), and wait for it."""
        with self._lock:
            if self._child is child:
                self._forget_and_kill()
                return
        child[0].kill()
        child[0].wait()

    def stop(self) -> None:
        """Kill the child: a running design stops at once (its `run` raises DesignCancelled); the next starts afresh."""
        with self._lock:
            self._forget_and_kill()

    close = stop
