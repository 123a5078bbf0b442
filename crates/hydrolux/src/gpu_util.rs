//! Small wgpu helpers shared by the passes: layouts, pipelines, readback.

use wgpu::util::DeviceExt;

pub fn uniform_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    label: &str,
    value: &T,
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::bytes_of(value),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    })
}

/// A single-level, single-sample 2D texture (size at least 1×1).
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0.max(1),
            height: size.1.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

pub fn layout_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility, ty, count: None }
}

pub fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

/// A storage buffer of `size` bytes (at least 16) that can be written and
/// read back, with `extra` usages.
pub fn storage_buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    })
}

pub fn storage_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

/// A compute layout of a uniform at binding 0 and storage buffers from
/// binding 1, each read-only or not as `read_only` says.
pub fn compute_buffers_layout(
    device: &wgpu::Device,
    label: &str,
    read_only: &[bool],
) -> wgpu::BindGroupLayout {
    let cs = wgpu::ShaderStages::COMPUTE;
    let entries: Vec<_> = std::iter::once(uniform_entry(0, cs))
        .chain(read_only.iter().enumerate().map(|(i, &r)| storage_entry(i as u32 + 1, cs, r)))
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A bind group of whole buffers, binding i the i-th.
pub fn bind_buffers(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<_> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A 2D depth texture (read with a comparison sampler or `textureLoad`).
pub fn depth_texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
    )
}

/// A 2D unsigned-integer texture (the stencil's medium, read with `textureLoad`).
pub fn uint_texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
    )
}

pub fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    dim: wgpu::TextureViewDimension,
    filterable: bool,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: dim,
            multisampled: false,
        },
    )
}

pub fn storage_texture_entry(
    binding: u32,
    format: wgpu::TextureFormat,
    dim: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    storage_texture_access_entry(binding, format, dim, wgpu::StorageTextureAccess::WriteOnly)
}

pub fn storage_texture_access_entry(
    binding: u32,
    format: wgpu::TextureFormat,
    dim: wgpu::TextureViewDimension,
    access: wgpu::StorageTextureAccess,
) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        wgpu::ShaderStages::COMPUTE,
        wgpu::BindingType::StorageTexture { access, format, view_dimension: dim },
    )
}

pub fn sampler_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    layout_entry(
        binding,
        visibility,
        wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
    )
}

pub fn shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

pub fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::ComputePipeline {
    compute_pipeline_with(device, label, module, entry, layouts, &[])
}

/// [`compute_pipeline`] with values for the shader's pipeline constants.
pub fn compute_pipeline_with(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    layouts: &[&wgpu::BindGroupLayout],
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
        cache: None,
    })
}

pub fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}

/// A pipeline drawing one fullscreen triangle (`vs_main`, `fs_main`) into
/// one colour target, without depth.
pub fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    pulled_pipeline(device, label, module, layouts, format.into())
}

/// A pipeline whose vertex shader (`vs_main`) pulls what it draws from its
/// bindings (no vertex buffers: a fullscreen triangle, instanced quads over
/// particles) and whose `fs_main` writes `target`, without depth.
pub fn pulled_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    target: wgpu::ColorTargetState,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout(device, label, layouts)),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(target)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Creates `a` on this thread and `b` on a second one, for GPU objects whose
/// creation is slow on the CPU: a driver compiles a pipeline's shaders when
/// it is created (lavapipe takes ~0.5 s for the water's fragment shader), and
/// Vulkan, Metal and D3D12 allow it from several threads. `b`'s wgpu errors
/// are caught on its own thread (error scopes are per thread) and returned;
/// `a`'s reach the caller's scope. On wasm32, one after the other.
#[cfg(not(target_arch = "wasm32"))]
pub fn create_in_parallel<A, B: Send>(
    device: &wgpu::Device,
    during: &str,
    a: impl FnOnce() -> A,
    b: impl FnOnce() -> B + Send,
) -> Result<(A, B), crate::error::RenderError> {
    std::thread::scope(|scope| {
        let second = scope
            .spawn(|| crate::error::catch_gpu_errors(device, || during.to_string(), || Ok(b())));
        let a = a();
        let b = second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))?;
        Ok((a, b))
    })
}

/// [`create_in_parallel`] where there are no threads: one after the other.
#[cfg(target_arch = "wasm32")]
pub fn create_in_parallel<A, B>(
    _device: &wgpu::Device,
    _during: &str,
    a: impl FnOnce() -> A,
    b: impl FnOnce() -> B,
) -> Result<(A, B), crate::error::RenderError> {
    Ok((a(), b()))
}

/// Premultiplied "over" blending into the HDR image (particles, sprites).
/// The image's alpha (the anti-aliasing's trust in a pixel's history) is
/// scaled by what shows through: a moving particle is not reprojected.
pub fn over_hdr() -> wgpu::ColorTargetState {
    let colour = wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING.color;
    let trust = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    };
    wgpu::ColorTargetState {
        format: crate::targets::HDR_FORMAT,
        blend: Some(wgpu::BlendState { color: colour, alpha: trust }),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// Draw a `fullscreen_pipeline` with its bind groups (group i = `groups[i]`)
/// into `target`, cleared to black first.
pub fn draw_fullscreen(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    groups: &[&wgpu::BindGroup],
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    for (i, group) in groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *group, &[]);
    }
    pass.draw(0..3, 0..1);
}

/// Copy `size` bytes of `source` to the CPU (submits and waits).
pub fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    source: &wgpu::Buffer,
    size: u64,
) -> Vec<u8> {
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(source, 0, &staging, 0, size);
    queue.submit([encoder.finish()]);
    map_and_read(device, &staging)
}

/// A copy of a buffer to the CPU that does not block the frame: `request`
/// records the copy and maps it; `take` hands the bytes over once the map
/// has completed. Native code may wait for it (`wait`: a copy submitted a
/// step earlier, done long since); a browser cannot block, so there `take`
/// answers `None` until the page's event loop has delivered the map.
pub struct AsyncReadback {
    staging: wgpu::Buffer,
    size: u64,
    /// 0 idle, 1 mapping, 2 mapped, 3 failed (device lost).
    state: std::sync::Arc<std::sync::atomic::AtomicU8>,
}

impl AsyncReadback {
    pub fn new(device: &wgpu::Device, label: &str, size: u64) -> Self {
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        AsyncReadback { staging, size, state: Default::default() }
    }

    /// Whether a copy is on its way.
    pub fn in_flight(&self) -> bool {
        self.state.load(std::sync::atomic::Ordering::Acquire) != 0
    }

    /// Copy `source` (its first `size` bytes) after the work submitted so
    /// far and start mapping it; false if the last copy is still in flight.
    pub fn request(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &wgpu::Buffer,
    ) -> bool {
        self.request_from(device, queue, source, 0)
    }

    /// [`AsyncReadback::request`] of `source`'s bytes from `offset` on.
    pub fn request_from(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        source: &wgpu::Buffer,
        offset: u64,
    ) -> bool {
        use std::sync::atomic::Ordering;
        if self.in_flight() {
            return false;
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(source, offset, &self.staging, 0, self.size);
        queue.submit([encoder.finish()]);
        self.state.store(1, Ordering::Release);
        let state = self.state.clone();
        self.staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            state.store(if r.is_ok() { 2 } else { 3 }, Ordering::Release);
        });
        true
    }

    /// The bytes of the last request once mapped (waiting for them if
    /// `wait`, which a browser ignores), or `None` (none requested, not
    /// mapped yet, or the device was lost).
    pub fn take(&self, device: &wgpu::Device, wait: bool) -> Option<Vec<u8>> {
        use std::sync::atomic::Ordering;
        if !self.in_flight() {
            return None;
        }
        let poll = if wait && !cfg!(target_arch = "wasm32") {
            wgpu::PollType::wait_indefinitely()
        } else {
            wgpu::PollType::Poll
        };
        let _ = device.poll(poll);
        match self.state.load(Ordering::Acquire) {
            2 => {
                let bytes = self.staging.slice(..).get_mapped_range().ok().map(|m| m.to_vec());
                self.staging.unmap();
                self.state.store(0, Ordering::Release);
                bytes
            }
            3 => {
                self.state.store(0, Ordering::Release);
                None
            }
            _ => None,
        }
    }
}

/// Map a MAP_READ buffer, wait, and copy its contents out.
pub fn map_and_read(device: &wgpu::Device, staging: &wgpu::Buffer) -> Vec<u8> {
    let slice = staging.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    device.poll(wgpu::PollType::wait_indefinitely()).expect("GPU device lost while reading back");
    let bytes = slice.get_mapped_range().expect("readback buffer mapped").to_vec();
    staging.unmap();
    bytes
}

/// Copy a 2D texture (one layer, mip 0) to the CPU as tightly packed rows.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
) -> Vec<u8> {
    read_texture_aspect(device, queue, texture, bytes_per_pixel, wgpu::TextureAspect::All)
}

/// Copy level 0 of one aspect of a texture (e.g. the stencil) to the CPU.
pub fn read_texture_aspect(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
    aspect: wgpu::TextureAspect,
) -> Vec<u8> {
    read_texture_region(device, queue, texture, bytes_per_pixel, aspect, 0)
}

/// Copy level 0 of one layer of an array texture to the CPU.
pub fn read_texture_layer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
    layer: u32,
) -> Vec<u8> {
    read_texture_region(device, queue, texture, bytes_per_pixel, wgpu::TextureAspect::All, layer)
}

fn read_texture_region(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
    aspect: wgpu::TextureAspect,
    layer: u32,
) -> Vec<u8> {
    let (w, h) = (texture.width(), texture.height());
    let unpadded = w * bytes_per_pixel;
    let padded =
        unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture readback"),
        size: (padded * h) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            aspect,
            origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
            ..texture.as_image_copy()
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    queue.submit([encoder.finish()]);
    let bytes = map_and_read(device, &staging);
    let mut out = Vec::with_capacity((unpadded * h) as usize);
    for row in bytes.chunks_exact(padded as usize) {
        out.extend_from_slice(&row[..unpadded as usize]);
    }
    out
}
/// IEEE half → single precision.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 => {
            if frac == 0.0 {
                sign * f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => sign * (1.0 + frac / 1024.0) * 2f32.powi(exp - 15),
    }
}

/// An RGBA half-float texture's texels as f32, rows top to bottom.
pub fn read_rgba16f(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Vec<[f32; 4]> {
    let bytes = read_texture(device, queue, texture, 8);
    let halves: &[u16] = bytemuck::cast_slice(&bytes);
    let texel =
        |c: &[u16]| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])];
    halves.chunks_exact(4).map(texel).collect()
}
