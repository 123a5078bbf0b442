//! The simulation layer: what changes with time, stepped before any
//! technique draws (ARCHITECTURE.md, "Simulations"). Each simulation is a
//! folder with its settings' GPU side, state, step, CPU twin (in
//! `hydrolux-core`) and tests, and one line in [`simulations!`] below:
//!
//! - `liquid`: the volumetric liquid (seed 003 §2.2, marker particles on a
//!   MAC grid), `fluid.substeps` steps on every clock step; what falls
//!   under the interactive water's level lands in it (first, so that the
//!   water's steps find the landings of their clock steps);
//! - `ripples`: the interactive water and the bodies in it (seed 003 §2.1,
//!   `ripples/dynamics.rs`), stepped on every clock step;
//! - `whitewater`: foam, bubbles and spray (seed 003 §4.4–4.6), stepped at
//!   its own rate, reading the surface at its own step's time;
//! - `surface`: the water surface's model (seed 000 §2.4: the FFT ocean in
//!   `ocean`, sines, a heightfield), a function of time evaluated for the
//!   frame and whenever a step reads it at another time.
//!
//! The scheduler ([`Simulations::advance`]) walks them on the one
//! [`SimulationClock`]'s steps in registry order: followers take any run of
//! clock steps, the others step at their own times, and the surface is
//! evaluated at those times first. What one hands another goes through
//! [`couplings::Couplings`]; what techniques read is [`Published`].

pub mod couplings;
pub mod liquid;
pub mod ocean;
pub mod published;
pub mod ripples;
pub mod surface;
pub mod whitewater;

use crate::error::RenderError;
use crate::info::TechniqueInfo;
use crate::technique::Shared;
use crate::timing::GpuTimer;
use couplings::Couplings;
use hydrolux_core::bodies::BodyState;
use hydrolux_core::camera::Camera;
use hydrolux_core::clock::{Advance, SimulationClock};
use hydrolux_core::scene::{CLOCK_HZ, Scene};
pub(crate) use published::Published;

/// What a caller asks of the simulations (the public API's `disturb`,
/// `splash`, the viewer's drag); the layer offers it to each in order.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Input {
    /// A crater in the interactive water.
    Disturb(hydrolux_core::coupling::Drop),
    /// A splash of spray, bubbles and foam.
    Splash(hydrolux_core::whitewater::Splash),
    /// Pull moving body `i` towards a point (m).
    Pull(usize, glam::DVec3),
    /// Put moving body `i` at a point (m), at rest.
    Place(usize, glam::DVec3),
}

/// How a simulation takes the clock's steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pace {
    /// Any run of clock steps at once ([`Simulation::follow`]); it keeps
    /// its own rate inside.
    Follows,
    /// One step at a time at the times it schedules ([`Simulation::schedule`],
    /// [`Simulation::step`]), after the followers have reached that time.
    OwnSteps,
    /// None: a function of time ([`Simulation::evaluate`]).
    Evaluated,
}

/// What a step sees.
pub(crate) struct StepContext<'a> {
    pub shared: &'a Shared,
    pub camera: &'a Camera,
    pub published: &'a Published,
    pub couplings: &'a mut Couplings,
}

/// One simulation. Defaults do nothing, so each implements what its pace
/// needs.
pub(crate) trait Simulation {
    /// Build it for `scene` (`None` when the scene has none); `published`
    /// holds what the simulations before it in the registry publish.
    fn create(
        shared: &Shared,
        scene: &Scene,
        published: &Published,
    ) -> Result<Option<Self>, RenderError>
    where
        Self: Sized;

    /// Whether its state goes on through the edit to `scene`.
    fn fits(&self, scene: &Scene) -> bool;

    /// Whether being made anew restarts every simulation from the clock's
    /// origin (its state cannot join mid-run).
    fn restarts_clock(&self) -> bool {
        false
    }

    /// Bind what earlier simulations publish (after any of them was made anew).
    fn connect(&mut self, _shared: &Shared, _published: &Published) {}

    /// The scene was edited and this simulation kept (it [`fits`]): take what
    /// does not touch its state (how it is drawn).
    ///
    /// [`fits`]: Simulation::fits
    fn adjust(&mut self, _shared: &Shared, _scene: &Scene) {}

    /// Put what others and the techniques read into `published`.
    fn publish(&self, published: &mut Published);

    fn pace(&self) -> Pace;

    /// Write what this frame's time decides (before the steps and again after).
    fn prepare(&mut self, _queue: &wgpu::Queue, _time: f64, _published: &Published) {}

    /// Back to its initial state, as it is at clock step `from`.
    fn reset(&mut self, _queue: &wgpu::Queue, _from: u64) {}

    /// [`Pace::Follows`]: follow `clock_steps` more clock steps.
    fn follow(
        &mut self,
        _ctx: &mut StepContext,
        _encoder: &mut wgpu::CommandEncoder,
        _clock_steps: u32,
    ) {
    }

    /// [`Pace::OwnSteps`]: its steps due in the next `clock_steps` of the
    /// clock, as (clock steps before it, its time in s); the frame reaches
    /// clock step `frame_end`.
    fn schedule(
        &mut self,
        _clock_steps: u64,
        _frame_end: u64,
        _queue: &wgpu::Queue,
    ) -> Vec<(u64, f64)> {
        Vec::new()
    }

    /// [`Pace::OwnSteps`]: seconds within which the surface it reads must
    /// have been evaluated at its step's time (`None`: it reads no surface).
    fn surface_tolerance(&self) -> Option<f64> {
        None
    }

    /// [`Pace::OwnSteps`]: record one step.
    fn step(&mut self, _ctx: &mut StepContext, _encoder: &mut wgpu::CommandEncoder) {}

    /// [`Pace::OwnSteps`]: keep what the couplings still hold after the
    /// last step of a batch for its next step.
    fn keep_leftovers(&mut self, _couplings: &mut Couplings) {}

    /// [`Pace::Evaluated`]: whether its GPU state is further than
    /// `tolerance` s from `time` (and so must be evaluated for a step there).
    fn stale_at(&self, _time: f64, _tolerance: f64) -> bool {
        false
    }

    /// [`Pace::Evaluated`]: record its evaluation at `time`.
    fn evaluate(&mut self, _shared: &Shared, _encoder: &mut wgpu::CommandEncoder, _time: f64) {}

    /// After a batch of steps (mips of what the steps wrote).
    fn finish(&mut self, _shared: &Shared, _encoder: &mut wgpu::CommandEncoder) {}

    /// The frame's size (pixels), before it is simulated: true if what it
    /// publishes changed (buffers made for the size).
    fn frame_size(&mut self, _shared: &Shared, _size: (u32, u32)) -> bool {
        false
    }

    /// The frame's own work (the surface at the frame's time), recorded
    /// with the frame's first stage.
    fn record_frame(
        &mut self,
        _shared: &Shared,
        _encoder: &mut wgpu::CommandEncoder,
        _plan: &crate::plan::FramePlan,
        _timer: Option<&mut GpuTimer>,
    ) {
    }

    /// Take a caller's input; false if it is not this simulation's.
    fn input(&mut self, _input: &Input) -> bool {
        false
    }

    /// The moving bodies it keeps.
    fn bodies(&self) -> Vec<BodyState> {
        Vec::new()
    }

    /// Read back dump `name` if it is one of those its `INFO` declares.
    fn dump(
        &self,
        _name: &str,
        _ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        None
    }
}

macro_rules! simulations {
    ($($field:ident: $ty:ty => $info:path),* $(,)?) => {
        /// Every simulation of the scene by name, in the order they are
        /// built, stepped and published (`None`: the scene has none).
        pub(crate) struct Simulations {
            $(pub(crate) $field: Option<$ty>,)*
            /// What they publish, for each other and the techniques.
            pub(crate) published: Published,
            couplings: Couplings,
        }

        impl Simulations {
            /// Build every simulation `scene` has, in order.
            pub fn new(shared: &Shared, scene: &Scene) -> Result<Self, RenderError> {
                let mut published = Published::default();
                $(
                    let $field = crate::error::catch_gpu_errors(
                        &shared.device,
                        || format!("creating the {} simulation", stringify!($field)),
                        || <$ty as Simulation>::create(shared, scene, &published),
                    )?;
                    if let Some(s) = &$field {
                        s.publish(&mut published);
                    }
                )*
                Ok(Simulations { $($field,)* published, couplings: Couplings::default() })
            }

            /// The scene was edited: make anew what does not fit it and
            /// reconnect what follows. Returns whether the clock must
            /// start again (a simulation that cannot join mid-run is new).
            // (`remade` is not read after the last simulation.)
            #[allow(unused_assignments)]
            pub fn set_scene(&mut self, shared: &Shared, scene: &Scene) -> Result<bool, RenderError> {
                let mut published = Published::default();
                let mut remade = false;
                let mut restart = false;
                $(
                    let keep = self.$field.take().filter(|s| s.fits(scene));
                    let kept = keep.is_some();
                    self.$field = match keep {
                        Some(mut s) => {
                            if remade {
                                s.connect(shared, &published);
                            }
                            s.adjust(shared, scene);
                            Some(s)
                        }
                        None => <$ty as Simulation>::create(shared, scene, &published)?,
                    };
                    if !kept {
                        remade = true;
                        restart |= self.$field.as_ref().is_some_and(|s| s.restarts_clock());
                    }
                    if let Some(s) = &self.$field {
                        s.publish(&mut published);
                    }
                )*
                self.published = published;
                Ok(restart)
            }

            /// Each simulation the scene has, in order.
            fn each_mut(&mut self) -> Vec<&mut dyn Simulation> {
                let mut v: Vec<&mut dyn Simulation> = Vec::new();
                $(if let Some(s) = &mut self.$field { v.push(s); })*
                v
            }

            fn each(&self) -> Vec<&dyn Simulation> {
                let mut v: Vec<&dyn Simulation> = Vec::new();
                $(if let Some(s) = &self.$field { v.push(s); })*
                v
            }

            /// Publish again (after steps that moved windows or bodies).
            fn republish(&mut self) {
                let mut published = Published::default();
                $(if let Some(s) = &self.$field { s.publish(&mut published); })*
                self.published = published;
            }
        }

        /// Each simulation's shaders and uniforms, validated offline.
        pub(crate) const SIMULATIONS: &[TechniqueInfo] = &[$($info),*];
    };
}

// The liquid comes first: the interactive water's steps take what lands
// in it during the same clock steps, so the liquid's run is recorded (and
// submitted) before the water's.
simulations! {
    liquid: liquid::Liquid => liquid::INFO,
    ripples: ripples::dynamics::Dynamics => ripples::INFO,
    whitewater: whitewater::Whitewater => whitewater::INFO,
    surface: surface::Surface => surface::INFO,
}

impl Simulations {
    /// Replace a caller's heightfield's heights (see `Renderer::update_heightfield`).
    pub fn update_heightfield(
        &mut self,
        queue: &wgpu::Queue,
        heights: &[f32],
    ) -> Result<(), RenderError> {
        let surface = self.surface.as_mut().expect("the surface is always built");
        surface.update_heightfield(queue, heights)?;
        if let Some(d) = &mut self.ripples {
            d.heightfield_updated(heights);
        }
        self.republish();
        Ok(())
    }

    /// Whether any keeps state on the clock.
    pub fn stateful(&self) -> bool {
        self.each().iter().any(|s| s.pace() != Pace::Evaluated)
    }

    /// Offer a caller's input to each in order; whether one took it.
    /// A body's index (in [`Simulations::bodies`] order) is its index in
    /// the simulation that keeps it less those kept before.
    pub fn input(&mut self, input: Input) -> bool {
        let mut before = 0;
        self.each_mut().into_iter().any(|s| {
            let kept = s.bodies().len();
            let own = match input {
                Input::Pull(i, _) | Input::Place(i, _) if !(before..before + kept).contains(&i) => {
                    before += kept;
                    return false;
                }
                Input::Pull(i, target) => Input::Pull(i - before, target),
                Input::Place(i, position) => Input::Place(i - before, position),
                other => other,
            };
            s.input(&own)
        })
    }

    /// Dump `name`, if a simulation declares it.
    pub fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        if name == "bodies" {
            let json = ripples::readback::bodies_json(&self.bodies(), ctx.scene, ctx.time);
            return Some(Ok(crate::info::DumpData::Json(json)));
        }
        self.each().into_iter().find_map(|s| s.dump(name, ctx))
    }

    /// The moving bodies now (position, velocities, submerged volume).
    pub fn bodies(&self) -> Vec<BodyState> {
        self.each().iter().flat_map(|s| s.bodies()).collect()
    }

    /// Advance every simulation by the clock's `advance` towards the
    /// frame's time: a reset first if the clock went back, then its steps
    /// in batches (all but the last submitted at once, the last into
    /// `encoder`), then the frame's own time written.
    #[allow(clippy::too_many_arguments)]
    pub fn advance(
        &mut self,
        shared: &Shared,
        clock: &SimulationClock,
        advance: Advance,
        camera: &Camera,
        frame_time: f64,
        encoder: &mut wgpu::CommandEncoder,
        progress: &mut Option<Box<dyn FnMut(u64, u64)>>,
    ) {
        let queue = &shared.queue;
        self.prepare(queue, frame_time);
        if !self.stateful() {
            return;
        }
        if advance.reset {
            for s in self.each_mut() {
                s.reset(queue, advance.from);
            }
            self.couplings = Couplings::default();
        }
        let batches: Vec<u32> = clock.batches(advance.steps).collect();
        for (i, &steps) in batches.iter().enumerate() {
            if i + 1 == batches.len() {
                self.batch(shared, encoder, camera, frame_time, steps);
            } else {
                let mut early = shared.device.create_command_encoder(&Default::default());
                self.batch(shared, &mut early, camera, frame_time, steps);
                queue.submit([early.finish()]);
                if let Some(report) = progress.as_mut() {
                    let _ = shared.device.poll(wgpu::PollType::wait_indefinitely());
                    report((i as u64 + 1) * clock.batch() as u64, advance.steps);
                }
            }
        }
        if batches.len() > 1
            && let Some(report) = progress.as_mut()
        {
            report(advance.steps, advance.steps);
        }
    }

    /// Write what the frame's time decides, from what is published now.
    fn prepare(&mut self, queue: &wgpu::Queue, frame_time: f64) {
        let published = std::mem::take(&mut self.published);
        for s in self.each_mut() {
            s.prepare(queue, frame_time, &published);
        }
        self.published = published;
    }

    /// One batch of `steps` clock steps: the followers run up to each
    /// own-paced step's time, the surface is evaluated there when it is
    /// not current, then those steps run (each in a submission of its own
    /// where later work may read it back); the followers finish the batch.
    fn batch(
        &mut self,
        shared: &Shared,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        frame_time: f64,
        steps: u32,
    ) {
        let (device, queue) = (&shared.device, &shared.queue);
        let frame_end = (frame_time.max(0.0) * CLOCK_HZ as f64).floor() as u64;
        let published = std::mem::take(&mut self.published);
        let mut couplings = std::mem::take(&mut self.couplings);
        let mut sims = self.each_mut();
        // Every own-paced step due in the batch, by clock step then order.
        let schedules: Vec<(usize, Vec<(u64, f64)>)> = sims
            .iter_mut()
            .enumerate()
            .filter(|(_, s)| s.pace() == Pace::OwnSteps)
            .map(|(k, s)| (k, s.schedule(steps as u64, frame_end, queue)))
            .collect();
        let due = merge_due(schedules);
        let followers = sims.iter().any(|s| s.pace() == Pace::Follows);
        let mut followed = 0u64;
        let mut ctx =
            StepContext { shared, camera, published: &published, couplings: &mut couplings };
        for (n, &Due { at, time, sim: k }) in due.iter().enumerate() {
            let tolerance = sims[k].surface_tolerance();
            let stale = tolerance.is_some_and(|t| sims.iter().any(|s| s.stale_at(time, t)));
            let own = n + 1 < due.len() || stale || followers;
            let mut own_encoder = own.then(|| device.create_command_encoder(&Default::default()));
            let e = own_encoder.as_mut().unwrap_or(&mut *encoder);
            let before = at.saturating_sub(followed);
            for s in sims.iter_mut().filter(|s| s.pace() == Pace::Follows) {
                s.follow(&mut ctx, e, before as u32);
            }
            followed += before;
            if stale {
                for s in sims.iter_mut() {
                    s.evaluate(shared, e, time);
                }
            }
            sims[k].step(&mut ctx, e);
            if let Some(e) = own_encoder {
                queue.submit([e.finish()]);
            }
        }
        let rest = (steps as u64).saturating_sub(followed);
        for s in sims.iter_mut().filter(|s| s.pace() == Pace::Follows) {
            s.follow(&mut ctx, encoder, rest as u32);
        }
        for s in sims.iter_mut() {
            s.keep_leftovers(ctx.couplings);
        }
        couplings.splashes.clear();
        for s in sims.iter_mut() {
            s.finish(shared, encoder);
        }
        drop(sims);
        self.couplings = couplings;
        self.published = published;
        self.republish();
        self.prepare(queue, frame_time);
    }

    /// The coming frame's size (pixels): what depends on it is made anew
    /// and published before the frame reads it.
    pub fn set_frame_size(&mut self, shared: &Shared, size: (u32, u32)) {
        let mut changed = false;
        for s in self.each_mut() {
            changed |= s.frame_size(shared, size);
        }
        if changed {
            self.republish();
        }
    }

    /// The frame's own work, with its first stage (the surface at the
    /// frame's time), in order.
    pub fn record_frame(
        &mut self,
        shared: &Shared,
        encoder: &mut wgpu::CommandEncoder,
        plan: &crate::plan::FramePlan,
        mut timer: Option<&mut GpuTimer>,
    ) {
        for s in self.each_mut() {
            s.record_frame(shared, encoder, plan, timer.as_deref_mut());
        }
    }
}

/// An own-paced step due in a batch: after `at` of the batch's clock steps,
/// simulation `sim` (in registry order) steps to `time` (s).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Due {
    at: u64,
    time: f64,
    sim: usize,
}

/// The own-paced simulations' schedules (each a list of (clock steps before
/// it, its time)) merged into one list in clock order, simultaneous steps in
/// registry order: the order the scheduler walks a batch in.
fn merge_due(schedules: Vec<(usize, Vec<(u64, f64)>)>) -> Vec<Due> {
    let mut due = Vec::new();
    for (sim, schedule) in schedules {
        let mut at = 0;
        for (before, time) in schedule {
            at += before;
            due.push(Due { at, time, sim });
        }
    }
    due.sort_by_key(|d| (d.at, d.sim));
    due
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn own_paced_steps_merge_in_clock_order_then_registry_order() {
        // Simulation 1 steps every 6 clock steps, simulation 0 every 4,
        // over a batch of 12 that starts one clock step into both strides.
        let every = |stride: u64, first: u64| {
            let mut v = vec![(first, first as f64)];
            let mut at = first;
            while at + stride <= 12 {
                at += stride;
                v.push((stride, at as f64));
            }
            v
        };
        let due = merge_due(vec![(1, every(6, 5)), (0, every(4, 3))]);
        let order: Vec<(u64, usize)> = due.iter().map(|d| (d.at, d.sim)).collect();
        assert_eq!(order, [(3, 0), (5, 1), (7, 0), (11, 0), (11, 1)]);
        // Each keeps its own time.
        let times: Vec<f64> = due.iter().map(|d| d.time).collect();
        assert_eq!(times, [3.0, 5.0, 7.0, 11.0, 11.0]);
    }

    #[test]
    fn no_own_paced_simulation_means_the_followers_take_the_whole_batch() {
        assert!(merge_due(Vec::new()).is_empty());
        assert!(merge_due(vec![(2, Vec::new())]).is_empty());
    }
}
