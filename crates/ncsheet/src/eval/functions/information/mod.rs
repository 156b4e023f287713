//! Information functions: what kind of value an argument is. They never coerce, so a
//! reference to an empty cell is blank while the text "" is not.

use crate::eval::functions::api::{lift, ArgSet, Ctx, FnSpec, Operand};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("ISNUMBER", 1, 1, isnumber, "ISNUMBER(value)", "TRUE for a number").biff(128),
    FnSpec::value("ISTEXT", 1, 1, istext, "ISTEXT(value)", "TRUE for text").biff(127),
    FnSpec::value("ISNONTEXT", 1, 1, isnontext, "ISNONTEXT(value)", "TRUE for anything but text (blank included)")
        .biff(190),
    FnSpec::value("ISBLANK", 1, 1, isblank, "ISBLANK(value)", "TRUE for an empty cell (not for the text \"\")")
        .biff(129),
    FnSpec::value("ISLOGICAL", 1, 1, islogical, "ISLOGICAL(value)", "TRUE for TRUE or FALSE").biff(198),
    FnSpec::value("ISERROR", 1, 1, iserror, "ISERROR(value)", "TRUE for any error").biff(3),
    FnSpec::value("ISERR", 1, 1, iserr, "ISERR(value)", "TRUE for any error but #N/A").biff(126),
    FnSpec::value("ISNA", 1, 1, isna, "ISNA(value)", "TRUE for #N/A").biff(2),
    FnSpec::value("ISREF", 1, 1, isref, "ISREF(value)", "TRUE when the argument is a reference")
        .biff(105)
        .range_args(ArgSet::only(0))
        .position_arg(),
    FnSpec::value("NA", 0, 0, na, "NA()", "The #N/A error").biff(10),
    FnSpec::value(
        "ERROR.TYPE",
        1,
        1,
        error_type,
        "ERROR.TYPE(value)",
        "1 #NULL!, 2 #DIV/0!, 3 #VALUE!, 4 #REF!, 5 #NAME?, 6 #NUM!, 7 #N/A; #N/A for a non-error",
    )
    .biff(261),
    FnSpec::value("N", 1, 1, n, "N(value)", "A number as itself, TRUE as 1, anything else as 0; errors stay").biff(131),
    FnSpec::value("T", 1, 1, t, "T(value)", "Text as itself, anything else as \"\"; errors stay").biff(130),
    FnSpec::value("TYPE", 1, 1, type_fn, "TYPE(value)", "1 number, 2 text, 4 logical, 16 error, 64 array").biff(86),
];

/// A test on one value, lifted over arrays and ranges (`ISBLANK(A1:A3)` spills).
fn is(ctx: &mut Ctx, args: &[Expr], test: fn(&Value) -> bool) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::Bool(test(&v[0]))))
}

fn isnumber(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| matches!(v, Value::Number(_)))
}

fn istext(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| matches!(v, Value::Text(_)))
}

fn isnontext(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| !matches!(v, Value::Text(_)))
}

fn isblank(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, Value::is_blank)
}

fn islogical(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| matches!(v, Value::Bool(_)))
}

fn iserror(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| v.as_error().is_some())
}

fn iserr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| v.as_error().is_some_and(|e| e != XlError::NA))
}

fn isna(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    is(ctx, args, |v| v.as_error() == Some(XlError::NA))
}

fn isref(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(matches!(ctx.reference_only(&args[0]), Operand::Ref(..) | Operand::Areas(_))))
}

fn na(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Err(XlError::NA)
}

fn error_type(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| match v[0] {
        Value::Error(e) => Ok(Value::Number(f64::from(e.type_number()))),
        _ => Err(XlError::NA),
    })
}

fn n(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| match &v[0] {
        Value::Number(x) => Ok(Value::Number(*x)),
        Value::Bool(b) => Ok(Value::Number(f64::from(u8::from(*b)))),
        Value::Error(e) => Err(*e),
        _ => Ok(Value::Number(0.0)),
    })
}

fn t(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| match &v[0] {
        Value::Text(s) => Ok(Value::Text(s.clone())),
        Value::Error(e) => Err(*e),
        _ => Ok(Value::from("")),
    })
}

/// TYPE does not lift: an array or a multi-cell range is 64.
fn type_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let code = match ctx.eval(&args[0]) {
        Value::Number(_) | Value::Blank => 1.0,
        Value::Text(_) => 2.0,
        Value::Bool(_) => 4.0,
        // A LAMBDA read as a value is #CALC!.
        Value::Error(_) | Value::Lambda(_) | Value::Null => 16.0,
        Value::Array(_) => 64.0,
    };
    Ok(Value::Number(code))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::{Array, Value, XlError};

    fn b(v: bool) -> Value {
        Value::Bool(v)
    }

    fn env() -> MapEnv {
        MapEnv::with(&[("A1", Value::Number(1.0)), ("A2", Value::text("")), ("A4", Value::Error(XlError::Div0))])
    }

    #[test]
    fn blank_is_an_empty_cell_only() {
        let env = env();
        assert_eq!(env.eval("=ISBLANK(A3)"), b(true));
        assert_eq!(env.eval("=ISBLANK(A2)"), b(false));
        assert_eq!(env.eval("=ISBLANK(\"\")"), b(false));
        assert_eq!(env.eval("=ISBLANK(A1:A3)"), Value::from(Array::column(vec![b(false), b(false), b(true)])));
        assert_eq!(env.eval("=ISNONTEXT(A3)"), b(true));
    }

    #[test]
    fn kinds_and_errors() {
        let env = env();
        assert_eq!(env.eval("=ISNUMBER(A1)"), b(true));
        assert_eq!(env.eval("=ISNUMBER(\"1\")"), b(false));
        assert_eq!(env.eval("=ISTEXT(A2)"), b(true));
        assert_eq!(env.eval("=ISLOGICAL(1=1)"), b(true));
        assert_eq!(env.eval("=ISERROR(A4)"), b(true));
        assert_eq!(env.eval("=ISERR(NA())"), b(false));
        assert_eq!(env.eval("=ISNA(NA())"), b(true));
        assert_eq!(env.eval("=ERROR.TYPE(A4)"), Value::Number(2.0));
        assert_eq!(env.eval("=ERROR.TYPE(1)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=ISREF(A1:A2)"), b(true));
        assert_eq!(env.eval("=ISREF(1)"), b(false));
    }

    #[test]
    fn n_t_type() {
        let env = env();
        assert_eq!(env.eval("=N(TRUE)"), Value::Number(1.0));
        assert_eq!(env.eval("=N(\"7\")"), Value::Number(0.0));
        assert_eq!(env.eval("=T(A1)"), Value::text(""));
        assert_eq!(env.eval("=T(\"x\")"), Value::text("x"));
        assert_eq!(env.eval("=TYPE(A3)"), Value::Number(1.0));
        assert_eq!(env.eval("=TYPE(\"x\")"), Value::Number(2.0));
        assert_eq!(env.eval("=TYPE(A4)"), Value::Number(16.0));
        assert_eq!(env.eval("=TYPE(A1:A2)"), Value::Number(64.0));
    }
}
