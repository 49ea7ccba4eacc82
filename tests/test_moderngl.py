"""moderngl on blurlab's own GL context: users' passes write blurlab textures, no copies."""

from __future__ import annotations

import numpy as np

VERTEX = """
#version 330
out vec2 uv;
void main() {
    // One triangle that covers the viewport.
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

FRAGMENT = """
#version 330
uniform float gain;
out vec4 color;
void main() {
    color = vec4(floor(gl_FragCoord.xy), gain, 1.0);
}
"""


def test_moderngl_shares_the_context(ctx):
    mgl = ctx.moderngl()
    assert mgl.info["GL_RENDERER"] == ctx.info()["renderer"]
    assert ctx.moderngl() is mgl


def test_moderngl_program_writes_a_blurlab_texture(ctx):
    width, height = 24, 10
    target = ctx.empty((height, width, 4), "float32")
    mgl = ctx.moderngl()
    shared = mgl.external_texture(target.glo, (width, height), 4, 0, "f4")
    framebuffer = mgl.framebuffer(color_attachments=[shared])
    program = mgl.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
    program["gain"] = 0.25
    vao = mgl.vertex_array(program, [])
    framebuffer.use()
    vao.render(vertices=3)
    mgl.finish()
    assert mgl.error == "GL_NO_ERROR"

    image = target.download()
    # gl_FragCoord counts rows from the texture's first row, which blurlab reads as row 0 (top).
    y, x = np.mgrid[0:height, 0:width]
    np.testing.assert_array_equal(image[..., 0], x)
    np.testing.assert_array_equal(image[..., 1], y)
    np.testing.assert_array_equal(image[..., 2], np.float32(0.25))
    framebuffer.release()
    vao.release()
    program.release()
