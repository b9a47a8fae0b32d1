"""WPILib data logs written byte by byte from the format's specification, and a corpus of damaged ones.

The specification is allwpilib's `wpiutil/doc/datalog.adoc` (version 1.0): a header of "WPILOG", the version
0x0100 (little endian: bytes 00 01), a 4-byte length and an extra header string; then records, each a header-length
byte (bits 0-1: entry id bytes - 1, bits 2-3: payload size bytes - 1, bits 4-6: time stamp bytes - 1), the entry id,
payload size and time stamp (little endian, in as few bytes as they need), and the payload. Entry 0 holds control
records: Start (0, entry id, name, type, metadata, each string a 4-byte length then its bytes), Finish (1, entry id)
and SetMetadata (2, entry id, metadata). Nothing here uses robotpy-wpiutil's writer, so a damaged log can hold
exactly the bytes a test asks for.
"""

from __future__ import annotations

import struct

CONTROL_START, CONTROL_FINISH, CONTROL_SET_METADATA = 0, 1, 2


def _varint(value: int, most: int) -> bytes:
    """`value` little endian in the fewest bytes (at least 1, at most `most`)."""
    length = max(1, (value.bit_length() + 7) // 8)
    assert length <= most, (value, most)
    return value.to_bytes(length, "little")


def header(extra: bytes = b"") -> bytes:
    """The file header: magic, version 1.0 and the extra header string's bytes."""
    return b"WPILOG" + struct.pack("<HI", 0x0100, len(extra)) + extra


def record(entry: int, timestamp: int, payload: bytes) -> bytes:
    """One record: the header-length bitfield byte, entry id, payload size, time stamp, payload."""
    fields = [_varint(entry, 4), _varint(len(payload), 4), _varint(timestamp, 8)]
    bits = (len(fields[0]) - 1) | (len(fields[1]) - 1) << 2 | (len(fields[2]) - 1) << 4
    return bytes([bits]) + b"".join(fields) + payload


def _string(data: bytes) -> bytes:
    return struct.pack("<I", len(data)) + data


def _bytes(text) -> bytes:
    return text if isinstance(text, bytes) else text.encode()


def start(entry: int, name, kind, metadata=b"", timestamp: int = 0) -> bytes:
    """A Start control record for `entry` (name, type and metadata as str, or as raw bytes)."""
    payload = bytes([CONTROL_START]) + struct.pack("<I", entry) + _string(_bytes(name)) + _string(_bytes(kind)) \
        + _string(_bytes(metadata))
    return record(0, timestamp, payload)


def finish(entry: int, timestamp: int = 0) -> bytes:
    """A Finish control record for `entry`."""
    return record(0, timestamp, bytes([CONTROL_FINISH]) + struct.pack("<I", entry))


def set_metadata(entry: int, metadata, timestamp: int = 0) -> bytes:
    """A SetMetadata control record for `entry`."""
    return record(0, timestamp, bytes([CONTROL_SET_METADATA]) + struct.pack("<I", entry) + _string(_bytes(metadata)))


def double(entry: int, timestamp: int, value: float) -> bytes:
    """A double data record (8 bytes, little endian IEEE 754)."""
    return record(entry, timestamp, struct.pack("<d", value))


def string(entry: int, timestamp: int, text) -> bytes:
    """A string data record (its bytes, no length: the payload size says it)."""
    return record(entry, timestamp, _bytes(text))


def joint_log(*, q_id: int = 1, tau_id: int = 2, q_name="q", tau_name="tau", q_unit="radians", extra=b"",
              samples: int = 40, tau_payload=None, first: bytes = b"") -> bytes:
    """A whole, valid log of two double entries (an angle and a torque) sampled together every 20 ms.

    `tau_payload`, when given, is the payload of every torque record instead of its 8-byte double; `first` are
    records put before all others.
    """
    out = [header(_bytes(extra)), first, start(q_id, q_name, "double", q_unit), start(tau_id, tau_name, "double")]
    for k in range(samples):
        stamp = 1_000_000 + 20_000 * k
        out.append(double(q_id, stamp, 0.5 * (k / samples) ** 2))
        out.append(record(tau_id, stamp, tau_payload) if tau_payload is not None
                   else double(tau_id, stamp, 1.0 + 0.01 * k))
    return b"".join(out)


NOT_UTF8 = b"\xff\xfe\xc3("
"""Bytes that are not UTF-8 (a lone 0xff, and a lead byte without its continuation)."""

DEEP_JSON = b'{"unit":' + b"[" * 200_000 + b"]" * 200_000 + b"}"
"""Unit metadata nested 200,000 deep: a JSON parser that recurses runs out of stack on it."""


def damaged_logs() -> dict[str, tuple[bytes, str]]:
    """{case: (bytes of the file, a word the one-line refusal must hold)}: each a log complete in its framing
    whose content is wrong in one way."""
    return {
        "extra-header-not-utf8": (joint_log(extra=NOT_UTF8), "UTF-8"),
        "entry-name-not-utf8": (joint_log(q_name=b"q" + NOT_UTF8), "UTF-8"),
        "entry-type-not-utf8": (joint_log(first=start(3, "x", b"dou" + NOT_UTF8)), "UTF-8"),
        "metadata-not-utf8": (joint_log(q_unit=b"rad" + NOT_UTF8), "UTF-8"),
        "set-metadata-not-utf8": (joint_log() + set_metadata(1, NOT_UTF8, 9_000_000), "UTF-8"),
        "string-record-not-utf8": (joint_log() + start(5, "sysid-test-state-arm", "string", "", 9_000_000)
                                   + string(5, 9_000_001, NOT_UTF8), "UTF-8"),
        "double-of-4-bytes": (joint_log(tau_payload=b"\x00\x00\x80\x3f"), "4 bytes"),
        "float-of-8-bytes": (b"".join([header(), start(1, "q", "double", "radians"), start(2, "tau", "float")]
                                      + [double(1, 1_000_000 + 20_000 * k, 0.01 * k)
                                         + record(2, 1_000_000 + 20_000 * k, struct.pack("<d", 1.0))
                                         for k in range(40)]), "8 bytes"),
        "unit-nested-200000-deep": (joint_log(q_unit=DEEP_JSON), "nested"),
    }
