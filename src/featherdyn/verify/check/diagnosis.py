"""The diagnosis in words: what a reading that explains the values means, or where they differ most."""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from ...joints import FreeFlyerJoint
from ..report import CheckResult
from .readings import QUANTITIES, Checker, Hypothesis

__all__ = ["explain", "largest_discrepancy"]


def _fmt_vec(g: Iterable[float]) -> str:
    return "(" + ", ".join(f"{x:+g}" if x else "0" for x in g) + ")"


def _names(names: list[str], limit: int = 6) -> str:
    shown = ", ".join(repr(n) for n in names[:limit])
    return shown + (f", … ({len(names)} joints)" if len(names) > limit else "")


def explain(ch: Checker, h: Hypothesis) -> tuple[str, dict[str, object]]:
    """What the values are under reading ``h``, in words with the conversion to apply, and its parameters."""
    conv = ch.convention
    model = ch.model
    parts: list[str] = []
    details: dict[str, object] = {}
    if h.cos_sin:
        joints = [b.name for b in ch.blocks if b.angle]
        kinds = " and ".join(sorted({"planar" if b.kind == "planar" else "continuous" for b in ch.blocks if b.angle}))
        if conv == "featherdyn":
            parts.append(f"{kinds} joints {_names(joints)} are given as (cos θ, sin θ), Pinocchio's layout "
                         f"(q has length {ch.declared_nq + ch.flip_nq}), where the featherdyn convention has the "
                         f"angle θ (nq={ch.declared_nq}); fd.conventions.continuous_q_from_pinocchio converts")
        else:
            parts.append(f"{kinds} joints {_names(joints)} are given as the angle θ (q has length "
                         f"{ch.declared_nq + ch.flip_nq}), where the pinocchio convention has (cos θ, sin θ) "
                         f"(nq={ch.declared_nq}); fd.conventions.continuous_q_to_pinocchio converts")
        details["continuous_joints"] = joints
    if h.order is not None:
        order = [model.joint_names[i] for i in ch.orders[h.order]]
        declared = [b.name for b in ch.blocks]
        what = {"pinocchio": "Pinocchio's joint order (pin.buildModelFromUrdf)",
                "featherdyn": "featherdyn's joint order (depth-first, URDF order)",
                "alphabetical": "alphabetical order of the joint names",
                "reverse": "reversed order"}[h.order]
        parts.append(f"the joints are in {what}: {_names(order)} instead of the {conv} convention's "
                     f"{_names(declared)}; q, v, a, tau, ddq and the rows and columns of M and of the derivative "
                     "matrices are permuted alike")
        details["joint_order"] = h.order
        details["joints"] = order
    if h.swap6:
        given, wanted = ("linear first [v; ω] (Pinocchio's order)", "angular first [ω; v]") if conv == "featherdyn" \
            else ("angular first [ω; v] (featherdyn's order)", "linear first [v; ω]")
        parts.append("the free-flyer block of v, a, tau and ddq (and of the rows and columns of M and of the "
                     f"derivative matrices) has its 6D halves swapped: the values are {given}, the {conv} convention is {wanted}; "
                     "fd.conventions.freeflyer_v_from_pinocchio / freeflyer_v_to_pinocchio convert")
    if h.quat_wxyz is not None:
        joints = [b.name for b in ch.blocks if b.quat_at is not None and h.quat_wxyz in ("all", b.kind)]
        details["quaternion_joints"] = joints
        parts.append(f"the quaternions of {_names(joints)} are in (w, x, y, z) order (Eigen's constructor, MuJoCo, "
                     "Drake), where featherdyn and Pinocchio store (x, y, z, w); fd.conventions.quat_wxyz_to_xyzw "
                     "converts")
    if h.world:
        parts.append("the free-flyer velocity is world-aligned (ω in world axes, ṗ the velocity of the base origin in "
                     "the world: Pinocchio's LOCAL_WORLD_ALIGNED) instead of in the base frame (LOCAL); with R the "
                     "base orientation: v_base = [Rᵀω_w; Rᵀṗ], a_base = [Rᵀω̇_w; Rᵀp̈ − ω_b × v_b], "
                     "base wrench [Rᵀn_w; Rᵀf_w], M_base = T M Tᵀ with T = diag(Rᵀ, Rᵀ)")
    if h.classical:
        parts.append("the free-flyer acceleration is the classical acceleration of the base origin (Rᵀp̈, base "
                     "coordinates) instead of the spatial acceleration: a_spatial = a_classical − [0; ω × v]; "
                     "fd.conventions.classical_to_spatial_acceleration converts")
    if h.gravity is not None:
        g_model = np.asarray(model.gravity, dtype=float)
        g = np.array(h.gravity)
        if not np.any(g):
            how = "without gravity (g = 0)"
        elif np.allclose(g, -g_model):
            how = f"with gravity {_fmt_vec(g)} m/s², the sign flipped"
        else:
            how = f"with gravity {_fmt_vec(g)} m/s² (|g| = {np.linalg.norm(g):g}" + \
                  (", pointing the other way" if float(g @ g_model) < 0 else "") + ")"
        parts.append(f"the values were computed {how}, where the model has {_fmt_vec(g_model)} m/s²; "
                     "pass the same gravity to both (dataclasses.replace(model, gravity=...))")
        details["gravity"] = list(h.gravity)
    if h.triangle is not None:
        M = ch.given.arrays["M"]
        other = np.tril(M, -1) if h.triangle == "upper" else np.triu(M, 1)
        state = "is zero" if not np.any(other) else "is not its transpose"
        sym = "triu(M) + triu(M, 1)ᵀ" if h.triangle == "upper" else "tril(M) + tril(M, −1)ᵀ"
        opposite = "lower" if h.triangle == "upper" else "upper"
        parts.append(f"M holds only its {h.triangle} triangle (the strict {opposite} triangle {state}, as an "
                     f"in-place CRBA leaves it); the mass matrix is {sym}")
        details["triangle"] = h.triangle
    return "\n".join(p[0].upper() + p[1:] + "." for p in parts), details


def largest_discrepancy(ch: Checker, h: Hypothesis, results: list[CheckResult]) -> tuple[str, dict[str, object]]:
    """Where the values differ most from featherdyn (joint, state, index) — for the no-suspect message."""
    failing = [r for r in results if not r.passed]
    worst = max(failing, key=lambda r: (r.max_rel if math.isfinite(r.max_rel) else math.inf))
    quantity = next(k for k, v in QUANTITIES.items() if v == worst.quantity)
    if not math.isfinite(worst.max_rel):
        return (f"{quantity} cannot be compared: {worst.note}",
                {"quantity": quantity, "reason": worst.note})
    expected, given = ch.expected_and_given(h, quantity)
    n = given.shape[0]
    err = np.abs(given - expected).reshape(n, -1)
    scale = np.maximum(np.abs(expected).reshape(n, -1).max(axis=1), 1.0)
    rel = err / scale[:, None]
    k_, flat_ = np.unravel_index(int(np.argmax(rel)), rel.shape)
    k, flat = int(k_), int(flat_)
    model = ch.model
    body_of_v = np.repeat(np.arange(model.nbodies), model.nvs)
    to_user = ch.pinocchio_map().v_perm if ch.convention == "pinocchio" else np.arange(model.nv)

    def joint(i: int) -> str:
        b = int(body_of_v[i])
        name, c = model.joint_names[b], i - model.idx_v[b]
        if isinstance(model.joints[b], FreeFlyerJoint):  # featherdyn's order: [ω; v] for motions, [n; f] for forces
            labels = ("ω", "v") if quantity == "M" else ("n", "f")
            return f"{name!r} ({labels[c // 3]}_{'xyz'[c % 3]} of the free-flyer)"
        if model.nvs[b] > 1:
            return f"{name!r} (component {c} of its {model.nvs[b]})"
        return repr(name)

    state = f" at state {k}" if ch.given.batched else ""
    gv, ev = float(given.reshape(n, -1)[k, flat]), float(expected.reshape(n, -1)[k, flat])
    if quantity == "M":
        i, j = divmod(flat, model.nv)
        ui, uj = int(to_user[i]), int(to_user[j])
        where = f"M[{ui}, {uj}], joints {joint(i)} and {joint(j)}"
        info: dict[str, object] = {"index": [ui, uj], "joints": [model.joint_names[body_of_v[i]],
                                                              model.joint_names[body_of_v[j]]]}
    else:
        ui = int(to_user[flat])
        where = f"tau[{ui}], joint {joint(flat)}" if quantity == "tau" else \
            f"the joint forces of ddq (fd.rnea(q, v, ddq) vs tau)[{ui}], joint {joint(flat)}"
        info = {"index": ui, "joint": model.joint_names[body_of_v[flat]]}
    info.update({"quantity": quantity, "state": k, "given": gv, "featherdyn": ev, "relative_error": float(rel[k, flat])})
    text = (f"the largest discrepancy is in {where}{state}: given {gv:.6g}, featherdyn {ev:.6g} "
            f"(relative error {rel[k, flat]:.2e})")
    return text, info

