//! How foam looks where the field says there is foam (seed 003 §4.4; the
//! CPU twin of `passes/water/foam.wgsl`, same f32 arithmetic and order).
//!
//! Sea foam is a raft of bubbles: a dense sheet is bright and lumpy with a
//! few holes, and as it thins it tears into a lace of filaments (the walls
//! between the bubble cells that burst first) before it goes. The simulated
//! field gives a cell's cover c (0–1, the fraction that is foam); the look
//! is a structure s(q) over the surface (0–1): the distance to the nearest
//! wall of a jittered cell network (Worley's F2 − F1, cells
//! [`LACE_CELL`] m across) mixed with a breakup noise [`BREAKUP`] m across,
//! in a frame stretched downwind by the streak length. Foam covers the
//! points where s lies below the threshold t(c) that makes the covered
//! fraction c itself ([`FOAM_THRESHOLDS`], the measured quantiles of s):
//! a sparse cover is lace, a dense one a sheet with holes, and a pixel too
//! coarse to resolve the cells shows c, the pattern's own mean, so the
//! near and far foam meet without a band. How far a point lies inside the
//! foam (t − s) is its thickness: the lumps on a thick sheet catch the sun
//! and thin lace lets the water show through.

use glam::Vec2;

/// The foam field's cell (m) that the sizes here are for (the storm's, 800 m
/// over 512 cells): the renderer scales them with the field's own cell, so
/// a pool's splash foam (1.6 cm cells) is a hundred times finer than a
/// whitecap's, as the structure below a cell should be.
pub const FOAM_REFERENCE_CELL: f32 = 1.5625;
/// Side of the lace's bubble cells (m, across the wind).
pub const LACE_CELL: f32 = 0.5;
/// The finest lace drawn (m): a splash's raft of millimetre bubbles still
/// gathers into clusters and filaments centimetres across, so a fine field
/// (the pool's 1.6 cm cells would give 5 mm lace, too fine to show from
/// the deck: the splash's foam was a smooth white blob) draws its lace no
/// finer than this.
pub const FINEST_LACE: f32 = 0.02;

/// The scale of the look's sizes over a foam field of `cell` (m): they are
/// for [`FOAM_REFERENCE_CELL`] and scale with the field's cell, down to
/// lace [`FINEST_LACE`] across. As `foam_units` in WGSL.
pub fn look_units(cell: f32) -> f32 {
    (cell / FOAM_REFERENCE_CELL).max(FINEST_LACE / LACE_CELL)
}
/// Size of the noise that breaks the foam into patches (m, across the wind).
pub const BREAKUP: f32 = 3.0;
/// How far the lace's walls wander (cells) and the size of their wander (cells).
pub const LACE_WARP: f32 = 0.35;
pub const WARP_SCALE: f32 = 2.3;
/// F2 − F1 (in cells) beyond which a point counts as a cell's middle.
pub const EDGE_SPAN: f32 = 0.6;
/// Weight of the cell network in the structure (the breakup noise has the rest).
pub const LACE_WEIGHT: f32 = 0.5;
/// t − s over which foam goes from a film to its full thickness.
pub const THICK_SPAN: f32 = 0.1;
/// A dense sheet is marbled: where the structure lies between
/// `MARBLE_FROM` and `MARBLE_TO` (the bubble cells' middles, the first to
/// burst), the sheet is a film at most `MARBLE` thinner, so a whitecap
/// shows its network of thick walls over thinner cells, as photographs of
/// breaking seas do, instead of one flat sheet. Only covers over about
/// 0.65 reach these s, so lace and sparse foam are untouched.
pub const MARBLE: f32 = 0.6;
pub const MARBLE_FROM: f32 = 0.45;
pub const MARBLE_TO: f32 = 0.7;

/// The structure's quantiles at cover c = 0, 1/16, …, 1: foam shows where
/// s < t(c), so that a fraction c of the surface is foam (measured over a
/// large area by `thresholds_are_the_structures_quantiles`).
pub const FOAM_THRESHOLDS: [f32; 17] = [
    0.15, 0.273, 0.321, 0.354, 0.383, 0.408, 0.433, 0.456, 0.479, 0.502, 0.526, 0.552, 0.580,
    0.612, 0.651, 0.706, 1.0,
];

/// The cover a cell of field cover `c` shows: the calibration to Monahan
/// counts a cell as whitecap where its cover passes ½, so a whitecap is
/// drawn as a raft with an edge there (full from 0.7, none below 0.3)
/// rather than the field's gradual rise across cells, and old foam below
/// it as the residual lace it is (0.6·c). As `foam_shown_cover` in WGSL.
pub fn shown_cover(c: f32) -> f32 {
    let t = ((c - 0.3) / 0.4).clamp(0.0, 1.0);
    (t * t * (3.0 - 2.0 * t)).max(0.6 * c)
}

/// The threshold t(c) for cover `c`: piecewise linear in the table.
pub fn foam_threshold(c: f32) -> f32 {
    let x = c.clamp(0.0, 1.0) * 16.0;
    let k = (x.floor() as usize).min(15);
    let f = x - k as f32;
    FOAM_THRESHOLDS[k] + (FOAM_THRESHOLDS[k + 1] - FOAM_THRESHOLDS[k]) * f
}

/// The lattice hash of WGSL's `noise_hash` (0–1): the integer point's bits
/// mixed as u32.
pub fn noise_hash(i: Vec2) -> f32 {
    let k = [i.x as i32 as u32, i.y as i32 as u32];
    let mut h = k[0].wrapping_mul(0x27d4_eb2d) ^ k[1].wrapping_mul(0x1656_67b1);
    h = (h ^ (h >> 15)).wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    (h & 0xffff) as f32 / 65535.0
}

/// Value noise (0–1) with its gradient: (value, ∂/∂x, ∂/∂y).
pub fn value_noise_d(x: Vec2) -> [f32; 3] {
    let i = x.floor();
    let f = x - i;
    let u = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let du = 6.0 * f * (Vec2::ONE - f);
    let a = noise_hash(i);
    let b = noise_hash(i + Vec2::new(1.0, 0.0));
    let c = noise_hash(i + Vec2::new(0.0, 1.0));
    let d = noise_hash(i + Vec2::new(1.0, 1.0));
    let k = a - b - c + d;
    let v = a + (b - a) * u.x + (c - a) * u.y + k * u.x * u.y;
    [v, du.x * ((b - a) + k * u.y), du.y * ((c - a) + k * u.x)]
}

/// A cell network's nearest and second-nearest feature points (Worley
/// 1996): their distances F1 ≤ F2 and the gradients of each, in cells.
#[derive(Clone, Copy, Debug)]
pub struct Cells {
    pub f1: f32,
    pub f2: f32,
    pub g1: Vec2,
    pub g2: Vec2,
}

/// One feature point per unit cell, jittered over its middle 80%.
pub fn cells(x: Vec2) -> Cells {
    let base = x.floor();
    let mut c = Cells { f1: 8.0, f2: 8.0, g1: Vec2::ZERO, g2: Vec2::ZERO };
    for j in -1..=1 {
        for i in -1..=1 {
            let cell = base + Vec2::new(i as f32, j as f32);
            let jitter = Vec2::new(
                noise_hash(cell + Vec2::new(113.0, 71.0)),
                noise_hash(cell + Vec2::new(37.0, 191.0)),
            );
            let to = x - (cell + Vec2::splat(0.1) + 0.8 * jitter);
            let d = to.length();
            let g = to / d.max(1e-6);
            if d < c.f1 {
                c.f2 = c.f1;
                c.g2 = c.g1;
                c.f1 = d;
                c.g1 = g;
            } else if d < c.f2 {
                c.f2 = d;
                c.g2 = g;
            }
        }
    }
    c
}

/// A cell network's wall distance at x (cells): (F2 − F1)/EDGE_SPAN capped
/// at 1, and its gradient (per cell).
fn walls(x: Vec2) -> (f32, Vec2) {
    let c = cells(x);
    let edge = (c.f2 - c.f1) / EDGE_SPAN;
    if edge < 1.0 { (edge, (c.g2 - c.g1) / EDGE_SPAN) } else { (1.0, Vec2::ZERO) }
}

/// The foam's structure at `along`, `across` (m, in the wind's frame) for
/// streaks `streak` times longer than wide: s (0–1) and its gradient (per
/// m along, per m across). The breakup is stretched by the full streak
/// length, the lace by its square root (bubble cells are drawn out less
/// than the windrows they gather in), and the lace is warped by a noise
/// LACE_WARP cells deep so that its walls wander; the network at two
/// scales (LACE_CELL and 0.4 of it) gives the bubbles many sizes. The
/// renderer draws it magnified by powers of two where a pixel is too
/// coarse for its finer network (foam has structure at every scale: lace,
/// patches of lace, streaks of patches); its distribution, and so the
/// thresholds, are the same at every magnification.
pub fn foam_structure(along: f32, across: f32, streak: f32) -> [f32; 3] {
    let streak = streak.max(1.0);
    let lace_stretch = streak.sqrt();
    // Lace space (cells) and its warp.
    let r = Vec2::new(along / lace_stretch, across) / LACE_CELL;
    let w1 = value_noise_d(r / WARP_SCALE + Vec2::new(41.0, 7.0));
    let w2 = value_noise_d(r / WARP_SCALE + Vec2::new(3.0, 53.0));
    let k = 2.0 * LACE_WARP / WARP_SCALE;
    let x = r + 2.0 * LACE_WARP * Vec2::new(w1[0] - 0.5, w2[0] - 0.5);
    // ∂x/∂r: the identity plus the warp's Jacobian (rows: x's components).
    let jx = Vec2::new(1.0 + k * w1[1], k * w1[2]);
    let jy = Vec2::new(k * w2[1], 1.0 + k * w2[2]);
    let (e1, g1) = walls(x);
    let (e2, g2) = walls(x / 0.4 + Vec2::new(19.0, 23.0));
    let e = 0.65 * e1 + 0.35 * e2;
    let ge_x = 0.65 * g1 + 0.35 * g2 / 0.4;
    // Back to r (chain rule through the warp), then to metres.
    let ge_r = Vec2::new(ge_x.x * jx.x + ge_x.y * jy.x, ge_x.x * jx.y + ge_x.y * jy.y);
    let ge = Vec2::new(ge_r.x / (lace_stretch * LACE_CELL), ge_r.y / LACE_CELL);
    // The breakup.
    let q = Vec2::new(along / streak, across);
    let m1 = value_noise_d(q / BREAKUP + Vec2::new(17.0, 3.0));
    let m2 = value_noise_d(q / (0.35 * BREAKUP) + Vec2::new(5.0, 29.0));
    let m = 0.65 * m1[0] + 0.35 * m2[0];
    let gq = 0.65 * Vec2::new(m1[1], m1[2]) / BREAKUP
        + 0.35 * Vec2::new(m2[1], m2[2]) / (0.35 * BREAKUP);
    let gm = Vec2::new(gq.x / streak, gq.y);
    let s = LACE_WEIGHT * e + (1.0 - LACE_WEIGHT) * m;
    let g = LACE_WEIGHT * ge + (1.0 - LACE_WEIGHT) * gm;
    [s, g.x, g.y]
}

/// Foam at a point of cover `c` whose structure is `s`, resolved (no
/// footprint): whether it is foam and how thick (0–1).
pub fn foam_at(c: f32, s: f32) -> (bool, f32) {
    let t = foam_threshold(c);
    (c > 0.0 && s < t, ((t - s) / THICK_SPAN).clamp(0.0, 1.0) * marbling(s))
}

/// How much of a dense sheet's thickness a point of structure `s` keeps
/// (1 on the walls, 1 − [`MARBLE`] in the cells' middles). As
/// `foam_marbling` in WGSL.
pub fn marbling(s: f32) -> f32 {
    let x = ((s - MARBLE_FROM) / (MARBLE_TO - MARBLE_FROM)).clamp(0.0, 1.0);
    1.0 - MARBLE * x * x * (3.0 - 2.0 * x)
}

/// The mean thickness of the foam where a cover `c` puts it (0.3 +
/// 0.65·c^0.6, less the marbling of dense sheets, 0.115·((c − 0.6)/0.4)²
/// above 0.6; within 0.04, measured by `mean_thickness_is_the_fit`): what
/// a pixel too coarse for any of the structure's magnifications shows, so
/// the opacity and shade of near and far foam agree. As
/// `foam_mean_thickness` in WGSL.
pub fn mean_thickness(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    let dense = (c - 0.6).max(0.0) / 0.4;
    0.3 + 0.65 * c.powf(0.6) - 0.115 * dense * dense
}

/// How far past a lump's terminator the sun reaches foam: a raft scatters
/// light through its depth, so it is lit half-Lambert over this wrap.
pub const FOAM_WRAP: f32 = 0.3;
/// The shade of a thin film relative to a thick sheet: light goes on into
/// the water through a film, so its shade runs from this to 1 with thickness.
pub const FOAM_FILM_SHADE: f32 = 0.65;

/// The radiance foam sends to the eye (it is diffuse: the same in every
/// direction). A raft of albedo [`super::FOAM_ALBEDO`] whose top faces
/// `top` (unit; the wave's normal tilted by the foam's lumps), of
/// `thickness` 0–1, lit by the sun (`sun_dir` unit, `sun_irradiance` on a
/// plane facing it, shadow already applied) and the sky
/// (`sky_irradiance_up` on a level plane). A tilted top sees (1 + top.y)/2
/// of the dome (an even sky's view factor), and the sea over the rest of
/// its view sends back a few percent, left out; so foam on a wave's face
/// takes the sky's hue and brightness as a white card would, and the sun
/// lights the faces turned to it. As `foam_radiance` in WGSL.
pub fn foam_radiance(
    top: glam::Vec3,
    thickness: f32,
    sun_dir: glam::Vec3,
    sun_irradiance: glam::Vec3,
    sky_irradiance_up: glam::Vec3,
) -> glam::Vec3 {
    let lit = if sun_dir.y >= 0.0 {
        ((top.dot(sun_dir) + FOAM_WRAP) / (1.0 + FOAM_WRAP)).max(0.0)
    } else {
        0.0
    };
    let sky_seen = 0.5 * (1.0 + top.y);
    let shade = FOAM_FILM_SHADE + (1.0 - FOAM_FILM_SHADE) * thickness.clamp(0.0, 1.0);
    (sky_irradiance_up * sky_seen + sun_irradiance * lit)
        * (super::FOAM_ALBEDO * shade / std::f32::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Structure samples over a large area (a 2-D lattice 0.37 m apart over
    /// 148 × 148 m: some 8000 lace cells and 2400 breakup blobs).
    fn samples(shift: Vec2) -> Vec<f32> {
        let n = 400_usize;
        let mut s = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let q = Vec2::new(i as f32 + 0.5 * (j % 2) as f32, j as f32 + 0.31) + shift;
                s.push(foam_structure(q.x * 0.37, q.y * 0.37, 3.0)[0]);
            }
        }
        s
    }

    fn mean_thickness_at(s: &[f32], c: f32) -> f32 {
        let (n, sum) = s
            .iter()
            .map(|&v| foam_at(c, v))
            .filter(|f| f.0)
            .fold((0, 0.0), |(n, sum), f| (n + 1, sum + f.1));
        sum / n as f32
    }

    #[test]
    fn thresholds_are_the_structures_quantiles() {
        let table = FOAM_THRESHOLDS;
        let mut s = samples(Vec2::new(3.7, -11.2));
        s.sort_by(f32::total_cmp);
        let q: Vec<String> =
            (0..=16).map(|k| format!("{:.3}", s[((s.len() - 1) * k) / 16])).collect();
        println!("quantiles: {}", q.join(", "));
        for (k, &t) in table.iter().enumerate().skip(1).take(15) {
            let measured = s[(s.len() * k) / 16];
            assert!(
                (measured - t).abs() < 0.005,
                "quantile {k}/16: measured {measured:.3}, table {t}"
            );
        }
    }

    /// The covered fraction is the cover itself at every cover and every
    /// share of the finer network, so a pixel that shows c (too far to
    /// resolve the lace) matches the lace's mean: no band where they meet.
    #[test]
    fn covered_fraction_is_the_cover() {
        // Elsewhere than where the quantiles were measured.
        let s = samples(Vec2::new(251.3, 87.9));
        for c in [0.05_f32, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95] {
            let covered = s.iter().filter(|&&v| foam_at(c, v).0).count() as f32 / s.len() as f32;
            assert!((covered - c).abs() < 0.03, "cover {c}: {covered:.3} of the surface is foam");
        }
    }

    /// Sparse foam is lace (thin filaments, mostly within a thickness span
    /// of an edge); dense foam is a thick sheet.
    #[test]
    fn sparse_foam_is_thin_lace_dense_foam_a_thick_sheet() {
        let s = samples(Vec2::new(-40.0, 17.0));
        let (sparse, dense) = (mean_thickness_at(&s, 0.05), mean_thickness_at(&s, 0.9));
        assert!(sparse < 0.5 && dense > 0.8, "thickness: sparse {sparse:.2}, dense {dense:.2}");
    }

    /// A whitecap's sheet is marbled, not flat: its cells' middles are a
    /// thinner film (a fifth to a half of it under 0.7 of full thickness)
    /// between walls of full thickness; lace is never marbled.
    #[test]
    fn a_dense_sheet_is_marbled_lace_is_not() {
        let s = samples(Vec2::new(77.0, -31.0));
        let sheet: Vec<f32> = s.iter().map(|&v| foam_at(1.0, v).1).collect();
        let thin = sheet.iter().filter(|&&t| t < 0.7).count() as f32 / sheet.len() as f32;
        let walls = s.iter().zip(&sheet).filter(|(v, _)| **v < 0.4).map(|(_, t)| *t);
        assert!((0.2..0.5).contains(&thin), "{thin:.2} of a full sheet is thinner than 0.7");
        assert!(walls.clone().count() > 1000 && walls.clone().all(|t| t == 1.0));
        assert!((marbling(MARBLE_TO) - (1.0 - MARBLE)).abs() < 1e-6);
        // Lace (cover 0.3, threshold 0.38) lies below where marbling starts.
        assert!(foam_threshold(0.3) < MARBLE_FROM);
        assert_eq!(marbling(foam_threshold(0.3)), 1.0);
    }

    #[test]
    fn mean_thickness_is_the_fit() {
        let s = samples(Vec2::new(-123.0, 45.6));
        for c in [0.05_f32, 0.1, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95] {
            let measured = mean_thickness_at(&s, c);
            assert!(
                (measured - mean_thickness(c)).abs() < 0.04,
                "cover {c}: mean thickness {measured:.3}, fit {:.3}",
                mean_thickness(c)
            );
        }
    }

    #[test]
    fn gradients_are_the_structures_slopes() {
        let mut checked = 0;
        for k in 0..400 {
            let q = Vec2::new(k as f32 * 0.173 + 0.05, k as f32 * 0.291 - 7.0);
            let f = |d: Vec2| foam_structure(q.x + d.x, q.y + d.y, 3.0)[0];
            let [_, gx, gy] = foam_structure(q.x, q.y, 3.0);
            let h = 1e-3;
            let dx = (f(Vec2::new(h, 0.0)) - f(Vec2::new(-h, 0.0))) / (2.0 * h);
            let dy = (f(Vec2::new(0.0, h)) - f(Vec2::new(0.0, -h))) / (2.0 * h);
            // Cell walls and the edge span's cap are creases: the one-sided
            // slopes differ there, so skip points where they do.
            let dx1 = (f(Vec2::new(h, 0.0)) - f(Vec2::ZERO)) / h;
            let dy1 = (f(Vec2::new(0.0, h)) - f(Vec2::ZERO)) / h;
            if (dx1 - dx).abs() > 0.02 * (1.0 + dx.abs())
                || (dy1 - dy).abs() > 0.02 * (1.0 + dy.abs())
            {
                continue;
            }
            checked += 1;
            assert!(
                (dx - gx).abs() < 0.03 * (1.0 + gx.abs())
                    && (dy - gy).abs() < 0.03 * (1.0 + gy.abs()),
                "at {q}: analytic ({gx}, {gy}), numeric ({dx}, {dy})"
            );
        }
        assert!(checked > 200, "only {checked} points away from creases");
    }

    /// A whitecap shows where the calibration counts one: a cell over ½
    /// cover shows more than half foam, one under it less; thick whitecap
    /// shows whole, old foam as lace.
    #[test]
    fn shown_cover_keeps_the_whitecap_threshold() {
        assert!((shown_cover(0.5) - 0.5).abs() < 1e-6);
        assert!(shown_cover(0.55) > 0.5 && shown_cover(0.45) < 0.5);
        assert_eq!(shown_cover(0.7), 1.0);
        assert!((shown_cover(0.2) - 0.12).abs() < 1e-6);
        let mut last = 0.0;
        for k in 0..=100 {
            let c = shown_cover(k as f32 / 100.0);
            assert!((0.0..=1.0).contains(&c) && c >= last);
            last = c;
        }
    }

    /// A thick level sheet under the sky alone is a white card: albedo ×
    /// E/π (Lambert). The sun adds E·(cos θ + wrap)/(1 + wrap); a face
    /// turned from the sun past the wrap gets none, a vertical face half
    /// the sky; a film is FOAM_FILM_SHADE as bright as a sheet.
    #[test]
    fn foam_radiance_is_a_lambertian_raft() {
        use crate::whitewater::FOAM_ALBEDO;
        use glam::Vec3;
        use std::f32::consts::PI;
        let sky = Vec3::new(28.0, 29.0, 30.0);
        let sun = Vec3::new(36.0, 20.0, 7.0);
        let sun_dir = Vec3::new(0.0, 0.5, -0.75_f32.sqrt());
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-4 * b.max_element();
        let card = foam_radiance(Vec3::Y, 1.0, Vec3::new(0.0, -1.0, 0.0), sun, sky);
        assert!(close(card, sky * FOAM_ALBEDO / PI), "{card}");
        let lit = foam_radiance(Vec3::Y, 1.0, sun_dir, sun, sky);
        assert!(close(lit, (sky + sun * (0.5 + FOAM_WRAP) / (1.0 + FOAM_WRAP)) * FOAM_ALBEDO / PI));
        let away = foam_radiance(-sun_dir.with_y(0.0).normalize(), 1.0, sun_dir, sun, sky);
        assert!(close(away, sky * 0.5 * FOAM_ALBEDO / PI), "{away}");
        let film = foam_radiance(Vec3::Y, 0.0, sun_dir, sun, sky);
        assert!(close(film, lit * FOAM_FILM_SHADE));
        let toward = foam_radiance(
            (Vec3::Y + 0.3 * sun_dir.with_y(0.0)).normalize(),
            1.0,
            sun_dir,
            sun,
            sky,
        );
        assert!(toward.x > lit.x && lit.x > away.x);
    }

    /// A whitecap's field keeps the reference sizes, a harbor's wake is
    /// scaled down with its cells, and a pool's fine field stops at the
    /// finest lace.
    #[test]
    fn look_units_follow_the_cell_down_to_the_finest_lace() {
        assert_eq!(look_units(FOAM_REFERENCE_CELL), 1.0);
        assert!((look_units(32.0 / 256.0) - 0.08).abs() < 1e-6);
        assert!((look_units(4.0 / 256.0) * LACE_CELL - FINEST_LACE).abs() < 1e-6);
    }
}
