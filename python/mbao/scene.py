"""Scenes from files and from arrays (SPEC 3.2)."""

import os
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike

from . import _checks, _core
from ._types import PathLike
from ._warnings import warn


class Mesh(_core._Mesh):
    """A scene made from arrays: Mesh(vertices, indices, normals=None, texcoords=None).

    vertices: (N, 3) numbers, world space; indices: (M, 3) integers into vertices,
    one row per triangle; normals: optional (N, 3) vertex normals (zero rows mean
    "no normal here": the geometric normal is used); texcoords: optional (N, 2)
    UVs, one set, which mbao.bake(target="texture") bakes into. Arrays are copied.
    """

    def __init__(
        self,
        vertices: ArrayLike,
        indices: ArrayLike,
        normals: Optional[ArrayLike] = None,
        texcoords: Optional[ArrayLike] = None,
    ) -> None:
        vertices = _checks.rows("vertices", vertices, 3, "fiu", np.float32)
        indices = _checks.rows("indices", indices, 3, "iu", np.int64)
        if indices.size and (indices.min() < 0 or indices.max() >= len(vertices)):
            bad = int(np.flatnonzero((indices < 0) | (indices >= len(vertices)))[0])
            raise ValueError(
                f"indices: triangle {bad // 3} uses vertex {int(indices.flat[bad])}, "
                f"but there are {len(vertices)} vertices"
            )
        if normals is not None:
            normals = _checks.rows("normals", normals, 3, "fiu", np.float32)
            if len(normals) != len(vertices):
                raise ValueError(f"normals has {len(normals)} rows for {len(vertices)} vertices")
        if texcoords is not None:
            texcoords = _checks.rows("texcoords", texcoords, 2, "fiu", np.float32)
            if len(texcoords) != len(vertices):
                raise ValueError(f"texcoords has {len(texcoords)} rows for {len(vertices)} vertices")
            texcoords.flags.writeable = False
        super().__init__(vertices, indices.astype(np.uint32), normals)
        self.texcoords = texcoords
        for message in self.warnings:
            warn(message)

    # Its own __init__'s signature, not the one mbao gives Scene's constructor.
    __signature__ = None

    def __repr__(self):
        return f"<mbao.Mesh: {self.triangle_count} triangles, {len(self.vertices)} vertices>"

    # Pickled as the core's state and the UVs, which only this class keeps.
    def __getstate__(self):
        return super().__getstate__(), self.texcoords

    def __setstate__(self, state):
        core, texcoords = state
        super().__setstate__(core)
        self.texcoords = texcoords


def is_gltf_path(path):
    """Whether `path` names a glTF file (.gltf or .glb), the format mbao reads stored bakes from."""
    return os.fspath(path).lower().endswith((".gltf", ".glb"))


def load(path: PathLike, *, normals: bool = True, texcoords: bool = False) -> _core.Scene:
    """Loads a glTF 2.0 file (.gltf or .glb): every triangle mesh of the default
    scene in world space (triangles, strips and fans; Draco-, meshopt- and
    quantization-compressed ones too), its vertex normals, the alpha masks of
    its MASK materials and its first perspective camera. Nothing else is read:
    no other attribute, no image but the alpha of mask textures. A mask image
    that cannot be read or decoded is named in a warning, and its surface is
    opaque (SPEC 3.2). normals=False skips the
    normals too (renders with normals="geometric" do not use them);
    texcoords=True also reads every UV set, the triangles' materials and their
    occlusion textures (scene.uv_sets), which texture bakes use.

    Every other format Assimp reads (.obj, .ply, .stl, .fbx, .dae, .3ds, ...)
    gives the triangles of its node tree in world space, their normals where
    the file has them, its first perspective camera, and alpha masks from its
    materials' opacity maps (OBJ map_d) or the alpha of their diffuse maps, cut
    at 0.5; with texcoords=True its meshes' UV channels as UV sets (v down the
    image, as glTF's) and their materials (SPEC 3.2).

    What is skipped (other primitive modes, ...) is reported as a warning and
    listed in scene.warnings. Raises mbao.LoadError naming the file and element.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike, got {type(path).__name__}")
    normals, texcoords = _checks.boolean("normals", normals), _checks.boolean("texcoords", texcoords)
    return _warned(_core.load(os.fspath(path), normals, texcoords))


def load_with_base_colors(path):
    """load(path, texcoords=True) that also reads the base colour (factor and image) of each material of a file of
    another format than glTF, into scene.uv_sets["materials"][i]["base_color"]: what bake_file writes them as. An
    image that cannot be read is named in a warning."""
    return _warned(_core.load(os.fspath(path), True, True, True))


def _warned(scene):
    """`scene`, its warnings issued as Python warnings at the user's line."""
    for message in scene.warnings:
        warn(message)
    return scene


def as_scene(scene):
    """`scene` if it is an mbao.Scene, else the glTF file it names, loaded (mbao.load) for this call."""
    if isinstance(scene, _core.Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return load(scene)
    raise TypeError(
        f"scene must be an mbao.Scene, an mbao.Mesh or the path of a scene file, got {type(scene).__name__}"
    )


# camera="frame": the camera that frames the whole scene, whatever camera it has (SPEC 3.1).
FRAME = "frame"


def as_camera(camera, scene=None, size=None):
    """`camera` if it is an mbao.Camera or None; for "frame", the camera that
    frames `scene` at `size` (width, height) (SPEC 3.1); else the camera.json
    file it names (SPEC 3.1.1), loaded."""
    if camera is None or isinstance(camera, _core.Camera):
        return camera
    if camera == FRAME:
        if scene is None:
            raise TypeError('camera="frame" frames a scene: this call has none to frame')
        return scene.framing_camera(*size)
    if isinstance(camera, (str, os.PathLike)):
        return _core.Camera.load(os.fspath(camera))
    raise TypeError(
        f'camera must be an mbao.Camera, the path of a camera.json file, "frame" or None, '
        f"got {type(camera).__name__}"
    )
