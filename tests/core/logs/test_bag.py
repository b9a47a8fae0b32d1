"""ROS bags: reading JointState bytes, the issue's acceptance on bags written by rosbags, bad bags, bag-info.

Every bag here is written with rosbags' own writers (ROS 2 sqlite3 and MCAP,
ROS 1) from the closed-form joint of bag_support, never from jointid's code.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

pytest.importorskip("rosbags")

from support.bag_support import (  # noqa: E402
    KINDS,
    NOISE_BOUND,
    NOISE_RMS,
    TRUE,
    BagWriter,
    G,
    bag_path,
    jittered_times,
    joint_state,
    rich,
    serialize,
    two_joints,
    typestore,
    write_joint_bag,
    write_mismatched_bag,
)

from jointid.cli import main  # noqa: E402
from jointid.logs.bag import bag_info, doubles, parse_layout, read_bag_table, stamps  # noqa: E402

DURATION, RATE = 20.0, 500.0


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    """Two joints at 500 Hz with +-5 % jitter, 20 s, in every kind, with velocity and with it empty."""
    folder = tmp_path_factory.mktemp("bags")
    t = jittered_times(DURATION, RATE, 0.05)
    joints = two_joints(t)
    made = {}
    for kind in KINDS:
        made[kind, True] = write_joint_bag(bag_path(folder, "rich", kind), kind, t, joints)
        made[kind, False] = write_joint_bag(bag_path(folder, "novel", kind), kind, t, joints, velocity=False)
    # The first 12 s alone, to compare with --train-window 0:12 on the whole bag.
    early = t <= 12.0
    made["early"] = write_joint_bag(bag_path(folder, "early", "sqlite3"), "sqlite3", t[early],
                                    {n: tuple(v[early] for v in values) for n, values in joints.items()})
    made["folder"] = folder
    return made


def fit_json(capsys, *argv) -> dict:
    """`jointid fit ... --json` run in this process; its document."""
    status = main(["fit", *argv, "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    return json.loads(out)


def refused(capsys, *argv) -> str:
    """Run a command that must fail: exit 2, nothing on stdout, one line on stderr; that line."""
    try:
        status = main(list(argv))
    except SystemExit as stop:  # argparse's own refusals
        status = stop.code
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("jointid"), err
    return err.strip()


def estimate(document: dict) -> dict:
    return {name: document["estimate"][name] for name in ("I", "h", "B")}


def assert_within(found: dict, tolerance: float) -> None:
    for name, value in TRUE.items():
        assert abs(found[name] - value) <= tolerance * value, (name, found[name])


# ------------------------------------------------------------------------------------ acceptance


@pytest.mark.parametrize("kind", KINDS)
def test_rich_joint_recovered_within_2_percent_with_velocity(bags, capsys, kind):
    document = fit_json(capsys, "--bag", str(bags[kind, True]), "--joint", "shoulder")
    assert_within(estimate(document), 0.02)
    assert document["derivatives"]["estimated"] == ["qd", "qdd"]  # a logged velocity alone is estimated too
    assert document["timing"]["resampled"] is True and 0.045 < document["timing"]["max_jitter"] < 0.051


@pytest.mark.parametrize("kind", KINDS)
def test_rich_joint_recovered_within_3_percent_with_velocity_empty(bags, capsys, kind):
    document = fit_json(capsys, "--bag", str(bags[kind, False]), "--joint", "shoulder", "--topic", "/joint_states")
    assert_within(estimate(document), 0.03)
    assert document["derivatives"]["estimated"] == ["qd", "qdd"]


def test_train_and_heldout_windows_of_one_bag(bags, capsys):
    bag = str(bags["sqlite3", True])
    both = fit_json(capsys, "--bag", bag, "--joint", "shoulder", "--train-window", "0:12", "--heldout-window", "12:20")
    alone = fit_json(capsys, "--bag", bag, "--joint", "shoulder", "--train-window", "0:12")
    written = fit_json(capsys, "--bag", str(bags["early"]), "--joint", "shoulder")
    for name in ("I", "h", "B"):
        assert both["estimate"][name] == alone["estimate"][name]
        assert math.isclose(both["estimate"][name], written["estimate"][name],
                            rel_tol=1e-9)
    # The held-out window goes through the training window's pipeline: both RMSEs are of the low-passed torque,
    # the noise left above the cutoff gone from both alike, so they are comparable, and far below the raw noise.
    heldout, training = both["heldout_rmse"], both["training_rmse"]
    assert 0.5 * training <= heldout <= 2.0 * training, (heldout, training)
    # White noise low-passed at fc keeps 2 fc / rate of its power: the held-out RMSE is about that share of it.
    passed = NOISE_RMS * math.sqrt(2 * both["low_pass"]["cutoff_hz"] / RATE)
    assert 0.5 * passed <= heldout <= 2.0 * passed, (heldout, passed)
    assert any("held-out window 12:20 s" in note for note in both["notes"])
    assert both["logs"]["heldout"] == {"path": bag, "format": "rosbag", "topic": "/joint_states", "joint": "shoulder",
                                       "time_window": {"start_s": 12.0, "end_s": 20.0}, "effort_scale": 1.0}
    assert both["logs"]["training"]["time_window"] == {"start_s": 0.0, "end_s": 12.0}


def test_effort_scale_converts_and_is_noted(bags, capsys):
    document = fit_json(capsys, "--bag", str(bags["mcap", True]), "--joint", "shoulder", "--effort-scale", "2.5")
    plain = fit_json(capsys, "--bag", str(bags["mcap", True]), "--joint", "shoulder")
    for name in ("I", "h", "B"):  # the model is linear in tau: every parameter scales with it
        assert math.isclose(document["estimate"][name], 2.5 * plain["estimate"][name],
                            rel_tol=1e-9)
    assert any("torque = 2.5 × effort" in note for note in document["notes"])
    assert any("--effort-scale 1)" in note for note in plain["notes"])
    assert document["logs"]["training"]["effort_scale"] == 2.5 and document["logs"]["heldout"] is None


def test_bag_info_lists_exactly_what_was_written(tmp_path, capsys):
    # Three joints; 'wrist' is left out of every third message, velocity is empty in 40 messages, and
    # a second topic carries no JointState.
    kind = "mcap"
    store = typestore(kind)
    path = bag_path(tmp_path, "info", kind)
    with BagWriter(path, kind) as bag:
        bag.add_topic("/joint_states")
        bag.add_topic("/count", "std_msgs/msg/Int32")
        for i in range(300):
            names = ["a", "b", "wrist"] if i % 3 else ["a", "b"]
            velocity = [] if i < 40 else [0.1] * len(names)
            message = joint_state(store, 1_000_000_000 + i * 10_000_000, names, [0.0] * len(names), velocity,
                                  [1.0] * len(names))
            bag.write("/joint_states", 1_000_000_000 + i * 10_000_000, serialize(store, kind, message))
        for i in range(7):
            count = store.types["std_msgs/msg/Int32"](data=i)
            bag.write("/count", 2_000_000_000 + i, bytes(store.serialize_cdr(count, "std_msgs/msg/Int32")))
    assert main(["bag-info", str(path), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["topics"] == [
        {"topic": "/count", "type": "std_msgs/msg/Int32", "messages": 7},
        {"topic": "/joint_states", "type": "sensor_msgs/msg/JointState", "messages": 300},
    ]
    (topic,) = info["joint_states"]
    assert topic["messages"] == 300 and topic["time_source"] == "header.stamp"
    assert math.isclose(topic["median_step_s"], 0.01) and math.isclose(topic["rate_hz"], 100.0)
    assert math.isclose(topic["duration_s"], 2.99)
    assert topic["joints"] == [
        {"name": "a", "messages": 300, "filled": {"position": 300, "velocity": 260, "effort": 300}},
        {"name": "b", "messages": 300, "filled": {"position": 300, "velocity": 260, "effort": 300}},
        {"name": "wrist", "messages": 200, "filled": {"position": 200, "velocity": 174, "effort": 200}},
    ]
    assert main(["bag-info", str(path)]) == 0
    text = capsys.readouterr().out
    assert "wrist       200  position, velocity (174 of 200), effort" in text
    assert "/count" in text and "100 Hz" in text


# ------------------------------------------------------------------------------------ bad bags


def _bad_bag(folder, name, *, t=None, mutate=None, **options):
    """A two-joint sqlite3 bag of 4 s at 500 Hz with `mutate(t, joints)` applied first."""
    t = np.arange(2000) / 500.0 if t is None else t
    joints = two_joints(t)
    if mutate is not None:
        mutate(t, joints)
    return write_joint_bag(bag_path(folder, name, "sqlite3"), "sqlite3", t, joints, **options)


@pytest.fixture(scope="module")
def bad_bags(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bad")
    made = {}
    corrupt = folder / "corrupt.bag"
    corrupt.write_bytes(b"#ROSBAG V2.0\n" + bytes(range(256)) * 4)
    made["corrupt"] = corrupt
    made["no metadata"] = folder / "no-metadata"
    made["no metadata"].mkdir()
    no_joint_state = bag_path(folder, "nojs", "sqlite3")
    with BagWriter(no_joint_state, "sqlite3") as bag:
        bag.add_topic("/count", "std_msgs/msg/Int32")
        bag.write("/count", 1, bytes(bag.store.serialize_cdr(bag.store.types["std_msgs/msg/Int32"](data=1),
                                                             "std_msgs/msg/Int32")))
    made["no JointState"] = no_joint_state
    made["effort empty"] = _bad_bag(folder, "noeffort", effort=False)

    def nan_position(t, joints):
        joints["shoulder"][0][700] = np.nan

    made["NaN position"] = _bad_bag(folder, "nan", mutate=nan_position)
    gap = np.arange(2000) / 500.0
    gap[1000:] += 2.0
    made["2 s gap"] = _bad_bag(folder, "gap", t=gap)
    repeated = np.arange(2000) / 500.0
    repeated[901] = repeated[900]
    made["duplicated stamps"] = _bad_bag(folder, "dup", t=repeated)
    made["ok"] = _bad_bag(folder, "ok")
    return made


BAD = {
    "corrupt": "cannot be read as a ROS 1 bag: the file is damaged, truncated or not a bag",
    "no metadata": "is a folder without metadata.yaml: not a ROS 2 bag folder",
    "no JointState": "has no sensor_msgs/JointState topic (topics: /count (std_msgs/msg/Int32))",
    "effort empty": "joint 'shoulder' has no effort in any message on /joint_states",
    "NaN position": "message 701 on /joint_states (t = 1.4 s), position of joint 'shoulder': NaN is not a measurement",
    "2 s gap": "message 1001 on /joint_states (t = 4 s): gap in time: 2.002 s",
    "duplicated stamps": "message 902 on /joint_states (t = 1.8 s): time stamp t = 1.8 s repeats with other values",
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_bag_is_one_line_and_exit_2(bad_bags, capsys, case):
    line = refused(capsys, "fit", "--bag", str(bad_bags[case]), "--joint", "shoulder")
    assert str(bad_bags[case]) in line and BAD[case] in line, line


def test_absent_joint_lists_the_joints_there(bad_bags, capsys):
    line = refused(capsys, "compare", "--bag", str(bad_bags["ok"]), "--joint", "wrist")
    assert line.endswith("no joint 'wrist' in any message on /joint_states; joints there: 'shoulder', 'elbow'")


def test_a_joint_named_twice_in_one_message_is_ambiguous(tmp_path, capsys):
    kind = "ros1"
    store = typestore(kind)
    path = bag_path(tmp_path, "twice", kind)
    with BagWriter(path, kind) as bag:
        bag.add_topic("/joint_states")
        for i in range(50):
            message = joint_state(store, (i + 1) * 2_000_000, ["a", "a"], [0.0, 1.0], [], [0.0, 1.0])
            bag.write("/joint_states", (i + 1) * 2_000_000, serialize(store, kind, message))
    line = refused(capsys, "fit", "--bag", str(path), "--joint", "a")
    assert "message 1 on /joint_states names joint 'a' more than once" in line


def test_bag_options_need_a_bag_and_a_joint(bad_bags, capsys):
    assert "--joint: only for a ROS bag" in refused(capsys, "fit", "--csv", "x.csv", "--joint", "a")
    assert "--bag needs --joint NAME" in refused(capsys, "fit", "--bag", str(bad_bags["ok"]))
    assert "only for fitting a log" in refused(capsys, "fit", "--train-window", "0:3")
    assert "START:END" in refused(capsys, "fit", "--bag", "b", "--joint", "a", "--train-window", "3")
    assert "END must be later" in refused(capsys, "fit", "--bag", "b", "--joint", "a", "--heldout-window", "3:1")
    assert "other than 0" in refused(capsys, "fit", "--bag", "b", "--joint", "a", "--effort-scale", "0")


def test_window_outside_the_log_is_refused(bad_bags, capsys):
    line = refused(capsys, "fit", "--bag", str(bad_bags["ok"]), "--joint", "shoulder", "--train-window", "10:20")
    assert "no samples in the training window 10:20 s; the log spans 0 to 3.998 s" in line


def test_without_rosbags_one_line_names_the_extra(bad_bags, capsys, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)  # import now raises ImportError
    line = refused(capsys, "fit", "--bag", str(bad_bags["ok"]), "--joint", "shoulder")
    assert line.endswith("pip install 'jointid[ros]'")
    assert refused(capsys, "bag-info", str(bad_bags["ok"])).endswith("pip install 'jointid[ros]'")


@pytest.mark.parametrize("kind, field, length", [("ros1", "position", 1), ("mcap", "effort", 3),
                                                  ("sqlite3", "velocity", 1)])
def test_mismatched_array_lengths_are_refused_for_fitting_naming_the_topic_and_the_count(tmp_path, capsys, kind,
                                                                                          field, length):
    path = write_mismatched_bag(tmp_path, kind, field, length)
    line = refused(capsys, "fit", "--bag", str(path), "--joint", "shoulder")
    assert (f"{path}: arrays of other lengths than their joint names in 1 of 100 messages on /joint_states "
            f"(first: message 41, {field} has {length} value{'s' if length > 1 else ''} for 2 joint names)") in line
    assert "empty" not in line


@pytest.mark.parametrize("kind, field, length", [("ros1", "position", 1), ("mcap", "effort", 3),
                                                  ("sqlite3", "velocity", 1)])
def test_bag_info_lists_a_bag_with_mismatched_arrays_and_says_which_messages(tmp_path, capsys, kind, field, length):
    """bag-info refused the whole bag over one message whose array lengths did not match its names."""
    path = write_mismatched_bag(tmp_path, kind, field, length)
    assert main(["bag-info", str(path)]) == 0
    text = capsys.readouterr().out
    values = f"value{'s' if length > 1 else ''}"
    assert (f"1 of 100 messages (first: message 41, {field} has {length} {values} for 2 joint names)") in text
    assert "shoulder        99  position, velocity, effort" in text and "elbow           99" in text
    assert "100 messages over 0.198 s" in text and "max 2 ms (jitter 0.0%)" in text  # its stamp still counts
    assert main(["bag-info", "--json", str(path)]) == 0
    (topic,) = json.loads(capsys.readouterr().out)["joint_states"]
    assert topic["mismatched_arrays"] == {"messages": 1, "first_message": 41,
                                          "problem": f"{field} has {length} {values} for 2 joint names"}
    assert [joint["messages"] for joint in topic["joints"]] == [99, 99]


@pytest.mark.parametrize("kind", ["sqlite3", "mcap"])
def test_a_bag_folders_missing_or_unusable_storage_file_is_named(tmp_path, capsys, kind):
    import shutil

    t = np.arange(200) / 500.0
    good = write_joint_bag(bag_path(tmp_path, "good", kind), kind, t, two_joints(t))
    (storage,) = [f.name for f in good.iterdir() if f.name != "metadata.yaml"]
    cases = {}
    for how in ("missing", "a folder", "empty"):
        copy = tmp_path / how.replace(" ", "-")
        shutil.copytree(good, copy)
        (copy / storage).unlink()
        if how == "a folder":
            (copy / storage).mkdir()
        elif how == "empty":
            (copy / storage).write_bytes(b"")
        cases[how] = copy
    expected = {"missing": f"its storage file {storage}, named in metadata.yaml, is missing",
                "a folder": f"storage file {storage}: cannot read: a directory",
                "empty": f"its storage file {storage} is damaged, truncated or not a bag's"}
    for how, path in cases.items():
        for argv in (["fit", "--bag", str(path), "--joint", "shoulder"], ["bag-info", str(path)]):
            line = refused(capsys, *argv)
            assert f"{path}" in line and expected[how] in line, (how, line)
            assert not any(text.lower() in line.lower() for text in ROSBAGS_WORDING), (how, line)


def _damaged_copies(folder, good, kind):
    """Copies of a good bag with its data file truncated, overwritten in the middle or headed by zeros, and
    (ROS 2) with an unparsable metadata.yaml."""
    import shutil

    def data_file(path):
        return next(f for f in path.iterdir() if f.name != "metadata.yaml") if path.is_dir() else path

    made = {}
    for how in ("truncated", "garbled", "zeroed", "bad metadata"):
        if how == "bad metadata" and kind == "ros1":
            continue
        copy = bag_path(folder, how.replace(" ", "-"), kind)
        (shutil.copytree if good.is_dir() else shutil.copy)(good, copy)
        target = data_file(copy)
        data = bytearray(target.read_bytes())
        if how == "truncated":
            data = data[: len(data) // 2]
        elif how == "garbled":
            start = len(data) // 3
            data[start: start + 4000] = np.random.default_rng(3).integers(0, 256, 4000, dtype=np.uint8).tobytes()
        elif how == "zeroed":
            data[:64] = bytes(64)
        else:
            (copy / "metadata.yaml").write_text("{{: [\n")
        target.write_bytes(bytes(data))
        made[how] = copy
    return made


# Fragments of rosbags' own exception texts, which must not reach the user.
ROSBAGS_WORDING = ("magic", "Header could not", "database files are missing", "malformed", "not a database", "load YAML", "NoneType", "ssize_t",
                   "codec", "offset", "Bag index", "Cannot open")


@pytest.mark.parametrize("kind", KINDS)
def test_a_damaged_bag_is_jointids_own_line_naming_the_file(tmp_path, capsys, kind):
    t = np.arange(2000) / 500.0
    good = write_joint_bag(bag_path(tmp_path, "good", kind), kind, t, two_joints(t))
    for how, path in _damaged_copies(tmp_path, good, kind).items():
        for argv in (["fit", "--bag", str(path), "--joint", "shoulder"], ["bag-info", str(path)]):
            line = refused(capsys, *argv)
            assert line.startswith("jointid") and f"{path}" in line and "cannot be read" in line, (how, line)
            assert not any(text.lower() in line.lower() for text in ROSBAGS_WORDING), (how, line)
            if "after message" in line or "at the first message" in line:
                assert "on /joint_states" in line, (how, line)


# ------------------------------------------------------------------------------------ timing


def test_zero_stamps_fall_back_to_receive_time(tmp_path):
    t = np.arange(1500) / 500.0
    path = write_joint_bag(bag_path(tmp_path, "zero", "mcap"), "mcap", t, two_joints(t), stamps_zero=True)
    table = read_bag_table(path, "shoulder")
    assert np.allclose(table.columns["t"], t, atol=1e-9)
    assert any("every header.stamp is zero, so time is the bag's receive time" in n for n in table.notes)


def test_out_of_order_stamps_are_sorted_and_noted(tmp_path):
    kind = "sqlite3"
    store = typestore(kind)
    t = np.arange(1000) / 500.0
    q, qd, tau = two_joints(t)["shoulder"]
    order = np.arange(1000)
    order[[300, 301]] = order[[301, 300]]  # recorded in this order, stamped in true order
    path = bag_path(tmp_path, "swap", kind)
    with BagWriter(path, kind) as bag:
        bag.add_topic("/joint_states")
        for k, i in enumerate(order):
            message = joint_state(store, 10**9 + int(i) * 2_000_000, ["shoulder"], [q[i]], [qd[i]], [tau[i]])
            bag.write("/joint_states", 10**9 + k * 2_000_000, serialize(store, kind, message))
    table = read_bag_table(path, "shoulder")
    assert np.array_equal(table.columns["q"], q) and np.allclose(table.columns["t"], t, atol=1e-9)
    assert any("1 messages arrived out of stamp order; sorted by header.stamp" in n for n in table.notes)


# ------------------------------------------------------------------------------------ the byte reader


def _random_message(rng, store):
    count = int(rng.integers(0, 6))
    names = ["".join(rng.choice(list("abcxyz_é0"), size=int(rng.integers(1, 9)))) for _ in range(count)]
    fields = [rng.normal(size=count) if rng.random() < 0.7 else np.zeros(0) for _ in range(3)]
    frame = "".join(rng.choice(list("base_link/ü"), size=int(rng.integers(0, 12))))
    stamp = int(rng.integers(0, 2**31 - 1)) * 1_000_000_000 + int(rng.integers(0, 10**9))
    return joint_state(store, stamp, names, *fields, frame_id=frame, seq=int(rng.integers(0, 2**32))), stamp


@pytest.mark.parametrize("kind", ["mcap", "ros1"])
def test_byte_reader_agrees_with_rosbags_deserialiser(kind):
    rng = np.random.default_rng(14)
    store = typestore(kind)
    for _ in range(300):
        message, stamp = _random_message(rng, store)
        raw = serialize(store, kind, message)
        back = store.deserialize_ros1(raw, "sensor_msgs/msg/JointState") if kind == "ros1" else \
            store.deserialize_cdr(raw, "sensor_msgs/msg/JointState")
        layout = parse_layout(raw, kind == "ros1")
        block = np.frombuffer(raw, dtype=np.uint8).reshape(1, -1)
        assert list(layout.names) == list(back.name)
        assert int(stamps(block, layout)[0]) == back.header.stamp.sec * 10**9 + back.header.stamp.nanosec == stamp
        for k, name in enumerate(("position", "velocity", "effort")):
            values = getattr(back, name)
            assert layout.counts[k] == len(values)
            for j in range(len(values)):
                assert doubles(block, layout.offsets[k] + 8 * j, layout.endian)[0] == values[j]


def test_messages_of_changing_layout_match_a_plain_rosbags_loop(tmp_path):
    # Joint order, joint set and frame_id change from message to message; the block reader must find the
    # joint in every one, exactly as deserialising each message does.
    from rosbags.highlevel import AnyReader

    kind = "sqlite3"
    store = typestore(kind)
    rng = np.random.default_rng(3)
    path = bag_path(tmp_path, "mixed", kind)
    with BagWriter(path, kind) as bag:
        bag.add_topic("/joint_states")
        for i in range(5000):
            names = ["a", "bb", "target"] if (i // 700) % 2 else ["target", "a"]
            if i % 97 == 0:
                names = ["a", "bb"]  # the joint left out
            frame = "f" * (i // 1000)
            values = [rng.normal(size=len(names)) for _ in range(3)]
            message = joint_state(store, 10**9 + i * 1_000_000, names, *values, frame_id=frame)
            bag.write("/joint_states", 10**9 + i * 1_000_000, serialize(store, kind, message))
    expected = {"q": [], "qd": [], "tau": []}
    with AnyReader([path]) as reader:
        for connection, _, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            if "target" in message.name:
                j = message.name.index("target")
                for key, field in (("q", "position"), ("qd", "velocity"), ("tau", "effort")):
                    expected[key].append(getattr(message, field)[j])
    table = read_bag_table(path, "target")
    for key in expected:
        assert np.array_equal(table.columns[key], np.array(expected[key]))
    assert any("joint 'target' is in 4948 of the 5000 messages" in note for note in table.notes)


def test_bag_info_and_read_agree_on_the_model_values(bags):
    # The values read are the model's own, at the stamps written: nothing resampled yet.
    table = read_bag_table(bags["ros1", True], "shoulder")
    t = jittered_times(DURATION, RATE, 0.05)
    q, qd, tau = two_joints(t)["shoulder"]
    assert np.allclose(table.columns["t"], t, atol=1e-9)
    assert np.array_equal(table.columns["q"], q) and np.array_equal(table.columns["tau"], tau)
    q_model, qd_model, qdd_model = rich(t)
    clean = TRUE["I"] * qdd_model + TRUE["h"] * G * np.cos(q_model) + TRUE["B"] * qd_model
    assert np.abs(table.columns["tau"] - clean).max() <= NOISE_BOUND
    info = bag_info(bags["ros1", True])
    assert [j.name for j in info.joint_states[0].joints] == ["shoulder", "elbow"]
