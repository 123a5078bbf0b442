// Projective texture lookups for local reflection and refraction. WGSL twin
// of hydrolux_core::projective (seed 000 §3.1.3, §4.4; seed 002 eq. 1).

// Clip space → texture coordinates (v down); w ≤ 0 gives a point far outside.
fn clip_to_uv(clip: vec4<f32>) -> vec2<f32> {
    if (clip.w <= 1e-6) {
        return vec2<f32>(-10.0);
    }
    return vec2<f32>(0.5 + 0.5 * clip.x / clip.w, 0.5 - 0.5 * clip.y / clip.w);
}

// Where the reflected ray r from p meets the plane y = height (above the
// surface for a viewer in air, below it for one in the water), mirrored and
// projected with `view_proj` (which already contains the mirror).
fn reflection_uv(view_proj: mat4x4<f32>, p: vec3<f32>, r: vec3<f32>, height: f32, max_distance: f32) -> vec2<f32> {
    var t = max_distance;
    if (abs(r.y) > 1e-4) {
        t = clamp((height - p.y) / r.y, 0.0, max_distance);
    }
    return clip_to_uv(view_proj * vec4<f32>(p + r * t, 1.0));
}

// Where the refracted ray meets the plane y = −depth (seed 000 §4.4).
fn refraction_point_plane(p: vec3<f32>, t_dir: vec3<f32>, depth: f32, max_distance: f32) -> vec3<f32> {
    var t = max_distance;
    if (t_dir.y < -1e-4) {
        t = clamp((p.y + depth) / -t_dir.y, 0.0, max_distance);
    }
    return p + t_dir * t;
}
