//! Output: filmic tone map of the pre-exposed HDR image into the caller's
//! target, or a debug view of an intermediate texture (`tonemap.wgsl`; CPU
//! twin `hydrolux_core::tonemap`).

use crate::gpu_util::*;
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;

pub fn source(srgb_target: bool) -> String {
    let c = format!("const OUTPUT_SRGB_CURVE: bool = {};\n", !srgb_target);
    shaders::compose(&c, include_str!("tonemap.wgsl"))
}

pub struct TonemapPass {
    pub layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    /// Its inputs at the current screen size: the HDR image and what the
    /// debug views show (`Technique::resize`).
    input: Option<wgpu::BindGroup>,
}

impl TonemapPass {
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        shadow_values: &wgpu::BindGroupLayout,
        target_format: wgpu::TextureFormat,
    ) -> Self {
        let fs = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tonemap input"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, false),
                texture_entry(2, fs, wgpu::TextureViewDimension::D2, false),
                texture_entry(3, fs, wgpu::TextureViewDimension::D2, false),
                uint_texture_entry(4, fs),
                sampler_entry(5, fs),
            ],
        });
        // Filters the frame up to the output when it is drawn smaller.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("tonemap upscale"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let module = shader(device, "tonemap", &source(target_format.is_srgb()));
        let pipeline = fullscreen_pipeline(
            device,
            "tonemap",
            &module,
            &[globals, &layout, shadow_values],
            target_format,
        );
        TonemapPass { layout, pipeline, sampler, input: None }
    }

    /// The HDR image and the screen-size textures the debug views show, in
    /// binding order: hdr, reflection, refraction, depth, medium (stencil).
    /// The shadow map's view reads it from the frame globals, so a new
    /// shadow resolution does not touch the screen targets.
    pub fn input_group(
        &self,
        device: &wgpu::Device,
        views: [&wgpu::TextureView; 5],
    ) -> wgpu::BindGroup {
        let mut entries: Vec<wgpu::BindGroupEntry> = views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: wgpu::BindingResource::TextureView(v),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 5,
            resource: wgpu::BindingResource::Sampler(&self.sampler),
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tonemap input"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        groups: [&wgpu::BindGroup; 3],
        timer: Option<&mut GpuTimer>,
    ) {
        let writes = timer.and_then(|t| t.render_writes("tonemap"));
        draw_fullscreen(encoder, "tonemap", target, &self.pipeline, &groups, writes);
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "tonemap",
    dumps: &[],
    shaders: || {
        vec![
            ("tonemap/srgb-target".to_string(), source(true)),
            ("tonemap/unorm-target".to_string(), source(false)),
        ]
    },
    uniforms: Vec::new,
};

impl Technique for TonemapPass {
    fn create(
        shared: &crate::technique::Shared,
        _scene: &hydrolux_core::scene::Scene,
    ) -> Result<Self, crate::error::RenderError> {
        let l = &shared.layouts;
        Ok(TonemapPass::new(&shared.device, &l.globals, &l.shadow_values, shared.target_format))
    }

    fn resize(&mut self, shared: &crate::technique::Shared, t: &crate::targets::Targets) {
        let views =
            [&t.hdr_view, &t.reflection.color_view, &t.refraction.color_view, &t.depth_view];
        let [hdr, reflection, refraction, depth] = views;
        let medium = t.medium_view();
        self.input =
            Some(self.input_group(&shared.device, [hdr, reflection, refraction, depth, medium]));
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if let (Stage::Output, Some(output)) = (stage, frame.output) {
            let Some(input) = &self.input else { return };
            let groups = [&frame.bound.globals, input, &frame.bound.shadow_values];
            TonemapPass::record(self, encoder, output, groups, timer);
        }
    }
}
