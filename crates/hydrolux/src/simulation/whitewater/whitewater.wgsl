// White water (seed 003 §4.4 foam, §4.5 bubbles after Thürey et al. 2007,
// §4.6 splashes, §2.3 particle systems): a foam field that drifts and
// decays, and one particle pool shared by bubbles and spray, stepped
// entirely on the GPU (atomic counters, a dead-slot stack, indirect
// dispatch). One step is `begin` (indirect arguments), `hash_clear`,
// `hash_insert`, `merge_pick`, `merge_apply` (bubbles that touch merge),
// `update` (integrate; what lands feeds the foam), `plunge` (the volumetric
// liquid falling into the water: froth and a plume of bubbles), `foam_step` (drift,
// decay, sources; breaking crests emit particles), `emit` (the CPU's
// splashes). Twin: hydrolux_core::whitewater, line by line.
#import constants, surface, particle, ripple_texel, liquid_landing, hash

struct WhitewaterParams {
    // The foam grid: world cell of the window's low corner, cells per
    // side, 1 if it tiles the plane.
    grid_low: vec2<i32>,
    grid_cells: i32,
    grid_periodic: i32,
    // Cell (m), step dt (s), foam kept per step e^(−dt/τ), fold threshold J₀.
    cell: f32,
    dt: f32,
    foam_keep: f32,
    fold_threshold: f32,
    // Surface drift (m/s), foam per second of a fully breaking cell,
    // ripple-slope source gain.
    drift: vec2<f32>,
    fold_gain: f32,
    ripple_gain: f32,
    // Step number, splashes this step, pool capacity, which alive list is
    // read (0, 1).
    step: u32,
    splash_count: u32,
    capacity: u32,
    parity: u32,
    // Wind at the surface (m/s), floor depth (m), particle age cap (s).
    wind: vec2<f32>,
    floor_depth: f32,
    max_age: f32,
    // The particles' domain: x min, z min, x max, z max (m).
    domain: vec4<f32>,
    // Spray drop radius (m), crest spray and bubbles per m²·s, emission radius (m).
    drop_radius: f32,
    spray_rate: f32,
    bubble_rate: f32,
    emission_radius: f32,
    // Camera (x, z); what runs (bit 0 fold source, bit 1 ripple source, bit 2 particles).
    camera: vec2<f32>,
    run: u32,
    // Clock steps per white-water step: `plunge` takes the landings whose
    // clock step over this is `step`.
    landing_stride: u32,
    // Bases in `atomics`: deposits, gained, hash heads; the hash's bucket mask.
    deposits_base: u32,
    gained_base: u32,
    heads_base: u32,
    bucket_mask: u32,
    // Volume (m³) of one of the liquid's particles (0: no liquid lands here).
    landing_volume: f32,
    // The bubbles' surface mobility: 1 clean fresh water, 0 sea water.
    bubble_mobility: f32,
    _pad2: u32,
    _pad3: u32,
}

struct Splash {
    position: vec3<f32>,
    radius: f32,
    velocity: vec3<f32>,
    speed: f32,
    spray: u32,
    bubbles: u32,
    foam: f32,
    // First particle of this splash among the step's emissions.
    first: u32,
}

// The step's parameters in a read-only storage buffer, not a uniform: they
// change every step (step number, splash count, list parity), and Mesa's
// lavapipe 22 compiles a new copy of a shader for each new value of the
// uniforms its branches read, keeping every copy (the memory test saw
// 0.13 MB a frame).
@group(0) @binding(0) var<storage, read> params: WhitewaterParams;
@group(0) @binding(1) var<storage, read> foam_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> foam_out: array<f32>;
// Cover per cell (x, `foam_cover`), for the surface's shading (mipmapped:
// the mips average cover, i.e. filter it statistically).
@group(0) @binding(3) var cover_out: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(4) var<storage, read> splashes: array<Splash>;
@group(0) @binding(5) var<storage, read_write> particles: array<Particle>;
// Every atomic, at the bases in `params` (`deposits_base`…): the counters (alive count
// of list 0 and list 1, free slots, emitted in total, lost), the foam left
// by particles this step per cell (in 1/DEPOSIT_SCALE of F), the volume
// merged into each slot this step, the merge hash's bucket heads.
@group(0) @binding(6) var<storage, read_write> atomics: array<atomic<u32>>;
// Every slot list, by capacity C: the two alive lists (0..2C), the free
// slots' stack (2C..3C), the merge hash's chains (3C..4C) and each
// bubble's merge pick (4C..5C).
@group(0) @binding(7) var<storage, read_write> slots: array<u32>;

const NONE: u32 = 0xffffffffu;
// The physics constants (G, WATER_NU, WATER_SIGMA_RHO, AIR_WATER_RATIO,
// DROP_DRAG, VOLUME_UNIT_M3, BURST_FOAM_PER_M3, SPRAY_FOAM, FOLD_RAMP,
// DEPOSIT_SCALE, FOAM_MAX, KICK_SCALE) come from hydrolux-core's whitewater module,
// written above this file by `source()`: one value for both twins.
// Merge buckets: cells of twice the largest entrained bubble radius.
const MERGE_CELL: f32 = 0.01;
// Lists in `slots`, in capacities.
const FREE: u32 = 2u;
const CHAIN: u32 = 3u;
const TARGET: u32 = 4u;


// Twin: hydrolux_core::whitewater::drag_balance_velocity (Mei, Klausner &
// Lawrence's clean bubble or Schiller & Naumann's rigid sphere).
fn drag_balance_velocity(r: f32, clean: bool) -> f32 {
    let weight = 8.0 / 3.0 * G * r;
    var v = min(2.0 * G * r * r / (9.0 * WATER_NU), 1.0);
    for (var k = 0u; k < RISE_STEPS; k++) {
        let re = max(2.0 * r * v / WATER_NU, 1e-6);
        var cd: f32;
        if (clean) {
            cd = 16.0 / re * (1.0 + 1.0 / (8.0 / re + 0.5 * (1.0 + 3.315 / sqrt(re))));
        } else {
            cd = 24.0 / re * (1.0 + 0.15 * pow(re, 0.687));
        }
        v = sqrt(weight / cd);
    }
    return v;
}

fn bubble_terminal_velocity(r0: f32, mobility: f32) -> f32 {
    let r = max(r0, 1e-6);
    let rigid = drag_balance_velocity(r, false);
    let clean = drag_balance_velocity(r, true);
    let viscous = rigid + (clean - rigid) * mobility;
    let d = 2.0 * r;
    let mendelson = sqrt(2.14 * WATER_SIGMA_RHO / d + 0.505 * G * d);
    return min(viscous, mendelson);
}

fn bubble_relaxation(r: f32, mobility: f32) -> f32 {
    return max(bubble_terminal_velocity(r, mobility) / (2.0 * G), 1e-4);
}

fn drop_drag(r: f32) -> f32 {
    return 3.0 * AIR_WATER_RATIO * DROP_DRAG / (8.0 * max(r, 1e-6));
}

fn bubble_radius(volume: u32) -> f32 {
    return pow(3.0 * f32(volume) * VOLUME_UNIT_M3 / (4.0 * PI), 1.0 / 3.0);
}

fn bubble_volume(r: f32) -> u32 {
    let v = 4.0 / 3.0 * PI * r * r * r / VOLUME_UNIT_M3;
    return u32(clamp(round(v), 1.0, 4294967040.0));
}

// Deane & Stokes (2002): r^(−3/2) below the Hinze scale, r^(−10/3) above.
fn sample_bubble_radius(u: f32) -> f32 {
    let r0 = 1.0e-4;
    let rh = 1.0e-3;
    let r1 = 5.0e-3;
    let a = -1.5;
    let b = -10.0 / 3.0;
    let n_small = (pow(rh, a + 1.0) - pow(r0, a + 1.0)) / (a + 1.0);
    let scale = pow(rh, a - b);
    let n_large = scale * (pow(r1, b + 1.0) - pow(rh, b + 1.0)) / (b + 1.0);
    let t = clamp(u, 0.0, 0.999999) * (n_small + n_large);
    if (t < n_small) {
        return pow(pow(r0, a + 1.0) + t * (a + 1.0), 1.0 / (a + 1.0));
    }
    let t2 = (t - n_small) / scale;
    return pow(pow(rh, b + 1.0) + t2 * (b + 1.0), 1.0 / (b + 1.0));
}

// ---------------------------------------------------------------- foam

fn cells() -> i32 {
    return params.grid_cells;
}

fn storage_index(i: i32, j: i32) -> u32 {
    let n = cells();
    return u32(((j % n) + n) % n * n + ((i % n) + n) % n);
}

fn inside(i: i32, j: i32) -> bool {
    let lo = params.grid_low;
    let n = cells();
    return params.grid_periodic == 1 || (i >= lo.x && i < lo.x + n && j >= lo.y && j < lo.y + n);
}

fn foam_at(i: i32, j: i32) -> f32 {
    if (!inside(i, j)) {
        return 0.0;
    }
    return foam_in[storage_index(i, j)];
}

fn foam_sample(x: f32, z: f32) -> f32 {
    let c = params.cell;
    let u = x / c - 0.5;
    let v = z / c - 0.5;
    let fi = floor(u);
    let fj = floor(v);
    let a = u - fi;
    let b = v - fj;
    let i = i32(fi);
    let j = i32(fj);
    let top = foam_at(i, j) * (1.0 - a) + foam_at(i + 1, j) * a;
    let bottom = foam_at(i, j + 1) * (1.0 - a) + foam_at(i + 1, j + 1) * a;
    return top * (1.0 - b) + bottom * b;
}

fn world_cell(k: u32) -> vec2<i32> {
    let n = cells();
    let s = vec2<i32>(i32(k) % n, i32(k) / n);
    let lo = params.grid_low;
    return lo + (((s - lo) % n) + n) % n;
}

fn cell_of(x: f32, z: f32) -> u32 {
    let c = params.cell;
    return storage_index(i32(floor(x / c)), i32(floor(z / c)));
}

fn deposit(x: f32, z: f32, foam: f32) {
    let c = params.cell;
    let i = i32(floor(x / c));
    let j = i32(floor(z / c));
    if (!inside(i, j)) {
        return;
    }
    // One deposit fills its cell at most (more runs off): the fixed-point
    // sum cannot wrap however many land in a cell in a step.
    let units = u32(round(min(foam / (c * c), FOAM_MAX) * DEPOSIT_SCALE));
    atomicAdd(&atomics[params.deposits_base + storage_index(i, j)], units);
}

// Take a free slot for a new particle, or NONE when the pool is full.
fn take_slot() -> u32 {
    let free = atomicSub(&atomics[COUNT_FREE], 1u);
    if (free == 0u || free > params.capacity) {
        atomicAdd(&atomics[COUNT_FREE], 1u);
        return NONE;
    }
    return slots[FREE * params.capacity + free - 1u];
}

fn out_list() -> u32 {
    return 1u - params.parity;
}

fn append_alive(slot: u32) {
    let o = out_list();
    let at = atomicAdd(&atomics[o], 1u);
    slots[o * params.capacity + at] = slot;
}

fn release(slot: u32) {
    particles[slot].kind = PARTICLE_DEAD;
    let at = atomicAdd(&atomics[COUNT_FREE], 1u);
    slots[FREE * params.capacity + at] = slot;
}

fn spawn(p: Particle) {
    let slot = take_slot();
    if (slot == NONE) {
        atomicAdd(&atomics[COUNT_LOST], 1u);
        return;
    }
    particles[slot] = p;
    atomicStore(&atomics[params.gained_base + slot], 0u);
    atomicAdd(&atomics[COUNT_EMITTED], 1u);
    append_alive(slot);
}

// The foam's sources at a cell centre (F per second), and particles born
// where crests break.
fn foam_source(k: u32, x: f32, z: f32) -> f32 {
    let run = params.run;
    if ((run & 3u) == 0u) {
        return 0.0;
    }
    // Prefiltered over the cell, as the calibration reads it: waves shorter
    // than a cell do not break a cell's worth of sea.
    let s = surface_sample_footprint(vec2<f32>(x, z), params.cell);
    var source = 0.0;
    if ((run & 1u) != 0u) {
        let fold = clamp((params.fold_threshold - surface_jacobian(s)) / FOLD_RAMP, 0.0, 1.0);
        source += params.fold_gain * fold;
        if ((run & 4u) != 0u && fold > 0.0) {
            emit_crest(k, vec2<f32>(x, z), s, fold);
        }
    }
    if ((run & 2u) != 0u) {
        // Interactive water steeper than ~0.3 curls and traps air; a hull's
        // hollow is no free surface and makes none.
        let r = ripples_sample(vec2<f32>(x, z));
        let free = 1.0 - r.w;
        source += params.ripple_gain * free * clamp((length(r.yz) - 0.3) / 0.3, 0.0, 1.0);
    }
    return source;
}

// Spray torn from a breaking crest and bubbles entrained under it, on the
// tile of the periodic window nearest the camera, within the emission radius.
fn emit_crest(k: u32, p: vec2<f32>, s: SurfaceSample, fold: f32) {
    let period = params.cell * f32(cells());
    var w = p + s.disp.xz;
    if (params.grid_periodic == 1) {
        w -= period * round((w - params.camera) / period);
    }
    if (distance(w, params.camera) > params.emission_radius) {
        return;
    }
    let area = params.cell * params.cell * params.dt * fold;
    let step = params.step;
    let spray = u32(params.spray_rate * area + random(step, k, 11u));
    let bubbles = u32(params.bubble_rate * area + random(step, k, 12u));
    let wind = params.wind;
    for (var m = 0u; m < min(spray + bubbles, 8u); m++) {
        let id = hash_u32(step ^ hash_u32(k * 16u + m)) | 0x80000000u;
        let r1 = random(step, id, 1u);
        let r2 = random(step, id, 2u);
        let r3 = random(step, id, 3u);
        let jitter = (vec2<f32>(r1, r2) - 0.5) * params.cell;
        var q = Particle(vec3<f32>(w.x + jitter.x, s.disp.y, w.y + jitter.y), 0.0, vec3<f32>(0.0), PARTICLE_BUBBLE, id, 0.0, 0u, 0u, vec3<f32>(0.0), 0u);
        if (m < spray) {
            q.kind = PARTICLE_SPRAY;
            q.radius = params.drop_radius;
            q.position.y += 0.05;
            // Torn off at the crest's speed, mostly with the wind.
            q.velocity = vec3<f32>(wind.x * (0.3 + 0.4 * r3), 1.0 + 2.5 * r3, wind.y * (0.3 + 0.4 * r3));
        } else {
            let r = sample_bubble_radius(r3);
            q.volume = bubble_volume(r);
            q.radius = bubble_radius(q.volume);
            q.position.y -= 0.05 + 0.5 * r1 * r2;
        }
        spawn(q);
    }
}

// The volumetric liquid's landings (liquid_landing.wgsl), read by `plunge`
// alone, which binds no surface: its group 1 is this log alone (a binding
// past the surface's, which the other kernels bind as group 1), so the
// stage holds eight storage buffers, WebGPU's default limit.
@group(1) @binding(15) var<storage, read> liquid: LandingLog;

// Air (m³) that `volume` of liquid plunging at `down_speed` carries under
// (twin: hydrolux_core::whitewater::entrained_air).
fn entrained_air(volume: f32, down_speed: f32) -> f32 {
    let v = clamp(down_speed, 0.0, 60.0);
    if (!(v > ENTRAINMENT_ONSET_SPEED)) {
        return 0.0;
    }
    let excess = 1.0 - ENTRAINMENT_ONSET_SPEED / v;
    return ENTRAINMENT_RATIO * excess * excess * volume;
}

// The liquid that landed in this step's clock steps: its entrained air
// surfaces as froth where it fell and shows as a plume of bubbles under
// it (twin: hydrolux_core::whitewater::Plunge). After `update`, so the
// bubbles join the list it writes; before `foam_step`, which takes the
// froth with the step's other deposits.
@compute @workgroup_size(64)
fn plunge(@builtin(global_invocation_id) gid: vec3<u32>) {
    let count = min(liquid.count, arrayLength(&liquid.landings));
    if (gid.x >= count) {
        return;
    }
    let l = liquid.landings[gid.x];
    if (l.step / params.landing_stride != params.step) {
        return;
    }
    let air = entrained_air(params.landing_volume, l.down_speed);
    if (air <= 0.0) {
        return;
    }
    let step = params.step;
    let id0 = hash_u32(bitcast<u32>(l.position.x) ^ hash_u32(bitcast<u32>(l.position.y) ^ hash_u32(l.step)));
    // The froth surfaces up to the plume's depth away, uniform in radius
    // (hydrolux-core `Plunge::froth_at`).
    let depth = PLUME_DEPTH_PER_SPEED * clamp(l.down_speed, 0.0, 60.0);
    let r = depth * random(step, id0, 21u);
    let angle = 6.2831855 * random(step, id0, 22u);
    deposit(l.position.x + r * cos(angle), l.position.y + r * sin(angle), air * BURST_FOAM_PER_M3);
    if ((params.run & 4u) == 0u) {
        return;
    }
    let bubbles = min(u32(air / PLUNGE_AIR_PER_BUBBLE + random(step, id0, 13u)), PLUNGE_MAX_BUBBLES);
    for (var m = 0u; m < bubbles; m++) {
        let id = hash_u32(id0 ^ (m * 0x9E3779B9u)) | 0x80000000u;
        let r1 = random(step, id, 1u);
        let r2 = random(step, id, 2u);
        let r3 = random(step, id, 3u);
        let r4 = random(step, id, 4u);
        var q = Particle(vec3<f32>(l.position.x + (r1 - 0.5) * depth, -0.01 - depth * r4, l.position.y + (r2 - 0.5) * depth), 0.0, vec3<f32>(0.0), PARTICLE_BUBBLE, id, 0.0, 0u, 0u, vec3<f32>(0.0), 0u);
        q.volume = bubble_volume(sample_bubble_radius(r3));
        q.radius = bubble_radius(q.volume);
        spawn(q);
    }
}

// How much of a cell holding foam F is white: a wide ramp about the
// whitecap level ln 2 at which the cover is calibrated against Monahan
// (hydrolux-core `WHITECAP_FOAM`): fresh foam (F ≳ 1.3) is a dense white
// sheet, decaying foam thins into lace (the water shader breaks the cover
// into patches by noise), and far away the cells' mean cover shows.
fn foam_cover(f: f32) -> f32 {
    return smoothstep(0.15, 1.3, f);
}

@compute @workgroup_size(64)
fn foam_step(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = u32(cells());
    let k = id.x;
    if (k >= n * n) {
        return;
    }
    let ij = world_cell(k);
    let c = params.cell;
    let dt = params.dt;
    let x = (f32(ij.x) + 0.5) * c;
    let z = (f32(ij.y) + 0.5) * c;
    let carried = foam_sample(x - params.drift.x * dt, z - params.drift.y * dt);
    var source = foam_source(k, x, z);
    for (var i = 0u; i < params.splash_count; i++) {
        let sp = splashes[i];
        let d = vec2<f32>(x, z) - sp.position.xz;
        let u = dot(d, d) / (sp.radius * sp.radius);
        source += sp.foam * max(1.0 - u, 0.0) / dt;
    }
    let landed = f32(atomicExchange(&atomics[params.deposits_base + k], 0u)) / DEPOSIT_SCALE;
    let f = min(carried * params.foam_keep + source * dt + landed, FOAM_MAX);
    foam_out[k] = f;
    let si = vec2<i32>(i32(k % n), i32(k / n));
    textureStore(cover_out, si, 0, vec4<f32>(foam_cover(f), 0.0, 0.0, 1.0));
}

// ---------------------------------------------------------------- particles

// The indirect arguments of this step's particle kernels, from the count
// of the list read; the list written starts empty.
@group(2) @binding(0) var<storage, read_write> args: array<u32>;

@compute @workgroup_size(1)
fn begin() {
    let count = atomicLoad(&atomics[params.parity]);
    atomicStore(&atomics[out_list()], 0u);
    args[0] = (count + 63u) / 64u;
    args[1] = 1u;
    args[2] = 1u;
}

// The interactive water's landing spray (simulation/ripples, `kicks`): the
// parcels' downward speeds summed per texel in fixed point, which the
// water's next step turns into a jump of its potential. Only `update`
// binds it (its layout's group 2 holds this one binding).
@group(2) @binding(1) var<storage, read_write> kicks: array<atomic<u32>>;

// The kicks' texel holding world point p, or −1 outside the interactive
// water. Twin: hydrolux-core waves::ripples::texel_of.
fn kick_texel(p: vec2<f32>) -> i32 {
    if (RIPPLES == RIPPLES_NONE) {
        return -1;
    }
    let cell = surface.ripple_cell;
    let n = i32(round(surface.ripple_side / cell));
    let origin = vec2<i32>(round(surface.ripple_window.xy / cell));
    return ripple_texel(p, cell, n, origin, RIPPLES == 1u);
}

// A spray parcel landing at p at `speed` m/s downwards (twin: RippleSim::land).
fn kick(p: vec2<f32>, speed: f32) {
    let t = kick_texel(p);
    if (t >= 0) {
        atomicAdd(&kicks[t], u32(round(clamp(speed, 0.0, 60.0) * KICK_SCALE)));
    }
}

// After the step: the draw's instance count (six vertices per particle).
@compute @workgroup_size(1)
fn finish() {
    args[4] = 6u;
    args[5] = atomicLoad(&atomics[out_list()]);
    args[6] = 0u;
    args[7] = 0u;
}

fn alive_slot(i: u32) -> u32 {
    return slots[params.parity * params.capacity + i];
}

fn alive_count() -> u32 {
    return atomicLoad(&atomics[params.parity]);
}

@compute @workgroup_size(64)
fn hash_clear(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x <= params.bucket_mask) {
        atomicStore(&atomics[params.heads_base + id.x], NONE);
    }
}

fn bucket(c: vec3<i32>) -> u32 {
    let h = hash_u32(u32(c.x) ^ hash_u32(u32(c.y) ^ hash_u32(u32(c.z))));
    return h & params.bucket_mask;
}

fn merge_cell(p: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(p / MERGE_CELL));
}

@compute @workgroup_size(64)
fn hash_insert(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= alive_count()) {
        return;
    }
    let slot = alive_slot(id.x);
    slots[TARGET * params.capacity + slot] = NONE;
    if (particles[slot].kind != PARTICLE_BUBBLE) {
        return;
    }
    slots[CHAIN * params.capacity + slot] =
        atomicExchange(&atomics[params.heads_base + bucket(merge_cell(particles[slot].position))], slot);
}

// Each bubble picks the touching bubble of smallest id below its own.
@compute @workgroup_size(64)
fn merge_pick(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= alive_count()) {
        return;
    }
    let slot = alive_slot(id.x);
    let a = particles[slot];
    if (a.kind != PARTICLE_BUBBLE) {
        return;
    }
    let home = merge_cell(a.position);
    var best = NONE;
    var best_id = a.id;
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let c = home + vec3<i32>(dx, dy, dz);
                var j = atomicLoad(&atomics[params.heads_base + bucket(c)]);
                for (var guard = 0u; j != NONE && guard < 64u; guard++) {
                    let b = particles[j];
                    let d = a.position - b.position;
                    let r = a.radius + b.radius;
                    if (j != slot && all(merge_cell(b.position) == c) && b.id < best_id && dot(d, d) < r * r) {
                        best = j;
                        best_id = b.id;
                    }
                    j = slots[CHAIN * params.capacity + j];
                }
            }
        }
    }
    slots[TARGET * params.capacity + slot] = best;
}

// A bubble merges into its pick unless that one merges too; volume moves whole.
@compute @workgroup_size(64)
fn merge_apply(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= alive_count()) {
        return;
    }
    let slot = alive_slot(id.x);
    let t = slots[TARGET * params.capacity + slot];
    if (t != NONE && slots[TARGET * params.capacity + t] == NONE) {
        atomicAdd(&atomics[params.gained_base + t], particles[slot].volume);
        particles[slot].kind = PARTICLE_DEAD;
    }
}

// The water's height under world (x, z): the surface at the point whose
// displacement lands there (one fixed-point step undoes the choppy shift).
fn water_height(x: f32, z: f32) -> f32 {
    let w = vec2<f32>(x, z);
    let s0 = surface_sample_footprint(w, 0.0);
    return surface_sample_footprint(w - s0.disp.xz, 0.0).disp.y;
}

// Where the surface point above a particle at p is displaced to, seen
// from p's depth: prefiltered over MOTION_FOOTPRINT_PER_DEPTH times it
// (the water moves with the longer waves only, deeper down).
fn water_displacement(p: vec3<f32>) -> vec3<f32> {
    return surface_sample_footprint(p.xz, MOTION_FOOTPRINT_PER_DEPTH * max(-p.y, 0.0)).disp;
}

@compute @workgroup_size(64)
fn update(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= alive_count()) {
        return;
    }
    let slot = alive_slot(id.x);
    var p = particles[slot];
    if (p.kind == PARTICLE_DEAD) {
        release(slot);
        return;
    }
    let dt = params.dt;
    let newborn = p.age == 0.0;
    p.age += dt;
    if (p.kind == PARTICLE_BUBBLE) {
        let more = atomicExchange(&atomics[params.gained_base + slot], 0u);
        if (more > 0u) {
            p.volume = p.volume + min(more, 0xffffffffu - p.volume);
            p.radius = bubble_radius(p.volume);
        }
        // The water's motion here: how far the surface above moved since
        // the last step (nothing known yet in a bubble's first step).
        var water = vec3<f32>(0.0);
        if (!newborn) {
            water = (water_displacement(p.position) - p.carried) / dt;
        }
        let rise = bubble_terminal_velocity(p.radius, params.bubble_mobility);
        let keep = exp(-dt / bubble_relaxation(p.radius, params.bubble_mobility));
        let goal = vec3<f32>(water.x, water.y + rise, water.z);
        p.velocity = goal + (p.velocity - goal) * keep;
    } else {
        let wind = params.wind;
        let k = drop_drag(p.radius);
        let rel = vec3<f32>(p.velocity.x - wind.x, p.velocity.y, p.velocity.z - wind.y);
        let speed = sqrt(rel.x * rel.x + rel.y * rel.y + rel.z * rel.z);
        let damp = 1.0 / (1.0 + k * speed * dt);
        p.velocity = vec3<f32>(wind.x + rel.x * damp, (rel.y - G * dt) * damp, wind.y + rel.z * damp);
    }
    p.position += p.velocity * dt;
    let finite = all(abs(p.position) < vec3<f32>(1e30)) && all(abs(p.velocity) < vec3<f32>(1e30));
    let d = params.domain;
    let inside = finite && p.position.x >= d.x && p.position.x <= d.z && p.position.z >= d.y
        && p.position.z <= d.w && p.age <= params.max_age;
    if (!inside) {
        release(slot);
        return;
    }
    let h = water_height(p.position.x, p.position.z);
    if (p.kind == PARTICLE_BUBBLE) {
        p.position.y = max(p.position.y, -params.floor_depth + p.radius);
        if (p.position.y >= h) {
            deposit(p.position.x, p.position.z, f32(p.volume) * VOLUME_UNIT_M3 * BURST_FOAM_PER_M3);
            release(slot);
            return;
        }
        p.carried = water_displacement(p.position);
    } else if (p.position.y <= h && p.velocity.y < 0.0) {
        deposit(p.position.x, p.position.z, SPRAY_FOAM);
        kick(p.position.xz, -p.velocity.y);
        release(slot);
        return;
    }
    particles[slot] = p;
    append_alive(slot);
}

// The CPU's splashes: one thread per particle (splash i's particles are
// `first` to `first + spray + bubbles`).
@compute @workgroup_size(64)
fn emit(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.splash_count;
    if (n == 0u) {
        return;
    }
    let last = splashes[n - 1u];
    if (id.x >= last.first + last.spray + last.bubbles) {
        return;
    }
    var i = 0u;
    while (i + 1u < n && splashes[i + 1u].first <= id.x) {
        i++;
    }
    let s = splashes[i];
    let k = id.x - s.first;
    let step = params.step;
    let pid = step * 1048576u + i * 1024u + k;
    let r1 = random(step, pid, 1u);
    let r2 = random(step, pid, 2u);
    let r3 = random(step, pid, 3u);
    let a = r1 * TAU;
    let d = s.radius * sqrt(r2);
    let ca = cos(a);
    let sa = sin(a);
    var p = Particle(vec3<f32>(s.position.x + d * ca, s.position.y, s.position.z + d * sa), 0.0, vec3<f32>(0.0), PARTICLE_BUBBLE, pid, 0.0, 0u, 0u, vec3<f32>(0.0), 0u);
    if (k < s.spray) {
        let up = s.speed * (0.6 + 0.4 * r3);
        let out = s.speed * 0.5 * r2;
        p.kind = PARTICLE_SPRAY;
        p.radius = params.drop_radius;
        p.position.y += 0.01;
        p.velocity = vec3<f32>(s.velocity.x * 0.5 + out * ca, up, s.velocity.z * 0.5 + out * sa);
    } else {
        let r = sample_bubble_radius(r3);
        p.volume = bubble_volume(r);
        p.radius = bubble_radius(p.volume);
        p.position.y -= 0.02 + 0.3 * s.radius * r3;
        p.velocity = vec3<f32>(s.velocity.x * 0.3, 0.0, s.velocity.z * 0.3);
    }
    spawn(p);
}
