//! The liquid and the scene's moving bodies stepped together (issue #29,
//! two-way coupling; seed 003 §2.4): each step the bodies, where rapier
//! has them, are moving solids of the liquid (`solids`), and the pressure's
//! force and torque on each go to rapier for its next step.
//!
//! Handing the pressure over explicitly is unstable for a light body: the
//! liquid's answer to the body's last change of speed is an added mass
//! m_a = C_a·ρ·V pushing back, and when m_a exceeds the body's own mass
//! the exchange grows step by step (the added-mass instability of
//! partitioned fluid–structure coupling; Causin, Gerbeau & Nobile 2005).
//! So each body carries a virtual mass m_v, its added-mass estimate
//! C_a·ρ·V·(wetted share), inside rapier, and is handed m_v times its last
//! acceleration (and m_v's weight back): a step then solves
//! (m + m_v)·aₙ = F + m_v·aₙ₋₁, which is the implicit (m + m_a)·aₙ = F′
//! when m_v = m_a and damps any mismatch (the spurious mode's ratio
//! (m_v − m_a)/(m + m_v) has magnitude under 1) — a ball of any density
//! floats.
//!
//! Rapier steps on the clock; the liquid takes `substeps` steps in each,
//! the bodies standing where rapier left them and moving at its velocity,
//! and their loads are the mean over those steps. The GPU liquid steps
//! the same way (`simulation/liquid`), with the loads read back each clock
//! step: [`LiquidBodies`] is the part both share.

use super::flip::Liquid;
use super::solids::{BodyLoad, LiquidBody};
use crate::bodies::BodyWorld;
use glam::DVec3;

/// The added-mass coefficient of a sphere (½), used for every body.
pub const ADDED_MASS_COEFFICIENT: f64 = 0.5;

/// The bodies in a liquid: their rapier world and what the coupling keeps
/// between steps.
pub struct LiquidBodies {
    pub world: BodyWorld,
    /// Each body's acceleration and angular acceleration over the last
    /// step (m/s², rad/s²).
    accelerations: Vec<(DVec3, DVec3)>,
}

impl LiquidBodies {
    pub fn new(world: BodyWorld) -> Self {
        let accelerations = vec![(DVec3::ZERO, DVec3::ZERO); world.bodies.len()];
        LiquidBodies { world, accelerations }
    }

    /// The bodies where rapier has them, as the liquid takes them.
    pub fn placed(&self) -> Vec<LiquidBody> {
        self.world
            .bodies
            .iter()
            .zip(self.world.motions())
            .map(|(b, (pose, velocity, angular_velocity))| LiquidBody {
                shape: b.shape,
                pose,
                velocity,
                angular_velocity,
            })
            .collect()
    }

    /// One rapier step under the liquid's `loads` (one per body; a liquid
    /// of `density` kg/m³): the virtual added mass of each, then the step.
    pub fn step(&mut self, loads: &[BodyLoad], density: f64) {
        let dt = self.world.dt();
        let before = self.world.motions();
        let gravity = DVec3::new(0.0, -crate::waves::dispersion::GRAVITY, 0.0);
        let mut forces = Vec::with_capacity(before.len());
        for i in 0..before.len() {
            let shape = self.world.bodies[i].shape;
            let load = loads.get(i).copied().unwrap_or_default();
            let (a, alpha) = self.accelerations[i];
            let mass = ADDED_MASS_COEFFICIENT * density * shape.volume() * load.wetted;
            let inertia = mass * shape.tilt_inertia_per_mass();
            self.world.set_virtual_mass(i, mass, inertia);
            // Rapier weighs the virtual mass too: its weight goes back.
            forces.push((load.force + mass * (a - gravity), load.torque + inertia * alpha));
        }
        // No heightfield water here: the liquid is the only water.
        self.world.step_with(&|_, _, _| f64::NEG_INFINITY, &forces);
        for ((acc, (_, v0, w0)), (_, v1, w1)) in
            self.accelerations.iter_mut().zip(&before).zip(self.world.motions())
        {
            *acc = ((v1 - *v0) / dt, (w1 - *w0) / dt);
        }
    }
}

/// A liquid with the bodies in it (the CPU twin of the GPU's coupling).
pub struct LiquidWithBodies {
    pub liquid: Liquid,
    pub bodies: LiquidBodies,
    /// Liquid steps per rapier step.
    pub substeps: usize,
}

impl LiquidWithBodies {
    /// `world`'s bodies in `liquid`: `substeps` liquid steps per step of the
    /// world's `dt`.
    pub fn new(liquid: Liquid, world: BodyWorld, substeps: usize) -> Self {
        LiquidWithBodies { liquid, bodies: LiquidBodies::new(world), substeps: substeps.max(1) }
    }

    /// The body world.
    pub fn world(&self) -> &BodyWorld {
        &self.bodies.world
    }

    /// One step of the world's `dt`: the liquid round the bodies where
    /// they are, then the bodies under the liquid's mean loads.
    pub fn step(&mut self) {
        let n = self.substeps;
        let dt = self.bodies.world.dt() / n as f64;
        self.liquid.bodies = self.bodies.placed();
        let mut mean = vec![BodyLoad::default(); self.liquid.bodies.len()];
        for _ in 0..n {
            self.liquid.step(dt);
            for (m, l) in mean.iter_mut().zip(&self.liquid.loads) {
                m.force += l.force / n as f64;
                m.torque += l.torque / n as f64;
                m.wetted += l.wetted / n as f64;
            }
        }
        self.bodies.step(&mean, self.liquid.settings.density);
    }
}
