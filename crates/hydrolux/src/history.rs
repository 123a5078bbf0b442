//! Persistent state of a simulation that steps on the GPU (seed 003 §2.4:
//! a heightfield's previous and current heights; particles; foam): two
//! copies of each resource, one read as the last step's state while the
//! other is written; which is which follows from the step's number. A
//! simulation keeps its `PingPong` across frames, steps it on the
//! simulation clock (`hydrolux_core::clock`) and starts both copies again
//! on a reset (the white water's foam and its bind groups).

/// Two copies of a state, addressed by the step count: after `n` steps
/// slot `n % 2` holds the latest state, so the slot a step reads and writes
/// depends only on its number (a simulation resumed or restarted at any
/// step, or skipping steps it no longer needs, reads the right one).
#[derive(Debug)]
pub(crate) struct PingPong<T> {
    slots: [T; 2],
    steps: u64,
}

impl<T> PingPong<T> {
    /// `even` holds the state after an even number of steps (the initial
    /// state); `odd` is written by the first step.
    pub fn new(even: T, odd: T) -> Self {
        PingPong { slots: [even, odd], steps: 0 }
    }

    /// The latest state (what the frame draws, and what the next step reads).
    pub fn current(&self) -> &T {
        &self.slots[self.parity()]
    }

    /// Where the next step writes (the white water binds both slots in
    /// each step's bind group instead).
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn next(&self) -> &T {
        &self.slots[1 - self.parity()]
    }

    /// Which slot holds the latest state.
    pub fn parity(&self) -> usize {
        (self.steps % 2) as usize
    }

    /// Both slots, e.g. to clear them.
    pub fn both(&self) -> &[T; 2] {
        &self.slots
    }

    /// The step was recorded: what it wrote is now the latest state.
    pub fn swap(&mut self) {
        self.steps += 1;
    }

    /// Steps taken (counted from t = 0, whatever step the state started at).
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The state is now that of step `step`: its slots were rewritten (a
    /// reset, `step` the first of a new start) or the steps before `step`
    /// are skipped (nothing they would change is still seen).
    pub fn start_at(&mut self, step: u64) {
        self.steps = step;
    }
}

#[cfg(test)]
mod tests {
    use super::PingPong;

    #[test]
    fn each_step_reads_the_last_state_and_writes_the_other() {
        // A stand-in for a GPU step: the written slot gets read + 1.
        let mut p = PingPong::new(std::cell::Cell::new(0), std::cell::Cell::new(-1));
        for step in 1..=5 {
            let (read, write) = (p.current(), p.next());
            assert!(!std::ptr::eq(read, write));
            write.set(read.get() + 1);
            p.swap();
            assert_eq!(p.current().get(), step);
            assert_eq!(p.steps(), step as u64);
        }
        // Restarted at step 7 (odd): the odd slot holds the state, the
        // even one is written next.
        p.start_at(7);
        assert_eq!(p.parity(), 1);
        p.current().set(0);
        p.next().set(p.current().get() + 1);
        p.swap();
        assert_eq!((p.current().get(), p.steps(), p.parity()), (1, 8, 0));
        assert!(std::ptr::eq(p.current(), &p.both()[0]));
    }
}
