"""The flat, read-only arrays of a :class:`~featherdyn.Model` that the compiled core reads (private).

Built once per model (:func:`model_view`, cached on the model as ``model._core``)
and copied into a ``featherdyn.core._core.Model``, whose C++ side is the
``ModelView`` struct of arrays (``cpp/model_view.hpp``). Per body ``i``:

* ints `(5, nb)` int32: parent ``λ(i)``, joint type (``JOINT_TYPES``), ``idx_q``, ``idx_v``, ``nv_i``;
* reals, field after field: joint placement ``Xtree`` rotation `(nb, 9)` (row-major) and
  translation `(nb, 3)`, mass `(nb,)`, ``h = m c`` `(nb, 3)`, ``Ī = I_c − m [c]×²`` about the body
  origin `(nb, 6)` (xx, xy, xz, yy, yz, zz), joint axis or plane normal `(nb, 3)`, plane basis
  ``[e1 e2 n]`` `(nb, 9)` (row-major), and for revolute and planar joints ``Xtree_R [a]×`` and
  ``Xtree_R [a]×²`` `(nb, 9)` each (so the joint rotation needs no matrix product);

per model gravity `(3,)`, the ABA singularity tolerance
``tolerances.SINGULAR_PIVOT_RTOL ×`` the largest entry of any body's spatial inertia matrix
(the reference's rule, ``algorithms/aba.py``) and the float64 unit-quaternion tolerance
``tolerances.QUATERNION_NORM``; per frame
its body (int32, ``-1`` = world) and placement (rotation `(nf, 9)`, then translation `(nf, 3)`);
per degree of freedom the armature ``model.armature`` `(nv,)` (zero when the model has none).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..joints import FreeFlyerJoint, Joint, PlanarJoint, PrismaticJoint, RevoluteJoint, SphericalJoint
from ..model import Model
from ..tolerances import QUATERNION_NORM, SINGULAR_PIVOT_RTOL

__all__ = ["JOINT_TYPES", "CoreHandle", "model_view"]

#: joint type codes (``cpp/model_view.hpp``: ``JointType``)
JOINT_TYPES: dict[type[Joint], int] = {
    RevoluteJoint: 0, PrismaticJoint: 1, SphericalJoint: 2, FreeFlyerJoint: 3, PlanarJoint: 4,
}


def _build(model: Model, core: Any) -> Any:
    nb = model.nbodies
    try:
        jtype = [JOINT_TYPES[type(j)] for j in model.joints]
    except KeyError as exc:
        raise NotImplementedError(f"featherdyn.core has no kernel for {exc.args[0].__name__}") from None
    ints = np.array([model.parents, jtype, model.idx_q, model.idx_v, model.nvs], dtype=np.int32).reshape(5 * nb)
    pl, inertias = model.joint_placements, model.inertias
    m = np.asarray(inertias.mass, dtype=np.float64).reshape(nb)
    c = np.asarray(inertias.com, dtype=np.float64).reshape(nb, 3)
    Ic = np.asarray(inertias.inertia_com, dtype=np.float64).reshape(nb, 3, 3)
    # Ī = I_c − m [c]×² = I_c + m (|c|² 1 − c cᵀ)
    Ibar = Ic + m[:, None, None] * (np.einsum("ij,ij->i", c, c)[:, None, None] * np.eye(3) - c[:, :, None] * c[:, None, :])
    axis = np.zeros((nb, 3))
    basis = np.zeros((nb, 9))
    for i, joint in enumerate(model.joints):
        if isinstance(joint, (RevoluteJoint, PrismaticJoint)):
            axis[i] = joint.axis
        elif isinstance(joint, PlanarJoint):
            axis[i] = joint.normal
            basis[i] = joint.basis.reshape(9)
    # Xtree_R [a]× and Xtree_R [a]×² for revolute and planar joints (cpp/joints.hpp: rotate_about_axis)
    Rt = np.asarray(pl.rotation, dtype=np.float64).reshape(nb, 3, 3)
    K = np.zeros((nb, 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    K = K - np.swapaxes(K, -1, -2)
    rotating = np.array([isinstance(j, (RevoluteJoint, PlanarJoint)) for j in model.joints], dtype=bool).reshape(nb)
    RK = np.where(rotating[:, None, None], Rt @ K, 0.0)
    RK2 = np.where(rotating[:, None, None], Rt @ (K @ K), 0.0)
    reals = np.concatenate([
        np.asarray(pl.rotation, dtype=np.float64).reshape(nb * 9),
        np.asarray(pl.translation, dtype=np.float64).reshape(nb * 3),
        m,
        (m[:, None] * c).reshape(nb * 3),
        Ibar[:, [0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]].reshape(nb * 6),
        axis.reshape(nb * 3),
        basis.reshape(nb * 9),
        RK.reshape(nb * 9),
        RK2.reshape(nb * 9),
    ])
    scale = max((float(np.max(np.abs(inertias[i].matrix()))) for i in range(nb)), default=1.0)
    frames = model.frames
    frame_body = np.array([f.body for f in frames], dtype=np.int32)
    frame_reals = np.concatenate([
        np.array([np.asarray(f.placement.rotation, dtype=np.float64).reshape(9) for f in frames]).reshape(-1),
        np.array([np.asarray(f.placement.translation, dtype=np.float64) for f in frames]).reshape(-1),
    ]) if frames else np.zeros(0)
    armature = getattr(model, "armature", None)
    armature = np.zeros(model.nv) if armature is None else np.array(armature, dtype=np.float64).reshape(model.nv)
    return core.Model(nb, model.nq, model.nv, ints, np.ascontiguousarray(reals),
                      np.ascontiguousarray(model.gravity, dtype=np.float64), SINGULAR_PIVOT_RTOL * scale,
                      QUATERNION_NORM.of(np.float64), frame_body, np.ascontiguousarray(frame_reals), armature)


class CoreHandle:
    """What the wrappers need of a model on every call: the core's ``Model`` and the sizes."""

    __slots__ = ("cm", "frames", "nb", "nq", "nv", "shape_J", "shape_M")

    def __init__(self, model: Model, cm: Any) -> None:
        self.cm = cm
        self.nb, self.nq, self.nv = model.nbodies, model.nq, model.nv
        #: result shapes, built once rather than per call
        self.shape_M, self.shape_J = (model.nv, model.nv), (6, model.nv)
        #: frame name → index (the first frame of a name, as ``model.frame_id``)
        self.frames = model._frame_index


def model_view(model: Model, core: Any) -> CoreHandle:
    """The :class:`CoreHandle` of ``model``, built on first use and kept on the model as ``model._core``."""
    try:
        handle: CoreHandle = model._core
        return handle
    except AttributeError:
        pass
    handle = CoreHandle(model, _build(model, core))
    object.__setattr__(model, "_core", handle)
    return handle
