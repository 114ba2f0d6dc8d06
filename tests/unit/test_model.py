"""Unit tests of featherdyn.model: ModelBuilder validation and the immutable Model."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import InertiaError, ModelError, PhysicalityWarning
from featherdyn.model import DEFAULT_GRAVITY, Mimic, massless_subtrees

# The chapter's appendix-D 2R planar arm: thin uniform rods along x (I_zz = m ℓ²/12 about the com).
L1, M1, C1, IZZ1 = 1.0, 3.0, 0.5, 0.25
L2, M2, C2, IZZ2 = 0.8, 2.0, 0.4, 0.11


def rod(mass: float, com_x: float, izz: float) -> fd.SpatialInertia:
    return fd.SpatialInertia(mass, [com_x, 0.0, 0.0], np.diag([0.0, izz, izz]))


def two_link_arm() -> fd.Model:
    b = fd.ModelBuilder("2R")
    l1 = b.add_body("link1", -1, fd.RevoluteJoint([0, 0, 1]), inertia=rod(M1, C1, IZZ1), joint_name="joint1")
    b.add_body(
        "link2",
        l1,
        fd.RevoluteJoint([0, 0, 1]),
        placement=fd.PluckerTransform(np.eye(3), [L1, 0.0, 0.0]),
        inertia=rod(M2, C2, IZZ2),
        joint_name="joint2",
    )
    b.add_frame("tip", l1 + 1, fd.PluckerTransform(np.eye(3), [L2, 0.0, 0.0]))
    return b.build()


def unit_inertia() -> fd.SpatialInertia:
    return fd.SpatialInertia(1.0, [0.1, 0.0, 0.0], np.diag([0.1, 0.2, 0.25]))


def mixed_tree() -> fd.Model:
    """world ─ base (free-flyer) ─┬─ ball (spherical) ─ arm (revolute y)
                                  └─ slide (planar)"""
    b = fd.ModelBuilder("mixed")
    base = b.add_body("base", -1, fd.FreeFlyerJoint(), inertia=unit_inertia(), joint_name="root")
    ball = b.add_body("ball", base, fd.SphericalJoint(), inertia=unit_inertia())
    b.add_body("arm", ball, fd.RevoluteJoint([0, 1, 0]), inertia=unit_inertia(), lower=-1.0, upper=2.0)
    b.add_body("slide", base, fd.PlanarJoint(), inertia=unit_inertia())
    return b.build()


# --------------------------------------------------------------------------
# the 2R arm
# --------------------------------------------------------------------------


def test_two_link_arm() -> None:
    model = two_link_arm()
    assert (model.nq, model.nv, model.nbodies) == (2, 2, 2)
    assert model.parents == (-1, 0)
    assert model.joint_names == ("joint1", "joint2")
    assert model.body_names == ("link1", "link2")
    assert model.total_mass == pytest.approx(M1 + M2)
    assert not model.floating_base
    np.testing.assert_array_equal(model.joint_placements.translation, [[0, 0, 0], [L1, 0, 0]])
    np.testing.assert_array_equal(model.inertias.mass, [M1, M2])
    np.testing.assert_array_equal(model.inertias.com[:, 0], [C1, C2])
    np.testing.assert_array_equal(model.inertias.inertia_com[:, 2, 2], [IZZ1, IZZ2])
    assert model.inertias.inertia_com[0, 2, 2] == pytest.approx(M1 * L1**2 / 12)  # a thin rod
    np.testing.assert_array_equal(model.gravity, DEFAULT_GRAVITY)
    assert model.idx_q == (0, 1) and model.idx_v == (0, 1) and model.nqs == (1, 1) and model.nvs == (1, 1)
    assert model.frame_id("tip") == 0
    tip = model.frames[model.frame_id("tip")]
    assert tip.body == 1 and tip.kind == "link"
    np.testing.assert_array_equal(tip.placement.translation, [L2, 0, 0])
    assert model.frames[model.frame_id("link2")].kind == "body"
    assert model.joint_id("joint2") == 1 and model.body_id("link1") == 0
    assert model.tree_transforms is model.joint_placements
    assert "2R" in repr(model) and "nq=2" in repr(model)
    np.testing.assert_array_equal(model.lower, [-np.inf, -np.inf])
    np.testing.assert_array_equal(model.velocity_limit, [np.inf, np.inf])
    assert model.source is None and model.mimics == ()


# --------------------------------------------------------------------------
# a mixed tree: where each joint sits in q and v
# --------------------------------------------------------------------------


def test_mixed_tree_indices() -> None:
    model = mixed_tree()
    assert model.nqs == (7, 4, 1, 3)
    assert model.nvs == (6, 3, 1, 3)
    assert model.idx_q == (0, 7, 11, 12)
    assert model.idx_v == (0, 6, 9, 10)
    assert (model.nq, model.nv, model.nbodies) == (15, 13, 4)
    assert model.total_mass == pytest.approx(4.0)
    assert model.floating_base
    assert model.joint_names == ("root", "ball_joint", "arm_joint", "slide_joint")
    assert [j.kind for j in model.joints] == ["free_flyer", "spherical", "revolute", "planar"]
    np.testing.assert_array_equal(model.lower[11], -1.0)
    np.testing.assert_array_equal(model.upper[11], 2.0)
    assert model.lower.shape == model.upper.shape == (15,)
    assert model.velocity_limit.shape == model.effort_limit.shape == (13,)
    # the slices tile q and v exactly
    assert sorted(i for k in range(4) for i in range(model.idx_q[k], model.idx_q[k] + model.nqs[k])) == list(range(15))
    assert sorted(i for k in range(4) for i in range(model.idx_v[k], model.idx_v[k] + model.nvs[k])) == list(range(13))


def test_children_and_subtree() -> None:
    model = mixed_tree()
    assert model.children(-1) == [0]
    assert model.children(0) == [1, 3]
    assert model.children(1) == [2]
    assert model.children(2) == []
    assert model.subtree(0) == [0, 1, 2, 3]
    assert model.subtree(1) == [1, 2]
    assert model.subtree(3) == [3]
    with pytest.raises(ModelError, match="body index"):
        model.subtree(4)
    with pytest.raises(ModelError):
        model.subtree(-1)
    with pytest.raises(ModelError):
        model.children(7)


# --------------------------------------------------------------------------
# frames
# --------------------------------------------------------------------------


def test_frame_lookup_and_unknown_names() -> None:
    model = two_link_arm()
    assert [f.name for f in model.frames] == ["tip", "link1", "link2"]
    with pytest.raises(ModelError, match=r"frame 'link3' not found in model '2R'; similar: \['link2', 'link1'\]"):
        model.frame_id("link3")
    with pytest.raises(ModelError, match="similar"):
        model.frame_id("LINK")  # substring, any case
    with pytest.raises(ModelError) as info:
        model.frame_id("nothing_like_it")
    assert "similar" not in str(info.value)
    with pytest.raises(ModelError, match=r"joint 'joint3' not found.*joint1"):
        model.joint_id("joint3")
    with pytest.raises(ModelError, match=r"body 'lnk1' not found.*link1"):
        model.body_id("lnk1")


def test_explicit_frame_of_a_body_name_wins() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_frame("a", 0, fd.PluckerTransform(np.eye(3), [1.0, 0, 0]), kind="link")
    b.add_frame("world_marker", -1)
    model = b.build()
    assert [f.name for f in model.frames] == ["a", "world_marker"]
    assert model.frames[model.frame_id("world_marker")].body == -1


def test_add_frame_validation() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    with pytest.raises(ModelError, match="no body 1"):
        b.add_frame("f", 1)
    with pytest.raises(ModelError, match="non-empty string"):
        b.add_frame("", 0)
    with pytest.raises(ModelError, match="PluckerTransform"):
        b.add_frame("f", 0, np.eye(4))  # type: ignore[arg-type]


# --------------------------------------------------------------------------
# builder validation
# --------------------------------------------------------------------------


def test_parent_must_already_exist() -> None:
    b = fd.ModelBuilder()
    with pytest.raises(ModelError, match="parents first"):
        b.add_body("a", 0, fd.RevoluteJoint())
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    with pytest.raises(ModelError, match="got 1"):
        b.add_body("b", 1, fd.RevoluteJoint())
    with pytest.raises(ModelError):
        b.add_body("b", -2, fd.RevoluteJoint())
    for bad in (0.0, "0", True, None):
        with pytest.raises(ModelError):
            b.add_body("b", bad, fd.RevoluteJoint())  # type: ignore[arg-type]
    assert b.add_body("b", np.int64(0), fd.RevoluteJoint(), inertia=unit_inertia()) == 1


def test_duplicate_names() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia(), joint_name="j")
    with pytest.raises(ModelError, match="body name 'a' is used twice"):
        b.add_body("a", 0, fd.RevoluteJoint(), joint_name="k")
    with pytest.raises(ModelError, match="joint name 'j' is used twice"):
        b.add_body("b", 0, fd.RevoluteJoint(), joint_name="j")
    # the default joint name may collide with an explicit one
    b.add_body("c", 0, fd.RevoluteJoint(), inertia=unit_inertia(), joint_name="d_joint")
    with pytest.raises(ModelError, match="'d_joint' is used twice"):
        b.add_body("d", 0, fd.RevoluteJoint())
    assert b.nbodies == 2  # the failed calls added nothing


def test_wrong_types() -> None:
    b = fd.ModelBuilder()
    with pytest.raises(ModelError, match="Joint"):
        b.add_body("a", -1, "revolute")  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="non-empty string"):
        b.add_body(3, -1, fd.RevoluteJoint())  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="non-empty string"):
        b.add_body("a", -1, fd.RevoluteJoint(), joint_name="")
    with pytest.raises(ModelError, match="placement"):
        b.add_body("a", -1, fd.RevoluteJoint(), placement=np.eye(4))  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="single PluckerTransform"):
        b.add_body("a", -1, fd.RevoluteJoint(), placement=fd.PluckerTransform.identity((2,)))
    with pytest.raises(ModelError, match="inertia"):
        b.add_body("a", -1, fd.RevoluteJoint(), inertia=np.eye(6))  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="single SpatialInertia"):
        b.add_body("a", -1, fd.RevoluteJoint(), inertia=fd.SpatialInertia.zero((2,)))
    with pytest.raises(ValueError):
        fd.ModelBuilder(gravity=(0.0, -9.81))
    assert b.nbodies == 0


def test_negative_mass() -> None:
    b = fd.ModelBuilder()
    with pytest.raises(InertiaError, match="negative mass -1"):
        b.add_body("a", -1, fd.RevoluteJoint(), inertia=fd.SpatialInertia(-1.0, np.zeros(3), np.eye(3)))


def test_limits() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.FreeFlyerJoint(), inertia=unit_inertia(), lower=-2.0, velocity_limit=[1, 2, 3, 4, 5, 6])
    with pytest.raises(ModelError, match="nq=1"):
        b.add_body("b", 0, fd.RevoluteJoint(), lower=[0.0, 1.0])
    with pytest.raises(ModelError, match="NaN"):
        b.add_body("b", 0, fd.RevoluteJoint(), upper=np.nan)
    with pytest.raises(TypeError):  # DTypeError
        b.add_body("b", 0, fd.RevoluteJoint(), upper="high")
    b.add_body("b", 0, fd.RevoluteJoint(), inertia=unit_inertia(), lower=1.0, upper=-1.0)
    with pytest.warns(PhysicalityWarning, match="lower limit .* above upper"):
        model = b.build()
    np.testing.assert_array_equal(model.lower[:7], -2.0)
    np.testing.assert_array_equal(model.upper[:7], np.inf)
    np.testing.assert_array_equal(model.velocity_limit[:6], [1, 2, 3, 4, 5, 6])
    with pytest.raises(ModelError, match="above upper"):
        b.build(strict=True)


def test_massless_subtree() -> None:
    b = fd.ModelBuilder("m")
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_body("b", 0, fd.RevoluteJoint())  # no inertia, no children
    b.add_body("c", 0, fd.RevoluteJoint())  # massless itself, but carries d
    b.add_body("d", 2, fd.RevoluteJoint(), inertia=unit_inertia())
    with pytest.warns(PhysicalityWarning, match="'b_joint'.*no mass") as record:
        model = b.build()
    assert len(record) == 1  # c is fine: its subtree (d) has mass
    assert len(massless_subtrees(model)) == 1
    with pytest.raises(ModelError, match=r"'b_joint'.*strict=True"):
        b.build(strict=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b.build(check_inertias=False)


def test_add_inertia_lumps() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_inertia(0, fd.SpatialInertia(2.0, [0.0, 0.5, 0.0], np.eye(3) * 0.01))
    model = b.build()
    assert model.total_mass == pytest.approx(3.0)
    np.testing.assert_allclose(model.inertias.matrix()[0], (unit_inertia() + fd.SpatialInertia(2.0, [0, 0.5, 0], np.eye(3) * 0.01)).matrix())
    with pytest.raises(ModelError, match="no body 1"):
        b.add_inertia(1, unit_inertia())


def test_empty_model() -> None:
    model = fd.ModelBuilder("empty").build()
    assert (model.nq, model.nv, model.nbodies, model.total_mass) == (0, 0, 0, 0.0)
    assert model.lower.shape == (0,)
    assert not model.floating_base


def test_mimic_is_recorded() -> None:
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_body("b", 0, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_mimic(Mimic("b_joint", "a_joint", -1.0, 0.1))
    assert b.build().mimics == (Mimic("b_joint", "a_joint", -1.0, 0.1),)


# --------------------------------------------------------------------------
# immutability
# --------------------------------------------------------------------------


def test_model_is_immutable() -> None:
    model = mixed_tree()
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.name = "other"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.parents = (-1,)  # type: ignore[misc]
    with pytest.raises((AttributeError, TypeError)):  # slots; CPython 3.11 raises TypeError here
        model.extra = 1  # type: ignore[attr-defined]
    for name in ("gravity", "lower", "upper", "velocity_limit", "effort_limit"):
        arr = getattr(model, name)
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 0.0
    for arr in (
        model.joint_placements.rotation,
        model.joint_placements.translation,
        model.inertias.mass,
        model.inertias.com,
        model.inertias.inertia_com,
    ):
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 0.0
    with pytest.raises(AttributeError):
        model.frames[0].name = "x"  # type: ignore[misc]
    assert isinstance(model.parents, tuple) and isinstance(model.joints, tuple)


def test_builder_is_not_aliased_by_the_model() -> None:
    """Building again after more add_body calls leaves the first model unchanged."""
    b = fd.ModelBuilder()
    b.add_body("a", -1, fd.RevoluteJoint(), inertia=unit_inertia())
    first = b.build()
    b.add_body("b", 0, fd.RevoluteJoint(), inertia=unit_inertia())
    b.add_inertia(0, unit_inertia())
    second = b.build()
    assert (first.nbodies, second.nbodies) == (1, 2)
    assert first.total_mass == pytest.approx(1.0) and second.total_mass == pytest.approx(3.0)


def test_replace_gives_a_new_model() -> None:
    model = two_link_arm()
    other = dataclasses.replace(model, name="renamed")
    assert other.name == "renamed" and model.name == "2R"
    assert other.frame_id("tip") == 0
    fewer = dataclasses.replace(model, frames=model.frames[1:])  # the frame index follows the frames
    assert fewer.frame_id("link2") == 1
    with pytest.raises(ModelError):
        fewer.frame_id("tip")
