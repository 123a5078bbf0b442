// GPU tests: The white water against its CPU twin: foam, bubbles, breaking crests, splashes.

use super::harness::*;

/// Foam scatters the sunlight back up: under a splash's foam on still
/// water the photon, beam and procedural caustics darken by the foam's transmittance, 1 − 0.8·c
/// (twin `foam_transmittance`), and the map's mean drops by the foam's
/// mean over the patch, against flat water's exact irradiance elsewhere.
#[test]
fn foam_darkens_the_caustics_beneath_it() {
    use hydrolux::core::caustics::flat_floor_irradiance;
    use hydrolux::core::scene::CausticMethod;
    use hydrolux::core::whitewater::{Splash, foam_cover, foam_transmittance};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    for method in [CausticMethod::Photons, CausticMethod::Beam, CausticMethod::Procedural] {
        let mut s = ripple_scene("walls");
        s.drops.clear();
        s.emitters.clear();
        s.ripples.extent = 4.0;
        s.caustics.method = method;
        s.caustics.photons = 256;
        s.caustics.map_resolution = 64;
        s.validate().expect("valid");
        let mut r = renderer(&ctx, &s);
        let splash = Splash {
            position: [0.4, 0.0, -0.3],
            radius: 1.2,
            velocity: [0.0; 3],
            speed: 0.0,
            spray: 0,
            bubbles: 0,
            foam: 2.0,
            first: 0,
        };
        assert!(r.splash(splash));
        let dt = 1.0 / s.whitewater.rate as f64;
        r.simulate(&s.camera(), (16, 16), dt);
        let foam = r.read_foam().expect("foam");
        let (m, map) = r.read_caustics().expect("caustics are on");
        let flat = flat_floor_irradiance(s.sun_direction(), s.water.ior);
        // The foam's mean cover over the caustics' patch (centred on the origin).
        let patch = s.surface_patch()[0];
        let area: f32 =
            foam.amount.iter().map(|&f| foam_cover(f)).sum::<f32>() * foam.cell_size.powi(2);
        let want = flat * (1.0 - (1.0 - foam_transmittance(1.0)) * area / (patch * patch));
        let mean = map.iter().sum::<f32>() / map.len() as f32;
        assert!(want < 0.9 * flat, "the foam covers enough of the patch: {want} vs {flat}");
        assert!(
            (mean - want).abs() < 0.02 * flat,
            "{method:?}: mean {mean}, want {want} (flat {flat})"
        );
        let darkest = map.iter().cloned().fold(f32::INFINITY, f32::min);
        assert!(
            (darkest - flat * foam_transmittance(1.0)).abs() < 0.05 * flat,
            "{method:?}: under dense foam {darkest}"
        );
        assert_eq!(m as usize * m as usize, map.len());
    }
}

/// Bubbles under moving waves on the GPU against the CPU twin: a splash's
/// bubbles on an FFT ocean, carried by the water's orbital motion (the
/// surface's displacement over each step, prefiltered by depth; twin
/// `WaterSurface for OceanMips`) as they rise, merge and burst, for a
/// second: the same bubbles, where the twin has them.
#[test]
fn bubbles_ride_the_gpu_waves_as_on_the_cpu_twin() {
    use hydrolux::core::whitewater::{BUBBLE, ParticleStep, Particles, SPRAY_DROP_RADIUS, Splash};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = scene(SMALL_OCEAN);
    // No crest emission: only the splash's particles.
    s.whitewater.spray_rate = 0.0;
    s.whitewater.bubble_rate = 0.0;
    let mut r = renderer(&ctx, &s);
    let cam = s.camera().position;
    let splash = Splash {
        position: [cam.x + 3.0, -0.2, cam.z - 4.0],
        radius: 1.5,
        velocity: [0.0; 3],
        speed: 0.0,
        spray: 0,
        bubbles: 300,
        foam: 0.0,
        first: 0,
    };
    assert!(r.splash(splash));
    let t = 1.0;
    r.simulate(&s.camera(), (16, 16), t);
    let gpu_particles = r.read_particles().expect("particles");

    let spectrum = OceanSpectrum::new(&s.ocean_settings());
    let rate = s.whitewater.rate;
    let dt = 1.0 / rate as f32;
    let reach = 120.0;
    let mut cpu = Particles::default();
    let steps = (t * rate as f64).round() as u32;
    let (mut swayed, mut moving) = (0.0f32, 0usize);
    for step in 0..steps {
        let surface = OceanFields::evaluate(&spectrum, (step + 1) as f64 * dt as f64).mips();
        let ps = ParticleStep {
            dt,
            step,
            wind: [0.0, 0.0],
            floor_depth: if s.floor.depth > 0.0 { s.floor.depth } else { 1.0e4 },
            max_age: 20.0,
            low: [cam.x - reach, cam.z - reach],
            high: [cam.x + reach, cam.z + reach],
            drop_radius: SPRAY_DROP_RADIUS,
            bubble_mobility: hydrolux_core::whitewater::bubble_mobility(s.water.salinity as f64),
        };
        let splashes: &[Splash] = if step == 0 { &[splash] } else { &[] };
        cpu.merge();
        cpu.update(&ps, surface);
        cpu.spawn(splashes, &ps, 1 << 16);
        for p in &cpu.alive {
            let h = p.velocity[0].hypot(p.velocity[2]);
            swayed = swayed.max(h);
            moving += (h > 0.05) as usize;
        }
    }
    assert!(swayed > 0.1 && moving > 0, "the waves move the bubbles sideways (up to {swayed} m/s)");
    let by_id: std::collections::HashMap<u32, _> = cpu.alive.iter().map(|p| (p.id, p)).collect();
    let gb = gpu_particles.iter().filter(|p| p.kind == BUBBLE).count();
    let cb = cpu.alive.iter().filter(|p| p.kind == BUBBLE).count();
    assert!(cb > 50, "the twin keeps {cb} bubbles after {t} s");
    assert!(gb.abs_diff(cb) <= 3, "GPU {gb} bubbles, CPU {cb}");
    let (mut worst, mut matched) = (0.0f32, 0);
    for g in &gpu_particles {
        let Some(c) = by_id.get(&g.id) else { continue };
        matched += 1;
        for k in 0..3 {
            worst = worst.max((g.position[k] - c.position[k]).abs());
        }
    }
    assert!(
        matched + 6 >= gpu_particles.len(),
        "{matched} of {} matched by id",
        gpu_particles.len()
    );
    eprintln!(
        "{gb} GPU, {cb} CPU bubbles; {matched} matched, worst {worst} m, sway up to {swayed} m/s"
    );
    // Half-float cascades: the motion to ~10⁻³ of itself, i.e. millimetres.
    assert!(worst < 1e-2, "positions differ by up to {worst} m");
}

/// Breaking crests on the GPU against the CPU twin: one white-water step
/// on an FFT ocean from no foam leaves F = gain·fold(J)·dt in every cell,
/// with J the Jacobian prefiltered over the cell (the cascades' mips, twin
/// `OceanMips`) and J₀ the threshold calibrated on the CPU.
#[test]
fn breaking_crests_match_the_cpu_twin() {
    use hydrolux::core::whitewater::{
        FOAM_MAX, FOLD_GAIN, FoamGrid, JacobianSeries, calibrated_fold_threshold, fold_source,
        jacobian,
    };
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = scene(SMALL_OCEAN);
    s.whitewater.particles = false;
    let mut r = renderer(&ctx, &s);
    let dt = 1.0 / s.whitewater.rate as f64;
    r.simulate(&s.camera(), (16, 16), dt);
    let gpu = r.read_foam().expect("foam");
    let grid = FoamGrid::periodic(gpu.cells, gpu.cells as f32 * gpu.cell_size);
    let spectrum = OceanSpectrum::new(&s.ocean_settings());
    let threshold = calibrated_fold_threshold(
        &JacobianSeries::of_ocean(&spectrum, &grid),
        s.sea_state().wind_speed,
    );
    let mips = OceanFields::evaluate(&spectrum, dt).mips();
    let (mut breaking, mut worst) = (0, 0.0f32);
    for (k, g) in gpu.amount.iter().enumerate() {
        let [i, j] = grid.world_cell(k);
        let (x, z) = ((i as f32 + 0.5) * grid.cell, (j as f32 + 0.5) * grid.cell);
        let sample = mips.sample_footprint(x as f64, z as f64, grid.cell as f64);
        let cpu = (FOLD_GAIN * fold_source(jacobian(&sample), threshold) * dt as f32).min(FOAM_MAX);
        breaking += (cpu > 0.0) as usize;
        worst = worst.max((g - cpu).abs());
    }
    let n = gpu.amount.len();
    eprintln!("{breaking} of {n} cells break; foam differs by up to {worst}");
    assert!(breaking * 1000 > n && breaking * 5 < n, "{breaking} of {n} cells break");
    // Half-float cascades: J to about 2·10⁻³, i.e. F to 0.02 of a step's most.
    let most = FOLD_GAIN * dt as f32;
    assert!(worst < 0.02 * most, "foam differs by up to {worst} (a step adds at most {most})");
}

/// A caller's splash on still water, stepped on the GPU and on the CPU
/// twin (hydrolux-core `Particles`, `FoamField`) for a second: the same
/// particles alive (matched by id), where the twin puts them, the same
/// bubble air after merging, and the same foam from the splash, the spray
/// falling back and the bubbles bursting.
#[test]
fn splash_particles_and_foam_match_the_cpu_twin() {
    use hydrolux::core::waves::ripples::{RippleSim, RippleWindow};
    use hydrolux::core::whitewater::{
        BUBBLE, FoamField, FoamGrid, FoamStep, ParticleStep, Particles, SPRAY, SPRAY_DROP_RADIUS,
        Splash, kick_per_unit,
    };
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = ripple_scene("walls");
    s.drops.clear();
    s.emitters.clear();
    s.ripples.extent = 8.0;
    s.validate().expect("valid");
    let mut r = renderer(&ctx, &s);
    let splash = Splash {
        position: [0.4, 0.0, -0.3],
        radius: 0.4,
        velocity: [0.5, 0.0, 0.0],
        speed: 8.0,
        spray: 120,
        bubbles: 240,
        foam: 0.8,
        first: 0,
    };
    assert!(r.splash(splash), "the scene runs white water");
    let t = 1.0;
    r.simulate(&s.camera(), (16, 16), t);
    let gpu_foam = r.read_foam().expect("foam");
    let gpu_particles = r.read_particles().expect("particles");

    let rate = s.whitewater.rate;
    let dt = 1.0 / rate as f32;
    let side = gpu_foam.cells as f32 * gpu_foam.cell_size;
    let centre = [0, 1].map(|a| gpu_foam.origin[a] + 0.5 * side);
    let grid = FoamGrid::centred(gpu_foam.cells, side, centre);
    assert_eq!([0, 1].map(|a| grid.low[a] as f32 * grid.cell), gpu_foam.origin);
    let mut foam = FoamField::new(grid);
    let mut cpu = Particles::default();
    let foam_step = FoamStep { dt, life: s.foam_life(), drift: [0.0, 0.0] };
    let steps = (t * rate as f64).round() as u32;
    // The interactive water, which the landing spray kicks: its steps
    // between white water's (three at 60 Hz before each at 20 Hz).
    let settings = s.ripple_settings().expect("interactive water");
    let mut water = RippleSim::new(settings, RippleWindow::centred(&settings.grid, [0.4, -0.3]));
    water.kick_per_unit =
        kick_per_unit(s.whitewater.spray_size, s.whitewater.spray_water, settings.grid.cell_size);
    let ripple_steps = (settings.dt * rate as f64).recip().round() as u32;
    let mut landed_spray = 0;
    for step in 0..steps {
        for _ in 0..ripple_steps {
            water.step(&[]);
        }
        let ps = ParticleStep {
            dt,
            step,
            wind: [0.0, 0.0],
            floor_depth: s.floor.depth,
            max_age: 20.0,
            low: gpu_foam.origin,
            high: [gpu_foam.origin[0] + side, gpu_foam.origin[1] + side],
            drop_radius: SPRAY_DROP_RADIUS,
            bubble_mobility: hydrolux_core::whitewater::bubble_mobility(s.water.salinity as f64),
        };
        let splashes: &[Splash] = if step == 0 { &[splash] } else { &[] };
        cpu.merge();
        for l in cpu.update(&ps, |_, _| 0.0) {
            foam.deposit(l.x, l.z, l.foam);
            if l.speed > 0.0 {
                water.land(l.x, l.z, l.speed);
                landed_spray += 1;
            }
        }
        foam.step(&foam_step, splashes, |_, _| 0.0);
        cpu.spawn(splashes, &ps, 1 << 16);
    }

    // The same particles alive, where the twin has them.
    let by_id: std::collections::HashMap<u32, _> = cpu.alive.iter().map(|p| (p.id, p)).collect();
    let count = |ps: &mut dyn Iterator<Item = u32>, kind| ps.filter(|&k| k == kind).count();
    let (gb, gs) = (
        count(&mut gpu_particles.iter().map(|p| p.kind), BUBBLE),
        count(&mut gpu_particles.iter().map(|p| p.kind), SPRAY),
    );
    let (cb, cs) = (
        count(&mut cpu.alive.iter().map(|p| p.kind), BUBBLE),
        count(&mut cpu.alive.iter().map(|p| p.kind), SPRAY),
    );
    assert!(cb > 20 && cs > 20, "the twin keeps bubbles ({cb}) and spray ({cs}) after {t} s");
    assert!(
        gb.abs_diff(cb) <= 2 && gs.abs_diff(cs) <= 2,
        "GPU {gb} bubbles, {gs} spray; CPU {cb}, {cs}"
    );
    let mut worst = 0.0f32;
    let mut matched = 0;
    for g in &gpu_particles {
        let Some(c) = by_id.get(&g.id) else { continue };
        matched += 1;
        for k in 0..3 {
            worst = worst.max((g.position[k] - c.position[k]).abs());
        }
        assert_eq!(g.kind, c.kind);
    }
    assert!(
        matched + 4 >= gpu_particles.len(),
        "{matched} of {} matched by id",
        gpu_particles.len()
    );
    assert!(worst < 2e-3, "positions differ by up to {worst} m");
    let air = |ps: &[hydrolux::core::whitewater::Particle]| -> u64 {
        ps.iter().filter(|p| p.kind == BUBBLE).map(|p| p.volume as u64 + p.gained as u64).sum()
    };
    let (ga, ca) = (air(&gpu_particles), cpu.bubble_volume());
    assert!(ga.abs_diff(ca) as f64 <= 0.02 * ca as f64, "bubble air: GPU {ga}, CPU {ca} units");

    // The same foam.
    let n = grid.cells as i32;
    let cpu_foam: Vec<f32> =
        (0..n * n).map(|k| foam.at(grid.low[0] + k % n, grid.low[1] + k / n)).collect();
    let total = |f: &[f32]| f.iter().map(|&v| v as f64).sum::<f64>();
    let (gt, ct) = (total(&gpu_foam.amount), total(&cpu_foam));
    assert!(ct > 1.0, "the splash left foam ({ct})");
    assert!((gt - ct).abs() < 0.02 * ct, "foam total: GPU {gt}, CPU {ct}");
    let worst =
        gpu_foam.amount.iter().zip(&cpu_foam).map(|(g, c)| (g - c).abs()).fold(0.0f32, f32::max);
    assert!(worst < 0.05, "foam differs by up to {worst} per cell");

    // The same rings from the spray that fell back (the splash itself made
    // none: only its particles touch the water).
    let gpu_water = r.read_ripples().expect("interactive water");
    let cpu_water = water.heights();
    let rms = |v: &mut dyn Iterator<Item = f64>| {
        let (sum, n) = v.fold((0.0, 0), |(s, n), x| (s + x * x, n + 1));
        (sum / n as f64).sqrt()
    };
    let amplitude = rms(&mut cpu_water.iter().copied());
    let error = rms(&mut gpu_water.heights.iter().zip(&cpu_water).map(|(g, c)| *g as f64 - c));
    assert!(landed_spray > 10, "spray fell back ({landed_spray} parcels)");
    assert!(amplitude > 1e-6, "the landing spray rang the water ({amplitude:e} m rms)");
    assert!(
        error < 0.05 * amplitude,
        "rings: GPU − CPU {error:e} m rms, waves {amplitude:e} m rms"
    );
}

/// A spray parcel's look as the shaders draw it against its CPU twin
/// (hydrolux_core::whitewater::spray_look): opacity over its quad, drawn
/// as sharp, streaked and pixel-sized drops and as mist, its optical
/// depth, the asymmetry that leaves and the sky's share of it.
#[test]
fn spray_is_drawn_and_lit_as_its_cpu_twin() {
    use hydrolux::core::whitewater::spray_look::*;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = scene(SMALL_OCEAN);
    let r = renderer(&ctx, &s);
    let shapes = [
        (0.5, 0.0025, 0.0, 0.06, 0.01),
        (0.5, 0.02, 0.6, 0.06, 0.01),
        (0.5, 0.05, 0.0, 0.25, 0.01),
        (0.35, 0.45, 1.5, 0.25, 0.01),
        (0.5, 0.01, 0.2, 0.6, 0.002),
    ];
    let mut queries = Vec::new();
    for (k, (parcel, pixel, streak, size, water)) in shapes.into_iter().enumerate() {
        let shape = SprayShape {
            parcel,
            pixel,
            streak,
            cover: parcel_cover(size, water),
            drops: parcel_drops(size, water),
        };
        // Ids whose bits are a normal float (they travel as one).
        let id = 0x4000_0000 + 97 * k as u32;
        for j in 0..24 {
            for i in 0..24 {
                let at = [-1.0 + (i as f32 + 0.5) / 12.0, -1.0 + (j as f32 + 0.5) / 12.0];
                queries.push((at, shape, id));
            }
        }
        // On a drop's centre, where the opacity is steepest.
        let c = drop_centre(id, 0, parcel, drawn_drop_radius(shape.cover));
        queries.push((c, shape, id));
    }
    let got = r.probe_spray(&queries);
    assert_eq!(got.len(), queries.len());
    let (mut seen, mut most) = (0.0f32, 0.0f32);
    for ((at, shape, id), g) in queries.iter().zip(&got) {
        let depth = mist_depth(*at, shape);
        let asymmetry = spray_asymmetry(depth);
        let want =
            [spray_opacity(*at, shape, *id), depth, asymmetry, spray_sky_share(at[1], asymmetry)];
        for (w, g) in want.iter().zip(g) {
            most = most.max((w - g).abs());
            assert!((w - g).abs() < 2e-4, "{at:?} {shape:?}: GPU {g:?} CPU {want:?}");
        }
        seen += want[0];
    }
    assert!(seen > 10.0, "the parcels are drawn at all ({seen})");
    eprintln!("spray twin: largest difference {most:e}");
}
