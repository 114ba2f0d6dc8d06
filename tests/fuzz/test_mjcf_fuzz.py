"""Mutation fuzzing of the MJCF loader with hypothesis: every mutant loads or raises MJCFError, never anything else.

Seeds: hand-written MJCF documents covering defaults, frames, several joints
per body, free and ball joints, inline meshes, replicate and the elements
without tree meaning. Each example applies one to three edits: an attribute
set to a hostile value (NaN, inf, 1e308, 1e999, subnormals, garbage, 12 000
digits, empty), an element deleted, duplicated, moved into another element
or replaced by an unknown one, a class renamed, the text truncated, a DTD or
entity prologue. For every mutant:

* ``load_mjcf`` returns a Model or raises ``MJCFError`` (a ``ValueError``)
  whose message starts with the source label and is short;
* a model that loaded without warnings gives finite RNEA, CRBA and ABA at a
  random state, or a featherdyn error (a singular mass matrix), with no
  numpy warning.
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn.errors import FeatherdynError, MJCFError


def restructure(root: ET.Element, e: ET.Element, kind: str, pick: Callable[[list[Any]], Any],
                tags: list[str]) -> None:
    """A structural edit of element ``e`` (not the root) of the tree ``root``: ``kind`` is ``"delete"``,
    ``"duplicate"`` (a copy appended to its parent), ``"move"`` (into another element chosen by ``pick``, unless
    that is inside ``e``) or ``"rename"`` (to a tag chosen by ``pick`` from ``tags``)."""
    parent = next(p for p in root.iter() if any(c is e for c in p))
    if kind == "delete":
        parent.remove(e)
    elif kind == "duplicate":
        parent.append(ET.fromstring(ET.tostring(e)))
    elif kind == "move":
        target = pick(list(root.iter()))
        if all(target is not d for d in e.iter()):
            parent.remove(e)
            target.append(e)
    else:
        e.tag = pick(tags)


SEEDS = [
    """<mujoco model="a"><compiler angle="radian" autolimits="true"/><option gravity="0 0 -9.81"/>
  <default><joint armature="0.1" damping="1"/><geom density="800"/>
    <default class="c1"><geom type="capsule" size="0.05 0.2"/><joint axis="0 1 0" range="-1 1"/></default></default>
  <asset><mesh name="tet" vertex="0 0 0 1 0 0 0 1 0 0 0 1" face="0 2 1 0 1 3 0 3 2 1 2 3"/></asset>
  <worldbody><geom type="plane" size="5 5 .1"/>
    <body name="base" pos="0 0 1" quat="1 0 0 0"><freejoint/><geom type="box" size=".2 .1 .05"/>
      <site name="imu" pos="0 0 .1"/>
      <body name="l1" pos=".2 0 0" childclass="c1"><joint name="j1"/><joint name="j2" axis="1 0 0" pos="0 0 .1"/>
        <geom fromto="0 0 0 0 0 -.3"/>
        <frame pos="0 0 -.3" euler="0 .3 0"><body name="l2"><joint name="j3" type="slide" axis="0 0 1"/>
          <geom type="mesh" mesh="tet" mass="0.3"/></body></frame>
      </body>
      <body name="tail" pos="-.2 0 0"><joint type="ball"/><inertial pos="0 0 0" mass=".5" diaginertia=".01 .01 .01"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1"/></actuator><sensor><jointpos joint="j1"/></sensor>
</mujoco>""",
    """<mujoco><compiler eulerseq="XYZ" inertiafromgeom="true" boundmass="0.01" boundinertia="1e-4"/>
  <worldbody>
    <replicate count="3" offset="0 0 .5" euler="0 0 30">
      <body name="seg" pos="0 0 1"><joint axis="1 0 0" ref="10"/><geom type="ellipsoid" size=".1 .2 .3"/>
        <geom type="cylinder" size=".05 .2" shellinertia="true" euler="90 0 0"/></body>
    </replicate>
    <body name="arm" xyaxes="0 1 0 -1 0 0"><joint axis="0 0 1" armature=".2"/>
      <geom type="sphere" size=".1" pos=".3 0 0"/><body pos=".6 0 0" zaxis="1 0 1"><joint/>
      <inertial pos="0 0 .1" mass="1" fullinertia=".3 .4 .5 .01 .02 .03"/></body></body>
  </worldbody>
</mujoco>""",
]

HOSTILE = ["nan", "inf", "-inf", "1e308", "1e999", "-1e308", "5e-324", "1e-320", "0", "-1", "", " ", "abc", "0x10",
           "1" * 12_000, "1 2", "1 2 3 4 5 6 7", "1e61", "1e101", "-0", "true", "false", "auto", "degree",
           "radian", "c1", "nope", "hinge", "ball", "free", "slide", "mesh", "plane", "tet", "../../../etc/passwd"]
PROLOGUES = ['<!DOCTYPE mujoco [<!ENTITY x "y">]>', '<!DOCTYPE mujoco SYSTEM "file:///etc/passwd">',
             '<?xml version="1.0" encoding="utf-8"?>\n', "\ufeff"]


def _mutate(text: str, data: st.DataObject) -> str:
    root = ET.fromstring(text)
    for _ in range(data.draw(st.integers(1, 3))):
        kind = data.draw(st.sampled_from(["attr", "delete", "duplicate", "move", "unknown", "class"]))
        e = data.draw(st.sampled_from(list(root.iter())))
        if kind == "attr":
            keys = [*e.attrib, "pos", "quat", "euler", "size", "mass", "axis", "range", "class", "type", "fromto",
                    "diaginertia", "count", "file", "mesh", "ref", "armature", "density", "group"]
            e.set(data.draw(st.sampled_from(keys)), data.draw(st.sampled_from(HOSTILE)))
        elif e is not root and kind in ("delete", "duplicate", "move", "unknown"):
            restructure(root, e, "rename" if kind == "unknown" else kind, lambda xs: data.draw(st.sampled_from(xs)),
                        ["gizmo", "composite", "flexcomp", "include", "body", "frame"])
        elif kind == "class":
            e.set("childclass" if data.draw(st.booleans()) else "class", data.draw(st.sampled_from(["c1", "main",
                                                                                                      "nope"])))
    out = ET.tostring(root, encoding="unicode")
    if data.draw(st.integers(0, 9)) == 0:
        out = out[: data.draw(st.integers(0, len(out)))]
    if data.draw(st.integers(0, 9)) == 0:
        out = data.draw(st.sampled_from(PROLOGUES)) + out
    return out


@settings(max_examples=400, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(seed=st.sampled_from(range(len(SEEDS))), data=st.data())
def test_mutants_load_or_raise_mjcf_error(seed: int, data: st.DataObject) -> None:
    xml = _mutate(SEEDS[seed], data)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            model = fd.load_mjcf(xml)
        except MJCFError as exc:
            msg = str(exc)
            if xml.lstrip("\ufeff \t\r\n").startswith("<"):  # (a truncation to nothing reads as a path)
                assert msg.startswith("<string>"), msg[:300]
            assert len(msg) < 3000, len(msg)
            return
    if caught:
        return
    rng = np.random.default_rng(0)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            tau = fd.rnea(model, q, v, a, backend="reference")
            M = fd.crba(model, q, backend="reference")
            ddq = fd.aba(model, q, v, tau, backend="reference")
        except FeatherdynError:
            return
    assert np.all(np.isfinite(tau)) and np.all(np.isfinite(M)) and np.all(np.isfinite(ddq))


@pytest.mark.parametrize("seed", range(len(SEEDS)))
def test_seeds_load_cleanly(seed: int) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_mjcf(SEEDS[seed])
    assert model.nv > 0
