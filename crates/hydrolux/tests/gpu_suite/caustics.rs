// GPU tests: Caustic maps against the CPU photon tracer, and caustic shadows.

use super::harness::*;

/// The GPU photon splatting against the CPU tracer (hydrolux_core::caustics)
/// on the same surface: flat water gives T(θ)·cos θ in every cell; under FFT
/// waves the maps agree in pattern (correlation) and in mean (energy).
#[test]
fn floor_caustics_match_the_cpu_photon_tracer() {
    use hydrolux::core::caustics::{PhotonSettings, flat_floor_irradiance, trace_floor_caustics};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let common = [
        "caustics.photons=256",
        "caustics.map_resolution=64",
        "floor.depth=5",
        "sun.elevation_deg=55",
        "ocean.patch_size=16",
    ];

    // Every method is calibrated on flat water.
    for method in ["photons", "beam", "procedural"] {
        let mut flat = common.to_vec();
        let m = format!("caustics.method={method}");
        flat.extend(["water.model=flat", m.as_str()]);
        let s = scene(&flat);
        let mut r = renderer(&ctx, &s);
        r.simulate(&s.camera(), (16, 16), 0.0);
        let (m, map) = r.read_caustics().expect("caustics are on");
        assert_eq!(m, 64);
        let want = flat_floor_irradiance(s.sun_direction(), s.water.ior);
        for v in &map {
            assert!((v - want).abs() < 2e-3, "{method}, flat water: {v} vs {want}");
        }
    }

    let mut waves = common.to_vec();
    waves.extend([
        "ocean.resolution=64",
        "ocean.cascades=1",
        "ocean.wind_speed=6",
        "ocean.fetch_km=20",
        "ocean.choppiness=0.5",
        // The tracer's surface has no foam (its shade is tested on its own).
        "whitewater.foam=false",
    ]);
    let s = scene(&waves);
    let mut r = renderer(&ctx, &s);
    let t = 12.0;
    r.simulate(&s.camera(), (16, 16), t);
    // The simulation clock follows the frame's time in fixed steps.
    assert_eq!(r.simulation_time(), t);
    let (_, gpu_map) = r.read_caustics().expect("caustics are on");
    let fields = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), t);
    let p = PhotonSettings {
        photons_per_side: 256,
        map_resolution: 64,
        patch: [16.0, 16.0],
        floor_depth: 5.0,
        ior: s.water.ior,
        sun_dir: s.sun_direction(),
    };
    let (cpu_map, _) = trace_floor_caustics(|x, z| fields.sample(x as f64, z as f64), &p);
    let cpu_map = cpu_map.blurred().irradiance;
    let (mg, mc, corr) = means_and_correlation(&gpu_map, &cpu_map);
    assert!((mg - mc).abs() < 0.02 * mc, "energy: GPU mean {mg}, CPU mean {mc}");
    assert!(corr > 0.95, "GPU and CPU caustic patterns correlate only {corr}");
    let max = gpu_map.iter().cloned().fold(0.0, f32::max);
    assert!(max > 1.4 * mg, "the waves should focus light: max {max}, mean {mg}");

    // Beams conserve energy too: the same mean as the photons, less what
    // falls between texel centres. At half the map's cells a beam focused
    // under a texel is lost: 2.9% of this sea's light (under 2% with a
    // quarter of the map's cells, whose beams are four texels wide).
    let mut beam = waves.clone();
    beam.push("caustics.method=beam");
    let s = scene(&beam);
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), t);
    let (_, beam_map) = r.read_caustics().expect("caustics are on");
    let mb = beam_map.iter().sum::<f32>() / beam_map.len() as f32;
    assert!((mb - mc).abs() < 0.035 * mc, "beam mean {mb}, photon mean {mc}");

    // Switching the method live (what the viewer's panel does) takes effect
    // on the next frame, and `off` removes the map.
    let mut live = s.clone();
    live.caustics.method = hydrolux::core::scene::CausticMethod::Procedural;
    r.set_scene(&high(&live)).expect("same scene, other method");
    r.simulate(&live.camera(), (16, 16), t);
    let (_, procedural_map) = r.read_caustics().expect("caustics are on");
    assert_ne!(procedural_map, beam_map);
    live.caustics.method = hydrolux::core::scene::CausticMethod::Off;
    r.set_scene(&high(&live)).expect("same scene, caustics off");
    assert!(r.read_caustics().is_none());
}

/// A user's surface (`water.model = "heightfield"`, a .npy), from a scene
/// file with only [water], [floor], [sun] and [caustics]: the GPU photon map
/// matches the CPU tracer on the very same surface.
#[test]
fn caustics_under_a_given_heightfield_match_the_cpu_tracer() {
    use hydrolux::core::caustics::{PhotonSettings, trace_floor_caustics};
    use hydrolux::core::waves::heightfield::Heightfield;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (n, l) = (64usize, 8.0f32);
    let (path, heights) = test_heightfield(n, l, "caustics");
    let text = format!(
        "[water]\nmodel = \"heightfield\"\nheightfield = \"{}\"\nsize = [{l}, {l}]\n[floor]\ndepth = 3.0\n[sun]\nelevation_deg = 60.0\n[caustics]\nphotons = 256\nmap_resolution = 64\n",
        path.display()
    );
    let s = Scene::from_toml(&text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.0);
    let (_, gpu_map) = r.read_caustics().expect("caustics are on");
    let field = Heightfield { nx: n, nz: n, size: [l, l], heights };
    let p = PhotonSettings {
        photons_per_side: 256,
        map_resolution: 64,
        patch: [l, l],
        floor_depth: 3.0,
        ior: s.water.ior,
        sun_dir: s.sun_direction(),
    };
    let cpu_map = trace_floor_caustics(|x, z| field.sample(x, z), &p).0.blurred().irradiance;
    let (mg, mc, corr) = means_and_correlation(&gpu_map, &cpu_map);
    assert!((mg - mc).abs() < 0.02 * mc, "GPU mean {mg}, CPU mean {mc}");
    assert!(corr > 0.97, "correlation {corr}");
    let max = cpu_map.iter().cloned().fold(0.0, f32::max);
    assert!(max > 1.3 * mc, "this surface focuses light: max {max}, mean {mc}");
    let _ = std::fs::remove_file(&path);

    // The update path (a caller's own simulation): new heights are drawn and
    // the caustics follow them on the next frame.
    let moved: Vec<f32> = (0..n * n).map(|i| field.heights[(i + 7 * n + 5) % (n * n)]).collect();
    r.update_heightfield(&moved).expect("same size");
    r.simulate(&s.camera(), (16, 16), 0.0);
    let (_, gpu_moved) = r.read_caustics().expect("caustics are on");
    let field = Heightfield { nx: n, nz: n, size: [l, l], heights: moved };
    let cpu_moved = trace_floor_caustics(|x, z| field.sample(x, z), &p).0.blurred().irradiance;
    let (_, _, corr) = means_and_correlation(&gpu_moved, &cpu_moved);
    assert!(corr > 0.97, "after the update: correlation {corr}");
    let (_, _, stale) = means_and_correlation(&gpu_moved, &gpu_map);
    assert!(stale < 0.9, "the map followed the new surface ({stale} with the old one)");
    let p0 = r.probe_surface(&[[0.0, 0.0]])[0].displacement[1];
    assert!((p0 - field.height(0.0, 0.0)).abs() < 1e-3, "probe {p0}");
    let e = r.update_heightfield(&[0.0; 3]).unwrap_err().to_string();
    assert!(e.contains("got 3 heights, the surface has 64 × 64"), "{e}");
    let e = r.update_heightfield(&vec![f32::NAN; n * n]).unwrap_err().to_string();
    assert!(e.contains("must be finite"), "{e}");
}

/// An object above the water casts a caustic shadow: on the floor in its
/// shadow there is neither sunlight nor its caustic network, beside it both.
#[test]
fn objects_cast_caustic_shadows() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let shadow_x =
        -(1.5 / 60f32.to_radians().tan()) - 4.0 * (30f32.to_radians().sin() / 1.333).asin().tan();
    let text = format!(
        r#"
        [camera]
        position = [{x}, -0.5, 3.0]
        look_at = [{x}, -4.0, 0.0]
        fov_y_deg = 80.0
        [sun]
        elevation_deg = 60.0
        azimuth_deg = 0.0
        [water]
        medium = "pure"
        [ocean]
        wind_speed = 6.0
        fetch_km = 20.0
        patch_size = 16.0
        resolution = 64
        cascades = 1
        [floor]
        depth = 4.0
        [floor.material]
        albedo = [1.0, 1.0, 1.0]
        [caustics]
        photons = 256
        map_resolution = 128
        [[objects]]
        primitive = "box"
        position = [0.0, 1.5, 0.0]
        scale = [2.0, 0.3, 2.0]
    "#,
        x = shadow_x + 1.25
    );
    let s = Scene::from_toml(&text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    let pixel = render_and_project(&ctx, &mut r, &s, (128, 96), 5.0);
    // Statistics of the floor's green channel over a 0.8 m square around (x, z).
    let patch = |x: f32, z: f32| {
        let mut v = Vec::new();
        for i in 0..9 {
            for j in 0..9 {
                v.push(
                    pixel(glam::Vec3::new(
                        x + (i as f32 - 4.0) * 0.1,
                        -4.0,
                        z + (j as f32 - 4.0) * 0.1,
                    ))[1],
                );
            }
        }
        let mean = v.iter().sum::<f32>() / v.len() as f32;
        let sd = (v.iter().map(|a| (a - mean) * (a - mean)).sum::<f32>() / v.len() as f32).sqrt();
        (mean, sd)
    };
    let (shaded, shaded_sd) = patch(shadow_x, 0.0);
    let (lit, lit_sd) = patch(shadow_x + 2.5, 0.0);
    assert!(shaded < 0.5 * lit, "the shadow is not darker: {shaded} vs {lit}");
    assert!(
        lit_sd > 3.0 * shaded_sd,
        "caustics should ripple in the light ({lit_sd}) and not in the shadow ({shaded_sd})"
    );
}
