"""Worker of the URDF mutation fuzz test: load mutants, report one outcome each (run as a subprocess).

Usage: ``python _urdf_fuzz_worker.py MUTANTS.jsonl``. Each input line is
``{"id": int, "xml": str, "floating_base": bool, "backend": str}``
(``"xml_bytes"``: latin-1 text of raw bytes instead of ``"xml"``). Each output line, written and flushed
as soon as a mutant is done, is::

    {"id": int, "load": "ok" | "URDFError" | <other exception class>,
     "warnings": [warning class names], "message": str (the error's first
     3000 characters, or ""), "message_length": int (if an error),
     "dynamics": "finite" | "skipped" | "error:<class>" | "nonfinite:<algorithm>",
     "dynamics_warnings": [class names], "seconds": float}

The parent knows a mutant that crashed or hung the worker as the first one
without an output line. The dynamics run (reference backend: no JIT) only on
models that loaded without any warning, at a seeded random state, on the
job's backend (``"reference"`` by default: no JIT compilation).
"""

from __future__ import annotations

import json
import sys
import time
import warnings
from typing import Any

import numpy as np

import featherdyn as fd
from featherdyn.errors import FeatherdynError, URDFError


def _dynamics(model: fd.Model, seed: int, backend: str) -> tuple[str, list[str]]:
    rng = np.random.default_rng(seed)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            q = fd.random_configuration(model, rng)
            v, a, tau = (rng.standard_normal(model.nv) for _ in range(3))
            results = {
                "rnea": fd.rnea(model, q, v, a, backend=backend),
                "crba": fd.crba(model, q, backend=backend),
                "aba": fd.aba(model, q, v, tau, backend=backend),
            }
        except FeatherdynError as exc:
            outcome = f"error:{type(exc).__name__}"
        except Exception as exc:  # reported, and failed on, by the parent
            outcome = f"raw:{type(exc).__name__}: {str(exc)[:300]}"
        else:
            bad = [name for name, value in results.items() if not np.all(np.isfinite(value))]
            outcome = f"nonfinite:{','.join(bad)}" if bad else "finite"
    return outcome, sorted({w.category.__name__ for w in caught})


def _one(job: dict[str, Any]) -> dict[str, Any]:
    start = time.perf_counter()
    source: str | bytes = job["xml_bytes"].encode("latin-1") if "xml_bytes" in job else job["xml"]
    out: dict[str, Any] = {"id": job["id"], "message": "", "dynamics": "skipped", "dynamics_warnings": []}
    model = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            model = fd.load_urdf(source, floating_base=job["floating_base"])
            out["load"] = "ok"
        except Exception as exc:  # any class but URDFError fails the test in the parent
            out["load"] = "URDFError" if isinstance(exc, URDFError) else type(exc).__name__
            out["message"], out["message_length"] = str(exc)[:3000], len(str(exc))
    out["warnings"] = sorted({w.category.__name__ for w in caught})
    if model is not None and not caught:
        out["dynamics"], out["dynamics_warnings"] = _dynamics(model, job["id"], job.get("backend", "reference"))
    out["seconds"] = time.perf_counter() - start
    return out


def main(path: str) -> None:
    with open(path, encoding="utf-8") as f:
        for line in f:
            sys.stdout.write(json.dumps(_one(json.loads(line))) + "\n")
            sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1])
