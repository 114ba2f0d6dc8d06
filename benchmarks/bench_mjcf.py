"""Loading MJCF: ``fd.load_mjcf(path)`` against MuJoCo's compiler ``mujoco.MjModel.from_xml_path(path)``.

Usage::

    FD_NO_EDITABLE=1 PYTHONPATH=src python benchmarks/bench_mjcf.py [--repeat 7] [--block 1] [--all] [--filter TEXT]
        [--cold [--runs K]] [--profile MODEL]

The models: gymnasium's ``envs/mujoco/assets``, mujoco's ``testdata`` and, if
installed, dm_control's ``suite`` (none is a featherdyn dependency), each
file both loaders accept. Times are the best of ``--repeat`` runs in one
process, the two loaders alternating (``--block B``: B loads of one, then B of the other, so that each runs
with the caches its own previous load left); the ratio is featherdyn / MuJoCo (below
1: featherdyn loads faster). MuJoCo's compile does more than featherdyn's load
(collision structures, constants, sizes of everything); featherdyn's builds the
rigid-body ``Model`` only. Both keep what they computed from mesh files in an in-process cache (MuJoCo the
meshes, featherdyn their mass properties, while the file is unchanged), so the best time on a model with large
meshes is a load from that cache.

``--cold``: instead, each model's first load in a fresh process (the libraries imported, nothing loaded yet),
featherdyn's and MuJoCo's in separate processes: the time with the mesh files read and integrated. ``--runs K``:
the best of K such fresh processes per library (on a shared machine a single run may be preempted mid-load).

``--filter TEXT``: only the models whose path contains TEXT.

``--all``: every standalone model of the MJCF survey (``scripts/mjcf_survey.py``: gymnasium,
gymnasium-robotics, dm_control, robosuite, metaworld and mujoco, whichever are installed) instead.

``--profile NAME`` runs cProfile on ``fd.load_mjcf`` of the models whose file
name contains NAME and prints the top entries.
"""

from __future__ import annotations

import argparse
import cProfile
import importlib.util
import io
import pstats
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import featherdyn as fd

mujoco = __import__("mujoco")


def models(every: bool = False) -> list[Path]:
    found: list[Path] = []
    if every:
        sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))
        import mjcf_survey

        found = [path for _, _, path in mjcf_survey.find_models()]
    else:
        for package, sub in (("gymnasium", "envs/mujoco/assets"), ("mujoco", "testdata"), ("dm_control", "suite")):
            spec = importlib.util.find_spec(package)
            if spec is not None and spec.origin is not None:
                found += sorted((Path(spec.origin).parent / sub).glob("*.xml"))
    out = []
    for path in found:
        try:
            mujoco.MjModel.from_xml_path(str(path))
            _fd_load(path)
        except Exception:  # not a standalone model, or refused by featherdyn: not a loading-speed question
            continue
        out.append(path)
    return out


def _fd_load(path: Path) -> fd.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fd.load_mjcf(path)


def _mj_load(path: Path) -> object:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mujoco.MjModel.from_xml_path(str(path))


def best_pair(path: Path, repeat: int, block: int = 1) -> tuple[float, float]:
    """Best-of seconds of featherdyn's and MuJoCo's load: ``repeat`` rounds, each ``block`` loads by featherdyn
    then ``block`` by MuJoCo (``block=1``: strict alternation, each load right after the other library's, with
    the caches the other left; larger blocks: both measured warm, after their own previous load)."""
    t_fd, t_mj = float("inf"), float("inf")
    for _ in range(repeat):
        for _ in range(block):
            t0 = time.perf_counter()
            _fd_load(path)
            t_fd = min(t_fd, time.perf_counter() - t0)
        for _ in range(block):
            t0 = time.perf_counter()
            _mj_load(path)
            t_mj = min(t_mj, time.perf_counter() - t0)
    return t_fd, t_mj


_FIRST_LOAD = """
import sys, time, warnings
warnings.simplefilter("ignore")
import featherdyn as fd, mujoco
fd.load_mjcf  # resolved before the clock starts, as mujoco.MjModel is
load = fd.load_mjcf if sys.argv[1] == "fd" else mujoco.MjModel.from_xml_path
t0 = time.perf_counter()
load(sys.argv[2])
print(time.perf_counter() - t0)
"""


def first_load(path: Path, which: str) -> float:
    """Seconds of the first load of ``path`` in a fresh process by ``which`` (``"fd"`` or ``"mj"``)."""
    out = subprocess.run([sys.executable, "-c", _FIRST_LOAD, which, str(path)], capture_output=True, text=True,
                         check=True)
    return float(out.stdout.split()[-1])


def profile(paths: list[Path], n: int = 25) -> str:
    prof = cProfile.Profile()
    prof.enable()
    for path in paths:
        for _ in range(5):
            _fd_load(path)
    prof.disable()
    out = io.StringIO()
    pstats.Stats(prof, stream=out).sort_stats("cumulative").print_stats(n)
    return out.getvalue()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="rounds (each: featherdyn's loads, then MuJoCo's)")
    parser.add_argument("--block", type=int, default=1, help="loads per library per round (1: alternate)")
    parser.add_argument("--all", action="store_true", help="every standalone model of the MJCF survey")
    parser.add_argument("--filter", default="", help="only models whose path contains this")
    parser.add_argument("--cold", action="store_true", help="first loads in fresh processes")
    parser.add_argument("--runs", type=int, default=1, help="--cold: best of this many fresh processes")
    parser.add_argument("--profile", default=None)
    args = parser.parse_args()
    paths = [p for p in models(args.all) if args.filter in str(p)]
    if args.profile is not None:
        print(profile([p for p in paths if args.profile in p.name]))
        return
    if args.cold:
        print(f"featherdyn {fd.__version__}, mujoco {mujoco.__version__}; first load in a fresh process"
              + (f", best of {args.runs}" if args.runs > 1 else ""))
        print(f"{'model':44s} {'fd ms':>9s} {'MuJoCo ms':>10s} {'ratio':>7s}")
        ratios = []
        for path in paths:
            t_fd = min(first_load(path, "fd") for _ in range(args.runs))
            t_mj = min(first_load(path, "mj") for _ in range(args.runs))
            ratios.append(t_fd / t_mj)
            name = f"{path.parent.parent.name}/{path.parent.name}/{path.name}"
            print(f"{name:44s} {t_fd * 1e3:9.2f} {t_mj * 1e3:10.2f} {t_fd / t_mj:7.2f}", flush=True)
        print(f"median ratio fd / MuJoCo over {len(ratios)} models: {statistics.median(ratios):.2f} "
              f"(min {min(ratios):.2f}, max {max(ratios):.2f}); slower than MuJoCo: {sum(r > 1 for r in ratios)}")
        return
    how = "alternating" if args.block == 1 else f"in blocks of {args.block}"
    print(f"featherdyn {fd.__version__}, mujoco {mujoco.__version__}; best of {args.repeat * args.block} "
          f"({how}), same process")
    print(f"{'model':44s} {'fd ms':>9s} {'MuJoCo ms':>10s} {'ratio':>7s}")
    ratios = []
    for path in paths:
        t_fd, t_mj = best_pair(path, args.repeat, args.block)
        ratios.append(t_fd / t_mj)
        name = f"{path.parent.parent.name}/{path.parent.name}/{path.name}"
        print(f"{name:44s} {t_fd * 1e3:9.2f} {t_mj * 1e3:10.2f} {t_fd / t_mj:7.2f}")
    print(f"median ratio fd / MuJoCo over {len(ratios)} models: {statistics.median(ratios):.2f} "
          f"(min {min(ratios):.2f}, max {max(ratios):.2f}); slower than MuJoCo: {sum(r > 1 for r in ratios)}")


if __name__ == "__main__":
    main()
