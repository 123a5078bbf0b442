//! The renderer: a short orchestrator. It keeps the scene, the simulations
//! (`simulation/`: stepped on the one clock, publishing their state), the
//! techniques (`registry.rs`, in frame order) and what they share; each
//! frame it advances the simulations, plans (`plan.rs`: every decision,
//! once), uploads (the frame globals and each technique's uniforms) and
//! records every stage by walking the techniques (see ARCHITECTURE.md). It
//! names no technique and no simulation.

use crate::capabilities::Capabilities;
pub use crate::error::RenderError;
use crate::error_view::{self, ErrorView};
pub use crate::gpu_util::f16_to_f32;
use crate::plan::FramePlan;
use crate::probe::ProbePass;
use crate::registry::{GlobalSamplers, Techniques};
use crate::simulation::Simulations;
use crate::surface_kind::SurfaceKind;
use crate::targets::{TargetSettings, Targets, main_pass};
use crate::technique::{Bound, FrameContext, Shared, Stage};
use crate::timing::GpuTimer;
use hydrolux_core::camera::Camera;
use hydrolux_core::clock::{MAX_TIME_S, SimulationClock};
use hydrolux_core::scene::{DebugView, Scene};
use hydrolux_core::sky::SkyParams;

/// What one frame needs beyond the scene: where to draw, and when.
pub struct FrameInput<'a> {
    pub target: &'a wgpu::TextureView,
    pub size: (u32, u32),
    pub camera: Camera,
    /// Simulation time, seconds.
    pub time: f64,
}

pub struct Renderer {
    pub(crate) shared: Shared,
    pub(crate) simulations: Simulations,
    pub(crate) techniques: Techniques,
    pub(crate) bound: Bound,
    samplers: GlobalSamplers,
    pub(crate) probe: ProbePass,
    /// Screen-size targets, keyed by (size, what sizes them); rebuilt in
    /// one place ([`Renderer::render`]) when the key changes.
    pub(crate) targets: Option<Targets>,
    /// The scene as rendered: the caller's with its quality tier applied.
    pub(crate) scene: Scene,
    /// The scene as the caller gave it.
    requested: Scene,
    /// The resolved quality tier.
    quality: hydrolux_core::scene::Quality,
    pub(crate) timer: Option<GpuTimer>,
    pub(crate) timing: bool,
    pub(crate) last_timings: Vec<(&'static str, f64)>,
    /// The last frame's (or simulation step's) plan, for readbacks.
    pub(crate) last_plan: Option<FramePlan>,
    /// The fixed-step clock the simulations advance on.
    pub(crate) clock: SimulationClock,
    /// Told how a long catch-up goes (`set_catch_up_progress`).
    pub(crate) catch_up_progress: Option<Box<dyn FnMut(u64, u64)>>,
    /// Size of the caller's target in the last frame.
    output_size: (u32, u32),
    /// The error view's frame mode (`render.view = "error"`).
    error_view: Option<ErrorView>,
}

/// Fixed step of the simulations (s): the one clock's 120 Hz (`CLOCK_HZ`,
/// whose divisors the simulations' rates are).
pub const SIMULATION_STEP_S: f64 = 1.0 / hydrolux_core::scene::CLOCK_HZ as f64;
/// Steps recorded per GPU submission when catching up to a late time.
pub const SIMULATION_BATCH: u32 = 1024;

impl Renderer {
    /// Create every simulation and technique for drawing into textures of
    /// `target_format`. An adapter that cannot run Hydrolux, or any wgpu
    /// error on the way, is an error naming what failed (never wgpu's panic).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        crate::error::catch_gpu_errors(
            device,
            || "creating the renderer".into(),
            || Self::create(device, queue, target_format, scene),
        )
    }

    fn create(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        let caps = Capabilities::of(device);
        caps.check_supported()?;
        let requested = scene.clone();
        let quality = scene.render.quality.resolve(caps.cpu);
        let scene = &error_view::projective(&quality.apply(scene));
        let shared = Shared::new(device, queue, target_format, caps, scene)?;
        let simulations = Simulations::new(&shared, scene)?;
        let techniques = Techniques::new(&shared, scene)?;
        let l = &shared.layouts;
        let probe = ProbePass::new(device, &l.globals, &l.surface, SurfaceKind::of(scene));
        let samplers = GlobalSamplers::new(device);
        let bound = techniques.bound(&shared, &samplers, &simulations.published);
        let mut r = Renderer {
            shared,
            simulations,
            techniques,
            bound,
            samplers,
            probe,
            targets: None,
            scene: scene.clone(),
            requested,
            quality,
            timer: GpuTimer::new(device, queue),
            timing: false,
            last_timings: Vec::new(),
            last_plan: None,
            clock: SimulationClock::new(SIMULATION_STEP_S, SIMULATION_BATCH)
                .expect("valid clock constants"),
            output_size: (0, 0),
            error_view: None,
            catch_up_progress: None,
        };
        r.clock.set_memory(scene.simulation_memory()).expect("memory is at most 600 s");
        r.update_modes(scene);
        r.update_sky();
        Ok(r)
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.shared.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.shared.queue
    }

    pub fn target_format(&self) -> wgpu::TextureFormat {
        self.shared.target_format
    }

    /// The scene as given (`new`, `set_scene`); the renderer's own `scene`
    /// field is the one it renders ([`Renderer::rendered_scene`]).
    #[allow(clippy::misnamed_getters)]
    pub fn scene(&self) -> &Scene {
        &self.requested
    }

    /// The scene as rendered: [`Renderer::scene`] with its quality tier
    /// applied (`render.quality`; `auto` resolved for this adapter).
    pub fn rendered_scene(&self) -> &Scene {
        &self.scene
    }

    /// The quality tier in effect.
    pub fn quality(&self) -> hydrolux_core::scene::Quality {
        self.quality
    }

    /// Switch to another scene (or an edited one): rebuilds only what changed.
    pub fn set_scene(&mut self, scene: &Scene) -> Result<(), RenderError> {
        let device = self.shared.device.clone();
        crate::error::catch_gpu_errors(
            &device,
            || "applying the scene".into(),
            || {
                let quality = scene.render.quality.resolve(self.shared.caps.cpu);
                self.apply_scene(&error_view::projective(&quality.apply(scene)))?;
                self.quality = quality;
                self.requested = scene.clone();
                Ok(())
            },
        )
    }

    fn apply_scene(&mut self, scene: &Scene) -> Result<(), RenderError> {
        let shared = &mut self.shared;
        if scene.floor != self.scene.floor
            || scene.objects != self.scene.objects
            || scene.base_dir != self.scene.base_dir
        {
            shared.geometry = shared.meshes.upload(&shared.device, &shared.queue, scene)?;
            self.targets = None;
        }
        // A simulation that cannot join mid-run starts every simulation
        // again, catching up with the clock's time on the next frame.
        if self.simulations.set_scene(&self.shared, scene)? {
            self.clock.reset();
        }
        self.clock.set_memory(scene.simulation_memory()).expect("memory is at most 600 s");
        self.techniques.set_scene(&self.shared, &self.scene, scene)?;
        // Techniques keep their screen-size resources through an edit (what
        // sizes them is in the targets' key).
        self.bound =
            self.techniques.bound(&self.shared, &self.samplers, &self.simulations.published);
        let (device, l) = (&self.shared.device, &self.shared.layouts);
        self.probe.specialise(device, &l.globals, &l.surface, SurfaceKind::of(scene));
        self.update_modes(scene);
        self.scene = scene.clone();
        self.last_plan = None;
        self.update_sky();
        Ok(())
    }

    /// The error view's frame mode exists exactly while `scene` asks for it.
    fn update_modes(&mut self, scene: &Scene) {
        if scene.render.view != DebugView::Error {
            self.error_view = None;
        } else if self.error_view.is_none() {
            self.error_view = Some(ErrorView::new(&self.shared));
        }
    }

    /// Let every technique build what it keeps at the screen targets' size:
    /// once per new set of targets.
    fn resize_techniques(&mut self) {
        let Some(targets) = &self.targets else { return };
        for t in self.techniques.each_mut() {
            t.resize(&self.shared, targets);
        }
    }

    fn sky_params(&self) -> SkyParams {
        self.scene.sky_params()
    }

    fn update_sky(&mut self) {
        let p = self.sky_params();
        self.techniques.set_sky(&self.shared.queue, p);
    }

    /// Advance the simulations to the frame's time, plan the frame as
    /// `scene` draws it (the rendered scene, or the error view's traced
    /// drawing of it), write the frame globals and the shared view slots,
    /// let every technique write its uniforms; then record `stages`.
    fn run(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: (Camera, (u32, u32), f64),
        output: Option<&wgpu::TextureView>,
        stages: &[Stage],
        scene: Option<&Scene>,
    ) {
        let scene = scene.unwrap_or(&self.scene);
        let (shared, queue) = (&self.shared, &self.shared.queue);
        // Simulations start at t = 0: earlier (or non-finite) times show the
        // initial state.
        let sim_time = if input.2.is_finite() { input.2.clamp(0.0, MAX_TIME_S) } else { 0.0 };
        let advance = self.clock.advance_to(sim_time).expect("a finite time from 0 on");
        self.simulations.set_frame_size(shared, input.1);
        let (camera, progress) = (&input.0, &mut self.catch_up_progress);
        self.simulations.advance(shared, &self.clock, advance, camera, input.2, encoder, progress);
        // Bodies the simulations moved are drawn where they are now.
        for &(i, transform) in &self.simulations.published.bodies {
            shared.geometry.move_object(queue, i, transform);
        }
        // The frame reads what the simulations published (theirs again after it).
        let published = &std::mem::take(&mut self.simulations.published);
        let world = self.techniques.world(shared, scene, published.surface(), self.sky_params());
        let mut plan = FramePlan::new(scene, &world, input.0, input.1, input.2);
        plan.simulation = advance;
        if output.is_some() {
            plan.frame.modes.output_width = self.output_size.0;
            plan.frame.modes.output_height = self.output_size.1;
        }
        shared.views.write(queue, &plan);
        queue.write_buffer(&shared.frame_buffer, 0, bytemuck::bytes_of(&plan.frame));
        let frame = FrameContext {
            plan: &plan,
            scene,
            shared,
            bound: &self.bound,
            published,
            targets: self.targets.as_ref().filter(|_| output.is_some()),
            output,
        };
        for t in self.techniques.each_mut() {
            t.prepare(queue, &frame);
        }
        let mut timer = if self.timing && output.is_some() { self.timer.as_mut() } else { None };
        if let Some(t) = timer.as_deref_mut() {
            t.begin_frame();
        }
        for &stage in stages {
            match stage {
                Stage::Medium | Stage::Main => {
                    let targets = frame.targets();
                    let (label, clear) = match stage {
                        Stage::Medium => ("medium", true),
                        _ => ("sky, scene and water", false),
                    };
                    let mut pass = main_pass(encoder, targets, label, clear, timer.as_deref_mut());
                    for t in self.techniques.each() {
                        t.draw(stage, &mut pass, &frame);
                    }
                    drop(pass);
                    if let (Stage::Main, Some(copy), Some(pass)) =
                        (stage, &targets.medium_copy, &shared.medium_copy)
                    {
                        pass.record(encoder, copy, &targets.depth_stencil_view);
                    }
                }
                _ => {
                    if stage == Stage::Simulate {
                        let t = timer.as_deref_mut();
                        self.simulations.record_frame(shared, encoder, &plan, t);
                    }
                    for t in self.techniques.each_mut() {
                        t.record(stage, encoder, &frame, timer.as_deref_mut());
                    }
                }
            }
        }
        if let Some(t) = timer {
            t.resolve(encoder);
        }
        self.simulations.published = published.clone();
        self.last_plan = Some(plan);
    }

    /// Write this frame's inputs and advance the simulations, without
    /// drawing: what [`Renderer::render`] does first. Queries and dumps use
    /// it alone.
    pub fn simulate(&mut self, camera: &Camera, size: (u32, u32), time: f64) {
        let mut encoder = self.shared.device.create_command_encoder(&Default::default());
        self.run(&mut encoder, (*camera, size, time), None, &[Stage::Simulate], None);
        self.shared.queue.submit([encoder.finish()]);
    }

    fn target_settings(&self) -> TargetSettings {
        TargetSettings {
            reflection_resolution: self.scene.render.reflection_resolution,
            reflection_margin: self.scene.render.fov_margin,
            godray_resolution: self.scene.godrays.resolution,
            refractive_objects: crate::passes::water_object::refractive_bounds(
                &self.shared.geometry,
                &self.scene,
            )
            .is_some(),
        }
    }

    /// Start the temporal anti-aliasing's history again (`render.antialias`):
    /// the next frame is drawn without jitter and shown as drawn, and the
    /// frames after it are blended into it evenly at first. An offline
    /// render draws each written frame this way, `n` times at its time
    /// (the CLI's `--samples`), so that every frame is a supersampled still
    /// whatever frames were drawn before it.
    pub fn restart_antialiasing(&mut self) {
        self.techniques.restart_history();
    }

    /// Record one frame into `encoder`, drawing into `input.target`.
    /// The frame is drawn at the quality tier's fraction of the output's
    /// size (`Quality::render_scale`) and filtered up by the tone map.
    pub fn render(&mut self, encoder: &mut wgpu::CommandEncoder, input: &FrameInput) {
        let scale = self.quality.render_scale();
        let inner = |n: u32| ((n as f32 * scale).round() as u32).max(1);
        let size = (inner(input.size.0), inner(input.size.1));
        let key = (size, self.target_settings());
        if self.targets.as_ref().map(|t| (t.size, t.settings)) != Some(key) {
            let s = &self.shared;
            let medium_copy = s.medium_copy.as_ref();
            self.targets = Some(Targets::new(
                &s.device,
                &s.downsampler,
                s.depth_format,
                medium_copy,
                key.0,
                key.1,
            ));
            self.resize_techniques();
        }
        self.output_size = input.size;
        let frame = (input.camera, size, input.time);
        let Some(mut error_view) = self.error_view.take() else {
            self.run(encoder, frame, Some(input.target), &Stage::ALL, None);
            return;
        };
        // The error view: the frame as drawn (projective), then ray traced
        // at the same time from the same published state (no simulation
        // steps), then their difference.
        let [projective, traced] = error_view.images(&self.shared.device, input.size);
        self.run(encoder, frame, Some(&projective), &Stage::ALL, None);
        let timing = std::mem::replace(&mut self.timing, false);
        let traced_scene = error_view::traced(&self.scene);
        self.run(encoder, frame, Some(&traced), &Stage::ALL, Some(&traced_scene));
        self.timing = timing;
        error_view.record(encoder, input.target);
        self.error_view = Some(error_view);
    }
}
