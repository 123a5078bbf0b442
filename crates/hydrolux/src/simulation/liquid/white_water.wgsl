// The liquid's white water (hydrolux_core::fluid::white_water, its CPU
// twin, formula for formula; Ihmsen, Akinci, Akinci & Teschner 2012 on the
// MAC grid): after a step's `advance`, `white_water_move` carries the pool
// (each slot classified by the fill around it: spray, foam or bubble) and
// `white_water_shed` lets each breaking liquid particle shed into its own
// empty slot. This file continues liquid.wgsl (its bindings and grid
// helpers); the constants SLOTS_PER_PARTICLE, SPRAY_FILL, BUBBLE_FILL,
// ENTRAINMENT_SPEED_*, TRAPPED_AIR_SHEAR_*, CREST_SPEED_*, CREST_ALIGNMENT and the
// salts are the core's, written above it by `source()`.
#import modes, hash, liquid_diffuse

// In group 1 beside the solve's arguments (its kernels bind one or the
// other: a stage binds at most 8 storage buffers, WebGPU's limit).
@group(1) @binding(1) var<storage, read_write> pool: array<Diffuse>;

fn ramp(value: f32, lo: f32, hi: f32) -> f32 {
    return clamp((min(value, hi) - min(value, lo)) / (hi - lo), 0.0, 1.0);
}

fn classify(fill: f32) -> u32 {
    if (fill < SPRAY_FILL) {
        return PARTICLE_SPRAY;
    }
    if (fill > BUBBLE_FILL) {
        return PARTICLE_BUBBLE;
    }
    return PARTICLE_FOAM;
}

// How full (0–1) the 3×3×3 cells around p are (particles over what they
// hold, solids left out), and the outward normal (unnormalised).
struct Fill {
    fill: f32,
    outward: vec3<f32>,
}

fn fill_at(p: vec3<f32>) -> Fill {
    let c = vec3<i32>(floor((p - params.origin) / params.h));
    var sum = 0.0;
    var room = 0.0;
    var outward = vec3<f32>(0.0);
    for (var k = 0; k < 27; k++) {
        let d = vec3<i32>(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
        let at = c + d;
        if (is_solid(at)) {
            continue;
        }
        var n = 0.0;
        if (inside(at)) {
            n = f32(atomicLoad(&accum[2u * params.face_count + cell_index(vec3<u32>(at))]));
        }
        sum += n;
        room += params.particles_per_cell;
        outward -= n * vec3<f32>(d);
    }
    var f: Fill;
    f.fill = select(1.0, min(sum / room, 1.0), room > 0.0);
    f.outward = outward;
    return f;
}

// |∇×u| at p by central differences a cell apart.
fn vorticity_at(p: vec3<f32>) -> f32 {
    let h = params.h;
    let dx = (velocity_at(p + vec3<f32>(h, 0.0, 0.0), 0u) - velocity_at(p - vec3<f32>(h, 0.0, 0.0), 0u)) / (2.0 * h);
    let dy = (velocity_at(p + vec3<f32>(0.0, h, 0.0), 0u) - velocity_at(p - vec3<f32>(0.0, h, 0.0), 0u)) / (2.0 * h);
    let dz = (velocity_at(p + vec3<f32>(0.0, 0.0, h), 0u) - velocity_at(p - vec3<f32>(0.0, 0.0, h), 0u)) / (2.0 * h);
    let w = vec3<f32>(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x);
    return length(w);
}

fn white_water_step() -> u32 {
    // This step's index (reduce_begin counted it already).
    return state.solve.steps - 1u;
}

@compute @workgroup_size(256)
fn white_water_move(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= params.particle_count * SLOTS_PER_PARTICLE || pool[i].kind == PARTICLE_DEAD) {
        return;
    }
    var d = pool[i];
    let dt = params.dt;
    d.kind = classify(fill_at(d.position).fill);
    let fluid = velocity_at(d.position, 0u);
    var next = fluid;
    if (d.kind == PARTICLE_SPRAY) {
        // Ballistic, with the quadratic drag of its drops.
        next = d.velocity + (params.gravity - params.drop_drag * length(d.velocity) * d.velocity) * dt;
    } else if (d.kind == PARTICLE_BUBBLE) {
        // With the liquid, rising at its terminal speed, reached over its
        // relaxation time.
        let keep = exp(-dt / params.bubble_relaxation);
        let target_velocity = fluid + vec3<f32>(0.0, params.bubble_rise, 0.0);
        next = target_velocity + (d.velocity - target_velocity) * keep;
    }
    d.velocity = next;
    d.position += next * dt;
    if (d.kind == PARTICLE_FOAM) {
        d.life -= dt;
    }
    let top = params.origin + vec3<f32>(params.cells) * params.h;
    let outside = any(d.position < params.origin) || any(d.position > top);
    let cell = clamp(vec3<i32>(floor((d.position - params.origin) / params.h)), vec3<i32>(0), vec3<i32>(params.cells) - vec3<i32>(1));
    let solid = !outside && is_solid(cell);
    let landed = params.landing == 1u && d.position.y < params.landing_level;
    if (outside || solid || landed || (d.kind == PARTICLE_FOAM && d.life <= 0.0)) {
        d = Diffuse(vec3<f32>(0.0), PARTICLE_DEAD, vec3<f32>(0.0), 0.0);
    }
    pool[i] = d;
}

@compute @workgroup_size(256)
fn white_water_shed(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = linear(wid, nwg, lid);
    if (i >= params.particle_count || particles[i].alive == 0u) {
        return;
    }
    let step = white_water_step();
    let slot = i * SLOTS_PER_PARTICLE + step % SLOTS_PER_PARTICLE;
    if (pool[slot].kind != PARTICLE_DEAD) {
        return;
    }
    let p = particles[i].position;
    let v = particles[i].velocity;
    let speed = length(v);
    if (speed < ENTRAINMENT_SPEED_MIN) {
        return;
    }
    let around = fill_at(p);
    let length_out = length(around.outward);
    var outward = 0.0;
    if (around.fill < BUBBLE_FILL && length_out > 0.0) {
        let along = dot(v, around.outward) / length_out;
        if (along >= CREST_ALIGNMENT * speed) {
            outward = along;
        }
    }
    let breaking = max(
        ramp(vorticity_at(p) * params.h, TRAPPED_AIR_SHEAR_MIN, TRAPPED_AIR_SHEAR_MAX),
        ramp(outward, CREST_SPEED_MIN, CREST_SPEED_MAX),
    );
    let energy = ramp(speed, ENTRAINMENT_SPEED_MIN, ENTRAINMENT_SPEED_MAX);
    let chance = min(params.white_water_rate * params.dt * energy * breaking, 1.0);
    if (random(step, slot, SALT_CHANCE) >= chance) {
        return;
    }
    // Anywhere in the particle's share of its cell.
    let spacing = params.h / pow(params.particles_per_cell, 1.0 / 3.0);
    let jitter = vec3<f32>(random(step, slot, SALT_JITTER_X), random(step, slot, SALT_JITTER_Y), random(step, slot, SALT_JITTER_Z));
    let at = p + (jitter - 0.5) * spacing;
    pool[slot] = Diffuse(at, classify(fill_at(at).fill), v, params.foam_life);
}
