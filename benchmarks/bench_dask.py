"""Scale-out throughput: Dask arrays and ``featherdyn dataset`` on 1 and 2 worker processes.

``python benchmarks/bench_dask.py [--states N] [--robot panda]``

Reports states/s of

* **in-process**: one batched NumPy call ``fd.rnea(model, q, v, a)`` (the core's own thread pool,
  all cores) — the baseline;
* **Dask arrays, threads**: ``fd.rnea`` on Dask arrays chunked along the batch,
  ``.compute()`` with Dask's threaded scheduler (one core thread per task);
* **Dask arrays, W worker processes**: the same graph on a ``LocalCluster`` of
  W processes × 1 thread, the states generated on the workers (``da.random``,
  uniform within the joint limits; the Panda's joints are all revolute with
  limits) and the torques reduced there (``.sum()``), so only the work and
  the scheduling are timed, not shipping 10⁶ states through one process;
* **featherdyn dataset**: the command's throughput (``M,dtau_dq,dtau_dv``, written to Zarr)
  with ``--workers 1`` and ``2``, cluster start-up excluded (it reports its own rate).

and the ratios the issue asks for: 2 workers / 1 worker (target ≥ 1.8) and
in-process / Dask (overhead, target ≤ 1.3). Pinocchio has no counterpart here.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import featherdyn as fd


def best_of(fn: Callable[[], object], repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=1_000_000)
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--chunk", type=int, default=50_000)
    parser.add_argument("--dataset-states", type=int, default=None, help="states of the dataset runs (default --states)")
    args = parser.parse_args()
    import dask
    import dask.array as da
    from dask.distributed import Client, LocalCluster

    from featherdyn.tools.dataset import write_dataset

    model = fd.load_robot(args.robot)
    if not all(j.nq == j.nv == 1 for j in model.joints):
        raise SystemExit("this benchmark draws q uniformly in the limits: use a robot of 1-dof joints with limits")
    n, c = args.states, args.chunk
    rng = np.random.default_rng(0)
    lo, hi = model.lower, model.upper
    q = rng.uniform(lo, hi, (n, model.nq))
    v, a = rng.standard_normal((2, n, model.nv))
    cores = len(os.sched_getaffinity(0))
    rows: list[tuple[str, float]] = []

    t_np = best_of(lambda: fd.rnea(model, q, v, a))
    rows.append((f"in-process batched fd.rnea ({fd.get_num_threads()} core threads)", n / t_np))

    qd, vd, ad = (da.from_array(x, chunks=(c, -1)) for x in (q, v, a))
    fd.set_num_threads(1)
    t_thr = best_of(lambda: fd.rnea(model, qd, vd, ad).compute(scheduler="threads", num_workers=cores))
    fd.set_num_threads(cores)
    rows.append((f"Dask arrays, threaded scheduler ({cores} threads, chunks of {c})", n / t_thr))

    def on_workers(client: Client) -> float:
        client.run(fd.set_num_threads, 1)
        # scalar bounds, then scaled: uniform(lo, hi) with array bounds would embed (n, nq) arrays in the graph
        qw = lo + (hi - lo) * da.random.default_rng(0).uniform(0.0, 1.0, size=(n, model.nq), chunks=(c, -1))
        vw = da.random.default_rng(1).standard_normal((n, model.nv), chunks=(c, -1))
        aw = da.random.default_rng(2).standard_normal((n, model.nv), chunks=(c, -1))
        qw, vw, aw = client.persist([qw, vw, aw])
        dask.distributed.wait([qw, vw, aw])
        return best_of(lambda: fd.rnea(model, qw, vw, aw).sum().compute())

    t_w = {}
    for w in (1, 2):
        with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            t_w[w] = on_workers(client)
        rows.append((f"Dask arrays, {w} worker process{'es' if w > 1 else ''} × 1 thread", n / t_w[w]))

    rate = {}
    for w in (1, 2):
        with tempfile.TemporaryDirectory() as tmp:
            nd = args.dataset_states or n
            runs = [write_dataset(model, Path(tmp) / f"d{k}.zarr", states=nd, chunk=min(c, 50_000), quantities=["M", "dtau_dq", "dtau_dv"],
                                  scheduler="local", workers=w) for k in range(2)]
        rate[w] = max(r.states_per_second for r in runs)
        rows.append((f"featherdyn dataset --quantities M,dtau_dq,dtau_dv --workers {w}", rate[w]))

    print(f"## {args.robot}, {n} states, chunks of {c}, {cores} cores, featherdyn {fd.__version__}, dask {dask.__version__}")
    print(f"{'':66}  states/s")
    for name, r in rows:
        print(f"{name:66}  {r:>12,.0f}")
    print()
    print(f"Dask arrays: 2 workers / 1 worker           {t_w[1] / t_w[2]:.2f}×   (target ≥ 1.8)")
    print(f"featherdyn dataset: 2 workers / 1 worker    {rate[2] / rate[1]:.2f}×   (target ≥ 1.8)")
    print(f"overhead: Dask 2 workers / in-process call  {t_w[2] / t_np:.2f}×   (target ≤ 1.3)")
    print(f"overhead: Dask threads / in-process call    {t_thr / t_np:.2f}×   (target ≤ 1.3)")


if __name__ == "__main__":
    main()
