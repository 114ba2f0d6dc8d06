"""Drake as a third oracle of ``featherdyn verify`` (``--oracle drake|all``).

The same file is parsed by Drake (``pydrake``'s ``Parser`` into a
``MultibodyPlant``: URDF, MJCF, SDFormat) and loaded by featherdyn; joints are
matched by name (a free-flyer by the body it moves) into a
:class:`~featherdyn.conventions.drake.DrakeLayout`, and at seeded random states
the rigid-body quantities are compared in Drake's coordinates, featherdyn's
numbers converted by :mod:`featherdyn.conventions.drake` (floating base
``q = [qw qx qy qz, x y z]``, ``v = [ω_WB; v_WBo]`` in world axes, Drake's
joint order, ``τ_g = −g``):

* total mass of the moving bodies; reflected rotor inertia
  (``JointActuator::calc_reflected_inertia``) against featherdyn's armature;
* body placements (``CalcRelativeTransform`` from the world to each body whose
  name is a featherdyn link or body frame);
* ``M(q)`` (``CalcMassMatrix``), gravity (``CalcGravityGeneralizedForces``),
  the bias ``C v`` (``CalcBiasTerm``), inverse dynamics
  (``CalcInverseDynamics`` with gravity as the applied generalized force),
  forward dynamics (``v̇ = M⁻¹ (τ + τ_g − C v)`` from Drake's own ``M`` and
  terms, judged by its backward error like Pinocchio's ABA);
* frame Jacobians (``CalcJacobianSpatialVelocity`` with respect to ``v``,
  measured and expressed in the world at the frame origin) in featherdyn's
  three references, on a link frame of each of the (up to) three deepest bodies.

What Drake cannot take as featherdyn's model is a :class:`DrakeRefusedError`, not a
failed comparison (``verify`` lists it with Drake's reason, as it lists the
oracles ``--oracle all`` leaves out): its parser refuses the file (its error:
a ``<mimic>`` of a joint that does not exist, ...); its parser changed the model
(its warning: an inertia it judged unphysical and replaced, an MJCF
``settotalmass`` it ignores); its MJCF parser moves the axis of the first of
several joints on a body (placed in the parent's frame without the body's
``pos`` and ``quat``; MuJoCo agrees with featherdyn); its plant drops the
armature of a joint no actuator drives (an MJCF ``armature`` on an unactuated
joint: Drake holds rotor inertia on a ``JointActuator`` only); or, with ``--floating-base``, Drake welds the body featherdyn floats
(its URDF parser welds a link named ``world`` to its world). What it ignores
without changing the rigid-body tree (``frictionloss``, joint friction,
``<safety_controller>``, mechanical reductions) is said in the report. Joint
damping, which Drake's plant applies as a force element, is left out on
purpose: the comparison is of the rigid-body tree (the applied force in
``CalcInverseDynamics`` is gravity alone).
"""

from __future__ import annotations

import importlib
import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..api import aba, crba, frame_jacobian, frame_placement, generalized_gravity, nonlinear_effects, rnea
from ..configuration import random_configuration
from ..conventions import drake as _conv
from ..errors import FeatherdynError, MissingDependencyError, ModelError, SingularMassMatrixError
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD
from ..model import Model
from .dynamics import _pick_frames, forward_dynamics_result
from .report import CheckResult, PairedRows, compare

__all__ = ["require_drake", "drake_version", "DrakePlant", "DrakeRefusedError", "build_drake", "drake_checks",
           "load_sdf_model", "dynamics_warnings", "model_changes"]

GROUP = "drake"

#: the forward-dynamics row: featherdyn's ABA against a solve with Drake's own M and terms
FORWARD = "aba vs Drake's M⁻¹ (τ + τ_g − CalcBiasTerm)"

_INSTALL = "pip install drake (or pip install 'featherdyn[drake]')"

#: words of a Drake parser warning about something that enters the rigid-body dynamics
_DYNAMICS_WORDS = ("mass", "inertia", "armature", "damping", "friction", "stiffness", "springref", "'ref'", "gear",
                   "reduction", "transmission", "actuator", "gravity", "inertial", "'range'", "limited")


#: Drake parser warnings after which its plant is not the file's model: (what Drake changed, words of the warning)
_CHANGES = (("an inertia it judged unphysical, replaced", ("while parsing inertia matrix",
                                                           "while re-expressing as central inertia")),
            ("the total mass: MJCF settotalmass ignored", ("settotalmass",)),
            ("the rotor inertia: armature ignored", ("'armature'",)))


class DrakeRefusedError(ModelError):
    """Drake cannot take the file as featherdyn's model: its parser refuses it, changed the model, or welds a
    body featherdyn floats. Not a failed comparison: ``verify`` lists the model with Drake's reason."""


def model_changes(warnings: list[str]) -> list[str]:
    """The Drake parser warnings after which its plant is another model than the file's, each as
    ``"<what Drake changed>: <Drake's words>"`` (an inertia it replaced, a total mass it ignored, ...)."""
    return [f"{what} ({w})" for w in warnings for what, words in _CHANGES if any(x in w.lower() for x in words)]


def require_drake() -> Any:
    """The ``pydrake`` module (its plant and parser imported), or :class:`MissingDependencyError` with the install."""
    try:
        import pydrake
        import pydrake.multibody.parsing
        import pydrake.multibody.plant
    except ImportError:
        raise MissingDependencyError(f"--oracle drake needs Drake (the pydrake module): {_INSTALL}") from None
    return pydrake


def drake_version() -> str:
    """Drake's version, or ``"not installed"``."""
    try:
        import pydrake
    except ImportError:
        return "not installed"
    return str(getattr(pydrake, "__version__", "unknown"))


@contextmanager
def _drake_log() -> Iterator[list[str]]:
    """The warnings Drake logs (its parser's) while the block runs, instead of on stderr."""
    caught: list[str] = []

    class _Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            caught.append(record.getMessage())

    logger = logging.getLogger("drake")
    handler, propagate, level = _Keep(level=logging.WARNING), logger.propagate, logger.level
    logger.addHandler(handler)
    logger.propagate = False  # kept for the report, not printed
    logger.setLevel(logging.WARNING)  # even where the caller silenced Drake: the report must say what it ignored
    try:
        yield caught
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate
        logger.setLevel(level)


def _short(message: str) -> str:
    """A Drake warning without its ``file:line: warning:`` prefix, on one line."""
    text = " ".join(message.split())
    return text.split(" warning: ", 1)[-1] if " warning: " in text else text


def dynamics_warnings(warnings: list[str]) -> list[str]:
    """The Drake parser warnings that name something of the rigid-body dynamics (masses, joints, gears, ...)."""
    return [w for w in warnings if any(word in w.lower() for word in _DYNAMICS_WORDS)]


@dataclass
class DrakePlant:
    """A finalized ``MultibodyPlant`` of one file, its context, and where featherdyn's joints sit in it.

    Attributes:
        plant, context: Drake's plant and a default context of it.
        instances: the model instances the parser added.
        layout: featherdyn joint → Drake ``position_start`` / ``velocity_start``.
        warnings: what Drake's parser said (deduplicated, prefixes removed).
        notes: what the comparison leaves out, and why (joint damping, ...).
    """

    plant: Any
    context: Any
    instances: list[Any]
    layout: _conv.DrakeLayout
    warnings: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def body(self, name: str) -> Any:
        """Drake's body called ``name`` in the parsed instances, or ``None``."""
        for instance in self.instances:
            if self.plant.HasBodyNamed(name, instance):
                return self.plant.GetBodyByName(name, instance)
        return None


def _parse(plant: Any, path: Path) -> tuple[list[Any], list[str]]:
    from pydrake.multibody.parsing import Parser

    with _drake_log() as caught:
        try:
            instances = list(Parser(plant).AddModels(path))
        except (RuntimeError, ValueError) as exc:
            first = " ".join(str(exc).split())[:400]
            raise DrakeRefusedError(f"{path}: Drake's parser refuses it ({first}); nothing was compared with Drake") from None
    return instances, list(dict.fromkeys(_short(w) for w in caught))


def _weld_roots(plant: Any, instances: list[Any]) -> None:
    """Weld to the world each parsed body that has no inboard joint (featherdyn's fixed-base URDF)."""
    from pydrake.multibody.tree import JointIndex

    children = {int(plant.get_joint(JointIndex(j)).child_body().index()) for j in range(plant.num_joints())}
    world = int(plant.world_body().index())
    for instance in instances:
        for b in plant.GetBodyIndices(instance):
            if int(b) not in children and int(b) != world:
                plant.WeldFrames(plant.world_frame(), plant.get_body(b).body_frame())


def _layout(model: Model, plant: Any, instances: list[Any]) -> _conv.DrakeLayout:
    """featherdyn's joints found in the plant (by name; a free-flyer by the body it moves), and checked to cover it."""
    from pydrake.multibody.tree import JointIndex

    joints = [plant.get_joint(JointIndex(j)) for j in range(plant.num_joints())]
    floating = {j.child_body().name(): j for j in joints if j.num_velocities() == 6 and j.num_positions() == 7}
    kinds = {"revolute": ("revolute",), "prismatic": ("prismatic",), "free_flyer": ("quaternion_floating",)}
    welded = {b.name() for b in plant.GetBodiesWeldedTo(plant.world_body())}
    q_start, v_start, missing, wrong = [], [], [], []
    for i, (name, joint) in enumerate(zip(model.joint_names, model.joints, strict=True)):
        found = None
        if joint.kind == "free_flyer":
            found = floating.get(model.body_names[i])
            if found is None and model.body_names[i] in welded:
                raise DrakeRefusedError(
                    f"not comparable: Drake welds body {model.body_names[i]!r} to its world, featherdyn floats it "
                    f"(joint {name!r})" + ("; Drake's URDF parser welds a link named 'world' to its world, so this "
                                           "robot has no floating base there" if model.body_names[i] == "world" else "")
                    + "; nothing was compared with Drake")
        else:
            found = next((plant.GetJointByName(name, inst) for inst in instances if plant.HasJointNamed(name, inst)),
                         None)
        if found is None:
            missing.append(name)
            continue
        if found.type_name() not in kinds.get(joint.kind, ()):
            wrong.append(f"{name} ({joint.kind} here, Drake's {found.type_name()})")
            continue
        q_start.append(found.position_start())
        v_start.append(found.velocity_start())
    if missing or wrong:
        drake_moving = sorted(j.name() for j in joints if j.num_velocities() > 0)
        raise ModelError(
            "Drake's plant has other joints than featherdyn's model"
            + (f"; featherdyn's not in Drake: {missing[:6]}" if missing else "")
            + (f"; of another type: {wrong[:4]}" if wrong else "")
            + f" (Drake's moving joints: {drake_moving[:8]}{' …' if len(drake_moving) > 8 else ''})"
            + ("; Drake's URDF parser welds a link named 'world' to its world, so such a robot has no floating base "
               "there" if any(model.joints[model.joint_names.index(n)].kind == "free_flyer" for n in missing) else "")
            + "; nothing was compared with Drake")
    if plant.num_positions() != model.nq or plant.num_velocities() != model.nv:
        raise ModelError(f"Drake's plant has nq={plant.num_positions()}, nv={plant.num_velocities()}; featherdyn's "
                         f"model nq={model.nq}, nv={model.nv} (a body floating in one and welded in the other?); "
                         "nothing was compared with Drake")
    return _conv.DrakeLayout(tuple(q_start), tuple(v_start))


def build_drake(path: str | os.PathLike[str], model: Model, *, weld_root: bool) -> DrakePlant:
    """Drake's plant of ``path``, with featherdyn's ``model``'s joints located in it.

    Args:
        path: a URDF, MJCF or SDFormat file (Drake's parser picks by the extension).
        model: featherdyn's model of the same file.
        weld_root: weld the parsed root bodies to the world (a URDF loaded without ``--floating-base``:
            Drake's URDF parser leaves a root link free, featherdyn fixes it).

    Raises:
        MissingDependencyError: pydrake is not installed.
        ModelError: Drake's parser refuses the file, or its joints are not featherdyn's.
    """
    require_drake()
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)
    instances, warnings = _parse(plant, Path(path))
    changed = model_changes(warnings)
    if changed:
        raise DrakeRefusedError(f"{os.fspath(path)}: not comparable: Drake's parser changed the model: "
                           + "; ".join(changed[:3]) + (f"; and {len(changed) - 3} more" if len(changed) > 3 else "")
                           + "; nothing was compared with Drake")
    if weld_root:
        _weld_roots(plant, instances)
    plant.Finalize()
    layout = _layout(model, plant, instances)
    notes = []
    from pydrake.multibody.tree import JointIndex

    damped = [plant.get_joint(JointIndex(j)).name() for j in range(plant.num_joints())
              if np.any(np.asarray(plant.get_joint(JointIndex(j)).default_damping_vector()) != 0)]
    if damped:
        notes.append(f"Drake applies joint damping on {len(damped)} joints ({', '.join(damped[:4])}"
                     f"{', …' if len(damped) > 4 else ''}): left out, the comparison is of the rigid-body tree")
    dk = DrakePlant(plant, plant.CreateDefaultContext(), instances, layout, warnings, notes)
    unactuated = _armature_without_actuator(model, dk)
    if unactuated:
        raise DrakeRefusedError(f"{os.fspath(path)}: not comparable: Drake's plant drops the armature of joints "
                                "without an actuator (it holds a rotor inertia on a JointActuator only): "
                                + ", ".join(unactuated[:6]) + (" …" if len(unactuated) > 6 else "")
                                + "; nothing was compared with Drake")
    moved = _moved_first_joints(model, dk)
    if moved:
        raise DrakeRefusedError(f"{os.fspath(path)}: not comparable: Drake's parser moved the axis of the first of several "
                           "joints on a body (its parent frame taken without the body's pos and quat; MuJoCo "
                           "places it as featherdyn does): " + "; ".join(moved[:3])
                           + (f"; and {len(moved) - 3} more" if len(moved) > 3 else "")
                           + "; nothing was compared with Drake")
    return dk


def _armature_without_actuator(model: Model, dk: DrakePlant) -> list[str]:
    """featherdyn's joints with an armature that no Drake actuator drives: ``"JOINT (armature A)"``."""
    from pydrake.multibody.tree import JointActuatorIndex

    plant = dk.plant
    driven = {plant.get_joint_actuator(JointActuatorIndex(k)).joint().velocity_start()
              for k in range(plant.num_actuators())}
    armature = np.asarray(model.armature)
    return [f"{name} (armature {float(armature[iv:iv + n].max()):.4g})"
            for name, iv, n, dv in zip(model.joint_names, model.idx_v, model.nvs, dk.layout.v_start, strict=True)
            if np.any(armature[iv:iv + n] != 0) and dv not in driven]


def _axis_line(column: np.ndarray) -> str:
    """A joint's axis line from its Plücker column ``[ω; v_O]`` (world, at the world origin): ``"through p along ω"``."""
    w, v = column[:3], column[3:]
    n2 = float(w @ w)
    if n2 == 0.0:  # a prismatic joint: a direction only
        return f"along {np.round(v, 4).tolist()}"
    return f"through {np.round(np.cross(w, v) / n2, 4).tolist()} along {np.round(w / np.sqrt(n2), 4).tolist()}"


def _moved_first_joints(model: Model, dk: DrakePlant) -> list[str]:
    """The first joints of bodies with several joints (featherdyn's inserted ``BODY#0``) whose axis, at the neutral
    configuration, is another line in Drake's plant than in featherdyn's model: ``"JOINT of BODY: ... (Drake ...)"``."""
    from pydrake.multibody.tree import JacobianWrtVariable

    from ..configuration import neutral

    firsts = [i for i, b in enumerate(model.body_names) if b.endswith("#0") and b in model.inserted_bodies]
    if not firsts:
        return []
    plant, ctx, layout = dk.plant, dk.context, dk.layout
    q = neutral(model)
    plant.SetPositions(ctx, _conv.q_to_drake(model, layout, q))
    frames = _link_frames(model, dk)
    out = []
    for i in firsts:
        owner = model.body_names[i][:-2]
        k = next((k for k, f in enumerate(model.frames) if f.name == owner and k in frames), None)
        if k is None:
            continue
        body = frames[k].body_frame()
        X = plant.CalcRelativeTransform(ctx, plant.world_frame(), body).GetAsMatrix4()
        J = plant.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, body, np.zeros(3), plant.world_frame(),
                                              plant.world_frame())
        col = slice(model.idx_v[i], model.idx_v[i] + model.nvs[i])
        ours = frame_jacobian(model, q, k, WORLD)[:, col]
        theirs = _conv.jacobian_from_drake(model, layout, q, J, X, WORLD)[:, col]
        if not compare(GROUP, "", ours[None], theirs[None], 1e-9).passed:
            out.append(f"joint {model.joint_names[i]!r} of body {owner!r}: featherdyn {_axis_line(ours[:, 0])}, "
                       f"Drake {_axis_line(theirs[:, 0])}")
    return out


def load_sdf_model(path: str | os.PathLike[str], strict: bool = False) -> Model:
    """featherdyn's model of an SDFormat file, through ``featherdyn.readers.sdf`` when this installation has it.

    Raises:
        ModelError: featherdyn cannot load SDFormat here, or its SDF loader refuses the file (its words), with
            "nothing was compared".
    """
    try:  # by name: the SDF loader is another change's (issue 34), absent from installations without it
        _sdf = importlib.import_module("featherdyn.readers.sdf")
    except ImportError:
        raise ModelError(f"{os.fspath(path)}: featherdyn cannot load SDFormat in this installation (no "
                         "featherdyn.readers.sdf); nothing was compared with Drake") from None
    try:
        model: Model = _sdf.load_sdf(path, strict=strict)
    except FeatherdynError as exc:
        raise ModelError(f"{os.fspath(path)}: featherdyn's SDF loader refuses it ({' '.join(str(exc).split())}); "
                         "nothing was compared with Drake") from None
    return model


def _link_frames(model: Model, dk: DrakePlant) -> dict[int, Any]:
    """featherdyn's link and body frames whose name is a Drake body: frame index → Drake body."""
    out = {}
    for k, f in enumerate(model.frames):
        if f.kind in ("link", "body"):
            body = dk.body(f.name)
            if body is not None:
                out[k] = body
    return out


def _moving_mass(dk: DrakePlant) -> float:
    """The mass of the parsed bodies that are not welded to the world."""
    plant = dk.plant
    fixed = {int(b.index()) for b in plant.GetBodiesWeldedTo(plant.world_body())}
    return float(sum(plant.get_body(b).get_mass(dk.context) for inst in dk.instances
                     for b in plant.GetBodyIndices(inst) if int(b) not in fixed))


def _reflected_inertia(model: Model, dk: DrakePlant) -> np.ndarray:
    """Drake's reflected rotor inertia ``ρ² I_rotor`` per featherdyn dof (zero where no actuator drives it)."""
    from pydrake.multibody.tree import JointActuatorIndex

    plant, out = dk.plant, np.zeros(model.nv)
    dof_of = {dv + d: iv + d for iv, n, dv in zip(model.idx_v, model.nvs, dk.layout.v_start, strict=True)
              for d in range(n)}
    for k in range(plant.num_actuators()):
        actuator = plant.get_joint_actuator(JointActuatorIndex(k))
        j = actuator.joint()
        for d in range(j.num_velocities()):
            out[dof_of[j.velocity_start() + d]] += float(actuator.calc_reflected_inertia(dk.context))
    return out


def drake_checks(model: Model, dk: DrakePlant, *, samples: int = 10, seed: int = 0,
                 tol: float = 1e-9) -> list[CheckResult]:
    """featherdyn's ``model`` against Drake's plant of the same file (module docstring), ``samples`` states."""
    from pydrake.multibody.tree import JacobianWrtVariable, MultibodyForces

    plant, ctx, layout = dk.plant, dk.context, dk.layout
    out = [compare(GROUP, "total mass vs Drake body masses (moving bodies)", [model.total_mass], [_moving_mass(dk)],
                   tol),
           compare(GROUP, "armature vs JointActuator reflected inertia", [np.asarray(model.armature)],
                   [_reflected_inertia(model, dk)], tol)]
    frames = _link_frames(model, dk)
    jac_frames = _pick_frames(model, frames)
    rng = np.random.default_rng(seed)
    paired = PairedRows()
    add = paired.add
    fwd: dict[str, list[np.ndarray]] = {}

    forces = MultibodyForces(plant)
    world = plant.world_frame()
    skipped = ""
    for _ in range(samples):
        q = random_configuration(model, rng)
        v, a, tau = rng.normal(size=(3, model.nv))
        qd, vd = _conv.q_to_drake(model, layout, q), _conv.v_to_drake(model, layout, q, v)
        plant.SetPositions(ctx, qd)
        plant.SetVelocities(ctx, vd)
        if frames:
            add(f"frame placements ({len(frames)} bodies) vs CalcRelativeTransform",
                np.stack([frame_placement(model, q, k).homogeneous() for k in frames]),
                np.stack([plant.CalcRelativeTransform(ctx, world, b.body_frame()).GetAsMatrix4()
                          for b in frames.values()]))
        for k in jac_frames:
            X = plant.CalcRelativeTransform(ctx, world, frames[k].body_frame()).GetAsMatrix4()
            J = plant.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, frames[k].body_frame(),
                                                  np.zeros(3), world, world)
            for rname, ref in (("LOCAL", LOCAL), ("WORLD", WORLD), ("LOCAL_WORLD_ALIGNED", LOCAL_WORLD_ALIGNED)):
                add(f"frame_jacobian {model.frames[k].name} {rname} vs CalcJacobianSpatialVelocity",
                    frame_jacobian(model, q, k, ref), _conv.jacobian_from_drake(model, layout, q, J, X, ref))
        M = crba(model, q)
        Md = plant.CalcMassMatrix(ctx)
        add("crba vs CalcMassMatrix", _conv.joint_matrix_to_drake(model, layout, q, M), Md)
        g = generalized_gravity(model, q)
        tau_g = plant.CalcGravityGeneralizedForces(ctx)
        add("generalized_gravity vs −CalcGravityGeneralizedForces",
            _conv.generalized_gravity_to_drake(model, layout, q, g), tau_g)
        bias = plant.CalcBiasTerm(ctx)
        a0 = _conv.a_from_drake(model, layout, qd, vd, np.zeros(model.nv))  # featherdyn's a at Drake's v̇ = 0
        add("rnea − g at Drake's v̇ = 0 vs CalcBiasTerm",
            _conv.tau_to_drake(model, layout, q, nonlinear_effects(model, q, v) - g + M @ a0), bias)
        forces.SetZero()
        forces.mutable_generalized_forces()[:] = tau_g
        vdot = _conv.a_to_drake(model, layout, q, v, a)
        add("rnea vs CalcInverseDynamics (gravity applied)", _conv.tau_to_drake(model, layout, q, rnea(model, q, v, a)),
            plant.CalcInverseDynamics(ctx, vdot, forces))
        if skipped or not model.nv:
            continue
        try:
            ddq = aba(model, q, v, tau)
        except SingularMassMatrixError as exc:  # as with Pinocchio: nothing to solve where M is singular
            skipped = str(exc)
            continue
        vdot_d = np.linalg.solve(Md, _conv.tau_to_drake(model, layout, q, tau) + tau_g - bias)
        for key, x in (("q", q), ("v", v), ("tau", tau), ("M", M), ("ddq", ddq),
                       ("ddq_ref", _conv.a_from_drake(model, layout, qd, vd, vdot_d))):
            fwd.setdefault(key, []).append(x)
    out += paired.compare(GROUP, tol)
    if skipped:
        out.append(CheckResult(GROUP, FORWARD, float("nan"), 0.0, 0, tol, True, f"skipped: {skipped}"))
    elif model.nv:
        F = {k: np.stack(x) for k, x in fwd.items()}
        out.append(forward_dynamics_result(GROUP, FORWARD, model, F["q"], F["v"], F["tau"], F["ddq"], F["ddq_ref"],
                                           F["M"], tol))
    return out
