"""featherdyn.core == the reference algorithms (``backend="reference"``) to 1e-12 relative.

On every robot of the library, fixed and floating base, one state and a batch,
and on the random trees of ``tests/_models.py`` (every joint type: revolute about
any axis, prismatic, spherical, free-flyer, planar): FK (placements, velocities,
accelerations, parent placements), RNEA (with f_ext, without gravity), NLE, gravity, CRBA, ABA,
frame placements, frame Jacobians and their time variation in the three
reference frames, joint Jacobians, kinetic and potential energy, the centre of
mass and its velocity, the centroidal momentum and its matrix. Also a
floating base 10⁶ m from the origin (CRBA in body coordinates stays exact).
"""

from __future__ import annotations

import numpy as np
import pytest
from _core_helpers import REFS, assert_aba, assert_rel, frames_of, robot, robots, same_message, state
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn import core


def check_all(model: fd.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, tau: np.ndarray, f: np.ndarray,
              label: str) -> None:
    """Every core quantity against the reference, for one state or a batch."""
    ref = "reference"
    assert_rel(core.rnea(model, q, v, a), fd.rnea(model, q, v, a, backend=ref), f"{label}: rnea")
    assert_rel(core.rnea(model, q, v, a, f_ext=f, gravity=False),
               fd.rnea(model, q, v, a, f_ext=f, gravity=False, backend=ref), f"{label}: rnea f_ext, no gravity")
    assert_rel(core.nonlinear_effects(model, q, v), fd.nonlinear_effects(model, q, v, backend=ref), f"{label}: nle")
    assert_rel(core.generalized_gravity(model, q), fd.generalized_gravity(model, q, backend=ref), f"{label}: gravity")
    M_ref = fd.crba(model, q, backend=ref)
    M = core.crba(model, q)
    assert_rel(M, M_ref, f"{label}: crba")
    assert np.array_equal(M, np.swapaxes(M, -1, -2)), f"{label}: crba not exactly symmetric"
    try:
        ddq_ref = fd.aba(model, q, v, tau, f_ext=f, backend=ref)
    except fd.errors.SingularMassMatrixError as exc:
        with pytest.raises(fd.errors.SingularMassMatrixError) as info:
            core.aba(model, q, v, tau, f_ext=f)
        assert same_message(info.value, exc), (str(info.value), str(exc))
    else:
        assert_aba(core.aba(model, q, v, tau, f_ext=f), ddq_ref, M_ref, f"{label}: aba")
    H = core.placements(model, q)
    kin = fd.forward_kinematics(model, q, v, a, backend=ref)
    assert_rel(H[..., :3, :3], kin.placements.rotation, f"{label}: fk rotation")
    assert_rel(H[..., :3, 3], kin.placements.translation, f"{label}: fk translation")
    if np.ndim(q) == 1:
        _, _, vel, acc = core.forward_kinematics(model, q, v, a)
        assert_rel(vel, kin.velocities.vector, f"{label}: fk velocities")
        assert_rel(acc, kin.accelerations.vector, f"{label}: fk accelerations")
    H, Hp, vel, acc = core.forward_kinematics(model, q, v, a)
    assert_rel(H[..., :3, 3], kin.placements.translation, f"{label}: kinematics translation")
    assert_rel(Hp[..., :3, :3], kin.parent_placements.rotation, f"{label}: kinematics parent rotation")
    assert_rel(Hp[..., :3, 3], kin.parent_placements.translation, f"{label}: kinematics parent translation")
    assert np.all(Hp[..., 3, :] == [0.0, 0.0, 0.0, 1.0]), f"{label}: parent placements' last row"
    assert_rel(vel, kin.velocities.vector, f"{label}: kinematics velocities")
    assert_rel(acc, kin.accelerations.vector, f"{label}: kinematics accelerations")
    assert core.forward_kinematics(model, q)[2] is None and core.forward_kinematics(model, q, v)[3] is None
    assert_rel(core.kinetic_energy(model, q, v), fd.kinetic_energy(model, q, v, backend=ref), f"{label}: kinetic")
    assert_rel(core.potential_energy(model, q), fd.potential_energy(model, q, backend=ref), f"{label}: potential")
    assert_rel(core.joint_jacobians(model, q), fd.joint_jacobians(model, q, backend=ref), f"{label}: joint_jacobians")
    if model.total_mass > 0:
        c, cd = core.center_of_mass(model, q, v)
        com = fd.center_of_mass(model, q, v, backend=ref)
        assert_rel(c, com.position, f"{label}: center_of_mass")
        assert_rel(cd, com.velocity, f"{label}: center_of_mass velocity")
        assert core.center_of_mass(model, q)[1] is None
        assert_rel(core.center_of_mass(model, q)[0], com.position, f"{label}: center_of_mass without v")
        assert_rel(core.centroidal_momentum_matrix(model, q), fd.centroidal_momentum_matrix(model, q, backend=ref),
                   f"{label}: centroidal_momentum_matrix")
        assert_rel(core.centroidal_momentum(model, q, v), fd.centroidal_momentum(model, q, v, backend=ref).vector,
                   f"{label}: centroidal_momentum")
    for fid in frames_of(model):
        for reference in REFS:
            J = fd.frame_jacobian(model, q, fid, reference, backend=ref)
            assert_rel(core.frame_jacobian_time_variation(model, q, v, fid, reference),
                       fd.frame_jacobian_time_variation(model, q, v, fid, reference, backend=ref),
                       f"{label}: frame_jacobian_time_variation({model.frames[fid].name!r}, {reference.name})",
                       floor=float(np.abs(J).max(initial=0.0) * np.abs(v).max(initial=0.0)))
    for fid in frames_of(model):
        R, p = core.frame_placement(model, q, fid)
        X = fd.frame_placement(model, q, fid, backend=ref)
        assert_rel(R, X.rotation, f"{label}: frame_placement({fid}) rotation")
        assert_rel(p, X.translation, f"{label}: frame_placement({fid}) translation")
        for reference in REFS:
            assert_rel(core.frame_jacobian(model, q, fid, reference),
                       fd.frame_jacobian(model, q, fid, reference, backend=ref),
                       f"{label}: frame_jacobian({model.frames[fid].name!r}, {reference.name})")


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("name", robots())
def test_core_matches_reference_on_every_robot(name: str, floating: bool) -> None:
    model = robot(name, floating)
    if model is None:
        pytest.skip(f"{name} does not load")
    label = f"{name} ({'floating' if floating else 'fixed'})"
    check_all(model, *state(model, 3), f"{label} one state")
    check_all(model, *state(model, 4, (3,)), f"{label} batch (3,)")


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
@pytest.mark.parametrize("size", [(), (5,), (2, 3)], ids=lambda s: f"batch{s}".replace(" ", ""))
def test_core_matches_reference_on_random_trees(spec, size) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 5, size)
    check_all(model, st.q, st.v, st.a, st.tau, st.f_ext, f"{spec.name} batch{size}")


def test_joint_types_are_all_covered() -> None:
    """The random trees together hold every joint type the core has a kernel for."""
    kinds = {j.kind for s in TREES for j in tree(s.name).joints}
    assert kinds >= {"revolute", "prismatic", "spherical", "free_flyer", "planar"}, kinds


def test_crba_exact_far_from_the_origin() -> None:
    """A floating Panda with its base 10⁶ m away: M equals the reference to 1e-12 (body coordinates)."""
    model = robot("panda", True)
    assert model is not None
    q, *_ = state(model, 7)
    q[:3] = [1e6, -2e6, 0.5e6]
    assert_rel(core.crba(model, q), fd.crba(model, q, backend="reference"), "crba at 1e6 m")
    assert_rel(core.crba(model, q[None]), fd.crba(model, q[None], backend="reference"), "crba_batch at 1e6 m")
    # M does not depend on where the base is
    q0 = q.copy()
    q0[:3] = 0.0
    assert_rel(core.crba(model, q), core.crba(model, q0), "crba at 1e6 m vs at the origin")


def test_complex_rnea_equals_double_on_real_input() -> None:
    """The std::complex<double> instantiation of the RNEA template: bit-equal real part, zero imaginary part."""
    for spec in TREES:
        model = tree(spec.name)
        st = random_state(model, 8)
        tc = core.rnea_complex(model, st.q, st.v, st.a, st.f_ext)
        td = core.rnea(model, st.q, st.v, st.a, st.f_ext)
        assert_rel(tc.real, td, f"{spec.name}: complex rnea, real part", rtol=1e-14)
        assert np.all(tc.imag == 0), f"{spec.name}: complex rnea on real input has an imaginary part"


def test_complex_step_gives_the_derivative() -> None:
    """Im τ(q + i h e_k) / h = ∂τ/∂q_k for a revolute chain (compared with central differences)."""
    model = tree("revolute_chain")
    st = random_state(model, 9)
    h = 1e-20
    for k in range(model.nq):
        dq = np.zeros(model.nq)
        dq[k] = 1.0
        d_complex = core.rnea_complex(model, st.q + 1j * h * dq, st.v, st.a).imag / h
        eps = 1e-6
        d_fd = (core.rnea(model, st.q + eps * dq, st.v, st.a) - core.rnea(model, st.q - eps * dq, st.v, st.a)) / (2 * eps)
        assert_rel(d_complex, d_fd, f"∂τ/∂q_{k}", rtol=1e-7)


def test_massless_tree_has_no_centre_of_mass() -> None:
    """The core raises the reference's error, word for word."""
    b = fd.ModelBuilder("massless")
    b.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        model = b.build()
    for call in (lambda: core.center_of_mass(model, np.zeros(1)), lambda: core.centroidal_momentum_matrix(model, np.zeros(1))):
        with pytest.raises(fd.errors.ModelError) as mine:
            call()
        with pytest.raises(fd.errors.ModelError) as ref:
            fd.center_of_mass(model, np.zeros(1), backend="reference")
        assert str(mine.value) == str(ref.value)
