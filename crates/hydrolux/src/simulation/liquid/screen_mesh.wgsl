// The liquid's surface as a screen-space mesh on the GPU (seed 003 §3.2,
// after Müller, Schirm & Duthaler 2007; the CPU twin is
// hydrolux_core::fluid::screen_mesh, step for step), with no read back:
// clear → depth (each particle's sphere front on the nodes, eq. 24, by
// atomic min of the depth's bits) → silhouette edges → their cuts (atomic
// max of the farthest cut) → the layer-aware binomial filter across, then
// down → vertices (filled nodes; one or two per silhouette edge) →
// triangles (each square's case of cut edges, Fig. 14; the silhouette's
// links) → silhouette smoothing rounds → back to world space (eq. 25–26) →
// normals from the triangles (summed in fixed point) → the indexed
// indirect draw's count.
#import liquid_particle, liquid_mesh, screen_project

struct ScreenMeshParams {
    // World → clip, and back.
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // The screen (W, H) in pixels, h (pixels), r (m).
    screen: vec2<f32>,
    h: f32,
    radius: f32,
    nodes: vec2<u32>,
    node_count: u32,
    edge_count: u32,
    // z_max (m), n_filter.
    depth_threshold: f32,
    filter_half_length: u32,
    particle_count: u32,
    vertex_capacity: u32,
    index_capacity: u32,
    // Threads per row of a two-dimensional dispatch.
    row: u32,
    // Widest particle splat (node spacings) and nearest depth (m).
    max_reach: f32,
    min_depth: f32,
    // Where in `screen` the smoothed silhouette is (0 or vertex_capacity).
    smoothed_half: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: ScreenMeshParams;
@group(0) @binding(1) var<storage, read> particles: array<LiquidParticle>;
// The nodes' depth bits (EMPTY: none), then the back of their layer's
// bits (0: none), then each edge's mark (0: not a silhouette; 1: one,
// uncut; 2 + q: cut at q/65535 from its front node), then three
// fixed-point normal sums per vertex.
@group(0) @binding(2) var<storage, read_write> marks: array<atomic<u32>>;
// The filtered depths (across, then across and down), then the filtered
// backs (the same).
@group(0) @binding(3) var<storage, read_write> depths: array<f32>;
// Vertex of each node, two of each edge (front, back), then two silhouette
// links per vertex.
@group(0) @binding(4) var<storage, read_write> maps: array<u32>;
// Each vertex on the screen (x_p, y_p, z_p, kind), twice (smoothing's
// ping-pong).
@group(0) @binding(5) var<storage, read_write> screen: array<vec4<f32>>;
// Eight floats a vertex: position, normal, uv (the meshes' layout).
@group(0) @binding(6) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(7) var<storage, read_write> indices: array<u32>;
@group(0) @binding(8) var<storage, read_write> counters: MeshCounters;

const NONE: u32 = 0xffffffffu;
const EMPTY: u32 = 0xffffffffu;
const KIND_NODE: f32 = 0.0;
const KIND_FRONT: f32 = 1.0;
const KIND_BACK: f32 = 2.0;
// The back sheet's copy of the vertex before it.
const KIND_SHEET: f32 = 3.0;
const CUT_STEPS: f32 = 65535.0;
// Units of a normal sum per unit normal.
const NORMAL_FIXED_POINT: f32 = 16384.0;

fn thread(id: vec3<u32>) -> u32 {
    return id.x + id.y * params.row;
}

fn node(i: u32, j: u32) -> u32 {
    return j * params.nodes.x + i;
}

fn edges_along_x() -> u32 {
    return (params.nodes.x - 1u) * params.nodes.y;
}

fn edge_x(i: u32, j: u32) -> u32 {
    return j * (params.nodes.x - 1u) + i;
}

fn edge_y(i: u32, j: u32) -> u32 {
    return edges_along_x() + j * params.nodes.x + i;
}

// An edge's two nodes, the lower first.
fn edge_nodes(e: u32) -> vec2<u32> {
    let nx = params.nodes.x;
    if (e < edges_along_x()) {
        let i = e % (nx - 1u);
        let j = e / (nx - 1u);
        return vec2<u32>(node(i, j), node(i + 1u, j));
    }
    let f = e - edges_along_x();
    let i = f % nx;
    let j = f / nx;
    return vec2<u32>(node(i, j), node(i, j + 1u));
}

fn raw_bits(n: u32) -> u32 {
    return atomicLoad(&marks[n]);
}

fn filled(n: u32) -> bool {
    return raw_bits(n) != EMPTY;
}

fn raw_depth(n: u32) -> f32 {
    return bitcast<f32>(raw_bits(n));
}

fn back_at(n: u32) -> u32 {
    return params.node_count + n;
}

fn edge_at(e: u32) -> u32 {
    return 2u * params.node_count + e;
}

fn edge_mark(e: u32) -> u32 {
    return atomicLoad(&marks[edge_at(e)]);
}

// Whether the edge's second node is its front (nearer) one; an empty
// node's bits are the largest.
fn front_is_second(ends: vec2<u32>) -> bool {
    let a = raw_bits(ends.x);
    let b = raw_bits(ends.y);
    if (a == EMPTY || b == EMPTY) {
        return a == EMPTY && b != EMPTY;
    }
    return bitcast<f32>(b) < bitcast<f32>(a);
}

fn node_xy(n: u32) -> vec2<f32> {
    return vec2<f32>(f32(n % params.nodes.x), f32(n / params.nodes.x)) * params.h;
}

// Eq. 21–23: pixels, depth (the clip w), radii in pixels.
struct Projected {
    ok: bool,
    x: f32,
    y: f32,
    z: f32,
    rx: f32,
    ry: f32,
}

fn row_length(k: u32) -> f32 {
    let m = params.view_proj;
    return length(vec3<f32>(m[0][k], m[1][k], m[2][k]));
}

fn project(i: u32) -> Projected {
    var p: Projected;
    p.ok = false;
    if (i >= params.particle_count || particles[i].alive == 0u) {
        return p;
    }
    let c = params.view_proj * vec4<f32>(particles[i].position, 1.0);
    if (c.w <= 1e-4) {
        return p;
    }
    p.x = params.screen.x * (0.5 + 0.5 * c.x / c.w);
    p.y = params.screen.y * (0.5 + 0.5 * c.y / c.w);
    p.z = c.w;
    p.rx = 0.5 * params.radius * params.screen.x * row_length(0u) / c.w;
    p.ry = 0.5 * params.radius * params.screen.y * row_length(1u) / c.w;
    p.ok = max(p.rx, p.ry) <= params.max_reach * params.h;
    return p;
}

// Eq. 25–26 (`screen_project`).
fn unproject(s: vec3<f32>) -> vec3<f32> {
    return unproject_depth(params.inv_view_proj, params.screen, s);
}

@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i == 0u) {
        reset_mesh_counters();
    }
    if (i < params.node_count) {
        atomicStore(&marks[i], EMPTY);
        atomicStore(&marks[back_at(i)], 0u);
    }
    if (i < params.edge_count) {
        atomicStore(&marks[edge_at(i)], 0u);
    }
    if (i < params.node_count + 2u * params.edge_count) {
        maps[i] = NONE;
    }
}

// The nodes in particle `p`'s circle: their range, clamped to the map.
struct Covered {
    ok: bool,
    lo: vec2<u32>,
    hi: vec2<u32>,
}

fn covered(p: Projected) -> Covered {
    var c: Covered;
    let h = params.h;
    let last = vec2<f32>(params.nodes) - 1.0;
    let i1 = min(floor((p.x + p.rx) / h), last.x);
    let j1 = min(floor((p.y + p.ry) / h), last.y);
    c.ok = i1 >= 0.0 && j1 >= 0.0;
    c.lo = vec2<u32>(u32(max(ceil((p.x - p.rx) / h), 0.0)), u32(max(ceil((p.y - p.ry) / h), 0.0)));
    c.hi = vec2<u32>(u32(max(i1, 0.0)), u32(max(j1, 0.0)));
    return c;
}

// √(1 − d²/r_p²) at node (i, j), negative outside the circle.
fn reach(p: Projected, i: u32, j: u32) -> f32 {
    let dx = (f32(i) * params.h - p.x) / p.rx;
    let dy = (f32(j) * params.h - p.y) / p.ry;
    let d2 = dx * dx + dy * dy;
    return select(-1.0, sqrt(max(1.0 - d2, 0.0)), d2 <= 1.0);
}

// One particle over the nodes in its circle: `back` false, eq. 24, its
// sphere's front (atomic min); true, the back of the front layer, its
// sphere's back where its front lies within z_max of the node's depth
// (atomic max; after the fronts are all in).
fn splat_particle(particle: u32, back: bool) {
    let p = project(particle);
    let c = covered(p);
    if (!p.ok || !c.ok) {
        return;
    }
    for (var j = c.lo.y; j <= c.hi.y; j++) {
        for (var i = c.lo.x; i <= c.hi.x; i++) {
            let k = reach(p, i, j);
            if (k < 0.0) {
                continue;
            }
            let n = node(i, j);
            let front = max(p.z - params.radius * k, params.min_depth);
            if (!back) {
                atomicMin(&marks[n], bitcast<u32>(front));
            } else if (front <= raw_depth(n) + params.depth_threshold) {
                atomicMax(&marks[back_at(n)], bitcast<u32>(p.z + params.radius * k));
            }
        }
    }
}

@compute @workgroup_size(64)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    splat_particle(thread(id), false);
}

@compute @workgroup_size(64)
fn splat_back(@builtin(global_invocation_id) id: vec3<u32>) {
    splat_particle(thread(id), true);
}

@compute @workgroup_size(64)
fn classify(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = thread(id);
    if (e >= params.edge_count) {
        return;
    }
    let ends = edge_nodes(e);
    let a = filled(ends.x);
    let b = filled(ends.y);
    var silhouette = a != b;
    if (a && b) {
        silhouette = abs(raw_depth(ends.x) - raw_depth(ends.y)) > params.depth_threshold;
    }
    if (silhouette) {
        atomicStore(&marks[edge_at(e)], 1u);
    }
}

// One particle's cut of edge `e` at `along` (from its lower node).
fn offer_cut(e: u32, along: f32, z: f32) {
    if (edge_mark(e) == 0u || along < 0.0 || along > 1.0) {
        return;
    }
    let ends = edge_nodes(e);
    // The mean of an edge with an empty node is infinite.
    if (filled(ends.x) && filled(ends.y)
        && z >= 0.5 * (raw_depth(ends.x) + raw_depth(ends.y))) {
        return;
    }
    var t = along;
    if (front_is_second(ends)) {
        t = 1.0 - along;
    }
    let q = u32(floor(clamp(t, 0.0, 1.0) * CUT_STEPS));
    atomicMax(&marks[edge_at(e)], 2u + q);
}

// Fig. 12–13: each particle cuts the silhouette edges its circle crosses.
@compute @workgroup_size(64)
fn cut(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = project(thread(id));
    if (!p.ok) {
        return;
    }
    let h = params.h;
    for (var axis = 0u; axis < 2u; axis++) {
        var rows = params.nodes.y;
        var cols = params.nodes.x;
        var across = p.y;
        var r_across = p.ry;
        var along = p.x;
        var r_along = p.rx;
        if (axis == 1u) {
            rows = params.nodes.x;
            cols = params.nodes.y;
            across = p.x;
            r_across = p.rx;
            along = p.y;
            r_along = p.ry;
        }
        let k0 = u32(max(ceil((across - r_across) / h), 0.0));
        let k1 = floor((across + r_across) / h);
        if (k1 < 0.0) {
            continue;
        }
        for (var k = k0; k <= min(u32(k1), rows - 1u); k++) {
            let q = (f32(k) * h - across) / r_across;
            if (q * q >= 1.0) {
                continue;
            }
            let half = r_along * sqrt(1.0 - q * q);
            for (var side = 0u; side < 2u; side++) {
                let x = along + select(-half, half, side == 1u);
                let m = floor(x / h);
                if (m < 0.0 || u32(m) >= cols - 1u) {
                    continue;
                }
                let t = x / h - m;
                var e = edge_x(u32(m), k);
                if (axis == 1u) {
                    e = edge_y(k, u32(m));
                }
                offer_cut(e, t, p.z);
            }
        }
    }
}

// The binomial weight of offset k in a filter of half length n: C(2n, n + k).
fn binomial(n: u32, k: u32) -> f32 {
    var w = 1.0;
    for (var m = 1u; m <= k; m++) {
        w = w * f32(2u * n - m + 1u) / f32(m);
    }
    return w;
}

// §3.2.6: the filter along x or y over filled nodes, from neighbours of
// the same layer (within z_max in the raw depths).
// The values a pass filters: SOURCE_RAW the depth bits, SOURCE_BACK the
// backs' bits, otherwise `depths` from that offset.
const SOURCE_RAW: u32 = 0xffffffffu;
const SOURCE_BACK: u32 = 0xfffffffeu;

fn smooth_along(c: u32, along_x: bool, source: u32) -> f32 {
    let zc = raw_depth(c);
    let n = i32(params.filter_half_length);
    let ci = i32(c % params.nodes.x);
    let cj = i32(c / params.nodes.x);
    var sum = 0.0;
    var weight = 0.0;
    for (var k = -n; k <= n; k++) {
        var ni = ci;
        var nj = cj;
        if (along_x) {
            ni += k;
        } else {
            nj += k;
        }
        if (ni < 0 || nj < 0 || ni >= i32(params.nodes.x) || nj >= i32(params.nodes.y)) {
            continue;
        }
        let m = node(u32(ni), u32(nj));
        if (!filled(m) || abs(raw_depth(m) - zc) > params.depth_threshold) {
            continue;
        }
        let w = binomial(params.filter_half_length, u32(k + n));
        var v: f32;
        if (source == SOURCE_RAW) {
            v = raw_depth(m);
        } else if (source == SOURCE_BACK) {
            v = bitcast<f32>(atomicLoad(&marks[back_at(m)]));
        } else {
            v = depths[source + m];
        }
        sum += w * v;
        weight += w;
    }
    return sum / weight;
}

@compute @workgroup_size(64)
fn smooth_x(@builtin(global_invocation_id) id: vec3<u32>) {
    let c = thread(id);
    if (c >= params.node_count || !filled(c)) {
        return;
    }
    depths[c] = smooth_along(c, true, SOURCE_RAW);
    depths[2u * params.node_count + c] = smooth_along(c, true, SOURCE_BACK);
}

@compute @workgroup_size(64)
fn smooth_y(@builtin(global_invocation_id) id: vec3<u32>) {
    let c = thread(id);
    if (c >= params.node_count || !filled(c)) {
        return;
    }
    let n = params.node_count;
    depths[n + c] = smooth_along(c, false, 0u);
    depths[3u * n + c] = smooth_along(c, false, 2u * n);
}

fn smoothed(n: u32) -> f32 {
    return depths[params.node_count + n];
}

fn smoothed_back(n: u32) -> f32 {
    return depths[3u * params.node_count + n];
}

fn put_vertex(slot: u32, s: vec4<f32>) {
    screen[slot] = s;
    let links = params.node_count + 2u * params.edge_count + 2u * slot;
    maps[links] = NONE;
    maps[links + 1u] = NONE;
}

// One vertex per filled node; on each silhouette edge one at its cut with
// the front layer's depth and, between two filled nodes, one with the
// back layer's.
@compute @workgroup_size(64)
fn emit_vertices(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = thread(id);
    if (i < params.node_count) {
        if (!filled(i)) {
            return;
        }
        // The node and its back-sheet copy.
        let slot = atomicAdd(&counters.vertex_count, 2u);
        if (slot + 2u <= params.vertex_capacity) {
            maps[i] = slot;
            put_vertex(slot, vec4<f32>(node_xy(i), smoothed(i), KIND_NODE));
            put_vertex(slot + 1u, vec4<f32>(node_xy(i), smoothed_back(i), KIND_SHEET));
        }
        return;
    }
    let e = i - params.node_count;
    if (e >= params.edge_count) {
        return;
    }
    let mark = edge_mark(e);
    if (mark == 0u) {
        return;
    }
    let ends = edge_nodes(e);
    var front = ends.x;
    var back = ends.y;
    if (front_is_second(ends)) {
        front = ends.y;
        back = ends.x;
    }
    var t = 0.5;
    if (mark >= 2u) {
        t = f32(mark - 2u) / CUT_STEPS;
    }
    let xy = mix(node_xy(front), node_xy(back), t);
    // The outline's vertex alone (front and back sheet meet there); between
    // two layers each layer's vertex and its copy.
    let two = filled(back);
    let count = select(1u, 4u, two);
    let slot = atomicAdd(&counters.vertex_count, count);
    if (slot + count > params.vertex_capacity) {
        return;
    }
    let at = params.node_count + 2u * e;
    maps[at] = slot;
    put_vertex(slot, vec4<f32>(xy, smoothed(front), KIND_FRONT));
    if (two) {
        put_vertex(slot + 1u, vec4<f32>(xy, smoothed_back(front), KIND_SHEET));
        maps[at + 1u] = slot + 2u;
        put_vertex(slot + 2u, vec4<f32>(xy, smoothed(back), KIND_BACK));
        put_vertex(slot + 3u, vec4<f32>(xy, smoothed_back(back), KIND_SHEET));
    }
}

// Square (i, j)'s edge k (k joins corner k and k + 1; corners
// counter-clockwise from (i, j)).
fn square_edge(i: u32, j: u32, k: u32) -> u32 {
    switch k {
        case 0u: { return edge_x(i, j); }
        case 1u: { return edge_y(i + 1u, j); }
        case 2u: { return edge_x(i, j + 1u); }
        default: { return edge_y(i, j); }
    }
}

fn square_corner(i: u32, j: u32, c: u32) -> u32 {
    let dx = select(0u, 1u, c == 1u || c == 2u);
    let dy = select(0u, 1u, c >= 2u);
    return node(i + dx, j + dy);
}

// The vertex on edge `e` for the polygon on node `n`'s side.
fn side_vertex(e: u32, n: u32) -> u32 {
    let ends = edge_nodes(e);
    var front = ends.x;
    if (front_is_second(ends)) {
        front = ends.y;
    }
    return maps[params.node_count + 2u * e + select(1u, 0u, n == front)];
}

fn kind(v: u32) -> f32 {
    return screen[v].w;
}

fn put_triangle(at: u32, a: u32, b: u32, c: u32) {
    if (at + 3u > params.index_capacity) {
        return;
    }
    // A vertex that did not fit: the triangle is left out (degenerate).
    let kept = a != NONE && b != NONE && c != NONE;
    indices[at] = select(0u, a, kept);
    indices[at + 1u] = select(0u, b, kept);
    indices[at + 2u] = select(0u, c, kept);
}

// The back sheet's copy of vertex `v` (taken with it, just after it), or
// `v` itself on the outline.
fn sheet(v: u32) -> u32 {
    if (v != NONE && v + 1u < vertex_count() && kind(v + 1u) == KIND_SHEET) {
        return v + 1u;
    }
    return v;
}

// A front triangle at `at` and its back-sheet twin, wound the other way,
// after it.
fn put_triangles(at: u32, a: u32, b: u32, c: u32) {
    put_triangle(at, a, b, c);
    put_triangle(at + 3u, sheet(a), sheet(c), sheet(b));
}

// Fig. 14: the square's boundary splits at its cut edges into runs of
// corners; each run of filled corners, closed by the vertices on the cuts
// it starts and ends on, is a polygon fanned into triangles.
@compute @workgroup_size(64)
fn emit_triangles(@builtin(global_invocation_id) id: vec3<u32>) {
    let s = thread(id);
    if (s >= params.node_count) {
        return;
    }
    let i = s % params.nodes.x;
    let j = s / params.nodes.x;
    if (i + 1u >= params.nodes.x || j + 1u >= params.nodes.y) {
        return;
    }
    var mask = 0u;
    for (var k = 0u; k < 4u; k++) {
        if (edge_mark(square_edge(i, j, k)) != 0u) {
            mask |= 1u << k;
        }
    }
    if (mask == 0u) {
        var poly: array<u32, 4>;
        for (var c = 0u; c < 4u; c++) {
            let n = square_corner(i, j, c);
            if (!filled(n)) {
                return;
            }
            poly[c] = maps[n];
        }
        let at = atomicAdd(&counters.index_count, 12u);
        put_triangles(at, poly[0], poly[1], poly[2]);
        put_triangles(at + 6u, poly[0], poly[2], poly[3]);
        return;
    }
    let links = params.node_count + 2u * params.edge_count;
    for (var start = 0u; start < 4u; start++) {
        let entering = (start + 3u) % 4u;
        if ((mask & (1u << entering)) == 0u || !filled(square_corner(i, j, start))) {
            continue;
        }
        var poly: array<u32, 6>;
        poly[0] = side_vertex(square_edge(i, j, entering), square_corner(i, j, start));
        var len = 1u;
        var k = start;
        loop {
            poly[len] = maps[square_corner(i, j, k)];
            len += 1u;
            if ((mask & (1u << k)) != 0u) {
                break;
            }
            k = (k + 1u) % 4u;
        }
        let leaving = k;
        poly[len] = side_vertex(square_edge(i, j, leaving), square_corner(i, j, leaving));
        len += 1u;
        let at = atomicAdd(&counters.index_count, 6u * (len - 2u));
        for (var t = 1u; t + 1u < len; t++) {
            put_triangles(at + 6u * (t - 1u), poly[0], poly[t], poly[t + 1u]);
        }
        // The closing edge joins two front silhouette vertices: they are
        // neighbours along the silhouette. Slot: which of the edge's two
        // squares this is (edges 0 and 3: the square above or right).
        let first = poly[0];
        let last = poly[len - 1u];
        if (first != NONE && last != NONE && kind(first) == KIND_FRONT
            && kind(last) == KIND_FRONT) {
            maps[links + 2u * first + select(0u, 1u, entering == 0u || entering == 3u)] = last;
            maps[links + 2u * last + select(0u, 1u, leaving == 0u || leaving == 3u)] = first;
        }
    }
}

fn vertex_count() -> u32 {
    return min(atomicLoad(&counters.vertex_count), params.vertex_capacity);
}

// Vertex `v` after a round of silhouette smoothing over `read_half`: a
// front silhouette vertex to the mean of itself and its neighbours.
fn smoothed_xy(v: u32, read_half: u32) -> vec2<f32> {
    let s = screen[read_half + v];
    if (s.w != KIND_FRONT) {
        return s.xy;
    }
    var sum = s.xy;
    var count = 1.0;
    let links = params.node_count + 2u * params.edge_count + 2u * v;
    for (var k = 0u; k < 2u; k++) {
        let n = maps[links + k];
        if (n != NONE) {
            sum += screen[read_half + n].xy;
            count += 1.0;
        }
    }
    return sum / count;
}

// One round of silhouette smoothing from one half of `screen` to the
// other; a back-sheet copy follows the vertex before it.
fn smooth_silhouette(v: u32, read_half: u32, write_half: u32) {
    if (v >= vertex_count()) {
        return;
    }
    let s = screen[read_half + v];
    var xy = smoothed_xy(v, read_half);
    if (s.w == KIND_SHEET) {
        xy = smoothed_xy(v - 1u, read_half);
    }
    screen[write_half + v] = vec4<f32>(xy, s.zw);
}

@compute @workgroup_size(64)
fn silhouette_forth(@builtin(global_invocation_id) id: vec3<u32>) {
    smooth_silhouette(thread(id), 0u, params.vertex_capacity);
}

@compute @workgroup_size(64)
fn silhouette_back(@builtin(global_invocation_id) id: vec3<u32>) {
    smooth_silhouette(thread(id), params.vertex_capacity, 0u);
}

fn normal_sum(v: u32) -> u32 {
    return 2u * params.node_count + params.edge_count + 3u * v;
}

// Eq. 25–26: each vertex back to the world; its normal's sum emptied.
@compute @workgroup_size(64)
fn to_world(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = thread(id);
    if (v >= vertex_count()) {
        return;
    }
    set_mesh_position(v, unproject(screen[params.smoothed_half + v].xyz));
    for (var k = 0u; k < 3u; k++) {
        atomicStore(&marks[normal_sum(v) + k], 0u);
    }
}

// Each triangle's unit normal added to its vertices' sums (fixed point;
// two's-complement sums of u32 are those of i32).
@compute @workgroup_size(64)
fn accumulate_normals(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = thread(id);
    let count = min(atomicLoad(&counters.index_count), params.index_capacity) / 3u;
    if (t >= count) {
        return;
    }
    let a = indices[3u * t];
    let b = indices[3u * t + 1u];
    let c = indices[3u * t + 2u];
    let pa = vec3<f32>(vertices[8u * a], vertices[8u * a + 1u], vertices[8u * a + 2u]);
    let pb = vec3<f32>(vertices[8u * b], vertices[8u * b + 1u], vertices[8u * b + 2u]);
    let pc = vec3<f32>(vertices[8u * c], vertices[8u * c + 1u], vertices[8u * c + 2u]);
    let n = cross(pb - pa, pc - pa);
    let len = length(n);
    if (!(len > 0.0)) {
        return;
    }
    let q = vec3<i32>(round(n / len * NORMAL_FIXED_POINT));
    for (var k = 0u; k < 3u; k++) {
        let units = bitcast<u32>(q[k]);
        atomicAdd(&marks[normal_sum(a) + k], units);
        atomicAdd(&marks[normal_sum(b) + k], units);
        atomicAdd(&marks[normal_sum(c) + k], units);
    }
}

// The normals made unit (a vertex of no triangle faces the camera), and
// the draw's count kept within the buffer.
@compute @workgroup_size(64)
fn finish(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = thread(id);
    if (v == 0u) {
        keep_indices_within(params.index_capacity);
    }
    if (v >= vertex_count()) {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        sum[k] = f32(bitcast<i32>(atomicLoad(&marks[normal_sum(v) + k])));
    }
    let s = screen[params.smoothed_half + v].xyz;
    var n = unproject(s) - unproject(s + vec3<f32>(0.0, 0.0, 1.0));
    if (length(sum) > 0.0) {
        n = sum;
    }
    set_mesh_normal(v, normalize(n));
}
