"""The 3D scene of the Foxglove live view: `foxglove.SceneUpdate` messages built from the simulation.

Entities (ids, frames):
- `vessel/<v>`: the vessel's visual parts (hull meshes as indexed triangle lists, boxes, cylinders) in
  frame `<v>/base_link`, `frame_locked`, so the `/tf` stream moves them (TF tree: ground_truth.py). Static:
  sent once per subscription, never per tick (the WAM-V's meshes are ~40 kB).
- `obstacles`: every static visual geom of the MuJoCo model (the world body's group-1 geoms: boxes,
  cylinders, spheres, convex meshes) in frame `world`. Static.
- `buoy/<b>`: each floating non-vessel body (buoys) in frame `world`, its pose baked into the primitives'
  poses (buoys have no TF frame). Dynamic (a few spheres).
- `water/<v>`: the ocean surface as an indexed triangle list around each vessel (clusters of nearby vessels
  share one grid), heights from `sim.ocean.height_grid` (the wave model the physics queries), coloured by
  height (troughs dark, crests light). Dynamic, on its own channel.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import mujoco
import numpy as np
from foxglove.messages import (
    Color,
    CubePrimitive,
    CylinderPrimitive,
    Point3,
    Pose,
    Quaternion,
    SceneEntity,
    SceneUpdate,
    SpherePrimitive,
    Timestamp,
    TriangleListPrimitive,
    Vector3,
)

from usvsim.world.shapes import drawn_parts, static_parts

if TYPE_CHECKING:
    from usvsim.simulation import Simulation
    from usvsim.vessels.parts import Part

WORLD_FRAME = "world"
WATER_ALPHA = 0.85
TROUGH_RGB, CREST_RGB = np.array([0.02, 0.15, 0.28]), np.array([0.45, 0.65, 0.72])


def stamp(stamp_ns: int) -> Timestamp:
    return Timestamp(sec=stamp_ns // 1_000_000_000, nsec=stamp_ns % 1_000_000_000)


def pose(pos, quat) -> Pose:
    """A Foxglove pose from a position and a (w, x, y, z) quaternion."""
    w, x, y, z = (float(q) for q in quat)
    return Pose(position=Vector3(x=float(pos[0]), y=float(pos[1]), z=float(pos[2])),
                orientation=Quaternion(x=x, y=y, z=z, w=w))  # fmt: skip


def color(rgba) -> Color:
    return Color(r=float(rgba[0]), g=float(rgba[1]), b=float(rgba[2]), a=float(rgba[3]))


class Primitives:
    """The primitive lists of one entity, filled shape by shape (poses in the entity's frame)."""

    def __init__(self):
        self.cubes, self.cylinders, self.spheres, self.triangles = [], [], [], []

    def add(self, kind: str, size, pos, quat, rgba, vertices=None, faces=None) -> None:
        """kind box (size = half extents), cylinder (radius, half length), sphere (radius) or mesh."""
        p, c = pose(pos, quat), color(rgba)
        if kind == "box":
            self.cubes.append(
                CubePrimitive(pose=p, size=_vec(2 * size[0], 2 * size[1], 2 * size[2]), color=c)
            )
        elif kind == "cylinder":
            d = 2 * size[0]
            self.cylinders.append(CylinderPrimitive(pose=p, size=_vec(d, d, 2 * size[1]), bottom_scale=1.0,
                                                    top_scale=1.0, color=c))  # fmt: skip
        elif kind == "sphere":
            d = 2 * size[0]
            self.spheres.append(SpherePrimitive(pose=p, size=_vec(d, d, d), color=c))
        elif kind == "mesh" and vertices is not None:
            points = [Point3(x=x, y=y, z=z) for x, y, z in np.asarray(vertices, dtype=float).tolist()]
            indices = np.asarray(faces, dtype=np.int64).ravel().tolist()
            self.triangles.append(TriangleListPrimitive(pose=p, points=points, color=c, indices=indices))

    def add_part(self, part: Part, base_pos=(0.0, 0.0, 0.0), base_quat=(1.0, 0.0, 0.0, 0.0)) -> None:
        """A body part (pose in the body frame) placed by the body pose `base_pos`, `base_quat`."""
        pos, quat = part.placed(base_pos, base_quat)
        mesh = part.mesh
        self.add(part.kind, part.size, pos, quat, part.rgba,
                 mesh.vertices if mesh is not None else None, mesh.faces if mesh is not None else None)  # fmt: skip

    def entity(self, entity_id: str, frame_id: str, stamp_ns: int, frame_locked: bool = False) -> SceneEntity:
        return SceneEntity(timestamp=stamp(stamp_ns), frame_id=frame_id, id=entity_id, frame_locked=frame_locked,
                           cubes=self.cubes, cylinders=self.cylinders, spheres=self.spheres,
                           triangles=self.triangles)  # fmt: skip

    def __len__(self) -> int:
        return len(self.cubes) + len(self.cylinders) + len(self.spheres) + len(self.triangles)


def _vec(x: float, y: float, z: float) -> Vector3:
    return Vector3(x=float(x), y=float(y), z=float(z))


class SceneBuilder:
    """Builds the scene's `SceneUpdate`s from a simulation (call from the simulation thread)."""

    def __init__(self, sim: Simulation, water_size_m: float = 60.0, water_points: int = 31):
        if water_points < 2 or water_size_m <= 0:
            raise ValueError("the water grid needs water_points >= 2 and water_size_m > 0")
        self.sim = sim
        self.water_size_m, self.water_points = float(water_size_m), int(water_points)
        self.buoys = [b for name, b in sim.bodies.items() if name not in sim.vessels]
        self._water_indices = grid_indices(self.water_points)

    # -- static: once per subscription ------------------------------------------------------------
    def static_update(self, stamp_ns: int) -> SceneUpdate:
        """Vessels (in their base_link frames) and static obstacles (world)."""
        entities = []
        for name, vessel in self.sim.vessels.items():
            prims = Primitives()
            for part in drawn_parts(vessel.model):  # its visuals, or its physics hull
                prims.add_part(part)
            entities.append(prims.entity(f"vessel/{name}", f"{name}/base_link", stamp_ns, frame_locked=True))
        obstacles = static_geoms(self.sim.model)
        if len(obstacles):
            entities.append(obstacles.entity("obstacles", WORLD_FRAME, stamp_ns))
        return SceneUpdate(entities=entities)

    # -- dynamic: every scene tick ----------------------------------------------------------------
    def bodies_update(self, stamp_ns: int) -> SceneUpdate:
        """Buoys (and any other floating non-vessel body) at their current world poses."""
        entities = []
        for body in self.buoys:
            prims = Primitives()
            pos, quat = body.position, body.quat
            for part in body.model.visuals:
                prims.add_part(part, pos, quat)
            entities.append(prims.entity(f"buoy/{body.name}", WORLD_FRAME, stamp_ns))
        return SceneUpdate(entities=entities)

    def water_update(self, stamp_ns: int) -> SceneUpdate:
        """The ocean surface around the vessels (or the origin when there are none) at the current time."""
        entities = []
        for name, center in self.water_centers():
            heights = np.asarray(self.sim.ocean.height_grid(center, self.water_size_m, self.water_points,
                                                            self.sim.time), dtype=float)  # fmt: skip
            entities.append(self._water_entity(name, center, heights, stamp_ns))
        return SceneUpdate(entities=entities)

    def water_centers(self) -> list[tuple[str, tuple[float, float]]]:
        """(entity name, snapped grid centre) per vessel; a vessel in the middle half of a grid shares it."""
        size, n, out = self.water_size_m, self.water_points, []
        positions = [(name, v.position) for name, v in self.sim.vessels.items()] or [("origin", np.zeros(3))]
        for name, pos in positions:
            if any(max(abs(pos[0] - c[0]), abs(pos[1] - c[1])) < size / 4 for _, c in out):
                continue
            out.append((name, snapped_center(pos[:2], size, n)))
        return out

    def _water_entity(self, name: str, center, heights: np.ndarray, stamp_ns: int) -> SceneEntity:
        n, size = self.water_points, self.water_size_m
        axis = np.linspace(-0.5 * size, 0.5 * size, n)
        gx, gy = np.meshgrid(center[0] + axis, center[1] + axis)
        xyz = np.stack([gx.ravel(), gy.ravel(), heights.ravel()], axis=1).tolist()
        rgb = water_colors(heights.ravel(), float(self.sim.ocean.level_m))
        points = [Point3(x=x, y=y, z=z) for x, y, z in xyz]
        colors = [Color(r=r, g=g, b=b, a=WATER_ALPHA) for r, g, b in rgb]
        tri = TriangleListPrimitive(pose=pose((0, 0, 0), (1, 0, 0, 0)), points=points, colors=colors,
                                    indices=self._water_indices)  # fmt: skip
        return SceneEntity(
            timestamp=stamp(stamp_ns), frame_id=WORLD_FRAME, id=f"water/{name}", triangles=[tri]
        )


def snapped_center(center_xy, size_m: float, n: int) -> tuple[float, float]:
    """Grid centre rounded to the grid spacing, so vertices stay put in the world as the grid follows a boat."""
    step = size_m / (n - 1)
    return float(np.round(center_xy[0] / step) * step), float(np.round(center_xy[1] / step) * step)


def water_colors(heights: np.ndarray, level_m: float) -> list[list[float]]:
    """RGB in [0, 1] per height: troughs dark, crests light (scaled to the sea's own height spread)."""
    rel = heights - level_m
    f = np.clip(0.5 + rel / max(4.0 * float(rel.std()), 0.1), 0.0, 1.0)[:, None]
    return (TROUGH_RGB + f * (CREST_RGB - TROUGH_RGB)).tolist()


def grid_indices(n: int) -> list[int]:
    """Triangle indices (two CCW triangles per cell, seen from above) of an n × n row-major vertex grid."""
    i = np.arange(n - 1)
    a = (i[:, None] * n + i[None, :]).ravel()  # lower-left corner of each cell (row iy, column ix)
    tris = np.stack([a, a + 1, a + n + 1, a, a + n + 1, a + n], axis=1)
    return tris.ravel().tolist()


def static_geoms(model: mujoco.MjModel) -> Primitives:
    """The world body's visual geoms (static obstacles), world frame."""
    prims = Primitives()
    for part in static_parts(model):
        prims.add_part(part)
    return prims


def scene_period_ns(rate_hz: float) -> int:
    if not (math.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"scene_rate_hz must be a positive number, got {rate_hz!r}")
    return max(1, round(1e9 / rate_hz))
