//! Rust twins of the WGSL uniform structs. Each is declared with
//! [`uniform!`], which makes it `#[repr(C)]` + bytemuck and records every
//! field's name, offset and size; a test (`registry::tests`) checks them by
//! name against naga's layout of the WGSL struct, so two swapped fields or a
//! missing pad fail, not only a size change.
//!
//! The per-frame globals (`Frame`, shaders/frame.wgsl) are one struct per
//! concern, all declared here (so that no pass is imported to build the
//! frame) and filled by the frame plan (`plan.rs`); techniques declare their
//! own uniform structs in their folders.

// The layout records are read by the offline checks (registry's tests) only.
#![cfg_attr(not(test), allow(dead_code))]

/// One field of a uniform struct as Rust lays it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
}

/// A uniform struct with a WGSL twin of the same layout.
pub(crate) trait Uniform: bytemuck::Pod {
    /// The WGSL struct's name.
    const WGSL_NAME: &'static str;
    fn fields() -> Vec<Field>;
}

/// The layout of one uniform struct, for the naga test: the WGSL struct's
/// name, the shader that declares it, the Rust size and fields.
pub(crate) struct Layout {
    pub wgsl_name: &'static str,
    pub source: String,
    pub size: usize,
    pub fields: Vec<Field>,
}

impl Layout {
    pub fn of<T: Uniform>(source: String) -> Self {
        Layout {
            wgsl_name: T::WGSL_NAME,
            source,
            size: std::mem::size_of::<T>(),
            fields: T::fields(),
        }
    }

    /// A storage record checked by size only.
    pub fn sized(wgsl_name: &'static str, source: String, size: usize) -> Self {
        Layout { wgsl_name, source, size, fields: Vec::new() }
    }
}

/// Declare a uniform struct: `uniform! { WgslName; pub struct RustName { … } }`.
macro_rules! uniform {
    ($wgsl:ident; $(#[$m:meta])* $vis:vis struct $name:ident {
        $($(#[$fm:meta])* $fvis:vis $field:ident : $ty:ty),* $(,)?
    }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        $vis struct $name { $($(#[$fm])* $fvis $field: $ty),* }

        impl $crate::uniforms::Uniform for $name {
            const WGSL_NAME: &'static str = stringify!($wgsl);
            fn fields() -> Vec<$crate::uniforms::Field> {
                vec![$($crate::uniforms::Field {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($name, $field),
                    size: std::mem::size_of::<$ty>(),
                }),*]
            }
        }

        impl Default for $name {
            fn default() -> Self {
                bytemuck::Zeroable::zeroed()
            }
        }
    };
}
pub(crate) use uniform;

type Mat4 = [[f32; 4]; 4];

uniform! { FrameView;
    /// The camera.
    pub(crate) struct FrameView {
        pub view_proj: Mat4,
        pub inv_view_proj: Mat4,
        pub position: [f32; 3],
        /// Simulation time (s), reduced modulo the ocean's repeat period.
        pub time: f32,
        pub size: [f32; 2],
        pub inv_size: [f32; 2],
    }
}

uniform! { FrameLight;
    /// Sun and sky, pre-exposed.
    pub(crate) struct FrameLight {
        pub sun_dir: [f32; 3],
        pub cos_sun_radius: f32,
        pub sun_illuminance: [f32; 3],
        pub inv_sun_solid_angle: f32,
        pub sky_ambient: [f32; 3],
        pub exposure: f32,
        pub sun_travel: [f32; 3],
        pub sun_travel_cos: f32,
        pub sun_underwater: [f32; 3],
        pub floor_depth: f32,
        pub sky_underwater: [f32; 3],
        pub floor_albedo: f32,
        /// The sky's and the grey world's irradiance on any normal in the
        /// air: nine spherical-harmonic coefficients (rgb, w unused).
        pub sky_light: [[f32; 4]; 9],
    }
}

uniform! { FrameWater;
    /// The water body and how its surface is shaded.
    pub(crate) struct FrameWater {
        pub body_color: [f32; 3],
        pub ior: f32,
        pub absorption: [f32; 3],
        pub phase_g: f32,
        pub scattering: [f32; 3],
        pub fresnel_power: f32,
        pub reflection_height: f32,
        pub refraction_depth: f32,
        pub refraction_max: f32,
        pub simple_attenuation: f32,
        pub has_water: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

uniform! { FrameSurface;
    /// What the surface's geometry and textures do not resolve.
    pub(crate) struct FrameSurface {
        pub unresolved_variance: [f32; 2],
        pub base_spacing: f32,
        pub rings: f32,
    }
}

uniform! { FrameProjective;
    /// Local reflection and refraction textures.
    pub(crate) struct FrameProjective {
        pub reflection_view_proj: Mat4,
        pub refraction_view_proj: Mat4,
        pub inv_refraction_view_proj: Mat4,
        pub reflection_texels_per_radian: f32,
        pub has_geometry: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

uniform! { FrameShadow;
    /// The sun's shadow map.
    pub(crate) struct FrameShadow {
        pub view_proj: Mat4,
        pub enabled: u32,
        pub size: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

uniform! { FrameFog;
    /// Fog in the air.
    pub(crate) struct FrameFog {
        pub scattering: f32,
        pub g: f32,
        pub distance: f32,
        pub sky_fraction: f32,
        pub air_extinction: [f32; 3],
        pub _pad0: f32,
    }
}

uniform! { FrameModes;
    /// Choices made by the scene.
    pub(crate) struct FrameModes {
        pub fresnel: u32,
        pub tonemap: u32,
        pub debug_view: u32,
        pub optics: u32,
        pub refraction_lookup: u32,
        pub output_width: u32,
        pub output_height: u32,
        pub _pad2: u32,
    }
}

uniform! { FrameCaustics;
    /// The caustics' part of the frame globals (shaders/frame.wgsl): what
    /// receivers need to read the layers.
    pub(crate) struct FrameCaustics {
        /// Patch the maps tile (m); x = 0 when caustics are off.
        pub patch_size: [f32; 2],
        /// The floor depth the layers reach (m).
        pub floor_depth: f32,
        /// 1 / the map's value under flat water.
        pub inv_flat_value: f32,
        /// Layers in use (the texture may hold more: `Capabilities::array_layers`).
        pub layers: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

uniform! { FrameVolume;
    /// The god rays' part of the frame globals (shaders/frame.wgsl).
    pub(crate) struct FrameVolume {
        /// Distance from the eye (m) within which god rays replace the
        /// uniform sun in-scattering (0: no god rays this frame).
        pub godray_distance: f32,
        /// 1 when this pass marches the sun's light in the fog this frame.
        pub fog_marched: u32,
        /// How far (m) along refracted paths seen from above the water
        /// shaders march god rays (0: not this frame).
        pub shafts_from_above: f32,
        pub _pad0: f32,
    }
}

uniform! { FrameObjects;
    /// The refractive objects' part of the frame globals (shaders/frame.wgsl).
    pub(crate) struct FrameObjects {
        /// Their light view (world → clip, orthographic along the sun).
        pub light_view_proj: [[f32; 4]; 4],
        /// 1 when they bend the sunlight (their caustic map is in use).
        pub enabled: u32,
        /// Depth tolerance of a receiver in that view.
        pub depth_tolerance: f32,
        pub _pad0: f32,
        pub _pad1: f32,
    }
}

uniform! { Occluder;
    /// One ambient occluder (shaders/frame.wgsl; `hydrolux_core::occlusion::Occluder::packed`).
    pub(crate) struct Occluder {
        /// Centre (m), and the shape: 0 a sphere, 1 a box.
        pub centre: [f32; 4],
        /// A box's half-axes (m); a sphere's radius in `axis_x.w`.
        pub axis_x: [f32; 4],
        pub axis_y: [f32; 4],
        pub axis_z: [f32; 4],
    }
}

uniform! { FrameOcclusion;
    /// The ambient occluders (shaders/occlusion.wgsl).
    pub(crate) struct FrameOcclusion {
        pub count: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
        pub occluders: [Occluder; hydrolux_core::occlusion::MAX_OCCLUDERS],
    }
}

impl FrameOcclusion {
    /// The occluders as the GPU holds them (the first `MAX_OCCLUDERS`).
    pub fn of(occluders: &[hydrolux_core::occlusion::Occluder]) -> Self {
        let mut o = FrameOcclusion::default();
        for (slot, occluder) in o.occluders.iter_mut().zip(occluders) {
            let [centre, axis_x, axis_y, axis_z] = occluder.packed();
            *slot = Occluder { centre, axis_x, axis_y, axis_z };
            o.count += 1;
        }
        o
    }
}

uniform! { Frame;
    /// WGSL `Frame` (shaders/frame.wgsl): group 0, binding 0 of every render pass.
    pub(crate) struct FrameUniforms {
        pub view: FrameView,
        pub light: FrameLight,
        pub water: FrameWater,
        pub surface: FrameSurface,
        pub projective: FrameProjective,
        pub shadow: FrameShadow,
        pub caustics: FrameCaustics,
        pub volume: FrameVolume,
        pub fog: FrameFog,
        pub objects: FrameObjects,
        pub occlusion: FrameOcclusion,
        pub modes: FrameModes,
    }
}

uniform! { View;
    /// WGSL `View` (meshes/geometry_common.wgsl).
    pub(crate) struct ViewUniforms {
        pub view_proj: Mat4,
        pub clip_plane: [f32; 4],
        /// Where the view's eye is (m; the reflection's mirrored below the
        /// water plane), for the view direction of specular light.
        pub eye: [f32; 3],
        pub _pad0: f32,
    }
}

uniform! { Object;
    /// WGSL `Object` (meshes/geometry_common.wgsl).
    pub(crate) struct ObjectUniforms {
        pub model: Mat4,
        pub normal_matrix: [[f32; 4]; 3],
        pub albedo: [f32; 3],
        pub uv_scale: f32,
        pub pattern_color: [f32; 3],
        pub tile_size: f32,
        pub pattern: u32,
        pub ior: f32,
        /// The specular parameters (`hydrolux_core::pbr::Surface`).
        pub roughness: f32,
        pub metalness: f32,
        pub specular: f32,
        /// Its place among the frame's ambient occluders (so that it does
        /// not occlude itself), or `occlusion::NO_OCCLUDER`.
        pub occluder: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

uniform! { SineWave;
    /// WGSL `SineWave` (shaders/surface.wgsl): one wave of the sines model.
    pub(crate) struct SineWave {
        /// Wave vector (rad/m).
        pub k: [f32; 2],
        pub amplitude: f32,
        /// Phase now (rad).
        pub phase: f32,
    }
}

uniform! { SurfaceParams;
    /// WGSL `SurfaceParams` (shaders/surface.wgsl).
    pub(crate) struct SurfaceUniforms {
        pub cascade_sizes: [f32; 4],
        pub cascades: u32,
        pub model: u32,
        pub sine_count: u32,
        pub fft_resolution: u32,
        pub waves: [SineWave; 64],
        pub wave_q: [[f32; 4]; 16],
        pub ripple_origin: [f32; 2],
        pub ripple_side: f32,
        pub ripple_cell: f32,
        pub ripple_window: [f32; 4],
        pub foam_origin: [f32; 2],
        pub foam_side: f32,
        pub foam_tiles: u32,
        pub foam_wind: [f32; 2],
        pub foam_streak: f32,
        pub _pad0: f32,
    }
}

uniform! { EvolveParams;
    /// WGSL `EvolveParams` (simulation/ocean/spectrum.wgsl).
    pub(crate) struct EvolveUniforms {
        pub phase: u32,
        pub n: u32,
        pub cascades: u32,
        pub choppiness: f32,
    }
}

uniform! { AssembleParams;
    /// WGSL `AssembleParams` (simulation/ocean/assemble.wgsl).
    pub(crate) struct AssembleUniforms {
        pub n: u32,
        pub cascades: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

/// Core types laid out for the GPU (their crate has no GPU code).
macro_rules! core_uniform {
    ($wgsl:ident, $ty:ty, [$($field:ident),* $(,)?]) => {
        impl Uniform for $ty {
            const WGSL_NAME: &'static str = stringify!($wgsl);
            fn fields() -> Vec<Field> {
                fn size_of_field<T, F>(_: fn(&T) -> &F) -> usize {
                    std::mem::size_of::<F>()
                }
                vec![$(Field {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($ty, $field),
                    size: size_of_field(|v: &$ty| &v.$field),
                }),*]
            }
        }
    };
}

core_uniform!(
    SkyParams,
    hydrolux_core::sky::SkyParams,
    [
        coeff_y,
        coeff_x,
        coeff_yy,
        coeff_e,
        zenith_over_f,
        sun_direction,
        sun_illuminance,
        rayleigh,
        mie,
        mie_extinction,
        ozone,
        model,
    ]
);
core_uniform!(
    SpectrumMode,
    hydrolux_core::waves::ocean::SpectrumMode,
    [h0, h0_minus_conj, kx, kz, omega_cycles, _pad,]
);
