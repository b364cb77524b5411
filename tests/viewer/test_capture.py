"""Screenshots on the P key (viewer/capture.py), without a window: names never overwrite an earlier file."""

from __future__ import annotations

import pytest

from usvsim.viewer.capture import Capture


class _Window:
    """Stands in for the viewer's window: a screenshot writes the frame's number."""

    def __init__(self):
        self.shots = 0

    def screenshot(self, path):
        self.shots += 1
        path.write_text(str(self.shots))


def test_screenshots_at_the_same_time_get_a_counter_suffix(tmp_path):
    """P pressed three times while paused (same simulated time) printed three 'saved' lines and left one file,
    the last: the names were time-based only. A file from an earlier session is kept too."""
    (tmp_path / "usvsim_harbor_00012.500s_2.png").write_text("earlier session")
    capture, window = Capture("harbor", tmp_path), _Window()
    for _ in range(3):
        capture.frame(window, 12.5, screenshot_requested=True)
    capture.frame(window, 13.0, screenshot_requested=True)
    names = [p.name for p in capture.saved]
    assert names == ["usvsim_harbor_00012.500s.png", "usvsim_harbor_00012.500s_3.png",
                     "usvsim_harbor_00012.500s_4.png", "usvsim_harbor_00013.000s.png"]  # fmt: skip
    assert [p.read_text() for p in capture.saved] == ["1", "2", "3", "4"]
    assert (tmp_path / "usvsim_harbor_00012.500s_2.png").read_text() == "earlier session"


@pytest.mark.parametrize(
    ("options", "words"),
    [({"time_scale": 0.0}, "time_scale"), ({"time_scale": -1.0}, "time_scale"),
     ({"max_seconds": float("nan")}, "max_seconds"), ({"max_seconds": -5.0}, "max_seconds"),
     ({"screenshot": "shot.txt"}, ".png"), ({"video": "run.gif"}, ".mp4 or .avi")],
)  # fmt: skip
def test_run_viewer_refuses_bad_options_before_the_window(monkeypatch, options, words):
    """time_scale 0 or below never stepped (the window hung until killed); max_seconds NaN was a ValueError
    traceback and -5 ran one frame; a screenshot name Pillow cannot write failed after the whole run."""
    from usvsim.core.errors import UsvsimError
    from usvsim.simulation import Simulation
    from usvsim.viewer import app

    def no_window(*_args, **_kwargs):
        raise AssertionError("the window opened although an option was bad")

    monkeypatch.setattr(app, "ViewerWindow", no_window)
    with pytest.raises(UsvsimError, match=words):
        app.run_viewer(Simulation.from_scenario("harbor"), **options)
