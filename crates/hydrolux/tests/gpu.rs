//! GPU tests on whatever adapter wgpu finds (Mesa lavapipe in CI, or the
//! one `WGPU_BACKEND` names): the suite in gpu_suite/.

const BACKENDS: Option<hydrolux::wgpu::Backends> = None;

mod golden;

#[path = "gpu_suite/mod.rs"]
mod suite;
