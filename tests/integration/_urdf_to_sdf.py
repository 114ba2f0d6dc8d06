"""A test-side URDF → SDFormat converter, writing the same robot's poses in several SDFormat styles.

Independent of featherdyn's readers (plain ElementTree and NumPy): the SDF loader is checked by loading
both files. Styles (``STYLES``):

* ``"model"`` — SDFormat 1.4: every link's pose in the model frame (the URDF chain composed here), joint
  poses omitted (at the child link), axes in the model frame (1.4 has no other choice);
* ``"use_parent_model_frame"`` — 1.6, as ``"model"`` but axes with ``<use_parent_model_frame>true``;
* ``"joint_frame_1_6"`` — 1.6, link poses in the model frame, axes in the joint frame (the default);
* ``"parent"`` — 1.9: each link's pose ``relative_to`` its parent link (the URDF origin as written);
* ``"joint"`` — 1.8: each joint's pose ``relative_to`` the parent link, the child link's pose ``relative_to``
  the joint (identity), axes ``expressed_in`` the parent link, in degrees;
* ``"frames"`` — 1.10: a ``<frame attached_to=PARENT>`` per joint holding the URDF origin (as a quaternion),
  each link ``relative_to`` its frame, axes ``expressed_in="__model__"``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

STYLES = ("model", "use_parent_model_frame", "joint_frame_1_6", "parent", "joint", "frames")
VERSION = {"model": "1.4", "use_parent_model_frame": "1.6", "joint_frame_1_6": "1.6", "parent": "1.9",
           "joint": "1.8", "frames": "1.10"}


def rpy_matrix(r: float, p: float, y: float) -> np.ndarray:
    """Rz(y) Ry(p) Rx(r), written out (URDF and SDFormat roll-pitch-yaw)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def matrix_quat_xyzw(R: np.ndarray) -> np.ndarray:
    """A unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = np.trace(R)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        return np.array([(R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, 0.25 * s])
    i = int(np.argmax(np.diag(R)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
    q = np.zeros(4)
    q[i] = 0.25 * s
    q[j] = (R[j, i] + R[i, j]) / s
    q[k] = (R[k, i] + R[i, k]) / s
    q[3] = (R[k, j] - R[j, k]) / s
    return q


def _floats(text: str | None, default: str) -> list[float]:
    return [float(x) for x in (text or default).split()]


def _origin(elem: ET.Element | None) -> tuple[np.ndarray, np.ndarray, list[float]]:
    o = None if elem is None else elem.find("origin")
    xyz = _floats(None if o is None else o.get("xyz"), "0 0 0")
    rpy = _floats(None if o is None else o.get("rpy"), "0 0 0")
    return rpy_matrix(*rpy), np.array(xyz), rpy


def _num(x: float) -> str:
    return repr(float(x))


def _pose_euler(R_p: tuple[np.ndarray, np.ndarray] | None, rpy: list[float] | None, xyz: np.ndarray,
                relative_to: str = "", degrees: bool = False) -> str:
    rel = f' relative_to="{relative_to}"' if relative_to else ""
    angles = rpy if rpy is not None else [0.0, 0.0, 0.0]
    if degrees:
        angles = [math.degrees(a) for a in angles]
    deg = ' degrees="true"' if degrees else ""
    return f"<pose{rel}{deg}>{' '.join(map(_num, [*xyz, *angles]))}</pose>"


def _pose_quat(R: np.ndarray, p: np.ndarray, relative_to: str = "") -> str:
    rel = f' relative_to="{relative_to}"' if relative_to else ""
    return f'<pose{rel} rotation_format="quat_xyzw">{" ".join(map(_num, [*p, *matrix_quat_xyzw(R)]))}</pose>'


def urdf_to_sdf(urdf_text: str, style: str, fixed_base: bool = True) -> str:
    """The SDFormat text of a URDF robot (revolute, continuous, prismatic and fixed joints), in ``style``.

    ``fixed_base``: the root link hangs on ``world`` by a fixed joint ``world_weld`` (else it floats).
    """
    robot = ET.fromstring(urdf_text)
    links = {e.get("name"): e for e in robot.findall("link")}
    joints = robot.findall("joint")
    parent_of = {j.find("child").get("link"): j for j in joints}
    root = next(n for n in links if n not in parent_of)
    on_world = root == "world"  # a URDF root link named "world" is SDFormat's world frame (as sdformat reads URDF)
    # each link's pose in the model frame (the root link at the model origin)
    X: dict[str, tuple[np.ndarray, np.ndarray]] = {root: (np.eye(3), np.zeros(3))}
    pending = list(joints)
    while pending:
        j = pending.pop(0)
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        if parent not in X:
            pending.append(j)
            continue
        R, p, _ = _origin(j)
        Rp, pp = X[parent]
        X[child] = (Rp @ R, Rp @ p + pp)
    version = VERSION[style]
    out = [f'<?xml version="1.0"?>\n<sdf version="{version}">', f'<model name="{robot.get("name")}">']
    for name, link in links.items():
        if name == "world" and on_world:
            continue
        out.append(f'<link name="{name}">')
        j = parent_of.get(name)
        R, p = X[name]
        if style in ("model", "use_parent_model_frame", "joint_frame_1_6"):
            if name != root:
                out.append(_pose_quat(R, p) if style == "joint_frame_1_6" else
                           _pose_euler(None, list(_matrix_rpy(R)), p))
        elif j is not None:
            jR, jp, jrpy = _origin(j)
            parent = j.find("parent").get("link")
            if style == "parent":
                out.append(_pose_euler(None, jrpy, jp, relative_to="__model__" if parent == "world" else parent))
            elif style == "joint":
                out.append(f'<pose relative_to="{j.get("name")}"/>')
            else:
                out.append('<pose relative_to="F_' + j.get("name") + '">0 0 0 0 0 0</pose>')
        inertial = link.find("inertial")
        if inertial is not None:
            iR, ip, irpy = _origin(inertial)
            inertia = inertial.find("inertia")
            values = "".join(f"<{k}>{_num(float(inertia.get(k, '0')))}</{k}>"
                             for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
            pose = _pose_quat(iR, ip) if style == "frames" else _pose_euler(None, irpy, ip)
            out.append(f'<inertial><mass>{_num(float(inertial.find("mass").get("value")))}</mass>{pose}'
                       f"<inertia>{values}</inertia></inertial>")
        else:
            # a URDF link without <inertial> is massless; SDFormat's default would be 1 kg
            out.append("<inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial>")
        out.append('<visual name="v"><geometry><box><size>1 1 1</size></box></geometry></visual></link>')
    if fixed_base and not on_world:
        out.append(f'<joint name="world_weld" type="fixed"><parent>world</parent><child>{root}</child></joint>')
    for j in joints:
        name, jtype = j.get("name"), j.get("type")
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        if style == "frames":
            jR, jp, _ = _origin(j)
            attached = "__model__" if parent == "world" else parent
            out.append(f'<frame name="F_{name}" attached_to="{attached}">{_pose_quat(jR, jp)}</frame>')
        out.append(f'<joint name="{name}" type="{jtype}"><parent>{parent}</parent><child>{child}</child>')
        if style == "joint":
            _, jp, jrpy = _origin(j)
            out.append(_pose_euler(None, jrpy, jp, relative_to="__model__" if parent == "world" else parent,
                                   degrees=True))
        if jtype != "fixed":
            axis = np.array(_floats(None if j.find("axis") is None else j.find("axis").get("xyz"), "1 0 0"))
            axis = axis / np.linalg.norm(axis)
            R_child = X[child][0]
            if style in ("model", "use_parent_model_frame"):
                xyz, attr = R_child @ axis, ""
            elif style == "joint":
                xyz, attr = _origin(j)[0] @ axis, f' expressed_in="{"__model__" if parent == "world" else parent}"'
            elif style == "frames":
                xyz, attr = R_child @ axis, ' expressed_in="__model__"'
            else:
                xyz, attr = axis, ""
            out.append(f"<axis><xyz{attr}>{' '.join(map(_num, xyz))}</xyz>")
            if style == "use_parent_model_frame":
                out.append("<use_parent_model_frame>true</use_parent_model_frame>")
            elif style == "joint_frame_1_6":
                out.append("<use_parent_model_frame>false</use_parent_model_frame>")
            limit = j.find("limit")
            if limit is not None:
                parts = []
                if jtype in ("revolute", "prismatic"):
                    parts += [f"<lower>{_num(float(limit.get('lower', '0')))}</lower>",
                              f"<upper>{_num(float(limit.get('upper', '0')))}</upper>"]
                for k in ("effort", "velocity"):
                    if limit.get(k) is not None:
                        parts.append(f"<{k}>{_num(float(limit.get(k)))}</{k}>")
                out.append(f"<limit>{''.join(parts)}</limit>")
            out.append("</axis>")
        out.append("</joint>")
    out.append("</model></sdf>")
    return "\n".join(out)


def _matrix_rpy(R: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch, yaw of ``R = Rz(y) Ry(p) Rx(r)``."""
    p = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) > 1e-9:
        r = math.atan2(R[2, 1], R[2, 2])
        y = math.atan2(R[1, 0], R[0, 0])
    else:  # gimbal lock: yaw absorbed into roll
        r = math.atan2(-R[1, 2], R[1, 1])
        y = 0.0
    return r, p, y
