//! WGSL modules by import. WGSL has no `#include`: a shader file names the
//! shared modules it uses on `#import a, b` lines, each module names its own,
//! and [`compose`] resolves them (depth first, each module once) into one
//! source. WGSL declarations are order-independent at module scope, so the
//! order only matters for reading. Every composed shader is validated with
//! naga by a test (`registry::tests`), without a GPU.

/// Shared modules, by the name they are imported as.
const MODULES: &[(&str, &str)] = &[
    ("constants", include_str!("shaders/constants.wgsl")),
    ("hash", include_str!("shaders/hash.wgsl")),
    ("frame", include_str!("shaders/frame.wgsl")),
    ("optics", include_str!("shaders/optics.wgsl")),
    ("lighting", include_str!("shaders/lighting.wgsl")),
    ("pbr", include_str!("shaders/pbr.wgsl")),
    ("sea_brdf", include_str!("shaders/sea_brdf.wgsl")),
    ("occlusion", include_str!("shaders/occlusion.wgsl")),
    ("complex", include_str!("shaders/complex.wgsl")),
    ("sky_model", include_str!("shaders/sky_model.wgsl")),
    ("sky_bindings", include_str!("shaders/sky_bindings.wgsl")),
    ("surface", include_str!("shaders/surface.wgsl")),
    ("tonemap_curve", include_str!("shaders/tonemap_curve.wgsl")),
    ("fullscreen", include_str!("shaders/fullscreen.wgsl")),
    ("downsample", include_str!("shaders/downsample.wgsl")),
    ("medium_copy", include_str!("shaders/medium_copy.wgsl")),
    ("medium", include_str!("shaders/medium.wgsl")),
    ("projective", include_str!("shaders/projective.wgsl")),
    ("shadow_space", include_str!("shaders/shadow_space.wgsl")),
    ("shadow_lookup", include_str!("shaders/shadow_lookup.wgsl")),
    ("photon", include_str!("shaders/photon.wgsl")),
    ("tube", include_str!("shaders/tube.wgsl")),
    ("fog", include_str!("shaders/fog.wgsl")),
    ("object_caustics", include_str!("shaders/object_caustics.wgsl")),
    ("caustics_lookup", include_str!("shaders/caustics_lookup.wgsl")),
    ("heightfield_trace", include_str!("shaders/heightfield_trace.wgsl")),
    ("ray_primitive", include_str!("shaders/ray_primitive.wgsl")),
    ("screen_project", include_str!("shaders/screen_project.wgsl")),
    ("screen_lookup", include_str!("shaders/screen_lookup.wgsl")),
    // Modules of one technique that another reuses.
    ("geometry_common", include_str!("meshes/geometry_common.wgsl")),
    ("caustic_params", include_str!("passes/caustics/params.wgsl")),
    ("particle", include_str!("simulation/whitewater/particle.wgsl")),
    ("white_water_light", include_str!("simulation/whitewater/light.wgsl")),
    ("liquid_particle", include_str!("simulation/liquid/particle.wgsl")),
    ("liquid_diffuse", include_str!("simulation/liquid/diffuse.wgsl")),
    ("liquid_mesh", include_str!("simulation/liquid/mesh.wgsl")),
    ("liquid_landing", include_str!("simulation/liquid/landing.wgsl")),
    ("liquid_bodies", include_str!("simulation/liquid/bodies.wgsl")),
    ("ripple_texel", include_str!("simulation/ripples/texel.wgsl")),
    ("godrays_common", include_str!("passes/godrays/common.wgsl")),
    ("atmosphere", include_str!("passes/sky/atmosphere.wgsl")),
    ("traced", include_str!("passes/raytrace/traced.wgsl")),
    ("traced_hits", include_str!("passes/raytrace/traced_hits.wgsl")),
    ("water_traced", include_str!("passes/water/traced.wgsl")),
    ("water_foam", include_str!("passes/water/foam.wgsl")),
    ("temporal_resolve", include_str!("passes/antialias/resolve_colour.wgsl")),
];

/// The names on a source's `#import` lines, in order.
fn imports(source: &str) -> Vec<&str> {
    source
        .lines()
        .filter_map(|l| l.trim().strip_prefix("#import"))
        .flat_map(|rest| rest.split(',').map(str::trim).filter(|n| !n.is_empty()))
        .collect()
}

/// A source without its `#import` lines (kept as comments, so line numbers
/// in naga's messages still point into the file).
fn body(source: &str) -> String {
    let mut out = String::with_capacity(source.len());
    for line in source.lines() {
        if line.trim_start().starts_with("#import") {
            out.push_str("// ");
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// A shared module's (name, source); an unknown name is a bug in a shader
/// file, caught by the validation test.
fn module(name: &str) -> (&'static str, &'static str) {
    if name == "modes" {
        static MODES: std::sync::OnceLock<String> = std::sync::OnceLock::new();
        return ("modes", MODES.get_or_init(crate::modes::wgsl).as_str());
    }
    *MODULES.iter().find(|(n, _)| *n == name).unwrap_or_else(|| {
        let known: Vec<_> = MODULES.iter().map(|(n, _)| *n).collect();
        panic!("WGSL import `{name}` is not a shared module ({})", known.join(", "))
    })
}

fn visit(name: &'static str, done: &mut Vec<&'static str>, stack: &mut Vec<&'static str>) {
    if done.contains(&name) {
        return;
    }
    assert!(!stack.contains(&name), "WGSL import cycle: {} → {name}", stack.join(" → "));
    stack.push(name);
    for dep in imports(module(name).1) {
        visit(module(dep).0, done, stack);
    }
    stack.pop();
    done.push(name);
}

/// One shader: `consts` (settings-dependent `const` lines) first, then every
/// module `main` imports (transitively, each once, dependencies first), then
/// `main` itself.
pub(crate) fn compose(consts: &str, main: &str) -> String {
    let mut order = Vec::new();
    for name in imports(main) {
        visit(module(name).0, &mut order, &mut Vec::new());
    }
    let mut out = String::new();
    if !consts.is_empty() {
        out.push_str("// ---- settings ----\n");
        out.push_str(consts);
        out.push('\n');
    }
    for name in order {
        out.push_str(&format!("// ---- module {name} ----\n"));
        out.push_str(&body(module(name).1));
    }
    out.push_str("// ---- main ----\n");
    out.push_str(&body(main));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// pbr.wgsl's constants are hydrolux_core::pbr's, and its
    /// `EnvironmentBrdf` holds the packed table exactly.
    #[test]
    fn the_pbr_module_agrees_with_its_twin() {
        use hydrolux_core::pbr::{ENVIRONMENT_TABLE_SIZE, MIN_ROUGHNESS, SPECULAR_LEVELS};
        let src = include_str!("shaders/pbr.wgsl");
        for line in [
            format!("const ENVIRONMENT_TABLE_SIZE: u32 = {ENVIRONMENT_TABLE_SIZE}u;"),
            format!("const SPECULAR_LEVELS: u32 = {SPECULAR_LEVELS}u;"),
            format!("const MIN_ROUGHNESS: f32 = {MIN_ROUGHNESS:?};"),
            format!(
                "table: array<vec4<f32>, {}>,",
                hydrolux_core::pbr::environment_table_packed().len()
            ),
        ] {
            assert!(src.contains(&line), "pbr.wgsl lacks `{line}`");
        }
    }

    #[test]
    fn imports_resolve_transitively_once_and_dependencies_first() {
        let s = compose("", "#import fog, shadow_lookup\nfn main_fn() {}\n");
        let at = |m: &str| s.find(&format!("// ---- module {m} ----")).unwrap_or(usize::MAX);
        // fog imports medium, which imports frame; shadow_lookup imports shadow_space.
        for m in ["fog", "medium", "frame", "constants", "shadow_lookup", "shadow_space"] {
            assert!(at(m) < s.len(), "{m} missing");
            assert_eq!(s.matches(&format!("// ---- module {m} ----")).count(), 1, "{m} twice");
        }
        assert!(at("frame") < at("medium") && at("medium") < at("fog"));
        assert!(at("shadow_space") < at("shadow_lookup"));
        assert!(s.find("// ---- main ----").unwrap() > at("fog"));
        assert!(!s.lines().any(|l| l.starts_with("#import")));
    }

    #[test]
    #[should_panic(expected = "not a shared module")]
    fn an_unknown_import_is_named() {
        compose("", "#import nowhere\n");
    }
}
