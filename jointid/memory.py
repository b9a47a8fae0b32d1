"""How much memory the machine can give a new allocation now: what a large fit checks before it starts."""

from __future__ import annotations

import os


def available_memory() -> int:
    """Bytes of memory available for new allocations now (Linux's MemAvailable; elsewhere all physical memory)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def in_words(size: int) -> str:
    """A byte count as a reader says it: '860 MB', '2.4 GB'."""
    return f"{size / 1e9:.1f} GB" if size >= 1e9 else f"{max(1, round(size / 1e6)):,} MB"
