// Interactive water (seed 003 §2.4; Tessendorf's eWave): one step is
// `disturb` (drops, the sponge, h + iφ conjugated into `spatial`), the
// FFT of `spatial` (ocean/fft.wgsl: an inverse transform of the conjugate
// is the conjugate of the forward one), `spectral` (each wave's exact
// rotation at both depth levels), the inverse FFT of `spectral`. `publish`
// writes the heights and slopes the surface is drawn with. Twin:
// hydrolux_core::waves::ripples.
#import constants, complex, ray_primitive, liquid_landing, ripple_texel

struct RippleParams {
    // Domain cells N, FFT size F, edges (0 walls, 1 open, 2 periodic), sponge cells.
    cells: u32,
    fft_size: u32,
    edges: u32,
    sponge_cells: u32,
    // World cell of the window's first cell; first drop of this step, drop count.
    window_origin: vec2<i32>,
    first_drop: i32,
    drop_count: i32,
    // Cell size (m), step (s), the two depth levels (m).
    cell: f32,
    dt: f32,
    depths: vec2<f32>,
    // g (m/s²), σ/ρ (m³/s²), ν (m²/s), extra damping (1/s).
    gravity: f32,
    tension: f32,
    viscosity: f32,
    damping: f32,
    // The sponge's peak damping rate (1/s); Δφ (m²/s) per unit of landing
    // spray (hydrolux-core coupling::kick_per_unit); first body move of this
    // step, their count.
    sponge_rate: f32,
    kick_per_unit: f32,
    first_move: i32,
    move_count: i32,
    // The volumetric liquid landing here (liquid_landing.wgsl): this step's
    // index, clock steps per step, a particle's water (m³), and the copies
    // of each domain cell in the FFT grid (4 between walls, else 1).
    landing_step: u32,
    landing_stride: u32,
    landing_volume: f32,
    landing_images: f32,
}

// A body in the water during one step (twin: waves::ripples::BodyMove):
// its shape (three sizes, code BODY_*), the pose whose hollow it held
// before the step (where it was, or was lifted out of: BodyMove::held) and
// its pose after, as position and rotation (quaternion x, y, z, w).
struct BodyMove {
    shape: vec4<f32>,
    held_position: vec4<f32>,
    held_rotation: vec4<f32>,
    after_position: vec4<f32>,
    after_rotation: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: RippleParams;
// The FFT grid, row = z: what is transformed forward (xy: conj(h + iφ)).
@group(0) @binding(1) var<storage, read_write> spatial: array<vec4<f32>>;
// The FFT grid: the spectrum stepped at both depth levels, then (after the
// inverse FFT) the state per level: (h₀, φ₀, h₁, φ₁).
@group(0) @binding(2) var<storage, read_write> spectral: array<vec4<f32>>;
// Depth (m) per domain cell, row = z.
@group(0) @binding(3) var<storage, read> depth: array<f32>;
// Drops of this batch: x, z, radius, crater depth (m).
@group(0) @binding(4) var<storage, read> drops: array<vec4<f32>>;
// Heights per domain cell (row = z), for readbacks.
@group(0) @binding(5) var<storage, read_write> heights: array<f32>;
// h, ∂h/∂x, ∂h/∂z per texel (texel = grid cell of the domain's N × N).
@group(0) @binding(6) var surface_out: texture_storage_2d<rgba16float, write>;
// Bodies moving through the water in this batch's steps.
@group(0) @binding(7) var<storage, read> moves: array<BodyMove>;
// Spray landed since the last step, per texel (row = z): the parcels'
// downward speeds summed in fixed point by the white water's `update`;
// used up by the step (cleared in `spectral_step`, after `disturb` read it).
@group(0) @binding(8) var<storage, read_write> kicks: array<atomic<u32>>;
// The hulls' ledger: the water they pushed out in this step (fixed point,
// PUSHED_UNITS_PER_M per metre summed over the grid: `disturb` and
// `land_liquid` add, `spectral_step` adds it to the level and clears it),
// and the free water's mean height (m) their heads are measured from
// (`free_level` writes it before each step with bodies).
struct HullLedger {
    pushed: atomic<i32>,
    free_level: f32,
}
@group(0) @binding(9) var<storage, read_write> ledger: HullLedger;
// The liquid's landings log (liquid_landing.wgsl; its state buffer read
// here past the solve state). Only `land_liquid` binds it, in a layout of
// its own with bindings 0, 8 and 9 of group 0.
@group(1) @binding(0) var<storage, read> liquid: LandingLog;


// The vertical extent (y0, y1) of a body over the column at world (x, z);
// y0 > y1 when the column misses it. Twin: bodies::body_column.
fn body_column(shape: vec4<f32>, position: vec3<f32>, rotation: vec4<f32>, xz: vec2<f32>) -> vec2<f32> {
    let code = u32(shape.w);
    var reach = shape.x;
    if (code == PRIMITIVE_BOX) {
        reach = length(shape.xyz);
    } else if (code != PRIMITIVE_SPHERE) {
        reach = length(shape.xy);
    }
    let top = position.y + reach + 1.0;
    let inv = vec4<f32>(-rotation.xyz, rotation.w);
    let o = quat_rotate(inv, vec3<f32>(xz.x, top, xz.y) - position);
    let d = quat_rotate(inv, vec3<f32>(0.0, -1.0, 0.0));
    let t = ray_primitive(code, shape.xyz, o, d);
    if (t.x > t.y) {
        return vec2<f32>(1.0, -1.0);
    }
    return vec2<f32>(top - t.y, top - t.x);
}

// Depth (m) a body reaches below the mean level at world point w after its
// move, where it pierces the surface: the head of the pressure it holds the
// surface down with (a column wholly under water holds nothing down). Twin:
// BodyMove::depth.
fn body_depth(m: BodyMove, w: vec2<f32>) -> f32 {
    let c = body_column(m.shape, m.after_position.xyz, m.after_rotation, w);
    if (c.x > c.y || c.y <= 0.0) {
        return 0.0;
    }
    return max(-c.x, 0.0);
}

// Depth (m) the body reached below the mean level at world point w before
// the step (at its held pose), where it pierced the surface. Twin:
// BodyMove::depth_before.
fn held_depth(m: BodyMove, w: vec2<f32>) -> f32 {
    let c = body_column(m.shape, m.held_position.xyz, m.held_rotation, w);
    if (c.x > c.y || c.y <= 0.0) {
        return 0.0;
    }
    return max(-c.x, 0.0);
}

// How deep the bodies' hulls hold the water down at world point w this
// step (0 where none pierces the surface). Twin: `held_down` of
// RippleSim::step_with.
fn hull_depth(w: vec2<f32>) -> f32 {
    var d = 0.0;
    for (var b = 0; b < params.move_count; b++) {
        d += body_depth(moves[params.first_move + b], w);
    }
    return d;
}

// Whether a body's hull covers world point w this step (it pierces the
// surface there): no free surface, so free water does not break into it,
// `publish` gives the water beside it the free surface's slopes, and white
// water makes no foam of its hollow.
fn hull_covers(w: vec2<f32>) -> bool {
    for (var b = 0; b < params.move_count; b++) {
        if (body_depth(moves[params.first_move + b], w) > 0.0) {
            return true;
        }
    }
    return false;
}

// Where a body was lifted out of the water and no hull holds it now, the
// grid index whose velocity potential the water of its hollow at world
// point w takes: the free water's one cell past the hollow's edge, along
// the line from the body's centre (-1 elsewhere). Twin:
// ripples::released_source.
fn released_source(w: vec2<f32>) -> i32 {
    // The lifted bodies first: every cell runs this every step, and
    // almost always none was lifted.
    var lifted = -1;
    for (var b = 0; b < params.move_count; b++) {
        let m = moves[params.first_move + b];
        if (m.held_position.w > 0.5 && held_depth(m, w) > 0.0) {
            lifted = params.first_move + b;
            break;
        }
    }
    if (lifted < 0 || hull_covers(w)) {
        return -1;
    }
    let m = moves[lifted];
    let r = w - m.held_position.xz;
    let len = length(r);
    let dir = select(vec2<f32>(1.0, 0.0), r / len, len > 1e-9);
    var edge = -1;
    for (var k = 1; k <= RELEASE_REACH_CELLS; k++) {
        let p = w + dir * f32(k) * params.cell;
        if (held_depth(m, p) <= 0.0 && !hull_covers(p)) {
            edge = k;
            break;
        }
    }
    if (edge < 0) {
        return -1;
    }
    let q = w + dir * f32(edge + 1) * params.cell;
    let world_cell = vec2<i32>(floor(q / params.cell));
    let n = i32(params.cells);
    let f = i32(params.fft_size);
    var g = ((world_cell % f) + f) % f;
    if (params.edges == EDGES_WALLS) {
        g = clamp(world_cell - params.window_origin, vec2<i32>(0), vec2<i32>(n - 1));
    }
    return g.y * f + g.x;
}

// The domain cell a grid cell holds: walls mirror (cell 2N−1−i holds i);
// open and periodic grids hold the world cell ≡ g (mod N) in the window.
fn domain_cell(g: vec2<u32>) -> vec2<u32> {
    let n = params.cells;
    if (params.edges == EDGES_WALLS) {
        return select(vec2<u32>(2u * n - 1u) - g, g, g < vec2<u32>(n));
    }
    let ni = i32(n);
    return vec2<u32>(((vec2<i32>(g) - params.window_origin) % ni + ni) % ni);
}

// The texel (of the surface's texture and of `kicks`) holding grid cell
// g's state: its domain cell between walls, itself in open water (the
// texture tiles the plane). Twin: ripples::grid_cell of domain_cell.
fn texel_of(g: vec2<u32>) -> u32 {
    var t = g;
    if (params.edges == EDGES_WALLS) {
        t = domain_cell(g);
    }
    return t.y * params.cells + t.x;
}

fn world_of(d: vec2<u32>) -> vec2<f32> {
    return (vec2<f32>(params.window_origin + vec2<i32>(d)) + 0.5) * params.cell;
}

fn grid_index(g: vec2<u32>) -> u32 {
    return g.y * params.fft_size + g.x;
}

// Blend weight of depth level 1, linear in √d.
fn depth_weight(d: f32) -> f32 {
    let a = sqrt(params.depths.x);
    let b = sqrt(params.depths.y);
    if (b > a) {
        return clamp((sqrt(max(d, 0.0)) - a) / (b - a), 0.0, 1.0);
    }
    return 0.0;
}

// Whether grid cell g holds water (else an obstacle or land stands there,
// and the water is held at rest). Twin: ripples::wet.
fn wet(g: vec2<u32>) -> bool {
    let d = domain_cell(g);
    return depth[d.y * params.cells + d.x] > 0.0;
}

// (h, φ) of grid cell g: its two depth levels blended by its own depth;
// none in a dry cell.
fn state(g: vec2<u32>) -> vec2<f32> {
    let d = domain_cell(g);
    let v = spectral[grid_index(g)];
    let here = depth[d.y * params.cells + d.x];
    return select(vec2<f32>(0.0), mix(v.xy, v.zw, depth_weight(here)), here > 0.0);
}

// The crater of drop (x, z, R, s) at world point w, with its mirror images
// in walls (volume-neutral next to a wall).
fn drop_height(drop: vec4<f32>, w: vec2<f32>) -> f32 {
    var images = 1;
    if (params.edges == EDGES_WALLS) {
        images = 3;
    }
    let lo = vec2<f32>(params.window_origin) * params.cell;
    let hi = lo + f32(params.cells) * params.cell;
    var dh = 0.0;
    for (var ix = 0; ix < images; ix++) {
        for (var iz = 0; iz < images; iz++) {
            var c = drop.xy;
            if (ix == 1) { c.x = 2.0 * lo.x - c.x; }
            if (ix == 2) { c.x = 2.0 * hi.x - c.x; }
            if (iz == 1) { c.y = 2.0 * lo.y - c.y; }
            if (iz == 2) { c.y = 2.0 * hi.y - c.y; }
            let r = w - c;
            let u = dot(r, r) / (drop.z * drop.z);
            if (u <= 16.0) {
                dh -= drop.w * (1.0 - u) * exp(-u);
            }
        }
    }
    return dh;
}

// Per-step damping of the sponge ring of an open domain.
fn sponge(d: vec2<u32>) -> f32 {
    let width = params.sponge_cells;
    if (width == 0u) {
        return 1.0;
    }
    let n = params.cells;
    let e = min(min(d.x, n - 1u - d.x), min(d.y, n - 1u - d.y));
    if (e >= width) {
        return 1.0;
    }
    if (e == 0u) {
        return 0.0;
    }
    let x = f32(width - e) / f32(width);
    return exp(-params.sponge_rate * x * x * params.dt);
}

var<workgroup> free_sums: array<vec2<f32>, 256>;

// The mean height of the free water (no hull over it) before the step,
// into ledger.free_level: one workgroup, each thread summing a stride of
// the domain's cells, then a tree (the same order every time). Twin:
// ripples::free_level.
@compute @workgroup_size(256, 1, 1)
fn free_level(@builtin(local_invocation_index) lid: u32) {
    let n = params.cells;
    var sum = vec2<f32>(0.0);
    for (var c = lid; c < n * n; c += 256u) {
        let g = vec2<u32>(c % n, c / n);
        if (wet(g) && !hull_covers(world_of(domain_cell(g)))) {
            sum += vec2<f32>(state(g).x, 1.0);
        }
    }
    free_sums[lid] = sum;
    workgroupBarrier();
    for (var half = 128u; half > 0u; half >>= 1u) {
        if (lid < half) {
            free_sums[lid] += free_sums[lid + half];
        }
        workgroupBarrier();
    }
    if (lid == 0u) {
        let total = free_sums[0];
        ledger.free_level = select(0.0, total.x / total.y, total.y > 0.0);
    }
}

@compute @workgroup_size(8, 8, 1)
fn disturb(@builtin(global_invocation_id) id: vec3<u32>) {
    let f = params.fft_size;
    if (id.x >= f || id.y >= f) {
        return;
    }
    let g = id.xy;
    let d = domain_cell(g);
    let w = world_of(d);
    var s = state(g);
    // Breaking: the water trades height with neighbours it stands steeper
    // than the limiting Stokes wave against (twin: waves::ripples::breaking;
    // BREAKING_SLOPE and BREAKING_RELAX are the twin's, set by ripples/mod.rs).
    let most = BREAKING_SLOPE * params.cell;
    var give = 0.0;
    let around = array<vec2<u32>, 4>(
        vec2<u32>((g.x + 1u) % f, g.y),
        vec2<u32>((g.x + f - 1u) % f, g.y),
        vec2<u32>(g.x, (g.y + 1u) % f),
        vec2<u32>(g.x, (g.y + f - 1u) % f),
    );
    // A hull holds its hollow down: free water does not pour into it (the
    // two fought every step and kept the ring about a ball steep), though a
    // hollow rebounding above the water around still breaks, and so does
    // water pushed below the hull's bottom (the contact holds it, not the
    // pressure head's spring). Twin: the `held` pairs of RippleSim::step_with.
    let here_down = hull_depth(w);
    let h_before = s.x;
    let here = here_down > 0.0;
    for (var j = 0; j < 4; j++) {
        // A dry neighbour is a wall: no water to trade with.
        if (!wet(around[j])) {
            continue;
        }
        let h_n = state(around[j]).x;
        let there_down = hull_depth(world_of(domain_cell(around[j])));
        let there = there_down > 0.0;
        let held = here != there
            && select(s.x < h_n && s.x >= -here_down - HULL_GAP, h_n < s.x && h_n >= -there_down - HULL_GAP, there);
        if (held) {
            continue;
        }
        let dh = s.x - h_n;
        give += sign(dh) * max(abs(dh) - most, 0.0);
    }
    s.x -= BREAKING_RELAX * give;
    // ∂φ/∂t = −g·(h + d): the bodies' pressure heads, one step's worth,
    // where the water touches the hulls (water that fell away below a
    // hull's bottom feels no push from it).
    // The head is that of the hull's bottom below the free water around
    // (ledger.free_level), not below the mean level. Twin: free_level.
    if (here && h_before >= -here_down - HULL_GAP) {
        s.y -= params.gravity * (here_down + ledger.free_level) * params.dt;
    }
    let first = params.first_drop;
    for (var i = 0; i < params.drop_count; i++) {
        s.x += drop_height(drops[first + i], w);
    }
    // Landing spray: an impulsive pressure P changes φ by −P/ρ.
    s.y -= f32(atomicLoad(&kicks[texel_of(g)])) * params.kick_per_unit;
    // Dry cells hold no water: what the step moved into them is taken out,
    // so waves reflect from them.
    s *= select(0.0, sponge(d), wet(g));
    // Contact: water touching a hull follows it up, to its new bottom or
    // the mean level; water that rose past a hull's bottom is put back
    // there. What the hulls let in or push out comes from or joins the
    // level (`spectral_step`). Twin: the contact of RippleSim::step_with.
    var was = 0.0;
    for (var b = 0; b < params.move_count; b++) {
        was += held_depth(moves[params.first_move + b], w);
    }
    let rise = -here_down - s.x;
    if (was > here_down && h_before >= -was - HULL_GAP && rise > 0.0) {
        let units = round(rise * PUSHED_UNITS_PER_M);
        s.x += units / PUSHED_UNITS_PER_M;
        atomicSub(&ledger.pushed, i32(units));
    }
    let excess = s.x + here_down;
    if (here && excess > 0.0) {
        let units = round(excess * PUSHED_UNITS_PER_M);
        s.x -= units / PUSHED_UNITS_PER_M;
        atomicAdd(&ledger.pushed, i32(units));
    }
    // A lifted body's hollow takes the free water's φ from beside it.
    let source = released_source(w);
    if (source >= 0) {
        s.y = state(vec2<u32>(u32(source) % f, u32(source) / f)).y;
    }
    spatial[grid_index(g)] = vec4<f32>(s.x, -s.y, 0.0, 0.0);
}

// One step's rotation of wave number k at depth h: (decay, cos, s_h, s_φ)
// with h' = e·(c·h + s_h·φ), φ' = e·(c·φ − s_φ·h).
fn rotation(k: f32, h: f32) -> vec4<f32> {
    if (k == 0.0) {
        return vec4<f32>(1.0, 1.0, 0.0, 0.0);
    }
    let dt = params.dt;
    let kk = k * tanh(min(k * h, 20.0));
    let bb = params.gravity + params.tension * k * k;
    let wt = sqrt(kk * bb) * dt;
    var sinc = 1.0;
    if (wt > 1e-4) {
        sinc = sin(wt) / wt;
    }
    let decay = exp(-(2.0 * params.viscosity * k * k + params.damping) * dt);
    return vec4<f32>(decay, cos(wt), kk * dt * sinc, bb * dt * sinc);
}

@compute @workgroup_size(8, 8, 1)
fn spectral_step(@builtin(global_invocation_id) id: vec3<u32>) {
    let f = params.fft_size;
    if (id.x >= f || id.y >= f) {
        return;
    }
    let i = id.y * f + id.x;
    let n = params.cells;
    if (id.x < n && id.y < n) {
        atomicStore(&kicks[id.y * n + id.x], 0u);
    }
    let m = ((f - id.y) % f) * f + (f - id.x) % f;
    // spatial holds conj(Z): Z(k) = conj(a), conj(Z(−k)) = b.
    let a = spatial[i].xy;
    let b = spatial[m].xy;
    let zk = vec2<f32>(a.x, -a.y);
    var hk = (zk + b) * 0.5;
    let pk = cmul(zk - b, vec2<f32>(0.0, -0.5));
    let half = f / 2u;
    let signed = vec2<f32>(
        select(f32(id.x), f32(id.x) - f32(f), id.x > half),
        select(f32(id.y), f32(id.y) - f32(f), id.y > half),
    );
    let k = length(signed) * TAU / (f32(f) * params.cell);
    let norm = 1.0 / (f32(f) * f32(f));
    var out = vec4<f32>(0.0);
    if (i == 0u) {
        // The water hulls pushed out raises the level (the sum of h over
        // the grid is the zero wave number's amplitude).
        hk.x += f32(atomicExchange(&ledger.pushed, 0)) / PUSHED_UNITS_PER_M;
    }
    // Open water has no level of its own: what the window gains or loses
    // flows away to the ocean around it.
    if (k == 0.0 && params.edges == 1u) {
        spectral[i] = out;
        return;
    }
    for (var l = 0u; l < 2u; l++) {
        let r = rotation(k, params.depths[l]);
        let h1 = (hk * r.y + pk * r.z) * r.x;
        let p1 = (pk * r.y - hk * r.w) * r.x;
        let z = (h1 + cmul_i(p1)) * norm;
        if (l == 0u) {
            out = vec4<f32>(z, out.zw);
        } else {
            out = vec4<f32>(out.xy, z);
        }
    }
    spectral[i] = out;
}

// The height of neighbour g_n for the slopes of a cell at height h: its
// own, unless a hull covers it while the cell is free water.
fn free_height(g_n: vec2<u32>, h: f32, covered: bool) -> f32 {
    if (!covered && hull_covers(world_of(domain_cell(g_n)))) {
        return h;
    }
    return state(g_n).x;
}

// Per texel of the domain's N × N: heights for readbacks and the surface's
// texture (h and central-difference slopes).
@compute @workgroup_size(8, 8, 1)
fn publish(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.cells;
    let f = params.fft_size;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let g = id.xy;
    let d = domain_cell(g);
    let h = state(g).x;
    // The free surface's slopes: a neighbour under a hull (its hollow) is
    // taken at this cell's height, so the water beside a hull does not
    // slope down into the hollow. w = 1 where a hull covers the cell (white
    // water makes no foam of its slopes there, and its slopes are 0).
    let covered = hull_covers(world_of(d));
    let east = free_height(vec2<u32>((g.x + 1u) % f, g.y), h, covered);
    let west = free_height(vec2<u32>((g.x + f - 1u) % f, g.y), h, covered);
    let north = free_height(vec2<u32>(g.x, (g.y + 1u) % f), h, covered);
    let south = free_height(vec2<u32>(g.x, (g.y + f - 1u) % f), h, covered);
    var slope = vec2<f32>(east - west, north - south) / (2.0 * params.cell);
    if (covered) {
        // The hollow's walls are the hull's: hidden, and no free surface.
        slope = vec2<f32>(0.0);
    }
    heights[d.y * n + d.x] = h;
    textureStore(surface_out, vec2<i32>(g), vec4<f32>(h, slope, select(0.0, 1.0, covered)));
}


// The share of a plunge's impulse a cell takes before normalising (twin:
// hydrolux_core::coupling::plunge_weight).
fn plunge_weight(r2: f32, radius: f32) -> f32 {
    let u = 1.0 - r2 / (radius * radius);
    return select(0.0, u * u, u > 0.0);
}

// Before `disturb`: the liquid that landed in this step's clock steps
// becomes this water, its momentum a kick (Δφ = −V·v/A), its volume the
// level's. Twin: RippleSim::land_liquid.
@compute @workgroup_size(64)
fn land_liquid(@builtin(global_invocation_id) id: vec3<u32>) {
    let count = min(liquid.count, arrayLength(&liquid.landings));
    if (id.x >= count) {
        return;
    }
    let l = liquid.landings[id.x];
    if (l.step / params.landing_stride != params.landing_step) {
        return;
    }
    let walls = params.edges == EDGES_WALLS;
    let n = i32(params.cells);
    let cell = params.cell;
    if (ripple_texel(l.position, cell, n, params.window_origin, walls) < 0) {
        return;
    }
    let area = cell * cell;
    let v = params.landing_volume;
    if (params.kick_per_unit > 0.0) {
        // Over the plume's width: the cells whose centres it covers, in the
        // domain, their weights normalised there.
        let speed = clamp(l.down_speed, 0.0, 60.0);
        let units = v * speed / area / params.kick_per_unit;
        let radius = max(PLUME_DEPTH_PER_SPEED * speed, cell);
        let reach = min(i32(ceil(radius / cell)), PLUNGE_SPREAD_CELLS);
        let c = floor(l.position / cell);
        var sum = 0.0;
        for (var sweep = 0; sweep < 2; sweep++) {
            for (var dj = -reach; dj <= reach; dj++) {
                for (var di = -reach; di <= reach; di++) {
                    let centre = (c + vec2<f32>(f32(di), f32(dj)) + 0.5) * cell;
                    let d = centre - l.position;
                    let w = plunge_weight(dot(d, d), radius);
                    let t = ripple_texel(centre, cell, n, params.window_origin, walls);
                    if (w <= 0.0 || t < 0) {
                        continue;
                    }
                    if (sweep == 0) {
                        sum += w;
                    } else {
                        atomicAdd(&kicks[t], u32(round(units * w / sum)));
                    }
                }
            }
        }
    }
    atomicAdd(&ledger.pushed, i32(round(v / area * params.landing_images * PUSHED_UNITS_PER_M)));
}
