//! The configuration of the fuzz targets (`tests/fuzz.rs`, `tests/nc_fuzz.rs`) and of the
//! property tests (`tests/proptest_*.rs`, `nc_roundtrip`, `nc_dialects`,
//! `geometry_chamfer_head`): a fixed seed, so that CI runs the same cases every time and a
//! failure found there is found again here.
//!
//! Locally, more or other cases come from proptest's own variables, which override what this
//! file sets: `PROPTEST_CASES=20000` runs that many cases of every target, and
//! `PROPTEST_RNG_SEED=N` another seed (or the one a failure printed, to replay it).

use proptest::test_runner::{Config, RngSeed};

/// The seed CI runs with.
pub const SEED: u64 = 0x6e63_7368_6565_7430;

/// `cases` cases from the fixed seed, no failure files written. The seed in use is written
/// to stderr, which `cargo test` shows only for a test that failed.
pub fn config(cases: u32) -> Config {
    Config { failure_persistence: None, ..with_regressions(cases) }
}

/// `cases` cases from the fixed seed, after the failures proptest saved in the test's
/// `.proptest-regressions` file (replayed first, as before the seed was fixed; a new failure
/// is added there).
pub fn with_regressions(cases: u32) -> Config {
    let given = std::env::var("PROPTEST_RNG_SEED").ok().and_then(|s| s.parse::<u64>().ok());
    let seed = given.unwrap_or(SEED);
    eprintln!("proptest seed {seed}: rerun with PROPTEST_RNG_SEED={seed}; PROPTEST_CASES=N runs N cases");
    Config { cases, rng_seed: RngSeed::Fixed(seed), ..Config::default() }
}

/// `data` with bytes replaced at the edits' places, then perhaps cut short.
pub fn mutated(
    mut data: Vec<u8>,
    edits: &[(proptest::sample::Index, u8)],
    cut: Option<proptest::sample::Index>,
) -> Vec<u8> {
    if !data.is_empty() {
        for (at, byte) in edits {
            let i = at.index(data.len());
            data[i] = *byte;
        }
    }
    if let Some(cut) = cut {
        data.truncate(cut.index(data.len() + 1));
    }
    data
}
