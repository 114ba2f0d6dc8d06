"""Frame tags: the checks made when tagged values meet, and the tags results carry.

Rule under test (featherdyn.frames): untagged values are never checked;
combining two tagged values whose frames differ raises FrameMismatchError
naming both frames; results carry the right tags (X.apply re-tags to
X.target, composition chains source/target, relative motions chain as
v_A/B + v_B/C = v_A/C).
"""

from __future__ import annotations

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.frames import chain_bodies, check_same_frame, merge_frames
from featherdyn.testing import assert_close

FrameMismatchError = fd.FrameMismatchError


def _names_both(info: pytest.ExceptionInfo, a: object, b: object) -> None:
    text = str(info.value)
    assert repr(a) in text and repr(b) in text, text


# --------------------------------------------------------------------------
# the helpers
# --------------------------------------------------------------------------


def test_check_same_frame():
    check_same_frame("A", "A", "op")
    check_same_frame("A", None, "op")
    check_same_frame(None, "B", "op")
    check_same_frame(None, None, "op")
    with pytest.raises(FrameMismatchError, match=r"^op: ") as info:
        check_same_frame("A", "B", "op")
    _names_both(info, "A", "B")
    assert isinstance(info.value, ValueError)


def test_merge_frames_keeps_the_tag_that_is_set():
    assert merge_frames("A", None, "op") == "A"
    assert merge_frames(None, "A", "op") == "A"
    assert merge_frames("A", "A", "op") == "A"
    assert merge_frames(None, None, "op") is None
    with pytest.raises(FrameMismatchError):
        merge_frames("A", "B", "op")


def test_chain_bodies():
    assert chain_bodies("A", "B", "B", "C", "op") == ("A", "C")
    assert chain_bodies("B", "C", "A", "B", "op") == ("A", "C")  # either order
    assert chain_bodies("A", "B", "A", "B", "op") == ("A", "B")
    assert chain_bodies("A", "B", "B", None, "op") == ("A", None)  # keeps what is certain
    assert chain_bodies("A", None, "C", "D", "op") == (None, None)
    assert chain_bodies(None, None, None, None, "op") == (None, None)
    with pytest.raises(FrameMismatchError, match="v_A/B \\+ v_B/C = v_A/C") as info:
        chain_bodies("A", "B", "C", "D", "op")
    for name in "ABCD":
        assert repr(name) in str(info.value)


def test_any_hashable_is_a_frame(samples):
    a, b = samples.motion(frame=("robot", 1)), samples.motion(frame=("robot", 1))
    assert (a + b).frame == ("robot", 1)
    with pytest.raises(FrameMismatchError):
        a + samples.motion(frame=("robot", 2))


# --------------------------------------------------------------------------
# combining tagged values
# --------------------------------------------------------------------------


def _mismatch_cases(samples):
    mA, mB = samples.motion(frame="A"), samples.motion(frame="B")
    fA, fB = samples.force(frame="A"), samples.force(frame="B")
    IA, IB = samples.inertia(frame="A"), samples.inertia(frame="B")
    return [
        ("motion + motion", lambda: mA + mB),
        ("motion - motion", lambda: mA - mB),
        ("force + force", lambda: fA + fB),
        ("force - force", lambda: fA - fB),
        ("motion.dot(force)", lambda: mA.dot(fB)),
        ("force.dot(motion)", lambda: fA.dot(mB)),
        ("cross_motion", lambda: mA.cross(mB)),
        ("cross_force", lambda: mA.cross(fB)),
        ("inertia @ motion", lambda: IA @ mB),
        ("inertia + inertia", lambda: IA + IB),
        ("kinetic_energy", lambda: IA.kinetic_energy(mB)),
        ("motion.allclose", lambda: mA.allclose(mB)),
        ("force.allclose", lambda: fA.allclose(fB)),
        ("X.allclose", lambda: samples.transform(source="A").allclose(samples.transform(source="B"))),
    ]


def test_tagged_values_in_different_frames_raise(samples):
    for what, call in _mismatch_cases(samples):
        with pytest.raises(FrameMismatchError) as info:
            call()
        text = str(info.value)
        assert "'A'" in text and "'B'" in text, f"{what}: {text}"


def test_untagged_values_are_never_checked(samples):
    mA, m = samples.motion(frame="A"), samples.motion()
    fA, f = samples.force(frame="A"), samples.force()
    IA, inertia = samples.inertia(frame="A"), samples.inertia()
    assert (mA + m).frame == "A" and (m + mA).frame == "A"
    assert (m + m).frame is None
    assert (fA - f).frame == "A"
    assert (IA @ m).frame == "A" and (inertia @ mA).frame == "A"
    assert (IA + inertia).frame == "A"
    assert mA.cross(m).frame == "A" and m.cross(fA).frame == "A"
    mA.dot(f)
    IA.kinetic_energy(m)


def test_same_frame_combines_and_keeps_the_tag(samples):
    a, b = samples.motion(frame="A"), samples.motion(frame="A")
    assert_close((a + b).vector, a.vector + b.vector, "a + b")
    assert (a + b).frame == "A" and (-a).frame == "A" and (2.0 * a).frame == "A" and a[()].frame == "A"
    f = samples.force(frame="A")
    assert (f + f).frame == "A" and (f / 2.0).frame == "A"


# --------------------------------------------------------------------------
# transforms
# --------------------------------------------------------------------------


def test_apply_retags_to_target_and_checks_source(samples, ref):
    X = samples.transform(source="A", target="B")
    m, f, inertia = samples.motion(frame="A"), samples.force(frame="A"), samples.inertia(frame="A")
    Xm, Xf, XI = X.apply(m), X.apply(f), X.apply(inertia)
    assert Xm.frame == "B" and Xf.frame == "B" and XI.frame == "B"
    assert_close(Xm.vector, ref.X(X.rotation, X.translation) @ m.vector, "X m")
    for value in (samples.motion(frame="C"), samples.force(frame="C"), samples.inertia(frame="C")):
        with pytest.raises(FrameMismatchError) as info:
            X.apply(value)
        _names_both(info, "C", "A")
        assert "X.source" in str(info.value)
    # untagged values are accepted and come out expressed in the target
    assert X.apply(samples.motion()).frame == "B"
    assert (X @ samples.force()).frame == "B"


def test_apply_inverse_checks_target_and_retags_to_source(samples):
    X = samples.transform(source="A", target="B")
    m, f, inertia = samples.motion(frame="B"), samples.force(frame="B"), samples.inertia(frame="B")
    assert X.apply_inverse(m).frame == "A"
    assert X.apply_inverse(f).frame == "A"
    assert X.apply_inverse(inertia).frame == "A"
    with pytest.raises(FrameMismatchError) as info:
        X.apply_inverse(samples.motion(frame="A"))
    _names_both(info, "A", "B")


def test_untagged_transform_keeps_nothing(samples):
    X = samples.transform()
    assert X.apply(samples.motion(frame="A")).frame is None  # target unknown
    assert X.source is None and X.target is None


def test_composition_checks_and_chains_frames(samples, ref):
    X_BA = samples.transform(source="A", target="B")
    X_CB = samples.transform(source="B", target="C")
    X_CA = X_CB @ X_BA
    assert X_CA.source == "A" and X_CA.target == "C"
    assert_close(
        X_CA.matrix(),
        ref.X(X_CB.rotation, X_CB.translation) @ ref.X(X_BA.rotation, X_BA.translation),
        "X_CB X_BA",
    )
    with pytest.raises(FrameMismatchError) as info:
        X_BA @ X_CB  # X_BA.source 'A' vs X_CB.target 'C'
    _names_both(info, "A", "C")
    X_DA = samples.transform(source="A", target="D")
    with pytest.raises(FrameMismatchError) as info:
        X_CB @ X_DA
    _names_both(info, "B", "D")
    # partial tags: composing with an untagged transform is not checked
    X = samples.transform()
    assert (X_CB @ X).source is None and (X_CB @ X).target == "C"
    assert (X @ X_BA).source == "A" and (X @ X_BA).target is None


def test_inverse_swaps_source_and_target(samples):
    X = samples.transform(source="A", target="B")
    inv = X.inverse()
    assert inv.source == "B" and inv.target == "A"
    assert (inv @ X).source == "A" and (inv @ X).target == "A"
    assert_close((inv @ X).matrix(), np.eye(6), "X⁻¹ X")


def test_batch_indexing_keeps_transform_tags(samples):
    X = samples.transform((3,), source="A", target="B")
    assert X[1].source == "A" and X[1].target == "B"


# --------------------------------------------------------------------------
# relative motions: body / relative_to
# --------------------------------------------------------------------------


def _rel(samples, body, relative_to, frame="W"):
    return samples.motion(frame=frame, body=body, relative_to=relative_to)


def test_relative_motions_chain(samples):
    v_AB, v_BC = _rel(samples, "A", "B"), _rel(samples, "B", "C")
    for total in (v_AB + v_BC, v_BC + v_AB):
        assert (total.body, total.relative_to) == ("A", "C")
        assert total.frame == "W"
        assert_close(total.vector, v_AB.vector + v_BC.vector, "v_A/B + v_B/C")


def test_negation_swaps_body_and_relative_to(samples):
    v = _rel(samples, "A", "B")
    neg = -v
    assert (neg.body, neg.relative_to) == ("B", "A")
    assert neg.frame == "W"
    np.testing.assert_array_equal(neg.vector, -v.vector)


def test_difference_of_motions_relative_to_world(samples):
    v_AW, v_BW = _rel(samples, "A", "world"), _rel(samples, "B", "world")
    v_AB = v_AW - v_BW
    assert (v_AB.body, v_AB.relative_to) == ("A", "B")
    assert_close(v_AB.vector, v_AW.vector - v_BW.vector, "v_A/W − v_B/W")


def test_incompatible_relative_motions_raise(samples):
    with pytest.raises(FrameMismatchError) as info:
        _rel(samples, "A", "B") + _rel(samples, "C", "D")
    for name in "ABCD":
        assert repr(name) in str(info.value)
    with pytest.raises(FrameMismatchError):
        _rel(samples, "A", "W") - _rel(samples, "B", "V")  # v_A/W + v_V/B: no link


def test_partially_tagged_relative_motions_are_not_checked(samples):
    total = _rel(samples, "A", None) + _rel(samples, "C", "D")
    assert total.body is None and total.relative_to is None


def test_scaling_and_transforms_keep_body_tags(samples):
    v = _rel(samples, "A", "B", frame="F")
    assert ((2.0 * v).body, (2.0 * v).relative_to) == ("A", "B")
    X = samples.transform(source="F", target="G")
    Xv = X.apply(v)
    assert (Xv.body, Xv.relative_to, Xv.frame) == ("A", "B", "G")
    back = X.apply_inverse(Xv)
    assert (back.body, back.relative_to, back.frame) == ("A", "B", "F")


def test_relative_motions_in_different_frames_still_raise(samples):
    with pytest.raises(FrameMismatchError):
        _rel(samples, "A", "B", frame="F") + _rel(samples, "B", "C", frame="G")
