"""The scene's detectable objects (vessels, buoys, static obstacles, traffic ships) and their ground-truth 3D boxes.

Each object has a box frame: for a floating body (vessel, buoy) its body frame (`<vessel>/base_link` for
vessels, FLU); for a static obstacle the frame at its scenario `position`, turned by `yaw_deg` about world z;
for a kinematic traffic ship (traffic/) its ship frame (FLU, origin midship on the waterline), which moves with
its geoms: the fleet writes their poses (`model.geom_pos`/`geom_quat`) before every step, and the box is read
from them, as the cameras draw them. A traffic ship under full physics is a scenario vessel: it is that vessel's
entry (named after the vessel).
The box is the tight axis-aligned box, in that frame, of all the object's visual geoms (group 1): boxes and
spheres exactly, cylinders from 32 points per rim, meshes from their vertices. So a buoy's box is the cube of
side 2r centred on the sphere; a dock's box is its scenario box; a pier's box reaches from the deck's top
down to the piles' feet on the seabed. Class labels: `vessel`, `buoy_<color>`, the static obstacle's
`type` (dock, wall, box, pier, berth, mesh), for a real place (geo/) `land` and `structure`, whose boxes
are axis-aligned in the world frame, and `vessel` for a kinematic traffic ship (named as in `traffic.ships`;
its box: length_m x beam_m, from draft_m below the waterline to the deckhouse's top, 1.5 height_m above it).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mujoco
import numpy as np

from usvsim.config.loader import base_dir, source_of
from usvsim.config.objects import Buoy
from usvsim.core.transforms import matrix_from_quat, quat_multiply
from usvsim.world.builder import VISUAL_GROUP, base_offset, kinematic_geoms
from usvsim.world.obstacles import static_parts

if TYPE_CHECKING:
    from usvsim.world.world import World

_G = mujoco.mjtGeom
_RIM = np.linspace(0.0, 2.0 * math.pi, 32, endpoint=False)


@dataclass(frozen=True)
class TrackedObject:
    """One detectable object. `state_index` ≥ 0: a floating body (index into `sim.state`); -1: static,
    with its box frame at `origin_world` turned by `rot_world`, or, with `anchor_geom` ≥ 0 (a kinematic traffic
    ship), at `origin_world` turned by `rot_world` in the frame of that geom wherever the model holds it now.
    Box centre and axes are in the box frame."""

    name: str
    category: str  # vessel | buoy | static
    label: str
    geoms: np.ndarray  # visual geom ids
    state_index: int
    origin_world: np.ndarray
    rot_world: np.ndarray
    center_box: np.ndarray
    size_m: np.ndarray  # full extents along the box frame's x, y, z
    anchor_geom: int = -1

    def pose_world(self, sim: World) -> tuple[np.ndarray, np.ndarray]:
        """Box centre (ENU, m) and box axes → world rotation at the simulation's current state."""
        if self.state_index >= 0:
            origin, rot = sim.state.pos[self.state_index], sim.state.rot[self.state_index]
        elif self.anchor_geom >= 0:
            geom_pos, geom_rot = _geom_pose(sim.model, self.anchor_geom)
            origin, rot = geom_pos + geom_rot @ self.origin_world, geom_rot @ self.rot_world
        else:
            origin, rot = self.origin_world, self.rot_world
        return origin + rot @ self.center_box, rot

    def corners_world(self, sim: World) -> np.ndarray:
        """The box's 8 corners (8, 3) in world ENU."""
        center, rot = self.pose_world(sim)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
        return center + (signs * (0.5 * self.size_m)) @ rot.T


def geom_points(model: mujoco.MjModel, geom: int) -> np.ndarray:
    """Points (n, 3) in the geom's own frame whose bounding box is the geom's, in any frame."""
    kind, size = int(model.geom_type[geom]), model.geom_size[geom]
    if kind == _G.mjGEOM_MESH:
        mesh = model.geom_dataid[geom]
        start = model.mesh_vertadr[mesh]
        return model.mesh_vert[start : start + model.mesh_vertnum[mesh]].astype(float)
    if kind in (_G.mjGEOM_CYLINDER, _G.mjGEOM_CAPSULE):
        rim = np.stack([size[0] * np.cos(_RIM), size[0] * np.sin(_RIM)], axis=1)
        cap = size[0] if kind == _G.mjGEOM_CAPSULE else 0.0
        return np.concatenate([np.c_[rim, np.full(len(rim), z)] for z in (-size[1] - cap, size[1] + cap)])
    half = np.full(3, size[0]) if kind == _G.mjGEOM_SPHERE else size.copy()
    return np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half


def _box_of(model: mujoco.MjModel, geoms: np.ndarray, origin: np.ndarray, rot: np.ndarray):
    """Centre and size of the tight box, in the frame (origin, rot) of the geoms' parent frame."""
    points = []
    for g in geoms:
        geom_rot = np.zeros(9)
        mujoco.mju_quat2Mat(geom_rot, model.geom_quat[g])
        points.append(model.geom_pos[g] + geom_points(model, g) @ geom_rot.reshape(3, 3).T)
    local = (np.concatenate(points) - origin) @ rot
    low, high = local.min(axis=0), local.max(axis=0)
    return 0.5 * (low + high), high - low


def _geom_pose(model: mujoco.MjModel, geom: int) -> tuple[np.ndarray, np.ndarray]:
    """A world-body geom's position and rotation as the model holds them (moved geoms: where they were put)."""
    return model.geom_pos[geom].copy(), matrix_from_quat(model.geom_quat[geom])


def _yaw(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _floating(sim: World, name: str, category: str, label: str) -> TrackedObject:
    m = sim.model
    body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)
    geoms = np.flatnonzero((m.geom_bodyid == body) & (m.geom_group == VISUAL_GROUP))
    center, size = _box_of(m, geoms, -base_offset(m, body), np.eye(3))  # in base_link (MuJoCo's frame is at the CoM)
    return TrackedObject(name, category, label, geoms, body - 1, np.zeros(3), np.eye(3), center, size)


def _static(sim: World, obj, geoms: np.ndarray) -> TrackedObject:
    m = sim.model
    origin, rot = np.asarray(obj.position, float), _yaw(obj.yaw_deg)
    center, size = _box_of(m, geoms, origin, rot)
    return TrackedObject(obj.name, "static", obj.type, geoms, -1, origin, rot, center, size)


def _kinematic_ship(sim: World, ship, geoms: np.ndarray) -> TrackedObject:
    """A kinematic traffic ship: its box in the ship frame, anchored to its first geom. That geom's pose in the
    ship frame is its part's (traffic/ships.py), after MuJoCo's move of a mesh to its inertial frame (mesh_pos,
    mesh_quat); the ship frame in the geom's frame is its inverse."""
    # here, not at the top: the usvsim.traffic package loads the fleet's numba kernels; only scenes with ships need it
    from usvsim.traffic.ships import ship_parts

    m, anchor = sim.model, int(geoms[0])
    tag = re.fullmatch(r"(solid|vis)(\d+)", m.geom(anchor).name.rsplit("/", 1)[-1])  # the builder's geom tags
    assert tag is not None, f"kinematic geom {m.geom(anchor).name!r} has no solid<k>/vis<k> tag"
    kind, k = tag.groups()
    solid, visuals = ship_parts(ship)
    part = (solid if kind == "solid" else visuals)[int(k)]
    pos, quat = np.asarray(part.pos, float), np.asarray(part.quat, float)
    if int(m.geom_type[anchor]) == _G.mjGEOM_MESH:
        mesh = m.geom_dataid[anchor]
        pos = pos + matrix_from_quat(quat) @ m.mesh_pos[mesh]
        quat = quat_multiply(quat, m.mesh_quat[mesh])
    rot_in_geom = matrix_from_quat(quat).T  # ship axes → geom axes
    origin_in_geom = -rot_in_geom @ pos
    geom_pos, geom_rot = _geom_pose(m, anchor)
    center, size = _box_of(m, geoms, geom_pos + geom_rot @ origin_in_geom, geom_rot @ rot_in_geom)
    return TrackedObject(ship.name, "vessel", "vessel", geoms, -1, origin_in_geom, rot_in_geom, center, size,
                         anchor_geom=anchor)  # fmt: skip


def catalogue(sim: World) -> list[TrackedObject]:
    """Every vessel, buoy and static obstacle of the scenario, in scenario order, then the kinematic traffic
    ships in `traffic.ships` order."""
    scenario, m = sim.scenario, sim.model
    out = [_floating(sim, v.name, "vessel", "vessel") for v in scenario.vessels]
    static = np.flatnonzero((m.geom_bodyid == 0) & (m.geom_group == VISUAL_GROUP))  # one per part, in build order
    first = 0
    for obj in scenario.objects:
        if isinstance(obj, Buoy):
            out.append(_floating(sim, obj.name, "buoy", f"buoy_{obj.color}"))
            continue
        count = len(static_parts([obj], base_dir(scenario), source_of(scenario)))
        out.append(_static(sim, obj, static[first : first + count]))
        first += count
    place = getattr(sim, "place", None)
    for k, (name, label) in enumerate(place.labels() if place is not None else []):
        center, size = _box_of(m, static[first + k : first + k + 1], np.zeros(3), np.eye(3))
        out.append(TrackedObject(name, "static", label, static[first + k : first + k + 1], -1, np.zeros(3),
                                 np.eye(3), center, size))  # fmt: skip
    names, geoms, owner = kinematic_geoms(m)
    ships = {s.name: s for s in scenario.traffic.ships if s.vessel is None}
    for k, name in enumerate(names):
        if name in ships:
            out.append(_kinematic_ship(sim, ships[name], geoms[owner == k]))
    return out


def geom_owner(model: mujoco.MjModel, objects: list[TrackedObject]) -> np.ndarray:
    """Look-up table (ngeom + 1,) int32: segmentation label (geom id + 1) → object index + 1 (0 = none)."""
    lut = np.zeros(model.ngeom + 1, np.int32)
    for k, obj in enumerate(objects):
        lut[obj.geoms + 1] = k + 1
    return lut
