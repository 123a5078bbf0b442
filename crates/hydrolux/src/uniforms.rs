//! Rust twins of the WGSL uniform structs. `#[repr(C)]` + bytemuck, and a
//! test (tests/shaders.rs) checks each size against naga's layout of the
//! WGSL struct, so the two cannot drift apart silently.

use bytemuck::{Pod, Zeroable};

/// WGSL `Frame` (shaders/frame.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub sun_dir: [f32; 4],
    pub sun_illuminance: [f32; 4],
    pub sky_ambient: [f32; 4],
    pub water_body: [f32; 4],
    pub modes: [u32; 4],
    pub viewport: [f32; 4],
    pub surface_detail: [f32; 4],
    pub refl_view_proj: [[f32; 4]; 4],
    pub refr_view_proj: [[f32; 4]; 4],
    pub inv_refr_view_proj: [[f32; 4]; 4],
    pub shadow_view_proj: [[f32; 4]; 4],
    pub absorption: [f32; 4],
    pub scattering: [f32; 4],
    pub water_params: [f32; 4],
    pub reflection_params: [f32; 4],
    pub sun_travel: [f32; 4],
    pub sun_underwater: [f32; 4],
    pub sky_underwater: [f32; 4],
    pub modes2: [u32; 4],
    pub caustic_params: [f32; 4],
    pub volume: [f32; 4],
    pub fog: [f32; 4],
    pub object_light_view_proj: [[f32; 4]; 4],
    pub object_params: [f32; 4],
}

/// WGSL `View` (passes/geometry/geometry_common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ViewUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub clip_plane: [f32; 4],
}

/// WGSL `Object` (passes/geometry/geometry_common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ObjectUniforms {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 3],
    pub albedo: [f32; 4],
    pub pattern_color: [f32; 4],
    pub flags: [u32; 4],
}

/// WGSL `SurfaceParams` (shaders/surface.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SurfaceUniforms {
    pub cascade_sizes: [f32; 4],
    pub counts: [u32; 4],
    pub waves: [[f32; 4]; 64],
    pub wave_q: [[f32; 4]; 16],
}

/// WGSL `EvolveParams` (passes/ocean/spectrum.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct EvolveUniforms {
    pub tau_n: [u32; 4],
    pub choppiness: [f32; 4],
}

/// WGSL `AssembleParams` (passes/ocean/assemble.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct AssembleUniforms {
    pub n: u32,
    pub cascades: u32,
    pub _pad: [u32; 2],
}

/// (WGSL struct name, shader it lives in, Rust size) for the layout test.
pub fn layouts() -> Vec<(&'static str, String, usize)> {
    use std::mem::size_of;
    vec![
        ("Frame", crate::passes::water::source(), size_of::<FrameUniforms>()),
        ("SurfaceParams", crate::passes::water::source(), size_of::<SurfaceUniforms>()),
        (
            "SkyParams",
            crate::passes::sky::bake_source(),
            size_of::<hydrolux_core::sky::SkyParams>(),
        ),
        ("EvolveParams", crate::passes::ocean::spectrum_source(), size_of::<EvolveUniforms>()),
        (
            "SpectrumMode",
            crate::passes::ocean::spectrum_source(),
            size_of::<hydrolux_core::waves::ocean::SpectrumMode>(),
        ),
        ("View", crate::passes::geometry::source(), size_of::<ViewUniforms>()),
        (
            "CausticParams",
            crate::passes::caustics::source(),
            size_of::<crate::passes::caustics::CausticUniforms>(),
        ),
        (
            "BeamParams",
            crate::passes::caustics::beam_source(),
            size_of::<crate::passes::caustics::CausticUniforms>(),
        ),
        ("Object", crate::passes::geometry::source(), size_of::<ObjectUniforms>()),
        (
            "GodRayParams",
            crate::passes::godrays::ribbons_source(),
            size_of::<crate::passes::godrays::GodRayUniforms>(),
        ),
        (
            "Tube",
            crate::passes::godrays::ribbons_source(),
            crate::passes::godrays::TUBE_BYTES as usize,
        ),
        (
            "ObjectLightParams",
            crate::passes::water_object::paths_source(),
            size_of::<crate::passes::water_object::ObjectLightUniforms>(),
        ),
        ("AssembleParams", crate::passes::ocean::assemble_source(), size_of::<AssembleUniforms>()),
    ]
}
