// The sky's tables, built when the sun or the air changes: transmittance,
// the multiple-scattering source Ψ and the sky-view table of the physical
// atmosphere (twins of hydrolux_core::atmosphere::AtmosphereTables), or
// Preetham's sky written into the same sky-view table. The cube map and the
// background read the sky-view table, whichever model filled it.
#import constants, sky_model, atmosphere

@group(0) @binding(0) var<uniform> sky: SkyParams;
@group(0) @binding(1) var transmittance_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(2) var transmittance_table: texture_2d<f32>;
@group(0) @binding(3) var table_sampler: sampler;
@group(0) @binding(4) var multiscattering_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var multiscattering_table: texture_2d<f32>;
@group(0) @binding(6) var sky_view_out: texture_storage_2d<rgba16float, write>;

fn transmittance_to_top(r: f32, mu: f32) -> vec3<f32> {
    if (atm_hits_ground(r, mu)) {
        return vec3<f32>(0.0);
    }
    return textureSampleLevel(transmittance_table, table_sampler, atm_transmittance_uv(r, mu), 0.0).rgb;
}

fn multiscattering_source(r: f32, mu_s: f32) -> vec3<f32> {
    let uv = atm_multiscattering_uv(r, mu_s);
    return textureSampleLevel(multiscattering_table, table_sampler, uv, 0.0).rgb;
}

@compute @workgroup_size(8, 8, 1)
fn transmittance(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ATM_TRANSMITTANCE_SIZE.x || id.y >= ATM_TRANSMITTANCE_SIZE.y) {
        return;
    }
    // (r, μ) at the texel's centre (Bruneton 2017 §4.1, inverted).
    let x_mu = f32(id.x) / f32(ATM_TRANSMITTANCE_SIZE.x - 1u);
    let x_r = f32(id.y) / f32(ATM_TRANSMITTANCE_SIZE.y - 1u);
    let h = sqrt(ATM_TOP_RADIUS * ATM_TOP_RADIUS - ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS);
    let rho = h * x_r;
    let r = sqrt(rho * rho + ATM_BOTTOM_RADIUS * ATM_BOTTOM_RADIUS);
    let d_min = ATM_TOP_RADIUS - r;
    let d_max = rho + h;
    let d = d_min + x_mu * (d_max - d_min);
    var mu = 1.0;
    if (d != 0.0) {
        mu = clamp((h * h - rho * rho - d * d) / (2.0 * r * d), -1.0, 1.0);
    }
    // Segments lengthening away from the start, as the CPU twin.
    let to_top = atm_distance_to_top(r, mu);
    let n = f32(ATM_TRANSMITTANCE_STEPS);
    var depth = vec3<f32>(0.0);
    for (var k = 0u; k < ATM_TRANSMITTANCE_STEPS; k++) {
        let a = f32(k) / n;
        let b = (f32(k) + 1.0) / n;
        let t0 = to_top * a * a;
        let t1 = to_top * b * b;
        let t = 0.5 * (t0 + t1);
        depth += atm_extinction(sky, atm_radius_at(r, mu, t) - ATM_BOTTOM_RADIUS) * (t1 - t0);
    }
    textureStore(transmittance_out, vec2<i32>(id.xy), vec4<f32>(exp(-depth), 1.0));
}

// Ψ (Hillaire 2020 eq. 10) per unit solar illuminance: the second order
// gathered over 8 × 8 directions with the ground's bounce, the orders after
// it as the series 1/(1 − f_ms).
@compute @workgroup_size(8, 8, 1)
fn multiscattering(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ATM_MULTISCATTERING_SIZE.x || id.y >= ATM_MULTISCATTERING_SIZE.y) {
        return;
    }
    let mu_s = -1.0 + 2.0 * f32(id.x) / f32(ATM_MULTISCATTERING_SIZE.x - 1u);
    let r = max(
        ATM_BOTTOM_RADIUS
            + (ATM_TOP_RADIUS - ATM_BOTTOM_RADIUS) * f32(id.y) / f32(ATM_MULTISCATTERING_SIZE.y - 1u),
        ATM_BOTTOM_RADIUS + 1e-3,
    );
    let sun = vec3<f32>(sqrt(max(1.0 - mu_s * mu_s, 0.0)), mu_s, 0.0);
    let origin = vec3<f32>(0.0, r, 0.0);
    let n = ATM_MULTISCATTERING_DIRECTIONS;
    var second = vec3<f32>(0.0);
    var transfer = vec3<f32>(0.0);
    for (var a = 0u; a < n; a++) {
        let cos_theta = 1.0 - 2.0 * (f32(a) + 0.5) / f32(n);
        let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
        for (var b = 0u; b < n; b++) {
            let phi = 2.0 * PI * (f32(b) + 0.5) / f32(n);
            let dir = vec3<f32>(sin_theta * cos(phi), cos_theta, sin_theta * sin(phi));
            let ground = atm_hits_ground(r, cos_theta);
            let t_max = select(atm_distance_to_top(r, cos_theta), atm_distance_to_ground(r, cos_theta), ground);
            let dt = t_max / f32(ATM_MULTISCATTERING_STEPS);
            var throughput = vec3<f32>(1.0);
            for (var k = 0u; k < ATM_MULTISCATTERING_STEPS; k++) {
                let p = origin + dir * ((f32(k) + 0.5) * dt);
                let rp = length(p);
                let h = rp - ATM_BOTTOM_RADIUS;
                let scattering = atm_rayleigh(sky, h) + atm_mie(sky, h);
                let extinction = atm_extinction(sky, h);
                let step = exp(-extinction * dt);
                let sun_t = transmittance_to_top(rp, dot(p, sun) / rp);
                let through = (vec3<f32>(1.0) - step) / extinction;
                second += throughput * scattering * sun_t / (4.0 * PI) * through;
                transfer += throughput * scattering * through;
                throughput *= step;
            }
            if (ground) {
                let up = normalize(origin + dir * t_max);
                let mu = dot(up, sun);
                second += throughput * transmittance_to_top(ATM_BOTTOM_RADIUS, mu) * max(mu, 0.0)
                    * sky.ozone.w / PI;
            }
        }
    }
    let count = f32(n * n);
    let psi = (second / count) / (vec3<f32>(1.0) - transfer / count);
    textureStore(multiscattering_out, vec2<i32>(id.xy), vec4<f32>(psi, 1.0));
}

// The world direction of the sky-view table's texel: azimuth π·i/(w−1)
// from the sun's, elevation (π/2)·(j/(h−1))².
fn sky_view_direction(id: vec2<u32>) -> vec3<f32> {
    let azimuth = PI * f32(id.x) / f32(ATM_SKY_VIEW_SIZE.x - 1u);
    let y = f32(id.y) / f32(ATM_SKY_VIEW_SIZE.y - 1u);
    let elevation = 0.5 * PI * y * y;
    let towards = atm_flat(sky.sun_direction.xyz);
    let across = vec2<f32>(-towards.y, towards.x);
    let flat = towards * cos(azimuth) + across * sin(azimuth);
    return vec3<f32>(flat.x * cos(elevation), sin(elevation), flat.y * cos(elevation));
}

// Radiance per unit solar illuminance along `dir` from the observer:
// single scattering in 40 segments lengthening away from the eye, plus
// σs·Ψ for the higher orders (Hillaire 2020 eq. 11).
fn march(dir: vec3<f32>, sun: vec3<f32>) -> vec3<f32> {
    let r = ATM_BOTTOM_RADIUS + ATM_OBSERVER_HEIGHT;
    let mu = dir.y;
    let t_max = select(atm_distance_to_top(r, mu), atm_distance_to_ground(r, mu), atm_hits_ground(r, mu));
    let nu = dot(dir, sun);
    let phase_r = atm_rayleigh_phase(nu);
    let phase_m = atm_mie_phase(sky.mie_extinction.w, nu);
    let origin = vec3<f32>(0.0, r, 0.0);
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    let n = f32(ATM_SKY_VIEW_STEPS);
    for (var k = 0u; k < ATM_SKY_VIEW_STEPS; k++) {
        let a = f32(k) / n;
        let b = (f32(k) + 1.0) / n;
        let t0 = t_max * a * a;
        let t1 = t_max * b * b;
        let p = origin + dir * (0.5 * (t0 + t1));
        let rp = length(p);
        let mu_s = dot(p, sun) / rp;
        let h = rp - ATM_BOTTOM_RADIUS;
        let rayleigh = atm_rayleigh(sky, h);
        let mie = atm_mie(sky, h);
        let extinction = atm_extinction(sky, h);
        let step = exp(-extinction * (t1 - t0));
        let source = (rayleigh * phase_r + mie * phase_m) * transmittance_to_top(rp, mu_s)
            + (rayleigh + mie) * multiscattering_source(rp, mu_s);
        radiance += throughput * source * (vec3<f32>(1.0) - step) / extinction;
        throughput *= step;
    }
    return radiance;
}

@compute @workgroup_size(8, 8, 1)
fn sky_view_physical(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ATM_SKY_VIEW_SIZE.x || id.y >= ATM_SKY_VIEW_SIZE.y) {
        return;
    }
    let l = march(sky_view_direction(id.xy), normalize(sky.sun_direction.xyz)) * ATM_SUN_TOP;
    textureStore(sky_view_out, vec2<i32>(id.xy), vec4<f32>(l, 1.0));
}

@compute @workgroup_size(8, 8, 1)
fn sky_view_preetham(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= ATM_SKY_VIEW_SIZE.x || id.y >= ATM_SKY_VIEW_SIZE.y) {
        return;
    }
    let l = sky_radiance(sky, sky_view_direction(id.xy));
    textureStore(sky_view_out, vec2<i32>(id.xy), vec4<f32>(l, 1.0));
}
