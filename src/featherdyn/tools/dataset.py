"""``featherdyn dataset``: random states of a robot and their dynamics, written to Zarr, on one or many machines.

::

    featherdyn dataset ROBOT|URDF --states N --out DIR.zarr [--quantities tau,M,ddq] [--floating-base]
                       [--seed S] [--chunk C] [--scheduler auto|local|sync|ADDRESS] [--workers W]

The states are cut into chunks of ``C``; chunk ``k`` draws its states from its
own generator, ``numpy.random.default_rng(SeedSequence(S, spawn_key=(k,)))``,
so the data depend on ``S``, ``N`` and ``C`` only — not on the number of workers,
nor on the order in which chunks finish. One Zarr group holds the inputs ``q``
`(N, nq)` (uniform within the joint limits, :func:`featherdyn.random_configuration`),
``v``, ``a``, ``u`` `(N, nv)` (standard normal; ``u`` is the torque of the
forward-dynamics quantities) and one array per quantity, each chunked like the
states, plus ``done`` `(N/C,)`: a chunk's flag is set after all its arrays are
written. The group's attributes record featherdyn's version, the model's
SHA-256, the settings and the conventions.

**Resumable**: run the same command again and chunks already done are
checked (their ``q`` regenerated and compared bit for bit, every array finite)
and skipped; a chunk that fails the check is computed again. A group made with
other settings is refused.

**Schedulers**: ``sync`` computes in this process (no Dask needed; the batches
run on all the core's threads); ``local`` starts a ``dask.distributed.LocalCluster``
of ``W`` worker processes (default: the cores available) with one core thread
each; any other value is the address of a running ``dask.distributed`` scheduler.
``auto`` (the default, :func:`choose_scheduler`) takes ``local`` when ``W`` is
given, or on a machine of at least :data:`LOCAL_MIN_CORES` cores for a job of at
least as many chunks as cores, and ``sync`` otherwise: measured on two cores,
``sync`` takes 1.8–2.6 s for 100 000 panda states (tau, M, ddq) where ``local``
takes 3.7–6.0 s, and 7.8–8.2 s against 11.7 s for 20 000 talos_full_v2 states
of M and the RNEA derivatives — starting the workers costs about 2 s and the
compute already uses both cores in ``sync``. What ``sync`` does not spread is
drawing the states and writing them with Zarr (80–90 % of a panda chunk's
time, one thread): with more cores, worker processes overlap those. The model is scattered
once to each worker; a task lost with its worker is run again by Dask
(a chunk written twice is written with the same bytes).

Layer: tools (``docs/architecture.md``); it calls the public API only.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
import time
from collections.abc import Callable, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..api import (
    aba,
    aba_derivatives,
    center_of_mass,
    centroidal_momentum_matrix,
    crba,
    generalized_gravity,
    get_num_threads,
    joint_torque_regressor,
    kinetic_energy,
    mass_matrix_inverse,
    nonlinear_effects,
    potential_energy,
    rnea,
    rnea_derivatives,
    set_num_threads,
)
from ..configuration import random_configuration
from ..errors import DatasetError, MissingDependencyError
from ..model import Model
from .args import plural
from .distributed import available_cores, dask_client

__all__ = ["QUANTITIES", "DEFAULT_QUANTITIES", "DatasetInterrupted", "DatasetSpec", "write_dataset", "model_sha256",
           "states_of_chunk", "choose_scheduler", "LOCAL_MIN_CORES"]


@dataclass(frozen=True)
class Quantity:
    """One array of a dataset: what it is, its per-state shape and how it is computed from a chunk."""

    description: str
    shape: Callable[[Model], tuple[int, ...]]
    compute: Callable[[Model, dict[str, Any]], np.ndarray]


def _once(s: dict[str, Any], key: str, compute: Callable[[], Any]) -> Any:
    """A result shared by several quantities of one chunk (∂τ/∂q and ∂τ/∂q̇ come from one derivative pass),
    computed the first time one of them asks for it and kept in the chunk's dict ``s``."""
    if key not in s:
        s[key] = compute()
    return s[key]


def _rnea_d(m: Model, s: dict[str, Any]) -> Any:
    return _once(s, "rnea_derivatives", lambda: rnea_derivatives(m, s["q"], s["v"], s["a"]))


def _aba_d(m: Model, s: dict[str, Any]) -> Any:
    return _once(s, "aba_derivatives", lambda: aba_derivatives(m, s["q"], s["v"], s["u"]))


def _nv(m: Model) -> tuple[int, ...]:
    return (m.nv,)


def _nvnv(m: Model) -> tuple[int, ...]:
    return (m.nv, m.nv)


#: every quantity ``--quantities`` takes; ``s`` holds the chunk's ``q``, ``v``, ``a``, ``u``
QUANTITIES: dict[str, Quantity] = {
    "tau": Quantity("τ = RNEA(q, v, a) (inverse dynamics)", _nv, lambda m, s: rnea(m, s["q"], s["v"], s["a"])),
    "M": Quantity("M(q), the joint-space mass matrix (CRBA)", _nvnv, lambda m, s: crba(m, s["q"])),
    "h": Quantity("h(q, v) = C(q, v) v + g(q)", _nv, lambda m, s: nonlinear_effects(m, s["q"], s["v"])),
    "g": Quantity("g(q), the generalized gravity", _nv, lambda m, s: generalized_gravity(m, s["q"])),
    "ddq": Quantity("q̈ = ABA(q, v, u) (forward dynamics under the torque u)", _nv,
                    lambda m, s: aba(m, s["q"], s["v"], s["u"])),
    "Minv": Quantity("M(q)⁻¹", _nvnv, lambda m, s: mass_matrix_inverse(m, s["q"])),
    "dtau_dq": Quantity("∂τ/∂q at (q, v, a)", _nvnv, lambda m, s: _rnea_d(m, s)[0]),
    "dtau_dv": Quantity("∂τ/∂v at (q, v, a)", _nvnv, lambda m, s: _rnea_d(m, s)[1]),
    "dddq_dq": Quantity("∂q̈/∂q at (q, v, u)", _nvnv, lambda m, s: _aba_d(m, s)[0]),
    "dddq_dv": Quantity("∂q̈/∂v at (q, v, u)", _nvnv, lambda m, s: _aba_d(m, s)[1]),
    "T": Quantity("kinetic energy ½ vᵀ M v", lambda m: (), lambda m, s: kinetic_energy(m, s["q"], s["v"])),
    "V": Quantity("potential energy", lambda m: (), lambda m, s: potential_energy(m, s["q"])),
    "com": Quantity("centre of mass in the world", lambda m: (3,), lambda m, s: center_of_mass(m, s["q"])),
    "Ag": Quantity("centroidal momentum matrix A_G(q) [k; p]", lambda m: (6, m.nv),
                   lambda m, s: centroidal_momentum_matrix(m, s["q"])),
    "Y": Quantity("joint torque regressor Y(q, v, a), τ = Y π", lambda m: (m.nv, 10 * m.nbodies),
                  lambda m, s: joint_torque_regressor(m, s["q"], s["v"], s["a"])),
}
DEFAULT_QUANTITIES = ("tau", "M", "ddq")
#: the inputs stored with every dataset
INPUTS = {"q": "configuration, uniform within the joint limits", "v": "joint velocity, standard normal",
          "a": "joint acceleration, standard normal", "u": "joint torque of ddq and its derivatives, standard normal"}
CONVENTIONS = {
    "motion": "[ω; v] angular first, body coordinates",
    "force": "[n; f] moment first",
    "quaternion": "(x, y, z, w), Pinocchio / ROS order",
    "free_flyer": "q = [p; quaternion of the base in the world], v = [ω; v] of the base in its own frame",
    "derivatives": "w.r.t. q along the tangent of featherdyn.integrate (v's layout)",
    "gravity": "model.gravity, included in tau, h, g, ddq",
}


def model_sha256(model: Model) -> str:
    """The SHA-256 of the model's pickle (the model's identity in a dataset's metadata)."""
    return hashlib.sha256(pickle.dumps(model, protocol=5)).hexdigest()


@dataclass(frozen=True)
class DatasetSpec:
    """What a dataset holds: sent to every worker with the model."""

    out: str
    states: int
    chunk: int
    seed: int
    quantities: tuple[str, ...]
    robot: str = ""
    floating_base: bool = False
    threads: int | None = None
    meta: dict[str, Any] = field(default_factory=dict, compare=False)

    @property
    def nchunks(self) -> int:
        return -(-self.states // self.chunk)

    def rows(self, k: int) -> tuple[int, int]:
        """The states ``[lo, hi)`` of chunk ``k``."""
        return k * self.chunk, min(self.states, (k + 1) * self.chunk)


def states_of_chunk(model: Model, spec: DatasetSpec, k: int) -> dict[str, np.ndarray]:
    """The inputs of chunk ``k``: ``q`` `(n, nq)`, ``v``, ``a``, ``u`` `(n, nv)`, from the chunk's own generator."""
    lo, hi = spec.rows(k)
    rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(k,)))
    n, nv = hi - lo, model.nv
    q = random_configuration(model, rng, n)
    return {"q": q, "v": rng.standard_normal((n, nv)), "a": rng.standard_normal((n, nv)),
            "u": rng.standard_normal((n, nv))}


def _zarr() -> Any:
    try:
        import zarr
    except ImportError:
        raise MissingDependencyError("featherdyn dataset writes Zarr (version 3, which needs Python >= 3.11): "
                                     "pip install 'featherdyn[distributed]'") from None
    return zarr


def _write_chunk(model: Model, spec: DatasetSpec, k: int) -> int:
    """Compute and write chunk ``k`` (a worker's task); its ``done`` flag last. Returns ``k``."""
    if spec.threads is not None and get_num_threads() != spec.threads:
        set_num_threads(spec.threads)
    group = _zarr().open_group(spec.out, mode="r+")
    lo, hi = spec.rows(k)
    s = states_of_chunk(model, spec, k)
    for name in INPUTS:
        group[name][lo:hi] = s[name]
    for name in spec.quantities:
        group[name][lo:hi] = QUANTITIES[name].compute(model, s)
    group["done"][k] = True
    return k


def _chunk_is_good(model: Model, spec: DatasetSpec, group: Any, k: int) -> bool:
    """A chunk marked done: its ``q`` is the one its generator gives, and every array is finite."""
    lo, hi = spec.rows(k)
    if not np.array_equal(group["q"][lo:hi], states_of_chunk(model, spec, k)["q"]):
        return False
    return all(bool(np.isfinite(group[name][lo:hi]).all()) for name in (*INPUTS, *spec.quantities))


def _settings(spec: DatasetSpec, model: Model) -> dict[str, Any]:
    from .. import __version__

    return {"featherdyn_version": __version__, "model_sha256": model_sha256(model), "robot": spec.robot,
            "floating_base": spec.floating_base, "states": spec.states, "chunk": spec.chunk, "seed": spec.seed,
            "quantities": list(spec.quantities)}


def _prepare(model: Model, spec: DatasetSpec) -> list[int]:
    """Create the group (or check an existing one); the chunks still to compute."""
    zarr = _zarr()
    path = Path(spec.out)
    settings = _settings(spec, model)
    if path.exists():
        try:
            group = zarr.open_group(spec.out, mode="r+")
            old = {k: group.attrs.get(k) for k in settings}
        except Exception as exc:  # not a Zarr group: refuse rather than write into it
            raise DatasetError(f"--out {path}: exists and is not a featherdyn dataset ({exc})") from None
        if old != settings:
            diff = ", ".join(f"{k}: {old[k]!r} there, {v!r} now" for k, v in settings.items() if old[k] != v)
            raise DatasetError(f"--out {path}: a dataset made with other settings ({diff}); "
                               "choose another --out or delete it to start again")
        done = np.asarray(group["done"][:], dtype=bool)
        todo = [k for k in range(spec.nchunks) if not (done[k] and _chunk_is_good(model, spec, group, k))]
        return todo
    group = zarr.open_group(spec.out, mode="w")
    for name, what in INPUTS.items():
        width = model.nq if name == "q" else model.nv
        group.create_array(name, shape=(spec.states, width), chunks=(spec.chunk, width), dtype="f8")
        group[name].attrs["description"] = what
    for name in spec.quantities:
        shape = QUANTITIES[name].shape(model)
        group.create_array(name, shape=(spec.states, *shape), chunks=(spec.chunk, *shape), dtype="f8")
        group[name].attrs["description"] = QUANTITIES[name].description
    group.create_array("done", shape=(spec.nchunks,), chunks=(1,), dtype="bool", fill_value=False)
    group.attrs.update({**settings, "conventions": CONVENTIONS, "joint_names": list(model.joint_names),
                        "nq": model.nq, "nv": model.nv, **spec.meta})
    return list(range(spec.nchunks))


def check_request(quantities: Sequence[str], out: str | os.PathLike[str], states: int, chunk: int,
                  seed: int = 0) -> tuple[str, ...]:
    """Refuse a bad request before any work: unknown quantity, unwritable ``out``, non-positive sizes, a negative seed.

    Raises:
        DatasetError: naming the option and what was expected.
    """
    names = tuple(dict.fromkeys(q.strip() for q in quantities if q.strip()))
    unknown = [q for q in names if q not in QUANTITIES]
    if unknown or not names:
        raise DatasetError(f"--quantities: unknown {', '.join(map(repr, unknown)) or 'empty list'}; "
                           f"expected a comma-separated list of {', '.join(QUANTITIES)}")
    if states < 1 or chunk < 1:
        raise DatasetError(f"--states and --chunk: expected positive integers, got {states} and {chunk}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise DatasetError(f"--seed: expected a non-negative integer (numpy's SeedSequence entropy), got {seed!r}")
    path = Path(out)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise DatasetError(f"--out {path}: the folder {folder} does not exist")
    target = path if path.exists() else folder
    if not os.access(target, os.W_OK):
        raise DatasetError(f"--out {path}: permission denied")
    if path.exists() and not path.is_dir():
        raise DatasetError(f"--out {path}: exists and is not a directory (a Zarr store is a directory)")
    return names


class DatasetInterrupted(KeyboardInterrupt):
    """Ctrl-C (``KeyboardInterrupt``) stopped :func:`write_dataset`; the workers are stopped and the chunks
    finished before it are kept (``kept`` of ``total``): the same call again resumes."""

    def __init__(self, kept: int, total: int) -> None:
        super().__init__(kept, total)
        self.kept, self.total = kept, total

    def __str__(self) -> str:
        return (f"interrupted: {self.kept} of {plural(self.total, 'chunk')} kept; "
                "run the same command again to resume")


def _chunks_done(out: str) -> int:
    """The chunks whose ``done`` flag is set in the store ``out`` (0 if it was not created)."""
    try:
        return int(np.count_nonzero(_zarr().open_group(out, mode="r")["done"][:]))
    except Exception:  # no store yet, or interrupted while it was being created
        return 0


#: ``--scheduler auto`` starts local worker processes on a machine of at least this many cores (module docstring)
LOCAL_MIN_CORES = 4


def choose_scheduler(nchunks: int, workers: int | None = None, cores: int | None = None) -> tuple[str, str]:
    """What ``--scheduler auto`` runs: ``("local" | "sync", why)`` for a job of ``nchunks`` chunks.

    ``local`` when ``workers`` is given, or when the machine has at least :data:`LOCAL_MIN_CORES` cores
    and the job at least one chunk per core; ``sync`` otherwise (see the module docstring for the timings).
    """
    cores = available_cores() if cores is None else cores
    if workers is not None:
        return "local", f"--workers {workers} given"
    if cores >= LOCAL_MIN_CORES and nchunks >= cores:
        return "local", f"{cores} cores and {plural(nchunks, 'chunk')}: worker processes overlap the single-threaded work"
    if cores < LOCAL_MIN_CORES:
        return "sync", (f"{plural(cores, 'core')}: in this process, faster than worker processes below "
                        f"{LOCAL_MIN_CORES} cores")
    return "sync", f"{plural(nchunks, 'chunk')} for {cores} cores: too few to spread over worker processes"


@dataclass
class DatasetRun:
    """What :func:`write_dataset` did."""

    out: str
    states: int
    computed_chunks: int
    skipped_chunks: int
    seconds: float

    @property
    def states_per_second(self) -> float:
        n = self.states * self.computed_chunks / max(self.computed_chunks + self.skipped_chunks, 1)
        return n / self.seconds if self.seconds > 0 else float("inf")


def write_dataset(model: Model, out: str | os.PathLike[str], *, states: int, quantities: Sequence[str] = DEFAULT_QUANTITIES,
                  seed: int = 0, chunk: int = 10_000, scheduler: str = "auto", workers: int | None = None,
                  robot: str = "", floating_base: bool = False,
                  progress: Callable[[int, int], None] | None = None) -> DatasetRun:
    """Write ``states`` random states of ``model`` and their ``quantities`` to the Zarr group ``out``.

    Args:
        model: the robot.
        out: the Zarr directory (created, or resumed when it exists with the same settings).
        states: ``N``, the number of states; chunk: states per chunk (and per Zarr chunk).
        quantities: names from :data:`QUANTITIES`.
        seed: ``S``: chunk ``k`` draws from ``default_rng(SeedSequence(S, spawn_key=(k,)))``.
        scheduler: ``"sync"`` (this process), ``"local"`` (a LocalCluster of ``workers`` processes),
            a ``dask.distributed`` scheduler address, or ``"auto"`` (:func:`choose_scheduler`).
        progress: called with ``(chunks finished, chunks to compute)`` after each chunk.

    Raises:
        DatasetError: bad request, or ``out`` holds a dataset made with other settings.
        MissingDependencyError: zarr, or dask.distributed for a scheduler other than ``sync``.
    """
    names = check_request(quantities, out, states, chunk, seed)
    cores = available_cores()
    if scheduler == "auto":
        scheduler, _why = choose_scheduler(-(-states // chunk), workers, cores)
    if scheduler == "local":
        workers = workers or cores
        threads: int | None = max(1, cores // workers)
    else:
        threads = None
    spec = DatasetSpec(out=str(out), states=states, chunk=chunk, seed=seed, quantities=names, robot=robot,
                       floating_base=floating_base, threads=threads)
    # the scheduler first: one that does not answer is refused before the store is created
    todo: list[int] = []
    start = time.perf_counter()
    try:
        with nullcontext() if scheduler == "sync" else dask_client(scheduler, workers) as client:
            todo = _prepare(model, spec)
            skipped = spec.nchunks - len(todo)
            start = time.perf_counter()
            if client is None or not todo:
                for n, k in enumerate(todo, 1):
                    _write_chunk(model, spec, k)
                    if progress is not None:
                        progress(n, len(todo))
            else:
                from dask.distributed import as_completed

                model_future = client.scatter(model, broadcast=True)  # once per worker
                futures = [client.submit(_write_chunk, model_future, spec, k, key=f"featherdyn-dataset-chunk-{k}",
                                         retries=3) for k in todo]
                for n, fut in enumerate(as_completed(futures), 1):
                    fut.result()
                    if progress is not None:
                        progress(n, len(todo))
    except KeyboardInterrupt:  # Ctrl-C: the workers are stopped (dask_client's exit); count what they finished
        raise DatasetInterrupted(_chunks_done(spec.out), spec.nchunks) from None
    return DatasetRun(str(out), states, len(todo), skipped, time.perf_counter() - start)


def progress_bar(stream: Any = None) -> Callable[[int, int], None]:
    """A text progress bar on ``stream`` (stderr): redrawn in place on a terminal, every ~10 % otherwise."""
    out = stream if stream is not None else sys.stderr
    tty = out.isatty()
    start = time.perf_counter()
    last = [-1]

    def show(done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if not tty and tenth == last[0] and done != total:
            return
        last[0] = tenth
        width = 30
        bar = "#" * (width * done // max(total, 1))
        rate = done / max(time.perf_counter() - start, 1e-9)
        text = f"[{bar:<{width}}] {done}/{total} {'chunk' if total == 1 else 'chunks'}, {rate:.1f} chunks/s"
        print(("\r" if tty else "") + text, end="" if tty and done < total else "\n", file=out, flush=True)

    return show
