"""`featherdyn verify`, `info` and `list` end to end, as a user runs them (subprocess)."""

from __future__ import annotations

import json
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest


def run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "featherdyn", *args], capture_output=True, text=True, timeout=600,
                          cwd=cwd)


def test_default_run_passes_and_prints_the_table(tmp_path: Path) -> None:
    res = run("verify", "--json", str(tmp_path / "r.json"), "--report", str(tmp_path / "r.html"))
    assert res.returncode == 0, res.stdout + res.stderr
    assert "featherdyn verify panda" in res.stdout
    for quantity in ("rnea vs pin.rnea", "crba vs pin.crba", "aba vs pin.aba", "X.apply(force) vs SE3.act(Force)",
                     "Ṁ − 2C skew-symmetric", "frame_jacobian"):
        assert quantity in res.stdout
    assert " 0 failed" in res.stdout
    data = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert data["passed"] is True and data["meta"]["robot"] == "panda"
    assert len(data["results"]) > 100 and all(r["passed"] for r in data["results"])
    assert all(r["max_rel"] <= r["tol"] for r in data["results"] if isinstance(r["max_rel"], float))

    class Collector(HTMLParser):
        def __init__(self) -> None:
            super().__init__()
            self.tags: list[str] = []

        def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
            self.tags.append(tag)

    html = (tmp_path / "r.html").read_text(encoding="utf-8")
    parser = Collector()
    parser.feed(html)
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    assert "svg" in parser.tags and "table" in parser.tags and "script" not in parser.tags  # offline, no JS
    assert "http://" not in html.replace("http://www.w3.org/2000/svg", "")  # nothing fetched from the network


def test_floating_base_robot() -> None:
    res = run("verify", "solo12", "--floating-base", "--samples", "3")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "floating base" in res.stdout and "nv=18" in res.stdout


def test_same_seed_same_report(tmp_path: Path) -> None:
    outs = []
    for k in range(2):
        res = run("verify", "two_link_arm", "--samples", "2", "--seed", "7", "--json", str(tmp_path / f"{k}.json"))
        assert res.returncode == 0, res.stderr
        outs.append(json.loads((tmp_path / f"{k}.json").read_text())["results"])
    assert outs[0] == outs[1]


@pytest.mark.parametrize(
    "args, message",
    [
        (("verify", "--samples", "0"), "positive integer"),
        (("verify", "--tol", "nan"), "positive finite"),
        (("verify", "no_such_robot_xyz"), "unknown robot"),
        (("verify", "pandaa"), "did you mean"),
        (("verify", "/nonexistent/robot.urdf"), "not found"),
        (("verify", "/dev/zero"), "'/dev/zero' is not a regular file (a device or a pipe)"),
        (("frobnicate",), "invalid choice"),
        (("verify", "panda", "--all"), "either"),
        (("verify", "panda", "--scheduler", "local"), "give --all as well"),
        (("verify", "--all", "--scheduler", "tcp://127.0.0.1:9"), "no Dask scheduler answers"),
    ],
)
def test_bad_arguments_exit_2_with_a_message(args: tuple[str, ...], message: str) -> None:
    res = run(*args)
    assert res.returncode == 2, res.stdout + res.stderr
    assert message in res.stderr
    assert "Traceback" not in res.stderr


HOSTILE = """<?xml version="1.0"?>
<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">]>
<robot name="bomb"><link name="&lol2;"/></robot>
"""


def test_hostile_urdf_is_a_clean_error(tmp_path: Path) -> None:
    path = tmp_path / "bomb.urdf"
    path.write_text(HOSTILE, encoding="utf-8")
    res = run("verify", str(path))
    assert res.returncode == 2
    assert "bomb.urdf" in res.stderr and "Traceback" not in res.stderr


def test_unwritable_report_is_a_usage_error(tmp_path: Path) -> None:
    res = run("verify", "two_link_arm", "--samples", "1", "--json", str(tmp_path / "missing_dir" / "r.json"))
    assert res.returncode == 2 and "cannot write" in res.stderr


def test_info_and_list() -> None:
    res = run("info", "panda")
    assert res.returncode == 0, res.stderr
    assert "nq=9" in res.stdout and "panda_joint1" in res.stdout and "kinematic tree" in res.stdout
    assert "frames" in res.stdout
    res = run("list")
    assert res.returncode == 0
    names = res.stdout.split()
    assert "panda" in names and "solo12" in names and "two_link_arm" in names
    assert len(names) == len(set(names))


def test_a_mismatch_exits_1(tmp_path: Path) -> None:
    # a tolerance no floating-point computation can meet forces a reported mismatch, not a crash
    res = run("verify", "two_link_arm", "--samples", "2", "--tol", "1e-300")
    assert res.returncode == 1, res.stdout + res.stderr
    assert "FAIL" in res.stdout


def test_a_one_dof_urdf(tmp_path: Path) -> None:
    from test_cli_first_use import ONE_DOF

    (tmp_path / "one.urdf").write_text(ONE_DOF, encoding="utf-8")
    res = run("verify", str(tmp_path / "one.urdf"), "--samples", "2")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "Traceback" not in res.stderr


def test_all_passes_and_shows_progress(tmp_path: Path) -> None:
    res = run("verify", "--all", "--json", str(tmp_path / "all.json"))
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    assert "[1/" in res.stderr and "robots" in res.stderr.splitlines()[0]
    assert "FAIL" not in res.stdout


def test_all_spread_over_two_dask_workers_gives_the_serial_report(tmp_path: Path) -> None:
    """``--all --scheduler local``: the robots run on worker processes; the reports are the serial run's."""
    serial = run("verify", "--all", "--samples", "2", "--json", str(tmp_path / "serial.json"))
    spread = run("verify", "--all", "--samples", "2", "--scheduler", "local", "--workers", "2",
                 "--json", str(tmp_path / "spread.json"))
    assert spread.returncode == serial.returncode == 0, spread.stderr[-3000:]
    assert spread.stdout.replace("spread.json", "serial.json") == serial.stdout
    a = json.loads((tmp_path / "serial.json").read_text())["reports"]
    b = json.loads((tmp_path / "spread.json").read_text())["reports"]
    assert len(a) == len(b) > 60
    for x, y in zip(a, b, strict=True):
        assert [(r["quantity"], r["max_abs"], r["max_rel"]) for r in x["results"]] == \
               [(r["quantity"], r["max_abs"], r["max_rel"]) for r in y["results"]]


def test_a_tolerance_below_round_off_is_named_not_blamed_on_a_convention() -> None:
    res = run("verify", "panda", "--samples", "2", "--tol", "1e-18")
    assert res.returncode == 1, res.stdout + res.stderr
    summary = res.stdout.strip().splitlines()[-1]
    assert "round-off" in summary
    assert "gravity" not in summary and "triangle" not in summary, summary


def test_contacts_compare_constrained_dynamics_with_pinocchio() -> None:
    import subprocess
    import sys

    res = subprocess.run([sys.executable, "-m", "featherdyn", "verify", "solo12", "--floating-base", "--samples", "3",
                          "--contacts", "FL_FOOT,HR_FOOT"], capture_output=True, text=True, timeout=600, check=False)
    assert res.returncode == 0, res.stdout + res.stderr
    rows = [ln for ln in res.stdout.splitlines() if ln.startswith("contacts")]
    # per setup (3D points, one 6D): q̈, forces, v⁺, and the ten derivative matrices of Pinocchio's two functions
    assert len(rows) == 2 * (3 + 10) and all(ln.rstrip().endswith("pass") for ln in rows), rows
    assert sum("computeConstraintDynamicsDerivatives" in ln for ln in rows) == 12, rows
    bad = subprocess.run([sys.executable, "-m", "featherdyn", "verify", "panda", "--contacts", "no_such_frame"],
                         capture_output=True, text=True, timeout=600, check=False)
    assert bad.returncode == 2 and "no_such_frame" in bad.stderr and not bad.stdout, bad.stdout + bad.stderr
