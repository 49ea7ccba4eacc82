"""Run by Blender's Python (bpy) in a child process: builds a named scene in Blender, exports it
with Blender's glTF exporter at its defaults, and writes what Blender itself evaluates (each
object's world matrix at given frames) beside it as JSON. With a size, Cycles also renders
frame RENDER_FRAME still and with motion blur (shutter half a frame, centred on the frame),
as OUT.still.exr and OUT.blur.exr.

    python blender_export.py SCENE OUT.glb [WIDTH HEIGHT SAMPLES]
"""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import bpy

FPS = 24
RENDER_FRAME = 13
SHUTTER_FRAMES = 0.5  # Blender's default: a 180° shutter
BACKGROUND = (0.05, 0.05, 0.07)  # a glTF scene's background in blurlab


def blurlab_child():
    """blurlab's own Blender child script, for its background-only world (it imports bpy and
    NumPy, never blurlab)."""
    path = Path(__file__).resolve().parents[1] / "python" / "blurlab" / "blender" / "child.py"
    spec = importlib.util.spec_from_file_location("blurlab_child", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def timing():
    """A cube keyed at frames 10 and 34, and a second one turning 3.5 rad from frame 1 to 48."""
    cube = cube_at((0, 0, 0), "Slider")
    cube.keyframe_insert("location", frame=10)
    cube.location = (2, 0, 0)
    cube.keyframe_insert("location", frame=34)
    spinner = cube_at((0, 3, 0), "Spinner")
    spinner.keyframe_insert("rotation_euler", frame=1)
    spinner.rotation_euler = (0, 0, 3.5)
    spinner.keyframe_insert("rotation_euler", frame=48)
    return [cube, spinner], range(1, 49)


def cube_at(location, name):
    bpy.ops.mesh.primitive_cube_add(location=location)
    bpy.context.object.name = name
    return bpy.context.object


def emissive(name, color):
    """A material that only emits `color`: the exporter writes it as a black base colour and an
    emissive factor, which blurlab shades as the colour itself, as Cycles does."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0, 0, 0, 1)
    bsdf.inputs["Specular IOR Level"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Emission Color"].default_value = (*color, 1)
    bsdf.inputs["Emission Strength"].default_value = 1.0
    return material


def painted(obj, name, color):
    obj.data.materials.append(emissive(name, color))
    return obj


def key(obj, path, frame, value):
    setattr(obj, path, value)
    obj.keyframe_insert(path, frame=frame)


def roundtrip():
    """Several animated objects: a cube sliding, a parent turning 12 rad (more than 180°) with
    a child on its arm, a cube growing, a two-bone skinned bar bending, and a panning camera;
    each moves several pixels per shutter at 320×180 around frame RENDER_FRAME."""
    slider = painted(cube_at((-8, -4, 0.5), "Slider"), "red", (0.8, 0.1, 0.1))
    key(slider, "location", 1, (-8, -4, 0.5))
    key(slider, "location", 25, (2, -4, 0.5))
    bpy.ops.object.empty_add(location=(3.5, 3, 0))
    arm = bpy.context.object
    arm.name = "Arm"
    key(arm, "rotation_euler", 1, (0, 0, 0))
    key(arm, "rotation_euler", 25, (0, 0, 12.0))
    tip = painted(cube_at((5.5, 3, 0), "Tip"), "green", (0.1, 0.7, 0.2))
    tip.scale = (0.5, 0.5, 0.5)
    tip.parent = arm
    tip.location = (2, 0, 0)
    grower = painted(cube_at((-4, 3, 0.5), "Grower"), "blue", (0.2, 0.3, 0.9))
    key(grower, "scale", 1, (0.2, 0.2, 0.2))
    key(grower, "scale", 25, (1.4, 1.8, 1.0))
    bar, rig = skinned_bar()
    bpy.ops.object.camera_add(location=(0, -16, 7), rotation=(math.radians(68), 0, 0))
    camera = bpy.context.object
    camera.name = "Camera"
    bpy.context.scene.camera = camera
    key(camera, "location", 1, (-3, -16, 7))
    key(camera, "location", 25, (3, -16, 7))
    return [slider, arm, tip, grower, bar, rig, camera], range(1, 26)


def skinned_bar():
    """A bar along x from -1 to 1 at (0, 0.5, 1), bound to two bones; the outer one turns."""
    bpy.ops.mesh.primitive_cube_add(location=(0, 0, 0))
    bar = bpy.context.object
    bar.name = "Bar"
    bar.scale = (1.0, 0.2, 0.2)
    bpy.ops.object.transform_apply(scale=True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=7)
    bpy.ops.object.mode_set(mode="OBJECT")
    painted(bar, "yellow", (0.9, 0.8, 0.1))
    armature = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", armature)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    root = armature.edit_bones.new("Root")
    root.head, root.tail = (-1, 0, 0), (0, 0, 0)
    tip = armature.edit_bones.new("Tip")
    tip.head, tip.tail, tip.parent = (0, 0, 0), (1, 0, 0), root
    bpy.ops.object.mode_set(mode="OBJECT")
    groups = {name: bar.vertex_groups.new(name=name) for name in ("Root", "Tip")}
    for v in bar.data.vertices:
        w = min(max((v.co.x + 0.25) / 0.5, 0.0), 1.0)  # blend over the middle half unit
        groups["Root"].add([v.index], 1.0 - w, "REPLACE")
        groups["Tip"].add([v.index], w, "REPLACE")
    bar.parent = rig
    bar.modifiers.new("Armature", "ARMATURE").object = rig
    rig.location = (0, 0.5, 1)
    bone = rig.pose.bones["Tip"]
    bone.rotation_mode = "XYZ"
    key(bone, "rotation_euler", 1, (0, 0, -1.5))
    key(bone, "rotation_euler", 25, (0, 0, 3.0))
    return bar, rig


SCENES = {"timing": timing, "roundtrip": roundtrip}


def render(out: str, size, samples: int) -> None:
    scene = bpy.context.scene
    blurlab_child().world(bpy, scene, BACKGROUND)
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = size
    r.resolution_percentage = 100
    r.use_compositing = r.use_sequencer = False
    r.motion_blur_position = "CENTER"
    r.motion_blur_shutter = SHUTTER_FRAMES
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_mode = "RGBA"
    r.image_settings.color_depth = "32"
    scene.view_settings.view_transform = "Standard"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = cycles.use_denoising = False
    cycles.max_bounces = 0
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    for obj in scene.objects:
        obj.cycles.motion_steps = 3  # 5 transforms over the shutter (2^(steps-1) + 1)
    scene.frame_set(RENDER_FRAME)
    for blur in (False, True):
        r.use_motion_blur = blur
        r.filepath = f"{out}.{'blur' if blur else 'still'}.exr"
        bpy.ops.render.render(write_still=True)


def main(name: str, out: str, size=None, samples: int = 0) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.preferences.edit.keyframe_new_interpolation_type = "LINEAR"
    bpy.context.scene.render.fps = FPS
    if size:
        bpy.context.scene.render.resolution_x, bpy.context.scene.render.resolution_y = size
    objects, frames = SCENES[name]()
    evaluated = {}
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        evaluated[frame] = {o.name: [list(row) for row in o.matrix_world] for o in objects}
    bpy.context.scene.frame_set(1)
    bpy.ops.export_scene.gltf(
        filepath=out, export_cameras=True
    )  # its one option off by default that a shot needs
    with open(out + ".json", "w") as f:
        json.dump({"fps": FPS, "frames": evaluated}, f)
    if size:
        render(out, size, samples)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index(__file__) + 1 if __file__ in sys.argv else 1 :]
    if len(args) == 5:
        main(args[0], args[1], (int(args[2]), int(args[3])), int(args[4]))
    else:
        main(args[0], args[1])
