"""The report of ``featherdyn check``: the comparisons, the readings that explain a mismatch, the text table."""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field

import numpy as np

from ..report import CheckResult

__all__ = ["Finding", "CheckReport", "result_dict", "table", "one_line", "agree"]


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line (the command line prints errors as one line)."""
    return " ".join(str(exc).split())


@dataclass(frozen=True)
class Finding:
    """One reading of the values under which every comparison of ``tau``, ``M`` and ``ddq`` passes.

    Attributes:
        suspects: the suspect names (from :data:`~featherdyn.verify.check.SUSPECTS`) combined in this reading.
        explanation: what the values are, in words, and how to convert them.
        results: the corrected comparisons of every quantity given: ``tau``, ``M`` and ``ddq`` (all passed),
            then the derivative matrices re-read alike at the corrected state (one the reading does not fix
            stays a failed row).
        details: the parameters of the reading (``gravity``, ``joint_order``, ``triangle``, ...).
    """

    suspects: tuple[str, ...]
    explanation: str
    results: tuple[CheckResult, ...]
    details: dict[str, object] = field(default_factory=dict)

    @property
    def suspect(self) -> str:
        """The suspect names joined with ``" + "``."""
        return " + ".join(self.suspects)

    def to_dict(self) -> dict[str, object]:
        return {
            "suspect": self.suspect,
            "suspects": list(self.suspects),
            "explanation": self.explanation,
            "details": self.details,
            "results": [result_dict(r) for r in self.results],
        }


@dataclass
class CheckReport:
    """The outcome of :func:`~featherdyn.verify.check.check_values`.

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
    largest_discrepancy: dict[str, object] | None = None
    meta: dict[str, object] = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return bool(self.results) and all(r.passed for r in self.results)

    def to_dict(self) -> dict[str, object]:
        """A JSON-ready dictionary of the whole report (infinities as strings)."""
        return {
            "title": self.title,
            "passed": self.passed,
            "summary": self.summary,
            "meta": self.meta,
            "results": [result_dict(r) for r in self.results],
            "diagnosis": [f.to_dict() for f in self.diagnosis],
            "largest_discrepancy": self.largest_discrepancy,
        }

    def to_json(self, indent: int = 2) -> str:
        def default(o: object) -> object:
            if isinstance(o, (np.floating, np.integer, np.bool_)):
                return o.item()
            if isinstance(o, np.ndarray):
                return o.tolist()
            raise TypeError(type(o).__name__)

        return json.dumps(self.to_dict(), indent=indent, default=default, ensure_ascii=False)

    def to_text(self) -> str:
        """The plain-text report printed by ``featherdyn check``."""
        lines = [self.title, "", *table(self.results), ""]
        if self.passed:
            lines.append(f"{agree(len(self.results))} within {self.meta.get('tol', 0):g}")
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
                lines += [f"    {row}" for row in table(list(f.results))]
        else:
            lines.append(f"MISMATCH: {self.summary}")
        return "\n".join(lines)


def result_dict(r: CheckResult) -> dict[str, object]:
    """``r`` as a JSON-ready dictionary (infinities and NaN as strings)."""
    d = dataclasses.asdict(r)
    for k in ("max_abs", "max_rel"):
        if not math.isfinite(d[k]):  # JSON has no inf / nan
            d[k] = str(d[k])
    return d


def table(results: list[CheckResult]) -> list[str]:
    """The rows of the plain-text table of ``results`` (header, rule, one row per comparison)."""
    head = ("quantity", "max abs err", "max rel err", "worst state", "result")
    rows = [(r.quantity, f"{r.max_abs:.2e}", f"{r.max_rel:.2e}", str(r.worst_sample),
             "pass" if r.passed else "FAIL" + (f" ({r.note})" if r.note else "")) for r in results]
    widths = [max(len(h), *(len(row[i]) for row in rows)) if rows else len(h) for i, h in enumerate(head)]
    widths[-1] = len(head[-1])
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    return [fmt.format(*head).rstrip(), fmt.format(*("-" * w for w in widths))] + [fmt.format(*row).rstrip()
                                                                                   for row in rows]



def agree(n: int) -> str:
    """``"all 3 comparisons agree"``; ``"the 1 comparison agrees"``."""
    return "the 1 comparison agrees" if n == 1 else f"all {n} comparisons agree"
