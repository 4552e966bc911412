#version 450
// The scene's vertex shader on the raw path: the GLSL twin of shaders_wgsl/scene.wgsl's vs_main.
//
// Variants are made like the wgpu path's: one source, preprocessed per material variant. wgpu's
// template uses "#if feature" (wgpurender/core/shaders/shader_variants.py); here glslc's own preprocessor does it,
// with -D flags made from the plan's variant (wgpurender/raw_path/scene/variants.py):
//   LIGHTING, ALBEDO_MAP, NORMAL_MAP, ROUGHNESS_MAP, FLIP_V, SRGB_OUTPUT, UV (any texture),
//   VERTEX_COLOR, ALPHA_MASK, OPAQUE_ALPHA, DOUBLE_SIDED, EMISSIVE, EMISSIVE_MAP, OCCLUSION_MAP (a model
//   file's own materials), TANGENT (a normal map or a clearcoat normal map), UV1 .. UV4 (further texture coordinate slots, a model file's materials only; the
//   fragment shader's <MAP>_UV=v_uv<k> says which map samples which),
//   DIRECTIONAL_LIGHTS=n, POINT_LIGHTS=n, MAX_LIGHTS=n (array sizes of the camera block).
// The std140 offsets of the blocks are spelled out in wgpurender/raw_path/device/uniforms.py.

layout(std140, set = 0, binding = 0) uniform Camera {
    mat4 proj;   // @0
    mat4 view;   // @64
    vec4 eye;    // @128
} camera;

// Every instance's block in one storage buffer, read at gl_InstanceIndex (which includes the draw's
// firstInstance): core/plan/batches.py packs it, 128 bytes per instance, the same bytes as the wgpu path's.
struct Object {
    mat4 world;   // @0
    mat3 normal;  // @64: three vec4-padded columns (48 bytes)
    float mirror; // @112: sign of det(world)
};
layout(std430, set = 1, binding = 0) readonly buffer Objects {
    Object objects[];
};

layout(location = 0) in vec3 a_position;
#ifdef LIGHTING
layout(location = 1) in vec3 a_normal;
#endif
#ifdef UV
layout(location = 2) in vec2 a_uv;
#endif
#ifdef TANGENT
layout(location = 3) in vec4 a_tangent;
#endif
#ifdef VERTEX_COLOR
layout(location = 4) in vec4 a_color;
#endif
#ifdef UV1
layout(location = 5) in vec2 a_uv1;
#endif
#ifdef UV2
layout(location = 6) in vec2 a_uv2;
#endif
#ifdef UV3
layout(location = 7) in vec2 a_uv3;
#endif
#ifdef UV4
layout(location = 8) in vec2 a_uv4;
#endif

#ifdef LIGHTING
layout(location = 0) out vec3 v_world_position;
layout(location = 1) out vec3 v_normal;
#endif
#ifdef UV
layout(location = 2) out vec2 v_uv;
#endif
#ifdef TANGENT
layout(location = 3) out vec4 v_tangent;
#endif
#ifdef VERTEX_COLOR
layout(location = 4) out vec4 v_color;
#endif
#ifdef UV1
layout(location = 5) out vec2 v_uv1;
#endif
#ifdef UV2
layout(location = 6) out vec2 v_uv2;
#endif
#ifdef UV3
layout(location = 7) out vec2 v_uv3;
#endif
#ifdef UV4
layout(location = 8) out vec2 v_uv4;
#endif

void main() {
    Object object_data = objects[gl_InstanceIndex];
    // proj * view * world * p, left to right, as the WGSL (and the tutorial's GLSL) writes it.
    gl_Position = camera.proj * camera.view * object_data.world * vec4(a_position, 1.0);
    gl_PointSize = 1.0;  // a point-list pipeline (glTF POINTS) must write it; WebGPU's points are 1 pixel too
#ifdef LIGHTING
    v_world_position = (object_data.world * vec4(a_position, 1.0)).xyz;
    v_normal = object_data.normal * a_normal;  // cofactor matrix: right direction, any length
#endif
#ifdef UV
#ifdef FLIP_V
    v_uv = vec2(a_uv.x, 1.0 - a_uv.y);
#else
    v_uv = a_uv;
#endif
#endif
#ifdef TANGENT
    mat3 world3 = mat3(object_data.world[0].xyz, object_data.world[1].xyz, object_data.world[2].xyz);
    v_tangent = vec4(world3 * a_tangent.xyz, a_tangent.w * object_data.mirror);
#endif
#ifdef VERTEX_COLOR
    v_color = a_color;
#endif
#ifdef UV1
    v_uv1 = a_uv1;
#endif
#ifdef UV2
    v_uv2 = a_uv2;
#endif
#ifdef UV3
    v_uv3 = a_uv3;
#endif
#ifdef UV4
    v_uv4 = a_uv4;
#endif
}
