"""Load a URDF model: the public names of :mod:`featherdyn.readers.urdf`, where the reader lives."""

from __future__ import annotations

from .readers.urdf import MAX_INERTIA, MAX_LENGTH, MAX_MASS, load_urdf

__all__ = ["MAX_INERTIA", "MAX_LENGTH", "MAX_MASS", "load_urdf"]
