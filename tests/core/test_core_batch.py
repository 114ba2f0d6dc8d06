"""Batched calls of featherdyn.core: batch == a loop of one-state calls, bit for bit; threads; fork.

* every batched entry point equals the loop of its one-state call exactly, for
  batch sizes around the chunking of the thread pool, with broadcast rows, and
  writing into ``out=``;
* 8 Python threads sharing one model (one-state and batched calls) get the
  single-threaded results;
* a fork-start ``multiprocessing`` pool after a batched call works (the child
  rebuilds the core's thread pool);
* ``set_num_threads`` changes the pool and not the numbers.
"""

from __future__ import annotations

import multiprocessing
import re
import threading
import time

import numpy as np
import pytest
from _core_helpers import state
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn import core

SIZES = [1, 2, 3, 4, 5, 7, 8, 9, 33]  # around the SIMD width (2) and the pool's chunks


def _loop(fn, *rows):  # type: ignore[no-untyped-def]
    return np.stack([fn(*r) for r in zip(*rows, strict=True)])


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
@pytest.mark.parametrize("N", SIZES)
def test_batch_equals_loop_bit_for_bit(spec, N: int) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 10 + N, (N,))
    q, v, a, tau, f = st.q, st.v, st.a, st.tau, st.f_ext
    fid = len(model.frames) - 1
    cases = {
        "rnea": (core.rnea(model, q, v, a), _loop(lambda *x: core.rnea(model, *x), q, v, a)),
        "rnea f_ext": (core.rnea(model, q, v, a, f, gravity=False),
                       _loop(lambda *x: core.rnea(model, *x, gravity=False), q, v, a, f)),
        "nle": (core.nonlinear_effects(model, q, v), _loop(lambda *x: core.nonlinear_effects(model, *x), q, v)),
        "gravity": (core.generalized_gravity(model, q), _loop(lambda x: core.generalized_gravity(model, x), q)),
        "crba": (core.crba(model, q), _loop(lambda x: core.crba(model, x), q)),
        "aba": (core.aba(model, q, v, tau, f), _loop(lambda *x: core.aba(model, *x), q, v, tau, f)),
        "fk": (core.placements(model, q), _loop(lambda x: core.placements(model, x), q)),
        "frame_placement": (core.frame_placement(model, q, fid)[1], _loop(lambda x: core.frame_placement(model, x, fid)[1], q)),
    }
    for ref in (0, 1, 2):
        cases[f"frame_jacobian {ref}"] = (core.frame_jacobian(model, q, fid, ref),
                                          _loop(lambda x, r=ref: core.frame_jacobian(model, x, fid, r), q))
    for what, (batch, loop) in cases.items():
        assert batch.shape == loop.shape, f"{spec.name} N={N} {what}: shape {batch.shape} != {loop.shape}"
        assert np.array_equal(batch, loop), f"{spec.name} N={N} {what}: batch differs from the loop"


def test_broadcast_rows_and_batch_axes() -> None:
    """A one-row input is used for every state; leading axes (2, 3) come back as they went in."""
    model = tree("free_branch")
    st = random_state(model, 11, (2, 3))
    q0 = st.q[0, 0]
    tau = core.rnea(model, q0, st.v, st.a)  # q broadcast over (2, 3)
    assert tau.shape == (2, 3, model.nv)
    for idx in np.ndindex(2, 3):
        assert np.array_equal(tau[idx], core.rnea(model, q0, st.v[idx], st.a[idx])), idx
    tau2 = core.rnea(model, st.q, st.v[:1, :1], np.zeros(model.nv))
    for idx in np.ndindex(2, 3):
        assert np.array_equal(tau2[idx], core.rnea(model, st.q[idx], st.v[0, 0], np.zeros(model.nv))), idx
    M = core.crba(model, st.q)
    assert M.shape == (2, 3, model.nv, model.nv)
    assert np.array_equal(M[1, 2], core.crba(model, st.q[1, 2]))


def test_out_is_written_and_returned() -> None:
    model = tree("fixed_branch_mixed")
    st = random_state(model, 12, (4,))
    out = np.full((4, model.nv), np.nan)
    res = core.rnea(model, st.q, st.v, st.a, out=out)
    assert res is out
    assert np.array_equal(out, core.rnea(model, st.q, st.v, st.a))
    one = np.full(model.nv, np.nan)
    assert core.aba(model, st.q[0], st.v[0], st.tau[0], out=one) is one
    with pytest.raises(fd.errors.ShapeError, match="out: expected shape"):
        core.rnea(model, st.q, st.v, st.a, out=np.empty((3, model.nv)))
    with pytest.raises(TypeError, match="out:"):
        core.rnea(model, st.q[0], st.v[0], st.a[0], out=np.empty(model.nv, dtype=np.float32))


def test_eight_python_threads_sharing_a_model() -> None:
    """Concurrent one-state and batched calls on one model give the single-threaded results."""
    model = tree("free_branch")
    st = random_state(model, 13, (64,))
    expected = (core.rnea(model, st.q, st.v, st.a), core.crba(model, st.q),
                core.aba(model, st.q, st.v, st.tau))
    errors: list[str] = []

    def work(k: int) -> None:
        for rep in range(20):
            got = (core.rnea(model, st.q, st.v, st.a), core.crba(model, st.q),
                   core.aba(model, st.q, st.v, st.tau))
            for name, g, e in zip(("rnea", "crba", "aba"), got, expected, strict=True):
                if not np.array_equal(g, e):
                    errors.append(f"thread {k} rep {rep}: batched {name} differs")
            r = (k + rep) % 64
            if not np.array_equal(core.rnea(model, st.q[r], st.v[r], st.a[r]), expected[0][r]):
                errors.append(f"thread {k} rep {rep}: one-state rnea differs")

    threads = [threading.Thread(target=work, args=(k,), daemon=True) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert not any(t.is_alive() for t in threads), "a thread is stuck in the core"
    assert not errors, errors[:5]


def _child_rnea(args):  # type: ignore[no-untyped-def]
    name, q, v, a = args
    return core.rnea(tree(name), q, v, a)


def test_fork_pool_after_a_batched_call() -> None:
    """The core's pool is running in the parent; forked children build their own and compute the same."""
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork on this platform")
    model = tree("free_chain")
    st = random_state(model, 14, (40,))
    expected = core.rnea(model, st.q, st.v, st.a)  # the pool exists now
    ctx = multiprocessing.get_context("fork")
    with ctx.Pool(2) as pool:
        chunks = [("free_chain", st.q[k::4], st.v[k::4], st.a[k::4]) for k in range(4)]
        # a child stuck on the parent's (absent) pool threads would hang: fail after a generous minute instead
        results = pool.map_async(_child_rnea, chunks, chunksize=1).get(timeout=60)
    for k, r in enumerate(results):
        assert np.array_equal(r, expected[k::4]), f"child chunk {k} differs"
    assert np.array_equal(core.rnea(model, st.q, st.v, st.a), expected)  # the parent's pool still works


def test_set_num_threads() -> None:
    model = tree("free_branch")
    st = random_state(model, 15, (50,))
    before = core.get_num_threads()
    try:
        expected = core.crba(model, st.q)
        for n in (1, 3, 8):
            core.set_num_threads(n)
            assert core.get_num_threads() == n
            assert np.array_equal(core.crba(model, st.q), expected), f"{n} threads"
        core.set_num_threads(0)  # back to the cores available
        assert core.get_num_threads() >= 1
    finally:
        core.set_num_threads(before)
    with pytest.raises(TypeError):
        core.set_num_threads(2.5)  # type: ignore[arg-type]


def test_batches_back_to_back_and_after_the_workers_sleep() -> None:
    """A worker polls for the next job for ~100 µs, then sleeps: batches right after one another (taken while it
    polls), after a pause (taken after a wake-up) and with the pool replaced right after a batch (its workers
    stopped while polling) all give the same numbers, and nothing hangs."""
    model = tree("free_branch")
    st = random_state(model, 18, (64,))
    before = core.get_num_threads()
    try:
        core.set_num_threads(2)
        expected = core.crba(model, st.q)
        for k in range(200):
            assert np.array_equal(core.crba(model, st.q), expected), f"back to back, call {k}"
        for k in range(5):
            time.sleep(0.002)
            assert np.array_equal(core.crba(model, st.q), expected), f"after a pause, call {k}"
        for n in [2, 3, 2, 1, 2] * 4:
            core.set_num_threads(n)
            assert np.array_equal(core.crba(model, st.q), expected), f"{n} threads, new pool"
    finally:
        core.set_num_threads(before)


def test_large_batches_stream_their_results_bit_for_bit() -> None:
    """A batch whose result passes 8 MB is written with non-temporal stores in whole 64-byte lines, ordinary
    stores for the partial lines at both ends of each row: every row (rows start at every alignment, here also
    in an output that starts 8 bytes into its buffer) equals one state's result bit for bit."""
    from _models import random_tree

    model = random_tree(19, 40, root="free_flyer", kinds=("revolute",), branching=True)
    nv = model.nv
    n = (1 << 20) // (nv * nv) + 3  # M alone just over 8 MB
    st = random_state(model, 19, (n,))
    rows = sorted({0, 1, 2, 7, 8, 9, n // 2, n - 2, n - 1})
    buffer = np.full(n * nv * nv + 1, np.nan)
    shifted = buffer[1:].reshape(n, nv, nv)  # 8 bytes past the buffer's start
    for out in (None, shifted):
        M = core.crba(model, st.q, out=out)
        for k in rows:
            assert np.array_equal(M[k], core.crba(model, st.q[k])), f"crba row {k}"
    assert not np.isnan(shifted).any()
    batch = core.rnea_derivatives(model, st.q, st.v, st.a)
    aba_batch = core.aba_derivatives(model, st.q, st.v, st.tau)
    for k in rows:
        one = core.rnea_derivatives(model, st.q[k], st.v[k], st.a[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(batch, one, strict=True)), f"rnea_derivatives row {k}"
        one = core.aba_derivatives(model, st.q[k], st.v[k], st.tau[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(aba_batch, one, strict=True)), f"aba_derivatives row {k}"


@pytest.mark.parametrize("n", [37, "large"])
def test_a_batch_whose_finite_input_overflows_names_the_row_whatever_its_group(n: int | str) -> None:
    """The derivative batches check each group's results while they are in the caches (a group that overflowed
    is redone row by row, whose status says which row): an overflowing row in a full group, in the remainder,
    in a small batch (results written straight into the rows) and in a streamed one (8 MB and more) raises
    the NonFiniteError of the row alone, naming the row's state; every other batch is the one-state results
    bit for bit."""
    from _models import random_tree

    model = random_tree(23, 30, root="free_flyer", kinds=("revolute",), branching=True)
    rows = 37 if n == 37 else (1 << 20) // (model.nv * model.nv) + 5
    st = random_state(model, 23, (rows,))
    width = core._core.simd()[1]
    for bad in (1, width + 1, rows - 1):  # in the first group, in the second, in the remainder (or last group)
        v = st.v.copy()
        v[bad] = 1e200  # v × I v overflows
        state = f" (state ({bad},) of the batch)"
        words = re.escape(f"rnea_derivatives{state}: the result overflowed")
        with pytest.raises(fd.NonFiniteError, match=words) as batch:
            core.rnea_derivatives(model, st.q, v, st.a)
        with pytest.raises(fd.NonFiniteError, match=r"^rnea_derivatives: the result overflowed") as alone:
            core.rnea_derivatives(model, st.q[bad], v[bad], st.a[bad])
        assert str(batch.value).replace(state, "") == str(alone.value)  # the same words, the same flat index
        with pytest.raises(fd.NonFiniteError, match=re.escape(f"aba_derivatives{state}: the result overflowed")):
            core.aba_derivatives(model, st.q, v, st.tau)
    batch = core.rnea_derivatives(model, st.q, st.v, st.a)
    aba_batch = core.aba_derivatives(model, st.q, st.v, st.tau)
    for k in (0, width, rows - 1):
        one = core.rnea_derivatives(model, st.q[k], st.v[k], st.a[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(batch, one, strict=True))
        one = core.aba_derivatives(model, st.q[k], st.v[k], st.tau[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(aba_batch, one, strict=True))


def test_derivative_solves_on_a_tree_numbered_breadth_first() -> None:
    """∂q̈/∂q and ∂q̈/∂q̇ solve M X = −∂τ only on each row's columns [0, end_k) in the first sweep when every
    subtree is a contiguous range of dofs; a tree numbered otherwise (bodies 1 and 2 both children of 0, 3 of
    1: body 1's subtree is {1, 3}) takes the full sweep, with the same results as the reference and lanes equal
    to one state."""
    from _models import _joint, random_inertia, random_placement

    rng = np.random.default_rng(5)
    b = fd.ModelBuilder("breadth_first")
    for i, parent in enumerate([-1, 0, 0, 1, 2, 3, 1]):
        joint = fd.FreeFlyerJoint() if i == 0 else _joint("revolute", rng)
        b.add_body(f"b{i}", parent, joint, placement=None if i == 0 else random_placement(rng),
                   inertia=random_inertia(rng))
    model = b.build()
    st = random_state(model, 5, (19,))
    batch = core.aba_derivatives(model, st.q, st.v, st.tau)
    reference = fd.aba_derivatives(model, st.q, st.v, st.tau, backend="reference")
    for got, want in zip(batch, reference, strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * float(np.abs(want).max()))
    for k in (0, 9, 18):
        one = core.aba_derivatives(model, st.q[k], st.v[k], st.tau[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(batch, one, strict=True))


def test_batch_on_a_library_robot() -> None:
    """Batched rnea on solo12 (floating) equals the loop of one-state calls exactly."""
    from _core_helpers import robot

    model = robot("solo12", True)
    assert model is not None
    q, v, a, tau, f = state(model, 16, (20,))
    assert np.array_equal(core.rnea(model, q, v, a, f), _loop(lambda *x: core.rnea(model, *x), q, v, a, f))
    assert np.array_equal(core.aba(model, q, v, tau), _loop(lambda *x: core.aba(model, *x), q, v, tau))


def test_set_num_threads_while_batches_run() -> None:
    """Replacing the pool while other threads run batches: running batches finish on the old pool, unchanged."""
    model = tree("fixed_branch_mixed")
    st = random_state(model, 17, (40,))
    expected = core.aba(model, st.q, st.v, st.tau)
    before = core.get_num_threads()
    errors: list[str] = []
    stop = threading.Event()

    def work() -> None:
        while not stop.is_set():
            if not np.array_equal(core.aba(model, st.q, st.v, st.tau), expected):
                errors.append("aba_batch differs")

    threads = [threading.Thread(target=work, daemon=True) for _ in range(3)]
    for t in threads:
        t.start()
    try:
        for n in [1, 4, 2, 3, 1, 2] * 5:
            core.set_num_threads(n)
            if not np.array_equal(core.aba(model, st.q, st.v, st.tau), expected):
                errors.append(f"aba_batch differs with {n} threads")
    finally:
        stop.set()
        for t in threads:
            t.join(timeout=120)
        core.set_num_threads(before)
    assert not any(t.is_alive() for t in threads), "a thread is stuck in the core"
    assert not errors, errors[:5]


_BASELINE_SCRIPT = """
import sys
import numpy as np
sys.path.insert(0, {tests!r})
from _models import TREES, random_state, tree
from featherdyn import core
print(core._core.simd()[0])
for spec in TREES:
    model = tree(spec.name)
    st = random_state(model, 18, (9,))
    for batch, one in [
        (core.rnea(model, st.q, st.v, st.a, st.f_ext), [core.rnea(model, *x) for x in zip(st.q, st.v, st.a, st.f_ext)]),
        (core.crba(model, st.q), [core.crba(model, x) for x in st.q]),
        (core.aba(model, st.q, st.v, st.tau), [core.aba(model, *x) for x in zip(st.q, st.v, st.tau)]),
        (core.placements(model, st.q), [core.placements(model, x) for x in st.q]),
        (core.kinematics_derivatives(model, st.q, st.v, st.a, len(model.frames) - 1, 2)[5],
         [core.kinematics_derivatives(model, *x, len(model.frames) - 1, 2)[5] for x in zip(st.q, st.v, st.a)]),
        (core.centroidal_dynamics_derivatives(model, st.q, st.v, st.a)[1],
         [core.centroidal_dynamics_derivatives(model, *x)[1] for x in zip(st.q, st.v, st.a)]),
    ]:
        assert np.array_equal(batch, np.stack(one)), spec.name
print("ok")
"""


@pytest.mark.parametrize("isa", ["baseline", "avx2", "avx512"])
def test_every_simd_build_is_bit_identical_too(isa: str) -> None:
    """FEATHERDYN_SIMD=baseline|avx2|avx512 in a fresh process: batch == loop bit for bit with those kernels.

    (A set the CPU lacks falls back to a narrower one, which is then what is tested.)
    """
    import os
    import subprocess
    import sys
    from pathlib import Path

    tests = str(Path(__file__).resolve().parents[1])
    env = dict(os.environ, FEATHERDYN_SIMD=isa)
    res = subprocess.run([sys.executable, "-c", _BASELINE_SCRIPT.format(tests=tests)], env=env, capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    used, verdict = res.stdout.split()
    assert verdict == "ok"
    order = ["baseline", "avx2", "avx512"]
    assert used in order[: order.index(isa) + 1], (isa, used)
    if isa == "baseline":
        assert used == "baseline"
