//! Image-based diffuse light (issue #32): the irradiance the sky and the
//! grey world below the horizon give a surface of any normal, as nine
//! spherical-harmonic coefficients (Ramamoorthi & Hanrahan, *An Efficient
//! Representation for Irradiance Environment Maps*, SIGGRAPH 2001): the
//! radiance is projected onto the real harmonics of order ≤ 2 and each
//! order convolved with the clamped cosine (Â₀ = π, Â₁ = 2π/3, Â₂ = π/4).
//! Irradiance is smooth, so nine coefficients hold it to a few per cent
//! (R&H: under 3% on average for real environments), and a surface of
//! normal n reads E(n) = Σ c_i·Y_i(n), a polynomial in n, in one line of
//! WGSL (`sky_irradiance` in `shaders/lighting.wgsl`). The sun is not in
//! it: its disc is a direction, lit with its own visibility (shadows).

use glam::Vec3;
use std::f32::consts::PI;

/// The nine real spherical harmonics of order ≤ 2 at unit direction `d`
/// (the order R&H list them: Y00, Y1−1, Y10, Y11, Y2−2, Y2−1, Y20, Y21, Y22).
pub fn harmonics(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_095,
        0.488_603 * y,
        0.488_603 * z,
        0.488_603 * x,
        1.092_548 * x * y,
        1.092_548 * y * z,
        0.315_392 * (3.0 * z * z - 1.0),
        1.092_548 * x * z,
        0.546_274 * (x * x - y * y),
    ]
}

/// Irradiance as nine coefficients, already convolved with the cosine lobe.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IrradianceSh {
    pub coefficients: [Vec3; 9],
}

impl IrradianceSh {
    /// Project `radiance(direction)` over the sphere (`rings` × 2·`rings`
    /// cells, midpoint rule in θ and φ) and convolve.
    pub fn project(radiance: impl Fn(Vec3) -> Vec3, rings: usize) -> Self {
        let mut c = [Vec3::ZERO; 9];
        for (d, d_omega) in sphere_cells(rings) {
            let l = radiance(d) * d_omega;
            for (k, y) in harmonics(d).into_iter().enumerate() {
                c[k] += l * y;
            }
        }
        let band = [
            PI,
            2.0 * PI / 3.0,
            2.0 * PI / 3.0,
            2.0 * PI / 3.0,
            PI / 4.0,
            PI / 4.0,
            PI / 4.0,
            PI / 4.0,
            PI / 4.0,
        ];
        for (k, a) in band.into_iter().enumerate() {
            c[k] *= a;
        }
        IrradianceSh { coefficients: c }
    }

    /// The irradiance on a surface of unit normal `n`. Twin of
    /// `sky_irradiance` in WGSL.
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        harmonics(n)
            .iter()
            .zip(&self.coefficients)
            .map(|(y, c)| *c * *y)
            .sum::<Vec3>()
            .max(Vec3::ZERO)
    }
}

/// Albedo of the grey world below the horizon (ground and water seen from
/// a little above). Twin of `GROUND_ALBEDO` in `shaders/lighting.wgsl`.
pub const GROUND_ALBEDO: f32 = 0.15;

/// The sky's and the grey world's light on any normal in the air, as nine
/// coefficients (the sun's disc apart): the sky above the
/// horizon, below it a grey world of [`GROUND_ALBEDO`] lit by the sky and
/// the sun (Lambertian: irradiance × albedo / π; twin of
/// `below_horizon_radiance` in WGSL).
pub fn sky_light(sky: &crate::sky::Sky) -> IrradianceSh {
    let p = &sky.params;
    let sun = Vec3::from_slice(&p.sun_illuminance[..3]);
    let l = Vec3::from_slice(&p.sun_direction[..3]);
    let ground = GROUND_ALBEDO * (crate::sky::sky_irradiance_up(sky) + sun * l.y.max(0.0)) / PI;
    IrradianceSh::project(|d| if d.y > 0.0 { sky.radiance(d) } else { ground }, 48)
}

/// The irradiance on normal `n` from `radiance` by direct integration (the
/// reference the coefficients are tested against).
pub fn irradiance_integrated(radiance: impl Fn(Vec3) -> Vec3, n: Vec3, rings: usize) -> Vec3 {
    sphere_cells(rings).map(|(d, d_omega)| radiance(d) * n.dot(d).max(0.0) * d_omega).sum()
}

/// The sphere in `rings` × 2·`rings` cells of θ and φ: each cell's middle
/// direction and solid angle (the midpoint rule).
fn sphere_cells(rings: usize) -> impl Iterator<Item = (Vec3, f32)> {
    let (nt, np) = (rings, 2 * rings);
    (0..nt).flat_map(move |i| {
        let theta = (i as f32 + 0.5) / nt as f32 * PI;
        let d_omega = theta.sin() * (PI / nt as f32) * (2.0 * PI / np as f32);
        (0..np).map(move |j| {
            let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
            (Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()), d_omega)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sky::{Sky, SkyParams, sun_direction};

    fn normals() -> Vec<Vec3> {
        let mut out = vec![Vec3::Y, Vec3::NEG_Y, Vec3::X, Vec3::Z, Vec3::NEG_X];
        for i in 0..40 {
            // A spiral over the sphere.
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / 40.0;
            let r = (1.0 - y * y).sqrt();
            let a = i as f32 * 2.399_963;
            out.push(Vec3::new(r * a.cos(), y, r * a.sin()));
        }
        out
    }

    /// A uniform sky of radiance L over black ground: E(n) = π·L·(1 + n_y)/2,
    /// which nine harmonics hold exactly (the step's order-2 part is zero);
    /// a uniform sphere: π·L.
    #[test]
    fn a_uniform_sky_gives_the_closed_form() {
        let sky = |d: Vec3| if d.y > 0.0 { Vec3::ONE } else { Vec3::ZERO };
        let sh = IrradianceSh::project(sky, 256);
        for n in normals() {
            let e = sh.irradiance(n).x;
            let exact = PI * (1.0 + n.y) / 2.0;
            assert!((e - exact).abs() < 5e-3, "n {n}: {e}, closed form {exact}");
        }
        let sphere = IrradianceSh::project(|_| Vec3::splat(2.0), 64);
        for n in normals() {
            let e = sphere.irradiance(n).y;
            assert!((e - 2.0 * PI).abs() < 1e-3 * 2.0 * PI, "n {n}: {e}, closed form 2π");
        }
    }

    /// A clear sky over the grey world, by either model, at a high, a middle
    /// and a low sun: the nine coefficients give every normal's irradiance
    /// within 6% of the direct integral (of the brightest face's).
    #[test]
    fn a_clear_sky_is_held_by_nine_coefficients() {
        let models = [SkyParams::new, SkyParams::physical];
        for (elevation, model) in [70.0, 35.0, 8.0].into_iter().flat_map(|e| models.map(|m| (e, m)))
        {
            let p = Sky::new(model(sun_direction(elevation, 30.0), 2.5));
            let ground = 0.15 * crate::sky::sky_irradiance_up(&p) / PI;
            let radiance = |d: Vec3| if d.y > 0.0 { p.radiance(d) } else { ground };
            let sh = IrradianceSh::project(radiance, 128);
            let exact: Vec<Vec3> =
                normals().iter().map(|&n| irradiance_integrated(radiance, n, 128)).collect();
            let top = exact.iter().map(|e| e.max_element()).fold(0.0, f32::max);
            let mut worst = 0.0f32;
            for (n, e) in normals().into_iter().zip(&exact) {
                worst = worst.max((sh.irradiance(n) - *e).abs().max_element() / top);
            }
            eprintln!(
                "sun at {elevation}°: worst error {:.2}% of the brightest face",
                100.0 * worst
            );
            assert!(worst < 0.06, "sun at {elevation}°: {worst}");
            // Facing up it is the sky's irradiance on the level.
            let up = sh.irradiance(Vec3::Y);
            let level = crate::sky::sky_irradiance_up(&p) + ground * PI * 0.0;
            // The atmosphere's bright horizon band at a low sun is a sharper
            // step than nine harmonics hold: 7% there.
            assert!(
                (up - level).abs().max_element() < 0.08 * level.max_element(),
                "{up} vs {level}"
            );
        }
    }
}
