"""Verification of the spatial algebra against Pinocchio's own operations.

Each check draws the same random values for both libraries, converts
Pinocchio's linear-first 6D layout to featherdyn's angular-first one, and
compares. The identities at the end need no oracle (appendix F of the chapter).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from .. import rotation as rot
from ..conventions import matrix6_from_pinocchio
from ..spatial_algebra import (
    PluckerTransform,
    SpatialForce,
    SpatialInertia,
    SpatialMotion,
    crf,
    crm,
    cross_force,
    cross_motion,
    skew,
)
from .bridge import SWAP6, from_pin6
from .pinocchio import PinValue, require_pinocchio
from .report import Cause, CheckResult, compare, likely_cause

__all__ = ["algebra_checks", "random_transforms", "random_inertias"]

# Pinocchio stores 6D quantities linear first; the named converters of featherdyn.conventions swap them
_from_pin66 = matrix6_from_pinocchio


def random_transforms(rng: np.random.Generator, n: int) -> PluckerTransform:
    """``n`` random transforms: uniformly random rotations, translations in [−1, 1]³."""
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    return PluckerTransform(rot.quat_to_matrix(quat), rng.uniform(-1, 1, size=(n, 3)))


def random_inertias(rng: np.random.Generator, n: int) -> SpatialInertia:
    """``n`` random physical inertias: boxes of random size and mass, rotated and offset."""
    mass = rng.uniform(0.1, 10.0, size=n)
    box = SpatialInertia.box(mass, rng.uniform(0.05, 1.0, size=(n, 3)))
    return random_transforms(rng, n).apply(box)


def _compared(group: str, quantity: str, ours: ArrayLike, ref: ArrayLike, tol: float,
              causes: Sequence[Cause]) -> CheckResult:
    """:func:`compare`, with the cause a failure's numbers point to (or where the difference is largest)."""
    r = compare(group, quantity, ours, ref, tol)
    if r.passed or r.note:
        return r
    return replace(r, note=likely_cause(np.asarray(ours, dtype=np.float64), np.asarray(ref, dtype=np.float64),
                                        causes, tol))


def algebra_checks(samples: int = 20, seed: int = 0, tol: float = 1e-12) -> list[CheckResult]:
    """Compare every spatial-algebra operation with Pinocchio over ``samples`` random values.

    Returns one :class:`CheckResult` per operation, then the oracle-free
    identities (power invariance, ``X* = X⁻ᵀ``, ``det X = 1``, Jacobi,
    kinetic-energy invariance, ``from_matrix ∘ matrix = id``).
    """
    pin = require_pinocchio()
    rng = np.random.default_rng(seed)
    n = samples
    X = random_transforms(rng, n)
    Y = random_transforms(rng, n)
    m = SpatialMotion.from_vector(rng.normal(size=(n, 6)))
    m2 = SpatialMotion.from_vector(rng.normal(size=(n, 6)))
    f = SpatialForce.from_vector(rng.normal(size=(n, 6)))
    inertia = random_inertias(rng, n)
    inertia2 = random_inertias(rng, n)

    def se3(i: int, T: PluckerTransform = X) -> PinValue:
        return pin.SE3(np.array(T.rotation[i]), np.array(T.translation[i]))

    def pm(i: int, mm: SpatialMotion = m) -> PinValue:
        return pin.Motion(np.array(mm.linear[i]), np.array(mm.angular[i]))

    def pf(i: int) -> PinValue:
        return pin.Force(np.array(f.linear[i]), np.array(f.angular[i]))

    def pI(i: int, ii: SpatialInertia = inertia) -> PinValue:
        return pin.Inertia(float(ii.mass[i]), np.array(ii.com[i]), np.array(ii.inertia_com[i]))

    def oracle(fn: Callable[[int], PinValue]) -> np.ndarray:
        return np.stack([np.asarray(fn(i), dtype=np.float64) for i in range(n)])

    def vec(x: PinValue) -> np.ndarray:  # a pinocchio Motion/Force in featherdyn order
        return from_pin6(x.vector)

    def swapped(ref: np.ndarray) -> np.ndarray:  # [linear; angular] read as [angular; linear]
        return ref[..., SWAP6] if ref.shape[-1] == 6 and ref.ndim == 2 else ref[..., SWAP6, :][..., SWAP6]

    layout: list[Cause] = [("the linear and angular halves are swapped (Pinocchio stores 6D vectors "
                            "[linear; angular])", swapped)]
    force_as_motion: list[Cause] = [("the force is moved with X, as a motion, instead of X* = X⁻ᵀ",
                                     lambda ref: oracle(lambda i: vec(se3(i).act(pin.Motion(np.array(f.linear[i]),
                                                                                             np.array(f.angular[i]))))))]
    wxyz: list[Cause] = [("the quaternion is read (w, x, y, z); featherdyn stores (x, y, z, w)",
                          lambda ref: oracle(lambda i: pin.Quaternion(*quat[i]).toRotationMatrix()))]
    rows: list[tuple[str, ArrayLike, ArrayLike, Sequence[Cause]]] = [
        ("X.apply(motion) vs SE3.act(Motion)", X.apply(m).vector, oracle(lambda i: vec(se3(i).act(pm(i)))), layout),
        ("X.apply_inverse(motion) vs SE3.actInv(Motion)", X.apply_inverse(m).vector,
         oracle(lambda i: vec(se3(i).actInv(pm(i)))), layout),
        ("X.apply(force) vs SE3.act(Force)", X.apply(f).vector, oracle(lambda i: vec(se3(i).act(pf(i)))),
         force_as_motion),
        ("X.apply_inverse(force) vs SE3.actInv(Force)", X.apply_inverse(f).vector,
         oracle(lambda i: vec(se3(i).actInv(pf(i)))), layout),
        ("X.apply(inertia) vs SE3.act(Inertia)", X.apply(inertia).matrix(),
         oracle(lambda i: _from_pin66(se3(i).act(pI(i)).matrix())), ()),
        ("X.apply_inverse(inertia) vs SE3.actInv(Inertia)", X.apply_inverse(inertia).matrix(),
         oracle(lambda i: _from_pin66(se3(i).actInv(pI(i)).matrix())), ()),
        ("X.matrix() vs SE3.toActionMatrix()", X.matrix(), oracle(lambda i: _from_pin66(se3(i).toActionMatrix())),
         layout),
        ("X.dual_matrix() vs SE3.toDualActionMatrix()", X.dual_matrix(),
         oracle(lambda i: _from_pin66(se3(i).toDualActionMatrix())), layout),
        ("X.homogeneous() vs SE3.homogeneous", X.homogeneous(), oracle(lambda i: se3(i).homogeneous), ()),
        ("X.inverse() vs SE3.inverse()", X.inverse().homogeneous(), oracle(lambda i: se3(i).inverse().homogeneous),
         ()),
        ("X @ Y vs SE3 * SE3", (X @ Y).homogeneous(), oracle(lambda i: (se3(i) * se3(i, Y)).homogeneous), ()),
        ("cross_motion vs Motion.cross(Motion)", cross_motion(m, m2).vector,
         oracle(lambda i: vec(pm(i).cross(pm(i, m2)))), layout),
        ("cross_force vs Motion.cross(Force)", cross_force(m, f).vector, oracle(lambda i: vec(pm(i).cross(pf(i)))),
         layout),
        ("crm(v) vs Motion.action", crm(m), oracle(lambda i: _from_pin66(pm(i).action)), layout),
        ("crf(v) vs Motion.dualAction", crf(m), oracle(lambda i: _from_pin66(pm(i).dualAction)), layout),
        ("motion.dot(force) vs Motion.dot(Force)", m.dot(f), oracle(lambda i: pm(i).dot(pf(i))), ()),
        ("skew vs pin.skew", skew(m.angular), oracle(lambda i: pin.skew(np.array(m.angular[i]))), ()),
        ("inertia.matrix() vs Inertia.matrix()", inertia.matrix(), oracle(lambda i: _from_pin66(pI(i).matrix())),
         layout),
        ("inertia @ motion vs Inertia * Motion", (inertia @ m).vector, oracle(lambda i: vec(pI(i) * pm(i))), layout),
        ("inertia + inertia vs Inertia + Inertia", (inertia + inertia2).matrix(),
         oracle(lambda i: _from_pin66((pI(i) + pI(i, inertia2)).matrix())), ()),
        ("to_dynamic_parameters vs toDynamicParameters", inertia.to_dynamic_parameters(),
         oracle(lambda i: pI(i).toDynamicParameters()), ()),
        ("from_dynamic_parameters vs FromDynamicParameters",
         SpatialInertia.from_dynamic_parameters(inertia.to_dynamic_parameters()).matrix(),
         oracle(lambda i: _from_pin66(pin.Inertia.FromDynamicParameters(pI(i).toDynamicParameters()).matrix())), ()),
        ("kinetic_energy vs ½ v·(I v)", inertia.kinetic_energy(m), oracle(lambda i: 0.5 * pm(i).dot(pI(i) * pm(i))),
         ()),
    ]
    sizes = rng.uniform(0.1, 1.0, size=(n, 3))
    masses = rng.uniform(0.1, 10.0, size=n)
    rows += [
        ("SpatialInertia.box vs Inertia.FromBox", SpatialInertia.box(masses, sizes).matrix(),
         oracle(lambda i: _from_pin66(pin.Inertia.FromBox(masses[i], *sizes[i]).matrix())), ()),
        ("SpatialInertia.cylinder vs Inertia.FromCylinder", SpatialInertia.cylinder(masses, sizes[:, 0], sizes[:, 1]).matrix(),
         oracle(lambda i: _from_pin66(pin.Inertia.FromCylinder(masses[i], sizes[i, 0], sizes[i, 1]).matrix())),
         ()),
        ("SpatialInertia.sphere vs Inertia.FromSphere", SpatialInertia.sphere(masses, sizes[:, 0]).matrix(),
         oracle(lambda i: _from_pin66(pin.Inertia.FromSphere(masses[i], sizes[i, 0]).matrix())), ()),
    ]
    # rotation module
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    rpy = rng.uniform(-np.pi, np.pi, size=(n, 3)) * np.array([1.0, 0.5, 1.0])
    omega = rng.normal(size=(n, 3))
    rows += [
        ("quat_to_matrix vs Quaternion.toRotationMatrix", rot.quat_to_matrix(quat),
         oracle(lambda i: pin.Quaternion(quat[i, 3], *quat[i, :3]).toRotationMatrix()),
         wxyz),
        ("rpy_to_matrix vs rpy.rpyToMatrix", rot.rpy_to_matrix(rpy), oracle(lambda i: pin.rpy.rpyToMatrix(rpy[i])), ()),
        ("matrix_to_rpy vs rpy.matrixToRpy", rot.matrix_to_rpy(rot.rpy_to_matrix(rpy)),
         oracle(lambda i: pin.rpy.matrixToRpy(pin.rpy.rpyToMatrix(rpy[i]))), ()),
        ("so3_exp vs exp3", rot.so3_exp(omega), oracle(lambda i: pin.exp3(omega[i])), ()),
        ("so3_log vs log3", rot.so3_log(X.rotation), oracle(lambda i: pin.log3(np.array(X.rotation[i]))), ()),
        ("se3_exp vs exp6", rot.se3_exp(m).homogeneous(), oracle(lambda i: pin.exp6(pm(i)).homogeneous),
         ()),
        ("se3_log vs log6", rot.se3_log(X).vector, oracle(lambda i: vec(pin.log6(se3(i)))), layout),
    ]
    results = [_compared("pinocchio", q, a, b, tol, causes) for q, a, b, causes in rows]

    # identities that need no oracle (chapter appendix F)
    Xm, Xf = X.matrix(), X.dual_matrix()
    m3 = SpatialMotion.from_vector(rng.normal(size=(n, 6)))
    jacobi = (cross_motion(m, cross_motion(m2, m3)) + cross_motion(m2, cross_motion(m3, m))
              + cross_motion(m3, cross_motion(m, m2))).vector
    identities = [
        ("power invariance (X m)·(X* f) = m·f", X.apply(m).dot(X.apply(f)), m.dot(f)),
        ("X* = X⁻ᵀ", Xf, np.swapaxes(np.linalg.inv(Xm), -1, -2)),
        ("det X = 1", np.linalg.det(Xm), np.ones(n)),
        ("crf(v) = −crm(v)ᵀ", crf(m), -np.swapaxes(crm(m), -1, -2)),
        ("Jacobi identity", jacobi, np.zeros((n, 6))),
        ("(X v)×(X w) = X(v × w)", cross_motion(X.apply(m), X.apply(m2)).vector, X.apply(cross_motion(m, m2)).vector),
        ("I_B = X* I_A X⁻¹", X.apply(inertia).matrix(), Xf @ inertia.matrix() @ np.linalg.inv(Xm)),
        ("kinetic energy invariance", X.apply(inertia).kinetic_energy(X.apply(m)), inertia.kinetic_energy(m)),
        ("from_matrix ∘ matrix = id", SpatialInertia.from_matrix(inertia.matrix()).matrix(), inertia.matrix()),
        ("exp ∘ log = id (SE3)", rot.se3_exp(rot.se3_log(X)).homogeneous(), X.homogeneous()),
    ]
    results += [_compared("identity", q, a, b, tol * 100, ()) for q, a, b in identities]
    return results
