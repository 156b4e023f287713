//! Reading the arguments of a function lifted over arrays (see [`lift`]): the functions of
//! the engineering, financial and number-text families take scalars item by item.

use std::rc::Rc;

use crate::eval::coerce::{to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{lift, lift_in_locale, Ctx};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

/// One call's scalar arguments, and the workbook's date system that date text among them is
/// read in.
#[derive(Clone, Copy)]
pub struct Scalars<'v>(pub &'v [Value], pub DateSystem);

impl Scalars<'_> {
    /// Whether argument `i` was given (an empty slot `f(1,,2)` counts as given, blank).
    pub fn given(&self, i: usize) -> bool {
        i < self.0.len()
    }

    pub fn value(&self, i: usize) -> &Value {
        self.0.get(i).unwrap_or(&Value::Blank)
    }

    pub fn num(&self, i: usize) -> XlResult<f64> {
        to_number(self.value(i), self.1)
    }

    /// An optional number: `default` when the call stops before it.
    pub fn num_or(&self, i: usize, default: f64) -> XlResult<f64> {
        if self.given(i) {
            self.num(i)
        } else {
            Ok(default)
        }
    }

    pub fn text(&self, i: usize) -> XlResult<Rc<str>> {
        to_text(self.value(i))
    }
}

/// Evaluates the arguments and runs `f` on each set of scalars (item by item over arrays).
pub fn scalar(ctx: &mut Ctx, args: &[Expr], f: &dyn Fn(Scalars) -> XlResult<Value>) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| f(Scalars(v, dates)))
}

/// [`scalar`] for functions whose every argument is a number or a date (the financial
/// ones): text reads as the workbook's locale reads it (`"12.03.2025"` in de-DE), as
/// arithmetic on text does.
pub fn scalar_numbers(ctx: &mut Ctx, args: &[Expr], f: &dyn Fn(Scalars) -> XlResult<Value>) -> XlResult<Value> {
    let dates = ctx.dates();
    lift_in_locale(ctx, args, &|_| true, &|v| f(Scalars(v, dates)))
}

/// A finite number, or #NUM!.
pub fn finite(x: f64) -> XlResult<Value> {
    if x.is_finite() {
        Ok(Value::Number(x))
    } else {
        Err(XlError::Num)
    }
}

/// `Err(error)` unless `ok`.
pub fn check(ok: bool, error: XlError) -> XlResult<()> {
    if ok {
        Ok(())
    } else {
        Err(error)
    }
}

/// The most whole numbers a function steps through one by one (a cumulative sum of
/// probabilities, the periods of a loan): about a second's work.
pub const MAX_STEPS: f64 = 10_000_000.0;

/// How many whole numbers lie from `from` to `to`, both included (`from` whole).
pub fn steps_between(from: f64, to: f64) -> f64 {
    if to >= from {
        (to - from).floor() + 1.0
    } else {
        0.0
    }
}

/// The whole numbers from `from` to `to`, both included (`from` whole), counted with an
/// integer: a float counter `j += 1.0` stops moving past 2^53, where `j + 1 == j`, and its
/// loop never ends (HYPGEOM.DIST, BINOM.DIST.RANGE and CUMIPMT near 1E+16 did so). Callers
/// bound the count first (see [`MAX_STEPS`]).
pub fn whole_numbers(from: f64, to: f64) -> impl Iterator<Item = f64> {
    (0..steps_between(from, to) as u64).map(move |i| from + i as f64)
}
