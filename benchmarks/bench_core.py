"""featherdyn.core (the compiled C++ core) against Pinocchio: ``python benchmarks/bench_core.py [--quick]``.

Times core calls and the equivalent Pinocchio calls interleaved in this process
(medians of alternating samples) on panda (fixed base) and solo12 (floating
base), and prints ratios core / Pinocchio (below 1: the core is faster). The
states are converted to Pinocchio's layout (linear-first 6D vectors, free-flyer
``[v; ω]`` in the base frame) by :class:`featherdyn.verify.bridge.JointMap`
before timing, so only the calls are timed.

Sections:

* one state: ``core.rnea(model, q, v, a, out=)`` & co. against ``pin.rnea(model, data, ...)``
  (the core's calls include the Python wrapper's checks and the model lookup);
* batched, N states on T threads: ``core.rnea`` / ``core.aba`` on batches against
  ``pin.rneaInParallel`` / ``pin.abaInParallel`` with the same thread count, and
  ``core.crba`` on a batch against a Python loop over ``pin.crba``;
* where a public one-state call's time goes: ``fd.crba(model, q)`` & co. (the public
  function), the binding call it makes (``_core.kernels["crba"].fresh(cm, [q])``: checks, kernel, result
  allocation) and the same binding call on a state it refuses at once (one wrong length: the
  Python call, argument conversion and return, i.e. the floor of any call), against Pinocchio's
  call; the kernel alone is the binding call minus that floor and the output checks;
* panda's batched RNEA as a fraction of the machine's double-precision arithmetic
  peak: its exact operation count (the RNEA template instantiated for a counting
  scalar, ``_core.flops``) over the time per state, against
  threads × clock × lanes of the batched kernels × 2 (one add and one multiply per
  cycle and lane: the kernels are built without fused multiply-adds; a CPU with
  two FMA pipes has twice that peak for code that fuses).

Pinocchio's batched calls run on OpenMP, whose idle threads spin for a while after each parallel call; in an
interleaved benchmark they spin on the cores while the core's own batch runs next (its rows moved by up to
1.7× between runs). The script therefore sets ``OMP_WAIT_POLICY=passive`` unless the environment sets it (the
threads then sleep between calls: a few µs on calls of milliseconds); it prints the policy used.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OMP_WAIT_POLICY", "passive")  # before Pinocchio loads OpenMP (see the module docstring)
import platform
import statistics
import sys
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

import featherdyn as fd
from featherdyn import core

ROBOTS = [("panda", False, "panda_hand"), ("solo12", True, "HR_FOOT"), ("talos_full_v2", True, "gripper_left_base_link")]


def median_pair(a: Callable[[], Any], b: Callable[[], Any], repeats: int, budget: float) -> tuple[float, float]:
    """Median seconds per call of ``a`` and ``b``, timed in alternating samples of about ``budget`` seconds."""

    def sample(n: int) -> tuple[float, float]:
        t0 = time.perf_counter()
        for _ in range(n):
            a()
        t1 = time.perf_counter()
        for _ in range(n):
            b()
        return t1 - t0, time.perf_counter() - t1

    a(), b()
    n = 1
    while True:
        ta, tb = sample(n)
        if max(ta, tb) >= budget / 4 or n >= 1 << 20:
            break
        n *= 2
    n = max(1, int(n * budget / max(ta, tb, 1e-9)))
    xs, ys = [], []
    for _ in range(repeats):
        ta, tb = sample(n)
        xs.append(ta / n)
        ys.append(tb / n)
    return statistics.median(xs), statistics.median(ys)


def print_ratios(rows: list[tuple[str, float, float]], other: str = "pin") -> None:
    """Print ``(label, featherdyn seconds, other seconds)`` rows as µs and the ratio featherdyn / other."""
    width = max(len(label) for label, _, _ in rows)
    print(f"{'call':{width}} {'fd µs':>9} {other + ' µs':>9} {'ratio':>7}")
    for label, a, b in rows:
        print(f"{label:{width}} {a * 1e6:9.2f} {b * 1e6:9.2f} {a / b:7.2f}")


class Pair:
    """A library robot loaded by featherdyn and by Pinocchio, with a converter of states."""

    def __init__(self, name: str, floating: bool) -> None:
        import pinocchio as pin

        from featherdyn.robots import robot_path
        from featherdyn.verify.bridge import JointMap

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.model = fd.load_robot(name, floating_base=floating)
            path = str(robot_path(name))
            self.pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
        self.pd = self.pm.createData()
        self.jm = JointMap(self.model, self.pm)
        self.rng = np.random.default_rng(0)

    def states(self, n: int) -> tuple[np.ndarray, ...]:
        m = self.model
        q = np.asarray(fd.random_configuration(m, self.rng, size=n), dtype=np.float64).reshape(n, m.nq)
        v = self.rng.normal(size=(n, m.nv))
        a = self.rng.normal(size=(n, m.nv))
        return q, v, a, self.jm.q_to_pin(q), self.jm.v_to_pin(v), self.jm.v_to_pin(a)


def single_rows(p: Pair, frame: str, repeats: int, budget: float) -> list[tuple[str, float, float]]:
    import pinocchio as pin

    m, pm, pd = p.model, p.pm, p.pd
    Q, V, A, Qp, Vp, Ap = p.states(1)
    q, v, a, qp, vp, ap = Q[0], V[0], A[0], np.ascontiguousarray(Qp[0]), np.ascontiguousarray(Vp[0]), np.ascontiguousarray(Ap[0])
    tau, M, H = np.empty(m.nv), np.empty((m.nv, m.nv)), np.empty((m.nbodies, 4, 4))
    J, pose = np.empty((6, m.nv)), np.empty((4, 4))
    fid, fid_pin = m.frame_id(frame), pm.getFrameId(frame)
    calls: list[tuple[str, Callable[[], Any], Callable[[], Any]]] = [
        ("rnea", lambda: core.rnea(m, q, v, a, out=tau), lambda: pin.rnea(pm, pd, qp, vp, ap)),
        ("nle", lambda: core.nonlinear_effects(m, q, v, out=tau), lambda: pin.nonLinearEffects(pm, pd, qp, vp)),
        ("gravity", lambda: core.generalized_gravity(m, q, out=tau), lambda: pin.computeGeneralizedGravity(pm, pd, qp)),
        ("crba", lambda: core.crba(m, q, out=M), lambda: pin.crba(pm, pd, qp)),
        ("aba", lambda: core.aba(m, q, v, a, out=tau), lambda: pin.aba(pm, pd, qp, vp, ap)),
        ("fk (placements)", lambda: core.fk(m, q, out=H), lambda: pin.forwardKinematics(pm, pd, qp)),
        ("frame_placement", lambda: core.frame_placement(m, q, fid, out=pose),
         lambda: pin.updateFramePlacement(pm, pd, fid_pin) if pin.forwardKinematics(pm, pd, qp) is None else None),
    ]
    for code, ref in ((0, pin.LOCAL), (1, pin.WORLD), (2, pin.LOCAL_WORLD_ALIGNED)):
        calls.append((f"frame_jacobian {ref.name}", lambda c=code: core.frame_jacobian(m, q, fid, c, out=J),
                      lambda r=ref: pin.computeFrameJacobian(pm, pd, qp, fid_pin, r)))
    return [(name, *median_pair(f, g, repeats, budget)) for name, f, g in calls]


def floor_rows(p: Pair, frame: str, repeats: int, budget: float) -> list[tuple[str, float, float, float, float]]:
    """``(call, public s, binding s, refused-at-once s, Pinocchio s)`` per one-state public call (see the module doc)."""
    import pinocchio as pin

    from featherdyn.core import _core

    m, pm, pd = p.model, p.pm, p.pd
    Q, V, A, Qp, Vp, Ap = p.states(1)
    q, v, a, qp, vp, ap = Q[0], V[0], A[0], np.ascontiguousarray(Qp[0]), np.ascontiguousarray(Vp[0]), np.ascontiguousarray(Ap[0])
    cm, short, K = core._view(m).cm, np.zeros(1), _core.kernels
    fid, fid_pin = m.frame_id(frame), pm.getFrameId(frame)
    H, R, p3 = np.empty((m.nbodies, 4, 4)), np.empty((3, 3)), np.empty(3)
    cmodel = fd.compile(m)
    calls: list[tuple[str, Callable[[], Any], Callable[[], Any], Callable[[], Any], Callable[[], Any]]] = [
        ("fd.rnea", lambda: fd.rnea(m, q, v, a), lambda: K["rnea"].fresh(cm, [q, v, a, None]),
         lambda: K["rnea"].fresh(cm, [short, v, a, None]), lambda: pin.rnea(pm, pd, qp, vp, ap)),
        ("fd.crba", lambda: fd.crba(m, q), lambda: K["crba"].fresh(cm, [q]), lambda: K["crba"].fresh(cm, [short]),
         lambda: pin.crba(pm, pd, qp)),
        ("fd.aba", lambda: fd.aba(m, q, v, a), lambda: K["aba"].fresh(cm, [q, v, a, None]),
         lambda: K["aba"].fresh(cm, [short, v, a, None]), lambda: pin.aba(pm, pd, qp, vp, ap)),
        ("fd.nonlinear_effects", lambda: fd.nonlinear_effects(m, q, v), lambda: K["nonlinear_effects"].fresh(cm, [q, v]),
         lambda: K["nonlinear_effects"].fresh(cm, [short, v]), lambda: pin.nonLinearEffects(pm, pd, qp, vp)),
        ("fd.generalized_gravity", lambda: fd.generalized_gravity(m, q), lambda: K["generalized_gravity"].fresh(cm, [q]),
         lambda: K["generalized_gravity"].fresh(cm, [short]), lambda: pin.computeGeneralizedGravity(pm, pd, qp)),
        ("fd.frame_jacobian LOCAL", lambda: fd.frame_jacobian(m, q, frame, fd.LOCAL),
         lambda: K["frame_jacobian"].fresh(cm, [q], _core.Options(frame=fid, reference=0)),
         lambda: K["frame_jacobian"].fresh(cm, [short], _core.Options(frame=fid, reference=0)),
         lambda: pin.computeFrameJacobian(pm, pd, qp, fid_pin, pin.LOCAL)),
        ("fd.frame_jacobian WORLD", lambda: fd.frame_jacobian(m, q, frame, fd.WORLD),
         lambda: K["frame_jacobian"].fresh(cm, [q], _core.Options(frame=fid, reference=1)),
         lambda: K["frame_jacobian"].fresh(cm, [short], _core.Options(frame=fid, reference=1)),
         lambda: pin.computeFrameJacobian(pm, pd, qp, fid_pin, pin.WORLD)),
        ("fd.frame_jacobian LOCAL_WORLD_ALIGNED", lambda: fd.frame_jacobian(m, q, frame, fd.LOCAL_WORLD_ALIGNED),
         lambda: K["frame_jacobian"].fresh(cm, [q], _core.Options(frame=fid, reference=2)),
         lambda: K["frame_jacobian"].fresh(cm, [short], _core.Options(frame=fid, reference=2)),
         lambda: pin.computeFrameJacobian(pm, pd, qp, fid_pin, pin.LOCAL_WORLD_ALIGNED)),
        ("fd.frame_placement", lambda: fd.frame_placement(m, q, frame), lambda: _core.frame_pose(cm, q, fid, R, p3),
         lambda: _core.frame_pose(cm, short, fid, R, p3),
         lambda: pin.updateFramePlacement(pm, pd, fid_pin) if pin.forwardKinematics(pm, pd, qp) is None else None),
        ("fd.compile(model).fk(q, out=H)", lambda: cmodel.fk(q, out=H), lambda: _core.placements(cm, q, H),
         lambda: _core.placements(cm, short, H), lambda: pin.forwardKinematics(pm, pd, qp)),
    ]
    rows = []
    for name, public, binding, refused, pin_call in calls:
        t_public, t_pin = median_pair(public, pin_call, repeats, budget)
        t_binding, t_refused = median_pair(binding, refused, repeats, budget)
        rows.append((name, t_public, t_binding, t_refused, t_pin))
    return rows


def batch_rows(p: Pair, n: int, threads: int, repeats: int, budget: float) -> list[tuple[str, float, float]]:
    import pinocchio as pin

    m, pm = p.model, p.pm
    Q, V, A, Qp, Vp, Ap = p.states(n)
    # Pinocchio's parallel calls take (nq, N) column-major batches
    Qc, Vc, Ac = (np.asfortranarray(x.T) for x in (Qp, Vp, Ap))
    tau_pin = np.asfortranarray(np.empty((m.nv, n)))
    pool = pin.ModelPool(pm, threads)
    tau, M = np.empty((n, m.nv)), np.empty((n, m.nv, m.nv))
    core.set_num_threads(threads)
    rows = [
        (f"rnea_batch N={n} / rneaInParallel", *median_pair(lambda: core.rnea(m, Q, V, A, out=tau),
                                                           lambda: pin.rneaInParallel(threads, pool, Qc, Vc, Ac, tau_pin),
                                                           repeats, budget)),
        (f"aba_batch N={n} / abaInParallel", *median_pair(lambda: core.aba(m, Q, V, A, out=tau),
                                                         lambda: pin.abaInParallel(threads, pool, Qc, Vc, Ac, tau_pin),
                                                         repeats, budget)),
    ]
    pd = pm.createData()
    Qrows = [np.ascontiguousarray(x) for x in Qp]
    rows.append((f"crba_batch N={n} / loop of pin.crba", *median_pair(lambda: core.crba(m, Q, out=M),
                                                                     lambda: [pin.crba(pm, pd, x) for x in Qrows],
                                                                     repeats, budget)))
    return rows


def _clock_ghz() -> float:
    """The CPU clock from /proc/cpuinfo (the first ``cpu MHz`` line), in GHz; 0 when unknown."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("cpu MHz"):
                    return float(line.split(":")[1]) / 1000.0
    except OSError:
        pass
    return 0.0


def peak_fraction(name: str, n: int, threads: int) -> str:
    """One line: the batched RNEA's operations per second against the machine's arithmetic peak."""
    from featherdyn.core import _core

    model = fd.load_robot(name)
    rng = np.random.default_rng(0)
    Q = fd.random_configuration(model, rng, size=n)
    V, A = rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))
    tau = np.empty((n, model.nv))
    flops = int(_core.flops(core._view(model).cm, 0, Q[0], V[0], A[0]))
    core.set_num_threads(threads)
    core.rnea(model, Q, V, A, out=tau)
    times = []
    for _ in range(15):
        t0 = time.perf_counter()
        core.rnea(model, Q, V, A, out=tau)
        times.append(time.perf_counter() - t0)
    per_state = statistics.median(times) / n
    isa, lanes = _core.simd()
    ghz = _clock_ghz()
    peak = threads * ghz * 1e9 * lanes * 2
    achieved = flops / per_state
    share = f"{achieved / peak:.0%} of {peak / 1e9:.0f} GFLOP/s" if peak else "peak unknown (no clock)"
    return (f"{name} RNEA batched: {flops} floating-point operations per state, {per_state * 1e9:.0f} ns per state on "
            f"{threads} threads ({isa}, {lanes} lanes, {ghz:.2f} GHz): {achieved / 1e9:.1f} GFLOP/s = {share}\n")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer, shorter samples (a smoke run)")
    parser.add_argument("--batch", type=int, default=20000, help="states per batched call (the issue's N = 20 000)")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args(argv)
    repeats, budget = (5, 2e-3) if args.quick else (15, 5e-3)
    import pinocchio

    print(f"featherdyn.core vs Pinocchio {pinocchio.__version__}; numpy {np.__version__}; Python "
          f"{platform.python_version()}; {os.cpu_count()} logical cores; core threads {core.get_num_threads()}; "
          f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}")
    print("ratio = core / Pinocchio (median of interleaved samples; < 1: the core is faster)\n")
    for name, floating, frame in ROBOTS:
        if name == "panda":
            print(peak_fraction(name, args.batch, args.threads))

        p = Pair(name, floating)
        print(f"## {name} ({'floating' if floating else 'fixed'}; nq={p.model.nq}, nv={p.model.nv})")
        print(f"{'call':40s} {'core µs':>9s} {'pin µs':>9s} {'ratio':>7s}")
        for row, t_core, t_pin in single_rows(p, frame, repeats, budget) + batch_rows(p, args.batch, args.threads,
                                                                                    max(3, repeats // 3), budget * 10):
            print(f"{row:40s} {t_core * 1e6:9.2f} {t_pin * 1e6:9.2f} {t_core / t_pin:7.2f}")
        print(f"\nwhere the time goes (µs; floor = the binding call on a state it refuses at once)\n"
              f"{'call':38s} {'public':>8s} {'binding':>8s} {'floor':>8s} {'pin':>8s} {'ratio':>7s}")
        for row, t_public, t_binding, t_floor, t_pin in floor_rows(p, frame, repeats, budget):
            print(f"{row:38s} {t_public * 1e6:8.2f} {t_binding * 1e6:8.2f} {t_floor * 1e6:8.2f} {t_pin * 1e6:8.2f} "
                  f"{t_public / t_pin:7.2f}")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
