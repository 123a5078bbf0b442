// Evaluate the surface (as the renderer draws it) and the sky cube map at
// arbitrary points: GPU height queries for users (buoyancy) and the hook the
// GPU-versus-CPU tests use; and the shaders' Fresnel formulas.
#import constants, frame, optics, sky_model, sky_bindings, surface

struct ProbeOut {
    disp: vec4<f32>,
    slope_dxx_dzz: vec4<f32>,
    dxz: vec4<f32>,
}

@group(2) @binding(0) var<storage, read> points: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read_write> results: array<ProbeOut>;

@compute @workgroup_size(64, 1, 1)
fn probe_surface(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&points)) {
        return;
    }
    let s = surface_sample_footprint(points[id.x].xy, 0.0);
    results[id.x] = ProbeOut(vec4<f32>(s.disp, 0.0), vec4<f32>(s.slope, s.dxx, s.dzz), vec4<f32>(s.dxz, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(64, 1, 1)
fn probe_sky(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&points)) {
        return;
    }
    let c = textureSampleLevel(sky_cube, sky_sampler, points[id.x].xyz, 0.0);
    results[id.x] = ProbeOut(c, vec4<f32>(0.0), vec4<f32>(0.0));
}

// x = cos θi, y = n1, z = n2 → reflectance in every mode (exact, Schlick,
// Jensen–Goliáš, power with the scene's exponent).
@compute @workgroup_size(64, 1, 1)
fn probe_fresnel(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&points)) {
        return;
    }
    let q = points[id.x];
    var r: vec4<f32>;
    for (var m = 0u; m < 4u; m++) {
        r[m] = fresnel(m, frame.water.fresnel_power, q.x, q.y, q.z);
    }
    results[id.x] = ProbeOut(r, vec4<f32>(0.0), vec4<f32>(0.0));
}
