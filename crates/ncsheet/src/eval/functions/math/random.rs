//! Random numbers: RAND, RANDBETWEEN and RANDARRAY, volatile like NOW (a cell calling one is
//! recalculated at every recalculation). They draw from the sequence of the workbook being
//! evaluated (`Env::next_random`, the workbook's `Settings`), which a seed fixes for
//! reproducible runs and tests.

use std::rc::Rc;

use crate::eval::functions::api::{check, given, number_or, scalar, sheet_sized, Ctx, Env, FnSpec, Outside};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("RAND", 0, 0, rand, "RAND()", "A random number 0 <= x < 1 (volatile)")
        .biff(63)
        .volatile()
        .reads(Outside::Chance),
    FnSpec::value(
        "RANDBETWEEN",
        2,
        2,
        randbetween,
        "RANDBETWEEN(bottom, top)",
        "A random whole number from bottom to top (volatile)",
    )
    .volatile()
    .reads(Outside::Chance),
    FnSpec::value(
        "RANDARRAY",
        0,
        5,
        randarray,
        "RANDARRAY([rows], [columns], [min], [max], [whole_number])",
        "An array of random numbers from min (0) to max (1), whole when asked (volatile)",
    )
    .volatile()
    .reads(Outside::Chance)
    .future()
    .dynamic(),
];

/// A whole number from `low` to `high` (both whole, low ≤ high), each equally likely.
fn whole_between(env: &dyn Env, low: f64, high: f64) -> f64 {
    let r = env.next_random();
    let span = high - low + 1.0;
    if span.is_finite() {
        (low + (r * span).floor()).min(high)
    } else {
        // Bounds further apart than a double holds (-1E308 to 1E308): every double that far
        // out is whole, so the point r of the way between them is a whole number too.
        between(low, high, r).floor().clamp(low, high)
    }
}

/// The point `r` (0 ≤ r < 1) of the way from `min` to `max`, also when `max - min` is past
/// a double's range.
fn between(min: f64, max: f64, r: f64) -> f64 {
    let span = max - min;
    if span.is_finite() {
        min + r * span
    } else {
        (min * (1.0 - r) + max * r).clamp(min, max)
    }
}

fn rand(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(ctx.env.next_random()))
}

fn randbetween(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let env = ctx.env;
    scalar(ctx, args, &|a| {
        let (low, high) = (a.num(0)?.ceil(), a.num(1)?.floor());
        check(low <= high, XlError::Num)?;
        Ok(Value::Number(whole_between(env, low, high)))
    })
}

fn randarray(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rows = number_or(ctx, args, 0, 1.0)?.trunc();
    let cols = number_or(ctx, args, 1, 1.0)?.trunc();
    let min = number_or(ctx, args, 2, 0.0)?;
    let max = number_or(ctx, args, 3, 1.0)?;
    let whole = match given(args, 4) {
        Some(e) => crate::eval::coerce::to_bool(&ctx.eval(e).unwrap_single())?,
        None => false,
    };
    check(rows >= 1.0 && cols >= 1.0 && min <= max, XlError::Value)?;
    check(!whole || min.fract() == 0.0 && max.fract() == 0.0, XlError::Value)?;
    let (rows, cols) = sheet_sized(ctx, "RANDARRAY", rows, cols)?;
    let env = ctx.env;
    let draw = || if whole { whole_between(env, min, max) } else { between(min, max, env.next_random()) };
    let data = (0..rows * cols).map(|_| Value::Number(draw())).collect();
    Ok(Value::Array(Rc::new(Array::new(rows, cols, data))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::testing::MapEnv;

    fn numbers(v: &Value) -> Vec<f64> {
        match v {
            Value::Array(a) => a.data.iter().map(|v| if let Value::Number(n) = v { *n } else { f64::NAN }).collect(),
            Value::Number(n) => vec![*n],
            other => panic!("not numbers: {other:?}"),
        }
    }

    #[test]
    fn random_functions_stay_in_their_ranges_and_shapes() {
        let env = MapEnv::default();
        for _ in 0..200 {
            let x = numbers(&env.eval("=RAND()"))[0];
            assert!((0.0..1.0).contains(&x));
            let k = numbers(&env.eval("=RANDBETWEEN(-2.5, 3.5)"))[0];
            assert!(k.fract() == 0.0 && (-2.0..=3.0).contains(&k), "{k}");
        }
        let Value::Array(a) = env.eval_at("=RANDARRAY(3, 2, 5, 10, TRUE)", "A1").unwrap() else { panic!("array") };
        assert_eq!((a.rows, a.cols), (3, 2));
        assert!(numbers(&Value::Array(a)).iter().all(|k| k.fract() == 0.0 && (5.0..=10.0).contains(k)));
        let Value::Array(a) = env.eval_at("=RANDARRAY(4)", "A1").unwrap() else { panic!("array") };
        assert_eq!((a.rows, a.cols), (4, 1));
        // Excel: RANDBETWEEN with bottom > top is #NUM!; RANDARRAY with min > max #VALUE!.
        assert_eq!(env.eval("=RANDBETWEEN(3, 1)"), Value::Error(XlError::Num));
        assert_eq!(env.eval("=RANDARRAY(2, 2, 5, 1)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=RANDARRAY(2, 2, 0.5, 3, TRUE)"), Value::Error(XlError::Value));
    }

    /// Bounds whose distance is past a double's range (issue 30): the draws still spread over
    /// the whole range, where `high - low` overflowed and every draw was the top bound.
    #[test]
    fn bounds_further_apart_than_a_double_still_spread() {
        let env = MapEnv::default();
        let draws: Vec<f64> = (0..200).flat_map(|_| numbers(&env.eval("=RANDBETWEEN(-1E308, 1E308)"))).collect();
        let whole = |k: &f64| k.is_finite() && k.fract() == 0.0 && (-1e308..=1e308).contains(k);
        assert!(draws.iter().all(whole), "{draws:?}");
        assert!(draws.iter().any(|k| *k < -1e307) && draws.iter().any(|k| *k > 1e307), "{draws:?}");
        for whole_numbers in ["FALSE", "TRUE"] {
            let formula = format!("=RANDARRAY(200, 1, -1.7E308, 1.7E308, {whole_numbers})");
            let a = numbers(&env.eval_at(&formula, "A1").unwrap());
            assert!(a.iter().all(|k| k.is_finite() && k.abs() <= 1.7e308), "{a:?}");
            assert!(a.iter().any(|k| *k < -1e307) && a.iter().any(|k| *k > 1e307), "{a:?}");
        }
    }
}
