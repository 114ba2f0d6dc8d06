"""Hypothesis fuzzing of ``fd.constrained_dynamics_derivatives`` and ``fd.impulse_dynamics_derivatives``: the
state bent as ``test_numeric_fuzz.py`` bends it (shapes, dtypes, layouts, odd values, non-unit quaternions),
and odd constraint arguments (unknown frames, bad references and gains, dependent contacts, bad ``mu`` and
restitution). The contract is that file's: a result (finite for finite input) or a featherdyn error, no
warning, no crash.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_numeric_fuzz import _check, bent_array

import featherdyn as fd
from featherdyn.errors import FeatherdynError

_SOLO: list[fd.Model] = []


def _solo() -> fd.Model:
    if not _SOLO:
        _SOLO.append(fd.load_robot("solo12", floating_base=True))
    return _SOLO[0]


@st.composite
def constraint_sets(draw: st.DrawFn) -> Any:
    frames = st.sampled_from(["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT", "base_link", "nope", 3, -1, 10**6])
    refs = st.sampled_from([fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED, "world", "sideways"])
    gains = st.sampled_from([(0.0, 0.0), (1.0, 2.0), (-1.0, 0.0), (np.nan, 1.0), "x"])
    out = []
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["point", "frame", "loop", "junk"]))
        try:
            if kind == "point":
                out.append(fd.PointContact(draw(frames), draw(refs), baumgarte=draw(gains)))
            elif kind == "frame":
                out.append(fd.FrameContact(draw(frames), draw(refs), baumgarte=draw(gains)))
            elif kind == "loop":
                out.append(fd.LoopConstraint(draw(frames), draw(frames), reference=draw(refs), baumgarte=draw(gains)))
            else:
                out.append(draw(st.sampled_from(["FL_FOOT", None, 1.5])))
        except FeatherdynError:
            continue
    return out


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data(), which=st.sampled_from(["constrained", "impulse"]),
       backend=st.sampled_from([None, None, "reference"]))
def test_contact_derivatives_raise_featherdyn_errors_or_return_finite_numbers(data: st.DataObject, which: str,
                                                                               backend: str | None) -> None:
    model = _solo()
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    q = data.draw(bent_array(fd.random_configuration(model, rng)), "q")
    v = data.draw(bent_array(rng.normal(size=model.nv)), "v")
    tau = data.draw(bent_array(rng.normal(size=model.nv)), "tau")
    cons = data.draw(constraint_sets(), "constraints")
    mu = data.draw(st.sampled_from([0.0, 0.0, 1e-6, -1.0, np.nan]), "mu")
    if which == "constrained":
        _check(lambda: fd.constrained_dynamics_derivatives(model, q, v, tau, cons, mu=mu, backend=backend).ddq_dq,
               q, v, tau)
    else:
        e = data.draw(st.sampled_from([0.0, 0.5, 1.0, 2.0, -0.1, np.nan]), "restitution")
        _check(lambda: fd.impulse_dynamics_derivatives(model, q, v, cons, restitution=e, mu=mu,
                                                       backend=backend).dv_plus_dq, q, v)
