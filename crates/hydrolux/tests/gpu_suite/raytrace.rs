// GPU tests: GPU ray tracing against the CPU tracer, Snell's law, the traced caustics, the error view.

use super::harness::*;

/// The GPU's traced ground (`water.method = "raytrace"`) against the CPU
/// twin (hydrolux-core `raytrace::trace_hierarchical`) on the lake's
/// terrain: rays from above and below the water, steep to grazing, the
/// same first hits.
#[test]
fn traced_ground_hits_match_the_cpu_tracer() {
    use hydrolux::core::raytrace::{
        MinMaxPyramid, Ray, trace_dense, trace_hierarchical, trace_hierarchical_within,
    };
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = Scene::load("lake", &["water.method=raytrace".to_string()]).expect("lake");
    let r = renderer(&ctx, &s);
    let hf = s.ground_heightfield().expect("terrain").expect("a ground");
    let pyramid = MinMaxPyramid::new(&hf);
    let mut rays = Vec::new();
    for k in 0..600u32 {
        let u = |salt: u32| hydrolux::core::whitewater::random(k, salt, 7);
        let x = (u(1) - 0.5) * 260.0;
        let z = (u(2) - 0.5) * 260.0;
        let y = -4.0 + 8.0 * u(3);
        let a = u(4) * std::f32::consts::TAU;
        let elevation = match k % 4 {
            0 => 0.01,
            1 => 0.1,
            _ => (u(5) - 0.5) * 3.0,
        };
        let dir = [a.cos() * elevation.cos(), -elevation.sin(), a.sin() * elevation.cos()];
        rays.push(([x, y, z], dir, 400.0));
    }
    let gpu = r.probe_traced_ground(&rays).expect("the scene ray-traces");
    let (mut hits, mut worst, mut dense_agree) = (0, 0.0f32, 0);
    for (k, ((o, d, reach), g)) in rays.iter().zip(&gpu).enumerate() {
        let ray = Ray { origin: *o, dir: *d };
        let cpu = trace_hierarchical(&hf, &pyramid, &ray, *reach).map(|h| h.t);
        match (cpu, g) {
            (Some(c), Some(g)) => {
                hits += 1;
                worst = worst.max((c - g).abs() / c.max(1.0));
                if k % 10 == 0 {
                    // And the brute-force reference agrees.
                    let dense = trace_dense(&hf, &ray, *reach).map(|h| h.t);
                    if dense.is_some_and(|t| (t - c).abs() < 1e-2 * c.max(1.0)) {
                        dense_agree += 1;
                    }
                }
            }
            (None, None) => {}
            (c, g) => panic!("ray {k} {o:?} {d:?}: CPU {c:?}, GPU {g:?}"),
        }
    }
    assert!(hits > 200, "{hits} of {} rays hit the terrain", rays.len());
    assert!(worst < 1e-3, "hit distances differ by up to {worst} (relative)");
    assert!(
        dense_agree * 10 + 20 >= hits,
        "the dense march agrees on {dense_agree} of ~{} checked",
        hits / 10
    );

    // A budget of steps (the quality tiers' water.trace_steps): rays that
    // spend it miss, on the GPU as on the CPU.
    let budget = 24;
    let s = Scene::load(
        "lake",
        &["water.method=raytrace".into(), format!("water.trace_steps={budget}")],
    )
    .expect("lake");
    let r = renderer(&ctx, &s);
    let gpu = r.probe_traced_ground(&rays).expect("the scene ray-traces");
    let (mut cut, mut differ) = (0, 0);
    for ((o, d, reach), g) in rays.iter().zip(&gpu) {
        let ray = Ray { origin: *o, dir: *d };
        let cpu = trace_hierarchical_within(&hf, &pyramid, &ray, *reach, budget).map(|h| h.t);
        let full = trace_hierarchical(&hf, &pyramid, &ray, *reach);
        cut += (full.is_some() && cpu.is_none()) as usize;
        let same = match (cpu, g) {
            (Some(c), Some(g)) => (c - g).abs() < 1e-3 * c.max(1.0),
            (None, None) => true,
            _ => false,
        };
        differ += !same as usize;
    }
    assert!(cut > 20, "a budget of {budget} steps cuts only {cut} rays short");
    assert!(differ * 100 <= rays.len(), "{differ} rays differ between GPU and CPU with the budget");
}

/// A red box on a white floor under flat water, seen at an angle with
/// `water.method = "raytrace"`: the pixels that show it are those whose
/// view ray, refracted at the surface by Snell's law, meets the box (a CPU
/// ray cast per pixel), where the projective lookup only approximates it.
#[test]
fn traced_refraction_shows_an_object_where_snells_law_puts_it() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    // A box…
    let (lo, hi) = (glam::Vec3::new(-0.2, -2.0, -0.6), glam::Vec3::new(1.0, -1.0, 0.2));
    let hits_box = |o: glam::Vec3, d: glam::Vec3| {
        let (t0, t1) = ((lo - o) / d, (hi - o) / d);
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        near <= far && far > 0.0
    };
    // Pure red: its sides are lit from below by the white floor's upwelling
    // light, blue-green after 2 m of water, which a box giving back 5% of
    // the green showed greener than red (147 red pixels of 230).
    let object = "{primitive=\"box\", position=[0.4, -1.5, -0.2], scale=[1.2, 1.0, 0.8], material={albedo=[0.9, 0.0, 0.0]}}";
    let nothing_above = |_: glam::Vec3, _: glam::Vec3| false;
    let (_, _) = snell_places_a_traced_object(&ctx, object, nothing_above, hits_box, 150);
    // …and a plane (seen from above, its front).
    let hits_plane = |o: glam::Vec3, d: glam::Vec3| {
        let p = o + d * ((-0.6 - o.y) / d.y);
        p.x.abs() < 0.7 && (p.z + 0.2).abs() < 0.45
    };
    let object = "{primitive=\"plane\", position=[0.0, -0.6, -0.2], scale=[1.4, 1.0, 0.9], material={albedo=[0.8, 0.05, 0.05]}}";
    let (_, _) = snell_places_a_traced_object(&ctx, object, nothing_above, hits_plane, 150);
    // …and a mesh, the bunny on the floor, found through its tree (the CPU
    // twin: MeshBvh::intersect in the bunny's own space).
    let object = "{mesh=\"builtin:bunny\", position=[0.3, -2.0, -0.2], rotation_deg=[0.0, 30.0, 0.0], scale=[1.2, 1.2, 1.2], material={albedo=[0.9, 0.0, 0.0]}}";
    let s = Scene::load("ocean", &[format!("objects=[{object}]")]).expect("valid");
    let mesh = s.object_mesh_file(&s.objects[0]).expect("the bunny");
    let bvh = hydrolux::core::raytrace::bvh::MeshBvh::build(&mesh.positions, &mesh.indices);
    let inverse = Scene::object_transform(&s.objects[0]).inverse();
    let hits_bunny = |o: glam::Vec3, d: glam::Vec3| {
        let (o, d) = (inverse.transform_point3(o), inverse.transform_vector3(d));
        bvh.intersect(o, d, 0.0, f32::INFINITY).is_some()
    };
    let (_, _) = snell_places_a_traced_object(&ctx, object, nothing_above, hits_bunny, 100);
}

/// A ball floating half under flat water (the pool's, issue #26): seen
/// from above at a slant, Snell's law squeezes its lower half into a thin
/// band under the waterline (rays bend down, towards the normal); the
/// projective approximation draws it far larger. The traced frame must
/// show that band where a CPU ray cast puts it, no more and no less.
#[test]
fn a_half_submerged_sphere_is_traced_where_snells_law_puts_it() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (c, r) = (glam::Vec3::new(0.0, 0.0, -0.2), 0.6f32);
    let sphere_t = move |o: glam::Vec3, d: glam::Vec3| {
        let oc = o - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        (disc >= 0.0).then(|| -b - disc.sqrt()).filter(|&t| t > 0.0)
    };
    // Above the water the view ray meets the ball before the water.
    let above =
        move |o: glam::Vec3, d: glam::Vec3| sphere_t(o, d).is_some_and(|t| (o + d * t).y >= 0.0);
    let below = move |o: glam::Vec3, d: glam::Vec3| sphere_t(o, d).is_some();
    let object = "{primitive=\"sphere\", position=[0.0, 0.0, -0.2], scale=[1.2, 1.2, 1.2], material={albedo=[0.8, 0.05, 0.05]}}";
    let (band, shown) = snell_places_a_traced_object(&ctx, object, above, below, 40);
    assert!(band >= 10, "Snell's law puts the lower half in {band} pixels");
    assert!(
        shown as f32 >= 0.8 * band as f32,
        "the traced frame shows the lower half in {shown} of the {band} pixels Snell's law puts it"
    );
}

/// Render `object` (red) under flat water over a white floor, traced, and
/// check its pixels are those whose view ray refracted by Snell's law
/// `hits` it.
/// `above(eye, d)`: the view ray meets the object above the water;
/// `hits(p, t)`: the refracted ray from the water at p meets it. Returns
/// how many pixels show it through the water alone by the ray cast, and
/// how many of those the traced frame shows it in.
fn snell_places_a_traced_object(
    ctx: &GpuContext,
    object: &str,
    above: impl Fn(glam::Vec3, glam::Vec3) -> bool,
    hits: impl Fn(glam::Vec3, glam::Vec3) -> bool,
    least: u32,
) -> (u32, u32) {
    use hydrolux::core::optics::{IOR_AIR, IOR_WATER, refract};
    let s = Scene::load(
        "ocean",
        &[
            "water.method=raytrace",
            "water.model=flat",
            "ocean.wind_speed=0.5",
            "water.medium=pure",
            "floor.depth=2",
            "floor.material.albedo=[1, 1, 1]",
            "caustics.method=off",
            "godrays.method=off",
            "sun.elevation_deg=60",
            "camera.position=[0, 3, 3.5]",
            "camera.look_at=[0, -1.5, 0]",
            "camera.fov_y_deg=50",
            &format!("objects=[{object}]"),
        ]
        .map(String::from),
    )
    .expect("valid scene");
    let mut r = renderer(ctx, &s);
    let (w, h) = (96u32, 64u32);
    let target = HeadlessTarget::new(&ctx.device, (w, h));
    target.render(&mut r, s.camera(), 0.0).expect("frame");
    let (hw, hh, hdr) = r.read_hdr().expect("rendered");
    let cam = s.camera();
    let forward = cam.forward();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let tan = (cam.fov_y_deg.to_radians() / 2.0).tan();
    let aspect = hw as f32 / hh as f32;
    let (mut agree, mut predicted, mut seen) = (0, 0, 0);
    let (mut through, mut through_seen) = (0, 0);
    for y in 0..hh {
        for x in 0..hw {
            let ndc = glam::Vec2::new(
                (x as f32 + 0.5) / hw as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / hh as f32 * 2.0,
            );
            let d = (forward + ndc.x * tan * aspect * right + ndc.y * tan * up).normalize();
            let mut red = above(cam.position, d);
            if d.y < 0.0 && !red {
                let p = cam.position + d * (-cam.position.y / d.y);
                let t = refract(d, glam::Vec3::Y, IOR_AIR, IOR_WATER).expect("into water");
                red = hits(p, t);
                through += red as u32;
            }
            let c = hdr[(y * hw + x) as usize];
            // Red light is what the object sends back; the water and the floor are cyan.
            let gpu_red = c[0] > c[1];
            through_seen += (red && gpu_red && !above(cam.position, d)) as u32;
            predicted += red as u32;
            seen += gpu_red as u32;
            agree += (red == gpu_red) as u32;
        }
    }
    let total = hw * hh;
    assert!(predicted > least, "{object} covers {predicted} pixels");
    assert!(seen.abs_diff(predicted) < predicted / 3, "{seen} red pixels, {predicted} predicted");
    assert!(
        agree as f32 > 0.97 * total as f32,
        "traced: {seen} red pixels, Snell's law puts {object} in {predicted}; they agree on {agree} of {total}"
    );
    (through, through_seen)
}

/// The ray-traced water's heightfield, resampled on the GPU from the FFT
/// ocean with its horizontal displacement undone, against the CPU twin
/// (hydrolux-core `Heightfield::resampled` over the CPU ocean's mips).
#[test]
fn traced_water_heightfield_matches_the_cpu_resampling() {
    use hydrolux::core::raytrace::Heightfield;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut sets: Vec<&str> = SMALL_OCEAN.to_vec();
    sets.push("water.method=raytrace");
    sets.push("ocean.choppiness=1.0");
    let s = scene(&sets);
    let mut r = renderer(&ctx, &s);
    let t = 2.5;
    r.simulate(&s.camera(), (16, 16), t);
    let (gpu, origin) = r.read_traced_water().expect("traced");
    let n = 257usize;
    assert_eq!(gpu.len(), n * n);
    let mips = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), t).mips();
    let cpu = Heightfield::resampled(origin, 0.25, n, 0.0, 6, |x, z| {
        mips.sample_footprint(x as f64, z as f64, 0.25).displacement
    });
    let rms = (cpu.heights.iter().map(|h| (h * h) as f64).sum::<f64>() / (n * n) as f64).sqrt();
    let mut errors: Vec<f32> = gpu.iter().zip(&cpu.heights).map(|(g, c)| (g - c).abs()).collect();
    errors.sort_by(f32::total_cmp);
    let p99 = errors[errors.len() * 99 / 100];
    assert!(rms > 0.1, "waves of {rms} m rms");
    assert!(p99 < 0.01 * rms as f32 + 2e-3, "99% within {p99} m (waves {rms} m rms)");
}

/// The paper's caustics on the traced ground (passes/raytrace/caustics.wgsl):
/// on a flat floor they are the layered photon map's floor layer (the same
/// surface, photons and cells: correlation and mean), they match their CPU
/// twin (hydrolux_core::raytrace::caustics) on the CPU ocean, and a box in
/// flat water shades the floor where the refracted sunbeam puts its shadow.
#[test]
fn traced_caustics_agree_with_the_photon_caustics_and_trace_shadows() {
    use hydrolux::core::caustics::{flat_floor_irradiance, refracted_photon};
    use hydrolux::core::raytrace::MinMaxPyramid;
    use hydrolux::core::raytrace::caustics::{
        CausticWindow, Emission, Ground, sun_travel, trace_ground_caustics,
    };
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(&[
        "water.method=raytrace",
        "caustics.photons=256",
        "caustics.map_resolution=64",
        "floor.depth=5",
        "sun.elevation_deg=55",
        "ocean.patch_size=16",
        "ocean.resolution=64",
        "ocean.cascades=1",
        "ocean.wind_speed=6",
        "ocean.fetch_km=20",
        "ocean.choppiness=0.5",
        "whitewater.foam=false",
        "camera.position=[3.3, 4, -2.1]",
    ]);
    let mut r = renderer(&ctx, &s);
    let t = 12.0;
    r.simulate(&s.camera(), (16, 16), t);
    let (_, layered) = r.read_caustics().expect("caustics are on");
    let (traced, w) = r.read_traced_caustics().expect("traced caustics are on");
    let m = 64usize;
    assert_eq!((traced.len(), w[3]), (m * m, 64.0));
    // Centred on the camera in whole cells of the periodic maps.
    assert!((w[0] - (3.25 - 8.0)).abs() < 1e-4 && (w[1] - (-2.0 - 8.0)).abs() < 1e-4, "{w:?}");
    let flat = flat_floor_irradiance(s.sun_direction(), s.water.ior);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for j in 1..m - 1 {
        for i in 1..m - 1 {
            let x = w[0] + (i as f32 + 0.5) * w[2];
            let z = w[1] + (j as f32 + 0.5) * w[2];
            let cell = |c: f32| ((c / 16.0 + 0.5) * 64.0 - 0.5).round().rem_euclid(64.0) as usize;
            a.push(traced[j * m + i]);
            b.push(layered[cell(z) * m + cell(x)] / flat);
        }
    }
    let (ma, mb, corr) = means_and_correlation(&a, &b);
    assert!(corr > 0.99, "traced and layered caustics correlate only {corr}");
    assert!((ma - mb).abs() < 0.01 * mb, "means: traced {ma}, layered {mb}");
    let max = a.iter().cloned().fold(0.0, f32::max);
    assert!(max > 1.4 * ma, "the waves focus light: max {max}, mean {ma}");

    // The CPU twin on the CPU ocean.
    let fields = OceanFields::evaluate(&OceanSpectrum::new(&s.ocean_settings()), t);
    let hf = s.ground_heightfield().expect("ground").expect("a floor");
    let pyramid = MinMaxPyramid::new(&hf);
    let ground = Ground { heightfield: &hf, pyramid: &pyramid };
    let window = CausticWindow { origin: [w[0], w[1]], cell: w[2], m };
    let (sun, ior) = (s.sun_direction(), s.water.ior);
    let emission = Emission::covering(&window, 16.0 / 256.0, sun, ior, 5.0);
    let photon =
        |x: f32, z: f32| refracted_photon(&fields.sample(x as f64, z as f64), x, z, sun, ior);
    let cpu = trace_ground_caustics(photon, &ground, |_, _, _| false, &window, &emission, sun, ior);
    let (mg, mc, corr) = means_and_correlation(&traced, &cpu.factor);
    assert!(corr > 0.95, "GPU and CPU traced caustics correlate only {corr}");
    assert!((mg - mc).abs() < 0.02 * mc, "means: GPU {mg}, CPU {mc}");

    // A box in flat water: its shadow, traced through the surface.
    let s = Scene::load(
        "ocean",
        &[
            "water.method=raytrace",
            "water.model=flat",
            "floor.depth=3",
            "sun.elevation_deg=50",
            "sun.azimuth_deg=0",
            "caustics.map_resolution=64",
            "caustics.photons=256",
            "ocean.patch_size=16",
            "camera.position=[0, 4, 0]",
            "objects=[{primitive=\"box\", position=[0, -1.0, 0], scale=[2.0, 0.2, 2.0]}]",
        ]
        .map(String::from),
    )
    .expect("valid scene");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.0);
    let (light, w) = r.read_traced_caustics().expect("traced caustics are on");
    let n = w[3] as usize;
    let at = |x: f32, z: f32| {
        let i = ((x - w[0]) / w[2]) as usize;
        let j = ((z - w[1]) / w[2]) as usize;
        light[j * n + i]
    };
    // The slab's underside (y = −1.1) carried down 1.9 m along the beam.
    let travel = sun_travel(s.sun_direction(), s.water.ior);
    let c = glam::Vec3::new(0.0, -1.1, 0.0) + travel * (1.9 / -travel.y);
    for (dx, dz) in [(0.0, 0.0), (0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3)] {
        let v = at(c.x + dx, c.z + dz);
        assert!(v < 1e-3, "in the box's shadow at {dx}, {dz}: {v}");
    }
    for (dx, dz) in [(1.8, 0.0), (-1.8, 0.0), (0.0, 1.8), (0.0, -1.8), (4.0, 3.0)] {
        let v = at(c.x + dx, c.z + dz);
        assert!((v - 1.0).abs() < 2e-3, "lit at {dx}, {dz}: {v}");
    }
}

/// The error view (`render.view = "error"`, the viewer's truth mode) is the
/// heat of ΔE*ab between the projective and the traced frame, per pixel, as
/// hydrolux-core `compare` computes it from the two frames rendered apart;
/// and drawing the frame twice does not step the simulation twice (the
/// pool's interactive water and ball move).
#[test]
fn error_view_is_the_heat_of_the_two_methods_difference() {
    use hydrolux::core::compare::{delta_e, heat};
    use hydrolux::core::scene::{DebugView, WaterMethod};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let base = Scene::load("pool", &[]).expect("built-in");
    let (size, t) = ((96, 64), 1.5);
    let frame = |s: &Scene| {
        let mut r = renderer(&ctx, s);
        let target = HeadlessTarget::new(&ctx.device, size);
        target.render(&mut r, s.camera(), t).expect("frame")
    };
    let mut s = base.clone();
    s.water.method = WaterMethod::Projective;
    let projective = frame(&s);
    s.water.method = WaterMethod::Raytrace;
    let traced = frame(&s);
    s.render.view = DebugView::Error;
    let error = frame(&s);
    let (mut off, mut hot, n) = (0, 0, (size.0 * size.1) as usize);
    for p in 0..n {
        let rgb = |v: &[u8]| [v[4 * p], v[4 * p + 1], v[4 * p + 2]];
        let e = delta_e(rgb(&projective), rgb(&traced));
        let want = heat(e);
        let got = rgb(&error);
        if want.iter().zip(&got).any(|(a, b)| a.abs_diff(*b) > 2) {
            off += 1;
        }
        hot += (e > 3.0) as usize;
    }
    assert!(hot > n / 50, "the methods differ somewhere in the pool: {hot} of {n} pixels");
    assert!(off <= n / 200, "{off} of {n} pixels off the CPU's heat");
}
