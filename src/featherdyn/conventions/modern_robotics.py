"""Lynch & Park, *Modern Robotics*: twists, wrenches and the adjoint maps.

Modern Robotics orders twists ``V = [ω; v]`` and wrenches ``F = [m; f]``
angular first, with the reference point at the origin of the frame of
expression: the numbers are featherdyn's, unchanged. What converts is
notation: ``[Ad_T]`` is the motion transform ``X``, ``[Ad_T]⁻ᵀ`` the force
transform ``X*``, ``[ad_V]`` the motion cross product ``crm(V)``; a body twist
``V_b`` and a spatial twist ``V_s`` are one motion in two frames.

Sources: Lynch & Park, *Modern Robotics* (2017) ch. 3 and 8; RBDA (2008) ch. 2.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..frames import Frame
from ..spatial import PluckerTransform, SpatialForce, SpatialMotion, crm
from ._common import as_transform, force_array, foreign_array, motion_array

__all__ = [
    "ad_matrix",
    "adjoint_matrix",
    "body_twist_to_spatial_twist",
    "spatial_twist_to_body_twist",
    "twist_from_mr",
    "twist_to_mr",
    "wrench_from_mr",
    "wrench_to_mr",
    "wrench_transform_matrix",
]


def twist_to_mr(m: SpatialMotion | ArrayLike) -> np.ndarray:
    """A featherdyn motion as a Modern Robotics twist: the numbers do not change.

    Modern Robotics writes twists ``V = [ω; v]``, angular first like
    Featherstone, and its ``v`` is the velocity of the body point at the
    origin of the frame of expression. So a featherdyn motion expressed in
    the world frame *is* MR's spatial twist ``V_s`` (reference point the
    space origin), and one expressed in the body frame is MR's body twist
    ``V_b``.

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)`.

    Returns:
        `(..., 6)` (a copy)::

            V = [ω; v] = m

    Source: Lynch & Park (2017) §3.3.2, eqs. (3.70) and (3.72).
    """
    return np.array(motion_array(m, "m"))


def twist_from_mr(V: ArrayLike, frame: Frame = None) -> SpatialMotion:
    """A Modern Robotics twist ``[ω; v]`` as a featherdyn motion (same numbers, see :func:`twist_to_mr`).

    Args:
        V: `(..., 6)` MR twist ``[ω; v]``.
        frame: optional frame tag (``V_s``: the space frame; ``V_b``: the body frame).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            m = V

    Source: Lynch & Park (2017) §3.3.2.
    """
    return SpatialMotion.from_vector(foreign_array(V, "V", "Modern Robotics [ω; v]"), frame)


def wrench_to_mr(f: SpatialForce | ArrayLike) -> np.ndarray:
    """A featherdyn force as a Modern Robotics wrench: the numbers do not change.

    MR writes a wrench ``F = [m; f]``, moment first, the moment taken about
    the origin of the frame of expression, exactly featherdyn's ``[n_O; f]``.

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)`.

    Returns:
        `(..., 6)` (a copy)::

            F = [m; f] = [n_O; f]

    Source: Lynch & Park (2017) §3.4, eq. (3.95).
    """
    return np.array(force_array(f, "f"))


def wrench_from_mr(F: ArrayLike, frame: Frame = None) -> SpatialForce:
    """A Modern Robotics wrench ``[m; f]`` as a featherdyn force (same numbers, see :func:`wrench_to_mr`).

    Args:
        F: `(..., 6)` MR wrench ``[m; f]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = F

    Source: Lynch & Park (2017) §3.4.
    """
    return SpatialForce.from_vector(foreign_array(F, "F", "Modern Robotics [m; f]"), frame)


def adjoint_matrix(T: PluckerTransform | ArrayLike) -> np.ndarray:
    """Modern Robotics ``[Ad_T]``: featherdyn's motion transform ``X.matrix()``.

    ``T`` = ``[[R, p], [0, 1]]`` is the pose of frame b in frame a (``T_ab``);
    as a :class:`PluckerTransform` it is ``PluckerTransform(R, p)``, and
    ``[Ad_T]`` maps twists in b-coordinates to a-coordinates.

    Args:
        T: :class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix.

    Returns:
        `(..., 6, 6)`::

            [Ad_T] = [[ R,     0 ],   = X
                      [ [p]R,  R ]]

    Source: Lynch & Park (2017) Definition 3.20, eq. (3.83); RBDA (2008) eq. 2.24.
    """
    return as_transform(T, "T").matrix()


def ad_matrix(V: SpatialMotion | ArrayLike) -> np.ndarray:
    """Modern Robotics ``[ad_V]`` (the Lie bracket ``[ad_V1] V2``): featherdyn's ``crm(V)``.

    Args:
        V: :class:`SpatialMotion` or raw `(..., 6)` twist ``[ω; v]``.

    Returns:
        `(..., 6, 6)`::

            [ad_V] = [[ [ω],  0   ],   = crm(V) = [V]×
                      [ [v],  [ω] ]]

    Source: Lynch & Park (2017) Definition 8.2, eq. (8.38); RBDA (2008) eq. 2.31.
    """
    return crm(motion_array(V, "V"))


def wrench_transform_matrix(T: PluckerTransform | ArrayLike) -> np.ndarray:
    """The wrench map of a pose: featherdyn's force transform ``X.dual_matrix()``.

    With ``T = T_ab`` (pose of b in a), Modern Robotics writes
    ``F_b = [Ad_{T_ab}]ᵀ F_a``, so ``F_a = [Ad_{T_ab}]⁻ᵀ F_b`` — featherdyn's
    ``X* = X⁻ᵀ`` of the same pose. It preserves power:
    ``(X V)ᵀ (X* F) = Vᵀ F``.

    Args:
        T: :class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix.

    Returns:
        `(..., 6, 6)`::

            [Ad_T]⁻ᵀ = [[ R,  [p]R ],   = X*
                        [ 0,  R    ]]

    Source: Lynch & Park (2017) §3.4, eq. (3.98); RBDA (2008) eq. 2.25.
    """
    return as_transform(T, "T").dual_matrix()


def body_twist_to_spatial_twist(T: PluckerTransform | ArrayLike, V_b: SpatialMotion | ArrayLike) -> SpatialMotion:
    """Modern Robotics: a body twist ``V_b`` to the spatial twist ``V_s`` of the same motion.

    Args:
        T: the pose ``T_sb`` of the body in the space frame
            (:class:`PluckerTransform` or `(..., 4, 4)` homogeneous matrix).
        V_b: `(..., 6)` body twist ``[ω_b; v_b]`` (:class:`SpatialMotion` or raw).

    Returns:
        :class:`SpatialMotion` `(..., 6)`, the spatial twist::

            V_s = [Ad_{T_sb}] V_b        ([V_s] = Ṫ T⁻¹,  [V_b] = T⁻¹ Ṫ)

    Source: Lynch & Park (2017) eq. (3.84).
    """
    X = as_transform(T, "T")
    vb = V_b if isinstance(V_b, SpatialMotion) else SpatialMotion.from_vector(motion_array(V_b, "V_b"))
    result: SpatialMotion = X.apply(vb)
    return result


def spatial_twist_to_body_twist(T: PluckerTransform | ArrayLike, V_s: SpatialMotion | ArrayLike) -> SpatialMotion:
    """Modern Robotics: a spatial twist ``V_s`` to the body twist ``V_b`` (inverse of :func:`body_twist_to_spatial_twist`).

    Args:
        T: the pose ``T_sb`` (:class:`PluckerTransform` or `(..., 4, 4)`).
        V_s: `(..., 6)` spatial twist (:class:`SpatialMotion` or raw).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            V_b = [Ad_{T_sb}]⁻¹ V_s = [Ad_{T_bs}] V_s

    Source: Lynch & Park (2017) eq. (3.84).
    """
    X = as_transform(T, "T")
    vs = V_s if isinstance(V_s, SpatialMotion) else SpatialMotion.from_vector(motion_array(V_s, "V_s"))
    result: SpatialMotion = X.apply_inverse(vs)
    return result
