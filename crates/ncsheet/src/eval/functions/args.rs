//! Argument helpers shared by function bodies: Excel's rules for reading arguments live
//! here once, not in every function.

use std::rc::Rc;

use crate::formula::address::Rect;
use crate::formula::ast::{Expr, ExprKind, SheetId};

use crate::eval::coerce::{to_bool, to_number};
use crate::eval::functions::api::{broadcast_whole, number_result, Ctx, Operand};
use crate::eval::value::{too_many_items, too_many_items_note, Array, Value, XlError, XlResult};

/// Where a value came from, which decides how aggregates treat text and booleans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Typed as an argument (`SUM(1,"2",TRUE)` counts all three).
    Direct,
    /// Read from a range or an array (`SUM(A1:A3)` skips text and booleans).
    Collection,
}

/// A scalar argument as a number (arrays give their first item; use [`lift`] to map instead).
pub fn number(ctx: &mut Ctx, e: &Expr) -> XlResult<f64> {
    let dates = ctx.dates();
    let v = ctx.eval(e);
    to_number(&ctx.locale().numbers_for_arithmetic(v, dates), dates)
}

/// Argument `i` when given: `None` when it is omitted or left empty (`ROUND(2.5,)`).
pub fn given(args: &[Expr], i: usize) -> Option<&Expr> {
    args.get(i).filter(|e| e.kind != ExprKind::Missing)
}

/// An optional number argument: `default` when omitted or left empty.
pub fn number_or(ctx: &mut Ctx, args: &[Expr], i: usize, default: f64) -> XlResult<f64> {
    given(args, i).map_or(Ok(default), |e| number(ctx, e))
}

/// The rows and columns of an array a function builds from a size it is given (SEQUENCE,
/// RANDARRAY), already truncated and at least 0: at most a sheet's 1,048,576 rows and 16,384
/// columns (`#VALUE!`, Excel's rule for SEQUENCE), then within the array limit of
/// [`Ctx::room_for`] (`#NUM!`), each with its note, before anything is allocated.
pub fn sheet_sized(ctx: &mut Ctx, function: &str, rows: f64, cols: f64) -> XlResult<(usize, usize)> {
    use crate::formula::address::{MAX_COLS, MAX_ROWS};
    if rows > f64::from(MAX_ROWS) || cols > f64::from(MAX_COLS) {
        let why =
            format!("{function} has more than the {MAX_ROWS} rows or {MAX_COLS} columns of a sheet (Excel's limit)");
        return Err(ctx.explain(XlError::Value, why));
    }
    let (rows, cols) = (rows as usize, cols as usize);
    ctx.room_for(rows, cols)?;
    Ok((rows, cols))
}

pub fn boolean(ctx: &mut Ctx, e: &Expr) -> XlResult<bool> {
    to_bool(&ctx.eval(e))
}

/// An optional boolean argument.
pub fn bool_or(ctx: &mut Ctx, args: &[Expr], i: usize, default: bool) -> XlResult<bool> {
    given(args, i).map_or(Ok(default), |e| boolean(ctx, e))
}

/// Evaluates every argument and calls `f` on the scalars; when any argument is an array
/// (or a multi-cell range) `f` runs item by item with broadcasting and the result is an
/// array — how `SIN(A1:A5)` spills in Excel 365.
pub fn lift(ctx: &mut Ctx, args: &[Expr], f: &dyn Fn(&[Value]) -> XlResult<Value>) -> XlResult<Value> {
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    lift_evaluated(ctx, &values, f)
}

/// [`lift`] of arguments already evaluated: their texts counted against the LAMBDA work
/// budget, `f` lifted over them, a result past the size limit explained.
fn lift_evaluated(ctx: &mut Ctx, values: &[Value], f: &dyn Fn(&[Value]) -> XlResult<Value>) -> XlResult<Value> {
    ctx.charge_texts(values);
    let lifted = lift_values(values, f);
    explain_lifted_size(ctx, values, &lifted);
    lifted
}

/// A number or date argument's value with its text read as the workbook's locale reads it
/// (`"12.03.2025"` is 12 March and `"0,5"` a half in de-DE), as arithmetic on text does;
/// text that is no number there is `#VALUE!`. Under en-US the value is unchanged.
pub fn in_locale(ctx: &Ctx, v: Value) -> Value {
    ctx.locale().numbers_for_arithmetic(v, ctx.dates())
}

/// [`lift`] for functions whose arguments at the positions `numeric` picks are numbers or
/// dates, read [`in_locale`]; the others (a unit, a weekend mask) stay as they are. Every
/// function taking dates reads their text this one way (DATEDIF, WORKDAY, COUPNCD, …).
pub fn lift_in_locale(
    ctx: &mut Ctx,
    args: &[Expr],
    numeric: &dyn Fn(usize) -> bool,
    f: &dyn Fn(&[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    let values: Vec<Value> = args
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let v = ctx.eval(a);
            if numeric(i) {
                in_locale(ctx, v)
            } else {
                v
            }
        })
        .collect();
    lift_evaluated(ctx, &values, f)
}

/// Names the array limit when a lifted call's result would pass it.
pub fn explain_lifted_size(ctx: &mut Ctx, values: &[Value], lifted: &XlResult<Value>) {
    if *lifted == Err(XlError::Num) {
        match lifted_size(values) {
            Some((rows, cols)) if too_many_items(rows, cols) => {
                ctx.explain(XlError::Num, too_many_items_note(rows, cols))
            }
            // The lifting refuses nothing else: its items' texts passed their limit.
            Some(_) => ctx.explain(XlError::Num, crate::eval::value::too_much_text_note()),
            None => XlError::Num,
        };
    }
}

/// The size of the array a lifted call makes: the largest of its array arguments'.
fn lifted_size(values: &[Value]) -> Option<(usize, usize)> {
    values.iter().fold(None, |acc: Option<(usize, usize)>, v| match v {
        Value::Array(a) => Some(acc.map_or((a.rows, a.cols), |(r, c)| (r.max(a.rows), c.max(a.cols)))),
        _ => acc,
    })
}

/// [`lift`] over values already evaluated.
pub fn lift_values(values: &[Value], f: &dyn Fn(&[Value]) -> XlResult<Value>) -> XlResult<Value> {
    let Some((rows, cols)) = lifted_size(values) else {
        return f(values);
    };
    if values.iter().any(|v| matches!(v, Value::Array(a) if a.tail.is_some())) {
        let refs: Vec<&Value> = values.iter().collect();
        // Its only error is its own refusal (too many items or texts), for the caller to explain.
        return match broadcast_whole(&refs, &|v| f(v).unwrap_or_else(Value::Error)) {
            Value::Error(e) => Err(e),
            whole => Ok(whole),
        };
    }
    if too_many_items(rows, cols) {
        return Err(XlError::Num);
    }
    let mut data = Vec::with_capacity(rows * cols);
    let mut scalars = Vec::with_capacity(values.len());
    let mut text = crate::eval::value::TextBudget::default();
    for r in 0..rows {
        for c in 0..cols {
            scalars.clear();
            scalars.extend(values.iter().map(|v| match v {
                Value::Array(a) => a.broadcast_get(r, c),
                other => other.clone(),
            }));
            scalars.iter().for_each(|v| text.read(v));
            let item = f(&scalars).unwrap_or_else(Value::Error);
            if !text.take(&item) {
                return Err(XlError::Num);
            }
            data.push(item);
        }
    }
    Ok(Value::Array(Rc::new(Array::new(rows, cols, data))))
}

/// A one-number function lifted over arrays: `f` gets the argument as a number.
/// The arguments sit in a stack array, not a `Vec`: a scalar call allocates nothing (surface
/// equations call these a million times).
pub fn lift_number1(ctx: &mut Ctx, args: &[Expr], f: fn(f64) -> XlResult<f64>) -> XlResult<Value> {
    let dates = ctx.dates();
    // A number, the usual case, needs no lifting.
    if let Some(x) = ctx.leaf_number(&args[0]) {
        return Ok(number_result(f(x)?));
    }
    let x = ctx.eval(&args[0]);
    if let Value::Number(x) = x {
        return Ok(number_result(f(x)?));
    }
    let x = ctx.locale().numbers_for_arithmetic(x, dates);
    lift_values(&[x], &|v| {
        let x = to_number(&v[0], dates)?;
        Ok(number_result(f(x)?))
    })
}

/// A two-number function lifted over arrays; a missing second argument reads as `default`.
pub fn lift_number2(ctx: &mut Ctx, args: &[Expr], default: f64, f: fn(f64, f64) -> XlResult<f64>) -> XlResult<Value> {
    let dates = ctx.dates();
    let missing_second = args.get(1).is_none_or(|e| e.kind == ExprKind::Missing);
    let values = [ctx.eval(&args[0]), args.get(1).map_or(Value::Blank, |e| ctx.eval(e))];
    // Numbers, the usual case, need no lifting.
    match values {
        [Value::Number(x), _] if missing_second => return Ok(number_result(f(x, default)?)),
        [Value::Number(x), Value::Number(y)] => return Ok(number_result(f(x, y)?)),
        _ => {}
    }
    let values = values.map(|v| ctx.locale().numbers_for_arithmetic(v, dates));
    let values = &values[..args.len().min(2)];
    let lifted = lift_values(values, &|v| {
        let x = to_number(&v[0], dates)?;
        let y = if missing_second { default } else { to_number(&v[1], dates)? };
        Ok(number_result(f(x, y)?))
    });
    explain_lifted_size(ctx, values, &lifted);
    lifted
}

/// Visits every value the arguments hold, in order: a range's non-blank cells, an array's
/// items, or the argument's own value. Stops at the first `Err` from `f`.
pub fn for_each_value(ctx: &mut Ctx, args: &[Expr], f: &mut dyn FnMut(&Value, Source) -> XlResult<()>) -> XlResult<()> {
    for a in args {
        if a.kind == ExprKind::Missing {
            continue;
        }
        // Each argument is visited and let go: the next one does not count it as held.
        let mark = ctx.held_mark();
        let operand = ctx.operand(a);
        for_each_value_of(ctx, operand, f)?;
        ctx.release_to(mark, &Value::Blank);
    }
    Ok(())
}

/// [`for_each_value`] of one argument's operand.
fn for_each_value_of(
    ctx: &mut Ctx,
    operand: Operand,
    f: &mut dyn FnMut(&Value, Source) -> XlResult<()>,
) -> XlResult<()> {
    match operand {
        Operand::Ref(sheet, rect) => for_each_cell_value(ctx, sheet, rect, f)?,
        // `SUM((A1:A3,C1))`: each area in turn, as Excel reads a multi-area reference.
        Operand::Areas(areas) => {
            for &(sheet, rect) in areas.iter() {
                for_each_cell_value(ctx, sheet, rect, f)?;
            }
        }
        Operand::Value(Value::Array(arr)) => {
            // `SUM(a)` of an array bound outside MAP's LAMBDA reads it whole at every call.
            let (rows, cols) = arr.whole_size();
            ctx.charge(rows.saturating_mul(cols));
            for v in &arr.data {
                f(v, Source::Collection)?;
            }
            // The items of a whole row or column beyond those stored (`COUNT(1:1*2)`):
            // one by one, so past the array limit (`SUM(B:XFD*1)`, 17 billion) #NUM!.
            if let Some(tail) = &arr.tail {
                if too_many_items(tail.rows, tail.cols) {
                    return Err(ctx.explain(XlError::Num, too_many_items_note(tail.rows, tail.cols)));
                }
                for _ in 0..tail.rows * tail.cols - arr.rows * arr.cols {
                    f(&tail.fill, Source::Collection)?;
                }
            }
        }
        Operand::Value(v) => f(&v, Source::Direct)?,
    }
    Ok(())
}

/// [`for_each_value`] over one range's non-blank cells.
fn for_each_cell_value(
    ctx: &mut Ctx,
    sheet: SheetId,
    rect: Rect,
    f: &mut dyn FnMut(&Value, Source) -> XlResult<()>,
) -> XlResult<()> {
    let rect = ctx.clip_to_used(sheet, rect);
    let mut outcome = Ok(());
    let mut visited = 0;
    ctx.env.for_each_value(sheet, rect, &mut |_, v| {
        visited += 1;
        if outcome.is_ok() {
            outcome = f(v, Source::Collection);
        }
    });
    // `SUM(A:A)` inside MAP's LAMBDA reads the column once per item.
    ctx.charge(visited);
    outcome
}

/// Visits the numbers of the arguments as SUM, AVERAGE, MIN, MAX read them: numbers
/// anywhere; typed text and booleans coerced; text, booleans and blanks in ranges and
/// arrays skipped; any error stops with that error.
pub fn for_each_number(ctx: &mut Ctx, args: &[Expr], f: &mut dyn FnMut(f64)) -> XlResult<()> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    for a in args {
        if a.kind == ExprKind::Missing {
            continue;
        }
        // Each argument is summed and let go: the next one does not count it as held.
        let mark = ctx.held_mark();
        match ctx.operand(a) {
            // A range, what aggregates read most: its numbers straight from the cells.
            Operand::Ref(sheet, rect) => {
                let rect = ctx.clip_to_used(sheet, rect);
                // Counted as `for_each_cell_value` counts a range (MAP's LAMBDA reading `SUM(A:A)`).
                ctx.charge(rect.rows() as usize * rect.cols() as usize);
                ctx.env.for_each_number_in(sheet, rect, f)?;
            }
            operand => for_each_value_of(ctx, operand, &mut |v, source| {
                match (v, source) {
                    (Value::Number(n), _) => f(*n),
                    (Value::Error(e), _) => return Err(*e),
                    (_, Source::Collection) => {}
                    (Value::Blank, Source::Direct) => {}
                    (Value::Text(_), Source::Direct) => {
                        f(to_number(&locale.numbers_for_arithmetic(v.clone(), dates), dates)?)
                    }
                    (other, Source::Direct) => f(to_number(other, dates)?),
                }
                Ok(())
            })?,
        }
        ctx.release_to(mark, &Value::Blank);
    }
    Ok(())
}

/// The numbers of the arguments, collected.
pub fn numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let mut out = Vec::new();
    for_each_number(ctx, args, &mut |n| out.push(n))?;
    Ok(out)
}

/// The values of the arguments as the functions ending in A (AVERAGEA, MINA, VARA, STDEVA…)
/// read them: as [`numbers`], except that in ranges and arrays TRUE is 1, FALSE and text
/// (even "") are 0. Blank cells are still skipped.
pub fn numbers_a(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    let dates = ctx.dates();
    let mut out = Vec::new();
    for_each_value(ctx, args, &mut |v, source| {
        match (v, source) {
            (Value::Number(n), _) => out.push(*n),
            (Value::Error(e), _) => return Err(*e),
            (Value::Lambda(_), _) => return Err(XlError::Calc),
            (Value::Null, _) => return Err(XlError::Value),
            (Value::Bool(b), _) => out.push(f64::from(u8::from(*b))),
            (Value::Text(_), Source::Collection) => out.push(0.0),
            (Value::Blank, _) | (Value::Array(_), Source::Collection) => {}
            (other, Source::Direct) => out.push(to_number(other, dates)?),
        }
        Ok(())
    })?;
    Ok(out)
}

/// An argument read as a 2-D block of values: a range (all cells, blanks included) or an
/// array; a scalar is a 1×1 block.
pub fn block(ctx: &mut Ctx, e: &Expr) -> XlResult<Rc<Array>> {
    as_block(ctx.eval(e))
}

/// A value as [`block`] reads it. An array of no items (VBA's `Array()` or `Split("")`) is
/// `#CALC!`, Excel's error for an empty array: the functions reading blocks take their
/// first row and column as given, and CHOOSEROWS, SORTBY, VLOOKUP and LOOKUP panicked.
pub fn as_block(v: Value) -> XlResult<Rc<Array>> {
    match v {
        Value::Array(a) if a.rows == 0 || a.cols == 0 => Err(XlError::Calc),
        Value::Array(a) => Ok(a),
        Value::Error(err) => Err(err),
        v => Ok(Rc::new(Array::new(1, 1, vec![v]))),
    }
}

/// `#VALUE!` unless `ok`: for argument checks that read as sentences.
pub fn require(ok: bool) -> XlResult<()> {
    if ok {
        Ok(())
    } else {
        Err(XlError::Value)
    }
}
