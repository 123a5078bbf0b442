//! The error view, `render.view = "error"` (issue #16's truth mode, in the
//! viewer and anywhere a renderer draws), a frame mode: the renderer draws
//! the frame twice from the same published state — as the scene is drawn
//! ([`projective`]: `water.method` set to `projective`) and as [`traced`]
//! (the water technique keeps a twin built for `raytrace` and draws it when
//! the frame's scene asks; for a liquid without surface water, issue #30,
//! the liquid meshed by marching cubes on its finest grid, which the liquid
//! keeps while the view is on) — each tone mapped into an image of the target's
//! format ([`ErrorView::images`]), and `error.wgsl` writes their per-pixel
//! ΔE*ab as heat into the caller's target. The simulation advances once:
//! the second drawing is at the same time, so it takes no steps. CPU twin:
//! hydrolux-core `compare` (what `hydrolux compare` computes on read-back
//! images).

use crate::gpu_util::*;
use crate::shaders;
use crate::technique::Shared;
use hydrolux_core::scene::{
    DebugView, FluidSurface, MAX_SURFACE_RESOLUTION, Scene, WaterMethod, WaterModel,
};

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

/// Whether the error view compares the liquid's surfaces (a scene with the
/// volumetric liquid and no surface water) rather than the water's methods.
pub fn compares_surfaces(scene: &Scene) -> bool {
    scene.water.model == WaterModel::None && scene.fluid.enabled()
}

/// The scene as the error view's second drawing takes it: traced water,
/// or (comparing surfaces) the liquid meshed by marching cubes on its
/// finest grid, `hydrolux compare --surfaces`' reference, which the liquid
/// keeps while the view is on. (Its own keys stay: the two drawings share
/// the frame's light view, fitted to them.)
pub fn traced(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    if compares_surfaces(scene) {
        s.fluid.surface = FluidSurface::MarchingCubes;
        s.render.surface_reference = true;
    } else {
        s.water.method = WaterMethod::Raytrace;
    }
    s
}

/// Whether `scene` draws the liquid as the surfaces' reference: the error
/// view's second drawing.
pub fn is_surface_reference(scene: &Scene) -> bool {
    scene.render.surface_reference && compares_surfaces(scene)
}

/// Whether the liquid's own surface is already the reference: marching
/// cubes on the finest grid.
pub fn is_finest_mesh(scene: &Scene) -> bool {
    scene.fluid.surface == FluidSurface::MarchingCubes
        && scene.fluid.surface_resolution == MAX_SURFACE_RESOLUTION
}

/// The two drawings' images, for one output size.
struct Images {
    size: (u32, u32),
    views: [wgpu::TextureView; 2],
    group: wgpu::BindGroup,
}

pub(crate) struct ErrorView {
    format: wgpu::TextureFormat,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    images: Option<Images>,
}

impl ErrorView {
    /// The difference's pipeline, for the caller's target format.
    pub fn new(shared: &Shared) -> Self {
        let device = &shared.device;
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
        ErrorView { format, layout, pipeline, images: None }
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
    dumps: &[],
    shaders: || {
        vec![
            ("truth/error".to_string(), source(true)),
            ("truth/error linear".into(), source(false)),
        ]
    },
    uniforms: Vec::new,
};
