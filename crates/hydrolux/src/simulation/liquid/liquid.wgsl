// The volumetric liquid's step (seed 003 §2.2, the marker-and-cell method;
// FLIP/PIC after Zhu & Bridson 2005; the projection as Bridson's *Fluid
// Simulation for Computer Graphics* ch. 5). The CPU twin is
// hydrolux_core::fluid (flip.rs, pressure.rs), kernel for kernel:
//
//   place_bodies (the moving bodies' cells) → clear → splat (particles to faces, fixed-point atomics: the sums do not
//   depend on the order particles arrive in) → faces (weighted means, the
//   old copy, gravity, closed walls) → solve_begin / reduce_begin → the
//   conjugate-gradient loop (apply with the new direction, update, and
//   reduce_beta: three dispatches, the first two indirect and emptied once
//   converged) →
//   body_loads (the pressure's force and torque on each body) → gradient →
//   extrapolate (two rounds) → advance (FLIP/PIC blend, midpoint advection,
//   particles kept outside the bodies).
//
// Every reduction sums in a fixed order (a tree in each workgroup, then one
// workgroup over the partials), so a step gives the same bits every time.
#import liquid_landing, liquid_bodies, liquid_particle

struct LiquidParams {
    // Cells per axis and in all; faces per axis and in all.
    cells: vec3<u32>,
    cell_count: u32,
    faces: vec3<u32>,
    face_count: u32,
    // The domain's low corner (m) and the cell's side (m).
    origin: vec3<f32>,
    h: f32,
    // m/s², the step (s).
    gravity: vec3<f32>,
    dt: f32,
    particle_count: u32,
    // Workgroups of WG cells.
    cell_groups: u32,
    max_iterations: u32,
    // Largest |∇·u| the solve leaves (1/s).
    tolerance: f32,
    flip: f32,
    density: f32,
    // Kinematic viscosity (m²/s; 0: none).
    viscosity: f32,
    // Bit 2a + side set: the domain's side (axis a, low 0 / high 1) is open.
    open_sides: u32,
    // 1: particles under `landing_level` (m) land in the interactive water
    // (liquid_landing.wgsl), into a log of `landing_capacity`; steps a
    // clock step.
    landing: u32,
    landing_level: f32,
    landing_capacity: u32,
    substeps: u32,
    // White water (white_water.wgsl): 1 while shed; particles a fully
    // breaking particle sheds per second; foam's lifetime (s); the
    // particles a full cell holds; the spray drops' quadratic drag (1/m);
    // the bubbles' rise (m/s) and the time they take to reach it (s).
    white_water: u32,
    white_water_rate: f32,
    foam_life: f32,
    particles_per_cell: f32,
    drop_drag: f32,
    bubble_rise: f32,
    bubble_relaxation: f32,
    _pad0: u32,
}


// A nozzle (hydrolux_core::fluid::Emitter): each step in first_step ..
// end_step it writes its `points` mouth positions, moving at `velocity`,
// into the next layer of its ring of `layers` layers from `first_slot`.
struct Emitter {
    velocity: vec3<f32>,
    first_step: u32,
    end_step: u32,
    first_slot: u32,
    layers: u32,
    points: u32,
    point_offset: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// A box that takes the particles entering it.
struct Drain {
    min: vec3<f32>,
    _pad0: f32,
    max: vec3<f32>,
    _pad1: f32,
}

const MAX_EMITTERS: u32 = 4u;
const MAX_DRAINS: u32 = 4u;

struct Sources {
    emitter_count: u32,
    drain_count: u32,
    // Mouth points of all the nozzles.
    point_count: u32,
    _pad0: u32,
    emitters: array<Emitter, MAX_EMITTERS>,
    drains: array<Drain, MAX_DRAINS>,
    points: array<vec4<f32>>,
}

// What the solve leaves for the next kernels and for the host to read.
struct SolveState {
    sigma: f32,
    alpha: f32,
    beta: f32,
    // max |r| now and before the first iteration (1/s).
    residual: f32,
    residual_before: f32,
    iterations: u32,
    running: u32,
    steps: u32,
}

const WG: u32 = 256u;
// Fixed point of the splat: 1/65536 of a weight, of a weight times m/s.
const FIXED: f32 = 65536.0;
// Particles' speed is kept under this (m/s) so the fixed-point sums fit.
const MAX_SPEED: f32 = 100.0;

@group(0) @binding(0) var<uniform> params: LiquidParams;
@group(0) @binding(1) var<storage, read_write> particles: array<LiquidParticle>;
// Per face the weighted velocity sum, then per face the weight, then per
// cell its particle count.
@group(0) @binding(2) var<storage, read_write> accum: array<atomic<i32>>;
// Per face: the velocity, the splatted (old) velocity, a spare copy.
@group(0) @binding(3) var<storage, read_write> faces: array<f32>;
// Per face: known (extrapolation), twice; then per cell what fills it (0
// nothing, 1 a static object or the ground, 2 + b moving body b: solid);
// then per cell its flags for the solve (below).
@group(0) @binding(4) var<storage, read_write> known: array<u32>;
// Per cell: p, r, z, s, q, t (s's second copy); then per cell workgroup
// a dot product's and two maxima's partials (the update's), then per cell
// workgroup the apply's s·q; then per body its load (`body_loads`).
@group(0) @binding(5) var<storage, read_write> solve: array<f32>;
@group(0) @binding(6) var<storage, read> sources: Sources;
// The solve's state, then the landings' log (liquid_landing.wgsl).
struct LiquidState {
    solve: SolveState,
    landing_dispatch: array<u32, 3>,
    landing_count: atomic<u32>,
    landings: array<Landing>,
}
@group(0) @binding(7) var<storage, read_write> state: LiquidState;
// The moving bodies where rapier has them this clock step.
@group(0) @binding(8) var<uniform> bodies: LiquidBodies;
// The conjugate-gradient kernels' indirect arguments (the reductions write them).
@group(1) @binding(0) var<storage, read_write> args: array<u32>;

var<workgroup> dot_part: array<f32, 256>;
var<workgroup> max_part: array<f32, 256>;
var<workgroup> div_part: array<f32, 256>;

fn linear(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * WG + lid;
}

fn face_dims(a: u32) -> vec3<u32> {
    var m = params.cells;
    m[a] += 1u;
    return m;
}

fn face_index(a: u32, c: vec3<u32>) -> u32 {
    let m = face_dims(a);
    var base = 0u;
    if (a > 0u) { base += params.faces.x; }
    if (a > 1u) { base += params.faces.y; }
    return base + (c.z * m.y + c.y) * m.x + c.x;
}

fn cell_index(c: vec3<u32>) -> u32 {
    return (c.z * params.cells.y + c.y) * params.cells.x + c.x;
}

fn inside(c: vec3<i32>) -> bool {
    return all(c >= vec3<i32>(0)) && all(c < vec3<i32>(params.cells));
}

// Whether a cell outside the domain lies beyond open sides only (air).
fn beyond_open(c: vec3<i32>) -> bool {
    let n = vec3<i32>(params.cells);
    for (var a = 0u; a < 3u; a++) {
        if (c[a] < 0 && (params.open_sides & (1u << (2u * a))) == 0u) {
            return false;
        }
        if (c[a] >= n[a] && (params.open_sides & (2u << (2u * a))) == 0u) {
            return false;
        }
    }
    return true;
}

// Cells outside the domain are solid (closed walls) or air (beyond open
// sides); those a static object fills are solid; any other cell holding a
// particle is liquid.
fn is_solid(c: vec3<i32>) -> bool {
    if (!inside(c)) {
        return !beyond_open(c);
    }
    return known[2u * params.face_count + cell_index(vec3<u32>(c))] != 0u;
}

// What fills cell c (inside the domain): 0 nothing, 1 a static solid, 2 + b
// moving body b.
fn filler(c: vec3<i32>) -> u32 {
    return known[2u * params.face_count + cell_index(vec3<u32>(c))];
}

fn cell_centre(c: vec3<i32>) -> vec3<f32> {
    return params.origin + (vec3<f32>(c) + 0.5) * params.h;
}

// The velocity of the solid filling cell c (0 but for a moving body's).
fn solid_velocity(c: vec3<i32>) -> vec3<f32> {
    if (!inside(c) || filler(c) < 2u) {
        return vec3<f32>(0.0);
    }
    return body_velocity_at(bodies.bodies[filler(c) - 2u], cell_centre(c));
}

// A solid face's velocity: its solid cell's along the face's axis
// (MacGrid::solid_face_velocity).
fn solid_face_velocity(face: vec4<u32>) -> f32 {
    let hi = vec3<i32>(face.xyz);
    if (inside(hi) && is_solid(hi)) {
        return solid_velocity(hi)[face.w];
    }
    let lo = low_cell(face);
    if (inside(lo) && is_solid(lo)) {
        return solid_velocity(lo)[face.w];
    }
    return 0.0;
}

fn is_liquid(c: vec3<i32>) -> bool {
    if (!inside(c) || is_solid(c)) {
        return false;
    }
    return atomicLoad(&accum[2u * params.face_count + cell_index(vec3<u32>(c))]) > 0;
}

// Face (axis a, coordinates c) and its two cells.
fn face_of(g: u32) -> vec4<u32> {
    var a = 0u;
    var f = g;
    if (f >= params.faces.x) {
        f -= params.faces.x;
        a = 1u;
        if (f >= params.faces.y) {
            f -= params.faces.y;
            a = 2u;
        }
    }
    let m = face_dims(a);
    return vec4<u32>(f % m.x, (f / m.x) % m.y, f / (m.x * m.y), a);
}

fn low_cell(face: vec4<u32>) -> vec3<i32> {
    var lo = vec3<i32>(face.xyz);
    lo[face.w] -= 1;
    return lo;
}

fn face_solid(face: vec4<u32>) -> bool {
    return is_solid(low_cell(face)) || is_solid(vec3<i32>(face.xyz));
}

// The eight faces of axis a around world point p and their trilinear
// weights, clamped to the grid (MacGrid::stencil).
struct Stencil {
    base: vec3<u32>,
    frac: vec3<f32>,
}

fn stencil(a: u32, p: vec3<f32>) -> Stencil {
    let m = face_dims(a);
    var s: Stencil;
    for (var b = 0u; b < 3u; b++) {
        let offset = select(0.5, 0.0, b == a);
        let hi = f32(m[b] - 1u);
        let x = clamp((p[b] - params.origin[b]) / params.h - offset, 0.0, hi);
        let i0 = min(u32(floor(x)), m[b] - 2u);
        s.base[b] = i0;
        s.frac[b] = x - f32(i0);
    }
    return s;
}

fn corner_weight(s: Stencil, d: vec3<u32>) -> f32 {
    var w = 1.0;
    for (var b = 0u; b < 3u; b++) {
        w *= select(1.0 - s.frac[b], s.frac[b], d[b] == 1u);
    }
    return w;
}

// Velocity component a at p from the faces' copy at `offset`.
fn sample(a: u32, p: vec3<f32>, offset: u32) -> f32 {
    let s = stencil(a, p);
    let m = face_dims(a);
    var v = 0.0;
    for (var c = 0u; c < 8u; c++) {
        let d = vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
        let at = min(s.base + d, m - vec3<u32>(1u));
        v += faces[offset + face_index(a, at)] * corner_weight(s, d);
    }
    return v;
}

fn velocity_at(p: vec3<f32>, offset: u32) -> vec3<f32> {
    return vec3<f32>(sample(0u, p, offset), sample(1u, p, offset), sample(2u, p, offset));
}

// Each nozzle's layer for this step (before the splat): thread i writes
// mouth point i of whichever nozzle holds it.
@compute @workgroup_size(256)
fn emit(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= sources.point_count) {
        return;
    }
    let step = state.solve.steps;
    for (var k = 0u; k < sources.emitter_count; k++) {
        let e = sources.emitters[k];
        if (i < e.point_offset || i >= e.point_offset + e.points) {
            continue;
        }
        if (step >= e.first_step && step < e.end_step) {
            let j = i - e.point_offset;
            let slot = e.first_slot + ((step - e.first_step) % e.layers) * e.points + j;
            particles[slot] = LiquidParticle(sources.points[i].xyz, 1u, e.velocity, 0.0);
        }
    }
}

// Each cell a moving body's centre lies in is that body's (the first's, in
// order); static solids stay (twin: Liquid::place_bodies).
@compute @workgroup_size(256)
fn place_bodies(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= params.cell_count) {
        return;
    }
    let at = 2u * params.face_count + i;
    if (known[at] == 1u) {
        return;
    }
    let centre = cell_centre(vec3<i32>(cell_coords(i)));
    var fill = 0u;
    for (var b = 0u; b < bodies.count; b++) {
        if (body_distance(bodies.bodies[b], centre) <= 0.0) {
            fill = 2u + b;
            break;
        }
    }
    known[at] = fill;
}

@compute @workgroup_size(256)
fn clear(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i < 2u * params.face_count + params.cell_count) {
        atomicStore(&accum[i], 0);
    }
}

@compute @workgroup_size(256)
fn splat(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= params.particle_count || particles[i].alive == 0u) {
        return;
    }
    let p = particles[i].position;
    let v = clamp(particles[i].velocity, vec3<f32>(-MAX_SPEED), vec3<f32>(MAX_SPEED));
    for (var a = 0u; a < 3u; a++) {
        let s = stencil(a, p);
        let m = face_dims(a);
        for (var c = 0u; c < 8u; c++) {
            let d = vec3<u32>(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
            let f = face_index(a, min(s.base + d, m - vec3<u32>(1u)));
            let w = corner_weight(s, d);
            atomicAdd(&accum[f], i32(round(w * v[a] * FIXED)));
            atomicAdd(&accum[params.face_count + f], i32(round(w * FIXED)));
        }
    }
    let cell = clamp(vec3<i32>(floor((p - params.origin) / params.h)), vec3<i32>(0), vec3<i32>(params.cells) - vec3<i32>(1));
    atomicAdd(&accum[2u * params.face_count + cell_index(vec3<u32>(cell))], 1);
}

// Weighted means (0 where no particle reaches), the old copy, gravity, walls.
@compute @workgroup_size(256)
fn faces_from_particles(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g >= params.face_count) {
        return;
    }
    let weight = atomicLoad(&accum[params.face_count + g]);
    var v = 0.0;
    if (weight > 0) {
        v = f32(atomicLoad(&accum[g])) / f32(weight);
    }
    let face = face_of(g);
    faces[params.face_count + g] = v;
    v += params.gravity[face.w] * params.dt;
    if (face_solid(face)) {
        v = solid_face_velocity(face);
    }
    faces[g] = v;
}

// A face of the liquid: beside a liquid cell and no solid (twin:
// Liquid::face_valid); the gradient and the viscosity act on these.
fn liquid_face(face: vec4<u32>) -> bool {
    return !face_solid(face) && (is_liquid(low_cell(face)) || is_liquid(vec3<i32>(face.xyz)));
}

// Viscosity, one explicit step of ν∇²u on the liquid's faces into the
// spare copy (twin: Liquid::diffuse): a neighbour face on a solid counts 0,
// one beyond the domain or in the air counts as the face itself.
@compute @workgroup_size(256)
fn diffuse(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g >= params.face_count) {
        return;
    }
    let face = face_of(g);
    let own = faces[g];
    var next = own;
    if (liquid_face(face)) {
        let a = face.w;
        let m = vec3<i32>(face_dims(a));
        var laplacian = 0.0;
        for (var b = 0u; b < 3u; b++) {
            for (var side = -1; side <= 1; side += 2) {
                var d = vec3<i32>(face.xyz);
                d[b] += side;
                if (d[b] < 0 || d[b] >= m[b]) {
                    continue;
                }
                let other = vec4<u32>(vec3<u32>(d), a);
                if (face_solid(other)) {
                    laplacian -= own;
                } else if (liquid_face(other)) {
                    laplacian += faces[face_index(a, vec3<u32>(d))] - own;
                }
            }
        }
        next = own + params.viscosity * params.dt / (params.h * params.h) * laplacian;
    }
    faces[2u * params.face_count + g] = next;
}

@compute @workgroup_size(256)
fn diffuse_back(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g < params.face_count) {
        faces[g] = faces[2u * params.face_count + g];
    }
}

fn divergence(c: vec3<u32>) -> f32 {
    var d = 0.0;
    for (var a = 0u; a < 3u; a++) {
        var hi = c;
        hi[a] += 1u;
        d += faces[face_index(a, hi)] - faces[face_index(a, c)];
    }
    return d / params.h;
}

fn scale() -> f32 {
    return params.dt / (params.density * params.h * params.h);
}

fn cell_coords(i: u32) -> vec3<u32> {
    let n = params.cells;
    return vec3<u32>(i % n.x, (i / n.x) % n.y, i / (n.x * n.y));
}

// The Poisson matrix's diagonal: scale per non-solid neighbour.
fn diagonal(c: vec3<i32>) -> f32 {
    var count = 0.0;
    for (var a = 0u; a < 3u; a++) {
        for (var side = -1; side <= 1; side += 2) {
            var q = c;
            q[a] += side;
            if (!is_solid(q)) {
                count += 1.0;
            }
        }
    }
    return count * scale();
}

const P: u32 = 0u;
const R: u32 = 1u;
const Z: u32 = 2u;
const S: u32 = 3u;
const Q: u32 = 4u;
// The search direction's second copy (the loop alternates S and T).
const T: u32 = 5u;
// Where the apply's s·q partials start (in workgroups' worth of partials).
const SQ_PARTIALS: u32 = 3u;

fn at(v: u32, i: u32) -> f32 {
    return solve[v * params.cell_count + i];
}

fn put(v: u32, i: u32, x: f32) {
    solve[v * params.cell_count + i] = x;
}

// Sum `dot_part` and take the maxima of `max_part` and `div_part` over the
// workgroup in a fixed order — sixteen runs of sixteen, then the sixteen —
// with two barriers (a software rasteriser pays for each): the results are
// in element 0.
fn tree_reduce(lid: u32) {
    workgroupBarrier();
    if (lid < 16u) {
        var d = 0.0;
        var m = 0.0;
        var v = 0.0;
        for (var k = 0u; k < 16u; k++) {
            let j = lid * 16u + k;
            d += dot_part[j];
            m = max(m, max_part[j]);
            v = max(v, div_part[j]);
        }
        dot_part[lid * 16u] = d;
        max_part[lid * 16u] = m;
        div_part[lid * 16u] = v;
    }
    workgroupBarrier();
    if (lid == 0u) {
        var d = 0.0;
        var m = 0.0;
        var v = 0.0;
        for (var k = 0u; k < 16u; k++) {
            d += dot_part[k * 16u];
            m = max(m, max_part[k * 16u]);
            v = max(v, div_part[k * 16u]);
        }
        dot_part[0] = d;
        max_part[0] = m;
        div_part[0] = v;
    }
    workgroupBarrier();
}

// Reduce one value of each kind over the workgroup into its partials.
fn reduce_group(group: u32, lid: u32, dot_value: f32, big: f32, div: f32) {
    dot_part[lid] = dot_value;
    max_part[lid] = big;
    div_part[lid] = div;
    tree_reduce(lid);
    if (lid == 0u) {
        solve[6u * params.cell_count + 3u * group] = dot_part[0];
        solve[6u * params.cell_count + 3u * group + 1u] = max_part[0];
        solve[6u * params.cell_count + 3u * group + 2u] = div_part[0];
    }
}

// (A x)_i over liquid cells: scale per non-solid neighbour times x_i, less
// scale times each liquid neighbour's x (air's pressure is 0).
fn apply_matrix(v: u32, c: vec3<i32>) -> f32 {
    var q = diagonal(c) * at(v, cell_index(vec3<u32>(c)));
    for (var a = 0u; a < 3u; a++) {
        for (var side = -1; side <= 1; side += 2) {
            var n = c;
            n[a] += side;
            if (is_liquid(n)) {
                q -= scale() * at(v, cell_index(vec3<u32>(n)));
            }
        }
    }
    return q;
}

// A cell's flags for the solve, so the loop reads one word where it would
// test seven cells (and no atomics): bit 0 liquid, bits 1–6 which of the
// neighbours −x, +x, −y, +y, −z, +z are liquid, bits 8–10 how many are not
// solid (the matrix's diagonal over scale).
const LIQUID: u32 = 1u;

fn solve_flags(i: u32) -> u32 {
    return known[2u * params.face_count + params.cell_count + i];
}

fn flags_of(c: vec3<i32>) -> u32 {
    if (!is_liquid(c)) {
        return 0u;
    }
    var f = LIQUID;
    var open = 0u;
    var bit = 2u;
    for (var a = 0u; a < 3u; a++) {
        for (var side = -1; side <= 1; side += 2) {
            var n = c;
            n[a] += side;
            if (is_liquid(n)) {
                f |= bit;
            }
            if (!is_solid(n)) {
                open += 1u;
            }
            bit <<= 1u;
        }
    }
    return f | (open << 8u);
}

fn diagonal_of(flags: u32) -> f32 {
    return f32((flags >> 8u) & 7u) * scale();
}

// The index offsets of a cell's six neighbours, in the flags' order.
fn neighbour_offset(k: u32) -> i32 {
    let n = vec3<i32>(params.cells);
    let step = array<i32, 3>(1, n.x, n.x * n.y);
    return select(-step[k / 2u], step[k / 2u], (k & 1u) == 1u);
}

// Warm-started from the last step's pressure (p₀ = p in liquid cells, 0
// elsewhere): r = −∇·u − A·p₀, z = M⁻¹r, s = z; partials of r·z, max|r|.
// A liquid cell's p₀ is its own last value, so reading a neighbour's
// while it is written gives the same number.
@compute @workgroup_size(256)
fn solve_begin(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    var rz = 0.0;
    var big = 0.0;
    var div = 0.0;
    if (i < params.cell_count) {
        let c = cell_coords(i);
        known[2u * params.face_count + params.cell_count + i] = flags_of(vec3<i32>(c));
        var r = 0.0;
        var z = 0.0;
        if (is_liquid(vec3<i32>(c))) {
            div = abs(divergence(c));
            r = -divergence(c) - apply_matrix(P, vec3<i32>(c));
            z = r / diagonal(vec3<i32>(c));
        } else {
            put(P, i, 0.0);
        }
        put(R, i, r);
        put(Z, i, z);
        put(S, i, z);
        put(Q, i, 0.0);
        rz = r * z;
        big = abs(r);
    }
    reduce_group(wid.y * nwg.x + wid.x, lid, rz, big, div);
}

// One workgroup over the partials, in a fixed order.
fn reduce_partials(lid: u32) {
    var d = 0.0;
    var m = 0.0;
    var v = 0.0;
    for (var g = lid; g < params.cell_groups; g += WG) {
        d += solve[6u * params.cell_count + 3u * g];
        m = max(m, solve[6u * params.cell_count + 3u * g + 1u]);
        v = max(v, solve[6u * params.cell_count + 3u * g + 2u]);
    }
    dot_part[lid] = d;
    max_part[lid] = m;
    div_part[lid] = v;
    tree_reduce(lid);
}

// Workgroups per row of a two-dimensional dispatch (`ROW` in mod.rs: under
// the 65535 a dimension may have).
const ROW: u32 = 32768u;

// The loop's indirect arguments: the cells' workgroups, in rows of ROW as
// the direct dispatches have them, or none once the solve stops.
fn set_running(running: bool) {
    state.solve.running = u32(running);
    let groups = params.cell_groups;
    args[0] = select(0u, min(groups, ROW), running);
    args[1] = (groups + ROW - 1u) / ROW;
    args[2] = 1u;
}

@compute @workgroup_size(256)
fn reduce_begin(@builtin(local_invocation_index) lid: u32) {
    reduce_partials(lid);
    if (lid == 0u) {
        state.solve.sigma = dot_part[0];
        // The first direction is z itself.
        state.solve.beta = 0.0;
        state.solve.residual = max_part[0];
        state.solve.residual_before = div_part[0];
        state.solve.iterations = 0u;
        state.solve.steps += 1u;
        set_running(max_part[0] > params.tolerance && params.max_iterations > 0u);
    }
}

// The loop: three dispatches an iteration. `cg_apply_*` forms the search
// direction s = z + βs (into the other of two copies, so neighbours still
// read the old one) and q = A s, with partials of s·q; `cg_update_*` reduces
// those partials itself in every workgroup (the same sum in the same order
// everywhere) for α, then p += αs, r −= αq, z = M⁻¹r with partials of r·z
// and max|r|; `reduce_beta` (one workgroup) takes β, the residual and
// whether to go on. The even iterations read S and write T, the odd ones
// read T and write S.

// The search direction at cell `i` from z and the old direction.
fn direction(i: u32, old: u32) -> f32 {
    return at(Z, i) + state.solve.beta * at(old, i);
}

fn apply_direction(i: u32, old: u32, next: u32, group: u32, lid: u32) {
    var sq = 0.0;
    if (i < params.cell_count) {
        let flags = solve_flags(i);
        var s = 0.0;
        var q = 0.0;
        if ((flags & LIQUID) != 0u) {
            s = direction(i, old);
            q = diagonal_of(flags) * s;
            for (var k = 0u; k < 6u; k++) {
                if ((flags & (2u << k)) != 0u) {
                    q -= scale() * direction(u32(i32(i) + neighbour_offset(k)), old);
                }
            }
        }
        put(next, i, s);
        put(Q, i, q);
        sq = s * q;
    }
    dot_part[lid] = sq;
    max_part[lid] = 0.0;
    div_part[lid] = 0.0;
    tree_reduce(lid);
    if (lid == 0u) {
        solve[6u * params.cell_count + SQ_PARTIALS * params.cell_groups + group] = dot_part[0];
    }
}

@compute @workgroup_size(256)
fn cg_apply_s_to_t(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    apply_direction(linear(wid, nwg, lid), S, T, wid.y * nwg.x + wid.x, lid);
}

@compute @workgroup_size(256)
fn cg_apply_t_to_s(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    apply_direction(linear(wid, nwg, lid), T, S, wid.y * nwg.x + wid.x, lid);
}

// s·q over the domain, from the apply's partials (fixed order).
fn sum_sq(lid: u32) -> f32 {
    var d = 0.0;
    for (var g = lid; g < params.cell_groups; g += WG) {
        d += solve[6u * params.cell_count + SQ_PARTIALS * params.cell_groups + g];
    }
    dot_part[lid] = d;
    max_part[lid] = 0.0;
    div_part[lid] = 0.0;
    tree_reduce(lid);
    let sq = dot_part[0];
    // Every thread has read it before any writes the next reduction.
    workgroupBarrier();
    return sq;
}

fn update(i: u32, s_now: u32, group: u32, lid: u32) {
    let sq = sum_sq(lid);
    // A direction the matrix does not see: the reduction stops the loop.
    let go = sq > 0.0;
    let alpha = select(0.0, state.solve.sigma / sq, go);
    var rz = 0.0;
    var big = 0.0;
    if (go && i < params.cell_count) {
        put(P, i, at(P, i) + alpha * at(s_now, i));
        let r = at(R, i) - alpha * at(Q, i);
        put(R, i, r);
        let flags = solve_flags(i);
        var z = 0.0;
        if ((flags & LIQUID) != 0u) {
            z = r / diagonal_of(flags);
        }
        put(Z, i, z);
        rz = r * z;
        big = abs(r);
    }
    reduce_group(group, lid, rz, big, 0.0);
}

@compute @workgroup_size(256)
fn cg_update_t(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    update(linear(wid, nwg, lid), T, wid.y * nwg.x + wid.x, lid);
}

@compute @workgroup_size(256)
fn cg_update_s(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    update(linear(wid, nwg, lid), S, wid.y * nwg.x + wid.x, lid);
}

// The reductions run whether or not the solve still runs (their barriers
// must be in uniform control flow); only thread 0 acts, and only while it runs.
@compute @workgroup_size(256)
fn reduce_beta(@builtin(local_invocation_index) lid: u32) {
    let sq = sum_sq(lid);
    reduce_partials(lid);
    if (lid == 0u && state.solve.running != 0u) {
        if (sq <= 0.0) {
            set_running(false);
        } else {
            let next = dot_part[0];
            state.solve.alpha = state.solve.sigma / sq;
            state.solve.beta = next / state.solve.sigma;
            state.solve.sigma = next;
            state.solve.residual = max_part[0];
            state.solve.iterations += 1u;
            set_running(max_part[0] > params.tolerance && state.solve.iterations < params.max_iterations);
        }
    }
}

fn pressure(c: vec3<i32>) -> f32 {
    if (!is_liquid(c)) {
        return 0.0;
    }
    return at(P, cell_index(vec3<u32>(c)));
}

// Per body: force (3), torque (3), its cells' faces to other cells, and
// those to liquid.
const LOAD_VALUES: u32 = 8u;
var<workgroup> load_part: array<array<f32, LOAD_VALUES>, WG>;

// Where the body loads start in `solve`.
fn loads_at() -> u32 {
    return 6u * params.cell_count + 4u * params.cell_groups;
}

// One workgroup per body: over every face between the body's cells and a
// liquid cell, the liquid's pressure carried linearly to the face (from
// that cell and the one beyond, so a hydrostatic pressure is exact there)
// times h², pushing the body away from the liquid; summed into a force and
// a torque about its centre, in a fixed order, and their share of the
// clock step (1/substeps) added to the body's load (the host clears it
// each clock step). Twin: Liquid::body_loads.
@compute @workgroup_size(256)
fn body_loads(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = wid.x;
    let body = bodies.bodies[b];
    let n = vec3<i32>(params.cells);
    let low = clamp(vec3<i32>(floor((body.position - body.reach - params.origin) / params.h)), vec3<i32>(0), n);
    let high = clamp(vec3<i32>(ceil((body.position + body.reach - params.origin) / params.h)) + 1, vec3<i32>(0), n);
    let span = vec3<u32>(max(high - low, vec3<i32>(0)));
    let total = span.x * span.y * span.z;
    var acc: array<f32, LOAD_VALUES>;
    let area = params.h * params.h;
    for (var k = lid; k < total; k += WG) {
        let c = low + vec3<i32>(vec3<u32>(k % span.x, (k / span.x) % span.y, k / (span.x * span.y)));
        if (filler(c) != 2u + b) {
            continue;
        }
        let centre = cell_centre(c);
        for (var side = 0u; side < 6u; side++) {
            let a = side / 2u;
            let step = select(1, -1, side % 2u == 0u);
            var q = c;
            q[a] += step;
            if (!inside(q) || filler(q) == 2u + b) {
                continue;
            }
            acc[6] += 1.0;
            if (!is_liquid(q)) {
                continue;
            }
            acc[7] += 1.0;
            let p = pressure(q);
            var beyond = q;
            beyond[a] += step;
            var p_beyond = p;
            if (!inside(beyond)) {
                let bit = select(1u, 2u, step > 0) << (2u * a);
                if ((params.open_sides & bit) != 0u) {
                    p_beyond = 0.0;
                }
            } else if (!is_solid(beyond)) {
                p_beyond = pressure(beyond);
            }
            let p_face = p + 0.5 * (p - p_beyond);
            var normal = vec3<f32>(0.0);
            normal[a] = -f32(step);
            let force = p_face * area * normal;
            let torque = cross(centre - normal * (0.5 * params.h) - body.position, force);
            acc[0] += force.x;
            acc[1] += force.y;
            acc[2] += force.z;
            acc[3] += torque.x;
            acc[4] += torque.y;
            acc[5] += torque.z;
        }
    }
    load_part[lid] = acc;
    workgroupBarrier();
    for (var stride = WG / 2u; stride > 0u; stride /= 2u) {
        if (lid < stride) {
            for (var v = 0u; v < LOAD_VALUES; v++) {
                load_part[lid][v] += load_part[lid + stride][v];
            }
        }
        workgroupBarrier();
    }
    if (lid == 0u) {
        let share = 1.0 / f32(params.substeps);
        let out = loads_at() + b * LOAD_VALUES;
        for (var v = 0u; v < 6u; v++) {
            solve[out + v] += load_part[0][v] * share;
        }
        // The wetted share of its faces.
        let faces = load_part[0][6];
        if (faces > 0.0) {
            solve[out + 6u] += load_part[0][7] / faces * share;
        }
    }
}

// Subtract the pressure's gradient from faces between a liquid cell and a
// liquid or air one; mark which faces the liquid knows.
@compute @workgroup_size(256)
fn gradient(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g >= params.face_count) {
        return;
    }
    let face = face_of(g);
    let lo = low_cell(face);
    let hi = vec3<i32>(face.xyz);
    let valid = liquid_face(face);
    if (valid) {
        let k = params.dt / (params.density * params.h);
        faces[g] -= k * (pressure(hi) - pressure(lo));
    }
    known[g] = u32(valid);
}

// Two rounds of extension into the air (`extend_between`): each unknown
// face the mean of its known neighbours of its own axis.
// Round one: from the velocities (copy 0) into the spare (copy 2; `known`
// copy 1 beside it — see the offsets in `extend`).
@compute @workgroup_size(256)
fn extrapolate_out(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g < params.face_count) {
        extend_between(g, 0u, 2u, 0u, 1u);
    }
}

@compute @workgroup_size(256)
fn extrapolate_back(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let g = linear(wid, nwg, lid);
    if (g < params.face_count) {
        extend_between(g, 2u, 0u, 1u, 0u);
    }
}

// `extend` with the velocity copies and the known copies named apart.
fn extend_between(g: u32, src: u32, dst: u32, known_src: u32, known_dst: u32) {
    let face = face_of(g);
    let a = face.w;
    let m = face_dims(a);
    let fc = params.face_count;
    var v = faces[src * fc + g];
    var k = known[known_src * fc + g];
    if (k == 0u) {
        var sum = 0.0;
        var n = 0u;
        for (var b = 0u; b < 3u; b++) {
            for (var side = -1; side <= 1; side += 2) {
                let q = i32(face[b]) + side;
                if (q < 0 || q >= i32(m[b])) {
                    continue;
                }
                var d = face.xyz;
                d[b] = u32(q);
                let o = face_index(a, d);
                if (known[known_src * fc + o] != 0u) {
                    sum += faces[src * fc + o];
                    n += 1u;
                }
            }
        }
        if (n > 0u) {
            v = sum / f32(n);
            k = 1u;
        }
    }
    // The second round ends with the solids' faces moving with them.
    if (dst == 0u && face_solid(face)) {
        v = solid_face_velocity(face);
    }
    faces[dst * fc + g] = v;
    known[known_dst * fc + g] = k;
}

// Each particle takes the grid's change (FLIP) blended with its value
// (PIC), then moves through the new field (midpoint rule), kept a hair
// inside the walls; a move that would end in a solid cell is not made.
@compute @workgroup_size(256)
fn advance(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= params.particle_count || particles[i].alive == 0u) {
        return;
    }
    var p = particles[i].position;
    let v = particles[i].velocity;
    let now = velocity_at(p, 0u);
    let then = velocity_at(p, params.face_count);
    let flip = params.flip;
    var velocity = flip * (v + now - then) + (1.0 - flip) * now;
    let mid = p + 0.5 * params.dt * now;
    let u = velocity_at(mid, 0u);
    let margin = 1e-3 * params.h;
    let lo = params.origin + vec3<f32>(margin);
    let hi = params.origin + vec3<f32>(params.cells) * params.h - vec3<f32>(margin);
    // Outside the bodies (a body's cells do not stop a particle, its exact
    // surface does: one inside goes to a twentieth of a cell outside and
    // loses its velocity into the body; twin: Liquid::clear_of_bodies), and
    // kept inside the closed sides; through an open one it leaves.
    var next = p + params.dt * u;
    let clearance = 0.05 * params.h;
    for (var b = 0u; b < bodies.count; b++) {
        let body = bodies.bodies[b];
        let d = body_distance(body, next);
        if (d >= clearance) {
            continue;
        }
        let n = body_normal(body, next);
        next += (clearance - d) * n;
        let into = dot(velocity - body_velocity_at(body, next), n);
        if (into < 0.0) {
            velocity -= into * n;
        }
    }
    particles[i].velocity = velocity;
    for (var a = 0u; a < 3u; a++) {
        if ((params.open_sides & (1u << (2u * a))) == 0u) {
            next[a] = max(next[a], lo[a]);
        }
        if ((params.open_sides & (2u << (2u * a))) == 0u) {
            next[a] = min(next[a], hi[a]);
        }
    }
    let top = params.origin + vec3<f32>(params.cells) * params.h;
    if (any(next < params.origin) || any(next > top)) {
        particles[i].alive = 0u;
        return;
    }
    let cell = clamp(vec3<i32>(floor((next - params.origin) / params.h)), vec3<i32>(0), vec3<i32>(params.cells) - vec3<i32>(1));
    if (!is_solid(cell) || filler(cell) >= 2u) {
        particles[i].position = next;
    }
    let at = particles[i].position;
    for (var d = 0u; d < sources.drain_count; d++) {
        let box = sources.drains[d];
        if (all(at >= box.min) && all(at <= box.max)) {
            particles[i].alive = 0u;
            return;
        }
    }
    // Under the interactive water's level it becomes that water. (A log
    // too small, which its capacity rules out, would lose the landing.)
    if (params.landing == 1u && at.y < params.landing_level) {
        particles[i].alive = 0u;
        let k = atomicAdd(&state.landing_count, 1u);
        if (k < params.landing_capacity) {
            // This step's index (reduce_begin counted it already).
            let step = state.solve.steps - 1u;
            let speed = -particles[i].velocity.y;
            state.landings[k] = Landing(at.xz, speed, step / params.substeps);
        }
    }
}

// After a run of steps: the interactive water's dispatch over the log.
@compute @workgroup_size(1)
fn landing_dispatch() {
    let count = min(atomicLoad(&state.landing_count), params.landing_capacity);
    state.landing_dispatch[0] = (count + LANDING_WG - 1u) / LANDING_WG;
    state.landing_dispatch[1] = 1u;
    state.landing_dispatch[2] = 1u;
}
