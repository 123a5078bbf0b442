//! Persistent state of a simulation that steps on the GPU (seed 003 §2.4:
//! a heightfield's previous and current heights; particles; foam): two
//! copies of each resource, one read as the last step's state while the
//! other is written, swapped after every step. A technique keeps its
//! `PingPong` across frames, steps it on the simulation clock
//! (`hydrolux_core::clock`) and starts both copies again on a reset.

/// Two copies of a state, with the one holding the latest step marked.
#[derive(Debug)]
pub(crate) struct PingPong<T> {
    slots: [T; 2],
    current: usize,
    steps: u64,
}

// The dynamic-water techniques (interactive heightfield, foam, particles)
// are its users; until the first one lands only the tests use it.
#[allow(dead_code)]
impl<T> PingPong<T> {
    /// `initial` holds the initial state; `other` is written by the first step.
    pub fn new(initial: T, other: T) -> Self {
        PingPong { slots: [initial, other], current: 0, steps: 0 }
    }

    /// The latest state (what the frame draws, and what the next step reads).
    pub fn current(&self) -> &T {
        &self.slots[self.current]
    }

    /// Where the next step writes.
    pub fn next(&self) -> &T {
        &self.slots[1 - self.current]
    }

    /// Both, as (read, write) for one step; call [`PingPong::swap`] after it.
    pub fn step_pair(&self) -> (&T, &T) {
        (self.current(), self.next())
    }

    /// The step was recorded: what it wrote is now the latest state.
    pub fn swap(&mut self) {
        self.current = 1 - self.current;
        self.steps += 1;
    }

    /// Steps taken since the initial state.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Back to the initial state's slot; the caller rewrites its contents
    /// (e.g. clears the heights) before the next step.
    pub fn reset(&mut self) -> &T {
        self.current = 0;
        self.steps = 0;
        &self.slots[0]
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
            let (read, write) = p.step_pair();
            assert!(!std::ptr::eq(read, write));
            write.set(read.get() + 1);
            p.swap();
            assert_eq!(p.current().get(), step);
            assert_eq!(p.steps(), step as u64);
        }
        p.reset().set(0);
        assert_eq!((p.current().get(), p.steps()), (0, 0));
        p.next().set(p.current().get() + 1);
        p.swap();
        assert_eq!(p.current().get(), 1);
    }
}
