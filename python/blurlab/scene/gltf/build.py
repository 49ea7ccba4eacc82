"""A blurlab Scene from an opened glTF file: its nodes' meshes, materials and skins, the
shutter, and the camera (the file's, or one that frames the scene's bounds)."""

from __future__ import annotations

import math
import warnings

import numpy as np

from ...errors import cause
from ..model import Camera, Scene
from .animation import (
    DEFAULT_SHUTTER_S,
    CameraNodeMotion,
    NodeMotion,
    Nodes,
    busiest_time,
    node_hierarchy,
)
from .document import GltfFile
from .materials import read_material
from .meshes import primitive_mesh
from .skins import JointSkin, joint_skin


def build_scene(file: GltfFile, animation, camera, size_hint, shutter) -> Scene:
    """The Scene of `file`'s scene: what blurlab.scene.gltf.load returns, its arguments as given."""
    doc = file.doc
    nodes, order = node_hierarchy(file, animation)
    if shutter is None:
        start = busiest_time(nodes)
        shutter = (start, start + DEFAULT_SHUTTER_S)
    scene = Scene(name=file.path.name, shutter=tuple(float(s) for s in shutter))
    scene.source = file.path
    materials: dict = {}
    skins: dict[int, JointSkin] = {}
    for i in order:
        node = doc.nodes[i]
        if node.mesh is None:
            continue
        meshes = doc.meshes or []
        mesh_index = file.index(node.mesh, len(meshes), f"node {i} mesh")
        skin = None
        if node.skin is not None:
            skin_index = file.index(node.skin, len(doc.skins or []), f"node {i} skin")
            if skin_index not in skins:
                skins[skin_index] = joint_skin(file, skin_index, nodes)
            skin = skins[skin_index]
        for p, primitive in enumerate(meshes[mesh_index].primitives or []):
            label = f"mesh {mesh_index} primitive {p}"
            mesh = primitive_mesh(file, primitive, label, skin)
            material = read_material(file, primitive.material, materials)
            name = f"{node.name or f'node{i}'}/{meshes[mesh_index].name or label}/{p}"
            motion = None if skin else NodeMotion(nodes, i)
            scene.add(mesh, material, motion, skin, name)
    if not scene.objects:
        file.fail("its scene has no mesh to draw")
    if file.ignored:
        warnings.warn(
            f"blurlab.scene.gltf: {file.path.name}: ignored {', '.join(sorted(file.ignored))}",
            stacklevel=3,
        )
    scene.camera = scene_camera(file, camera, nodes, order, scene, size_hint)
    return scene


def scene_camera(
    file: GltfFile, camera, nodes: Nodes, order: list[int], scene: Scene, size_hint
) -> Camera:
    if isinstance(camera, Camera):
        return camera
    cameras = file.doc.cameras or []
    if camera is not None:
        file.index(camera, len(cameras), "camera")
    wanted = camera if camera is not None else 0
    for i in order:
        if file.doc.nodes[i].camera is not None and file.doc.nodes[i].camera == wanted:
            return _file_camera(file, cameras[wanted], wanted, nodes, i, scene)
    if camera is not None:
        file.fail(f"camera {camera} is used by no node of the scene")
    return _framing_camera(scene, size_hint)


def _file_camera(
    file: GltfFile, entry, index: int, nodes: Nodes, node: int, scene: Scene
) -> Camera:
    if entry.type != "perspective" or entry.perspective is None:
        file.fail(f"camera {index} is {entry.type!r}; only perspective cameras are read")
    p = entry.perspective
    fov = math.degrees(file.floats([p.yfov], f"camera {index} yfov", 1)[0])
    near = file.floats([p.znear], f"camera {index} znear", 1)[0]
    far = None if p.zfar is None else file.floats([p.zfar], f"camera {index} zfar", 1)[0]
    if far is None:  # an infinite projection: far enough for the scene's bounds
        center, radius = _bounds(scene)
        eye = nodes.world(scene.shutter[0])[node][:3, 3]
        far = max(near * 1e4, 4.0 * (np.linalg.norm(eye - center) + radius))
    try:
        return Camera(
            position=(0, 0, 0),
            look_at=(0, 0, -1),
            fov_y=fov,
            near=near,
            far=far,
            motion=CameraNodeMotion(nodes, node),
        )
    except ValueError as error:
        file.fail(f"camera {index}: {cause(error)}")


def _framing_camera(scene: Scene, size_hint) -> Camera:
    """A camera on +z of the scene's bounds at the shutter's opening, looking at their centre,
    with the bounding sphere inside the view (docs/spec.md §15)."""
    center, radius = _bounds(scene)
    fov_y = 45.0
    aspect = 16 / 9 if size_hint is None else float(size_hint[0]) / float(size_hint[1])
    half = math.radians(fov_y) / 2
    half = min(half, math.atan(math.tan(half) * aspect))
    distance = 1.1 * radius / math.sin(half)
    return Camera(
        position=tuple(center + np.array([0.0, 0.0, distance])),
        look_at=tuple(center),
        fov_y=fov_y,
        near=max(distance - 2 * radius, distance * 1e-3),
        far=distance + 4 * radius,
    )


def _bounds(scene: Scene) -> tuple[np.ndarray, float]:
    t = scene.shutter[0]
    points = []
    for obj in scene.objects:
        p = np.c_[obj.mesh.positions.astype(np.float64), np.ones(len(obj.mesh.positions))]
        if obj.skeleton is not None:
            bones = obj.skeleton.matrices(t)
            skinning = np.einsum(
                "vk,vkij->vij", obj.mesh.bone_weights, bones[obj.mesh.bone_indices]
            )
            p = np.einsum("vij,vj->vi", skinning, p)
        points.append((p @ obj.model(t).T)[:, :3])
    points = np.concatenate(points)
    low, high = points.min(axis=0), points.max(axis=0)
    center = 0.5 * (low + high)
    radius = max(float(np.linalg.norm(high - low)) / 2, 1e-3)
    return center, radius
