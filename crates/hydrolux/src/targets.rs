//! Size-dependent render targets, rebuilt in one place when the output size changes.

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub struct Targets {
    pub size: (u32, u32),
    pub hdr: wgpu::Texture,
    pub hdr_view: wgpu::TextureView,
    pub depth_view: wgpu::TextureView,
    /// The tone map's input bind group (refers to `hdr`).
    pub tonemap_input: wgpu::BindGroup,
}

impl Targets {
    pub fn new(device: &wgpu::Device, size: (u32, u32), tonemap: &crate::passes::tonemap::TonemapPass) -> Self {
        let extent = wgpu::Extent3d { width: size.0.max(1), height: size.1.max(1), depth_or_array_layers: 1 };
        let texture = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let hdr = texture("hdr", HDR_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC);
        let depth = texture("depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let hdr_view = hdr.create_view(&Default::default());
        let tonemap_input = tonemap.input_group(device, &hdr_view);
        Targets { size, hdr, hdr_view, depth_view: depth.create_view(&Default::default()), tonemap_input }
    }
}
