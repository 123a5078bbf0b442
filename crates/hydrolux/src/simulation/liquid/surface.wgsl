// The liquid's surface by marching cubes on the GPU (seed 003 §3.1; the
// CPU twin is hydrolux_core::fluid::surface, step for step), with no read
// back: clear → splat (each particle's kernel added to the nodes in fixed
// point, so the sum does not depend on the particles' order) → smooth
// (`fluid.surface_smoothing` rounds of a binomial filter per axis) → vertices
// (one per grid edge the level crosses, eq. 18, its normal from the field's
// central differences, eq. 19–20) → triangles (each cell's case from the
// derived table, indices into the edges' shared vertices) → finish (the
// indexed indirect draw's count). Slots are taken with atomic counters, so
// the vertices' order varies run to run but never the mesh.
#import liquid_particle, liquid_mesh

struct SurfaceParams {
    // The nodes' low corner (m), their spacing (m).
    origin: vec3<f32>,
    h: f32,
    nodes: vec3<u32>,
    node_count: u32,
    // The kernel's reach (m), its weight (the density of a full liquid is
    // 1), the level that is the surface.
    reach: f32,
    scale: f32,
    iso: f32,
    fixed_point: f32,
    particle_count: u32,
    vertex_capacity: u32,
    index_capacity: u32,
    // Threads per row of a two-dimensional dispatch.
    row: u32,
}

@group(0) @binding(0) var<uniform> params: SurfaceParams;
@group(0) @binding(1) var<storage, read> particles: array<LiquidParticle>;
@group(0) @binding(2) var<storage, read_write> field: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> edge_vertex: array<u32>;
// Eight floats a vertex: position, normal, uv (the meshes' layout).
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(5) var<storage, read_write> indices: array<u32>;
@group(0) @binding(6) var<storage, read_write> counters: MeshCounters;
// Per case: its triangle count, then three cube edges per triangle.
@group(0) @binding(7) var<storage, read> cases: array<u32>;
// A smoothing round's output (copied back over the field after each axis).
@group(0) @binding(8) var<storage, read_write> smoothed: array<u32>;

const WG: u32 = 64u;
const MAX_CASE_TRIANGLES: u32 = 5u;
const CASE_STRIDE: u32 = 16u;

fn thread(id: vec3<u32>) -> u32 {
    return id.x + id.y * params.row;
}

fn node_index(p: vec3<u32>) -> u32 {
    return p.x + params.nodes.x * (p.y + params.nodes.y * p.z);
}

fn node_of(i: u32) -> vec3<u32> {
    let nx = params.nodes.x;
    let ny = params.nodes.y;
    return vec3<u32>(i % nx, (i / nx) % ny, i / (nx * ny));
}

fn node_position(p: vec3<u32>) -> vec3<f32> {
    return params.origin + params.h * vec3<f32>(p);
}

fn value(p: vec3<u32>) -> f32 {
    return f32(atomicLoad(&field[node_index(p)])) / params.fixed_point;
}

@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i == 0u) {
        reset_mesh_counters();
    }
    if (i < params.node_count) {
        atomicStore(&field[i], 0u);
    }
}

@compute @workgroup_size(64)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i >= params.particle_count || particles[i].alive == 0u) {
        return;
    }
    let p = particles[i].position;
    let r = params.reach;
    let n = vec3<f32>(params.nodes);
    let lo = vec3<u32>(clamp(ceil((p - r - params.origin) / params.h), vec3<f32>(0.0), n));
    let hi = vec3<u32>(clamp(floor((p + r - params.origin) / params.h) + 1.0, vec3<f32>(0.0), n));
    for (var z = lo.z; z < hi.z; z++) {
        for (var y = lo.y; y < hi.y; y++) {
            for (var x = lo.x; x < hi.x; x++) {
                let d = node_position(vec3<u32>(x, y, z)) - p;
                let q2 = dot(d, d) / (r * r);
                if (q2 < 1.0) {
                    let w = (1.0 - q2) * (1.0 - q2) * (1.0 - q2);
                    let units = u32(w * params.scale * params.fixed_point + 0.5);
                    atomicAdd(&field[node_index(vec3<u32>(x, y, z))], units);
                }
            }
        }
    }
}

// The binomial filter (¼, ½, ¼) along `axis` in fixed point, zero beyond
// the grid (the twin's `smooth` and `filtered`).
fn smooth_along(i: u32, axis: u32) {
    if (i >= params.node_count) {
        return;
    }
    let p = node_of(i);
    var lo = 0u;
    var hi = 0u;
    if (p[axis] > 0u) {
        var q = p;
        q[axis] -= 1u;
        lo = atomicLoad(&field[node_index(q)]);
    }
    if (p[axis] + 1u < params.nodes[axis]) {
        var q = p;
        q[axis] += 1u;
        hi = atomicLoad(&field[node_index(q)]);
    }
    let mid = atomicLoad(&field[i]);
    // (lo + 2·mid + hi + 2) / 4 without overflowing 32 bits.
    let sum_low = (lo & 3u) + 2u * (mid & 3u) + (hi & 3u) + 2u;
    smoothed[i] = (lo >> 2u) + 2u * (mid >> 2u) + (hi >> 2u) + sum_low / 4u;
}

@compute @workgroup_size(64)
fn smooth_x(@builtin(global_invocation_id) id: vec3<u32>) {
    smooth_along(thread(id), 0u);
}

@compute @workgroup_size(64)
fn smooth_y(@builtin(global_invocation_id) id: vec3<u32>) {
    smooth_along(thread(id), 1u);
}

@compute @workgroup_size(64)
fn smooth_z(@builtin(global_invocation_id) id: vec3<u32>) {
    smooth_along(thread(id), 2u);
}

// ∇ of the field at a node, by central differences (one-sided at the
// grid's border).
fn gradient(p: vec3<u32>) -> vec3<f32> {
    var g = vec3<f32>(0.0);
    for (var a = 0u; a < 3u; a++) {
        var lo = p;
        var hi = p;
        lo[a] = select(p[a] - 1u, p[a], p[a] == 0u);
        hi[a] = min(p[a] + 1u, params.nodes[a] - 1u);
        g[a] = (value(hi) - value(lo)) / (f32(hi[a] - lo[a]) * params.h);
    }
    return g;
}

@compute @workgroup_size(64)
fn emit_vertices(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i >= params.node_count) {
        return;
    }
    let p = node_of(i);
    let v0 = value(p);
    for (var axis = 0u; axis < 3u; axis++) {
        var o = p;
        o[axis] += 1u;
        if (o[axis] >= params.nodes[axis]) {
            continue;
        }
        let v1 = value(o);
        if ((v0 > params.iso) == (v1 > params.iso)) {
            continue;
        }
        let t = (params.iso - v0) / (v1 - v0);
        let slot = atomicAdd(&counters.vertex_count, 1u);
        edge_vertex[i * 3u + axis] = slot;
        if (slot >= params.vertex_capacity) {
            continue;
        }
        let position = mix(node_position(p), node_position(o), t);
        let g = mix(gradient(p), gradient(o), t);
        let normal = -g / max(length(g), 1e-20);
        set_mesh_position(slot, position);
        set_mesh_normal(slot, normal);
    }
}

// Cube edge e (4·axis + k) as (its lower corner's offset, axis); the
// twin's `cube_edge`.
fn cube_edge_vertex(cell: vec3<u32>, e: u32) -> u32 {
    let axis = e / 4u;
    let k = e % 4u;
    var offset = vec3<u32>(0u);
    var others = vec2<u32>(1u, 2u);
    if (axis == 1u) {
        others = vec2<u32>(0u, 2u);
    } else if (axis == 2u) {
        others = vec2<u32>(0u, 1u);
    }
    offset[others.x] = k & 1u;
    offset[others.y] = (k >> 1u) & 1u;
    return edge_vertex[node_index(cell + offset) * 3u + axis];
}

@compute @workgroup_size(64)
fn emit_triangles(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i >= params.node_count) {
        return;
    }
    let cell = node_of(i);
    if (any(cell + 1u >= params.nodes)) {
        return;
    }
    var case_index = 0u;
    for (var c = 0u; c < 8u; c++) {
        let corner = cell + vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
        if (value(corner) > params.iso) {
            case_index |= 1u << c;
        }
    }
    let entry = case_index * CASE_STRIDE;
    let count = cases[entry];
    if (count == 0u) {
        return;
    }
    let base = atomicAdd(&counters.index_count, 3u * count);
    for (var t = 0u; t < count; t++) {
        let at = base + 3u * t;
        if (at + 3u > params.index_capacity) {
            return;
        }
        let a = cube_edge_vertex(cell, cases[entry + 1u + 3u * t]);
        let b = cube_edge_vertex(cell, cases[entry + 2u + 3u * t]);
        let c = cube_edge_vertex(cell, cases[entry + 3u + 3u * t]);
        // A vertex past the buffer's end: the triangle is left out (drawn
        // degenerate).
        let kept = max(a, max(b, c)) < params.vertex_capacity;
        indices[at] = select(0u, a, kept);
        indices[at + 1u] = select(0u, b, kept);
        indices[at + 2u] = select(0u, c, kept);
    }
}

@compute @workgroup_size(1)
fn finish() {
    keep_indices_within(params.index_capacity);
}
