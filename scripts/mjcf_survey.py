"""Survey every MJCF model shipped in the installed Python packages: featherdyn and Pinocchio against MuJoCo.

Usage (from the repository root, featherdyn installed: ``pip install -e ".[test]"``)::

    python scripts/mjcf_survey.py            # writes docs/mjcf-models.md
    python scripts/mjcf_survey.py --out -    # the table on stdout
    python scripts/mjcf_survey.py --one PATH # one model, JSON (a worker's job)
    python scripts/mjcf_survey.py --root DIR --out -   # the MJCF files under DIR (e.g. unpacked wheels)

Finds every ``*.xml`` whose root element is ``<mujoco>`` among the files of
the installed distributions (``importlib.metadata``: mujoco's test data,
gymnasium, dm_control, robosuite, metaworld, ... whatever is installed; none
of them is a dependency of featherdyn). For each file MuJoCo compiles, it
loads the model with ``featherdyn.load_mjcf`` and with Pinocchio's
``buildModelFromMJCF`` and compares each with MuJoCo at a few seeded random
configurations: total mass of the moving bodies, ``M(q)`` (``mj_fullM``) and
the gravity torques (``qfrc_bias`` at ``qvel = 0``), as relative errors
(``max |x − x_mj| / max |x_mj|``). A disagreement or failure gets a reason
found by a measurement (layouts, per-body masses, gravity, armature, MuJoCo
variants of the model), or "unexplained".

Each model runs in its own subprocess (``--one``) with a time limit, so a
crash or a hang of one loader costs one row, not the survey.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata as md
import json
import os
import platform
import subprocess
import sys
import time
import warnings
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

#: Agreement threshold (relative); mesh-based models get MESH_RTOL (MuJoCo stores a mesh's inertia in a principal
#: frame found by an iterative eigensolver whose residual reaches ~1e-9 relative).
RTOL = 1e-9
MESH_RTOL = 1e-8
SAMPLES = 3
SEED = 0
TIMEOUT = 120.0
COMMAND = "python scripts/mjcf_survey.py"


# --------------------------------------------------------------------------- finding the models


def _root_tag(path: Path) -> str | None:
    try:
        for _, elem in ET.iterparse(path, events=("start",)):
            return elem.tag
    except (ET.ParseError, OSError, UnicodeDecodeError):
        return None
    return None


def find_models() -> list[tuple[str, str, Path]]:
    """``(distribution, path inside site-packages, absolute path)`` of every installed MJCF file, sorted."""
    seen: set[Path] = set()
    out = []
    for dist in md.distributions():
        name = dist.metadata["Name"]
        if name is None or name.lower() == "featherdyn":
            continue
        for f in dist.files or []:
            if not str(f).endswith(".xml"):
                continue
            path = Path(str(dist.locate_file(f))).resolve()
            if path in seen or not path.is_file() or _root_tag(path) != "mujoco":
                continue
            seen.add(path)
            out.append((name, str(f), path))
    return sorted(out, key=lambda t: (t[0].lower(), t[1]))


def find_models_under(roots: list[Path]) -> list[tuple[str, str, Path]]:
    """The same for the MJCF files under folders (``--root``): the distribution is the first folder below a
    root, e.g. wheels not installed here, unpacked: ``pip download --no-deps brax`` then ``unzip``."""
    out = []
    for root in roots:
        for path in sorted(root.resolve().rglob("*.xml")):
            if path.is_file() and _root_tag(path) == "mujoco":
                rel = path.relative_to(root.resolve())
                out.append((rel.parts[0] if len(rel.parts) > 1 else root.name, str(rel), path))
    return out


# --------------------------------------------------------------------------- MuJoCo's side


def _mujoco() -> Any:
    import mujoco

    return mujoco


def _full_m(m: Any, d: Any) -> np.ndarray:
    mujoco = _mujoco()
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, M, d.qM) if hasattr(d, "qM") else mujoco.mj_fullM(m, d, M)
    return M


def _moving_bodies(m: Any) -> list[int]:
    """Bodies welded to a body with degrees of freedom (a mocap body is welded to itself, without any)."""
    return [b for b in range(1, m.nbody) if m.body_dofnum[m.body_weldid[b]] > 0]


def _random_qpos(m: Any, rng: np.random.Generator) -> np.ndarray:
    """A configuration within the joint ranges (hinge ±π, slide ±1 where unlimited), uniform quaternions."""
    mujoco = _mujoco()
    qpos = np.zeros(m.nq)
    for j in range(m.njnt):
        a, t = int(m.jnt_qposadr[j]), int(m.jnt_type[j])
        if t in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
            lo, hi = m.jnt_range[j] if m.jnt_limited[j] else ((-np.pi, np.pi) if t == mujoco.mjtJoint.mjJNT_HINGE
                                                              else (-1.0, 1.0))
            qpos[a] = rng.uniform(lo, hi)
        else:
            if t == mujoco.mjtJoint.mjJNT_FREE:
                qpos[a:a + 3] = rng.uniform(-1, 1, 3)
                a += 3
            quat = rng.normal(size=4)
            qpos[a:a + 4] = quat / np.linalg.norm(quat)
    return qpos


def _mj_states(m: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``(qpos, M, gravity torques)`` at SAMPLES seeded configurations."""
    mujoco = _mujoco()
    d = mujoco.MjData(m)
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(SAMPLES):
        d.qpos[:] = _random_qpos(m, rng)
        d.qvel[:] = 0
        mujoco.mj_forward(m, d)
        out.append((d.qpos.copy(), _full_m(m, d), d.qfrc_bias.copy()))
    return out


def _rel(ours: np.ndarray, ref: np.ndarray, floor: float = 1e-12) -> float:
    ours, ref = np.asarray(ours, dtype=float), np.asarray(ref, dtype=float)
    scale = max(float(np.max(np.abs(ref), initial=0.0)), floor)
    return float(np.max(np.abs(ours - ref), initial=0.0)) / scale


def _worst(errs: dict[str, float]) -> tuple[str, float]:
    what = max(errs, key=lambda k: errs[k]) if errs else "-"
    return what, errs.get(what, 0.0)


def _has_mesh_inertia(m: Any) -> bool:
    mujoco = _mujoco()
    return bool(np.any(m.geom_type == mujoco.mjtGeom.mjGEOM_MESH))


def _trees(m: Any) -> list[int]:
    """Top-level body (child of the world) of each body (0 for the world)."""
    return [int(m.body_rootid[b]) for b in range(m.nbody)]


# --------------------------------------------------------------------------- featherdyn


def _fd_joint_names(m: Any, model: Any) -> list[str]:
    mujoco = _mujoco()
    out = []
    for j in range(m.njnt):
        name = m.joint(j).name
        if not name:
            b = int(m.jnt_bodyid[j])
            body = m.body(b).name or f"body{b}"
            name = f"{body}/joint{j - int(m.body_jntadr[b])}"
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE and name not in model.joint_names:
                name = f"{body}/free"
        out.append(name)
    return out


def survey_featherdyn(path: Path, m: Any, states: list) -> dict[str, Any]:
    import featherdyn as fd
    from featherdyn import conventions as conv

    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fd.load_mjcf(path)
    except fd.FeatherdynError as exc:
        return {"status": "refused", "detail": _first_line(exc), "reason": _fd_refusal_reason(exc, m)}
    except Exception as exc:  # a bug, reported as such
        return {"status": "error", "detail": f"{type(exc).__name__}: {_first_line(exc)}",
                "reason": f"featherdyn raises {type(exc).__name__} (a bug)"}
    load_time = time.perf_counter() - t0
    names = _fd_joint_names(m, model)
    layout_ok = (model.nq == m.nq and model.nv == m.nv and sorted(names) == sorted(model.joint_names)
                 and all(model.idx_q[model.joint_id(n)] == m.jnt_qposadr[j] for j, n in enumerate(names)))
    if not layout_ok:
        return {"status": "layout", "detail": f"nq={model.nq} nv={model.nv} (MuJoCo {m.nq}, {m.nv})",
                "reason": "joint layout differs from MuJoCo's"}
    errs: dict[str, float] = {}
    mass_mj = float(sum(m.body_mass[b] for b in _moving_bodies(m)))
    errs["mass"] = abs(model.total_mass - mass_mj) / max(mass_mj, 1e-12)
    for qpos, M_mj, g_mj in states:
        q = conv.q_from_mujoco(model, qpos)
        M = conv.joint_matrix_to_mujoco(model, q, fd.crba(model, q))
        g = conv.tau_to_mujoco(model, q, fd.generalized_gravity(model, q))
        errs["M"] = max(errs.get("M", 0.0), _rel(M, M_mj))
        errs["gravity"] = max(errs.get("gravity", 0.0), _rel(g, g_mj))
    what, err = _worst(errs)
    return {"status": "compared", "errors": errs, "worst": what, "err": err, "load_time": load_time}


# --------------------------------------------------------------------------- Pinocchio


def _pin_segments(pm: Any, m: Any) -> tuple[list[tuple[int, list[int]]], list[str]]:
    """Each Pinocchio joint with the MuJoCo joints it stands for, and the Pinocchio joints that match none.

    By name (``Composite_X``: the joints of X's body); a joint MuJoCo leaves unnamed by the body Pinocchio
    hangs on it (its ``BODY`` frame of the same name as a MuJoCo body with joints).
    """
    import pinocchio as pin

    mj_names = {m.joint(j).name: j for j in range(m.njnt) if m.joint(j).name}
    mj_bodies = {m.body(b).name: b for b in range(1, m.nbody) if m.body(b).name and m.body_jntnum[b] > 0}
    out, unmatched = [], []
    for jid in range(1, pm.njoints):
        name = pm.names[jid]
        base = name.removeprefix("Composite_")
        body = None
        if base in mj_names:
            j = mj_names[base]
            if not name.startswith("Composite_"):
                out.append((jid, [j]))
                continue
            body = int(m.jnt_bodyid[j])
        else:
            frames = [f.name for f in pm.frames if f.parentJoint == jid and f.type == pin.FrameType.BODY]
            body = next((mj_bodies[f] for f in frames if f in mj_bodies), None)
        if body is None:
            unmatched.append(name)
        else:
            out.append((jid, list(range(int(m.body_jntadr[body]), int(m.body_jntadr[body] + m.body_jntnum[body])))))
    return out, unmatched


def _pin_maps(pm: Any, m: Any, segs: list[tuple[int, list[int]]], qpos: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Pinocchio's ``q`` from MuJoCo's ``qpos`` and ``P`` with ``v_pin = P qvel`` (``τ_mj = Pᵀ τ_pin``).

    featherdyn's MuJoCo converters give the configurations (Pinocchio's free-flyer and ball ``q`` are
    featherdyn's: ``[p; x y z w]``); velocities: a free joint's ``qvel = [v_world; ω_body]`` becomes
    Pinocchio's ``[Rᵀ v_world; ω_body]`` (``featherdyn.conventions.mujoco_velocity_map`` with the halves
    in Pinocchio's order), hinge, slide and ball velocities are the same numbers.
    """
    from featherdyn import conventions as conv
    from featherdyn.rotation import quat_to_matrix

    mujoco = _mujoco()
    q = np.zeros(pm.nq)
    P = np.zeros((pm.nv, m.nv))
    for jid, joints in segs:
        iq, iv = int(pm.idx_qs[jid]), int(pm.idx_vs[jid])
        for j in joints:
            a, v, t = int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j]), int(m.jnt_type[j])
            if t == mujoco.mjtJoint.mjJNT_FREE:
                q[iq:iq + 7] = conv.freeflyer_q_from_mujoco(qpos[a:a + 7])
                R = quat_to_matrix(q[iq + 3:iq + 7])
                P[iv:iv + 3, v:v + 3] = R.T
                P[iv + 3:iv + 6, v + 3:v + 6] = np.eye(3)
                iq, iv = iq + 7, iv + 6
            elif t == mujoco.mjtJoint.mjJNT_BALL:
                q[iq:iq + 4] = conv.quat_wxyz_to_xyzw(qpos[a:a + 4])
                P[iv:iv + 3, v:v + 3] = np.eye(3)
                iq, iv = iq + 4, iv + 3
            else:
                q[iq] = qpos[a]
                P[iv, v] = 1.0
                iq, iv = iq + 1, iv + 1
    return q, P


def _pin_compare(pm: Any, m: Any, segs: list[tuple[int, list[int]]], states: list, floor: float = 1e-12
                 ) -> dict[str, float]:
    import pinocchio as pin

    data = pm.createData()
    errs: dict[str, float] = {}
    mass_mj = float(sum(m.body_mass[b] for b in _moving_bodies(m)))
    mass_pin = float(sum(pm.inertias[i].mass for i in range(1, pm.njoints)))
    errs["mass"] = abs(mass_pin - mass_mj) / max(mass_mj, floor)
    for qpos, M_mj, g_mj in states:
        q, P = _pin_maps(pm, m, segs, qpos)
        M = pin.crba(pm, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(pm, data, q)
        errs["M"] = max(errs.get("M", 0.0), _rel(P.T @ M @ P, M_mj, floor))
        errs["gravity"] = max(errs.get("gravity", 0.0), _rel(P.T @ g, g_mj, floor))
    return errs


def survey_pinocchio(path: Path, m: Any, states: list, rtol: float) -> dict[str, Any]:
    try:
        import pinocchio as pin
    except ImportError as exc:
        return {"status": "error", "detail": str(exc), "reason": "Pinocchio is not installed"}
    try:
        pm = pin.buildModelFromMJCF(str(path))
    except Exception as exc:
        reason = f"Pinocchio cannot load: {_pin_message(exc)}"
        if "No such node (body)" in str(exc) and not _own_worldbody_has_body(path):
            reason += " (the file's own <worldbody> has no <body>: none, or only through <include>)"
        return {"status": "refused", "detail": _pin_message(exc), "reason": reason}
    segs, unmatched = _pin_segments(pm, m)
    covered = sorted(j for _, js in segs for j in js)
    nq_ok = all(pm.nqs[jid] == sum(_mj_nq(m, j) for j in js) and pm.nvs[jid] == sum(_mj_nv(m, j) for j in js)
                for jid, js in segs)
    info = {"pin_nv": int(pm.nv), "pin_njoints": int(pm.njoints - 1)}
    if unmatched or covered != list(range(m.njnt)) or not nq_ok:
        reason = _pin_layout_reason(pm, m, covered, unmatched, nq_ok)
        return {"status": "layout", "detail": f"nv={pm.nv} (MuJoCo {m.nv})", "reason": reason, **info}
    errs = _pin_compare(pm, m, segs, states)
    what, err = _worst(errs)
    out = {"status": "compared", "errors": errs, "worst": what, "err": err, "agrees": err <= rtol, **info}
    if not out["agrees"]:
        out["reason"] = explain_pinocchio(path, pm, segs, rtol)
    return out


def _own_worldbody_has_body(path: Path) -> bool:
    root = ET.parse(path).getroot()
    return any(child.tag == "body" for wb in root.iter("worldbody") for child in wb)


def _mj_nq(m: Any, j: int) -> int:
    return {0: 7, 1: 4}.get(int(m.jnt_type[j]), 1)


def _mj_nv(m: Any, j: int) -> int:
    return {0: 6, 1: 3}.get(int(m.jnt_type[j]), 1)


def _pin_layout_reason(pm: Any, m: Any, covered: list[int], unmatched: list[str], nq_ok: bool) -> str:
    missing = sorted(set(range(m.njnt)) - set(covered))
    if missing:
        roots = _trees(m)
        kept = {roots[int(m.jnt_bodyid[j])] for j in covered}
        lost = {roots[int(m.jnt_bodyid[j])] for j in missing}
        ntop = sum(1 for b in range(1, m.nbody) if m.body_parentid[b] == 0)
        if len(kept) <= 1 and not kept & lost:
            first = min(b for b in range(1, m.nbody) if m.body_parentid[b] == 0)
            which = "the first body" if kept in (set(), {first}) else f"one body ({m.body(kept.pop()).name!r})"
            return (f"Pinocchio reads only {which} under <worldbody> (keeps {len(covered)} of {m.njnt} joints; "
                    f"{ntop} top-level bodies)")
        return f"Pinocchio drops {len(missing)} of {m.njnt} joints (e.g. {m.joint(missing[0]).name or missing[0]!r})"
    if unmatched:
        return f"Pinocchio names joints MuJoCo does not have (e.g. {unmatched[0]!r})"
    return "Pinocchio's joint sizes differ from MuJoCo's"


# --------------------------------------------------------------------------- reasons of disagreements


def _first_line(exc: BaseException) -> str:
    return (str(exc).strip().splitlines() or [type(exc).__name__])[0]


def _short_error(exc: BaseException, n: int = 110) -> str:
    s = _first_line(exc)
    return s if len(s) <= n else s[: n - 1] + "…"


def _pin_message(exc: BaseException) -> str:
    """Pinocchio's exceptions start with the C++ file and function; the message follows ``message:``."""
    text = str(exc).strip()
    if "message:" in text:
        text = text.split("message:", 1)[1].strip()
    s = " ".join(text.split())
    return s if len(s) <= 110 else s[:109] + "…"


#: Edits of MuJoCo's model, each a hypothesis about what Pinocchio does differently. A spec edit
#: (``MjSpec``, then compiled) returns whether it changed anything; a model edit acts on the compiled model.
def _drop_mass(spec: Any, which: Any) -> bool:
    hit = False
    for g in spec.geoms:
        if which(g):
            g.mass, g.density, hit = 0.0, 0.0, True
    return hit


def _spec_edits() -> dict[str, Any]:
    mujoco = _mujoco()
    mesh = mujoco.mjtGeom.mjGEOM_MESH

    def no_totalmass(spec: Any) -> bool:
        hit = spec.compiler.settotalmass > 0
        spec.compiler.settotalmass = -1
        return bool(hit)

    def geom_mass_ignored(spec: Any) -> bool:
        hit = False
        for g in spec.geoms:
            if not np.isnan(g.mass) and g.type != mesh:
                g.mass, hit = float("nan"), True
        return hit

    def default_mass_ignored(spec: Any) -> bool:
        # a geom whose mass equals its default class's is taken as having it from the class (an explicit
        # attribute of the same value would be misread: then the edit fails to explain and is not chosen)
        hit = False
        for g in spec.geoms:
            cls = g.classname if isinstance(g.classname, str) else g.classname.name
            d = spec.find_default(cls)
            if d is not None and not np.isnan(d.geom.mass) and g.mass == d.geom.mass:
                g.mass, hit = float("nan"), True
        return hit

    def top_body_unrotated(spec: Any) -> bool:
        hit = False
        for b in spec.worldbody.bodies:
            if not b.joints and not np.array_equal(b.quat, [1.0, 0.0, 0.0, 0.0]):
                b.quat, hit = [1.0, 0.0, 0.0, 0.0], True
        return hit

    def mesh_unit(spec: Any) -> bool:
        # mass 1 and inertia 1 about each axis at the geom's origin: a sphere of radius √2.5 (I = 2/5 m r²)
        hit = False
        for g in spec.geoms:
            if g.type == mesh and not (g.contype == 0 and g.conaffinity == 0):
                g.type, g.meshname, g.size, g.mass, hit = mujoco.mjtGeom.mjGEOM_SPHERE, "", [2.5 ** 0.5, 0, 0], 1.0, True
        return hit

    def all_groups(spec: Any) -> bool:
        lo, hi = spec.compiler.inertiagrouprange
        hit = any(not lo <= g.group <= hi for g in spec.geoms)
        for g in spec.geoms:
            g.group = lo
        return hit

    return {
        "Pinocchio drops geoms with contype=conaffinity=0 from the inertia":
            lambda s: _drop_mass(s, lambda g: g.contype == 0 and g.conaffinity == 0),
        "Pinocchio ignores settotalmass": no_totalmass,
        "Pinocchio ignores a geom mass set in a <default> class (uses the density)": default_mass_ignored,
        "Pinocchio ignores a geom's mass attribute (uses the density)": geom_mass_ignored,
        "Pinocchio ignores the orientation of a jointless top-level body": top_body_unrotated,
        "Pinocchio gives a mesh geom mass 1 and unit inertia (about the geom's origin)": mesh_unit,
        "Pinocchio drops mesh geoms from the inertia": lambda s: _drop_mass(s, lambda g: g.type == mesh),
        "Pinocchio ignores inertiagrouprange": all_groups,
    }


def _model_edits(pm: Any) -> dict[str, Any]:
    mujoco = _mujoco()
    g_pin = np.array(pm.gravity.linear)

    def armature(m: Any) -> bool:
        hit = bool(np.any(m.dof_armature != 0))
        m.dof_armature[:] = 0
        return hit

    def ref(m: Any) -> bool:
        hit = False
        for j in range(m.njnt):
            if m.jnt_type[j] in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
                a = m.jnt_qposadr[j]
                hit, m.qpos0[a] = hit or m.qpos0[a] != 0, 0.0
        return hit

    def gravity(m: Any) -> bool:
        off = bool(m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY)
        hit = off or not np.array_equal(m.opt.gravity, g_pin)
        m.opt.gravity[:] = g_pin
        m.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)
        return hit

    return {
        f"Pinocchio ignores <option gravity> / the gravity flag (uses {_vec(g_pin)})": gravity,
        "Pinocchio ignores joint armature": armature,
        "Pinocchio ignores a joint's ref (qpos0)": ref,
    }


def explain_pinocchio(path: Path, pm: Any, segs: list[tuple[int, list[int]]], rtol: float) -> str:
    """Which edits of MuJoCo's model make it agree with Pinocchio: greedily, the edit that lowers the largest
    relative error most, until it agrees or no edit helps (then the rest is "unexplained")."""
    spec_edits, model_edits = _spec_edits(), _model_edits(pm)
    chosen: list[str] = []

    def errors_with(names: list[str]) -> dict[str, float] | None:
        mujoco = _mujoco()
        for tiny in (0.0, 1e-14):  # an edit may leave a moving body massless: then bound it to ~0
            try:
                spec = mujoco.MjSpec.from_file(str(path))
                spec.compiler.boundmass = max(spec.compiler.boundmass, tiny)
                spec.compiler.boundinertia = max(spec.compiler.boundinertia, tiny)
                for n in names:
                    if n in spec_edits and not spec_edits[n](spec):
                        return None
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    m = spec.compile()
                for n in names:
                    if n in model_edits and not model_edits[n](m):
                        return None
                return _pin_compare(pm, m, segs, _mj_states(m), floor=1e-3 if tiny else 1e-12)
            except Exception:
                continue
        return None

    def score(errs: dict[str, float]) -> float:  # decades above the threshold, summed over the quantities
        return sum(np.log10(max(e, rtol) / rtol) for e in errs.values())

    base = errors_with([])
    if base is None:
        return "unexplained (MuJoCo's MjSpec cannot recompile the model)"
    current = base
    while score(current) > 0:
        trials = {n: errors_with([*chosen, n]) for n in [*spec_edits, *model_edits] if n not in chosen}
        scored = {n: score(e) for n, e in trials.items() if e is not None}
        best = min(scored, key=lambda n: scored[n], default=None)
        if best is None or scored[best] > score(current) - np.log10(2):
            break
        chosen.append(best)
        current = trials[best]  # type: ignore[assignment]
    if score(current) > 0:
        what, err = _worst(current)
        chosen.append(f"unexplained ({what} still {err:.1e})" if chosen else "unexplained")
    return "; ".join(chosen)


def _vec(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


def _fd_refusal_reason(exc: BaseException, m: Any) -> str:
    """featherdyn's message (paths shortened), with what MuJoCo made of the same element where that is measurable."""
    text = _first_line(exc)
    _, _, what = text.partition(": line ")
    short = f"line {what}" if what else text
    extra = ""
    if "mjMINVAL" in text and "body '" in text:
        name = text.split("body '", 1)[1].split("'", 1)[0]
        try:
            b = m.body(name).id
            extra = (f" (MuJoCo compiles it: body_mass {m.body_mass[b]:g}, its subtree's mass "
                     f"{m.body_subtreemass[b]:g}, {m.body_jntnum[b]} joints)")
        except KeyError:
            pass
    elif "unknown MJCF element <body> in <mujoco>" in text:
        extra = f" (MuJoCo ignores it: nbody={m.nbody})"
    short = short if len(short) <= 140 else short[:139] + "…"
    return f"featherdyn refuses: {short}{extra}"


def explain_featherdyn(path: Path, m: Any, res: dict[str, Any]) -> str:
    """No featherdyn disagreement was seen when this was written (every difference is a refusal); a new one is
    reported with its worst quantity, as unexplained until someone looks."""
    return f"unexplained ({res['worst']} {res['err']:.1e})"


# --------------------------------------------------------------------------- one model


def survey_one(path: Path) -> dict[str, Any]:
    mujoco = _mujoco()
    out: dict[str, Any] = {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = mujoco.MjModel.from_xml_path(str(path))
    except Exception as exc:
        out["mujoco"] = {"status": "not standalone", "detail": _short_error(exc, 160)}
        return out
    mesh = _has_mesh_inertia(m)
    out["mujoco"] = {"status": "compiled", "nbody": int(m.nbody), "njnt": int(m.njnt), "nv": int(m.nv),
                     "mesh": mesh}
    states = _mj_states(m)
    rtol = MESH_RTOL if mesh else RTOL
    fd_res = survey_featherdyn(path, m, states)
    if fd_res["status"] == "compared":
        fd_res["agrees"] = fd_res["err"] <= rtol
        if not fd_res["agrees"]:
            fd_res["reason"] = explain_featherdyn(path, m, fd_res)
    out["featherdyn"] = fd_res
    out["pinocchio"] = survey_pinocchio(path, m, states, rtol)
    return out


def _run_worker(path: Path, timeout: float) -> dict[str, Any]:
    cmd = [sys.executable, os.path.abspath(__file__), "--one", str(path)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"crash": f"no answer within {timeout:g} s"}
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr.strip().splitlines() or ["(nothing on stderr)"])[-1]
        return {"crash": f"worker exit code {proc.returncode}: {tail[:160]}"}
    result: dict[str, Any] = json.loads(lines[-1])
    return result


# --------------------------------------------------------------------------- the document


def _backend() -> str:
    """Which featherdyn engine computed M and the gravity torques (the compiled core when it is built)."""
    from featherdyn.core import _core

    return "compiled core" if _core is not None else "reference algorithms (the core is not built)"


def _versions() -> dict[str, str]:
    out = {}
    for name in ("mujoco", "pin", "numpy", "gymnasium", "gymnasium-robotics", "dm_control", "robosuite", "metaworld"):
        try:
            out[name] = md.version(name)
        except md.PackageNotFoundError:
            pass
    return out


def _featherdyn_source() -> str:
    """``featherdyn <version>`` and, in a git checkout, the commit of ``src/`` (and whether it has local changes)."""
    import featherdyn as fd

    out = f"featherdyn {fd.__version__}"
    root = Path(fd.__file__).resolve().parents[2]
    try:
        sha = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "src"], capture_output=True,
                               text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return out
    return out + (f" (source at commit {sha}{', with local changes' if dirty else ''})" if sha else "")


def _cell(res: dict[str, Any] | None, mj: dict[str, Any]) -> str:
    if res is None or mj.get("status") != "compiled":
        return "–"
    if res["status"] == "compared":
        if mj["nv"] == 0:
            return "agrees (no joints)" if res["agrees"] else f"**differs** (no joints), {res['err']:.1e} (mass)"
        mark = "agrees" if res["agrees"] else "**differs**"
        return f"{mark}, {res['err']:.1e} ({res['worst']})"
    if res["status"] == "refused":
        return "refused"
    if res["status"] == "layout":
        return f"**joints differ**: {res['detail']}"
    return f"**error**: {res.get('detail', '')}"


def _md_escape(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def write_markdown(rows: list[tuple[str, str, dict[str, Any]]], elapsed: float,
                   where: str = "in the installed distributions") -> str:
    compiled = [r for r in rows if r[2].get("mujoco", {}).get("status") == "compiled"]
    jointless = [r for r in compiled if r[2]["mujoco"]["nv"] == 0]
    fd_ok = sum(1 for r in compiled if r[2]["featherdyn"].get("agrees"))
    pin_ok = sum(1 for r in compiled if r[2]["pinocchio"].get("agrees"))
    fd_ok0 = sum(1 for r in jointless if r[2]["featherdyn"].get("agrees"))
    pin_ok0 = sum(1 for r in jointless if r[2]["pinocchio"].get("agrees"))
    vers = ", ".join(f"{k} {v}" for k, v in _versions().items())
    lines = [
        "# MJCF models shipped in Python packages: featherdyn and Pinocchio against MuJoCo",
        "",
        f"Generated by `{COMMAND}` on {datetime.date.today().isoformat()} ({elapsed:.0f} s; Python "
        f"{platform.python_version()}; {_featherdyn_source()}, {_backend()}; {vers}). Do not edit by hand: "
        "re-run the script.",
        "",
        f"Every `*.xml` whose root element is `<mujoco>` {where}. For each model MuJoCo "
        f"compiles, featherdyn (`fd.load_mjcf`) and Pinocchio (`pinocchio.buildModelFromMJCF`) are compared with "
        f"MuJoCo's compiled model at {SAMPLES} seeded random configurations: total mass of the moving bodies, "
        f"`M(q)` (`mj_fullM`) and the gravity torques (`qfrc_bias` at `qvel = 0`), as the largest relative error "
        f"`max|x − x_mj| / max|x_mj|`. Agreement: {RTOL:g} relative, {MESH_RTOL:g} for models with mesh geoms "
        f"(MuJoCo keeps a mesh's inertia in a principal frame from an iterative eigensolver). Joints are mapped by "
        f"name (Pinocchio's `Composite_X` is the joints of X's body); quaternions and free-joint velocities are "
        f"converted (featherdyn's `featherdyn.conventions` MuJoCo converters; for Pinocchio `(x, y, z, w)` and "
        f"`[v; ω]` in the body frame). Each reason is a measurement, or says \"unexplained\": joint layouts and "
        f"body trees; featherdyn's refusal with MuJoCo's numbers for the same element; for a Pinocchio "
        f"disagreement, MuJoCo's model edited one hypothesis at a time (Pinocchio's gravity vector, zero armature, "
        f"zero joint `ref`, some geoms' mass dropped or ignored, no `settotalmass`, ...; `explain_pinocchio` in "
        f"the script), greedily, until it agrees with Pinocchio; what remains is listed as unexplained.",
        "",
        f"**Summary: {len(rows)} model files, {len(compiled)} standalone models; featherdyn agrees with MuJoCo on "
        f"{fd_ok}; Pinocchio on {pin_ok}.** Of the standalone models {len(jointless)} have no joints (only a "
        f"total mass of 0 to compare; featherdyn agrees on {fd_ok0} of them, Pinocchio on {pin_ok0}); on the "
        f"{len(compiled) - len(jointless)} with joints featherdyn agrees on {fd_ok - fd_ok0}, Pinocchio on "
        f"{pin_ok - pin_ok0}.",
        "",
        "| package | model file | nbody/njnt/nv | featherdyn vs MuJoCo | Pinocchio vs MuJoCo | reason |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for dist, rel, res in rows:
        mj = res.get("mujoco", {})
        if "crash" in res:
            size, fd_cell, pin_cell, reason = "–", "**error**", "**error**", f"survey worker: {res['crash']}"
        elif mj.get("status") != "compiled":
            size, fd_cell, pin_cell = "–", "–", "–"
            reason = f"not a standalone model: MuJoCo: {mj.get('detail', '')}"
        else:
            size = f"{mj['nbody']}/{mj['njnt']}/{mj['nv']}"
            fd_cell, pin_cell = _cell(res.get("featherdyn"), mj), _cell(res.get("pinocchio"), mj)
            reasons = []
            for who in ("featherdyn", "pinocchio"):
                r = res.get(who, {})
                if not r.get("agrees") and r.get("reason"):
                    reasons.append(r["reason"])
            reason = "; ".join(reasons)
        lines.append(f"| {dist} | `{rel}` | {size} | {_md_escape(fd_cell)} | {_md_escape(pin_cell)} | "
                     f"{_md_escape(reason)} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--one", type=Path, help="survey one file and print JSON (what the workers run)")
    parser.add_argument("--out", default="docs/mjcf-models.md", help="the markdown file ('-' for stdout)")
    parser.add_argument("--jobs", type=int, default=max(1, min(4, os.cpu_count() or 1)))
    parser.add_argument("--timeout", type=float, default=TIMEOUT, help="seconds per model")
    parser.add_argument("--filter", default="", help="only files whose path contains this")
    parser.add_argument("--root", type=Path, action="append", default=[],
                        help="survey the MJCF files under this folder instead of the installed ones (repeatable)")
    args = parser.parse_args(argv)
    if args.one is not None:
        print(json.dumps(survey_one(args.one)))
        return 0
    t0 = time.perf_counter()
    found = find_models_under(args.root) if args.root else find_models()
    models = [t for t in found if args.filter in str(t[2])]
    with ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda t: _run_worker(t[2], args.timeout), models))
    rows = [(dist, rel, res) for (dist, rel, _), res in zip(models, results, strict=True)]
    where = ("under " + ", ".join(f"`{r.name}/`" for r in args.root) + " (`--root`: the first folder below is the "
             "distribution)") if args.root else "in the installed distributions"
    text = write_markdown(rows, time.perf_counter() - t0, where)
    if args.out == "-":
        sys.stdout.write(text)
    else:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}: " + next(ln for ln in text.splitlines() if ln.startswith("**Summary")))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
