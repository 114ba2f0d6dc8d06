"""Unit tests of featherdyn.urdf: a corpus of broken, hostile and tricky URDF documents.

Each document is generated here (small strings, written to ``tmp_path`` where a
file is needed) and each test asserts the exact outcome: the exception class
and that its message names the source, the element and the link or joint; or
the warning class; or the loaded numbers, against hand computations.
"""

from __future__ import annotations

import builtins
import codecs
import errno
import io
import math
import os
import re
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import ModelError, PhysicalityWarning, URDFError

INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>'
LIMIT = '<limit lower="-1" upper="1" effort="10" velocity="2"/>'


def link(name: str, inertial: str = INERTIAL) -> str:
    return f'<link name="{name}">{inertial}</link>'


def joint(name: str, parent: str, child: str, jtype: str = "revolute", body: str = LIMIT) -> str:
    return f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/><child link="{child}"/>{body}</joint>'


def robot(*parts: str, name: str = "r") -> str:
    return f'<robot name="{name}">\n' + "\n".join(parts) + "\n</robot>"


def arm(**joint_body: str) -> str:
    """base -> (j1) -> l1 -> (j2) -> l2, both revolute; override a joint's inner XML by name."""
    return robot(
        link("base"),
        link("l1"),
        link("l2"),
        joint("j1", "base", "l1", body=joint_body.get("j1", LIMIT)),
        joint("j2", "l1", "l2", body=joint_body.get("j2", LIMIT)),
    )


def load_quietly(source, **kw) -> fd.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)
        return fd.load_urdf(source, **kw)


@pytest.fixture
def no_warnings():
    """Fail the test on any warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


# ---------------------------------------------------------------------------
# sources and encodings
# ---------------------------------------------------------------------------


def test_path_str_pathlike_string_and_bytes_give_the_same_model(tmp_path: Path, no_warnings) -> None:
    xml = arm()
    f = tmp_path / "arm.urdf"
    f.write_text(xml, encoding="utf-8")
    models = [fd.load_urdf(f), fd.load_urdf(str(f)), fd.load_urdf(xml), fd.load_urdf(xml.encode()), fd.load_urdf("  \n" + xml)]
    for m in models:
        assert m.body_names == ("l1", "l2") and m.name == "r"
    assert models[0].source == str(f) and models[1].source == str(f)
    assert models[2].source is None and models[3].source is None


@pytest.mark.parametrize(
    "encode",
    [
        pytest.param(lambda s: s.replace('encoding="utf-8"', 'encoding="UTF-16"').encode("utf-16"), id="utf16-bom"),
        pytest.param(lambda s: codecs.BOM_UTF16_BE + s.replace('encoding="utf-8"', 'encoding="UTF-16"').encode("utf-16-be"), id="utf16be-bom"),
        pytest.param(lambda s: codecs.BOM_UTF8 + s.encode("utf-8"), id="utf8-bom"),
        pytest.param(lambda s: s.encode("utf-32"), id="utf32-bom"),
        pytest.param(lambda s: s.replace('encoding="utf-8"', 'encoding="ISO-8859-1"').encode("latin-1"), id="declared-latin1"),
    ],
)
def test_encodings(tmp_path: Path, encode, no_warnings) -> None:
    xml = '<?xml version="1.0" encoding="utf-8"?>\n' + robot(link("bäse"), link("l1"), joint("jé", "bäse", "l1"), name="rôbot")
    data = encode(xml)
    for source in (data, tmp_path / "x.urdf"):
        (tmp_path / "x.urdf").write_bytes(data)
        m = fd.load_urdf(source)
        assert m.name == "rôbot" and m.joint_names == ("jé",) and m.frames[0].name == "bäse"


def test_str_with_bom_and_unicode_names(no_warnings) -> None:
    xml = "\ufeff" + robot(link("基座"), link("βραχίονας"), joint("關節", "基座", "βραχίονας"), name="ロボット")
    m = fd.load_urdf(xml)
    assert m.name == "ロボット" and m.body_names == ("βραχίονας",) and m.joint_names == ("關節",)
    assert m.frames[m.frame_id("基座")].body == -1


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (robot(link("é")).encode("latin-1"), r"<bytes>: line 2: bytes are not valid utf-8"),
        (b"\x80\x81\x82\xff garbage", r"<bytes>: line 1: bytes are not valid utf-8"),
        (b'<?xml version="1.0" encoding="klingon"?><robot/>', r"<bytes>: unknown encoding 'klingon'"),
        (b'<?xml version="1.0" encoding="UTF-16"?><robot/>', r"<bytes>: .*says 'UTF-16' but the bytes are not UTF-16"),
        (b'<?xml version="1.0" encoding="zlib"?><robot/>', r"<bytes>: .*'zlib', which is not a text encoding"),
    ],
)
def test_undecodable_bytes(data: bytes, match: str) -> None:
    with pytest.raises(URDFError, match=match):
        fd.load_urdf(data)


def test_file_errors_name_the_file(tmp_path: Path) -> None:
    missing = tmp_path / "missing.urdf"
    with pytest.raises(URDFError, match=r"missing\.urdf: cannot read the URDF file"):
        fd.load_urdf(missing)
    with pytest.raises(URDFError, match=r"cannot read the URDF file"):
        fd.load_urdf(tmp_path)  # a directory
    bad = tmp_path / "bad.urdf"
    bad.write_text(robot(link("a"), link("a")))
    with pytest.raises(URDFError, match=rf"{bad.name}: line 3: <link name='a'>: duplicate link name \(first defined on line 2\)"):
        fd.load_urdf(bad)
    with pytest.raises(URDFError, match=r"expected a path, an XML string or bytes, got int"):
        fd.load_urdf(123)  # type: ignore[arg-type]


def test_model_name_defaults(tmp_path: Path, no_warnings) -> None:
    xml = "<robot>" + link("a") + "</robot>"
    assert fd.load_urdf(xml).name == "robot"
    f = tmp_path / "my_bot.urdf"
    f.write_text(xml)
    assert fd.load_urdf(f).name == "my_bot"


# ---------------------------------------------------------------------------
# hostile XML
# ---------------------------------------------------------------------------

BILLION_LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE robot [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<robot name="&lol9;"><link name="a"/></robot>"""

HOSTILE = {
    "billion-laughs": (BILLION_LAUGHS, r"<string>: line 2: DTD declarations are not allowed"),
    "external-entity": (
        '<?xml version="1.0"?><!DOCTYPE robot [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>'
        '<robot name="r"><link name="&xxe;"/></robot>',
        r"DTD declarations are not allowed",
    ),
    "external-dtd": (
        '<?xml version="1.0"?><!DOCTYPE robot SYSTEM "file:///etc/passwd"><robot name="r"><link name="a"/></robot>',
        r"DTD declarations are not allowed",
    ),
    "plain-dtd": ('<!DOCTYPE robot><robot name="r"><link name="a"/></robot>', r"DTD declarations are not allowed"),
    "undeclared-entity": ('<robot name="r"><link name="&xxe;"/></robot>', r"<string>: line 1: malformed XML: undefined entity"),
    "xinclude": (
        '<robot name="r" xmlns:xi="http://www.w3.org/2001/XInclude">\n<link name="a"/>\n'
        '<xi:include href="/etc/passwd" parse="text"/></robot>',
        r"<string>: line 3: XInclude .* is not allowed",
    ),
    "deep-nesting": ('<robot name="r">' + "<a>" * 100_000 + "</a>" * 100_000 + "</robot>", r"nested deeper than 1000 levels"),
    "malformed": (robot(link("a"), '<link name="b">'), r"<string>: line 4: malformed XML"),
    "not-xml": ("<", r"<string>: line 1: malformed XML"),
    "nul-character": ('<robot name="r\x00"><link name="a"/></robot>', r"<string>: line 1: malformed XML"),
    "lone-surrogate": ('<robot name="\ud800"><link name="a"/></robot>',
                       r"<string>: line 1: the character '\\ud800' \(position 13\) is a lone surrogate"),
}


@pytest.mark.parametrize(("xml", "match"), list(HOSTILE.values()), ids=list(HOSTILE))
def test_hostile_xml_is_refused(xml: str, match: str) -> None:
    start = time.monotonic()
    with pytest.raises(URDFError, match=match) as info:
        fd.load_urdf(xml)
    assert "root:" not in str(info.value)  # /etc/passwd never read
    assert time.monotonic() - start < 10  # hang guard, not a speed claim


def test_nothing_is_opened_for_a_string(monkeypatch: pytest.MonkeyPatch, no_warnings) -> None:
    """Meshes, XInclude and entities are never read: loading a string touches no file."""

    def refuse(*args, **kwargs):
        raise AssertionError(f"tried to open {args[:1]}")

    xml = robot(
        '<link name="a"><visual><geometry><mesh filename="/etc/passwd"/></geometry></visual>'
        '<collision><geometry><mesh filename="package://nowhere/x.stl"/></geometry></collision>' + INERTIAL + "</link>",
        link("b"),
        joint("j", "a", "b"),
    )
    monkeypatch.setattr(builtins, "open", refuse)
    monkeypatch.setattr(io, "open", refuse)
    assert fd.load_urdf(xml).nbodies == 1


def test_moderate_nesting_inside_extensions_is_fine(no_warnings) -> None:
    gazebo = "<gazebo>" + "<x>" * 200 + "text" + "</x>" * 200 + "</gazebo>"
    xml = robot(link("a"), link("b"), joint("j", "a", "b"), gazebo, '<transmission name="t"><type>x</type></transmission>',
                '<material name="blue"><color rgba="0 0 1 1"/></material>')
    assert fd.load_urdf(xml).nbodies == 1


def test_5000_link_chain_loads() -> None:
    n = 5000
    parts = [link(f"l{i}") for i in range(n)]
    parts += [joint(f"j{i}", f"l{i - 1}", f"l{i}", "continuous", '<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>') for i in range(1, n)]
    xml = robot(*parts)
    start = time.monotonic()
    m = fd.load_urdf(xml)
    assert time.monotonic() - start < 10  # hang guard only
    assert m.nbodies == n - 1 and m.nq == n - 1
    assert m.parents == tuple(range(-1, n - 2))
    assert m.body_names[-1] == f"l{n - 1}"
    mf = fd.load_urdf(xml, floating_base=True)
    assert mf.nbodies == n and mf.nq == n - 1 + 7


# ---------------------------------------------------------------------------
# structural errors
# ---------------------------------------------------------------------------

STRUCTURE = {
    "wrong-root": ('<model name="m"><link name="a"/></model>', r"<string>: line 1: expected the root element <robot>, got <model>"),
    "no-links": (robot(), r"<string>: <robot> has no <link> elements$"),
    "xacro": (
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m"/></robot>',
        r"no <link> elements \(an unexpanded xacro file",
    ),
    "link-without-name": (robot("<link/>"), r"<string>: line 2: <link>: missing or empty 'name'"),
    "link-with-empty-name": (robot('<link name=" "/>'), r"<link>: missing or empty 'name'"),
    "duplicate-link": (robot(link("a"), link("a")), r"line 3: <link name='a'>: duplicate link name"),
    "joint-without-name": (robot(link("a"), link("b"), '<joint type="fixed"><parent link="a"/><child link="b"/></joint>'),
                           r"line 4: <joint>: missing or empty 'name'"),
    "duplicate-joint": (robot(link("a"), link("b"), link("c"), joint("j", "a", "b"), joint("j", "b", "c")),
                        r"line 6: <joint name='j'>: duplicate joint name \(first defined on line 5\)"),
    "missing-type": (robot(link("a"), link("b"), '<joint name="j"><parent link="a"/><child link="b"/></joint>'),
                     r"<joint name='j'>: missing 'type' attribute"),
    "unknown-type": (robot(link("a"), link("b"), joint("j", "a", "b", "spherical")),
                     r"line 4: <joint name='j'>: unknown joint type 'spherical'"),
    "missing-parent-element": (robot(link("a"), link("b"), '<joint name="j" type="fixed"><child link="b"/></joint>'),
                               r"<joint name='j'>: missing <parent link=...> element"),
    "missing-child-element": (robot(link("a"), link("b"), '<joint name="j" type="fixed"><parent link="a"/></joint>'),
                              r"<joint name='j'>: missing <child link=...> element"),
    "parent-without-link": (robot(link("a"), link("b"), '<joint name="j" type="fixed"><parent/><child link="b"/></joint>'),
                            r"<joint name='j'>: <parent> needs a non-empty 'link' attribute"),
    "unknown-parent": (robot(link("a"), link("b"), joint("j", "zz", "b")), r"line 4: <joint name='j'>: unknown parent link 'zz'"),
    "unknown-child": (robot(link("a"), link("b"), joint("j", "a", "zz")), r"line 4: <joint name='j'>: unknown child link 'zz'"),
    "two-parents": (robot(link("a"), link("b"), link("c"), joint("j1", "a", "c"), joint("j2", "b", "c")),
                    r"<joint name='j2'>: link 'c' has two parents \(joints 'j1' and 'j2'\)"),
    "self-loop": (robot(link("a"), link("b"), joint("j", "a", "b"), joint("k", "b", "b")),
                  r"<joint name='k'>: parent and child are the same link 'b' \(a cycle\)"),
    "cycle-without-root": (robot(link("a"), link("b"), joint("j", "a", "b"), joint("k", "b", "a")), r"the joints form a cycle"),
    "detached-cycle": (robot(link("r"), link("a"), link("b"), joint("j", "a", "b"), joint("k", "b", "a")),
                       r"the joints form a cycle through links '(a|b)' -> '(a|b)' -> '(a|b)'"),
    "two-roots": (robot(link("a"), link("b")), r"more than one root link \(2: 'a', 'b'\): the links are not all connected"),
    "unreachable": (robot(link("a"), link("b"), link("c"), link("d"), joint("j", "a", "b"), joint("k", "c", "d")),
                    r"more than one root link \(2: 'a', 'c'\)"),
    "revolute-without-limit": (robot(link("a"), link("b"), joint("j", "a", "b", body="")),
                               r"line 4: <joint name='j'>: a revolute joint needs a <limit"),
    "prismatic-without-limit": (robot(link("a"), link("b"), joint("j", "a", "b", "prismatic", body='<axis xyz="0 0 1"/>')),
                                r"<joint name='j'>: a prismatic joint needs a <limit"),
    "negative-mass": (robot(link("a", '<inertial><mass value="-1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
                      r"<link name='a'>: <mass> value='-1': expected a mass >= 0, got a negative mass -1$"),
    "inertial-without-mass": (robot(link("a", '<inertial><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
                              r"<link name='a'>: <inertial> needs a <mass"),
    "inertial-without-inertia": (robot(link("a", '<inertial><mass value="1"/></inertial>')),
                                 r"<link name='a'>: <inertial> needs an <inertia"),
    "inertia-missing-attribute": (robot(link("a", '<inertial><mass value="1"/><inertia ixx="1" ixy="0" iyy="1" iyz="0" izz="1"/></inertial>')),
                                  r"<link name='a'>: <inertia> needs the attribute 'ixz'"),
    "mass-without-value": (robot(link("a", '<inertial><mass/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
                           r"<link name='a'>: <mass> needs the attribute 'value'"),
    "zero-axis": (robot(link("a"), link("b"), joint("j", "a", "b", body='<axis xyz="0 0 0"/>' + LIMIT)),
                  r"<joint name='j'>: <axis> xyz=\[0.0, 0.0, 0.0\]: expected a direction, got a zero-length joint axis$"),
    "self-mimic": (arm(j2=LIMIT + '<mimic joint="j2"/>'), r"<joint name='j2'>: the joint mimics itself"),
    "mimic-cycle": (arm(j1=LIMIT + '<mimic joint="j2"/>', j2=LIMIT + '<mimic joint="j1"/>'),
                    r"<joint name='j1'>: mimic cycle 'j1' -> 'j2' -> 'j1'"),
    "mimic-without-joint": (arm(j2=LIMIT + "<mimic/>"), r"<joint name='j2'>: <mimic> needs a non-empty 'joint'"),
}


@pytest.mark.parametrize(("xml", "match"), list(STRUCTURE.values()), ids=list(STRUCTURE))
def test_structural_errors(xml: str, match: str) -> None:
    with pytest.raises(URDFError, match=match) as info:
        load_quietly(xml)
    assert str(info.value).startswith("<string>: ")
    assert isinstance(info.value, ModelError) and isinstance(info.value, ValueError)


def test_free_flyer_name_never_clashes_with_the_urdf(pin, no_warnings) -> None:
    """A URDF joint called root_joint loads with floating_base=True: the free flyer takes the next free name."""
    xml = robot(link("a"), link("b"), joint("root_joint", "a", "b"))
    assert fd.load_urdf(xml).joint_names == ("root_joint",)
    m = fd.load_urdf(xml, floating_base=True)
    assert m.joint_names == ("root_joint_1", "root_joint") and m.floating_base
    assert (m.frames[0].name, m.frames[0].kind) == ("root_joint_1", "joint")
    assert m.frames[m.frame_id("root_joint", "joint")].body == 1
    # a link of the next name is skipped too, so every frame name stays unambiguous
    xml = robot(link("a"), link("root_joint_1"), joint("root_joint", "a", "root_joint_1"))
    assert fd.load_urdf(xml, floating_base=True).joint_names == ("root_joint_2", "root_joint")
    # the verification bridge maps joints by name: the renamed free flyer mirrors into Pinocchio
    from featherdyn.verify.bridge import pinocchio_model_from

    assert list(pinocchio_model_from(m).names)[1:] == ["root_joint_1", "root_joint"]


BAD_NUMBERS = ["1 2", "1 2 3 4", "", "   ", "nan 0 0", "NaN 0 0", "inf 0 0", "-inf 0 0", "1e999 0 0", "0x10 0 0",
               "1,2,3", "1_0 0 0", "\u0663 0 0", "1e 0 0", "one 0 0", "1.2.3 0 0", "+-1 0 0"]


@pytest.mark.parametrize("value", BAD_NUMBERS, ids=[repr(v) for v in BAD_NUMBERS])
def test_bad_numbers(value: str) -> None:
    xml = robot(link("a"), link("b"), joint("j", "a", "b", body=f'<origin xyz="{value}"/>' + LIMIT))
    with pytest.raises(URDFError, match=r"<string>: line 4: <joint name='j'>: <origin> xyz=") as info:
        fd.load_urdf(xml)
    assert any(w in str(info.value) for w in ("expected 3 numbers", "is not a decimal number", "not finite"))


@pytest.mark.parametrize(
    ("where", "xml", "match"),
    [
        ("mass", robot(link("a", '<inertial><mass value="nan"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
         r"<link name='a'>: <mass> value='nan'"),
        ("inertia", robot(link("a", '<inertial><mass value="1"/><inertia ixx="1e999" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
         r"<link name='a'>: <inertia> ixx='1e999': .*not finite"),
        ("rpy", robot(link("a", '<inertial><origin rpy="0 0"/><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>')),
         r"<link name='a'>: <origin> rpy='0 0': expected 3 numbers, got 2"),
        ("limit", arm(j1='<limit lower="abc" upper="1" effort="1" velocity="1"/>'), r"<joint name='j1'>: <limit> lower='abc'"),
        ("axis", arm(j1='<axis xyz="0 0 inf"/>' + LIMIT), r"<joint name='j1'>: <axis> xyz='0 0 inf'"),
        ("mimic", arm(j2=LIMIT + '<mimic joint="j1" multiplier="x"/>'), r"<joint name='j2'>: <mimic> multiplier='x'"),
    ],
)
def test_bad_numbers_everywhere(where: str, xml: str, match: str) -> None:
    with pytest.raises(URDFError, match=match):
        fd.load_urdf(xml)


# ---------------------------------------------------------------------------
# physicality warnings (errors with strict=True)
# ---------------------------------------------------------------------------


def _inertial(mass: float, ixx: float, iyy: float, izz: float, ixy: float = 0.0) -> str:
    return (f'<inertial><mass value="{mass}"/><inertia ixx="{ixx}" ixy="{ixy}" ixz="0" iyy="{iyy}" iyz="0" '
            f'izz="{izz}"/></inertial>')


WARNINGS = {
    "indefinite": (robot(link("a"), link("b", _inertial(1, 1, 1, -0.5)), joint("j", "a", "b")),
                   r"line 3: <link name='b'>: inertia is not positive semi-definite \(principal moments -0.5, 1, 1\)"),
    "indefinite-offdiagonal": (robot(link("a"), link("b", _inertial(1, 1, 1, 1, ixy=2)), joint("j", "a", "b")),
                               r"<link name='b'>: inertia is not positive semi-definite"),
    "triangle": (robot(link("a"), link("b", _inertial(1, 0.1, 0.1, 1)), joint("j", "a", "b")),
                 r"<link name='b'>: principal moments violate the triangle inequality"),
    "zero-mass": (robot(link("a"), link("b", _inertial(0, 0.1, 0.1, 0.1)), link("c"), joint("j", "a", "b"), joint("k", "b", "c")),
                  r"<link name='b'>: zero mass but non-zero rotational inertia"),
    "lower-above-upper": (arm(j2='<limit lower="1" upper="-1" effort="1" velocity="1"/>'), r"<string>: .*'j2'.*lower limit.*upper"),
    "mimic-of-unknown-joint": (arm(j2=LIMIT + '<mimic joint="nope"/>'), r"<joint name='j2'>: <mimic> of unknown joint 'nope'; ignored"),
    "mimic-of-fixed-joint": (robot(link("a"), link("b"), link("c"), joint("f", "a", "b", "fixed", ""),
                                   joint("j", "b", "c", body=LIMIT + '<mimic joint="f"/>')),
                             r"<joint name='j'>: <mimic> of the fixed joint 'f'; ignored"),
    "massless-subtree": (robot(link("a"), link("b", ""), joint("j", "a", "b")), r"<string>: joint 'j' .*subtree has no mass"),
    "non-unit-axis": (arm(j1='<axis xyz="0 0 2"/>' + LIMIT), r"line \d+: <joint name='j1'>: axis \[0.0, 0.0, 2.0\] has length 2; normalised"),
}


@pytest.mark.parametrize(("xml", "match"), list(WARNINGS.values()), ids=list(WARNINGS))
def test_physicality_warnings_and_strict(xml: str, match: str) -> None:
    with pytest.warns(PhysicalityWarning, match=match):
        model = fd.load_urdf(xml)
    assert isinstance(model, fd.Model)
    with pytest.raises(URDFError, match=match + r".*\(strict=True\)"):
        fd.load_urdf(xml, strict=True)


@pytest.mark.parametrize(
    "inertial",
    [
        _inertial(1, 1, 1, 2 + 1e-10),  # triangle inequality off by round-off
        _inertial(1, 0.5, 0.5, 1, ixy=-0.5000000005),  # a rod along (1, 1, 0) with an eigenvalue of −5e-10
        _inertial(1, 0, 0, 0),  # a point mass
        _inertial(1, 0, 1, 1),  # a thin rod
        "",  # no inertial, but a child with mass
    ],
)
def test_no_warning_within_round_off(inertial: str, no_warnings) -> None:
    xml = robot(link("a"), link("b", inertial), link("c"), joint("j", "a", "b"), joint("k", "b", "c"))
    fd.load_urdf(xml, strict=True)


# ---------------------------------------------------------------------------
# tricky legal documents
# ---------------------------------------------------------------------------


def test_inertial_frame_rotation_and_lumping_by_hand(ref, no_warnings) -> None:
    """The URDF tensor is in the <inertial><origin> frame; a fixed child is lumped with the parallel-axis theorem."""
    xml = robot(
        link("base", ""),
        '<link name="arm"><inertial><origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/><mass value="2"/>'
        '<inertia ixx="1" ixy="0" ixz="0" iyy="2" iyz="0" izz="3"/></inertial></link>',
        '<link name="tool"><inertial><origin xyz="0 0.5 0"/><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>',
        joint("j", "base", "arm", body='<axis xyz="0 0 1"/>' + LIMIT),
        joint("mount", "arm", "tool", "fixed", '<origin xyz="0 0 1" rpy="1.5707963267948966 0 0"/>'),
    )
    m = fd.load_urdf(xml)
    # arm: Rz(90°) diag(1, 2, 3) Rz(90°)ᵀ = diag(2, 1, 3), com (0.1, 0.2, 0.3)
    # tool in arm's frame: Rx(90°) maps y to z, so com = (0, 0, 0.5) + (0, 0, 1), I_c = diag(0.1, 0.3, 0.2)
    expected = ref.inertia(2, [0.1, 0.2, 0.3], np.diag([2.0, 1.0, 3.0])) + ref.inertia(1, [0, 0, 1.5], np.diag([0.1, 0.3, 0.2]))
    I = m.inertias[0]
    assert np.allclose(I.matrix(), expected, rtol=0, atol=1e-12)
    assert float(I.mass) == 3.0
    assert np.allclose(I.com, [0.2 / 3, 0.4 / 3, 0.7], atol=1e-15)
    # the merged link and the fixed joint are frames on body 0 at the mount
    for name, kind in (("tool", "link"), ("mount", "fixed_joint")):
        f = m.frames[m.frame_id(name)]
        assert (f.body, f.kind) == (0, kind)
        assert np.allclose(f.placement.rotation, [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-15)
        assert np.allclose(f.placement.translation, [0, 0, 1])


def test_fixed_base_drops_the_root_and_its_fixed_children(no_warnings) -> None:
    xml = robot(link("base"), link("plate"), link("arm"),
                joint("weld", "base", "plate", "fixed", '<origin xyz="0 0 2" rpy="0 0 1.5707963267948966"/>'),
                joint("j", "plate", "arm", body='<origin xyz="1 0 0"/>' + LIMIT))
    m = fd.load_urdf(xml)
    assert m.total_mass == 1.0 and m.parents == (-1,)
    X = m.joint_placements[0]  # plate's pose in the world composed with the joint origin
    assert np.allclose(X.translation, [0, 1, 2]) and np.allclose(X.rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    kinds = [(f.name, f.body, f.kind) for f in m.frames]
    assert kinds == [("base", -1, "link"), ("weld", -1, "fixed_joint"), ("plate", -1, "link"),
                     ("j", 0, "joint"), ("arm", 0, "body")]
    mf = fd.load_urdf(xml, floating_base=True)
    assert mf.total_mass == 3.0 and mf.joint_names == ("root_joint", "j") and mf.body_names == ("base", "arm")
    assert [(f.name, f.body, f.kind) for f in mf.frames][:3] == [("root_joint", 0, "joint"), ("base", 0, "body"),
                                                               ("weld", 0, "fixed_joint")]
    assert isinstance(mf.joints[0], fd.FreeFlyerJoint) and mf.floating_base


def test_single_link(pin, no_warnings) -> None:
    xml = robot(link("only", _inertial(2, 0.1, 0.1, 0.1)))
    m = fd.load_urdf(xml)
    assert (m.nbodies, m.nq, m.nv, m.total_mass) == (0, 0, 0, 0.0)
    assert [(f.name, f.body, f.kind) for f in m.frames] == [("only", -1, "link")]
    mf = fd.load_urdf(xml, floating_base=True)
    assert (mf.nbodies, mf.nq, mf.nv, mf.total_mass) == (1, 7, 6, 2.0)
    assert mf.joint_names == ("root_joint",) and mf.body_names == ("only",)
    assert pin.buildModelFromXML(xml).njoints - 1 == m.nbodies
    assert pin.buildModelFromXML(xml, pin.JointModelFreeFlyer()).nq == mf.nq


def test_root_link_named_world_is_an_ordinary_root(pin, no_warnings) -> None:
    """Pinocchio (4.1) gives a root link called "world" no special meaning: so does featherdyn."""
    xml = robot(link("world"), link("base"), link("arm"), joint("world_joint", "world", "base", "fixed", ""),
                joint("j", "base", "arm"))
    for floating in (False, True):
        m = fd.load_urdf(xml, floating_base=floating)
        pm = pin.buildModelFromXML(xml, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromXML(xml)
        assert (m.nbodies, m.nq, m.nv) == (pm.njoints - 1, pm.nq, pm.nv)
        assert m.total_mass == pytest.approx(sum(pm.inertias[j].mass for j in range(1, pm.njoints)))
    m = fd.load_urdf(xml)
    assert m.frame_id("world") == 0 and m.frames[0].body == -1 and m.frames[0].kind == "link"


def test_depth_first_document_order(no_warnings) -> None:
    xml = robot(link("r"), link("a"), link("b"), link("c"), link("d"),
                joint("j_b", "r", "b"), joint("j_a", "r", "a"), joint("j_c", "b", "c"), joint("j_d", "a", "d"))
    m = fd.load_urdf(xml)
    assert m.body_names == ("b", "c", "a", "d")
    assert m.parents == (-1, 0, -1, 2)
    assert all(p < i for i, p in enumerate(m.parents))


def test_joint_types_axes_and_limits() -> None:
    xml = robot(
        link("base"), link("p"), link("f"), link("c"), link("s"), link("d"), link("x"),
        joint("planar", "base", "p", "planar", '<axis xyz="1 0 0"/>'),
        joint("float", "p", "f", "floating", '<origin xyz="0 0 1"/>'),
        joint("cont", "f", "c", "continuous", '<axis xyz="0 0 -1"/><limit effort="7" velocity="3"/>'),
        joint("slide", "c", "s", "prismatic", '<axis xyz="0 -3 4"/><limit lower="-0.5" upper="0.25" effort="9"/>'),
        joint("default_axis", "s", "d", "revolute", '<limit effort="1" velocity="1"/>'),
        joint("neg", "d", "x", "revolute", '<axis xyz="-1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/>'),
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = fd.load_urdf(xml)
    assert [str(w.message) for w in caught] == [
        "<string>: line 12: <joint name='slide'>: axis [0.0, -3.0, 4.0] has length 5; normalised",
        "<string>: <limit> needs both 'effort' and 'velocity' (the URDF specification requires them); 1 joint "
        "without: 'slide' (line 12: no velocity); the missing limits are recorded as unbounded (inf)",
    ]
    kinds = [type(j).__name__ for j in m.joints]
    assert kinds == ["PlanarJoint", "FreeFlyerJoint", "RevoluteJoint", "PrismaticJoint", "RevoluteJoint", "RevoluteJoint"]
    assert m.nqs == (3, 7, 1, 1, 1, 1) and m.nvs == (3, 6, 1, 1, 1, 1)
    assert np.array_equal(m.joints[0].normal, [1, 0, 0])
    assert np.array_equal(m.joints[2].axis, [0, 0, -1])  # negative axes are kept
    assert np.allclose(m.joints[3].axis, [0, -0.6, 0.8])  # normalised
    assert np.array_equal(m.joints[4].axis, [1, 0, 0])  # the URDF default
    assert np.array_equal(m.joints[5].axis, [-1, 0, 0])
    iq = dict(zip(m.joint_names, m.idx_q, strict=True))
    iv = dict(zip(m.joint_names, m.idx_v, strict=True))
    assert np.all(np.isinf(m.lower[:10])) and np.all(np.isinf(m.upper[:10]))  # planar, floating, continuous
    assert (m.velocity_limit[iv["cont"]], m.effort_limit[iv["cont"]]) == (3, 7)
    assert (m.lower[iq["slide"]], m.upper[iq["slide"]]) == (-0.5, 0.25)
    assert (m.velocity_limit[iv["slide"]], m.effort_limit[iv["slide"]]) == (math.inf, 9)  # absent: unbounded
    assert (m.lower[iq["default_axis"]], m.upper[iq["default_axis"]]) == (0, 0)  # URDF defaults
    assert (m.lower[iq["neg"]], m.upper[iq["neg"]]) == (-2, 2)
    # a moving joint's frame is its child body's frame (it moves with q, as in Pinocchio); the joint
    # placement is the body's joint_placements entry
    f = m.frames[m.frame_id("float")]
    assert (f.kind, f.body) == ("joint", 1) and np.allclose(f.placement.translation, [0, 0, 0])
    assert np.allclose(m.joint_placements[1].translation, [0, 0, 1])
    assert m.frames[m.frame_id("f")].kind == "body" and m.frames[m.frame_id("f")].body == 1


def test_mimic_is_recorded_not_enforced(no_warnings) -> None:
    m = fd.load_urdf(arm(j2=LIMIT + '<mimic joint="j1" multiplier="-2" offset="0.5"/>'))
    assert m.mimics == (fd.Mimic("j2", "j1", -2.0, 0.5),)
    assert m.nq == 2
    m = fd.load_urdf(arm(j2=LIMIT + '<mimic joint="j1"/>'))
    assert m.mimics == (fd.Mimic("j2", "j1", 1.0, 0.0),)
    # a fixed joint mimicking another is what a reduced model leaves behind: nothing to record, nothing to say
    xml = robot(link("a"), link("b"), link("c"), joint("j", "a", "b"), joint("f", "b", "c", "fixed", '<mimic joint="j"/>'))
    assert fd.load_urdf(xml).mimics == ()


def test_namespaced_robot_and_foreign_elements(no_warnings) -> None:
    xml = ('<robot name="r" xmlns="http://example.org/urdf" xmlns:x="http://example.org/other">'
           + link("a") + link("b") + joint("j", "a", "b") + '<x:link name="not_a_link"/></robot>')
    m = fd.load_urdf(xml)
    assert m.body_names == ("b",) and "not_a_link" not in {f.name for f in m.frames}


# ---------------------------------------------------------------------------
# hostile values: length, time, message size, error types, magnitudes
# ---------------------------------------------------------------------------


def _with_mass(value: str) -> str:
    return robot(link("a"), link("b", f'<inertial><mass value="{value}"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" '
                                      'iyz="0" izz="1"/></inertial>'), joint("j", "a", "b"))


def test_numbers_are_parsed_in_linear_time() -> None:
    """A digit run that fails to match must not backtrack quadratically (it took 1.8 s at 12 000 digits)."""
    xml = _with_mass("1" * 9_999 + "x")  # just within MAX_ATTRIBUTE_LENGTH
    start = time.monotonic()
    for _ in range(5):
        with pytest.raises(URDFError, match=r"is not a decimal number"):
            fd.load_urdf(xml)
    assert time.monotonic() - start < 1.0  # linear: about 1 ms each; quadratic: > 1 s each


@pytest.mark.parametrize("size", [10_001, 5_000_000])
def test_attribute_length_is_bounded(size: int) -> None:
    start = time.monotonic()
    with pytest.raises(URDFError) as info:
        fd.load_urdf(_with_mass("1" * size))
    assert time.monotonic() - start < 5  # hang guard
    msg = str(info.value)
    assert msg.startswith("<string>: line 3: <mass>: value='1111")
    assert msg.endswith(f"... ({size} characters): expected at most 10000 characters (MAX_ATTRIBUTE_LENGTH), got {size}")
    # any attribute, also of an element the loader ignores, and the element's name is said
    with pytest.raises(URDFError, match=r"line 2: <gazebo name='g'>: plugin='xxx.*got 20000$"):
        fd.load_urdf(robot('<gazebo name="g" plugin="' + "x" * 20_000 + '"/>', link("a")))
    # quotes and ">" inside the value do not hide its length (only "<" cannot be in a value)
    with pytest.raises(URDFError, match=r"plugin=.*got 20000$"):
        fd.load_urdf(robot('<gazebo name="g" plugin="' + "x>'" * 6_666 + 'xx"/>', link("a")))


LONG = "n" * 5000

LONG_VALUES = {
    "bad-number": (_with_mass("1" * 5000 + "x"), URDFError),
    "too-many-numbers": (arm(j1='<origin xyz="' + "1 " * 3000 + '"/>' + LIMIT), URDFError),
    "duplicate-link": (robot(link(LONG), link(LONG)), URDFError),
    "unknown-parent": (robot(link("a"), link("b"), joint("j", LONG, "b")), URDFError),
    "unknown-type": (robot(link("a"), link("b"), joint("j", "a", "b", LONG)), URDFError),
    "two-roots": (robot(link(LONG), link(LONG + "x")), URDFError),
    "mimic-cycle": (robot(link("a"), link("b"), link("c"), joint(LONG, "a", "b", body=LIMIT + '<mimic joint="k"/>'),
                          joint("k", "b", "c", body=LIMIT + f'<mimic joint="{LONG}"/>')), URDFError),
    "wrong-root": (f"<{LONG}/>", URDFError),
    "unknown-encoding": (f'<?xml version="1.0" encoding="{LONG}"?><robot/>'.encode(), URDFError),
    "builder-warning": (robot(link("a"), link(LONG, ""), joint(LONG, "a", LONG)), PhysicalityWarning),
    "builder-limits": (robot(link("a"), link(LONG), joint(LONG, "a", LONG, body='<limit lower="1" upper="0" '
                                                                                 'effort="1" velocity="1"/>')),
                       PhysicalityWarning),
}


@pytest.mark.parametrize(("xml", "kind"), list(LONG_VALUES.values()), ids=list(LONG_VALUES))
def test_messages_quote_at_most_100_characters(xml, kind) -> None:
    """A long offending value is quoted by its first 100 characters and its length (it was quoted whole)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fd.load_urdf(xml)
        except URDFError as exc:
            messages = [str(exc)]
        else:
            messages = [str(w.message) for w in caught if issubclass(w.category, kind)]
    assert messages
    for msg in messages:
        assert len(msg) < 600, msg[:300]
        assert re.search(r"\.\.\. \(\d{4,} characters\)", msg), msg


@pytest.mark.parametrize(
    ("inertia", "what"),
    [
        ('ixx="1e308" ixy="0" ixz="0" iyy="1e308" iyz="0" izz="1e308"', "ixx='1e308'"),
        ('ixx="1" ixy="-1e101" ixz="0" iyy="1" iyz="0" izz="1"', "ixy='-1e101'"),
    ],
)
def test_a_huge_inertia_is_a_urdf_error_naming_file_element_and_attribute(tmp_path: Path, inertia: str, what: str) -> None:
    """It was a ModelError 'body 'b': inertia must hold finite floating-point numbers', without the file."""
    f = tmp_path / "big.urdf"
    f.write_text(robot(link("a"), link("b", f'<inertial><mass value="1"/><inertia {inertia}/></inertial>'), joint("j", "a", "b")))
    with pytest.raises(URDFError) as info:
        load_quietly(f)
    assert re.match(rf"{re.escape(str(f))}: line 3: <link name='b'>: <inertia> {what}: expected a magnitude of at "
                    r"most 1e\+100 \(MAX_INERTIA", str(info.value)), str(info.value)


@pytest.mark.parametrize(
    ("axis", "expected", "length"),
    [("1e155 0 0", [1, 0, 0], "1e+155"), ("0 -1.5e308 1.5e308", [0, -0.5**0.5, 0.5**0.5], "1.41421 × 1.5e+308"),
     ("3e-7 4e-7 0", [0.6, 0.8, 0], "5e-07")],
)
def test_a_huge_or_tiny_axis_is_a_direction(axis: str, expected: list[float], length: str) -> None:
    """|axis|² overflows from 1.3e154: the axis was reported as 'zero-length' (a ModelError)."""
    with pytest.warns(PhysicalityWarning, match=rf"<joint name='j1'>: axis .* has length {re.escape(length)}; normalised"):
        m = fd.load_urdf(arm(j1=f'<axis xyz="{axis}"/>' + LIMIT))
    assert np.allclose(m.joints[0].axis, expected, rtol=0, atol=1e-15)


def test_a_subnormal_axis_is_refused_as_too_short() -> None:
    with pytest.raises(URDFError, match=r"<joint name='j1'>: <axis> xyz=\[1e-320, 0.0, 0.0\]: expected a direction, "
                                        r"got a zero-length joint axis \(length 1e-320\)"):
        fd.load_urdf(arm(j1='<axis xyz="1e-320 0 0"/>' + LIMIT))


def _inertial_at(com: str, mass: str = "1", moment: str = "1") -> str:
    return (f'<inertial><origin xyz="{com}"/><mass value="{mass}"/><inertia ixx="{moment}" ixy="0" ixz="0" '
            f'iyy="{moment}" iyz="0" izz="{moment}"/></inertial>')


MAGNITUDES = {
    "mass-1e308": (_with_mass("1e308"), r"<link name='b'>: <mass> value='1e308': expected a magnitude of at most "
                                        r"1e\+100 \(MAX_MASS: larger values overflow the dynamics\), got 1e\+308"),
    "mass-above-limit": (_with_mass("1.0000001e100"), r"<mass> value='1.0000001e100': .*MAX_MASS"),
    "joint-origin-1e154": (arm(j2='<origin xyz="0 1e154 0"/>' + LIMIT),
                           r"<joint name='j2'>: <origin> xyz='0 1e154 0': expected a magnitude of at most 1e\+60 "
                           r"\(MAX_LENGTH"),
    "com-above-limit": (robot(link("a"), link("b", _inertial_at("0 0 -2e60")), joint("j", "a", "b")),
                        r"line 3: <link name='b'>: <origin> xyz='0 0 -2e60': .*MAX_LENGTH"),
    "prismatic-limit": (arm(j1='<limit lower="-1e308" upper="1e308" effort="1" velocity="1"/>'),
                        r"<joint name='j1'>: <limit> lower='-1e308': .*MAX_LENGTH"),
}


@pytest.mark.parametrize(("xml", "match"), list(MAGNITUDES.values()), ids=list(MAGNITUDES))
def test_magnitudes_that_overflow_the_dynamics_are_refused(xml: str, match: str) -> None:
    """These loaded without a word and gave NaN in the dynamics (or in random configurations)."""
    with pytest.raises(URDFError, match=match):
        load_quietly(xml)


def _chain_at_the_limits(n: int, types: tuple[str, ...]) -> str:
    """n links, every joint origin, centre of mass, mass and inertia entry at the loader's limits."""
    from featherdyn.urdf import MAX_INERTIA, MAX_LENGTH, MAX_MASS

    L, M, J = f"{MAX_LENGTH:.17g}", f"{MAX_MASS:.17g}", f"{MAX_INERTIA:.17g}"
    inertial = (f'<inertial><origin xyz="{L} -{L} {L}" rpy="0.3 -1 2"/><mass value="{M}"/>'
                f'<inertia ixx="{J}" ixy="0" ixz="0" iyy="{J}" iyz="0" izz="{J}"/></inertial>')
    parts = [link(f"l{i}", inertial) for i in range(n)]
    for i in range(1, n):
        jtype = types[i % len(types)]
        body = f'<origin xyz="-{L} {L} {L}" rpy="{i} 0.5 -0.25"/><axis xyz="{i % 3} 1 -1"/>'
        if jtype in ("revolute", "prismatic"):
            body += f'<limit lower="-{L}" upper="{L}" effort="1" velocity="1"/>'
        parts.append(joint(f"j{i}", f"l{i - 1}", f"l{i}", jtype, body))
    return robot(*parts)


ROTARY = ("revolute", "continuous")
ALL_TYPES = ("revolute", "prismatic", "continuous", "floating", "planar")


@pytest.mark.parametrize("backend", ["reference", "compiled"])
@pytest.mark.parametrize("types", [ROTARY, ALL_TYPES], ids=["rotary", "all-types"])
@pytest.mark.parametrize("floating_base", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("scale", [1.0, 1e10], ids=["state1", "state1e10"])
def test_dynamics_at_the_limits_stay_finite(types: tuple[str, ...], floating_base: bool, scale: float,
                                            backend: str) -> None:
    """The documented limits keep RNEA, CRBA and ABA finite (module doc of featherdyn.urdf).

    ABA's singularity test is relative to the largest inertia entry (``m·|c|²``, 1e220 here): a joint
    whose articulated inertia is a bare mass (prismatic, free flyer: 1e100) then counts as singular, a
    featherdyn error rather than a number. Rotary chains must give numbers.
    """
    m = load_quietly(_chain_at_the_limits(12, types), floating_base=floating_base)
    rng = np.random.default_rng(16)
    for _ in range(3):
        q = fd.random_configuration(m, rng)
        v, a, tau = (scale * rng.standard_normal(m.nv) for _ in range(3))
        results = {"rnea": fd.rnea(m, q, v, a, backend=backend), "crba": fd.crba(m, q, backend=backend)}
        try:
            results["aba"] = fd.aba(m, q, v, tau, backend=backend)
        except fd.errors.SingularMassMatrixError:
            assert types != ROTARY or floating_base, "ABA called a rotary chain at the limits singular"
        for name, value in results.items():
            assert np.all(np.isfinite(value)), f"{name} ({backend}): not finite at the limits (floating_base={floating_base})"


# ---------------------------------------------------------------------------
# required <limit> attributes, real-file leniency
# ---------------------------------------------------------------------------


def test_limit_without_effort_or_velocity_warns_once_listing_the_joints() -> None:
    n = 15
    parts = [link(f"l{i}") for i in range(n + 1)]
    parts += [joint(f"j{i}", f"l{i - 1}", f"l{i}", body='<limit lower="-1" upper="1" velocity="1"/>') for i in range(1, n + 1)]
    parts[-1] = joint(f"j{n}", f"l{n - 1}", f"l{n}", "continuous", "<limit/>")
    xml = robot(*parts)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = fd.load_urdf(xml)
    assert len(caught) == 1 and caught[0].category is PhysicalityWarning
    msg = str(caught[0].message)
    assert msg.startswith("<string>: <limit> needs both 'effort' and 'velocity' (the URDF specification requires them); "
                          f"{n} joints without: 'j1' (line {n + 3}: no effort), 'j2' ")
    assert msg.endswith("'j10' (line 27: no effort) and 5 more; the missing limits are recorded as unbounded (inf)")
    assert np.all(np.isinf(m.effort_limit)) and m.velocity_limit[0] == 1
    with pytest.raises(URDFError, match=r"<string>: <limit> needs both 'effort' and 'velocity'.*\(strict=True\)$"):
        fd.load_urdf(xml, strict=True)
    # a continuous joint's <limit> is checked as well; fixed, floating and planar joints ignore <limit>
    with pytest.warns(PhysicalityWarning, match=r"1 joint without: 'j2' \(line 6: no effort or velocity\)"):
        fd.load_urdf(arm(j2='<limit lower="-1" upper="1"/>'))
    fd.load_urdf(robot(link("a"), link("b"), joint("f", "a", "b", "fixed", "<limit/>")), strict=True)


def test_library_robots_give_every_limit(no_warnings) -> None:
    """No bundled or example-robot-data robot lacks effort or velocity: the new warning stays quiet for them."""
    from featherdyn.robots import robot_path

    for name in fd.list_robots():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PhysicalityWarning)
            fd.load_urdf(robot_path(name))
        assert not [w for w in caught if "'effort' and 'velocity'" in str(w.message)], name


DECLARATION = '<?xml version="1.0" encoding="utf-8"?>'


@pytest.mark.parametrize("lead", ["\n", "  \n\t ", "\r\n\r\n"])
def test_whitespace_before_the_xml_declaration_is_accepted(tmp_path: Path, lead: str, no_warnings) -> None:
    """Pinocchio, MuJoCo and PyBullet load such files; expat refused them ('XML declaration not at start')."""
    xml = lead + DECLARATION + "\n" + arm()
    f = tmp_path / "lead.urdf"
    f.write_bytes(xml.encode())
    sources = [xml, "\ufeff" + xml, xml.encode(), codecs.BOM_UTF8 + xml.encode(), f,
               xml.replace('encoding="utf-8"', 'encoding="UTF-16"').encode("utf-16"),
               xml.replace('encoding="utf-8"', 'encoding="UTF-16"').encode("utf-16-le")]
    for source in sources:
        assert fd.load_urdf(source).body_names == ("l1", "l2")


def test_line_numbers_survive_whitespace_before_the_declaration() -> None:
    xml = "\n\n\n" + DECLARATION + "\n" + robot(link("a"), link("a"))
    with pytest.raises(URDFError, match=r"<string>: line 7: <link name='a'>: duplicate link name \(first defined on line 6\)"):
        fd.load_urdf(xml)


@pytest.mark.parametrize("tiny", ["1e-310", "5e-324", "1e-101"])
def test_a_vanishing_inertial_is_refused(tiny: str) -> None:
    """A chain of subnormal masses loaded without a word and ABA returned NaN."""
    inertial = (f'<inertial><mass value="{tiny}"/><inertia ixx="{tiny}" ixy="0" ixz="0" iyy="{tiny}" iyz="0" '
                f'izz="{tiny}"/></inertial>')
    with pytest.raises(URDFError, match=rf"<string>: line 2: <link name='base'>: <inertial>: expected 0 \(a massless "
                                        rf"link\) or a mass or inertia entry of at least 1e-100 \(MIN_INERTIAL.*got mass "
                                        rf"{float(tiny):g}"):
        fd.load_urdf(arm().replace(INERTIAL, inertial))


def test_tiny_entries_beside_a_real_scale_are_fine(no_warnings) -> None:
    """Round-off off-diagonals such as iCub's ixz=2.4e-35 (and subnormal ones) stay accepted, as does a bare 1e-100 kg."""
    inertial = ('<inertial><mass value="0.5"/><inertia ixx="1e-3" ixy="5e-324" ixz="2.4e-35" iyy="1e-3" iyz="0" '
                'izz="1e-3"/></inertial>')
    fd.load_urdf(robot(link("a"), link("b", inertial), link("c"), joint("j", "a", "b"), joint("k", "b", "c")), strict=True)
    point = '<inertial><mass value="1e-100"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>'
    fd.load_urdf(robot(link("a"), link("b", point), joint("j", "a", "b", "prismatic")), strict=True)


@pytest.mark.parametrize("backend", ["reference", "compiled"])
@pytest.mark.parametrize("floating_base", [False, True], ids=["fixed", "floating"])
def test_dynamics_at_the_smallest_inertial_stay_finite(floating_base: bool, backend: str) -> None:
    """Every link at MIN_INERTIAL, torques up to 1e10: ABA gives numbers (or says the matrix is singular)."""
    inertial = '<inertial><mass value="1e-100"/><inertia ixx="1e-100" ixy="0" ixz="0" iyy="1e-100" iyz="0" izz="1e-100"/></inertial>'
    m = fd.load_urdf(arm().replace(INERTIAL, inertial), floating_base=floating_base)
    rng = np.random.default_rng(16)
    for scale in (1.0, 1e10):
        q = fd.random_configuration(m, rng)
        v, a, tau = (scale * rng.standard_normal(m.nv) for _ in range(3))
        for value in (fd.rnea(m, q, v, a, backend=backend), fd.crba(m, q, backend=backend),
                      fd.aba(m, q, v, tau, backend=backend)):
            assert np.all(np.isfinite(value))


def test_a_name_too_long_is_refused_with_urdf_error(tmp_path: Path) -> None:
    """A path longer than a file name may be fails with ENAMETOOLONG: a URDFError that says so."""
    long = tmp_path / ("a" * (os.pathconf(tmp_path, "PC_NAME_MAX") + 1) + ".urdf")
    with pytest.raises(URDFError, match=rf"cannot read the URDF file: {os.strerror(errno.ENAMETOOLONG)}"):
        fd.load_urdf(long)
