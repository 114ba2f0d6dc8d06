"""Unknown URDF names are named, not passed over in silence (issue 32 item 6).

The names featherdyn reads are checked against the URDF specification and the known extensions
(``featherdyn.readers.urdf.URDF_EXTENSIONS``): one warning per file lists each unknown element and attribute with
its line and the nearest valid name; ``strict=True`` refuses; an error the unknown names may explain names them.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import PhysicalityWarning, URDFError

_INERTIAL = ('<inertial><mass value="1"/><origin xyz="0 0 0.1"{extra}/>'
             '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>')
_JOINT = ('<{tag} name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 1"/>'
          '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="2"{limit}/></{tag}>')


def _robot(extra: str = "", tag: str = "joint", limit: str = "", more: str = "") -> str:
    return (f'<robot name="r">\n<link name="a"/>\n<link name="b">{_INERTIAL.format(extra=extra)}</link>\n'
            f'{_JOINT.format(tag=tag, limit=limit)}\n{more}</robot>')


def _unknown_warnings(caught: list[warnings.WarningMessage]) -> list[str]:
    return [str(w.message) for w in caught if "unknown URDF names" in str(w.message)]


def test_a_misspelt_attribute_is_named_with_its_line_and_the_nearest_name() -> None:
    with pytest.warns(PhysicalityWarning, match=r"^<string>: unknown URDF names, ignored \(strict=True refuses "
                                                r"them\): line 3: <origin> attribute 'rpyy' \(did you mean 'rpy'\?\)$"):
        model = fd.load_urdf(_robot(extra=' rpyy="0 0 1"'))
    # what it means: the rpy was not read (the inertia is the one without a rotation)
    plain = fd.load_urdf(_robot())
    assert np.array_equal(model.inertias.inertia_com, plain.inertias.inertia_com)
    with pytest.raises(URDFError, match=r"line 3: <origin> attribute 'rpyy' \(did you mean 'rpy'\?\) \(strict=True\)"):
        fd.load_urdf(_robot(extra=' rpyy="0 0 1"'), strict=True)


def test_a_misspelt_element_is_named_in_the_error_it_causes() -> None:
    with pytest.raises(URDFError, match=r"more than one root link .*the file has unknown names, which may be why: "
                                        r"line 4: element <jiont> in <robot> \(did you mean <joint>\?\)"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PhysicalityWarning)
            fd.load_urdf(_robot(tag="jiont"))


def test_one_warning_per_file_names_every_unknown_name() -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fd.load_urdf(_robot(extra=' rpyy="0 0 1"', limit=' velocty="3"', more='<lnik name="c"/>\n'))
    found = _unknown_warnings(caught)
    assert len(found) == 1, found
    assert ("line 3: <origin> attribute 'rpyy' (did you mean 'rpy'?); line 4: <limit> attribute 'velocty' (did you "
            "mean 'velocity'?); line 5: element <lnik> in <robot> (did you mean <link>?)") in found[0]


def test_a_name_close_to_nothing_lists_what_is_valid() -> None:
    with pytest.warns(PhysicalityWarning, match=r"<mass> attribute 'frobnicate' \(expected one of 'value'\)"):
        fd.load_urdf(_robot().replace('<mass value="1"/>', '<mass value="1" frobnicate="2"/>'))


EXTENSIONS = (
    '<gazebo reference="b"><mu1>0.5</mu1><anything at="all"/></gazebo>\n'
    '<transmission name="t"><type>transmission_interface/SimpleTransmission</type><joint name="j">'
    '<hardwareInterface>EffortJointInterface</hardwareInterface></joint><actuator name="m">'
    '<mechanicalReduction>1</mechanicalReduction></actuator></transmission>\n'
    '<ros2_control name="c" type="system"><hardware><plugin>x</plugin></hardware></ros2_control>\n'
    '<sensor name="s" type="camera" update_rate="30"><parent link="b"/></sensor>\n'
    '<mujoco><compiler meshdir="meshes" discardvisual="false"/></mujoco>\n'
    '<material name="red"><color rgba="1 0 0 1"/></material>\n'
)


def test_documented_extensions_and_unread_parts_pass_silently() -> None:
    xml = _robot(more=EXTENSIONS).replace(
        '<link name="b">', '<link name="b"><contact><lateral_friction value="1"/></contact>'
        '<visual name="v"><origin xyz="0 0 0" rpyy="1"/><geometry><capsule radius="1" length="2"/></geometry>'
        '<material name="red"/></visual>').replace(
        '<joint name="j"', '<joint dont_collapse="true" name="j"').replace(
        'velocity="2"', 'velocity="2" command_effort="1" current="2" gear_velocity="3"')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fd.load_urdf(xml)
    assert not _unknown_warnings(caught), _unknown_warnings(caught)


def test_another_namespaces_names_pass_silently() -> None:
    xml = _robot().replace('<robot name="r">', '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro" '
                           'xmlns:x="http://example.org/x">').replace('<origin xyz="0 0 1"/>',
                                                                      '<origin xyz="0 0 1" x:note="hi"/><x:extra/>')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fd.load_urdf(xml)
    assert not _unknown_warnings(caught)


def test_the_robot_library_loads_without_unknown_name_warnings() -> None:
    """example-robot-data's robots use extensions (Gazebo, PyBullet, vendor attributes): none is reported, except
    so101's ``<link><origin>``, which URDF does not have (every reader ignores it; it is zero there)."""
    names = [n for n in fd.list_robots()]
    if len(names) < 10:
        pytest.skip("example-robot-data is not installed")
    reported = {}
    for name in names:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fd.load_robot(name)
        found = _unknown_warnings(caught)
        if found:
            reported[name] = found
    assert set(reported) <= {"so101"}, reported
    assert all("element <origin> in <link>" in w for found in reported.values() for w in found), reported
