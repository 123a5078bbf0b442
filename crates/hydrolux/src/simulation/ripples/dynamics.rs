//! The water's state and what floats in it, stepped together on the
//! simulation clock: the interactive water on the GPU (`RipplePass`) and
//! the scene's moving bodies on the CPU (`hydrolux_core::bodies`, rapier3d).
//!
//! Each step, the bodies move first (buoyancy and drag from the water
//! surface), then the water takes their moves (`BodyMove`) and the drops.
//! The bodies see the water as rendered: the surface model's CPU twin plus
//! the interactive water's heights, read back from the GPU every
//! [`SYNC_STEPS`] steps (a fixed rhythm of simulated time, so the state
//! at a time does not depend on the frame rate).

use super::{MAX_STEPS, RipplePass, StepInput};
use hydrolux_core::bodies::{BodyState, BodyWorld, Pose};
use hydrolux_core::scene::{CLOCK_HZ, Scene};
use hydrolux_core::waves::heightfield::Heightfield;
use hydrolux_core::waves::ripples::{BodyMove, RippleBoundary, resting_heights};
use hydrolux_core::waves::sines::SineWaves;

/// Steps between readbacks of the water the bodies float in (0.1 s at 60 Hz).
pub const SYNC_STEPS: u64 = 6;
/// Time constant (s) of the water level bodies float on.
pub const LEVEL_SMOOTHING_S: f64 = 1.0;

/// The interactive water's heights as last read back, for buoyancy.
struct HeightsSeen {
    heights: Vec<f32>,
    cells: usize,
    cell: f64,
    origin: [f64; 2],
    walls: bool,
}

impl HeightsSeen {
    /// Bilinear height at world (x, z), as the surface shader samples it
    /// (0 outside the domain).
    fn at(&self, x: f64, z: f64) -> f64 {
        let n = self.cells;
        let side = n as f64 * self.cell;
        let (u, v) =
            ((x - self.origin[0]) / self.cell - 0.5, (z - self.origin[1]) / self.cell - 0.5);
        if !(-0.5..=side / self.cell - 0.5).contains(&u)
            || !(-0.5..=side / self.cell - 0.5).contains(&v)
        {
            return 0.0;
        }
        let (i0, j0) = (u.floor(), v.floor());
        let (a, b) = (u - i0, v - j0);
        let texel = |i: f64, j: f64| {
            let c = |k: f64| {
                if self.walls {
                    k.clamp(0.0, (n - 1) as f64) as usize
                } else {
                    k.rem_euclid(n as f64) as usize
                }
            };
            self.heights[c(j) * n + c(i)] as f64
        };
        let top = texel(i0, j0) * (1.0 - a) + texel(i0 + 1.0, j0) * a;
        let bottom = texel(i0, j0 + 1.0) * (1.0 - a) + texel(i0 + 1.0, j0 + 1.0) * a;
        top * (1.0 - b) + bottom * b
    }
}

pub struct Dynamics {
    pub ripples: Option<RipplePass>,
    pub bodies: Option<BodyWorld>,
    /// Scale of each body's object (its transform is scale × pose).
    scales: Vec<[f32; 3]>,
    /// The surface model's waves, for buoyancy (`Scene::floating_waves`:
    /// the sines, or the FFT sea's strongest modes; flat water is 0).
    waves: Option<SineWaves>,
    /// A user's surface (`water.model = "heightfield"`), as the caller last
    /// set it (`Renderer::update_heightfield`).
    heightfield: Option<Heightfield>,
    seen: Option<HeightsSeen>,
    /// The heights' copy on its way to the CPU (made at the last sync step).
    readback: Option<crate::gpu_util::AsyncReadback>,
    /// Where the water's window was when that copy was made.
    readback_origin: [f64; 2],
    /// Each body's smoothed water level from the interactive water (m).
    levels: Vec<f64>,
    /// Clock steps followed since the initial state, and per step of ours.
    clock_steps: u64,
    stride: u64,
    dt: f64,
    /// The bodies' initial world, for resets.
    scene: Scene,
    /// The water was set (at rest around the bodies) but not yet written to
    /// the surface's texture: a frame at t = 0 takes no step, and showed
    /// flat water the next frame's hollow then popped into.
    unpublished: bool,
}

impl Dynamics {
    /// The scene's stateful water and bodies (`None` if nothing moves).
    pub fn new(queue: &wgpu::Queue, scene: &Scene, ripples: Option<RipplePass>) -> Option<Self> {
        let dt = 1.0 / scene.ripples.rate.max(1) as f64;
        let bodies = BodyWorld::new(&scene.surface_bodies(), dt);
        if ripples.is_none() && bodies.is_none() {
            return None;
        }
        let scales = bodies.as_ref().map_or(Vec::new(), |w| {
            w.bodies.iter().map(|b| scene.objects[b.object].scale).collect()
        });
        let waves = if bodies.is_some() { scene.floating_waves() } else { None };
        // The surface failed to load it already if it cannot be loaded.
        let heightfield = (bodies.is_some()
            && scene.water.model == hydrolux_core::scene::WaterModel::Heightfield)
            .then(|| scene.load_heightfield().ok())
            .flatten();
        let mut d = Dynamics {
            ripples,
            bodies,
            scales,
            waves,
            heightfield,
            seen: None,
            readback: None,
            readback_origin: [0.0; 2],
            levels: Vec::new(),
            clock_steps: 0,
            stride: scene.ripples.clock_stride() as u64,
            dt,
            scene: scene.clone(),
            unpublished: false,
        };
        d.settle_water(queue);
        Some(d)
    }

    /// The water at rest around the bodies where they start (no rings from
    /// bodies appearing at t = 0).
    fn settle_water(&mut self, queue: &wgpu::Queue) {
        let (Some(r), Some(world)) = (&mut self.ripples, &self.bodies) else { return };
        let moves = world.moves_since(&world.poses());
        let g = r.settings.grid;
        let heights = resting_heights(&g, &r.window, &moves);
        r.set_heights(queue, &heights, &moves);
        self.unpublished = true;
    }

    /// Write the water as set to the surface's texture if no step has yet.
    pub fn publish_if_unpublished(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        if std::mem::take(&mut self.unpublished)
            && let Some(r) = &mut self.ripples
        {
            r.record(device, queue, encoder, &[], None);
        }
    }

    /// Whether `scene` keeps this state (same water simulation, same objects).
    pub fn fits(&self, scene: &Scene) -> bool {
        let water = match &self.ripples {
            Some(r) => r.fits(scene),
            None => !scene.has_interactive_water(),
        };
        water
            && scene.objects == self.scene.objects
            && scene.surface_bodies() == self.scene.surface_bodies()
            && scene.ripples.rate == self.scene.ripples.rate
            && self.floats_on_the_same_surface(scene)
    }

    /// Whether bodies in `scene` would float on the surface this state's
    /// bodies float on (its waves or heightfield).
    fn floats_on_the_same_surface(&self, scene: &Scene) -> bool {
        let (a, b) = (&scene.water, &self.scene.water);
        self.bodies.is_none()
            || (a.model == b.model
                && a.heightfield == b.heightfield
                && a.size == b.size
                && (self.waves.is_none()
                    || (scene.ocean == self.scene.ocean && scene.sines == self.scene.sines)))
    }

    /// Start again from the initial state at clock step `from` (an origin
    /// of the clock: a whole number of seconds, so of our steps and of
    /// [`SYNC_STEPS`]): still water, the bodies where the scene puts them,
    /// the kinematic ones moved on to that time.
    pub fn reset(&mut self, queue: &wgpu::Queue, from: u64) {
        if let Some(r) = &mut self.ripples {
            r.reset(queue);
        }
        if self.bodies.is_some() {
            self.bodies = BodyWorld::new(&self.scene.surface_bodies(), self.dt);
            if let Some(w) = &mut self.bodies {
                w.advance_kinematic(from as f64 / CLOCK_HZ as f64);
            }
            self.settle_water(queue);
        }
        self.seen = None;
        // A copy of the old water still on its way is dropped with its buffer.
        self.readback = None;
        self.levels.clear();
        self.clock_steps = from;
    }

    /// The interactive water's level each body floats on. Between walls
    /// (and in a periodic domain) the level of its free water, which the
    /// hulls' heads are measured from (`free_level` in ripples.wgsl): it
    /// rises as bodies displace water and falls as they are lifted out.
    /// It is found from the water's volume (the mean of all its heights,
    /// which no wave changes) and the hollows the hulls hold (the water
    /// under them stands at their bottoms), not from the waves about the
    /// body: those hold the water's reply to the body's own bobbing, which
    /// fed back on itself in a pool, and the ball and the water about it
    /// never forgot where they started (two starts 14 s apart differed by
    /// 4 cm about the ball, 2 cm on the mean height of the free cells, 3 mm
    /// on this). Open water (its level is the ocean's) uses the mean on a
    /// ring just outside each waterline.
    fn water_levels(&self, world: &BodyWorld) -> Vec<f64> {
        let poses = world.poses();
        let closed =
            self.ripples.as_ref().is_some_and(|r| r.settings.grid.boundary != RippleBoundary::Open);
        match &self.seen {
            Some(seen) if closed => {
                let n = seen.cells;
                let volume: f64 = seen.heights.iter().map(|&h| h as f64).sum();
                // The hollows: their depth summed over the cells they cover.
                let (mut hollows, mut covered) = (0.0, 0usize);
                for (b, p) in world.bodies.iter().zip(&poses) {
                    let hull = BodyMove { shape: b.shape, before: *p, after: *p, released: None };
                    let r = b.shape.bounding_radius();
                    let span = |c: f64, o: f64| {
                        let lo = ((c - r - o) / seen.cell).floor().clamp(0.0, n as f64) as usize;
                        let hi = ((c + r - o) / seen.cell).ceil().clamp(0.0, n as f64) as usize;
                        lo..hi
                    };
                    for j in span(p.position.z, seen.origin[1]) {
                        for i in span(p.position.x, seen.origin[0]) {
                            let x = seen.origin[0] + (i as f64 + 0.5) * seen.cell;
                            let z = seen.origin[1] + (j as f64 + 0.5) * seen.cell;
                            let d = hull.depth(x, z);
                            if d > 0.0 {
                                hollows += d;
                                covered += 1;
                            }
                        }
                    }
                }
                let free = (n * n).saturating_sub(covered);
                let level = if free > 0 { (volume + hollows) / free as f64 } else { 0.0 };
                vec![level; poses.len()]
            }
            Some(seen) => world
                .bodies
                .iter()
                .zip(&poses)
                .map(|(b, p)| {
                    let r = 1.25 * b.shape.bounding_radius();
                    let n = 16;
                    (0..n)
                        .map(|k| {
                            let a = k as f64 / n as f64 * std::f64::consts::TAU;
                            seen.at(p.position.x + r * a.cos(), p.position.z + r * a.sin())
                        })
                        .sum::<f64>()
                        / n as f64
                })
                .collect(),
            _ => vec![0.0; poses.len()],
        }
    }

    /// The water height body `i` floats on at world (x, z) and time t: the
    /// surface model's waves (read from a patch about each body where it is
    /// now, `poses`), raised by the interactive water's level
    /// (`water_levels`) averaged over [`LEVEL_SMOOTHING_S`]. The body rides
    /// the slow swell of the water it is in; the quick reply of the water
    /// to the body's own bobbing is left out (read back 0.1 s late, it would
    /// pump the bobbing instead of damping it).
    /// Kinematic bodies, which the water does not move, get no patch
    /// unless `all` (their states, for dumps and the viewer).
    fn water(&self, t: f64, world: &BodyWorld, all: bool) -> impl Fn(usize, f64, f64) -> f64 + '_ {
        let has_water = self.scene.has_water();
        let levels = &self.levels;
        let patches: Vec<_> = match &self.waves {
            Some(w) if has_water => world
                .bodies
                .iter()
                .zip(world.poses())
                .map(|(b, p)| {
                    let half = b.shape.horizontal_half_extent(&p);
                    let centre = [p.position.x, p.position.z];
                    (all || b.dynamic).then(|| w.patch_around(t, centre, half[0].max(half[1])))
                })
                .collect(),
            _ => Vec::new(),
        };
        move |i, x, z| {
            if !has_water {
                return f64::NEG_INFINITY;
            }
            let base = match (&self.heightfield, patches.get(i).and_then(Option::as_ref)) {
                (Some(h), _) => h.height(x as f32, z as f32) as f64,
                (None, Some(p)) => p.height_at(x, z),
                _ => 0.0,
            };
            base + levels.get(i).copied().unwrap_or(0.0)
        }
    }

    /// A sync step: take the heights copied at the last one (bodies float
    /// on them from now), then copy the heights now for the next. In a
    /// browser a copy that has not arrived yet is waited for at the next
    /// frame's sync step instead.
    fn sync(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        let (Some(r), Some(_)) = (&self.ripples, &self.bodies) else { return };
        let readback = self.readback.take().unwrap_or_else(|| r.heights_readback(device));
        if let Some(bytes) = readback.take(device, true) {
            self.take_heights(bytemuck::cast_slice(&bytes).to_vec());
        }
        if let Some(r) = &self.ripples
            && r.request_heights(device, queue, &readback)
        {
            let g = r.settings.grid;
            self.readback_origin = [0, 1].map(|a| r.window.low_edge(&g, a));
        }
        self.readback = Some(readback);
    }

    fn take_heights(&mut self, heights: Vec<f32>) {
        let Some(r) = &self.ripples else { return };
        let g = r.settings.grid;
        self.seen = Some(HeightsSeen {
            heights,
            cells: g.cells,
            cell: g.cell_size,
            origin: self.readback_origin,
            walls: g.boundary == RippleBoundary::Walls,
        });
        let raw = self.water_levels(self.bodies.as_ref().expect("bodies"));
        let keep = (-(SYNC_STEPS as f64 * self.dt) / LEVEL_SMOOTHING_S).exp();
        self.levels.resize(raw.len(), 0.0);
        for (l, r) in self.levels.iter_mut().zip(raw) {
            *l = keep * *l + (1.0 - keep) * r;
        }
    }

    /// One step of the water and the bodies (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Follow `clock_steps` more steps of the clock: the bodies step on the
    /// CPU, the water records its steps (earlier batches are submitted at
    /// once; the last goes into `encoder`). Returns what disturbed the
    /// water in each step (white water splashes from it).
    pub fn step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &hydrolux_core::camera::Camera,
        clock_steps: u32,
    ) -> Vec<StepInput> {
        let mut taken = Vec::new();
        let first = self.clock_steps / self.stride;
        self.clock_steps += clock_steps as u64;
        let count = self.clock_steps / self.stride - first;
        if count > 0 {
            self.unpublished = false;
        }
        if let Some(r) = &mut self.ripples {
            r.follow(camera);
        }
        let syncing = self.ripples.is_some()
            && self.bodies.as_ref().is_some_and(|b| b.bodies.iter().any(|b| b.dynamic));
        let mut k = 0;
        while k < count {
            let step = first + k;
            if syncing && step.is_multiple_of(SYNC_STEPS) {
                self.sync(device, queue);
            }
            let mut end = (k + MAX_STEPS as u64).min(count);
            if syncing {
                end = end.min((step / SYNC_STEPS + 1) * SYNC_STEPS - first);
            }
            let mut inputs = Vec::with_capacity((end - k) as usize);
            for s in first + k..first + end {
                let moves = self.step_bodies(s);
                let drops = self.ripples.as_mut().map_or(Vec::new(), |r| r.drops_for(s));
                inputs.push(StepInput { drops, moves, step: s });
            }
            if let Some(r) = &mut self.ripples {
                if end < count {
                    let mut early = device.create_command_encoder(&Default::default());
                    r.record(device, queue, &mut early, &inputs, None);
                    queue.submit([early.finish()]);
                } else {
                    r.record(device, queue, encoder, &inputs, None);
                }
            }
            taken.extend(inputs);
            k = end;
        }
        taken
    }

    /// Step the bodies once (simulation step `s`); their moves for the water.
    fn step_bodies(&mut self, s: u64) -> Vec<BodyMove> {
        let Some(mut world) = self.bodies.take() else { return Vec::new() };
        let before = world.poses();
        world.step(&self.water(s as f64 * self.dt, &world, false));
        let mut moves = world.moves_since(&before);
        world.release_hollows(&mut moves);
        self.bodies = Some(world);
        moves
    }

    /// Each moving object's index and world transform now.
    pub fn transforms(&self) -> Vec<(usize, glam::Mat4)> {
        let Some(w) = &self.bodies else { return Vec::new() };
        w.bodies
            .iter()
            .zip(w.poses())
            .zip(&self.scales)
            .map(|((b, p), s): ((_, Pose), _)| (b.object, p.matrix(*s)))
            .collect()
    }

    /// Each moving body's state (for dumps and the viewer).
    pub fn states(&self) -> Vec<BodyState> {
        let t = self.clock_steps as f64 / CLOCK_HZ as f64;
        let Some(w) = &self.bodies else { return Vec::new() };
        let water = self.water(t, w, true);
        // Each body's state against its own water.
        (0..w.bodies.len()).map(|i| w.states(&|x, z| water(i, x, z))[i]).collect()
    }

    /// The caller's heightfield changed (its size already checked): bodies
    /// float on the new heights from the next step.
    pub fn heightfield_updated(&mut self, heights: &[f32]) {
        if let Some(h) = &mut self.heightfield
            && h.heights.len() == heights.len()
        {
            h.heights.copy_from_slice(heights);
        }
    }

    /// Pull moving body `i` towards `target` (the viewer's drag).
    pub fn pull(&mut self, i: usize, target: glam::DVec3) {
        if let Some(w) = &mut self.bodies {
            w.pull(i, target, 0.1);
        }
    }

    /// Put moving body `i` at `position`, at rest (the viewer drops it).
    pub fn place(&mut self, i: usize, position: glam::DVec3) {
        if let Some(w) = &mut self.bodies {
            w.place(i, position);
        }
    }
}

impl crate::simulation::Simulation for Dynamics {
    fn create(
        shared: &crate::technique::Shared,
        scene: &Scene,
        published: &crate::simulation::Published,
    ) -> Result<Option<Self>, crate::error::RenderError> {
        let (device, queue) = (&shared.device, &shared.queue);
        let ripples = match scene.ripple_settings() {
            Some(settings) => {
                let bed = scene.ripple_bed()?;
                let mut pass = RipplePass::new(device, queue, &shared.caps, scene, settings, bed);
                pass.bind_landings(device, landings(published));
                Some(pass)
            }
            None => None,
        };
        Ok(Dynamics::new(queue, scene, ripples))
    }

    /// The liquid (before it in the registry) was made anew: take its log.
    fn connect(
        &mut self,
        shared: &crate::technique::Shared,
        published: &crate::simulation::Published,
    ) {
        if let Some(r) = &mut self.ripples {
            r.bind_landings(&shared.device, landings(published));
        }
    }

    fn fits(&self, scene: &Scene) -> bool {
        Dynamics::fits(self, scene)
    }

    /// The water and the bodies start from rest at a clock origin.
    fn restarts_clock(&self) -> bool {
        true
    }

    fn publish(&self, published: &mut crate::simulation::Published) {
        if let Some(r) = &self.ripples {
            let g = r.settings.grid;
            let lo = [0, 1].map(|a| r.window.low_edge(&g, a) as f32);
            let side = g.extent() as f32;
            published.ripples = Some(crate::simulation::published::RippleState {
                heights: r.view.clone(),
                kicks: r.kicks.clone(),
                // Walls: the texture is the domain; open: it tiles from the origin.
                origin: match g.boundary {
                    RippleBoundary::Walls => lo,
                    _ => [0.0, 0.0],
                },
                side,
                cell: g.cell_size as f32,
                window: [lo[0], lo[1], lo[0] + side, lo[1] + side],
            });
        }
        published.bodies.extend(self.transforms());
    }

    fn pace(&self) -> crate::simulation::Pace {
        crate::simulation::Pace::Follows
    }

    fn reset(&mut self, queue: &wgpu::Queue, from: u64) {
        Dynamics::reset(self, queue, from);
    }

    fn follow(
        &mut self,
        ctx: &mut crate::simulation::StepContext,
        encoder: &mut wgpu::CommandEncoder,
        clock_steps: u32,
    ) {
        let (device, queue) = (&ctx.shared.device, &ctx.shared.queue);
        let dt = self.dt();
        for input in self.step(device, queue, encoder, ctx.camera, clock_steps) {
            ctx.couplings.add_step(&input.drops, &input.moves, dt);
        }
        ctx.couplings.water_centre = self.ripples.as_ref().map(|r| {
            let g = r.settings.grid;
            let half = 0.5 * g.extent();
            [0, 1].map(|a| (r.window.low_edge(&g, a) + half) as f32)
        });
    }

    fn record_frame(
        &mut self,
        shared: &crate::technique::Shared,
        encoder: &mut wgpu::CommandEncoder,
        _plan: &crate::plan::FramePlan,
        _timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        // A frame before the first step draws the water at rest as set.
        self.publish_if_unpublished(&shared.device, &shared.queue, encoder);
    }

    fn input(&mut self, input: &crate::simulation::Input) -> bool {
        use crate::simulation::Input;
        match *input {
            Input::Disturb(drop) => match &mut self.ripples {
                Some(r) => {
                    r.disturb(drop);
                    true
                }
                None => false,
            },
            Input::Pull(i, target) => {
                self.pull(i, target);
                self.bodies.is_some()
            }
            Input::Place(i, position) => {
                self.place(i, position);
                self.bodies.is_some()
            }
            Input::Splash(_) => false,
        }
    }

    fn bodies(&self) -> Vec<BodyState> {
        self.states()
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        Dynamics::dump(self, name, ctx)
    }
}

/// The log of the liquid that lands in this water, if one does.
fn landings(published: &crate::simulation::Published) -> Option<&wgpu::Buffer> {
    published.liquid.as_ref().and_then(|l| l.landings.as_ref())
}
