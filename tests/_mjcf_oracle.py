"""Comparing a model from featherdyn.load_mjcf with MuJoCo's compiled model of the same XML (the oracle).

Nothing here calls the featherdyn code under test except through its public
functions; MuJoCo's numbers come from ``mujoco`` itself:

* joints mapped by name (MuJoCo's name, or featherdyn's documented name of
  an unnamed joint), their ``qpos``/``qvel`` addresses equal to featherdyn's
  ``idx_q``/``idx_v``;
* total mass of the moving bodies (welded to a body with degrees of freedom);
* per featherdyn body, the world-frame 6×6 spatial inertia against the sum of
  the MuJoCo bodies welded into it (``xipos``, ``ximat``, ``body_inertia``);
* world placements of every MJCF body frame and site (``xpos``/``xmat``,
  ``site_xpos``/``site_xmat``);
* ``M(q)`` (``mj_fullM``, armature included), gravity torques
  (``qfrc_bias`` at ``qvel = 0``) and inverse dynamics
  (``qfrc_bias + M qacc``), converted with featherdyn.conventions' MuJoCo
  converters, at random configurations.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import featherdyn as fd
from featherdyn import conventions as conv

mujoco = __import__("mujoco")


def mj_body_name(m, b: int) -> str:
    return m.body(b).name or f"body{b}"


def mj_joint_names(m, model: fd.Model) -> list[str]:
    """MuJoCo's joint names; an unnamed one as featherdyn documents (``BODY/jointK``, ``BODY/free`` for a
    ``<freejoint/>``, which the compiled model cannot tell from ``<joint type="free"/>``: either is accepted)."""
    out = []
    for j in range(m.njnt):
        name = m.joint(j).name
        if not name:
            b = int(m.jnt_bodyid[j])
            k = j - int(m.body_jntadr[b])
            name = f"{mj_body_name(m, b)}/joint{k}"
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE and name not in model.joint_names:
                name = f"{mj_body_name(m, b)}/free"
        out.append(name)
    return out


def _spatial(mass: float, com: np.ndarray, Ic: np.ndarray) -> np.ndarray:
    """6×6 [ω; v]-ordered inertia about the world origin."""
    c = np.array([[0, -com[2], com[1]], [com[2], 0, -com[0]], [-com[1], com[0], 0]])
    return np.block([[Ic + mass * c @ c.T, mass * c], [mass * c.T, mass * np.eye(3)]])


@dataclass
class Errors:
    worst: dict[str, float] = field(default_factory=dict)

    def add(self, what: str, ours: np.ndarray, ref: np.ndarray, scale: float | None = None) -> None:
        ours, ref = np.asarray(ours, dtype=float), np.asarray(ref, dtype=float)
        s = max(float(np.max(np.abs(ref), initial=0.0)), 1e-300) if scale is None else scale
        err = float(np.max(np.abs(ours - ref), initial=0.0)) / s
        self.worst[what] = max(self.worst.get(what, 0.0), err)

    @property
    def max(self) -> float:
        return max(self.worst.values(), default=0.0)


def compare(model: fd.Model, m, *, samples: int = 3, seed: int = 0, names: list[str] | None = None) -> Errors:
    """Relative errors (per quantity, the largest over ``samples`` random states) of ``model`` against ``m``."""
    errs = Errors()
    d = mujoco.MjData(m)
    names = mj_joint_names(m, model) if names is None else names
    assert len(names) == len(model.joint_names), (names, model.joint_names)
    for j, name in enumerate(names):
        i = model.joint_id(name)
        assert model.idx_q[i] == m.jnt_qposadr[j], (name, model.idx_q[i], m.jnt_qposadr[j])
        assert model.idx_v[i] == m.jnt_dofadr[j], (name, model.idx_v[i], m.jnt_dofadr[j])
    assert model.nq == m.nq and model.nv == m.nv
    # moving: welded to a body with degrees of freedom (a mocap body is welded to itself, without any)
    moving = [b for b in range(1, m.nbody) if m.body_dofnum[m.body_weldid[b]] > 0]
    mass_ref = float(sum(m.body_mass[b] for b in moving))
    errs.add("total mass", model.total_mass, mass_ref)
    errs.add("armature", model.armature, m.dof_armature, max(1.0, float(np.max(np.abs(m.dof_armature), initial=0))))
    rng = np.random.default_rng(seed)
    for _ in range(samples):
        q = fd.random_configuration(model, rng)
        qpos = conv.q_to_mujoco(model, q)
        qvel = rng.normal(size=m.nv)
        qacc = rng.normal(size=m.nv)
        d.qpos[:] = qpos
        d.qvel[:] = 0
        mujoco.mj_forward(m, d)
        # kinematics and per-body inertia (world frame)
        per_body = {}
        scale = 0.0
        for b in range(1, m.nbody):
            fid = body_frame(model, mj_body_name(m, b))
            f = model.frames[fid]
            X = fd.frame_placement(model, q, fid)
            errs.add("body placement", np.concatenate([X.rotation.ravel(), X.translation]),
                     np.concatenate([d.xmat[b], d.xpos[b]]), 1.0 + float(np.max(np.abs(d.xpos[b]))))
            if f.body < 0:
                continue
            R = d.ximat[b].reshape(3, 3)
            I6 = _spatial(m.body_mass[b], d.xipos[b], R @ np.diag(m.body_inertia[b]) @ R.T)
            per_body[f.body] = per_body.get(f.body, 0) + I6
            scale = max(scale, float(np.max(np.abs(I6))))
        kin = fd.forward_kinematics(model, q)
        for i, I6 in per_body.items():
            ours = kin.placements[i].apply(model.inertias[i]).matrix()
            errs.add("body inertia (world)", ours, I6, max(scale, 1e-300))
        for s in range(m.nsite):
            name = m.site(s).name or f"{mj_body_name(m, int(m.site_bodyid[s]))}/site{s - _first_site(m, int(m.site_bodyid[s]))}"
            X = fd.frame_placement(model, q, model.frame_id(name, kind="site"))
            errs.add("site placement", np.concatenate([X.rotation.ravel(), X.translation]),
                     np.concatenate([d.site_xmat[s], d.site_xpos[s]]), 1.0 + float(np.max(np.abs(d.site_xpos[s]))))
        M_mj = full_mass_matrix(m, d)
        g_mj = d.qfrc_bias.copy()
        M = conv.joint_matrix_to_mujoco(model, q, fd.crba(model, q))
        errs.add("M", M, M_mj)
        g = conv.tau_to_mujoco(model, q, fd.generalized_gravity(model, q))
        errs.add("gravity", g, g_mj, max(float(np.max(np.abs(g_mj), initial=0.0)), 1e-12))
        d.qvel[:] = qvel
        mujoco.mj_forward(m, d)
        M_mj = full_mass_matrix(m, d)
        tau_mj = d.qfrc_bias + M_mj @ qacc
        v = conv.v_from_mujoco(model, qpos, qvel)
        a = conv.a_from_mujoco(model, qpos, qvel, qacc)
        for backend in ("reference", "compiled"):
            tau = conv.tau_to_mujoco(model, q, fd.rnea(model, q, v, a, backend=backend))
            errs.add(f"rnea ({backend})", tau, tau_mj)
    return errs


def full_mass_matrix(m, d) -> np.ndarray:
    """``mj_fullM`` of either MuJoCo API (featherdyn.verify.mujoco's wrapper: a call, not a computation)."""
    from featherdyn.verify.mujoco import full_mass_matrix as _full

    return _full(mujoco, m, d)


def body_frame(model: fd.Model, name: str) -> int:
    """The frame of the MJCF body ``name`` (kind ``"body"``, or ``"link"`` for a welded body)."""
    try:
        return model.frame_id(name, kind="body")
    except fd.ModelError:
        return model.frame_id(name, kind="link")


def _first_site(m, b: int) -> int:
    return int(np.flatnonzero(m.site_bodyid == b)[0])
