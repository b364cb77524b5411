"""Build the MuJoCo model of a scenario in memory (MjSpec): floating bodies, static obstacles, moorings.

Marine forces are not MuJoCo's business: they arrive each step through `xfrc_applied`. MuJoCo's own
fluid model is off (density 0). A floating body's MuJoCo frame sits at its centre of mass (axes = base_link's):
with a free joint elsewhere MuJoCo's mass matrix depends on the orientation and its semi-implicit step gains
or loses energy every oscillation (an undamped Otter rolling from 20° gained 1.1 % per cycle at 100 Hz;
about 0.02 % with the frame at the CoM). `model.body_user[b, :3]` keeps the CoM in base_link, so
`base_offset` takes geom poses back to base_link. Collision geoms are convex pieces (group 3, invisible); visual geoms
(group 1) never collide. The still-water plane is a visual in group 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from usvsim.vessels.model import BodyModel
from usvsim.vessels.parts import Part
from usvsim.world.water_visual import add_water_surface

COLLISION_GROUP, VISUAL_GROUP, WATER_GROUP = 3, 1, 2
KINEMATIC_PREFIX = "kinematic/"
SOLID, STRUCK_BY_KINEMATIC = 1, 2  # contype/conaffinity bits: kinematic geoms only pair with floating bodies
_KIND = {
    "box": mujoco.mjtGeom.mjGEOM_BOX,
    "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
    "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
    "mesh": mujoco.mjtGeom.mjGEOM_MESH,
    "hfield": mujoco.mjtGeom.mjGEOM_HFIELD,
}
HFIELD_BASE_M = 1.0  # solid thickness of a height field below its lowest point


@dataclass(frozen=True)
class FloatingBody:
    """A free body in the world: its model and initial pose (world ENU position, quaternion w, x, y, z).
    `anchor` (x, y, z) and `line_length` make it moored by a slack line from its lowest point."""

    name: str
    model: BodyModel
    position: tuple[float, float, float]
    quat: tuple[float, float, float, float]
    anchor: tuple[float, float, float] | None = None
    line_length: float = 0.0
    bottom_offset: float = 0.0


@dataclass(frozen=True)
class KinematicBody:
    """A body moved along a prescribed track: drawn, seen by ray sensors, and floating bodies collide with it; it
    does not respond to forces. Parts are in its body frame (FLU). It is no MuJoCo body (50 bodies would cost
    more than the whole harbour): its geoms belong to the world body, named `kinematic/<name>/<part>`, and whoever
    moves it writes their `model.geom_pos`/`geom_quat` (see `kinematic_geoms`). `solid` parts are drawn and
    collide (one geom instead of two: MuJoCo's step costs per geom), `collision` parts only collide."""

    name: str
    collision: tuple[Part, ...]
    visuals: tuple[Part, ...]
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)  # world ENU at t = 0 (and after a reset), m
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    solid: tuple[Part, ...] = ()


def principal_inertia(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and the quaternion (w, x, y, z) of the principal axes in the body frame."""
    moments, axes = np.linalg.eigh(inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, axes.flatten())
    return moments, quat


def base_offset(model: mujoco.MjModel, body: int) -> np.ndarray:
    """Origin of MuJoCo body `body`'s frame in its base_link frame (m): the CoM for floating bodies, else 0."""
    return np.array(model.body_user[body, :3], dtype=float) if model.nuser_body >= 3 else np.zeros(3)


def _shifted(part: Part, offset: np.ndarray) -> Part:
    return replace(part, pos=tuple(float(p) for p in np.asarray(part.pos, dtype=float) - offset))


def _add_geom(spec: mujoco.MjSpec, parent, part: Part, group: int, collide: bool, tag: str) -> None:
    geom = parent.add_geom()
    geom.type = _KIND[part.kind]
    if part.kind == "mesh":
        assert part.mesh is not None, "a mesh part has its mesh"
        mesh = spec.add_mesh(name=tag)
        mesh.uservert = part.mesh.vertices.flatten().tolist()
        mesh.userface = part.mesh.faces.flatten().tolist()
        geom.meshname = tag
    elif part.kind == "hfield":
        z = np.asarray(part.heights, float)
        lo, span = float(z.min()), max(float(z.max() - z.min()), 1e-3)
        spec.add_hfield(name=tag, size=[part.size[0], part.size[1], span, HFIELD_BASE_M], nrow=z.shape[0],
                        ncol=z.shape[1], userdata=((z - lo) / span).ravel().tolist())  # MuJoCo rescales to [0, 1]
        geom.hfieldname = tag
        if part.texture is not None:
            _add_texture(spec, geom, tag, part.texture)
        part = Part(part.kind, part.size, (part.pos[0], part.pos[1], part.pos[2] + lo), part.quat, rgba=part.rgba)
    else:
        size = list(part.size) + [0.0] * (3 - len(part.size))
        geom.size = size
    geom.pos, geom.quat = list(part.pos), list(part.quat)
    geom.group = group
    geom.rgba = list(part.rgba) if not collide else [0.5, 0.5, 0.5, 0.0]
    geom.contype = geom.conaffinity = SOLID if collide else 0
    geom.friction = [0.6, 0.005, 0.0001]
    geom.mass = 0.0


def _add_texture(spec: mujoco.MjSpec, geom, tag: str, rgb: np.ndarray) -> None:
    """An RGB image (rows, cols, 3) stretched once over the geom (a height field's extent)."""
    rows, cols, _ = rgb.shape
    texture = spec.add_texture(name=tag, type=mujoco.mjtTexture.mjTEXTURE_2D, width=cols, height=rows, nchannel=3)
    texture.data = np.ascontiguousarray(rgb, dtype=np.uint8).tobytes()
    material = spec.add_material(name=tag, texrepeat=[1, 1], texuniform=False, specular=0.1, shininess=0.1)
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tag
    geom.material = tag


def _add_floating(spec: mujoco.MjSpec, fb: FloatingBody) -> None:
    model, com = fb.model, np.asarray(fb.model.com, dtype=float)
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, np.asarray(fb.quat, dtype=float))
    origin = np.asarray(fb.position, dtype=float) + rot.reshape(3, 3) @ com  # the body frame sits at the CoM
    body = spec.worldbody.add_body(name=fb.name, pos=origin.tolist(), quat=list(fb.quat))
    body.userdata = com.tolist()
    body.add_freejoint(name=f"{fb.name}_free")
    body.explicitinertial = True
    moments, iquat = principal_inertia(model.inertia)
    body.mass, body.ipos, body.iquat, body.inertia = model.mass_kg, [0.0, 0.0, 0.0], list(iquat), list(moments)
    for k, part in enumerate(model.collision):
        _add_geom(spec, body, _shifted(part, com), COLLISION_GROUP, True, f"{fb.name}_col{k}")
        body.geoms[-1].contype = SOLID | STRUCK_BY_KINEMATIC
    for k, part in enumerate(model.visuals):
        _add_geom(spec, body, _shifted(part, com), VISUAL_GROUP, False, f"{fb.name}_vis{k}")
    if fb.anchor is not None:
        body.add_site(name=f"{fb.name}_fairlead", pos=(np.array([0.0, 0.0, -fb.bottom_offset]) - com).tolist())
        spec.worldbody.add_site(name=f"{fb.name}_anchor", pos=list(fb.anchor))
        line = spec.add_tendon(name=f"{fb.name}_mooring", limited=True, range=[0.0, fb.line_length])
        line.wrap_site(f"{fb.name}_fairlead")
        line.wrap_site(f"{fb.name}_anchor")
        line.rgba = [0.9, 0.9, 0.2, 1.0]


def _add_kinematic(spec: mujoco.MjSpec, kb: KinematicBody) -> None:
    """The body's parts as world-body geoms at its initial pose. Collision parts are compiled with contype and
    conaffinity 0, which keeps them out of the world body's bounding volume tree (built once, so it would hold
    them where they started, and every floating body's midphase would walk past them each step); whoever moves
    them sets their conaffinity to STRUCK_BY_KINEMATIC while a floating body is near (never contype: they pair
    with floating bodies, not with static parts or each other)."""
    pos, quat = np.asarray(kb.position, float), np.asarray(kb.quat, float)
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    parts = [(p, True, COLLISION_GROUP, f"col{k}") for k, p in enumerate(kb.collision)]
    parts += [(p, False, VISUAL_GROUP, f"solid{k}") for k, p in enumerate(kb.solid)]  # drawn; collides when near
    parts += [(p, False, VISUAL_GROUP, f"vis{k}") for k, p in enumerate(kb.visuals)]
    for part, collide, group, tag in parts:
        name = f"{KINEMATIC_PREFIX}{kb.name}/{tag}"
        _add_geom(spec, spec.worldbody, part, group, collide, name)
        geom, q = spec.worldbody.geoms[-1], np.zeros(4)
        mujoco.mju_mulQuat(q, quat, np.asarray(part.quat, float))
        geom.name, geom.pos, geom.quat = name, (pos + rot.reshape(3, 3) @ np.asarray(part.pos, float)).tolist(), q.tolist()
        if collide:
            geom.contype, geom.conaffinity = 0, 0


def kinematic_colliders(model: mujoco.MjModel, geoms: np.ndarray) -> np.ndarray:
    """Which of these kinematic geoms collide (`collision` and `solid` parts; compiled with conaffinity 0)."""
    return np.array([model.geom(int(g)).name.rsplit("/", 1)[-1].startswith(("col", "solid")) for g in geoms], bool)


def kinematic_geoms(model: mujoco.MjModel) -> tuple[list[str], np.ndarray, np.ndarray]:
    """(names of the kinematic bodies in build order, their geom ids, each geom's index into the names)."""
    names: list[str] = []
    geoms, owner = [], []
    for g in range(model.ngeom):
        name = model.geom(g).name
        if name.startswith(KINEMATIC_PREFIX):
            body = name[len(KINEMATIC_PREFIX) :].rsplit("/", 1)[0]
            if not names or names[-1] != body:
                names.append(body)
            geoms.append(g)
            owner.append(len(names) - 1)
    return names, np.array(geoms, int), np.array(owner, int)


def geom_owners(model: mujoco.MjModel) -> list[str]:
    """Per geom, the name of what it belongs to: its body ('world' for static parts) or its kinematic body."""
    bodies = [model.body(b).name for b in range(model.nbody)]
    out = [bodies[b] for b in model.geom_bodyid]
    names, geoms, owner = kinematic_geoms(model)
    for g, k in zip(geoms, owner):
        out[g] = names[k]
    return out


def build_model(floating: list[FloatingBody], static: list[Part], dt: float, gravity: float,
                visual_only: Sequence[Part] = (), collision_only: Sequence[Part] = (),
                kinematic: tuple[KinematicBody, ...] = ()) -> mujoco.MjModel:  # fmt: skip
    """Compile the world. Body i+1 of the result is floating[i] (body 0 is the world). `static` parts are
    drawn and solid; `visual_only` (after them, in order) and `collision_only` parts one or the other.
    Kinematic bodies are world-body geoms (`kinematic_geoms`), free to move: MuJoCo recomputes their frames
    from `model.geom_pos`/`geom_quat` every step."""
    spec = mujoco.MjSpec()
    spec.modelname = "usvsim"
    spec.nuser_body = 3  # base_offset: each floating body's CoM in base_link
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.option.timestep = dt
    spec.option.gravity = [0.0, 0.0, -gravity]
    spec.option.density = 0.0
    spec.option.viscosity = 0.0
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.visual.global_.offwidth, spec.visual.global_.offheight = 1920, 1080
    sky = spec.add_texture(name="sky", type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
                           builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT, width=256, height=256)
    sky.rgb1, sky.rgb2 = [0.55, 0.72, 0.92], [0.95, 0.97, 1.0]
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.worldbody.add_light(name="sun", pos=[0, 0, 100], dir=[0.3, 0.2, -1.0], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL)
    water = spec.worldbody.add_geom(name="still_water", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[500, 500, 1])
    water.rgba, water.group, water.contype, water.conaffinity = [0.1, 0.35, 0.5, 0.85], WATER_GROUP, 0, 0
    add_water_surface(spec)  # the drawn wave surface (visual only); renderers refresh it from the ocean
    for k, part in enumerate(static):
        _add_geom(spec, spec.worldbody, part, COLLISION_GROUP, True, f"static_col{k}")
        _add_geom(spec, spec.worldbody, part, VISUAL_GROUP, False, f"static_vis{k}")
    for k, part in enumerate(visual_only):
        _add_geom(spec, spec.worldbody, part, VISUAL_GROUP, False, f"extra_vis{k}")
    for k, part in enumerate(collision_only):
        _add_geom(spec, spec.worldbody, part, COLLISION_GROUP, True, f"extra_col{k}")
    for fb in floating:
        _add_floating(spec, fb)
    for kb in kinematic:
        _add_kinematic(spec, kb)
    if kinematic:  # the world body's bounding volume tree is built once; moved geoms would fall outside it
        spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_MIDPHASE
    model = spec.compile()
    model.geom_sameframe[kinematic_geoms(model)[1]] = 0  # frames from geom_pos/geom_quat, not the world's
    if any(kb.collision or kb.solid for kb in kinematic):  # the world body may collide (its kinematic geoms)
        model.body_conaffinity[0] |= STRUCK_BY_KINEMATIC
    return model
