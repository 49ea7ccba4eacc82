"""`blurlab new-method NAME --out DIR`: a method folder to start from, which loads, runs and
passes the contract (blurlab.methods.contract) as written: a tent-weighted gather along the
motion, its shader in GLSL or HLSL, its NumPy twin, its spec text and its test. The template is
itself a method folder, template_files/, named TEMPLATE_NAME: new-method copies it with the new
name in place of that one (docs/adding_a_method.md shows its files)."""

from __future__ import annotations

from pathlib import Path

from .folders import DECLARATION_FILE, NAME, TEMPLATE_FOLDER, MethodFolderError
from .registry import methods

LANGUAGES = ("glsl", "hlsl")
TEMPLATE = Path(__file__).resolve().parent / TEMPLATE_FOLDER
TEMPLATE_NAME = "my_tent"


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
    named = lambda text: text.replace(TEMPLATE_NAME, name)  # noqa: E731
    declaration = (TEMPLATE / DECLARATION_FILE).read_text().replace("gather.glsl", shader)
    files = {
        DECLARATION_FILE: named(declaration),
        "twin.py": named((TEMPLATE / "twin.py").read_text()),
        shader: named((TEMPLATE / shader).read_text()),
        "spec.md": named((TEMPLATE / "spec.md").read_text()),
        f"test_{name}.py": named((TEMPLATE / f"test_{TEMPLATE_NAME}.py").read_text()),
    }
    # Written beside, then renamed: no half-written folder is left by a failure.
    partial = folder.with_name(f".{name}.partial")
    partial.mkdir(parents=True)
    for file, text in files.items():
        (partial / file).write_text(text)
    partial.rename(folder)
    return folder
