// A physically based atmosphere: the WGSL twin of hydrolux_core::atmosphere
// (Hillaire 2020 with Bruneton 2017's transmittance table; same constants,
// table sizes, samples and order). Lengths in km. Needs `constants` and
// `sky_model` (SkyParams).

const ATM_BOTTOM_RADIUS: f32 = 6360.0;
const ATM_TOP_RADIUS: f32 = 6460.0;
const ATM_OZONE_CENTER: f32 = 25.0;
const ATM_OZONE_HALF_WIDTH: f32 = 15.0;
const ATM_OBSERVER_HEIGHT: f32 = 0.001;
const ATM_TRANSMITTANCE_SIZE: vec2<u32> = vec2<u32>(256u, 64u);
const ATM_MULTISCATTERING_SIZE: vec2<u32> = vec2<u32>(32u, 32u);
const ATM_SKY_VIEW_SIZE: vec2<u32> = vec2<u32>(192u, 108u);
const ATM_TRANSMITTANCE_STEPS: u32 = 40u;
const ATM_MULTISCATTERING_STEPS: u32 = 20u;
const ATM_MULTISCATTERING_DIRECTIONS: u32 = 8u;
const ATM_SKY_VIEW_STEPS: u32 = 40u;
// Solar illuminance above the atmosphere (klx) in its colour
// (hydrolux_core::sky::SUN_ILLUMINANCE_TOP · SUN_TOP_COLOUR).
const ATM_SUN_TOP: vec3<f32> = vec3<f32>(1.05, 1.0, 0.94) * 128.0;

// Rayleigh scattering (1/km) at height h (km).
fn atm_rayleigh(p: SkyParams, h: f32) -> vec3<f32> {
    return p.rayleigh.xyz * exp(-max(h, 0.0) / p.rayleigh.w);
}

// Mie scattering (1/km) at height h.
fn atm_mie(p: SkyParams, h: f32) -> vec3<f32> {
    return p.mie.xyz * exp(-max(h, 0.0) / p.mie.w);
}

fn atm_extinction(p: SkyParams, h_in: f32) -> vec3<f32> {
    let h = max(h_in, 0.0);
    let ozone = max(1.0 - abs(h - ATM_OZONE_CENTER) / ATM_OZONE_HALF_WIDTH, 0.0);
    return p.rayleigh.xyz * exp(-h / p.rayleigh.w) + p.mie_extinction.xyz * exp(-h / p.mie.w)
        + p.ozone.xyz * ozone;
}

fn atm_distance_to_top(r: f32, mu: f32) -> f32 {
    let disc = r * r * (mu * mu - 1.0) + ATM_TOP_RADIUS * ATM_TOP_RADIUS;
    return max(-r * mu + sqrt(max(disc, 0.0)), 0.0);
}

fn atm_distance_to_ground(r: f32, mu: f32) -> f32 {
    let disc = r * r * (mu * mu - 1.0) + ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS;
    return max(-r * mu - sqrt(max(disc, 0.0)), 0.0);
}

fn atm_hits_ground(r: f32, mu: f32) -> bool {
    return mu < 0.0 && r * r * (mu * mu - 1.0) + ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS >= 0.0;
}

fn atm_radius_at(r: f32, mu: f32, t: f32) -> f32 {
    return sqrt(max(t * t + 2.0 * r * mu * t + r * r, 0.0));
}

fn atm_rayleigh_phase(nu: f32) -> f32 {
    return 3.0 / (16.0 * PI) * (1.0 + nu * nu);
}

fn atm_mie_phase(g: f32, nu: f32) -> f32 {
    let k = 3.0 / (8.0 * PI) * (1.0 - g * g) / (2.0 + g * g);
    return k * (1.0 + nu * nu) / pow(max(1.0 + g * g - 2.0 * g * nu, 1e-6), 1.5);
}

fn atm_unit_to_texel(x: f32, n: u32) -> f32 {
    return 0.5 / f32(n) + x * (1.0 - 1.0 / f32(n));
}

fn atm_transmittance_uv(r: f32, mu: f32) -> vec2<f32> {
    let h = sqrt(ATM_TOP_RADIUS * ATM_TOP_RADIUS - ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS);
    let rho = sqrt(max(r * r - ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS, 0.0));
    let d = atm_distance_to_top(r, mu);
    let d_min = ATM_TOP_RADIUS - r;
    let d_max = rho + h;
    let x_mu = clamp((d - d_min) / max(d_max - d_min, 1e-6), 0.0, 1.0);
    return vec2<f32>(
        atm_unit_to_texel(x_mu, ATM_TRANSMITTANCE_SIZE.x),
        atm_unit_to_texel(rho / h, ATM_TRANSMITTANCE_SIZE.y),
    );
}

fn atm_multiscattering_uv(r: f32, mu_s: f32) -> vec2<f32> {
    let height = clamp((r - ATM_BOTTOM_RADIUS) / (ATM_TOP_RADIUS - ATM_BOTTOM_RADIUS), 0.0, 1.0);
    return vec2<f32>(
        atm_unit_to_texel(clamp(mu_s, -1.0, 1.0) * 0.5 + 0.5, ATM_MULTISCATTERING_SIZE.x),
        atm_unit_to_texel(height, ATM_MULTISCATTERING_SIZE.y),
    );
}

// The horizontal direction of v ((1, 0) straight up or down). No division
// by zero even in the branch `select` drops: some drivers blend both.
fn atm_flat(v: vec3<f32>) -> vec2<f32> {
    let l = length(v.xz);
    return select(vec2<f32>(1.0, 0.0), v.xz / max(l, 1e-6), l > 1e-6);
}

// The sky-view table's coordinates for a direction (azimuth from the sun
// across, elevation on a square-root scale up; below the horizon, the
// horizon's row).
fn atm_sky_view_uv(dir: vec3<f32>, sun: vec3<f32>) -> vec2<f32> {
    let elevation = asin(clamp(dir.y, 0.0, 1.0));
    let azimuth = acos(clamp(dot(atm_flat(dir), atm_flat(sun)), -1.0, 1.0));
    return vec2<f32>(
        atm_unit_to_texel(azimuth / PI, ATM_SKY_VIEW_SIZE.x),
        atm_unit_to_texel(sqrt(elevation / (0.5 * PI)), ATM_SKY_VIEW_SIZE.y),
    );
}

// The sky (kcd/m², no sun disc) towards `dir` from the sky-view table, for
// either model.
fn sky_from_view_table(
    table: texture_2d<f32>,
    samp: sampler,
    p: SkyParams,
    dir: vec3<f32>,
) -> vec3<f32> {
    let uv = atm_sky_view_uv(normalize(dir), p.sun_direction.xyz);
    return textureSampleLevel(table, samp, uv, 0.0).rgb;
}
