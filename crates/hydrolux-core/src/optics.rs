//! Geometric optics at a water surface: reflection, refraction with total
//! internal reflection, and Fresnel reflectance.
//!
//! Seed 000 §2.1.1 (eq. 2.1–2.2), §2.1.2 (exact unpolarized Fresnel, after
//! Glassner) and §3.2 (Schlick, eq. 3.1–3.2). The WGSL twin is
//! `shaders/shared/optics.wgsl` in the `hydrolux` crate.

use glam::Vec3;

/// Refractive index of air.
pub const IOR_AIR: f32 = 1.0;
/// Refractive index of water at visible wavelengths (about 1.333 at 589 nm).
pub const IOR_WATER: f32 = 1.333;

/// Which Fresnel formula shades the surface. `Exact` is the default; the
/// approximations exist to compare against it. Every mode gives the
/// reflectance R; the transmittance is always 1 − R, so energy is conserved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FresnelMode {
    Exact,
    /// Seed 000 eq. 3.1–3.2.
    Schlick,
    /// Jensen & Goliáš: R = 1/(1 + cos θ)^8 (seed 003 eq. 27).
    JensenGolias,
    /// R = (1 − E·N)^q with a free exponent q (seed 002 eq. 3).
    Power(f32),
}

/// Mirror `incident` (pointing towards the surface) about `normal`.
/// Same convention as GLSL/WGSL `reflect`.
pub fn reflect(incident: Vec3, normal: Vec3) -> Vec3 {
    incident - 2.0 * incident.dot(normal) * normal
}

/// Refract `incident` (unit, pointing towards the surface) through a surface
/// with unit `normal` facing the incident side, going from index `n1` to `n2`.
/// Returns `None` on total internal reflection. Same convention as WGSL
/// `refract(I, N, n1 / n2)`.
pub fn refract(incident: Vec3, normal: Vec3, n1: f32, n2: f32) -> Option<Vec3> {
    let eta = n1 / n2;
    let cos_i = -incident.dot(normal);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 { None } else { Some(eta * incident + (eta * cos_i - k.sqrt()) * normal) }
}

/// Critical angle (radians) for light going from `n1` into a less dense `n2`;
/// `None` when `n1 <= n2` (no total internal reflection possible).
pub fn critical_angle(n1: f32, n2: f32) -> Option<f32> {
    (n1 > n2).then(|| (n2 / n1).asin())
}

/// Exact unpolarized Fresnel reflectance R = (Rs + Rp) / 2 for light arriving
/// with `cos_i` = cos θi from medium `n1` into `n2` (seed 000 §2.1.2).
/// Returns 1 beyond the critical angle. Transmittance is `1 - R`.
pub fn fresnel_exact(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t = n1 / n2 * (1.0 - cos_i * cos_i).max(0.0).sqrt();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let rp = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
    0.5 * (rs * rs + rp * rp)
}

/// Reflectance at normal incidence, R(0) = ((n1 - n2) / (n1 + n2))² (seed 000 eq. 3.2).
pub fn fresnel_r0(n1: f32, n2: f32) -> f32 {
    let r = (n1 - n2) / (n1 + n2);
    r * r
}

/// Schlick's approximation R(θ) = R0 + (1 - R0)(1 - cos θ)^5 (seed 000 eq. 3.1).
/// When leaving the denser medium the angle is taken on the transmitted side,
/// so the approximation also shows total internal reflection.
pub fn fresnel_schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let mut cos = cos_i.clamp(0.0, 1.0);
    if n1 > n2 {
        let sin_t2 = (n1 / n2).powi(2) * (1.0 - cos * cos);
        if sin_t2 >= 1.0 {
            return 1.0;
        }
        cos = (1.0 - sin_t2).sqrt();
    }
    let r0 = fresnel_r0(n1, n2);
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

/// cos θ for an approximation that only knows external reflection: leaving
/// the denser medium, the transmitted angle (or `None` beyond the critical angle).
fn external_cos(cos_i: f32, n1: f32, n2: f32) -> Option<f32> {
    let cos = cos_i.clamp(0.0, 1.0);
    if n1 <= n2 {
        return Some(cos);
    }
    let sin_t2 = (n1 / n2).powi(2) * (1.0 - cos * cos);
    (sin_t2 < 1.0).then(|| (1.0 - sin_t2).sqrt())
}

/// Jensen & Goliáš' fit R = 1/(1 + cos θ)^8 (seed 003 eq. 27): 1/256 at
/// normal incidence (too low for water's 0.02), 1 at grazing.
pub fn fresnel_jensen_golias(cos_i: f32, n1: f32, n2: f32) -> f32 {
    external_cos(cos_i, n1, n2).map_or(1.0, |c| (1.0 + c).powi(-8))
}

/// The artistic (1 − E·N)^q of seed 002 eq. 3.
pub fn fresnel_power(cos_i: f32, n1: f32, n2: f32, q: f32) -> f32 {
    external_cos(cos_i, n1, n2).map_or(1.0, |c| (1.0 - c).powf(q))
}

/// Fresnel reflectance with the chosen formula.
pub fn fresnel(mode: FresnelMode, cos_i: f32, n1: f32, n2: f32) -> f32 {
    match mode {
        FresnelMode::Exact => fresnel_exact(cos_i, n1, n2),
        FresnelMode::Schlick => fresnel_schlick(cos_i, n1, n2),
        FresnelMode::JensenGolias => fresnel_jensen_golias(cos_i, n1, n2),
        FresnelMode::Power(q) => fresnel_power(cos_i, n1, n2, q),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_air_water_is_two_percent() {
        let r = fresnel_exact(1.0, IOR_AIR, IOR_WATER);
        assert!((r - 0.02037).abs() < 2e-4, "R(0) = {r}");
        assert!((r - fresnel_r0(IOR_AIR, IOR_WATER)).abs() < 1e-6);
        assert!((fresnel_schlick(1.0, IOR_AIR, IOR_WATER) - r).abs() < 1e-6);
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        assert!(fresnel_exact(0.0, IOR_AIR, IOR_WATER) > 0.999);
        assert!(fresnel_schlick(0.0, IOR_AIR, IOR_WATER) > 0.999);
    }

    #[test]
    fn brewster_angle_kills_p_polarisation() {
        // At Brewster's angle Rp = 0, so R = Rs / 2; Rs at 53.1° is about 0.0765.
        let theta_b = (IOR_WATER / IOR_AIR).atan();
        let r = fresnel_exact(theta_b.cos(), IOR_AIR, IOR_WATER);
        assert!((r - 0.0383).abs() < 1e-3, "R(Brewster) = {r}");
    }

    #[test]
    fn critical_angle_of_water_is_48_6_degrees() {
        let c = critical_angle(IOR_WATER, IOR_AIR).unwrap().to_degrees();
        assert!((c - 48.61).abs() < 0.05, "critical angle {c}");
        assert!(critical_angle(IOR_AIR, IOR_WATER).is_none());
        // Just inside the critical angle light gets out; just beyond it is totally reflected.
        let just_inside = (c - 0.2).to_radians().cos();
        let beyond = (c + 0.2).to_radians().cos();
        assert!(fresnel_exact(just_inside, IOR_WATER, IOR_AIR) < 1.0);
        assert_eq!(fresnel_exact(beyond, IOR_WATER, IOR_AIR), 1.0);
        assert_eq!(fresnel_schlick(beyond, IOR_WATER, IOR_AIR), 1.0);
    }

    #[test]
    fn schlick_stays_close_to_exact_from_air() {
        for i in 0..=90 {
            let cos = (i as f32).to_radians().cos();
            let e = fresnel_exact(cos, IOR_AIR, IOR_WATER);
            let s = fresnel_schlick(cos, IOR_AIR, IOR_WATER);
            assert!((e - s).abs() < 0.06, "{i}°: exact {e} schlick {s}");
        }
    }

    #[test]
    fn every_mode_reflects_between_zero_and_one_with_tir() {
        let modes = [
            FresnelMode::Exact,
            FresnelMode::Schlick,
            FresnelMode::JensenGolias,
            FresnelMode::Power(5.0),
        ];
        let c = critical_angle(IOR_WATER, IOR_AIR).unwrap();
        for m in modes {
            for i in 0..=90 {
                let cos = (i as f32).to_radians().cos();
                for (n1, n2) in [(IOR_AIR, IOR_WATER), (IOR_WATER, IOR_AIR)] {
                    let r = fresnel(m, cos, n1, n2);
                    assert!((0.0..=1.0).contains(&r), "{m:?} {i}° {n1}->{n2}: {r}");
                }
            }
            assert_eq!(fresnel(m, (c + 0.01).cos(), IOR_WATER, IOR_AIR), 1.0, "{m:?} has TIR");
            assert!(fresnel(m, 0.0, IOR_AIR, IOR_WATER) > 0.99, "{m:?} is a mirror at grazing");
        }
        assert!((fresnel_jensen_golias(1.0, IOR_AIR, IOR_WATER) - 1.0 / 256.0).abs() < 1e-7);
        assert_eq!(fresnel_power(1.0, IOR_AIR, IOR_WATER, 5.0), 0.0);
        assert!((fresnel_power(0.5, IOR_AIR, IOR_WATER, 2.0) - 0.25).abs() < 1e-6);
    }

    #[test]
    fn refraction_obeys_snell_and_tir() {
        let n = Vec3::Y;
        for deg in [0.0f32, 10.0, 30.0, 60.0, 85.0] {
            let t = deg.to_radians();
            let i = Vec3::new(t.sin(), -t.cos(), 0.0);
            let r = refract(i, n, IOR_AIR, IOR_WATER).unwrap();
            assert!((r.length() - 1.0).abs() < 1e-5);
            let sin_t = r.x;
            assert!((IOR_AIR * t.sin() - IOR_WATER * sin_t).abs() < 1e-5);
            let refl = reflect(i, n);
            assert!((refl - Vec3::new(i.x, -i.y, 0.0)).length() < 1e-6);
        }
        // From below at 60° (beyond 48.6°) there is no transmitted ray.
        let t = 60f32.to_radians();
        let up = Vec3::new(t.sin(), t.cos(), 0.0);
        assert!(refract(up, -Vec3::Y, IOR_WATER, IOR_AIR).is_none());
    }
}
