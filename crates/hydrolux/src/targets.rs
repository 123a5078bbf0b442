//! Size-dependent render targets, rebuilt in one place when the output size
//! (or a setting that sizes them) changes: the HDR image and its depth, the
//! reflection and refraction textures with their depths, and the bind
//! groups that read them.

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Depth of the offscreen views (reflection, refraction).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Depth + stencil of the main view: the stencil holds each pixel's medium
/// (0 air, 1 water). Float depth where the device has it (reversed-Z keeps
/// its precision to the horizon), 24-bit otherwise.
pub fn main_depth_format(caps: &crate::capabilities::Capabilities) -> wgpu::TextureFormat {
    if caps.depth32_stencil8 {
        wgpu::TextureFormat::Depth32FloatStencil8
    } else {
        wgpu::TextureFormat::Depth24PlusStencil8
    }
}

/// Stencil values of the two media.
pub const STENCIL_AIR: u32 = 0;
pub const STENCIL_WATER: u32 = 1;

/// A depth-stencil state for the main view whose stencil only tests
/// (`stencil_reference` picks the medium drawn).
pub fn main_depth_state(
    format: wgpu::TextureFormat,
    write: bool,
    compare: wgpu::CompareFunction,
) -> wgpu::DepthStencilState {
    let face =
        wgpu::StencilFaceState { compare: wgpu::CompareFunction::Equal, ..Default::default() };
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: wgpu::StencilState { front: face, back: face, read_mask: 0xff, write_mask: 0 },
        bias: Default::default(),
    }
}

/// Field-of-view widening of the refraction texture: refracted rays bend
/// towards the vertical, so they stray off screen much less than reflected ones.
pub const REFRACTION_MARGIN: f32 = 0.1;

/// What sizes the targets besides the output size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetSettings {
    /// Reflection texel density relative to the output.
    pub reflection_resolution: f32,
    /// Reflection field-of-view widening (0.5 = 50%).
    pub reflection_margin: f32,
    /// God-ray buffer size relative to the output.
    pub godray_resolution: f32,
    /// The scene has refractive objects (they need camera-size targets).
    pub refractive_objects: bool,
}

pub struct ColorDepth {
    pub size: (u32, u32),
    _color: wgpu::Texture,
    /// Level 0: the attachment (and what debug views show).
    pub color_view: wgpu::TextureView,
    /// Every level, for sampling.
    pub sampled_view: wgpu::TextureView,
    pub depth_view: wgpu::TextureView,
    /// The mip chain's downsampling (when the texture has mips).
    pub mips: Option<crate::passes::mips::MipChain>,
}

pub struct Targets {
    pub size: (u32, u32),
    pub settings: TargetSettings,
    pub hdr: wgpu::Texture,
    pub hdr_view: wgpu::TextureView,
    /// The main view's depth + stencil (the pixel's medium).
    pub depth_stencil: wgpu::Texture,
    pub depth_stencil_view: wgpu::TextureView,
    /// The main view's depth alone, for sampling (the particles' test).
    pub depth_view: wgpu::TextureView,
    /// For viewers in air: the scene above the water mirrored, and below it.
    pub reflection: ColorDepth,
    pub refraction: ColorDepth,
    /// For viewers in the water: the scene below mirrored, and above it.
    pub reflection_under: ColorDepth,
    pub refraction_over: ColorDepth,
    /// The water pass's inputs (reflection, refraction colour and depth).
    pub water_inputs: wgpu::BindGroup,
    /// The tone map's inputs (HDR image and the debug views' textures).
    pub tonemap_input: wgpu::BindGroup,
    /// The god-ray buffer and its depth.
    pub godrays: crate::passes::godrays::GodRayTargets,
    /// Refractive objects' back faces and the image behind them.
    pub water_object: Option<crate::passes::water_object::ObjectTargets>,
    /// The stencil's colour copy, where depth and stencil cannot be read
    /// in one draw (`Capabilities::depth_and_stencil_reads`).
    pub medium_copy: Option<MediumCopy>,
}

/// Copies the main view's stencil (each pixel's medium) into an R8Uint
/// texture after the main pass, on backends where shaders cannot read it
/// reliably: wgpu's GL sets one depth-or-stencil mode per texture object
/// (a draw reading both gets one wrong) and leaves a combined depth-stencil
/// texture's filter linear (stencil reads are then incomplete, all zeros).
/// The copy uses the stencil *test* instead: cleared to air, a fullscreen
/// triangle writes water where the stencil equals STENCIL_WATER. The
/// stencil holds only those two values (the volume count of a closed
/// surface). Readers bind the copy instead of the stencil view; their
/// shaders are the same.
pub struct MediumCopyPass {
    pipeline: wgpu::RenderPipeline,
}

pub struct MediumCopy {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

pub const MEDIUM_COPY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;

pub(crate) fn medium_copy_source() -> String {
    crate::shaders::compose("", "#import medium_copy")
}

pub(crate) const MEDIUM_COPY_INFO: crate::technique::TechniqueInfo =
    crate::technique::TechniqueInfo {
        name: "medium copy",
        shaders: || vec![("medium copy".to_string(), medium_copy_source())],
        uniforms: Vec::new,
    };

impl MediumCopyPass {
    pub fn new(device: &wgpu::Device, depth_format: wgpu::TextureFormat) -> Self {
        let module = crate::gpu_util::shader(device, "medium copy", &medium_copy_source());
        let equal_water =
            wgpu::StencilFaceState { compare: wgpu::CompareFunction::Equal, ..Default::default() };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("medium copy"),
            layout: Some(&crate::gpu_util::pipeline_layout(device, "medium copy", &[])),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth_format,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: wgpu::StencilState {
                    front: equal_water,
                    back: equal_water,
                    read_mask: 0xff,
                    write_mask: 0,
                },
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(MEDIUM_COPY_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        MediumCopyPass { pipeline }
    }

    fn targets(&self, device: &wgpu::Device, size: (u32, u32)) -> MediumCopy {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture = texture(device, "medium copy", size, MEDIUM_COPY_FORMAT, usage);
        let view = texture.create_view(&Default::default());
        MediumCopy { texture, view }
    }

    /// After the main pass (the stencil is final), before any reader.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        copy: &MediumCopy,
        depth_stencil: &wgpu::TextureView,
    ) {
        let keep = wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("medium copy"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &copy.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: f64::from(STENCIL_AIR),
                        ..wgpu::Color::BLACK
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth_stencil,
                depth_ops: Some(keep),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_stencil_reference(STENCIL_WATER);
        pass.draw(0..3, 0..1);
    }
}

use crate::gpu_util::texture_2d as texture;

impl ColorDepth {
    /// With `downsampler`, the colour gets a mip chain (box-filtered after
    /// each frame's render) so rough water can read it blurred.
    fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        downsampler: Option<&crate::passes::mips::Downsampler>,
    ) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let levels = if downsampler.is_some() { size.0.max(size.1).max(1).ilog2() + 1 } else { 1 };
        let color = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HDR_FORMAT,
            usage: if levels > 1 { usage | wgpu::TextureUsages::STORAGE_BINDING } else { usage },
            view_formats: &[],
        });
        let depth = texture(device, label, size, DEPTH_FORMAT, usage);
        let level0 = wgpu::TextureViewDescriptor { mip_level_count: Some(1), ..Default::default() };
        ColorDepth {
            size,
            color_view: color.create_view(&level0),
            sampled_view: color.create_view(&Default::default()),
            mips: downsampler.filter(|_| levels > 1).map(|d| d.chain(device, &color)),
            _color: color,
            depth_view: depth.create_view(&Default::default()),
        }
    }
}

fn scaled(size: (u32, u32), s: f32) -> (u32, u32) {
    (((size.0 as f32 * s).round() as u32).max(1), ((size.1 as f32 * s).round() as u32).max(1))
}

impl Targets {
    pub fn new(
        shared: &crate::technique::Shared,
        techniques: &crate::registry::Techniques,
        size: (u32, u32),
        settings: TargetSettings,
    ) -> Self {
        let device = &shared.device;
        let downsampler = &shared.downsampler;
        let tonemap = &techniques.tonemap;
        let water_inputs_layout = &techniques.water.inputs_layout;
        let godrays = &techniques.godrays.pass;
        let water_object = &techniques.water_objects.pass;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let hdr = texture(device, "hdr", size, HDR_FORMAT, usage);
        let depth_stencil = texture(device, "depth stencil", size, shared.depth_format, usage);
        let hdr_view = hdr.create_view(&Default::default());
        let depth_stencil_view = depth_stencil.create_view(&Default::default());
        let aspect = |aspect| {
            depth_stencil.create_view(&wgpu::TextureViewDescriptor { aspect, ..Default::default() })
        };
        let (depth_view, stencil_view) =
            (aspect(wgpu::TextureAspect::DepthOnly), aspect(wgpu::TextureAspect::StencilOnly));
        let medium_copy = shared.medium_copy.as_ref().map(|pass| pass.targets(device, size));
        // What readers of the medium bind: the stencil, or its copy.
        let medium_view = medium_copy.as_ref().map_or(&stencil_view, |c| &c.view);
        let reflection = ColorDepth::new(
            device,
            "reflection",
            scaled(size, settings.reflection_resolution * (1.0 + settings.reflection_margin)),
            Some(downsampler),
        );
        let refraction =
            ColorDepth::new(device, "refraction", scaled(size, 1.0 + REFRACTION_MARGIN), None);
        let reflection_under =
            ColorDepth::new(device, "reflection under", reflection.size, Some(downsampler));
        let refraction_over = ColorDepth::new(device, "refraction over", refraction.size, None);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("clamp"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let tv = wgpu::BindingResource::TextureView;
        let water_inputs = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("water inputs"),
            layout: water_inputs_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: tv(&reflection.sampled_view) },
                wgpu::BindGroupEntry { binding: 1, resource: tv(&refraction.color_view) },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&refraction.depth_view) },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
                wgpu::BindGroupEntry { binding: 4, resource: tv(&reflection_under.sampled_view) },
                wgpu::BindGroupEntry { binding: 5, resource: tv(&refraction_over.color_view) },
                wgpu::BindGroupEntry { binding: 6, resource: tv(&refraction_over.depth_view) },
            ],
        });
        let water_object = settings
            .refractive_objects
            .then(|| water_object.create_targets(device, size, &depth_view));
        let godrays = godrays.create_targets(
            device,
            size,
            settings.godray_resolution,
            &depth_view,
            medium_view,
        );
        let tonemap_input = tonemap.input_group(
            device,
            [&hdr_view, &reflection.color_view, &refraction.color_view, &depth_view, medium_view],
        );
        Targets {
            size,
            settings,
            hdr,
            hdr_view,
            depth_stencil,
            depth_stencil_view,
            depth_view,
            reflection,
            refraction,
            reflection_under,
            refraction_over,
            water_inputs,
            tonemap_input,
            godrays,
            water_object,
            medium_copy,
        }
    }
}
