// One of the volumetric liquid's marker particles (liquid.wgsl; Rust:
// `LiquidParticle`), as the step writes them and the draws read them.
struct LiquidParticle {
    position: vec3<f32>,
    // 1 while the slot holds liquid (a nozzle's slots wait empty; a drain
    // empties them).
    alive: u32,
    velocity: vec3<f32>,
    _pad1: f32,
}

// Corner `v` (0–5, two triangles) of a quad facing `eye` that covers the
// whole silhouette of the sphere (`centre`, `r`): moved towards the eye by
// r and grown, as a sphere seen from close by is wider than r. The draws
// that find the sphere per pixel (points, the screen-space splats) use it.
fn sphere_quad_corner(centre: vec3<f32>, r: f32, eye: vec3<f32>, v: u32) -> vec3<f32> {
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let to_eye = eye - centre;
    let dist = max(length(to_eye), 1e-4);
    let forward = -to_eye / dist;
    let right = normalize(cross(forward, vec3<f32>(0.0, 1.0, 0.0)) + vec3<f32>(1e-6, 0.0, 0.0));
    let up = cross(right, forward);
    let grow = dist / sqrt(max(dist * dist - r * r, 1e-8));
    let c = corners[v] * r * grow;
    return centre + right * c.x + up * c.y - forward * r;
}
