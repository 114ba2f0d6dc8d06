# needs: featherdyn[verify] (example-robot-data): pip install "featherdyn[verify]"
"""One DDP step for a quadruped on its four feet, from the contact-dynamics derivatives.

Solo12 stands on four point contacts and should lower its base by 4 cm in a quarter of a
second. The discrete dynamics (semi-implicit Euler on the configuration manifold)::

    v⁺ = v + Δt q̈(q, v, τ),      q⁺ = q ⊕ Δt v⁺        (q̈ from fd.constrained_dynamics)

is linearised at each knot from ``fd.constrained_dynamics_derivatives`` (∂q̈/∂q along
fd.integrate's tangent, ∂q̈/∂v, ∂q̈/∂τ) and ``fd.integrate_derivatives``::

    ∂v⁺/∂(q, v, τ) = Δt ∂q̈ + (0, 1, 0)
    ∂q⁺/∂q = J_q + J_v Δt ∂v⁺/∂q,   ∂q⁺/∂v = J_v Δt ∂v⁺/∂v,   ∂q⁺/∂τ = J_v Δt ∂v⁺/∂τ

then one iLQR/DDP backward pass (Gauss–Newton cost Hessians) and a forward pass with a line
search. Checked: the linearisation against a finite difference of the rollout, and that the
step lowers the cost.

Run: python examples/30_quadruped_ddp_step.py
"""

# %% 0. the robot, the contacts, the horizon
from __future__ import annotations

from _check import needs

needs("example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, section, show

import featherdyn as fd

model = fd.load_robot("solo12", floating_base=True)
nv = model.nv
contacts = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED, baumgarte=(0.0, 10.0))
            for f in ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]]
q0 = fd.neutral(model)
q0[7:] = [0.0, 0.8, -1.6] * 2 + [0.0, -0.8, 1.6] * 2  # knees bent (straight legs could not lower the base)
dt, N = 0.025, 10
q_goal = q0.copy()
q_goal[2] -= 0.04  # the base 4 cm lower (q[2]: the free-flyer's height)
tau_rest = fd.generalized_gravity(model, q0)[6:]  # the legs' share of gravity (the contacts carry the rest)
S = np.eye(nv)[:, 6:]  # actuation: the twelve leg joints (the base has no motor)
W_q, w_v, w_u = np.diag([1.0] * 6 + [0.1] * 12) * 100.0, 1.0, 1e-3


def step(q: np.ndarray, v: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(q⁺, v⁺)``: semi-implicit Euler under the contacts (the module docstring's equation)."""
    v_next = v + dt * fd.constrained_dynamics(model, q, v, S @ u, contacts).ddq
    return fd.integrate(model, q, dt * v_next), v_next


def linearised(q: np.ndarray, v: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(A, B)``: ∂(q⁺, v⁺)/∂(q, v) `(2nv, 2nv)` and ∂(q⁺, v⁺)/∂u `(2nv, 12)`, q along its tangent."""
    d = fd.constrained_dynamics_derivatives(model, q, v, S @ u, contacts)
    v_next = v + dt * d.ddq
    Jq, Jv = fd.integrate_derivatives(model, q, dt * v_next)
    dv = np.hstack([dt * d.ddq_dq, np.eye(nv) + dt * d.ddq_dv])
    dq = np.hstack([Jq, np.zeros((nv, nv))]) + dt * Jv @ dv
    A = np.vstack([dq, dv])
    B = np.vstack([dt * Jv @ (dt * d.ddq_dtau @ S), dt * d.ddq_dtau @ S])
    return A, B


def cost(qs: list[np.ndarray], vs: list[np.ndarray], us: list[np.ndarray]) -> float:
    """``Σ ½‖q ⊖ q_goal‖²_W + ½ w_v ‖v‖² + ½ w_u ‖u − u_rest‖²`` over the knots."""
    total = 0.0
    for k, (q, v) in enumerate(zip(qs, vs, strict=True)):
        e = fd.difference(model, q_goal, q)
        total += 0.5 * e @ W_q @ e + 0.5 * w_v * v @ v
        if k < N:
            du = us[k] - tau_rest
            total += 0.5 * w_u * du @ du
    return float(total)


def rollout(us: list[np.ndarray]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    qs, vs = [q0], [np.zeros(nv)]
    for u in us:
        q, v = step(qs[-1], vs[-1], u)
        qs.append(q)
        vs.append(v)
    return qs, vs


# %% 1. the nominal trajectory: hold the rest torques
section("the nominal trajectory (the rest torques held)")
us = [tau_rest.copy() for _ in range(N)]
qs, vs = rollout(us)
J0 = cost(qs, vs, us)
show("cost", J0)

# %% 2. the linearisation, checked against the rollout
section("the contact dynamics linearised at knot 3")
A, B = linearised(qs[3], vs[3], us[3])
dx = np.random.default_rng(0).normal(size=2 * nv) * 1e-6
du = np.random.default_rng(1).normal(size=12) * 1e-6
qp, vp = step(fd.integrate(model, qs[3], dx[:nv]), vs[3] + dx[nv:], us[3] + du)
qm, vm = step(fd.integrate(model, qs[3], -dx[:nv]), vs[3] - dx[nv:], us[3] - du)
finite = np.concatenate([fd.difference(model, qm, qp), vp - vm]) / 2
check("(A δx + B δu) against the rollout's central difference", A @ dx + B @ du, finite, tol=1e-12)

# %% 3. one DDP step: backward pass (Gauss-Newton), forward pass with a line search
section("one DDP step")
Vx = np.zeros(2 * nv)
Vxx = np.zeros((2 * nv, 2 * nv))
e = fd.difference(model, q_goal, qs[N])
Vx[:nv], Vx[nv:] = W_q @ e, w_v * vs[N]
Vxx[:nv, :nv], Vxx[nv:, nv:] = W_q, w_v * np.eye(nv)
gains = []
for k in reversed(range(N)):
    A, B = linearised(qs[k], vs[k], us[k])
    e = fd.difference(model, q_goal, qs[k])
    lx = np.concatenate([W_q @ e, w_v * vs[k]])
    lxx = np.block([[W_q, np.zeros((nv, nv))], [np.zeros((nv, nv)), w_v * np.eye(nv)]])
    Qx, Qu = lx + A.T @ Vx, w_u * (us[k] - tau_rest) + B.T @ Vx
    Qxx, Quu, Qux = lxx + A.T @ Vxx @ A, w_u * np.eye(12) + B.T @ Vxx @ B, B.T @ Vxx @ A
    kff, K = -np.linalg.solve(Quu, Qu), -np.linalg.solve(Quu, Qux)
    gains.append((kff, K))
    Vx = Qx + K.T @ Quu @ kff + K.T @ Qu + Qux.T @ kff
    Vxx = Qxx + K.T @ Quu @ K + K.T @ Qux + Qux.T @ K
    Vxx = 0.5 * (Vxx + Vxx.T)
gains.reverse()

best = J0
for alpha in (1.0, 0.5, 0.25, 0.125):
    q, v, new_us, new_qs, new_vs = q0, np.zeros(nv), [], [q0], [np.zeros(nv)]
    for k in range(N):
        dx = np.concatenate([fd.difference(model, qs[k], q), v - vs[k]])
        u = us[k] + alpha * gains[k][0] + gains[k][1] @ dx
        q, v = step(q, v, u)
        new_us.append(u)
        new_qs.append(q)
        new_vs.append(v)
    J1 = cost(new_qs, new_vs, new_us)
    show(f"cost after the step, α = {alpha}", J1)
    if J1 < J0:
        best = J1
        break
check_true("the DDP step lowers the cost", best < 0.5 * J0)
show("base height at the last knot [m] (goal 0.04 below the start)", new_qs[N][2] - q0[2])
