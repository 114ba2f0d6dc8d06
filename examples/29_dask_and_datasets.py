# needs: featherdyn[verify,distributed] (Dask, Zarr, example-robot-data): pip install "featherdyn[verify,distributed]"
"""Beyond one call: Dask arrays through the dynamics, and a dataset on disk.

``fd.rnea`` & co. take Dask arrays chunked along the batch and return Dask
arrays, lazily, equal bit for bit to the NumPy call. ``featherdyn dataset``
(here its Python function) writes random states and their dynamics to Zarr,
chunk by chunk, the same bytes whatever the number of workers.

Run: python examples/29_dask_and_datasets.py
"""

# %% 0. a batch of states as Dask arrays
from __future__ import annotations

from _check import needs

needs("dask.distributed", "zarr", "example-robot-data")  # first: a missing module is one line naming its install

import tempfile
from pathlib import Path

import dask.array as da
import numpy as np
import zarr
from _check import check, check_true, section, show

import featherdyn as fd
from featherdyn.tools.dataset import write_dataset

model = fd.load_robot("panda")
rng = np.random.default_rng(0)
N = 20_000
q_np = fd.random_configuration(model, rng, N)
v_np = rng.normal(size=(N, model.nv))
q = da.from_array(q_np, chunks=(5_000, -1))      # chunked along the batch only
v = da.from_array(v_np, chunks=(5_000, -1))

# %% 1. lazy in, lazy out
section("Dask arrays")
M = fd.crba(model, q)                             # nothing computed yet
h = fd.nonlinear_effects(model, q, v)
show("M", M)
check("crba on Dask == crba on NumPy (bit for bit)", M.compute(), fd.crba(model, q_np), 0.0)
check("nle on Dask == nle on NumPy", h.compute(), fd.nonlinear_effects(model, q_np, v_np), 0.0)
dq, dv, _ = fd.rnea_derivatives(model, q[:8], v[:8], v[:8])     # tuples keep their structure
check_true("rnea_derivatives gives Dask arrays", type(dq).__module__.startswith("dask"))

# %% 2. a dataset: per-chunk seeds, resumable
section("a dataset on disk (in this process; --scheduler local spreads chunks over worker processes)")
with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "panda.zarr"
    run = write_dataset(model, out, states=3_000, chunk=1_000, quantities=["tau", "M", "ddq"], seed=7,
                        scheduler="sync")
    show("chunks computed, skipped", [run.computed_chunks, run.skipped_chunks])
    again = write_dataset(model, out, states=3_000, chunk=1_000, quantities=["tau", "M", "ddq"], seed=7,
                          scheduler="sync")
    check_true("a second run finds every chunk done and checked", again.skipped_chunks == 3)
    g = zarr.open_group(str(out), mode="r")
    check("stored τ = RNEA(stored q, v, a)", g["tau"][:], fd.rnea(model, g["q"][:], g["v"][:], g["a"][:]), 0.0)
    show("metadata", {k: g.attrs[k] for k in ("featherdyn_version", "seed", "chunk", "quantities")})
