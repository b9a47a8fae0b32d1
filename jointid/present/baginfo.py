"""What `jointid bag-info` prints, and the joint lines the explorer's joint picker shows."""

from __future__ import annotations

from .text import COLUMN_GAP


def joint_line(joint) -> str:
    """"shoulder: position, velocity, effort (10000 messages)" for a bag.JointFields."""
    return f"{joint.name}: {joint.fields_text()} ({joint.messages} messages)"


def topic_timing_text(topic) -> str:
    """Rate, steps, jitter and duration of a bag.JointStateTopic, in one sentence."""
    if topic.median_step is None:
        return f"{topic.messages} message(s); too few to give a rate"
    return (f"{topic.messages} messages over {topic.duration:.6g} s at {topic.rate:.6g} Hz; step median "
            f"{topic.median_step * 1e3:.6g} ms, min {topic.min_step * 1e3:.6g} ms, max {topic.max_step * 1e3:.6g} ms "
            f"(jitter {topic.jitter:.1%}); time from {topic.time_source}")


def _columns(header: list[str], rows: list[list[str]], counts: int) -> str:
    """Rows under a header, names left-aligned and the message counts (column `counts`) right-aligned."""
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    return "\n".join(
        COLUMN_GAP.join(cell.rjust(w) if i == counts else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths)))
        .rstrip() for row in table)


def bag_info_text(info) -> str:
    """The text of `jointid bag-info` for a bag.BagInfo."""
    topics = f"{len(info.topics)} topic" + ("" if len(info.topics) == 1 else "s")
    lines = [f"{info.path}: {info.kind} bag, {info.duration:.6g} s, {topics}", ""]
    lines.append(_columns(["topic", "type", "messages"], [[t, m, str(n)] for t, m, n in info.topics], 2))
    if not info.joint_states:
        lines += ["", "No sensor_msgs/JointState topic: nothing jointid can fit."]
    for topic in info.joint_states:
        lines += ["", f"JointState {topic.name}: {topic_timing_text(topic)}."]
        if topic.first_mismatch is not None:
            number, problem = topic.first_mismatch
            lines.append(f"Left out of the joints below, with arrays of other lengths than their joint names: "
                         f"{topic.mismatched:,} of {topic.messages:,} messages (first: message {number}, {problem}).")
        rows = [[j.name, str(j.messages), j.fields_text()] for j in topic.joints]
        lines.append(_columns(["joint", "messages", "filled fields"], rows, 1))
    return "\n".join(lines)
