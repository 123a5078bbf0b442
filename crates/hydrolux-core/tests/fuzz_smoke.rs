//! A short fuzz run of every input parser on stable (deterministic
//! mutations of valid seeds; see `hydrolux_core::fuzz`): no panic, no hang,
//! no unbounded allocation. HYDROLUX_FUZZ_RUNS sets the mutants per target
//! (default 20,000; the 1,000,000-run results are in BENCHMARKS.md), and
//! HYDROLUX_FUZZ_SEED the generator's seed. The coverage-guided runs use
//! cargo-fuzz on nightly (`fuzz/`).

use hydrolux_core::fuzz::{TARGETS, run_mutations};

fn runs() -> u64 {
    std::env::var("HYDROLUX_FUZZ_RUNS").ok().and_then(|v| v.parse().ok()).unwrap_or(20_000)
}

fn seed() -> u64 {
    std::env::var("HYDROLUX_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(0x5eed)
}

#[test]
fn every_parser_survives_mutated_input() {
    for (name, target) in TARGETS {
        let t0 = std::time::Instant::now();
        let n = run_mutations(name, *target, runs(), seed());
        let s = t0.elapsed().as_secs_f64();
        eprintln!("fuzz {name}: {n} executions in {s:.1} s ({:.0}/s)", n as f64 / s);
    }
}
