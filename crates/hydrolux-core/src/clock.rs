//! The simulation clock: simulations that keep state (interactive
//! heightfields, foam, particles; seed 003 §2.3–2.4) advance in fixed steps
//! of `dt`, decoupled from the frame rate. The state at time t is the state
//! after ⌊t/dt⌋ steps from the start, whatever frames led there, so
//! `render --time T`, `render --frames`, `bench` and the viewer agree.
//!
//! Reaching a late time (a still at t = 600 s) does not need one frame per
//! step: [`SimulationClock::advance_to`] returns every step still due, and
//! the renderer records them in batches of [`SimulationClock::batch`] steps
//! per GPU submission. Going back in time resets to the start and steps
//! forward again (simulations cannot run backwards).
//!
//! **Memory.** Every simulation here forgets where it started: waves decay
//! (viscosity, damping) or leave an open domain, foam and particles die,
//! bodies settle. A scene's *memory* M (`Scene::simulation_memory`) is the
//! time after which its state no longer depends on its start (to 1e-3).
//! So the state at time t is simulated from the *origin*
//! (⌊t/M⌋ − 1)·M (0 for t < 2M), at most 2M before t: any time, however
//! late, costs under 2M of steps. In *exact* mode (offline renders) every
//! time uses its own origin, so a whole sequence and any slice of it give
//! identical frames; otherwise (the viewer, `bench`) playing on continues
//! from the state it has and only a jump of more than 2M starts again from
//! the new time's origin, so playback never stalls to re-simulate.

/// The latest simulation time (s) any command accepts, either side of 0
/// (about 31.7 years): step numbers stay exact and a time keeps a
/// precision far finer than a step (1.2e-7 s at 1e9 s in f64).
pub const MAX_TIME_S: f64 = 1e9;

/// What a simulation must do to reach a requested time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Advance {
    /// Start again from the initial state first, set at step `from` (time
    /// went backwards, the clock was reset, or the time has a new origin).
    pub reset: bool,
    /// The step the state starts from: after a reset the origin, else the
    /// step it is at.
    pub from: u64,
    /// Fixed steps to take (after the reset, if any).
    pub steps: u64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SimulationClock {
    dt: f64,
    batch: u32,
    /// Steps taken since the initial state.
    step: u64,
    /// [`SimulationClock::reset`] was called: the next advance starts over.
    pending_reset: bool,
    /// The memory M in steps (`None`: unbounded, every time starts from
    /// step 0; `Some(0)`: nothing remembers, no steps are due).
    memory: Option<u64>,
    /// Every time from its own origin (offline renders), not only jumps.
    exact: bool,
    /// The step the current state was started from.
    origin: u64,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ClockError {
    #[error("simulation time step {0} s is out of range: must be finite and between 1e-5 and 1 s")]
    Step(f64),
    #[error("simulation batch {0} is out of range: must be 1 to 65536 steps")]
    Batch(u32),
    #[error("simulation time {0} s is out of range: must be 0 to 1e9 s")]
    Time(f64),
    #[error("simulation memory {0} s is out of range: must be 0 to 3600 s")]
    Memory(f64),
}

impl SimulationClock {
    /// A clock of fixed step `dt` (s), recording at most `batch` steps per
    /// GPU submission.
    pub fn new(dt: f64, batch: u32) -> Result<Self, ClockError> {
        if !(dt.is_finite() && (1e-5..=1.0).contains(&dt)) {
            return Err(ClockError::Step(dt));
        }
        if !(1..=65536).contains(&batch) {
            return Err(ClockError::Batch(batch));
        }
        Ok(SimulationClock {
            dt,
            batch,
            step: 0,
            pending_reset: false,
            memory: None,
            exact: false,
            origin: 0,
        })
    }

    /// Set the memory M (s; 0 = nothing keeps state), rounded up to whole
    /// steps. (In exact mode the next advance starts again if its origin
    /// moved.)
    pub fn set_memory(&mut self, memory_s: f64) -> Result<(), ClockError> {
        if !(memory_s.is_finite() && (0.0..=3600.0).contains(&memory_s)) {
            return Err(ClockError::Memory(memory_s));
        }
        self.memory = Some((memory_s / self.dt - 1e-9).ceil().max(0.0) as u64);
        Ok(())
    }

    /// The memory M in steps (`None`: unbounded).
    pub fn memory_steps(&self) -> Option<u64> {
        self.memory
    }

    /// Exact mode: every time is simulated from its own origin, so any
    /// slice of a sequence gives the frames of the whole (offline renders).
    pub fn set_exact(&mut self, exact: bool) {
        self.exact = exact;
    }

    /// The origin of step `target`: (⌊target/M⌋ − 1)·M, 0 before 2M (and
    /// without a memory); `target` itself when nothing remembers (M = 0).
    pub fn origin_of(&self, target: u64) -> u64 {
        match self.memory {
            None => 0,
            Some(0) => target,
            Some(m) => (target / m).saturating_sub(1) * m,
        }
    }

    /// Steps the next advance to `time` would take (what a caller shows
    /// progress for); 0 for a time out of range.
    pub fn steps_to(&self, time: f64) -> u64 {
        let mut probe = self.clone();
        probe.advance_to(time).map_or(0, |a| a.steps)
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn batch(&self) -> u32 {
        self.batch
    }

    /// Steps taken since the initial state.
    pub fn step(&self) -> u64 {
        self.step
    }

    /// Simulated time of the current state (s).
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// The step whose state shows at `time`: ⌊time/dt⌋, with a tolerance
    /// of 1e-9 steps so that times given as k·dt in decimal land on step k.
    pub fn step_at(&self, time: f64) -> u64 {
        (time / self.dt + 1e-9).floor().max(0.0) as u64
    }

    /// Move the clock to `time` and say what the simulation must do to follow.
    pub fn advance_to(&mut self, time: f64) -> Result<Advance, ClockError> {
        if !(time.is_finite() && (0.0..=MAX_TIME_S).contains(&time)) {
            return Err(ClockError::Time(time));
        }
        let target = self.step_at(time);
        let origin = self.origin_of(target);
        let far = self.memory.is_some_and(|m| target - self.step.min(target) > 2 * m);
        let reset = self.pending_reset
            || target < self.step
            || (self.exact && origin != self.origin)
            || (!self.exact && far);
        let from = if reset { origin } else { self.step };
        if reset {
            self.origin = origin;
        }
        self.step = target;
        self.pending_reset = false;
        Ok(Advance { reset, from, steps: target - from })
    }

    /// Back to the initial state; the next advance steps from t = 0.
    pub fn reset(&mut self) {
        self.step = 0;
        self.origin = 0;
        self.pending_reset = true;
    }

    /// `steps` split into GPU submissions of at most [`Self::batch`] steps.
    pub fn batches(&self, steps: u64) -> impl Iterator<Item = u32> + use<> {
        let batch = self.batch as u64;
        let full = steps / batch;
        let rest = (steps % batch) as u32;
        std::iter::repeat_n(batch as u32, full as usize).chain((rest > 0).then_some(rest))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in for a simulation's state: a deterministic function of the
    /// steps taken since its initial state.
    #[derive(Default)]
    struct Counter {
        state: u64,
    }

    impl Counter {
        fn follow(&mut self, a: Advance) {
            if a.reset {
                self.state = a.from;
            }
            for _ in 0..a.steps {
                self.state = self.state.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
        }
    }

    #[test]
    fn the_state_at_a_time_does_not_depend_on_the_frame_rate() {
        let dt = 1.0 / 120.0;
        let end = 10.0;
        let mut states = Vec::new();
        for fps in [24.0f64, 30.0, 60.0, 144.0, 1000.0] {
            let mut clock = SimulationClock::new(dt, 256).unwrap();
            let mut sim = Counter::default();
            let mut t = 0.0f64;
            while t < end {
                t = (t + 1.0 / fps).min(end);
                sim.follow(clock.advance_to(t).unwrap());
            }
            assert_eq!(clock.step(), 1200);
            states.push(sim.state);
        }
        // One jump straight to the end (`render --time 10`).
        let mut clock = SimulationClock::new(dt, 256).unwrap();
        let mut sim = Counter::default();
        sim.follow(clock.advance_to(end).unwrap());
        states.push(sim.state);
        assert!(states.windows(2).all(|w| w[0] == w[1]), "{states:?}");
    }

    #[test]
    fn going_back_resets_and_replays() {
        let mut clock = SimulationClock::new(0.01, 64).unwrap();
        let mut sim = Counter::default();
        sim.follow(clock.advance_to(5.0).unwrap());
        let at_5 = sim.state;
        sim.follow(clock.advance_to(7.0).unwrap());
        let a = clock.advance_to(5.0).unwrap();
        assert_eq!(a, Advance { reset: true, from: 0, steps: 500 });
        sim.follow(a);
        assert_eq!(sim.state, at_5);
        // Same time again: nothing to do.
        assert_eq!(clock.advance_to(5.0).unwrap(), Advance { reset: false, from: 500, steps: 0 });
        clock.reset();
        assert_eq!(clock.advance_to(0.5).unwrap(), Advance { reset: true, from: 0, steps: 50 });
        assert_eq!(clock.advance_to(0.6).unwrap(), Advance { reset: false, from: 50, steps: 10 });
    }

    #[test]
    fn a_late_still_is_a_few_large_batches() {
        // t = 600 s at 120 Hz: 72,000 steps, recorded 1024 per submission.
        let mut clock = SimulationClock::new(1.0 / 120.0, 1024).unwrap();
        let a = clock.advance_to(600.0).unwrap();
        assert_eq!(a.steps, 72_000);
        let batches: Vec<u32> = clock.batches(a.steps).collect();
        assert_eq!(batches.len(), 71);
        assert_eq!(batches.iter().map(|&b| b as u64).sum::<u64>(), 72_000);
        assert!(batches.iter().all(|&b| b <= 1024));
        assert_eq!(clock.time(), 600.0);
    }

    #[test]
    fn decimal_multiples_of_the_step_land_on_their_step() {
        let clock = SimulationClock::new(0.1, 1).unwrap();
        assert_eq!(clock.step_at(0.3), 3); // 0.3 / 0.1 = 2.9999999999999996
        assert_eq!(clock.step_at(0.29), 2);
        assert_eq!(clock.step_at(0.0), 0);
    }

    #[test]
    fn bad_settings_and_times_are_refused() {
        assert_eq!(SimulationClock::new(0.0, 1), Err(ClockError::Step(0.0)));
        assert!(SimulationClock::new(f64::NAN, 1).is_err());
        assert_eq!(SimulationClock::new(0.01, 0), Err(ClockError::Batch(0)));
        let mut c = SimulationClock::new(0.01, 1).unwrap();
        assert_eq!(c.advance_to(-1.0), Err(ClockError::Time(-1.0)));
        assert!(c.advance_to(f64::INFINITY).is_err());
        assert!(ClockError::Step(0.0).to_string().contains("between 1e-5 and 1 s"));
        assert_eq!(c.advance_to(1e30), Err(ClockError::Time(1e30)));
        assert!(c.advance_to(MAX_TIME_S).is_ok());
        assert_eq!(c.set_memory(-1.0), Err(ClockError::Memory(-1.0)));
        assert!(c.set_memory(f64::NAN).is_err());
    }

    #[test]
    fn any_time_costs_under_twice_the_memory() {
        let mut clock = SimulationClock::new(1.0 / 120.0, 1024).unwrap();
        clock.set_memory(10.0).unwrap();
        assert_eq!(clock.memory_steps(), Some(1200));
        for exact in [false, true] {
            clock.set_exact(exact);
            for t in [0.0, 5.0, 19.99, 20.0, 1e3, 123_456.789, MAX_TIME_S, 3.0] {
                let a = clock.advance_to(t).unwrap();
                assert!(a.steps < 2400, "t = {t}: {a:?}");
                assert_eq!(a.from + a.steps, clock.step_at(t), "t = {t}");
            }
        }
        // Before 2M everything starts from t = 0, as without a memory.
        let mut c = SimulationClock::new(1.0 / 120.0, 1024).unwrap();
        c.set_memory(10.0).unwrap();
        assert_eq!(c.advance_to(19.5).unwrap(), Advance { reset: false, from: 0, steps: 2340 });
    }

    #[test]
    fn without_state_no_steps_are_due() {
        let mut clock = SimulationClock::new(1.0 / 120.0, 1024).unwrap();
        clock.set_memory(0.0).unwrap();
        for exact in [false, true] {
            clock.set_exact(exact);
            assert_eq!(clock.steps_to(MAX_TIME_S), 0);
            assert_eq!(clock.advance_to(50.0).unwrap().steps, 0);
        }
    }

    #[test]
    fn in_exact_mode_a_slice_gives_the_frames_of_the_whole_sequence() {
        let dt = 1.0 / 120.0;
        let frame_states = |first: u32, fps: f64| {
            let mut clock = SimulationClock::new(dt, 256).unwrap();
            clock.set_memory(2.0).unwrap();
            clock.set_exact(true);
            let mut sim = Counter::default();
            (first..200)
                .map(|i| {
                    sim.follow(clock.advance_to(100.0 + i as f64 / fps).unwrap());
                    sim.state
                })
                .collect::<Vec<_>>()
        };
        for fps in [24.0, 60.0, 7.0] {
            let whole = frame_states(0, fps);
            for first in [1, 37, 150] {
                assert_eq!(
                    frame_states(first, fps),
                    whole[first as usize..],
                    "{fps} fps from {first}"
                );
            }
        }
    }

    #[test]
    fn playing_on_continues_and_only_a_long_jump_starts_again() {
        let dt = 1.0 / 120.0;
        let mut clock = SimulationClock::new(dt, 256).unwrap();
        clock.set_memory(2.0).unwrap();
        let first = clock.advance_to(100.0).unwrap();
        assert!(first.reset && first.from == clock.origin_of(12_000));
        // 60 fps for 10 s crosses several origins without starting again.
        for i in 1..=600 {
            let a = clock.advance_to(100.0 + i as f64 / 60.0).unwrap();
            assert!(!a.reset && a.steps <= 2, "frame {i}: {a:?}");
        }
        // A jump of 4.1 s (over 2M) starts from the new time's origin.
        let a = clock.advance_to(114.1).unwrap();
        assert!(a.reset && a.from == clock.origin_of(clock.step_at(114.1)), "{a:?}");
    }
}
