"""The ``featherdyn`` command line (also ``python -m featherdyn``).

Exit codes: 0 everything agrees, 1 a mismatch, 2 a usage or model error
(with a one-line message, never a traceback).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
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
    parser = _Parser(
        prog="featherdyn",
        description="Spatial vector algebra and rigid-body dynamics, verified against Pinocchio.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    v = sub.add_parser("verify", help="compare featherdyn with Pinocchio and check oracle-free identities")
    v.add_argument("--samples", type=_positive_int, default=50, help="random values per check (default 50)")
    v.add_argument("--seed", type=int, default=0, help="random seed (default 0; same seed, same report)")
    v.add_argument("--tol", type=_positive_float, default=None, help="relative tolerance (default 1e-12)")
    v.add_argument("--json", type=Path, default=None, metavar="FILE", help="also write the full report as JSON")
    return parser


def _cmd_verify(args: argparse.Namespace) -> int:
    from . import verify

    report = verify.run(samples=args.samples, seed=args.seed, tol=args.tol)
    print(report.to_table())
    if args.json is not None:
        try:
            args.json.write_text(report.to_json() + "\n", encoding="utf-8")
        except OSError as exc:
            print(f"featherdyn: error: cannot write {args.json}: {exc.strerror}", file=sys.stderr)
            return EXIT_USAGE
        print(f"report written to {args.json}")
    return EXIT_OK if report.passed else EXIT_MISMATCH


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    try:
        if args.command == "verify":
            return _cmd_verify(args)
    except FeatherdynError as exc:
        print(f"featherdyn: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    parser.print_help()  # pragma: no cover - argparse rejects unknown commands
    return EXIT_USAGE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
