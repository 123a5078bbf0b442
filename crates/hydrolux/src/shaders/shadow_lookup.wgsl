// Sun visibility from the shadow map (group 0, bindings 4 and 5), with a
// 3×3 percentage-closer filter. Needs `frame` and shadow_space().
#import frame, shadow_space

@group(0) @binding(4) var shadow_map: texture_depth_2d;
@group(0) @binding(5) var shadow_sampler: sampler_comparison;

fn sun_visibility(world: vec3<f32>, n: vec3<f32>) -> f32 {
    if (frame.shadow.enabled == 0u) {
        return 1.0;
    }
    let size = f32(frame.shadow.size);
    // Normal offset against acne: one texel-ish along the normal.
    let clip = frame.shadow.view_proj * vec4<f32>(shadow_space(world + n * 0.02), 1.0);
    let uv = vec2<f32>(0.5 + 0.5 * clip.x, 0.5 - 0.5 * clip.y);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 1.0;
    }
    // The map is fitted to the casters only: a receiver beyond its far plane
    // is behind every caster, so it compares as the far plane.
    let z = min(clip.z, 1.0);
    var sum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            sum += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(f32(i), f32(j)) / size, z - 0.0015);
        }
    }
    return sum / 9.0;
}

// One filtered tap, for the many samples of a volume (god rays).
fn sun_visibility_point(world: vec3<f32>) -> f32 {
    if (frame.shadow.enabled == 0u) {
        return 1.0;
    }
    let clip = frame.shadow.view_proj * vec4<f32>(shadow_space(world), 1.0);
    let uv = vec2<f32>(0.5 + 0.5 * clip.x, 0.5 - 0.5 * clip.y);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 1.0;
    }
    return textureSampleCompareLevel(shadow_map, shadow_sampler, uv, min(clip.z, 1.0) - 0.0015);
}
