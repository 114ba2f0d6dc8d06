"""Survey every SDFormat model shipped in the installed Python packages: featherdyn against Drake.

Usage (from the repository root, featherdyn and ``drake`` installed)::

    python scripts/sdf_survey.py            # writes docs/sdf-models.md
    python scripts/sdf_survey.py --out -    # the table on stdout

Finds every ``*.sdf`` and ``*.world`` file among the files of the installed
distributions (``importlib.metadata``: Drake's examples, example-robot-data's
Cassie, ... whatever is installed). For each model of each file it loads the
model with ``featherdyn.load_sdf`` and Drake's ``Parser`` and compares them at
a few seeded random configurations: the mass of the bodies not welded to the
world, ``M(q)`` (``CalcMassMatrix``) and the gravity torques
(``−CalcGravityGeneralizedForces``), as relative errors
``max |x − x_drake| / max |x_drake|``. Joints map by name; a free body's
coordinates convert at the boundary (Drake: ``q = [w x y z, p_W]``,
``v = [ω_W; v_W]``; featherdyn: ``q = [p_W, x y z w]``, ``v = [ω_B; v_B]`` in
the body frame, so ``M_fd = Tᵀ M_drake T`` and ``g_fd = Tᵀ g_drake`` with
``T = diag(R, R)``); ball joints are held at the identity (Drake's are
roll-pitch-yaw joints, whose rates equal the angular velocity there). A row
that does not agree says why: the loader's refusal, or Drake's, verbatim.
"""

from __future__ import annotations

import argparse
import importlib.metadata as md
import platform
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

RTOL = 1e-9
SAMPLES = 3
SEED = 0
COMMAND = "python scripts/sdf_survey.py"
DOC = Path(__file__).resolve().parents[1] / "docs" / "sdf-models.md"


def find_files() -> list[tuple[str, Path]]:
    """``(distribution, file)`` for every ``*.sdf`` / ``*.world`` file of the installed distributions."""
    out = []
    seen: set[Path] = set()
    for dist in md.distributions():
        for f in dist.files or ():
            if f.suffix in (".sdf", ".world"):
                path = Path(dist.locate_file(f)).resolve()
                if path.is_file() and path not in seen:
                    seen.add(path)
                    out.append((dist.metadata["Name"], path))
    return sorted(out, key=lambda x: (x[0].lower(), str(x[1])))


def model_names(path: Path) -> list[str]:
    """The names of the models a file offers (``<sdf>``'s and its worlds' ``<model>``\\ s), read with ElementTree."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        return [""]
    names = [m.get("name", "") for m in root.findall("model")]
    names += [m.get("name", "") for w in root.findall("world") for m in w.findall("model")]
    names += ["" for w in root.findall("world") for _ in w.findall("include")]
    return names or [""]


def compare(path: Path, name: str) -> dict[str, Any]:
    """One model: featherdyn and Drake, or the reason one of them refused."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    import featherdyn as fd

    row: dict[str, Any] = {"model": name}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fd.load_sdf(path, model=name or None)
        row["size"] = f"{model.nbodies}/{model.nq}/{model.nv}"
    except fd.SDFError as exc:
        row["fd"] = "refused: " + str(exc).replace(str(path), path.name)  # (the table shows the path)
        model = None
    try:
        plant = MultibodyPlant(0.0)
        instances = Parser(plant).AddModels(str(path))
        plant.Finalize()
    except Exception as exc:  # Drake's parser raises RuntimeError with its message
        row["drake"] = "refused: " + str(exc).split("\n")[0].replace("/" + str(path), path.name).replace(
            str(path), path.name)
        return row
    if model is None:
        return row
    try:
        instance = next(i for i in instances if plant.GetModelInstanceName(i) == model.name)
    except StopIteration:
        row["drake"] = f"no model instance {model.name!r}"
        return row
    context = plant.CreateDefaultContext()
    # each featherdyn joint's Drake slots: (kind, featherdyn q slice, Drake q indices, Drake v indices, v start)
    slots: list[tuple[str, slice, list[int], list[int], int]] = []
    for i, (joint, jname) in enumerate(zip(model.joints, model.joint_names, strict=True)):
        sq = slice(model.idx_q[i], model.idx_q[i] + joint.nq)
        if joint.kind == "free_flyer":
            body = plant.GetBodyByName(model.body_names[i], instance)
            s, v = body.floating_positions_start(), body.floating_velocities_start_in_v()
            slots.append((joint.kind, sq, list(range(s, s + 7)), list(range(v, v + 6)), model.idx_v[i]))
            continue
        base, _, axis = jname.partition("/axis")  # a universal joint's two featherdyn joints: J/axis, J/axis2
        dj = plant.GetJointByName(base.split("::")[-1], instance)
        k = 1 if axis == "2" else 0
        qs, vs = dj.position_start() + k, dj.velocity_start() + k
        slots.append((joint.kind, sq, list(range(qs, qs + min(joint.nq, 3))), list(range(vs, vs + joint.nv)),
                      model.idx_v[i]))
    v_index = [v for *_, vi, _ in slots for v in vi]
    mass_fd = model.total_mass
    mass_drake = sum(plant.get_body(b).default_mass() for b in plant.GetBodyIndices(instance)
                     if not plant.IsAnchored(plant.get_body(b)))
    errors = {"mass": abs(mass_fd - mass_drake) / max(abs(mass_drake), 1e-300)}
    rng = np.random.default_rng(SEED)
    err_M = err_g = 0.0
    for _ in range(SAMPLES if model.nv else 0):
        q = np.asarray(fd.random_configuration(model, rng), dtype=float)
        q_drake = np.zeros(plant.num_positions())
        T = np.eye(model.nv)
        for kind, sq, qi, _, v0 in slots:
            if kind == "free_flyer":
                x, y, z, qx, qy, qz, qw = q[sq]
                q_drake[qi] = [qw, qx, qy, qz, x, y, z]
                R = fd.rotation.quat_to_matrix(np.array([qx, qy, qz, qw]))
                T[v0:v0 + 3, v0:v0 + 3] = R
                T[v0 + 3:v0 + 6, v0 + 3:v0 + 6] = R
            elif kind == "spherical":
                q[sq] = [0.0, 0.0, 0.0, 1.0]  # Drake's roll-pitch-yaw at zero: rates = angular velocity
            else:
                q_drake[qi] = q[sq]
        plant.SetPositions(context, q_drake)
        M = plant.CalcMassMatrix(context)[np.ix_(v_index, v_index)]
        g = -plant.CalcGravityGeneralizedForces(context)[v_index]
        M_drake, g_drake = T.T @ M @ T, T.T @ g
        err_M = max(err_M, float(np.abs(fd.crba(model, q) - M_drake).max() / max(np.abs(M_drake).max(), 1e-300)))
        gd = np.abs(g_drake).max()
        err_g = max(err_g, float(np.abs(fd.generalized_gravity(model, q) - g_drake).max() / gd) if gd > 0 else 0.0)
    errors["M"], errors["gravity"] = err_M, err_g
    row["errors"] = errors
    if sorted(v_index) != list(range(plant.num_velocities())) and len(instances) == 1:
        row["note"] = "the joints do not cover Drake's velocities"
    return row


def _fmt(row: dict[str, Any]) -> tuple[str, str]:
    if "errors" in row:
        e = row["errors"]
        worst = max(e.values())
        verdict = "agrees" if worst <= RTOL else "DISAGREES"
        return f"{verdict} (mass {e['mass']:.1e}, M {e['M']:.1e}, gravity {e['gravity']:.1e})", row.get("note", "")
    reasons = [row[k] for k in ("fd", "drake") if k in row]
    if "fd" in row and "drake" in row:
        return "both refuse", f"featherdyn {row['fd']}; Drake {row['drake']}"
    return ("featherdyn refuses" if "fd" in row else "Drake refuses"), "; ".join(reasons)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=str(DOC), help="the Markdown file to write ('-': stdout)")
    args = parser.parse_args(argv)
    import featherdyn as fd

    rows = []
    for dist, path in find_files():
        for name in model_names(path):
            row = compare(path, name)
            rows.append((dist, path, row))
    agree = sum(1 for *_, r in rows if "errors" in r and max(r["errors"].values()) <= RTOL)
    compared = sum(1 for *_, r in rows if "errors" in r)
    both = sum(1 for *_, r in rows if "fd" in r and "drake" in r)
    lines = [
        "# SDFormat models: featherdyn against Drake",
        "",
        f"Generated by `{COMMAND}` (featherdyn {fd.__version__}, Drake {md.version('drake')}, "
        f"Python {platform.python_version()}). Every `*.sdf` / `*.world` file of the installed distributions; "
        "each model loaded by `fd.load_sdf` and by Drake's `Parser`, compared at "
        f"{SAMPLES} seeded random configurations: the mass of the bodies not welded to the world, `M(q)` "
        "(`CalcMassMatrix`) and the gravity torques (`−CalcGravityGeneralizedForces`), as the largest relative "
        f"error `max|x − x_drake| / max|x_drake|`; agreement: {RTOL:g}. Joints map by name; free bodies convert "
        "(Drake `q = [w x y z, p]`, `v = [ω_W; v_W]`; featherdyn `q = [p, x y z w]`, `v = [ω; v]` in the body "
        "frame); ball joints are held at the identity.",
        "",
        f"**Summary: {len(rows)} models in {len({p for _, p, _ in rows})} files; both load {compared}, featherdyn "
        f"agrees with Drake on {agree}; both refuse {both}; one refuses: {len(rows) - compared - both}.** "
        "Each refusal is quoted in the last column.",
        "",
        "| package | model file | model | nbody/nq/nv | featherdyn vs Drake | reason |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for dist, path, row in rows:
        verdict, reason = _fmt(row)
        short = "/".join(path.parts[-3:])
        reason = reason.replace("|", "\\|").replace("\n", " ")
        lines.append(f"| {dist} | {short} | {row['model'] or '(the only one)'} | {row.get('size', '')} | {verdict} | "
                     f"{reason} |")
    text = "\n".join(lines) + "\n"
    if args.out == "-":
        sys.stdout.write(text)
    else:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
