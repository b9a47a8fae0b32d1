"""What `jointid bag-info` prints, and the joint lines the explorer's joint picker shows."""

from __future__ import annotations

from .text import text_table


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


def bag_info_text(info) -> str:
    """The text of `jointid bag-info` for a bag.BagInfo."""
    lines = [f"{info.path}: {info.kind} bag, {info.duration:.6g} s, {len(info.topics)} topic(s)", ""]
    lines.append(text_table(["topic", "type", "messages"], [[t, m, str(n)] for t, m, n in info.topics]))
    if not info.joint_states:
        lines += ["", "No sensor_msgs/JointState topic: nothing jointid can fit."]
    for topic in info.joint_states:
        lines += ["", f"JointState {topic.name}: {topic_timing_text(topic)}."]
        rows = [[j.name, str(j.messages), j.fields_text()] for j in topic.joints]
        lines.append(text_table(["joint", "messages", "filled fields"], rows))
    return "\n".join(lines)
