//! The error view, `render.view = "error"` (issue #16's truth mode, in the
//! viewer and anywhere a renderer draws): the frame is drawn twice from the
//! same state — with the projective approximations (the renderer's own
//! water technique, the scene's `water.method` set to `projective`) and ray
//! traced (a second water technique built for `raytrace`, swapped in) —
//! each tone mapped into an image of the target's format, and `error.wgsl`
//! writes their per-pixel ΔE*ab as heat into the caller's target. The
//! simulation advances once: the second drawing is at the same time, so it
//! takes no steps. CPU twin: hydrolux-core `compare` (what `hydrolux
//! compare` computes on read-back images).

use crate::gpu_util::*;
use crate::passes::water::WaterPass;
use crate::shaders;
use crate::technique::{Shared, Technique};
use hydrolux_core::scene::{DebugView, Scene, WaterMethod};

pub fn source(srgb_target: bool) -> String {
    let c = format!("const SRGB_TARGET: bool = {srgb_target};\n");
    shaders::compose(&c, include_str!("error.wgsl"))
}

/// The scene as the error view's first drawing takes it: projective water.
pub fn projective(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    if s.render.view == DebugView::Error {
        s.water.method = WaterMethod::Projective;
    }
    s
}

fn traced(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.water.method = WaterMethod::Raytrace;
    s
}

/// The two drawings' images, for one output size.
struct Images {
    size: (u32, u32),
    views: [wgpu::TextureView; 2],
    group: wgpu::BindGroup,
}

pub(crate) struct TruthView {
    /// The traced water technique (swapped with the renderer's for the
    /// second drawing).
    pub water: WaterPass,
    format: wgpu::TextureFormat,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    images: Option<Images>,
}

impl TruthView {
    /// For `scene` (as drawn: quality applied, water projective) beside the
    /// renderer's `water`.
    pub fn new(
        shared: &Shared,
        scene: &Scene,
        water: &WaterPass,
    ) -> Result<Self, crate::error::RenderError> {
        let device = &shared.device;
        let traced_water = WaterPass::for_scene(
            shared,
            &traced(scene),
            water.inputs_layout.clone(),
            water.traced_layout.clone(),
        )?;
        let fs = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("error view"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, false),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, false),
            ],
        });
        let format = shared.target_format;
        let module = shader(device, "error view", &source(format.is_srgb()));
        let pipeline = fullscreen_pipeline(device, "error view", &module, &[&layout], format);
        Ok(TruthView { water: traced_water, format, layout, pipeline, images: None })
    }

    /// The traced water follows a scene edit (`old`, `new` as drawn).
    pub fn set_scene(
        &mut self,
        shared: &Shared,
        old: &Scene,
        new: &Scene,
    ) -> Result<(), crate::error::RenderError> {
        self.water.set_scene(shared, &traced(old), &traced(new))?;
        Ok(())
    }

    /// The two images' views (projective, traced) at `size`.
    pub fn images(&mut self, device: &wgpu::Device, size: (u32, u32)) -> [wgpu::TextureView; 2] {
        if self.images.as_ref().map(|i| i.size) != Some(size) {
            let usage =
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
            let image = |label| {
                texture_2d(device, label, size, self.format, usage).create_view(&Default::default())
            };
            let views = [image("error view: projective"), image("error view: traced")];
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("error view"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&views[0]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&views[1]),
                    },
                ],
            });
            self.images = Some(Images { size, views, group });
        }
        self.images.as_ref().expect("just made").views.clone()
    }

    /// The heat of the two images' difference into `target`.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        let Some(images) = &self.images else {
            return;
        };
        draw_fullscreen(encoder, "error view", target, &self.pipeline, &[&images.group], None);
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "truth",
    shaders: || {
        vec![
            ("truth/error".to_string(), source(true)),
            ("truth/error linear".into(), source(false)),
        ]
    },
    uniforms: Vec::new,
};
