"""How the user's arrays are read: the declared layout, a reading (hypothesis) of it, and the comparisons.

A :class:`Hypothesis` is one reading of the values (joint order, 6D halves,
quaternion order, continuous joints, triangle of ``M``, base frame, classical
acceleration, gravity); :class:`Checker` converts the values to featherdyn's
convention under it and compares them with featherdyn, caching both.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TypedDict

import numpy as np

from ...errors import FeatherdynError, MissingDependencyError
from ...frames import LOCAL, ReferenceFrame
from ...joints import FreeFlyerJoint, Joint, PlanarJoint, SphericalJoint
from ...model import Model
from ..bridge import SWAP6, JointMap, from_pin6_rows
from ..pinocchio import PinModel
from ..report import CheckResult, compare
from .report import one_line
from .values import DERIVATIVE_KEYS, DERIVATIVE_SPECS, VECTOR_KEYS, Given

__all__ = ["QUANTITIES", "DERIVATIVES", "COMPUTE", "Block", "Change", "Hypothesis", "UnreadableError", "Layout", "Checker"]

QUANTITIES = {
    "tau": "tau vs fd.rnea(q, v, a)",
    "M": "M vs fd.crba(q)",
    "ddq": "ddq: tau vs fd.rnea(q, v, ddq)",
}

#: The derivative matrices compared, by key (:mod:`.derivatives` reads a mismatch of their own).
DERIVATIVES = {k: f"{k} vs {spec.function}" for k, spec in DERIVATIVE_SPECS.items()}


def _kinematics(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
                ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    assert frame is not None  # (check_values refuses a frame's key without a frame)
    v = x["v"]
    a = x["a"] if "a" in x else np.zeros_like(v)
    return dict(fd.kinematics_derivatives(model, x["q"], v, a, frame, reference)._asdict())


def _centroidal(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
                ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    v = x["v"]
    return dict(fd.centroidal_dynamics_derivatives(model, x["q"], v, x["a"] if "a" in x else np.zeros_like(v))
                ._asdict())


def _center_of_mass(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
                    ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    v = x["v"] if "v" in x else np.zeros(x["q"].shape[:-1] + (model.nv,))
    return dict(fd.center_of_mass_derivatives(model, x["q"], v)._asdict())


def _rnea(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
          ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    dq, dv, _ = fd.rnea_derivatives(model, x["q"], x["v"], x["a"])
    return {"dtau_dq": dq, "dtau_dv": dv}


def _aba(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
         ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    dq, dv, _ = fd.aba_derivatives(model, x["q"], x["v"], x["tau"])
    return {"dddq_dq": dq, "dddq_dv": dv}


def _gravity(model: Model, x: dict[str, np.ndarray], frame: int | None, reference: ReferenceFrame
             ) -> dict[str, np.ndarray]:
    import featherdyn as fd

    return {"dg_dq": fd.generalized_gravity_derivatives(model, x["q"])}


#: featherdyn's derivative matrices by the function of :data:`~.values.DERIVATIVE_SPECS`: ``(model, the values
#: read in featherdyn's convention, frame index, reference) → {key: (N, rows, nv)}``
COMPUTE = {"fd.rnea_derivatives": _rnea, "fd.aba_derivatives": _aba, "fd.generalized_gravity_derivatives": _gravity,
           "fd.center_of_mass_derivatives": _center_of_mass, "fd.centroidal_dynamics_derivatives": _centroidal,
           "fd.kinematics_derivatives": _kinematics}


@dataclass(frozen=True)
class Block:
    """One joint in the declared convention's layout."""

    body: int       # featherdyn body index
    name: str
    kind: str
    q0: int         # start in the declared q
    nq: int
    v0: int         # start in the declared v
    nv: int
    angle: bool     # continuous revolute or planar: its angle may be given as (cos, sin) or the reverse
    quat_at: int | None  # offset of the quaternion inside the q block


class Change(TypedDict, total=False):
    """One suspect as a change of :class:`Hypothesis` fields, e.g. ``{"gravity": (0.0, 0.0, 9.81)}``."""

    cos_sin: bool
    order: str
    swap6: bool
    quat_wxyz: str
    world: bool
    classical: bool
    gravity: tuple[float, float, float]
    triangle: str


@dataclass(frozen=True)
class Hypothesis:
    """A reading of the user's values (all false / ``None``: as the declared convention says)."""

    cos_sin: bool = False
    order: str | None = None
    swap6: bool = False
    quat_wxyz: str | None = None  # "all" quaternions, or only the "free_flyer"'s
    world: bool = False
    classical: bool = False
    gravity: tuple[float, float, float] | None = None
    triangle: str | None = None

    def merged(self, change: Change) -> Hypothesis:
        """This reading with the fields of ``change`` set."""
        return dataclasses.replace(self, **change)

    @property
    def suspects(self) -> tuple[str, ...]:
        names = [("continuous_layout", self.cos_sin), ("joint_order", self.order is not None),
                 ("swapped_6d_halves", self.swap6), ("quaternion_wxyz", self.quat_wxyz is not None),
                 ("world_frame_base_velocity", self.world), ("classical_base_acceleration", self.classical),
                 ("gravity", self.gravity is not None), ("mass_matrix_triangle", self.triangle is not None)]
        return tuple(n for n, on in names if on)


class UnreadableError(Exception):
    """The values cannot be read under a hypothesis (wrong lengths)."""


class Layout:
    """The declared convention's layout of q and v, joint by joint, and the other joint orders worth trying."""

    def __init__(self, model: Model, pin_model: PinModel | None, jmap: JointMap | None, convention: str,
                 continuous: set[int]) -> None:
        self.model, self.pin_model, self.jmap, self.convention = model, pin_model, jmap, convention
        self.ff = next((i for i, j in enumerate(model.joints) if isinstance(j, FreeFlyerJoint)), None)
        self.blocks = self._declared_blocks(continuous)
        self.flip_nq = sum(self._flip_delta(b) for b in self.blocks)
        self.declared_nq = sum(b.nq for b in self.blocks)
        self.orders = self._order_candidates()

    def _declared_blocks(self, continuous: set[int]) -> list[Block]:
        m = self.model
        blocks = []
        if self.convention == "featherdyn":
            for i, joint in enumerate(m.joints):
                blocks.append(Block(i, m.joint_names[i], joint.kind, m.idx_q[i], m.nqs[i], m.idx_v[i], m.nvs[i],
                                     i in continuous or isinstance(joint, PlanarJoint), _quat_offset(joint)))
        else:
            body_of = {e.pin_joint: e.fd_body for e in self.pinocchio_map().entries}
            pm = self.pin_model
            assert pm is not None  # it comes with the joint map
            for jid in sorted(body_of):
                i = body_of[jid]
                joint = m.joints[i]
                blocks.append(Block(i, m.joint_names[i], joint.kind, int(pm.idx_qs[jid]), int(pm.nqs[jid]),
                                     int(pm.idx_vs[jid]), int(pm.nvs[jid]),
                                     i in continuous or isinstance(joint, PlanarJoint), _quat_offset(joint)))
        return blocks

    def pinocchio_map(self) -> JointMap:
        """The joint map to Pinocchio (always there in the pinocchio convention: Pinocchio is required then)."""
        if self.jmap is None:
            raise MissingDependencyError("the pinocchio convention needs Pinocchio (`pip install pin`)")
        return self.jmap

    def _flip_delta(self, b: Block) -> int:
        """How much longer the block's q is when its angle layout is flipped."""
        if not b.angle:
            return 0
        return 1 if self.convention == "featherdyn" else -1

    def _order_candidates(self) -> dict[str, tuple[int, ...]]:
        declared = tuple(b.body for b in self.blocks)
        names = self.model.joint_names
        head = tuple(i for i in declared if i == self.ff)
        rest = [i for i in declared if i != self.ff]
        cands: dict[str, tuple[int, ...]] = {}
        if self.convention == "featherdyn" and self.jmap is not None:
            cands["pinocchio"] = tuple(e.fd_body for e in sorted(self.jmap.entries, key=lambda e: e.pin_joint))
        elif self.convention == "pinocchio":
            cands["featherdyn"] = tuple(range(self.model.nbodies))
        cands["alphabetical"] = head + tuple(sorted(rest, key=lambda i: names[i]))
        cands["reverse"] = head + tuple(reversed(rest))
        out: dict[str, tuple[int, ...]] = {}
        for name, order in cands.items():
            if order != declared and order not in out.values():
                out[name] = order
        return out

    def order_of(self, h: Hypothesis) -> list[Block]:
        if h.order is None:
            return self.blocks
        by_body = {b.body: b for b in self.blocks}
        return [by_body[i] for i in self.orders[h.order]]


class Checker(Layout):
    """Compares the values under any reading (:class:`Hypothesis`), caching readings and results."""

    def __init__(self, model: Model, pin_model: PinModel | None, jmap: JointMap | None, convention: str,
                 continuous: set[int],
                 given: Given, tol: float, frame: int | None = None, reference: ReferenceFrame = LOCAL) -> None:
        super().__init__(model, pin_model, jmap, convention, continuous)
        self.given, self.tol = given, tol
        #: the frame (index) and reference of the frame derivatives (``dv_dq`` & co.)
        self.frame, self.reference = frame, reference
        self._reads: dict[tuple[object, ...], dict[str, np.ndarray] | Exception] = {}
        self._results: dict[tuple[Hypothesis, str], CheckResult] = {}
        self._derivatives: dict[tuple[object, ...], dict[str, np.ndarray]] = {}
        self._models: dict[tuple[float, float, float], Model] = {}

    # ---- reading the user's arrays ------------------------------------------------------------------------

    def read(self, h: Hypothesis) -> dict[str, np.ndarray]:
        """The user's arrays in featherdyn's convention under hypothesis ``h`` (featherdyn order, ``(N, ...)``)."""
        key = (h.cos_sin, h.order, h.swap6, h.quat_wxyz, h.world, h.classical, h.triangle)
        if key not in self._reads:
            try:
                self._reads[key] = self._read(h)
            except (UnreadableError, FeatherdynError, ValueError) as exc:
                self._reads[key] = exc
        out = self._reads[key]
        if isinstance(out, Exception):
            raise out
        return out

    def _read(self, h: Hypothesis) -> dict[str, np.ndarray]:
        g = self.given.arrays
        n = self.given.n
        order = self.order_of(h)
        # q, block by block in the user's order, into the declared layout
        q_user = g["q"]
        q_decl = np.zeros((n, self.declared_nq))
        pos = 0
        for b in order:
            length = b.nq + (self._flip_delta(b) if h.cos_sin else 0)
            seg = q_user[:, pos : pos + length].copy()
            pos += length
            if h.cos_sin and b.angle:
                seg = self._unflip_angle(b, seg)
            if b.quat_at is not None and (h.quat_wxyz == "all" or h.quat_wxyz == "free_flyer" == b.kind):
                o = b.quat_at
                seg[:, o : o + 4] = seg[:, [o + 1, o + 2, o + 3, o]]
            q_decl[:, b.q0 : b.q0 + b.nq] = seg
        if pos != q_user.shape[1]:
            raise UnreadableError(f"q has length {q_user.shape[1]}, this reading needs {pos}")
        # v-like arrays: a permutation src with declared[k] = user[src[k]]
        nv = self.model.nv
        src = np.empty(nv, dtype=int)
        pos = 0
        for b in order:
            idx = np.arange(pos, pos + b.nv)
            pos += b.nv
            if h.swap6 and b.kind == "free_flyer":
                idx = idx[SWAP6]
            src[b.v0 : b.v0 + b.nv] = idx
        out: dict[str, np.ndarray] = {}
        out["q"] = q_decl
        for k in VECTOR_KEYS:
            if k in g:
                out[k] = g[k][:, src]
        if "M" in g:
            M = g["M"]
            if h.triangle == "upper":
                M = np.triu(M) + np.swapaxes(np.triu(M, 1), -1, -2)
            elif h.triangle == "lower":
                M = np.tril(M) + np.swapaxes(np.tril(M, -1), -1, -2)
            out["M"] = M[:, src][:, :, src]
        for k in DERIVATIVE_KEYS:  # columns in v's layout (rows too for nv rows, as M); (·, nq) stays as given
            if k in g and g[k].shape[-1] == nv:
                out[k] = g[k][:, src][:, :, src] if DERIVATIVE_SPECS[k].rows == "joint" else g[k][:, :, src]
        if self.convention == "pinocchio":
            jm = self.pinocchio_map()
            out["q"] = jm.q_from_pin(out["q"])
            for k in VECTOR_KEYS:
                if k in out:
                    out[k] = jm.v_from_pin(out[k])
            for k in ("M", *DERIVATIVE_KEYS):
                if k in out:
                    rows = "joint" if k == "M" else DERIVATIVE_SPECS[k].rows
                    if rows == "joint":
                        out[k] = jm.matrix_from_pin(out[k])
                    else:  # Pinocchio's 6 rows are [v; ω] and [p; k]
                        out[k] = jm.columns_from_pin(from_pin6_rows(out[k]) if rows != "point" else out[k])
        if h.world or h.classical:
            self._base_frame(out, h)
        return out

    def _unflip_angle(self, b: Block, seg: np.ndarray) -> np.ndarray:
        """The block's q in the declared layout from the flipped one (cos/sin ↔ angle)."""
        if self.convention == "featherdyn":  # (cos, sin) given, angle wanted
            angle = np.arctan2(seg[:, -1], seg[:, -2])
            return np.concatenate([seg[:, :-2], angle[:, None]], axis=1)
        angle = seg[:, -1]  # angle given, (cos, sin) wanted
        return np.concatenate([seg[:, :-1], np.cos(angle)[:, None], np.sin(angle)[:, None]], axis=1)

    def _base_frame(self, out: dict[str, np.ndarray], h: Hypothesis) -> None:
        """Free-flyer velocity, acceleration, wrench (and M) to featherdyn's base-frame spatial quantities."""
        from ...rotation import quat_to_matrix

        m, i = self.model, self.ff
        assert i is not None
        qs, vs = m.idx_q[i], m.idx_v[i]
        ang, lin = slice(vs, vs + 3), slice(vs + 3, vs + 6)

        def rt(x: np.ndarray) -> np.ndarray:  # Rᵀ x, per state
            return np.einsum("nji,nj->ni", R, x)

        R = quat_to_matrix(out["q"][:, qs + 3 : qs + 7], check_norm=False)
        if h.world:
            for k in ("v", "a", "tau", "ddq"):
                if k in out:
                    x = out[k].copy()
                    x[:, ang], x[:, lin] = rt(x[:, ang]), rt(x[:, lin])
                    out[k] = x
            if "M" in out:
                T = np.broadcast_to(np.eye(m.nv), out["M"].shape).copy()
                T[:, ang, ang] = np.swapaxes(R, -1, -2)
                T[:, lin, lin] = np.swapaxes(R, -1, -2)
                out["M"] = T @ out["M"] @ np.swapaxes(T, -1, -2)
        if "v" in out:  # accelerations given as d/dt of world-aligned (or classical) quantities
            omega, vel = out["v"][:, ang], out["v"][:, lin]
            for k in ("a", "ddq"):
                if k in out:
                    x = out[k].copy()
                    x[:, lin] -= np.cross(omega, vel)
                    out[k] = x

    # ---- comparing -----------------------------------------------------------------------------------------

    def model_for(self, h: Hypothesis) -> Model:
        if h.gravity is None:
            return self.model
        if h.gravity not in self._models:
            self._models[h.gravity] = dataclasses.replace(self.model, gravity=np.array(h.gravity, dtype=float))
        return self._models[h.gravity]

    def quantities(self) -> list[str]:
        g = self.given.arrays
        out = []
        if "M" in g:
            out.append("M")
        if "tau" in g and "a" in g:
            out.append("tau")
        if "ddq" in g:
            out.append("ddq")
        return out

    @staticmethod
    def _relevant(h: Hypothesis, quantity: str) -> Hypothesis:
        if quantity == "M":
            return dataclasses.replace(h, classical=False, gravity=None)
        return dataclasses.replace(h, triangle=None)

    def result(self, h: Hypothesis, quantity: str, group: str = "check") -> CheckResult:
        key = (self._relevant(h, quantity), quantity)
        if key not in self._results:
            self._results[key] = self._compute(key[0], quantity)
        r = self._results[key]
        return r if r.group == group else dataclasses.replace(r, group=group)

    def expected_and_given(self, h: Hypothesis, quantity: str) -> tuple[np.ndarray, np.ndarray]:
        import featherdyn as fd

        x = self.read(h)
        model = self.model_for(h)
        if quantity == "M":
            return fd.crba(model, x["q"]), x["M"]
        if quantity == "tau":
            return fd.rnea(model, x["q"], x["v"], x["a"]), x["tau"]
        # forward dynamics judged by its backward error: the force that ddq needs against the given tau
        # (comparing fd.aba(q, v, tau) with ddq would amplify round-off in tau by the condition number of M)
        return fd.rnea(model, x["q"], x["v"], x["ddq"]), x["tau"]

    def _compute(self, h: Hypothesis, quantity: str) -> CheckResult:
        name = QUANTITIES[quantity]
        try:
            expected, given = self.expected_and_given(h, quantity)
        except (UnreadableError, FeatherdynError, ValueError) as exc:
            return CheckResult("check", name, math.inf, math.inf, 0, self.tol, False, one_line(exc))
        return compare("check", name, given, expected, self.tol, "")

    def derivative_keys(self) -> list[str]:
        """The derivative matrices given (the keys of :data:`~.values.DERIVATIVE_SPECS`)."""
        return [k for k in DERIVATIVE_KEYS if k in self.given.arrays]

    def label(self, key: str) -> str:
        """The row's name of derivative matrix ``key`` (a frame's with the frame and its reference)."""
        if DERIVATIVE_SPECS[key].frame and self.frame is not None:
            return f"{DERIVATIVES[key]} ({self.model.frames[self.frame].name}, {self.reference.name})"
        return DERIVATIVES[key]

    def derivatives_at(self, h: Hypothesis, reference: ReferenceFrame | None = None) -> dict[str, np.ndarray]:
        """featherdyn's derivative matrices at the state read under ``h`` (:data:`COMPUTE`: e.g.
        ``fd.rnea_derivatives(q, v, a)``), for the keys given; cached per state and gravity. ``reference``:
        the frame derivatives in another reference than the one declared."""
        ref = self.reference if reference is None else reference
        key = (h.cos_sin, h.order, h.swap6, h.quat_wxyz, h.world, h.classical, h.gravity, ref)
        if key not in self._derivatives:
            x, model = self.read(h), self.model_for(h)
            ours: dict[str, np.ndarray] = {}
            for function in dict.fromkeys(DERIVATIVE_SPECS[k].function for k in self.derivative_keys()):
                ours.update(COMPUTE[function](model, x, self.frame, ref))
            self._derivatives[key] = ours
        return self._derivatives[key]

    def derivative_result(self, h: Hypothesis, key: str, group: str = "check") -> CheckResult:
        """The user's derivative matrix ``key`` read under ``h`` against featherdyn's at the state read so.

        The reading moves its rows and columns as it moves ``v``'s entries (joint order, 6D halves, the
        declared convention); a world-frame base or a classical acceleration has no conversion for a derivative
        matrix, so under those the matrix is compared as given and the row says so."""
        name = self.label(key)
        cache = (dataclasses.replace(h, triangle=None), key)
        if cache not in self._results:
            raw = self.given.arrays[key]
            if raw.shape[-1] != self.model.nv:  # with respect to q's coordinates: .derivatives reads it
                r = CheckResult("check", name, math.inf, math.inf, 0, self.tol, False,
                                f"{key} has {raw.shape[-1]} columns (nq): a derivative with respect to q's "
                                "coordinates")
            else:
                try:
                    given, expected = self.read(h)[key], self.derivatives_at(h)[key]
                except (UnreadableError, FeatherdynError, ValueError) as exc:
                    r = CheckResult("check", name, math.inf, math.inf, 0, self.tol, False, one_line(exc))
                else:
                    r = compare("check", name, given, expected, self.tol, "")
                    unconverted = [n for n, on in (("world_frame_base_velocity", h.world),
                                                   ("classical_base_acceleration", h.classical)) if on]
                    if unconverted and not r.passed:
                        r = dataclasses.replace(r, note=f"compared as given: {' and '.join(unconverted)} has no "
                                                "conversion for a derivative matrix")
            self._results[cache] = r
        r = self._results[cache]
        return r if r.group == group else dataclasses.replace(r, group=group)

    def explains(self, h: Hypothesis) -> bool:
        return all(self.result(h, q).passed for q in self.quantities())


def _quat_offset(joint: Joint) -> int | None:
    if isinstance(joint, FreeFlyerJoint):
        return 3
    if isinstance(joint, SphericalJoint):
        return 0
    return None
