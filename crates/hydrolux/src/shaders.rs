//! WGSL sources. Each pass has its own file; the shared modules under
//! `src/shaders/` are prepended to it, never pasted (WGSL has no #include).
//! [`all_for_validation`] lists every composed shader so a test can check
//! them all with naga, without a GPU.

pub const FRAME: &str = include_str!("shaders/frame.wgsl");
pub const CONSTANTS: &str = include_str!("shaders/constants.wgsl");
pub const OPTICS: &str = include_str!("shaders/optics.wgsl");
pub const COMPLEX: &str = include_str!("shaders/complex.wgsl");
pub const SKY_MODEL: &str = include_str!("shaders/sky_model.wgsl");
pub const SKY_BINDINGS: &str = include_str!("shaders/sky_bindings.wgsl");
pub const SURFACE: &str = include_str!("shaders/surface.wgsl");
pub const TONEMAP_CURVE: &str = include_str!("shaders/tonemap_curve.wgsl");
pub const FULLSCREEN: &str = include_str!("shaders/fullscreen.wgsl");
pub const DOWNSAMPLE: &str = include_str!("shaders/downsample.wgsl");
pub const MEDIUM: &str = include_str!("shaders/medium.wgsl");
pub const PROJECTIVE: &str = include_str!("shaders/projective.wgsl");
pub const SHADOW_SPACE: &str = include_str!("shaders/shadow_space.wgsl");
pub const SHADOW_LOOKUP: &str = include_str!("shaders/shadow_lookup.wgsl");
pub const PHOTON: &str = include_str!("shaders/photon.wgsl");
pub const TUBE: &str = include_str!("shaders/tube.wgsl");
pub const FOG: &str = include_str!("shaders/fog.wgsl");
pub const OBJECT_CAUSTICS: &str = include_str!("shaders/object_caustics.wgsl");
pub const CAUSTICS_LOOKUP: &str = include_str!("shaders/caustics_lookup.wgsl");

/// Join shader parts, each introduced by a comment naming its position.
pub fn compose(parts: &[&str]) -> String {
    let mut out = String::new();
    for (i, p) in parts.iter().enumerate() {
        out.push_str(&format!("// ---- part {i} ----\n"));
        out.push_str(p);
        out.push('\n');
    }
    out
}

/// Every shader the renderer builds, composed, with representative constants.
pub fn all_for_validation() -> Vec<(String, String)> {
    let mut v = vec![
        ("ocean/spectrum".to_string(), crate::passes::ocean::spectrum_source()),
        ("ocean/assemble".to_string(), crate::passes::ocean::assemble_source()),
        ("downsample".to_string(), compose(&[DOWNSAMPLE])),
        ("sky/bake".to_string(), crate::passes::sky::bake_source()),
        ("sky/background".to_string(), crate::passes::sky::background_source()),
        ("water".to_string(), crate::passes::water::source()),
        ("tonemap/srgb-target".to_string(), crate::passes::tonemap::source(true)),
        ("tonemap/unorm-target".to_string(), crate::passes::tonemap::source(false)),
        ("probe".to_string(), crate::passes::probe::source()),
        ("geometry".to_string(), crate::passes::geometry::source()),
        ("geometry/shadow".to_string(), crate::passes::geometry::shadow_source()),
        ("caustics".to_string(), crate::passes::caustics::source()),
        ("caustics/beam".to_string(), crate::passes::caustics::beam_source()),
        ("water_object/light".to_string(), crate::passes::water_object::light_source()),
        ("water_object/paths".to_string(), crate::passes::water_object::paths_source()),
        ("water_object/shade".to_string(), crate::passes::water_object::shade_source()),
        ("godrays/tubes".to_string(), crate::passes::godrays::tubes_source()),
        ("godrays/ribbons".to_string(), crate::passes::godrays::ribbons_source()),
        ("godrays/march".to_string(), crate::passes::godrays::march_source()),
        ("godrays/resolve".to_string(), crate::passes::godrays::resolve_source()),
    ];
    for n in [64u32, 256, 1024] {
        v.push((format!("ocean/fft N={n}"), crate::passes::ocean::fft_source(n)));
    }
    v
}
