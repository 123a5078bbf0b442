//! The GPU suite (gpu_suite/) again on wgpu's OpenGL backend: Mesa
//! llvmpipe in CI, the adapter of machines without a Vulkan driver. Every
//! CPU twin and golden image holds there too.

const BACKENDS: Option<hydrolux::wgpu::Backends> = Some(hydrolux::wgpu::Backends::GL);

mod golden;

#[path = "gpu_suite/mod.rs"]
mod suite;
