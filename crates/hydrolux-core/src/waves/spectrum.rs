//! Ocean wave spectra and directional spreading.
//!
//! Frequency spectra S(ω) (m²·s): Pierson–Moskowitz (fully developed sea) and
//! JONSWAP (fetch-limited, peak enhancement γ); the Phillips spectrum of
//! Tessendorf's *Simulating Ocean Water* is defined on wave numbers. All are
//! turned into a directional wave-number density Ψ(kx, kz) (m⁴) whose integral
//! over the plane is the height variance. Seed 000 §2.3.1.

use super::dispersion::{GRAVITY, domega_dk, omega};

/// The spectrum family. Names match the scene key `ocean.spectrum`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    Phillips,
    PiersonMoskowitz,
    Jonswap,
}

/// Everything that shapes the sea state.
#[derive(Clone, Debug, PartialEq)]
pub struct SeaState {
    pub kind: SpectrumKind,
    /// Wind speed (m/s), 19.5 m above the sea for Pierson–Moskowitz, 10 m for JONSWAP.
    pub wind_speed: f64,
    /// Direction the wind blows towards, radians from +x towards +z.
    pub wind_direction: f64,
    /// Fetch in metres (JONSWAP only).
    pub fetch: f64,
    /// Water depth in metres (finite-depth dispersion).
    pub depth: f64,
    /// JONSWAP peak enhancement γ (3.3 in the JONSWAP fit).
    pub peak_enhancement: f64,
    /// Exponent s of the cos^(2s)(θ/2) spreading (larger is narrower).
    pub spreading: f64,
}

/// Phillips constant shared by PM and Phillips.
const ALPHA_PM: f64 = 8.1e-3;

impl SeaState {
    /// Peak angular frequency ωp (rad/s).
    pub fn peak_omega(&self) -> f64 {
        let u = self.wind_speed.max(1e-3);
        match self.kind {
            SpectrumKind::PiersonMoskowitz | SpectrumKind::Phillips => 0.855 * GRAVITY / u,
            SpectrumKind::Jonswap => {
                22.0 * (GRAVITY * GRAVITY / (u * self.effective_fetch())).powf(1.0 / 3.0)
            }
        }
    }

    /// Fetch (m) used by JONSWAP: the given fetch, capped where the sea is
    /// fully developed (where JONSWAP's peak frequency reaches
    /// Pierson–Moskowitz's 0.855·g/U). A longer fetch adds no energy.
    pub fn effective_fetch(&self) -> f64 {
        let u = self.wind_speed.max(1e-3);
        let fully_developed = u * u / (GRAVITY * (0.855f64 / 22.0).powi(3));
        // max(1): in a near calm even a 1 m fetch is "fully developed".
        self.fetch.clamp(1.0, fully_developed.max(1.0))
    }

    /// One-sided frequency spectrum S(ω) in m²·s (∫S dω = height variance).
    /// For Phillips it is derived from the wave-number form through dispersion.
    pub fn frequency_spectrum(&self, w: f64) -> f64 {
        if w <= 0.0 {
            return 0.0;
        }
        let g = GRAVITY;
        let wp = self.peak_omega();
        match self.kind {
            SpectrumKind::PiersonMoskowitz => {
                ALPHA_PM * g * g / w.powi(5) * (-1.25 * (wp / w).powi(4)).exp()
            }
            SpectrumKind::Jonswap => {
                let u = self.wind_speed.max(1e-3);
                let alpha = 0.076 * (u * u / (self.effective_fetch() * g)).powf(0.22);
                let sigma = if w <= wp { 0.07 } else { 0.09 };
                let r = (-(w - wp).powi(2) / (2.0 * sigma * sigma * wp * wp)).exp();
                alpha * g * g / w.powi(5)
                    * (-1.25 * (wp / w).powi(4)).exp()
                    * self.peak_enhancement.powf(r)
            }
            SpectrumKind::Phillips => {
                let k = super::dispersion::wave_number(w, self.depth);
                self.phillips_k(k) / domega_dk(k, self.depth)
            }
        }
    }

    /// Phillips omnidirectional wave-number spectrum F(k) = α/2·k⁻³·e^(−1/(kL)²)
    /// with L = U²/g, and Tessendorf's small-wave damping e^(−k²ℓ²), ℓ = L/1000.
    fn phillips_k(&self, k: f64) -> f64 {
        if k <= 0.0 {
            return 0.0;
        }
        let l = self.wind_speed.max(1e-3).powi(2) / GRAVITY;
        let small = l / 1000.0;
        0.5 * ALPHA_PM / k.powi(3) * (-1.0 / (k * l).powi(2)).exp() * (-(k * small).powi(2)).exp()
    }

    /// Omnidirectional wave-number spectrum F(k) in m³ (∫F dk = variance).
    pub fn wavenumber_spectrum(&self, k: f64) -> f64 {
        if k <= 0.0 {
            return 0.0;
        }
        match self.kind {
            SpectrumKind::Phillips => self.phillips_k(k),
            _ => self.frequency_spectrum(omega(k, self.depth)) * domega_dk(k, self.depth),
        }
    }

    /// Directional density Ψ(kx, kz) = F(k)·D(θ)/k in m⁴: its integral over the
    /// wave-number plane is the height variance.
    pub fn directional_density(&self, kx: f64, kz: f64, spreading: &Spreading) -> f64 {
        let k = (kx * kx + kz * kz).sqrt();
        if k <= 0.0 {
            return 0.0;
        }
        let theta = kz.atan2(kx) - self.wind_direction;
        self.wavenumber_spectrum(k) * spreading.density(theta) / k
    }

    /// Height variance m0 = ∫ S(ω) dω, integrated numerically.
    pub fn variance(&self) -> f64 {
        // The spectra vanish quickly below ωp/3; integrate in log ω.
        let wp = self.peak_omega();
        let (lo, hi) = ((wp / 8.0).ln(), (wp * 200.0).ln());
        let n = 20_000;
        let dh = (hi - lo) / n as f64;
        (0..n)
            .map(|i| {
                let w = (lo + (i as f64 + 0.5) * dh).exp();
                self.frequency_spectrum(w) * w * dh
            })
            .sum()
    }

    /// Significant wave height Hs = 4·√m0.
    pub fn significant_wave_height(&self) -> f64 {
        4.0 * self.variance().sqrt()
    }
}

/// Longuet-Higgins spreading D(θ) = C·cos^(2s)(θ/2), normalised so that
/// ∫ D dθ = 1 over the full circle.
#[derive(Clone, Debug)]
pub struct Spreading {
    s: f64,
    norm: f64,
}

impl Spreading {
    pub fn new(s: f64) -> Self {
        let n = 8192;
        let d = 2.0 * std::f64::consts::PI / n as f64;
        let integral: f64 = (0..n)
            .map(|i| {
                let theta = -std::f64::consts::PI + (i as f64 + 0.5) * d;
                (theta / 2.0).cos().abs().powf(2.0 * s) * d
            })
            .sum();
        Spreading { s, norm: 1.0 / integral }
    }

    pub fn density(&self, theta: f64) -> f64 {
        self.norm * (theta / 2.0).cos().abs().powf(2.0 * self.s)
    }
}

/// Cox & Munk (1954) mean-square slopes of a wind-roughened sea, rotated
/// from (upwind, crosswind) into the world's (x, z):
/// σu² = 3.16e-3·U, σc² = 0.003 + 1.92e-3·U (U at 12.5 m, m/s).
pub fn cox_munk_slope_variance(wind_speed: f64, wind_direction: f64) -> [f64; 2] {
    let up = 3.16e-3 * wind_speed;
    let cross = 0.003 + 1.92e-3 * wind_speed;
    let (s, c) = wind_direction.sin_cos();
    [up * c * c + cross * s * s, up * s * s + cross * c * c]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pm(u: f64) -> SeaState {
        SeaState {
            kind: SpectrumKind::PiersonMoskowitz,
            wind_speed: u,
            wind_direction: 0.0,
            fetch: 100_000.0,
            depth: 10_000.0,
            peak_enhancement: 3.3,
            spreading: 8.0,
        }
    }

    #[test]
    fn pierson_moskowitz_significant_height_is_0_21_u2_over_g() {
        for u in [5.0, 10.0, 20.0] {
            let hs = pm(u).significant_wave_height();
            let expected = 0.2202 * u * u / GRAVITY; // 4·√(α/(5·0.855⁴))
            assert!((hs / expected - 1.0).abs() < 0.005, "U={u}: Hs={hs} expected {expected}");
            assert!((hs / (0.21 * u * u / GRAVITY) - 1.0).abs() < 0.06);
        }
    }

    #[test]
    fn wavenumber_spectrum_integrates_to_the_same_variance() {
        let s = pm(12.0);
        let (lo, hi) = (1e-4f64.ln(), 50f64.ln());
        let n = 40_000;
        let dh = (hi - lo) / n as f64;
        let var_k: f64 = (0..n)
            .map(|i| {
                let k = (lo + (i as f64 + 0.5) * dh).exp();
                s.wavenumber_spectrum(k) * k * dh
            })
            .sum();
        assert!((var_k / s.variance() - 1.0).abs() < 1e-3);
    }

    #[test]
    fn jonswap_peaks_higher_than_pm_and_grows_with_fetch() {
        let mut j = pm(10.0);
        j.kind = SpectrumKind::Jonswap;
        j.fetch = 50_000.0;
        let wp = j.peak_omega();
        let mut j1 = j.clone();
        j1.peak_enhancement = 1.0;
        let ratio = j.frequency_spectrum(wp) / j1.frequency_spectrum(wp);
        assert!((ratio - 3.3).abs() < 1e-9, "γ enhancement at the peak {ratio}");
        let mut longer = j.clone();
        longer.fetch = 200_000.0;
        assert!(longer.significant_wave_height() > j.significant_wave_height());
        assert!(longer.peak_omega() < j.peak_omega());
    }

    #[test]
    fn jonswap_saturates_at_full_development() {
        let mut j = pm(9.0);
        j.kind = SpectrumKind::Jonswap;
        j.fetch = 5_000_000.0;
        // Beyond the fully developed fetch the peak sits at Pierson–Moskowitz's.
        assert!((j.peak_omega() - 0.855 * GRAVITY / 9.0).abs() < 1e-9);
        let mut longer = j.clone();
        longer.fetch = 50_000_000.0;
        assert_eq!(j.significant_wave_height(), longer.significant_wave_height());
        // A fresh breeze (Beaufort 5) over open water: Hs of a couple of metres.
        let hs = j.significant_wave_height();
        assert!((1.8..2.8).contains(&hs), "Hs {hs}");
    }

    #[test]
    fn spreading_is_normalised_and_peaks_downwind() {
        let sp = Spreading::new(6.0);
        let n = 10_000;
        let d = 2.0 * std::f64::consts::PI / n as f64;
        let total: f64 =
            (0..n).map(|i| sp.density(-std::f64::consts::PI + (i as f64 + 0.5) * d) * d).sum();
        assert!((total - 1.0).abs() < 1e-6);
        assert!(sp.density(0.0) > sp.density(1.0));
        assert!(sp.density(std::f64::consts::PI) < 1e-9);
    }
}
