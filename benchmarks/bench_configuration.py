"""fd.integrate and fd.difference: the compiled core against the NumPy reference and Pinocchio.

``python benchmarks/bench_configuration.py [N]`` — one state and N states (default 10 000) on panda (fixed),
solo12 and talos (floating). Before the core kernels, ``fd.integrate`` was the NumPy function joint by joint
(``featherdyn.configuration.integrate``, still the reference: ``backend="reference"``). Medians of interleaved
repetitions; Pinocchio's one state in the same process (its layouts converted once, outside the timing), its
batch estimated as N × that (a lower bound of a Python loop: Pinocchio has no batched call).
"""

from __future__ import annotations

import sys
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

import featherdyn as fd
from featherdyn import configuration


def _median_time(f: Callable[[], Any], repeat: int, number: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            f()
        times.append((time.perf_counter() - t0) / number)
    return float(np.median(times))


def _pinocchio(name: str, floating: bool) -> tuple[Any, Any] | None:
    try:
        import pinocchio as pin

        from featherdyn.robots import robot_path
    except ImportError:
        return None
    path = robot_path(name)
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(str(path))
    return pin, model


def main(argv: list[str]) -> int:
    N = int(argv[0]) if argv else 10_000
    print(f"fd.integrate / fd.difference, one state and {N} states; times in µs (medians); ratios: NumPy / core")
    print(f"{'robot':<16}{'call':<12}{'NumPy 1':>10}{'core 1':>9}{'ratio':>7}{'Pinocchio 1':>13}"
          f"{'NumPy N':>11}{'core N':>10}{'ratio':>7}{'Pin. N×1':>13}")
    for name, floating in (("panda", False), ("solo12", True), ("talos_full_v2", True)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fd.load_robot(name, floating_base=floating)
        rng = np.random.default_rng(0)
        q, q1 = fd.random_configuration(model, rng), fd.random_configuration(model, rng)
        v = rng.normal(size=model.nv)
        Q, Q1 = fd.random_configuration(model, rng, N), fd.random_configuration(model, rng, N)
        V = rng.normal(size=(N, model.nv))
        pin_pair = _pinocchio(name, floating)
        for call, before, after, one, many in (
            ("integrate", configuration.integrate, fd.integrate, (q, v), (Q, V)),
            ("difference", configuration.difference, fd.difference, (q, q1), (Q, Q1)),
        ):
            assert np.abs(before(model, *one) - after(model, *one)).max() < 1e-12
            t_np1 = _median_time(lambda before=before, one=one, model=model: before(model, *one), 15, 200)
            t_c1 = _median_time(lambda after=after, one=one, model=model: after(model, *one), 15, 2000)
            t_npN = _median_time(lambda before=before, many=many, model=model: before(model, *many), 7, 3)
            t_cN = _median_time(lambda after=after, many=many, model=model: after(model, *many), 7, 10)
            pin1 = pinN = float("nan")
            if pin_pair is not None:
                pin, pm = pin_pair
                # Pinocchio's layouts (free-flyer v = [v; ω], same q) — the timing is what matters here
                pq, pq1, pv = pin.randomConfiguration(pm), pin.randomConfiguration(pm), np.zeros(pm.nv)
                f = pin.integrate if call == "integrate" else pin.difference
                second = pv if call == "integrate" else pq1
                pin1 = _median_time(lambda f=f, second=second, pm=pm, pq=pq: f(pm, pq, second), 15, 2000)
                pinN = pin1 * N  # (N × its one-state time: a lower bound of a Python loop over the states)
            print(f"{name:<16}{call:<12}{t_np1 * 1e6:>10.1f}{t_c1 * 1e6:>9.2f}{t_np1 / t_c1:>7.0f}{pin1 * 1e6:>13.2f}"
                  f"{t_npN * 1e6:>11.0f}{t_cN * 1e6:>10.0f}{t_npN / t_cN:>7.1f}{pinN * 1e6:>13.0f}")
    print(f"threads: {fd.get_num_threads()}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
