//! What can go wrong building or feeding the renderer: one error type for
//! the library's callers, each variant a one-line message naming the value.

use hydrolux_core::geometry::load::AssetError;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    OceanTooLarge(#[from] OceanTooLarge),
    #[error(transparent)]
    Asset(#[from] AssetError),
    #[error("cannot update the heightfield: {0}")]
    Heightfield(String),
    /// The adapter lacks something every frame needs.
    #[error("{0}")]
    Unsupported(String),
    /// wgpu reported a validation, out-of-memory or internal error.
    #[error("GPU error while {during}: {message}")]
    Gpu { during: String, message: String },
}

#[derive(Debug, thiserror::Error)]
#[error(
    "ocean.resolution = {n} with {cascades} cascades needs a {need_mib} MiB GPU buffer, but this device allows {max_mib} MiB: \
     lower ocean.resolution or ocean.cascades"
)]
pub struct OceanTooLarge {
    pub n: u32,
    pub cascades: u32,
    pub need_mib: u64,
    pub max_mib: u64,
}

/// wgpu's error as one line: its chain of causes ("In Device::create_render_pipeline,
/// label = 'x'", "Color state [0] is invalid", …) joined by ": ".
pub fn gpu_error_line(error: &wgpu::Error) -> String {
    let text = match error {
        wgpu::Error::OutOfMemory { .. } => return "out of GPU memory".into(),
        other => other.to_string(),
    };
    let parts: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && *l != "Caused by:" && *l != "Validation Error")
        .collect();
    if parts.is_empty() { text.trim().to_string() } else { parts.join(": ") }
}

/// Run `f` inside validation, out-of-memory and internal error scopes;
/// wgpu's first error becomes [`RenderError::Gpu`] (`during` says what
/// was being done) instead of wgpu's default panic. On the web the scopes
/// resolve asynchronously, so there the device's uncaptured-error handler
/// reports instead.
pub fn catch_gpu_errors<T>(
    device: &wgpu::Device,
    during: impl FnOnce() -> String,
    f: impl FnOnce() -> Result<T, RenderError>,
) -> Result<T, RenderError> {
    #[cfg(target_arch = "wasm32")]
    {
        let _ = (device, during);
        f()
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let scopes = [
            wgpu::ErrorFilter::Validation,
            wgpu::ErrorFilter::OutOfMemory,
            wgpu::ErrorFilter::Internal,
        ]
        .map(|filter| device.push_error_scope(filter));
        let value = f();
        // Pop innermost first; the first error is the cause of any later one.
        let mut first = None;
        for scope in scopes.into_iter().rev() {
            if let Some(e) = pollster::block_on(scope.pop()) {
                first.get_or_insert(e);
            }
        }
        match first {
            Some(e) => Err(RenderError::Gpu { during: during(), message: gpu_error_line(&e) }),
            None => value,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wgpu_validation_error_reads_as_one_line() {
        let e = wgpu::Error::Validation {
            source: Box::new(std::fmt::Error),
            description: "Validation Error\n\nCaused by:\n  In Device::create_render_pipeline, label = 'x'\n    \
                          Color state [0] is invalid\n      Format Rgba32Float is not renderable\n"
                .into(),
        };
        assert_eq!(
            gpu_error_line(&e),
            "In Device::create_render_pipeline, label = 'x': Color state [0] is invalid: \
             Format Rgba32Float is not renderable"
        );
        let r = RenderError::Gpu {
            during: "creating the godrays technique".into(),
            message: gpu_error_line(&e),
        };
        assert!(!r.to_string().contains('\n'));
    }
}
