//! What an approximation costs (`hydrolux compare`, issue #16): the error
//! between two renderings of one frame, as the CIELAB colour difference
//! ΔE*ab (CIE 1976) of the displayed sRGB colours (about 1 is the smallest
//! difference a viewer notices side by side, 10 is plain to see), and its
//! statistics over a set of pixels.

/// CIELAB (L*, a*, b*) of an 8-bit sRGB colour (D65 white).
pub fn srgb8_to_lab(c: [u8; 3]) -> [f32; 3] {
    let lin = c.map(|v| {
        let v = v as f32 / 255.0;
        if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
    });
    let x = 0.4124 * lin[0] + 0.3576 * lin[1] + 0.1805 * lin[2];
    let y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2];
    let z = 0.0193 * lin[0] + 0.1192 * lin[1] + 0.9505 * lin[2];
    let f = |t: f32| {
        let d: f32 = 6.0 / 29.0;
        if t > d * d * d { t.cbrt() } else { t / (3.0 * d * d) + 4.0 / 29.0 }
    };
    let (fx, fy, fz) = (f(x / 0.95047), f(y), f(z / 1.08883));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// ΔE*ab between two 8-bit sRGB colours.
pub fn delta_e(a: [u8; 3], b: [u8; 3]) -> f32 {
    let (p, q) = (srgb8_to_lab(a), srgb8_to_lab(b));
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Statistics of a set of per-pixel errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    pub pixels: usize,
    pub mean: f32,
    /// The 95th percentile (nearest rank).
    pub p95: f32,
    pub max: f32,
}

impl ErrorStats {
    pub fn of(values: &[f32]) -> Self {
        if values.is_empty() {
            return ErrorStats::default();
        }
        let mut v = values.to_vec();
        v.sort_by(f32::total_cmp);
        let rank = ((0.95 * v.len() as f64).ceil() as usize).clamp(1, v.len());
        ErrorStats {
            pixels: v.len(),
            mean: (v.iter().map(|&e| e as f64).sum::<f64>() / v.len() as f64) as f32,
            p95: v[rank - 1],
            max: v[v.len() - 1],
        }
    }
}

/// The error image's colour for ΔE `e`: black at 0, red at 10, yellow at
/// 20, white from 40.
pub fn heat(e: f32) -> [u8; 3] {
    let ramp = |a: f32, b: f32| ((e - a) / (b - a)).clamp(0.0, 1.0);
    [ramp(0.0, 10.0), ramp(10.0, 20.0), ramp(20.0, 40.0)].map(|v| (v * 255.0).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cielab_of_known_colours() {
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 0.05);
        assert!(close(srgb8_to_lab([255, 255, 255]), [100.0, 0.0, 0.0]));
        assert!(close(srgb8_to_lab([0, 0, 0]), [0.0, 0.0, 0.0]));
        // sRGB red and mid grey (published values).
        assert!(
            close(srgb8_to_lab([255, 0, 0]), [53.24, 80.09, 67.20]),
            "{:?}",
            srgb8_to_lab([255, 0, 0])
        );
        assert!(
            close(srgb8_to_lab([119, 119, 119]), [50.03, 0.0, 0.0]),
            "{:?}",
            srgb8_to_lab([119, 119, 119])
        );
        assert_eq!(delta_e([10, 200, 30], [10, 200, 30]), 0.0);
        assert!((delta_e([255, 255, 255], [0, 0, 0]) - 100.0).abs() < 0.05);
    }

    #[test]
    fn statistics_of_a_known_set() {
        let v: Vec<f32> = (1..=100).map(|i| i as f32).collect();
        let s = ErrorStats::of(&v);
        assert_eq!((s.pixels, s.p95, s.max), (100, 95.0, 100.0));
        assert!((s.mean - 50.5).abs() < 1e-4);
        assert_eq!(ErrorStats::of(&[]), ErrorStats::default());
        assert_eq!(heat(0.0), [0, 0, 0]);
        assert_eq!(heat(10.0), [255, 0, 0]);
        assert_eq!(heat(50.0), [255, 255, 255]);
    }
}
