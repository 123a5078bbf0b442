//! How the simulation layer drives the white water (`simulation/mod.rs`).

use super::*;

impl crate::simulation::Simulation for Whitewater {
    fn create(
        shared: &crate::technique::Shared,
        scene: &Scene,
        published: &crate::simulation::Published,
    ) -> Result<Option<Self>, crate::error::RenderError> {
        let mut w = Whitewater::new(shared, scene);
        if let Some(w) = &mut w {
            w.connect(shared, published);
        }
        Ok(w)
    }

    fn fits(&self, scene: &Scene) -> bool {
        Whitewater::fits(self, scene)
    }

    /// Its foam and particles are built up from the clock's origin: made
    /// anew mid-run it started empty, and a live edit (the viewer's panel
    /// changing the medium) showed a sea without its foam, unlike a fresh
    /// render of the edited scene.
    fn restarts_clock(&self) -> bool {
        true
    }

    fn connect(
        &mut self,
        shared: &crate::technique::Shared,
        published: &crate::simulation::Published,
    ) {
        self.bind_kicks(&shared.device, published.ripples.as_ref().map(|r| &r.kicks));
        let landings = published.liquid.as_ref().and_then(|l| l.landings.as_ref());
        self.bind_landings(&shared.device, landings);
    }

    fn publish(&self, published: &mut crate::simulation::Published) {
        use crate::simulation::published::{FoamState, ParticleState};
        let (wind, streak) = self.foam_wind();
        published.foam = Some(FoamState {
            cover: self.cover_view.clone(),
            window: self.foam_area(),
            wind,
            streak,
        });
        published.particles = self.has_particles().then(|| ParticleState {
            particles: self.particles.clone(),
            slots: self.slots.clone(),
            args: self.args.clone(),
            list: self.list(),
            capacity: self.capacity,
        });
    }

    fn pace(&self) -> crate::simulation::Pace {
        crate::simulation::Pace::OwnSteps
    }

    fn reset(&mut self, queue: &wgpu::Queue, from: u64) {
        Whitewater::reset(self, queue, from);
    }

    fn schedule(
        &mut self,
        clock_steps: u64,
        frame_end: u64,
        queue: &wgpu::Queue,
    ) -> Vec<(u64, f64)> {
        Whitewater::schedule(self, clock_steps, frame_end, queue)
    }

    /// A step reads the surface at its own time, to within half a step.
    fn surface_tolerance(&self) -> Option<f64> {
        Some(0.5 * self.dt as f64)
    }

    fn step(
        &mut self,
        ctx: &mut crate::simulation::StepContext,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let camera = [ctx.camera.position.x, ctx.camera.position.z];
        let input = StepInput {
            centre: ctx.couplings.water_centre.unwrap_or(camera),
            camera,
            splashes: std::mem::take(&mut ctx.couplings.splashes),
        };
        let surface = &ctx.published.surface().group_without_foam;
        self.record_step(&ctx.shared.queue, encoder, surface, input);
    }

    /// Splashes of the steps after its last one wait for its next step
    /// (in a later frame), as they would had the frame ended elsewhere.
    fn keep_leftovers(&mut self, couplings: &mut crate::simulation::couplings::Couplings) {
        for splash in couplings.splashes.drain(..) {
            self.splash(splash);
        }
    }

    fn finish(&mut self, shared: &crate::technique::Shared, encoder: &mut wgpu::CommandEncoder) {
        self.record_mips(encoder, &shared.downsampler);
    }

    fn input(&mut self, input: &crate::simulation::Input) -> bool {
        match *input {
            crate::simulation::Input::Splash(splash) => self.splash(splash),
            _ => false,
        }
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        Whitewater::dump(self, name, ctx)
    }
}
