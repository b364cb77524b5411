"""The marine look: sky, sun, water, fog and haze drawn with GLSL shaders (moderngl) into the GL context that
MuJoCo's renderer draws the geoms into, so one depth buffer holds both and depth and labels stay exact.
Needs the `render` extra (moderngl); imported lazily by the camera sensors and the viewer."""
