// How opaque surfaces are lit and patterned, shared by the geometry pass
// (rasterised meshes) and the traced water's hits (passes/water/traced.wgsl)
// so that both draw the same scene.

#import constants, frame, modes

// Light bounced off the ground and water below, a grey world of this albedo,
// so that the undersides reflections show are not black (twin:
// hydrolux-core irradiance::GROUND_ALBEDO).
const GROUND_ALBEDO: f32 = 0.15;

// Radiance of that grey world below the horizon: what a ray that leaves
// downwards without a lookup sees.
fn below_horizon_radiance() -> vec3<f32> {
    let l = frame.light.sun_dir;
    let e_down = frame.light.sky_ambient + frame.light.sun_illuminance * max(l.y, 0.0);
    return GROUND_ALBEDO * e_down / PI;
}

// The sky's and the grey world's irradiance on unit normal n in the air,
// from its nine spherical-harmonic coefficients (Ramamoorthi & Hanrahan
// 2001): brighter on the side towards the sun's glow, bluer facing the
// zenith, dimmer facing down. Twin: hydrolux-core IrradianceSh::irradiance.
fn sky_irradiance(n: vec3<f32>) -> vec3<f32> {
    let c = frame.light.sky_light;
    let e = c[0].rgb * 0.282095
        + (c[1].rgb * n.y + c[2].rgb * n.z + c[3].rgb * n.x) * 0.488603
        + (c[4].rgb * (n.x * n.y) + c[5].rgb * (n.y * n.z) + c[7].rgb * (n.x * n.z)) * 1.092548
        + c[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0))
        + c[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3<f32>(0.0));
}

// Irradiance on a surface of normal n in the air: the sun (times
// `sun_factor`: its visibility and what else bends light onto the point,
// per channel), and the sky and GROUND_ALBEDO's grey world around
// (`sky_irradiance`).
fn air_irradiance(n: vec3<f32>, sun_factor: vec3<f32>) -> vec3<f32> {
    let l = frame.light.sun_dir;
    return frame.light.sun_illuminance * max(dot(n, l), 0.0) * sun_factor + sky_irradiance(n);
}

// Where on its plane a pattern is drawn: the plane facing the dominant axis
// of the normal n at `world` (m).
fn pattern_plane(world: vec3<f32>, n: vec3<f32>) -> vec2<f32> {
    let a = abs(n);
    var p = world.xz;
    if (a.x > a.y && a.x > a.z) {
        p = world.zy;
    } else if (a.z > a.y) {
        p = world.xy;
    }
    return p;
}

// How much of a pattern's second colour shows at `q` (in tiles) for a pixel
// footprint of `footprint` tiles per axis: grout lines 6% of a tile wide (3%
// each side; they cover 1 − 0.94² ≈ 11.6% of the area) or checkers, faded to
// the mean where a pixel covers a good part of a tile instead of aliasing
// into moiré.
fn pattern_coverage(q: vec2<f32>, footprint: vec2<f32>, kind: u32) -> f32 {
    let w = max(footprint, vec2<f32>(1e-4));
    let far = smoothstep(0.15, 0.5, max(w.x, w.y));
    if (kind == PATTERN_TILES) {
        let f = abs(fract(q) - 0.5);
        let line = smoothstep(vec2<f32>(0.47) - w, vec2<f32>(0.47) + w, f);
        return mix(max(line.x, line.y), 0.1164, far);
    }
    if (kind == PATTERN_CHECKER) {
        let c = floor(q);
        return mix(f32((i32(c.x) + i32(c.y)) & 1), 0.5, far);
    }
    return 0.0;
}
