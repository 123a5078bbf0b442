//! Bad and hostile input: one line naming the bad value, exit status 1,
//! no panic and no file.

use super::*;

#[test]
fn bad_input_is_one_line_exit_1_and_writes_nothing() {
    let dir = scratch("bad");
    std::fs::write(dir.join("broken.toml"), "[ocean]\nwind_speed = = 3\n").unwrap();
    std::fs::write(dir.join("no_mesh.toml"), "[[objects]]\nmesh = \"nope.obj\"\n").unwrap();
    std::fs::write(dir.join("bad.glb"), "not a glb").unwrap();
    std::fs::write(dir.join("ripples_only.toml"), "[ripples]\nresolution = 64\n").unwrap();
    std::fs::write(dir.join("bad_mesh.toml"), "[[objects]]\nmesh = \"bad.glb\"\n").unwrap();
    std::fs::write(
        dir.join("no_texture.toml"),
        "[[objects]]\n[objects.material]\ntexture = \"nope.png\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("refractive_in_water.toml"),
        "[[objects]]\nprimitive = \"sphere\"\nmaterial = { ior = 1.333 }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("unknown_builtin_mesh.toml"),
        "[water]\nmodel = \"none\"\n[[objects]]\nmesh = \"builtin:teapot\"\n",
    )
    .unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--scene", "nowhere"], "unknown scene `nowhere`"),
        (&["render", "--scene", "missing.toml"], "cannot read scene file missing.toml"),
        (&["render", "--scene", "broken.toml"], "broken.toml:2:"),
        (&["render", "--set", "ocean.wind_sped=3"], "did you mean `ocean.wind_speed`"),
        (&["render", "--set", "ocean.wind_speed=\"fast\""], "must be a number"),
        (&["render", "--set", "ocean.wind_speed=-1"], "`ocean.wind_speed` = -1 is out of range"),
        (&["render", "--set", "ocean.resolution=100"], "power of two"),
        (&["render", "--set", "camera.fov_y_deg=0"], "(0, 180)"),
        (
            &["render", "--width", "0"],
            "'0' for '--width <WIDTH>': must be a whole number from 1 to 16384 pixels",
        ),
        (&["render", "--out", "picture.jpg"], "must end in .png or .exr"),
        (&["render", "--out", "no/such/folder/x.png"], "does not exist"),
        (&["render", "--dump", "sky=x.npy"], "unknown buffer"),
        (
            &["render", "--frames", "0"],
            "'0' for '--frames <FRAMES>': must be a whole number from 1",
        ),
        (&["bench", "--frames", "0"], "must be a whole number from 1 to 1000000 frames"),
        // Each number in its option's own terms (not the integer type's),
        // and every time within the clock's range (1e30 once aborted).
        (
            &["render", "--time", "1e30"],
            "'1e30' for '--time <TIME>': must be a time from -1e9 to 1e9 s",
        ),
        (
            &["render", "--time", "-inf"],
            "'-inf' for '--time <TIME>': must be a time from -1e9 to 1e9 s",
        ),
        (&["render", "--time=nan"], "must be a time from -1e9 to 1e9 s"),
        (&["compare", "--time", "1e300"], "must be a time from -1e9 to 1e9 s"),
        (
            &["bench", "--start", "1e30"],
            "'1e30' for '--start <START>': must be a time from 0 to 1e9 s",
        ),
        (&["bench", "--start", "-1"], "must be a time from 0 to 1e9 s"),
        (
            &["render", "--frames", "3", "--fps", "1e-30"],
            "must be 0.001 to 10000 frames per second",
        ),
        (
            &["render", "--crf=-1", "--out", "v.mp4"],
            "must be a whole number from 0 (lossless) to 51",
        ),
        (&["render", "--height", "-1"], "must be a whole number from 1 to 16384 pixels"),
        (
            &["render", "--samples", "0"],
            "'0' for '--samples <SAMPLES>': must be a whole number from 1 to 64",
        ),
        (&["render", "--set", "render.antialias=msaa"], "render.antialias"),
        (
            &["render", "--frames", "4000000000", "--fps", "1"],
            "--frames 4000000000 at --fps 1 from t = 0 s ends at t = 3.999999999e9 s: the latest time is 1e9 s",
        ),
        (&["render", "--scene", "no_mesh.toml"], "cannot load mesh nope.obj: no such file"),
        (&["render", "--scene", "bad_mesh.toml"], "cannot load mesh bad.glb"),
        (&["render", "--scene", "no_texture.toml"], "cannot load texture nope.png: no such file"),
        (&["render", "--set", "water.medium=swamp"], "turbid_harbor"),
        (&["render", "--view", "xray"], "render.view"),
        (&["render", "--dump", "caustics=c.npy"], "the scene has no caustics"),
        (
            &["render", "--scene", "lake", "--set", "water.model=none", "--dump", "caustics=c.npy"],
            "the scene has no caustics",
        ),
        (&["render", "--set", "caustics.photons=3"], "`caustics.photons` = 3 is out of range"),
        (&["render", "--set", "water.model=heightfield"], "water.heightfield"),
        (
            &["render", "--set", "water.model=heightfield", "--set", "water.heightfield=nope.npy"],
            "cannot load heightfield nope.npy: no such file",
        ),
        (
            &[
                "render",
                "--set",
                "water.model=heightfield",
                "--set",
                "water.heightfield=broken.toml",
            ],
            "cannot load heightfield broken.toml: not a .npy file",
        ),
        (&["render", "--set", "godrays.method=rays"], "godrays.method"),
        (&["render", "--set", "godrays.resolution=2"], "`godrays.resolution` = 2 is out of range"),
        (&["render", "--set", "godrays.photons=1"], "`godrays.photons` = 1 is out of range"),
        (&["render", "--set", "air.fog=-0.1"], "`air.fog` = -0.1 is out of range"),
        (
            &["render", "--scene", "refractive_in_water.toml"],
            "refractive objects need water.model = \"none\"",
        ),
        (&["render", "--scene", "unknown_builtin_mesh.toml"], "cannot load mesh builtin:teapot"),
        (&["render", "--set", "godrays.method=off", "--dump", "godrays=g.npy"], "god rays are off"),
        (&["render", "--dump", "object_caustics=o.npy"], "no refractive object"),
        (&["render", "--dump", "ripples=r.npy"], "no interactive water"),
        (&["render", "--dump", "bodies=b.json"], "no moving object"),
        (&["render", "--scene", "pool", "--dump", "bodies=b.npy"], "must end in .json"),
        (&["render", "--scene", "pool", "--set", "ripples.rate=7"], "ripples.rate"),
        (&["render", "--out", "x.exr", "--dump", "hdr=./x.exr"], "the same file as --out x.exr"),
        (&["render", "--dump", "particles=p.exr"], "which an EXR image cannot hold; write .npy"),
        (
            &["render", "--dump", "hdr=h.npy", "--dump", "height=h.npy"],
            "--dump height=h.npy: the same file as --dump hdr=h.npy",
        ),
        (&["render", "--width", "-1"], "'--width <WIDTH>'"),
        (&["render", "--widht", "3"], "a similar argument exists: '--width'"),
        (&["render", "--frames", "-2"], "'--frames <FRAMES>'"),
        (&["render", "--set", "air.fog_g=1"], "open interval (-1, 1)"),
        (&["render", "--set", "water.method=exact"], "water.method"),
        (&["compare", "--view", "normals"], "--view"),
        (
            &["compare", "--scene", "lake", "--surfaces"],
            "--surfaces: the scene lake has no liquid ([fluid] with sources)",
        ),
        (
            &["compare", "--set", "water.model=none"],
            "--set water.model=none: the scene then has no water to compare",
        ),
        // Settings and views without effect are refused, naming both keys.
        (
            &["render", "--scene", "ripples_only.toml"],
            "`[ripples]` has no effect without `water.dynamic = true`",
        ),
        (
            &["render", "--set", "drops=[{time=1.0}]"],
            "`[[drops]]` has no effect without `water.dynamic = true`",
        ),
        (
            &["render", "--scene", "pool", "--set", "water.model=none"],
            "`water.dynamic = true` has no effect with `water.model = \"none\"`",
        ),
        (
            &["render", "--view", "ripples"],
            "\"ripples\" is out of range: it shows the interactive water, and the scene has none",
        ),
        (
            &["render", "--view", "foam", "--set", "whitewater.foam=false"],
            "it shows the foam, and the scene has none",
        ),
        (
            &["render", "--scene", "water_dragon", "--view", "fresnel"],
            "it is a view of the water, and the scene has none",
        ),
        (
            &["render", "--scene", "water_dragon", "--view", "error"],
            "it compares the water's methods or the liquid's surfaces, and the scene has neither",
        ),
        (
            &["render", "--scene", "pool", "--set", "ripples.resolution=4294967296"],
            "bad --set `ripples.resolution=4294967296`: out of range: must be a power of two from 16 to 512",
        ),
        (
            &["render", "--set", "objects=[{rotation_deg=[1e30,0,0]}]"],
            "must be angles within ±1000000 degrees",
        ),
        (&["compare", "--width", "0"], "'0' for '--width <WIDTH>'"),
        // The volumetric liquid (#29): a domain of 0 or 10¹² cells, a
        // source outside it, NaN, a view of a liquid the scene lacks, and
        // a grid past the device's buffers.
        (
            &["render", "--scene", "dam_break", "--set", "fluid.resolution=0"],
            "`fluid.resolution` = 0 is out of range: must be 4 to 512",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.resolution=1000000000000"],
            "fluid.resolution",
        ),
        (
            &[
                "render",
                "--scene",
                "dam_break",
                "--set",
                "fluid.sources=[{kind=\"block\",min=[0,0,0],max=[2,0.1,0.1]}]",
            ],
            "`fluid.sources[0].max` = [2.0, 0.1, 0.1] is out of range: must lie inside the domain",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.gravity=[nan,0,0]"],
            "`fluid.gravity` = [NaN, 0.0, 0.0] is out of range",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.open=[\"top\"]"],
            "`fluid.open` = \"top\" is out of range: each must be one of -x, +x, -y, +y, -z, +z",
        ),
        // A jet faster than a cell a step; a nozzle running backwards in time.
        (
            &[
                "render",
                "--scene",
                "pour",
                "--set",
                "fluid.sources=[{kind=\"nozzle\",position=[0,0.2,0],speed=50}]",
            ],
            "`fluid.sources[0].speed` = 50 is out of range: must be over 0 and at most a cell a step",
        ),
        (
            &[
                "render",
                "--scene",
                "pour",
                "--set",
                "fluid.sources=[{kind=\"nozzle\",position=[0,0.2,0],start=2,end=1}]",
            ],
            "`fluid.sources[0].end` = 1 is out of range: must be after start = 2 s",
        ),
        (&["render", "--view", "fluid"], "it shows the volumetric liquid, and the scene has none"),
        (
            &[
                "render",
                "--scene",
                "dam_break",
                "--set",
                "fluid.surface=points",
                "--dump",
                "fluid_mesh=m.npy",
            ],
            "the liquid's surface is not meshed (it needs fluid.surface = \"marching_cubes\" or \"screen_mesh\")",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.screen_depth_threshold=0.5"],
            "`fluid.screen_depth_threshold` = 0.5 is out of range: must be more than 1 and at most 20 particle radii (Table 1: z_max > r_z)",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.white_water=-1"],
            "`fluid.white_water` = -1 is out of range: must be 0 to 1000 particles per second",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.foam_life=0"],
            "`fluid.foam_life` = 0 is out of range: must be 0.1 to 60 seconds",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.screen_spacing=0"],
            "`fluid.screen_spacing` = 0 is out of range: must be 1 to 10 pixels between nodes",
        ),
        (
            &["render", "--scene", "dam_break", "--set", "fluid.surface_resolution=1000"],
            "`fluid.surface_resolution` = 1000 is out of range: must be 8 to 160",
        ),
        (
            &[
                "render",
                "--scene",
                "dam_break",
                "--set",
                "fluid.resolution=400",
                "--set",
                "fluid.budget=16000000",
                "--set",
                "fluid.particles_per_cell=1",
            ],
            "the liquid's face velocities (fluid.resolution) need a ",
        ),
    ];
    for (args, want) in cases {
        let (code, err) = hydrolux(args, &dir);
        assert_eq!(code, 1, "{args:?}: exit {code}, stderr {err}");
        assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
        assert_eq!(err.lines().count(), 1, "{args:?}: not one line: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    let mut left: Vec<String> =
        left.into_iter().map(|f| f.to_string_lossy().into_owned()).collect();
    left.sort();
    assert_eq!(
        left,
        [
            "bad.glb",
            "bad_mesh.toml",
            "broken.toml",
            "no_mesh.toml",
            "no_texture.toml",
            "refractive_in_water.toml",
            "ripples_only.toml",
            "unknown_builtin_mesh.toml"
        ],
        "files were written: {left:?}"
    );
}

#[test]
fn a_negative_time_is_a_time_in_either_spelling() {
    let dir = scratch("negative-time");
    for args in [&["--time", "-1.5"][..], &["--time=-1.5"][..]] {
        let mut all = vec!["render", "--width", "16", "--height", "16", "--out", "t.png"];
        all.extend_from_slice(args);
        let (code, err) = hydrolux(&all, &dir);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(dir.join("t.png").is_file());
    }
}

#[test]
fn hostile_input_is_refused_plainly() {
    let dir = scratch("hostile");
    let w = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
    // Input that never ends, is not a file, or is too large.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.toml")).unwrap();
        std::os::unix::fs::symlink("/dev/urandom", dir.join("random.npy")).unwrap();
        std::os::unix::fs::symlink("loop_b.obj", dir.join("loop_a.obj")).unwrap();
        std::os::unix::fs::symlink("loop_a.obj", dir.join("loop_b.obj")).unwrap();
    }
    let fifo =
        Command::new("mkfifo").arg(dir.join("fifo.toml")).status().is_ok_and(|s| s.success());
    std::fs::create_dir_all(dir.join("folder.obj")).unwrap();
    let object = "[[objects]]\nprimitive = \"sphere\"\nposition = [1, 2, 3]\n";
    w("huge.toml", object.repeat((5 << 20) / object.len() + 1).as_bytes());
    // Meshes, arrays and images that are corrupt.
    w("binary.obj", &[0xff, 0xfe, 0x00, 0x01]);
    w("bad_face.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    w("garbage.gltf", b"{ this is not json");
    w(
        "needs_bin.gltf",
        br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"geometry.bin"}]}"#,
    );
    w("garbage.npy", b"\x93NUMPY\x01\x00\x08\x00garbage!");
    w("text.png", b"not an image at all");
    let mesh = |name: &str| format!("[water]\nmodel = \"none\"\n[[objects]]\nmesh = \"{name}\"\n");
    for (scene, m) in [
        ("m_folder", "folder.obj"),
        ("m_loop", "loop_a.obj"),
        ("m_binary", "binary.obj"),
        ("m_face", "bad_face.obj"),
        ("m_garbage", "garbage.gltf"),
        ("m_bin", "needs_bin.gltf"),
    ] {
        w(&format!("{scene}.toml"), mesh(m).as_bytes());
    }
    w("texture.toml", b"[[objects]]\n[objects.material]\ntexture = \"text.png\"\n");
    w("empty_mesh.toml", b"[[objects]]\nmesh = \"\"\n");
    w("torus.toml", b"[[objects]]\n[[objects]]\nprimitive = \"torus\"\n");
    w("far.toml", b"[[objects]]\nposition = [1e30, 0, 0]\n");
    w("inf_scale.toml", b"[[objects]]\nscale = [inf, 1, 1]\n");
    w("seed.toml", b"[ocean]\nseed = 18446744073709551615\n");
    w("many.toml", "[[objects]]\n".repeat(300_000).as_bytes());
    w("pure_and_custom.toml", b"[water]\nmedium = \"pure\"\nabsorption = [1, 1, 1]\n");
    let heightfield = |file: &str| {
        vec!["render", "--set", "water.model=heightfield", "--set", "water.heightfield=FILE"]
            .into_iter()
            .map(|a| {
                if a == "water.heightfield=FILE" {
                    format!("water.heightfield={file}")
                } else {
                    a.into()
                }
            })
            .collect::<Vec<String>>()
    };
    let long_number = format!("ocean.wind_speed={}", "9".repeat(400));
    let mut cases: Vec<(Vec<String>, &str)> = vec![
        (heightfield("random.npy"), "not a regular file (a device, pipe or socket)"),
        (heightfield("garbage.npy"), "not a NumPy header dictionary"),
        (heightfield("folder.obj"), "it is a folder, not a file"),
        (
            vec!["render".into(), "--scene".into(), "huge.toml".into()],
            "more than the 4.0 MB allowed",
        ),
        (vec!["render".into(), "--set".into(), long_number], "a number TOML cannot hold"),
        (
            vec!["render".into(), "--set".into(), "ocean.seed=18446744073709551615".into()],
            "9223372036854775807",
        ),
        (
            vec!["render".into(), "--set".into(), "ocean.resolution=4294967296".into()],
            "bad --set `ocean.resolution=4294967296`: out of range: must be a power of two",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.position=[inf,0,0]".into()],
            "`camera.position`",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.position=[1e30,0,0]".into()],
            "`camera.position`",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.look_at=[nan,0,0]".into()],
            "must be finite",
        ),
        (vec!["render".into(), "--set".into(), "camera.up=[nan,1,0]".into()], "`camera.up`"),
        (
            vec![
                "render".into(),
                "--scene".into(),
                "pool".into(),
                "--set".into(),
                "water.absorption=[1,1,1]".into(),
                "--set".into(),
                "water.medium=pure".into(),
            ],
            "`water.absorption` must be given only with water.medium = \"custom\"",
        ),
        (
            vec![
                "render".into(),
                "--set".into(),
                "water.model=none".into(),
                "--dump".into(),
                "height=h.npy".into(),
            ],
            "no water surface",
        ),
        (vec!["render".into(), "--dump".into(), "godrays=g.npy".into()], "no god-ray buffer"),
        (vec!["render".into(), "--frame-range".into(), "5-2".into()], "FIRST ≤ LAST"),
        (
            vec![
                "render".into(),
                "--frames".into(),
                "3".into(),
                "--frame-range".into(),
                "1-3".into(),
            ],
            "numbered 0 to 2",
        ),
    ];
    for (scene, want) in [
        ("zero.toml", "not a regular file"),
        ("m_folder.toml", "cannot load mesh folder.obj: it is a folder, not a file"),
        ("m_loop.toml", "a loop of symbolic links"),
        ("m_binary.toml", "not text"),
        ("m_face.toml", "line 4: a face refers to vertex 9, of 3 defined before it"),
        ("m_garbage.toml", "not valid glTF JSON"),
        (
            "m_bin.toml",
            "cannot load mesh buffer geometry.bin: no such file (used by needs_bin.gltf)",
        ),
        ("texture.toml", "cannot load texture text.png: it is not a PNG or JPEG image"),
        ("empty_mesh.toml", "`objects[0].mesh`"),
        ("torus.toml", "`objects[1].primitive` must be one of"),
        ("far.toml", "`objects[0].position`"),
        ("inf_scale.toml", "`objects[0].scale`"),
        ("seed.toml", "`ocean.seed`: u64 value was too large"),
        ("many.toml", "(line 1025 starts object 1025) is out of range: at most 1024 objects"),
        ("pure_and_custom.toml", "`water.absorption`"),
    ] {
        cases.push((vec!["render".into(), "--scene".into(), scene.into()], want));
    }
    if fifo {
        cases.push((
            vec!["render".into(), "--scene".into(), "fifo.toml".into()],
            "not a regular file",
        ));
    }
    let before = files_in(&dir);
    for (args, want) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let t0 = std::time::Instant::now();
        let (code, err) = hydrolux(&args, &dir);
        let short: Vec<&str> =
            args.iter().map(|a| if a.len() > 60 { &a[..60] } else { a }).collect();
        assert_eq!(code, 1, "{short:?}: exit {code}, stderr {err}");
        assert!(err.contains(want), "{short:?}: `{err}` lacks `{want}`");
        assert_eq!(err.lines().count(), 1, "{short:?}: not one line: {err}");
        assert!(!err.contains("panicked") && !err.contains(".rs:"), "{short:?}: {err}");
        // Refused at once, not after reading an endless stream.
        assert!(t0.elapsed().as_secs() < 60, "{short:?} took {:?}", t0.elapsed());
    }
    assert_eq!(files_in(&dir), before, "a refused command wrote a file");
    // The environment: a backend that is no backend, and no display.
    let (code, err) = hydrolux_env(&["info"], &dir, &[("WGPU_BACKEND", Some("bogus"))]);
    assert!(code == 1 && err.contains("WGPU_BACKEND=\"bogus\"") && err.contains("vulkan"), "{err}");
    let no_display = [("DISPLAY", None), ("WAYLAND_DISPLAY", None), ("WAYLAND_SOCKET", None)];
    let (code, err) = hydrolux_env(&["view"], &dir, &no_display);
    assert!(code == 1 && err.contains("cannot open a window") && !err.contains(".rs:"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
