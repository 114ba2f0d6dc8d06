"""featherdyn.jax and featherdyn.torch against adam and jaxsim: ``python benchmarks/bench_framework_peers.py [N ...]``.

The issue's target: at least 10× the throughput of adam's JAX and PyTorch backends and of jaxsim on the same
robots and batch, for RNEA, ABA, CRBA and their gradients. The peers are a benchmark's only (not featherdyn's
dependencies): ``pip install adam-robotics jaxsim`` (adam's ``[jax]`` extra pins jax ≤ 0.6.0; adam runs without
it). jaxsim reads a URDF through rod, which calls Gazebo's ``gz sdf -p``; the script says so if it is missing.

For each robot (panda fixed base, solo12 and talos_full_v2 floating; the same URDF file for every library, the
one ``fd.load_robot`` reads) and batch N (default 1 000), interleaved medians in one process
(``bench_core.median_pair``) of, in states per second:

* JAX: ``jax.jit`` of ``fj.rnea(model, Q, V, A)`` (the batch as leading axes: one FFI call, the core's batch)
  against ``jax.jit`` of adam's functions on the batch (its own batch path, leading axes: on solo12, N = 1 000,
  as fast as ``jax.vmap`` for RNEA and 1.7× faster for CRBA) and ``jax.jit(jax.vmap(...))`` of jaxsim's
  one-state kernels; the same for ``aba`` and ``crba``; and the gradients
  ``jax.jit(jax.grad(lambda Q, V, A: Σ w · f(Q, V, A), argnums=(0, 1, 2)))`` (``crba``: ``Σ W ∘ M(Q)`` with
  respect to Q) on both sides.
* PyTorch: ``ft.rnea(model, Q, V, A)`` & co. against adam's batched PyTorch class on the same tensors;
  gradients ``torch.autograd.grad(Σ w · f, (Q, V, A))``.

Every peer function here takes featherdyn's layout (q = ``[p, quat xyzw, joints]``, v = ``[ω; v]`` of the base
in its own frame, then the joints in featherdyn's order) and returns featherdyn's layout, converting inside the
timed (and differentiated) function: the quaternion to the peer's rotation (adam's 4×4 ``base_transform``,
jaxsim's wxyz quaternion), the 6D halves (the peers are linear-first), the joints by name. adam runs in its
body-fixed representation and jaxsim's kernels (``jaxsim.rbda``) get inertial-fixed velocities converted with
jaxsim's own adjoints, which is featherdyn's (and Pinocchio's) free-flyer convention. Gradients with respect to
q are in q's coordinates on both sides (the peers differentiate their quaternion-to-rotation formula,
featherdyn's rule gives the gradient tangent to the unit quaternions); the agreement check compares the
quaternion part after removing its radial component.

Conventions the peers impose:

* adam has no fixed base: its models always carry a 6-DoF base. Its panda rows use panda on a floating base on
  both sides (the same problem), with the two finger joints fixed in the URDF both read (adam 0.5.0 cannot build
  a prismatic joint: :func:`adam_robot`); jaxsim's panda is fixed, fingers included (the URDF handed to it gets a
  ``world`` link and a fixed joint, which is how rod/jaxsim read a fixed base).
* adam has no RNEA with accelerations: its inverse dynamics is ``M(q) ν̇ + h(q, ν)`` (``mass_matrix`` +
  ``bias_force``, its reduced RNEA), which is what its users write.
* ABA with a floating base: adam's and jaxsim's take joint torques only (no base wrench), so the floating
  robots' τ has zeros in its 6 base entries (for featherdyn too).

Before timing, every pair is checked on the timed batch itself: values and gradients equal featherdyn's to
``TOL`` (1e-8) relative to max(1, the largest entry); the script prints each difference and stops before timing
on a disagreement. The first call of each jitted function (its compilation) is timed apart and printed.

jaxsim reads URDF through rod, which needs Gazebo's ``gz sdf -p`` (and rod checks that it writes SDFormat ≥ 1.10;
``ROD_SKIP_SDFORMAT_CHECK=1`` skips that check for an older sdformat): results-framework-peers-2026-11-29.md says
what stood in for it here.
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import os
import platform
import re
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_core import median_pair

ROBOTS = [("panda", False), ("solo12", True), ("talos_full_v2", True)]
TOL = 1e-8


class NotTimedError(Exception):
    """A (robot, peer) pair that is not timed: the peer cannot read the robot, or disagrees with featherdyn."""


def require_peers() -> None:
    """Exit with a message (not a traceback) when adam or jaxsim is not installed."""
    missing = [pkg for mod, pkg in (("adam", "adam-robotics"), ("jaxsim", "jaxsim"), ("torch", "torch"),
                                    ("jax", "jax")) if importlib.util.find_spec(mod) is None]
    if missing:
        sys.exit(f"bench_framework_peers: not installed: {', '.join(missing)}. This benchmark compares featherdyn "
                 "with adam and jaxsim, which are not featherdyn's dependencies: pip install adam-robotics jaxsim "
                 "(benchmarks/results-framework-peers-2026-11-29.md lists the versions used)")


# --- layouts ------------------------------------------------------------------------------------------------------


class Layout:
    """featherdyn ↔ a peer's vectors: ``x_fd = x_peer[perm]``, ``x_peer = x_fd[inv]``.

    A floating robot's peer vector is ``[v_lin; ω; joints in the peer's order]`` (6 + n), featherdyn's
    ``[ω; v_lin; joints in featherdyn's order]``; a fixed one's is the joints alone.
    """

    def __init__(self, model: Any, peer_joints: list[str], floating: bool) -> None:
        names = list(model.joint_names)[1:] if floating else list(model.joint_names)
        missing = sorted(set(names) - set(peer_joints))
        if missing:
            raise NotTimedError(f"{model.name}: joints {missing} are not the peer's joints")
        base = [3, 4, 5, 0, 1, 2] if floating else []
        off = 6 if floating else 0
        self.perm = np.array(base + [off + peer_joints.index(n) for n in names])
        self.inv = np.argsort(self.perm)
        self.floating = floating
        self.nj = len(names)


def quat_xyzw_to_rotation(quat: Any, xp: Any) -> Any:
    """``R`` `(..., 3, 3)` of unit quaternions `(..., 4)` ``(x, y, z, w)`` (array namespace ``xp``: jnp or torch)."""
    x, y, z, w = quat[..., 0], quat[..., 1], quat[..., 2], quat[..., 3]
    rows = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return xp.stack([xp.stack(r, -1) for r in rows], -2)


def homogeneous(p: Any, quat: Any, xp: Any) -> Any:
    """``[[R, p], [0, 1]]`` `(..., 4, 4)`."""
    R = quat_xyzw_to_rotation(quat, xp)
    top = xp.concatenate([R, p[..., :, None]], -1)
    last = xp.zeros_like(top[..., :1, :])
    one = xp.ones_like(p[..., :1])
    last = xp.concatenate([last[..., :3], one[..., None, :]], -1)
    return xp.concatenate([top, last], -2)


# --- adam ---------------------------------------------------------------------------------------------------------


def patch_adam_jax_device() -> None:
    """adam's JAX arrays are made with ``device=`` its reference array's device; on traced values (``jax.jit``,
    ``jax.vmap``) jax 0.10 refuses that (``'SingleDeviceSharding' object has no attribute 'spec'``; adam's ``[jax]``
    extra pins jax ≤ 0.6.0).
    Its JAX class is given a spec without a device (JAX's default device: the CPU here, the same arrays)."""
    import dataclasses

    import adam.jax.computations as adam_jax

    original = adam_jax.spec_from_reference
    if getattr(original, "patched_here", False):
        return

    def spec_from_reference(ref: Any) -> Any:
        return dataclasses.replace(original(ref), device=None)

    spec_from_reference.patched_here = True  # type: ignore[attr-defined]
    adam_jax.spec_from_reference = spec_from_reference


_TMP = tempfile.TemporaryDirectory(prefix="bench_framework_peers_")


def adam_robot(name: str) -> tuple[Any, Path, bool]:
    """The floating-base model adam and featherdyn share, its URDF, and whether prismatic joints were fixed.

    adam 0.5.0 cannot build a prismatic joint (``StdJoint.motion_subspace`` stacks the axis' three scalars with
    ``zeros(3)``), nor batch one (``H_prismatic_joint``: ``xyz + q * axis``, a batch of q against a 3-vector): a
    URDF's prismatic joints (panda's two fingers) are made fixed, for adam and featherdyn both.
    """
    import featherdyn as fd
    from featherdyn.robots import robot_path

    path = robot_path(name)
    text = path.read_text()
    fixed = re.sub(r'(<joint\s+name="[^"]+"\s+type=)"prismatic"', r'\1"fixed"', text)
    if fixed != text:
        path = Path(_TMP.name) / f"{name}_prismatic_fixed.urdf"
        path.write_text(fixed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fd.load_robot(str(path), floating_base=True), path, fixed != text


def adam_functions(kd: Any, lay: Layout, xp: Any) -> dict[str, Callable[..., Any]]:
    """adam's rnea / aba / crba in featherdyn's layout (batched by leading axes; ``xp`` is jnp or torch)."""
    perm, inv = xp.asarray(lay.perm), xp.asarray(lay.inv)

    def split(q: Any) -> tuple[Any, Any]:
        return homogeneous(q[..., :3], q[..., 3:7], xp), q[..., 7:]

    def rnea(q: Any, v: Any, a: Any) -> Any:
        H, s = split(q)
        nu, nud = v[..., inv], a[..., inv]
        M = kd.mass_matrix(H, s)
        h = kd.bias_force(H, s, nu[..., :6], nu[..., 6:])
        return ((M @ nud[..., None])[..., 0] + h)[..., perm]

    def aba(q: Any, v: Any, tau: Any) -> Any:
        H, s = split(q)
        nu, t = v[..., inv], tau[..., inv]
        return kd.aba(H, s, nu[..., :6], nu[..., 6:], t[..., 6:])[..., perm]

    def crba(q: Any) -> Any:
        H, s = split(q)
        return kd.mass_matrix(H, s)[..., perm, :][..., :, perm]

    return {"rnea": rnea, "aba": aba, "crba": crba}


# --- jaxsim -------------------------------------------------------------------------------------------------------


def jaxsim_model(path: Path, floating: bool, gravity: Any) -> Any:
    """jaxsim's model of the URDF at ``path`` (a fixed base: a ``world`` link and a fixed joint added to the text)
    with featherdyn's gravity ``(0, 0, -g)`` (jaxsim takes ``g``)."""
    import jaxsim.api as js

    if gravity[0] != 0 or gravity[1] != 0:
        raise NotTimedError(f"jaxsim's gravity is along -z; featherdyn's is {list(gravity)}")
    text = _without_empty_inertials(path.read_text())
    if not floating:
        root = _urdf_root_link(text)
        m = re.search(r"<robot\b[^>]*>", text)
        assert m is not None
        text = (text[: m.end()] + '\n  <link name="world"/>\n  <joint name="world_to_root" type="fixed">'
                f'<parent link="world"/><child link="{root}"/></joint>' + text[m.end():])
    try:
        model = js.model.JaxSimModel.build_from_model_description(text, is_urdf=True,
                                                                  gravity=-float(gravity[2]))
    except (FileNotFoundError, RuntimeError) as exc:
        raise NotTimedError(f"jaxsim could not read {path.name}: {exc}. rod (jaxsim's reader) turns a URDF into "
                       "SDFormat with Gazebo's `gz sdf -p`; put a `gz` with its sdf command on PATH "
                       "(results-framework-peers-2026-11-29.md says how it was done here)") from exc
    if model.floating_base() != floating:
        raise NotTimedError(f"jaxsim read {path.name} with floating_base={model.floating_base()}")
    return model


def _without_empty_inertials(text: str) -> str:
    """The URDF without its ``<inertial>`` elements of zero mass and zero inertia (talos' camera frames): the same
    dynamics, and sdformat 12 lumps such a link into its parent with a non-finite pose (0/0) and refuses the file."""

    def empty(m: re.Match[str]) -> str:
        numbers = re.findall(r'(?:value|i[xyz]{2})="([^"]*)"', m.group(0))
        return "" if numbers and all(float(x) == 0.0 for x in numbers) else m.group(0)

    return re.sub(r"<inertial>.*?</inertial>", empty, text, flags=re.DOTALL)


def _urdf_root_link(text: str) -> str:
    links = re.findall(r'<link\s+name="([^"]+)"', text)
    children = set(re.findall(r'<child\s+link="([^"]+)"', text))
    roots = [n for n in links if n not in children]
    if len(roots) != 1:
        raise NotTimedError(f"the URDF has roots {roots}")
    return roots[0]


def jaxsim_functions(model: Any, lay: Layout) -> dict[str, Callable[..., Any]]:
    """jaxsim's RNEA / ABA / CRBA kernels (``jaxsim.rbda``) on one state in featherdyn's layout (vmap them)."""
    import jax.numpy as jnp
    import jaxsim.rbda as rbda
    from jaxsim.math import Adjoint, Transform

    perm, inv, nj, floating = lay.perm, lay.inv, lay.nj, lay.floating

    def base(q: Any) -> tuple[Any, Any, Any, Any]:
        if floating:
            p, quat = q[:3], q[jnp.array([6, 3, 4, 5])]
            s = q[7:][inv[6:] - 6]
        else:
            p, quat = jnp.zeros(3, q.dtype), jnp.array([1.0, 0, 0, 0], q.dtype)
            s = q[inv]
        W_H_B = Transform.from_quaternion_and_translation(translation=p, quaternion=quat)
        return p, quat, s, W_H_B

    def to_inertial(x: Any, W_H_B: Any) -> tuple[Any, Any]:
        """A body-frame 6D motion (featherdyn's [ω; v] first 6 entries) → inertial-fixed, and the joints' part."""
        if not floating:
            return jnp.zeros(6, x.dtype), x[inv]
        xp = x[inv]
        return Adjoint.from_transform(W_H_B) @ xp[:6], xp[6:]

    def rnea(q: Any, v: Any, a: Any) -> Any:
        p, quat, s, W_H_B = base(q)
        W_v, sd = to_inertial(v, W_H_B)
        W_a, sdd = to_inertial(a, W_H_B)
        jt = model.kin_dyn_parameters.joint_transforms(joint_positions=s, base_transform=W_H_B)
        W_f, tau = rbda.rnea(model, base_position=p, base_quaternion=quat, joint_positions=s,
                             base_linear_velocity=W_v[:3], base_angular_velocity=W_v[3:], joint_velocities=sd,
                             base_linear_acceleration=W_a[:3], base_angular_acceleration=W_a[3:],
                             joint_accelerations=sdd, joint_transforms=jt, standard_gravity=model.gravity)
        if not floating:
            return tau[perm]
        B_f = Adjoint.from_transform(W_H_B).T @ W_f  # a wrench: B_f = (W_X_B)ᵀ W_f
        return jnp.concatenate([B_f, tau])[perm]

    def aba(q: Any, v: Any, tau: Any) -> Any:
        p, quat, s, W_H_B = base(q)
        W_v, sd = to_inertial(v, W_H_B)
        t = tau[inv][6:] if floating else tau[inv]
        jt = model.kin_dyn_parameters.joint_transforms(joint_positions=s, base_transform=W_H_B)
        W_vd, sdd = rbda.aba(model, base_position=p, base_quaternion=quat, joint_positions=s,
                             base_linear_velocity=W_v[:3], base_angular_velocity=W_v[3:], joint_velocities=sd,
                             joint_transforms=jt, joint_forces=t, standard_gravity=model.gravity)
        if not floating:
            return sdd[perm]
        B_vd = Adjoint.from_transform(W_H_B, inverse=True) @ W_vd  # body representation: B_X_W W_v̇ (v×v = 0)
        return jnp.concatenate([B_vd, sdd])[perm]

    def crba(q: Any) -> Any:
        _, _, s, _ = base(q)
        M = rbda.crba(model, joint_positions=s)  # (6 + n)²: body-fixed base block
        if not floating:
            M = M[6:, 6:]
        return M[perm][:, perm]

    assert nj == model.dofs()
    return {"rnea": rnea, "aba": aba, "crba": crba}


# --- states, checks, timing ---------------------------------------------------------------------------------------


def states(model: Any, n: int, seed: int = 0) -> dict[str, np.ndarray]:
    """q, v, a, τ `(n, ·)` (τ's free-flyer entries zero: the peers' ABA takes joint torques only)."""
    import featherdyn as fd

    rng = np.random.default_rng(seed)
    q = np.asarray(fd.random_configuration(model, rng, size=n), dtype=np.float64).reshape(n, model.nq)
    v, a, tau = (rng.normal(size=(n, model.nv)) for _ in range(3))
    if model.joints[0].kind == "free_flyer":
        tau[:, :6] = 0.0
    return {"q": q, "v": v, "a": a, "tau": tau}


def rel_diff(x: Any, y: Any) -> tuple[float, float]:
    """(max |x − y|, that over max(1, max |y|))."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    d = float(np.max(np.abs(x - y))) if x.size else 0.0
    return d, d / max(1.0, float(np.max(np.abs(y))) if y.size else 1.0)


def tangent_q(g: np.ndarray, q: np.ndarray, floating: bool) -> np.ndarray:
    """A coordinate gradient with respect to q with its free-flyer quaternion's radial component removed."""
    g = np.array(g, dtype=np.float64, copy=True)
    if floating:
        u = q[..., 3:7] / np.linalg.norm(q[..., 3:7], axis=-1, keepdims=True)
        g[..., 3:7] -= np.sum(g[..., 3:7] * u, axis=-1, keepdims=True) * u
    return g


ARGS = {"rnea": ("q", "v", "a"), "aba": ("q", "v", "tau"), "crba": ("q",)}


class Report:
    """Collects agreement lines and timing rows."""

    def __init__(self) -> None:
        self.checks: list[tuple[str, float, float, float]] = []
        self.rows: list[tuple[str, str, str, int, float, float, float, float]] = []

    def check(self, label: str, got: Any, ref: Any, tol: float) -> None:
        d, r = rel_diff(got, ref)
        self.checks.append((label, d, r, tol))
        print(f"  check {label:<60} max |Δ| {d:9.2e}  relative {r:9.2e}  (tol {tol:.0e})", flush=True)
        if not r <= tol:
            raise NotTimedError(f"{label}: the peer disagrees with featherdyn (relative {r:.2e} > {tol:.0e})")


def weights(model: Any, quantity: str, rng: np.random.Generator) -> np.ndarray:
    """The fixed weights of the scalar that is differentiated: `(nv,)` or `(nv, nv)` (broadcast over the batch)."""
    return rng.normal(size=(model.nv, model.nv) if quantity == "crba" else (model.nv,))


def first_call(f: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


# --- JAX ----------------------------------------------------------------------------------------------------------


def jax_section(rep: Report, name: str, floating: bool, peer: str, ns: list[int], budget: float,
                quantities: list[str]) -> None:
    import jax
    import jax.numpy as jnp

    import featherdyn as fd
    import featherdyn.jax as fj
    from featherdyn.errors import FeatherdynError
    from featherdyn.robots import robot_path

    use_floating = True if peer == "adam.jax" else floating
    if peer == "adam.jax":
        model, path, fingers_fixed = adam_robot(name)
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fd.load_robot(name, floating_base=floating)
        path, fingers_fixed = robot_path(name), False
    if peer == "adam.jax":
        from adam.core.constants import Representations
        from adam.jax import KinDynComputations

        kd = KinDynComputations(str(path), list(model.joint_names)[1:], dtype=jnp.float64,
                                gravity=jnp.array([*model.gravity, 0.0, 0.0, 0.0]))
        kd.set_frame_velocity_representation(Representations.BODY_FIXED_REPRESENTATION)
        lay = Layout(model, list(model.joint_names)[1:], True)
        peer_fns = adam_functions(kd, lay, jnp)  # adam's own batch (leading axes), not vmap: see the docstring
    else:
        jsm = jaxsim_model(path, floating, model.gravity)
        lay = Layout(model, list(jsm.joint_names()), floating)
        peer_fns = {k: jax.vmap(f) for k, f in jaxsim_functions(jsm, lay).items()}
    tol = TOL
    fd_fns = {"rnea": lambda q, v, a: fj.rnea(model, q, v, a), "aba": lambda q, v, t: fj.aba(model, q, v, t),
              "crba": lambda q: fj.crba(model, q)}
    base = ("floating" if use_floating else "fixed") + (", prismatic fixed" if fingers_fixed else "")
    rng = np.random.default_rng(1)
    for quantity in quantities:
        argn = ARGS[quantity]
        w = jnp.asarray(weights(model, quantity, rng))
        nargs = len(argn)

        def scalar_of(f: Callable[..., Any], w: Any = w) -> Callable[..., Any]:
            return lambda *args: jnp.sum(w * f(*args))

        val = {"fd": jax.jit(fd_fns[quantity]), "peer": jax.jit(peer_fns[quantity])}
        grd = {"fd": jax.jit(jax.grad(scalar_of(fd_fns[quantity]), argnums=tuple(range(nargs)))),
               "peer": jax.jit(jax.grad(scalar_of(peer_fns[quantity]), argnums=tuple(range(nargs))))}
        for n in ns:
            s = states(model, n)
            xs = [jnp.asarray(s[k]) for k in argn]
            label = f"{name} {base} {quantity} {peer} N={n}"
            out: dict[str, Any] = {}
            times = {}
            for side in ("fd", "peer"):  # the first call compiles; its result is checked
                t0 = time.perf_counter()
                out[side] = jax.block_until_ready(val[side](*xs))
                times[side] = time.perf_counter() - t0
            rep.check(f"{label} value", out["peer"], out["fd"], tol)
            cases: list[tuple[str, dict[str, Any], dict[str, float]]] = [("value", val, times)]
            try:
                t0 = time.perf_counter()
                g_fd = jax.block_until_ready(grd["fd"](*xs))
                gtimes = {"fd": time.perf_counter() - t0}
            except FeatherdynError as exc:
                print(f"  {label}: featherdyn.jax has no gradient ({type(exc).__name__}: {str(exc)[:100]}); "
                      "gradient: pending", flush=True)
                cases.append(("grad", {}, {}))
            else:
                t0 = time.perf_counter()
                g_peer = jax.block_until_ready(grd["peer"](*xs))
                gtimes["peer"] = time.perf_counter() - t0
                check_grads(rep, label, argn, g_peer, g_fd, s["q"], use_floating, tol)
                cases.append(("grad", grd, gtimes))
            for kind, fns, first in cases:
                if not fns:  # featherdyn's gradient is pending
                    rep.rows.append((f"{name} ({base})", f"{quantity} {kind}", peer, n, *[float("nan")] * 4))
                    continue
                t_fd, t_peer = median_pair(*(calling(fns[side], xs) for side in ("fd", "peer")), 5, budget)
                rep.rows.append((f"{name} ({base})", f"{quantity} {kind}", peer, n, n / t_fd, n / t_peer,
                                 first["fd"], first["peer"]))
                print(f"  {name:<14}{quantity} {kind:<6}{peer:<9}N={n:<6} fd {n / t_fd:12.0f}/s  peer "
                      f"{n / t_peer:12.0f}/s  ratio {t_peer / t_fd:8.1f}   (first call {first['fd']:.2f} s / "
                      f"{first['peer']:.2f} s)", flush=True)


def calling(f: Callable[..., Any], xs: list[Any]) -> Callable[[], Any]:
    """``f(*xs)`` waited for (JAX dispatches asynchronously)."""
    import jax

    return lambda: jax.block_until_ready(f(*xs))


def check_grads(rep: Report, label: str, argn: tuple[str, ...], g_peer: Any, g_fd: Any, q: np.ndarray,
                floating: bool, tol: float) -> None:
    """Check each input's gradient: q's with the quaternion's radial part removed, a floating robot's τ on the
    joints only (the peers' ABA has no base wrench input: its gradient there is zero)."""
    for k, gp, gf in zip(argn, g_peer, g_fd, strict=True):
        gp, gf = np.asarray(gp), np.asarray(gf)
        if k == "q":
            gp, gf = tangent_q(gp, q, floating), tangent_q(gf, q, floating)
        if k == "tau" and floating:
            gp, gf = gp[..., 6:], gf[..., 6:]
        rep.check(f"{label} grad wrt {k}", gp, gf, tol)


# --- PyTorch ------------------------------------------------------------------------------------------------------


def torch_section(rep: Report, name: str, ns: list[int], budget: float, quantities: list[str]) -> None:
    import torch
    from adam.core.constants import Representations
    from adam.pytorch import KinDynComputationsBatch

    import featherdyn.torch as ft

    model, path, fingers_fixed = adam_robot(name)
    base = "floating" + (", prismatic fixed" if fingers_fixed else "")
    kd = KinDynComputationsBatch(str(path), list(model.joint_names)[1:], device=torch.device("cpu"),
                                 dtype=torch.float64,
                                 gravity=torch.tensor([*model.gravity, 0.0, 0.0, 0.0], dtype=torch.float64))
    kd.set_frame_velocity_representation(Representations.BODY_FIXED_REPRESENTATION)
    lay = Layout(model, list(model.joint_names)[1:], True)
    peer_fns = adam_functions(kd, lay, torch)
    fd_fns = {"rnea": lambda q, v, a: ft.rnea(model, q, v, a), "aba": lambda q, v, t: ft.aba(model, q, v, t),
              "crba": lambda q: ft.crba(model, q)}
    rng = np.random.default_rng(1)
    peer = "adam.pytorch"
    for quantity in quantities:
        argn = ARGS[quantity]
        w = torch.from_numpy(weights(model, quantity, rng))

        def grad_of(f: Callable[..., Any], xs: list[Any], w: Any = w) -> tuple[Any, ...]:
            return torch.autograd.grad(torch.sum(w * f(*xs)), xs)

        for n in ns:
            s = states(model, n)
            xv = [torch.from_numpy(s[k]) for k in argn]
            xg = [torch.from_numpy(s[k].copy()).requires_grad_() for k in argn]
            label = f"{name} {base} {quantity} {peer} N={n}"
            with torch.no_grad():
                rep.check(f"{label} value", peer_fns[quantity](*xv), fd_fns[quantity](*xv), TOL)
            check_grads(rep, label, argn, [g.numpy() for g in grad_of(peer_fns[quantity], xg)],
                        [g.numpy() for g in grad_of(fd_fns[quantity], xg)], s["q"], True, TOL)

            def value(f: Callable[..., Any], xv: list[Any] = xv) -> Callable[[], Any]:
                def run() -> Any:
                    with torch.no_grad():
                        return f(*xv)
                return run

            def grad(f: Callable[..., Any], xg: list[Any] = xg) -> Callable[[], Any]:
                return lambda: grad_of(f, xg)

            f_fd, f_peer = fd_fns[quantity], peer_fns[quantity]
            cases = [("value", value(f_fd), value(f_peer)), ("grad", grad(f_fd), grad(f_peer))]
            for kind, f_fd, f_peer in cases:
                t_fd, t_peer = median_pair(f_fd, f_peer, 5, budget)
                rep.rows.append((f"{name} ({base})", f"{quantity} {kind}", peer, n, n / t_fd, n / t_peer,
                                 float("nan"), float("nan")))
                print(f"  {name:<14}{quantity} {kind:<6}{peer:<13}N={n:<6} fd {n / t_fd:12.0f}/s  peer "
                      f"{n / t_peer:12.0f}/s  ratio {t_peer / t_fd:8.1f}", flush=True)


# --- main ---------------------------------------------------------------------------------------------------------


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", nargs="*", type=int, default=[1000], help="batch sizes (default 1000)")
    parser.add_argument("--robots", default=",".join(r for r, _ in ROBOTS))
    parser.add_argument("--peers", default="adam.jax,jaxsim,adam.pytorch")
    parser.add_argument("--quantities", default="rnea,aba,crba")
    parser.add_argument("--budget", type=float, default=0.5, help="seconds per interleaved sample (default 0.5)")
    args = parser.parse_args(argv[1:])
    require_peers()
    import adam
    import jax
    import jaxsim
    import torch

    import featherdyn as fd
    import featherdyn.jax  # jax_enable_x64 before the peers build their arrays

    for lib in ("jaxsim", "rod"):
        logging.getLogger(lib).setLevel(logging.ERROR)
    print(f"python {platform.python_version()}, jax {jax.__version__}, torch {torch.__version__}, adam "
          f"{_version('adam-robotics', adam)}, jaxsim {jaxsim.__version__}, featherdyn threads "
          f"{fd.get_num_threads()}, torch threads {torch.get_num_threads()}, load {os.getloadavg()[0]:.2f}",
          flush=True)
    patch_adam_jax_device()
    rep = Report()
    not_timed: list[str] = []
    robots = [(r, f) for r, f in ROBOTS if r in args.robots.split(",")]
    peers = args.peers.split(",")
    quantities = args.quantities.split(",")
    for name, floating in robots:
        for peer in peers:
            print(f"{name}: {peer}", flush=True)
            try:
                if peer == "adam.pytorch":
                    torch_section(rep, name, args.n, args.budget, quantities)
                else:
                    jax_section(rep, name, floating, peer, args.n, args.budget, quantities)
            except NotTimedError as exc:
                print(f"  not timed: {exc}", flush=True)
                not_timed.append(f"{name} / {peer}: {exc}")
    print()
    width = max([len(r[0]) for r in rep.rows] + [5]) + 1
    print(f"{'robot':<{width}}{'quantity':<12}{'peer':<14}{'N':>6}{'featherdyn/s':>14}{'peer/s':>12}{'ratio':>9}"
          f"{'1st call fd s':>15}{'peer s':>8}")
    for robot, quantity, peer, n, a, b, ca, cb in rep.rows:
        ratio = f"{a / b:9.1f}" if np.isfinite(a) else "  pending"
        first = f"{ca:>15.2f}{cb:>8.2f}" if np.isfinite(ca) else f"{'':>15}{'':>8}"
        print(f"{robot:<{width}}{quantity:<12}{peer:<14}{n:>6}{a:>14.0f}{b:>12.0f}{ratio}{first}")
    for what in ("value", "grad"):
        rel = [r for label, _, r, _ in rep.checks if (" grad wrt " in label) == (what == "grad")]
        if rel:
            print(f"agreement of the {what}s: {len(rel)} checks, largest |Δ| / max(1, max |featherdyn|) {max(rel):.1e}")
    for line in not_timed:
        print(f"not timed: {line}")
    print(f"load at the end {os.getloadavg()[0]:.2f}")
    _TMP.cleanup()
    return 1 if not_timed else 0


def _version(dist: str, module: Any) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(dist)
    except PackageNotFoundError:
        return str(getattr(module, "__version__", "?"))


if __name__ == "__main__":
    raise SystemExit(main(sys.argv))
