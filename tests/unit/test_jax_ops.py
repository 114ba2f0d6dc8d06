"""``featherdyn.jax``: the declared algorithms as XLA FFI operations (jit, vmap, gradients).

Oracles: the NumPy functions (the same kernels: equal bit for bit), their declared derivatives
(``fd.rnea_derivatives`` & co.), ``jax.test_util.check_grads`` (finite differences in JAX, fwd and rev modes),
and the identities of the configuration's tangent.
"""

from __future__ import annotations

import numpy as np
import pytest
from _models import TREES, library_robot, tree

import featherdyn as fd

jax = pytest.importorskip("jax")  # CI installs the `jax` extra (test_extras_in_ci.py holds it there)
import jax.numpy as jnp  # noqa: E402
from jax.test_util import check_grads  # noqa: E402

import featherdyn.jax as fj  # noqa: E402
from featherdyn.api.declarations import DECLARATIONS  # noqa: E402
from featherdyn.api.jacobians import has_jacobians  # noqa: E402

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]
#: each robot the other way round (panda on a free-flyer, solo12 and talos fixed at the base)
OTHER_BASE = [("panda", True), ("solo12", False), ("talos_full_v2", False)]
BOTH = ROBOTS + OTHER_BASE


def _id(robot: tuple[str, bool]) -> str:
    return f"{robot[0]}-{'floating' if robot[1] else 'fixed'}"


def _robot(name: str, floating: bool) -> fd.Model:
    model = library_robot(name, floating)
    assert model is not None
    return model


def _state(model: fd.Model, seed: int = 0, n: int | None = None) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    shape = () if n is None else (n,)
    q0, q1 = fd.random_configuration(model, rng, size=n), fd.random_configuration(model, rng, size=n)
    return {"q": q0, "q0": q0, "q1": q1, "v": rng.normal(size=shape + (model.nv,)),
            "a": rng.normal(size=shape + (model.nv,)), "tau": rng.normal(size=shape + (model.nv,)),
            "f_ext": rng.normal(size=shape + (model.nbodies, 6)), "w": rng.normal(size=shape + (model.nv,)),
            "W": rng.normal(size=shape + (model.nv, model.nv))}


def _arrays(result: object) -> list[np.ndarray]:
    """A NumPy function's result as its arrays in the declaration's output order."""
    if isinstance(result, np.ndarray):
        return [result]
    if isinstance(result, tuple):
        return [np.asarray(x) for x in result]
    if isinstance(result, (fd.SpatialMotion, fd.SpatialForce)):
        return [result.vector]
    if isinstance(result, fd.PluckerTransform):
        return [result.rotation, result.translation]
    raise TypeError(type(result))


#: the declarations whose NumPy result is the outputs themselves (records are compared field by field elsewhere)
PLAIN = sorted(n for n, d in DECLARATIONS.items()
               if n not in ("forward_kinematics", "placements", "center_of_mass", "kinematics_derivatives",
                            "center_of_mass_derivatives", "centroidal_dynamics_derivatives"))


@pytest.mark.parametrize("robot", BOTH, ids=_id)
def test_every_operation_equals_the_numpy_function(robot: tuple[str, bool]) -> None:
    model = _robot(*robot)
    st = _state(model, 1)
    frame = model.frames[-1].name
    for name in PLAIN:
        decl = DECLARATIONS[name]
        args = [st[n] for n in decl.inputs]
        extra = [frame] if "frame" in decl.options else []
        ours = getattr(fj, name)(model, *args, *extra)
        ours = [ours] if not isinstance(ours, tuple) else list(ours)
        theirs = _arrays(getattr(fd, name)(model, *args, *extra))
        assert len(ours) == len(theirs), name
        for o, t in zip(ours, theirs, strict=True):
            np.testing.assert_array_equal(np.asarray(o), t, err_msg=name)


def test_kinematics_derivatives_at_a_point_as_in_numpy() -> None:
    """A point (after the frame and reference, as in fd.*; by position or by name) is an input of the operation: jit,
    vmap over points and a batch of states equal the NumPy function bit for bit, and the point changes the result
    in LOCAL; a non-finite point under jit is an error naming it."""
    model = _robot("solo12", True)
    st = _state(model, 21, n=4)
    P = np.random.default_rng(22).normal(size=(4, 3)) * 0.1
    for ref in ("local", "local_world_aligned"):
        f = jax.jit(jax.vmap(lambda q, v, a, p, ref=ref: fj.kinematics_derivatives(model, q, v, a, "HR_FOOT", ref, p)))
        got, want = f(st["q"], st["v"], st["a"], P), fd.kinematics_derivatives(model, st["q"], st["v"], st["a"],
                                                                                "HR_FOOT", ref, P)
        assert got._fields == want._fields
        assert all(np.array_equal(np.asarray(x), y) for x, y in zip(got, want, strict=True))
    one = fj.kinematics_derivatives(model, st["q"][0], st["v"][0], st["a"][0], "HR_FOOT", point=P[0])
    frame = fj.kinematics_derivatives(model, st["q"][0], st["v"][0], st["a"][0], "HR_FOOT")
    assert np.array_equal(np.asarray(one.dv_dq), fd.kinematics_derivatives(model, st["q"][0], st["v"][0], st["a"][0],
                                                                           "HR_FOOT", fd.LOCAL, P[0]).dv_dq)
    assert not np.allclose(np.asarray(one.dv_dv), np.asarray(frame.dv_dv))  # (the linear rows move with the point)
    with pytest.raises(Exception, match="point"):
        jax.block_until_ready(jax.jit(lambda p: fj.kinematics_derivatives(
            model, st["q"][0], st["v"][0], st["a"][0], "HR_FOOT", "local", p).dv_dq)(P[0] * np.nan))
    with pytest.raises(TypeError, match="unexpected keyword"):
        fj.kinematics_derivatives(model, st["q"][0], st["v"][0], st["a"][0], "HR_FOOT", pointt=P[0])
    with pytest.raises(TypeError, match="multiple values"):
        fj.kinematics_derivatives(model, st["q"][0], st["v"][0], st["a"][0], "HR_FOOT", "local", P[0], point=P[0])


@pytest.mark.parametrize("robot", ROBOTS, ids=[r[0] for r in ROBOTS])
def test_jit_and_vmap_run_the_core_batch(robot: tuple[str, bool]) -> None:
    model = _robot(*robot)
    st = _state(model, 2, n=6)
    one = _state(model, 3)
    rnea = jax.jit(jax.vmap(lambda q, v: fj.rnea(model, q, v, one["a"])))
    np.testing.assert_array_equal(np.asarray(rnea(st["q"], st["v"])), fd.rnea(model, st["q"], st["v"], one["a"]))
    aba = jax.jit(jax.vmap(jax.vmap(lambda q, v, tau: fj.aba(model, q, v, tau)), in_axes=(None, 0, None)))
    V = np.stack([st["v"], 2 * st["v"]])
    np.testing.assert_array_equal(np.asarray(aba(st["q"], V, st["tau"])), fd.aba(model, st["q"], V, st["tau"]))
    M = jax.jit(lambda q: fj.crba(model, q))(st["q"])  # explicit leading axes: the same batch
    np.testing.assert_array_equal(np.asarray(M), fd.crba(model, st["q"]))


@pytest.mark.parametrize("robot", ROBOTS, ids=[r[0] for r in ROBOTS])
def test_gradients_are_the_declared_derivatives(robot: tuple[str, bool]) -> None:
    """jax.grad / jacfwd / jacrev against fd.rnea_derivatives & co., q's through the tangent maps."""
    model = _robot(*robot)
    st = _state(model, 4)
    q, v, a, tau = st["q"], st["v"], st["a"], st["tau"]
    dq, dv, M = fd.rnea_derivatives(model, q, v, a)
    w = np.random.default_rng(5).normal(size=model.nv)
    np.testing.assert_allclose(jax.grad(lambda v: fj.rnea(model, q, v, a) @ w)(v), dv.T @ w, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(jax.jacrev(lambda a: fj.rnea(model, q, v, a))(a), M, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fj.tangent_grad(lambda q: fj.rnea(model, q, v, a) @ w, model)(q), dq.T @ w,
                               rtol=1e-10, atol=1e-10 * max(1.0, float(np.abs(dq).max())))
    _, ddq_dv, Minv = fd.aba_derivatives(model, q, v, tau)
    J = jax.jacfwd(lambda x: fj.aba(model, q, x[0], x[1]))(jnp.stack([v, tau]))
    np.testing.assert_allclose(J[:, 0], ddq_dv, rtol=1e-12, atol=1e-12 * max(1.0, float(np.abs(ddq_dv).max())))
    np.testing.assert_allclose(J[:, 1], Minv, rtol=1e-12, atol=1e-12 * max(1.0, float(np.abs(Minv).max())))
    # q in coordinates: the tangent's Jacobian composed with the coordinates' map
    Jq = jax.jacfwd(lambda q: fj.generalized_gravity(model, q))(q)
    E = jax.jacfwd(lambda d: fj.coordinates_of_tangent(model, q, d))(np.zeros(model.nv))
    dg = fd.generalized_gravity_derivatives(model, q)
    np.testing.assert_allclose(Jq @ E, dg, rtol=1e-10, atol=1e-10 * max(1.0, float(np.abs(dg).max())))


def _call(model: fd.Model, name: str, st: dict[str, np.ndarray], reference: fd.ReferenceFrame = fd.LOCAL
          ) -> tuple[object, tuple[np.ndarray, ...]]:
    """``fj.<name>`` as a function of its state inputs but ``f_ext`` (held), ``q`` through ``fj.normalize`` (the
    differences leave the unit quaternions), and those inputs."""
    decl = DECLARATIONS[name]
    moving = [n for n in decl.inputs if n != "f_ext"]
    options = {k: v for k, v in (("frame", model.frames[-1].name), ("reference", reference)) if k in decl.options}

    def f(*xs: object) -> object:
        given = dict(zip(moving, xs, strict=True))
        for c in ("q", "q0", "q1"):  # (the configurations)
            if c in given:
                given[c] = fj.normalize(model, given[c])
        if "f_ext" in decl.inputs:
            given["f_ext"] = st["f_ext"]
        return getattr(fj, name)(model, **{n: given.get(n) for n in decl.inputs}, **options)  # (by name: a point last)

    return f, tuple(st[n] for n in moving)


#: the operations with first derivatives (their declaration's derivative, or api/jacobians.py's rules)
FIRST = sorted(n for n in DECLARATIONS if has_jacobians(n))
#: the operations whose first derivatives are made of operations with derivatives: second order
SECOND = ["rnea", "aba", "crba", "mass_matrix_inverse", "generalized_gravity", "nonlinear_effects", "kinetic_energy",
          "potential_energy", "joint_jacobians", "placements", "frame_placement"]


@pytest.mark.parametrize("robot", BOTH, ids=_id)
def test_check_grads_first_order_on_every_operation_with_derivatives(robot: tuple[str, bool]) -> None:
    """jax.test_util.check_grads (finite differences, fwd and rev modes) on each operation with derivatives; the
    frame functions in each reference frame."""
    model = _robot(*robot)
    st = _state(model, 6)
    assert {"rnea", "aba", "crba", "nonlinear_effects", "mass_matrix_inverse", "forward_kinematics",
            "frame_placement", "frame_jacobian", "frame_velocity", "frame_classical_acceleration", "center_of_mass",
            "centroidal_momentum", "rnea_derivatives", "aba_derivatives"} <= set(FIRST)
    for name in FIRST:
        refs: list[fd.ReferenceFrame] = [fd.LOCAL]
        if "reference" in DECLARATIONS[name].options:  # (each reference on the usual base; one on the other)
            refs = list(fd.ReferenceFrame) if robot in ROBOTS else [fd.LOCAL_WORLD_ALIGNED]
        for ref in refs:
            f, args = _call(model, name, st, ref)
            check_grads(f, args, order=1, modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)


@pytest.mark.parametrize("robot", ROBOTS, ids=[r[0] for r in ROBOTS])
def test_check_grads_with_respect_to_f_ext(robot: tuple[str, bool]) -> None:
    """rnea and aba in f_ext too (∂τ/∂f_b = −J_bᵀ, ∂q̈/∂f_b = M⁻¹ J_bᵀ, body coordinates), with the state."""
    model = _robot(*robot)
    st = _state(model, 13)
    args = (st["q"], st["v"], st["a"], st["f_ext"])
    check_grads(lambda q, v, a, f: fj.rnea(model, fj.normalize(model, q), v, a, f), args, order=1,
                modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)
    check_grads(lambda q, v, t, f: fj.aba(model, fj.normalize(model, q), v, t, f), args, order=1,
                modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)
    # against the NumPy function: τ is affine in f_ext
    w = np.random.default_rng(14).normal(size=model.nv)
    g = jax.grad(lambda f: fj.rnea(model, st["q"], st["v"], st["a"], f) @ w)(st["f_ext"])
    e = np.zeros_like(st["f_ext"])
    e[-1, 4] = 1.0
    dtau = fd.rnea(model, st["q"], st["v"], st["a"], f_ext=e) - fd.rnea(model, st["q"], st["v"], st["a"])
    assert abs(g[-1, 4] - dtau @ w) <= 1e-10 * max(1.0, abs(dtau @ w))


#: a random tree per joint kind the robots lack (prismatic, spherical, planar; the free-flyer on a branched tree)
KIND_TREES = ["fixed_chain_mixed", "fixed_branch_mixed", "planar_root_branch", "free_branch"]
assert set(KIND_TREES) <= {t.name for t in TREES}


@pytest.mark.parametrize("name", KIND_TREES)
def test_check_grads_first_order_on_every_joint_kind(name: str) -> None:
    """The rules' assumptions per joint kind (a spherical, planar or free-flyer joint's columns moving with its own
    tangent; the planar and quaternion tangent maps) on the random trees of every joint kind."""
    model = tree(name)
    st = _state(model, 6)
    for fn in FIRST:
        f, args = _call(model, fn, st, fd.WORLD)
        check_grads(f, args, order=1, modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)


SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def _contacts(model: fd.Model) -> list[object]:
    if model.name.startswith("talos"):
        return [fd.FrameContact("left_sole_link", fd.LOCAL), fd.FrameContact("right_sole_link", fd.LOCAL_WORLD_ALIGNED)]
    return [fd.PointContact(f, ref) for f, ref in zip(SOLO_FEET, (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED,
                                                                   fd.LOCAL), strict=True)]


@pytest.mark.parametrize("robot", ROBOTS[1:], ids=[r[0] for r in ROBOTS[1:]])
def test_constrained_and_impulse_dynamics(robot: tuple[str, bool]) -> None:
    """The contact operations: the NumPy functions' values (the same kernels, bit for bit), vmap on the core's
    batch, check_grads order 1 and jacfwd against the contact derivative kernels, and a second derivative
    refused."""
    model = _robot(*robot)
    st = _state(model, 10)
    cs = _contacts(model)
    q, v, tau = st["q"], st["v"], st["tau"]
    r, ref = fj.constrained_dynamics(model, q, v, tau, cs), fd.constrained_dynamics(model, q, v, tau, cs)
    np.testing.assert_array_equal(r.ddq, ref.ddq)
    np.testing.assert_array_equal(r.lagrange, ref.lagrange)
    for mine, theirs in zip(r.forces, ref.forces, strict=True):
        np.testing.assert_array_equal(mine, theirs)
    i, iref = fj.impulse_dynamics(model, q, v, cs, restitution=0.4), fd.impulse_dynamics(model, q, v, cs,
                                                                                        restitution=0.4)
    np.testing.assert_array_equal(i.v_plus, iref.v_plus)
    np.testing.assert_array_equal(i.lagrange, iref.lagrange)
    for mine, theirs in zip(i.impulses, iref.impulses, strict=True):
        np.testing.assert_array_equal(mine, theirs)
    b = _state(model, 11, n=6)
    ddq = jax.jit(jax.vmap(lambda q, v, t: fj.constrained_dynamics(model, q, v, t, cs).ddq))(b["q"], b["v"], b["tau"])
    np.testing.assert_array_equal(ddq, fd.constrained_dynamics(model, b["q"], b["v"], b["tau"], cs).ddq)
    vp = jax.jit(jax.vmap(lambda q, v: fj.impulse_dynamics(model, q, v, cs, restitution=0.4).v_plus))(b["q"], b["v"])
    np.testing.assert_array_equal(vp, fd.impulse_dynamics(model, b["q"], b["v"], cs, restitution=0.4).v_plus)
    check_grads(lambda q, v, t: fj.constrained_dynamics(model, fj.normalize(model, q), v, t, cs)[::2], (q, v, tau),
                order=1, modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)
    check_grads(lambda q, v: fj.impulse_dynamics(model, fj.normalize(model, q), v, cs, restitution=0.4)[::2],
                (q, v), order=1, modes=("fwd", "rev"), eps=1e-5, atol=1e-5, rtol=1e-5)
    d = fd.constrained_dynamics_derivatives(model, q, v, tau, cs)
    J = jax.jacfwd(lambda x: fj.constrained_dynamics(model, q, x[0], x[1], cs).ddq)(jnp.stack([v, tau]))
    np.testing.assert_allclose(J[:, 0], d.ddq_dv, rtol=1e-12, atol=1e-12 * np.abs(d.ddq_dv).max())
    np.testing.assert_allclose(J[:, 1], d.ddq_dtau, rtol=1e-12, atol=1e-12 * np.abs(d.ddq_dtau).max())
    di = fd.impulse_dynamics_derivatives(model, q, v, cs, restitution=0.4)
    Ji = jax.jacfwd(lambda x: fj.impulse_dynamics(model, q, x, cs, restitution=0.4).lagrange)(v)
    np.testing.assert_allclose(Ji, di.impulses_dv, rtol=1e-12, atol=1e-12 * np.abs(di.impulses_dv).max())
    with pytest.raises(fd.FeatherdynError, match="not available"):
        jax.hessian(lambda v: fj.constrained_dynamics(model, q, v, tau, cs).ddq.sum())(v)


def test_contact_errors() -> None:
    model = _robot("solo12", True)
    st = _state(model, 12)
    with pytest.raises(fd.FeatherdynError, match="point and frame contacts only"):
        fj.constrained_dynamics(model, st["q"], st["v"], st["tau"], [fd.LoopConstraint("FL_FOOT", "FR_FOOT")])
    with pytest.raises(fd.ModelError, match="nope"):
        fj.constrained_dynamics(model, st["q"], st["v"], st["tau"], [fd.PointContact("nope")])
    with pytest.raises(fd.ModelError, match="restitution"):
        fj.impulse_dynamics(model, st["q"], st["v"], [fd.PointContact("FL_FOOT")], restitution=2.0)
    with pytest.raises(fd.FeatherdynError, match="f_ext"):
        jax.grad(lambda f: fj.constrained_dynamics(model, st["q"], st["v"], st["tau"], [fd.PointContact("FL_FOOT")],
                                                   f).ddq.sum())(st["f_ext"])


@pytest.mark.parametrize("robot", ROBOTS, ids=[r[0] for r in ROBOTS])
def test_check_grads_second_order(robot: tuple[str, bool]) -> None:
    """Order 2 (jvp of jvp, vjp of jvp …) where the second derivatives exist: each first derivative is made of
    operations that have their own (rnea's of fd.rnea_derivatives, whose are fd.rnea_second_derivatives')."""
    model = _robot(*robot)
    st = _state(model, 7)
    # talos (nv = 50): the three and the gravity; the rest of the list on panda and solo12
    for name in SECOND if robot[0] != "talos_full_v2" else ["rnea", "aba", "crba", "generalized_gravity"]:
        f, args = _call(model, name, st)
        check_grads(f, args, order=2, modes=("fwd", "rev"), eps=1e-5, atol=1e-4, rtol=1e-4)


def test_hessian_of_rnea_is_the_second_derivatives() -> None:
    """jax.hessian in the tangent (q ⊕ δ at δ = 0) equals fd.rnea_second_derivatives (its symmetric part in q: the
    tangent's second derivative of the function q ↦ τ), and the v block exactly."""
    model = _robot("solo12", True)
    st = _state(model, 8)
    q, v, a = st["q"], st["v"], st["a"]
    w = np.random.default_rng(9).normal(size=model.nv)
    S = fd.rnea_second_derivatives(model, q, v, a)
    Hv = jax.hessian(lambda v: fj.rnea(model, q, v, a) @ w)(v)
    np.testing.assert_allclose(Hv, np.einsum("i,ijk->jk", w, S.d2tau_dv2), rtol=1e-10, atol=1e-10)
    Hq = jax.hessian(lambda d: fj.rnea(model, fj.coordinates_of_tangent(model, q, d) + q, v, a) @ w)(
        np.zeros(model.nv))
    ref = np.einsum("i,ijk->jk", w, S.d2tau_dq2)
    assert np.abs(Hq - Hq.T).max() <= 1e-9 * max(1.0, np.abs(Hq).max())
    np.testing.assert_allclose(Hq, 0.5 * (ref + ref.T), rtol=1e-6, atol=1e-6 * max(1.0, np.abs(ref).max()))


@pytest.mark.parametrize("name", ["crba", "mass_matrix_inverse"])
def test_reverse_mode_of_the_mass_matrix_contracts_as_it_goes(name: str) -> None:
    """jax.grad of ``Σ W ∘ M(q)`` (and of ``M⁻¹``) through the linear primitive's transpose (api/jacobians.py's
    VJPS, kinetic-energy gradients): equal to the contraction of ``∂M/∂q`` of ``fd.rnea_second_derivatives``, the same
    under jit and vmap, and the reverse-mode program holds no array of ``∂M/∂q``'s shape (nv³ a state)."""
    model = _robot("solo12", True)
    nv = model.nv
    rng = np.random.default_rng(12)
    Q = jnp.asarray(np.stack([fd.random_configuration(model, rng) for _ in range(3)]))
    W = jnp.asarray(rng.normal(size=(3, nv, nv)))
    f = getattr(fj, name)

    def loss(q):  # type: ignore[no-untyped-def]
        return jnp.sum(W * f(model, q))

    g = fj.tangent_grad(loss, model)(Q)  # (3, nv): along fd.integrate's tangent
    dM_dq = fd.rnea_second_derivatives(model, np.asarray(Q), np.zeros((3, nv)), np.zeros((3, nv))).dM_dq
    if name == "crba":
        expected = np.einsum("bij,bijk->bk", W, dM_dq)
    else:
        Minv = fd.mass_matrix_inverse(model, np.asarray(Q))
        expected = -np.einsum("nij,nia,nabk,nbj->nk", W, Minv, dM_dq, Minv)
    np.testing.assert_allclose(g, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
    grad = jax.grad(loss)
    np.testing.assert_allclose(jax.jit(grad)(Q), grad(Q), rtol=1e-13, atol=1e-13)
    per_state = jax.vmap(jax.grad(lambda q, w: jnp.sum(w * f(model, q))))(Q, W)
    np.testing.assert_allclose(per_state, grad(Q), rtol=1e-13, atol=1e-13)
    program = str(jax.make_jaxpr(grad)(Q))
    assert f"{nv},{nv},{nv}]" not in program and "featherdyn_linear_tangent" not in program
    assert "featherdyn_linear_tangent" in str(jax.make_jaxpr(jax.jacfwd(loss))(Q))  # (forward mode: J · δ)


@pytest.mark.parametrize("name", ["rnea", "aba"])
def test_reverse_mode_of_the_dynamics_forms_no_jacobian(name: str) -> None:
    """jax.grad of ``wᵀ rnea`` / ``wᵀ aba`` through the linear primitive's transpose (``fd.rnea_vjp``,
    ``fd.aba_vjp``, O(nb)): equal to ``w @`` the Jacobians of ``fd.rnea_derivatives`` / ``fd.aba_derivatives`` in
    ``q`` (along the tangent), ``v``, ``a``/``τ`` and ``f_ext`` (against forward mode), the same under jit and vmap,
    and the reverse program holds no (nv, nv) array and no forward-mode product."""
    model = _robot("solo12", True)
    nv, rng = model.nv, np.random.default_rng(14)
    Q = jnp.asarray(np.stack([fd.random_configuration(model, rng) for _ in range(3)]))
    V, A, W = (jnp.asarray(rng.normal(size=(3, nv))) for _ in range(3))
    F = jnp.asarray(rng.normal(size=(3, model.nbodies, 6)))
    f, jac = getattr(fj, name), getattr(fd, f"{name}_derivatives")

    def loss(q, v, a, fx):  # type: ignore[no-untyped-def]
        return jnp.sum(W * f(model, q, v, a, fx))

    gq = fj.tangent_grad(lambda q: loss(q, V, A, F), model)(Q)
    gv, ga, gf = jax.grad(loss, argnums=(1, 2, 3))(Q, V, A, F)
    J = jac(model, np.asarray(Q), np.asarray(V), np.asarray(A), np.asarray(F))
    for got, Jx in zip((gq, gv, ga), J, strict=True):
        expected = np.einsum("bi,bij->bj", W, Jx)
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())
    forward = jax.jacfwd(lambda fx: jnp.sum(W * f(model, Q, V, A, fx)))(F)  # (forward mode: the table and u̇)
    np.testing.assert_allclose(gf, forward, rtol=1e-10, atol=1e-10 * np.abs(forward).max())
    grad = jax.grad(loss, argnums=(0, 1, 2, 3))
    for x, y in zip(jax.jit(grad)(Q, V, A, F), grad(Q, V, A, F), strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-13, atol=1e-13)
    per_state = jax.vmap(jax.grad(lambda q, v, a, w: w @ f(model, q, v, a), argnums=(1, 2)))(Q, V, A, W)  # (∂/∂q̇: no f_ext)
    np.testing.assert_allclose(per_state[0], gv, rtol=1e-13, atol=1e-13)
    program = str(jax.make_jaxpr(grad)(Q, V, A, F))
    assert f"{nv},{nv}]" not in program and "featherdyn_linear_tangent" not in program


def test_tangent_maps_are_inverse_on_the_tangent() -> None:
    model = _robot("solo12", True)
    q = fd.random_configuration(model, 7)
    d = np.random.default_rng(8).normal(size=model.nv)
    np.testing.assert_allclose(fj.tangent_of_coordinates(model, q, fj.coordinates_of_tangent(model, q, d)), d,
                               rtol=1e-14, atol=1e-14)
    eps = 1e-7  # E(q) δ is the direction of q ⊕ ε δ
    np.testing.assert_allclose(fj.coordinates_of_tangent(model, q, d),
                               (fd.integrate(model, q, eps * d) - fd.integrate(model, q, -eps * d)) / (2 * eps),
                               atol=1e-7)


def test_errors() -> None:
    model = _robot("solo12", True)
    st = _state(model, 9)
    with pytest.raises(fd.ModelError, match="nope"):
        fj.frame_velocity(model, st["q"], st["v"], "nope")
    with pytest.raises(fd.ShapeError):
        fj.rnea(model, st["q"][:-1], st["v"], st["a"])
    with pytest.raises(fd.DTypeError, match="real numbers"):
        fj.rnea(model, "abc", st["v"], st["a"])
    with pytest.raises(fd.FeatherdynError, match="not available"):
        jax.grad(lambda q: fj.joint_torque_regressor(model, q, st["v"], st["a"]).sum())(st["q"])
    with pytest.raises(fd.FeatherdynError, match="rnea_second_derivatives: its derivatives are not available"):
        jax.jacfwd(jax.jacfwd(jax.jacfwd(lambda q: fj.crba(model, q))))(st["q"])  # a fourth derivative of τ
    with pytest.raises(fd.FeatherdynError, match="f_ext"):
        jax.grad(lambda f: fj.static_torque_derivatives(model, st["q"], f).sum())(st["f_ext"])
    with pytest.raises(Exception, match=r"featherdyn\.rnea: row 0: non-finite value"):
        jax.block_until_ready(jax.jit(lambda q: fj.rnea(model, q, st["v"], st["a"]))(st["q"] * np.nan))
