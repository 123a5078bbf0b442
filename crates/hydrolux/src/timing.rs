//! Per-pass GPU timing with timestamp queries (when the adapter has
//! TIMESTAMP_QUERY). Each pass asks for its begin/end slots by name; after
//! the frame, [`GpuTimer::read`] returns milliseconds per pass. The query
//! set grows with the passes: a frame that asks for more slots than it has
//! is timed in full from the next frame on.

pub struct GpuTimer {
    device: wgpu::Device,
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    names: Vec<&'static str>,
    capacity: u32,
    /// Passes the last frame asked to time (more than `names` when full).
    wanted: u32,
    period_ns: f32,
}

impl GpuTimer {
    /// Passes timed before the first growth.
    pub const INITIAL_PASSES: u32 = 16;

    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Self> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let (query_set, resolve, staging) = Self::buffers(device, Self::INITIAL_PASSES * 2);
        Some(GpuTimer {
            device: device.clone(),
            query_set,
            resolve,
            staging,
            names: Vec::new(),
            capacity: Self::INITIAL_PASSES * 2,
            wanted: 0,
            period_ns: queue.get_timestamp_period(),
        })
    }

    fn buffers(
        device: &wgpu::Device,
        capacity: u32,
    ) -> (wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer) {
        let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        let size = capacity as u64 * 8;
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamp resolve"),
            size,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamp readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        (query_set, resolve, staging)
    }

    /// Start a new frame's list of passes.
    pub fn begin_frame(&mut self) {
        if 2 * self.wanted > self.capacity {
            let capacity = (2 * self.wanted).next_power_of_two();
            (self.query_set, self.resolve, self.staging) = Self::buffers(&self.device, capacity);
            self.capacity = capacity;
        }
        self.names.clear();
        self.wanted = 0;
    }

    fn slot(&mut self, name: &'static str) -> Option<u32> {
        self.wanted += 1;
        let i = self.names.len() as u32;
        if 2 * i + 2 > self.capacity {
            return None;
        }
        self.names.push(name);
        Some(2 * i)
    }

    pub fn compute_writes(
        &mut self,
        name: &'static str,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let i = self.slot(name)?;
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(i),
            end_of_pass_write_index: Some(i + 1),
        })
    }

    pub fn render_writes(
        &mut self,
        name: &'static str,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = self.slot(name)?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(i),
            end_of_pass_write_index: Some(i + 1),
        })
    }

    /// Encode the resolve; call once after the frame's passes.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let n = self.names.len() as u32 * 2;
        if n == 0 {
            return;
        }
        encoder.resolve_query_set(&self.query_set, 0..n, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, n as u64 * 8);
    }

    /// Wait for the frame and return (pass, milliseconds).
    pub fn read(&self, device: &wgpu::Device) -> Vec<(&'static str, f64)> {
        if self.names.is_empty() {
            return Vec::new();
        }
        let bytes = crate::gpu_util::map_and_read(device, &self.staging);
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        self.names
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]);
                (*name, dt as f64 * self.period_ns as f64 / 1e6)
            })
            .collect()
    }
}
