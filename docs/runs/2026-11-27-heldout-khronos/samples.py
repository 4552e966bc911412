"""The held-out Khronos samples: which file of each, what its README says a right render shows, and the view.

None of these files is shipped or read by the tests (tests/data/khronos holds MeshPrimitiveModes and SimpleMorph
only). ``right`` paraphrases the sample's README (or, where the README gives no description, what the model
plainly is); ``view`` is the direction from the model's centre to the camera (default +z, the glTF front).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Sample:
    name: str
    variant: str
    feature: str
    right: str
    view: tuple[float, float, float] = (0.0, 0.0, 1.0)
    zoom: float = 1.0  # > 1 moves the camera closer than the bounding sphere needs (wide, flat test boards)
    tag: str = ""  # a second view of the same file: "+tag" after its key
    sky: bool = False  # wgpurender also lit by its procedural sky ([environment]); pygfx gets none

    @property
    def key(self) -> str:
        return f"{self.name}/{self.variant}" + (f"+{self.tag}" if self.tag else "")

    @property
    def file(self) -> str:
        suffix = ".glb" if self.variant == "glTF-Binary" else ".gltf"
        return f"{self.name}/{self.variant}/{self.name}{suffix}"


SAMPLES = (
    Sample("MetalRoughSpheresNoTextures", "glTF-Binary", "PBR spheres",
           "a grid of spheres: metallic rises along one axis, roughness along the other; rough spheres have "
           "wide dim highlights, smooth ones small sharp highlights, metals take their base colour", zoom=1.3),
    Sample("TextureTransformTest", "glTF", "KHR_texture_transform",
           "six quads: top row shows the UV texture's offset quadrants (no yellow), bottom row arrows point "
           "at the green markers (rotation 22.5 deg, scale 1.5, all three)"),
    Sample("TextureTransformMultiTest", "glTF-Binary", "KHR_texture_transform + TEXCOORD_1",
           "rows of checkmarks, the three tiles of each row virtually identical (transforms on every texture "
           "input, TEXCOORD_1 transformed too)"),
    Sample("MultiUVTest", "glTF-Binary", "TEXCOORD_1",
           "a cube whose base colour uses TEXCOORD_0 and emissive TEXCOORD_1: two different textures overlaid"),
    Sample("TextureCoordinateTest", "glTF-Binary", "UV orientation",
           "texture coordinates (0,0) at the image's top-left: the quads show the labelled corners of the "
           "texture in the matching places"),
    Sample("AnimatedMorphCube", "glTF-Quantized", "morph + KHR_mesh_quantization",
           "a cube with two morph targets (thin, angle); default weights 0: the plain cube (animation not "
           "played)", (0.6, 0.5, 1.0)),
    Sample("MorphPrimitivesTest", "glTF-Draco", "morph (weights 0.5) + Draco",
           "a red grid over 3 quadrants and a green quadrant, the centre raised by the morph targets at half "
           "strength", (1.0, 0.0, 0.35)),
    Sample("SimpleInstancing", "glTF-Binary", "EXT_mesh_gpu_instancing",
           "a 5x5x5 block of 125 cubes, each an instance of one mesh", (0.6, 0.5, 1.0)),
    Sample("Avocado", "glTF-Quantized", "KHR_mesh_quantization + textures",
           "an avocado half: green skin and yellow flesh, brown stone (textured)"),
    Sample("Duck", "glTF-Quantized", "KHR_mesh_quantization",
           "the yellow rubber duck with its texture"),
    Sample("Duck", "glTF-Draco", "KHR_draco_mesh_compression",
           "the yellow rubber duck with its texture"),
    Sample("Box", "glTF-Draco", "Draco, minimal",
           "a red cube", (0.6, 0.5, 1.0)),
    Sample("WaterBottle", "glTF-Draco", "Draco + PBR textures + emissive",
           "a metal water bottle with a label, textured PBR"),
    Sample("UnlitTest", "glTF-Binary", "KHR_materials_unlit",
           "two objects of one uniform colour each, orange #FF7F00 and blue #007FFF, the 3D effect lost"),
    Sample("EmissiveStrengthTest", "glTF-Binary", "KHR_materials_emissive_strength",
           "cubes progressively brighter to the right (without the extension all the same light blue)", zoom=1.3),
    Sample("LightsPunctualLamp", "glTF", "KHR_lights_punctual + transmission",
           "a lamp whose lights (spot and point) light it; transmission glass (not supported by either)"),
    Sample("AlphaBlendModeTest", "glTF-Binary", "alpha modes",
           "OPAQUE ignores alpha, BLEND shows the background through a gradient, MASK cuts at each cutoff as "
           "labelled (green checkmarks where it passes)", zoom=1.15),
    Sample("TextureSettingsTest", "glTF-Binary", "wrap modes, doubleSided",
           "every box in the Test column looks like its Sample pass box: green checkmarks, the two clamp "
           "tests solid green", zoom=1.3),
    Sample("SimpleSkin", "glTF-Embedded", "skin (not supported)",
           "a strip of quads bent by two joints when animated; bind pose: a straight vertical strip"),
    Sample("RiggedSimple", "glTF-Binary", "skin (not supported)",
           "a cylinder rigged with two bones; bind pose: a straight cylinder"),
    Sample("CesiumMan", "glTF-Draco", "skin + Draco",
           "the textured Cesium man; bind pose standing (walk animation not played)"),
    Sample("BoxAnimated", "glTF-Binary", "animation (not supported)",
           "a smaller box inside a larger hollow one; at rest the small one sits inside", (0.6, 0.5, 1.0)),
    Sample("AnimatedTriangle", "glTF-Embedded", "animation (not supported)",
           "a triangle that rotates when animated; at rest one triangle"),
    Sample("Cameras", "glTF-Embedded", "cameras (file camera not used by either)",
           "a plane; the file's two cameras are not the viewer's"),
    Sample("BoxVertexColors", "glTF-Binary", "COLOR_0",
           "a cube coloured by position: (0,0,0) black, (1,0,0) red, (1,1,0) yellow, (1,1,1) white",
           (0.6, 0.5, 1.0)),
    Sample("VertexColorTest", "glTF-Binary", "COLOR_0 x baseColor",
           "two rows of checkmarks: the Test row (vertex colours times base colour) like the Sample row", zoom=1.3),
    Sample("BoxInterleaved", "glTF-Binary", "interleaved byteStride",
           "a grey cube", (0.6, 0.5, 1.0)),
    Sample("SimpleSparseAccessor", "glTF-Embedded", "sparse accessor",
           "a flat grid of quads with a block of vertices raised by the sparse accessor"),
    Sample("TriangleWithoutIndices", "glTF-Embedded", "non-indexed",
           "one triangle"),
    Sample("OrientationTest", "glTF-Binary", "node rotations",
           "each coloured arrow points at its target indicator of the same colour, opposite the point",
           (1.0, 0.8, 1.0)),
    Sample("OrientationTest", "glTF-Binary", "node rotations, the far side",
           "each coloured arrow points at its target indicator of the same colour, opposite the point",
           (-1.0, -0.8, -1.0), tag="back"),
    Sample("NegativeScaleTest", "glTF-Binary", "negative scale",
           "mirrored objects lit and culled like their originals (winding flips with negative determinant)", zoom=1.2),
    Sample("TwoSidedPlane", "glTF", "doubleSided",
           "a textured plane visible from both sides", (0.0, 0.3, 1.0)),
    Sample("TwoSidedPlane", "glTF", "doubleSided, the back",
           "the same plane from behind: drawn (doubleSided), its back lit with the normal turned around",
           (0.0, -0.3, -1.0), tag="back"),
    Sample("BoxTexturedNonPowerOfTwo", "glTF-Binary", "NPOT texture",
           "a cube with the CesiumLogo texture on each face", (0.6, 0.5, 1.0)),
    Sample("NormalTangentMirrorTest", "glTF-Binary", "normal map with tangents",
           "normal-mapped hemispheres lit like the geometry beside them, mirrored UVs included"),
    Sample("NormalTangentMirrorTest", "glTF-Binary", "normal map with tangents, under a sky",
           "every test block (real geometry and the normal-mapped quads beside it) shows similar reflections of "
           "the environment's horizon, level", tag="sky", sky=True),
    Sample("SpecGlossVsMetalRough", "glTF", "KHR_materials_pbrSpecularGlossiness (required)",
           "expected to fail to load without the spec/gloss extension (it is required)"),
    Sample("MultipleScenes", "glTF-Embedded", "scene index",
           "the default scene (1): a square, not the triangle"),
    Sample("TextureLinearInterpolationTest", "glTF-Binary", "sRGB texture filtering",
           "the spheres of each pair nearly the same colour (filtering after sRGB decoding)", zoom=1.5),
)

# Each sample's licence as its metadata.json states it (legal: license (artist)); the renders of a sample are
# derived images under the same licence. Samples whose licence is not CC0 or plain CC-BY (Sony's SCEA licence,
# Cesium's trademark terms) are left out of the committed contact sheets (NO_SHEET); their rows stay in the CSV.
LICENCES = {
    "AlphaBlendModeTest": "CC-BY 4.0 (Ed Mackey)",
    "AnimatedMorphCube": "CC0 (Microsoft)",
    "AnimatedTriangle": "CC0 (javagl)",
    "Avocado": "CC0 (Microsoft)",
    "Box": "CC-BY 4.0 (Cesium)",
    "BoxAnimated": "CC-BY 4.0 (Cesium)",
    "BoxInterleaved": "CC-BY 4.0 (Cesium)",
    "BoxTexturedNonPowerOfTwo": "LicenseRef-CC-BY-TM (Cesium)",
    "BoxVertexColors": "Public Domain / CC0 (Marco Hutter)",
    "Cameras": "CC0 (javagl)",
    "CesiumMan": "LicenseRef-CC-BY-TM (Cesium)",
    "Duck": "SCEA (Sony)",
    "EmissiveStrengthTest": "CC-BY 4.0 (Ed Mackey)",
    "LightsPunctualLamp": "CC-BY 4.0 (DGG)",
    "MetalRoughSpheresNoTextures": "CC0 (Open CASCADE Draw Harness script); CC0 (Krill Gavrilov)",
    "MorphPrimitivesTest": "CC-BY 4.0 (Frank Galligan); CC-BY 4.0 (ft-lab)",
    "MultiUVTest": "CC-BY 4.0 (Hilo 3D)",
    "MultipleScenes": "Public Domain / CC0 (Public)",
    "NegativeScaleTest": "CC-BY International 4.0 (Ed Mackey)",
    "NormalTangentMirrorTest": "CC-BY 4.0 (Ed Mackey)",
    "OrientationTest": "CC-BY 4.0 (Khronos)",
    "RiggedSimple": "CC-BY 4.0 (Cesium)",
    "SimpleInstancing": "Public Domain / CC0 (Marco Hutter)",
    "SimpleSkin": "CC0 (javagl)",
    "SimpleSparseAccessor": "CC-BY 4.0 (javagl)",
    "SpecGlossVsMetalRough": "CC-BY 4.0 (Microsoft)",
    "TextureCoordinateTest": "CC0 (Ed Mackey)",
    "TextureLinearInterpolationTest": "CC0 (lexaknyazev)",
    "TextureSettingsTest": "CC-BY 4.0 (Ed Mackey)",
    "TextureTransformMultiTest": "CC-BY 4.0 (Ed Mackey)",
    "TextureTransformTest": "CC0 (Microsoft)",
    "TriangleWithoutIndices": "CC0 (javagl)",
    "TwoSidedPlane": "CC0 (Norbert Nopper)",
    "UnlitTest": "CC-BY 4.0 (Ed Mackey)",
    "VertexColorTest": "CC-BY 4.0 (Ed Mackey)",
    "WaterBottle": "CC0 (Microsoft)",
}

NO_SHEET = {"Duck", "CesiumMan", "BoxTexturedNonPowerOfTwo"}
