//! Every enumerated scene key and its allowed values, in one place: the
//! viewer's drop-downs and key bindings read them from here, and the names
//! come from serde (the same spelling the TOML parser accepts), so they
//! cannot drift from the enums.

use super::*;

/// An enum a scene key takes.
pub trait Choice: Sized + Copy + Serialize + 'static {
    /// Every variant; [`Choice::exhaustive`] makes a new variant a compile
    /// error until it is listed.
    const ALL: &'static [Self];
    #[doc(hidden)]
    fn exhaustive(self);

    /// The name a scene file uses for this value.
    fn name(self) -> String {
        match toml::Value::try_from(self) {
            Ok(toml::Value::String(s)) => s,
            other => unreachable!("a scene enum serializes to a string, got {other:?}"),
        }
    }

    fn names() -> Vec<String> {
        Self::ALL.iter().map(|v| v.name()).collect()
    }
}

macro_rules! choice {
    ($ty:ident: $($v:ident),+ $(,)?) => {
        impl Choice for $ty {
            const ALL: &'static [Self] = &[$($ty::$v),+];
            fn exhaustive(self) {
                match self {
                    $($ty::$v => ()),+
                }
            }
        }
    };
}

choice!(Spectrum: Phillips, PiersonMoskowitz, Jonswap);
choice!(WaterModel: Fft, Sines, Flat, Heightfield, None);
choice!(Fresnel: Exact, Schlick, JensenGolias, Power);
choice!(WaterOptics: Physical, Simple);
choice!(MediumName: Pure, ClearOcean, Coastal, TurbidHarbor, Custom);
choice!(RefractionLookup: Depth, Plane);
choice!(WaterMethod: Projective, Raytrace);
choice!(TerrainKind: None, Noise, Heightmap);
choice!(Pattern: None, Tiles, Checker);
choice!(Primitive: Box, Sphere, Cylinder, Plane);
choice!(Tonemap: Aces, Clamp);
choice!(Antialias: Temporal, Off);
choice!(DebugView: Final, Reflection, Refraction, Depth, Normals, Shadow, Medium, Caustics, Ripples, Foam, Fresnel, Fluid, Error);
choice!(CausticMethod: Photons, Beam, Procedural, Off);
choice!(GodRayMethod: Lines, March, Off);
choice!(RippleEdges: Walls, Open);
choice!(Quality: Auto, Low, Medium, High, Ultra);
choice!(FluidSurface: Points, MarchingCubes, ScreenMesh, ScreenSpace, None);
choice!(FluidSourceKind: Block, Nozzle, Drain);
choice!(SkyModel: Physical, Preetham);

/// Each enumerated key (array indices left out: `objects.primitive`) and
/// its allowed values.
pub fn enumerated_keys() -> Vec<(&'static str, Vec<String>)> {
    vec![
        ("ocean.spectrum", Spectrum::names()),
        ("water.model", WaterModel::names()),
        ("water.fresnel", Fresnel::names()),
        ("water.optics", WaterOptics::names()),
        ("water.medium", MediumName::names()),
        ("water.refraction", RefractionLookup::names()),
        ("water.method", WaterMethod::names()),
        ("floor.terrain", TerrainKind::names()),
        ("floor.material.pattern", Pattern::names()),
        ("objects.material.pattern", Pattern::names()),
        ("objects.primitive", Primitive::names()),
        ("render.tonemap", Tonemap::names()),
        ("render.antialias", Antialias::names()),
        ("render.view", DebugView::names()),
        ("caustics.method", CausticMethod::names()),
        ("godrays.method", GodRayMethod::names()),
        ("ripples.edges", RippleEdges::names()),
        ("render.quality", Quality::names()),
        ("fluid.surface", FluidSurface::names()),
        ("sky.model", SkyModel::names()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_value_is_accepted_by_the_parser_for_its_key() {
        for (key, names) in enumerated_keys() {
            if key.starts_with("objects.") {
                continue; // needs an [[objects]] entry; covered by the enum's serde
            }
            assert!(names.len() >= 2, "{key}");
            for n in names {
                let scene = Scene::load("ocean", &[format!("{key}=\"{n}\"")]);
                // Some values need more keys (a heightfield file, a
                // heightmap): those fail on the missing key, never on the name.
                if let Err(e) = scene {
                    let msg = e.to_string();
                    assert!(!msg.contains("unknown variant"), "{key}={n}: {msg}");
                }
            }
        }
    }

    #[test]
    fn names_are_the_scene_file_spelling() {
        assert_eq!(WaterModel::names(), ["fft", "sines", "flat", "heightfield", "none"]);
        assert_eq!(MediumName::TurbidHarbor.name(), "turbid_harbor");
        assert_eq!(Spectrum::PiersonMoskowitz.name(), "pierson-moskowitz");
    }
}
