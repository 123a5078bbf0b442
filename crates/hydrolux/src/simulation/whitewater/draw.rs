//! The `particles` technique: the white water's published bubbles and
//! spray drawn over the lit scene (`particles.wgsl`): one indirect draw of
//! six vertices per alive particle, blended (premultiplied) into the HDR
//! image after the water. Its pipeline is built the first time a scene
//! has particles.

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::info::TechniqueInfo;
use crate::shaders;
use crate::simulation::published::ParticleState;
use crate::technique::{FrameContext, Shared, Stage, Technique};
use crate::uniforms::uniform;
use hydrolux_core::scene::Scene;

uniform! { DrawParams;
    /// WGSL `DrawParams` (simulation/whitewater/particles.wgsl).
    pub(crate) struct DrawUniforms {
        pub capacity: u32,
        pub list: u32,
        pub spray_cover: f32,
        pub spray_drops: f32,
        pub spray_size: f32,
        pub bubble_size: f32,
        pub shutter: f32,
        pub vertical_reach: f32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("particles.wgsl"))
}

/// A 60 Hz camera's shutter (s): how long a streak is.
const SHUTTER_S: f32 = 1.0 / 60.0;

/// The technique: its pipeline once a scene has particles.
#[derive(Default)]
pub(crate) struct Particles {
    draw: Option<ParticleDraw>,
}

struct ParticleDraw {
    params: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    /// Bound to the particle buffers it was last given.
    group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    depth_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ParticleDraw {
    fn new(shared: &crate::technique::Shared) -> Self {
        let device = &shared.device;
        let (vs, fs) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("particles"),
            entries: &[
                uniform_entry(0, vs | fs),
                storage_entry(1, vs, true),
                storage_entry(2, vs, true),
            ],
        });
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("particles depth"),
            entries: &[texture_entry(0, fs, wgpu::TextureViewDimension::D2, false)],
        });
        let params = uniform_buffer(device, "particles draw", &DrawUniforms::default());
        let module = shader(device, "particles", &source());
        let pipeline = pulled_pipeline(
            device,
            "particles",
            &module,
            &[&shared.layouts.globals, &layout, &depth_layout],
            over_hdr(),
        );
        ParticleDraw { params, layout, group: None, depth_layout, pipeline }
    }

    /// The group over `particles`' buffers (made again when they change).
    fn bind(&mut self, device: &wgpu::Device, particles: &ParticleState) {
        if self.group.as_ref().is_some_and(|(b, _)| *b == particles.particles) {
            return;
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particles"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: particles.particles.as_entire_binding(),
                },
                wgpu::BindGroupEntry { binding: 2, resource: particles.slots.as_entire_binding() },
            ],
        });
        self.group = Some((particles.particles.clone(), group));
    }

    /// Draw the particles of alive `list` into the frame's HDR image.
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        particles: &ParticleState,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        let shared = frame.shared;
        let targets = frame.targets();
        let Some((_, group)) = &self.group else { return };
        let w = &frame.scene.whitewater;
        let u = DrawUniforms {
            capacity: particles.capacity,
            list: particles.list,
            spray_cover: hydrolux_core::whitewater::spray_look::parcel_cover(
                w.spray_size,
                w.spray_water,
            ),
            spray_drops: hydrolux_core::whitewater::spray_look::parcel_drops(
                w.spray_size,
                w.spray_water,
            ),
            spray_size: w.spray_size,
            bubble_size: w.bubble_size,
            shutter: SHUTTER_S,
            vertical_reach: frame.published.surface().vertical_reach,
        };
        shared.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&u));
        let depth = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particles depth"),
            layout: &self.depth_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&targets.depth_view),
            }],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("whitewater particles"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.and_then(|t| t.render_writes("whitewater particles")),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &frame.bound.globals, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.set_bind_group(2, &depth, &[]);
        pass.draw_indirect(&particles.args, 16);
    }
}

impl Technique for Particles {
    fn create(_shared: &Shared, _scene: &Scene) -> Result<Self, RenderError> {
        Ok(Particles::default())
    }

    fn prepare(&mut self, _queue: &wgpu::Queue, frame: &FrameContext) {
        let Some(particles) = &frame.published.particles else { return };
        let draw = self.draw.get_or_insert_with(|| ParticleDraw::new(frame.shared));
        draw.bind(&frame.shared.device, particles);
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        if stage == Stage::Volume
            && let (Some(particles), Some(draw)) = (&frame.published.particles, &self.draw)
        {
            draw.record(encoder, frame, particles, timer);
        }
    }
}

/// The particles' draw, validated offline.
pub(crate) const INFO: TechniqueInfo = TechniqueInfo {
    name: "particles",
    dumps: &[],
    shaders: || vec![("particles".into(), source())],
    uniforms: || vec![crate::uniforms::Layout::of::<DrawUniforms>(source())],
};
