"""Unit tests of featherdyn.joints: each joint model against Pinocchio's, and its own contract.

Every joint is compared with the same joint in a one-joint Pinocchio model
(identity placement): ``pose(q)`` with ``data.oMi[1]``, ``S`` with the LOCAL
joint Jacobian, and ``integrate`` / ``difference`` with ``pin.integrate`` /
``pin.difference``. Layouts are converted here, explicitly and independently
of :mod:`featherdyn.conventions`:

* Pinocchio's 6D vectors are linear first, ``[v; ω]`` (featherdyn ``[ω; v]``);
* free-flyer ``v``: Pinocchio ``[v; ω]``, featherdyn ``[ω; v]`` (both LOCAL);
* planar ``q``: Pinocchio ``[x, y, cos θ, sin θ]``, featherdyn ``[x, y, θ]``;
  planar ``v``: Pinocchio ``[v_x, v_y, ω]``, featherdyn ``[ω, v_x, v_y]``;
* spherical and free-flyer quaternions are ``(x, y, z, w)`` in both.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import rotation as rot
from featherdyn.errors import ModelError, PhysicalityWarning, QuaternionNormError, ShapeError
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

SEED = 20240611
N_SAMPLES = 20
ROWS_PIN_TO_FD = [3, 4, 5, 0, 1, 2]  # a linear-first 6-vector's rows in angular-first order

_AXIS = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])

# (id, featherdyn joint, Pinocchio joint model factory)
CASES: list[tuple[str, Callable[[], fd.Joint], Callable[[], Any]]] = [
    ("RX", lambda: fd.RevoluteJoint([1.0, 0.0, 0.0]), lambda: pin.JointModelRX()),
    ("RY", lambda: fd.RevoluteJoint([0.0, 1.0, 0.0]), lambda: pin.JointModelRY()),
    ("RZ", lambda: fd.RevoluteJoint([0.0, 0.0, 1.0]), lambda: pin.JointModelRZ()),
    ("R-neg-z", lambda: fd.RevoluteJoint([0.0, 0.0, -1.0]), lambda: pin.JointModelRevoluteUnaligned(0.0, 0.0, -1.0)),
    ("R-unaligned", lambda: fd.RevoluteJoint(_AXIS), lambda: pin.JointModelRevoluteUnaligned(*_AXIS)),
    ("PX", lambda: fd.PrismaticJoint([1.0, 0.0, 0.0]), lambda: pin.JointModelPX()),
    ("PZ", lambda: fd.PrismaticJoint([0.0, 0.0, 1.0]), lambda: pin.JointModelPZ()),
    ("P-unaligned", lambda: fd.PrismaticJoint(_AXIS), lambda: pin.JointModelPrismaticUnaligned(*_AXIS)),
    ("spherical", lambda: fd.SphericalJoint(), lambda: pin.JointModelSpherical()),
    ("free-flyer", lambda: fd.FreeFlyerJoint(), lambda: pin.JointModelFreeFlyer()),
    ("planar", lambda: fd.PlanarJoint(), lambda: pin.JointModelPlanar()),
]
CASE_IDS = [c[0] for c in CASES]


# --------------------------------------------------------------------------
# explicit layout conversions
# --------------------------------------------------------------------------


def q_to_pin(joint: fd.Joint, q: np.ndarray) -> np.ndarray:
    if isinstance(joint, fd.PlanarJoint):
        return np.array([q[0], q[1], np.cos(q[2]), np.sin(q[2])])
    return np.array(q, dtype=np.float64)


def v_to_pin(joint: fd.Joint, v: np.ndarray) -> np.ndarray:
    if isinstance(joint, fd.FreeFlyerJoint):
        return np.concatenate([v[3:], v[:3]])  # [ω; v] -> [v; ω]
    if isinstance(joint, fd.PlanarJoint):
        return np.array([v[1], v[2], v[0]])  # [ω, vx, vy] -> [vx, vy, ω]
    return np.array(v, dtype=np.float64)


def v_from_pin(joint: fd.Joint, v: np.ndarray) -> np.ndarray:
    if isinstance(joint, fd.FreeFlyerJoint):
        return np.concatenate([v[3:], v[:3]])
    if isinstance(joint, fd.PlanarJoint):
        return np.array([v[2], v[0], v[1]])
    return np.array(v, dtype=np.float64)


def same_config(joint: fd.Joint, q_fd: np.ndarray, q_pin: np.ndarray) -> np.ndarray:
    """``q_pin`` in featherdyn's layout, the quaternion's sign matched to ``q_fd``'s."""
    q = np.array(q_pin, dtype=np.float64)
    if isinstance(joint, fd.PlanarJoint):
        theta = np.arctan2(q[3], q[2])
        theta += 2 * np.pi * np.round((q_fd[2] - theta) / (2 * np.pi))  # featherdyn keeps θ unwrapped
        return np.array([q[0], q[1], theta])
    return q


def one_joint_model(pin_joint: Any) -> tuple[Any, Any]:
    model = pin.Model()
    model.addJoint(0, pin_joint, pin.SE3.Identity(), "j")
    return model, model.createData()


def random_q(joint: fd.Joint, rng: np.random.Generator) -> np.ndarray:
    return joint.random(rng, np.full(joint.nq, -2.0), np.full(joint.nq, 2.0))


def small_v(joint: fd.Joint, rng: np.random.Generator, scale: float = 1.0) -> np.ndarray:
    """A velocity whose rotation part has norm below π (so difference inverts integrate)."""
    v = rng.uniform(-1.0, 1.0, joint.nv) * scale
    if isinstance(joint, (fd.SphericalJoint, fd.FreeFlyerJoint)):
        w = v[:3]
        n = np.linalg.norm(w)
        if n > 0.9 * np.pi:
            v[:3] = w * (0.9 * np.pi / n)
    if isinstance(joint, fd.PlanarJoint):
        v[0] = np.clip(v[0], -0.9 * np.pi, 0.9 * np.pi)
    return v


@pytest.fixture(params=CASES, ids=CASE_IDS)
def case(request: pytest.FixtureRequest) -> tuple[fd.Joint, Any]:
    _, make_fd, make_pin = request.param
    return make_fd(), make_pin()


# --------------------------------------------------------------------------
# against Pinocchio
# --------------------------------------------------------------------------


def test_pose_matches_pinocchio(case: tuple[fd.Joint, Any]) -> None:
    joint, pin_joint = case
    model, data = one_joint_model(pin_joint)
    rng = np.random.default_rng(SEED)
    for k in range(N_SAMPLES):
        q = random_q(joint, rng)
        pin.forwardKinematics(model, data, q_to_pin(joint, q))
        M = data.oMi[1]
        T = joint.pose(q)
        assert_close(T.rotation, M.rotation, f"{joint!r} pose rotation", where=f"sample {k}")
        assert_close(T.translation, M.translation, f"{joint!r} pose translation", where=f"sample {k}")


def test_motion_subspace_matches_pinocchio(case: tuple[fd.Joint, Any]) -> None:
    joint, pin_joint = case
    model, data = one_joint_model(pin_joint)
    rng = np.random.default_rng(SEED + 1)
    q = random_q(joint, rng)
    pin.computeJointJacobians(model, data, q_to_pin(joint, q))
    J = np.asarray(pin.getJointJacobian(model, data, 1, pin.ReferenceFrame.LOCAL)).reshape(6, -1)  # rows [v; ω]
    # columns of J follow Pinocchio's v; map each featherdyn unit velocity through it
    S_pin = np.stack([J @ v_to_pin(joint, e) for e in np.eye(joint.nv)], axis=1)[ROWS_PIN_TO_FD]
    assert joint.S.shape == (6, joint.nv)
    assert_close(joint.S, S_pin, f"{joint!r} motion subspace S")


def test_integrate_matches_pinocchio(case: tuple[fd.Joint, Any]) -> None:
    joint, pin_joint = case
    model, _ = one_joint_model(pin_joint)
    rng = np.random.default_rng(SEED + 2)
    for k in range(N_SAMPLES):
        q = random_q(joint, rng)
        v = rng.uniform(-2.0, 2.0, joint.nv)  # rotations beyond π included
        expected = pin.integrate(model, q_to_pin(joint, q), v_to_pin(joint, v))
        actual = joint.integrate(q, v)
        # same sign of the quaternion as Pinocchio, not only the same rotation
        assert_close(actual, same_config(joint, actual, expected), f"{joint!r} integrate", where=f"sample {k}")


def test_difference_matches_pinocchio(case: tuple[fd.Joint, Any]) -> None:
    joint, pin_joint = case
    model, _ = one_joint_model(pin_joint)
    rng = np.random.default_rng(SEED + 3)
    for k in range(N_SAMPLES):
        q0, q1 = random_q(joint, rng), random_q(joint, rng)
        expected = v_from_pin(joint, pin.difference(model, q_to_pin(joint, q0), q_to_pin(joint, q1)))
        assert_close(joint.difference(q0, q1), expected, f"{joint!r} difference", where=f"sample {k}", scale=10)


def test_neutral_matches_pinocchio(case: tuple[fd.Joint, Any]) -> None:
    joint, pin_joint = case
    model, _ = one_joint_model(pin_joint)
    neutral = joint.neutral()
    assert neutral.shape == (joint.nq,)
    np.testing.assert_array_equal(q_to_pin(joint, neutral), pin.neutral(model))


def test_planar_with_other_normal_is_a_rotated_pinocchio_planar() -> None:
    """A planar joint with normal n is Pinocchio's planar joint seen through the basis B = [e1 e2 n]."""
    joint = fd.PlanarJoint([1.0, 0.0, 0.0])
    B = joint.basis
    np.testing.assert_allclose(B.T @ B, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(B[:, 2], [1.0, 0.0, 0.0])
    assert np.linalg.det(B) == pytest.approx(1.0)
    model, data = one_joint_model(pin.JointModelPlanar())
    rng = np.random.default_rng(SEED + 4)
    for _ in range(5):
        q = random_q(joint, rng)
        pin.forwardKinematics(model, data, q_to_pin(joint, q))
        expected = pin.SE3(B, np.zeros(3)) * data.oMi[1] * pin.SE3(B.T, np.zeros(3))
        T = joint.pose(q)
        assert_close(T.rotation, expected.rotation, "planar(x) pose rotation")
        assert_close(T.translation, expected.translation, "planar(x) pose translation")


# --------------------------------------------------------------------------
# internal consistency: pose, S and integrate describe the same motion
# --------------------------------------------------------------------------


def test_pose_of_integrate_is_pose_times_exp_S_v(case: tuple[fd.Joint, Any]) -> None:
    """``pose(q)⁻¹ pose(integrate(q, v)) = exp(S v)``: the velocity is a body velocity along S."""
    joint, _ = case
    rng = np.random.default_rng(SEED + 5)
    for _ in range(10):
        q, v = random_q(joint, rng), small_v(joint, rng)
        step = joint.pose(q).inverse() @ joint.pose(joint.integrate(q, v))
        assert_close(rot.se3_log(step).vector, joint.S @ v, f"{joint!r} log(pose⁻¹ pose(q ⊕ v))", scale=10)


def test_difference_inverts_integrate(case: tuple[fd.Joint, Any]) -> None:
    joint, _ = case
    rng = np.random.default_rng(SEED + 6)
    for _ in range(10):
        q, v = random_q(joint, rng), small_v(joint, rng)
        assert_close(joint.difference(q, joint.integrate(q, v)), v, f"{joint!r} difference(q, q ⊕ v)", scale=10)


def test_motion_is_S_times_qd(case: tuple[fd.Joint, Any]) -> None:
    joint, _ = case
    qd = np.random.default_rng(SEED + 7).normal(size=(4, joint.nv))
    m = joint.motion(qd)
    assert isinstance(m, fd.SpatialMotion)
    assert_close(m.vector, qd @ joint.S.T, f"{joint!r} motion")


def test_batched_pose_equals_loop(case: tuple[fd.Joint, Any]) -> None:
    joint, _ = case
    rng = np.random.default_rng(SEED + 8)
    q = joint.random(rng, np.full(joint.nq, -2.0), np.full(joint.nq, 2.0), size=(2, 3))
    assert q.shape == (2, 3, joint.nq)
    T = joint.pose(q)
    assert T.shape == (2, 3)
    for idx in np.ndindex(2, 3):
        Ti = joint.pose(q[idx])
        np.testing.assert_allclose(T.rotation[idx], Ti.rotation, atol=1e-15)
        np.testing.assert_allclose(T.translation[idx], Ti.translation, atol=1e-15)
    v = rng.uniform(-1, 1, (2, 3, joint.nv))
    loop = np.stack([joint.integrate(q[idx], v[idx]) for idx in np.ndindex(2, 3)]).reshape(q.shape)
    np.testing.assert_allclose(joint.integrate(q, v), loop, atol=1e-15)


def test_float32_stays_float32(case: tuple[fd.Joint, Any]) -> None:
    joint, _ = case
    rng = np.random.default_rng(SEED + 9)
    q = random_q(joint, rng).astype(np.float32)
    v = small_v(joint, rng).astype(np.float32)
    T = joint.pose(q)
    assert T.rotation.dtype == np.float32 and T.translation.dtype == np.float32
    assert joint.integrate(q, v).dtype == np.float32
    assert joint.difference(q, q).dtype == np.float32
    assert joint.normalize(q).dtype == np.float32
    T64 = joint.pose(q.astype(np.float64))
    assert_close(T.rotation, T64.rotation, f"{joint!r} float32 pose")


def test_S_and_axis_are_read_only(case: tuple[fd.Joint, Any]) -> None:
    joint, _ = case
    with pytest.raises(ValueError):
        joint.S[0, 0] = 5.0
    for name in ("axis", "normal"):
        if hasattr(joint, name):
            with pytest.raises(ValueError):
                getattr(joint, name)[0] = 5.0
            with pytest.raises(AttributeError):
                setattr(joint, name, np.zeros(3))


# --------------------------------------------------------------------------
# configuration-space pieces
# --------------------------------------------------------------------------


@pytest.mark.parametrize("joint", [fd.SphericalJoint(), fd.FreeFlyerJoint()], ids=repr)
def test_quaternion_joints_normalize(joint: fd.Joint) -> None:
    q = joint.neutral() * 1.0
    q[-4:] = [0.2, -0.4, 0.1, 1.3]
    assert not joint.is_normalized(q)
    qn = joint.normalize(q)
    assert joint.is_normalized(qn)
    np.testing.assert_allclose(qn[-4:], q[-4:] / np.linalg.norm(q[-4:]), rtol=1e-15)
    np.testing.assert_array_equal(qn[: joint.nq - 4], q[: joint.nq - 4])  # position untouched
    with pytest.raises(QuaternionNormError, match="q"):
        joint.integrate(q, np.zeros(joint.nv))
    with pytest.raises(QuaternionNormError, match="q1"):
        joint.difference(qn, q)
    with pytest.raises(QuaternionNormError):
        joint.pose(q)


@pytest.mark.parametrize("joint", [fd.SphericalJoint(), fd.FreeFlyerJoint()], ids=repr)
def test_integrate_keeps_the_quaternion_sign(joint: fd.Joint) -> None:
    q = joint.neutral()
    q[-4:] = [0.0, 0.0, -0.6, -0.8]  # w < 0
    np.testing.assert_allclose(joint.integrate(q, np.zeros(joint.nv)), q, atol=1e-15)


def test_vector_joints_are_always_normalized() -> None:
    for joint in (fd.RevoluteJoint(), fd.PrismaticJoint(), fd.PlanarJoint()):
        q = np.full((2, joint.nq), 7.0)
        assert joint.is_normalized(q).shape == (2,) and joint.is_normalized(q).all()
        np.testing.assert_array_equal(joint.normalize(q), q)


def test_revolute_difference_does_not_wrap() -> None:
    """As Pinocchio's bounded revolute joints: difference is q1 − q0, even beyond 2π."""
    joint = fd.RevoluteJoint()
    assert joint.difference([0.0], [7.0])[0] == 7.0
    assert joint.integrate([3.0], [4.0])[0] == 7.0


def test_planar_difference_takes_the_short_way() -> None:
    joint = fd.PlanarJoint()
    v = joint.difference([0.0, 0.0, 3.0], [0.0, 0.0, -3.0])
    assert v[0] == pytest.approx(2 * np.pi - 6.0)


def test_integrate_broadcasts_q_and_v() -> None:
    joint = fd.FreeFlyerJoint()
    rng = np.random.default_rng(SEED + 10)
    q = random_q(joint, rng)
    v = rng.uniform(-1, 1, (4, 6))
    out = joint.integrate(q, v)
    assert out.shape == (4, 7)
    for k in range(4):
        np.testing.assert_allclose(out[k], joint.integrate(q, v[k]), atol=1e-15)


@pytest.mark.parametrize(
    ("joint", "lower", "upper"),
    [
        (fd.RevoluteJoint(), [-0.5], [0.25]),
        (fd.RevoluteJoint(), [-np.inf], [np.inf]),
        (fd.RevoluteJoint(), [-np.inf], [-5.0]),  # half-infinite, away from [−π, π]
        (fd.RevoluteJoint(), [4.0], [np.inf]),
        (fd.PrismaticJoint(), [-np.inf], [np.inf]),
        (fd.PrismaticJoint(), [0.1], [0.2]),
        (fd.PlanarJoint(), [-np.inf] * 3, [np.inf] * 3),
        (fd.PlanarJoint(), [-3.0, 0.0, -0.1], [-2.0, 5.0, 0.1]),
        (fd.FreeFlyerJoint(), [-np.inf] * 7, [np.inf] * 7),
        (fd.FreeFlyerJoint(), [-5, 2, 0] + [-np.inf] * 4, [-4, 3, 0.5] + [np.inf] * 4),
    ],
    ids=lambda x: repr(x) if isinstance(x, fd.Joint) else None,
)
def test_random_within_limits(joint: fd.Joint, lower: list[float], upper: list[float]) -> None:
    lo, hi = np.array(lower, dtype=float), np.array(upper, dtype=float)
    q = joint.random(np.random.default_rng(SEED), lo, hi, size=500)
    assert q.shape == (500, joint.nq)
    assert np.all(np.isfinite(q))
    # the defaults where unbounded: angles in [−π, π], lengths in [−1, 1]
    angle = {fd.RevoluteJoint: [True], fd.PrismaticJoint: [False], fd.PlanarJoint: [False, False, True]}
    for k in range(joint.nq if not isinstance(joint, fd.FreeFlyerJoint) else 3):
        col = q[:, k]
        assert np.all(col >= lo[k]) and np.all(col <= hi[k]), f"coordinate {k} out of [{lo[k]}, {hi[k]}]"
        if not np.isfinite(lo[k]) and not np.isfinite(hi[k]):
            bound = np.pi if angle.get(type(joint), [False] * 3)[k] else 1.0
            assert np.all(np.abs(col) <= bound)
            assert col.max() - col.min() > bound  # actually spread out
    if isinstance(joint, fd.FreeFlyerJoint):
        np.testing.assert_allclose(np.linalg.norm(q[:, 3:], axis=-1), 1.0, atol=1e-14)


def test_random_accepts_seed_generator_and_none() -> None:
    joint = fd.SphericalJoint()
    a = joint.random(7, size=3)
    b = joint.random(np.random.default_rng(7), size=3)
    np.testing.assert_array_equal(a, b)
    assert joint.random().shape == (4,)
    assert joint.random(None, size=(2, 5)).shape == (2, 5, 4)


# --------------------------------------------------------------------------
# axes
# --------------------------------------------------------------------------


@pytest.mark.parametrize("cls", [fd.RevoluteJoint, fd.PrismaticJoint, fd.PlanarJoint])
def test_non_unit_axis_is_normalised_with_a_warning(cls: type) -> None:
    with pytest.warns(PhysicalityWarning, match="length 2"):
        joint = cls([0.0, 0.0, 2.0])
    np.testing.assert_array_equal(joint._params()[0], [0.0, 0.0, 1.0])
    with pytest.warns(PhysicalityWarning) as record:
        cls([0.0, 0.7, 0.7])
    assert record[0].filename == __file__  # the warning points at the caller


@pytest.mark.parametrize("cls", [fd.RevoluteJoint, fd.PrismaticJoint, fd.PlanarJoint])
def test_zero_or_malformed_axis_raises(cls: type) -> None:
    with pytest.raises(ModelError, match="zero-length"):
        cls([0.0, 0.0, 0.0])
    with pytest.raises(ShapeError):
        cls([0.0, 1.0])
    with pytest.raises(ModelError, match="single axis"):
        cls([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    with pytest.raises(ValueError):
        cls([0.0, np.nan, 1.0])


def test_negative_axis_is_kept() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        joint = fd.RevoluteJoint([0, 0, -1])
    np.testing.assert_array_equal(joint.axis, [0.0, 0.0, -1.0])
    np.testing.assert_allclose(joint.pose([0.3]).rotation, fd.RevoluteJoint().pose([-0.3]).rotation, atol=1e-15)
    np.testing.assert_array_equal(joint.S[:, 0], [0, 0, -1, 0, 0, 0])


def test_unit_axis_helper() -> None:
    np.testing.assert_array_equal(fd.joints.unit_axis([0, -1, 0]), [0.0, -1.0, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = fd.joints.unit_axis([0, 3, 4], warn=False)
    np.testing.assert_allclose(out, [0.0, 0.6, 0.8])
    assert not out.flags.writeable


# --------------------------------------------------------------------------
# values: equality, hashing, repr, SymPy
# --------------------------------------------------------------------------


def test_equality_and_hash() -> None:
    assert fd.RevoluteJoint() == fd.RevoluteJoint([0, 0, 1])
    assert fd.RevoluteJoint() != fd.RevoluteJoint([0, 0, -1])
    assert fd.RevoluteJoint() != fd.PrismaticJoint()
    assert fd.SphericalJoint() == fd.SphericalJoint()
    assert fd.PlanarJoint() != fd.PlanarJoint([1, 0, 0])
    assert len({fd.RevoluteJoint(), fd.RevoluteJoint(), fd.FreeFlyerJoint(), fd.FreeFlyerJoint()}) == 2
    assert "axis=[0.0, 0.0, 1.0]" in repr(fd.RevoluteJoint())
    assert (fd.RevoluteJoint.nq, fd.PrismaticJoint.nv, fd.SphericalJoint.nq, fd.FreeFlyerJoint.nv) == (1, 1, 4, 6)
    assert {j.kind for j in (fd.RevoluteJoint(), fd.FreeFlyerJoint(), fd.PlanarJoint())} == {
        "revolute",
        "free_flyer",
        "planar",
    }


def test_revolute_pose_with_a_sympy_symbol() -> None:
    sympy = pytest.importorskip("sympy")
    theta = sympy.Symbol("theta", real=True)
    joint = fd.RevoluteJoint(_AXIS)
    T = joint.pose(np.array([theta], dtype=object))
    assert T.rotation.dtype == object
    for value in (0.0, 0.7, -2.5):
        numeric = np.array(
            [[float(sympy.N(e.subs(theta, value))) for e in row] for row in T.rotation], dtype=np.float64
        )
        assert_close(numeric, joint.pose([value]).rotation, "symbolic revolute pose", where=f"θ = {value}")
    np.testing.assert_array_equal(np.asarray(T.translation, dtype=float), np.zeros(3))


def test_prismatic_pose_with_a_sympy_symbol() -> None:
    sympy = pytest.importorskip("sympy")
    d = sympy.Symbol("d", real=True)
    T = fd.PrismaticJoint([0, 1, 0]).pose(np.array([d], dtype=object))
    assert [sympy.simplify(e - x) for e, x in zip(T.translation, [0, d, 0], strict=True)] == [0, 0, 0]


def test_planar_difference_is_exact_at_small_angles() -> None:
    """Against a 40-digit reference: Pinocchio's SE(2) log loses up to ~5e-10 at angles ~1e-3; this does not."""
    mp = pytest.importorskip("mpmath")
    joint = fd.PlanarJoint()
    q0 = np.array([1.98176371, -1.47773413, 1.76555872])
    with mp.workdps(40):
        for dtheta in (1e-12, 1e-9, 7.0297e-4, 0.3, 3.1):
            q1 = np.array([0.50314723, 0.71566768, q0[2] + dtheta])
            th0, th1 = mp.mpf(q0[2]), mp.mpf(q1[2])
            w = th1 - th0
            c, s = mp.cos(th0), mp.sin(th0)
            gx, gy = mp.mpf(q1[0]) - mp.mpf(q0[0]), mp.mpf(q1[1]) - mp.mpf(q0[1])
            dx, dy = c * gx + s * gy, -s * gx + c * gy  # displacement in the frame of q0
            a, b = mp.sin(w) / w, (1 - mp.cos(w)) / w  # V(w) = [[a, -b], [b, a]]
            det = a * a + b * b
            exact = np.array([float(w), float((a * dx + b * dy) / det), float((-b * dx + a * dy) / det)])
            assert_close(joint.difference(q0, q1), exact, "planar difference", where=f"Δθ = {dtheta}", atol=1e-13)
