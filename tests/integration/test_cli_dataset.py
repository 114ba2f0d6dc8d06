"""``featherdyn dataset``: the same bytes on 1 and 2 worker processes, resumable, survives a killed worker.

Oracles: a dataset written in this process (``--scheduler sync``) chunk by
chunk; the public functions on the stored inputs; the chunk generators.
Everything runs on loopback (a ``LocalCluster`` of worker processes).
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.tools.dataset import DatasetSpec, model_sha256, states_of_chunk, write_dataset

zarr = pytest.importorskip("zarr")  # test dependencies (the `test` extra): these run in CI
pytest.importorskip("dask.distributed")
import psutil  # noqa: E402  (installed with dask.distributed)


def cli(*args: str | Path, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "featherdyn", "dataset", *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)


def arrays(path: Path) -> dict[str, np.ndarray]:
    group = zarr.open_group(str(path), mode="r")
    return {name: group[name][:] for name in group.array_keys()}


def assert_same(a: Path, b: Path) -> None:
    x, y = arrays(a), arrays(b)
    assert sorted(x) == sorted(y)
    for name in x:
        assert x[name].dtype == y[name].dtype and np.array_equal(x[name], y[name]), name


@pytest.fixture(scope="module")
def panda() -> fd.Model:
    return fd.load_robot("panda")


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory, panda: fd.Model) -> Path:
    """1 000 Panda states in chunks of 150, written in this process."""
    out = tmp_path_factory.mktemp("ref") / "sync.zarr"
    run = write_dataset(panda, out, states=1000, chunk=150, seed=7, quantities=["tau", "M", "ddq", "dtau_dq"],
                        scheduler="sync", robot="panda")
    assert (run.computed_chunks, run.skipped_chunks) == (7, 0)
    return out


def test_the_data_are_the_public_functions_on_the_stored_states(reference: Path, panda: fd.Model) -> None:
    d = arrays(reference)
    assert d["q"].shape == (1000, panda.nq) and d["M"].shape == (1000, panda.nv, panda.nv)
    assert d["done"].all()
    np.testing.assert_array_equal(d["tau"], fd.rnea(panda, d["q"], d["v"], d["a"]))
    np.testing.assert_array_equal(d["M"], fd.crba(panda, d["q"]))
    np.testing.assert_array_equal(d["ddq"], fd.aba(panda, d["q"], d["v"], d["u"]))
    np.testing.assert_array_equal(d["dtau_dq"], fd.rnea_derivatives(panda, d["q"], d["v"], d["a"])[0])
    lower, upper = panda.lower, panda.upper
    assert np.all(d["q"] >= lower) and np.all(d["q"] <= upper)
    # chunk k comes from its own generator: the dataset is a function of (seed, states, chunk) only
    spec = DatasetSpec(out=str(reference), states=1000, chunk=150, seed=7, quantities=("tau",))
    np.testing.assert_array_equal(d["v"][900:], states_of_chunk(panda, spec, 6)["v"])
    attrs = dict(zarr.open_group(str(reference), mode="r").attrs)
    assert attrs["featherdyn_version"] == fd.__version__
    assert attrs["model_sha256"] == model_sha256(fd.load_robot("panda"))
    assert attrs["seed"] == 7 and attrs["chunk"] == 150 and attrs["quantities"] == ["tau", "M", "ddq", "dtau_dq"]
    assert "quaternion" in attrs["conventions"] and attrs["joint_names"] == list(panda.joint_names)


@pytest.mark.parametrize("workers", [1, 2])
def test_one_and_two_worker_processes_write_the_same_bytes(reference: Path, tmp_path: Path, workers: int) -> None:
    out = tmp_path / f"w{workers}.zarr"
    p = cli("panda", "--states", "1000", "--chunk", "150", "--seed", "7", "--quantities", "tau,M,ddq,dtau_dq",
            "--out", out, "--workers", str(workers))
    assert p.returncode == 0, p.stderr
    assert "7 chunks computed, 0 already done" in p.stdout
    assert "7/7 chunks" in p.stderr  # the progress bar
    assert_same(out, reference)


def test_an_interrupted_run_resumes_and_a_damaged_chunk_is_recomputed(reference: Path, tmp_path: Path,
                                                                      panda: fd.Model) -> None:
    out = tmp_path / "resume.zarr"

    def stop_after_three(done: int, total: int) -> None:
        if done == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_dataset(panda, out, states=1000, chunk=150, seed=7, quantities=["tau", "M", "ddq", "dtau_dq"],
                      scheduler="sync", robot="panda", progress=stop_after_three)
    assert arrays(out)["done"].sum() == 3
    p = cli("panda", "--states", "1000", "--chunk", "150", "--seed", "7", "--quantities", "tau,M,ddq,dtau_dq",
            "--out", out, "--scheduler", "sync")
    assert p.returncode == 0, p.stderr
    assert "4 chunks computed, 3 already done" in p.stdout
    assert_same(out, reference)
    # a chunk marked done whose data were damaged is checked, found bad and computed again
    group = zarr.open_group(str(out), mode="r+")
    group["tau"][160] = np.nan
    run = write_dataset(panda, out, states=1000, chunk=150, seed=7, quantities=["tau", "M", "ddq", "dtau_dq"],
                        scheduler="sync", robot="panda")
    assert (run.computed_chunks, run.skipped_chunks) == (1, 6)
    assert_same(out, reference)


def _worker_processes(pid: int) -> list[psutil.Process]:
    kids = psutil.Process(pid).children(recursive=True)
    return [k for k in kids if "multiprocessing" in " ".join(k.cmdline()) and "resource_tracker" not in
            " ".join(k.cmdline())]


def test_a_worker_killed_mid_run_loses_no_chunk(tmp_path: Path) -> None:
    """SIGKILL one of two workers while chunks are being written: Dask runs its tasks again."""
    talos = fd.load_robot("talos_full_v2")
    args = ["talos_full_v2", "--states", "6000", "--chunk", "100", "--seed", "3", "--quantities", "M,dtau_dq,dtau_dv",
            "--workers", "2"]
    out = tmp_path / "killed.zarr"
    proc = subprocess.Popen([sys.executable, "-m", "featherdyn", "dataset", *args, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    killed = None
    deadline = time.monotonic() + 120
    while killed is None and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
        done_dir = out / "done"
        if done_dir.exists() and sum(1 for _ in done_dir.rglob("*") if _.is_file()) >= 4:
            workers = _worker_processes(proc.pid)
            if workers:
                killed = workers[0].pid
                os.kill(killed, signal.SIGKILL)
    _stdout, stderr = proc.communicate(timeout=300)
    assert killed is not None, "the run ended before a worker could be killed"
    assert proc.returncode == 0, stderr
    d = arrays(out)
    assert d["done"].all()
    ref = tmp_path / "sync.zarr"
    write_dataset(talos, ref, states=6000, chunk=100, seed=3, quantities=["M", "dtau_dq", "dtau_dv"],
                  scheduler="sync", robot="talos_full_v2")
    assert_same(out, ref)


def test_bad_requests_are_refused_before_any_work(tmp_path: Path, reference: Path) -> None:
    cases = [
        (["--quantities", "tau,torque"], "--quantities: unknown 'torque'; expected"),
        (["--out", tmp_path / "missing" / "x.zarr"], "the folder"),
    ]
    for extra, words in cases:
        args = ["panda", "--states", "100", "--out", tmp_path / "new.zarr", *extra]
        p = cli(*args)
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not (tmp_path / "new.zarr").exists()
    a_file = tmp_path / "file.zarr"
    a_file.write_text("not a store")
    p = cli("panda", "--states", "100", "--out", a_file)
    assert p.returncode == 2 and "is not a directory" in p.stderr
    # an existing dataset with other settings is not touched
    before = arrays(reference)
    p = cli("panda", "--states", "1000", "--chunk", "150", "--seed", "8", "--quantities", "tau,M,ddq,dtau_dq",
            "--out", reference, "--scheduler", "sync")
    assert p.returncode == 2 and "seed: 7 there, 8 now" in p.stderr
    after = arrays(reference)
    assert all(np.array_equal(before[k], after[k]) for k in before)
    p = cli("no_such_robot", "--states", "10", "--out", tmp_path / "r.zarr")
    assert p.returncode == 2 and "unknown robot" in p.stderr
    p = cli("panda", "--states", "0", "--out", tmp_path / "r.zarr")
    assert p.returncode == 2 and "positive integer" in p.stderr
    p = cli("panda", "--states", "10", "--seed", "-1", "--out", tmp_path / "n.zarr", "--scheduler", "sync")
    assert p.returncode == 2 and "--seed: expected a non-negative integer" in p.stderr
    assert not (tmp_path / "n.zarr").exists()
    p = cli("panda", "--states", "10", "--out", tmp_path / "a.zarr", "--scheduler", "not:an-address", timeout=60)
    assert p.returncode == 2 and "no Dask scheduler answers" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not (tmp_path / "a.zarr").exists()
    p = cli("panda", "--states", "10", "--out", tmp_path / "s.zarr", "--scheduler", "tcp://127.0.0.1:9", timeout=60)
    assert p.returncode == 2 and "no Dask scheduler answers" in p.stderr, p.stderr
    assert not (tmp_path / "s.zarr").exists()


INTERRUPTED = re.compile(r"^interrupted: (\d+) of (\d+) chunks kept; run the same command again to resume$")


def _interrupted_line(stderr: str) -> tuple[int, int]:
    """The one ``interrupted: N of M chunks kept …`` line of ``stderr``, whatever else it holds (progress)."""
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    matches = [m for m in map(INTERRUPTED.match, stderr.splitlines()) if m]
    assert len(matches) == 1, stderr
    return int(matches[0][1]), int(matches[0][2])


def test_ctrl_c_stops_the_workers_keeps_the_finished_chunks_and_a_rerun_resumes(tmp_path: Path) -> None:
    """Ctrl-C in a terminal: SIGINT to the whole process group (the command and its Dask worker processes)."""
    args = ["talos_full_v2", "--states", "4000", "--chunk", "100", "--seed", "5", "--quantities", "M,dtau_dq,dtau_dv",
            "--workers", "2"]
    out = tmp_path / "ctrl_c.zarr"
    proc = subprocess.Popen([sys.executable, "-m", "featherdyn", "dataset", *args, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
        done_dir = out / "done"
        if done_dir.exists() and sum(1 for f in done_dir.rglob("*") if f.is_file() and f.name != "zarr.json") >= 3:
            os.killpg(proc.pid, signal.SIGINT)
            break
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    kept, total = _interrupted_line(stderr)
    assert total == 40 and 3 <= kept < 40
    assert arrays(out)["done"].sum() == kept  # the line tells the truth about the store
    assert stdout == ""
    assert not [p for p in _worker_processes_of_group(proc.pid)], "worker processes outlived the command"
    p = cli(*args[:-2], "--out", out, "--scheduler", "sync")
    assert p.returncode == 0, p.stderr
    assert f"{40 - kept} chunks computed, {kept} already done" in p.stdout
    assert arrays(out)["done"].all()


def _worker_processes_of_group(pgid: int) -> list[psutil.Process]:
    """The live processes of the process group ``pgid`` (zombies, already exited, left out)."""
    return [p for p in psutil.process_iter(["pid", "status"]) if _pgid(p.pid) == pgid and
            p.info["status"] != psutil.STATUS_ZOMBIE]


def _pgid(pid: int) -> int | None:
    try:
        return os.getpgid(pid)
    except OSError:
        return None


def test_ctrl_c_in_this_process_one_line_and_exit_130(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    """``--scheduler sync``: the KeyboardInterrupt arrives inside the fourth chunk's computation."""
    from featherdyn.tools import cli as cli_module
    from featherdyn.tools import dataset

    real, calls = dataset._write_chunk, []

    def interrupted_on_the_fourth(model: fd.Model, spec: DatasetSpec, k: int) -> int:
        calls.append(k)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(model, spec, k)

    monkeypatch.setattr(dataset, "_write_chunk", interrupted_on_the_fourth)
    out = tmp_path / "sync.zarr"
    argv = ["dataset", "panda", "--states", "1000", "--chunk", "100", "--out", str(out), "--scheduler", "sync"]
    assert cli_module.main(argv) == 130
    captured = capsys.readouterr()
    assert _interrupted_line(captured.err) == (3, 10) and captured.out == ""
    monkeypatch.setattr(dataset, "_write_chunk", real)
    assert cli_module.main(argv) == 0
    assert "7 chunks computed, 3 already done" in capsys.readouterr().out
