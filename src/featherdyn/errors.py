"""The featherdyn exception hierarchy.

Every error that bad input can cause is one of these. Each subclasses the
builtin a caller would naturally catch (``ValueError`` for bad values and
shapes, ``TypeError`` for mixing a motion with a force), so plain
``except ValueError`` keeps working, while ``except FeatherdynError`` catches
everything featherdyn raises on purpose.

Messages name the argument, what was expected and what came, e.g.
``"qd: expected trailing dimension nv=7, got shape (6,)"``.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "FeatherdynError",
    "DatasetError",
    "ShapeError",
    "NotAModelError",
    "NonFiniteError",
    "DTypeError",
    "RotationError",
    "QuaternionNormError",
    "InertiaError",
    "SpatialTypeError",
    "FrameMismatchError",
    "ModelError",
    "URDFError",
    "MJCFError",
    "SDFError",
    "PhysicalityWarning",
    "MissingDependencyError",
    "SingularMassMatrixError",
    "BackendError",
]


class FeatherdynError(Exception):
    """Base class of every exception featherdyn raises on purpose."""


class ShapeError(FeatherdynError, ValueError):
    """An array argument has the wrong shape (names the argument and the expected shape)."""


class NotAModelError(ShapeError, TypeError):
    """A model argument is not a featherdyn :class:`~featherdyn.model.Model`: a :class:`ShapeError`, as every declared
    function has raised it, and a ``TypeError``, as ``fd.integrate`` & co. raised it before they were declared."""


class NonFiniteError(FeatherdynError, ValueError):
    """An argument contains NaN or infinity where finite numbers are required."""

    @classmethod
    def overflowed(cls, what: str, where: str) -> NonFiniteError:
        """The error of a computation ``what`` whose finite input gave a non-finite result (``where``: which value)."""
        return cls(f"{what}: the result overflowed ({where}) although every input is finite: the state or the "
                   "model holds magnitudes whose products exceed float64's range (about 1.8e308)")


class DTypeError(FeatherdynError, TypeError):
    """An array argument has a dtype featherdyn cannot compute with (complex, strings, ...)."""


class RotationError(FeatherdynError, ValueError):
    """A matrix given as a rotation is not orthonormal with determinant +1."""


class QuaternionNormError(FeatherdynError, ValueError):
    """A quaternion that must be unit is off unit norm by more than the tolerance."""


class InertiaError(FeatherdynError, ValueError):
    """A spatial inertia is malformed or not physically realisable.

    The message names the failed condition (mass > 0, positive definite
    rotational inertia, triangle inequality, rigid-body structure) and the
    numbers that failed it.
    """


class SpatialTypeError(FeatherdynError, TypeError):
    """A motion vector was used where a force vector belongs, or vice versa.

    Motion vectors (M⁶) and force vectors (F⁶) are dual spaces: they transform
    differently (X vs X* = X⁻ᵀ) and only their pairing (power) is meaningful.
    """


class FrameMismatchError(FeatherdynError, ValueError):
    """Two frame-tagged values were combined although their frames differ.

    The message names both frames. Untagged values (frame ``None``) are never
    checked.
    """


class ModelError(FeatherdynError, ValueError):
    """A model description is inconsistent (parent order, names, inertias, ...)."""

    @classmethod
    def no_mass(cls, model_name: str) -> ModelError:
        """The error of a quantity defined by the tree's mass (centre of mass, centroidal momentum) on a massless tree."""
        return cls(f"model {model_name!r} has no mass: its centre of mass is undefined")


class URDFError(ModelError):
    """A URDF document is malformed, hostile or describes an impossible tree.

    The message names the file, the element and the link or joint involved.
    """


class MJCFError(ModelError):
    """An MJCF (MuJoCo XML) document is malformed, hostile, unsupported or refused by MuJoCo's compiler rules.

    The message names the file, the line, the element and the attribute involved.
    """


class SDFError(ModelError):
    """An SDFormat (SDF) document is malformed, hostile, unsupported or describes an impossible tree.

    The message names the file, the line, the element and the attribute involved.
    """


class PhysicalityWarning(UserWarning):
    """A model is loadable but physically odd (indefinite inertia, triangle-inequality violation, ...).

    Loaders turn these into errors with ``strict=True``.
    """


class MissingDependencyError(FeatherdynError, ImportError):
    """An optional dependency (Pinocchio, example-robot-data, SymPy) is not installed.

    The message says which pip package provides it (Pinocchio is ``pin`` on
    PyPI; the package called ``pinocchio`` there is something else).
    """


class SingularMassMatrixError(FeatherdynError, ValueError):
    """The joint-space mass matrix is singular, so forward dynamics has no unique answer.

    Raised by ABA instead of returning NaN; the message names the joint whose
    articulated inertia vanished (typically a moving subtree without mass).
    """

    @classmethod
    def for_joint(cls, joint: str, body: str, pivot: float | None = None,
                  batch_index: tuple[int, ...] | None = None) -> SingularMassMatrixError:
        """The error for joint ``joint`` (moving body ``body``), the one message every backend raises.

        ``pivot`` is the smallest eigenvalue of the joint's articulated inertia
        ``D = Sᵀ IA S`` when it is known; ``batch_index`` the state of a batch.
        The rule that decides it is :data:`featherdyn.tolerances.SINGULAR_PIVOT_RTOL`.
        """
        value = "singular" if pivot is None else f"{pivot:.3g}"
        where = f" (batch index {batch_index})" if batch_index else ""
        return cls(
            f"joint {joint!r} (body {body!r}): the articulated inertia of its subtree along the joint axis is "
            f"{value} — the subtree has no mass or inertia that this joint can move, so the mass matrix is "
            f"singular and q̈ is not unique{where}"
        )


class ConstraintError(FeatherdynError, ValueError):
    """Constraints that cannot be solved as given: dependent rows (a rank-deficient constraint Jacobian)
    with ``mu = 0``, or proximal iterations that did not converge."""

    @classmethod
    def dependent(cls, m: int) -> ConstraintError:
        """``m`` rows whose Delassus matrix ``J M⁻¹ Jᵀ`` is singular (``mu = 0``)."""
        return cls(f"the {m} constraint rows are dependent (J M⁻¹ Jᵀ is singular): their forces are not unique; "
                   "pass mu > 0 (e.g. mu=1e-8) for the minimum-norm forces")

    @classmethod
    def singular_frames(cls, m: int) -> ConstraintError:
        """Frames whose ``m`` stacked Jacobian rows make ``J M⁻¹ Jᵀ + μ 1`` singular: no operational-space Λ."""
        return cls(f"operational_space_inertia: the {m} rows of the frames' Jacobians are dependent at this "
                   "configuration (J M⁻¹ Jᵀ + μ 1 is singular: a kinematic singularity), so Λ does not exist; pass "
                   "mu > 0 (e.g. mu=1e-8) for the damped Λ = (J M⁻¹ Jᵀ + μ 1)⁻¹")

    @classmethod
    def not_converged(cls, max_iter: int, tol: float) -> ConstraintError:
        """Proximal iterations that did not reach ``tol`` in ``max_iter``."""
        return cls(f"the proximal iterations did not converge in max_iter={max_iter} (tol={tol:g}): "
                   "raise max_iter or mu")

    @classmethod
    def check_iterations(cls, iterations: Any, m: int, max_iter: int, tol: float) -> None:
        """Raise for a solve's failed states: iterations ``−1`` (dependent rows with ``mu = 0``), ``−2`` (not
        converged); ``iterations`` an integer array `(...)`."""
        if (iterations == -1).any():
            raise cls.dependent(m)
        if (iterations == -2).any():
            raise cls.not_converged(max_iter, tol)


class DatasetError(FeatherdynError, ValueError):
    """A ``featherdyn dataset`` request refused before any work (unknown quantity, unwritable or
    mismatched ``--out``, bad sizes, unreachable scheduler)."""


class BackendError(FeatherdynError, ValueError):
    """An unknown or unavailable ``backend=`` was requested, or a setting of the batched calls is out of range
    (``fd.set_result_cache_size``)."""
