"""Mutation fuzzing of the URDF loader: thousands of seeded mutants of real files, each loaded in a subprocess.

The seeds are the library's URDFs (the bundled 2R arm and a few
example-robot-data robots). Each mutant applies one to three random edits:
deleting, duplicating or re-parenting elements, swapping attribute values,
hostile numbers (NaN, inf, 1e308, subnormals, garbage, 12 000 digits), long
strings, renamed or unknown links (cycles, two parents), deep nesting, DTDs
and entities, XInclude, truncation, stray characters and bytes, encodings.

The mutants run in worker subprocesses (``_urdf_fuzz_worker.py``), many per
worker, with a time limit: a worker that crashes or hangs names the mutant it
was on, and a fresh worker takes the rest. The test asserts, for every mutant:

* the load succeeds (with featherdyn warnings only) or raises ``URDFError``,
  whose message starts with the source and is short (values are quoted at
  most 100 characters each);
* no crash and no hang;
* a model that loaded without any warning gives finite RNEA, CRBA and ABA at a
  random finite state, or a featherdyn error (a singular mass matrix), and no
  numpy warning on the way.

Everything is seeded: a failure names the mutant's id, and
``_mutants()[id]`` rebuilds it. ``FEATHERDYN_URDF_FUZZ=2000,1,compiled`` runs
2000 mutants per seed file from random seed 1, the dynamics on the compiled
engine (CI: 500 per file, seed 16, the reference algorithms).
"""

from __future__ import annotations

import copy
import json
import os
import random
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

import featherdyn as fd

WORKER = Path(__file__).with_name("_urdf_fuzz_worker.py")
#: Mutants per seed file, the random seed and the dynamics backend; another run:
#: FEATHERDYN_URDF_FUZZ=<per seed>,<seed>[,<backend>]. CI keeps "reference": the compiled engine's
#: first compilation takes minutes, longer than the worker's hang limit.
_SPEC = os.environ.get("FEATHERDYN_URDF_FUZZ", "500,16").split(",")
PER_SEED, RANDOM_SEED, BACKEND = int(_SPEC[0]), int(_SPEC[1]), (_SPEC[2] if len(_SPEC) > 2 else "reference")
#: Parallel workers (the CI machines have 2 cores).
WORKERS = 2
#: A single mutant taking longer than this counts as a hang.
HANG_SECONDS = 20.0
#: Longest URDFError message accepted (several names quoted at most 100 characters each, plus the text).
MAX_MESSAGE = 2000

NEST = "nest"
SEED_ROBOTS = ("two_link_arm", "double_pendulum_continuous", "TwoDofs", "ur5_robot", "panda", "solo12")

NUMBERS = [
    "nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1.7976931348623157e308", "1e999", "1e155", "-1e154", "1e101",
    "1e61", "1e60", "1e100", "-1e100", "1e-320", "5e-324", "1e-300", "0", "-0", "-1", "-1e-9", "1e-12", "", "   ",
    "abc", "0x10", "1_0", "1,2", "+-1", "1e", ".", "-.5e+3", "\u0663", "1" * 12_000, "1" * 9_999 + "x",
    "9" * 400, "0." + "0" * 5000 + "1",
]
MAGNITUDES = [1e-320, 1e-300, 1e-120, 1e-99, 1e40, 1e59, 1e61, 1e99, 1e150, 1e200, 1e300]
NAMES = ["", " ", "root_joint", "root_joint_1", "world", "n" * 12_000, "ü\u0301", "a'b\"c", "<&>", "\t"]
TEXT_INSERTS = ["&", "<", ">", "]]>", "&#0;", "&#xD800;", "&lol;", "<!-- x", "\x00", "\ufffe", "<?pi x?>", "'\""]
PROLOGUES = [
    "\n  \t", "\ufeff", "\ufeff\n ",
    '<!DOCTYPE robot [<!ENTITY x "y">]>',
    '<!DOCTYPE robot SYSTEM "file:///etc/passwd">',
    '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>',
]


def _seed_texts() -> dict[str, str]:
    from featherdyn.robots import robot_path

    out = {}
    for name in SEED_ROBOTS:
        try:
            out[name] = Path(robot_path(name)).read_text(encoding="utf-8")
        except (fd.errors.ModelError, fd.errors.MissingDependencyError):
            continue  # example-robot-data is a test dependency; without it the bundled arm alone is fuzzed
    return out


# ---------------------------------------------------------------------------
# mutations
# ---------------------------------------------------------------------------


def _elements(root: ET.Element) -> list[tuple[ET.Element, ET.Element]]:
    """``(parent, element)`` for every element below the root."""
    return [(p, c) for p in root.iter() for c in p]


def _attributes(root: ET.Element) -> list[tuple[ET.Element, str]]:
    return [(e, k) for e in root.iter() for k in e.attrib]


def _hostile_number(rng: random.Random, old: str) -> str:
    choice = rng.random()
    if choice < 0.6:
        value = rng.choice(NUMBERS)
    elif choice < 0.8:
        value = f"{rng.choice([-1, 1]) * rng.random():.6g}e{rng.randint(-330, 330)}"
    else:
        value = repr(rng.uniform(-10, 10))
    parts = old.split()
    if len(parts) > 1 and rng.random() < 0.7:  # one component of a list
        parts[rng.randrange(len(parts))] = value
        return " ".join(parts)
    return value


def _is_float(text: str | None) -> bool:
    try:
        float(text or "")
    except ValueError:
        return False
    return True


def _mutate_tree(rng: random.Random, root: ET.Element) -> None:
    kind = rng.randrange(14)
    elements = _elements(root)
    attributes = _attributes(root)
    links = [e.get("name", "") for e in root.iter("link")]
    if kind == 0 and elements:  # delete an element
        parent, elem = rng.choice(elements)
        parent.remove(elem)
    elif kind == 1 and elements:  # duplicate an element
        parent, elem = rng.choice(elements)
        parent.insert(rng.randrange(len(parent) + 1), copy.deepcopy(elem))
    elif kind == 2 and len(attributes) > 1:  # swap two attribute values
        (e1, k1), (e2, k2) = rng.sample(attributes, 2)
        v1, v2 = e1.get(k1, ""), e2.get(k2, "")
        e1.set(k1, v2)
        e2.set(k2, v1)
    elif kind in (3, 4, 5) and attributes:  # a hostile number in a numeric attribute
        numeric = [(e, k) for e, k in attributes if k not in ("name", "link", "type", "joint", "filename")]
        elem, key = rng.choice(numeric or attributes)
        elem.set(key, _hostile_number(rng, elem.get(key, "")))
    elif kind == 6:  # re-point a joint: cycles, two parents, self-loops, unknown links
        ends = list(root.iter("parent")) + list(root.iter("child"))
        if ends:
            target = rng.choice(links + [*NAMES, "no_such_link"]) if links else "x"
            rng.choice(ends).set("link", target)
    elif kind == 7 and attributes:  # rename, drop or blank an attribute
        elem, key = rng.choice(attributes)
        action = rng.randrange(3)
        if action == 0:
            elem.set(key, rng.choice(NAMES + links[:3]))
        elif action == 1:
            del elem.attrib[key]
        else:
            elem.set(key, rng.choice(["x" * 20_000, "x" * 10_000, "y" * 200]))
    elif kind == 8:  # change a joint's type
        joints = list(root.iter("joint"))
        if joints:
            rng.choice(joints).set("type", rng.choice(["revolute", "continuous", "prismatic", "fixed", "floating",
                                                       "planar", "spherical", "", "REVOLUTE"]))
    elif kind == 9 and elements:  # deep nesting below an element (written out by _expand_nesting)
        _, elem = rng.choice(elements)
        ET.SubElement(elem, f"{NEST}{rng.choice([50, 400, 998, 1001, 3000])}")
    elif kind == 10:  # a new link and joint hanging anywhere (or nowhere)
        name = rng.choice([f"new{rng.randrange(5)}", *links[:2], *NAMES])
        ET.SubElement(root, "link", {"name": name})
        j = ET.SubElement(root, "joint", {"name": rng.choice(["jn", "root_joint", *NAMES]),
                                          "type": rng.choice(["revolute", "fixed", "prismatic"])})
        ET.SubElement(j, "parent", {"link": rng.choice(links + [name]) if links else name})
        ET.SubElement(j, "child", {"link": rng.choice([name, *links[:3]])})
        if rng.random() < 0.5:
            ET.SubElement(j, "limit", {"lower": "-1", "upper": "1"})
        if rng.random() < 0.3:
            ET.SubElement(j, "mimic", {"joint": rng.choice(["jn", "root_joint", "nope"])})
    elif kind == 12:  # a whole robot rescaled: every mass and inertia entry, or every origin, to one magnitude
        magnitude = rng.choice(MAGNITUDES)
        if rng.random() < 0.5:
            for e in list(root.iter("mass")) + list(root.iter("inertia")):
                for key in e.attrib:
                    e.set(key, f"{float(e.get(key, '0') or 0) * magnitude:.17g}" if _is_float(e.get(key)) else "1")
        else:
            for e in root.iter("origin"):
                e.set("xyz", " ".join(f"{rng.uniform(-1, 1) * magnitude:.17g}" for _ in range(3)))
    else:  # foreign, namespaced and XInclude elements
        tag = rng.choice(["{http://www.w3.org/2001/XInclude}include", "{http://example.org/x}link", "gazebo",
                          "transmission", "{http://www.w3.org/2003/XInclude}include"])
        ET.SubElement(root, tag, {"href": "/etc/passwd", "name": "t"})


def _expand_nesting(xml: str) -> str:
    """Write each nesting placeholder ``<nestN>`` as N nested elements (ElementTree would recurse to write them)."""
    xml = re.sub(rf"<{NEST}(\d+) />", lambda m: "<x>" * int(m[1]) + "</x>" * int(m[1]), xml)
    xml = re.sub(rf"<{NEST}(\d+)>", lambda m: "<x>" * int(m[1]), xml)
    return re.sub(rf"</{NEST}(\d+)>", lambda m: "</x>" * int(m[1]), xml)


def _mutate_text(rng: random.Random, text: str) -> str:
    kind = rng.randrange(5)
    if kind == 0:  # truncation
        return text[: rng.randrange(len(text) + 1)]
    if kind == 1:  # stray characters
        k = rng.randrange(len(text) + 1)
        return text[:k] + rng.choice(TEXT_INSERTS) + text[k:]
    if kind == 2:  # a prologue: whitespace, BOM, DTDs and entities
        decl, _, body = text.partition("?>") if text.startswith("<?xml") else ("", "", text)
        decl = decl + "?>" if decl else ""
        prologue = rng.choice(PROLOGUES)
        return (prologue + decl + body) if rng.random() < 0.5 or not decl else (decl + prologue + body)
    if kind == 3:  # an entity reference in an attribute
        return text.replace('name="', 'name="&x;', 1)
    return text.replace("<robot", '<robot xmlns="http://example.org/urdf"', 1)


def _mutants() -> list[dict[str, Any]]:
    seeds = _seed_texts()
    rng = random.Random(RANDOM_SEED)
    out: list[dict[str, Any]] = []
    for seed_name, text in seeds.items():
        base = ET.fromstring(text)
        for _ in range(PER_SEED):
            root = copy.deepcopy(base)
            for _ in range(rng.choice([1, 1, 2, 3])):
                _mutate_tree(rng, root)
            xml = _expand_nesting(ET.tostring(root, encoding="unicode"))
            if rng.random() < 0.1:
                xml = '<?xml version="1.0" encoding="utf-8"?>\n' + xml
            if rng.random() < 0.2:
                xml = _mutate_text(rng, xml)
            job: dict[str, Any] = {"id": len(out), "seed": seed_name, "floating_base": rng.random() < 0.3,
                                   "backend": BACKEND}
            if rng.random() < 0.1:  # as bytes, in some encoding (possibly a wrong one)
                encoding = rng.choice(["utf-8", "utf-16", "utf-16-le", "latin-1", "utf-32"])
                job["xml_bytes"] = xml.encode(encoding, errors="replace").decode("latin-1")
            else:
                job["xml"] = xml
            out.append(job)
    return out


# ---------------------------------------------------------------------------
# running the workers
# ---------------------------------------------------------------------------


def _run_shard(jobs: list[dict[str, Any]], tmp: Path) -> list[dict[str, Any]]:
    """Outcomes of ``jobs`` in order; a crash or hang is the outcome of the mutant the worker was on."""
    # the workers import the featherdyn this test imported; one BLAS thread each (there are WORKERS of them)
    package_root = str(Path(fd.__file__).resolve().parents[1])
    pythonpath = os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH", "")) if p)
    env = dict(os.environ, PYTHONPATH=pythonpath, PYTHONHASHSEED="0", OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    results: list[dict[str, Any]] = []
    while len(results) < len(jobs):
        rest = jobs[len(results):]
        path = tmp / f"jobs_{rest[0]['id']}.jsonl"
        path.write_text("".join(json.dumps(j) + "\n" for j in rest), encoding="utf-8")
        budget = HANG_SECONDS + 0.5 * len(rest)
        proc = subprocess.Popen([sys.executable, str(WORKER), str(path)], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, env=env)
        try:
            stdout, stderr = proc.communicate(timeout=budget)
            why = f"worker exited with status {proc.returncode}"
        except subprocess.TimeoutExpired:
            proc.kill()
            stdout, stderr = proc.communicate()
            why = f"hang: no outcome within {budget:.0f} s"
        done = [json.loads(line) for line in stdout.splitlines() if line.strip()]
        results.extend(done)
        if len(done) < len(rest):  # the worker died or hung on rest[len(done)]
            culprit = rest[len(done)]
            results.append({"id": culprit["id"], "load": "CRASH", "message": f"{why}; stderr: {stderr[-1500:]}",
                            "warnings": [], "dynamics": "skipped", "dynamics_warnings": [], "seconds": 0.0})
    return results


def _run(jobs: list[dict[str, Any]], tmp: Path) -> list[dict[str, Any]]:
    shards = [jobs[k::WORKERS] for k in range(WORKERS)]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(WORKERS) as pool:
        parts = list(pool.map(lambda shard: _run_shard(shard, tmp), shards))
    return sorted((r for part in parts for r in part), key=lambda r: r["id"])


def _problems(job: dict[str, Any], r: dict[str, Any]) -> list[str]:
    label = "<bytes>" if "xml_bytes" in job else "<string>"
    out = []
    if r["load"] not in ("ok", "URDFError"):
        out.append(f"load raised {r['load']}: {r['message'][:300]}")
    if r["load"] == "URDFError":
        if not r["message"].startswith(label + ": "):
            out.append(f"the message does not start with {label!r}: {r['message'][:300]}")
        if r["message_length"] > MAX_MESSAGE:
            out.append(f"a message of {r['message_length']} characters: {r['message'][:300]}")
    foreign = [w for w in r["warnings"] if w != "PhysicalityWarning"]
    if foreign:
        out.append(f"warnings other than featherdyn's: {foreign}")
    if r["dynamics"] != "skipped" and r["dynamics"] != "finite" and not r["dynamics"].startswith("error:"):
        out.append(f"dynamics on a model loaded without warnings: {r['dynamics']}")
    if r["dynamics_warnings"]:
        out.append(f"warnings in the dynamics: {r['dynamics_warnings']}")
    if r["seconds"] > HANG_SECONDS:
        out.append(f"took {r['seconds']:.1f} s")
    return out


@pytest.mark.slow
def test_urdf_mutants_load_or_fail_cleanly(tmp_path: Path) -> None:
    jobs = _mutants()
    assert len(jobs) >= PER_SEED
    start = time.monotonic()
    results = _run(jobs, tmp_path)
    elapsed = time.monotonic() - start
    assert [r["id"] for r in results] == [j["id"] for j in jobs]

    failures = []
    for job, r in zip(jobs, results, strict=True):
        for problem in _problems(job, r):
            failures.append(f"mutant {job['id']} (of {job['seed']}, floating_base={job['floating_base']}): {problem}")
    outcomes = Counter(r["load"] if r["load"] != "ok" else ("ok, warned" if r["warnings"] else "ok") for r in results)
    dynamics = Counter(r["dynamics"] for r in results if r["dynamics"] != "skipped")
    summary = f"{len(jobs)} mutants in {elapsed:.1f} s: {dict(outcomes)}; dynamics {dict(dynamics)}"
    print(summary)
    assert not failures, f"{len(failures)} failures ({summary}):\n" + "\n".join(failures[:30])
    assert outcomes["ok"] > 0 and outcomes["URDFError"] > 0, summary  # the mutants reach both sides


def test_a_mutant_that_kills_the_worker_is_named_and_the_rest_still_run(tmp_path: Path) -> None:
    """The harness itself: a job the worker dies on (no document: a KeyError) is reported as the crash."""
    arm = '<robot name="r"><link name="a"/></robot>'
    jobs = [{"id": 0, "xml": arm, "floating_base": False}, {"id": 1, "floating_base": False},
            {"id": 2, "xml": "<robot/>", "floating_base": True}]
    results = _run_shard(jobs, tmp_path)
    assert [(r["id"], r["load"]) for r in results] == [(0, "ok"), (1, "CRASH"), (2, "URDFError")]
    assert "worker exited with status 1" in results[1]["message"] and "KeyError" in results[1]["message"]
