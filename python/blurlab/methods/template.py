"""`blurlab new-method NAME --out DIR`: a method folder to start from, which loads, runs and
passes the contract (blurlab.methods.contract) as written: a tent-weighted gather along the
motion, its shader in GLSL or HLSL, its NumPy twin, its spec text and its test."""

from __future__ import annotations

from pathlib import Path

from .folders import DECLARATION_FILE, NAME, MethodFolderError
from .registry import methods

LANGUAGES = ("glsl", "hlsl")

METHOD_PY = '''"""{name}: n taps along the motion, centred on the pixel, tent-weighted (spec.md).
Written by `blurlab new-method`; `blurlab check-method PATH/{name}` runs the contract."""

from blurlab.methods import Declaration, Param, Pass

from .twin import {name}

# Each parameter is declared once: its uniform in the shader has the same name.
PARAMS = {{
    "taps": Param(9, int, "taps along the motion, centred on the pixel", low=2, high=64),
    "scale": Param(1.0, float, "the blur's length, a fraction of the motion", low=0.0, high=4.0),
}}

METHOD = Declaration(
    name="{name}",
    kind="gather",
    doc="n taps along the motion around the pixel, tent-weighted (spec.md).",
    instant="center",  # the G-buffer time its motion is centred on
    params=PARAMS,
    passes=(Pass("gather", "{shader}", tuple(PARAMS)),),
    default_grid={{"taps": [5, 9, 17]}},
    twin={name},
)
'''

TWIN_PY = '''"""The NumPy twin of {name}: spec.md in code, float64; the shader agrees with it."""

import numpy as np

from blurlab.twins.inputs import sanitize_color, sanitize_motion


def {name}(color, motion, *, taps: int, scale: float) -> np.ndarray:
    c = sanitize_color(color)
    m = sanitize_motion(motion) * scale
    height, width = c.shape[:2]
    ys, xs = np.mgrid[0:height, 0:width]
    center = np.stack([xs + 0.5, ys + 0.5], -1)
    total = np.zeros_like(c)
    weights = 0.0
    for i in range(taps):
        s = (i + 0.5) / taps - 0.5
        weight = 1.0 - 2.0 * abs(s)
        p = np.floor(center - s * m)
        x = np.clip(p[..., 0], 0, width - 1).astype(np.int64)
        y = np.clip(p[..., 1], 0, height - 1).astype(np.int64)
        total += weight * c[y, x]
        weights += weight
    return total / weights
'''

GATHER_GLSL = """#version 450
// {name} (spec.md beside this file); NumPy twin: twin.py. blurlab's common/inputs.glsl gives
// sanitize_color and sanitize_motion: how blurlab reads NaN and inf.
#include "common/inputs.glsl"

layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion;
uniform int taps;
uniform float scale;

vec4 {name}_at(ivec2 x) {{
    ivec2 size = textureSize(color, 0);
    vec2 m = sanitize_motion(texelFetch(motion, x, 0).xy) * scale;
    vec2 center = vec2(x) + 0.5;
    vec4 sum = vec4(0.0);
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {{
        float s = (float(i) + 0.5) / float(taps) - 0.5;
        float weight = 1.0 - 2.0 * abs(s);
        ivec2 y = clamp(ivec2(floor(center - s * m)), ivec2(0), size - 1);
        sum += weight * sanitize_color(texelFetch(color, y, 0));
        total += weight;
    }}
    return sum / total;
}}

// The entry points: image `result`, one invocation per pixel.
#define PASS_AT {name}_at
#include "common/pass_main.glsl"
"""

GATHER_HLSL = """// {name} (spec.md beside this file); NumPy twin: twin.py. An HLSL compute shader:
// blurlab translates it to GLSL 4.50 (glslang, SPIRV-Cross) and binds its resources by name.
Texture2D<float4> color;
Texture2D<float4> motion;
RWTexture2D<float4> result;
int taps;
float scale;

// How blurlab reads NaN and inf (its shaders/common/inputs.glsl): NaN colour is 0, colour
// beyond 2^64 clamps; a motion with a NaN or inf component is none, the rest clamps to 2^20.
static const float COLOR_LIMIT = 18446744073709551616.0;
static const float MOTION_LIMIT = 1048576.0;

bool is_nan_bits(float x) {{ return (asuint(x) & 0x7fffffffu) > 0x7f800000u; }}
bool is_finite_bits(float x) {{ return (asuint(x) & 0x7f800000u) != 0x7f800000u; }}

float4 sanitize_color(float4 c) {{
    [unroll] for (int i = 0; i < 4; ++i)
        c[i] = is_nan_bits(c[i]) ? 0.0 : clamp(c[i], -COLOR_LIMIT, COLOR_LIMIT);
    return c;
}}

float2 sanitize_motion(float2 m) {{
    if (!is_finite_bits(m.x) || !is_finite_bits(m.y)) return float2(0.0, 0.0);
    return clamp(m, -MOTION_LIMIT, MOTION_LIMIT);
}}

[numthreads(16, 16, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
    uint width, height;
    color.GetDimensions(width, height);
    if (id.x >= width || id.y >= height) return;
    int2 size = int2(width, height);
    float2 m = sanitize_motion(motion.Load(int3(id.xy, 0)).xy) * scale;
    float2 center = float2(id.xy) + 0.5;
    float4 sum = 0.0;
    float total = 0.0;
    for (int i = 0; i < taps; ++i) {{
        float s = (float(i) + 0.5) / float(taps) - 0.5;
        float weight = 1.0 - 2.0 * abs(s);
        int2 y = clamp(int2(floor(center - s * m)), int2(0, 0), size - 1);
        sum += weight * sanitize_color(color.Load(int3(y, 0)));
        total += weight;
    }}
    result[id.xy] = sum / total;
}}
"""

SPEC_MD = """# {name}

A gather along the pixel's motion M (pixels over the shutter, G-buffer at the shutter's
centre). With n = `taps` and L = `scale`, tap i = 0..n-1 sits at

    s_i = (i + 1/2) / n - 1/2,    p_i = X + (1/2, 1/2) - s_i L M,

reads the pixel containing p_i (clamped to the image), and weighs 1 - 2|s_i| (a tent). The
output is the weighted mean of the taps. Colour and motion are read as blurlab reads
non-finite values (NaN colour is 0; a motion with NaN or inf is none).
"""

TEST_PY = '''"""{name} meets blurlab's method contract (run: pytest {folder})."""

from pathlib import Path

import blurlab as bl
from blurlab.methods.contract import check_method, table


def test_the_contract():
    names = bl.load_methods(Path(__file__).parent)
    try:
        checks = check_method(bl.Context(), "{name}")
        assert all(c.passed is not False for c in checks), table("{name}", checks)
    finally:
        bl.unload_methods(names)
'''


def write_template(name: str, out, language: str = "glsl") -> Path:
    """Writes the method folder OUT/NAME and returns it; refuses a bad or taken name, an
    unknown language and a folder that exists."""
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise MethodFolderError(
            f"blurlab: method name {name!r} must be lower case letters, digits and _, "
            "starting with a letter"
        )
    if name in methods():
        raise MethodFolderError(f"blurlab: {name!r} is the name of a registered method")
    if language not in LANGUAGES:
        raise MethodFolderError(f"blurlab: language {language!r} is not one of {LANGUAGES}")
    folder = Path(out) / name
    if folder.exists():
        raise MethodFolderError(f"blurlab: {folder} exists already; new-method writes a new folder")
    shader = f"gather.{language}"
    files = {
        DECLARATION_FILE: METHOD_PY.format(name=name, shader=shader),
        "twin.py": TWIN_PY.format(name=name),
        shader: (GATHER_GLSL if language == "glsl" else GATHER_HLSL).format(name=name),
        "spec.md": SPEC_MD.format(name=name),
        f"test_{name}.py": TEST_PY.format(name=name, folder=name),
    }
    # Written beside, then renamed: no half-written folder is left by a failure.
    partial = folder.with_name(f".{name}.partial")
    partial.mkdir(parents=True)
    for file, text in files.items():
        (partial / file).write_text(text)
    partial.rename(folder)
    return folder
