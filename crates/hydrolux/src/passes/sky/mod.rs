//! The sky: a physically based atmosphere (Hillaire 2020; the default) or
//! the Preetham model, written into a sky-view table and baked into a
//! mipmapped environment cube map when the sun or the air changes (seed 000
//! §3.1.2; reflections look it up; its smaller levels are the sky filtered
//! for rough surfaces' GGX lobes, `prefilter` in bake.wgsl), and drawn per pixel behind the scene
//! from the sky-view table with the sun's disk. The atmosphere's
//! transmittance and multiple-scattering tables are built first, on the GPU.
//! CPU twins: `hydrolux_core::sky::Sky`, `hydrolux_core::atmosphere`.

use crate::gpu_util::*;
use crate::mips::FORMAT;
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;
use hydrolux_core::sky::SkyParams;

/// Edge length of the environment cube map's faces.
pub const CUBE_SIZE: u32 = 128;

/// vec4s of the split sum's table (two texels each; `EnvironmentBrdf`).
const ENVIRONMENT_BRDF_ENTRIES: usize =
    hydrolux_core::pbr::ENVIRONMENT_TABLE_SIZE * hydrolux_core::pbr::ENVIRONMENT_TABLE_SIZE / 2;

pub fn bake_source() -> String {
    use hydrolux_core::pbr::{PREFILTER_SAMPLES, SPECULAR_LEVELS};
    let prelude = format!(
        "const SKY_CUBE_SIZE: u32 = {CUBE_SIZE}u;\nconst SPECULAR_LEVELS: u32 = {SPECULAR_LEVELS}u;\n\
         const PREFILTER_SAMPLES: u32 = {PREFILTER_SAMPLES}u;\n"
    );
    shaders::compose(&prelude, include_str!("bake.wgsl"))
}

pub fn tables_source() -> String {
    shaders::compose("", include_str!("tables.wgsl"))
}

/// A table the atmosphere writes in one dispatch and later ones sample (and
/// `--dump` reads back).
fn table(
    device: &wgpu::Device,
    label: &str,
    (w, h): (usize, usize),
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}

fn not_physical(scene: &hydrolux_core::scene::Scene) -> Option<&'static str> {
    (scene.sky.model != hydrolux_core::scene::SkyModel::Physical).then_some(
        "the sky is Preetham's fit, which has no atmosphere tables (set sky.model to \"physical\")",
    )
}

/// `sky_view`: the sky-view table (kcd/m², azimuth from the sun across,
/// elevation on a square-root scale up; either model); `transmittance` and
/// `multiscattering`: the atmosphere's tables (hydrolux_core::atmosphere).
pub(crate) const DUMPS: &[crate::info::DumpKind] = &[
    crate::info::DumpKind {
        name: "sky_view",
        shape: crate::info::DumpShape::Grid,
        missing: |_| None,
    },
    crate::info::DumpKind {
        name: "transmittance",
        shape: crate::info::DumpShape::Grid,
        missing: not_physical,
    },
    crate::info::DumpKind {
        name: "multiscattering",
        shape: crate::info::DumpShape::Grid,
        missing: not_physical,
    },
];

/// The tables' pipelines and bind groups: the physical atmosphere's
/// transmittance and Ψ (each written by one dispatch and read by the next),
/// then the sky-view table by either model.
struct Tables {
    transmittance: (wgpu::ComputePipeline, wgpu::BindGroup),
    multiscattering: (wgpu::ComputePipeline, wgpu::BindGroup),
    sky_view_physical: wgpu::ComputePipeline,
    sky_view_preetham: wgpu::ComputePipeline,
    sky_view_group: wgpu::BindGroup,
    /// The sky-view table (kcd/m²) the cube map and the background read.
    sky_view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    /// The tables by their dump names.
    textures: [(&'static str, wgpu::Texture); 3],
}

impl Tables {
    fn new(device: &wgpu::Device, params: &wgpu::Buffer) -> Self {
        use hydrolux_core::atmosphere::{MULTISCATTERING_SIZE, SKY_VIEW_SIZE, TRANSMITTANCE_SIZE};
        let (transmittance_texture, transmittance) =
            table(device, "atmosphere transmittance", TRANSMITTANCE_SIZE);
        let (multiscattering_texture, multiscattering) =
            table(device, "atmosphere multiple scattering", MULTISCATTERING_SIZE);
        let (sky_view_texture, sky_view) = table(device, "sky view", SKY_VIEW_SIZE);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sky tables"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let d2 = wgpu::TextureViewDimension::D2;
        let uniform = || uniform_entry(0, compute);
        let written = |b| storage_texture_entry(b, FORMAT, d2);
        let read = |b| texture_entry(b, compute, d2, true);
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let l_transmittance = layout("atmosphere transmittance", &[uniform(), written(1)]);
        let l_multiscattering = layout(
            "atmosphere multiple scattering",
            &[uniform(), read(2), sampler_entry(3, compute), written(4)],
        );
        let l_view = layout(
            "sky view",
            &[uniform(), read(2), sampler_entry(3, compute), read(5), written(6)],
        );
        // The uniform, the sampler where the layout reads a table, the views.
        let group = |layout: &wgpu::BindGroupLayout, views: &[(u32, &wgpu::TextureView)]| {
            let reads = views.len() > 1;
            let mut entries =
                vec![wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() }];
            if reads {
                let resource = wgpu::BindingResource::Sampler(&sampler);
                entries.push(wgpu::BindGroupEntry { binding: 3, resource });
            }
            entries.extend(views.iter().map(|(b, v)| wgpu::BindGroupEntry {
                binding: *b,
                resource: wgpu::BindingResource::TextureView(v),
            }));
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sky tables"),
                layout,
                entries: &entries,
            })
        };
        let module = shader(device, "sky tables", &tables_source());
        let pipeline = |entry, layout| compute_pipeline(device, entry, &module, entry, &[layout]);
        Tables {
            transmittance: (
                pipeline("transmittance", &l_transmittance),
                group(&l_transmittance, &[(1, &transmittance)]),
            ),
            multiscattering: (
                pipeline("multiscattering", &l_multiscattering),
                group(&l_multiscattering, &[(2, &transmittance), (4, &multiscattering)]),
            ),
            sky_view_physical: pipeline("sky_view_physical", &l_view),
            sky_view_preetham: pipeline("sky_view_preetham", &l_view),
            sky_view_group: group(
                &l_view,
                &[(2, &transmittance), (5, &multiscattering), (6, &sky_view)],
            ),
            sky_view,
            sampler,
            textures: [
                ("sky_view", sky_view_texture),
                ("transmittance", transmittance_texture),
                ("multiscattering", multiscattering_texture),
            ],
        }
    }

    /// Fill the tables for `params`' model.
    fn record(&self, pass: &mut wgpu::ComputePass<'_>, params: &SkyParams) {
        use hydrolux_core::atmosphere::{MULTISCATTERING_SIZE, SKY_VIEW_SIZE, TRANSMITTANCE_SIZE};
        let groups = |(w, h): (usize, usize)| ((w as u32).div_ceil(8), (h as u32).div_ceil(8));
        let view = if params.is_physical() {
            for ((pipeline, group), size) in [
                (&self.transmittance, TRANSMITTANCE_SIZE),
                (&self.multiscattering, MULTISCATTERING_SIZE),
            ] {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                let (x, y) = groups(size);
                pass.dispatch_workgroups(x, y, 1);
            }
            &self.sky_view_physical
        } else {
            &self.sky_view_preetham
        };
        pass.set_pipeline(view);
        pass.set_bind_group(0, &self.sky_view_group, &[]);
        let (x, y) = groups(SKY_VIEW_SIZE);
        pass.dispatch_workgroups(x, y, 1);
    }
}

pub fn background_source() -> String {
    shaders::compose("", include_str!("background.wgsl"))
}

pub struct SkyPass {
    pub params: wgpu::Buffer,
    /// The split sum's table (`hydrolux_core::pbr`), a uniform of group 0
    /// (`EnvironmentBrdf` in shaders/pbr.wgsl): written once.
    pub environment_brdf: wgpu::Buffer,
    /// Kept with its views (the cube map the sky bakes into).
    _cube: wgpu::Texture,
    pub cube_view: wgpu::TextureView,
    tables: Tables,
    bake: wgpu::ComputePipeline,
    bake_group: wgpu::BindGroup,
    /// The smaller levels, filtered for rough surfaces' lobes: one group per level.
    prefilter: wgpu::ComputePipeline,
    prefilter_levels: Vec<(wgpu::BindGroup, u32)>,
    /// The background's view of the sky-view table (group 1).
    background_group: wgpu::BindGroup,
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
                texture_entry(2, wgpu::ShaderStages::COMPUTE, wgpu::TextureViewDimension::D2, true),
                sampler_entry(3, wgpu::ShaderStages::COMPUTE),
            ],
        });
        let tables = Tables::new(device, &params);
        // One level of the cube as a storage array, and the group that
        // writes it from the sky-view table (the bake's level 0, the
        // prefilter's others).
        let level_group = |level: u32, label: &str| {
            let view = cube.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            });
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&tables.sky_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::Sampler(&tables.sampler),
                    },
                ],
            })
        };
        let bake_group = level_group(0, "sky bake");
        let module = shader(device, "sky bake", &bake_source());
        let bake = compute_pipeline(device, "sky bake", &module, "bake", &[&layout]);
        let prefilter = compute_pipeline(device, "sky prefilter", &module, "prefilter", &[&layout]);
        let prefilter_levels = (1..cube.mip_level_count())
            .map(|level| {
                let group = level_group(level, "sky prefilter level");
                (group, (CUBE_SIZE >> level).max(1))
            })
            .collect();
        let module = shader(device, "sky background", &background_source());
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sky background view"),
            entries: &[
                texture_entry(0, fragment, wgpu::TextureViewDimension::D2, true),
                sampler_entry(1, fragment),
            ],
        });
        let background_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sky background view"),
            layout: &view_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&tables.sky_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&tables.sampler),
                },
            ],
        });
        let layout = pipeline_layout(device, "sky background", &[globals, &view_layout]);
        // The sky where the pixel's medium is anything but water: a count
        // the medium pass left at neither 0 nor 1 (a far wall of the water
        // volume edge-on at the horizon, rasterised with the wrong facing
        // under a 24-bit depth buffer) is air, not a hole in the frame.
        let pipeline = |fs: &str, stencil: wgpu::CompareFunction| {
            let mut depth_stencil = crate::targets::main_depth_state(
                main_depth_format,
                false,
                wgpu::CompareFunction::Always,
            );
            depth_stencil.stencil.front.compare = stencil;
            depth_stencil.stencil.back.compare = stencil;
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
                depth_stencil: Some(depth_stencil),
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
        let (background, deep_water) = (
            pipeline("fs_main", wgpu::CompareFunction::NotEqual),
            pipeline("fs_deep", wgpu::CompareFunction::Equal),
        );
        let mut table = [[0.0f32; 4]; ENVIRONMENT_BRDF_ENTRIES];
        table.copy_from_slice(&hydrolux_core::pbr::environment_table_packed());
        let environment_brdf = uniform_buffer(device, "environment brdf", &table);
        SkyPass {
            params,
            environment_brdf,
            _cube: cube,
            cube_view,
            tables,
            bake,
            bake_group,
            prefilter,
            prefilter_levels,
            background_group,
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
        timer: Option<&mut GpuTimer>,
    ) {
        if !self.dirty {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sky bake"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("sky bake")),
        });
        if let Some(params) = &self.current {
            self.tables.record(&mut pass, params);
        }
        pass.set_pipeline(&self.bake);
        pass.set_bind_group(0, &self.bake_group, &[]);
        pass.dispatch_workgroups(CUBE_SIZE / 8, CUBE_SIZE / 8, 6);
        pass.set_pipeline(&self.prefilter);
        for (group, size) in &self.prefilter_levels {
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(size.div_ceil(8), size.div_ceil(8), 6);
        }
        self.dirty = false;
    }

    /// The background of the main view: the sky where the pixel's medium is
    /// air, endless water where it is water (stencil reference).
    pub fn record_background(&self, pass: &mut wgpu::RenderPass<'_>, globals: &wgpu::BindGroup) {
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(1, &self.background_group, &[]);
        // Both against the water's value: the sky where it is not, the
        // endless water where it is.
        for pipeline in [&self.background, &self.deep_water] {
            let medium = crate::targets::STENCIL_WATER;
            pass.set_pipeline(pipeline);
            pass.set_stencil_reference(medium);
            pass.draw(0..3, 0..1);
        }
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "sky",
    dumps: DUMPS,
    shaders: || {
        vec![
            ("sky/tables".to_string(), tables_source()),
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
        Ok(SkyPass::new(&shared.device, &l.globals, shared.depth_format))
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        _frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if stage == Stage::Simulate {
            self.record_bake(encoder, timer);
        }
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        let (_, texture) = self.tables.textures.iter().find(|(n, _)| *n == name)?;
        let px = crate::gpu_util::read_rgba16f(ctx.device, ctx.queue, texture);
        Some(Ok(crate::info::DumpData::Floats {
            columns: texture.width() as usize,
            rows: texture.height() as usize,
            channels: 3,
            data: px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect(),
            note: None,
        }))
    }

    fn draw(&self, stage: Stage, pass: &mut wgpu::RenderPass<'_>, frame: &FrameContext) {
        // The normals view shows only what has a normal.
        let normals = frame.scene.render.view == hydrolux_core::scene::DebugView::Normals;
        if stage == Stage::Main && !normals {
            self.record_background(pass, &frame.bound.globals);
        }
    }
}
