"""Constraints on a model (``featherdyn/constraints.py``): the contact plan and its cache on the model.

* the plan resolves each contact against its own model (frame index, rows, reference code, K_d);
* the plans live on the model (``model._plans``): two models called in turn with the same list each get their
  own plan, the same answer where they are the same robot, and a model's plans go when the model does;
* the cache is bounded, and the last list's plan is served only while the list is unchanged.
"""

from __future__ import annotations

import dataclasses
import gc
import weakref

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.constraints import ConstraintPlans, cached_contact_plan, contact_plan, frames_plan, plans_of
from featherdyn.model import FrameInfo
from featherdyn.spatial_algebra import PluckerTransform

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


@pytest.fixture(scope="module")
def solo() -> fd.Model:
    model = library_robot("solo12", True)
    assert model is not None
    return model


def _shifted(model: fd.Model) -> fd.Model:
    """The same robot with one more frame in front: every frame index one higher (its plans must differ)."""
    extra = FrameInfo("extra_marker", 0, PluckerTransform.identity(), "link")
    return dataclasses.replace(model, frames=(extra, *model.frames))


def _no_compile(model: fd.Model, plan: object) -> None:
    return None


def test_the_plan_resolves_contacts_against_the_model(solo: fd.Model) -> None:
    cons = (fd.PointContact("FL_FOOT", fd.WORLD, baumgarte=(1.0, 2.5)), fd.FrameContact("HR_FOOT"))
    plan = contact_plan(solo, cons)
    assert plan is not None
    fl, hr = solo.frame_id("FL_FOOT"), solo.frame_id("HR_FOOT")
    np.testing.assert_array_equal(plan.specs, [[3, fl, 1, 2.5], [6, hr, 0, 0.0]])
    assert plan.slices == (slice(0, 3), slice(3, 9)) and plan.size == 9
    assert not plan.specs.flags.writeable
    assert contact_plan(solo, (fd.PointContact("FL_FOOT"), fd.LoopConstraint("FR_FOOT", "HR_FOOT"))) is None
    frames = frames_plan(solo, ["FL_FOOT", "HR_FOOT"], fd.LOCAL_WORLD_ALIGNED)
    np.testing.assert_array_equal(frames.specs, [[6, fl, 2, 0.0], [6, hr, 2, 0.0]])
    with pytest.raises(fd.ConstraintError, match="fixed to the world"):
        contact_plan(fd.load_robot("panda"), (fd.PointContact("panda_link0"),))


def test_two_models_called_in_turn_each_get_their_own_plan(solo: fd.Model) -> None:
    a, b = dataclasses.replace(solo), _shifted(solo)
    rng = np.random.default_rng(3)
    q, v, tau = fd.random_configuration(solo, rng), rng.normal(size=solo.nv), rng.normal(size=solo.nv)
    cons = [fd.PointContact(f) for f in FEET[:3]]
    for _ in range(3):  # interleaved: a, b, a, b, ... with the very same list
        ra = fd.constrained_dynamics(a, q, v, tau, cons)
        rb = fd.constrained_dynamics(b, q, v, tau, cons)
        np.testing.assert_allclose(ra.ddq, rb.ddq, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(ra.lagrange, rb.lagrange, rtol=1e-12, atol=1e-12)
    pa, pb = plans_of(a).last_contacts[1], plans_of(b).last_contacts[1]
    assert pa is not None and pb is not None and pa[0] is not pb[0]
    np.testing.assert_array_equal(pb[0].specs[:, 1], pa[0].specs[:, 1] + 1)
    np.testing.assert_array_equal(pa[0].specs[:, 1], [solo.frame_id(f) for f in FEET[:3]])
    # the frames' plans (fd.operational_space_inertia) too
    la, lb = (fd.operational_space_inertia(m, q, ["FL_FOOT", "HR_FOOT"]) for m in (a, b))
    np.testing.assert_allclose(la, lb, rtol=1e-10)
    fa, fb = plans_of(a).last_frames[2], plans_of(b).last_frames[2]
    np.testing.assert_array_equal(fb[0].specs[:, 1], fa[0].specs[:, 1] + 1)


def test_a_model_takes_its_plans_with_it(solo: fd.Model) -> None:
    model = dataclasses.replace(solo)
    q, zero = fd.neutral(model), np.zeros(model.nv)
    fd.constrained_dynamics(model, q, zero, zero, [fd.PointContact(f) for f in FEET])
    fd.operational_space_inertia(model, q, "FL_FOOT")
    plans = plans_of(model)
    contacts, frames = plans.last_contacts[1][0], plans.last_frames[2][0]
    alive = [weakref.ref(contacts), weakref.ref(frames)]
    del model, plans, contacts, frames
    gc.collect()
    assert [r() for r in alive] == [None, None]


def test_the_cache_is_bounded_and_the_last_list_is_compared_item_by_item(solo: fd.Model) -> None:
    model = dataclasses.replace(solo)
    plans = plans_of(model)
    assert isinstance(plans, ConstraintPlans) and plans_of(model) is plans
    for k in range(ConstraintPlans.MAX + 5):
        cached_contact_plan(model, (fd.PointContact("FL_FOOT", baumgarte=(0.0, float(k))),), _no_compile)
        assert len(plans.by_key) <= ConstraintPlans.MAX
    cons = [fd.PointContact("FL_FOOT")]
    first = cached_contact_plan(model, cons, _no_compile)
    assert first is not None and cached_contact_plan(model, list(cons), _no_compile) is first
    cons[0] = fd.FrameContact("FL_FOOT")
    assert cached_contact_plan(model, cons, _no_compile)[0].size == 6
    cons.append(fd.LoopConstraint("FR_FOOT", "HR_FOOT"))
    assert cached_contact_plan(model, cons, _no_compile) is None
    assert cached_contact_plan(model, [fd.PointContact("FL_FOOT"), np.zeros(3)], _no_compile) is None


def test_a_model_copy_and_a_pickle_start_without_plans(solo: fd.Model) -> None:
    import pickle

    model = dataclasses.replace(solo)
    fd.constraint_jacobian(model, fd.neutral(model), fd.PointContact("FL_FOOT"))
    fd.constrained_dynamics(model, fd.neutral(model), np.zeros(model.nv), np.zeros(model.nv), fd.PointContact("FL_FOOT"))
    assert plans_of(model).by_key
    for other in (dataclasses.replace(model), pickle.loads(pickle.dumps(model))):
        with pytest.raises(AttributeError):
            other._plans  # noqa: B018
