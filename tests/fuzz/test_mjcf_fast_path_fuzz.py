"""Seeded mutation fuzz of the MJCF loader's fast path against the Python reader.

Seeds: three documents the fast path reads (default classes, frames, every
orientation, fromto, inertials, every joint and primitive geom, inline meshes,
compiler and option settings, ignored elements), 1 000 mutants of each; and a
document including four files (nested includes, ``<mujocoinclude>``, default
classes, meshes and bodies from included files), 500 mutants. Each mutant
applies one to three edits,
either to the tree (an attribute set to a hostile or plausible value, an
element deleted, duplicated, moved or renamed, a class changed) or to the text
(a character, entity, comment, CDATA, namespace, declaration or line end
inserted, a span deleted or duplicated, a quote swapped). For each mutant the
fast path and the Python reader must give the same outcome
(``tests/_mjcf_fast.py``: the same model bit for bit and the same warnings, or
the same error and message). The fast path must read a good share of the
mutants itself, and decline some.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from _mjcf_fast import outcome, restructure, taken

SEEDS = [
    """<mujoco model="fuzz"><compiler angle="degree" eulerseq="xyz" autolimits="true" settotalmass="12"/>
  <option gravity="0 0 -9.81"><flag gravity="enable"/></option>
  <default><joint armature="0.01" damping="1" range="-90 90"/><geom density="800" type="capsule" size=".05 .1"/>
    <site size=".01"/>
    <default class="c1"><geom type="box" size=".1 .1 .1" quat="1 0 0 1"/><joint axis="0 1 0" ref="10"/></default>
    <default class="c2"><geom type="ellipsoid" size=".1 .2 .3" mass="1"/><joint type="slide"/>
      <default class="c3"><geom type="cylinder" size=".1 .2" fromto="0 0 0 0 0 .4"/></default></default>
  </default>
  <worldbody><geom type="plane" size="5 5 .1"/><light pos="0 0 3"/>
    <body name="base" pos="0 0 1" euler="0 0 30"><freejoint/><geom type="sphere" size=".2"/>
      <site name="imu" pos="0 0 .1" quat="0 0 0 1"/>
      <body name="l1" pos=".2 0 0" childclass="c1"><joint name="j1"/><joint name="j2" axis="1 0 0" pos="0 0 .1"/>
        <geom fromto="0 0 0 0 0 -.3" type="capsule" size=".04"/>
        <frame pos="0 0 -.3" axisangle="0 1 0 20" childclass="c2"><body name="l2"><joint name="j3" axis="0 0 1"/>
          <geom/><geom class="c3"/></body></frame>
      </body>
      <body name="tail" pos="-.2 0 0" xyaxes="0 1 0 -1 0 0"><joint type="ball"/>
        <inertial pos="0 0 .05" mass=".5" diaginertia=".01 .02 .025" euler="10 0 0"/>
        <body name="tip" zaxis="1 0 1"><geom size=".05 .1 .02" class="c1"/></body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1"/></actuator><sensor><jointpos joint="j1"/></sensor>
</mujoco>""",
    """<?xml version="1.0" encoding="utf-8"?>
<!-- a second seed: radians, extrinsic angles, geoms from inertia groups -->
<mujoco model='two'>
  <compiler angle='radian' eulerseq='ZYX' inertiafromgeom='true' inertiagrouprange='0 2' boundmass='0.01'/>
  <worldbody>
    <body name='a' euler='0.1 0.2 0.3'><joint type='hinge' axis='1 1 1' range='-1 1' limited='true'/>
      <geom type='box' size='.1 .2 .3' group='1'/><geom type='sphere' size='.3' group='3'/>
      <inertial pos='0 0 0' mass='2' diaginertia='1 1 1'/>
      <body name='b' pos='0 .5 0'><joint type='slide' axis='0 0 1' ref='.2'/>
        <geom type='capsule' fromto='0 0 0 .3 .3 0' size='.05'/><site fromto='0 0 0 0 0 1'/>
        <body name='c'><geom type='cylinder' size='.1 .1' zaxis='0 1 0'/></body>
      </body>
    </body>
    <body name='free'><joint type='free'/><geom type='ellipsoid' size='.1 .1 .2' mass='3'/></body>
  </worldbody>
  <tendon><fixed armature='0'><joint joint='a' coef='1'/></fixed></tendon>
</mujoco>""",
    """<mujoco model="three"><compiler meshdir="."/>
  <default><mesh scale="1 1 1"/>
    <default class="m2"><mesh scale=".5 .5 .5" inertia="exact"/><geom type="mesh" mesh="tet" density="500"/></default>
  </default>
  <asset><mesh name="tet" vertex="0 0 0 1 0 0 0 1 0 0 0 1" face="0 2 1 0 1 3 0 3 2 1 2 3"/>
    <mesh name="pts" class="m2" inertia="convex" vertex="0 0 0 1 0 0 0 1 0 0 0 1 1 1 1"/></asset>
  <worldbody>
    <body name="a" pos="0 0 1"><joint axis="0 1 0"/><geom type="mesh" mesh="tet"/><geom class="m2"/>
      <body name="b" quat="1 0 1 0"><joint type="slide" axis="1 0 0"/><geom type="mesh" mesh="pts" mass="1" euler="10 20 30"/>
        <site name="s" pos=".1 .1 .1"/></body>
    </body>
  </worldbody>
</mujoco>""",
]

HOSTILE = ["nan", "inf", "-inf", "1e308", "1e999", "-1e308", "5e-324", "1e-320", "1e-400", "0", "-1", "", " ",
           "abc", "0x10", "1" * 400, "1 2", "1 2 3 4 5 6 7", "1e61", "1e101", "-0", "+1", "1.", ".5", "1e5", "1E-5",
           "true", "false", "auto", "degree", "radian", "c1", "c2", "nope", "hinge", "ball", "free", "slide", "mesh",
           "plane", "hfield", "sdf", "box", "0 0 0", "-0 0 0", "0 0 1", "1 0 0 0", "0 0 0 0", "1 2 3", "1 2 3 4",
           "0 0 0 1 0 0", "1 0 0 0 1 0", "-1 1", "1 -1", "0.5 0.5 0.5 0.5", "1_0", "١", "1\t2\n3", "tet", "pts",
           "legacy", "exact", "convex", "shell", "0 1 2", "0 0 0 1 0 0 0 1 0 0 0 1"]
KEYS = ["pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "size", "mass", "axis", "range", "class",
        "childclass", "type", "fromto", "diaginertia", "ref", "armature", "density", "group", "limited", "name",
        "angle", "eulerseq", "inertiafromgeom", "inertiagrouprange", "boundmass", "settotalmass", "autolimits",
        "gravity", "shellinertia", "fullinertia", "coordinate", "mesh", "inertia", "scale", "vertex", "face",
        "meshdir", "file"]
SNIPPETS = ["<", ">", "&", "&amp;", "&#65;", '"', "'", "/", "=", " ", "\x00", "\x01", "é", "<!--", "-->", "--",
            "<!-- c -->", "<![CDATA[x]]>", "\r\n", "\r", "\t", "<?pi x?>", "</body>", "<body>", "<geom/>",
            ' xmlns:x="u"', "x:y", "<!DOCTYPE m>", '<?xml version="1.0"?>', "\ufeff", "<include file='x.xml'/>"]


def _tree_edit(root: ET.Element, rng: np.random.Generator) -> None:
    elems = list(root.iter())
    e = elems[rng.integers(len(elems))]
    kind = str(rng.choice(["attr", "attr", "attr", "delete", "duplicate", "move", "rename", "class"]))
    if kind == "attr":
        keys = [*e.attrib, *KEYS]
        e.set(str(rng.choice(keys)), str(rng.choice(HOSTILE)))
    elif kind == "class":
        e.set(str(rng.choice(["class", "childclass"])), str(rng.choice(["c1", "c2", "c3", "main", "nope"])))
    elif e is not root:
        restructure(root, e, kind, lambda xs: xs[rng.integers(len(xs))],
                    ["gizmo", "frame", "body", "geom", "site", "joint", "freejoint", "inertial", "camera", "plugin",
                     "composite", "replicate", "include", "default"])


def _text_edit(text: str, rng: np.random.Generator) -> str:
    at = int(rng.integers(len(text) + 1))
    kind = rng.choice(["insert", "insert", "delete", "duplicate", "quote"])
    if kind == "insert":
        return text[:at] + str(rng.choice(SNIPPETS)) + text[at:]
    end = min(len(text), at + int(rng.integers(1, 12)))
    if kind == "delete":
        return text[:at] + text[end:]
    if kind == "duplicate":
        return text[:end] + text[at:end] + text[end:]
    return text[:at] + text[at:].replace('"', "'", 1)


def mutant(seed: int, k: int, text: str | None = None) -> str:
    """Mutant ``k`` of ``SEEDS[seed]`` (or of ``text``, with the random stream of ``seed``)."""
    rng = np.random.default_rng([seed, k])
    text = SEEDS[seed] if text is None else text
    for _ in range(int(rng.integers(1, 4))):
        if rng.random() < 0.6:
            try:
                root = ET.fromstring(text)
            except ET.ParseError:
                text = _text_edit(text, rng)
                continue
            _tree_edit(root, rng)
            text = ET.tostring(root, encoding="unicode")
        else:
            text = _text_edit(text, rng)
    return text


@pytest.mark.parametrize("seed", range(len(SEEDS)))
def test_mutants_give_the_python_readers_outcome(seed: int) -> None:
    assert taken(SEEDS[seed])
    n, read, models = 1000, 0, 0
    for k in range(n):
        text = mutant(seed, k)
        fast, slow = outcome(text, fast=True), outcome(text, fast=False)
        assert fast == slow, (k, text)
        read += taken(text)
        models += fast[0] == "model"
    # most tree edits keep a document the fast path reads; text edits and hostile values make it decline
    assert read >= n // 5, read
    assert read <= n - n // 20, read
    assert models >= n // 10, models


INCLUDED = {
    "defaults.xml": "<mujocoinclude><default><geom density='700'/><default class='c1'><joint axis='0 1 0'/>"
                    "</default></default></mujocoinclude>",
    "legs.xml": "<mujoco><body name='leg' childclass='c1'><joint/><geom size='.1'/><include file='foot.xml'/></body>"
                "</mujoco>",
    "foot.xml": "<mujoco><body name='foot' pos='0 0 -.3'><joint/><geom type='mesh' mesh='tet'/></body></mujoco>",
    "assets.xml": "<mujoco><asset><mesh name='tet' vertex='0 0 0 1 0 0 0 1 0 0 0 1' face='0 2 1 0 1 3 0 3 2 1 2 3'/>"
                  "</asset></mujoco>",
}
INCLUDING = """<mujoco model="four"><include file="defaults.xml"/><include file="assets.xml"/>
  <worldbody><body name="torso" pos="0 0 1"><freejoint/><geom size=".2"/><include file="legs.xml"/></body>
  </worldbody>
</mujoco>"""


def test_mutants_of_a_document_with_includes_give_the_python_readers_outcome(tmp_path: Path) -> None:
    for name, text in INCLUDED.items():
        (tmp_path / name).write_text(text)
    path = tmp_path / "main.xml"
    path.write_text(INCLUDING)
    assert taken(INCLUDING, path=path)
    n, read = 500, 0
    for k in range(n):
        text = mutant(len(SEEDS), k, INCLUDING)
        path.write_text(text)
        fast, slow = outcome(path, fast=True), outcome(path, fast=False)
        assert fast == slow, (k, text)
        read += taken(text, path=path)
    assert n // 10 <= read <= n - n // 20, read
