use super::*;

#[test]
fn frustum_keeps_what_is_ahead_and_drops_what_is_behind() {
    let cam = Camera {
        position: glam::Vec3::new(0.0, 5.0, 0.0),
        look_at: glam::Vec3::new(0.0, 0.0, -50.0),
        up: glam::Vec3::Y,
        fov_y_deg: 60.0,
    };
    let planes = frustum_planes(cam.view_projection(16.0 / 9.0));
    let ahead =
        box_visible(&planes, glam::Vec3::new(-5.0, -1.0, -40.0), glam::Vec3::new(5.0, 1.0, -30.0));
    let behind =
        box_visible(&planes, glam::Vec3::new(-5.0, -1.0, 30.0), glam::Vec3::new(5.0, 1.0, 40.0));
    let far_left = box_visible(
        &planes,
        glam::Vec3::new(-500.0, -1.0, -20.0),
        glam::Vec3::new(-400.0, 1.0, -10.0),
    );
    // A huge box around the camera is always visible.
    let around = box_visible(&planes, glam::Vec3::splat(-1000.0), glam::Vec3::splat(1000.0));
    assert!(ahead && !behind && !far_left && around);
    // Very far ahead is still inside: there is no far plane.
    assert!(box_visible(
        &planes,
        glam::Vec3::new(-10.0, -1.0, -90_000.0),
        glam::Vec3::new(10.0, 1.0, -80_000.0)
    ));
}

#[test]
fn every_ring_hole_is_exactly_the_finer_ring() {
    // For many camera positions, the finer ring's extent equals the hole.
    for i in 0..2000 {
        let xz = [i as f32 * 0.173 - 150.0, i as f32 * -0.311 + 40.0];
        for level in 1..DISPLACED_RINGS {
            let s = BASE_SPACING * 2f32.powi(level as i32);
            let (outer, inner) = (ring_centre(xz, level), ring_centre(xz, level - 1));
            let v = hole_variant(xz, level);
            let (dx, dz) = (v as i32 / 3 - 1, v as i32 % 3 - 1);
            let hole_centre = [outer[0] + dx as f32 * s, outer[1] + dz as f32 * s];
            assert!(
                (hole_centre[0] - inner[0]).abs() < 1e-3
                    && (hole_centre[1] - inner[1]).abs() < 1e-3,
                "{xz:?} level {level}"
            );
            // The finer ring stays near the camera.
            assert!((inner[0] - xz[0]).abs() <= s / 2.0 + 1e-3);
        }
    }
}

/// The foam's look in WGSL (passes/water/foam.wgsl) is its CPU twin's
/// (hydrolux_core::whitewater::foam_look): the same sizes, weights and the
/// measured quantile tables.
#[test]
fn wgsl_foam_look_constants_are_the_twins() {
    use hydrolux_core::whitewater::foam_look as twin;
    let source = crate::shaders::compose("", "#import water_foam\n");
    let module = naga::front::wgsl::parse_str(&source).expect("foam.wgsl parses");
    let init = |name: &str| {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{name} in foam.wgsl"));
        c.init
    };
    let literal = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
        naga::Expression::Literal(naga::Literal::F32(v)) => v,
        ref e => panic!("not an f32 literal: {e:?}"),
    };
    for (name, value) in [
        ("FOAM_REFERENCE_CELL", twin::FOAM_REFERENCE_CELL),
        ("LACE_CELL", twin::LACE_CELL),
        ("FINEST_LACE", twin::FINEST_LACE),
        ("BREAKUP", twin::BREAKUP),
        ("LACE_WARP", twin::LACE_WARP),
        ("WARP_SCALE", twin::WARP_SCALE),
        ("EDGE_SPAN", twin::EDGE_SPAN),
        ("LACE_WEIGHT", twin::LACE_WEIGHT),
        ("THICK_SPAN", twin::THICK_SPAN),
        ("MARBLE", twin::MARBLE),
        ("MARBLE_FROM", twin::MARBLE_FROM),
        ("MARBLE_TO", twin::MARBLE_TO),
        ("FOAM_WRAP", twin::FOAM_WRAP),
        ("FOAM_FILM_SHADE", twin::FOAM_FILM_SHADE),
    ] {
        assert_eq!(literal(init(name)), value, "{name}");
    }
    for (name, table) in [("FOAM_THRESHOLDS", twin::FOAM_THRESHOLDS)] {
        match &module.global_expressions[init(name)] {
            naga::Expression::Compose { components, .. } => {
                let wgsl: Vec<f32> = components.iter().map(|&h| literal(h)).collect();
                assert_eq!(wgsl, table, "{name}");
            }
            e => panic!("{name} is not an array literal: {e:?}"),
        }
    }
}
