"""featherdyn.torch: the declared functions as PyTorch operators (docs/frameworks.md).

Values against the NumPy functions (bit for bit in float64), float32, batches, the featherdyn errors,
``torch.library.opcheck`` on every operator, ``torch.compile(fullgraph=True)`` of functions and of their
gradients, and the gradients (api/jacobians.py): ``gradcheck`` (finite differences in ``q``'s coordinates,
``q`` through ``ft.normalize``; reverse and forward mode) on every operator with Jacobians, the frame functions
in each reference frame, ``gradgradcheck`` on those whose Jacobians are differentiable again, on panda (fixed),
solo12 and talos_full_v2 (floating) and a random tree with spherical and planar joints; ``torch.func`` (grad,
jacrev, jacfwd, vmap, hessian) against the NumPy derivative functions; the tangent gradient against a finite
difference along ``fd.integrate``.

torch is in the ``test`` extra, which CI installs; without it this module is skipped, and
``test_optional_dependency_is_installed_in_ci[torch]`` (tests/unit/test_extras_in_ci.py) fails in CI so the skip cannot hide there.
"""

from __future__ import annotations

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from _models import library_robot, random_state, random_tree  # noqa: E402

import featherdyn as fd  # noqa: E402
import featherdyn.torch as ft  # noqa: E402
from featherdyn.api import declarations  # noqa: E402
from featherdyn.api.declarations import DECLARATIONS  # noqa: E402
from featherdyn.api.declared import Record, positional_parameters  # noqa: E402
from featherdyn.api.jacobians import has_jacobians  # noqa: E402


@pytest.fixture(autouse=True, scope="module")
def _one_torch_thread():  # type: ignore[no-untyped-def]
    """torch's intra-op pool at one thread for this module: the tensors are small (a few hundred entries), and on
    CI's two cores, beside featherdyn's own pool, two OpenMP threads make each matmul milliseconds, not µs."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


def _robot(name: str, floating: bool) -> fd.Model:
    m = library_robot(name, floating)
    if m is None:
        pytest.fail(f"{name} does not load (example-robot-data is in the test extra)")
    return m


def _mixed_tree() -> fd.Model:
    """A floating tree with every joint kind whose q is not its tangent (free-flyer, spherical, planar)."""
    return random_tree(3, 6, root="free_flyer", kinds=("revolute", "spherical", "planar", "prismatic"))


MODELS = {"panda": lambda: _robot("panda", False), "solo12": lambda: _robot("solo12", True),
          "talos_full_v2": lambda: _robot("talos_full_v2", True), "mixed_tree": _mixed_tree}


def _state(model: fd.Model, seed: int = 0, size: tuple[int, ...] = (), grad: bool = False) -> dict[str, torch.Tensor]:
    s = random_state(model, seed, size)
    st = {k: torch.tensor(getattr(s, k), requires_grad=grad) for k in ("q", "v", "a", "tau", "f_ext", "w", "W")}
    q1 = fd.random_configuration(model, np.random.default_rng(seed + 1000), size=size or None)
    st["q0"] = torch.tensor(s.q, requires_grad=grad)  # (fd.difference's configurations)
    st["q1"] = torch.tensor(q1, requires_grad=grad)
    point = np.random.default_rng(seed + 2000).standard_normal(size + (3,))  # (fd.kinematics_derivatives')
    st["point"] = torch.tensor(point, requires_grad=grad)
    return st


def _args(decl, model, st, frame=None):  # type: ignore[no-untyped-def]
    """The positional arguments of ft.<name> / fd.<name> for a declaration (inputs, then frame and reference, then
    a point)."""
    given = {**st, "frame": frame if frame is not None else model.frames[-1].name, "reference": "world"}
    return [given[n] for n in positional_parameters(decl)]


def _expected(decl, r):  # type: ignore[no-untyped-def]
    """The output arrays of ``fd.<name>``'s result, in the declaration's order."""
    if len(decl.outputs) == 1 and isinstance(r, np.ndarray):
        return [r]
    if isinstance(decl.result, Record):
        field = {source: f for f, source in decl.result.fields}
        return [getattr(r, field[o]) for o in decl.outputs]
    if hasattr(r, decl.outputs[0]):
        return [getattr(r, o) for o in decl.outputs]
    return list(r)


# --------------------------------------------------------------------------------------------- values

@pytest.mark.parametrize("robot", ["panda", "solo12"])
def test_every_operator_equals_the_numpy_function_bit_for_bit(robot: str) -> None:
    model = MODELS[robot]()
    st = _state(model, 1)
    npst = {k: t.numpy() for k, t in st.items()}
    checked = 0
    for name, decl in DECLARATIONS.items():
        if name not in ft.OPERATORS:
            continue
        got = getattr(ft, name)(model, *_args(decl, model, st))
        numpy_function = getattr(fd, name, None) or getattr(declarations, name)  # (placements: fd.compile's fk)
        want = _expected(decl, numpy_function(model, *_args(decl, model, npst)))
        got = [got] if len(decl.outputs) == 1 else list(got)
        assert len(got) == len(want), name
        for o, g, w in zip(decl.outputs, got, want, strict=True):
            assert g.dtype == torch.float64, (name, o)
            assert np.array_equal(g.numpy(), np.asarray(w)), (name, o)
        checked += 1
    assert checked == len(DECLARATIONS)  # every declared function is an operator


def test_kinematics_derivatives_at_a_point_as_in_numpy() -> None:
    """A point (after the frame and reference, as in fd.*) is an input of the operator: a batch of states and points
    equals the NumPy function bit for bit, and the point changes the result in LOCAL; a bad point is refused with
    fd.<name>'s words."""
    model = MODELS["solo12"]()
    st = _state(model, 23, (3,))
    np_st = {k: t.numpy() for k, t in st.items()}
    got = ft.kinematics_derivatives(model, st["q"], st["v"], st["a"], "HR_FOOT", "local", st["point"])
    want = fd.kinematics_derivatives(model, np_st["q"], np_st["v"], np_st["a"], "HR_FOOT", fd.LOCAL, np_st["point"])
    assert all(np.array_equal(x.numpy(), y) for x, y in zip(got, want, strict=True))
    frame = ft.kinematics_derivatives(model, st["q"], st["v"], st["a"], "HR_FOOT", "local")
    assert not torch.allclose(got.dv_dv, frame.dv_dv)  # (the linear rows move with the point)
    with pytest.raises(fd.NonFiniteError, match="point"):
        ft.kinematics_derivatives(model, st["q"], st["v"], st["a"], "HR_FOOT", "local", st["point"] * np.nan)
    with pytest.raises(fd.ShapeError, match="point"):
        ft.kinematics_derivatives(model, st["q"], st["v"], st["a"], "HR_FOOT", "local", st["point"][..., :2])


def test_results_with_several_outputs_are_named_tuples_and_absent_outputs_none() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 2)
    k = ft.forward_kinematics(model, st["q"])
    assert k._fields == ("H", "Hp", "vel", "acc") and k.vel is None and k.acc is None
    assert k.H.shape == (model.nbodies, 4, 4)
    k = ft.forward_kinematics(model, st["q"], st["v"])
    assert k.vel.shape == (model.nbodies, 6) and k.acc is None
    d = ft.rnea_derivatives(model, st["q"], st["v"], st["a"])
    assert d._fields == ("dtau_dq", "dtau_dv", "M")
    assert torch.equal(d.M, ft.crba(model, st["q"]))
    s = ft.rnea_second_derivatives(model, st["q"], st["v"], st["a"])
    assert type(s) is fd.RneaSecondDerivatives and s.dM_dq.shape == (model.nv,) * 3


def test_float32_in_float32_out_computed_in_float64() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 3)
    f32 = {k: t.to(torch.float32).requires_grad_() for k, t in st.items()}
    tau = ft.rnea(model, f32["q"], f32["v"], f32["a"])
    assert tau.dtype == torch.float32
    # the float64 computation of the float32 values, rounded once
    want = fd.rnea(model, *(f32[k].detach().numpy().astype(np.float64) for k in ("q", "v", "a"))).astype(np.float32)
    assert np.array_equal(tau.detach().numpy(), want)
    # gradients in float32 too, the float64 ones rounded
    grads = torch.autograd.grad(tau.sum(), (f32["q"], f32["v"]))
    q64, v64 = (f32[k].detach().double().requires_grad_() for k in ("q", "v"))
    grads64 = torch.autograd.grad(ft.rnea(model, q64, v64, f32["a"].detach().double()).sum(), (q64, v64))
    for g, g64 in zip(grads, grads64, strict=True):
        assert g.dtype == torch.float32
        torch.testing.assert_close(g, g64.float(), rtol=1e-6, atol=1e-5)
    assert ft.rnea(model, f32["q"], st["v"], st["a"]).dtype == torch.float64  # any float64 input: float64


def test_batches_broadcast_as_the_numpy_functions_do() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 4, (2, 3))
    tau = ft.rnea(model, st["q"], st["v"], st["a"], st["f_ext"])
    assert tau.shape == (2, 3, model.nv)
    assert np.array_equal(tau.numpy(), fd.rnea(model, *(st[k].numpy() for k in ("q", "v", "a", "f_ext"))))
    q0 = st["q"][0, 0]  # one configuration for the whole batch
    M = ft.aba_derivatives(model, q0, st["v"], st["tau"]).Minv
    assert M.shape == (2, 3, model.nv, model.nv)
    assert torch.equal(M[1, 2], ft.mass_matrix_inverse(model, q0))


def test_bad_input_raises_the_featherdyn_errors() -> None:
    model = MODELS["panda"]()
    st = _state(model, 5)
    with pytest.raises(fd.ShapeError, match=r"q: expected trailing dimension nq=\d+, got shape \(2,\)"):
        ft.rnea(model, torch.zeros(2, dtype=torch.float64), st["v"], st["a"])
    with pytest.raises(fd.DTypeError, match="q: expected real numbers"):
        ft.rnea(model, st["q"].to(torch.complex128), st["v"], st["a"])
    with pytest.raises(fd.FeatherdynError) as info:
        fd.frame_jacobian(model, st["q"].numpy(), "no_such_frame")
    with pytest.raises(type(info.value), match=str(info.value)[:30]):
        ft.frame_jacobian(model, st["q"], "no_such_frame")
    with pytest.raises(fd.DTypeError, match="gravity: expected True or False"):
        ft.rnea(model, st["q"], st["v"], st["a"], gravity="no")
    with pytest.raises(fd.ShapeError, match="model: expected a featherdyn Model"):
        ft.rnea("panda", st["q"], st["v"], st["a"])


# ------------------------------------------------------------------------------------------ operators

#: the operators with Jacobians (api/jacobians.py: a declared derivative or a rule)
FIRST = sorted(n for n in DECLARATIONS if has_jacobians(n))
#: the operators whose Jacobians are made of operators with Jacobians: second order (as tests/unit/test_jax_ops.py)
SECOND = ["rnea", "aba", "crba", "mass_matrix_inverse", "generalized_gravity", "nonlinear_effects", "kinetic_energy",
          "potential_energy"]
ROBOTS = ["panda", "solo12", "talos_full_v2"]


@pytest.mark.parametrize("robot", ROBOTS)
def test_opcheck_on_every_operator(robot: str) -> None:
    """opcheck on every operator; the inputs of the operators with Jacobians require grad (but f_ext outside rnea
    and aba: its gradient raises there). All of opcheck's tests on solo12 and panda; on talos the ones that read
    the model's shapes (schema, fake implementation, autograd registration): AOTAutograd's (static and dynamic
    dispatch) trace the same Python on every robot, and take 2 minutes on talos (all of them pass there too:
    run once, 117 s, 2026-11-29)."""
    model = MODELS[robot]()
    tests = None if robot in ("solo12", "panda") else ("test_schema", "test_autograd_registration", "test_faketensor")
    key = ft.model_key(model)
    st = _state(model, 6, (2,), grad=True)
    options = {"gravity": True, "frame": len(model.frames) - 1, "reference": 1}
    for name, op in ft.OPERATORS.items():
        decl = DECLARATIONS[name]
        differentiable = has_jacobians(name)
        args = (key, *(st[n] if differentiable and (n != "f_ext" or name in ("rnea", "aba")) else st[n].detach()
                       for n in decl.inputs), *(options[n] for n in decl.options))
        torch.library.opcheck(op, args, test_utils=tests) if tests else torch.library.opcheck(op, args)


def test_compile_fullgraph_of_several_operators_and_of_their_gradient() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 7, (4,))
    frame = model.frames[-1].name

    def f(q: torch.Tensor, v: torch.Tensor, a: torch.Tensor) -> torch.Tensor:
        tau = ft.rnea(model, q, v, a)
        qdd = ft.aba(model, q, v, tau)
        M = ft.crba(model, q)
        J = ft.frame_jacobian(model, q, frame, "world")
        k = ft.forward_kinematics(model, q, v)
        return (qdd - a).square().sum() + M.sum() + J.sum() + k.vel.sum()

    # aot_eager: Dynamo's capture (fullgraph: no graph break), the fake implementations and AOTAutograd's
    # backward, without Inductor's C++ code generation (CI runs this file where no compiler is installed)
    compiled = torch.compile(f, fullgraph=True, backend="aot_eager")
    q = st["q"].clone().requires_grad_()
    value = compiled(q, st["v"], st["a"])
    (grad,) = torch.autograd.grad(value, q)
    q2 = st["q"].clone().requires_grad_()
    value2 = f(q2, st["v"], st["a"])
    (grad2,) = torch.autograd.grad(value2, q2)
    torch.testing.assert_close(value, value2)
    torch.testing.assert_close(grad, grad2)
    # the gradient itself compiled: torch.func.grad inside the graph
    compiled_grad = torch.compile(torch.func.grad(lambda q: f(q, st["v"], st["a"])), fullgraph=True,
                                  backend="aot_eager")
    torch.testing.assert_close(compiled_grad(st["q"]), grad2)


def test_compiled_function_retraces_for_another_model() -> None:
    import dataclasses

    model = MODELS["panda"]()
    light = dataclasses.replace(model, gravity=np.asarray(model.gravity) * 0.5)
    st = _state(model, 8)
    compiled = torch.compile(lambda m, q: ft.generalized_gravity(m, q), fullgraph=True, backend="aot_eager")
    assert torch.equal(compiled(model, st["q"]), ft.generalized_gravity(model, st["q"]))
    assert torch.equal(compiled(light, st["q"]), ft.generalized_gravity(light, st["q"]))
    assert not torch.allclose(ft.generalized_gravity(light, st["q"]), ft.generalized_gravity(model, st["q"]))


def test_vmap_maps_the_batch_in_one_call_and_vectorized_jacobians_work() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 14, (3,))
    q, v, a = st["q"], st["v"], st["a"]
    r = torch.vmap(lambda q: ft.rnea(model, q, v, a))(q)  # q mapped, v and a (3, nv) unmapped: (3, 3, nv)
    assert r.shape == (3, 3, model.nv)
    for k in range(3):
        assert torch.equal(r[k], ft.rnea(model, q[k], v, a))
    vel = torch.vmap(lambda q, v: ft.forward_kinematics(model, q, v).vel, in_dims=(0, 1))(q, v.T)
    assert torch.equal(vel, ft.forward_kinematics(model, q, v).vel)
    panda = MODELS["panda"]()
    s = _state(panda, 15)
    dtau_dq = fd.rnea_derivatives(panda, s["q"].numpy(), s["v"].numpy(), s["a"].numpy())[0]
    J = torch.autograd.functional.jacobian(lambda q: ft.rnea(panda, q, s["v"], s["a"]), s["q"], vectorize=True)
    np.testing.assert_allclose(J.numpy(), dtau_dq, rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------------------------------ gradients

def _call(model: fd.Model, name: str, st: dict[str, torch.Tensor], reference: fd.ReferenceFrame = fd.LOCAL):
    """``ft.<name>`` as a function of its state inputs but ``f_ext`` (held), ``q`` through ``ft.normalize`` (the
    differences leave the unit quaternions), returning its outputs as a tuple; and those inputs."""
    decl = DECLARATIONS[name]
    moving = [n for n in decl.inputs if n != "f_ext"]
    options = {k: v for k, v in (("frame", model.frames[-1].name), ("reference", reference)) if k in decl.options}

    def f(*xs: torch.Tensor):  # type: ignore[no-untyped-def]
        given = dict(zip(moving, xs, strict=True))
        for c in ("q", "q0", "q1"):  # (the configurations)
            if c in given:
                given[c] = ft.normalize(model, given[c])
        if "f_ext" in decl.inputs:
            given["f_ext"] = st["f_ext"].detach()
        r = getattr(ft, name)(model, **{n: given.get(n) for n in decl.inputs}, **options)  # (by name: a point last)
        return tuple(r) if isinstance(r, tuple) else r

    return f, tuple(st[n] for n in moving)


@pytest.mark.parametrize("robot", ROBOTS)
def test_gradcheck_every_operator_with_jacobians(robot: str) -> None:
    """gradcheck, reverse and forward mode, on each operator with Jacobians (the frame functions in each reference
    frame). talos (nv = 50) and the outputs of more than 400 numbers in gradcheck's fast mode (random projections
    of the Jacobian: one backward and one forward-mode product each, not one per row and column)."""
    model = MODELS[robot]()
    st = _state(model, 6, grad=True)
    assert {"rnea", "aba", "crba", "nonlinear_effects", "mass_matrix_inverse", "forward_kinematics",
            "frame_placement", "frame_jacobian", "frame_velocity", "frame_classical_acceleration", "center_of_mass",
            "centroidal_momentum", "rnea_derivatives", "aba_derivatives"} <= set(FIRST)
    for name in FIRST:
        refs = fd.ReferenceFrame if "reference" in DECLARATIONS[name].options else [fd.LOCAL]
        for ref in refs:
            f, args = _call(model, name, st, ref)
            size = sum(o.numel() for o in (f(*args) if name in ("forward_kinematics", "placements", "frame_placement",
                                                                "center_of_mass")
                                           or len(DECLARATIONS[name].outputs) > 1 else (f(*args),)))
            fast = robot == "talos_full_v2" or size > 400
            # aba's and the inverse mass matrix's Jacobians reach 1e4 on talos: central differences are off by
            # ~1e-8 of that
            atol = 1e-3 if robot == "talos_full_v2" else 1e-5
            assert torch.autograd.gradcheck(f, args, atol=atol, fast_mode=fast, check_forward_ad=True), (name, ref)


def test_gradcheck_f_ext_and_a_shared_configuration() -> None:
    """f_ext's gradient and tangent (rnea, aba: api/jacobians.py's generalized force), and a configuration broadcast
    against a batch."""
    model = MODELS["solo12"]()
    st = _state(model, 9, grad=True)
    q, v, a, tau, f = st["q"], st["v"], st["a"], st["tau"], st["f_ext"]
    n = lambda q: ft.normalize(model, q)  # noqa: E731
    assert torch.autograd.gradcheck(lambda q, v, a, f: ft.rnea(model, n(q), v, a, f), (q, v, a, f),
                                     check_forward_ad=True)
    assert torch.autograd.gradcheck(lambda q, v, t, f: ft.aba(model, n(q), v, t, f), (q, v, tau, f),
                                     check_forward_ad=True)
    sb = _state(model, 10, (3,), grad=True)
    q0 = sb["q"][0].detach().clone().requires_grad_()  # (nq,) broadcast against (3, nv)
    assert torch.autograd.gradcheck(lambda q, v, a: ft.rnea(model, n(q), v, a), (q0, sb["v"], sb["a"]),
                                     check_forward_ad=True)


@pytest.mark.parametrize("robot", ROBOTS)
def test_gradgradcheck_where_second_derivatives_exist(robot: str) -> None:
    model = MODELS[robot]()
    st = _state(model, 11, grad=True)
    fast = robot != "panda"  # the floating ones in gradcheck's fast mode (random projections)
    for name in SECOND:
        f, args = _call(model, name, st)
        atol = 1e-3 if robot == "talos_full_v2" and name == "aba" else 1e-5
        assert torch.autograd.gradgradcheck(f, args, atol=atol, fast_mode=fast), name


@pytest.mark.parametrize("robot", ["panda", "solo12"])
def test_gradgradcheck_of_the_kinematics(robot: str) -> None:
    """Second order of the placements: their Jacobians are made of joint_jacobians, placements, frame_placement
    and frame_jacobian, which have their own (forward_kinematics: H and Hp, v and a held)."""
    model = MODELS[robot]()
    st = _state(model, 17, grad=True)
    for name in ("joint_jacobians", "placements", "frame_placement"):
        f, args = _call(model, name, st)
        assert torch.autograd.gradgradcheck(f, args, fast_mode=True), name
    f, (q, v, a) = _call(model, "forward_kinematics", st)
    assert torch.autograd.gradgradcheck(lambda q: f(q, v.detach(), a.detach())[:2], (q,), fast_mode=True)


def test_mixed_tree_first_and_second_order() -> None:
    """Every joint kind whose q is not its tangent (free-flyer, spherical, planar): rnea and aba."""
    model = MODELS["mixed_tree"]()
    st = _state(model, 11, grad=True)
    for name in ("rnea", "aba", "crba", "frame_placement"):
        f, args = _call(model, name, st)
        assert torch.autograd.gradcheck(f, args, check_forward_ad=True), name
    for name in ("rnea", "aba"):
        f, args = _call(model, name, st)
        assert torch.autograd.gradgradcheck(f, args, fast_mode=True), name


# ------------------------------------------------------------------------------------------ torch.func

def _numpy_state(model: fd.Model, seed: int) -> dict[str, np.ndarray]:
    s = random_state(model, seed)
    return {k: getattr(s, k) for k in ("q", "v", "a", "tau")}


@pytest.mark.parametrize("robot", ["panda", "solo12"])
def test_torch_func_grad_jacrev_jacfwd_are_the_declared_derivatives(robot: str) -> None:
    model = MODELS[robot]()
    s = _numpy_state(model, 4)
    q, v, a, tau = (torch.tensor(s[k]) for k in ("q", "v", "a", "tau"))
    dq, dv, M = fd.rnea_derivatives(model, s["q"], s["v"], s["a"])
    w = torch.tensor(np.random.default_rng(5).normal(size=model.nv))
    tol = {"rtol": 1e-12, "atol": 1e-12}
    torch.testing.assert_close(torch.func.grad(lambda v: ft.rnea(model, q, v, a) @ w)(v).numpy(), dv.T @ w.numpy(),
                               **tol)
    torch.testing.assert_close(torch.func.jacrev(lambda a: ft.rnea(model, q, v, a))(a).numpy(), M, **tol)
    gq = torch.func.grad(lambda q: ft.rnea(model, q, v, a) @ w)(q)
    torch.testing.assert_close(ft.tangent_grad(model, q, gq).numpy(), dq.T @ w.numpy(), rtol=1e-10,
                               atol=1e-10 * max(1.0, float(np.abs(dq).max())))
    _, ddq_dv, Minv = fd.aba_derivatives(model, s["q"], s["v"], s["tau"])
    J = torch.func.jacfwd(lambda x: ft.aba(model, q, x[0], x[1]))(torch.stack([v, tau]))
    torch.testing.assert_close(J[:, 0].numpy(), ddq_dv, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(ddq_dv).max()))
    torch.testing.assert_close(J[:, 1].numpy(), Minv, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(Minv).max()))
    # q in coordinates: the tangent's Jacobian composed with the coordinates' map, forward and reverse
    E = torch.func.jacfwd(lambda d: ft.coordinates_of_tangent(model, q, d))(torch.zeros(model.nv,
                                                                                         dtype=torch.float64))
    dg = fd.generalized_gravity_derivatives(model, s["q"])
    for jac in (torch.func.jacfwd, torch.func.jacrev):
        Jq = jac(lambda q: ft.generalized_gravity(model, q))(q)
        torch.testing.assert_close((Jq @ E).numpy(), dg, rtol=1e-10, atol=1e-10 * max(1.0, np.abs(dg).max()))
    # a frame's Jacobian is the derivative of its velocity (fd.frame_velocity_derivatives.dv_dv)
    frame = model.frames[-1].name
    Jv = torch.func.jacrev(lambda v: ft.frame_velocity(model, q, v, frame, "world"))(v)
    torch.testing.assert_close(Jv, ft.frame_jacobian(model, q, frame, "world"), rtol=1e-12, atol=1e-12)


def test_torch_func_hessian_is_the_second_derivatives() -> None:
    """torch.func.hessian (jacfwd of jacrev) of w·rnea: in v, w·d2tau_dv2 exactly; in the tangent (q ⊕ δ at
    δ = 0), the symmetric part of w·d2tau_dq2 (the tangent's second derivative of q ↦ τ)."""
    model = MODELS["solo12"]()
    s = _numpy_state(model, 8)
    q, v, a = (torch.tensor(s[k]) for k in ("q", "v", "a"))
    w = np.random.default_rng(9).normal(size=model.nv)
    wt = torch.tensor(w)
    S = fd.rnea_second_derivatives(model, s["q"], s["v"], s["a"])
    Hv = torch.func.hessian(lambda v: ft.rnea(model, q, v, a) @ wt)(v)
    torch.testing.assert_close(Hv.numpy(), np.einsum("i,ijk->jk", w, S.d2tau_dv2), rtol=1e-10, atol=1e-10)
    zero = torch.zeros(model.nv, dtype=torch.float64)
    Hq = torch.func.hessian(lambda d: ft.rnea(model, ft.coordinates_of_tangent(model, q, d) + q, v, a) @ wt)(zero)
    ref = np.einsum("i,ijk->jk", w, S.d2tau_dq2)
    Hq = Hq.numpy()
    assert np.abs(Hq - Hq.T).max() <= 1e-9 * max(1.0, np.abs(Hq).max())
    np.testing.assert_allclose(Hq, 0.5 * (ref + ref.T), rtol=1e-6, atol=1e-6 * max(1.0, np.abs(ref).max()))
    # the mixed block by double backward (torch.autograd.grad, create_graph): ∂²(w·τ)/∂q̇∂q̈ = 0, ∂(w·M q̈)/∂q
    v_ = v.clone().requires_grad_()
    (gv,) = torch.autograd.grad(ft.rnea(model, q, v_, a) @ wt, v_, create_graph=True)
    (Hvv,) = torch.autograd.grad(gv @ wt, v_)
    torch.testing.assert_close(Hvv.numpy(), np.einsum("i,ijk,j->k", w, S.d2tau_dv2, w), rtol=1e-10, atol=1e-10)


def test_torch_func_vmap_of_grad_is_the_loop() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 16, (4,))
    q, v, a = st["q"], st["v"], st["a"]
    w = torch.tensor(np.random.default_rng(3).normal(size=model.nv))
    loss = lambda q, v: ft.aba(model, q, v, a[0]) @ w  # noqa: E731
    g = torch.func.vmap(torch.func.grad(loss, argnums=(0, 1)))(q, v)
    for k in range(4):
        q_, v_ = q[k].clone().requires_grad_(), v[k].clone().requires_grad_()
        want = torch.autograd.grad(loss(q_, v_), (q_, v_))
        torch.testing.assert_close(g[0][k], want[0], rtol=1e-12, atol=1e-12)
        torch.testing.assert_close(g[1][k], want[1], rtol=1e-12, atol=1e-12)
    # float32 in forward mode too: the tangents have the outputs' dtype
    J32 = torch.func.jacfwd(lambda v: ft.rnea(model, q[0].float(), v, a[0].float()))(v[0].float())
    assert J32.dtype == torch.float32


def test_tangent_grad_is_the_derivative_along_integrate() -> None:
    model = MODELS["mixed_tree"]()
    st = _state(model, 12)
    w = torch.tensor(np.random.default_rng(0).normal(size=model.nv))
    q = st["q"].clone().requires_grad_()

    def loss_np(qn: np.ndarray) -> float:  # featherdyn and a plain function of the coordinates
        return float(fd.rnea(model, qn, st["v"].numpy(), st["a"].numpy()) @ w.numpy() + np.sum(qn ** 3))

    loss = ft.rnea(model, q, st["v"], st["a"]) @ w + torch.sum(q ** 3)
    (g,) = torch.autograd.grad(loss, q)
    gt = ft.tangent_grad(model, q.detach(), g)
    eps = 1e-6
    fdiff = [(loss_np(fd.integrate(model, st["q"].numpy(), eps * e)) -
              loss_np(fd.integrate(model, st["q"].numpy(), -eps * e))) / (2 * eps) for e in np.eye(model.nv)]
    np.testing.assert_allclose(gt.numpy(), fdiff, rtol=1e-6, atol=1e-6)
    # featherdyn's tangent gradient is the declared derivative's: w · ∂τ/∂q
    (g_rnea,) = torch.autograd.grad(ft.rnea(model, q, st["v"], st["a"]) @ w, q)
    dtau_dq = fd.rnea_derivatives(model, st["q"].numpy(), st["v"].numpy(), st["a"].numpy())[0]
    np.testing.assert_allclose(ft.tangent_grad(model, q.detach(), g_rnea).numpy(), w.numpy() @ dtau_dq,
                               rtol=1e-12, atol=1e-10)
    # and tangent_to_coordinates is its inverse on such gradients
    gt2 = torch.tensor(np.random.default_rng(1).normal(size=model.nv))
    torch.testing.assert_close(ft.tangent_grad(model, q.detach(),
                                               ft.tangent_to_coordinates(model, q.detach(), gt2)), gt2)
    # coordinates_of_tangent is the direction of fd.integrate
    d = torch.tensor(np.random.default_rng(2).normal(size=model.nv))
    h = 1e-7
    qn = st["q"].numpy()
    np.testing.assert_allclose(ft.coordinates_of_tangent(model, st["q"], d).numpy(),
                               (fd.integrate(model, qn, h * d.numpy()) - fd.integrate(model, qn, -h * d.numpy()))
                               / (2 * h), atol=1e-7)


def test_a_missing_derivative_raises_a_featherdyn_error() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 13, grad=True)
    Y = ft.joint_torque_regressor(model, st["q"], st["v"], st["a"])
    with pytest.raises(fd.FeatherdynError, match="derivative of joint_torque_regressor is not available"):
        Y.sum().backward()
    with pytest.raises(fd.FeatherdynError, match="derivative of joint_torque_regressor is not available"):
        torch.func.jacfwd(lambda q: ft.joint_torque_regressor(model, q, st["v"], st["a"]))(st["q"].detach())
    # third order: crba's ∂²M/∂q² is rnea_derivatives' derivative, fd.rnea_second_derivatives, which has none
    (g,) = torch.autograd.grad(ft.crba(model, st["q"]).sum(), st["q"], create_graph=True)
    (h,) = torch.autograd.grad(g.sum(), st["q"], create_graph=True)
    with pytest.raises(fd.FeatherdynError, match="derivative of rnea_second_derivatives is not available"):
        h.sum().backward()
    # f_ext: first derivatives of rnea and aba only
    y = ft.rnea(model, st["q"], st["v"], st["a"], st["f_ext"])
    (g,) = torch.autograd.grad(y.sum(), st["q"], create_graph=True)
    with pytest.raises(fd.FeatherdynError, match="rnea_derivatives with respect to f_ext is not available"):
        torch.autograd.grad(g.sum(), st["f_ext"])


CONTACTS = {"solo12": [("FL_FOOT", fd.LOCAL), ("FR_FOOT", fd.WORLD), ("HL_FOOT", fd.LOCAL_WORLD_ALIGNED),
                       ("HR_FOOT", fd.LOCAL)],
            "talos_full_v2": [("left_sole_link", fd.LOCAL), ("right_sole_link", fd.LOCAL_WORLD_ALIGNED)]}


@pytest.mark.parametrize("name", sorted(CONTACTS))
def test_constrained_and_impulse_dynamics(name: str) -> None:
    """ft.constrained_dynamics / ft.impulse_dynamics: the NumPy functions' values bit for bit, gradcheck in both
    modes against finite differences (their derivative functions), torch.func.grad against
    fd.constrained_dynamics_derivatives, vmap in one call, and a second derivative refused."""
    model = _robot(name, True)
    point = name == "solo12"
    cs = [fd.PointContact(f, r) if point else fd.FrameContact(f, r) for f, r in CONTACTS[name]]
    rng = np.random.default_rng(21)
    q0 = fd.random_configuration(model, rng)
    v0, t0 = rng.normal(size=(2, model.nv))
    q, v, tau = (torch.tensor(x, requires_grad=True) for x in (q0, v0, t0))
    r, ref = ft.constrained_dynamics(model, q, v, tau, cs), fd.constrained_dynamics(model, q0, v0, t0, cs)
    np.testing.assert_array_equal(r.ddq.detach().numpy(), ref.ddq)
    np.testing.assert_array_equal(r.lagrange.detach().numpy(), ref.lagrange)
    assert [f.shape[-1] for f in r.forces] == [3 if point else 6] * len(cs)
    i = ft.impulse_dynamics(model, q, v, cs, restitution=0.4)
    np.testing.assert_array_equal(i.v_plus.detach().numpy(),
                                  fd.impulse_dynamics(model, q0, v0, cs, restitution=0.4).v_plus)
    fast = not point  # (talos: 50 columns)

    def f(q: torch.Tensor, v: torch.Tensor, t: torch.Tensor) -> tuple[torch.Tensor, ...]:
        out = ft.constrained_dynamics(model, ft.normalize(model, q), v, t, cs)
        return out.ddq, out.lagrange

    # talos: accelerations of ~1e4 under its sole contacts; central differences carry ~1e-3 of rounding there
    eps, atol = (1e-5, 1e-3) if fast else (1e-6, 1e-5)
    assert torch.autograd.gradcheck(f, (q, v, tau), eps=eps, atol=atol, rtol=1e-5, fast_mode=fast)
    assert torch.autograd.gradcheck(f, (q, v, tau), eps=eps, atol=atol, rtol=1e-5, fast_mode=fast, check_forward_ad=True,
                                    check_backward_ad=False, check_undefined_grad=False)
    assert torch.autograd.gradcheck(lambda q, v: ft.impulse_dynamics(model, ft.normalize(model, q), v, cs,
                                                                     restitution=0.4).v_plus,
                                    (q, v), eps=eps, atol=atol, rtol=1e-5, fast_mode=fast)
    d = fd.constrained_dynamics_derivatives(model, q0, v0, t0, cs)
    w = torch.tensor(rng.normal(size=model.nv))
    gv = torch.func.grad(lambda v: ft.constrained_dynamics(model, q.detach(), v, tau.detach(), cs).ddq @ w)(
        v.detach())
    np.testing.assert_allclose(gv.numpy(), d.ddq_dv.T @ w.numpy(), rtol=1e-12, atol=1e-12 * np.abs(d.ddq_dv).max())
    Q = torch.tensor(fd.random_configuration(model, rng, size=3))
    V = torch.tensor(rng.normal(size=(3, model.nv)))
    batch = torch.func.vmap(lambda q, v: ft.constrained_dynamics(model, q, v, tau.detach(), cs).ddq)(Q, V)
    np.testing.assert_array_equal(batch.numpy(), fd.constrained_dynamics(model, Q.numpy(), V.numpy(), t0, cs).ddq)
    (g,) = torch.autograd.grad(r.ddq @ w, v, create_graph=True)
    with pytest.raises(fd.FeatherdynError, match="second derivative of constrained dynamics"):
        torch.autograd.grad(g.sum(), v)
    with pytest.raises(fd.FeatherdynError, match="second derivative"):
        torch.func.hessian(lambda v: ft.constrained_dynamics(model, q.detach(), v, tau.detach(), cs).ddq @ w)(
            v.detach())
    f_ext = torch.zeros(model.nbodies, 6, dtype=torch.float64, requires_grad=True)
    with pytest.raises(fd.FeatherdynError, match="f_ext"):
        torch.autograd.grad(ft.constrained_dynamics(model, q, v, tau, cs, f_ext).ddq.sum(), f_ext)


def test_the_contact_functions_under_torch_compile_run_eagerly() -> None:
    """ft.constrained_dynamics / ft.impulse_dynamics are ``torch.compiler.disable``d (Dynamo cannot take the
    constraint objects into a graph; before, it failed inside Dynamo): a compiled function around them gives the
    eager values and gradients with a graph break, and ``fullgraph=True`` refuses them with Dynamo's message."""
    model = _robot("solo12", True)
    cs = [fd.PointContact(f, r) for f, r in CONTACTS["solo12"]]
    rng = np.random.default_rng(23)
    q = torch.tensor(fd.random_configuration(model, rng))
    v, tau = (torch.tensor(rng.normal(size=model.nv), requires_grad=True) for _ in range(2))

    def f(q: torch.Tensor, v: torch.Tensor, tau: torch.Tensor) -> torch.Tensor:
        r = ft.constrained_dynamics(model, q, v, tau, cs)
        return (r.ddq ** 2).sum() + ft.impulse_dynamics(model, q, v, cs, restitution=0.5).v_plus.sum()

    compiled = torch.compile(f, backend="aot_eager")
    y, y_eager = compiled(q, v, tau), f(q, v, tau)
    assert torch.equal(y, y_eager)
    for g, g_eager in zip(torch.autograd.grad(y, (v, tau)), torch.autograd.grad(y_eager, (v, tau)), strict=True):
        assert torch.equal(g, g_eager)

    def whole(q: torch.Tensor, v: torch.Tensor, tau: torch.Tensor) -> torch.Tensor:  # (its own code: its own cache)
        return ft.constrained_dynamics(model, q, v, tau, cs).ddq.sum()

    with pytest.raises(Exception, match="disable"):
        torch.compile(whole, fullgraph=True, backend="aot_eager")(q, v, tau)


@pytest.mark.parametrize("name", ["rnea", "aba"])
def test_backward_of_the_dynamics_forms_no_jacobian(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """``.backward()`` of ``wᵀ rnea`` / ``wᵀ aba`` runs ``fd.rnea_vjp`` / ``fd.aba_vjp`` (api/jacobians.py's VJPS),
    never the Jacobian table (patched to fail here): the gradients in ``q`` (coordinates), ``v``, ``a``/``τ`` and
    ``f_ext`` equal those of the table's path (a graph built: ``create_graph=True``) on a batch."""
    from featherdyn.api import jacobians

    model = _robot("solo12", True)
    st = _state(model, 31, size=(3,), grad=True)
    x = [st["q"], st["v"], st["a" if name == "rnea" else "tau"], st["f_ext"]]
    w = torch.tensor(np.random.default_rng(32).normal(size=(3, model.nv)))
    f = getattr(ft, name)
    expected = torch.autograd.grad((w * f(model, *x)).sum(), x, create_graph=True)  # (the Jacobians' path)

    def refused(*args: object, **kwargs: object) -> None:
        raise AssertionError("the backward formed the Jacobian table")

    monkeypatch.setattr(jacobians, "jacobians", refused)
    got = torch.autograd.grad((w * f(model, *x)).sum(), x)
    for g, e in zip(got, expected, strict=True):
        torch.testing.assert_close(g, e.detach(), rtol=1e-10, atol=1e-10)
    with pytest.raises(AssertionError, match="Jacobian table"):  # (the patch is in the path of a double backward)
        torch.autograd.grad((w * f(model, *x)).sum(), x, create_graph=True)
