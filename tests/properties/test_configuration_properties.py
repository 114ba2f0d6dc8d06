"""Properties of configuration space (hypothesis, derandomized by the conftest profile).

One property per test, over a tree holding every joint type and over batch
shapes: ``integrate`` and ``difference`` are inverse maps, ``normalize``
lands on valid configurations, random configurations respect the limits,
and a batched call equals the loop over its elements.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn import configuration as cfg
from featherdyn.testing import assert_close

seeds = st.integers(min_value=0, max_value=2**32 - 1)
batch_shapes = st.sampled_from([(), (1,), (3,), (2, 3)])


def _inertia() -> fd.SpatialInertia:
    return fd.SpatialInertia(1.0, [0.0, 0.1, 0.0], np.diag([0.02, 0.03, 0.04]))


def build_model() -> fd.Model:
    """A floating base carrying every joint type, some with limits."""
    b = fd.ModelBuilder("all-joints")
    base = b.add_body("base", -1, fd.FreeFlyerJoint(), inertia=_inertia())
    hip = b.add_body("hip", base, fd.SphericalJoint(), inertia=_inertia())
    b.add_body("knee", hip, fd.RevoluteJoint([0.0, 1.0, 0.0]), inertia=_inertia(), lower=-2.0, upper=0.5)
    b.add_body("spin", base, fd.RevoluteJoint([1.0, 0.0, 0.0]), inertia=_inertia())
    b.add_body("slide", base, fd.PrismaticJoint([0.0, 0.0, 1.0]), inertia=_inertia(), lower=0.0, upper=0.4)
    b.add_body("sled", base, fd.PlanarJoint([0.0, 1.0, 0.0]), inertia=_inertia(), lower=[-np.inf, 0.0, -1.0],
               upper=[np.inf, 2.0, 1.0])
    return b.build()


MODEL = build_model()
QUAT_SLICES = [
    slice(MODEL.idx_q[i] + (3 if isinstance(j, fd.FreeFlyerJoint) else 0), MODEL.idx_q[i] + MODEL.nqs[i])
    for i, j in enumerate(MODEL.joints)
    if isinstance(j, (fd.FreeFlyerJoint, fd.SphericalJoint))
]
# the angular parts of v (one rotation vector per quaternion joint, one angle per planar joint)
ROTATION_SLICES = [
    slice(MODEL.idx_v[i], MODEL.idx_v[i] + (3 if isinstance(j, (fd.FreeFlyerJoint, fd.SphericalJoint)) else 1))
    for i, j in enumerate(MODEL.joints)
    if isinstance(j, (fd.FreeFlyerJoint, fd.SphericalJoint, fd.PlanarJoint))
]


def same_sign(q: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``q`` with each quaternion's sign flipped to agree with ``reference``'s (``q`` and ``−q`` are one rotation)."""
    out = np.array(q)
    for sl in QUAT_SLICES:
        flip = np.sum(out[..., sl] * reference[..., sl], axis=-1, keepdims=True) < 0
        out[..., sl] = np.where(flip, -out[..., sl], out[..., sl])
    return out


def small_velocity(rng: np.random.Generator, shape: tuple[int, ...], scale: float) -> np.ndarray:
    """Velocities whose rotation parts have norm below 0.95 π (where log is the inverse of exp)."""
    v = rng.uniform(-1.0, 1.0, shape + (MODEL.nv,)) * scale
    for sl in ROTATION_SLICES:
        n = np.linalg.norm(v[..., sl], axis=-1, keepdims=True)
        v[..., sl] *= np.minimum(1.0, 0.95 * np.pi / np.maximum(n, 1e-300))
    return v


@given(seed=seeds, shape=batch_shapes)
def test_integrate_of_difference_reaches_q1(seed: int, shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(seed)
    q0 = cfg.random_configuration(MODEL, rng, size=shape)
    q1 = cfg.random_configuration(MODEL, rng, size=shape)
    reached = fd.integrate(MODEL, q0, fd.difference(MODEL, q0, q1))
    # the planar angle comes back modulo 2π
    for i, joint in enumerate(MODEL.joints):
        if isinstance(joint, fd.PlanarJoint):
            k = MODEL.idx_q[i] + 2
            reached[..., k] += 2 * np.pi * np.round((q1[..., k] - reached[..., k]) / (2 * np.pi))
    assert_close(same_sign(reached, q1), q1, "integrate(q0, difference(q0, q1))", scale=10)


@given(seed=seeds, shape=batch_shapes, scale=st.sampled_from([1e-9, 1e-3, 0.5, 3.0]))
def test_difference_of_integrate_is_v(seed: int, shape: tuple[int, ...], scale: float) -> None:
    rng = np.random.default_rng(seed)
    q = cfg.random_configuration(MODEL, rng, size=shape)
    v = small_velocity(rng, shape, scale)
    assert_close(fd.difference(MODEL, q, fd.integrate(MODEL, q, v)), v, "difference(q, q ⊕ v)", scale=10)


@given(seed=seeds)
def test_difference_at_the_same_point_is_zero(seed: int) -> None:
    rng = np.random.default_rng(seed)
    q = cfg.random_configuration(MODEL, rng)
    np.testing.assert_allclose(fd.difference(MODEL, q, q), 0.0, atol=1e-12)
    np.testing.assert_allclose(fd.integrate(MODEL, q, np.zeros(MODEL.nv)), q, atol=1e-15)


@given(seed=seeds, shape=batch_shapes)
def test_normalize_gives_normalized(seed: int, shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(seed)
    q = cfg.random_configuration(MODEL, rng, size=shape)
    for sl in QUAT_SLICES:
        q[..., sl] *= rng.uniform(0.1, 10.0, shape + (1,))
        q[..., sl] += rng.normal(scale=0.1, size=shape + (4,))
    qn = fd.normalize(MODEL, q)
    assert np.all(fd.is_normalized(MODEL, qn))
    np.testing.assert_allclose(fd.normalize(MODEL, qn), qn, atol=1e-15)  # idempotent
    keep = np.ones(MODEL.nq, dtype=bool)
    for sl in QUAT_SLICES:
        keep[sl] = False
    np.testing.assert_array_equal(qn[..., keep], q[..., keep])


@given(seed=seeds, shape=batch_shapes)
def test_random_configuration_is_valid(seed: int, shape: tuple[int, ...]) -> None:
    q = fd.random_configuration(MODEL, seed, size=shape)
    assert q.shape == shape + (MODEL.nq,)
    assert np.all((q >= MODEL.lower) & (q <= MODEL.upper))
    assert np.all(fd.is_normalized(MODEL, q))
    for sl in QUAT_SLICES:
        assert np.all(q[..., sl][..., 3] >= 0)  # w >= 0 representative
    np.testing.assert_array_equal(q, fd.random_configuration(MODEL, seed, size=shape))  # seeded = reproducible


@given(seed=seeds)
def test_interpolate_ends_and_midpoint(seed: int) -> None:
    rng = np.random.default_rng(seed)
    q0, q1 = cfg.random_configuration(MODEL, rng, size=2)
    np.testing.assert_allclose(cfg.interpolate(MODEL, q0, q1, 0.0), q0, atol=1e-15)
    mid = cfg.interpolate(MODEL, q0, q1, 0.5)
    # the midpoint is equally far (in the tangent space) from both ends along the geodesic
    assert_close(fd.difference(MODEL, q0, mid), 0.5 * fd.difference(MODEL, q0, q1), "q0 → midpoint", scale=10)


@given(seed=seeds, shape=st.sampled_from([(1,), (3,), (2, 3)]))
def test_batch_equals_loop(seed: int, shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(seed)
    q0 = cfg.random_configuration(MODEL, rng, size=shape)
    q1 = cfg.random_configuration(MODEL, rng, size=shape)
    v = rng.uniform(-2.0, 2.0, shape + (MODEL.nv,))
    q_out, v_out = fd.integrate(MODEL, q0, v), fd.difference(MODEL, q0, q1)
    for idx in np.ndindex(*shape):
        np.testing.assert_allclose(q_out[idx], fd.integrate(MODEL, q0[idx], v[idx]), atol=1e-15)
        np.testing.assert_allclose(v_out[idx], fd.difference(MODEL, q0[idx], q1[idx]), atol=1e-15)


@given(seed=seeds)
def test_float32_round_trip(seed: int) -> None:
    rng = np.random.default_rng(seed)
    q = cfg.random_configuration(MODEL, rng, size=4).astype(np.float32)
    v = small_velocity(rng, (4,), 0.5).astype(np.float32)
    out = fd.integrate(MODEL, q, v)
    assert out.dtype == np.float32
    back = fd.difference(MODEL, q, out)
    assert back.dtype == np.float32
    assert_close(back, v, "float32 difference(q, q ⊕ v)", scale=10)
