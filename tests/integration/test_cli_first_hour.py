"""The small rough edges a new user met in the first hour (issue 32, item 12), each as the user sees it.

The command line's output through :func:`featherdyn.tools.cli.main` (captured) or a subprocess; the
README's claims against what the commands print.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_verify_help_does_not_promise_minutes(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main(["verify", "--help"])
    assert stop.value.code == 0
    found = re.search(r"^\s+--all\s+(.*?)^\s+--", capsys.readouterr().out, flags=re.S | re.M)
    assert found, "no --all in verify's help"
    all_help = " ".join(found[1].split())
    assert "minutes" not in all_help.replace("not minutes", "") and " s " in all_help, all_help


def test_verify_all_ends_with_totals_and_says_why_counts_differ(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("pinocchio")
    assert main(["verify", "--all", "--samples", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [ln.split() for ln in out if re.match(r"^\S+\s+\d+\s+\d+\s+\S+e[-+]\d\d\s", ln)]
    assert len(rows) == len(fd.list_robots())
    checks = sum(int(r[1]) for r in rows)
    n = len(rows)
    assert out[-1] == (f"total: {n} robots: {n} compared, {n} agree, 0 disagree, 0 refused by the oracle; "
                       f"{checks} checks, all passed"), out[-1]
    assert len({int(r[1]) for r in rows}) > 1  # the counts do differ, so the output must say why
    assert any("number of checks follows the robot" in ln for ln in out)
    for r in rows:  # a worst error above the default tolerance passed on a scaled one, and says so
        worst, tol = float(r[3]), float(r[4])
        assert worst <= tol or (worst <= 1e-9 * 1e12 and "cond(M)" in " ".join(r[5:])), r


def test_a_pass_on_the_cond_scaled_tolerance_is_named_and_the_columns_explained() -> None:
    pytest.importorskip("pinocchio")
    from featherdyn import verify

    table = verify.run("icub", samples=2).to_table()
    summary = table.strip().splitlines()[-1]
    assert re.search(r"\d+ of the passes on a tolerance scaled by cond\(M\)", summary), summary
    assert "worst: the random state" in table and "max rel err: " in table


def test_the_cli_points_to_featherdyn_list(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", "talos"]) == 2
    err = capsys.readouterr().err
    assert "`featherdyn list`" in err and "talos_full_v2" in err, err


def test_list_hints_at_floating_base_on_stderr_and_keeps_stdout_to_names(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["list"]) == 0
    captured = capsys.readouterr()
    assert captured.out.split() == fd.list_robots()
    assert "--floating-base" in captured.err and "solo12" in captured.err


def test_info_is_titled_with_the_robot_asked_for(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", "solo12"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("solo12: the model 'solo' ("), first


def test_bench_says_which_chain_it_is_timing() -> None:
    pytest.importorskip("pinocchio")
    res = subprocess.run([sys.executable, "-m", "featherdyn", "bench", "panda", "--chains", "8,16", "--repeats", "1",
                          "--batch", "2", "--no-compile-times"], capture_output=True, text=True, timeout=300,
                         check=False)
    assert res.returncode == 0, res.stderr
    assert "[1/2] a chain of 8 links" in res.stderr and "[2/2] a chain of 16 links" in res.stderr, res.stderr
    assert "| 16 |" in res.stdout


def test_one_comparison_is_singular(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    m = fd.load_robot("two_link_arm")
    q, v, a = fd.neutral(m), np.zeros(m.nv), np.ones(m.nv)
    np.savez(tmp_path / "one.npz", q=q, v=v, a=a, tau=fd.rnea(m, q, v, a))
    assert main(["check", str(tmp_path / "one.npz"), "--robot", "two_link_arm"]) == 0
    out = capsys.readouterr().out
    assert "the 1 comparison agrees" in out and "all 1 " not in out, out


def test_dataset_one_chunk_single_prefix_and_a_resumed_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("zarr")
    argv = ["dataset", "two_link_arm", "--states", "50", "--chunk", "50", "--out", str(tmp_path / "d.zarr")]
    assert main(argv) == 0
    first = capsys.readouterr()
    assert "1 chunk computed" in first.out and "1/1 chunk," in first.err, first
    assert not re.search(r"(?<![\d.])1 chunks", first.out + first.err), first  # (not the rate "14.1 chunks/s")
    assert "featherdyn: featherdyn" not in first.err and "featherdyn dataset:" not in first.err, first.err
    assert "scheduler sync (--scheduler auto:" in first.err, first.err  # one chunk: nothing to spread
    assert main(argv) == 0
    again = capsys.readouterr().out
    assert "0 chunks computed, 1 already done; nothing left to compute" in again and "states/s" not in again, again


def test_the_default_scheduler_follows_the_machine() -> None:
    from featherdyn.tools.dataset import LOCAL_MIN_CORES, choose_scheduler

    assert choose_scheduler(100, None, 2)[0] == "sync"  # measured: sync twice as fast on two cores
    assert choose_scheduler(100, None, LOCAL_MIN_CORES)[0] == "local"
    assert choose_scheduler(2, None, 8)[0] == "sync"  # fewer chunks than cores
    assert choose_scheduler(100, 2, 2)[0] == "local"  # --workers asks for worker processes
    assert all(why for why in (choose_scheduler(n, w, c)[1] for n in (1, 100) for w in (None, 2) for c in (1, 2, 8)))


def test_readme_robots_exist_and_its_sentences_are_current(request: pytest.FixtureRequest) -> None:
    robots = set(fd.list_robots())
    assert not re.search(r"\btalos\b", README), "README names a robot `talos`; `featherdyn list` has talos_full_v2"
    for name in ("panda", "solo12", "talos_full_v2", "go1", "iris"):
        if name in README:
            assert name in robots, name
    assert "cold kernel cache" not in README
    # the suite's size and time (measured: 4 733 tests, 12 min 23 s with -n 2 and 22 min 22 s in one process, on this
    # machine, 2026-11-29); where the whole suite was collected, the count stated is within 5 % of it
    stated = re.search(r"about (\d) (\d{3}) tests\) on one worker process a core \(pytest-xdist's\s+`-n auto`\): "
                       r"12–13 minutes on two cores, 22 minutes in one process", README)
    assert stated, "README's sentence on the test suite's size and time"
    collected = request.session.testscollected
    if collected > 4000:
        assert abs(int(stated[1] + stated[2]) - collected) <= 0.05 * collected, (stated[0], collected)
