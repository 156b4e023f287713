//! Statistical aggregates: MIN, MAX, AVERAGE, COUNT and their conditional forms.

use crate::eval::evaluator::Ctx;
use crate::eval::value::{Value, XlResult};
use crate::formula::ast::Expr;

use super::args::for_each_number;
use super::{FnSpec, MANY};

pub const FUNCTIONS: &[FnSpec] =
    &[FnSpec::value("MAX", 1, MANY, max, "MAX(number1, [number2], ...)", "Largest number; 0 when there is none")];

fn max(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut best: Option<f64> = None;
    for_each_number(ctx, args, &mut |n| best = Some(best.map_or(n, |b| b.max(n))))?;
    Ok(Value::Number(best.unwrap_or(0.0)))
}
