"""Every reference algorithm against Pinocchio, on random trees and random states.

Each tree of ``_models.TREES`` (fixed and floating base, chains and branches,
revolute about random axes, prismatic, spherical, planar, free-flyer) is
mirrored into Pinocchio with :func:`featherdyn.verify.bridge.pinocchio_model_from`;
every featherdyn frame (body frames, tool frames at random placements, a
world-fixed marker) is added to the Pinocchio model as an ``OP_FRAME``.
Layouts are converted with :class:`~featherdyn.verify.bridge.JointMap`
(Pinocchio is linear-first ``[v; ω]``, featherdyn angular-first ``[ω; v]``).

Every comparison is elementwise ``|a − b| / max(|b|, 1) <= 1e-9``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from _models import TREES, State, random_axis, random_inertia, random_placement, random_state, tool_frames, tree

import featherdyn as fd
from featherdyn.verify.bridge import JointMap, from_pin6, from_pin6_rows, pinocchio_model_from

pin = pytest.importorskip("pinocchio")

REL_TOL = 1e-9
STATES_PER_TREE = 3

#: worst relative error seen per quantity (read by whoever wants the numbers; asserts do not use it)
MAX_ERRORS: dict[str, float] = {}


def check(actual: Any, expected: Any, quantity: str, where: str) -> None:
    """Assert ``max |a − b| / max(|b|, 1) <= REL_TOL`` elementwise; the message names the quantity and the worst index."""
    a = np.asarray(actual, dtype=np.float64)
    b = np.asarray(expected, dtype=np.float64)
    assert a.shape == b.shape, f"{quantity} ({where}): shape {a.shape} vs Pinocchio {b.shape}"
    rel = np.abs(a - b) / np.maximum(np.abs(b), 1.0)
    worst = float(rel.max(initial=0.0))
    MAX_ERRORS[quantity] = max(MAX_ERRORS.get(quantity, 0.0), worst)
    if not worst <= REL_TOL:
        idx = np.unravel_index(int(np.argmax(rel)), rel.shape)
        raise AssertionError(
            f"{quantity} ({where}): relative error {worst:.3g} > {REL_TOL:g} at index {tuple(int(i) for i in idx)}: "
            f"featherdyn {a[idx]:.12g}, Pinocchio {b[idx]:.12g}"
        )


@dataclass
class Case:
    """A tree, its Pinocchio mirror (with frames) and one random state in both layouts."""

    name: str
    model: fd.Model
    pm: Any
    jm: JointMap
    frame_ids: dict[str, int]  # featherdyn frame name -> Pinocchio frame id
    st: State
    q: np.ndarray  # Pinocchio layouts
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray
    fext: list

    def data(self) -> Any:
        return self.pm.createData()


def _mirror(model: fd.Model) -> tuple[Any, dict[str, int]]:
    pm = pinocchio_model_from(model)
    ids = {}
    for f in model.frames:
        joint = 0 if f.body == -1 else pm.getJointId(model.joint_names[f.body])
        M = pin.SE3(np.array(f.placement.rotation), np.array(f.placement.translation))
        ids[f.name] = pm.addFrame(pin.Frame(f.name, joint, M, pin.FrameType.OP_FRAME))
    return pm, ids


def _pin_forces(model: fd.Model, pm: Any, f_ext: np.ndarray) -> list:
    """featherdyn body-frame forces `(nb, 6)` ``[n; f]`` → Pinocchio's per-joint LOCAL forces (index 0 = universe)."""
    out = [pin.Force.Zero() for _ in range(pm.njoints)]
    for i, name in enumerate(model.joint_names):
        out[pm.getJointId(name)] = pin.Force(from_pin6(f_ext[i]))
    return out


_CASE_IDS = [(spec.name, k) for spec in TREES for k in range(STATES_PER_TREE)]


@pytest.fixture(scope="module", params=_CASE_IDS, ids=[f"{n}-state{k}" for n, k in _CASE_IDS])
def case(request: pytest.FixtureRequest) -> Case:
    name, k = request.param
    model = tree(name)
    pm, ids = _mirror(model)
    jm = JointMap(model, pm)
    st = random_state(model, 1000 + 17 * k + len(name))
    return Case(
        name=f"{name}, state {k}",
        model=model,
        pm=pm,
        jm=jm,
        frame_ids=ids,
        st=st,
        q=jm.q_to_pin(st.q),
        v=jm.v_to_pin(st.v),
        a=jm.v_to_pin(st.a),
        tau=jm.v_to_pin(st.tau),
        fext=_pin_forces(model, pm, st.f_ext),
    )


REFERENCES = [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED]


@pytest.fixture(params=REFERENCES, ids=[r.name for r in REFERENCES])
def reference(request: pytest.FixtureRequest) -> tuple[Any, Any, str]:
    """``(featherdyn reference, Pinocchio reference, name)``: the enum members share their names."""
    ref = request.param
    return ref, getattr(pin.ReferenceFrame, ref.name), ref.name


def _frames(case: Case) -> list[str]:
    """Body frames (identity placement), tool frames (random placement) and the world marker."""
    return list(case.model.body_names) + tool_frames(case.model)


# ---------------------------------------------------------------------------------------------------------------
# kinematics
# ---------------------------------------------------------------------------------------------------------------


def test_the_mirror_has_every_frame_at_a_non_identity_offset(case: Case) -> None:
    tools = tool_frames(case.model)
    assert len(tools) == case.model.nbodies + 1
    for name in tools:
        f = case.model.frames[case.model.frame_id(name)]
        assert np.abs(f.placement.homogeneous() - np.eye(4)).max() > 0.05, name


def test_forward_kinematics(case: Case) -> None:
    m, pm, d = case.model, case.pm, case.data()
    pin.forwardKinematics(pm, d, case.q, case.v, case.a)
    kin = fd.forward_kinematics(m, case.st.q, case.st.v, case.st.a)
    for i, jname in enumerate(m.joint_names):
        jid = pm.getJointId(jname)
        where = f"{case.name}, body {m.body_names[i]}"
        check(kin.placements[i].homogeneous(), d.oMi[jid].homogeneous, "placement oMi", where)
        check(kin.velocities.vector[i], from_pin6(d.v[jid].vector), "body velocity v", where)
        check(kin.accelerations.vector[i], from_pin6(d.a[jid].vector), "body spatial acceleration a", where)


def test_frame_placements(case: Case) -> None:
    m, pm, d = case.model, case.pm, case.data()
    pin.framesForwardKinematics(pm, d, case.q)
    for name in _frames(case):
        check(fd.frame_placement(m, case.st.q, name).homogeneous(), d.oMf[case.frame_ids[name]].homogeneous,
              "frame placement oMf", f"{case.name}, frame {name}")


def test_frame_velocity_and_accelerations(case: Case, reference: tuple[Any, Any, str]) -> None:
    ref, pref, rname = reference
    m, pm, d = case.model, case.pm, case.data()
    st = case.st
    pin.forwardKinematics(pm, d, case.q, case.v, case.a)
    pin.updateFramePlacements(pm, d)
    for name in _frames(case):
        fid, where = case.frame_ids[name], f"{case.name}, frame {name}, {rname}"
        check(fd.frame_velocity(m, st.q, st.v, name, ref).vector,
              from_pin6(pin.getFrameVelocity(pm, d, fid, pref).vector), f"frame velocity {rname}", where)
        check(fd.frame_acceleration(m, st.q, st.v, st.a, name, ref).vector,
              from_pin6(pin.getFrameAcceleration(pm, d, fid, pref).vector), f"frame spatial acceleration {rname}", where)
        check(fd.frame_classical_acceleration(m, st.q, st.v, st.a, name, ref).vector,
              from_pin6(pin.getFrameClassicalAcceleration(pm, d, fid, pref).vector),
              f"frame classical acceleration {rname}", where)


# ---------------------------------------------------------------------------------------------------------------
# dynamics
# ---------------------------------------------------------------------------------------------------------------


def test_rnea(case: Case) -> None:
    m, st, jm = case.model, case.st, case.jm
    tau_pin = pin.rnea(case.pm, case.data(), case.q, case.v, case.a)
    check(fd.rnea(m, st.q, st.v, st.a), jm.v_from_pin(tau_pin), "rnea", case.name)


def test_rnea_without_gravity(case: Case) -> None:
    pm0 = pin.Model(case.pm)
    pm0.gravity = pin.Motion.Zero()
    tau_pin = pin.rnea(pm0, pm0.createData(), case.q, case.v, case.a)
    check(fd.rnea(case.model, case.st.q, case.st.v, case.st.a, gravity=False), case.jm.v_from_pin(tau_pin),
          "rnea gravity=False", case.name)


def test_rnea_with_external_forces(case: Case) -> None:
    m, st, jm = case.model, case.st, case.jm
    tau_pin = pin.rnea(case.pm, case.data(), case.q, case.v, case.a, case.fext)
    tau = fd.rnea(m, st.q, st.v, st.a, st.f_ext)
    check(tau, jm.v_from_pin(tau_pin), "rnea with f_ext", case.name)
    # the forces are not negligible: the comparison would catch a sign or frame error
    assert np.abs(tau - fd.rnea(m, st.q, st.v, st.a)).max() > 0.1


def test_crba(case: Case) -> None:
    M_pin = pin.crba(case.pm, case.data(), case.q)
    check(fd.crba(case.model, case.st.q), case.jm.matrix_from_pin(M_pin), "crba", case.name)


def test_aba(case: Case) -> None:
    m, st, jm = case.model, case.st, case.jm
    ddq_pin = pin.aba(case.pm, case.data(), case.q, case.v, case.tau)
    check(fd.aba(m, st.q, st.v, st.tau), jm.v_from_pin(ddq_pin), "aba", case.name)


def test_aba_with_external_forces(case: Case) -> None:
    m, st, jm = case.model, case.st, case.jm
    ddq_pin = pin.aba(case.pm, case.data(), case.q, case.v, case.tau, case.fext)
    check(fd.aba(m, st.q, st.v, st.tau, st.f_ext), jm.v_from_pin(ddq_pin), "aba with f_ext", case.name)


def test_nonlinear_effects_and_gravity(case: Case) -> None:
    m, st, jm = case.model, case.st, case.jm
    check(fd.nonlinear_effects(m, st.q, st.v),
          jm.v_from_pin(pin.nonLinearEffects(case.pm, case.data(), case.q, case.v)), "nonlinear_effects", case.name)
    check(fd.generalized_gravity(m, st.q),
          jm.v_from_pin(pin.computeGeneralizedGravity(case.pm, case.data(), case.q)), "generalized_gravity", case.name)


def test_coriolis_matrix(case: Case) -> None:
    C_pin = pin.computeCoriolisMatrix(case.pm, case.data(), case.q, case.v)
    check(fd.coriolis_matrix(case.model, case.st.q, case.st.v), case.jm.matrix_from_pin(C_pin), "coriolis_matrix",
          case.name)


# ---------------------------------------------------------------------------------------------------------------
# Jacobians
# ---------------------------------------------------------------------------------------------------------------


def test_joint_jacobians(case: Case) -> None:
    d = case.data()
    J_pin = pin.computeJointJacobians(case.pm, d, case.q)
    check(fd.joint_jacobians(case.model, case.st.q), case.jm.columns_from_pin(from_pin6_rows(J_pin)),
          "joint_jacobians (data.J)", case.name)


def test_frame_jacobian(case: Case, reference: tuple[Any, Any, str]) -> None:
    ref, pref, rname = reference
    m, pm, d = case.model, case.pm, case.data()
    pin.computeJointJacobians(pm, d, case.q)
    pin.updateFramePlacements(pm, d)
    for name in _frames(case):
        J_pin = pin.getFrameJacobian(pm, d, case.frame_ids[name], pref)
        check(fd.frame_jacobian(m, case.st.q, name, ref), case.jm.columns_from_pin(from_pin6_rows(J_pin)),
              f"frame_jacobian {rname}", f"{case.name}, frame {name}")


def test_frame_jacobian_time_variation(case: Case, reference: tuple[Any, Any, str]) -> None:
    ref, pref, rname = reference
    m, pm, d = case.model, case.pm, case.data()
    pin.computeJointJacobiansTimeVariation(pm, d, case.q, case.v)
    pin.updateFramePlacements(pm, d)
    for name in _frames(case):
        dJ_pin = pin.getFrameJacobianTimeVariation(pm, d, case.frame_ids[name], pref)
        check(fd.frame_jacobian_time_variation(m, case.st.q, case.st.v, name, ref),
              case.jm.columns_from_pin(from_pin6_rows(dJ_pin)), f"frame_jacobian_time_variation {rname}",
              f"{case.name}, frame {name}")


# ---------------------------------------------------------------------------------------------------------------
# energies, centre of mass, centroidal momentum
# ---------------------------------------------------------------------------------------------------------------


def test_energies(case: Case) -> None:
    m, st = case.model, case.st
    check(fd.kinetic_energy(m, st.q, st.v), pin.computeKineticEnergy(case.pm, case.data(), case.q, case.v),
          "kinetic_energy", case.name)
    check(fd.potential_energy(m, st.q), pin.computePotentialEnergy(case.pm, case.data(), case.q),
          "potential_energy", case.name)


def test_center_of_mass(case: Case) -> None:
    m, st, d = case.model, case.st, case.data()
    pin.centerOfMass(case.pm, d, case.q, case.v)
    com = fd.center_of_mass(m, st.q, st.v)
    assert isinstance(com, fd.CenterOfMass)
    check(com.position, d.com[0], "center_of_mass position", case.name)
    check(com.velocity, d.vcom[0], "center_of_mass velocity", case.name)
    position_only = fd.center_of_mass(m, st.q)
    assert isinstance(position_only, np.ndarray)
    check(position_only, d.com[0], "center_of_mass (no v)", case.name)


def test_centroidal_momentum(case: Case) -> None:
    m, st, d = case.model, case.st, case.data()
    Ag_pin = pin.ccrba(case.pm, d, case.q, case.v)
    check(fd.centroidal_momentum_matrix(m, st.q), case.jm.columns_from_pin(from_pin6_rows(Ag_pin)),
          "centroidal_momentum_matrix Ag", case.name)
    h = fd.centroidal_momentum(m, st.q, st.v)
    assert isinstance(h, fd.SpatialForce)
    check(h.vector, from_pin6(d.hg.vector), "centroidal_momentum hg", case.name)


# ---------------------------------------------------------------------------------------------------------------
# a tree numbered parents-first but not depth-first
# ---------------------------------------------------------------------------------------------------------------


def test_tree_not_numbered_depth_first() -> None:
    """featherdyn needs only ``parent[i] < i``; Pinocchio also assumes depth-first numbering.

    Here body ``d`` hangs from ``b`` but comes after ``b``'s sibling ``c``. Pinocchio's
    CRBA (and ABA) index subtrees as contiguous velocity ranges, so on this
    mirror they are wrong, while its RNEA — a plain parent-pointer recursion —
    stays right. featherdyn is checked against Pinocchio's RNEA only: τ, the
    columns ``rnea(q, 0, e_j) − rnea(q, 0, 0)`` of M, and ABA against M⁻¹(τ − h).
    """
    rng = np.random.default_rng(31)
    b = fd.ModelBuilder("not depth-first")
    b.add_body("a", -1, fd.RevoluteJoint(random_axis(rng)), inertia=random_inertia(rng))
    b.add_body("b", 0, fd.SphericalJoint(), placement=random_placement(rng), inertia=random_inertia(rng))
    b.add_body("c", 0, fd.PrismaticJoint(random_axis(rng)), placement=random_placement(rng), inertia=random_inertia(rng))
    b.add_body("d", 1, fd.RevoluteJoint(random_axis(rng)), placement=random_placement(rng), inertia=random_inertia(rng))
    m = b.build()
    with pytest.raises(fd.ModelError, match="depth-first"):
        pinocchio_model_from(m)  # the bridge refuses a mirror on which Pinocchio's CRBA would be wrong
    pm = pinocchio_model_from(m, check_order=False)
    d, jm = pm.createData(), JointMap(m, pm)
    st = random_state(m, 4)
    q = jm.q_to_pin(st.q)
    zero = np.zeros(m.nv)
    check(fd.rnea(m, st.q, st.v, st.a), jm.v_from_pin(pin.rnea(pm, d, q, jm.v_to_pin(st.v), jm.v_to_pin(st.a))),
          "rnea", "not depth-first")
    g_pin = pin.rnea(pm, d, q, zero, zero)
    M_pin = np.array([pin.rnea(pm, d, q, zero, e) - g_pin for e in np.eye(m.nv)]).T
    M = fd.crba(m, st.q)
    check(M, jm.matrix_from_pin(M_pin), "crba vs Pinocchio rnea columns", "not depth-first")
    h = jm.v_from_pin(pin.rnea(pm, d, q, jm.v_to_pin(st.v), zero))
    check(fd.aba(m, st.q, st.v, st.tau), np.linalg.solve(M, st.tau - h), "aba vs M⁻¹(τ − h)", "not depth-first")
