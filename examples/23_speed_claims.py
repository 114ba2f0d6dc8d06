# needs: featherdyn[verify] (Pinocchio, example-robot-data): pip install "featherdyn[verify]"
"""§11, §16.1, appendix G.2 — the chapter's speed claims, measured where they can be.

* §11: "Pinocchio: 7-DoF RNEA ≈ 1.5 µs". That is a C++-internal figure; from
  Python every call also pays the binding (argument conversion, result
  allocation). Measured here: ``pin.rnea`` on the 7-DoF Panda (fingers
  locked) with timeit, next to ``pin.rnea`` on a one-joint model, which
  estimates that per-call overhead.
* §16.1: "finite differences need 2n RNEA calls ≈ 21 µs; analytic derivatives
  one sweep ≈ 3 µs". Measured: ``pin.computeRNEADerivatives`` against 2n
  central-difference ``pin.rnea`` calls from Python (and their accuracy).
* Appendix G.2: "Pinocchio is 3–10× faster than RBDL" — not measurable here:
  ``rbdl`` is not on PyPI, and ``pyrbdl`` 0.0.2 (2020, the only RBDL binding
  there) fails to build on Python 3.11 (its bundled pybind11 predates the
  CPython 3.11 frame API).

Timings depend on the machine; nothing here asserts a speed. The script does
assert that the finite differences match the analytic derivatives.

Run: python examples/23_speed_claims.py
"""

# %% 0. setup: the 7-DoF Panda in Pinocchio
from __future__ import annotations

from _check import needs

needs("pinocchio", "example-robot-data")  # first: a missing module is one line naming its install

import importlib.util
import timeit

import numpy as np
import pinocchio as pin
from _check import check, check_true, section

import featherdyn as fd
from featherdyn.robots import robot_path

full = pin.buildModelFromUrdf(str(robot_path("panda")))
fingers = [full.getJointId(n) for n in ("panda_finger_joint1", "panda_finger_joint2")]
model = pin.buildReducedModel(full, fingers, pin.neutral(full))
data = model.createData()
print(f"  reduced Panda: nq = {model.nq}, nv = {model.nv}")
rng = np.random.default_rng(0)
q = rng.uniform(model.lowerPositionLimit, model.upperPositionLimit)
v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)


def best_of(fn, number: int, repeat: int = 5) -> float:
    """Best time per call in seconds (timeit's recommended statistic)."""
    return min(timeit.repeat(fn, number=number, repeat=repeat)) / number


# %% 1. RNEA from Python
section("1. pin.rnea on the 7-DoF Panda, called from Python")
t_rnea = best_of(lambda: pin.rnea(model, data, q, v, a), 20000)
one = pin.Model()
one.appendBodyToJoint(one.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "j"), pin.Inertia(1.0, np.array([0.1, 0.0, 0.0]), np.eye(3)), pin.SE3.Identity())
one_data = one.createData()
z1 = np.zeros(1)
t_one = best_of(lambda: pin.rnea(one, one_data, z1, z1, z1), 20000)
print(f"  pin.rnea, 7 DoF:  {t_rnea * 1e6:6.2f} µs per call")
print(f"  pin.rnea, 1 DoF:  {t_one * 1e6:6.2f} µs per call  (≈ the Python-binding overhead)")
print(f"  difference:       {(t_rnea - t_one) * 1e6:6.2f} µs  (≈ the algorithm; chapter: ≈ 1.5 µs in C++)")
check_true("timings are positive and finite", 0 < t_one < 1e-2 and 0 < t_rnea < 1e-2)

# %% 2. analytic derivatives vs 2n finite-difference RNEA calls
section("2. ∂τ/∂q: pin.computeRNEADerivatives vs 2n central differences")
n = model.nv
h = 1e-6


def finite_differences():
    J = np.empty((n, n))
    for k in range(n):
        e = np.zeros(n)
        e[k] = h
        J[:, k] = (pin.rnea(model, data, pin.integrate(model, q, e), v, a)
                   - pin.rnea(model, data, pin.integrate(model, q, -e), v, a)) / (2 * h)
    return J


t_der = best_of(lambda: pin.computeRNEADerivatives(model, data, q, v, a), 5000)
t_fd = best_of(finite_differences, 500)
dtau_dq, dtau_dv, dtau_da = pin.computeRNEADerivatives(model, data, q, v, a)
print(f"  computeRNEADerivatives (∂τ/∂q, ∂τ/∂v, ∂τ/∂a): {t_der * 1e6:7.2f} µs")
print(f"  2n = {2 * n} pin.rnea calls (+ integrate), Python loop: {t_fd * 1e6:7.2f} µs")
print(f"  2n × (one rnea call):                           {2 * n * t_rnea * 1e6:7.2f} µs")
print(f"  ratio (Python loop) / analytic: {t_fd / t_der:.1f}×;  ratio (2n bare calls) / analytic: "
      f"{2 * n * t_rnea / t_der:.1f}×")
print(f"  chapter: 21 µs / 3 µs = 7×, and 'faster by 2n = {2 * n}× or more'")
check("finite differences ≈ analytic ∂τ/∂q", finite_differences(), dtau_dq, 1e-5 * max(1.0, np.abs(dtau_dq).max()))
check("∂τ/∂a = M", dtau_da, pin.crba(model, data, q), 1e-10)

# %% 3. featherdyn's two backends on the same robot, for scale
section("3. featherdyn: the reference backend (pure NumPy) and the compiled core (C++)")
fmodel = fd.load_robot("panda")
fq = np.concatenate([q, [0.0, 0.0]])
fv, fa = np.concatenate([v, [0.0, 0.0]]), np.concatenate([a, [0.0, 0.0]])
# backend="reference" forces the NumPy recursion: the default is the compiled core (built at install)
t_ref = best_of(lambda: fd.rnea(fmodel, fq, fv, fa, backend="reference"), 20)
print(f"  fd.rnea (9 DoF, backend='reference', NumPy):                {t_ref * 1e6:8.1f} µs  = "
      f"{t_ref / t_rnea:6.1f}× pin.rnea")
if fd.core.available() and fd.default_backend() is None:
    # backend=None (the default) hands one float64 state straight to the core; backend="compiled" would
    # take the general path (full input checks in Python, then the same kernel)
    fd.rnea(fmodel, fq, fv, fa)  # the first call copies the model's arrays into the core
    t_compiled = best_of(lambda: fd.rnea(fmodel, fq, fv, fa), 20000)
    print(f"  fd.rnea (9 DoF, default backend = compiled core, C++):     {t_compiled * 1e6:8.2f} µs  = "
          f"{t_compiled / t_rnea:6.1f}× pin.rnea")
    check("both backends give the same τ", fd.rnea(fmodel, fq, fv, fa),
          fd.rnea(fmodel, fq, fv, fa, backend="reference"), 1e-10)
else:
    print("  the default backend is the reference here (core not built or FEATHERDYN_BACKEND=reference): "
          "the compiled core is not measured")

# %% 4. RBDL
section("4. RBDL (appendix G.2: 'Pinocchio is 3–10× faster than RBDL')")
have = [name for name in ("rbdl", "pyrbdl") if importlib.util.find_spec(name) is not None]
if have:
    print(f"  an RBDL binding is importable ({have}) — not benchmarked by this script")
else:
    print("  no RBDL binding importable: `rbdl` is not on PyPI, and `pyrbdl` 0.0.2 does not build on")
    print("  Python ≥ 3.11 — the 3–10× claim cannot be measured here.")
print("\nSpeed measurements done.")
