"""Unit tests of featherdyn.configuration, cross-checked against Pinocchio.

The Pinocchio model mirrors a featherdyn model joint for joint (free-flyer
root, revolute, spherical, prismatic, planar). Layouts are converted here,
explicitly: free-flyer ``v`` is ``[v; ω]`` in Pinocchio and ``[ω; v]`` here;
planar ``q`` is ``[x, y, cos θ, sin θ]`` there and ``[x, y, θ]`` here, planar
``v`` ``[v_x, v_y, ω]`` there and ``[ω, v_x, v_y]`` here.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import configuration as cfg
from featherdyn.errors import DTypeError, NonFiniteError, QuaternionNormError, ShapeError
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

SEED = 31415
N_SAMPLES = 25


# --------------------------------------------------------------------------
# the mirrored models
# --------------------------------------------------------------------------


def _inertia() -> fd.SpatialInertia:
    return fd.SpatialInertia(1.0, [0.05, 0.0, 0.02], np.diag([0.02, 0.03, 0.04]))


def _placement(rng: np.random.Generator) -> fd.PluckerTransform:
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    return fd.PluckerTransform(fd.rotation.quat_to_matrix(quat), rng.uniform(-0.5, 0.5, 3))


def build_pair() -> tuple[fd.Model, Any]:
    """A featherdyn model and the same tree in Pinocchio (limits on the revolute and prismatic joints)."""
    rng = np.random.default_rng(7)
    axis = np.array([0.2, 0.9, -0.4]) / np.linalg.norm([0.2, 0.9, -0.4])
    # (name, parent, featherdyn joint, Pinocchio joint model, lower, upper)
    spec = [
        ("root", -1, fd.FreeFlyerJoint(), pin.JointModelFreeFlyer(), None, None),
        ("shoulder", 0, fd.RevoluteJoint(axis), pin.JointModelRevoluteUnaligned(*axis), -1.5, 2.0),
        ("ball", 1, fd.SphericalJoint(), pin.JointModelSpherical(), None, None),
        ("slider", 0, fd.PrismaticJoint([1.0, 0.0, 0.0]), pin.JointModelPX(), -0.2, 0.3),
        ("wheel", 2, fd.RevoluteJoint([0.0, 0.0, 1.0]), pin.JointModelRZ(), None, None),
        ("sled", 3, fd.PlanarJoint(), pin.JointModelPlanar(), None, None),
    ]
    b = fd.ModelBuilder("mirror")
    pmodel = pin.Model()
    for name, parent, joint, pin_joint, lo, hi in spec:
        X = _placement(rng)
        b.add_body(name + "_link", parent, joint, placement=X, inertia=_inertia(), joint_name=name, lower=lo, upper=hi)
        pmodel.addJoint(parent + 1, pin_joint, pin.SE3(X.rotation, X.translation), name)
    return b.build(), pmodel


MODEL, PMODEL = build_pair()


def q_to_pin(q: np.ndarray) -> np.ndarray:
    parts = []
    for i, joint in enumerate(MODEL.joints):
        qi = q[MODEL.idx_q[i] : MODEL.idx_q[i] + MODEL.nqs[i]]
        if isinstance(joint, fd.PlanarJoint):
            qi = np.array([qi[0], qi[1], np.cos(qi[2]), np.sin(qi[2])])
        parts.append(qi)
    out = np.concatenate(parts)
    assert out.shape == (PMODEL.nq,)
    return out


def q_from_pin(qp: np.ndarray, like: np.ndarray) -> np.ndarray:
    """Pinocchio's ``q`` in featherdyn's layout; planar angles unwrapped towards ``like``."""
    out = np.empty(MODEL.nq)
    for i, joint in enumerate(MODEL.joints):
        sp = slice(PMODEL.idx_qs[i + 1], PMODEL.idx_qs[i + 1] + PMODEL.nqs[i + 1])
        sf = slice(MODEL.idx_q[i], MODEL.idx_q[i] + MODEL.nqs[i])
        qi = qp[sp]
        if isinstance(joint, fd.PlanarJoint):
            theta = np.arctan2(qi[3], qi[2])
            theta += 2 * np.pi * np.round((like[sf][2] - theta) / (2 * np.pi))
            qi = np.array([qi[0], qi[1], theta])
        out[sf] = qi
    return out


def v_to_pin(v: np.ndarray) -> np.ndarray:
    out = np.array(v, dtype=np.float64)
    for i, joint in enumerate(MODEL.joints):
        s = slice(MODEL.idx_v[i], MODEL.idx_v[i] + MODEL.nvs[i])
        vi = v[s]
        if isinstance(joint, fd.FreeFlyerJoint):
            out[s] = np.concatenate([vi[3:], vi[:3]])
        elif isinstance(joint, fd.PlanarJoint):
            out[s] = [vi[1], vi[2], vi[0]]
    return out


def v_from_pin(vp: np.ndarray) -> np.ndarray:
    out = np.array(vp, dtype=np.float64)
    for i, joint in enumerate(MODEL.joints):
        s = slice(MODEL.idx_v[i], MODEL.idx_v[i] + MODEL.nvs[i])
        vi = vp[s]
        if isinstance(joint, fd.FreeFlyerJoint):
            out[s] = np.concatenate([vi[3:], vi[:3]])
        elif isinstance(joint, fd.PlanarJoint):
            out[s] = [vi[2], vi[0], vi[1]]
    return out


def quaternion_slices(model: fd.Model) -> list[slice]:
    out = []
    for i, joint in enumerate(model.joints):
        if isinstance(joint, fd.SphericalJoint):
            out.append(slice(model.idx_q[i], model.idx_q[i] + 4))
        elif isinstance(joint, fd.FreeFlyerJoint):
            out.append(slice(model.idx_q[i] + 3, model.idx_q[i] + 7))
    return out


def test_mirror_is_consistent() -> None:
    assert (MODEL.nq, MODEL.nv) == (PMODEL.nq - 1, PMODEL.nv)  # planar: 3 here, 4 in Pinocchio
    assert MODEL.joint_names == tuple(PMODEL.names[1:])
    q = cfg.random_configuration(MODEL, SEED)
    np.testing.assert_allclose(q_from_pin(q_to_pin(q), q), q, atol=1e-15)
    v = np.arange(MODEL.nv, dtype=float)
    np.testing.assert_array_equal(v_from_pin(v_to_pin(v)), v)


# --------------------------------------------------------------------------
# against Pinocchio
# --------------------------------------------------------------------------


def test_neutral_matches_pinocchio() -> None:
    q = fd.neutral(MODEL)
    assert q.shape == (MODEL.nq,) and q.dtype == np.float64
    np.testing.assert_array_equal(q_to_pin(q), pin.neutral(PMODEL))


def test_integrate_matches_pinocchio() -> None:
    rng = np.random.default_rng(SEED)
    for k in range(N_SAMPLES):
        q = cfg.random_configuration(MODEL, rng)
        v = rng.uniform(-2.0, 2.0, MODEL.nv)
        expected = pin.integrate(PMODEL, q_to_pin(q), v_to_pin(v))
        actual = fd.integrate(MODEL, q, v)
        # compared in Pinocchio's layout: the same quaternion sign, not just the same rotation
        assert_close(q_to_pin(actual), expected, "integrate", where=f"sample {k}")


def test_difference_matches_pinocchio() -> None:
    rng = np.random.default_rng(SEED + 1)
    for k in range(N_SAMPLES):
        q0, q1 = cfg.random_configuration(MODEL, rng, size=2)
        expected = v_from_pin(pin.difference(PMODEL, q_to_pin(q0), q_to_pin(q1)))
        assert_close(fd.difference(MODEL, q0, q1), expected, "difference", where=f"sample {k}", scale=10)


@pytest.mark.parametrize("t", [0.0, 0.25, 0.5, 1.0, 1.5])
def test_interpolate_matches_pinocchio(t: float) -> None:
    rng = np.random.default_rng(SEED + 2)
    for k in range(5):
        q0, q1 = cfg.random_configuration(MODEL, rng, size=2)
        expected = pin.interpolate(PMODEL, q_to_pin(q0), q_to_pin(q1), t)
        actual = cfg.interpolate(MODEL, q0, q1, t)
        assert_close(q_to_pin(actual), expected, "interpolate", where=f"t = {t}, sample {k}", scale=10)


def test_normalize_matches_pinocchio() -> None:
    rng = np.random.default_rng(SEED + 3)
    q = cfg.random_configuration(MODEL, rng)
    for sl in quaternion_slices(MODEL):
        q[sl] *= rng.uniform(0.5, 2.0)
    assert not fd.is_normalized(MODEL, q)
    assert not pin.isNormalized(PMODEL, q_to_pin(q), 1e-10)
    qn = fd.normalize(MODEL, q)
    assert fd.is_normalized(MODEL, qn)
    assert_close(q_to_pin(qn), pin.normalize(PMODEL, q_to_pin(q)), "normalize")


# --------------------------------------------------------------------------
# random_configuration
# --------------------------------------------------------------------------


def test_random_configuration_within_limits() -> None:
    q = fd.random_configuration(MODEL, SEED, size=2000)
    assert q.shape == (2000, MODEL.nq) and q.dtype == np.float64
    finite = np.isfinite(MODEL.lower)
    assert finite.sum() == 2  # the revolute "shoulder" and the prismatic "slider"
    assert np.all(q[:, finite] >= MODEL.lower[finite]) and np.all(q[:, finite] <= MODEL.upper[finite])
    # unbounded revolute angles in [−π, π]; free-flyer and planar positions in [−1, 1]
    wheel = MODEL.idx_q[MODEL.joint_id("wheel")]
    assert np.all(np.abs(q[:, wheel]) <= np.pi) and np.ptp(q[:, wheel]) > 6.0
    assert np.all(np.abs(q[:, 0:3]) <= 1.0)
    sled = MODEL.idx_q[MODEL.joint_id("sled")]
    assert np.all(np.abs(q[:, sled : sled + 2]) <= 1.0) and np.all(np.abs(q[:, sled + 2]) <= np.pi)
    for sl in quaternion_slices(MODEL):
        np.testing.assert_allclose(np.linalg.norm(q[:, sl], axis=-1), 1.0, atol=1e-14)
    assert np.all(fd.is_normalized(MODEL, q))


def test_free_flyer_position_uses_finite_limits() -> None:
    b = fd.ModelBuilder()
    b.add_body("base", -1, fd.FreeFlyerJoint(), inertia=_inertia(), lower=[2, 3, -5, -1, -1, -1, -1],
               upper=[2.5, 4, -4, 1, 1, 1, 1])
    model = b.build()
    q = fd.random_configuration(model, SEED, size=500)
    assert np.all(q[:, :3] >= [2, 3, -5]) and np.all(q[:, :3] <= [2.5, 4, -4])
    np.testing.assert_allclose(np.linalg.norm(q[:, 3:], axis=-1), 1.0, atol=1e-14)


def test_random_quaternions_are_uniform() -> None:
    """Uniform on S³: E[x²] = E[y²] = E[z²] = E[w²] = 1/4 (std of the mean over 20000 draws ≈ 0.002)."""
    b = fd.ModelBuilder()
    b.add_body("ball", -1, fd.SphericalJoint(), inertia=_inertia())
    quat = fd.random_configuration(b.build(), SEED, size=20000)
    np.testing.assert_allclose(np.mean(quat**2, axis=0), 0.25, atol=0.01)
    np.testing.assert_allclose(np.mean(quat[:, :3], axis=0), 0.0, atol=0.02)
    # the rotation angle 2 acos|w| has density (1 − cos θ)/π on [0, π]: mean π/2 + 2/π
    angle = 2 * np.arccos(np.clip(np.abs(quat[:, 3]), 0, 1))
    assert np.mean(angle) == pytest.approx(np.pi / 2 + 2 / np.pi, abs=0.02)


def test_random_configuration_rng_and_size() -> None:
    a = fd.random_configuration(MODEL, 5, size=(2, 3))
    b = fd.random_configuration(MODEL, np.random.default_rng(5), size=(2, 3))
    assert a.shape == (2, 3, MODEL.nq)
    np.testing.assert_array_equal(a, b)
    gen = np.random.default_rng(5)
    first, second = fd.random_configuration(MODEL, gen), fd.random_configuration(MODEL, gen)
    assert not np.array_equal(first, second)  # a Generator is advanced, not re-seeded
    assert fd.random_configuration(MODEL).shape == (MODEL.nq,)
    assert fd.random_configuration(MODEL, size=4).shape == (4, MODEL.nq)
    assert fd.random_configuration(MODEL, size=0).shape == (0, MODEL.nq)
    with pytest.raises(TypeError, match="rng"):
        fd.random_configuration(MODEL, np.random.RandomState(0))
    with pytest.raises(TypeError, match="rng"):
        fd.random_configuration(MODEL, "seed")
    with pytest.raises(ShapeError, match="size"):
        fd.random_configuration(MODEL, 0, size=-1)
    with pytest.raises(ShapeError, match="size"):
        fd.random_configuration(MODEL, 0, size="big")


# --------------------------------------------------------------------------
# batching, broadcasting and dtypes
# --------------------------------------------------------------------------


@pytest.mark.parametrize("shape", [(), (1,), (3,), (2, 3)], ids=str)
def test_batch_equals_loop(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(SEED + 4)
    q0 = cfg.random_configuration(MODEL, rng, size=shape)
    q1 = cfg.random_configuration(MODEL, rng, size=shape)
    v = rng.uniform(-1, 1, shape + (MODEL.nv,))
    t = rng.uniform(0, 1, shape)
    batched = {
        "integrate": fd.integrate(MODEL, q0, v),
        "difference": fd.difference(MODEL, q0, q1),
        "interpolate": cfg.interpolate(MODEL, q0, q1, t),
        "normalize": fd.normalize(MODEL, q0 * 1.5),
    }
    assert batched["integrate"].shape == shape + (MODEL.nq,)
    assert batched["difference"].shape == shape + (MODEL.nv,)
    assert np.shape(fd.is_normalized(MODEL, q0)) == shape
    for idx in np.ndindex(*shape):
        single = {
            "integrate": fd.integrate(MODEL, q0[idx], v[idx]),
            "difference": fd.difference(MODEL, q0[idx], q1[idx]),
            "interpolate": cfg.interpolate(MODEL, q0[idx], q1[idx], t[idx]),
            "normalize": fd.normalize(MODEL, q0[idx] * 1.5),
        }
        for name, value in single.items():
            np.testing.assert_allclose(batched[name][idx], value, atol=1e-14, err_msg=f"{name} at {idx}")


def test_batch_axes_broadcast() -> None:
    rng = np.random.default_rng(SEED + 5)
    q = cfg.random_configuration(MODEL, rng)
    v = rng.uniform(-1, 1, (4, 1, MODEL.nv))
    q_batch = cfg.random_configuration(MODEL, rng, size=3)
    out = fd.integrate(MODEL, q_batch, v)
    assert out.shape == (4, 3, MODEL.nq)
    np.testing.assert_allclose(out[2, 1], fd.integrate(MODEL, q_batch[1], v[2, 0]), atol=1e-15)
    assert fd.integrate(MODEL, q, v).shape == (4, 1, MODEL.nq)
    assert fd.difference(MODEL, q, q_batch).shape == (3, MODEL.nv)
    with pytest.raises(ShapeError, match="do not broadcast"):
        fd.integrate(MODEL, q_batch, np.zeros((2, MODEL.nv)))


def test_float32_stays_float32() -> None:
    rng = np.random.default_rng(SEED + 6)
    q0 = cfg.random_configuration(MODEL, rng, size=5).astype(np.float32)
    q1 = cfg.random_configuration(MODEL, rng, size=5).astype(np.float32)
    v = rng.uniform(-1, 1, (5, MODEL.nv)).astype(np.float32)
    out = fd.integrate(MODEL, q0, v)
    assert out.dtype == np.float32
    assert fd.difference(MODEL, q0, q1).dtype == np.float32
    assert cfg.interpolate(MODEL, q0, q1, 0.5).dtype == np.float32
    assert fd.normalize(MODEL, q0).dtype == np.float32
    assert_close(out, fd.integrate(MODEL, q0.astype(np.float64), v.astype(np.float64)), "float32 integrate")
    # a float32 unit quaternion is unit to ~1e-7, within float32's tolerance of 1e-4
    assert_close(fd.difference(MODEL, q0, out), v, "float32 difference(q, q ⊕ v)", scale=10)
    # mixed precision promotes
    assert fd.integrate(MODEL, q0, v.astype(np.float64)).dtype == np.float64


def test_integer_input_becomes_float64() -> None:
    q = fd.neutral(MODEL).astype(int)
    assert fd.integrate(MODEL, q, np.zeros(MODEL.nv, dtype=int)).dtype == np.float64


def test_inputs_are_not_modified() -> None:
    rng = np.random.default_rng(SEED + 7)
    q = cfg.random_configuration(MODEL, rng) * 1.0
    v = rng.uniform(-1, 1, MODEL.nv)
    q_copy, v_copy = q.copy(), v.copy()
    fd.integrate(MODEL, q, v)
    fd.difference(MODEL, q, q)
    fd.normalize(MODEL, q)
    np.testing.assert_array_equal(q, q_copy)
    np.testing.assert_array_equal(v, v_copy)


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------


def test_wrong_lengths_name_the_argument() -> None:
    q = fd.neutral(MODEL)
    v = np.zeros(MODEL.nv)
    with pytest.raises(ShapeError, match=r"^q: expected trailing dimension nq=17, got shape \(16,\)$"):
        fd.integrate(MODEL, q[:-1], v)
    with pytest.raises(ShapeError, match=r"^v: expected trailing dimension nv=15, got shape \(3, 17\)$"):
        fd.integrate(MODEL, q, np.zeros((3, 17)))
    with pytest.raises(ShapeError, match=r"^q1: expected trailing dimension nq=17, got shape \(\)$"):
        fd.difference(MODEL, q, 0.0)
    with pytest.raises(ShapeError, match="q0: expected trailing dimension nq=17"):
        fd.difference(MODEL, q[:7], q)
    with pytest.raises(ShapeError, match="q: expected trailing dimension nq=17"):
        fd.normalize(MODEL, np.zeros((2, 18)))
    with pytest.raises(ShapeError, match="q: expected trailing dimension nq=17"):
        fd.is_normalized(MODEL, [1.0])
    assert (MODEL.nq, MODEL.nv) == (17, 15)


def test_non_finite_values() -> None:
    q = fd.neutral(MODEL)
    q[12] = np.nan
    with pytest.raises(NonFiniteError, match=r"q: expected finite numbers.*index \(12,\)"):
        fd.integrate(MODEL, q, np.zeros(MODEL.nv))
    v = np.zeros((2, MODEL.nv))
    v[1, 3] = np.inf
    with pytest.raises(NonFiniteError, match=r"v: .*index \(1, 3\)"):
        fd.integrate(MODEL, fd.neutral(MODEL), v)
    with pytest.raises(NonFiniteError, match="q1"):
        fd.difference(MODEL, fd.neutral(MODEL), q)
    with pytest.raises(DTypeError):
        fd.integrate(MODEL, fd.neutral(MODEL).astype(complex), np.zeros(MODEL.nv))


def test_non_unit_quaternions_name_the_joint() -> None:
    q = fd.neutral(MODEL)
    v = np.zeros(MODEL.nv)
    bad = q.copy()
    bad[6] = 1.01  # the free-flyer's w
    with pytest.raises(QuaternionNormError, match=r"q: joint 'root' \(free_flyer, q\[3:7\]\).*norm 1\.01"):
        fd.integrate(MODEL, bad, v)
    ball = MODEL.idx_q[MODEL.joint_id("ball")]
    bad = np.stack([q, q, q])
    bad[2, ball : ball + 4] = [0.0, 0.0, 0.0, 0.0]
    with pytest.raises(QuaternionNormError, match=rf"q1: joint 'ball' \(spherical, q1\[{ball}:{ball + 4}\]\).*batch index \(2,\)"):
        fd.difference(MODEL, q, bad)
    with pytest.raises(QuaternionNormError, match="q0: joint 'ball'"):
        fd.difference(MODEL, bad, q)
    # within 1e-6 is accepted, and the result is unit again
    near = q.copy()
    near[ball + 3] = 1 + 5e-7
    out = fd.integrate(MODEL, near, v)
    assert fd.is_normalized(MODEL, out)
    with pytest.raises(QuaternionNormError, match=r"joint 'ball'.*zero quaternion"):
        fd.normalize(MODEL, bad[2])


def test_not_a_model() -> None:
    with pytest.raises(TypeError, match="Model"):
        fd.neutral(PMODEL)
    with pytest.raises(TypeError, match="Model"):
        fd.integrate("panda", np.zeros(7), np.zeros(6))


def test_is_normalized_returns_bool_for_one_configuration() -> None:
    q = fd.neutral(MODEL)
    assert fd.is_normalized(MODEL, q) is True
    q[6] = 1 + 1e-9
    assert fd.is_normalized(MODEL, q) is False
    assert fd.is_normalized(MODEL, q, tol=1e-8) is True


def test_fixed_base_model_without_quaternions() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=_inertia())
    b.add_body("b", 0, fd.PrismaticJoint(), inertia=_inertia())
    model = b.build()
    np.testing.assert_array_equal(fd.neutral(model), [0.0, 0.0])
    np.testing.assert_array_equal(fd.integrate(model, [1.0, 2.0], [0.5, -1.0]), [1.5, 1.0])
    np.testing.assert_array_equal(fd.difference(model, [1.0, 2.0], [0.5, -1.0]), [-0.5, -3.0])
    empty = fd.ModelBuilder().build()
    assert fd.neutral(empty).shape == (0,)
    assert fd.integrate(empty, np.zeros((3, 0)), np.zeros(0)).shape == (3, 0)


def test_symbolic_vector_joints() -> None:
    """Object (SymPy) arrays pass through the vector-space joints unchanged."""
    sympy = pytest.importorskip("sympy")
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=_inertia())
    b.add_body("b", 0, fd.PrismaticJoint(), inertia=_inertia())
    model = b.build()
    q1, q2, v1 = sympy.symbols("q1 q2 v1")
    out = fd.integrate(model, np.array([q1, q2], dtype=object), np.array([v1, 0], dtype=object))
    assert out.dtype == object
    assert sympy.simplify(out[0] - (q1 + v1)) == 0 and sympy.simplify(out[1] - q2) == 0
