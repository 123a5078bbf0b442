//! The scene's meshes, shared by every technique that draws them (shared
//! vocabulary below the framework and the techniques): objects, terrain
//! and floor (`geometry.wgsl`), uploaded once per scene ([`SceneGeometry`]),
//! and the pipelines that draw them into any view ([`ViewSlot`]: its own
//! matrix and clip plane) or the sun's shadow map. The `geometry` technique
//! (passes/geometry) decides which views; refractive objects draw them too.

use crate::gpu_util::*;
use crate::shaders;
use crate::uniforms::{ObjectUniforms, ViewUniforms};
use hydrolux_core::geometry::Mesh;
use hydrolux_core::geometry::load::{AssetError, load_texture};
use hydrolux_core::scene::Scene;
use wgpu::util::DeviceExt;

pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub fn source() -> String {
    shaders::compose("", include_str!("geometry.wgsl"))
}

/// Source of the shadow pipeline: without the shadow map's bindings (it is
/// the attachment being written).
pub fn shadow_source() -> String {
    shaders::compose("", include_str!("geometry_shadow.wgsl"))
}

/// Which way a view's triangles wind: mirrored views flip them.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Winding {
    Normal,
    Mirrored,
}

/// One view of the geometry: its uniform buffer and bind group.
pub struct ViewSlot {
    buffer: wgpu::Buffer,
    group: wgpu::BindGroup,
    pub winding: Winding,
    /// It sees only what lies under the water (the refraction view).
    pub below_water: bool,
}

impl ViewSlot {
    /// This view sees only what lies under the water.
    pub fn seeing_below_water(self) -> Self {
        ViewSlot { below_water: true, ..self }
    }

    pub fn write(
        &self,
        queue: &wgpu::Queue,
        view_proj: glam::Mat4,
        clip_plane: glam::Vec4,
        eye: glam::Vec3,
    ) {
        let u = ViewUniforms {
            view_proj: view_proj.to_cols_array_2d(),
            clip_plane: clip_plane.into(),
            eye: eye.into(),
            _pad0: 0.0,
        };
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&u));
    }
}

struct GpuObject {
    indices: std::ops::Range<u32>,
    base_vertex: i32,
    group: wgpu::BindGroup,
    /// Its uniforms, rewritten when it moves.
    buffer: wgpu::Buffer,
    uniforms: ObjectUniforms,
    /// Where it is now (a moving body's last move).
    model: std::cell::Cell<glam::Mat4>,
    /// Its box in its own space, if it casts shadows.
    caster: Option<(glam::Vec3, glam::Vec3)>,
    /// A clear refractive object (`material.ior` > 0): drawn by water_object.
    refractive: bool,
    /// Its shape as an ambient occluder, if it is one.
    occluder: Option<hydrolux_core::occlusion::Shape>,
}

/// Which of the scene's objects a draw covers.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Objects {
    Opaque,
    Refractive,
    All,
}

impl SceneGeometry {
    /// Put `[[objects]]` entry `index` at `transform` (a moving body) from
    /// the next frame on.
    pub fn move_object(&self, queue: &wgpu::Queue, index: usize, transform: glam::Mat4) {
        let Some(o) = self.objects.get(self.first_object + index) else { return };
        if o.refractive && o.model.get() != transform {
            self.refractive_moved.set(true);
        }
        o.model.set(transform);
        let normal = glam::Mat3::from_mat4(transform).inverse().transpose();
        let mut u = o.uniforms;
        u.model = transform.to_cols_array_2d();
        u.normal_matrix = [
            normal.x_axis.extend(0.0).into(),
            normal.y_axis.extend(0.0).into(),
            normal.z_axis.extend(0.0).into(),
        ];
        queue.write_buffer(&o.buffer, 0, bytemuck::bytes_of(&u));
    }

    /// The union of the shadow casters' boxes where they are now (`None`:
    /// nothing casts shadows): the sun's shadow view follows a moving body
    /// rather than staying where the scene started.
    pub fn shadow_bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        self.bounds_where(|_| true)
    }

    /// The union of the casters' boxes that `pick` keeps, where they are now.
    fn bounds_where(&self, pick: impl Fn(&GpuObject) -> bool) -> Option<(glam::Vec3, glam::Vec3)> {
        self.objects
            .iter()
            .filter(|o| pick(o))
            .filter_map(|o| o.caster.map(|b| Mesh::moved_bounds(&o.model.get(), b)))
            .reduce(|(a, b), (lo, hi)| (a.min(lo), b.max(hi)))
    }

    /// The union of the clear refractive objects' boxes where they are now
    /// (`None`: there are none): their light view follows them.
    /// The ambient occluders where they are now (the first
    /// `MAX_OCCLUDERS`).
    pub fn occluders(&self) -> Vec<hydrolux_core::occlusion::Occluder> {
        use hydrolux_core::occlusion::{MAX_OCCLUDERS, Occluder};
        self.objects
            .iter()
            .filter_map(|o| o.occluder.map(|shape| Occluder::placed(shape, &o.model.get())))
            .take(MAX_OCCLUDERS)
            .collect()
    }

    pub fn refractive_bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        self.bounds_where(|o| o.refractive)
    }

    /// Whether the scene has clear refractive objects at all.
    pub fn has_refractive(&self) -> bool {
        self.objects.iter().any(|o| o.refractive)
    }

    /// Whether a refractive object has moved since the last call: what was
    /// traced through it in its light view is stale.
    pub fn take_refractive_moved(&self) -> bool {
        self.refractive_moved.replace(false)
    }

    /// Whether a refractive object has moved since its light view was drawn.
    pub fn refractive_moved(&self) -> bool {
        self.refractive_moved.get()
    }

    /// Where `[[objects]]` entry `index` is now.
    pub fn object_model(&self, index: usize) -> Option<glam::Mat4> {
        self.objects.get(self.first_object + index).map(|o| o.model.get())
    }
}

/// The scene's meshes on the GPU.
pub struct SceneGeometry {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    objects: Vec<GpuObject>,
    /// Entries of `objects` before the scene's `[[objects]]` (the floor).
    first_object: usize,
    /// A refractive object moved (`move_object`) since its light view was drawn.
    refractive_moved: std::cell::Cell<bool>,
    pub triangle_count: usize,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [f32; 2],
}

pub struct GeometryPass {
    view_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    /// Offscreen views (reflection, refraction): plain depth.
    offscreen: wgpu::RenderPipeline,
    /// The refraction view: the light under the surface alone (`fs_below`).
    offscreen_below: wgpu::RenderPipeline,
    offscreen_mirrored: wgpu::RenderPipeline,
    /// The main view, per medium (stencil reference): seen through air, or
    /// from inside the water (attenuated and in-scattered on the way).
    main_air: wgpu::RenderPipeline,
    main_water: wgpu::RenderPipeline,
    shadow: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    white: wgpu::TextureView,
}

pub fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRS: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];
    wgpu::VertexBufferLayout {
        array_stride: 32,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRS,
    }
}

impl GeometryPass {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        globals: &wgpu::BindGroupLayout,
        frame_only: &wgpu::BindGroupLayout,
        main_depth_format: wgpu::TextureFormat,
    ) -> Self {
        let (vs, fs) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT);
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("geometry view"),
            entries: &[uniform_entry(0, vs | fs)],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("geometry object"),
            entries: &[
                uniform_entry(0, vs | fs),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, true),
                sampler_entry(2, fs),
            ],
        });
        let module = shader(device, "geometry", &source());
        let layout = pipeline_layout(device, "geometry", &[globals, &view_layout, &object_layout]);
        let offscreen_depth = wgpu::DepthStencilState {
            format: crate::formats::DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let main_depth = crate::formats::main_depth_state(
            main_depth_format,
            true,
            wgpu::CompareFunction::Greater,
        );
        let colour = |front_face, depth_stencil: &wgpu::DepthStencilState, fs: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("geometry"),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout())],
                },
                primitive: wgpu::PrimitiveState {
                    front_face,
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(depth_stencil.clone()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(crate::formats::HDR_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let shadow_module = shader(device, "geometry shadow", &shadow_source());
        let shadow_layout =
            pipeline_layout(device, "geometry shadow", &[frame_only, &view_layout, &object_layout]);
        let shadow = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow map"),
            layout: Some(&shadow_layout),
            vertex: wgpu::VertexState {
                module: &shadow_module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout())],
            },
            // Both faces: open meshes (planes) must cast too.
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState { constant: 2, slope_scale: 2.0, clamp: 0.0 },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("albedo"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let white = upload_rgba8(device, queue, "white", 1, 1, &[255; 4]);
        GeometryPass {
            view_layout,
            object_layout,
            offscreen: colour(wgpu::FrontFace::Ccw, &offscreen_depth, "fs_main"),
            offscreen_below: colour(wgpu::FrontFace::Ccw, &offscreen_depth, "fs_below"),
            offscreen_mirrored: colour(wgpu::FrontFace::Cw, &offscreen_depth, "fs_main"),
            main_air: colour(wgpu::FrontFace::Ccw, &main_depth, "fs_air"),
            main_water: colour(wgpu::FrontFace::Ccw, &main_depth, "fs_underwater"),
            shadow,
            sampler,
            white,
        }
    }

    pub fn view_slot(&self, device: &wgpu::Device, label: &str, winding: Winding) -> ViewSlot {
        let buffer = uniform_buffer(device, label, &ViewUniforms::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &self.view_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        ViewSlot { buffer, group, winding, below_water: false }
    }

    /// Build every mesh, texture and per-object uniform of `scene`.
    pub fn upload(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
    ) -> Result<SceneGeometry, AssetError> {
        let built = scene.build_geometry()?;
        let (mut vertices, mut indices, mut objects) = (Vec::new(), Vec::new(), Vec::new());
        // The floor or terrain comes first, then the scene's objects in order.
        use hydrolux_core::occlusion::NO_OCCLUDER;
        let slots = scene.occluder_slots();
        let first_scene_object = built.len() - scene.objects.len();
        for (built_index, o) in built.iter().enumerate() {
            let base_vertex = vertices.len() as i32;
            let first = indices.len() as u32;
            vertices.extend(o.mesh.positions.iter().zip(&o.mesh.normals).zip(&o.mesh.uvs).map(
                |((p, n), uv)| Vertex {
                    position: p.to_array(),
                    normal: n.to_array(),
                    uv: uv.to_array(),
                },
            ));
            indices.extend_from_slice(&o.mesh.indices);
            let m = &o.material;
            let texture = if m.texture.is_empty() {
                None
            } else {
                let img = load_texture(&scene.resolve_path(&m.texture))?;
                Some(upload_rgba8(device, queue, &m.texture, img.width, img.height, &img.rgba))
            };
            let normal = glam::Mat3::from_mat4(o.transform).inverse().transpose();
            let u = ObjectUniforms {
                model: o.transform.to_cols_array_2d(),
                normal_matrix: [
                    normal.x_axis.extend(0.0).into(),
                    normal.y_axis.extend(0.0).into(),
                    normal.z_axis.extend(0.0).into(),
                ],
                albedo: m.albedo,
                uv_scale: m.uv_scale,
                pattern_color: m.pattern_color,
                tile_size: m.tile_size,
                pattern: crate::modes::pattern(m.pattern),
                ior: m.ior,
                roughness: m.roughness,
                metalness: m.metalness,
                specular: m.specular,
                occluder: built_index
                    .checked_sub(first_scene_object)
                    .map_or(NO_OCCLUDER, |i| slots[i]),
                _pad1: 0,
                _pad2: 0,
            };
            let buffer = uniform_buffer(device, &o.name, &u);
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&o.name),
                layout: &self.object_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(
                            texture.as_ref().unwrap_or(&self.white),
                        ),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                ],
            });
            objects.push(GpuObject {
                indices: first..indices.len() as u32,
                base_vertex,
                group,
                buffer,
                uniforms: u,
                model: std::cell::Cell::new(o.transform),
                caster: o.shadow_bounds.and(o.mesh.bounds(&glam::Mat4::IDENTITY)),
                refractive: m.ior > 0.0,
                occluder: o.occluder,
            });
        }
        // wgpu wants non-empty buffers.
        vertices.push(bytemuck::Zeroable::zeroed());
        indices.push(0);
        let init = |label, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        Ok(SceneGeometry {
            vertices: init(
                "scene vertices",
                bytemuck::cast_slice(&vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: init(
                "scene indices",
                bytemuck::cast_slice(&indices),
                wgpu::BufferUsages::INDEX,
            ),
            triangle_count: (indices.len() - 1) / 3,
            first_object: built.len() - scene.objects.len(),
            objects,
            refractive_moved: std::cell::Cell::new(false),
        })
    }

    /// Draw every object into an offscreen `view` (reflection, refraction).
    pub fn record(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        globals: &wgpu::BindGroup,
        view: &ViewSlot,
        geometry: &SceneGeometry,
    ) {
        pass.set_pipeline(if view.winding == Winding::Mirrored {
            &self.offscreen_mirrored
        } else if view.below_water {
            &self.offscreen_below
        } else {
            &self.offscreen
        });
        pass.set_bind_group(0, globals, &[]);
        self.draw_objects(pass, view, geometry, Objects::Opaque);
    }

    /// Draw every object into the main view, once per medium: pixels whose
    /// stencil says air, then those that look out from inside the water.
    pub fn record_main(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        globals: &wgpu::BindGroup,
        view: &ViewSlot,
        geometry: &SceneGeometry,
    ) {
        for (pipeline, medium) in [
            (&self.main_air, crate::formats::STENCIL_AIR),
            (&self.main_water, crate::formats::STENCIL_WATER),
        ] {
            pass.set_pipeline(pipeline);
            pass.set_stencil_reference(medium);
            pass.set_bind_group(0, globals, &[]);
            self.draw_objects(pass, view, geometry, Objects::Opaque);
        }
    }

    /// Draw `which` objects into a depth map from the sun (the shadow map).
    pub fn record_shadow(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        frame_only: &wgpu::BindGroup,
        view: &ViewSlot,
        geometry: &SceneGeometry,
        which: Objects,
    ) {
        pass.set_pipeline(&self.shadow);
        pass.set_bind_group(0, frame_only, &[]);
        self.draw_objects(pass, view, geometry, which);
    }

    pub fn view_layout(&self) -> &wgpu::BindGroupLayout {
        &self.view_layout
    }

    pub fn object_layout(&self) -> &wgpu::BindGroupLayout {
        &self.object_layout
    }

    /// The bind group of an untextured object drawn where it is (identity
    /// model) with `ior` (> 0: clear, drawn by water_object): for meshes
    /// made on the GPU, such as the liquid's surface.
    pub fn plain_object_group(
        &self,
        device: &wgpu::Device,
        label: &str,
        ior: f32,
    ) -> wgpu::BindGroup {
        let identity = glam::Mat4::IDENTITY;
        let u = ObjectUniforms {
            model: identity.to_cols_array_2d(),
            normal_matrix: [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]],
            albedo: [1.0; 3],
            uv_scale: 1.0,
            pattern_color: [1.0; 3],
            tile_size: 1.0,
            pattern: 0,
            ior,
            roughness: 0.5,
            metalness: 0.0,
            specular: 0.5,
            occluder: hydrolux_core::occlusion::NO_OCCLUDER,
            _pad1: 0,
            _pad2: 0,
        };
        let buffer = uniform_buffer(device, label, &u);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &self.object_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&self.white),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        })
    }

    /// Draw the liquid's surface mesh (made on the GPU, its count too) with
    /// the caller's pipeline, as [`Self::draw_objects`] draws an object.
    pub fn draw_liquid(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        view: &ViewSlot,
        mesh: &crate::simulation::published::LiquidMesh,
    ) {
        pass.set_bind_group(1, &view.group, &[]);
        pass.set_bind_group(2, &mesh.group, &[]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed_indirect(&mesh.args, 0);
    }

    /// Draw `which` objects with the caller's pipeline (groups 1 and 2 are
    /// the view and each object; the caller sets group 0 and any after 2).
    pub fn draw_objects(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        view: &ViewSlot,
        geometry: &SceneGeometry,
        which: Objects,
    ) {
        if geometry.objects.is_empty() {
            return;
        }
        pass.set_bind_group(1, &view.group, &[]);
        pass.set_vertex_buffer(0, geometry.vertices.slice(..));
        pass.set_index_buffer(geometry.indices.slice(..), wgpu::IndexFormat::Uint32);
        for o in &geometry.objects {
            let wanted = match which {
                Objects::Opaque => !o.refractive,
                Objects::Refractive => o.refractive,
                Objects::All => true,
            };
            if !wanted {
                continue;
            }
            pass.set_bind_group(2, &o.group, &[]);
            pass.draw_indexed(o.indices.clone(), o.base_vertex, 0..1);
        }
    }
}

/// An sRGB texture with a full mip chain (box-filtered in linear light on the CPU).
fn upload_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> wgpu::TextureView {
    let levels = 32 - width.max(height).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let to_linear = |c: u8| {
        let c = c as f32 / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    let mut level: Vec<[f32; 4]> = rgba
        .chunks_exact(4)
        .map(|p| [to_linear(p[0]), to_linear(p[1]), to_linear(p[2]), p[3] as f32 / 255.0])
        .collect();
    let (mut w, mut h) = (width, height);
    for mip in 0..levels {
        let bytes: Vec<u8> = level
            .iter()
            .flat_map(|p| {
                let enc = |c: f32| {
                    let s =
                        if c <= 0.0031308 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
                    (s.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                };
                [enc(p[0]), enc(p[1]), enc(p[2]), (p[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8]
            })
            .collect();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: mip,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = vec![[0.0f32; 4]; (nw * nh) as usize];
        for y in 0..nh {
            for x in 0..nw {
                let mut sum = [0.0f32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(w - 1);
                    let sy = (2 * y + dy).min(h - 1);
                    let p = level[(sy * w + sx) as usize];
                    for c in 0..4 {
                        sum[c] += 0.25 * p[c];
                    }
                }
                next[(y * nw + x) as usize] = sum;
            }
        }
        level = next;
        (w, h) = (nw, nh);
    }
    texture.create_view(&Default::default())
}
