"""Poses and twists given from Python (reset poses, teleports) as arrays: world ENU m, (w, x, y, z)
quaternions body FLU → world ENU, twists in the body frame FLU."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from pydantic import ValidationError

from usvsim.config.base import MAX_COORDINATE_M
from usvsim.config.loader import first_error_text
from usvsim.config.vessel import Pose
from usvsim.core.errors import InputError
from usvsim.core.transforms import quat_from_rpy

PoseLike = Any  # see `pose_arrays`


def pose_arrays(pose: PoseLike) -> tuple[np.ndarray, np.ndarray]:
    """(position (3,), unit quaternion (4,)) from one of:
    - a scenario pose section or dict: `{"position": [x, y, z], "roll_deg": .., "pitch_deg": .., "yaw_deg": ..}`;
    - `(x, y, z, roll, pitch, yaw)`: metres and radians (REP 103);
    - `(x, y, z, qw, qx, qy, qz)`;
    - a pair `(position, quaternion)`."""
    if isinstance(pose, Mapping):
        try:
            pose = Pose.model_validate(dict(pose), strict=False)
        except ValidationError as exc:  # pydantic's several lines with links, as one line naming the key
            raise InputError(f"pose {dict(pose)!r}: {first_error_text(exc, dict(pose), list(Pose.model_fields))}") from None
    if isinstance(pose, Pose):
        rpy = (math.radians(a) for a in (pose.roll_deg, pose.pitch_deg, pose.yaw_deg))
        return np.array(pose.position, dtype=float), np.asarray(quat_from_rpy(*rpy), dtype=float)
    if isinstance(pose, tuple | list) and len(pose) == 2 and not np.isscalar(pose[0]):
        pos, quat = np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float)
    else:
        flat = np.asarray(pose, dtype=float).reshape(-1)
        if flat.size == 6:
            pos, quat = flat[:3], np.asarray(quat_from_rpy(*flat[3:]), dtype=float)
        elif flat.size == 7:
            pos, quat = flat[:3], flat[3:]
        else:
            raise InputError(f"a pose has 6 (x, y, z, roll, pitch, yaw) or 7 (x, y, z, qw, qx, qy, qz) numbers, got {flat.size}")
    norm = float(np.linalg.norm(quat)) if quat.shape == (4,) else 0.0
    if pos.shape != (3,) or not (np.isfinite(pos).all() and np.isfinite(quat).all() and norm > 0):
        raise InputError(f"not a finite pose: position {pos}, quaternion {quat}")
    if np.abs(pos).max() > MAX_COORDINATE_M:  # the limit of every scenario position (docs/limits.md)
        raise InputError(f"position {pos.tolist()} is more than {MAX_COORDINATE_M / 1000:.0f} km from the world origin "
                         "(positions must be within it)")  # fmt: skip
    return pos.copy(), quat / norm


def twist_array(twist) -> np.ndarray:
    """(6,) body-frame twist (u, v, w m/s; p, q, r rad/s) from 0 / None or 6 numbers."""
    if twist is None or (np.isscalar(twist) and twist == 0):
        return np.zeros(6)
    out = np.asarray(twist, dtype=float).reshape(-1)
    if out.shape != (6,) or not np.isfinite(out).all():
        raise InputError(f"a twist is 6 finite numbers (u, v, w, p, q, r in base_link, FLU), got {twist!r}")
    return out
