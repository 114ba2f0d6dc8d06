"""featherdyn.load_mjcf against MuJoCo's own compiler, on hand-written snippets and on every MJCF model installed.

Each model is compiled by ``mujoco`` and loaded by featherdyn; ``_mjcf_oracle.compare``
checks joint layout, total mass, armature, per-body inertia, body and site
placements, ``M(q)``, gravity torques and RNEA (both backends) at random
states, all to :data:`RTOL` relative to MuJoCo's largest entry. Nothing here
comes from featherdyn's own numbers: the expected values are MuJoCo's.
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd

mujoco = pytest.importorskip("mujoco")
from _mjcf_oracle import compare, full_mass_matrix  # noqa: E402

RTOL = 1e-9

_BOX_ARM = """
<mujoco model="{name}">
  {compiler}
  {option}
  <default>
    <joint armature="0.05"/>
    <geom density="500"/>
    <default class="heavy"><geom density="3000"/><joint armature="0.2"/>
      <default class="heavier"><geom density="5000"/></default>
    </default>
  </default>
  <worldbody>
    {body}
  </worldbody>
</mujoco>
"""

SNIPPETS: dict[str, str] = {
    "hinge chain, degrees, euler": """
      <body name="a" pos="0 0 1" euler="10 20 30">
        <joint name="j1" axis="0 1 0" range="-90 45"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0.1" size="0.05"/>
        <body name="b" pos="0.3 0 0.1" euler="-30 5 60">
          <joint name="j2" axis="1 1 0" pos="0.05 0 0" ref="30"/>
          <geom type="box" size="0.1 0.05 0.02" pos="0.1 0 0" quat="0.9 0.1 0.3 0.2"/>
        </body>
      </body>""",
    "radian, axisangle, xyaxes, zaxis": """
      <body name="a" pos="0.1 0.2 0.3" axisangle="1 2 3 0.7">
        <joint axis="0 0 1"/>
        <geom type="ellipsoid" size="0.1 0.2 0.3" xyaxes="1 1 0 -1 2 0"/>
        <body pos="0 0 0.4" zaxis="0.3 -0.2 1">
          <joint type="slide" axis="1 0 0" ref="0.2"/>
          <geom type="cylinder" size="0.05 0.2" zaxis="1 0 0"/>
          <site name="tip" pos="0 0 0.3" xyaxes="0 1 0 -1 0 0"/>
        </body>
      </body>""",
    "eulerseq extrinsic": """
      <body pos="0 0 1" euler="30 60 -45"><joint axis="1 0 0"/><geom type="box" size=".1 .2 .3" euler="10 -20 70"/>
      <site pos=".1 .2 .3" euler="5 15 25"/></body>""",
    "inertial diaginertia quat, fullinertia": """
      <body name="a"><joint axis="0 1 0"/>
        <inertial pos="0.1 0.2 -0.1" quat="0.5 0.5 -0.5 0.5" mass="2" diaginertia="0.1 0.2 0.25"/>
        <geom size="0.1"/>
        <body name="b" pos="0.5 0 0"><joint type="ball"/>
          <inertial pos="0 0.1 0" mass="1.5" fullinertia="0.3 0.4 0.5 0.01 -0.02 0.03"/>
        </body>
      </body>""",
    "ball and free, several trees, static bodies": """
      <body name="floor_block" pos="1 1 0"><geom type="box" size=".5 .5 .1"/></body>
      <body name="base" pos="0 0 1" quat="0.8 0 0.6 0"><freejoint/>
        <geom type="box" size=".2 .1 .05"/>
        <body name="leg" pos="0.2 0 0"><joint type="ball" pos="0 0 0.05"/><geom type="capsule" fromto="0 0 0 0 0 -.4" size=".03"/>
          <body name="foot" pos="0 0 -0.4"><geom type="sphere" size=".05" pos=".02 0 0"/></body>
        </body>
      </body>
      <body name="second" pos="-1 0 0.5"><joint name="free2" type="free" armature="0"/><geom type="cylinder" size=".1 .3"/></body>
      <body name="pend" pos="0 2 1"><joint axis="1 0 0"/><geom type="capsule" fromto="0 0 0 0 0 -1" size=".05"/></body>""",
    "several joints on one body": """
      <body name="a" pos="0 0 1">
        <joint name="x" type="slide" axis="1 0 0"/>
        <joint name="z" type="slide" axis="0 0 1" ref="0.3"/>
        <joint name="r" axis="0 1 0" pos="0.1 0 0.05" ref="-20"/>
        <joint axis="1 0 0" pos="0 0.2 0"/>
        <geom type="box" size=".2 .1 .05" pos=".1 .05 0"/>
        <site name="s" pos=".3 0 0"/>
        <body name="b" pos="0.4 0 0">
          <joint type="ball" pos="0.05 0.02 0"/>
          <joint type="slide" axis="0 1 1"/>
          <geom type="sphere" size=".1"/>
        </body>
      </body>""",
    "default classes and childclass": """
      <body name="a" childclass="heavy"><joint axis="0 0 1"/><geom size=".1" pos=".2 0 0"/>
        <geom class="main" size=".1" pos="-.2 0 0"/>
        <body name="b" pos=".5 0 0" childclass="heavier"><joint axis="0 1 0"/><geom type="box" size=".1 .1 .1"/>
          <body name="c" pos=".5 0 0"><joint class="main" axis="1 0 0"/><geom class="heavy" size=".05"/></body>
        </body>
      </body>""",
    "frames": """
      <frame pos="0 0 1" euler="0 0 90">
        <body name="a" pos="1 0 0"><joint axis="1 0 0"/>
          <frame pos="0.2 0 0" euler="90 0 0">
            <geom type="capsule" fromto="0 0 0 0 0 .3" size=".04"/>
            <site name="fs" pos="0 0 .3"/>
            <joint axis="0 1 0" pos="0 0 .1"/>
            <body name="b" pos="0 0 .3"><joint axis="0 0 1"/><geom size=".05"/></body>
          </frame>
        </body>
      </frame>""",
    "geom mass, density, shellinertia, groups, contype": """
      <body name="a"><joint axis="0 0 1"/>
        <geom type="sphere" size=".1" mass="2" pos=".1 0 0"/>
        <geom type="box" size=".1 .2 .3" shellinertia="true" pos="0 .3 0"/>
        <geom type="cylinder" size=".1 .2" shellinertia="true" density="20" pos="0 0 .3"/>
        <geom type="capsule" size=".1 .2" shellinertia="true" pos="0 0 -.3" euler="10 20 30"/>
        <geom type="sphere" size=".2" shellinertia="true" pos="0 -.3 0"/>
        <geom type="sphere" size=".2" contype="0" conaffinity="0" pos="0.3 -.3 0"/>
        <geom type="ellipsoid" size=".1 .2 .15" group="3" pos="0.3 -.3 0.2"/>
        <geom type="box" size=".1 .1 .1" mass="0"/>
      </body>""",
    "replicate": """
      <replicate count="3" offset="1 0 0" euler="0 0 30" sep="-">
        <body name="b" pos="0 1 0"><joint name="j" axis="0 1 0"/><geom size=".1"/><site name="s" pos=".1 0 0"/></body>
      </replicate>
      <replicate count="11" offset="0 0 1" euler="10 0 0">
        <body name="c"><joint/><geom type="box" size=".1 .2 .1"/>
          <replicate count="2" euler="0 0 90"><body name="d" pos="1 0 0"><joint type="slide"/><geom size=".1"/></body>
          </replicate>
        </body>
      </replicate>""",
    # measured: an empty number is not read (the class's value stays: armature 0.05 / 0.2, density 5000), an
    # empty orientation is the identity, and a zero pos may accompany fromto (brax's test models)
    "empty numbers, zero pos with fromto": """
      <body name="a" pos=""><joint axis="0 1 0" ref="" armature=""/>
        <geom type="capsule" fromto="0 0 0 .3 0 0" pos="0 0 0" size=".05"/>
        <geom type="box" size=".1 .1 .1" mass="" pos=".2 0 0" quat=""/>
        <body name="b" pos=".5 0 0" euler="" childclass="heavier"><joint axis="1 0 0" armature="" range=""/>
          <geom type="sphere" size=".1" density=""/>
          <geom type="cylinder" size=".05 .1" fromto="0 0 0 0 0 .2" pos="-0 0 0"/>
        </body>
      </body>""",
}

_COMPILERS = {
    "replicate": "",
    "hinge chain, degrees, euler": "",
    "radian, axisangle, xyaxes, zaxis": '<compiler angle="radian"/>',
    "eulerseq extrinsic": '<compiler eulerseq="ZYX"/>',
    "inertial diaginertia quat, fullinertia": "",
    "ball and free, several trees, static bodies": "",
    "several joints on one body": "",
    "default classes and childclass": "",
    "frames": "",
    "geom mass, density, shellinertia, groups, contype": "",
    "empty numbers, zero pos with fromto": "",
}

COMPILER_VARIANTS = {
    "inertiafromgeom true": '<compiler inertiafromgeom="true"/>',
    "inertiagrouprange": '<compiler inertiagrouprange="0 2"/>',
    "boundmass boundinertia": '<compiler boundmass="3" boundinertia="0.5"/>',
    "balanceinertia": '<compiler balanceinertia="true"/>',
    "eulerseq zxy": '<compiler eulerseq="zxy"/>',
}

_VARIANT_BODY = """
  <body name="a" euler="10 20 30"><joint axis="0 0 1"/>
    <inertial pos="0 0 0.1" mass="0.5" diaginertia="0.01 0.02 0.025"/>
    <geom type="box" size=".1 .2 .3" euler="5 6 7"/><geom type="sphere" size=".1" group="4" pos=".3 0 0"/>
    <body name="b" pos=".4 0 0"><joint axis="0 1 0"/><geom type="sphere" size=".01"/>
      <body name="c" pos=".1 0 0"><joint type="slide" axis="1 0 0"/><site name="only"/>{massless}</body>
      <body name="d" pos=".1 0 0"><joint type="slide" axis="0 0 1"/>
        <inertial pos="0 0 0" mass="0.2" diaginertia="0.001 0.002 0.0025"/></body>
    </body>
  </body>"""


#: Meshes: MuJoCo stores a mesh geom in its principal frame, found by an iterative eigensolver
#: (``mjuu_eig3``) whose residual reaches ~1e-9 relative on nearly symmetric inertias; featherdyn keeps
#: the tensor (no eigendecomposition), so the two differ by that residual.
MESH_RTOL = 1e-8


def _check(xml: str, name: str, tmp: Path | None = None, rtol: float = RTOL) -> None:
    m = mujoco.MjModel.from_xml_string(xml) if tmp is None else mujoco.MjModel.from_xml_path(str(tmp))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_mjcf(xml if tmp is None else tmp)
    errs = compare(model, m, samples=2)
    bad = {k: v for k, v in errs.worst.items() if not v <= rtol}
    assert not bad, f"{name}: relative errors above {rtol:g} against MuJoCo: {bad}"


@pytest.mark.parametrize("name", list(SNIPPETS))
def test_snippet_matches_mujoco(name: str) -> None:
    _check(_BOX_ARM.format(name="snippet", compiler=_COMPILERS[name], option="", body=SNIPPETS[name]), name)


@pytest.mark.parametrize("name", list(COMPILER_VARIANTS))
def test_compiler_option_matches_mujoco(name: str) -> None:
    body = _VARIANT_BODY.replace("{massless}", '<geom size=".02"/>')
    if name == "balanceinertia":
        body = body.replace('diaginertia="0.01 0.02 0.025"', 'diaginertia="0.01 0.01 0.05"')
    _check(_BOX_ARM.format(name="variant", compiler=COMPILER_VARIANTS[name], option="", body=body), name)


def test_inertiafromgeom_false_and_settotalmass() -> None:
    body = SNIPPETS["inertial diaginertia quat, fullinertia"]
    _check(_BOX_ARM.format(name="x", compiler='<compiler inertiafromgeom="false"/>', option="", body=body), "false")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # MuJoCo deprecates settotalmass (prints a warning)
        _check(_BOX_ARM.format(name="x", compiler='<compiler settotalmass="7.5"/>', option="",
                               body=SNIPPETS["ball and free, several trees, static bodies"]), "settotalmass")


@pytest.mark.parametrize("option", ['<option gravity="1 -2 -5"/>', '<option><flag gravity="disable"/></option>'])
def test_gravity_option_matches_mujoco(option: str) -> None:
    _check(_BOX_ARM.format(name="g", compiler="", option=option, body=SNIPPETS["hinge chain, degrees, euler"]), option)


def test_include_matches_mujoco(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "arm.xml").write_text(
        "<mujoco><body name='inc' pos='0 0 1'><joint axis='0 1 0'/><geom type='capsule' size='.05 .2'/>"
        "</body></mujoco>")
    (tmp_path / "defaults.xml").write_text("<mujoco><default><joint armature='0.3'/></default></mujoco>")
    main = tmp_path / "main.xml"
    main.write_text("<mujoco><include file='defaults.xml'/><worldbody><include file='parts/arm.xml'/>"
                    "</worldbody></mujoco>")
    _check("", "include", main)


def _installed_models() -> list[Path]:
    """The MJCF models shipped in mujoco, gymnasium (test extras) and dm_control (when installed) that MuJoCo
    compiles on their own (asset-only fragments are not models; docs/mjcf-models.md lists them)."""
    found = []
    for package, sub in (("mujoco", "testdata"), ("gymnasium", "envs/mujoco/assets"), ("dm_control", "suite")):
        spec = importlib.util.find_spec(package)
        if spec is None or spec.origin is None:
            continue
        for path in sorted((Path(spec.origin).parent / sub).glob("*.xml")):
            try:
                mujoco.MjModel.from_xml_path(str(path))
            except ValueError:
                continue
            found.append(path)
    return found


INSTALLED = _installed_models()


def test_the_installed_models_are_found() -> None:
    """gymnasium is a test dependency: its 14 models at least (an empty list would make the test below vacuous)."""
    assert sum(p.parent.name == "assets" for p in INSTALLED) >= 14, INSTALLED


@pytest.mark.parametrize("path", INSTALLED, ids=[f"{p.parent.name}/{p.name}" for p in INSTALLED])
def test_installed_model_matches_mujoco(path: Path) -> None:
    m = mujoco.MjModel.from_xml_path(str(path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_mjcf(path)
    errs = compare(model, m, samples=2)
    bad = {k: v for k, v in errs.worst.items() if not v <= RTOL}
    assert not bad, f"{path.name}: relative errors above {RTOL:g} against MuJoCo: {bad}"


def test_converters_round_trip_on_a_model_with_every_joint_type() -> None:
    from featherdyn import conventions as conv

    xml = _BOX_ARM.format(name="rt", compiler="", option="", body=SNIPPETS["ball and free, several trees, static bodies"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_mjcf(xml)
    rng = np.random.default_rng(5)
    q = fd.random_configuration(model, rng, size=(3,))
    v, a = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    qpos = conv.q_to_mujoco(model, q)
    np.testing.assert_allclose(conv.q_from_mujoco(model, qpos), q, rtol=0, atol=1e-15)
    qvel = conv.v_to_mujoco(model, q, v)
    np.testing.assert_allclose(conv.v_from_mujoco(model, qpos, qvel), v, rtol=0, atol=1e-14)
    qacc = conv.a_to_mujoco(model, q, v, a)
    np.testing.assert_allclose(conv.a_from_mujoco(model, qpos, qvel, qacc), a, rtol=0, atol=1e-14)
    tau = rng.normal(size=(3, model.nv))
    np.testing.assert_allclose(conv.tau_from_mujoco(model, qpos, conv.tau_to_mujoco(model, q, tau)), tau, atol=1e-14)
    M = fd.crba(model, q)
    np.testing.assert_allclose(conv.joint_matrix_from_mujoco(model, qpos, conv.joint_matrix_to_mujoco(model, q, M)), M,
                               atol=1e-13)
    # MuJoCo's own integration agrees with the velocity conversion: qpos(t + h) ≈ integrate(q, v h)
    # (MuJoCo moves a free body along a straight line, featherdyn along the screw of exp: equal to first order)
    m = mujoco.MjModel.from_xml_string(xml)
    h = 1e-7
    for k in range(3):
        nxt = qpos[k].copy()
        mujoco.mj_integratePos(m, nxt, qvel[k], h)
        ours = conv.q_to_mujoco(model, fd.integrate(model, q[k], v[k] * h))
        np.testing.assert_allclose((ours - qpos[k]) / h, (nxt - qpos[k]) / h, rtol=0, atol=1e-5)


# --------------------------------------------------------------------------- meshes

# an L-shaped prism (not convex), closed and outward-oriented; vertices off the float32 grid on purpose
_L = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]


def _l_prism() -> tuple[np.ndarray, np.ndarray]:
    V = np.array([(x * 0.13 + 0.01, y * 0.17 - 0.02, 0.0) for x, y in _L]
                 + [(x * 0.13 + 0.01, y * 0.17 - 0.02, 0.11) for x, y in _L])
    F = []
    for a, b, c in [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]:
        F += [(c, b, a), (a + 6, b + 6, c + 6)]
    for i in range(6):
        j = (i + 1) % 6
        F += [(i, j, j + 6), (i, j + 6, i + 6)]
    return V, np.array(F)


def _write_meshes(folder: Path) -> None:
    import struct

    V, F = _l_prism()
    with open(folder / "l.stl", "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(F)))
        for t in F:
            f.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *V[k]) for k in t) + b"\0\0")
    with open(folder / "l.obj", "w") as f:
        f.write("# L prism, quads on the sides\n")
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
        for a, b, c in [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]:
            f.write(f"f {c + 1}/1 {b + 1}/1 {a + 1}/1\nf {a + 7} {b + 7} {c + 7}\n")
        for i in range(6):
            j = (i + 1) % 6
            f.write(f"f {i + 1}//1 {j + 1}//1 {j + 7}//1 {i + 7}//1\n")
    with open(folder / "l.msh", "wb") as f:
        f.write(struct.pack("<4i", len(V), 0, 0, len(F)))
        f.write(V.astype("<f4").tobytes() + F.astype("<i4").tobytes())
    # an open surface (the L prism without its top): "legacy" and "exact" differ there
    with open(folder / "open.obj", "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F.tolist() if not (a >= 6 and b >= 6 and c >= 6))


@pytest.mark.parametrize("mode", ["", 'inertia="exact"', 'inertia="shell"', 'inertia="legacy"', 'inertia="convex"'])
@pytest.mark.parametrize("file", ["l.stl", "l.obj", "l.msh", "open.obj"])
def test_mesh_inertia_matches_mujoco(tmp_path: Path, file: str, mode: str) -> None:
    (tmp_path / "meshes").mkdir()
    _write_meshes(tmp_path / "meshes")
    xml = f"""<mujoco><compiler meshdir="meshes"/>
      <asset><mesh name="m" file="{file}" scale="1 1.5 0.7" {mode}/>
        <mesh name="inline" vertex="0 0 0  1 0 0  0 1 0  0 0 1.3" face="0 2 1  0 1 3  0 3 2  1 2 3"/>
        <mesh name="cloud" scale=".05 .05 .05" vertex="0 1 1.618 0 -1 1.618 0 1 -1.618 0 -1 -1.618 1 1.618 0
          -1 1.618 0 1 -1.618 0 -1 -1.618 0 1.618 0 1 1.618 0 -1 -1.618 0 1 -1.618 0 -1 0.1 0.2 0.3"/></asset>
      <worldbody><body name="a" euler="10 20 30"><joint axis="0 1 0"/>
        <geom type="mesh" mesh="m" pos=".1 .2 .3" euler="30 40 50" density="700"/>
        <body name="b" pos="0.5 0 0"><joint axis="1 0 0"/><geom type="mesh" mesh="m" mass="2.5"/>
          <geom type="mesh" mesh="inline" pos="0 .1 0"/><geom type="mesh" mesh="cloud" pos=".3 0 0"/></body>
      </body></worldbody></mujoco>"""
    main = tmp_path / "model.xml"
    main.write_text(xml)
    _check("", f"mesh {file} {mode}", main, MESH_RTOL)


def test_free_joint_armature_differs_from_mujoco_exactly_as_documented() -> None:
    """MuJoCo adds ``armature · qacc`` in its coordinates; featherdyn ``armature · v̇`` in its own::

        Tᵀ τ_featherdyn − τ_mujoco = armature · [−R (ω_b × v_b); 0]     (M and gravity agree)
    """
    from featherdyn import conventions as conv

    xml = ('<mujoco><worldbody><body pos="0 0 1"><joint type="free" armature="0.7"/>'
           '<geom type="box" size=".2 .1 .05" pos=".1 0 0"/></body></worldbody></mujoco>')
    m = mujoco.MjModel.from_xml_string(xml)
    model = fd.load_mjcf(xml)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(2)
    q = fd.random_configuration(model, rng)
    qpos, qvel, qacc = conv.q_to_mujoco(model, q), rng.normal(size=6), rng.normal(size=6)
    d.qpos[:], d.qvel[:] = qpos, qvel
    mujoco.mj_forward(m, d)

    tau_mj = d.qfrc_bias + full_mass_matrix(m, d) @ qacc
    v, a = conv.v_from_mujoco(model, qpos, qvel), conv.a_from_mujoco(model, qpos, qvel, qacc)
    tau = conv.tau_to_mujoco(model, q, fd.rnea(model, q, v, a))
    R = d.xmat[1].reshape(3, 3)
    expected = 0.7 * np.concatenate([-R @ np.cross(v[:3], v[3:]), np.zeros(3)])
    np.testing.assert_allclose(tau - tau_mj, expected, rtol=0, atol=1e-12 * np.abs(tau_mj).max())


def test_mujocoinclude_roots_and_bodies_outside_the_worldbody_as_mujoco(tmp_path: Path) -> None:
    """Two things MuJoCo reads that the survey found in public models (adroit, fetch): an included file whose root
    is the older <mujocoinclude>, and a <body> directly under <mujoco> (MuJoCo ignores it; featherdyn too, with the
    ignored-elements warning, and refuses it with strict=True)."""
    (tmp_path / "arm.xml").write_text(
        '<mujocoinclude><body name="a" pos="0 0 1"><joint name="j" axis="0 1 0"/>'
        '<geom type="capsule" fromto="0 0 0 .3 0 0" size=".04"/></body></mujocoinclude>')
    main = tmp_path / "main.xml"
    main.write_text('<mujoco><body name="stray"><geom size=".1"/></body>'
                    '<worldbody><include file="arm.xml"/></worldbody></mujoco>')
    with pytest.warns(fd.PhysicalityWarning, match="body \\(outside <worldbody>\\)"):
        model = fd.load_mjcf(main)
    assert model.joint_names == ("j",) and "stray" not in model.body_names
    _check("", "mujocoinclude", main)
    with pytest.raises(fd.MJCFError, match="outside <worldbody>"):
        fd.load_mjcf(main, strict=True)


@pytest.mark.parametrize(("child", "compiles"), [("", True), ('<joint axis="0 0 1"/>', False)],
                         ids=["welded-massive-child", "jointed-child"])
def test_a_massless_moving_body_is_judged_with_its_welded_descendants(child: str, compiles: bool) -> None:
    """MuJoCo's mjMINVAL rule looks at a moving body with the bodies welded to it (robosuite's omron base)."""
    xml = ('<mujoco><worldbody><body name="a"><joint type="slide" axis="1 0 0"/>'
           '<inertial pos="0 0 0" mass="0" diaginertia="0 0 0"/>'
           f'<body name="b" pos=".2 0 0">{child}<geom size=".1"/></body></body></worldbody></mujoco>')
    if compiles:
        _check(xml, "massless body, massive welded child")
        return
    with pytest.raises(ValueError, match="mjMINVAL"):
        mujoco.MjModel.from_xml_string(xml)
    with pytest.raises(fd.MJCFError, match="mjMINVAL"):
        fd.load_mjcf(xml)


def test_tendon_armature_is_refused_because_mujoco_adds_it_to_m_with_couplings() -> None:
    """The measurement behind the refusal: a fixed tendon of coefficients c adds ``armature · c cᵀ`` to MuJoCo's
    M (off-diagonal terms, no joint armature can stand for it); without armature the tendon changes nothing."""
    xml = """<mujoco><worldbody><body><joint name="j1" type="slide" axis="0 0 1"/><joint name="j2" axis="0 1 0"/>
      <geom type="box" size=".1 .1 .1" mass="1" pos="1 0 0"/></body></worldbody>
      <tendon><fixed armature="{a}"><joint joint="j1" coef="1"/><joint joint="j2" coef="0.5"/></fixed></tendon>
    </mujoco>"""
    with_arm, without = (mujoco.MjModel.from_xml_string(xml.format(a=a)) for a in (2, 0))
    Ms = []
    for m in (with_arm, without):
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        Ms.append(full_mass_matrix(m, d))
    c = np.array([1.0, 0.5])
    np.testing.assert_allclose(Ms[0] - Ms[1], 2 * np.outer(c, c), rtol=0, atol=1e-12)
    with pytest.raises(fd.errors.MJCFError, match="tendon's armature"):
        fd.load_mjcf(xml.format(a=2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_mjcf(xml.format(a=0))
    errs = compare(model, without, samples=2)
    assert all(v <= RTOL for v in errs.worst.values()), errs.worst
