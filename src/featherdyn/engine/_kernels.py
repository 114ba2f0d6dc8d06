"""The compiled kernels: Numba, one state at a time, over the flat arrays of :mod:`._layout` (private index).

The kernels live in three modules, by job: :mod:`._flat_spatial` (joint
transforms and spatial algebra on flat blocks), :mod:`._cores` (one core per
algorithm and the batched FK / Jacobian forms) and :mod:`._entries` (the
entry points of ``fd.compile`` and the checked entry points of the public
functions); this module re-exports what the rest of the engine calls.

Each algorithm has a *core* that computes one state into caller-provided
outputs using a flat float64 workspace ``W`` (nothing is allocated inside),
and a *batched* form that runs the core over the rows of `(N, ·)` inputs with
``prange``, one workspace per thread. The cores follow the reference
algorithms (:mod:`featherdyn.algorithms`) line by line and keep their names:
``X_up``, ``v``, ``a``, ``f``, ``IC``, ``IA``, ``pA``, ``U``, ``D``, ``u`` are
*offsets* of per-body blocks in ``W`` (block of body ``i`` at
``X_up + 12 i``, ``v + 6 i``, ...) and ``S`` is applied by joint code. Working
with offsets instead of array views is deliberate: a view costs two atomic
reference-count updates in Numba, which is half the run time of a small model.

Representations (row-major, angular first):

* a pose `(12,)` = ``(R (9), p (3))``; ``X_up[i]`` stores the pose ``ᵖM_i`` of
  body ``i`` in its parent and is applied as its inverse, with ``m = [ω; v]``::

      X_up m      = [Rᵀ ω; Rᵀ (v − p × ω)]            (motion, parent → body)
      X_upᵀ f     = [R n + p × R f; R f]              (force,  body → parent)

* a rigid-body inertia `(10,)` = ``(m, h = m c (3), Ī (6: xx xy xz yy yz zz))``
  about the body origin::

      I [ω; v] = [Ī ω + h × v;  m v − h × ω]

* an articulated inertia `(36,)`: a full 6×6 matrix.

Inputs are trusted: the callers check shapes, dtypes and finiteness.
"""

from __future__ import annotations

from ._cores import (
    _chunks,
    aba_core,
    crba_core,
    fk_batch,
    fk_core,
    frame_jacobian_batch,
    frame_jacobian_core,
    gravity_core,
    rnea_core,
)
from ._entries import (
    CHECKED_SIGNATURES,
    ENTRY_SIGNATURES,
    QUAT_TOL,
    checked_aba,
    checked_crba,
    checked_fk,
    checked_frame_jacobian,
    checked_frame_placement,
    checked_gravity,
    checked_nle,
    checked_rnea,
    entry_aba,
    entry_crba,
    entry_fk,
    entry_frame_jacobian,
    entry_gravity,
    entry_nle,
    entry_rnea,
    entry_rnea_fext,
    lock_checked,
    lock_entries,
)

__all__ = ['CHECKED_SIGNATURES', 'ENTRY_SIGNATURES', 'QUAT_TOL', '_chunks', 'aba_core', 'checked_aba', 'checked_crba', 'checked_fk', 'checked_frame_jacobian', 'checked_frame_placement', 'checked_gravity', 'checked_nle', 'checked_rnea', 'crba_core', 'entry_aba', 'entry_crba', 'entry_fk', 'entry_frame_jacobian', 'entry_gravity', 'entry_nle', 'entry_rnea', 'entry_rnea_fext', 'fk_batch', 'fk_core', 'frame_jacobian_batch', 'frame_jacobian_core', 'gravity_core', 'lock_checked', 'lock_entries', 'rnea_core']
