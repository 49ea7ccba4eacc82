"""What engine_godot's fixes buy (docs/failure_cases.md, "Godot's fixes"; docs/spec.md §17.10):
each fix switched on and off on the failure scene it addresses, PSNR against the reference of
the same shutter, over the whole image or over one object's pixels. The godot_fixes benchmark
records the numbers; gallery() draws the reference beside the two outputs."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..methods import blur, method, method_instant, methods
from ..metrics import psnr
from ..scene import scenes
from . import plots


@dataclass(frozen=True)
class Fix:
    """One fix on one scene: the parameter that switches it, the parameters held meanwhile,
    and the object whose pixels are scored (None: the whole image)."""

    scene: str
    switch: str
    held: dict = field(default_factory=dict)
    region: str | None = None

    @property
    def label(self) -> str:
        held = ", ".join(f"{key}={value}" for key, value in self.held.items())
        return f"{self.switch}" + (f" ({held})" if held else "")


# The method whose parameters switch the fixes (no code outside a method's folder names it).
METHOD = next(
    name
    for name in methods()
    if {"near_correction", "depth_velocity", "clamp_to_original"} <= set(method(name).params)
)

# A user who halves the camera's part of the blur, as games let players do, keeps a tracked
# car sharp only through the clamp; the reference shows the car as the panning shot does.
# The near-plane correction again with k = 256 px, where the tile clamp (2k) no longer hides
# the vectors' lengths.
FIXES = (
    Fix("reverse_near_plane", "near_correction"),
    Fix("reverse_near_plane", "near_correction", {"k": 256}),
    Fix("racing_road", "depth_velocity"),
    Fix("racing_road", "clamp_to_original", {"translation_multiplier": 0.5}, "car"),
    Fix("tracked_car", "clamp_to_original", {"rotation_multiplier": 0.5}, "car"),
)


def _region(frame, name: str | None) -> np.ndarray:
    """The pixels scored: where the G-buffer sees object `name`, or every pixel."""
    if name is None:
        return np.ones(frame.depth.shape, bool)
    index = [obj.name for obj in frame.scene.objects].index(name)
    return frame.object_id == index


def _scored(reference, image, mask) -> float:
    return psnr(reference[mask][None], image[mask][None])


def measure(ctx, size, reference_samples: int | str = "auto") -> list[list]:
    """One row per fix: scene, fix, pixels scored, PSNR on, PSNR off (dB)."""
    rows, references = [], {}
    for fix in FIXES:
        scene = scenes.get(fix.scene)
        if fix.scene not in references:
            references[fix.scene] = ctx.reference(
                scene, size, samples=reference_samples, progress=False
            ).color
        frame = ctx.render(scene, size, instant=method_instant(METHOD, {}))
        mask = _region(frame, fix.region)
        scores = [
            _scored(
                references[fix.scene],
                blur(ctx, frame, METHOD, **fix.held, **{fix.switch: on}).color,
                mask,
            )
            for on in (True, False)
        ]
        rows.append([fix.scene, fix.label, fix.region or "all", *scores])
    return rows


def gallery(ctx, fix: Fix, size, reference_samples: int | str = "auto"):
    """A figure: the reference, engine_godot with the fix on and off, and their |error| maps."""
    scene = scenes.get(fix.scene)
    reference = ctx.reference(scene, size, samples=reference_samples, progress=False).color
    frame = ctx.render(scene, size, instant=method_instant(METHOD, {}))
    images = {
        f"{fix.switch} {'on' if on else 'off'}": blur(
            ctx, frame, METHOD, **fix.held, **{fix.switch: on}
        ).color
        for on in (True, False)
    }
    return plots.image_grid(reference, images, title=f"{fix.scene}: engine_godot, {fix.label}")
