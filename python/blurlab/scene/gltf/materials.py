"""glTF materials as blurlab materials: the base colour factor and texture, and the emission
(KHR_materials_emissive_strength for HDR); what blurlab does not draw is noted as ignored."""

from __future__ import annotations

import io as bytes_io

import numpy as np

from ..model import MAX_EMISSION_STRENGTH, Material
from .document import GltfError, GltfFile

MAX_IMAGE_PIXELS = 1 << 26  # 8192 x 8192: larger base colour textures are refused


def read_material(file: GltfFile, index, cache: dict) -> Material:
    if index is None:
        return Material(color=(1.0, 1.0, 1.0))
    materials = file.doc.materials or []
    index = file.index(index, len(materials), "material")
    if index in cache:
        return cache[index]
    m = materials[index]
    pbr = m.pbrMetallicRoughness
    color = (1.0, 1.0, 1.0, 1.0)
    texture = None
    if pbr is not None:
        color = file.floats(pbr.baseColorFactor or color, f"material {index} baseColorFactor", 4)
        if pbr.baseColorTexture is not None:
            texture = base_color_texture(file, pbr.baseColorTexture, index)
        if pbr.metallicRoughnessTexture is not None or (pbr.metallicFactor not in (None, 0)):
            file.ignored.add("metallic-roughness")
    for feature in ("normalTexture", "occlusionTexture", "emissiveTexture"):
        if getattr(m, feature, None) is not None:
            file.ignored.add(feature)
    emission = file.floats(m.emissiveFactor or (0, 0, 0), f"material {index} emissiveFactor", 3)
    extensions = dict(m.extensions or {})
    # KHR_materials_emissive_strength scales the factor beyond 1: blurlab's HDR emission.
    strength_ext = extensions.pop("KHR_materials_emissive_strength", None) or {}
    strength = 1.0
    if isinstance(strength_ext, dict) and "emissiveStrength" in strength_ext:
        strength = file.floats([strength_ext["emissiveStrength"]], "emissiveStrength", 1)[0]
    if np.any(emission < 0) or np.any(emission > 1) or not 0 <= strength <= MAX_EMISSION_STRENGTH:
        file.fail(
            f"material {index}: emission {emission.tolist()} x {strength} is outside colour "
            f"[0, 1] x strength [0, {MAX_EMISSION_STRENGTH:g}]"
        )
    blend, cutoff = alpha_mode(file, m, index)
    if not 0.0 <= color[3] <= 1.0:
        file.fail(f"material {index}: baseColorFactor alpha {color[3]} is outside [0, 1]")
    if extensions:
        file.ignored.add("material extensions " + ", ".join(sorted(extensions)))
    lit = bool(np.any(emission > 0))
    cache[index] = Material(
        color=tuple(float(c) for c in color[:3]),
        texture=texture,
        emission=tuple(float(e) for e in emission),
        emission_strength=float(strength) if lit else 0.0,
        alpha=float(color[3]) if blend != "opaque" else 1.0,
        blend=blend,
        alpha_cutoff=cutoff,
    )
    return cache[index]


# glTF's alphaMode as blurlab's Material.blend (docs/spec.md §15, §20).
ALPHA_MODES = {"OPAQUE": "opaque", "MASK": "mask", "BLEND": "blend"}


def alpha_mode(file: GltfFile, material, index: int) -> tuple[str, float]:
    """(blend, alpha_cutoff) of a glTF material: alphaMode (default OPAQUE) and alphaCutoff
    (default 0.5, MASK only), checked."""
    mode = material.alphaMode if material.alphaMode is not None else "OPAQUE"
    if not isinstance(mode, str) or mode not in ALPHA_MODES:
        file.fail(f"material {index}: alphaMode {mode!r} is not one of {sorted(ALPHA_MODES)}")
    cutoff = 0.5
    if material.alphaCutoff is not None:
        cutoff = file.floats([material.alphaCutoff], f"material {index} alphaCutoff", 1)[0]
        if not 0.0 <= cutoff <= 1.0:
            file.fail(f"material {index}: alphaCutoff {cutoff} is outside [0, 1]")
    return ALPHA_MODES[mode], float(cutoff)


def base_color_texture(file: GltfFile, info, material: int) -> np.ndarray:
    from PIL import Image, UnidentifiedImageError

    textures = file.doc.textures or []
    texture = textures[file.index(info.index, len(textures), f"material {material} texture")]
    if (info.texCoord or 0) != 0:
        file.ignored.add("texture coordinate sets other than 0")
    images = file.doc.images or []
    if texture.source is None:
        file.fail(f"material {material}'s texture has no image")
    image_index = file.index(texture.source, len(images), "texture source")
    image = images[image_index]
    what = f"image {image_index}"
    if image.uri is not None:
        data = file.external(str(image.uri), what)
    else:
        views = file.doc.bufferViews or []
        view = views[file.index(image.bufferView, len(views), f"{what} bufferView")]
        buffer = file.buffer(file.integer(view.buffer, f"{what} buffer", 0, 1 << 20))
        start, length = view.byteOffset or 0, view.byteLength or 0
        if start < 0 or length <= 0 or start + length > len(buffer):
            file.fail(f"{what}'s bufferView runs past its buffer")
        data = buffer[start : start + length]
    try:
        with Image.open(bytes_io.BytesIO(data), formats=("PNG", "JPEG")) as picture:
            w, h = picture.size
            if w * h > MAX_IMAGE_PIXELS:
                file.fail(f"{what} is {w}x{h}; at most {MAX_IMAGE_PIXELS} pixels are read")
            array = np.asarray(picture.convert("RGBA"))
    except GltfError:
        raise  # the size check above, which says what it found
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError) as error:
        file.fail(f"{what} could not be decoded as PNG or JPEG ({error})")
    return array
