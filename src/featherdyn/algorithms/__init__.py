"""The reference algorithms: batched NumPy, dtype-generic, written like the book — one algorithm per file.

Each module holds one recursion in the chapter's symbols and nothing else: it
receives arrays the public layer (:mod:`featherdyn.api`) has checked and
returns plain arrays or :mod:`featherdyn.results` values. Input checks,
backend choice and the compiled fast path live in :mod:`featherdyn.api`; the
public functions (``fd.rnea`` & co.) are there. See ``docs/architecture.md``.

* :mod:`.kinematics` — forward kinematics; frame placement, velocity, spatial and classical acceleration
* :mod:`.rnea` — inverse dynamics (RNEA)
* :mod:`.crba` — the joint-space mass matrix (CRBA)
* :mod:`.aba` — forward dynamics (ABA)
* :mod:`.jacobians` — joint and frame Jacobians and their time variation
* :mod:`.coriolis` — the Coriolis matrix
* :mod:`.energy` — kinetic and potential energy, centre of mass
* :mod:`.centroidal` — centroidal momentum and its matrix
* :mod:`.derivatives` — first-order derivatives of inverse and forward dynamics (analytical), the regressor
* :mod:`.second_order` — their second order (the first order on dual numbers; ABA's from RNEA's)
* :mod:`.constraints` — constraint rows (J, γ), M's LᵀL factor, constrained dynamics, impulses, operational space
"""

from __future__ import annotations
