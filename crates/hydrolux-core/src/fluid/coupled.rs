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

use super::flip::Liquid;
use super::solids::LiquidBody;
use crate::bodies::BodyWorld;
use glam::DVec3;

/// The added-mass coefficient of a sphere (½), used for every body.
pub const ADDED_MASS_COEFFICIENT: f64 = 0.5;

/// A liquid with the bodies in it.
pub struct LiquidWithBodies {
    pub liquid: Liquid,
    pub world: BodyWorld,
    /// Each body's acceleration and angular acceleration over the last
    /// step (m/s², rad/s²).
    accelerations: Vec<(DVec3, DVec3)>,
}

impl LiquidWithBodies {
    /// `world`'s bodies in `liquid`; the world's step is the liquid's.
    pub fn new(liquid: Liquid, world: BodyWorld) -> Self {
        let accelerations = vec![(DVec3::ZERO, DVec3::ZERO); world.bodies.len()];
        LiquidWithBodies { liquid, world, accelerations }
    }

    /// One step of the world's `dt`: the liquid round the bodies where
    /// they are, then the bodies under the liquid's loads.
    pub fn step(&mut self) {
        let dt = self.world.dt();
        let before = self.world.motions();
        self.liquid.bodies = self
            .world
            .bodies
            .iter()
            .zip(&before)
            .map(|(b, &(pose, velocity, angular_velocity))| LiquidBody {
                shape: b.shape,
                pose,
                velocity,
                angular_velocity,
            })
            .collect();
        self.liquid.step(dt);
        let rho = self.liquid.settings.density;
        let gravity = DVec3::new(0.0, -crate::waves::dispersion::GRAVITY, 0.0);
        let mut loads = Vec::with_capacity(before.len());
        for i in 0..before.len() {
            let shape = self.world.bodies[i].shape;
            let load = self.liquid.loads[i];
            let (a, alpha) = self.accelerations[i];
            let mass = ADDED_MASS_COEFFICIENT * rho * shape.volume() * load.wetted;
            let inertia = mass * shape.tilt_inertia_per_mass();
            self.world.set_virtual_mass(i, mass, inertia);
            // Rapier weighs the virtual mass too: its weight goes back.
            loads.push((load.force + mass * (a - gravity), load.torque + inertia * alpha));
        }
        // No heightfield water here: the liquid is the only water.
        self.world.step_with(&|_, _, _| f64::NEG_INFINITY, &loads);
        for ((acc, (_, v0, w0)), (_, v1, w1)) in
            self.accelerations.iter_mut().zip(&before).zip(self.world.motions())
        {
            *acc = ((v1 - *v0) / dt, (w1 - *w0) / dt);
        }
    }
}
