"""The MJCF loader's fast path (``featherdyn._mjcf_native``, C++) against the Python reader.

The fast path reads the usual one-file document itself and declines
everything else to the Python reader. Whatever it takes, the user must see
exactly what the Python reader gives: the same model bit for bit, the same
warnings, the same error and message (``tests/_mjcf_fast.py``). Here: every
installed MJCF model, documents chosen to reach each feature the fast path
reads, each reason it declines, and the refusals of ``test_mjcf.py``. The
seeded mutation fuzz is ``tests/fuzz/test_mjcf_fast_path_fuzz.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from _mjcf_fast import outcome, snapshot, taken
from test_mjcf import BAD

import featherdyn as fd
from featherdyn import mjcf

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import mjcf_survey


def _wrap(body: str, head: str = "", tail: str = "") -> str:
    return f"<mujoco model='t'>{head}<worldbody>{body}</worldbody>{tail}</mujoco>"


def test_the_fast_path_is_built() -> None:
    # CI installs the package from source: the extension exists there (a source tree without the build reads with
    # the Python reader alone, which the other tests compare against)
    assert mjcf._mjcf_native is not None


def test_every_installed_model_it_takes_loads_as_the_python_reader_loads_it() -> None:
    models = [path for _, _, path in mjcf_survey.find_models()]
    read = 0
    for path in models:
        text = mjcf.read_source(path)[0]
        if not taken(text, path=path):
            continue
        read += 1
        fast, slow = outcome(path, fast=True), outcome(path, fast=False)
        assert fast == slow, path
    # gymnasium's models (a test dependency) are read by the fast path: ant, cheetah, hopper, humanoid, ...
    assert read >= 10, f"the fast path read {read} of {len(models)} installed models"


# documents reaching what the fast path reads: each must be taken (not declined) and give the Python reader's model
TAKEN = {
    "declaration, comments, quotes, white space": (
        "<?xml version='1.0' encoding=\"utf-8\" standalone='yes'?>\n<!-- a comment - fine -->\r\n"
        "<mujoco model = 'm' >\r\n<worldbody ><body name='a\tb\r\nc' pos = '0\t0\r\n1'><joint/>"
        "<geom size='.1'/></body ></worldbody>\n<!-- after --></mujoco >\n"),
    "every orientation, degrees": _wrap(
        '<body quat="0.5 0.5 0.5 0.5"><joint axis="1 1 0"/><geom size=".1"/>'
        '<body axisangle="1 2 3 30"><joint type="slide" axis="0 3 4"/><geom type="box" size=".1 .2 .3"/>'
        '<body euler="10 20 30"><joint/><geom type="ellipsoid" size=".1 .2 .3" euler="0 90 0"/>'
        '<body xyaxes="0 1 0 -1 0 0.5"><joint/><geom type="cylinder" size=".1 .2" zaxis="1 1 1"/>'
        '<body zaxis="0 0 -1"><joint type="ball"/><geom type="capsule" size=".1 .2" xyaxes="1 0 0 0 0 1"/>'
        '</body></body></body></body></body>'),
    "radians and an extrinsic euler sequence": _wrap(
        '<body euler="0.1 0.2 0.3"><joint range="-1 1" ref="0.3"/><geom size=".1" euler="0.3 0.2 0.1"/></body>',
        head='<compiler angle="radian" eulerseq="ZyX"/>'),
    "default classes, childclass, frames": _wrap(
        '<body childclass="arm" pos="0 0 1"><joint/><geom/><frame pos="1 0 0" euler="0 0 90" childclass="leg">'
        '<body><joint/><geom/><site name="s" class="arm"/></body><frame quat="0 1 0 0"><geom class="arm"/></frame>'
        '</frame><geom class="leg" pos="0 1 0"/></body>',
        head='<default><geom density="900"/><joint armature=".1" range="-30 30"/>'
             '<default class="arm"><geom type="capsule" size=".05 .2" euler="0 90 0"/><joint axis="1 0 0"/>'
             '<site size=".1" quat="0 0 0 1"/></default>'
             '<default class="leg"><geom type="box" size=".1 .1 .1" quat="0 0 1 0"/><joint damping="2" '
             'armature="0"/></default></default>'
             '<default><geom rgba="1 0 0 1" density="700"/></default>'),
    "fromto geoms and sites": _wrap(
        '<body><joint type="ball"/><geom type="capsule" size=".05" fromto="0 0 0 .1 .2 .3"/>'
        '<geom type="cylinder" size=".05" fromto="0 0 0 0 0 -.3" pos="0 0 0"/>'
        '<geom type="box" size=".05" fromto="0 0 0 .3 0 0"/><geom type="ellipsoid" size=".05" fromto="0 .3 0 0 0 0"/>'
        '<geom type="sphere" size=".05" fromto="0 0 0 0 0 .1"/><site fromto="0 0 0 1 1 1"/></body>'),
    "mass, density, groups": _wrap(
        '<body><joint/><geom size=".1" mass="2"/><geom size=".1" mass="0"/><geom size=".1" group="4"/>'
        '<geom size=".2" group="2" density="10"/><geom type="plane" size="1 1 1" group="5"/></body>'
        '<geom type="plane" size="1 1 1"/>',
        head='<compiler inertiagrouprange="0 3" boundmass="0.5"/>'),
    "inertials, settotalmass, several trees": _wrap(
        '<body name="a"><freejoint name="f"/><inertial pos="0 0 .1" mass="2" diaginertia=".1 .2 .25" '
        'quat="1 1 0 0"/><geom size=".1"/><body><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body>'
        '</body><body name="b" pos="1 0 0"><joint type="free"/><geom size=".1"/></body>'
        '<body name="fixed"><geom size=".3"/><body><geom size=".1"/></body></body>',
        head='<compiler settotalmass="10" inertiafromgeom="auto"/><option gravity="0 0 -3"/>'),
    "inertiafromgeom true, welded bodies, limits": _wrap(
        '<body><joint type="slide" range="-.5 .5" limited="true" ref=".1"/><inertial pos="0 0 0" mass="5" '
        'diaginertia="1 1 1"/><geom size=".1"/><body pos="0 0 1"><geom type="box" size=".1 .2 .3"/>'
        '<site/></body><body><joint limited="false" range="1 2"/><geom size=".1"/></body></body>',
        head='<compiler inertiafromgeom="true" autolimits="true"/>'),
    "ignored elements, cameras, gravity off": _wrap(
        '<camera/><light/><body><joint name="j"/><geom size=".1"/><camera/><light/><plugin plugin="x"/></body>',
        head='<option><flag gravity="disable"/></option><size memory="1M"/><visual/><statistic/>'
             '<asset><texture name="t" builtin="checker"/><material name="m"/></asset>',
        tail='<actuator><motor joint="j"/></actuator><sensor><jointpos joint="j"/></sensor>'
             '<tendon><fixed><joint joint="j" coef="1"/></fixed></tendon><contact/><equality/><keyframe/>'
             '<custom/>'),
    "inline meshes, by faces and by their hull; a mesh class": _wrap(
        '<body pos="0 0 1"><joint/><geom type="mesh" mesh="tet" pos=".1 0 0" euler="0 30 0"/>'
        '<geom type="mesh" mesh="hull" mass="2"/><geom type="mesh" mesh="hull" class="big"/>'
        '<body><joint/><frame quat="0 1 0 0"><geom type="mesh" mesh="tet" density="10"/></frame></body></body>'
        '<geom type="mesh" mesh="unused"/>',
        head='<default><default class="big"><mesh scale="2 2 2"/><geom density="50"/></default></default>'
             '<asset><mesh name="tet" vertex="0 0 0 1 0 0 0 1 0 0 0 1" face="0 2 1 0 1 3 0 3 2 1 2 3"/>'
             '<mesh name="hull" inertia="convex" vertex="0 0 0 1 0 0 0 1 0 0 0 1 1 1 1"/>'
             '<mesh name="unused" class="big" vertex="0 0 0 1 0 0 0 1 0 0 0 2"/></asset>'),
    "text inside elements (a stray '>', a '-' after a tag)": _wrap(
        '<body>><joint/>-\n<geom size=".1"/>] ]]<!-- -->></body>text'),
    "more elements than the C parser of ElementTree takes": _wrap(
        '<body><joint/>' + '<geom size=".1"/>' * 1200 + '</body>'),
    "a body outside worldbody (ignored)": _wrap('<body><joint/><geom size=".1"/></body>',
                                                tail='<body name="x"><geom type="mesh" mesh="nowhere"/></body>'),
    "tendon armature zero, empty values": _wrap(
        '<body pos="" euler=""><joint name="j" axis="" armature=""/><geom size=".1" mass=""/></body>',
        tail='<tendon><fixed armature="0"><joint joint="j" coef="1"/></fixed></tendon>'),
}


@pytest.mark.parametrize("case", list(TAKEN))
def test_documents_it_reads_load_as_the_python_reader_loads_them(case: str) -> None:
    text = TAKEN[case]
    assert taken(text), "declined"
    fast, slow = outcome(text, fast=True), outcome(text, fast=False)
    assert fast[0] == "model", fast
    assert fast == slow


# documents the fast path declines (the Python reader reads them, or words why not)
DECLINED = {
    "include": '<mujoco><include file="/nonexistent/x.xml"/></mujoco>',
    "replicate": _wrap('<replicate count="2"><body><joint/><geom size=".1"/></body></replicate>'),
    "a missing mesh file": _wrap('<body><joint/><geom size=".1"/></body>',
                                 head='<asset><mesh name="m" file="/nonexistent/m.stl"/></asset>'),
    "a mesh face index out of range": _wrap('<body><joint/><geom type="mesh" mesh="m"/></body>',
                                            head='<asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1" '
                                                 'face="0 2 1 0 1 3 0 3 2 1 2 9"/></asset>'),
    "an unknown mesh": _wrap('<body><joint/><geom type="mesh" mesh="x"/></body>'),
    "a mesh reference frame": _wrap('<body><joint/><geom type="mesh" mesh="m"/></body>',
                                    head='<asset><mesh name="m" refpos="0 0 1" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>'
                                         '</asset>'),
    "shell": _wrap('<body><joint/><geom size=".1" shellinertia="true"/></body>'),
    "fullinertia": _wrap('<body><joint/><inertial pos="0 0 0" mass="1" fullinertia="1 1 1 0 0 0"/></body>'),
    "boundinertia": _wrap('<body><joint/><geom size=".1"/></body>', head='<compiler boundinertia="0.1"/>'),
    "balanceinertia": _wrap('<body><joint/><geom size=".1"/></body>', head='<compiler balanceinertia="true"/>'),
    "doctype": '<!DOCTYPE mujoco><mujoco/>',
    "entity reference": _wrap('<body name="a&amp;b"><joint/><geom size=".1"/></body>'),
    "character reference": _wrap('<body name="a&#65;"><joint/><geom size=".1"/></body>'),
    "cdata": _wrap('<body><![CDATA[x]]><joint/><geom size=".1"/></body>'),
    "processing instruction": _wrap('<?pi x?><body><joint/><geom size=".1"/></body>'),
    "namespace": '<mujoco xmlns:x="urn:x"><worldbody><x:body/></worldbody></mujoco>',
    "non-ASCII": _wrap('<body name="é"><joint/><geom size=".1"/></body>'),
    "text outside the root": _wrap('<body><joint/><geom size=".1"/></body>') + "x",
    "a reference in text": _wrap('<body>a &amp; b<joint/><geom size=".1"/></body>'),
    "]]> in text": _wrap('<body>a ]]> b<joint/><geom size=".1"/></body>'),
    "a control character in text": _wrap('<body>a \x02 b<joint/><geom size=".1"/></body>'),
    "unknown element": _wrap('<body><joint/><geom size=".1"/><gizmo/></body>'),
    "malformed": "<mujoco><worldbody></mujoco>",
    "unclosed": "<mujoco><worldbody>",
    "repeated attribute": '<mujoco model="a" model="b"/>',
    "unquoted attribute": "<mujoco model=a/>",
    "attributes not separated": '<mujoco><worldbody><body name="a"pos="0 0 0"/></worldbody></mujoco>',
    "two roots": "<mujoco/><mujoco/>",
    "declaration not first": " <?xml version='1.0'?><mujoco/>x",
    "bad declaration": "<?xml version='2.0'?><mujoco/>",
    "double hyphen in a comment": "<mujoco><!-- a -- b --></mujoco>",
    "control character": "<mujoco model='a\x01'/>",
    "a number it does not read": _wrap('<body pos="1e-400 0 0"><joint/><geom size=".1"/></body>'),
    "not a number": _wrap('<body pos="1 2 x"><joint/><geom size=".1"/></body>'),
    "a massless moving body": _wrap("<body><joint/></body>"),
    "nesting deeper than MAX_DEPTH": "<mujoco><worldbody>" + "<frame>" * 1000 + "</frame>" * 1000 + "</worldbody></mujoco>",
    "an attribute longer than MAX_ATTRIBUTE_LENGTH": _wrap('<body name="' + "a" * 10_001 + '"><joint/><geom size=".1"/></body>'),
}


@pytest.mark.parametrize("case", list(DECLINED))
def test_documents_it_declines_are_read_by_the_python_reader(case: str) -> None:
    text = DECLINED[case]
    if case == "a massless moving body":  # taken by the C++ reader, refused by the model's build: read again
        assert taken(text)
    else:
        assert not taken(text), "taken"
    assert outcome(text, fast=True) == outcome(text, fast=False)


@pytest.mark.parametrize("case", list(BAD))
def test_refusals_are_worded_as_the_python_reader_words_them(case: str) -> None:
    text = BAD[case][0]
    assert outcome(text, fast=True) == outcome(text, fast=False)


def test_strict_declines_what_it_would_ignore() -> None:
    text = TAKEN["ignored elements, cameras, gravity off"]
    assert taken(text) and not taken(text, strict=True)
    fast, slow = outcome(text, fast=True, strict=True), outcome(text, fast=False, strict=True)
    assert fast[0] == "error" and fast == slow
    clean = TAKEN["every orientation, degrees"]
    assert taken(clean, strict=True)
    assert outcome(clean, fast=True, strict=True) == outcome(clean, fast=False, strict=True)


def test_a_file_path_bytes_and_a_string_give_the_same_model(tmp_path: Path) -> None:
    text = TAKEN["default classes, childclass, frames"]
    path = tmp_path / "m.xml"
    path.write_text(text)
    by_path = outcome(path, fast=True)
    assert by_path == outcome(path, fast=False)
    assert by_path[1]["source"] == str(path)
    assert outcome(text.encode(), fast=True) == outcome(text.encode(), fast=False)


def test_mesh_files_found_as_the_python_reader_finds_them(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    cube = "".join(f"v {x} {y} {z}\n" for x in (0, 1) for y in (0, 2) for z in (0, 3))
    cube += "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\n" \
            "f 2 4 8\nf 2 8 6\n"
    (tmp_path / "parts" / "cube.obj").write_text(cube)
    text = _wrap('<body><joint/><geom type="mesh" mesh="cube"/><geom type="mesh" mesh="other" pos="1 0 0"/></body>',
                 head='<compiler meshdir="parts"/><asset><mesh file="cube.obj"/>'
                      '<mesh name="other" file="cube.obj" scale="1 1 .5" inertia="shell"/></asset>')
    path = tmp_path / "model.xml"
    path.write_text(text)
    assert taken(text, path=path)
    fast = outcome(path, fast=True)
    assert fast[0] == "model" and fast == outcome(path, fast=False)
    assert not taken(text)  # from another folder: the mesh file is not there, and the Python reader says so
    assert outcome(text, fast=True) == outcome(text, fast=False)


def test_errors_found_while_building_are_worded_with_the_line() -> None:
    text = "<mujoco>\n<worldbody>\n<body>\n<joint/>\n<body><freejoint/><geom size='.1'/></body>\n</body>\n" \
           "</worldbody>\n</mujoco>"
    assert taken(text)
    fast = outcome(text, fast=True)
    assert fast == outcome(text, fast=False)
    assert fast[0] == "error" and "line 5" in fast[2] and "top-level body" in fast[2]


def test_the_reader_refuses_a_wrong_call() -> None:
    assert mjcf._mjcf_native is not None
    with pytest.raises(TypeError):
        mjcf._mjcf_native.read(b"<mujoco/>", False)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        mjcf._mjcf_native.read("<mujoco/>")  # type: ignore[call-arg]


def test_reading_again_and_again_keeps_no_memory() -> None:
    import gc
    import tracemalloc

    assert mjcf._mjcf_native is not None
    text = TAKEN["inline meshes, by faces and by their hull; a mesh class"]
    files = mjcf._FastFiles(None)
    declined = DECLINED["a mesh face index out of range"]  # a callback that raises, then a decline

    def rounds(n: int) -> None:
        for _ in range(n):
            assert mjcf._mjcf_native.read(text, False, files) is not None
            assert mjcf._mjcf_native.read(declined, False, files) is None

    rounds(20)
    gc.collect()
    tracemalloc.start()
    try:
        rounds(20)
        gc.collect()
        before = tracemalloc.get_traced_memory()[0]
        rounds(300)
        gc.collect()
        grown = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    assert grown < 20_000, f"{grown} bytes kept after 300 rounds"


def test_threads_loading_at_once_get_each_their_model() -> None:
    from concurrent.futures import ThreadPoolExecutor

    texts = [TAKEN[k] for k in ("every orientation, degrees", "default classes, childclass, frames",
                                "inline meshes, by faces and by their hull; a mesh class", "fromto geoms and sites")]
    assert all(outcome(t, fast=True)[2] == [] for t in texts)  # (no warnings: the threads need not catch them)
    expected = [snapshot(fd.load_mjcf(t)) for t in texts]
    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(lambda k: snapshot(fd.load_mjcf(texts[k % 4])), range(64)))
    assert all(g == expected[k % 4] for k, g in enumerate(got))


def _files(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)


INCLUDED = {
    "defaults.xml": "<mujocoinclude><default><geom density='700'/><default class='leg'><joint axis='0 1 0'/>"
                    "</default></default></mujocoinclude>",
    "sub/legs.xml": "<mujoco model='ignored'><body name='leg' childclass='leg'><joint/><geom size='.1'/>"
                    "<include file='sub/foot.xml'/></body></mujoco>",
    "sub/foot.xml": "<?xml version='1.0'?>\n<!-- c --><mujoco><body name='foot' pos='0 0 -.3'><joint/>"
                    "<geom type='mesh' mesh='tet'/></body></mujoco>",
    "assets.xml": "<mujoco><asset><mesh name='tet' vertex='0 0 0 1 0 0 0 1 0 0 0 1' face='0 2 1 0 1 3 0 3 2 1 2 3'/>"
                  "</asset></mujoco>",
}


def test_included_files_are_read_as_the_python_reader_reads_them(tmp_path: Path) -> None:
    _files(tmp_path, INCLUDED)
    text = ("<mujoco model='m'><include file='defaults.xml'/><include file='assets.xml'/>"
            "<worldbody><body name='torso'><freejoint/><geom size='.2'/><include file='sub/legs.xml'/></body>"
            "<include file='empty.xml'/></worldbody></mujoco>")
    _files(tmp_path, {"main.xml": text, "empty.xml": "<mujoco/>"})
    path = tmp_path / "main.xml"
    assert taken(text, path=path)
    fast = outcome(path, fast=True)
    assert fast[0] == "model" and fast == outcome(path, fast=False)
    assert fast[1]["body_names"] == ("torso", "leg", "foot")


INCLUDE_DECLINED = {
    "a cycle": {"main.xml": "<mujoco><include file='a.xml'/></mujoco>",
                "a.xml": "<mujoco><include file='main.xml'/></mujoco>"},
    "a file included twice": {"main.xml": "<mujoco><include file='a.xml'/><include file='b.xml'/></mujoco>",
                              "a.xml": "<mujoco><include file='b.xml'/></mujoco>", "b.xml": "<mujoco/>"},
    "a missing file": {"main.xml": "<mujoco><include file='nowhere.xml'/></mujoco>"},
    "no file attribute": {"main.xml": "<mujoco><include file=' '/></mujoco>"},
    "an include with children": {"main.xml": "<mujoco><include file='a.xml'><size/></include></mujoco>",
                                 "a.xml": "<mujoco/>"},
    "another root": {"main.xml": "<mujoco><include file='a.xml'/></mujoco>", "a.xml": "<robot name='r'/>"},
    "a malformed included file": {"main.xml": "<mujoco><include file='a.xml'/></mujoco>", "a.xml": "<mujoco>"},
    "a non-ASCII included file": {"main.xml": "<mujoco><include file='a.xml'/></mujoco>",
                                  "a.xml": "<mujoco><!-- é --></mujoco>"},
    "too deep": {"main.xml": "<mujoco><include file='f0.xml'/></mujoco>",
                 **{f"f{k}.xml": f"<mujoco><include file='f{k + 1}.xml'/></mujoco>" for k in range(25)},
                 "f25.xml": "<mujoco/>"},
    "a replicate in an included file": {"main.xml": "<mujoco><worldbody><include file='a.xml'/></worldbody></mujoco>",
                                        "a.xml": "<mujoco><replicate count='2'><body><joint/><geom size='.1'/></body>"
                                                 "</replicate></mujoco>"},
}


@pytest.mark.parametrize("case", list(INCLUDE_DECLINED))
def test_includes_it_declines_are_read_by_the_python_reader(case: str, tmp_path: Path) -> None:
    files = INCLUDE_DECLINED[case]
    _files(tmp_path, files)
    path = tmp_path / "main.xml"
    assert not taken(files["main.xml"], path=path), "taken"
    assert outcome(path, fast=True) == outcome(path, fast=False)
