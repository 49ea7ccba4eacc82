"""Cycles renders blurlab's translucent, additive and masked materials (docs/spec.md §20.1)
as shader mixes with a transparent BSDF: their images converge to blurlab's reference."""

import numpy as np
import pytest

import blurlab as bl
from blurlab.blender import crosscheck, cycles_shutter

pytestmark = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not installed (pip install 'blurlab[blender]')"
)

SIZE = (40, 24)


@pytest.mark.parametrize("blend", ["blend", "additive", "mask"])
def test_a_still_textured_pane_matches_cycles(ctx, blend):
    """Unlit, still: the composite is exact, so Cycles matches it up to its own noise."""
    scene = bl.Scene(
        bl.Camera((0, 0, 4), (0, 0, 0), fov_y=45), crosscheck.UNLIT, (0.2, 0.3, 0.2, 1), name="p"
    )
    texture = np.full((4, 4, 4), 0.5, np.float32)
    texture[..., 3] = 0.6
    material = bl.Material((0.9, 0.2, 0.1), texture, alpha=0.5, blend=blend, alpha_cutoff=0.25)
    scene.add(bl.mesh.plane(1.5, 1.5), material, crosscheck.backdrop((0, 0, 0)))
    cycles = bl.blender.render(scene, SIZE, samples=64, seed=1).color
    ours = ctx.reference(scene, SIZE, samples=64, antialias=True, progress=False).color
    center = (SIZE[1] // 2, SIZE[0] // 2)
    np.testing.assert_allclose(cycles[center][:3], ours[center][:3], atol=2e-3)
    assert bl.metrics.psnr(ours, cycles) > 35


@pytest.mark.parametrize("name", ["moving_glass", "sparks_over_mover"])
def test_transparency_scenes_converge_to_the_antialiased_reference(ctx, name):
    scene = bl.scenes.get(name)
    cycles = bl.blender.render(scene, SIZE, samples=128, seed=1).color
    shutter = cycles_shutter(scene.shutter)
    ours = ctx.reference(scene, SIZE, shutter, samples=256, antialias=True, progress=False).color
    opaque = ctx.reference(opaque_copy(scene), SIZE, shutter, samples=256, antialias=True).color
    # Near the reference, and far nearer than the same scene with its translucency ignored.
    assert bl.metrics.psnr(ours, cycles) > 33
    assert bl.metrics.psnr(ours, cycles) > bl.metrics.psnr(opaque, cycles) + 2


def opaque_copy(scene):
    for obj in scene.objects:
        m = obj.material
        obj.material = bl.Material(
            m.color, m.texture, emission=m.emission, emission_strength=m.emission_strength
        )
    return scene


@pytest.mark.parametrize("name", sorted(crosscheck.TRANSLUCENT_SCENES))
def test_translucent_crosscheck_scenes_are_ground_truth(ctx, name):
    """Flat colours, box filter: Cycles' noise, and for puffs its unfiltered minified texture,
    part it from the antialiased reference (glass 55.5 dB, puffs 45.4 dB at this size; the
    transparency_cycles benchmark gives the figures at 320x180 and 4096 samples)."""
    scene = crosscheck.TRANSLUCENT_SCENES[name]()
    cycles = bl.blender.render(scene, SIZE, samples=512, seed=1).color
    shutter = cycles_shutter(scene.shutter)
    ours = ctx.reference(scene, SIZE, shutter, samples=1024, antialias=True, progress=False).color
    assert bl.metrics.psnr(ours, cycles) > 42


def alpha_modes_file(path):
    """A glTF file: an opaque backdrop, a BLEND pane (factor alpha 0.4) and a MASK quad whose
    texture's alpha alternates 1 and 0.16 (cutoff 0.5), all KHR_materials_unlit, so that
    Blender's importer makes emission shaders and blurlab, lit by ambient 1 alone, the same."""
    import io as bytes_io

    from gltf_writer import GltfBuilder
    from PIL import Image

    b = GltfBuilder()
    rgba = np.zeros((8, 8, 4), np.uint8)
    rgba[..., :3] = (60, 200, 80)
    rgba[..., 3] = np.where((np.arange(8)[:, None] + np.arange(8)) % 4 < 2, 255, 40)
    png = bytes_io.BytesIO()
    Image.fromarray(rgba, "RGBA").save(png, format="PNG")
    materials = [
        b.material((0.3, 0.5, 0.8, 1.0)),
        b.material((0.9, 0.6, 0.2, 0.4), alpha_mode="BLEND"),
        b.texture_material(png.getvalue(), alpha_mode="MASK", alpha_cutoff=0.5),
    ]
    for m in materials:
        b.doc.materials[m].extensions = {"KHR_materials_unlit": {}}
    b.doc.extensionsUsed = ["KHR_materials_unlit"]
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
    sizes = [(3.0, 1.6), (0.8, 0.8), (0.8, 0.8)]
    places = [[0, 0, -1], [-0.4, 0, 0], [0.5, 0, 0.3]]
    for material, (w, h), place in zip(materials, sizes, places, strict=True):
        corners = np.array([[-w / 2, -h / 2, 0], [w / 2, -h / 2, 0], [w / 2, h / 2, 0],
                            [-w / 2, h / 2, 0]], np.float32)  # fmt: skip
        normals = np.tile(np.float32([0, 0, 1]), (4, 1))
        triangles = np.array([0, 1, 2, 0, 2, 3], np.uint32)
        mesh = b.mesh(corners, triangles, normals, uvs=uvs, material=material)
        b.node(mesh=mesh, translation=place)
    b.node(camera=b.camera(0.7, 0.1, 100.0), translation=[0, 0, 5])
    return b.save(path)


def test_a_blend_and_mask_gltf_renders_as_blender_imports_it(ctx, tmp_path):
    # 80x45: at 40x24 the masked 8x8 texture is minified, and blurlab's mipmaps then differ
    # from Cycles' many unfiltered samples (46 dB).
    size = (80, 45)
    path = alpha_modes_file(tmp_path / "alpha_modes.gltf")
    background = (0.05, 0.05, 0.1)
    with pytest.warns(UserWarning, match="KHR_materials_unlit"):
        scene = bl.scenes.gltf(path, size_hint=size)
    scene.light, scene.background = crosscheck.UNLIT, np.array([*background, 1.0])
    assert sorted(obj.material.blend for obj in scene.objects) == ["blend", "mask", "opaque"]
    blender = bl.blender.render_gltf(path, size, samples=1024, seed=1, background=background)
    ours = ctx.reference(scene, size, samples=1024, antialias=True, progress=False).color
    assert bl.metrics.psnr(ours, blender.color) > 55
