"""How the PVS reference numbers in test_otter_pvs.py were made (not part of the suite: it needs a checkout of
Fossen's PythonVehicleSimulator, github.com/cybergalactic/PythonVehicleSimulator, commit c717e07).

PVS's own code, unmodified, does the work: `otter()` in step-input mode with its `stepInput` replaced by a constant
command, integrated by PVS's `mainLoop.simulate` (h = 0.02 s) for 120 s from rest; steady values are the mean of the
last 10 s (they vary by < 1e-15 there). One run-time setting: `vehicle.mp = 0` after construction switches off PVS's
payload-weight double count (the payload's weight g_0 added on top of a restoring matrix whose equilibrium already
holds it: physics.md §3.2, quirk 2); `mp` is read after construction only for g_0, so mass, centre of gravity and
inertia keep the payload, as usvsim's otter_pvs does. Velocities at Fossen's CO, converted from NED body (FRD) to FLU.

    python tests/sim/pvs_reference_runs.py /path/to/PythonVehicleSimulator/src
"""

from __future__ import annotations

import sys

import numpy as np


def steady(n_left: float, n_right: float) -> tuple[float, float, float, float]:
    """PVS's steady (u, v, r) at CO, FLU (m/s, m/s, rad/s), and the turning diameter 2U/|r| m (inf if straight)."""
    from python_vehicle_simulator.lib.mainLoop import simulate
    from python_vehicle_simulator.vehicles.otter import otter

    vehicle = otter()
    vehicle.mp = 0.0  # no payload-weight double count (see the module text)
    command = np.array([n_left, n_right], float)
    vehicle.stepInput = lambda t: command
    _, data = simulate(6000, 0.02, vehicle)
    last = data[-500:, 6:12]
    u, v, r = last[:, 0].mean(), -last[:, 1].mean(), -last[:, 5].mean()  # FRD → FLU
    return float(u), float(v), float(r), (2 * float(np.hypot(u, v)) / abs(r) if abs(r) > 1e-12 else float("inf"))


if __name__ == "__main__":
    sys.path.insert(0, sys.argv[1])
    for n in ((80.0, 120.0), (103.930864, 51.965432), (51.965432, 51.965432), (60.0, 60.0)):
        print(n, tuple(round(x, 6) for x in steady(*n)))
