"""The vessel library and how a scenario's vessel entry becomes a BodyModel (defaults + overrides)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from usvsim.config.vessel import Vessel
from usvsim.core.errors import ScenarioError
from usvsim.vessels import otter, otter_pvs, wamv
from usvsim.vessels.custom import estimated_drag, load_mesh, solid_mass_properties
from usvsim.vessels.model import BodyModel
from usvsim.vessels.parts import Mesh, Part

LIBRARY = {
    "wamv": (wamv.build, "WAM-V 16 catamaran: VRX mass/inertia, the seed's four 250 N azimuth outboards"),
    "otter": (otter.build, "Maritime Robotics Otter (Fossen): 2 m twin-pontoon USV, two fixed propellers"),
    "otter_pvs": (otter_pvs.build, "the Otter as Fossen's PVS models it: his waterplane, GM_T, GM_L and hydrodynamics"),
}


def vessel_model(cfg: Vessel, index: int, base_dir: Path, source: str) -> BodyModel:
    """Build the BodyModel of `vessels[index]`, applying the scenario's overrides to the library defaults."""
    key = f"vessels[{index}]"
    if cfg.model == "custom":
        model = _custom(cfg, key, base_dir, source)
    elif cfg.model in LIBRARY:
        model = LIBRARY[cfg.model][0]()
    else:
        known = ", ".join([*LIBRARY, "custom"])
        raise ScenarioError(source, f"{key}.model", f"unknown vessel model {cfg.model!r} (known: {known})")
    return _with_overrides(model, cfg)


def _custom(cfg: Vessel, key: str, base_dir: Path, source: str) -> BodyModel:
    import trimesh  # here: ~0.5 s to import, and the built-in vessels never need it

    if cfg.mass.mass_kg is None:
        raise ScenarioError(source, f"{key}.mass.mass_kg", "required for a custom vessel")
    assert cfg.hull_mesh is not None  # validated: model 'custom' needs it
    hull = load_mesh(base_dir / cfg.hull_mesh, cfg.mesh_scale, key=f"{source}: {key}.hull_mesh")
    com, inertia = solid_mass_properties(hull, cfg.mass.mass_kg)
    visual = hull
    if cfg.visual_mesh:
        visual = load_mesh(base_dir / cfg.visual_mesh, cfg.mesh_scale, f"{source}: {key}.visual_mesh", False)
    convex = trimesh.Trimesh(hull.vertices, hull.faces, process=False).convex_hull
    collision = (Part("mesh", mesh=Mesh(np.asarray(convex.vertices), np.asarray(convex.faces))),)
    return BodyModel(
        hull=hull, collision=collision, visuals=(Part("mesh", mesh=visual, rgba=(0.9, 0.9, 0.9, 1.0)),),
        mass_kg=cfg.mass.mass_kg, com=com, inertia=inertia,
        drag=estimated_drag(hull, cfg.mass.mass_kg, inertia),
    )  # fmt: skip


def _with_overrides(model: BodyModel, cfg: Vessel) -> BodyModel:
    changes = {}
    if cfg.mass.mass_kg is not None and cfg.model != "custom":
        scale = cfg.mass.mass_kg / model.mass_kg
        changes.update(mass_kg=cfg.mass.mass_kg, inertia=model.inertia * scale)
    if cfg.mass.com is not None:
        changes["com"] = np.array(cfg.mass.com)
    if cfg.mass.inertia is not None:
        changes["inertia"] = np.diag(cfg.mass.inertia)
    if cfg.hydrodynamics is not None:
        changes["drag"] = cfg.hydrodynamics
    if cfg.thrusters is not None:
        changes["thrusters"] = cfg.thrusters
    if cfg.wind_load is not None:
        changes["wind_load"] = cfg.wind_load
    return replace(model, **changes)
