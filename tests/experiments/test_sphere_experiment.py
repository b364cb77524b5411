"""The sphere experiment runs, writes its files and meets the seed's figures."""

from __future__ import annotations

import json

import numpy as np

from usvsim.experiments import sphere


def test_sphere_experiment(tmp_path):
    result = sphere.run(tmp_path)
    assert (tmp_path / "sphere.png").stat().st_size > 10_000
    saved = json.loads((tmp_path / "sphere.json").read_text())
    assert saved["table"] == result["table"]
    assert "m³" in saved["units"] and "ENU" in saved["units"]
    assert [row["faces"] for row in result["table"]] == [80, 320, 1280, 5120]
    for row in result["table"]:
        assert row["max_rel_err_vs_clipped"] <= 1e-9
        assert row["max_cob_err_vs_clipped_m"] <= 1e-9  # the centre of buoyancy was not checked at all
        assert row["kernel_exact"] and row["pass"]
    assert result["passed"]
    assert len(saved["curves"]["5120"]["volume_m3"]) == len(saved["depths_m"]) == 401
    # physics.md §2.3, 1280-face icosphere: centre of buoyancy z at d = 0.25, 0.5, 0.75 m (5 decimals)
    got = [z for z, _ in saved["cob_z_1280_vs_physics_md_m"].values()]
    np.testing.assert_allclose(got, [-0.08699, -0.18696, -0.31202], atol=1e-5)
    # fully immersed 80-face icosphere: 4486.496 N / (rho g) (physics.md §1.10)
    assert abs(saved["curves"]["80"]["volume_m3"][-1] - 4486.496 / 9810.0) < 1e-7


def test_cap_volume_is_archimedes_cap():
    r = sphere.RADIUS_M
    np.testing.assert_allclose(
        sphere.cap_volume_m3(np.array([0.0, r, 2 * r, 3 * r])),
        [0.0, 2 / 3 * np.pi * r**3, 4 / 3 * np.pi * r**3, 4 / 3 * np.pi * r**3],
    )
