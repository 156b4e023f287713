//! What a workbook decides for its own evaluation besides its cells: the clock NOW and TODAY
//! read, the random sequence RAND, RANDBETWEEN and RANDARRAY draw from, and the locale. Each workbook
//! owns its settings (the evaluator asks for them through `Env`), so two workbooks evaluated
//! on one thread, or a server holding many, never see each other's clock or sequence.

use std::cell::Cell;

use super::dates;

#[derive(Clone, Debug, Default)]
pub struct Settings {
    /// The date and time NOW reads, as a serial; `None`: the system clock. Fixing it
    /// reproduces results saved at a known time.
    pub clock: Option<f64>,
    /// The user's locale: how typed numbers, dates and formulas are read, values shown, and
    /// text turned into numbers while formulas compute (see `locale.rs`).
    pub locale: super::Locale,
    /// The state of the random sequence: 0 seeds it from the system clock at the next draw.
    random: Cell<u64>,
    /// How much the workbook's own VBA Functions may run when its cells call them.
    pub functions: FunctionLimits,
    /// The work the LAMBDAs of MAP, REDUCE, SCAN, BYROW, BYCOL and MAKEARRAY may do in one
    /// formula; `None`: ncsheet's limit, `MAX_LAMBDA_WORK` (docs/limits.md). A smaller budget
    /// lets a test show what is charged without doing 2^28 items of work.
    pub lambda_work: Option<u64>,
}

/// The limits of the workbook's VBA Functions called from its cells: each call's, and all the
/// calls' of one recalculation together, so that a thousand cells calling a slow function
/// stop in seconds, explained, instead of running for half an hour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FunctionLimits {
    /// Statements and loop turns one call may run.
    pub statements_per_call: u64,
    /// Statements and loop turns all the calls of one recalculation may run together.
    pub statements_per_recalculation: u64,
    /// How deep one call may nest its own calls (it may run inside a macro already deep).
    pub max_depth: usize,
    /// The seconds of wall-clock time all the calls of one recalculation may take together
    /// (`None`: none but the command's own `--timeout`). A front end that stays open (the
    /// workbench) gives each edit's recalculation the time a command's `--timeout` gives it.
    pub seconds_per_recalculation: Option<f64>,
}

impl Default for FunctionLimits {
    fn default() -> FunctionLimits {
        FunctionLimits {
            statements_per_call: 10_000_000,
            statements_per_recalculation: 100_000_000,
            max_depth: 32,
            seconds_per_recalculation: None,
        }
    }
}

impl Settings {
    /// Settings whose random sequence starts from `seed` (0: from the clock), for
    /// reproducible runs and tests.
    pub fn seeded(seed: u64) -> Settings {
        Settings { random: Cell::new(seed), ..Settings::default() }
    }

    /// Restarts the random sequence from `seed` (0: from the clock at the next draw).
    pub fn seed_random(&self, seed: u64) {
        self.random.set(seed);
    }

    /// The serial NOW returns; the system clock is read as a serial of `system`, the
    /// workbook's date system.
    pub fn now(&self, system: dates::DateSystem) -> f64 {
        self.clock.unwrap_or_else(|| dates::system_now(system))
    }

    /// The locale with the year of the fixed clock (if any) as the year a day and month typed
    /// without a year fall in (de-DE `12.03.`), as NOW reads the clock; `system` is the
    /// workbook's date system, the clock's serial's.
    pub fn locale_in_force(&self, system: dates::DateSystem) -> super::Locale {
        let year = self.clock.filter(|c| c.is_finite()).map(|c| dates::ymd_from_serial(system, c.floor() as i64).0);
        self.locale.at_year(year.and_then(|y| i32::try_from(y).ok()))
    }

    /// The work the LAMBDAs of MAP, REDUCE, … may do in one formula (see [`Settings::lambda_work`]).
    pub fn lambda_work_limit(&self) -> u64 {
        self.lambda_work.unwrap_or(super::evaluator::MAX_LAMBDA_WORK)
    }

    /// The next number 0 ≤ x < 1 of the sequence, with 53 random bits (xorshift64*).
    pub fn next_random(&self) -> f64 {
        let mut x = self.random.get();
        if x == 0 {
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0x9E37_79B9_7F4A_7C15, |d| d.as_nanos() as u64);
            x = nanos | 1;
        }
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.random.set(x);
        (x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_seeded_sequence_repeats_and_stays_in_range() {
        let (a, b) = (Settings::seeded(7), Settings::seeded(7));
        for _ in 0..1000 {
            let x = a.next_random();
            assert!((0.0..1.0).contains(&x));
            assert_eq!(x, b.next_random());
        }
    }
}
