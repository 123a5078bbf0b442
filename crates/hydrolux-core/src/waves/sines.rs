//! A sum of directional waves with analytic derivatives: the wave function of
//! seed 001 (GPU Gems ch. 2: octaves of cosines whose partial derivatives give
//! the normal exactly, no finite differences), generalised to directional
//! waves whose wavelengths, amplitudes and directions are drawn from the same
//! sea state as the FFT ocean, so switching `water.model` keeps the sea's
//! character. Optionally Gerstner (trochoidal) waves (Tessendorf §3.1).
//!
//! The phases ω·t are advanced here in f64 and uploaded each frame, so the
//! GPU never multiplies a large time by a frequency.

use super::SurfaceSample;
use super::dispersion::{omega, wave_number};
use super::spectrum::{SeaState, Spreading};
use std::f64::consts::PI;

/// Most waves the GPU uniform holds.
pub const MAX_SINE_WAVES: usize = 64;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SineWave {
    pub kx: f64,
    pub kz: f64,
    pub amplitude: f64,
    pub omega: f64,
    pub phase0: f64,
    /// Gerstner steepness Q·k·A in [0, 1] (0 = plain sine wave).
    pub steepness: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SineWaves {
    pub waves: Vec<SineWave>,
}

impl SineWaves {
    /// `count` waves from the sea state: frequencies stratified over
    /// [0.75·ωp, 5·ωp] in log spacing, amplitude a = √(2·S(ω)·Δω) so that the
    /// variance matches the spectrum over that band; directions drawn from
    /// the spreading function. `gerstner` ∈ [0, 1] scales the choppiness.
    pub fn from_sea_state(sea: &SeaState, count: usize, seed: u64, gerstner: f64) -> Self {
        let count = count.clamp(1, MAX_SINE_WAVES);
        let wp = sea.peak_omega();
        let (lo, hi) = ((0.75 * wp).ln(), (5.0 * wp).ln());
        let spreading = Spreading::new(sea.spreading);
        let mut rng = seed ^ 0xC0FF_EE00_D15E_A5E5;
        let mut next = || {
            rng = rng.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = rng;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let waves = (0..count)
            .map(|i| {
                let (a, b) = (
                    lo + (hi - lo) * i as f64 / count as f64,
                    lo + (hi - lo) * (i + 1) as f64 / count as f64,
                );
                let w = (lo + (hi - lo) * (i as f64 + 0.5) / count as f64).exp();
                let dw = b.exp() - a.exp();
                let amplitude = (2.0 * sea.frequency_spectrum(w) * dw).sqrt();
                // Rejection-sample a direction from D(θ).
                let peak = spreading.density(0.0);
                let mut theta = 0.0;
                for _ in 0..64 {
                    let t = (next() * 2.0 - 1.0) * PI;
                    if next() * peak <= spreading.density(t) {
                        theta = t;
                        break;
                    }
                }
                let dir = sea.wind_direction + theta;
                let k = wave_number(w, sea.depth);
                let w = omega(k, sea.depth);
                SineWave {
                    kx: k * dir.cos(),
                    kz: k * dir.sin(),
                    amplitude,
                    omega: w,
                    phase0: next() * 2.0 * PI,
                    steepness: (gerstner * k * amplitude * count as f64).min(1.0) / count as f64,
                }
            })
            .collect();
        SineWaves { waves }
    }

    /// Slope variance along x and z of the sum: Σ (a·k)²/2 per axis.
    pub fn slope_variance(&self) -> [f64; 2] {
        self.waves.iter().fold([0.0, 0.0], |acc, w| {
            let a2 = w.amplitude * w.amplitude / 2.0;
            [acc[0] + a2 * w.kx * w.kx, acc[1] + a2 * w.kz * w.kz]
        })
    }

    /// Phase of each wave at time t, reduced mod 2π in f64 (what the GPU gets).
    pub fn phases(&self, t: f64) -> Vec<f32> {
        self.waves.iter().map(|w| (w.phase0 - w.omega * t).rem_euclid(2.0 * PI) as f32).collect()
    }

    /// The surface at undisplaced (x, z) and time t, from the given phases.
    /// h = Σ a·cos(k·x + φ); Gerstner adds D = −Σ (Q/k)·k̂… see the WGSL twin
    /// `sines_sample` in `shaders/shared/surface.wgsl`.
    pub fn sample_with_phases(&self, phases: &[f32], x: f32, z: f32) -> SurfaceSample {
        let mut s = SurfaceSample::default();
        for (w, &phi) in self.waves.iter().zip(phases) {
            let (kx, kz, a) = (w.kx as f32, w.kz as f32, w.amplitude as f32);
            let k = (kx * kx + kz * kz).sqrt();
            // Horizontal amplitude Q·A, from the steepness Q·k·A.
            let q = w.steepness as f32 / k.max(1e-6);
            let arg = kx * x + kz * z + phi;
            let (sn, cs) = arg.sin_cos();
            s.displacement[1] += a * cs;
            s.slope[0] -= a * kx * sn;
            s.slope[1] -= a * kz * sn;
            let (ux, uz) = (kx / k.max(1e-6), kz / k.max(1e-6));
            s.displacement[0] -= q * ux * sn;
            s.displacement[2] -= q * uz * sn;
            s.dxx -= q * ux * kx * cs;
            s.dzz -= q * uz * kz * cs;
            s.dxz -= q * ux * kz * cs;
        }
        s
    }

    pub fn sample(&self, x: f64, z: f64, t: f64) -> SurfaceSample {
        self.sample_with_phases(&self.phases(t), x as f32, z as f32)
    }

    pub fn height_at(&self, x: f64, z: f64, t: f64) -> f32 {
        let phases = self.phases(t);
        super::height_at_displaced(
            |px, pz| self.sample_with_phases(&phases, px as f32, pz as f32),
            x,
            z,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::spectrum::SpectrumKind;
    use super::*;

    fn sea() -> SeaState {
        SeaState {
            kind: SpectrumKind::PiersonMoskowitz,
            wind_speed: 8.0,
            wind_direction: 0.0,
            fetch: 1e5,
            depth: 1e4,
            peak_enhancement: 3.3,
            spreading: 8.0,
        }
    }

    #[test]
    fn analytic_derivatives_match_finite_differences() {
        let w = SineWaves::from_sea_state(&sea(), 12, 3, 0.6);
        let p = w.phases(17.0);
        let h = 1e-3f32;
        for i in 0..20 {
            let (x, z) = (i as f32 * 3.1, i as f32 * -1.7);
            let s = w.sample_with_phases(&p, x, z);
            let sx = w.sample_with_phases(&p, x + h, z);
            let sxm = w.sample_with_phases(&p, x - h, z);
            let sz = w.sample_with_phases(&p, x, z + h);
            let szm = w.sample_with_phases(&p, x, z - h);
            let fd = |a: f32, b: f32| (a - b) / (2.0 * h);
            assert!((s.slope[0] - fd(sx.displacement[1], sxm.displacement[1])).abs() < 2e-3);
            assert!((s.slope[1] - fd(sz.displacement[1], szm.displacement[1])).abs() < 2e-3);
            assert!((s.dxx - fd(sx.displacement[0], sxm.displacement[0])).abs() < 2e-3);
            assert!((s.dzz - fd(sz.displacement[2], szm.displacement[2])).abs() < 2e-3);
            assert!((s.dxz - fd(sz.displacement[0], szm.displacement[0])).abs() < 2e-3);
        }
    }

    #[test]
    fn waves_follow_dispersion_and_never_fold() {
        let w = SineWaves::from_sea_state(&sea(), 24, 9, 1.0);
        let total_steepness: f64 = w.waves.iter().map(|x| x.steepness).sum();
        assert!(total_steepness <= 1.0 + 1e-9, "Gerstner waves would loop: {total_steepness}");
        for x in &w.waves {
            let k = (x.kx * x.kx + x.kz * x.kz).sqrt();
            assert!((x.omega - (9.81 * k).sqrt()).abs() < 1e-9);
        }
    }
}
