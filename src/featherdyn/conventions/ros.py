"""ROS ``geometry_msgs``: ``Twist`` and ``Wrench``, as fields or flattened.

A ``Twist`` holds ``linear`` (the velocity of the point at the origin of the
message's frame, featherdyn's ``v_O``) and ``angular``; a ``Wrench`` holds
``force`` and ``torque`` (the moment about that origin, ``n_O``). As mappings
or message objects the fields convert by name; flattened in field order they
are linear first, the half swap ``P`` of featherdyn's vectors.

Sources: ROS ``geometry_msgs/msg/Twist`` and ``geometry_msgs/msg/Wrench``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ShapeError, SpatialTypeError
from ..frames import Frame
from ..spatial import SpatialForce, SpatialMotion
from ..spatial.validation import as_array
from ._common import SPATIAL_TYPES, force_array, foreign_array, motion_array, qualified_type_name, swap

__all__ = [
    "force_from_ros_wrench",
    "force_to_ros_wrench",
    "motion_from_ros_twist",
    "motion_to_ros_twist",
    "twist_array_from_ros",
    "twist_array_to_ros",
    "wrench_array_from_ros",
    "wrench_array_to_ros",
]

#: a message's fields as returned by the ``*_to_ros_*`` converters: 3-tuples for one value,
#: `(..., 3)` arrays for a batch
RosFields: TypeAlias = dict[str, tuple[float, ...] | np.ndarray]


def _ros_out(vec: np.ndarray, first: tuple[str, np.ndarray], second: tuple[str, np.ndarray]) -> RosFields:
    if vec.ndim == 1:
        return {first[0]: tuple(first[1].tolist()), second[0]: tuple(second[1].tolist())}
    return {first[0]: np.array(first[1]), second[0]: np.array(second[1])}


def _ros_field(msg: object, key: str, name: str, keys: tuple[str, str], message: str, flat_function: str) -> object:
    if isinstance(msg, SPATIAL_TYPES):
        raise SpatialTypeError(
            f"{name}: expected a {message} (a mapping with keys {keys[0]!r} and {keys[1]!r}), got a "
            f"{qualified_type_name(msg)}, which is a featherdyn value already"
        )
    if isinstance(msg, Mapping):
        if key not in msg:
            raise ShapeError(
                f"{name}: missing key {key!r}; expected a {message} mapping with keys {keys[0]!r} and {keys[1]!r}, "
                f"got keys {[str(k) for k in msg]}"
            )
        return msg[key]
    if isinstance(msg, (np.ndarray, list, tuple, str, bytes)) or not hasattr(msg, key):
        raise ShapeError(
            f"{name}: expected a {message} (a mapping with keys {keys[0]!r} and {keys[1]!r}, or a message object "
            f"with those fields), got a {qualified_type_name(msg)} without field {key!r}; flattened 6-arrays convert with "
            f"{flat_function}"
        )
    return getattr(msg, key)


def _ros_vector3(value: object, name: str) -> np.ndarray:
    if isinstance(value, Mapping):
        for k in "xyz":
            if k not in value:
                raise ShapeError(
                    f"{name}: missing key {k!r}; expected a 3-sequence or a mapping with keys 'x', 'y', 'z', "
                    f"got keys {[str(key) for key in value]}"
                )
        comps = [as_array(value[k], f"{name}[{k!r}]") for k in "xyz"]
    elif not isinstance(value, (np.ndarray, list, tuple)) and all(hasattr(value, k) for k in "xyz"):
        comps = [as_array(getattr(value, k), f"{name}.{k}") for k in "xyz"]
    else:
        return as_array(value, name, (3,))
    return np.stack(np.broadcast_arrays(*comps), axis=-1)


def motion_to_ros_twist(m: SpatialMotion | ArrayLike) -> RosFields:
    """A featherdyn motion as the fields of a ROS ``geometry_msgs/Twist``.

    ROS's ``linear`` is the velocity of the point at the origin of the
    message's frame (the ``v_O`` of featherdyn), expressed in that frame.

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        ``{"linear": v_O, "angular": ω}``: tuples of 3 floats for one motion,
        `(..., 3)` arrays for a batch::

            Twist(linear=Vector3(*d["linear"]), angular=Vector3(*d["angular"]))

    Source: ROS ``geometry_msgs/msg/Twist``.
    """
    vec = motion_array(m, "m")
    return _ros_out(vec, ("linear", vec[..., 3:]), ("angular", vec[..., :3]))


def motion_from_ros_twist(twist: Mapping[str, object] | object, frame: Frame = None) -> SpatialMotion:
    """A ROS ``Twist`` (message, or mapping) as a featherdyn motion.

    Args:
        twist: a mapping with keys ``"linear"`` and ``"angular"`` (or an object
            with those attributes, e.g. a ``geometry_msgs/Twist``), each a
            3-sequence / `(..., 3)` array, a mapping with keys ``x, y, z`` or a
            ``Vector3``-like object.
        frame: optional frame tag (the message's ``header.frame_id``).

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            [ω; v_O] = [twist.angular; twist.linear]

    Raises:
        ShapeError: a key or field is missing (the message names it) or a
            vector is not 3 long.

    Source: ROS ``geometry_msgs/msg/Twist``.
    """
    keys = ("linear", "angular")
    lin = _ros_vector3(_ros_field(twist, "linear", "twist", keys, "Twist", "twist_array_from_ros"), "twist['linear']")
    ang = _ros_vector3(_ros_field(twist, "angular", "twist", keys, "Twist", "twist_array_from_ros"), "twist['angular']")
    return SpatialMotion(ang, lin, frame)


def force_to_ros_wrench(f: SpatialForce | ArrayLike) -> RosFields:
    """A featherdyn force as the fields of a ROS ``geometry_msgs/Wrench``.

    ROS's ``torque`` is the moment about the origin of the message's frame
    (featherdyn's ``n_O``).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        ``{"force": f, "torque": n_O}``: tuples of 3 floats for one force,
        `(..., 3)` arrays for a batch::

            Wrench(force=Vector3(*d["force"]), torque=Vector3(*d["torque"]))

    Source: ROS ``geometry_msgs/msg/Wrench``.
    """
    vec = force_array(f, "f")
    return _ros_out(vec, ("force", vec[..., 3:]), ("torque", vec[..., :3]))


def force_from_ros_wrench(wrench: Mapping[str, object] | object, frame: Frame = None) -> SpatialForce:
    """A ROS ``Wrench`` (message, or mapping) as a featherdyn force.

    Args:
        wrench: a mapping with keys ``"force"`` and ``"torque"`` (or an object
            with those attributes), each a 3-sequence / `(..., 3)` array, a
            mapping with keys ``x, y, z`` or a ``Vector3``-like object.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            [n_O; f] = [wrench.torque; wrench.force]

    Raises:
        ShapeError: a key or field is missing (the message names it) or a
            vector is not 3 long.

    Source: ROS ``geometry_msgs/msg/Wrench``.
    """
    keys = ("force", "torque")
    force = _ros_vector3(
        _ros_field(wrench, "force", "wrench", keys, "Wrench", "wrench_array_from_ros"), "wrench['force']"
    )
    torque = _ros_vector3(
        _ros_field(wrench, "torque", "wrench", keys, "Wrench", "wrench_array_from_ros"), "wrench['torque']"
    )
    return SpatialForce(torque, force, frame)


def twist_array_to_ros(m: SpatialMotion | ArrayLike) -> np.ndarray:
    """A featherdyn motion as a flattened ROS twist, linear first (message field order).

    Args:
        m: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]``.

    Returns:
        `(..., 6)`::

            [linear; angular] = [v_O; ω] = P m

    Source: ROS ``geometry_msgs/msg/Twist`` field order.
    """
    return swap(motion_array(m, "m"))


def twist_array_from_ros(twist: ArrayLike, frame: Frame = None) -> SpatialMotion:
    """A flattened ROS twist ``[linear; angular]`` as a featherdyn motion.

    Args:
        twist: `(..., 6)` ``[v_O; ω]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            m = P [v_O; ω] = [ω; v_O]

    Source: ROS ``geometry_msgs/msg/Twist`` field order.
    """
    return SpatialMotion.from_vector(swap(foreign_array(twist, "twist", "ROS [linear; angular]")), frame)


def wrench_array_to_ros(f: SpatialForce | ArrayLike) -> np.ndarray:
    """A featherdyn force as a flattened ROS wrench, force first (message field order).

    Args:
        f: :class:`SpatialForce` or raw `(..., 6)` ``[n_O; f]``.

    Returns:
        `(..., 6)`::

            [force; torque] = [f; n_O] = P f

    Source: ROS ``geometry_msgs/msg/Wrench`` field order.
    """
    return swap(force_array(f, "f"))


def wrench_array_from_ros(wrench: ArrayLike, frame: Frame = None) -> SpatialForce:
    """A flattened ROS wrench ``[force; torque]`` as a featherdyn force.

    Args:
        wrench: `(..., 6)` ``[f; n_O]``.
        frame: optional frame tag.

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            f = P [f; n_O] = [n_O; f]

    Source: ROS ``geometry_msgs/msg/Wrench`` field order.
    """
    return SpatialForce.from_vector(swap(foreign_array(wrench, "wrench", "ROS [force; torque]")), frame)
