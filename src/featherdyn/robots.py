"""The robot library: robots bundled with featherdyn and those of ``example-robot-data``.

Names:

* a bundled robot is the stem of its file in ``featherdyn/data``
  (``"two_link_arm"``, the chapter's appendix-D 2R arm);
* a robot of the installed ``example-robot-data`` package (``pip install
  example-robot-data``) is the stem of its URDF file (``"panda"``,
  ``"solo12"``, ``"talos_full_v2"``); where two files share a stem, each is
  named ``"<robot folder>/<stem>"`` after its folder under ``robots/``
  (``"anymal_b_simple_description/anymal"`` and
  ``"anymal_c_simple_description/anymal"``). The qualified form is accepted
  for every robot (``"panda_description/panda"``).

Files with no ``<link>`` at all (``ur_description/urdf/ur3.urdf`` is an empty
stub) are not listed. The package is found through its installed files
(:func:`importlib.metadata.files`), never through a fixed path.
"""

from __future__ import annotations

import difflib
import functools
import importlib.metadata
import os
from pathlib import Path

from .errors import MissingDependencyError, ModelError
from .model import Model

__all__ = ["list_robots", "load_robot", "robot_path", "default_robot", "DEFAULT_ROBOT", "BUNDLED_DEFAULT_ROBOT"]

#: The default robot (of ``load_robot()`` and ``featherdyn verify``) when example-robot-data is installed.
DEFAULT_ROBOT = "panda"
#: The default robot otherwise: the bundled 2R arm.
BUNDLED_DEFAULT_ROBOT = "two_link_arm"

_DATA_DIR = Path(__file__).resolve().parent / "data"
_ERD_DIST = "example-robot-data"
_ERD_MARKER = ("example-robot-data", "robots")


@functools.lru_cache(maxsize=1)
def _bundled() -> dict[str, Path]:
    return {p.stem: p for p in sorted(_DATA_DIR.glob("*.urdf"))}


@functools.lru_cache(maxsize=1)
def _erd_files() -> tuple[tuple[str, str, Path], ...] | None:
    """``(folder, stem, path)`` of each robot URDF of example-robot-data; ``None`` if it is not installed."""
    try:
        files = importlib.metadata.files(_ERD_DIST)
    except importlib.metadata.PackageNotFoundError:
        return None
    if files is None:
        return None
    out = []
    for f in files:
        parts = f.parts
        if not parts or not parts[-1].endswith(".urdf"):
            continue
        for k in range(len(parts) - 2):
            if parts[k : k + 2] == _ERD_MARKER:
                folder = parts[k + 2]
                break
        else:
            continue
        path = Path(str(f.locate()))
        try:
            if b"<link" not in path.read_bytes():  # an empty stub, not a robot
                continue
        except OSError:
            continue
        out.append((folder, Path(parts[-1]).stem, path))
    return tuple(sorted(out))


@functools.lru_cache(maxsize=1)
def _erd_names() -> tuple[dict[str, Path], dict[str, Path]]:
    """``(listed names, every accepted name)`` of the example-robot-data robots."""
    files = _erd_files() or ()
    stems: dict[str, int] = {}
    for _, stem, _ in files:
        stems[stem] = stems.get(stem, 0) + 1
    listed: dict[str, Path] = {}
    accepted: dict[str, Path] = {}
    for folder, stem, path in files:
        qualified = f"{folder}/{stem}"
        listed[stem if stems[stem] == 1 else qualified] = path
        accepted[qualified] = path
        if stems[stem] == 1:
            accepted[stem] = path
    return listed, accepted


def list_robots() -> list[str]:
    """The names :func:`load_robot` accepts, sorted (qualified forms of unambiguous names omitted).

    Returns:
        The bundled robots, plus every robot of example-robot-data if it is
        installed (see the module docstring for the naming scheme).
    """
    names = set(_bundled())
    names.update(_erd_names()[0])
    return sorted(names)


def default_robot() -> str:
    """The robot :func:`load_robot` loads without a name (and ``featherdyn verify`` checks).

    Returns:
        :data:`DEFAULT_ROBOT` (``"panda"``) when example-robot-data is
        installed, else :data:`BUNDLED_DEFAULT_ROBOT` (``"two_link_arm"``).
    """
    return DEFAULT_ROBOT if _erd_files() else BUNDLED_DEFAULT_ROBOT


def robot_path(name: str) -> Path:
    """The URDF file of the robot called ``name``.

    Args:
        name: a name from :func:`list_robots`, or the ``"<folder>/<stem>"``
            form of an example-robot-data robot.

    Raises:
        ModelError: unknown name (the message lists close matches).
        MissingDependencyError: the name is not bundled and example-robot-data
            is not installed.
    """
    bundled = _bundled()
    if name in bundled:
        return bundled[name]
    if _erd_files() is None:
        raise MissingDependencyError(
            f"robot {name!r} is not bundled with featherdyn (bundled: {', '.join(sorted(bundled))}); "
            "the robot library needs example-robot-data: pip install example-robot-data"
        )
    listed, accepted = _erd_names()
    if name in accepted:
        return accepted[name]
    same_stem = sorted(n for n in listed if n.endswith("/" + name))
    if same_stem:
        raise ModelError(f"robot name {name!r} is ambiguous: use one of {', '.join(repr(n) for n in same_stem)}")
    candidates = list_robots()
    close = [c for c in candidates if name.lower() in c.lower()]  # "talos" -> talos_*
    close += [c for c in difflib.get_close_matches(name, candidates, n=5, cutoff=0.6) if c not in close]
    hint = f"; did you mean {', '.join(repr(c) for c in close[:5])}?" if close else ""
    raise ModelError(f"unknown robot {name!r}{hint} (`featherdyn list` lists all {len(candidates)}; in Python, featherdyn.list_robots())")


def load_robot(name: str | os.PathLike[str] | None = None, floating_base: bool = False, strict: bool = False) -> Model:
    """Load a robot of the library by name, or a URDF, MJCF or SDFormat file by path.

    Args:
        name: a name from :func:`list_robots`; ``None`` loads
            :func:`default_robot` (``"panda"`` when example-robot-data is
            installed, else the bundled ``"two_link_arm"``); the path of an
            existing ``.urdf``, ``.xml``, ``.sdf`` or ``.world`` file loads it
            with :func:`featherdyn.load_model` (URDF, MJCF or SDFormat by its
            root element; ``floating_base`` applies to a URDF only).
        floating_base: put the root link on a free-flyer joint (see
            :func:`featherdyn.load_urdf`).
        strict: physicality warnings become errors (see :func:`featherdyn.load_urdf`).

    Returns:
        The :class:`~featherdyn.Model`.

    Raises:
        ModelError: unknown name (with close matches); :class:`~featherdyn.URDFError`
            if the file does not load.
        MissingDependencyError: a robot that is not bundled was asked for and
            example-robot-data is not installed.
    """
    from .readers.urdf import load_urdf

    if name is None:
        name = default_robot()
    if (isinstance(name, (str, os.PathLike)) and str(name).lower().endswith((".urdf", ".xml", ".sdf", ".world"))
            and Path(name).is_file()):
        from .readers.mjcf import load_mjcf, model_format

        fmt = model_format(name)
        if fmt == "mjcf":
            return load_mjcf(name, strict=strict)
        if fmt == "sdf":
            from .readers.sdf import load_sdf

            return load_sdf(name, strict=strict)
        return load_urdf(name, floating_base=floating_base, strict=strict)
    return load_urdf(robot_path(os.fspath(name)), floating_base=floating_base, strict=strict)
