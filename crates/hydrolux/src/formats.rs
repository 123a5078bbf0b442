//! The main view's formats and media, as every pipeline that draws into it
//! must know (shared vocabulary below the framework and the techniques):
//! the HDR image, depths, the stencil's two media.

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
