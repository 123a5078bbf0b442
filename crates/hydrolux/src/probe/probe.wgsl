// Evaluate the surface (as the renderer draws it) and the sky cube map at
// arbitrary points: GPU height queries for users (buoyancy) and the hook the
// GPU-versus-CPU tests use; the shaders' Fresnel formulas; how a parcel of
// spray is drawn and lit; the temporal anti-aliasing's resolve.
#import constants, frame, optics, sea_brdf, sky_model, sky_bindings, surface, white_water_light, temporal_resolve

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
    // w: the cube's level (0 the sky itself; above, filtered for roughness).
    let c = textureSampleLevel(sky_cube, sky_sampler, points[id.x].xyz, points[id.x].w);
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

// The far sea's BRDF (sea_brdf): points 3i, 3i + 1, 3i + 2 hold (v, mode),
// (l, ior) and (mean slope, variance); result 3i is (mean Fresnel, the
// mirrored direction) and (glitter per unit irradiance, 0, 0, 0).
@compute @workgroup_size(64, 1, 1)
fn probe_sea_brdf(@builtin(global_invocation_id) id: vec3<u32>) {
    if (3u * id.x + 2u >= arrayLength(&points)) {
        return;
    }
    let a = points[3u * id.x];
    let b = points[3u * id.x + 1u];
    let c = points[3u * id.x + 2u];
    let mode = u32(a.w);
    let q = frame.water.fresnel_power;
    let r = sea_reflection(a.xyz, c.xy, c.zw, mode, q, b.w);
    let glitter = sea_glitter(a.xyz, b.xyz, c.xy, c.zw, mode, q, b.w);
    results[3u * id.x] = ProbeOut(vec4<f32>(r.fresnel, r.direction), vec4<f32>(glitter, 0.0, 0.0, 0.0), vec4<f32>(0.0));
}

// A spray parcel as drawn (white_water_light): points 2i and 2i + 1 hold
// (quad x, quad y, parcel, pixel) and (streak, cover, drops, id's bits);
// result 2i is (opacity, optical depth, the asymmetry it gives, the sky's
// share seen along a view whose vertical is quad y).
@compute @workgroup_size(64, 1, 1)
fn probe_spray(@builtin(global_invocation_id) id: vec3<u32>) {
    if (2u * id.x + 1u >= arrayLength(&points)) {
        return;
    }
    let a = points[2u * id.x];
    let b = points[2u * id.x + 1u];
    let s = SprayShape(a.z, a.w, b.x, b.y, b.z);
    let depth = mist_depth(a.xy, s);
    let g = spray_asymmetry(depth);
    let r = vec4<f32>(spray_opacity(a.xy, s, bitcast<u32>(b.w)), depth, g, spray_sky_share(a.y, g));
    results[2u * id.x] = ProbeOut(r, vec4<f32>(0.0), vec4<f32>(0.0));
}

// The temporal resolve (temporal_resolve): points 10i … 10i + 8 hold the
// new frame's 3×3 neighbourhood (rgb; w of the centre its trust, of the
// first 1 where the view is settled), 10i + 9 the history (rgb, w the new
// frame's least share, 0 where there is no history); result 10i is the
// resolved colour.
@compute @workgroup_size(64, 1, 1)
fn probe_antialias(@builtin(global_invocation_id) id: vec3<u32>) {
    if (10u * id.x + 9u >= arrayLength(&points)) {
        return;
    }
    var n: array<vec3<f32>, 9>;
    for (var k = 0u; k < 9u; k++) {
        n[k] = points[10u * id.x + k].xyz;
    }
    let h = points[10u * id.x + 9u];
    let trust = points[10u * id.x + 4u].w;
    let settled = points[10u * id.x].w > 0.5;
    let r = taa_resolve(n, h.xyz, h.w > 0.0, trust, h.w, settled);
    results[10u * id.x] = ProbeOut(vec4<f32>(r, 0.0), vec4<f32>(0.0), vec4<f32>(0.0));
}
