//! The ordered registry of techniques. One line per technique in
//! [`registry!`] below declares it: the renderer holds it by that name,
//! walks it in this order for every stage of a frame (`Technique`), and the
//! offline checks validate its shaders and uniform layouts (`TechniqueInfo`).
//! The passes import the shader resolver, the uniform types and the trait;
//! neither the resolver nor the uniforms import a pass, and no pass imports
//! the renderer.

use crate::error::RenderError;
use crate::passes::{antialias, caustics, geometry, godrays, sky, tonemap, water, water_object};
use crate::plan::World;
use crate::simulation::liquid::draw as liquid_points;
use crate::simulation::liquid::screen_space as liquid_screen_space;
use crate::simulation::liquid::white_water_draw as liquid_white_water;
use crate::simulation::whitewater::draw as particles;
use crate::technique::{Bound, Shared, Technique, TechniqueInfo};
use hydrolux_core::scene::Scene;
use hydrolux_core::sky::SkyParams;

macro_rules! registry {
    ($($field:ident: $ty:ty => $info:path),* $(,)?) => {
        /// Every technique of the frame, by name, in frame order.
        pub(crate) struct Techniques {
            $(pub $field: $ty),*
        }

        impl Techniques {
            /// Build every technique for `scene`, in registry order, and
            /// link them.
            pub fn new(shared: &Shared, scene: &Scene) -> Result<Self, RenderError> {
                let mut t = Techniques { $($field: crate::error::catch_gpu_errors(
                    &shared.device,
                    || format!("creating the {} technique", stringify!($field)),
                    || <$ty as Technique>::create(shared, scene),
                )?),* };
                t.connect(shared, scene);
                Ok(t)
            }

            /// The scene was edited; returns whether a resource the shared
            /// bind groups hold was replaced.
            pub fn set_scene(
                &mut self,
                shared: &Shared,
                old: &Scene,
                new: &Scene,
            ) -> Result<bool, RenderError> {
                let mut rebind = false;
                for t in self.each_mut() {
                    rebind |= t.set_scene(shared, old, new)?;
                }
                self.connect(shared, new);
                Ok(rebind)
            }

            /// Each technique, in frame order.
            pub fn each_mut(&mut self) -> Vec<&mut dyn Technique> {
                vec![$(&mut self.$field as &mut dyn Technique),*]
            }

            pub fn each(&self) -> Vec<&dyn Technique> {
                vec![$(&self.$field as &dyn Technique),*]
            }
        }

        /// The frame's techniques by name, in frame order.
        pub(crate) const ORDER: &[&str] = &[$(stringify!($field)),*];

        /// The frame's techniques, then the framework's services that build
        /// shaders (the frame globals, the probe, the error view's frame
        /// mode, mip chains, the medium copy). A technique's parts (the
        /// water's ray tracing) are in its own `INFO`.
        pub(crate) const TECHNIQUES: &[TechniqueInfo] = &[
            $($info,)*
            FRAME_INFO,
            crate::probe::INFO,
            crate::error_view::INFO,
            crate::mips::INFO,
            crate::targets::MEDIUM_COPY_INFO,
        ];
    };
}

registry! {
    sky: sky::SkyPass => sky::INFO,
    particles: particles::Particles => particles::INFO,
    caustics: caustics::Caustics => caustics::INFO,
    geometry: geometry::Geometry => geometry::INFO,
    liquid_points: liquid_points::LiquidPoints => liquid_points::INFO,
    liquid_screen_space: liquid_screen_space::LiquidScreenSpace => liquid_screen_space::INFO,
    water_objects: water_object::WaterObjects => water_object::INFO,
    liquid_white_water: liquid_white_water::LiquidWhiteWaterDraw => liquid_white_water::INFO,
    water: water::WaterPass => water::INFO,
    godrays: godrays::GodRays => godrays::INFO,
    antialias: antialias::TemporalAntialias => antialias::INFO,
    tonemap: tonemap::TonemapPass => tonemap::INFO,
}

/// The frame globals, checked against the water shader (which imports them).
const FRAME_INFO: TechniqueInfo = TechniqueInfo {
    name: "frame",
    dumps: &[crate::info::DumpKind {
        name: "hdr",
        shape: crate::info::DumpShape::Grid,
        missing: |_| None,
    }],
    shaders: Vec::new,
    uniforms: || {
        let src = crate::passes::water::source;
        vec![
            crate::uniforms::Layout::of::<crate::uniforms::FrameUniforms>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameView>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameLight>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameWater>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameSurface>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameProjective>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameShadow>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameFog>(src()),
            crate::uniforms::Layout::of::<crate::uniforms::FrameModes>(src()),
        ]
    },
};

/// Samplers the frame globals bind.
pub(crate) struct GlobalSamplers {
    sky: wgpu::Sampler,
    shadow: wgpu::Sampler,
    caustics: wgpu::Sampler,
}

impl GlobalSamplers {
    pub fn new(device: &wgpu::Device) -> Self {
        let linear = wgpu::FilterMode::Linear;
        GlobalSamplers {
            sky: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("sky"),
                mag_filter: linear,
                min_filter: linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            shadow: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow"),
                mag_filter: linear,
                min_filter: linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            caustics: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("caustic map"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: linear,
                min_filter: linear,
                ..Default::default()
            }),
        }
    }
}

impl Techniques {
    /// The bind groups over what techniques write and others read: the
    /// frame globals (group 0: the frame's uniforms and what the sky,
    /// geometry's shadow map, caustics and water objects wrote), the
    /// shadow map's values, and the published surface.
    pub fn bound(
        &self,
        shared: &Shared,
        samplers: &GlobalSamplers,
        published: &crate::simulation::Published,
    ) -> Bound {
        let tv = wgpu::BindingResource::TextureView;
        let sampler = wgpu::BindingResource::Sampler;
        let globals = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &shared.layouts.globals,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: shared.frame_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry { binding: 1, resource: self.sky.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&self.sky.cube_view) },
                wgpu::BindGroupEntry { binding: 3, resource: sampler(&samplers.sky) },
                wgpu::BindGroupEntry { binding: 4, resource: tv(&self.geometry.shadow.view) },
                wgpu::BindGroupEntry { binding: 5, resource: sampler(&samplers.shadow) },
                wgpu::BindGroupEntry { binding: 6, resource: tv(&self.caustics.map.view) },
                wgpu::BindGroupEntry { binding: 7, resource: sampler(&samplers.caustics) },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: tv(&self.water_objects.light.map_view),
                },
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: self.sky.environment_brdf.as_entire_binding(),
                },
            ],
        });
        let shadow_values = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow values"),
            layout: &shared.layouts.shadow_values,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: tv(&self.geometry.shadow.view),
            }],
        });
        Bound { globals, surface: published.surface().group.clone(), shadow_values }
    }

    /// What the frame plan needs to know of the techniques and the
    /// published surface.
    pub fn world(
        &self,
        shared: &Shared,
        scene: &hydrolux_core::scene::Scene,
        surface: &crate::simulation::published::SurfaceState,
        sky: SkyParams,
    ) -> World {
        World {
            shadow_bounds: shared.geometry.shadow_bounds(),
            refractive_bounds: crate::passes::water_object::refractive_bounds(
                &shared.geometry,
                scene,
            ),
            has_geometry: shared.geometry.triangle_count > 0,
            vertical_reach: surface.vertical_reach,
            cull_margin: surface.bounds_margin,
            surface_moving: surface.moving,
            unresolved_variance: surface.unresolved_variance,
            shadow_resolution: self.geometry.shadow.resolution,
            object_light_resolution: self.water_objects.light.resolution,
            sky,
            sky_irradiance: self.sky.irradiance,
            sky_light: self.sky.light,
            caustics_current: self.caustics.current,
            object_light_current: self.water_objects.current && !shared.geometry.refractive_moved(),
            occlusion: crate::uniforms::FrameOcclusion::of(&shared.geometry.occluders()),
            jitter_px: self.antialias.jitter_px(scene),
        }
    }

    /// The sun or sky changed: bake the sky again.
    pub fn set_sky(&mut self, queue: &wgpu::Queue, sky: SkyParams) {
        let twin = hydrolux_core::sky::Sky::new(sky);
        self.sky.irradiance = hydrolux_core::sky::sky_irradiance_up(&twin);
        self.sky.light = hydrolux_core::irradiance::sky_light(&twin);
        self.sky.prepare(queue, sky);
    }

    /// The anti-aliasing's history starts again with the next frame.
    pub fn restart_history(&mut self) {
        self.antialias.reset();
    }

    /// The surface changed outside the clock (a caller's heightfield):
    /// what is computed from it is due again.
    pub fn surface_edited(&mut self) {
        self.caustics.current = false;
    }

    /// Links between techniques: what one writes and another reads. The
    /// god rays draw the refractive objects' paths (their buffer belongs to
    /// the water objects, which write it) into the fog.
    fn connect(&mut self, shared: &Shared, scene: &Scene) {
        let light = &self.water_objects.light;
        self.water_objects.liquid_faces =
            self.liquid_screen_space.sun_faces(shared, scene, light.resolution);
        let tubes =
            self.godrays.pass.bind_tubes(&shared.device, light.tubes.clone(), light.resolution);
        self.godrays.object_tubes = Some(tubes);
    }
}

/// Every dump the techniques, the frame, the probe and the simulations
/// declare (what `hydrolux render --dump` offers), in registry order.
pub fn dump_kinds() -> Vec<&'static crate::info::DumpKind> {
    TECHNIQUES.iter().chain(crate::simulation::SIMULATIONS).flat_map(|t| t.dumps).collect()
}

/// Every technique's and simulation's shaders and uniforms (what the
/// offline checks validate).
#[cfg(test)]
pub(crate) fn validated() -> impl Iterator<Item = &'static TechniqueInfo> {
    TECHNIQUES.iter().chain(crate::simulation::SIMULATIONS)
}

/// The names of the renderer's simulations, in the order they step.
pub fn simulation_names() -> Vec<&'static str> {
    crate::simulation::SIMULATIONS.iter().map(|s| s.name).collect()
}

/// The names of the renderer's techniques, in frame order.
pub fn technique_names() -> Vec<&'static str> {
    TECHNIQUES[..ORDER.len()].iter().map(|t| t.name).collect()
}

#[cfg(test)]
mod tests {
    use crate::uniforms::{Field, Layout};

    fn parse(name: &str, source: &str) -> naga::Module {
        naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)))
    }

    #[test]
    fn every_shader_composes_parses_and_validates() {
        let shaders: Vec<_> = super::validated().flat_map(|t| (t.shaders)()).collect();
        assert!(shaders.len() >= 20, "{} shaders", shaders.len());
        for (name, source) in shaders {
            let module = parse(&name, &source);
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        }
    }

    /// naga's members of a WGSL struct: (name, offset, size).
    fn wgsl_fields(module: &naga::Module, ty: &naga::Type) -> (usize, Vec<Field>) {
        let size = ty.inner.size(module.to_ctx()) as usize;
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            return (size, Vec::new());
        };
        let fields = members
            .iter()
            .map(|m| Field {
                name: m.name.clone().map_or("", |n| n.leak()),
                offset: m.offset as usize,
                size: module.types[m.ty].inner.size(module.to_ctx()) as usize,
            })
            .collect();
        (size, fields)
    }

    #[test]
    fn every_uniform_field_has_the_wgsl_offset_and_size_by_name() {
        let layouts: Vec<Layout> = super::validated().flat_map(|t| (t.uniforms)()).collect();
        assert!(layouts.len() >= 20, "{} uniform structs", layouts.len());
        for l in layouts {
            let module = parse(l.wgsl_name, &l.source);
            let (_, ty) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(l.wgsl_name))
                .unwrap_or_else(|| panic!("struct {} not found in its shader", l.wgsl_name));
            let (size, wgsl) = wgsl_fields(&module, ty);
            assert_eq!(size, l.size, "{}: WGSL {size} bytes, Rust {}", l.wgsl_name, l.size);
            if l.fields.is_empty() {
                continue; // a storage record checked by size (e.g. `Tube`)
            }
            let names = |f: &[Field]| f.iter().map(|f| f.name).collect::<Vec<_>>();
            assert_eq!(names(&wgsl), names(&l.fields), "{}: fields differ", l.wgsl_name);
            for (w, r) in wgsl.iter().zip(&l.fields) {
                assert_eq!(
                    (w.offset, w.size),
                    (r.offset, r.size),
                    "{}.{}: WGSL (offset, size) vs Rust",
                    l.wgsl_name,
                    w.name
                );
            }
        }
    }

    #[test]
    fn a_swapped_field_would_be_caught() {
        // The check above compares names in order and offsets by name: a
        // Rust struct whose two vec4 fields are swapped has the same size
        // but not the same field order.
        let wgsl =
            "struct S { a: vec4<f32>, b: vec4<u32> }\n@group(0) @binding(0) var<uniform> s: S;";
        let module = parse("S", wgsl);
        let (_, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("S")).unwrap();
        let (_, fields) = wgsl_fields(&module, ty);
        let swapped =
            [Field { name: "b", offset: 0, size: 16 }, Field { name: "a", offset: 16, size: 16 }];
        assert_ne!(fields.iter().map(|f| f.name).collect::<Vec<_>>(), ["b", "a"]);
        assert_eq!(fields[0].offset, 0);
        assert_ne!(fields[0].name, swapped[0].name);
    }

    #[test]
    fn each_technique_is_named_as_its_registry_field() {
        assert_eq!(super::technique_names(), super::ORDER);
    }

    #[test]
    fn technique_names_are_unique() {
        let mut names: Vec<_> = super::validated().map(|t| t.name).collect();
        let count = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), count);
    }
}
