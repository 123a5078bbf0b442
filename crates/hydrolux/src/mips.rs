//! Mip chains for 2D-array (and cube) textures written by compute passes:
//! one 2×2 box-filter dispatch per level (`shaders/downsample.wgsl`).

use crate::gpu_util::*;
use crate::shaders;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The downsampling pipeline, created once and shared.
pub struct Downsampler {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// Bind groups for every level of one texture.
pub struct MipChain {
    levels: Vec<(wgpu::BindGroup, [u32; 3])>,
}

impl Downsampler {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("downsample"),
            entries: &[
                // Read as storage, not sampled: a sampled 2D-array view of
                // a cube texture does not exist on wgpu's GL backend (the
                // sky's mips would read zeros there); a storage image does.
                storage_texture_access_entry(
                    0,
                    FORMAT,
                    wgpu::TextureViewDimension::D2Array,
                    wgpu::StorageTextureAccess::ReadOnly,
                ),
                storage_texture_entry(1, FORMAT, wgpu::TextureViewDimension::D2Array),
            ],
        });
        let module = shader(device, "downsample", &source());
        let pipeline = compute_pipeline(device, "downsample", &module, "downsample", &[&layout]);
        Downsampler { layout, pipeline }
    }

    pub fn chain(&self, device: &wgpu::Device, texture: &wgpu::Texture) -> MipChain {
        let layers = texture.depth_or_array_layers();
        let view = |level: u32| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        let levels = (1..texture.mip_level_count())
            .map(|level| {
                let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("downsample level"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(&view(level - 1)),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&view(level)),
                        },
                    ],
                });
                let size =
                    [(texture.width() >> level).max(1), (texture.height() >> level).max(1), layers];
                (bg, size)
            })
            .collect();
        MipChain { levels }
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>, chain: &MipChain) {
        pass.set_pipeline(&self.pipeline);
        for (bg, [w, h, layers]) in &chain.levels {
            pass.set_bind_group(0, bg, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), *layers);
        }
    }
}

/// A mipmapped rgba16float 2D array texture usable as storage and for sampling.
pub fn storage_array_texture(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    layers: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: layers },
        mip_level_count: size.ilog2() + 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

pub(crate) fn source() -> String {
    shaders::compose("", "#import downsample")
}

pub(crate) const INFO: crate::info::TechniqueInfo = crate::info::TechniqueInfo {
    name: "mips",
    dumps: &[],
    shaders: || vec![("downsample".to_string(), source())],
    uniforms: Vec::new,
};
