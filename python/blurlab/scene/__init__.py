"""The scene model: scenes, cameras and materials (model.py), meshes, motion and skeletons,
particles, translucent layers, blur scales, shutters and sampling, glTF import (gltf/) and the
scene catalogue (scenes/: built-in, failure, transparency, HDR and random scenes)."""
