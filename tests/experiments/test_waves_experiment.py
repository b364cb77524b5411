"""`usvsim experiment waves` passes its acceptance checks and writes its outputs."""

import json

from usvsim.experiments import waves


def test_waves_experiment(tmp_path):
    result = waves.run(tmp_path)
    assert result["passed"], json.dumps(result, indent=1)
    record = result["jonswap_point_record"]
    assert abs(record["hs_error"]) <= 0.03 and abs(record["tp_error"]) <= 0.05
    for t in ("t=0", "t=2"):
        entry = result["worked_example_4_6"][t]
        assert abs(entry["height_m"] - entry["reference_m"]) < 1e-3
    assert max(result["dispersion"]["max_relative_error"].values()) < 1e-3
    assert json.loads((tmp_path / "waves.json").read_text())["passed"]
    assert (tmp_path / "waves.png").stat().st_size > 10_000
