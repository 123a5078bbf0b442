// God rays, the buffer's way in and out. `fs_reduce`: the scene's depth at
// the buffer's resolution, keeping the nearest of each block, so that
// shafts stop at the first surface in it. `fs_composite`: the buffer
// upsampled to the output without halos — of the four nearest buffer
// texels, those whose depth matches the pixel's are blended (bilinearly);
// where none does (an edge), the one nearest in depth is taken — and added
// to the image where the pixel's medium is the one the buffer is for.
#import godrays_common, fullscreen

@group(1) @binding(0) var full_depth: texture_2d<f32>;
@group(1) @binding(4) var<uniform> params: GodRayParams;
// The buffer's depth, as the bits of an f32.
@group(1) @binding(1) var buffer_depth: texture_2d<u32>;
@group(1) @binding(2) var shafts: texture_2d<f32>;
@group(1) @binding(3) var medium_tex: texture_2d<u32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

@fragment
fn fs_reduce(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<u32> {
    let full = vec2<f32>(textureDimensions(full_depth));
    let small = vec2<f32>(params.buffer_size);
    let lo = vec2<i32>(floor(floor(pos.xy) * full / small));
    let hi = min(vec2<i32>(ceil((floor(pos.xy) + 1.0) * full / small)) - 1, vec2<i32>(full) - 1);
    var nearest = 0.0;
    for (var y = lo.y; y <= min(hi.y, lo.y + 7); y++) {
        for (var x = lo.x; x <= min(hi.x, lo.x + 7); x++) {
            nearest = max(nearest, textureLoad(full_depth, vec2<i32>(x, y), 0).r);
        }
    }
    return vec4<u32>(bitcast<u32>(nearest), 0u, 0u, 0u);
}

fn pixel_distance(ndc: vec2<f32>, z: f32) -> f32 {
    return min(scene_distance(ndc, z), 1e6);
}

@fragment
fn fs_composite(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    if (textureLoad(medium_tex, px, 0).r != params.medium) {
        discard;
    }
    let full = vec2<f32>(textureDimensions(full_depth));
    let small = vec2<f32>(textureDimensions(buffer_depth));
    let dist = pixel_distance(texel_ndc(floor(pos.xy), full), textureLoad(full_depth, px, 0).r);
    let q = pos.xy * small / full - 0.5;
    let base = floor(q);
    let f = q - base;
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    var nearest = vec3<f32>(0.0);
    var nearest_gap = 1e30;
    for (var k = 0; k < 4; k++) {
        let o = vec2<f32>(f32(k & 1), f32(k >> 1));
        let t = clamp(base + o, vec2<f32>(0.0), small - 1.0);
        let ti = vec2<i32>(t);
        let value = textureLoad(shafts, ti, 0).rgb;
        let gap = abs(pixel_distance(texel_ndc(t, small), bitcast<f32>(textureLoad(buffer_depth, ti, 0).r)) - dist) / max(dist, 1e-3);
        let bilinear = mix(1.0 - f.x, f.x, o.x) * mix(1.0 - f.y, f.y, o.y);
        if (gap < 0.05) {
            sum += value * bilinear;
            weight += bilinear;
        }
        if (gap < nearest_gap) {
            nearest_gap = gap;
            nearest = value;
        }
    }
    let shafts_here = select(nearest, sum / max(weight, 1e-6), weight > 1e-3);
    // Added light only: the HDR alpha (the anti-aliasing's trust) stays.
    return vec4<f32>(shafts_here, 0.0);
}
