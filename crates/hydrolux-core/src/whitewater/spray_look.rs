//! How a parcel of spray looks (seed 003 §4.5; the CPU twin of
//! `spray_opacity` in simulation/whitewater/light.wgsl, same f32
//! arithmetic and order).
//!
//! A parcel drawn `spray_size` wide is a cloud of drops holding
//! [`SPRAY_LIQUID_FRACTION`] of its volume as water, in drops of
//! [`SPRAY_DROP_RADIUS`]: N = φ(R/r)³ drops whose cross-sections cover
//! φ·R/r of the parcel's disc ([`parcel_cover`]: 0.2 for the default 6 cm
//! parcel). Close up it is drawn as [`DRAWN_DROPS`] drops with that same
//! cross-section between them, spread over [`SPREAD`] times its radius, each swept along its motion over the
//! shutter (a capsule, the motion blur of a drop) and at least
//! [`MIN_DROP_PIXELS`] wide, its opacity spread over what it is drawn on,
//! so the parcel sends the same light at every distance and speed. Where
//! its drops crowd to a pixel apart the parcel is the mist they make:
//! cover·3(1 − r²)² over the disc (the same mean), soft at a distance.

use super::{SPRAY_DROP_RADIUS, random};
use crate::coupling::SPRAY_LIQUID_FRACTION;

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
pub fn parcel_cover(spray_size: f32) -> f32 {
    (SPRAY_LIQUID_FRACTION as f32 * 0.5 * spray_size / SPRAY_DROP_RADIUS).min(MAX_COVER)
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

/// The mist the parcel's drops make where they are too small to draw:
/// 3(1 − r²)² over the (streaked) quad, with the parcel's light (cover
/// times its disc) spread over the quad's.
pub fn mist_opacity(quad: [f32; 2], s: &SprayShape) -> f32 {
    let r2 = quad[0] * quad[0] + quad[1] * quad[1];
    if r2 > 1.0 {
        return 0.0;
    }
    let density = (1.0 - r2) * (1.0 - r2);
    3.0 * s.cover * density * s.parcel * s.parcel / (1.0 + s.streak)
}

/// How much of the parcel's drops are drawn as drops (1) rather than mist
/// (0): by the drawn drops' mean spacing in pixels, √(area/N).
pub fn drops_resolved(s: &SprayShape) -> f32 {
    let spread = SPREAD * s.parcel;
    let spacing = spread * (std::f32::consts::PI / DRAWN_DROPS as f32).sqrt() / s.pixel;
    let t = ((spacing - MIST_BELOW_SPACING) / (DROPS_FROM_SPACING - MIST_BELOW_SPACING))
        .clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The parcel's opacity at `quad`: its drops, or their mist.
pub fn spray_opacity(quad: [f32; 2], s: &SprayShape, id: u32) -> f32 {
    let resolved = drops_resolved(s);
    let mut drops = 0.0;
    if resolved > 0.0 {
        drops = drops_opacity(quad, s, id);
    }
    mist_opacity(quad, s) * (1.0 - resolved) + drops * resolved
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
        assert!((parcel_cover(0.06) - 0.2).abs() < 1e-6);
        assert_eq!(parcel_cover(10.0), MAX_COVER);
        let unit = drawn_drop_radius(0.2);
        assert!((DRAWN_DROPS as f32 * unit * unit - 0.2).abs() < 1e-6);
    }

    /// The parcel sends the same light (cover × its disc) whether its
    /// drops are drawn sharp, motion-blurred, at a pixel or as mist.
    #[test]
    fn a_parcel_keeps_its_light_at_every_distance_and_speed() {
        let cover = parcel_cover(0.06);
        for (parcel, pixel, streak) in [
            (0.5, 0.0025, 0.0),
            (0.5, 0.0025, 1.5),
            (0.5, 0.02, 0.0),
            (0.5, 0.05, 0.6),
            (0.5, 0.12, 0.0),
            (0.35, 0.45, 0.0),
            (0.2, 1.33, 2.0),
        ] {
            let s = SprayShape { parcel, pixel, streak, cover };
            let expected = std::f32::consts::PI * cover * parcel * parcel;
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
        let cover = parcel_cover(0.06);
        let still = SprayShape { parcel: 1.0 / SPREAD, pixel: 0.0025, streak: 0.0, cover };
        assert_eq!(drops_resolved(&still), 1.0);
        let unit = drawn_drop_radius(cover);
        let c = drop_centre(9, 0, still.parcel, unit);
        assert!(spray_opacity(c, &still, 9) > 0.99);
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
        assert!(o > 0.02 && o < 0.2, "a blurred drop is faint: {o}");
        // Far off, a parcel of a pixel or two is mist, no drops.
        let far = SprayShape { parcel: 0.3, pixel: 1.0, streak: 0.0, cover };
        assert_eq!(drops_resolved(&far), 0.0);
    }
}
