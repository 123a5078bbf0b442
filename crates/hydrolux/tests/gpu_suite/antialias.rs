// GPU tests: the temporal anti-aliasing (hydrolux_core::antialias): the
// resolve against its CPU twin, a still and a panning camera against a
// supersampled frame, and the debug views drawn exact.

use super::harness::*;
use glam::Vec3;
use hydrolux::core::antialias;

/// The resolve's arithmetic on the GPU (the probe runs the same WGSL
/// function the resolve pass does) is the CPU twin's.
fn resolve_matches_the_twin(r: &Renderer) {
    let mut rng = hydrolux::core::rng::SplitMix64::new(7);
    let mut colour = |scale: f32| {
        let mut c = [0.0f32; 3];
        for v in &mut c {
            *v = rng.unit() as f32 * scale;
        }
        c
    };
    let mut queries = Vec::new();
    for i in 0..96u64 {
        let scale = [0.05, 1.0, 20.0][i as usize % 3];
        let neighbourhood: [Vec3; 9] = std::array::from_fn(|_| Vec3::from(colour(scale)));
        let history = (i % 5 != 0).then(|| antialias::History {
            colour: Vec3::from(colour(scale * 2.0)),
            frames: i % 12 + 1,
            settled: i % 4 == 1,
        });
        let trust = [0.0, 0.4, 1.0][(i as usize / 5) % 3];
        queries.push(hydrolux::AntialiasQuery { neighbourhood, history, trust });
    }
    let gpu = r.probe_antialias(&queries);
    assert_eq!(gpu.len(), queries.len());
    for (q, got) in queries.iter().zip(&gpu) {
        let want = antialias::resolve(&q.neighbourhood, q.history, q.trust);
        let got = Vec3::from(*got);
        let err = (got - want).abs().max_element() / want.abs().max_element().max(1e-3);
        assert!(err < 1e-4, "{q:?}: GPU {got} CPU {want}");
    }
}

/// Linear HDR, tone-mapped (what the eye compares), of an image.
fn toned(hdr: &[[f32; 4]]) -> Vec<Vec3> {
    hdr.iter().map(|p| aces_filmic(Vec3::new(p[0], p[1], p[2]))).collect()
}

/// Mean per-channel difference of two tone-mapped images over the pixels
/// `edges` marks.
fn mean_difference(a: &[Vec3], b: &[Vec3], edges: &[bool]) -> f32 {
    let d = a.iter().zip(b).zip(edges).filter(|(_, e)| **e);
    let n = edges.iter().filter(|e| **e).count().max(1);
    d.map(|((x, y), _)| (*x - *y).abs().element_sum() / 3.0).sum::<f32>() / n as f32
}

/// `hdr` (w·k × h·k) averaged over k × k blocks (the supersampled frame),
/// and which blocks straddle an edge (their tone-mapped luma spans more
/// than 0.15): where a pixel aliases. Elsewhere the two sizes differ by
/// what is filtered by the pixel's footprint (textures, the tiles'
/// pattern), not by aliasing.
fn box_down(hdr: &[[f32; 4]], (w, h): (u32, u32), k: u32) -> (Vec<[f32; 4]>, Vec<bool>) {
    let (w, h, k) = (w as usize, h as usize, k as usize);
    let mut out = vec![[0.0f32; 4]; w * h];
    let mut range = vec![(f32::MAX, f32::MIN); w * h];
    for y in 0..h * k {
        for x in 0..w * k {
            let p = hdr[y * w * k + x];
            let i = (y / k) * w + x / k;
            for c in 0..4 {
                out[i][c] += p[c] / (k * k) as f32;
            }
            let l = aces_filmic(Vec3::new(p[0], p[1], p[2])).dot(Vec3::new(0.2126, 0.7152, 0.0722));
            range[i] = (range[i].0.min(l), range[i].1.max(l));
        }
    }
    (out, range.iter().map(|(lo, hi)| hi - lo > 0.15).collect())
}

#[test]
fn the_resolve_matches_its_twin_and_edges_converge_to_the_supersampled_frame() {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    // The pool at rest, its edges and the ball what alias. Its tiles are
    // plain: their pattern is filtered by each pixel's footprint, so the
    // two sizes would differ there by more than aliasing.
    let load = |mode: &str| {
        let mut s = Scene::load("pool", &[format!("render.antialias=\"{mode}\"")]).expect("pool");
        use hydrolux::core::scene::Pattern;
        s.floor.material.pattern = Pattern::None;
        for o in &mut s.objects {
            o.material.pattern = Pattern::None;
        }
        high(&s)
    };
    let (on, off) = (load("temporal"), load("off"));
    let mut r = renderer(&ctx, &on);
    resolve_matches_the_twin(&r);

    let size = (64, 36);
    let k = 4;
    let camera = on.camera();
    let t = 0.0;
    // The reference: the frame drawn at 4 × 4 the pixels, averaged.
    r.set_scene(&off).expect("edit");
    let big = HeadlessTarget::new(&ctx.device, (size.0 * k, size.1 * k));
    big.render(&mut r, camera, t).expect("frame");
    let (reference, edges) = box_down(&r.read_hdr().unwrap().2, size, k);
    let reference = toned(&reference);
    let edge_count = edges.iter().filter(|e| **e).count();
    assert!(edge_count > 40, "{edge_count} edge pixels");
    let small = HeadlessTarget::new(&ctx.device, size);
    small.render(&mut r, camera, t).expect("frame");
    let aliased = toned(&r.read_hdr().unwrap().2);
    let aliased_error = mean_difference(&aliased, &reference, &edges);
    assert!(aliased_error > 0.02, "the test scene has edges that alias: {aliased_error}");

    // A still: one cycle of jittered frames at one time.
    r.set_scene(&on).expect("edit");
    small.render(&mut r, camera, t).expect("frame");
    let as_drawn = toned(&r.read_hdr().unwrap().2);
    assert_eq!(as_drawn, aliased, "the first frame is the frame as drawn");
    for _ in 1..antialias::JITTER_PERIOD {
        small.render(&mut r, camera, t).expect("frame");
    }
    let still = toned(&r.read_hdr().unwrap().2);
    let still_error = mean_difference(&still, &reference, &edges);
    assert!(
        still_error < 0.35 * aliased_error,
        "still: {still_error} from the supersampled frame, drawn once {aliased_error}"
    );

    // A camera panning sideways, 0.3 px a frame: what the history holds is
    // reprojected, so the frame stays anti-aliased rather than smeared.
    let mut pan = camera;
    let right = (camera.look_at - camera.position).cross(Vec3::Y).normalize();
    for _ in 0..12 {
        pan.position += right * 0.01;
        pan.look_at += right * 0.01;
        small.render(&mut r, pan, t).expect("frame");
    }
    let panned = toned(&r.read_hdr().unwrap().2);
    r.set_scene(&off).expect("edit");
    big.render(&mut r, pan, t).expect("frame");
    let (reference, edges) = box_down(&r.read_hdr().unwrap().2, size, k);
    let reference = toned(&reference);
    small.render(&mut r, pan, t).expect("frame");
    let aliased_error = mean_difference(&toned(&r.read_hdr().unwrap().2), &reference, &edges);
    let pan_error = mean_difference(&panned, &reference, &edges);
    assert!(
        pan_error < 0.6 * aliased_error,
        "panning: {pan_error} from the supersampled frame, drawn once {aliased_error}"
    );

    // Debug views are drawn exact: no jitter, frame after frame.
    let mut normals = on.clone();
    normals.render.view = hydrolux::core::scene::DebugView::Normals;
    r.set_scene(&normals).expect("edit");
    let a = small.render(&mut r, camera, t).expect("frame");
    let b = small.render(&mut r, camera, t).expect("frame");
    assert_eq!(a, b, "a debug view moved between frames");
}
