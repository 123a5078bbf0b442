//! Size-dependent render targets, rebuilt in one place when the output size
//! (or a setting that sizes them) changes: the HDR image and its depth, the
//! reflection and refraction textures with their depths, and the bind
//! groups that read them.

pub use crate::formats::*;

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
    pub mips: Option<crate::mips::MipChain>,
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
    /// The main view's stencil alone (each pixel's medium).
    pub stencil_view: wgpu::TextureView,
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

pub(crate) const MEDIUM_COPY_INFO: crate::info::TechniqueInfo = crate::info::TechniqueInfo {
    name: "medium copy",
    dumps: &[],
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
        downsampler: Option<&crate::mips::Downsampler>,
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
    /// What readers of the pixel's medium bind: the stencil, or its copy
    /// where depth and stencil cannot be read in one draw.
    pub fn medium_view(&self) -> &wgpu::TextureView {
        self.medium_copy.as_ref().map_or(&self.stencil_view, |c| &c.view)
    }

    /// The targets for `size`: on `device`, the main view's depth and
    /// stencil in `depth_format`, the reflections' mips by `downsampler`,
    /// the stencil copied by `medium_copy` where it cannot be read.
    pub fn new(
        device: &wgpu::Device,
        downsampler: &crate::mips::Downsampler,
        depth_format: wgpu::TextureFormat,
        medium_copy: Option<&MediumCopyPass>,
        size: (u32, u32),
        settings: TargetSettings,
    ) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        // The anti-aliasing copies its resolve back into the HDR image.
        let hdr_usage = usage | wgpu::TextureUsages::COPY_DST;
        let hdr = texture(device, "hdr", size, HDR_FORMAT, hdr_usage);
        let depth_stencil = texture(device, "depth stencil", size, depth_format, usage);
        let hdr_view = hdr.create_view(&Default::default());
        let depth_stencil_view = depth_stencil.create_view(&Default::default());
        let aspect = |aspect| {
            depth_stencil.create_view(&wgpu::TextureViewDescriptor { aspect, ..Default::default() })
        };
        let (depth_view, stencil_view) =
            (aspect(wgpu::TextureAspect::DepthOnly), aspect(wgpu::TextureAspect::StencilOnly));
        let medium_copy = medium_copy.map(|pass| pass.targets(device, size));
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
            stencil_view,
            medium_copy,
        }
    }
}

/// One of the main view's two render passes (the medium classification
/// clears; the scene loads), over the HDR image and the depth-stencil.
pub(crate) fn main_pass(
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
    label: &'static str,
    clear: bool,
    timer: Option<&mut crate::timing::GpuTimer>,
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
