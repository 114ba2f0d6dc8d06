# needs: featherdyn[verify] (example-robot-data): pip install "featherdyn[verify]"
"""Appendix F (and §7.2, §12.1, §17.2) — the identity tables, checked row by row on random values.

Rows that do not hold as printed (each shown, with the corrected form):

* F.1 "(X*)⁻¹ = (X⁻¹)* = X⁻ᵀ": X⁻ᵀ is X* itself; the inverse is Xᵀ.
* F.2 "v ×* (I v) = −I(v × v) + (v×)ᵀ I v": v × v = 0 and (v×)ᵀ = −(v×*),
  so the right side is −(v ×* I v): the sign is wrong.
* F.3 "I_B = X*ᵀ I_A X*" and "I_composite = Σ X_i*ᵀ I_i X_i*": X*ᵀ = X⁻¹, so
  these are X⁻¹ I X⁻ᵀ — not an inertia transform. Right: I_B = X* I_A X⁻¹
  (§5.2 has it right), I_parent += ᵢXᵀ I_i ᵢX.
* F.4 "d/dt (I v) = f + v ×* (I v)" (body frame): the sign is wrong,
  d/dt (I v) = f − v ×* (I v).
* §17.2 "Σ_i S_iᵀ [v_i ×* (I_i v_i)] = C(q, q̇) q̇": the velocity-product
  accelerations v_i × S_i q̇_i also contribute (through I_i a_i), and the
  forces of descendants reach each joint; C q̇ = RNEA(q, q̇, 0) without gravity.

Run: python examples/25_appendix_f_identities.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, differs, section

import featherdyn as fd
from featherdyn.rotation import quat_normalize, quat_to_matrix

rng = np.random.default_rng(11)


def random_X():
    return fd.PluckerTransform(quat_to_matrix(quat_normalize(rng.normal(size=4))), rng.normal(size=3))


def random_I():
    a, b = rng.uniform(0.05, 0.3, 2)
    c = abs(a - b) + 0.5 * (a + b - abs(a - b))
    R = quat_to_matrix(quat_normalize(rng.normal(size=4)))
    return fd.SpatialInertia(rng.uniform(0.5, 3.0), rng.uniform(-0.3, 0.3, 3), R @ np.diag([a, b, c]) @ R.T)


X_AB, X_BC = random_X(), random_X()
X = random_X()
Xm, Xd = X.matrix(), X.dual_matrix()
v, w = rng.normal(size=6), rng.normal(size=6)
I_A = random_I()

# %% 1. F.1 transform identities
section("1. F.1")
check("X_AB X_BC = X_AC", X_AB.matrix() @ X_BC.matrix(), (X_AB @ X_BC).matrix(), 1e-13)
check("X_AB⁻¹ = X_BA", np.linalg.inv(X_AB.matrix()), X_AB.inverse().matrix(), 1e-13)
check("(X*)⁻¹ = (X⁻¹)* (true part)", np.linalg.inv(Xd), X.inverse().dual_matrix(), 1e-13)
differs("F.1: (X*)⁻¹ = X⁻ᵀ", np.linalg.inv(Xd), np.linalg.inv(Xm).T, 0.01)
check("(X*)⁻¹ = Xᵀ (corrected)", np.linalg.inv(Xd), Xm.T, 1e-13)
check("X*ᵀ = X⁻¹", Xd.T, np.linalg.inv(Xm), 1e-13)
check("det X = 1", np.linalg.det(Xm), 1.0, 1e-12)

# %% 2. F.2 cross-product identities
section("2. F.2")
check("v × w = −w × v", fd.crm(v) @ w, -fd.crm(w) @ v, 1e-14)
u = rng.normal(size=6)
check("Jacobi", fd.crm(u) @ (fd.crm(v) @ w) + fd.crm(v) @ (fd.crm(w) @ u) + fd.crm(w) @ (fd.crm(u) @ v), np.zeros(6), 1e-13)
check("(X v) × (X w) = X (v × w)", fd.crm(Xm @ v) @ (Xm @ w), Xm @ (fd.crm(v) @ w), 1e-12)
Iv = I_A.matrix() @ v
lhs = fd.crf(v) @ Iv
printed = -I_A.matrix() @ (fd.crm(v) @ v) + fd.crm(v).T @ Iv
differs("F.2: v ×* (I v) = −I(v × v) + (v×)ᵀ I v", lhs, printed, 0.01)
check("v ×* (I v) = −(v×)ᵀ I v (corrected)", lhs, -fd.crm(v).T @ Iv, 1e-13)
check("[v]×* = −[v]×ᵀ", fd.crf(v), -fd.crm(v).T, 0.0)

# %% 3. F.3 inertia identities
section("3. F.3")
IA = I_A.matrix()
check("I = Iᵀ", IA, IA.T, 0.0)
check_true("vᵀ I v > 0", v @ IA @ v > 0)
I_B = X.apply(I_A).matrix()
check("I_B = X* I_A X⁻¹ (§5.2)", I_B, Xd @ IA @ np.linalg.inv(Xm), 1e-12)
differs("F.3: I_B = X*ᵀ I_A X*", I_B, Xd.T @ IA @ Xd, 0.01)
# composite inertia of a 3-body chain: CRBA's I^C_0 vs the printed sum
model = fd.ModelBuilder("chain")
p0 = model.add_body("b0", -1, fd.RevoluteJoint([0, 0, 1]), inertia=random_I())
p1 = model.add_body("b1", p0, fd.RevoluteJoint([0, 1, 0]), inertia=random_I(), placement=random_X())
model.add_body("b2", p1, fd.RevoluteJoint([1, 0, 0]), inertia=random_I(), placement=random_X())
chain = model.build()
q = rng.normal(size=3)
kin = fd.forward_kinematics(chain, q)
X_i0 = [kin.placements[i].inverse() for i in range(3)]  # ⁱX₀: base (body 0) … here world → body i
IC_world = sum(X_i0[i].matrix().T @ chain.inertias[i].matrix() @ X_i0[i].matrix() for i in range(3))
IC_printed = sum(X_i0[i].dual_matrix().T @ chain.inertias[i].matrix() @ X_i0[i].dual_matrix() for i in range(3))
M = fd.crba(chain, q)
S0_world = np.array([0, 0, 1, 0, 0, 0.0])  # joint 0's axis through the world origin
check("M₀₀ = S₀ᵀ (Σ ⁱX₀ᵀ I_i ⁱX₀) S₀ (composite inertia, corrected)", S0_world @ IC_world @ S0_world, M[0, 0], 1e-12)
differs("F.3: composite Σ X_i*ᵀ I_i X_i*", S0_world @ IC_printed @ S0_world, M[0, 0], 1e-3)
check("T = ½ vᵀ I v", I_A.kinetic_energy(fd.SpatialMotion.from_vector(v)), 0.5 * v @ IA @ v, 1e-14)
check("h = I v", (I_A @ fd.SpatialMotion.from_vector(v)).vector, IA @ v, 1e-14)

# %% 4. F.4 Newton–Euler, one free body (gravity off)
section("4. F.4 and §12.1: one free-floating body")
b = fd.ModelBuilder("body", gravity=(0.0, 0.0, 0.0))
b.add_body("body", -1, fd.FreeFlyerJoint(), inertia=I_A)
body = b.build()
qb = fd.random_configuration(body, rng)
f = rng.normal(size=6)
a = fd.aba(body, qb, v, np.zeros(6), f_ext=f[None, :])  # body-frame spatial acceleration [ω̇; v̇]
check("f = I a + v ×* I v", IA @ a + fd.crf(v) @ Iv, f, 1e-12)
dh = IA @ a  # d/dt of the body-frame momentum components (I is constant in the body frame)
differs("F.4: d/dt(I v) = f + v ×* (I v)", dh, f + fd.crf(v) @ Iv, 0.01)
check("d/dt(I v) = f − v ×* (I v) (corrected)", dh, f - fd.crf(v) @ Iv, 1e-12)
check("τ = Sᵀ f (free flyer: S = 1)", fd.rnea(body, qb, v, a, f_ext=np.zeros((1, 6))), IA @ a + fd.crf(v) @ Iv, 1e-12)
# §12.1: at the CoM, the force row is m (a_c + ω × v_c) = m · (classical acceleration of the CoM)
c = I_A.com
X_c = fd.PluckerTransform(np.eye(3), -c)  # body frame seen from a frame at the CoM (same axes)
v_c, a_c, f_c = X_c.apply(fd.SpatialMotion.from_vector(v)), X_c.apply(fd.SpatialMotion.from_vector(a)), X_c.apply(fd.SpatialForce.from_vector(f))
check("§12.1: f = m (a_c + ω × v_c)", f_c.linear, I_A.mass * (a_c.linear + np.cross(v_c.angular, v_c.linear)), 1e-12)

# %% 5. F.5, §7.2 and §17.2 on the Panda
section("5. F.5, §7.2, §17.2 on the Panda")
panda = fd.load_robot("panda")
qp = fd.random_configuration(panda, rng)
vp, ap = rng.normal(size=panda.nv), rng.normal(size=panda.nv)
M = fd.crba(panda, qp)
C = fd.coriolis_matrix(panda, qp, vp)
g = fd.generalized_gravity(panda, qp)
check("RNEA(q, q̇, 0) without gravity = C q̇", fd.rnea(panda, qp, vp, np.zeros(panda.nv), gravity=False), C @ vp, 1e-10)
check("RNEA(q, 0, 0) = g(q)", fd.rnea(panda, qp, np.zeros(panda.nv), np.zeros(panda.nv)), g, 1e-10)
check("RNEA(q, q̇, q̈) = M q̈ + C q̇ + g", fd.rnea(panda, qp, vp, ap), M @ ap + C @ vp + g, 1e-10)
acc = fd.frame_acceleration(panda, qp, vp, ap, "panda_link5", fd.LOCAL)
vel = fd.frame_velocity(panda, qp, vp, "panda_link5", fd.LOCAL)
check("§7.2: classical = spatial + (0; ω × v)", fd.frame_classical_acceleration(panda, qp, vp, ap, "panda_link5", fd.LOCAL).vector,
      acc.vector + np.concatenate([np.zeros(3), np.cross(vel.angular, vel.linear)]), 1e-12)
# §17.2: the projected gyroscopic forces alone
kin = fd.forward_kinematics(panda, qp, vp)
gyro = [panda.inertias[i] @ fd.SpatialMotion.from_vector(kin.velocities.vector[i]) for i in range(panda.nbodies)]
gyro = [fd.SpatialMotion.from_vector(kin.velocities.vector[i]).cross(h) for i, h in enumerate(gyro)]
literal = np.concatenate([panda.joints[i].S.T @ gyro[i].vector for i in range(panda.nbodies)])
differs("§17.2: S_iᵀ [v_i ×* (I_i v_i)] = C q̇ (per joint)", literal, C @ vp, 0.01)
X_up = [kin.parent_placements[i].inverse() for i in range(panda.nbodies)]
propagated = list(gyro)
for i in reversed(range(panda.nbodies)):
    if panda.parents[i] != -1:
        propagated[panda.parents[i]] = propagated[panda.parents[i]] + X_up[i].apply_inverse(propagated[i])
with_children = np.concatenate([panda.joints[i].S.T @ propagated[i].vector for i in range(panda.nbodies)])
differs("§17.2 even with the children's forces propagated", with_children, C @ vp, 0.01)
print("\nAppendix F table checked.")
