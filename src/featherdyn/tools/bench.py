"""``featherdyn bench [ROBOT]``: the compiled core against Pinocchio, in the same process.

Every figure is a ratio ``featherdyn time / Pinocchio time`` (below 1: featherdyn
is faster) or a throughput ratio, from interleaved repetitions (featherdyn,
Pinocchio, featherdyn, ...) and their medians, so that both sides see the same
machine load. Both libraries read the same URDF; states are converted with
:class:`featherdyn.verify.bridge.JointMap` before timing.

Sections: single calls (``fd.compile(model)`` methods against ``pin.rnea`` &
co.), batched throughput (``rnea_batch`` & co. on every core against a Python
loop over Pinocchio), a scaling table over revolute chains of 8…512 links,
and compile / load times. ``python benchmarks/bench.py`` runs the same code.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import time
import warnings
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from ..errors import FeatherdynError, MissingDependencyError
from ..model import Model
from ..verify.pinocchio import PinModel
from .args import check_writable, positive_int

__all__ = ["bench_main", "build_parser", "add_arguments", "run", "chain_urdf"]

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]
CHAIN_LENGTHS = [8, 16, 32, 64, 128, 256, 512]
#: the frame of the single-call Jacobian: a tool or foot at the end of a long branch
JACOBIAN_FRAMES = {"panda": "panda_hand", "solo12": "HR_FOOT", "talos_full_v2": "gripper_left_base_link"}
TARGETS = {"single": 1.0, "batch": 6.0, "chain512": 0.5}


def _median_ratio(fd_call: Callable[[], object], pin_call: Callable[[], object], repeats: int,
                  budget: float = 2e-3) -> tuple[float, float]:
    """Median seconds per call of both, interleaved; each sample runs about ``budget`` seconds."""
    def pair(n: int) -> tuple[float, float]:
        """Seconds for ``n`` featherdyn calls, then for ``n`` Pinocchio calls."""
        t0 = time.perf_counter()
        for _ in range(n):
            fd_call()
        t1 = time.perf_counter()
        for _ in range(n):
            pin_call()
        return t1 - t0, time.perf_counter() - t1

    fd_call()
    pin_call()
    n = 1
    while True:  # calibrate on the slower of the two
        t_fd, t_pin = pair(n)
        if max(t_fd, t_pin) >= budget / 4 or n >= 1 << 20:
            break
        n *= 2
    n = max(1, int(n * budget / max(t_fd, t_pin, 1e-9)))
    a, b = [], []
    for _ in range(repeats):
        t_fd, t_pin = pair(n)
        a.append(t_fd / n)
        b.append(t_pin / n)
    return statistics.median(a), statistics.median(b)


def _versions() -> list[str]:
    import pinocchio

    import featherdyn

    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return [
        f"- date: {datetime.datetime.now().isoformat(timespec='seconds')}",
        f"- featherdyn {featherdyn.__version__}, numpy {np.__version__}, "
        f"pinocchio {pinocchio.__version__}, Python {platform.python_version()}",
        f"- machine: {platform.system()} {platform.machine()}, {cpu}, {os.cpu_count()} logical cores, "
        f"core threads {featherdyn.get_num_threads()}, batched kernels {_simd()}",
    ]


def _simd() -> str:
    """The batched kernels' instruction set and lanes, e.g. ``avx2 × 4``."""
    from ..core import _core

    isa, width = _core.simd()
    return f"{isa} × {width}"


class _Pair:
    """A robot loaded by both libraries, with converted random states."""

    def __init__(self, name: str, model: Model, pin_model: PinModel, seed: int = 0) -> None:
        from ..api import compile as compile_model
        from ..verify.bridge import JointMap

        self.name, self.model, self.pm = name, model, pin_model
        self.pd = pin_model.createData()
        self.jm = JointMap(model, pin_model)
        self.cm = compile_model(model)
        self.rng = np.random.default_rng(seed)

    @classmethod
    def from_urdf(cls, name: str, path: str, floating: bool) -> _Pair:
        """A robot read from the same URDF by both libraries (an MJCF file: Pinocchio's model mirrors featherdyn's)."""
        import pinocchio as pin

        from ..readers.mjcf import model_format
        from ..verify.bridge import pinocchio_model_from
        from ..verify.resolve import load_resolved

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = load_resolved(path, floating)
            if model_format(path) == "mjcf":
                pin_model = pinocchio_model_from(model)
            else:
                pin_model = (pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating
                             else pin.buildModelFromUrdf(path))
        return cls(name, model, pin_model)

    def states(self, n: int) -> tuple[np.ndarray, ...]:
        from ..configuration import random_configuration

        m = self.model
        q = np.asarray(random_configuration(m, self.rng, size=n), dtype=np.float64).reshape(n, m.nq)
        v = self.rng.normal(size=(n, m.nv))
        a = self.rng.normal(size=(n, m.nv))
        return q, v, a, self.jm.q_to_pin(q), self.jm.v_to_pin(v), self.jm.v_to_pin(a)


def _single_rows(pair: _Pair, repeats: int) -> list[tuple[str, float, float, float, float, float]]:
    """``(algorithm, fd µs, fd µs with out=, pin µs, ratio, ratio with out=)`` for one state.

    Each ratio comes from its own interleaved run (so ``ratio (out=)`` is not
    ``fd (out=) / pin`` of the printed medians exactly).
    """
    import pinocchio as pin

    import featherdyn as fd

    cm, pm, pd = pair.cm, pair.pm, pair.pd
    q, v, a, qp, vp, ap = (x[0].copy() for x in pair.states(1))
    nv, nb = pair.model.nv, pair.model.nbodies
    frame = JACOBIAN_FRAMES.get(pair.name, pair.model.frames[-1].name)
    if frame not in pair.model._frame_index or not pm.existFrame(frame):
        frame = pair.model.frames[-1].name
    fid, fid_pin = pair.model.frame_id(frame), pm.getFrameId(frame)
    tau, M, H, J = np.empty(nv), np.empty((nv, nv)), np.empty((nb, 4, 4)), np.empty((6, nv))
    cases: list[tuple[str, Callable[[], object], Callable[[], object], Callable[[], object]]] = [
        ("RNEA", lambda: cm.rnea(q, v, a), lambda: cm.rnea(q, v, a, out=tau), lambda: pin.rnea(pm, pd, qp, vp, ap)),
        ("CRBA", lambda: cm.crba(q), lambda: cm.crba(q, out=M), lambda: pin.crba(pm, pd, qp)),
        ("ABA", lambda: cm.aba(q, v, a), lambda: cm.aba(q, v, a, out=tau), lambda: pin.aba(pm, pd, qp, vp, ap)),
        ("FK", lambda: cm.fk(q), lambda: cm.fk(q, out=H), lambda: pin.forwardKinematics(pm, pd, qp)),
        (f"Jacobian {frame} (LOCAL)", lambda: cm.frame_jacobian(q, fid, fd.LOCAL),
         lambda: cm.frame_jacobian(q, fid, fd.LOCAL, out=J),
         lambda: pin.computeFrameJacobian(pm, pd, qp, fid_pin, pin.LOCAL)),
    ]
    rows = []
    for label, f_alloc, f_out, f_pin in cases:
        t_fd, t_pin = _median_ratio(f_alloc, f_pin, repeats)
        t_out, t_pin2 = _median_ratio(f_out, f_pin, repeats)
        rows.append((label, t_fd * 1e6, t_out * 1e6, t_pin * 1e6, t_fd / t_pin, t_out / t_pin2))
    return rows


def _public_rows(pair: _Pair, repeats: int) -> list[tuple[str, float, float]]:
    """``fd.rnea`` & co. (validated input, the compiled backend) against Pinocchio."""
    import pinocchio as pin

    import featherdyn as fd

    m, pm, pd = pair.model, pair.pm, pair.pd
    q, v, a, qp, vp, ap = (x[0].copy() for x in pair.states(1))
    frame = JACOBIAN_FRAMES.get(pair.name, m.frames[-1].name)
    if frame not in m._frame_index or not pm.existFrame(frame):
        frame = m.frames[-1].name
    fid_pin = pm.getFrameId(frame)
    cases = [
        ("fd.rnea", lambda: fd.rnea(m, q, v, a), lambda: pin.rnea(pm, pd, qp, vp, ap)),
        ("fd.crba", lambda: fd.crba(m, q), lambda: pin.crba(pm, pd, qp)),
        ("fd.aba", lambda: fd.aba(m, q, v, a), lambda: pin.aba(pm, pd, qp, vp, ap)),
        ("fd.nonlinear_effects", lambda: fd.nonlinear_effects(m, q, v), lambda: pin.nonLinearEffects(pm, pd, qp, vp)),
        ("fd.generalized_gravity", lambda: fd.generalized_gravity(m, q),
         lambda: pin.computeGeneralizedGravity(pm, pd, qp)),
        (f"fd.frame_jacobian {frame} (LOCAL)", lambda: fd.frame_jacobian(m, q, frame, fd.LOCAL),
         lambda: pin.computeFrameJacobian(pm, pd, qp, fid_pin, pin.LOCAL)),
        ("fd.forward_kinematics (a Kinematics object)", lambda: fd.forward_kinematics(m, q),
         lambda: pin.forwardKinematics(pm, pd, qp)),
    ]
    out = []
    for label, f_fd, f_pin in cases:
        t_fd, t_pin = _median_ratio(f_fd, f_pin, repeats)
        out.append((label, t_fd * 1e6, t_pin * 1e6))
    return out


def _batch_rows(pair: _Pair, n: int, repeats: int) -> list[tuple[str, float, float, float, float]]:
    """``(algorithm, fd s (fresh output), fd s (out=), fd s (out=, 1 thread), Pinocchio loop s)``.

    A fresh output of ``N`` mass matrices is hundreds of megabytes whose first
    touch (page faults, taken by the threads at once) can cost more than the
    computation; writing into a reused ``out=`` array measures the kernels.
    """
    import pinocchio as pin

    from ..api import get_num_threads, set_num_threads

    cm, pm, pd = pair.cm, pair.pm, pair.pd
    nv = pair.model.nv
    Q, V, A, Qp, Vp, Ap = pair.states(n)
    TAU, M, QDD = np.empty((n, nv)), np.empty((n, nv, nv)), np.empty((n, nv))
    cases = [
        ("RNEA", lambda: cm.rnea_batch(Q, V, A), lambda: cm.rnea_batch(Q, V, A, out=TAU),
         lambda: [pin.rnea(pm, pd, Qp[i], Vp[i], Ap[i]) for i in range(n)]),
        ("CRBA", lambda: cm.crba_batch(Q), lambda: cm.crba_batch(Q, out=M),
         lambda: [pin.crba(pm, pd, Qp[i]) for i in range(n)]),
        ("ABA", lambda: cm.aba_batch(Q, V, A), lambda: cm.aba_batch(Q, V, A, out=QDD),
         lambda: [pin.aba(pm, pd, Qp[i], Vp[i], Ap[i]) for i in range(n)]),
    ]
    threads = get_num_threads()
    rows = []
    for label, f_fresh, f_out, f_pin in cases:
        t_fresh, t_pin = _median_ratio(f_fresh, f_pin, repeats, budget=0.0)
        t_out, t_pin2 = _median_ratio(f_out, f_pin, repeats, budget=0.0)
        set_num_threads(1)
        try:
            t_one, _ = _median_ratio(f_out, lambda: None, repeats, budget=0.0)
        finally:
            set_num_threads(threads)
        rows.append((label, t_fresh, t_out, t_one, (t_pin + t_pin2) / 2))
    return rows


def chain_urdf(n: int) -> str:
    """A serial chain of ``n`` revolute links, axes cycling z, y, x, with offsets and physical inertias."""
    axes = ["0 0 1", "0 1 0", "1 0 0"]
    parts = [f'<robot name="chain{n}">', '<link name="base"/>']
    for i in range(n):
        parts.append(
            f'<link name="l{i}"><inertial><origin xyz="0.05 0.01 0.02" rpy="0 0 0"/><mass value="1.0"/>'
            '<inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.02" iyz="0.0005" izz="0.015"/></inertial></link>'
        )
        parent = "base" if i == 0 else f"l{i - 1}"
        parts.append(
            f'<joint name="j{i}" type="revolute"><parent link="{parent}"/><child link="l{i}"/>'
            f'<origin xyz="0.1 0 0.02" rpy="0.1 0 0.05"/><axis xyz="{axes[i % 3]}"/>'
            '<limit lower="-3" upper="3" effort="100" velocity="10"/></joint>'
        )
    parts.append("</robot>")
    return "\n".join(parts)


def _chain_rows(lengths: Sequence[int], repeats: int) -> Iterator[tuple[float, ...]]:
    """One row per chain length, as each is measured (a line on stderr first: the long chains take seconds)."""
    import pinocchio as pin

    from ..readers.urdf import load_urdf

    for k, n in enumerate(lengths, 1):
        print(f"featherdyn bench: [{k}/{len(lengths)}] a chain of {n} links…", file=sys.stderr, flush=True)
        xml = chain_urdf(n)
        model = load_urdf(xml)
        pair = _Pair(f"chain{n}", model, pin.buildModelFromXML(xml))
        r: list[float] = []
        for f_fd, f_pin in _dynamics_calls(pair):
            t_fd, t_pin = _median_ratio(f_fd, f_pin, repeats)
            r += [t_fd * 1e6, t_pin * 1e6]
        yield (float(n), *r)


def _dynamics_calls(pair: _Pair) -> list[tuple[Callable[[], object], Callable[[], object]]]:
    """RNEA, CRBA and ABA of one random state, as (featherdyn, Pinocchio) call pairs."""
    import pinocchio as pin

    cm, pm, pd = pair.cm, pair.pm, pair.pd
    q, v, a, qp, vp, ap = (x[0].copy() for x in pair.states(1))
    return [(lambda: cm.rnea(q, v, a), lambda: pin.rnea(pm, pd, qp, vp, ap)),
            (lambda: cm.crba(q), lambda: pin.crba(pm, pd, qp)),
            (lambda: cm.aba(q, v, a), lambda: pin.aba(pm, pd, qp, vp, ap))]


def _compile_times() -> list[str]:
    """First use in fresh processes: import, fd.compile of panda, the first fd.rnea, fd.compile of a new model."""
    code = (
        "import time, warnings; warnings.simplefilter('ignore'); t0 = time.perf_counter();"
        "import numpy as np, featherdyn as fd; t1 = time.perf_counter();"
        "m = fd.load_robot('panda'); t2 = time.perf_counter();"
        "cm = fd.compile(m); t3 = time.perf_counter();"
        "fd.rnea(m, fd.neutral(m), np.zeros(m.nv), np.zeros(m.nv)); t4 = time.perf_counter();"
        "b = fd.ModelBuilder('new'); [b.add_body(f'b{i}', i - 1, fd.RevoluteJoint([0, 1, 0]), "
        "inertia=fd.SpatialInertia(1.0 + i, [0.1, 0, 0], np.eye(3) * 0.01)) for i in range(7)];"
        "m2 = b.build(); t5 = time.perf_counter(); fd.compile(m2); t6 = time.perf_counter();"
        "print(t1 - t0, t3 - t2, t4 - t3, t6 - t5)"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False, timeout=900)
    if res.returncode != 0:
        return [f"- (could not measure: {res.stderr.strip().splitlines()[-1] if res.stderr else '?'})"]
    t_import, t_compile, t_public, t_new = (float(x) for x in res.stdout.split())
    return [
        f"- `import featherdyn`: {t_import:.2f} s (the core is compiled at install: nothing is compiled here)",
        f"- first `fd.compile(panda)` in a fresh process (copies the model's arrays into the core): {t_compile:.3f} s",
        f"- first `fd.rnea` after it: {t_public:.4f} s",
        f"- `fd.compile` of a model never seen before: {t_new:.3f} s",
    ]


def _fmt_ratio(x: float, target: float, lower_is_better: bool = True) -> str:
    ok = x <= target if lower_is_better else x >= target
    return f"{x:.2f} {'✓' if ok else '✗'}"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``featherdyn bench`` (shared by :func:`build_parser` and the CLI)."""
    p.add_argument("robot", nargs="?", default=None, metavar="ROBOT|URDF",
                   help="one robot of the library or a URDF file (default: panda, solo12 (floating), "
                        "talos_full_v2 (floating))")
    p.add_argument("--floating-base", action="store_true", help="with ROBOT: put it on a free-flyer joint")
    p.add_argument("--repeats", type=positive_int, default=15, help="interleaved repetitions per figure (default 15)")
    p.add_argument("--batch", type=positive_int, default=10_000, help="states per batched call (default 10000)")
    p.add_argument("--chains", default=",".join(map(str, CHAIN_LENGTHS)),
                   help="chain lengths of the scaling table, comma-separated ('' to skip)")
    p.add_argument("--no-compile-times", action="store_true", help="skip the compile/load time section")
    p.add_argument("--output", default=None, help="also write the report (Markdown) to this file")


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="featherdyn bench", description=__doc__.splitlines()[0])
    add_arguments(p)
    return p


def bench_main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark (command-line arguments ``argv``) and print a Markdown report.

    Returns:
        0, or 2 after a one-line message when the run cannot start (Pinocchio or
        the core not built, an unknown robot, an output that cannot be written).
    """
    try:
        return run(build_parser().parse_args(argv))
    except FeatherdynError as exc:
        print(f"featherdyn bench: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2


def _prepare(args: argparse.Namespace) -> tuple[list[tuple[str, str, bool]], list[int]]:
    """Check everything the run needs before any work: ``([(name, urdf, floating)], chain lengths)``.

    Raises:
        MissingDependencyError: Pinocchio is not installed, or the core is not built.
        ModelError: an unknown robot, a missing file or a directory.
        FeatherdynError: bad chain lengths, an output that cannot be written.
    """
    from ..core import available
    from ..verify.pinocchio import require_pinocchio
    from ..verify.resolve import resolve_robot

    require_pinocchio()
    if not available():
        raise MissingDependencyError("featherdyn bench times the compiled core, which is not built: "
                                     "reinstall featherdyn with pip")
    check_writable(args.output, "--output")
    try:
        chains = [int(x) for x in args.chains.split(",") if x.strip()]
    except ValueError:
        raise FeatherdynError(f"--chains: expected comma-separated positive integers, got {args.chains!r}") from None
    if any(n < 1 for n in chains):
        raise FeatherdynError(f"--chains: expected comma-separated positive integers, got {args.chains!r}")
    if args.robot:
        name, path = resolve_robot(args.robot)
        return [(name, str(path), args.floating_base)], chains
    return [(name, str(resolve_robot(name)[1]), floating) for name, floating in ROBOTS], chains


def run(args: argparse.Namespace, on_ready: Callable[[], None] | None = None) -> int:
    """Run the benchmark for parsed arguments (see :func:`add_arguments`); returns 0.

    Args:
        args: the parsed arguments.
        on_ready: called once the arguments are checked, before any work (the command line
            announces a first compilation there).

    Raises:
        FeatherdynError: the run cannot start (see :func:`_prepare`); raised before anything is printed.
    """
    robots, chains = _prepare(args)
    if on_ready is not None:
        on_ready()
    lines = ["# featherdyn compiled core vs Pinocchio", ""] + _versions() + [
        f"- method: interleaved repetitions, medians of {args.repeats}; ratio = featherdyn time / Pinocchio "
        "time (< 1: featherdyn faster); both read the same URDF",
        "",
    ]

    def emit(*new: str) -> None:
        for line in new:
            print(line, flush=True)
        lines.extend(new)

    for line in lines:
        print(line, flush=True)
    emit("## Single calls (`cm = fd.compile(model)`; `cm.rnea(q, v, a)` & co. against `pin.rnea(model, data, ...)`)",
         "",
         f"Target: ratio ≤ {TARGETS['single']:.1f}. `fd` allocates and returns its result like Pinocchio's "
         "`rnea`, `crba`, `aba` and `computeFrameJacobian`; `fd (out=)` writes into a preallocated array, the "
         "analogue of `pin.forwardKinematics`, which fills `data.oMi` and returns nothing.",
         "",
         "| robot | algorithm | fd µs | fd (out=) µs | Pinocchio µs | ratio | ratio (out=) |",
         "|---|---|---:|---:|---:|---:|---:|")
    pairs = []
    for name, path, floating in robots:
        pair = _Pair.from_urdf(name, path, floating)
        pairs.append(pair)
        label = f"{name}{' (floating)' if floating else ''} nv={pair.model.nv}"
        for alg, t_fd, t_out, t_pin, ratio, ratio_out in _single_rows(pair, args.repeats):
            emit(f"| {label} | {alg} | {t_fd:.2f} | {t_out:.2f} | {t_pin:.2f} | "
                 f"{_fmt_ratio(ratio, TARGETS['single'])} | {_fmt_ratio(ratio_out, TARGETS['single'])} |")
    emit("", "## Public API (`fd.rnea(model, q, v, a)` & co. on one float64 state)", "",
         "The call a user writes: lengths, finiteness and unit quaternions are checked inside the compiled "
         "kernel (any other input takes the general path with the reference's checks), the result is a fresh "
         "array. `fd.forward_kinematics` returns a `Kinematics` object of read-only `PluckerTransform`s, "
         "`pin.forwardKinematics` fills `data` and returns nothing.", "",
         "| robot | call | fd µs | Pinocchio µs | ratio |", "|---|---|---:|---:|---:|")
    for pair in pairs:
        for label, t_fd, t_pin in _public_rows(pair, args.repeats):
            emit(f"| {pair.name} | {label} | {t_fd:.2f} | {t_pin:.2f} | {_fmt_ratio(t_fd / t_pin, 1.0)} |")
    emit("", f"## Batched throughput (N = {args.batch} states; `cm.rnea_batch` & co. on all the core's threads "
         "against a Python loop over Pinocchio)", "",
         f"Target: throughput ratio ≥ {TARGETS['batch']:.0f}. *fresh*: the call allocates its output; *out=*: "
         "it writes into a reused array (no first-touch page faults). The Pinocchio loop indexes "
         "`Q[i]` and calls `pin.rnea(model, data, ...)` per state, returning a new array each time.", "",
         "| robot | algorithm | fd fresh ms | fd out= ms | fd out= 1 thread ms | Pinocchio loop ms | "
         "ratio (fresh) | ratio (out=) | 1-thread ratio |", "|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for pair in pairs:
        for alg, t_fresh, t_out, t_one, t_pin in _batch_rows(pair, args.batch, max(7, args.repeats // 2)):
            emit(f"| {pair.name} | {alg} | {t_fresh * 1e3:.2f} | {t_out * 1e3:.2f} | {t_one * 1e3:.2f} | "
                 f"{t_pin * 1e3:.2f} | {_fmt_ratio(t_pin / t_fresh, TARGETS['batch'], lower_is_better=False)} | "
                 f"{_fmt_ratio(t_pin / t_out, TARGETS['batch'], lower_is_better=False)} | {t_pin / t_one:.1f} |")
    if chains:
        emit("", "## Scaling over revolute chains (single calls, `fd.compile` methods; URDF axes cycling z, y, x)",
             "", f"Target: RNEA ratio ≤ {TARGETS['chain512']} at 512 links.", "",
             "| links | RNEA fd µs | RNEA pin µs | RNEA ratio | CRBA ratio | ABA ratio |",
             "|---:|---:|---:|---:|---:|---:|")
        for row in _chain_rows(chains, max(5, args.repeats // 2)):
            n, r_fd, r_pin, c_fd, c_pin, a_fd, a_pin = int(row[0]), *row[1:]
            rnea_ratio = f"{r_fd / r_pin:.2f}"
            if n == 512:
                rnea_ratio = _fmt_ratio(r_fd / r_pin, TARGETS["chain512"])
            emit(f"| {n} | {r_fd:.2f} | {r_pin:.2f} | {rnea_ratio} | {c_fd / c_pin:.2f} | {a_fd / a_pin:.2f} |")
    if not args.no_compile_times:
        emit("", "## First use (fresh processes)", "",
             *_compile_times())
    if args.output:
        try:
            with open(args.output, "w", encoding="utf-8") as f:
                f.write("\n".join(lines) + "\n")
        except OSError as exc:
            raise FeatherdynError(f"cannot write --output {args.output}: {exc.strerror}") from None
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(bench_main())
