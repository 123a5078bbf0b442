//! A minimal wgpu program showing the driver behaviour behind Hydrolux's
//! old memory growth (issue "Reliability"), and the workaround it uses.
//!
//! Mesa's lavapipe 22 (Debian 12's `mesa-vulkan-drivers`) "inlines"
//! uniform values that a shader branches on: when the branch can remove
//! much of the shader, it compiles a copy with the values folded in — again
//! every time a bind group with that uniform buffer is set, and it never
//! frees the copies. A vertex shader that switches on a uniform between a
//! few large cases therefore grows resident memory on every bind.
//!
//! ```text
//! cargo run --release -p hydrolux --example lavapipe_uniform_branch            # grows
//! cargo run --release -p hydrolux --example lavapipe_uniform_branch specialised # flat
//! ```
//!
//! `specialised` sets the switch's selector as a pipeline constant
//! (`override`), so the dead cases fold away at pipeline creation and there
//! is no uniform branch left to inline. Newer Mesa caches the inlined
//! variants; other drivers do not do this at all.

use wgpu::util::DeviceExt;

const SHADER: &str = r#"
@group(0) @binding(0) var<uniform> params: vec4<u32>;
// 255: read the selector from the uniform buffer.
override SELECTOR: u32 = 255u;

fn selector() -> u32 {
    if (SELECTOR == 255u) {
        return params.x;
    }
    return SELECTOR;
}

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let q = vec2<f32>(f32(i % 2u), f32(i / 2u));
    var h = 0.0;
    switch selector() {
        case 0u: { for (var k = 0; k < 16; k++) { h += sin(q.x * f32(k)) * cos(q.y * f32(k + 1)); } }
        case 1u: { for (var k = 0; k < 16; k++) { h += exp(q.x * f32(k) * 0.01) * tan(q.y + f32(k)); } }
        case 3u: { for (var k = 0; k < 16; k++) { h += pow(q.x + 1.0, f32(k) * 0.1) * sqrt(q.y + f32(k)); } }
        default: {}
    }
    return vec4<f32>(q - 0.5, 0.5 + 0.001 * h, 1.0);
}

@fragment
fn fs() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0);
}
"#;

fn main() {
    let specialised = std::env::args().any(|a| a == "specialised");
    let ctx = hydrolux::GpuContext::headless().expect("a GPU adapter");
    let (device, queue) = (&ctx.device, &ctx.queue);
    println!("adapter: {}", ctx.adapter.get_info().name);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let constants = [("SELECTOR", 2.0)];
    let options = || wgpu::PipelineCompilationOptions {
        constants: if specialised { &constants } else { &[] },
        ..Default::default()
    };
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: options(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: options(),
            targets: &[Some(wgpu::TextureFormat::Rgba8Unorm.into())],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&[2u32, 0, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() }],
    });
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width: 16, height: 16, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = target.create_view(&Default::default());
    let (frames, binds_per_frame) = (200, 4);
    let mut start = 0.0;
    for frame in 0..frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            for _ in 0..binds_per_frame {
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
        let index = queue.submit([encoder.finish()]);
        device
            .poll(wgpu::PollType::Wait { submission_index: Some(index), timeout: None })
            .expect("frame finishes");
        if frame == 19 {
            start = hydrolux::headless::resident_mb().unwrap_or(0.0);
        }
    }
    println!(
        "{}: resident memory grew {:.1} MB over {} frames ({binds_per_frame} binds each)",
        if specialised { "specialised" } else { "uniform switch" },
        hydrolux::headless::resident_mb().unwrap_or(0.0) - start,
        frames - 20
    );
}
