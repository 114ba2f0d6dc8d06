"""Unit tests of featherdyn.robots: names, the default robot, the bundled 2R arm, missing example-robot-data."""

from __future__ import annotations

import importlib.metadata
import importlib.resources
import warnings

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import robots
from featherdyn.errors import MissingDependencyError, ModelError, PhysicalityWarning

ERD_INSTALLED = robots._erd_files() is not None
needs_erd = pytest.mark.skipif(not ERD_INSTALLED, reason="example-robot-data is not installed")


@pytest.fixture
def without_erd(monkeypatch: pytest.MonkeyPatch):
    """Pretend example-robot-data is not installed (through importlib.metadata, as the real lookup does)."""

    def not_found(name: str):
        raise importlib.metadata.PackageNotFoundError(name)

    robots._erd_files.cache_clear()
    robots._erd_names.cache_clear()
    monkeypatch.setattr(importlib.metadata, "files", not_found)
    yield
    monkeypatch.undo()
    robots._erd_files.cache_clear()
    robots._erd_names.cache_clear()


def test_list_robots_is_sorted_unique_and_includes_the_bundled_arm() -> None:
    names = fd.list_robots()
    assert names and names == sorted(set(names))
    assert "two_link_arm" in names


@needs_erd
def test_list_robots_names_example_robot_data_by_stem() -> None:
    names = fd.list_robots()
    assert len(names) >= 60
    for expected in ("panda", "solo12", "talos_full_v2", "ur5_robot"):
        assert expected in names
    # the two anymal.urdf files are qualified by folder, the unambiguous ones are not
    assert "anymal" not in names
    assert {"anymal_b_simple_description/anymal", "anymal_c_simple_description/anymal"} <= set(names)
    assert "ur3" not in names  # ur_description/urdf/ur3.urdf is an empty stub
    for name in names:
        assert robots.robot_path(name).is_file()


@needs_erd
def test_load_robot_default_is_panda() -> None:
    assert robots.default_robot() == "panda"
    model = fd.load_robot()
    assert model.name == "panda" and model.nbodies == 9 and model.nq == 9
    assert model.source == str(robots.robot_path("panda"))


@needs_erd
def test_qualified_names_and_base_option() -> None:
    assert robots.robot_path("panda_description/panda") == robots.robot_path("panda")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)
        b = fd.load_robot("anymal_b_simple_description/anymal", floating_base=True)
        c = fd.load_robot("anymal_c_simple_description/anymal", floating_base=True)
    assert b.floating_base and c.floating_base and b.nv == c.nv == 18
    assert b.total_mass != c.total_mass


@needs_erd
@pytest.mark.parametrize(
    ("name", "match"),
    [
        ("pandaa", r"unknown robot 'pandaa'; did you mean 'panda'"),
        ("talos", r"unknown robot 'talos'; did you mean 'talos_full_v2'"),
        ("anymal", r"robot name 'anymal' is ambiguous: use one of 'anymal_b_simple_description/anymal', "
                   r"'anymal_c_simple_description/anymal'"),
        ("ur3", r"unknown robot 'ur3'; did you mean 'ur3_gripper'"),
        ("zzzzzz", r"unknown robot 'zzzzzz' \(`featherdyn list` lists all \d+; in Python, featherdyn.list_robots\(\)\)"),
    ],
)
def test_unknown_names_suggest_close_matches(name: str, match: str) -> None:
    with pytest.raises(ModelError, match=match):
        fd.load_robot(name)


def test_bundled_two_link_arm(no_physicality_warnings) -> None:
    """The chapter's appendix-D arm: link lengths 1.0 / 0.8 m, masses 3 / 2 kg, COM at mid-link, Izz 0.25 / 0.11."""
    model = fd.load_robot("two_link_arm", strict=True)
    assert model.name == "two_link_arm"
    assert model.body_names == ("link1", "link2") and model.joint_names == ("joint1", "joint2")
    assert model.parents == (-1, 0) and (model.nq, model.nv) == (2, 2)
    assert np.array_equal(model.inertias.mass, [3.0, 2.0]) and model.total_mass == 5.0
    assert np.array_equal(model.inertias.com, [[0.5, 0, 0], [0.4, 0, 0]])
    assert np.array_equal(model.inertias.inertia_com[:, 2, 2], [0.25, 0.11])
    assert model.inertias.is_physical().all()
    for joint in model.joints:
        assert isinstance(joint, fd.RevoluteJoint) and np.array_equal(joint.axis, [0, 0, 1])
    assert np.array_equal(model.joint_placements.translation, [[0, 0, 0], [1.0, 0, 0]])
    assert np.allclose(model.lower, -np.pi) and np.allclose(model.upper, np.pi)
    tip = model.frames[model.frame_id("tip")]
    assert tip.body == 1 and np.array_equal(tip.placement.translation, [0.8, 0, 0])


def test_bundled_arm_is_package_data() -> None:
    resource = importlib.resources.files("featherdyn") / "data" / "two_link_arm.urdf"
    assert resource.is_file()
    assert robots.robot_path("two_link_arm").read_bytes() == resource.read_bytes()


def test_without_example_robot_data(without_erd) -> None:
    assert fd.list_robots() == ["two_link_arm"]
    assert robots.default_robot() == "two_link_arm"
    assert fd.load_robot().name == "two_link_arm"
    with pytest.raises(MissingDependencyError, match=r"robot 'panda' is not bundled.*pip install example-robot-data"):
        fd.load_robot("panda")


@pytest.fixture
def no_physicality_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error", PhysicalityWarning)
        yield
