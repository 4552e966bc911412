"""Scene files: TOML parsed and validated into frozen dataclasses.

A scene says what to draw (models, materials, lights, camera) and how to present
it (size, MSAA, HDR, post chain). :mod:`wgpurender.core.plan` turns a :class:`Scene`
into the passes and pipelines it needs. Full schema, with an example, in
docs/scenes.md; in short (every path is relative to the scene file's folder)::

    description = "optional text"

    [camera]                       # required
    eye = [0, 1, 3]                # required
    target = [0, 0, 0]             # required
    up = [0, 1, 0]
    fov_y = 45.0                   # degrees, vertical
    near = 0.1
    far = 100.0
    convention = "wgpu"            # or "glm-vulkan": see Camera

    [materials.brick]              # a named material (or inline: material = { ... } in a model)
    albedo_map = "textures/brick.png"      # sRGB colour texture
    albedo_color = [1, 1, 1]               # linear RGB(A); multiplies albedo_map
    normal_map = "textures/brick_n.png"    # tangent space, +Y up, linear
    roughness_map = "textures/brick_r.png" # linear, G channel (glTF layout)
    roughness = 0.5
    unlit = false
    uv_flip_v = false                      # v -> 1 - v, for meshes whose v = 0 is the bottom
    sampler = { filter = "linear", mipmaps = true, anisotropy = 1, address_mode = "repeat" }

    [[models]]                     # zero or more, drawn in order
    path = "models/cube.glb"       # .obj .gltf .glb .ply .stl .fbx
    material = "brick"             # a [materials] name, an inline table, or omitted (white, lit)
    transform = { translate = [0, 0, 0], rotate = { axis = [0, 1, 0], degrees = 30 }, scale = 1.0 }
    instances = { grid = [10, 10, 1], spacing = [2, 2, 2] }  # optional: N copies (core/scene/instances.py)
    # or rotate = { euler = [x, y, z] } (degrees, X then Y then Z), or matrix = 4 rows of 4 (alone)

    [[lights]]                     # at most MAX_LIGHTS
    type = "directional"           # or "point" (with position instead of direction)
    direction = [-1, -1, -1]       # the way the light travels
    color = [1, 1, 1]
    intensity = 1.0

    [render]
    size = [800, 600]
    msaa = 4                       # 1 or 4
    hdr = true                     # render into rgba16float (needed by tone mapping)
    clear_color = [0, 0, 0, 1]     # linear
    output_format = "rgba8unorm-srgb"

    [[post]]                       # effects in order; the keys besides `effect` are its parameters
    effect = "tonemap"
    exposure = 1.0

Every mistake raises :class:`UserError` as ``FILE:LINE: what, and what is valid``.
tomllib gives no line numbers for values, so :class:`KeyLines` finds them by
scanning the text for table headers and keys.

The package: :mod:`.toml_locator` (line numbers of keys), :mod:`.model` (the dataclasses), :mod:`.checker`
(typed checks with ``FILE:LINE`` errors), :mod:`.validate` (each part of the file), :mod:`.load` (read + parse).
"""

from wgpurender.core.scene.checker import Checker
from wgpurender.core.scene.load import load_scene, parse_scene
from wgpurender.core.scene.model import (
    ADDRESS_MODES,
    CONVENTIONS,
    DEFAULT_MATERIAL,
    FILTERS,
    IDENTITY,
    LIGHT_TYPES,
    MAX_ANISOTROPY,
    MAX_INSTANCES,
    MAX_LIGHTS,
    OUTPUT_FORMATS,
    Camera,
    Light,
    Material,
    Model,
    Placements,
    PostStep,
    RenderSettings,
    SamplerSettings,
    Scene,
    Transform,
    Vec3,
    Vec4,
)
from wgpurender.core.scene.toml_locator import KeyLines, KeyPath, format_path
from wgpurender.core.scene.validate import (
    CAMERA_KEYS,
    LIGHT_KEYS,
    MATERIAL_KEYS,
    MODEL_KEYS,
    RENDER_KEYS,
    SAMPLER_KEYS,
    TOP_KEYS,
    TRANSFORM_KEYS,
)

__all__ = [
    "ADDRESS_MODES", "CAMERA_KEYS", "CONVENTIONS", "Camera", "Checker", "DEFAULT_MATERIAL", "FILTERS", "IDENTITY",
    "KeyLines", "KeyPath", "LIGHT_KEYS", "LIGHT_TYPES", "Light", "MATERIAL_KEYS", "MAX_ANISOTROPY", "MAX_INSTANCES",
    "MAX_LIGHTS", "MODEL_KEYS", "Material", "Model", "OUTPUT_FORMATS", "Placements", "PostStep", "RENDER_KEYS",
    "RenderSettings",
    "SAMPLER_KEYS", "SamplerSettings", "Scene", "TOP_KEYS", "TRANSFORM_KEYS", "Transform", "Vec3", "Vec4",
    "format_path", "load_scene", "parse_scene",
]
