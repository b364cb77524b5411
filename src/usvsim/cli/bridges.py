"""Start the live bridges `usvsim run` asks for (each an optional extra, imported only when asked for)."""

from __future__ import annotations

import os
from dataclasses import dataclass

from usvsim.core.errors import UsvsimError


@dataclass(frozen=True)
class BridgeOptions:
    """The `usvsim run` bridge options (their defaults and help live on the CLI options)."""

    ros2: bool
    domain_id: int | None  # None: $ROS_DOMAIN_ID, else 0
    ros2_interface: str
    ros_tcp: str | None  # HOST:PORT of a ros_tcp_endpoint
    ros_tcp_profile: str
    ros_tcp_vessel: str | None  # the vessel the seed profile renames (None: the first)
    foxglove: bool
    foxglove_host: str
    foxglove_port: int
    foxglove_max_clients: int = 16

    def check_used(self, given: set[str]) -> None:
        """A UsvsimError for a bridge option given (`given`: the names of the options away from their defaults) without
        its bridge: it was ignored in silence (e.g. `--ros-tcp-profile seed` without `--ros-tcp`)."""
        bridges = {"--ros2": self.ros2, "--ros-tcp": self.ros_tcp is not None, "--foxglove": self.foxglove}
        needs = {"domain_id": "--ros2", "ros2_interface": "--ros2", "ros_tcp_profile": "--ros-tcp",
                 "ros_tcp_vessel": "--ros-tcp", "foxglove_host": "--foxglove", "foxglove_port": "--foxglove",
                 "foxglove_max_clients": "--foxglove"}  # fmt: skip
        for name, bridge in needs.items():
            if name in given and not bridges[bridge]:
                raise UsvsimError(f"--{name.replace('_', '-')} applies to {bridge}, which is not on: add {bridge}")


def host_port(text: str) -> tuple[str, int]:
    """`HOST:PORT` → (host, port), or a UsvsimError saying what is wrong."""
    host, sep, port = text.rpartition(":")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise UsvsimError(f"--ros-tcp expects HOST:PORT (e.g. 127.0.0.1:10000), got {text!r}")
    return host, int(port)


def check_interface(interface: str) -> None:
    """A UsvsimError unless `interface` is a network interface of this machine or an IP address (Cyclone DDS
    would fail with a bare 'DDS_RETCODE_ERROR' traceback)."""
    import ipaddress
    import socket

    from usvsim.bridges.dds_config import LOOPBACK_NAMES

    names = [name for _, name in socket.if_nameindex()]
    if interface in LOOPBACK_NAMES or interface in names:
        return
    try:
        ipaddress.ip_address(interface)
    except ValueError:
        raise UsvsimError(f"--ros2-interface: no network interface {interface!r} on this machine "
                          f"(interfaces: {', '.join(names)}; 'any' lets Cyclone DDS choose)") from None  # fmt: skip


def _extra(module: str, extra: str):
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise UsvsimError(f"{exc.name or module} is not installed: pip install 'usvsim[{extra}]'") from None


MAX_DOMAIN_ID = 232  # ROS 2's range: with Cyclone's port mapping, domains above it have no valid ports


def domain_id(given: int | None) -> int:
    """--domain-id, else $ROS_DOMAIN_ID, else 0; a bad $ROS_DOMAIN_ID is a one-line error (it was the text of
    int()'s ValueError, or a DDS_RETCODE_ERROR traceback for 999)."""
    if given is not None:
        return given
    text = os.environ.get("ROS_DOMAIN_ID", "").strip()
    if not text:
        return 0
    if not (text.isdigit() and int(text) <= MAX_DOMAIN_ID):
        raise UsvsimError(f"$ROS_DOMAIN_ID must be a whole number from 0 to {MAX_DOMAIN_ID}, got {text[:40]!r} "
                          "(or give --domain-id)")  # fmt: skip
    return int(text)


def open_bridges(sim, options: BridgeOptions) -> list:
    """The bridges `options` asks for, attached to `sim`; each has `close()` and `stats`."""
    bridges = []
    try:
        if options.ros2:
            dds = _extra("usvsim.bridges.dds", "ros2")
            interface = None if options.ros2_interface in ("", "any") else options.ros2_interface
            if interface is not None:
                check_interface(interface)
            bridges.append(dds.DdsBridge(sim, domain_id=domain_id(options.domain_id), interface=interface))
        if options.ros_tcp:
            from usvsim.bridges.ros_tcp import RosTcpBridge

            host, port = host_port(options.ros_tcp)
            bridges.append(RosTcpBridge(sim, host, port, options.ros_tcp_profile, options.ros_tcp_vessel))
        if options.foxglove:
            fox = _extra("usvsim.bridges.foxglove", "ros2")
            bridges.append(
                fox.FoxgloveBridge(
                    sim,
                    host=options.foxglove_host,
                    port=options.foxglove_port,
                    max_clients=options.foxglove_max_clients,
                )
            )
    except ValueError as exc:  # a bad option value (profile, vessel name, port)
        close_all(bridges)
        raise UsvsimError(str(exc)) from None
    except BaseException:
        close_all(bridges)
        raise
    return bridges


def close_all(bridges: list) -> None:
    for bridge in reversed(bridges):
        bridge.close()
