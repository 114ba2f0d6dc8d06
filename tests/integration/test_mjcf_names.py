"""Unknown MJCF elements and attributes are refused as MuJoCo refuses them (issue 32 item 6), with the nearest
valid name; MuJoCo (the ``mujoco`` package) is the oracle of what a typo is.

Where MuJoCo's schema check does not look (inside ``<frame>`` and ``<replicate>``, measured: it ignores unknown
attributes there) featherdyn warns instead, naming each; ``strict=True`` refuses.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

import featherdyn as fd
from featherdyn.readers.mjcf_schema import check_names
from featherdyn.readers.mjcf_xml import read_document

mujoco = pytest.importorskip("mujoco")

_ARM = ('<mujoco><worldbody><body name="arm" pos="0 0 1">{inner}<geom type="capsule" fromto="0 0 0 0.5 0 0" '
        'size="0.05"/></body></worldbody>{after}</mujoco>')

# (document, the message featherdyn gives): every one of them MuJoCo refuses too
TYPOS = {
    "attribute frobnicate": (_ARM.format(inner='<joint name="j" frobnicate="1"/>', after=""),
                             r"line 1: <joint name='j'>: unknown attribute 'frobnicate' of <joint> \(MuJoCo refuses "
                             r"it\); expected one of 'actuatorfrclimited', .*'axis'"),
    "attribute axsi": (_ARM.format(inner='<joint name="j" axsi="0 1 0"/>', after=""),
                       r"<joint name='j'>: unknown attribute 'axsi' of <joint> \(MuJoCo refuses it\); did you mean "
                       r"'axis'\?"),
    "element jiont": (_ARM.format(inner='<jiont name="j"/>', after=""),
                      r"<jiont name='j'>: unknown MJCF element <jiont> in <body> \(MuJoCo refuses it\); did you "
                      r"mean <joint>\?"),
    "top-level wordlbody": ("<mujoco><wordlbody/></mujoco>",
                            r"unknown MJCF element <wordlbody> in <mujoco> .*did you mean <worldbody>\?"),
    "compiler angel": ('<mujoco><compiler angel="radian"/><worldbody/></mujoco>',
                       r"<compiler>: unknown attribute 'angel' of <compiler> .*did you mean 'angle'\?"),
    "a name in a default": ('<mujoco><default><geom name="g"/></default><worldbody/></mujoco>',
                            r"unknown attribute 'name' of <geom>"),
    "sensor nosie": (_ARM.format(inner='<joint name="j"/>', after='<sensor><jointpos joint="j" nosie="1"/></sensor>'),
                     r"<jointpos>: unknown attribute 'nosie' of <jointpos> .*did you mean 'noise'\?"),
    "world body pos": ('<mujoco><worldbody pos="1 0 0"/></mujoco>',
                       r"<worldbody>: pos='1 0 0': the world body takes no attributes"),
    "a frame in a default": ('<mujoco><default><frame pos="1 0 0"/></default><worldbody/></mujoco>',
                             r"unknown MJCF element <frame> in <default>"),
    "an element of an unknown name in a frame": (_ARM.format(inner='<frame><jiont/></frame>', after=""),
                                                 r"unknown MJCF element <jiont> in <frame> .*did you mean <joint>\?"),
}


def _mujoco_refuses(xml: str) -> bool:
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError:
        return True
    return False


@pytest.mark.parametrize("case", list(TYPOS))
def test_a_typo_is_refused_as_mujoco_refuses_it(case: str) -> None:
    xml, message = TYPOS[case]
    assert _mujoco_refuses(xml), "MuJoCo is the oracle: it refuses this document"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fd.PhysicalityWarning)
        with pytest.raises(fd.MJCFError, match=message):
            fd.load_mjcf(xml)


def test_the_error_names_the_line_in_the_file(tmp_path: Path) -> None:
    path = tmp_path / "arm.xml"
    path.write_text(_ARM.format(inner='\n<joint name="j"\n axsi="0 1 0"/>\n', after="").replace("><", ">\n<"),
                    encoding="utf-8")
    with pytest.raises(fd.MJCFError, match=rf"^{path}: line 4: <joint name='j'>: unknown attribute 'axsi'"):
        fd.load_mjcf(path)


def test_an_included_files_typo_names_that_file(tmp_path: Path) -> None:
    (tmp_path / "part.xml").write_text('<mujoco><body name="b"><joint axsi="1 0 0"/><geom size="0.1"/></body>'
                                       '</mujoco>', encoding="utf-8")
    main = tmp_path / "main.xml"
    main.write_text('<mujoco><worldbody><include file="part.xml"/></worldbody></mujoco>', encoding="utf-8")
    with pytest.raises(ValueError, match="axsi"):
        mujoco.MjModel.from_xml_path(str(main))
    with pytest.raises(fd.MJCFError, match=rf"{tmp_path / 'part.xml'}: line 1: <joint>: unknown attribute 'axsi'"):
        fd.load_mjcf(main)


# documents MuJoCo accepts, some with rarely used names: featherdyn accepts them too, without a warning
VALID = {
    "every joint attribute a default may set": (
        '<mujoco><default><joint armature="0.1" damping="1" frictionloss="0.1" springref="0" stiffness="0" '
        'limited="auto" margin="0" group="1" actuatorfrcrange="-1 1" actuatorgravcomp="false"/>'
        '<default class="a"><geom density="500" friction="1 0.005 0.0001" condim="3"/></default></default>'
        + _ARM.format(inner='<joint name="j" class="a" axis="0 1 0" range="-1 1" ref="0.1" user="1"/>',
                      after='<actuator><motor joint="j" gear="2" ctrlrange="-1 1"/></actuator>')[len("<mujoco>"):]),
    "visual, statistic, size, keyframe, custom": (
        '<mujoco model="m"><visual><global azimuth="10" offwidth="640"/><quality shadowsize="1024"/>'
        '<map fogstart="3"/></visual><statistic extent="2" center="0 0 1"/><size nkey="1"/>'
        '<custom><numeric name="n" data="1 2"/></custom>'
        + _ARM.format(inner='<joint name="j"/>', after='<keyframe><key name="k" qpos="0.5"/></keyframe>')[
            len("<mujoco>"):]),
    "frames and replicates": (
        _ARM.format(inner='<joint name="j"/><frame name="f" pos="0 0 1" euler="0 0 90"><site name="s"/></frame>',
                    after="").replace('<worldbody>', '<worldbody><replicate count="2" offset="1 0 0" sep="-">'
                                      '<frame pos="0 1 0"><geom size="0.1"/></frame></replicate>')),
}


@pytest.mark.parametrize("case", list(VALID))
def test_valid_names_load_without_a_word(case: str) -> None:
    xml = VALID[case]
    assert not _mujoco_refuses(xml)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fd.load_mjcf(xml)
    assert not [w for w in caught if "unknown" in str(w.message)], [str(w.message) for w in caught]


def test_inside_a_frame_mujoco_ignores_an_unknown_attribute_and_featherdyn_warns() -> None:
    xml = _ARM.format(inner='<joint name="j"/><frame><site name="s" frob="1"/></frame>', after="")
    assert not _mujoco_refuses(xml)  # measured: MuJoCo's schema check skips <frame>
    with pytest.warns(fd.PhysicalityWarning, match=r"unknown attributes inside <frame> or <replicate>, where MuJoCo "
                                                   r"ignores them .*line 1: <site name='s'>: 'frob'"):
        fd.load_mjcf(xml)
    with pytest.raises(fd.MJCFError, match=r"<site name='s'>: unknown attribute 'frob' of <site> \(MuJoCo ignores it "
                                           r"inside <frame> and <replicate>; refused with strict=True\)"):
        fd.load_mjcf(xml, strict=True)


def test_a_replicates_childclass_gives_its_copies_their_defaults() -> None:
    # MuJoCo's reader takes childclass on <replicate> (undocumented): the copies' joints get the class's defaults
    xml = ('<mujoco><default><default class="a"><joint armature="0.5" axis="0 1 0"/></default></default>'
           '<worldbody><replicate count="2" offset="1 0 0" childclass="a"><body><joint/><geom size=".1"/></body>'
           '</replicate></worldbody></mujoco>')
    m = mujoco.MjModel.from_xml_string(xml)
    model = fd.load_mjcf(xml)
    assert model.armature.tolist() == m.dof_armature.tolist() == [0.5, 0.5]
    assert [j.axis.tolist() for j in model.joints] == m.jnt_axis.tolist()


def _installed() -> list[Path]:
    """The MJCF files shipped in mujoco (testdata), gymnasium and dm_control (suite), where installed."""
    import importlib.util

    found = []
    for package, sub in (("mujoco", "testdata"), ("gymnasium", "envs/mujoco/assets"), ("dm_control", "suite")):
        spec = importlib.util.find_spec(package)
        if spec is not None and spec.origin is not None:
            found += sorted((Path(spec.origin).parent / sub).glob("*.xml"))
    return found


INSTALLED = _installed()


@pytest.mark.parametrize("path", INSTALLED, ids=[f"{p.parent.name}/{p.name}" for p in INSTALLED])
def test_every_installed_model_mujoco_loads_passes_the_name_check(path: Path) -> None:
    try:
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError:
        pytest.skip("MuJoCo refuses this file: not a model on its own")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_names(read_document(path, strict=False))
    assert not caught, [str(w.message) for w in caught]


def test_the_installed_models_are_there() -> None:
    assert sum(p.parent.name == "assets" for p in INSTALLED) >= 14, INSTALLED
