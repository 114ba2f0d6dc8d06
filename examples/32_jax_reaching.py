# needs: featherdyn[jax] (jax): pip install "featherdyn[jax]"
"""A two-link arm driven to a target by gradient descent in JAX, through featherdyn's forward dynamics.

The torques of a 1.5 s horizon (60 steps) are the unknowns; the rollout integrates
``q̈ = fj.aba(model, q, q̇, τ)`` (semi-implicit Euler) and the cost is the distance to the
target state ``q = (π, 0)`` at rest at the end plus a small torque penalty (the arm moves in a
horizontal plane: gravity does no work). ``jax.grad`` differentiates the
whole rollout: each ``fj.aba`` is one XLA FFI call into the compiled core, and its
derivative the declared ``fd.aba_derivatives`` (no autodiff through scalar operations).
Checked: the gradient against a central difference, and that the cost falls tenfold.

Run: python examples/32_jax_reaching.py
"""

# %% 0. the arm, the horizon, the cost
from __future__ import annotations

from _check import needs

needs("jax")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, section, show

import featherdyn as fd
import featherdyn.jax as fj
import jax
import jax.numpy as jnp

model = fd.load_robot("two_link_arm")
N, dt = 60, 0.025
target = jnp.array([np.pi, 0.0])


def rollout(u: jax.Array) -> tuple[jax.Array, jax.Array]:
    """The final ``(q, q̇)`` from rest at q = 0 under the torques ``u`` `(N, 2)`."""

    def step(x: tuple[jax.Array, jax.Array], tau: jax.Array) -> tuple[tuple[jax.Array, jax.Array], None]:
        q, v = x
        v = v + dt * fj.aba(model, q, v, tau)
        return (q + dt * v, v), None

    (q, v), _ = jax.lax.scan(step, (jnp.zeros(2), jnp.zeros(2)), u)
    return q, v


def cost(u: jax.Array) -> jax.Array:
    q, v = rollout(u)
    return jnp.sum((q - target) ** 2) + 0.1 * jnp.sum(v**2) + 1e-4 * jnp.sum(u**2)


# %% 1. the gradient through the rollout, checked
section("the gradient of the cost through 60 calls of fj.aba")
grad = jax.jit(jax.grad(cost))
u = jnp.zeros((N, 2))
g = grad(u)
e = np.zeros((N, 2))
e[10, 1] = 1e-6
finite = (cost(u + e) - cost(u - e)) / 2e-6
check("∂cost/∂u[10, 1] against a central difference", float(g[10, 1]), float(finite), tol=1e-6)

# %% 2. gradient descent (Adam, in a few lines)
section("to the target by gradient descent")
m, s = jnp.zeros_like(u), jnp.zeros_like(u)
value_and_grad = jax.jit(jax.value_and_grad(cost))
first = float(cost(u))
for k in range(1, 401):
    c, g = value_and_grad(u)
    m, s = 0.9 * m + 0.1 * g, 0.999 * s + 0.001 * g**2
    u = u - 0.05 * (m / (1 - 0.9**k)) / (jnp.sqrt(s / (1 - 0.999**k)) + 1e-8)
last = float(cost(u))
q_end, _ = rollout(u)
show("cost before", first)
show("cost after 400 steps", last)
show("final joint angles (target: π, 0)", np.asarray(q_end))
check_true("the cost fell by at least 10×", last < 0.1 * first)
