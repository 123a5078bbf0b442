//! Opaque scene geometry as a technique: the sun's shadow map, the
//! offscreen reflection and refraction views (seed 000 §3.1.3, §4.4) and the
//! scene in the main view. The meshes and their pipelines are shared
//! vocabulary (`crate::meshes`).

use crate::gpu_util::*;
use crate::meshes::{Objects, SHADOW_FORMAT, ViewSlot, shadow_source, source};
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;
use hydrolux_core::scene::Scene;

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "geometry",
    dumps: &[],
    shaders: || {
        vec![("geometry".to_string(), source()), ("geometry/shadow".to_string(), shadow_source())]
    },
    uniforms: || {
        use crate::uniforms::{Layout, ObjectUniforms, ViewUniforms};
        vec![Layout::of::<ViewUniforms>(source()), Layout::of::<ObjectUniforms>(source())]
    },
};

/// The sun's shadow map (written here, read through the frame globals).
pub(crate) struct ShadowMap {
    pub resolution: u32,
    pub view: wgpu::TextureView,
}

impl ShadowMap {
    pub fn new(device: &wgpu::Device, resolution: u32) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let texture =
            texture_2d(device, "shadow map", (resolution, resolution), SHADOW_FORMAT, usage);
        ShadowMap { resolution, view: texture.create_view(&Default::default()) }
    }
}

/// The scene's opaque geometry as a technique: the shadow map from the sun,
/// the offscreen reflection and refraction views (seed 000 §3.1.3, §4.4),
/// and the main view. The meshes and their pipelines are shared
/// (`Shared::meshes`, `Shared::geometry`): refractive objects draw them too.
pub(crate) struct Geometry {
    pub shadow: ShadowMap,
}

impl Geometry {
    fn record_shadow_map(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow map"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.shadow.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.and_then(|t| t.render_writes("shadow")),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let shared = frame.shared;
        if frame.plan.matrices.shadow.is_some() {
            shared.meshes.record_shadow(
                &mut pass,
                &shared.frame_only,
                &shared.views.shadow,
                &shared.geometry,
                Objects::All,
            );
        }
    }

    /// Reflection and refraction textures: cleared to "nothing here" (alpha
    /// 0, depth at infinity) so the water falls back to the sky or to
    /// endless water where no geometry was drawn.
    fn record_offscreen(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let (shared, targets, views) = (frame.shared, frame.targets(), &frame.shared.views);
        let mut offscreen: Vec<(&'static str, &crate::targets::ColorDepth, &ViewSlot, bool)> =
            Vec::new();
        if frame.plan.offscreen.air {
            offscreen.push(("reflection", &targets.reflection, &views.reflection, true));
            offscreen.push(("refraction", &targets.refraction, &views.refraction, false));
        }
        if frame.plan.offscreen.water {
            let under = &targets.reflection_under;
            offscreen.push(("reflection under", under, &views.reflection_under, true));
            let over = &targets.refraction_over;
            offscreen.push(("refraction over", over, &views.refraction_over, false));
        }
        for (name, target, slot, mipmapped) in offscreen {
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(name),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &target.color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &target.depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(0.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timer.as_deref_mut().and_then(|t| t.render_writes(name)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                shared.meshes.record(&mut pass, &frame.bound.globals, slot, &shared.geometry);
            }
            if let (true, Some(chain)) = (mipmapped, &target.mips) {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("reflection mips"),
                    timestamp_writes: None,
                });
                shared.downsampler.record(&mut pass, chain);
            }
        }
    }
}

impl Technique for Geometry {
    fn create(
        shared: &crate::technique::Shared,
        scene: &Scene,
    ) -> Result<Self, crate::error::RenderError> {
        Ok(Geometry { shadow: ShadowMap::new(&shared.device, scene.render.shadow_resolution) })
    }

    fn set_scene(
        &mut self,
        shared: &crate::technique::Shared,
        _old: &Scene,
        new: &Scene,
    ) -> Result<bool, crate::error::RenderError> {
        let resolution = new.render.shadow_resolution;
        let changed = resolution != self.shadow.resolution;
        if changed {
            self.shadow = ShadowMap::new(&shared.device, resolution);
        }
        Ok(changed)
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        match stage {
            Stage::Light => self.record_shadow_map(encoder, frame, timer),
            Stage::Offscreen => self.record_offscreen(encoder, frame, timer),
            _ => {}
        }
    }

    fn draw(&self, stage: Stage, pass: &mut wgpu::RenderPass<'_>, frame: &FrameContext) {
        if stage == Stage::Main {
            let shared = frame.shared;
            let main = &shared.views.main;
            shared.meshes.record_main(pass, &frame.bound.globals, main, &shared.geometry);
        }
    }
}
