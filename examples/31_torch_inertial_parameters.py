# needs: featherdyn[torch,verify] (torch; example-robot-data for panda): pip install "featherdyn[torch,verify]"
"""Learning a robot's inertial parameters with PyTorch, through featherdyn's operators.

``import featherdyn.torch as ft`` gives featherdyn's functions as PyTorch operators (docs/frameworks.md):
tensors in, tensors out, with analytical gradients. The torques are linear in the ten inertial parameters
of each body, ``τ = Y(q, q̇, q̈) π`` (``ft.joint_torque_regressor``), so a batch of measured torques
identifies the combinations of ``π`` the motions excite; here an optimiser of ``torch.optim`` finds them
from noisy torques of panda. Then a gradient through ``ft.rnea`` itself: the gradient of the torque error
with respect to the accelerations, ``M (τ − τ*)``, and the Newton step it gives, which lands on ABA's.

Run: python examples/31_torch_inertial_parameters.py
"""

# %% 0. a robot and a batch of recorded motions
from __future__ import annotations

from _check import needs

needs("torch", "example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
import torch
from _check import check, check_true, section

import featherdyn as fd
import featherdyn.torch as ft

torch.manual_seed(0)
model = fd.load_robot("panda")
rng = np.random.default_rng(31)
n = 400
Q = torch.tensor(fd.random_configuration(model, rng, size=n))
V, A = torch.tensor(rng.normal(size=(n, model.nv))), torch.tensor(rng.normal(size=(n, model.nv)))
tau = ft.rnea(model, Q, V, A)                                # the "measured" torques, (n, nv)
measured = tau + 1e-3 * torch.randn_like(tau)                 # with 1 mN·m of noise

# %% 1. the regressor: τ = Y π, π the bodies' ten parameters (m, m c, I about the body origin)
section("τ = Y(q, q̇, q̈) π")
Y = ft.joint_torque_regressor(model, Q, V, A)                # (n, nv, 10 nb)
pi_true = torch.tensor(fd.dynamic_parameters(model))
check("Y π_true = RNEA", Y @ pi_true, tau, 1e-9)

# %% 2. learn π from the noisy torques with an optimiser of torch.optim (from zero)
section("π learned by L-BFGS on the mean squared torque error")
train, test = slice(0, 300), slice(300, n)
pi = torch.zeros_like(pi_true, requires_grad=True)
opt = torch.optim.LBFGS([pi], max_iter=300, tolerance_grad=1e-12, tolerance_change=1e-15,
                        line_search_fn="strong_wolfe")


def closure() -> torch.Tensor:
    opt.zero_grad()
    loss = torch.mean((Y[train] @ pi - measured[train]) ** 2)
    loss.backward()
    return loss


for _ in range(2):
    opt.step(closure)
pi_hat = pi.detach()
# (driver gelsd: the SVD's minimum-norm solution, right for a rank-deficient Y; the default driver differs between
# PyTorch releases, and torch 2.13's CPU default returned a wrong solution here)
lstsq = torch.linalg.lstsq(Y[train].reshape(-1, Y.shape[-1]), measured[train].reshape(-1), driver="gelsd").solution
error = (Y[test] @ pi_hat - tau[test]).abs().max()
print(f"  held-out torque error {float(error):.2e} N·m (noise 1e-3), "
      f"{int(torch.linalg.matrix_rank(Y[train].reshape(-1, Y.shape[-1])))} of {Y.shape[-1]} combinations identifiable")
check("the learned π predicts the held-out torques", Y[test] @ pi_hat, tau[test], 1e-2)
check("and agrees with the least-squares solution there", Y[test] @ pi_hat, Y[test] @ lstsq, 1e-5)
check_true("π itself is not unique (the regressor has a null space): π̂ ≠ π_true",
           bool((pi_hat - pi_true).abs().max() > 1e-3))

# %% 3. a gradient through ft.rnea: of the torque error, with respect to the accelerations
section("∇_q̈ ½|RNEA(q, q̇, q̈) − τ*|² = M(q) (τ − τ*)  (backward: fd.rnea_derivatives)")
q, v = Q[:8], V[:8]
a = A[:8].clone().requires_grad_(True)
error = ft.rnea(model, q, v, a) - measured[:8]
loss = 0.5 * torch.sum(error ** 2)
(grad_a,) = torch.autograd.grad(loss, a)
M = ft.crba(model, q)                                          # (8, nv, nv)
check("autograd through ft.rnea = M (τ − τ*)", grad_a, (M @ error.detach()[..., None])[..., 0], 1e-9)
# one Newton step on the accelerations (the error is affine in q̈): q̈ − M⁻¹ (τ − τ*) = ABA(q, q̇, τ*)
a_new = a.detach() - torch.linalg.solve(M, torch.linalg.solve(M, grad_a[..., None]))[..., 0]
check("one Newton step with that gradient lands on ft.aba(q, q̇, τ*)", a_new, ft.aba(model, q, v, measured[:8]), 1e-8)
