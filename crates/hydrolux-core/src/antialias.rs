//! Temporal anti-aliasing: the CPU twin of the renderer's `antialias`
//! technique (`passes/antialias/`).
//!
//! Each frame the camera's projection is shifted by a sub-pixel offset
//! (the Halton (2, 3) sequence, so that successive frames sample different
//! points of every pixel), and a resolve blends the new frame into the
//! history of earlier ones, read where the same surface was last frame
//! (reprojected by depth through last frame's camera). What the history
//! says is first clipped to the colours of the new frame's 3×3
//! neighbourhood (variance clipping in YCoCg), so what moved or was
//! uncovered does not ghost. Karis, "High Quality Temporal Supersampling"
//! (SIGGRAPH 2014 course); Salvi, "An Excursion in Temporal Supersampling"
//! (GDC 2016); Pedersen, "Temporal Reprojection Anti-Aliasing in INSIDE"
//! (GDC 2016). This answers issue #32's item 5 (edges that do not crawl in
//! motion); seed 000 §5.2 names the horizon's aliasing it also removes.
//!
//! The first frame after a reset (a new renderer, scene, size or view) is
//! drawn without an offset and passed through unchanged, so a single still
//! is exactly the frame as drawn.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Offsets per cycle of the jitter sequence.
pub const JITTER_PERIOD: u64 = 16;
/// The new frame's share of the resolved colour (an exponential history of
/// about 1 / 0.1 = 10 frames, time constant ~9.5 frames).
pub const CURRENT_WEIGHT: f32 = 0.1;
/// The new frame's share where the pixel's look changes by itself rather
/// than with the camera (the water's surface, particles): its history is
/// trusted for about two frames, enough to average the jitter's shimmer
/// without smearing ripples that no reprojection follows.
pub const RESPONSIVE_WEIGHT: f32 = 0.5;
/// Half-width of the clipping box in standard deviations of the
/// neighbourhood's colours (Salvi's γ).
pub const CLIP_SIGMAS: f32 = 1.25;

/// The radical inverse of `index` in `base` (index ≥ 1 gives (0, 1)).
pub fn halton(mut index: u64, base: u64) -> f32 {
    let mut f = 1.0f64;
    let mut r = 0.0f64;
    while index > 0 {
        f /= base as f64;
        r += f * (index % base) as f64;
        index /= base;
    }
    r as f32
}

/// The sub-pixel offset (pixels, x right and y down, each within ½) of
/// the `frame`-th frame since the history was reset: none for the first.
/// A cycle's offsets are centred on the pixel's centre (their mean is
/// removed), so the image that converges is not shifted.
pub fn jitter_px(frame: u64) -> Vec2 {
    if frame == 0 {
        return Vec2::ZERO;
    }
    let point = |i: u64| Vec2::new(halton(i, 2), halton(i, 3));
    let mean = (1..=JITTER_PERIOD).map(point).sum::<Vec2>() / JITTER_PERIOD as f32;
    point((frame - 1) % JITTER_PERIOD + 1) - mean
}

/// The clip-space shift that moves everything drawn by `jitter` pixels on
/// a `size` image: applied after the view-projection (`shift * view_proj`).
pub fn jitter_matrix(jitter: Vec2, size: (u32, u32)) -> Mat4 {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    // NDC spans 2 over the image, and its y points up.
    Mat4::from_translation(Vec3::new(2.0 * jitter.x / w, -2.0 * jitter.y / h, 0.0))
}

/// Where the point seen at texture coordinate `uv` (x right, y down, in
/// [0, 1]) with depth `depth` (the main view's reversed-Z depth) was on
/// last frame's image: `reprojection` is last frame's view-projection
/// times the inverse of this frame's (both without jitter). Points at
/// infinity (depth 0, the sky) move with the camera's turn only. `None`
/// where it was behind the camera or off the image.
pub fn reproject(reprojection: Mat4, uv: Vec2, depth: f32) -> Option<Vec2> {
    let ndc = Vec4::new(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y, depth, 1.0);
    let clip = reprojection * ndc;
    if clip.w <= 1e-7 {
        return None;
    }
    let p = Vec2::new(clip.x, clip.y) / clip.w;
    let prev = Vec2::new(0.5 * p.x + 0.5, 0.5 - 0.5 * p.y);
    let inside = (0.0..=1.0).contains(&prev.x) && (0.0..=1.0).contains(&prev.y);
    inside.then_some(prev)
}

/// Linear RGB to YCoCg (luma and two chroma axes: a box around a
/// neighbourhood's colours is tighter here than in RGB).
pub fn rgb_to_ycocg(c: Vec3) -> Vec3 {
    Vec3::new(
        0.25 * c.x + 0.5 * c.y + 0.25 * c.z,
        0.5 * c.x - 0.5 * c.z,
        -0.25 * c.x + 0.5 * c.y - 0.25 * c.z,
    )
}

pub fn ycocg_to_rgb(c: Vec3) -> Vec3 {
    Vec3::new(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z)
}

/// `history` moved towards `centre` until it lies in the box
/// `centre ± extent` (unchanged if it already does): the point where the
/// segment between them leaves the box, which keeps the history's hue
/// better than clamping each axis.
pub fn clip_to_box(history: Vec3, centre: Vec3, extent: Vec3) -> Vec3 {
    let offset = history - centre;
    let units = (offset / extent.max(Vec3::splat(1e-6))).abs();
    let largest = units.max_element();
    if largest > 1.0 { centre + offset / largest } else { history }
}

/// What the history holds at a pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct History {
    /// The reprojected colour (linear pre-exposed HDR).
    pub colour: Vec3,
    /// Frames it holds: since the last reset, or while `settled`, since
    /// the view last changed.
    pub frames: u64,
    /// Neither the camera nor the simulation's time changed since the
    /// last frame (a still, a paused viewer): only the jitter differs.
    pub settled: bool,
}

/// The resolved colour of one pixel: `neighbourhood` the new frame's 3×3
/// colours around it (row by row, the pixel itself at index 4), `history`
/// what the history holds there (`None`: nothing). Colours are linear
/// pre-exposed HDR.
///
/// A settled view averages its jittered frames evenly (the supersampled
/// pixel, converging as 1 / frames). Otherwise the history is first clipped
/// to the neighbourhood's variance box, and `trust` (the HDR image's alpha,
/// in [0, 1]) says how far the pixel's colour follows the geometry that
/// reprojection tracks (1) or changes by itself (0: the water's surface):
/// the new frame's share goes from [`CURRENT_WEIGHT`] to
/// [`RESPONSIVE_WEIGHT`], and is at least 1 / (frames + 1) while the
/// history is young. That blend weighs each side by 1 / (1 + luma)
/// (Karis), so that a lone bright sample (a glint) does not flicker through.
pub fn resolve(neighbourhood: &[Vec3; 9], history: Option<History>, trust: f32) -> Vec3 {
    let current = neighbourhood[4];
    let Some(history) = history else { return current };
    if history.settled {
        return history.colour + (current - history.colour) * min_share(history.frames);
    }
    let mut sum = Vec3::ZERO;
    let mut sum_sq = Vec3::ZERO;
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    for &c in neighbourhood {
        let y = rgb_to_ycocg(c);
        sum += y;
        sum_sq += y * y;
        lo = lo.min(y);
        hi = hi.max(y);
    }
    let mean = sum / 9.0;
    let sigma = (sum_sq / 9.0 - mean * mean).max(Vec3::ZERO).sqrt();
    // The variance box, no larger than the neighbourhood's own range.
    let box_lo = (mean - CLIP_SIGMAS * sigma).max(lo);
    let box_hi = (mean + CLIP_SIGMAS * sigma).min(hi);
    let centre = 0.5 * (box_lo + box_hi);
    let extent = 0.5 * (box_hi - box_lo);
    let clipped =
        ycocg_to_rgb(clip_to_box(rgb_to_ycocg(history.colour), centre, extent)).max(Vec3::ZERO);
    let share = current_share(trust, history.frames);
    let weight = |c: Vec3, share: f32| share / (1.0 + luma(c));
    let (wc, wh) = (weight(current, share), weight(clipped, 1.0 - share));
    // The box in YCoCg reaches outside the RGB gamut: radiance stays ≥ 0.
    ((current * wc + clipped * wh) / (wc + wh)).max(Vec3::ZERO)
}

/// A pixel's trust in its history from the HDR image's alpha: what
/// changes by itself (alpha < 1) is trusted fully while the simulation's
/// time stands still (a paused viewer, an offline frame's samples), since
/// then only the camera moves.
pub fn trust(alpha: f32, time_still: bool) -> f32 {
    if time_still { 1.0 } else { alpha.clamp(0.0, 1.0) }
}

/// The new frame's share of the resolve (before the luma weights): by the
/// pixel's `trust`, and at least an even share of the `frames` in the history.
pub fn current_share(trust: f32, frames: u64) -> f32 {
    let by_trust = RESPONSIVE_WEIGHT + (CURRENT_WEIGHT - RESPONSIVE_WEIGHT) * trust.clamp(0.0, 1.0);
    by_trust.max(min_share(frames))
}

/// The least share of the new frame while the history holds `frames`
/// (counted up to 1024: by then a settled pixel has converged).
pub fn min_share(frames: u64) -> f32 {
    1.0 / (frames.min(1024) as f32 + 1.0)
}

/// Rec. 709 luma of linear RGB.
pub fn luma(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;

    /// A history of `frames` frames of a view that moves.
    fn moving(colour: Option<Vec3>, frames: u64) -> Option<History> {
        colour.map(|colour| History { colour, frames, settled: false })
    }

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 2.0, 8.0),
            look_at: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
        }
    }

    #[test]
    fn halton_is_the_radical_inverse() {
        let expect = [(1, 2, 0.5), (2, 2, 0.25), (3, 2, 0.75), (5, 2, 0.625)];
        for (i, b, want) in expect {
            assert_eq!(halton(i, b), want);
        }
        let thirds = [(1, 1.0 / 3.0), (2, 2.0 / 3.0), (3, 1.0 / 9.0), (4, 4.0 / 9.0)];
        for (i, want) in thirds {
            assert!((halton(i, 3) - want).abs() < 1e-7);
        }
    }

    #[test]
    fn the_jitter_starts_centred_and_covers_the_pixel_evenly() {
        assert_eq!(jitter_px(0), Vec2::ZERO);
        let cycle: Vec<Vec2> = (1..=JITTER_PERIOD).map(jitter_px).collect();
        assert_eq!(jitter_px(1), jitter_px(1 + JITTER_PERIOD));
        for j in &cycle {
            assert!(j.abs().max_element() < 0.5, "{j}");
        }
        // Each quarter of the pixel holds a quarter of a cycle's samples,
        // and their mean is the centre.
        for q in 0..4 {
            let (right, down) = (q % 2 == 1, q / 2 == 1);
            let n = cycle.iter().filter(|j| (j.x >= 0.0) == right && (j.y >= 0.0) == down).count();
            assert!((3..=5).contains(&n), "quarter {q}: {n} of 16");
        }
        let mean = cycle.iter().sum::<Vec2>() / cycle.len() as f32;
        assert!(mean.length() < 1e-6, "{mean}");
    }

    #[test]
    fn the_jitter_matrix_moves_every_point_by_the_offset_in_pixels() {
        let cam = camera();
        let size = (320, 180);
        let vp = cam.view_projection(size.0 as f32 / size.1 as f32);
        let jitter = Vec2::new(0.3, -0.45);
        let shifted = jitter_matrix(jitter, size) * vp;
        let pixel = |m: Mat4, p: Vec3| {
            let c = m.project_point3(p);
            Vec2::new((0.5 * c.x + 0.5) * size.0 as f32, (0.5 - 0.5 * c.y) * size.1 as f32)
        };
        for p in [cam.look_at, cam.look_at + Vec3::new(3.0, 1.0, -2.0), Vec3::new(-5.0, 0.0, 9.0)] {
            let moved = pixel(shifted, p) - pixel(vp, p);
            assert!((moved - jitter).length() < 1e-3, "{p}: moved {moved}");
            // Depth is untouched, so the depth test sees the same surfaces.
            assert!((shifted.project_point3(p).z - vp.project_point3(p).z).abs() < 1e-7);
        }
    }

    /// A point seen through one camera reprojects to where a second camera
    /// sees it; a point at infinity moves only with the turn.
    #[test]
    fn reprojection_finds_where_a_point_was_last_frame() {
        let aspect = 16.0 / 9.0;
        let a = camera();
        let mut b = a;
        b.position += Vec3::new(0.4, 0.1, -0.3);
        b.look_at += Vec3::new(0.2, 0.0, 0.1);
        let (vp_a, vp_b) = (a.view_projection(aspect), b.view_projection(aspect));
        let uv = |vp: Mat4, p: Vec3| {
            let c = vp.project_point3(p);
            (Vec2::new(0.5 * c.x + 0.5, 0.5 - 0.5 * c.y), c.z)
        };
        let m = vp_b * vp_a.inverse();
        for p in [a.look_at, a.look_at + Vec3::new(1.0, 0.5, 2.0), Vec3::new(-2.0, -1.0, -3.0)] {
            let (now, depth) = uv(vp_a, p);
            let (then, _) = uv(vp_b, p);
            let got = reproject(m, now, depth).expect("on screen");
            assert!((got - then).length() < 1e-4, "{p}: {got} vs {then}");
        }
        // The sky (depth 0) through a camera that only moved: no motion.
        let mut moved = a;
        moved.position += Vec3::new(5.0, 2.0, 1.0);
        moved.look_at += Vec3::new(5.0, 2.0, 1.0);
        let m = moved.view_projection(aspect) * vp_a.inverse();
        let sky = Vec2::new(0.3, 0.2);
        assert!((reproject(m, sky, 0.0).unwrap() - sky).length() < 1e-5);
        // A still camera reprojects every pixel onto itself.
        assert!((reproject(Mat4::IDENTITY, sky, 0.5).unwrap() - sky).length() < 1e-6);
        // Off the last image: none.
        let far_turn = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0));
        assert_eq!(reproject(far_turn, sky, 0.5), None);
    }

    #[test]
    fn ycocg_round_trips_and_clipping_stays_in_the_box() {
        for c in [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.2, 0.7, 3.5), Vec3::ZERO] {
            assert!((ycocg_to_rgb(rgb_to_ycocg(c)) - c).length() < 1e-6);
        }
        assert_eq!(rgb_to_ycocg(Vec3::ONE), Vec3::new(1.0, 0.0, 0.0));
        let (centre, extent) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.1, 0.05, 0.05));
        let inside = Vec3::new(0.55, 0.01, -0.02);
        assert_eq!(clip_to_box(inside, centre, extent), inside);
        let clipped = clip_to_box(Vec3::new(1.5, 0.2, 0.0), centre, extent);
        assert!(((clipped - centre) / extent).abs().max_element() <= 1.0 + 1e-5);
        // On the segment towards the centre.
        let dir = (Vec3::new(1.5, 0.2, 0.0) - centre).normalize();
        assert!(((clipped - centre).normalize() - dir).length() < 1e-5);
    }

    /// The pixel a straight edge crosses converges, with a still camera, to
    /// the part of it the bright side covers (the supersampled answer),
    /// where without the jitter it is all or nothing; and it stops
    /// flickering.
    #[test]
    fn a_still_edge_converges_to_its_coverage() {
        // A vertical edge at x = a inside the pixel [0, 1]²: brighter right.
        for a in [0.3f32, 0.5, 0.8] {
            let (dark, bright) = (Vec3::splat(0.05), Vec3::splat(0.6));
            let sample = |x: f32| if x >= a { bright } else { dark };
            let mut history: Option<Vec3> = None;
            let mut last = Vec::new();
            for frame in 0..200u64 {
                let x = 0.5 + jitter_px(frame).x;
                let mut n = [dark; 9];
                for row in 0..3 {
                    n[row * 3] = dark; // the pixel to the left: all dark
                    n[row * 3 + 1] = sample(x);
                    n[row * 3 + 2] = bright; // to the right: all bright
                }
                let out = resolve(&n, moving(history, frame), 1.0);
                history = Some(out);
                if frame >= 200 - JITTER_PERIOD {
                    last.push(out.x);
                }
            }
            // The exact answer blends in linear light by area, but the
            // resolve weighs by 1 / (1 + luma): the converged value is
            // the weighted mean of the two sides.
            let w = |c: Vec3| 1.0 / (1.0 + luma(c));
            let share = 1.0 - a;
            let want = (share * bright.x * w(bright) + (1.0 - share) * dark.x * w(dark))
                / (share * w(bright) + (1.0 - share) * w(dark));
            let mean = last.iter().sum::<f32>() / last.len() as f32;
            let (lo, hi) =
                last.iter().fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
            let contrast = bright.x - dark.x;
            assert!((mean - want).abs() < 0.05 * contrast, "edge at {a}: {mean} vs {want}");
            // The raw samples swing over the whole contrast; the resolve
            // keeps within a third of it.
            assert!(hi - lo < 0.35 * contrast, "edge at {a}: flickers {lo}..{hi}");
        }
    }

    /// What was there before and is no longer anywhere in the neighbourhood
    /// (a bright object moved away) is clipped out at once.
    #[test]
    fn a_stale_history_does_not_ghost() {
        let now = [Vec3::splat(0.1); 9];
        let out = resolve(&now, moving(Some(Vec3::splat(4.0)), 50), 1.0);
        assert!((out - Vec3::splat(0.1)).length() < 1e-5, "{out}");
        // With no history, the frame passes through exactly.
        let mut n = [Vec3::splat(0.2); 9];
        n[4] = Vec3::new(0.3, 0.4, 0.5);
        assert_eq!(resolve(&n, None, 1.0), n[4]);
        // A history inside the neighbourhood's range is kept at 90% (its
        // luma weight equal to the current's).
        let mut n = [Vec3::splat(0.2); 9];
        n[1] = Vec3::splat(0.4);
        n[4] = Vec3::splat(0.3);
        let h = Vec3::splat(0.25);
        let out = resolve(&n, moving(Some(h), 50), 1.0);
        let (wc, wh) = (0.1 / 1.3, 0.9 / 1.25);
        let want = (0.3 * wc + 0.25 * wh) / (wc + wh);
        assert!((out.x - want).abs() < 1e-5, "{out} vs {want}");
        // Where the pixel changes by itself, half of it is the new frame.
        let out = resolve(&n, moving(Some(h), 50), 0.0);
        let (wc, wh) = (0.5 / 1.3, 0.5 / 1.25);
        let want = (0.3 * wc + 0.25 * wh) / (wc + wh);
        assert!((out.x - want).abs() < 1e-5, "{out} vs {want}");
        // Clipped into a neighbourhood of saturated colours, a history
        // stays a radiance (YCoCg's box reaches outside RGB's gamut).
        let mut n = [Vec3::new(0.0, 0.0, 1.0); 9];
        n[2] = Vec3::new(1.0, 0.0, 0.0);
        n[6] = Vec3::new(0.0, 1.0, 0.0);
        for h in [Vec3::new(5.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 9.0), Vec3::new(0.0, 3.0, 3.0)] {
            let out = resolve(&n, moving(Some(h), 50), 1.0);
            assert!(out.min_element() >= 0.0, "{h} → {out}");
        }
        // A young history is averaged evenly: the second frame is half.
        assert_eq!(current_share(1.0, 1), 0.5);
        assert_eq!(current_share(1.0, 3), 0.25);
        assert!((current_share(1.0, 30) - CURRENT_WEIGHT).abs() < 1e-6);
    }

    /// A settled view averages its jittered frames evenly, without
    /// clipping: the supersampled pixel, exactly.
    #[test]
    fn a_still_is_the_mean_of_its_jittered_frames() {
        let samples = [0.2f32, 0.6, 0.3, 0.5, 0.25, 0.55, 0.4, 3.0];
        let mut history: Option<History> = None;
        for (k, &v) in samples.iter().enumerate() {
            let mut n = [Vec3::splat(0.4); 9];
            n[4] = Vec3::splat(v);
            let out = resolve(&n, history, 1.0);
            history = Some(History { colour: out, frames: k as u64 + 1, settled: true });
        }
        let want = samples.iter().sum::<f32>() / samples.len() as f32;
        let got = history.unwrap().colour.x;
        assert!((got - want).abs() < 1e-5, "{got} vs {want}");
    }
}
