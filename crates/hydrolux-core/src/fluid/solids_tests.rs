//! Bodies in the liquid against Archimedes and the knock of a surge.

use super::*;
use crate::bodies::{BodiesDesc, BodyDesc, BodyWorld};
use crate::coupling::{Pose, Shape};
use glam::{DQuat, DVec3};

const G: f64 = 9.81;
const RHO: f64 = 1000.0;

/// A closed tank of `n` cells of `h` from `origin`, holding nothing yet.
fn tank(n: [usize; 3], h: f64, origin: [f64; 3]) -> Liquid {
    let settings = LiquidSettings { tolerance: 1e-3, ..Default::default() };
    Liquid::new(MacGrid::new(n, h, origin), settings)
}

#[test]
fn the_liquid_presses_on_a_sunk_ball_with_its_weight_of_water() {
    // A ball held still deep in a tank at rest: the pressure over its
    // faces is Archimedes' ρ·g·V upwards, nothing sideways, no torque.
    let (h, dt, radius) = (0.025, 1.0 / 240.0, 0.1);
    let mut liquid = tank([16, 16, 16], h, [0.0; 3]);
    let centre = DVec3::new(0.2, 0.15, 0.2);
    liquid.bodies = vec![LiquidBody {
        shape: Shape::Sphere { radius },
        pose: Pose { position: centre, rotation: DQuat::IDENTITY },
        velocity: DVec3::ZERO,
        angular_velocity: DVec3::ZERO,
    }];
    liquid.place_bodies();
    liquid.fill_box([0.0; 3], [0.4, 0.35, 0.4], 2);
    let mut force = DVec3::ZERO;
    let mut torque = DVec3::ZERO;
    let steps = 10;
    for _ in 0..steps {
        liquid.step(dt);
        force += liquid.loads[0].force / steps as f64;
        torque += liquid.loads[0].torque / steps as f64;
    }
    let weight = RHO * G * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    // The ball is four cells across its radius: its cells' volume is
    // within 5% of the sphere's.
    assert!((force.y / weight - 1.0).abs() < 0.05, "buoyancy {:.2} N, ρgV {weight:.2} N", force.y);
    assert!(force.x.abs().max(force.z.abs()) < 0.01 * weight, "sideways {force:?}");
    assert!(torque.length() < 0.01 * weight * radius, "torque {torque:?}");
    assert_eq!(liquid.loads[0].wetted, 1.0);
}

/// A tank 0.4 m square, its floor at y = −0.4 and walls round it, for
/// rapier; and the body world of `bodies` in it.
fn world_in_tank(bodies: Vec<BodyDesc>, dt: f64, size: [f64; 3]) -> BodyWorld {
    let wall = |centre: [f64; 3], scale: [f64; 3]| BodyDesc {
        transform: glam::Mat4::from_translation(glam::DVec3::from(centre).as_vec3()),
        shape: Some(Shape::Box { half: DVec3::from(scale) * 0.5 }),
        scale: scale.map(|c| c as f32),
        velocity: [0.0; 3],
        path: None,
        dynamic: false,
        density: 1000.0,
        elsewhere: false,
    };
    let [x, y, z] = size;
    let mut objects = vec![
        wall([-0.05, -y / 2.0, z / 2.0], [0.1, y, z + 0.2]),
        wall([x + 0.05, -y / 2.0, z / 2.0], [0.1, y, z + 0.2]),
        wall([x / 2.0, -y / 2.0, -0.05], [x + 0.2, y, 0.1]),
        wall([x / 2.0, -y / 2.0, z + 0.05], [x + 0.2, y, 0.1]),
    ];
    objects.extend(bodies);
    BodyWorld::new(&BodiesDesc { floor_depth: y as f32, objects }, dt).expect("a body moves")
}

fn ball(centre: DVec3, radius: f64, density: f32) -> BodyDesc {
    BodyDesc {
        transform: glam::Mat4::from_translation(centre.as_vec3()),
        shape: Some(Shape::Sphere { radius }),
        scale: [2.0 * radius as f32; 3],
        velocity: [0.0; 3],
        path: None,
        dynamic: true,
        density,
        elsewhere: false,
    }
}

/// The depth of a sphere's cap of `volume` (m³).
fn cap_depth(radius: f64, volume: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 2.0 * radius);
    for _ in 0..60 {
        let d = 0.5 * (lo + hi);
        let v = std::f64::consts::PI * d * d * (3.0 * radius - d) / 3.0;
        if v < volume { lo = d } else { hi = d }
    }
    0.5 * (lo + hi)
}

/// A ball of `density` dropped onto a tank of water.
fn drop_ball(density: f32) {
    // A ball dropped onto a tank of water comes to rest with the cap under the water that
    // weighs what it does, without blowing up (a ball of a fifth of water's
    // density has an added mass 2.5 times its own: explicitly coupled, it
    // would). The
    // water's level is its particles' volume plus the cap's over the
    // tank's floor. The pressure's free surface sits half a cell above the
    // particles' top (p = 0 at the air cells' centres, no ghost fluid) and
    // the ball is its cells (their centres inside it), so it floats up to
    // a cell high: measured 0.85 cells at half density, 0.36 at a fifth,
    // its radius 3.2 cells.
    let (h, dt, radius) = (0.025, 1.0 / 240.0, 0.08);
    let size = [0.4, 0.4, 0.4];
    {
        let mut liquid = tank([16, 16, 16], h, [0.0, -0.4, 0.0]);
        liquid.fill_box([0.0, -0.4, 0.0], [0.4, -0.2, 0.4], 2);
        let particles = liquid.alive_count() as f64;
        let start = DVec3::new(0.2, -0.2 + radius + 0.02, 0.2);
        let world = world_in_tank(vec![ball(start, radius, density)], dt, size);
        let mut both = LiquidWithBodies::new(liquid, world, 1);
        let mut heights = Vec::new();
        for step in 0..480 {
            both.step();
            let (pose, ..) = both.world().motions()[0];
            assert!(pose.position.is_finite(), "density {density}: the ball flew off at {step}");
            if step >= 360 {
                heights.push(pose.position.y);
            }
        }
        let mean = heights.iter().sum::<f64>() / heights.len() as f64;
        let swing = heights.iter().fold(0.0f64, |m, y| m.max((y - mean).abs()));
        let volume = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
        let cap = volume * density as f64 / RHO;
        let level = -0.4 + (particles * h.powi(3) / 8.0 + cap) / (size[0] * size[2]);
        let expected = level - cap_depth(radius, cap) + radius;
        let (_, v, _) = both.world().motions()[0];
        assert!(
            mean - expected > 0.0 && mean - expected < h,
            "density {density}: the ball rests at {mean:.4} m, Archimedes {expected:.4} m (level {level:.4})"
        );
        assert!(swing < 0.5 * h, "density {density}: still bobbing ±{swing:.4} m");
        assert!(v.length() < 0.1, "density {density}: still moving at {v:?}");
    }
}

#[test]
fn a_dropped_ball_of_half_waters_density_floats_as_deep_as_archimedes_says() {
    drop_ball(500.0);
}

#[test]
fn a_dropped_ball_of_a_fifth_of_waters_density_floats_as_deep_as_archimedes_says() {
    drop_ball(200.0);
}

#[test]
fn a_collapsing_column_knocks_over_a_box_standing_in_its_way() {
    // The dam break of the tank's left third onto a box of pine (500
    // kg/m³), 5 × 12 × 8 cm, standing on the floor downstream: the surge
    // arrives at about 2 m/s and tips it over (past 45°) and sweeps it
    // downstream, and the box never leaves the tank.
    let (h, dt) = (0.02, 1.0 / 240.0);
    let size = [0.6, 0.3, 0.12];
    let mut liquid = tank([30, 15, 6], h, [0.0, -0.3, 0.0]);
    liquid.fill_box([0.0, -0.3, 0.0], [0.2, -0.05, 0.12], 2);
    let half = DVec3::new(0.025, 0.06, 0.04);
    let standing = DVec3::new(0.42, -0.3 + half.y, 0.06);
    let box_body = BodyDesc {
        transform: glam::Mat4::from_translation(standing.as_vec3()),
        shape: Some(Shape::Box { half }),
        scale: (2.0 * half).as_vec3().to_array(),
        velocity: [0.0; 3],
        path: None,
        dynamic: true,
        density: 500.0,
        elsewhere: false,
    };
    let world = world_in_tank(vec![box_body], dt, size);
    let mut both = LiquidWithBodies::new(liquid, world, 1);
    let mut tilt = 0.0f64;
    let mut tipped_at = None;
    let mut furthest = standing.x;
    for step in 0..360 {
        both.step();
        let (pose, ..) = both.world().motions()[0];
        let up = pose.rotation * DVec3::Y;
        tilt = up.y.clamp(-1.0, 1.0).acos().to_degrees();
        furthest = furthest.max(pose.position.x);
        if tilt > 45.0 && tipped_at.is_none() {
            tipped_at = Some(step as f64 * dt);
        }
        assert!(
            (0.0..size[0]).contains(&pose.position.x) && pose.position.y > -0.3,
            "the box left the tank at step {step}: {:?}",
            pose.position
        );
    }
    let (pose, ..) = both.world().motions()[0];
    eprintln!(
        "tipped at {tipped_at:?}, final tilt {tilt:.0}°, at {:?}, furthest x {furthest:.3}",
        pose.position
    );
    assert!(tipped_at.is_some(), "the box stood: tilt {tilt:.0}°");
    // Not before the surge reached it: Martin & Moyce's front gets 0.3 m
    // from the column's foot (x/a = 2.1 with a = 0.2 m) at
    // T = t·√(2g/a) ≈ 1.6, t ≈ 0.16 s.
    assert!(tipped_at.unwrap() > 0.15, "tipped at {tipped_at:?}");
    // Pushed downstream first (then afloat, it rides the wave back from
    // the far wall).
    assert!(furthest > standing.x + 0.05, "the box was not swept: furthest x {furthest:.3}");
}

#[test]
fn a_ball_set_moving_in_still_water_meets_its_added_mass() {
    // A ball held at rest deep in still water, then moved at U: the first
    // step's pressure is the potential flow's impulse (p·dt/ρ = φ, with
    // ∂φ/∂n = U·n on the ball), and its force the added mass's −m_a·U/dt.
    // In open water m_a = ½ρV (Lamb §92); in a sphere of water of radius
    // b it is ½ρV·(1 + 2a³/b³)/(1 − a³/b³), and a cube of side 0.5 m
    // confines the ball (a = 0.1 m) between the spheres it holds
    // (b = 0.25 m: ×1.21) and of its volume (b = 0.31 m: ×1.10). The ball
    // is 8 cells across its radius (at 4 the staircase adds 10%).
    let (h, dt, radius, speed) = (0.0125, 1.0 / 240.0, 0.1, 0.1);
    let mut liquid = tank([40, 40, 40], h, [0.0; 3]);
    let mut ball = LiquidBody {
        shape: Shape::Sphere { radius },
        pose: Pose { position: DVec3::splat(0.25), rotation: DQuat::IDENTITY },
        velocity: DVec3::ZERO,
        angular_velocity: DVec3::ZERO,
    };
    liquid.bodies = vec![ball];
    liquid.place_bodies();
    // Water to 2.5 cm under the lid.
    liquid.fill_box([0.0; 3], [0.5, 0.475, 0.5], 2);
    liquid.step(dt);
    let resting = liquid.loads[0].force;
    ball.velocity = DVec3::X * speed;
    liquid.bodies = vec![ball];
    liquid.step(dt);
    let push = liquid.loads[0].force - resting;
    let volume = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    let ratio = -push.x / (0.5 * RHO * volume * speed / dt);
    assert!((1.10 * 0.95..1.21 * 1.05).contains(&ratio), "added mass {ratio:.3} × ½ρV");
    assert!(push.y.abs().max(push.z.abs()) < 0.02 * push.x.abs(), "{push:?}");
}

/// A dam break in a tank 0.8 × 0.4 × 0.4 m (2.5 cm cells) from its left
/// quarter, `objects` in it.
fn tank_scene(objects: Vec<crate::scene::ObjectDesc>) -> crate::scene::Scene {
    use crate::scene::{FluidSource, Scene};
    let mut s = Scene::default();
    s.fluid.min = [0.0, 0.0, 0.0];
    s.fluid.max = [0.8, 0.4, 0.4];
    s.fluid.resolution = 32;
    s.fluid.substeps = 2;
    s.fluid.sources =
        vec![FluidSource { min: [0.0; 3], max: [0.2, 0.3, 0.4], ..FluidSource::default() }];
    s.objects = objects;
    s.validate().expect("valid");
    s
}

#[test]
fn a_closed_mesh_is_a_solid_as_big_as_it_is_and_an_open_one_is_refused() {
    use crate::geometry::load::builtin_mesh;
    use crate::scene::ObjectDesc;
    // The bunny (0.3 m tall) mid-tank: its cells hold its volume (the
    // divergence theorem over its triangles) to within 10%, and the surge
    // flows round it, never into it.
    let bunny = ObjectDesc {
        mesh: "builtin:bunny".into(),
        position: [0.5, 0.0, 0.2],
        scale: [0.3; 3],
        ..ObjectDesc::default()
    };
    let s = tank_scene(vec![bunny.clone()]);
    let mut liquid = s.fluid_start().expect("a closed mesh");
    let mesh = builtin_mesh("bunny").unwrap();
    let t =
        crate::geometry::sdf::Triangles::of(&mesh, &crate::scene::Scene::object_transform(&bunny));
    let volume: f64 = t.0.iter().map(|[a, b, c]| a.dot(b.cross(*c)) / 6.0).sum::<f64>().abs();
    let h = liquid.grid.h;
    let solid = liquid.grid.cells.iter().filter(|c| **c == Cell::Solid).count() as f64;
    assert!((solid * h.powi(3) / volume - 1.0).abs() < 0.1, "{solid} cells for {volume} m³");
    for _ in 0..120 {
        liquid.step(s.fluid.step_seconds());
    }
    let in_solid = liquid.live_positions().filter(|p| {
        let c = [0, 1, 2].map(|a| ((p[a] - liquid.grid.origin[a]) / h).floor() as usize);
        liquid.grid.cells[liquid.grid.cell(c[0], c[1], c[2])] == Cell::Solid
    });
    assert_eq!(in_solid.count(), 0, "particles inside the bunny");
    assert!(liquid.live_positions().any(|p| p[0] > 0.6), "the surge did not pass the bunny");

    // An open box (a cube without its top) has no inside.
    let dir = std::env::temp_dir().join(format!("hydrolux-open-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cube = crate::geometry::primitives::cube();
    let mut obj = String::new();
    for p in &cube.positions {
        obj += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for t in cube.indices.chunks_exact(3) {
        // Leave out the two triangles facing up.
        if t.iter().all(|&i| cube.positions[i as usize].y > 0.49) {
            continue;
        }
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(dir.join("open.obj"), obj).unwrap();
    let mut s = tank_scene(vec![ObjectDesc {
        mesh: "open.obj".into(),
        position: [0.5, 0.1, 0.2],
        scale: [0.1; 3],
        ..ObjectDesc::default()
    }]);
    s.base_dir = dir.clone();
    let e = s.fluid_start().expect_err("an open mesh").to_string();
    assert!(e.contains("open.obj") && e.contains("4 open edges"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_ground_is_a_solid_the_liquid_rests_on() {
    // A domain reaching 0.2 m under the mean level over a floor 0.1 m
    // down: the cells under the floor are solid, and a block dropped from
    // above comes to rest on it.
    use crate::scene::FluidSource;
    let mut s = tank_scene(Vec::new());
    s.floor.depth = 0.1;
    s.fluid.min = [0.0, -0.2, 0.0];
    s.fluid.sources =
        vec![FluidSource { min: [0.0, 0.0, 0.0], max: [0.8, 0.1, 0.4], ..FluidSource::default() }];
    s.validate().expect("valid");
    let mut liquid = s.fluid_start().expect("starts");
    let h = liquid.grid.h;
    let solid = liquid.grid.cells.iter().filter(|c| **c == Cell::Solid).count();
    assert_eq!(solid, 32 * 4 * 16, "the four layers under the floor");
    for _ in 0..240 {
        liquid.step(s.fluid.step_seconds());
    }
    let lowest = liquid.live_positions().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    assert!(lowest > -0.1 && lowest < -0.1 + h, "the lowest particle is at {lowest} m");
}

#[test]
fn a_moving_body_that_starts_in_the_domain_is_the_liquid_s() {
    // dam_break's pine block: the liquid's world moves it (with the
    // domain's six closed sides as walls), the surface water's has none.
    let s = crate::scene::Scene::load("dam_break", &[]).expect("built-in");
    let block = s.objects.iter().position(|o| o.dynamic).expect("a moving block");
    assert!(s.in_liquid(&s.objects[block]));
    assert!(BodyWorld::new(&s.surface_bodies(), 1.0 / 120.0).is_none());
    let desc = s.liquid_bodies().expect("the liquid has a body");
    assert_eq!(desc.objects.len(), s.objects.len() + 6);
    let world = BodyWorld::new(&desc, 1.0 / 120.0).expect("it moves");
    assert_eq!(world.bodies.len(), 1);
    assert_eq!(world.bodies[0].object, block);
    // Moved out of the domain, it floats on the surface water instead.
    let mut outside = s.clone();
    outside.objects[block].position = [2.0, 0.1, 0.0];
    assert!(outside.liquid_bodies().is_none());
    assert!(BodyWorld::new(&outside.surface_bodies(), 1.0 / 120.0).is_some());
    // At most eight start in it (the GPU's table).
    let mut many = s.clone();
    many.objects.extend(std::iter::repeat_n(s.objects[block].clone(), 8));
    let err = many.validate().unwrap_err().to_string();
    assert!(err.contains("at most 8 moving objects"), "{err}");
}
