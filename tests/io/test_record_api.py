"""`with sim.record(path):` writes the file `usvsim run --record` writes: the same channels (topic, type, QoS
metadata), schemas and messages (log time and bytes) for the same scenario, seed and duration."""

from __future__ import annotations

from pathlib import Path

from mcap.reader import make_reader
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.simulation import Simulation


def contents(path: Path):
    with path.open("rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        channels = sorted((c.topic, c.message_encoding, sorted(c.metadata.items()), summary.schemas[c.schema_id].name,
                           summary.schemas[c.schema_id].data) for c in summary.channels.values())  # fmt: skip
        messages = [(channel.topic, message.log_time, message.publish_time, message.data)
                    for _, channel, message in reader.iter_messages(log_time_order=False)]  # fmt: skip
    return channels, messages


def test_python_recording_equals_the_cli_recording(tmp_path):
    cli_path, api_path = tmp_path / "cli.mcap", tmp_path / "api.mcap"
    result = CliRunner().invoke(app, ["run", "harbor", "--seed", "4", "--duration", "2", "--record", str(cli_path)])
    assert result.exit_code == 0, result.output
    sim = Simulation.from_scenario("harbor", seed=4)
    try:
        with sim.record(api_path):
            sim.run(2.0)
    finally:
        sim.close()
    cli, api = contents(cli_path), contents(api_path)
    assert len(cli[1]) > 200  # /clock, /tf, odometry... over 2 s
    assert api[0] == cli[0]
    assert api[1] == cli[1]
