//! A physically based atmosphere for the sky (issue #32 item 3: a sky that
//! holds at every sun height). Rayleigh and Mie scattering and ozone
//! absorption over a spherical Earth; single scattering marched along the
//! view ray, and all higher orders by Hillaire's multiple-scattering term
//! (S. Hillaire, *A Scalable and Production Ready Sky and Atmosphere
//! Rendering Technique*, EGSR 2020, §5.5). The transmittance table is
//! parametrised as in E. Bruneton, *Precomputed Atmospheric Scattering: a
//! New Implementation* (2017), and the constants are that implementation's
//! Earth. Seed 000 §3.1 names the sky as the light the water reflects;
//! Preetham's fit (`crate::sky`) stays selectable.
//!
//! Three tables are built in order, on the CPU here and on the GPU by
//! `passes/sky/atmosphere.wgsl` (same sizes, same samples, same order):
//! transmittance to the top of the atmosphere, the multiple-scattering
//! source Ψ, and the sky seen from sea level in a latitude–azimuth frame
//! around the sun. The sky-view table is what the cube map and the
//! background read.
//!
//! Units: lengths in km, scattering in 1/km; radiance per unit solar
//! illuminance above the atmosphere until scaled by
//! `crate::sky::SUN_ILLUMINANCE_TOP` and the sun's colour.

use glam::Vec3;
use std::f32::consts::PI;

/// Radius of the ground (km).
pub const BOTTOM_RADIUS: f32 = 6360.0;
/// Radius of the top of the atmosphere (km).
pub const TOP_RADIUS: f32 = 6460.0;
/// Where the ozone layer is densest and how far its density falls to zero
/// on either side (km): Bruneton's tent between 10 and 40 km.
pub const OZONE_CENTER: f32 = 25.0;
pub const OZONE_HALF_WIDTH: f32 = 15.0;
/// The observer's height above the ground (km): the camera's few metres do
/// not change the sky.
pub const OBSERVER_HEIGHT: f32 = 0.001;

/// Table sizes (texels), shared with the GPU.
pub const TRANSMITTANCE_SIZE: (usize, usize) = (256, 64);
pub const MULTISCATTERING_SIZE: (usize, usize) = (32, 32);
pub const SKY_VIEW_SIZE: (usize, usize) = (192, 108);
/// Samples along a ray for each table.
pub const TRANSMITTANCE_STEPS: usize = 40;
pub const MULTISCATTERING_STEPS: usize = 20;
/// Directions over the sphere for Ψ: an 8 × 8 grid, equal in solid angle.
pub const MULTISCATTERING_DIRECTIONS: usize = 8;
pub const SKY_VIEW_STEPS: usize = 40;

/// The air: scattering and absorption coefficients at sea level and how
/// they fall off with height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Atmosphere {
    /// Rayleigh scattering at sea level (1/km) for the sRGB primaries
    /// (680, 550, 440 nm).
    pub rayleigh_scattering: Vec3,
    pub rayleigh_height: f32,
    /// Aerosol (Mie) scattering and extinction at sea level (1/km), falling
    /// with wavelength by Ångström's law.
    pub mie_scattering: Vec3,
    pub mie_extinction: Vec3,
    pub mie_height: f32,
    /// Asymmetry of the aerosols' phase function (Cornette–Shanks).
    pub mie_g: f32,
    /// Ozone absorption at the layer's peak (1/km).
    pub ozone_absorption: Vec3,
    /// The ground's Lambertian albedo (the sea, mostly).
    pub ground_albedo: f32,
}

impl Atmosphere {
    /// Bruneton's Earth (air, ozone, the aerosols' height, phase and
    /// single-scattering albedo) with as many aerosols as Preetham's
    /// turbidity says, so the `[sky]` setting keeps its meaning for both
    /// models: turbidity is the ratio of the total vertical optical depth
    /// to the air's alone (T = 1 is air without aerosols), so the aerosols'
    /// optical depth is (T − 1) times Rayleigh's at 550 nm (0.11): 0.16 at
    /// T = 2.5, a clear day's. Across wavelengths it goes as λ^−1.3
    /// (Ångström's exponent for continental and maritime aerosols, the one
    /// Preetham's sun colour uses).
    pub fn earth(turbidity: f32) -> Self {
        let (rayleigh_height, mie_height) = (8.0, 1.2);
        let rayleigh_scattering = Vec3::new(5.802e-3, 13.558e-3, 33.1e-3);
        let aerosol_depth = (turbidity - 1.0).max(0.0) * rayleigh_scattering.y * rayleigh_height;
        let angstrom = Vec3::new(0.680f32, 0.550, 0.440).map(|l| (l / 0.55).powf(-1.3));
        let mie_extinction = angstrom * aerosol_depth / mie_height;
        Atmosphere {
            rayleigh_scattering,
            rayleigh_height,
            // Bruneton's aerosols scatter 90% of what they take out.
            mie_scattering: 0.9 * mie_extinction,
            mie_extinction,
            mie_height,
            mie_g: 0.7,
            ozone_absorption: Vec3::new(0.650e-3, 1.881e-3, 0.085e-3),
            ground_albedo: 0.1,
        }
    }

    /// Rayleigh and Mie scattering (1/km) at height `h` (km).
    pub fn scattering(&self, h: f32) -> (Vec3, Vec3) {
        let h = h.max(0.0);
        (
            self.rayleigh_scattering * (-h / self.rayleigh_height).exp(),
            self.mie_scattering * (-h / self.mie_height).exp(),
        )
    }

    /// Extinction (1/km) at height `h` (km).
    pub fn extinction(&self, h: f32) -> Vec3 {
        let h = h.max(0.0);
        let ozone = (1.0 - (h - OZONE_CENTER).abs() / OZONE_HALF_WIDTH).max(0.0);
        self.rayleigh_scattering * (-h / self.rayleigh_height).exp()
            + self.mie_extinction * (-h / self.mie_height).exp()
            + self.ozone_absorption * ozone
    }

    /// Transmittance from radius `r` along a ray of zenith cosine `mu` to the
    /// top of the atmosphere, integrated directly (no table): the reference
    /// the table is tested against, and the sun's colour.
    pub fn transmittance_to_top(&self, r: f32, mu: f32) -> Vec3 {
        let d = distance_to_top(r, mu);
        let n = 200;
        let dt = d / n as f32;
        let depth: Vec3 = (0..n)
            .map(|i| self.extinction(radius_at(r, mu, (i as f32 + 0.5) * dt) - BOTTOM_RADIUS))
            .sum();
        (-depth * dt).exp()
    }
}

/// Distance from radius `r` along zenith cosine `mu` to the top boundary.
pub fn distance_to_top(r: f32, mu: f32) -> f32 {
    let disc = r * r * (mu * mu - 1.0) + TOP_RADIUS * TOP_RADIUS;
    (-r * mu + disc.max(0.0).sqrt()).max(0.0)
}

/// Distance from radius `r` along zenith cosine `mu` to the ground (only
/// meaningful where [`hits_ground`]).
pub fn distance_to_ground(r: f32, mu: f32) -> f32 {
    let disc = r * r * (mu * mu - 1.0) + BOTTOM_RADIUS * BOTTOM_RADIUS;
    (-r * mu - disc.max(0.0).sqrt()).max(0.0)
}

/// Whether a ray from radius `r` along zenith cosine `mu` meets the ground.
pub fn hits_ground(r: f32, mu: f32) -> bool {
    mu < 0.0 && r * r * (mu * mu - 1.0) + BOTTOM_RADIUS * BOTTOM_RADIUS >= 0.0
}

/// Radius at distance `t` along a ray from radius `r`, zenith cosine `mu`.
pub fn radius_at(r: f32, mu: f32, t: f32) -> f32 {
    (t * t + 2.0 * r * mu * t + r * r).max(0.0).sqrt()
}

/// Rayleigh's phase function.
pub fn rayleigh_phase(nu: f32) -> f32 {
    3.0 / (16.0 * PI) * (1.0 + nu * nu)
}

/// Cornette–Shanks' phase function for aerosols.
pub fn mie_phase(g: f32, nu: f32) -> f32 {
    let k = 3.0 / (8.0 * PI) * (1.0 - g * g) / (2.0 + g * g);
    k * (1.0 + nu * nu) / (1.0 + g * g - 2.0 * g * nu).max(1e-6).powf(1.5)
}

/// A texel-centred coordinate for `x ∈ [0, 1]` on `n` texels: 0 and 1 fall
/// on the first and last texels' centres.
pub fn unit_to_texel(x: f32, n: usize) -> f32 {
    0.5 / n as f32 + x * (1.0 - 1.0 / n as f32)
}

/// The transmittance table's coordinates for (r, μ) (Bruneton 2017 §4.1).
pub fn transmittance_uv(r: f32, mu: f32) -> (f32, f32) {
    let h = (TOP_RADIUS * TOP_RADIUS - BOTTOM_RADIUS * BOTTOM_RADIUS).sqrt();
    let rho = (r * r - BOTTOM_RADIUS * BOTTOM_RADIUS).max(0.0).sqrt();
    let d = distance_to_top(r, mu);
    let (d_min, d_max) = (TOP_RADIUS - r, rho + h);
    let x_mu = ((d - d_min) / (d_max - d_min).max(1e-6)).clamp(0.0, 1.0);
    (unit_to_texel(x_mu, TRANSMITTANCE_SIZE.0), unit_to_texel(rho / h, TRANSMITTANCE_SIZE.1))
}

/// (r, μ) at the centre of the transmittance table's texel (i, j).
pub fn transmittance_texel(i: usize, j: usize) -> (f32, f32) {
    let (x_mu, x_r) = (
        i as f32 / (TRANSMITTANCE_SIZE.0 - 1) as f32,
        j as f32 / (TRANSMITTANCE_SIZE.1 - 1) as f32,
    );
    let h = (TOP_RADIUS * TOP_RADIUS - BOTTOM_RADIUS * BOTTOM_RADIUS).sqrt();
    let rho = h * x_r;
    let r = (rho * rho + BOTTOM_RADIUS * BOTTOM_RADIUS).sqrt();
    let (d_min, d_max) = (TOP_RADIUS - r, rho + h);
    let d = d_min + x_mu * (d_max - d_min);
    let mu = if d == 0.0 { 1.0 } else { (h * h - rho * rho - d * d) / (2.0 * r * d) };
    (r, mu.clamp(-1.0, 1.0))
}

/// The multiple-scattering table's coordinates for (r, μs): the sun's
/// zenith cosine across, height up.
pub fn multiscattering_uv(r: f32, mu_s: f32) -> (f32, f32) {
    let height = ((r - BOTTOM_RADIUS) / (TOP_RADIUS - BOTTOM_RADIUS)).clamp(0.0, 1.0);
    (
        unit_to_texel(mu_s.clamp(-1.0, 1.0) * 0.5 + 0.5, MULTISCATTERING_SIZE.0),
        unit_to_texel(height, MULTISCATTERING_SIZE.1),
    )
}

/// The sky-view table's coordinates for a view direction: the azimuth from
/// the sun's across (0 towards it, π away; the sky is symmetric about the
/// sun's vertical plane), the elevation up on a square-root scale so the
/// horizon, where the sky changes fastest, gets the most rows. Below the
/// horizon the horizon's row is used (the sea reflects it there).
pub fn sky_view_uv(dir: Vec3, sun: Vec3) -> (f32, f32) {
    let elevation = dir.y.clamp(0.0, 1.0).asin();
    let flat = |v: Vec3| {
        let l = (v.x * v.x + v.z * v.z).sqrt();
        if l > 1e-6 { (v.x / l, v.z / l) } else { (1.0, 0.0) }
    };
    let (d, s) = (flat(dir), flat(sun));
    let azimuth = (d.0 * s.0 + d.1 * s.1).clamp(-1.0, 1.0).acos();
    (
        unit_to_texel(azimuth / PI, SKY_VIEW_SIZE.0),
        unit_to_texel((elevation / (PI / 2.0)).sqrt(), SKY_VIEW_SIZE.1),
    )
}

/// A table of RGB values, sampled bilinearly with clamped edges like a
/// GPU's linear sampler.
#[derive(Clone, Debug)]
pub struct Table {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
}

impl Table {
    fn build(size: (usize, usize), f: impl Fn(usize, usize) -> Vec3) -> Self {
        let texels =
            (0..size.1).flat_map(|j| (0..size.0).map(move |i| (i, j))).map(|(i, j)| f(i, j));
        Table { width: size.0, height: size.1, texels: texels.collect() }
    }

    pub fn texel(&self, i: usize, j: usize) -> Vec3 {
        self.texels[j * self.width + i]
    }

    /// Bilinear lookup at (u, v) ∈ [0, 1]², texel centres at (i + ½)/n.
    pub fn sample(&self, u: f32, v: f32) -> Vec3 {
        let x = (u * self.width as f32 - 0.5).clamp(0.0, (self.width - 1) as f32);
        let y = (v * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (i, j) = (x.floor() as usize, y.floor() as usize);
        let (i1, j1) = ((i + 1).min(self.width - 1), (j + 1).min(self.height - 1));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let top = self.texel(i, j).lerp(self.texel(i1, j), fx);
        let bottom = self.texel(i, j1).lerp(self.texel(i1, j1), fx);
        top.lerp(bottom, fy)
    }
}

/// The first two tables: they depend on the air only, not on the sun.
#[derive(Clone, Debug)]
pub struct AtmosphereTables {
    pub atmosphere: Atmosphere,
    pub transmittance: Table,
    pub multiscattering: Table,
}

impl AtmosphereTables {
    pub fn new(atmosphere: Atmosphere) -> Self {
        let transmittance = Table::build(TRANSMITTANCE_SIZE, |i, j| {
            let (r, mu) = transmittance_texel(i, j);
            // Segments that lengthen away from the start, where the air is
            // densest for every ray that does not dip (the aerosols' 1.2 km
            // would fall between evenly spaced samples).
            let d = distance_to_top(r, mu);
            let n = TRANSMITTANCE_STEPS as f32;
            let depth: Vec3 = (0..TRANSMITTANCE_STEPS)
                .map(|k| {
                    let (t0, t1) = (d * (k as f32 / n).powi(2), d * ((k as f32 + 1.0) / n).powi(2));
                    let t = 0.5 * (t0 + t1);
                    atmosphere.extinction(radius_at(r, mu, t) - BOTTOM_RADIUS) * (t1 - t0)
                })
                .sum();
            (-depth).exp()
        });
        let mut tables = AtmosphereTables {
            atmosphere,
            transmittance,
            multiscattering: Table { width: 1, height: 1, texels: vec![Vec3::ZERO] },
        };
        tables.multiscattering = Table::build(MULTISCATTERING_SIZE, |i, j| {
            let mu_s = -1.0 + 2.0 * i as f32 / (MULTISCATTERING_SIZE.0 - 1) as f32;
            let r = BOTTOM_RADIUS
                + (TOP_RADIUS - BOTTOM_RADIUS) * j as f32 / (MULTISCATTERING_SIZE.1 - 1) as f32;
            tables.multiscattering_source(r.max(BOTTOM_RADIUS + 1e-3), mu_s)
        });
        tables
    }

    /// Transmittance from radius `r` towards zenith cosine `mu` to the top
    /// of the atmosphere, from the table; zero through the ground.
    pub fn transmittance(&self, r: f32, mu: f32) -> Vec3 {
        if hits_ground(r, mu) {
            return Vec3::ZERO;
        }
        let (u, v) = transmittance_uv(r, mu);
        self.transmittance.sample(u, v)
    }

    /// Ψ of Hillaire 2020 eq. 10: the light of every scattering order above
    /// the first reaching a point at radius `r` under a sun of zenith
    /// cosine `mu_s`, per unit solar illuminance, isotropic. The second
    /// order is gathered over 64 directions (with the ground's bounce), and
    /// the orders after it as the geometric series 1/(1 − f_ms).
    fn multiscattering_source(&self, r: f32, mu_s: f32) -> Vec3 {
        let atm = &self.atmosphere;
        let sun = Vec3::new((1.0 - mu_s * mu_s).max(0.0).sqrt(), mu_s, 0.0);
        let origin = Vec3::new(0.0, r, 0.0);
        let n = MULTISCATTERING_DIRECTIONS;
        let (mut second, mut transfer) = (Vec3::ZERO, Vec3::ZERO);
        for a in 0..n {
            let cos_theta = 1.0 - 2.0 * (a as f32 + 0.5) / n as f32;
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            for b in 0..n {
                let phi = 2.0 * PI * (b as f32 + 0.5) / n as f32;
                let dir = Vec3::new(sin_theta * phi.cos(), cos_theta, sin_theta * phi.sin());
                let ground = hits_ground(r, cos_theta);
                let t_max = if ground {
                    distance_to_ground(r, cos_theta)
                } else {
                    distance_to_top(r, cos_theta)
                };
                let dt = t_max / MULTISCATTERING_STEPS as f32;
                let mut throughput = Vec3::ONE;
                for k in 0..MULTISCATTERING_STEPS {
                    let p = origin + dir * ((k as f32 + 0.5) * dt);
                    let rp = p.length();
                    let (rayleigh, mie) = atm.scattering(rp - BOTTOM_RADIUS);
                    let scattering = rayleigh + mie;
                    let extinction = atm.extinction(rp - BOTTOM_RADIUS);
                    let step = (-extinction * dt).exp();
                    let sun_t = self.transmittance(rp, p.dot(sun) / rp);
                    let through = (Vec3::ONE - step) / extinction;
                    second += throughput * scattering * sun_t / (4.0 * PI) * through;
                    transfer += throughput * scattering * through;
                    throughput *= step;
                }
                if ground {
                    let p = origin + dir * t_max;
                    let up = p.normalize();
                    let mu = up.dot(sun);
                    second += throughput
                        * self.transmittance(BOTTOM_RADIUS, mu)
                        * mu.max(0.0)
                        * atm.ground_albedo
                        / PI;
                }
            }
        }
        let count = (n * n) as f32;
        let (second, transfer) = (second / count, transfer / count);
        second / (Vec3::ONE - transfer)
    }

    /// Ψ from its table.
    pub fn multiscattering(&self, r: f32, mu_s: f32) -> Vec3 {
        let (u, v) = multiscattering_uv(r, mu_s);
        self.multiscattering.sample(u, v)
    }

    /// Radiance per unit solar illuminance reaching the observer along
    /// `dir` under the sun in `sun` (unit vectors, y up): single scattering
    /// marched in 40 segments that lengthen away from the eye, plus σs·Ψ
    /// for the rest (Hillaire 2020 eq. 11). The ground and the sun's disc
    /// are not included.
    pub fn march(&self, dir: Vec3, sun: Vec3) -> Vec3 {
        let atm = &self.atmosphere;
        let r = BOTTOM_RADIUS + OBSERVER_HEIGHT;
        let mu = dir.y;
        let t_max =
            if hits_ground(r, mu) { distance_to_ground(r, mu) } else { distance_to_top(r, mu) };
        let nu = dir.dot(sun);
        let (phase_r, phase_m) = (rayleigh_phase(nu), mie_phase(atm.mie_g, nu));
        let origin = Vec3::new(0.0, r, 0.0);
        let (mut radiance, mut throughput) = (Vec3::ZERO, Vec3::ONE);
        let n = SKY_VIEW_STEPS as f32;
        for k in 0..SKY_VIEW_STEPS {
            let (t0, t1) = (t_max * (k as f32 / n).powi(2), t_max * ((k as f32 + 1.0) / n).powi(2));
            let dt = t1 - t0;
            let p = origin + dir * (0.5 * (t0 + t1));
            let rp = p.length();
            let mu_s = p.dot(sun) / rp;
            let (rayleigh, mie) = atm.scattering(rp - BOTTOM_RADIUS);
            let extinction = atm.extinction(rp - BOTTOM_RADIUS);
            let step = (-extinction * dt).exp();
            let sun_t = self.transmittance(rp, mu_s);
            let source = (rayleigh * phase_r + mie * phase_m) * sun_t
                + (rayleigh + mie) * self.multiscattering(rp, mu_s);
            radiance += throughput * source * (Vec3::ONE - step) / extinction;
            throughput *= step;
        }
        radiance
    }

    /// The sky-view table under the sun at elevation `sun_elevation`
    /// (radians): texel (i, j) looks at azimuth π·i/(w−1) from the sun and
    /// elevation (π/2)·(j/(h−1))².
    pub fn sky_view(&self, sun_elevation: f32) -> Table {
        let sun = Vec3::new(sun_elevation.cos(), sun_elevation.sin(), 0.0);
        Table::build(SKY_VIEW_SIZE, |i, j| self.march(sky_view_direction(i, j), sun))
    }
}

/// The view direction at the centre of the sky-view table's texel (i, j),
/// in a frame whose sun lies in the x–y plane (x towards it).
pub fn sky_view_direction(i: usize, j: usize) -> Vec3 {
    let azimuth = PI * i as f32 / (SKY_VIEW_SIZE.0 - 1) as f32;
    let y = j as f32 / (SKY_VIEW_SIZE.1 - 1) as f32;
    let elevation = PI / 2.0 * y * y;
    Vec3::new(elevation.cos() * azimuth.cos(), elevation.sin(), elevation.cos() * azimuth.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn luminance(c: Vec3) -> f32 {
        0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
    }

    #[test]
    fn table_coordinates_invert() {
        for (i, j) in [(0, 0), (17, 3), (128, 40), (255, 63), (200, 1)] {
            let (r, mu) = transmittance_texel(i, j);
            let (u, v) = transmittance_uv(r, mu);
            let (ui, vj) = (
                (i as f32 + 0.5) / TRANSMITTANCE_SIZE.0 as f32,
                (j as f32 + 0.5) / TRANSMITTANCE_SIZE.1 as f32,
            );
            assert!((u - ui).abs() < 2e-3 && (v - vj).abs() < 1e-4, "{i},{j}: {u},{v}");
        }
        let sun = Vec3::new(0.3, 0.2, 0.9).normalize();
        for (i, j) in [(0, 0), (50, 20), (191, 100), (96, 54)] {
            // The table's frame turned so its sun lies under `sun`.
            let local = sky_view_direction(i, j);
            let (sx, sz) = (sun.x, sun.z);
            let l = (sx * sx + sz * sz).sqrt();
            let (c, s) = (sx / l, sz / l);
            let dir = Vec3::new(local.x * c - local.z * s, local.y, local.x * s + local.z * c);
            let (u, v) = sky_view_uv(dir, sun);
            let (ui, vj) = (
                (i as f32 + 0.5) / SKY_VIEW_SIZE.0 as f32,
                (j as f32 + 0.5) / SKY_VIEW_SIZE.1 as f32,
            );
            assert!((u - ui).abs() < 2e-3 && (v - vj).abs() < 2e-3, "{i},{j}: {u},{v}");
        }
    }

    #[test]
    fn transmittance_table_matches_direct_integration_and_beer_lambert() {
        let tables = AtmosphereTables::new(Atmosphere::earth(2.5));
        let atm = tables.atmosphere;
        for (h, mu) in [(0.0, 1.0), (0.0, 0.2), (0.0, 0.02), (5.0, -0.03), (30.0, 0.5)] {
            let r = BOTTOM_RADIUS + h;
            let table = tables.transmittance(r, mu);
            let direct = atm.transmittance_to_top(r, mu);
            // Relative, or against 1% where almost nothing passes.
            let rel = ((table - direct).abs() / direct.max(Vec3::splat(0.01))).max_element();
            assert!(rel < 0.03, "h {h} mu {mu}: table {table} direct {direct}");
        }
        // Straight up, the optical depth is a closed form: the scale height
        // times the sea-level coefficient for each exponential layer (the
        // 100 km top leaves e^-12.5 of Rayleigh's), plus the ozone tent's
        // area (its half width times its peak).
        let depth = atm.rayleigh_scattering * atm.rayleigh_height * (1.0 - (-100.0f32 / 8.0).exp())
            + atm.mie_extinction * atm.mie_height
            + atm.ozone_absorption * OZONE_HALF_WIDTH;
        let expected = (-depth).exp();
        let got = atm.transmittance_to_top(BOTTOM_RADIUS, 1.0);
        assert!((got - expected).abs().max_element() < 2e-3, "{got} vs {expected}");
        // Through the ground nothing passes.
        assert_eq!(tables.transmittance(BOTTOM_RADIUS + 1.0, -0.5), Vec3::ZERO);
    }

    #[test]
    fn rayleigh_only_zenith_sky_matches_single_scattering_closed_form() {
        // A thin, optically weak air (Rayleigh only, about a hundredth of
        // Earth's) under a zenith sun: the zenith's radiance is the sun's
        // light scattered along the vertical, a closed form to first order.
        let atm = Atmosphere {
            rayleigh_scattering: Vec3::splat(1e-4),
            mie_scattering: Vec3::ZERO,
            mie_extinction: Vec3::ZERO,
            ozone_absorption: Vec3::ZERO,
            ground_albedo: 0.0,
            ..Atmosphere::earth(2.5)
        };
        let tables = AtmosphereTables::new(atm);
        let single_only = AtmosphereTables {
            multiscattering: Table { width: 1, height: 1, texels: vec![Vec3::ZERO] },
            ..tables.clone()
        };
        let l = single_only.march(Vec3::Y, Vec3::Y).x;
        let h = atm.rayleigh_height;
        // Along the zenith the path to the sun is the path back: the beam
        // reaching height z has passed 100 − z km; to first order in β the
        // transmittance is 1, so L = P(1) β ∫ e^{−z/H} dz.
        let expected = rayleigh_phase(1.0) * 1e-4 * h * (1.0 - (-(100.0 - 0.001) / h).exp());
        assert!((l - expected).abs() / expected < 0.02, "{l} vs {expected}");
        // Higher orders are second order in β: a few percent here.
        let all = tables.march(Vec3::Y, Vec3::Y).x;
        assert!(all > l && all < l * 1.05, "{all} vs {l}");
    }

    #[test]
    fn the_sky_is_blue_by_day_and_red_at_sunset() {
        let tables = AtmosphereTables::new(Atmosphere::earth(2.5));
        let noon = Vec3::new(0.5f32.cos(), 0.5f32.sin(), 0.0).normalize();
        let zenith = tables.march(Vec3::Y, noon);
        assert!(zenith.z > 1.5 * zenith.x, "zenith {zenith}");
        // Per unit illuminance; × 128 klx this is a few kcd/m², Preetham's range.
        let y = luminance(zenith) * crate::sky::SUN_ILLUMINANCE_TOP;
        assert!((1.0..10.0).contains(&y), "zenith luminance {y}");
        // At sunset the horizon under the sun is reddest; the sky opposite
        // stays bluish; the zenith is darker than by day.
        let sunset = Vec3::new(3f32.to_radians().cos(), 3f32.to_radians().sin(), 0.0);
        let under_sun = tables.march(Vec3::new(1.0, 0.02, 0.0).normalize(), sunset);
        let opposite = tables.march(Vec3::new(-1.0, 0.3, 0.0).normalize(), sunset);
        assert!(under_sun.x > 1.8 * under_sun.z, "under the sun {under_sun}");
        assert!(opposite.z > opposite.x, "opposite {opposite}");
        let dim = luminance(tables.march(Vec3::Y, sunset)) / luminance(zenith);
        assert!(dim < 0.5, "sunset zenith / noon zenith {dim}");
        // Multiple scattering keeps the twilight sky lit after sunset.
        let dusk = Vec3::new(4f32.to_radians().cos(), -(4f32.to_radians().sin()), 0.0);
        assert!(luminance(tables.march(Vec3::Y, dusk)) > 0.0);
    }

    #[test]
    fn the_sky_view_table_agrees_with_marching() {
        let tables = AtmosphereTables::new(Atmosphere::earth(3.5));
        let elevation = 4f32.to_radians();
        let view = tables.sky_view(elevation);
        let sun = Vec3::new(elevation.cos(), elevation.sin(), 0.0);
        for dir in
            [Vec3::new(0.9, 0.05, 0.3), Vec3::new(-0.2, 0.6, 0.7), Vec3::new(1.0, 0.001, 0.0)]
        {
            let dir = dir.normalize();
            let (u, v) = sky_view_uv(dir, sun);
            let (table, marched) = (view.sample(u, v), tables.march(dir, sun));
            let rel = ((table - marched).abs() / marched).max_element();
            assert!(rel < 0.05, "{dir}: {table} vs {marched}");
        }
    }
}
