"""Runs inside the child process that blurlab.blender starts: builds the exported scene in
Blender and renders it. Needs bpy and NumPy only (never imports blurlab, so a Blender crash
here cannot touch the caller's GL context). Usage: python child.py JOB_FOLDER."""

from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np


def main(folder: Path) -> None:
    job = json.loads((folder / "job.json").read_text())
    arrays = np.load(folder / "arrays.npz")
    import bpy  # noqa: PLC0415 (after the job is read: a bad job fails fast)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    keys = job["keys"]
    frames = [1.0 + k / keys for k in range(keys + 1)]  # one frame = the shutter
    configure(bpy, scene, job)
    world(bpy, scene, job["background"])
    if "gltf" in job:  # the file as Blender's own importer makes it, through its camera
        bpy.ops.import_scene.gltf(filepath=job["gltf"])
        scene.camera = next(o for o in scene.objects if o.type == "CAMERA")
        finish(bpy, scene, job, folder)
        return
    camera = camera_object(bpy, job)
    scene.collection.objects.link(camera)
    scene.camera = camera
    animate(camera, arrays["camera"], frames)
    for i, description in enumerate(job["objects"]):
        obj = mesh_object(bpy, description, arrays, i)
        scene.collection.objects.link(obj)
        animate(obj, arrays[f"world{i}"], frames)
    if job["sun"]:
        scene.collection.objects.link(sun(bpy, job["sun"]))
    for obj in scene.objects:
        if job["engine"] == "CYCLES":
            obj.cycles.use_motion_blur = True
            obj.cycles.use_deform_motion = True
            obj.cycles.motion_steps = job["steps"]
        linear_keys(obj)
    if job["instant"] is None:
        scene.frame_set(1)
    else:
        t0, t1 = job["shutter"]
        frame = 1.0 + (job["instant"] - t0) / (t1 - t0)
        scene.frame_set(int(math.floor(frame)), subframe=frame - math.floor(frame))
    if job["passes"]:
        passes(scene)
    finish(bpy, scene, job, folder)


def finish(bpy, scene, job, folder: Path) -> None:
    """Renders the scene into render.exr and writes result.json."""
    scene.render.filepath = str(folder / "render.exr")
    started = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    render_s = time.perf_counter() - started
    result = {"render_s": render_s, "device": device(job), "settings": settings(bpy, scene, job)}
    (folder / "result.json").write_text(json.dumps(result))


def configure(bpy, scene, job) -> None:
    render = scene.render
    render.engine = job["engine"]
    render.resolution_x, render.resolution_y = job["size"]
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    t0, t1 = job["shutter"]
    render.fps, render.fps_base = 1, t1 - t0  # one frame per shutter
    scene.frame_start = scene.frame_end = 1
    render.use_motion_blur = job["instant"] is None
    render.motion_blur_position = "START"
    render.motion_blur_shutter = 1.0
    render.film_transparent = False
    render.use_compositing = False
    render.use_sequencer = False
    settings = render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    if job["engine"] == "CYCLES":
        cycles = scene.cycles
        cycles.device = "CPU"
        cycles.samples = job["samples"]
        cycles.use_adaptive_sampling = False
        cycles.use_denoising = False
        cycles.max_bounces = 0
        for bounce in ("diffuse", "glossy", "transmission", "volume", "transparent_max"):
            setattr(cycles, f"{bounce}_bounces", 0)
        cycles.transparent_max_bounces = job.get("transparent_bounces", 0)
        cycles.pixel_filter_type = "BOX"
        cycles.filter_width = 1.0
        cycles.seed = job["seed"]
        cycles.use_animated_seed = False
        cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    else:
        eevee = scene.eevee
        eevee.taa_render_samples = job["samples"]
        eevee.motion_blur_steps = job["steps"]
        eevee.use_shadows = False
        eevee.use_raytracing = False


def passes(scene) -> None:
    """Combined, Depth and Vector in one multi-layer EXR. With one sample and a pixel filter
    0.01 px wide, every pass is sampled within 0.005 px of the pixel centre, as a
    rasterizer's G-buffer is; the Vector pass needs motion blur off (the instant)."""
    layer = scene.view_layers[0]
    layer.use_pass_z = True
    layer.use_pass_vector = True
    image = scene.render.image_settings
    image.media_type = "MULTI_LAYER_IMAGE"  # Blender 5: this first, then the format
    image.file_format = "OPEN_EXR_MULTILAYER"
    image.color_depth = "32"
    image.exr_codec = "ZIP"
    scene.cycles.samples = 1
    scene.cycles.filter_width = 0.01  # Blender's smallest


def world(bpy, scene, color) -> None:
    """The background colour for camera rays only: it must not light the surfaces."""
    scene.world = bpy.data.worlds.new("blurlab background")
    scene.world.use_nodes = True
    nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
    nodes.clear()
    background = nodes.new("ShaderNodeBackground")
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = 1.0
    dark = nodes.new("ShaderNodeBackground")
    dark.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    path = nodes.new("ShaderNodeLightPath")
    mix = nodes.new("ShaderNodeMixShader")
    links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    links.new(dark.outputs["Background"], mix.inputs[1])
    links.new(background.outputs["Background"], mix.inputs[2])
    output = nodes.new("ShaderNodeOutputWorld")
    links.new(mix.outputs["Shader"], output.inputs["Surface"])


def camera_object(bpy, job):
    data = bpy.data.cameras.new("blurlab camera")
    data.sensor_fit = "VERTICAL"
    data.sensor_height = 24.0
    data.lens = data.sensor_height / 2 / math.tan(math.radians(job["camera"]["fov_y"]) / 2)
    data.clip_start = job["camera"]["near"]
    data.clip_end = job["camera"]["far"]
    data.shift_x = data.shift_y = 0.0
    return bpy.data.objects.new("blurlab camera", data)


def mesh_object(bpy, description, arrays, i):
    positions = arrays[f"positions{i}"].astype(np.float32)
    if description.get("skinned"):
        positions = arrays[f"skinned{i}"][0].astype(np.float32)  # the shape keys' basis
    indices = arrays[f"indices{i}"].astype(np.int32)
    mesh = bpy.data.meshes.new(description["name"])
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.loops.add(indices.size)
    mesh.loops.foreach_set("vertex_index", indices.ravel())
    mesh.polygons.add(len(indices))
    mesh.polygons.foreach_set("loop_start", np.arange(0, indices.size, 3, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(indices), dtype=bool))
    mesh.update()
    if not description.get("skinned"):  # a deforming mesh keeps Blender's own smooth normals
        normals = arrays[f"normals{i}"].astype(np.float64)
        mesh.normals_split_custom_set_from_vertices([tuple(n) for n in normals])
    texture = None
    if description["textured"]:
        uvs = arrays[f"uvs{i}"].astype(np.float32)
        layer = mesh.uv_layers.new(name="uv")
        layer.data.foreach_set("uv", uvs[indices.ravel()].ravel())
        texture = image(bpy, description["name"], arrays[f"texture{i}"])
    mesh.materials.append(material(bpy, description, texture))
    obj = bpy.data.objects.new(description["name"], mesh)
    if description.get("skinned"):
        deform(obj, arrays[f"skinned{i}"])
    # blurlab shades locally: no surface lights, shadows or reflects another. Emissive
    # meshes would otherwise light their neighbours even with zero bounces (direct light).
    obj.visible_diffuse = obj.visible_glossy = obj.visible_transmission = False
    obj.visible_volume_scatter = obj.visible_shadow = False
    return obj


def deform(obj, positions) -> None:
    """Baked skinning as shape keys: key k holds the positions at frame 1 + k/K and its value
    is a tent over the neighbouring frames, so the mesh moves linearly from one baked step to
    the next (Cycles' and EEVEE's deformation blur sample it)."""
    keys = len(positions) - 1
    obj.shape_key_add(name="t0", from_mix=False).data.foreach_set("co", positions[0].ravel())
    for k in range(1, keys + 1):
        shape = obj.shape_key_add(name=f"t{k}", from_mix=False)
        shape.data.foreach_set("co", positions[k].ravel())
        frame = 1.0 + k / keys
        for value, at in ((0.0, frame - 1.0 / keys), (1.0, frame), (0.0, frame + 1.0 / keys)):
            shape.value = value
            shape.keyframe_insert("value", frame=at)
    shape_keys = obj.data.shape_keys
    for curve in fcurves(shape_keys.animation_data.action):
        curve.extrapolation = "CONSTANT"  # 0 outside its tent
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"


def image(bpy, name, rgba):
    """A float image from blurlab's linear texture; Blender's row 0 is v = 0, as blurlab's."""
    height, width = rgba.shape[:2]
    result = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    result.colorspace_settings.name = "Linear Rec.709"
    result.alpha_mode = "CHANNEL_PACKED"  # colour and alpha apart: neither scales the other
    result.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    result.update()
    return result


def material(bpy, description, texture=None):
    """Emission (albedo · ambient) plus a diffuse BSDF lit by the sun: blurlab's Lambert;
    albedo = colour × texture, sampled at the mesh's UVs, repeating."""
    mat = bpy.data.materials.new(description["name"])
    mat.use_nodes = True
    mat.cycles.emission_sampling = "NONE"  # not a light source for other surfaces
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    if texture is None:
        emission.inputs["Color"].default_value = (*description["emission"], 1.0)
        diffuse.inputs["Color"].default_value = (*description["diffuse"], 1.0)
    else:
        sampled = nodes.new("ShaderNodeTexImage")
        sampled.image = texture
        sampled.interpolation = "Linear"
        sampled.extension = "REPEAT"
        coordinates = nodes.new("ShaderNodeUVMap")
        coordinates.uv_map = "uv"
        links.new(coordinates.outputs["UV"], sampled.inputs["Vector"])
        for target, factor in ((emission, "emission"), (diffuse, "diffuse")):
            scaled = nodes.new("ShaderNodeVectorMath")
            scaled.operation = "MULTIPLY"
            links.new(sampled.outputs["Color"], scaled.inputs[0])
            scaled.inputs[1].default_value = description[factor]
            links.new(scaled.outputs["Vector"], target.inputs["Color"])
    add = nodes.new("ShaderNodeAddShader")
    links.new(emission.outputs["Emission"], add.inputs[0])
    links.new(diffuse.outputs["BSDF"], add.inputs[1])
    shaded = add.outputs["Shader"]
    if any(v > 0 for v in description.get("radiance", (0, 0, 0))):
        glow = nodes.new("ShaderNodeEmission")
        glow.inputs["Color"].default_value = (*description["radiance"], 1.0)
        glow.inputs["Strength"].default_value = 1.0
        lit = nodes.new("ShaderNodeAddShader")
        links.new(shaded, lit.inputs[0])
        links.new(glow.outputs["Emission"], lit.inputs[1])
        shaded = lit.outputs["Shader"]
    output = nodes.new("ShaderNodeOutputMaterial")
    links.new(alpha_blend(nodes, links, description, shaded, texture), output.inputs["Surface"])
    return mat


def alpha_blend(nodes, links, description, shaded, texture):
    """docs/spec.md §20.1 as shader mixes: mask keeps the surface where alpha >= cutoff and is
    transparent elsewhere; blend mixes it with a transparent BSDF by alpha; additive adds
    alpha x the surface to a white transparent BSDF. Alpha = the material's x the texture's."""
    blend = description.get("blend", "opaque")
    if blend == "opaque":
        return shaded
    alpha = nodes.new("ShaderNodeMath")
    alpha.operation = "MULTIPLY"
    alpha.inputs[0].default_value = description["alpha"]
    alpha.inputs[1].default_value = 1.0
    if texture is not None:
        sampled = next(n for n in nodes if n.bl_idname == "ShaderNodeTexImage")
        links.new(sampled.outputs["Alpha"], alpha.inputs[1])
    factor = alpha.outputs["Value"]
    if blend == "mask":
        kept = nodes.new("ShaderNodeMath")
        kept.operation = "GREATER_THAN"  # alpha > cutoff - 1e-7: alpha >= cutoff in float32
        links.new(factor, kept.inputs[0])
        kept.inputs[1].default_value = description["alpha_cutoff"] - 1e-7
        factor = kept.outputs["Value"]
    clear = nodes.new("ShaderNodeBsdfTransparent")
    clear.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    mix = nodes.new("ShaderNodeMixShader")
    links.new(factor, mix.inputs["Fac"])
    if blend == "additive":  # alpha x surface, then added to what lies behind
        black = nodes.new("ShaderNodeEmission")
        black.inputs["Strength"].default_value = 0.0
        links.new(black.outputs["Emission"], mix.inputs[1])
        links.new(shaded, mix.inputs[2])
        add = nodes.new("ShaderNodeAddShader")
        links.new(clear.outputs["BSDF"], add.inputs[0])
        links.new(mix.outputs["Shader"], add.inputs[1])
        return add.outputs["Shader"]
    links.new(clear.outputs["BSDF"], mix.inputs[1])
    links.new(shaded, mix.inputs[2])
    return mix.outputs["Shader"]


def sun(bpy, description):
    import mathutils  # noqa: PLC0415 (bpy's companion module, present only with bpy)

    data = bpy.data.lights.new("blurlab sun", "SUN")
    data.energy = description["strength"]
    data.color = description["color"]
    data.angle = 0.0
    data.use_shadow = False
    data.specular_factor = 0.0
    obj = bpy.data.objects.new("blurlab sun", data)
    # A sun shines along its local -z: +z points toward the light.
    direction = mathutils.Vector(description["direction"])
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = direction.to_track_quat("Z", "Y")
    return obj


def animate(obj, matrices, frames) -> None:
    """Keys location, rotation (quaternion, sign kept continuous) and scale at every frame."""
    import mathutils  # noqa: PLC0415

    obj.rotation_mode = "QUATERNION"
    previous = None
    for matrix, frame in zip(matrices, frames, strict=True):
        m = mathutils.Matrix(matrix.tolist())
        location, rotation, scale = m.decompose()  # no shear: blurlab.blender checked
        if previous is not None and previous.dot(rotation) < 0:
            rotation.negate()
        previous = rotation
        obj.location, obj.rotation_quaternion, obj.scale = location, rotation, scale
        for path in ("location", "rotation_quaternion", "scale"):
            obj.keyframe_insert(path, frame=frame)


def linear_keys(obj) -> None:
    """Linear interpolation and extrapolation on every F-curve of the object's action."""
    animation = obj.animation_data
    if animation is None or animation.action is None:
        return
    for curve in fcurves(animation.action):
        curve.extrapolation = "LINEAR"
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"


def fcurves(action):
    """Every F-curve of a Blender 5 layered action: layers -> strips -> channel bags."""
    for layer in action.layers:
        for strip in layer.strips:
            for bag in strip.channelbags:
                yield from bag.fcurves


def device(job) -> str:
    if job["engine"] == "CYCLES":
        return f"Cycles on the CPU ({os.cpu_count()} threads)"
    # Background mode hides the GL renderer string; the GL driver loaded into this process
    # says which device EEVEE ran on.
    try:
        maps = Path("/proc/self/maps").read_text()
    except OSError:
        maps = ""
    if "nvidia" in maps.lower():
        return "EEVEE on an NVIDIA GPU (EGL)"
    if "swrast" in maps or "gallium" in maps or "llvmpipe" in maps:
        return "EEVEE on Mesa's software rasterizer (llvmpipe, CPU)"
    return "EEVEE on the GPU that Blender's EGL found"


def settings(bpy, scene, job) -> dict:
    render = scene.render
    out = {
        "blender": bpy.app.version_string,
        "engine": render.engine,
        "resolution": [render.resolution_x, render.resolution_y],
        "fps": render.fps,
        "fps_base": render.fps_base,
        "use_motion_blur": render.use_motion_blur,
        "motion_blur_position": render.motion_blur_position,
        "motion_blur_shutter": render.motion_blur_shutter,
        "keys_per_shutter": job["keys"],
        "view_transform": scene.view_settings.view_transform,
        "look": scene.view_settings.look,
        "exposure": scene.view_settings.exposure,
        "instant": job["instant"],
        "passes": job["passes"],
    }
    if job["engine"] == "CYCLES":
        cycles = scene.cycles
        out.update(
            samples=cycles.samples,
            seed=cycles.seed,
            pixel_filter_type=cycles.pixel_filter_type,
            filter_width=cycles.filter_width,
            max_bounces=cycles.max_bounces,
            use_adaptive_sampling=cycles.use_adaptive_sampling,
            use_denoising=cycles.use_denoising,
            motion_steps=job["steps"],
        )
    else:
        out.update(
            taa_render_samples=scene.eevee.taa_render_samples,
            motion_blur_steps=scene.eevee.motion_blur_steps,
            filter_size=render.filter_size,
        )
    return out


if __name__ == "__main__":
    main(Path(sys.argv[1]))
