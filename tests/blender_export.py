"""Run by Blender's Python (bpy) in a child process: builds a named scene in Blender, exports it
with Blender's glTF exporter at its defaults, and writes what Blender itself evaluates (each
object's world matrix at given frames) beside it as JSON.

    python blender_export.py SCENE OUT.glb
"""

from __future__ import annotations

import json
import sys

import bpy

FPS = 24


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


SCENES = {"timing": timing}


def main(name: str, out: str) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.render.fps = FPS
    objects, frames = SCENES[name]()
    evaluated = {}
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        evaluated[frame] = {o.name: [list(row) for row in o.matrix_world] for o in objects}
    bpy.context.scene.frame_set(1)
    bpy.ops.export_scene.gltf(filepath=out)
    with open(out + ".json", "w") as f:
        json.dump({"fps": FPS, "frames": evaluated}, f)


if __name__ == "__main__":
    main(sys.argv[-2], sys.argv[-1])
