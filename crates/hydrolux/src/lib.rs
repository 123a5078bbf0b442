//! Hydrolux: a real-time water renderer on wgpu. Bring your own
//! `wgpu::Device` and `Queue`, create a [`Renderer`] for your target's
//! format, and call [`Renderer::render`] with a view of any texture.
//!
//! ```no_run
//! # fn demo(device: &wgpu::Device, queue: &wgpu::Queue, view: &wgpu::TextureView) {
//! use hydrolux::{FrameInput, Renderer, core::scene::Scene};
//! let scene = Scene::load("ocean", &[]).unwrap();
//! let mut renderer = Renderer::new(device, queue, wgpu::TextureFormat::Rgba8UnormSrgb, &scene).unwrap();
//! let mut encoder = device.create_command_encoder(&Default::default());
//! renderer.render(&mut encoder, &FrameInput { target: view, size: (1280, 720), camera: scene.camera(), time: 0.0 });
//! queue.submit([encoder.finish()]);
//! # }
//! ```

pub mod capabilities;
pub mod context;
pub(crate) mod error;
pub(crate) mod error_view;
pub(crate) mod formats;
pub(crate) mod gpu_util;
pub mod headless;
pub(crate) mod history;
pub(crate) mod info;
pub(crate) mod meshes;
pub(crate) mod mips;
pub(crate) mod modes;
pub(crate) mod passes;
pub(crate) mod plan;
pub(crate) mod probe;
pub mod readback;
pub(crate) mod registry;
pub mod renderer;
pub(crate) mod shaders;
pub(crate) mod simulating;
pub(crate) mod simulation;
pub(crate) mod surface_kind;
pub(crate) mod targets;
pub(crate) mod technique;
pub(crate) mod timing;
pub(crate) mod uniforms;

pub use capabilities::Capabilities;
pub use context::{ContextError, GpuContext};
pub use error::{OceanTooLarge, RenderError, catch_gpu_errors, gpu_error_line};
pub use hydrolux_core as core;
pub use info::{DumpData, DumpKind, DumpShape};
pub use probe::{AntialiasQuery, SeaBrdfQuery};
pub use registry::{dump_kinds, simulation_names, technique_names};
pub use renderer::{FrameInput, Renderer};
pub use simulation::liquid::readback::{
    LiquidBench, LiquidReadback, LiquidSurfaceReadback, ScreenMeshReadback,
};
pub use simulation::liquid::screen_space::ScreenSpaceReadback;
pub use simulation::liquid::{LiquidParticle, SolveState};
pub use simulation::ocean::largest_ocean_resolution;
pub use simulation::ripples::readback::RippleField;
pub use simulation::whitewater::readback::{FoamDump, ParticleCounts};
pub use wgpu;
