//! The daylight sky, by one of two models: a physically based atmosphere
//! (`crate::atmosphere`, the default: Rayleigh, Mie and ozone over a round
//! Earth, which holds at every sun height) or Preetham, Shirley & Smits'
//! analytic fit, *A Practical Analytic Model for Daylight* (SIGGRAPH 1999),
//! with the sun's colour from the same paper's Rayleigh + aerosol
//! transmittance. Either is written into a sky-view table and baked into an
//! environment cube map (seed 000 §3.1.2) by `passes/sky`; [`Sky`] is the
//! CPU twin of what they hold.
//!
//! Units: radiance in kcd/m² (Preetham's zenith luminance unit), illuminance
//! in klx, so a clear noon sky is a few units and the sun ~100.

use glam::Vec3;

/// Angular radius of the sun (radians).
pub const SUN_ANGULAR_RADIUS: f32 = 0.004_65;
/// Solar illuminance above the atmosphere, klx.
pub const SUN_ILLUMINANCE_TOP: f32 = 128.0;
/// The extraterrestrial sun's colour in linear sRGB (slightly warm of D65).
pub const SUN_TOP_COLOUR: Vec3 = Vec3::new(1.05, 1.0, 0.94);

/// Which model draws the sky (`SkyParams::model[0]`).
pub const MODEL_PREETHAM: u32 = 0;
pub const MODEL_PHYSICAL: u32 = 1;

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
    /// The physical atmosphere (`crate::atmosphere::Atmosphere`): Rayleigh
    /// scattering (1/km) and its scale height (km);
    pub rayleigh: [f32; 4],
    /// Mie scattering (1/km) and its scale height (km);
    pub mie: [f32; 4],
    /// Mie extinction (1/km) and the phase function's g;
    pub mie_extinction: [f32; 4],
    /// ozone's peak absorption (1/km) and the ground's albedo.
    pub ozone: [f32; 4],
    /// x: [`MODEL_PREETHAM`] or [`MODEL_PHYSICAL`].
    pub model: [u32; 4],
}

impl SkyParams {
    /// The physically based sky (`crate::atmosphere`) for this sun, with
    /// aerosols set by Preetham's turbidity. The sun is dimmed and reddened
    /// by the same air the sky scatters in, and sets below the horizon.
    pub fn physical(sun_dir: Vec3, turbidity: f32) -> Self {
        let atm = crate::atmosphere::Atmosphere::earth(turbidity);
        let sun = sun_dir.normalize();
        let r = crate::atmosphere::BOTTOM_RADIUS + crate::atmosphere::OBSERVER_HEIGHT;
        let through = if crate::atmosphere::hits_ground(r, sun.y) {
            Vec3::ZERO
        } else {
            atm.transmittance_to_top(r, sun.y)
        };
        let e = through * SUN_TOP_COLOUR * SUN_ILLUMINANCE_TOP;
        let omega_sun = 2.0 * std::f32::consts::PI * (1.0 - SUN_ANGULAR_RADIUS.cos());
        let rs = atm.rayleigh_scattering;
        SkyParams {
            sun_direction: [sun.x, sun.y, sun.z, SUN_ANGULAR_RADIUS.cos()],
            sun_illuminance: [e.x, e.y, e.z, 1.0 / omega_sun],
            rayleigh: [rs.x, rs.y, rs.z, atm.rayleigh_height],
            mie: atm.mie_scattering.extend(atm.mie_height).into(),
            mie_extinction: atm.mie_extinction.extend(atm.mie_g).into(),
            ozone: [
                atm.ozone_absorption.x,
                atm.ozone_absorption.y,
                atm.ozone_absorption.z,
                atm.ground_albedo,
            ],
            model: [MODEL_PHYSICAL, 0, 0, 0],
            ..Default::default()
        }
    }

    /// The atmosphere these parameters describe (the physical model's air).
    pub fn atmosphere(&self) -> crate::atmosphere::Atmosphere {
        crate::atmosphere::Atmosphere {
            rayleigh_scattering: Vec3::new(self.rayleigh[0], self.rayleigh[1], self.rayleigh[2]),
            rayleigh_height: self.rayleigh[3],
            mie_scattering: Vec3::new(self.mie[0], self.mie[1], self.mie[2]),
            mie_extinction: Vec3::new(
                self.mie_extinction[0],
                self.mie_extinction[1],
                self.mie_extinction[2],
            ),
            mie_height: self.mie[3],
            mie_g: self.mie_extinction[3],
            ozone_absorption: Vec3::new(self.ozone[0], self.ozone[1], self.ozone[2]),
            ground_albedo: self.ozone[3],
        }
    }

    pub fn is_physical(&self) -> bool {
        self.model[0] == MODEL_PHYSICAL
    }

    /// Preetham's analytic sky for this sun and turbidity.
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
            model: [MODEL_PREETHAM, 0, 0, 0],
            ..Default::default()
        }
    }
}

/// The sky as the GPU holds it, on the CPU: what the cube map and the
/// background show in each direction (kcd/m², the sun's disc apart; below
/// the horizon the horizon's radiance).
#[derive(Clone, Debug)]
pub struct Sky {
    pub params: SkyParams,
    /// The physical model's tables and its sky-view table.
    physical: Option<(crate::atmosphere::AtmosphereTables, crate::atmosphere::Table)>,
}

impl Sky {
    pub fn new(params: SkyParams) -> Self {
        let physical = params.is_physical().then(|| {
            let tables = crate::atmosphere::AtmosphereTables::new(params.atmosphere());
            let view = tables.sky_view(params.sun_direction[1].clamp(-1.0, 1.0).asin());
            (tables, view)
        });
        Sky { params, physical }
    }

    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match &self.physical {
            // Below the horizon, the horizon in the same azimuth (as the
            // sky-view table holds it).
            None if dir.y < 0.0 && dir.x.abs() + dir.z.abs() > 0.0 => {
                sky_radiance(&self.params, Vec3::new(dir.x, 0.0, dir.z))
            }
            None => sky_radiance(&self.params, dir),
            Some((_, view)) => {
                let sun = Vec3::from_slice(&self.params.sun_direction[..3]);
                let (u, v) = crate::atmosphere::sky_view_uv(dir.normalize(), sun);
                view.sample(u, v) * SUN_TOP_COLOUR * SUN_ILLUMINANCE_TOP
            }
        }
    }

    /// The physical model's tables (None for Preetham).
    pub fn tables(&self) -> Option<&crate::atmosphere::AtmosphereTables> {
        self.physical.as_ref().map(|(t, _)| t)
    }

    /// The physical model's sky-view table, per unit solar illuminance.
    pub fn view_table(&self) -> Option<&crate::atmosphere::Table> {
        self.physical.as_ref().map(|(_, v)| v)
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

/// Preetham's sky radiance (kcd/m², linear sRGB) seen in direction `dir`,
/// without the sun disk ([`Sky::radiance`] for either model).
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
    Vec3::from(t) * SUN_TOP_COLOUR * SUN_ILLUMINANCE_TOP
}

/// Irradiance on an upward-facing plane from the sky dome alone (klx),
/// integrated numerically; used for the water body's ambient light.
pub fn sky_irradiance_up(sky: &Sky) -> Vec3 {
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
            sum += sky.radiance(d) * theta.cos() * d_omega;
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
        let sky = sky_irradiance_up(&Sky::new(p)).y;
        let direct = sun_illuminance(sun, 2.5).y * sun.y;
        assert!(sky > 0.05 * direct && sky < 0.6 * direct, "sky {sky} sun {direct}");
    }

    #[test]
    fn the_physical_sun_is_dimmed_reddened_and_sets() {
        let noon = SkyParams::physical(sun_direction(70.0, 0.0), 2.5).sun_illuminance;
        let dusk = SkyParams::physical(sun_direction(3.0, 0.0), 2.5).sun_illuminance;
        // Clear noon sun: roughly 90–110 klx, as Preetham's model gives.
        assert!((85.0..120.0).contains(&noon[1]), "{noon:?}");
        assert!(dusk[0] / dusk[2] > 3.0 * noon[0] / noon[2], "noon {noon:?} dusk {dusk:?}");
        let set = SkyParams::physical(sun_direction(-2.0, 0.0), 2.5).sun_illuminance;
        assert_eq!(&set[..3], &[0.0; 3]);
        // Preetham and the atmosphere agree on a clear midday sky to within
        // a factor of two on the level (they are different models).
        let sun = sun_direction(45.0, 0.0);
        let preetham = sky_irradiance_up(&Sky::new(SkyParams::new(sun, 2.5))).y;
        let physical = sky_irradiance_up(&Sky::new(SkyParams::physical(sun, 2.5))).y;
        assert!(physical > 0.5 * preetham && physical < 2.0 * preetham, "{physical} vs {preetham}");
    }
}
