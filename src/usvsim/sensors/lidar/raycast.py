"""`RayWorld`: nearest hits of many rays against the static scene and every moving body's scene.

Per cast, each body's pose is read from `sim.state` (the post-step pose, not MuJoCo's one-step-old
`geom_xpos`); rays that can reach the body's bounding sphere (within range and before a nearer hit already
found) are transformed into the body frame and cast against its prebuilt scene (`scene.body_scenes`).
Scenes are cast nearest first (bodies whose sphere holds the ray origins, then the static world, then the
rest by distance), each starting from the best distance so far as Embree's `tfar`; a ray is only handed to a
scene it can reach (static: its bounding box, beyond the nearest static geom's sphere; bodies: their
sphere, and at chunk level the band of elevations it subtends). The rays are split into chunks run on a
thread pool: Embree and the numba kernels drop the GIL, and each chunk writes only its slice of the
preallocated outputs.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from usvsim.sensors.lidar import kernels
from usvsim.sensors.lidar.scene import NO_HIT, BodyScene, body_scenes

MIN_CHUNK_RAYS = 8192  # below this a thread hand-off costs more than it saves
CHUNKS_PER_THREAD = 4  # several chunks per thread balance costly rays (down, at the boat) with cheap ones (sky)
SPHERE_SLACK = 1e-5  # relative slack on the sphere tests against float32 round-off


class _Chunk:
    """One slice of the rays (world frame) and of the outputs, cast scene by scene."""

    def __init__(self, origins, dirs, dist, geom, cos_inc):
        self.origins, self.dirs, self.dist, self.geom, self.cos_inc = origins, dirs, dist, geom, cos_inc
        self.origin0 = origins[0].astype(np.float64)
        self.spread_m = kernels.max_offset(origins)  # spheres grow by this to cover rays from every origin
        self.dz_range = (float(dirs[:, 2].min()), float(dirs[:, 2].max()))

    def cast_all(self, scene: BodyScene, pose: tuple[np.ndarray, np.ndarray] | None) -> None:
        """Every ray of the chunk against `scene` (pose (pos, rot) of its body; None: world frame)."""
        o, d = self.origins, self.dirs
        if pose is not None:
            o, d = np.empty_like(o), np.empty_like(d)
            kernels.rays_to_body(self.origins, self.dirs, kernels.NO_ROWS, True, *pose, o, d)
        self._run(scene, o, d, kernels.NO_ROWS, True, self.dist)

    def cast_static(self, scene: BodyScene) -> None:
        """The rays that pass through the static scene's box between the nearest static geom's bounding sphere
        and their nearest hit so far."""
        gap = np.min(np.linalg.norm(scene.part_centers_m - self.origin0, axis=1) - scene.part_radii_m)
        rows, tfar = self._rows()
        count = kernels.reachable_box(self.origins, self.dirs, self.dist, scene.box_lo_m, scene.box_hi_m,
                                      gap - self.spread_m, rows, tfar)  # fmt: skip
        if count == len(rows):
            self._run(scene, self.origins, self.dirs, kernels.NO_ROWS, True, self.dist)
        elif count:
            o, d = np.empty((count, 3), np.float32), np.empty((count, 3), np.float32)
            kernels.gather_rows(self.origins, self.dirs, rows[:count], o, d)
            self._run(scene, o, d, rows[:count], False, tfar[:count])

    def cast_spheres(self, scenes: list[BodyScene], poses: list[tuple[np.ndarray, np.ndarray]], to_center, center_dist,
                     radius) -> None:  # fmt: skip
        """Bodies outside the origins' reach (up to 32, nearest first): each gets the rays that meet its bounding
        sphere (centre at to_center from origin0) before a nearer hit, in its body frame."""
        elevation = np.arcsin(to_center[:, 2] / center_dist)
        half = np.arcsin(np.minimum(1.0, radius / center_dist))
        lo, hi = np.sin(np.maximum(elevation - half, -0.5 * np.pi)), np.sin(np.minimum(elevation + half, 0.5 * np.pi))
        # no ray of the chunk points into the band of elevations the sphere covers
        seen = np.flatnonzero((hi >= self.dz_range[0] - SPHERE_SLACK) & (lo <= self.dz_range[1] + SPHERE_SLACK))
        if len(seen) == 0:
            return
        # a unit ray meets a sphere iff its projection on to_center is >= sqrt(|to_center|² - r²)
        min_proj_m = np.sqrt(center_dist[seen] ** 2 - radius[seen] ** 2) - SPHERE_SLACK * center_dist[seen]
        masks, counts = np.empty(len(self.dirs), np.uint32), np.empty(len(seen), np.int64)
        kernels.sphere_masks(self.dirs, self.dist, to_center[seen], min_proj_m, center_dist[seen] - radius[seen],
                             masks, counts)  # fmt: skip
        rows, tfar = self._rows()
        for bit in np.flatnonzero(counts):
            count = kernels.rows_of_bit(masks, bit, self.dist, rows, tfar)  # current distances: nearer bodies cast
            o, d = np.empty((count, 3), np.float32), np.empty((count, 3), np.float32)
            body = int(seen[bit])
            pos_b, rot_b = poses[body]
            kernels.rays_to_body(self.origins, self.dirs, rows[:count], False, pos_b, rot_b, o, d)
            self._run(scenes[body], o, d, rows[:count], False, tfar[:count])

    def _rows(self) -> tuple[np.ndarray, np.ndarray]:
        return np.empty(len(self.dirs), np.int64), np.empty(len(self.dirs), np.float32)

    def _run(self, scene: BodyScene, o, d, rows, all_rows: bool, tfar) -> None:
        hit = scene.scene.run(o, d, dists=tfar, output=1)  # tfar is updated in place for hits
        kernels.merge_hits(rows, all_rows, hit["geomID"], hit["primID"], tfar, hit["Ng"], d, scene.prim_geom,
                           self.dist, self.geom, self.cos_inc)  # fmt: skip


def quat_matrices(quats: np.ndarray) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of unit quaternions (n, 4) (w, x, y, z)."""
    w, x, y, z = quats.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)  # fmt: skip


class RayWorld:
    """The triangles of one geom group, static and moving, and a multi-threaded `cast`."""

    def __init__(self, sim, group: int, threads: int = 2):
        self.sim, self.threads = sim, threads
        self.pool = ThreadPoolExecutor(threads) if threads > 1 else None
        self.static, self.bodies = body_scenes(sim.model, group)
        self.center_body_m = np.array([b.center_body_m for b in self.bodies]).reshape(-1, 3)
        self.radius_m = np.array([b.radius_m for b in self.bodies])
        self.body_index = np.array([b.body for b in self.bodies], int)
        # kinematic bodies (world-body geoms, e.g. traffic ships) are placed by their anchor geom's model.geom_pos/quat
        self.anchor = np.array([b.anchor for b in self.bodies], int)
        self._kinematic = np.flatnonzero(self.anchor >= 0)
        self._floating = np.flatnonzero(self.anchor < 0)

    def scene_of(self, body: int) -> int | None:
        """Index into `bodies` of the scene of `sim.state` body `body` (None: it has no triangles)."""
        found = np.flatnonzero(self.body_index == body)
        return int(found[0]) if len(found) else None

    def poses(self) -> tuple[np.ndarray, np.ndarray]:
        """World positions (B, 3) and rotations (B, 3, 3, body → world) of the moving scenes now."""
        s = self.sim.state
        if not len(self._kinematic):
            return s.pos[self.body_index], s.rot[self.body_index]
        pos, rot = np.empty((len(self.bodies), 3)), np.empty((len(self.bodies), 3, 3))
        pos[self._floating], rot[self._floating] = s.pos[self.body_index[self._floating]], s.rot[self.body_index[self._floating]]
        anchors, m = self.anchor[self._kinematic], self.sim.model
        pos[self._kinematic] = m.geom_pos[anchors]
        rot[self._kinematic] = quat_matrices(m.geom_quat[anchors])
        return pos, rot

    def cast(self, origins: np.ndarray, dirs: np.ndarray, max_range: float, prior=None, skip: int | None = None):
        """Nearest hits of rays (world ENU; `dirs` unit). Returns distance (m, float32, +inf on a miss or
        beyond max_range), MuJoCo geom id (int32, -1 on a miss) and |cos| of the incidence angle (float32).
        `prior` (distance, geom, cos) holds hits already known, e.g. of the rays on scene `skip`, not cast."""
        origins = np.ascontiguousarray(origins, np.float32)
        dirs = np.ascontiguousarray(dirs, np.float32)
        dist, geom, cos_inc = self._outputs(len(dirs), max_range, prior)
        pos, rot = self.poses()
        centers = pos + np.einsum("bij,bj->bi", rot, self.center_body_m)
        bodies = [b for b in range(len(self.bodies)) if b != skip]

        def work(rows: slice) -> None:
            chunk = _Chunk(origins[rows], dirs[rows], dist[rows], geom[rows], cos_inc[rows])
            self._cast_chunk(chunk, max_range, pos, rot, centers, bodies)

        self._map(work, len(dirs))
        dist[geom == NO_HIT] = np.inf
        return dist, geom, cos_inc

    def cast_in_body(self, scene: int, origins_body: np.ndarray, dirs_body: np.ndarray, max_range: float):
        """Like `cast`, for rays in the frame of `bodies[scene]`, against that scene only."""
        origins_body = np.ascontiguousarray(origins_body, np.float32)
        dirs_body = np.ascontiguousarray(dirs_body, np.float32)
        dist, geom, cos_inc = self._outputs(len(dirs_body), max_range, None)
        self._map(lambda rows: _Chunk(origins_body[rows], dirs_body[rows], dist[rows], geom[rows],
                                      cos_inc[rows]).cast_all(self.bodies[scene], None), len(dirs_body))  # fmt: skip
        dist[geom == NO_HIT] = np.inf
        return dist, geom, cos_inc

    @staticmethod
    def _outputs(n: int, max_range: float, prior):
        if prior is None:
            return np.full(n, max_range, np.float32), np.full(n, NO_HIT, np.int32), np.zeros(n, np.float32)
        return np.minimum(prior[0], np.float32(max_range)), prior[1].copy(), prior[2].copy()

    def _map(self, work, n: int) -> None:
        count = max(1, min(self.threads * CHUNKS_PER_THREAD, n // MIN_CHUNK_RAYS)) if self.pool else 1
        bounds = np.linspace(0, n, count + 1).astype(int)
        slices = [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:])]
        if count == 1:
            work(slices[0])
        else:
            assert self.pool is not None  # count > 1 only with a pool
            list(self.pool.map(work, slices))

    def _cast_chunk(self, chunk: _Chunk, max_range: float, pos, rot, centers, bodies: list[int]) -> None:
        """Nearest first: bodies around the origins, the static world, the other bodies within reach."""
        to_center = centers - chunk.origin0
        center_dist = np.linalg.norm(to_center, axis=1)
        radius = self.radius_m + chunk.spread_m
        inside = center_dist <= radius
        for b in bodies:
            if inside[b]:
                chunk.cast_all(self.bodies[b], (pos[b], rot[b]))
        if self.static is not None:
            chunk.cast_static(self.static)
        far = [b for b in sorted(bodies, key=lambda b: center_dist[b]) if not inside[b]]
        far = [b for b in far if center_dist[b] - radius[b] < max_range]
        for group in (far[k : k + 32] for k in range(0, len(far), 32)):  # 32 spheres per mask word
            chunk.cast_spheres([self.bodies[b] for b in group], [(pos[b], rot[b]) for b in group], to_center[group],
                               center_dist[group], radius[group])  # fmt: skip

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=False)
            self.pool = None
