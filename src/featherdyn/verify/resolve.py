"""Which robot a command means: a robot-library name, a URDF or MJCF path, or the default robot; and its model."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import ModelError
from ..model import Model

__all__ = ["resolve_robot", "load_resolved"]


def resolve_robot(robot: str | os.PathLike[str] | None) -> tuple[str, Path]:
    """``(name, urdf_path)`` of a robot-library name, a URDF path, or ``None`` (the default robot).

    Raises:
        ModelError: no such file, a directory, or an unknown robot name.
    """
    from ..robots import default_robot, robot_path

    if robot is None:
        name = default_robot()
        return name, robot_path(name)
    text = os.fspath(robot)
    path = Path(text)
    if path.is_dir():
        raise ModelError(f"{text!r} is a directory, expected a URDF or MJCF file or a robot name "
                         "(see `featherdyn list`)")
    if text.lower().endswith((".urdf", ".xml")) or (os.sep in text and path.exists()) or path.is_file():
        if not path.is_file():
            what = "is not a regular file (a device or a pipe)" if path.exists() else "not found"
            raise ModelError(f"{'URDF' if text.lower().endswith('.urdf') else 'model'} file {text!r} {what}")
        return path.stem, path
    return text, robot_path(text)


def load_resolved(path: str | os.PathLike[str], floating_base: bool = False, strict: bool = False) -> Model:
    """The model in ``path``: a URDF (``floating_base`` puts its root on a free-flyer) or an MJCF (by the
    root element, :func:`featherdyn.readers.mjcf.model_format`).

    Raises:
        ModelError: ``floating_base`` with an MJCF model (its free joints are in the file); the loaders' errors.
    """
    from ..readers.mjcf import load_mjcf, model_format
    from ..readers.urdf import load_urdf

    if model_format(path) == "urdf":
        return load_urdf(path, floating_base=floating_base, strict=strict)
    if floating_base:
        raise ModelError(f"{os.fspath(path)}: --floating-base applies to a URDF; an MJCF model's free joints are "
                         "in the file")
    return load_mjcf(path, strict=strict)
