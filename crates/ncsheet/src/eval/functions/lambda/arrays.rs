//! The functions that run a LAMBDA over arrays: MAP, REDUCE, SCAN, BYROW, BYCOL and
//! MAKEARRAY. The LAMBDA is written in the call or is a defined name holding one; its body is
//! evaluated by the one evaluator with its parameters bound as LET binds names.

use std::rc::Rc;

use crate::eval::functions::api::{block, number, Ctx, FnSpec, MANY};
use crate::eval::value::{too_much_text_note, Array, Closure, TextBudget, Value, XlError, XlResult};
use crate::eval::CallFrame;
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "BYCOL",
        2,
        2,
        bycol,
        "BYCOL(array, lambda)",
        "A LAMBDA of one column applied to each column: a row of results",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "BYROW",
        2,
        2,
        byrow,
        "BYROW(array, lambda)",
        "A LAMBDA of one row applied to each row: a column of results",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "MAKEARRAY",
        3,
        3,
        makearray,
        "MAKEARRAY(rows, columns, lambda)",
        "An array whose items are LAMBDA(row, column)",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "MAP",
        2,
        MANY,
        map,
        "MAP(array1, [array2], ..., lambda)",
        "A LAMBDA applied item by item to one or more arrays",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "REDUCE",
        2,
        3,
        reduce,
        "REDUCE([initial_value], array, lambda)",
        "An accumulator carried through the array by LAMBDA(accumulator, value)",
    )
    .future(),
    FnSpec::value(
        "SCAN",
        2,
        3,
        scan,
        "SCAN([initial_value], array, lambda)",
        "Every intermediate accumulator of REDUCE, as an array",
    )
    .future()
    .dynamic(),
];

/// The LAMBDA a loop of MAP, REDUCE, … calls, with the list of names its calls share.
struct Caller {
    closure: Rc<Closure>,
    frame: CallFrame,
}

/// Runs `f` with the LAMBDA that `e` gives (written in place, a LET name or parameter, a
/// defined name, a function choosing one); `#VALUE!` when it gives anything else.
fn with_lambda<T>(ctx: &mut Ctx, e: &Expr, f: impl FnOnce(&mut Ctx, &mut Caller) -> XlResult<T>) -> XlResult<T> {
    match ctx.eval(e) {
        Value::Lambda(closure) => f(ctx, &mut Caller { closure, frame: CallFrame::default() }),
        Value::Error(XlError::Name) => Err(XlError::Name),
        _ => Err(XlError::Value),
    }
}

/// The LAMBDA's body with its parameters bound to `values`; `#NUM!` (the whole call's) once
/// the LAMBDAs of one formula have done ncsheet's limit of work (`MAX_LAMBDA_WORK`).
fn apply(ctx: &mut Ctx, lambda: &mut Caller, values: &[Value]) -> XlResult<Value> {
    ctx.apply_closure(&lambda.closure, values, &mut lambda.frame)
}

/// `#NUM!` with the budget's note before the first call when `work` (the calls, at one item
/// of work each, and what they are given) is already more than is left of the LAMBDAs'
/// budget, inside another LAMBDA of MAP, REDUCE, …: a nested MAP of a million items stops
/// at once, not after its calls have run up to the budget.
fn within_calls(ctx: &mut Ctx, work: usize) -> XlResult<()> {
    ctx.within_lambda_budget(work)
}

/// A LAMBDA's result as one item of the result array of `name` (MAP, SCAN, BYROW…): a blank
/// reads as 0, and an array is `#CALC!`, as in Excel ("anything but a single value return
/// from the LAMBDA function returns a #CALC error", Microsoft's BYROW function page), the
/// note saying why.
fn as_item(ctx: &mut Ctx, v: Value, name: &str) -> Value {
    match v.unwrap_single() {
        Value::Array(_) => Value::Error(ctx.explain_once(XlError::Calc, nested_array_note(name))),
        Value::Blank => Value::Number(0.0),
        v => v,
    }
}

/// The note of `#CALC!` for a LAMBDA of `name` that returned an array.
fn nested_array_note(name: &str) -> String {
    format!(
        "the LAMBDA of {name} returned an array where each call must return one value: the items of \
         {name}'s result cannot be arrays (Excel's #CALC!; wrap the LAMBDA's result in INDEX, SUM or \
         TEXTJOIN to make it one value)"
    )
}

/// The LAMBDA called with `values`, its result made one item of `name`'s result
/// ([`as_item`]): an array it returned is let go at once, not counted as held by the
/// calls after it (100,000 rows each returning 1,000 items passed the limit on items held
/// at once, where Excel's answer is `#CALC!`).
fn item_of(ctx: &mut Ctx, lambda: &mut Caller, values: &[Value], name: &str) -> XlResult<Value> {
    let mark = ctx.held_mark();
    let out = apply(ctx, lambda, values)?;
    let item = as_item(ctx, out, name);
    ctx.release_to(mark, &item);
    Ok(item)
}

/// Adds a LAMBDA's result to the array being made, its text counted against the limit every
/// array a formula makes has (`MAP(SEQUENCE(200000),LAMBDA(x,REPT("q",32767)))` asked for
/// 6.5 GB): `#NUM!` with the limit's note past it.
fn push_item(ctx: &mut Ctx, data: &mut Vec<Value>, text: &mut TextBudget, item: Value) -> XlResult<()> {
    if !text.take(&item) {
        return Err(ctx.explain(XlError::Num, too_much_text_note()));
    }
    data.push(item);
    Ok(())
}

fn array(rows: usize, cols: usize, data: Vec<Value>) -> Value {
    Value::Array(Rc::new(Array::new(rows, cols, data)))
}

fn map(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (lambda, arrays) = args.split_last().expect("MAP has at least two arguments");
    let blocks: Vec<Rc<Array>> = arrays.iter().map(|e| block(ctx, e)).collect::<XlResult<_>>()?;
    let rows = blocks.iter().map(|b| b.rows).max().unwrap_or(1);
    let cols = blocks.iter().map(|b| b.cols).max().unwrap_or(1);
    // A column and a row broadcast to their product (a million rows by 16,000 columns asked
    // for 512 GB up front): the result's size is checked first, as every array's is.
    ctx.room_for(rows, cols)?;
    within_calls(ctx, rows * cols)?;
    with_lambda(ctx, lambda, |ctx, lambda| {
        let mut data = Vec::with_capacity(rows * cols);
        let mut text = TextBudget::default();
        for r in 0..rows {
            for c in 0..cols {
                let values: Vec<Value> = blocks.iter().map(|b| b.broadcast_get(r, c)).collect();
                let item = item_of(ctx, lambda, &values, "MAP")?;
                push_item(ctx, &mut data, &mut text, item)?;
            }
        }
        Ok(array(rows, cols, data))
    })
}

/// REDUCE's and SCAN's arguments: the initial value (blank when omitted) and the items.
fn accumulation(ctx: &mut Ctx, args: &[Expr]) -> XlResult<(Value, Rc<Array>)> {
    let (initial, items) = match args {
        [items, _] => (Value::Blank, items),
        [init, items, _] => (if init.kind == ExprKind::Missing { Value::Blank } else { ctx.eval(init) }, items),
        _ => unreachable!("REDUCE and SCAN take two or three arguments"),
    };
    Ok((initial.unwrap_single(), block(ctx, items)?))
}

fn reduce(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (mut acc, items) = accumulation(ctx, args)?;
    within_calls(ctx, items.data.len())?;
    with_lambda(ctx, &args[args.len() - 1], |ctx, lambda| {
        // Each step's accumulator replaces the last: only one is held at a time.
        let mark = ctx.held_mark();
        for v in &items.data {
            acc = apply(ctx, lambda, &[acc.clone(), v.clone()])?;
            ctx.release_to(mark, &acc);
        }
        Ok(acc)
    })
}

fn scan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (mut acc, items) = accumulation(ctx, args)?;
    within_calls(ctx, items.data.len())?;
    with_lambda(ctx, &args[args.len() - 1], |ctx, lambda| {
        let mut data = Vec::with_capacity(items.data.len());
        let mut text = TextBudget::default();
        let mark = ctx.held_mark();
        for v in &items.data {
            acc = apply(ctx, lambda, &[acc.clone(), v.clone()])?;
            ctx.release_to(mark, &acc);
            let item = as_item(ctx, acc.clone(), "SCAN");
            push_item(ctx, &mut data, &mut text, item)?;
        }
        Ok(array(items.rows, items.cols, data))
    })
}

fn by_line(ctx: &mut Ctx, args: &[Expr], rows: bool) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let (lines, line_len) = if rows { (a.rows, a.cols) } else { (a.cols, a.rows) };
    // Each call gets its line as a copy: the calls and the copies are known before the first.
    within_calls(ctx, lines.saturating_mul(line_len.saturating_add(1)))?;
    with_lambda(ctx, &args[1], |ctx, lambda| {
        let mut data = Vec::with_capacity(lines);
        let mut text = TextBudget::default();
        for i in 0..lines {
            ctx.charge(line_len);
            let line = if rows {
                Array::row((0..a.cols).map(|c| a.get(i, c).clone()).collect())
            } else {
                Array::column((0..a.rows).map(|r| a.get(r, i).clone()).collect())
            };
            let name = if rows { "BYROW" } else { "BYCOL" };
            let item = item_of(ctx, lambda, &[Value::Array(Rc::new(line))], name)?;
            push_item(ctx, &mut data, &mut text, item)?;
        }
        Ok(if rows { array(lines, 1, data) } else { array(1, lines, data) })
    })
}

fn byrow(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    by_line(ctx, args, true)
}

fn bycol(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    by_line(ctx, args, false)
}

fn makearray(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rows = number(ctx, &args[0])?.trunc();
    let cols = number(ctx, &args[1])?.trunc();
    if rows < 1.0 || cols < 1.0 {
        return Err(XlError::Value);
    }
    // Past 2^24 items it is #NUM! with the limit's note, as every array (docs/limits.md).
    let (rows, cols) = (rows.min(1e15) as usize, cols.min(1e15) as usize);
    ctx.room_for(rows, cols)?;
    within_calls(ctx, rows * cols)?;
    with_lambda(ctx, &args[2], |ctx, lambda| {
        let mut data = Vec::with_capacity(rows * cols);
        let mut text = TextBudget::default();
        for r in 0..rows {
            for c in 0..cols {
                let at = [Value::Number((r + 1) as f64), Value::Number((c + 1) as f64)];
                let item = item_of(ctx, lambda, &at, "MAKEARRAY")?;
                push_item(ctx, &mut data, &mut text, item)?;
            }
        }
        Ok(array(rows, cols, data))
    })
}
