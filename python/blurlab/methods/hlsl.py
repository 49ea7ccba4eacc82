"""HLSL compute shaders for method folders (docs/adding_a_method.md, "HLSL"): glslang's HLSL
front end compiles one to SPIR-V, SPIRV-Cross writes that as GLSL 4.50, and the GLSL's
resources get back the HLSL names, so that a pass binds an HLSL shader's textures, images and
parameters by name exactly as a GLSL one's:

- a Texture2D read with Load (or with a SamplerState) becomes a sampler2D of the texture's name;
- a RWTexture2D keeps its name and format;
- the global parameters (HLSL's `$Global` constant buffer) become plain uniforms of their names.

Texture and image bindings are assigned by glslang (--auto-map-bindings) and kept."""

from __future__ import annotations

import atexit
import hashlib
import json
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

PACKAGES = (
    "glslang-tools and spirv-cross (Debian/Ubuntu: apt-get install glslang-tools spirv-cross)"
)
TIMEOUT_S = 60  # each tool, per shader
SUFFIXES = (".hlsl",)


class HLSLError(ValueError):
    """An HLSL shader that cannot be used: the tools are absent, or it does not compile."""


def tools() -> tuple[str, str]:
    """The paths of glslangValidator and spirv-cross, or HLSLError naming the packages."""
    glslang = shutil.which("glslangValidator") or shutil.which("glslang")
    cross = shutil.which("spirv-cross")
    if glslang is None or cross is None:
        absent = [n for n, p in (("glslangValidator", glslang), ("spirv-cross", cross)) if not p]
        raise HLSLError(f"{' and '.join(absent)} not found on PATH; HLSL shaders need {PACKAGES}")
    return glslang, cross


_OUT: list[Path] = []


def _out_dir() -> Path:
    """This process's folder of translated shaders, removed when it exits."""
    if not _OUT:
        folder = Path(tempfile.mkdtemp(prefix="blurlab-hlsl-"))
        atexit.register(shutil.rmtree, folder, True)
        _OUT.append(folder)
    return _OUT[0]


def _run(command: list[str], source: Path) -> str:
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise HLSLError(f"{source}: {Path(command[0]).name} took over {TIMEOUT_S} s") from None
    if done.returncode != 0:
        log = (done.stdout + done.stderr).strip()
        # glslang prints the file it read first; the errors carry file:line themselves.
        lines = [line for line in log.splitlines() if line.strip() and line.strip() != str(source)]
        raise HLSLError(f"{source} failed to compile:\n" + "\n".join(lines[:40]))
    return done.stdout


def translate(source: Path, defines: dict[str, int]) -> Path:
    """The GLSL 4.50 file translated from HLSL compute shader `source` (entry point main) with
    `defines`, its resources named as in the HLSL; made once per content and defines."""
    glslang, cross = tools()
    text = source.read_bytes()
    key = hashlib.sha256(text + json.dumps(sorted(defines.items())).encode()).hexdigest()[:16]
    target = _out_dir() / f"{source.stem}-{key}.comp"
    if target.is_file():
        return target
    spirv = target.with_suffix(".spv")
    command = [glslang, "-D", "-V", "-S", "comp", "-e", "main", "--auto-map-bindings"]
    command += [f"-D{name}={value}" for name, value in sorted(defines.items())]
    _run([*command, "-o", str(spirv), str(source)], source)
    glsl = _run(
        [cross, "--version", "450", "--no-es", "--combined-samplers-inherit-bindings", str(spirv)],
        source,
    )
    reflection = json.loads(_run([cross, str(spirv), "--reflect"], source))
    target.write_text(named(glsl, reflection, source))
    return target


def named(glsl: str, reflection: dict, source: Path) -> str:
    """SPIRV-Cross's GLSL with the HLSL names back: combined samplers renamed to their
    texture, the `$Global` block's members as plain uniforms."""
    textures = [t["name"] for t in reflection.get("separate_images", [])]
    samplers = [s["name"] for s in reflection.get("separate_samplers", [])] + [
        "SPIRV_Cross_DummySampler"
    ]
    for texture in textures:
        combined = [
            f"SPIRV_Cross_Combined{texture}{sampler}"
            for sampler in samplers
            if re.search(rf"\bSPIRV_Cross_Combined{texture}{sampler}\b", glsl)
        ]
        if len(combined) > 1:
            raise HLSLError(
                f"{source}: texture {texture} is read with {len(combined) - 1} samplers; "
                "read each texture with one (or with Load)"
            )
        if combined:
            glsl = re.sub(rf"\b{combined[0]}\b", texture, glsl)
    return _plain_uniforms(glsl, source)


_BLOCK = re.compile(
    r"layout\([^)]*\)\s*uniform\s+(?:type_)?_?\$?Globals?\s*\{(?P<members>[^}]*)\}\s*"
    r"(?P<instance>\w+)\s*;"
)


def _plain_uniforms(glsl: str, source: Path) -> str:
    match = _BLOCK.search(glsl)
    if match is None:
        if re.search(r"\buniform\s+\w+\s*\{", glsl):
            raise HLSLError(
                f"{source}: parameters go in the global scope, not in a cbuffer of their own"
            )
        return glsl
    members = [m.strip() for m in match["members"].split(";") if m.strip()]
    uniforms = "".join(f"uniform {member};\n" for member in members)
    glsl = glsl[: match.start()] + uniforms + glsl[match.end() :]
    return re.sub(rf"\b{match['instance']}\.", "", glsl)
