// Looking things up on the main view's screen from a shading pass: world
// points to screen uv and back, the opaque scene's depth as a distance, and
// the sky where a lookup leaves the screen. Used by the refractive objects
// (passes/water_object/shade.wgsl) and the screen-space liquid
// (simulation/liquid/screen_space.wgsl).
#import frame, sky_bindings, lighting, screen_project

// World → (uv, inside the screen).
fn screen_uv(p: vec3<f32>) -> vec3<f32> {
    let clip = frame.view.view_proj * vec4<f32>(p, 1.0);
    let ndc = clip.xy / clip.w;
    let inside = (clip.w > 0.0) & all(abs(ndc) <= vec2<f32>(1.0));
    return vec3<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y, select(0.0, 1.0, inside));
}

// The texel under screen uv, clamped to the texture — in float first, so
// that a degenerate projection (NaN) cannot become a wild integer index.
fn texel_at(uv: vec2<f32>, size: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(clamp(uv * size, vec2<f32>(0.0), size - 1.0));
}

// The sky cube towards `dir`, or the grey ground below the horizon; a
// degenerate direction (zero, NaN) reads straight up instead (Mesa's
// lavapipe crashes on a NaN cube lookup).
fn sky_towards(dir: vec3<f32>) -> vec3<f32> {
    let d = clamp(dir, vec3<f32>(-1.0), vec3<f32>(1.0));
    let ok = dot(d, d) > 1e-8;
    let sky = textureSampleLevel(sky_cube, sky_sampler, select(vec3<f32>(0.0, 1.0, 0.0), d, ok), 0.0).rgb * exposure();
    return select(sky, below_horizon_radiance(), ok & (d.y < 0.0));
}

// The world point at framebuffer position `pixel` (pixels, y down) and
// depth w (the clip w, m).
fn pixel_point(pixel: vec2<f32>, w: f32) -> vec3<f32> {
    let size = frame.view.size;
    return unproject_depth(frame.view.inv_view_proj, size, vec3<f32>(pixel.x, size.y - pixel.y, w));
}

// The clip w of the depth buffer's value `z` at framebuffer position
// `pixel`: how far along the view axis the opaque scene lies there
// (infinite where the buffer is empty, 0 with reversed Z). CPU twin:
// `fluid::screen_space::scene_w`.
fn scene_w(pixel: vec2<f32>, z: f32) -> f32 {
    let ndc = vec2<f32>(2.0 * pixel.x * frame.view.inv_size.x - 1.0, 1.0 - 2.0 * pixel.y * frame.view.inv_size.y);
    let h = frame.view.inv_view_proj * vec4<f32>(ndc, z, 1.0);
    return select(3.0e38, 1.0 / h.w, h.w > 0.0);
}
