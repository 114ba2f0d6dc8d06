"""Load an MJCF (MuJoCo XML) model: the public names of :mod:`featherdyn.readers.mjcf`, where the reader lives."""

from __future__ import annotations

from .readers.mjcf import MJ_MINVAL, clear_mesh_cache, load_mjcf, load_model, model_format

__all__ = ["MJ_MINVAL", "clear_mesh_cache", "load_mjcf", "load_model", "model_format"]
