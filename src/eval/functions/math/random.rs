//! Random numbers: RAND, RANDBETWEEN and RANDARRAY, volatile like NOW (a cell calling one is
//! recalculated at every recalculation). The generator is xorshift64* on this thread, seeded
//! from the clock; [`seed_random`] fixes the sequence for reproducible runs and tests.

use std::cell::Cell;
use std::rc::Rc;

use crate::eval::functions::api::{check, given, number_or, scalar, Ctx, FnSpec, Outside};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("RAND", 0, 0, rand, "RAND()", "A random number 0 <= x < 1 (volatile)")
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

/// The most items RANDARRAY makes (as SEQUENCE).
const MAX_ITEMS: f64 = 16_777_216.0;

thread_local! {
    static STATE: Cell<u64> = const { Cell::new(0) };
}

/// Fixes the random sequence of this thread (0 reseeds from the clock at the next draw).
pub fn seed_random(seed: u64) {
    STATE.with(|s| s.set(seed));
}

/// The next number 0 ≤ x < 1, with 53 random bits.
fn next_unit() -> f64 {
    STATE.with(|s| {
        let mut x = s.get();
        if x == 0 {
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0x9E37_79B9_7F4A_7C15, |d| d.as_nanos() as u64);
            x = nanos | 1;
        }
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        s.set(x);
        (x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    })
}

/// A whole number from `low` to `high` (both whole, low ≤ high), each equally likely.
fn whole_between(low: f64, high: f64) -> f64 {
    (low + (next_unit() * (high - low + 1.0)).floor()).min(high)
}

fn rand(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(next_unit()))
}

fn randbetween(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let (low, high) = (a.num(0)?.ceil(), a.num(1)?.floor());
        check(low <= high, XlError::Num)?;
        Ok(Value::Number(whole_between(low, high)))
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
    if rows * cols > MAX_ITEMS {
        return Err(ctx.explain(XlError::Num, "RANDARRAY is too large"));
    }
    let draw = || if whole { whole_between(min, max) } else { min + next_unit() * (max - min) };
    let data = (0..(rows * cols) as usize).map(|_| Value::Number(draw())).collect();
    Ok(Value::Array(Rc::new(Array::new(rows as usize, cols as usize, data))))
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
        seed_random(12345);
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
}
