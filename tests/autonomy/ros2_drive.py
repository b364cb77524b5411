"""The ROS 2 side of test_ros2_node.py; runs inside a loopback-only network namespace.

`usvsim run SCENARIO --ros2 --realtime --record OUT.mcap` (Cyclone DDS) and the stack as an rclpy node
(`python -m usvsim.autonomy.ros2_node --ros2`, Fast DDS) in two processes: the node maps from the
PointCloud2 it receives and drives the boat over `cmd_vel` until it reports its goal reached.
Prints `RESULT {...}` with the node's report; the recording then holds the true track.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

FASTDDS_PROFILE = """<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com"><profiles>
  <participant profile_name="usvsim_test" is_default_profile="true"><rtps>
    <propertiesPolicy><properties><property><name>fastdds.type_propagation</name><value>disabled</value>
    </property></properties></propertiesPolicy>
  </rtps></participant>
</profiles></dds>
"""


def main(scenario: str, goal: str, record: str, limit_s: float) -> None:
    tmp = Path(record).parent
    (tmp / "fastdds.xml").write_text(FASTDDS_PROFILE)
    sim = subprocess.Popen([sys.executable, "-m", "usvsim.cli", "run", scenario, "--ros2", "--realtime",
                            "--duration", str(limit_s), "--record", record],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)  # fmt: skip
    env = dict(os.environ, RMW_IMPLEMENTATION="rmw_fastrtps_cpp", FASTDDS_DEFAULT_PROFILES_FILE=str(tmp / "fastdds.xml"),
               ROS_DOMAIN_ID="0")  # fmt: skip
    node = subprocess.Popen([sys.executable, "-m", "usvsim.autonomy.ros2_node", "--ros2", "--goals", goal,
                             "--odometry", "sensor", "--bounds=-25,-15,25,15", "--exit-when-done"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        out, err = node.communicate(timeout=limit_s + 60)
    except subprocess.TimeoutExpired:
        node.kill()
        out, err = node.communicate()
    time.sleep(1.0)
    sim.send_signal(signal.SIGINT)  # Ctrl-C: the run stops between steps and the recorder closes its file
    sim.wait(timeout=60)
    lines = [ln for ln in out.splitlines() if ln.startswith("RESULT ")]
    report = json.loads(lines[-1][7:]) if lines else {"error": err[-2000:]}
    print("RESULT " + json.dumps(report), flush=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]))
