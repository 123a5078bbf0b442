//! Rendering without a window: an offscreen sRGB target and readback, for
//! the CLI, benchmarks and tests.

use crate::error::{RenderError, catch_gpu_errors};
use crate::gpu_util::read_texture;
use crate::renderer::{FrameInput, Renderer};
use hydrolux_core::camera::Camera;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The pixels of an 8-bit RGBA or BGRA texture (a window's format), as
/// tightly packed RGBA8 (submits and waits): the viewer's screenshot of
/// what it shows.
pub fn read_rgba8(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Vec<u8> {
    let mut px = read_texture(device, queue, texture, 4);
    if matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for p in px.chunks_exact_mut(4) {
            p.swap(0, 2);
        }
    }
    px
}

pub struct HeadlessTarget {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub size: (u32, u32),
}

impl HeadlessTarget {
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("headless target"),
            size: wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        HeadlessTarget { texture, view, size }
    }

    /// Render one frame, wait for it, and return its tightly packed RGBA8
    /// (sRGB) pixels; a wgpu error on the way is a [`RenderError::Gpu`].
    pub fn render(
        &self,
        renderer: &mut Renderer,
        camera: Camera,
        time: f64,
    ) -> Result<Vec<u8>, RenderError> {
        self.submit(renderer, camera, time)?;
        let device = renderer.device().clone();
        catch_gpu_errors(
            &device,
            || "reading the frame back".into(),
            || Ok(read_texture(renderer.device(), renderer.queue(), &self.texture, 4)),
        )
    }

    /// Render one frame and submit it without reading it back.
    pub fn submit(
        &self,
        renderer: &mut Renderer,
        camera: Camera,
        time: f64,
    ) -> Result<wgpu::SubmissionIndex, RenderError> {
        let device = renderer.device().clone();
        catch_gpu_errors(
            &device,
            || format!("rendering a {}×{} frame", self.size.0, self.size.1),
            || {
                let mut encoder = renderer.device().create_command_encoder(&Default::default());
                renderer.render(
                    &mut encoder,
                    &FrameInput { target: &self.view, size: self.size, camera, time },
                );
                Ok(renderer.queue().submit([encoder.finish()]))
            },
        )
    }
}

/// Resident memory of this process (MB), where /proc tells it (Linux): for
/// `bench` and the soak and memory tests.
pub fn resident_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<f64>().ok()? / 1024.0)
}
