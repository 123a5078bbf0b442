//! How a parcel of spray looks (seed 003 §4.5; the CPU twin of
//! `spray_opacity` in simulation/whitewater/light.wgsl, same f32
//! arithmetic and order).
//!
//! A parcel drawn `spray_size` wide is a cloud of drops holding
//! `spray_water` (φ, by default 1%) of its volume as water, in drops of
//! [`SPRAY_DROP_RADIUS`]: N = φ(R/r)³ drops whose cross-sections cover
//! φ·R/r of the parcel's disc ([`parcel_cover`]: 0.2 for the default 6 cm
//! parcel). Where its N real drops ([`parcel_drops`]) are pixels apart it
//! is drawn as [`DRAWN_DROPS`] drops with that same
//! cross-section between them, spread over [`SPREAD`] times its radius, each swept along its motion over the
//! shutter (a capsule, the motion blur of a drop) and at least
//! [`MIN_DROP_PIXELS`] wide, its opacity spread over what it is drawn on,
//! so the parcel sends the same light at every distance and speed. Where
//! its real drops crowd to a pixel apart the parcel is the mist they make:
//! an optical depth cover·3(1 − r²)² over the disc (the same mean), soft
//! at a distance. What the drops pass on straight ahead is not taken from
//! the background ([`FORWARD_SHARE`], the delta-Eddington split), and the
//! light they scatter forgets its direction as the parcel thickens
//! ([`spray_asymmetry`], [`spray_sky_share`]).

use super::{SPRAY_DROP_RADIUS, random};

/// Drops a parcel is drawn with (together they have its cross-section).
pub const DRAWN_DROPS: u32 = 24;
/// Least radius a drawn drop gets (pixels): thinner, it would alias.
pub const MIN_DROP_PIXELS: f32 = 0.6;
/// Most of a parcel's disc its drops hide (a dense parcel is not a wall).
pub const MAX_COVER: f32 = 0.8;
/// The drawn drops' mean spacing (pixels) below which the parcel is drawn
/// as mist (several drops to a pixel blend), and from which it is all drops
/// (each its own dot, however small: spray close by is separate drops).
pub const MIST_BELOW_SPACING: f32 = 0.75;
pub const DROPS_FROM_SPACING: f32 = 1.5;
/// Salts of a drop's position in its parcel.
pub const SALT_RADIUS: u32 = 0x5A1D;
pub const SALT_ANGLE: u32 = 0x7E11;

/// Fraction of a parcel's disc its drops cover: N·πr²/(πR²) = φ·R/r.
pub fn parcel_cover(spray_size: f32, water: f32) -> f32 {
    (water * 0.5 * spray_size / SPRAY_DROP_RADIUS).min(MAX_COVER)
}

/// How many real drops a parcel holds: N = φ(R/r)³ (80 in the default
/// 6 cm parcel of 1% water).
pub fn parcel_drops(spray_size: f32, water: f32) -> f32 {
    let ratio = 0.5 * spray_size / SPRAY_DROP_RADIUS;
    water * ratio * ratio * ratio
}

/// The radius of a drawn drop, in parcel radii: the [`DRAWN_DROPS`]
/// together cover `cover` of the disc.
pub fn drawn_drop_radius(cover: f32) -> f32 {
    (cover / DRAWN_DROPS as f32).sqrt()
}

/// A parcel as its quad is drawn, in the quad's units (half its width
/// across the motion is 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SprayShape {
    /// The parcel's radius (1/[`SPREAD`]: its quad covers its drops'
    /// spread; less where the quad is drawn wider, at a few pixels).
    pub parcel: f32,
    /// A pixel.
    pub pixel: f32,
    /// How far the parcel moves either way over the shutter (0: still).
    pub streak: f32,
    /// [`parcel_cover`].
    pub cover: f32,
    /// [`parcel_drops`]: the real drops, whose spacing decides whether the
    /// parcel is drawn as drops or as mist.
    pub drops: f32,
}

/// How far a parcel's drops spread, in parcel radii: a parcel is a cloud
/// whose drops thin out past its nominal size, and drawn over twice its
/// radius neighbouring parcels' drops mingle instead of showing clumps.
pub const SPREAD: f32 = 2.0;

/// Where drop `k` of parcel `id` sits, in quad units: uniform over the disc
/// of [`SPREAD`] parcel radii, inside its edge.
pub fn drop_centre(id: u32, k: u32, parcel: f32, drop_radius: f32) -> [f32; 2] {
    let r = random(id, k, SALT_RADIUS).sqrt() * (SPREAD - drop_radius) * parcel;
    let a = std::f32::consts::TAU * random(id, k, SALT_ANGLE);
    [r * a.cos(), r * a.sin()]
}

/// The parcel's drops at `quad` (x along the motion, both in [−1, 1]).
pub fn drops_opacity(quad: [f32; 2], s: &SprayShape, id: u32) -> f32 {
    let unit = drawn_drop_radius(s.cover);
    let a = unit * s.parcel;
    let drawn = a.max(MIN_DROP_PIXELS * s.pixel);
    // What a capsule with edges a pixel soft covers: π(A² + p²/12) + 4sA.
    let footprint = s.pixel * s.pixel / 12.0;
    let energy = std::f32::consts::PI * a * a
        / (std::f32::consts::PI * (drawn * drawn + footprint) + 4.0 * s.streak * drawn);
    let x = quad[0] * (1.0 + s.streak);
    let y = quad[1];
    let mut covered = 0.0;
    for k in 0..DRAWN_DROPS {
        let c = drop_centre(id, k, s.parcel, unit);
        let ex = ((x - c[0]).abs() - s.streak).max(0.0);
        let ey = y - c[1];
        let d = (ex * ex + ey * ey).sqrt();
        covered += ((drawn - d) / s.pixel + 0.5).clamp(0.0, 1.0);
    }
    (covered * energy).min(1.0)
}

/// The parcel's optical depth at `quad` with its drops spread evenly:
/// 3(1 − r²)² over the (streaked) quad, holding the parcel's
/// cross-section (cover times its disc).
pub fn mist_depth(quad: [f32; 2], s: &SprayShape) -> f32 {
    let r2 = quad[0] * quad[0] + quad[1] * quad[1];
    if r2 > 1.0 {
        return 0.0;
    }
    let density = (1.0 - r2) * (1.0 - r2);
    3.0 * s.cover * density * s.parcel * s.parcel / (1.0 + s.streak)
}

/// The mist the parcel's drops make where they are too small to draw,
/// seen through by Beer–Lambert (drops behind drops are hidden: a thick
/// parcel is not whiter than white).
pub fn mist_opacity(quad: [f32; 2], s: &SprayShape) -> f32 {
    1.0 - (-mist_depth(quad, s)).exp()
}

/// How much of the parcel's drops are drawn as drops (1) rather than mist
/// (0): by the mean spacing in pixels, √(area/N), of its real drops or of
/// the drawn ones where it has fewer. Drops a pixel apart blend into mist
/// however few are drawn: a storm's spume, thousands of millimetre drops
/// a parcel, is a veil at any distance a pixel is centimetres.
pub fn drops_resolved(s: &SprayShape) -> f32 {
    let spread = SPREAD * s.parcel;
    let drops = s.drops.max(DRAWN_DROPS as f32);
    let spacing = spread * (std::f32::consts::PI / drops).sqrt() / s.pixel;
    let t = ((spacing - MIST_BELOW_SPACING) / (DROPS_FROM_SPACING - MIST_BELOW_SPACING))
        .clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// How much of what is behind the parcel it hides at `quad`: its drops,
/// or their mist, less the light they pass on straight ahead
/// ([`FORWARD_SHARE`]: through a drop the background still shows).
pub fn spray_opacity(quad: [f32; 2], s: &SprayShape, id: u32) -> f32 {
    let resolved = drops_resolved(s);
    if resolved == 0.0 {
        return 1.0 - (-(1.0 - FORWARD_SHARE) * mist_depth(quad, s)).exp();
    }
    let drops = drops_opacity(quad, s, id);
    (mist_opacity(quad, s) * (1.0 - resolved) + drops * resolved) * (1.0 - FORWARD_SHARE)
}

/// Millimetre drops' asymmetry: most of what they scatter goes within a
/// few degrees of forward (diffraction and refraction; g ≈ 0.8 for water
/// drops many wavelengths wide, as in clouds' larger droplets).
pub const DROP_ASYMMETRY: f32 = 0.8;

/// The delta-Eddington split (Joseph, Wiscombe & Weinman 1976): g² of
/// what a drop scatters is taken as going straight on, so it is the
/// background seen through the spray rather than light taken from it;
/// the rest scatters with asymmetry g/(1 + g).
pub const FORWARD_SHARE: f32 = DROP_ASYMMETRY * DROP_ASYMMETRY;

/// The asymmetry of light leaving a parcel where its optical depth is
/// `tau` ([`mist_depth`], however its drops are drawn): single
/// scattering's, the delta-Eddington g/(1 + g), where it is thin; where
/// it is thick, light has scattered about τ' = (1 − g²)τ times on the way
/// and forgets its direction (g'/(1 + τ')): a dense cloud of spray is
/// white from every side, as clouds are, not only against the sun.
pub fn spray_asymmetry(tau: f32) -> f32 {
    let scattered = (1.0 - FORWARD_SHARE) * tau.max(0.0);
    DROP_ASYMMETRY / (1.0 + DROP_ASYMMETRY) / (1.0 + scattered)
}

/// Henyey–Greenstein's phase function (per steradian).
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let d = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * std::f32::consts::PI * d * d.sqrt())
}

/// What a parcel scatters towards the eye looking along `view_y` (the
/// view's vertical component) out of a uniform sky above, per unit sky
/// radiance: the share of its phase function over the upper hemisphere.
/// Exact looking straight up, F = (1 + g)/2g − (1 − g²)/(2g√(1 + g²)),
/// and ½ looking level; between them a fit, within 0.03 of the integral
/// for g up to 0.8: spray seen against the sky glows with it, spray seen
/// against the sea does not, thick spray takes half the sky from any side.
pub fn spray_sky_share(view_y: f32, g: f32) -> f32 {
    let g = g.clamp(0.01, 0.95);
    let up = (1.0 + g) / (2.0 * g) - (1.0 - g * g) / (2.0 * g * (1.0 + g * g).sqrt());
    let b = 1.5 * ((1.0 - g) / g).powf(1.12);
    0.5 + (up - 0.5) * (1.0 + b) * view_y / (view_y.abs() + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ opacity over the quad, in parcel-radius units² (x stretched).
    fn light(s: &SprayShape, id: u32) -> f32 {
        let n = 600;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let q = [
                    -1.0 + (i as f32 + 0.5) * 2.0 / n as f32,
                    -1.0 + (j as f32 + 0.5) * 2.0 / n as f32,
                ];
                sum += spray_opacity(q, s, id) as f64;
            }
        }
        (sum * 4.0 / (n * n) as f64) as f32 * (1.0 + s.streak)
    }

    #[test]
    fn the_default_parcel_covers_a_fifth_of_its_disc() {
        // 6 cm parcel, 1 % water, 1.5 mm drops: φR/r = 0.01 · 30 / 1.5.
        assert!((parcel_cover(0.06, 0.01) - 0.2).abs() < 1e-6);
        assert_eq!(parcel_cover(10.0, 0.01), MAX_COVER);
        let unit = drawn_drop_radius(0.2);
        assert!((DRAWN_DROPS as f32 * unit * unit - 0.2).abs() < 1e-6);
    }

    /// The parcel sends the same light (cover × its disc, less what passes
    /// straight on) whether its drops are drawn sharp, motion-blurred, at a
    /// pixel or as mist.
    #[test]
    fn a_parcel_keeps_its_light_at_every_distance_and_speed() {
        let cover = parcel_cover(0.06, 0.01);
        for (parcel, pixel, streak) in [
            (0.5, 0.0025, 0.0),
            (0.5, 0.0025, 1.5),
            (0.5, 0.02, 0.0),
            (0.5, 0.05, 0.6),
            (0.5, 0.12, 0.0),
            (0.35, 0.45, 0.0),
            (0.2, 1.33, 2.0),
        ] {
            let s = SprayShape { parcel, pixel, streak, cover, drops: parcel_drops(0.06, 0.01) };
            let hidden = 1.0 - FORWARD_SHARE;
            let expected = std::f32::consts::PI * cover * parcel * parcel * hidden;
            for id in [3, 77, 1024] {
                let got = light(&s, id);
                assert!(
                    (got / expected - 1.0).abs() < 0.1,
                    "parcel {parcel} pixel {pixel} streak {streak} id {id}: {got} vs {expected}"
                );
            }
        }
    }

    /// Close up a still parcel is separate, opaque drops with clear water
    /// between; moving, each drop is a faint streak along its motion.
    #[test]
    fn close_up_drops_are_sharp_and_motion_blurs_them() {
        let cover = parcel_cover(0.06, 0.01);
        let drops = parcel_drops(0.06, 0.01);
        let still = SprayShape { parcel: 1.0 / SPREAD, pixel: 0.0025, streak: 0.0, cover, drops };
        assert_eq!(drops_resolved(&still), 1.0);
        let unit = drawn_drop_radius(cover);
        let c = drop_centre(9, 0, still.parcel, unit);
        assert!(spray_opacity(c, &still, 9) > 0.99 * (1.0 - FORWARD_SHARE));
        let (mut clear, n) = (0, 200);
        for j in 0..n {
            for i in 0..n {
                let q = [-1.0 + 2.0 * i as f32 / n as f32, -1.0 + 2.0 * j as f32 / n as f32];
                if spray_opacity(q, &still, 9) == 0.0 {
                    clear += 1;
                }
            }
        }
        assert!(clear as f32 / (n * n) as f32 > 0.9, "most of the quad is clear: {clear}");
        let moving = SprayShape { streak: 0.5, ..still };
        let at = [c[0] / 1.5, c[1]];
        let o = spray_opacity(at, &moving, 9);
        assert!(o > 0.01 && o < 0.1, "a blurred drop is faint: {o}");
        // Far off, a parcel of a pixel or two is mist, no drops.
        let far = SprayShape { parcel: 0.3, pixel: 1.0, streak: 0.0, cover, drops };
        assert_eq!(drops_resolved(&far), 0.0);
    }

    /// A pixel (m) at `distance` m in a 960×540 view with a 60° field.
    fn pixel_at(distance: f32) -> f32 {
        2.0 * distance * (30.0f32).to_radians().tan() / 540.0
    }

    /// The shape of a still parcel `size` m wide `distance` m away, drawn
    /// at its own size (quad half-width SPREAD parcel radii).
    fn parcel_at(size: f32, distance: f32) -> SprayShape {
        let half_quad = SPREAD * 0.5 * size;
        SprayShape {
            parcel: 1.0 / SPREAD,
            pixel: pixel_at(distance) / half_quad,
            streak: 0.0,
            cover: parcel_cover(size, 0.01),
            drops: parcel_drops(size, 0.01),
        }
    }

    /// The pool's 6 cm parcel a metre away is separate drops (80 of them,
    /// 1.2 cm apart, 6 pixels); the storm's 25 cm spume parcel holds 5800
    /// drops 6 mm apart, a fifth of a pixel at 15 m: a veil of mist, not
    /// two dozen drawn drops (which would be 3 pixels apart, confetti).
    #[test]
    fn spume_is_mist_where_its_drops_are_closer_than_a_pixel() {
        assert!((parcel_drops(0.06, 0.01) - 80.0).abs() < 0.01);
        assert!((parcel_drops(0.25, 0.01) - 5787.0).abs() < 1.0);
        assert_eq!(drops_resolved(&parcel_at(0.06, 1.0)), 1.0);
        let spume = parcel_at(0.25, 15.0);
        assert_eq!(drops_resolved(&spume), 0.0);
        let as_drawn = SprayShape { drops: 0.0, ..spume };
        assert_eq!(drops_resolved(&as_drawn), 1.0, "24 drawn drops alone would be resolved");
        // Resolved again where its real drops are pixels apart.
        assert_eq!(drops_resolved(&parcel_at(0.25, 0.5)), 1.0);
    }

    /// The phase integrates to 1 for every asymmetry; thin spray throws
    /// light forward, thick spray evenly; the sky share is the phase's
    /// upper half (integrated numerically).
    #[test]
    fn spray_light_forgets_its_direction_as_the_parcel_thickens() {
        let n = 4000;
        for g in [0.0, 0.3, DROP_ASYMMETRY] {
            let integral: f32 = (0..n)
                .map(|i| {
                    let mu = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
                    henyey_greenstein(mu, g) * 2.0 * std::f32::consts::PI * 2.0 / n as f32
                })
                .sum();
            assert!((integral - 1.0).abs() < 2e-3, "g {g}: {integral}");
        }
        // Thin: g' = 0.8/1.8; τ = 5 scatters τ' = 1.8 times.
        assert!((spray_asymmetry(0.0) - 0.8 / 1.8).abs() < 1e-6);
        assert!((spray_asymmetry(5.0) - 0.8 / 1.8 / 2.8).abs() < 1e-6);
        let ratio = |tau: f32| {
            let g = spray_asymmetry(tau);
            henyey_greenstein(1.0, g) / henyey_greenstein(-1.0, g)
        };
        assert!(ratio(0.01) > 10.0 && ratio(5.0) < 3.0, "{} {}", ratio(0.01), ratio(5.0));
        // The sky share against a numerical integral over the upper half
        // of the incoming directions, for a parcel seen level, from above
        // and from below (azimuth-averaged: HG depends on the angle only).
        for (view_y, g) in [
            (0.0, 0.8),
            (-0.6, 0.8),
            (-0.2, 0.8),
            (0.3, 0.8),
            (0.99, 0.8),
            (0.8, 0.3),
            (-0.9, 0.5),
            (0.5, 0.0),
            (-0.4, 0.1),
        ] {
            let view = [(1.0f32 - view_y * view_y).sqrt(), view_y, 0.0];
            let (m, mut share) = (400, 0.0f32);
            for i in 0..m {
                for j in 0..m {
                    // Light arriving from direction `from` (upper
                    // hemisphere) travels along −from; scattering it
                    // towards the eye turns it by the angle between its
                    // travel and the view's reverse, cos = dot(from, view).
                    let mu = (i as f32 + 0.5) / m as f32;
                    let phi = std::f32::consts::TAU * (j as f32 + 0.5) / m as f32;
                    let s = (1.0 - mu * mu).sqrt();
                    let from = [s * phi.cos(), mu, s * phi.sin()];
                    let c = from[0] * view[0] + from[1] * view[1];
                    share += henyey_greenstein(c, g) * std::f32::consts::TAU / (m * m) as f32;
                }
            }
            let approx = spray_sky_share(view_y, g);
            assert!((share - approx).abs() < 0.035, "view_y {view_y} g {g}: {share} vs {approx}");
        }
    }
}
