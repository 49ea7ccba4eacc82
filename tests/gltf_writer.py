"""Writes small glTF 2.0 files for the tests through pygltflib: nodes, meshes, animations,
skins and textures from NumPy arrays, in one buffer (a data: URI in .gltf, the binary chunk in
.glb)."""

from __future__ import annotations

import base64
from pathlib import Path

import numpy as np
import pygltflib as g

_COMPONENT = {np.float32: 5126, np.uint16: 5123, np.uint32: 5125, np.uint8: 5121}
_TYPE = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class GltfBuilder:
    def __init__(self):
        self.doc = g.GLTF2(asset=g.Asset(version="2.0"), scenes=[g.Scene(nodes=[])], scene=0)
        self.blob = bytearray()

    def accessor(self, array, dtype=np.float32) -> int:
        a = np.ascontiguousarray(np.asarray(array, dtype=dtype))
        a2 = a.reshape(len(a), -1)
        while len(self.blob) % 4:
            self.blob.append(0)
        view = len(self.doc.bufferViews)
        self.doc.bufferViews.append(
            g.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=a.nbytes)
        )
        self.blob += a.tobytes()
        kwargs = {}
        if dtype == np.float32 and np.isfinite(a2).all():
            kwargs = {"min": a2.min(0).tolist(), "max": a2.max(0).tolist()}
        self.doc.accessors.append(
            g.Accessor(
                bufferView=view,
                componentType=_COMPONENT[dtype],
                count=len(a2),
                type=_TYPE[a2.shape[1]],
                **kwargs,
            )
        )
        return len(self.doc.accessors) - 1

    def node(self, root=True, **kwargs) -> int:
        self.doc.nodes.append(g.Node(**kwargs))
        index = len(self.doc.nodes) - 1
        if root:
            self.doc.scenes[0].nodes.append(index)
        return index

    def mesh(
        self,
        positions,
        indices=None,
        normals=None,
        uvs=None,
        joints=None,
        weights=None,
        material=None,
        mode=None,
    ) -> int:
        attributes = g.Attributes(POSITION=self.accessor(positions))
        if normals is not None:
            attributes.NORMAL = self.accessor(normals)
        if uvs is not None:
            attributes.TEXCOORD_0 = self.accessor(uvs)
        if joints is not None:
            attributes.JOINTS_0 = self.accessor(joints, np.uint16)
            attributes.WEIGHTS_0 = self.accessor(weights)
        primitive = g.Primitive(attributes=attributes, material=material, mode=mode)
        if indices is not None:
            primitive.indices = self.accessor(np.asarray(indices).ravel(), np.uint32)
        self.doc.meshes.append(g.Mesh(primitives=[primitive]))
        return len(self.doc.meshes) - 1

    def animate(
        self, node: int, path: str, times, values, interpolation="LINEAR", animation=0, name=None
    ):
        """A channel of animation number `animation` (made, named `name`, when it is new)."""
        while len(self.doc.animations) <= animation:
            self.doc.animations.append(g.Animation(samplers=[], channels=[]))
        if name is not None:
            self.doc.animations[animation].name = name
        animation = self.doc.animations[animation]
        animation.samplers.append(
            g.AnimationSampler(
                input=self.accessor(np.asarray(times).reshape(-1, 1)),
                output=self.accessor(values),
                interpolation=interpolation,
            )
        )
        animation.channels.append(
            g.AnimationChannel(
                sampler=len(animation.samplers) - 1,
                target=g.AnimationChannelTarget(node=node, path=path),
            )
        )

    def skin(self, joints, inverse_bind) -> int:
        flat = np.asarray(inverse_bind, dtype=np.float32).transpose(0, 2, 1).reshape(-1, 16)
        self.doc.skins.append(g.Skin(joints=list(joints), inverseBindMatrices=self.accessor(flat)))
        return len(self.doc.skins) - 1

    def texture_material(self, png_bytes: bytes, factor=(1, 1, 1, 1), **alpha) -> int:
        while len(self.blob) % 4:
            self.blob.append(0)
        self.doc.bufferViews.append(
            g.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(png_bytes))
        )
        self.blob += png_bytes
        self.doc.images.append(
            g.Image(bufferView=len(self.doc.bufferViews) - 1, mimeType="image/png")
        )
        self.doc.textures.append(g.Texture(source=len(self.doc.images) - 1))
        return self.material(factor, texture=len(self.doc.textures) - 1, **alpha)

    def material(self, factor=(1, 1, 1, 1), texture=None, alpha_mode=None, alpha_cutoff=None):
        """A material's index; `alpha_mode` and `alpha_cutoff` as glTF's alphaMode, alphaCutoff."""
        pbr = g.PbrMetallicRoughness(baseColorFactor=list(factor), metallicFactor=0)
        if texture is not None:
            pbr.baseColorTexture = g.TextureInfo(index=texture)
        material = g.Material(pbrMetallicRoughness=pbr)
        if alpha_mode is not None:
            material.alphaMode = alpha_mode
        if alpha_cutoff is not None:
            material.alphaCutoff = alpha_cutoff
        self.doc.materials.append(material)
        return len(self.doc.materials) - 1

    def camera(self, yfov: float, znear: float, zfar: float | None) -> int:
        self.doc.cameras.append(
            g.Camera(
                type="perspective",
                perspective=g.Perspective(yfov=yfov, znear=znear, zfar=zfar, aspectRatio=16 / 9),
            )
        )
        return len(self.doc.cameras) - 1

    def save(self, path) -> Path:
        path = Path(path)
        blob = bytes(self.blob)
        if path.suffix == ".glb":
            self.doc.buffers = [g.Buffer(byteLength=len(blob))]
            self.doc.set_binary_blob(blob)
            self.doc.save_binary(str(path))
        else:
            uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
            self.doc.buffers = [g.Buffer(byteLength=len(blob), uri=uri)]
            self.doc.save_json(str(path))
        return path


def box_triangles(size=1.0):
    """A cube's 24 vertices (flat normals) and 12 triangles, centred on the origin."""
    h = size / 2
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1
            v = np.cross(n, u)
            base = len(positions)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append(n * h + u * h * a + v * h * b)
                normals.append(n)
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return np.array(positions), np.array(normals), np.array(indices).reshape(-1, 3)


def moving_box(path):
    """Writes a box sliding 4 units along x over t in [0, 1] before a camera at z = 5 (.gltf or
    .glb by the suffix); returns the path."""
    builder = GltfBuilder()
    positions, normals, indices = box_triangles()
    node = builder.node(mesh=builder.mesh(positions, indices, normals))
    builder.animate(node, "translation", [0.0, 1.0], [[-2, 0, 0], [2, 0, 0]])
    builder.node(camera=builder.camera(0.9, 0.1, 50.0), translation=[0, 0, 5])
    return builder.save(path)
