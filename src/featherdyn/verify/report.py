"""Results of a verification run: one row per compared quantity, and the table they make."""

from __future__ import annotations

import json
import platform
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike

from ..testing import tolerance

__all__ = ["CheckResult", "VerifyReport", "RunMeta", "Diagnostics", "LinkInfo", "InvalidInertia", "compare", "ROUNDOFF", "roundoff_note", "Cause", "likely_cause"]


#: the mark of a check whose tolerance is scaled by the mass matrix's condition number (in its quantity)
COND_SCALED = "tol × cond(M)"
#: what the table's columns mean, printed above it
COLUMNS = ("max abs err: the largest |featherdyn − oracle| over the states and entries; max rel err: the same over "
           "max(|oracle|, 1), judged against tol; worst: the random state (0 .. samples − 1) where it occurs")


@dataclass(frozen=True, slots=True)
class CheckResult:
    """The comparison of one quantity over all sampled states.

    Attributes:
        group: what kind of check (``"pinocchio"`` for an oracle comparison,
            ``"identity"`` for a law that needs no oracle).
        quantity: the operation compared, named after both libraries
            (``"X.apply(motion) vs SE3.act(Motion)"``).
        max_abs: largest absolute error over all samples and entries.
        max_rel: largest error relative to the magnitude of the expected value
            (``|a − b| / max(|b|, 1)``, so tiny expected values do not blow up).
        worst_sample: index of the sample with the largest relative error.
        tol: the tolerance the relative error was held to.
        passed: ``max_rel <= tol``.
        note: what the comparison shows on a failure (the likely cause).
        sample_errors: the relative error of each sample (the distribution the
            HTML report plots).
        criterion: how the comparison was judged when not by ``max_rel <= tol``
            alone (forward dynamics: by its backward error and the conditioning
            of ``M``, :func:`featherdyn.verify.dynamics.forward_dynamics_result`).
    """

    group: str
    quantity: str
    max_abs: float
    max_rel: float
    worst_sample: int
    tol: float
    passed: bool
    note: str = ""
    sample_errors: tuple[float, ...] = ()
    criterion: str = ""


#: relative errors up to this are float64 round-off: the comparison tolerance of float64 results
#: (:data:`featherdyn.tolerances.COMPARISON`). A failure below it means the tolerance asked for is finer
#: than double precision can resolve, not that a quantity is wrong.
ROUNDOFF = tolerance(np.float64)[0]


def roundoff_note(max_rel: float, tol: float) -> str:
    """The note of a failure that is only round-off."""
    return (f"differs only by round-off ({max_rel:.1e}, float64 results agree to {ROUNDOFF:.0e}): the tolerance "
            f"{tol:.0e} is below what double precision can resolve")


def compare(
    group: str, quantity: str, actual: ArrayLike, expected: ArrayLike, tol: float, note: str = ""
) -> CheckResult:
    """Compare stacked samples ``actual`` and ``expected`` (leading axis = sample).

    ::

        max_rel = max over samples of  max|a − b| / max(max|b|, 1)

    A failure within float64 round-off (:data:`ROUNDOFF`) is noted as such instead of ``note``.
    """
    a = np.asarray(actual, dtype=np.float64)
    b = np.asarray(expected, dtype=np.float64)
    if a.shape != b.shape:
        return CheckResult(group, quantity, float("inf"), float("inf"), 0, tol, False,
                           f"shape mismatch: featherdyn {a.shape} vs oracle {b.shape}")
    n = a.shape[0] if a.ndim else 1
    a2, b2 = a.reshape(n, -1), b.reshape(n, -1)
    err = np.abs(a2 - b2)
    if not np.all(np.isfinite(err)):
        worst = int(np.argmax(~np.isfinite(err).all(axis=1)))
        return CheckResult(group, quantity, float("inf"), float("inf"), worst, tol, False, "non-finite values")
    abs_per = err.max(axis=1, initial=0.0)
    scale = np.maximum(np.abs(b2).max(axis=1, initial=0.0), 1.0)
    rel_per = abs_per / scale
    worst = int(np.argmax(rel_per)) if n else 0
    max_rel = float(rel_per.max(initial=0.0))
    if max_rel <= tol:
        note = ""
    elif max_rel <= ROUNDOFF:
        note = roundoff_note(max_rel, tol)
    return CheckResult(group, quantity, float(abs_per.max(initial=0.0)), max_rel, worst, tol, max_rel <= tol,
                       note, tuple(float(e) for e in rel_per))


#: a possible cause of a mismatch: its description, and what the oracle's values `(N, ...)` would be
#: had featherdyn made that mistake. It is named only when featherdyn's values match those.
Cause = tuple[str, Callable[[np.ndarray], np.ndarray]]



class PairedRows:
    """An oracle's values beside featherdyn's, gathered per check over the sampled states, then compared stacked
    (one :func:`compare` per check, in the order the checks were first added)."""

    def __init__(self) -> None:
        self.rows: dict[str, tuple[list[np.ndarray], list[np.ndarray]]] = {}

    def add(self, key: str, ours: np.ndarray, theirs: np.ndarray) -> None:
        """One state's values of check ``key``: featherdyn's, the oracle's."""
        mine, other = self.rows.setdefault(key, ([], []))
        mine.append(np.asarray(ours, dtype=float))
        other.append(np.asarray(theirs, dtype=float))

    def compare(self, group: str, tol: float) -> list[CheckResult]:
        return [compare(group, key, np.stack(ours), np.stack(theirs), tol) for key, (ours, theirs) in self.rows.items()]


def likely_cause(ours: np.ndarray, ref: np.ndarray, causes: Sequence[Cause], tol: float) -> str:
    """The cause that explains a mismatch of ``ours`` against ``ref`` `(N, ...)`, or where the difference is largest.

    A cause is named only when featherdyn's values agree, within ``max(tol, ROUNDOFF)``, with
    the oracle's values as that mistake would have made them.
    """
    for text, mistaken in causes:
        try:
            alt = mistaken(ref)
        except (ValueError, RuntimeError, IndexError):  # the alternative cannot be computed for this robot
            continue
        if compare("", "", ours, alt, max(tol, ROUNDOFF)).passed:
            return text
    n = ours.shape[0] if ours.ndim else 1
    a, b = ours.reshape(n, -1), ref.reshape(n, -1)
    rel = np.abs(a - b) / np.maximum(np.abs(b).max(axis=1, initial=0.0), 1.0)[:, None]
    k, flat = (int(i) for i in np.unravel_index(int(np.argmax(rel)), rel.shape))
    index = tuple(int(i) for i in np.unravel_index(flat, ours.shape[1:])) if ours.ndim > 1 else ()
    where = f"state {k}" + (f", index {index[0] if len(index) == 1 else index}" if index else "")
    return (f"no usual cause explains it; largest difference at {where}: featherdyn {a[k, flat]:.6g}, "
            f"expected {b[k, flat]:.6g}")


class LinkInfo(TypedDict):
    """One body in :attr:`VerifyReport.diagnostics` (``links``)."""

    body: str
    mass: float
    principal_moments: list[float]
    ellipsoid_semi_axes: list[float] | None
    valid: bool
    reason: str


class InvalidInertia(TypedDict):
    """A body whose inertia is not physical, and why."""

    body: str
    reason: str


class Diagnostics(TypedDict, total=False):
    """What :attr:`VerifyReport.diagnostics` holds (:func:`featherdyn.verify.dynamics.model_diagnostics`)."""

    links: list[LinkInfo]
    invalid_inertias: list[InvalidInertia]
    singular_subtrees: list[str]
    mass_matrix_condition: float
    total_mass: float


class RunMeta(TypedDict, total=False):
    """What :attr:`VerifyReport.meta` holds: versions, machine, robot and settings of the run."""

    python: str
    numpy: str
    machine: str
    system: str
    featherdyn: str
    pinocchio: str
    robot: str
    urdf: str
    mjcf: str
    format: str
    oracle: str
    mujoco: str
    drake: str
    sdf: str
    #: what Drake's parser said of the file (every warning, deduplicated)
    drake_warnings: list[str]
    #: what an oracle refuses or ignores of the model, or leaves out of the comparison (printed under the table)
    oracle_notes: list[str]
    #: ``--oracle all``: the libraries that cannot take this model, and why
    oracles_skipped: dict[str, str]
    floating_base: bool
    samples: int
    seed: int
    tol: float
    nq: int
    nv: int
    nbodies: int
    load_warnings: list[str]
    seconds: float
    error: str
    contacts: list[str]


@dataclass
class VerifyReport:
    """Everything a verification run found; ``passed`` is true when every check passed."""

    title: str
    results: list[CheckResult] = field(default_factory=list)
    meta: RunMeta = field(default_factory=lambda: RunMeta())
    diagnostics: Diagnostics = field(default_factory=lambda: Diagnostics())

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.results)

    @property
    def failures(self) -> list[CheckResult]:
        return [r for r in self.results if not r.passed]

    def to_dict(self) -> dict[str, object]:
        """A dictionary of the whole report (:meth:`to_json` writes infinities as strings)."""
        return {
            "title": self.title,
            "passed": self.passed,
            "meta": self.meta,
            "diagnostics": self.diagnostics,
            "results": [asdict(r) for r in self.results],
        }

    def to_json(self, indent: int = 2) -> str:
        def default(o: object) -> object:
            if isinstance(o, (np.floating, np.integer, np.bool_)):
                return o.item()
            raise TypeError(type(o).__name__)

        diagnostics: dict[str, object] = dict(self.diagnostics)
        cond = self.diagnostics.get("mass_matrix_condition")
        if isinstance(cond, float) and not np.isfinite(cond):  # JSON has no inf / nan
            diagnostics["mass_matrix_condition"] = str(cond)
        results: list[dict[str, object]] = []
        for r in self.results:
            row: dict[str, object] = asdict(r)
            for k in ("max_abs", "max_rel"):
                value = getattr(r, k)
                if not np.isfinite(value):
                    row[k] = str(value)
            results.append(row)
        d = dict(self.to_dict(), diagnostics=diagnostics, results=results)
        return json.dumps(d, indent=indent, default=default, ensure_ascii=False)

    def to_table(self) -> str:
        """The plain-text table printed by ``featherdyn verify``."""
        head = ("group", "quantity", "max abs err", "max rel err", "worst", "tol", "result")
        rows = [
            (r.group, r.quantity, f"{r.max_abs:.2e}", f"{r.max_rel:.2e}", str(r.worst_sample), f"{r.tol:.0e}",
             "pass" if r.passed else "FAIL")
            for r in self.results
        ]
        widths = [max(len(h), *(len(row[i]) for row in rows)) if rows else len(h) for i, h in enumerate(head)]
        fmt = "  ".join(f"{{:<{w}}}" for w in widths)
        lines = [self.title, "", COLUMNS, "", fmt.format(*head), fmt.format(*("-" * w for w in widths))]
        lines += [fmt.format(*row) for row in rows]
        n_fail = len(self.failures)
        d = self.diagnostics
        if d:
            lines.append("")
            lines.append(f"model: total mass {d.get('total_mass', float('nan')):.6g} kg, "
                         f"mass-matrix condition number {d.get('mass_matrix_condition', float('nan')):.3g}")
            bad = d.get("invalid_inertias", [])
            lines.append(f"link inertias: {'all physical' if not bad else f'{len(bad)} not physical'}")
            lines += [f"  {b['body']}: {b['reason']}" for b in bad]
            lines += [f"  singular: {s}" for s in d.get("singular_subtrees", [])]
        warned = self.meta.get("load_warnings", [])
        if warned:  # what the loader said of the file (unknown names, odd inertias): never silent
            lines += ["", f"loader warning{'s' if len(warned) > 1 else ''}:", *(f"  {w}" for w in warned)]
        skipped = self.meta.get("oracles_skipped", {})
        if skipped:  # --oracle all: who could not take the model
            lines += ["", "oracles left out:", *(f"  {k}: {why}" for k, why in skipped.items())]
        notes = self.meta.get("oracle_notes", [])
        if notes:  # what an oracle refuses or ignores: never silent
            lines += ["", "what the oracles ignore or leave out:", *(f"  {n}" for n in notes)]
        rules: dict[str, list[str]] = {}  # a rule stated once, then each row's figures ("<rule>; <figures>")
        for r in self.results:
            if r.criterion:
                rule, _, figures = r.criterion.partition("; ")
                rules.setdefault(rule, []).append(f"  {r.quantity}: {figures}" if figures else f"  {r.quantity}")
        for rule, judged in rules.items():
            lines += ["", f"{rule[0].upper()}{rule[1:]}:", *judged]
        roundoff = [r for r in self.failures if r.max_rel <= ROUNDOFF]
        others = [r for r in self.failures if r.max_rel > ROUNDOFF]
        summary = f"{len(self.results)} checks: {len(self.results) - n_fail} passed, {n_fail} failed"
        scaled = [r for r in self.results if r.passed and COND_SCALED in r.quantity]
        if scaled:
            summary += (f"; {len(scaled)} of the passes on a tolerance scaled by cond(M) (marked "
                        f"'{COND_SCALED}': solving with M amplifies round-off by cond(M))")
        if roundoff:
            summary += (f"; {'all' if not others else len(roundoff)} only by round-off (largest "
                        f"{max(r.max_rel for r in roundoff):.1e}): the tolerance {min(r.tol for r in roundoff):.0e} "
                        f"is below what double precision can resolve (float64 results agree to {ROUNDOFF:.0e})")
        if others:
            summary += "  — " + "; ".join(f"{r.quantity}: {r.note}" for r in others if r.note)
        lines += ["", summary]
        return "\n".join(lines)


def machine_meta() -> RunMeta:
    """Versions and machine, recorded in every report."""
    meta = RunMeta(python=platform.python_version(), numpy=np.__version__, machine=platform.machine(),
                   system=platform.system())
    try:
        from .. import __version__

        meta["featherdyn"] = __version__
    except ImportError:  # pragma: no cover
        pass
    return meta
