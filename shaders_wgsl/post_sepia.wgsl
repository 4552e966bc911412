// Sepia: the classic sepia tone matrix, mixed in by `amount`, see wgpurender/core/course/effects.py (the spec).
// Needs post_common.wgsl (prepended). No clamp: bright inputs may exceed 1 in an
// HDR chain; an 8-bit target clamps on write.

// SepiaParams is generated from the effect's spec (wgpurender/wgpu_path/post/shaders.py).

fn sepia_pixel(texel: vec4f, pos: vec2f, size: vec2f, params: SepiaParams) -> vec4f {
    let c = texel.rgb;
    let sepia = vec3f(dot(vec3f(0.393, 0.769, 0.189), c),
                      dot(vec3f(0.349, 0.686, 0.168), c),
                      dot(vec3f(0.272, 0.534, 0.131), c));
    return vec4f(mix(c, sepia, params.amount), texel.a);
}
