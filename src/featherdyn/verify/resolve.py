"""Which robot a command means: a robot-library name, a URDF path, or the default robot."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import ModelError

__all__ = ["resolve_robot"]


def resolve_robot(robot: str | os.PathLike[str] | None) -> tuple[str, Path]:
    """``(name, urdf_path)`` of a robot-library name, a URDF path, or ``None`` (the default robot).

    Raises:
        ModelError: no such file, a directory, or an unknown robot name.
    """
    from ..robots import BUNDLED_DEFAULT_ROBOT, DEFAULT_ROBOT, _erd_files, robot_path

    if robot is None:
        name = DEFAULT_ROBOT if _erd_files() else BUNDLED_DEFAULT_ROBOT
        return name, robot_path(name)
    text = os.fspath(robot)
    path = Path(text)
    if path.is_dir():
        raise ModelError(f"{text!r} is a directory, expected a URDF file or a robot name (see `featherdyn list`)")
    if text.lower().endswith((".urdf", ".xml")) or (os.sep in text and path.exists()) or path.is_file():
        if not path.is_file():
            raise ModelError(f"URDF file {text!r} not found")
        return path.stem, path
    return text, robot_path(text)
