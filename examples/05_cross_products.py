# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""§10.3 — motion and force cross products; the chapter's duality check has the wrong sign.

The chapter checks "(v1 × v2)ᵀ f == v2ᵀ (v1 ×* f)". From [v]×* = −[v]×ᵀ the
truth is v2 · (v1 ×* f) = −(v1 × v2) · f. With the chapter's f (gravity,
(0, 0, 9.81)) both sides are 0, so its printed check passes by accident.

Run: python examples/05_cross_products.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, differs, section, show

import featherdyn as fd
from featherdyn import conventions

v1 = fd.SpatialMotion([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
v2 = fd.SpatialMotion([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
gravity = fd.SpatialForce([0.0, 0.0, 0.0], [0.0, 0.0, 9.81])
p1, p2 = conventions.to_pinocchio_motion(v1), conventions.to_pinocchio_motion(v2)
pg = conventions.to_pinocchio_force(gravity)

# %% 1. motion cross product
section("1. v1 × v2 = (ω1 × ω2; ω1 × v2 − ω2 × v1)")
v12 = v1.cross(v2)
manual = np.concatenate([np.cross(v1.angular, v2.angular),
                         np.cross(v1.angular, v2.linear) - np.cross(v2.angular, v1.linear)])
show("featherdyn v1 × v2", v12.vector)
check("manual (chapter's formula)", v12.vector, manual, 0.0)
check("crm(v1) @ v2", fd.crm(v1) @ v2.vector, manual, 0.0)
check("Pinocchio v1.cross(v2)", conventions.from_pinocchio_motion(p1.cross(p2)).vector, manual, 1e-14)

# %% 2. force cross product
section("2. v1 ×* f")
v1f = v1.cross(gravity)
show("featherdyn v1 ×* f", v1f.vector)
check("crf(v1) @ f = −crm(v1)ᵀ f", v1f.vector, -fd.crm(v1).T @ gravity.vector, 1e-14)
check("Pinocchio v1.cross(force)", conventions.from_pinocchio_force(p1.cross(pg)).vector, v1f.vector, 1e-14)

# %% 3. the duality check, as printed and as true
section("3. duality: v2 · (v1 ×* f) = −(v1 × v2) · f")
lhs, rhs = v12.dot(gravity), v2.dot(v1f)
show("chapter's f: (v1×v2)·f, v2·(v1×*f)", [lhs, rhs])
check("both 0 with the chapter's f — the printed check cannot see the sign", [lhs, rhs], [0.0, 0.0], 0.0)
rng = np.random.default_rng(3)
f = fd.SpatialForce.from_vector(rng.normal(size=6))
lhs, rhs = v12.dot(f), v2.dot(v1.cross(f))
show("random f: (v1×v2)·f, v2·(v1×*f)", [lhs, rhs])
check("v2·(v1×*f) = −(v1×v2)·f", rhs, -lhs, 1e-14)
differs("chapter's '(v1×v2)·f == v2·(v1×*f)'", rhs, lhs, 0.1)
pf = conventions.to_pinocchio_force(f)
check("Pinocchio agrees: v2·(v1×*f) = −(v1×v2)·f", p2.dot(p1.cross(pf)), -p1.cross(p2).dot(pf), 1e-14)
print("\nAll §10.3 checks passed.")
