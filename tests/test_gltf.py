"""glTF 2.0 scenes (docs/spec.md §15): files the tests write with pygltflib, their motion against
NumPy projections of the same transforms computed here, and bad files refused clearly."""

from __future__ import annotations

import io as bytes_io
import math
import warnings

import numpy as np
import pytest
from gltf_writer import GltfBuilder, box_triangles
from test_gbuffer import expected_motion

import blurlab as bl
from blurlab.scene.gltf import GltfError
from blurlab.scene.motion import quaternion_matrix

SIZE = (160, 90)
SHUTTER = (0.4, 0.5)
CAMERA = bl.Camera((0.0, 0.0, 6.0), (0.0, 0.0, 0.0), fov_y=50)


def xyzw(axis, angle):
    q = bl.quaternion(axis, angle)  # (w, x, y, z)
    return [q[1], q[2], q[3], q[0]]


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def translation(v):
    m = np.eye(4)
    m[:3, 3] = v
    return m


def apply(m, points):
    return points @ m[:3, :3].T + m[:3, 3]


def rigid(model_of_t):
    """local_of for expected_motion: the surface point follows model_of_t (a NumPy function)."""

    def local_of(world, mask):
        def at(t):
            return apply(model_of_t(t) @ np.linalg.inv(model_of_t(local_of.instant)), world)

        return at

    return local_of


def check_motion(ctx, scene, model_of_t, object_id=0, tolerance=0.01):
    frame = ctx.render(scene, SIZE, SHUTTER)
    local_of = rigid(model_of_t)
    local_of.instant = frame.time
    mask, expected = expected_motion(frame, scene, object_id, local_of)
    assert mask.sum() > 50
    assert np.abs(expected).max() > 3, "the test should move pixels"
    error = np.abs(frame.motion[mask] - expected).max()
    assert error <= tolerance, f"max motion error {error:.4f} px"


def box_file(tmp_path, suffix=".gltf", build=None):
    b = GltfBuilder()
    p, n, i = box_triangles(1.0)
    mesh = b.mesh(p, i, n)
    node = b.node(mesh=mesh)
    if build is not None:
        build(b, node)
    return b.save(tmp_path / f"box{suffix}")


def test_translating_node(ctx, tmp_path):
    velocity = np.array([4.0, 1.5, 0.0])

    def build(b, node):
        b.animate(node, "translation", [0.0, 1.0], [[0, 0, 0], velocity])

    scene = bl.scenes.gltf(box_file(tmp_path, build=build), camera=CAMERA)
    check_motion(ctx, scene, lambda t: translation(velocity * t))


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_rotating_child_under_a_moving_parent(ctx, tmp_path, suffix):
    b = GltfBuilder()
    p, n, i = box_triangles(0.8)
    child = b.node(root=False, mesh=b.mesh(p, i, n), translation=[1.0, 0.0, 0.0])
    parent = b.node(children=[child])
    b.animate(parent, "translation", [0.0, 1.0], [[-1, 0, 0], [5, 3, 0]])
    # Two keys a quarter turn apart: slerp turns at a constant rate.
    b.animate(child, "rotation", [0.0, 1.0], [xyzw((0, 0, 1), 0), xyzw((0, 0, 1), math.pi / 2)])
    scene = bl.scenes.gltf(b.save(tmp_path / f"nested{suffix}"), camera=CAMERA)

    def model(t):
        parent_at = translation(np.array([-1, 0, 0]) + t * np.array([6, 3, 0]))
        return parent_at @ translation([1, 0, 0]) @ rotation_z(t * math.pi / 2)

    check_motion(ctx, scene, model)


def test_cubic_spline_channel(ctx, tmp_path):
    times = np.array([0.0, 1.0])
    p0, p1 = np.array([-3.0, -1.0, 0.0]), np.array([3.0, 1.5, 0.0])
    m0, m1 = np.array([0.0, 8.0, 0.0]), np.array([9.0, 0.0, 0.0])
    values = [[0, 0, 0], p0, m0, m1, p1, [0, 0, 0]]  # in-tangent, value, out-tangent per key

    def build(b, node):
        b.animate(node, "translation", times, values, "CUBICSPLINE")

    scene = bl.scenes.gltf(box_file(tmp_path, build=build), camera=CAMERA)

    def hermite(t):
        s = t  # one-second key interval: tangents are used as they are
        h = (2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2)
        return translation(h[0] * p0 + h[1] * m0 + h[2] * p1 + h[3] * m1)

    check_motion(ctx, scene, hermite)
    motion = scene.objects[0].motion
    assert np.allclose(motion.transform(-3.0), translation(p0))  # clamped before the keys
    assert np.allclose(motion.transform(7.0), translation(p1))  # and after them


def test_step_interpolation_holds_each_key(tmp_path):
    def build(b, node):
        b.animate(node, "translation", [0.0, 1.0, 2.0], [[0, 0, 0], [1, 0, 0], [2, 0, 0]], "STEP")

    scene = bl.scenes.gltf(box_file(tmp_path, build=build), camera=CAMERA)
    at = lambda t: scene.objects[0].motion.transform(t)[0, 3]  # noqa: E731
    assert [at(t) for t in (0.0, 0.5, 0.99, 1.0, 1.7, 2.0, 9.0)] == [0, 0, 0, 1, 1, 2, 2]


def test_two_joint_skin_follows_cpu_skinning(ctx, tmp_path):
    # A bar along x from 0 to 2: vertices with x < 1 belong to joint 0, the rest to joint 1,
    # which turns about z at the elbow (1, 0, 0).
    xs = np.linspace(0.0, 2.0, 9)
    ring = [(0.25, 0.25), (-0.25, 0.25), (-0.25, -0.25), (0.25, -0.25)]
    positions = np.array([[x, y, z] for x in xs for y, z in ring])
    indices = []
    for s in range(len(xs) - 1):
        for k in range(4):
            a, b2, c, d = 4 * s + k, 4 * s + (k + 1) % 4, 4 * (s + 1) + k, 4 * (s + 1) + (k + 1) % 4
            indices += [a, c, b2, b2, c, d]
    joints = np.zeros((len(positions), 4), int)
    joints[positions[:, 0] >= 1.0, 0] = 1
    weights = np.zeros((len(positions), 4))
    weights[:, 0] = 1
    b = GltfBuilder()
    j1 = b.node(root=False, translation=[1.0, 0.0, 0.0])
    j0 = b.node(children=[j1], translation=[-1.0, -0.3, 0.0])
    inverse_bind = [
        np.linalg.inv(translation([-1, -0.3, 0])),
        np.linalg.inv(translation([0, -0.3, 0])),
    ]
    skin = b.skin([j0, j1], inverse_bind)
    b.node(mesh=b.mesh(positions, indices, joints=joints, weights=weights), skin=skin)
    b.animate(j1, "rotation", [0.0, 1.0], [xyzw((0, 0, 1), 0), xyzw((0, 0, 1), math.pi)])
    scene = bl.scenes.gltf(b.save(tmp_path / "skin.glb"), camera=CAMERA)
    frame = ctx.render(scene, SIZE, SHUTTER)

    def joint1(t):  # the joint's world matrix x its inverse bind matrix, in NumPy
        return (
            translation([-1, -0.3, 0])
            @ translation([1, 0, 0])
            @ rotation_z(math.pi * t)
            @ inverse_bind[1]
        )

    def local_of(world, mask):
        bind = apply(np.linalg.inv(joint1(frame.time)), world)
        local_of.moving = bind[:, 0] > 1.05  # vertices of joint 1 only (a margin at the elbow)
        return lambda t: apply(joint1(t), bind)

    mask, expected = expected_motion(frame, scene, 0, local_of)
    moving = local_of.moving
    assert moving.sum() > 30
    assert np.abs(expected[moving]).max() > 3
    assert np.abs(frame.motion[mask][moving] - expected[moving]).max() <= 0.01
    # The CPU-skinned vertices of the loader's matrices equal the NumPy ones.
    skinned = apply(scene.objects[0].skeleton.matrices(0.3)[1], positions)
    assert np.allclose(skinned, apply(joint1(0.3), positions))


def test_base_color_factor_and_srgb_texture(tmp_path):
    from PIL import Image

    texels = np.array([[[255, 128, 0, 255], [10, 20, 30, 255]]], np.uint8)
    png = bytes_io.BytesIO()
    Image.fromarray(texels, "RGBA").save(png, format="PNG")
    b = GltfBuilder()
    p, n, i = box_triangles()
    uvs = np.zeros((len(p), 2))
    material = b.texture_material(png.getvalue(), factor=(0.5, 1.0, 0.25, 1.0))
    b.node(mesh=b.mesh(p, i, n, uvs=uvs, material=material))
    scene = bl.scenes.gltf(b.save(tmp_path / "textured.gltf"))
    m = scene.objects[0].material
    assert np.allclose(np.asarray(m.color)[:3], (0.5, 1.0, 0.25))
    rgba = m.texture_rgba().astype(np.float64)
    assert np.allclose(rgba[..., :3], bl.io.srgb_to_linear(texels[..., :3] / 255.0), atol=1e-3)


def test_the_files_camera_and_the_framing_default(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles(2.0)
    b.node(mesh=b.mesh(p, i, n), translation=[3.0, 1.0, -2.0])
    cam = b.camera(yfov=0.7, znear=0.05, zfar=50.0)
    b.node(camera=cam, translation=[3.0, 1.0, 8.0], rotation=xyzw((0, 1, 0), 0.1))
    path = b.save(tmp_path / "camera.gltf")
    scene = bl.scenes.gltf(path)
    assert scene.camera.fov_y == pytest.approx(math.degrees(0.7))
    assert (scene.camera.near, scene.camera.far) == (0.05, 50.0)
    world = scene.camera.world(0.0)
    assert np.allclose(world[:3, 3], [3, 1, 8])
    assert np.allclose(world[:3, :3], quaternion_matrix(bl.quaternion((0, 1, 0), 0.1)))
    framed = bl.scenes.gltf(path, camera=None, size_hint=(90, 160))  # the file's camera wins
    assert framed.camera.fov_y == pytest.approx(math.degrees(0.7))
    # A file without a camera: every vertex lands inside the image at the hinted size.
    doc_without = tmp_path / "no_camera.gltf"
    b2 = GltfBuilder()
    b2.node(mesh=b2.mesh(p, i, n), translation=[3.0, 1.0, -2.0], scale=[4.0, 1.0, 1.0])
    scene = bl.scenes.gltf(b2.save(doc_without), size_hint=(90, 160))
    from blurlab.twins import projection

    corners = apply(scene.objects[0].model(0.0), p)
    pixels, depth = projection.project(corners, scene.camera, 0.0, (90, 160))
    assert (depth > scene.camera.near).all() and (depth < scene.camera.far).all()
    assert (pixels >= 0).all() and (pixels[:, 0] <= 90).all() and (pixels[:, 1] <= 160).all()


def test_missing_normals_are_flat(tmp_path):
    b = GltfBuilder()
    p, _, i = box_triangles()
    b.node(mesh=b.mesh(p, i))
    mesh = bl.scenes.gltf(b.save(tmp_path / "flat.gltf")).objects[0].mesh
    tri = mesh.positions[mesh.indices]
    face = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    assert np.allclose(mesh.normals[mesh.indices], face[:, None, :], atol=1e-6)


def test_a_second_weight_set_keeps_the_four_largest(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles()
    joints = [b.node(root=(k == 0)) for k in range(6)]
    b.doc.nodes[joints[0]].children = joints[1:]
    skin = b.skin(joints, [np.eye(4)] * 6)
    mesh = b.mesh(
        p,
        i,
        n,
        joints=np.tile([0, 1, 2, 3], (len(p), 1)),
        weights=np.tile([0.1, 0.3, 0.05, 0.15], (len(p), 1)),
    )
    primitive = b.doc.meshes[mesh].primitives[0]
    primitive.attributes.JOINTS_1 = b.accessor(np.tile([4, 5, 0, 0], (len(p), 1)), np.uint16)
    primitive.attributes.WEIGHTS_1 = b.accessor(np.tile([0.25, 0.15, 0.0, 0.0], (len(p), 1)))
    b.node(mesh=mesh, skin=skin)
    with pytest.warns(UserWarning, match="four largest"):
        scene = bl.scenes.gltf(b.save(tmp_path / "eight.gltf"))
    m = scene.objects[0].mesh
    assert sorted(m.bone_indices[0].tolist()) == [1, 3, 4, 5]
    assert np.allclose(m.bone_weights.sum(1), 1)
    assert np.isclose(m.bone_weights[0][m.bone_indices[0] == 1][0], 0.3 / 0.85, atol=1e-6)


def test_ignored_material_features_are_named_once(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles()
    material = b.material()
    b.doc.materials[material].normalTexture = {"index": 0}
    b.doc.materials[material].occlusionTexture = {"index": 0}
    b.doc.materials[material].alphaMode = "BLEND"  # honoured (docs/spec.md §20), not ignored
    b.node(mesh=b.mesh(p, i, n, material=material))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bl.scenes.gltf(b.save(tmp_path / "features.gltf"))
    messages = [str(w.message) for w in caught if "blurlab.scene.gltf" in str(w.message)]
    assert len(messages) == 1
    assert "normalTexture" in messages[0] and "occlusionTexture" in messages[0]
    assert "alphaMode" not in messages[0]


def test_emissive_factor_and_strength_become_hdr_emission(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles()
    material = b.material()
    b.doc.materials[material].emissiveFactor = [1.0, 0.5, 0.0]
    b.doc.materials[material].extensions = {
        "KHR_materials_emissive_strength": {"emissiveStrength": 300.0}
    }
    b.node(mesh=b.mesh(p, i, n, material=material))
    scene = bl.scenes.gltf(b.save(tmp_path / "lamp.gltf"))
    assert np.allclose(scene.objects[0].material.radiance, [300.0, 150.0, 0.0])
    assert scene.hdr
    b.doc.materials[material].emissiveFactor = [2.0, 0.0, 0.0]
    with pytest.raises(GltfError, match="outside colour"):
        bl.scenes.gltf(b.save(tmp_path / "too_bright.gltf"))


def _edit(tmp_path, name, change):
    b = GltfBuilder()
    p, n, i = box_triangles()
    node = b.node(mesh=b.mesh(p, i, n))
    b.animate(node, "translation", [0.0, 1.0], [[0, 0, 0], [1, 0, 0]])
    change(b)
    return b.save(tmp_path / name)


def _set(obj, **kwargs):
    for k, v in kwargs.items():
        setattr(obj, k, v)


BAD_FILES = {
    "accessor past its view": (
        lambda b: _set(b.doc.accessors[0], count=10**9),
        "count is 1000000000",
    ),
    "accessor out of range": (
        lambda b: _set(b.doc.meshes[0].primitives[0].attributes, POSITION=99),
        "POSITION accessor is 99",
    ),
    "short buffer": (
        lambda b: _set(b.doc.bufferViews[0], byteLength=10**7),
        "byteLength is 10000000",
    ),
    "line mode": (lambda b: _set(b.doc.meshes[0].primitives[0], mode=1), "only triangles"),
    "morph targets": (
        lambda b: _set(b.doc.meshes[0].primitives[0], targets=[{"POSITION": 0}]),
        "morph targets are not supported",
    ),
    "network uri": (
        lambda b: b.doc.images.append(
            __import__("pygltflib").Image(uri="https://example.com/x.png")
        ),
        None,  # an unused image is never fetched: the file loads
    ),
    "decreasing keys": (
        lambda b: b.doc.animations[0].samplers[0].__setattr__("input", 0),
        "do not increase|type 'VEC3'",
    ),
    "version 1": (lambda b: _set(b.doc.asset, version="1.0"), "only glTF 2.x"),
    "required extension": (
        lambda b: _set(b.doc, extensionsRequired=["KHR_draco_mesh_compression"]),
        "requires extensions",
    ),
    "cycle": (lambda b: _set(b.doc.nodes[0], children=[0]), "more than one parent"),
}


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_bad_files_are_refused_clearly(tmp_path, case):
    change, message = BAD_FILES[case]
    path = _edit(tmp_path, "bad.gltf", change)
    if message is None:
        bl.scenes.gltf(path)
        return
    with pytest.raises(GltfError, match=message) as error:
        bl.scenes.gltf(path)
    assert "bad.gltf" in str(error.value)


def _glb(json_chunk: bytes, magic: bytes = b"glTF") -> bytes:
    length = 12 + 8 + len(json_chunk)
    header = np.array([2, length, len(json_chunk), 0x4E4F534A], "<u4").tobytes()
    return magic + header + json_chunk


def _huge_texture(b, monkeypatch):
    from PIL import Image

    monkeypatch.setattr(bl.gltf.materials, "MAX_IMAGE_PIXELS", 1)
    png = bytes_io.BytesIO()
    Image.fromarray(np.zeros((2, 2, 4), np.uint8), "RGBA").save(png, format="PNG")
    p, n, i = box_triangles()
    material = b.texture_material(png.getvalue())
    b.node(mesh=b.mesh(p, i, n, uvs=np.zeros((len(p), 2)), material=material))


MALFORMED = {
    "cut JSON": ("bad.gltf", b'{"asset": ', "(Expecting value: line 1 column 11 (char 10))"),
    "broken GLB magic": (
        "bad.glb",
        _glb(b'{"asset": ', magic=b"glTX"),
        "not a glTF JSON document or GLB (Expecting value: line 1 column 1 (char 0))",
    ),
    "GLB magic and text": ("bad.glb", b"glTX" + b'{"asset": ', "Expecting value"),
    "not UTF-8": ("bad.glb", b"\xff\xfe{", "nor glTF JSON text: byte 0xff at 0 (invalid start"),
    "GLB chunk not UTF-8": ("bad.glb", _glb(b"\xff\xff\xff\xff"), "not UTF-8: byte 0xff at 0"),
}


def assert_says_its_cause_once(message: str, name: str):
    assert message.startswith(f"blurlab.scene.gltf: {name}: "), message
    assert message.count("blurlab") == 1 and message.count(name) == 1, message
    assert message.lower().count("utf-8") <= 1, message


@pytest.mark.parametrize("case", list(MALFORMED))
def test_a_malformed_file_says_its_cause_once(tmp_path, case):
    name, data, fragment = MALFORMED[case]
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(GltfError) as error:
        bl.scenes.gltf(path)
    assert fragment in str(error.value)
    assert_says_its_cause_once(str(error.value), name)


def test_a_refused_texture_says_its_cause_once(tmp_path, monkeypatch):
    path = _edit(tmp_path, "huge.glb", lambda b: _huge_texture(b, monkeypatch))
    with pytest.raises(GltfError, match="at most 1 pixels are read") as error:
        bl.scenes.gltf(path)
    assert "could not be decoded" not in str(error.value)
    assert_says_its_cause_once(str(error.value), "huge.glb")


def test_nan_positions_and_keyframes_are_refused(tmp_path):
    for what in ("positions", "keys"):
        b = GltfBuilder()
        p, n, i = box_triangles()
        if what == "positions":
            p = p.copy()
            p[3, 1] = np.nan
        node = b.node(mesh=b.mesh(p, i, n))
        b.animate(
            node,
            "translation",
            [0.0, 1.0],
            [[0, 0, 0], [np.inf, 0, 0]] if what == "keys" else [[0, 0, 0], [1, 0, 0]],
        )
        with pytest.raises(GltfError, match="NaN or inf"):
            bl.scenes.gltf(b.save(tmp_path / f"nan_{what}.gltf"))


@pytest.mark.parametrize(
    "uri, message",
    [
        ("../outside.bin", "leaves the file's folder"),
        ("/etc/passwd", "relative path"),
        ("http://example.com/data.bin", "never downloads"),
        ("file:///etc/passwd", "never downloads"),
        ("missing.bin", "does not exist"),
        ("data:application/octet-stream;base64,@@@", "not valid base64"),
    ],
)
def test_buffer_uris_that_leave_the_folder_or_the_machine_are_refused(tmp_path, uri, message):
    (tmp_path / "outside.bin").write_bytes(bytes(4096))
    folder = tmp_path / "model"
    folder.mkdir()
    path = _edit(folder, "scene.gltf", lambda b: None)
    text = path.read_text()
    import json

    doc = json.loads(text)
    doc["buffers"][0]["uri"] = uri
    path.write_text(json.dumps(doc))
    with pytest.raises(GltfError, match=message):
        bl.scenes.gltf(path)


def test_external_buffer_beside_the_file_and_a_path_with_spaces(tmp_path):
    folder = tmp_path / "a folder"
    folder.mkdir()
    path = _edit(folder, "scene one.gltf", lambda b: None)
    import base64
    import json

    doc = json.loads(path.read_text())
    data = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    (folder / "the data.bin").write_bytes(data)
    doc["buffers"][0]["uri"] = "the%20data.bin"
    path.write_text(json.dumps(doc))
    scene = bl.scenes.gltf(path)
    assert scene.name == "scene one.gltf" and len(scene.objects) == 1


def test_truncated_glb_and_broken_json(tmp_path):
    path = _edit(tmp_path, "scene.glb", lambda b: None)
    data = path.read_bytes()
    cut = tmp_path / "cut.glb"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(GltfError, match="truncated"):
        bl.scenes.gltf(cut)
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "nodes": [')
    with pytest.raises(GltfError, match="not a glTF JSON"):
        bl.scenes.gltf(broken)
    with pytest.raises(FileNotFoundError):
        bl.scenes.gltf(tmp_path / "absent.gltf")


def test_undecodable_image_is_refused(tmp_path):
    b = GltfBuilder()
    p, n, i = box_triangles()
    material = b.texture_material(b"\x89PNG\r\n\x1a\n" + bytes(40))
    b.node(mesh=b.mesh(p, i, n, uvs=np.zeros((len(p), 2)), material=material))
    with pytest.raises(GltfError, match="could not be decoded"):
        bl.scenes.gltf(b.save(tmp_path / "image.gltf"))


def test_scene_names_and_files_resolve_the_same_way(tmp_path):
    path = _edit(tmp_path, "moving box.glb", lambda b: None)
    assert bl.scenes.is_file(path) and bl.scenes.is_file(str(path))
    assert not bl.scenes.is_file("teapot_pass")
    assert bl.scenes.label(str(path)) == "moving box.glb"
    assert bl.scenes.get(str(path)).name == "moving box.glb"
    with pytest.raises(ValueError, match="gltf/.glb path"):
        bl.scenes.get("no_such_scene")


def test_oversized_json_and_empty_accessors_are_bounded(tmp_path):
    path = _edit(tmp_path, "big.gltf", lambda b: _set(b.doc, extras={"pad": [0] * 200_000}))
    with pytest.raises(GltfError, match="more than 100000 values"):
        bl.scenes.gltf(path)
    # An accessor without data reads as zeros: its size is bounded before anything is allocated.
    path = _edit(
        tmp_path, "zeros.gltf", lambda b: _set(b.doc.accessors[0], bufferView=None, count=2**40)
    )
    with pytest.raises(GltfError, match="count is 1099511627776"):
        bl.scenes.gltf(path)
