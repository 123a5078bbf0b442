//! The `liquid_screen_space` technique: the liquid's published particles
//! drawn by screen-space fluid rendering (`fluid.surface = "screen_space"`;
//! `screen_space.wgsl`, CPU twin `hydrolux_core::fluid::screen_space`).
//! No mesh: in the Composite stage, before the refractive objects (so a
//! glass shows the liquid inside it), the image so far is copied; the
//! particles' spheres are splatted into a depth image (the nearest front's
//! clip w, depth-tested) and a thickness image (chords added); the
//! narrow-range filter runs across and then down; and a full-screen pass
//! shades each covered pixel as clear water over the image. Its images
//! follow the frame's size and are made the first frame a scene draws it.
//!
//! Its caustics: in the Light stage, while the refractive things' light
//! paths are due (`passes/water_object`), the same splats and filter run
//! in their orthographic light view (CPU twin `SunView`), and that pass
//! draws the faces the light enters and leaves from the filtered maps
//! (`SunFaces`, handed to it when the techniques are linked) beside the
//! glasses' faces: its paths then refract through the liquid as through a
//! mesh.

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::info::{DumpData, DumpKind, DumpShape, TechniqueInfo};
use crate::shaders;
use crate::simulation::published::LiquidState;
use crate::technique::{DumpContext, FrameContext, Shared, Stage, Technique};
use crate::timing::GpuTimer;
use crate::uniforms::uniform;
use hydrolux_core::fluid::screen_space::{self as twin, FluidMaps, ScreenSpaceParams};
use hydrolux_core::scene::{FluidSurface, Scene};

uniform! { ScreenSpaceParams;
    /// WGSL `ScreenSpaceParams` (simulation/liquid/screen_space.wgsl).
    pub(crate) struct ScreenSpaceUniforms {
        pub sun_view_proj: [[f32; 4]; 4],
        pub sun_inv_view_proj: [[f32; 4]; 4],
        pub radius: f32,
        pub volume_share: f32,
        pub filter_radius: f32,
        pub threshold: f32,
        pub clamp: f32,
        pub pixels_per_metre: f32,
        pub max_reach: u32,
        pub count: u32,
        pub perspective: u32,
        pub sun_resolution: f32,
        pub sun_span: f32,
        pub ior: f32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("screen_space.wgsl"))
}

/// Whether the liquid is drawn this way (the fluid view draws points).
pub(crate) fn drawn_screen_space(scene: &Scene) -> bool {
    scene.fluid.surface == FluidSurface::ScreenSpace && !super::draw::drawn_as_points(scene)
}

/// The depths and the filtered maps hold float bits: downlevel OpenGL
/// renders no 32-bit float colour.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const THICKNESS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
const FILTERED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// The pipelines and layouts, made the first time a scene draws this way.
struct Pipelines {
    params: wgpu::Buffer,
    splat_layout: wgpu::BindGroupLayout,
    filter_layout: wgpu::BindGroupLayout,
    shade_layout: wgpu::BindGroupLayout,
    depth: wgpu::RenderPipeline,
    thickness: wgpu::RenderPipeline,
    across: wgpu::RenderPipeline,
    down: wgpu::RenderPipeline,
    shade: wgpu::RenderPipeline,
    /// From the sun: the splats, and the faces drawn into the refractive
    /// things' light-view images.
    depth_sun: wgpu::RenderPipeline,
    back_sun: wgpu::RenderPipeline,
    sun_front: wgpu::RenderPipeline,
    sun_back: wgpu::RenderPipeline,
}

/// One render pipeline of `screen_space.wgsl` over the globals and one
/// group of its own.
struct PipelineSpec<'a> {
    label: &'a str,
    layout: &'a wgpu::BindGroupLayout,
    vertex: &'a str,
    fragment: &'a str,
    target: wgpu::ColorTargetState,
    depth: Option<wgpu::DepthStencilState>,
    /// Drawn inside the refractive things' light passes, whose group 0 is
    /// the frame alone.
    frame_only: bool,
}

/// A depth test keeping the nearest: `Greater` with the camera's reversed
/// Z, `Less` in the sun's view.
fn nearest(compare: wgpu::CompareFunction) -> Option<wgpu::DepthStencilState> {
    Some(wgpu::DepthStencilState {
        format: wgpu::TextureFormat::Depth32Float,
        depth_write_enabled: Some(true),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    })
}

/// A target every splat blends into by `operation` (added chords, the
/// farthest back).
fn blended(format: wgpu::TextureFormat, operation: wgpu::BlendOperation) -> wgpu::ColorTargetState {
    let c = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation,
    };
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState { color: c, alpha: c }),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

impl Pipelines {
    fn new(shared: &Shared) -> Self {
        let device = &shared.device;
        let (vs, fs) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT);
        let unfiltered = |b| texture_entry(b, fs, wgpu::TextureViewDimension::D2, false);
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let splat_layout = layout(
            "liquid screen space splat",
            &[storage_entry(0, vs | fs, true), storage_entry(1, vs, true), unfiltered(2)],
        );
        let bits = |b| uint_texture_entry(b, fs);
        let filter_layout = layout(
            "liquid screen space filter",
            &[storage_entry(0, fs, true), bits(3), unfiltered(4)],
        );
        let shade_layout = layout(
            "liquid screen space shade",
            &[storage_entry(0, fs, true), unfiltered(2), bits(3), unfiltered(5)],
        );
        let params = storage_buffer(
            device,
            "liquid screen space",
            std::mem::size_of::<ScreenSpaceUniforms>() as u64,
            wgpu::BufferUsages::empty(),
        );
        let module = shader(device, "liquid screen space", &source());
        let make = |spec: PipelineSpec| {
            let frame =
                if spec.frame_only { &shared.layouts.frame_only } else { &shared.layouts.globals };
            let layout = pipeline_layout(device, spec.label, &[frame, spec.layout]);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(spec.label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(spec.vertex),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: spec.depth,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(spec.fragment),
                    compilation_options: Default::default(),
                    targets: &[Some(spec.target)],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let depth = make(PipelineSpec {
            label: "liquid depth splat",
            layout: &splat_layout,
            vertex: "vs_sphere",
            fragment: "fs_depth",
            target: DEPTH_FORMAT.into(),
            depth: nearest(wgpu::CompareFunction::Greater),
            frame_only: false,
        });
        let thickness = make(PipelineSpec {
            label: "liquid thickness splat",
            layout: &splat_layout,
            vertex: "vs_sphere",
            fragment: "fs_thickness",
            target: blended(THICKNESS_FORMAT, wgpu::BlendOperation::Add),
            depth: None,
            frame_only: false,
        });
        let depth_sun = make(PipelineSpec {
            label: "liquid depth splat from the sun",
            layout: &splat_layout,
            vertex: "vs_sphere_sun",
            fragment: "fs_depth_sun",
            target: DEPTH_FORMAT.into(),
            depth: nearest(wgpu::CompareFunction::Less),
            frame_only: false,
        });
        let back_sun = make(PipelineSpec {
            label: "liquid back splat from the sun",
            layout: &splat_layout,
            vertex: "vs_sphere_sun",
            fragment: "fs_back_sun",
            target: blended(THICKNESS_FORMAT, wgpu::BlendOperation::Max),
            depth: None,
            frame_only: false,
        });
        let face = |label, fragment| {
            make(PipelineSpec {
                label,
                layout: &filter_layout,
                vertex: "vs_fullscreen",
                fragment,
                target: crate::passes::water_object::FACES_FORMAT.into(),
                depth: nearest(wgpu::CompareFunction::Less),
                frame_only: true,
            })
        };
        let sun_front = face("liquid faces from the sun", "fs_sun_front");
        let sun_back = face("liquid back faces from the sun", "fs_sun_back");
        let filter = |label, fragment| {
            make(PipelineSpec {
                label,
                layout: &filter_layout,
                vertex: "vs_fullscreen",
                fragment,
                target: FILTERED_FORMAT.into(),
                depth: None,
                frame_only: false,
            })
        };
        let across = filter("liquid filter across", "fs_filter_across");
        let down = filter("liquid filter down", "fs_filter_down");
        let shade = make(PipelineSpec {
            label: "liquid screen space shade",
            layout: &shade_layout,
            vertex: "vs_fullscreen",
            fragment: "fs_shade",
            target: crate::formats::HDR_FORMAT.into(),
            depth: None,
            frame_only: false,
        });
        Pipelines {
            params,
            splat_layout,
            filter_layout,
            shade_layout,
            depth,
            thickness,
            across,
            down,
            shade,
            depth_sun,
            back_sun,
            sun_front,
            sun_back,
        }
    }
}

/// One view's splatted and filtered images: the depth test, the nearest
/// fronts, the second image (the chords added, or the farthest back), the
/// filter's pass across and its result.
struct MapImages {
    depth_test: wgpu::TextureView,
    front: wgpu::Texture,
    front_view: wgpu::TextureView,
    thickness_view: wgpu::TextureView,
    across_view: wgpu::TextureView,
    filtered: wgpu::Texture,
    filtered_view: wgpu::TextureView,
}

impl MapImages {
    /// At `size`, labelled "liquid … `view`", the second image `second`.
    fn new(device: &wgpu::Device, size: (u32, u32), second: &str, view: &str) -> Self {
        use wgpu::TextureUsages as U;
        let image = |what: &str, format, usage| {
            let label = format!("liquid {what}{view}");
            let t = texture_2d(device, &label, size, format, U::TEXTURE_BINDING | usage);
            let v = t.create_view(&Default::default());
            (t, v)
        };
        let target = U::RENDER_ATTACHMENT | U::COPY_SRC;
        let (_, depth_test) =
            image("depth test", wgpu::TextureFormat::Depth32Float, U::RENDER_ATTACHMENT);
        let (front, front_view) = image("depth", DEPTH_FORMAT, target);
        let (_, thickness_view) = image(second, THICKNESS_FORMAT, target);
        let (_, across_view) = image("filtered across", FILTERED_FORMAT, target);
        let (filtered, filtered_view) = image("filtered", FILTERED_FORMAT, target);
        MapImages {
            depth_test,
            front,
            front_view,
            thickness_view,
            across_view,
            filtered,
            filtered_view,
        }
    }
}

/// The images at the frame's size and the bind groups over them.
struct Images {
    size: (u32, u32),
    /// The particle buffer the splat group binds.
    particles: wgpu::Buffer,
    maps: MapImages,
    behind: wgpu::Texture,
    splat_group: wgpu::BindGroup,
    across_group: wgpu::BindGroup,
    down_group: wgpu::BindGroup,
    shade_group: wgpu::BindGroup,
}

impl Images {
    fn new(
        device: &wgpu::Device,
        p: &Pipelines,
        size: (u32, u32),
        liquid: &LiquidState,
        scene_depth: &wgpu::TextureView,
    ) -> Self {
        use wgpu::TextureUsages as U;
        let maps = MapImages::new(device, size, "thickness", "");
        let MapImages { front_view, thickness_view, across_view, filtered_view, .. } = &maps;
        let behind = texture_2d(
            device,
            "liquid behind",
            size,
            crate::formats::HDR_FORMAT,
            U::TEXTURE_BINDING | U::COPY_DST,
        );
        let behind_view = behind.create_view(&Default::default());
        let tv = wgpu::BindingResource::TextureView;
        let group = |label, layout, entries: &[(u32, wgpu::BindingResource)]| {
            bind_group(device, label, layout, entries)
        };
        let params = p.params.as_entire_binding();
        let splat_group = group(
            "liquid splat",
            &p.splat_layout,
            &[(0, params.clone()), (1, liquid.particles.as_entire_binding()), (2, tv(scene_depth))],
        );
        let across_group = group(
            "liquid filter across",
            &p.filter_layout,
            &[(0, params.clone()), (3, tv(front_view)), (4, tv(thickness_view))],
        );
        let down_group = group(
            "liquid filter down",
            &p.filter_layout,
            // The thickness is the first pass's second channel (binding 4
            // is not read).
            &[(0, params.clone()), (3, tv(across_view)), (4, tv(thickness_view))],
        );
        let shade_group = group(
            "liquid shade",
            &p.shade_layout,
            &[(0, params), (2, tv(scene_depth)), (3, tv(filtered_view)), (5, tv(&behind_view))],
        );
        Images {
            size,
            particles: liquid.particles.clone(),
            maps,
            behind,
            splat_group,
            across_group,
            down_group,
            shade_group,
        }
    }
}

/// A bind group of `(binding, resource)` pairs.
fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    entries: &[(u32, wgpu::BindingResource)],
) -> wgpu::BindGroup {
    let entries: Vec<_> = entries
        .iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: resource.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// The maps made from the sun, at the refractive things' light-view
/// resolution, and the bind groups over them.
struct SunImages {
    resolution: u32,
    params: wgpu::Buffer,
    maps: MapImages,
    across_group: wgpu::BindGroup,
    down_group: wgpu::BindGroup,
    faces_group: wgpu::BindGroup,
    /// Bound where the camera's splats bind the scene's depth (the sun's
    /// splats read none).
    no_scene_depth: wgpu::TextureView,
    /// The splats' group, over the particle buffer it binds (made when
    /// the liquid publishes it).
    splat: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl SunImages {
    fn new(device: &wgpu::Device, p: &Pipelines, resolution: u32) -> Self {
        // The farthest back (m) in the thickness's place.
        let maps = MapImages::new(device, (resolution, resolution), "back", " from the sun");
        let params = storage_buffer(
            device,
            "liquid screen space from the sun",
            std::mem::size_of::<ScreenSpaceUniforms>() as u64,
            wgpu::BufferUsages::empty(),
        );
        let tv = wgpu::BindingResource::TextureView;
        let filter = |label, source| {
            bind_group(
                device,
                label,
                &p.filter_layout,
                &[(0, params.as_entire_binding()), (3, tv(source)), (4, tv(&maps.thickness_view))],
            )
        };
        let across_group = filter("liquid filter across from the sun", &maps.front_view);
        let down_group = filter("liquid filter down from the sun", &maps.across_view);
        let faces_group = filter("liquid faces from the sun", &maps.filtered_view);
        let (_, no_scene_depth) = image_1x1(device);
        SunImages {
            resolution,
            params,
            maps,
            across_group,
            down_group,
            faces_group,
            no_scene_depth,
            splat: None,
        }
    }
}

/// A 1×1 float image (a binding nothing reads).
fn image_1x1(device: &wgpu::Device) -> (wgpu::Texture, wgpu::TextureView) {
    let t = texture_2d(
        device,
        "liquid no scene depth",
        (1, 1),
        THICKNESS_FORMAT,
        wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let v = t.create_view(&Default::default());
    (t, v)
}

/// The liquid's faces from the sun, drawn by the refractive things' light
/// passes (`passes/water_object`) from the maps this technique filtered in
/// the Light stage before them.
#[derive(Clone)]
pub(crate) struct SunFaces {
    front: wgpu::RenderPipeline,
    back: wgpu::RenderPipeline,
    group: wgpu::BindGroup,
}

impl SunFaces {
    /// Into a pass over the face images (group 0, the frame alone, is the
    /// caller's): the faces the light enters, or those it leaves by.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, back: bool) {
        pass.set_pipeline(if back { &self.back } else { &self.front });
        pass.set_bind_group(1, &self.group, &[]);
        pass.draw(0..3, 0..1);
    }
}

#[derive(Default)]
pub(crate) struct LiquidScreenSpace {
    pipelines: Option<Pipelines>,
    images: Option<Images>,
    sun: Option<SunImages>,
}

/// The method's parameters for the GPU.
fn uniforms(
    scene: &Scene,
    liquid: &LiquidState,
    view_proj: glam::Mat4,
    size: (u32, u32),
) -> ScreenSpaceUniforms {
    let p = ScreenSpaceParams::of(&scene.fluid);
    let view =
        hydrolux_core::fluid::screen_mesh::ScreenView { view_proj, width: size.0, height: size.1 };
    ScreenSpaceUniforms {
        radius: p.radius,
        volume_share: p.volume_share,
        filter_radius: p.filter_radius,
        threshold: p.threshold,
        clamp: p.clamp,
        pixels_per_metre: twin::pixels_per_metre(&view),
        max_reach: twin::MAX_FILTER_PIXELS,
        count: liquid.count,
        perspective: 1,
        ..Default::default()
    }
}

/// The method's parameters from the sun, in the refractive things' light
/// view.
fn sun_uniforms(
    scene: &Scene,
    liquid: &LiquidState,
    light: &crate::plan::ObjectLightPlan,
) -> ScreenSpaceUniforms {
    let p = ScreenSpaceParams::of(&scene.fluid);
    let view = twin::SunView { view_proj: light.view_proj, resolution: light.resolution };
    let (_, _, span) = view.texel_ray(0.5, 0.5);
    ScreenSpaceUniforms {
        sun_view_proj: light.view_proj.to_cols_array_2d(),
        sun_inv_view_proj: light.view_proj.inverse().to_cols_array_2d(),
        radius: p.radius,
        volume_share: p.volume_share,
        filter_radius: p.filter_radius,
        threshold: p.threshold,
        clamp: p.clamp,
        pixels_per_metre: view.texels_per_metre(),
        max_reach: twin::MAX_FILTER_PIXELS,
        count: liquid.count,
        perspective: 0,
        sun_resolution: light.resolution as f32,
        sun_span: span,
        ior: scene.water.ior,
    }
}

/// A filtered image (two floats' bits a pixel) read back.
fn read_maps(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    filtered: &wgpu::Texture,
    (width, height): (u32, u32),
) -> FluidMaps {
    let bytes = read_texture(device, queue, filtered, 8);
    let values: &[f32] = bytemuck::cast_slice(&bytes); // float bits
    let mut maps = FluidMaps::empty(width, height);
    for (i, v) in values.chunks_exact(2).enumerate() {
        maps.depth[i] = v[0];
        maps.thickness[i] = v[1];
    }
    maps
}

/// One view's splats and filter: the nearest front (depth-tested against
/// `depth_test`, cleared to its far plane), the second image (the chords
/// added, or the farthest back), then the filter across and down.
struct SplatAndFilter<'a> {
    labels: [&'static str; 4],
    splat_group: &'a wgpu::BindGroup,
    front: (&'a wgpu::TextureView, &'a wgpu::RenderPipeline),
    depth_test: (&'a wgpu::TextureView, f32),
    second: (&'a wgpu::TextureView, &'a wgpu::RenderPipeline),
    across: (&'a wgpu::TextureView, &'a wgpu::BindGroup),
    down: (&'a wgpu::TextureView, &'a wgpu::BindGroup),
}

/// A colour attachment cleared to `clear` (or loaded).
fn attachment(
    view: &wgpu::TextureView,
    clear: Option<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        },
    }
}

impl LiquidScreenSpace {
    #[allow(clippy::too_many_arguments)]
    fn pass(
        encoder: &mut wgpu::CommandEncoder,
        label: &'static str,
        color: wgpu::RenderPassColorAttachment<'_>,
        depth: Option<(&wgpu::TextureView, f32)>,
        pipeline: &wgpu::RenderPipeline,
        globals: &wgpu::BindGroup,
        group: &wgpu::BindGroup,
        timer: Option<&mut GpuTimer>,
        (vertices, instances): (u32, u32),
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(color)],
            depth_stencil_attachment: depth.map(|(view, far)| {
                wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(far),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }
            }),
            timestamp_writes: timer.and_then(|t| t.render_writes(label)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, globals, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.draw(0..vertices, 0..instances);
    }

    /// The faces from the sun for `scene` at the refractive things' light
    /// view's `resolution`: `None` unless the liquid is drawn this way and
    /// that view holds it (then its maps are made at that resolution).
    pub(crate) fn sun_faces(
        &mut self,
        shared: &Shared,
        scene: &Scene,
        resolution: u32,
    ) -> Option<SunFaces> {
        if !drawn_screen_space(scene) || scene.liquid_light_bounds().is_none() || resolution <= 1 {
            self.sun = None;
            return None;
        }
        let pipelines = self.pipelines.get_or_insert_with(|| Pipelines::new(shared));
        if self.sun.as_ref().is_none_or(|s| s.resolution != resolution) {
            self.sun = Some(SunImages::new(&shared.device, pipelines, resolution));
        }
        let sun = self.sun.as_ref()?;
        Some(SunFaces {
            front: pipelines.sun_front.clone(),
            back: pipelines.sun_back.clone(),
            group: sun.faces_group.clone(),
        })
    }

    /// The sun's splats and filter, before the refractive things' light
    /// passes draw the faces from them.
    fn record_sun(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        let (Some(liquid), Some(p), Some(sun)) =
            (&frame.published.liquid, &self.pipelines, &self.sun)
        else {
            return;
        };
        let Some((_, splat)) = &sun.splat else { return };
        let work = SplatAndFilter {
            labels: [
                "liquid depth splat from the sun",
                "liquid back splat from the sun",
                "liquid filter across from the sun",
                "liquid filter down from the sun",
            ],
            splat_group: splat,
            front: (&sun.maps.front_view, &p.depth_sun),
            depth_test: (&sun.maps.depth_test, 1.0),
            second: (&sun.maps.thickness_view, &p.back_sun),
            across: (&sun.maps.across_view, &sun.across_group),
            down: (&sun.maps.filtered_view, &sun.down_group),
        };
        Self::splat_and_filter(encoder, p, &frame.bound.globals, (6, liquid.count), &work, timer);
    }

    /// `work`'s splats of `quads` (vertices, instances) and its filter.
    fn splat_and_filter(
        encoder: &mut wgpu::CommandEncoder,
        p: &Pipelines,
        globals: &wgpu::BindGroup,
        quads: (u32, u32),
        work: &SplatAndFilter,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let black = Some(wgpu::Color::TRANSPARENT);
        let [front_label, second_label, across_label, down_label] = work.labels;
        Self::pass(
            encoder,
            front_label,
            attachment(work.front.0, black),
            Some(work.depth_test),
            work.front.1,
            globals,
            work.splat_group,
            timer.as_deref_mut(),
            quads,
        );
        Self::pass(
            encoder,
            second_label,
            attachment(work.second.0, black),
            None,
            work.second.1,
            globals,
            work.splat_group,
            timer.as_deref_mut(),
            quads,
        );
        let passes = [
            (across_label, work.across.0, &p.across, work.across.1),
            (down_label, work.down.0, &p.down, work.down.1),
        ];
        for (label, view, pipeline, group) in passes {
            let color = attachment(view, black);
            let timer = timer.as_deref_mut();
            Self::pass(encoder, label, color, None, pipeline, globals, group, timer, (3, 1));
        }
    }

    /// The filtered maps from the sun of the last frame that made them.
    fn read_sun(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<(FluidMaps, Vec<f32>)> {
        let sun = self.sun.as_ref()?;
        let maps = read_maps(device, queue, &sun.maps.filtered, (sun.resolution, sun.resolution));
        let splatted = read_texture(device, queue, &sun.maps.front, 4);
        Some((maps, bytemuck::cast_slice(&splatted).to_vec()))
    }

    /// The filtered depth and thickness of the last frame drawn this way.
    fn read_filtered(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<FluidMaps> {
        let images = self.images.as_ref()?;
        Some(read_maps(device, queue, &images.maps.filtered, images.size))
    }

    /// The splatted depth (before the filter) of the last frame.
    fn read_splatted_depth(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Vec<f32>> {
        let images = self.images.as_ref()?;
        let bytes = read_texture(device, queue, &images.maps.front, 4);
        Some(bytemuck::cast_slice(&bytes).to_vec())
    }
}

impl Technique for LiquidScreenSpace {
    fn create(_shared: &Shared, _scene: &Scene) -> Result<Self, RenderError> {
        Ok(LiquidScreenSpace::default())
    }

    fn resize(&mut self, _shared: &Shared, _targets: &crate::targets::Targets) {
        // The scene's depth is a new view: bind it anew.
        self.images = None;
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        let Some(liquid) = &frame.published.liquid else { return };
        if !drawn_screen_space(frame.scene) {
            return;
        }
        let pipelines = self.pipelines.get_or_insert_with(|| Pipelines::new(frame.shared));
        if let (Some(sun), Some(light)) = (&mut self.sun, &frame.plan.object_light) {
            if sun.splat.as_ref().is_none_or(|(b, _)| *b != liquid.particles) {
                let tv = wgpu::BindingResource::TextureView;
                let group = bind_group(
                    &frame.shared.device,
                    "liquid splat from the sun",
                    &pipelines.splat_layout,
                    &[
                        (0, sun.params.as_entire_binding()),
                        (1, liquid.particles.as_entire_binding()),
                        (2, tv(&sun.no_scene_depth)),
                    ],
                );
                sun.splat = Some((liquid.particles.clone(), group));
            }
            let u = sun_uniforms(frame.scene, liquid, light);
            queue.write_buffer(&sun.params, 0, bytemuck::bytes_of(&u));
        }
        let Some(targets) = frame.targets else { return };
        let stale = self
            .images
            .as_ref()
            .is_none_or(|i| i.size != targets.size || i.particles != liquid.particles);
        if stale {
            self.images = Some(Images::new(
                &frame.shared.device,
                pipelines,
                targets.size,
                liquid,
                &targets.depth_view,
            ));
        }
        let u = uniforms(frame.scene, liquid, frame.plan.matrices.view_proj, targets.size);
        queue.write_buffer(&pipelines.params, 0, bytemuck::bytes_of(&u));
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        mut timer: Option<&mut GpuTimer>,
    ) {
        if !drawn_screen_space(frame.scene) {
            return;
        }
        if stage == Stage::Light {
            // While the refractive things' light paths are due (they read
            // what this draws).
            if frame.plan.object_light.is_some_and(|o| o.due) && !frame.plan.liquid_reference {
                self.record_sun(encoder, frame, timer);
            }
            return;
        }
        if stage != Stage::Composite {
            return;
        }
        let (Some(liquid), Some(p), Some(images)) =
            (&frame.published.liquid, &self.pipelines, &self.images)
        else {
            return;
        };
        let targets = frame.targets();
        let globals = &frame.bound.globals;
        encoder.copy_texture_to_texture(
            targets.hdr.as_image_copy(),
            images.behind.as_image_copy(),
            targets.hdr.size(),
        );
        let work = SplatAndFilter {
            labels: [
                "liquid depth splat",
                "liquid thickness splat",
                "liquid filter across",
                "liquid filter down",
            ],
            splat_group: &images.splat_group,
            front: (&images.maps.front_view, &p.depth),
            // Reversed Z: the far plane is 0.
            depth_test: (&images.maps.depth_test, 0.0),
            second: (&images.maps.thickness_view, &p.thickness),
            across: (&images.maps.across_view, &images.across_group),
            down: (&images.maps.filtered_view, &images.down_group),
        };
        let quads = (6, liquid.count);
        Self::splat_and_filter(encoder, p, globals, quads, &work, timer.as_deref_mut());
        Self::pass(
            encoder,
            "liquid screen space shade",
            attachment(&targets.hdr_view, None),
            None,
            &p.shade,
            globals,
            &images.shade_group,
            timer,
            (3, 1),
        );
    }

    fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        (name == "fluid_screen_space").then(|| {
            let maps = self.read_filtered(ctx.device, ctx.queue).ok_or_else(|| {
                "no frame has drawn the liquid by screen-space fluid rendering yet".to_string()
            })?;
            let data = maps.depth.iter().zip(&maps.thickness).flat_map(|(&z, &t)| [z, t]).collect();
            Ok(DumpData::Floats {
                columns: maps.width as usize,
                rows: maps.height as usize,
                channels: 2,
                data,
                note: Some(
                    "per pixel, rows from the top: the filtered depth (the clip w, m; 0 where no liquid) and thickness (m)"
                        .into(),
                ),
            })
        })
    }
}

fn not_screen_space(scene: &Scene) -> Option<&'static str> {
    if !scene.fluid.enabled() {
        Some("the scene has no volumetric liquid (it needs [[fluid.sources]])")
    } else if scene.fluid.surface != FluidSurface::ScreenSpace {
        Some(
            "the liquid is not drawn by screen-space fluid rendering (it needs fluid.surface = \"screen_space\")",
        )
    } else {
        None
    }
}

/// What one frame of screen-space fluid rendering made, for its tests.
pub struct ScreenSpaceReadback {
    /// The camera it was drawn for.
    pub view: hydrolux_core::fluid::screen_mesh::ScreenView,
    pub eye: glam::Vec3,
    /// The nearest fronts as splatted (clip w, 0 where empty).
    pub splatted_depth: Vec<f32>,
    /// After the narrow-range filter.
    pub filtered: FluidMaps,
}

/// What the last frame made of the liquid from the sun, for its tests.
pub struct SunReadback {
    /// The refractive things' light view it was made in.
    pub view: twin::SunView,
    /// The nearest fronts as splatted (m from the near plane, 0 where empty).
    pub splatted_depth: Vec<f32>,
    /// After the narrow-range filter.
    pub filtered: FluidMaps,
}

impl crate::renderer::Renderer {
    /// The liquid's maps from the sun after the last frame; `None` unless
    /// it is drawn by screen-space fluid rendering and the refractive
    /// things' light view holds it.
    pub fn read_liquid_screen_space_sun(&self) -> Option<SunReadback> {
        let t = &self.techniques.liquid_screen_space;
        let light = self.last_plan.as_ref()?.object_light?;
        let (filtered, splatted_depth) = t.read_sun(self.device(), self.queue())?;
        let view = twin::SunView { view_proj: light.view_proj, resolution: light.resolution };
        Some(SunReadback { view, splatted_depth, filtered })
    }

    /// The liquid's screen-space images after the last frame; `None` unless
    /// it was drawn by screen-space fluid rendering.
    pub fn read_liquid_screen_space(&self) -> Option<ScreenSpaceReadback> {
        let t = &self.techniques.liquid_screen_space;
        let plan = self.last_plan.as_ref()?;
        let filtered = t.read_filtered(self.device(), self.queue())?;
        let splatted_depth = t.read_splatted_depth(self.device(), self.queue())?;
        Some(ScreenSpaceReadback {
            view: hydrolux_core::fluid::screen_mesh::ScreenView {
                view_proj: plan.matrices.view_proj,
                width: filtered.width,
                height: filtered.height,
            },
            eye: plan.camera.position,
            splatted_depth,
            filtered,
        })
    }
}

/// The liquid's screen-space draw, validated offline.
pub(crate) const INFO: TechniqueInfo = TechniqueInfo {
    name: "liquid_screen_space",
    dumps: &[DumpKind {
        name: "fluid_screen_space",
        shape: DumpShape::Grid,
        missing: not_screen_space,
    }],
    shaders: || vec![("liquid screen space".into(), source())],
    uniforms: || vec![crate::uniforms::Layout::of::<ScreenSpaceUniforms>(source())],
};
