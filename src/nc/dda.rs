//! The DDA linear interpolator of DOMAIN.md §4 (Glavonjić, table T8.1.1), exactly as the
//! control runs it: integer registers, one n-bit adder per axis, a pulse of one machine
//! increment whenever the adder overflows. Every clock each axis adds its register p (the
//! move's length in increments) to its register q; when the sum reaches 2ⁿ, 2ⁿ is taken off
//! and one pulse goes to the axis. After 2ⁿ clocks every axis has had exactly |δ| pulses, so
//! all arrive together and each axis's pulse rate is proportional to its length.

use std::fmt;

/// What the interpolator cannot run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DdaError(pub String);

impl fmt::Display for DdaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DdaError {}

/// The most adder bits we run: 2ⁿ clocks are listed one by one.
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

/// A whole straight move through the interpolator.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DdaRun {
    pub bits: u32,
    /// The move per axis in increments, with its sign (the pulses' direction).
    pub deltas: Vec<i64>,
    pub clocks: Vec<Clock>,
}

impl DdaRun {
    /// 2ⁿ, the adder's capacity.
    pub fn capacity(&self) -> u64 {
        1u64 << self.bits
    }

    /// Pulses each axis received, signed by direction.
    pub fn pulses(&self) -> Vec<i64> {
        (0..self.deltas.len())
            .map(|i| {
                let n = self.clocks.iter().filter(|c| c.axes[i].pulse).count() as i64;
                n * self.deltas[i].signum()
            })
            .collect()
    }
}

/// The smallest n with 2ⁿ ≥ the longest axis move (the paper's choice), at least 1.
pub fn bits_for(deltas: &[i64]) -> u32 {
    let longest = deltas.iter().map(|d| d.unsigned_abs()).max().unwrap_or(0).max(2);
    64 - (longest - 1).leading_zeros()
}

/// Runs a straight move of `deltas` increments per axis through `bits`-bit adders: 2ⁿ clocks
/// at constant feed (Δp = 0). An axis longer than 2ⁿ would need two pulses in one clock,
/// which the adder cannot give.
pub fn linear(bits: u32, deltas: &[i64]) -> Result<DdaRun, DdaError> {
    if !(1..=MAX_BITS).contains(&bits) {
        return Err(DdaError(format!("the adder has 1 to {MAX_BITS} bits, not {bits}")));
    }
    let capacity = 1u64 << bits;
    if let Some(d) = deltas.iter().find(|d| d.unsigned_abs() > capacity) {
        return Err(DdaError(format!(
            "a move of {d} increments needs more than one pulse per clock from a {bits}-bit adder \
             (at most 2^{bits} = {capacity}); use at least {} bits",
            bits_for(deltas)
        )));
    }
    let p: Vec<u64> = deltas.iter().map(|d| d.unsigned_abs()).collect();
    let mut q = vec![0u64; deltas.len()];
    let clocks = (1..=capacity)
        .map(|number| {
            let axes = p.iter().zip(q.iter_mut()).map(|(&p, q)| add(p, q, capacity)).collect();
            Clock { number, axes }
        })
        .collect();
    Ok(DdaRun { bits, deltas: deltas.to_vec(), clocks })
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
}
