"""Memory sampling: resident memory (``/proc/self/statm``), glibc's ``malloc_trim`` and the
live heap from glibc's ``mallinfo2`` (through ctypes; skipped with a note without glibc or
before 2.33).

The live heap (in-use chunks ``uordblks`` plus mmapped blocks ``hblkhd``, over every arena)
is bytes still allocated: the leak check. RSS after ``malloc_trim(0)`` also counts the heap's
fragmentation: freed chunks glibc cannot return because live ones share their pages. Python's
small objects live in pymalloc's own arenas, outside malloc: ``sys.getallocatedblocks()`` is
printed beside them.
"""

from __future__ import annotations

import os
from typing import Any

from tactile_search import _core


def rss_bytes() -> int:
    """Resident set size of this process now (``/proc/self/statm``; else the peak)."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:  # not Linux: the peak so far is the best the standard library has
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _malloc_trim() -> Any:
    """glibc's ``malloc_trim`` (returns freed heap pages to the system), or None."""
    try:
        import ctypes

        return ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None


MALLOC_TRIM = _malloc_trim()


def live_rss_bytes() -> int:
    """RSS after glibc's ``malloc_trim(0)``: without the free memory the allocator can hand
    back (free pages in its per-thread arenas; the core's worker threads free big GPIS
    buffers there). What stays is memory in use plus the heap's fragmentation: free chunks
    the allocator cannot return because live ones sit on the same pages. Plain RSS where
    there is no glibc."""
    if MALLOC_TRIM is not None:
        MALLOC_TRIM(0)
    return rss_bytes()


def _mallinfo2() -> Any:
    """glibc's ``mallinfo2`` (glibc >= 2.33) through ctypes, or None."""
    try:
        import ctypes

        class MallInfo2(ctypes.Structure):
            _fields_ = [
                (name, ctypes.c_size_t)
                for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                             "fsmblks", "uordblks", "fordblks", "keepcost")
            ]  # fmt: skip

        function = ctypes.CDLL("libc.so.6").mallinfo2
        function.restype = MallInfo2
        function.argtypes = []
        return function
    except (OSError, AttributeError):
        return None


MALLINFO2 = _mallinfo2()
#: Why the live heap is not measured (None when it is).
LIVE_HEAP_NOTE = (
    None
    if MALLINFO2 is not None
    else "no glibc mallinfo2 here (not glibc, or glibc < 2.33): live heap not measured"
)


def live_heap_bytes() -> int:
    """Bytes the program holds from its allocators now: glibc's ``mallinfo2`` (summed over
    every arena) in-use chunks ``uordblks`` plus directly mmapped blocks ``hblkhd``, plus the
    Rust core's live blocks, which its own allocator counts (``_core.allocated_bytes()``:
    the core's blocks come from mimalloc, which glibc does not see); -1
    without glibc. Unlike RSS it does not count free memory an allocator keeps or cannot
    return (fragmentation), so growth here is memory still referenced: a leak. It covers
    the Rust core, numpy's buffers and Python's large objects; Python's small objects live
    in pymalloc's own mmapped arenas (``sys.getallocatedblocks()``, printed beside it)."""
    if MALLINFO2 is None:
        return -1
    info = MALLINFO2()
    return int(info.uordblks + info.hblkhd) + _core.allocated_bytes()
