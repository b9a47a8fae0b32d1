"""The explorer in a browser (`jointid serve`, where `App.is_web` is true): files go to the browser, and logs come
from the server's --data folder only.

In a terminal the person at the keys owns the disk the explorer reads and
writes; in a browser the disk is the server's. So in web mode exports are
browser downloads (Textual's `deliver_text`), never files on the server, and
Ctrl+O reads only inside the folder `jointid serve --data DIR` names: every
path is resolved, symlinks followed, and refused unless it lies inside.
"""

from __future__ import annotations

import io
import os
import signal
import sys
from pathlib import Path

from textual.app import App

from jointid.cli.serve_command import DATA_ENVIRONMENT, SERVER_PID_ENVIRONMENT
from jointid.files import confine_reading, json_text, shown_path

NO_DATA_FOLDER = ("Opening logs is off in the browser: the server was started without a --data folder "
                  "(jointid serve --data DIR).")
"""What Ctrl+O says in a browser when the server names no folder."""


class OutsideDataFolder(ValueError):
    """A path that resolves outside the --data folder (str() is the one line why)."""


def data_folder() -> Path | None:
    """The folder Ctrl+O may read in a browser (resolved by `jointid serve`), or None when it named none."""
    folder = os.environ.get(DATA_ENVIRONMENT)
    return Path(folder) if folder else None


def inside(path: str | os.PathLike, folder: Path) -> str:
    """`path` (relative ones taken from `folder`) with every link resolved, if that lies in `folder`.

    Raises:
        OutsideDataFolder: the resolved path is outside `folder` (`../`, an absolute path, a symlink out).
    """
    resolved = Path(os.path.realpath(os.path.join(folder, path)))
    if resolved != folder and folder not in resolved.parents:
        raise OutsideDataFolder(f"{shown_path(path)}: outside the server's data folder; in the browser only "
                                f"logs in {shown_path(folder)} can be opened")
    return str(resolved)


def is_inside(path: str | os.PathLike, folder: Path) -> bool:
    """Whether `path` resolves into `folder` (see `inside`)."""
    try:
        inside(path, folder)
    except OutsideDataFolder:
        return False
    return True


def start_session() -> None:
    """In a session of `jointid serve` (nothing elsewhere): end with the server, and read only inside the --data
    folder from now on (jointid.files.confine_reading), whatever path a check let through."""
    end_with_server()
    folder = data_folder()
    if folder is not None:
        confine_reading(folder)


PR_SET_PDEATHSIG = 1
"""Linux's prctl option asking for a signal when the parent process ends (prctl(2))."""


def end_with_server() -> None:
    """In a session of `jointid serve`, end this explorer when its server ends, even killed outright (SIGKILL
    leaves no time to end the sessions): on Linux the kernel sends SIGTERM when the parent goes, and everywhere
    a thread watches standard input, whose other end is the server's, for its closing."""
    server = os.environ.get(SERVER_PID_ENVIRONMENT)
    if not server:
        return
    import threading

    if sys.platform.startswith("linux"):
        import ctypes

        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
        except (OSError, AttributeError):
            pass  # no prctl here: the watch below still ends the session
    if os.getppid() != int(server):  # the server went before the signal was asked for
        os.kill(os.getpid(), signal.SIGTERM)
    threading.Thread(target=_end_when_closed, args=(sys.stdin.fileno(),), name="end-with-server",
                     daemon=True).start()


def _end_when_closed(descriptor: int) -> None:
    """Wait, without reading anything, until the other end of `descriptor` closes; then end this process."""
    import select

    watch = select.poll()
    watch.register(descriptor, 0)  # no events asked: poll returns only on a hang-up or an error
    while not watch.poll():
        pass
    os.kill(os.getpid(), signal.SIGTERM)


def deliver_export(app: App, stem: str, document: dict, svg: str) -> tuple[str, str]:
    """Send the fit's JSON and the screen's SVG to the browser as two downloads; their file names."""
    names = (f"{stem}.json", f"{stem}.svg")
    app.deliver_text(io.StringIO(json_text(document)), save_filename=names[0], mime_type="application/json")
    app.deliver_text(io.StringIO(svg), save_filename=names[1], mime_type="image/svg+xml")
    return names


def deliver_report(app: App, stem: str, page: str) -> str:
    """Send the report page (Ctrl+R) to the browser as a download; its file name."""
    name = f"{stem}.html"
    app.deliver_text(io.StringIO(page), save_filename=name, mime_type="text/html")
    return name


def deliver_motion(app: App, name: str, text: str) -> None:
    """Send a designed motion file to the browser as a download."""
    app.deliver_text(io.StringIO(text), save_filename=name, mime_type="application/json")
