"""The declared kinematics records against Pinocchio, one state: best of 9 interleaved repeats, same process.

Pinocchio's forwardKinematics writes its data and returns nothing; its frame velocity and acceleration are read
after a forwardKinematics with v (and a), as a user calls them.

Usage: ``python benchmarks/bench_records.py`` (needs pin and example-robot-data); prints robot, call, featherdyn
µs, Pinocchio µs and their ratio (benchmarks/results-records-2026-11-29.md).
"""

from __future__ import annotations

import timeit
import warnings

import numpy as np
import pinocchio as pin

import featherdyn as fd
from featherdyn.robots import robot_path
from featherdyn.verify.bridge import JointMap

N = 20000


def bench_robot(name: str, floating: bool) -> None:
    """Each call on one robot: featherdyn's and Pinocchio's times and their ratio, printed."""
    m = fd.load_robot(name, floating_base=floating)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = str(robot_path(name))
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    pd = pm.createData()
    rng = np.random.default_rng(0)
    q, v = fd.random_configuration(m, rng), rng.normal(size=m.nv)
    jm = JointMap(m, pm)
    qp, vp = jm.q_to_pin(q), jm.v_to_pin(v)
    frame = m.frames[-1].name
    fid = pm.getFrameId(frame)
    calls = [
        ("frame_placement", lambda: fd.frame_placement(m, q, frame),
         lambda: (pin.forwardKinematics(pm, pd, qp), pin.updateFramePlacement(pm, pd, fid))),
        ("forward_kinematics", lambda: fd.forward_kinematics(m, q), lambda: pin.forwardKinematics(pm, pd, qp)),
        ("centroidal_momentum", lambda: fd.centroidal_momentum(m, q, v),
         lambda: pin.computeCentroidalMomentum(pm, pd, qp, vp)),
        ("center_of_mass", lambda: fd.center_of_mass(m, q), lambda: pin.centerOfMass(pm, pd, qp)),
        ("rnea", lambda: fd.rnea(m, q, v, v), lambda: pin.rnea(pm, pd, qp, vp, vp)),
        ("frame_velocity", lambda: fd.frame_velocity(m, q, v, frame, fd.LOCAL_WORLD_ALIGNED),
         lambda: (pin.forwardKinematics(pm, pd, qp, vp),
                  pin.getFrameVelocity(pm, pd, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED))),
        ("frame_classical_acceleration", lambda: fd.frame_classical_acceleration(m, q, v, v, frame, fd.LOCAL),
         lambda: (pin.forwardKinematics(pm, pd, qp, vp, vp),
                  pin.getFrameClassicalAcceleration(pm, pd, fid, pin.ReferenceFrame.LOCAL))),
    ]
    for label, ours, theirs in calls:
        ta, tb = [], []
        for _ in range(9):
            ta.append(min(timeit.repeat(ours, number=N, repeat=3)))
            tb.append(min(timeit.repeat(theirs, number=N, repeat=3)))
        x, y = min(ta) / N * 1e6, min(tb) / N * 1e6
        print(f"{name}\t{label}\t{x:.3f}\t{y:.3f}\t{x / y:.3f}", flush=True)


def main() -> None:
    for name, floating in [("panda", False), ("solo12", True), ("talos_full_v2", True)]:
        bench_robot(name, floating)


if __name__ == "__main__":
    main()
