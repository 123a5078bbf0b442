//! Tests of loading, overrides and validation (`load.rs`).

use super::*;

/// The quality tiers choose the tracer's budget and its water's cells.
#[test]
fn quality_tiers_choose_the_trace_budget() {
    use super::super::Quality;
    let s = Scene::load("lake", &["water.method=raytrace".into()]).expect("lake");
    let w = |q: Quality| {
        let a = q.apply(&s);
        (a.water.trace_resolution, a.water.trace_steps)
    };
    assert_eq!(w(Quality::High), (256, 4096), "high is the scene as written");
    assert_eq!(w(Quality::Low), (128, 256));
    assert_eq!(w(Quality::Medium), (256, 1024));
    assert_eq!(w(Quality::Ultra), (512, 4096));
    let bad = Scene::load("lake", &["water.trace_resolution=100".into()]).unwrap_err();
    assert!(bad.to_string().contains("water.trace_resolution"), "{bad}");
    let bad = Scene::load("lake", &["water.trace_steps=8".into()]).unwrap_err();
    assert!(bad.to_string().contains("water.trace_steps"), "{bad}");
}

/// A tier may coarsen the interactive water, but never past the size
/// of what disturbs it: the pool's 4 cm drips and the pointer's crater
/// stay resolved at `low` (4 m / 128 cells = 3.1 cm ≤ 4 cm).
#[test]
fn quality_tiers_keep_the_ripples_that_make_a_scene() {
    use super::super::Quality;
    let pool = Scene::load("pool", &[]).expect("pool");
    assert_eq!(pool.ripple_cells_needed(), 128);
    for q in [Quality::Low, Quality::Medium, Quality::High] {
        let r = q.apply(&pool).ripples;
        assert!(r.extent / r.resolution as f32 <= 0.04, "{q:?}: {} cells", r.resolution);
    }
    // A wide open sea whose cells are coarser than the pointer's crater,
    // with nothing scripted: the tiers coarsen it (the wake's 16 m
    // Kelvin waves stay resolved by 1 m cells).
    let wake = Scene::load("wake", &[]).expect("wake");
    assert_eq!(wake.ripple_cells_needed(), 16);
    assert_eq!(Quality::Low.apply(&wake).ripples.resolution, 64);
    // A 0.5 m drop on it needs 64 m / 0.5 m = 128 cells.
    let dropped = Scene::load(
        "wake",
        &["drops=[{time=1.0,position=[0.0,0.0],radius=0.5,strength=0.1}]".into()],
    )
    .expect("a drop");
    assert_eq!(Quality::Low.apply(&dropped).ripples.resolution, 128);
}

/// `start_time` opens a scene where its point shows; out of range is one line.
#[test]
fn scenes_open_at_their_start_time() {
    for (name, t) in
        [("pool", 2.0), ("harbor", 4.0), ("wake", 7.0), ("storm", 20.0), ("ocean", 0.0)]
    {
        assert_eq!(Scene::load(name, &[]).unwrap().start_time, t, "{name}");
    }
    let s = Scene::load("pool", &["start_time=5".into()]).expect("a top-level key");
    assert_eq!(s.start_time, 5.0);
    for bad in ["start_time=-1", "start_time=1e9", "start_time=nan"] {
        let e = Scene::load("pool", &[bad.into()]).unwrap_err().to_string();
        assert!(e.contains("start_time") && e.contains("3600"), "{bad}: {e}");
    }
}

#[test]
fn builtins_load_and_validate() {
    for b in BUILTIN_SCENES {
        let s = Scene::load(b.name, &[]).unwrap_or_else(|e| panic!("{}: {e}", b.name));
        assert!(!s.description.is_empty(), "{} has no description", b.name);
    }
}

#[test]
fn overrides_take_toml_values_and_bare_words() {
    let s = Scene::load(
        "ocean",
        &[
            "ocean.wind_speed=14".into(),
            "ocean.spectrum=phillips".into(),
            "camera.position=[1, 20, 3]".into(),
        ],
    )
    .unwrap();
    assert_eq!(s.ocean.wind_speed, 14.0);
    assert_eq!(s.ocean.spectrum, super::super::Spectrum::Phillips);
    assert_eq!(s.camera.position, [1.0, 20.0, 3.0]);
}

#[test]
fn errors_are_one_clear_line() {
    let cases: &[(&str, &[&str], &str)] = &[
        ("nowhere", &[], "unknown scene `nowhere`: built-in scenes are ocean"),
        ("ocean", &["ocean.wind_sped=3"], "did you mean `ocean.wind_speed`?"),
        ("ocean", &["ocean.wind_speed=-3"], "`ocean.wind_speed` = -3 is out of range"),
        ("ocean", &["ocean.resolution=300"], "power of two from 64 to 1024"),
        (
            "ocean",
            &["ocean.wind_speed=fast"],
            "`ocean.wind_speed` must be a number, got a string \"fast\"",
        ),
        ("ocean", &["ocean.spectrum=foo"], "ocean.spectrum"),
        ("ocean", &["camera.fov_y_deg=180"], "must be in (0, 180)"),
        ("ocean", &["camera.position=[1, 2]"], "an array of 3 numbers"),
        ("ocean", &["nonsense"], "expected section.key=value"),
        ("ocean", &["ocean.seed=-1"], "a whole number ≥ 0"),
        ("pool", &["floor.material.roughness=1.5"], "`floor.material.roughness` = 1.5"),
        ("pool", &["floor.material.metalness=-1"], "must be in [0, 1]"),
    ];
    for (scene, sets, want) in cases {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let e = Scene::load(scene, &sets).unwrap_err().to_string();
        assert!(e.contains(want), "{scene} {sets:?}: `{e}` lacks `{want}`");
        assert!(!e.contains('\n'), "multi-line error: {e}");
    }
}

#[test]
fn objects_are_checked_and_media_resolve() {
    let text = "[[objects]]\nprimitive = \"sphere\"\nposition = [0, 1, 2]\n[objects.material]\nalbedo = [0.9, 0.1, 0.1]\n";
    let s = Scene::from_toml(text, "x.toml", &[]).unwrap();
    assert_eq!(s.objects.len(), 1);
    assert_eq!(s.objects[0].primitive, super::super::Primitive::Sphere);
    assert_eq!(s.objects[0].material.albedo, [0.9, 0.1, 0.1]);
    let e = Scene::from_toml("[[objects]]\npositon = [0, 1, 2]\n", "x.toml", &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`objects[0].positon`") && e.contains("did you mean `objects[0].position`"),
        "{e}"
    );
    let e = Scene::from_toml("[[objects]]\nscale = [1, 0, 1]\n", "x.toml", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("objects[0].scale") && e.contains("non-zero"), "{e}");
    let e =
        Scene::from_toml("[water]\nmedium = \"swamp\"\n", "x.toml", &[]).unwrap_err().to_string();
    assert!(
        e.contains("water.medium") && e.contains("clear_ocean") && e.contains("turbid_harbor"),
        "{e}"
    );
    // Coefficients alone make a custom medium.
    let s = Scene::from_toml("[water]\nabsorption = [0.5, 0.1, 0.05]\n", "x.toml", &[]).unwrap();
    assert_eq!(s.water.medium, super::super::MediumName::Custom);
    assert_eq!(s.medium().absorption, glam::Vec3::new(0.5, 0.1, 0.05));
    let s = Scene::from_toml("[water]\nmedium = \"pure\"\n", "x.toml", &[]).unwrap();
    assert_eq!(s.medium().absorption, glam::Vec3::from(crate::medium::PURE_WATER_ABSORPTION));
}

#[test]
fn coefficients_mean_custom_in_files_and_overrides_alike() {
    let pure = "[water]\nmedium = \"pure\"\n";
    // A --set coefficient overrides the file's named medium.
    let s =
        Scene::from_toml(pure, "x.toml", &["water.absorption=[0.5, 0.1, 0.05]".into()]).unwrap();
    assert_eq!(s.water.medium, super::super::MediumName::Custom);
    assert_eq!(s.medium().absorption, glam::Vec3::new(0.5, 0.1, 0.05));
    // The preset's scattering stays unless given.
    let sets = ["water.scattering=[0.01, 0.02, 0.03]".to_string()];
    let s = Scene::from_toml(pure, "x.toml", &sets).unwrap();
    assert_eq!(s.medium().scattering, glam::Vec3::new(0.01, 0.02, 0.03));
    // Named medium and coefficients together contradict each other.
    let both = "[water]\nmedium = \"pure\"\nabsorption = [1, 1, 1]\n";
    let e = Scene::from_toml(both, "x.toml", &[]).unwrap_err().to_string();
    assert!(e.contains("`water.absorption`") && e.contains("\"pure\""), "{e}");
    let sets = ["water.absorption=[1,1,1]".to_string(), "water.medium=coastal".to_string()];
    let e = Scene::from_toml("", "x.toml", &sets).unwrap_err().to_string();
    assert!(e.starts_with("--set") && e.contains("\"coastal\""), "{e}");
    let sets = ["water.absorption=[1,1,1]".to_string(), "water.medium=custom".to_string()];
    assert!(Scene::from_toml(pure, "x.toml", &sets).is_ok());
}

#[test]
fn long_values_in_messages_are_cut_between_characters() {
    // 39 ASCII bytes, then multi-byte characters across byte 40.
    let text = format!("[ocean]\nwind_speed = \"{}ééé\"\n", "x".repeat(38));
    let e = Scene::from_toml(&text, "x.toml", &[]).unwrap_err().to_string();
    assert!(e.contains("must be a number") && e.contains('…'), "{e}");
}

#[test]
fn messages_name_the_key_that_is_wrong() {
    let err = |text: &str, sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        Scene::from_toml(text, "x.toml", &sets).unwrap_err().to_string()
    };
    // Each camera vector on its own: the bad one is named.
    let e = err("", &["camera.position=[inf, 0, 0]"]);
    assert!(e.contains("`camera.position`") && e.contains("finite"), "{e}");
    let e = err("", &["camera.position=[1e30, 0, 0]"]);
    assert!(e.contains("`camera.position`") && e.contains("100000"), "{e}");
    let e = err("", &["camera.look_at=[nan, 0, 0]"]);
    assert!(e.contains("`camera.look_at`") && e.contains("finite"), "{e}");
    let e = err("", &["camera.up=[nan, 1, 0]"]);
    assert!(e.contains("`camera.up`") && e.contains("finite"), "{e}");
    // Objects: far away, infinite or huge scale, empty mesh, unknown primitive.
    let e = err("[[objects]]\nposition = [1e30, 0, 0]\n", &[]);
    assert!(e.contains("`objects[0].position`"), "{e}");
    let e = err("[[objects]]\nscale = [inf, 1, 1]\n", &[]);
    assert!(e.contains("`objects[0].scale`") && e.contains("finite"), "{e}");
    let e = err("[[objects]]\nscale = [1e30, 1, 1]\n", &[]);
    assert!(e.contains("`objects[0].scale`"), "{e}");
    let e = err("[[objects]]\nmesh = \"\"\n", &[]);
    assert!(e.contains("`objects[0].mesh`") && e.contains("leave the key out"), "{e}");
    let e = err("[[objects]]\n[[objects]]\nprimitive = \"torus\"\n", &[]);
    assert!(e.contains("`objects[1].primitive`") && e.contains("\"torus\""), "{e}");
    // Integers out of the key's range, and beyond TOML's.
    // (the key's own rule, not u32's range, where the key has one)
    let e = err("", &["ocean.resolution=4294967296"]);
    assert!(
        e.contains("--set `ocean.resolution=4294967296`") && e.contains("from 64 to 1024"),
        "{e}"
    );
    let e = err("", &["ocean.seed=-1"]);
    assert!(e.starts_with("--set: `ocean.seed`") && e.contains("≥ 0"), "{e}");
    let e = err("[ocean]\nseed = 18446744073709551615\n", &[]);
    assert!(e.contains("`ocean.seed`") && e.contains("9223372036854775807"), "{e}");
    let e = err("", &["ocean.seed=18446744073709551615"]);
    assert!(e.contains("number TOML cannot hold"), "{e}");
    let long = format!("ocean.wind_speed={}", "9".repeat(400));
    let e = err("", &[&long]);
    assert!(e.contains("number TOML cannot hold") && e.len() < 300, "{e}");
}

#[test]
fn syntax_errors_name_line_and_column() {
    let e = Scene::from_toml("[ocean]\nwind_speed = = 3\n", "x.toml", &[]).unwrap_err().to_string();
    assert!(e.starts_with("x.toml:2:"), "{e}");
    assert!(!e.contains('\n'));
}

#[test]
fn a_file_with_one_section_gets_defaults_for_the_rest() {
    let s = Scene::from_toml("[sun]\nelevation_deg = 10\n", "x.toml", &[]).unwrap();
    assert_eq!(s.sun.elevation_deg, 10.0);
    assert_eq!(s.ocean, super::super::OceanDesc::default());
}

#[test]
fn fluid_open_sides_are_a_list_of_names() {
    let s = Scene::load("dam_break", &["fluid.open=[\"+x\", \"-y\"]".into()]).expect("valid");
    assert_eq!(s.fluid.open_sides(), [[false, true], [true, false], [false, false]]);
    let err = Scene::load("dam_break", &["fluid.open=[1]".into()]).unwrap_err().to_string();
    assert!(err.contains("an array of strings"), "{err}");
}

/// Foam tiles with an FFT ocean's patch only where there is no interactive
/// water: a wake's or a splash's foam is drawn once, in the interactive
/// water's window, not again every patch across the sea.
#[test]
fn foam_tiles_only_on_an_ocean_without_interactive_water() {
    let storm = Scene::load("storm", &[]).unwrap();
    assert!(storm.foam_tiles());
    for name in ["wake", "harbor", "pool"] {
        let s = Scene::load(name, &[]).unwrap();
        assert!(!s.foam_tiles(), "{name}");
        assert_eq!(s.foam_extent(), s.ripples.extent, "{name}");
    }
    let wider = Scene::load("wake", &["whitewater.extent=200".into()]).unwrap();
    assert_eq!(wider.foam_extent(), 200.0);
}

/// A path is checked when the scene loads: one line naming the key, the
/// bad value and what is allowed.
#[test]
fn a_bad_path_is_a_clear_error() {
    let scene = |path: &str| {
        Scene::from_toml(
            &format!("[[objects]]\nprimitive = \"box\"\n[objects.path]\n{path}\n"),
            "test",
            &[],
        )
    };
    assert!(scene("points = [[0, 0, 0], [4, 0, 0]]\nspeed = 2").is_ok());
    for (bad, says) in [
        ("points = [[0, 0, 0]]\nspeed = 2", "2 to 256 points"),
        ("points = [[0, 0, 0], [4, 0, 0]]\ntimes = [0, 2]\nspeed = 2", "not both"),
        ("points = [[0, 0, 0], [4, 0, 0]]\ntimes = [1, 2]", "increasing times from 0"),
        ("points = [[0, 0, 0], [4, 0, 0]]", "speed"),
        ("points = [[0, 0], [4, 0, 0]]\nspeed = 2", "[x, y, z] points"),
    ] {
        let e = scene(bad).unwrap_err().to_string();
        assert!(e.contains("objects[0].path") && e.contains(says), "{bad}: {e}");
    }
    let both = Scene::from_toml(
        "[[objects]]\nprimitive = \"box\"\nvelocity = [1, 0, 0]\n[objects.path]\npoints = [[0, 0, 0], [4, 0, 0]]\nspeed = 2\n",
        "test",
        &[],
    );
    assert!(both.unwrap_err().to_string().contains("leave dynamic false and velocity zero"));
}
