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

/// The surface of a sum of waves at one time over a square, sampled at
/// `nodes`² points and read bilinearly: what a floating body integrates its
/// buoyancy over ([`crate::bodies::BUOYANCY_COLUMNS`]² columns, each a
/// fixed-point search through the displacement). One wave sum per node
/// instead of one per column and iteration, and each node's e^(ik·x) is
/// the last one's turned by e^(ik·spacing) rather than a new sine: the FFT
/// sea's hundreds of waves cost a body a fraction of a millisecond a step.
#[derive(Clone, Debug)]
pub struct SurfacePatch {
    low: [f64; 2],
    spacing: f64,
    nodes: usize,
    /// Per node: horizontal displacement x, height, displacement z.
    fields: Vec<[f64; 3]>,
}

impl SineWaves {
    /// The surface at time t over the square `centre` ± `half` (m), of
    /// the waves at least `shortest` (m) long.
    pub fn patch(
        &self,
        t: f64,
        centre: [f64; 2],
        half: f64,
        nodes: usize,
        shortest: f64,
    ) -> SurfacePatch {
        use rustfft::num_complex::Complex64;
        let n = nodes.max(2);
        let half = half.max(1e-3);
        let spacing = 2.0 * half / (n - 1) as f64;
        let low = [centre[0] - half, centre[1] - half];
        let mut fields = vec![[0.0f64; 3]; n * n];
        for w in &self.waves {
            let k = w.kx.hypot(w.kz).max(1e-9);
            if 2.0 * PI / k < shortest {
                continue;
            }
            let q = w.steepness / k;
            let (ux, uz) = (w.kx / k, w.kz / k);
            let phase = (w.phase0 - w.omega * t).rem_euclid(2.0 * PI);
            let step_x = Complex64::from_polar(1.0, w.kx * spacing);
            let step_z = Complex64::from_polar(1.0, w.kz * spacing);
            let mut row = Complex64::from_polar(1.0, w.kx * low[0] + w.kz * low[1] + phase);
            for line in fields.chunks_exact_mut(n) {
                let mut e = row;
                for f in line {
                    // h = a·cos(k·x + φ), D = −Q·A·k̂·sin(k·x + φ) (as `sample_with_phases`).
                    f[1] += w.amplitude * e.re;
                    f[0] -= q * ux * e.im;
                    f[2] -= q * uz * e.im;
                    e *= step_x;
                }
                row *= step_z;
            }
        }
        SurfacePatch { low, spacing, nodes: n, fields }
    }

    /// The patch a body reaching `half` (m) from `centre` floats on at t:
    /// wider by three standard deviations of the horizontal displacement
    /// (where its displaced points come from), with six nodes to the
    /// shortest wave (9 to 17 a side). Waves under four nodes long are
    /// left out: the patch could not hold them, and the body, wider than
    /// two of them, averages them out (a hull does not heave on ripples).
    pub fn patch_around(&self, t: f64, centre: [f64; 2], half: f64) -> SurfacePatch {
        let sway: f64 = self
            .waves
            .iter()
            .map(|w| (w.steepness / w.kx.hypot(w.kz).max(1e-9)).powi(2) / 2.0)
            .sum();
        let shortest = self
            .waves
            .iter()
            .map(|w| 2.0 * PI / w.kx.hypot(w.kz).max(1e-9))
            .fold(f64::MAX, f64::min);
        let reach = half + 3.0 * sway.sqrt();
        let nodes = ((2.0 * reach / (shortest / 6.0)).ceil() as usize + 1).clamp(9, 17);
        let spacing = 2.0 * reach / (nodes - 1) as f64;
        self.patch(t, centre, reach, nodes, 4.0 * spacing)
    }
}

impl SurfacePatch {
    /// Displacement and height at undisplaced (x, z), bilinear between
    /// nodes (held at the patch's edge beyond it).
    fn sample(&self, x: f64, z: f64) -> [f64; 3] {
        let last = (self.nodes - 1) as f64;
        let u = ((x - self.low[0]) / self.spacing).clamp(0.0, last);
        let v = ((z - self.low[1]) / self.spacing).clamp(0.0, last);
        let (i, j) =
            ((u.floor() as usize).min(self.nodes - 2), (v.floor() as usize).min(self.nodes - 2));
        let (a, b) = (u - i as f64, v - j as f64);
        let at = |i: usize, j: usize| self.fields[j * self.nodes + i];
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            let top = at(i, j)[c] * (1.0 - a) + at(i + 1, j)[c] * a;
            let bottom = at(i, j + 1)[c] * (1.0 - a) + at(i + 1, j + 1)[c] * a;
            *o = top * (1.0 - b) + bottom * b;
        }
        out
    }

    /// Height of the displaced surface above world (x, z).
    pub fn height_at(&self, x: f64, z: f64) -> f64 {
        let sample = |px, pz| {
            let [dx, h, dz] = self.sample(px, pz);
            SurfaceSample { displacement: [dx as f32, h as f32, dz as f32], ..Default::default() }
        };
        super::height_at_displaced(sample, x, z) as f64
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

    /// The patch reads the waves as the exact sum does: to 2 mm on a 4 m
    /// square of a choppy sea whose shortest wave is 12 nodes long.
    #[test]
    fn a_patch_reads_the_surface_as_the_exact_sum() {
        let w = SineWaves::from_sea_state(&sea(), 24, 5, 0.8);
        let shortest = w.waves.iter().map(|x| 2.0 * PI / x.kx.hypot(x.kz)).fold(f64::MAX, f64::min);
        // The square holds the displaced points' sources (within 3 m).
        let (half, margin) = (2.0, 3.0);
        let nodes = (2.0 * (half + margin) / (shortest / 12.0)).ceil() as usize + 1;
        let (t, centre) = (123.4, [31.0, -17.0]);
        let patch = w.patch(t, centre, half + margin, nodes, 0.0);
        for i in 0..40 {
            let (x, z) = (centre[0] - half + 0.1 * i as f64, centre[1] + half - 0.07 * i as f64);
            let (a, b) = (patch.height_at(x, z), w.height_at(x, z, t) as f64);
            assert!((a - b).abs() < 2e-3, "at ({x}, {z}): patch {a} vs exact {b}");
        }
    }
}
