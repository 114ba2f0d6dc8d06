# needs: featherdyn[examples] (MuJoCo, gymnasium's models): pip install "featherdyn[examples]"
"""An MJCF model read by featherdyn and compiled by MuJoCo: the same mass matrix, gravity and dynamics.

gymnasium's Ant: featherdyn's ``load_mjcf`` applies MuJoCo's compiler rules
(degrees, inertia from capsule geoms, the free joint). MuJoCo stores a free
joint as ``qpos = [p; w x y z]`` and ``qvel = [v_world; ω_body]``; featherdyn's
``[p; x y z w]`` and ``[ω; v]`` in the body frame — the converters in
``featherdyn.conventions`` map one to the other.

Run: python examples/28_mjcf_against_mujoco.py
"""

# %% 0. one file, two compilers
from __future__ import annotations

from _check import needs

needs("mujoco", "gymnasium")  # first: a missing module is one line naming its install

import os
import warnings

import gymnasium
import mujoco
import numpy as np
from _check import check, section, show

import featherdyn as fd
from featherdyn import conventions as conv
from featherdyn.verify.mujoco import full_mass_matrix  # mj_fullM across MuJoCo 3 and 4

path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "ant.xml")
with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # the actuators and contacts have no rigid-tree meaning: listed, ignored
    model = fd.load_mjcf(path)
m = mujoco.MjModel.from_xml_path(path)
d = mujoco.MjData(m)
show("featherdyn", model)
show("MuJoCo nq, nv, nbody", [m.nq, m.nv, m.nbody])

# %% 1. a random state in both layouts
rng = np.random.default_rng(0)
q = fd.random_configuration(model, rng)
qpos = conv.q_to_mujoco(model, q)
qvel = rng.normal(size=m.nv)
v = conv.v_from_mujoco(model, qpos, qvel)
check("qpos → q → qpos", conv.q_to_mujoco(model, conv.q_from_mujoco(model, qpos)), qpos, 1e-15)

# %% 2. mass matrix, gravity, inverse dynamics
section("M, g, RNEA against MuJoCo")
d.qpos[:], d.qvel[:] = qpos, 0
mujoco.mj_forward(m, d)
M_mj = full_mass_matrix(mujoco, m, d)
check("M (MuJoCo's coordinates)", conv.joint_matrix_to_mujoco(model, q, fd.crba(model, q)), M_mj, 1e-12)
check("gravity torques", conv.tau_to_mujoco(model, q, fd.generalized_gravity(model, q)), d.qfrc_bias, 1e-12)
check("total mass", model.total_mass, sum(m.body_mass), 1e-12)
d.qvel[:] = qvel
mujoco.mj_forward(m, d)
qacc = rng.normal(size=m.nv)
M_mj = full_mass_matrix(mujoco, m, d)
a = conv.a_from_mujoco(model, qpos, qvel, qacc)
check("RNEA = qfrc_bias + M qacc", conv.tau_to_mujoco(model, q, fd.rnea(model, q, v, a)), d.qfrc_bias + M_mj @ qacc,
      1e-11)
print("\n  `featherdyn verify ant.xml` runs these comparisons (and ABA, body inertias) as a report.")
