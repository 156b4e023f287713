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
    /// VBA's own generator, which the macros' `Rnd` and `Randomize` use (not RAND's).
    pub vba_rnd: VbaRnd,
    /// How much the workbook's own VBA Functions may run when its cells call them.
    pub functions: FunctionLimits,
    /// The work the LAMBDAs of MAP, REDUCE, SCAN, BYROW, BYCOL and MAKEARRAY may do in one
    /// formula; `None`: ncsheet's limit, `MAX_LAMBDA_WORK` (docs/limits.md). A smaller budget
    /// lets a test show what is charged without doing 2^28 items of work.
    pub lambda_work: Option<u64>,
    /// The array items one formula may hold at once; `None`: ncsheet's limit,
    /// `MAX_LIVE_ITEMS` (docs/limits.md). A smaller one lets a test show what is held
    /// without holding gigabytes.
    pub live_items: Option<usize>,
    /// The evaluations the iterating cycles of one recalculation may spend together, the work
    /// inside them counted; `None`: ncsheet's limit, the workbook's
    /// `MAX_ITERATION_EVALUATIONS` (docs/limits.md). A smaller one lets a test show what is charged in a moment.
    pub iteration_work: Option<u64>,
}

/// VBA's `Rnd` generator, as Microsoft's KB 231847 gives it: x1 = (x0 × 1140671485 +
/// 12820163) mod 2^24, Rnd = x1 / 2^24, from x0 = 327680 when the session starts; so a macro
/// that draws without `Randomize` gets the numbers Excel's VBA gives in a fresh session
/// (0.7055475, 0.533424, 0.5795186, …). The state is the workbook's, as Excel keeps one per
/// session: a second macro run on the same document goes on with the sequence.
#[derive(Clone, Debug)]
pub struct VbaRnd(Cell<u32>);

/// x0 of a new session (KB 231847).
const VBA_RND_START: u32 = 327_680;
const VBA_RND_MODULUS: u32 = 1 << 24;

impl Default for VbaRnd {
    fn default() -> VbaRnd {
        VbaRnd(Cell::new(VBA_RND_START))
    }
}

impl VbaRnd {
    /// `Rnd(n)` ("Rnd function"): the next number for n > 0 (or none given), the last one
    /// again for n = 0, and for n < 0 the same number every time for that n (its Single's bits
    /// become the state before the step).
    pub fn draw(&self, n: f64) -> f64 {
        let mut x = self.0.get();
        if n < 0.0 {
            let bits = (n as f32).to_bits();
            x = bits.wrapping_add(bits >> 24) % VBA_RND_MODULUS;
        }
        if n != 0.0 {
            x = ((u64::from(x) * 1_140_671_485 + 12_820_163) % u64::from(VBA_RND_MODULUS)) as u32;
        }
        self.0.set(x);
        f64::from(x) / f64::from(VBA_RND_MODULUS)
    }

    /// `Randomize n`: the Double's high bytes, folded, become the middle bytes of the state;
    /// its low byte stays ("Randomize statement": the same number does not repeat a sequence
    /// by itself; `Rnd(-1)` just before it does).
    pub fn randomize(&self, n: f64) {
        let b = n.to_le_bytes();
        self.mix(b[4] ^ b[6], b[5] ^ b[7]);
    }

    /// `Randomize` alone: the same from `Timer`'s seconds as a Single.
    pub fn randomize_from_timer(&self, seconds: f32) {
        let b = seconds.to_le_bytes();
        self.mix(b[0] ^ b[2], b[1] ^ b[3]);
    }

    fn mix(&self, middle: u8, high: u8) {
        let x = self.0.get();
        self.0.set((u32::from(high) << 16) | (u32::from(middle) << 8) | (x & 0xFF));
    }
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

    /// The array items one formula may hold at once (see [`Settings::live_items`]).
    pub fn live_items_limit(&self) -> usize {
        self.live_items.unwrap_or(super::value::MAX_LIVE_ITEMS)
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

#[cfg(test)]
mod vba_rnd_tests {
    use super::VbaRnd;

    /// KB 231847's generator worked in Python's integers from x0 = 327680:
    /// (x * 1140671485 + 12820163) % 2**24 / 2**24 gives 0.7055475115776062,
    /// 0.5334240198135376, 0.5795186161994934, the first three Rnd values the VBA of a fresh
    /// Excel session prints (microsoft.public.excel.worksheet.functions, "How to get repeatable
    /// Excel RAND sequence?", 2010: 0.705547511577606, 0.533424019813537, 0.579518616199493).
    /// Rnd(-1) is 0.2240070104598999 (the widely quoted 0.224007), every time, and Rnd(0)
    /// repeats the last number.
    #[test]
    fn rnd_follows_vbas_generator() {
        let rnd = VbaRnd::default();
        assert_eq!(rnd.draw(1.0), 0.7055475115776062);
        assert_eq!(rnd.draw(1.0), 0.5334240198135376);
        assert_eq!(rnd.draw(0.0), 0.5334240198135376);
        assert_eq!(rnd.draw(1.0), 0.5795186161994934);
        assert_eq!(rnd.draw(-1.0), 0.2240070104598999);
        assert_eq!(rnd.draw(-1.0), 0.2240070104598999);
    }

    /// "Randomize statement": "To repeat sequences of random numbers, call Rnd with a negative
    /// argument immediately before using Randomize with a numeric argument." After Rnd(-1),
    /// Randomize 42 makes the state ((b4^b6) << 8 | (b5^b7) << 16 | its low byte) of 42.0's
    /// bytes; Python gives the next Rnd as 0.907809317111969.
    #[test]
    fn rnd_minus_one_then_randomize_repeats_a_sequence() {
        let rnd = VbaRnd::default();
        let mut runs = Vec::new();
        for _ in 0..2 {
            rnd.draw(-1.0);
            rnd.randomize(42.0);
            runs.push((rnd.draw(1.0), rnd.draw(1.0)));
        }
        assert_eq!(runs[0], runs[1]);
        assert_eq!(runs[0].0, 0.907809317111969);
    }
}
