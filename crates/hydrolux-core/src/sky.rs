//! Analytic daylight sky: Preetham, Shirley & Smits, *A Practical Analytic
//! Model for Daylight* (SIGGRAPH 1999), with the sun's colour from the same
//! paper's Rayleigh + aerosol transmittance. The sky is baked into an
//! environment cube map (seed 000 §3.1.2) by `shaders/sky.wgsl`, the WGSL twin
//! of [`sky_radiance`].
//!
//! Units: radiance in kcd/m² (Preetham's zenith luminance unit), illuminance
//! in klx, so a clear noon sky is a few units and the sun ~100.

use glam::Vec3;

/// Angular radius of the sun (radians).
pub const SUN_ANGULAR_RADIUS: f32 = 0.004_65;
/// Solar illuminance above the atmosphere, klx.
pub const SUN_ILLUMINANCE_TOP: f32 = 128.0;

/// Direction towards the sun: elevation above the horizon, azimuth from +x
/// towards +z (y up).
pub fn sun_direction(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
}

fn perez(theta_cos: f32, gamma: f32, c: [f32; 5]) -> f32 {
    let cos_t = theta_cos.max(0.01);
    (1.0 + c[0] * (c[1] / cos_t).exp())
        * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * gamma.cos().powi(2))
}

/// Everything the sky shader needs for one sun position, precomputed.
/// Laid out like WGSL `SkyParams` (shaders/shared/sky_model.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SkyParams {
    /// Perez coefficients A..E for Y, x, y (15 floats) + padding.
    pub coeff_y: [f32; 4],
    pub coeff_x: [f32; 4],
    pub coeff_yy: [f32; 4],
    /// E (fifth coefficient) of Y, x, y, and unused.
    pub coeff_e: [f32; 4],
    /// Zenith Y/F(0,θs), x/F, y/F, and unused.
    pub zenith_over_f: [f32; 4],
    /// Unit direction to the sun, w = cos of the sun's angular radius.
    pub sun_direction: [f32; 4],
    /// Sun illuminance on a plane facing it (klx, linear sRGB), w = disk radiance scale 1/Ω.
    pub sun_illuminance: [f32; 4],
}

impl SkyParams {
    pub fn new(sun_dir: Vec3, turbidity: f32) -> Self {
        let t = turbidity;
        let cy = [
            0.1787 * t - 1.4630,
            -0.3554 * t + 0.4275,
            -0.0227 * t + 5.3251,
            0.1206 * t - 2.5771,
            -0.0670 * t + 0.3703,
        ];
        let cx = [
            -0.0193 * t - 0.2592,
            -0.0665 * t + 0.0008,
            -0.0004 * t + 0.2125,
            -0.0641 * t - 0.8989,
            -0.0033 * t + 0.0452,
        ];
        let cyy = [
            -0.0167 * t - 0.2608,
            -0.0950 * t + 0.0092,
            -0.0079 * t + 0.2102,
            -0.0441 * t - 1.6537,
            -0.0109 * t + 0.0529,
        ];
        // The model is fitted for suns above the horizon; keep it there.
        let sun = Vec3::new(sun_dir.x, sun_dir.y.max(0.02), sun_dir.z).normalize();
        let ts = sun.y.clamp(-1.0, 1.0).acos();
        let chi = (4.0 / 9.0 - t / 120.0) * (std::f32::consts::PI - 2.0 * ts);
        let zy = ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192).max(0.05);
        let (t2, ts2, ts3) = (t * t, ts * ts, ts * ts * ts);
        let zx = t2 * (0.00166 * ts3 - 0.00375 * ts2 + 0.00209 * ts)
            + t * (-0.02903 * ts3 + 0.06377 * ts2 - 0.03202 * ts + 0.00394)
            + (0.11693 * ts3 - 0.21196 * ts2 + 0.06052 * ts + 0.25886);
        let zyy = t2 * (0.00275 * ts3 - 0.00610 * ts2 + 0.00317 * ts)
            + t * (-0.04214 * ts3 + 0.08970 * ts2 - 0.04153 * ts + 0.00516)
            + (0.15346 * ts3 - 0.26756 * ts2 + 0.06670 * ts + 0.26688);
        let f0 = |c| perez(1.0, ts, c);
        let omega_sun = 2.0 * std::f32::consts::PI * (1.0 - SUN_ANGULAR_RADIUS.cos());
        let e = sun_illuminance(sun_dir, turbidity);
        SkyParams {
            coeff_y: [cy[0], cy[1], cy[2], cy[3]],
            coeff_x: [cx[0], cx[1], cx[2], cx[3]],
            coeff_yy: [cyy[0], cyy[1], cyy[2], cyy[3]],
            coeff_e: [cy[4], cx[4], cyy[4], 0.0],
            zenith_over_f: [zy / f0(cy), zx / f0(cx), zyy / f0(cyy), 0.0],
            sun_direction: [sun_dir.x, sun_dir.y, sun_dir.z, SUN_ANGULAR_RADIUS.cos()],
            sun_illuminance: [e.x, e.y, e.z, 1.0 / omega_sun],
        }
    }
}

/// CIE xyY → linear sRGB (D65).
pub fn xyy_to_linear_srgb(x: f32, y: f32, luminance: f32) -> Vec3 {
    let y = y.max(1e-4);
    let (cx, cy, cz) = (x * luminance / y, luminance, (1.0 - x - y) * luminance / y);
    Vec3::new(
        3.2406 * cx - 1.5372 * cy - 0.4986 * cz,
        -0.9689 * cx + 1.8758 * cy + 0.0415 * cz,
        0.0557 * cx - 0.2040 * cy + 1.0570 * cz,
    )
    .max(Vec3::ZERO)
}

/// Sky radiance (kcd/m², linear sRGB) seen in direction `dir`, without the sun disk.
/// Below the horizon the horizon's radiance is returned (the open sea's
/// distant "ground" is sky reflected at grazing angles anyway).
pub fn sky_radiance(p: &SkyParams, dir: Vec3) -> Vec3 {
    let dir = dir.normalize();
    let sun =
        Vec3::new(p.sun_direction[0], p.sun_direction[1].max(0.02), p.sun_direction[2]).normalize();
    let cos_t = dir.y.max(0.0);
    let gamma = dir.dot(sun).clamp(-1.0, 1.0).acos();
    let c = |v: [f32; 4], e: f32| [v[0], v[1], v[2], v[3], e];
    let lum = p.zenith_over_f[0] * perez(cos_t, gamma, c(p.coeff_y, p.coeff_e[0]));
    let x = p.zenith_over_f[1] * perez(cos_t, gamma, c(p.coeff_x, p.coeff_e[1]));
    let y = p.zenith_over_f[2] * perez(cos_t, gamma, c(p.coeff_yy, p.coeff_e[2]));
    xyy_to_linear_srgb(x, y, lum)
}

/// Solar illuminance (klx, linear sRGB) on a plane facing the sun, after
/// Rayleigh and aerosol extinction along the air mass (Kasten–Young).
pub fn sun_illuminance(sun_dir: Vec3, turbidity: f32) -> Vec3 {
    let elevation = sun_dir.normalize().y.asin().to_degrees();
    if elevation <= -1.0 {
        return Vec3::ZERO;
    }
    let zenith = (90.0 - elevation).min(93.0);
    let air_mass =
        1.0 / (zenith.to_radians().cos().max(0.0) + 0.50572 * (96.07995 - zenith).powf(-1.6364));
    let beta = 0.04608 * turbidity - 0.04586;
    // Wavelengths (µm) standing for the sRGB primaries.
    let lambdas = [0.680f32, 0.550, 0.440];
    let t = lambdas.map(|l| {
        let rayleigh = 0.008735 * l.powf(-4.08);
        let aerosol = beta * l.powf(-1.3);
        (-air_mass * (rayleigh + aerosol)).exp()
    });
    // The extraterrestrial sun is slightly warm of D65 white in sRGB.
    Vec3::new(t[0] * 1.05, t[1], t[2] * 0.94) * SUN_ILLUMINANCE_TOP
}

/// Irradiance on an upward-facing plane from the sky dome alone (klx),
/// integrated numerically; used for the water body's ambient light.
pub fn sky_irradiance_up(p: &SkyParams) -> Vec3 {
    let (nt, np) = (24, 48);
    let mut sum = Vec3::ZERO;
    for i in 0..nt {
        let theta = (i as f32 + 0.5) / nt as f32 * std::f32::consts::FRAC_PI_2;
        for j in 0..np {
            let phi = (j as f32 + 0.5) / np as f32 * std::f32::consts::TAU;
            let d = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            let d_omega = theta.sin()
                * (std::f32::consts::FRAC_PI_2 / nt as f32)
                * (std::f32::consts::TAU / np as f32);
            sum += sky_radiance(p, d) * theta.cos() * d_omega;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clear_sky_is_blue_and_brighter_towards_the_sun() {
        let sun = sun_direction(45.0, 0.0);
        let p = SkyParams::new(sun, 2.5);
        let zenith = sky_radiance(&p, Vec3::Y);
        assert!(zenith.z > zenith.x, "zenith should be blue: {zenith}");
        let near_sun = sky_radiance(&p, sun_direction(40.0, 5.0));
        let away = sky_radiance(&p, sun_direction(40.0, 180.0));
        assert!(near_sun.length() > 2.0 * away.length());
        // Preetham's zenith luminance for T=2.5, θs=45° is a few kcd/m².
        let y = 0.2126 * zenith.x + 0.7152 * zenith.y + 0.0722 * zenith.z;
        assert!((1.0..15.0).contains(&y), "zenith luminance {y}");
    }

    #[test]
    fn low_sun_is_reddened_and_dimmer() {
        let noon = sun_illuminance(sun_direction(70.0, 0.0), 2.5);
        let dusk = sun_illuminance(sun_direction(3.0, 0.0), 2.5);
        assert!(dusk.x / dusk.z > 2.0 * noon.x / noon.z, "noon {noon} dusk {dusk}");
        assert!(dusk.y < 0.5 * noon.y);
        // Clear noon sun: roughly 90–110 klx.
        assert!((70.0..120.0).contains(&noon.y), "{noon}");
    }

    #[test]
    fn sky_irradiance_is_a_fraction_of_the_sun() {
        let sun = sun_direction(45.0, 0.0);
        let p = SkyParams::new(sun, 2.5);
        let sky = sky_irradiance_up(&p).y;
        let direct = sun_illuminance(sun, 2.5).y * sun.y;
        assert!(sky > 0.05 * direct && sky < 0.6 * direct, "sky {sky} sun {direct}");
    }
}
