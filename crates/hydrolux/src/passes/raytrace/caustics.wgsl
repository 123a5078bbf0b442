// Caustics on the traced ground, the paper's photon texture (seed 003
// §3.3.1 after Baboud & Décoret 2006 §5): one thread per photon of a grid
// over the water surface (rest positions, the window widened up-sun) —
// refracted at the displaced surface (shaders/photon.wgsl), dropped where
// the land or a traced object shades its way in from the sun, traced to the
// ground heightfield, dropped if it meets an object first — and splatted
// where it lands into the window's cells (bilinear, fixed point: WebGPU has
// no float atomics); then a 3×3 binomial filter into the light the traced
// ground reads (traced_hits.wgsl `traced_ground_light`). Twin:
// hydrolux-core raytrace::caustics (trace_ground_caustics).
#import constants, frame, optics, surface, photon, heightfield_trace, traced, traced_hits

@group(2) @binding(0) var<uniform> traced: TracedParams;
@group(2) @binding(1) var<storage, read> hf_heights: array<f32>;
@group(2) @binding(2) var<storage, read> hf_bounds: array<vec2<f32>>;
@group(2) @binding(3) var<storage, read> traced_objects: array<TracedObject>;
@group(2) @binding(4) var<storage, read_write> ground_light: array<f32>;
@group(2) @binding(5) var<storage, read_write> photon_sum: array<atomic<u32>>;
@group(2) @binding(6) var<storage, read> traced_meshes: array<vec4<f32>>;

// Fixed-point units per unit of a cell's flat light (the layered maps' scale).
const PHOTON_FIXED_POINT: f32 = 65536.0;

fn cells() -> u32 {
    return traced.caustic_cells;
}

@compute @workgroup_size(64)
fn caustic_clear(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x < cells() * cells()) {
        atomicStore(&photon_sum[id.x], 0u);
    }
}

fn deposit(i: i32, j: i32, energy: f32) {
    let m = i32(cells());
    if (i >= 0 && j >= 0 && i < m && j < m) {
        atomicAdd(&photon_sum[j * m + i], u32(energy * PHOTON_FIXED_POINT + 0.5));
    }
}

@compute @workgroup_size(8, 8, 1)
fn caustic_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= traced.emission_count.x || id.y >= traced.emission_count.y) {
        return;
    }
    let rest = traced.emission_origin + (vec2<f32>(id.xy) + 0.5) * traced.emission_spacing;
    let photon = refracted_photon(rest);
    if (photon.weight <= 0.0) {
        return;
    }
    let pos = photon.pos;
    // The surface there lies under the land: no water, no photon.
    if (traced.has_ground != 0u && pos.y <= hf_height(traced.ground, pos.x, pos.z)) {
        return;
    }
    let l = frame.light.sun_dir;
    let reach = traced.reach;
    if (trace_ground(pos, l) != NO_ROOT || objects_block(pos, l, reach)) {
        return;
    }
    let t = trace_ground(pos, photon.dir);
    if (t == NO_ROOT || objects_block(pos, photon.dir, t)) {
        return;
    }
    let hit = pos + photon.dir * t;
    let f = (hit.xz - traced.caustic_corner) / traced.caustic_cell - 0.5;
    let base = floor(f);
    let a = f - base;
    let i = i32(base.x);
    let j = i32(base.y);
    let energy = photon.weight * traced.photon_energy;
    deposit(i, j, energy * (1.0 - a.x) * (1.0 - a.y));
    deposit(i + 1, j, energy * a.x * (1.0 - a.y));
    deposit(i, j + 1, energy * (1.0 - a.x) * a.y);
    deposit(i + 1, j + 1, energy * a.x * a.y);
}

fn summed(i: i32, j: i32) -> f32 {
    let m = i32(cells());
    return f32(atomicLoad(&photon_sum[clamp(j, 0, m - 1) * m + clamp(i, 0, m - 1)])) / PHOTON_FIXED_POINT;
}

// [1 2 1]/4 × [1 2 1]/4, the window's edge cells repeated beyond it; in
// units of flat water's light on flat ground.
@compute @workgroup_size(8, 8, 1)
fn caustic_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = cells();
    if (id.x >= m || id.y >= m) {
        return;
    }
    let i = i32(id.x);
    let j = i32(id.y);
    var sum = 0.0;
    for (var dj = -1; dj <= 1; dj++) {
        for (var di = -1; di <= 1; di++) {
            let w = (2.0 - f32(abs(di))) * (2.0 - f32(abs(dj))) / 16.0;
            sum += w * summed(i + di, j + dj);
        }
    }
    ground_light[id.y * m + id.x] = sum * frame.caustics.inv_flat_value;
}
