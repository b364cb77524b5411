"""Marine message definitions registered in the typestore beside vision_msgs (so CDR, MCAP schemas, DDS
types and Foxglove channels work for them like for any ROS 2 type):

- `marine_sensor_msgs/RadarSector` and `RadarEcho` (apl-ocean-iss/marine_msgs, ROS 2): one radar sector,
  `intensities[k].echoes[j]` is the return of azimuth angle_start + k·angle_increment in range bin j;
- `nmea_msgs/Sentence` (ros-drivers/nmea_msgs, ROS 2): one NMEA 0183 sentence, e.g. an `!AIVDM` AIS report;
- `usvsim_msgs/TrafficTarget`, `TrafficSituation`: ground-truth situational awareness of the own ship;
- `usvsim_msgs/RadarTrack`, `RadarTrackArray`: an ARPA-style target list from the radar tracker.

Units: SI, radians. Bearings and courses are nautical (clockwise from north; relative bearings clockwise
from the own ship's heading, starboard positive), as on a radar display and in AIS, with north the world frame's y
axis (grid north: AIS's true courses differ from them by the meridians' convergence away from the world origin). `cpa` (m) and `tcpa` (s) of
both target types are the straight-line prediction from the relative position and velocity, given for every
target as an ARPA shows them: tcpa < 0: opening, the closest point is past; tcpa = 0 with cpa = range: no
relative motion. A CPA is a warning only with its TCPA: the alarm rule (cpa < a limit and 0 <= tcpa <= a limit)
is the receiver's, as the run report's (`traffic.awareness.tcpa_limit_s`).
"""

from __future__ import annotations

MARINE_MSGS = {
    "marine_sensor_msgs/msg/RadarEcho": "float32[] echoes\n",
    "marine_sensor_msgs/msg/RadarSector": (
        "std_msgs/Header header\nfloat32 angle_start\nfloat32 angle_increment\n"
        "builtin_interfaces/Duration time_increment\nbuiltin_interfaces/Duration scan_time\n"
        "float32 range_min\nfloat32 range_max\nmarine_sensor_msgs/RadarEcho[] intensities\n"
    ),
    "nmea_msgs/msg/Sentence": "std_msgs/Header header\nstring sentence\n",
    "usvsim_msgs/msg/TrafficTarget": (
        "uint8 NONE=0\nuint8 HEAD_ON=1\nuint8 CROSSING_GIVE_WAY=2\nuint8 CROSSING_STAND_ON=3\n"
        "uint8 OVERTAKING=4\nuint8 OVERTAKEN=5\n"
        "string name\nuint32 mmsi\ngeometry_msgs/Point position\ngeometry_msgs/Vector3 velocity\n"
        "float64 course\nfloat64 speed\nfloat64 heading\nfloat64 range\nfloat64 bearing\n"
        "float64 relative_bearing\nfloat64 cpa\nfloat64 tcpa\nuint8 encounter\n"
    ),
    "usvsim_msgs/msg/TrafficSituation": (
        "std_msgs/Header header\nstring own_ship\ngeometry_msgs/Point own_position\n"
        "geometry_msgs/Vector3 own_velocity\nfloat64 own_heading\nusvsim_msgs/TrafficTarget[] targets\n"
    ),
    "usvsim_msgs/msg/RadarTrack": (
        "uint32 id\nfloat64 range\nfloat64 bearing\nfloat64 course\nfloat64 speed\nfloat64 cpa\nfloat64 tcpa\n"
        "geometry_msgs/Point position\ngeometry_msgs/Vector3 velocity\nuint32 hits\n"
    ),
    "usvsim_msgs/msg/RadarTrackArray": "std_msgs/Header header\nusvsim_msgs/RadarTrack[] tracks\n",
}
