// Course step 5: one mip level from the previous one (the vkCmdBlitImage of the course).
//
// `src` is a one-level view of level i-1; the render target is a one-level view of
// level i. For an rgba8unorm-srgb texture textureLoad returns linear values (the
// texture unit decodes sRGB on every read) and the -srgb render target encodes
// again, so the average below is taken in linear light.
//
// Exact area-weighted box filter, in integers: along one axis, source texel i covers
// [i*dst, (i+1)*dst) and destination texel x covers [x*src, (x+1)*src) in units of
// 1/(src*dst) of the axis. A destination texel overlaps at most 3 source texels
// (src/dst <= 3 when dst = max(1, src >> 1)); each weight is overlap / src. For even
// sizes this is the plain 2x2 average. wgpurender/wgpu_path/device/textures.py documents the rule and
// tests/test_textures.py checks it against numpy.

@group(0) @binding(0) var src: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4f {
    // One triangle that covers the viewport: (-1,-1), (3,-1), (-1,3).
    let p = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4f(p * 2.0 - 1.0, 0.0, 1.0);
}

struct AxisTaps {
    first: u32,
    weights: vec3f,
};

fn axis_taps(x: u32, src_size: u32, dst_size: u32) -> AxisTaps {
    let lo = x * src_size;
    let hi = lo + src_size;
    var taps: AxisTaps;
    taps.first = lo / dst_size;
    for (var k = 0u; k < 3u; k++) {
        let i = taps.first + k;
        let a = max(i * dst_size, lo);
        let b = min((i + 1u) * dst_size, hi);
        taps.weights[k] = select(0.0, f32(b - a), b > a) / f32(src_size);
    }
    return taps;
}

@fragment
fn fs_main(@builtin(position) frag: vec4f) -> @location(0) vec4f {
    let src_size = textureDimensions(src);
    let dst_size = max(src_size >> vec2u(1u), vec2u(1u));
    let dst = vec2u(frag.xy);
    let tx = axis_taps(dst.x, src_size.x, dst_size.x);
    let ty = axis_taps(dst.y, src_size.y, dst_size.y);
    var sum = vec4f(0.0);
    for (var j = 0u; j < 3u; j++) {
        for (var i = 0u; i < 3u; i++) {
            let w = tx.weights[i] * ty.weights[j];
            let coord = min(vec2u(tx.first + i, ty.first + j), src_size - vec2u(1u));
            sum += w * textureLoad(src, coord, 0);
        }
    }
    return sum;
}
