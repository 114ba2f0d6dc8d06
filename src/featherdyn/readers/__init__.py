"""The file readers: URDF, MJCF and SDFormat documents into a :class:`~featherdyn.Model` (the "model" layer).

* :mod:`.urdf` — :func:`~featherdyn.load_urdf` and the magnitude bounds every reader shares
  (``MAX_LENGTH``, ``MAX_MASS``, ``MAX_INERTIA``);
* :mod:`.mjcf` — :func:`~featherdyn.load_mjcf`, ``load_model``, ``model_format``, with MuJoCo's compiler
  semantics; its pieces :mod:`.mjcf_xml` (includes, default classes, numbers, orientations),
  :mod:`.mjcf_schema` (the element and attribute names MuJoCo knows; the others are refused),
  :mod:`.mjcf_inertia` (primitive geoms) and :mod:`.mjcf_mesh` (mesh files and their mass properties);
* :mod:`.sdf` — :func:`~featherdyn.load_sdf`: SDFormat 1.4–1.11 models, frames, nested models and includes;
* :mod:`.xml` — the guarded XML reader all three use: bytes, encodings, the parser, bounded input, messages.

``featherdyn.urdf`` and ``featherdyn.mjcf`` re-export the public names of :mod:`.urdf` and :mod:`.mjcf`.
"""
