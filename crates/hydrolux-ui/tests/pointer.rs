//! The pointer on the pool as a person uses it (issue #26, item 4): press B
//! to drop the ball in, draw a stroke of ripples across the water and
//! through the floating ball, then grab the ball and shake it through the
//! water, let go and watch. Nothing a pointer can do may make the water
//! unstable: every frame the water stays finite and bounded (a hard shake
//! of a 0.9 m ball does raise a stern wave about the deck's 0.3 m, so the
//! bound is 0.6 m), its hollows stay above the floor (1.6 m down), foam
//! never covers a third of the pool, the ball stays in it, and once let
//! go the waves die down. Before the hulls' contact, B's hollow sprang up
//! 0.41 m, the plunge dug to −2.1 m and spouted over the deck, and foam
//! covered half the pool. Run on the default adapter (lavapipe in CI) at
//! the tier the viewer picks there (`auto`), about 20 s.

use glam::Vec3;
use hydrolux::core::scene::Scene;
use hydrolux::{GpuContext, Renderer};
use hydrolux_ui::Pointer;
use hydrolux_ui::pointer::drop_ball;

const SIZE: (u32, u32) = (64, 48);
const ASPECT: f32 = SIZE.0 as f32 / SIZE.1 as f32;
const FPS: f64 = 30.0;

/// Where world point `p` is in the view, as the pointer's `ndc`.
fn ndc_of(scene: &Scene, p: Vec3) -> [f32; 2] {
    let clip = scene.camera().view_projection(ASPECT) * p.extend(1.0);
    [clip.x / clip.w, clip.y / clip.w]
}

struct Check {
    highest: f32,
    last_highest: f32,
    foam_cover: f64,
}

/// One frame at `t`; its water, foam and ball must be sane.
fn frame(r: &mut Renderer, scene: &Scene, t: f64, what: &str, check: &mut Check) {
    r.simulate(&scene.camera(), SIZE, t);
    let water = r.read_ripples().expect("the pool's water is dynamic");
    // Up, not down: under the ball the water is its hollow (its draft).
    let highest = water.heights.iter().fold(0.0f32, |m, &h| m.max(h));
    let lowest = water.heights.iter().fold(0.0f32, |m, &h| m.min(h));
    let ball = r.bodies()[0].pose.position;
    // Shown when the test fails: how it came to that.
    let n = water.cells as usize;
    let top = (0..n * n).max_by(|&a, &b| water.heights[a].total_cmp(&water.heights[b])).unwrap();
    let top_at =
        [0, 1].map(|a| water.origin[a] + ([top % n, top / n][a] as f32 + 0.5) * water.cell_size);
    eprintln!(
        "{what}, t = {t:.2} s: water {lowest:.3} to {highest:.3} m (at {top_at:.2?}), ball at {ball:.2}"
    );
    assert!(
        water.heights.iter().all(|h| h.is_finite()) && highest < 0.6 && lowest > -1.4,
        "{what}, t = {t:.2} s: the water reached {highest} m (the deck is at 0.3 m), fell to {lowest} m"
    );
    check.highest = check.highest.max(highest);
    check.last_highest = highest;
    if let Some(foam) = r.read_foam() {
        let cover = foam.coverage();
        assert!(cover < 0.3, "{what}, t = {t:.2} s: foam covers {:.0}% of the pool", cover * 100.0);
        check.foam_cover = check.foam_cover.max(cover);
    }
    assert!(
        ball.is_finite() && ball.x.abs() < 2.0 && ball.z.abs() < 2.0 && ball.y.abs() < 1.6,
        "{what}, t = {t:.2} s: the ball is at {ball}"
    );
}

#[test]
fn no_pointer_stroke_or_shake_makes_the_pool_unstable() {
    let ctx = GpuContext::headless().expect("an adapter (CI installs mesa-vulkan-drivers)");
    let scene = Scene::load("pool", &[]).expect("built-in");
    let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)
        .expect("renderer");
    let camera = scene.camera();
    let mut pointer = Pointer::default();
    let mut check = Check { highest: 0.0, last_highest: 0.0, foam_cover: 0.0 };
    let mut t = scene.start_time;
    let mut next = |r: &mut Renderer, what: &str, check: &mut Check| {
        t += 1.0 / FPS;
        frame(r, &scene, t, what, check);
    };
    next(&mut r, "opening", &mut check);
    // B: the ball dropped in from a metre above the middle of the view.
    assert!(drop_ball(&mut r, &camera, [0.0, 0.0], ASPECT));
    for _ in 0..8 {
        next(&mut r, "the ball dropped in", &mut check);
    }
    // A stroke of ripples from left to right across the view, through
    // where the ball floats, three pointer moves a frame as a fast hand
    // gives them.
    let ball = r.bodies()[0].pose.position.as_vec3();
    let through = ndc_of(&scene, Vec3::new(ball.x, 0.0, ball.z));
    let start = [-0.8, through[1]];
    assert!(pointer.press(&mut r, &camera, start, ASPECT), "the press lands on the water");
    let moves = 60;
    for m in 1..=moves {
        let x = -0.8 + 1.6 * m as f32 / moves as f32;
        pointer.drag(&mut r, &camera, [x, through[1] + 0.05 * (m as f32 * 0.7).sin()], ASPECT);
        if m % 3 == 0 {
            next(&mut r, "a stroke across the ball", &mut check);
        }
    }
    pointer.release();
    for _ in 0..15 {
        next(&mut r, "after the stroke", &mut check);
    }
    // Grab the ball and shake it hard through the water, then let go.
    let ball = r.bodies()[0].pose.position.as_vec3();
    let at = ndc_of(&scene, ball);
    assert!(pointer.press(&mut r, &camera, at, ASPECT), "the press grabs the ball");
    for m in 0..24 {
        let swing = if (m / 4) % 2 == 0 { 0.5 } else { -0.5 };
        pointer.drag(&mut r, &camera, [at[0] + swing, at[1] - 0.2 * swing], ASPECT);
        next(&mut r, "shaking the ball", &mut check);
    }
    pointer.release();
    for _ in 0..75 {
        next(&mut r, "after the shake", &mut check);
    }
    let calm = check.last_highest;
    eprintln!(
        "highest water {:.3} m, most foam {:.1}% of the pool",
        check.highest,
        check.foam_cover * 100.0
    );
    // The stroke and the shake did disturb the water (the check above is
    // not of still water).
    assert!(check.highest > 0.01, "the pointer made waves: {} m", check.highest);
    // And they die down once the pointer lets go.
    assert!(
        calm < 0.7 * check.highest,
        "2.5 s after the shake the water still stands {calm} m high"
    );
}
