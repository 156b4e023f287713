//! Statistics of samples: shape (SKEW, SKEW.P, KURT), means (HARMEAN, GEOMEAN, TRIMMEAN),
//! paired samples (COVARIANCE.P/.S, COVAR, CORREL, PEARSON, RSQ, SLOPE, INTERCEPT, STEYX,
//! FORECAST), FREQUENCY and PROB, and the hypothesis tests (Z.TEST, T.TEST, F.TEST,
//! CHISQ.TEST with their old names).

use std::rc::Rc;

use crate::eval::coerce::to_number;
use crate::eval::functions::api::{
    block, lift_values, number, number_or, number_result, numbers, ArgSet, Ctx, FnSpec, MANY,
};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::statistics::dispersion::scale_of;
use crate::eval::functions::statistics::mean;
use crate::eval::functions::statistics::special::{beta_i, gamma_q, norm_cdf};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "CHISQ.TEST",
        2,
        2,
        chisq_test,
        "CHISQ.TEST(actual_range, expected_range)",
        "Chi-squared test of independence: the probability of the observed counts",
    )
    .future()
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "CHITEST",
        2,
        2,
        chisq_test,
        "CHITEST(actual_range, expected_range)",
        "Chi-squared test (CHISQ.TEST)",
    )
    .biff(306)
    .array_args(ArgSet::ALL),
    FnSpec::value("CORREL", 2, 2, correl, "CORREL(array1, array2)", "Correlation coefficient of two samples")
        .biff(307)
        .array_args(ArgSet::ALL),
    FnSpec::value("COVAR", 2, 2, covariance_p, "COVAR(array1, array2)", "Population covariance (COVARIANCE.P)")
        .biff(308)
        .array_args(ArgSet::ALL),
    FnSpec::value(
        "COVARIANCE.P",
        2,
        2,
        covariance_p,
        "COVARIANCE.P(array1, array2)",
        "Population covariance of two samples",
    )
    .future()
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "COVARIANCE.S",
        2,
        2,
        covariance_s,
        "COVARIANCE.S(array1, array2)",
        "Sample covariance of two samples",
    )
    .future()
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "F.TEST",
        2,
        2,
        f_test,
        "F.TEST(array1, array2)",
        "Two-tailed probability that two samples' variances do not differ",
    )
    .future()
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "FORECAST",
        3,
        3,
        forecast,
        "FORECAST(x, known_ys, known_xs)",
        "Value at x of the least-squares line (FORECAST.LINEAR)",
    )
    .biff(309)
    .array_args(ArgSet::from(1)),
    FnSpec::value(
        "FORECAST.LINEAR",
        3,
        3,
        forecast,
        "FORECAST.LINEAR(x, known_ys, known_xs)",
        "Value at x of the least-squares line through the known points",
    )
    .future()
    .array_args(ArgSet::from(1)),
    FnSpec::value(
        "FREQUENCY",
        2,
        2,
        frequency,
        "FREQUENCY(data_array, bins_array)",
        "How many values fall in each bin: a column one longer than the bins",
    )
    .biff(252)
    .array_args(ArgSet::ALL),
    FnSpec::value("FTEST", 2, 2, f_test, "FTEST(array1, array2)", "F-test (F.TEST)").biff(310).array_args(ArgSet::ALL),
    FnSpec::value(
        "GEOMEAN",
        1,
        MANY,
        geomean,
        "GEOMEAN(number1, [number2], ...)",
        "Geometric mean of positive numbers",
    )
    .biff(319)
    .range_args(ArgSet::ALL),
    FnSpec::value("HARMEAN", 1, MANY, harmean, "HARMEAN(number1, [number2], ...)", "Harmonic mean of positive numbers")
        .biff(320)
        .range_args(ArgSet::ALL),
    FnSpec::value("INTERCEPT", 2, 2, intercept, "INTERCEPT(known_ys, known_xs)", "Intercept of the least-squares line")
        .biff(311)
        .array_args(ArgSet::ALL),
    FnSpec::value("KURT", 1, MANY, kurt, "KURT(number1, [number2], ...)", "Excess kurtosis of a sample")
        .biff(322)
        .range_args(ArgSet::ALL),
    FnSpec::value("PEARSON", 2, 2, correl, "PEARSON(array1, array2)", "Pearson correlation coefficient (CORREL)")
        .biff(312)
        .array_args(ArgSet::ALL),
    FnSpec::value(
        "PROB",
        3,
        4,
        prob,
        "PROB(x_range, prob_range, lower_limit, [upper_limit])",
        "Probability that a value lies between the limits",
    )
    .biff(317)
    .array_args(ArgSet::only(0).and(ArgSet::only(1))),
    FnSpec::value("RSQ", 2, 2, rsq, "RSQ(known_ys, known_xs)", "Square of the correlation coefficient")
        .biff(313)
        .array_args(ArgSet::ALL),
    FnSpec::value("SKEW", 1, MANY, skew, "SKEW(number1, [number2], ...)", "Skewness of a sample")
        .biff(323)
        .range_args(ArgSet::ALL),
    FnSpec::value("SKEW.P", 1, MANY, skew_p, "SKEW.P(number1, [number2], ...)", "Skewness of a population")
        .future()
        .range_args(ArgSet::ALL),
    FnSpec::value("SLOPE", 2, 2, slope, "SLOPE(known_ys, known_xs)", "Slope of the least-squares line")
        .biff(315)
        .array_args(ArgSet::ALL),
    FnSpec::value(
        "STEYX",
        2,
        2,
        steyx,
        "STEYX(known_ys, known_xs)",
        "Standard error of the y predicted by the least-squares line",
    )
    .biff(314)
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "T.TEST",
        4,
        4,
        t_test,
        "T.TEST(array1, array2, tails, type)",
        "Student's t-test probability (type 1 paired, 2 equal variance, 3 unequal)",
    )
    .future()
    .array_args(ArgSet::only(0).and(ArgSet::only(1))),
    FnSpec::value(
        "TRIMMEAN",
        2,
        2,
        trimmean,
        "TRIMMEAN(array, percent)",
        "Mean without the given fraction of the extreme values",
    )
    .biff(331)
    .array_args(ArgSet::only(0)),
    FnSpec::value("TTEST", 4, 4, t_test, "TTEST(array1, array2, tails, type)", "Student's t-test (T.TEST)")
        .biff(316)
        .array_args(ArgSet::only(0).and(ArgSet::only(1))),
    FnSpec::value("Z.TEST", 2, 3, z_test, "Z.TEST(array, x, [sigma])", "One-tailed probability of a z-test")
        .future()
        .array_args(ArgSet::only(0)),
    FnSpec::value("ZTEST", 2, 3, z_test, "ZTEST(array, x, [sigma])", "One-tailed z-test (Z.TEST)")
        .biff(324)
        .array_args(ArgSet::only(0)),
];

fn sum_sq_dev(xs: &[f64]) -> f64 {
    let m = mean(xs);
    xs.iter().map(|x| (x - m) * (x - m)).sum()
}

fn sample_var(xs: &[f64]) -> f64 {
    sum_sq_dev(xs) / (xs.len() as f64 - 1.0)
}

/// A denominator: `#DIV/0!` when it is 0 (the data do not vary), `#NUM!` when its sum of
/// squares overflowed (`CORREL({1E+308,1},{1,1E+308})`), as LibreOffice says, where
/// `#DIV/0!` blamed data that vary.
fn nonzero(x: f64) -> XlResult<f64> {
    if x == 0.0 {
        Err(XlError::Div0)
    } else if !x.is_finite() {
        Err(XlError::Num)
    } else {
        Ok(x)
    }
}

// ---- shape and means ----------------------------------------------------------------------

/// Σ ((x − mean) / sd)^power with the sample (n − 1) or population standard deviation.
/// Computed at the scale of the largest magnitude (exact: a power of two), which standardizing
/// divides out: SKEW(1E+308,1E+308,-1E+308) squared deviations past the largest double.
fn standardized_power_sum(xs: &[f64], power: i32, sample: bool) -> XlResult<f64> {
    let n = xs.len() as f64;
    let scale = scale_of(xs);
    let scaled: Vec<f64> = xs.iter().map(|x| x / scale).collect();
    let xs = &scaled[..];
    let m = mean(xs);
    let sd = nonzero((sum_sq_dev(xs) / if sample { n - 1.0 } else { n }).sqrt())?;
    Ok(xs.iter().map(|x| ((x - m) / sd).powi(power)).sum())
}

fn skew(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = numbers(ctx, args)?;
    let n = xs.len() as f64;
    if n < 3.0 {
        return Err(XlError::Div0);
    }
    let s = standardized_power_sum(&xs, 3, true)?;
    Ok(number_result(n / ((n - 1.0) * (n - 2.0)) * s))
}

fn skew_p(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = numbers(ctx, args)?;
    if xs.is_empty() {
        return Err(XlError::Div0);
    }
    let s = standardized_power_sum(&xs, 3, false)?;
    Ok(number_result(s / xs.len() as f64))
}

fn kurt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = numbers(ctx, args)?;
    let n = xs.len() as f64;
    if n < 4.0 {
        return Err(XlError::Div0);
    }
    let s = standardized_power_sum(&xs, 4, true)?;
    let k = n * (n + 1.0) / ((n - 1.0) * (n - 2.0) * (n - 3.0)) * s - 3.0 * (n - 1.0).powi(2) / ((n - 2.0) * (n - 3.0));
    Ok(number_result(k))
}

fn positive_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let xs = numbers(ctx, args)?;
    if xs.is_empty() || xs.iter().any(|&x| x <= 0.0) {
        return Err(XlError::Num);
    }
    Ok(xs)
}

fn harmean(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = positive_numbers(ctx, args)?;
    Ok(number_result(xs.len() as f64 / xs.iter().map(|x| 1.0 / x).sum::<f64>()))
}

fn geomean(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = positive_numbers(ctx, args)?;
    Ok(number_result(geometric_mean(&xs)))
}

/// The n-th root of the product of `xs` (all positive), the product kept as a mantissa in
/// [0.5, 1) times a whole power of two so it neither overflows nor underflows. The root of
/// the power is split into a whole power of two and a root of what is left, which is near 1:
/// through logarithms, exp(709.19…) lost the last digits and GEOMEAN(1E308,1E308) was
/// 1.00000000000001E+308 where Excel shows 1E+308.
fn geometric_mean(xs: &[f64]) -> f64 {
    let (mut mantissa, mut exponent) = (1.0, 0i64);
    for &x in xs {
        let (m, e) = binary_parts(x);
        let (product, carry) = binary_parts(mantissa * m);
        mantissa = product;
        exponent += e + carry;
    }
    let n = xs.len() as i64;
    let (whole, rest) = (exponent.div_euclid(n), exponent.rem_euclid(n));
    let root = if rest < 1000 {
        // mantissa × 2^rest is exact and finite: one rounding in the root.
        times_power_of_two(mantissa, rest).powf(1.0 / n as f64)
    } else {
        ((mantissa.ln() + rest as f64 * std::f64::consts::LN_2) / n as f64).exp()
    };
    times_power_of_two(root, whole)
}

/// `x` (positive, finite) as (m, e) with x = m × 2^e and m in [0.5, 1).
fn binary_parts(x: f64) -> (f64, i64) {
    if x < f64::MIN_POSITIVE {
        // A subnormal has no implicit leading bit: scaled into the normal range first.
        let (m, e) = binary_parts(x * 2f64.powi(54));
        return (m, e - 54);
    }
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i64;
    (f64::from_bits((bits & !(0x7ff << 52)) | (1022 << 52)), biased - 1022)
}

/// x × 2^e, in steps a double can hold (2^-1074 and 2^1023 are not both powers `powi` reaches).
fn times_power_of_two(mut x: f64, mut e: i64) -> f64 {
    while e != 0 {
        let step = e.clamp(-1000, 1000);
        x *= 2f64.powi(step as i32);
        e -= step;
    }
    x
}

fn trimmean(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut xs = numbers(ctx, &args[..1])?;
    let percent = number(ctx, &args[1])?;
    if !(0.0..1.0).contains(&percent) || xs.is_empty() {
        return Err(XlError::Num);
    }
    xs.sort_by(f64::total_cmp);
    // Excel drops the same whole number of values at each end, rounding down.
    let drop = ((xs.len() as f64 * percent) / 2.0).floor() as usize;
    Ok(number_result(mean(&xs[drop..xs.len() - drop])))
}

// ---- paired samples -----------------------------------------------------------------------

/// An argument's items in order (a range's cells, blanks included; a scalar is one item).
fn items(ctx: &mut Ctx, e: &Expr) -> XlResult<Rc<Array>> {
    block(ctx, e)
}

/// The (x, y) pairs of two equally long samples where both are numbers; an error in either
/// is the result; different lengths are `#N/A`.
fn pairs(ctx: &mut Ctx, xs: &Expr, ys: &Expr) -> XlResult<(Vec<f64>, Vec<f64>)> {
    let (a, b) = (items(ctx, xs)?, items(ctx, ys)?);
    if a.data.len() != b.data.len() {
        return Err(XlError::NA);
    }
    let mut out = (Vec::new(), Vec::new());
    for (x, y) in a.data.iter().zip(&b.data) {
        if let Value::Error(e) = x {
            return Err(*e);
        }
        if let Value::Error(e) = y {
            return Err(*e);
        }
        if let (Value::Number(x), Value::Number(y)) = (x, y) {
            out.0.push(*x);
            out.1.push(*y);
        }
    }
    Ok(out)
}

/// Sums of the centred products: (Sxx, Syy, Sxy, n, mean x, mean y).
struct Moments {
    sxx: f64,
    syy: f64,
    sxy: f64,
    n: f64,
    mx: f64,
    my: f64,
}

fn moments(xs: &[f64], ys: &[f64]) -> Moments {
    let (mx, my) = (mean(xs), mean(ys));
    let mut m = Moments { sxx: 0.0, syy: 0.0, sxy: 0.0, n: xs.len() as f64, mx, my };
    for (x, y) in xs.iter().zip(ys) {
        m.sxx += (x - mx) * (x - mx);
        m.syy += (y - my) * (y - my);
        m.sxy += (x - mx) * (y - my);
    }
    m
}

/// The moments of `(first, second)` read as (x, y); `#DIV/0!` below `min` pairs.
fn paired_moments(ctx: &mut Ctx, x: &Expr, y: &Expr, min: usize) -> XlResult<Moments> {
    let (xs, ys) = pairs(ctx, x, y)?;
    if xs.len() < min {
        return Err(XlError::Div0);
    }
    Ok(moments(&xs, &ys))
}

fn covariance_p(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = paired_moments(ctx, &args[0], &args[1], 1)?;
    Ok(number_result(m.sxy / m.n))
}

fn covariance_s(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = paired_moments(ctx, &args[0], &args[1], 2)?;
    Ok(number_result(m.sxy / (m.n - 1.0)))
}

fn correlation(m: &Moments) -> XlResult<f64> {
    Ok(m.sxy / nonzero((m.sxx * m.syy).sqrt())?)
}

fn correl(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = paired_moments(ctx, &args[0], &args[1], 1)?;
    Ok(number_result(correlation(&m)?))
}

/// Known ys come first in the regression functions: (ys, xs).
fn regression_moments(ctx: &mut Ctx, ys: &Expr, xs: &Expr) -> XlResult<Moments> {
    paired_moments(ctx, xs, ys, 1)
}

fn rsq(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = regression_moments(ctx, &args[0], &args[1])?;
    Ok(number_result(correlation(&m)?.powi(2)))
}

fn slope(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = regression_moments(ctx, &args[0], &args[1])?;
    Ok(number_result(m.sxy / nonzero(m.sxx)?))
}

fn intercept(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = regression_moments(ctx, &args[0], &args[1])?;
    Ok(number_result(m.my - m.sxy / nonzero(m.sxx)? * m.mx))
}

fn steyx(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let m = regression_moments(ctx, &args[0], &args[1])?;
    if m.n < 3.0 {
        return Err(XlError::Div0);
    }
    let residual = m.syy - m.sxy * m.sxy / nonzero(m.sxx)?;
    // A residual below 0 is rounding, read as 0; one that is NaN (sums of squares past the
    // largest double) stays NaN and is #NUM!: `f64::max` would have made it 0.
    let residual = if residual < 0.0 { 0.0 } else { residual };
    Ok(number_result((residual / (m.n - 2.0)).sqrt()))
}

fn forecast(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let m = regression_moments(ctx, &args[1], &args[2])?;
    let b = m.sxy / nonzero(m.sxx)?;
    let a = m.my - b * m.mx;
    let x = ctx.eval(&args[0]);
    let values = [x];
    lift_values(&values, &|v| Ok(number_result(a + b * to_number(&v[0], dates)?)))
}

// ---- distributions of data -----------------------------------------------------------------

/// The numbers of an array argument (text, booleans and blanks skipped, errors returned).
fn array_numbers(ctx: &mut Ctx, e: &Expr) -> XlResult<Vec<f64>> {
    numbers(ctx, std::slice::from_ref(e))
}

fn frequency(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let data = array_numbers(ctx, &args[0])?;
    let bins = array_numbers(ctx, &args[1])?;
    let mut order: Vec<usize> = (0..bins.len()).collect();
    order.sort_by(|&a, &b| bins[a].total_cmp(&bins[b]));
    let mut counts = vec![0.0; bins.len() + 1];
    for x in data {
        // The first bin in ascending order that holds x; beyond the largest, the last row.
        // A binary search: 2^20 data in 2^20 bins was 2^40 comparisons one by one.
        let first_holding = order.partition_point(|&i| bins[i] < x);
        let slot = order.get(first_holding).copied().unwrap_or(bins.len());
        counts[slot] += 1.0;
    }
    Ok(Value::Array(Rc::new(Array::column(counts.into_iter().map(Value::Number).collect()))))
}

fn prob(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (xs, ps) = pairs(ctx, &args[0], &args[1])?;
    let lower = number(ctx, &args[2])?;
    let upper = number_or(ctx, args, 3, lower)?;
    if xs.is_empty() {
        return Err(XlError::Div0);
    }
    if ps.iter().any(|p| !(0.0..=1.0).contains(p)) || (ps.iter().sum::<f64>() - 1.0).abs() > 1e-7 {
        return Err(XlError::Num);
    }
    let total =
        xs.iter().zip(&ps).filter(|(x, _)| (lower..=upper).contains(*x)).map(|(_, p)| p).fold(0.0, |a, p| a + p); // not -0 for none
    Ok(number_result(total))
}

// ---- tests --------------------------------------------------------------------------------

fn z_test(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let xs = array_numbers(ctx, &args[0])?;
    if xs.is_empty() {
        return Err(XlError::NA);
    }
    let sigma = match args.get(2) {
        Some(_) => Some(number(ctx, &args[2])?),
        None => None,
    };
    let n = xs.len() as f64;
    let m = mean(&xs);
    let sigma = match sigma {
        Some(s) => s,
        None if n < 2.0 => return Err(XlError::Div0),
        None => sample_var(&xs).sqrt(),
    };
    let sigma = nonzero(sigma)?;
    let values = [ctx.eval(&args[1])];
    lift_values(&values, &|v| {
        let x = to_number(&v[0], dates)?;
        Ok(number_result(1.0 - norm_cdf((m - x) / (sigma / n.sqrt()))))
    })
}

/// Two-tailed probability P(|T| > t) for Student's t with `df` degrees of freedom.
fn t_two_tailed(t: f64, df: f64) -> f64 {
    beta_i(df / (df + t * t), df / 2.0, 0.5)
}

fn t_test(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let tails = number(ctx, &args[2])?.trunc();
    let kind = number(ctx, &args[3])?.trunc();
    if !(tails == 1.0 || tails == 2.0) || !(1.0..=3.0).contains(&kind) {
        return Err(XlError::Num);
    }
    let (t, df) = if kind == 1.0 {
        let (a, b) = pairs(ctx, &args[0], &args[1])?;
        let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
        let n = d.len() as f64;
        if n < 2.0 {
            return Err(XlError::Div0);
        }
        (mean(&d) / nonzero((sample_var(&d) / n).sqrt())?, n - 1.0)
    } else {
        let a = array_numbers(ctx, &args[0])?;
        let b = array_numbers(ctx, &args[1])?;
        let (n1, n2) = (a.len() as f64, b.len() as f64);
        if n1 < 2.0 || n2 < 2.0 {
            return Err(XlError::Div0);
        }
        let (v1, v2) = (sample_var(&a), sample_var(&b));
        let diff = mean(&a) - mean(&b);
        if kind == 2.0 {
            let pooled = ((n1 - 1.0) * v1 + (n2 - 1.0) * v2) / (n1 + n2 - 2.0);
            (diff / nonzero((pooled * (1.0 / n1 + 1.0 / n2)).sqrt())?, n1 + n2 - 2.0)
        } else {
            let (s1, s2) = (v1 / n1, v2 / n2);
            let df = (s1 + s2).powi(2) / (s1 * s1 / (n1 - 1.0) + s2 * s2 / (n2 - 1.0));
            (diff / nonzero((s1 + s2).sqrt())?, df)
        }
    };
    Ok(number_result(tails / 2.0 * t_two_tailed(t.abs(), df)))
}

fn f_test(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = array_numbers(ctx, &args[0])?;
    let b = array_numbers(ctx, &args[1])?;
    if a.len() < 2 || b.len() < 2 {
        return Err(XlError::Div0);
    }
    let (v1, v2) = (nonzero(sample_var(&a))?, nonzero(sample_var(&b))?);
    let (d1, d2) = (a.len() as f64 - 1.0, b.len() as f64 - 1.0);
    let f = v1 / v2;
    let right = beta_i(d2 / (d2 + d1 * f), d2 / 2.0, d1 / 2.0);
    Ok(number_result(2.0 * right.min(1.0 - right)))
}

fn chisq_test(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let actual = items(ctx, &args[0])?;
    let expected = items(ctx, &args[1])?;
    if actual.rows != expected.rows || actual.cols != expected.cols {
        return Err(XlError::NA);
    }
    let mut chi = 0.0;
    for (a, e) in actual.data.iter().zip(&expected.data) {
        if let (Value::Number(a), Value::Number(e)) = (a, e) {
            if *e == 0.0 {
                return Err(XlError::Div0);
            }
            chi += (a - e) * (a - e) / e;
        }
    }
    let df = match (actual.rows, actual.cols) {
        (1, 1) => return Err(XlError::NA),
        (1, c) => c - 1,
        (r, 1) => r - 1,
        (r, c) => (r - 1) * (c - 1),
    } as f64;
    Ok(number_result(gamma_q(df / 2.0, chi / 2.0)))
}
