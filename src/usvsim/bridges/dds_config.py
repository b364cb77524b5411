"""Cyclone DDS configuration for the bridge, built in code (no file, no environment variable needed).

Default (`interface="lo"`): loopback only, multicast off, 127.0.0.1 as the unicast discovery peer, so no
discovery or data traffic leaves the machine (design.md, network safety). ROS 2 nodes on the same machine
find the simulator through unicast discovery on 127.0.0.1 (Fast DDS and Cyclone both listen on the
well-known per-participant unicast ports). Pass `interface="eth0"` (or another name or address) to
publish on a real network with multicast discovery, or `interface=None` for Cyclone's own choice.

Large samples (images, point clouds, up to tens of MB): on loopback the datagram limit is 64 KiB, so the
bridge sends 60 KiB fragments instead of Cyclone's default 1344 B (50x fewer packets for a VGA image),
asks for 8 MiB socket buffers (`SocketReceiveBufferSize`/`SocketSendBufferSize` min="default", so
Cyclone takes what the kernel grants instead of failing), and lets a reliable writer keep up to 16 MiB of
unacknowledged data before it would block (`WhcHigh`). The kernel caps the socket buffers at
`net.core.rmem_max` / `wmem_max` (often 208 KiB): for clouds and images at camera rates raise them, e.g.
`sysctl -w net.core.rmem_max=8388608 net.core.wmem_max=8388608`; subscribers need the same on their side
(rmw_fastrtps: a Fast DDS XML profile with larger `listenSocketBufferSize`, or on Jazzy+
`FASTDDS_BUILTIN_TRANSPORTS=LARGE_DATA`; rmw_cyclonedds: `SocketReceiveBufferSize`).
"""

from __future__ import annotations

import ipaddress
from xml.sax.saxutils import quoteattr

LOOPBACK_NAMES = ("lo", "lo0", "127.0.0.1", "localhost")
SOCKET_BUFFER = "8MiB"
WHC_HIGH = "16MiB"
MAX_PARTICIPANT_INDEX = 32  # unicast discovery reaches this many participants per host and domain
NAME_MATCHED_VENDORS = "1.15"  # eProsima Fast DDS: match its endpoints by type name, ignore its XTypes data
SPDP_INTERVAL = "1s"  # without multicast, a node started after the bridge is found at the next announcement


def cyclone_config(interface: str | None = "lo", *, socket_buffer: str = SOCKET_BUFFER) -> str:
    """The `<CycloneDDS>` XML for `interface` ("lo" = loopback only, the default)."""
    loopback = interface in LOOPBACK_NAMES
    general = ""
    if interface is not None:
        general += f"<Interfaces><NetworkInterface {_iface(interface)}/></Interfaces>"
    discovery = ""
    if loopback:
        general += "<AllowMulticast>false</AllowMulticast>"
        general += "<MaxMessageSize>65000B</MaxMessageSize><FragmentSize>61440B</FragmentSize>"
        discovery = (
            "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
            f"<MaxAutoParticipantIndex>{MAX_PARTICIPANT_INDEX}</MaxAutoParticipantIndex>"
            f"<SPDPInterval>{SPDP_INTERVAL}</SPDPInterval>"
            '<Peers><Peer address="127.0.0.1"/></Peers></Discovery>'
        )
    internal = (
        f'<Internal><SocketReceiveBufferSize min="default" max={quoteattr(socket_buffer)}/>'
        f'<SocketSendBufferSize min="default" max={quoteattr(socket_buffer)}/>'
        f"<Watermarks><WhcHigh>{WHC_HIGH}</WhcHigh></Watermarks></Internal>"
    )
    return (
        '<CycloneDDS><Domain id="any">'
        f"<Compatibility><IgnoreTypeInformation>{NAME_MATCHED_VENDORS}</IgnoreTypeInformation></Compatibility>"
        f"<General>{general}</General>{discovery}{internal}"
        "</Domain></CycloneDDS>"
    )


def _iface(interface: str) -> str:
    """The NetworkInterface attribute: Cyclone takes an address as `address=`, never as `name=`."""
    if interface in ("localhost", "127.0.0.1"):
        return 'name="lo"'
    try:
        ipaddress.ip_address(interface)
    except ValueError:
        return f"name={quoteattr(interface)}"
    return f"address={quoteattr(interface)}"
