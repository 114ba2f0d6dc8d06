# needs: featherdyn[verify] (Pinocchio, example-robot-data): pip install "featherdyn[verify]"
"""Appendix C.1 — RNEA verification on the Panda (example-robot-data), done so that it can fail.

The chapter's script has three problems, measured here:

* its "Verification passed!" line is ``np.allclose(tau_pin, tau_pin)`` — it
  compares Pinocchio with itself and cannot fail; here the recursion is
  written out with featherdyn's spatial algebra and compared with Pinocchio;
* it rebuilds the velocity as ``data.liMi[i].act(v_parent)``. ``liMi`` is the
  pose of joint i in its parent, so ``act`` maps child → parent; the parent's
  velocity must go the other way, ``liMi.actInv(v_parent)`` (= ``ⁱX_λ v_λ``);
* its ``model.joints[i].calc(q_i, v_i)`` is not Pinocchio's Python API
  (``JointModel.calc`` takes a ``JointData`` first and returns nothing);
* it symmetrises ``pin.crba``'s result "because CRBA fills only the upper
  triangle"; the Python binding (pin 4.1) returns the full symmetric matrix.

Run: python examples/06_rnea_verification_panda.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup: the same URDF in both libraries
from __future__ import annotations

from _check import needs

needs("pinocchio", "example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, check_true, differs, section, show

import featherdyn as fd
from featherdyn.robots import robot_path
from featherdyn.verify.bridge import JointMap, to_pin6

model = fd.load_robot("panda")
pmodel = pin.buildModelFromUrdf(str(robot_path("panda")))
pdata = pmodel.createData()
jmap = JointMap(model, pmodel)
print(f"  featherdyn: {model}")
print(f"  Pinocchio:  nq={pmodel.nq}, nv={pmodel.nv}, joints {list(pmodel.names)[1:4]} …")

rng = np.random.default_rng(42)
q = fd.random_configuration(model, rng)
v = rng.normal(size=model.nv) * 0.5
a = rng.normal(size=model.nv) * 0.1
qp, vp, ap = jmap.q_to_pin(q), jmap.v_to_pin(v), jmap.v_to_pin(a)

# %% 1. RNEA: featherdyn vs Pinocchio
section("1. τ = RNEA(q, v, a)")
tau_pin = pin.rnea(pmodel, pdata, qp, vp, ap)
tau_fd = fd.rnea(model, q, v, a)
show("τ (Pinocchio)", tau_pin)
check("fd.rnea = pin.rnea", tau_fd, jmap.v_from_pin(tau_pin), 1e-10)

# %% 2. the recursion written out (chapter §8.1) — a verification that can fail
section("2. RNEA by hand with featherdyn's spatial algebra")
kin = fd.forward_kinematics(model, q)
X_up = [kin.parent_placements[i].inverse() for i in range(model.nbodies)]  # ⁱX_λ(i)
a0 = fd.SpatialMotion(np.zeros(3), -model.gravity)  # gravity as a base acceleration
vel, acc, f = [], [], []
for i in range(model.nbodies):
    lam = model.parents[i]
    S = model.joints[i].S
    qd_i, qdd_i = v[model.idx_v[i]:model.idx_v[i] + model.nvs[i]], a[model.idx_v[i]:model.idx_v[i] + model.nvs[i]]
    vJ = fd.SpatialMotion.from_vector(S @ qd_i)
    v_i = vJ if lam == -1 else X_up[i].apply(vel[lam]) + vJ
    a_i = X_up[i].apply(a0 if lam == -1 else acc[lam]) + fd.SpatialMotion.from_vector(S @ qdd_i) + v_i.cross(vJ)
    I_i = model.inertias[i]
    vel.append(v_i)
    acc.append(a_i)
    f.append(I_i @ a_i + v_i.cross(I_i @ v_i))
tau_manual = np.zeros(model.nv)
for i in reversed(range(model.nbodies)):
    lam = model.parents[i]
    tau_manual[model.idx_v[i]:model.idx_v[i] + model.nvs[i]] = model.joints[i].S.T @ f[i].vector
    if lam != -1:
        f[lam] = f[lam] + X_up[i].apply_inverse(f[i])  # λX*_i f_i
check("manual recursion = Pinocchio", tau_manual, jmap.v_from_pin(tau_pin), 1e-10)

# %% 3. the velocity recursion: liMi.actInv, not act
section("3. v_i = ⁱX_λ v_λ + S_i q̇_i with Pinocchio objects")
pin.forwardKinematics(pmodel, pdata, qp, vp, ap)
worst_actinv, worst_act = 0.0, 0.0
for i in range(2, pmodel.njoints):  # joint 1's parent is the fixed universe
    parent = pmodel.parents[i]
    v_joint = np.asarray(pdata.joints[i].S).reshape(6, -1) @ vp[pmodel.idx_vs[i]:pmodel.idx_vs[i] + pmodel.nvs[i]]
    right = pdata.liMi[i].actInv(pdata.v[parent]).vector + v_joint
    chapter = pdata.liMi[i].act(pdata.v[parent]).vector + v_joint
    worst_actinv = max(worst_actinv, float(np.abs(right - pdata.v[i].vector).max()))
    worst_act = max(worst_act, float(np.abs(chapter - pdata.v[i].vector).max()))
check("data.v[i] = liMi.actInv(data.v[parent]) + S q̇", worst_actinv, 0.0, 1e-12)
try:  # the chapter's v_joint = pin.Motion(model.joints[i].calc(q_i, v_i))
    pmodel.joints[2].calc(qp[pmodel.idx_qs[2]:pmodel.idx_qs[2] + 1], vp[pmodel.idx_vs[2]:pmodel.idx_vs[2] + 1])
except TypeError as err:
    print(f"  chapter's model.joints[i].calc(q_i, v_i): {type(err).__name__} (calc needs a JointData first)")
    calc_raised = True
else:
    calc_raised = False
check_true("the chapter's JointModel.calc(q_i, v_i) call is not Pinocchio's API", calc_raised)
differs("chapter's liMi.act(v_parent) + S q̇", worst_act, 0.0, 1e-3)
v_fd = np.stack([vel[i].vector for i in range(model.nbodies)])
v_pin = np.stack([to_pin6(pdata.v[pmodel.getJointId(name)].vector) for name in model.joint_names])
check("featherdyn body velocities = Pinocchio data.v (all bodies)", v_fd, v_pin, 1e-10)

# %% 4. the identities the chapter prints
section("4. RNEA(q, v, 0) = nle,  RNEA(q, 0, 0) = g,  M a + nle = RNEA")
z = np.zeros(pmodel.nv)
nle = pin.nonLinearEffects(pmodel, pdata, qp, vp)
check("RNEA(q, v, 0) = nonLinearEffects", pin.rnea(pmodel, pdata, qp, vp, z), nle, 1e-12)
check("RNEA(q, 0, 0) = computeGeneralizedGravity", pin.rnea(pmodel, pdata, qp, z, z),
      pin.computeGeneralizedGravity(pmodel, pdata, qp), 1e-12)
M = pin.crba(pmodel, pdata, qp)
show("max |M − Mᵀ| of pin.crba (Python)", np.abs(M - M.T).max())
show("max |strict lower triangle| of pin.crba", np.abs(np.tril(M, -1)).max())
check_true("pin.crba returns the full symmetric matrix (no triu fix needed)",
           np.abs(M - M.T).max() == 0.0 and np.abs(np.tril(M, -1)).max() > 0.1)
check("M a + nle = RNEA", M @ ap + nle, tau_pin, 1e-10)
check("featherdyn: fd.crba(q) @ a + fd.nonlinear_effects = fd.rnea",
      fd.crba(model, q) @ a + fd.nonlinear_effects(model, q, v), tau_fd, 1e-10)
check("fd.crba = pin.crba", fd.crba(model, q), jmap.matrix_from_pin(M), 1e-10)
print("\nAll appendix C.1 checks passed.")
