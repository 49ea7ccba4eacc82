"""The suite's definition, version 1 (docs/spec.md §24): its categories, and what each one
fixes at each preset: scenes, image size, shutter, reference, metrics and the statistic.

Everything here is data. A change to it is a change of the suite: the content hash
(blurlab.suite.content) covers every value below, so cards made under another definition no
longer compare (blurlab.suite.compare).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

from ..scene import scenes
from ..studies.identity import HASH_CHARS, scene_files

VERSION = 1
PRESETS = ("tiny", "software", "gpu")  # CI; llvmpipe's cards; a GPU's cards
FRAMES, SEQUENCE = "frames", "sequence"  # a category of single frames, or of sequences

# The statistic of every category: the median over its scenes (or its sequences' frames),
# with a percentile bootstrap interval of this level (blurlab.studies.rankings).
STATISTIC = "median"
LEVEL = 0.95

# Authored content: glTF files with skins and node animation (the Khronos sample models), found
# under the folder a run is given (`--assets`), each pinned by the digest of its bytes
# (file_digest), so that every card of this version measured the same files. Without the folder
# the category is skipped, and the card says so.
AUTHORED_FILES = {
    "BoxAnimated/BoxAnimated.gltf": "4bd75ec2304846e1",
    "RiggedFigure/RiggedFigure.gltf": "09a6cddac9fcefaf",
    "RiggedSimple/RiggedSimple.gltf": "07d35c012baaae3d",
    "SimpleSkin/SimpleSkin.gltf": "025d34a6a2e31c23",
}
# The random scenes' seeds start here, away from the seeds the rankings and the auto rules
# were studied on (0 upwards), so that the suite's random scenes are held out from them.
RANDOM_FIRST_SEED = 1_000_000

LDR_METRICS = ("psnr", "ssim", "flip")
HDR_METRICS = ("psnr_tm", "ssim_tm", "log_lum_error")
SEQUENCE_METRICS = ("psnr", "temporal_instability")


@dataclass(frozen=True)
class Preset:
    """One preset's values of a category: the scenes (built-in names, 'random:SEED', or files
    relative to the assets folder), the image size, and the reference's sub-frames N."""

    scenes: tuple[str, ...]
    size: tuple[int, int]
    reference_samples: int


@dataclass(frozen=True)
class Sequences:
    """How a sequence category runs (docs/spec.md §21): frames measured after a warm-up, at a
    frame rate and shutter angle, the method placed before TAA."""

    fps: float = 60.0
    shutter_angle: float = 180.0
    order: str = "blur_then_taa"
    frames: dict[str, int] = field(default_factory=dict)  # per preset
    warmup: dict[str, int] = field(default_factory=dict)  # per preset


@dataclass(frozen=True)
class Category:
    """A category of the suite. The first of `metrics` is its primary metric: it ranks the
    methods and decides win rates; the card gives every metric with its interval. `shutter`:
    "scene" is each scene's own shutter (1/60 s for the built-ins; a glTF file's default,
    spec §15)."""

    name: str
    doc: str
    kind: str
    metrics: tuple[str, ...]
    presets: dict[str, Preset]
    shutter: str = "scene"
    antialias: bool = False  # the reference of the metrics named (temporal unless an *_aa)
    needs_assets: bool = False
    sequences: Sequences | None = None

    @property
    def primary(self) -> str:
        return self.metrics[0]

    def at(self, preset: str) -> Preset:
        return self.presets[check_preset(preset)]

    def settings(self, preset: str) -> dict:
        """Every value this category fixes at `preset`, as plain JSON (hashed, and on cards)."""
        chosen = self.at(preset)
        settings = {
            "kind": self.kind,
            "scenes": list(chosen.scenes),
            "size": list(chosen.size),
            "shutter": self.shutter,
            "reference": {"samples": chosen.reference_samples, "antialias": self.antialias},
            "metrics": list(self.metrics),
            "primary": self.primary,
            "statistic": {"name": STATISTIC, "level": LEVEL},
        }
        if self.sequences is not None:
            s = self.sequences
            settings["sequence"] = {
                "fps": s.fps,
                "shutter_angle": s.shutter_angle,
                "order": s.order,
                "frames": s.frames[preset],
                "warmup": s.warmup[preset],
            }
        if self.needs_assets:
            settings["files"] = {name: AUTHORED_FILES[name] for name in chosen.scenes}
        return settings


def _same(scenes_: tuple[str, ...], sizes: dict, samples: dict, tiny=None) -> dict:
    """Presets with the given sizes and N, every scene at software and gpu, `tiny` (or the
    first two scenes) at tiny."""
    chosen = {"tiny": tiny or scenes_[:2], "software": scenes_, "gpu": scenes_}
    return {p: Preset(tuple(chosen[p]), sizes[p], samples[p]) for p in PRESETS}


SIZES = {"tiny": (64, 36), "software": (160, 90), "gpu": (1920, 1080)}
SAMPLES = {"tiny": 32, "software": 64, "gpu": 512}
RANDOM_SIZES = {"tiny": (64, 36), "software": (160, 90), "gpu": (960, 540)}
RANDOM_SAMPLES = {"tiny": 32, "software": 64, "gpu": 256}
RANDOM_COUNTS = {"tiny": 4, "software": 30, "gpu": 500}


def _random_scenes(count: int) -> tuple[str, ...]:
    return tuple(scenes.random_name(s) for s in range(RANDOM_FIRST_SEED, RANDOM_FIRST_SEED + count))


CATEGORIES = (
    Category(
        "opaque",
        "the built-in scenes: a pass, a fan, a vehicle, a textured spin, a skinned arm",
        FRAMES,
        LDR_METRICS,
        _same(tuple(scenes.names()), SIZES, SAMPLES),
    ),
    Category(
        "failure",
        "the failure cases (docs/failure_cases.md): thin, fast, crossing and near-plane motion",
        FRAMES,
        LDR_METRICS,
        _same(
            tuple(scenes.names("failure")), SIZES, SAMPLES, ("thin_bar", "crossing", "edge_exit")
        ),
    ),
    Category(
        "transparency",
        "glass, smoke, sparks and foliage over moving objects (docs/transparency.md)",
        FRAMES,
        LDR_METRICS,
        _same(tuple(scenes.names("transparency")), SIZES, SAMPLES, ("moving_glass", "smoke_pan")),
    ),
    Category(
        "hdr",
        "scenes lit by emission far above 1, scored tone-mapped and in log luminance (docs/hdr.md)",
        FRAMES,
        HDR_METRICS,
        _same(tuple(scenes.names("hdr")), SIZES, SAMPLES, ("sparks", "neon_pan")),
    ),
    Category(
        "authored",
        "authored glTF content: skinned and node-animated models, each file pinned by its "
        "digest; skipped without the assets folder",
        FRAMES,
        LDR_METRICS,
        _same(tuple(AUTHORED_FILES), SIZES, SAMPLES, ("RiggedSimple/RiggedSimple.gltf",)),
        needs_assets=True,
    ),
    Category(
        "sequences",
        "sequences under TAA: each method before TAA, frame after frame, against each frame's "
        "antialiased reference (docs/temporal.md)",
        SEQUENCE,
        SEQUENCE_METRICS,
        {
            "tiny": Preset(("fan",), SIZES["tiny"], 16),
            "software": Preset(("teapot_pass", "fan", "camera_yaw"), SIZES["software"], 32),
            "gpu": Preset(
                tuple(scenes.names()) + ("thin_bar", "crossing", "camera_yaw", "racing_road"),
                SIZES["gpu"],
                256,
            ),
        },
        antialias=True,
        sequences=Sequences(
            frames={"tiny": 3, "software": 6, "gpu": 16},
            warmup={"tiny": 2, "software": 3, "gpu": 8},
        ),
    ),
    Category(
        "random",
        f"procedural scenes (docs/random_scenes.md), seeds from {RANDOM_FIRST_SEED} on",
        FRAMES,
        LDR_METRICS,
        {
            p: Preset(_random_scenes(RANDOM_COUNTS[p]), RANDOM_SIZES[p], RANDOM_SAMPLES[p])
            for p in PRESETS
        },
    ),
)


def check_preset(preset) -> str:
    if preset not in PRESETS:
        raise ValueError(
            f"blurlab suite: preset must be one of {', '.join(PRESETS)}, not {preset!r}"
        )
    return preset


def categories() -> tuple[Category, ...]:
    """The categories of suite version VERSION, in the order cards show them."""
    return CATEGORIES


def category(name: str) -> Category:
    for c in CATEGORIES:
        if c.name == name:
            return c
    names = ", ".join(c.name for c in CATEGORIES)
    raise ValueError(f"blurlab suite: no category {name!r}; v{VERSION} has {names}")


def definition(preset: str) -> dict:
    """The whole definition at `preset` as plain JSON: what the hash covers first."""
    check_preset(preset)
    return {
        "version": VERSION,
        "preset": preset,
        "categories": {c.name: c.settings(preset) for c in CATEGORIES},
    }


def file_digest(path: Path) -> str:
    """A glTF file's digest: its bytes and those of the files it refers to (buffers, images),
    each by name, as blurlab.studies.identity hashes a scene loaded from a file."""
    h = hashlib.sha256()
    for part in scene_files(Path(path)):
        h.update(part.name.encode() + b"\0" + part.read_bytes())
    return h.hexdigest()[:HASH_CHARS]


def authored_paths(category_: Category, preset: str, assets) -> tuple[list[Path], str | None]:
    """(paths, None) of the category's files under `assets`, each checked against its pinned
    digest; ([], why) where the folder is not given or lacks a file. A file present with other
    bytes is an error: it is not the content this version of the suite defines."""
    names = category_.at(preset).scenes
    if assets is None:
        return [], "no assets folder given (--assets DIR: the folder of the glTF sample models)"
    folder = Path(assets)
    if not folder.is_dir():
        raise ValueError(f"blurlab suite: the assets folder {folder} is not a folder")
    missing = [n for n in names if not (folder / n).is_file()]
    if missing:
        return [], f"the assets folder {folder} lacks {', '.join(missing)}"
    paths = []
    for name in names:
        path = (folder / name).resolve()
        if not path.is_relative_to(folder.resolve()):
            raise ValueError(f"blurlab suite: {name} lies outside the assets folder {folder}")
        got = file_digest(path)
        if got != AUTHORED_FILES[name]:
            raise ValueError(
                f"blurlab suite: {path} has digest {got}, not the {AUTHORED_FILES[name]} that "
                f"suite v{VERSION} pins: it is other content (use the file the suite names)"
            )
        paths.append(path)
    return paths, None


def markdown_table() -> str:
    """Each category's settings at each preset as a Markdown table (docs/suite.md shows it;
    a test holds the page to it)."""
    lines = [
        "| category | scenes (tiny / software / gpu) | size | reference N "
        "| metrics (first ranks) |",
        "|---|---|---|---|---|",
    ]
    for c in CATEGORIES:
        chosen = [c.at(p) for p in PRESETS]
        counts = " / ".join(str(len(s.scenes)) for s in chosen)
        sizes = " / ".join(f"{s.size[0]}×{s.size[1]}" for s in chosen)
        samples = " / ".join(str(s.reference_samples) for s in chosen)
        lines.append(f"| {c.name} | {counts} | {sizes} | {samples} | {', '.join(c.metrics)} |")
    return "\n".join(lines) + "\n"
