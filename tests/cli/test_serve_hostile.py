"""`jointid serve` against hostile browsers and clients: pages of other sites, malformed frames, hostile download
names, a flood of idle sockets, a server killed outright, malformed addresses (issue 35).

Each test waits on events (a log line, a frame, a socket closing, a process's pidfd) under a deadline.
"""

from __future__ import annotations

import asyncio
import os
import select
import signal
import socket
import time

import aiohttp
import pytest
from aiohttp.test_utils import TestClient, TestServer

from tests.support.serve_support import (
    DEADLINE,
    BrowserTerminal,
    ServedExplorer,
    disposition_name,
    path_field,
    process_alive,
    run,
)

PUBLIC_URL = "https://jointid.example.org"
ALLOWED = "http://class.example:8080"


@pytest.fixture(scope="module")
def server():
    """`jointid serve` behind a (pretend) reverse proxy, trusting one more site, with three sessions."""
    served = ServedExplorer("--noise", "0.2", "--max-sessions", "3", "--public-url", PUBLIC_URL + "/",
                            "--allow-origin", ALLOWED)
    yield served
    served.stop()


def test_a_page_of_another_site_is_refused_and_starts_no_explorer_while_the_served_page_connects(server):
    async def scenario(http):
        start = len(server.lines)
        for hostile in ("http://evil.example", f"http://evil.example:{server.port}", "null",
                        f"http://127.0.0.1:{server.port + 1 if server.port < 65535 else 1}"):
            with pytest.raises(aiohttp.WSServerHandshakeError) as refusal:
                await BrowserTerminal(http, server).connect(origin=hostile)
            assert refusal.value.status == 403, hostile
        for path in ("/", "/download/anything"):
            async with http.get(server.url + path, headers={"Origin": "http://evil.example"}) as page:
                assert page.status == 403 and "other sites" in await page.text()
        server.wait_for_lines(r"refused /\S* from origin", 6, start)
        assert not any("session started" in line for line in server.lines[start:])  # no explorer for them
        # The served page itself: under its own address, under localhost, behind the proxy, from the allowed site.
        for origin in (f"http://127.0.0.1:{server.port}", f"http://localhost:{server.port}", PUBLIC_URL, ALLOWED):
            tab = await BrowserTerminal(http, server).connect(origin=origin)
            await tab.wait_for_text("0.793312")  # the lesson's rich motion: a session runs for it
            await tab.close()

    run(scenario)


def test_the_origin_rule_trusts_the_servers_own_addresses_and_no_name_it_did_not_give():
    from jointid.cli.web_server import origin_allowed, origin_of

    trusted = frozenset({origin_of("https://Jointid.example.org/")})
    assert trusted == {"https://jointid.example.org"}
    assert origin_allowed(None, "127.0.0.1:8000", trusted, 8000)  # no Origin: not a page's request
    assert origin_allowed("https://jointid.example.org:443", "x", trusted, 8000)
    assert origin_allowed("http://[::1]:8000", "[::1]:8000", trusted, 8000)
    assert origin_allowed("http://192.168.1.5:8000", "192.168.1.5:8000", trusted, 8000)  # reached by its address
    assert not origin_allowed("http://192.168.1.6:8000", "192.168.1.5:8000", trusted, 8000)
    # A name pointed at this machine by its DNS (rebinding) is not the server's: only trusted names count.
    assert not origin_allowed("http://rebind.example:8000", "rebind.example:8000", trusted, 8000)
    assert not origin_allowed("http://localhost:3000", "127.0.0.1:8000", trusted, 8000)  # another local site
    assert not origin_allowed("https://jointid.example.org.evil.example", "x", trusted, 8000)


def test_malformed_frames_are_ignored_and_a_huge_one_closes_only_its_own_connection(server):
    frames = ['["resize",{"width":Infinity,"height":24}]', '[[1],"x"]', '["stdin","\\ud800"]', "not json",
              '{"stdin": "2"}', "[]", '["resize",{"width":1e400,"height":"x"}]', '["stdin",2]', '["ping"]',
              "[" * 100_000 + "]" * 100_000, '["resize",[80,24]]', '[null,"2"]']

    async def scenario(http):
        start = len(server.lines)
        tab = await BrowserTerminal(http, server).connect()
        other = await BrowserTerminal(http, server).connect()
        for each in (tab, other):
            await each.wait_for_text("0.793312")
        for frame in frames:
            await tab.socket.send_str(frame)
        huge = await BrowserTerminal(http, server).connect()
        await huge.wait_for_text("0.793312")
        await huge.socket.send_str('["stdin","' + "x" * (2 << 20) + '"]')
        await huge.wait_for_close()
        assert huge.close_reason[0] == 1009  # message too big: that connection alone
        await tab.press("2")  # the session that took every malformed frame still answers
        await other.press("2")
        for each in (tab, other):
            await each.wait_for_text("-1.607788")
        await tab.close()
        await other.close()
        server.wait_for_lines("session ended", 3, start)
        log = "".join(server.lines[start:])
        assert "Traceback" not in log and "session failed" not in log, log

    run(scenario)


class OneDelivery:
    """A stand-in for a session's explorer that hands the download manager one file in one chunk."""

    app_service_id = "stand-in"

    def __init__(self, manager, content: bytes) -> None:
        self.manager, self.content = manager, content

    async def send_meta(self, meta: dict) -> bool:
        """Answer a chunk request: the content, then an empty chunk (the end)."""
        chunk, self.content = self.content, b""
        await self.manager.chunk_received(meta["key"], chunk)
        return True


@pytest.mark.parametrize("name, saved", [
    ("x; filename*=UTF-8''evil.html; y=.csv", "x; filename*=UTF-8''evil.html; y=.csv"),
    ("run\r\nSet-Cookie: a=b.json", "run__Set-Cookie: a=b.json"),
    ("été \"final\" (2).json", "été \"final\" (2).json"),
    ("../../.bashrc", "_.._.bashrc"),
    ("\x1b]0;owned\x07.svg", "_]0;owned_.svg"),
])
def test_a_download_is_saved_under_its_own_name_quoted_and_sanitised(name, saved):
    from jointid.cli.web_server import JointIdServer

    async def scenario():
        served = JointIdServer(["true"], host="127.0.0.1", port=0, public_url=None, max_sessions=1,
                               idle_timeout=60, environment={})
        await served.download_manager.create_download(
            app_service=OneDelivery(served.download_manager, b"{}\n"), delivery_key="k", file_name=name,
            open_method="download", mime_type="application/json", encoding="utf-8")
        async with TestClient(TestServer(await served.make_app())) as client:
            response = await client.get("/download/k")
            assert response.status == 200, await response.text()
            assert await response.read() == b"{}\n"
            return disposition_name(response), response.headers["Content-Disposition"]

    name_saved, header = asyncio.run(scenario())
    assert name_saved == saved
    assert header.isascii() and "\r" not in header and "\n" not in header


@pytest.mark.parametrize("flag, value", [("--public-url", ""), ("--public-url", "example.org"),
                                         ("--public-url", "ftp://example.org"), ("--public-url", "http://"),
                                         ("--public-url", "http://example.org:99999"),
                                         ("--public-url", "http://a b.org"), ("--public-url", "http://x.org/?q#f"),
                                         ("--allow-origin", "https://x.org/page"), ("--allow-origin", "*")])
def test_a_malformed_address_is_refused_at_start_in_one_line(capsys, flag, value):
    from jointid.cli import main

    with pytest.raises(SystemExit) as exit:
        main(["serve", flag, value])
    assert exit.value.code == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and flag in err and "http:// or https://" in err or "path" in err, err


def pidfd_ended(pid: int, timeout: float) -> bool:
    """Whether process `pid` ends within `timeout` seconds, waited for on its pidfd (an event, not a poll)."""
    try:
        descriptor = os.pidfd_open(pid)
    except ProcessLookupError:
        return True
    try:
        readable, _, _ = select.select([descriptor], [], [], timeout)
        return bool(readable)
    finally:
        os.close(descriptor)


@pytest.mark.skipif(not hasattr(os, "pidfd_open"), reason="waits on a pidfd (Linux)")
def test_every_explorer_ends_when_its_server_is_killed_outright():
    served = ServedExplorer("--noise", "0.2", "--max-sessions", "2")
    try:
        async def scenario(http):
            tabs = [await BrowserTerminal(http, served).connect() for _ in range(2)]
            for tab in tabs:
                await tab.wait_for_text("0.793312")
            pids = [int(match.group(1)) for match in served.wait_for_lines(r"session started: pid (\d+)", 2)]
            assert all(process_alive(pid) for pid in pids)
            os.kill(served.process.pid, signal.SIGKILL)  # no time to end its sessions
            return pids

        pids = run(scenario)
        assert all(pidfd_ended(pid, DEADLINE) for pid in pids)
        assert not any(process_alive(pid) for pid in pids)
    finally:
        served.stop()


@pytest.mark.slow  # a storm of 400 connections: with the rest of the suite beside it, its browser's session once ended
def test_a_flood_of_idle_and_half_sent_connections_is_shed_and_a_browser_gets_in_at_once():
    """Under 256 open files, 400 connections (half idle, half with a request cut short) used to fill the server's
    files, so a browser waited 75 s for aiohttp's keep-alive timeout; the bound sheds them instead."""
    served = ServedExplorer("--noise", "0.2", "--max-sessions", "2", open_files=256)
    flood: list[socket.socket] = []
    try:
        deadline = time.monotonic() + DEADLINE
        for number in range(400):
            assert time.monotonic() < deadline, "the flood itself took too long"
            connection = socket.create_connection(("127.0.0.1", served.port), timeout=5)
            if number % 2:
                connection.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")  # never finished
            flood.append(connection)

        async def scenario(http):
            timeout = aiohttp.ClientTimeout(total=30)  # well under aiohttp's 75 s that the flood used to cost
            async with http.get(served.url + "/", timeout=timeout) as page:
                assert page.status == 200
            tab = await BrowserTerminal(http, served).connect()
            await tab.wait_for_text("0.793312")
            await tab.close()

        run(scenario)
        served.wait_for_line(r"connections at the limit of \d+: \d+ closed to make room")
    finally:
        for connection in flood:
            connection.close()
        served.stop()


LOG = "t,q,qd,qdd,tau\n" + "".join(
    f"{i * 0.01:.2f},{0.1 * i:.3f},1,0.5,{0.4 + 0.05 * i + 0.01 * (i % 3):.4f}\n" for i in range(40))
"""A small log every name below holds."""

NOT_UTF8 = b"caf\xe9.csv"
"""A Latin-1 name: not UTF-8."""
ESCAPES = "\x1b[2J\x1b]0;owned\x07\rclear.csv"
"""A name that clears the screen, sets the window's title, rings and rewrites its line, if shown raw."""


@pytest.fixture(scope="module")
def data_server(tmp_path_factory):
    """`jointid serve --data DIR` whose folder holds a log under a name that is not UTF-8 and one full of
    terminal escapes."""
    data = tmp_path_factory.mktemp("odd-names")
    (data / "inside.csv").write_text(LOG)
    with open(os.path.join(os.fsencode(data), NOT_UTF8), "w") as log:
        log.write(LOG)
    (data / ESCAPES).write_text(LOG)
    served = ServedExplorer("--noise", "0.2", "--max-sessions", "2", "--data", str(data))
    yield served
    served.stop()


def test_odd_file_names_show_escaped_in_the_browser_and_open_without_ending_the_session(data_server):
    async def scenario(http):
        start = len(data_server.lines)
        tab = await BrowserTerminal(http, data_server, 120, 40).connect()
        await tab.wait_for_text("0.793312")
        await tab.press("ctrl+o")
        await tab.wait_for_text("inside.csv")  # the tree lists the folder
        await tab.wait_for_text("caf\\xe9.csv")  # escaped, where it used to end the session
        assert "\\x1b[2J\\x1b]0;owned\\x07\\rclear.csv" in tab.text  # shown, not obeyed
        assert tab.screen.title != "owned" and "0.793312" not in tab.text  # no title set; the dialog is on top
        await tab.press("ctrl+u")
        await tab.wait_until(lambda: path_field(tab) == "", "the path field to empty")
        await tab.press("caf\\xe9.csv", "enter")  # typed as it is shown: opens the file of that name
        await tab.wait_until(lambda: "Log loaded" in tab.notices, "the log's notification")
        assert "caf\\xe9.csv" in "".join(tab.notices.split())  # the toast wraps anywhere
        await tab.press("ctrl+s")  # its exports' names hold the odd name: downloads with a safe one
        await tab.wait_until(lambda: len(tab.deliveries) == 2, "two downloads")
        names = sorted([(await tab.download(key))[0] for key in tab.deliveries])
        assert names == ["caf_-fit.json", "caf_-fit.svg"]
        assert not tab.closed
        await tab.close()
        data_server.wait_for_line("session ended", start)
        log = "".join(data_server.lines[start:])
        assert "Traceback" not in log and "UnicodeEncodeError" not in log, log

    run(scenario)
