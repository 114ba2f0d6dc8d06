"""The ``featherdyn`` command line (also ``python -m featherdyn``).

::

    featherdyn verify [ROBOT|URDF|MJCF|SDF] [--oracle pinocchio|mujoco|both|drake|all] [--floating-base] [--samples N] [--seed S] [--tol T] [--contacts F1,F2]
                      [--json FILE] [--report FILE.html] [--all [--scheduler local|ADDRESS] [--workers W]]
    featherdyn check VALUES.npz --robot ROBOT|URDF [--floating-base] [--convention featherdyn|pinocchio]
                     [--frame FRAME] [--reference LOCAL|WORLD|LOCAL_WORLD_ALIGNED]
                     [--tol T] [--json FILE]
    featherdyn dataset ROBOT|URDF --states N --out DIR.zarr [--quantities tau,M,ddq] [--floating-base]
                       [--seed S] [--chunk C] [--scheduler auto|local|sync|ADDRESS] [--workers W]
    featherdyn info ROBOT|URDF [--floating-base]
    featherdyn info --build
    featherdyn list
    featherdyn bench [ROBOT|URDF] [--floating-base] [--repeats N] [--batch N] [--chains 8,16,...] [--output FILE]
    featherdyn --version

Exit codes: 0 everything agrees, 1 a mismatch, 2 a usage or model error
(with a one-line message, never a traceback), 130 interrupted by Ctrl-C (one line; an interrupted
``dataset`` keeps its finished chunks and resumes when run again). Arguments, input files and
output folders are checked before any work; progress notices (a large URDF,
``--all``) go to stderr, reports to stdout.

This module is the top of the tools layer: it imports :mod:`featherdyn.verify`
and :mod:`featherdyn.tools.bench`, which never import it (``docs/architecture.md``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import FeatherdynError
from .args import check_writable, plural, positive_float, positive_int

if TYPE_CHECKING:
    from ..verify.report import VerifyReport

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_MISMATCH, EXIT_USAGE = 0, 1, 2
#: Ctrl-C: 128 + SIGINT, as a shell reports a command the signal stopped
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"featherdyn: error: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``featherdyn`` command."""
    parser = _Parser(prog="featherdyn",
                     description="Spatial vector algebra and rigid-body dynamics, verified against Pinocchio.")
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"featherdyn {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    v = sub.add_parser("verify", help="compare featherdyn with Pinocchio on a robot and check oracle-free identities")
    v.add_argument("robot", nargs="?", default=None, metavar="ROBOT|URDF|MJCF|SDF",
                   help="a robot-library name (see `featherdyn list`), a URDF, an MJCF or (with Drake) an SDFormat "
                        "file; default: the default robot")
    v.add_argument("--floating-base", action="store_true", help="put the root link on a free-flyer joint")
    v.add_argument("--samples", type=positive_int, default=10, help="random states per check (default 10)")
    v.add_argument("--seed", type=int, default=0, help="random seed (default 0; same seed, same report)")
    v.add_argument("--tol", type=positive_float, default=None, help="relative tolerance (default 1e-9)")
    v.add_argument("--json", type=Path, default=None, metavar="FILE", help="write the full report as JSON")
    v.add_argument("--report", type=Path, default=None, metavar="FILE.html",
                   help="write an HTML report with the table and plots (opens offline)")
    v.add_argument("--all", action="store_true",
                   help="verify every robot of the library (seconds, not minutes: about 0.15 s a robot, "
                        "10 s for example-robot-data's 69 on two cores)")
    v.add_argument("--strict", action="store_true", help="physicality warnings of the URDF loader are errors")
    v.add_argument("--oracle", choices=("pinocchio", "mujoco", "both", "drake", "all"), default=None,
                   help="what to compare with: Pinocchio (the default for a URDF), MuJoCo (the default for an MJCF "
                        "model; a URDF through MuJoCo's URDF importer), both, Drake (pip install drake; the default "
                        "for an SDFormat file) or all three (those that cannot take the model are named and left out)")
    v.add_argument("--scheduler", default=None, metavar="local|ADDRESS",
                   help="with --all: spread the robots over Dask workers (local: a LocalCluster on this machine; "
                        "or a dask.distributed scheduler address)")
    v.add_argument("--workers", type=positive_int, default=None, metavar="W",
                   help="worker processes of --scheduler local (default: the cores available)")
    v.add_argument("--contacts", default="", metavar="FRAME[,FRAME...]",
                   help="also compare constrained and impulse dynamics with these frames held (Pinocchio's "
                        "constraintDynamics / impulseDynamics)")
    i = sub.add_parser("info", help="the kinematic tree, joints, masses and inertia validity of a robot; "
                                    "--build: how the compiled core was built")
    i.add_argument("robot", metavar="ROBOT|URDF", nargs="?")
    i.add_argument("--floating-base", action="store_true")
    i.add_argument("--build", action="store_true",
                   help="print how featherdyn's compiled core was built (compiler, SIMD kernels in use, NumPy's C API, "
                        "nanobind, build type) instead of a robot")
    sub.add_parser("list", help="the names of the robot library (legged, humanoid and flying robots want "
                                "--floating-base)")
    _add_check(sub)
    _add_dataset(sub)
    from .bench import add_arguments as add_bench_arguments

    add_bench_arguments(sub.add_parser("bench", help="time the compiled core against Pinocchio (ratios)"))
    return parser


def _add_check(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``featherdyn check VALUES.npz --robot ROBOT`` (:func:`featherdyn.verify.check.check_values`)."""
    from ..verify.check import CONVENTIONS, DEFAULT_TOL

    p = sub.add_parser(
        "check", help="check your own numbers (an .npz of q, v, a, tau, M, ddq) against featherdyn and "
                      "diagnose a mismatch",
        description="Check the values in VALUES.npz (keys q, v, a and any of tau, M, ddq with tau, and derivative "
                    "matrices: dtau_dq, dtau_dv, dddq_dq, dddq_dv, dg_dq, dc_dq, dcdot_dq, dh_dq, dhdot_dq, dhdot_dv, "
                    "dhdot_da, and with --frame dv_dq, dv_dv, da_dq, da_dv, da_da, dac_dq, dac_dv, dac_da; one state "
                    "or a batch along a leading axis) against featherdyn. On a mismatch, try the usual suspects (6D "
                    "order, world-frame base velocity, quaternion order, classical acceleration, gravity, "
                    "continuous joints, joint order, triangular M; for derivative matrices: transposed, tangent, "
                    "[v; ω] or [p; k] rows, reference frame, Pinocchio's LOCAL_WORLD_ALIGNED convention) and say "
                    "which one explains the numbers. "
                    "Exit codes: 0 all agree, 1 a mismatch, 2 a usage or model error.")
    p.add_argument("values", metavar="VALUES.npz", help="an .npz archive of named arrays (numpy.savez)")
    p.add_argument("--robot", required=True, metavar="ROBOT|URDF",
                   help="a robot-library name (see `featherdyn list`) or a URDF file")
    p.add_argument("--floating-base", action="store_true", help="put the root link on a free-flyer joint")
    p.add_argument("--convention", choices=CONVENTIONS, default="featherdyn",
                   help="the layout of the values (default featherdyn; pinocchio: continuous joints as cos/sin, "
                        "Pinocchio's joint order, free-flyer [v; ω] LOCAL)")
    p.add_argument("--tol", type=positive_float, default=DEFAULT_TOL,
                   help=f"relative tolerance |a − b| / max(|b|, 1) (default {DEFAULT_TOL:g})")
    p.add_argument("--frame", default=None, metavar="FRAME",
                   help="the frame of the frame derivatives dv_dq, dv_dv, da_*, dac_* (fd.kinematics_derivatives)")
    p.add_argument("--reference", choices=("LOCAL", "WORLD", "LOCAL_WORLD_ALIGNED"), default="LOCAL",
                   help="their reference frame (default LOCAL)")
    p.add_argument("--json", type=Path, default=None, metavar="FILE", help="write the full report as JSON")


def _add_dataset(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``featherdyn dataset ROBOT --states N --out DIR.zarr`` (:mod:`featherdyn.tools.dataset`)."""
    from .dataset import DEFAULT_QUANTITIES, QUANTITIES

    p = sub.add_parser(
        "dataset", help="random states and their dynamics written to Zarr (resumable; one machine or a Dask cluster)",
        description="Draw N random states (q within the joint limits; v, a, u standard normal) and write them with "
                    "the chosen quantities to a Zarr group, one array per quantity, chunk by chunk. Deterministic "
                    "for a seed whatever the number of workers; run the same command again to resume. Quantities: "
                    + "; ".join(f"{k}: {q.description}" for k, q in QUANTITIES.items()) + ".")
    p.add_argument("robot", metavar="ROBOT|URDF", help="a robot-library name (see `featherdyn list`) or a URDF file")
    p.add_argument("--states", type=positive_int, required=True, metavar="N", help="number of states")
    p.add_argument("--out", type=Path, required=True, metavar="DIR.zarr", help="the Zarr directory to write")
    p.add_argument("--quantities", default=",".join(DEFAULT_QUANTITIES),
                   help=f"comma-separated (default {','.join(DEFAULT_QUANTITIES)}; any of {','.join(QUANTITIES)})")
    p.add_argument("--floating-base", action="store_true", help="put the root link on a free-flyer joint")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--chunk", type=positive_int, default=10_000, metavar="C",
                   help="states per chunk and per Zarr chunk (default 10000)")
    p.add_argument("--scheduler", default="auto", metavar="auto|local|sync|ADDRESS",
                   help="auto (default): local with --workers or on 4+ cores for at least one chunk per core, else "
                        "sync (faster on fewer cores: the compute already uses every core, workers cost seconds "
                        "to start); local: a LocalCluster of worker processes; sync: this process; or the address "
                        "of a dask.distributed scheduler")
    p.add_argument("--workers", type=positive_int, default=None, metavar="W",
                   help="worker processes of --scheduler local (default: the cores available)")


def _cmd_dataset(args: argparse.Namespace) -> int:
    from .. import verify
    from .dataset import DatasetInterrupted, check_request, choose_scheduler, progress_bar, write_dataset

    quantities = check_request(args.quantities.split(","), args.out, args.states, args.chunk, args.seed)
    _name, path = verify.resolve_robot(args.robot)
    model = verify.load_resolved(path, args.floating_base)
    scheduler, why = args.scheduler, ""
    if scheduler == "auto":
        scheduler, why = choose_scheduler(-(-args.states // args.chunk), args.workers)
        why = f" (--scheduler auto: {why})"
    _say(f"{plural(args.states, 'state')} of {args.robot} ({model.nq} q, {model.nv} v), "
         f"{', '.join(quantities)} -> {args.out}; scheduler {scheduler}{why}")
    try:
        run = write_dataset(model, args.out, states=args.states, quantities=quantities, seed=args.seed,
                            chunk=args.chunk, scheduler=scheduler, workers=args.workers, robot=str(args.robot),
                            floating_base=args.floating_base, progress=progress_bar())
    except DatasetInterrupted as exc:
        if sys.stderr.isatty():
            print(file=sys.stderr)  # after the progress bar and the terminal's ^C
        print(exc, file=sys.stderr, flush=True)
        return EXIT_INTERRUPTED
    done = f"{plural(run.computed_chunks, 'chunk')} computed, {run.skipped_chunks} already done"
    speed = (f"{run.seconds:.1f} s ({run.states_per_second:,.0f} states/s)" if run.computed_chunks
             else "nothing left to compute")
    print(f"{run.out}: {plural(run.states, 'state')}; {done}; {speed}")
    return EXIT_OK


def _cmd_check(args: argparse.Namespace) -> int:
    from ..verify.check import check_values

    check_writable(args.json, "--json")
    try:
        report = check_values(args.values, args.robot, floating_base=args.floating_base,
                              convention=args.convention, tol=args.tol, frame=args.frame, reference=args.reference)
    except TypeError as exc:  # a value of the wrong type inside the archive
        raise FeatherdynError(str(exc)) from None
    print(report.to_text())
    if args.json is not None:
        _write(args.json, report.to_json() + "\n")
        print(f"JSON report written to {args.json}")
    return EXIT_OK if report.passed else EXIT_MISMATCH


def _say(msg: str) -> None:
    """A line on stderr about what is happening (never on stdout, which holds the report)."""
    print(f"featherdyn: {msg}", file=sys.stderr, flush=True)


#: a URDF file above this size takes a second or more to load: say so first.
_LARGE_URDF_BYTES = 2_000_000


def _announce_large(path: Path) -> None:
    size = path.stat().st_size
    if size > _LARGE_URDF_BYTES:
        _say(f"loading {path} ({size / 1e6:.1f} MB)…")


def _progress(enabled: bool) -> Callable[[str], None]:
    def show(msg: str) -> None:
        if enabled:
            print(f"  … {msg}", file=sys.stderr, flush=True)
    return show


def _write(path: Path, text: str) -> None:
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise FeatherdynError(f"cannot write {path}: {exc.strerror}") from None


def _cmd_verify(args: argparse.Namespace) -> int:
    from .. import verify
    from ..verify.html import reports_to_html
    from ..verify.pinocchio import require_pinocchio

    if args.all and args.robot:
        raise FeatherdynError("give either a ROBOT or --all, not both")
    if args.scheduler is not None and not args.all:
        raise FeatherdynError("--scheduler spreads the robots of --all over workers: give --all as well")
    check_writable(args.json, "--json")
    check_writable(args.report, "--report")
    if args.all:  # (one robot: verify.run asks for the oracles it needs)
        if args.oracle not in (None, "pinocchio", "drake"):
            raise FeatherdynError(f"--all verifies the URDF library against Pinocchio or Drake; --oracle {args.oracle} "
                                  "takes one model")
        if args.oracle == "drake":
            from ..verify.drake import require_drake

            require_drake()
        else:
            require_pinocchio()
    tty = sys.stderr.isatty()
    reports = []
    if args.all:
        from ..robots import list_robots

        names = list_robots()
        _say(f"verifying {plural(len(names), 'robot')} of the library, one line per robot (a few seconds in all)…")
        options = {"floating_base": args.floating_base, "samples": args.samples, "seed": args.seed,
                   "tol": args.tol, "strict": args.strict, "oracle": args.oracle}
        if args.scheduler is None:
            for k, name in enumerate(names, 1):
                print(f"[{k}/{len(names)}] {name}", file=sys.stderr, flush=True)
                reports.append(verify.run_or_report(name, algebra=(k == 1), **options))
        else:
            reports = _verify_distributed(names, options, args.scheduler, args.workers)
        print(_all_table(reports))
    else:
        _name, path = verify.resolve_robot(args.robot)  # a bad name or path is refused before anything is printed
        _announce_large(path)
        contacts = [f.strip() for f in args.contacts.split(",") if f.strip()]
        report = verify.run(args.robot, floating_base=args.floating_base, samples=args.samples, seed=args.seed,
                            contacts=contacts, oracle=args.oracle,
                            tol=args.tol, strict=args.strict, progress=_progress(tty))
        reports.append(report)
        print(report.to_table())
    if args.json is not None:
        text = reports[0].to_json() if len(reports) == 1 else \
            json.dumps({"reports": [json.loads(r.to_json()) for r in reports],
                        "refused": {str(r.meta.get("robot")): verify.refused_by(r) for r in reports
                                    if verify.refused_by(r)}}, indent=2, ensure_ascii=False)
        _write(args.json, text + "\n")
        print(f"JSON report written to {args.json}")
    if args.report is not None:
        _write(args.report, reports_to_html(reports))
        print(f"HTML report written to {args.report}")
    return EXIT_OK if all(r.passed for r in reports) else EXIT_MISMATCH


#: what ``verify --all`` prints under its table: why the robots' check counts differ
_ALL_NOTES = (
    "worst rel err: the relative error of the robot's check closest to its tolerance, and that tolerance "
    "('scaled by cond(M)': the condition number of M times the base tolerance, as for M⁻¹ and ABA's derivatives).",
    "The number of checks follows the robot: 26 for each frame checked, a link frame on each of its (up to) 3 deepest "
    "bodies (velocity, acceleration, classical acceleration, Jacobian and its time variation, and the derivatives of "
    "the velocity, acceleration and classical acceleration, in 3 reference frames; a point's derivatives in 2), "
    "no forward-dynamics checks "
    "where M is singular, no joint-space ones without joints; the first robot also carries the "
    "spatial-algebra checks (run once).",
)


def _all_table(reports: Sequence[VerifyReport]) -> str:
    """``verify --all``'s table: one row per robot, the failures, notes, and a totals line."""
    from ..verify import refused_by
    from ..verify.report import COND_SCALED

    refused = {str(rep.meta.get("robot", "?")): refused_by(rep) for rep in reports if refused_by(rep)}
    compared = [rep for rep in reports if str(rep.meta.get("robot", "?")) not in refused]
    names = [str(rep.meta.get("robot", "?")) for rep in compared]
    width = max(len("robot"), *(len(n) for n in names))
    lines = [f"{'robot':<{width}}  checks  failed  worst rel err  its tol"]
    for name, rep in zip(names, compared, strict=True):
        judged = [r for r in rep.results if r.max_rel == r.max_rel and r.tol > 0]  # not NaN
        worst = max(judged, key=lambda r: r.max_rel / r.tol, default=None)  # the closest to failing
        tol = "" if worst is None else f"{worst.tol:.0e}" + (" (scaled by cond(M))" if COND_SCALED in worst.quantity
                                                               else "")
        err = f"{worst.max_rel:.2e}" if worst is not None else "nan"
        lines.append(f"{name:<{width}}  {len(rep.results):>6}  {len(rep.failures):>6}  {err:>13}  {tol}")
    for name, rep in zip(names, compared, strict=True):
        lines += [f"FAIL {name}: {r.quantity}: {r.note}" for r in rep.failures]
        if rep.failures:  # what the oracle's parser said of the file: a likely reason of the failures above
            lines += [f"  {name}: {n}" for n in rep.meta.get("oracle_notes", []) if "parser" in n]
    if refused:  # not failures: the oracle cannot take these as featherdyn's model (its parser's own words)
        lines += ["", f"refused by {'/'.join(sorted({k.capitalize() for r in refused.values() for k in r}))} "
                      f"(not compared; the oracle's reason):"]
        lines += [f"  {name}: {_MODEL_PATH.sub('', why)}" for name, r in refused.items() for why in r.values()]
    checks, failed = sum(len(r.results) for r in compared), sum(len(r.failures) for r in compared)
    bad = sum(1 for r in compared if r.failures)
    verdict = "all passed" if not failed else f"{failed} failed on {plural(bad, 'robot')}"
    lines += ["", *_ALL_NOTES, "",
              f"total: {plural(len(reports), 'robot')}: {len(compared)} compared, {len(compared) - bad} agree, "
              f"{bad} disagree, {len(refused)} refused by the oracle; {plural(checks, 'check')}, {verdict}"]
    return "\n".join(lines)


#: the folders of a model file's path in a refusal's reason (the table names the robot; the file name stays)
_MODEL_PATH = re.compile(r"/\S+/(?=[^/\s]+\.(?:urdf|xml|sdf)\b)", re.IGNORECASE)


def _verify_distributed(names: list[str], options: dict[str, object], scheduler: str,
                        workers: int | None) -> list:
    """``verify --all --scheduler``: one task per robot on Dask workers; reports in the library's order."""
    from dask.distributed import as_completed

    from .. import verify
    from .distributed import dask_client

    with dask_client(scheduler, workers) as client:
        futures = {client.submit(verify.run_or_report, name, algebra=(k == 0), key=f"featherdyn-verify-{name}",
                                 retries=1, **options): name for k, name in enumerate(names)}
        done: dict[str, object] = {}
        for k, fut in enumerate(as_completed(futures), 1):
            done[futures[fut]] = fut.result()
            print(f"[{k}/{len(names)}] {futures[fut]}", file=sys.stderr, flush=True)
    return [done[name] for name in names]


def _cmd_list(args: argparse.Namespace) -> int:
    from ..robots import list_robots

    for name in list_robots():
        print(name)
    # on stderr, so that stdout stays one name per line for scripts
    print("featherdyn: robots that walk or fly (quadrupeds such as solo12 and go1, humanoids such as "
          "talos_full_v2, drones) move their root freely: give --floating-base to verify, info, dataset and bench "
          "(a free-flyer root joint; without it the root link is fixed to the world)", file=sys.stderr)
    return EXIT_OK


def _limits(lower: np.ndarray, upper: np.ndarray, velocity: np.ndarray, effort: np.ndarray) -> str:
    """A joint's limits as ``info`` prints them (``"q [-2.9, 2.9], |v| ≤ 2.2, |τ| ≤ 87; "``), or ``""`` if it has none."""
    def fmt(x: np.ndarray) -> str:
        vals = [f"{float(e):.6g}" for e in x]
        return vals[0] if len(vals) == 1 else "(" + ", ".join(vals) + ")"

    parts = []
    if np.any(np.isfinite(lower)) or np.any(np.isfinite(upper)):
        parts.append(f"q [{fmt(lower)}, {fmt(upper)}]")
    if np.any(np.isfinite(velocity)):
        parts.append(f"|v| ≤ {fmt(velocity)}")
    if np.any(np.isfinite(effort)):
        parts.append(f"|τ| ≤ {fmt(effort)}")
    return "limits " + ", ".join(parts) + "; " if parts else ""


def build_report() -> list[str]:
    """The lines of ``featherdyn info --build``: this installation and how its compiled core was built."""
    from .. import __version__

    lines = [f"featherdyn {__version__} ({Path(__file__).resolve().parents[1]})",
             f"  Python {sys.version.split()[0]}, NumPy {np.__version__}"]
    try:
        from ..core import _core
    except ImportError as exc:
        return [*lines, f"  compiled core: not importable ({exc}); reinstall featherdyn with pip"]
    info = _core.build_info()
    simd = os.environ.get("FEATHERDYN_SIMD")
    forced = f" (FEATHERDYN_SIMD={simd})" if simd else ""
    compiled = ", ".join(str(x) for x in info["simd_compiled"]) if isinstance(info["simd_compiled"], tuple) else "?"
    stub = Path(_core.__file__).with_name("_core.pyi")
    jax_ffi = (f"XLA FFI handler built with {info['jax_ffi']}'s headers" if info["jax_ffi"] else
               "no XLA FFI handler (jaxlib was not in the build environment)")
    return [
        *lines,
        f"  compiled core: {Path(_core.__file__).name}",
        f"  compiler: {info['compiler']}, {info['build_type']} build, for {info['processor']}",
        f"  SIMD: {info['simd']} × {info['simd_lanes']} lanes in use{forced}; compiled: {compiled} "
        "(FEATHERDYN_SIMD=baseline forces the portable kernels)",
        f"  NumPy C API: NumPy {info['numpy_headers']}'s headers (API {info['numpy_api']}), for NumPy >= "
        f"{info['numpy_minimum']} (API {info['numpy_target_api']})",
        f"  nanobind {info['nanobind']}; built for Python {info['python']}, stable ABI (abi3): "
        f"{'yes' if info['stable_abi'] else 'no'}",
        f"  type stub: {'_core.pyi' if stub.exists() else 'none (a source checkout: the wheel has one)'}",
        f"  featherdyn.jax: {jax_ffi}",
    ]


def _cmd_info(args: argparse.Namespace) -> int:
    if args.build:
        print("\n".join(build_report()))
        return EXIT_OK
    if args.robot is None:
        raise FeatherdynError("info: give a ROBOT or URDF, or --build")
    from ..verify import load_resolved, resolve_robot
    from ..verify.dynamics import inertia_problem

    _name, path = resolve_robot(args.robot)
    _announce_large(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_resolved(path, args.floating_base)
    base = "floating" if model.floating_base else "fixed"
    named = f"{args.robot}: the model {model.name!r}" if model.name != Path(str(args.robot)).stem else model.name
    print(f"{named} ({path})")
    print(f"  {base} base, {model.nbodies} bodies, nq={model.nq}, nv={model.nv}, total mass {model.total_mass:.6g} kg")
    print("kinematic tree:")
    depth = [0] * model.nbodies
    for i, p in enumerate(model.parents):
        depth[i] = 0 if p == -1 else depth[p] + 1
        joint = model.joints[i]
        axis = getattr(joint, "axis", getattr(joint, "normal", None))
        ax = f" axis {np.round(axis, 6).tolist()}" if axis is not None else ""
        problem = inertia_problem(model, i)
        valid = (f"INERTIA NOT PHYSICAL: {problem.split(': ', 1)[-1]}" if problem else
                 "massless joint carrier inserted by the loader" if model.body_names[i] in model.inserted_bodies
                 else "inertia ok")
        q_range = slice(model.idx_q[i], model.idx_q[i] + model.nqs[i])
        v_range = slice(model.idx_v[i], model.idx_v[i] + model.nvs[i])
        limits = _limits(model.lower[q_range], model.upper[q_range], model.velocity_limit[v_range],
                         model.effort_limit[v_range])
        print(f"  {'  ' * depth[i]}{model.body_names[i]}  [{joint.kind} {model.joint_names[i]!r}{ax}; "
              f"q[{q_range.start}:{q_range.stop}] v[{v_range.start}:{v_range.stop}]; {limits}"
              f"m={float(model.inertias.mass[i]):.4g} kg; {valid}]")
    print(f"frames ({len(model.frames)}):")
    for f in model.frames:
        owner = "world" if f.body == -1 else model.body_names[f.body]
        print(f"  {f.name}  ({f.kind}, on {owner}, at {np.round(f.placement.translation, 6).tolist()})")
    for w in sorted({str(w.message) for w in caught}):
        print(f"warning: {w}")
    return EXIT_OK


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench import run

    return run(args)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    commands = {"verify": _cmd_verify, "list": _cmd_list, "info": _cmd_info, "check": _cmd_check, "bench": _cmd_bench,
                "dataset": _cmd_dataset}
    try:
        return commands[args.command](args)
    except (FeatherdynError, ValueError) as exc:
        print(f"featherdyn: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # `featherdyn info talos_full_v2 | head`: the reader left; say nothing more
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:  # Ctrl-C anywhere else: one line, no traceback
        print("\nfeatherdyn: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
