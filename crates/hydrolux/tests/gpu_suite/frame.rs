// GPU tests: Whole frames: live edits, determinism and the tone map, golden images, finite pixels everywhere, wgpu errors as render errors.

use super::harness::*;

/// What the viewer's panel does: editing the scene on a live renderer gives
/// the same frame as a renderer made for the edited scene.
#[test]
fn editing_the_scene_live_gives_the_same_image_as_a_fresh_renderer() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let load = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        Scene::load("underwater", &sets).expect("test scene")
    };
    let base = load(&[]);
    let size = (48, 32);
    let edits: &[&[&str]] = &[
        &["water.model=flat"],
        &["water.model=sines", "godrays.method=march"],
        &["render.shadow_resolution=512", "caustics.photons=128", "water.medium=coastal"],
        // The error view's traced water is made after the screen targets.
        &["render.view=error"],
    ];
    let mut live = renderer(&ctx, &base);
    let target = HeadlessTarget::new(&ctx.device, size);
    target.render(&mut live, base.camera(), 3.0).expect("frame");
    for edit in edits {
        let edited = load(edit);
        live.set_scene(&high(&edited)).expect("valid edit");
        let a = target.render(&mut live, edited.camera(), 3.0).expect("frame");
        let mut fresh = renderer(&ctx, &edited);
        let b = target.render(&mut fresh, edited.camera(), 3.0).expect("frame");
        assert_eq!(a, b, "{edit:?}: the live renderer's frame differs from a fresh one");
    }
}

#[test]
fn same_inputs_give_the_same_image_and_the_tone_map_matches_cpu() {
    let s = scene(SMALL_OCEAN);
    let (a, hdr) = render(&s, (48, 32), 7.0);
    let (b, _) = render(&s, (48, 32), 7.0);
    assert_eq!(a, b, "rendering is not deterministic");
    let (c, _) = render(&s, (48, 32), 8.0);
    assert_ne!(a, c, "the sea did not move between t=7 and t=8");
    // Output = sRGB(ACES(hdr)) computed on the CPU, to within rounding.
    for (i, h) in hdr.iter().enumerate() {
        let m = aces_filmic(glam::Vec3::new(h[0], h[1], h[2]));
        for ch in 0..3 {
            let want = (linear_to_srgb(m[ch]) * 255.0).round();
            let got = a[4 * i + ch] as f32;
            assert!((want - got).abs() <= 2.0, "pixel {i} channel {ch}: GPU {got} CPU {want}");
        }
    }
}

/// The time the scenes' goldens show (s): the white water and the
/// interactive water well under way.
const GOLDEN_TIME: f64 = 3.0;

#[test]
fn golden_images() {
    // (A frame at a time is every simulation's catch-up from 0 to it:
    // 3 s, not 10, saves minutes of CI on the software adapters.)
    for (name, sets) in [
        ("ocean", vec![]),
        ("sunset", vec![]),
        ("calm", vec![]),
        ("storm", vec![]),
        ("lake", vec![]),
        ("pool", vec![]),
        ("harbor", vec![]),
    ] {
        let s = Scene::load(name, &sets).expect("built-in");
        let (px, _) = render(&s, (160, 90), GOLDEN_TIME);
        golden::check(name, 160, 90, &px);
    }
}

/// `lake` and `coastal` with `water.method = "raytrace"`: reflections and
/// refractions traced against their terrains and the waves; and the `pool`
/// at 2 s, its ball half under the moving interactive water (its lower half
/// squeezed under the waterline as Snell's law puts it).
#[test]
fn golden_images_ray_traced() {
    for (name, time) in [("lake", GOLDEN_TIME), ("coastal", GOLDEN_TIME), ("pool", 2.0)] {
        let s = Scene::load(name, &["water.method=raytrace".to_string()]).expect("built-in");
        let (px, _) = render(&s, (160, 90), time);
        golden::check(&format!("{name}-raytrace"), 160, 90, &px);
    }
}

/// Golden images of the view from under the water, and of a camera whose
/// lens sits exactly on the moving surface (the waterline across the image).
#[test]
fn golden_images_below_and_half_submerged() {
    let s = Scene::load("underwater", &[]).expect("built-in");
    let (px, _) = render(&s, (160, 90), 10.0);
    golden::check("underwater", 160, 90, &px);

    let mut s = Scene::load("ocean", &["ocean.resolution=128".into()]).expect("built-in");
    let cpu = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), 10.0);
    let y = cpu.height_at(0.0, 0.0);
    s.camera.position = [0.0, y + 0.005, 0.0];
    s.camera.look_at = [0.0, y - 1.0, -20.0];
    let (px, _) = render(&s, (160, 90), 10.0);
    golden::check("half-submerged", 160, 90, &px);
}

/// Goldens of the volume caustics: the `underwater` scene's shafts by the
/// lines and by the march (the plain `underwater` golden has the default,
/// lines, too), and the `water_dragon` (light bent through a water bunny
/// into shafts in the fog and a caustic on the floor).
#[test]
fn golden_images_of_god_rays_and_the_water_dragon() {
    for (name, method) in
        [("underwater-godrays-lines", "lines"), ("underwater-godrays-march", "march")]
    {
        let s = Scene::load(
            "underwater",
            &[format!("godrays.method={method}"), "godrays.resolution=1".into()],
        )
        .expect("built-in");
        let (px, _) = render(&s, (160, 90), 10.0);
        golden::check(name, 160, 90, &px);
    }
    let s =
        Scene::load("water_dragon", &["godrays.object_resolution=192".into()]).expect("built-in");
    let (px, _) = render(&s, (160, 108), 0.0);
    golden::check("water_dragon", 160, 108, &px);
}

#[test]
fn every_pixel_stays_finite_and_bounded_at_any_depth_and_height() {
    // 10 m to 10 km below and above, looking level and up: deep down it is
    // dark (no white Snell's window from overflowing in-scatter), high up
    // the sea and sky keep their radiance; nothing saturates.
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    // One renderer a scene, its camera moved as the viewer's is: every
    // view is of the same state at the same time.
    let target = HeadlessTarget::new(&ctx.device, (24, 16));
    for name in ["underwater", "pool"] {
        let s = Scene::load(name, &[]).expect("scene");
        let mut r = renderer(&ctx, &s);
        for y in [-10_000.0f32, -1000.0, -100.0, -10.0, 10.0, 100.0, 1000.0, 10_000.0] {
            for rise in [-5.0f32, 100.0] {
                let mut camera = s.camera();
                camera.position = glam::Vec3::new(0.0, y, 0.0);
                camera.look_at = glam::Vec3::new(0.0, y + rise, -30.0);
                target.render(&mut r, camera, 1.0).expect("frame");
                let (_, _, px) = r.read_hdr().expect("frame");
                let max = px.iter().flat_map(|p| [p[0], p[1], p[2]]).fold(0.0f32, f32::max);
                assert!(
                    px.iter().all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)),
                    "{name} at y = {y}: a pixel is not a finite radiance"
                );
                assert!(max < 1000.0, "{name} at y = {y}, looking {rise}: {max}");
                if y <= -1000.0 {
                    assert!(max < 1e-3, "{name} {y} m down, looking {rise}: {max} is not dark");
                }
                if y >= 10.0 {
                    assert!(max > 0.1, "{name} {y} m up, looking {rise}: {max} is black");
                }
            }
        }
    }
}

#[test]
fn wgpu_errors_become_one_line_render_errors_and_the_renderer_goes_on() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(&["ocean.resolution=64", "ocean.cascades=1"]);
    let mut r = renderer(&ctx, &s);
    // A target of another format than the renderer was made for: the tone
    // map's pipeline does not match it, and wgpu's validation fails.
    let wrong = ctx.device.create_texture(&hydrolux::wgpu::TextureDescriptor {
        label: Some("wrong format"),
        size: hydrolux::wgpu::Extent3d { width: 32, height: 24, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: hydrolux::wgpu::TextureDimension::D2,
        format: hydrolux::wgpu::TextureFormat::Rgba16Float,
        usage: hydrolux::wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let wrong_view = wrong.create_view(&Default::default());
    let err = hydrolux::catch_gpu_errors(
        &ctx.device,
        || "rendering into a wrong target".into(),
        || {
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            let input = hydrolux::FrameInput {
                target: &wrong_view,
                size: (32, 24),
                camera: s.camera(),
                time: 0.0,
            };
            r.render(&mut encoder, &input);
            ctx.queue.submit([encoder.finish()]);
            Ok(())
        },
    )
    .expect_err("the mismatch is a validation error");
    let message = err.to_string();
    assert!(message.starts_with("GPU error while rendering into a wrong target: "), "{message}");
    eprintln!("{message}");
    assert!(!message.contains('\n') && message.len() > 60, "{message}");
    assert!(ctx.take_error().is_none(), "the scope caught it");
    // Nothing is left broken: the next frame renders.
    let small = HeadlessTarget::new(&ctx.device, (32, 24));
    let px = small.render(&mut r, s.camera(), 0.0).expect("a good frame after a bad one");
    assert!(px.chunks_exact(4).any(|p| p[2] > 20));
    // An error outside any scope is kept for the caller, not a panic.
    let _ = ctx.device.create_texture(&hydrolux::wgpu::TextureDescriptor {
        label: Some("impossible"),
        size: hydrolux::wgpu::Extent3d { width: 0, height: 4, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: hydrolux::wgpu::TextureDimension::D2,
        format: hydrolux::headless::FORMAT,
        usage: hydrolux::wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let uncaught = ctx.take_error().expect("kept");
    assert!(uncaught.contains("impossible") && !uncaught.contains('\n'), "{uncaught}");
}
