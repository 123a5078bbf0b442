// GPU tests: The surface models on the GPU against their CPU twins: the FFT ocean, height queries, sines.

use super::harness::*;

#[test]
fn gpu_fft_ocean_matches_cpu_reference() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(SMALL_OCEAN);
    let mut r = renderer(&ctx, &s);
    // A large time too: the phase must stay exact after hours.
    for t in [0.0, 123.45, 9.0 * 3600.0 + 0.3] {
        r.simulate(&s.camera(), (64, 64), t);
        let gpu = r.read_ocean_fields().expect("fft model");
        let cpu = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), t).texels;
        assert_eq!(gpu.len(), cpu.len());
        for field in 0..8 {
            let scale = cpu.iter().map(|t| t[field].abs()).fold(0.0f32, f32::max).max(1e-6);
            let worst = gpu
                .iter()
                .zip(&cpu)
                .map(|(g, c)| (g[field] - c[field]).abs())
                .fold(0.0f32, f32::max);
            assert!(
                worst < 2e-4 * scale + 1e-6,
                "t={t} field {field}: max error {worst} vs scale {scale}"
            );
        }
    }
}

#[test]
fn rendered_surface_and_height_queries_match_cpu() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(SMALL_OCEAN);
    let mut r = renderer(&ctx, &s);
    let t = 42.0;
    r.simulate(&s.camera(), (64, 64), t);
    let cpu = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), t);
    let points: Vec<[f32; 2]> =
        (0..64).map(|i| [i as f32 * 7.31 - 200.0, i as f32 * -3.17 + 50.0]).collect();
    let probed = r.probe_surface(&points);
    let hmax = cpu.texels.iter().map(|t| t[1].abs()).fold(0.0f32, f32::max);
    for (p, g) in points.iter().zip(&probed) {
        let c = cpu.sample(p[0] as f64, p[1] as f64);
        for i in 0..3 {
            // Textures are half floats: about 3 significant digits.
            assert!(
                (g.displacement[i] - c.displacement[i]).abs() < 2e-3 * hmax + 1e-3,
                "{p:?}[{i}]: {} vs {}",
                g.displacement[i],
                c.displacement[i]
            );
        }
        assert!(
            (g.normal() - c.normal()).length() < 5e-3,
            "{p:?}: normal {} vs {}",
            g.normal(),
            c.normal()
        );
    }
    for p in points.iter().take(6) {
        let (gh, ch) = (r.height_at(p[0], p[1]), cpu.height_at(p[0] as f64, p[1] as f64));
        assert!((gh - ch).abs() < 5e-3 * hmax + 2e-3, "height_at{p:?}: GPU {gh} CPU {ch}");
    }
}

#[test]
fn sines_model_matches_cpu_analytic_waves() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(&["water.model=sines", "sines.count=16", "sines.gerstner=0.8"]);
    let mut r = renderer(&ctx, &s);
    let t = 3600.0 * 5.0 + 1.25;
    r.simulate(&s.camera(), (64, 64), t);
    let waves = SineWaves::from_sea_state(&s.sea_state(), 16, s.ocean.seed, 0.8);
    let points: Vec<[f32; 2]> = (0..40).map(|i| [i as f32 * 3.7, i as f32 * -2.9]).collect();
    for (p, g) in points.iter().zip(r.probe_surface(&points)) {
        let c = waves.sample(p[0] as f64, p[1] as f64, t);
        for i in 0..3 {
            assert!(
                (g.displacement[i] - c.displacement[i]).abs() < 1e-3,
                "{p:?}: {:?} vs {:?}",
                g.displacement,
                c.displacement
            );
        }
        assert!((g.slope[0] - c.slope[0]).abs() < 1e-3 && (g.slope[1] - c.slope[1]).abs() < 1e-3);
    }
}
