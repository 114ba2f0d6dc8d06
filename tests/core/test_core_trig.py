"""The core's sin and cos (``cpp/trig.hpp``): within 2 ulp of the C library, and Packs bit-identical to one state.

Joint angles reach the kernels' rotations through these; the batched kernels
evaluate them four (AVX2) or two lanes at a time with the one-state operations.
"""

from __future__ import annotations

import numpy as np

from featherdyn.core import _core


def _sin_cos(x: np.ndarray, packs: bool) -> tuple[np.ndarray, np.ndarray]:
    s, c = np.empty_like(x), np.empty_like(x)
    _core.sin_cos(x, s, c, packs)
    return s, c


def _angles() -> np.ndarray:
    rng = np.random.default_rng(11)
    special = [0.0, -0.0, 5e-324, 1e-300, -1e-8, np.pi / 4, -np.pi / 4, np.pi / 2, np.pi, 3 * np.pi / 2,
               2 * np.pi, 1e5, -1e5, 1.0000001e5, 1e300, -1e300, np.inf, -np.inf, np.nan]
    return np.concatenate([rng.uniform(-4, 4, 100_000), rng.uniform(-1e3, 1e3, 50_000),
                           rng.uniform(-1e5, 1e5, 50_000), np.pi / 2 * np.arange(-2000, 2000), special])


def test_within_two_ulp_of_the_c_library() -> None:
    x = _angles()
    s, c = _sin_cos(x, packs=False)
    finite = np.isfinite(x)
    xf = x[finite]
    for mine, ref in ((s[finite], np.sin(xf)), (c[finite], np.cos(xf))):
        err = np.abs(mine - ref)
        assert np.all(err <= 2 * np.spacing(np.abs(ref)) + 1e-300), float(err.max())
        assert np.all(np.abs(mine) <= 1.0)
    assert np.isnan(s[~finite]).all() and np.isnan(c[~finite]).all()


def test_packs_are_bit_identical_to_one_state() -> None:
    x = _angles()
    s1, c1 = _sin_cos(x, packs=False)
    s2, c2 = _sin_cos(x, packs=True)
    assert np.array_equal(s1.view(np.int64), s2.view(np.int64))
    assert np.array_equal(c1.view(np.int64), c2.view(np.int64))


def test_a_wide_lane_sends_its_pack_to_the_one_state_rule() -> None:
    """One angle beyond the reduction's range in a pack: every lane still equals its one-state value."""
    x = np.array([0.3, 1e200, -2.0, 7.0, 0.1, -0.2, 1e6, 3.0])
    assert np.array_equal(_sin_cos(x, packs=True)[0], _sin_cos(x, packs=False)[0])
    assert np.array_equal(_sin_cos(x, packs=True)[1], _sin_cos(x, packs=False)[1])


def test_operation_counts_grow_by_one_body_at_a_time() -> None:
    """``_core.flops``: the RNEA / CRBA / ABA templates on a counting scalar. Adding one identical revolute
    link to a chain adds the same number of operations each time to RNEA and ABA (O(n)); CRBA's
    increments grow by a constant (O(n²): one more ancestor per new link)."""
    import featherdyn as fd

    def chain(n: int) -> fd.Model:
        b = fd.ModelBuilder(f"chain{n}")
        for i in range(n):
            b.add_body(f"l{i}", parent=i - 1, joint=fd.RevoluteJoint([0.0, 1.0, 0.0]),
                       placement=fd.PluckerTransform(np.eye(3), [0.0, 0.0, 0.3]),
                       inertia=fd.SpatialInertia(1.0, [0.0, 0.0, 0.15], np.eye(3) * 0.01))
        return b.build()

    counts = []
    for n in (3, 4, 5, 6):
        m = chain(n)
        q = v = a = np.full(n, 0.3)
        cm = fd.core._view(m).cm
        counts.append([_core.flops(cm, kind, q, v, a) for kind in (0, 1, 2)])
    c = np.array(counts)
    assert (c > 0).all()
    steps = np.diff(c, axis=0)
    assert len(set(steps[:, 0])) == 1 and len(set(steps[:, 2])) == 1, steps  # RNEA, ABA: linear
    assert len(set(np.diff(steps[:, 1]))) == 1 and np.diff(steps[:, 1])[0] > 0, steps  # CRBA: quadratic
