//! God rays: the volume caustics under the water surface (seed 000 §3.5 and
//! §4.6, after Papadopoulos & Papaioannou 2009). CPU reference of
//! `passes/godrays`.
//!
//! The photons of the surface caustics, refracted at the moving surface,
//! each become a *beam tube*: a line from where the photon enters the water
//! to where it meets the floor, carrying the flux the photon's surface cell
//! lets through. Light scattered out of the tubes towards the eye is what
//! makes the shafts: where the surface focuses, tubes crowd together.
//!
//! Seed 000 eq. 4.2 shades a line fragment with L0·e^(−σk·d)·e^(−σk·s)·p(θ).
//! Here that is made exact in energy. A tube of flux Φ scatters σs·p(θ)·Φ·
//! e^(−σk·d) W/sr per metre of its length towards a viewer along θ. It is drawn
//! as a screen-facing ribbon of half-width `a` with a tent profile across
//! (1 − |u|, u the distance between the view ray and the tube's axis in
//! units of a), whose radiance is
//!
//! `L = σs · p(θ) · Φ · (1 − |u|) / (a · sin α) · e^(−σk·(d + s))`
//!
//! with α the angle between the view ray and the tube, d the distance along
//! the tube from the surface and s the distance to the eye. Over a field of
//! parallel tubes that fill space with irradiance E⊥ this sums, along any
//! view ray, to the single-scattering integral ∫σs·p·E⊥·e^(−σk(d+s))ds of a
//! uniform beam — [`crate::medium::UnderwaterLight::sun_in_scatter`] — and
//! one ribbon seen from afar carries exactly the tube's scattered intensity
//! (both are tested below).
//!
//! Unit: flux relative to the sun's irradiance on a plane facing it (m²);
//! radiance relative to that irradiance (sr⁻¹).

use crate::caustics::refracted_photon;
use crate::medium::{Medium, henyey_greenstein};
use crate::waves::SurfaceSample;
use glam::{Vec2, Vec3};

/// Smallest sin α a ribbon is shaded with: looking straight along a beam,
/// the tube's whole length lies behind one pixel and the ribbon model breaks
/// down; within ~6° of the beam the radiance is capped instead.
pub const MIN_SIN_ALPHA: f32 = 0.1;

/// One photon's path in the water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamTube {
    /// Where it enters the water (on the displaced surface).
    pub start: Vec3,
    /// Unit direction of travel.
    pub dir: Vec3,
    /// Length (m) to where it ends (the floor, or the deepest point drawn).
    pub length: f32,
    /// Flux, relative to the sun's irradiance on a plane facing it (m²).
    pub flux: f32,
}

/// The square of surface, around the viewer, whose photons are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeRegion {
    pub centre: Vec2,
    pub half: f32,
}

impl TubeRegion {
    /// Every tube that passes within `distance` of `eye` starts in this square:
    /// a point at depth D traces back up its beam to the surface D·tan θw
    /// towards the sun (θw the refracted sun's angle to the vertical).
    pub fn around(eye: Vec3, travel: Vec3, distance: f32) -> Self {
        let cos_w = (-travel.y).max(1e-3);
        let tan_w = (1.0 - cos_w * cos_w).max(0.0).sqrt() / cos_w;
        let towards_sun = -Vec2::new(travel.x, travel.z).normalize_or_zero();
        let depth = (-eye.y).max(0.0);
        TubeRegion {
            centre: Vec2::new(eye.x, eye.z) + towards_sun * depth * tan_w,
            half: distance * (1.0 + tan_w) + 1.0,
        }
    }

    /// Distance between neighbouring photons (m) with `per_side` photons per side.
    pub fn spacing(&self, per_side: u32) -> f32 {
        2.0 * self.half / per_side.max(1) as f32
    }

    /// Undisplaced surface point of photon (i, j): the cell centre.
    pub fn photon_origin(&self, per_side: u32, i: u32, j: u32) -> Vec2 {
        let n = per_side.max(1) as f32;
        self.centre
            + Vec2::new((i as f32 + 0.5) / n - 0.5, (j as f32 + 0.5) / n - 0.5) * 2.0 * self.half
    }
}

/// Deepest point a tube needs to reach to pass within `distance` of `eye`.
pub fn deepest_needed(eye: Vec3, distance: f32) -> f32 {
    (-eye.y).max(0.0) + distance
}

/// The tubes of a `per_side`² photon grid over `region`, against the surface
/// `sample(x, z)`, ending at the floor (`floor_depth` m down, if any) or at
/// depth `max_depth`.
pub fn beam_tubes(
    sample: impl Fn(f32, f32) -> SurfaceSample,
    region: &TubeRegion,
    per_side: u32,
    sun_dir: Vec3,
    ior: f32,
    floor_depth: Option<f32>,
    max_depth: f32,
) -> Vec<BeamTube> {
    let cell_area = region.spacing(per_side).powi(2);
    let end_depth = floor_depth.map_or(max_depth, |f| f.min(max_depth));
    let mut tubes = Vec::new();
    for j in 0..per_side {
        for i in 0..per_side {
            let o = region.photon_origin(per_side, i, j);
            if let Some((start, dir, weight)) =
                refracted_photon(&sample(o.x, o.y), o.x, o.y, sun_dir, ior)
            {
                let length = ((start.y + end_depth) / -dir.y).max(0.0);
                tubes.push(BeamTube { start, dir, length, flux: weight * cell_area });
            }
        }
    }
    tubes
}

/// Where a view ray passes a tube: the closest approach of the two lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RibbonHit {
    /// Distance from the eye along the view ray (m).
    pub s: f32,
    /// Distance along the tube from its start (m).
    pub d: f32,
    /// Distance between the two lines, in ribbon half-widths.
    pub u: f32,
    /// Sine of the angle between them.
    pub sin_alpha: f32,
}

/// The closest approach of the view ray `eye + s·view` (unit `view`) to the
/// tube's axis, if it falls on the ribbon: within the tube's length, within
/// a half-width of the axis, in front of the eye and not parallel to it.
pub fn ribbon_hit(tube: &BeamTube, half_width: f32, eye: Vec3, view: Vec3) -> Option<RibbonHit> {
    let w0 = eye - tube.start;
    let b = view.dot(tube.dir);
    let denom = 1.0 - b * b;
    if denom < 1e-6 {
        return None;
    }
    let (dv, dt) = (view.dot(w0), tube.dir.dot(w0));
    let s = (b * dt - dv) / denom;
    let d = (dt - b * dv) / denom;
    let gap = (w0 + view * s - tube.dir * d).length();
    let u = gap / half_width;
    (s > 0.0 && (0.0..=tube.length).contains(&d) && u <= 1.0).then_some(RibbonHit {
        s,
        d,
        u,
        sin_alpha: denom.sqrt(),
    })
}

/// Radiance (relative to the sun's irradiance) a ribbon sends along `view`
/// at `hit` (see the module documentation).
pub fn ribbon_radiance(
    medium: &Medium,
    g: f32,
    tube: &BeamTube,
    half_width: f32,
    view: Vec3,
    hit: &RibbonHit,
) -> Vec3 {
    let phase = henyey_greenstein(tube.dir.dot(-view), g);
    let profile = (1.0 - hit.u).max(0.0) / (half_width * hit.sin_alpha.max(MIN_SIN_ALPHA));
    medium.scattering * phase * tube.flux * profile * medium.transmittance(hit.d + hit.s)
}

/// What a view ray from `eye` along unit `view` collects from every ribbon
/// it crosses closer than `max_distance` — one pixel of the GPU's buffer.
pub fn ribbons_along_ray(
    medium: &Medium,
    g: f32,
    tubes: &[BeamTube],
    half_width: f32,
    eye: Vec3,
    view: Vec3,
    max_distance: f32,
) -> Vec3 {
    tubes
        .iter()
        .filter_map(|t| {
            ribbon_hit(t, half_width, eye, view)
                .filter(|h| h.s < max_distance)
                .map(|h| ribbon_radiance(medium, g, t, half_width, view, &h))
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::{MediumPreset, UnderwaterLight};
    use crate::sky::sun_direction;

    fn flat_tubes(sun: Vec3, eye: Vec3, distance: f32, per_side: u32) -> (Vec<BeamTube>, f32) {
        let light = UnderwaterLight::new(sun, Vec3::ONE, Vec3::ZERO, 1.333);
        let region = TubeRegion::around(eye, light.sun_travel, distance);
        let tubes = beam_tubes(
            |_, _| SurfaceSample::default(),
            &region,
            per_side,
            sun,
            1.333,
            Some(30.0),
            deepest_needed(eye, distance),
        );
        (tubes, region.spacing(per_side))
    }

    #[test]
    fn one_ribbon_carries_the_tubes_scattered_intensity() {
        // A tube seen side-on from far away: the ribbon's radiance integrated
        // over its solid angle must be the closed form of the intensity
        // scattered out of the line, σs·p·Φ·e^(−σk·S)·(1 − e^(−σk·L))/σk / S².
        let medium = MediumPreset::ClearOcean.medium();
        let tube =
            BeamTube { start: Vec3::new(0.0, 0.0, 0.0), dir: Vec3::NEG_Y, length: 4.0, flux: 0.3 };
        let (a, big_s, g) = (0.25, 30.0, 0.0);
        let eye = Vec3::new(0.0, -2.0, big_s);
        // Integrate over a fine grid of view directions (a pinhole image).
        let (nx, ny) = (400, 1600);
        let (half_x, half_y) = (0.3 / big_s, 2.2 / big_s);
        let mut sum = Vec3::ZERO;
        for j in 0..ny {
            for i in 0..nx {
                let x = ((i as f32 + 0.5) / nx as f32 * 2.0 - 1.0) * half_x;
                let y = ((j as f32 + 0.5) / ny as f32 * 2.0 - 1.0) * half_y;
                let view = Vec3::new(x, y, -1.0).normalize();
                if let Some(h) = ribbon_hit(&tube, a, eye, view) {
                    let solid_angle = (2.0 * half_x / nx as f32) * (2.0 * half_y / ny as f32);
                    sum += ribbon_radiance(&medium, g, &tube, a, view, &h) * solid_angle;
                }
            }
        }
        let k = medium.extinction();
        let phase = henyey_greenstein(0.0, g);
        // The line's intensity with its true distances to the eye (quadrature
        // along the line) ...
        let mut along = Vec3::ZERO;
        let steps = 4000;
        for i in 0..steps {
            let d = (i as f32 + 0.5) / steps as f32 * tube.length;
            let p = tube.start + tube.dir * d;
            let s = (p - eye).length();
            along += medium.scattering * phase * tube.flux * medium.transmittance(d + s) / (s * s)
                * (tube.length / steps as f32);
        }
        for c in 0..3 {
            assert!(
                (sum[c] / along[c] - 1.0).abs() < 0.01,
                "channel {c}: {} vs {}",
                sum[c],
                along[c]
            );
        }
        // ... and, in the clearest channel where the ends' distances hardly
        // matter, the closed form at the mean distance S.
        let closed = medium.scattering.z * phase * tube.flux * (1.0 - (-k.z * tube.length).exp())
            / k.z
            * (-k.z * big_s).exp()
            / (big_s * big_s);
        assert!((sum.z / closed - 1.0).abs() < 0.01, "{} vs {closed}", sum.z);
    }

    #[test]
    fn flat_water_makes_parallel_tubes_of_equal_flux_that_fill_space_evenly() {
        let sun = sun_direction(55.0, 20.0);
        let eye = Vec3::new(0.0, -3.0, 0.0);
        let (tubes, spacing) = flat_tubes(sun, eye, 12.0, 128);
        let light = UnderwaterLight::new(sun, Vec3::ONE, Vec3::ZERO, 1.333);
        assert_eq!(tubes.len(), 128 * 128);
        for t in &tubes {
            assert!(
                (t.dir - light.sun_travel).length() < 1e-5,
                "{} vs {}",
                t.dir,
                light.sun_travel
            );
            assert!((t.flux - tubes[0].flux).abs() < 1e-6);
        }
        // Flux per unit area across the beam is the refracted sun's irradiance.
        let across = spacing * spacing * -light.sun_travel.y;
        assert!((tubes[0].flux / across - light.sun_irradiance.x).abs() < 1e-4);
    }

    #[test]
    fn ribbons_of_a_flat_slab_sum_to_the_uniform_beams_in_scattering() {
        // Any view ray through parallel tubes must collect what the uniform
        // sunlight under flat water scatters into it (up to the sampling of
        // the tube lattice by one ray: a few % per ray, less on average).
        let sun = sun_direction(60.0, 30.0);
        let eye = Vec3::new(0.3, -4.0, 0.2);
        let distance = 10.0;
        let (tubes, spacing) = flat_tubes(sun, eye, distance, 160);
        let medium = MediumPreset::ClearOcean.medium();
        let light = UnderwaterLight::new(sun, Vec3::ONE, Vec3::ZERO, 1.333);
        let g = 0.0;
        let mut ratios = Vec::new();
        for k in 0..40 {
            let a = k as f32 * 2.4;
            let view = Vec3::new(a.cos(), -0.6 + 0.03 * k as f32, a.sin()).normalize();
            if view.dot(light.sun_travel).abs() > 0.9 {
                continue;
            }
            // Stay under the surface and above the floor.
            let s_max = if view.y > 0.0 {
                (-eye.y / view.y).min(distance)
            } else {
                ((30.0 + eye.y) / -view.y).min(distance)
            };
            let lines = ribbons_along_ray(&medium, g, &tubes, spacing, eye, view, s_max);
            let uniform = light.sun_in_scatter(&medium, -eye.y, view, 0.0, s_max, g);
            ratios.push(lines.z / uniform.z);
        }
        let mean = ratios.iter().sum::<f32>() / ratios.len() as f32;
        assert!((mean - 1.0).abs() < 0.02, "mean ratio {mean}");
        for r in &ratios {
            assert!((r - 1.0).abs() < 0.08, "ratio {r} in {ratios:?}");
        }
    }

    #[test]
    fn waves_focus_the_tubes() {
        // A single sine wave: tubes bunch under its crests (converging
        // directions) instead of staying parallel.
        let sun = sun_direction(90.0, 0.0);
        let eye = Vec3::new(0.0, -2.0, 0.0);
        let region = TubeRegion::around(eye, Vec3::NEG_Y, 6.0);
        let wave = |x: f32, _z: f32| {
            let k = std::f32::consts::TAU / 4.0;
            SurfaceSample {
                displacement: [0.0, 0.1 * (k * x).cos(), 0.0],
                slope: [-0.1 * k * (k * x).sin(), 0.0],
                ..Default::default()
            }
        };
        let tubes = beam_tubes(wave, &region, 64, sun, 1.333, None, 8.0);
        let spread = tubes.iter().map(|t| t.dir.x.abs()).fold(0.0f32, f32::max);
        assert!(spread > 0.02, "directions should differ, max |dir.x| = {spread}");
        // Energy is conserved: total flux equals the flat value (T·A), up to
        // the Fresnel factor varying with the slope.
        let total: f32 = tubes.iter().map(|t| t.flux).sum();
        let flat = crate::caustics::flat_floor_irradiance(sun, 1.333) * (2.0 * region.half).powi(2);
        assert!((total / flat - 1.0).abs() < 0.01, "{total} vs {flat}");
    }
}
