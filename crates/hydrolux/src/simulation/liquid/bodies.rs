//! The moving bodies in the GPU liquid (issue #29, two-way coupling; seed
//! 003 §2.4): rapier moves them on the CPU (`hydrolux_core::fluid::
//! LiquidBodies`, shared with the twin), the GPU liquid flows round them
//! and presses on them (`bodies.wgsl`, `place_bodies` and `body_loads` in
//! `liquid.wgsl`).
//!
//! Each clock step: their poses and velocities go up (a uniform), the
//! liquid takes its substeps, their loads (the mean over the substeps)
//! come back, and rapier steps under them. The loads must be this step's:
//! a load a step late is a delayed restoring force, which pumps energy
//! into a floating body. So native code waits for each clock step's loads
//! (a few hundred bytes); a browser cannot wait, so there a body takes the
//! latest loads that have arrived, up to a frame late.

use crate::gpu_util::AsyncReadback;
use hydrolux_core::bodies::{BodiesDesc, BodyState, BodyWorld};
use hydrolux_core::fluid::{BodyLoad, LiquidBodies};
use hydrolux_core::scene::{MAX_LIQUID_BODIES, Scene};

/// WGSL `LiquidBody` (liquid/bodies.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BodyRecord {
    position: [f32; 3],
    shape: u32,
    rotation: [f32; 4],
    velocity: [f32; 3],
    reach: f32,
    angular_velocity: [f32; 3],
    _pad0: f32,
    size: [f32; 4],
}

/// WGSL `LiquidBodies`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BodiesRecord {
    count: u32,
    _pad: [u32; 3],
    bodies: [BodyRecord; MAX_LIQUID_BODIES],
}

impl BodiesRecord {
    pub(crate) fn empty() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

/// Floats per body in the loads (`LOAD_VALUES` in liquid.wgsl): force,
/// torque, the wetted share, one spare.
pub(crate) const LOAD_VALUES: usize = 8;
/// Bytes of every body's loads.
pub(crate) const LOADS_BYTES: u64 = (MAX_LIQUID_BODIES * LOAD_VALUES * 4) as u64;

/// The bodies of a GPU liquid.
pub(crate) struct GpuBodies {
    pub bodies: LiquidBodies,
    /// Their world at the start (a reset builds it again).
    desc: BodiesDesc,
    /// Each one's object's scale (its transform is scale × pose).
    scales: Vec<[f32; 3]>,
    /// Each body's load over the last clock step the GPU reported.
    pub loads: Vec<BodyLoad>,
    readback: AsyncReadback,
    /// The copy on its way is from before a reset.
    discard: bool,
    density: f64,
}

impl GpuBodies {
    /// The bodies of `scene`'s liquid (`None` when none starts in it).
    pub fn new(device: &wgpu::Device, scene: &Scene, density: f64) -> Option<Self> {
        let desc = scene.liquid_bodies()?;
        let world = BodyWorld::new(&desc, Self::dt(scene))?;
        let count = world.bodies.len();
        let scales = world.bodies.iter().map(|b| scene.objects[b.object].scale).collect();
        Some(GpuBodies {
            scales,
            bodies: LiquidBodies::new(world),
            desc,
            loads: vec![BodyLoad::default(); count],
            readback: AsyncReadback::new(device, "liquid body loads", LOADS_BYTES),
            discard: false,
            density,
        })
    }

    /// Rapier's step: the clock's.
    fn dt(scene: &Scene) -> f64 {
        scene.fluid.step_seconds() * scene.fluid.substeps.max(1) as f64
    }

    pub fn count(&self) -> u32 {
        self.bodies.world.bodies.len() as u32
    }

    /// Where rapier has them, as the GPU takes them.
    pub fn record(&self) -> BodiesRecord {
        let mut record = BodiesRecord::empty();
        record.count = self.count();
        for (out, b) in record.bodies.iter_mut().zip(self.bodies.placed()) {
            let (code, size) = b.shape.gpu();
            *out = BodyRecord {
                position: b.pose.position.as_vec3().to_array(),
                shape: code,
                rotation: b.pose.rotation.as_quat().to_array(),
                velocity: b.velocity.as_vec3().to_array(),
                reach: b.shape.bounding_radius() as f32,
                angular_velocity: b.angular_velocity.as_vec3().to_array(),
                _pad0: 0.0,
                size: [size[0], size[1], size[2], 0.0],
            };
        }
        record
    }

    /// After a clock step's liquid steps were submitted: its loads from
    /// `solve` (at byte `at`), then rapier's step under them.
    pub fn step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        solve: &wgpu::Buffer,
        at: u64,
    ) {
        if !self.readback.in_flight() {
            self.readback.request_from(device, queue, solve, at);
            self.discard = false;
        }
        if let Some(bytes) = self.readback.take(device, true)
            && !std::mem::take(&mut self.discard)
        {
            let values: &[f32] = bytemuck::cast_slice(&bytes);
            for (load, v) in self.loads.iter_mut().zip(values.chunks(LOAD_VALUES)) {
                let vec =
                    |k: usize| glam::DVec3::new(v[k] as f64, v[k + 1] as f64, v[k + 2] as f64);
                *load = BodyLoad { force: vec(0), torque: vec(3), wetted: v[6] as f64 };
            }
        }
        self.bodies.step(&self.loads, self.density);
    }

    /// Back where the scene puts them, at rest.
    pub fn reset(&mut self) {
        let dt = self.bodies.world.dt();
        if let Some(world) = BodyWorld::new(&self.desc, dt) {
            self.bodies = LiquidBodies::new(world);
        }
        self.loads.iter_mut().for_each(|l| *l = BodyLoad::default());
        // A copy still on its way (a browser's) is of the old run's loads.
        self.discard = self.readback.in_flight();
    }

    /// Each one's object and its world transform now.
    pub fn transforms(&self) -> Vec<(usize, glam::Mat4)> {
        let world = &self.bodies.world;
        world
            .bodies
            .iter()
            .zip(world.poses())
            .zip(&self.scales)
            .map(|((b, pose), scale)| (b.object, pose.matrix(*scale)))
            .collect()
    }

    /// Their states; `submerged` is the wetted share of the volume.
    pub fn states(&self) -> Vec<BodyState> {
        let mut states = self.bodies.world.states(&|_, _| f64::NEG_INFINITY);
        for ((s, b), load) in states.iter_mut().zip(&self.bodies.world.bodies).zip(&self.loads) {
            s.submerged = load.wetted * b.shape.volume();
        }
        states
    }
}
