//! The water surface: a camera-centred clipmap of square rings on a
//! world-fixed grid, displaced by the surface model and shaded with Fresnel,
//! sky reflection, sun glint, the water body and foam (see `water.wgsl`).

pub mod readback;

use crate::gpu_util::*;
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use hydrolux_core::camera::Camera;
use hydrolux_core::scene::Scene;
use wgpu::util::DeviceExt;

/// Grid cells from a ring's centre to its edge.
pub const RING_HALF: i32 = 32;
pub use crate::surface_kind::{BASE_SPACING, DISPLACED_RINGS};
/// Cells from the far field's centre to its edge (hole inside half of it).
pub const FAR_HALF: i32 = 4;
/// The far field's outer edge is this many times the last ring's (≈100 km).
pub const FAR_SCALE: f32 = 50.0;
/// The instance index that draws the far field with the rings' pipelines
/// (`vs_main`); ring levels are below it.
pub const FAR_LEVEL: u32 = 255;
const _: () = assert!(DISPLACED_RINGS < FAR_LEVEL);

pub fn source() -> String {
    let consts = format!(
        "const RING_HALF: f32 = {RING_HALF}.0;\nconst FAR_HALF: f32 = {FAR_HALF}.0;\nconst FAR_SCALE: f32 = {FAR_SCALE:?};\n\
         const DISPLACED_RINGS: u32 = {DISPLACED_RINGS}u;\nconst FAR_LEVEL: u32 = {FAR_LEVEL}u;\nconst VOLUME_DEPTH: f32 = {VOLUME_DEPTH:?};\n"
    );
    shaders::compose(&consts, include_str!("water.wgsl"))
}

/// Depth of the closed water volume's floor (m): below any camera a scene
/// allows (`WORLD_EXTENT_M`), so that a camera deep down is still in the water.
pub const VOLUME_DEPTH: f32 = 1.0e6;
const _: () = assert!(VOLUME_DEPTH > 2.0 * hydrolux_core::scene::WORLD_EXTENT_M);

/// Tiles per side of a ring: rings are culled per tile against the frustum.
pub const TILES: i32 = 4;

/// A square grid of cells (vertices at integer cell corners in [−h, h]²),
/// with index ranges per variant (hole position) and per tile.
struct GridMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// `tiles[variant][tile]`: the tile's cell bounds [x0, z0, x1, z1] and index range.
    tiles: Vec<Vec<([i32; 4], std::ops::Range<u32>)>>,
}

impl GridMesh {
    fn new(device: &wgpu::Device, label: &str, h: i32, holes: &[Option<(i32, i32)>]) -> Self {
        let cells: Vec<[i32; 2]> = (-h..=h).flat_map(|z| (-h..=h).map(move |x| [x, z])).collect();
        let mut idx = Vec::new();
        let mut tiles = Vec::new();
        let t = 2 * h / TILES;
        for hole in holes {
            let mut per_tile = Vec::new();
            for tz in 0..TILES {
                for tx in 0..TILES {
                    let bounds = [-h + tx * t, -h + tz * t, -h + (tx + 1) * t, -h + (tz + 1) * t];
                    let start = idx.len() as u32;
                    idx.extend(grid_indices(h, *hole, bounds));
                    if idx.len() as u32 > start {
                        per_tile.push((bounds, start..idx.len() as u32));
                    }
                }
            }
            tiles.push(per_tile);
        }
        let init = |contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        GridMesh {
            vertices: init(bytemuck::cast_slice(&cells), wgpu::BufferUsages::VERTEX),
            indices: init(bytemuck::cast_slice(&idx), wgpu::BufferUsages::INDEX),
            tiles,
        }
    }

    /// Draw the tiles of `variant` whose cell bounds pass `visible`.
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: usize,
        instance: u32,
        visible: impl Fn([i32; 4]) -> bool,
    ) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for (bounds, range) in &self.tiles[variant] {
            if visible(*bounds) {
                pass.draw_indexed(range.clone(), 0, instance..instance + 1);
            }
        }
    }
}

/// The view frustum as inward-facing planes (a·x + b·y + c·z + d ≥ 0 inside),
/// from a reversed-Z, infinite-far view-projection matrix: left, right,
/// bottom, top, near (there is no far plane).
pub fn frustum_planes(view_proj: glam::Mat4) -> [glam::Vec4; 5] {
    let r = |i| view_proj.row(i);
    [r(3) + r(0), r(3) - r(0), r(3) + r(1), r(3) - r(1), r(3) - r(2)]
}

/// Whether the box [min, max] is at least partly inside the frustum.
pub fn box_visible(planes: &[glam::Vec4; 5], min: glam::Vec3, max: glam::Vec3) -> bool {
    planes.iter().all(|p| {
        let far_corner = glam::Vec3::new(
            if p.x >= 0.0 { max.x } else { min.x },
            if p.y >= 0.0 { max.y } else { min.y },
            if p.z >= 0.0 { max.z } else { min.z },
        );
        p.truncate().dot(far_corner) + p.w >= 0.0
    })
}

/// Centre of ring `level` for a camera at `xz`, exactly as `vs_main` computes
/// it (f32, round half to even).
pub fn ring_centre(xz: [f32; 2], level: u32) -> [f32; 2] {
    let spacing = BASE_SPACING * 2f32.powi(level as i32);
    xz.map(|c| (c / (2.0 * spacing)).round_ties_even() * 2.0 * spacing)
}

/// Which hole variant ring `level` ≥ 1 needs: the finer ring inside it is
/// centred up to one cell off this ring's centre, per axis.
pub fn hole_variant(xz: [f32; 2], level: u32) -> usize {
    let (outer, inner) = (ring_centre(xz, level), ring_centre(xz, level - 1));
    let spacing = BASE_SPACING * 2f32.powi(level as i32);
    let d = |i: usize| (((inner[i] - outer[i]) / spacing).round() as i32).clamp(-1, 1);
    ((d(0) + 1) * 3 + (d(1) + 1)) as usize
}

/// Hole offsets in the order [`hole_variant`] indexes them.
fn hole_offsets() -> Vec<Option<(i32, i32)>> {
    (-1..=1).flat_map(|dx| (-1..=1).map(move |dz| Some((dx, dz)))).collect()
}

pub struct WaterPass {
    full: GridMesh,
    ring: GridMesh,
    far: GridMesh,
    /// Each pipeline draws the rings and the far field (`FAR_LEVEL`).
    depth: wgpu::RenderPipeline,
    /// Shading per medium of the pixel (stencil reference): from the air
    /// (`fs_main`) and from inside the water (`fs_below`).
    shade: [wgpu::RenderPipeline; 2],
    /// The closed water volume into the stencil (seed 000 §4.2).
    volume: wgpu::RenderPipeline,
    volume_box: wgpu::RenderPipeline,
    /// Layout of its inputs (the reflection and refraction textures), which
    /// the screen targets bind.
    pub inputs_layout: wgpu::BindGroupLayout,
    /// Its inputs at the current screen size (`Technique::resize`).
    inputs: Option<wgpu::BindGroup>,
    /// The surface model the pipelines are specialised to.
    model: crate::surface_kind::SurfaceKind,
    /// What `water.method = "raytrace"` traces (group 3; stand-ins otherwise).
    pub traced: crate::passes::raytrace::Traced,
    pub traced_layout: wgpu::BindGroupLayout,
    /// The error view's other drawing (`render.view = "error"`): the same
    /// water built for `raytrace`, drawn when the frame's scene asks for
    /// it (`passes/truth`).
    twin: Option<Box<WaterPass>>,
}

/// Index list of the quads of a (2h)×(2h) cell grid inside `bounds`
/// ([x0, z0, x1, z1] in cells), skipping the (h)×(h) square centred at
/// `hole` (in cells) when there is one.
fn grid_indices(h: i32, hole: Option<(i32, i32)>, bounds: [i32; 4]) -> Vec<u32> {
    let side = (2 * h + 1) as u32;
    let id = |x: i32, z: i32| ((z + h) as u32) * side + (x + h) as u32;
    let mut out = Vec::new();
    for z in bounds[1]..bounds[3] {
        for x in bounds[0]..bounds[2] {
            if let Some((hx, hz)) = hole {
                let inside = x >= hx - h / 2 && x < hx + h / 2 && z >= hz - h / 2 && z < hz + h / 2;
                if inside {
                    continue;
                }
            }
            // Counter-clockwise seen from above (+y).
            out.extend_from_slice(&[
                id(x, z),
                id(x, z + 1),
                id(x + 1, z),
                id(x + 1, z),
                id(x, z + 1),
                id(x + 1, z + 1),
            ]);
        }
    }
    out
}

impl WaterPass {
    /// The layout of the water's inputs (group 2): reflection colour,
    /// refraction colour and depth, a clamping sampler; and for viewers in
    /// the water the mirrored scene below, and the scene above with depth.
    pub fn inputs_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
        let fs = wgpu::ShaderStages::FRAGMENT;
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("water inputs"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(2, fs, wgpu::TextureViewDimension::D2, false),
                sampler_entry(3, fs),
                texture_entry(4, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(5, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(6, fs, wgpu::TextureViewDimension::D2, false),
            ],
        })
    }

    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        inputs: &wgpu::BindGroupLayout,
        main_depth_format: wgpu::TextureFormat,
        model: crate::surface_kind::SurfaceKind,
        traced: crate::passes::raytrace::Traced,
        traced_layout: wgpu::BindGroupLayout,
    ) -> Result<Self, crate::error::RenderError> {
        let module = shader(device, "water", &source());
        let mut constants = crate::surface_kind::specialised_to(model).to_vec();
        let tracing = traced.method == hydrolux_core::scene::WaterMethod::Raytrace;
        constants.push(("RAYTRACE", tracing as u32 as f64));
        let options =
            || wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let layout = pipeline_layout(device, "water", &[globals, surface, inputs, &traced_layout]);
        let grid_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: 8,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Sint32x2],
        })];
        let pipeline = |label: &str,
                        vs: &str,
                        fs: Option<&'static str>,
                        depth_stencil: wgpu::DepthStencilState,
                        buffers: &[Option<wgpu::VertexBufferLayout>]| {
            let targets = [Some(wgpu::ColorTargetState {
                format: crate::targets::HDR_FORMAT,
                blend: None,
                write_mask: if fs == Some("fs_depth") {
                    wgpu::ColorWrites::empty()
                } else {
                    wgpu::ColorWrites::ALL
                },
            })];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: options(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(depth_stencil),
                multisample: wgpu::MultisampleState::default(),
                fragment: fs.map(|fs| wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: options(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let mut depth_only = crate::targets::main_depth_state(
            main_depth_format,
            true,
            wgpu::CompareFunction::Greater,
        );
        depth_only.stencil = Default::default();
        let shade = crate::targets::main_depth_state(
            main_depth_format,
            false,
            wgpu::CompareFunction::GreaterEqual,
        );
        // Two-sided stencil counting: +1 where a ray from the near plane leaves
        // the volume, −1 where it enters; what is left is 1 exactly for
        // pixels whose near-plane point lies inside (no depth test: every
        // face counts, in front of objects or behind them).
        let count = |compare_pass_op| wgpu::StencilFaceState {
            compare: wgpu::CompareFunction::Always,
            pass_op: compare_pass_op,
            ..Default::default()
        };
        let volume = wgpu::DepthStencilState {
            format: main_depth_format,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: wgpu::StencilState {
                front: count(wgpu::StencilOperation::DecrementWrap),
                back: count(wgpu::StencilOperation::IncrementWrap),
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: Default::default(),
        };
        // The two shading pipelines hold the largest shader by far: compile
        // them side by side.
        let (shade_above, shade_below) = crate::gpu_util::create_in_parallel(
            device,
            "creating the water's shading pipelines",
            || pipeline("water shade", "vs_main", Some("fs_main"), shade.clone(), &grid_buffers),
            || {
                pipeline(
                    "water shade below",
                    "vs_main",
                    Some("fs_below"),
                    shade.clone(),
                    &grid_buffers,
                )
            },
        )?;
        Ok(WaterPass {
            inputs_layout: inputs.clone(),
            inputs: None,
            model,
            traced,
            traced_layout,
            twin: None,
            full: GridMesh::new(device, "water full grid", RING_HALF, &[None]),
            ring: GridMesh::new(device, "water ring", RING_HALF, &hole_offsets()),
            far: GridMesh::new(device, "water far field", FAR_HALF, &[Some((0, 0))]),
            depth: pipeline("water depth", "vs_main", Some("fs_depth"), depth_only, &grid_buffers),
            shade: [shade_above, shade_below],
            volume: pipeline(
                "water volume",
                "vs_main",
                Some("fs_depth"),
                volume.clone(),
                &grid_buffers,
            ),
            volume_box: pipeline("water volume box", "vs_box", Some("fs_depth"), volume, &[]),
        })
    }

    /// Classify every pixel of the main view by the medium its near-plane
    /// point lies in (seed 000 §4.2): the water volume (surface, walls, floor)
    /// counted into the stencil, which must be cleared to 0 first.
    pub fn record_medium(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        globals: &wgpu::BindGroup,
        surface: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        camera: &Camera,
    ) {
        let xz = [camera.position.x, camera.position.z];
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(1, surface, &[]);
        pass.set_bind_group(2, inputs, &[]);
        pass.set_bind_group(3, &self.traced.group, &[]);
        // All tiles: off-screen ones make no fragments anyway, so culling
        // would only save vertex work.
        pass.set_pipeline(&self.volume);
        self.full.draw(pass, 0, 0, |_| true);
        for level in 1..DISPLACED_RINGS {
            self.ring.draw(pass, hole_variant(xz, level), level, |_| true);
        }
        self.far.draw(pass, 0, FAR_LEVEL, |_| true);
        pass.set_pipeline(&self.volume_box);
        pass.draw(0..30, 0..1);
    }

    /// Depth pre-pass, then shading of what survived (depth Equal). Tiles
    /// outside the frustum are skipped; `bounds_margin` (m) is how far the
    /// displaced surface can reach beyond a tile's flat footprint (up and
    /// down, and sideways).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        globals: &wgpu::BindGroup,
        surface: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        camera: &Camera,
        aspect: f32,
        bounds_margin: f32,
    ) {
        let planes = frustum_planes(camera.view_projection(aspect));
        let xz = [camera.position.x, camera.position.z];
        let visible = |level: u32| {
            let spacing = BASE_SPACING * 2f32.powi(level as i32);
            let centre = ring_centre(xz, level);
            let planes = &planes;
            move |b: [i32; 4]| {
                // Morphing moves vertices by up to one spacing.
                let m = bounds_margin + spacing;
                let min = glam::Vec3::new(
                    centre[0] + b[0] as f32 * spacing - m,
                    -bounds_margin,
                    centre[1] + b[1] as f32 * spacing - m,
                );
                let max = glam::Vec3::new(
                    centre[0] + b[2] as f32 * spacing + m,
                    bounds_margin,
                    centre[1] + b[3] as f32 * spacing + m,
                );
                box_visible(planes, min, max)
            }
        };
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(1, surface, &[]);
        pass.set_bind_group(2, inputs, &[]);
        pass.set_bind_group(3, &self.traced.group, &[]);
        let draw_surface = |pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline| {
            pass.set_pipeline(pipeline);
            self.full.draw(pass, 0, 0, visible(0));
            for level in 1..DISPLACED_RINGS {
                self.ring.draw(pass, hole_variant(xz, level), level, visible(level));
            }
            self.far.draw(pass, 0, FAR_LEVEL, |_| true);
        };
        draw_surface(pass, &self.depth);
        for (i, medium) in
            [crate::targets::STENCIL_AIR, crate::targets::STENCIL_WATER].into_iter().enumerate()
        {
            pass.set_stencil_reference(medium);
            draw_surface(pass, &self.shade[i]);
        }
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "water",
    dumps: &[],
    // With its ray tracing (`passes/raytrace`), a part of it.
    shaders: || {
        let mut v = vec![("water".to_string(), source())];
        v.extend((crate::passes::raytrace::INFO.shaders)());
        v
    },
    uniforms: || {
        let mut v = vec![crate::uniforms::Layout::of::<crate::uniforms::SurfaceUniforms>(source())];
        v.extend((crate::passes::raytrace::INFO.uniforms)());
        v
    },
};

impl WaterPass {
    /// The pass for `scene`, with the layouts the screen targets bind.
    pub(crate) fn for_scene(
        shared: &crate::technique::Shared,
        scene: &Scene,
        inputs: wgpu::BindGroupLayout,
        traced_layout: wgpu::BindGroupLayout,
    ) -> Result<Self, crate::error::RenderError> {
        let l = &shared.layouts;
        let model = crate::surface_kind::SurfaceKind::of(scene);
        let traced = crate::passes::raytrace::Traced::new(shared, scene, &traced_layout)?;
        WaterPass::new(
            &shared.device,
            &l.globals,
            &l.surface,
            &inputs,
            shared.depth_format,
            model,
            traced,
            traced_layout,
        )
    }

    /// The traced twin exists exactly while `new` asks for the error view,
    /// and follows its edits (`old` as drawn before).
    fn update_twin(
        &mut self,
        shared: &crate::technique::Shared,
        old: &Scene,
        new: &Scene,
    ) -> Result<(), crate::error::RenderError> {
        use crate::error_view::traced;
        if new.render.view != hydrolux_core::scene::DebugView::Error {
            self.twin = None;
            return Ok(());
        }
        match &mut self.twin {
            Some(twin) => {
                twin.set_scene(shared, &traced(old), &traced(new))?;
            }
            None => {
                let (inputs, layout) = (self.inputs_layout.clone(), self.traced_layout.clone());
                self.twin =
                    Some(Box::new(WaterPass::for_scene(shared, &traced(new), inputs, layout)?));
            }
        }
        // The twin reads the same screen targets.
        if let Some(twin) = &mut self.twin {
            twin.inputs = self.inputs.clone();
        }
        Ok(())
    }

    /// Which drawing the frame asks for: this one or the error view's twin.
    fn drawing(&self, frame: &FrameContext) -> &WaterPass {
        match &self.twin {
            Some(twin) if frame.scene.water.method != self.traced.method => twin,
            _ => self,
        }
    }
}

impl Technique for WaterPass {
    fn create(
        shared: &crate::technique::Shared,
        scene: &Scene,
    ) -> Result<Self, crate::error::RenderError> {
        let device = &shared.device;
        let inputs = WaterPass::inputs_layout(device);
        let traced_layout = crate::passes::raytrace::Traced::layout(device);
        let mut water = WaterPass::for_scene(shared, scene, inputs, traced_layout)?;
        water.update_twin(shared, scene, scene)?;
        Ok(water)
    }

    /// The reflection and refraction textures (colour and depth) of the
    /// new size, bound as the water's inputs.
    fn resize(&mut self, shared: &crate::technique::Shared, t: &crate::targets::Targets) {
        let sampler = shared.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("clamp"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let tv = wgpu::BindingResource::TextureView;
        let views = [
            &t.reflection.sampled_view,
            &t.refraction.color_view,
            &t.refraction.depth_view,
            &t.reflection_under.sampled_view,
            &t.refraction_over.color_view,
            &t.refraction_over.depth_view,
        ];
        let mut entries: Vec<_> = views
            .iter()
            .enumerate()
            .map(|(i, v)| wgpu::BindGroupEntry {
                binding: if i < 3 { i as u32 } else { i as u32 + 1 },
                resource: tv(v),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: wgpu::BindingResource::Sampler(&sampler),
        });
        self.inputs = Some(shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("water inputs"),
            layout: &self.inputs_layout,
            entries: &entries,
        }));
        if let Some(twin) = &mut self.twin {
            twin.inputs = self.inputs.clone();
        }
    }

    /// A new surface model gets pipelines specialised to it; the inputs'
    /// layout stays, and with it their bind group.
    fn set_scene(
        &mut self,
        shared: &crate::technique::Shared,
        old: &Scene,
        new: &Scene,
    ) -> Result<bool, crate::error::RenderError> {
        let model = crate::surface_kind::SurfaceKind::of(new);
        if model != self.model || !self.traced.fits(old, new) {
            let (inputs, traced_layout) = (self.inputs_layout.clone(), self.traced_layout.clone());
            let group = self.inputs.take();
            let twin = self.twin.take();
            *self = WaterPass::for_scene(shared, new, inputs, traced_layout)?;
            self.inputs = group;
            self.twin = twin;
        }
        self.update_twin(shared, old, new)?;
        Ok(false)
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        if let Some(twin) =
            self.twin.as_mut().filter(|_| frame.scene.water.method != self.traced.method)
        {
            return Technique::record(twin.as_mut(), stage, encoder, frame, timer);
        }
        if stage == Stage::Simulate && frame.plan.has_water {
            self.traced.move_objects(&frame.shared.queue, &frame.shared.geometry);
            self.traced.record(frame, encoder, timer);
        }
    }

    fn draw(&self, stage: Stage, pass: &mut wgpu::RenderPass<'_>, frame: &FrameContext) {
        let plan = frame.plan;
        if !plan.has_water {
            return;
        }
        let water = self.drawing(frame);
        let (globals, surface) = (&frame.bound.globals, &frame.bound.surface);
        let Some(inputs) = &water.inputs else { return };
        match stage {
            Stage::Medium => water.record_medium(pass, globals, surface, inputs, &plan.camera),
            Stage::Main => {
                let aspect = plan.size.0.max(1) as f32 / plan.size.1.max(1) as f32;
                let margin = plan.cull_margin;
                water.record(pass, globals, surface, inputs, &plan.camera, aspect, margin);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests;
