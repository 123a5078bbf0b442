//! Exposure and filmic tone mapping. The CPU twin of `shaders/tonemap.wgsl`.
//!
//! Exposure is a photographic EV100 (the scene's `render.exposure`): a pixel
//! of luminance L cd/m² maps to L / (1.2 · 2^EV) before the curve (the
//! "saturation-based" camera model; sunny daylight is about EV 15). The curve is
//! Stephen Hill's fit of the ACES RRT + sRGB ODT.

use glam::{Mat3, Vec3};

/// Linear scale from scene radiance (kcd/m²) to the tone curve's input.
pub fn exposure_scale(ev100: f32) -> f32 {
    1000.0 / (1.2 * 2f32.powf(ev100))
}

const ACES_IN: Mat3 = Mat3::from_cols_array(&[
    0.59719, 0.07600, 0.02840, 0.35458, 0.90834, 0.13383, 0.04823, 0.01566, 0.83777,
]);
const ACES_OUT: Mat3 = Mat3::from_cols_array(&[
    1.60475, -0.10208, -0.00327, -0.53108, 1.10813, -0.07276, -0.07367, -0.00605, 1.07602,
]);

fn rrt_odt_fit(v: Vec3) -> Vec3 {
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.432951) + 0.238081;
    a / b
}

/// ACES filmic curve on linear sRGB, output clamped to [0, 1] (linear).
pub fn aces_filmic(color: Vec3) -> Vec3 {
    (ACES_OUT * rrt_odt_fit(ACES_IN * color)).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Linear → sRGB transfer function.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filmic_curve_is_monotonic_black_to_white() {
        assert!(aces_filmic(Vec3::ZERO).length() < 1e-3);
        assert!(aces_filmic(Vec3::splat(100.0)).min_element() > 0.99);
        let mut last = 0.0;
        for i in 1..200 {
            let v = aces_filmic(Vec3::splat(i as f32 * 0.05)).y;
            assert!(v >= last);
            last = v;
        }
        // ACES puts scene mid grey 0.18 at about 0.1 linear (0.36 sRGB).
        let g = aces_filmic(Vec3::splat(0.18)).y;
        assert!((0.09..0.13).contains(&g), "{g}");
    }

    #[test]
    fn sunny_sixteen_exposure_puts_daylight_sky_in_range() {
        // An 8 kcd/m² sky at EV 15 maps to ≈0.2.
        let v = 8.0 * exposure_scale(15.0);
        assert!((0.15..0.25).contains(&v), "{v}");
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
    }
}
