"""A stand-in for a VRX team's ROS 2 stack, in its own process and DDS participant (test_live_ros2.py).

No usvsim import: the message types are written here by hand as cyclonedds IDL structs with ROS 2 naming,
and Cyclone is pinned to loopback with multicast off. It subscribes to /clock and /vrx/task/info, reports each
perception object with
geographic_msgs/GeoPoseStamped on /vrx/perception/landmark while the object is shown (its window in
simulation time, from /clock), plus one bad report (NaN latitude), then pushes the WAM-V with VRX's thruster
topics (N): objects appear at offsets from the boat where it is then, so the boat stays at its start pose (where
the given positions are) until the last one is reported. Prints one JSON line when /clock stops.

    python vrx_peer.py DOMAIN 'JSON [[class, t_s, duration_s, lat, lon], ...]' THRUST_N
"""
# no `from __future__ import annotations`: cyclonedds resolves the field types at run time
import json
import math
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import Qos
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl import annotations as annotate
from cyclonedds.idl.types import float64, int32, int64, sequence, uint8, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

LOOPBACK = ('<CycloneDDS><Domain id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces>'
            "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
            "<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex><SPDPInterval>1s</SPDPInterval>"
            '<Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>')  # fmt: skip


@annotate.final
@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@annotate.final
@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@annotate.final
@dataclass
class ParameterValue(IdlStruct, typename="rcl_interfaces::msg::dds_::ParameterValue_"):
    type: uint8
    bool_value: bool
    integer_value: int64
    double_value: float64
    string_value: str
    byte_array_value: sequence[uint8]
    bool_array_value: sequence[bool]
    integer_array_value: sequence[int64]
    double_array_value: sequence[float64]
    string_array_value: sequence[str]


@annotate.final
@dataclass
class Parameter(IdlStruct, typename="rcl_interfaces::msg::dds_::Parameter_"):
    name: str
    value: ParameterValue


@annotate.final
@dataclass
class ParamVec(IdlStruct, typename="ros_gz_interfaces::msg::dds_::ParamVec_"):
    header: Header
    params: sequence[Parameter]


@annotate.final
@dataclass
class Clock(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    clock: Time


@annotate.final
@dataclass
class Float64(IdlStruct, typename="std_msgs::msg::dds_::Float64_"):
    data: float64


@annotate.final
@dataclass
class GeoPoint(IdlStruct, typename="geographic_msgs::msg::dds_::GeoPoint_"):
    latitude: float64
    longitude: float64
    altitude: float64


@annotate.final
@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@annotate.final
@dataclass
class GeoPose(IdlStruct, typename="geographic_msgs::msg::dds_::GeoPose_"):
    position: GeoPoint
    orientation: Quaternion


@annotate.final
@dataclass
class GeoPoseStamped(IdlStruct, typename="geographic_msgs::msg::dds_::GeoPoseStamped_"):
    header: Header
    pose: GeoPose


def value(v: ParameterValue):
    return {1: v.bool_value, 2: v.integer_value, 3: v.double_value, 4: v.string_value}.get(v.type)


def main(domain_id: int, objects: list, thrust_n: float) -> dict:
    domain = Domain(domain_id, LOOPBACK)  # keep it: a collected Domain object is deleted
    dp = DomainParticipant(domain_id)
    qos = Qos(Policy.Reliability.Reliable(duration(milliseconds=100)), Policy.Durability.Volatile,
              Policy.History.KeepLast(10), Policy.DataRepresentation(use_cdrv0_representation=True))  # fmt: skip
    clock = DataReader(dp, Topic(dp, "rt/clock", Clock), qos=qos)
    info = DataReader(dp, Topic(dp, "rt/vrx/task/info", ParamVec), qos=qos)
    thrust = [DataWriter(dp, Topic(dp, f"rt/wamv/thrusters/{s}/thrust", Float64), qos=qos) for s in ("left", "right")]
    landmark = DataWriter(dp, Topic(dp, "rt/vrx/perception/landmark", GeoPoseStamped), qos=qos)
    deadline = time.monotonic() + 120.0  # discovery on a loaded machine
    while landmark.get_publication_matched_status().current_count == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    print("READY", flush=True)
    infos, sim_s, last_clock, reported, bad_sent = [], -1.0, time.monotonic(), set(), False
    while time.monotonic() - last_clock < 2.0:  # until the simulation stops publishing /clock
        for sample in clock.take(N=100):
            if not isinstance(sample, Clock):  # an InvalidSample: the writer went away
                continue
            sim_s, last_clock = sample.clock.sec + sample.clock.nanosec * 1e-9, time.monotonic()
        for sample in info.take(N=10):
            if isinstance(sample, ParamVec):
                infos.append({p.name: value(p.value) for p in sample.params})
        for w in thrust:  # ahead once every object is reported: they appear relative to the boat (VRX's
            w.write(Float64(thrust_n if len(reported) == len(objects) else 0.0))  # StartTrial), the start pose here
        for kind, t0, dur, lat, lon in objects:
            if t0 + 0.15 * dur < sim_s < t0 + 0.5 * dur and kind not in reported:  # shown now: report it once
                header = Header(Time(int(sim_s), int(sim_s % 1 * 1e9)), kind)
                landmark.write(GeoPoseStamped(header, GeoPose(GeoPoint(lat, lon, 0.0), Quaternion(0, 0, 0, 1))))
                reported.add(kind)
        if sim_s > 0.5 and not bad_sent:
            landmark.write(GeoPoseStamped(Header(Time(0, 0), "mb_marker_buoy_red"),
                                          GeoPose(GeoPoint(math.nan, 0.0, 0.0), Quaternion(0, 0, 0, 1))))  # fmt: skip
            bad_sent = True
        time.sleep(0.02)
    del domain
    return {"infos": infos, "last_sim_s": sim_s, "reported": sorted(reported)}


if __name__ == "__main__":
    print("RESULT " + json.dumps(main(int(sys.argv[1]), json.loads(sys.argv[2]), float(sys.argv[3]))), flush=True)
