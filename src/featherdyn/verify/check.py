"""``featherdyn check``: the user's own numbers checked against featherdyn, with a diagnosis of any mismatch.

The values (from the user's code, another library or a log) are arrays named

=======  =====================  ==================================================
key      shape                  compared with
=======  =====================  ==================================================
``q``    `(nq,)` or `(N, nq)`   (input; always required)
``v``    `(nv,)` or `(N, nv)`   (input; required with ``tau`` or ``ddq``)
``a``    `(nv,)` or `(N, nv)`   (input; required with ``tau`` unless ``ddq`` is given)
``tau``  `(nv,)` or `(N, nv)`   ``fd.rnea(q, v, a)`` (when ``a`` is given)
``M``    `(nv, nv)` or ...      ``fd.crba(q)``
``ddq``  `(nv,)` or `(N, nv)`   forward dynamics: ``tau`` vs ``fd.rnea(q, v, ddq)``
=======  =====================  ==================================================

in the featherdyn convention (``DESIGN.md``) or in Pinocchio's (``q`` with
continuous joints as ``(cos θ, sin θ)``, joints in Pinocchio's order, the
free-flyer velocity ``[v; ω]`` LOCAL), one state or a batch along a leading axis.
Each quantity is compared with the relative error ``|a − b| / max(|b|, 1)``
per state (``b`` = featherdyn's value, :func:`~featherdyn.verify.compare`).
Forward dynamics (``ddq`` for ``tau``) is judged by its backward error, the
joint forces ``fd.rnea(q, v, ddq)`` against ``tau``: comparing ``fd.aba(q, v,
tau)`` with ``ddq`` directly would amplify the round-off of a float32 ``tau``
by the condition number of ``M`` (1e4 and more on arms with light fingers).

On a mismatch the usual suspects are tried, alone and in pairs, and every
reading of the values under which *all* comparisons pass is reported:

* ``swapped_6d_halves``: the free-flyer block of ``v``, ``a``, ``tau``, ``ddq``
  (and of ``M``) has its 6D halves swapped (linear first vs angular first);
* ``world_frame_base_velocity``: the free-flyer velocity is world-aligned
  (Pinocchio's LOCAL_WORLD_ALIGNED) instead of in the base frame::

      v_b = [Rᵀω_w; Rᵀṗ],   a_b = [Rᵀω̇_w; Rᵀp̈ − ω_b × v_b],   τ_b = [Rᵀn_w; Rᵀf_w],   M_b = T M_w Tᵀ

* ``quaternion_wxyz``: quaternions (free-flyer, spherical) in ``(w, x, y, z)``
  order instead of ``(x, y, z, w)``;
* ``classical_base_acceleration``: the free-flyer acceleration is the classical
  one (``Rᵀp̈``) instead of the spatial one::

      a_spatial = a_classical − [0; ω × v]     (base coordinates)

* ``gravity``: computed with another gravity along the model's gravity axis
  (``−g``, ``0``, ``±9.8``, ``±9.80665``, ``±10``);
* ``continuous_layout``: continuous joints as ``(cos θ, sin θ)`` where the
  convention has the angle, or the reverse (told by the length of ``q``);
* ``joint_order``: joints in Pinocchio's (or featherdyn's), alphabetical or
  reversed order (a free-flyer stays first), inputs and outputs permuted;
* ``mass_matrix_triangle``: ``M`` holds only its upper (or lower) triangle.

Readings that change the *layout* of the user's arrays (joint order, 6D halves,
quaternion order, continuous joints, triangle) are applied in the user's own
layout, before the declared convention is converted to featherdyn's; the others
(frames, accelerations, gravity) in featherdyn's.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import json
import math
import os
import sys
import warnings
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DTypeError, FeatherdynError, ModelError, NonFiniteError, ShapeError
from ..joints import FreeFlyerJoint, PlanarJoint, RevoluteJoint, SphericalJoint
from ..model import Model
from .report import CheckResult, compare

__all__ = [
    "check_values",
    "CheckReport",
    "Finding",
    "ValuesError",
    "SUSPECTS",
    "DEFAULT_TOL",
    "CONVENTIONS",
    "add_check_subcommand",
    "cmd_check",
]

#: Default relative tolerance: loose enough for values saved as float32 or rounded in a log.
DEFAULT_TOL = 1e-6

CONVENTIONS = ("featherdyn", "pinocchio")

#: The suspects tried on a mismatch, by the name a :class:`Finding` reports.
SUSPECTS = (
    "swapped_6d_halves",
    "world_frame_base_velocity",
    "quaternion_wxyz",
    "classical_base_acceleration",
    "gravity",
    "continuous_layout",
    "joint_order",
    "mass_matrix_triangle",
)

_KEYS = ("q", "v", "a", "tau", "M", "ddq")
_VECTOR_KEYS = ("v", "a", "tau", "ddq")
_QUANTITIES = {
    "tau": "tau vs fd.rnea(q, v, a)",
    "M": "M vs fd.crba(q)",
    "ddq": "ddq: tau vs fd.rnea(q, v, ddq)",
}
_GRAVITY_MAGNITUDES = (9.8, 9.80665, 10.0)
_SWAP6 = np.array([3, 4, 5, 0, 1, 2])
_EXIT_OK, _EXIT_MISMATCH, _EXIT_USAGE = 0, 1, 2


class ValuesError(FeatherdynError, ValueError):
    """The values to check are unusable: no such file, not an ``.npz`` archive, or keys missing."""


# --------------------------------------------------------------------------
# the report
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Finding:
    """One reading of the values under which every comparison passes.

    Attributes:
        suspects: the suspect names (from :data:`SUSPECTS`) combined in this reading.
        explanation: what the values are, in words, and how to convert them.
        results: the corrected comparisons (all passed).
        details: the parameters of the reading (``gravity``, ``joint_order``, ``triangle``, ...).
    """

    suspects: tuple[str, ...]
    explanation: str
    results: tuple[CheckResult, ...]
    details: dict[str, Any] = field(default_factory=dict)

    @property
    def suspect(self) -> str:
        """The suspect names joined with ``" + "``."""
        return " + ".join(self.suspects)

    def to_dict(self) -> dict[str, Any]:
        return {
            "suspect": self.suspect,
            "suspects": list(self.suspects),
            "explanation": self.explanation,
            "details": self.details,
            "results": [_result_dict(r) for r in self.results],
        }


@dataclass
class CheckReport:
    """The outcome of :func:`check_values`.

    Attributes:
        title: one line naming the robot, the convention and the number of states.
        results: the comparisons of the values as given (group ``"check"``).
        diagnosis: the readings that explain a mismatch (empty when it passed
            or when no usual suspect explains it).
        summary: one line: all agree, the diagnosis, or where the largest discrepancy is.
        largest_discrepancy: where the values differ most when nothing explains
            them (quantity, state, index, joint, given and expected values).
        meta: robot, URDF, convention, tolerance, keys, versions.
    """

    title: str
    results: list[CheckResult] = field(default_factory=list)
    diagnosis: list[Finding] = field(default_factory=list)
    summary: str = ""
    largest_discrepancy: dict[str, Any] | None = None
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return bool(self.results) and all(r.passed for r in self.results)

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary of the whole report (infinities as strings)."""
        return {
            "title": self.title,
            "passed": self.passed,
            "summary": self.summary,
            "meta": self.meta,
            "results": [_result_dict(r) for r in self.results],
            "diagnosis": [f.to_dict() for f in self.diagnosis],
            "largest_discrepancy": self.largest_discrepancy,
        }

    def to_json(self, indent: int = 2) -> str:
        def default(o: Any) -> Any:
            if isinstance(o, (np.floating, np.integer, np.bool_)):
                return o.item()
            if isinstance(o, np.ndarray):
                return o.tolist()
            raise TypeError(type(o).__name__)

        return json.dumps(self.to_dict(), indent=indent, default=default, ensure_ascii=False)

    def to_text(self) -> str:
        """The plain-text report printed by ``featherdyn check``."""
        lines = [self.title, "", *_table(self.results), ""]
        if self.passed:
            lines.append(f"all {len(self.results)} comparisons agree within {self.meta.get('tol', 0):g}")
            return "\n".join(lines)
        if self.diagnosis:
            many = len(self.diagnosis) > 1
            lines.append("MISMATCH. " + ("Several readings explain the values equally well:" if many
                                         else "Diagnosis:"))
            for k, f in enumerate(self.diagnosis, 1):
                lines.append("")
                lines.append(f"{f'{k}. ' if many else ''}suspect: {f.suspect}")
                lines += [f"  {line}" for line in f.explanation.split("\n")]
                lines.append("  corrected comparison:")
                lines += [f"    {row}" for row in _table(list(f.results))]
        else:
            lines.append(f"MISMATCH: {self.summary}")
        return "\n".join(lines)


def _result_dict(r: CheckResult) -> dict[str, Any]:
    d = dataclasses.asdict(r)
    for k in ("max_abs", "max_rel"):
        if not math.isfinite(d[k]):  # JSON has no inf / nan
            d[k] = str(d[k])
    return d


def _table(results: list[CheckResult]) -> list[str]:
    head = ("quantity", "max abs err", "max rel err", "worst state", "result")
    rows = [(r.quantity, f"{r.max_abs:.2e}", f"{r.max_rel:.2e}", str(r.worst_sample),
             "pass" if r.passed else "FAIL" + (f" ({r.note})" if r.note else "")) for r in results]
    widths = [max(len(h), *(len(row[i]) for row in rows)) if rows else len(h) for i, h in enumerate(head)]
    widths[-1] = len(head[-1])
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    return [fmt.format(*head).rstrip(), fmt.format(*("-" * w for w in widths))] + [fmt.format(*row).rstrip()
                                                                                   for row in rows]


# --------------------------------------------------------------------------
# loading and validating the values
# --------------------------------------------------------------------------


def _load_npz(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    label = os.fspath(path)
    p = Path(label)
    if not p.exists():
        raise ValuesError(f"{label}: file not found")
    if p.is_dir():
        raise ValuesError(f"{label}: is a directory, expected an .npz file")
    try:
        loaded = np.load(p, allow_pickle=False)
    except PermissionError as exc:
        raise ValuesError(f"{label}: cannot read ({exc.strerror})") from None
    except (ValueError, OSError, EOFError, zipfile.BadZipFile):
        raise ValuesError(f"{label}: not an .npz archive of named arrays (save one with numpy.savez(file, q=..., "
                          "v=..., a=..., tau=...))") from None
    if not isinstance(loaded, np.lib.npyio.NpzFile):
        raise ValuesError(f"{label}: holds a single .npy array, expected an .npz archive of named arrays "
                          "(numpy.savez(file, q=..., v=..., a=..., tau=...))")
    out = {}
    with loaded:
        for key in loaded.files:
            try:
                out[key] = loaded[key]
            except ValueError:
                raise ValuesError(f"{label}: array {key!r} holds Python objects, expected numbers") from None
            except (OSError, EOFError, zipfile.BadZipFile):
                raise ValuesError(f"{label}: array {key!r} is corrupt") from None
    return out


@dataclass(frozen=True)
class _Given:
    """The validated user arrays, float64, each with a leading batch axis of length ``n``."""

    arrays: dict[str, np.ndarray]
    n: int
    batched: bool
    ignored: tuple[str, ...]
    dtypes: dict[str, str] = field(default_factory=dict)  # as given, before the cast to float64


def _numeric(key: str, x: Any) -> np.ndarray:
    try:
        arr = np.asarray(x)
    except Exception as exc:  # ragged lists and the like
        raise ShapeError(f"{key}: not an array of numbers ({exc})") from None
    if arr.dtype.kind not in "biuf":
        raise DTypeError(f"{key}: expected real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64)


def _validate(values: Mapping[str, Any], nq_allowed: dict[int, str], nv: int, other_base: tuple[int, int, str]
              ) -> _Given:
    """Check keys, shapes, batch sizes and finiteness; raise a one-line error naming the key and expected shape."""
    present = [k for k in _KEYS if k in values]
    ignored = tuple(sorted(str(k) for k in values if k not in _KEYS))
    have = f" (given: {', '.join(sorted(map(str, values))) or 'nothing'})"
    need = "expected q, v, a and any of tau, M, ddq (with tau)"

    def missing(key: str, why: str) -> ValuesError:
        return ValuesError(f"missing key {key!r}: {why}{have}")

    if "q" not in values:
        raise missing("q", "the configuration is always needed")
    if not any(k in values for k in ("tau", "M", "ddq")):
        raise ValuesError(f"nothing to check: {need}{have}")
    if "ddq" in values and "tau" not in values:
        raise missing("tau", "ddq is checked against the joint forces tau that produced it")
    if ("tau" in values or "ddq" in values) and "v" not in values:
        raise missing("v", "tau and ddq need the joint velocities")
    if "tau" in values and "a" not in values and "ddq" not in values:
        raise missing("a", "tau is compared with fd.rnea(q, v, a)")

    nq_text = " or ".join(f"{n} ({why})" if why else str(n) for n, why in nq_allowed.items())
    nq_main = next(iter(nq_allowed))
    o_nq, o_nv, o_flag = other_base
    arrays: dict[str, np.ndarray] = {}
    shapes: dict[str, tuple[int, ...]] = {}
    batch: dict[str, int | None] = {}
    dtypes: dict[str, str] = {}
    for key in present:
        dtypes[key] = str(np.asarray(values[key]).dtype)
        arr = _numeric(key, values[key])
        expected: tuple[int, ...]
        if key == "q":
            expected, unit = (nq_main,), f"nq={nq_text}"
            ok = arr.ndim in (1, 2) and arr.shape[-1] in nq_allowed
            hint = f" — {o_nq} is nq {o_flag}" if arr.ndim in (1, 2) and arr.shape[-1] == o_nq else ""
        elif key == "M":
            expected, unit = (nv, nv), f"nv={nv}"
            ok = arr.ndim in (2, 3) and arr.shape[-2:] == (nv, nv)
            hint = f" — {o_nv} is nv {o_flag}" if arr.ndim in (2, 3) and arr.shape[-1] == o_nv else ""
        else:
            expected, unit = (nv,), f"nv={nv}"
            ok = arr.ndim in (1, 2) and arr.shape[-1] == nv
            hint = f" — {o_nv} is nv {o_flag}" if arr.ndim in (1, 2) and arr.shape[-1] == o_nv else ""
        if not ok:
            dims = ", ".join(map(str, expected))
            one = f"({dims},)" if len(expected) == 1 else f"({dims})"
            raise ShapeError(f"{key}: expected shape {one} for one state or (N, {dims}) for a batch "
                             f"({unit}), got {tuple(arr.shape)}{hint}")
        is_batch = arr.ndim == len(expected) + 1
        if is_batch and arr.shape[0] == 0:
            raise ShapeError(f"{key}: empty batch (shape {tuple(arr.shape)})")
        bad = ~np.isfinite(arr)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            where = f"at state {idx[0]}, index {idx[1:] if len(idx) > 2 else idx[1]}" if is_batch else \
                f"at index {idx if len(idx) > 1 else idx[0]}"
            raise NonFiniteError(f"{key}: non-finite value {arr[idx]} {where}")
        batch[key] = arr.shape[0] if is_batch else None
        shapes[key] = tuple(arr.shape)
        arrays[key] = arr if is_batch else arr[None]
    sizes = set(batch.values())
    if len(sizes) > 1:
        if None in sizes:
            one = next(k for k, b in batch.items() if b is None)
            many = next(k for k, b in batch.items() if b is not None)
            raise ShapeError(f"{one} is one state (shape {shapes[one]}) but {many} is a batch of {batch[many]} "
                             f"(shape {shapes[many]}): give every array the same leading batch axis")
        a, b = sorted(sizes, key=lambda s: -1 if s is None else s)[:2]
        ka = next(k for k, s in batch.items() if s == a)
        kb = next(k for k, s in batch.items() if s == b)
        raise ShapeError(f"batch sizes differ: {ka} has {a} states, {kb} has {b} (the batch is the leading axis "
                         "of every array)")
    n = next(iter(sizes))
    return _Given(arrays, 1 if n is None else int(n), n is not None, ignored, dtypes)


# --------------------------------------------------------------------------
# layouts: how the user's arrays are read
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class _Block:
    """One joint in the declared convention's layout."""

    body: int       # featherdyn body index
    name: str
    kind: str
    q0: int         # start in the declared q
    nq: int
    v0: int         # start in the declared v
    nv: int
    angle: bool     # continuous revolute or planar: its angle may be given as (cos, sin) or the reverse
    quat_at: int | None  # offset of the quaternion inside the q block


@dataclass(frozen=True)
class _Hypothesis:
    """A reading of the user's values (all false / ``None``: as the declared convention says)."""

    cos_sin: bool = False
    order: str | None = None
    swap6: bool = False
    quat_wxyz: str | None = None  # "all" quaternions, or only the "free_flyer"'s
    world: bool = False
    classical: bool = False
    gravity: tuple[float, float, float] | None = None
    triangle: str | None = None

    def merged(self, **kw: Any) -> _Hypothesis:
        return dataclasses.replace(self, **kw)

    @property
    def suspects(self) -> tuple[str, ...]:
        names = [("continuous_layout", self.cos_sin), ("joint_order", self.order is not None),
                 ("swapped_6d_halves", self.swap6), ("quaternion_wxyz", self.quat_wxyz is not None),
                 ("world_frame_base_velocity", self.world), ("classical_base_acceleration", self.classical),
                 ("gravity", self.gravity is not None), ("mass_matrix_triangle", self.triangle is not None)]
        return tuple(n for n, on in names if on)


class _UnreadableError(Exception):
    """The values cannot be read under a hypothesis (wrong lengths)."""


class _Layout:
    """The declared convention's layout of q and v, joint by joint, and the other joint orders worth trying."""

    def __init__(self, model: Model, pin_model: Any, jmap: Any, convention: str, continuous: set[int]) -> None:
        self.model, self.pin_model, self.jmap, self.convention = model, pin_model, jmap, convention
        self.ff = next((i for i, j in enumerate(model.joints) if isinstance(j, FreeFlyerJoint)), None)
        self.blocks = self._declared_blocks(continuous)
        self.flip_nq = sum(self._flip_delta(b) for b in self.blocks)
        self.declared_nq = sum(b.nq for b in self.blocks)
        self.orders = self._order_candidates()

    def _declared_blocks(self, continuous: set[int]) -> list[_Block]:
        m = self.model
        blocks = []
        if self.convention == "featherdyn":
            for i, joint in enumerate(m.joints):
                blocks.append(_Block(i, m.joint_names[i], joint.kind, m.idx_q[i], m.nqs[i], m.idx_v[i], m.nvs[i],
                                     i in continuous or isinstance(joint, PlanarJoint), _quat_offset(joint)))
        else:
            pm = self.pin_model
            body_of = {e.pin_joint: e.fd_body for e in self.jmap.entries}
            for jid in sorted(body_of):
                i = body_of[jid]
                joint = m.joints[i]
                blocks.append(_Block(i, m.joint_names[i], joint.kind, int(pm.idx_qs[jid]), int(pm.nqs[jid]),
                                     int(pm.idx_vs[jid]), int(pm.nvs[jid]),
                                     i in continuous or isinstance(joint, PlanarJoint), _quat_offset(joint)))
        return blocks

    def _flip_delta(self, b: _Block) -> int:
        """How much longer the block's q is when its angle layout is flipped."""
        if not b.angle:
            return 0
        return 1 if self.convention == "featherdyn" else -1

    def _order_candidates(self) -> dict[str, tuple[int, ...]]:
        declared = tuple(b.body for b in self.blocks)
        names = self.model.joint_names
        head = tuple(i for i in declared if i == self.ff)
        rest = [i for i in declared if i != self.ff]
        cands: dict[str, tuple[int, ...]] = {}
        if self.convention == "featherdyn" and self.jmap is not None:
            cands["pinocchio"] = tuple(e.fd_body for e in sorted(self.jmap.entries, key=lambda e: e.pin_joint))
        elif self.convention == "pinocchio":
            cands["featherdyn"] = tuple(range(self.model.nbodies))
        cands["alphabetical"] = head + tuple(sorted(rest, key=lambda i: names[i]))
        cands["reverse"] = head + tuple(reversed(rest))
        out: dict[str, tuple[int, ...]] = {}
        for name, order in cands.items():
            if order != declared and order not in out.values():
                out[name] = order
        return out

    def order_of(self, h: _Hypothesis) -> list[_Block]:
        if h.order is None:
            return self.blocks
        by_body = {b.body: b for b in self.blocks}
        return [by_body[i] for i in self.orders[h.order]]


class _Checker(_Layout):
    """Compares the values under any reading (:class:`_Hypothesis`), caching readings and results."""

    def __init__(self, model: Model, pin_model: Any, jmap: Any, convention: str, continuous: set[int],
                 given: _Given, tol: float) -> None:
        super().__init__(model, pin_model, jmap, convention, continuous)
        self.given, self.tol = given, tol
        self._reads: dict[Any, Any] = {}
        self._results: dict[Any, CheckResult] = {}
        self._models: dict[Any, Model] = {}

    # ---- reading the user's arrays ------------------------------------------------------------------------

    def read(self, h: _Hypothesis) -> dict[str, np.ndarray]:
        """The user's arrays in featherdyn's convention under hypothesis ``h`` (featherdyn order, ``(N, ...)``)."""
        key = (h.cos_sin, h.order, h.swap6, h.quat_wxyz, h.world, h.classical, h.triangle)
        if key not in self._reads:
            try:
                self._reads[key] = self._read(h)
            except (_UnreadableError, FeatherdynError, ValueError) as exc:
                self._reads[key] = exc
        out = self._reads[key]
        if isinstance(out, Exception):
            raise out
        return out

    def _read(self, h: _Hypothesis) -> dict[str, np.ndarray]:
        g = self.given.arrays
        n = self.given.n
        order = self.order_of(h)
        # q, block by block in the user's order, into the declared layout
        q_user = g["q"]
        q_decl = np.zeros((n, self.declared_nq))
        pos = 0
        for b in order:
            length = b.nq + (self._flip_delta(b) if h.cos_sin else 0)
            seg = q_user[:, pos : pos + length].copy()
            pos += length
            if h.cos_sin and b.angle:
                seg = self._unflip_angle(b, seg)
            if b.quat_at is not None and (h.quat_wxyz == "all" or h.quat_wxyz == "free_flyer" == b.kind):
                o = b.quat_at
                seg[:, o : o + 4] = seg[:, [o + 1, o + 2, o + 3, o]]
            q_decl[:, b.q0 : b.q0 + b.nq] = seg
        if pos != q_user.shape[1]:
            raise _UnreadableError(f"q has length {q_user.shape[1]}, this reading needs {pos}")
        # v-like arrays: a permutation src with declared[k] = user[src[k]]
        nv = self.model.nv
        src = np.empty(nv, dtype=int)
        pos = 0
        for b in order:
            idx = np.arange(pos, pos + b.nv)
            pos += b.nv
            if h.swap6 and b.kind == "free_flyer":
                idx = idx[_SWAP6]
            src[b.v0 : b.v0 + b.nv] = idx
        out: dict[str, np.ndarray] = {}
        out["q"] = q_decl
        for k in _VECTOR_KEYS:
            if k in g:
                out[k] = g[k][:, src]
        if "M" in g:
            M = g["M"]
            if h.triangle == "upper":
                M = np.triu(M) + np.swapaxes(np.triu(M, 1), -1, -2)
            elif h.triangle == "lower":
                M = np.tril(M) + np.swapaxes(np.tril(M, -1), -1, -2)
            out["M"] = M[:, src][:, :, src]
        if self.convention == "pinocchio":
            jm = self.jmap
            out["q"] = jm.q_from_pin(out["q"])
            for k in _VECTOR_KEYS:
                if k in out:
                    out[k] = jm.v_from_pin(out[k])
            if "M" in out:
                out["M"] = jm.matrix_from_pin(out["M"])
        if h.world or h.classical:
            self._base_frame(out, h)
        return out

    def _unflip_angle(self, b: _Block, seg: np.ndarray) -> np.ndarray:
        """The block's q in the declared layout from the flipped one (cos/sin ↔ angle)."""
        if self.convention == "featherdyn":  # (cos, sin) given, angle wanted
            angle = np.arctan2(seg[:, -1], seg[:, -2])
            return np.concatenate([seg[:, :-2], angle[:, None]], axis=1)
        angle = seg[:, -1]  # angle given, (cos, sin) wanted
        return np.concatenate([seg[:, :-1], np.cos(angle)[:, None], np.sin(angle)[:, None]], axis=1)

    def _base_frame(self, out: dict[str, np.ndarray], h: _Hypothesis) -> None:
        """Free-flyer velocity, acceleration, wrench (and M) to featherdyn's base-frame spatial quantities."""
        from ..rotation import quat_to_matrix

        m, i = self.model, self.ff
        assert i is not None
        qs, vs = m.idx_q[i], m.idx_v[i]
        ang, lin = slice(vs, vs + 3), slice(vs + 3, vs + 6)

        def rt(x: np.ndarray) -> np.ndarray:  # Rᵀ x, per state
            return np.einsum("nji,nj->ni", R, x)

        R = quat_to_matrix(out["q"][:, qs + 3 : qs + 7], check_norm=False)
        if h.world:
            for k in ("v", "a", "tau", "ddq"):
                if k in out:
                    x = out[k].copy()
                    x[:, ang], x[:, lin] = rt(x[:, ang]), rt(x[:, lin])
                    out[k] = x
            if "M" in out:
                T = np.broadcast_to(np.eye(m.nv), out["M"].shape).copy()
                T[:, ang, ang] = np.swapaxes(R, -1, -2)
                T[:, lin, lin] = np.swapaxes(R, -1, -2)
                out["M"] = T @ out["M"] @ np.swapaxes(T, -1, -2)
        if "v" in out:  # accelerations given as d/dt of world-aligned (or classical) quantities
            omega, vel = out["v"][:, ang], out["v"][:, lin]
            for k in ("a", "ddq"):
                if k in out:
                    x = out[k].copy()
                    x[:, lin] -= np.cross(omega, vel)
                    out[k] = x

    # ---- comparing -----------------------------------------------------------------------------------------

    def model_for(self, h: _Hypothesis) -> Model:
        if h.gravity is None:
            return self.model
        if h.gravity not in self._models:
            self._models[h.gravity] = dataclasses.replace(self.model, gravity=np.array(h.gravity, dtype=float))
        return self._models[h.gravity]

    def quantities(self) -> list[str]:
        g = self.given.arrays
        out = []
        if "M" in g:
            out.append("M")
        if "tau" in g and "a" in g:
            out.append("tau")
        if "ddq" in g:
            out.append("ddq")
        return out

    @staticmethod
    def _relevant(h: _Hypothesis, quantity: str) -> _Hypothesis:
        if quantity == "M":
            return h.merged(classical=False, gravity=None)
        return h.merged(triangle=None)

    def result(self, h: _Hypothesis, quantity: str, group: str = "check") -> CheckResult:
        key = (self._relevant(h, quantity), quantity)
        if key not in self._results:
            self._results[key] = self._compute(key[0], quantity)
        r = self._results[key]
        return r if r.group == group else dataclasses.replace(r, group=group)

    def expected_and_given(self, h: _Hypothesis, quantity: str) -> tuple[np.ndarray, np.ndarray]:
        from .. import api as alg

        x = self.read(h)
        model = self.model_for(h)
        if quantity == "M":
            return alg.crba(model, x["q"]), x["M"]
        if quantity == "tau":
            return alg.rnea(model, x["q"], x["v"], x["a"]), x["tau"]
        # forward dynamics judged by its backward error: the force that ddq needs against the given tau
        # (comparing fd.aba(q, v, tau) with ddq would amplify round-off in tau by the condition number of M)
        return alg.rnea(model, x["q"], x["v"], x["ddq"]), x["tau"]

    def _compute(self, h: _Hypothesis, quantity: str) -> CheckResult:
        name = _QUANTITIES[quantity]
        try:
            expected, given = self.expected_and_given(h, quantity)
        except (_UnreadableError, FeatherdynError, ValueError) as exc:
            return CheckResult("check", name, math.inf, math.inf, 0, self.tol, False, _one_line(exc))
        return compare("check", name, given, expected, self.tol, "")

    def explains(self, h: _Hypothesis) -> bool:
        return all(self.result(h, q).passed for q in self.quantities())

    # ---- the suspects ----------------------------------------------------------------------------------------

    def atoms(self) -> list[dict[str, Any]]:
        """Single-suspect modifications applicable to this robot and these keys."""
        g = self.given.arrays
        m = self.model
        out: list[dict[str, Any]] = []
        vec = any(k in g for k in _VECTOR_KEYS) or "M" in g
        if self.ff is not None and vec:
            out.append({"swap6": True})
            out.append({"world": True})
        quats = {b.kind for b in self.blocks if b.quat_at is not None}
        if quats:
            out.append({"quat_wxyz": "all"})
        if len(quats) > 1:  # a free-flyer and spherical joints: perhaps only the base's quaternion is (w, x, y, z)
            out.append({"quat_wxyz": "free_flyer"})
        if self.ff is not None and "v" in g and (("a" in g and "tau" in g) or "ddq" in g):
            out.append({"classical": True})
        if "tau" in g or "ddq" in g:
            for gv in _gravity_candidates(np.asarray(m.gravity, dtype=float)):
                out.append({"gravity": gv})
        for name in self.orders:
            out.append({"order": name})
        if "M" in g:
            out += [{"triangle": "upper"}, {"triangle": "lower"}]
        return out

    def diagnose(self, forced_cos_sin: bool) -> list[_Hypothesis]:
        """The readings that explain every comparison: single suspects first, then pairs."""
        base = _Hypothesis(cos_sin=forced_cos_sin)
        atoms = self.atoms()
        if forced_cos_sin:
            tiers = [[base], [base.merged(**a) for a in atoms]]
        else:
            pairs = [base.merged(**a, **b) for a, b in itertools.combinations(atoms, 2) if _compatible(a, b)]
            tiers = [[base.merged(**a) for a in atoms], pairs]
        for tier in tiers:
            found = [h for h in tier if self.explains(h)]
            if found:
                return found
        return []


def _quat_offset(joint: Any) -> int | None:
    if isinstance(joint, FreeFlyerJoint):
        return 3
    if isinstance(joint, SphericalJoint):
        return 0
    return None


def _compatible(a: dict[str, Any], b: dict[str, Any]) -> bool:
    if set(a) & set(b):  # two gravities, two orders, two triangles, two quaternion readings
        return False
    # world-aligned base accelerations are already the classical p̈: the pair would count ω × v twice
    return set(a) | set(b) != {"world", "classical"}


def _gravity_candidates(g: np.ndarray) -> list[tuple[float, float, float]]:
    norm = float(np.linalg.norm(g))
    axis = g / norm if norm > 0 else np.array([0.0, 0.0, -1.0])
    cands = [-g, np.zeros(3)] + [s * mag * axis for mag in _GRAVITY_MAGNITUDES for s in (1.0, -1.0)]
    out: list[tuple[float, float, float]] = []
    for c in cands:
        t = tuple(float(x) + 0.0 for x in c)  # + 0.0: no negative zeros in the report
        if not np.allclose(c, g, rtol=0, atol=1e-12) and t not in out:
            out.append(t)  # type: ignore[arg-type]
    return out


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


# --------------------------------------------------------------------------
# explanations
# --------------------------------------------------------------------------


def _fmt_vec(g: Any) -> str:
    return "(" + ", ".join(f"{x:+g}" if x else "0" for x in g) + ")"


def _names(names: list[str], limit: int = 6) -> str:
    shown = ", ".join(repr(n) for n in names[:limit])
    return shown + (f", … ({len(names)} joints)" if len(names) > limit else "")


def _explain(ch: _Checker, h: _Hypothesis) -> tuple[str, dict[str, Any]]:
    conv = ch.convention
    model = ch.model
    parts: list[str] = []
    details: dict[str, Any] = {}
    if h.cos_sin:
        joints = [b.name for b in ch.blocks if b.angle]
        kinds = " and ".join(sorted({"planar" if b.kind == "planar" else "continuous" for b in ch.blocks if b.angle}))
        if conv == "featherdyn":
            parts.append(f"{kinds} joints {_names(joints)} are given as (cos θ, sin θ), Pinocchio's layout "
                         f"(q has length {ch.declared_nq + ch.flip_nq}), where the featherdyn convention has the "
                         f"angle θ (nq={ch.declared_nq}); fd.conventions.continuous_q_from_pinocchio converts")
        else:
            parts.append(f"{kinds} joints {_names(joints)} are given as the angle θ (q has length "
                         f"{ch.declared_nq + ch.flip_nq}), where the pinocchio convention has (cos θ, sin θ) "
                         f"(nq={ch.declared_nq}); fd.conventions.continuous_q_to_pinocchio converts")
        details["continuous_joints"] = joints
    if h.order is not None:
        order = [model.joint_names[i] for i in ch.orders[h.order]]
        declared = [b.name for b in ch.blocks]
        what = {"pinocchio": "Pinocchio's joint order (pin.buildModelFromUrdf)",
                "featherdyn": "featherdyn's joint order (depth-first, URDF order)",
                "alphabetical": "alphabetical order of the joint names",
                "reverse": "reversed order"}[h.order]
        parts.append(f"the joints are in {what}: {_names(order)} instead of the {conv} convention's "
                     f"{_names(declared)}; q, v, a, tau, ddq and the rows and columns of M are permuted alike")
        details["joint_order"] = h.order
        details["joints"] = order
    if h.swap6:
        given, wanted = ("linear first [v; ω] (Pinocchio's order)", "angular first [ω; v]") if conv == "featherdyn" \
            else ("angular first [ω; v] (featherdyn's order)", "linear first [v; ω]")
        parts.append(f"the free-flyer block of v, a, tau and ddq (and of the rows and columns of M) has its 6D halves "
                     f"swapped: the values are {given}, the {conv} convention is {wanted}; "
                     "fd.conventions.freeflyer_v_from_pinocchio / freeflyer_v_to_pinocchio convert")
    if h.quat_wxyz is not None:
        joints = [b.name for b in ch.blocks if b.quat_at is not None and h.quat_wxyz in ("all", b.kind)]
        details["quaternion_joints"] = joints
        parts.append(f"the quaternions of {_names(joints)} are in (w, x, y, z) order (Eigen's constructor, MuJoCo, "
                     "Drake), where featherdyn and Pinocchio store (x, y, z, w); fd.conventions.quat_wxyz_to_xyzw "
                     "converts")
    if h.world:
        parts.append("the free-flyer velocity is world-aligned (ω in world axes, ṗ the velocity of the base origin in "
                     "the world: Pinocchio's LOCAL_WORLD_ALIGNED) instead of in the base frame (LOCAL); with R the "
                     "base orientation: v_base = [Rᵀω_w; Rᵀṗ], a_base = [Rᵀω̇_w; Rᵀp̈ − ω_b × v_b], "
                     "base wrench [Rᵀn_w; Rᵀf_w], M_base = T M Tᵀ with T = diag(Rᵀ, Rᵀ)")
    if h.classical:
        parts.append("the free-flyer acceleration is the classical acceleration of the base origin (Rᵀp̈, base "
                     "coordinates) instead of the spatial acceleration: a_spatial = a_classical − [0; ω × v]; "
                     "fd.conventions.classical_to_spatial_acceleration converts")
    if h.gravity is not None:
        g_model = np.asarray(model.gravity, dtype=float)
        g = np.array(h.gravity)
        if not np.any(g):
            how = "without gravity (g = 0)"
        elif np.allclose(g, -g_model):
            how = f"with gravity {_fmt_vec(g)} m/s², the sign flipped"
        else:
            how = f"with gravity {_fmt_vec(g)} m/s² (|g| = {np.linalg.norm(g):g}" + \
                  (", pointing the other way" if float(g @ g_model) < 0 else "") + ")"
        parts.append(f"the values were computed {how}, where the model has {_fmt_vec(g_model)} m/s²; "
                     "pass the same gravity to both (dataclasses.replace(model, gravity=...))")
        details["gravity"] = list(h.gravity)
    if h.triangle is not None:
        M = ch.given.arrays["M"]
        other = np.tril(M, -1) if h.triangle == "upper" else np.triu(M, 1)
        state = "is zero" if not np.any(other) else "is not its transpose"
        sym = "triu(M) + triu(M, 1)ᵀ" if h.triangle == "upper" else "tril(M) + tril(M, −1)ᵀ"
        opposite = "lower" if h.triangle == "upper" else "upper"
        parts.append(f"M holds only its {h.triangle} triangle (the strict {opposite} triangle {state}, as an "
                     f"in-place CRBA leaves it); the mass matrix is {sym}")
        details["triangle"] = h.triangle
    return "\n".join(p[0].upper() + p[1:] + "." for p in parts), details


def _largest_discrepancy(ch: _Checker, h: _Hypothesis, results: list[CheckResult]) -> tuple[str, dict[str, Any]]:
    """Where the values differ most from featherdyn (joint, state, index) — for the no-suspect message."""
    failing = [r for r in results if not r.passed]
    worst = max(failing, key=lambda r: (r.max_rel if math.isfinite(r.max_rel) else math.inf))
    quantity = next(k for k, v in _QUANTITIES.items() if v == worst.quantity)
    if not math.isfinite(worst.max_rel):
        return (f"{quantity} cannot be compared: {worst.note}",
                {"quantity": quantity, "reason": worst.note})
    expected, given = ch.expected_and_given(h, quantity)
    n = given.shape[0]
    err = np.abs(given - expected).reshape(n, -1)
    scale = np.maximum(np.abs(expected).reshape(n, -1).max(axis=1), 1.0)
    rel = err / scale[:, None]
    k_, flat_ = np.unravel_index(int(np.argmax(rel)), rel.shape)
    k, flat = int(k_), int(flat_)
    model = ch.model
    body_of_v = np.repeat(np.arange(model.nbodies), model.nvs)
    to_user = ch.jmap.v_perm if ch.convention == "pinocchio" else np.arange(model.nv)

    def joint(i: int) -> str:
        b = int(body_of_v[i])
        name, c = model.joint_names[b], i - model.idx_v[b]
        if isinstance(model.joints[b], FreeFlyerJoint):  # featherdyn's order: [ω; v] for motions, [n; f] for forces
            labels = ("ω", "v") if quantity == "M" else ("n", "f")
            return f"{name!r} ({labels[c // 3]}_{'xyz'[c % 3]} of the free-flyer)"
        if model.nvs[b] > 1:
            return f"{name!r} (component {c} of its {model.nvs[b]})"
        return repr(name)

    state = f" at state {k}" if ch.given.batched else ""
    gv, ev = float(given.reshape(n, -1)[k, flat]), float(expected.reshape(n, -1)[k, flat])
    if quantity == "M":
        i, j = divmod(flat, model.nv)
        ui, uj = int(to_user[i]), int(to_user[j])
        where = f"M[{ui}, {uj}], joints {joint(i)} and {joint(j)}"
        info: dict[str, Any] = {"index": [ui, uj], "joints": [model.joint_names[body_of_v[i]],
                                                              model.joint_names[body_of_v[j]]]}
    else:
        ui = int(to_user[flat])
        where = f"tau[{ui}], joint {joint(flat)}" if quantity == "tau" else \
            f"the joint forces of ddq (fd.rnea(q, v, ddq) vs tau)[{ui}], joint {joint(flat)}"
        info = {"index": ui, "joint": model.joint_names[body_of_v[flat]]}
    info.update({"quantity": quantity, "state": k, "given": gv, "featherdyn": ev, "relative_error": float(rel[k, flat])})
    text = (f"the largest discrepancy is in {where}{state}: given {gv:.6g}, featherdyn {ev:.6g} "
            f"(relative error {rel[k, flat]:.2e})")
    return text, info


# --------------------------------------------------------------------------
# the entry point
# --------------------------------------------------------------------------


def _load_robot(robot: Any, floating_base: bool, need_pin: bool) -> tuple[str, str | None, Model, Any, Any, list[str]]:
    """``(name, urdf, model, pin_model, joint map, loader warnings)``; Pinocchio only where it can be had."""
    from ..urdf import load_urdf
    from . import resolve_robot
    from ._pinocchio import require_pinocchio
    from .bridge import JointMap, pinocchio_model_from

    caught_msgs: list[str] = []
    if isinstance(robot, Model):
        if floating_base and not robot.floating_base:
            raise ModelError("floating_base=True needs a model with a free-flyer root (load it with floating_base=True)")
        model, name, path = robot, robot.name, None
    else:
        name, urdf = resolve_robot(robot)
        path = str(urdf)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = load_urdf(urdf, floating_base=floating_base)
        caught_msgs = sorted({str(w.message) for w in caught})
    try:
        pin = require_pinocchio()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if path is None:
                pm = pinocchio_model_from(model)
            elif floating_base:
                pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
            else:
                pm = pin.buildModelFromUrdf(path)
        jm = JointMap(model, pm)
    except (FeatherdynError, ValueError, RuntimeError):
        if need_pin:
            raise
        pm, jm = None, None
    return name, path, model, pm, jm, caught_msgs


def check_values(values: Mapping[str, Any] | str | os.PathLike[str], robot: Any, floating_base: bool = False,
                 convention: str = "featherdyn", tol: float = DEFAULT_TOL) -> CheckReport:
    """Check the user's numbers against featherdyn and, on a mismatch, say which usual suspect explains them.

    Args:
        values: a mapping of arrays (``q``, ``v``, ``a`` and any of ``tau``,
            ``M``, ``ddq`` with ``tau``; see the module docstring for shapes) or
            the path of an ``.npz`` file holding them. One state, or a batch
            along a leading axis (the same for every array).
        robot: a robot-library name, a URDF path, or a featherdyn :class:`~featherdyn.Model`.
        floating_base: put the root link on a free-flyer joint.
        convention: ``"featherdyn"`` or ``"pinocchio"`` (the layout of the values).
        tol: relative tolerance, ``|a − b| / max(|b|, 1)`` per state.

    Returns:
        a :class:`CheckReport`: ``.passed``, ``.results``, ``.diagnosis``,
        ``.to_text()``, ``.to_json()``.

    Raises:
        ValuesError: no such file, not an ``.npz`` archive, or a key missing.
        ShapeError, NonFiniteError, DTypeError: an array has the wrong shape, NaN or
            infinity, or is not numeric (the message names the key and the expected shape).
        ModelError, URDFError: the robot cannot be found or loaded.
        MissingDependencyError: ``convention="pinocchio"`` without Pinocchio installed.
    """
    if convention not in CONVENTIONS:
        raise ValueError(f"convention: expected one of {', '.join(CONVENTIONS)}, got {convention!r}")
    if not (isinstance(tol, (int, float)) and 0 < tol < math.inf):
        raise ValueError(f"tol: expected a positive finite number, got {tol!r}")
    source = None
    if isinstance(values, (str, os.PathLike)):
        source = os.fspath(values)
        values = _load_npz(values)
    elif not isinstance(values, Mapping):
        raise ValuesError(f"values: expected a mapping of arrays or the path of an .npz file, got "
                          f"{type(values).__name__}")
    name, path, model, pm, jm, load_warnings = _load_robot(robot, floating_base, convention == "pinocchio")

    continuous = {e.fd_body for e in jm.entries if e.continuous} if jm is not None else \
        {i for i, j in enumerate(model.joints) if isinstance(j, RevoluteJoint)
         and not np.isfinite(model.lower[model.idx_q[i]]) and not np.isfinite(model.upper[model.idx_q[i]])}
    # the allowed lengths of q: the declared layout, and the one with continuous joints flipped
    layout = _Layout(model, pm, jm, convention, continuous)
    nq_decl, nq_flip = layout.declared_nq, layout.declared_nq + layout.flip_nq
    flipped = "cos θ, sin θ" if convention == "featherdyn" else "angle"
    nq_allowed = {nq_decl: ""}
    if nq_flip != nq_decl:
        nq_allowed[nq_flip] = f"continuous joints as {flipped}"
    if floating_base or model.floating_base:
        other = (nq_decl - 7, model.nv - 6, "without --floating-base")
    else:
        other = (nq_decl + 7, model.nv + 6, "with --floating-base")
    given = _validate(values, nq_allowed, model.nv, other)

    ch = _Checker(model, pm, jm, convention, continuous, given, tol)
    forced = given.arrays["q"].shape[1] != nq_decl
    base = "floating" if model.floating_base else "fixed"
    states = f"{given.n} state{'s' if given.n != 1 else ''}" if given.batched else "one state"
    title = (f"featherdyn check {source or 'values'} against {name} ({base} base, nq={model.nq}, nv={model.nv}), "
             f"{convention} convention, {states}, tol {tol:g}")
    report = CheckReport(title=title, meta={
        "robot": name, "urdf": path, "source": source, "floating_base": model.floating_base,
        "convention": convention, "tol": tol, "states": given.n, "batched": given.batched,
        "keys": [k for k in _KEYS if k in given.arrays], "ignored_keys": list(given.ignored),
        "dtypes": given.dtypes, "compared": ch.quantities(), "load_warnings": load_warnings,
    })
    if forced:
        q_len = given.arrays["q"].shape[1]
        report.results = [CheckResult("check", "q layout", math.inf, math.inf, 0, tol, False,
                                      f"q has length {q_len}, the {convention} convention's nq is {nq_decl}")]
    else:
        report.results = [ch.result(_Hypothesis(), q) for q in ch.quantities()]
        if report.passed:
            report.summary = f"all {len(report.results)} comparisons agree within {tol:g}"
            return report

    for h in ch.diagnose(forced):
        explanation, details = _explain(ch, h)
        results = tuple(ch.result(h, q, group="corrected") for q in ch.quantities())
        report.diagnosis.append(Finding(h.suspects, explanation, results, details))
    if report.diagnosis:
        report.summary = "explained by " + " or ".join(f.suspect for f in report.diagnosis)
        return report
    h0 = _Hypothesis(cos_sin=forced)
    rows = [ch.result(h0, q) for q in ch.quantities()]
    lead = "" if not forced else f"continuous joints read as {flipped} (the length of q says so); "
    try:
        where, info = _largest_discrepancy(ch, h0, rows) if not all(r.passed for r in rows) else \
            ("the values agree once q's continuous joints are read that way", {})
    except (FeatherdynError, ValueError) as exc:  # the values cannot even be read
        where, info = _one_line(exc), {}
    report.summary = f"no usual suspect explains it; {lead}{where}"
    low = sorted({d for d in given.dtypes.values() if d in ("float32", "float16")})
    if low:  # float32 round-off of q alone moves tau by ~1e-6 relative on long arms (UR5: up to 4e-6)
        report.summary += (f" — the values are {'/'.join(low)}, whose round-off alone can exceed the tolerance "
                           f"{tol:g}: retry with --tol 1e-5 (float32) to tell round-off from a real discrepancy")
    report.largest_discrepancy = info or None
    return report


# --------------------------------------------------------------------------
# the command line
# --------------------------------------------------------------------------


def add_check_subcommand(subparsers: Any) -> argparse.ArgumentParser:
    """Add ``featherdyn check`` to the sub-command parsers of the ``featherdyn`` command."""
    from ..cli import _positive_float

    p: argparse.ArgumentParser = subparsers.add_parser(
        "check", help="check your own numbers (an .npz of q, v, a, tau, M, ddq) against featherdyn and "
                      "diagnose a mismatch",
        description="Check the values in VALUES.npz (keys q, v, a and any of tau, M, ddq with tau; one state or a "
                    "batch along a leading axis) against featherdyn. On a mismatch, try the usual suspects (6D "
                    "order, world-frame base velocity, quaternion order, classical acceleration, gravity, "
                    "continuous joints, joint order, triangular M) and say which one explains the numbers. "
                    "Exit codes: 0 all agree, 1 a mismatch, 2 a usage or model error.")
    p.add_argument("values", metavar="VALUES.npz", help="an .npz archive of named arrays (numpy.savez)")
    p.add_argument("--robot", required=True, metavar="ROBOT|URDF",
                   help="a robot-library name (see `featherdyn list`) or a URDF file")
    p.add_argument("--floating-base", action="store_true", help="put the root link on a free-flyer joint")
    p.add_argument("--convention", choices=CONVENTIONS, default="featherdyn",
                   help="the layout of the values (default featherdyn; pinocchio: continuous joints as cos/sin, "
                        "Pinocchio's joint order, free-flyer [v; ω] LOCAL)")
    p.add_argument("--tol", type=_positive_float, default=DEFAULT_TOL,
                   help=f"relative tolerance |a − b| / max(|b|, 1) (default {DEFAULT_TOL:g})")
    p.add_argument("--json", type=Path, default=None, metavar="FILE", help="write the full report as JSON")
    return p


def cmd_check(args: argparse.Namespace) -> int:
    """Run ``featherdyn check``; returns the exit code (0 agree, 1 mismatch, 2 usage or model error)."""
    try:
        report = check_values(args.values, args.robot, floating_base=args.floating_base,
                              convention=args.convention, tol=args.tol)
    except (FeatherdynError, ValueError, TypeError) as exc:
        print(f"featherdyn: error: {_one_line(exc)}", file=sys.stderr)
        return _EXIT_USAGE
    print(report.to_text())
    if args.json is not None:
        try:
            args.json.write_text(report.to_json() + "\n", encoding="utf-8")
        except OSError as exc:
            print(f"featherdyn: error: cannot write {args.json}: {exc.strerror}", file=sys.stderr)
            return _EXIT_USAGE
        print(f"JSON report written to {args.json}")
    return _EXIT_OK if report.passed else _EXIT_MISMATCH

