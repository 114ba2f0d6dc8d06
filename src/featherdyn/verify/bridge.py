"""The bridge between a featherdyn :class:`~featherdyn.Model` and a Pinocchio model.

Joints are mapped **by name**; layouts are converted explicitly, joint by joint:

============  ==========================  ===========================================
joint         featherdyn q / v            Pinocchio q / v
============  ==========================  ===========================================
revolute      θ / θ̇                       θ / θ̇  (continuous: cos θ, sin θ / θ̇)
prismatic     d / ḋ                       d / ḋ
spherical     quat xyzw / ω               quat xyzw / ω
free-flyer    [p, quat xyzw] / [ω; v]     [p, quat xyzw] / [v; ω]
planar        [x, y, θ] / [ω, vx, vy]     [x, y, cos θ, sin θ] / [vx, vy, ω]
============  ==========================  ===========================================

6D vectors and 6-row matrices swap halves (Pinocchio is linear-first).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import conventions
from ..errors import ModelError
from ..joints import FreeFlyerJoint, PlanarJoint, PrismaticJoint, RevoluteJoint, SphericalJoint
from ..model import Model
from .pinocchio import PinModel, require_pinocchio

__all__ = ["pinocchio_model_from", "JointMap", "SWAP6", "to_pin6", "from_pin6", "from_pin6_rows"]

SWAP6 = np.array([3, 4, 5, 0, 1, 2])


def to_pin6(x: np.ndarray) -> np.ndarray:
    """featherdyn `(..., 6)` ``[ang; lin]`` → Pinocchio ``[lin; ang]`` (its own inverse)."""
    return np.asarray(x)[..., SWAP6]


from_pin6 = to_pin6


def from_pin6_rows(m: np.ndarray) -> np.ndarray:
    """Swap the halves of the 6 rows of a `(..., 6, n)` matrix (a Jacobian or momentum matrix).

    Pinocchio returns the `(6, 1)` matrices of a one-DoF model flattened to `(6,)`; such an
    array is read as the one column it is.
    """
    arr = np.asarray(m)
    if arr.ndim == 1:
        arr = arr.reshape(arr.shape[0], 1)
    return arr[..., SWAP6, :]


def pinocchio_model_from(model: Model, *, check_order: bool = True) -> PinModel:
    """A Pinocchio model mirroring ``model`` body by body (same names, placements, inertias, gravity).

    Joint types: revolute → ``JointModelRevoluteUnaligned``, prismatic →
    ``JointModelPrismaticUnaligned``, spherical, free-flyer, planar (normal
    +z only, Pinocchio's planar joint is in the xy plane).

    The armature (``model.armature``) is copied to Pinocchio's ``armature``.

    Pinocchio's CRBA and ABA assume depth-first body numbering (each subtree a
    contiguous index range); featherdyn needs only ``parent[i] < i``. A model
    numbered otherwise raises :class:`ModelError` unless ``check_order=False``
    (then only Pinocchio's RNEA can be trusted on the mirror).
    """
    pin = require_pinocchio()
    for i in range(model.nbodies if check_order else 0):  # Pinocchio's algorithms assume every subtree is a contiguous index range
        sub = model.subtree(i)
        if sub[-1] - sub[0] + 1 != len(sub):
            raise ModelError(
                f"body {model.body_names[i]!r}: its subtree {sub} is not numbered contiguously; Pinocchio needs "
                "depth-first body numbering (add each body's descendants right after it)"
            )
    pm = pin.Model()
    pm.name = model.name
    pm.gravity = pin.Motion(np.array(model.gravity, dtype=float), np.zeros(3))
    ids: list[int] = []
    for i, joint in enumerate(model.joints):
        parent = 0 if model.parents[i] == -1 else ids[model.parents[i]]
        if isinstance(joint, RevoluteJoint):
            jm = pin.JointModelRevoluteUnaligned(np.array(joint.axis))
        elif isinstance(joint, PrismaticJoint):
            jm = pin.JointModelPrismaticUnaligned(np.array(joint.axis))
        elif isinstance(joint, SphericalJoint):
            jm = pin.JointModelSpherical()
        elif isinstance(joint, FreeFlyerJoint):
            jm = pin.JointModelFreeFlyer()
        elif isinstance(joint, PlanarJoint):
            if not np.allclose(joint.normal, [0.0, 0.0, 1.0]):
                raise ModelError(f"joint {model.joint_names[i]!r}: Pinocchio's planar joint needs normal +z")
            jm = pin.JointModelPlanar()
        else:  # pragma: no cover
            raise ModelError(f"joint {model.joint_names[i]!r}: no Pinocchio equivalent for {joint!r}")
        X = model.joint_placements[i]
        jid = pm.addJoint(parent, jm, pin.SE3(np.array(X.rotation), np.array(X.translation)), model.joint_names[i])
        I = model.inertias[i]
        pm.appendBodyToJoint(jid, pin.Inertia(float(I.mass), np.array(I.com), np.array(I.inertia_com)),
                             pin.SE3.Identity())
        ids.append(jid)
    if np.any(model.armature):
        pm.armature = JointMap(model, pm).v_to_pin(np.asarray(model.armature, dtype=np.float64))
    return pm


@dataclass
class _Entry:
    fd_body: int
    pin_joint: int
    kind: str
    continuous: bool


def _pin_names(model: Model, pin_model: PinModel) -> dict[str, str]:
    """Pinocchio's name of each featherdyn joint found there: the same name, except that the free-flyer roots map
    to each other whatever their names (a URDF with a joint ``root_joint`` has featherdyn's free flyer named
    ``root_joint_1`` and Pinocchio's ``root_joint``), in order, when as many are left unmatched on each side."""
    pin_names = list(pin_model.names)[1:]
    taken = set(pin_names)
    out = {n: n for n in model.joint_names if n in taken}
    fd_roots = [n for i, n in enumerate(model.joint_names) if n not in out and model.parents[i] == -1
                and isinstance(model.joints[i], FreeFlyerJoint)]
    pin_roots = [n for jid, n in enumerate(pin_model.names) if jid > 0 and n not in model.joint_names
                 and pin_model.parents[jid] == 0 and pin_model.joints[jid].shortname() == "JointModelFreeFlyer"]
    if fd_roots and len(fd_roots) == len(pin_roots):
        out.update(zip(fd_roots, pin_roots, strict=True))
    return out


class JointMap:
    """Maps configurations, velocities and joint-space matrices between featherdyn and Pinocchio by joint name.

    Args:
        model: the featherdyn model.
        pin_model: a Pinocchio model of the same robot (built from the same URDF,
            or by :func:`pinocchio_model_from`). Its joints (other than the
            universe) must be exactly featherdyn's joints, by name; the free-flyer
            roots (hanging from the world) map to each other whatever their names.
    """

    def __init__(self, model: Model, pin_model: PinModel) -> None:
        self.model = model
        self.pin_model = pin_model
        pin_names = list(pin_model.names)[1:]
        fd_names = list(model.joint_names)
        pin_of = _pin_names(model, pin_model)
        if sorted(pin_of) != sorted(fd_names) or sorted(pin_of.values()) != sorted(pin_names):
            only_fd = sorted(set(fd_names) - set(pin_of))
            only_pin = sorted(set(pin_names) - set(pin_of.values()))
            raise ModelError(f"joints differ between featherdyn and Pinocchio: only in featherdyn {only_fd}, "
                             f"only in Pinocchio {only_pin}")
        self.entries: list[_Entry] = []
        for i, name in enumerate(fd_names):
            jid = pin_model.getJointId(pin_of[name])
            short = pin_model.joints[jid].shortname()
            kind = model.joints[i].kind
            continuous = kind == "revolute" and pin_model.nqs[jid] == 2
            self.entries.append(_Entry(i, jid, kind, continuous))
        #: Pinocchio's joint id of each featherdyn body's joint, `(nb,)`.
        self.joint_ids = [e.pin_joint for e in self.entries]
        # featherdyn v index → Pinocchio v index (a permutation)
        perm = np.empty(model.nv, dtype=int)
        for e in self.entries:
            i, jid = e.fd_body, e.pin_joint
            fv = np.arange(model.idx_v[i], model.idx_v[i] + model.nvs[i])
            pv = np.arange(pin_model.idx_vs[jid], pin_model.idx_vs[jid] + pin_model.nvs[jid])
            if e.kind == "free_flyer":
                pv = pv[SWAP6]
            elif e.kind == "planar":
                pv = pv[[2, 0, 1]]
            if len(fv) != len(pv):
                raise ModelError(f"joint {model.joint_names[i]!r}: featherdyn nv={len(fv)}, Pinocchio nv={len(pv)} "
                                 f"({short})")
            perm[fv] = pv
        self.v_perm = perm  # v_pin[perm] = v_fd

    def q_to_pin(self, q: np.ndarray) -> np.ndarray:
        """featherdyn `(..., nq)` → Pinocchio `(..., pin.nq)`."""
        q = np.asarray(q, dtype=np.float64)
        out = np.zeros(q.shape[:-1] + (self.pin_model.nq,))
        for e in self.entries:
            i, jid = e.fd_body, e.pin_joint
            qi = q[..., self.model.idx_q[i] : self.model.idx_q[i] + self.model.nqs[i]]
            s = self.pin_model.idx_qs[jid]
            if e.continuous:
                out[..., s : s + 2] = conventions.continuous_q_to_pinocchio(qi[..., 0])
            elif e.kind == "planar":
                out[..., s : s + 4] = conventions.planar_q_to_pinocchio(qi)
            else:
                out[..., s : s + qi.shape[-1]] = qi
        return out

    def q_from_pin(self, q_pin: np.ndarray) -> np.ndarray:
        """Pinocchio `(..., pin.nq)` → featherdyn `(..., nq)`."""
        q_pin = np.asarray(q_pin, dtype=np.float64)
        out = np.zeros(q_pin.shape[:-1] + (self.model.nq,))
        for e in self.entries:
            i, jid = e.fd_body, e.pin_joint
            s, t = self.pin_model.idx_qs[jid], self.model.idx_q[i]
            if e.continuous:
                out[..., t] = conventions.continuous_q_from_pinocchio(q_pin[..., s : s + 2])
            elif e.kind == "planar":
                out[..., t : t + 3] = conventions.planar_q_from_pinocchio(q_pin[..., s : s + 4])
            else:
                n = self.model.nqs[i]
                out[..., t : t + n] = q_pin[..., s : s + n]
        return out

    def v_to_pin(self, v: np.ndarray) -> np.ndarray:
        """featherdyn `(..., nv)` (also ``a``, ``τ``) → Pinocchio."""
        v = np.asarray(v, dtype=np.float64)
        out = np.zeros(v.shape)
        out[..., self.v_perm] = v
        return out

    def v_from_pin(self, v_pin: np.ndarray) -> np.ndarray:
        """Pinocchio `(..., nv)` → featherdyn."""
        return np.asarray(v_pin)[..., self.v_perm]

    def matrix_from_pin(self, m_pin: np.ndarray) -> np.ndarray:
        """A joint-space `(..., nv, nv)` matrix from Pinocchio's ordering (a `(1,)` or scalar one of nv=1 too)."""
        arr = np.asarray(m_pin)
        if arr.ndim < 2:
            arr = arr.reshape(self.model.nv, self.model.nv)
        return arr[..., self.v_perm, :][..., :, self.v_perm]

    def columns_from_pin(self, m_pin: np.ndarray) -> np.ndarray:
        """A `(..., k, nv)` matrix (Jacobian-like) with columns from Pinocchio's ordering."""
        return np.asarray(m_pin)[..., self.v_perm]
