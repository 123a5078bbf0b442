// GPU tests: Seed 004's light through a water object against the analytic refraction.

use super::harness::*;

/// Seed 004's light paths through a water sphere: the GPU marches the
/// exit point p1 against the back-face depth from the light; it must land on
/// the analytic exit point (hydrolux_core::water_object) within the light
/// view's texel size, leave in the analytic direction, and carry the
/// analytic Fresnel transmittance.
#[test]
fn water_sphere_exit_points_match_the_analytic_refraction() {
    use hydrolux::core::water_object::sphere_path;
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let text = "[water]\nmodel = \"none\"\n[floor]\ndepth = 0.001\n[sun]\nelevation_deg = 62.0\nazimuth_deg = 20.0\n\
                [camera]\nposition = [3.0, 2.0, 3.0]\nlook_at = [0.0, 0.6, 0.0]\n[air]\nfog = 0.05\n[godrays]\nobject_resolution = 256\n\
                [[objects]]\nprimitive = \"sphere\"\nposition = [0.0, 1.0, 0.0]\nmaterial = { ior = 1.333 }\n";
    let s = Scene::from_toml(text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    HeadlessTarget::new(&ctx.device, (48, 32)).render(&mut r, s.camera(), 0.0).expect("frame");
    let (view_proj, k) = r.object_light_view().expect("a refractive object under the sun");
    let paths = r.read_object_paths();
    let inv = view_proj.inverse();
    let sun = s.sun_direction();
    let texel = (inv.project_point3(glam::Vec3::new(1.0, 0.0, 0.5))
        - inv.project_point3(glam::Vec3::new(1.0 - 2.0 / k as f32, 0.0, 0.5)))
    .length();
    let (mut checked, mut worst, mut ratios, mut dir_errors, mut land_errors) =
        (0, 0.0f32, Vec::new(), Vec::new(), Vec::new());
    for j in 0..k {
        for i in 0..k {
            let g = paths[(j * k + i) as usize];
            let ndc = glam::Vec2::new(
                (i as f32 + 0.5) / k as f32 * 2.0 - 1.0,
                1.0 - (j as f32 + 0.5) / k as f32 * 2.0,
            );
            let origin = inv.project_point3(ndc.extend(0.0));
            // The sphere primitive has diameter 1 (radius 0.5); its mesh is
            // a 64 × 32 tessellation, so stay off the rim.
            let Some(want) = sphere_path(glam::Vec3::Y, 0.5, 1.333, origin, -sun) else { continue };
            let rim = (want.p0 - glam::Vec3::Y).normalize().dot(sun);
            if rim < 0.35 {
                continue;
            }
            assert!(g[7] > 0.0, "texel ({i}, {j}) should carry a path");
            let p1 = glam::Vec3::new(g[0], g[1], g[2]);
            let dir = glam::Vec3::new(g[4], g[5], g[6]);
            let miss = (p1 - want.p1).length();
            worst = worst.max(miss / texel);
            assert!(
                miss < 2.5 * texel,
                "texel ({i}, {j}): p1 {p1} vs analytic {} ({} texels)",
                want.p1,
                miss / texel
            );
            dir_errors.push((dir - want.exit_dir).length());
            // Where it lands: on the floor plane, where the analytic path does.
            let p2 = p1 + dir * g[3];
            let want_p2 = want.p1 + want.exit_dir * ((-0.001 - want.p1.y) / want.exit_dir.y);
            land_errors.push((p2 - want_p2).length());
            ratios.push(g[7] / (want.transmitted * texel * texel));
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked} paths checked");
    ratios.sort_by(|a, b| a.total_cmp(b));
    let (p5, median, p95) =
        (ratios[ratios.len() / 20], ratios[ratios.len() / 2], ratios[ratios.len() * 19 / 20]);
    eprintln!(
        "{checked} paths; worst p1 error {worst:.2} texels; flux GPU/analytic {p5:.3} {median:.3} {p95:.3}"
    );
    assert!((median - 1.0).abs() < 0.02, "median flux ratio {median}");
    // The exit direction follows the back face's normal, which the GPU reads
    // from a texel of the tessellated mesh: close on the whole, looser at worst.
    dir_errors.sort_by(|a, b| a.total_cmp(b));
    let (dir_median, dir_p95) =
        (dir_errors[dir_errors.len() / 2], dir_errors[dir_errors.len() * 19 / 20]);
    eprintln!("exit direction error: median {dir_median:.4}, 95th percentile {dir_p95:.4}");
    assert!(
        dir_median < 0.02 && dir_p95 < 0.08,
        "exit direction error median {dir_median}, 95th percentile {dir_p95}"
    );

    // The caustic map holds all the light that came through (the splat and
    // its filter conserve it): Σ map = Σ transmitted × tint over the paths.
    let (_, map) = r.read_object_caustics();
    let through: f32 =
        paths.iter().filter(|g| g[7] > 0.0).map(|g| g[7] / (texel * texel) * g[10]).sum();
    let landed: f32 = map.iter().map(|m| m[2]).sum();
    let peak = map.iter().map(|m| m[2]).fold(0.0f32, f32::max);
    eprintln!("light through {through}, landed {landed}, peak {peak}");
    land_errors.sort_by(|a, b| a.total_cmp(b));
    eprintln!(
        "landing error median {} p95 {}",
        land_errors[land_errors.len() / 2],
        land_errors[land_errors.len() * 19 / 20]
    );
    assert!((landed / through - 1.0).abs() < 0.02, "landed {landed} vs through {through}");
    // A water ball 0.5 m above the floor is a lens focused near the floor.
    assert!(peak > 10.0, "the ball lens should focus the sunlight: peak {peak}× the sun");
    assert!(
        land_errors[land_errors.len() / 2] < 0.05,
        "paths land within 5 cm of the analytic landing point (median)"
    );
    assert!(p5 > 0.9 && p95 < 1.1, "flux ratio 5th–95th percentile {p5}–{p95}");
}

/// A glass wall (ior 1.5) in the sunlight, a water ball (1.333) behind it
/// along the light, the ball listed first: the light through the wall
/// leaves it as it came (a parallel plate, `plate_path`), carrying the
/// glass's Fresnel transmittance, not the water's, even where the ball lies
/// further along its line. Each face carries its own index of refraction,
/// and the light leaves at the first thing's back face, not at the
/// farthest one (which turned a glass tank with water in it dark).
#[test]
fn light_through_a_glass_wall_leaves_it_unbent_with_the_glass_transmittance() {
    use hydrolux::core::optics::{IOR_AIR, fresnel_exact};
    use hydrolux::core::water_object::{plate_path, sphere_path};
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let (elevation, azimuth) = (40.0f32, 35.0f32);
    let sun = hydrolux::core::sky::sun_direction(elevation, azimuth);
    let ball = glam::Vec3::new(0.0, 1.2, 0.0) - sun * 0.9;
    let (half, glass) = (0.02f32, 1.5f32);
    let text = format!(
        "[water]\nmodel = \"none\"\n[floor]\ndepth = 0.001\n[sun]\nelevation_deg = {elevation}\nazimuth_deg = {azimuth}\n\
         [camera]\nposition = [3.0, 2.0, 3.0]\nlook_at = [0.0, 0.6, 0.0]\n[godrays]\nobject_resolution = 256\n\
         [[objects]]\nprimitive = \"sphere\"\nposition = [{}, {}, {}]\nmaterial = {{ ior = 1.333 }}\n\
         [[objects]]\nprimitive = \"box\"\nposition = [0.0, 0.8, 0.0]\nscale = [{}, 1.6, 1.6]\nmaterial = {{ ior = {glass} }}\n",
        ball.x,
        ball.y,
        ball.z,
        2.0 * half
    );
    let s = Scene::from_toml(&text, "test", &[]).expect("valid scene");
    let mut r = renderer(&ctx, &s);
    HeadlessTarget::new(&ctx.device, (48, 32)).render(&mut r, s.camera(), 0.0).expect("frame");
    let (view_proj, k) = r.object_light_view().expect("refractive objects under the sun");
    let paths = r.read_object_paths();
    let inv = view_proj.inverse();
    let texel = (inv.project_point3(glam::Vec3::new(1.0, 0.0, 0.5))
        - inv.project_point3(glam::Vec3::new(1.0 - 2.0 / k as f32, 0.0, 0.5)))
    .length();
    let (mut checked, mut behind_ball) = (0, 0);
    let (mut ratios, mut dir_errors) = (Vec::new(), Vec::new());
    for j in 0..k {
        for i in 0..k {
            let ndc = glam::Vec2::new(
                (i as f32 + 0.5) / k as f32 * 2.0 - 1.0,
                1.0 - (j as f32 + 0.5) / k as f32 * 2.0,
            );
            let origin = inv.project_point3(ndc.extend(0.0));
            let Some(want) = plate_path(
                glam::Vec3::new(0.0, 0.8, 0.0),
                glam::Vec3::X,
                half,
                glass,
                origin,
                -sun,
            ) else {
                continue;
            };
            // On the wall's sunlit face and out of its far one, four texels
            // clear of its edges, and not behind the ball from the sun.
            let inside = |p: glam::Vec3| {
                p.y > 4.0 * texel && p.y < 1.6 - 4.0 * texel && p.z.abs() < 0.8 - 4.0 * texel
            };
            if !inside(want.p0)
                || !inside(want.p1)
                || sphere_path(ball, 0.5, 1.333, origin, -sun)
                    .is_some_and(|b| (b.p0 - origin).length() < (want.p0 - origin).length())
            {
                continue;
            }
            let g = paths[(j * k + i) as usize];
            assert!(g[7] > 0.0, "texel ({i}, {j}) should carry a path");
            let dir = glam::Vec3::new(g[4], g[5], g[6]);
            dir_errors.push((dir - want.exit_dir).length());
            ratios.push(g[7] / (want.transmitted * texel * texel));
            behind_ball += sphere_path(ball, 0.5, 1.333, want.p1, -sun).is_some() as u32;
            checked += 1;
        }
    }
    assert!(
        checked > 1000 && behind_ball > 300,
        "{checked} paths checked, {behind_ball} on to the ball"
    );
    ratios.sort_by(|a, b| a.total_cmp(b));
    dir_errors.sort_by(|a, b| a.total_cmp(b));
    let median = ratios[ratios.len() / 2];
    let worst_dir = dir_errors[dir_errors.len() * 99 / 100];
    let cos0 = sun.dot(glam::Vec3::X);
    let water = (1.0 - fresnel_exact(cos0, IOR_AIR, 1.333)).powi(2);
    let glass_t = (1.0 - fresnel_exact(cos0, IOR_AIR, glass)).powi(2);
    eprintln!(
        "{checked} paths ({behind_ball} on to the ball): flux / glass's {median:.4} (water's would be {:.4}); exit direction error 99th percentile {worst_dir:.5}",
        water / glass_t
    );
    assert!((median - 1.0).abs() < 0.01, "median flux ratio {median}");
    assert!(worst_dir < 0.01, "the wall bends the light: 99th percentile error {worst_dir}");
}

/// A clear sphere carried 12 m across a floor (a kinematic object) casts
/// its shadow and focuses its caustic where it is, as the same sphere
/// standing there does: the refractive objects' light view is fitted to
/// them where they are and drawn again when they move (it was fitted where
/// the scene started and drawn once).
#[test]
fn a_moving_glass_sphere_lights_the_floor_where_it_is() {
    let toml = |position: &str, velocity: &str| {
        format!(
            "[camera]\nposition = [0.0, 9.0, 0.01]\nlook_at = [0.0, 0.0, 0.0]\nfov_y_deg = 45.0\n\
             [sun]\nelevation_deg = 35.0\nazimuth_deg = 0.0\n\
             [water]\nmodel = \"none\"\nmedium = \"pure\"\n[floor]\ndepth = 1.0\n\
             [[objects]]\nprimitive = \"sphere\"\nposition = {position}\nscale = [1.5, 1.5, 1.5]\n\
             velocity = {velocity}\n[objects.material]\nior = 1.5\n"
        )
    };
    let moved =
        Scene::from_toml(&toml("[-12.0, 0.0, 0.0]", "[3.0, 0.0, 0.0]"), "moved", &[]).unwrap();
    let standing =
        Scene::from_toml(&toml("[0.0, 0.0, 0.0]", "[0.0, 0.0, 0.0]"), "standing", &[]).unwrap();
    assert_moved_looks_standing("moving-glass", &moved, &standing);
}
