//! Light through a refractive object (seed 004, after Hu et al. 2010): the
//! path of a sunbeam that enters a closed object at p0, refracts, leaves at
//! p1, refracts again and travels on. CPU reference of
//! `passes/water_object`, exact for a sphere and for a flat plate (a glass's
//! wall), where the GPU marches depth maps from the light instead of
//! intersecting analytically.

use crate::optics::{IOR_AIR, fresnel_exact, refract};
use glam::Vec3;

/// One sunbeam through the object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPath {
    /// Entry point on the front face.
    pub p0: Vec3,
    /// Exit point on the back face.
    pub p1: Vec3,
    /// Unit direction after leaving.
    pub exit_dir: Vec3,
    /// Fraction of the beam's power the two surfaces let through (Fresnel),
    /// before absorption inside.
    pub transmitted: f32,
    /// Distance travelled inside (m), for absorption e^(−σa·d).
    pub inside: f32,
}

/// The far intersection of the ray `origin + t·dir` (unit `dir`) with a
/// sphere, and the near one: (t_near, t_far).
fn sphere_hits(centre: Vec3, radius: f32, origin: Vec3, dir: Vec3) -> Option<(f32, f32)> {
    let oc = origin - centre;
    let b = oc.dot(dir);
    let c = oc.length_squared() - radius * radius;
    let disc = b * b - c;
    (disc >= 0.0).then(|| (-b - disc.sqrt(), -b + disc.sqrt()))
}

/// The path of the sunbeam travelling along `travel` (unit) through
/// `origin` into a sphere of index of refraction `ior`; `None` if it misses
/// or is totally reflected at the back face (the GPU drops those too).
pub fn sphere_path(
    centre: Vec3,
    radius: f32,
    ior: f32,
    origin: Vec3,
    travel: Vec3,
) -> Option<LightPath> {
    let (t0, _) = sphere_hits(centre, radius, origin, travel)?;
    let p0 = origin + travel * t0;
    let n0 = (p0 - centre) / radius;
    let cos0 = -travel.dot(n0);
    let inside_dir = refract(travel, n0, IOR_AIR, ior)?;
    // From p0 the refracted ray is inside: its far hit is the exit.
    let (_, t1) = sphere_hits(centre, radius, p0, inside_dir)?;
    let p1 = p0 + inside_dir * t1;
    let n1 = (p1 - centre) / radius;
    let cos1 = inside_dir.dot(n1);
    let exit_dir = refract(inside_dir, -n1, ior, IOR_AIR)?;
    let transmitted =
        (1.0 - fresnel_exact(cos0, IOR_AIR, ior)) * (1.0 - fresnel_exact(cos1, ior, IOR_AIR));
    Some(LightPath { p0, p1, exit_dir, transmitted, inside: t1 })
}

/// The path of the sunbeam travelling along `travel` (unit) through
/// `origin` across a flat plate of index of refraction `ior` (a glass
/// tank's wall): faces at ±`half_thickness` along the unit `normal` from
/// `centre`, unbounded across them. A parallel plate hands the beam on in
/// its own direction, shifted sideways by d·sin(θ − θt)/cos θt; `None` if
/// the beam runs along the faces.
pub fn plate_path(
    centre: Vec3,
    normal: Vec3,
    half_thickness: f32,
    ior: f32,
    origin: Vec3,
    travel: Vec3,
) -> Option<LightPath> {
    // The face the beam meets first is the one facing against it.
    let front = if normal.dot(travel) < 0.0 { normal } else { -normal };
    let cos0 = -front.dot(travel);
    if cos0 < 1e-4 {
        return None;
    }
    let t0 = front.dot(centre + front * half_thickness - origin) / -cos0;
    let p0 = origin + travel * t0;
    let inside_dir = refract(travel, front, IOR_AIR, ior)?;
    let cos1 = -front.dot(inside_dir);
    let inside = 2.0 * half_thickness / cos1;
    let p1 = p0 + inside_dir * inside;
    let exit_dir = refract(inside_dir, front, ior, IOR_AIR)?;
    let transmitted =
        (1.0 - fresnel_exact(cos0, IOR_AIR, ior)) * (1.0 - fresnel_exact(cos1, ior, IOR_AIR));
    Some(LightPath { p0, p1, exit_dir, transmitted, inside })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A parallel plate: the beam leaves as it came, shifted sideways by
    /// the textbook d·sin(θ − θt)/cos θt, and the two faces let through
    /// (1 − R)² of it, R the Fresnel reflectance at each (equal by Stokes).
    #[test]
    fn a_plate_hands_the_beam_on_unbent_and_shifted() {
        let travel = Vec3::new(0.6, -0.5, 0.2).normalize();
        let (d, ior) = (0.014, 1.5);
        let p = plate_path(Vec3::ZERO, Vec3::X, 0.5 * d, ior, Vec3::new(-1.0, 0.3, 0.1), travel)
            .expect("crosses");
        assert!((p.exit_dir - travel).length() < 1e-5, "{}", p.exit_dir);
        assert!((p.p0.x + 0.5 * d).abs() < 1e-6 && (p.p1.x - 0.5 * d).abs() < 1e-6);
        let theta = travel.x.acos();
        let theta_t = (theta.sin() / ior).asin();
        let shift = d * (theta - theta_t).sin() / theta_t.cos();
        // The exit's distance from the unbent line through p0.
        let off = (p.p1 - p.p0).reject_from(travel).length();
        assert!((off - shift).abs() < 1e-6, "shift {off} vs {shift}");
        let r = fresnel_exact(travel.x, IOR_AIR, ior);
        assert!((p.transmitted - (1.0 - r) * (1.0 - r)).abs() < 1e-5, "{}", p.transmitted);
        // Normal incidence: (1 − 0.04)² for glass.
        let n = plate_path(Vec3::ZERO, Vec3::X, 0.5 * d, ior, -Vec3::X, Vec3::X).expect("crosses");
        assert!((n.transmitted - 0.96f32.powi(2)).abs() < 1e-4, "{}", n.transmitted);
        assert!(plate_path(Vec3::ZERO, Vec3::X, d, ior, Vec3::ZERO, Vec3::Y).is_none());
    }

    #[test]
    fn a_central_beam_goes_straight_through() {
        let p = sphere_path(Vec3::ZERO, 1.0, 1.333, Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y)
            .expect("hits");
        assert!((p.p0 - Vec3::Y).length() < 1e-5);
        assert!((p.p1 + Vec3::Y).length() < 1e-5);
        assert!((p.exit_dir - Vec3::NEG_Y).length() < 1e-5);
        let r = ((1.333f32 - 1.0) / 2.333).powi(2);
        assert!((p.transmitted - (1.0 - r).powi(2)).abs() < 1e-5);
        assert!((p.inside - 2.0).abs() < 1e-5);
    }

    #[test]
    fn a_ball_lens_focuses_near_its_paraxial_focus() {
        // Paraxial beams cross the axis at the ball lens's back focal
        // distance: f = n R / (2 (n − 1)) from the centre.
        let (n, r) = (1.333f32, 1.0f32);
        let p =
            sphere_path(Vec3::ZERO, r, n, Vec3::new(0.05, 5.0, 0.0), Vec3::NEG_Y).expect("hits");
        let t = -p.p1.x / p.exit_dir.x;
        let crossing = p.p1 + p.exit_dir * t;
        let focus = n * r / (2.0 * (n - 1.0));
        assert!(
            (-crossing.y - focus).abs() < 0.01 * focus,
            "crosses at {} vs {focus}",
            -crossing.y
        );
        // Snell at both faces: the exit angle equals the entry angle.
        let n0 = p.p0.normalize();
        let n1 = p.p1.normalize();
        assert!((Vec3::NEG_Y.dot(-n0) - p.exit_dir.dot(n1)).abs() < 1e-4);
    }

    #[test]
    fn grazing_beams_lose_most_of_their_power_and_misses_have_no_path() {
        // In a sphere the exit angle equals the entry one, so light always
        // gets out; grazing beams leave with little transmitted power.
        let p = sphere_path(Vec3::ZERO, 1.0, 1.333, Vec3::new(0.999, 5.0, 0.0), Vec3::NEG_Y)
            .expect("hits");
        assert!(p.transmitted < 0.5, "grazing beam transmits {}", p.transmitted);
        assert!(
            sphere_path(Vec3::ZERO, 1.0, 1.333, Vec3::new(1.01, 5.0, 0.0), Vec3::NEG_Y).is_none()
        );
    }
}
