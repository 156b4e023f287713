//! Order statistics: SMALL, LARGE, PERCENTILE and QUARTILE (.INC and .EXC), PERCENTRANK,
//! RANK (.EQ and .AVG) and MODE (.SNGL and .MULT). The data argument is read as MEDIAN reads
//! it (numbers; text and booleans in ranges skipped); the position arguments lift over arrays,
//! so `LARGE(A1:A9, {1,2,3})` spills the three largest.

use std::collections::HashMap;
use std::rc::Rc;

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::format::number_format::round15;
use crate::eval::functions::api::{lift_values, number_result, numbers, ArgSet, Ctx, FnSpec, MANY};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::statistics::{between, fraction_between};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("LARGE", 2, 2, large, "LARGE(array, k)", "The k-th largest number")
        .biff(325)
        .range_args(ArgSet::only(0)),
    FnSpec::value("MODE", 1, MANY, mode_sngl, "MODE(number1, [number2], ...)", "Most frequent number (MODE.SNGL)")
        .biff(330)
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "MODE.MULT",
        1,
        MANY,
        mode_mult,
        "MODE.MULT(number1, [number2], ...)",
        "Every most frequent number, in order of appearance, as a column",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "MODE.SNGL",
        1,
        MANY,
        mode_sngl,
        "MODE.SNGL(number1, [number2], ...)",
        "Most frequent number, the first to appear on a tie; #N/A when none repeats",
    )
    .future()
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "PERCENTILE",
        2,
        2,
        percentile_inc,
        "PERCENTILE(array, k)",
        "The k-th percentile, 0 <= k <= 1 (PERCENTILE.INC)",
    )
    .biff(328)
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "PERCENTILE.EXC",
        2,
        2,
        percentile_exc,
        "PERCENTILE.EXC(array, k)",
        "The k-th percentile interpolated at k*(n+1); #NUM! outside the data",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "PERCENTILE.INC",
        2,
        2,
        percentile_inc,
        "PERCENTILE.INC(array, k)",
        "The k-th percentile interpolated at k*(n-1)+1, 0 <= k <= 1",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "PERCENTRANK",
        2,
        3,
        percentrank_inc,
        "PERCENTRANK(array, x, [significance])",
        "Rank of x as a fraction 0..1 (PERCENTRANK.INC)",
    )
    .biff(329)
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "PERCENTRANK.EXC",
        2,
        3,
        percentrank_exc,
        "PERCENTRANK.EXC(array, x, [significance])",
        "Rank of x as a fraction strictly between 0 and 1, truncated to significance digits",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "PERCENTRANK.INC",
        2,
        3,
        percentrank_inc,
        "PERCENTRANK.INC(array, x, [significance])",
        "Rank of x as a fraction 0..1, truncated to significance digits (3)",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value("QUARTILE", 2, 2, quartile_inc, "QUARTILE(array, quart)", "Quartile 0 to 4 (QUARTILE.INC)")
        .biff(327)
        .range_args(ArgSet::only(0)),
    FnSpec::value(
        "QUARTILE.EXC",
        2,
        2,
        quartile_exc,
        "QUARTILE.EXC(array, quart)",
        "Quartile 1 to 3 by PERCENTILE.EXC",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value(
        "QUARTILE.INC",
        2,
        2,
        quartile_inc,
        "QUARTILE.INC(array, quart)",
        "Quartile 0 (minimum) to 4 (maximum) by PERCENTILE.INC",
    )
    .future()
    .range_args(ArgSet::only(0)),
    FnSpec::value("RANK", 2, 3, rank_eq, "RANK(number, ref, [order])", "Rank of number in ref (RANK.EQ)")
        .biff(216)
        .range_args(ArgSet::from(1)),
    FnSpec::value(
        "RANK.AVG",
        2,
        3,
        rank_avg,
        "RANK.AVG(number, ref, [order])",
        "Rank of number in ref, ties sharing their mean rank; order<>0 ranks ascending",
    )
    .future()
    .range_args(ArgSet::from(1)),
    FnSpec::value(
        "RANK.EQ",
        2,
        3,
        rank_eq,
        "RANK.EQ(number, ref, [order])",
        "Rank of number in ref (1 the largest), ties sharing the top rank; order<>0 ranks ascending",
    )
    .future()
    .range_args(ArgSet::from(1)),
    FnSpec::value("SMALL", 2, 2, small, "SMALL(array, k)", "The k-th smallest number")
        .biff(326)
        .range_args(ArgSet::only(0)),
];

/// The numbers of the data argument, ascending.
fn sorted(ctx: &mut Ctx, data: &Expr) -> XlResult<Vec<f64>> {
    let mut xs = numbers(ctx, std::slice::from_ref(data))?;
    xs.sort_by(f64::total_cmp);
    Ok(xs)
}

/// A computation on the ascending data and one item of each other argument.
type OnData = dyn Fn(&[f64], &[Value]) -> XlResult<f64>;

/// Reads the data (`args[0]`), then applies `f` to it and each item of the other arguments.
fn over_data(ctx: &mut Ctx, args: &[Expr], f: &OnData) -> XlResult<Value> {
    let xs = sorted(ctx, &args[0])?;
    let rest: Vec<Value> = args[1..].iter().map(|a| ctx.eval(a)).collect();
    lift_values(&rest, &|v| f(&xs, v).map(number_result))
}

// ---- k-th values and percentiles ----------------------------------------------------------

/// The k-th smallest (or largest) of the ascending numbers, k from 1. A fractional k is
/// rounded down for SMALL and up for LARGE, as if LARGE's k were SMALL's n + 1 - k rounded
/// down (newer LibreOffice does the same for Excel's sake).
fn kth(xs: &[f64], k: &Value, largest: bool, dates: DateSystem) -> XlResult<f64> {
    let k = to_number(k, dates)?;
    let k = if largest { k.ceil() } else { k.floor() };
    if k < 1.0 || k > xs.len() as f64 {
        return Err(XlError::Num);
    }
    let k = k as usize;
    Ok(if largest { xs[xs.len() - k] } else { xs[k - 1] })
}

fn small(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| kth(xs, &v[0], false, dates))
}

fn large(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| kth(xs, &v[0], true, dates))
}

/// The value at 0-based position `rank` of the ascending numbers, interpolated between the
/// neighbours.
fn interpolate(xs: &[f64], rank: f64) -> f64 {
    let i = rank.floor() as usize;
    let fraction = rank - rank.floor();
    match xs.get(i + 1) {
        Some(&next) if fraction > 0.0 => between(xs[i], next, fraction),
        _ => xs[i],
    }
}

/// PERCENTILE.INC: position k*(n-1) from the smallest, 0 <= k <= 1.
fn inclusive(xs: &[f64], k: f64) -> XlResult<f64> {
    if xs.is_empty() || !(0.0..=1.0).contains(&k) {
        return Err(XlError::Num);
    }
    Ok(interpolate(xs, k * (xs.len() - 1) as f64))
}

/// PERCENTILE.EXC: position k*(n+1) counted from 1, which must fall within 1..n.
fn exclusive(xs: &[f64], k: f64) -> XlResult<f64> {
    let rank = k * (xs.len() + 1) as f64;
    if xs.is_empty() || rank < 1.0 || rank > xs.len() as f64 {
        return Err(XlError::Num);
    }
    Ok(interpolate(xs, rank - 1.0))
}

fn percentile_inc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| inclusive(xs, to_number(&v[0], dates)?))
}

fn percentile_exc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| exclusive(xs, to_number(&v[0], dates)?))
}

/// A quartile number, truncated; `#NUM!` outside `allowed`.
fn quart(v: &Value, allowed: std::ops::RangeInclusive<f64>, dates: DateSystem) -> XlResult<f64> {
    let q = to_number(v, dates)?.trunc();
    if allowed.contains(&q) {
        Ok(q / 4.0)
    } else {
        Err(XlError::Num)
    }
}

fn quartile_inc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| inclusive(xs, quart(&v[0], 0.0..=4.0, dates)?))
}

fn quartile_exc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| exclusive(xs, quart(&v[0], 1.0..=3.0, dates)?))
}

// ---- ranks --------------------------------------------------------------------------------

/// How many numbers are below and how many equal to `x`.
fn below_and_equal(xs: &[f64], x: f64) -> (usize, usize) {
    let below = xs.partition_point(|&v| v < x);
    // Searched too, not counted one by one: a million ranks among a million equal numbers
    // counted a million million.
    let equal = xs.partition_point(|&v| v <= x) - below;
    (below, equal)
}

/// The rank of `number` among the data, 1 the largest (or with `order`<>0 the smallest),
/// plus how many tie with it; `#N/A` when it is not there.
fn rank_of(xs: &[f64], v: &[Value], dates: DateSystem) -> XlResult<(f64, f64)> {
    let x = to_number(&v[0], dates)?;
    let ascending = match v.get(1) {
        Some(order) => to_number(order, dates)? != 0.0,
        None => false,
    };
    let (below, equal) = below_and_equal(xs, x);
    if equal == 0 {
        return Err(XlError::NA);
    }
    let before = if ascending { below } else { xs.len() - below - equal };
    Ok(((before + 1) as f64, equal as f64))
}

/// RANK: the number's data is `args[1]`, so the data is read from there.
fn ranked(ctx: &mut Ctx, args: &[Expr], f: fn(f64, f64) -> f64) -> XlResult<Value> {
    let dates = ctx.dates();
    let xs = sorted(ctx, &args[1])?;
    let mut rest = vec![ctx.eval(&args[0])];
    rest.extend(args[2..].iter().map(|a| ctx.eval(a)));
    lift_values(&rest, &|v| rank_of(&xs, v, dates).map(|(rank, ties)| number_result(f(rank, ties))))
}

fn rank_eq(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    ranked(ctx, args, |rank, _| rank)
}

fn rank_avg(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    ranked(ctx, args, |rank, ties| rank + (ties - 1.0) / 2.0)
}

/// PERCENTRANK: where x falls among the data as a fraction, interpolated between the
/// neighbours when it is not one of them, truncated (not rounded) to `significance` digits.
fn percentrank(xs: &[f64], v: &[Value], exclusive: bool, dates: DateSystem) -> XlResult<f64> {
    let x = to_number(&v[0], dates)?;
    let digits = match v.get(1) {
        Some(s) => to_number(s, dates)?.trunc(),
        None => 3.0,
    };
    if xs.is_empty() || digits < 1.0 {
        return Err(XlError::Num);
    }
    if x < xs[0] || x > xs[xs.len() - 1] {
        return Err(XlError::NA);
    }
    let (below, equal) = below_and_equal(xs, x);
    // Position of x counted from 0, fractional between two data points.
    let position = if equal > 0 {
        below as f64
    } else {
        let (lo, hi) = (xs[below - 1], xs[below]);
        (below - 1) as f64 + fraction_between(lo, x, hi)
    };
    let n = xs.len() as f64;
    let fraction = match (exclusive, xs.len()) {
        (true, _) => (position + 1.0) / (n + 1.0),
        (false, 1) => 1.0,
        (false, _) => position / (n - 1.0),
    };
    let scale = 10f64.powi(digits.min(15.0) as i32);
    // Truncated from the value as shown (15 digits), so 0.29 does not become 0.28.
    Ok(round15(fraction * scale).floor() / scale)
}

fn percentrank_inc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| percentrank(xs, v, false, dates))
}

fn percentrank_exc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    over_data(ctx, args, &move |xs, v| percentrank(xs, v, true, dates))
}

// ---- modes --------------------------------------------------------------------------------

/// The most frequent numbers, each once, in order of first appearance; empty when no number
/// appears twice.
fn modes(xs: &[f64]) -> Vec<f64> {
    // Count by bit pattern (0.0 and -0.0 are one number); remember each one's first place.
    let mut counts: HashMap<u64, (usize, usize)> = HashMap::new();
    for (i, &x) in xs.iter().enumerate() {
        counts.entry((x + 0.0).to_bits()).or_insert((0, i)).0 += 1;
    }
    let most = counts.values().map(|&(count, _)| count).max().unwrap_or(0);
    if most < 2 {
        return Vec::new();
    }
    let mut firsts: Vec<usize> = counts.values().filter(|&&(c, _)| c == most).map(|&(_, first)| first).collect();
    firsts.sort_unstable();
    firsts.into_iter().map(|i| xs[i]).collect()
}

fn mode_sngl(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = numbers(ctx, args)?;
    modes(&xs).first().map(|&m| Value::Number(m)).ok_or(XlError::NA)
}

fn mode_mult(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let found = modes(&numbers(ctx, args)?);
    if found.is_empty() {
        return Err(XlError::NA);
    }
    Ok(Value::Array(Rc::new(Array::column(found.into_iter().map(Value::Number).collect()))))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::testing::{err, n};
    use crate::eval::value::{Value, XlError};

    /// A1:A10 = 1..10; B1:B8 = 65, 70, 66, 65, 72, 37, 89, 70; C1:C3 = TRUE, "x", 3.
    fn env() -> MapEnv {
        let mut cells: Vec<(String, Value)> = (1..=10).map(|i| (format!("A{i}"), n(f64::from(i)))).collect();
        for (i, v) in [65.0, 70.0, 66.0, 65.0, 72.0, 37.0, 89.0, 70.0].iter().enumerate() {
            cells.push((format!("B{}", i + 1), n(*v)));
        }
        cells.push(("C1".into(), Value::Bool(true)));
        cells.push(("C2".into(), Value::text("x")));
        cells.push(("C3".into(), n(3.0)));
        let refs: Vec<(&str, Value)> = cells.iter().map(|(c, v)| (c.as_str(), v.clone())).collect();
        MapEnv::with(&refs)
    }

    /// Values by hand from the definitions (Microsoft's documentation of each function).
    #[test]
    fn order_statistics_by_hand() {
        let env = env();
        let cases = [
            ("=SMALL(A1:A10,2)", n(2.0)),
            ("=SMALL(A1:A10,1.5)", n(1.0)),
            ("=LARGE(A1:A10,1.5)", n(9.0)),
            ("=LARGE(B1:B8,2)", n(72.0)),
            ("=SUM(LARGE(A1:A10,{1,2,3}))", n(27.0)),
            ("=SMALL(A1:A10,0)", err(XlError::Num)),
            ("=SMALL(A1:A10,11)", err(XlError::Num)),
            ("=SMALL(C1:C3,1)", n(3.0)),
            ("=SMALL(\"3.4\",1)", n(3.4)),
            ("=SMALL(TRUE,1)", n(1.0)),
            ("=SMALL(\"x\",1)", err(XlError::Value)),
            ("=PERCENTILE.INC(A1:A10,0.4)", n(4.6)),
            ("=PERCENTILE(A1:A10,1)", n(10.0)),
            ("=PERCENTILE.INC(A1:A10,1.1)", err(XlError::Num)),
            ("=PERCENTILE.EXC(A1:A10,0.11)", n(1.21)),
            ("=PERCENTILE.EXC(A1:A10,0.05)", err(XlError::Num)),
            ("=QUARTILE(A1:A10,1)", n(3.25)),
            ("=QUARTILE.INC(A1:A10,2.7)", n(5.5)),
            ("=QUARTILE.EXC(A1:A10,1)", n(2.75)),
            ("=QUARTILE.EXC(A1:A10,4)", err(XlError::Num)),
            ("=RANK(70,B1:B8)", n(3.0)),
            ("=RANK.EQ(70,B1:B8,1)", n(5.0)),
            ("=RANK.AVG(70,B1:B8)", n(3.5)),
            ("=RANK.AVG(65,B1:B8,1)", n(2.5)),
            ("=RANK(71,B1:B8)", err(XlError::NA)),
            ("=PERCENTRANK.INC(A1:A10,7)", n(0.666)),
            ("=PERCENTRANK.INC(A1:A10,5.12,6)", n(0.457777)),
            ("=PERCENTRANK.EXC(A1:A10,9,2)", n(0.81)),
            ("=PERCENTRANK(A1:A10,11)", err(XlError::NA)),
            ("=MODE(B1:B8)", n(65.0)),
            ("=MODE.SNGL(A1:A10)", err(XlError::NA)),
            ("=SUM(MODE.MULT(B1:B8))", n(135.0)),
        ];
        for (formula, want) in cases {
            let got = env.eval(formula);
            let ok = match (&got, &want) {
                (Value::Number(a), Value::Number(b)) => (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                _ => got == want,
            };
            assert!(ok, "{formula}: {got:?}, want {want:?}");
        }
    }
}
