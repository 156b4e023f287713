//! Logical functions. IF and friends evaluate only the branch they return, as Excel does.

use crate::eval::coerce::to_bool;
use crate::eval::evaluator::{map_value, Ctx};
use crate::eval::value::{Value, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use super::FnSpec;

pub const FUNCTIONS: &[FnSpec] = &[FnSpec::value(
    "IF",
    2,
    3,
    if_fn,
    "IF(condition, then, [else])",
    "then when condition is TRUE, else otherwise (FALSE when omitted)",
)];

fn if_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let condition = ctx.eval(&args[0]);
    if let Value::Array(_) = condition {
        // An array condition chooses item by item (both branches evaluated once).
        let then = branch(ctx, args, 1);
        let otherwise = branch(ctx, args, 2);
        return Ok(map_value(&condition, &|c| match to_bool(c) {
            Ok(true) => then.clone().unwrap_single(),
            Ok(false) => otherwise.clone().unwrap_single(),
            Err(e) => Value::Error(e),
        }));
    }
    Ok(if to_bool(&condition)? { branch(ctx, args, 1) } else { branch(ctx, args, 2) })
}

/// An IF branch: an omitted else is FALSE, an empty one (`IF(c, 1, )`) is 0.
fn branch(ctx: &mut Ctx, args: &[Expr], i: usize) -> Value {
    match args.get(i) {
        None => Value::Bool(false),
        Some(e) if e.kind == ExprKind::Missing => Value::Number(0.0),
        Some(e) => ctx.eval(e),
    }
}
