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
     ({"screenshot": "shot.txt"}, ".png"), ({"video": "run.gif"}, ".mp4 or .avi"),
     ({"vessel": "nemo"}, "no vessel 'nemo' to follow")],
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


def test_the_video_runs_on_simulated_time(tmp_path, monkeypatch):
    """One frame per drawn frame at a nominal 30 fps played 1 s simulated in 0.4 s (12 frames drawn). Now a frame
    per 1/30 s of simulated time: the latest drawn frame repeated, extra frames left out, a pause left out."""
    import numpy as np

    from usvsim.viewer import capture as capture_module

    written = []

    class Writer:
        def write(self, bgr):
            written.append(int(bgr[0, 0, 0]))

        def release(self):
            pass

    monkeypatch.setattr(capture_module, "_open_writer", lambda *args: Writer())

    class Window:
        viewport = None

        def __init__(self):
            self.renderer = self
            self.value = 0

        def read_rgb(self, _viewport):
            return np.full((4, 4, 3), self.value, np.uint8)

    capture, window = Capture("harbor", tmp_path, video=tmp_path / "v.mp4", fps=10.0), Window()
    for t in (0.0, 0.25, 0.26, 0.27, 1.0, 1.0, 1.0):  # slow frames, fast frames, then paused at 1 s
        window.value = round(t * 100) % 256
        capture.frame(window, t, screenshot_requested=False)
    assert written == [0, 25, 25] + [100] * 8  # t = 0, 0.1, ..., 1.0: 11 frames, each the latest drawn
    window.value = 7
    capture.frame(window, 0.0, screenshot_requested=False)  # a reset: the clock starts again, the video goes on
    assert written[-1] == 7 and len(written) == 12


def test_the_viewer_on_a_scenario_without_vessels_is_one_error(monkeypatch):
    """`usvsim run buoys.yaml --view` with objects only ended in a StopIteration traceback."""
    from usvsim.config.loader import parse_scenario
    from usvsim.core.errors import UsvsimError
    from usvsim.simulation import Simulation
    from usvsim.viewer import app

    monkeypatch.setattr(app, "ViewerWindow", None)
    data = {"version": 1, "name": "buoys", "objects": [{"type": "buoy", "name": "b1", "position": [5.0, 0.0, 0.0]}]}
    with pytest.raises(UsvsimError, match="'buoys' has none"):
        app.run_viewer(Simulation(parse_scenario(data, "buoys.yaml")))
