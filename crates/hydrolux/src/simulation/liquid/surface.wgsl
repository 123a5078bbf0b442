// The liquid's surface by marching cubes on the GPU (seed 003 §3.1; the
// CPU twin is hydrolux_core::fluid::surface, step for step), with no read
// back: clear → splat (each particle's kernel, and the kernel times its
// position, added to the nodes in fixed point, so the sums do not depend on
// the particles' order) → levels (the field meshed: the density, or Zhu &
// Bridson's distance to the particles' weighted mean less a radius,
// `fluid.surface_field`) → smooth (`fluid.surface_smoothing` rounds of a
// binomial filter per axis over the levels) → vertices
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
    // The mean-position field's radius r (m); 1 to mesh that field, 0 the
    // density.
    radius: f32,
    mean_position: u32,
    // The closed walls (bit 2a: low side of axis a, 2a + 1: high) and the
    // nodes at least a spacing inside them (the twin's `Walls`).
    closed: u32,
    _pad0: u32,
    inner_lo: vec3<u32>,
    _pad1: u32,
    inner_hi: vec3<u32>,
    _pad2: u32,
    beyond_hi: vec3<u32>,
    _pad3: u32,
}

@group(0) @binding(0) var<uniform> params: SurfaceParams;
@group(0) @binding(1) var<storage, read> particles: array<LiquidParticle>;
// The splat's four channels, node_count each: the density, then its
// moments along x, y, z (the kernel times the particle's place as a
// fraction of the grid's extent).
@group(0) @binding(2) var<storage, read_write> field: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> edge_vertex: array<u32>;
// Eight floats a vertex: position, normal, uv (the meshes' layout).
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(5) var<storage, read_write> indices: array<u32>;
@group(0) @binding(6) var<storage, read_write> counters: MeshCounters;
// Per case: its triangle count, then three cube edges per triangle.
@group(0) @binding(7) var<storage, read> cases: array<u32>;
// Each node's level (f32 bits), in the first node_count words.
@group(0) @binding(8) var<storage, read_write> level_values: array<u32>;

const CHANNELS: u32 = 4u;

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
    return bitcast<f32>(level_values[node_index(p)]);
}

fn extent() -> vec3<f32> {
    return params.h * vec3<f32>(params.nodes - 1u);
}

@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i == 0u) {
        reset_mesh_counters();
    }
    if (i < CHANNELS * params.node_count) {
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
    let u = clamp((p - params.origin) / extent(), vec3<f32>(0.0), vec3<f32>(1.0));
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
                    let units = w * params.scale * params.fixed_point;
                    let at = node_index(vec3<u32>(x, y, z));
                    let n = params.node_count;
                    atomicAdd(&field[at], u32(units + 0.5));
                    atomicAdd(&field[n + at], u32(units * u.x + 0.5));
                    atomicAdd(&field[2u * n + at], u32(units * u.y + 0.5));
                    atomicAdd(&field[3u * n + at], u32(units * u.z + 0.5));
                }
            }
        }
    }
}

// The binomial filter (¼, ½, ¼) along `axis` over the levels, zero beyond
// the grid (the twin's `smooth` and `filtered`): read from `level_values`,
// written to the field's first channel (copied back after each axis).
fn smooth_along(i: u32, axis: u32) {
    if (i >= params.node_count) {
        return;
    }
    let p = node_of(i);
    var lo = 0.0;
    var hi = 0.0;
    if (p[axis] > 0u) {
        var q = p;
        q[axis] -= 1u;
        lo = bitcast<f32>(level_values[node_index(q)]);
    }
    if (p[axis] + 1u < params.nodes[axis]) {
        var q = p;
        q[axis] += 1u;
        hi = bitcast<f32>(level_values[node_index(q)]);
    }
    let mid = bitcast<f32>(level_values[i]);
    atomicStore(&field[i], bitcast<u32>(0.25 * (lo + hi) + 0.5 * mid));
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

// A node's own level, the field meshed at `iso` (the twin's `node_level`):
// the density, or ½ − φ/R with φ = |x − x̄| − r from the particles'
// weighted mean x̄, held within r/R of ½.
fn own_level(i: u32) -> f32 {
    let n = params.node_count;
    let weight = atomicLoad(&field[i]);
    var level = f32(weight) / params.fixed_point;
    if (params.mean_position != 0u) {
        let span = params.radius / params.reach;
        level = params.iso - span;
        if (weight != 0u) {
            let w = f32(weight);
            let moments = vec3<f32>(
                f32(atomicLoad(&field[n + i])),
                f32(atomicLoad(&field[2u * n + i])),
                f32(atomicLoad(&field[3u * n + i])),
            );
            let mean = params.origin + extent() * (moments / w);
            let x = node_position(node_of(i));
            level = max(params.iso - (distance(x, mean) - params.radius) / params.reach, params.iso - span);
        }
    }
    return level;
}

// The level outside the liquid, and deep inside (the twin's
// `outside_level` and `inside_level`).
fn outside_level() -> f32 {
    return select(0.0, params.iso - params.radius / params.reach, params.mean_position != 0u);
}

fn inside_level() -> f32 {
    return select(1.0, params.iso + params.radius / params.reach, params.mean_position != 0u);
}

// Each node's level, carried through the closed walls (the twin's `level`
// and `Walls::source`): an outermost node past a closed wall is outside; a
// node past a wall is inside where the node a spacing inside is; a node
// nearer a wall than a spacing has at least that node's level.
@compute @workgroup_size(64)
fn levels(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i >= params.node_count) {
        return;
    }
    let p = node_of(i);
    var q = p;
    var outermost = false;
    var beyond = false;
    for (var a = 0u; a < 3u; a++) {
        let low = ((params.closed >> (2u * a)) & 1u) != 0u;
        let high = ((params.closed >> (2u * a + 1u)) & 1u) != 0u;
        outermost = outermost | (low & (p[a] == 0u)) | (high & (p[a] + 1u == params.nodes[a]));
        if (low) {
            beyond = beyond | (p[a] < 2u);
            q[a] = max(q[a], params.inner_lo[a]);
        }
        if (high) {
            beyond = beyond | (p[a] >= params.beyond_hi[a]);
            q[a] = min(q[a], params.inner_hi[a]);
        }
    }
    var level = own_level(i);
    if (outermost) {
        level = outside_level();
    } else if (beyond) {
        level = select(outside_level(), inside_level(), own_level(node_index(q)) > params.iso);
    } else if (any(q != p)) {
        level = max(level, own_level(node_index(q)));
    }
    level_values[i] = bitcast<u32>(level);
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
