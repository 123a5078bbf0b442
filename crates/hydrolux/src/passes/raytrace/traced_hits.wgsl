// What traced rays meet besides the water (passes/raytrace): the ground's
// heightfield and the traced objects' primitives. The importing shader
// declares `traced: TracedParams`, `hf_heights`, `hf_bounds` and
// `traced_objects: array<TracedObject>` (traced.wgsl).
#import heightfield_trace, traced, ray_primitive

// Where a traced ray first meets the ground (t; NO_ROOT: nowhere).
fn trace_ground(o: vec3<f32>, d: vec3<f32>) -> f32 {
    if (traced.has_ground == 0u) {
        return NO_ROOT;
    }
    return trace_heightfield(traced.ground, o, d, traced.reach);
}

// The ground's normal at world (x, z), from its heightfield.
fn ground_normal(x: f32, z: f32) -> vec3<f32> {
    let e = traced.ground.spacing;
    let hx = hf_height(traced.ground, x + e, z) - hf_height(traced.ground, x - e, z);
    let hz = hf_height(traced.ground, x, z + e) - hf_height(traced.ground, x, z - e);
    return normalize(vec3<f32>(-hx, 2.0 * e, -hz));
}

// A traced object's first hit: t (NO_ROOT: none), which, and its normal.
struct ObjectHit {
    t: f32,
    index: u32,
    normal: vec3<f32>,
}

// A traced plane (PRIMITIVE_PLANE) is the unit square |x|, |z| ≤ ½ at
// y = 0, facing +y (drawn one-sided, as the geometry pass culls its back).

// Where the ray o + t·d (object space) is inside a traced shape: (t_in,
// t_out) as ray_primitive gives them; a plane is the one point it crosses.
fn traced_interval(shape: u32, o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    if (shape != PRIMITIVE_PLANE) {
        return ray_primitive(shape, vec3<f32>(0.5), o, d);
    }
    if (abs(d.y) < 1e-8) {
        return vec2<f32>(1.0, -1.0);
    }
    let t = -o.y / d.y;
    let p = o.xz + d.xz * t;
    if (any(abs(p) > vec2<f32>(0.5))) {
        return vec2<f32>(1.0, -1.0);
    }
    return vec2<f32>(t, t);
}

// The first entry of the ray o + t·d (object space) into a unit primitive
// (ray_primitive's codes, half-size ½) or a plane: (t, object-space
// normal); t = NO_ROOT if it misses, starts inside or meets a plane's back.
fn hit_primitive(shape: u32, o: vec3<f32>, d: vec3<f32>) -> vec4<f32> {
    let size = vec3<f32>(0.5);
    let t = traced_interval(shape, o, d);
    if (shape == PRIMITIVE_PLANE) {
        if (t.x > t.y || t.x <= 1e-4 || o.y <= 0.0) {
            return vec4<f32>(NO_ROOT, 0.0, 0.0, 0.0);
        }
        return vec4<f32>(t.x, 0.0, 1.0, 0.0);
    }
    if (t.x > t.y || t.x <= 1e-4) {
        return vec4<f32>(NO_ROOT, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(t.x, primitive_normal(shape, size, o + d * t.x));
}

// The first traced object along o + t·d within t_max (world space).
fn trace_objects(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> ObjectHit {
    var best = ObjectHit(NO_ROOT, 0u, vec3<f32>(0.0, 1.0, 0.0));
    let count = traced.object_count;
    for (var i = 0u; i < count; i++) {
        let inv = traced_objects[i].inverse_model;
        let h = hit_primitive(traced_objects[i].shape, (inv * vec4<f32>(o, 1.0)).xyz, (inv * vec4<f32>(d, 0.0)).xyz);
        if (h.x < best.t && h.x <= t_max) {
            // World normal: the inverse transpose, i.e. n·M⁻¹.
            best = ObjectHit(h.x, i, normalize((vec4<f32>(h.yzw, 0.0) * inv).xyz));
        }
    }
    return best;
}

// Whether a traced object lies on the ray o + t·d for t in (0, t_max), or
// the ray starts inside one.
fn objects_block(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> bool {
    let count = traced.object_count;
    for (var i = 0u; i < count; i++) {
        let inv = traced_objects[i].inverse_model;
        let t = traced_interval(traced_objects[i].shape, (inv * vec4<f32>(o, 1.0)).xyz, (inv * vec4<f32>(d, 0.0)).xyz);
        if (t.x <= t.y && t.y > 0.0 && t.x < t_max) {
            return true;
        }
    }
    return false;
}

// The traced photons' light on the ground at q (passes/raytrace/caustics.wgsl:
// per horizontal area, relative to flat water over flat ground; bilinear
// between cell centres), or −1 off its window or when it is off. Needs
// `ground_light: array<f32>`.
fn traced_ground_light(q: vec3<f32>) -> f32 {
    let m = i32(traced.caustic_cells);
    let f = (q.xz - traced.caustic_corner) / traced.caustic_cell;
    if (m == 0 || any(f < vec2<f32>(0.0)) || any(f >= vec2<f32>(f32(m)))) {
        return -1.0;
    }
    let g = f - 0.5;
    let base = floor(g);
    let a = g - base;
    let i = i32(base.x);
    let j = i32(base.y);
    let i0 = clamp(i, 0, m - 1);
    let i1 = clamp(i + 1, 0, m - 1);
    let j0 = clamp(j, 0, m - 1);
    let j1 = clamp(j + 1, 0, m - 1);
    let v00 = ground_light[j0 * m + i0];
    let v10 = ground_light[j0 * m + i1];
    let v01 = ground_light[j1 * m + i0];
    let v11 = ground_light[j1 * m + i1];
    return mix(mix(v00, v10, a.x), mix(v01, v11, a.x), a.y);
}
