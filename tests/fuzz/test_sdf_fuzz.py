"""Mutation fuzzing of the SDF loader with hypothesis: every mutant loads or raises SDFError, never anything else.

Seeds: hand-written SDFormat documents (1.4 and 1.9: nested models, frames,
``relative_to``, universal and ball joints, a world with two models). Each
example applies one to three edits: an element's text or an attribute set to
a hostile value (NaN, inf, 1e308, 1e999, garbage, 12 000 digits, empty, a
name of another element), an element deleted, duplicated, moved into another
element or renamed, the text truncated, a DTD prologue. For every mutant
``load_sdf`` returns a Model or raises ``SDFError`` whose message starts with
the source label; a model that loaded gives finite CRBA at its neutral
configuration.
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn.errors import SDFError

INERTIAL = ("<inertial><mass>1.5</mass><pose>0 0 -0.2 0 0 0</pose><inertia><ixx>0.1</ixx><ixy>0</ixy><ixz>0</ixz>"
            "<iyy>0.2</iyy><iyz>0</iyz><izz>0.3</izz></inertia></inertial>")
SEEDS = [
    f"""<sdf version="1.9"><model name="m">
  <link name="base">{INERTIAL}</link>
  <joint name="weld" type="fixed"><parent>world</parent><child>base</child></joint>
  <frame name="F" attached_to="base"><pose>0 0 1 0 0.3 0</pose></frame>
  <link name="a"><pose relative_to="F">0 0.2 0 0 0 0</pose>{INERTIAL}<visual name="v"/></link>
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child><pose relative_to="F"/>
    <axis><xyz expressed_in="__model__">0 0 1</xyz><limit><lower>-1</lower><upper>1</upper><effort>5</effort>
    </limit><dynamics><damping>0.1</damping></dynamics></axis></joint>
  <model name="inner"><pose relative_to="a">0 0 -0.5 0 0 0</pose>
    <link name="b">{INERTIAL}</link><link name="c"><pose>0.1 0 0 0 0 0</pose>{INERTIAL}</link>
    <joint name="u" type="universal"><parent>b</parent><child>c</child><axis><xyz>1 0 0</xyz></axis>
      <axis2><xyz>0 1 0</xyz></axis2></joint></model>
  <joint name="j2" type="ball"><parent>a</parent><child>inner::b</child></joint>
</model></sdf>""",
    f"""<sdf version="1.4"><world name="w"><physics type="ode"/>
  <model name="one"><pose>1 0 0 0 0 0</pose><link name="l1"><pose>0 0 1 0.1 0.2 0.3</pose>{INERTIAL}</link>
    <link name="l2"><pose>0 0 2 0 0 0</pose>{INERTIAL}</link>
    <joint name="p" type="prismatic"><parent>l1</parent><child>l2</child><pose>0 0 0.1 0 0 0</pose>
      <axis><xyz>0 1 0</xyz><limit><lower>0</lower><upper>1</upper></limit></axis></joint></model>
</world></sdf>""",
]
HOSTILE = ["nan", "inf", "-inf", "1e308", "1e999", "-1", "0", "", "garbage", "1 2", "0 0 0", "1" * 12000,
           "world", "__model__", "a", "inner::b", "base", "1 0 0 0 0 0 1", "true"]


def mutate(text: str, data: st.DataObject) -> str:
    root = ET.fromstring(text)
    for _ in range(data.draw(st.integers(1, 3))):
        elements = list(root.iter())
        e = data.draw(st.sampled_from(elements))
        kind = data.draw(st.sampled_from(["text", "attr", "delete", "duplicate", "move", "rename"]))
        if kind == "text":
            e.text = data.draw(st.sampled_from(HOSTILE))
        elif kind == "attr":
            attr = data.draw(st.sampled_from(["name", "type", "relative_to", "attached_to", "expressed_in", "version",
                                              "rotation_format", "degrees", "canonical_link"]))
            e.set(attr, data.draw(st.sampled_from(HOSTILE)))
        elif e is not root:
            parent = next(p for p in root.iter() if any(c is e for c in p))
            if kind == "delete":
                parent.remove(e)
            elif kind == "duplicate":
                parent.append(ET.fromstring(ET.tostring(e)))
            elif kind == "move":
                target = data.draw(st.sampled_from(elements))
                if all(target is not d for d in e.iter()):
                    parent.remove(e)
                    target.append(e)
            else:
                e.tag = data.draw(st.sampled_from(["link", "joint", "frame", "model", "pose", "axis", "include",
                                                   "inertia", "x"]))
    out = ET.tostring(root, encoding="unicode")
    cut = data.draw(st.sampled_from([None, "truncate", "dtd"]))
    if cut == "truncate":
        out = out[: data.draw(st.integers(1, len(out)))]  # (an empty text would be a path)
    elif cut == "dtd":
        out = '<!DOCTYPE sdf [<!ENTITY x "y">]>' + out
    return out


@settings(max_examples=200, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(range(len(SEEDS))), st.data())
def test_every_mutant_loads_or_raises_sdf_error(seed: int, data: st.DataObject) -> None:
    text = mutate(SEEDS[seed], data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            model = fd.load_sdf(text, model="one" if seed == 1 else None)
        except SDFError as exc:
            assert str(exc).startswith("<string>"), str(exc)[:300]
            return
    M = fd.crba(model, fd.neutral(model))
    assert np.all(np.isfinite(M))


def test_the_seeds_load() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert fd.load_sdf(SEEDS[0]).nv == 1 + 3 + 2
        assert fd.load_sdf(SEEDS[1], model="one").nv == 6 + 1
