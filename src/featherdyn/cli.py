"""The ``featherdyn`` command line (also ``python -m featherdyn``).

::

    featherdyn verify [ROBOT|URDF] [--floating-base] [--samples N] [--seed S] [--tol T]
                      [--json FILE] [--report FILE.html] [--all]
    featherdyn check VALUES.npz --robot ROBOT|URDF [--floating-base] [--convention featherdyn|pinocchio]
                     [--tol T] [--json FILE]
    featherdyn info ROBOT|URDF [--floating-base]
    featherdyn list
    featherdyn bench [ROBOT] [--floating-base] [--repeats N] [--batch N] [--chains 8,16,...] [--output FILE]

Exit codes: 0 everything agrees, 1 a mismatch, 2 a usage or model error
(with a one-line message, never a traceback).
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

from .errors import FeatherdynError

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_MISMATCH, EXIT_USAGE = 0, 1, 2


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"featherdyn: error: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _positive_int(text: str) -> int:
    try:
        val = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if val < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {val}")
    return val


def _positive_float(text: str) -> float:
    try:
        val = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (val > 0 and val < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {text!r}")
    return val


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``featherdyn`` command."""
    parser = _Parser(prog="featherdyn",
                     description="Spatial vector algebra and rigid-body dynamics, verified against Pinocchio.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    v = sub.add_parser("verify", help="compare featherdyn with Pinocchio on a robot and check oracle-free identities")
    v.add_argument("robot", nargs="?", default=None, metavar="ROBOT|URDF",
                   help="a robot-library name (see `featherdyn list`) or a URDF file; default: the default robot")
    v.add_argument("--floating-base", action="store_true", help="put the root link on a free-flyer joint")
    v.add_argument("--samples", type=_positive_int, default=10, help="random states per check (default 10)")
    v.add_argument("--seed", type=int, default=0, help="random seed (default 0; same seed, same report)")
    v.add_argument("--tol", type=_positive_float, default=None, help="relative tolerance (default 1e-9)")
    v.add_argument("--json", type=Path, default=None, metavar="FILE", help="write the full report as JSON")
    v.add_argument("--report", type=Path, default=None, metavar="FILE.html",
                   help="write an HTML report with the table and plots (opens offline)")
    v.add_argument("--all", action="store_true", help="verify every robot of the library (takes minutes)")
    v.add_argument("--strict", action="store_true", help="physicality warnings of the URDF loader are errors")
    i = sub.add_parser("info", help="the kinematic tree, joints, masses and inertia validity of a robot")
    i.add_argument("robot", metavar="ROBOT|URDF")
    i.add_argument("--floating-base", action="store_true")
    sub.add_parser("list", help="the names of the robot library")
    _add_check(sub)
    from .bench import add_arguments as add_bench_arguments

    add_bench_arguments(sub.add_parser("bench", help="time the compiled engine against Pinocchio (ratios)"))
    return parser


def _add_check(sub: argparse._SubParsersAction[_Parser]) -> None:
    """``featherdyn check VALUES.npz --robot ROBOT`` (:func:`featherdyn.verify.check.check_values`)."""
    from .verify.check import CONVENTIONS, DEFAULT_TOL

    p = sub.add_parser(
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


def _cmd_check(args: argparse.Namespace) -> int:
    from .verify.check import check_values

    try:
        report = check_values(args.values, args.robot, floating_base=args.floating_base,
                              convention=args.convention, tol=args.tol)
    except TypeError as exc:  # a value of the wrong type inside the archive
        raise FeatherdynError(str(exc)) from None
    print(report.to_text())
    if args.json is not None:
        _write(args.json, report.to_json() + "\n")
        print(f"JSON report written to {args.json}")
    return EXIT_OK if report.passed else EXIT_MISMATCH


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
    from . import verify
    from .verify.html import reports_to_html

    if args.all and args.robot:
        raise FeatherdynError("give either a ROBOT or --all, not both")
    tty = sys.stderr.isatty()
    reports = []
    if args.all:
        from .robots import list_robots

        names = list_robots()
        for k, name in enumerate(names, 1):
            print(f"[{k}/{len(names)}] {name}", file=sys.stderr, flush=True)
            try:
                rep = verify.run(name, floating_base=args.floating_base, samples=args.samples, seed=args.seed,
                                 tol=args.tol, algebra=(k == 1), strict=args.strict)
            except FeatherdynError as exc:  # a robot that does not load is reported, not fatal
                rep = verify.VerifyReport(title=f"featherdyn verify {name}: not loadable",
                                          meta={"robot": name, "error": str(exc)})
                rep.results.append(verify.CheckResult("load", "load_urdf", float("nan"), float("nan"), 0, 0.0,
                                                      False, str(exc)))
            reports.append(rep)
        width = max(len(n) for n in names)
        print(f"{'robot':<{width}}  checks  failed  worst rel err")
        for rep in reports:
            worst = max((r.max_rel for r in rep.results if r.max_rel == r.max_rel), default=float("nan"))
            print(f"{rep.meta.get('robot', '?'):<{width}}  {len(rep.results):>6}  {len(rep.failures):>6}  {worst:.2e}")
        for rep in reports:
            for r in rep.failures:
                print(f"FAIL {rep.meta.get('robot')}: {r.quantity}: {r.note}")
    else:
        report = verify.run(args.robot, floating_base=args.floating_base, samples=args.samples, seed=args.seed,
                            tol=args.tol, strict=args.strict, progress=_progress(tty))
        reports.append(report)
        print(report.to_table())
    if args.json is not None:
        text = reports[0].to_json() if len(reports) == 1 else \
            json.dumps({"reports": [json.loads(r.to_json()) for r in reports]}, indent=2, ensure_ascii=False)
        _write(args.json, text + "\n")
        print(f"JSON report written to {args.json}")
    if args.report is not None:
        _write(args.report, reports_to_html(reports))
        print(f"HTML report written to {args.report}")
    return EXIT_OK if all(r.passed for r in reports) else EXIT_MISMATCH


def _cmd_list(args: argparse.Namespace) -> int:
    from .robots import list_robots

    for name in list_robots():
        print(name)
    return EXIT_OK


def _cmd_info(args: argparse.Namespace) -> int:
    import numpy as np

    from .errors import InertiaError
    from .urdf import load_urdf
    from .verify import resolve_robot

    _name, path = resolve_robot(args.robot)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_urdf(path, floating_base=args.floating_base)
    base = "floating" if model.floating_base else "fixed"
    print(f"{model.name} ({path})")
    print(f"  {base} base, {model.nbodies} bodies, nq={model.nq}, nv={model.nv}, total mass {model.total_mass:.6g} kg")
    print("kinematic tree:")
    depth = [0] * model.nbodies
    for i, p in enumerate(model.parents):
        depth[i] = 0 if p == -1 else depth[p] + 1
        joint = model.joints[i]
        axis = getattr(joint, "axis", getattr(joint, "normal", None))
        ax = f" axis {np.round(axis, 6).tolist()}" if axis is not None else ""
        try:
            model.inertias[i].check()
            valid = "inertia ok"
        except InertiaError as exc:
            valid = f"INERTIA NOT PHYSICAL: {str(exc).split(': ', 1)[-1]}"
        print(f"  {'  ' * depth[i]}{model.body_names[i]}  [{joint.kind} {model.joint_names[i]!r}{ax}; "
              f"q[{model.idx_q[i]}:{model.idx_q[i] + model.nqs[i]}] v[{model.idx_v[i]}:{model.idx_v[i] + model.nvs[i]}]; "
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
    commands = {"verify": _cmd_verify, "list": _cmd_list, "info": _cmd_info, "check": _cmd_check, "bench": _cmd_bench}
    try:
        return commands[args.command](args)
    except (FeatherdynError, ValueError) as exc:
        print(f"featherdyn: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:  # pragma: no cover
        return EXIT_USAGE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
