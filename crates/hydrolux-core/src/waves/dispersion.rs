//! Dispersion of surface gravity waves: ω² = g·k·tanh(k·h) (Tessendorf,
//! *Simulating Ocean Water* §3.2; finite depth h), and the group speed dω/dk
//! needed to move a frequency spectrum S(ω) onto wave numbers.

/// Standard gravity, m/s².
pub const GRAVITY: f64 = 9.81;

/// Angular frequency ω(k) in rad/s for wave number `k` (rad/m) over water of
/// `depth` metres. Deep water (k·h > 20) uses ω² = g·k exactly.
pub fn omega(k: f64, depth: f64) -> f64 {
    let kh = k * depth;
    if kh > 20.0 { (GRAVITY * k).sqrt() } else { (GRAVITY * k * kh.tanh()).sqrt() }
}

/// dω/dk at `k`, the group speed.
pub fn domega_dk(k: f64, depth: f64) -> f64 {
    let w = omega(k, depth);
    if w <= 0.0 {
        return 0.0;
    }
    let kh = k * depth;
    if kh > 20.0 {
        return 0.5 * GRAVITY / w;
    }
    let th = kh.tanh();
    let sech2 = 1.0 - th * th;
    GRAVITY * (th + kh * sech2) / (2.0 * w)
}

/// Inverse of the deep-water relation: k = ω² / g.
pub fn deep_wave_number(omega: f64) -> f64 {
    omega * omega / GRAVITY
}

/// Wave number for frequency `omega` at `depth`, by Newton iteration on the
/// finite-depth relation (monotonic, so it converges from the deep guess).
pub fn wave_number(omega: f64, depth: f64) -> f64 {
    let mut k = deep_wave_number(omega).max(omega / (GRAVITY * depth).sqrt());
    for _ in 0..50 {
        let f = self::omega(k, depth) - omega;
        let d = domega_dk(k, depth);
        if d <= 0.0 {
            break;
        }
        let step = f / d;
        k = (k - step).max(k * 0.1);
        if step.abs() < 1e-12 * k {
            break;
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_water_wave_of_100m_has_8_second_period() {
        let k = 2.0 * std::f64::consts::PI / 100.0;
        let period = 2.0 * std::f64::consts::PI / omega(k, 10_000.0);
        assert!((period - 8.004).abs() < 0.01, "period {period}");
        // Group speed is half the phase speed in deep water.
        let c = omega(k, 10_000.0) / k;
        assert!((domega_dk(k, 10_000.0) - c / 2.0).abs() < 1e-9);
    }

    #[test]
    fn shallow_water_waves_travel_at_sqrt_gh() {
        let depth = 2.0;
        let k = 2.0 * std::f64::consts::PI / 500.0; // wavelength ≫ depth
        let c = omega(k, depth) / k;
        assert!((c - (GRAVITY * depth).sqrt()).abs() / c < 1e-3, "c = {c}");
        // Shallow waves are non-dispersive: group speed = phase speed.
        assert!((domega_dk(k, depth) - c).abs() / c < 2e-3);
    }

    #[test]
    fn group_speed_matches_numeric_derivative_and_inverse_round_trips() {
        for &depth in &[1.0, 5.0, 50.0, 1000.0] {
            for &k in &[0.01, 0.1, 0.5, 2.0, 10.0] {
                let h = 1e-6 * k;
                let numeric = (omega(k + h, depth) - omega(k - h, depth)) / (2.0 * h);
                assert!((numeric - domega_dk(k, depth)).abs() < 1e-6 * numeric.max(1.0));
                let back = wave_number(omega(k, depth), depth);
                assert!((back - k).abs() < 1e-9 * k.max(1.0), "k {k} depth {depth} back {back}");
            }
        }
    }
}
