"""Ground-truth situational awareness: range, bearing, CPA/TCPA and the COLREG encounter of each target.

Inputs are world ENU positions (m) and velocities (m/s) in the horizontal plane, headings as ENU yaw (rad).
Bearings are nautical (rad, clockwise from north); relative bearings are clockwise from the own ship's
heading, in (-π, π] (starboard positive).

CPA/TCPA for straight-line motion: with relative position r = p_target − p_own and relative velocity
w = v_target − v_own, TCPA = −r·w / |w|² (0 when |w| = 0) and CPA = |r + w·TCPA|. A negative TCPA means the
closest point is past (the ships are opening).

Encounters (COLREG rules 13–15, the usual geometric reading): a target that is opening (TCPA ≤ 0) is `NONE`;
`HEAD_ON` when it is within ±HEAD_ON_RAD of the bow and its heading is reciprocal within ±HEAD_ON_RAD;
`OVERTAKING` (own ship gives way) when the own ship is more than 22.5° abaft the target's beam and faster;
`OVERTAKEN` (own ship stands on) when the target is more than 22.5° abaft the own ship's beam; otherwise
crossing: target on the starboard side → `CROSSING_GIVE_WAY`, on the port side → `CROSSING_STAND_ON`.
"""

from __future__ import annotations

import math

import numpy as np

NONE, HEAD_ON, CROSSING_GIVE_WAY, CROSSING_STAND_ON, OVERTAKING, OVERTAKEN = range(6)
ENCOUNTER_NAMES = ("none", "head_on", "crossing_give_way", "crossing_stand_on", "overtaking", "overtaken")
HEAD_ON_RAD = math.radians(10.0)
ABAFT_BEAM_RAD = math.radians(112.5)  # 22.5° abaft the beam, from the bow


def wrap_pi(a):
    """Angle(s) wrapped to (-π, π]."""
    return -((np.pi - np.asarray(a)) % (2 * np.pi) - np.pi)


def cpa_tcpa(rel_pos: np.ndarray, rel_vel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CPA distance (m) and TCPA (s) of targets at rel_pos (N, 2) moving at rel_vel (N, 2) relative to own."""
    w2 = np.einsum("ij,ij->i", rel_vel, rel_vel)
    tcpa = np.where(w2 > 1e-12, -np.einsum("ij,ij->i", rel_pos, rel_vel) / np.maximum(w2, 1e-12), 0.0)
    return np.linalg.norm(rel_pos + rel_vel * tcpa[:, None], axis=1), tcpa


def nautical_bearing(rel_pos: np.ndarray) -> np.ndarray:
    """True bearing (rad, [0, 2π), clockwise from north) of ENU offsets (N, 2)."""
    return np.arctan2(rel_pos[:, 0], rel_pos[:, 1]) % (2 * np.pi)


def encounters(rel_pos, own_vel, own_yaw: float, tgt_vel, tgt_yaw, tcpa) -> np.ndarray:
    """COLREG encounter code per target (see the module docstring)."""
    own_heading = 0.5 * np.pi - own_yaw  # nautical
    rel_bearing = wrap_pi(nautical_bearing(rel_pos) - own_heading)  # target seen from own, starboard +
    tgt_heading = 0.5 * np.pi - np.asarray(tgt_yaw)
    own_from_tgt = wrap_pi(nautical_bearing(-rel_pos) - tgt_heading)  # own ship seen from the target
    reciprocal = np.abs(wrap_pi(tgt_heading - own_heading - np.pi)) <= HEAD_ON_RAD
    faster = np.linalg.norm(own_vel) > np.linalg.norm(tgt_vel, axis=1)
    out = np.where(rel_bearing > 0, CROSSING_GIVE_WAY, CROSSING_STAND_ON)
    out = np.where(np.abs(rel_bearing) > ABAFT_BEAM_RAD, OVERTAKEN, out)
    out = np.where((np.abs(own_from_tgt) > ABAFT_BEAM_RAD) & faster & (np.abs(rel_bearing) <= ABAFT_BEAM_RAD),
                   OVERTAKING, out)  # fmt: skip
    out = np.where((np.abs(rel_bearing) <= HEAD_ON_RAD) & reciprocal, HEAD_ON, out)
    return np.where(tcpa > 0, out, NONE)


def min_distance_over(rel_pos, rel_vel, horizon_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Least distance (m) over the next horizon_s seconds of straight relative motion, and when (s from now)."""
    _, tcpa = cpa_tcpa(rel_pos, rel_vel)
    t = np.clip(tcpa, 0.0, horizon_s)
    return np.linalg.norm(rel_pos + rel_vel * t[:, None], axis=1), t
