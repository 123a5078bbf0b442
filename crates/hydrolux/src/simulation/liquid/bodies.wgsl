// The moving bodies in the volumetric liquid (issue #29, two-way coupling;
// seed 003 §2.4): where rapier has them this clock step, written by the
// host before the step. Twin: hydrolux_core::fluid::solids (LiquidBody).
#import ray_primitive

const MAX_LIQUID_BODIES: u32 = 8u;

struct LiquidBody {
    // Its centre (m) and shape (PRIMITIVE_*).
    position: vec3<f32>,
    shape: u32,
    // Its rotation, a quaternion (x, y, z, w).
    rotation: vec4<f32>,
    // m/s, of its centre; its bounding radius (m).
    velocity: vec3<f32>,
    reach: f32,
    // rad/s
    angular_velocity: vec3<f32>,
    _pad0: f32,
    // The shape's sizes (coupling::Shape::gpu): a sphere's radius, a box's
    // half-sizes, a cylinder's radius and half-height.
    size: vec4<f32>,
}

struct LiquidBodies {
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    bodies: array<LiquidBody, MAX_LIQUID_BODIES>,
}

fn body_local(b: LiquidBody, x: vec3<f32>) -> vec3<f32> {
    return quat_rotate(vec4<f32>(-b.rotation.xyz, b.rotation.w), x - b.position);
}

// Signed distance (m) from body b's surface to world point x.
fn body_distance(b: LiquidBody, x: vec3<f32>) -> f32 {
    return shape_distance(b.shape, b.size.xyz, body_local(b, x));
}

// Its outward normal nearest x: the distance's gradient by central
// differences a thousandth of its size apart (Shape::outward_normal).
fn body_normal(b: LiquidBody, x: vec3<f32>) -> vec3<f32> {
    let p = body_local(b, x);
    let e = 1e-3 * b.reach;
    let s = b.size.xyz;
    let g = vec3<f32>(
        shape_distance(b.shape, s, p + vec3<f32>(e, 0.0, 0.0)) - shape_distance(b.shape, s, p - vec3<f32>(e, 0.0, 0.0)),
        shape_distance(b.shape, s, p + vec3<f32>(0.0, e, 0.0)) - shape_distance(b.shape, s, p - vec3<f32>(0.0, e, 0.0)),
        shape_distance(b.shape, s, p + vec3<f32>(0.0, 0.0, e)) - shape_distance(b.shape, s, p - vec3<f32>(0.0, 0.0, e)),
    );
    let len = length(g);
    if (len == 0.0) {
        return vec3<f32>(0.0);
    }
    return quat_rotate(b.rotation, g / len);
}

// Body b's velocity at world point x: v + ω × r.
fn body_velocity_at(b: LiquidBody, x: vec3<f32>) -> vec3<f32> {
    return b.velocity + cross(b.angular_velocity, x - b.position);
}
