//! Ray tracing of water volumes on the GPU (seed 003 §3.3.1, after Baboud
//! & Décoret 2006; `water.method = "raytrace"`): the ground and the water
//! surface as heightfields with min/max pyramids, which the water shader
//! traces its reflected and refracted rays against exactly
//! (`shaders/heightfield_trace.wgsl`). The ground's heightfield is built
//! once per scene on the CPU (hydrolux-core `Scene::ground_heightfield`,
//! `raytrace::MinMaxPyramid`, uploaded as is); the water's is resampled
//! from the displaced surface over a window around the camera each frame
//! (`resample.wgsl`) and reduced into its pyramid (`raytrace.wgsl`). The CPU
//! twin of everything here is hydrolux-core `raytrace`.

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::shaders;
use crate::uniforms::uniform;
use hydrolux_core::raytrace::{Heightfield, MinMaxPyramid};
use hydrolux_core::scene::{Pattern, Scene, WaterMethod};

uniform! { Heightfield;
    /// WGSL `Heightfield` (shaders/heightfield_trace.wgsl).
    pub(crate) struct HeightfieldUniforms {
        pub origin: [f32; 2],
        pub spacing: f32,
        pub outside: f32,
        pub cells: u32,
        pub samples: u32,
        pub top_level: u32,
        pub max_steps: u32,
        pub first_sample: u32,
        pub first_bound: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

uniform! { TracedParams;
    /// WGSL `TracedParams` (passes/raytrace/traced.wgsl).
    pub(crate) struct TracedUniforms {
        pub ground: HeightfieldUniforms,
        pub water: HeightfieldUniforms,
        pub ground_albedo: [f32; 3],
        pub ground_tile_size: f32,
        pub ground_pattern_color: [f32; 3],
        pub ground_pattern: u32,
        pub has_ground: u32,
        pub reach: f32,
        pub object_count: u32,
        /// The ground's specular parameters (`hydrolux_core::pbr::Surface`).
        pub ground_roughness: f32,
        pub caustic_corner: [f32; 2],
        pub caustic_cell: f32,
        pub caustic_cells: u32,
        pub emission_origin: [f32; 2],
        pub emission_spacing: f32,
        pub photon_energy: f32,
        pub emission_count: [u32; 2],
        pub ground_metalness: f32,
        pub ground_specular: f32,
    }
}

uniform! { TracedObject;
    /// An object traced as its primitive or its mesh's tree (WGSL
    /// `TracedObject`, a storage record checked by name like a uniform):
    /// the inverse of its transform, its shape, its material.
    pub(crate) struct TracedObject {
        pub inverse_model: [[f32; 4]; 4],
        pub albedo: [f32; 3],
        /// The pattern's tile size (m).
        pub tile_size: f32,
        /// The pattern's second colour, and the pattern (`modes::pattern`).
        pub pattern_color: [f32; 3],
        pub pattern: u32,
        /// 0 sphere, 1 box, 2 cylinder (unit primitives), 3 plane, 4 mesh.
        pub shape: u32,
        /// A mesh's first node and first triangle corner in the traced
        /// meshes' buffer (vec4 indices; [`TracedMeshes`]).
        pub mesh_nodes: u32,
        pub mesh_triangles: u32,
        /// The specular parameters (`hydrolux_core::pbr::Surface`).
        pub roughness: f32,
        pub metalness: f32,
        pub specular: f32,
        /// Its place among the frame's ambient occluders, or `NO_OCCLUDER`.
        pub occluder: u32,
        pub _pad1: u32,
    }
}

/// Shape codes of `TracedObject.shape` (the WGSL `PRIMITIVE_*`, generated).
use hydrolux_core::coupling::{
    PRIMITIVE_BOX as SHAPE_BOX, PRIMITIVE_CYLINDER as SHAPE_CYLINDER, PRIMITIVE_MESH as SHAPE_MESH,
    PRIMITIVE_PLANE as SHAPE_PLANE, PRIMITIVE_SPHERE as SHAPE_SPHERE,
};

fn pattern_code(p: Pattern) -> u32 {
    crate::modes::pattern(p)
}

/// The traced meshes' trees and triangles, one `vec4<f32>` array
/// (`traced_meshes` in WGSL): each mesh's nodes as two vec4s (box min and
/// the first triangle or second child as bits; box max and the leaf's
/// triangle count as bits), then its triangles as three corners. Each mesh
/// file once, however many objects show it.
#[derive(Default)]
pub(crate) struct TracedMeshes {
    pub data: Vec<[f32; 4]>,
    /// Mesh name → its first node and first corner (vec4 indices).
    at: std::collections::HashMap<String, (u32, u32)>,
}

impl TracedMeshes {
    /// Where `name`'s tree is, built and appended the first time.
    fn place(
        &mut self,
        name: &str,
        mesh: impl FnOnce() -> Result<hydrolux_core::geometry::Mesh, RenderError>,
    ) -> Result<(u32, u32), RenderError> {
        if let Some(&at) = self.at.get(name) {
            return Ok(at);
        }
        let mesh = mesh()?;
        let bvh = hydrolux_core::raytrace::bvh::MeshBvh::build(&mesh.positions, &mesh.indices);
        let nodes = self.data.len() as u32;
        for n in &bvh.nodes {
            self.data.push([n.min.x, n.min.y, n.min.z, f32::from_bits(n.first_or_next)]);
            self.data.push([n.max.x, n.max.y, n.max.z, f32::from_bits(n.count)]);
        }
        let triangles = self.data.len() as u32;
        for t in &bvh.triangles {
            self.data.extend(t.iter().map(|p| [p.x, p.y, p.z, 0.0]));
        }
        self.at.insert(name.to_string(), (nodes, triangles));
        Ok((nodes, triangles))
    }
}

/// The scene's objects rays can be traced against: opaque boxes, spheres,
/// cylinders, planes (their unit primitives, transformed) and meshes
/// (their trees), by `[[objects]]` index. Refractive objects are not traced.
fn traceable(scene: &Scene) -> Result<(Vec<(usize, TracedObject)>, TracedMeshes), RenderError> {
    use hydrolux_core::scene::Primitive;
    let mut meshes = TracedMeshes::default();
    let mut out = Vec::new();
    let slots = scene.occluder_slots();
    for (i, o) in scene.objects.iter().enumerate().filter(|(_, o)| o.material.ior <= 0.0) {
        let (mut mesh_nodes, mut mesh_triangles) = (0, 0);
        let shape = if o.mesh.is_empty() {
            match o.primitive {
                Primitive::Box => SHAPE_BOX,
                Primitive::Sphere => SHAPE_SPHERE,
                Primitive::Cylinder => SHAPE_CYLINDER,
                Primitive::Plane => SHAPE_PLANE,
            }
        } else {
            (mesh_nodes, mesh_triangles) =
                meshes.place(&o.mesh, || Ok(scene.object_mesh_file(o)?))?;
            SHAPE_MESH
        };
        let m = &o.material;
        let object = TracedObject {
            inverse_model: Scene::object_transform(o).inverse().to_cols_array_2d(),
            albedo: m.albedo,
            tile_size: m.tile_size,
            pattern_color: m.pattern_color,
            pattern: pattern_code(m.pattern),
            shape,
            mesh_nodes,
            mesh_triangles,
            roughness: m.roughness,
            metalness: m.metalness,
            specular: m.specular,
            occluder: slots[i],
            _pad1: 0,
        };
        out.push((i, object));
    }
    Ok((out, meshes))
}

/// Side of the water's heightfield window (m): 64 m around the camera
/// (where a reflected ray can meet the next wave; beyond, the water is
/// traced as its mean level), in `water.trace_resolution` cells.
pub const WATER_WINDOW_M: f32 = 64.0;
/// The furthest a traced ray goes (m).
pub const TRACE_REACH: f32 = 2000.0;

pub fn resample_source() -> String {
    shaders::compose("", include_str!("resample.wgsl"))
}

pub fn source() -> String {
    shaders::compose("", include_str!("raytrace.wgsl"))
}

pub fn caustics_source() -> String {
    shaders::compose("", include_str!("caustics.wgsl"))
}

/// Where the water's window of `cells` cells lies for a camera at (x, z):
/// whole cells, centred.
pub fn water_window(camera_xz: [f32; 2], cells: u32) -> [f32; 2] {
    let cell = WATER_WINDOW_M / cells as f32;
    camera_xz.map(|c| (c / cell).round() * cell - 0.5 * WATER_WINDOW_M)
}

/// Entries of a pyramid with `side` cells at level 0 (all its levels).
fn pyramid_entries(side: u32) -> u32 {
    (side * side - 1) / 3 * 4 + 1
}

/// The traced heightfields and what builds them.
pub struct Traced {
    pub method: WaterMethod,
    uniforms: TracedUniforms,
    buffer: wgpu::Buffer,
    /// Every sample, the ground's then the water's (the bounds live in the
    /// bind groups alone).
    heights: wgpu::Buffer,
    /// The water shader's group 3.
    pub group: wgpu::BindGroup,
    /// Traced objects (by `[[objects]]` index) and their GPU copy.
    objects: Vec<(usize, TracedObject)>,
    /// Whether an object moved since the caustics were last traced.
    objects_moved: bool,
    objects_buffer: wgpu::Buffer,
    resample: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
    compute_group: wgpu::BindGroup,
    /// Per pyramid level: which level `reduce` writes.
    level_groups: Vec<wgpu::BindGroup>,
    probe: wgpu::ComputePipeline,
    probe_layout: wgpu::BindGroupLayout,
    caustics: TracedCaustics,
}

/// The photons traced to the ground (`caustics.wgsl`; twin hydrolux-core
/// `raytrace::caustics`).
struct TracedCaustics {
    /// Cells per side of the window (0: no traced caustics).
    cells: u32,
    /// How deep the ground goes under the mean level (m): how far up-sun
    /// photons must start.
    depth: f32,
    /// The light the traced ground reads, and the photons' fixed-point sums.
    light: wgpu::Buffer,
    /// Clear, trace, resolve: made only where there are traced caustics
    /// (the trace walks every object, meshes too: compiled for nothing in
    /// a projective scene, it held ~23 MB on lavapipe).
    pipelines: Option<[wgpu::ComputePipeline; 3]>,
    group: wgpu::BindGroup,
    /// The window and emission last traced (not again while they, the
    /// surface and the objects stay).
    last: Option<([f32; 4], [f32; 4])>,
}

impl Traced {
    /// The water shader's group 3: the uniforms, the heights, the bounds,
    /// the traced objects and the light the photons left on the ground.
    pub fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
        let fs = wgpu::ShaderStages::FRAGMENT;
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traced"),
            entries: &[
                uniform_entry(0, fs),
                storage_entry(1, fs, true),
                storage_entry(2, fs, true),
                storage_entry(3, fs, true),
                storage_entry(4, fs, true),
                storage_entry(5, fs, true),
            ],
        })
    }

    /// What `scene` traces (small stand-ins for the projective method, whose
    /// pipelines bind them without reading them).
    pub fn new(
        shared: &crate::technique::Shared,
        scene: &Scene,
        layout: &wgpu::BindGroupLayout,
    ) -> Result<Self, RenderError> {
        let (device, queue) = (&shared.device, &shared.queue);
        let method = scene.water.method;
        let tracing = method == WaterMethod::Raytrace;
        let ground = if tracing { scene.ground_heightfield()? } else { None };
        let has_ground = ground.is_some();
        let ground = ground
            .unwrap_or_else(|| Heightfield::sampled([0.0, 0.0], 1.0, 2, -1.0e6, |_, _| -1.0e6));
        let pyramid = MinMaxPyramid::new(&ground);
        let ground_side = pyramid.side as u32;
        let water_side = if tracing { scene.water.trace_resolution } else { 2 };
        let water_cell = WATER_WINDOW_M / water_side as f32;
        let steps = scene.water.trace_steps;
        let water_n = water_side + 1;
        // Heights: the ground's samples, then the water's; bounds likewise.
        let ground_samples = ground.heights.len() as u32;
        let ground_bounds = pyramid_entries(ground_side);
        let heights_len = ground_samples + water_n * water_n;
        let bounds_len = ground_bounds + pyramid_entries(water_side);
        let storage = |label: &str, bytes: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let heights = storage("traced heights", 4 * heights_len as u64);
        // Traced caustics: over the caustic maps' cells, when there are
        // caustics and ground to receive them.
        let caustic_cells = if tracing && has_ground && scene.has_caustics() {
            scene.caustics.map_resolution
        } else {
            0
        };
        let caustic_len = 4 * (caustic_cells * caustic_cells).max(1) as u64;
        let ground_light = storage("traced ground light", caustic_len);
        let photon_sum = storage("traced photon sums", caustic_len);
        let ground_depth = (-ground.range().0).max(0.0);
        let bounds = storage("traced bounds", 8 * bounds_len as u64);
        queue.write_buffer(&heights, 0, bytemuck::cast_slice(&ground.heights));
        let flat: Vec<[f32; 2]> = pyramid.levels.concat();
        debug_assert_eq!(flat.len() as u32, ground_bounds);
        queue.write_buffer(&bounds, 0, bytemuck::cast_slice(&flat));
        let material = &scene.floor.material;
        let pattern = pattern_code(material.pattern);
        let (objects, meshes) =
            if tracing { traceable(scene)? } else { (Vec::new(), TracedMeshes::default()) };
        let meshes_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("traced meshes"),
            size: (16 * meshes.data.len().max(1)) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if !meshes.data.is_empty() {
            queue.write_buffer(&meshes_buffer, 0, bytemuck::cast_slice(&meshes.data));
        }
        let objects_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("traced objects"),
            size: (objects.len().max(1) * std::mem::size_of::<TracedObject>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let gpu_objects: Vec<TracedObject> = objects.iter().map(|(_, o)| *o).collect();
        if !gpu_objects.is_empty() {
            queue.write_buffer(&objects_buffer, 0, bytemuck::cast_slice(&gpu_objects));
        }
        let uniforms = TracedUniforms {
            ground: HeightfieldUniforms {
                origin: ground.origin,
                spacing: ground.cell,
                outside: ground.outside,
                cells: ground_side,
                samples: ground.n as u32,
                top_level: ground_side.ilog2(),
                max_steps: steps,
                ..Default::default()
            },
            water: HeightfieldUniforms {
                spacing: water_cell,
                cells: water_side,
                samples: water_n,
                top_level: water_side.ilog2(),
                max_steps: steps,
                first_sample: ground_samples,
                first_bound: ground_bounds,
                ..Default::default()
            },
            ground_albedo: material.albedo,
            ground_tile_size: material.tile_size,
            ground_pattern_color: material.pattern_color,
            ground_pattern: pattern,
            has_ground: has_ground as u32,
            reach: TRACE_REACH,
            object_count: objects.len() as u32,
            ground_roughness: material.roughness,
            ground_metalness: material.metalness,
            ground_specular: material.specular,
            ..Default::default()
        };
        let buffer = uniform_buffer(device, "traced", &uniforms);
        fn whole(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("traced"),
            layout,
            entries: &[
                whole(0, &buffer),
                whole(1, &heights),
                whole(2, &bounds),
                whole(3, &objects_buffer),
                whole(4, &ground_light),
                whole(5, &meshes_buffer),
            ],
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traced compute"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, false),
                storage_entry(2, cs, false),
            ],
        });
        let level_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traced level"),
            entries: &[uniform_entry(0, cs)],
        });
        let probe_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traced probe"),
            entries: &[storage_entry(1, cs, true), storage_entry(2, cs, false)],
        });
        let constants =
            crate::surface_kind::specialised_to(crate::surface_kind::SurfaceKind::of(scene));
        let resample_module = shader(device, "traced resample", &resample_source());
        let resample = compute_pipeline_with(
            device,
            "traced resample",
            &resample_module,
            "resample",
            &[&compute_layout, &shared.layouts.surface],
            &constants,
        );
        let module = shader(device, "traced", &source());
        let reduce = compute_pipeline(
            device,
            "traced reduce",
            &module,
            "reduce",
            &[&compute_layout, &level_layout],
        );
        let probe = compute_pipeline(
            device,
            "traced probe",
            &module,
            "probe_rays",
            &[&compute_layout, &probe_layout],
        );
        let compute_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("traced compute"),
            layout: &compute_layout,
            entries: &[whole(0, &buffer), whole(1, &heights), whole(2, &bounds)],
        });
        let level_groups = (0..=water_side.ilog2())
            .map(|k| {
                let b = uniform_buffer(device, "traced level", &[k, 0, 0, 0]);
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("traced level"),
                    layout: &level_layout,
                    entries: &[whole(0, &b)],
                })
            })
            .collect();
        let caustic_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("traced caustics"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, true),
                storage_entry(2, cs, true),
                storage_entry(3, cs, true),
                storage_entry(4, cs, false),
                storage_entry(5, cs, false),
                storage_entry(6, cs, true),
            ],
        });
        let caustic_module = shader(device, "traced caustics", &caustics_source());
        let caustic_pipeline = |entry: &str| {
            let layouts = [&shared.layouts.frame_only, &shared.layouts.surface, &caustic_layout];
            compute_pipeline_with(device, entry, &caustic_module, entry, &layouts, &constants)
        };
        let caustics = TracedCaustics {
            cells: caustic_cells,
            depth: ground_depth,
            pipelines: (caustic_cells > 0).then(|| {
                ["caustic_clear", "caustic_trace", "caustic_resolve"].map(caustic_pipeline)
            }),
            group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("traced caustics"),
                layout: &caustic_layout,
                entries: &[
                    whole(0, &buffer),
                    whole(1, &heights),
                    whole(2, &bounds),
                    whole(3, &objects_buffer),
                    whole(4, &ground_light),
                    whole(5, &photon_sum),
                    whole(6, &meshes_buffer),
                ],
            }),
            light: ground_light,
            last: None,
        };
        Ok(Traced {
            caustics,
            objects_moved: false,
            method,
            uniforms,
            buffer,
            heights,
            group,
            objects,
            objects_buffer,
            resample,
            reduce,
            compute_group,
            level_groups,
            probe,
            probe_layout,
        })
    }

    /// Whether `scene` traces what this was built for.
    pub fn fits(&self, old: &Scene, new: &Scene) -> bool {
        new.water.method == self.method
            && (self.method == WaterMethod::Projective
                || (new.floor == old.floor
                    && new.water.model == old.water.model
                    && new.objects == old.objects
                    && new.caustics == old.caustics
                    && new.water.trace_resolution == old.water.trace_resolution
                    && new.water.trace_steps == old.water.trace_steps
                    && new.has_caustics() == old.has_caustics()))
    }

    /// Put the traced objects where they are now (moving bodies).
    pub fn move_objects(&mut self, queue: &wgpu::Queue, geometry: &crate::meshes::SceneGeometry) {
        if self.objects.is_empty() {
            return;
        }
        for (index, o) in &mut self.objects {
            if let Some(m) = geometry.object_model(*index) {
                let inverse = m.inverse().to_cols_array_2d();
                self.objects_moved |= inverse != o.inverse_model;
                o.inverse_model = inverse;
            }
        }
        let gpu: Vec<TracedObject> = self.objects.iter().map(|(_, o)| *o).collect();
        queue.write_buffer(&self.objects_buffer, 0, bytemuck::cast_slice(&gpu));
    }

    /// Resample the water around the camera and rebuild its pyramid, then
    /// trace the sun's photons to the ground (only when tracing).
    pub fn record(
        &mut self,
        frame: &crate::technique::FrameContext,
        encoder: &mut wgpu::CommandEncoder,
        mut timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        if self.method != WaterMethod::Raytrace {
            return;
        }
        let queue = &frame.shared.queue;
        let camera = frame.plan.camera.position;
        let cells = self.uniforms.water.cells;
        let origin = water_window([camera.x, camera.z], cells);
        self.uniforms.water.origin = origin;
        let caustics_due = self.plan_caustics(frame);
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&self.uniforms));
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("traced water"),
                timestamp_writes: timer
                    .as_deref_mut()
                    .and_then(|t| t.compute_writes("traced water")),
            });
            let n = cells + 1;
            pass.set_pipeline(&self.resample);
            pass.set_bind_group(0, &self.compute_group, &[]);
            pass.set_bind_group(1, &frame.bound.surface, &[]);
            pass.dispatch_workgroups(n.div_ceil(8), n.div_ceil(8), 1);
            pass.set_pipeline(&self.reduce);
            for (k, group) in self.level_groups.iter().enumerate() {
                let side = cells >> k;
                pass.set_bind_group(1, group, &[]);
                pass.dispatch_workgroups(side.div_ceil(8), side.div_ceil(8), 1);
            }
        }
        if !caustics_due {
            return;
        }
        let c = &self.caustics;
        let Some([clear, trace, resolve]) = &c.pipelines else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("traced caustics"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("traced caustics")),
        });
        pass.set_bind_group(0, &frame.shared.frame_only, &[]);
        pass.set_bind_group(1, &frame.bound.surface, &[]);
        pass.set_bind_group(2, &c.group, &[]);
        pass.set_pipeline(clear);
        pass.dispatch_workgroups((c.cells * c.cells).div_ceil(64), 1, 1);
        pass.set_pipeline(trace);
        let [nx, nz] = self.uniforms.emission_count;
        pass.dispatch_workgroups(nx.div_ceil(8), nz.div_ceil(8), 1);
        pass.set_pipeline(resolve);
        pass.dispatch_workgroups(c.cells.div_ceil(8), c.cells.div_ceil(8), 1);
    }

    /// Set the traced caustics' window and photons for this frame; whether
    /// they are to be traced again (the surface or the objects moved, the
    /// window moved, the maps are stale).
    fn plan_caustics(&mut self, frame: &crate::technique::FrameContext) -> bool {
        use hydrolux_core::raytrace::caustics::{Emission, window_for};
        let (scene, plan) = (frame.scene, frame.plan);
        let Some(layered) = plan.caustics.as_ref().filter(|_| self.caustics.cells > 0) else {
            self.set_caustic_window([0.0; 4]);
            self.caustics.last = None;
            return false;
        };
        let camera = plan.camera.position;
        let window = window_for(scene, [camera.x, camera.z]);
        let spacing = window.side() / scene.caustics.photons as f32;
        let emission = Emission::covering(
            &window,
            spacing,
            scene.sun_direction(),
            scene.water.ior,
            self.caustics.depth,
        );
        let w = [window.origin[0], window.origin[1], window.cell, window.m as f32];
        let e = [emission.origin[0], emission.origin[1], spacing, (spacing / window.cell).powi(2)];
        self.set_caustic_window(w);
        self.uniforms.emission_origin = emission.origin;
        self.uniforms.emission_spacing = spacing;
        self.uniforms.photon_energy = e[3];
        self.uniforms.emission_count = emission.count.map(|c| c as u32);
        let due = layered.due || self.objects_moved || self.caustics.last != Some((w, e));
        self.caustics.last = Some((w, e));
        self.objects_moved = false;
        due
    }

    /// The traced caustics' window (x, z of its corner, cell, cells per
    /// side; all 0: off).
    fn set_caustic_window(&mut self, w: [f32; 4]) {
        self.uniforms.caustic_corner = [w[0], w[1]];
        self.uniforms.caustic_cell = w[2];
        self.uniforms.caustic_cells = w[3] as u32;
    }

    /// The traced caustics' light per cell of their window (row = z), and
    /// the window (x, z of its corner, cell, cells per side); `None` when
    /// there are none.
    pub fn read_caustics(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<(Vec<f32>, [f32; 4])> {
        let c = &self.caustics;
        if c.cells == 0 || self.uniforms.caustic_cells == 0 {
            return None;
        }
        let n = (c.cells * c.cells) as usize;
        let bytes = read_buffer(device, queue, &c.light, 4 * n as u64);
        let u = &self.uniforms;
        let [x, z] = u.caustic_corner;
        let window = [x, z, u.caustic_cell, u.caustic_cells as f32];
        Some((bytemuck::cast_slice(&bytes).to_vec(), window))
    }

    /// Trace `rays` (origin, direction, reach) against the ground on the
    /// GPU: each ray's t, or `None` where it hits nothing (the GPU twin
    /// check of hydrolux-core `raytrace::trace_hierarchical`).
    pub fn probe_ground(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        rays: &[([f32; 3], [f32; 3], f32)],
    ) -> Vec<Option<f32>> {
        use wgpu::util::DeviceExt;
        let data: Vec<[f32; 4]> = rays
            .iter()
            .flat_map(|(o, d, reach)| [[o[0], o[1], o[2], *reach], [d[0], d[1], d[2], 0.0]])
            .collect();
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("traced probe rays"),
            contents: bytemuck::cast_slice(&data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("traced probe hits"),
            size: 4 * rays.len().max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("traced probe"),
            layout: &self.probe_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 1, resource: input.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: output.as_entire_binding() },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.probe);
            pass.set_bind_group(0, &self.compute_group, &[]);
            pass.set_bind_group(1, &group, &[]);
            pass.dispatch_workgroups((rays.len() as u32).div_ceil(64), 1, 1);
        }
        queue.submit([encoder.finish()]);
        let bytes = read_buffer(device, queue, &output, 4 * rays.len() as u64);
        bytemuck::cast_slice::<u8, f32>(&bytes).iter().map(|&t| (t < 1e38).then_some(t)).collect()
    }

    /// The water heightfield's samples now (row = z, (cells + 1)² of them)
    /// and its window's origin (m).
    pub fn read_water(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> (Vec<f32>, [f32; 2]) {
        let w = &self.uniforms.water;
        let bytes = read_buffer(device, queue, &self.heights, self.heights.size());
        let all: &[f32] = bytemuck::cast_slice(&bytes);
        let n = (w.samples * w.samples) as usize;
        let from = w.first_sample as usize;
        (all[from..from + n].to_vec(), w.origin)
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "raytrace",
    dumps: &[],
    shaders: || {
        vec![
            ("raytrace".to_string(), source()),
            ("raytrace/resample".to_string(), resample_source()),
            ("raytrace/caustics".to_string(), caustics_source()),
        ]
    },
    uniforms: || {
        vec![
            crate::uniforms::Layout::of::<TracedUniforms>(source()),
            crate::uniforms::Layout::of::<HeightfieldUniforms>(source()),
            crate::uniforms::Layout::of::<TracedObject>(source()),
        ]
    },
};
