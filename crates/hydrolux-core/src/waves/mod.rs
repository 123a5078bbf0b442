//! Water surface models: the FFT ocean, a sum of directional sines (seed
//! 001's analytic-derivative wave function, Gerstner optional), and flat water.

pub mod dispersion;
pub mod heightfield;
pub mod ocean;
pub mod ripples;
pub mod sea_brdf;
pub mod sines;
pub mod spectrum;

use glam::Vec3;
use rustfft::{Fft, FftNum, num_complex::Complex};

/// 2-D FFT of an n×n grid (row = z) in place with `fft`, a 1-D plan of
/// size n: rows, then columns. The ocean's and the interactive water's CPU
/// twins share it.
pub fn fft2<T: FftNum>(fft: &dyn Fft<T>, data: &mut [Complex<T>], n: usize) {
    for row in data.chunks_exact_mut(n) {
        fft.process(row);
    }
    let mut column = vec![Complex::new(T::zero(), T::zero()); n];
    for x in 0..n {
        for z in 0..n {
            column[z] = data[z * n + x];
        }
        fft.process(&mut column);
        for z in 0..n {
            data[z * n + x] = column[z];
        }
    }
}

/// The surface at one undisplaced point: displacement (Dx, h, Dz) and the
/// partial derivatives needed for normals and the Jacobian.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceSample {
    pub displacement: [f32; 3],
    /// ∂h/∂x, ∂h/∂z
    pub slope: [f32; 2],
    /// ∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z
    pub dxx: f32,
    pub dzz: f32,
    pub dxz: f32,
}

impl SurfaceSample {
    /// From the packed field order [Dx, h, Dz, hx, hz, Dxx, Dzz, Dxz].
    pub fn from_fields(f: [f32; 8]) -> Self {
        SurfaceSample {
            displacement: [f[0], f[1], f[2]],
            slope: [f[3], f[4]],
            dxx: f[5],
            dzz: f[6],
            dxz: f[7],
        }
    }

    /// Unit normal of the displaced surface: the cross product of the
    /// displaced tangents ∂p/∂z × ∂p/∂x. Twin of `surface_normal` in WGSL.
    pub fn normal(&self) -> Vec3 {
        let tx = Vec3::new(1.0 + self.dxx, self.slope[0], self.dxz);
        let tz = Vec3::new(self.dxz, self.slope[1], 1.0 + self.dzz);
        tz.cross(tx).normalize()
    }

    /// Jacobian determinant of the horizontal displacement; below 0 the
    /// surface folds over (where foam forms).
    pub fn jacobian(&self) -> f32 {
        (1.0 + self.dxx) * (1.0 + self.dzz) - self.dxz * self.dxz
    }
}

/// Height of a horizontally displaced surface above world (x, z), given a
/// sampler of undisplaced points: solve p + D(p) = (x, z) by fixed-point
/// iteration (converges while the surface does not fold, J > 0).
pub fn height_at_displaced(sample: impl Fn(f64, f64) -> SurfaceSample, x: f64, z: f64) -> f32 {
    let (mut px, mut pz) = (x, z);
    for _ in 0..12 {
        let s = sample(px, pz);
        let (ex, ez) = (px + s.displacement[0] as f64 - x, pz + s.displacement[2] as f64 - z);
        if ex.abs() < 1e-4 && ez.abs() < 1e-4 {
            break;
        }
        px -= ex;
        pz -= ez;
    }
    sample(px, pz).displacement[1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_sample_has_up_normal_and_unit_jacobian() {
        let s = SurfaceSample::default();
        assert!((s.normal() - Vec3::Y).length() < 1e-6);
        assert_eq!(s.jacobian(), 1.0);
        let tilted = SurfaceSample { slope: [0.5, 0.0], ..Default::default() };
        let n = tilted.normal();
        assert!((n.x / n.y + 0.5).abs() < 1e-6, "normal {n}");
    }
}
