"""Large results in reused memory (batches', and one state's from 64 KiB): the buffers of results dropped.

A fresh array above 128 KiB comes from ``mmap``, and freed heap memory above 128 KiB goes back (glibc): the kernel
faults in and zeroes every page at the first write, so a loop of batches paid ~5 µs a talos state, more than the
derivative kernels. Like the array libraries' caching allocators, the batches keep their results' buffers: a
result is a view of a buffer held here; once the caller holds no view of it (its reference count is back to the
pool's own: a slice, a ``memoryview`` or a reshape all hold it), the next result of its size reuses it.

Kept: buffers of at least ``MIN_BYTES`` (64 KiB; panda's frame-derivative batch of six 110 kB results, 3.3 → 1.3 µs
a state), ``PER_SIZE`` of a size at most, all together (held or free) within :func:`set_result_cache_size`
(``DEFAULT_BYTES``; 0: no reuse). Every batch writes every entry of its results, so nothing of an earlier result
shows through. See docs/architecture.md, "Results of batched calls".
"""

from __future__ import annotations

import math
import os
import sys
import threading

import numpy as np

MIN_BYTES = 64 << 10
PER_SIZE = 8  # kept of one size: beyond, a caller keeping every result gets fresh memory (and the search stays short)
DEFAULT_BYTES = 256 << 20

_lock = threading.Lock()
_buffers: dict[int, list[np.ndarray]] = {}  # kept buffers by their size in entries, least recently handed out first
_limit = DEFAULT_BYTES
_getrefcount = sys.getrefcount
_empty = np.empty


def _after_fork_in_child() -> None:
    # another thread of the parent may have held the lock at the fork: the child gets a fresh one
    global _lock
    _lock = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def _free(same_size: list[np.ndarray], i: int) -> bool:
    return _getrefcount(same_size[i]) <= 2  # nobody holds it but the list (and getrefcount's argument)


def _release(limit: int) -> int:
    """Drop free buffers (sizes kept longest first, each's oldest first) till ``limit`` bytes are kept; the bytes kept."""
    kept = sum(b.nbytes for same_size in _buffers.values() for b in same_size)
    for same_size in _buffers.values():
        i = 0
        while kept > limit and i < len(same_size):
            if _free(same_size, i):
                kept -= same_size.pop(i).nbytes
            else:
                i += 1
    return kept


def result_array(shape: tuple[int, ...]) -> np.ndarray:
    """A float64 C-contiguous array of ``shape`` for a batch or one state (run_fresh) to fill: reused if free."""
    n = math.prod(shape)
    nbytes = 8 * n
    if nbytes < MIN_BYTES or nbytes > _limit:
        return _empty(shape)
    with _lock:
        same_size = _buffers.get(n, [])
        for i in range(len(same_size)):
            if _free(same_size, i):
                same_size.append(same_size.pop(i))  # most recently handed out last
                return same_size[-1].reshape(shape)
        if len(same_size) < PER_SIZE and _release(_limit - nbytes) + nbytes <= _limit:  # (else nothing is dropped)
            _buffers.setdefault(n, []).append(_empty(n))
            return _buffers[n][-1].reshape(shape)
        return _empty(shape)


def set_result_cache_size(nbytes: int) -> None:
    """Bytes the batched calls may keep to reuse for their large results (default 256 MiB); 0: never reuse.

    A batch result of at least 64 KiB is a view of a kept buffer, which the next result of its size reuses once the
    caller drops every view of it (new pages are zeroed at first touch, which costs more than a derivative batch).
    The limit counts buffers the caller still holds; free ones beyond a new limit are released at once.
    """
    global _limit
    from ..errors import BackendError, DTypeError

    if isinstance(nbytes, bool) or not isinstance(nbytes, (int, np.integer)):
        raise DTypeError(f"nbytes: expected an integer number of bytes, got {type(nbytes).__name__} {nbytes!r}")
    if nbytes < 0:
        raise BackendError(f"nbytes: expected a number of bytes >= 0, got {nbytes}")
    with _lock:
        _limit = int(nbytes)
        _release(_limit)
        if _limit == 0:
            _buffers.clear()  # buffers the caller holds stay theirs; none is handed out again


def result_cache_info() -> dict[str, int]:
    """``{"limit": bytes, "kept": bytes, "free": bytes, "buffers": count}`` of the kept result buffers."""
    with _lock:
        kept, free = (sum(b[i].nbytes for b in _buffers.values() for i in range(len(b)) if every or _free(b, i))
                      for every in (True, False))
        return {"limit": _limit, "kept": kept, "free": free, "buffers": sum(len(b) for b in _buffers.values())}
