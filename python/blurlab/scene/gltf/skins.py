"""glTF skins: the joints and inverse bind matrices of a skin, and the per-vertex joint indices
and weights of a skinned primitive (four influences per vertex, as blurlab skins)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .accessors import accessor
from .animation import Nodes
from .document import GltfFile


@dataclass
class JointSkin:
    """A glTF skin: the skinning matrix of joint j at t is global_j(t) · inverseBind_j, applied
    to the mesh's bind-pose vertices (the skinned mesh node's own transform is ignored, as the
    glTF spec says)."""

    nodes: object  # Nodes
    joints: list[int]
    inverse_bind: np.ndarray  # (J, 4, 4)

    @property
    def bones(self) -> list[int]:
        return self.joints

    def matrices(self, t: float) -> np.ndarray:
        globals_ = self.nodes.world(t)
        return np.stack(
            [globals_[j] @ m for j, m in zip(self.joints, self.inverse_bind, strict=True)]
        )


def joint_skin(file: GltfFile, index: int, nodes: Nodes) -> JointSkin:
    skin = file.doc.skins[index]
    count = len(file.doc.nodes)
    joints = [file.index(j, count, f"skin {index} joint") for j in skin.joints or []]
    if not joints:
        file.fail(f"skin {index} has no joints")
    if skin.inverseBindMatrices is None:
        inverse = np.tile(np.eye(4), (len(joints), 1, 1))
    else:
        flat = accessor(
            file, skin.inverseBindMatrices, f"skin {index} inverseBindMatrices", ("MAT4",)
        )
        if len(flat) != len(joints):
            file.fail(
                f"skin {index} has {len(flat)} inverse bind matrices for {len(joints)} joints"
            )
        inverse = flat.reshape(-1, 4, 4).transpose(0, 2, 1)  # column-major
    return JointSkin(nodes, joints, inverse)


def skin_weights(file: GltfFile, attributes, label: str, n: int, joint_count: int):
    sets = []
    for k in range(2):
        j = getattr(attributes, f"JOINTS_{k}", None)
        w = getattr(attributes, f"WEIGHTS_{k}", None)
        if j is None and w is None:
            continue
        if j is None or w is None:
            file.fail(f"{label} has JOINTS_{k} or WEIGHTS_{k} without the other")
        jj = accessor(file, j, f"{label} JOINTS_{k}", ("VEC4",), False)
        ww = accessor(file, w, f"{label} WEIGHTS_{k}", ("VEC4",))
        file.check_count(jj, n, f"{label} JOINTS_{k}")
        file.check_count(ww, n, f"{label} WEIGHTS_{k}")
        sets.append((jj, ww))
    if not sets:
        file.fail(f"{label} belongs to a skinned node but has no JOINTS_0/WEIGHTS_0")
    joints = np.concatenate([s[0] for s in sets], axis=1)
    weights = np.concatenate([s[1] for s in sets], axis=1)
    if np.any(weights < 0):
        file.fail(f"{label} has negative skin weights")
    if joints.min() < 0 or joints[weights > 0].max(initial=0) >= joint_count:
        file.fail(f"{label} names a joint outside its skin's {joint_count}")
    joints = np.where(weights > 0, joints, 0)
    if joints.shape[1] > 4:
        # blurlab skins with four influences: keep the four largest, renormalised.
        top = np.argsort(-weights, axis=1, kind="stable")[:, :4]
        if np.any(np.take_along_axis(weights, np.argsort(-weights, axis=1)[:, 4:], 1) > 0):
            warnings.warn(
                f"blurlab.scene.gltf: {file.path.name}: {label} has more than four joint weights "
                "per vertex; the four largest are kept and renormalised",
                stacklevel=5,
            )
        joints = np.take_along_axis(joints, top, 1)
        weights = np.take_along_axis(weights, top, 1)
    total = weights.sum(axis=1, keepdims=True)
    if np.any(total <= 0):
        file.fail(f"{label} has a vertex whose skin weights are all zero")
    return joints.astype(np.uint32), weights / total
