"""The GPU core: the GL context and its textures and passes (gl, timers, graph), then the frame,
the G-buffer render and the converged references built on it (docs/architecture.md)."""
