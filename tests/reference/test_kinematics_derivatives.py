"""``fd.kinematics_derivatives``, ``fd.center_of_mass_derivatives``, ``fd.centroidal_dynamics_derivatives``.

Against Pinocchio 4's ``computeForwardKinematicsDerivatives`` + ``get{Frame,Point}*Derivatives``,
``jacobianCenterOfMass``, ``getCenterOfMassVelocityDerivatives`` and ``computeCentroidalDynamicsDerivatives``
(joints mapped by name, rows ``[v; ω]`` / ``[p; k]`` swapped, the free-flyer's columns converted), against
central differences of featherdyn's own functions along ``fd.integrate``'s tangent, the core against the
reference, and the point path (batches, dtypes, bad input). The declared front ends (one state, batches, Dask,
``fd.compile``): ``test_declared_front_ends.py``. The equations: ``docs/derivatives.md``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pytest
from _models import TREES, library_robot, pinocchio_pair, tree

import featherdyn as fd
from featherdyn.model import FrameInfo

ROBOTS = [("panda", False, "panda_hand"), ("ur5_robot", False, "tool0"), ("solo12", True, "FL_FOOT"),
          ("talos_full_v2", True, "gripper_left_fingertip_3_link")]
REFS = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)
POINT = np.array([0.05, -0.12, 0.2])


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


def _state(model: fd.Model, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)


def _central(f: Callable[[np.ndarray], np.ndarray], model: fd.Model, x: np.ndarray, on_q: bool,
             eps: float = 1e-6) -> np.ndarray:
    """Central differences of ``f`` `(rows,)` at ``x``: along the tangent of fd.integrate for q, plainly else."""
    cols = []
    for j in range(model.nv):
        step = np.zeros(model.nv)
        step[j] = eps
        plus, minus = (fd.integrate(model, x, step), fd.integrate(model, x, -step)) if on_q else (x + step, x - step)
        cols.append((f(plus) - f(minus)) / (2 * eps))
    return np.stack(cols, axis=-1)


def _with_frame_at(model: fd.Model, frame: str, point: np.ndarray) -> fd.Model:
    """The model with one more frame, ``frame`` moved to ``point`` (its coordinates), its orientation kept."""
    f = model.frames[model.resolve_frame(frame)]
    moved = f.placement @ fd.PluckerTransform(np.eye(3), point)
    return dataclasses.replace(model, frames=(*model.frames, FrameInfo("moved_frame", f.body, moved, "link")))


# ---------------------------------------------------------------------------------------------------------
# Pinocchio
# ---------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("backend", [None, "reference"])
@pytest.mark.parametrize(("name", "floating", "frame"), ROBOTS)
def test_against_pinocchio(name: str, floating: bool, frame: str, backend: str | None) -> None:
    pin = pytest.importorskip("pinocchio")
    model, pm, pd, jm = pinocchio_pair(name, floating)
    q, v, a = _state(model, 5)
    qp, vp, ap = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a)

    def ours(m_pin: np.ndarray) -> np.ndarray:  # rows [v; ω] (or [p; k]) → [ω; v], columns to featherdyn's dofs
        m_pin = np.asarray(m_pin).copy()
        return jm.columns_from_pin(np.concatenate([m_pin[3:], m_pin[:3]]) if m_pin.shape[0] == 6 else m_pin)

    def check(x: np.ndarray, y: np.ndarray, what: str) -> None:
        assert _rel(x, y) < 1e-8, (name, what, _rel(x, y))

    # the centroidal momentum about the centre of mass and its rate (Pinocchio: rows [p; k])
    c = fd.centroidal_dynamics_derivatives(model, q, v, a, backend=backend)
    pc = [ours(x) for x in pin.computeCentroidalDynamicsDerivatives(pm, pd, qp, vp, ap)]
    for field, y in zip(c._fields, pc, strict=True):
        check(getattr(c, field), y, field)
    assert np.abs(c.dhdot_dq).max() > 1e-3 and np.abs(c.dh_dq).max() > 1e-3  # not trivially zero
    # the centre of mass: its Jacobian and its velocity's derivative
    dc_dq, dcdot_dq = fd.center_of_mass_derivatives(model, q, v, backend=backend)
    check(dc_dq, jm.columns_from_pin(pin.jacobianCenterOfMass(pm, pd, qp).copy()), "dc_dq")
    pin.centerOfMass(pm, pd, qp, vp)
    check(dcdot_dq, jm.columns_from_pin(pin.getCenterOfMassVelocityDerivatives(pm, pd).copy()), "dcdot_dq")
    # a frame and a point of it
    pin.computeForwardKinematicsDerivatives(pm, pd, qp, vp, ap)
    fid = pm.getFrameId(frame)
    F = pm.frames[fid]
    pin.updateFramePlacements(pm, pd)  # the same frame on both sides
    assert _rel(fd.frame_placement(model, q, frame).translation, pd.oMf[fid].translation) < 1e-12
    for ref, pref in zip(REFS, (pin.LOCAL, pin.WORLD, pin.LOCAL_WORLD_ALIGNED), strict=True):
        k = fd.kinematics_derivatives(model, q, v, a, frame, ref, backend=backend)
        pv = [ours(x) for x in pin.getFrameVelocityDerivatives(pm, pd, fid, pref)]
        pa = [ours(x) for x in pin.getFrameAccelerationDerivatives(pm, pd, fid, pref)]
        if ref is fd.LOCAL_WORLD_ALIGNED:  # Pinocchio keeps the frame's origin fixed (docs/derivatives.md)
            J, w = k.dv_dv, fd.frame_velocity(model, q, v, frame, ref).vector[:3]
            wdot = fd.frame_acceleration(model, q, v, a, frame, ref).vector[:3]
            pv[0][3:] += np.cross(w, J[3:].T).T
            pa[1][3:] += np.cross(wdot, J[3:].T).T
        label = ref.name
        check(k.dv_dq, pv[0], f"{label} dv_dq")
        check(k.dv_dv, pv[1], f"{label} dv_dv")
        check(k.da_dq, pa[1], f"{label} da_dq")
        check(k.da_dv, pa[2], f"{label} da_dv")
        check(k.da_da, pa[3], f"{label} da_da")
        check(k.dac_da, pa[3], f"{label} dac_da")
        if ref is fd.WORLD:
            continue
        # a point: Pinocchio's point derivatives are the linear rows (the true derivatives, in LWA too)
        kp = fd.kinematics_derivatives(model, q, v, a, frame, ref, POINT, backend=backend)
        place = F.placement * pin.SE3(np.eye(3), POINT)
        pvp = pin.getPointVelocityDerivatives(pm, pd, F.parentJoint, place, pref)
        pcl = pin.getPointClassicAccelerationDerivatives(pm, pd, F.parentJoint, place, pref)
        check(kp.dv_dq[3:], jm.columns_from_pin(pvp[0].copy()), f"{label} point dv_dq")
        check(kp.dv_dv[3:], jm.columns_from_pin(pvp[1].copy()), f"{label} point dv_dv")
        check(kp.dac_dq[3:], jm.columns_from_pin(pcl[1].copy()), f"{label} point dac_dq")
        check(kp.dac_dv[3:], jm.columns_from_pin(pcl[2].copy()), f"{label} point dac_dv")
        check(kp.dac_da[3:], jm.columns_from_pin(pcl[3].copy()), f"{label} point dac_da")
        assert _rel(kp.dv_dq, k.dv_dq) > 1e-4  # the point moved something


# ---------------------------------------------------------------------------------------------------------
# central differences of featherdyn's own functions
# ---------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize(("name", "floating", "frame"), [ROBOTS[0], ROBOTS[2]])
@pytest.mark.parametrize("at_point", [False, True])
def test_kinematics_derivatives_are_central_differences(name: str, floating: bool, frame: str,
                                                        at_point: bool) -> None:
    """Each field against fd.frame_velocity / frame_acceleration / frame_classical_acceleration; with a point,
    those of a frame added at that point."""
    model = library_robot(name, floating)
    assert model is not None
    q, v, a = _state(model, 21)
    target, point = (_with_frame_at(model, frame, POINT), POINT) if at_point else (model, None)
    tf = "moved_frame" if at_point else frame
    for ref in REFS:
        k = fd.kinematics_derivatives(model, q, v, a, frame, ref, point)

        def values(qq: np.ndarray, vv: np.ndarray, aa: np.ndarray, ref: fd.ReferenceFrame = ref) -> np.ndarray:
            return np.concatenate([fd.frame_velocity(target, qq, vv, tf, ref).vector,
                                   fd.frame_acceleration(target, qq, vv, aa, tf, ref).vector,
                                   fd.frame_classical_acceleration(target, qq, vv, aa, tf, ref).vector])

        dq = _central(lambda x: values(x, v, a), model, q, True)
        dv = _central(lambda x: values(q, x, a), model, v, False)
        da = _central(lambda x: values(q, v, x), model, a, False)
        fields = {"dv_dq": dq[:6], "dv_dv": dv[:6], "da_dq": dq[6:12], "da_dv": dv[6:12], "da_da": da[6:12],
                  "dac_dq": dq[12:], "dac_dv": dv[12:], "dac_da": da[12:]}
        for field, expected in fields.items():
            assert _rel(getattr(k, field), expected) < 1e-6, (name, ref.name, field, _rel(getattr(k, field), expected))
        assert np.abs(k.dac_dq - k.da_dq).max() > 1e-3  # the classical part is not the spatial one


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True)])
def test_center_of_mass_derivatives_are_central_differences(name: str, floating: bool) -> None:
    model = library_robot(name, floating)
    assert model is not None
    q, v, _ = _state(model, 22)
    d = fd.center_of_mass_derivatives(model, q, v)
    assert _rel(d.dc_dq, _central(lambda x: fd.center_of_mass(model, x), model, q, True)) < 1e-7
    assert _rel(d.dcdot_dq, _central(lambda x: fd.center_of_mass(model, x, v).velocity, model, q, True)) < 1e-7
    # ∂ċ/∂q̇ = ∂c/∂q: ċ is linear in q̇
    assert _rel(d.dc_dq, _central(lambda x: fd.center_of_mass(model, q, x).velocity, model, v, False)) < 1e-7
    dc, dcd = d  # unpacks as the pair
    assert dc is d.dc_dq and dcd is d.dcdot_dq


def _momentum_rate(model: fd.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float = 1e-5) -> np.ndarray:
    """ḣ_G: the time derivative of fd.centroidal_momentum along q ⊕ (τ v + ½ τ² a) with velocity v + τ a."""
    def h(tau: float) -> np.ndarray:
        return fd.centroidal_momentum(model, fd.integrate(model, q, tau * v + 0.5 * tau * tau * a), v + tau * a).vector
    return (h(t) - h(-t)) / (2 * t)


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True)])
def test_centroidal_dynamics_derivatives_are_central_differences(name: str, floating: bool) -> None:
    model = library_robot(name, floating)
    assert model is not None
    q, v, a = _state(model, 23)
    c = fd.centroidal_dynamics_derivatives(model, q, v, a)
    assert _rel(c.dh_dq, _central(lambda x: fd.centroidal_momentum(model, x, v).vector, model, q, True)) < 1e-7
    A = fd.centroidal_momentum_matrix(model, q)
    assert _rel(c.dhdot_da, A) < 1e-12
    # the rate itself along a motion is ∂h/∂q q̇ + A q̈ (the time derivative of h_G, about the moving CoM)
    assert _rel(c.dh_dq @ v + A @ a, _momentum_rate(model, q, v, a)) < 1e-7

    def rate(qq: np.ndarray, vv: np.ndarray, aa: np.ndarray) -> np.ndarray:
        r = fd.centroidal_dynamics_derivatives(model, qq, vv, aa)
        return r.dh_dq @ vv + r.dhdot_da @ aa

    assert _rel(c.dhdot_dq, _central(lambda x: rate(x, v, a), model, q, True)) < 1e-6
    assert _rel(c.dhdot_dv, _central(lambda x: rate(q, x, a), model, v, False)) < 1e-6
    # and the rate of featherdyn's own h by time differences, differentiated in v (two nested differences)
    dv = _central(lambda x: _momentum_rate(model, q, x, a), model, v, False, eps=1e-4)
    assert _rel(c.dhdot_dv, dv) < 1e-5


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_every_joint_type_against_central_differences(spec) -> None:  # type: ignore[no-untyped-def]
    """Random trees with revolute, prismatic, spherical, planar and free-flyer joints (branches too): the three
    functions' q-derivatives against central differences, the core and the reference alike."""
    model = tree(spec.name)
    q, v, a = _state(model, 24)
    frame = model.frames[-1].name
    moved = _with_frame_at(model, frame, POINT)
    for backend in (None, "reference"):
        k = fd.kinematics_derivatives(model, q, v, a, frame, fd.LOCAL_WORLD_ALIGNED, POINT, backend=backend)
        dq = _central(lambda x: fd.frame_classical_acceleration(moved, x, v, a, "moved_frame",
                                                                 fd.LOCAL_WORLD_ALIGNED).vector, model, q, True)
        assert _rel(k.dac_dq, dq) < 1e-6, (spec.name, backend, _rel(k.dac_dq, dq))
        d = fd.center_of_mass_derivatives(model, q, v, backend=backend)
        assert _rel(d.dcdot_dq, _central(lambda x: fd.center_of_mass(model, x, v).velocity, model, q, True)) < 1e-6
        c = fd.centroidal_dynamics_derivatives(model, q, v, a, backend=backend)
        assert _rel(c.dh_dq, _central(lambda x: fd.centroidal_momentum(model, x, v).vector, model, q, True)) < 1e-6
        assert _rel(c.dh_dq @ v + c.dhdot_da @ a, _momentum_rate(model, q, v, a)) < 1e-6


# ---------------------------------------------------------------------------------------------------------
# core == reference, the point path's front ends
# ---------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize(("name", "floating", "frame"), [ROBOTS[0], ROBOTS[3]])
def test_core_equals_reference(name: str, floating: bool, frame: str) -> None:
    model = library_robot(name, floating)
    assert model is not None
    rng = np.random.default_rng(31)
    Q = fd.random_configuration(model, rng, size=(3,))
    V, A = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    P = rng.normal(size=(3, 3)) * 0.1
    calls = [lambda b: fd.center_of_mass_derivatives(model, Q, V, backend=b),
             lambda b: fd.centroidal_dynamics_derivatives(model, Q, V, A, backend=b)]
    for ref in REFS:
        calls.append(lambda b, ref=ref: fd.kinematics_derivatives(model, Q, V, A, frame, ref, backend=b))
        calls.append(lambda b, ref=ref: fd.kinematics_derivatives(model, Q, V, A, frame, ref, P, backend=b))
    for call in calls:
        core, ref_ = call(None), call("reference")
        assert type(core) is type(ref_)
        for x, y in zip(core, ref_, strict=True):
            assert x.shape == y.shape and x.dtype == np.float64
            assert _rel(x, y) < 1e-11


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_batches_in_simd_lanes_equal_the_one_state_calls(spec) -> None:  # type: ignore[no-untyped-def]
    """A batch of 11 states (groups of the SIMD width and a remainder row by row) equals the one-state calls bit
    for bit: the frame's derivatives in each reference, the centre of mass's and the centroidal ones, on trees with
    every joint kind. (The group kernels are the one-state templates on Packs: simd_groups.hpp.)"""
    model = tree(spec.name)
    rng = np.random.default_rng(33)
    Q = fd.random_configuration(model, rng, size=(11,))
    V, A = rng.normal(size=(11, model.nv)), rng.normal(size=(11, model.nv))
    frame = model.frames[-1].name
    calls: list[Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, ...]]] = [
        lambda q, v, a: tuple(fd.center_of_mass_derivatives(model, q, v)),
        lambda q, v, a: tuple(fd.centroidal_dynamics_derivatives(model, q, v, a))]
    calls += [lambda q, v, a, ref=ref: tuple(fd.kinematics_derivatives(model, q, v, a, frame, ref)) for ref in REFS]
    for call in calls:
        batch = call(Q, V, A)
        assert all(np.isfinite(x).all() and x.shape[0] == 11 for x in batch)
        for k in range(11):
            assert all(np.array_equal(x[k], y) for x, y in zip(batch, call(Q[k], V[k], A[k]), strict=True)), k


def test_point_batches_broadcast_and_equal_the_loop() -> None:
    model = library_robot("solo12", True)
    assert model is not None
    rng = np.random.default_rng(32)
    Q = fd.random_configuration(model, rng, size=(2, 3))
    V, A = rng.normal(size=(2, 3, model.nv)), rng.normal(size=(model.nv,))
    P = rng.normal(size=(3, 3)) * 0.1  # broadcast against (2, 3)
    for ref in REFS:
        batch = fd.kinematics_derivatives(model, Q, V, A, "HR_FOOT", ref, P)
        assert all(x.shape == (2, 3, 6, model.nv) for x in batch)
        for i in range(2):
            for j in range(3):
                one = fd.kinematics_derivatives(model, Q[i, j], V[i, j], A, "HR_FOOT", ref, P[j])
                assert all(np.array_equal(x[i, j], y) for x, y in zip(batch, one, strict=True))
    # one state, a batch of points: the state broadcast (both backends)
    for backend in (None, "reference"):
        points = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.LOCAL_WORLD_ALIGNED, P,
                                           backend=backend)
        assert points.dac_dq.shape == (3, 6, model.nv)
        one = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.LOCAL_WORLD_ALIGNED, P[1],
                                        backend=backend)
        assert all(_rel(x[1], y) < 1e-14 for x, y in zip(points, one, strict=True))
    # the point's own float32 stays float32 (the reference), as the state's does
    r32 = fd.kinematics_derivatives(model, Q[0, 0].astype(np.float32), V[0, 0].astype(np.float32),
                                    A.astype(np.float32), "HR_FOOT", fd.LOCAL, P[0].astype(np.float32))
    r64 = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.LOCAL, P[0])
    assert all(x.dtype == np.float32 for x in r32) and max(_rel(x, y) for x, y in zip(r32, r64, strict=True)) < 1e-3
    # the point at the frame's origin is the frame; a frame index works as its name
    origin = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, model.resolve_frame("HR_FOOT"), fd.LOCAL,
                                       np.zeros(3))
    frame = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.LOCAL)
    assert all(_rel(x, y) < 1e-14 for x, y in zip(origin, frame, strict=True))
    # the core's kernel of the point, as featherdyn.core declares it
    core = fd.core.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.WORLD, P[0])
    public = fd.kinematics_derivatives(model, Q[0, 0], V[0, 0], A, "HR_FOOT", fd.WORLD, P[0])
    assert np.array_equal(core[0], public.dv_dq) and np.array_equal(core[6], public.dac_dv) and np.array_equal(core[4], public.dv_dv)


def test_an_out_over_the_point_gets_the_result_without_out() -> None:
    """out= that shares memory with the point (one state, the core's one-state call; a batch, its rows): the one
    rule, the result computed as if it did not, then written."""
    model = library_robot("solo12", True)
    assert model is not None
    q, v, a = _state(model, 35)
    expected = fd.kinematics_derivatives(model, q, v, a, "HR_FOOT", fd.LOCAL, POINT)
    out = tuple(np.full((6, model.nv), np.nan) for _ in range(8))
    point = out[2].reshape(-1)[5:8]
    point[:] = POINT
    r = fd.kinematics_derivatives(model, q, v, a, "HR_FOOT", fd.LOCAL, point, out=out)
    assert all(np.array_equal(x, y) for x, y in zip(r, expected, strict=True))
    Q = np.stack([q, q])
    batch = fd.kinematics_derivatives(model, Q, v, a, "HR_FOOT", fd.LOCAL, np.stack([POINT, 2 * POINT]))
    outs = tuple(np.full((2, 6, model.nv), np.nan) for _ in range(8))
    points = outs[7].reshape(-1)[:6].reshape(2, 3)
    points[:] = [POINT, 2 * POINT]
    r = fd.kinematics_derivatives(model, Q, v, a, "HR_FOOT", fd.LOCAL, points, out=outs)
    assert all(np.array_equal(x, y) for x, y in zip(r, batch, strict=True))


def test_the_records_and_their_fields() -> None:
    model = library_robot("panda", False)
    assert model is not None
    q, v, a = _state(model, 33)
    k = fd.kinematics_derivatives(model, q, v, a, "panda_hand")
    assert isinstance(k, fd.KinematicsDerivatives)
    J = fd.frame_jacobian(model, q, "panda_hand", fd.LOCAL)
    assert np.array_equal(k.dv_dv, k.da_da) and np.array_equal(k.da_da, k.dac_da) and _rel(k.dv_dv, J) < 1e-14
    k.da_da[0, 0] += 1.0  # the three Jacobians are separate arrays
    assert not np.array_equal(k.dv_dv, k.da_da)
    c = fd.centroidal_dynamics_derivatives(model, q, v, a)
    assert isinstance(c, fd.CentroidalDynamicsDerivatives) and c.dh_dq.shape == (6, model.nv)
    d = fd.center_of_mass_derivatives(model, q, v)
    assert isinstance(d, fd.CenterOfMassDerivatives) and d.dc_dq.shape == (3, model.nv)
    cm = fd.compile(model, warmup=False)
    assert all(np.array_equal(x, y) for x, y in zip(cm.kinematics_derivatives(q, v, a, "panda_hand"),
                                                    fd.kinematics_derivatives(model, q, v, a, "panda_hand"), strict=True))
    assert all(np.array_equal(x, y) for x, y in zip(cm.centroidal_dynamics_derivatives(q, v, a), c, strict=True))
    # a frame fixed to the world does not move: every derivative is zero
    w = fd.kinematics_derivatives(model, q, v, a, "panda_link0", fd.WORLD, POINT)
    assert model.frames[model.resolve_frame("panda_link0")].body == -1
    assert all(not x.any() for x in w)


def test_bad_input() -> None:
    model = library_robot("panda", False)
    assert model is not None
    q, v, a = _state(model, 34)
    with pytest.raises(fd.ShapeError, match="point"):
        fd.kinematics_derivatives(model, q, v, a, "panda_hand", fd.LOCAL, np.zeros(2))
    with pytest.raises(fd.NonFiniteError, match="point"):
        fd.kinematics_derivatives(model, q, v, a, "panda_hand", fd.LOCAL, np.array([0.0, np.nan, 0.0]))
    with pytest.raises(fd.DTypeError, match="point"):
        fd.kinematics_derivatives(model, q, v, a, "panda_hand", fd.LOCAL, np.array(["a", "b", "c"]))
    with pytest.raises(fd.ShapeError, match="point"):  # batch shapes (2,) and (4,) do not broadcast
        fd.kinematics_derivatives(model, np.stack([q] * 2), v, a, "panda_hand", fd.LOCAL, np.zeros((4, 3)))
    with pytest.raises(fd.ShapeError, match="v: expected trailing dimension nv=9"):
        fd.kinematics_derivatives(model, q, v[:3], a, "panda_hand", fd.LOCAL, POINT)
    with pytest.raises(fd.ModelError):
        fd.kinematics_derivatives(model, q, v, a, "no such frame", fd.LOCAL, POINT)
    massless = fd.ModelBuilder("massless")
    massless.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), joint_name="j",
                      inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        m0 = massless.build()
    for backend in (None, "reference"):
        with pytest.raises(fd.ModelError, match="mass"):
            fd.center_of_mass_derivatives(m0, np.zeros(1), np.zeros(1), backend=backend)
        with pytest.raises(fd.ModelError, match="mass"):
            fd.centroidal_dynamics_derivatives(m0, np.zeros(1), np.zeros(1), np.zeros(1), backend=backend)
        # batches of whole SIMD groups too (their kernels leave a massless tree to the row-by-row status)
        with pytest.raises(fd.ModelError, match="mass"):
            fd.center_of_mass_derivatives(m0, np.zeros((9, 1)), np.zeros((9, 1)), backend=backend)
        with pytest.raises(fd.ModelError, match="mass"):
            fd.centroidal_dynamics_derivatives(m0, np.zeros((9, 1)), np.zeros((9, 1)), np.zeros(1), backend=backend)
