"""ARPA-style target tracking from one radar turn.

Plots: cell-averaging CFAR along range (a cell is detected when its power exceeds `threshold_db` over the mean
of `training_bins` bins on each side beyond 2 guard bins, and over the noise floor); connected detections
(8-neighbour, scipy.ndimage.label, circular in azimuth: the last spoke of a turn borders spoke 0, the bow) form
one plot at their power-weighted centroid (range mean, azimuth mean on the unit circle), placed in the world (ENU)
with the antenna pose and time of the spoke at that centroid.

Detections within JOIN_CELLS of each other belong to one plot (a ship's bow, stern and superstructure), and plots
of one turn closer than `join_m` are one (the pieces an echo breaks into along a ship's length);
plots nearer than `range_min_m` (the clutter around the own ship) and of fewer than `min_cells` cells are dropped (a target fills the beam, so it spans several spokes; a
clutter spike fills one cell). Tracks: nearest-pair association within `gate_m` of each track's prediction, α-β filter per track (state:
ENU position and velocity), tentative until `confirm_hits` updates, dropped after `drop_misses` turns without a
plot. Reported (confirmed) tracks carry range and true bearing from the own antenna, course and speed over
ground, and CPA/TCPA against the own ship's velocity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from usvsim.messages import ros

GUARD_BINS = 2
JOIN_CELLS = 2


@dataclass
class Plot:
    pos: np.ndarray  # world ENU (x, y), m
    time_s: float
    power: float


def cfar(power: np.ndarray, threshold_db: float, training: int) -> np.ndarray:
    """Boolean detections (spokes, bins) by cell-averaging CFAR along range."""
    csum = np.concatenate([np.zeros((len(power), 1)), np.cumsum(power, axis=1)], axis=1)
    bins = power.shape[1]
    i = np.arange(bins)
    lo_a, lo_b = np.clip(i - GUARD_BINS - training, 0, bins), np.clip(i - GUARD_BINS, 0, bins)
    hi_a, hi_b = np.clip(i + GUARD_BINS + 1, 0, bins), np.clip(i + GUARD_BINS + 1 + training, 0, bins)
    total = (csum[:, lo_b] - csum[:, lo_a]) + (csum[:, hi_b] - csum[:, hi_a])
    mean = total / np.maximum((lo_b - lo_a) + (hi_b - hi_a), 1)
    factor = 10.0 ** (threshold_db / 10.0)
    return (power > factor * mean) & (power > factor)


def plots(power: np.ndarray, pose: np.ndarray, time_s: np.ndarray, cfg) -> list[Plot]:
    """Plots of one turn: power (spokes, bins), antenna pose (spokes, 3: x, y, ENU yaw) and time per spoke."""
    spokes, bins = power.shape
    detected = cfar(power, cfg.arpa.threshold_db, cfg.arpa.training_bins)
    detected[:, : int(cfg.arpa.range_min_m / cfg.range_max_m * bins)] = False
    # pieces of one target (bow, stern, superstructure) closer than a few cells join into one plot; the spokes are
    # a circle (the last spoke of a turn borders spoke 0, the bow), so the dilation wraps round
    pad = min(JOIN_CELLS, spokes)
    wrapped = np.pad(detected, ((pad, pad), (0, 0)), mode="wrap")
    joined = ndimage.binary_dilation(wrapped, np.ones((2 * JOIN_CELLS + 1, 2 * JOIN_CELLS + 1), bool))[pad : pad + spokes]
    # scipy's stub unions the return over `output`; without one it is (labels, count)
    labels, count = cast(tuple[np.ndarray, int], ndimage.label(joined, np.ones((3, 3))))
    labels, count = join_around(labels, count)
    labels[~detected] = 0
    if count == 0:
        return []
    cells = ndimage.sum_labels(detected, labels, np.arange(1, count + 1))
    index = np.flatnonzero(cells >= cfg.arpa.min_cells) + 1  # a target fills the beam; a clutter spike one cell
    count = len(index)
    if count == 0:
        return []
    k, b = np.indices(power.shape)
    weight = ndimage.sum_labels(power, labels, index)
    # azimuth centroid on the unit circle (a plot may straddle spoke 0)
    angle = -k * 2.0 * math.pi / spokes
    cx = ndimage.sum_labels(power * np.cos(angle), labels, index) / weight
    cy = ndimage.sum_labels(power * np.sin(angle), labels, index) / weight
    rng = (ndimage.sum_labels(power * b, labels, index) / weight + 0.5) * cfg.range_max_m / bins
    centre = np.arctan2(cy, cx)
    # the spoke at the centroid, for the antenna pose and time (a plot across spoke 0 has spokes of two times)
    spoke = np.round(-centre / (2.0 * math.pi) * spokes).astype(int) % spokes
    out = []
    for j in range(count):
        x, y, yaw = pose[spoke[j]]
        a = yaw + centre[j]
        out.append(Plot(np.array([x + rng[j] * math.cos(a), y + rng[j] * math.sin(a)]), float(time_s[spoke[j]]),
                        float(weight[j])))  # fmt: skip
    return join_near(out, cfg.arpa.join_m)


def join_near(found: list[Plot], join_m: float) -> list[Plot]:
    """Plots closer than join_m (chains of them: single linkage) merged into one at their power-weighted centroid,
    with the time of the strongest. A ship's echo breaks up along its length (CA-CFAR: its strong end raises the
    training mean of the weaker cells beside it), and each piece would start a track of its own (found by QA: a
    30 m ship 800 m out seen end-on gave pieces 30-34 m apart and two confirmed tracks)."""
    if join_m <= 0.0 or len(found) < 2:
        return found
    pos = np.array([p.pos for p in found])
    near = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2) < join_m
    _, group = cast(tuple[int, np.ndarray], connected_components(csr_matrix(near), directed=False))
    out = []
    for g in range(int(group.max()) + 1):
        members = [found[i] for i in np.flatnonzero(group == g)]
        power = np.array([p.power for p in members])
        centroid = (power[:, None] * np.array([p.pos for p in members])).sum(axis=0) / power.sum()
        out.append(Plot(centroid, members[int(np.argmax(power))].time_s, float(power.sum())))
    return out


def join_around(labels: np.ndarray, count: int) -> tuple[np.ndarray, int]:
    """Labels (spokes, bins) of an 8-connected labelling with the components that touch across the last and the
    first spoke merged (the azimuth axis is a circle), renumbered 1..count."""
    first, last = labels[0], labels[-1]
    pairs = set()
    for shift in (-1, 0, 1):  # 8-neighbours across the seam
        a = first[max(shift, 0) : len(first) + min(shift, 0)]
        b = last[max(-shift, 0) : len(last) + min(-shift, 0)]
        both = (a > 0) & (b > 0) & (a != b)
        pairs.update(zip(a[both].tolist(), b[both].tolist(), strict=True))
    if not pairs:
        return labels, count
    parent = list(range(count + 1))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in pairs:
        ra, rb = root(a), root(b)
        parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([root(i) for i in range(count + 1)])
    kept = np.unique(roots[1:])
    number = np.zeros(count + 1, int)
    number[kept] = np.arange(1, len(kept) + 1)
    return number[roots][labels], len(kept)


@dataclass
class Track:
    id: int
    pos: np.ndarray
    vel: np.ndarray
    time_s: float
    hits: int = 1
    misses: int = 0


class Tracker:
    def __init__(self, cfg):
        self.cfg = cfg
        self.reset()

    def reset(self) -> None:
        self.tracks: list[Track] = []
        self.next_id = 1

    def update(self, found: list[Plot], now_s: float) -> None:
        """Associate one turn's plots with the tracks (nearest pairs first, within the gate), correct, start and
        drop tracks."""
        free = set(range(len(found)))
        if self.tracks and found:
            pos = np.array([t.pos for t in self.tracks])
            vel = np.array([t.vel for t in self.tracks])
            t0 = np.array([t.time_s for t in self.tracks])
            plot_pos, plot_t = np.array([p.pos for p in found]), np.array([p.time_s for p in found])
            predicted = pos[:, None, :] + vel[:, None, :] * (plot_t[None, :] - t0[:, None])[..., None]
            dist = np.linalg.norm(predicted - plot_pos[None, :, :], axis=2)
            used = set()
            for flat in np.argsort(dist, axis=None):
                i, j = divmod(int(flat), len(found))
                if dist[i, j] >= self.cfg.gate_m:
                    break
                if i in used or j not in free:
                    continue
                used.add(i)
                free.discard(j)
                self._correct(self.tracks[i], found[j])
            for i, tr in enumerate(self.tracks):
                tr.misses += i not in used
        else:
            for tr in self.tracks:
                tr.misses += 1
        self.tracks = [t for t in self.tracks if t.misses < self.cfg.drop_misses]
        for j in sorted(free):
            self.tracks.append(Track(self.next_id, found[j].pos.copy(), np.zeros(2), found[j].time_s))
            self.next_id += 1

    def _correct(self, tr: Track, plot: Plot) -> None:
        dt = max(plot.time_s - tr.time_s, 1e-3)
        predicted = tr.pos + tr.vel * dt
        residual = plot.pos - predicted
        if tr.hits == 1:  # second plot: velocity from the two positions
            tr.vel = (plot.pos - tr.pos) / dt
            tr.pos = plot.pos.copy()
        else:
            tr.pos = predicted + self.cfg.alpha * residual
            tr.vel = tr.vel + self.cfg.beta / dt * residual
        tr.time_s, tr.hits, tr.misses = plot.time_s, tr.hits + 1, 0

    def confirmed(self) -> list[Track]:
        return [t for t in self.tracks if t.hits >= self.cfg.confirm_hits]

    def message(self, stamp_ns: int, antenna_pos: np.ndarray, own_vel: np.ndarray) -> object:
        """usvsim_msgs/RadarTrackArray of the confirmed tracks (CPA/TCPA against own_vel, ENU m/s)."""
        cls = ros.msg_class("usvsim_msgs/msg/RadarTrack")
        out = []
        for t in self.confirmed():
            pos = t.pos + t.vel * (stamp_ns / 1e9 - t.time_s)  # extrapolated to the stamp
            rel, rel_vel = pos - antenna_pos[:2], t.vel - own_vel
            w2 = float(rel_vel @ rel_vel)
            tcpa = -float(rel @ rel_vel) / w2 if w2 > 1e-9 else 0.0
            out.append(cls(id=t.id, range=float(np.hypot(*rel)), bearing=math.atan2(rel[0], rel[1]) % (2 * math.pi),
                           course=math.atan2(t.vel[0], t.vel[1]) % (2 * math.pi), speed=float(np.hypot(*t.vel)),
                           cpa=float(np.linalg.norm(rel + rel_vel * tcpa)), tcpa=tcpa,
                           position=ros.point([*pos, 0.0]), velocity=ros.vector3([*t.vel, 0.0]), hits=t.hits))  # fmt: skip
        return ros.msg_class("usvsim_msgs/msg/RadarTrackArray")(header=ros.header(stamp_ns, "world"), tracks=out)
