"""The MJCF loader's two readers side by side: the fast path (``featherdyn._mjcf_native``) and the Python reader.

:func:`outcome` loads a document one way and records everything a user sees:
the model's every array and name (bit for bit: the bytes of each array), its
frames with their placements, the warnings, or the exception's type and
message. The fast path must give the Python reader's outcome exactly.
"""

from __future__ import annotations

import contextlib
import warnings
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

import featherdyn as fd
from featherdyn import mjcf


@contextlib.contextmanager
def python_reader_only() -> Iterator[None]:
    """Within: ``load_mjcf`` reads with the Python reader alone (as a source tree without the build)."""
    saved = mjcf._mjcf_native
    mjcf._mjcf_native = None
    try:
        yield
    finally:
        mjcf._mjcf_native = saved


def snapshot(model: fd.Model) -> dict[str, Any]:
    """Every attribute of a model, arrays as ``(shape, dtype, bytes)``: equal snapshots mean the same model."""

    def arr(x: Any) -> tuple[Any, ...]:
        a = np.asarray(x)
        return a.shape, str(a.dtype), a.tobytes()

    out: dict[str, Any] = {k: getattr(model, k) for k in ("name", "parents", "joint_names", "body_names", "idx_q",
                                                             "nqs", "idx_v", "nvs", "source")}
    out["joints"] = [(type(j).__name__, arr(getattr(j, "axis", ()))) for j in model.joints]
    X, inertia = model.joint_placements, model.inertias
    out["placements"] = arr(X.rotation), arr(X.translation)
    out["inertias"] = arr(inertia.mass), arr(inertia.com), arr(inertia.inertia_com)
    for k in ("gravity", "lower", "upper", "velocity_limit", "effort_limit", "armature"):
        out[k] = arr(getattr(model, k))
    out["frames"] = [(f.name, f.body, f.kind, arr(f.placement.rotation), arr(f.placement.translation))
                     for f in model.frames]
    return out


def outcome(source: Any, *, fast: bool, strict: bool = False) -> tuple[Any, ...]:
    """``("model", snapshot, warnings)`` or ``("error", type name, message)`` of ``fd.load_mjcf(source)``, by the
    fast path (``fast=True``, the default reader) or by the Python reader alone."""
    with contextlib.ExitStack() as stack:
        if not fast:
            stack.enter_context(python_reader_only())
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                model = fd.load_mjcf(source, strict=strict)
            except Exception as exc:
                return "error", type(exc).__name__, str(exc)
        return "model", snapshot(model), [(w.category.__name__, str(w.message)) for w in caught]


def taken(text: str, strict: bool = False, path: Any = None) -> bool:
    """Whether the fast path reads ``text`` (of the file ``path``, if one) itself, rather than declining it to the
    Python reader."""
    from featherdyn._urdf_xml import _declaration_first

    assert mjcf._mjcf_native is not None
    files = mjcf._FastFiles(None if path is None else str(path))
    return mjcf._mjcf_native.read(_declaration_first(text), strict, files) is not None


def restructure(root: ET.Element, e: ET.Element, kind: str, pick: Callable[[list[Any]], Any],
                tags: list[str]) -> None:
    """A mutation fuzzer's structural edit of element ``e`` (not the root) of the tree ``root``: ``kind`` is
    ``"delete"``, ``"duplicate"`` (a copy appended to its parent), ``"move"`` (into another element chosen by
    ``pick``, unless that is inside ``e``) or ``"rename"`` (to a tag chosen by ``pick`` from ``tags``)."""
    parent = next(p for p in root.iter() if any(c is e for c in p))
    if kind == "delete":
        parent.remove(e)
    elif kind == "duplicate":
        parent.append(ET.fromstring(ET.tostring(e)))
    elif kind == "move":
        target = pick(list(root.iter()))
        if all(target is not d for d in e.iter()):
            parent.remove(e)
            target.append(e)
    else:
        e.tag = pick(tags)
