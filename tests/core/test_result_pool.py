"""Large batch results in reused memory (``featherdyn.core._result_pool``, ``fd.set_result_cache_size``).

* a dropped result's memory is reused by the next result of its size, and only then: a result, a slice of
  it or a ``memoryview`` the caller still holds is never written again;
* every batched function that returns reused memory writes all of it: results over memory filled with NaN
  by an earlier caller equal the results into fresh ``out=`` arrays, bit for bit;
* the limit holds (0: no reuse), bad limits are refused, 8 threads calling at once get their own results.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
from _models import library_robot, random_state, tree

import featherdyn as fd
from featherdyn.core import _result_pool

MODEL = tree("free_branch")  # nv = 14: (N, nv, nv) reaches 1 MiB at N = 669
N = 700


def _address(x: np.ndarray) -> int:
    return int(x.__array_interface__["data"][0])


@pytest.fixture(autouse=True)
def _fresh_pool() -> Iterator[None]:
    limit = _result_pool.result_cache_info()["limit"]
    fd.set_result_cache_size(0)
    fd.set_result_cache_size(limit)
    yield
    fd.set_result_cache_size(0)
    fd.set_result_cache_size(limit)


def _state() -> Any:
    return random_state(MODEL, 3, (N,))


def test_a_dropped_result_is_reused_and_a_held_one_never() -> None:
    st = _state()
    r1 = fd.crba(MODEL, st.q)
    a1 = _address(r1)
    r2 = fd.crba(MODEL, st.q)
    assert not np.shares_memory(r1, r2)  # r1 is held
    del r1
    r3 = fd.crba(MODEL, st.q)
    assert _address(r3) == a1  # r1 was dropped: its memory comes back
    part = r3[5:9]
    mv = memoryview(r2)
    del r2, r3
    r4, r5 = fd.crba(MODEL, st.q), fd.crba(MODEL, st.q)
    for r in (r4, r5):
        assert not np.shares_memory(r, part)
        assert _address(r) != _address(np.asarray(mv))
    np.testing.assert_array_equal(part, fd.crba(MODEL, st.q[5:9]))


def test_results_from_64_kib_are_reused_and_eight_of_a_size_kept() -> None:
    """From MIN_BYTES (64 KiB) up, at most PER_SIZE (8) buffers of one size; below it, fresh memory."""
    st = _state()
    per_state = MODEL.nv * MODEL.nv * 8
    above, below = (64 << 10) // per_state + 1, (64 << 10) // per_state - 1
    a = _address(fd.crba(MODEL, st.q[:above]))  # (dropped at once)
    assert _address(fd.crba(MODEL, st.q[:above])) == a
    assert _result_pool.result_cache_info()["buffers"] == 1
    fd.crba(MODEL, st.q[:below])
    assert _result_pool.result_cache_info()["buffers"] == 1
    fd.set_result_cache_size(8 * above * per_state + 2 * above * per_state)  # room for 8 and a free one of 2 above
    fd.crba(MODEL, st.q[: 2 * above])  # (dropped: free)
    held = [fd.crba(MODEL, st.q[:above]) for _ in range(12)]  # a caller keeping every result
    info = _result_pool.result_cache_info()
    assert info["buffers"] == 9 and info["free"] == 2 * above * per_state  # 8 held; the other size not dropped
    assert len({_address(r) for r in held}) == 12


def test_small_results_and_a_zero_limit_take_fresh_memory() -> None:
    st = _state()
    fd.crba(MODEL, st.q[:10])  # 15 kB: below MIN_BYTES
    assert _result_pool.result_cache_info()["buffers"] == 0
    fd.set_result_cache_size(0)
    fd.crba(MODEL, st.q)
    assert _result_pool.result_cache_info() == {"limit": 0, "kept": 0, "free": 0, "buffers": 0}


def test_the_limit_counts_every_kept_buffer() -> None:
    st = _state()
    nbytes = N * MODEL.nv * MODEL.nv * 8
    fd.set_result_cache_size(2 * nbytes)
    held = [fd.crba(MODEL, st.q) for _ in range(4)]
    info = _result_pool.result_cache_info()
    assert info["kept"] == 2 * nbytes and info["buffers"] == 2 and info["free"] == 0
    del held
    assert _result_pool.result_cache_info()["free"] == 2 * nbytes
    fd.set_result_cache_size(nbytes)  # free buffers beyond a new limit go at once
    assert _result_pool.result_cache_info()["kept"] == nbytes
    other = fd.crba(MODEL, st.q[: N - 50])  # another size: the free buffer makes room for it
    assert _result_pool.result_cache_info()["kept"] == other.nbytes


def test_bad_limits_are_refused() -> None:
    with pytest.raises(fd.DTypeError, match="nbytes: expected an integer"):
        fd.set_result_cache_size(1.5)  # type: ignore[arg-type]
    with pytest.raises(fd.DTypeError):
        fd.set_result_cache_size(True)
    with pytest.raises(fd.BackendError, match="nbytes: expected a number of bytes >= 0, got -1"):
        fd.set_result_cache_size(-1)


def _calls() -> list[tuple[str, Callable[..., Any], Callable[..., Any]]]:
    """(name, call returning new results, the same call into given ``out=`` arrays)."""
    st = _state()
    cm = fd.compile(MODEL)
    frame = MODEL.frames[-1].name
    Q = np.repeat(st.q, 12, axis=0)  # (8400, nq): the vector results reach 1 MiB
    V, A, T = (np.repeat(x, 12, axis=0) for x in (st.v, st.a, st.tau))

    def one(fn: Callable[..., Any], *args: Any) -> tuple[Callable[..., Any], Callable[..., Any]]:
        return (lambda: fn(*args)), (lambda out: fn(*args, out=out))

    return [
        ("rnea", *one(cm.rnea_batch, Q, V, A)),
        ("aba", *one(cm.aba_batch, Q, V, T)),
        ("crba", *one(cm.crba_batch, st.q)),
        ("fk", *one(cm.fk_batch, Q[:2000])),
        ("frame_jacobian", *one(cm.frame_jacobian_batch, Q[:2000], frame)),
        ("rnea_derivatives", *one(cm.rnea_derivatives_batch, st.q, st.v, st.a)),
        ("aba_derivatives", *one(cm.aba_derivatives_batch, st.q, st.v, st.tau)),
        ("mass_matrix_inverse", lambda: fd.mass_matrix_inverse(MODEL, st.q), None),
        ("joint_torque_regressor", lambda: fd.joint_torque_regressor(MODEL, st.q, st.v, st.a), None),
    ]


@pytest.mark.parametrize("name", [c[0] for c in _calls()])
def test_reused_memory_is_written_entirely(name: str) -> None:
    call, into = next((c, i) for n, c, i in _calls() if n == name)
    first = call()
    firsts = first if isinstance(first, tuple) else (first,)
    assert all(_address(x) == _address(x.base) for x in firsts)  # views of kept buffers
    addresses = [_address(x) for x in firsts]
    for x in firsts:
        x.fill(np.nan)
    del first, firsts, x
    again = call()
    agains = again if isinstance(again, tuple) else (again,)
    assert sorted(_address(x) for x in agains) == sorted(addresses)  # the NaN-filled memory, reused
    if into is not None:
        outs = tuple(np.full_like(x, np.nan) for x in agains)
        into(outs if isinstance(again, tuple) else outs[0])
        expected = outs
    else:  # no out=: the reference algorithms
        st = _state()
        fn = getattr(fd, name)
        expected = (fn(MODEL, st.q, backend="reference") if name == "mass_matrix_inverse"
                    else fn(MODEL, st.q, st.v, st.a, backend="reference"),)
    for x, e in zip(agains, expected, strict=True):
        assert np.isfinite(x).all()
        if into is not None:
            np.testing.assert_array_equal(x, e)
        else:
            np.testing.assert_allclose(x, e, rtol=1e-12, atol=1e-12 * np.abs(e).max())


def test_threads_get_their_own_results() -> None:
    st = _state()
    expected = fd.crba(MODEL, st.q, backend="reference")
    errors: list[BaseException] = []

    def work(k: int) -> None:
        try:
            for _ in range(5):
                M = fd.crba(MODEL, st.q)
                M2 = fd.crba(MODEL, st.q[::-1])
                assert not np.shares_memory(M, M2)
                np.testing.assert_allclose(M, expected, rtol=1e-12, atol=1e-12)
                np.testing.assert_allclose(M2[::-1], expected, rtol=1e-12, atol=1e-12)
        except BaseException as exc:  # reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors[0]


def test_a_forked_child_gets_a_fresh_lock() -> None:
    """A fork while another thread holds the pool's lock: the child's batches still run (a fresh lock)."""
    import multiprocessing

    st = _state()
    expected = fd.crba(MODEL, st.q, backend="reference")
    held = threading.Event()
    release = threading.Event()

    def hold() -> None:
        with _result_pool._lock:
            held.set()
            release.wait(10)

    t = threading.Thread(target=hold)
    t.start()
    held.wait(10)
    try:
        ctx = multiprocessing.get_context("fork")
        with ctx.Pool(1) as pool:
            got = pool.apply_async(_crba_in_child, (st.q,)).get(timeout=60)
    finally:
        release.set()
        t.join()
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)


def _crba_in_child(q: np.ndarray) -> np.ndarray:
    first = fd.crba(MODEL, q)  # the pool's lock in the child: not the one the parent's thread holds
    del first
    return np.array(fd.crba(MODEL, q))


def test_one_state_results_of_64_kib_reuse_it_and_smaller_ones_not() -> None:
    """A one-state result of at least 64 KiB (talos_full_v2's four (50, 50, 50) second derivatives, 1 MB each) takes
    the pool's memory, through the core's C path and through fd.compile's method: a dropped one's memory, filled with
    NaN, is all written again (equal to the call into fresh out= arrays), one held is never reused; the same call's
    results on panda (nv = 9: 5.8 kB each) are not pooled."""
    model = library_robot("talos_full_v2", True)
    assert model is not None, "example-robot-data is a test dependency"
    rng = np.random.default_rng(5)
    q, v, a = fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)
    expected = tuple(np.empty((model.nv,) * 3) for _ in range(4))
    fd.rnea_second_derivatives(model, q, v, a, out=expected)
    method = fd.compile(model, warmup=False).rnea_second_derivatives
    for call in (lambda: fd.rnea_second_derivatives(model, q, v, a), lambda: method(q, v, a)):
        limit = _result_pool.result_cache_info()["limit"]
        fd.set_result_cache_size(0)
        fd.set_result_cache_size(limit)
        r1 = call()
        assert _result_pool.result_cache_info()["buffers"] == 4
        addresses = {_address(x) for x in r1}
        held = r1.dM_dq
        for x in r1:
            x.fill(np.nan)
        del r1, x
        r2 = call()
        again = {_address(x) for x in r2}
        assert len(again & addresses) == 3 and _address(held) not in again  # the three dropped, not the one held
        assert all(np.array_equal(x, y) for x, y in zip(r2, expected, strict=True))
        del r2, held
    panda = library_robot("panda", False)
    assert panda is not None and 8 * panda.nv ** 3 < _result_pool.MIN_BYTES
    small = random_state(panda, 6)
    before = _result_pool.result_cache_info()
    fd.rnea_second_derivatives(panda, small.q, small.v, small.a)
    assert _result_pool.result_cache_info() == before
