//! The sky: the Preetham model baked into a mipmapped environment cube map
//! when the sun or turbidity changes (seed 000 §3.1.2; reflections look it
//! up), and drawn per pixel behind the scene with the sun's disk.
//! CPU twin: `hydrolux_core::sky`.

use crate::gpu_util::*;
use crate::mips::{Downsampler, FORMAT, MipChain};
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;
use hydrolux_core::sky::SkyParams;

/// Edge length of the environment cube map's faces.
pub const CUBE_SIZE: u32 = 128;

pub fn bake_source() -> String {
    shaders::compose("", include_str!("bake.wgsl"))
}

pub fn background_source() -> String {
    shaders::compose("", include_str!("background.wgsl"))
}

pub struct SkyPass {
    pub params: wgpu::Buffer,
    /// Kept with its views (the cube map the sky bakes into).
    _cube: wgpu::Texture,
    pub cube_view: wgpu::TextureView,
    bake: wgpu::ComputePipeline,
    bake_group: wgpu::BindGroup,
    mips: MipChain,
    background: wgpu::RenderPipeline,
    deep_water: wgpu::RenderPipeline,
    current: Option<SkyParams>,
    dirty: bool,
    /// The sky's irradiance on a horizontal plane (kcd/m² · sr), for the
    /// frame plan.
    pub irradiance: glam::Vec3,
    /// The sky's and the grey world's light on every normal
    /// (`hydrolux_core::irradiance`), for the frame plan.
    pub light: hydrolux_core::irradiance::IrradianceSh,
}

impl SkyPass {
    pub fn new(
        device: &wgpu::Device,
        downsampler: &Downsampler,
        globals: &wgpu::BindGroupLayout,
        main_depth_format: wgpu::TextureFormat,
    ) -> Self {
        let params = uniform_buffer(device, "sky params", &SkyParams::default());
        let cube = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sky cube"),
            size: wgpu::Extent3d { width: CUBE_SIZE, height: CUBE_SIZE, depth_or_array_layers: 6 },
            mip_level_count: CUBE_SIZE.ilog2() + 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let cube_view = cube.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sky bake"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::COMPUTE),
                storage_texture_entry(1, FORMAT, wgpu::TextureViewDimension::D2Array),
            ],
        });
        let level0 = cube.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            base_mip_level: 0,
            mip_level_count: Some(1),
            ..Default::default()
        });
        let bake_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sky bake"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&level0),
                },
            ],
        });
        let module = shader(device, "sky bake", &bake_source());
        let bake = compute_pipeline(device, "sky bake", &module, "bake", &[&layout]);
        let mips = downsampler.chain(device, &cube);
        let module = shader(device, "sky background", &background_source());
        let layout = pipeline_layout(device, "sky background", &[globals]);
        let pipeline = |fs: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(fs),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(crate::targets::main_depth_state(
                    main_depth_format,
                    false,
                    wgpu::CompareFunction::Always,
                )),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(crate::targets::HDR_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let (background, deep_water) = (pipeline("fs_main"), pipeline("fs_deep"));
        SkyPass {
            params,
            _cube: cube,
            cube_view,
            bake,
            bake_group,
            mips,
            background,
            deep_water,
            current: None,
            irradiance: glam::Vec3::ZERO,
            light: Default::default(),
            dirty: true,
        }
    }

    /// Per-frame input: the sky for this sun. Re-bakes only when it changed.
    pub fn prepare(&mut self, queue: &wgpu::Queue, params: SkyParams) {
        if self.current != Some(params) {
            queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
            self.current = Some(params);
            self.dirty = true;
        }
    }

    pub fn record_bake(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        downsampler: &Downsampler,
        timer: Option<&mut GpuTimer>,
    ) {
        if !self.dirty {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sky bake"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("sky bake")),
        });
        pass.set_pipeline(&self.bake);
        pass.set_bind_group(0, &self.bake_group, &[]);
        pass.dispatch_workgroups(CUBE_SIZE / 8, CUBE_SIZE / 8, 6);
        downsampler.record(&mut pass, &self.mips);
        self.dirty = false;
    }

    /// The background of the main view: the sky where the pixel's medium is
    /// air, endless water where it is water (stencil reference).
    pub fn record_background(&self, pass: &mut wgpu::RenderPass<'_>, globals: &wgpu::BindGroup) {
        pass.set_bind_group(0, globals, &[]);
        for (pipeline, medium) in [
            (&self.background, crate::targets::STENCIL_AIR),
            (&self.deep_water, crate::targets::STENCIL_WATER),
        ] {
            pass.set_pipeline(pipeline);
            pass.set_stencil_reference(medium);
            pass.draw(0..3, 0..1);
        }
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "sky",
    dumps: &[],
    shaders: || {
        vec![
            ("sky/bake".to_string(), bake_source()),
            ("sky/background".to_string(), background_source()),
        ]
    },
    uniforms: || vec![crate::uniforms::Layout::of::<hydrolux_core::sky::SkyParams>(bake_source())],
};

impl Technique for SkyPass {
    fn create(
        shared: &crate::technique::Shared,
        _scene: &hydrolux_core::scene::Scene,
    ) -> Result<Self, crate::error::RenderError> {
        let l = &shared.layouts;
        Ok(SkyPass::new(&shared.device, &shared.downsampler, &l.globals, shared.depth_format))
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if stage == Stage::Simulate {
            self.record_bake(encoder, &frame.shared.downsampler, timer);
        }
    }

    fn draw(&self, stage: Stage, pass: &mut wgpu::RenderPass<'_>, frame: &FrameContext) {
        // The normals view shows only what has a normal.
        let normals = frame.scene.render.view == hydrolux_core::scene::DebugView::Normals;
        if stage == Stage::Main && !normals {
            self.record_background(pass, &frame.bound.globals);
        }
    }
}
