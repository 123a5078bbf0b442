//! The renderer: a short orchestrator. It keeps the scene, the techniques
//! (`registry.rs`, in frame order) and what they share; each frame it plans
//! (`plan.rs`: every decision, once), uploads (the frame globals and each
//! technique's uniforms) and records every stage by walking the techniques
//! (see ARCHITECTURE.md).

use crate::capabilities::Capabilities;
pub use crate::error::RenderError;
use crate::gpu_util::*;
use crate::meshes::{GeometryPass, Winding};
use crate::mips::Downsampler;
use crate::passes::probe::ProbePass;
use crate::passes::ripples::dynamics::Dynamics;
use crate::plan::{FramePlan, World};
use crate::registry::Techniques;
use crate::targets::{TargetSettings, Targets};
use crate::technique::{Bound, FrameContext, Layouts, Shared, Stage, ViewSlots};
use crate::timing::GpuTimer;
use crate::uniforms::FrameUniforms;
use hydrolux_core::camera::Camera;
use hydrolux_core::clock::{MAX_TIME_S, SimulationClock};
use hydrolux_core::projective::ClipPlane;
use hydrolux_core::scene::{DebugView, Scene};
use hydrolux_core::sky::{SkyParams, sky_irradiance_up};

/// What one frame needs beyond the scene: where to draw, and when.
pub struct FrameInput<'a> {
    pub target: &'a wgpu::TextureView,
    pub size: (u32, u32),
    pub camera: Camera,
    /// Simulation time, seconds.
    pub time: f64,
}

/// Samplers the frame globals bind.
struct GlobalSamplers {
    sky: wgpu::Sampler,
    shadow: wgpu::Sampler,
    caustics: wgpu::Sampler,
}

pub struct Renderer {
    pub(crate) shared: Shared,
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
    pub(crate) sky_irradiance: glam::Vec3,
    pub(crate) timer: Option<GpuTimer>,
    pub(crate) timing: bool,
    pub(crate) last_timings: Vec<(&'static str, f64)>,
    /// The last frame's (or simulation step's) plan, for readbacks.
    pub(crate) last_plan: Option<FramePlan>,
    /// The fixed-step clock stateful simulations advance on.
    clock: SimulationClock,
    /// Told how a long catch-up goes (`set_catch_up_progress`).
    catch_up_progress: Option<Box<dyn FnMut(u64, u64)>>,
    /// Size of the caller's target in the last frame.
    output_size: (u32, u32),
    /// The error view's second drawing and its pass (`render.view = "error"`).
    truth: Option<Box<crate::passes::truth::TruthView>>,
}

/// Fixed step of stateful simulations (s): the one clock's 120 Hz
/// (`CLOCK_HZ`, whose divisors the simulations' rates are).
pub const SIMULATION_STEP_S: f64 = 1.0 / hydrolux_core::scene::CLOCK_HZ as f64;
/// Steps recorded per GPU submission when catching up to a late time.
pub const SIMULATION_BATCH: u32 = 1024;

impl Renderer {
    /// Create every technique for drawing into textures of `target_format`.
    /// An adapter that cannot run Hydrolux, or any wgpu error on the way,
    /// is an error naming what failed (never wgpu's panic).
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
        let scene = &crate::passes::truth::projective(&quality.apply(scene));
        let layouts = Layouts::new(device);
        let frame_buffer = uniform_buffer(device, "frame", &FrameUniforms::default());
        let samplers = GlobalSamplers {
            sky: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("sky"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            shadow: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            caustics: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("caustic map"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
        };
        let frame_only = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame only"),
            layout: &layouts.frame_only,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buffer.as_entire_binding(),
            }],
        });
        let depth_format = crate::targets::main_depth_format(&caps);
        let downsampler = Downsampler::new(device);
        let meshes =
            GeometryPass::new(device, queue, &layouts.globals, &layouts.frame_only, depth_format);
        let geometry = meshes.upload(device, queue, scene)?;
        let slot = |label, winding| meshes.view_slot(device, label, winding);
        let views = ViewSlots {
            main: slot("main view", Winding::Normal),
            reflection: slot("reflection view", Winding::Mirrored),
            refraction: slot("refraction view", Winding::Normal),
            reflection_under: slot("reflection under view", Winding::Mirrored),
            refraction_over: slot("refraction over view", Winding::Normal),
            shadow: slot("shadow view", Winding::Normal),
            object_light: slot("object light view", Winding::Normal),
        };
        let shared = Shared {
            device: device.clone(),
            queue: queue.clone(),
            medium_copy: (!caps.depth_and_stencil_reads || !caps.depth_stencil_copies)
                .then(|| crate::targets::MediumCopyPass::new(device, depth_format)),
            caps,
            target_format,
            depth_format,
            layouts,
            frame_buffer,
            frame_only,
            downsampler,
            meshes,
            geometry,
            views,
        };
        let techniques = Techniques::new(&shared, scene)?;
        let l = &shared.layouts;
        let probe = ProbePass::new(
            device,
            &l.globals,
            &l.surface,
            crate::surface_kind::SurfaceKind::of(scene),
        );
        let bound = Bound {
            globals: Self::globals(&shared, &techniques, &samplers),
            surface: techniques.surface.group.clone(),
            shadow_values: Self::shadow_values(&shared, &techniques),
        };
        let mut r = Renderer {
            shared,
            techniques,
            bound,
            samplers,
            probe,
            targets: None,
            scene: scene.clone(),
            requested,
            quality,
            sky_irradiance: glam::Vec3::ZERO,
            timer: GpuTimer::new(device, queue),
            timing: false,
            last_timings: Vec::new(),
            last_plan: None,
            clock: SimulationClock::new(SIMULATION_STEP_S, SIMULATION_BATCH)
                .expect("valid clock constants"),
            output_size: (0, 0),
            truth: None,
            catch_up_progress: None,
        };
        r.clock.set_memory(scene.simulation_memory()).expect("memory is at most 600 s");
        r.update_truth(scene)?;
        r.update_sky();
        Ok(r)
    }

    /// The frame globals (group 0): the frame's uniforms and what the sky,
    /// geometry (shadow map), caustics and water-object techniques wrote.
    fn globals(shared: &Shared, t: &Techniques, samplers: &GlobalSamplers) -> wgpu::BindGroup {
        let tv = wgpu::BindingResource::TextureView;
        let sampler = wgpu::BindingResource::Sampler;
        shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &shared.layouts.globals,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: shared.frame_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry { binding: 1, resource: t.sky.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&t.sky.cube_view) },
                wgpu::BindGroupEntry { binding: 3, resource: sampler(&samplers.sky) },
                wgpu::BindGroupEntry { binding: 4, resource: tv(&t.geometry.shadow.view) },
                wgpu::BindGroupEntry { binding: 5, resource: sampler(&samplers.shadow) },
                wgpu::BindGroupEntry { binding: 6, resource: tv(&t.caustics.map.view) },
                wgpu::BindGroupEntry { binding: 7, resource: sampler(&samplers.caustics) },
                wgpu::BindGroupEntry { binding: 8, resource: tv(&t.water_objects.light.map_view) },
            ],
        })
    }

    /// The shadow map's values, for its debug view.
    fn shadow_values(shared: &Shared, t: &Techniques) -> wgpu::BindGroup {
        shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow values"),
            layout: &shared.layouts.shadow_values,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&t.geometry.shadow.view),
            }],
        })
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
                self.apply_scene(&crate::passes::truth::projective(&quality.apply(scene)))?;
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
        // A new simulation of the interactive water starts from still water
        // and catches up with the clock's time on the next frame.
        let ripples_restart = match &self.techniques.surface.dynamics {
            Some(d) => !d.fits(scene),
            None => Dynamics::new_needed(scene),
        };
        if ripples_restart {
            self.clock.reset();
        }
        self.clock.set_memory(scene.simulation_memory()).expect("memory is at most 600 s");
        if self.techniques.set_scene(&self.shared, &self.scene, scene)? {
            self.bound.globals = Self::globals(&self.shared, &self.techniques, &self.samplers);
            self.bound.shadow_values = Self::shadow_values(&self.shared, &self.techniques);
        }
        self.bound.surface = self.techniques.surface.group.clone();
        let (device, l) = (&self.shared.device, &self.shared.layouts);
        self.probe.specialise(
            device,
            &l.globals,
            &l.surface,
            crate::surface_kind::SurfaceKind::of(scene),
        );
        if let Some(truth) = self.truth.as_mut().filter(|_| scene.render.view == DebugView::Error) {
            truth.set_scene(&self.shared, &self.scene, scene)?;
        }
        // Techniques keep their screen-size resources through an edit (what
        // sizes them is in the targets' key); only a new traced water needs
        // its own (`update_truth`).
        self.update_truth(scene)?;
        self.scene = scene.clone();
        self.last_plan = None;
        self.update_sky();
        Ok(())
    }

    /// Let every technique (and the error view's traced water) build what
    /// it keeps at the screen targets' size: once per new set of targets.
    fn resize_techniques(&mut self) {
        let Some(targets) = &self.targets else { return };
        for t in self.techniques.each_mut() {
            t.resize(&self.shared, targets);
        }
        if let Some(truth) = &mut self.truth {
            crate::technique::Technique::resize(&mut truth.water, &self.shared, targets);
        }
    }

    /// The error view's traced drawing exists exactly while `scene` (as
    /// drawn) asks for it.
    fn update_truth(&mut self, scene: &Scene) -> Result<(), RenderError> {
        let wanted = scene.render.view == DebugView::Error;
        if !wanted {
            self.truth = None;
        } else if self.truth.is_none() {
            let mut truth =
                crate::passes::truth::TruthView::new(&self.shared, scene, &self.techniques.water)?;
            if let Some(targets) = &self.targets {
                crate::technique::Technique::resize(&mut truth.water, &self.shared, targets);
            }
            self.truth = Some(Box::new(truth));
        }
        Ok(())
    }

    /// Replace the heights of a `water.model = "heightfield"` surface (same
    /// samples per side as its file, row = z, col = x, metres), e.g. from a
    /// simulation of the caller's. Everything that reads the surface follows
    /// from the next frame: shading, the medium division, height queries,
    /// and the caustics and god rays (their maps are remade).
    pub fn update_heightfield(&mut self, heights: &[f32]) -> Result<(), RenderError> {
        self.techniques.surface.update_heightfield(&self.shared.queue, heights)?;
        self.techniques.caustics.current = false;
        Ok(())
    }

    fn sky_params(&self) -> SkyParams {
        SkyParams::new(self.scene.sun_direction(), self.scene.sky.turbidity)
    }

    fn update_sky(&mut self) {
        let p = self.sky_params();
        self.sky_irradiance = sky_irradiance_up(&p);
        self.techniques.sky.prepare(&self.shared.queue, p);
    }

    /// Collect per-pass GPU timestamps for each frame (where the adapter supports them).
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    pub fn has_timestamps(&self) -> bool {
        self.timer.is_some()
    }

    /// Per-pass GPU milliseconds of the last frame, once its submission has
    /// been waited for ([`Renderer::collect_timings`]).
    pub fn last_timings(&self) -> &[(&'static str, f64)] {
        &self.last_timings
    }

    /// Wait for the last frame and read its pass timings (no-op without timing).
    pub fn collect_timings(&mut self) {
        if let (true, Some(t)) = (self.timing, &self.timer) {
            self.last_timings = t.read(&self.shared.device);
        }
    }

    /// What the renderer holds that the frame plan depends on.
    fn world(&self) -> World {
        let t = &self.techniques;
        World {
            shadow_bounds: self.shared.geometry.shadow_bounds,
            refractive_bounds: self.shared.geometry.refractive_bounds,
            has_geometry: self.shared.geometry.triangle_count > 0,
            vertical_reach: t.surface.vertical_reach,
            cull_margin: t.surface.bounds_margin,
            surface_moving: t.surface.moving,
            unresolved_variance: t.surface.unresolved_variance,
            shadow_resolution: t.geometry.shadow.resolution,
            object_light_resolution: t.water_objects.light.resolution,
            sky: self.sky_params(),
            sky_irradiance: self.sky_irradiance,
            caustics_current: t.caustics.current,
            object_light_current: t.water_objects.current,
        }
    }

    /// Plan the frame, write the frame globals and the shared view slots,
    /// and let every technique write its uniforms; then record `stages`.
    fn run(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: (Camera, (u32, u32), f64),
        output: Option<&wgpu::TextureView>,
        stages: &[Stage],
    ) {
        let mut plan = FramePlan::new(&self.scene, &self.world(), input.0, input.1, input.2);
        if output.is_some() {
            plan.frame.modes.output_width = self.output_size.0;
            plan.frame.modes.output_height = self.output_size.1;
        }
        // Simulations start at t = 0: earlier (or non-finite) times show the
        // initial state.
        let sim_time = if input.2.is_finite() { input.2.clamp(0.0, MAX_TIME_S) } else { 0.0 };
        plan.simulation = self.clock.advance_to(sim_time).expect("a finite time from 0 on");
        let (shared, queue) = (&self.shared, &self.shared.queue);
        let (m, v) = (&plan.matrices, &shared.views);
        v.main.write(queue, m.view_proj, ClipPlane::none().0);
        v.reflection.write(queue, m.reflection, ClipPlane::above(0.0).0);
        v.refraction.write(queue, m.refraction, ClipPlane::below(0.0).0);
        v.reflection_under.write(queue, m.reflection, ClipPlane::below(0.0).0);
        v.refraction_over.write(queue, m.refraction, ClipPlane::above(0.0).0);
        if let Some(shadow) = m.shadow {
            v.shadow.write(queue, shadow, ClipPlane::none().0);
        }
        if let Some(o) = &plan.object_light {
            v.object_light.write(queue, o.view_proj, ClipPlane::none().0);
        }
        queue.write_buffer(&shared.frame_buffer, 0, bytemuck::bytes_of(&plan.frame));
        let frame = FrameContext {
            plan: &plan,
            scene: &self.scene,
            shared,
            bound: &self.bound,
            targets: self.targets.as_ref().filter(|_| output.is_some()),
            output,
        };
        for t in self.techniques.each_mut() {
            t.prepare(queue, &frame);
        }
        record_simulation_steps(
            &mut self.techniques,
            &self.clock,
            encoder,
            &frame,
            &mut self.catch_up_progress,
        );
        // Bodies the simulation moved are drawn where they are now.
        if let Some(d) = &self.techniques.surface.dynamics {
            for (i, transform) in d.transforms() {
                self.shared.geometry.move_object(queue, i, transform);
            }
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
                    for t in self.techniques.each_mut() {
                        t.record(stage, encoder, &frame, timer.as_deref_mut());
                    }
                }
            }
        }
        if let Some(t) = timer {
            t.resolve(encoder);
        }
        self.last_plan = Some(plan);
    }

    /// Disturb the interactive water at world (x, z): a crater of `radius`
    /// and depth `strength` (m) lands in its next step (a click in the
    /// viewer, a thrown stone). Returns false without `water.dynamic`.
    pub fn disturb(&mut self, x: f32, z: f32, radius: f32, strength: f32) -> bool {
        let Some(r) = self.techniques.surface.dynamics.as_mut().and_then(|d| d.ripples.as_mut())
        else {
            return false;
        };
        r.disturb(hydrolux_core::waves::ripples::Drop {
            x: x as f64,
            z: z as f64,
            radius: radius as f64,
            strength: strength as f64,
        });
        true
    }

    /// A splash of the caller's (an explosion, a thrown stone): its spray,
    /// bubbles and foam are born in the next simulation step. Returns false
    /// when the scene runs no white water (or too many splashes wait).
    pub fn splash(&mut self, splash: hydrolux_core::whitewater::Splash) -> bool {
        self.techniques.surface.whitewater.as_mut().is_some_and(|w| w.splash(splash))
    }

    /// The moving bodies now: position, orientation, velocities and
    /// submerged volume of each (empty if nothing moves).
    pub fn bodies(&self) -> Vec<hydrolux_core::bodies::BodyState> {
        self.techniques.surface.dynamics.as_ref().map_or(Vec::new(), |d| d.states())
    }

    /// Pull moving body `i` (in [`Renderer::bodies`] order) towards world
    /// `target` over the next steps: the viewer's drag.
    pub fn pull_body(&mut self, i: usize, target: glam::Vec3) {
        if let Some(d) = &mut self.techniques.surface.dynamics {
            d.pull(i, target.as_dvec3());
        }
    }

    /// Put moving body `i` at world `position`, at rest (drop it from there).
    pub fn place_body(&mut self, i: usize, position: glam::Vec3) {
        if let Some(d) = &mut self.techniques.surface.dynamics {
            d.place(i, position.as_dvec3());
        }
    }

    /// Start stateful simulations again from their initial state; the next
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

    /// Simulated time (s) of the stateful simulations' current state: the
    /// last frame's time rounded down to the clock's step.
    pub fn simulation_time(&self) -> f64 {
        self.clock.time()
    }

    /// Write this frame's inputs and advance the simulation, without drawing:
    /// what [`Renderer::render`] does first. Queries and dumps use it alone.
    pub fn simulate(&mut self, camera: &Camera, size: (u32, u32), time: f64) {
        let mut encoder = self.shared.device.create_command_encoder(&Default::default());
        self.run(&mut encoder, (*camera, size, time), None, &[Stage::Simulate]);
        self.shared.queue.submit([encoder.finish()]);
    }

    fn target_settings(&self) -> TargetSettings {
        TargetSettings {
            reflection_resolution: self.scene.render.reflection_resolution,
            reflection_margin: self.scene.render.fov_margin,
            godray_resolution: self.scene.godrays.resolution,
            refractive_objects: self.shared.geometry.refractive_bounds.is_some(),
        }
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
        let Some(mut truth) = self.truth.take() else {
            self.run(encoder, frame, Some(input.target), &Stage::ALL);
            return;
        };
        // The error view: the frame projective, then ray traced at the same
        // time (no simulation steps) with the traced water swapped in, then
        // their difference.
        use hydrolux_core::scene::WaterMethod;
        let [projective, traced] = truth.images(&self.shared.device, input.size);
        self.run(encoder, frame, Some(&projective), &Stage::ALL);
        std::mem::swap(&mut self.techniques.water, &mut truth.water);
        self.scene.water.method = WaterMethod::Raytrace;
        let timing = std::mem::replace(&mut self.timing, false);
        self.run(encoder, frame, Some(&traced), &Stage::ALL);
        self.timing = timing;
        self.scene.water.method = WaterMethod::Projective;
        std::mem::swap(&mut self.techniques.water, &mut truth.water);
        truth.record(encoder, input.target);
        self.truth = Some(truth);
    }
}

/// The largest `ocean.resolution` (a power of two, 64 to 1024) whose FFT
/// buffers fit this device's storage-buffer limit with `cascades` cascades.
pub fn largest_ocean_resolution(device: &wgpu::Device, cascades: u32) -> u32 {
    let max = Capabilities::of(device).max_storage_buffer;
    [1024u32, 512, 256, 128, 64]
        .into_iter()
        .find(|&n| crate::passes::ocean::fields_bytes(n, cascades) <= max)
        .unwrap_or(64)
}

/// IEEE half → single precision.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 => {
            if frac == 0.0 {
                sign * f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => sign * (1.0 + frac / 1024.0) * 2f32.powi(exp - 15),
    }
}

/// One of the main view's two render passes (the medium classification
/// clears; the scene loads), over the HDR image and the depth-stencil.
fn main_pass(
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
    label: &'static str,
    clear: bool,
    timer: Option<&mut GpuTimer>,
) -> wgpu::RenderPass<'static> {
    let load = |v| if clear { wgpu::LoadOp::Clear(v) } else { wgpu::LoadOp::Load };
    encoder
        .begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: if clear {
                        wgpu::LoadOp::Clear(wgpu::Color::BLACK)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_stencil_view,
                depth_ops: Some(wgpu::Operations { load: load(0.0), store: wgpu::StoreOp::Store }),
                stencil_ops: Some(wgpu::Operations {
                    load: if clear { wgpu::LoadOp::Clear(0) } else { wgpu::LoadOp::Load },
                    store: wgpu::StoreOp::Store,
                }),
            }),
            timestamp_writes: timer.and_then(|t| t.render_writes(label)),
            occlusion_query_set: None,
            multiview_mask: None,
        })
        .forget_lifetime()
}

/// Advance every stateful technique to the plan's time: a reset first if
/// the clock went back, then its steps in batches; all batches but the
/// last are submitted at once (a late still is a few large submissions,
/// not thousands of frames), the last goes into the frame's encoder.
fn record_simulation_steps(
    techniques: &mut Techniques,
    clock: &SimulationClock,
    encoder: &mut wgpu::CommandEncoder,
    frame: &FrameContext,
    progress: &mut Option<Box<dyn FnMut(u64, u64)>>,
) {
    let advance = frame.plan.simulation;
    let (queue, dt) = (&frame.shared.queue, clock.dt());
    let mut stateful: Vec<_> =
        techniques.each_mut().into_iter().filter(|t| t.simulates()).collect();
    if stateful.is_empty() {
        return;
    }
    if advance.reset {
        for t in stateful.iter_mut() {
            t.reset_state(queue, advance.from);
        }
    }
    let batches: Vec<u32> = clock.batches(advance.steps).collect();
    for (i, &steps) in batches.iter().enumerate() {
        if i + 1 == batches.len() {
            for t in stateful.iter_mut() {
                t.step(encoder, frame, steps, dt);
            }
        } else {
            let mut early = frame.shared.device.create_command_encoder(&Default::default());
            for t in stateful.iter_mut() {
                t.step(&mut early, frame, steps, dt);
            }
            queue.submit([early.finish()]);
            if let Some(report) = progress.as_mut() {
                let _ = frame.shared.device.poll(wgpu::PollType::wait_indefinitely());
                let done = (i as u64 + 1) * clock.batch() as u64;
                report(done, advance.steps);
            }
        }
    }
    if batches.len() > 1
        && let Some(report) = progress.as_mut()
    {
        report(advance.steps, advance.steps);
    }
}
