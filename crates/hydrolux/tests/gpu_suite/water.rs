// GPU tests: Shading the water: Fresnel, the flat-water optics, local reflections and refractions, shadows through the surface, the per-pixel medium, Snell's window.

use super::harness::*;
use hydrolux::core::optics::FresnelMode;

/// The shaders' Fresnel modes in their WGSL order, the power mode with the
/// exponent [`probing_renderer`] sets.
const FRESNEL_MODES: [FresnelMode; 4] =
    [FresnelMode::Exact, FresnelMode::Schlick, FresnelMode::JensenGolias, FresnelMode::Power(3.5)];

/// A renderer whose frame uniforms are set (`water.fresnel_power` = 3.5),
/// for the probes that evaluate the shaders' optics.
fn probing_renderer(ctx: &GpuContext) -> (Scene, Renderer) {
    let mut sets = SMALL_OCEAN.to_vec();
    sets.push("water.fresnel_power=3.5");
    let s = scene(&sets);
    let mut r = renderer(ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.0);
    (s, r)
}

#[test]
fn shader_fresnel_matches_cpu_optics_in_every_mode() {
    use hydrolux::core::optics::fresnel;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (_, r) = probing_renderer(&ctx);
    let mut queries = Vec::new();
    for i in 0..=90 {
        let c = (i as f32).to_radians().cos();
        for (n1, n2) in [(1.0, 1.333), (1.333, 1.0), (1.0, 1.5)] {
            queries.push((c, n1, n2));
        }
    }
    let modes = FRESNEL_MODES;
    for (q, g) in queries.iter().zip(r.probe_fresnel(&queries)) {
        for (m, got) in modes.iter().zip(g) {
            let want = fresnel(*m, q.0, q.1, q.2);
            assert!((got - want).abs() < 1e-5, "{m:?} {q:?}: GPU {got} CPU {want}");
        }
    }
}

/// A camera straight above flat water over a white floor: the centre pixel
/// must be what the optics predict (hydrolux_core::medium::FlatWaterView):
/// Fresnel-weighted sky, and the floor's light and the water's in-scattering
/// attenuated along the path and divided by n² on the way out.
#[test]
fn flat_water_over_a_white_floor_matches_the_optics() {
    use hydrolux::core::medium::{FlatWaterView, UnderwaterLight};
    use hydrolux::core::sky::sky_irradiance_up;
    use hydrolux::core::tonemap::exposure_scale;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let cases = [
        ("clear_ocean", 2.0f32, "depth"),
        ("coastal", 2.0, "depth"),
        ("clear_ocean", 8.0, "depth"),
        ("turbid_harbor", 1.0, "depth"),
        ("pure", 3.0, "depth"),
        ("coastal", 3.0, "plane"),
        ("coastal", 3.0, "simple"),
        // Ray traced (water.method = "raytrace"): the same light, exactly.
        ("clear_ocean", 8.0, "raytrace"),
        ("turbid_harbor", 1.0, "raytrace"),
        ("coastal", 3.0, "raytrace"),
    ];
    for (medium, depth, mode) in cases {
        let lookup = if mode == "plane" { "plane" } else { "depth" };
        let optics = if mode == "simple" { "simple" } else { "physical" };
        let method = if mode == "raytrace" { "raytrace" } else { "projective" };
        let sets = [
            format!("water.method={method}"),
            format!("water.refraction={lookup}"),
            format!("water.refraction_depth={depth}"),
            format!("water.optics={optics}"),
            "water.model=flat".to_string(),
            "ocean.wind_speed=0.5".to_string(),
            format!("water.medium={medium}"),
            format!("floor.depth={depth}"),
            "floor.material.albedo=[1, 1, 1]".to_string(),
            "sun.elevation_deg=50".to_string(),
            "camera.position=[0, 5, 0]".to_string(),
            "camera.look_at=[0, 0, 0]".to_string(),
            "camera.up=[0, 0, -1]".to_string(),
        ];
        let s = Scene::load("ocean", &sets).expect("valid scene");
        let mut r = renderer(&ctx, &s);
        let target = HeadlessTarget::new(&ctx.device, (33, 33));
        target.render(&mut r, s.camera(), 0.0).expect("frame");
        let (w, _, hdr) = r.read_hdr().expect("rendered");
        let got = hdr[16 * w as usize + 16];

        let params = s.sky_params();
        let sky = Sky::new(params);
        let exposure = exposure_scale(s.render.exposure);
        let sun = glam::Vec3::from_slice(&params.sun_illuminance[..3]) * exposure;
        let light = UnderwaterLight::new(
            s.sun_direction(),
            sun,
            sky_irradiance_up(&sky) * exposure,
            s.water.ior,
        );
        let m = s.medium();
        let view = FlatWaterView {
            medium: &m,
            light: &light,
            ior: s.water.ior,
            phase_g: s.water.phase_g,
            floor_depth: Some(depth),
            floor_albedo: glam::Vec3::ONE,
        };
        let sky_up = sky.radiance(glam::Vec3::Y) * exposure;
        let want = if optics == "simple" {
            use hydrolux::core::medium::simple_water_colour;
            use hydrolux::core::optics::fresnel_exact;
            let floor = light.irradiance(&m, depth, glam::Vec3::Y, 1.0) / std::f32::consts::PI;
            let e_down = sky_irradiance_up(&sky) * exposure + sun * s.sun_direction().y;
            let water = glam::Vec3::from(s.water.body_color) * e_down / std::f32::consts::PI;
            let f = fresnel_exact(1.0, 1.0, s.water.ior);
            f * sky_up
                + (1.0 - f) * simple_water_colour(floor, water, depth, s.water.simple_attenuation)
        } else {
            view.radiance(glam::Vec3::NEG_Y, sky_up)
        };
        for c in 0..3 {
            // Half-float targets and a mip-blurred sky: within 3%.
            assert!(
                (got[c] - want[c]).abs() < 0.03 * want[c] + 2e-3,
                "{medium} at {depth} m ({mode}), channel {c}: GPU {} CPU {}",
                got[c],
                want[c]
            );
        }
    }
}

/// A red box above flat water, its sunlit face towards the camera, is seen
/// mirrored where the mirror image of that face projects (the local
/// reflection), and water elsewhere reflects the sky.
#[test]
fn local_reflection_shows_objects_above_the_water() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let text = r#"
        [camera]
        position = [0.0, 2.0, 10.0]
        look_at = [0.0, -0.5, 0.0]
        [sun]
        elevation_deg = 20.0
        azimuth_deg = 90.0
        [water]
        model = "flat"
        [ocean]
        wind_speed = 0.5
        [[objects]]
        primitive = "box"
        position = [0.0, 1.2, 0.0]
        scale = [1.5, 2.0, 1.5]
        [objects.material]
        albedo = [0.9, 0.02, 0.02]
    "#;
    let s = Scene::from_toml(text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    let pixel = render_and_project(&ctx, &mut r, &s, (96, 64), 0.0);
    let face = pixel(glam::Vec3::new(0.0, 1.2, 0.75));
    assert!(face[0] > 3.0 * face[1], "the box's face is not red: {face:?}");
    let image = pixel(glam::Vec3::new(0.0, -1.2, 0.75));
    assert!(
        image[0] > 3.0 * image[1] && image[0] > 3.0 * image[2],
        "mirror image is not red: {image:?}"
    );
    let beside = pixel(glam::Vec3::new(3.0, 0.0, 0.0));
    assert!(beside[2] > beside[0], "open water should reflect the blue sky: {beside:?}");
}

/// A box above flat water casts its shadow through the surface onto the
/// floor, displaced along the refracted sunlight; nothing above the water
/// appears in the refraction texture.
#[test]
fn objects_shadow_the_floor_through_the_water_and_stay_out_of_the_refraction() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    // Sun 60° up towards +x: in air the shadow moves 1.5/tan 60° = 0.87 m
    // towards −x, in 1 m of water another tan(asin(sin 30°/1.333)) = 0.41 m.
    let shadow_x =
        -(1.5 / 60f32.to_radians().tan()) - (30f32.to_radians().sin() / 1.333).asin().tan();
    let text = format!(
        r#"
        [camera]
        position = [{shadow_x}, 6.0, 6.0]
        look_at = [{shadow_x}, -1.0, 0.0]
        [sun]
        elevation_deg = 60.0
        azimuth_deg = 0.0
        [water]
        model = "flat"
        medium = "pure"
        [ocean]
        wind_speed = 0.5
        [floor]
        depth = 1.0
        [floor.material]
        albedo = [1.0, 1.0, 1.0]
        [[objects]]
        primitive = "box"
        position = [0.0, 1.5, 0.0]
        scale = [0.8, 0.8, 0.8]
        [objects.material]
        albedo = [0.9, 0.02, 0.02]
    "#
    );
    let s = Scene::from_toml(&text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    let size = (96, 64);
    let pixel = render_and_project(&ctx, &mut r, &s, size, 0.0);
    // Floor points seen through flat water appear where their refracted rays
    // leave the surface; compare two floor points at equal distance instead
    // of predicting pixels: the one in the shadow is much darker.
    let shaded = pixel(glam::Vec3::new(shadow_x, -0.6, 0.0));
    let lit = pixel(glam::Vec3::new(shadow_x + 2.5, -0.6, 0.0));
    assert!(shaded[1] < 0.6 * lit[1], "no shadow on the floor: shaded {shaded:?} lit {lit:?}");

    // The refraction texture (debug view) holds no trace of the red box.
    let mut sr = s.clone();
    sr.render.view = hydrolux::core::scene::DebugView::Refraction;
    r.set_scene(&high(&sr)).expect("same scene");
    let px = HeadlessTarget::new(&ctx.device, size).render(&mut r, s.camera(), 0.0).expect("frame");
    let reddish = px.chunks_exact(4).filter(|p| p[0] as i32 > 2 * p[1] as i32 + 20).count();
    assert_eq!(reddish, 0, "objects above the water leaked into the refraction texture");
}

/// The stencil classification of each pixel's medium (seed 000 §4.2) against
/// a CPU test of the same question: is the pixel's near-plane point under the
/// wavy surface? Cameras well above, well below, and exactly at the surface
/// (where the waterline crosses the image).
#[test]
fn pixel_medium_matches_a_cpu_heightfield_test() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let t = 31.0;
    let base = scene(SMALL_OCEAN);
    let cpu = OceanFields::evaluate(&OceanSpectrum::new(&base.ocean_settings()), t);
    let (x0, z0) = (3.0f32, -2.0f32);
    let surface = cpu.height_at(x0 as f64, z0 as f64);
    let size = (64, 48);
    for (offset, expect) in [(0.4f32, "air"), (-0.4, "water"), (0.004, "both")] {
        let mut s = base.clone();
        s.camera.position = [x0, surface + offset, z0];
        s.camera.look_at = [x0, surface + offset - 0.3, z0 - 10.0];
        let mut r = renderer(&ctx, &s);
        let target = HeadlessTarget::new(&ctx.device, size);
        target.render(&mut r, s.camera(), t).expect("frame");
        let (w, h, medium) = r.read_medium().expect("rendered");
        let inv = s.camera().view_projection(w as f32 / h as f32).inverse();
        let (mut water, mut mismatched_far_from_waterline) = (0, 0);
        let mut cpu_water = vec![false; (w * h) as usize];
        for y in 0..h {
            for x in 0..w {
                let ndc = glam::Vec2::new(
                    (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                );
                // Reversed Z: the near plane is at depth 1.
                let p = inv.project_point3(ndc.extend(1.0));
                cpu_water[(y * w + x) as usize] = p.y < cpu.height_at(p.x as f64, p.z as f64);
            }
        }
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let gpu_water = medium[i] == 1;
                water += gpu_water as usize;
                if gpu_water != cpu_water[i] {
                    // Allow disagreement only right at the waterline (half-float
                    // heights, mesh interpolation): a CPU neighbour within 2 rows differs.
                    let near_line = (y.saturating_sub(2)..(y + 3).min(h))
                        .any(|yy| cpu_water[(yy * w + x) as usize] != cpu_water[i]);
                    if !near_line {
                        mismatched_far_from_waterline += 1;
                    }
                }
            }
        }
        let all = (w * h) as usize;
        match expect {
            "air" => assert_eq!(water, 0, "camera {offset} m above the surface"),
            "water" => assert_eq!(water, all, "camera {offset} m below the surface"),
            _ => assert!(
                water > all / 10 && water < all * 9 / 10,
                "no waterline across the image: {water} of {all} in water"
            ),
        }
        assert_eq!(
            mismatched_far_from_waterline, 0,
            "camera at {offset}: GPU and CPU disagree away from the waterline"
        );
    }
}

/// From under flat, clear water looking straight up, the sky shows through a
/// disc of angular radius equal to the critical angle (48.6°, Snell's
/// window); beyond it the surface reflects the dark deep water.
#[test]
fn snells_window_has_the_critical_angle_and_total_reflection_outside() {
    use hydrolux::core::optics::{IOR_AIR, IOR_WATER, critical_angle};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    // Projective and ray traced alike.
    for method in ["projective", "raytrace"] {
        let method_set = format!("water.method={method}");
        let sets = [
            "water.model=flat",
            "ocean.wind_speed=0",
            "water.medium=pure",
            "sun.elevation_deg=89",
            "camera.position=[0, -1, 0]",
            "camera.look_at=[0, 10, 0]",
            "camera.up=[0, 0, -1]",
            "camera.fov_y_deg=130",
            &method_set,
        ];
        let s = scene(&sets);
        let mut r = renderer(&ctx, &s);
        let n = 161u32;
        let target = HeadlessTarget::new(&ctx.device, (n, n));
        target.render(&mut r, s.camera(), 0.0).expect("frame");
        let (w, _, hdr) = r.read_hdr().expect("rendered");
        let half_tan = (65f32).to_radians().tan();
        // Luminance against the angle from the zenith along the centre row.
        let profile: Vec<(f32, f32)> = (n / 2..n)
            .map(|x| {
                let ndc = (x as f32 + 0.5) / n as f32 * 2.0 - 1.0;
                let angle = (ndc * half_tan).atan().to_degrees();
                let p = hdr[(n / 2 * w + x) as usize];
                (angle, 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
            })
            .collect();
        let at = |deg: f32| {
            profile
                .iter()
                .min_by(|a, b| (a.0 - deg).abs().total_cmp(&(b.0 - deg).abs()))
                .expect("profile")
                .1
        };
        let critical = critical_angle(IOR_WATER, IOR_AIR).expect("water is denser").to_degrees();
        let inside = at(critical - 6.0);
        let outside = at(critical + 3.0);
        assert!(inside > 8.0 * outside, "window {inside} vs reflection {outside}");
        // The edge: where the luminance first falls below a quarter of the window's.
        let edge = profile.iter().find(|p| p.0 > 10.0 && p.1 < 0.25 * inside).expect("an edge").0;
        assert!(
            (edge - critical).abs() < 2.0,
            "{method}: window edge at {edge}°, critical angle {critical}°"
        );
        assert!(inside > 8.0 * outside, "{method}: window {inside} vs reflection {outside}");
    }
}

/// The far sea's BRDF as the water pass evaluates it (`shaders/sea_brdf.wgsl`)
/// against its CPU twin (`hydrolux_core::waves::sea_brdf`): the mean Fresnel
/// over a pixel's visible facets, the direction the sky is looked up about,
/// and the sun's glitter, from grazing to steep views, rough and smooth, in
/// every Fresnel mode.
#[test]
fn the_far_seas_brdf_matches_the_cpu_twin() {
    use glam::DVec3;
    use hydrolux::SeaBrdfQuery;
    use hydrolux::core::optics::fresnel;
    use hydrolux::core::waves::sea_brdf::{SlopeStatistics, filtered_reflection, sun_glitter};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (s, r) = probing_renderer(&ctx);
    let dir = |elevation: f64, azimuth: f64| {
        let e = elevation.to_radians();
        DVec3::new(e.cos() * azimuth.cos(), e.sin(), e.cos() * azimuth.sin())
    };
    let modes = FRESNEL_MODES;
    let mut queries = Vec::new();
    let mut cases = Vec::new();
    for (i, elevation) in [1.0, 3.0, 8.0, 20.0, 50.0, 85.0].into_iter().enumerate() {
        for (j, variance) in [[0.001, 0.001], [0.02, 0.008], [0.06, 0.03]].into_iter().enumerate() {
            for (k, mean) in [[0.0, 0.0], [0.12, -0.05]].into_iter().enumerate() {
                let v = dir(elevation, 0.3 + i as f64);
                // The sun ahead of the eye, a little off the mirror direction.
                let l = dir(
                    10.0 + 7.0 * j as f64,
                    0.3 + i as f64 + std::f64::consts::PI + 0.1 * k as f64,
                );
                let mode = (i + j + k) % 4;
                cases.push((v, l, SlopeStatistics { mean, variance }, mode));
                queries.push(SeaBrdfQuery {
                    view: v.as_vec3().into(),
                    sun: l.as_vec3().into(),
                    mean_slope: [mean[0] as f32, mean[1] as f32],
                    variance: [variance[0] as f32, variance[1] as f32],
                    mode: mode as u32,
                    ior: s.water.ior,
                });
            }
        }
    }
    let got = r.probe_sea_brdf(&queries);
    for ((v, l, stats, mode), g) in cases.iter().zip(got) {
        let f = |c: f64| fresnel(modes[*mode], c as f32, 1.0, s.water.ior) as f64;
        let want = filtered_reflection(*v, stats, f);
        let glitter = sun_glitter(*v, *l, stats, f);
        let direction = DVec3::new(g[1] as f64, g[2] as f64, g[3] as f64);
        assert!(
            (g[0] as f64 - want.fresnel).abs() < 1e-4 + 1e-3 * want.fresnel
                && (direction - want.direction).length() < 1e-3
                && (g[4] as f64 - glitter).abs() < 1e-4 + 2e-3 * glitter,
            "v {v:?}, l {l:?}, {stats:?}, {:?}: GPU {g:?}, CPU {} {:?} {glitter}",
            modes[*mode],
            want.fresnel,
            want.direction
        );
    }
}

/// Issue #32 item 4: a distant band of sea averages to the same radiance
/// whether its waves are resolved (512×288) or sixteen times below a pixel
/// (32×18): the BRDF of the filtered slopes stands in for the facets. With
/// the mean normal's mirror the coarse band was 10–35% brighter.
#[test]
fn a_distant_sea_looks_the_same_resolved_or_filtered() {
    let s = Scene::load("ocean", &[]).expect("valid scene");
    let (lo, hi) = ((32u32, 18u32), (512u32, 288u32));
    let scale = (hi.0 / lo.0) as usize;
    let fine = render(&s, hi, s.start_time).1;
    let coarse = render(&s, lo, s.start_time).1;
    // The horizon's row on the coarse image.
    let cam = s.camera();
    let forward = cam.forward();
    let towards = glam::Vec3::new(forward.x, 0.0, forward.z).normalize();
    let far = glam::Vec3::new(cam.position.x, 0.0, cam.position.z) + towards * 1e5;
    let clip = cam.view_projection(lo.0 as f32 / lo.1 as f32) * far.extend(1.0);
    let horizon = (1.0 - clip.y / clip.w) * 0.5 * lo.1 as f32;
    let (first, last) = (horizon.ceil() as usize + 1, (horizon + lo.1 as f32 / 3.0) as usize);
    assert!(first < last && last < lo.1 as usize, "a band of sea below the horizon ({horizon})");
    let mean = |img: &[[f32; 4]], width: usize, rows: std::ops::Range<usize>| {
        let mut sum = glam::Vec3::ZERO;
        for y in rows.clone() {
            for x in 0..width {
                sum += glam::Vec3::from_slice(&img[y * width + x][..3]);
            }
        }
        sum / (rows.len() * width) as f32
    };
    for (a, b) in [(first, last + 1), (first, first + 2)] {
        let c = mean(&coarse, lo.0 as usize, a..b);
        let f = mean(&fine, hi.0 as usize, a * scale..b * scale);
        eprintln!("rows {a}..{b} of {}: filtered {c:?}, resolved {f:?}", lo.1);
        for k in 0..3 {
            assert!(
                (c[k] - f[k]).abs() < 0.06 * f[k],
                "rows {a}..{b}, channel {k}: filtered {} against resolved {}",
                c[k],
                f[k]
            );
        }
    }
}
