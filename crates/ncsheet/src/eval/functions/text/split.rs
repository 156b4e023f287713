//! Text cut at delimiters: TEXTBEFORE, TEXTAFTER and TEXTSPLIT (Excel 365). A delimiter
//! argument may be an array of delimiters, any of which cuts; match mode 1 ignores case.

use std::rc::Rc;

use crate::eval::coerce::{to_bool, to_number, to_text};
use crate::eval::functions::api::{lift_values, number_or, Ctx, FnSpec};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "TEXTAFTER",
        2,
        6,
        textafter,
        "TEXTAFTER(text, delimiter, [instance_num], [match_mode], [match_end], [if_not_found])",
        "The text after the nth delimiter (negative n counts from the end)",
    )
    .future(),
    FnSpec::value(
        "TEXTBEFORE",
        2,
        6,
        textbefore,
        "TEXTBEFORE(text, delimiter, [instance_num], [match_mode], [match_end], [if_not_found])",
        "The text before the nth delimiter (negative n counts from the end)",
    )
    .future(),
    FnSpec::value(
        "TEXTSPLIT",
        2,
        6,
        textsplit,
        "TEXTSPLIT(text, col_delimiter, [row_delimiter], [ignore_empty], [match_mode], [pad_with])",
        "Text split into columns (and rows) at the delimiters",
    )
    .future()
    .dynamic(),
];

fn present(args: &[Expr], i: usize) -> bool {
    args.get(i).is_some_and(|e| e.kind != ExprKind::Missing)
}

/// The delimiters an argument holds (one text, or every item of an array).
fn delimiters(v: &Value) -> XlResult<Vec<Vec<char>>> {
    match v {
        Value::Array(a) => a.data.iter().map(|d| Ok(to_text(d)?.chars().collect())).collect(),
        v => Ok(vec![to_text(v)?.chars().collect()]),
    }
}

fn fold(c: char, ignore_case: bool) -> char {
    if ignore_case {
        c.to_lowercase().next().unwrap_or(c)
    } else {
        c
    }
}

/// The delimiter (longest first) that starts at `at`, as its length.
fn match_at(text: &[char], at: usize, delims: &[Vec<char>], ignore_case: bool) -> Option<usize> {
    delims
        .iter()
        .filter(|d| !d.is_empty() && at + d.len() <= text.len())
        .filter(|d| d.iter().zip(&text[at..]).all(|(a, b)| fold(*a, ignore_case) == fold(*b, ignore_case)))
        .map(Vec::len)
        .max()
}

/// Every match of a delimiter, left to right, not overlapping, as (start, end) in chars.
fn matches(text: &[char], delims: &[Vec<char>], ignore_case: bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        match match_at(text, i, delims, ignore_case) {
            Some(len) => {
                out.push((i, i + len));
                i += len;
            }
            None => i += 1,
        }
    }
    out
}

/// The (start, end) of the delimiter TEXTBEFORE and TEXTAFTER cut at, or `None`.
fn cut(
    text: &[char],
    delims: &[Vec<char>],
    instance: i64,
    ignore_case: bool,
    match_end: bool,
) -> Option<(usize, usize)> {
    if delims.iter().all(Vec::is_empty) {
        // An empty delimiter matches at once: at the start reading forward, the end backward.
        return Some(if instance > 0 { (0, 0) } else { (text.len(), text.len()) });
    }
    let mut found = matches(text, delims, ignore_case);
    if instance > 0 {
        if match_end {
            found.push((text.len(), text.len()));
        }
        found.get(instance as usize - 1).copied()
    } else {
        if match_end {
            found.insert(0, (0, 0));
        }
        let k = instance.unsigned_abs() as usize;
        found.len().checked_sub(k).map(|i| found[i])
    }
}

fn before_or_after(ctx: &mut Ctx, args: &[Expr], before: bool) -> XlResult<Value> {
    let text = ctx.eval(&args[0]);
    let delims = delimiters(&ctx.eval(&args[1]))?;
    // Excel rounds the instance down: -1.2 is the second from the end.
    let instance = number_or(ctx, args, 2, 1.0)?.floor();
    let mode = number_or(ctx, args, 3, 0.0)?.trunc();
    let end = number_or(ctx, args, 4, 0.0)?.trunc();
    if !(mode == 0.0 || mode == 1.0) || !(end == 0.0 || end == 1.0) {
        return Err(XlError::Value);
    }
    let (ignore_case, match_end) = (mode == 1.0, end == 1.0);
    // A blank if_not_found is empty text.
    let not_found = if present(args, 5) { Some(ctx.eval(&args[5]).blank_as_text()) } else { None };
    let instance_given = present(args, 2);
    lift_values(&[text], &|v| {
        let text: Vec<char> = to_text(&v[0])?.chars().collect();
        let too_long = delims.iter().any(|d| !d.is_empty()) && delims.iter().all(|d| d.len() > text.len());
        if instance == 0.0 || instance.abs() > text.len().max(1) as f64 || too_long && instance_given {
            return Err(XlError::Value);
        }
        // Excel's stored results: a delimiter longer than the text is not found (#N/A) when
        // no instance is given, #VALUE! when one is.
        if too_long {
            return not_found.clone().ok_or(XlError::NA);
        }
        match cut(&text, &delims, instance as i64, ignore_case, match_end) {
            Some((start, end)) => {
                let part: String = if before { text[..start].iter().collect() } else { text[end..].iter().collect() };
                Ok(Value::text(part))
            }
            None => not_found.clone().ok_or(XlError::NA),
        }
    })
}

fn textbefore(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    before_or_after(ctx, args, true)
}

fn textafter(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    before_or_after(ctx, args, false)
}

/// `text` cut at every delimiter match.
fn split(text: &[char], delims: &[Vec<char>], ignore_case: bool) -> Vec<String> {
    let mut out = Vec::new();
    let mut start = 0;
    for (s, e) in matches(text, delims, ignore_case) {
        out.push(text[start..s].iter().collect());
        start = e;
    }
    out.push(text[start..].iter().collect());
    out
}

fn textsplit(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let text: Vec<char> = to_text(&ctx.eval(&args[0]).unwrap_single())?.chars().collect();
    let col_delims = if present(args, 1) { delimiters(&ctx.eval(&args[1]))? } else { Vec::new() };
    let row_delims = if present(args, 2) { delimiters(&ctx.eval(&args[2]))? } else { Vec::new() };
    if col_delims.iter().chain(&row_delims).all(Vec::is_empty) {
        return Err(XlError::Value);
    }
    let ignore_empty = if present(args, 3) { to_bool(&ctx.eval(&args[3]))? } else { false };
    let ignore_case = if present(args, 4) { to_number(&ctx.eval(&args[4]), dates)? != 0.0 } else { false };
    let pad = if present(args, 5) { ctx.eval(&args[5]).unwrap_single() } else { Value::Error(XlError::NA) };
    let mut rows: Vec<Vec<String>> = Vec::new();
    for line in split(&text, &row_delims, ignore_case) {
        if ignore_empty && line.is_empty() {
            continue;
        }
        let chars: Vec<char> = line.chars().collect();
        let mut cells = split(&chars, &col_delims, ignore_case);
        if ignore_empty {
            cells.retain(|c| !c.is_empty());
        }
        rows.push(cells);
    }
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    if rows.is_empty() || cols == 0 {
        return Err(XlError::Calc);
    }
    let n = rows.len();
    // Every row is padded to the widest: 16,384 rows under one row of 16,384 parts (a text
    // of 32,767 delimiters) would be 2^28 items.
    ctx.room_for(n, cols)?;
    let data = rows
        .into_iter()
        .flat_map(|r| {
            let len = r.len();
            r.into_iter().map(Value::text).chain(std::iter::repeat_n(pad.clone(), cols - len)).collect::<Vec<_>>()
        })
        .collect();
    Ok(Value::Array(Rc::new(Array::new(n, cols, data))))
}

trait BlankAsText {
    fn blank_as_text(self) -> Value;
}

impl BlankAsText for Value {
    fn blank_as_text(self) -> Value {
        match self {
            Value::Blank => Value::text(""),
            v => v,
        }
    }
}
