// What traced rays meet besides the water (passes/raytrace): the ground's
// heightfield and the traced objects' primitives and meshes. The importing
// shader declares `traced: TracedParams`, `hf_heights`, `hf_bounds`,
// `traced_objects: array<TracedObject>` (traced.wgsl) and
// `traced_meshes: array<vec4<f32>>` (the meshes' trees, passes/raytrace
// `TracedMeshes`).
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

// Deepest a mesh's tree goes, plus one: its walk's stack (raytrace::bvh::MAX_DEPTH + 1).
const BVH_STACK: u32 = 33u;

// Where the ray o + t·d (inv = 1/d) is inside the box lo..hi, within
// (t0, t1): (near, far), near > far where it misses. Twin: bvh::slab.
fn bvh_slab(lo: vec3<f32>, hi: vec3<f32>, o: vec3<f32>, inv: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let lo_t = min(a, b);
    let hi_t = max(a, b);
    return vec2<f32>(max(max(max(lo_t.x, lo_t.y), lo_t.z), t0), min(min(min(hi_t.x, hi_t.y), hi_t.z), t1));
}

// Möller–Trumbore: where o + t·d meets the triangle p0 p1 p2 from either
// side, (t, e1 × e2); t = NO_ROOT where it misses. Twin: bvh::triangle.
fn bvh_triangle(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, o: vec3<f32>, d: vec3<f32>) -> vec4<f32> {
    let miss = vec4<f32>(NO_ROOT, 0.0, 1.0, 0.0);
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let p = cross(d, e2);
    let det = dot(e1, p);
    if (abs(det) < 1e-12) {
        return miss;
    }
    let inv = 1.0 / det;
    let s = o - p0;
    let u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) {
        return miss;
    }
    let q = cross(s, e1);
    let v = dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) {
        return miss;
    }
    return vec4<f32>(dot(e2, q) * inv, cross(e1, e2));
}

// The first hit of o + t·d (object space) on object `obj`'s mesh with t in
// (t_min, t_max): (t, object-space normal facing the ray); t = NO_ROOT if
// none. Walks its tree nearer child first. Twin: MeshBvh::intersect.
fn trace_mesh(obj: TracedObject, o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32) -> vec4<f32> {
    var stack: array<u32, BVH_STACK>;
    var top = 1u;
    stack[0] = 0u;
    var best = vec4<f32>(NO_ROOT, 0.0, 1.0, 0.0);
    var reach = t_max;
    let inv = 1.0 / d;
    while (top > 0u) {
        top -= 1u;
        let i = stack[top];
        let a = traced_meshes[obj.mesh_nodes + 2u * i];
        let b = traced_meshes[obj.mesh_nodes + 2u * i + 1u];
        let span = bvh_slab(a.xyz, b.xyz, o, inv, t_min, reach);
        if (span.x > span.y) {
            continue;
        }
        let link = bitcast<u32>(a.w);
        let count = bitcast<u32>(b.w);
        if (count > 0u) {
            for (var k = link; k < link + count; k++) {
                let c = obj.mesh_triangles + 3u * k;
                let h = bvh_triangle(traced_meshes[c].xyz, traced_meshes[c + 1u].xyz, traced_meshes[c + 2u].xyz, o, d);
                if (h.x > t_min && h.x < reach) {
                    reach = h.x;
                    best = h;
                }
            }
        } else if (top + 2u <= BVH_STACK) {
            // The nearer child (by its box's centre along d) walked first.
            let first = i + 1u;
            let c_first = traced_meshes[obj.mesh_nodes + 2u * first].xyz + traced_meshes[obj.mesh_nodes + 2u * first + 1u].xyz;
            let c_link = traced_meshes[obj.mesh_nodes + 2u * link].xyz + traced_meshes[obj.mesh_nodes + 2u * link + 1u].xyz;
            let first_nearer = dot(0.5 * c_first - o, d) <= dot(0.5 * c_link - o, d);
            stack[top] = select(first, link, first_nearer);
            stack[top + 1u] = select(link, first, first_nearer);
            top += 2u;
        }
    }
    if (best.x < NO_ROOT && dot(best.yzw, d) > 0.0) {
        best = vec4<f32>(best.x, -best.yzw);
    }
    return best;
}

// The first entry of o + t·d (object space) into traced object i's shape
// within t_max: (t, object-space normal), t = NO_ROOT if none.
fn hit_object(i: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> vec4<f32> {
    let obj = traced_objects[i];
    if (obj.shape == PRIMITIVE_MESH) {
        return trace_mesh(obj, o, d, 1e-4, t_max);
    }
    return hit_primitive(obj.shape, o, d);
}

// The first traced object along o + t·d within t_max (world space).
fn trace_objects(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> ObjectHit {
    var best = ObjectHit(NO_ROOT, 0u, vec3<f32>(0.0, 1.0, 0.0));
    let count = traced.object_count;
    for (var i = 0u; i < count; i++) {
        let inv = traced_objects[i].inverse_model;
        let h = hit_object(i, (inv * vec4<f32>(o, 1.0)).xyz, (inv * vec4<f32>(d, 0.0)).xyz, min(best.t, t_max));
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
        let oo = (inv * vec4<f32>(o, 1.0)).xyz;
        let dd = (inv * vec4<f32>(d, 0.0)).xyz;
        if (traced_objects[i].shape == PRIMITIVE_MESH) {
            // A mesh has no inside to start in: any surface on the way.
            if (trace_mesh(traced_objects[i], oo, dd, 1e-4, t_max).x < t_max) {
                return true;
            }
            continue;
        }
        let t = traced_interval(traced_objects[i].shape, oo, dd);
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
