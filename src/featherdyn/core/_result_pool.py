"""Large batch results in reused memory: the buffers of results the caller has dropped.

A fresh array of tens of megabytes comes from ``mmap``: the kernel faults in and zeroes every page on the
first write, and ``free`` gives the pages back at once, so a loop calling a batch again pays it again (measured
on talos' derivative batches: ~5 µs per state, more than the kernels' own time). Like the caching allocators
of the array libraries, the batches therefore keep the buffers of their large results: a result is a view of
a buffer held here, and once the caller holds no view of it any more (its reference count is back to the
pool's own), the next result of the same size reuses it, with its pages already mapped.

Only buffers of at least ``MIN_BYTES`` are kept; all kept buffers together (held by the caller or free) stay
within the limit set by :func:`set_result_cache_size` (``DEFAULT_BYTES``; 0 turns the reuse off). Memory a
caller still holds is never handed out again: a view, a slice, a ``memoryview`` or a reshaped copy of the
result all reference the buffer. Every batch writes every entry of its results, so nothing of an earlier result
shows through. See docs/architecture.md, "Results of batched calls".
"""

from __future__ import annotations

import math
import os
import sys
import threading

import numpy as np

MIN_BYTES = 1 << 20
DEFAULT_BYTES = 256 << 20

_lock = threading.Lock()
_buffers: list[np.ndarray] = []  # least recently handed out first
_limit = DEFAULT_BYTES
_getrefcount = sys.getrefcount
_empty = np.empty


def _after_fork_in_child() -> None:
    # another thread of the parent may have held the lock at the fork: the child gets a fresh one
    global _lock
    _lock = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def _free(i: int) -> bool:
    """Whether nobody but this module references ``_buffers[i]``."""
    return _getrefcount(_buffers[i]) <= 2  # the list and getrefcount's argument


def _release(kept: int, limit: int) -> int:
    """Drop free buffers, oldest first, until at most ``limit`` bytes are kept; the bytes kept after."""
    i = 0
    while kept > limit and i < len(_buffers):
        if _free(i):
            kept -= _buffers.pop(i).nbytes
        else:
            i += 1
    return kept


def result_array(shape: tuple[int, ...]) -> np.ndarray:
    """A float64 C-contiguous array of ``shape`` for a batch to fill: reused memory when there is some."""
    n = math.prod(shape)
    nbytes = 8 * n
    if nbytes < MIN_BYTES or nbytes > _limit:
        return _empty(shape)
    with _lock:
        for i in range(len(_buffers)):
            if _buffers[i].size == n and _free(i):
                buf = _buffers.pop(i)
                _buffers.append(buf)  # most recently handed out last
                return buf.reshape(shape)
        kept = _release(sum(b.nbytes for b in _buffers) + nbytes, _limit) - nbytes
        new = _empty(n)
        if kept + nbytes <= _limit:
            _buffers.append(new)
        return new.reshape(shape)


def set_result_cache_size(nbytes: int) -> None:
    """Bytes the batched calls may keep to reuse for their large results (default 256 MiB); 0: never reuse.

    A batch result of at least 1 MiB is a view of a kept buffer; once the caller drops every view of it, the
    next result of the same size is written into it instead of into new pages (the operating system zeroes new
    pages on first touch, which costs more than computing a derivative batch). The limit counts buffers the
    caller still holds; free buffers beyond a new limit are released at once.
    """
    global _limit
    from ..errors import BackendError, DTypeError

    if isinstance(nbytes, bool) or not isinstance(nbytes, (int, np.integer)):
        raise DTypeError(f"nbytes: expected an integer number of bytes, got {type(nbytes).__name__} {nbytes!r}")
    if nbytes < 0:
        raise BackendError(f"nbytes: expected a number of bytes >= 0, got {nbytes}")
    with _lock:
        _limit = int(nbytes)
        _release(sum(b.nbytes for b in _buffers), _limit)
        if _limit == 0:
            _buffers.clear()  # buffers the caller holds stay theirs; none is handed out again


def result_cache_info() -> dict[str, int]:
    """``{"limit": bytes, "kept": bytes, "free": bytes, "buffers": count}`` of the kept result buffers."""
    with _lock:
        free = sum(_buffers[i].nbytes for i in range(len(_buffers)) if _free(i))
        return {"limit": _limit, "kept": sum(b.nbytes for b in _buffers), "free": free, "buffers": len(_buffers)}
