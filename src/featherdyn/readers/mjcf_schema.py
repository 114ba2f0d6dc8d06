"""The names an MJCF document may use: each element, where it may sit, and its attributes (MuJoCo's schema).

MuJoCo's compiler refuses an element or attribute its schema does not know
("Schema violation: unrecognized attribute: 'axsi'"); featherdyn's reader
does the same (:func:`check_names`), naming the file, the line and the
nearest valid name, so that a typo cannot pass silently.

The table (:data:`ATTRIBUTES`) holds facts, not code: the union of the schema
``mujoco`` 4.0.0 prints (``mujoco.mj_printSchema``) and the elements and
attributes MuJoCo's XML reference documents (``doc/XMLreference.rst`` of the
3.x series, which adds ``<frame>``, ``<replicate>``, ``<composite>`` and a few
attributes 4.0 dropped): a model either series accepts keeps loading. Each
entry is ``"context/name"``: the element ``name`` as a child of an element of
kind ``context`` — a ``<worldbody>``, ``<frame>`` and ``<replicate>`` hold what
a ``<body>`` holds, a nested ``<default>`` what the top-level one holds.

Where MuJoCo does not look, featherdyn warns instead of refusing: MuJoCo's
schema check skips ``<frame>`` and ``<replicate>`` and everything inside them
(an unknown attribute there is ignored by MuJoCo, measured with ``mujoco``
4.0), so an unknown attribute there is a
:class:`~featherdyn.PhysicalityWarning` (one per file, listing each), an
error with ``strict=True``; an unknown element is refused everywhere, as
MuJoCo's reader refuses one inside a frame. The subtrees of ``<composite>``,
``<flexcomp>`` and ``<attach>`` are not looked into: the loader refuses those
elements whole. ``<include>`` elements are expanded before the check (an
included file's names are checked in place).
"""

from __future__ import annotations

import difflib
import functools
import warnings
from typing import Any

from ..errors import PhysicalityWarning
from .mjcf_xml import Doc
from .xml import quote, shorten

__all__ = ["ATTRIBUTES", "check_names"]

#: The attributes of each element an MJCF document may hold, by ``"context/name"`` (module doc).
ATTRIBUTES: dict[str, str] = {
    "actuator/adhesion": "body class ctrlrange delay forcelimited forcerange gain group interp name nsample user",
    "actuator/cylinder": (
        "area armature bias class cranklength cranksite ctrllimited ctrlrange damping delay diameter forcelimited "
        "forcerange gear group interp joint jointinparent lengthrange name nsample refsite site slidersite tendon "
        "timeconst user"),
    "actuator/damper": (
        "armature class cranklength cranksite ctrlrange damping delay forcelimited forcerange gear group interp joint "
        "jointinparent kv lengthrange name nsample refsite site slidersite tendon user"),
    "actuator/dcmotor": (
        "armature class cogging controller cranklength cranksite ctrllimited ctrlrange damping delay gear group "
        "inductance input interp joint jointinparent lengthrange lugre motorconst name nominal nsample refsite "
        "resistance saturation site slidersite tendon thermal user"),
    "actuator/general": (
        "actdim actearly actlimited actrange armature biasprm biastype body class cranklength cranksite ctrllimited "
        "ctrlrange damping delay dynprm dyntype ffrange forcelimited forcerange gainprm gaintype gear group "
        "inheritrange input interp joint jointinparent lengthrange name nsample refsite site slidersite tendon user "
        "velrange"),
    "actuator/intvelocity": (
        "actlimited actrange armature class cranklength cranksite ctrllimited ctrlrange damping dampratio delay "
        "forcelimited forcerange gear group inheritrange interp joint jointinparent kp kv lengthrange name nsample "
        "refsite site slidersite tendon user"),
    "actuator/motor": (
        "armature class cranklength cranksite ctrllimited ctrlrange damping delay forcelimited forcerange gear group "
        "interp joint jointinparent lengthrange name nsample refsite site slidersite tendon user"),
    "actuator/muscle": (
        "armature class cranklength cranksite ctrllimited ctrlrange damping delay force forcelimited forcerange fpmax "
        "fvmax gear group interp joint jointinparent lengthrange lmax lmin name nsample range scale slidersite "
        "tausmooth tendon timeconst user vmax"),
    "actuator/orientation": (
        "class ctrlrange dampratio delay forcelimited forcerange group input interp joint kp kv name nsample refsite "
        "site user"),
    "actuator/pid": (
        "armature class cranklength cranksite ctrllimited ctrlrange damping dampratio delay ffrange forcelimited "
        "forcerange gear group imax inheritrange input interp joint jointinparent ki kp kv lengthrange name nsample "
        "posrange refsite site slewmax slidersite tendon user velrange"),
    "actuator/plugin": (
        "actdim actearly actlimited actrange armature class cranklength cranksite ctrllimited ctrlrange damping delay "
        "dynprm dyntype forcelimited forcerange gear group instance interp joint jointinparent lengthrange name "
        "nsample plugin site slidersite tendon user"),
    "actuator/position": (
        "armature class cranklength cranksite ctrllimited ctrlrange damping dampratio delay forcelimited forcerange "
        "gear group inheritrange interp joint jointinparent kp kv lengthrange name nsample refsite site slidersite "
        "tendon timeconst user"),
    "actuator/velocity": (
        "armature class cranklength cranksite ctrllimited ctrlrange damping delay forcelimited forcerange gear group "
        "interp joint jointinparent kv lengthrange name nsample refsite site slidersite tendon user"),
    "asset/hfield": "content_type elevation file name ncol nrow size",
    "asset/material": (
        "class emission metallic name reflectance rgba roughness shininess specular texrepeat texture texuniform"),
    "asset/mesh": (
        "builtin class content_type face file inertia material maxhullvert name normal params refpos refquat scale "
        "smoothnormal texcoord vertex"),
    "asset/model": "content_type file name",
    "asset/skin": "face file group inflate material name rgba texcoord vertex",
    "asset/texture": (
        "builtin class colorspace content_type embed file fileback filedown filefront fileleft fileright fileup "
        "gridlayout gridsize height hflip mark markrgb name nchannel random rgb1 rgb2 type vflip width"),
    "body/attach": "body frame model prefix",
    "body/body": "axisangle childclass euler fuse gravcomp mocap name pos quat simple sleep user xyaxes zaxis",
    "body/camera": (
        "axisangle class euler focal focalpixel fovy ipd mode name output pos principal principalpixel projection "
        "quat resolution sensorsize target user xyaxes zaxis"),
    "body/composite": "count curve initial offset prefix quat size type vertex",
    "body/flexcomp": (
        "axisangle cellcount count dim dof element euler file flatskin group inertiabox mass material mesh name "
        "origin point pos quat radius rgba rigid scale spacing texcoord type xyaxes zaxis"),
    "body/frame": "axisangle childclass euler name pos quat xyaxes zaxis",
    "body/freejoint": "align group name",
    "body/geom": (
        "adhesion axisangle castshadow class conaffinity condim contype density euler fitscale fluidcoef fluidshape "
        "friction fromto gap group hfield margin mass material mesh name pos priority quat rgba shellinertia size "
        "solimp solmix solref surfacevel type user xyaxes zaxis"),
    "body/inertial": "axisangle diaginertia euler fullinertia mass pos quat xyaxes zaxis",
    "body/joint": (
        "actuatorfrclimited actuatorfrcrange actuatorgravcomp armature axis class damping frictionloss group limited "
        "margin name pos range ref solimpfriction solimplimit solreffriction solreflimit springdamper springref "
        "springyield stiffness type user"),
    "body/light": (
        "active ambient attenuation bulbradius castshadow class cutoff diffuse dir directional exponent intensity "
        "mode name pos range softness specular target texture type"),
    "body/plugin": "instance plugin",
    "body/replicate": "childclass count euler offset sep",  # childclass: read by MuJoCo's reader, undocumented
    "body/site": "axisangle class euler fromto group material mesh name pos quat rgba size type user xyaxes zaxis",
    "compiler/lengthrange": "accel interval inttotal maxforce mode timeconst timestep tolrange useexisting uselimit",
    "composite/geom": "",
    "composite/joint": "kind solimpfix solreffix",
    "composite/plugin": "instance plugin",
    "composite/site": "group material rgba size",
    "composite/skin": "group inflate material rgba subgrid texcoord",
    "contact/exclude": "body1 body2 name",
    "contact/pair": "adhesion class condim friction gap geom1 geom2 margin name solimp solref solreffriction",
    "custom/numeric": "data name size",
    "custom/text": "data name",
    "custom/tuple": "name",
    "default/adhesion": "ctrlrange delay forcelimited forcerange gain group interp nsample user",
    "default/camera": (
        "axisangle euler focal focalpixel fovy ipd mode output pos principal principalpixel projection quat "
        "resolution sensorsize user xyaxes zaxis"),
    "default/cylinder": (
        "area armature bias cranklength ctrllimited ctrlrange damping delay diameter forcelimited forcerange gear "
        "group interp nsample timeconst user"),
    "default/damper": (
        "armature cranklength ctrlrange damping delay forcelimited forcerange gear group interp kv nsample user"),
    "default/dcmotor": (
        "armature cogging controller cranklength ctrllimited ctrlrange damping delay gear group inductance input "
        "interp lugre motorconst nominal nsample resistance saturation thermal user"),
    "default/default": "class",
    "default/equality": "active solimp solref",
    "default/general": (
        "actdim actearly actlimited actrange armature biasprm biastype cranklength ctrllimited ctrlrange damping "
        "delay dynprm dyntype ffrange forcelimited forcerange gainprm gaintype gear group inheritrange input interp "
        "nsample user velrange"),
    "default/geom": (
        "adhesion axisangle castshadow conaffinity condim contype density euler fitscale fluidcoef fluidshape "
        "friction fromto gap group hfield margin mass material mesh pos priority quat rgba shellinertia size solimp "
        "solmix solref surfacevel type user xyaxes zaxis"),
    "default/intvelocity": (
        "actlimited actrange armature cranklength ctrllimited ctrlrange damping dampratio delay forcelimited "
        "forcerange gear group inheritrange interp kp kv nsample user"),
    "default/joint": (
        "actuatorfrclimited actuatorfrcrange actuatorgravcomp armature axis damping frictionloss group limited margin "
        "pos range ref solimpfriction solimplimit solreffriction solreflimit springdamper springref springyield "
        "stiffness type user"),
    "default/light": (
        "active ambient attenuation bulbradius castshadow cutoff diffuse dir directional exponent intensity mode pos "
        "range softness specular type"),
    "default/material": "emission metallic reflectance rgba roughness shininess specular texrepeat texture texuniform",
    "default/mesh": "inertia maxhullvert scale",
    "default/motor": (
        "armature cranklength ctrllimited ctrlrange damping delay forcelimited forcerange gear group interp nsample "
        "user"),
    "default/muscle": (
        "armature cranklength ctrllimited ctrlrange damping delay force forcelimited forcerange fpmax fvmax gear "
        "group interp lmax lmin nsample range scale timeconst user vmax"),
    "default/orientation": "ctrlrange dampratio delay forcelimited forcerange group input interp kp kv nsample user",
    "default/pair": "adhesion condim friction gap margin solimp solref solreffriction",
    "default/pid": (
        "armature cranklength ctrllimited ctrlrange damping dampratio delay ffrange forcelimited forcerange gear "
        "group imax inheritrange input interp ki kp kv nsample posrange slewmax user velrange"),
    "default/position": (
        "armature cranklength ctrllimited ctrlrange damping dampratio delay forcelimited forcerange gear group "
        "inheritrange interp kp kv nsample timeconst user"),
    "default/site": "axisangle euler fromto group material mesh pos quat rgba size type user xyaxes zaxis",
    "default/tendon": (
        "actuatorfrclimited actuatorfrcrange armature damping frictionloss group limited margin material range rgba "
        "solimpfriction solimplimit solreffriction solreflimit springlength springyield stiffness user width"),
    "default/texture": (
        "builtin colorspace embed gridlayout gridsize height hflip mark markrgb nchannel random rgb1 rgb2 type vflip "
        "width"),
    "default/velocity": (
        "armature cranklength ctrllimited ctrlrange damping delay forcelimited forcerange gear group interp kv "
        "nsample user"),
    "deformable/flex": (
        "body cellcount dim dof element elemtexcoord flatskin group material name node nodecoord radius rgba texcoord "
        "vertex"),
    "deformable/skin": "face file group inflate material name rgba texcoord vertex",
    "equality/connect": "active anchor body1 body2 class name site1 site2 solimp solref",
    "equality/flex": "active class flex name solimp solref",
    "equality/flexstrain": "active cell class flex name solimp solref",
    "equality/flexvert": "active class flex name solimp solref",
    "equality/joint": "active class joint1 joint2 name polycoef solimp solref",
    "equality/tendon": "active class name polycoef solimp solref tendon1 tendon2",
    "equality/weld": "active anchor body1 body2 class name relpose site1 site2 solimp solref torquescale",
    "extension/plugin": "plugin",
    "fixed/joint": "coef joint",
    "flex/contact": (
        "activelayers conaffinity condim contype friction gap internal margin passive priority selfcollide solimp "
        "solmix solref"),
    "flex/edge": "damping stiffness",
    "flex/elasticity": "damping elastic2d poisson section sectionsize shear thickness yield young",
    "flexcomp/contact": (
        "activelayers conaffinity condim contype friction gap margin passive priority selfcollide solimp solmix "
        "solref"),
    "flexcomp/edge": "damping equality solimp solref stiffness",
    "flexcomp/elasticity": "damping elastic2d poisson section sectionsize shear thickness yield young",
    "flexcomp/pin": "grid gridrange id range",
    "flexcomp/plugin": "instance plugin",
    "geom/plugin": "instance plugin",
    "instance/config": "key value",
    "keyframe/key": "act ctrl mpos mquat name plastic qpos qvel time",
    "material/layer": "role texture",
    "mesh/plugin": "instance plugin",
    "mujoco/actuator": "",
    "mujoco/asset": "",
    "mujoco/body": "axisangle childclass euler fuse gravcomp mocap name pos quat simple sleep user xyaxes zaxis",
    "mujoco/compiler": (
        "alignfree angle assetdir autolimits balanceinertia boundinertia boundmass conflict coordinate discardvisual "
        "eulerseq fitaabb fusestatic inertiafromgeom inertiagrouprange meshdir passthrough savecanonical savecompiled "
        "saveinertial settotalmass strippath texturedir usethread"),
    "mujoco/contact": "",
    "mujoco/custom": "",
    "mujoco/default": "class",
    "mujoco/deformable": "",
    "mujoco/equality": "",
    "mujoco/extension": "",
    "mujoco/keyframe": "",
    "mujoco/mujoco": "model",
    "mujoco/option": (
        "actuatorgroupdisable ccd_iterations ccd_tolerance cone density gravity impratio integrator iterations "
        "jacobian ls_iterations ls_tolerance magnetic noslip_iterations noslip_tolerance o_friction o_margin o_solimp "
        "o_solref sdf_initpoints sdf_iterations sleep_tolerance solver timestep tolerance viscosity wind"),
    "mujoco/sensor": "",
    "mujoco/size": (
        "memory nconmax njmax nkey nstack nuser_actuator nuser_body nuser_cam nuser_geom nuser_jnt nuser_sensor "
        "nuser_site nuser_tendon nuserdata"),
    "mujoco/statistic": "center extent meaninertia meanmass meansize",
    "mujoco/tendon": "",
    "mujoco/visual": "",
    "mujoco/worldbody": "",
    "option/flag": (
        "actuation autoreset clampctrl constraint contact damper diagexact energy equality eulerdamp filterparent "
        "frictionloss fwdinv gravity invdiscrete ipc island limit midphase multiccd nativeccd override refsafe sensor "
        "sleep speculative spring warmstart"),
    "plugin/config": "key value",
    "plugin/instance": "name",
    "sensor/accelerometer": "cutoff delay interp interval name noise nsample site user",
    "sensor/actuatorfrc": "actuator cutoff delay interp interval name noise nsample user",
    "sensor/actuatorpos": "actuator cutoff delay interp interval name noise nsample user",
    "sensor/actuatorvel": "actuator cutoff delay interp interval name noise nsample user",
    "sensor/ballangvel": "cutoff delay interp interval joint name noise nsample user",
    "sensor/ballquat": "cutoff delay interp interval joint name noise nsample user",
    "sensor/camprojection": "camera cutoff delay interp interval name noise nsample site user",
    "sensor/clock": "cutoff delay interp interval name noise nsample user",
    "sensor/contact": (
        "body1 body2 cutoff data delay geom1 geom2 interp interval name noise nsample num reduce site subtree1 "
        "subtree2 user"),
    "sensor/distance": "body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user",
    "sensor/e_kinetic": "cutoff delay interp interval name noise nsample user",
    "sensor/e_potential": "cutoff delay interp interval name noise nsample user",
    "sensor/force": "cutoff delay interp interval name noise nsample site user",
    "sensor/frameangacc": "cutoff delay interp interval name noise nsample objname objtype user",
    "sensor/frameangvel": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/framelinacc": "cutoff delay interp interval name noise nsample objname objtype user",
    "sensor/framelinvel": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/framepos": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/framequat": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/framexaxis": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/frameyaxis": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/framezaxis": "cutoff delay interp interval name noise nsample objname objtype refname reftype user",
    "sensor/fromto": "body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user",
    "sensor/gyro": "cutoff delay interp interval name noise nsample site user",
    "sensor/insidesite": (
        "body1 body2 cutoff delay enclosed geom1 geom2 interp interval name noise nsample objname objtype site user"),
    "sensor/jointactuatorfrc": "cutoff delay interp interval joint name noise nsample user",
    "sensor/jointlimitfrc": "cutoff delay interp interval joint name noise nsample user",
    "sensor/jointlimitpos": "cutoff delay interp interval joint name noise nsample user",
    "sensor/jointlimitvel": "cutoff delay interp interval joint name noise nsample user",
    "sensor/jointpos": "cutoff delay interp interval joint name noise nsample user",
    "sensor/jointvel": "cutoff delay interp interval joint name noise nsample user",
    "sensor/magnetometer": "cutoff delay interp interval name noise nsample site user",
    "sensor/normal": "body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user",
    "sensor/plugin": "cutoff instance name objname objtype plugin refname reftype user",
    "sensor/rangefinder": "camera cutoff data delay interp interval name noise nsample site user",
    "sensor/subtreeangmom": "body cutoff delay interp interval name noise nsample user",
    "sensor/subtreecom": "body cutoff delay interp interval name noise nsample user",
    "sensor/subtreelinvel": "body cutoff delay interp interval name noise nsample user",
    "sensor/tactile": "cutoff delay geom interp interval mesh name nsample user",
    "sensor/tendonactuatorfrc": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/tendonlimitfrc": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/tendonlimitpos": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/tendonlimitvel": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/tendonpos": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/tendonvel": "cutoff delay interp interval name noise nsample tendon user",
    "sensor/torque": "cutoff delay interp interval name noise nsample site user",
    "sensor/touch": "cutoff delay interp interval name noise nsample site user",
    "sensor/user": "cutoff datatype dim name needstage noise objname objtype user",
    "sensor/velocimeter": "cutoff delay interp interval name noise nsample site user",
    "skin/bone": "bindpos bindquat body vertid vertweight",
    "spatial/geom": "geom sidesite",
    "spatial/pulley": "divisor",
    "spatial/site": "site",
    "tendon/fixed": (
        "actuatorfrclimited actuatorfrcrange armature class damping frictionloss group limited margin name range "
        "solimpfriction solimplimit solreffriction solreflimit springlength springyield stiffness user"),
    "tendon/spatial": (
        "actuatorfrclimited actuatorfrcrange armature class damping frictionloss group limited margin material name "
        "range rgba solimpfriction solimplimit solreffriction solreflimit springlength springyield stiffness user "
        "width"),
    "tuple/element": "objname objtype prm",
    "visual/global": (
        "azimuth bvactive cameraid elevation ellipsoidinertia fovy glow ipd linewidth offheight offwidth orthographic "
        "realtime"),
    "visual/headlight": "active ambient diffuse specular",
    "visual/map": (
        "actuatortendon alpha fogend fogstart force haze shadowclip shadowscale stiffness stiffnessrot torque zfar "
        "znear"),
    "visual/quality": "numquads numslices numstacks offsamples shadowsize",
    "visual/rgba": (
        "actuator actuatornegative actuatorpositive bv bvactive camera com connect constraint contactforce "
        "contactfriction contactgap contactpoint contacttorque crankbroken fog force frustum haze inertia joint light "
        "rangefinder selectpoint slidercrank"),
    "visual/scale": (
        "actuatorlength actuatorwidth camera com connect constraint contactheight contactwidth forcewidth framelength "
        "framewidth frustum jointlength jointwidth light selectpoint slidercrank"),
}

# the kind whose children an element holds: a <worldbody>, <frame> and <replicate> hold a <body>'s
_CONTEXT = {"worldbody": "body", "frame": "body", "replicate": "body"}
# where MuJoCo's schema check does not look (unknown attributes warn): these and everything inside them
_UNCHECKED_BY_MUJOCO = frozenset({"frame", "replicate"})
# refused whole by the loader (its message says why): not looked into
_REFUSED = frozenset({"body/composite", "body/flexcomp", "body/attach"})
# unknown attributes listed in the warning (the rest counted)
_MOST_LISTED = 10
_QUOTED = "'{}'"

#: ``{tag: (attributes, the same table for its children, or None where not looked into)}`` of one kind's children
_Children = dict[Any, tuple[frozenset[str], "_Children | None"]]


@functools.cache
def _tables() -> tuple[dict[str, frozenset[str]], dict[str, tuple[str, ...]], _Children]:
    """``(attributes of each "context/name", the child names of each context, the table of the root's children
    for the quick pass)``, made on first use."""
    from xml.etree.ElementTree import Comment, ProcessingInstruction

    attributes = {key: frozenset(names.split()) for key, names in ATTRIBUTES.items()}
    names: dict[str, list[str]] = {}
    for key in ATTRIBUTES:
        context, name = key.split("/")
        names.setdefault(context, []).append(name)
    by_context: dict[str, _Children] = {c: {} for c in names}
    for key, valid in attributes.items():
        context, name = key.split("/")
        inner = _CONTEXT.get(name, name)
        by_context[context][name] = (valid, None if key in _REFUSED else by_context.get(inner, {}))
    for table in by_context.values():  # comments and processing instructions: nothing to check
        table[Comment] = table[ProcessingInstruction] = (frozenset(), None)
    return attributes, {c: tuple(sorted(n)) for c, n in names.items()}, {"mujoco": by_context["mujoco"]["mujoco"]}


def _all_known(root: Any, top: _Children) -> bool:
    """Whether every element and attribute under ``root`` is known (the quick pass: one lookup per element)."""
    stack: list[tuple[Any, _Children]] = [(root, top)]
    while stack:
        elem, table = stack.pop()
        for child in elem:
            entry = table.get(child.tag)
            if entry is None or not entry[0].issuperset(child.attrib):
                return False
            if entry[1] is not None and len(child):
                stack.append((child, entry[1]))
    return True


def _nearest(name: str, valid: tuple[str, ...] | frozenset[str], what: str) -> str:
    """``"did you mean 'axis'?"``, or the valid names when none is close."""
    close = difflib.get_close_matches(name, sorted(valid), n=1, cutoff=0.6)
    if close:
        return f"did you mean {what.format(close[0])}?"
    if not valid:
        return "it takes none"
    names = sorted(valid)
    shown = ", ".join(what.format(n) for n in names[:30]) + (f", ... ({len(names)} in all)" if len(names) > 30 else "")
    return f"expected one of {shown}"


def check_names(doc: Doc) -> None:
    """Refuse an element or attribute MuJoCo's schema does not know, naming the nearest valid one (module doc).

    Walks the document (includes expanded, before ``<replicate>`` is) in document order; the first unknown name
    outside ``<frame>``/``<replicate>`` is an :class:`~featherdyn.MJCFError`
    (``file: line N: <joint name='j'>: unknown attribute 'axsi' (MuJoCo refuses it); did you mean 'axis'?``),
    the unknown attributes inside them one :class:`~featherdyn.PhysicalityWarning` (``strict``: the error).
    """
    attributes, children, top = _tables()
    if top["mujoco"][0].issuperset(doc.root.attrib) and _all_known(doc.root, top["mujoco"][1] or {}):
        return  # the usual document; otherwise the walk below finds the first unknown name in document order
    lax: list[str] = []
    lax_count = 0
    # (element, its parent's name and kind, whether inside a <frame> or <replicate>), popped in document order
    stack: list[tuple[Any, str, str, bool]] = [(doc.root, "", "mujoco", False)]
    while stack:
        elem, parent, context, unchecked = stack.pop()
        tag = elem.tag
        key = f"{context}/{tag}"
        valid = attributes.get(key)
        if valid is None:
            raise doc.error(elem, f"unknown MJCF element <{shorten(str(tag))}> in <{parent}> (MuJoCo refuses it); "
                            + _nearest(tag, children.get(context, ()), "<{}>"))
        inside = unchecked or tag in _UNCHECKED_BY_MUJOCO
        if not valid.issuperset(elem.attrib):
            for attr in elem.attrib:
                if attr in valid:
                    continue
                if key == "mujoco/worldbody":
                    raise doc.error(elem, f"{shorten(attr)}={quote(elem.attrib[attr])}: the world body takes no "
                                    "attributes (MuJoCo refuses them)")
                if not inside:
                    raise doc.error(elem, f"unknown attribute {quote(attr)} of <{tag}> (MuJoCo refuses it); "
                                    + _nearest(attr, valid, _QUOTED))
                if doc.strict:
                    raise doc.error(elem, f"unknown attribute {quote(attr)} of <{tag}> (MuJoCo ignores it inside "
                                    f"<frame> and <replicate>; refused with strict=True); {_nearest(attr, valid, _QUOTED)}")
                lax_count += 1
                if len(lax) < _MOST_LISTED:  # (the nearest names of the first few only: a file may hold thousands)
                    where = doc.where(elem).removeprefix(doc.label + ": ")
                    lax.append(f"{where}: {quote(attr)} ({_nearest(attr, valid, _QUOTED)})")
        if key in _REFUSED:
            continue
        inner = _CONTEXT.get(tag, tag)
        stack.extend((child, tag, inner, inside) for child in reversed(elem) if isinstance(child.tag, str))
    if lax:
        more = f" and {lax_count - len(lax)} more" if lax_count > len(lax) else ""
        warnings.warn(f"{doc.label}: unknown attributes inside <frame> or <replicate>, where MuJoCo ignores them "
                      f"(featherdyn does too; strict=True refuses them): {'; '.join(lax)}{more}",
                      PhysicalityWarning, stacklevel=4)
