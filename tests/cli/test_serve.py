"""`jointid serve`: the explorer over a WebSocket as a browser drives it, read through a terminal emulator (pyte).

One server for the module (--noise 0.2, two sessions at most, a --data folder); each test opens its own
connections. The lesson's numbers checked here are the lesson's own table (DESIGN.md), not jointid's output.
"""

from __future__ import annotations

import json
import os
import socket
import sys

import pytest

from tests.support.serve_support import BrowserTerminal, ServedExplorer, path_field, process_alive, run

SLOW_FIT = {"I": -1.607788, "h": 0.400094, "B": 0.109966}
"""The lesson's slow motion at noise 0.20 (DESIGN.md's table)."""


@pytest.fixture(scope="module")
def data_tree(tmp_path_factory):
    """A --data folder with one log, a log outside it, and a symlink inside pointing at that outside log."""
    root = tmp_path_factory.mktemp("serve")
    data = root / "data"
    data.mkdir()
    log = "t,q,qd,qdd,tau\n" + "".join(
        f"{i * 0.01:.2f},{0.1 * i:.3f},1,0.5,{0.4 + 0.05 * i + 0.01 * (i % 3):.4f}\n" for i in range(40))
    (data / "inside.csv").write_text(log)
    (root / "secret.csv").write_text(log)
    (data / "link.csv").symlink_to(root / "secret.csv")
    return root


@pytest.fixture(scope="module")
def server(data_tree):
    """`jointid serve --noise 0.2 --max-sessions 2 --data DIR` on a free port."""
    served = ServedExplorer("--noise", "0.2", "--max-sessions", "2", "--data", str(data_tree / "data"))
    yield served
    served.stop()


def test_the_browser_sees_the_lesson_and_downloads_the_fit_and_the_session_ends_with_the_socket(server):
    async def scenario(http):
        async with http.get(server.url + "/") as page:  # the page: the address of its WebSocket, and a cookie
            assert page.status == 200 and f"ws://127.0.0.1:{server.port}/ws" in await page.text()
            assert len(page.cookies["jointid_client"].value) == 32
        start = len(server.lines)
        tab = await BrowserTerminal(http, server).connect()
        await tab.wait_for_text("0.793312")  # rich motion at noise 0.20, the lesson's first readouts
        assert "Held-out RMSE (N m)       0.014150" in tab.text
        pid = int(server.wait_for_line(r"session started: pid (\d+)", start).group(1))
        assert process_alive(pid)
        await tab.press("2")
        await tab.wait_for_text("-1.607788")
        await tab.press("ctrl+s")
        await tab.wait_until(lambda: len(tab.deliveries) == 2, "two downloads")
        files = {}
        for key in tab.deliveries:
            name, kind, content = await tab.download(key)
            files[os.path.splitext(name)[1]] = (name, kind, content)
        assert files[".json"][0] == "jointid-slow-0.20-24-7.json"
        assert files[".json"][1].startswith("application/json")
        document = json.loads(files[".json"][2])
        assert document["settings"]["motion"] == "slow" and document["settings"]["noise"] == 0.2
        assert document["estimate"] == pytest.approx(SLOW_FIT, abs=5e-7)
        assert document["heldout_rmse"] == pytest.approx(2.261865, abs=5e-7)
        assert files[".svg"][1].startswith("image/svg+xml")
        svg = files[".svg"][2].decode()
        assert svg.lstrip().startswith("<svg") and svg.rstrip().endswith("</svg>")
        assert "-1.607788" in svg.replace("&#160;", " ")  # the screen with slow motion's fit
        await tab.press("ctrl+r")  # the report page: a third download, not a file on the server
        await tab.wait_until(lambda: len(tab.deliveries) == 3, "the report's download")
        name, kind, content = await tab.download(tab.deliveries[2])
        assert name == "jointid-slow-0.20-24-7-report.html" and kind.startswith("text/html")
        assert b"-1.607788" in content and content.rstrip().endswith(b"</html>")
        await tab.close()
        server.session_ended(pid, start)
        assert not process_alive(pid)

    run(scenario)


def test_a_third_browser_is_told_the_server_is_full_and_the_first_two_keep_working(server):
    async def scenario(http):
        start = len(server.lines)
        first = await BrowserTerminal(http, server).connect()
        second = await BrowserTerminal(http, server).connect()
        for tab in (first, second):
            await tab.wait_for_text("0.793312")
        third = await BrowserTerminal(http, server).connect()
        await third.wait_for_close()
        code, reason = third.close_reason
        assert code == 1013 and "full" in reason and "2 sessions" in reason, third.close_reason
        assert "jointid serve is full" in third.text
        async with http.get(server.url + "/") as page:
            assert page.status == 503 and "jointid serve is full" in await page.text()
        for tab in (first, second):
            await tab.press("2")
        for tab in (first, second):
            await tab.wait_for_text("-1.607788")
        for tab in (first, second):
            await tab.close()
        server.wait_for_lines("session ended", 2, start)
        async with http.get(server.url + "/") as page:
            assert page.status == 200  # places free again

    run(scenario)


def test_ctrl_o_in_the_browser_reads_only_inside_the_data_folder(server, data_tree):
    secret = data_tree / "secret.csv"

    async def scenario(http):
        tab = await BrowserTerminal(http, server, 120, 40).connect()
        await tab.wait_for_text("0.793312")
        await tab.press("ctrl+o")
        await tab.wait_for_text("inside.csv")  # the tree shows the data folder
        assert "link.csv" not in tab.text  # a symlink out of it is not listed
        for typed in ("../secret.csv", str(secret), "link.csv"):
            await tab.press("ctrl+u")  # keys typed straight after Ctrl+U can be lost (in a terminal too): wait
            await tab.wait_until(lambda: path_field(tab) == "", "the path field to empty")
            await tab.press(typed, "enter")
            refusal = "".join(f"{typed}: outside the server's data folder".split())  # a long path wraps anywhere
            await tab.wait_until(lambda refusal=refusal: refusal in "".join(tab.notices.split()), refusal)
            assert "Log loaded" not in tab.text
        await tab.press("ctrl+u")
        await tab.wait_until(lambda: path_field(tab) == "", "the path field to empty")
        await tab.press("inside.csv", "enter")
        await tab.wait_for_text("Log loaded")
        await tab.press("?")
        await tab.wait_for_text("Keys")
        await tab.press_until_text("end", "In a browser")  # the help's last section, in a browser only
        await tab.close()

    run(scenario)


@pytest.fixture(scope="module")
def idle_server():
    """`jointid serve --idle-timeout 10` without --data (longer than an explorer takes to start on a machine
    loaded by other tests: at 3 s a session was ended before it had drawn)."""
    served = ServedExplorer("--idle-timeout", "10")
    yield served
    served.stop()


def test_an_abandoned_session_ends_after_the_idle_timeout_and_ctrl_o_is_off_without_data(idle_server):
    async def scenario(http):
        start = len(idle_server.lines)
        tab = await BrowserTerminal(http, idle_server, 120, 40).connect()
        await tab.press("ctrl+o")  # the last key: the idle clock runs from here
        await tab.wait_until(lambda: "without a --data folder" in tab.notices, "Ctrl+O's refusal")
        assert "Path (Enter opens it)" not in tab.text
        pid = int(idle_server.wait_for_line(r"session started: pid (\d+)", start).group(1))
        await tab.wait_for_close()  # nothing typed since: the server ends the session
        code, reason = tab.close_reason
        assert code == 1001 and reason == "Session ended after 10 s without a key. Reload the page to start again."
        idle_server.session_ended(pid, start)
        assert not process_alive(pid)

    run(scenario)


def test_serve_refuses_a_port_in_use_a_missing_folder_bad_flags_and_a_missing_extra_in_one_line(
        capsys, monkeypatch, tmp_path):
    from jointid.cli import main

    def refused(*argv: str) -> str:
        try:
            status = main(list(argv))
        except SystemExit as exit:  # argparse's refusals end the process (OneLineParser.error)
            status = exit.code
        assert status == 2
        out, err = capsys.readouterr()
        assert out == "" and err.count("\n") == 1, err
        return err

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert refused("serve", "--port", str(port)) == (
            f"jointid: --port {port}: the port is in use on 127.0.0.1; choose another with --port\n")
    assert refused("serve", "--data", str(tmp_path / "nowhere")) == f"jointid: --data {tmp_path / 'nowhere'}: no such folder\n"
    (tmp_path / "file").write_text("")
    assert refused("serve", "--data", str(tmp_path / "file")) == f"jointid: --data {tmp_path / 'file'}: not a folder\n"
    assert refused("serve", "--csv", "nowhere.csv") == "jointid: nowhere.csv: cannot open: No such file or directory\n"
    assert refused("--noise", "0.2", "serve").startswith("jointid: put the explorer's flags after `serve`")
    # `jointid fit` takes 500 samples, the explorer 2 to 240: refused at start, not by each tab's session ending.
    assert refused("serve", "--samples", "500").startswith("jointid: the explorer's --samples is from 2 to 240")
    assert "--max-sessions: must be a whole number from 1" in refused("serve", "--max-sessions", "0")
    import jointid.cli

    monkeypatch.setitem(sys.modules, "jointid.cli.web_server", None)  # as if textual-serve were not installed
    monkeypatch.delattr(jointid.cli, "web_server", raising=False)  # imported by the port's check above
    assert refused("serve") == "jointid: jointid serve needs textual-serve: pip install 'jointid[web]'\n"


def test_the_default_session_limit_is_the_fewer_of_memory_and_cores():
    """Memory alone allowed 160 sessions on this 2-core machine, where 20 were measured (10 a core): the default
    takes the fewer, and says both."""
    from jointid.cli.serve_command import sessions_sentence

    gib = 2**30
    limit, sentence = sessions_sentence(None, 24 * gib, cores=2)
    assert limit == 20 and "the fewer of 167" in sentence and "20 (10 for each of 2 cores" in sentence
    assert sessions_sentence(None, 4 * gib, cores=16)[0] == int(4 * gib * 0.75 / (110 * 2**20)) == 27
    assert sessions_sentence(None, 100 * 2**20, cores=8)[0] == 1  # never none
    assert sessions_sentence(50, 4 * gib, cores=2) == (50, "At most 50 sessions at once (--max-sessions).")
