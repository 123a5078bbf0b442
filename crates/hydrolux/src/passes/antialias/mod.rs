//! Temporal anti-aliasing (`render.antialias = "temporal"`; issue #32 item
//! 5; Karis 2014, Salvi 2016; CPU twin `hydrolux_core::antialias`). The
//! technique decides each frame's sub-pixel jitter (the frame plan shifts
//! the main view by it, so every technique draws the same jittered view),
//! and after the frame is lit resolves it (`resolve.wgsl`) into one of two
//! history textures: the new frame blended with the last resolve,
//! reprojected by depth through last frame's camera and clipped to the new
//! frame's neighbourhood. The resolve is copied back into the HDR image, so
//! the tone map, dumps and readbacks see the anti-aliased frame.
//!
//! The history starts again (the next frame is drawn without jitter and
//! passed through) on a new renderer, a scene edit, a new size, and while a
//! debug view is shown (those are drawn exact, without jitter).

use crate::gpu_util::*;
use crate::shaders;
use crate::targets::{HDR_FORMAT, Targets};
use crate::technique::{FrameContext, Shared, Stage, Technique};
use crate::timing::GpuTimer;
use glam::{Mat4, Vec2};
use hydrolux_core::antialias;
use hydrolux_core::scene::{Antialias, DebugView, Scene};

crate::uniforms::uniform! { AntialiasParams;
    /// WGSL `AntialiasParams` (resolve.wgsl).
    pub struct AntialiasUniforms {
        /// Last frame's view-projection times the inverse of this frame's
        /// (both without jitter): this frame's NDC and depth to last frame's clip.
        pub reprojection: [[f32; 4]; 4],
        /// 1 where the history holds earlier frames.
        pub has_history: u32,
        /// The new frame's least share: 1 / (frames in the history + 1).
        pub min_share: f32,
        /// 1 when the simulation's time is the last frame's (every pixel's
        /// history is trusted: `hydrolux_core::antialias::trust`).
        pub time_still: u32,
        /// 1 when neither the camera nor the time changed: the frames are
        /// averaged evenly (`min_share` counts the frames since the change).
        pub settled: u32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("resolve.wgsl"))
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "antialias",
    dumps: &[],
    shaders: || vec![("antialias".to_string(), source())],
    uniforms: || vec![crate::uniforms::Layout::of::<AntialiasUniforms>(source())],
};

/// The two history textures at the screen size, and the bind group that
/// reads each as last frame's (writing the other).
struct History {
    textures: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
    /// `groups[i]` reads history `i` (and the new frame), for writing `1 - i`.
    groups: [wgpu::BindGroup; 2],
}

pub struct TemporalAntialias {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    uniforms: wgpu::Buffer,
    history: Option<History>,
    /// Which history texture holds the last resolve.
    latest: usize,
    /// Frames resolved since the history was last reset (0: none, so the
    /// next frame is drawn without jitter and passed through).
    frames: u64,
    /// Frames the history holds of the view as it is now (since the camera
    /// or the time last changed).
    since_change: u64,
    /// Last resolved frame's view-projection, without jitter, and time.
    last_view_proj: Mat4,
    last_time: f64,
}

impl TemporalAntialias {
    /// Whether `scene`'s frames are anti-aliased: asked for, and the final
    /// image (debug views and the error view are drawn exact).
    pub fn enabled(scene: &Scene) -> bool {
        scene.render.antialias == Antialias::Temporal && scene.render.view == DebugView::Final
    }

    /// The sub-pixel offset the next frame of `scene` is drawn with.
    pub fn jitter_px(&self, scene: &Scene) -> Vec2 {
        if Self::enabled(scene) { antialias::jitter_px(self.frames) } else { Vec2::ZERO }
    }

    /// The next frame starts the history again (drawn without jitter).
    pub fn reset(&mut self) {
        self.frames = 0;
    }
}

impl Technique for TemporalAntialias {
    fn create(shared: &Shared, _scene: &Scene) -> Result<Self, crate::error::RenderError> {
        let device = &shared.device;
        let fs = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("antialias"),
            entries: &[
                storage_entry(0, fs, true),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(2, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(3, fs, wgpu::TextureViewDimension::D2, false),
                sampler_entry(4, fs),
            ],
        });
        let module = shader(device, "antialias", &source());
        let pipeline = fullscreen_pipeline(device, "antialias", &module, &[&layout], HDR_FORMAT);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("antialias history"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        // Read as storage (resolve.wgsl says why).
        let size = std::mem::size_of::<AntialiasUniforms>() as u64;
        let uniforms = storage_buffer(device, "antialias", size, wgpu::BufferUsages::empty());
        Ok(TemporalAntialias {
            layout,
            pipeline,
            sampler,
            uniforms,
            history: None,
            latest: 0,
            frames: 0,
            since_change: 0,
            last_view_proj: Mat4::IDENTITY,
            last_time: f64::NAN,
        })
    }

    fn set_scene(
        &mut self,
        _shared: &Shared,
        old: &Scene,
        new: &Scene,
    ) -> Result<bool, crate::error::RenderError> {
        // What the history shows is no longer what the scene would draw.
        if old != new {
            self.reset();
        }
        Ok(false)
    }

    fn resize(&mut self, shared: &Shared, t: &Targets) {
        let device = &shared.device;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let textures = [0, 1].map(|i| {
            texture_2d(device, &format!("antialias history {i}"), t.size, HDR_FORMAT, usage)
        });
        let views = [0, 1].map(|i| textures[i].create_view(&Default::default()));
        let groups = [0, 1].map(|i| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("antialias"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.uniforms.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&t.hdr_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&views[i]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&t.depth_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                ],
            })
        });
        self.history = Some(History { textures, views, groups });
        self.reset();
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        if frame.output.is_none() || !Self::enabled(frame.scene) {
            return;
        }
        let now = frame.plan.matrices.unjittered;
        let still_camera = now == self.last_view_proj;
        let time_still = frame.plan.time == self.last_time;
        let settled = still_camera && time_still && self.frames > 0;
        // A still camera reprojects exactly onto itself.
        let reprojection =
            if still_camera { Mat4::IDENTITY } else { self.last_view_proj * now.inverse() };
        let u = AntialiasUniforms {
            reprojection: reprojection.to_cols_array_2d(),
            has_history: u32::from(self.frames > 0),
            min_share: antialias::min_share(if settled { self.since_change } else { self.frames }),
            time_still: u32::from(time_still),
            settled: u32::from(settled),
        };
        self.since_change = if settled { self.since_change + 1 } else { 1 };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if stage != Stage::Output || frame.output.is_none() {
            return;
        }
        if !Self::enabled(frame.scene) {
            self.reset();
            return;
        }
        let Some(h) = &self.history else { return };
        let targets = frame.targets();
        let write = 1 - self.latest;
        let writes = timer.and_then(|t| t.render_writes("antialias"));
        let group = &h.groups[self.latest];
        draw_fullscreen(encoder, "antialias", &h.views[write], &self.pipeline, &[group], writes);
        copy_whole(encoder, &h.textures[write], &targets.hdr, targets.size);
        self.latest = write;
        self.frames += 1;
        self.last_view_proj = frame.plan.matrices.unjittered;
        self.last_time = frame.plan.time;
    }
}

/// Copy all of `from` into `to` (same size and format).
fn copy_whole(
    encoder: &mut wgpu::CommandEncoder,
    from: &wgpu::Texture,
    to: &wgpu::Texture,
    size: (u32, u32),
) {
    encoder.copy_texture_to_texture(
        from.as_image_copy(),
        to.as_image_copy(),
        wgpu::Extent3d { width: size.0.max(1), height: size.1.max(1), depth_or_array_layers: 1 },
    );
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_shader_uses_cores_constants() {
        let src = include_str!("resolve_colour.wgsl");
        let value = |name: &str| -> f32 {
            let line = src.lines().find(|l| l.contains(&format!("const {name}: f32 ="))).unwrap();
            line.split('=').nth(1).unwrap().trim().trim_end_matches(';').parse().unwrap()
        };
        assert_eq!(value("TAA_CURRENT_WEIGHT"), hydrolux_core::antialias::CURRENT_WEIGHT);
        assert_eq!(value("TAA_RESPONSIVE_WEIGHT"), hydrolux_core::antialias::RESPONSIVE_WEIGHT);
        assert_eq!(value("TAA_CLIP_SIGMAS"), hydrolux_core::antialias::CLIP_SIGMAS);
    }
}
