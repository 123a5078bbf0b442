//! Getting a device: headless (CLI render/bench, tests) or for a window.
//! The features Hydrolux uses are optional except what every WebGPU adapter
//! has; timestamp queries are enabled when the adapter offers them.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum ContextError {
    #[error(
        "no GPU adapter found: install your GPU's Vulkan/Metal/DX12 driver, or Mesa's software Vulkan \
         (Debian/Ubuntu: apt-get install mesa-vulkan-drivers)"
    )]
    NoAdapter,
    #[error(
        "no GPU adapter found for WGPU_BACKEND={0}: try another backend, or unset it to let wgpu choose"
    )]
    NoAdapterForBackend(String),
    #[error(
        "WGPU_BACKEND={0:?} is not a backend: use vulkan, metal, dx12 or gl (several separated by commas), or unset it"
    )]
    BadBackend(String),
    #[error("the GPU adapter refused to create a device: {0}")]
    Device(String),
}

/// The instance flags Hydrolux's own devices use: wgpu's, less its
/// validation of indirect calls (which adds a dispatch before every one:
/// about a fifth of the liquid's step on lavapipe) unless
/// WGPU_VALIDATION_INDIRECT_CALL asks for it. Every indirect call Hydrolux
/// records has arguments its own kernels write within the limits: the
/// liquid's solve (its cells' workgroups in rows, `set_running`) and the
/// white water's particles (at most 65535 workgroups, its capacity).
pub fn instance_flags(flags: wgpu::InstanceFlags) -> wgpu::InstanceFlags {
    if std::env::var_os("WGPU_VALIDATION_INDIRECT_CALL").is_some() {
        return flags;
    }
    flags - wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL
}

/// Check `WGPU_BACKEND` (which wgpu would silently ignore when it names no
/// backend); its value, when set.
pub fn backend_from_env() -> Result<Option<String>, ContextError> {
    let Ok(value) = std::env::var("WGPU_BACKEND") else { return Ok(None) };
    let known = ["vulkan", "vk", "dx12", "d3d12", "metal", "mtl", "opengl", "gles", "gl"];
    let ok = value.split(',').all(|b| known.contains(&b.trim().to_lowercase().as_str()));
    if value.trim().is_empty() || !ok {
        return Err(ContextError::BadBackend(value));
    }
    Ok(Some(value))
}

/// A device and queue with the adapter they came from.
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// The first wgpu error no error scope caught (wgpu would panic).
    uncaught: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

/// Features Hydrolux turns on when the adapter has them.
pub fn optional_features(adapter: &wgpu::Adapter) -> wgpu::Features {
    // Float depth with stencil keeps reversed-Z precision for the main view.
    adapter.features() & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::DEPTH32FLOAT_STENCIL8)
}

/// Device limits: the adapter's own storage-buffer and texture limits, so
/// large FFT sizes work where the hardware allows them.
pub fn required_limits(adapter: &wgpu::Adapter) -> wgpu::Limits {
    let a = adapter.limits();
    wgpu::Limits {
        max_storage_buffer_binding_size: a.max_storage_buffer_binding_size,
        max_buffer_size: a.max_buffer_size,
        max_texture_dimension_2d: a.max_texture_dimension_2d,
        max_compute_workgroup_storage_size: a.max_compute_workgroup_storage_size,
        ..wgpu::Limits::default()
    }
}

impl GpuContext {
    /// A device with no window. Honours WGPU_BACKEND / WGPU_ADAPTER_NAME.
    pub fn headless() -> Result<Self, ContextError> {
        Self::headless_on(None)
    }

    /// A device with no window on one of `backends` (None: WGPU_BACKEND's
    /// choice, else wgpu's).
    pub fn headless_on(backends: Option<wgpu::Backends>) -> Result<Self, ContextError> {
        let backend = match backends {
            Some(b) => Some(format!("{b:?}")),
            None => backend_from_env()?,
        };
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        descriptor.flags = instance_flags(descriptor.flags);
        if let Some(b) = backends {
            descriptor.backends = b;
        }
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            compatible_surface: None,
            force_fallback_adapter: false,
            apply_limit_buckets: false,
        }))
        .map_err(|_| match backend {
            Some(b) => ContextError::NoAdapterForBackend(b),
            None => ContextError::NoAdapter,
        })?;
        Self::from_adapter(instance, adapter)
    }

    /// A device on a chosen adapter (the viewer picks one compatible with its window).
    pub fn from_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, ContextError> {
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("hydrolux"),
            required_features: optional_features(&adapter),
            required_limits: required_limits(&adapter),
            ..Default::default()
        }))
        .map_err(|e| ContextError::Device(e.to_string()))?;
        // wgpu's default handler panics; keep the first error for the caller.
        let uncaught = std::sync::Arc::new(std::sync::Mutex::new(None));
        let sink = uncaught.clone();
        device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            if let Ok(mut slot) = sink.lock() {
                slot.get_or_insert_with(|| crate::error::gpu_error_line(&e));
            }
        }));
        Ok(GpuContext { instance, adapter, device, queue, uncaught })
    }

    /// The first wgpu error that no [`crate::Renderer`] call caught (the
    /// viewer's own drawing, say), taken: check it after each frame.
    pub fn take_error(&self) -> Option<String> {
        self.uncaught.lock().ok()?.take()
    }

    pub fn has_timestamps(&self) -> bool {
        self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
    }
}
