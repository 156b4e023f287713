//! Spread of a sample: the variance and standard deviation families (VAR.S, VAR.P, STDEV.S,
//! STDEV.P with their old names, and VARA, VARPA, STDEVA, STDEVPA), DEVSQ and AVEDEV; and the
//! A forms of the plain aggregates (AVERAGEA, MINA, MAXA), which count text and booleans in
//! ranges.

use crate::eval::functions::api::{number_result, numbers, numbers_a, ArgSet, Ctx, FnSpec, MANY};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::statistics::{mean, Total};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "AVEDEV",
        1,
        MANY,
        avedev,
        "AVEDEV(number1, [number2], ...)",
        "Mean absolute deviation from the mean",
    )
    .biff(269)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "AVERAGEA",
        1,
        MANY,
        averagea,
        "AVERAGEA(value1, [value2], ...)",
        "Mean counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(361)
    .range_args(ArgSet::ALL),
    FnSpec::value("DEVSQ", 1, MANY, devsq, "DEVSQ(number1, [number2], ...)", "Sum of squared deviations from the mean")
        .biff(318)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "MAXA",
        1,
        MANY,
        maxa,
        "MAXA(value1, [value2], ...)",
        "Largest value counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(362)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "MINA",
        1,
        MANY,
        mina,
        "MINA(value1, [value2], ...)",
        "Smallest value counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(363)
    .range_args(ArgSet::ALL),
    FnSpec::value("STDEV", 1, MANY, stdev_s, "STDEV(number1, [number2], ...)", "Sample standard deviation (STDEV.S)")
        .biff(12)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "STDEV.P",
        1,
        MANY,
        stdev_p,
        "STDEV.P(number1, [number2], ...)",
        "Standard deviation of a whole population",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "STDEV.S",
        1,
        MANY,
        stdev_s,
        "STDEV.S(number1, [number2], ...)",
        "Sample standard deviation; #DIV/0! below two numbers",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "STDEVA",
        1,
        MANY,
        stdev_a,
        "STDEVA(value1, [value2], ...)",
        "Sample standard deviation counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(366)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "STDEVP",
        1,
        MANY,
        stdev_p,
        "STDEVP(number1, [number2], ...)",
        "Standard deviation of a whole population (STDEV.P)",
    )
    .biff(193)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "STDEVPA",
        1,
        MANY,
        stdev_pa,
        "STDEVPA(value1, [value2], ...)",
        "Population standard deviation counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(364)
    .range_args(ArgSet::ALL),
    FnSpec::value("VAR", 1, MANY, var_s, "VAR(number1, [number2], ...)", "Sample variance (VAR.S)")
        .biff(46)
        .range_args(ArgSet::ALL),
    FnSpec::value("VAR.P", 1, MANY, var_p, "VAR.P(number1, [number2], ...)", "Variance of a whole population")
        .future()
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "VAR.S",
        1,
        MANY,
        var_s,
        "VAR.S(number1, [number2], ...)",
        "Sample variance (divided by n - 1); #DIV/0! below two numbers",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "VARA",
        1,
        MANY,
        var_a,
        "VARA(value1, [value2], ...)",
        "Sample variance counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(367)
    .range_args(ArgSet::ALL),
    FnSpec::value("VARP", 1, MANY, var_p, "VARP(number1, [number2], ...)", "Variance of a whole population (VAR.P)")
        .biff(194)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "VARPA",
        1,
        MANY,
        var_pa,
        "VARPA(value1, [value2], ...)",
        "Population variance counting text in ranges as 0 and booleans as 1 or 0",
    )
    .biff(365)
    .range_args(ArgSet::ALL),
];

/// Which values a function reads: numbers only (VAR) or text and booleans too (VARA).
#[derive(Clone, Copy)]
enum Reading {
    Numbers,
    All,
}

/// What the squared deviations are divided by: n - 1 (a sample) or n (a population).
#[derive(Clone, Copy)]
enum Of {
    Sample,
    Population,
}

fn values(ctx: &mut Ctx, args: &[Expr], reading: Reading) -> XlResult<Vec<f64>> {
    match reading {
        Reading::Numbers => numbers(ctx, args),
        Reading::All => numbers_a(ctx, args),
    }
}

/// A power of two at the largest magnitude among `xs` (1 for none or zeros): dividing by it
/// is exact, so sums and squares at that scale round as they would unscaled, yet stay
/// finite where the result is (the standard deviation of 1E+308 and -1E+308 is 1.41E+308).
pub(crate) fn scale_of(xs: &[f64]) -> f64 {
    let largest = xs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest.is_normal() {
        2f64.powi(largest.log2().floor() as i32)
    } else {
        1.0
    }
}

/// Σ(x - mean)² as (its value at the scale, the scale): the true sum is the first times the
/// square of the second, which may overflow where its square root does not.
/// By the corrected two-pass algorithm: the deviations from the computed mean, less the
/// square of their own sum over n, which removes the rounding error of the mean. Accurate
/// where the one-pass Σx² - (Σx)²/n cancels (values near 1e9 that differ by 0.1).
pub(crate) fn scaled_squared_deviations(xs: &[f64]) -> (f64, f64) {
    let scale = scale_of(xs);
    let ys: Vec<f64> = xs.iter().map(|x| x / scale).collect();
    let m = ys.iter().sum::<f64>() / ys.len() as f64;
    let (squares, sum) = ys.iter().fold((0.0, 0.0), |(sq, s), &y| (sq + (y - m) * (y - m), s + (y - m)));
    (squares - sum * sum / ys.len() as f64, scale)
}

/// The variance of the arguments as (its value at the scale, the scale) of
/// [`scaled_squared_deviations`]; `#DIV/0!` without enough values (two for a sample).
fn variance(ctx: &mut Ctx, args: &[Expr], reading: Reading, of: Of) -> XlResult<(f64, f64)> {
    let xs = values(ctx, args, reading)?;
    let divisor = match of {
        Of::Sample => xs.len().saturating_sub(1),
        Of::Population => xs.len(),
    };
    if divisor == 0 {
        return Err(XlError::Div0);
    }
    let (squares, scale) = scaled_squared_deviations(&xs);
    Ok((squares / divisor as f64, scale))
}

/// A variance at its scale as a value: `#NUM!` only where the true variance is past the
/// largest double.
pub(crate) fn unscaled((v, scale): (f64, f64)) -> Value {
    number_result(v * scale * scale)
}

/// The standard deviation of a variance at its scale: its square root scaled back, finite
/// wherever the deviation is, though the variance may not be.
pub(crate) fn deviation((v, scale): (f64, f64)) -> Value {
    number_result(v.sqrt() * scale)
}

fn var_s(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::Numbers, Of::Sample).map(unscaled)
}

fn var_p(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::Numbers, Of::Population).map(unscaled)
}

fn var_a(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::All, Of::Sample).map(unscaled)
}

fn var_pa(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::All, Of::Population).map(unscaled)
}

fn stdev_s(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::Numbers, Of::Sample).map(deviation)
}

fn stdev_p(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::Numbers, Of::Population).map(deviation)
}

fn stdev_a(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::All, Of::Sample).map(deviation)
}

fn stdev_pa(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    variance(ctx, args, Reading::All, Of::Population).map(deviation)
}

/// The numbers, `#NUM!` when there are none (DEVSQ, AVEDEV).
fn some_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let xs = numbers(ctx, args)?;
    if xs.is_empty() {
        Err(XlError::Num)
    } else {
        Ok(xs)
    }
}

fn devsq(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(unscaled(scaled_squared_deviations(&some_numbers(ctx, args)?)))
}

fn avedev(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = some_numbers(ctx, args)?;
    let m = mean(&xs);
    let mut deviations = Total::default();
    xs.iter().for_each(|x| deviations.add((x - m).abs()));
    Ok(number_result(deviations.over(xs.len() as f64)))
}

fn averagea(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = numbers_a(ctx, args)?;
    if xs.is_empty() {
        return Err(XlError::Div0);
    }
    Ok(number_result(mean(&xs)))
}

fn mina(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(numbers_a(ctx, args)?.into_iter().reduce(f64::min).unwrap_or(0.0)))
}

fn maxa(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(numbers_a(ctx, args)?.into_iter().reduce(f64::max).unwrap_or(0.0)))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::n;
    use crate::eval::testing::MapEnv;
    use crate::eval::value::{Value, XlError};

    /// A1:A5 = 1, 2, TRUE, "x", 5 (A6 blank); B1:B3 = 1e9+0.1, 1e9+0.2, 1e9+0.3.
    fn env() -> MapEnv {
        MapEnv::with(&[
            ("A1", n(1.0)),
            ("A2", n(2.0)),
            ("A3", Value::Bool(true)),
            ("A4", Value::text("x")),
            ("A5", n(5.0)),
            ("B1", n(1e9 + 0.1)),
            ("B2", n(1e9 + 0.2)),
            ("B3", n(1e9 + 0.3)),
        ])
    }

    fn close(got: Value, want: f64) -> bool {
        matches!(got, Value::Number(x) if (x - want).abs() <= 1e-12 * want.abs().max(1.0))
    }

    /// Hand arithmetic: the numbers 1, 2, 5 have mean 8/3 and squared deviations 26/3; with
    /// TRUE and "x" read as 1 and 0 the values 1, 2, 1, 0, 5 have mean 1.8 and 14.8.
    #[test]
    fn variances_by_hand() {
        let env = env();
        let cases = [
            ("=VAR.S(A1:A6)", 13.0 / 3.0),
            ("=VAR(A1:A6)", 13.0 / 3.0),
            ("=VAR.P(A1:A6)", 26.0 / 9.0),
            ("=VARA(A1:A6)", 3.7),
            ("=VARPA(A1:A6)", 2.96),
            ("=STDEV.S(A1:A6)", (13.0f64 / 3.0).sqrt()),
            ("=STDEVPA(A1:A6)", 2.96f64.sqrt()),
            ("=DEVSQ(A1:A6)", 26.0 / 3.0),
            ("=AVEDEV(A1:A6)", (5.0 / 3.0 + 2.0 / 3.0 + 7.0 / 3.0) / 3.0),
            ("=AVERAGEA(A1:A6)", 1.8),
            ("=VAR.S(1,\"2\",TRUE)", 1.0 / 3.0),
        ];
        for (formula, want) in cases {
            assert!(close(env.eval(formula), want), "{formula}: {:?}", env.eval(formula));
        }
    }

    #[test]
    fn the_two_pass_variance_keeps_its_digits() {
        // 0.1, 0.2, 0.3 shifted by 1e9: the sample variance is 0.01 (doubles near 1e9 hold
        // 0.1 to about 1e-7, hence the tolerance).
        let got = env().eval("=VAR.S(B1:B3)");
        assert!(matches!(got, Value::Number(x) if (x - 0.01).abs() < 1e-7), "{got:?}");
    }

    #[test]
    fn edge_cases() {
        let env = env();
        assert_eq!(env.eval("=VAR.S(1)"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=VAR.P(A4)"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=STDEV.P(7)"), n(0.0));
        assert_eq!(env.eval("=DEVSQ(A4)"), Value::Error(XlError::Num));
        assert_eq!(env.eval("=MINA(A1:A6)"), n(0.0));
        assert_eq!(env.eval("=MAXA(A3:A4)"), n(1.0));
        assert_eq!(env.eval("=MINA(1,\"x\")"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=MAXA(A6)"), n(0.0));
        assert_eq!(env.eval("=VAR.S(1,1/0)"), Value::Error(XlError::Div0));
    }
}
