// Filmic tone map of the pre-exposed HDR image into the output target.
// modes.z: 0 ACES, 1 clamp. If the target is not an sRGB format the
// transfer curve is applied here (OUTPUT_SRGB_CURVE prepended by the pass).

@group(1) @binding(0) var hdr: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(pos.xy), 0).rgb;
    var mapped = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    if (frame.modes.z == 0u) {
        mapped = aces_filmic(c);
    }
    if (OUTPUT_SRGB_CURVE) {
        mapped = linear_to_srgb(mapped);
    }
    return vec4<f32>(mapped, 1.0);
}
