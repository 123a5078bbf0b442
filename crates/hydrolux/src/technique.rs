//! Techniques as plug-ins. Each technique (`passes/<name>/`) owns its
//! settings' GPU side, resources, uniforms, shaders and recording, and
//! implements [`Technique`]; the renderer walks them in registry order
//! (`registry.rs`) for each [`Stage`] of a planned frame. What techniques
//! read from each other is in [`Shared`] (created once) and [`Bound`] (the
//! bind groups that join resources several techniques write).

use crate::error::RenderError;
use crate::gpu_util::*;
pub(crate) use crate::info::{DumpData, TechniqueInfo};
use crate::meshes::{GeometryPass, SceneGeometry, ViewSlot};
use crate::mips::Downsampler;
use crate::plan::FramePlan;
use crate::targets::Targets;
use crate::timing::GpuTimer;
use hydrolux_core::scene::Scene;

/// Where in a frame a technique records, in frame order. `Medium` and
/// `Main` are drawn inside the main view's two shared render passes
/// ([`Technique::draw`]); the others open passes of their own
/// ([`Technique::record`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    /// Compute that later stages read: the sky bake, the ocean, caustics.
    Simulate,
    /// Views from the sun: the shadow map, refractive objects' light.
    Light,
    /// Views the water looks up: reflection and refraction.
    Offscreen,
    /// The main view's medium classification (stencil).
    Medium,
    /// The main view: background, scene and water, per medium.
    Main,
    /// Light scattered in the media (god rays, fog).
    Volume,
    /// What is drawn over the lit image (refractive objects).
    Composite,
    /// Into the caller's target (tone map or a debug view).
    Output,
}

impl Stage {
    /// Every stage, in frame order.
    pub const ALL: [Stage; 8] = [
        Stage::Simulate,
        Stage::Light,
        Stage::Offscreen,
        Stage::Medium,
        Stage::Main,
        Stage::Volume,
        Stage::Composite,
        Stage::Output,
    ];
}

/// The geometry views: one uniform slot per view.
pub(crate) struct ViewSlots {
    pub main: ViewSlot,
    pub reflection: ViewSlot,
    pub refraction: ViewSlot,
    pub reflection_under: ViewSlot,
    pub refraction_over: ViewSlot,
    pub shadow: ViewSlot,
    /// Refractive objects' light view.
    pub object_light: ViewSlot,
}

impl ViewSlots {
    /// Each view's matrix and clip plane as `plan` decided them.
    pub fn write(&self, queue: &wgpu::Queue, plan: &FramePlan) {
        use hydrolux_core::projective::ClipPlane;
        let m = &plan.matrices;
        // The reflections' eye is the main one mirrored in the water plane;
        // the refractions keep the main eye (their bending is approximate).
        let eye = glam::Vec3::from(plan.frame.view.position);
        let mirrored = eye * glam::Vec3::new(1.0, -1.0, 1.0);
        self.main.write(queue, m.view_proj, ClipPlane::none().0, eye);
        self.reflection.write(queue, m.reflection, ClipPlane::above(0.0).0, mirrored);
        self.refraction.write(queue, m.refraction, ClipPlane::below(0.0).0, eye);
        self.reflection_under.write(queue, m.reflection, ClipPlane::below(0.0).0, mirrored);
        self.refraction_over.write(queue, m.refraction, ClipPlane::above(0.0).0, eye);
        if let Some(shadow) = m.shadow {
            self.shadow.write(queue, shadow, ClipPlane::none().0, eye);
        }
        if let Some(o) = &plan.object_light {
            self.object_light.write(queue, o.view_proj, ClipPlane::none().0, eye);
        }
    }
}

/// Bind group layouts every technique may bind.
pub(crate) struct Layouts {
    /// Group 0 of render passes: the frame globals, sky, shadow map, caustics.
    pub globals: wgpu::BindGroupLayout,
    /// Group 0 of passes that write something the globals hold: the frame alone.
    pub frame_only: wgpu::BindGroupLayout,
    /// The water surface (whichever model makes it).
    pub surface: wgpu::BindGroupLayout,
    /// The shadow map's values (the tone map's debug view).
    pub shadow_values: wgpu::BindGroupLayout,
}

impl Layouts {
    pub fn new(device: &wgpu::Device) -> Self {
        let (vs, fs, cs) =
            (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::COMPUTE);
        let all = vs | fs | cs;
        let globals = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                uniform_entry(0, all),
                uniform_entry(1, all),
                texture_entry(2, all, wgpu::TextureViewDimension::Cube, true),
                sampler_entry(3, all),
                depth_texture_entry(4, all),
                layout_entry(
                    5,
                    all,
                    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                ),
                texture_entry(6, all, wgpu::TextureViewDimension::D2Array, true),
                sampler_entry(7, all),
                texture_entry(8, all, wgpu::TextureViewDimension::D2, true),
                uniform_entry(9, all),
            ],
        });
        // The shadow map again, for reading its values (the debug view):
        // GLSL cannot `textureLoad` a comparison texture. A group of its
        // own, so that it does not count against every pass's textures.
        let shadow_values = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow values"),
            entries: &[texture_entry(0, fs, wgpu::TextureViewDimension::D2, false)],
        });
        let frame_only = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame only"),
            entries: &[uniform_entry(0, all)],
        });
        let surface = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("surface"),
            entries: &[
                uniform_entry(0, all),
                texture_entry(1, all, wgpu::TextureViewDimension::D2Array, true),
                texture_entry(2, all, wgpu::TextureViewDimension::D2Array, true),
                texture_entry(3, all, wgpu::TextureViewDimension::D2Array, true),
                sampler_entry(4, all),
                sampler_entry(5, all),
                texture_entry(6, all, wgpu::TextureViewDimension::D2, false),
                texture_entry(7, all, wgpu::TextureViewDimension::D2, true),
                texture_entry(8, all, wgpu::TextureViewDimension::D2, true),
            ],
        });
        Layouts { globals, frame_only, surface, shadow_values }
    }
}

/// What is created once and read by several techniques.
pub(crate) struct Shared {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// What the device can do: techniques choose from it, not the device.
    pub caps: crate::capabilities::Capabilities,
    /// The stencil's colour copy, where the device needs one.
    pub medium_copy: Option<crate::targets::MediumCopyPass>,
    /// The caller's target format (the tone map writes it).
    pub target_format: wgpu::TextureFormat,
    /// The main view's depth-stencil format (the device's best).
    pub depth_format: wgpu::TextureFormat,
    pub layouts: Layouts,
    /// The frame globals' uniform buffer (written once per frame from the plan).
    pub frame_buffer: wgpu::Buffer,
    pub frame_only: wgpu::BindGroup,
    pub downsampler: Downsampler,
    /// Pipelines that draw the scene's meshes (any view), and the meshes.
    pub meshes: GeometryPass,
    pub geometry: SceneGeometry,
    pub views: ViewSlots,
}

impl Shared {
    /// What every technique shares, for drawing `scene`'s meshes into
    /// textures of `target_format` on a device that can do `caps`.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        caps: crate::capabilities::Capabilities,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        use crate::meshes::Winding;
        let layouts = Layouts::new(device);
        let frame_buffer =
            uniform_buffer(device, "frame", &crate::uniforms::FrameUniforms::default());
        let frame_only = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame only"),
            layout: &layouts.frame_only,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buffer.as_entire_binding(),
            }],
        });
        let depth_format = crate::targets::main_depth_format(&caps);
        let meshes =
            GeometryPass::new(device, queue, &layouts.globals, &layouts.frame_only, depth_format);
        let geometry = meshes.upload(device, queue, scene)?;
        let slot = |label, winding| meshes.view_slot(device, label, winding);
        let views = ViewSlots {
            main: slot("main view", Winding::Normal),
            reflection: slot("reflection view", Winding::Mirrored),
            refraction: slot("refraction view", Winding::Normal).seeing_below_water(),
            reflection_under: slot("reflection under view", Winding::Mirrored),
            refraction_over: slot("refraction over view", Winding::Normal),
            shadow: slot("shadow view", Winding::Normal),
            object_light: slot("object light view", Winding::Normal),
        };
        Ok(Shared {
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
            downsampler: Downsampler::new(device),
            meshes,
            geometry,
            views,
        })
    }
}

/// Bind groups over resources that different techniques write, rebuilt by
/// the renderer when one of them is replaced.
pub(crate) struct Bound {
    /// Group 0 of render passes: frame, sky (sky), shadow map (geometry),
    /// caustic layers (caustics), object caustic map (water objects).
    pub globals: wgpu::BindGroup,
    /// The surface's group (the simulations publish it).
    pub surface: wgpu::BindGroup,
    /// The shadow map's values (geometry), for the shadow debug view.
    pub shadow_values: wgpu::BindGroup,
}

/// Everything a technique sees while recording one frame.
pub(crate) struct FrameContext<'a> {
    pub plan: &'a FramePlan,
    pub scene: &'a Scene,
    pub shared: &'a Shared,
    pub bound: &'a Bound,
    /// What the simulations publish (the surface, foam, particles, bodies).
    pub published: &'a crate::simulation::published::Published,
    /// The screen targets (`None` when only simulating).
    pub targets: Option<&'a Targets>,
    /// The caller's target (`None` when only simulating).
    pub output: Option<&'a wgpu::TextureView>,
}

impl FrameContext<'_> {
    pub fn targets(&self) -> &Targets {
        self.targets.expect("a stage after Simulate runs with targets")
    }
}

/// What a dump reads besides its owner's state: the device, the scene as
/// drawn, the last frame's plan and the simulations' time.
pub(crate) struct DumpContext<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub scene: &'a Scene,
    pub plan: Option<&'a FramePlan>,
    pub time: f64,
}

/// One technique of the frame. Every method has a default that does
/// nothing, so a technique implements only the stages it takes part in.
pub(crate) trait Technique {
    /// Build it for `scene` (techniques are built in registry order, after
    /// `Shared`; links between them are made in `Techniques::connect`).
    fn create(shared: &Shared, scene: &Scene) -> Result<Self, RenderError>
    where
        Self: Sized;

    /// The scene was edited: rebuild what depends on what changed. Returns
    /// whether it replaced a resource that `Bound`'s groups hold. The
    /// scene's meshes (`Shared::geometry`) are already the new ones.
    fn set_scene(
        &mut self,
        _shared: &Shared,
        _old: &Scene,
        _new: &Scene,
    ) -> Result<bool, RenderError> {
        Ok(false)
    }

    /// Write this frame's uniforms (the plan decided them).
    fn prepare(&mut self, _queue: &wgpu::Queue, _frame: &FrameContext) {}

    /// The screen-size targets were made anew (the output's size or a
    /// setting that sizes them changed): build what the technique keeps at
    /// that size (its own targets, the bind groups over the shared ones).
    /// A technique that remakes itself on a scene edit keeps these.
    fn resize(&mut self, _shared: &Shared, _targets: &Targets) {}

    /// Record this technique's own passes for `stage`.
    fn record(
        &mut self,
        _stage: Stage,
        _encoder: &mut wgpu::CommandEncoder,
        _frame: &FrameContext,
        _timer: Option<&mut GpuTimer>,
    ) {
    }

    /// Draw into the main view's shared render pass of `stage`
    /// ([`Stage::Medium`] or [`Stage::Main`]).
    fn draw(&self, _stage: Stage, _pass: &mut wgpu::RenderPass<'_>, _frame: &FrameContext) {}

    /// Read back dump `name` if it is one of those its `INFO` declares.
    fn dump(&self, _name: &str, _ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        None
    }
}
