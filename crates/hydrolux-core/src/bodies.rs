//! Rigid bodies in the water (seed 003 §2.4, two-way coupling of objects
//! and heightfields): rapier3d moves the scene's dynamic objects (contacts
//! with the floor, static objects and each other); buoyancy and drag come
//! from the water surface handed in (the one the GPU draws: the surface
//! model plus the interactive water), integrated column by column over each
//! body's footprint. A body's columns are also what it gives to or takes
//! from the water each step (`waves::ripples`): the GPU twin is
//! `body_column` in `simulation/ripples/ripples.wgsl`.

pub use crate::coupling::{Pose, Shape, body_column};
use glam::{DQuat, DVec3};
use rapier3d::prelude as rp;

/// What the body world is built from: the floor and each of the scene's
/// objects as physics sees it (`Scene::bodies` describes a scene's).
#[derive(Clone, Debug, PartialEq)]
pub struct BodiesDesc {
    /// Depth (m) of the flat floor under the mean level (0: none).
    pub floor_depth: f32,
    /// Every object, in the scene's order (a body's `object` is its index).
    pub objects: Vec<BodyDesc>,
}

/// One object as physics sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDesc {
    /// Where it starts: scale, rotation and translation.
    pub transform: glam::Mat4,
    /// Its exact shape (`None`: a mesh or a shape the scaling squashes,
    /// an obstacle of its box `scale` wide).
    pub shape: Option<Shape>,
    pub scale: [f32; 3],
    /// m/s; a kinematic object keeps it.
    pub velocity: [f32; 3],
    /// A kinematic object's scripted path (its velocity is then zero).
    pub path: Option<crate::path::KinematicPath>,
    /// It moves under forces (otherwise only by its velocity, if any).
    pub dynamic: bool,
    /// kg/m³
    pub density: f32,
    /// Another world moves it (the volumetric liquid's, for a body in its
    /// domain): this one leaves it out.
    pub elsewhere: bool,
}

impl BodyDesc {
    /// Whether it moves at all (dynamic, or kinematic with a velocity or a path).
    pub fn moving(&self) -> bool {
        self.dynamic || self.velocity.iter().any(|&v| v != 0.0) || self.path.is_some()
    }
}

/// Density of water (kg/m³).
pub const WATER_DENSITY: f64 = 1000.0;

/// The part of a body below the water.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Submerged {
    /// m³
    pub volume: f64,
    /// Centre of buoyancy (world).
    pub centroid: DVec3,
    /// Area (m²) of the body's cut by the water surface.
    pub waterplane: f64,
    /// Second moment of that cut about its own centre (m⁴), the mean of
    /// its two horizontal axes: how stiffly the water rights the body
    /// (ρ·g·I is the metacentric part of the roll stiffness).
    pub waterplane_inertia: f64,
}

/// Columns per side of the footprint grid buoyancy is integrated over.
pub const BUOYANCY_COLUMNS: usize = 32;

/// Submerged volume and centre of buoyancy of `shape` at `pose` under the
/// surface `water(x, z)` (height, m): the midpoint rule over a grid of
/// columns across the body's footprint, each column exact.
pub fn submerged(shape: &Shape, pose: &Pose, water: &dyn Fn(f64, f64) -> f64) -> Submerged {
    let half = shape.horizontal_half_extent(pose);
    let n = BUOYANCY_COLUMNS;
    let cell = [2.0 * half[0] / n as f64, 2.0 * half[1] / n as f64];
    let area = cell[0] * cell[1];
    let mut s = Submerged::default();
    let mut moment = DVec3::ZERO;
    // Σx, Σz, Σx², Σz² over the waterplane's columns (times their area).
    let mut plane = [0.0f64; 4];
    for j in 0..n {
        for i in 0..n {
            let x = pose.position.x - half[0] + (i as f64 + 0.5) * cell[0];
            let z = pose.position.z - half[1] + (j as f64 + 0.5) * cell[1];
            let Some((y0, y1)) = body_column(shape, pose, x, z) else { continue };
            let h = water(x, z);
            let top = h.min(y1);
            if top <= y0 {
                continue;
            }
            let v = (top - y0) * area;
            s.volume += v;
            moment += DVec3::new(x, 0.5 * (y0 + top), z) * v;
            if h > y0 && h < y1 {
                s.waterplane += area;
                let (dx, dz) = (x - pose.position.x, z - pose.position.z);
                plane[0] += dx * area;
                plane[1] += dz * area;
                plane[2] += dx * dx * area;
                plane[3] += dz * dz * area;
            }
        }
    }
    if s.volume > 0.0 {
        s.centroid = moment / s.volume;
    }
    if s.waterplane > 0.0 {
        let a = s.waterplane;
        let ix = plane[3] - plane[1] * plane[1] / a;
        let iz = plane[2] - plane[0] * plane[0] / a;
        s.waterplane_inertia = 0.5 * (ix + iz).max(0.0);
    }
    s
}

/// A body of the scene that moves.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its `[[objects]]` index.
    pub object: usize,
    pub shape: Shape,
    /// Simulated (true) or moved at a constant velocity (false: kinematic).
    pub dynamic: bool,
    pub density: f64,
    handle: rp::RigidBodyHandle,
    /// Constant velocity of a kinematic body (m/s).
    velocity: DVec3,
    /// A kinematic body's scripted path, its rotation as the scene places
    /// it (before it faces along the path), and its heading now (rad about
    /// +y: its own +x points along the path).
    path: Option<crate::path::KinematicPath>,
    placed: DQuat,
    turned: f64,
}

/// What a body's state is, for dumps and the viewer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    pub object: usize,
    pub pose: Pose,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
    pub submerged: f64,
}

/// The fastest a hand moves a body through the water (m/s): the viewer's
/// drag pulls no faster. At 2 m/s the drag on the pool's ball, half under
/// water, is ½ρ·C_d·A·v² ≈ 300 N, about the most a person pushes with (at
/// 4 m/s the ball's wake and stern wave stood over the pool's deck).
pub const MAX_PULL_SPEED: f64 = 2.0;

/// Drag coefficient of a sphere at the Reynolds numbers of a floating ball.
const DRAG_SPHERE: f64 = 0.47;
const DRAG_BLUFF: f64 = 1.0;
/// Damping of heave, as a fraction of critical: the energy a bobbing body
/// radiates as waves (the interactive water carries the waves, but not
/// their reaction on the body).
const HEAVE_DAMPING: f64 = 0.15;
/// Damping of roll and pitch, as a fraction of critical: the waves a
/// rocking body radiates and the eddies at its bilge keels (0.05–0.2 for
/// boats and boxes; drag at the centre of buoyancy does not see rotation).
const ROLL_DAMPING: f64 = 0.15;

/// The scene's moving bodies in a rapier3d world with its static objects
/// and floor.
pub struct BodyWorld {
    pub bodies: Vec<Body>,
    set: rp::RigidBodySet,
    colliders: rp::ColliderSet,
    pipeline: rp::PhysicsPipeline,
    islands: rp::IslandManager,
    broad_phase: rp::BroadPhaseBvh,
    narrow_phase: rp::NarrowPhase,
    impulse_joints: rp::ImpulseJointSet,
    multibody_joints: rp::MultibodyJointSet,
    soft_bodies: rp::SoftBodySet,
    ccd: rp::CCDSolver,
    params: rp::IntegrationParameters,
    /// Steps taken.
    pub steps: u64,
    /// The scene time (s) of step 0 ([`BodyWorld::advance_kinematic`]).
    time_origin: f64,
    /// Bodies put elsewhere since the last step, and where they were (the
    /// water lets their hollows go: `BodyMove::released`).
    released: Vec<(usize, Pose)>,
}

fn v3(v: DVec3) -> rp::Vector {
    rp::Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

fn dv3(v: rp::Vector) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

fn collider(shape: &Shape) -> rp::ColliderBuilder {
    match *shape {
        Shape::Sphere { radius } => rp::ColliderBuilder::ball(radius as f32),
        Shape::Box { half } => {
            rp::ColliderBuilder::cuboid(half.x as f32, half.y as f32, half.z as f32)
        }
        Shape::Cylinder { radius, half_height } => {
            rp::ColliderBuilder::cylinder(half_height as f32, radius as f32)
        }
    }
}

impl BodyWorld {
    /// The world `desc` describes (`None` if nothing moves), stepping `dt`
    /// s at a time.
    pub fn new(desc: &BodiesDesc, dt: f64) -> Option<Self> {
        if !desc.objects.iter().any(|o| o.moving() && !o.elsewhere) {
            return None;
        }
        let mut set = rp::RigidBodySet::new();
        let mut colliders = rp::ColliderSet::new();
        if desc.floor_depth > 0.0 {
            let floor =
                rp::ColliderBuilder::halfspace(rapier3d::na::Unit::new_unchecked(rp::Vector::Y))
                    .translation(rp::Vector::new(0.0, -desc.floor_depth, 0.0));
            colliders.insert(floor.build());
        }
        let mut bodies = Vec::new();
        for (i, o) in desc.objects.iter().enumerate() {
            if o.elsewhere {
                continue;
            }
            let (_, rotation, position) = o.transform.to_scale_rotation_translation();
            let pose = rp::Pose::from_parts(position.to_array().into(), rotation_of(rotation));
            let shape = o.shape;
            if !o.moving() {
                // A static obstacle: its exact shape, or the box around a mesh.
                let c = match shape {
                    Some(s) => collider(&s),
                    None => {
                        let h = o.scale.map(|c| 0.5 * c.abs());
                        rp::ColliderBuilder::cuboid(h[0], h[1], h[2])
                    }
                };
                colliders.insert(c.position(pose).build());
                continue;
            }
            let shape = shape?;
            let velocity = DVec3::from(o.velocity.map(|c| c as f64));
            // A body on a path faces along it from the start.
            let heading = o.path.as_ref().and_then(|p| p.heading(0.0)).unwrap_or(0.0);
            let pose = if o.path.is_some() {
                let turned = glam::Quat::from_rotation_y(heading as f32) * rotation;
                rp::Pose::from_parts(position.to_array().into(), rotation_of(turned))
            } else {
                pose
            };
            let builder = if o.dynamic {
                rp::RigidBodyBuilder::dynamic().linvel(v3(velocity)).angular_damping(0.5)
            } else {
                rp::RigidBodyBuilder::kinematic_velocity_based().linvel(v3(velocity))
            };
            let handle = set.insert(builder.pose(pose).can_sleep(false).build());
            colliders.insert_with_parent(
                collider(&shape).density(o.density).friction(0.4).restitution(0.1).build(),
                handle,
                &mut set,
            );
            bodies.push(Body {
                object: i,
                shape,
                dynamic: o.dynamic,
                density: o.density as f64,
                handle,
                velocity,
                path: o.path.clone(),
                placed: rotation.as_dquat(),
                turned: heading,
            });
        }
        let params = rp::IntegrationParameters { dt: dt as f32, ..Default::default() };
        Some(BodyWorld {
            bodies,
            set,
            colliders,
            pipeline: rp::PhysicsPipeline::new(),
            islands: rp::IslandManager::new(),
            broad_phase: rp::BroadPhaseBvh::new(),
            narrow_phase: rp::NarrowPhase::new(),
            impulse_joints: rp::ImpulseJointSet::new(),
            multibody_joints: rp::MultibodyJointSet::new(),
            soft_bodies: rp::SoftBodySet::new(),
            ccd: rp::CCDSolver::new(),
            params,
            steps: 0,
            time_origin: 0.0,
            released: Vec::new(),
        })
    }

    fn pose_of(&self, b: &Body) -> Pose {
        let p = self.set[b.handle].position();
        let q = p.rotation;
        Pose {
            position: dv3(p.translation),
            rotation: DQuat::from_xyzw(q.x as f64, q.y as f64, q.z as f64, q.w as f64),
        }
    }

    /// Every moving body's state.
    pub fn states(&self, water: &dyn Fn(f64, f64) -> f64) -> Vec<BodyState> {
        self.bodies
            .iter()
            .map(|b| {
                let rb = &self.set[b.handle];
                let pose = self.pose_of(b);
                BodyState {
                    object: b.object,
                    pose,
                    velocity: dv3(rb.linvel()),
                    angular_velocity: dv3(rb.angvel()),
                    submerged: submerged(&b.shape, &pose, water).volume,
                }
            })
            .collect()
    }

    /// Every moving body's pose, velocity and angular velocity (rad/s).
    pub fn motions(&self) -> Vec<(Pose, DVec3, DVec3)> {
        self.bodies
            .iter()
            .map(|b| {
                let rb = &self.set[b.handle];
                (self.pose_of(b), dv3(rb.linvel()), dv3(rb.angvel()))
            })
            .collect()
    }

    /// Give body `i` a virtual mass (kg) beyond its own, and as much
    /// inertia (kg·m², about every axis), from the next step: rapier then
    /// also weighs it, which the caller's loads must take back
    /// (`fluid::coupled` stabilises the added mass of a light body so).
    pub fn set_virtual_mass(&mut self, i: usize, mass: f64, inertia: f64) {
        let Some(b) = self.bodies.get(i) else { return };
        let props = rp::MassProperties::new(
            rp::Vector::ZERO,
            mass as f32,
            rp::Vector::splat(inertia as f32),
        );
        self.set[b.handle].set_additional_mass_properties(props, true);
    }

    /// The step (s).
    pub fn dt(&self) -> f64 {
        self.params.dt as f64
    }

    /// Body `i`'s kinetic energy, translation and rotation (J).
    pub fn kinetic_energy(&self, i: usize) -> f64 {
        self.bodies.get(i).map_or(0.0, |b| self.set[b.handle].kinetic_energy() as f64)
    }

    pub fn poses(&self) -> Vec<Pose> {
        self.bodies.iter().map(|b| self.pose_of(b)).collect()
    }

    /// The bodies' moves from `before` (poses in body order) to where
    /// they are now, as the water takes them (`before` = now: at rest).
    pub fn moves_since(&self, before: &[Pose]) -> Vec<crate::coupling::BodyMove> {
        self.bodies
            .iter()
            .zip(before.iter().zip(self.poses()))
            .map(|(b, (p0, p1))| crate::coupling::BodyMove {
                shape: b.shape,
                before: *p0,
                after: p1,
                released: None,
            })
            .collect()
    }

    /// Mark in `moves` (this world's bodies in order, from
    /// [`BodyWorld::moves_since`]) the hollows of the bodies placed
    /// elsewhere since the last call, which the water lets go.
    pub fn release_hollows(&mut self, moves: &mut [crate::coupling::BodyMove]) {
        for (i, pose) in self.released.drain(..) {
            if let Some(m) = moves.get_mut(i) {
                m.released = Some(pose);
            }
        }
    }

    /// One step: buoyancy and drag from the water surface each body is in,
    /// `water(body, x, z)`, then rapier's step (gravity, contacts).
    pub fn step(&mut self, water: &dyn Fn(usize, f64, f64) -> f64) {
        self.step_with(water, &[]);
    }

    /// [`BodyWorld::step`] with more loads: per body (in order, those
    /// given), a force (N) through its centre of mass and a torque (N·m),
    /// such as the volumetric liquid's (`fluid::coupled`).
    pub fn step_with(&mut self, water: &dyn Fn(usize, f64, f64) -> f64, loads: &[(DVec3, DVec3)]) {
        let g = crate::waves::dispersion::GRAVITY;
        for (i, b) in self.bodies.iter().enumerate() {
            let pose = self.pose_of(b);
            let rb = &mut self.set[b.handle];
            if !b.dynamic {
                let (linvel, angvel) = match &b.path {
                    // Towards where the path is at the step's end, so the
                    // body stays on it (rapier keeps f32 positions).
                    Some(path) => {
                        let dt = self.params.dt as f64;
                        let t = self.time_origin + (self.steps + 1) as f64 * dt;
                        let turn = Self::turn_at(&b.path, t, b.turned);
                        ((path.at(t).0 - pose.position) / dt, DVec3::Y * (turn - b.turned) / dt)
                    }
                    None => (b.velocity, DVec3::ZERO),
                };
                rb.set_linvel(v3(linvel), true);
                rb.set_angvel(v3(angvel), true);
                continue;
            }
            // Forces and torques are both user forces that rapier keeps
            // from step to step: each step's buoyancy and drag replace the
            // last's (a torque left standing pumps energy into the body).
            rb.reset_forces(true);
            rb.reset_torques(true);
            if let Some((force, torque)) = loads.get(i) {
                rb.add_force(v3(*force), true);
                rb.add_torque(v3(*torque), true);
            }
            let sub = submerged(&b.shape, &pose, &|x, z| water(i, x, z));
            if sub.volume <= 0.0 {
                continue;
            }
            let r = sub.centroid - pose.position;
            let v = dv3(rb.linvel()) + dv3(rb.angvel()).cross(r);
            let mass = b.density * b.shape.volume();
            let fraction = (sub.volume / b.shape.volume()).min(1.0);
            let radius = b.shape.bounding_radius();
            let cd = if matches!(b.shape, Shape::Sphere { .. }) { DRAG_SPHERE } else { DRAG_BLUFF };
            let area = std::f64::consts::PI * radius * radius * fraction;
            // Quadratic drag, at most what stops the body in one step (an
            // explicit step of a stiffer drag would reverse it and grow).
            let stop = mass * v.length() / self.params.dt as f64;
            let drag = -(0.5 * WATER_DENSITY * cd * area * v.length_squared()).min(stop)
                * v.normalize_or_zero();
            let stiffness = WATER_DENSITY * g * sub.waterplane;
            let heave = -2.0 * HEAVE_DAMPING * (stiffness * mass).sqrt() * v.y;
            let force = DVec3::Y * (WATER_DENSITY * g * sub.volume + heave) + drag;
            rb.add_force_at_point(v3(force), v3(sub.centroid), true);
            // Roll and pitch: ρ·g·I_waterplane is their stiffness (the
            // metacentric part), the body's inertia about a horizontal axis
            // their mass.
            let tilt_stiffness = WATER_DENSITY * g * sub.waterplane_inertia;
            let tilt_inertia = mass * b.shape.tilt_inertia_per_mass();
            let w = dv3(rb.angvel());
            let rocking = DVec3::new(w.x, 0.0, w.z);
            let roll = -2.0 * ROLL_DAMPING * (tilt_stiffness * tilt_inertia).sqrt() * rocking;
            rb.add_torque(v3(roll), true);
        }
        self.pipeline.step(
            rp::Vector::new(0.0, -g as f32, 0.0),
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.set,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
        self.steps += 1;
        let t = self.time_origin + self.steps as f64 * self.params.dt as f64;
        for b in self.bodies.iter_mut().filter(|b| b.path.is_some()) {
            b.turned = Self::turn_at(&b.path, t, b.turned);
        }
    }

    /// The heading (rad, about +y) of a body on `path` at time `t`, the
    /// one nearest `was` (so a loop keeps turning rather than snapping
    /// back by 2π); where it stands still it keeps `was`.
    fn turn_at(path: &Option<crate::path::KinematicPath>, t: f64, was: f64) -> f64 {
        let Some(path) = path else { return was };
        let Some(heading) = path.heading(t) else { return was };
        let tau = std::f64::consts::TAU;
        let delta = (heading - was).rem_euclid(tau);
        was + if delta > std::f64::consts::PI { delta - tau } else { delta }
    }

    /// Kinematic bodies where their constant velocity has taken them by
    /// `time` (s): the world started again at a later origin (`clock`).
    pub fn advance_kinematic(&mut self, time: f64) {
        self.time_origin = time;
        for b in self.bodies.iter_mut().filter(|b| !b.dynamic) {
            let rb = &mut self.set[b.handle];
            match &b.path {
                Some(path) => {
                    b.turned = Self::turn_at(&b.path, time, b.turned);
                    let rotation = DQuat::from_rotation_y(b.turned) * b.placed;
                    rb.set_translation(v3(path.at(time).0), true);
                    rb.set_rotation(rotation_of(rotation.as_quat()), true);
                }
                None => {
                    let position = dv3(rb.translation()) + b.velocity * time;
                    rb.set_translation(v3(position), true);
                }
            }
        }
    }

    /// Put body `i` at `position`, at rest and upright: lifted out of the
    /// water, not moved through it (the next step's moves release its
    /// hollow: [`BodyWorld::release_hollows`]).
    pub fn place(&mut self, i: usize, position: DVec3) {
        let Some(b) = self.bodies.get(i) else { return };
        let was = self.pose_of(b);
        if !self.released.iter().any(|&(j, _)| j == i) {
            self.released.push((i, was));
        }
        let rb = &mut self.set[b.handle];
        rb.set_translation(v3(position), true);
        rb.set_rotation(rp::Rotation::IDENTITY, true);
        rb.set_linvel(rp::Vector::ZERO, true);
        rb.set_angvel(rp::Vector::ZERO, true);
    }

    /// Move body `i` towards `target` (the viewer's drag): its velocity is
    /// set to cover the distance in `over` seconds, at most
    /// [`MAX_PULL_SPEED`] (a drag towards the horizon once threw the ball
    /// through the pool at tens of m/s, and its wake and spray whitened the
    /// whole pool).
    pub fn pull(&mut self, i: usize, target: DVec3, over: f64) {
        let Some(b) = self.bodies.get(i) else { return };
        let pose = self.pose_of(b);
        let rb = &mut self.set[b.handle];
        let v = ((target - pose.position) / over.max(1e-3)).clamp_length_max(MAX_PULL_SPEED);
        rb.set_linvel(v3(v), true);
        rb.set_angvel(rp::Vector::ZERO, true);
    }
}

fn rotation_of(q: glam::Quat) -> rp::Rotation {
    rp::Rotation::from_xyzw(q.x, q.y, q.z, q.w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use std::f64::consts::PI;

    fn flat(_: f64, _: f64) -> f64 {
        0.0
    }

    #[test]
    fn columns_are_exact_for_each_shape() {
        let at = |p: DVec3| Pose { position: p, rotation: DQuat::IDENTITY };
        let s = Shape::Sphere { radius: 0.5 };
        let (y0, y1) = body_column(&s, &at(DVec3::new(1.0, 2.0, 0.0)), 1.3, 0.0).unwrap();
        let half = (0.25f64 - 0.09).sqrt();
        assert!((y0 - (2.0 - half)).abs() < 1e-9 && (y1 - (2.0 + half)).abs() < 1e-9);
        assert!(body_column(&s, &at(DVec3::ZERO), 0.6, 0.0).is_none());
        // A box turned 90° about z: its x extent is now vertical.
        let b = Shape::Box { half: DVec3::new(1.0, 0.2, 0.3) };
        let turned = Pose { position: DVec3::ZERO, rotation: DQuat::from_rotation_z(PI / 2.0) };
        let (y0, y1) = body_column(&b, &turned, 0.1, 0.0).unwrap();
        assert!((y0 + 1.0).abs() < 1e-9 && (y1 - 1.0).abs() < 1e-9, "{y0} {y1}");
        let c = Shape::Cylinder { radius: 0.5, half_height: 1.0 };
        let (y0, y1) = body_column(&c, &at(DVec3::ZERO), 0.3, 0.2).unwrap();
        assert!((y0 + 1.0).abs() < 1e-9 && (y1 - 1.0).abs() < 1e-9);
        assert!(body_column(&c, &at(DVec3::ZERO), 0.4, 0.4).is_none());
    }

    #[test]
    fn submerged_volume_matches_closed_forms() {
        // A half-submerged sphere, a spherical cap, a box at 30% draft.
        let r = 0.4;
        let s = Shape::Sphere { radius: r };
        let at = |y: f64| Pose { position: DVec3::new(0.3, y, -0.2), rotation: DQuat::IDENTITY };
        let half = submerged(&s, &at(0.0), &flat);
        assert!((half.volume - s.volume() / 2.0).abs() < 0.01 * s.volume(), "{half:?}");
        assert!((half.centroid.y + 3.0 * r / 8.0).abs() < 0.01, "centroid {:?}", half.centroid);
        let d = 0.15;
        let cap = submerged(&s, &at(r - d), &flat).volume;
        let exact = PI * d * d * (3.0 * r - d) / 3.0;
        assert!((cap - exact).abs() < 0.02 * exact, "cap {cap} vs {exact}");
        let b = Shape::Box { half: DVec3::new(0.5, 0.5, 0.25) };
        let v = submerged(&b, &at(0.2), &flat).volume;
        assert!((v - 0.3 * b.volume()).abs() < 0.01 * b.volume(), "box {v}");
    }

    fn floating_sphere(density: f32) -> Scene {
        Scene::from_toml(
            &format!(
                "[water]\nmodel = \"flat\"\n[floor]\ndepth = 2.0\n[[objects]]\nprimitive = \"sphere\"\n\
                 position = [0.0, 0.6, 0.0]\nscale = [0.5, 0.5, 0.5]\ndynamic = true\ndensity = {density}\n"
            ),
            "test",
            &[],
        )
        .unwrap()
    }

    /// Draft d of a sphere of radius r and density ρ: the cap below the
    /// water, π·d²·(3r − d)/3, weighs as much as the sphere (bisection).
    fn archimedes_draft(r: f64, density: f64) -> f64 {
        let target = density / WATER_DENSITY * 4.0 / 3.0 * PI * r.powi(3);
        let (mut lo, mut hi) = (0.0, 2.0 * r);
        for _ in 0..60 {
            let d = 0.5 * (lo + hi);
            if PI * d * d * (3.0 * r - d) / 3.0 < target {
                lo = d;
            } else {
                hi = d;
            }
        }
        lo
    }

    #[test]
    fn spheres_float_at_the_draft_archimedes_gives_and_settle() {
        for density in [250.0f32, 500.0, 800.0] {
            let scene = floating_sphere(density);
            let mut world = BodyWorld::new(&scene.bodies(), 1.0 / 60.0).unwrap();
            let mut heights = Vec::new();
            for _ in 0..60 * 20 {
                world.step(&|_, x, z| flat(x, z));
                heights.push(world.poses()[0].position.y);
            }
            let r = 0.25;
            let draft = r - heights.last().unwrap();
            let expected = archimedes_draft(r, density as f64);
            assert!(
                (draft - expected).abs() < 0.02 * 2.0 * r,
                "density {density}: draft {draft:.4} m, Archimedes {expected:.4} m"
            );
            // It bobbed (it was dropped from above) and settled.
            let lowest = heights.iter().cloned().fold(f64::MAX, f64::min);
            assert!(lowest < r - expected - 0.02, "density {density}: it never dipped ({lowest})");
            let last_second = &heights[heights.len() - 60..];
            let spread = last_second.iter().cloned().fold(f64::MIN, f64::max)
                - last_second.iter().cloned().fold(f64::MAX, f64::min);
            assert!(spread < 1e-3, "density {density}: still bobbing by {spread} m");
        }
    }

    #[test]
    fn an_upright_buoy_floats_at_its_density_fraction_of_its_height() {
        // A cylinder 1.2 m tall, 0.5 m across, 300 kg/m³: draft 0.36 m.
        let scene = Scene::from_toml(
            "[water]\nmodel = \"flat\"\n[floor]\ndepth = 3.0\n[[objects]]\nprimitive = \"cylinder\"\n\
             position = [0.0, 0.5, 0.0]\nscale = [0.5, 1.2, 0.5]\ndynamic = true\ndensity = 300.0\n",
            "test",
            &[],
        )
        .unwrap();
        let mut world = BodyWorld::new(&scene.bodies(), 1.0 / 60.0).unwrap();
        for _ in 0..60 * 20 {
            world.step(&|_, x, z| flat(x, z));
        }
        let p = world.poses()[0];
        let draft = 0.6 - p.position.y;
        assert!((draft - 0.36).abs() < 0.012, "draft {draft:.4} m, Archimedes 0.36 m");
        let tilt = (p.rotation * DVec3::Y).angle_between(DVec3::Y);
        assert!(tilt < 0.05, "it stays upright: tilted {tilt} rad");
    }

    #[test]
    fn a_sphere_denser_than_water_sinks_to_the_floor() {
        let scene = floating_sphere(1500.0);
        let mut world = BodyWorld::new(&scene.bodies(), 1.0 / 60.0).unwrap();
        for _ in 0..60 * 10 {
            world.step(&|_, x, z| flat(x, z));
        }
        let y = world.poses()[0].position.y;
        assert!((y - (-2.0 + 0.25)).abs() < 0.02, "resting on the floor at y = {y}");
    }

    fn one_body(object: &str) -> Scene {
        Scene::from_toml(
            &format!("[water]\nmodel = \"flat\"\n[floor]\ndepth = 3.0\n[[objects]]\n{object}dynamic = true\n"),
            "test",
            &[],
        )
        .unwrap()
    }

    const SPHERE: &str = "primitive = \"sphere\"\nposition = [0.0, 0.1, 0.0]\nscale = [0.5, 0.5, 0.5]\ndensity = 600.0\n";
    const BOX: &str = "primitive = \"box\"\nposition = [0.0, 0.1, 0.0]\nscale = [1.0, 0.3, 0.6]\ndensity = 500.0\n";
    const CYLINDER: &str = "primitive = \"cylinder\"\nposition = [0.0, 0.1, 0.0]\n\
                            scale = [0.8, 0.4, 0.8]\ndensity = 500.0\n";

    /// A body settled on still water and pushed sideways at 1.5 m/s only
    /// loses energy to drag (the torque of last step's buoyancy was once
    /// kept and added to: bodies sped up and spun).
    #[test]
    fn a_pushed_body_only_loses_energy_on_still_water() {
        for (name, object) in [("sphere", SPHERE), ("box", BOX), ("cylinder", CYLINDER)] {
            let scene = one_body(object);
            let dt = 1.0 / 60.0;
            let mut world = BodyWorld::new(&scene.bodies(), dt).unwrap();
            for _ in 0..60 * 10 {
                world.step(&|_, x, z| flat(x, z));
            }
            let p = world.poses()[0].position;
            world.pull(0, p + DVec3::new(1.5 * 0.1, 0.0, 0.0), 0.1);
            let start = world.kinetic_energy(0);
            let mut lowest = start;
            for k in 0..60 * 10 {
                world.step(&|_, x, z| flat(x, z));
                let e = world.kinetic_energy(0);
                // Heave and roll trade a little energy with the buoyancy's
                // potential; kinetic energy never climbs past 1% of the start
                // above its lowest so far.
                assert!(
                    e <= lowest + 0.01 * start,
                    "{name}: kinetic energy rose to {e:.4} J from {lowest:.4} J at step {k}"
                );
                lowest = lowest.min(e);
            }
            let end = world.kinetic_energy(0);
            let state = world.states(&flat)[0];
            assert!(
                end < 0.02 * start,
                "{name}: after 10 s it keeps {end:.4} J of {start:.4} J ({:?} m/s, {:?} rad/s)",
                state.velocity,
                state.angular_velocity
            );
            assert!(
                state.angular_velocity.length() < 0.2,
                "{name}: spins {:?}",
                state.angular_velocity
            );
        }
    }

    /// A stable body started tilted rocks and comes to rest upright.
    #[test]
    fn a_tilted_stable_body_comes_to_rest_upright() {
        for (name, object) in [("sphere", SPHERE), ("box", BOX), ("cylinder", CYLINDER)] {
            let object = format!("{object}rotation_deg = [10.0, 0.0, 5.0]\n");
            let scene = one_body(&object);
            let mut world = BodyWorld::new(&scene.bodies(), 1.0 / 60.0).unwrap();
            let mut worst: f64 = 0.0;
            for _ in 0..60 * 20 {
                world.step(&|_, x, z| flat(x, z));
                let up = world.poses()[0].rotation * DVec3::Y;
                worst = worst.max(up.angle_between(DVec3::Y));
            }
            let p = world.poses()[0];
            let tilt = (p.rotation * DVec3::Y).angle_between(DVec3::Y).to_degrees();
            let state = world.states(&flat)[0];
            if name != "sphere" {
                assert!(tilt < 1.0, "{name}: still tilted {tilt:.2}° after 20 s");
                // It rocked back, never over: never past its starting tilt.
                assert!(worst.to_degrees() < 12.0, "{name}: swung to {:.1}°", worst.to_degrees());
            }
            assert!(
                state.angular_velocity.length() < 0.05 && state.velocity.length() < 0.02,
                "{name}: still moving {:?} m/s, {:?} rad/s",
                state.velocity,
                state.angular_velocity
            );
        }
    }

    fn boat_on_a_loop() -> Scene {
        Scene::from_toml(
            "[water]\nmodel = \"flat\"\n[floor]\ndepth = 2.0\n[[objects]]\nprimitive = \"box\"\n\
             scale = [4.0, 1.0, 1.5]\n[objects.path]\npoints = [[0.0, 0.3, 0.0], [10.0, 0.3, 0.0], \
             [10.0, 0.3, -10.0], [0.0, 0.3, -10.0]]\nspeed = 4.0\nclosed = true\n",
            "test",
            &[],
        )
        .unwrap()
    }

    /// A kinematic body on a scripted path is where the path is at every
    /// step (within a millimetre over two rounds, though rapier keeps f32
    /// positions), its long axis along its heading; started at a later
    /// time it is where a world stepped from 0 has it.
    #[test]
    fn a_body_on_a_path_follows_it_and_turns_with_it() {
        let scene = boat_on_a_loop();
        let path = scene.objects[0].path.as_ref().unwrap().build().unwrap();
        let dt = 1.0 / 60.0;
        let mut world = BodyWorld::new(&scene.bodies(), dt).unwrap();
        let steps = (2.0 * path.duration() / dt) as usize;
        let mut worst = 0.0_f64;
        for k in 1..=steps {
            world.step(&|_, x, z| flat(x, z));
            let t = k as f64 * dt;
            let pose = world.poses()[0];
            worst = worst.max(pose.position.distance(path.at(t).0));
            // Its long axis, the box's +x, along the path.
            let axis = pose.rotation * DVec3::X;
            let v = path.at(t).1.normalize();
            assert!(axis.dot(v) > 0.999, "t = {t:.2}: long axis {axis}, heading {v}");
        }
        assert!(worst < 1e-3, "{worst} m off the path");
        let at = 7.3;
        let mut later = BodyWorld::new(&scene.bodies(), dt).unwrap();
        later.advance_kinematic(at);
        let mut early = BodyWorld::new(&scene.bodies(), dt).unwrap();
        let k = (at / dt).round() as usize;
        for _ in 0..k {
            early.step(&|_, x, z| flat(x, z));
        }
        for _ in 0..30 {
            later.step(&|_, x, z| flat(x, z));
            early.step(&|_, x, z| flat(x, z));
        }
        let (a, b) = (later.poses()[0], early.poses()[0]);
        assert!(a.position.distance(b.position) < 1e-3, "{} vs {}", a.position, b.position);
        assert!(a.rotation.angle_between(b.rotation) < 1e-3);
    }

    /// A small buoy on the FFT sea rides its waves: its heave follows the
    /// height of the surface the FFT draws where it floats (all 4096
    /// modes; the buoy reads the strongest 1024), in phase and at full
    /// height, as a body whose own heave period (~1 s) is far below the
    /// waves' (5–9 s) must. Sampled every 0.25 s over 40 s after 10 s of
    /// settling.
    #[test]
    fn a_buoy_heaves_with_the_fft_sea_in_phase() {
        use crate::waves::ocean::{OceanFields, OceanSpectrum};
        let scene = Scene::from_toml(
            "[water]\nmodel = \"fft\"\n[ocean]\nwind_speed = 10.0\npatch_size = 400.0\n\
             resolution = 64\ncascades = 1\nchoppiness = 0.8\nseed = 3\n[floor]\ndepth = 40.0\n\
             [[objects]]\nprimitive = \"sphere\"\nposition = [12.0, 0.0, -7.0]\n\
             scale = [0.8, 0.8, 0.8]\ndynamic = true\ndensity = 500.0\n",
            "test",
            &[],
        )
        .unwrap();
        let waves = scene.floating_waves().expect("the FFT sea has waves");
        let spectrum = OceanSpectrum::new(&scene.ocean_settings());
        let dt = 1.0 / 60.0;
        let mut world = BodyWorld::new(&scene.bodies(), dt).unwrap();
        let (mut heave, mut surface) = (Vec::new(), Vec::new());
        for step in 0..60 * 50 {
            let t = step as f64 * dt;
            let p = world.poses()[0];
            let half = world.bodies[0].shape.horizontal_half_extent(&p);
            let patch = waves.patch_around(t, [p.position.x, p.position.z], half[0].max(half[1]));
            world.step(&|_, x, z| patch.height_at(x, z));
            if step >= 600 && step % 15 == 0 {
                let p = world.poses()[0].position;
                let fields = OceanFields::evaluate(&spectrum, t + dt);
                heave.push(p.y);
                surface.push(fields.height_at(p.x, p.z) as f64);
            }
        }
        let centred = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            v.iter().map(|x| x - m).collect::<Vec<_>>()
        };
        let (y, h) = (centred(&heave), centred(&surface));
        // Correlation of the heave with the surface `lag` samples earlier.
        let correlation = |lag: i64| {
            let pairs: Vec<(f64, f64)> = (0..y.len() as i64)
                .filter(|&i| i - lag >= 0 && i - lag < h.len() as i64)
                .map(|i| (y[i as usize], h[(i - lag) as usize]))
                .collect();
            let dot = |f: &dyn Fn(&(f64, f64)) -> f64| pairs.iter().map(f).sum::<f64>();
            dot(&|p| p.0 * p.1) / (dot(&|p| p.0 * p.0) * dot(&|p| p.1 * p.1)).sqrt()
        };
        let best = (-4..=4).max_by(|&a, &b| correlation(a).total_cmp(&correlation(b))).unwrap();
        let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        let gain = y.iter().zip(&h).map(|(a, b)| a * b).sum::<f64>()
            / h.iter().map(|b| b * b).sum::<f64>();
        assert!(rms(&h) > 0.2, "the sea must have waves: {} m rms", rms(&h));
        assert!(correlation(0) > 0.98, "heave and surface correlate by {}", correlation(0));
        assert!(best.abs() <= 1, "the heave lags the surface by {} s", best as f64 * 0.25);
        assert!((gain - 1.0).abs() < 0.1, "heave over surface height: {gain}");
    }
}
