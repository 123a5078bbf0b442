//! The GPU suite (gpu_suite/suite.rs) again on wgpu's OpenGL backend: Mesa
//! llvmpipe in CI, the adapter of machines without a Vulkan driver. Every
//! CPU twin and golden image holds there too.

const BACKENDS: Option<hydrolux::wgpu::Backends> = Some(hydrolux::wgpu::Backends::GL);

mod golden;

include!("gpu_suite/suite.rs");
