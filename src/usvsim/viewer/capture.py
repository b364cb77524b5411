"""What the viewer saves besides the window: screenshots on the P key and an optional video.

Screenshots go to `shots_dir` as `usvsim_<scenario>_<sim time>s.png`, or `..._<sim time>s_2.png`, `_3`, ... when
that name is taken (P pressed twice while paused overwrote the first). The video (`--video FILE`, MP4 or
AVI) runs on simulated time at `fps` frames per simulated second; OpenCV writes it (imported only when asked for).
"""

from __future__ import annotations

import sys
from pathlib import Path

from usvsim.core.errors import UsvsimError


class Capture:
    def __init__(self, scenario_name: str, shots_dir: Path = Path("."), video: Path | None = None,
                 fps: float = 30.0):  # fmt: skip
        self.name, self.shots_dir, self.video_path, self.fps = scenario_name, Path(shots_dir), video, fps
        self._writer = None
        self._next_s: float | None = None  # simulated time of the video's next frame
        self._last_s = 0.0
        self.saved: list[Path] = []

    def frame(self, window, sim_time_s: float, screenshot_requested: bool) -> None:
        """Call after drawing, before swapping buffers."""
        if screenshot_requested:
            path = self.shot_path(sim_time_s)
            window.screenshot(path)
            self.saved.append(path)
            print(f"usvsim: saved {path}", file=sys.stderr)
        if self.video_path is not None:
            self._write_video(window, sim_time_s)

    def shot_path(self, sim_time_s: float) -> Path:
        """A screenshot's file name at `sim_time_s` that no file has: a counter suffix after the first."""
        stem = f"usvsim_{self.name}_{sim_time_s:09.3f}s"
        path, n = self.shots_dir / f"{stem}.png", 1
        while path.exists() or path in self.saved:
            n += 1
            path = self.shots_dir / f"{stem}_{n}.png"
        return path

    def _write_video(self, window, sim_time_s: float) -> None:
        """The video runs on simulated time: a frame per 1/fps s of it, the latest drawn frame repeated when the
        window draws slower, frames between two ticks left out, a pause left out (one frame per drawn frame at a
        nominal 30 fps played 1 s simulated in 0.4 s at 12 fps). A reset restarts the clock: the video goes on."""
        if self._next_s is None or sim_time_s < self._last_s - 1e-9:
            self._next_s = sim_time_s
        self._last_s = sim_time_s
        count = 0
        while self._next_s <= sim_time_s + 1e-9:
            count, self._next_s = count + 1, self._next_s + 1.0 / self.fps
        if count == 0:
            return
        rgb = window.renderer.read_rgb(window.viewport)
        if self._writer is None:
            assert self.video_path is not None
            self._writer = _open_writer(self.video_path, rgb.shape[1], rgb.shape[0], self.fps)
        bgr = rgb[..., ::-1].copy()  # OpenCV wants BGR
        for _ in range(count):
            self._writer.write(bgr)

    def close(self) -> None:
        if self._writer is not None:
            self._writer.release()
            self._writer = None


VIDEO_SUFFIXES = (".mp4", ".avi")


def check_outputs(screenshot: str | Path | None = None, video: str | Path | None = None) -> None:
    """Raise a one-line UsvsimError, before the window opens, when `screenshot` has no image format Pillow writes
    (`x.txt` ended the whole run in a ValueError traceback) or `video` is neither MP4 nor AVI (the window opened,
    then failed on its first frame)."""
    if screenshot is not None:
        from PIL import Image

        fmt = Image.registered_extensions().get(Path(screenshot).suffix.lower())
        if fmt is None or fmt not in Image.SAVE:
            raise UsvsimError(
                f"{screenshot}: a screenshot is an image; give a file name ending in .png (or .jpg)"
            )
    if video is not None and Path(video).suffix.lower() not in VIDEO_SUFFIXES:
        raise UsvsimError(f"{video}: a video is MP4 or AVI; give a file name ending in .mp4 or .avi")


def _open_writer(path: Path, width: int, height: int, fps: float):
    try:
        import cv2
    except ImportError:
        raise UsvsimError("--video needs OpenCV: pip install opencv-python-headless") from None
    fourcc = cv2.VideoWriter.fourcc(*("mp4v" if path.suffix.lower() == ".mp4" else "MJPG"))
    writer = cv2.VideoWriter(str(path), fourcc, fps, (width, height))
    if not writer.isOpened():
        raise UsvsimError(f"cannot write the video {path} (use .mp4 or .avi in an existing directory)")
    return writer
