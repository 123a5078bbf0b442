//! FFT ocean on the GPU (Tessendorf, *Simulating Ocean Water*; seed 000
//! §2.3.1). Per frame: evolve the uploaded initial spectrum to time t
//! (`spectrum.wgsl`), inverse-FFT rows then columns in workgroup memory
//! (`fft.wgsl`), unpack into displacement / derivative / slope-moment textures
//! per cascade and build their mips (`assemble.wgsl`). The CPU twin is
//! `hydrolux_core::waves::ocean`.

use crate::error::OceanTooLarge;
use crate::gpu_util::*;
use crate::mips::{Downsampler, MipChain, storage_array_texture};
use crate::shaders;
use crate::timing::GpuTimer;
use crate::uniforms::{AssembleUniforms, EvolveUniforms};
use hydrolux_core::waves::ocean::{OceanSpectrum, time_phase};
use wgpu::util::DeviceExt;

pub fn spectrum_source() -> String {
    shaders::compose("", include_str!("spectrum.wgsl"))
}

pub fn assemble_source() -> String {
    shaders::compose("", include_str!("assemble.wgsl"))
}

/// Threads of an FFT row's workgroup on a device without a lower limit.
pub const MAX_FFT_THREADS: u32 = 256;

/// Workgroup size of the FFT: one thread per butterfly, at most 256 and at
/// most what the device allows (`max_threads`, a power of two); the shader
/// strides over the rest.
fn fft_threads(n: u32, max_threads: u32) -> u32 {
    (n / 2).min(MAX_FFT_THREADS).min(max_threads).max(1)
}

pub fn fft_source(n: u32, max_threads: u32) -> String {
    let consts = format!(
        "const FFT_N: u32 = {n}u;\nconst FFT_LOG2_N: u32 = {}u;\nconst FFT_THREADS: u32 = {}u;\n",
        n.ilog2(),
        fft_threads(n, max_threads)
    );
    shaders::compose(&consts, include_str!("fft.wgsl"))
}

/// Bytes of the FFT working buffer: 2 vec4 planes per cascade.
pub fn fields_bytes(n: u32, cascades: u32) -> u64 {
    n as u64 * n as u64 * cascades as u64 * 2 * 16
}

/// The ocean's textures, sampled by every pass that draws the surface.
pub struct SurfaceTextures {
    pub displacement: wgpu::Texture,
    pub derivative: wgpu::Texture,
    pub moments: wgpu::Texture,
}

pub struct OceanPass {
    pub n: u32,
    pub cascades: u32,
    choppiness: f32,
    pub fields: wgpu::Buffer,
    evolve_uniforms: wgpu::Buffer,
    evolve: wgpu::ComputePipeline,
    fft_rows: wgpu::ComputePipeline,
    fft_columns: wgpu::ComputePipeline,
    assemble: wgpu::ComputePipeline,
    evolve_group: wgpu::BindGroup,
    fft_group: wgpu::BindGroup,
    assemble_group: wgpu::BindGroup,
    pub textures: SurfaceTextures,
    mips: [MipChain; 3],
}

impl OceanPass {
    pub fn new(
        device: &wgpu::Device,
        spectrum: &OceanSpectrum,
        downsampler: &Downsampler,
        caps: &crate::capabilities::Capabilities,
    ) -> Result<Self, OceanTooLarge> {
        let n = spectrum.settings.resolution as u32;
        let cascades = spectrum.cascades.len() as u32;
        let need =
            fields_bytes(n, cascades).max(std::mem::size_of_val(spectrum.modes.as_slice()) as u64);
        let max = caps.max_storage_buffer;
        if need > max {
            return Err(OceanTooLarge {
                n,
                cascades,
                need_mib: need.div_ceil(1 << 20),
                max_mib: max >> 20,
            });
        }
        let modes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ocean initial spectrum"),
            contents: bytemuck::cast_slice(&spectrum.modes),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let fields = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ocean FFT fields"),
            size: fields_bytes(n, cascades),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let choppiness = spectrum.settings.choppiness as f32;
        let evolve_uniforms = uniform_buffer(device, "ocean evolve", &EvolveUniforms::default());
        let assemble_uniforms = uniform_buffer(
            device,
            "ocean assemble",
            &AssembleUniforms { n, cascades, _pad0: 0, _pad1: 0 },
        );

        let cs = wgpu::ShaderStages::COMPUTE;
        let evolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ocean evolve"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, true),
                storage_entry(2, cs, false),
            ],
        });
        let fft_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ocean fft"),
            entries: &[storage_entry(0, cs, false)],
        });
        let d2a = wgpu::TextureViewDimension::D2Array;
        let assemble_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ocean assemble"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, true),
                storage_texture_entry(2, crate::mips::FORMAT, d2a),
                storage_texture_entry(3, crate::mips::FORMAT, d2a),
                storage_texture_entry(4, crate::mips::FORMAT, d2a),
            ],
        });
        let spectrum_module = shader(device, "ocean spectrum", &spectrum_source());
        let fft_module = shader(device, "ocean fft", &fft_source(n, caps.max_workgroup_threads));
        let assemble_module = shader(device, "ocean assemble", &assemble_source());
        let evolve =
            compute_pipeline(device, "ocean evolve", &spectrum_module, "evolve", &[&evolve_layout]);
        let fft_rows =
            compute_pipeline(device, "ocean fft rows", &fft_module, "fft_rows", &[&fft_layout]);
        let fft_columns = compute_pipeline(
            device,
            "ocean fft columns",
            &fft_module,
            "fft_columns",
            &[&fft_layout],
        );
        let assemble = compute_pipeline(
            device,
            "ocean assemble",
            &assemble_module,
            "assemble",
            &[&assemble_layout],
        );

        // The shaders take the cascade count from their uniforms; the
        // textures may hold a padding layer (`Capabilities::array_layers`).
        let layers = caps.array_layers(cascades);
        let textures = SurfaceTextures {
            displacement: storage_array_texture(device, "ocean displacement", n, layers),
            derivative: storage_array_texture(device, "ocean derivatives", n, layers),
            moments: storage_array_texture(device, "ocean slope moments", n, layers),
        };
        let mip0 = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(d2a),
                base_mip_level: 0,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        fn buffer(b: u32, buf: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding: b, resource: buf.as_entire_binding() }
        }
        let evolve_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ocean evolve"),
            layout: &evolve_layout,
            entries: &[buffer(0, &evolve_uniforms), buffer(1, &modes), buffer(2, &fields)],
        });
        let fft_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ocean fft"),
            layout: &fft_layout,
            entries: &[buffer(0, &fields)],
        });
        let (v0, v1, v2) =
            (mip0(&textures.displacement), mip0(&textures.derivative), mip0(&textures.moments));
        let assemble_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ocean assemble"),
            layout: &assemble_layout,
            entries: &[
                buffer(0, &assemble_uniforms),
                buffer(1, &fields),
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&v0),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&v1),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&v2),
                },
            ],
        });
        let mips = [
            downsampler.chain(device, &textures.displacement),
            downsampler.chain(device, &textures.derivative),
            downsampler.chain(device, &textures.moments),
        ];
        Ok(OceanPass {
            n,
            cascades,
            choppiness,
            fields,
            evolve_uniforms,
            evolve,
            fft_rows,
            fft_columns,
            assemble,
            evolve_group,
            fft_group,
            assemble_group,
            textures,
            mips,
        })
    }

    /// Per-frame input: the simulation time.
    pub fn prepare(&self, queue: &wgpu::Queue, time: f64) {
        let u = EvolveUniforms {
            phase: time_phase(time),
            n: self.n,
            cascades: self.cascades,
            choppiness: self.choppiness,
        };
        queue.write_buffer(&self.evolve_uniforms, 0, bytemuck::bytes_of(&u));
    }

    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        downsampler: &Downsampler,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let (n, c) = (self.n, self.cascades);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ocean spectrum"),
                timestamp_writes: timer
                    .as_deref_mut()
                    .and_then(|t| t.compute_writes("ocean spectrum")),
            });
            pass.set_pipeline(&self.evolve);
            pass.set_bind_group(0, &self.evolve_group, &[]);
            pass.dispatch_workgroups(n.div_ceil(8), n.div_ceil(8), c);
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ocean fft"),
                timestamp_writes: timer.as_deref_mut().and_then(|t| t.compute_writes("ocean fft")),
            });
            pass.set_bind_group(0, &self.fft_group, &[]);
            pass.set_pipeline(&self.fft_rows);
            pass.dispatch_workgroups(n, 2 * c, 1);
            pass.set_pipeline(&self.fft_columns);
            pass.dispatch_workgroups(n, 2 * c, 1);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ocean textures"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("ocean textures")),
        });
        pass.set_pipeline(&self.assemble);
        pass.set_bind_group(0, &self.assemble_group, &[]);
        pass.dispatch_workgroups(n.div_ceil(8), n.div_ceil(8), c);
        for chain in &self.mips {
            downsampler.record(&mut pass, chain);
        }
    }

    /// The transformed fields of every cascade, as the CPU twin lays them out:
    /// per texel [Dx, h, Dz, ∂h/∂x, ∂h/∂z, ∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z].
    pub fn read_fields(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<[f32; 8]> {
        let bytes = read_buffer(device, queue, &self.fields, fields_bytes(self.n, self.cascades));
        let v: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let plane = (self.n * self.n) as usize;
        let mut out = Vec::with_capacity(plane * self.cascades as usize);
        for c in 0..self.cascades as usize {
            for i in 0..plane {
                let a = v[2 * c * plane + i];
                let b = v[(2 * c + 1) * plane + i];
                out.push([a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]);
            }
        }
        out
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "ocean",
    dumps: &[],
    shaders: || {
        let mut v = vec![
            ("ocean/spectrum".to_string(), spectrum_source()),
            ("ocean/assemble".to_string(), assemble_source()),
        ];
        v.extend([64u32, 256, 1024].map(|n| (format!("ocean/fft N={n}"), fft_source(n, 256))));
        // A GLES 3.1 device's guaranteed 128 threads, and a tiny workgroup.
        v.extend(
            [(1024u32, 128u32), (256, 16)]
                .map(|(n, t)| (format!("ocean/fft N={n}, {t} threads"), fft_source(n, t))),
        );
        v
    },
    uniforms: || {
        use crate::uniforms::{AssembleUniforms, EvolveUniforms, Layout};
        vec![
            Layout::of::<EvolveUniforms>(spectrum_source()),
            Layout::of::<hydrolux_core::waves::ocean::SpectrumMode>(spectrum_source()),
            Layout::of::<AssembleUniforms>(assemble_source()),
        ]
    },
};

/// The largest `ocean.resolution` (a power of two, 64 to 1024) whose FFT
/// buffers fit this device's storage-buffer limit with `cascades` cascades.
pub fn largest_ocean_resolution(device: &wgpu::Device, cascades: u32) -> u32 {
    let max = crate::capabilities::Capabilities::of(device).max_storage_buffer;
    [1024u32, 512, 256, 128, 64]
        .into_iter()
        .find(|&n| fields_bytes(n, cascades) <= max)
        .unwrap_or(64)
}

#[cfg(test)]
mod tests {
    use super::fft_threads;

    #[test]
    fn fft_workgroups_fit_the_device() {
        assert_eq!(fft_threads(64, 1024), 32, "one thread per butterfly");
        assert_eq!(fft_threads(1024, 1024), 256, "at most 256");
        assert_eq!(fft_threads(1024, 128), 128, "a GLES 3.1 device's guarantee");
        assert_eq!(fft_threads(256, 16), 16);
    }
}
