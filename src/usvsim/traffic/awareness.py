"""Ground-truth situational awareness: range, bearing, CPA/TCPA and the COLREG encounter of each target.

Inputs are world ENU positions (m) and velocities (m/s) in the horizontal plane, headings as ENU yaw (rad).
Bearings are nautical (rad, clockwise from north); relative bearings are clockwise from the own ship's
heading, in (-π, π] (starboard positive).

CPA/TCPA for straight-line motion: with relative position r = p_target − p_own and relative velocity
w = v_target − v_own, TCPA = −r·w / |w|² (0 when |w| = 0: the range never changes, so the closest point is now
and CPA = range) and CPA = |r + w·TCPA|. A negative TCPA means the closest point is past (the ships are
opening). Like an ARPA display, the situation gives every target's CPA with its TCPA whatever their values; a
CPA means something only together with its TCPA (a target 200 m off closing at 1 cm/s has a CPA of 0 m some 5 h
from now). The run report (`situation`'s min_cpa) follows ARPA's CPA/TCPA alarm rule (IMO MSC.192(79)): a
predicted CPA counts only while 0 ≤ TCPA ≤ tcpa_limit_s (`traffic.awareness.tcpa_limit_s`) and there is
relative motion (|w| > STEADY_MPS; without it the range stays, nothing approaches: the least distance says it).

Encounters (COLREG rules 13–15, the usual geometric reading): a target that is opening (TCPA ≤ 0) is `NONE`;
`HEAD_ON` when it is within ±HEAD_ON_RAD of the bow and its heading is reciprocal within ±HEAD_ON_RAD;
`OVERTAKING` (own ship gives way) when the own ship is more than 22.5° abaft the target's beam and faster;
`OVERTAKEN` (own ship stands on) when the target is more than 22.5° abaft the own ship's beam; otherwise
crossing: target on the starboard side → `CROSSING_GIVE_WAY`, on the port side → `CROSSING_STAND_ON`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

NONE, HEAD_ON, CROSSING_GIVE_WAY, CROSSING_STAND_ON, OVERTAKING, OVERTAKEN = range(6)
ENCOUNTER_NAMES = ("none", "head_on", "crossing_give_way", "crossing_stand_on", "overtaking", "overtaken")
HEAD_ON_RAD = math.radians(10.0)
ABAFT_BEAM_RAD = math.radians(112.5)  # 22.5° abaft the beam, from the bow
STEADY_MPS = 1e-6  # relative speeds up to this are no relative motion: TCPA 0, CPA = range


def wrap_pi(a):
    """Angle(s) wrapped to (-π, π]."""
    return -((np.pi - np.asarray(a)) % (2 * np.pi) - np.pi)


@njit(cache=True)
def _wrap(a):
    return -((math.pi - a) % (2.0 * math.pi) - math.pi)


@njit(cache=True)
def _cpa(rx, ry, wx, wy):
    """(CPA m, TCPA s) of one target at (rx, ry) moving at (wx, wy) relative to the own ship."""
    w2 = wx * wx + wy * wy
    tcpa = -(rx * wx + ry * wy) / w2 if w2 > STEADY_MPS * STEADY_MPS else 0.0
    return math.hypot(rx + wx * tcpa, ry + wy * tcpa), tcpa


@njit(cache=True)
def _encounter(rx, ry, own_speed, own_yaw, tgt_speed, tgt_yaw, tcpa):
    """COLREG encounter code of one target (module docstring): offset (rx, ry) from the own ship, ENU yaws."""
    if not tcpa > 0.0:
        return NONE
    own_heading, tgt_heading = 0.5 * math.pi - own_yaw, 0.5 * math.pi - tgt_yaw  # nautical
    bearing = math.atan2(rx, ry) % (2.0 * math.pi)
    rel_bearing = _wrap(bearing - own_heading)  # target seen from own, starboard +
    own_from_tgt = _wrap((math.atan2(-rx, -ry) % (2.0 * math.pi)) - tgt_heading)  # own ship seen from the target
    if abs(rel_bearing) <= HEAD_ON_RAD and abs(_wrap(tgt_heading - own_heading - math.pi)) <= HEAD_ON_RAD:
        return HEAD_ON
    if abs(rel_bearing) > ABAFT_BEAM_RAD:
        return OVERTAKEN
    if abs(own_from_tgt) > ABAFT_BEAM_RAD and own_speed > tgt_speed:
        return OVERTAKING
    return CROSSING_GIVE_WAY if rel_bearing > 0.0 else CROSSING_STAND_ON


@njit(cache=True)
def _cpa_all(rel_pos, rel_vel, cpa, tcpa):
    for k in range(len(cpa)):
        cpa[k], tcpa[k] = _cpa(rel_pos[k, 0], rel_pos[k, 1], rel_vel[k, 0], rel_vel[k, 1])


@njit(cache=True)
def _encounter_all(rel_pos, own_vel, own_yaw, tgt_vel, tgt_yaw, tcpa, out):
    own_speed = math.hypot(own_vel[0], own_vel[1])
    for k in range(len(out)):
        out[k] = _encounter(rel_pos[k, 0], rel_pos[k, 1], own_speed, own_yaw, math.hypot(tgt_vel[k, 0], tgt_vel[k, 1]),
                            tgt_yaw[k], tcpa[k])  # fmt: skip


def cpa_tcpa(rel_pos: np.ndarray, rel_vel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CPA distance (m) and TCPA (s) of targets at rel_pos (N, 2) moving at rel_vel (N, 2) relative to own."""
    rel_pos, rel_vel = np.asarray(rel_pos, float).reshape(-1, 2), np.asarray(rel_vel, float).reshape(-1, 2)
    cpa, tcpa = np.empty(len(rel_pos)), np.empty(len(rel_pos))
    _cpa_all(rel_pos, rel_vel, cpa, tcpa)
    return cpa, tcpa


def nautical_bearing(rel_pos: np.ndarray) -> np.ndarray:
    """True bearing (rad, [0, 2π), clockwise from north) of ENU offsets (N, 2)."""
    return np.arctan2(rel_pos[:, 0], rel_pos[:, 1]) % (2 * np.pi)


def encounters(rel_pos, own_vel, own_yaw: float, tgt_vel, tgt_yaw, tcpa) -> np.ndarray:
    """COLREG encounter code per target (see the module docstring)."""
    rel_pos = np.asarray(rel_pos, float).reshape(-1, 2)
    n = len(rel_pos)
    out = np.empty(n, np.int64)
    _encounter_all(rel_pos, np.asarray(own_vel, float), float(own_yaw), np.asarray(tgt_vel, float).reshape(n, 2),
                   np.broadcast_to(np.asarray(tgt_yaw, float), n).copy(), np.asarray(tcpa, float).reshape(n), out)  # fmt: skip
    return out


def min_distance_over(rel_pos, rel_vel, horizon_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Least distance (m) over the next horizon_s seconds of straight relative motion, and when (s from now)."""
    _, tcpa = cpa_tcpa(rel_pos, rel_vel)
    t = np.clip(tcpa, 0.0, horizon_s)
    return np.linalg.norm(rel_pos + rel_vel * t[:, None], axis=1), t


# columns of `situation`'s output, one row per target
X, Y, VX, VY, RANGE, BEARING, REL_BEARING, CPA, TCPA, ENCOUNTER = range(10)


@njit(cache=True)
def situation(own, tgt_pos, tgt_vel, tgt_yaw, targets, out, since_s, now_s, prev, min_dist, t_min, min_cpa,
              tcpa_at_min_cpa, tcpa_limit_s):  # fmt: skip
    """Every target's situation in one call. own = (x, y, vx, vy, ENU yaw); targets: indices into the fleet's
    tgt_pos (N, 2), tgt_vel (N, 2), tgt_yaw (N,); out (T, 10): columns above (relative position and velocity,
    range, true and relative bearing, CPA, TCPA, encounter code). With since_s >= 0, also the run report: prev
    (T, 2) holds each target's relative position at the previous sample, since_s seconds ago (0: there was
    none), and the least distance on the straight line from it to the relative position now (exact at the
    samples, and exact between them for straight relative motion; never an extrapolation) lowers min_dist (and
    sets t_min); prev becomes the relative position now; and a CPA predicted with 0 <= TCPA <= tcpa_limit_s and relative motion (ARPA's alarm window; a
    target closing so slowly that its closest point is hours away predicts nothing yet) lowers min_cpa (and sets
    tcpa_at_min_cpa, the TCPA it was predicted with)."""
    own_speed = math.hypot(own[2], own[3])
    own_heading = 0.5 * math.pi - own[4]
    for j in range(len(targets)):
        k = targets[j]
        rx, ry = tgt_pos[k, 0] - own[0], tgt_pos[k, 1] - own[1]
        wx, wy = tgt_vel[k, 0] - own[2], tgt_vel[k, 1] - own[3]
        cpa, tcpa = _cpa(rx, ry, wx, wy)
        bearing = math.atan2(rx, ry) % (2.0 * math.pi)
        out[j, X], out[j, Y], out[j, VX], out[j, VY] = rx, ry, wx, wy
        out[j, RANGE], out[j, BEARING], out[j, REL_BEARING] = math.hypot(rx, ry), bearing, _wrap(bearing - own_heading)
        out[j, CPA], out[j, TCPA] = cpa, tcpa
        out[j, ENCOUNTER] = _encounter(rx, ry, own_speed, own[4], math.hypot(tgt_vel[k, 0], tgt_vel[k, 1]),
                                       tgt_yaw[k], tcpa)  # fmt: skip
        if since_s < 0.0:
            continue
        u, dx, dy = 0.0, 0.0, 0.0  # the closest point: r - u (r - prev), u in [0, 1] back along the chord
        if since_s > 0.0:
            dx, dy = rx - prev[j, 0], ry - prev[j, 1]
            chord2 = dx * dx + dy * dy
            if chord2 > 0.0:
                u = min(max((rx * dx + ry * dy) / chord2, 0.0), 1.0)
        d = math.hypot(rx, ry) if u == 0.0 else math.hypot(rx - u * dx, ry - u * dy)
        if d < min_dist[j]:
            min_dist[j], t_min[j] = d, now_s - u * since_s
        prev[j, 0], prev[j, 1] = rx, ry
        if 0.0 <= tcpa <= tcpa_limit_s and math.hypot(wx, wy) > STEADY_MPS and cpa < min_cpa[j]:
            min_cpa[j], tcpa_at_min_cpa[j] = cpa, tcpa
