"""A :class:`~featherdyn.Model` flattened into the plain arrays the kernels read (private, NumPy only).

Nothing here imports Numba.

Per body ``i`` (row ``i``):

``BI`` `(7 nb,)` int64, row ``i`` at ``7 i``
    ``[parent λ(i), joint code, idx_q, idx_v, nv_i, nq_i, unit]``, ``unit`` = the
    index 0…5 of the one non-zero (±1) of ``S_i`` when ``S_i`` is a signed unit
    column (a revolute or prismatic joint along ±x, ±y, ±z), else ``-1``.
``BF`` `(34 nb,)` float64, row ``i`` at ``34 i``
    ``[Xtree rotation (9, row-major) | Xtree translation (3) | m | h = m c (3) |
    Ī = I_c − m [c]×² about the body origin (xx, xy, xz, yy, yz, zz) | joint axis or
    plane normal (3) | plane basis [e1 e2 n] (9, row-major)]`` — the inertia as
    the ten standard parameters ``(m, h, Ī)``.

Per model: ``G`` `(4,)` float64 ``[g_x, g_y, g_z, ABA singularity scale]``;
per frame: ``FB`` `(nf,)` int64 the body (``-1`` = world) and ``FR`` `(12 nf,)`
its placement in that body (rotation row-major, translation), frame ``k`` at ``12 k``.

All of them are views of one C-contiguous float64 array (:func:`pack`), so a
kernel call can pass the model as one argument, and the kernels are typed (and
compiled) once for all models. The arrays are writable because Numba checks
the type of a read-only argument on a slower path (about 0.07 µs a call); they
are private and never written. The per-body tables are flat so that the
kernels address everything by offset and create no array views (a view costs
reference counting in Numba, about half the run time of a small model).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD
from ..joints import FreeFlyerJoint, Joint, PlanarJoint, PrismaticJoint, RevoluteJoint, SphericalJoint
from ..model import Model
from ..tolerances import SINGULAR_PIVOT_RTOL

__all__ = ["ModelArrays", "model_arrays", "JOINT_CODES"]

# joint codes (BI column JT); REV_X/Y/Z are revolute joints about ±e_x, ±e_y, ±e_z
REV, REV_X, REV_Y, REV_Z, PRIS, SPH, FF, PLANAR = range(8)
JOINT_CODES = {"revolute": REV, "revolute_x": REV_X, "revolute_y": REV_Y, "revolute_z": REV_Z,
               "prismatic": PRIS, "spherical": SPH, "free_flyer": FF, "planar": PLANAR}

# BI columns
PARENT, JT, IQ, IV, NV, NQ, UNIT = range(7)
NBI = 7
# BF columns
XR, XP, MASS, H, IBAR, AX, PB = 0, 9, 12, 13, 16, 22, 25
NBF = 34
# reference-frame codes of the Jacobian kernel
LOCAL_CODE, WORLD_CODE, LWA_CODE = LOCAL.code, WORLD.code, LOCAL_WORLD_ALIGNED.code

#: ABA's singularity rule (defined in :mod:`featherdyn.tolerances`)
SINGULAR_RTOL = SINGULAR_PIVOT_RTOL


def _joint_code(joint: Joint) -> int:
    if isinstance(joint, RevoluteJoint):
        nz = np.flatnonzero(joint.axis)
        if len(nz) == 1 and abs(joint.axis[nz[0]]) == 1.0:
            return (REV_X, REV_Y, REV_Z)[int(nz[0])]
        return REV
    if isinstance(joint, PrismaticJoint):
        return PRIS
    if isinstance(joint, SphericalJoint):
        return SPH
    if isinstance(joint, FreeFlyerJoint):
        return FF
    if isinstance(joint, PlanarJoint):
        return PLANAR
    raise NotImplementedError(f"the compiled engine has no kernel for {type(joint).__name__}")


def _unit_column(joint: Joint) -> int:
    """The index of the ±1 in ``S`` when it is a signed unit column, else ``-1``."""
    if isinstance(joint, (RevoluteJoint, PrismaticJoint)):
        nz = np.flatnonzero(joint.axis)
        if len(nz) == 1 and abs(joint.axis[nz[0]]) == 1.0:
            return int(nz[0]) + (0 if isinstance(joint, RevoluteJoint) else 3)
    return -1


@dataclass(frozen=True, eq=False)
class ModelArrays:
    """The flat arrays of one model (see the module docstring) and its sizes."""

    BI: np.ndarray
    BF: np.ndarray
    G: np.ndarray
    FB: np.ndarray
    FR: np.ndarray
    nb: int
    nq: int
    nv: int
    #: `(0, 6)`: "no external forces"
    no_fext: np.ndarray
    #: everything above in one float64 array (see :func:`pack`); the arrays above are views of it
    packed: np.ndarray

    def digest(self) -> str:
        """A hex digest of the model's arrays (two models with equal digests compute the same)."""
        return hashlib.sha256(self.packed.tobytes()).hexdigest()[:24]


def model_arrays(model: Model) -> ModelArrays:
    """Flatten ``model`` (see the module docstring) into fresh arrays."""
    nb = model.nbodies
    BI = np.zeros((nb, NBI), dtype=np.int64)
    BF = np.zeros((nb, NBF), dtype=np.float64)
    pl, I = model.joint_placements, model.inertias
    for i, joint in enumerate(model.joints):
        BI[i] = (model.parents[i], _joint_code(joint), model.idx_q[i], model.idx_v[i], model.nvs[i], model.nqs[i],
                 _unit_column(joint))
        if isinstance(joint, (RevoluteJoint, PrismaticJoint)):
            BF[i, AX : AX + 3] = joint.axis
        elif isinstance(joint, PlanarJoint):
            BF[i, AX : AX + 3] = joint.normal
            BF[i, PB : PB + 9] = joint.basis.reshape(9)
    # every body at once (a per-body loop over the batched values cost ~0.3 ms a body)
    BF[:, XR : XR + 9] = np.asarray(pl.rotation, dtype=np.float64).reshape(nb, 9)
    BF[:, XP : XP + 3] = np.asarray(pl.translation, dtype=np.float64).reshape(nb, 3)
    m = np.asarray(I.mass, dtype=np.float64).reshape(nb)
    c = np.asarray(I.com, dtype=np.float64).reshape(nb, 3)
    Ic = np.asarray(I.inertia_com, dtype=np.float64).reshape(nb, 3, 3)
    # Ī = I_c − m [c]×² = I_c + m (|c|² 1 − c cᵀ)
    cc = c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1] + c[:, 2] * c[:, 2]
    Ibar = Ic + m[:, None, None] * (cc[:, None, None] * np.eye(3) - c[:, :, None] * c[:, None, :])
    BF[:, MASS] = m
    BF[:, H : H + 3] = m[:, None] * c
    BF[:, IBAR : IBAR + 6] = Ibar[:, [0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]]
    # the reference ABA's scale: the largest entry of any body's spatial inertia matrix
    scale = float(np.max(np.abs(I.matrix()))) if nb else 1.0
    G = np.array([*np.asarray(model.gravity, dtype=np.float64), scale])
    nf = len(model.frames)
    FB = np.array([f.body for f in model.frames], dtype=np.int64).reshape(nf)
    FR = np.zeros((nf, 12))
    for k, f in enumerate(model.frames):
        FR[k, :9] = np.asarray(f.placement.rotation, dtype=np.float64).reshape(9)
        FR[k, 9:] = np.asarray(f.placement.translation, dtype=np.float64)
    packed = pack(nb, model.nq, model.nv, BI.reshape(-1), BF.reshape(-1), G, FB, FR.reshape(-1))
    # the separate arrays are views of the packed one, so that every kernel sees the same types
    ints = packed.view(np.int64)
    o = ints[4 : PACK_HEADER]
    return ModelArrays(ints[o[0] : o[1]], packed[o[1] : o[2]], packed[o[2] : o[3]], ints[o[3] : o[4]],
                       packed[o[4] : o[5]], nb, model.nq, model.nv, np.zeros((0, 6)), packed)


#: header of the packed array (int64 bit patterns): sizes, then offsets of BI, BF, G, FB, FR and the workspace
PACK_HEADER = 10

# kernel workspaces: entries per body of each algorithm, plus a fixed tail of scratch
WS_FK = 12
WS_RNEA = 30
WS_CRBA = 58
WS_ABA = 150
WS_TAIL = 160


def workspace_size(width: int, nb: int) -> int:
    """Entries of the flat workspace of a kernel whose per-body width is ``width``."""
    return width * nb + WS_TAIL


def pack(nb: int, nq: int, nv: int, BI: np.ndarray, BF: np.ndarray, G: np.ndarray, FB: np.ndarray,
         FR: np.ndarray) -> np.ndarray:
    """One float64 array holding every model array, so that a kernel call passes the model as one argument.

    ``[nb, nq, nv, nf, o_BI, o_BF, o_G, o_FB, o_FR, o_W | BI | BF | G | FB | FR]``; the header,
    ``BI`` and ``FB`` are int64 bit patterns (read through ``packed.view(np.int64)``). ``o_W`` is
    where a workspace starts: :func:`with_workspace` appends one.
    """
    parts = [BI.view(np.float64), BF, G, FB.view(np.float64), FR]
    offsets, o = [], PACK_HEADER
    for p in parts:
        offsets.append(o)
        o += len(p)
    header = np.array([nb, nq, nv, len(FB), *offsets, o], dtype=np.int64).view(np.float64)
    return np.concatenate([header, *parts])


def with_workspace(packed: np.ndarray, nb: int, nv: int) -> np.ndarray:
    """A copy of ``packed`` followed by a workspace large enough for every single-state entry point."""
    return np.concatenate([packed, np.zeros(workspace_size(WS_ABA, nb) + nv)])
