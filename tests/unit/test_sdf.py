"""Unit tests of featherdyn.readers.sdf (``fd.load_sdf``): closed forms, SDFormat's frame semantics, includes, errors.

Each document is written here; each test asserts numbers computed by hand
(mass matrices of pendulums, frame placements), or the equality of two
documents that say the same thing in two SDFormat styles, or the exact
refusal: an :class:`~featherdyn.SDFError` whose message names the source,
the element and the attribute.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import ModelError, PhysicalityWarning, SDFError
from featherdyn.readers.sdf import MAX_INCLUDE_DEPTH

INERTIA = "<inertia><ixx>{}</ixx><ixy>0</ixy><ixz>0</ixz><iyy>{}</iyy><iyz>0</iyz><izz>{}</izz></inertia>"


def inertial(mass: float, ixx: float, iyy: float, izz: float, pose: str = "") -> str:
    return f"<inertial><mass>{mass}</mass>{pose}{INERTIA.format(ixx, iyy, izz)}</inertial>"


def sdf(body: str, version: str = "1.9", name: str = "m") -> str:
    return f'<sdf version="{version}"><model name="{name}">{body}</model></sdf>'


def load(text, **kw) -> fd.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)
        return fd.load_sdf(text, **kw)


def rotx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rotz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


WELD = '<joint name="weld" type="fixed"><parent>world</parent><child>base</child></joint><link name="base"/>'


# --------------------------------------------------------------------------
# closed forms
# --------------------------------------------------------------------------


def test_pendulum_mass_matrix_and_gravity_by_hand():
    """A pendulum about x through the joint at the link origin: M = Ixx + m d², gravity torque m g d sin(q)."""
    m, d, ixx = 2.0, 0.5, 0.1
    text = sdf(WELD + f'<link name="arm"><pose>0 0 1 0 0 0</pose>{inertial(m, ixx, 0.2, 0.3, f"<pose>0 0 {-d} 0 0 0</pose>")}'
               '</link><joint name="j" type="revolute"><parent>base</parent><child>arm</child>'
               "<axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>2</upper><effort>5</effort>"
               "<velocity>3</velocity></limit></axis></joint>")
    model = load(text)
    assert model.nq == model.nv == 1 and model.joint_names == ("j",) and model.body_names == ("arm",)
    q = np.array([0.3])
    np.testing.assert_allclose(fd.crba(model, q), [[ixx + m * d * d]], rtol=1e-14)
    # the com hangs at -d below the axis: rotated by q about x, its height is -d cos(q); τ_g = ∂V/∂q = m g d sin(q)
    np.testing.assert_allclose(fd.generalized_gravity(model, q), [m * 9.81 * d * math.sin(0.3)], rtol=1e-12)
    assert model.lower.tolist() == [-1.0] and model.upper.tolist() == [2.0]
    assert model.velocity_limit.tolist() == [3.0] and model.effort_limit.tolist() == [5.0]
    # the joint is at the link's origin (its default relative_to is the child): z = 1 in the world
    np.testing.assert_allclose(fd.frame_placement(model, np.zeros(1), "arm").translation, [0, 0, 1], atol=1e-15)


def test_rotated_inertia_is_expressed_in_the_link_frame():
    """<inertial><pose> rotates the tensor: I_link = R I Rᵀ (here R = Rz(90°) swaps ixx and iyy)."""
    body = f'<link name="arm">{inertial(1.0, 0.1, 0.4, 0.3, "<pose>0 0 0 0 0 1.5707963267948966</pose>")}</link>'
    for axis, expected in (("1 0 0", 0.4), ("0 1 0", 0.1), ("0 0 1", 0.3)):
        model = load(sdf(WELD + body + '<joint name="j" type="continuous"><parent>base</parent><child>arm</child>'
                         f"<axis><xyz>{axis}</xyz></axis></joint>"))
        np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[expected]], rtol=1e-12, atol=1e-15)
    # the same with a quaternion (x y z w) and in degrees
    for pose in ('<pose rotation_format="quat_xyzw">0 0 0 0 0 0.7071067811865476 0.7071067811865476</pose>',
                 '<pose degrees="true">0 0 0 0 0 90</pose>'):
        model = load(sdf(WELD + f'<link name="arm">{inertial(1.0, 0.1, 0.4, 0.3, pose)}</link>'
                         '<joint name="j" type="continuous"><parent>base</parent><child>arm</child>'
                         "<axis><xyz>1 0 0</xyz></axis></joint>"))
        np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[0.4]], rtol=1e-12)
    assert model.lower.tolist() == [-math.inf]  # continuous: unbounded


def test_ball_joint_is_spherical_and_prismatic_moves_the_mass():
    model = load(sdf(WELD + f'<link name="b">{inertial(3.0, 0.1, 0.2, 0.3, "<pose>0 0 -1 0 0 0</pose>")}</link>'
                     '<joint name="ball" type="ball"><parent>base</parent><child>b</child></joint>'))
    assert (model.nq, model.nv) == (4, 3)
    np.testing.assert_allclose(fd.crba(model, fd.neutral(model)), np.diag([0.1 + 3, 0.2 + 3, 0.3]), atol=1e-14)
    model = load(sdf(WELD + f'<link name="s">{inertial(3.0, 0.1, 0.2, 0.3)}</link>'
                     '<joint name="slide" type="prismatic"><parent>base</parent><child>s</child>'
                     "<axis><xyz>0 0 1</xyz><limit><lower>0</lower><upper>1</upper></limit></axis></joint>"))
    np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[3.0]])
    np.testing.assert_allclose(fd.generalized_gravity(model, np.zeros(1)), [3 * 9.81])


def test_universal_joint_is_two_revolute_joints_through_a_massless_carrier():
    """universal = revolute about <axis>, then revolute about <axis2>: the same as two joints and a massless link."""
    child = f'<link name="c"><pose>0 0 0.2 0.1 0.2 0.3</pose>{inertial(2.0, 0.1, 0.2, 0.3, "<pose>0.1 0 -0.4 0 0 0</pose>")}</link>'
    universal = load(sdf(WELD + child + '<joint name="u" type="universal"><parent>base</parent><child>c</child>'
                         "<pose>0 0 0.1 0 0 0</pose><axis><xyz>1 0 0</xyz></axis><axis2><xyz>0 1 0</xyz></axis2>"
                         "</joint>"))
    assert universal.joint_names == ("u/axis", "u/axis2") and universal.body_names == ("c#0", "c")
    assert universal.inserted_bodies == ("c#0",)
    two = load(sdf(WELD + child + '<link name="mid"><pose relative_to="c">0 0 0.1 0 0 0</pose>'
                   "<inertial><mass>0</mass>" + INERTIA.format(0, 0, 0) + "</inertial></link>"
                   '<joint name="a1" type="continuous"><parent>base</parent><child>mid</child>'
                   "<axis><xyz>1 0 0</xyz></axis></joint>"
                   '<joint name="a2" type="continuous"><parent>mid</parent><child>c</child>'
                   '<pose relative_to="mid"/><axis><xyz expressed_in="mid">0 1 0</xyz></axis></joint>'))
    rng = np.random.default_rng(3)
    for _ in range(3):
        q, v, a = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2)
        np.testing.assert_allclose(fd.crba(universal, q), fd.crba(two, q), rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(fd.rnea(universal, q, v, a), fd.rnea(two, q, v, a), rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(fd.frame_placement(universal, q, "c").matrix(),
                                   fd.frame_placement(two, q, "c").matrix(), atol=1e-14)


# --------------------------------------------------------------------------
# poses and frames
# --------------------------------------------------------------------------


def test_relative_to_chains_and_frames_give_placements_by_hand():
    """A frame F attached to base, posed relative to it; a link relative to F; a frame relative to the link."""
    text = sdf(WELD +
               '<frame name="F" attached_to="base"><pose>1 0 0 0 0 1.5707963267948966</pose></frame>'
               f'<link name="l"><pose relative_to="F">0 2 0 0 0 0</pose>{inertial(1, 1, 1, 1)}</link>'
               '<frame name="tip" attached_to="l"><pose>0 0 3 0 0 0</pose></frame>'
               '<frame name="G"><pose relative_to="tip">0 0 1 0 0 0</pose></frame>'
               '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
               "<axis><xyz>0 0 1</xyz></axis></joint>")
    model = load(text)
    q0 = np.zeros(1)
    # F at (1,0,0) turned 90° about z: its y axis is the world's −x, so l sits at (1,0,0) + 2·(−1,0,0) = (−1,0,0)
    np.testing.assert_allclose(fd.frame_placement(model, q0, "l").translation, [-1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(fd.frame_placement(model, q0, "l").rotation, rotz(math.pi / 2), atol=1e-15)
    np.testing.assert_allclose(fd.frame_placement(model, q0, "tip").translation, [-1, 0, 3], atol=1e-15)
    # G is attached to the model frame (the canonical link: base, on the world) but placed relative to tip
    np.testing.assert_allclose(fd.frame_placement(model, q0, "G").translation, [-1, 0, 4], atol=1e-15)
    assert model.frames[model.frame_id("G")].body == -1
    # turning j about z (through l's origin) carries tip along, not G
    q = np.array([0.5])
    np.testing.assert_allclose(fd.frame_placement(model, q, "tip").translation, [-1, 0, 3], atol=1e-14)
    np.testing.assert_allclose(fd.frame_placement(model, q, "tip").rotation, rotz(math.pi / 2 + 0.5), atol=1e-14)


def test_joint_pose_relative_to_the_parent_and_axis_expressed_in_the_model():
    """The joint frame posed relative to the parent link, the child relative to the joint; axis in __model__."""
    a = sdf(WELD + f'<link name="l"><pose relative_to="j">0 0 0 0 0 0</pose>{inertial(2, 0.1, 0.2, 0.3, "<pose>0 0.5 0 0 0 0</pose>")}</link>'
            '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
            '<pose relative_to="base">0 0 1 0.7 0 0</pose><axis><xyz expressed_in="__model__">0 0 1</xyz></axis></joint>')
    model = load(a)
    # the joint frame is rotated 0.7 about x: the model's z is (0, sin 0.7, cos 0.7) in it
    joint = model.joints[0]
    np.testing.assert_allclose(np.asarray(joint.axis), [0, math.sin(0.7), math.cos(0.7)], atol=1e-15)
    # M = a·(I_c + m (|d|² 1 − d dᵀ)) a with d = (0, 0.5, 0) in the joint frame
    ax = np.array([0, math.sin(0.7), math.cos(0.7)])
    d = np.array([0, 0.5, 0])
    I_o = np.diag([0.1, 0.2, 0.3]) + 2 * (d @ d * np.eye(3) - np.outer(d, d))
    np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[ax @ I_o @ ax]], rtol=1e-12)


def test_sdf_1_4_axis_in_the_model_frame_equals_1_7_axis_in_the_joint_frame():
    """The same robot: SDFormat 1.4 (axis in the model frame), 1.6 use_parent_model_frame, 1.7 expressed_in."""
    link = f'<link name="l"><pose>0.1 0.2 0.3 0.4 0 0</pose>{inertial(2, 0.1, 0.2, 0.3, "<pose>0 0.3 0.1 0 0 0</pose>")}</link>'
    in_model = rotx(0.4) @ np.array([0.0, 1.0, 0.0])
    xyz = " ".join(repr(float(x)) for x in in_model)
    models = [
        load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                 f"<axis><xyz>{xyz}</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>", "1.4")),
        load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                 f"<axis><xyz>{xyz}</xyz><use_parent_model_frame>true</use_parent_model_frame>"
                 "<limit><lower>-1</lower><upper>1</upper></limit></axis></joint>", "1.6")),
        load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                 "<axis><xyz>0 1 0</xyz><use_parent_model_frame>false</use_parent_model_frame>"
                 "<limit><lower>-1</lower><upper>1</upper></limit></axis></joint>", "1.6")),
        load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                 "<axis><xyz>0 1 0</xyz></axis></joint>", "1.7")),
        load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                 f'<axis><xyz expressed_in="__model__">{xyz}</xyz></axis></joint>', "1.11")),
    ]
    q = np.array([0.6])
    M = [fd.crba(m, q) for m in models]
    g = [fd.generalized_gravity(m, q) for m in models]
    for k in range(1, len(models)):
        np.testing.assert_allclose(M[k], M[0], rtol=1e-13)
        np.testing.assert_allclose(g[k], g[0], rtol=1e-12, atol=1e-14)
    # and the 1.7 reading of an axis "0 1 0" in the joint frame is not the model-frame one
    wrong = load(sdf(WELD + link + '<joint name="j" type="revolute"><parent>base</parent><child>l</child>'
                     "<axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>", "1.4"))
    assert abs(fd.crba(wrong, q)[0, 0] - M[0][0, 0]) > 1e-3


def test_floating_static_and_world_joints():
    two = f'<link name="a">{inertial(3, 1, 1, 1)}</link><link name="b"><pose>0 0 -1 0 0 0</pose>{inertial(2, 1, 1, 1)}</link>'
    j = '<joint name="j" type="{}"><parent>a</parent><child>b</child><axis><xyz>1 0 0</xyz></axis></joint>'
    floating = load(sdf(two + j.format("revolute")))
    assert floating.joint_names == ("root_joint", "j") and floating.nq == 8 and floating.nv == 7
    assert floating.total_mass == pytest.approx(5.0)
    static = load(sdf("<static>true</static><pose>0 0 2 0 0 0</pose>" + two + j.format("fixed")))
    assert static.nq == 0 and static.nbodies == 0
    np.testing.assert_allclose(fd.frame_placement(static, np.zeros(0), "b").translation, [0, 0, 1])
    with pytest.raises(SDFError, match=r"<joint name='j'>: type='revolute' in a static model"):
        load(sdf("<static>true</static>" + two + j.format("revolute")))
    # two free links: each on its own free flyer, named after it
    several = load(sdf(two))
    assert several.joint_names == ("a/root_joint", "b/root_joint") and several.nv == 12


def test_default_inertial_is_sdformat_s_one_kilogram_and_warns():
    text = sdf(WELD + '<link name="l"/><joint name="j" type="continuous"><parent>base</parent><child>l</child>'
               "<axis><xyz>0 0 1</xyz></axis></joint>")
    with pytest.warns(PhysicalityWarning, match=r"moving links without <inertial> take SDFormat's default.*'l'"):
        model = fd.load_sdf(text)
    assert model.total_mass == 1.0
    np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[1.0]])
    with pytest.raises(SDFError, match="strict=True"):
        fd.load_sdf(text, strict=True)


def test_nested_models_are_scoped_and_posed_in_their_parent():
    inner = (f'<model name="arm"><pose>0 0 1 0 0 0</pose><link name="l">{inertial(2, 0.1, 0.1, 0.1, "<pose>0 0 -0.5 0 0 0</pose>")}'
             '</link><frame name="tip" attached_to="l"><pose>0 0 -1 0 0 0</pose></frame></model>')
    text = sdf(WELD + inner + '<joint name="j" type="revolute"><parent>base</parent><child>arm::l</child>'
               '<axis><xyz>1 0 0</xyz></axis></joint>'
               '<frame name="F" attached_to="arm::tip"/>')
    model = load(text)
    assert model.body_names == ("arm::l",) and "arm::tip" in [f.name for f in model.frames]
    np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[0.1 + 2 * 0.25]])
    np.testing.assert_allclose(fd.frame_placement(model, np.zeros(1), "arm::tip").translation, [0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(fd.frame_placement(model, np.zeros(1), "F").translation, [0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(fd.frame_placement(model, np.array([math.pi / 2]), "F").translation, [0, 1, 1],
                               atol=1e-14)


def test_nested_model_frame_as_joint_end_and_canonical_link():
    text = sdf(WELD + f'<model name="inner" canonical_link="b"><link name="a">{inertial(1, 1, 1, 1)}</link>'
               f'<link name="b"><pose>0 0 1 0 0 0</pose>{inertial(5, 1, 1, 1)}</link>'
               '<joint name="w" type="fixed"><parent>b</parent><child>a</child></joint></model>'
               '<joint name="j" type="prismatic"><parent>base</parent><child>inner</child>'
               '<axis><xyz>0 0 1</xyz></axis></joint>')
    model = load(text)
    # the child "inner" is the model's canonical link b (not its first link a), which carries a by the fixed joint
    assert model.body_names == ("inner::b",) and model.joint_names == ("j",)
    assert model.total_mass == 6.0
    assert model.frames[model.frame_id("inner::a")].body == 0
    np.testing.assert_allclose(fd.frame_placement(model, np.array([0.5]), "inner::a").translation, [0, 0, 0.5])


# --------------------------------------------------------------------------
# worlds, includes and load_model
# --------------------------------------------------------------------------


def test_world_with_several_models_picks_by_name():
    world = ('<sdf version="1.8"><world name="w"><physics name="p" type="ode"/>'
             f'<model name="one"><link name="a">{inertial(1, 1, 1, 1)}</link></model>'
             f'<model name="two"><link name="b">{inertial(2, 1, 1, 1)}</link></model></world></sdf>')
    with pytest.raises(SDFError, match=r"<string>: the document holds 2 models \('one', 'two'\); pick one with model="):
        load(world)
    assert load(world, model="two").total_mass == 2.0
    with pytest.raises(SDFError, match=r"model='three': no such model; the document holds 'one', 'two'"):
        load(world, model="three")


def _write_model(directory: Path, name: str, body: str, version: str = "1.9", config: bool = True) -> Path:
    d = directory / name
    d.mkdir(parents=True)
    (d / "m.sdf").write_text(f'<sdf version="{version}"><model name="{name}">{body}</model></sdf>')
    if config:
        (d / "model.config").write_text(f'<?xml version="1.0"?><model><name>{name}</name>'
                                        '<sdf version="1.5">old.sdf</sdf><sdf version="1.9">m.sdf</sdf></model>')
    return d


def test_include_by_model_uri_file_uri_and_relative_path(tmp_path, monkeypatch):
    lib = tmp_path / "lib"
    _write_model(lib, "pend", f'<link name="l"><pose>0 0 -1 0 0 0</pose>{inertial(2, 0.1, 0.1, 0.1)}</link>')
    main = ("<sdf version='1.9'><model name='top'>" + WELD +
            "<include><uri>{}</uri><name>p</name><pose>0 0 1 0 0 0</pose></include>"
            "<joint name='j' type='continuous'><parent>base</parent><child>p::l</child>"
            "<pose relative_to='__model__'/><axis><xyz>1 0 0</xyz></axis></joint></model></sdf>")
    # model:// through search_path, then through SDF_PATH
    model = load(main.format("model://pend"), search_path=[lib])
    assert model.body_names == ("p::l",)
    np.testing.assert_allclose(fd.crba(model, np.zeros(1)), [[0.1]], atol=1e-14)  # the com is on the axis: z = 0
    monkeypatch.setenv("SDF_PATH", str(lib))
    assert load(main.format("model://pend")).body_names == ("p::l",)
    monkeypatch.delenv("SDF_PATH")
    monkeypatch.setenv("GZ_SIM_RESOURCE_PATH", os.pathsep.join(["/nonexistent", str(lib)]))
    assert load(main.format("model://pend")).body_names == ("p::l",)
    monkeypatch.delenv("GZ_SIM_RESOURCE_PATH")
    # file:// of the file, a relative directory path from the including file
    assert load(main.format(f"file://{lib / 'pend' / 'm.sdf'}")).body_names == ("p::l",)
    top = tmp_path / "top.sdf"
    top.write_text(main.format("lib/pend"))
    assert load(top).body_names == ("p::l",)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)
        assert fd.load_model(str(top)).body_names == ("p::l",)


def test_include_at_world_level_and_errors(tmp_path):
    lib = tmp_path / "lib"
    _write_model(lib, "box", f'<link name="l">{inertial(2, 0.1, 0.1, 0.1)}</link>', config=False)
    (lib / "box" / "model.sdf").write_text((lib / "box" / "m.sdf").read_text())
    world = '<sdf version="1.9"><world name="w"><include><uri>model://box</uri></include></world></sdf>'
    assert load(world, search_path=[lib]).total_mass == 2.0
    with pytest.raises(SDFError, match=r"<string>: line 1: <include>: <uri>'model://nothere'</uri>: no model "
                                       r"'nothere' found in"):
        load(world.replace("box", "nothere"), search_path=[lib])
    with pytest.raises(SDFError, match=r"<uri>'http://example.com/m.sdf'</uri>: the scheme 'http' is not supported"):
        load(world.replace("model://box", "http://example.com/m.sdf"))


def test_include_cycle_and_depth_are_refused(tmp_path):
    a, b = tmp_path / "a.sdf", tmp_path / "b.sdf"
    link = f'<link name="l">{inertial(1, 1, 1, 1)}</link>'
    a.write_text(f'<sdf version="1.9"><model name="a">{link}<include><uri>b.sdf</uri></include></model></sdf>')
    b.write_text(f'<sdf version="1.9"><model name="b">{link}<include><uri>a.sdf</uri></include></model></sdf>')
    with pytest.raises(SDFError, match=r"b\.sdf: line 1: <include>: <uri>'a\.sdf'</uri>: include cycle"):
        load(a)
    # a chain deeper than MAX_INCLUDE_DEPTH
    n = MAX_INCLUDE_DEPTH + 2
    for k in range(n):
        inc = f"<include><uri>d{k + 1}.sdf</uri></include>" if k + 1 < n else ""
        (tmp_path / f"d{k}.sdf").write_text(f'<sdf version="1.9"><model name="d{k}">{link}{inc}</model></sdf>')
    with pytest.raises(SDFError, match=rf"<include>: includes nested deeper than {MAX_INCLUDE_DEPTH} files"):
        load(tmp_path / "d0.sdf")


def test_load_model_recognises_sdf_by_extension_and_root(tmp_path):
    text = sdf(f'<link name="a">{inertial(1, 1, 1, 1)}</link>')
    path = tmp_path / "robot.sdf"
    path.write_text(text)
    assert fd.load_model(path).nv == 6
    assert fd.load_model(text).nv == 6
    assert fd.load_robot(str(path)).nv == 6
    world = tmp_path / "x.world"
    world.write_text("not xml")  # the extension says SDF: the SDF reader's error
    with pytest.raises(SDFError, match=r"x\.world: line 1: malformed XML"):
        fd.load_model(world)
    from featherdyn.mjcf import model_format

    assert model_format(text) == "sdf" and model_format(str(path)) == "sdf"
    assert issubclass(SDFError, ModelError) and fd.SDFError is SDFError
    # the other loaders point an SDF document to this one
    with pytest.raises(fd.URDFError, match=r"got <sdf> \(an SDFormat document: use featherdyn.load_sdf"):
        fd.load_urdf(text)
    with pytest.raises(fd.MJCFError, match=r"got <sdf> \(an SDFormat document: use featherdyn.load_sdf"):
        fd.load_mjcf(text)


# --------------------------------------------------------------------------
# ignored elements, strictness
# --------------------------------------------------------------------------


def test_ignored_elements_are_one_warning_and_strict_refuses_them():
    text = sdf(WELD + f'<link name="l">{inertial(1, 1, 1, 1)}<visual name="v"/><collision name="c"/>'
               '<visual name="v2"/><sensor name="s" type="imu"/></link><plugin name="p" filename="x"/>'
               '<joint name="j" type="revolute"><parent>base</parent><child>l</child><axis><xyz>1 0 0</xyz>'
               "<dynamics><damping>0.5</damping><friction>0.1</friction><spring_stiffness>3</spring_stiffness>"
               "</dynamics></axis><frobnicate/></joint>")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fd.load_sdf(text)
    messages = [str(w.message) for w in caught if issubclass(w.category, PhysicalityWarning)]
    assert len(messages) == 1
    msg = messages[0]
    assert msg.startswith("<string>: ignored SDF elements without rigid-tree meaning: ")
    for part in ("<link>/<visual> ×2", "<link>/<collision>", "<link>/<sensor>", "<model>/<plugin>",
                 "<dynamics>/<spring_stiffness>", "<joint>/<frobnicate> (unknown to SDFormat)"):
        assert part in msg, part
    with pytest.raises(SDFError, match=r"ignored SDF elements .* \(strict=True refuses them\)"):
        fd.load_sdf(text, strict=True)


# --------------------------------------------------------------------------
# errors: each names the source, the element and the attribute
# --------------------------------------------------------------------------

J = '<joint name="j" type="revolute"><parent>base</parent><child>l</child><axis><xyz>1 0 0</xyz></axis></joint>'
L = f'<link name="l">{inertial(1, 1, 1, 1)}</link>'


@pytest.mark.parametrize(("text", "pattern"), [
    ("<sdf version='1.9'><model name='m'><link name='a'></model></sdf>", r"<string>: line 1: malformed XML"),
    ('<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY e "x">]><sdf version="1.9"/>',
     r"<string>: line \d+: .*(DTD|Entit).* not allowed in a SDF"),
    ("<robot name='r'/>", r"expected the root element <sdf>, got <robot> \(a URDF"),
    ("<sdf><model name='m'/></sdf>", r"<sdf>: missing the attribute 'version'"),
    ("<sdf version='2.0'><model name='m'/></sdf>", r"<sdf> version='2.0': expected an SDFormat version"),
    ("<sdf version='1.9'></sdf>", r"<string>: the document holds no <model>"),
    (sdf(WELD + '<link name="l"><inertial><mass>1</mass><inertia><ixy>0</ixy><iyy>1</iyy><izz>1</izz></inertia>'
         "</inertial></link>" + J),
     r"<string>: line 1: <link name='l'>: <inertia> needs <ixx>"),
    (sdf(WELD + '<link name="l"><inertial><mass>-1</mass></inertial></link>' + J),
     r"<link name='l'>: <mass>: expected a mass >= 0, got -1"),
    (sdf(WELD + '<link name="l"><inertial><mass>abc</mass></inertial></link>' + J),
     r"<link name='l'>: <mass>'abc'</mass>: 'abc' is not a decimal number"),
    (sdf(WELD + '<link name="l"><inertial><mass>1e999</mass></inertial></link>' + J),
     r"<link name='l'>: <mass>'1e999'</mass>: '1e999' is out of range"),
    (sdf(WELD + L + J.replace("revolute", "hinge")),
     r"<joint name='j'>: type='hinge': unknown joint type; expected one of revolute, continuous"),
    (sdf(WELD + L + J.replace("revolute", "screw")), r"<joint name='j'>: type='screw' is not supported"),
    (sdf(WELD + L + J.replace("<child>l</child>", "<child>nobody</child>")),
     r"<joint name='j'>: <child> 'nobody': no link, joint, frame or model of that name in <model name='m'>"),
    (sdf(WELD + L + J.replace("<child>l</child>", "")), r"<joint name='j'>: needs a non-empty <child> element"),
    (sdf(WELD + '<link name="l"><pose>1 2 3</pose></link>' + J),
     r"<string>: line 1: <link name='l'>: <pose>'1 2 3'</pose>: expected 6 numbers, got 3"),
    (sdf(WELD + '<link name="l"><pose>1 2 3 x 0 0</pose></link>' + J),
     r"<link name='l'>: <pose>'1 2 3 x 0 0'</pose>: 'x' is not a decimal number"),
    (sdf(WELD + '<link name="l"><pose rotation_format="quat_xyzw">0 0 0 0 0 0 0</pose></link>' + J),
     r"<link name='l'>: <pose> quaternion \[0.0, 0.0, 0.0, 0.0\]: expected a non-zero quaternion"),
    (sdf(WELD + '<link name="l"><pose relative_to="nowhere"/></link>' + J),
     r"<link name='l'>: relative_to 'nowhere': no link, joint, frame or model of that name"),
    (sdf(WELD + '<frame name="A"><pose relative_to="B"/></frame><frame name="B"><pose relative_to="A"/></frame>' + L + J),
     r"<frame name='[AB]'>: the poses' relative_to form a cycle: '[AB]' -> '[AB]' -> '[AB]'"),
    (sdf(WELD + '<frame name="A" attached_to="B"/><frame name="B" attached_to="A"/>' + L + J
         + '<frame name="C" attached_to="A"/>'),
     r"attached_to forms a cycle|relative_to form a cycle"),
    (sdf(WELD + L + '<link name="k"/>' + J + J.replace('name="j"', 'name="j2"').replace("<parent>base", "<parent>k")),
     r"<joint name='j2'>: link 'l' has two parents \(joints 'j' and 'j2'\): a kinematic loop"),
    (sdf(L + '<link name="k"/>' + J.replace("base", "k")
         + J.replace('name="j"', 'name="j2"').replace("<parent>base</parent><child>l", "<parent>l</parent><child>k")),
     r"the joints form a cycle through this link"),
    (sdf(WELD + L + L), r"<link name='l'>: the name 'l' is used twice in <model name='m'>"),
    (sdf(WELD + L + J.replace("1 0 0", "0 0 0")), r"<joint name='j'>: <axis><xyz> \[0.0, 0.0, 0.0\]: expected a "
                                                 r"direction, got a zero-length axis"),
    (sdf(WELD + '<link name="l"><pose>1e99 0 0 0 0 0</pose></link>' + J),
     r"<link name='l'>: <pose> position .*MAX_LENGTH"),
    (sdf(WELD + L + J.replace("<axis><xyz>1 0 0</xyz></axis>", "")), r"needs an <axis> element"),
    (sdf(WELD + L + J + '<include><uri>missing.sdf</uri></include>'),
     r"<include>: <uri>'missing.sdf'</uri>: no such file or directory"),
    (sdf(WELD + '<link name="world"/>' + L + J), r"<link>: name='world': the name is reserved by SDFormat"),
    (sdf(WELD + '<link name="l"><inertial auto="true"/></link>' + J), r"<inertial auto=\"true\">.*not supported"),
])
def test_every_failure_is_an_sdf_error_naming_the_place(text, pattern):
    if "<axis>" not in text and "needs an <axis>" in pattern:
        text = text.replace('version="1.9"', 'version="1.6"')
    with pytest.raises(SDFError) as info:
        load(text)
    assert re.search(pattern, str(info.value)), str(info.value)
    assert str(info.value).startswith("<string>")


def test_a_file_s_errors_name_the_file(tmp_path):
    path = tmp_path / "bad.sdf"
    path.write_text(sdf(WELD + '<link name="l"><pose>0 0</pose></link>' + J))
    with pytest.raises(SDFError, match=rf"^{re.escape(str(path))}: line 1: <link name='l'>: <pose>'0 0'</pose>"):
        load(path)
    with pytest.raises(SDFError, match=r"cannot read the SDF file"):
        load(tmp_path / "absent.sdf")
    with pytest.raises(SDFError, match=r"load_sdf: expected a path, an XML string or bytes, got int"):
        load(3)


def test_mimic_is_recorded_as_the_urdf_loader_records_it():
    """SDFormat 1.11: follower = multiplier (leader − reference) + offset → Mimic(offset − multiplier · reference)."""
    text = sdf(WELD + L + '<link name="k">' + inertial(1, 1, 1, 1) + "</link>" + J
               + '<joint name="f" type="revolute"><parent>l</parent><child>k</child><axis><xyz>0 1 0</xyz>'
               '<mimic joint="j"><multiplier>2</multiplier><offset>0.5</offset><reference>0.1</reference></mimic>'
               "</axis></joint>", "1.11")
    model = load(text)
    assert model.mimics == (fd.Mimic("f", "j", 2.0, 0.5 - 2 * 0.1),)
    with pytest.raises(SDFError, match=r"<joint name='f'>: <mimic> joint 'nobody': no link, joint"):
        load(text.replace('joint="j"', 'joint="nobody"'))
    with pytest.raises(SDFError, match=r"<joint name='f'>: <mimic>: the axis mimics itself"):
        load(text.replace('joint="j"', 'joint="f"'))
