# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""§10.1 — Motion, Force and power: the chapter's Pinocchio snippet, redone with featherdyn and measured.

The chapter's comments say Pinocchio stores a Motion, and returns ``.vector``,
as [angular; linear] "like Featherstone", and that ``pin.Motion(v6)`` must be
given [angular; linear]. Measured here: Pinocchio is **linear first** — both
claims are wrong. The argument order ``pin.Motion(linear, angular)`` is right.

Run: python examples/03_pinocchio_motion_force.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, differs, section, show

import featherdyn as fd
from featherdyn import conventions

omega = np.array([0.0, 0.0, 1.0])  # about z
v_linear = np.array([1.0, 0.0, 0.0])  # along x
tau = np.array([0.0, 0.0, 5.0])
f = np.array([0.0, 10.0, 0.0])

# %% 1. featherdyn: angular first, a separate type for forces, power as the only product
section("1. featherdyn")
motion = fd.SpatialMotion(omega, v_linear)
force = fd.SpatialForce(tau, f)
show("motion.vector [ω; v]", motion.vector)
show("force.vector [n; f]", force.vector)
power = motion.dot(force)
show("power", power)
check("power = ωᵀn + vᵀf = 5", power, 5.0, 0.0)
try:
    motion + force  # the type check is the point
except TypeError as err:
    print(f"  motion + force → TypeError: {str(err)[:80]}…")
else:
    raise SystemExit("FAILED: motion + force should raise")

# %% 2. Pinocchio's argument order and storage order (measured)
section("2. Pinocchio: Motion(linear, angular); .vector is [linear; angular]")
pm = pin.Motion(v_linear, omega)
show("pin.Motion(v, ω).vector", pm.vector)
check("angular part", pm.angular, omega, 0.0)
check("linear part", pm.linear, v_linear, 0.0)
check(".vector = [linear; angular] (measured)", pm.vector, np.concatenate([v_linear, omega]), 0.0)
differs("chapter: '.vector is [angular; linear]'", pm.vector, np.concatenate([omega, v_linear]), 0.5)
pf = pin.Force(f, tau)
check("pin.Force(f, n).vector = [f; n]", pf.vector, np.concatenate([f, tau]), 0.0)

# %% 3. the chapter's "method 2": pin.Motion([ω; v]) builds another motion
section("3. chapter's method 2: pin.Motion(np.concatenate([omega, v]))")
motion2 = pin.Motion(np.concatenate([omega, v_linear]))
show("motion2.linear", motion2.linear)
show("motion2.angular", motion2.angular)
differs("motion2 vs motion (method 1)", motion2.vector, pm.vector, 0.5)
check("motion2 reads ω as its linear part", motion2.linear, omega, 0.0)

# %% 4. the converters
section("4. featherdyn.conventions: explicit conversion at the boundary")
check("conventions.motion_to_pinocchio(m) = pin vector", conventions.motion_to_pinocchio(motion), pm.vector, 0.0)
check("conventions.force_to_pinocchio(f) = pin vector", conventions.force_to_pinocchio(force), pf.vector, 0.0)
check("to_pinocchio_motion round trip",
      conventions.from_pinocchio_motion(conventions.to_pinocchio_motion(motion)).vector, motion.vector, 0.0)
check("Pinocchio power Motion.dot(Force) = 5", pm.dot(pf), 5.0, 0.0)
print("\nAll §10.1 checks passed.")
