// Caustics by beam projection (Jensen & Goliáš; seed 003 §4.2, eq. 28): every
// triangle of a grid over the periodic surface patch is projected along its
// refracted rays onto the floor plane and drawn there, additively, with the
// irradiance its intercepted sunlight has once spread over the projected
// area: (A·l)·T / A_floor, relative to the sun on a plane facing it. Each
// vertex computes its whole triangle (WebGPU has no geometry shaders), so the
// draw is non-indexed: 6 vertices per grid cell, 9 instances for the
// periodic neighbours of the patch; one pass per layer (instance / 9).
#import constants, frame, optics, surface, caustic_params

@group(2) @binding(0) var<uniform> beam: CausticParams;

struct BeamOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) irradiance: f32,
}

// The displaced surface point of grid vertex (i, j) and where its refracted
// sunlight meets the floor; w = 0 when no light gets through there.
fn project(i: u32, j: u32, depth: f32) -> array<vec4<f32>, 2> {
    let n = beam.beam_cells;
    let size = beam.patch_size;
    let x0 = (f32(i) / f32(n) - 0.5) * size.x;
    let z0 = (f32(j) / f32(n) - 0.5) * size.y;
    let s = surface_sample_footprint(vec2<f32>(x0, z0), 0.0);
    let pos = vec3<f32>(x0 + s.disp.x, s.disp.y, z0 + s.disp.z);
    let ior = frame.water.ior;
    let dir = refract(-frame.light.sun_dir, surface_normal(s), 1.0 / ior);
    var ok = 1.0;
    if (dir.y > -1e-4) {
        ok = 0.0;
    }
    let hit = pos + dir * (max(pos.y + depth, 0.0) / max(-dir.y, 1e-4));
    return array<vec4<f32>, 2>(vec4<f32>(pos, ok), vec4<f32>(hit, ok));
}

@vertex
fn vs_beam(@builtin(vertex_index) v: u32, @builtin(instance_index) instance: u32) -> BeamOut {
    let n = beam.beam_cells;
    let cell = v / 6u;
    let ci = cell % n;
    let cj = cell / n;
    // Two counter-clockwise (from above) triangles per cell.
    var corners = array<vec2<u32>, 6>(vec2<u32>(0u, 0u), vec2<u32>(0u, 1u), vec2<u32>(1u, 0u), vec2<u32>(1u, 0u), vec2<u32>(0u, 1u), vec2<u32>(1u, 1u));
    let first = (v % 6u) / 3u * 3u;
    let layer = instance / 9u;
    let depth = beam.floor_depth * f32(layer + 1u) / f32(beam.layers);
    let a = project(ci + corners[first].x, cj + corners[first].y, depth);
    let b = project(ci + corners[first + 1u].x, cj + corners[first + 1u].y, depth);
    let c = project(ci + corners[first + 2u].x, cj + corners[first + 2u].y, depth);
    let me = corners[v % 6u];
    let own = project(ci + me.x, cj + me.y, depth);
    let l = frame.light.sun_dir;
    let area_vector = 0.5 * cross(b[0].xyz - a[0].xyz, c[0].xyz - a[0].xyz);
    let shown = max(dot(area_vector, l), 0.0);
    let ior = frame.water.ior;
    // Foam over the cell scatters most of the light back up.
    let centre = (vec2<f32>(f32(ci), f32(cj)) + 0.5) / f32(n) - 0.5;
    let foam = foam_transmittance(foam_cover_at(centre * beam.patch_size));
    let t = (1.0 - fresnel_exact(dot(normalize(area_vector), l), 1.0, ior)) * foam;
    let floor_area = 0.5 * abs(cross(vec3<f32>(c[1].x - a[1].x, 0.0, c[1].z - a[1].z), vec3<f32>(b[1].x - a[1].x, 0.0, b[1].z - a[1].z)).y);
    var out: BeamOut;
    // Folds make the projected area vanish: cap the focus.
    out.irradiance = min(shown * t / max(floor_area, 1e-9), 64.0) * a[1].w * b[1].w * c[1].w;
    let periodic = instance % 9u;
    let shift = vec2<f32>(f32(periodic % 3u) - 1.0, f32(periodic / 3u) - 1.0) * beam.patch_size;
    let p = (own[1].xz + shift) / beam.patch_size * 2.0;
    out.clip = vec4<f32>(p.x, -p.y, 0.0, 1.0);
    return out;
}

@fragment
fn fs_beam(in: BeamOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.irradiance, 0.0, 0.0, 0.0);
}
