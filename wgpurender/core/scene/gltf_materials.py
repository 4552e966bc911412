"""A glTF model's own materials as scene materials: what the file's author meant, mapped onto the course's shading.

A model in a scene file without ``material = ...`` draws with its file's materials (the scene's ``material``
still overrides). Each file material its placed triangles use becomes one :class:`~wgpurender.core.scene.Material`
and one draw. What is taken, and how it maps onto the course's normalized Blinn-Phong (scene.wgsl):

- ``baseColorFactor`` x ``baseColorTexture`` (sRGB) -> base colour (x ``COLOR_0`` when the primitive has one);
- ``normalTexture`` with its ``scale`` -> normal map and its strength;
- ``roughnessFactor`` x the metallic-roughness texture's G channel -> the roughness;
- ``doubleSided`` -> no culling, back faces lit with the normal turned around;
- ``alphaMode`` OPAQUE / MASK (``alphaCutoff``: fragments below are discarded) / BLEND (alpha blending, drawn
  after the opaque draws, not sorted by depth);
- each texture's own sampler: mag/min/mipmap filters and per-axis wrap (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT);
- ``emissiveFactor`` (x ``KHR_materials_emissive_strength``) x ``emissiveTexture`` (sRGB) -> added to the shaded
  colour;
- ``occlusionTexture`` (R channel) with its ``strength`` -> scales the ambient term (lit materials);
- ``KHR_materials_unlit`` -> an unlit material (base colour only: emissive and occlusion unused).
- ``KHR_materials_clearcoat`` -> a clear coat over a lit metallic-roughness material: ``clearcoatFactor`` x
  ``clearcoatTexture``'s R, ``clearcoatRoughnessFactor`` x ``clearcoatRoughnessTexture``'s G, ``clearcoatNormalTexture``
  with its ``scale`` (shaders_wgsl/clearcoat.wgsl has the layering); each texture samples its own coordinate slot as
  the others do.
- ``KHR_materials_pbrSpecularGlossiness`` -> converted to metallic-roughness at load (gltf_specgloss.py: factors
  as factors, textures per texel into ``model.glb#specgloss[k].base`` / ``.metalrough`` images); the material's
  --explain line says so, and whether the conversion is exact or an approximation.

- a lit material -> the glTF metallic-roughness model (``shading_model = "pbr"``, shaders_wgsl/pbr.wgsl: the
  spec's Appendix B BRDF) with ``metallicFactor`` (default 1) x the metallic-roughness texture's B channel; the
  course's scene materials and primitives without a file material keep Blinn-Phong.
- each texture's ``texCoord`` and ``KHR_texture_transform`` -> its coordinate slot (gltf_geometry.uv_slots: the
  mesh carries one per distinct (set, transform) of the material, each a TEXCOORD set with its transform applied
  at load); a texture on slot k >= 1 is listed in ``Material.uv_slots`` and the plan gives its sampling the variant
  flag ``<feature>_uv<k>`` (only such materials read a second vertex attribute).

Ignored, and listed by ``--explain``: every other extension by name (the applied ones are listed as used).
"""

from __future__ import annotations

import dataclasses
import functools
import os
from pathlib import Path

from wgpurender.core.course.samplers import SamplerSpec
from wgpurender.core.files import read_jail
from wgpurender.core.files.input_files import input_file
from wgpurender.core.models import gltf_extensions, gltf_geometry, gltf_io
from wgpurender.core.scene import gltf_specgloss
from wgpurender.core.scene.model import DEFAULT_MATERIAL, Material, ModelMaterials

CLEARCOAT = gltf_extensions.CLEARCOAT
EMBEDDED_MARK = "#images["  # a texture "path" naming an image embedded in a model file: model.glb#images[3]
WRAP = {10497: "repeat", 33071: "clamp-to-edge", 33648: "mirror-repeat"}
MIN_FILTERS = {9728: ("nearest", None), 9729: ("linear", None), 9984: ("nearest", "nearest"),
               9985: ("linear", "nearest"), 9986: ("nearest", "linear"), 9987: ("linear", "linear")}
ROLES = {"albedo_map": ("pbrMetallicRoughness", "baseColorTexture"), "normal_map": ("normalTexture",),
         "roughness_map": ("pbrMetallicRoughness", "metallicRoughnessTexture"),
         "emissive_map": ("emissiveTexture",), "occlusion_map": ("occlusionTexture",),
         "clearcoat_map": ("extensions", CLEARCOAT, "clearcoatTexture"),
         "clearcoat_roughness_map": ("extensions", CLEARCOAT, "clearcoatRoughnessTexture"),
         "clearcoat_normal_map": ("extensions", CLEARCOAT, "clearcoatNormalTexture")}
SUPPORTED_MATERIAL_EXTENSIONS = ("KHR_materials_unlit", "KHR_materials_emissive_strength", gltf_specgloss.EXTENSION)
SUPPORTED_MATERIAL_EXTENSIONS += (CLEARCOAT,)
# extensionsUsed entries that are applied (gltf_extensions, gltf_compression): --explain lists them as used
USED_EXTENSIONS = frozenset(SUPPORTED_MATERIAL_EXTENSIONS) | gltf_extensions.SUPPORTED_REQUIRED


def embedded_image_path(model: Path, image: int) -> Path:
    return Path(f"{model}{EMBEDDED_MARK}{image}]")


def document(path: str) -> gltf_io.GltfDocument:
    """The parsed model, read once while the file is unchanged (the plan asks each embedded image's size, the
    upload its pixels: one read of a large GLB each, not one per image)."""
    stat = os.stat(path)
    return _read_cached(path, stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=4)
def _read_cached(path: str, mtime_ns: int, size: int) -> gltf_io.GltfDocument:
    return gltf_io.read_document(path)


def embedded_image_bytes(path: Path, decode=None) -> bytes | None:
    """The encoded bytes of an image a ``model.glb#images[k]`` path names, or None for an ordinary path; with
    ``decode`` (an image path -> (H, W, 4) uint8, texture_pixels.load_image) also a spec-gloss material's
    converted texture (``model.glb#specgloss[k].base``, gltf_specgloss.py)."""
    text = str(path)
    if gltf_specgloss.MARK in text:
        parsed = gltf_specgloss.parse_path(path)
        if parsed is None or decode is None:
            return None
        stat = os.stat(parsed[0])
        return _converted(parsed[0], stat.st_mtime_ns, stat.st_size, parsed[1], decode)[parsed[2]]
    if EMBEDDED_MARK not in text or not text.endswith("]"):
        return None
    model, _, index = text.rpartition(EMBEDDED_MARK)
    if not os.path.isfile(model):
        return None
    if model.lower().endswith(".fbx"):  # an image embedded in an FBX (core/scene/fbx_materials.py)
        from wgpurender.core.models import fbx

        return fbx.embedded_texture_bytes(Path(model), int(index[:-1]))
    doc = document(model)
    image = doc.json["images"][int(index[:-1])]
    source = gltf_io.image_source(doc, image)
    if source["data"] is not None:
        return source["data"]
    return read_jail.read_checked(input_file(source["uri"], "glTF image"))


@functools.lru_cache(maxsize=2)
def _converted(model: str, mtime_ns: int, size: int, index: int, decode) -> tuple[bytes, bytes]:
    """Both converted images of spec-gloss material ``index`` (asked twice: the plan's size, then the upload)."""
    doc = document(model)
    ext = doc.json["materials"][index]["extensions"][gltf_specgloss.EXTENSION]
    texels = {key: decode(texture_file(doc, doc.json["textures"][ext[key]["index"]]))
              for key in ("diffuseTexture", "specularGlossinessTexture") if isinstance(ext.get(key), dict)}
    return gltf_specgloss.converted_pngs(ext, texels, f"{model} material {index}")


def sampler_spec(doc: gltf_io.GltfDocument, texture: dict) -> tuple[SamplerSpec, bool]:
    """A glTF texture's sampler as a SamplerSpec, and whether it samples a mip chain (a *_MIPMAP_* minFilter, or
    none given: glTF leaves it to the renderer, we build mips)."""
    sampler = doc.json.get("samplers", [])[texture["sampler"]] if "sampler" in texture else {}
    mag = "nearest" if sampler.get("magFilter") == 9728 else "linear"
    min_filter, mip = MIN_FILTERS.get(sampler.get("minFilter", 9987), ("linear", "linear"))
    spec = SamplerSpec(mag_filter=mag, min_filter=min_filter, mipmap_filter=mip or "nearest",
                       address_mode_u=WRAP.get(sampler.get("wrapS", 10497), "repeat"),
                       address_mode_v=WRAP.get(sampler.get("wrapT", 10497), "repeat"),
                       lod_max_clamp=32.0 if mip else 0.0)
    return spec, mip is not None


def texture_file(doc: gltf_io.GltfDocument, texture: dict) -> Path:
    index = texture["source"]
    uri = doc.json["images"][index].get("uri")
    if uri is not None and not uri.startswith("data:"):
        return gltf_io._uri_file(doc.path, f"$.images[{index}].uri", uri)
    return embedded_image_path(doc.path.resolve(), index)


def _info(material: dict, keys: tuple[str, ...]) -> dict | None:
    info = material
    for key in keys:
        info = info.get(key) if isinstance(info, dict) else None
    return info if isinstance(info, dict) else None


def file_material(doc: gltf_io.GltfDocument, index: int, label: str, vertex_colors: bool,
                  ignored: list[str]) -> Material:
    """File material ``index`` as a scene Material (see the module docstring for the mapping)."""
    mat = doc.json["materials"][index]
    name = f"{label} material {index}" + (f" '{mat['name']}'" if mat.get("name") else "")
    mat, converted, _ = _spec_gloss(mat, name)
    pbr = mat.get("pbrMetallicRoughness", {})
    maps, samplers, mipmaps, slots = {}, [], [], []
    for feature, keys in ROLES.items():
        info = _info(mat, keys)
        if info is None:
            continue
        texture = doc.json["textures"][info["index"]]
        if "source" not in texture:
            ignored.append(f"{name}: {keys[-1]} has no image source (ignored)")
            continue
        slot, how = _uv_slot(doc, index, info)
        if slot is None:
            ignored.append(f"{name}: {keys[-1]} ignored: it samples a sixth distinct texture coordinate choice "
                           f"({how}); a mesh carries at most {gltf_geometry.MAX_UV_SLOTS} (vertex attributes)")
            continue
        maps[feature] = texture_file(doc, texture)
        spec, mips = sampler_spec(doc, texture)
        samplers.append((feature, spec))
        mipmaps.append((feature, mips))
        if slot:
            slots.append((feature, slot, how))
    for feature, kind in converted:
        if feature in maps:
            maps[feature] = gltf_specgloss.texture_path(doc.path.resolve(), index, kind)
    _note_ignored(mat, name, ignored)
    unlit = "KHR_materials_unlit" in mat.get("extensions", {})
    roughness = float(pbr.get("roughnessFactor", 1.0))
    normal = _info(mat, ("normalTexture",)) or {}
    occlusion = _info(mat, ("occlusionTexture",)) or {}
    strength = mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    emissive = (0.0, 0.0, 0.0) if unlit else tuple(float(c) * float(strength) for c in mat.get("emissiveFactor",
                                                                                               (0, 0, 0)))
    if unlit and ("emissiveTexture" in mat or any(mat.get("emissiveFactor", (0, 0, 0)))):
        ignored.append(f"{name}: emissive: ignored (KHR_materials_unlit draws the base colour only)")
    return Material(
        name=name, albedo_color=tuple(float(v) for v in pbr.get("baseColorFactor", (1.0, 1.0, 1.0, 1.0))),
        albedo_map=maps.get("albedo_map"), normal_map=maps.get("normal_map"), roughness_map=maps.get("roughness_map"),
        roughness=roughness, unlit=unlit, origin=name, vertex_colors=vertex_colors,
        double_sided=bool(mat.get("doubleSided", False)), alpha_mode=str(mat.get("alphaMode", "OPAQUE")).lower(),
        alpha_cutoff=float(mat.get("alphaCutoff", 0.5)), normal_strength=float(normal.get("scale", 1.0)),
        roughness_map_scale=roughness, texture_samplers=tuple(samplers), texture_mipmaps=tuple(mipmaps),
        part=index, written=tuple((f, str(p.name)) for f, p in maps.items()), emissive_color=emissive,
        emissive_map=maps.get("emissive_map") if not unlit else None,
        occlusion_map=maps.get("occlusion_map"), occlusion_strength=float(occlusion.get("strength", 1.0)),
        shading_model="blinn-phong" if unlit else "pbr", metallic=float(pbr.get("metallicFactor", 1.0)),
        uv_slots=tuple(slots), **_clearcoat(mat, maps, name, unlit, ignored),
    )


def _clearcoat(mat: dict, maps: dict, name: str, unlit: bool, ignored: list[str]) -> dict:
    """The Material fields of KHR_materials_clearcoat (its defaults: factor 0, roughness 0, normal scale 1)."""
    ext = mat.get("extensions", {}).get(CLEARCOAT)
    if not isinstance(ext, dict):
        return {}
    if unlit:  # the extension's exclusions: never with KHR_materials_unlit
        ignored.append(f"{name}: {CLEARCOAT}: ignored (KHR_materials_unlit draws the base colour only)")
        return {}
    normal = ext.get("clearcoatNormalTexture") if isinstance(ext.get("clearcoatNormalTexture"), dict) else {}
    return {"clearcoat": float(ext.get("clearcoatFactor", 0.0)),
            "clearcoat_roughness": float(ext.get("clearcoatRoughnessFactor", 0.0)),
            "clearcoat_map": maps.get("clearcoat_map"), "clearcoat_roughness_map": maps.get("clearcoat_roughness_map"),
            "clearcoat_normal_map": maps.get("clearcoat_normal_map"),
            "clearcoat_normal_scale": float(normal.get("scale", 1.0))}


def _spec_gloss(mat: dict, name: str) -> tuple[dict, tuple[tuple[str, str], ...], str]:
    """A KHR_materials_pbrSpecularGlossiness material as its metallic-roughness equivalent (gltf_specgloss.py):
    its factors converted; its textures, if any, replaced by the converted base-colour and metallic-roughness
    images (the features whose paths become converted ones are returned), and what --explain adds to the
    material's line."""
    ext = mat.get("extensions", {}).get(gltf_specgloss.EXTENSION)
    if not isinstance(ext, dict):
        return mat, (), ""
    said = f", converted from {gltf_specgloss.EXTENSION} to metallic-roughness"
    info = gltf_specgloss.source_info(ext, name)
    if info is not None:
        pbr = {"baseColorTexture": info, "metallicRoughnessTexture": info}
        return ({**mat, "pbrMetallicRoughness": pbr}, (("albedo_map", "base"), ("roughness_map", "metalrough")),
                said + " per texel (an approximation, exact only for dielectric (specular 0.04) or metal (black "
                "diffuse) texels)")
    diffuse, specular, gloss = gltf_specgloss.factors(ext)
    base, metallic, roughness = gltf_specgloss.convert(diffuse, specular, gloss)
    pbr = {"baseColorFactor": base.tolist(), "metallicFactor": float(metallic), "roughnessFactor": float(roughness)}
    how = " (exact)" if gltf_specgloss.exact(diffuse, specular, base, float(metallic)) else " (an approximation)"
    return {**mat, "pbrMetallicRoughness": pbr}, (), said + how


def _uv_slot(doc: gltf_io.GltfDocument, index: int, info: dict) -> tuple[int | None, str]:
    """(the coordinate slot a texture samples: gltf_geometry.uv_slots, None past the last; what it samples in
    words)."""
    texcoord, key = gltf_extensions.texture_uv_choice(info)
    how = f"TEXCOORD_{texcoord}" + (f" with KHR_texture_transform {dict(key)}" if key else "")
    return gltf_geometry.texture_slot(doc, index, info), how


def _note_ignored(mat: dict, name: str, ignored: list[str]) -> None:
    for ext in mat.get("extensions", {}):
        if ext not in SUPPORTED_MATERIAL_EXTENSIONS:
            ignored.append(f"{name}: {ext}: ignored")


def model_materials(path: Path, label: str) -> ModelMaterials:
    """The materials of the placed triangle primitives of glTF file ``path`` (``label`` names the model)."""
    doc = document(str(path))
    gltf_geometry.check_something_to_draw(doc)
    used: dict[tuple[str, int], bool] = {}  # (topology, file material index, -1: none) -> any has COLOR_0
    meshes = doc.json.get("meshes", [])
    for _, mesh_index, _ in gltf_geometry.placed_meshes(doc):
        for prim in meshes[mesh_index].get("primitives", []):
            topology = gltf_geometry.TOPOLOGIES.get(prim.get("mode", 4))
            if topology is not None:
                key = (topology != "triangle-list", prim.get("material", -1), topology)
                used[key] = used.get(key, False) or "COLOR_0" in prim.get("attributes", {})
    taken, ignored = [], list(gltf_geometry.geometry_notes(doc))
    materials = []
    for (_, k, topology), colours in sorted(used.items()):  # triangles first, then points and lines
        if k < 0:
            material = dataclasses.replace(DEFAULT_MATERIAL, name=f"{label} without material",
                                           origin=f"{label} primitives without a material (the default one)",
                                           vertex_colors=colours, part=-1)
        else:
            material = file_material(doc, k, label, colours, ignored)
        materials.append(material if topology == "triangle-list" else _points_or_lines(material, topology))
    for m in materials:
        converted = _spec_gloss(doc.json["materials"][m.part], m.name)[2] if m.part is not None and m.part >= 0 else ""
        taken.append(_taken_text(m) + converted)
    for ext in doc.json.get("extensionsUsed", []):
        if ext in USED_EXTENSIONS:
            taken.append(f"extensionsUsed {ext}: used")
        elif ext != "KHR_lights_punctual":  # lights: gltf_lights.py
            ignored.append(f"extensionsUsed {ext}: ignored")
    return ModelMaterials(tuple(materials), tuple(taken), tuple(dict.fromkeys(ignored)))


def _points_or_lines(material: Material, topology: str) -> Material:
    """The material of a points or lines primitive: drawn unlit (no surface to light), its own topology."""
    kind = "points" if topology == "point-list" else "lines"
    return dataclasses.replace(material, name=f"{material.name} ({kind})", origin=f"{material.origin} ({kind}, "
                               "unlit)", unlit=True, topology=topology, normal_map=None, roughness_map=None,
                               occlusion_map=None, emissive_map=None, emissive_color=(0.0, 0.0, 0.0),
                               clearcoat=0.0, clearcoat_map=None, clearcoat_roughness_map=None,
                               clearcoat_normal_map=None)


def _taken_text(m: Material) -> str:
    items = [f"baseColorFactor {tuple(round(c, 4) for c in m.albedo_color)}"]
    for feature, path in m.textures.items():
        spec = dict(m.texture_samplers).get(feature)
        how = ""
        if spec is not None:
            how = f" ({spec.min_filter}/{spec.mag_filter}, wrap {spec.address_mode_u}/{spec.address_mode_v})"
        slot = "".join(f" ({what}: coordinate slot {k})" for f, k, what in m.uv_slots if f == feature)
        items.append(f"{feature} {Path(path).name}{how}{slot}")
    if m.vertex_colors:
        items.append("COLOR_0 vertex colours")
    if m.double_sided:
        items.append("doubleSided")
    if m.alpha_mode != "opaque":
        items.append(f"alphaMode {m.alpha_mode.upper()}" + (f" cutoff {m.alpha_cutoff:g}" if m.alpha_mode == "mask"
                                                             else " (unsorted)"))
    if any(m.emissive_color):
        items.append(f"emissiveFactor {tuple(round(c, 4) for c in m.emissive_color)}")
    if m.occlusion_map:
        items.append(f"occlusion strength {m.occlusion_strength:g}")
    if m.clearcoat > 0 or m.clearcoat_map:
        items.append(f"{CLEARCOAT} clearcoatFactor {m.clearcoat:g}, clearcoatRoughnessFactor "
                     f"{m.clearcoat_roughness:g}" + (f", clearcoatNormalTexture scale {m.clearcoat_normal_scale:g}"
                                                     if m.clearcoat_normal_map else ""))
    if m.unlit:
        items.append("KHR_materials_unlit")
    elif m.part is not None and m.part >= 0:
        items.append(f"metallicFactor {m.metallic:g}, roughnessFactor {m.roughness:g}")
    return f"{m.origin}: " + ", ".join(items)
