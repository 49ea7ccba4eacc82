"""Translucent surfaces in the G-buffer (docs/spec.md §20): the fragment lists the G-buffer
pass collects, their resolve into the composite and the translucent layer, and the check that
no pixel had more fragments than the scene keeps."""

from __future__ import annotations

from .model import MAX_LAYERS, Scene


def fragment_layout(capacity: int, height: int, width: int, max_size: int) -> tuple[int, int]:
    """(rows, columns) of H x W blocks that hold `capacity` fragments per pixel in one texture no
    side of which exceeds `max_size` (GL_MAX_TEXTURE_SIZE): fragment k of pixel (x, y) lies at
    texel (x + (k // rows)·W, y + (k % rows)·H). One column while capacity·H fits (1080p holds
    30 fragments a pixel in one column of 32768 rows), as few columns as needed beyond."""
    most_rows = max_size // height
    columns = -(-capacity // most_rows) if most_rows else 0
    if not most_rows or columns * width > max_size:
        raise ValueError(
            f"blurlab: {capacity} translucent fragments per pixel at {width}x{height} do not fit "
            f"a texture of at most {max_size} per side; lower scene.max_layers or the size"
        )
    return -(-capacity // columns), columns


def translucent_layer(
    ctx, gbuffer, targets, camera_uniforms, light, draws, scene, most_fragments=None
) -> None:
    """Adds the translucent surfaces to `targets` (docs/spec.md §20): their fragments are listed
    per pixel, then sorted and composited (shaders/passes/translucent_resolve.comp). "color"
    becomes the composite over the opaque layer, which moves to "opaque_color"; "translucent"
    holds (Σ, a) and "translucent_motion" the dominant fragment's motion, depth and the pixel's
    fragment count. The largest count goes to `most_fragments` (1 x 1, uint32), by default a
    new targets["most_fragments"]."""
    height, width = targets["depth"].shape
    capacity = scene.max_layers
    counts = ctx.pooled((height, width), "uint32")
    counts.clear()
    rows, columns = fragment_layout(capacity, height, width, ctx.max_texture_size)
    surface = ctx.pooled((rows * height, columns * width, 4))
    motion = ctx.pooled((rows * height, columns * width, 4))
    # A colour-only render (a reference's sub-frame) has no motion or ids: nothing is written
    # to the G-buffer targets here, and the fragments' own motion is kept in their lists.
    natives = [
        targets[name].native if name in targets else None
        for name in ("color", "depth", "motion", "object_id")
    ]
    gbuffer.render(
        *natives,
        camera_uniforms,
        light,
        draws,
        fragment_counts=counts.native,
        fragment_surface=surface.native,
        fragment_motion=motion.native,
        opaque_depth=targets["depth"].native,
    )
    targets["opaque_color"] = targets["color"]
    targets["color"] = ctx.pooled((height, width, 4))
    targets["translucent"] = ctx.pooled((height, width, 4))
    targets["translucent_motion"] = ctx.pooled((height, width, 4))
    if most_fragments is None:
        most_fragments = targets["most_fragments"] = ctx.pooled((1, 1), "uint32")
        most_fragments.clear()
    resolve_fragments(
        ctx,
        {
            "opaque_color": targets["opaque_color"],
            "fragment_counts": counts,
            "fragment_surface": surface,
            "fragment_motion": motion,
        },
        {
            "composite": targets["color"],
            "translucent": targets["translucent"],
            "translucent_motion": targets["translucent_motion"],
            "most_fragments": most_fragments,
        },
        capacity,
    )
    ctx.recycle(counts, surface, motion)


def resolve_fragments(ctx, lists: dict, outputs: dict, capacity: int | None = None) -> None:
    """Sorts and composites fragment lists on the GPU (shaders/passes/translucent_resolve.comp;
    NumPy twin: blurlab.twins.translucency.resolve). `lists`: "opaque_color", "fragment_counts"
    (H, W) uint32, "fragment_surface" and "fragment_motion" in fragment_layout's blocks (one
    column, (kH, W, 4), where `capacity` is not given); `outputs`: "composite", "translucent",
    "translucent_motion" (H, W, 4) and "most_fragments" (1 x 1 uint32)."""
    height = lists["fragment_counts"].shape[0]
    capacity = capacity or lists["fragment_surface"].shape[0] // height
    resolve = ctx.shader_pass("passes/translucent_resolve.comp", {"CAPACITY": capacity})
    resolve.run(lists, outputs)


def check_fragment_capacity(most_fragments, scene: Scene) -> int:
    """The largest number of translucent fragments a pixel had (read from the 1 x 1 target of
    translucent_layer); raises if it is more than the scene's max_layers held (docs/spec.md
    §20: fragments are never dropped silently)."""
    most = int(most_fragments.download().max())
    if most > scene.max_layers:
        raise OverflowError(
            f"blurlab: a pixel has {most} translucent fragments in front of the opaque surface, "
            f"more than scene.max_layers = {scene.max_layers} holds; set scene.max_layers >= "
            f"{most} (at most {MAX_LAYERS})"
        )
    return most
