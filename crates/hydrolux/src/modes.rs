//! Integer modes the shaders switch on, defined once: the uniforms carry
//! `index(value)` of a scene enum, and the WGSL compares against constants
//! generated from the same enum and the same function (the `modes` shader
//! module: `VIEW_NORMALS`, `FRESNEL_SCHLICK`, `PATTERN_TILES`…), and so are
//! the codes the core and the renderer share (primitives, particle kinds, the
//! stencil's media). No number is matched by hand on either side.

use hydrolux_core::scene::{
    Choice, DebugView, Fresnel, Pattern, RefractionLookup, Tonemap, WaterModel, WaterOptics,
};
use hydrolux_core::waves::ripples::RippleBoundary;

/// `frame.modes.debug_view`: what the output shows.
pub(crate) fn debug_view(view: DebugView) -> u32 {
    match view {
        DebugView::Final => 0,
        DebugView::Reflection => 1,
        DebugView::Refraction => 2,
        DebugView::Depth => 3,
        DebugView::Normals => 4,
        DebugView::Shadow => 5,
        DebugView::Medium => 6,
        DebugView::Caustics => 7,
        // Views of the water's own state after `VIEW_RIPPLES` (geometry
        // shades them as the water's colour).
        DebugView::Ripples => 8,
        DebugView::Foam => 9,
        DebugView::Fresnel => 10,
        DebugView::Fluid => 11,
        // Each of its two drawings is a final image.
        DebugView::Error => 0,
    }
}

/// `frame.modes.fresnel`: the reflectance formula.
pub(crate) fn fresnel(f: Fresnel) -> u32 {
    match f {
        Fresnel::Exact => 0,
        Fresnel::Schlick => 1,
        Fresnel::JensenGolias => 2,
        Fresnel::Power => 3,
    }
}

/// `frame.modes.tonemap`.
pub(crate) fn tonemap(t: Tonemap) -> u32 {
    match t {
        Tonemap::Aces => 0,
        Tonemap::Clamp => 1,
    }
}

/// `frame.modes.optics`.
pub(crate) fn optics(o: WaterOptics) -> u32 {
    match o {
        WaterOptics::Physical => 0,
        WaterOptics::Simple => 1,
    }
}

/// `frame.modes.refraction_lookup`.
pub(crate) fn refraction(r: RefractionLookup) -> u32 {
    match r {
        RefractionLookup::Depth => 0,
        RefractionLookup::Plane => 1,
    }
}

/// An object's `pattern`.
pub(crate) fn pattern(p: Pattern) -> u32 {
    match p {
        Pattern::None => 0,
        Pattern::Tiles => 1,
        Pattern::Checker => 2,
    }
}

/// The surface's model (`surface.model`, the `SURFACE_MODEL` pipeline
/// constant); no water samples as flat water.
pub(crate) fn surface_model(model: WaterModel) -> u32 {
    match model {
        WaterModel::Fft => 0,
        WaterModel::Sines => 1,
        WaterModel::Flat | WaterModel::None => 2,
        WaterModel::Heightfield => 3,
    }
}

/// The interactive water as the `RIPPLES` pipeline constant: none, walls
/// (the texture covers the domain), open (the texture tiles the plane).
pub(crate) fn ripples(edges: Option<RippleBoundary>) -> u32 {
    match edges {
        None => 0,
        Some(RippleBoundary::Walls) => 1,
        Some(RippleBoundary::Open | RippleBoundary::Periodic) => 2,
    }
}

/// `const PREFIX_NAME: u32 = index;` for every variant of `T`.
fn constants<T: Choice>(out: &mut String, prefix: &str, index: fn(T) -> u32) {
    for &v in T::ALL {
        let name = v.name().to_uppercase().replace('-', "_");
        out.push_str(&format!("const {prefix}_{name}: u32 = {}u;\n", index(v)));
    }
}

/// The `modes` shader module.
pub(crate) fn wgsl() -> String {
    let mut out = String::from("// Generated from the scene's enums (src/modes.rs).\n");
    constants(&mut out, "VIEW", debug_view);
    constants(&mut out, "FRESNEL", fresnel);
    constants(&mut out, "TONEMAP", tonemap);
    constants(&mut out, "OPTICS", optics);
    constants(&mut out, "REFRACTION", refraction);
    constants(&mut out, "PATTERN", pattern);
    constants(&mut out, "MODEL", surface_model);
    let named = [
        ("PRIMITIVE_SPHERE", hydrolux_core::coupling::PRIMITIVE_SPHERE),
        ("PRIMITIVE_BOX", hydrolux_core::coupling::PRIMITIVE_BOX),
        ("PRIMITIVE_CYLINDER", hydrolux_core::coupling::PRIMITIVE_CYLINDER),
        ("PRIMITIVE_PLANE", hydrolux_core::coupling::PRIMITIVE_PLANE),
        ("PRIMITIVE_MESH", hydrolux_core::coupling::PRIMITIVE_MESH),
        ("PARTICLE_DEAD", hydrolux_core::whitewater::DEAD),
        ("PARTICLE_BUBBLE", hydrolux_core::whitewater::BUBBLE),
        ("PARTICLE_SPRAY", hydrolux_core::whitewater::SPRAY),
        ("PARTICLE_FOAM", hydrolux_core::whitewater::FOAM),
        ("STENCIL_AIR", crate::formats::STENCIL_AIR),
        ("STENCIL_WATER", crate::formats::STENCIL_WATER),
    ];
    for (name, value) in named {
        out.push_str(&format!("const {name}: u32 = {value}u;\n"));
    }
    for (name, edges) in [
        ("NONE", None),
        ("WALLS", Some(RippleBoundary::Walls)),
        ("OPEN", Some(RippleBoundary::Open)),
    ] {
        out.push_str(&format!("const RIPPLES_{name}: u32 = {}u;\n", ripples(edges)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variant_has_one_constant_and_distinct_numbers_per_enum() {
        let src = wgsl();
        let module = naga::front::wgsl::parse_str(&src).expect("the modes module parses");
        assert_eq!(module.constants.len(), 13 + 4 + 2 + 2 + 2 + 3 + 5 + 11 + 3);
        assert!(src.contains("const VIEW_NORMALS: u32 = 4u;"));
        assert!(src.contains("const FRESNEL_JENSEN_GOLIAS: u32 = 2u;"));
        assert!(src.contains("const MODEL_HEIGHTFIELD: u32 = 3u;"));
        assert!(src.contains("const RIPPLES_OPEN: u32 = 2u;"));
        // Only the error view shares a number (its drawings are final images).
        let mut views: Vec<u32> = DebugView::ALL.iter().map(|&v| debug_view(v)).collect();
        views.sort_unstable();
        views.dedup();
        assert_eq!(views.len(), DebugView::ALL.len() - 1);
    }

    #[test]
    fn no_shader_defines_a_mode_number_by_hand() {
        let validated: Vec<_> = crate::registry::validated().flat_map(|t| (t.shaders)()).collect();
        for (name, source) in validated {
            for prefix in [
                "VIEW",
                "FRESNEL",
                "TONEMAP",
                "OPTICS",
                "REFRACTION",
                "PATTERN",
                "MODEL",
                "RIPPLES",
                "PRIMITIVE",
                "PARTICLE",
                "STENCIL",
            ] {
                let hand = format!("const {prefix}_");
                let generated = wgsl().matches(&hand).count();
                assert!(
                    source.matches(&hand).count() <= generated,
                    "{name}: defines a `{prefix}_*` constant of its own"
                );
            }
        }
    }
}
