// GPU tests: The sky cube map against the Preetham model.

use super::harness::*;

#[test]
fn sky_cube_map_matches_preetham_in_every_direction() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(&["sun.elevation_deg=30", "sun.azimuth_deg=40"]);
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (64, 64), 0.0);
    let params = SkyParams::new(s.sun_direction(), s.sky.turbidity);
    let dirs: Vec<[f32; 3]> = (0..200)
        .map(|i| {
            let (a, b) = (i as f32 * 0.7137, (i as f32 * 0.3911).sin() * 0.9);
            [a.cos() * (1.0 - b * b).sqrt(), b, a.sin() * (1.0 - b * b).sqrt()]
        })
        .collect();
    for (d, g) in dirs.iter().zip(r.probe_sky(&dirs)) {
        let c = sky_radiance(&params, glam::Vec3::from(*d));
        for i in 0..3 {
            // Bilinear lookup in a 128² face against the exact model.
            assert!((g[i] - c[i]).abs() < 0.03 * c[i].max(0.2), "dir {d:?}: cube {g:?} model {c}");
        }
    }
}
