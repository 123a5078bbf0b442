// GPU tests: the volumetric liquid against its CPU twin, hydrostatics and
// determinism (small grids: lavapipe runs ~1000 dispatches a step).

use super::harness::*;
use hydrolux::core::scene::{FluidSource, FluidSourceKind, Scene};

/// A small closed tank 0.4 × 0.3 × 0.1 m (16 × 12 × 4 cells of 2.5 cm)
/// holding a block of liquid from `lo` to `hi`, its surface not drawn.
fn tank(lo: [f32; 3], hi: [f32; 3]) -> Scene {
    let mut s = Scene::load("dam_break", &[]).expect("built-in");
    s.fluid.min = [0.0, 0.0, 0.0];
    s.fluid.max = [0.4, 0.3, 0.1];
    s.fluid.resolution = 16;
    s.fluid.tolerance = 1e-4;
    s.fluid.iterations = 100;
    s.fluid.sources = vec![FluidSource { min: lo, max: hi, ..FluidSource::default() }];
    // Not meshed: these tests read the simulation; the surface's own test
    // asks for its mesh.
    s.fluid.surface = hydrolux::core::scene::FluidSurface::None;
    s.objects.clear();
    s.validate().expect("valid");
    s
}

fn max_distance(a: &[[f32; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|k| (p[k] as f64 - q[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

/// A collapsing column for 0.1 s (12 steps) on the GPU and on the CPU twin
/// (f64, the same transfers and solve), in the open tank, with a box
/// standing in its way (a solid), as a viscous liquid (ν = 5e-3 m²/s), and
/// with the tank's end behind it open (the liquid runs out): the same
/// particles alive, every one where the twin has it to a millimetre, with
/// the solve meeting its residual.
#[test]
fn a_collapsing_column_follows_its_cpu_twin() {
    use hydrolux::core::scene::{ObjectDesc, Primitive};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let cases = [(false, 0.0, false), (true, 0.0, false), (false, 5e-3, false), (false, 0.0, true)];
    for (obstacle, viscosity, open) in cases {
        let mut s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
        s.fluid.viscosity = viscosity;
        if open {
            s.fluid.open = vec!["-x".into()];
        }
        if obstacle {
            s.objects = vec![ObjectDesc {
                primitive: Primitive::Box,
                position: [0.15, 0.05, 0.05],
                scale: [0.05, 0.1, 0.2],
                ..ObjectDesc::default()
            }];
        }
        let mut r = renderer(&ctx, &s);
        r.simulate(&s.camera(), (16, 16), 0.1);
        let gpu = r.read_liquid().expect("a liquid");
        let mut twin = s.fluid_start().expect("the liquid starts");
        assert_eq!(
            twin.grid.cells.iter().filter(|c| **c == hydrolux::core::fluid::Cell::Solid).count(),
            if obstacle { 2 * 4 * 4 } else { 0 }
        );
        let steps = (0.1 * 120.0) as usize * s.fluid.substeps as usize;
        for _ in 0..steps {
            twin.step(s.fluid.step_seconds());
        }
        let live: Vec<[f64; 3]> = twin.live_positions().copied().collect();
        assert_eq!(gpu.particles.len(), live.len(), "open {open}");
        if open {
            assert!(live.len() < twin.positions.len(), "none ran out of the open end");
        }
        assert_eq!(gpu.solve.steps as usize, steps);
        let positions: Vec<[f32; 3]> = gpu.particles.iter().map(|p| p.position).collect();
        let apart = max_distance(&positions, &live);
        assert!(
            apart < 1e-3,
            "obstacle {obstacle}, ν {viscosity}, open {open}: a particle is {apart} m from the twin's"
        );
        // It moved: the column is falling and spreading.
        let start = s.fluid_start().expect("the liquid starts");
        let now: Vec<[f32; 3]> = twin.positions.iter().map(|p| p.map(|c| c as f32)).collect();
        let moved = max_distance(&now, &start.positions);
        assert!(moved > 0.01, "fastest particle moved {moved} m");
        let p = twin.last.expect("stepped");
        assert!(
            gpu.solve.iterations > 0 && gpu.solve.residual <= s.fluid.tolerance,
            "{:?}",
            gpu.solve
        );
        assert!(
            gpu.max_liquid_divergence() <= 1.5 * s.fluid.tolerance,
            "{}",
            gpu.max_liquid_divergence()
        );
        assert!(p.divergence_after <= s.fluid.tolerance as f64, "{p:?}");
    }
}

/// A nozzle pouring down onto a drain in the tank's floor for 0.25 s
/// (30 steps), on the GPU and the twin: the same particles alive, each
/// where the twin has it to a millimetre, and some already drained.
#[test]
fn a_jet_into_a_drain_follows_its_cpu_twin() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = tank([0.0; 3], [0.1, 0.05, 0.1]);
    s.fluid.sources.push(FluidSource {
        kind: FluidSourceKind::Nozzle,
        position: [0.22, 0.15, 0.05],
        direction: [1.0, -1.0, 0.0],
        speed: 1.0,
        radius: 0.02,
        ..FluidSource::default()
    });
    s.fluid.sources.push(FluidSource {
        kind: FluidSourceKind::Drain,
        min: [0.3, 0.0, 0.0],
        max: [0.4, 0.06, 0.1],
        ..FluidSource::default()
    });
    s.validate().expect("valid");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.25);
    let gpu = r.read_liquid().expect("a liquid");
    let mut twin = s.fluid_start().expect("the liquid starts");
    let steps = 30;
    let block = twin.alive_count();
    for _ in 0..steps {
        twin.step(s.fluid.step_seconds());
    }
    let per_step = twin.emitters[0].points.len();
    let live: Vec<[f64; 3]> = twin.live_positions().copied().collect();
    assert_eq!(gpu.particles.len(), live.len(), "particles alive on the GPU and the twin");
    let drained = block + steps * per_step - live.len();
    assert!(drained > 0, "nothing reached the drain");
    let positions: Vec<[f32; 3]> = gpu.particles.iter().map(|p| p.position).collect();
    let apart = max_distance(&positions, &live);
    assert!(apart < 1e-3, "a particle is {apart} m from the twin's");
    assert!(gpu.solve.residual <= s.fluid.tolerance, "{:?}", gpu.solve);
}

/// A column collapsing and its front running into the tank's far wall
/// for 0.25 s (60 steps),
/// shedding white water on the GPU and on the CPU twin: the pools agree
/// slot by slot (a slot is a particle's own, so they line up): nearly
/// every slot alive on one is alive on the other, and those alive on both
/// are of one kind and within 2 mm of each other. (A particle that sheds
/// on one side only, where its chance is within f32 rounding of the
/// draw, starts a difference that the rest do not share.)
#[test]
fn the_liquids_white_water_follows_its_cpu_twin() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = tank([0.0; 3], [0.15, 0.3, 0.1]);
    s.fluid.white_water = 200.0;
    s.validate().expect("valid");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.25);
    let gpu = r.read_liquid_white_water().expect("a liquid");
    let mut twin = s.fluid_start().expect("the liquid starts");
    let steps = (0.25 * 120.0) as usize * s.fluid.substeps as usize;
    for _ in 0..steps {
        twin.step(s.fluid.step_seconds());
    }
    let cpu = &twin.white_water.as_ref().expect("it sheds").pool;
    assert_eq!(gpu.len(), cpu.len());
    let alive = |d: &hydrolux::core::fluid::Diffuse| d.kind != 0;
    let (mut both, mut one, mut apart, mut kinds) = (0, 0, 0.0f32, 0);
    for (g, c) in gpu.iter().zip(cpu) {
        match (alive(g), alive(c)) {
            (true, true) => {
                both += 1;
                kinds += (g.kind != c.kind) as usize;
                let d = (0..3).map(|a| (g.position[a] - c.position[a]).powi(2)).sum::<f32>();
                apart = apart.max(d.sqrt());
            }
            (false, false) => {}
            _ => one += 1,
        }
    }
    let count = |k: u32| cpu.iter().filter(|d| d.kind == k).count();
    use hydrolux::core::whitewater::{BUBBLE, FOAM, SPRAY};
    let (spray, foam, bubbles) = (count(SPRAY), count(FOAM), count(BUBBLE));
    eprintln!(
        "white water: {both} alive on both, {one} on one; {spray} spray, {foam} foam, {bubbles} bubbles; {kinds} kinds differ; {apart} m apart"
    );
    assert!(both > 100, "only {both} white-water particles alive on both");
    assert!(foam > 0 && bubbles > 0, "foam {foam}, bubbles {bubbles}");
    assert!(one * 20 <= both, "{one} slots alive on one side only, {both} on both");
    assert!(kinds * 20 <= both, "{kinds} of {both} differ in kind");
    assert!(apart < 2e-3, "a white-water particle is {apart} m from the twin's");
}

/// Still liquid in a tank for half a second: no currents (every particle
/// under 5 mm/s), pressure ρ·g·d at each cell's depth d below the surface
/// (to 1 %), and the solve's residual met.
#[test]
fn a_tank_at_rest_keeps_hydrostatic_pressure() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = tank([0.0, 0.0, 0.0], [0.4, 0.15, 0.1]);
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.5);
    let l = r.read_liquid().expect("a liquid");
    let fastest = l
        .particles
        .iter()
        .map(|p| p.velocity.iter().map(|v| v * v).sum::<f32>().sqrt())
        .fold(0.0f32, f32::max);
    assert!(fastest < 5e-3, "fastest particle {fastest} m/s");
    let [nx, ny, _] = l.cells.map(|c| c as usize);
    // Six rows of liquid (0.15 m of 2.5 cm cells): the surface is at the
    // top row's top face, and p = 0 half a cell above it.
    let g = 9.81f32;
    for j in 0..6 {
        let c = (2 * ny + j) * nx + 8;
        let depth = (6 - j) as f32 * l.h;
        let want = 1000.0 * g * depth;
        assert!(
            (l.pressure[c] - want).abs() < 0.01 * want,
            "row {j}: {} Pa, ρgd = {want} Pa",
            l.pressure[c]
        );
    }
    assert!(l.max_liquid_divergence() <= 1.5 * s.fluid.tolerance, "{}", l.max_liquid_divergence());
}

/// The liquid's state at a time is the same bits whatever frames reached
/// it: one jump of 0.1 s, ten frames of 10 ms, and a second renderer.
#[test]
fn the_liquid_is_the_same_whatever_frames_reach_a_time() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
    let run = |frames: usize| {
        let mut r = renderer(&ctx, &s);
        for f in 1..=frames {
            r.simulate(&s.camera(), (16, 16), 0.1 * f as f64 / frames as f64);
        }
        r.read_liquid().expect("a liquid").particles
    };
    let once = run(1);
    assert_eq!(once, run(10));
    assert_eq!(once, run(1));
    // With a ball in it (rapier steps on the CPU between the clock steps,
    // under the loads read back): the ball and the liquid alike.
    let mut s = s.clone();
    s.objects = vec![hydrolux::core::scene::ObjectDesc {
        primitive: hydrolux::core::scene::Primitive::Sphere,
        position: [0.2, 0.06, 0.05],
        scale: [0.06; 3],
        dynamic: true,
        density: 300.0,
        ..Default::default()
    }];
    let run = |frames: usize| {
        let mut r = renderer(&ctx, &s);
        for f in 1..=frames {
            r.simulate(&s.camera(), (16, 16), 0.1 * f as f64 / frames as f64);
        }
        (r.read_liquid().expect("a liquid").particles, r.bodies()[0].pose)
    };
    let once = run(1);
    assert_eq!(once, run(10));
}

/// A block of liquid over the interactive water's pool (walls, 32 cells of
/// 6.25 cm), its domain reaching 5 cm under the level: the block falls
/// 0.2–0.3 m and lands.
fn block_over_a_pool() -> Scene {
    let mut s = ripple_scene("walls");
    s.drops.clear();
    s.emitters.clear();
    s.whitewater.particles = false;
    s.fluid.min = [-0.2, -0.05, -0.1];
    s.fluid.max = [0.2, 0.35, 0.1];
    s.fluid.resolution = 16;
    s.fluid.substeps = 1;
    s.fluid.tolerance = 1e-4;
    s.fluid.iterations = 100;
    s.fluid.sources = vec![FluidSource {
        min: [-0.05, 0.2, -0.05],
        max: [0.05, 0.3, 0.05],
        ..FluidSource::default()
    }];
    s.validate().expect("valid");
    s
}

/// The block falls into the pool on the GPU and on the twins (the liquid's
/// and the interactive water's, coupled step by step as the scheduler
/// does: each water step takes the landings of its clock steps before it
/// moves): every particle has landed by 0.3 s, the pool holds their water
/// (its volume above the level, to 0.1 %; measured 1e-6), and its heights
/// are the twins' (to 0.1 % of the waves; measured 3e-5).
/// The same bits whether 0.3 s is reached at once or in seven frames that
/// split the water's steps.
#[test]
fn a_block_falling_into_the_pool_becomes_its_water() {
    use hydrolux::core::waves::ripples::{RippleSim, RippleWindow};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let s = block_over_a_pool();
    let landing = s.fluid_landing().expect("the liquid lands in the pool");
    let t = 0.3;
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), t);
    let gpu = r.read_ripples().expect("dynamic water");
    assert!(r.read_liquid().expect("a liquid").particles.is_empty(), "all of it landed");

    let settings = s.ripple_settings().unwrap();
    let mut sim = RippleSim::new(settings, RippleWindow::centred(&settings.grid, [0.4, -0.3]));
    sim.kick_per_unit = hydrolux::core::coupling::kick_per_unit_of_volume(
        landing.particle_volume,
        settings.grid.cell_size,
    );
    let mut liquid = s.fluid_start().expect("the liquid starts");
    let particles = liquid.alive_count();
    let stride = (120 / s.ripples.rate) as u64;
    let clock_steps = (t * 120.0).round() as u64;
    for c in 0..clock_steps {
        liquid.step(s.fluid.step_seconds());
        if (c + 1) % stride == 0 {
            for l in liquid.landings.drain(..) {
                sim.land_liquid(l.position[0], l.position[1], -l.velocity[1], l.volume);
            }
            sim.step(&[]);
        }
    }
    assert_eq!(liquid.alive_count(), 0);
    let area = (settings.grid.cell_size * settings.grid.cell_size) as f32;
    let volume = particles as f64 * landing.particle_volume;
    let held = gpu.heights.iter().sum::<f32>() as f64 * area as f64;
    assert!((held - volume).abs() < 1e-3 * volume, "the pool holds {held:e} m³ of {volume:e}");
    let cpu = sim.heights();
    let level = volume / (settings.grid.extent() * settings.grid.extent());
    let scale = cpu.iter().fold(0.0f64, |m, h| m.max((h - level).abs()));
    assert!(scale > 10.0 * level, "the landing rang the water ({scale:e} m)");
    let worst =
        gpu.heights.iter().zip(&cpu).map(|(g, c)| (*g as f64 - c).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-3 * scale, "GPU vs twins max error {worst:e} m, waves {scale:e} m");

    let mut frames = renderer(&ctx, &s);
    for f in 1..=7 {
        frames.simulate(&s.camera(), (16, 16), t * f as f64 / 7.0);
    }
    assert_eq!(frames.read_ripples().unwrap().heights, gpu.heights);
}

/// The block plunging into the pool at 2 m/s with white water: the air it
/// carries under (β·V, `hydrolux_core::whitewater::entrained_air`) surfaces
/// as froth where it fell and shows as a plume of bubbles under it, as the
/// twins have it (the liquid's landings, each white-water step taking those
/// of its clock steps: `Plunge`, `FoamField`): the bubbles born within 15%
/// of the twin's expected count (each landing rounds its share at random),
/// every one under the block's footprint and within the plume's depth; the
/// froth over the plunge's reach as the twin spreads it (its total within
/// −5%/+20%, the steep rings adding their own; its mean distance from the
/// centre within 10%). The same foam bits and the
/// same bubbles when 0.3 s is reached in seven frames.
#[test]
fn a_block_plunging_into_the_pool_leaves_froth_and_a_plume_of_bubbles() {
    use hydrolux::core::whitewater::{
        BUBBLE, FoamField, FoamGrid, FoamStep, PLUME_DEPTH_PER_SPEED, PLUNGE_AIR_PER_BUBBLE,
        Plunge, entrained_air,
    };
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = block_over_a_pool();
    s.whitewater.particles = true;
    // Cells of 3 cm: a millimetre between the twins' particles seldom puts
    // one in another cell.
    s.whitewater.resolution = 64;
    s.validate().expect("valid");
    let landing = s.fluid_landing().expect("the liquid lands in the pool");
    let t = 0.3;
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), t);
    let gpu_foam = r.read_foam().expect("foam");
    let gpu_counts = r.particle_counts().expect("particles");
    let gpu_particles = r.read_particles().expect("particles");

    let side = gpu_foam.cells as f32 * gpu_foam.cell_size;
    let centre = [0, 1].map(|a| gpu_foam.origin[a] + 0.5 * side);
    let mut foam = FoamField::new(FoamGrid::centred(gpu_foam.cells, side, centre));
    let rate = s.whitewater.rate;
    let foam_step = FoamStep { dt: 1.0 / rate as f32, life: s.foam_life(), drift: [0.0, 0.0] };
    let stride = (120 / rate) as u64;
    let mut liquid = s.fluid_start().expect("the liquid starts");
    let (mut expected, mut twin_bubbles, mut fastest, mut step) = (0.0f64, 0usize, 0.0f32, 0);
    let mut pending = Vec::new();
    for c in 0..(t * 120.0).round() as u64 {
        liquid.step(s.fluid.step_seconds());
        pending.append(&mut liquid.landings);
        if (c + 1) % stride == 0 {
            for l in pending.drain(..) {
                let plunge = Plunge {
                    x: l.position[0] as f32,
                    z: l.position[1] as f32,
                    down_speed: -l.velocity[1] as f32,
                    volume: landing.particle_volume as f32,
                    clock_step: l.step as u32,
                };
                fastest = fastest.max(plunge.down_speed);
                let [x, z] = plunge.froth_at(step);
                foam.deposit(x, z, plunge.foam());
                expected += (entrained_air(plunge.volume, plunge.down_speed)
                    / PLUNGE_AIR_PER_BUBBLE) as f64;
                twin_bubbles += plunge.bubbles(step).len();
            }
            foam.step(&foam_step, &[], |_, _| 0.0);
            step += 1;
        }
    }
    assert_eq!(liquid.alive_count(), 0, "all of it landed");
    eprintln!(
        "bubbles born: GPU {}, twin {twin_bubbles}, expected {expected:.0}; fastest {fastest} m/s",
        gpu_counts.emitted
    );
    assert!(expected > 100.0, "the plunge entrains air for {expected} bubbles");
    let born = gpu_counts.emitted as f64;
    assert!((born - expected).abs() < 0.15 * expected, "GPU {born} bubbles, expected {expected}");
    assert!((twin_bubbles as f64 - expected).abs() < 0.15 * expected, "twin {twin_bubbles}");
    let depth = PLUME_DEPTH_PER_SPEED * fastest;
    for p in &gpu_particles {
        assert_eq!(p.kind, BUBBLE);
        let reach = 0.05 + 0.5 * depth + 1e-3;
        assert!(
            p.position[0].abs() <= reach && p.position[2].abs() <= reach,
            "a bubble at {:?}, outside the plunge",
            p.position
        );
        assert!(p.position[1] < 0.0 && p.position[1] > -0.01 - depth - 1e-3, "{:?}", p.position);
    }

    let n = foam.grid.cells as i32;
    let twin: Vec<f32> =
        (0..n * n).map(|k| foam.at(foam.grid.low[0] + k % n, foam.grid.low[1] + k / n)).collect();
    // Each landing's froth surfaces at a random spot in its plume's reach,
    // hashed from where it landed, so the twins' froth agrees in amount
    // and spread, not cell by cell (the GPU's landings are the twin's to
    // a millimetre, not to the bit). Over the plunge's reach (the block's
    // half-diagonal and the plume's depth) the two totals and their mean
    // distances from the centre agree (measured 0.101 against 0.098 m).
    let reach = (0.05f64 * std::f64::consts::SQRT_2 + depth as f64 + 0.02) as f32;
    let moments = |f: &[f32]| {
        let (mut total, mut moment) = (0.0f64, 0.0f64);
        for (k, &v) in f.iter().enumerate() {
            let (i, j) = ((k as i32 % n) as f32, (k as i32 / n) as f32);
            let x = gpu_foam.origin[0] + (i + 0.5) * gpu_foam.cell_size;
            let z = gpu_foam.origin[1] + (j + 0.5) * gpu_foam.cell_size;
            let r = x.hypot(z);
            if r < reach {
                total += v as f64;
                moment += (v * r) as f64;
            }
        }
        (total, moment / total.max(1e-12))
    };
    let (gt, gr) = moments(&gpu_foam.amount);
    let (ct, cr) = moments(&twin);
    eprintln!("froth within {reach:.3} m: GPU {gt:.1} at {gr:.4} m, twin {ct:.1} at {cr:.4} m");
    assert!(ct > 1.0, "the plunge left froth ({ct})");
    // The rings' own foam adds to the GPU's (measured 139.9 against 128.3).
    assert!(gt > 0.95 * ct && gt < 1.2 * ct, "froth: GPU {gt}, twin {ct}");
    assert!((gr - cr).abs() < 0.1 * cr, "froth's mean distance: GPU {gr} m, twin {cr} m");
    let mut frames = renderer(&ctx, &s);
    for f in 1..=7 {
        frames.simulate(&s.camera(), (16, 16), t * f as f64 / 7.0);
    }
    assert_eq!(frames.read_foam().unwrap().amount, gpu_foam.amount);
    let ids = |ps: Vec<hydrolux::core::whitewater::Particle>| {
        let mut ids: Vec<u32> = ps.iter().map(|p| p.id).collect();
        ids.sort_unstable();
        ids
    };
    assert_eq!(ids(frames.read_particles().unwrap()), ids(gpu_particles));
}

/// A ball of pine (500 kg/m³, 8 cm) dropped onto the water of a closed
/// tank 0.4 m square (16³ cells): rapier moves it under the pressure the
/// GPU reads back each clock step. Over 1.5 s it follows the CPU twin
/// (the same coupling in f64) to a fifth of a cell; its bobbing dies down
/// (the swing of its last half second under half its first bounce's) about
/// Archimedes' depth, within a cell (high, as the twin's: the free surface
/// sits half a cell above the particles); the liquid keeps out of it. (The
/// twin's own tests follow it to rest, for longer.) On OpenGL (the suite's
/// second run, several times slower at this) it checks the first half
/// second against the twin.
#[test]
fn a_ball_dropped_into_a_tank_floats_as_its_cpu_twin_does() {
    use hydrolux::core::scene::{ObjectDesc, Primitive};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
    s.fluid.max = [0.4, 0.4, 0.4];
    s.fluid.sources[0].max = [0.4, 0.2, 0.4];
    let radius = 0.08f32;
    s.objects = vec![ObjectDesc {
        primitive: Primitive::Sphere,
        position: [0.2, 0.2 + radius + 0.02, 0.2],
        scale: [2.0 * radius; 3],
        dynamic: true,
        density: 500.0,
        ..ObjectDesc::default()
    }];
    s.validate().expect("valid");
    let h = 0.4 / 16.0;
    let mut r = renderer(&ctx, &s);
    let mut twin = s.fluid_with_bodies().expect("it starts").expect("a body in the liquid");
    let particles = twin.liquid.alive_count() as f64;
    let mut heights = Vec::new();
    let mut first = Vec::new();
    let mut clock = 0;
    let whole = BACKENDS.is_none();
    for k in 1..=if whole { 12 } else { 4 } {
        let t = 0.125 * k as f64;
        r.simulate(&s.camera(), (16, 16), t);
        while clock < (t * 120.0).round() as usize {
            twin.step();
            clock += 1;
        }
        let gpu = r.bodies()[0];
        let (pose, ..) = twin.world().motions()[0];
        let apart = (gpu.pose.position - pose.position).length();
        eprintln!("t {t:.3}: GPU {:.4} m, twin {:.4} m", gpu.pose.position.y, pose.position.y);
        assert!(apart < 0.2 * h, "at {t} s the ball is {apart:.4} m from the twin's");
        if t >= 1.0 {
            heights.push(gpu.pose.position.y);
        } else if t >= 0.25 {
            first.push(gpu.pose.position.y);
        }
    }
    if !whole {
        return;
    }
    let range = |v: &[f64]| {
        v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
    };
    let mean = heights.iter().sum::<f64>() / heights.len() as f64;
    let volume = 4.0 / 3.0 * std::f64::consts::PI * (radius as f64).powi(3);
    let cap = volume * 0.5;
    let level = (particles * h.powi(3) / 8.0 + cap) / (0.4 * 0.4);
    // The cap of a sphere under the water that weighs what it does: half
    // of it for half water's density, so its centre sits at the level.
    let expected = level;
    assert!(
        mean - expected > 0.0 && mean - expected < h,
        "the ball rests at {mean:.4} m, Archimedes {expected:.4} m"
    );
    let (swing, bounce) = (range(&heights), range(&first));
    assert!(
        swing < 0.5 * bounce,
        "still bobbing {swing:.4} m high after its bounce of {bounce:.4} m"
    );
    let liquid = r.read_liquid().expect("a liquid");
    let centre = r.bodies()[0].pose.position;
    let inside = liquid
        .particles
        .iter()
        .filter(|p| {
            (glam::DVec3::from(p.position.map(|c| c as f64)) - centre).length()
                < radius as f64 - 0.25 * h
        })
        .count();
    assert_eq!(inside, 0, "particles inside the ball");
}

/// The liquid's surface by marching cubes (`fluid.surface =
/// "marching_cubes"`, a round of smoothing), made on the GPU for a
/// collapsing column at 0.1 s, against the CPU twin meshing the same
/// particles: the same triangles (to
/// a few in a thousand, the rounding of the f32 splat aside), area and
/// enclosed volume to 0.5 %; the GPU's mesh is closed and wound outwards;
/// unsmoothed and not carried through the walls, the surface encloses the
/// particles' volume (their count × the volume each stands for) to 10 %.
#[test]
fn the_liquid_surface_is_meshed_as_its_cpu_twin_meshes_it() {
    use hydrolux::core::fluid::surface as mc;
    use hydrolux::core::scene::FluidSurface;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
    s.fluid.surface = FluidSurface::MarchingCubes;
    s.fluid.surface_resolution = 32;
    s.fluid.surface_smoothing = 1;
    s.validate().expect("valid");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (16, 16), 0.1);
    let liquid = r.read_liquid().expect("a liquid");
    let gpu = r.read_liquid_surface().expect("a meshed surface");
    assert!(gpu.vertices_taken <= gpu.vertex_capacity);
    let positions: Vec<[f32; 3]> = liquid.particles.iter().map(|p| p.position).collect();
    let spacing = liquid.h / s.fluid.particles_per_axis() as f32;
    let grid = mc::SurfaceGrid::over(s.fluid.min, s.fluid.max, s.fluid.surface_resolution);
    assert_eq!(grid, gpu.grid);
    let field = s.fluid.surface_field;
    let walls = mc::Walls::of(&grid, [s.fluid.min, s.fluid.max], s.fluid.open_sides(), spacing);
    let mut values =
        mc::level(&grid, &mc::splat(&grid, &positions, spacing), spacing, field, &walls);
    mc::smooth(&grid, &mut values, s.fluid.surface_smoothing);
    let twin = mc::marching_cubes(&grid, &values, mc::ISO_LEVEL);
    let (nt, ng) = (twin.indices.len() as f64, gpu.mesh.indices.len() as f64);
    assert!(nt > 300.0 && (ng - nt).abs() <= 0.005 * nt, "{ng} indices, twin {nt}");
    let (at, ag) = (twin.area(), gpu.mesh.area());
    assert!((ag - at).abs() < 0.005 * at, "area {ag} m², twin {at} m²");
    let (vt, vg) = (twin.volume(), gpu.mesh.volume());
    assert!((vg - vt).abs() < 0.005 * vt, "volume {vg} m³, twin {vt} m³");
    // Closed and consistently wound: each directed edge once, with its twin.
    let mut edges = std::collections::HashMap::new();
    for t in gpu.mesh.indices.chunks_exact(3) {
        for v in 0..3 {
            *edges.entry((t[v], t[(v + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert!(n == 1 && edges.get(&(b, a)) == Some(&1), "edge {a}→{b}");
    }
    // Unsmoothed and not carried through the tank's walls, the surface
    // encloses the particles' volume (each a spacing cubed) to 10%.
    let particles = positions.len() as f64 * (spacing as f64).powi(3);
    let raw = mc::marching_cubes(
        &grid,
        &mc::level(
            &grid,
            &mc::splat(&grid, &positions, spacing),
            spacing,
            field,
            &mc::Walls::default(),
        ),
        mc::ISO_LEVEL,
    )
    .volume();
    assert!((raw / particles - 1.0).abs() < 0.1, "encloses {raw} m³, the particles {particles} m³");
    // Carried through the walls and floor, the mesh holds at least that.
    assert!(vg > particles, "meshed {vg} m³, the particles {particles} m³");
}

/// The liquid's surface as a screen-space mesh (`fluid.surface =
/// "screen_mesh"`, Table 1's defaults), made on the GPU for a collapsing
/// column at 0.1 s seen by the scene's camera on a 96 × 64 screen, against
/// the CPU twin meshing the same particles for the same view: the same
/// vertices and triangles (to 1 %, the f32 projection's rounding at the
/// circles' rims aside) and area (to 1 %); 30–70 % of its area faces the
/// camera (the front sheet; the rest, the back sheet, faces away), and it is a
/// consistently wound shell, closed but for under 2 % of its edges;
/// the mesh lies on the liquid (every vertex within two particle radii of
/// the particles' box).
#[test]
fn the_liquid_screen_mesh_is_made_as_its_cpu_twin_makes_it() {
    use hydrolux::core::fluid::screen_mesh as sm;
    use hydrolux::core::scene::FluidSurface;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
    s.fluid.surface = FluidSurface::ScreenMesh;
    s.camera.position = [0.2, 0.22, 0.4];
    s.camera.look_at = [0.1, 0.08, 0.05];
    s.validate().expect("valid");
    let mut r = renderer(&ctx, &s);
    r.simulate(&s.camera(), (96, 64), 0.1);
    let liquid = r.read_liquid().expect("a liquid");
    let gpu = r.read_liquid_screen_mesh().expect("a screen mesh");
    assert!(gpu.vertices_taken <= gpu.vertex_capacity);
    assert_eq!((gpu.grid.nx, gpu.grid.ny), (49, 33));
    let positions: Vec<[f32; 3]> = liquid.particles.iter().map(|p| p.position).collect();
    let params = sm::ScreenMeshParams::of(&s.fluid);
    let twin = sm::mesh(&gpu.view, &params, &positions);
    let (vt, vg) = (twin.mesh.positions.len() as f64, gpu.mesh.positions.len() as f64);
    assert!(vt > 200.0 && (vg - vt).abs() <= 0.01 * vt, "{vg} vertices, twin {vt}");
    let (nt, ng) = (twin.mesh.indices.len() as f64, gpu.mesh.indices.len() as f64);
    assert!((ng - nt).abs() <= 0.01 * nt, "{ng} indices, twin {nt}");
    let (at, ag) = (twin.mesh.area(), gpu.mesh.area());
    assert!(at > 0.0 && (ag - at).abs() < 0.01 * at, "area {ag} m², twin {at} m²");
    let eye = glam::Vec3::from(s.camera.position);
    let (lo, hi) = positions.iter().fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
        ([0, 1, 2].map(|k| lo[k].min(p[k])), [0, 1, 2].map(|k| hi[k].max(p[k])))
    });
    // The front sheet faces the camera and the back sheet away; about as
    // much of each.
    let (mut facing, mut total) = (0.0, 0.0);
    for t in gpu.mesh.triangles() {
        let [a, b, c] = t.map(glam::Vec3::from);
        let n = (b - a).cross(c - a);
        total += n.length();
        if n.dot(eye - a) > 0.0 {
            facing += n.length();
        }
    }
    assert!((facing / total - 0.5).abs() < 0.2, "{facing} of {total} faces the camera");
    for p in &gpu.mesh.positions {
        for k in 0..3 {
            let reach = 2.0 * params.radius;
            assert!(p[k] > lo[k] - reach && p[k] < hi[k] + reach, "vertex {p:?} off the liquid");
        }
    }
    for n in &gpu.mesh.normals {
        assert!((glam::Vec3::from(*n).length() - 1.0).abs() < 1e-3);
    }
    // A closed shell (front and back sheet meet at the outline), but
    // where two layers part: each directed edge once, nearly every one
    // with its twin.
    let mut edges = std::collections::HashMap::new();
    for t in gpu.mesh.indices.chunks_exact(3) {
        if t[0] != t[1] {
            for v in 0..3 {
                *edges.entry((t[v], t[(v + 1) % 3])).or_insert(0) += 1;
            }
        }
    }
    assert!(edges.values().all(|&n| n == 1));
    let open = edges.keys().filter(|(a, b)| !edges.contains_key(&(*b, *a))).count();
    assert!(open * 50 < edges.len(), "{open} open edges of {}", edges.len());
}

/// Screen-space fluid rendering on the GPU against its CPU twin: a
/// collapsing column at 0.1 s drawn on a 96 × 64 screen (the tank lifted
/// 0.3 m over the floor, so that no opaque surface cuts the spheres and
/// the twin needs no scene depth). The splatted depth covers the same
/// pixels with the same fronts, and after the narrow-range filter the
/// depth and thickness agree (the thickness is added in half floats on
/// the GPU).
#[test]
fn the_liquid_screen_space_images_are_drawn_as_their_cpu_twin_draws_them() {
    use hydrolux::core::fluid::screen_space as ss;
    use hydrolux::core::scene::FluidSurface;
    let lift = |p: [f32; 3]| [p[0], p[1] + 0.3, p[2]];
    let mut s = tank([0.0, 0.0, 0.0], [0.1, 0.2, 0.1]);
    s.fluid.min = lift(s.fluid.min);
    s.fluid.max = lift(s.fluid.max);
    for source in &mut s.fluid.sources {
        (source.min, source.max) = (lift(source.min), lift(source.max));
    }
    s.fluid.surface = FluidSurface::ScreenSpace;
    s.camera.position = [0.2, 0.52, 0.4];
    s.camera.look_at = [0.1, 0.38, 0.05];
    s.validate().expect("valid");
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer(&ctx, &s);
    let target = HeadlessTarget::new(&ctx.device, (96, 64));
    target.render(&mut r, s.camera(), 0.1).expect("frame");
    let liquid = r.read_liquid().expect("a liquid");
    let gpu = r.read_liquid_screen_space().expect("drawn in screen space");
    let positions: Vec<[f32; 3]> = liquid.particles.iter().map(|p| p.position).collect();
    let params = ss::ScreenSpaceParams::of(&s.fluid);
    let splat =
        ss::splat(&gpu.view, gpu.eye, (params.radius, params.volume_share), &positions, None);
    let filtered = ss::filter(&splat, &params, &gpu.view);
    let covered = splat.covered();
    assert!(covered > 600, "the liquid covers {covered} pixels");
    let (mut only_one, mut worst_front) = (0, 0.0f32);
    for (a, b) in gpu.splatted_depth.iter().zip(&splat.depth) {
        if (*a > 0.0) != (*b > 0.0) {
            only_one += 1;
        } else if *a > 0.0 {
            worst_front = worst_front.max((a - b).abs());
        }
    }
    // Pixels a sphere's outline grazes may fall either way.
    assert!(only_one * 100 <= covered, "{only_one} of {covered} pixels covered by one alone");
    assert!(worst_front < 1e-4, "fronts differ by {worst_front} m");
    let (mut depth_error, mut thickness_error, mut thickness_sum, mut n) = (0.0f32, 0.0, 0.0, 0);
    for i in 0..filtered.depth.len() {
        let (a, b) = (gpu.filtered.depth[i], filtered.depth[i]);
        if a > 0.0 && b > 0.0 {
            depth_error = depth_error.max((a - b).abs());
            thickness_error += (gpu.filtered.thickness[i] - filtered.thickness[i]).abs();
            thickness_sum += filtered.thickness[i];
            n += 1;
        }
    }
    assert!(n * 100 >= covered * 98, "{n} of {covered} pixels filtered on both");
    // A pixel whose neighbour's coverage differs is filtered differently.
    assert!(depth_error < 0.2 * params.radius, "filtered depths differ by {depth_error} m");
    let mean = thickness_sum / n as f32;
    assert!(mean > 0.02, "mean thickness {mean} m");
    assert!(
        thickness_error < 0.01 * thickness_sum,
        "thickness differs by {} of {thickness_sum}",
        thickness_error
    );
}

/// The liquid drawn by screen-space fluid rendering casts caustics: from
/// the sun, a block at rest (0.6 m square, 0.4 m deep) is splatted and
/// filtered in the refractive things' light view as its CPU twin does it
/// (`SunView`: the same texels covered, the same fronts, the filtered
/// depth and back alike), and the light through it lands on the floor as
/// the light through the marching-cubes mesh of the same particles does
/// (their totals within 25% at 128² texels: 16% apart, the mesh's bottom
/// flat under the floor, the spheres' bumpy at it). Most of what enters
/// lands (66%, the mesh's 78%): the block rests on the floor, so a path
/// meets it inside the water; what is lost is light from the top that
/// meets the far wall beyond the critical angle (a path leaves by one exit).
#[test]
fn the_liquid_in_screen_space_casts_the_caustics_its_mesh_casts() {
    use hydrolux::core::fluid::screen_space as ss;
    use hydrolux::core::scene::FluidSurface;
    let mut s = block_at_rest(&["godrays.object_resolution=128".into()]);
    s.fluid.surface = FluidSurface::ScreenSpace;
    s.validate().expect("valid");
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer(&ctx, &s);
    let target = HeadlessTarget::new(&ctx.device, (48, 32));
    target.render(&mut r, s.camera(), 0.0).expect("frame");
    let liquid = r.read_liquid().expect("a liquid");
    let sun = r.read_liquid_screen_space_sun().expect("made from the sun");
    let positions: Vec<[f32; 3]> = liquid.particles.iter().map(|p| p.position).collect();
    let params = ss::ScreenSpaceParams::of(&s.fluid);
    let splat = sun.view.splat(params.radius, &positions);
    let filtered = sun.view.filter(&splat, &params);
    let covered = splat.covered();
    assert!(covered > 200, "the liquid covers {covered} texels");
    let (mut only_one, mut worst_front) = (0, 0.0f32);
    for (a, b) in sun.splatted_depth.iter().zip(&splat.depth) {
        if (*a > 0.0) != (*b > 0.0) {
            only_one += 1;
        } else if *a > 0.0 {
            worst_front = worst_front.max((a - b).abs());
        }
    }
    assert!(only_one * 100 <= covered, "{only_one} of {covered} texels covered by one alone");
    assert!(worst_front < 1e-3, "fronts differ by {worst_front} m");
    let (mut depth_errors, mut thickness_error, mut thickness_sum) = (Vec::new(), 0.0, 0.0);
    for i in 0..filtered.depth.len() {
        let (a, b) = (sun.filtered.depth[i], filtered.depth[i]);
        if a > 0.0 && b > 0.0 {
            depth_errors.push((a - b).abs());
            thickness_error += (sun.filtered.thickness[i] - filtered.thickness[i]).abs();
            thickness_sum += filtered.thickness[i];
        }
    }
    // A texel whose neighbour's coverage differs is filtered differently.
    depth_errors.sort_by(|a, b| a.total_cmp(b));
    let (p99, worst) =
        (depth_errors[depth_errors.len() * 99 / 100], depth_errors[depth_errors.len() - 1]);
    eprintln!(
        "filtered depths differ by {p99} m (99th percentile), {worst} m at most; r = {}",
        params.radius
    );
    assert!(p99 < 0.1 * params.radius && worst < 0.5 * params.radius, "{p99}, {worst} m");
    assert!(thickness_error < 0.01 * thickness_sum, "thickness differs by {thickness_error}");

    let landed = |r: &hydrolux::Renderer| {
        let (_, map) = r.read_object_caustics();
        map.iter().map(|m| m[2]).sum::<f32>()
    };
    let through_screen_space = landed(&r);
    s.fluid.surface = FluidSurface::MarchingCubes;
    r.set_scene(&s).expect("the mesh instead");
    target.render(&mut r, s.camera(), 0.0).expect("frame");
    let through_mesh = landed(&r);
    eprintln!(
        "{covered} texels; landed {through_screen_space} (screen space), {through_mesh} (mesh)"
    );
    assert!(
        (through_screen_space / through_mesh - 1.0).abs() < 0.25,
        "{through_screen_space} through the screen-space surface, {through_mesh} through the mesh"
    );
    let entering = covered as f32;
    assert!(
        through_screen_space > 0.5 * entering && through_screen_space < entering,
        "{through_screen_space} of the light over {entering} texels"
    );
}

/// A block of liquid at rest, 0.6 m square and 0.4 m deep on the floor,
/// meshed by marching cubes, in water with the medium `sets` give.
fn block_at_rest(sets: &[String]) -> Scene {
    use hydrolux::core::scene::FluidSurface;
    let mut s = Scene::load("dam_break", sets).expect("built-in");
    s.objects.clear();
    s.fluid.min = [-0.3, 0.0, -0.3];
    s.fluid.max = [0.3, 0.6, 0.3];
    s.fluid.resolution = 12;
    s.fluid.surface_resolution = 24;
    s.fluid.sources = vec![FluidSource {
        min: [-0.3, 0.0, -0.3],
        max: [0.3, 0.4, 0.3],
        ..FluidSource::default()
    }];
    s.fluid.surface = FluidSurface::MarchingCubes;
    s
}

/// A camera inside the liquid (its lens under the meshed surface of a block
/// at rest, 0.6 m square and 0.4 m deep) looking down at the floor: every
/// pixel's near-plane point is inside (the stencil's face count), the floor
/// lies against the liquid (no air between), so each pixel is the image
/// behind the liquid carried through the water alone. With a purely
/// absorbing medium that is Beer–Lambert exactly: the image behind times
/// e^(−a·d), d the distance to the floor along the pixel's ray.
#[test]
fn a_camera_inside_the_liquid_sees_the_floor_through_the_water() {
    let absorption = [1.5f32, 3.0, 6.0];
    let sets = ["water.absorption=[1.5, 3.0, 6.0]".into(), "water.scattering=[0, 0, 0]".into()];
    let mut s = block_at_rest(&sets);
    s.camera.position = [0.0, 0.25, 0.0];
    s.camera.look_at = [0.0, 0.0, -0.02];
    s.validate().expect("valid");
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer(&ctx, &s);
    let target = HeadlessTarget::new(&ctx.device, (64, 48));
    target.render(&mut r, s.camera(), 0.0).expect("frame");
    let (w, h, seen) = r.read_hdr().expect("an image");
    let (_, _, behind) = r.read_behind_water_objects().expect("the liquid is drawn");
    let inverse = s.camera().view_projection(w as f32 / h as f32).inverse();
    let eye = glam::Vec3::from(s.camera.position);
    let floor = -s.floor.depth;
    let (mut worst, mut checked) = (0.0f32, 0);
    for y in 0..h {
        for x in 0..w {
            let ndc =
                [2.0 * (x as f32 + 0.5) / w as f32 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5) / h as f32];
            let far = inverse.project_point3(glam::Vec3::new(ndc[0], ndc[1], 0.5));
            let dir = (far - eye).normalize();
            let d = (floor - eye.y) / dir.y;
            let i = (y * w + x) as usize;
            for c in 0..3 {
                let expected = behind[i][c] * (-absorption[c] * d).exp();
                // Half-float images: a relative 1e-3, and a floor
                // absolute for the dimmest channel.
                let error = (seen[i][c] - expected).abs() / (expected.abs() + 1e-3);
                worst = worst.max(error);
            }
            checked += 1;
        }
    }
    assert_eq!(checked, w * h);
    eprintln!("{checked} pixels, worst relative error {worst}");
    assert!(worst < 0.02, "a pixel differs from Beer–Lambert through the water by {worst}");
    // And the water was there: even red, the least absorbed, loses a third.
    let mean =
        |img: &[[f32; 4]], c: usize| img.iter().map(|p| p[c]).sum::<f32>() / img.len() as f32;
    assert!(mean(&seen, 0) < 0.7 * mean(&behind, 0), "red barely absorbed");
}

/// From inside the same block, looking up at its flat top through strongly
/// absorbing water: within the critical angle (48.6° from the normal for
/// n = 1.333) the sky comes through Snell's window, n² brighter; beyond it
/// the surface reflects totally and only light that went twice as far
/// through the water remains. The window's edge is where Snell puts it.
#[test]
fn a_camera_inside_the_liquid_sees_snells_window() {
    let sets = ["water.absorption=[40, 40, 40]".into(), "water.scattering=[0, 0, 0]".into()];
    let mut s = block_at_rest(&sets);
    s.camera.position = [0.0, 0.34, 0.0];
    s.camera.look_at = [0.0, 1.0, -0.02];
    s.camera.fov_y_deg = 100.0;
    s.validate().expect("valid");
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer(&ctx, &s);
    let target = HeadlessTarget::new(&ctx.device, (64, 48));
    target.render(&mut r, s.camera(), 0.0).expect("frame");
    let (w, h, seen) = r.read_hdr().expect("an image");
    let inverse = s.camera().view_projection(w as f32 / h as f32).inverse();
    let eye = glam::Vec3::from(s.camera.position);
    let critical = (1.0 / s.water.ior).asin().to_degrees();
    let (mut window, mut mirror) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let ndc =
                [2.0 * (x as f32 + 0.5) / w as f32 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5) / h as f32];
            let far = inverse.project_point3(glam::Vec3::new(ndc[0], ndc[1], 0.5));
            let from_up = (far - eye).normalize().y.acos().to_degrees();
            let p = seen[(y * w + x) as usize];
            let luminance = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            if from_up < critical - 3.0 {
                window.push(luminance);
            } else if from_up > critical + 3.0 {
                mirror.push(luminance);
            }
        }
    }
    assert!(window.len() > 300 && mirror.len() > 100, "{} {}", window.len(), mirror.len());
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let dimmest_window = window.iter().copied().fold(f32::MAX, f32::min);
    let brightest_mirror = mirror.iter().copied().fold(0.0f32, f32::max);
    eprintln!(
        "critical {critical:.1}°: window mean {} (least {dimmest_window}), mirror mean {} (most {brightest_mirror})",
        mean(&window),
        mean(&mirror)
    );
    assert!(dimmest_window > 2.0 * brightest_mirror, "no edge at the critical angle");
}

/// The error view of a liquid without surface water compares its surface
/// with marching cubes on the finest grid (`hydrolux compare --surfaces`'
/// reference), live: the heat of ΔE*ab between the frame as drawn (here in
/// screen space) and the reference, per pixel, as hydrolux-core `compare`
/// computes it from the two frames rendered apart.
#[test]
fn the_error_view_compares_the_liquids_surface_with_the_finest_mesh() {
    use hydrolux::core::compare::{delta_e, heat};
    use hydrolux::core::scene::{DebugView, FluidSurface, MAX_SURFACE_RESOLUTION};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut base = Scene::load("dam_break", &[]).expect("built-in");
    base.fluid.resolution = 16;
    // The error view fits the sun's view of the liquid to both drawings by
    // its own grid's cell: at the finest, as the reference rendered apart.
    base.fluid.surface_resolution = MAX_SURFACE_RESOLUTION;
    base.validate().expect("valid");
    let (size, t) = ((96, 64), 0.3);
    let frame = |s: &Scene| {
        let mut r = renderer(&ctx, s);
        let target = HeadlessTarget::new(&ctx.device, size);
        target.render(&mut r, s.camera(), t).expect("frame")
    };
    let mut s = base.clone();
    s.fluid.surface = FluidSurface::ScreenSpace;
    let drawn = frame(&s);
    let mut reference = base.clone();
    reference.fluid.surface = FluidSurface::MarchingCubes;
    let finest = frame(&reference);
    s.render.view = DebugView::Error;
    s.validate().expect("the error view of a liquid without water");
    let error = frame(&s);
    let (mut off, mut hot, n) = (0, 0, (size.0 * size.1) as usize);
    for p in 0..n {
        let rgb = |v: &[u8]| [v[4 * p], v[4 * p + 1], v[4 * p + 2]];
        let e = delta_e(rgb(&drawn), rgb(&finest));
        let got = rgb(&error);
        if heat(e).iter().zip(&got).any(|(a, b)| a.abs_diff(*b) > 2) {
            off += 1;
        }
        hot += (e > 3.0) as usize;
    }
    eprintln!("{hot} of {n} pixels differ by more than ΔE 3; {off} off the CPU's heat");
    assert!(hot > n / 100, "the surfaces differ somewhere: {hot} of {n} pixels");
    assert!(off <= n / 200, "{off} of {n} pixels off the CPU's heat");
}
