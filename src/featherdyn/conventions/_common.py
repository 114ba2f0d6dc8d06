"""Helpers shared by the converters: reading featherdyn values and foreign arrays, the 6D half swap.

Every converter reads its featherdyn argument with :func:`motion_array` /
:func:`force_array` (a typed value or a raw angular-first array, the other
kind refused with a message that names the right function) and its foreign
argument with :func:`foreign_array` (a raw array; featherdyn values and
Pinocchio objects refused). The half swap ``P`` is its own inverse::

    P [a; b] = [b; a],   P = Pᵀ = P⁻¹
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ShapeError, SpatialTypeError
from ..spatial import PluckerTransform, SpatialForce, SpatialInertia, SpatialMotion
from ..spatial.validation import as_array, check_rotation
from ..tolerances import SPATIAL_STRUCTURE

# The half swap [a; b] -> [b; a] of a 6-vector; an involution, so the same
# index array converts in both directions (and for motions and forces alike).
SWAP = np.array([3, 4, 5, 0, 1, 2])


SPATIAL_TYPES = (SpatialMotion, SpatialForce, SpatialInertia, PluckerTransform)


def qualified_type_name(x: object) -> str:
    """``"pinocchio.Motion"``, ``"list"``: the type of a refused argument, with its package unless built in."""
    t = type(x)
    top = t.__module__.split(".")[0]
    return t.__name__ if top == "builtins" else f"{top}.{t.__name__}"


def is_pinocchio_object(x: object) -> bool:
    """Whether ``x`` is an object of Pinocchio's Python bindings (``pin.Motion``, ``pin.SE3``, ...)."""
    return type(x).__module__.split(".")[0] == "pinocchio"


def motion_array(m: SpatialMotion | ArrayLike, name: str) -> np.ndarray:
    """A featherdyn motion (SpatialMotion or raw ``[ω; v]``) as a ``(..., 6)`` array."""
    if isinstance(m, SpatialMotion):
        return m.vector
    if isinstance(m, SpatialForce):
        raise SpatialTypeError(
            f"{name}: expected a motion vector (SpatialMotion or a raw (..., 6) [ω; v] array), got a SpatialForce; "
            "forces convert with the force_* / *_wrench functions (they are ordered and transformed differently)"
        )
    return featherdyn_array(m, name, "motion vector (SpatialMotion or a raw (..., 6) [ω; v] array)")


def force_array(f: SpatialForce | ArrayLike, name: str) -> np.ndarray:
    """A featherdyn force (SpatialForce or raw ``[n; f]``) as a ``(..., 6)`` array."""
    if isinstance(f, SpatialForce):
        return f.vector
    if isinstance(f, SpatialMotion):
        raise SpatialTypeError(
            f"{name}: expected a force vector (SpatialForce or a raw (..., 6) [n; f] array), got a SpatialMotion; "
            "motions convert with the motion_* / twist_* functions (they are ordered and transformed differently)"
        )
    return featherdyn_array(m=f, name=name, what="force vector (SpatialForce or a raw (..., 6) [n; f] array)")


def featherdyn_array(m: ArrayLike, name: str, what: str) -> np.ndarray:
    if isinstance(m, SPATIAL_TYPES):
        raise SpatialTypeError(f"{name}: expected a {what}, got a {qualified_type_name(m)}")
    if is_pinocchio_object(m):
        raise SpatialTypeError(
            f"{name}: expected a {what}, got a {qualified_type_name(m)}; Pinocchio objects convert with "
            "from_pinocchio_motion / from_pinocchio_force / from_pinocchio_inertia / transform_from_pinocchio_se3"
        )
    return as_array(m, name, (6,))


def foreign_array(x: ArrayLike, name: str, layout: str, trailing: tuple[int, ...] = (6,)) -> np.ndarray:
    """A raw array in another library's layout; featherdyn values (already converted) are refused."""
    if isinstance(x, SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a raw array in {layout} order, got a {qualified_type_name(x)}, which is a featherdyn value "
            "already (angular first); use it directly, or convert it with the matching *_to_* function"
        )
    if is_pinocchio_object(x):
        raise SpatialTypeError(
            f"{name}: expected a raw array in {layout} order, got a {qualified_type_name(x)}; Pinocchio objects convert with "
            "from_pinocchio_motion / from_pinocchio_force / from_pinocchio_inertia / transform_from_pinocchio_se3"
        )
    return as_array(x, name, trailing)


def swap(x: np.ndarray) -> np.ndarray:
    """``[a; b] -> [b; a]`` over the last axis (a fresh array, dtype kept)."""
    return x[..., SWAP]


def cat(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Concatenate two ``(..., 3)`` halves after broadcasting their batch shapes."""
    a, b = np.broadcast_arrays(a, b)
    return np.concatenate([a, b], axis=-1)


def as_transform(T: PluckerTransform | ArrayLike, name: str) -> PluckerTransform:
    """A :class:`PluckerTransform`, or one built from a ``(..., 4, 4)`` homogeneous matrix."""
    if isinstance(T, PluckerTransform):
        return T
    if isinstance(T, SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a PluckerTransform or a (..., 4, 4) homogeneous matrix, got a {qualified_type_name(T)}"
        )
    if is_pinocchio_object(T):
        raise SpatialTypeError(
            f"{name}: expected a PluckerTransform or a (..., 4, 4) homogeneous matrix, got a {qualified_type_name(T)}; "
            "convert a pin.SE3 with transform_from_pinocchio_se3"
        )
    t = as_array(T, name, (4, 4))
    if t.dtype.kind != "O":
        bottom = t[..., 3, :]
        expected = np.array([0, 0, 0, 1], dtype=t.dtype)
        if not np.allclose(bottom, expected, atol=SPATIAL_STRUCTURE.of(t.dtype), rtol=0):
            raise ShapeError(
                f"{name}: expected a homogeneous transform with last row [0, 0, 0, 1], "
                f"got {np.asarray(bottom).reshape(-1, 4)[0].tolist()}"
            )
    check_rotation(t[..., :3, :3], f"{name}[..., :3, :3]")
    return PluckerTransform(t[..., :3, :3], t[..., :3, 3], validate=False)
