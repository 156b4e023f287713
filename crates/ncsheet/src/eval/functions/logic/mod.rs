//! Logical functions. IF and friends evaluate only the branch they return, as Excel does;
//! an array condition makes them choose item by item (Excel 365 spills the result).

use crate::eval::coerce::{to_bool, to_number, values_equal};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{
    broadcast2, for_each_value, lift, lift_values, ArgSet, Ctx, FnSpec, Operand, Source, MANY,
};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::reference(
        "IF",
        2,
        3,
        if_fn,
        "IF(condition, then, [else])",
        "then when condition is TRUE, else otherwise (FALSE when omitted)",
    )
    .biff(1),
    FnSpec::value(
        "IFS",
        2,
        MANY,
        ifs,
        "IFS(condition1, value1, [condition2, value2], …)",
        "The value of the first TRUE condition; #N/A when none is",
    )
    .future(),
    FnSpec::value(
        "IFERROR",
        2,
        2,
        iferror,
        "IFERROR(value, value_if_error)",
        "value, or value_if_error when value is any error",
    )
    .biff(480),
    FnSpec::value("IFNA", 2, 2, ifna, "IFNA(value, value_if_na)", "value, or value_if_na when value is #N/A").future(),
    FnSpec::value(
        "AND",
        1,
        MANY,
        and,
        "AND(logical1, …)",
        "TRUE when every argument is TRUE; text and blanks in ranges are skipped",
    )
    .biff(36)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "OR",
        1,
        MANY,
        or,
        "OR(logical1, …)",
        "TRUE when any argument is TRUE; text and blanks in ranges are skipped",
    )
    .biff(37)
    .range_args(ArgSet::ALL),
    FnSpec::value("XOR", 1, MANY, xor, "XOR(logical1, …)", "TRUE when an odd number of arguments are TRUE")
        .future()
        .range_args(ArgSet::ALL),
    FnSpec::value("NOT", 1, 1, not, "NOT(logical)", "Reverses TRUE and FALSE").biff(38),
    FnSpec::value(
        "SWITCH",
        3,
        MANY,
        switch,
        "SWITCH(expression, value1, result1, …, [default])",
        "The result paired with the first value equal to expression; default or #N/A otherwise",
    )
    .future()
    .dynamic(),
    FnSpec::reference(
        "CHOOSE",
        2,
        MANY,
        choose,
        "CHOOSE(index, value1, value2, …)",
        "The index-th value (1-based); references stay references",
    )
    .biff(100),
    FnSpec::value("TRUE", 0, 0, true_fn, "TRUE()", "The logical value TRUE").biff(34),
    FnSpec::value("FALSE", 0, 0, false_fn, "FALSE()", "The logical value FALSE").biff(35),
];

/// IF returns the chosen branch as a reference when it is one (`SUM(A1:IF(x, B5, B9))`).
fn if_fn(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    let condition = ctx.eval(&args[0]);
    if let Value::Array(_) = condition {
        // An array condition chooses item by item; both branches are evaluated once and
        // broadcast against it.
        let values = [condition, branch(ctx, args, 1), branch(ctx, args, 2)];
        let chosen = lift_values(&values, &|v| Ok(if to_bool(&v[0])? { v[1].clone() } else { v[2].clone() }));
        return Operand::Value(chosen.unwrap_or_else(Value::Error));
    }
    match to_bool(&condition) {
        Ok(true) => branch_operand(ctx, args, 1),
        Ok(false) => branch_operand(ctx, args, 2),
        Err(e) => Operand::Value(Value::Error(e)),
    }
}

/// An IF branch: an omitted else is FALSE, an empty one (`IF(c, 1, )`) is 0.
fn branch(ctx: &mut Ctx, args: &[Expr], i: usize) -> Value {
    let operand = branch_operand(ctx, args, i);
    ctx.deref(operand)
}

fn branch_operand(ctx: &mut Ctx, args: &[Expr], i: usize) -> Operand {
    match args.get(i) {
        None => Operand::Value(Value::Bool(false)),
        Some(e) if e.kind == ExprKind::Missing => Operand::Value(Value::Number(0.0)),
        Some(e) => ctx.operand(e),
    }
}

fn ifs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    if !args.len().is_multiple_of(2) {
        return Err(XlError::Value);
    }
    for (k, pair) in args.chunks(2).enumerate() {
        let condition = ctx.eval(&pair[0]);
        if let Value::Array(_) = condition {
            return ifs_by_item(ctx, condition, &args[2 * k..]);
        }
        if to_bool(&condition)? {
            return Ok(ctx.eval(&pair[1]));
        }
    }
    Err(XlError::NA)
}

/// IFS from the first array condition on: every remaining pair is evaluated and the
/// choice is made item by item.
fn ifs_by_item(ctx: &mut Ctx, first: Value, pairs: &[Expr]) -> XlResult<Value> {
    let mut values = vec![first];
    values.extend(pairs[1..].iter().map(|e| ctx.eval(e)));
    lift_values(&values, &|v| {
        for pair in v.chunks(2) {
            if to_bool(&pair[0])? {
                return Ok(pair[1].clone());
            }
        }
        Err(XlError::NA)
    })
}

fn iferror(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    if_error_matching(ctx, args, |_| true)
}

fn ifna(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    if_error_matching(ctx, args, |e| e == XlError::NA)
}

/// IFERROR/IFNA: a scalar error gives the whole fallback (which may be an array); an
/// array value is checked item by item against the broadcast fallback.
fn if_error_matching(ctx: &mut Ctx, args: &[Expr], catches: fn(XlError) -> bool) -> XlResult<Value> {
    let value = ctx.eval(&args[0]);
    match value {
        Value::Error(e) if catches(e) => Ok(fallback(ctx, &args[1])),
        Value::Array(ref a) if a.data.iter().any(|v| v.as_error().is_some_and(catches)) => {
            let other = fallback(ctx, &args[1]);
            Ok(broadcast2(&value, &other, &|v, f| match v {
                Value::Error(e) if catches(*e) => f.clone(),
                _ => v.clone(),
            }))
        }
        v => Ok(v),
    }
}

/// An empty fallback argument (`IFERROR(x,)`) is 0, as Excel shows it.
fn fallback(ctx: &mut Ctx, e: &Expr) -> Value {
    match e.kind {
        ExprKind::Missing => Value::Number(0.0),
        _ => ctx.eval(e),
    }
}

fn and(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let flags = logicals(ctx, args)?;
    Ok(Value::Bool(flags.iter().all(|&b| b)))
}

fn or(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let flags = logicals(ctx, args)?;
    Ok(Value::Bool(flags.iter().any(|&b| b)))
}

fn xor(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let flags = logicals(ctx, args)?;
    Ok(Value::Bool(flags.iter().filter(|&&b| b).count() % 2 == 1))
}

/// The truth values AND, OR and XOR combine. Ranges and arrays give their numbers and
/// booleans (text and blanks skipped); typed text counts as "TRUE" or "FALSE", the empty
/// text is skipped (Excel: `OR("", TRUE)` is TRUE) and any other is `#VALUE!` (`AND("1",1)`).
/// No value at all is `#VALUE!`; any error wins, over bad text too (`AND("x",NA())` is #N/A).
/// An argument left empty (`AND(,TRUE)`) and an empty value a function gave (a VLOOKUP that
/// finds an empty cell) are FALSE, as Excel computes them (BooleanFunctionsTestCaseData.xls);
/// only empty cells of a reference are skipped.
fn logicals(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<bool>> {
    let mut flags: Vec<bool> = args.iter().filter(|a| a.kind == ExprKind::Missing).map(|_| false).collect();
    let mut bad_text = false;
    for_each_value(ctx, args, &mut |v, source| {
        match (v, source) {
            (Value::Error(e), _) => return Err(*e),
            (Value::Bool(b), _) => flags.push(*b),
            (Value::Number(n), _) => flags.push(*n != 0.0),
            (Value::Blank, Source::Direct) => flags.push(false),
            (Value::Text(s), Source::Direct) if !s.is_empty() => match to_bool(&Value::Text(s.clone())) {
                Ok(b) => flags.push(b),
                Err(_) => bad_text = true,
            },
            _ => {}
        }
        Ok(())
    })?;
    if bad_text || flags.is_empty() {
        Err(XlError::Value)
    } else {
        Ok(flags)
    }
}

fn not(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::Bool(!to_bool(&v[0])?)))
}

fn switch(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let subject = ctx.eval(&args[0]);
    if let Value::Error(e) = subject {
        return Err(e);
    }
    let cases = &args[1..];
    for pair in cases.chunks_exact(2) {
        let candidate = ctx.eval(&pair[0]);
        if let Value::Error(e) = candidate {
            return Err(e);
        }
        if same_kind(&subject, &candidate) && values_equal(&subject, &candidate)? {
            return Ok(ctx.eval(&pair[1]));
        }
    }
    match cases.len() % 2 {
        1 => Ok(ctx.eval(&cases[cases.len() - 1])),
        _ => Err(XlError::NA),
    }
}

/// SWITCH matches like `=` but never across kinds (1 does not match "1"); a blank
/// subject matches what a blank compares equal to.
fn same_kind(a: &Value, b: &Value) -> bool {
    use Value::*;
    matches!((a, b), (Number(_), Number(_)) | (Text(_), Text(_)) | (Bool(_), Bool(_)) | (Blank, _) | (_, Blank))
}

/// CHOOSE keeps a chosen reference a reference (`SUM(A1:CHOOSE(2, B1, B2))`); an array
/// index chooses item by item.
fn choose(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    let dates = ctx.dates();
    let index = ctx.eval(&args[0]);
    let choices = &args[1..];
    if let Value::Array(_) = index {
        let mut values = vec![index];
        values.extend(choices.iter().map(|e| ctx.eval(e)));
        let chosen = lift_values(&values, &|v| {
            let i = choice_index(&v[0], v.len() - 1, dates)?;
            Ok(v[i].clone())
        });
        return Operand::Value(chosen.unwrap_or_else(Value::Error));
    }
    match choice_index(&index, choices.len(), dates) {
        Ok(i) => match &choices[i - 1].kind {
            ExprKind::Missing => Operand::Value(Value::Number(0.0)),
            _ => ctx.operand(&choices[i - 1]),
        },
        Err(e) => Operand::Value(Value::Error(e)),
    }
}

/// A 1-based index into `count` choices, truncated as Excel does (1.9 picks the first).
fn choice_index(index: &Value, count: usize, dates: DateSystem) -> XlResult<usize> {
    let i = to_number(index, dates)?.trunc();
    if i < 1.0 || i > count as f64 {
        return Err(XlError::Value);
    }
    Ok(i as usize)
}

fn true_fn(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(true))
}

fn false_fn(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(false))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::n;
    use crate::eval::testing::MapEnv;
    use crate::eval::{Array, Value, XlError};

    fn env() -> MapEnv {
        MapEnv::with(&[
            ("A1", n(1.0)),
            ("A2", n(5.0)),
            ("A3", Value::text("x")),
            ("B1", n(10.0)),
            ("B2", n(20.0)),
            ("B3", n(30.0)),
        ])
    }

    /// Excel's cached values in BooleanFunctionsTestCaseData.xls (Apache POI's test data,
    /// sheet Tests, rows 19-32): an empty argument and an empty value from a function are
    /// FALSE; empty cells of a reference are skipped, and nothing else left is #VALUE!.
    #[test]
    fn and_or_read_an_empty_argument_and_a_functions_empty_value_as_false() {
        let env = env();
        assert_eq!(env.eval("=AND(,TRUE)"), Value::Bool(false));
        assert_eq!(env.eval("=AND(C9,)"), Value::Bool(false));
        assert_eq!(env.eval("=OR(C9,)"), Value::Bool(false));
        assert_eq!(env.eval("=OR(,TRUE)"), Value::Bool(true));
        assert_eq!(env.eval("=AND(TRUE,VLOOKUP(1,A1:C1,3,FALSE))"), Value::Bool(false));
        assert_eq!(env.eval("=AND(C9)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=AND(TRUE,C9)"), Value::Bool(true));
    }

    #[test]
    fn if_chooses_and_broadcasts() {
        let env = env();
        assert_eq!(env.eval("=IF(A1>0,\"pos\",\"neg\")"), Value::text("pos"));
        assert_eq!(env.eval("=IF(FALSE,1)"), Value::Bool(false));
        assert_eq!(env.eval("=IF(FALSE,1,)"), n(0.0));
        // Only the chosen branch is evaluated: the error in the other one does not leak.
        assert_eq!(env.eval("=IF(TRUE,1,1/0)"), n(1.0));
        assert_eq!(env.eval("=SUM(B1:IF(TRUE,B3,B2))"), n(60.0));
        // Excel 365: =IF({TRUE,FALSE},{1,2,3},{10,11,12}) spills 1, 11, #N/A.
        assert_eq!(
            env.eval("=IF({TRUE,FALSE},{1,2,3},{10,11,12})"),
            Value::from(Array::row(vec![n(1.0), n(11.0), Value::Error(XlError::NA)]))
        );
    }

    #[test]
    fn ifs_switch_and_choose() {
        let env = env();
        assert_eq!(env.eval("=IFS(A1=2,\"a\",A1=1,\"b\")"), Value::text("b"));
        assert_eq!(env.eval("=IFS(FALSE,1)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=SWITCH(2,1,\"a\",2,\"b\",\"z\")"), Value::text("b"));
        assert_eq!(env.eval("=SWITCH(9,1,\"a\",\"z\")"), Value::text("z"));
        assert_eq!(env.eval("=SWITCH(9,1,\"a\")"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=SWITCH(\"1\",1,\"a\",\"z\")"), Value::text("z"));
        assert_eq!(env.eval("=CHOOSE(2,\"a\",\"b\")"), Value::text("b"));
        assert_eq!(env.eval("=CHOOSE(1.9,\"a\",\"b\")"), Value::text("a"));
        assert_eq!(env.eval("=CHOOSE(3,\"a\",\"b\")"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=SUM(CHOOSE(2,B1:B2,B1:B3))"), n(60.0));
    }

    #[test]
    fn iferror_and_ifna() {
        let env = env();
        assert_eq!(env.eval("=IFERROR(1/0,\"x\")"), Value::text("x"));
        assert_eq!(env.eval("=IFERROR(3,1/0)"), n(3.0));
        assert_eq!(env.eval("=IFNA(1/0,\"x\")"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=IFNA(NA(),\"x\")"), Value::text("x"));
        assert_eq!(env.eval("=IFERROR({1;0}/{0;1},{7;8})"), Value::from(Array::column(vec![n(7.0), n(0.0)])));
    }

    #[test]
    fn and_or_xor_not() {
        let env = env();
        assert_eq!(env.eval("=AND(TRUE,1)"), Value::Bool(true));
        assert_eq!(env.eval("=AND(TRUE,0)"), Value::Bool(false));
        assert_eq!(env.eval("=OR(\"\",TRUE)"), Value::Bool(true));
        assert_eq!(env.eval("=OR(\"\")"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=OR(\"true\")"), Value::Bool(true));
        // Text in a range is skipped; an empty range alone has no logical value.
        assert_eq!(env.eval("=AND(A1:A3)"), Value::Bool(true));
        assert_eq!(env.eval("=AND(C1:C3)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=XOR(TRUE,TRUE,TRUE)"), Value::Bool(true));
        assert_eq!(env.eval("=NOT(0)"), Value::Bool(true));
        assert_eq!(env.eval("=OR(1/0,TRUE)"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=TRUE()"), Value::Bool(true));
        assert_eq!(env.eval("=FALSE()"), Value::Bool(false));
    }
}
