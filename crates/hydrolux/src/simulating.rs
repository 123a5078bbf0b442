//! The caller's hold on the simulations: disturbing the water, splashing,
//! moving bodies, the clock. Each goes through the simulation layer
//! (`simulation/mod.rs`), which offers it to the simulations in order;
//! none names a simulation's fields.

use crate::renderer::{RenderError, Renderer};
use crate::simulation::Input;
use hydrolux_core::clock::MAX_TIME_S;

impl Renderer {
    /// Disturb the interactive water at world (x, z): a crater of `radius`
    /// and depth `strength` (m) lands in its next step (a click in the
    /// viewer, a thrown stone). Returns false without `water.dynamic`.
    pub fn disturb(&mut self, x: f32, z: f32, radius: f32, strength: f32) -> bool {
        self.simulations.input(Input::Disturb(hydrolux_core::coupling::Drop {
            x: x as f64,
            z: z as f64,
            radius: radius as f64,
            strength: strength as f64,
        }))
    }

    /// A splash of the caller's (an explosion, a thrown stone): its spray,
    /// bubbles and foam are born in the next simulation step. Returns false
    /// when the scene runs no white water (or too many splashes wait).
    pub fn splash(&mut self, splash: hydrolux_core::whitewater::Splash) -> bool {
        self.simulations.input(Input::Splash(splash))
    }

    /// The moving bodies now: position, orientation, velocities and
    /// submerged volume of each (empty if nothing moves).
    pub fn bodies(&self) -> Vec<hydrolux_core::bodies::BodyState> {
        self.simulations.bodies()
    }

    /// Pull moving body `i` (in [`Renderer::bodies`] order) towards world
    /// `target` over the next steps: the viewer's drag.
    pub fn pull_body(&mut self, i: usize, target: glam::Vec3) {
        self.simulations.input(Input::Pull(i, target.as_dvec3()));
    }

    /// Put moving body `i` at world `position`, at rest (drop it from there).
    pub fn place_body(&mut self, i: usize, position: glam::Vec3) {
        self.simulations.input(Input::Place(i, position.as_dvec3()));
    }

    /// Replace the heights of a `water.model = "heightfield"` surface (same
    /// samples per side as its file, row = z, col = x, metres), e.g. from a
    /// simulation of the caller's. Everything that reads the surface follows
    /// from the next frame: shading, the medium division, height queries,
    /// and the caustics and god rays (their maps are remade).
    pub fn update_heightfield(&mut self, heights: &[f32]) -> Result<(), RenderError> {
        self.simulations.update_heightfield(&self.shared.queue, heights)?;
        self.techniques.surface_edited();
        Ok(())
    }

    /// Start the simulations again from their initial state; the next
    /// frame steps them from t = 0 to its time.
    pub fn reset_simulation(&mut self) {
        self.clock.reset();
    }

    /// Exact time (offline renders): the state at every time is simulated
    /// from that time's own origin (`hydrolux_core::clock`), so any slice
    /// of a sequence renders the frames of the whole. Off (the viewer,
    /// `bench`), playing on continues the state it has and only a long jump
    /// starts again. Either way a time costs under twice the scene's
    /// memory of steps.
    pub fn set_exact_time(&mut self, exact: bool) {
        self.clock.set_exact(exact);
    }

    /// Clock steps the simulations would take to reach `time` from where
    /// they are (what a caller shows progress for).
    pub fn simulation_steps_to(&self, time: f64) -> u64 {
        self.clock.steps_to(time.clamp(0.0, MAX_TIME_S))
    }

    /// Call `progress(done, total)` after each batch of a catch-up of more
    /// than one batch of steps (waiting for the GPU, so it is honest).
    pub fn set_catch_up_progress(&mut self, progress: Option<Box<dyn FnMut(u64, u64)>>) {
        self.catch_up_progress = progress;
    }

    /// Simulated time (s) of the simulations' current state: the last
    /// frame's time rounded down to the clock's step.
    pub fn simulation_time(&self) -> f64 {
        self.clock.time()
    }
}
