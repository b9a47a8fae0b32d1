"""NetworkTables 4 on loopback: a simulated arm and flywheel published to a server in this process, received whole
and exact, on one time base, with their units; a server restart reconnected with the gap said and not bridged;
missing topics, wrong types and a dead host each one clear line."""

import math
import time

import numpy as np
import pytest

pytest.importorskip("ntcore")

from support.nt_publishers import CLOCK_START, LoopbackServer, free_port, wait_until  # noqa: E402
from support.simulated_joints import ARM, arm, flywheel  # noqa: E402

from jointid.live.network_tables import NetworkTablesError, NetworkTablesSource, parse_address  # noqa: E402
from jointid.live.received_log import ReceivedLog  # noqa: E402
from jointid.logs.csv_reader import load_log  # noqa: E402

ARM_TOPICS = {"/Arm/Position": "double", "/Arm/Velocity": "double", "/Arm/Acceleration": "double",
              "/Arm/Torque": "double"}
ARM_ENTRIES = "q=/Arm/Position,qd=/Arm/Velocity,qdd=/Arm/Acceleration,tau=/Arm/Torque"


@pytest.fixture
def server(tmp_path):
    running = LoopbackServer(tmp_path)
    yield running
    running.stop()


@pytest.fixture
def sources():
    opened = []
    yield opened
    for source in opened:
        source.close()


def collect(source, rows: int, timeout: float = 20.0, until=None):
    """Poll until `rows` samples have arrived (and `until(events)` holds, when given); (columns, events, blocks)."""
    blocks, received = [], 0
    deadline = time.monotonic() + timeout  # only a failing test waits this long
    events = []
    while time.monotonic() < deadline:
        block = source.poll(0.2)
        blocks.append(block)
        received += block.count
        events += block.events
        if received >= rows and (until is None or until(events)) or block.ended:
            break
    full = [b for b in blocks if b.count]
    columns = {name: np.concatenate([b.columns[name] for b in full]) for name in (full[0].columns if full else ())}
    return columns, events, blocks


def arm_source(server, sources, **options):
    source = NetworkTablesSource(server.address, ARM_ENTRIES, **options)
    sources.append(source)
    wait_until(lambda: all(server.subscribed(name) for name in ARM_TOPICS), what="the subscriptions")
    return source


def test_a_50_hz_arm_arrives_whole_exact_and_in_radians_said(server, sources):
    run = arm(rate=50, duration=10.0)
    server.publish_topics(ARM_TOPICS)
    source = arm_source(server, sources)
    server.stream(dict(zip(ARM_TOPICS, (run.q, run.qd, run.qdd, run.tau))), run.t)
    columns, events, _ = collect(source, len(run.t))
    np.testing.assert_allclose(columns["t"], CLOCK_START + run.t, rtol=0, atol=1e-9)
    for name in ("q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(columns[name], getattr(run, name))
    assert source.effort == "torque" and not source.linear
    assert f"connected to {server.address}" in events
    assert any("publish no unit property: read in radians" in event for event in events)


def test_a_1_khz_flywheel_in_rotations_with_a_sysid_state_is_read_in_radians_as_voltage(server, sources):
    run = flywheel(rate=1000, duration=5.0)
    topics = {"/Fly/Position": "double", "/Fly/Velocity": "double", "/Fly/Voltage": "double",
              "/Fly/State": "string"}
    server.publish_topics(topics, units={"/Fly/Position": "Rotation", "/Fly/Velocity": "Rotation per Second",
                                         "/Fly/Voltage": "Volt"})
    source = NetworkTablesSource(server.address, "q=/Fly/Position,qd=/Fly/Velocity,tau=/Fly/Voltage,"
                                 "state=/Fly/State")
    sources.append(source)
    wait_until(lambda: all(server.subscribed(name) for name in topics), what="the subscriptions")
    turn = 2 * math.pi
    server.stream(dict(zip(topics, (run.q / turn, run.qd / turn, run.tau, run.state))), run.t)
    columns, events, blocks = collect(source, len(run.t))
    assert len(columns["t"]) == len(run.t)
    np.testing.assert_allclose(columns["q"], run.q, rtol=1e-15, atol=1e-12)
    np.testing.assert_allclose(columns["qd"], run.qd, rtol=1e-15, atol=1e-12)
    np.testing.assert_array_equal(columns["tau"], run.tau)
    assert columns["state"].tolist() == run.state.tolist()
    assert source.effort == "voltage" and "qdd" not in columns
    assert any("read as motor voltage" in event for event in events)
    assert sum(block.dropped for block in blocks) == 0


@pytest.mark.parametrize("unit, units", [("degrees", None), (None, "degrees")])
def test_degrees_by_the_unit_property_or_by_units_arrive_in_radians(server, sources, unit, units):
    run = arm(rate=50, duration=2.0)
    topics = {"/Arm/Position": "double", "/Arm/Torque": "double"}
    server.publish_topics(topics, units=None if unit is None else {"/Arm/Position": unit})
    source = NetworkTablesSource(server.address, "q=/Arm/Position,tau=/Arm/Torque", units=units)
    sources.append(source)
    wait_until(lambda: all(server.subscribed(name) for name in topics), what="the subscriptions")
    server.stream(dict(zip(topics, (np.degrees(run.q), run.tau))), run.t)
    columns, events, _ = collect(source, len(run.t))
    np.testing.assert_allclose(columns["q"], run.q, rtol=1e-14, atol=1e-14)
    said = ("'/Arm/Position' is in 'degrees' (its unit property): q = 0.0174533 × the logged value, in radians."
            if units is None else "'/Arm/Position' is read in degrees (--units degrees).")
    assert said in events


def test_a_velocity_without_a_position_is_integrated_into_q(server, sources):
    run = flywheel(rate=200, duration=2.0)
    topics = {"/Fly/Velocity": "double", "/Fly/Voltage": "double"}
    server.publish_topics(topics)
    source = NetworkTablesSource(server.address, "qd=/Fly/Velocity,tau=/Fly/Voltage")
    sources.append(source)
    wait_until(lambda: all(server.subscribed(name) for name in topics), what="the subscriptions")
    server.stream(dict(zip(topics, (run.qd, run.tau))), run.t)
    columns, events, _ = collect(source, len(run.t))
    trapezoids = np.concatenate(([0.0], np.cumsum(0.5 * (run.qd[1:] + run.qd[:-1]) * np.diff(run.t))))
    np.testing.assert_allclose(columns["q"], trapezoids, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(columns["qd"], run.qd)
    assert any("No position topic" in event for event in events)


def test_a_server_restart_is_reconnected_and_the_gap_said_not_bridged(server, sources, tmp_path):
    first, second = arm(rate=50, duration=4.0), arm(rate=50, duration=4.0, start=6.0)
    server.publish_topics(ARM_TOPICS)
    source = arm_source(server, sources)
    server.stream(dict(zip(ARM_TOPICS, (first.q, first.qd, first.qdd, first.tau))), first.t).join()
    before, _, _ = collect(source, len(first.t))
    assert len(before["t"]) == len(first.t)
    port = server.port
    server.stop()
    _, gone, _ = collect(source, 0, until=lambda events: any("source gone" in e for e in events))
    assert any("source gone at" in event and "disconnected" in event for event in gone)
    restarted = LoopbackServer(tmp_path, port)
    try:
        restarted.publish_topics(ARM_TOPICS)
        wait_until(lambda: all(restarted.subscribed(name) for name in ARM_TOPICS), what="the resubscriptions")
        restarted.stream(dict(zip(ARM_TOPICS, (second.q, second.qd, second.qdd, second.tau))), second.t)
        after, events, blocks = collect(source, len(second.t))
    finally:
        restarted.stop()
    assert any(event.startswith("reconnected after a ") and event.endswith(" s gap (not bridged)")
               for event in events)
    np.testing.assert_array_equal(after["q"], second.q)
    np.testing.assert_allclose(after["t"], CLOCK_START + second.t, rtol=0, atol=1e-9)
    first_block = next(block for block in blocks if block.count)
    assert first_block.breaks == (0,)  # the second stretch starts a new one: nothing across the gap


def test_what_arrived_across_a_restart_is_written_as_a_log_that_reads_back_the_same(server, sources, tmp_path):
    first, second = arm(rate=50, duration=3.0), arm(rate=50, duration=3.0, start=5.0)
    server.publish_topics(ARM_TOPICS)
    source = arm_source(server, sources)
    log = ReceivedLog.for_source(tmp_path / "watched.csv", source)
    server.stream(dict(zip(ARM_TOPICS, (first.q, first.qd, first.qdd, first.tau))), first.t).join()
    port = server.port
    blocks = collect(source, len(first.t))[2]
    server.stop()
    blocks += collect(source, 0, until=lambda events: any("source gone" in e for e in events))[2]
    restarted = LoopbackServer(tmp_path, port)
    try:
        restarted.publish_topics(ARM_TOPICS)
        wait_until(lambda: all(restarted.subscribed(name) for name in ARM_TOPICS), what="the resubscriptions")
        restarted.stream(dict(zip(ARM_TOPICS, (second.q, second.qd, second.qdd, second.tau))), second.t)
        blocks += collect(source, len(second.t))[2]
    finally:
        restarted.stop()
    for block in blocks:
        log.write(block)
    log.finish()
    read = load_log(tmp_path / "watched.csv")
    np.testing.assert_allclose(read.data.t, CLOCK_START + np.concatenate([first.t, second.t]), rtol=0, atol=1e-9)
    np.testing.assert_array_equal(read.data.tau, np.concatenate([first.tau, second.tau]))
    text = (tmp_path / "watched.csv").read_text()
    assert "# stretch 2 starts here" in text and "(not bridged)" in text


def test_a_server_gone_longer_than_the_gone_timeout_ends_the_source(server, sources):
    server.publish_topics(ARM_TOPICS)
    source = arm_source(server, sources, gone_timeout=0.2)
    server.stop()
    _, events, blocks = collect(source, 0, until=lambda events: False)
    assert blocks[-1].ended and "the server has been gone for 0.2 s: done" in events


def test_values_published_faster_than_polled_beyond_the_buffer_are_counted_as_dropped(server, sources):
    run = arm(rate=1000, duration=1.0)
    server.publish_topics(ARM_TOPICS)
    source = arm_source(server, sources, buffered_values=400)
    assert "connected" in source.poll(0.0).events[-1]  # taken, so the buffer holds values only
    server.stream(dict(zip(ARM_TOPICS, (run.q, run.qd, run.qdd, run.tau))), run.t).join()
    total = 4 * len(run.t)
    wait_until(lambda: source.dropped + len(source.incoming) >= total, what="every value to arrive")
    block = source.poll(0.0)
    assert block.dropped == total - 400
    assert block.count <= 100


def test_a_missing_topic_is_named_with_the_topics_the_server_publishes(server, sources):
    server.publish_topics({"/Arm/Position": "double", "/Arm/Torque": "double"})
    with pytest.raises(NetworkTablesError) as raised:
        # Long enough for the announcements of the topics that are published to arrive on a loaded machine.
        NetworkTablesSource(server.address, "q=/Arm/Positon,tau=/Arm/Torque", topic_timeout=3.0)
    message = str(raised.value)
    assert "--entry q=/Arm/Positon: the server publishes no topic '/Arm/Positon'" in message
    assert "/Arm/Position" in message and "\n" not in message


def test_a_string_topic_named_as_q_is_the_wrong_type(server, sources):
    server.publish_topics({"/Arm/State": "string", "/Arm/Torque": "double"})
    with pytest.raises(NetworkTablesError, match=r"--entry q=/Arm/State: topic '/Arm/State' holds string, not a "
                                                 r"number"):
        # The type is known as soon as the topic is announced: a long wait costs nothing unless that is late.
        NetworkTablesSource(server.address, "q=/Arm/State,tau=/Arm/Torque", topic_timeout=30.0)


def test_a_dead_host_is_one_line():
    with pytest.raises(NetworkTablesError, match=r"NetworkTables 127.0.0.1:\d+: no NetworkTables server answered "
                                                 r"in 0.3 s"):
        NetworkTablesSource(f"127.0.0.1:{free_port()}", ARM_ENTRIES, connect_timeout=0.3)


@pytest.mark.parametrize("text, expected", [
    ("10.12.34.2", ("10.12.34.2", 5810)), ("localhost:5811", ("localhost", 5811)), ("[::1]:5812", ("::1", 5812)),
    ("[::1]", ("::1", 5810)), (("robot", 5813), ("robot", 5813)), (("::1", 5814), ("::1", 5814)),
])
def test_an_address_is_host_and_port_5810_by_default(text, expected):
    assert parse_address(text) == expected


@pytest.mark.parametrize("text", ["", "robot:", "robot:99999", "robot:port"])
def test_a_bad_address_is_one_line(text):
    with pytest.raises(NetworkTablesError, match="--nt"):
        parse_address(text)


def test_an_entry_map_without_an_effort_is_refused_before_connecting():
    with pytest.raises(NetworkTablesError, match="names no topic for tau"):
        NetworkTablesSource("127.0.0.1:1", "q=/Arm/Position")
    with pytest.raises(NetworkTablesError, match="unknown quantity 'x'"):
        NetworkTablesSource("127.0.0.1:1", "x=/Arm/Position")


def test_a_closed_source_freed_later_leaves_the_next_sources_subscriptions_alone(server, sources):
    """ntcore gives a new instance the handles of a destroyed one: a closed source's subscribers, freed only when
    the source object goes (a garbage collection, at any time), would unsubscribe the next source's own."""
    import gc

    run = arm(rate=50, duration=2.0)
    server.publish_topics(ARM_TOPICS)
    first = NetworkTablesSource(server.address, ARM_ENTRIES)
    first.close()
    second = arm_source(server, sources)
    del first
    gc.collect()
    server.stream(dict(zip(ARM_TOPICS, (run.q, run.qd, run.qdd, run.tau))), run.t)
    columns, _, _ = collect(second, len(run.t))
    np.testing.assert_allclose(columns["tau"], run.tau, rtol=1e-12)
