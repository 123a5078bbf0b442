// The sky's parameters (hydrolux_core::sky::SkyParams) and Preetham's
// analytic daylight sky, the WGSL twin of hydrolux_core::sky::sky_radiance.
// The physical model's atmosphere is `passes/sky/atmosphere.wgsl`.

struct SkyParams {
    coeff_y: vec4<f32>,
    coeff_x: vec4<f32>,
    coeff_yy: vec4<f32>,
    coeff_e: vec4<f32>,
    zenith_over_f: vec4<f32>,
    sun_direction: vec4<f32>,
    sun_illuminance: vec4<f32>,
    // Rayleigh scattering (1/km), scale height (km).
    rayleigh: vec4<f32>,
    // Mie scattering (1/km), scale height (km).
    mie: vec4<f32>,
    // Mie extinction (1/km), the phase function's g.
    mie_extinction: vec4<f32>,
    // Ozone's peak absorption (1/km), the ground's albedo.
    ozone: vec4<f32>,
    // x: 0 Preetham, 1 physical.
    model: vec4<u32>,
}

fn perez(cos_theta: f32, gamma: f32, c: vec4<f32>, e: f32) -> f32 {
    let ct = max(cos_theta, 0.01);
    let cg = cos(gamma);
    return (1.0 + c.x * exp(c.y / ct)) * (1.0 + c.z * exp(c.w * gamma) + e * cg * cg);
}

fn xyy_to_linear_srgb(x: f32, y_in: f32, lum: f32) -> vec3<f32> {
    let y = max(y_in, 1e-4);
    let cx = x * lum / y;
    let cy = lum;
    let cz = (1.0 - x - y) * lum / y;
    return max(vec3<f32>(
        3.2406 * cx - 1.5372 * cy - 0.4986 * cz,
        -0.9689 * cx + 1.8758 * cy + 0.0415 * cz,
        0.0557 * cx - 0.2040 * cy + 1.0570 * cz,
    ), vec3<f32>(0.0));
}

// Preetham's sky radiance (kcd/m², linear sRGB) towards `dir`, without the sun disk.
fn sky_radiance(p: SkyParams, dir_in: vec3<f32>) -> vec3<f32> {
    let dir = normalize(dir_in);
    let sun = normalize(vec3<f32>(p.sun_direction.x, max(p.sun_direction.y, 0.02), p.sun_direction.z));
    let cos_t = max(dir.y, 0.0);
    let gamma = acos(clamp(dot(dir, sun), -1.0, 1.0));
    let lum = p.zenith_over_f.x * perez(cos_t, gamma, p.coeff_y, p.coeff_e.x);
    let x = p.zenith_over_f.y * perez(cos_t, gamma, p.coeff_x, p.coeff_e.y);
    let y = p.zenith_over_f.z * perez(cos_t, gamma, p.coeff_yy, p.coeff_e.z);
    return xyy_to_linear_srgb(x, y, lum);
}

// Direction of texel (u, v ∈ [-1, 1]) on cube face `face` (+X, -X, +Y, -Y, +Z, -Z).
fn cube_direction(face: u32, u: f32, v: f32) -> vec3<f32> {
    switch face {
        case 0u: { return normalize(vec3<f32>(1.0, -v, -u)); }
        case 1u: { return normalize(vec3<f32>(-1.0, -v, u)); }
        case 2u: { return normalize(vec3<f32>(u, 1.0, v)); }
        case 3u: { return normalize(vec3<f32>(u, -1.0, -v)); }
        case 4u: { return normalize(vec3<f32>(u, -v, 1.0)); }
        default: { return normalize(vec3<f32>(-u, -v, -1.0)); }
    }
}
