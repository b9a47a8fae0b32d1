"""The command line's printed output: complete through a pipe, one line (status 2) when it cannot be
written, and nothing at all when its reader has gone; a subcommand's process ends without the
interpreter's teardown."""

from __future__ import annotations

import errno
import io
import json
import os
import subprocess
import sys

import pytest

from jointid.cli import main

FULL_DISK = "jointid: cannot write the output: No space left on device"

BUFFERED = {name: value for name, value in os.environ.items() if name != "PYTHONUNBUFFERED"}
"""A user's environment: stdout into a pipe or file is block-buffered, so what is printed is written when
flushed (this machine sets PYTHONUNBUFFERED, which writes at every print)."""
UNBUFFERED = {**BUFFERED, "PYTHONUNBUFFERED": "1"}


def jointid_process(*args: str, environment=BUFFERED, stdout=subprocess.PIPE) -> subprocess.CompletedProcess:
    """`python -m jointid ARGS` as a user's shell runs it (the console script's own path), stderr captured."""
    return subprocess.run([sys.executable, "-m", "jointid", *args], stdout=stdout, stderr=subprocess.PIPE,
                          text=True, env=environment)


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("environment", [BUFFERED, UNBUFFERED], ids=["buffered", "unbuffered"])
@pytest.mark.parametrize("args", [["fit", "--json"], ["fit", "--motion", "rich"], ["sweep", "--seeds", "3"]])
def test_output_onto_a_full_disk_is_one_line_and_status_2(args, environment):
    """Buffered, the write fails when the process ends; unbuffered, at the first print."""
    with open("/dev/full", "w") as full:
        done = jointid_process(*args, environment=environment, stdout=full)
    assert done.returncode == 2
    assert done.stderr == FULL_DISK + "\n"


def test_a_failed_write_in_process_is_one_line_and_status_2(monkeypatch, capsys):
    class FullStream(io.StringIO):
        def write(self, text):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(sys, "stdout", FullStream())
    assert main(["fit", "--json"]) == 2
    assert capsys.readouterr().err == FULL_DISK + "\n"


@pytest.mark.parametrize("environment", [BUFFERED, UNBUFFERED], ids=["buffered", "unbuffered"])
def test_a_reader_that_left_before_the_output_is_no_error(environment):
    process = subprocess.Popen([sys.executable, "-m", "jointid", "fit", "--motion", "rich"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=environment)
    process.stdout.close()  # before the interpreter has even started: every write meets a closed pipe
    _, errors = process.communicate()
    assert process.returncode == 0
    assert errors == b""


def test_the_output_through_a_pipe_is_the_output_in_process(capsys):
    assert main(["sweep", "--seeds", "50", "--json"]) == 0
    expected = capsys.readouterr().out
    done = jointid_process("sweep", "--seeds", "50", "--json")
    assert done.returncode == 0 and done.stderr == ""
    assert done.stdout == expected and json.loads(done.stdout)["seeds"]["count"] == 50


TEARDOWN_PROBE = """\
import atexit, sys
atexit.register(print, "teardown ran")
from jointid.cli import console_script
sys.argv = ["jointid", *{args!r}]
console_script()
"""


@pytest.mark.parametrize("args, teardown", [(["torque", "--q", "1", "--qd", "2", "--qdd", "3"], False),
                                            (["fit", "--samples", "0"], True)])
def test_a_finished_subcommand_ends_the_process_without_the_teardown(args, teardown):
    """Exit handlers are skipped after a subcommand that ran (its output flushed first), kept after an error."""
    done = subprocess.run([sys.executable, "-c", TEARDOWN_PROBE.format(args=args)], capture_output=True, text=True,
                          env=BUFFERED)
    assert ("teardown ran" in done.stdout) == teardown
    assert done.returncode == (2 if teardown else 0)
    if not teardown:
        assert done.stdout.startswith("State: q = 1.000000 rad") and "Actuator torque" in done.stdout


COLLECTOR_PROBE = """\
import gc, sys
import jointid.cli

def recorded(*args, **kwargs):
    print("collecting" if gc.isenabled() else "not collecting", flush=True)
    return 0

if {recorded!r}:
    jointid.cli.subcommand({recorded!r}).run = recorded
sys.argv = ["jointid", *{args!r}]
jointid.cli.console_script(explorer=recorded)
"""


@pytest.mark.parametrize("args, recorded, collecting", [
    (["torque", "--q", "1", "--qd", "2", "--qdd", "3"], "torque", False),
    (["fit", "--samples", "20"], "fit", False),
    (["watch", "--csv", "growing.csv"], "watch", True),
    (["serve"], "serve", True),
    ([], None, True),  # the explorer
])
def test_only_a_command_that_lasts_collects_reference_cycles(args, recorded, collecting):
    """console_script turns the cyclic collector off for a command that ends and back on for one that runs until
    stopped, whose cycles would otherwise pile up for hours."""
    done = subprocess.run([sys.executable, "-c", COLLECTOR_PROBE.format(args=args, recorded=recorded)],
                          capture_output=True, text=True, env=BUFFERED)
    assert done.stderr == "" and done.returncode == 0
    assert done.stdout.strip() == ("collecting" if collecting else "not collecting")
