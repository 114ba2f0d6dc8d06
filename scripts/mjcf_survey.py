"""Survey every MJCF model shipped in the installed Python packages: featherdyn and Pinocchio against MuJoCo.

Usage (from the repository root)::

    FD_NO_EDITABLE=1 PYTHONPATH=src python scripts/mjcf_survey.py            # writes docs/mjcf-models.md
    FD_NO_EDITABLE=1 PYTHONPATH=src python scripts/mjcf_survey.py --out -    # the table on stdout
    FD_NO_EDITABLE=1 PYTHONPATH=src python scripts/mjcf_survey.py --one PATH # one model, JSON (a worker's job)

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
COMMAND = "FD_NO_EDITABLE=1 PYTHONPATH=src python scripts/mjcf_survey.py"


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


def _mj_states(m: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """``(qpos, M, gravity torques, xquat of every body)`` at SAMPLES seeded configurations."""
    mujoco = _mujoco()
    d = mujoco.MjData(m)
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(SAMPLES):
        d.qpos[:] = _random_qpos(m, rng)
        d.qvel[:] = 0
        mujoco.mj_forward(m, d)
        out.append((d.qpos.copy(), _full_m(m, d), d.qfrc_bias.copy(), d.xquat.copy()))
    return out


def _rel(ours: np.ndarray, ref: np.ndarray) -> float:
    ours, ref = np.asarray(ours, dtype=float), np.asarray(ref, dtype=float)
    scale = max(float(np.max(np.abs(ref), initial=0.0)), 1e-12)
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
        return {"status": "refused", "detail": _first_line(exc), "reason": f"featherdyn refuses: {_short_error(exc)}"}
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
    for qpos, M_mj, g_mj, _ in states:
        q = conv.q_from_mujoco(model, qpos)
        M = conv.joint_matrix_to_mujoco(model, q, fd.crba(model, q))
        g = conv.tau_to_mujoco(model, q, fd.generalized_gravity(model, q))
        errs["M"] = max(errs.get("M", 0.0), _rel(M, M_mj))
        errs["gravity"] = max(errs.get("gravity", 0.0), _rel(g, g_mj))
    what, err = _worst(errs)
    return {"status": "compared", "errors": errs, "worst": what, "err": err, "load_time": load_time}


# --------------------------------------------------------------------------- Pinocchio


def _pin_segments(pm: Any, m: Any) -> tuple[list[tuple[int, list[int]]], list[str]]:
    """Each Pinocchio joint with the MuJoCo joints it stands for (by name; ``Composite_X`` for the joints of X's
    body), and the Pinocchio joints that match none."""
    mj_names = {m.joint(j).name: j for j in range(m.njnt) if m.joint(j).name}
    out, unmatched = [], []
    for jid in range(1, pm.njoints):
        name = pm.names[jid]
        base = name.removeprefix("Composite_")
        if base in mj_names:
            j = mj_names[base]
            if name.startswith("Composite_"):
                b = int(m.jnt_bodyid[j])
                joints = list(range(int(m.body_jntadr[b]), int(m.body_jntadr[b] + m.body_jntnum[b])))
            else:
                joints = [j]
            out.append((jid, joints))
        else:
            unmatched.append(name)
    return out, unmatched


def _pin_maps(pm: Any, m: Any, segs: list[tuple[int, list[int]]], qpos: np.ndarray, xquat: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Pinocchio's ``q`` from MuJoCo's ``qpos`` and ``P`` with ``v_pin = P qvel`` (``τ_mj = Pᵀ τ_pin``)."""
    mujoco = _mujoco()
    q = np.zeros(pm.nq)
    P = np.zeros((pm.nv, m.nv))
    for jid, joints in segs:
        iq, iv = int(pm.idx_qs[jid]), int(pm.idx_vs[jid])
        for j in joints:
            a, v, t = int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j]), int(m.jnt_type[j])
            if t == mujoco.mjtJoint.mjJNT_FREE:
                w, x, y, z = qpos[a + 3:a + 7]
                q[iq:iq + 7] = [*qpos[a:a + 3], x, y, z, w]
                R = np.zeros(9)
                mujoco.mju_quat2Mat(R, qpos[a + 3:a + 7])
                P[iv:iv + 3, v:v + 3] = R.reshape(3, 3).T  # Pinocchio: linear velocity in the body frame
                P[iv + 3:iv + 6, v + 3:v + 6] = np.eye(3)
                iq, iv = iq + 7, iv + 6
            elif t == mujoco.mjtJoint.mjJNT_BALL:
                w, x, y, z = qpos[a:a + 4]
                q[iq:iq + 4] = [x, y, z, w]
                P[iv:iv + 3, v:v + 3] = np.eye(3)
                iq, iv = iq + 4, iv + 3
            else:
                q[iq] = qpos[a]
                P[iv, v] = 1.0
                iq, iv = iq + 1, iv + 1
    return q, P


def survey_pinocchio(path: Path, m: Any, states: list) -> dict[str, Any]:
    try:
        import pinocchio as pin
    except ImportError as exc:
        return {"status": "error", "detail": str(exc), "reason": "Pinocchio is not installed"}
    try:
        pm = pin.buildModelFromMJCF(str(path))
    except Exception as exc:
        return {"status": "refused", "detail": _first_line(exc), "reason": f"Pinocchio cannot load: {_short_error(exc)}"}
    segs, unmatched = _pin_segments(pm, m)
    covered = sorted(j for _, js in segs for j in js)
    nq_ok = all(pm.nqs[jid] == sum(_mj_nq(m, j) for j in js) and pm.nvs[jid] == sum(_mj_nv(m, j) for j in js)
                for jid, js in segs)
    info = {"pin_nv": int(pm.nv), "pin_njoints": int(pm.njoints - 1)}
    if unmatched or covered != list(range(m.njnt)) or not nq_ok:
        reason = _pin_layout_reason(pm, m, covered, unmatched, nq_ok)
        return {"status": "layout", "detail": f"nv={pm.nv} (MuJoCo {m.nv})", "reason": reason, **info}
    data = pm.createData()
    errs: dict[str, float] = {}
    mass_mj = float(sum(m.body_mass[b] for b in _moving_bodies(m)))
    mass_pin = float(sum(pm.inertias[i].mass for i in range(1, pm.njoints)))
    errs["mass"] = abs(mass_pin - mass_mj) / max(mass_mj, 1e-12)
    for qpos, M_mj, g_mj, xquat in states:
        q, P = _pin_maps(pm, m, segs, qpos, xquat)
        M = pin.crba(pm, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(pm, data, q)
        errs["M"] = max(errs.get("M", 0.0), _rel(P.T @ M @ P, M_mj))
        errs["gravity"] = max(errs.get("gravity", 0.0), _rel(P.T @ g, g_mj))
    what, err = _worst(errs)
    return {"status": "compared", "errors": errs, "worst": what, "err": err, "mass": mass_pin,
            "gravity_vec": list(map(float, pm.gravity.linear)), **info}


def _mj_nq(m: Any, j: int) -> int:
    return {0: 7, 1: 4}.get(int(m.jnt_type[j]), 1)


def _mj_nv(m: Any, j: int) -> int:
    return {0: 6, 1: 3}.get(int(m.jnt_type[j]), 1)


def _pin_layout_reason(pm: Any, m: Any, covered: list[int], unmatched: list[str], nq_ok: bool) -> str:
    missing = sorted(set(range(m.njnt)) - set(covered))
    if missing:
        roots = _trees(m)
        tree_of = sorted({roots[int(m.jnt_bodyid[j])] for j in missing})
        moving_roots = sorted({roots[int(m.jnt_bodyid[j])] for j in range(m.njnt)})
        first_top = min(b for b in range(1, m.nbody) if m.body_parentid[b] == 0)
        kept_roots = sorted({roots[int(m.jnt_bodyid[j])] for j in covered})
        if kept_roots in ([], [first_top]) and set(tree_of) == set(moving_roots) - set(kept_roots):
            ntop = sum(1 for b in range(1, m.nbody) if m.body_parentid[b] == 0)
            return (f"Pinocchio reads only the first body under <worldbody> (keeps {len(covered)} of {m.njnt} joints; "
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


def explain_pinocchio(path: Path, m: Any, res: dict[str, Any], states: list) -> str:
    """Measure why Pinocchio's numbers differ from MuJoCo's (checks in order; the first that accounts for it)."""
    reasons = []
    g_mj = np.zeros(3) if m.opt.disableflags & _mujoco().mjtDisableBit.mjDSBL_GRAVITY else np.array(m.opt.gravity)
    g_pin = np.array(res["gravity_vec"])
    if not np.allclose(g_pin, g_mj, rtol=1e-12, atol=1e-12):
        reasons.append(f"Pinocchio's gravity is {_vec(g_pin)}, MuJoCo's {_vec(g_mj)}")
    if np.any(m.dof_armature != 0) and res["errors"]["M"] > RTOL:
        reasons.append("Pinocchio ignores joint armature") if _armature_explains(path, m, res) else None
    if res["errors"]["mass"] > RTOL:
        reasons.append(_mass_reason(path, m, res["mass"]))
    return "; ".join(r for r in reasons if r) or "unexplained"


def _vec(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


def _armature_explains(path: Path, m: Any, res: dict[str, Any]) -> bool:
    """Recompile with zero armature: does MuJoCo's M then agree with Pinocchio's?"""
    mujoco = _mujoco()
    m0 = mujoco.MjModel.from_xml_path(str(path))
    m0.dof_armature[:] = 0
    pres = survey_pinocchio(path, m0, _mj_states(m0))
    return pres.get("status") == "compared" and pres["errors"]["M"] <= MESH_RTOL * 10


def _mass_reason(path: Path, m: Any, mass_pin: float) -> str:
    """Compile variants of the model with MuJoCo (geoms of some kind removed from the inertia) and see which one
    has Pinocchio's total mass."""
    mujoco = _mujoco()
    mass_mj = float(sum(m.body_mass[b] for b in _moving_bodies(m)))
    variants = {
        "Pinocchio drops geoms with contype=conaffinity=0 from the inertia":
            lambda g: g.contype == 0 and g.conaffinity == 0,
        "Pinocchio drops mesh geoms from the inertia": lambda g: g.type == mujoco.mjtGeom.mjGEOM_MESH,
        "Pinocchio ignores inertiagrouprange (counts every geom group)": None,
    }
    for text, drop in variants.items():
        try:
            spec = mujoco.MjSpec.from_file(str(path))
            if drop is None:
                spec.compiler.inertiagrouprange = [0, 5]
                # count geoms of any group: move them into group 0
                for g in spec.geoms:
                    g.group = 0
            else:
                hit = False
                for g in spec.geoms:
                    if drop(g):
                        hit = True
                        g.mass = 0
                        g.density = 0
                if not hit:
                    continue
            mv = spec.compile()
        except Exception:
            continue
        mass_v = float(sum(mv.body_mass[b] for b in _moving_bodies(mv)))
        if abs(mass_v - mass_mj) > 1e-9 * mass_mj and abs(mass_v - mass_pin) <= 1e-6 * max(mass_v, 1e-12):
            return f"{text} (total mass {mass_pin:.6g} vs {mass_mj:.6g})"
    return f"total mass {mass_pin:.6g} vs MuJoCo {mass_mj:.6g}: unexplained"


def explain_featherdyn(path: Path, m: Any, res: dict[str, Any]) -> str:
    return "unexplained"


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
    pin_res = survey_pinocchio(path, m, states)
    if pin_res["status"] == "compared":
        pin_res["agrees"] = pin_res["err"] <= rtol
        if not pin_res["agrees"]:
            pin_res["reason"] = explain_pinocchio(path, m, pin_res, states)
    out["pinocchio"] = pin_res
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


def _versions() -> dict[str, str]:
    out = {}
    for name in ("mujoco", "pin", "numpy", "gymnasium", "gymnasium-robotics", "dm_control", "robosuite", "metaworld"):
        try:
            out[name] = md.version(name)
        except md.PackageNotFoundError:
            pass
    return out


def _cell(res: dict[str, Any] | None, mj: dict[str, Any]) -> str:
    if res is None or mj.get("status") != "compiled":
        return "–"
    if res["status"] == "compared":
        mark = "agrees" if res["agrees"] else "**differs**"
        return f"{mark}, {res['err']:.1e} ({res['worst']})"
    if res["status"] == "refused":
        return "refused"
    if res["status"] == "layout":
        return f"**joints differ**: {res['detail']}"
    return f"**error**: {res.get('detail', '')}"


def _md_escape(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def write_markdown(rows: list[tuple[str, str, dict[str, Any]]], elapsed: float) -> str:
    compiled = [r for r in rows if r[2].get("mujoco", {}).get("status") == "compiled"]
    fd_ok = sum(1 for r in compiled if r[2]["featherdyn"].get("agrees"))
    pin_ok = sum(1 for r in compiled if r[2]["pinocchio"].get("agrees"))
    vers = ", ".join(f"{k} {v}" for k, v in _versions().items())
    lines = [
        "# MJCF models shipped in Python packages: featherdyn and Pinocchio against MuJoCo",
        "",
        f"Generated by `{COMMAND}` on {datetime.date.today().isoformat()} ({elapsed:.0f} s; Python "
        f"{platform.python_version()}; {vers}). Do not edit by hand: re-run the script.",
        "",
        f"Every `*.xml` whose root element is `<mujoco>` in the installed distributions. For each model MuJoCo "
        f"compiles, featherdyn (`fd.load_mjcf`) and Pinocchio (`pinocchio.buildModelFromMJCF`) are compared with "
        f"MuJoCo's compiled model at {SAMPLES} seeded random configurations: total mass of the moving bodies, "
        f"`M(q)` (`mj_fullM`) and the gravity torques (`qfrc_bias` at `qvel = 0`), as the largest relative error "
        f"`max|x − x_mj| / max|x_mj|`. Agreement: {RTOL:g} relative, {MESH_RTOL:g} for models with mesh geoms "
        f"(MuJoCo keeps a mesh's inertia in a principal frame from an iterative eigensolver). Joints are mapped by "
        f"name (Pinocchio's `Composite_X` is the joints of X's body); quaternions and free-joint velocities are "
        f"converted (featherdyn's `featherdyn.conventions` MuJoCo converters; for Pinocchio `(x, y, z, w)` and "
        f"`[v; ω]` in the body frame). Each reason is a measurement (layouts, gravity vectors, MuJoCo recompiled "
        f"with zero armature or without some geoms' mass), or says \"unexplained\".",
        "",
        f"**Summary: {len(rows)} model files, {len(compiled)} standalone models; featherdyn agrees with MuJoCo on "
        f"{fd_ok}; Pinocchio on {pin_ok}.**",
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
    args = parser.parse_args(argv)
    if args.one is not None:
        print(json.dumps(survey_one(args.one)))
        return 0
    t0 = time.perf_counter()
    models = [t for t in find_models() if args.filter in str(t[2])]
    with ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda t: _run_worker(t[2], args.timeout), models))
    rows = [(dist, rel, res) for (dist, rel, _), res in zip(models, results, strict=True)]
    text = write_markdown(rows, time.perf_counter() - t0)
    if args.out == "-":
        sys.stdout.write(text)
    else:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}: {text.splitlines()[8 if len(text.splitlines()) > 8 else -1]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
