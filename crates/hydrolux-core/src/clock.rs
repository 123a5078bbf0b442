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

/// What a simulation must do to reach a requested time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Advance {
    /// Start again from the initial state first (time went backwards, or
    /// the clock was reset).
    pub reset: bool,
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
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ClockError {
    #[error("simulation time step {0} s is out of range: must be finite and between 1e-5 and 1 s")]
    Step(f64),
    #[error("simulation batch {0} is out of range: must be 1 to 65536 steps")]
    Batch(u32),
    #[error("simulation time {0} s is out of range: must be finite, 0 or later")]
    Time(f64),
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
        Ok(SimulationClock { dt, batch, step: 0, pending_reset: false })
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
        if !(time.is_finite() && time >= 0.0) {
            return Err(ClockError::Time(time));
        }
        let target = self.step_at(time);
        let reset = self.pending_reset || target < self.step;
        let from = if reset { 0 } else { self.step };
        self.step = target;
        self.pending_reset = false;
        Ok(Advance { reset, steps: target - from })
    }

    /// Back to the initial state; the next advance steps from t = 0.
    pub fn reset(&mut self) {
        self.step = 0;
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
                self.state = 0;
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
        assert_eq!(a, Advance { reset: true, steps: 500 });
        sim.follow(a);
        assert_eq!(sim.state, at_5);
        // Same time again: nothing to do.
        assert_eq!(clock.advance_to(5.0).unwrap(), Advance { reset: false, steps: 0 });
        clock.reset();
        assert_eq!(clock.advance_to(0.5).unwrap(), Advance { reset: true, steps: 50 });
        assert_eq!(clock.advance_to(0.6).unwrap(), Advance { reset: false, steps: 10 });
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
    }
}
