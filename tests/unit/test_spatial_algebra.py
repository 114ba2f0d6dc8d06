"""Unit tests of featherdyn.spatial_algebra: the classes, their operators, the
raw-array kernels, the input checks and the error messages.

Expected values come from formulas written out here or in ``conftest.py``
(chapter §2–§5, appendix A, Featherstone's spatial_v2), never from the code
under test.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import (
    DTypeError,
    InertiaError,
    NonFiniteError,
    RotationError,
    ShapeError,
    SpatialTypeError,
)
from featherdyn.testing import assert_close

# --------------------------------------------------------------------------
# constructors and accessors
# --------------------------------------------------------------------------


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_constructor_stacks_angular_then_linear(cls, batch_shape, dtype, samples):
    ang = samples.array(batch_shape, (3,), dtype)
    lin = samples.array(batch_shape, (3,), dtype)
    x = cls(ang, lin)
    assert x.vector.shape == batch_shape + (6,)
    assert x.shape == batch_shape
    assert x.vector.dtype == dtype and x.dtype == dtype
    np.testing.assert_array_equal(x.vector[..., :3], ang)
    np.testing.assert_array_equal(x.vector[..., 3:], lin)
    np.testing.assert_array_equal(x.angular, ang)
    np.testing.assert_array_equal(x.linear, lin)


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_constructor_broadcasts_parts(cls):
    x = cls(np.array([1.0, 2.0, 3.0]), np.arange(18.0).reshape(2, 3, 3))
    assert x.shape == (2, 3)
    np.testing.assert_array_equal(x.angular, np.broadcast_to([1.0, 2.0, 3.0], (2, 3, 3)))
    np.testing.assert_array_equal(x.linear, np.arange(18.0).reshape(2, 3, 3))


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_integer_input_becomes_float64(cls):
    x = cls([1, 2, 3], [4, 5, 6])
    assert x.dtype == np.float64
    np.testing.assert_array_equal(x.vector, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0])


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_from_vector_copies_and_is_read_only(cls, batch_shape, dtype, samples):
    raw = samples.array(batch_shape, (6,), dtype)
    keep = raw.copy()
    x = cls.from_vector(raw)
    assert x.dtype == dtype
    assert not np.shares_memory(x.vector, raw)
    raw[...] = 99.0
    np.testing.assert_array_equal(x.vector, keep)
    assert raw.flags.writeable  # the caller's array is left alone
    with pytest.raises(ValueError):
        x.vector[..., 0] = 1.0


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_constructor_never_keeps_callers_arrays(cls):
    ang, lin = np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])
    x = cls(ang, lin)
    ang[0] = lin[0] = -1.0
    np.testing.assert_array_equal(x.vector, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    assert ang.flags.writeable and lin.flags.writeable


@pytest.mark.parametrize("cls", [fd.SpatialMotion, fd.SpatialForce])
def test_zero(cls, dtype):
    z = cls.zero((2, 3), dtype=dtype)
    assert z.shape == (2, 3) and z.dtype == dtype
    assert not np.any(z.vector)


def test_transform_and_inertia_accessors(batch_shape, dtype, samples):
    R = samples.rotation(batch_shape, dtype)
    p = samples.array(batch_shape, (3,), dtype)
    X = fd.PluckerTransform(R, p)
    assert X.shape == batch_shape and X.dtype == dtype
    np.testing.assert_array_equal(X.rotation, R)
    np.testing.assert_array_equal(X.translation, p)
    m, c, Ic = samples.inertia_params(batch_shape, dtype)
    inertia = fd.SpatialInertia(m, c, Ic)
    assert inertia.shape == batch_shape and inertia.dtype == dtype
    np.testing.assert_array_equal(inertia.mass, m)
    np.testing.assert_array_equal(inertia.com, c)
    assert_close(inertia.inertia_com, Ic, "inertia_com")


def test_python_scalar_mass_keeps_float32():
    c = np.array([0.1, 0.2, 0.3], np.float32)
    inertia = fd.SpatialInertia(2.0, c, np.eye(3, dtype=np.float32))
    assert inertia.dtype == np.float32 and inertia.mass.dtype == np.float32
    assert inertia.matrix().dtype == np.float32


# --------------------------------------------------------------------------
# immutability
# --------------------------------------------------------------------------


def _values(samples):
    return [
        samples.motion((2,)),
        samples.force((2,)),
        samples.transform((2,)),
        samples.inertia((2,)),
    ]


def test_attributes_cannot_be_set(samples):
    for value in _values(samples):
        for name in [f.name for f in dataclasses.fields(value)]:
            with pytest.raises(dataclasses.FrozenInstanceError):
                setattr(value, name, getattr(value, name))
        with pytest.raises((AttributeError, TypeError)):
            value.extra = 1  # slots: no new attributes


def test_arrays_are_read_only(samples):
    m, f, X, inertia = _values(samples)
    arrays = [m.vector, m.angular, m.linear, f.vector, f.angular, f.linear, X.rotation, X.translation]
    arrays += [inertia.mass, inertia.com, inertia.inertia_com]
    for arr in arrays:
        assert not arr.flags.writeable
        with pytest.raises(ValueError):
            arr[...] = 0


def test_transform_and_inertia_never_keep_callers_arrays(samples):
    R, p = samples.rotation(), samples.array((), (3,))
    X = fd.PluckerTransform(R, p)
    assert not np.shares_memory(X.rotation, R) and not np.shares_memory(X.translation, p)
    m, c, Ic = samples.inertia_params()
    inertia = fd.SpatialInertia(m, c, Ic)
    assert not np.shares_memory(inertia.com, c) and not np.shares_memory(inertia.inertia_com, Ic)
    p_before, c_before = p.copy(), c.copy()
    p[:] = 7.0
    c[:] = 7.0
    np.testing.assert_array_equal(X.translation, p_before)
    np.testing.assert_array_equal(inertia.com, c_before)
    assert p.flags.writeable and c.flags.writeable


# --------------------------------------------------------------------------
# linear structure: +, -, unary -, scalar * and /
# --------------------------------------------------------------------------


@pytest.mark.parametrize("make", ["motion", "force"])
def test_vector_space_operations(make, batch_shape, dtype, samples):
    a = getattr(samples, make)(batch_shape, dtype)
    b = getattr(samples, make)(batch_shape, dtype)
    cls = type(a)
    av, bv = a.vector.astype(np.float64), b.vector.astype(np.float64)
    cases = {
        "a + b": (a + b, av + bv),
        "a - b": (a - b, av - bv),
        "-a": (-a, -av),
        "a * 2.5": (a * 2.5, 2.5 * av),
        "2.5 * a": (2.5 * a, 2.5 * av),
        "a * 3": (a * 3, 3 * av),
        "a / 4.0": (a / 4.0, av / 4.0),
    }
    for what, (got, expected) in cases.items():
        assert type(got) is cls, what
        assert got.dtype == dtype, f"{what}: dtype {got.dtype}, expected {dtype}"
        assert got.shape == batch_shape, what
        assert_close(got.vector, expected.astype(dtype), what)


@pytest.mark.parametrize("make", ["motion", "force"])
def test_numpy_scalar_multiplies(make, samples):
    a = getattr(samples, make)()
    got = np.float64(2) * a
    assert type(got) is type(a)
    np.testing.assert_array_equal(got.vector, 2 * a.vector)
    got = a * np.float32(0.5)
    np.testing.assert_array_equal(got.vector, 0.5 * a.vector)


@pytest.mark.parametrize("make", ["motion", "force"])
def test_scalar_array_scales_each_batch_element(make, samples):
    a = getattr(samples, make)((2, 3))
    s = np.arange(1.0, 7.0).reshape(2, 3)
    assert_close((a * s).vector, a.vector * s[..., None], "a * s")
    assert_close((a / s).vector, a.vector / s[..., None], "a / s")
    with pytest.raises(ShapeError, match=r"scalar.*broadcastable.*\(2, 3\)"):
        a * np.ones(4)


# --------------------------------------------------------------------------
# batch indexing and broadcasting
# --------------------------------------------------------------------------


def test_batch_indexing(samples):
    m = samples.motion((2, 3), frame="A")
    np.testing.assert_array_equal(m[1].vector, m.vector[1])
    np.testing.assert_array_equal(m[1, 2].vector, m.vector[1, 2])
    np.testing.assert_array_equal(m[:, 1:].vector, m.vector[:, 1:])
    assert m[1].frame == "A" and m[1].shape == (3,)
    assert len(m) == 2
    f = samples.force((3,))
    np.testing.assert_array_equal(f[-1].vector, f.vector[-1])
    X = samples.transform((3,))
    np.testing.assert_array_equal(X[2].rotation, X.rotation[2])
    np.testing.assert_array_equal(X[2].translation, X.translation[2])
    inertia = samples.inertia((2, 3))
    np.testing.assert_array_equal(inertia[1, 0].com, inertia.com[1, 0])
    np.testing.assert_array_equal(inertia[1, 0].mass, inertia.mass[1, 0])
    assert inertia[1].shape == (3,)


def test_batch_indexing_refuses_the_trailing_axis(samples):
    m = samples.motion((3,))
    with pytest.raises(IndexError):
        m[0, 1]
    with pytest.raises(IndexError):
        m[..., 0]
    with pytest.raises(TypeError, match="unbatched"):
        len(samples.motion())


def test_single_transform_applied_to_batch(samples, ref):
    X = samples.transform()
    m = samples.motion((2, 3))
    f = samples.force((2, 3))
    Xm, Xf = X.apply(m), X.apply(f)
    assert Xm.shape == (2, 3) and Xf.shape == (2, 3)
    assert_close(Xm.vector, m.vector @ ref.X(X.rotation, X.translation).T, "X m (one X, batch of m)")
    assert_close(Xf.vector, f.vector @ ref.Xstar(X.rotation, X.translation).T, "X* f (one X, batch of f)")


def test_batch_of_transforms_applied_to_single_value(samples, ref):
    X = samples.transform((2, 3))
    m, f, inertia = samples.motion(), samples.force(), samples.inertia()
    expected_m = ref.per_batch(lambda R, p: ref.X(R, p) @ m.vector, (X.rotation, 2), (X.translation, 1))
    expected_f = ref.per_batch(lambda R, p: ref.Xstar(R, p) @ f.vector, (X.rotation, 2), (X.translation, 1))
    assert_close(X.apply(m).vector, expected_m, "X m (batch of X, one m)")
    assert_close(X.apply(f).vector, expected_f, "X* f (batch of X, one f)")
    XI = X.apply(inertia)
    assert XI.shape == (2, 3)
    I_A = ref.inertia(inertia.mass, inertia.com, inertia.inertia_com)
    expected_I = ref.per_batch(
        lambda R, p: ref.Xstar(R, p) @ I_A @ np.linalg.inv(ref.X(R, p)), (X.rotation, 2), (X.translation, 1)
    )
    assert_close(XI.matrix(), expected_I, "X* I X⁻¹ (batch of X, one I)")


def test_broadcasting_between_batch_shapes(samples, ref):
    X = samples.transform((3,))
    m = samples.motion((2, 1))
    got = X.apply(m)
    assert got.shape == (2, 3)
    expected = ref.per_batch(lambda R, p, v: ref.X(R, p) @ v, (X.rotation, 2), (X.translation, 1), (m.vector, 1))
    assert_close(got.vector, expected, "X (3,) applied to m (2, 1)")


# --------------------------------------------------------------------------
# repr
# --------------------------------------------------------------------------


def test_repr_names_type_parts_and_tags():
    m = fd.SpatialMotion([1.0, 2.0, 3.0], [4.0, 5.0, 6.0], frame="base")
    text = repr(m)
    assert text.startswith("SpatialMotion(angular=")
    assert "[1., 2., 3.]" in text and "[4., 5., 6.]" in text and "frame='base'" in text
    f = fd.SpatialForce([0.0, 0.0, 5.0], [0.0, 10.0, 0.0])
    assert repr(f).startswith("SpatialForce(angular=") and "frame" not in repr(f)
    X = fd.PluckerTransform(np.eye(3), [1.0, 0.0, 0.0], source="A", target="B")
    assert "PluckerTransform(rotation=" in repr(X) and "source='A'" in repr(X) and "target='B'" in repr(X)
    inertia = fd.SpatialInertia(12.0, [0.2, 0.1, 0.0], np.diag([0.1, 0.3, 0.35]))
    assert re.search(r"SpatialInertia\(mass=12\.?", repr(inertia))
    assert "0.35" in repr(inertia)


# --------------------------------------------------------------------------
# cross products and raw-array kernels
# --------------------------------------------------------------------------


def test_skew_and_unskew(batch_shape, dtype, samples):
    w = samples.array(batch_shape, (3,), dtype)
    x = samples.array(batch_shape, (3,), dtype)
    S = fd.skew(w)
    assert S.shape == batch_shape + (3, 3) and S.dtype == dtype
    assert_close((S @ x[..., None])[..., 0], np.cross(w.astype(np.float64), x), "skew(w) @ x")
    assert_close(fd.unskew(S), w, "unskew(skew(w))")


def test_crm_crf_match_the_written_out_blocks(batch_shape, dtype, samples, ref):
    v = samples.array(batch_shape, (6,), dtype)
    assert fd.crm(v).dtype == dtype and fd.crf(v).dtype == dtype
    assert_close(fd.crm(v), ref.per_batch(ref.crm, (v, 1)), "crm(v)")
    assert_close(fd.crf(v), ref.per_batch(ref.crf, (v, 1)), "crf(v)")


def test_cross_dispatch(batch_shape, dtype, samples, ref):
    v = samples.motion(batch_shape, dtype)
    m = samples.motion(batch_shape, dtype)
    f = samples.force(batch_shape, dtype)
    vm = v.cross(m)
    vf = v.cross(f)
    assert isinstance(vm, fd.SpatialMotion) and isinstance(vf, fd.SpatialForce)
    assert vm.dtype == dtype and vf.dtype == dtype
    expected_vm = ref.per_batch(lambda a, b: ref.crm(a) @ b, (v.vector, 1), (m.vector, 1))
    expected_vf = ref.per_batch(lambda a, b: ref.crf(a) @ b, (v.vector, 1), (f.vector, 1))
    assert_close(vm.vector, expected_vm, "v.cross(m)")
    assert_close(vf.vector, expected_vf, "v.cross(f)")
    assert_close(fd.cross_motion(v, m).vector, expected_vm, "cross_motion")
    assert_close(fd.cross_force(v, f).vector, expected_vf, "cross_force")
    # raw arrays are accepted by the functions (the type is stated by the function name)
    assert_close(fd.cross_motion(v.vector, m.vector).vector, expected_vm, "cross_motion(raw)")
    assert_close(fd.cross_force(v.vector, f.vector).vector, expected_vf, "cross_force(raw)")


def test_cross_functions_refuse_swapped_types(samples):
    m, f = samples.motion(), samples.force()
    with pytest.raises(SpatialTypeError, match="swap"):
        fd.cross_force(f, m)
    with pytest.raises(SpatialTypeError, match="cross_motion"):
        fd.cross_force(m, m)
    with pytest.raises(SpatialTypeError, match="expected a motion"):
        fd.crm(f)


# --------------------------------------------------------------------------
# type errors that say what was meant
# --------------------------------------------------------------------------


def _type_error_cases(samples):
    m, f, X, inertia = samples.motion(), samples.force(), samples.transform(), samples.inertia()
    raw = np.zeros(6)
    return [
        ("motion + force", lambda: m + f, r"dual spaces.*motion\.dot\(force\)"),
        ("force + motion", lambda: f + m, r"dual spaces"),
        ("motion - force", lambda: m - f, r"dual spaces"),
        ("motion.dot(motion)", lambda: m.dot(m), r"pairs a motion with a force.*kinetic_energy"),
        ("force.dot(force)", lambda: f.dot(f), r"pairs a force with a motion"),
        ("force.cross(motion)", lambda: f.cross(m), r"motion\.cross\(force\)"),
        ("force.cross(force)", lambda: f.cross(f), r"no cross product on the left"),
        ("X.apply(ndarray)", lambda: X.apply(raw), r"ambiguous.*SpatialMotion\.from_vector.*SpatialForce\.from_vector"),
        ("X @ ndarray", lambda: X @ raw, r"ambiguous.*from_vector"),
        ("ndarray @ X", lambda: raw @ X, r"ambiguous"),
        ("X.apply_inverse(ndarray)", lambda: X.apply_inverse(raw), r"ambiguous"),
        ("inertia @ force", lambda: inertia @ f, r"maps motion to force.*solve"),
        ("inertia @ ndarray", lambda: inertia @ raw, r"SpatialMotion\.from_vector"),
        ("motion + ndarray", lambda: m + raw, r"SpatialMotion\.from_vector"),
        ("ndarray + motion", lambda: raw + m, r"SpatialMotion\.from_vector"),
        ("ndarray - force", lambda: raw - f, r"SpatialForce\.from_vector"),
        ("motion * motion", lambda: m * m, r"cross.*dot"),
        ("motion @ motion", lambda: m @ m, r"motion\.dot\(force\)"),
        ("inertia + motion", lambda: inertia + m, r"only adds to another SpatialInertia"),
        ("motion.cross(ndarray)", lambda: m.cross(raw), r"SpatialMotion\.from_vector"),
        ("inertia.kinetic_energy(force)", lambda: inertia.kinetic_energy(f), r"inertia @ motion"),
    ]


def test_type_errors_say_what_was_meant(samples):
    for what, call, hint in _type_error_cases(samples):
        with pytest.raises(SpatialTypeError) as info:
            call()
        assert isinstance(info.value, TypeError), what
        assert re.search(hint, str(info.value), re.DOTALL), f"{what}: message lacks {hint!r}: {info.value}"


# --------------------------------------------------------------------------
# bad inputs
# --------------------------------------------------------------------------


def test_wrong_shapes_name_the_argument():
    eye = np.eye(3)
    cases = [
        (lambda: fd.SpatialMotion(np.zeros(4), np.zeros(3)), "angular", r"\(\.\.\., 3\)"),
        (lambda: fd.SpatialMotion(np.zeros(3), np.zeros((3, 2))), "linear", r"\(3, 2\)"),
        (lambda: fd.SpatialForce(np.zeros(2), np.zeros(3)), "angular", r"\(2,\)"),
        (lambda: fd.SpatialMotion.from_vector(np.zeros(5)), "vector", r"\(\.\.\., 6\)"),
        (lambda: fd.SpatialForce.from_vector(np.zeros((6, 2))), "vector", r"\(6, 2\)"),
        (lambda: fd.PluckerTransform(np.eye(2), np.zeros(3)), "rotation", r"\(\.\.\., 3, 3\)"),
        (lambda: fd.PluckerTransform(eye, np.zeros(4)), "translation", r"\(4,\)"),
        (lambda: fd.SpatialInertia(1.0, np.zeros(2), eye), "com", r"\(\.\.\., 3\)"),
        (lambda: fd.SpatialInertia(1.0, np.zeros(3), np.eye(2)), "inertia_com", r"\(\.\.\., 3, 3\)"),
        (lambda: fd.SpatialInertia.from_matrix(np.eye(5)), "matrix", r"\(\.\.\., 6, 6\)"),
        (lambda: fd.PluckerTransform.from_homogeneous(np.eye(3)), "matrix", r"\(\.\.\., 4, 4\)"),
        (lambda: fd.crm(np.zeros(5)), "v", r"\(\.\.\., 6\)"),
        (lambda: fd.skew(np.zeros(4)), "w", r"\(\.\.\., 3\)"),
        (lambda: fd.SpatialMotion([[1, 2, 3], [4, 5]], np.zeros(3)), "angular", "cannot be read"),
    ]
    for call, name, shape in cases:
        with pytest.raises(ShapeError) as info:
            call()
        assert isinstance(info.value, ValueError)
        text = str(info.value)
        assert text.startswith(f"{name}:"), text
        assert re.search(shape, text), f"{text!r} lacks {shape!r}"


def test_mismatched_batch_shapes_raise():
    with pytest.raises(ValueError):
        fd.SpatialMotion(np.zeros((2, 3)), np.zeros((3, 3)))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_input_is_refused(bad):
    v = np.array([0.0, 1.0, bad])
    cases = [
        (lambda: fd.SpatialMotion(v, np.zeros(3)), "angular"),
        (lambda: fd.SpatialForce(np.zeros(3), v), "linear"),
        (lambda: fd.SpatialMotion.from_vector(np.r_[v, v]), "vector"),
        (lambda: fd.PluckerTransform(np.eye(3), v), "translation"),
        (lambda: fd.SpatialInertia(bad, np.zeros(3), np.eye(3)), "mass"),
        (lambda: fd.SpatialInertia(1.0, v, np.eye(3)), "com"),
        (lambda: fd.SpatialMotion([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]) * bad, "scalar"),
    ]
    for call, name in cases:
        with pytest.raises(NonFiniteError, match=f"^{name}: expected finite"):
            call()


def test_complex_input_is_refused():
    z = np.array([1j, 0, 0])
    cases = [
        (lambda: fd.SpatialMotion(z, np.zeros(3)), "angular"),
        (lambda: fd.SpatialForce.from_vector(np.zeros(6, complex)), "vector"),
        (lambda: fd.PluckerTransform(np.eye(3, dtype=complex), np.zeros(3)), "rotation"),
        (lambda: fd.SpatialInertia(1.0 + 0j, np.zeros(3), np.eye(3)), "mass"),
        (lambda: fd.crm(np.zeros(6, complex)), "v"),
        (lambda: fd.SpatialMotion(np.array(["a", "b", "c"]), np.zeros(3)), "angular"),
    ]
    for call, name in cases:
        with pytest.raises(DTypeError, match=f"^{name}: expected real numbers"):
            call()


def test_rotation_must_be_proper_and_orthonormal():
    with pytest.raises(RotationError, match=r"rotation: expected a rotation matrix.*RᵀR"):
        fd.PluckerTransform(np.diag([1.0, 1.0, 1.1]), np.zeros(3))
    with pytest.raises(RotationError, match=r"reflection"):
        fd.PluckerTransform(np.diag([1.0, 1.0, -1.0]), np.zeros(3))
    batch = np.broadcast_to(np.eye(3), (3, 3, 3)).copy()
    batch[2] = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # a swap of axes: det −1
    with pytest.raises(RotationError, match=r"batch index \(2,\)"):
        fd.PluckerTransform(batch, np.zeros(3))
    with pytest.raises(RotationError):
        fd.plux(np.diag([1.0, -1.0, -1.0]) * 2, np.zeros(3))
    # validate=False is the documented escape hatch
    X = fd.PluckerTransform(np.diag([1.0, 1.0, 1.1]), np.zeros(3), validate=False)
    assert X.rotation[2, 2] == 1.1


def test_rotation_tolerance_is_dtype_aware():
    # a float32 rounding of a rotation is accepted as float32 ...
    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    fd.PluckerTransform(R.astype(np.float32), np.zeros(3, np.float32))
    # ... but a 1e-5 error in float64 is not a rotation
    with pytest.raises(RotationError):
        fd.PluckerTransform(R * (1 + 1e-5), np.zeros(3))


def test_inertia_com_must_be_symmetric():
    Ic = np.array([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    with pytest.raises(InertiaError, match=r"inertia_com: expected a symmetric.*0\.1"):
        fd.SpatialInertia(1.0, np.zeros(3), Ic)


def _valid_inertia_matrix():
    return fd.SpatialInertia(2.0, [0.1, -0.2, 0.3], np.diag([0.1, 0.2, 0.25])).matrix()


@pytest.mark.parametrize(
    "corrupt, message",
    [
        (lambda M: M.__setitem__((0, 1), M[0, 1] + 0.1), r"not symmetric"),
        (lambda M: M.__setitem__((5, 5), M[5, 5] + 1.0), r"lower-right block is not m·1"),
        (lambda M: [M.__setitem__((3, 4), 0.5), M.__setitem__((4, 3), 0.5)], r"lower-right block is not m·1"),
        (
            lambda M: [M.__setitem__((0, 3), 0.3), M.__setitem__((3, 0), 0.3)],
            r"upper-right block is not skew-symmetric",
        ),
    ],
    ids=["asymmetric", "lower-right-diagonal", "lower-right-offdiagonal", "non-skew-offdiagonal"],
)
def test_from_matrix_refuses_non_inertias(corrupt, message):
    M = _valid_inertia_matrix()
    corrupt(M)
    with pytest.raises(InertiaError, match=f"matrix: not a rigid-body spatial inertia: {message}"):
        fd.SpatialInertia.from_matrix(M)


def test_from_matrix_refuses_zero_mass_with_first_moment(ref):
    M = np.zeros((6, 6))
    M[:3, 3:] = ref.skew([0.0, 0.0, 0.5])
    M[3:, :3] = M[:3, 3:].T
    with pytest.raises(InertiaError, match="zero mass with a non-zero first moment"):
        fd.SpatialInertia.from_matrix(M)
    with pytest.raises(InertiaError, match="zero mass with a non-zero first moment"):
        fd.SpatialInertia.from_dynamic_parameters([0.0, 0.0, 0.0, 0.5, 1, 0, 1, 0, 0, 1])


def test_transform_from_matrix_refuses_non_transforms(ref):
    R = np.eye(3)
    good = ref.X(R, [1.0, 2.0, 3.0])
    bad_upper = good.copy()
    bad_upper[0, 4] = 0.5
    with pytest.raises(ShapeError, match=r"not a Plücker motion transform"):
        fd.PluckerTransform.from_matrix(bad_upper)
    bad_lower = good.copy()
    bad_lower[3:, :3] = np.eye(3)  # symmetric, not p×R
    with pytest.raises(ShapeError, match=r"not skew-symmetric"):
        fd.PluckerTransform.from_matrix(bad_lower)
    H = np.eye(4)
    H[3, 0] = 1.0
    with pytest.raises(ShapeError, match=r"last row \[0, 0, 0, 1\]"):
        fd.PluckerTransform.from_homogeneous(H)


# --------------------------------------------------------------------------
# physical validity
# --------------------------------------------------------------------------


def test_check_accepts_physical_inertias(samples):
    samples.inertia((2, 3)).check()
    assert np.all(samples.inertia((2, 3)).is_physical())
    # a thin lamina sits exactly on the triangle inequality (I1 + I2 = I3) and is physical
    plate = fd.SpatialInertia(1.0, np.zeros(3), np.diag([1.0, 2.0, 3.0]))
    plate.check()
    assert plate.is_physical() is True


@pytest.mark.parametrize(
    "mass, moments, condition, numbers",
    [
        (-1.0, [0.1, 0.2, 0.25], "mass > 0", ["-1"]),
        (0.0, [0.1, 0.2, 0.25], "mass > 0", ["mass 0"]),
        (1.0, [-0.02, 0.05, 0.1], "positive definite", ["-0.02", "0.05", "0.1"]),
        (1.0, [0.1, 0.1, 0.5], "triangle inequality", ["0.1", "0.5"]),
    ],
    ids=["negative-mass", "zero-mass", "indefinite", "triangle"],
)
def test_check_names_the_condition_and_numbers(mass, moments, condition, numbers):
    inertia = fd.SpatialInertia(mass, np.zeros(3), np.diag(moments))
    assert inertia.is_physical() is False
    with pytest.raises(InertiaError) as info:
        inertia.check(name="link 'thigh'")
    text = str(info.value)
    assert text.startswith("link 'thigh':") and condition in text, text
    for number in numbers:
        assert number in text, f"{text!r} lacks {number}"


def test_batched_is_physical_returns_bool_array(samples):
    m, c, Ic = samples.inertia_params((4,))
    m[1] = -1.0
    Ic[2] = np.diag([0.1, 0.1, 0.5])
    Ic[3] = np.diag([-0.1, 0.3, 0.3])
    inertia = fd.SpatialInertia(m, c, Ic)
    ok = inertia.is_physical()
    assert isinstance(ok, np.ndarray) and ok.dtype == bool and ok.shape == (4,)
    np.testing.assert_array_equal(ok, [True, False, False, False])
    with pytest.raises(InertiaError, match=r"batch index \(1,\)"):
        inertia.check()


def test_principal_moments_are_rotation_invariant(samples):
    Q = samples.rotation()
    inertia = fd.SpatialInertia(1.0, np.zeros(3), Q @ np.diag([0.3, 0.1, 0.35]) @ Q.T)
    assert_close(inertia.principal_moments(), [0.1, 0.3, 0.35], "principal moments")


# --------------------------------------------------------------------------
# standard solids: closed forms and Pinocchio
# --------------------------------------------------------------------------


def test_box_cylinder_sphere_closed_forms(dtype):
    m, x, y, z = 12.0, 1.0, 2.0, 3.0
    box = fd.SpatialInertia.box(np.asarray(m, dtype), np.array([x, y, z], dtype))
    assert box.dtype == dtype
    assert_close(box.inertia_com, np.diag([m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12]), "box")
    r, h = 0.1, 0.4
    cyl = fd.SpatialInertia.cylinder(np.asarray(2.0, dtype), np.asarray(r, dtype), np.asarray(h, dtype))
    side = 2.0 * (3 * r * r + h * h) / 12
    assert_close(cyl.inertia_com, np.diag([side, side, 2.0 * r * r / 2]), "cylinder")
    sph = fd.SpatialInertia.sphere(np.asarray(2.0, dtype), np.asarray(0.1, dtype))
    assert_close(sph.inertia_com, np.eye(3) * 0.4 * 2.0 * 0.01, "sphere")
    for solid in (box, cyl, sph):
        np.testing.assert_array_equal(solid.com, 0.0)
        solid.check()


def test_solids_batched():
    masses = np.array([1.0, 2.0, 3.0])
    sph = fd.SpatialInertia.sphere(masses, 0.5)
    assert sph.shape == (3,)
    assert_close(sph.inertia_com[:, 0, 0], 0.4 * masses * 0.25, "sphere I_xx")
    box = fd.SpatialInertia.box(2.0, np.array([[1.0, 1.0, 1.0], [2.0, 1.0, 1.0]]))
    assert box.shape == (2,)
    assert_close(box.inertia_com[1].diagonal(), 2.0 / 12 * np.array([2.0, 5.0, 5.0]), "box batch")


def test_solids_refuse_negative_sizes():
    with pytest.raises(InertiaError, match=r"^mass: expected non-negative"):
        fd.SpatialInertia.sphere(-1.0, 0.1)
    with pytest.raises(InertiaError, match=r"^size: expected non-negative"):
        fd.SpatialInertia.box(1.0, [1.0, 1.0, -1.0])
    with pytest.raises(InertiaError, match=r"^radius: expected non-negative"):
        fd.SpatialInertia.sphere(1.0, -0.1)
    with pytest.raises(InertiaError, match=r"^length: expected non-negative"):
        fd.SpatialInertia.cylinder(1.0, 0.1, -0.4)


def test_solids_match_pinocchio(pin):
    cases = [
        (fd.SpatialInertia.box(12.0, [1.0, 2.0, 3.0]), pin.Inertia.FromBox(12.0, 1.0, 2.0, 3.0)),
        (fd.SpatialInertia.box(0.5, [0.1, 0.3, 0.2]), pin.Inertia.FromBox(0.5, 0.1, 0.3, 0.2)),
        (fd.SpatialInertia.cylinder(2.0, 0.1, 0.4), pin.Inertia.FromCylinder(2.0, 0.1, 0.4)),
        (fd.SpatialInertia.sphere(2.0, 0.1), pin.Inertia.FromSphere(2.0, 0.1)),
    ]
    for ours, theirs in cases:
        assert_close(ours.mass, theirs.mass, "mass")
        assert_close(ours.com, theirs.lever, "com vs lever")
        assert_close(ours.inertia_com, theirs.inertia, "I_c vs pinocchio")


def test_point_mass(ref):
    pm = fd.SpatialInertia.point_mass(2.0, [1.0, 0.0, 0.0])
    assert_close(pm.matrix(), ref.inertia(2.0, [1.0, 0.0, 0.0], np.zeros((3, 3))), "point mass")
    assert_close(pm.inertia_origin, np.diag([0.0, 2.0, 2.0]), "point mass about the origin")


# --------------------------------------------------------------------------
# dynamic parameters
# --------------------------------------------------------------------------


def test_dynamic_parameters_written_out():
    m, c = 2.0, np.array([0.1, 0.2, 0.3])
    Ic = np.array([[1.0, 0.1, 0.2], [0.1, 2.0, 0.3], [0.2, 0.3, 2.5]])
    ibar = Ic + m * (c @ c * np.eye(3) - np.outer(c, c))
    expected = [m, m * c[0], m * c[1], m * c[2], ibar[0, 0], ibar[0, 1], ibar[1, 1], ibar[0, 2], ibar[1, 2], ibar[2, 2]]
    assert_close(fd.SpatialInertia(m, c, Ic).to_dynamic_parameters(), np.array(expected), "dynamic parameters")


def test_dynamic_parameters_round_trip(batch_shape, dtype, samples):
    inertia = samples.inertia(batch_shape, dtype)
    pi = inertia.to_dynamic_parameters()
    assert pi.shape == batch_shape + (10,) and pi.dtype == dtype
    back = fd.SpatialInertia.from_dynamic_parameters(pi)
    assert back.dtype == dtype
    assert_close(back.mass, inertia.mass, "mass")
    assert_close(back.com, inertia.com, "com")
    assert_close(back.inertia_com, inertia.inertia_com, "inertia_com")


def test_dynamic_parameters_match_pinocchio(pin, samples):
    for _ in range(5):
        m, c, Ic = samples.inertia_params()
        theirs = pin.Inertia(float(m), c, Ic)
        ours = fd.SpatialInertia(m, c, Ic)
        assert_close(ours.to_dynamic_parameters(), theirs.toDynamicParameters(), "toDynamicParameters")
        pi = theirs.toDynamicParameters()
        back = fd.SpatialInertia.from_dynamic_parameters(pi)
        again = pin.Inertia.FromDynamicParameters(pi)
        assert_close(back.com, again.lever, "FromDynamicParameters lever")
        assert_close(back.inertia_com, again.inertia, "FromDynamicParameters inertia")


# --------------------------------------------------------------------------
# screw parameters
# --------------------------------------------------------------------------


def _known_screw(dtype=np.float64):
    # rotation 2 rad/s about the axis through q along d, sliding h = 0.5 m/rad
    d = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    q = np.array([0.0, 0.0, 1.5])  # q ⟂ d: it is the axis point nearest the origin
    h, speed = 0.5, 2.0
    w = speed * d
    v_O = h * w + np.cross(w, -q)  # v_O = h ω + ω × (O − q)
    return fd.SpatialMotion(w.astype(dtype), v_O.astype(dtype)), d, q, h, speed


def test_screw_of_a_known_motion(dtype):
    motion, d, q, h, speed = _known_screw(dtype)
    screw = motion.screw()
    for field in screw:
        assert field.dtype == dtype
    assert_close(screw.direction, d, "screw direction")
    assert_close(screw.point, q, "screw point")
    assert_close(screw.pitch, h, "screw pitch")
    assert_close(screw.magnitude, speed, "screw magnitude")


def test_screw_point_is_nearest_to_origin():
    motion, d, q, h, speed = _known_screw()
    # any point of the axis builds the same motion; the nearest one comes back
    again = fd.SpatialMotion.from_screw(d, q + 3.0 * d, h, speed)
    assert_close(again.vector, motion.vector, "from_screw with another axis point")
    assert_close(again.screw().point, q, "nearest axis point")


def test_screw_of_pure_translation_and_zero():
    pure = fd.SpatialMotion([0.0, 0.0, 0.0], [0.0, 3.0, 4.0])
    screw = fd.screw_parameters(pure)
    assert np.isinf(screw.pitch) and screw.pitch > 0
    assert_close(screw.direction, [0.0, 0.6, 0.8], "translation direction")
    assert_close(screw.magnitude, 5.0, "translation speed")
    np.testing.assert_array_equal(screw.point, 0.0)
    back = fd.SpatialMotion.from_screw(screw.direction, screw.point, np.inf, screw.magnitude)
    assert_close(back.vector, pure.vector, "from_screw(pitch=inf)")
    zero = fd.screw_parameters(fd.SpatialMotion.zero())
    for field in zero:
        np.testing.assert_array_equal(field, 0.0)


def test_screw_batched_mixed_cases():
    motion, _, _, h, speed = _known_screw()
    vectors = np.stack([motion.vector, [0, 0, 0, 1.0, 0, 0], np.zeros(6), [0, 0, 1.0, 0, 0, 0]])
    screw = fd.screw_parameters(vectors)
    assert screw.pitch.shape == (4,)
    assert_close(screw.pitch, [h, np.inf, 0.0, 0.0], "pitches")
    assert_close(screw.magnitude, [speed, 1.0, 0.0, 1.0], "magnitudes")
    assert_close(screw.direction[3], [0.0, 0.0, 1.0], "pure rotation direction")


def test_from_screw_round_trip(batch_shape, dtype, samples):
    motion = samples.motion(batch_shape, dtype)
    screw = motion.screw()
    back = fd.SpatialMotion.from_screw(*screw)
    assert back.dtype == dtype
    assert_close(back.vector, motion.vector, "from_screw(screw(m))", scale=10.0)


def test_from_screw_refuses_bad_axes():
    with pytest.raises(ValueError, match="zero-length"):
        fd.SpatialMotion.from_screw([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.1)
    with pytest.raises(NonFiniteError, match="pitch"):
        fd.SpatialMotion.from_screw([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], np.nan)


def test_screw_refuses_symbolic():
    sympy = pytest.importorskip("sympy")
    with pytest.raises(DTypeError):
        fd.screw_parameters(np.array(sympy.symbols("a:6"), dtype=object))


# --------------------------------------------------------------------------
# spatial_v2 constructors
# --------------------------------------------------------------------------


def _sv2_rot(axis: str, theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    E = {
        "x": [[1, 0, 0], [0, c, s], [0, -s, c]],
        "y": [[c, 0, -s], [0, 1, 0], [s, 0, c]],
        "z": [[c, s, 0], [-s, c, 0], [0, 0, 1]],
    }[axis]
    E = np.array(E, dtype=np.float64)
    Z = np.zeros((3, 3))
    return np.block([[E, Z], [Z, E]])


def _sv2_xlt(r) -> np.ndarray:
    x, y, z = r
    rx = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]], dtype=np.float64)
    return np.block([[np.eye(3), np.zeros((3, 3))], [-rx, np.eye(3)]])


def _sv2_plux(E, r) -> np.ndarray:
    x, y, z = r
    rx = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]], dtype=np.float64)
    return np.block([[E, np.zeros((3, 3))], [-E @ rx, E]])


@pytest.mark.parametrize("axis, fn", [("x", fd.rotx), ("y", fd.roty), ("z", fd.rotz)])
def test_rot_matches_spatial_v2(axis, fn, dtype):
    thetas = np.array([0.0, 0.3, -1.2, 2.5])
    X = fn(thetas.astype(dtype))
    assert X.shape == (4,) and X.dtype == dtype
    for i, th in enumerate(thetas):
        assert_close(X[i].matrix(), _sv2_rot(axis, th), f"rot{axis}({th})")
    assert fn(0.7).shape == ()
    assert_close(fn(0.7).matrix(), _sv2_rot(axis, 0.7), f"rot{axis} unbatched")


def test_xlt_and_plux_match_spatial_v2(dtype, samples):
    r = np.array([0.3, -0.5, 1.2])
    X = fd.xlt(r.astype(dtype))
    assert X.dtype == dtype
    assert_close(X.matrix(), _sv2_xlt(r), "xlt(r)")
    E = _sv2_rot("z", 0.4)[:3, :3] @ _sv2_rot("x", -1.1)[:3, :3]
    P = fd.plux(E.astype(dtype), r.astype(dtype))
    assert P.dtype == dtype
    assert_close(P.matrix(), _sv2_plux(E, r), "plux(E, r)")
    # spatial_v2: plux(E, r) = rot(E) * xlt(r)
    rotE = fd.PluckerTransform(E, np.zeros(3))
    assert_close((rotE @ fd.xlt(r)).matrix(), _sv2_plux(E, r), "rot(E) @ xlt(r)")
    assert_close(fd.PluckerTransform.from_plux(E, r).matrix(), _sv2_plux(E, r), "from_plux")


def test_xlt_batched():
    r = np.arange(6.0).reshape(2, 3)
    X = fd.xlt(r)
    assert X.shape == (2,)
    assert_close(X[1].matrix(), _sv2_xlt(r[1]), "xlt batch")


# --------------------------------------------------------------------------
# matrices and round trips
# --------------------------------------------------------------------------


def test_transform_matrices(batch_shape, dtype, samples, ref):
    X = samples.transform(batch_shape, dtype)
    for name, got, formula in [
        ("X", X.matrix(), ref.X),
        ("X*", X.dual_matrix(), ref.Xstar),
        ("X⁻¹", X.inverse_matrix(), lambda R, p: np.linalg.inv(ref.X(R, p))),
    ]:
        assert got.shape == batch_shape + (6, 6) and got.dtype == dtype, name
        assert_close(got, ref.per_batch(formula, (X.rotation, 2), (X.translation, 1)), name)


def test_homogeneous_round_trip(batch_shape, dtype, samples):
    X = samples.transform(batch_shape, dtype)
    H = X.homogeneous()
    assert H.shape == batch_shape + (4, 4) and H.dtype == dtype
    np.testing.assert_array_equal(H[..., :3, :3], X.rotation)
    np.testing.assert_array_equal(H[..., :3, 3], X.translation)
    np.testing.assert_array_equal(H[..., 3, :], np.broadcast_to([0, 0, 0, 1], batch_shape + (4,)))
    back = fd.PluckerTransform.from_homogeneous(H)
    assert back.dtype == dtype
    np.testing.assert_array_equal(back.rotation, X.rotation)
    np.testing.assert_array_equal(back.translation, X.translation)


def test_transform_from_matrix_round_trip(batch_shape, dtype, samples):
    X = samples.transform(batch_shape, dtype)
    back = fd.PluckerTransform.from_matrix(X.matrix())
    assert back.shape == batch_shape and back.dtype == dtype
    assert_close(back.rotation, X.rotation, "rotation")
    assert_close(back.translation, X.translation, "translation")


def test_inertia_matrix_and_from_matrix(batch_shape, dtype, samples, ref):
    inertia = samples.inertia(batch_shape, dtype)
    M = inertia.matrix()
    assert M.shape == batch_shape + (6, 6) and M.dtype == dtype
    expected = ref.per_batch(ref.inertia, (inertia.mass, 0), (inertia.com, 1), (inertia.inertia_com, 2))
    assert_close(M, expected, "inertia matrix")
    back = fd.SpatialInertia.from_matrix(M)
    assert back.dtype == dtype
    assert_close(back.mass, inertia.mass, "mass")
    assert_close(back.com, inertia.com, "com")
    assert_close(back.inertia_com, inertia.inertia_com, "inertia_com")


def test_momentum_and_kinetic_energy(batch_shape, dtype, samples, ref):
    inertia = samples.inertia(batch_shape, dtype)
    v = samples.motion(batch_shape, dtype)
    h = inertia @ v
    assert isinstance(h, fd.SpatialForce) and h.dtype == dtype and h.shape == batch_shape
    Iref = ref.per_batch(ref.inertia, (inertia.mass, 0), (inertia.com, 1), (inertia.inertia_com, 2))
    expected = (Iref @ v.vector.astype(np.float64)[..., None])[..., 0]
    assert_close(h.vector, expected, "I v")
    T = inertia.kinetic_energy(v)
    assert np.shape(T) == batch_shape and np.asarray(T).dtype == dtype
    assert_close(T, 0.5 * np.sum(v.vector * expected, axis=-1), "½ vᵀ I v")


def test_inertia_sum_and_zero(samples, ref):
    a, b = samples.inertia(), samples.inertia()
    s = a + b
    assert_close(s.matrix(), ref.inertia(a.mass, a.com, a.inertia_com) + ref.inertia(b.mass, b.com, b.inertia_com), "I_a + I_b")
    total = sum([a, b])
    assert_close(total.matrix(), s.matrix(), "sum([I_a, I_b])")
    z = fd.SpatialInertia.zero()
    assert_close((a + z).matrix(), a.matrix(), "I + 0")
    assert_close((z + z).matrix(), np.zeros((6, 6)), "0 + 0")


def test_apply_inverse_matches_formulas(samples, ref):
    X = samples.transform((3,))
    m, f = samples.motion((3,)), samples.force((3,))
    Xinv = ref.per_batch(lambda R, p: np.linalg.inv(ref.X(R, p)), (X.rotation, 2), (X.translation, 1))
    assert_close(X.apply_inverse(m).vector, (Xinv @ m.vector[..., None])[..., 0], "X⁻¹ m")
    XT = np.swapaxes(ref.per_batch(ref.X, (X.rotation, 2), (X.translation, 1)), -1, -2)
    assert_close(X.apply_inverse(f).vector, (XT @ f.vector[..., None])[..., 0], "Xᵀ f")


def test_identity_transform(dtype, samples):
    identity = fd.PluckerTransform.identity((2,), dtype=dtype)
    assert identity.dtype == dtype
    m = samples.motion((2,), dtype)
    np.testing.assert_array_equal(identity.apply(m).vector, m.vector)
    assert_close(identity.matrix(), np.broadcast_to(np.eye(6), (2, 6, 6)), "identity")


def test_allclose_methods(samples):
    m = samples.motion()
    assert m.allclose(fd.SpatialMotion.from_vector(m.vector + 1e-13))
    assert not m.allclose(fd.SpatialMotion.from_vector(m.vector + 1e-3))
    X = samples.transform()
    assert X.allclose(X.inverse().inverse())
    assert not X.allclose(X.inverse())
    with pytest.raises(SpatialTypeError):
        m.allclose(samples.force())
    with pytest.raises(SpatialTypeError, match="needs a PluckerTransform"):
        X.allclose(m)


# --------------------------------------------------------------------------
# SymPy object arrays
# --------------------------------------------------------------------------


def _symbols(prefix, n):
    sympy = pytest.importorskip("sympy")
    return np.array(sympy.symbols(f"{prefix}0:{n}", real=True), dtype=object)


def _subs(arr, values):
    return np.vectorize(lambda e: float(e.subs(values)) if hasattr(e, "subs") else float(e), otypes=[float])(arr)


def test_sympy_cross_products_and_matrices(samples):
    v_sym, m_sym, f_sym = _symbols("v", 6), _symbols("m", 6), _symbols("f", 6)
    v_num, m_num, f_num = samples.array((), (6,)), samples.array((), (6,)), samples.array((), (6,))
    values = dict(zip(v_sym, v_num, strict=True)) | dict(zip(m_sym, m_num, strict=True)) | dict(zip(f_sym, f_num, strict=True))
    assert fd.crm(v_sym).dtype == object
    assert_close(_subs(fd.crm(v_sym), values), fd.crm(v_num), "crm symbolic")
    assert_close(_subs(fd.crf(v_sym), values), fd.crf(v_num), "crf symbolic")
    vs, ms, fs = (fd.SpatialMotion.from_vector(v_sym), fd.SpatialMotion.from_vector(m_sym), fd.SpatialForce.from_vector(f_sym))
    vn, mn, fn = fd.SpatialMotion.from_vector(v_num), fd.SpatialMotion.from_vector(m_num), fd.SpatialForce.from_vector(f_num)
    assert_close(_subs(vs.cross(ms).vector, values), vn.cross(mn).vector, "v × m symbolic")
    assert_close(_subs(vs.cross(fs).vector, values), vn.cross(fn).vector, "v ×* f symbolic")
    assert_close(_subs(np.asarray(vs.dot(fs)), values), np.asarray(vn.dot(fn)), "v · f symbolic")


def test_sympy_transform(samples):
    sympy = pytest.importorskip("sympy")
    theta = sympy.Symbol("theta", real=True)
    p_sym = _symbols("p", 3)
    X = fd.rotz(np.array(theta, dtype=object)) @ fd.xlt(p_sym)
    assert X.dtype == object
    # exact symbolic entries: spatial_v2's rotz has cos θ on the diagonal
    assert X.rotation[0, 0] == sympy.cos(theta) and X.rotation[0, 1] == sympy.sin(theta)
    th, p = 0.7, samples.array((), (3,))
    values = {theta: th, **dict(zip(p_sym, p, strict=True))}
    Xn = fd.rotz(th) @ fd.xlt(p)
    assert_close(_subs(X.matrix(), values), Xn.matrix(), "X symbolic")
    assert_close(_subs(X.dual_matrix(), values), Xn.dual_matrix(), "X* symbolic")
    m = samples.motion()
    assert_close(_subs(X.apply(m).vector, values), Xn.apply(m).vector, "X m symbolic")


def test_sympy_inertia(samples):
    sympy = pytest.importorskip("sympy")
    mass = sympy.Symbol("m", positive=True)
    c_sym = _symbols("c", 3)
    i = sympy.symbols("ixx ixy ixz iyy iyz izz", real=True)
    Ic_sym = np.array([[i[0], i[1], i[2]], [i[1], i[3], i[4]], [i[2], i[4], i[5]]], dtype=object)
    inertia = fd.SpatialInertia(np.array(mass, dtype=object), c_sym, Ic_sym)
    M = inertia.matrix()
    assert M.dtype == object
    # the lower-right block is exactly m·1 (no floating-point 1.0 creeping into the algebra)
    assert M[3, 3] == mass and M[3, 4] == 0
    m_num, c_num, Ic_num = samples.inertia_params()
    values = {mass: float(m_num), **dict(zip(c_sym, c_num, strict=True))}
    values |= {i[0]: Ic_num[0, 0], i[1]: Ic_num[0, 1], i[2]: Ic_num[0, 2], i[3]: Ic_num[1, 1], i[4]: Ic_num[1, 2], i[5]: Ic_num[2, 2]}
    numeric = fd.SpatialInertia(m_num, c_num, Ic_num)
    assert_close(_subs(M, values), numeric.matrix(), "inertia matrix symbolic")
    v = samples.motion()
    assert_close(_subs((inertia @ v).vector, values), (numeric @ v).vector, "I v symbolic")
    other = samples.inertia()
    total = inertia + other
    assert total.dtype == object
    assert_close(_subs(total.matrix(), values), (numeric + other).matrix(), "I + I symbolic")
