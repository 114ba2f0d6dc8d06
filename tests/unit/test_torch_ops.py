"""featherdyn.torch: the declared functions as PyTorch operators (docs/frameworks.md).

Values against the NumPy functions (bit for bit in float64), float32, batches, the featherdyn errors,
``torch.library.opcheck`` on every operator, ``torch.compile(fullgraph=True)``, and the gradients:
``gradcheck`` (finite differences in ``q``'s coordinates, against the analytical backward) on every operator
with a derivative, ``gradgradcheck`` on ``rnea`` and ``aba``, on panda (fixed), solo12 and talos_full_v2
(floating) and a random tree with spherical and planar joints; the tangent gradient against a finite difference
along ``fd.integrate``.

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
from featherdyn.api.declared import Record  # noqa: E402


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
    return {k: torch.tensor(getattr(s, k), requires_grad=grad) for k in ("q", "v", "a", "tau", "f_ext")}


def _args(decl, model, st, frame=None):  # type: ignore[no-untyped-def]
    """The positional arguments of ft.<name> / fd.<name> for a declaration (inputs, then frame and reference)."""
    args = [st["a"] if n == "a" else st[n] for n in decl.inputs]
    if "frame" in decl.options:
        args.append(frame if frame is not None else model.frames[-1].name)
    if "reference" in decl.options:
        args.append("world")
    return args


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

def test_opcheck_on_every_operator() -> None:
    model = MODELS["solo12"]()
    key = ft.model_key(model)
    st = _state(model, 6, (2,), grad=True)
    options = {"gravity": True, "frame": len(model.frames) - 1, "reference": 1}
    for name, op in ft.OPERATORS.items():
        decl = DECLARATIONS[name]
        differentiable = name in ft.VJP_OPERATORS  # (the others' backward raises: they take constants here)
        args = (key, *(st[n] if differentiable else st[n].detach() for n in decl.inputs),
                *(options[n] for n in decl.options))
        torch.library.opcheck(op, args)
        if name in ft.VJP_OPERATORS:  # (f_ext has first derivatives only: a constant of the VJP here)
            second = name in ("rnea", "aba")  # the others' VJP has no derivative: constants here
            args = tuple(a.detach() if a is st["f_ext"] or (torch.is_tensor(a) and not second) else a for a in args)
            ybar = torch.ones_like(op(*args)).requires_grad_(second)
            torch.library.opcheck(ft.VJP_OPERATORS[name], (*args, ybar))


def test_compile_fullgraph_of_several_operators() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 7, (4,))
    frame = model.frames[-1].name

    def f(q: torch.Tensor, v: torch.Tensor, a: torch.Tensor) -> torch.Tensor:
        tau = ft.rnea(model, q, v, a)
        qdd = ft.aba(model, q, v, tau)
        M = ft.crba(model, q)
        J = ft.frame_jacobian(model, q, frame, "world")
        k = ft.forward_kinematics(model, q, v)
        return (qdd - a).square().sum() + M.sum() + (J.sum() + k.vel.sum()).detach()

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
    J = torch.autograd.functional.jacobian(lambda q: ft.rnea(panda, q, s["v"], s["a"]), s["q"], vectorize=True)
    dtau_dq = fd.rnea_derivatives(panda, s["q"].numpy(), s["v"].numpy(), s["a"].numpy())[0]
    np.testing.assert_allclose(J.numpy(), dtau_dq, rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------------------------------ gradients

@pytest.mark.parametrize("robot", ["panda", "solo12", "talos_full_v2", "mixed_tree"])
def test_gradcheck_first_order(robot: str) -> None:
    model = MODELS[robot]()
    st = _state(model, 9, grad=True)
    q, v, a, tau, f = st["q"], st["v"], st["a"], st["tau"], st["f_ext"]
    # talos (nv = 50): gradcheck's fast mode (random projections of the Jacobians: one backward each, not nv²)
    fast = robot == "talos_full_v2"

    def gc(fn, inputs, atol=1e-5):  # type: ignore[no-untyped-def]
        return torch.autograd.gradcheck(fn, inputs, atol=atol, fast_mode=fast)

    assert gc(lambda q, v, a, f: ft.rnea(model, q, v, a, f), (q, v, a, f))
    # talos' ∂q̈/∂q reaches 4e4 (∂q̈/∂f_ext 1e5): central differences of q̈ are off by ~1e-4 there (1e-8 relative)
    atol = 1e-3 if robot == "talos_full_v2" else 1e-5
    assert gc(lambda q, v, t, f: ft.aba(model, q, v, t, f), (q, v, tau, f), atol=atol)
    assert gc(lambda q: ft.generalized_gravity(model, q), (q,))
    assert gc(lambda q: ft.crba(model, q), (q,))
    assert gc(lambda q, v, a: ft.rnea(model, q, v, a, gravity=False), (q, v, a))


def test_gradcheck_on_a_batch_with_a_shared_configuration() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 10, (3,), grad=True)
    q = st["q"][0].detach().clone().requires_grad_()  # (nq,) broadcast against (3, nv)
    assert torch.autograd.gradcheck(lambda q, v, a: ft.rnea(model, q, v, a), (q, st["v"], st["a"]))


@pytest.mark.parametrize("robot", ["panda", "solo12", "mixed_tree"])
def test_gradgradcheck_rnea_and_aba(robot: str) -> None:
    model = MODELS[robot]()
    st = _state(model, 11, grad=True)
    q, v, a, tau = st["q"], st["v"], st["a"], st["tau"]
    fast = robot != "panda"  # the floating ones in gradcheck's fast mode (random projections; ~40 s each in full)
    assert torch.autograd.gradgradcheck(lambda q, v, a: ft.rnea(model, q, v, a), (q, v, a), fast_mode=fast)
    assert torch.autograd.gradgradcheck(lambda q, v, t: ft.aba(model, q, v, t), (q, v, tau), fast_mode=fast)


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


def test_a_missing_derivative_raises_a_featherdyn_error_at_backward() -> None:
    model = MODELS["solo12"]()
    st = _state(model, 13, grad=True)
    J = ft.frame_jacobian(model, st["q"], model.frames[-1].name)
    with pytest.raises(fd.FeatherdynError, match="derivative of frame_jacobian is not available"):
        J.sum().backward()
    # third order: the second-derivative operators have none
    y = ft.generalized_gravity(model, st["q"])
    (g,) = torch.autograd.grad(y.sum(), st["q"], create_graph=True)
    with pytest.raises(fd.FeatherdynError, match="second derivative of generalized_gravity is not available"):
        g.sum().backward()
    y = ft.rnea(model, st["q"], st["v"], st["a"], st["f_ext"])
    (g,) = torch.autograd.grad(y.sum(), st["q"], create_graph=True)
    with pytest.raises(fd.FeatherdynError, match="with respect to f_ext is not available"):
        torch.autograd.grad(g.sum(), st["f_ext"])
