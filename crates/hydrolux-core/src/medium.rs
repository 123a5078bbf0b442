//! The water body as a participating medium: per-channel absorption σa and
//! scattering σs (m⁻¹), extinction σk = σa + σs, and the analytic single
//! scattering of seed 000 §3.3 (eq. 3.3–3.6, after Gath 2008), with an
//! isotropic or Henyey–Greenstein phase function. Also the light field under
//! a flat surface that the renderer uses to light submerged receivers, and
//! [`flat_water_radiance`]: the whole chain for one pixel, the CPU reference
//! the GPU water shader is tested against.
//!
//! Conventions: all light quantities are in the sky module's units (kcd/m²,
//! klx). Radiance inside water is *in-medium* radiance; crossing the surface
//! upwards it is multiplied by the Fresnel transmittance and divided by n²
//! (the n² law of radiance: the solid angle widens on the way out).

use crate::optics::{IOR_AIR, fresnel_exact};
use glam::Vec3;
use std::f32::consts::PI;

/// The named media of `water.medium`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MediumPreset {
    Pure,
    ClearOcean,
    Coastal,
    TurbidHarbor,
}

/// Pure-water absorption at 720, 550 and 450 nm (R, G, B), seed 000 §5.1
/// (after Premože & Ashikhmin 2001).
pub const PURE_WATER_ABSORPTION: [f32; 3] = [1.169, 0.0638, 0.0150];

/// Homogeneous water: coefficients in m⁻¹ for R, G, B.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    pub absorption: Vec3,
    pub scattering: Vec3,
}

impl MediumPreset {
    pub const ALL: [MediumPreset; 4] = [
        MediumPreset::Pure,
        MediumPreset::ClearOcean,
        MediumPreset::Coastal,
        MediumPreset::TurbidHarbor,
    ];

    /// The preset's coefficients. Scattering of the three natural waters is
    /// seed 000 Table 5.1. The seed keeps pure-water absorption for all of
    /// them, which leaves turbid water milky blue-white; real coastal and
    /// harbour water owe their green-brown to dissolved organic matter
    /// ("yellow substance") and sediment, which absorb blue strongly, so
    /// those add a CDOM-like term a·e^(−0.014(λ−440)) on top of pure water.
    /// Pure water scatters only by molecules (Morel 1974: ~0.0006, 0.0019,
    /// 0.0045 m⁻¹ at 720, 550, 450 nm).
    pub fn medium(self) -> Medium {
        let pure = Vec3::from(PURE_WATER_ABSORPTION);
        // e^(−0.014(λ−440)) at 720, 550, 450 nm.
        let cdom = Vec3::new(0.0198, 0.2144, 0.8694);
        let (extra, scattering) = match self {
            MediumPreset::Pure => (0.0, Vec3::new(0.0006, 0.0019, 0.0045)),
            MediumPreset::ClearOcean => (0.01, Vec3::new(0.028, 0.035, 0.039)),
            MediumPreset::Coastal => (0.25, Vec3::new(0.17, 0.20, 0.234)),
            MediumPreset::TurbidHarbor => (2.4, Vec3::new(0.71, 0.82, 0.96)),
        };
        Medium { absorption: pure + extra * cdom, scattering }
    }
}

impl Medium {
    pub fn extinction(&self) -> Vec3 {
        self.absorption + self.scattering
    }

    /// Single-scattering albedo Λ = σs / σk (seed 000 §3.3).
    pub fn albedo(&self) -> Vec3 {
        self.scattering / self.extinction().max(Vec3::splat(1e-9))
    }

    /// Fraction of light left after `distance` metres: e^(−σk·d).
    pub fn transmittance(&self, distance: f32) -> Vec3 {
        (-self.extinction() * distance.max(0.0)).exp()
    }

    /// Radiance scattered towards the viewer along a path of length `s`
    /// inside the water, lit by a collimated beam of irradiance `e0` (on a
    /// plane facing the beam, just under the surface) which itself loses
    /// e^(−σk·c·x) by the time the path has gone x metres (seed 000 eq. 3.5:
    /// the beam's distance to the surface grows as c·x). Seed 000 eq. 3.6:
    /// σs·p·e0·(1 − e^(−σk(1+c)s)) / (σk(1+c)).
    pub fn in_scatter(&self, e0: Vec3, phase: f32, c: f32, s: f32) -> Vec3 {
        self.in_scatter_from(e0, 0.0, phase, c, s)
    }

    /// [`Medium::in_scatter`] for light `e_top` that has come `t` metres
    /// through the water to the path's start (e0 = e_top·e^(−σk·t)), with
    /// both attenuations in one exponent: e^(−σk·t) − e^(−σk(t + (1+c)s)).
    /// For a path that stays in the water both exponents are ≤ 0, so
    /// nothing overflows however deep the eye (a rising path's own gain
    /// e^(σk|1+c|s) alone overflows f32 a few hundred metres down).
    pub fn in_scatter_from(&self, e_top: Vec3, t: f32, phase: f32, c: f32, s: f32) -> Vec3 {
        let s = s.max(0.0);
        let k = self.extinction();
        let integral = Vec3::new(
            attenuated_integral(k.x, t, c, s),
            attenuated_integral(k.y, t, c, s),
            attenuated_integral(k.z, t, c, s),
        );
        self.scattering * phase * e_top * integral
    }
}

/// ∫0^s e^(−k(t + (1+c)x)) dx = (e^(−kt) − e^(−k(t + (1+c)s))) / (k(1+c)),
/// continuous at k(1+c) → 0. The end's exponent is clamped at 0: light
/// never grows past its value at the surface.
fn attenuated_integral(k: f32, t: f32, c: f32, s: f32) -> f32 {
    let a = (k * t).max(0.0);
    let kc = k * (1.0 + c);
    if (kc * s).abs() < 1e-4 {
        (-a).exp() * s * (1.0 - 0.5 * kc * s)
    } else {
        ((-a).exp() - (-(a + kc * s).max(0.0)).exp()) / kc
    }
}

/// Isotropic phase function, 1/(4π) per steradian.
pub const PHASE_ISOTROPIC: f32 = 1.0 / (4.0 * PI);

/// Henyey–Greenstein phase function for the cosine of the angle between the
/// light's travel direction and the scattered direction; g = 0 is isotropic.
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let d = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * PI * d * d.sqrt())
}

/// Mean cosine (from the vertical) of diffuse skylight after it crosses a flat
/// surface: refraction squeezes the hemisphere into the 48.6° Snell cone.
/// For a uniform sky the irradiance-weighted mean is ≈ 0.85 (computed in the tests).
pub const DIFFUSE_MEAN_COSINE: f32 = 0.85;
/// Fraction of uniform diffuse skylight transmitted by a flat surface
/// (1 − the hemispherical Fresnel reflectance 0.066 of water).
pub const DIFFUSE_TRANSMITTANCE: f32 = 0.934;

/// Fraction of the downwelling irradiance that comes back up from below
/// (floor and water) and lights undersides: a grey-world bounce, the least
/// upwelling anywhere (over deep water or a dark floor).
pub const UPWELLING_FRACTION: f32 = 0.15;

/// The light field under a flat water surface at y = 0, lit by the sun and sky.
#[derive(Clone, Copy, Debug)]
pub struct UnderwaterLight {
    /// Direction the refracted sunlight travels (pointing down into the water).
    pub sun_travel: Vec3,
    /// Sun irradiance just below the surface on a plane facing the refracted
    /// beam: E_sun·T(θ)·cos θ / cos θw (the beam narrows as it bends).
    pub sun_irradiance: Vec3,
    /// Sky irradiance just below the surface on a horizontal plane.
    pub sky_irradiance: Vec3,
    /// The floor's depth (m; 0: none) and its mean albedo: a bright,
    /// shallow floor lights undersides above it (a pool's white tiles).
    pub floor_depth: f32,
    pub floor_albedo: f32,
}

impl UnderwaterLight {
    /// `sun_dir` points towards the sun; `sun_illuminance` is on a plane facing
    /// it; `sky_irradiance` on a horizontal plane above the water.
    pub fn new(sun_dir: Vec3, sun_illuminance: Vec3, sky_irradiance: Vec3, ior: f32) -> Self {
        let cos_sun = sun_dir.y.max(0.0);
        let incident = -sun_dir;
        let travel = crate::optics::refract(incident, Vec3::Y, IOR_AIR, ior).unwrap_or(Vec3::NEG_Y);
        let cos_w = (-travel.y).max(1e-3);
        let t = 1.0 - fresnel_exact(cos_sun, IOR_AIR, ior);
        UnderwaterLight {
            sun_travel: travel,
            sun_irradiance: if cos_sun > 0.0 {
                sun_illuminance * t * cos_sun / cos_w
            } else {
                Vec3::ZERO
            },
            sky_irradiance: sky_irradiance * DIFFUSE_TRANSMITTANCE,
            floor_depth: 0.0,
            floor_albedo: 0.0,
        }
    }

    /// The same over a Lambertian floor `depth` m down of mean `albedo`.
    pub fn with_floor(self, depth: f32, albedo: f32) -> Self {
        UnderwaterLight { floor_depth: depth.max(0.0), floor_albedo: albedo.max(0.0), ..self }
    }

    /// Downwelling irradiance on a horizontal plane `depth` m down.
    pub fn downwelling(&self, medium: &Medium, depth: f32) -> Vec3 {
        let d = depth.max(0.0);
        let cos_w = (-self.sun_travel.y).max(1e-3);
        self.sun_irradiance * medium.transmittance(d / cos_w) * cos_w
            + self.sky_irradiance * medium.transmittance(d / DIFFUSE_MEAN_COSINE)
    }

    /// Upwelling irradiance on a downward-facing plane `depth` m down: the
    /// floor's diffuse reflection of the downwelling light that reaches it,
    /// dimmed on its way up as diffuse light is (path / mean cosine), or
    /// [`UPWELLING_FRACTION`] of the downwelling light here, whichever is
    /// more (per channel).
    pub fn upwelling(&self, medium: &Medium, depth: f32) -> Vec3 {
        let d = depth.max(0.0);
        let grey_world = UPWELLING_FRACTION * self.downwelling(medium, d);
        if self.floor_depth <= d {
            return grey_world;
        }
        let from_floor = self.floor_albedo
            * self.downwelling(medium, self.floor_depth)
            * medium.transmittance((self.floor_depth - d) / DIFFUSE_MEAN_COSINE);
        grey_world.max(from_floor)
    }

    /// Irradiance on a surface with unit normal `n` at `depth` metres below the
    /// mean surface (`sun_visibility` ∈ [0, 1] from the shadow map). The sky
    /// term is the cosine lobe (1 + n·y)/2 of a vertical diffuse field; the
    /// undersides get the upwelling light ([`UnderwaterLight::upwelling`]).
    pub fn irradiance(&self, medium: &Medium, depth: f32, n: Vec3, sun_visibility: f32) -> Vec3 {
        let d = depth.max(0.0);
        let cos_w = (-self.sun_travel.y).max(1e-3);
        let sun_down = self.sun_irradiance * medium.transmittance(d / cos_w);
        let sky_down = self.sky_irradiance * medium.transmittance(d / DIFFUSE_MEAN_COSINE);
        let sun = sun_down * n.dot(-self.sun_travel).max(0.0) * sun_visibility;
        let sky = sky_down * (0.5 + 0.5 * n.y);
        let up = self.upwelling(medium, d) * (0.5 - 0.5 * n.y);
        sun + sky + up
    }

    /// Light scattered once into a downward path of length `s` along unit
    /// direction `dir` (starting just under the surface), towards the viewer
    /// (who looks along `dir`): sun (phase `g`) and sky (isotropic) terms.
    pub fn path_in_scatter(&self, medium: &Medium, dir: Vec3, s: f32, g: f32) -> Vec3 {
        self.view_in_scatter(medium, 0.0, dir, s, g)
    }

    /// The sun's part of [`UnderwaterLight::view_in_scatter`], from distance
    /// `s0` to `s1` along the view ray only: the uniform (unfocused) beam that
    /// god rays replace near the eye (`crate::godrays`).
    pub fn sun_in_scatter(
        &self,
        medium: &Medium,
        depth: f32,
        dir: Vec3,
        s0: f32,
        s1: f32,
        g: f32,
    ) -> Vec3 {
        let cos_w = (-self.sun_travel.y).max(1e-3);
        let d0 = (depth - dir.y * s0).max(0.0);
        let phase = henyey_greenstein(self.sun_travel.dot(-dir), g);
        medium.transmittance(s0)
            * medium.in_scatter_from(
                self.sun_irradiance,
                d0 / cos_w,
                phase,
                -dir.y / cos_w,
                s1 - s0,
            )
    }

    /// Seed 000 eq. 3.7–3.8 with the viewer inside the water: light scattered
    /// once into the path of length `s` that starts `depth` metres under the
    /// mean surface and runs along unit `dir` (up or down). The light at the
    /// start has already lost e^(−σk·depth/cos θ); along the path the depth
    /// changes by −dir.y per metre, so c = −dir.y / cos θ may be negative.
    pub fn view_in_scatter(&self, medium: &Medium, depth: f32, dir: Vec3, s: f32, g: f32) -> Vec3 {
        let depth = depth.max(0.0);
        let down = -dir.y;
        let cos_w = (-self.sun_travel.y).max(1e-3);
        // Angle between the light's travel and the direction back to the eye.
        let phase = henyey_greenstein(self.sun_travel.dot(-dir), g);
        let sun =
            medium.in_scatter_from(self.sun_irradiance, depth / cos_w, phase, down / cos_w, s);
        // Diffuse skylight: scalar irradiance E/μ̄, isotropic phase.
        let (mu, sky_top) = (DIFFUSE_MEAN_COSINE, self.sky_irradiance / DIFFUSE_MEAN_COSINE);
        let sky = medium.in_scatter_from(sky_top, depth / mu, PHASE_ISOTROPIC, down / mu, s);
        sun + sky
    }
}

/// What the camera sees looking at flat water (mean level y = 0) over a
/// Lambertian floor at y = −`floor_depth` (`None`: bottomless), unshadowed:
/// L = F·L_reflected + (1 − F)/n² · (L_floor·e^(−σk·s) + L_in(s)), with the
/// view ray refracted at the surface and s its length to the floor. This is
/// the CPU reference of the water shader's "physical" mode.
pub struct FlatWaterView<'a> {
    pub medium: &'a Medium,
    pub light: &'a UnderwaterLight,
    pub ior: f32,
    pub phase_g: f32,
    pub floor_depth: Option<f32>,
    pub floor_albedo: Vec3,
}

impl FlatWaterView<'_> {
    /// Radiance towards the eye from the water along the unit view direction
    /// `view_dir` (camera → water, pointing down), given the radiance the
    /// mirror direction sees (`reflected`).
    pub fn radiance(&self, view_dir: Vec3, reflected: Vec3) -> Vec3 {
        let cos_v = (-view_dir.y).clamp(1e-4, 1.0);
        let f = fresnel_exact(cos_v, IOR_AIR, self.ior);
        let refracted =
            crate::optics::refract(view_dir, Vec3::Y, IOR_AIR, self.ior).unwrap_or(Vec3::NEG_Y);
        let (floor, s) = match self.floor_depth {
            Some(depth) => {
                let s = depth / (-refracted.y).max(1e-4);
                let e = self.light.irradiance(self.medium, depth, Vec3::Y, 1.0);
                (self.floor_albedo / PI * e * self.medium.transmittance(s), s)
            }
            None => (Vec3::ZERO, f32::INFINITY),
        };
        let inscatter =
            self.light.path_in_scatter(self.medium, refracted, s.min(1e6), self.phase_g);
        f * reflected + (1.0 - f) / (self.ior * self.ior) * (floor + inscatter)
    }
}

/// Seed 002 eq. 5–6, the `simple` water colour: what the refraction shows
/// (`seen`), blended towards the water's colour by a = e^(−d·k) over the
/// path length d. `water_colour` is the body colour's radiance (albedo ×
/// downwelling irradiance / π).
pub fn simple_water_colour(seen: Vec3, water_colour: Vec3, distance: f32, k: f32) -> Vec3 {
    let a = (-distance * k).exp();
    water_colour + a * (seen - water_colour)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Undersides over a floor: a Lambertian floor's exitance is its albedo
    /// times the irradiance on it, dimmed on the way up; without a floor,
    /// or over a deep one, the grey-world bounce.
    #[test]
    fn a_bright_shallow_floor_lights_undersides() {
        let m = MediumPreset::Pure.medium();
        let sun = Vec3::new(0.3, 0.85, 0.2).normalize();
        let open = UnderwaterLight::new(sun, Vec3::splat(1000.0), Vec3::splat(300.0), 1.333);
        let down = open.downwelling(&m, 0.2);
        assert!((open.upwelling(&m, 0.2) - UPWELLING_FRACTION * down).abs().max_element() < 1e-3);
        // Right above a white floor: all the light on the floor comes back up.
        let white = open.with_floor(1.6, 1.0);
        let at_floor = white.upwelling(&m, 1.6 - 1e-4);
        let on_floor = open.downwelling(&m, 1.6);
        assert!((at_floor - on_floor).abs().max_element() < 1e-2 * on_floor.max_element());
        let half = open.with_floor(1.6, 0.5).upwelling(&m, 1.6 - 1e-4);
        assert!((half - 0.5 * on_floor).abs().max_element() < 1e-2 * on_floor.max_element());
        // The pool: tiles (mean albedo about 0.7) 1.6 m down light a ball's
        // underside 0.2 m down several times more than the grey world does
        // in green and blue; red, absorbed on the way, less so.
        let pool = open.with_floor(1.6, 0.7).upwelling(&m, 0.2);
        let grey = UPWELLING_FRACTION * down;
        assert!(pool.y > 3.0 * grey.y && pool.z > 3.0 * grey.z, "{pool} vs {grey}");
        assert!(pool.x / grey.x < pool.z / grey.z);
        // A floor 200 m down sends nothing back: the grey world.
        let deep = open.with_floor(200.0, 1.0).upwelling(&m, 0.2);
        assert!((deep - grey).abs().max_element() < 1e-3);
        // The irradiance on a face looking straight down is the upwelling.
        let n = Vec3::NEG_Y;
        let e = open.with_floor(1.6, 0.7).irradiance(&m, 0.2, n, 1.0);
        assert!((e - pool).abs().max_element() < 1e-3 * pool.max_element());
    }

    #[test]
    fn a_materials_mean_albedo_counts_its_pattern() {
        use crate::scene::{MaterialDesc, Pattern};
        let mut tiles = MaterialDesc {
            albedo: [0.75, 0.85, 0.88],
            pattern: Pattern::Tiles,
            pattern_color: [0.12, 0.2, 0.24],
            ..Default::default()
        };
        let expected = 0.8836 * (0.75 + 0.85 + 0.88) / 3.0 + 0.1164 * (0.12 + 0.2 + 0.24) / 3.0;
        assert!((tiles.mean_albedo() - expected).abs() < 1e-6);
        tiles.pattern = Pattern::None;
        assert!((tiles.mean_albedo() - (0.75 + 0.85 + 0.88) / 3.0).abs() < 1e-6);
    }

    #[test]
    fn transmittance_is_beer_lambert() {
        let m = MediumPreset::Pure.medium();
        let t = m.transmittance(1.0);
        // Red dies within metres, blue travels tens of metres.
        assert!((t.x - (-1.169f32 - 0.0006).exp()).abs() < 1e-6);
        assert!(t.z > 0.98 && t.x < 0.32);
        let t10 = m.transmittance(10.0);
        assert!((t10.y - t.y.powi(10)).abs() < 1e-5);
    }

    #[test]
    fn in_scatter_stays_bounded_at_any_depth() {
        // A rising path's own gain e^(σk|1+c|s) overflows f32 a few hundred
        // metres down; the light reaching it from above must not.
        let m = MediumPreset::ClearOcean.medium();
        let sun = Vec3::new(0.3, 0.8, 0.2).normalize();
        let light = UnderwaterLight::new(sun, Vec3::splat(1000.0), Vec3::splat(300.0), 1.333);
        for dir in [Vec3::Y, Vec3::new(0.0, 0.5, -1.0).normalize(), Vec3::NEG_Z, Vec3::NEG_Y] {
            let mut last = Vec3::splat(f32::INFINITY);
            for depth in [0.0, 10.0, 100.0, 1000.0, 10_000.0, 100_000.0] {
                // Looking up, the path ends at the surface; else 1 km long.
                let s = if dir.y > 0.0 { depth / dir.y } else { 1000.0 };
                let l = light.view_in_scatter(&m, depth, dir, s, 0.9);
                assert!(l.is_finite() && l.min_element() >= 0.0, "{dir} at {depth} m: {l}");
                // Deep down, less and less light whichever way one looks.
                if depth >= 1000.0 {
                    assert!(l.cmple(last).all(), "{dir}: more light at {depth} m ({l}) than above");
                    last = l;
                }
            }
            assert!(last.max_element() < 1e-20, "{dir}: {last} at 100 km");
        }
        // The split form agrees with attenuating first where that is exact.
        let (e, t, c, s) = (Vec3::new(50.0, 60.0, 70.0), 7.0, -0.4, 5.0);
        let split = m.in_scatter_from(e, t, 0.1, c, s);
        let first = m.in_scatter(e * m.transmittance(t), 0.1, c, s);
        assert!(((split - first) / first).abs().max_element() < 1e-5, "{split} vs {first}");
    }

    #[test]
    fn in_scatter_matches_numerical_integral() {
        let m = MediumPreset::Coastal.medium();
        let (e0, phase, c, s) = (Vec3::new(50.0, 60.0, 70.0), 0.1, 0.7, 6.0);
        let closed = m.in_scatter(e0, phase, c, s);
        // ∫0^s σs·p·e0·e^(−σk·c·x)·e^(−σk·x) dx by the midpoint rule.
        let n = 20_000;
        let dx = s / n as f32;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let x = (i as f32 + 0.5) * dx;
            sum += m.scattering * phase * e0 * (-m.extinction() * (1.0 + c) * x).exp() * dx;
        }
        assert!(((closed - sum) / sum).abs().max_element() < 1e-3, "{closed} vs {sum}");
        // Infinitely deep water saturates at Λ·p·e0/(1+c) (seed 000 eq. 3.6).
        let deep = m.in_scatter(e0, phase, c, 1e6);
        let limit = m.albedo() * phase * e0 / (1.0 + c);
        assert!(((deep - limit) / limit).abs().max_element() < 1e-5);
        assert_eq!(m.in_scatter(e0, phase, c, 0.0), Vec3::ZERO);
    }

    #[test]
    fn in_scatter_seen_from_inside_the_water_matches_numerical_integral() {
        let m = MediumPreset::Coastal.medium();
        let light = UnderwaterLight::new(
            crate::sky::sun_direction(50.0, 30.0),
            Vec3::splat(80.0),
            Vec3::splat(15.0),
            1.333,
        );
        for dir in [
            Vec3::new(0.3, 0.9, 0.1).normalize(),
            Vec3::new(0.8, -0.2, 0.1).normalize(),
            Vec3::NEG_Y,
            Vec3::X,
        ] {
            // Paths that rise end before the surface.
            let (depth, g) = (4.0f32, 0.3f32);
            let s = if dir.y > 0.0 { (0.95 * depth / dir.y).min(9.0) } else { 9.0 };
            let closed = light.view_in_scatter(&m, depth, dir, s, g);
            // March the path: at each point, the sun and sky light arriving at
            // that depth, scattered towards the eye, attenuated back to it.
            let n = 20_000;
            let dx = s / n as f32;
            let cos_w = -light.sun_travel.y;
            let phase = henyey_greenstein(light.sun_travel.dot(-dir), g);
            let mut sum = Vec3::ZERO;
            for i in 0..n {
                let x = (i as f32 + 0.5) * dx;
                let z = depth - dir.y * x;
                let sun = light.sun_irradiance * m.transmittance(z / cos_w) * phase;
                let sky = light.sky_irradiance / DIFFUSE_MEAN_COSINE
                    * m.transmittance(z / DIFFUSE_MEAN_COSINE)
                    * PHASE_ISOTROPIC;
                sum += m.scattering * (sun + sky) * m.transmittance(x) * dx;
            }
            assert!(((closed - sum) / sum).abs().max_element() < 2e-3, "{dir}: {closed} vs {sum}");
        }
        // Deeper viewers see less light scattered towards them.
        let shallow = light.view_in_scatter(&m, 1.0, Vec3::X, 1e4, 0.0);
        let deep = light.view_in_scatter(&m, 10.0, Vec3::X, 1e4, 0.0);
        assert!(deep.max_element() < 0.5 * shallow.max_element());
    }

    #[test]
    fn henyey_greenstein_is_normalised() {
        for g in [0.0f32, 0.3, 0.8, -0.5] {
            let n = 4000;
            let integral: f32 = (0..n)
                .map(|i| {
                    let mu = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
                    henyey_greenstein(mu, g) * 2.0 * PI * 2.0 / n as f32
                })
                .sum();
            assert!((integral - 1.0).abs() < 2e-3, "g = {g}: {integral}");
        }
        assert!((henyey_greenstein(0.3, 0.0) - PHASE_ISOTROPIC).abs() < 1e-7);
    }

    #[test]
    fn diffuse_constants_follow_from_fresnel() {
        // Uniform sky radiance over the hemisphere, cosine weighted.
        let n = 20_000;
        let (mut transmitted, mut total, mut mean_cos_w) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            let theta = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
            let w = theta.cos() * theta.sin();
            let t = 1.0 - fresnel_exact(theta.cos() as f32, 1.0, 1.333) as f64;
            let sin_w = theta.sin() / 1.333;
            total += w;
            transmitted += w * t;
            mean_cos_w += w * t * (1.0 - sin_w * sin_w).sqrt();
        }
        let tr = transmitted / total;
        assert!((tr - DIFFUSE_TRANSMITTANCE as f64).abs() < 0.003, "{tr}");
        // Irradiance-weighted mean cosine of the refracted directions.
        let mu = mean_cos_w / transmitted;
        assert!((mu - DIFFUSE_MEAN_COSINE as f64).abs() < 0.01, "{mu}");
    }

    #[test]
    fn overhead_sun_under_flat_water() {
        let light = UnderwaterLight::new(Vec3::Y, Vec3::splat(100.0), Vec3::ZERO, 1.333);
        // T(0) = 1 − 0.0204, no narrowing at normal incidence.
        assert!((light.sun_irradiance.x - 97.96).abs() < 0.02);
        assert!((light.sun_travel - Vec3::NEG_Y).length() < 1e-6);
        let m = MediumPreset::Pure.medium();
        let e = light.irradiance(&m, 2.0, Vec3::Y, 1.0);
        assert!((e.x - 97.96 * (-(1.169f32 + 0.0006) * 2.0).exp()).abs() < 0.01);
        // A low sun bends towards the vertical (Snell) and its beam narrows.
        let low = crate::sky::sun_direction(10.0, 0.0);
        let l = UnderwaterLight::new(low, Vec3::splat(100.0), Vec3::ZERO, 1.333);
        let sin_w = (80f32.to_radians().sin()) / 1.333;
        assert!((l.sun_travel.x + sin_w).abs() < 1e-5);
        let t = 1.0 - fresnel_exact(10f32.to_radians().sin(), 1.0, 1.333);
        let want = 100.0 * t * 10f32.to_radians().sin() / (1.0 - sin_w * sin_w).sqrt();
        assert!((l.sun_irradiance.x - want).abs() < 1e-3);
    }

    #[test]
    fn presets_have_the_expected_colours() {
        // Deep-water colour seen from straight above with the sun overhead.
        let colour = |p: MediumPreset| {
            let m = p.medium();
            let light = UnderwaterLight::new(Vec3::Y, Vec3::splat(100.0), Vec3::splat(20.0), 1.333);
            let view = FlatWaterView {
                medium: &m,
                light: &light,
                ior: 1.333,
                phase_g: 0.0,
                floor_depth: None,
                floor_albedo: Vec3::ZERO,
            };
            view.radiance(Vec3::NEG_Y, Vec3::ZERO)
        };
        let clear = colour(MediumPreset::ClearOcean);
        assert!(clear.z > clear.y && clear.y > clear.x, "clear ocean is blue: {clear}");
        let harbor = colour(MediumPreset::TurbidHarbor);
        assert!(
            harbor.y > harbor.z && harbor.y > harbor.x,
            "turbid harbour is green-brown: {harbor}"
        );
        // Turbid water hides a white floor 3 m down; clear water shows it.
        let floor_share = |p: MediumPreset| {
            let m = p.medium();
            let light = UnderwaterLight::new(Vec3::Y, Vec3::splat(100.0), Vec3::splat(20.0), 1.333);
            let v = |d| FlatWaterView {
                medium: &m,
                light: &light,
                ior: 1.333,
                phase_g: 0.0,
                floor_depth: d,
                floor_albedo: Vec3::ONE,
            };
            (v(Some(3.0)).radiance(Vec3::NEG_Y, Vec3::ZERO)
                - v(None).radiance(Vec3::NEG_Y, Vec3::ZERO))
            .y
        };
        assert!(
            floor_share(MediumPreset::ClearOcean) > 20.0 * floor_share(MediumPreset::TurbidHarbor)
        );
        for p in MediumPreset::ALL {
            let m = p.medium();
            assert!(m.absorption.min_element() > 0.0 && m.scattering.min_element() > 0.0);
        }
    }

    #[test]
    fn shallow_white_floor_shows_through() {
        let m = MediumPreset::ClearOcean.medium();
        let light = UnderwaterLight::new(Vec3::Y, Vec3::splat(100.0), Vec3::splat(20.0), 1.333);
        let view = |d| FlatWaterView {
            medium: &m,
            light: &light,
            ior: 1.333,
            phase_g: 0.5,
            floor_depth: d,
            floor_albedo: Vec3::ONE,
        };
        let shallow = view(Some(0.5)).radiance(Vec3::NEG_Y, Vec3::ZERO);
        let deep = view(Some(30.0)).radiance(Vec3::NEG_Y, Vec3::ZERO);
        // Half a metre of water: white floor, red slightly reduced; direct
        // calculation of the floor term.
        let t = 1.0 - fresnel_exact(1.0, 1.0, 1.333);
        let e = light.irradiance(&m, 0.5, Vec3::Y, 1.0);
        let floor = Vec3::ONE / PI * e * m.transmittance(0.5) * t / (1.333 * 1.333);
        assert!(
            (shallow - floor).max_element() > 0.0
                && ((shallow - floor) / shallow).max_element() < 0.05
        );
        assert!(deep.x < 0.05 * shallow.x, "red is gone at 30 m");
    }
}
