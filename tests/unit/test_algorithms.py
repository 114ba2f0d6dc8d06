"""Unit tests of the reference algorithms: input validation, singular mass matrices, tiny models.

Numerical agreement is tested elsewhere (``tests/reference`` against Pinocchio
and closed forms, ``tests/properties`` for identities); this file checks what
happens at the edges: wrong shapes, non-finite numbers, non-unit quaternions,
bad frames and references, unavailable backends, singular trees, and models
with one or no body.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from _models import random_inertia, random_placement, random_state, tree

import featherdyn as fd
from featherdyn.errors import SingularMassMatrixError
from featherdyn.testing import assert_close

MODEL = "free_branch"  # free-flyer root, spherical, planar, revolute joints
G = 9.81

# name -> (call(model, q, v, a), the arguments it validates, with the name each is reported under)
CALLS: dict[str, tuple[Callable[..., Any], tuple[str, ...]]] = {
    "forward_kinematics": (lambda m, q, v, a: fd.forward_kinematics(m, q, v, a), ("q", "v", "a")),
    "rnea": (lambda m, q, v, a: fd.rnea(m, q, v, a), ("q", "v", "a")),
    "crba": (lambda m, q, v, a: fd.crba(m, q), ("q",)),
    "aba": (lambda m, q, v, a: fd.aba(m, q, v, a), ("q", "v", "tau")),
    "nonlinear_effects": (lambda m, q, v, a: fd.nonlinear_effects(m, q, v), ("q", "v")),
    "generalized_gravity": (lambda m, q, v, a: fd.generalized_gravity(m, q), ("q",)),
    "coriolis_matrix": (lambda m, q, v, a: fd.coriolis_matrix(m, q, v), ("q", "v")),
    "joint_jacobians": (lambda m, q, v, a: fd.joint_jacobians(m, q), ("q",)),
    "frame_placement": (lambda m, q, v, a: fd.frame_placement(m, q, "b3_tool"), ("q",)),
    "frame_velocity": (lambda m, q, v, a: fd.frame_velocity(m, q, v, "b3_tool"), ("q", "v")),
    "frame_acceleration": (lambda m, q, v, a: fd.frame_acceleration(m, q, v, a, "b3_tool"), ("q", "v", "a")),
    "frame_classical_acceleration": (
        lambda m, q, v, a: fd.frame_classical_acceleration(m, q, v, a, "b3_tool", fd.WORLD), ("q", "v", "a")),
    "frame_jacobian": (lambda m, q, v, a: fd.frame_jacobian(m, q, "b3_tool", fd.WORLD), ("q",)),
    "frame_jacobian_time_variation": (
        lambda m, q, v, a: fd.frame_jacobian_time_variation(m, q, v, "b3_tool", fd.LOCAL_WORLD_ALIGNED), ("q", "v")),
    "kinetic_energy": (lambda m, q, v, a: fd.kinetic_energy(m, q, v), ("q", "v")),
    "potential_energy": (lambda m, q, v, a: fd.potential_energy(m, q), ("q",)),
    "center_of_mass": (lambda m, q, v, a: fd.center_of_mass(m, q, v), ("q", "v")),
    "centroidal_momentum_matrix": (lambda m, q, v, a: fd.centroidal_momentum_matrix(m, q), ("q",)),
    "centroidal_momentum": (lambda m, q, v, a: fd.centroidal_momentum(m, q, v), ("q", "v")),
}
ARG_CASES = [(fn, arg) for fn, (_, args) in CALLS.items() for arg in args]
POSITION = {"q": 0, "v": 1, "a": 2, "tau": 2}


def _inputs(model: fd.Model) -> list[np.ndarray]:
    s = random_state(model, 3)
    return [s.q, s.v, s.a]


def _call(fn: str, model: fd.Model, args: list[np.ndarray]) -> Any:
    return CALLS[fn][0](model, *args)


# ---------------------------------------------------------------------------------------------------------------
# shapes, finiteness, quaternions
# ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("fn", "arg"), ARG_CASES, ids=[f"{f}-{a}" for f, a in ARG_CASES])
def test_wrong_length_names_the_argument_and_the_expected_dimension(fn: str, arg: str) -> None:
    m = tree(MODEL)
    args = _inputs(m)
    k = POSITION[arg]
    args[k] = args[k][:-1]
    size = f"nq={m.nq}" if arg == "q" else f"nv={m.nv}"
    with pytest.raises(fd.ShapeError) as err:
        _call(fn, m, args)
    msg = str(err.value)
    assert msg.startswith(f"{arg}:"), msg
    assert f"trailing dimension {size}" in msg, msg
    assert str(tuple(args[k].shape)) in msg, msg


@pytest.mark.parametrize(("fn", "arg"), ARG_CASES, ids=[f"{f}-{a}" for f, a in ARG_CASES])
def test_non_finite_input_is_refused(fn: str, arg: str) -> None:
    m = tree(MODEL)
    args = _inputs(m)
    k = POSITION[arg]
    args[k] = args[k].copy()
    args[k][1] = np.nan if k != 1 else np.inf
    with pytest.raises(fd.NonFiniteError, match=rf"^{arg}: expected finite numbers"):
        _call(fn, m, args)


@pytest.mark.parametrize("fn", list(CALLS))
def test_a_scalar_q_is_a_shape_error(fn: str) -> None:
    m = tree(MODEL)
    args = _inputs(m)
    args[0] = np.float64(0.3)
    with pytest.raises(fd.ShapeError, match=rf"^q: expected trailing dimension nq={m.nq}, got shape \(\)"):
        _call(fn, m, args)


@pytest.mark.parametrize("fn", list(CALLS))
@pytest.mark.parametrize("kind", ["free_flyer", "spherical"])
def test_non_unit_quaternion_names_the_joint(fn: str, kind: str) -> None:
    m = tree(MODEL)
    i = next(k for k, j in enumerate(m.joints) if j.kind == kind)
    start = m.idx_q[i] + (3 if kind == "free_flyer" else 0)
    args = _inputs(m)
    args[0] = args[0].copy()
    args[0][start : start + 4] *= 1.001
    with pytest.raises(fd.QuaternionNormError) as err:
        _call(fn, m, args)
    assert repr(m.joint_names[i]) in str(err.value)


def test_a_quaternion_within_tolerance_is_accepted() -> None:
    m = tree(MODEL)
    q, v, a = _inputs(m)
    q = q.copy()
    q[3:7] *= 1 + 1e-9
    fd.rnea(m, q, v, a)


def test_batch_shapes_that_do_not_broadcast() -> None:
    m = tree(MODEL)
    s = random_state(m, 1, size=(3,))
    with pytest.raises(fd.ShapeError, match="batch shapes do not broadcast"):
        fd.rnea(m, s.q, s.v[:2], s.a)


def test_complex_input_is_a_dtype_error() -> None:
    m = tree(MODEL)
    q, v, a = _inputs(m)
    with pytest.raises(fd.DTypeError, match=r"^v:"):
        fd.rnea(m, q, v.astype(complex), a)


def test_model_argument_must_be_a_model() -> None:
    q, v, a = _inputs(tree(MODEL))
    with pytest.raises(fd.FeatherdynError, match=r"^model: expected a featherdyn Model"):
        fd.rnea("panda", q, v, a)


def test_accelerations_need_velocities() -> None:
    m = tree(MODEL)
    q, _, a = _inputs(m)
    with pytest.raises(fd.ShapeError, match=r"^a:"):
        fd.forward_kinematics(m, q, None, a)


# ---------------------------------------------------------------------------------------------------------------
# external forces
# ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("fn", [fd.rnea, fd.aba], ids=["rnea", "aba"])
@pytest.mark.parametrize("shape", [(8, 6), (9, 3), (6, 9), (54,)], ids=str)
def test_f_ext_of_the_wrong_shape(fn: Callable[..., Any], shape: tuple[int, ...]) -> None:
    m = tree(MODEL)
    assert m.nbodies == 9
    q, v, a = _inputs(m)
    with pytest.raises(fd.ShapeError) as err:
        fn(m, q, v, a, np.zeros(shape))
    msg = str(err.value)
    assert msg.startswith("f_ext:") and "nb=9, 6" in msg and str(shape) in msg, msg


@pytest.mark.parametrize("fn", [fd.rnea, fd.aba], ids=["rnea", "aba"])
def test_f_ext_batch_must_broadcast_with_the_state(fn: Callable[..., Any]) -> None:
    m = tree(MODEL)
    s = random_state(m, 2, size=(3,))
    with pytest.raises(fd.ShapeError, match=r"^f_ext: batch shape \(2,\)"):
        fn(m, s.q, s.v, s.a, s.f_ext[:2])
    # a batch of forces on one state broadcasts
    assert fn(m, s.q[0], s.v[0], s.a[0], s.f_ext).shape == (3, m.nv)


@pytest.mark.parametrize("fn", [fd.rnea, fd.aba], ids=["rnea", "aba"])
def test_f_ext_must_be_finite(fn: Callable[..., Any]) -> None:
    m = tree(MODEL)
    s = random_state(m, 2)
    f = s.f_ext.copy()
    f[4, 2] = np.nan
    with pytest.raises(fd.NonFiniteError, match=r"^f_ext:"):
        fn(m, s.q, s.v, s.a, f)


def test_zero_f_ext_changes_nothing() -> None:
    m = tree(MODEL)
    s = random_state(m, 2)
    zero = np.zeros((m.nbodies, 6))
    np.testing.assert_array_equal(fd.rnea(m, s.q, s.v, s.a, zero), fd.rnea(m, s.q, s.v, s.a))
    np.testing.assert_array_equal(fd.aba(m, s.q, s.v, s.tau, zero), fd.aba(m, s.q, s.v, s.tau))


# ---------------------------------------------------------------------------------------------------------------
# frames, references, backends
# ---------------------------------------------------------------------------------------------------------------

FRAME_CALLS: dict[str, Callable[..., Any]] = {
    "frame_placement": lambda m, s, f, r: fd.frame_placement(m, s.q, f),
    "frame_velocity": lambda m, s, f, r: fd.frame_velocity(m, s.q, s.v, f, r),
    "frame_acceleration": lambda m, s, f, r: fd.frame_acceleration(m, s.q, s.v, s.a, f, r),
    "frame_classical_acceleration": lambda m, s, f, r: fd.frame_classical_acceleration(m, s.q, s.v, s.a, f, r),
    "frame_jacobian": lambda m, s, f, r: fd.frame_jacobian(m, s.q, f, r),
    "frame_jacobian_time_variation": lambda m, s, f, r: fd.frame_jacobian_time_variation(m, s.q, s.v, f, r),
}


@pytest.mark.parametrize("fn", list(FRAME_CALLS))
def test_unknown_frame_name_is_a_model_error(fn: str) -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    with pytest.raises(fd.ModelError, match="'b3_tol' not found") as err:
        FRAME_CALLS[fn](m, s, "b3_tol", fd.LOCAL)
    assert "b3_tool" in str(err.value)  # the near miss is suggested


@pytest.mark.parametrize("fn", list(FRAME_CALLS))
def test_frame_index_out_of_range_or_of_the_wrong_type(fn: str) -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    with pytest.raises(fd.ModelError, match="out of range"):
        FRAME_CALLS[fn](m, s, len(m.frames), fd.LOCAL)
    with pytest.raises(fd.ModelError, match="out of range"):
        FRAME_CALLS[fn](m, s, -1, fd.LOCAL)
    with pytest.raises(fd.FeatherdynError, match=r"^frame:"):
        FRAME_CALLS[fn](m, s, 2.0, fd.LOCAL)


def test_frame_by_index_equals_frame_by_name() -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    k = m.frame_id("b5_tool")
    np.testing.assert_array_equal(fd.frame_jacobian(m, s.q, k, fd.WORLD), fd.frame_jacobian(m, s.q, "b5_tool", fd.WORLD))


@pytest.mark.parametrize("fn", [f for f in FRAME_CALLS if f != "frame_placement"])
@pytest.mark.parametrize("reference", ["sideways", 3, None, "LOCAL_WORLD"], ids=repr)
def test_bad_reference_is_refused(fn: str, reference: Any) -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    with pytest.raises(fd.FeatherdynError, match=r"^reference: expected fd\.LOCAL, fd\.WORLD or fd\.LOCAL_WORLD_ALIGNED"):
        FRAME_CALLS[fn](m, s, "b3_tool", reference)


def test_reference_names_as_strings() -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        # a name takes the general path, the enum the compiled core: equal to round-off
        np.testing.assert_allclose(fd.frame_jacobian(m, s.q, "b3_tool", ref.value),
                                   fd.frame_jacobian(m, s.q, "b3_tool", ref), rtol=1e-12, atol=1e-12)


def _with_backend(fn: str, m: fd.Model, s: Any, backend: str) -> Any:
    frame, ref = "b3_tool", fd.LOCAL
    table: dict[str, Callable[[], Any]] = {
        "forward_kinematics": lambda: fd.forward_kinematics(m, s.q, s.v, s.a, backend=backend),
        "rnea": lambda: fd.rnea(m, s.q, s.v, s.a, backend=backend),
        "crba": lambda: fd.crba(m, s.q, backend=backend),
        "aba": lambda: fd.aba(m, s.q, s.v, s.tau, backend=backend),
        "nonlinear_effects": lambda: fd.nonlinear_effects(m, s.q, s.v, backend=backend),
        "generalized_gravity": lambda: fd.generalized_gravity(m, s.q, backend=backend),
        "coriolis_matrix": lambda: fd.coriolis_matrix(m, s.q, s.v, backend=backend),
        "joint_jacobians": lambda: fd.joint_jacobians(m, s.q, backend=backend),
        "frame_placement": lambda: fd.frame_placement(m, s.q, frame, backend=backend),
        "frame_velocity": lambda: fd.frame_velocity(m, s.q, s.v, frame, ref, backend=backend),
        "frame_acceleration": lambda: fd.frame_acceleration(m, s.q, s.v, s.a, frame, ref, backend=backend),
        "frame_classical_acceleration":
            lambda: fd.frame_classical_acceleration(m, s.q, s.v, s.a, frame, ref, backend=backend),
        "frame_jacobian": lambda: fd.frame_jacobian(m, s.q, frame, ref, backend=backend),
        "frame_jacobian_time_variation":
            lambda: fd.frame_jacobian_time_variation(m, s.q, s.v, frame, ref, backend=backend),
        "kinetic_energy": lambda: fd.kinetic_energy(m, s.q, s.v, backend=backend),
        "potential_energy": lambda: fd.potential_energy(m, s.q, backend=backend),
        "center_of_mass": lambda: fd.center_of_mass(m, s.q, s.v, backend=backend),
        "centroidal_momentum_matrix": lambda: fd.centroidal_momentum_matrix(m, s.q, backend=backend),
        "centroidal_momentum": lambda: fd.centroidal_momentum(m, s.q, s.v, backend=backend),
    }
    return table[fn]()


def _compiled_available() -> bool:
    m = tree("revolute_chain")
    try:
        fd.rnea(m, np.zeros(m.nq), np.zeros(m.nv), np.zeros(m.nv), backend="compiled")
    except fd.FeatherdynError as exc:
        if "not available" in str(exc):
            return False
        raise
    return True


@pytest.mark.parametrize("fn", list(CALLS))
def test_compiled_backend_is_reported_unavailable_or_agrees(fn: str) -> None:
    """Until the compiled engine exists, ``backend='compiled'`` is a clear error; once it does, it agrees."""
    m = tree(MODEL)
    s = random_state(m, 0)
    if not _compiled_available():
        with pytest.raises(fd.FeatherdynError, match=r"backend='compiled'.*not available") as err:
            _with_backend(fn, m, s, "compiled")
        assert isinstance(err.value, ValueError)
        return
    compiled, reference = _flat_result(_with_backend(fn, m, s, "compiled")), _flat_result(_with_backend(fn, m, s, "reference"))
    for c, r in zip(compiled, reference, strict=True):
        assert_close(c, r, f"{fn}: compiled vs reference", scale=max(1.0, float(np.abs(r).max(initial=0.0))))


def _flat_result(x: Any) -> list[np.ndarray]:
    if isinstance(x, fd.Kinematics):
        return [x.placements.homogeneous(), x.velocities.vector, x.accelerations.vector]
    if isinstance(x, fd.CenterOfMass):
        return [x.position, x.velocity]
    if isinstance(x, fd.PluckerTransform):
        return [x.homogeneous()]
    return [np.asarray(getattr(x, "vector", x))]


@pytest.mark.parametrize("fn", ["rnea", "crba", "aba", "frame_jacobian", "centroidal_momentum"])
def test_unknown_backend_is_refused_and_reference_works(fn: str) -> None:
    m = tree(MODEL)
    s = random_state(m, 0)
    with pytest.raises(fd.FeatherdynError, match=r"^backend: expected None, 'reference' or 'compiled', got 'numba'"):
        _with_backend(fn, m, s, "numba")
    out, default = _flat_result(_with_backend(fn, m, s, "reference")), _flat_result(_with_backend(fn, m, s, None))
    for a, b in zip(out, default, strict=True):
        assert_close(a, b, f"{fn}: backend='reference' vs default", scale=max(1.0, float(np.abs(b).max(initial=0.0))))


# ---------------------------------------------------------------------------------------------------------------
# singular mass matrices
# ---------------------------------------------------------------------------------------------------------------


def _build(bodies: list[tuple[str, int, fd.Joint, Any, Any]], name: str = "singular") -> fd.Model:
    b = fd.ModelBuilder(name)
    for body, parent, joint, placement, inertia in bodies:
        b.add_body(body, parent, joint, placement=placement, inertia=inertia)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fd.PhysicalityWarning)
        return b.build()


def _singular_models() -> dict[str, tuple[fd.Model, str]]:
    """Trees whose mass matrix is singular at every configuration, and the joint to blame."""
    rng = np.random.default_rng(4)
    base = ("base", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), None, random_inertia(rng))
    return {
        "massless prismatic leaf": (
            _build([base, ("ghost", 0, fd.PrismaticJoint([1.0, 0.0, 0.0]), random_placement(rng), None)]),
            "ghost_joint"),
        "massless revolute leaf under a free-flyer": (
            _build([("trunk", -1, fd.FreeFlyerJoint(), None, random_inertia(rng)),
                    ("arm", 0, fd.SphericalJoint(), random_placement(rng), random_inertia(rng)),
                    ("finger", 1, fd.RevoluteJoint([0.0, 1.0, 0.0]), random_placement(rng), None)]),
            "finger_joint"),
        # mass but no inertia the joint can move: a point mass on the revolute axis (no build warning for this one)
        "point mass on the joint axis": (
            _build([base, ("bead", 0, fd.RevoluteJoint([0.0, 0.0, 1.0]), random_placement(rng),
                           fd.SpatialInertia.point_mass(1.5, [0.0, 0.0, 0.4]))]),
            "bead_joint"),
        "point mass at the centre of a spherical joint": (
            _build([base, ("ball", 0, fd.SphericalJoint(), random_placement(rng),
                           fd.SpatialInertia.point_mass(1.5, [0.0, 0.0, 0.0]))]),
            "ball_joint"),
        # rank-deficient, not zero: a point mass off the centre cannot be spun about the line to the centre
        "point mass off the centre of a spherical joint": (
            _build([base, ("pendulum", 0, fd.SphericalJoint(), random_placement(rng),
                           fd.SpatialInertia.point_mass(1.5, [0.0, 0.0, -0.5]))]),
            "pendulum_joint"),
    }


SINGULAR = _singular_models()


@pytest.mark.parametrize("case", list(SINGULAR))
def test_aba_names_the_joint_of_a_singular_mass_matrix(case: str) -> None:
    m, joint = SINGULAR[case]
    s = random_state(m, 8)
    eig = np.linalg.eigvalsh(fd.crba(m, s.q))
    assert abs(eig[0]) < 1e-12 * eig[-1], f"{case}: the test model is not singular ({eig})"
    with pytest.raises(SingularMassMatrixError) as err:
        fd.aba(m, s.q, s.v, s.tau)
    assert repr(joint) in str(err.value)
    assert isinstance(err.value, ValueError)
    # also in a batch, and with gravity off: never NaN
    sb = random_state(m, 9, size=(4,))
    with pytest.raises(SingularMassMatrixError, match=repr(joint)):
        fd.aba(m, sb.q, sb.v, sb.tau, gravity=False)


def test_configuration_dependent_singularity() -> None:
    """A massless link carrying a point mass that sits on the first axis when ``q₂ = 0``.

    Joint 1 (about z) moves nothing then; at any other ``q₂`` the matrix is regular.
    """
    m = _build([
        ("link", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), None, None),
        ("bob", 0, fd.RevoluteJoint([1.0, 0.0, 0.0]), None, fd.SpatialInertia.point_mass(2.0, [0.0, 0.0, 0.3])),
    ])
    v, tau = np.array([0.2, -0.4]), np.array([0.5, 0.1])
    with pytest.raises(SingularMassMatrixError, match="'link_joint'"):
        fd.aba(m, [0.7, 0.0], v, tau)
    with pytest.raises(SingularMassMatrixError, match="'link_joint'"):  # one singular element spoils the batch
        fd.aba(m, [[0.7, 0.5], [0.7, 0.0]], v, tau)
    q = np.array([0.7, 0.5])
    # closed form: M = diag(m (0.3 sin q₂)², m 0.3²)
    M = np.diag([2.0 * (0.3 * np.sin(0.5)) ** 2, 2.0 * 0.09])
    assert_close(fd.crba(m, q), M, "crba of the bob")
    ddq = fd.aba(m, q, v, tau)
    assert np.all(np.isfinite(ddq))
    assert_close(ddq, np.linalg.solve(M, tau - fd.nonlinear_effects(m, q, v)), "aba of the bob")


def test_massless_subtree_warns_at_build_time() -> None:
    b = fd.ModelBuilder("warn")
    b.add_body("base", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), inertia=fd.SpatialInertia.box(1.0, [0.1, 0.2, 0.3]))
    b.add_body("ghost", 0, fd.PrismaticJoint([1.0, 0.0, 0.0]))
    with pytest.warns(fd.PhysicalityWarning, match="'ghost_joint'"):
        b.build()


def test_a_massless_body_with_a_massive_child_is_not_singular() -> None:
    rng = np.random.default_rng(5)
    m = _build([
        ("hip", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]), None, None),
        ("thigh", 0, fd.RevoluteJoint([1.0, 0.0, 0.0]), random_placement(rng), random_inertia(rng)),
    ])
    s = random_state(m, 1)
    ddq = fd.aba(m, s.q, s.v, s.tau)
    assert_close(ddq, np.linalg.solve(fd.crba(m, s.q), s.tau - fd.nonlinear_effects(m, s.q, s.v)), "aba")


# ---------------------------------------------------------------------------------------------------------------
# one body, no body
# ---------------------------------------------------------------------------------------------------------------


def test_single_revolute_pendulum(ref: Any) -> None:
    """One body on a revolute joint about z, gravity along −y: the pendulum's closed form."""
    mass, d, Izz = 1.7, 0.45, 0.08
    b = fd.ModelBuilder("pendulum", gravity=(0.0, -G, 0.0))
    b.add_body("bob", -1, fd.RevoluteJoint([0.0, 0.0, 1.0]),
               inertia=fd.SpatialInertia(mass, [d, 0.0, 0.0], np.diag([0.01, 0.09, Izz])))
    m = b.build()
    q, v, a = np.array([0.6]), np.array([-1.3]), np.array([2.1])
    J = Izz + mass * d * d
    torque = J * a + mass * G * d * np.cos(q)
    assert_close(fd.crba(m, q), [[J]], "pendulum M")
    assert_close(fd.rnea(m, q, v, a), torque, "pendulum τ")
    assert_close(fd.generalized_gravity(m, q), mass * G * d * np.cos(q), "pendulum g")
    assert_close(fd.coriolis_matrix(m, q, v), [[0.0]], "pendulum C")
    assert_close(fd.aba(m, q, v, torque), a, "pendulum q̈")
    assert_close(fd.kinetic_energy(m, q, v), 0.5 * J * v[0] ** 2, "pendulum T")
    assert_close(fd.potential_energy(m, q), mass * G * d * np.sin(q[0]), "pendulum U")
    assert_close(fd.center_of_mass(m, q), [d * np.cos(q[0]), d * np.sin(q[0]), 0.0], "pendulum CoM")


def test_single_free_body(ref: Any) -> None:
    """One free-flying body: M is its spatial inertia; at rest with τ = 0 it falls, ``q̈ = [0; Rᵀ g]``."""
    rng = np.random.default_rng(11)
    I = random_inertia(rng)
    b = fd.ModelBuilder("free body")
    b.add_body("body", -1, fd.FreeFlyerJoint(), inertia=I)
    m = b.build()
    q = fd.FreeFlyerJoint().random(rng)
    R = fd.frame_placement(m, q, "body").rotation
    assert_close(fd.crba(m, q), ref.inertia(I.mass, I.com, I.inertia_com), "free body M = spatial inertia")
    ddq = fd.aba(m, q, np.zeros(6), np.zeros(6))
    g_body = R.T @ np.array([0.0, 0.0, -G])
    assert_close(ddq, np.concatenate([np.zeros(3), g_body]), "free fall: q̈ = [0; Rᵀ g]")
    assert_close(fd.rnea(m, q, np.zeros(6), ddq), np.zeros(6), "free fall needs no force", scale=G)
    # supporting it against gravity takes exactly its weight, applied at the centre of mass
    weight = -I.mass * g_body
    assert_close(fd.generalized_gravity(m, q), np.concatenate([np.cross(I.com, weight), weight]), "free body g")


def test_a_model_without_bodies() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = fd.ModelBuilder("empty").build()
    assert (m.nq, m.nv, m.nbodies) == (0, 0, 0)
    q, v = np.zeros(0), np.zeros(0)
    assert fd.rnea(m, q, v, v).shape == (0,)
    assert fd.crba(m, q).shape == (0, 0)
    assert fd.aba(m, q, v, v).shape == (0,)
    assert fd.rnea(m, np.zeros((3, 0)), v, v).shape == (3, 0)
    assert float(fd.kinetic_energy(m, q, v)) == 0.0
    assert float(fd.potential_energy(m, q)) == 0.0
    with pytest.raises(fd.ModelError, match="no mass"):
        fd.center_of_mass(m, q)
