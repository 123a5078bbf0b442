// Temporal anti-aliasing's resolve (hydrolux_core::antialias): the new,
// jittered frame blended into the history of earlier frames, read where
// each pixel's surface was last frame (reprojected by the nearest depth of
// its 3×3 neighbourhood, so edges move with what is in front) and clipped
// to the new frame's neighbourhood. The HDR image's alpha is each pixel's
// trust in its history: 1 (cleared, solid geometry), 0 where the water's
// surface was drawn, lowered by particles drawn over (their coverage).
#import fullscreen, temporal_resolve

struct AntialiasParams {
    reprojection: mat4x4<f32>,
    has_history: u32,
    min_share: f32,
    time_still: u32,
    settled: u32,
}

// A storage buffer, not a uniform: lavapipe inlines a small uniform buffer
// into the shader that branches on it and keeps a compiled copy for every
// new content (1.5 MB a frame here; tests/memory.rs).
@group(0) @binding(0) var<storage, read> params: AntialiasParams;
@group(0) @binding(1) var current: texture_2d<f32>;
@group(0) @binding(2) var history: texture_2d<f32>;
@group(0) @binding(3) var depth_tex: texture_2d<f32>;
@group(0) @binding(4) var history_sampler: sampler;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(current));
    let p = vec2<i32>(pos.xy);
    let centre = textureLoad(current, p, 0);
    var n: array<vec3<f32>, 9>;
    var depth = 0.0;
    for (var k = 0; k < 9; k++) {
        let q = clamp(p + vec2<i32>(k % 3 - 1, k / 3 - 1), vec2<i32>(0), size - 1);
        n[k] = textureLoad(current, q, 0).rgb;
        // Reversed Z: the nearest is the largest.
        depth = max(depth, textureLoad(depth_tex, q, 0).r);
    }
    var has = params.has_history != 0u;
    var last = vec3<f32>(0.0);
    if (has) {
        let uv = pos.xy / vec2<f32>(size);
        let prev = taa_reproject(params.reprojection, uv, depth);
        has = prev.z > 0.5;
        last = textureSampleLevel(history, history_sampler, prev.xy, 0.0).rgb;
    }
    // While time stands still only the camera moves: every pixel is trusted.
    let trust = select(clamp(centre.a, 0.0, 1.0), 1.0, params.time_still != 0u);
    let out = taa_resolve(n, last, has, trust, params.min_share, params.settled != 0u);
    // A non-finite history (never expected) must not stick.
    if (any(out != out) || any(abs(out) > vec3<f32>(6.0e4))) {
        return centre;
    }
    return vec4<f32>(out, 1.0);
}
