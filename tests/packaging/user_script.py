"""A user's script, type-checked by tests/packaging/test_typing.py with ``mypy --strict`` (never run)."""
import numpy as np

import featherdyn as fd

model = fd.load_robot("panda")
q, v, a = fd.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
tau = fd.rnea(model, q, v, a)
ddq = fd.compile(model).aba(q, v, tau)
held = fd.constrained_dynamics(model, q, v, tau, [fd.FrameContact("panda_hand")])
reveal_type(tau)  # noqa: F821 (mypy's)
reveal_type(ddq)  # noqa: F821 (mypy's)
reveal_type(held)  # noqa: F821 (mypy's)
reveal_type(held.ddq)  # noqa: F821 (mypy's)
