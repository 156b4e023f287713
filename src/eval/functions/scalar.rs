//! Reading the arguments of a function lifted over arrays (see [`lift`]): the functions of
//! the engineering, financial and number-text families take scalars item by item.

use std::rc::Rc;

use crate::eval::coerce::{to_number, to_text};
use crate::eval::functions::api::{lift, Ctx};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

/// One call's scalar arguments.
#[derive(Clone, Copy)]
pub struct Scalars<'v>(pub &'v [Value]);

impl Scalars<'_> {
    /// Whether argument `i` was given (an empty slot `f(1,,2)` counts as given, blank).
    pub fn given(&self, i: usize) -> bool {
        i < self.0.len()
    }

    pub fn value(&self, i: usize) -> &Value {
        self.0.get(i).unwrap_or(&Value::Blank)
    }

    pub fn num(&self, i: usize) -> XlResult<f64> {
        to_number(self.value(i))
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
    lift(ctx, args, &|v| f(Scalars(v)))
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
