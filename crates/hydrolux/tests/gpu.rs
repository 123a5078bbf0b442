//! GPU tests on whatever adapter wgpu finds (Mesa lavapipe in CI, or the
//! one `WGPU_BACKEND` names): the suite in gpu_suite/suite.rs.

const BACKENDS: Option<hydrolux::wgpu::Backends> = None;

mod golden;

include!("gpu_suite/suite.rs");
