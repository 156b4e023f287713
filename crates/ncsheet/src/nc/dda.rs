//! The DDA linear interpolator of docs/domain.md §4 (Glavonjić, table T8.1.1), exactly as the
//! control runs it: integer registers, one n-bit adder per axis, a pulse of one machine
//! increment whenever the adder overflows. Every clock each axis adds its register p (the
//! move's length in increments) to its register q; when the sum reaches 2ⁿ, 2ⁿ is taken off
//! and one pulse goes to the axis. After 2ⁿ clocks every axis has had exactly |δ| pulses, so
//! all arrive together and each axis's pulse rate is proportional to its length.

use std::fmt;

use super::program::ArcDirection;

/// What the interpolator cannot run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DdaError(pub String);

impl fmt::Display for DdaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DdaError {}

/// The most adder bits we run: 2ⁿ clocks, each computed as it is read (a 24-bit adder's
/// 16,777,216 clocks are a table of about 1.2 GB, written row by row, never held).
pub const MAX_BITS: u32 = 24;

/// One axis in one clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AxisClock {
    /// Register p: the axis's length in increments (constant while the feed is).
    pub p: u64,
    /// q + p before the overflow test.
    pub sum: u64,
    /// Register q after the clock.
    pub q: u64,
    /// Whether a pulse (one increment) went to the axis this clock.
    pub pulse: bool,
}

/// One interpolation clock, numbered from 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Clock {
    pub number: u64,
    pub axes: Vec<AxisClock>,
}

/// A whole straight move through the interpolator. Its clocks are computed as they are
/// read ([`DdaRun::clocks`]), so a run of 2^24 clocks takes no more memory than one of 16.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DdaRun {
    pub bits: u32,
    /// The move per axis in increments, with its sign (the pulses' direction).
    pub deltas: Vec<i64>,
}

impl DdaRun {
    /// 2ⁿ, the adder's capacity.
    pub fn capacity(&self) -> u64 {
        1u64 << self.bits
    }

    /// The run's 2ⁿ clocks in order, each computed when it is asked for.
    pub fn clocks(&self) -> impl Iterator<Item = Clock> + '_ {
        let capacity = self.capacity();
        let mut q = vec![0u64; self.deltas.len()];
        (1..=capacity).map(move |number| {
            let axes = self.deltas.iter().zip(q.iter_mut()).map(|(d, q)| add(d.unsigned_abs(), q, capacity)).collect();
            Clock { number, axes }
        })
    }

    /// Pulses each axis received, signed by direction (counted by running the adders).
    pub fn pulses(&self) -> Vec<i64> {
        let mut counts = vec![0i64; self.deltas.len()];
        for clock in self.clocks() {
            for (n, a) in counts.iter_mut().zip(&clock.axes) {
                *n += i64::from(a.pulse);
            }
        }
        counts.iter().zip(&self.deltas).map(|(n, d)| n * d.signum()).collect()
    }
}

/// The smallest n with 2ⁿ ≥ the longest axis move (the paper's choice), at least 1.
pub fn bits_for(deltas: &[i64]) -> u32 {
    let longest = deltas.iter().map(|d| d.unsigned_abs()).max().unwrap_or(0).max(2);
    64 - (longest - 1).leading_zeros()
}

/// A straight move of `deltas` increments per axis through `bits`-bit adders: 2ⁿ clocks at
/// constant feed (Δp = 0). An axis longer than 2ⁿ would need two pulses in one clock, which
/// the adder cannot give.
pub fn linear(bits: u32, deltas: &[i64]) -> Result<DdaRun, DdaError> {
    check_bits(bits)?;
    let capacity = 1u64 << bits;
    if let Some(d) = deltas.iter().find(|d| d.unsigned_abs() > capacity) {
        return Err(DdaError(format!(
            "a move of {d} increments needs more than one pulse per clock from a {bits}-bit adder \
             (at most 2^{bits} = {capacity}); use at least {} bits",
            bits_for(deltas)
        )));
    }
    Ok(DdaRun { bits, deltas: deltas.to_vec() })
}

/// An adder of 1 to [`MAX_BITS`] bits.
fn check_bits(bits: u32) -> Result<(), DdaError> {
    if !(1..=MAX_BITS).contains(&bits) {
        return Err(DdaError(format!("the adder has 1 to {MAX_BITS} bits, not {bits}")));
    }
    Ok(())
}

/// One clock of one axis's adder.
fn add(p: u64, q: &mut u64, capacity: u64) -> AxisClock {
    let sum = *q + p;
    let pulse = sum >= capacity;
    *q = if pulse { sum - capacity } else { sum };
    AxisClock { p, sum, q: *q, pulse }
}

/// A length in mm as a whole number of machine increments, or why it is not one (a program
/// is written on the machine's grid: a length between grid points is a mistake upstream).
pub fn increments(length: f64, increment: f64) -> Result<i64, DdaError> {
    if !(increment.is_finite() && increment > 0.0) {
        return Err(DdaError(format!("the machine increment must be a length above 0 mm, not {increment}")));
    }
    let n = length / increment;
    if !n.is_finite() || n.abs() > (1u64 << MAX_BITS) as f64 {
        return Err(DdaError(format!(
            "{length} mm is not a move of at most 2^{MAX_BITS} increments of {increment} mm"
        )));
    }
    let whole = n.round();
    if (n - whole).abs() > 1e-6 {
        return Err(DdaError(format!("{length} mm is not a whole number of increments of {increment} mm")));
    }
    Ok(whole as i64)
}

/// One clock of the circular interpolator: both adders, the steps they gave (−1, 0, +1 per
/// axis, X then Y) and the position after them, relative to the centre.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CircleClock {
    pub number: u64,
    pub axes: [AxisClock; 2],
    pub steps: [i8; 2],
    pub position: (i64, i64),
}

/// An arc through the interpolator, positions in increments relative to its centre. Its
/// clocks are computed as they are read ([`CircularRun::clocks`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CircularRun {
    pub bits: u32,
    pub direction: ArcDirection,
    pub start: (i64, i64),
    pub end: (i64, i64),
}

impl CircularRun {
    pub fn capacity(&self) -> u64 {
        1u64 << self.bits
    }

    /// The arc's clocks in order, each computed when it is asked for; an error in place of a
    /// clock, and then no more, when the adders lose the circle.
    pub fn clocks(&self) -> ArcClocks {
        // A clockwise arc is a counter-clockwise one with X and Y exchanged (a mirror image):
        // the adders run in that order, so that both directions keep to the circle alike.
        let mirrored = self.direction == ArcDirection::Clockwise;
        let (start, end) = if mirrored { (swap(self.start), swap(self.end)) } else { (self.start, self.end) };
        ArcClocks::counter_clockwise(self.capacity(), start, end, mirrored)
    }

    /// Steps each axis took, X then Y (a full circle takes 4R on each), or why the arc did
    /// not reach its end, or that it takes more clocks than a table has rows
    /// ([`MAX_TABLE_CLOCKS`]).
    pub fn pulses(&self) -> Result<[u64; 2], DdaError> {
        let mut counts = [0u64; 2];
        for (n, clock) in self.clocks().enumerate() {
            if n as u64 >= MAX_TABLE_CLOCKS {
                return Err(self.too_many_clocks());
            }
            let clock = clock?;
            for (n, step) in counts.iter_mut().zip(clock.steps) {
                *n += u64::from(step != 0);
            }
        }
        Ok(counts)
    }
}

impl CircularRun {
    /// A full circle takes about 2π·2ⁿ clocks: with 24-bit adders, 105 million rows (6 GB of
    /// text, minutes to write), where a straight move's table ends at 2^24.
    fn too_many_clocks(&self) -> DdaError {
        let needed = bits_for_circle(self.start, self.end);
        let advice = if self.bits > needed {
            format!("give fewer bits (--bits {needed} is enough for this radius) or a coarser --increment")
        } else {
            "give a coarser --increment (the radius in fewer increments needs fewer bits and clocks)".to_string()
        };
        DdaError(format!(
            "the arc takes more than {MAX_TABLE_CLOCKS} clocks with {}-bit adders (2^{MAX_BITS}, the longest table \
             ncsheet writes, as a straight move's): {advice}",
            self.bits
        ))
    }
}

/// The most clocks a table shows: a straight move's 2^[`MAX_BITS`], and an arc's as many.
pub const MAX_TABLE_CLOCKS: u64 = 1 << MAX_BITS;

fn swap(p: (i64, i64)) -> (i64, i64) {
    (p.1, p.0)
}

/// The bits an arc of these end points needs: 2ⁿ at least four times the radius (no adder is
/// asked for two pulses in one clock, and the path stays within an increment of the circle).
pub fn bits_for_circle(start: (i64, i64), end: (i64, i64)) -> u32 {
    let r = radius(start).max(radius(end)).ceil() as i64;
    (bits_for(&[r.max(2)]) + EXTRA).min(MAX_BITS)
}

/// Bits beyond the radius's: with 2ⁿ ≥ 4R each clock turns the arc by at most a quarter
/// increment, and the path keeps within one increment on each axis of the circle
/// (tests/nc_readback.rs).
const EXTRA: u32 = 2;

fn radius(p: (i64, i64)) -> f64 {
    (p.0 as f64).hypot(p.1 as f64)
}

/// Circular interpolation by the same adders (docs/domain.md §4): the circle x = R·cos θ,
/// y = R·sin θ moves as dx = −y·dθ, dy = x·dθ (counter-clockwise), so the X adder's register
/// p holds |y| and the Y adder's |x|, each taken again from the position after every pulse:
/// two integrators feeding each other. The step's sign is the derivative's (−sign y and
/// sign x counter-clockwise; the opposite clockwise). Both q registers start half full, so
/// that a pulse comes when the sum rounds past a whole increment, not when it passes it
/// (the path is centred on the circle rather than lagging behind it). In the
/// arc's last quadrant, where both axes only approach their ends, an axis that is at its end
/// takes no more pulses: the end point is reached exactly.
pub fn circular(
    bits: u32,
    start: (i64, i64),
    end: (i64, i64),
    direction: ArcDirection,
) -> Result<CircularRun, DdaError> {
    check_bits(bits)?;
    let (rs, re) = (radius(start), radius(end));
    if rs == 0.0 {
        return Err(DdaError("an arc whose start is its centre".into()));
    }
    if (rs - re).abs() > 0.5 {
        return Err(DdaError(format!(
            "the end is {re:.3} increments from the centre but the start {rs:.3}: not on one circle \
             (within half an increment)"
        )));
    }
    let needed = bits_for_circle(start, end);
    if bits < needed {
        return Err(DdaError(format!(
            "a radius of {:.0} increments needs adders of at least {needed} bits (2^n at least 4 times the radius)",
            rs.max(re),
        )));
    }
    Ok(CircularRun { bits, direction, start, end })
}

/// The counter-clockwise arc's clocks, one at a time. The Y adder takes the X register as
/// this clock's X pulse left it (an integrator fed the newest value: the path closes on
/// itself rather than spiralling outwards, as two adders fed the same clock's old values do).
/// A mirrored arc (a clockwise one with X and Y exchanged) gives its clocks exchanged back.
pub struct ArcClocks {
    capacity: u64,
    end: (i64, i64),
    mirrored: bool,
    /// Axes the arc crosses before its last quadrant, and how many it has crossed.
    crossings: usize,
    crossed: usize,
    last_quadrant: bool,
    position: (i64, i64),
    q: [u64; 2],
    last_dir: [i64; 2],
    number: u64,
    /// A full circle takes about 2π·2ⁿ clocks; far more means the adders lost the circle.
    limit: u64,
    failed: bool,
}

impl ArcClocks {
    fn counter_clockwise(capacity: u64, start: (i64, i64), end: (i64, i64), mirrored: bool) -> ArcClocks {
        let crossings = axis_crossings(start, end, ArcDirection::CounterClockwise);
        ArcClocks {
            capacity,
            end,
            mirrored,
            crossings,
            crossed: 0,
            last_quadrant: crossings == 0,
            position: start,
            q: [capacity / 2; 2],
            last_dir: [0; 2],
            number: 0,
            limit: 8 * capacity + 16,
            failed: false,
        }
    }

    /// One clock of both adders, counter-clockwise.
    fn step(&mut self) -> CircleClock {
        let (capacity, end, last_quadrant) = (self.capacity, self.end, self.last_quadrant);
        let (x, y) = self.position;
        let mut steps = [0i8; 2];
        // q holds how far the integral is past the position in the axis's direction of
        // travel; where that direction turns (the other axis crossed 0) it starts again
        // from half, the rounding point. Each axis's direction is the one its own step
        // takes: Y's from the X this clock's X pulse left (the value its adder is fed), or
        // Y would take one more step the old way with the other's sum, just past X = 0.
        turn(&mut self.q[0], &mut self.last_dir[0], -y.signum(), capacity);
        let ax = add(y.unsigned_abs(), &mut self.q[0], capacity);
        if ax.pulse && !(last_quadrant && x == end.0) {
            steps[0] = -y.signum() as i8;
        }
        let nx = x + i64::from(steps[0]);
        turn(&mut self.q[1], &mut self.last_dir[1], nx.signum(), capacity);
        let ay = add(nx.unsigned_abs(), &mut self.q[1], capacity);
        if ay.pulse && !(last_quadrant && y == end.1) {
            steps[1] = nx.signum() as i8;
        }
        let ny = y + i64::from(steps[1]);
        self.crossed += usize::from(x != 0 && nx == 0) + usize::from(y != 0 && ny == 0);
        self.last_quadrant |= self.crossed >= self.crossings;
        self.position = (nx, ny);
        self.number += 1;
        CircleClock { number: self.number, axes: [ax, ay], steps, position: (nx, ny) }
    }
}

impl Iterator for ArcClocks {
    type Item = Result<CircleClock, DdaError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || (self.last_quadrant && self.position == self.end) {
            return None;
        }
        if self.number >= self.limit {
            self.failed = true;
            return Some(Err(DdaError(format!("the arc did not reach its end in {} clocks", self.limit))));
        }
        let c = self.step();
        Some(Ok(if self.mirrored {
            CircleClock {
                axes: [c.axes[1], c.axes[0]],
                steps: [c.steps[1], c.steps[0]],
                position: swap(c.position),
                ..c
            }
        } else {
            c
        }))
    }
}

/// An adder whose axis now steps the other way (`dir`, 0 at the turning point itself) starts
/// again from half, the rounding point.
fn turn(q: &mut u64, last_dir: &mut i64, dir: i64, capacity: u64) {
    if dir != 0 && *last_dir != 0 && dir != *last_dir {
        *q = capacity / 2;
    }
    if dir != 0 {
        *last_dir = dir;
    }
}

/// How often the arc from `start` to `end` crosses an axis between them (its ends not
/// counted): the quadrants it passes through before its last.
fn axis_crossings(start: (i64, i64), end: (i64, i64), direction: ArcDirection) -> usize {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let angle = |p: (i64, i64)| (p.1 as f64).atan2(p.0 as f64);
    let (a0, a1) = (angle(start), angle(end));
    let sweep = match direction {
        ArcDirection::CounterClockwise => (a1 - a0).rem_euclid(TAU),
        ArcDirection::Clockwise => (a0 - a1).rem_euclid(TAU),
    };
    let sweep = if sweep < 1e-12 { TAU } else { sweep };
    // Walk counter-clockwise from the lower end of the sweep.
    let from = if direction == ArcDirection::CounterClockwise { a0 } else { a0 - sweep };
    let eps = 1e-9;
    let first = ((from + eps) / FRAC_PI_2).ceil() as i64;
    let last = ((from + sweep - eps) / FRAC_PI_2).floor() as i64;
    (last - first + 1).max(0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_cover_the_longest_axis() {
        assert_eq!(bits_for(&[16, 8]), 4);
        assert_eq!(bits_for(&[17, 8]), 5);
        assert_eq!(bits_for(&[0, -1]), 1);
    }

    #[test]
    fn too_long_a_move_for_the_adder_is_refused() {
        assert!(linear(4, &[17, 1]).unwrap_err().0.contains("at least 5 bits"));
        assert!(increments(0.0105, 0.001).is_err());
        assert_eq!(increments(-0.016, 0.001), Ok(-16));
    }

    #[test]
    fn a_run_of_two_to_the_24_clocks_is_computed_as_it_is_read() {
        // 16,000,000 increments: a legal move for a 24-bit adder, 16,777,216 clocks (2^24 =
        // 16,777,216: the second clock's sum 32,000,000 overflows, leaving 15,222,784).
        let run = linear(bits_for(&[16_000_000, 1]), &[16_000_000, 1]).unwrap();
        assert_eq!(run.capacity(), 16_777_216);
        let first: Vec<(u64, u64, bool)> =
            run.clocks().take(3).map(|c| (c.axes[0].sum, c.axes[0].q, c.axes[0].pulse)).collect();
        assert_eq!(
            first,
            [(16_000_000, 16_000_000, false), (32_000_000, 15_222_784, true), (31_222_784, 14_445_568, true)]
        );
        let arc = circular(24, (-4_000_000, 0), (4_000_000, 0), ArcDirection::Clockwise).unwrap();
        // Clockwise from (-R, 0) the first steps go up: +Y, X still.
        let c = arc.clocks().find_map(|c| c.ok().filter(|c| c.steps != [0, 0])).unwrap();
        assert_eq!(c.steps, [0, 1]);
    }
}
