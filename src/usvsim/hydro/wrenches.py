"""Per-step kinematics of the floating bodies and assembly of their marine wrenches (numba kernels).

MuJoCo free joints: qpos = (position of the MuJoCo body frame origin, world; quaternion w, x, y, z body→world),
qvel = (linear velocity of that origin, world frame; angular velocity, body frame). Floating bodies have their
MuJoCo frame at the centre of mass (world/builder.py), axes along base_link: base_link = CoM - R com_body.
"""

from __future__ import annotations

from numba import njit

from usvsim.hydro.statespace import drag_wrench
from usvsim.hydro.thrusters import thruster_step
from usvsim.hydro.wind import wind_wrenches


@njit(cache=True)
def body_kinematics(qpos, qvel, qpos_adr, qvel_adr, com_body, pos, rot, com_world, vcom_world, omega_body):
    """Pose of base_link, rotation matrix, CoM position and CoM velocity (world) and body angular velocity of each
    body (the free joint's origin is the CoM)."""
    for i in range(qpos_adr.shape[0]):
        a, b = qpos_adr[i], qvel_adr[i]
        w, x, y, z = qpos[a + 3], qpos[a + 4], qpos[a + 5], qpos[a + 6]
        n = (w * w + x * x + y * y + z * z) ** 0.5
        w, x, y, z = w / n, x / n, y / n, z / n
        rot[i, 0, 0] = 1 - 2 * (y * y + z * z)
        rot[i, 0, 1] = 2 * (x * y - w * z)
        rot[i, 0, 2] = 2 * (x * z + w * y)
        rot[i, 1, 0] = 2 * (x * y + w * z)
        rot[i, 1, 1] = 1 - 2 * (x * x + z * z)
        rot[i, 1, 2] = 2 * (y * z - w * x)
        rot[i, 2, 0] = 2 * (x * z - w * y)
        rot[i, 2, 1] = 2 * (y * z + w * x)
        rot[i, 2, 2] = 1 - 2 * (x * x + y * y)
        cx = com_body[i, 0] * rot[i, 0, 0] + com_body[i, 1] * rot[i, 0, 1] + com_body[i, 2] * rot[i, 0, 2]
        cy = com_body[i, 0] * rot[i, 1, 0] + com_body[i, 1] * rot[i, 1, 1] + com_body[i, 2] * rot[i, 1, 2]
        cz = com_body[i, 0] * rot[i, 2, 0] + com_body[i, 1] * rot[i, 2, 1] + com_body[i, 2] * rot[i, 2, 2]
        for k in range(3):
            com_world[i, k] = qpos[a + k]
            vcom_world[i, k] = qvel[b + k]
            omega_body[i, k] = qvel[b + 3 + k]
        pos[i, 0], pos[i, 1], pos[i, 2] = com_world[i, 0] - cx, com_world[i, 1] - cy, com_world[i, 2] - cz


@njit(cache=True)
def relative_velocity_body(rot, vcom_world, omega_body, water_vel_world, nu_out):
    """nu = (R^T (v_com - v_water), omega_body): body-frame velocity relative to the water."""
    for i in range(rot.shape[0]):
        dx = vcom_world[i, 0] - water_vel_world[i, 0]
        dy = vcom_world[i, 1] - water_vel_world[i, 1]
        dz = vcom_world[i, 2] - water_vel_world[i, 2]
        for k in range(3):
            nu_out[i, k] = rot[i, 0, k] * dx + rot[i, 1, k] * dy + rot[i, 2, k] * dz
            nu_out[i, 3 + k] = omega_body[i, k]


@njit(cache=True)
def assemble(rot, body_wrenches, world_force, world_torque, out):
    """out[i] = world force and torque about the CoM: hydrostatics (world) + sum of body-frame wrenches
    rotated to the world. body_wrenches: (m, nb, 6) list of body-frame wrench tables."""
    for i in range(rot.shape[0]):
        for k in range(3):
            out[i, k] = world_force[i, k]
            out[i, 3 + k] = world_torque[i, k]
        for j in range(body_wrenches.shape[0]):
            for k in range(3):
                f = rot[i, k, 0] * body_wrenches[j, i, 0] + rot[i, k, 1] * body_wrenches[j, i, 1]
                f += rot[i, k, 2] * body_wrenches[j, i, 2]
                t = rot[i, k, 0] * body_wrenches[j, i, 3] + rot[i, k, 1] * body_wrenches[j, i, 4]
                t += rot[i, k, 2] * body_wrenches[j, i, 5]
                out[i, k] += f
                out[i, 3 + k] += t


@njit(cache=True)
def immersion_scale(volume, rest_volume, wrench):
    """Fade each body's hydrodynamic damping wrench (nb,6) as its hull leaves the water: in full while at least half
    its displacement at rest (`rest_volume`, m³) is under water (`volume`, m³: the active buoyancy model's), then
    in proportion down to none in the air. Damping identified on the floating hull acted in full on a hull out of
    the water (an Otter dropped from 20 m fell at 1.3 m/s; one in steep waves was carried 35 m up by the water's
    velocity); above half immersion nothing changes, bit for bit."""
    for i in range(wrench.shape[0]):
        s = 2.0 * volume[i] / rest_volume[i]
        if s < 1.0:
            for k in range(6):
                wrench[i, k] *= s


@njit(cache=True)
def marine_tail(rot, vcom_world, omega_body, water_vel_world, nu, hs_force, hs_torque, hs_volume, rest_volume,
                ss_coef, wind_kind, wind_coef, rho_air, wind_world, thruster_params, cmd_u, cmd_angle, last_cmd_ns,
                timeout_ns, thrust, angle, wet, thruster_body, com_body, world_force, world_torque, volume, body_wrench,
                scratch, thrust_wrench, xfrc, now_ns, dt):  # fmt: skip
    """One call for what follows the hydrostatics when a body has neither Kerner, Fossen nor voxel models
    (world/world.py's simple step), the same operations in the same order as the separate kernels:
    relative velocity `nu`; world_force/torque and volume = the hydrostatics'; body_wrench = state-space drag
    (faded out of the water, `immersion_scale`) + wind (statespace.py, wind.py); thrust_wrench = the thrusters'
    (thrusters.py, dynamics advanced); xfrc (nb,6) = world wrench about each CoM (`assemble`)."""
    relative_velocity_body(rot, vcom_world, omega_body, water_vel_world, nu)
    world_force[:] = hs_force
    world_torque[:] = hs_torque
    volume[:] = hs_volume
    drag_wrench(ss_coef, nu, body_wrench)
    immersion_scale(volume, rest_volume, body_wrench)
    wind_wrenches(wind_kind, wind_coef, rho_air, rot, vcom_world, wind_world, scratch)
    body_wrench += scratch
    thruster_step(thruster_params, cmd_u, cmd_angle, last_cmd_ns, timeout_ns, now_ns, dt, thrust, angle, wet,
                  thruster_body, com_body, thrust_wrench)  # fmt: skip
    for i in range(rot.shape[0]):  # assemble() over (body_wrench, thrust_wrench)
        for k in range(3):
            xfrc[i, k] = world_force[i, k]
            xfrc[i, 3 + k] = world_torque[i, k]
        for w in (body_wrench, thrust_wrench):
            for k in range(3):
                f = rot[i, k, 0] * w[i, 0] + rot[i, k, 1] * w[i, 1]
                f += rot[i, k, 2] * w[i, 2]
                t = rot[i, k, 0] * w[i, 3] + rot[i, k, 1] * w[i, 4]
                t += rot[i, k, 2] * w[i, 5]
                xfrc[i, k] += f
                xfrc[i, 3 + k] += t

