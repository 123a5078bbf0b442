// GPU tests: God rays: tubes and buffer against the CPU twin, flat water's closed form, shafts from the waves.

use super::harness::*;

/// The god-ray tubes and buffer against the CPU twin (hydrolux_core::godrays)
/// under a given heightfield: every tube's entry point, direction and flux,
/// then the buffer texel by texel where the view ray ends on the flat floor.
#[test]
fn god_ray_tubes_and_ribbons_match_the_cpu_twin() {
    use hydrolux::core::godrays::{
        BeamTube, TubeRegion, beam_tubes, deepest_needed, ribbons_along_ray,
    };
    use hydrolux::core::medium::UnderwaterLight;
    use hydrolux::core::waves::heightfield::Heightfield;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (n, l) = (64usize, 8.0f32);
    let (path, heights) = test_heightfield(n, l, "godrays");
    let text = format!(
        "[water]\nmodel = \"heightfield\"\nheightfield = \"{}\"\nsize = [{l}, {l}]\nmedium = \"clear_ocean\"\n[floor]\ndepth = 3.0\n[sun]\nelevation_deg = 65.0\n\
         [camera]\nposition = [0.0, -1.0, 0.0]\nlook_at = [1.0, -2.2, -4.0]\n[godrays]\nphotons = 96\ndistance = 6.0\nresolution = 1.0\n",
        path.display()
    );
    let s = Scene::from_toml(&text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    let size = (64u32, 40u32);
    HeadlessTarget::new(&ctx.device, size).render(&mut r, s.camera(), 0.0).expect("frame");
    let gpu_tubes = r.read_godray_tubes();
    let field = Heightfield { nx: n, nz: n, size: [l, l], heights };
    let eye = s.camera().position;
    let sun = s.sun_direction();
    let travel =
        UnderwaterLight::new(sun, glam::Vec3::ONE, glam::Vec3::ZERO, s.water.ior).sun_travel;
    let region = TubeRegion::around(eye, travel, 6.0);
    let cpu = beam_tubes(
        |x, z| field.sample(x, z),
        &region,
        96,
        sun,
        s.water.ior,
        Some(3.0),
        deepest_needed(eye, 6.0),
    );
    assert_eq!(cpu.len(), 96 * 96, "every photon of this gentle surface enters the water");
    let mut drawn = Vec::new();
    for (g, c) in gpu_tubes.iter().zip(&cpu) {
        let start = glam::Vec3::new(g[0], g[1], g[2]);
        assert!((start - c.start).length() < 2e-3, "start {start} vs {}", c.start);
        if g[7] > 0.0 {
            let dir = glam::Vec3::new(g[4], g[5], g[6]);
            assert!((dir - c.dir).length() < 2e-3, "dir {dir} vs {}", c.dir);
            assert!((g[7] / c.flux - 1.0).abs() < 5e-3, "flux {} vs {}", g[7], c.flux);
            assert!((g[3] / c.length - 1.0).abs() < 5e-3, "length {} vs {}", g[3], c.length);
            drawn.push(BeamTube { start, dir, length: g[3], flux: g[7] });
        }
    }
    assert!(drawn.len() > 1000, "only {} tubes pass near the eye", drawn.len());

    // The buffer: texels whose ray goes down to the floor unobstructed.
    let (w, h, buffer) = r.read_godrays().expect("rendered");
    assert_eq!((w, h), size);
    let vp_inv = s.camera().view_projection(size.0 as f32 / size.1 as f32).inverse();
    let medium = s.medium();
    let sun_e = {
        let sky = s.sky_params();
        glam::Vec3::from_slice(&sky.sun_illuminance[..3])
            * hydrolux::core::tonemap::exposure_scale(s.render.exposure)
    };
    let spacing = region.spacing(96);
    let (mut ratios, mut checked) = (Vec::new(), 0);
    for y in (2..h - 2).step_by(3) {
        for x in (2..w - 2).step_by(3) {
            let ndc = glam::Vec2::new(
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            );
            let far = vp_inv.project_point3(ndc.extend(0.5));
            let view = (far - eye).normalize();
            if view.y > -0.05 {
                continue;
            }
            let s_floor = (3.0 + eye.y) / -view.y;
            let want = ribbons_along_ray(
                &medium,
                s.water.phase_g,
                &drawn,
                spacing,
                eye,
                view,
                s_floor.min(6.0),
            ) * sun_e;
            let got = buffer[(y * w + x) as usize];
            checked += 1;
            ratios.push(got[2] / want.z);
        }
    }
    assert!(checked > 40, "{checked} texels checked");
    ratios.sort_by(|a, b| a.total_cmp(b));
    let median = ratios[ratios.len() / 2];
    let p90 = ratios[ratios.len() * 9 / 10];
    let p10 = ratios[ratios.len() / 10];
    assert!((median - 1.0).abs() < 0.03, "median GPU/CPU {median}");
    assert!(p10 > 0.9 && p90 < 1.1, "10th–90th percentile GPU/CPU {p10}–{p90}");
    let _ = std::fs::remove_file(&path);
}

/// Flat water is a slab: its tubes are parallel and evenly spaced, so the
/// shafts must vanish into the uniform in-scattering — the lines, the march
/// and no god rays at all give the same image, pixel by pixel.
#[test]
fn flat_water_has_no_shafts_and_every_method_gives_the_closed_form() {
    let base = [
        "water.model=flat",
        "water.medium=clear_ocean",
        "floor.depth=8",
        "sun.elevation_deg=55",
        "godrays.distance=12",
        "godrays.photons=192",
    ];
    let image = |method: &str, position: [f32; 3], look_at: [f32; 3]| {
        let mut sets: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        sets.push(format!("godrays.method={method}"));
        let mut s = Scene::load("ocean", &sets).expect("scene");
        s.camera.position = position;
        s.camera.look_at = look_at;
        render(&s, (64, 40), 0.0).1
    };
    let off = image("off", [0.0, -3.0, 0.0], [0.0, -4.0, -10.0]);
    for method in ["lines", "march"] {
        let with = image(method, [0.0, -3.0, 0.0], [0.0, -4.0, -10.0]);
        let mut rel: Vec<f32> = off.iter().zip(&with).map(|(a, b)| (b[2] - a[2]) / a[2]).collect();
        let mean = rel.iter().sum::<f32>() / rel.len() as f32;
        rel.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
        let p95 = rel[rel.len() * 95 / 100].abs();
        assert!(mean.abs() < 0.02, "{method}: mean relative difference {mean}");
        assert!(p95 < 0.06, "{method}: 95th percentile of |relative difference| {p95}");
    }
    // Seen from above, the water shader marches the shafts along refracted
    // paths; over flat water they too vanish into the closed form.
    let (from, to) = ([0.0, 3.0, 6.0], [0.0, -4.0, -8.0]);
    let off = image("off", from, to);
    let with = image("lines", from, to);
    let worst =
        off.iter().zip(&with).map(|(a, b)| ((b[2] - a[2]) / a[2]).abs()).fold(0.0f32, f32::max);
    assert!(worst < 0.03, "from above: worst relative difference {worst}");
}

/// Under FFT waves the shafts are real focusing: the buffer varies across
/// the image far more than under flat water, and it changes as the waves move.
#[test]
fn god_rays_come_from_the_waves_and_move_with_them() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let buffer_at = |model: &str, t: f64| {
        let mut sets: Vec<String> = SMALL_OCEAN.iter().map(|s| s.to_string()).collect();
        sets.extend([
            format!("water.model={model}"),
            "water.medium=clear_ocean".into(),
            "floor.depth=10".into(),
            "sun.elevation_deg=60".into(),
        ]);
        sets.extend(["godrays.photons=192".into(), "godrays.distance=12".into()]);
        let mut s = Scene::load("ocean", &sets).expect("scene");
        s.camera.position = [0.0, -4.0, 0.0];
        s.camera.look_at = [0.0, -4.5, -10.0];
        let mut r = renderer(&ctx, &s);
        HeadlessTarget::new(&ctx.device, (64, 40)).render(&mut r, s.camera(), t).expect("frame");
        r.read_godrays().expect("rendered").2.iter().map(|p| p[2]).collect::<Vec<f32>>()
    };
    // Relative spread between neighbouring columns of the middle row band.
    let ripple = |b: &[f32]| {
        let (w, rows) = (32usize, 12..18usize);
        let mut sum = 0.0;
        for y in rows.clone() {
            for x in 1..w {
                let (a, c) = (b[y * w + x - 1], b[y * w + x]);
                sum += ((c - a) / (0.5 * (a + c)).max(1e-9)).abs();
            }
        }
        sum / (rows.len() * (w - 1)) as f32
    };
    let flat = buffer_at("flat", 0.0);
    let waves = buffer_at("fft", 0.0);
    let later = buffer_at("fft", 1.5);
    let (rf, rw) = (ripple(&flat), ripple(&waves));
    assert!(rw > 4.0 * rf, "waves ripple {rw}, flat {rf}");
    // The shafts' pattern (differences between neighbouring columns, which
    // removes the smooth in-scattering they ride on) decorrelates.
    let pattern = |b: &[f32]| {
        b.windows(2)
            .enumerate()
            .filter(|(i, _)| i % 32 != 31)
            .map(|(_, p)| p[1] - p[0])
            .collect::<Vec<f32>>()
    };
    let (_, _, same) = means_and_correlation(&pattern(&waves), &pattern(&buffer_at("fft", 0.0)));
    let (_, _, moved) = means_and_correlation(&pattern(&waves), &pattern(&later));
    assert!(same > 0.999, "the same instant renders the same shafts: {same}");
    assert!(
        moved < 0.5,
        "the shafts should move: pattern correlation {moved} between t = 0 and 1.5 s"
    );
}
