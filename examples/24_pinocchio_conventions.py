# needs: featherdyn[verify] (Pinocchio, example-robot-data): pip install "featherdyn[verify]"
"""§10.1, §11, §18.3, appendix G.1, troubleshooting table — Pinocchio's conventions, measured.

Each claim of the chapter about Pinocchio's layouts is measured in the
running Pinocchio (pin 4.1):

* 6D storage: linear first, ``[v; ω]`` and ``[f; n]`` (chapter: angular first);
* free-flyer ``q = [x y z, qx qy qz qw]`` (chapter §18.3: "quaternion(4) +
  position(3)"), quaternion order ``(x, y, z, w)`` (chapter: right);
* free-flyer ``v = [v; ω]`` in the base (LOCAL) frame (chapter §18.3: "angular
  + linear");
* ``pin.crba`` from Python returns the full symmetric matrix (chapter: upper
  triangle only);
* forces move with ``act`` (troubleshooting table: "force uses actInv").

Run: python examples/24_pinocchio_conventions.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, check_true, differs, section, show

import featherdyn as fd
from featherdyn import conventions
from featherdyn.robots import robot_path
from featherdyn.verify.bridge import JointMap, pinocchio_model_from

# %% 1. 6D storage order
section("1. Motion / Force storage")
m = pin.Motion(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))  # (linear, angular)
show("pin.Motion(linear=(1,2,3), angular=(4,5,6)).vector", m.vector)
check("linear first", m.vector, [1, 2, 3, 4, 5, 6], 0.0)
differs("chapter §10.1 / §11 / G.1: angular first", m.vector, [4, 5, 6, 1, 2, 3], 1.0)
fo = pin.Force(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))
check("Force: [f; n]", fo.vector, [1, 2, 3, 4, 5, 6], 0.0)
check("conventions.motion_from_pinocchio swaps the halves",
      conventions.motion_from_pinocchio(m.vector).vector, [4, 5, 6, 1, 2, 3], 0.0)

# %% 2. free-flyer q: position, then quaternion (x, y, z, w)
section("2. free-flyer q layout (pin.neutral, pin.integrate)")
ff = pin.Model()
ff.appendBodyToJoint(ff.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base"),
                     pin.Inertia(1.0, np.zeros(3), np.eye(3)), pin.SE3.Identity())
q0 = pin.neutral(ff)
show("pin.neutral", q0)
check("neutral = [0 0 0, 0 0 0 1]: position first, w last", q0, [0, 0, 0, 0, 0, 0, 1], 0.0)
differs("chapter §18.3: quaternion(4) first", q0, [0, 0, 0, 1, 0, 0, 0], 0.5)
q_rot = pin.integrate(ff, q0, np.array([0, 0, 0, np.pi, 0, 0]))
show("integrate(neutral, v = (0,0,0, π,0,0))", q_rot)
check("rotation by π about x: quaternion (1, 0, 0, 0) in (x, y, z, w)", q_rot[3:], [1, 0, 0, 0], 1e-12)

# %% 3. free-flyer v: linear first, in the base frame
section("3. free-flyer v layout")
q_lin = pin.integrate(ff, q0, np.array([1.0, 0, 0, 0, 0, 0]))
show("integrate(neutral, v = (1,0,0, 0,0,0))", q_lin)
check("v[0:3] is linear: the base moves along x", q_lin, [1, 0, 0, 0, 0, 0, 1], 1e-12)
differs("chapter §18.3: v = [angular(3) + linear(3)] (would rotate 1 rad about x)", q_lin,
        [0, 0, 0, np.sin(0.5), 0, 0, np.cos(0.5)], 0.1)
yawed = pin.integrate(ff, q0, np.array([0, 0, 0, 0, 0, np.pi / 2]))  # base yawed by 90°
moved = pin.integrate(ff, yawed, np.array([1.0, 0, 0, 0, 0, 0]))
check("linear velocity is in the base (LOCAL) frame: yawed base moves along world y",
      moved[:3] - yawed[:3], [0, 1, 0], 1e-12)
# featherdyn: v = [ω; v]; the converter swaps; integrate agrees
b = fd.ModelBuilder("ff")
b.add_body("base", -1, fd.FreeFlyerJoint(), inertia=fd.SpatialInertia(1.0, [0.1, 0, 0], np.eye(3) * 0.1))
fmodel = b.build()
pm = pinocchio_model_from(fmodel)
jmap = JointMap(fmodel, pm)
rng = np.random.default_rng(2)
q = fd.random_configuration(fmodel, rng)
v = rng.normal(size=6)
check("fd.integrate = pin.integrate (v converted with freeflyer_v_to_pinocchio)",
      fd.integrate(fmodel, q, v), pin.integrate(pm, q, conventions.freeflyer_v_to_pinocchio(v)), 1e-12)

# %% 4. pin.crba returns the full matrix
section("4. pin.crba from Python")
panda = pin.buildModelFromUrdf(str(robot_path("panda")))
pdata = panda.createData()
M = pin.crba(panda, pdata, pin.randomConfiguration(panda))
show("max |M − Mᵀ|, max |strict lower triangle|", [np.abs(M - M.T).max(), np.abs(np.tril(M, -1)).max()])
check_true("symmetric and the lower triangle is filled (pin 4.1 Python binding)",
           np.abs(M - M.T).max() == 0.0 and np.abs(np.tril(M, -1)).max() > 0)
check_true("data.M is full too after the Python call", np.abs(pdata.M - pdata.M.T).max() == 0.0)

# %% 5. forces: act, not actInv
section("5. act vs actInv on a force (power invariance)")
T = pin.SE3(fd.rotation.rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3))
vm, fm = pin.Motion(rng.normal(size=6)), pin.Force(rng.normal(size=6))
show("v·f, (T v)·(T f), (T v)·(T⁻¹ f)", [vm.dot(fm), T.act(vm).dot(T.act(fm)), T.act(vm).dot(T.actInv(fm))])
check("act on both: power invariant", T.act(vm).dot(T.act(fm)), vm.dot(fm), 1e-12)
differs("troubleshooting table: 'force uses actInv'", T.act(vm).dot(T.actInv(fm)), vm.dot(fm), 1e-3)
print("\nAll Pinocchio-convention measurements done.")
