//! What the device can do, read in one place: every technique chooses its
//! formats, variants and sizes from [`Capabilities`], never from the device
//! directly, so one list says how Hydrolux adapts to an adapter and what it
//! turns off (`hydrolux info` prints it).
//!
//! The differences that matter today, all met on real adapters:
//! - wgpu's OpenGL backend (Mesa llvmpipe, older GPUs, VMs, Raspberry Pi
//!   class boards) renders no 32-bit float colour target, cannot `textureLoad`
//!   a depth texture bound for comparison, cannot copy depth or stencil to a
//!   buffer, and guesses a GL texture target from the layer count: a 2D
//!   array of one layer becomes a plain 2D texture, a square array of six
//!   becomes a cube map, and either then reads as zeros through an array
//!   view. Hydrolux renders floats as their bits into 32-bit integer
//!   targets on every backend, binds depth it reads as unfilterable float,
//!   and pads array textures here ([`Capabilities::array_layers`]).
//! - `Depth32FloatStencil8` and timestamp queries are optional features.
//! - WebGL2 and OpenGL ES 3.0 have no compute shaders; most of Hydrolux's
//!   techniques are compute, so such an adapter is refused with a message
//!   ([`Capabilities::check_supported`]) rather than rendering half a frame.

use crate::error::RenderError;

/// The device's capabilities as Hydrolux uses them.
#[derive(Clone, Debug)]
pub struct Capabilities {
    /// The adapter's name and backend, for messages.
    pub adapter: String,
    pub backend: wgpu::Backend,
    /// A software adapter (lavapipe, llvmpipe, SwiftShader): `render.quality = "auto"` picks `low`.
    pub cpu: bool,
    /// Compute shaders (not on WebGL2 / GLES 3.0).
    pub compute: bool,
    /// The main view keeps 32-bit float depth with its stencil.
    pub depth32_stencil8: bool,
    /// GPU timestamps for `bench`'s per-pass times.
    pub timestamps: bool,
    /// Depth and stencil can be copied to a buffer (not on GL): the medium
    /// readback copies the stencil where it can, else its colour copy.
    pub depth_stencil_copies: bool,
    /// Depth and stencil of one texture can be read in the same draw (not
    /// on GL, where the texture is in one mode or the other): elsewhere
    /// the stencil is copied to a colour texture first (`targets::MediumCopy`).
    pub depth_and_stencil_reads: bool,
    /// GL picks a texture's target from its layer count (see the module
    /// doc): array textures get layers that keep them arrays.
    pub pad_array_layers: bool,
    /// Largest 2D texture side.
    pub max_texture_2d: u32,
    /// Threads one workgroup may have along x (a power of two): the FFT's
    /// rows use up to 256, GLES 3.1 guarantees only 128.
    pub max_workgroup_threads: u32,
    /// Largest storage buffer binding (bytes): bounds the FFT ocean size.
    pub max_storage_buffer: u64,
}

impl Capabilities {
    /// Read from a device (the library's callers bring their own, so the
    /// adapter is known only through it).
    pub fn of(device: &wgpu::Device) -> Self {
        let info = device.adapter_info();
        let (features, limits) = (device.features(), device.limits());
        let gl = info.backend == wgpu::Backend::Gl;
        Capabilities {
            adapter: format!("{} ({:?})", info.name, info.backend),
            backend: info.backend,
            cpu: info.device_type == wgpu::DeviceType::Cpu,
            compute: limits.max_compute_workgroups_per_dimension > 0
                && limits.max_compute_invocations_per_workgroup >= 64
                && limits.max_storage_buffers_per_shader_stage > 0,
            depth32_stencil8: features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8),
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            depth_stencil_copies: !gl,
            depth_and_stencil_reads: !gl,
            pad_array_layers: gl,
            max_texture_2d: limits.max_texture_dimension_2d,
            max_workgroup_threads: {
                let t = limits
                    .max_compute_invocations_per_workgroup
                    .min(limits.max_compute_workgroup_size_x)
                    .max(1);
                1 << t.ilog2()
            },
            max_storage_buffer: limits.max_storage_buffer_binding_size.min(limits.max_buffer_size),
        }
    }

    /// Layers to allocate for a 2D array texture of `layers` layers (square
    /// or not), so that every backend keeps it an array: on GL one layer
    /// becomes two and a multiple of six gets one more. Shaders take the
    /// real count from a uniform, never from `textureNumLayers`.
    pub fn array_layers(&self, layers: u32) -> u32 {
        if !self.pad_array_layers {
            layers
        } else if layers == 1 {
            2
        } else if layers.is_multiple_of(6) {
            layers + 1
        } else {
            layers
        }
    }

    /// Refuse an adapter Hydrolux cannot draw a frame on, with the reason.
    pub fn check_supported(&self) -> Result<(), RenderError> {
        if !self.compute {
            return Err(RenderError::Unsupported(format!(
                "the adapter {} has no compute shaders (WebGL2 and OpenGL ES 3.0 lack them), \
                 which the ocean, sky, caustics and god rays need: use a WebGPU, Vulkan, Metal, \
                 DX12 or OpenGL 4.3 / ES 3.1 adapter",
                self.adapter
            )));
        }
        Ok(())
    }

    /// How each technique adapts to this device, one line each (for
    /// `hydrolux info`).
    pub fn adaptations(&self) -> Vec<String> {
        let mut out = vec![
            format!(
                "main depth: {}",
                if self.depth32_stencil8 {
                    "Depth32FloatStencil8"
                } else {
                    "Depth24PlusStencil8 (no Depth32FloatStencil8)"
                }
            ),
            format!(
                "per-pass GPU times: {}",
                if self.timestamps { "timestamp queries" } else { "off (no timestamp queries)" }
            ),
            "float targets (god-ray depth, water-object faces): f32 bits in 32-bit integer \
             targets, renderable everywhere"
                .into(),
            format!(
                "compute workgroups: at most {} threads (the FFTs' rows use up to that)",
                self.max_workgroup_threads
            ),
        ];
        if !self.depth_and_stencil_reads {
            out.push(
                "pixel medium: the stencil copied to an R8Uint texture after the main pass \
                 (depth and stencil cannot be read in one draw)"
                    .into(),
            );
        }
        if self.pad_array_layers {
            out.push(
                "array textures: one layer padded to two, six to seven (GL texture targets)".into(),
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn caps(pad: bool) -> Capabilities {
        Capabilities {
            adapter: "test".into(),
            cpu: false,
            backend: if pad { wgpu::Backend::Gl } else { wgpu::Backend::Vulkan },
            compute: true,
            depth32_stencil8: true,
            timestamps: false,
            depth_stencil_copies: !pad,
            depth_and_stencil_reads: !pad,
            pad_array_layers: pad,
            max_texture_2d: 8192,
            max_workgroup_threads: 256,
            max_storage_buffer: 1 << 27,
        }
    }

    #[test]
    fn gl_array_layers_never_read_as_2d_or_cube() {
        let gl = caps(true);
        for n in 1..=30 {
            let l = gl.array_layers(n);
            assert!(l >= n && l != 1 && !l.is_multiple_of(6), "{n} layers → {l}");
        }
        let vk = caps(false);
        assert!((1..=30).all(|n| vk.array_layers(n) == n));
    }

    #[test]
    fn no_compute_is_refused_with_the_reason() {
        let mut c = caps(true);
        assert!(c.check_supported().is_ok());
        c.compute = false;
        let e = c.check_supported().unwrap_err().to_string();
        assert!(e.contains("no compute shaders") && e.contains("test"), "{e}");
    }
}
