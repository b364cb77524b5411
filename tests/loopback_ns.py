"""Run a command in a loopback-only network namespace with a private /dev/shm (for real ROS 2 peers).

`unshare -n -m`: the only interface is `lo` (multicast on, so Fast DDS's default discovery works and cannot
leave the machine), and a fresh tmpfs on /dev/shm, so Fast DDS's shared-memory transport neither meets other
processes' participants on this machine nor stale port segments left by killed ones (which can push its
participant id beyond the ports the simulation's unicast discovery reaches).
"""

from __future__ import annotations

import shutil
import subprocess

SETUP = (
    "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo && "
    "mount -t tmpfs -o size=512m usvsim-shm /dev/shm && exec \"$@\""
)


def isolated(*cmd: str) -> list[str]:
    """`cmd` wrapped to run in the namespace."""
    return ["unshare", "-n", "-m", "sh", "-c", SETUP, "sh", *cmd]


def unusable() -> str | None:
    """Why the namespace cannot be made here, or None."""
    if shutil.which("unshare") is None or shutil.which("ip") is None:
        return "unshare/ip not installed"
    probe = subprocess.run(isolated("true"), capture_output=True, text=True)
    return None if probe.returncode == 0 else f"cannot create a loopback-only namespace: {probe.stderr.strip()}"
