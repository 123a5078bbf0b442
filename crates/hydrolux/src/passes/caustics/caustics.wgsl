// Surface caustics by photon splatting (seed 000 §4.5, after Papadopoulos &
// Papaioannou 2009), into a stack of horizontal layers down to the floor so
// that receivers at any depth find the caustic focused for their depth (the
// slices idea of seed 003 §4.3). One thread per photon of a regular grid
// over the periodic surface patch: refract at the displaced surface (Snell),
// weight by the Fresnel transmittance and by the sunlight its cell
// intercepts, follow the ray to each layer, and add its energy to the four
// nearest cells in fixed point (WebGPU has no float atomics). Then a
// periodic 3×3 binomial filter into the map texture array. CPU twin (one
// plane): hydrolux_core::caustics (the unit and the formulas are there).
#import constants, frame, optics, surface, photon, caustic_params

@group(2) @binding(0) var<uniform> params: CausticParams;
@group(2) @binding(1) var<storage, read_write> accum: array<atomic<u32>>;
@group(2) @binding(2) var map_out: texture_storage_2d_array<rgba16float, write>;

fn layer_depth(layer: u32) -> f32 {
    return params.floor_depth * f32(layer + 1u) / f32(params.layers);
}

@compute @workgroup_size(8, 8, 1)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = params.cells;
    if (id.x < m && id.y < m && id.z < params.layers) {
        atomicStore(&accum[(id.z * m + id.y) * m + id.x], 0u);
    }
}

fn cell_index(layer: u32, i: i32, j: i32) -> u32 {
    let m = i32(params.cells);
    return (layer * u32(m) + u32(((j % m) + m) % m)) * u32(m) + u32(((i % m) + m) % m);
}

fn deposit(layer: u32, i: i32, j: i32, value: f32) {
    atomicAdd(&accum[cell_index(layer, i, j)], u32(value * params.fixed_point_scale + 0.5));
}

@compute @workgroup_size(8, 8, 1)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.photons;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let size = params.patch_size;
    let x0 = ((f32(id.x) + 0.5) / f32(n) - 0.5) * size.x;
    let z0 = ((f32(id.y) + 0.5) / f32(n) - 0.5) * size.y;
    let photon = refracted_photon(vec2<f32>(x0, z0));
    if (photon.weight <= 0.0) {
        return;
    }
    let pos = photon.pos;
    let dir = photon.dir;
    let m = f32(params.cells);
    let cell_area = size.x * size.y / (m * m);
    let energy = photon.weight * (size.x * size.y / f32(n * n)) / cell_area;
    for (var layer = 0u; layer < params.layers; layer++) {
        let hit = pos + dir * (max(pos.y + layer_depth(layer), 0.0) / -dir.y);
        // Bilinear (tent) weights over the four nearest cell centres.
        let f = (hit.xz / size + 0.5) * m - 0.5;
        let base = floor(f);
        let a = f - base;
        let i = i32(base.x);
        let j = i32(base.y);
        deposit(layer, i, j, energy * (1.0 - a.x) * (1.0 - a.y));
        deposit(layer, i + 1, j, energy * a.x * (1.0 - a.y));
        deposit(layer, i, j + 1, energy * (1.0 - a.x) * a.y);
        deposit(layer, i + 1, j + 1, energy * a.x * a.y);
    }
}

fn accumulated(layer: u32, i: i32, j: i32) -> f32 {
    return f32(atomicLoad(&accum[cell_index(layer, i, j)])) / params.fixed_point_scale;
}

// Periodic [1 2 1]/4 × [1 2 1]/4 filter (seed 000 uses a 3×3 Gaussian).
@compute @workgroup_size(8, 8, 1)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = params.cells;
    if (id.x >= m || id.y >= m || id.z >= params.layers) {
        return;
    }
    let i = i32(id.x);
    let j = i32(id.y);
    var sum = 0.0;
    for (var dj = -1; dj <= 1; dj++) {
        for (var di = -1; di <= 1; di++) {
            let w = (2.0 - f32(abs(di))) * (2.0 - f32(abs(dj))) / 16.0;
            sum += w * accumulated(id.z, i + di, j + dj);
        }
    }
    textureStore(map_out, vec2<i32>(i, j), id.z, vec4<f32>(sum, 0.0, 0.0, 1.0));
}

// Seed 001's backward method (procedural, cheap): from each map cell on the
// floor, go back up the flat-refracted sunbeam to the surface, take the
// wave's normal there (analytic derivatives), refract the sunlight through
// it, and light the cell by how closely the bent ray points at the cell —
// a soft sun map of angular radius SUN_MAP_RADIUS. Flat water gives the same
// value as the photons (T·cos θ); it does not conserve energy under waves.
const SUN_MAP_RADIUS: f32 = 0.04;

@compute @workgroup_size(8, 8, 1)
fn procedural(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = params.cells;
    if (id.x >= m || id.y >= m || id.z >= params.layers) {
        return;
    }
    let size = params.patch_size;
    let depth = layer_depth(id.z);
    let on_floor = (vec2<f32>(id.xy) + 0.5) / f32(m) - 0.5;
    let floor_point = vec3<f32>(on_floor.x * size.x, -depth, on_floor.y * size.y);
    let travel = frame.light.sun_travel;
    let entry = floor_point - travel * (depth / max(frame.light.sun_travel_cos, 1e-3));
    let s = surface_sample_footprint(entry.xz, 0.0);
    let nrm = surface_normal(s);
    let l = frame.light.sun_dir;
    let ior = frame.water.ior;
    let bent = refract(-l, nrm, 1.0 / ior);
    let cos_angle = clamp(dot(bent, travel), -1.0, 1.0);
    let angle2 = 2.0 * (1.0 - cos_angle);
    let flat_value = (1.0 - fresnel_exact(l.y, 1.0, ior)) * max(l.y, 0.0);
    // Foam where the beam enters scatters most of it back up.
    let value = flat_value * exp(-0.5 * angle2 / (SUN_MAP_RADIUS * SUN_MAP_RADIUS)) * foam_transmittance(foam_cover_at(entry.xz));
    textureStore(map_out, vec2<i32>(id.xy), id.z, vec4<f32>(value, 0.0, 0.0, 1.0));
}
