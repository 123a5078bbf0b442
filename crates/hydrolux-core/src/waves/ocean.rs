//! The FFT ocean (Tessendorf, *Simulating Ocean Water*; seed 000 §2.3.1):
//! initial spectrum, time evolution and the CPU reference of the GPU FFT.
//!
//! The initial amplitudes h0(k) are made here, on the CPU, once per sea
//! state, and uploaded; the GPU then evolves and transforms them every frame
//! (`simulation/ocean` in the `hydrolux` crate). [`OceanFields::evaluate`] does
//! the same evolution and inverse FFT with rustfft, so the two can be compared.
//!
//! Precision at large times: every ω is rounded to a multiple of 2π/T with
//! T = [`REPEAT_PERIOD_S`] (about 18 h) and stored as a whole number of cycles
//! per period. The phase is then `cycles · τ` in wrapping 32-bit integer
//! arithmetic, with τ = frac(t/T)·2³², which is exact: the sea has no jitter
//! after hours, and is exactly periodic with period T. The rounding changes no
//! frequency by more than 2π/T ≈ 1e-4 rad/s.

use super::SurfaceSample;
use super::dispersion::omega;
use super::spectrum::{SeaState, Spreading};
use rustfft::{FftPlanner, num_complex::Complex};
use std::f64::consts::PI;

/// Period after which the simulated sea repeats exactly, in seconds.
pub const REPEAT_PERIOD_S: f64 = 65536.0;
/// Ratio between the patch sizes of consecutive cascades. Not a whole number,
/// so the patches' tiling periods never line up.
pub const CASCADE_RATIO: f64 = 5.23;
/// Modes of cascade i+1 start at this many cycles across that cascade's patch;
/// below it, cascade i carries the waves.
const BAND_SPLIT_CYCLES: f64 = 4.0;

/// Everything the FFT ocean needs (the `[ocean]` scene section, resolved).
#[derive(Clone, Debug, PartialEq)]
pub struct OceanSettings {
    pub sea: SeaState,
    /// Side of the largest cascade's square patch, metres.
    pub patch_size: f64,
    /// FFT size N (power of two).
    pub resolution: usize,
    pub cascades: usize,
    /// Horizontal displacement scale λ (0 = no choppiness).
    pub choppiness: f64,
    pub seed: u64,
}

/// One initial spectrum mode, laid out exactly like WGSL `SpectrumMode`
/// (`shaders/ocean_spectrum.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SpectrumMode {
    /// h0(k)
    pub h0: [f32; 2],
    /// conj(h0(−k))
    pub h0_minus_conj: [f32; 2],
    pub kx: f32,
    pub kz: f32,
    /// ω rounded to whole cycles per [`REPEAT_PERIOD_S`].
    pub omega_cycles: u32,
    pub _pad: u32,
}

/// The wave-number band and patch of one cascade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    pub patch_size: f64,
    pub k_min: f64,
    pub k_max: f64,
}

/// Initial spectra of all cascades: `modes[c * N * N + z * N + x]`, in FFT
/// order (index i ↔ frequency i for i < N/2, i − N above).
#[derive(Clone, Debug)]
pub struct OceanSpectrum {
    pub settings: OceanSettings,
    pub cascades: Vec<Cascade>,
    pub modes: Vec<SpectrumMode>,
}

/// Signed frequency index of FFT bin `i`.
pub fn bin_frequency(i: usize, n: usize) -> i64 {
    if i < n / 2 { i as i64 } else { i as i64 - n as i64 }
}

fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// Two independent standard normal numbers for one wave vector. Keyed on the
/// signed frequency indices, so the big waves stay the same when N changes.
fn gaussian_pair(seed: u64, cascade: usize, fx: i64, fz: i64) -> (f64, f64) {
    let mut h = splitmix64(seed ^ 0x5EA5_0CEA_u64);
    h = splitmix64(h ^ cascade as u64);
    h = splitmix64(h ^ fx as u64);
    h = splitmix64(h ^ (fz as u64).rotate_left(32));
    let u1 = ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let h2 = splitmix64(h);
    let u2 = ((h2 >> 11) as f64) / (1u64 << 53) as f64;
    let r = (-2.0 * u1.ln()).sqrt();
    (r * (2.0 * PI * u2).cos(), r * (2.0 * PI * u2).sin())
}

/// τ = frac(t / T) · 2³², the time argument of [`phase_of`].
pub fn time_phase(t: f64) -> u32 {
    let f = (t / REPEAT_PERIOD_S).rem_euclid(1.0);
    ((f * 4_294_967_296.0) as u64 & 0xFFFF_FFFF) as u32
}

/// Phase ω·t in radians (mod 2π) of a mode with `omega_cycles`, as the GPU computes it.
pub fn phase_of(omega_cycles: u32, tau: u32) -> f32 {
    let turns = omega_cycles.wrapping_mul(tau);
    turns as f32 * (std::f32::consts::TAU / 4_294_967_296.0)
}

/// ω (rad/s) that a mode with `omega_cycles` really moves at.
pub fn quantized_omega(omega_cycles: u32) -> f64 {
    omega_cycles as f64 * 2.0 * PI / REPEAT_PERIOD_S
}

impl OceanSettings {
    pub fn cascades(&self) -> Vec<Cascade> {
        let sizes: Vec<f64> =
            (0..self.cascades).map(|i| self.patch_size / CASCADE_RATIO.powi(i as i32)).collect();
        (0..self.cascades)
            .map(|i| Cascade {
                patch_size: sizes[i],
                k_min: if i == 0 { 0.0 } else { BAND_SPLIT_CYCLES * 2.0 * PI / sizes[i] },
                k_max: sizes.get(i + 1).map_or(f64::INFINITY, |s| BAND_SPLIT_CYCLES * 2.0 * PI / s),
            })
            .collect()
    }
}

impl OceanSpectrum {
    pub fn new(settings: &OceanSettings) -> Self {
        let n = settings.resolution;
        let cascades = settings.cascades();
        let spreading = Spreading::new(settings.sea.spreading);
        let mut modes = vec![SpectrumMode::default(); cascades.len() * n * n];
        for (c, cascade) in cascades.iter().enumerate() {
            let dk = 2.0 * PI / cascade.patch_size;
            // Amplitude of the mode at signed index (fx, fz), or 0 outside the band.
            let amplitude = |fx: i64, fz: i64| -> (f64, f64) {
                let (kx, kz) = (fx as f64 * dk, fz as f64 * dk);
                let k = (kx * kx + kz * kz).sqrt();
                let nyquist =
                    fx.unsigned_abs() as usize == n / 2 || fz.unsigned_abs() as usize == n / 2;
                if k == 0.0 || nyquist || k < cascade.k_min || k >= cascade.k_max {
                    return (0.0, 0.0);
                }
                let psi = settings.sea.directional_density(kx, kz, &spreading);
                let scale = (psi * dk * dk).sqrt() * 0.5;
                let (g1, g2) = gaussian_pair(settings.seed, c, fx, fz);
                (g1 * scale, g2 * scale)
            };
            for z in 0..n {
                for x in 0..n {
                    let (fx, fz) = (bin_frequency(x, n), bin_frequency(z, n));
                    let (kx, kz) = (fx as f64 * dk, fz as f64 * dk);
                    let k = (kx * kx + kz * kz).sqrt();
                    let h0 = amplitude(fx, fz);
                    let hm = amplitude(-fx, -fz);
                    let w = omega(k, settings.sea.depth);
                    modes[c * n * n + z * n + x] = SpectrumMode {
                        h0: [h0.0 as f32, h0.1 as f32],
                        h0_minus_conj: [hm.0 as f32, -hm.1 as f32],
                        kx: kx as f32,
                        kz: kz as f32,
                        omega_cycles: (w * REPEAT_PERIOD_S / (2.0 * PI)).round() as u32,
                        _pad: 0,
                    };
                }
            }
        }
        OceanSpectrum { settings: settings.clone(), cascades, modes }
    }

    /// The `count` modes with the most energy as travelling waves, for
    /// what floats on this sea. Mode k of the spectrum and its partner −k
    /// together are h = 2|h₀(k)|·cos(k·x − ω·t + arg h₀(k)) and, with the
    /// choppy displacement D = i·λ·k̂·h̃, a Gerstner wave of steepness λ·k·a:
    /// the same wave the FFT draws, at the same phase (ω as quantized).
    /// 1024 of them hold ~99% of a 256² sea's height variance; what is
    /// left is short waves a hull averages out.
    pub fn strongest_waves(&self, count: usize) -> super::sines::SineWaves {
        let lambda = self.settings.choppiness;
        let mut waves: Vec<super::sines::SineWave> = self
            .modes
            .iter()
            .filter(|m| m.h0 != [0.0, 0.0])
            .map(|m| {
                let (re, im) = (m.h0[0] as f64, m.h0[1] as f64);
                let (kx, kz) = (m.kx as f64, m.kz as f64);
                let amplitude = 2.0 * re.hypot(im);
                super::sines::SineWave {
                    kx,
                    kz,
                    amplitude,
                    omega: quantized_omega(m.omega_cycles),
                    phase0: im.atan2(re),
                    steepness: lambda * kx.hypot(kz) * amplitude,
                }
            })
            .collect();
        waves.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
        waves.truncate(count);
        super::sines::SineWaves { waves }
    }

    /// Expected height variance Σ Ψ(k)Δk² of the modes this spectrum holds
    /// (what the random amplitudes average to), for calibration checks.
    pub fn expected_variance(&self) -> f64 {
        self.expected_moments().0
    }

    /// Expected slope variance along x and z, Σ kx²Ψ Δk² and Σ kz²Ψ Δk²: what
    /// the simulated waves resolve (the renderer adds the unresolved rest).
    pub fn expected_slope_variance(&self) -> [f64; 2] {
        let m = self.expected_moments();
        [m.1, m.2]
    }

    fn expected_moments(&self) -> (f64, f64, f64) {
        let n = self.settings.resolution;
        let spreading = Spreading::new(self.settings.sea.spreading);
        let mut total = (0.0, 0.0, 0.0);
        for cascade in &self.cascades {
            let dk = 2.0 * PI / cascade.patch_size;
            for z in 0..n {
                for x in 0..n {
                    let (fx, fz) = (bin_frequency(x, n), bin_frequency(z, n));
                    let (kx, kz) = (fx as f64 * dk, fz as f64 * dk);
                    let k = (kx * kx + kz * kz).sqrt();
                    let nyquist =
                        fx.unsigned_abs() as usize == n / 2 || fz.unsigned_abs() as usize == n / 2;
                    if k > 0.0 && !nyquist && k >= cascade.k_min && k < cascade.k_max {
                        let v = self.settings.sea.directional_density(kx, kz, &spreading) * dk * dk;
                        total.0 += v;
                        total.1 += kx * kx * v;
                        total.2 += kz * kz * v;
                    }
                }
            }
        }
        total
    }
}

/// The spectral fields of one mode at time phase τ, packed two real fields per
/// complex number as the GPU packs them: [Dx + i·h, Dz + i·∂h/∂x,
/// ∂h/∂z + i·∂Dx/∂x, ∂Dz/∂z + i·∂Dx/∂z] (D already scaled by λ).
/// Twin of `evolve` in `shaders/ocean_spectrum.wgsl`.
pub fn evolve_mode(mode: &SpectrumMode, tau: u32, choppiness: f32) -> [[f32; 2]; 4] {
    let theta = phase_of(mode.omega_cycles, tau);
    let (s, c) = theta.sin_cos();
    let mul = |a: [f32; 2], b: [f32; 2]| [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]];
    let e_neg = [c, -s];
    let e_pos = [c, s];
    let a = mul(mode.h0, e_neg);
    let b = mul(mode.h0_minus_conj, e_pos);
    let h = [a[0] + b[0], a[1] + b[1]];
    let (kx, kz) = (mode.kx, mode.kz);
    let k = (kx * kx + kz * kz).sqrt();
    let inv_k = if k > 0.0 { 1.0 / k } else { 0.0 };
    let lambda = choppiness;
    let scale = |f: f32| [h[0] * f, h[1] * f];
    let times_i = |v: [f32; 2]| [-v[1], v[0]];
    // D = +i·λ·k̂·h̃. Tessendorf writes −i·k̂·h̃, which with this e^(+ik·x)
    // sum moves points away from the crests: broad crests, sharp troughs,
    // and the fold (J < 0) where whitecaps are drawn in the troughs. This
    // sign is Gerstner's x₀ − Q·k̂·A·sin θ (`sines.rs`): crests sharpen.
    let dx = times_i(scale(lambda * kx * inv_k));
    let dz = times_i(scale(lambda * kz * inv_k));
    let hx = times_i(scale(kx));
    let hz = times_i(scale(kz));
    let dxx = scale(-lambda * kx * kx * inv_k);
    let dzz = scale(-lambda * kz * kz * inv_k);
    let dxz = scale(-lambda * kx * kz * inv_k);
    // A + i·B for complex A, B.
    let pack = |a: [f32; 2], b: [f32; 2]| [a[0] - b[1], a[1] + b[0]];
    [pack(dx, h), pack(dz, hx), pack(hz, dxx), pack(dzz, dxz)]
}

/// The eight real fields of every cascade at one time, on each cascade's own
/// N×N corner-sampled grid (x_j = j·L/N). Per texel:
/// [Dx, h, Dz, ∂h/∂x, ∂h/∂z, ∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z].
#[derive(Clone, Debug)]
pub struct OceanFields {
    pub resolution: usize,
    pub patch_sizes: Vec<f64>,
    pub texels: Vec<[f32; 8]>,
}

impl OceanFields {
    /// Evolve `spectrum` to time `t` and inverse-transform it with rustfft.
    pub fn evaluate(spectrum: &OceanSpectrum, t: f64) -> Self {
        Self::evaluate_packed(spectrum, t, &[0, 1, 2, 3])
    }

    /// The surface's Jacobian parts only (∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z; the rest
    /// left zero): half the transforms.
    pub fn evaluate_jacobian(spectrum: &OceanSpectrum, t: f64) -> Self {
        Self::evaluate_packed(spectrum, t, &[2, 3])
    }

    /// Only the packed complex fields `packed` (field f holds texel
    /// entries 2f and 2f + 1) are transformed.
    fn evaluate_packed(spectrum: &OceanSpectrum, t: f64, packed: &[usize]) -> Self {
        let n = spectrum.settings.resolution;
        let tau = time_phase(t);
        let lambda = spectrum.settings.choppiness as f32;
        let mut planner = FftPlanner::<f32>::new();
        let fft = planner.plan_fft_inverse(n);
        let mut texels = vec![[0.0f32; 8]; spectrum.cascades.len() * n * n];
        let mut fields = vec![vec![Complex::new(0.0f32, 0.0); n * n]; 4];
        for c in 0..spectrum.cascades.len() {
            for i in 0..n * n {
                let packed_modes = evolve_mode(&spectrum.modes[c * n * n + i], tau, lambda);
                for &f in packed {
                    fields[f][i] = Complex::new(packed_modes[f][0], packed_modes[f][1]);
                }
            }
            for &f in packed {
                super::fft2(&*fft, &mut fields[f], n);
            }
            for i in 0..n * n {
                let t = &mut texels[c * n * n + i];
                for &f in packed {
                    t[2 * f] = fields[f][i].re;
                    t[2 * f + 1] = fields[f][i].im;
                }
            }
        }
        OceanFields {
            resolution: n,
            patch_sizes: spectrum.cascades.iter().map(|c| c.patch_size).collect(),
            texels,
        }
    }

    /// Bilinear, periodic sample of one cascade at world (x, z), as a GPU
    /// sampler with repeat addressing reads the texture.
    pub fn sample_cascade(&self, cascade: usize, x: f64, z: f64) -> [f32; 8] {
        let n = self.resolution;
        let l = self.patch_sizes[cascade];
        let (gx, gz) = (x / l * n as f64, z / l * n as f64);
        let (x0, z0) = (gx.floor(), gz.floor());
        let (fx, fz) = ((gx - x0) as f32, (gz - z0) as f32);
        let wrap = |v: f64| (v.rem_euclid(n as f64)) as usize % n;
        let (x0, z0) = (wrap(x0), wrap(z0));
        let (x1, z1) = ((x0 + 1) % n, (z0 + 1) % n);
        let base = cascade * n * n;
        let at = |xi: usize, zi: usize| &self.texels[base + zi * n + xi];
        let mut out = [0.0; 8];
        for (i, o) in out.iter_mut().enumerate() {
            let top = at(x0, z0)[i] * (1.0 - fx) + at(x1, z0)[i] * fx;
            let bottom = at(x0, z1)[i] * (1.0 - fx) + at(x1, z1)[i] * fx;
            *o = top * (1.0 - fz) + bottom * fz;
        }
        out
    }

    /// The surface at undisplaced position (x, z): all cascades summed.
    pub fn sample(&self, x: f64, z: f64) -> SurfaceSample {
        let mut sum = [0.0f32; 8];
        for c in 0..self.patch_sizes.len() {
            let s = self.sample_cascade(c, x, z);
            for i in 0..8 {
                sum[i] += s[i];
            }
        }
        SurfaceSample::from_fields(sum)
    }

    /// Height of the rendered surface above world point (x, z): the choppy
    /// displacement moves points sideways, so the undisplaced point p with
    /// p + D(p) = (x, z) is found by fixed-point iteration first.
    pub fn height_at(&self, x: f64, z: f64) -> f32 {
        super::height_at_displaced(|px, pz| self.sample(px, pz), x, z)
    }

    /// Vertical displacement of all cascades summed on the largest cascade's
    /// N×N grid (row = z, col = x), before horizontal displacement: the
    /// `--dump height` buffer.
    pub fn height_grid(&self) -> Vec<f32> {
        let n = self.resolution;
        let l = self.patch_sizes[0];
        let mut out = Vec::with_capacity(n * n);
        for z in 0..n {
            for x in 0..n {
                out.push(
                    self.sample(x as f64 * l / n as f64, z as f64 * l / n as f64).displacement[1],
                );
            }
        }
        out
    }
}

/// The fields' mip chains as the GPU builds them (a 2×2 box filter per
/// level, `shaders/downsample.wgsl`), read as the GPU's trilinear sampler
/// with repeat addressing reads them: the CPU twin of
/// `fft_sample_footprint` in `surface.wgsl`.
#[derive(Clone, Debug)]
pub struct OceanMips {
    resolution: usize,
    patch_sizes: Vec<f64>,
    /// The texel entries filtered and read (the others stay zero).
    entries: std::ops::Range<usize>,
    /// Level m: every cascade's (N/2^m)² texels, cascade-major.
    levels: Vec<Vec<[f32; 8]>>,
}

impl OceanFields {
    pub fn mips(&self) -> OceanMips {
        self.mips_of(0..8)
    }

    /// Mips of the texel entries `entries` only (the others left zero).
    pub fn mips_of(&self, entries: std::ops::Range<usize>) -> OceanMips {
        let cascades = self.patch_sizes.len();
        let mut levels = vec![self.texels.clone()];
        let mut n = self.resolution;
        while n > 1 {
            let (up, half) = (levels.last().expect("level 0"), n / 2);
            let mut next = vec![[0.0f32; 8]; cascades * half * half];
            for c in 0..cascades {
                for z in 0..half {
                    for x in 0..half {
                        let t = &mut next[c * half * half + z * half + x];
                        for (dz, dx) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                            let u = &up[c * n * n + (2 * z + dz) * n + 2 * x + dx];
                            for i in entries.clone() {
                                t[i] += 0.25 * u[i];
                            }
                        }
                    }
                }
            }
            levels.push(next);
            n = half;
        }
        OceanMips {
            resolution: self.resolution,
            patch_sizes: self.patch_sizes.clone(),
            entries,
            levels,
        }
    }
}

impl OceanMips {
    /// Bilinear, periodic sample of level `m` of one cascade at world (x, z).
    fn sample_level(&self, cascade: usize, m: usize, x: f64, z: f64) -> [f32; 8] {
        let n = self.resolution >> m;
        let l = self.patch_sizes[cascade];
        // Level-0 texel j holds x = j·L/N; a level-m texel averages 2^m of
        // them, so its centre sits (2^m − 1)/2 level-0 texels further on.
        let shift = ((1usize << m) as f64 - 1.0) / 2.0;
        let to_level = |v: f64| (v / l * self.resolution as f64 - shift) / (1usize << m) as f64;
        let (gx, gz) = (to_level(x), to_level(z));
        let (x0, z0) = (gx.floor(), gz.floor());
        let (fx, fz) = ((gx - x0) as f32, (gz - z0) as f32);
        let wrap = |v: f64| (v.rem_euclid(n as f64)) as usize % n;
        let (x0, z0) = (wrap(x0), wrap(z0));
        let (x1, z1) = ((x0 + 1) % n, (z0 + 1) % n);
        let texels = &self.levels[m][cascade * n * n..(cascade + 1) * n * n];
        let at = |xi: usize, zi: usize| &texels[zi * n + xi];
        let mut out = [0.0; 8];
        for i in self.entries.clone() {
            let top = at(x0, z0)[i] * (1.0 - fx) + at(x1, z0)[i] * fx;
            let bottom = at(x0, z1)[i] * (1.0 - fx) + at(x1, z1)[i] * fx;
            out[i] = top * (1.0 - fz) + bottom * fz;
        }
        out
    }

    /// The surface at (x, z) prefiltered over a square footprint (m): each
    /// cascade read at lod log2(footprint / texel), trilinearly.
    pub fn sample_footprint(&self, x: f64, z: f64, footprint: f64) -> SurfaceSample {
        let top = self.levels.len() - 1;
        let mut sum = [0.0f32; 8];
        for (c, &l) in self.patch_sizes.iter().enumerate() {
            let texel = l / self.resolution as f64;
            let lod = (footprint.max(1e-6) / texel).log2().clamp(0.0, top as f64);
            let m = (lod.floor() as usize).min(top);
            let f = (lod - m as f64) as f32;
            let a = self.sample_level(c, m, x, z);
            let b = if f > 0.0 { self.sample_level(c, (m + 1).min(top), x, z) } else { a };
            for i in self.entries.clone() {
                sum[i] += a[i] * (1.0 - f) + b[i] * f;
            }
        }
        SurfaceSample::from_fields(sum)
    }
}

#[cfg(test)]
mod tests {
    use super::super::spectrum::SpectrumKind;
    use super::*;

    pub(crate) fn settings(kind: SpectrumKind, u: f64, n: usize, cascades: usize) -> OceanSettings {
        OceanSettings {
            sea: SeaState {
                kind,
                wind_speed: u,
                wind_direction: 0.3,
                fetch: 100_000.0,
                depth: 10_000.0,
                peak_enhancement: 3.3,
                spreading: 8.0,
            },
            patch_size: 1000.0,
            resolution: n,
            cascades,
            choppiness: 0.8,
            seed: 7,
        }
    }

    /// The mips' twin reads the fields themselves at footprint 0, and a
    /// footprint wider than every patch reads each cascade's mean (no
    /// slope, no stretch: the derivatives of periodic fields average 0).
    #[test]
    fn mips_read_the_fields_at_zero_footprint_and_the_mean_beyond() {
        let spectrum = OceanSpectrum::new(&settings(SpectrumKind::Jonswap, 12.0, 32, 2));
        let fields = OceanFields::evaluate(&spectrum, 3.0);
        let mips = fields.mips();
        for p in [(0.0, 0.0), (13.7, -41.2), (250.3, 77.7)] {
            let (a, b) = (fields.sample(p.0, p.1), mips.sample_footprint(p.0, p.1, 0.0));
            assert!(
                (a.dxx - b.dxx).abs() < 1e-6
                    && (a.displacement[1] - b.displacement[1]).abs() < 1e-6
            );
            let far = mips.sample_footprint(p.0, p.1, 1e6);
            assert!(far.dxx.abs() < 1e-5 && far.dzz.abs() < 1e-5 && far.slope[0].abs() < 1e-5);
        }
        // Halfway in lod, halfway between the two levels (one cascade).
        let single = OceanFields::evaluate(
            &OceanSpectrum::new(&settings(SpectrumKind::Jonswap, 12.0, 32, 1)),
            3.0,
        );
        let (mips, texel) = (single.mips(), single.patch_sizes[0] / 32.0);
        let at = |lod: f64| mips.sample_footprint(31.0, 9.0, 2.0f64.powf(lod) * texel).dxx;
        assert!((at(1.5) - 0.5 * (at(1.0) + at(2.0))).abs() < 1e-6 + 1e-4 * at(1.0).abs());
        assert!((at(1.0) - at(2.0)).abs() > 1e-4, "the levels differ");
    }

    #[test]
    fn field_is_real_because_spectrum_is_hermitian() {
        // If h0_minus_conj were wrong the inverse FFT would leave an imaginary
        // part, which the packing would mix into the neighbouring field.
        let s = OceanSpectrum::new(&settings(SpectrumKind::PiersonMoskowitz, 10.0, 32, 1));
        let n = 32;
        for z in 0..n {
            for x in 0..n {
                let m = s.modes[z * n + x];
                let mirror = s.modes[((n - z) % n) * n + (n - x) % n];
                assert_eq!(m.h0_minus_conj, [mirror.h0[0], -mirror.h0[1]]);
            }
        }
    }

    #[test]
    fn pierson_moskowitz_ocean_has_the_calibrated_significant_height() {
        let u = 10.0;
        let st = settings(SpectrumKind::PiersonMoskowitz, u, 128, 3);
        let target = 0.2202 * u * u / 9.81;
        let spec = OceanSpectrum::new(&st);
        let hs_expected = 4.0 * spec.expected_variance().sqrt();
        assert!((hs_expected / target - 1.0).abs() < 0.03, "expected Hs {hs_expected} vs {target}");
        // Realised sea, averaged over a few seeds: each cascade on its own grid
        // (bands are disjoint, so variances add).
        let mut var = 0.0;
        let seeds = 6;
        for seed in 0..seeds {
            let mut s = st.clone();
            s.seed = seed;
            let fields = OceanFields::evaluate(&OceanSpectrum::new(&s), 1234.5);
            let nn = 128 * 128;
            for c in 0..3 {
                let heights: Vec<f64> =
                    fields.texels[c * nn..(c + 1) * nn].iter().map(|t| t[1] as f64).collect();
                let mean = heights.iter().sum::<f64>() / nn as f64;
                var += heights.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / nn as f64;
            }
        }
        let hs = 4.0 * (var / seeds as f64).sqrt();
        assert!((hs / target - 1.0).abs() < 0.08, "realised Hs {hs} vs {target}");
    }

    #[test]
    fn every_mode_moves_at_its_dispersion_frequency() {
        let mut st = settings(SpectrumKind::PiersonMoskowitz, 10.0, 64, 2);
        st.sea.depth = 12.0; // finite depth, so tanh matters
        let spec = OceanSpectrum::new(&st);
        for m in spec.modes.iter().filter(|m| m.h0 != [0.0, 0.0]) {
            let k = ((m.kx as f64).powi(2) + (m.kz as f64).powi(2)).sqrt();
            let w = omega(k, 12.0);
            assert!((quantized_omega(m.omega_cycles) - w).abs() < 1e-4 + 1e-6 * w, "k {k}");
            // The phase after dt seconds is ω·dt.
            let dt = 3.7;
            let measured = phase_of(m.omega_cycles, time_phase(dt)) as f64;
            let expected = (w * dt).rem_euclid(2.0 * PI);
            let err = (measured - expected + PI).rem_euclid(2.0 * PI) - PI;
            assert!(err.abs() < 2e-3, "k {k}: phase {measured} vs {expected}");
        }
    }

    #[test]
    fn a_single_mode_travels_downwind_at_phase_speed() {
        // Keep one mode only and watch its crest move.
        let st = settings(SpectrumKind::PiersonMoskowitz, 10.0, 64, 1);
        let mut spec = OceanSpectrum::new(&st);
        let n = 64;
        let (x, z) = (3usize, 0usize);
        for (i, m) in spec.modes.iter_mut().enumerate() {
            if i != z * n + x && i != z * n + (n - x) {
                m.h0 = [0.0, 0.0];
                m.h0_minus_conj = [0.0, 0.0];
            }
        }
        let own = spec.modes[z * n + x];
        spec.modes[z * n + x].h0 = [1.0, 0.0];
        spec.modes[z * n + x].h0_minus_conj = [0.0, 0.0];
        spec.modes[z * n + n - x].h0 = [0.0, 0.0];
        spec.modes[z * n + n - x].h0_minus_conj = [1.0, 0.0];
        let k = own.kx as f64;
        let c = quantized_omega(own.omega_cycles) / k;
        let dt = 2.0;
        let f0 = OceanFields::evaluate(&spec, 100.0);
        let f1 = OceanFields::evaluate(&spec, 100.0 + dt);
        // h(x, t+dt) = h(x − c·dt, t): compare by sampling.
        for i in 0..20 {
            let xs = i as f64 * 37.0;
            let a = f1.sample_cascade(0, xs, 5.0)[1];
            let b = f0.sample_cascade(0, xs - c * dt, 5.0)[1];
            assert!((a - b).abs() < 0.02, "x {xs}: {a} vs {b}");
        }
    }

    #[test]
    fn no_jitter_after_hours_and_exact_repeat() {
        let st = settings(SpectrumKind::Jonswap, 12.0, 32, 2);
        let spec = OceanSpectrum::new(&st);
        let t = 10.0 * 3600.0 + 0.25;
        let a = OceanFields::evaluate(&spec, t);
        let b = OceanFields::evaluate(&spec, t + REPEAT_PERIOD_S);
        for (p, q) in a.texels.iter().zip(&b.texels) {
            for i in 0..8 {
                assert!((p[i] - q[i]).abs() < 1e-4);
            }
        }
        // And the integer phase agrees with f64 evaluation of ω·t to 1e-5 turns.
        for m in spec.modes.iter().take(200) {
            let exact = (quantized_omega(m.omega_cycles) * t / (2.0 * PI)).rem_euclid(1.0);
            let ours = phase_of(m.omega_cycles, time_phase(t)) as f64 / (2.0 * PI);
            let d = (exact - ours + 0.5).rem_euclid(1.0) - 0.5;
            assert!(d.abs() < 1e-5, "turn error {d}");
        }
    }

    #[test]
    fn height_at_inverts_the_choppy_displacement() {
        let st = settings(SpectrumKind::PiersonMoskowitz, 14.0, 64, 2);
        let fields = OceanFields::evaluate(&OceanSpectrum::new(&st), 50.0);
        for i in 0..50 {
            let (px, pz) = (i as f64 * 13.7, i as f64 * -7.3);
            let s = fields.sample(px, pz);
            let (wx, wz) = (px + s.displacement[0] as f64, pz + s.displacement[2] as f64);
            let h = fields.height_at(wx, wz);
            assert!(
                (h - s.displacement[1]).abs() < 0.02,
                "at ({wx},{wz}): {h} vs {}",
                s.displacement[1]
            );
        }
    }

    #[test]
    fn a_dead_calm_is_a_flat_sea_not_a_crash() {
        for kind in [SpectrumKind::Phillips, SpectrumKind::PiersonMoskowitz, SpectrumKind::Jonswap]
        {
            let s = settings(kind, 0.0, 32, 2);
            let spectrum = OceanSpectrum::new(&s);
            let v = spectrum.expected_variance();
            assert!(v.is_finite() && v < 1e-6, "{kind:?}: variance {v}");
        }
    }

    /// One mode of amplitude a, displaced by λ: a trochoid, whose crest
    /// (h > 0) spans π/k − 2λa of each wavelength 2π/k, so the crest is the
    /// narrow part (Gerstner; the sign Tessendorf's −i·k̂·h̃ gets wrong with
    /// an e^(+ik·x) transform).
    #[test]
    fn choppy_displacement_sharpens_crests_as_a_trochoid() {
        let n = 64;
        let mut st = settings(SpectrumKind::PiersonMoskowitz, 10.0, n, 1);
        st.choppiness = 1.0;
        let mut spec = OceanSpectrum::new(&st);
        let x = 3usize;
        for m in spec.modes.iter_mut() {
            m.h0 = [0.0, 0.0];
            m.h0_minus_conj = [0.0, 0.0];
        }
        // h = 2·Re(h0·e^(i(kx − ωt))) with h0 = a/2.
        let a = 16.0f32;
        spec.modes[x].h0 = [a / 2.0, 0.0];
        spec.modes[n - x].h0_minus_conj = [a / 2.0, 0.0];
        let k = spec.modes[x].kx as f64;
        let fields = OceanFields::evaluate(&spec, 0.0);
        let wavelength = 2.0 * PI / k;
        let samples = 4000;
        let crest = (0..samples)
            .filter(|&i| fields.height_at(i as f64 * wavelength / samples as f64, 0.0) > 0.0)
            .count() as f64
            / samples as f64;
        let expected = 0.5 - st.choppiness * a as f64 * k / PI;
        assert!(expected < 0.45, "the test's wave must be steep: {expected}");
        assert!((crest - expected).abs() < 0.01, "crest share {crest}, trochoid {expected}");
    }

    /// On a random sea the surface is squeezed (J < 1) where it is high:
    /// folds, where whitecaps are drawn, come on crests.
    #[test]
    fn a_random_sea_folds_on_its_crests() {
        let spectrum = OceanSpectrum::new(&settings(SpectrumKind::Jonswap, 12.0, 64, 1));
        let fields = OceanFields::evaluate(&spectrum, 10.0);
        let samples: Vec<_> =
            fields.texels.iter().map(|t| SurfaceSample::from_fields(*t)).collect();
        let mean = |f: &dyn Fn(&SurfaceSample) -> f64| {
            samples.iter().map(f).sum::<f64>() / samples.len() as f64
        };
        let (h, j) = (mean(&|s| s.displacement[1] as f64), mean(&|s| s.jacobian() as f64));
        let covariance = mean(&|s| (s.displacement[1] as f64 - h) * (s.jacobian() as f64 - j));
        let sd = |f: &dyn Fn(&SurfaceSample) -> f64, m: f64| mean(&|s| (f(s) - m).powi(2)).sqrt();
        let correlation =
            covariance / (sd(&|s| s.displacement[1] as f64, h) * sd(&|s| s.jacobian() as f64, j));
        assert!(correlation < -0.3, "height and stretch correlate by {correlation}");
    }

    /// All of a spectrum's modes as travelling waves are the surface the
    /// FFT draws (height and choppy displacement), and its strongest 1024
    /// of 4096 hold nearly all of its height.
    #[test]
    fn the_strongest_waves_are_the_fft_surface() {
        let spectrum = OceanSpectrum::new(&settings(SpectrumKind::Jonswap, 10.0, 64, 1));
        let t = 1234.5;
        let fields = OceanFields::evaluate(&spectrum, t);
        let all = spectrum.strongest_waves(usize::MAX);
        let strongest = spectrum.strongest_waves(1024);
        let (mut error, mut total) = (0.0, 0.0);
        // On the FFT's own grid, where its samples are exact.
        let cell = spectrum.settings.patch_size / 64.0;
        for i in 0..30 {
            let (x, z) = (cell * (3 * i) as f64, cell * (1 - 5 * i) as f64);
            let fft = fields.sample(x, z);
            let sum = all.sample(x, z, t);
            for c in 0..3 {
                let (a, b) = (fft.displacement[c], sum.displacement[c]);
                assert!((a - b).abs() < 1e-3 * (1.0 + a.abs()), "at ({x}, {z})[{c}]: {a} vs {b}");
            }
            let (h, s) = (fields.height_at(x, z) as f64, strongest.height_at(x, z, t) as f64);
            error += (h - s).powi(2);
            total += h * h;
        }
        assert!(error / total < 0.06, "the strongest 1024 miss {:.3} of the height", error / total);
    }
}
