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
