"""The Otter as Fossen's PythonVehicleSimulator (PVS) models it (`model: otter_pvs`).

PVS gives the Otter's restoring forces by formulas (physics.md §3.1): waterplane area 0.75 m², GM_T 1.2325 m,
GM_L 3.1113 m. The default `otter` hull (vessels/otter.py: tapered pontoons, raked bows) floats at Fossen's draft
but its waterplane is smaller (GM_T 1.10 m, GM_L 1.67 m). This hull is made to have Fossen's numbers: two
prismatic pontoons whose rectangular waterplanes (length `length`, beam `beam`, centres at y = ±`y`) give his area
and both metacentric heights exactly, with V-shaped sections (half-width ∝ depth^`exponent` below the waterline,
vertical sides above) that hold his displacement at his draft. Mass, centre of mass (so Fossen's r_g from CO,
`fossen_sets.OTTER_CO_BASE_LINK`), inertia, propellers and wind load are the default Otter's; the hydrodynamics
default to Fossen's (`{type: fossen, parameters: otter}`).

What still differs from PVS (docs/vessel-dynamics.md): the centre of flotation lies under the centre of mass, where
Fossen puts it 0.353 m aft (his G35 heave-pitch coupling); the thrust acts at the propellers (0.135 m below CO,
so it trims the boat), and the hydrostatics are those of the hull at its actual pose, not PVS's linear G.

Body frame `base_link`: FLU, keel line at z = 0, the same origin as the default Otter's (the pontoons are centred
under its centre of mass, x = -0.206 m).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from usvsim.config.hydro_models import FossenHydrodynamics
from usvsim.hydro.fossen_sets import otter_pvs
from usvsim.vessels import otter
from usvsim.vessels.model import BodyModel
from usvsim.vessels.parts import Mesh, Part, merge

WATER_DENSITY = 1025.0  # kg/m³, Fossen's (and the scenario default)
LEVELS = 8  # section vertices below the waterline on each side
STATIONS = 21  # sections along a pontoon (the water is sampled at the vertices: 0.1 m apart)
DECK_Z_M = otter.PONTOON_DEPTH_M


@dataclass(frozen=True)
class Pontoons:
    """The pontoon design (m): waterline length and beam, centreline offset, section exponent, keel to
    waterline draft, and the resulting centre of buoyancy height KB (m above the keel)."""

    length: float
    beam: float
    y: float
    exponent: float
    draft: float
    kb: float


def _section(beam: float, exponent: float, draft: float, deck: float) -> np.ndarray:
    """The section outline (n, 2) as (y, z), counter-clockwise seen from +x: keel point, one side up to the deck,
    across, down the other side."""
    z = draft * np.arange(1, LEVELS + 1) / LEVELS
    half = 0.5 * beam * (z / draft) ** exponent
    port = np.column_stack([half, z])  # +y, keel to waterline
    deck_edge = [[0.5 * beam, deck], [-0.5 * beam, deck]]
    return np.vstack([[[0.0, 0.0]], port, deck_edge, port[::-1] * [-1.0, 1.0]])


def _area_centroid(poly: np.ndarray) -> tuple[float, float]:
    """Area and centroid height of a closed counter-clockwise polygon (y, z) (shoelace)."""
    y, z = poly[:, 0], poly[:, 1]
    cross = y * np.roll(z, -1) - np.roll(y, -1) * z
    area = 0.5 * cross.sum()
    return float(area), float(((z + np.roll(z, -1)) * cross).sum() / (6.0 * area))


@cache
def design() -> Pontoons:
    """Solve the pontoons for Fossen's draft, displacement, waterplane area, GM_T and GM_L (his KB formula aside:
    the sections' own KB is used, so the metacentric heights, which set the restoring moments, come out his)."""
    pvs = otter_pvs()
    draft, kg = otter.DESIGN_DRAFT_M, otter.COM[2]
    nabla = otter.MASS_KG / WATER_DENSITY
    fullness = nabla / (pvs.waterplane_area * draft)  # section area / (beam × draft): 0.534

    def wet(exponent: float) -> np.ndarray:  # the underwater section of a unit beam (deck at the waterline)
        return _section(1.0, exponent, draft, draft)

    lo, hi = 0.2, 1.0  # fullness falls as the exponent grows (1: a V, 0.5)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _area_centroid(wet(mid))[0] / draft > fullness else (lo, mid)
    exponent = 0.5 * (lo + hi)
    kb = _area_centroid(wet(exponent))[1]
    i_l = (pvs.gm_l + kg - kb) * nabla  # waterplane second moments (m⁴) that give his GM at this KB
    i_t = (pvs.gm_t + kg - kb) * nabla
    length = np.sqrt(12.0 * i_l / pvs.waterplane_area)  # two rectangles: I_L = 2 b L³/12, A = 2 b L
    beam = pvs.waterplane_area / (2.0 * length)
    y = np.sqrt((0.5 * i_t - length * beam**3 / 12.0) / (0.5 * pvs.waterplane_area))
    return Pontoons(float(length), float(beam), float(y), exponent, draft, kb)


def pontoon(p: Pontoons, y_center: float, x_center: float) -> Mesh:
    """One closed pontoon: the section swept along x over `STATIONS` stations, flat ends."""
    outline = _section(p.beam, p.exponent, p.draft, DECK_Z_M)
    n = len(outline)
    xs = x_center + p.length * (np.linspace(0.0, 1.0, STATIONS) - 0.5)
    rings = np.empty((STATIONS, n, 3))
    rings[..., 0] = xs[:, None]
    rings[..., 1] = y_center + outline[None, :, 0]
    rings[..., 2] = outline[None, :, 1]
    ends = [[xs[0], y_center, outline[:, 1].mean()], [xs[-1], y_center, outline[:, 1].mean()]]
    verts = np.vstack([rings.reshape(-1, 3), ends])
    faces = []
    for i in range(STATIONS - 1):
        for j in range(n):
            a, b = i * n + j, i * n + (j + 1) % n
            faces += [(a, b, a + n), (b, b + n, a + n)]
    first, last = STATIONS * n, STATIONS * n + 1
    for j in range(n):
        faces += [(first, (j + 1) % n, j), (last, (STATIONS - 1) * n + j, (STATIONS - 1) * n + (j + 1) % n)]
    mesh = Mesh(verts, np.array(faces))
    return mesh if mesh.volume() > 0 else Mesh(mesh.vertices, mesh.faces[:, ::-1])


def build() -> BodyModel:
    p = design()
    x_c = otter.COM[0]  # pontoons centred under the CoM: a prismatic hull floats level there
    left = pontoon(p, p.y, x_c)
    right = left.mirrored_y()
    deck_size, deck_pos = (0.55, p.y, 0.03), (x_c, 0.0, DECK_Z_M - 0.03)
    stern = x_c - 0.5 * p.length - 0.05
    thrusters = tuple(t.model_copy(update={"position": (stern, *t.position[1:])}) for t in otter.thrusters())
    base = otter.build()
    return BodyModel(
        hull=merge([left, right]),
        collision=(Part("mesh", mesh=left), Part("mesh", mesh=right), Part("box", size=deck_size, pos=deck_pos)),
        visuals=(
            Part("mesh", mesh=left, rgba=otter.HULL_RGBA),
            Part("mesh", mesh=right, rgba=otter.HULL_RGBA),
            Part("box", size=deck_size, pos=deck_pos, rgba=(0.15, 0.15, 0.15, 1.0)),
            Part("cylinder", size=(0.02, 0.25), pos=(x_c + 0.3, 0.0, DECK_Z_M + 0.25), rgba=(0.9, 0.9, 0.9, 1.0)),
        ),
        mass_kg=base.mass_kg, com=base.com, inertia=base.inertia, drag=FossenHydrodynamics(parameters="otter"),
        thrusters=thrusters, wind_load=base.wind_load,
    )  # fmt: skip
