//! Statistics: aggregates and the conditional ones (`aggregates.rs`), spread (`dispersion.rs`),
//! order statistics (`order.rs`), distributions (`distributions.rs`, over the numerics of
//! `special.rs`), samples and tests (`sample_stats.rs`), regression (`regression.rs`).

pub(crate) mod aggregates;
pub(crate) mod dispersion;
pub(crate) mod distributions;
pub(crate) mod order;
pub(crate) mod regression;
pub(crate) mod sample_stats;
pub(crate) mod special;

use crate::eval::functions::api::FnSpec;

/// 2^64 and its inverse: a sum past the largest double goes on at the scale 2^-64, a power
/// of two (so scaling is exact), at which a sheet's count of numbers of any size stays finite.
const UP: f64 = 18_446_744_073_709_551_616.0;
const DOWN: f64 = 1.0 / UP;

/// A running sum for a mean that overflows only where the true mean would:
/// `AVERAGE(1E+308,1E+308)` is 1E+308 as in Excel, where the plain sum was infinite and the
/// mean `#NUM!`. It adds as plainly as ever (the same roundings, one more comparison) until
/// a sum would pass the largest double, and only then goes on at the scale 2^-64.
#[derive(Default, Clone, Copy)]
pub(crate) struct Total {
    sum: f64,
    scaled: bool,
}

impl Total {
    #[inline]
    pub(crate) fn add(&mut self, x: f64) {
        if self.scaled {
            self.sum += x * DOWN;
            return;
        }
        let sum = self.sum + x;
        if sum.is_finite() || !x.is_finite() || !self.sum.is_finite() {
            self.sum = sum;
        } else {
            self.sum = self.sum * DOWN + x * DOWN;
            self.scaled = true;
        }
    }

    /// The sum over `n`: the mean of `n` numbers added.
    pub(crate) fn over(self, n: f64) -> f64 {
        if self.scaled {
            self.sum / n * UP
        } else {
            self.sum / n
        }
    }
}

/// The arithmetic mean of `xs` through [`Total`] (NaN for none).
pub(crate) fn mean(xs: &[f64]) -> f64 {
    let mut total = Total::default();
    xs.iter().for_each(|&x| total.add(x));
    total.over(xs.len() as f64)
}

/// `a + t (b - a)` for `t` in 0..=1, finite wherever `a` and `b` are: where `b - a` overflows
/// (-1E+308 to 1E+308) the difference is taken of the halves, exactly, and doubled back
/// (PERCENTILE({-1E+308,1E+308},0.5) is 0, not `#NUM!`).
pub(crate) fn between(a: f64, b: f64, t: f64) -> f64 {
    let d = b - a;
    if d.is_finite() {
        a + t * d
    } else {
        a + t * (b / 2.0 - a / 2.0) * 2.0
    }
}

/// Where `x` lies from `lo` to `hi`, `(x - lo) / (hi - lo)`, finite wherever they are: the
/// halves are compared where the whole difference overflows (PERCENTRANK({-1E+308,1E+308},0)
/// is 0.5, where an infinite width made it 0).
pub(crate) fn fraction_between(lo: f64, x: f64, hi: f64) -> f64 {
    let d = hi - lo;
    if d.is_finite() {
        (x - lo) / d
    } else {
        (x / 2.0 - lo / 2.0) / (hi / 2.0 - lo / 2.0)
    }
}

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[
    aggregates::FUNCTIONS,
    dispersion::FUNCTIONS,
    distributions::FUNCTIONS,
    sample_stats::FUNCTIONS,
    regression::FUNCTIONS,
    order::FUNCTIONS,
];
