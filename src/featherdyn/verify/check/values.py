"""Reading the user's values: an ``.npz`` archive or a mapping of arrays, validated key by key."""

from __future__ import annotations

import os
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ...errors import DTypeError, FeatherdynError, NonFiniteError, ShapeError
from ...readers.xml import open_regular_file

__all__ = ["ValuesError", "KEYS", "VECTOR_KEYS", "DERIVATIVE_KEYS", "DERIVATIVE_SPECS", "DerivativeKey", "ROW_COUNTS",
           "Given", "load_npz", "validate"]


@dataclass(frozen=True)
class DerivativeKey:
    """A derivative matrix ``featherdyn check`` takes: what its rows are, where it is computed, by what.

    ``rows``: ``"joint"`` (nv rows in v's layout, as ``∂τ/∂q``), ``"motion"`` (6 rows ``[ω; v]``),
    ``"momentum"`` (6 rows ``[k; p]``) or ``"point"`` (3 rows, a point's coordinates); ``inputs``: the arrays
    besides ``q`` it is computed at (missing ones are an error); ``function``: featherdyn's function it is
    compared with; ``frame``: it is a frame's derivative (``check_values(frame=..., reference=...)``).
    """

    rows: str
    inputs: tuple[str, ...]
    function: str
    frame: bool = False


#: Every derivative matrix taken, by key; the ∂/∂q ones may also be given with respect to q's coordinates
#: (nq columns). Adding one is an entry here and its computation in :mod:`.readings` (``COMPUTE``).
DERIVATIVE_SPECS: dict[str, DerivativeKey] = {
    "dtau_dq": DerivativeKey("joint", ("v", "a"), "fd.rnea_derivatives"),
    "dtau_dv": DerivativeKey("joint", ("v", "a"), "fd.rnea_derivatives"),
    "dddq_dq": DerivativeKey("joint", ("v", "tau"), "fd.aba_derivatives"),
    "dddq_dv": DerivativeKey("joint", ("v", "tau"), "fd.aba_derivatives"),
    "dg_dq": DerivativeKey("joint", (), "fd.generalized_gravity_derivatives"),
    "dc_dq": DerivativeKey("point", (), "fd.center_of_mass_derivatives"),
    "dcdot_dq": DerivativeKey("point", ("v",), "fd.center_of_mass_derivatives"),
    "dh_dq": DerivativeKey("momentum", ("v",), "fd.centroidal_dynamics_derivatives"),
    "dhdot_dq": DerivativeKey("momentum", ("v", "a"), "fd.centroidal_dynamics_derivatives"),
    "dhdot_dv": DerivativeKey("momentum", ("v", "a"), "fd.centroidal_dynamics_derivatives"),
    "dhdot_da": DerivativeKey("momentum", ("v", "a"), "fd.centroidal_dynamics_derivatives"),
    **{k: DerivativeKey("motion", ("v",), "fd.kinematics_derivatives", frame=True) for k in ("dv_dq", "dv_dv")},
    **{k: DerivativeKey("motion", ("v", "a"), "fd.kinematics_derivatives", frame=True)
       for k in ("da_dq", "da_dv", "da_da", "dac_dq", "dac_dv", "dac_da")},
}

#: rows of each kind of derivative matrix (``"joint"``: nv)
ROW_COUNTS = {"motion": 6, "momentum": 6, "point": 3}

DERIVATIVE_KEYS = tuple(DERIVATIVE_SPECS)
KEYS = ("q", "v", "a", "tau", "M", "ddq", *DERIVATIVE_KEYS)
VECTOR_KEYS = ("v", "a", "tau", "ddq")
_ROWS = {"motion": "[ω; v]", "momentum": "[k; p]", "point": "x, y, z"}


class ValuesError(FeatherdynError, ValueError):
    """The values to check are unusable: no such file, not an ``.npz`` archive, or keys missing."""


#: Largest array read from a values file, in bytes (its declared size; a zip member's too).
MAX_VALUES_BYTES = 4_000_000_000


def load_npz(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """The named arrays of an ``.npz`` archive (``numpy.savez``), checked before they are read.

    Only a regular file is opened (a named pipe or a device is refused at once, not read forever); each member
    must be a ``.npy`` array of numbers whose declared size is at most :data:`MAX_VALUES_BYTES` and fits in the
    member (a header declaring terabytes is refused before anything is allocated). ``ValuesError`` otherwise.
    """
    label = os.fspath(path)
    p = Path(label)
    if not p.exists():
        raise ValuesError(f"{label}: file not found")
    if p.is_dir():
        raise ValuesError(f"{label}: is a directory, expected an .npz file")
    not_npz = (f"{label}: not an .npz archive of named arrays (save one with numpy.savez(file, q=..., v=..., a=..., "
               "tau=...))")
    try:
        fd, _ = open_regular_file(label)
    except OSError as exc:
        raise ValuesError(f"{label}: cannot read: {exc.strerror or exc}; expected an .npz file") from None
    with os.fdopen(fd, "rb") as file:
        try:
            loaded = np.load(file, allow_pickle=False)
        except (ValueError, OSError, EOFError, zipfile.BadZipFile):
            raise ValuesError(not_npz) from None
        if not isinstance(loaded, np.lib.npyio.NpzFile):
            raise ValuesError(f"{label}: holds a single .npy array, expected an .npz archive of named arrays "
                              "(numpy.savez(file, q=..., v=..., a=..., tau=...))")
        out = {}
        with loaded:
            for key in loaded.files:
                _check_member(loaded, key, label)
                try:
                    out[key] = loaded[key]
                except ValueError:
                    raise ValuesError(f"{label}: array {key!r} holds Python objects, expected numbers") from None
                except (OSError, EOFError, zipfile.BadZipFile):
                    raise ValuesError(f"{label}: array {key!r} is corrupt") from None
    return out


def _check_member(loaded: np.lib.npyio.NpzFile, key: str, label: str) -> None:
    """Refuse a member whose ``.npy`` header declares more bytes than :data:`MAX_VALUES_BYTES` or than it holds."""
    archive = loaded.zip
    if archive is None:  # closed (it is open while load_npz reads it)
        raise ValuesError(f"{label}: array {key!r} cannot be read (archive closed)")
    name = key if key in archive.namelist() else key + ".npy"
    try:
        info = archive.getinfo(name)
        with archive.open(name) as member:
            if member.read(6) != b"\x93NUMPY":
                return  # not an .npy member: numpy's own reading words it
            member.seek(0)
            version = np.lib.format.read_magic(member)
            if version == (1, 0):
                shape, _, dtype = np.lib.format.read_array_header_1_0(member)
            elif version == (2, 0):
                shape, _, dtype = np.lib.format.read_array_header_2_0(member)
            else:
                raise ValuesError(f"{label}: array {key!r} is in .npy format {version}, expected 1.0 or 2.0 "
                                  "(numpy.savez)")
    except ValuesError:
        raise
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, KeyError):
        raise ValuesError(f"{label}: array {key!r} is corrupt") from None
    declared = int(np.prod(shape, dtype=object)) * dtype.itemsize
    if declared > MAX_VALUES_BYTES or declared > info.file_size:
        raise ValuesError(f"{label}: array {key!r} declares shape {tuple(shape)} of {dtype} ({declared} bytes), "
                          f"more than its {info.file_size} bytes in the archive or MAX_VALUES_BYTES = "
                          f"{MAX_VALUES_BYTES}")


@dataclass(frozen=True)
class Given:
    """The validated user arrays, float64, each with a leading batch axis of length ``n``."""

    arrays: dict[str, np.ndarray]
    n: int
    batched: bool
    ignored: tuple[str, ...]
    dtypes: dict[str, str] = field(default_factory=dict)  # as given, before the cast to float64


def _numeric(key: str, x: object) -> np.ndarray:
    try:
        arr = np.asarray(x)
    except Exception as exc:  # ragged lists and the like
        raise ShapeError(f"{key}: not an array of numbers ({exc})") from None
    if arr.dtype.kind not in "biuf":
        raise DTypeError(f"{key}: expected real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64)


def validate(values: Mapping[str, ArrayLike], nq_allowed: dict[int, str], nv: int, other_base: tuple[int, int, str]
              ) -> Given:
    """Check keys, shapes, batch sizes and finiteness; raise a one-line error naming the key and expected shape."""
    present = [k for k in KEYS if k in values]
    ignored = tuple(sorted(str(k) for k in values if k not in KEYS))
    have = f" (given: {', '.join(sorted(map(str, values))) or 'nothing'})"
    need = ("expected q, v, a and any of tau, M, ddq (with tau), or derivative matrices (" + ", ".join(DERIVATIVE_KEYS)
            + ")")

    def missing(key: str, why: str) -> ValuesError:
        return ValuesError(f"missing key {key!r}: {why}{have}")

    if "q" not in values:
        raise missing("q", "the configuration is always needed")
    if not any(k in values for k in ("tau", "M", "ddq", *DERIVATIVE_KEYS)):
        raise ValuesError(f"nothing to check: {need}{have}")
    for key, spec in DERIVATIVE_SPECS.items():
        if key in values:
            for needed in spec.inputs:
                if needed not in values:
                    raise missing(needed, f"{key} is compared with {spec.function} at (q, {', '.join(spec.inputs)})")
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
        elif key == "M" or key in DERIVATIVE_KEYS:
            kind = "joint" if key == "M" else DERIVATIVE_SPECS[key].rows
            rows = ROW_COUNTS.get(kind, nv)
            expected, unit = (rows, nv), f"nv={nv}" if kind == "joint" else f"{rows} rows ({_ROWS[kind]}), nv={nv}"
            cols = (nv, nq_main) if key.endswith("_dq") else (nv,)  # ∂/∂q also w.r.t. q's coordinates
            ok = arr.ndim in (2, 3) and arr.shape[-2] == rows and arr.shape[-1] in cols
            if key.endswith("_dq") and nq_main != nv:
                unit += f"; or ({rows}, nq={nq_main}) for a derivative with respect to q's coordinates"
            hint = f" — {o_nv} is nv {o_flag}" if arr.ndim in (2, 3) and arr.shape[-1] == o_nv else ""
            if not ok and kind != "joint" and arr.ndim in (2, 3) and arr.shape[-2:] in ((nv, rows), (nq_main, rows)):
                hint = f" — that is the transposed shape: featherdyn's rows are the {rows} outputs, its columns the nv inputs"
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
    return Given(arrays, 1 if n is None else int(n), n is not None, ignored, dtypes)

