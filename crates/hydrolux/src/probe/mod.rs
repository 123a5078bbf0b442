//! GPU queries: the surface exactly as the renderer samples it, at any
//! points (heights for buoyancy, and the GPU side of the CPU-twin tests), and
//! the sky cube map in any direction.

use crate::gpu_util::*;
use crate::shaders;
use hydrolux_core::waves::SurfaceSample;
use wgpu::util::DeviceExt;

pub fn source() -> String {
    shaders::compose("", include_str!("probe.wgsl"))
}

pub struct ProbePass {
    layout: wgpu::BindGroupLayout,
    /// The surface model the pipelines are specialised to, as the renderer's are.
    model: crate::surface_kind::SurfaceKind,
    surface: wgpu::ComputePipeline,
    sky: wgpu::ComputePipeline,
    fresnel: wgpu::ComputePipeline,
    sea_brdf: wgpu::ComputePipeline,
    spray: wgpu::ComputePipeline,
    antialias: wgpu::ComputePipeline,
}

impl ProbePass {
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("probe io"),
            entries: &[storage_entry(0, cs, true), storage_entry(1, cs, false)],
        });
        Self::with_layout(device, [globals, surface], layout, model)
    }

    fn with_layout(
        device: &wgpu::Device,
        [globals, surface]: [&wgpu::BindGroupLayout; 2],
        layout: wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
    ) -> Self {
        let module = shader(device, "probe", &source());
        let constants = crate::surface_kind::specialised_to(model);
        let p = |entry| {
            let layouts = [globals, surface, &layout];
            compute_pipeline_with(device, entry, &module, entry, &layouts, &constants)
        };
        ProbePass {
            surface: p("probe_surface"),
            sky: p("probe_sky"),
            fresnel: p("probe_fresnel"),
            sea_brdf: p("probe_sea_brdf"),
            spray: p("probe_spray"),
            antialias: p("probe_antialias"),
            model,
            layout,
        }
    }

    /// Pipelines for another surface model.
    pub fn specialise(
        &mut self,
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
    ) {
        if model != self.model {
            *self = Self::with_layout(device, [globals, surface], self.layout.clone(), model);
        }
    }

    fn run(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        pipeline: &wgpu::ComputePipeline,
        groups: [&wgpu::BindGroup; 2],
        points: &[[f32; 4]],
    ) -> Vec<[f32; 12]> {
        if points.is_empty() {
            return Vec::new();
        }
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe points"),
            contents: bytemuck::cast_slice(points),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (points.len() * 48) as u64;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe results"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let io = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("probe io"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: output.as_entire_binding() },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, groups[0], &[]);
            pass.set_bind_group(1, groups[1], &[]);
            pass.set_bind_group(2, &io, &[]);
            pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
        }
        queue.submit([encoder.finish()]);
        bytemuck::cast_slice(&read_buffer(device, queue, &output, size)).to_vec()
    }

    pub fn surface(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        points: &[[f32; 2]],
    ) -> Vec<SurfaceSample> {
        let pts: Vec<[f32; 4]> = points.iter().map(|p| [p[0], p[1], 0.0, 0.0]).collect();
        self.run(device, queue, &self.surface, groups, &pts)
            .into_iter()
            .map(|r| SurfaceSample {
                displacement: [r[0], r[1], r[2]],
                slope: [r[4], r[5]],
                dxx: r[6],
                dzz: r[7],
                dxz: r[8],
            })
            .collect()
    }

    /// Fresnel reflectance as the shaders compute it for (cos θi, n1, n2), in
    /// every mode: [exact, Schlick, Jensen–Goliáš, power (the scene's q)].
    pub fn fresnel(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        queries: &[(f32, f32, f32)],
    ) -> Vec<[f32; 4]> {
        let pts: Vec<[f32; 4]> = queries.iter().map(|q| [q.0, q.1, q.2, 0.0]).collect();
        self.run(device, queue, &self.fresnel, groups, &pts)
            .into_iter()
            .map(|r| [r[0], r[1], r[2], r[3]])
            .collect()
    }

    /// The far sea's BRDF as the water shades it (`shaders/sea_brdf.wgsl`)
    /// for each (v, l, mean slope, slope variance) with the Fresnel `mode`
    /// (0 exact, 1 Schlick, 2 Jensen–Goliáš, 3 power) and index `ior`:
    /// [mean Fresnel, mirrored direction (xyz), glitter per unit irradiance].
    pub fn sea_brdf(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        queries: &[SeaBrdfQuery],
    ) -> Vec<[f32; 5]> {
        let pts: Vec<[f32; 4]> = queries
            .iter()
            .flat_map(|q| {
                [
                    [q.view[0], q.view[1], q.view[2], q.mode as f32],
                    [q.sun[0], q.sun[1], q.sun[2], q.ior],
                    [q.mean_slope[0], q.mean_slope[1], q.variance[0], q.variance[1]],
                ]
            })
            .collect();
        self.run(device, queue, &self.sea_brdf, groups, &pts)
            .into_iter()
            .step_by(3)
            .map(|r| [r[0], r[1], r[2], r[3], r[4]])
            .collect()
    }

    /// A spray parcel's look at quad point `at` (and a view whose vertical
    /// is `at[1]`): [opacity, optical depth, asymmetry, sky share].
    pub fn spray(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        queries: &[([f32; 2], hydrolux_core::whitewater::spray_look::SprayShape, u32)],
    ) -> Vec<[f32; 4]> {
        let pts: Vec<[f32; 4]> = queries
            .iter()
            .flat_map(|(at, s, id)| {
                [
                    [at[0], at[1], s.parcel, s.pixel],
                    [s.streak, s.cover, s.drops, f32::from_bits(*id)],
                ]
            })
            .collect();
        self.run(device, queue, &self.spray, groups, &pts)
            .into_iter()
            .step_by(2)
            .map(|r| [r[0], r[1], r[2], r[3]])
            .collect()
    }

    /// The temporal resolve of each query.
    pub fn antialias(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        queries: &[AntialiasQuery],
    ) -> Vec<[f32; 3]> {
        let pts: Vec<[f32; 4]> = queries
            .iter()
            .flat_map(|q| {
                let h = q.history;
                let settled = h.is_some_and(|h| h.settled);
                let last = h.map_or([0.0; 4], |h| {
                    let share = hydrolux_core::antialias::min_share(h.frames);
                    [h.colour.x, h.colour.y, h.colour.z, share]
                });
                let colour = move |(k, c): (usize, &glam::Vec3)| {
                    let w = match k {
                        0 => f32::from(u8::from(settled)),
                        4 => q.trust,
                        _ => 0.0,
                    };
                    [c.x, c.y, c.z, w]
                };
                q.neighbourhood.iter().enumerate().map(colour).chain(std::iter::once(last))
            })
            .collect();
        self.run(device, queue, &self.antialias, groups, &pts)
            .into_iter()
            .step_by(10)
            .map(|r| [r[0], r[1], r[2]])
            .collect()
    }

    pub fn sky(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        groups: [&wgpu::BindGroup; 2],
        dirs: &[[f32; 3]],
        level: f32,
    ) -> Vec<[f32; 3]> {
        let pts: Vec<[f32; 4]> = dirs.iter().map(|d| [d[0], d[1], d[2], level]).collect();
        self.run(device, queue, &self.sky, groups, &pts)
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect()
    }
}

/// One resolve of the temporal anti-aliasing, as
/// `hydrolux_core::antialias::resolve` takes it.
#[derive(Clone, Copy, Debug)]
pub struct AntialiasQuery {
    /// The new frame's 3×3 neighbourhood, the pixel at index 4.
    pub neighbourhood: [glam::Vec3; 9],
    pub history: Option<hydrolux_core::antialias::History>,
    /// The pixel's trust in its history (the HDR alpha).
    pub trust: f32,
}

/// One evaluation of the far sea's BRDF: towards the eye, towards the sun,
/// the pixel's slope statistics, the Fresnel formula and the water's index.
#[derive(Clone, Copy, Debug)]
pub struct SeaBrdfQuery {
    pub view: [f32; 3],
    pub sun: [f32; 3],
    pub mean_slope: [f32; 2],
    pub variance: [f32; 2],
    pub mode: u32,
    pub ior: f32,
}

fn no_surface(scene: &hydrolux_core::scene::Scene) -> Option<&'static str> {
    (scene.water.model == hydrolux_core::scene::WaterModel::None)
        .then_some("the scene has no water surface (water.model = \"none\")")
}

/// The surface as rendered on the largest cascade's N×N grid (x_j = j·L/N,
/// row = z, col = x), before horizontal displacement: its height, its
/// displacement (xyz), its normal (xyz) and its Jacobian (`readback.rs`
/// reads them: the FFT's float32 output, or this probe).
pub(crate) const SURFACE_DUMPS: &[crate::info::DumpKind] = &[
    crate::info::DumpKind {
        name: "height",
        shape: crate::info::DumpShape::Grid,
        missing: no_surface,
    },
    crate::info::DumpKind {
        name: "displacement",
        shape: crate::info::DumpShape::Grid,
        missing: no_surface,
    },
    crate::info::DumpKind {
        name: "normals",
        shape: crate::info::DumpShape::Grid,
        missing: no_surface,
    },
    crate::info::DumpKind {
        name: "jacobian",
        shape: crate::info::DumpShape::Grid,
        missing: no_surface,
    },
];

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "probe",
    dumps: SURFACE_DUMPS,
    shaders: || vec![("probe".to_string(), source())],
    uniforms: Vec::new,
};
