"""A process forked after its parent rendered cannot make a GL context (EGL/Mesa are not fork-safe: it hung for
good): a camera there raises one clear UsvsimError that names the 'spawn' start method instead. A spawned process
renders as the parent does."""

from __future__ import annotations

import multiprocessing
import os

import numpy as np
import pytest

from usvsim.sensors.camera.render import RenderContext

CAMERA = {"type": "camera", "name": "camera", "width": 32, "height": 24, "rate_hz": 10, "streams": ["rgb"],
          "mount": {"position": [0.3, 0.0, 1.3]}}  # fmt: skip
JOIN_S = 120.0  # generous: a child that raises returns at once; one that hangs (the bug) is killed after this


def _forked_child(model, conn) -> None:
    try:
        RenderContext(model, 32, 24)
        conn.send(("made", ""))
    except Exception as e:  # the test reads the type and message
        conn.send((type(e).__name__, str(e)))
    finally:
        os._exit(0)  # no finalizers here: they would touch the parent's GL state


def _run_child(ctx, target, args):
    parent_end, child_end = ctx.Pipe(duplex=False)
    child = ctx.Process(target=target, args=(*args, child_end), daemon=True)
    child.start()
    child.join(JOIN_S)
    if child.is_alive():
        child.kill()
        child.join()
        pytest.fail(f"the child process hung (still running after {JOIN_S:.0f} s)")
    assert parent_end.poll(), f"the child exited ({child.exitcode}) without an answer"
    return parent_end.recv()


def test_a_camera_in_a_process_forked_after_rendering_raises_instead_of_hanging(rig):
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork on this platform")
    sim, suite, collector = rig(CAMERA)
    collector.run(0.2)
    assert suite.sensors["wamv/camera"].latest["rgb"].std() > 0  # this process has rendered
    kind, message = _run_child(multiprocessing.get_context("fork"), _forked_child, (sim.model,))
    assert kind == "UsvsimError", (kind, message)
    assert "forked after its parent rendered" in message and "'spawn'" in message and "\n" not in message
    suite.close()


def _spawned_child(model, conn) -> None:
    context = RenderContext(model, 32, 24)
    context.close()
    conn.send(("made", ""))


def test_a_spawned_process_renders_after_its_parent_did(rig):
    sim, suite, collector = rig(CAMERA)
    collector.run(0.2)
    assert _run_child(multiprocessing.get_context("spawn"), _spawned_child, (sim.model,)) == ("made", "")
    assert np.isfinite(suite.sensors["wamv/camera"].latest["rgb"]).all()
    suite.close()


def test_the_viewer_window_refuses_a_process_forked_after_rendering(monkeypatch):
    """The GLFW viewer window checks as cameras do: in a process whose GL state came from a parent by fork() (here:
    the recorded GL process is another pid) it raises the same one-line error before touching GLFW."""
    from usvsim.core.errors import UsvsimError
    from usvsim.sensors.camera import render
    from usvsim.viewer.app import ViewerWindow

    monkeypatch.setattr(render, "_gl_pid", os.getpid() + 1)
    with pytest.raises(UsvsimError, match="forked after its parent rendered"):
        ViewerWindow(None, None)  # type: ignore[arg-type]  # refused before the driver or view are used
