"""Dask arrays in, Dask arrays out (private; model layer, so that the configuration functions use it too):
the public functions over chunked batches.

A public function (``fd.rnea`` & co.) that receives a Dask array among its
state arguments hands the call to :func:`call`, which returns at once a result
of the same structure whose arrays are Dask arrays, computed lazily block by
block::

    τ = fd.rnea(model, q, v, a)          # q, v, a: dask arrays (N, nq), (N, nv), (N, nv) chunked along N
    τ.compute()                          # == fd.rnea(model, q.compute(), v.compute(), a.compute()), bit for bit

How (``docs/architecture.md``, "Dask"):

* **checked before any work**: one call of the function itself on a single
  state with the trailing shapes and dtype of the arguments (the neutral
  configuration, zero vectors) raises exactly what the NumPy call would raise
  for a wrong length, dtype, frame name or reference frame, and gives the
  structure of the result; chunks along a trailing (state) axis, unknown chunk
  sizes and batch shapes that do not broadcast raise :class:`ShapeError`;
* **one task per block**: the batch axes of all arguments are broadcast and
  their chunks aligned (``dask.array.blockwise``); each task calls the same
  public function on its NumPy block (the compiled core's batched path), so
  every state gets exactly the operations it gets in one NumPy call;
* **the model once**: the model is one key of the graph,
  ``featherdyn-model-<sha256 of its pickle>``, on which every block depends,
  so a distributed scheduler ships it once to each worker, not once per chunk;
* results with several arrays (tuples, :class:`~featherdyn.results.CenterOfMass`,
  :class:`~featherdyn.results.Kinematics`, spatial vectors and transforms,
  the constrained-dynamics results) come back with the same structure, each
  array a Dask array sliced from one packed block result.

Dask is imported only when a Dask array arrives: ``import featherdyn`` never imports it.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import math
import pickle
import re
from collections.abc import Callable
from typing import Any

import numpy as np

from .errors import DTypeError, FeatherdynError, ShapeError
from .model import Model

__all__ = ["lazy", "call", "model_key"]

#: number of trailing (state) axes of each state argument of the public functions
_CORE_NDIM = {"q": 1, "q0": 1, "q1": 1, "v": 1, "a": 1, "tau": 1, "w": 1, "W": 2, "f_ext": 2, "point": 1}
#: the arguments that are configurations (their single-state stand-in is the neutral configuration)
_CONFIGURATIONS = ("q", "q0", "q1")
#: the state index in the words of featherdyn's errors ("… at index (4, 2)")
_AT_INDEX = re.compile(r"at index \((\d+(?:, \d+)*)\)")


def _is_dask(x: Any) -> bool:
    t = type(x)
    return t.__name__ == "Array" and t.__module__.startswith("dask.")


def lazy(*xs: Any) -> bool:
    """Whether any of ``xs`` is a Dask array (without importing Dask)."""
    return any(_is_dask(x) for x in xs)


def model_key(model: Model) -> str:
    """The graph key of ``model``: ``featherdyn-model-`` and the SHA-256 of its pickle."""
    return "featherdyn-model-" + hashlib.sha256(pickle.dumps(model, protocol=5)).hexdigest()


# --------------------------------------------------------------------------
# results as trees of arrays
# --------------------------------------------------------------------------


def _is_record(x: Any) -> bool:
    """A result record whose fields may hold arrays: a dataclass instance other than the model, or a record that
    names its fields (``FIELDS``: :class:`~featherdyn.results.Kinematics`)."""
    return (dataclasses.is_dataclass(x) or hasattr(type(x), "FIELDS")) and not isinstance(x, (type, Model))


def _fields(x: Any) -> tuple[str, ...]:
    return tuple(type(x).FIELDS) if hasattr(type(x), "FIELDS") else tuple(f.name for f in dataclasses.fields(x))


def _leaves(result: Any, out: list[np.ndarray]) -> None:
    """Append the arrays of ``result`` to ``out`` depth-first (the order :func:`_rebuild` reads them)."""
    if isinstance(result, (np.ndarray, np.generic)):
        out.append(np.asarray(result))
    elif _is_record(result):
        for name in _fields(result):
            _leaves(getattr(result, name), out)
    elif isinstance(result, (tuple, list)):
        for item in result:
            _leaves(item, out)


def _rebuild(meta: Any, arrays: list[Any]) -> Any:
    """``meta`` with its arrays replaced, in order, by those popped from the front of ``arrays``."""
    if isinstance(meta, (np.ndarray, np.generic)):
        return arrays.pop(0)
    if _is_record(meta) and hasattr(type(meta), "FIELDS"):
        return type(meta)(*(_rebuild(getattr(meta, name), arrays) for name in _fields(meta)))
    if _is_record(meta):
        obj = object.__new__(type(meta))
        for f in dataclasses.fields(meta):  # frozen, slotted dataclasses: set the fields as their __init__ would
            object.__setattr__(obj, f.name, _rebuild(getattr(meta, f.name), arrays))
        return obj
    if isinstance(meta, tuple):
        items = [_rebuild(item, arrays) for item in meta]
        return type(meta)(*items) if hasattr(meta, "_fields") else tuple(items)
    if isinstance(meta, list):
        return [_rebuild(item, arrays) for item in meta]
    return meta


def _block(fn: Callable[..., Any], names: tuple[str, ...], kwargs: dict[str, Any], batch_ndim: int,
           packed: bool, dtype: np.dtype, model: Model, *blocks: np.ndarray) -> np.ndarray:
    """One task: ``fn`` on one block of states, its result's arrays packed along one last axis.

    ``blocks`` ends with one block of ``arange`` per batch axis: where the block starts in the batch.
    """
    states = blocks[: len(names)]
    try:
        result = fn(model, **dict(zip(names, states, strict=True)), **kwargs)
    except FeatherdynError as error:
        offsets = tuple(int(r[0]) for r in blocks[len(names):] if len(r))
        raise _block_errors(error, offsets) from None
    arrays: list[np.ndarray] = []
    _leaves(result, arrays)
    if not packed:
        return arrays[0]
    batch = states[0].shape[:batch_ndim]
    return np.concatenate([np.asarray(x, dtype=dtype).reshape(batch + (-1,)) for x in arrays], axis=-1)


# --------------------------------------------------------------------------
# the call
# --------------------------------------------------------------------------


def _stand_in(model: Model, name: str, x: Any, rng: np.random.Generator) -> np.ndarray:
    """One state with the trailing shape and dtype of argument ``x``: a random configuration or vector.

    Random rather than neutral: the neutral configuration is often singular (a
    stretched arm's operational-space inertia, dependent contacts).
    """
    k = _CORE_NDIM[name]
    shape = tuple(x.shape[-k:]) if x.ndim >= k else tuple(x.shape)
    if name in _CONFIGURATIONS and shape == (model.nq,):
        # joint by joint within the limits, as fd.random_configuration (which lives in configuration.py, a user
        # of this module)
        q = np.empty(model.nq)
        for i, joint in enumerate(model.joints):
            sq = slice(model.idx_q[i], model.idx_q[i] + joint.nq)
            q[sq] = joint.random(rng, model.lower[sq], model.upper[sq], ())
        return q.astype(x.dtype)
    return rng.standard_normal(shape).astype(x.dtype)


def _first_state(name: str, x: Any) -> np.ndarray:
    """The first state of argument ``x`` (computed: a Dask array's first block is read)."""
    k = _CORE_NDIM[name]
    first = x[(0,) * max(x.ndim - k, 0)]
    return np.asarray(first.compute() if _is_dask(first) else first)


def _structure(fn: Callable[..., Any], model: Model, arrays: dict[str, Any], nones: dict[str, None],
               kwargs: dict[str, Any]) -> Any:
    """``fn`` on one state shaped like the arguments: what NumPy would raise, else the result's structure.

    A stand-in state that meets a value-dependent error (a singular matrix, dependent constraints)
    is replaced by the arguments' first state; a shape error is raised as the full-shape call
    raises it (zero-stride stand-ins, no memory), so its message names the shapes given.
    """
    rng = np.random.default_rng(0)
    try:
        return fn(model, **{k: _stand_in(model, k, x, rng) for k, x in arrays.items()}, **nones, **kwargs)
    except (ShapeError, DTypeError):
        full = {k: np.broadcast_to(_stand_in(model, k, x, rng), x.shape) for k, x in arrays.items()}
        fn(model, **full, **nones, **kwargs)  # raises the NumPy call's words
        raise
    except (FeatherdynError, np.linalg.LinAlgError):
        return fn(model, **{k: _first_state(k, x) for k, x in arrays.items()}, **nones, **kwargs)


def _block_errors(error: Exception, offsets: tuple[int, ...]) -> Exception:
    """``error`` raised in a block, its ``at index (i, j, …)`` moved from block to whole-batch indices."""
    message = str(error)
    match = _AT_INDEX.search(message)
    if not offsets or match is None:
        return error
    index = [int(i) for i in match.group(1).split(",")]
    if len(index) < len(offsets):
        return error
    index[: len(offsets)] = [i + o for i, o in zip(index, offsets, strict=False)]
    moved = copy.copy(error)
    moved.args = (message[: match.start(1)] + ", ".join(map(str, index)) + message[match.end(1):],) + error.args[1:]
    return moved


def call(fn: Callable[..., Any], model: Model, states: dict[str, Any], **kwargs: Any) -> Any:
    """``fn(model, **states, **kwargs)`` over Dask arrays: the result's structure, with Dask arrays.

    Args:
        fn: the public function (called on NumPy blocks, and once on a single state to check).
        model: the model (one key of the graph).
        states: the state arguments by name (``q``, ``v``, ``a``, ``tau``, ``f_ext``, ``q0``, ``q1``):
            Dask or NumPy arrays (or anything ``np.asarray`` takes) with batch axes leading; ``None``
            entries are passed on as ``None``.
        kwargs: the other arguments (frames, reference frames, flags), passed to every block.

    Raises:
        ShapeError: a state argument chunked along a trailing (state) axis, chunks of unknown size,
            batch shapes that do not broadcast; and whatever ``fn`` raises for the arguments' trailing
            shapes, dtypes and the other arguments, before any block is computed.
    """
    import dask
    import dask.array as da

    given = {k: x for k, x in states.items() if x is not None}
    arrays: dict[str, Any] = {k: x if _is_dask(x) else np.asarray(x) for k, x in given.items()}
    # 1. one state through the function itself: the NumPy path's errors, and the result's structure
    meta = _structure(fn, model, arrays, {k: None for k in states if k not in given}, kwargs)
    leaves: list[np.ndarray] = []
    _leaves(meta, leaves)
    # 2. batch axes: broadcast shapes, chunks only along them
    batch_shapes = []
    for name, x in arrays.items():
        k = _CORE_NDIM[name]
        batch_shapes.append(tuple(x.shape[: x.ndim - k]))
        if _is_dask(x):
            if any(math.isnan(c) for cs in x.chunks for c in cs):
                raise ShapeError(f"{name}: a Dask array with chunks of unknown size; call compute_chunk_sizes() first")
            split = [i for i in range(x.ndim - k, x.ndim) if len(x.chunks[i]) > 1]
            if split:
                raise ShapeError(
                    f"{name}: a Dask array may be chunked only along its batch axes; its trailing "
                    f"{'axis' if k == 1 else 'axes'} {tuple(x.shape[x.ndim - k:])} "
                    f"{'is' if k == 1 else 'are'} split into chunks {[x.chunks[i] for i in split]}: "
                    f"rechunk with {{{', '.join(f'{i}: -1' for i in range(x.ndim - k, x.ndim))}}}")
    try:
        batch = np.broadcast_shapes(*batch_shapes)
    except ValueError:
        raise ShapeError(f"batch shapes do not broadcast ({', '.join(map(str, batch_shapes))})") from None
    nb = len(batch)
    # 3. one blockwise over aligned batch chunks
    batch_index = tuple(f"b{i}" for i in range(nb))
    args: list[Any] = []
    names = tuple(arrays)
    for name, x in arrays.items():
        k = _CORE_NDIM[name]
        core = tuple(x.shape[x.ndim - k:])
        xd = x if _is_dask(x) else da.from_array(x, chunks=-1)
        if tuple(xd.shape) != batch + core:
            xd = da.broadcast_to(xd, batch + core)
        args += [xd, batch_index + tuple(f"{name}{j}" for j in range(k))]
    # aligned chunks now (not inside blockwise), so that the block offsets below are made in the same chunks
    chunkss, aligned = da.core.unify_chunks(*args)
    args = [item for x, ind in zip(aligned, args[1::2], strict=True) for item in (x, ind)]
    for i in range(nb):  # where each block starts, for the errors raised in it: made per block, never moved
        args += [da.arange(batch[i], chunks=(chunkss[batch_index[i]],)), (batch_index[i],)]
    packed = len(leaves) != 1
    dtype = np.result_type(*leaves) if leaves else np.dtype(np.float64)
    if packed:
        size = sum(int(x.size) for x in leaves)
        out_index = batch_index + ("c0",)
        new_axes = {"c0": size}
    else:
        out_index = batch_index + tuple(f"c{j}" for j in range(leaves[0].ndim))
        new_axes = {f"c{j}": n for j, n in enumerate(leaves[0].shape)}
    model_node = dask.delayed(model, pure=True, name=model_key(model), traverse=False)
    name = f"featherdyn-{fn.__name__}-" + dask.base.tokenize(fn.__name__, model_node.key, args, kwargs)
    out = da.blockwise(_block, out_index, fn, None, names, None, kwargs, None, nb, None, packed, None, dtype, None,
                       model_node, None, *args, new_axes=new_axes, dtype=dtype, name=name,
                       align_arrays=False, concatenate=True, meta=np.empty((0,) * len(out_index), dtype=dtype))
    if not packed:
        return _rebuild(meta, [out])
    lazy_leaves = []
    offset = 0
    for x in leaves:
        part = out[..., offset: offset + x.size]
        offset += x.size
        lazy_leaves.append(part.reshape(batch + x.shape).astype(x.dtype, copy=False))
    return _rebuild(meta, lazy_leaves)
