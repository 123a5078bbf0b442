//! Light through refractive objects (seed 004, after Hu et al. 2010; CPU
//! twin of the path: `hydrolux_core::water_object`), and the objects
//! themselves seen as clear water.
//!
//! From the light (`record_light`), in an orthographic view fitted to the
//! refractive objects and what lies below them:
//! 1. `light.wgsl`: their front faces and the back faces where that light
//!    leaves them (outward normal × the thing's index of refraction, depth);
//!    the opaque scene's depth (the geometry pass's shadow pipeline).
//! 2. `paths.wgsl`: per texel, refract in, march to the exit p1 against the
//!    back depth, refract out, march to p2 against the scene depth; write
//!    the path p1 → p2 as a beam tube (drawn by the god-ray pass as the
//!    volume caustic in the fog) and splat its light where it lands, then
//!    filter that into the object caustic map that receivers read
//!    (`shaders/object_caustics.wgsl`).
//!
//! From the camera (`record_camera`), after the opaque scene and the god
//! rays: `shade.wgsl` records the objects' back faces, then shades their
//! front faces by two refractions into a copy of the image behind them.

pub mod readback;

use crate::gpu_util::*;
use crate::meshes::{
    self as meshes, GeometryPass, Objects, SHADOW_FORMAT, SceneGeometry, ViewSlot,
};
use crate::shaders;
use crate::simulation::liquid::screen_space::SunFaces;
use crate::simulation::published::LiquidMesh;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;

/// Front/back faces from the light: outward normal and depth, as the bits
/// of four f32 (`bitcast`): full precision, and a 32-bit integer target is
/// renderable on every backend, unlike `Rgba32Float` (not on wgpu's GL).
pub(crate) const FACES_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// The object caustic map: rgb irradiance, a the scene's depth.
pub const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The camera's back-face record: outward normal and distance.
const BACK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The camera-inside pass's depth and stencil (the stencil counts faces).
const INSIDE_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;
/// How far outside the clear objects' and the liquid's box the camera may
/// be and still have its lens in them (the near plane's reach).
const INSIDE_MARGIN: f32 = 0.1;
/// Fixed point of the splat: 2¹⁶ per unit of relative irradiance.
pub const FIXED_POINT_SCALE: f32 = 65536.0;
/// Samples of each march (before bisection).
pub const MARCH_STEPS: u32 = 96;

pub fn light_source() -> String {
    shaders::compose("", include_str!("light.wgsl"))
}

pub fn paths_source() -> String {
    shaders::compose("", include_str!("paths.wgsl"))
}

pub fn shade_source() -> String {
    shaders::compose("", include_str!("shade.wgsl"))
}

crate::uniforms::uniform! { ObjectLightParams;
    /// WGSL `ObjectLightParams` (paths.wgsl).
    pub struct ObjectLightUniforms {
        pub inv_view_proj: [[f32; 4]; 4],
        pub resolution: u32,
        pub march_steps: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub texel_area: f32,
        pub _pad4: f32,
        pub floor_y: f32,
        pub reach: f32,
        pub fixed_point_scale: f32,
        pub has_floor: u32,
        pub _pad2: f32,
        pub _pad3: f32,
    }
}

/// The light paths' uniforms from the plan's decisions.
fn light_uniforms(o: &crate::plan::ObjectLightPlan) -> ObjectLightUniforms {
    ObjectLightUniforms {
        inv_view_proj: o.view_proj.inverse().to_cols_array_2d(),
        resolution: o.resolution,
        march_steps: MARCH_STEPS,
        texel_area: o.texel_area,
        floor_y: o.floor_y,
        reach: o.reach,
        fixed_point_scale: FIXED_POINT_SCALE,
        has_floor: o.floor as u32,
        ..Default::default()
    }
}

/// The light-view targets for one resolution, and the paths' tubes.
pub struct ObjectLight {
    pub resolution: u32,
    front_view: wgpu::TextureView,
    front_depth: wgpu::TextureView,
    back_view: wgpu::TextureView,
    back_depth: wgpu::TextureView,
    scene_depth: wgpu::TextureView,
    pub map: wgpu::Texture,
    pub map_view: wgpu::TextureView,
    paths_group: wgpu::BindGroup,
    /// The paths as tubes (`resolution`² of them); the god rays draw them
    /// into the fog.
    pub tubes: wgpu::Buffer,
}

/// Camera-size targets: the back faces and a copy of the image behind.
pub struct ObjectTargets {
    back_view: wgpu::TextureView,
    back_depth: wgpu::TextureView,
    front_depth: wgpu::TextureView,
    behind: wgpu::Texture,
    /// Depth and the face count for a camera inside.
    inside_depth: wgpu::TextureView,
    inputs: wgpu::BindGroup,
}

/// The passes that draw a camera's view from inside the clear objects or
/// the liquid (`shade.wgsl`: `fs_count`, `fs_inside`, `fs_inside_medium`).
struct InsidePipelines {
    count: wgpu::RenderPipeline,
    faces: wgpu::RenderPipeline,
    medium: wgpu::RenderPipeline,
}

pub struct WaterObjectPass {
    params: wgpu::Buffer,
    light_front: wgpu::RenderPipeline,
    light_back: wgpu::RenderPipeline,
    paths_layout: wgpu::BindGroupLayout,
    clear: wgpu::ComputePipeline,
    trace: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    inputs_layout: wgpu::BindGroupLayout,
    camera_back: wgpu::RenderPipeline,
    camera_front: wgpu::RenderPipeline,
    inside: InsidePipelines,
}

#[allow(clippy::too_many_arguments)]
fn mesh_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    (vs, fs): (&str, &str),
    layouts: &[&wgpu::BindGroupLayout],
    target: impl Into<wgpu::ColorTargetState>,
    cull: Option<wgpu::Face>,
    depth: wgpu::DepthStencilState,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout(device, label, layouts)),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            compilation_options: Default::default(),
            buffers: &[Some(meshes::vertex_layout())],
        },
        primitive: wgpu::PrimitiveState { cull_mode: cull, ..Default::default() },
        depth_stencil: Some(depth),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: Default::default(),
            targets: &[Some(target.into())],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// What is drawn as clear water (the refractive objects and the liquid's
/// mesh), in one view.
#[derive(Clone, Copy)]
pub struct ClearThings<'a> {
    pub meshes: &'a GeometryPass,
    pub geometry: &'a SceneGeometry,
    pub view: &'a ViewSlot,
    pub liquid: Option<&'a LiquidMesh>,
    /// Whether the refractive objects are drawn (a layer may leave them).
    pub objects: bool,
}

impl<'a> ClearThings<'a> {
    /// Draw them all with the pass's pipeline (groups 1 and 2 set here).
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.objects {
            self.meshes.draw_objects(pass, self.view, self.geometry, Objects::Refractive);
        }
        if let Some(mesh) = self.liquid {
            self.meshes.draw_liquid(pass, self.view, mesh);
        }
    }

    /// The layers the camera draws one over the other: with both, the
    /// liquid first (it lies in its glass), then the clear objects
    /// refracting the image with the liquid in it, so water is seen
    /// through a glass's walls; one layer otherwise.
    fn layers(&self) -> Vec<ClearThings<'a>> {
        let objects = self.objects && self.geometry.has_refractive();
        match (objects, self.liquid) {
            (true, Some(_)) => {
                vec![ClearThings { objects: false, ..*self }, ClearThings { liquid: None, ..*self }]
            }
            _ => vec![*self],
        }
    }
}

/// A pass drawing over the camera's image with a depth (and stencil)
/// attachment of its own, cleared to the far plane and not kept.
fn over_image<'a>(
    encoder: &'a mut wgpu::CommandEncoder,
    label: &str,
    image: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    stencil: bool,
) -> wgpu::RenderPass<'a> {
    over_image_keeping(encoder, label, image, depth, stencil, cleared(0.0))
}

fn cleared<T>(value: T) -> wgpu::Operations<T> {
    wgpu::Operations { load: wgpu::LoadOp::Clear(value), store: wgpu::StoreOp::Discard }
}

/// As [`over_image`], with the depth's load and store given (layers drawn
/// in turn keep the nearer layers' depth).
fn over_image_keeping<'a>(
    encoder: &'a mut wgpu::CommandEncoder,
    label: &str,
    image: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    stencil: bool,
    depth_ops: wgpu::Operations<f32>,
) -> wgpu::RenderPass<'a> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: image,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(depth_ops),
            stencil_ops: stencil.then_some(cleared(0u32)),
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

fn depth_state(
    format: wgpu::TextureFormat,
    compare: wgpu::CompareFunction,
) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: Some(true),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

impl WaterObjectPass {
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        frame_only: &wgpu::BindGroupLayout,
        geometry_pass: &GeometryPass,
    ) -> Self {
        let (fs, cs) = (wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::COMPUTE);
        let mesh_layouts = [frame_only, geometry_pass.view_layout(), geometry_pass.object_layout()];
        let light_module = shader(device, "water object light", &light_source());
        let d32 = wgpu::TextureFormat::Depth32Float;
        let light_front = mesh_pipeline(
            device,
            "water object front",
            &light_module,
            ("vs_light", "fs_light"),
            &mesh_layouts,
            FACES_FORMAT,
            Some(wgpu::Face::Back),
            depth_state(d32, wgpu::CompareFunction::Less),
        );
        let light_back = mesh_pipeline(
            device,
            "water object back",
            &light_module,
            ("vs_light", "fs_light"),
            &mesh_layouts,
            FACES_FORMAT,
            Some(wgpu::Face::Front),
            depth_state(d32, wgpu::CompareFunction::Less),
        );
        let paths_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("water object paths"),
            entries: &[
                uniform_entry(0, cs),
                uint_texture_entry(1, cs),
                uint_texture_entry(2, cs),
                texture_entry(3, cs, wgpu::TextureViewDimension::D2, false),
                storage_entry(4, cs, false),
                storage_entry(5, cs, false),
                storage_texture_entry(6, MAP_FORMAT, wgpu::TextureViewDimension::D2),
            ],
        });
        let paths_module = shader(device, "water object paths", &paths_source());
        let p = |entry| {
            compute_pipeline(device, entry, &paths_module, entry, &[frame_only, &paths_layout])
        };
        let inputs_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("water object inputs"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, true),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, false),
                texture_entry(2, fs, wgpu::TextureViewDimension::D2, false),
            ],
        });
        let shade_module = shader(device, "water object shade", &shade_source());
        let shade_layouts =
            [globals, geometry_pass.view_layout(), geometry_pass.object_layout(), &inputs_layout];
        // Reversed Z: the farthest back face has the smallest depth.
        let camera_back = mesh_pipeline(
            device,
            "water object back faces",
            &shade_module,
            ("vs_object", "fs_back"),
            &shade_layouts[..3],
            BACK_FORMAT,
            Some(wgpu::Face::Front),
            depth_state(d32, wgpu::CompareFunction::Less),
        );
        // Its own depth (nearest front face); the scene's depth is tested in
        // the shader, which reads it (a read-only attachment that is also
        // sampled is not portable).
        let camera_front = mesh_pipeline(
            device,
            "water object",
            &shade_module,
            ("vs_object", "fs_front"),
            &shade_layouts,
            crate::targets::HDR_FORMAT,
            Some(wgpu::Face::Back),
            depth_state(d32, wgpu::CompareFunction::Greater),
        );
        let inside = Self::inside_pipelines(device, &shade_module, &shade_layouts);
        let (clear, trace, resolve) = (p("clear"), p("trace"), p("resolve"));
        WaterObjectPass {
            params: uniform_buffer(device, "water object params", &ObjectLightUniforms::default()),
            light_front,
            light_back,
            paths_layout,
            clear,
            trace,
            resolve,
            inputs_layout,
            camera_back,
            camera_front,
            inside,
        }
    }

    fn inside_pipelines(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        layouts: &[&wgpu::BindGroupLayout; 4],
    ) -> InsidePipelines {
        let stencil = |compare, front, back, write_mask| wgpu::StencilState {
            front: wgpu::StencilFaceState { compare, pass_op: front, ..Default::default() },
            back: wgpu::StencilFaceState { compare, pass_op: back, ..Default::default() },
            read_mask: 0xff,
            write_mask,
        };
        let state = |write, compare, stencil| wgpu::DepthStencilState {
            format: INSIDE_DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil,
            bias: Default::default(),
        };
        use wgpu::{CompareFunction as C, StencilOperation as S};
        let keep = S::Keep;
        // Every face, no depth test: −1 entering (front), +1 leaving (back).
        let count = mesh_pipeline(
            device,
            "water object inside count",
            module,
            ("vs_object", "fs_count"),
            layouts,
            wgpu::ColorTargetState {
                format: crate::targets::HDR_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::empty(),
            },
            None,
            state(false, C::Always, stencil(C::Always, S::DecrementWrap, S::IncrementWrap, 0xff)),
        );
        // The nearest back face where the count is 1 (reversed Z).
        let faces = mesh_pipeline(
            device,
            "water object inside",
            module,
            ("vs_object", "fs_inside"),
            layouts,
            crate::targets::HDR_FORMAT,
            Some(wgpu::Face::Front),
            state(true, C::Greater, stencil(C::Equal, keep, keep, 0)),
        );
        // Where no back face was drawn: the opaque scene in the water. Its
        // layout is the faces' (groups 1 and 2 stay bound from their draws,
        // unread): one with the middle groups left empty reads the wrong
        // textures on lavapipe.
        let label = "water object inside medium";
        let layout = pipeline_layout(device, label, layouts);
        let medium = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_far"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(state(false, C::Greater, stencil(C::Equal, keep, keep, 0))),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("fs_inside_medium"),
                compilation_options: Default::default(),
                targets: &[Some(crate::targets::HDR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        InsidePipelines { count, faces, medium }
    }

    /// The light-view targets for `resolution`² paths (1 when there are no
    /// refractive objects: the map globals bind must exist).
    pub fn create_light(&self, device: &wgpu::Device, resolution: u32) -> ObjectLight {
        let k = (resolution, resolution);
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let view = |t: wgpu::Texture| t.create_view(&Default::default());
        let front_view = view(texture_2d(device, "water object front", k, FACES_FORMAT, att));
        let back_view = view(texture_2d(device, "water object back", k, FACES_FORMAT, att));
        let front_depth = view(texture_2d(
            device,
            "water object front depth",
            k,
            wgpu::TextureFormat::Depth32Float,
            att,
        ));
        let back_depth = view(texture_2d(
            device,
            "water object back depth",
            k,
            wgpu::TextureFormat::Depth32Float,
            att,
        ));
        let scene_depth =
            view(texture_2d(device, "water object scene depth", k, SHADOW_FORMAT, att));
        let map = texture_2d(
            device,
            "object caustic map",
            k,
            MAP_FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let map_view = map.create_view(&Default::default());
        let accum = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("object caustic accumulator"),
            size: (resolution as u64).pow(2) * 3 * 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let tubes = crate::passes::godrays::tube_buffer(device, resolution);
        let tv = wgpu::BindingResource::TextureView;
        let paths_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("water object paths"),
            layout: &self.paths_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: tv(&front_view) },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&back_view) },
                wgpu::BindGroupEntry { binding: 3, resource: tv(&scene_depth) },
                wgpu::BindGroupEntry { binding: 4, resource: tubes.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: accum.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: tv(&map_view) },
            ],
        });
        ObjectLight {
            resolution,
            front_view,
            front_depth,
            back_view,
            back_depth,
            scene_depth,
            map,
            map_view,
            paths_group,
            tubes,
        }
    }

    /// Camera-size targets reading the main view's depth.
    pub fn create_targets(
        &self,
        device: &wgpu::Device,
        size: (u32, u32),
        main_depth: &wgpu::TextureView,
    ) -> ObjectTargets {
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let back_view = texture_2d(device, "water object back faces", size, BACK_FORMAT, att)
            .create_view(&Default::default());
        let back_depth = texture_2d(
            device,
            "water object back faces depth",
            size,
            wgpu::TextureFormat::Depth32Float,
            att,
        )
        .create_view(&Default::default());
        let front_depth = texture_2d(
            device,
            "water object front faces depth",
            size,
            wgpu::TextureFormat::Depth32Float,
            att,
        )
        .create_view(&Default::default());
        let behind = texture_2d(
            device,
            "behind water objects",
            size,
            crate::targets::HDR_FORMAT,
            // COPY_SRC: `Renderer::read_behind_water_objects`.
            wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let behind_view = behind.create_view(&Default::default());
        let inside_depth =
            texture_2d(device, "water object inside depth", size, INSIDE_DEPTH_FORMAT, att)
                .create_view(&Default::default());
        let tv = wgpu::BindingResource::TextureView;
        let inputs = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("water object inputs"),
            layout: &self.inputs_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: tv(&behind_view) },
                wgpu::BindGroupEntry { binding: 1, resource: tv(main_depth) },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&back_view) },
            ],
        });
        ObjectTargets { back_view, back_depth, front_depth, behind, inside_depth, inputs }
    }

    /// The light's uniforms. The error view comparing surfaces (`staged`)
    /// draws a frame twice in one submission, each drawing fitting the light
    /// to its own mesh, so there they are copied in the encoder's order: a
    /// queue write of the second drawing's would land before the first's
    /// paths.
    pub fn prepare(
        &self,
        shared: &crate::technique::Shared,
        encoder: &mut wgpu::CommandEncoder,
        uniforms: &ObjectLightUniforms,
        staged: bool,
    ) {
        let bytes = bytemuck::bytes_of(uniforms);
        if !staged {
            shared.queue.write_buffer(&self.params, 0, bytes);
            return;
        }
        let staging = wgpu::util::DeviceExt::create_buffer_init(
            &shared.device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("water object params (staged)"),
                contents: bytes,
                usage: wgpu::BufferUsages::COPY_SRC,
            },
        );
        encoder.copy_buffer_to_buffer(&staging, 0, &self.params, 0, bytes.len() as u64);
    }

    /// Everything from the light: faces, scene depth, paths and the map.
    pub fn record_light(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame_only: &wgpu::BindGroup,
        things: &ClearThings,
        light: &ObjectLight,
        liquid_faces: Option<&SunFaces>,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let faces = |encoder: &mut wgpu::CommandEncoder,
                     label,
                     color,
                     depth,
                     clear_w: f64,
                     clear_depth: f32,
                     pipeline,
                     back: bool,
                     timer: Option<&mut GpuTimer>| {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.0,
                            g: 0.0,
                            b: 0.0,
                            // The bits of the float, as the target holds them.
                            a: f64::from((clear_w as f32).to_bits()),
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(clear_depth),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.and_then(|t| t.render_writes(label)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, frame_only, &[]);
            things.draw(&mut pass);
            // The liquid drawn by screen-space fluid rendering: its faces
            // from the maps it made from the sun.
            if let Some(liquid) = liquid_faces {
                liquid.draw(&mut pass, back);
            }
        };
        // Empty texels: front beyond the far plane (2), back before the near
        // one (−1). Both keep the face nearest the sun: the back face is where
        // the light leaves the first thing it entered (a glass's wall, then the
        // water in it: each its own exit, not the farthest face of them all).
        faces(
            encoder,
            "water object faces",
            &light.front_view,
            &light.front_depth,
            2.0,
            1.0,
            &self.light_front,
            false,
            timer.as_deref_mut(),
        );
        faces(
            encoder,
            "water object back",
            &light.back_view,
            &light.back_depth,
            -1.0,
            1.0,
            &self.light_back,
            true,
            None,
        );
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("water object scene depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &light.scene_depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            things.meshes.record_shadow(
                &mut pass,
                frame_only,
                things.view,
                things.geometry,
                Objects::Opaque,
            );
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("water object paths"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("water object paths")),
        });
        pass.set_bind_group(0, frame_only, &[]);
        pass.set_bind_group(1, &light.paths_group, &[]);
        let n = light.resolution.div_ceil(8);
        for pipeline in [&self.clear, &self.trace, &self.resolve] {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(n, n, 1);
        }
    }

    /// The refractive objects in the main view (after the opaque scene and
    /// the god rays are in `hdr`).
    #[allow(clippy::too_many_arguments)]
    pub fn record_camera(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        globals: &wgpu::BindGroup,
        things: &ClearThings,
        targets: &ObjectTargets,
        (hdr, hdr_view): (&wgpu::Texture, &wgpu::TextureView),
        camera_may_be_inside: bool,
        timer: Option<&mut GpuTimer>,
    ) {
        // A camera that may be inside sees all as one layer: from within,
        // the image behind must be the scene before any of them.
        let layers = if camera_may_be_inside { vec![*things] } else { things.layers() };
        let mut timer = timer;
        let count = layers.len();
        for (i, layer) in layers.iter().enumerate() {
            self.record_layer(encoder, globals, layer, targets, (hdr, hdr_view), timer.take(), {
                // Each layer keeps its depth for the next, so that a far
                // layer's faces (a glass's back wall) do not cover a nearer
                // one's (the water in front of it).
                let load = if i == 0 { wgpu::LoadOp::Clear(0.0) } else { wgpu::LoadOp::Load };
                let store =
                    if i + 1 < count { wgpu::StoreOp::Store } else { wgpu::StoreOp::Discard };
                wgpu::Operations { load, store }
            });
        }
        if camera_may_be_inside {
            self.record_inside(encoder, globals, things, targets, hdr_view);
        }
    }

    /// One layer of clear things over the image: their back faces, then
    /// their front faces refracting a copy of the image as it is.
    #[allow(clippy::too_many_arguments)]
    fn record_layer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        globals: &wgpu::BindGroup,
        things: &ClearThings,
        targets: &ObjectTargets,
        (hdr, hdr_view): (&wgpu::Texture, &wgpu::TextureView),
        timer: Option<&mut GpuTimer>,
        depth_ops: wgpu::Operations<f32>,
    ) {
        encoder.copy_texture_to_texture(
            hdr.as_image_copy(),
            targets.behind.as_image_copy(),
            hdr.size(),
        );
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("water object back faces"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &targets.back_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.back_depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.and_then(|t| t.render_writes("water object")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.camera_back);
            pass.set_bind_group(0, globals, &[]);
            things.draw(&mut pass);
        }
        let mut pass = over_image_keeping(
            encoder,
            "water object front",
            hdr_view,
            &targets.front_depth,
            false,
            depth_ops,
        );
        pass.set_pipeline(&self.camera_front);
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(3, &targets.inputs, &[]);
        things.draw(&mut pass);
    }

    /// A camera whose lens may be inside a clear object or the liquid: the
    /// pixels whose near-plane point is inside (a stencil face count of
    /// one) are drawn as seen from within the water, over what the front
    /// faces drew.
    fn record_inside(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        globals: &wgpu::BindGroup,
        things: &ClearThings,
        targets: &ObjectTargets,
        hdr_view: &wgpu::TextureView,
    ) {
        let mut pass =
            over_image(encoder, "water object inside", hdr_view, &targets.inside_depth, true);
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(3, &targets.inputs, &[]);
        let p = &self.inside;
        for pipeline in [&p.count, &p.faces] {
            pass.set_pipeline(pipeline);
            pass.set_stencil_reference(1);
            things.draw(&mut pass);
        }
        pass.set_pipeline(&p.medium);
        pass.draw(0..3, 0..1);
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "water_objects",
    dumps: readback::DUMPS,
    shaders: || {
        vec![
            ("water_object/light".to_string(), light_source()),
            ("water_object/paths".to_string(), paths_source()),
            ("water_object/shade".to_string(), shade_source()),
        ]
    },
    uniforms: || {
        use crate::uniforms::Layout;
        vec![
            Layout::of::<ObjectLightUniforms>(paths_source()),
            Layout::of::<crate::uniforms::FrameObjects>(paths_source()),
        ]
    },
};

/// The water-object technique: the pass, the light-view resources for the
/// scene's refractive objects, and whether their paths still hold (they
/// depend only on the scene, so they are made once per scene).
pub(crate) struct WaterObjects {
    pub pass: WaterObjectPass,
    /// Back faces and the image behind them at the current screen size,
    /// when the scene has refractive objects (`Technique::resize`).
    targets: Option<ObjectTargets>,
    pub light: ObjectLight,
    pub current: bool,
    /// The liquid's faces from the sun where it is drawn by screen-space
    /// fluid rendering (`liquid_screen_space`, linked by the registry).
    pub liquid_faces: Option<SunFaces>,
}

/// The box holding everything drawn as clear water: the refractive
/// objects and the liquid's surface mesh.
pub fn refractive_bounds(
    geometry: &SceneGeometry,
    scene: &hydrolux_core::scene::Scene,
) -> Option<(glam::Vec3, glam::Vec3)> {
    let liquid = scene.liquid_light_bounds().map(|(lo, hi)| (lo.into(), hi.into()));
    match (geometry.refractive_bounds(), liquid) {
        (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
        (a, b) => a.or(b),
    }
}

/// Whether the camera's lens can be inside a clear object or the liquid's
/// mesh: within their box (and a margin for the near plane).
fn camera_may_be_inside(frame: &FrameContext, liquid: bool) -> bool {
    let geometry = &frame.shared.geometry;
    let liquid = liquid.then(|| frame.scene.liquid_mesh_bounds()).flatten();
    let boxes = [geometry.refractive_bounds(), liquid.map(|(lo, hi)| (lo.into(), hi.into()))];
    let eye = frame.plan.camera.position;
    boxes.into_iter().flatten().any(|(lo, hi): (glam::Vec3, glam::Vec3)| {
        let margin = glam::Vec3::splat(INSIDE_MARGIN);
        eye.cmpge(lo - margin).all() && eye.cmple(hi + margin).all()
    })
}

impl WaterObjects {
    /// Light-view texels per side for `scene` (1 without refractive objects).
    pub fn resolution(geometry: &SceneGeometry, scene: &hydrolux_core::scene::Scene) -> u32 {
        if refractive_bounds(geometry, scene).is_some() {
            scene.godrays.object_resolution
        } else {
            1
        }
    }
}

impl Technique for WaterObjects {
    fn create(
        shared: &crate::technique::Shared,
        scene: &hydrolux_core::scene::Scene,
    ) -> Result<Self, crate::error::RenderError> {
        let (device, l) = (&shared.device, &shared.layouts);
        let pass = WaterObjectPass::new(device, &l.globals, &l.frame_only, &shared.meshes);
        let light = pass.create_light(device, Self::resolution(&shared.geometry, scene));
        Ok(WaterObjects { pass, targets: None, light, current: false, liquid_faces: None })
    }

    fn set_scene(
        &mut self,
        shared: &crate::technique::Shared,
        _old: &hydrolux_core::scene::Scene,
        new: &hydrolux_core::scene::Scene,
    ) -> Result<bool, crate::error::RenderError> {
        self.current = false;
        let resolution = Self::resolution(&shared.geometry, new);
        let changed = resolution != self.light.resolution;
        if changed {
            self.light = self.pass.create_light(&shared.device, resolution);
        }
        Ok(changed)
    }

    fn resize(&mut self, shared: &crate::technique::Shared, t: &crate::targets::Targets) {
        self.targets = t
            .settings
            .refractive_objects
            .then(|| self.pass.create_targets(&shared.device, t.size, &t.depth_view));
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        let shared = frame.shared;
        let liquid = frame.published.liquid.as_ref().and_then(|l| l.mesh_for(frame.plan));
        // The fluid view draws the particles instead.
        let liquid =
            liquid.filter(|_| !crate::simulation::liquid::draw::drawn_as_points(frame.scene));
        match stage {
            Stage::Light if let Some(o) = frame.plan.object_light.filter(|o| o.due) => {
                // The error view comparing surfaces draws the liquid two
                // ways a frame: each drawing traces its own light.
                let compared = frame.scene.render.view == hydrolux_core::scene::DebugView::Error
                    && crate::error_view::compares_surfaces(frame.scene);
                self.pass.prepare(shared, encoder, &light_uniforms(&o), compared);
                let things = ClearThings {
                    meshes: &shared.meshes,
                    geometry: &shared.geometry,
                    view: &shared.views.object_light,
                    liquid,
                    objects: true,
                };
                // Not in the reference drawing of the error view (its mesh).
                let liquid_faces = self.liquid_faces.as_ref().filter(|_| {
                    liquid.is_none()
                        && crate::simulation::liquid::screen_space::drawn_screen_space(frame.scene)
                });
                self.pass.record_light(
                    encoder,
                    &shared.frame_only,
                    &things,
                    &self.light,
                    liquid_faces,
                    timer,
                );
                // The liquid changes every frame; the objects only when they
                // move (drawn again the frame after).
                shared.geometry.take_refractive_moved();
                self.current = liquid.is_none() && liquid_faces.is_none() && !compared;
            }
            Stage::Composite => {
                let targets = frame.targets();
                // (The liquid drawn by screen-space fluid rendering is in
                // the light view, not here: it draws itself.)
                let anything = liquid.is_some() || shared.geometry.has_refractive();
                if let Some(object_targets) = self.targets.as_ref().filter(|_| anything) {
                    let things = ClearThings {
                        meshes: &shared.meshes,
                        geometry: &shared.geometry,
                        view: &shared.views.main,
                        liquid,
                        objects: true,
                    };
                    self.pass.record_camera(
                        encoder,
                        &frame.bound.globals,
                        &things,
                        object_targets,
                        (&targets.hdr, &targets.hdr_view),
                        camera_may_be_inside(frame, liquid.is_some()),
                        timer,
                    );
                }
            }
            _ => {}
        }
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        WaterObjects::dump(self, name, ctx)
    }
}
