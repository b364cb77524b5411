"""moderngl on the GL context that is current (MuJoCo's EGL offscreen context, or a GLFW/GLX window).

moderngl cannot detect an EGL context by itself, so it gets a loader that resolves GL functions through
`eglGetProcAddress` when an EGL context is current, else through GLX. This is the one place that attaches to
a context; the caller keeps the context current while drawing.
"""

from __future__ import annotations

import ctypes
import ctypes.util


class _Loader:
    """What moderngl's `create_context(context=...)` calls to find GL entry points."""

    def __init__(self):
        egl = ctypes.CDLL(ctypes.util.find_library("EGL") or "libEGL.so.1")
        egl.eglGetCurrentContext.restype = ctypes.c_void_p
        if egl.eglGetCurrentContext():
            self._get = egl.eglGetProcAddress
        else:
            self._get = ctypes.CDLL(ctypes.util.find_library("GL") or "libGL.so.1").glXGetProcAddressARB
        self._get.restype, self._get.argtypes = ctypes.c_void_p, [ctypes.c_char_p]

    def load_opengl_function(self, name: str) -> int:
        return self._get(name.encode()) or 0

    def release(self) -> None:
        pass


def attach_current():
    """A moderngl context wrapping the current GL context (it must be GL >= 3.3; llvmpipe gives 4.5)."""
    from usvsim.core.errors import UsvsimError

    try:
        import moderngl
    except ModuleNotFoundError as exc:
        raise UsvsimError("the shader renderer needs moderngl (pip install moderngl) "
                          "(or set rendering.renderer: mujoco)") from exc  # fmt: skip
    # moderngl's stub types `context` as a dict; its loader protocol (load_opengl_function, release) is what
    # create_context uses with an object (moderngl's "external context" documentation)
    return moderngl.create_context(context=_Loader(), require=330)  # pyright: ignore[reportArgumentType]
