"""MuJoCo as a second oracle of ``featherdyn verify`` (``--oracle mujoco|both``).

The same file is compiled by MuJoCo (``mujoco.MjModel``: MJCF as is; a URDF
through MuJoCo's own URDF importer) and loaded by featherdyn, joints are
matched by name, and at seeded random states the rigid-body quantities are
compared, MuJoCo's numbers converted to featherdyn's layout
(:mod:`featherdyn.conventions.mujoco`):

* total mass of the moving bodies, armature ``dof_armature``;
* each body's spatial inertia in the world frame (MuJoCo's bodies welded to
  one featherdyn body summed: ``xipos``, ``ximat``, ``body_inertia``);
* ``M(q)`` (``mj_fullM``, armature included), gravity torques
  (``qfrc_bias`` at ``qvel = 0``), inverse dynamics ``qfrc_bias + M qacc``,
  forward dynamics (``mj_forward`` with ``qfrc_applied = τ`` and contacts,
  equality constraints, passive forces and actuators disabled: only the tree).

What MuJoCo's URDF importer refuses or builds differently (stated in the
error, never compared silently): meshes it cannot find (the importer is
given the URDF without ``<visual>``/``<collision>``, which do not enter the
dynamics), moving links without mass or inertia (MuJoCo requires them
positive), inertias that violate the triangle inequality, and
``--floating-base`` (the importer has no free joint: compare MJCF for that).
A free joint with a non-zero armature differs by construction (MuJoCo applies
it to its own ``[v̇_world; ω̇_body]``, featherdyn to the body-frame ``[ω̇; v̇]``).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from ..api import aba, crba, forward_kinematics, generalized_gravity, rnea
from ..configuration import random_configuration
from ..conventions import mujoco as _conv
from ..errors import MissingDependencyError, ModelError
from ..model import Model
from .dynamics import forward_dynamics_result
from .report import CheckResult, PairedRows, compare

__all__ = ["require_mujoco", "mujoco_version", "compile_mujoco", "mujoco_checks", "full_mass_matrix"]

GROUP = "mujoco"


def require_mujoco() -> Any:
    """The ``mujoco`` module, or :class:`MissingDependencyError` with the install command."""
    try:
        import mujoco
    except ImportError:
        raise MissingDependencyError("--oracle mujoco needs MuJoCo: pip install mujoco") from None
    return mujoco


def mujoco_version() -> str:
    """MuJoCo's version, or ``"not installed"``."""
    try:
        import mujoco
    except ImportError:
        return "not installed"
    return str(mujoco.__version__)


_GEOMETRY = re.compile(r"<(visual|collision)\b.*?</\1\s*>|<(visual|collision)\b[^>]*/>", re.S)


def compile_mujoco(path: Path, fmt: str) -> Any:
    """MuJoCo's model of ``path`` (``fmt``: ``"mjcf"`` or ``"urdf"``; a URDF without its geometry).

    Raises:
        ModelError: MuJoCo refuses the file (its own words, and what featherdyn does about it).
    """
    mujoco = require_mujoco()
    try:
        if fmt == "mjcf":
            return mujoco.MjModel.from_xml_path(str(path))
        text = _GEOMETRY.sub("", path.read_text(encoding="utf-8"))
        return mujoco.MjModel.from_xml_string(text)
    except ValueError as exc:
        raise ModelError(f"{path}: MuJoCo does not compile it ({' '.join(str(exc).split())}); "
                         "nothing was compared with MuJoCo") from None


def _name(m: Any, kind: Any, index: int) -> str:
    import mujoco

    return mujoco.mj_id2name(m, kind, index) or ""


def _joint_names(m: Any, model: Model) -> list[str]:
    """MuJoCo's joint names; an unnamed one as featherdyn names it (``BODY/jointK``, ``BODY/free``)."""
    import mujoco

    out = []
    for j in range(m.njnt):
        name = _name(m, mujoco.mjtObj.mjOBJ_JOINT, j)
        if not name:
            b = int(m.jnt_bodyid[j])
            body = _name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
            name = f"{body}/joint{j - int(m.body_jntadr[b])}"
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE and name not in model.joint_names:
                name = f"{body}/free"
        out.append(name)
    return out


class _Layout:
    """featherdyn's (q, v) ↔ MuJoCo's (qpos, qvel): the MJCF converters when the layouts coincide, a
    permutation of one-dof joints for a URDF."""

    def __init__(self, model: Model, m: Any, fmt: str) -> None:
        names = _joint_names(m, model)
        missing = sorted(set(model.joint_names) - set(names))
        if missing or len(names) != len(model.joint_names):
            raise ModelError(f"MuJoCo's model has other joints than featherdyn's (featherdyn only: {missing[:5]}; "
                             f"MuJoCo {len(names)}, featherdyn {len(model.joint_names)})")
        self.model, self.same = model, fmt == "mjcf"
        if self.same:
            return
        if any(j.nq != 1 or j.nv != 1 for j in model.joints):
            raise ModelError("--oracle mujoco on a URDF compares one-dof joints only (MuJoCo's URDF importer has no "
                             "free joint; for a floating base compare an MJCF model)")
        self.perm = np.array([int(m.jnt_dofadr[names.index(n)]) for n in model.joint_names])

    def q_to(self, q: np.ndarray) -> np.ndarray:
        if self.same:
            return np.asarray(_conv.q_to_mujoco(self.model, q))
        out = np.empty_like(q)
        out[self.perm] = q
        return out

    def v_from(self, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        """featherdyn's velocity of MuJoCo's ``qvel``."""
        return np.asarray(_conv.v_from_mujoco(self.model, qpos, qvel)) if self.same else qvel[self.perm]

    def a_from(self, qpos: np.ndarray, qvel: np.ndarray, qacc: np.ndarray) -> np.ndarray:
        """featherdyn's acceleration of MuJoCo's ``qacc`` at the velocity ``qvel``."""
        return np.asarray(_conv.a_from_mujoco(self.model, qpos, qvel, qacc)) if self.same else qacc[self.perm]

    def tau_from(self, qpos: np.ndarray, qfrc: np.ndarray) -> np.ndarray:
        """featherdyn's joint forces of MuJoCo's generalized forces ``qfrc``."""
        return np.asarray(_conv.tau_from_mujoco(self.model, qpos, qfrc)) if self.same else qfrc[self.perm]

    def tau_to(self, q: np.ndarray, tau: np.ndarray) -> np.ndarray:
        if self.same:
            return np.asarray(_conv.tau_to_mujoco(self.model, q, tau))
        out = np.empty_like(tau)
        out[self.perm] = tau
        return out

    def matrix_to(self, q: np.ndarray, M: np.ndarray) -> np.ndarray:
        if self.same:
            return np.asarray(_conv.joint_matrix_to_mujoco(self.model, q, M))
        out = np.empty_like(M)
        out[np.ix_(self.perm, self.perm)] = M
        return out


def _spatial(mass: float, com: np.ndarray, Ic: np.ndarray) -> np.ndarray:
    """The 6×6 ``[ω; v]`` inertia about the world origin of a body with ``mass``, centre ``com``, ``Ic``."""
    c = np.array([[0, -com[2], com[1]], [com[2], 0, -com[0]], [-com[1], com[0], 0]])
    return np.block([[Ic + mass * c @ c.T, mass * c], [mass * c.T, mass * np.eye(3)]])


def _body_of(model: Model, name: str) -> int | None:
    """featherdyn's body carrying the MJCF body or URDF link ``name`` (``None``: welded to the world or absent)."""
    for kind in ("body", "link"):
        try:
            return model.frames[model.frame_id(name, kind=kind)].body
        except ModelError:
            continue
    return None


def full_mass_matrix(mujoco: Any, m: Any, d: Any) -> np.ndarray:
    """``mj_fullM`` (MuJoCo 3 takes ``(m, dst, d.qM)``, MuJoCo 4 ``(m, d, dst)``)."""
    M = np.zeros((m.nv, m.nv))
    if hasattr(d, "qM"):
        mujoco.mj_fullM(m, M, d.qM)
    else:
        mujoco.mj_fullM(m, d, M)
    return M


def mujoco_checks(model: Model, m: Any, fmt: str, *, samples: int = 10, seed: int = 0,
                  tol: float = 1e-9) -> list[CheckResult]:
    """featherdyn's ``model`` against MuJoCo's ``m`` of the same file (module docstring), ``samples`` states."""
    mujoco = require_mujoco()
    layout = _Layout(model, m, fmt)
    d = mujoco.MjData(m)
    off = 0  # only the tree: no constraints, springs, dampers, actuators (names present in this MuJoCo)
    for flag in ("mjDSBL_CONSTRAINT", "mjDSBL_PASSIVE", "mjDSBL_SPRING", "mjDSBL_DAMPER", "mjDSBL_ACTUATION"):
        off |= int(getattr(mujoco.mjtDisableBit, flag, 0))
    m.opt.disableflags |= off
    moving = [b for b in range(1, m.nbody) if m.body_dofnum[m.body_weldid[b]] > 0]
    out = [compare(GROUP, "total mass vs MuJoCo body_mass (moving bodies)", [model.total_mass],
                   [float(sum(m.body_mass[b] for b in moving))], tol)]
    arm = np.zeros(model.nv) if model.armature is None else np.asarray(model.armature)
    arm_mj = np.asarray(m.dof_armature)  # per dof: MJCF layouts coincide, a URDF's are permuted
    out.append(compare(GROUP, "armature vs dof_armature", [arm], [arm_mj if layout.same else arm_mj[layout.perm]],
                       tol))
    rng = np.random.default_rng(seed)
    paired = PairedRows()
    add = paired.add
    fwd: dict[str, list[np.ndarray]] = {}

    bodies = [(b, _body_of(model, _name(m, mujoco.mjtObj.mjOBJ_BODY, b))) for b in range(1, m.nbody)]
    for _ in range(samples):
        q = random_configuration(model, rng)
        qpos = layout.q_to(q)
        d.qpos[:] = qpos
        d.qvel[:] = 0
        d.qfrc_applied[:] = 0
        mujoco.mj_forward(m, d)
        kin = forward_kinematics(model, q)
        ours_I, theirs_I = [], []
        per_body: dict[int, np.ndarray] = {}
        for b, i in bodies:
            if i is None or i < 0:
                continue
            R = d.ximat[b].reshape(3, 3)
            per_body[i] = per_body.get(i, 0) + _spatial(m.body_mass[b], d.xipos[b], R @ np.diag(m.body_inertia[b]) @ R.T)
        for i, I6 in sorted(per_body.items()):
            ours_I.append(kin.placements[i].apply(model.inertias[i]).matrix())
            theirs_I.append(I6)
        if ours_I:
            add("body spatial inertias (world) vs xipos, ximat, body_inertia", np.stack(ours_I), np.stack(theirs_I))
        add("crba vs mj_fullM", layout.matrix_to(q, crba(model, q)), full_mass_matrix(mujoco, m, d))
        add("generalized_gravity vs qfrc_bias (qvel = 0)", layout.tau_to(q, generalized_gravity(model, q)),
            d.qfrc_bias.copy())
        qvel, qacc, frc = rng.normal(size=(3, m.nv))
        d.qvel[:] = qvel
        mujoco.mj_forward(m, d)
        Mmj = full_mass_matrix(mujoco, m, d)
        v = layout.v_from(qpos, qvel)
        a = layout.a_from(qpos, qvel, qacc)
        add("rnea vs qfrc_bias + M qacc", layout.tau_to(q, rnea(model, q, v, a)), d.qfrc_bias + Mmj @ qacc)
        d.qfrc_applied[:] = frc
        mujoco.mj_forward(m, d)
        tau = layout.tau_from(qpos, frc)
        for key, x in (("q", q), ("v", v), ("tau", tau), ("M", crba(model, q)), ("ddq", aba(model, q, v, tau)),
                       ("ddq_ref", layout.a_from(qpos, qvel, np.asarray(d.qacc)))):
            fwd.setdefault(key, []).append(x)
    out += paired.compare(GROUP, tol)
    # forward dynamics judged like Pinocchio's ABA: backward error, and forward error within cond(M)
    F = {k: np.stack(x) for k, x in fwd.items()}
    out.append(forward_dynamics_result(GROUP, "aba vs mj_forward qacc (constraints, passive forces, actuators off)",
                                       model, F["q"], F["v"], F["tau"], F["ddq"], F["ddq_ref"], F["M"], tol))
    return out
