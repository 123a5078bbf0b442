// Eq. 25–26 of seed 003 §3.2 with the depth known: the world point at
// screen position (x, y) pixels (y up, as clip space's), depth w (the clip
// w, m), by Q = P⁻¹; the clip z is solved from the unit homogeneous
// coordinate. CPU twin: `hydrolux_core::fluid::screen_mesh::ScreenView::unproject_by`.

fn unproject_depth(q: mat4x4<f32>, screen: vec2<f32>, s: vec3<f32>) -> vec3<f32> {
    let cx = (-1.0 + 2.0 * s.x / screen.x) * s.z;
    let cy = (-1.0 + 2.0 * s.y / screen.y) * s.z;
    let cz = (1.0 - q[0][3] * cx - q[1][3] * cy - q[3][3] * s.z) / q[2][3];
    return (q * vec4<f32>(cx, cy, cz, s.z)).xyz;
}
