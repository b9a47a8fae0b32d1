"""Reading confined to one folder (a `jointid serve --data` session): no link out of it is followed, and a path
swapped between its check and its read is refused or read as checked, never read outside (issue 35)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from jointid import files
from jointid.files import FileRefused, confine_reading, open_for_reading

INSIDE = b"t,q,tau\n0,0,1\n"
OUTSIDE = b"t,q,tau\n0,0,666\n"


@pytest.fixture
def tree(tmp_path):
    """data/flip/secret.csv (inside) and outside/secret.csv; reading confined to data/ for the test."""
    data = tmp_path / "data"
    (data / "flip").mkdir(parents=True)
    (data / "flip" / "secret.csv").write_bytes(INSIDE)
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.csv").write_bytes(OUTSIDE)
    confine_reading(data)
    yield tmp_path
    confine_reading(None)


def swap_for_link(path: Path, target: Path) -> None:
    """Put a symlink to `target` where the folder or file `path` was (the attacker's move)."""
    os.rename(path, path.with_name(path.name + ".was"))
    path.symlink_to(target)


def checked_inside(path: Path, folder: Path) -> bool:
    """The web check Ctrl+O makes (tui/web.py's `inside`): the path resolved, links followed, lies in `folder`."""
    resolved = Path(os.path.realpath(path))
    return folder in resolved.parents


def test_a_folder_swapped_for_a_link_out_after_the_check_is_refused_not_read(tree):
    path = tree / "data" / "flip" / "secret.csv"
    assert checked_inside(path, tree / "data")  # the check passes: flip is a folder now
    swap_for_link(tree / "data" / "flip", tree / "outside")  # between the check and the worker's open
    with pytest.raises(FileRefused, match="symbolic link"):
        open_for_reading(path)


def test_a_swap_between_looking_at_the_file_and_opening_it_reads_what_was_looked_at_or_nothing(tree, monkeypatch):
    path = tree / "data" / "flip" / "secret.csv"
    monkeypatch.setattr(files, "before_open_hook",
                        lambda: swap_for_link(tree / "data" / "flip", tree / "outside"))
    with open_for_reading(path) as handle:  # opened from flip's own descriptor: the folder that was looked at
        assert handle.read() == INSIDE
    monkeypatch.setattr(files, "before_open_hook",
                        lambda: swap_for_link(tree / "data" / "flip.was" / "secret.csv", tree / "outside" / "secret.csv"))
    with pytest.raises(FileRefused, match="symbolic link"):
        open_for_reading(tree / "data" / "flip.was" / "secret.csv")

    def replace_file() -> None:
        (tree / "data" / "other.csv").write_bytes(OUTSIDE)
        os.replace(tree / "data" / "other.csv", tree / "data" / "flip.was" / "secret.csv.was")

    monkeypatch.setattr(files, "before_open_hook", replace_file)
    with pytest.raises(FileRefused, match="changed while it was being opened"):
        open_for_reading(tree / "data" / "flip.was" / "secret.csv.was")


def test_links_dot_dot_and_paths_outside_are_refused_even_when_they_lead_back_inside(tree):
    data = tree / "data"
    (data / "out.csv").symlink_to(tree / "outside" / "secret.csv")
    (data / "back.csv").symlink_to(data / "flip" / "secret.csv")  # the check resolves it: the read takes that
    for path in (data / "out.csv", data / "back.csv", data / ".." / "outside" / "secret.csv",
                 tree / "outside" / "secret.csv", "flip/../../outside/secret.csv"):
        with pytest.raises(FileRefused):
            open_for_reading(path)
    with open_for_reading("flip/secret.csv") as handle:  # relative paths start in the folder
        assert handle.read() == INSIDE
    os.mkfifo(data / "pipe.csv")
    with pytest.raises(FileRefused, match="named pipe"):
        open_for_reading(data / "pipe.csv")  # refused without being opened: no hang


def test_a_bag_folder_whose_storage_file_links_out_of_the_data_folder_is_not_loaded(tmp_path):
    pytest.importorskip("rosbags")
    from jointid.logs.bag import open_bag
    from jointid.logs.table import LogError
    from tests.support.bag_support import bag_path, write_joint_bag

    t = np.linspace(0, 1, 50)
    joints = {"j": (np.sin(t), np.cos(t), np.ones_like(t))}
    outside = write_joint_bag(bag_path(tmp_path / "outside", "real", "mcap"), "mcap", t, joints)
    data = tmp_path / "data"
    evil = data / "evilbag"
    evil.mkdir(parents=True)
    (evil / "metadata.yaml").write_bytes((outside / "metadata.yaml").read_bytes())
    storage = next(path for path in outside.iterdir() if path.suffix == ".mcap")
    (evil / storage.name).symlink_to(storage)
    reader = open_bag(str(evil))  # a terminal follows the user's own links
    assert reader.message_count == 50
    reader.close()
    confine_reading(data)
    try:
        with pytest.raises(LogError, match="symbolic link"):
            open_bag(str(evil))
        os.unlink(evil / storage.name)  # the metadata may not link out either
        (evil / storage.name).write_bytes(storage.read_bytes())
        os.unlink(evil / "metadata.yaml")
        (evil / "metadata.yaml").symlink_to(outside / "metadata.yaml")
        with pytest.raises(LogError, match="symbolic link"):
            open_bag(str(evil))
    finally:
        confine_reading(None)
