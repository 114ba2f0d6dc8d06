"""``fd.compile(model)``: the core bound to one model — same numbers and same errors as the public functions.

The single-state methods hand their arguments to the binding as they are and
take the core's general path for anything else; the batched methods are the
core's batched calls. Compared against ``fd.rnea`` & co. (which the core tests
compare with the reference), bit for bit.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest
from _core_helpers import robot

import featherdyn as fd
from featherdyn.errors import NonFiniteError, QuaternionNormError, ShapeError, SingularMassMatrixError


@pytest.fixture(scope="module")
def solo() -> fd.Model:
    model = robot("solo12", True)
    assert model is not None
    return model


def _state(model: fd.Model, seed: int, size: int | None = None) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    shape = () if size is None else (size,)
    q = fd.random_configuration(model, rng, size=size)
    return q, rng.normal(size=shape + (model.nv,)), rng.normal(size=shape + (model.nv,))


def test_single_state_methods_equal_the_public_functions(solo: fd.Model) -> None:
    cm = fd.compile(solo)
    q, v, a = _state(solo, 1)
    f = np.random.default_rng(2).normal(size=(solo.nbodies, 6))
    tau = fd.rnea(solo, q, v, a)
    assert np.array_equal(cm.rnea(q, v, a), tau)
    assert np.array_equal(cm.rnea(q, v, a, f_ext=f), fd.rnea(solo, q, v, a, f))
    assert np.array_equal(cm.nle(q, v), fd.nonlinear_effects(solo, q, v))
    assert np.array_equal(cm.gravity(q), fd.generalized_gravity(solo, q))
    assert np.array_equal(cm.crba(q), fd.crba(solo, q))
    assert np.array_equal(cm.aba(q, v, tau), fd.aba(solo, q, v, tau))
    assert np.array_equal(cm.fk(q)[:, :3, 3], fd.forward_kinematics(solo, q).placements.translation)
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        assert np.array_equal(cm.frame_jacobian(q, "HR_FOOT", ref), fd.frame_jacobian(solo, q, "HR_FOOT", ref))


def test_out_is_written_and_converted_inputs_agree(solo: fd.Model) -> None:
    cm = fd.compile(solo)
    q, v, a = _state(solo, 3)
    out = np.empty(solo.nv)
    assert cm.rnea(q, v, a, out=out) is out
    assert np.array_equal(out, fd.rnea(solo, q, v, a))
    M = np.empty((solo.nv, solo.nv))
    assert cm.crba(q, out=M) is M
    # lists, float32 and strided arrays take the general path and give the converted state's numbers
    assert np.array_equal(cm.rnea(list(q), list(v), list(a)), fd.rnea(solo, q, v, a))
    strided = np.repeat(q, 2)[::2]
    assert np.array_equal(cm.crba(strided), fd.crba(solo, q))
    q32 = q.astype(np.float32)
    assert np.array_equal(cm.gravity(q32), fd.generalized_gravity(solo, q32.astype(np.float64)))
    with pytest.raises(ShapeError, match="out: expected shape"):
        cm.rnea(q, v, a, out=np.empty(solo.nv + 1))


def test_bad_input_raises_what_the_public_functions_raise(solo: fd.Model) -> None:
    cm = fd.compile(solo)
    q, v, a = _state(solo, 4)
    cases = [
        ((q[:-1], v, a), ShapeError),
        ((q, np.full(solo.nv, np.nan), a), NonFiniteError),
        ((np.concatenate([q[:3], 2 * q[3:7], q[7:]]), v, a), QuaternionNormError),
    ]
    for args, error in cases:
        with pytest.raises(error) as mine:
            cm.rnea(*args)
        with pytest.raises(error) as public:
            fd.rnea(solo, *args)
        assert str(mine.value) == str(public.value)


def test_singular_aba_names_the_joint() -> None:
    b = fd.ModelBuilder("massless")
    b.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), joint_name="j",
               inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        model = b.build()
    with pytest.raises(SingularMassMatrixError, match="'j'"):
        fd.compile(model).aba(np.zeros(1), np.zeros(1), np.zeros(1))


def test_batched_methods_equal_the_public_batches(solo: fd.Model) -> None:
    cm = fd.compile(solo)
    Q, V, A = _state(solo, 5, size=9)
    TAU = cm.rnea_batch(Q, V, A)
    assert np.array_equal(TAU, fd.rnea(solo, Q, V, A))
    assert np.array_equal(cm.crba_batch(Q), fd.crba(solo, Q))
    assert np.array_equal(cm.aba_batch(Q, V, TAU), fd.aba(solo, Q, V, TAU))
    assert np.array_equal(cm.fk_batch(Q)[..., :3, 3], fd.forward_kinematics(solo, Q).placements.translation)
    assert np.array_equal(cm.frame_jacobian_batch(Q, "HR_FOOT", fd.WORLD),
                          fd.frame_jacobian(solo, Q, "HR_FOOT", fd.WORLD))


def test_one_compiled_model_shared_by_threads(solo: fd.Model) -> None:
    """The core's scratch is per thread: one CompiledModel serves several threads at once."""
    cm = fd.compile(solo)
    states = [_state(solo, 10 + k) for k in range(6)]
    expected = [fd.crba(solo, q) for q, _, _ in states]
    errors: list[str] = []

    def work(k: int) -> None:
        q = states[k][0]
        for _ in range(200):
            if not np.array_equal(cm.crba(q), expected[k]):
                errors.append(f"thread {k}")
                return

    threads = [threading.Thread(target=work, args=(k,)) for k in range(len(states))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors


def test_compile_refuses_what_is_not_a_model() -> None:
    with pytest.raises(fd.errors.ModelError, match="expected a featherdyn Model"):
        fd.compile("panda")  # type: ignore[arg-type]


def test_frame_jacobian_refuses_integer_reference_codes_as_the_public_function_does() -> None:
    """``cm.frame_jacobian(q, frame, 1)`` is refused like ``fd.frame_jacobian(model, q, frame, 1)``: the core's
    integer codes are not public (issue: they were taken as WORLD / LOCAL_WORLD_ALIGNED)."""
    import featherdyn as fd
    from featherdyn.errors import ShapeError

    model = fd.load_robot("panda")
    cm = fd.compile(model, warmup=False)
    q = fd.neutral(model)
    frame = model.frames[-1].name
    for code in (1, np.int64(2), 0, True):
        with pytest.raises(ShapeError, match="reference"):
            fd.frame_jacobian(model, q, frame, code)
        with pytest.raises(ShapeError, match="reference"):
            cm.frame_jacobian(q, frame, code)
        with pytest.raises(ShapeError, match="reference"):
            cm.frame_jacobian_batch(q[None], frame, code)
    assert np.array_equal(cm.frame_jacobian(q, frame, "world"), fd.frame_jacobian(model, q, frame, fd.WORLD))


_ARM = """<mujoco><worldbody><body name="l1"><joint name="j1" type="hinge" axis="0 1 0" armature="0.5"/>
<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
<body name="l2" pos="0.5 0 0"><joint name="j2" type="hinge" axis="0 1 0" armature="0.5"/>
<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/></body></body></worldbody></mujoco>"""


def test_out_sharing_memory_with_an_input_gives_the_result_without_out() -> None:
    """The one rule for out= (hostile input round 3, items 1 and 2): an out that is, or overlaps, an input gives the
    same result as a fresh one — cm.rnea(q, v, a, out=a) on a model with armature read q̈ where τ was being
    written (error 3.1); cm.frame_jacobian(q, frame, out=J) with J over q's memory read a q being overwritten."""
    import featherdyn as fd

    arm = fd.load_mjcf(_ARM)
    assert np.any(arm.armature > 0)
    rng = np.random.default_rng(12)
    cm = fd.compile(arm, warmup=False)
    q, v, a = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2)
    expected = cm.rnea(q, v, a)
    for name, args, k in (("rnea", (q, v, a), 2), ("rnea", (q, v, a), 1), ("rnea", (q, v, a), 0),
                          ("aba", (q, v, a), 2), ("nle", (q, v), 1)):
        inputs = [x.copy() for x in args]
        want = getattr(cm, name)(*inputs)
        got = getattr(cm, name)(*inputs, out=inputs[k])
        assert got is inputs[k] and np.array_equal(got, want), (name, k)
        assert np.array_equal(getattr(fd, {"nle": "nonlinear_effects"}.get(name, name))(arm, *args), want)
    assert np.array_equal(expected, fd.rnea(arm, q, v, a))
    panda = robot("panda", False)
    assert panda is not None
    cmp_ = fd.compile(panda, warmup=False)
    q = fd.random_configuration(panda, rng)
    frame = panda.frames[-1].name
    for method, shape, call in (
            ("frame_jacobian", (6, panda.nv), lambda qq, out: cmp_.frame_jacobian(qq, frame, fd.WORLD, out=out)),
            ("crba", (panda.nv, panda.nv), lambda qq, out: cmp_.crba(qq, out=out)),
            ("gravity", (panda.nv,), lambda qq, out: cmp_.gravity(qq, out=out)),
            ("fk", (panda.nbodies, 4, 4), lambda qq, out: cmp_.fk(qq, out=out))):
        want = call(q.copy(), None)
        n = int(np.prod(shape))
        for start in (0, 3, panda.nq - 1):  # J's memory from inside q's on
            buf = np.zeros(panda.nq + n + 8)
            buf[start:start + panda.nq] = q
            qq = buf[start:start + panda.nq]
            out = buf[start + 1:start + 1 + n].reshape(shape)
            got = call(qq, out)
            assert got is out and np.array_equal(got, want), (method, start)


def test_batches_with_out_sharing_memory_with_an_input_give_the_result_without_out() -> None:
    """The same rule for the batched methods: an input that shares memory with out is read from a copy."""
    import featherdyn as fd

    arm = fd.load_mjcf(_ARM)
    cm = fd.compile(arm, warmup=False)
    rng = np.random.default_rng(13)
    Q, V, A = (rng.normal(size=(5, 2)) for _ in range(3))
    for name, k in (("rnea_batch", 2), ("rnea_batch", 0), ("aba_batch", 2), ("aba_batch", 1)):
        inputs = [Q.copy(), V.copy(), A.copy()]
        want = getattr(cm, name)(*inputs)
        got = getattr(cm, name)(*inputs, out=inputs[k])
        assert got is inputs[k] and np.array_equal(got, want), (name, k)
    # the derivatives' three outputs over the inputs' memory
    buf = np.zeros(3 * 5 * 4 + 3 * 5 * 2)
    q, v, a = (buf[10 * i:10 * i + 10].reshape(5, 2) for i in range(3))
    q[...], v[...], a[...] = Q, V, A
    want = cm.rnea_derivatives_batch(Q, V, A)
    outs = tuple(buf[4 + 20 * i:4 + 20 * i + 20].reshape(5, 2, 2) for i in range(3))
    got = cm.rnea_derivatives_batch(q, v, a, out=outs)
    assert all(g is o and np.array_equal(g, w) for g, o, w in zip(got, outs, want, strict=True))
    panda = robot("panda", False)
    assert panda is not None
    cmp_ = fd.compile(panda, warmup=False)
    Qp = fd.random_configuration(panda, rng, size=(3,))
    frame = panda.frames[-1].name
    want = cmp_.frame_jacobian_batch(Qp, frame, fd.WORLD)
    buf = np.zeros(Qp.size + want.size)
    qs = buf[:Qp.size].reshape(Qp.shape)
    qs[...] = Qp
    out = buf[5:5 + want.size].reshape(want.shape)
    assert np.array_equal(cmp_.frame_jacobian_batch(qs, frame, fd.WORLD, out=out), want)
