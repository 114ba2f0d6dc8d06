"""The bodies a loader inserts are not the user's mistakes (issue 32 item 5).

Several joints on one MJCF body become a chain of massless featherdyn bodies ``BODY#0``, ``BODY#1``, ...: the model
names them (:attr:`Model.inserted_bodies`) and the physicality checks of ``featherdyn info`` and ``verify`` pass over
them, while a user's massless body is still reported.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.tools.cli import main
from featherdyn.verify.dynamics import inertia_problem, model_diagnostics

TWO_JOINTS = """<mujoco model="two">
  <worldbody>
    <body name="arm" pos="0 0 1">
      <joint name="yaw" type="hinge" axis="0 0 1"/>
      <joint name="pitch" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_the_mjcf_loader_names_the_bodies_it_inserts() -> None:
    model = fd.load_mjcf(TWO_JOINTS)
    assert model.body_names == ("arm#0", "arm")
    assert model.inserted_bodies == ("arm#0",)
    assert float(model.inertias.mass[0]) == 0.0  # massless by construction
    assert fd.load_mjcf(TWO_JOINTS.replace('<joint name="pitch" type="hinge" axis="0 1 0"/>', "")
                        ).inserted_bodies == ()
    assert fd.load_robot("two_link_arm").inserted_bodies == ()


def test_inserted_bodies_are_not_reported_as_not_physical() -> None:
    model = fd.load_mjcf(TWO_JOINTS)
    diag = model_diagnostics(model)
    assert diag.invalid_inertias == []
    assert [link["valid"] for link in diag.links] == [True, True]
    assert inertia_problem(model, 0) == "" and inertia_problem(model, 1) == ""


def test_a_users_massless_body_is_still_reported_whatever_its_name() -> None:
    b = fd.ModelBuilder("user")
    i = b.add_body("arm#0", -1, fd.RevoluteJoint([0, 0, 1]))  # massless, named like a carrier, but the user's
    b.add_body("arm", i, fd.RevoluteJoint([0, 1, 0]), inertia=fd.SpatialInertia.box(1.0, [0.1, 0.2, 0.3]))
    model = b.build()  # (no massless subtree: its child has mass)
    assert model.inserted_bodies == ()
    assert "mass > 0" in inertia_problem(model, 0)
    assert [name for name, _ in model_diagnostics(model).invalid_inertias] == ["arm#0"]


def test_featherdyn_info_does_not_call_an_inserted_body_not_physical(tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "two.xml"
    path.write_text(TWO_JOINTS, encoding="utf-8")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "NOT PHYSICAL" not in out
    carrier = next(line for line in out.splitlines() if line.strip().startswith("arm#0 "))
    assert "inserted by the loader" in carrier


@pytest.mark.parametrize("env, carriers", [("humanoid", 7), ("pusher", 2)])
def test_the_gymnasium_models_of_the_issue_have_no_false_warnings(env: str, carriers: int) -> None:
    gymnasium = pytest.importorskip("gymnasium")
    path = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / f"{env}.xml"
    with pytest.warns(fd.PhysicalityWarning, match="ignored MJCF elements"):
        model = fd.load_mjcf(path)
    assert len(model.inserted_bodies) == carriers
    assert all(float(model.inertias.mass[model.body_id(n)]) == 0.0 for n in model.inserted_bodies)
    assert model_diagnostics(model, np.zeros((1, model.nq)) + fd.neutral(model)).invalid_inertias == []
