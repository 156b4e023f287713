//! Excel 365's dynamic-array functions that reshape and select: SORT, SORTBY, FILTER,
//! UNIQUE, TOCOL, TOROW, HSTACK, VSTACK, TAKE, DROP, EXPAND, CHOOSECOLS, CHOOSEROWS,
//! WRAPCOLS, WRAPROWS and ARRAYTOTEXT. Each reads its array argument as a block (a range's
//! blanks included) and returns a new array that spills.

use std::cmp::Ordering;
use std::collections::hash_map::HashMap;
use std::hash::BuildHasherDefault;
use std::rc::Rc;

use crate::eval::coerce::{compare_text, to_bool, to_number};
use crate::eval::format::number_format::general;
use crate::eval::functions::api::{block, bool_or, given, number, number_or, require, ArgSet, Ctx, FnSpec, MANY};
use crate::eval::value::{too_many_items_note, Array, Value, XlError, XlResult, MAX_ARRAY_ITEMS};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "ARRAYTOTEXT",
        1,
        2,
        arraytotext,
        "ARRAYTOTEXT(array, [format])",
        "An array as one text: items joined by \", \" (format 0) or as an array constant (format 1)",
    )
    .future()
    .array_args(ArgSet::only(0)),
    FnSpec::value(
        "CHOOSECOLS",
        2,
        MANY,
        choosecols,
        "CHOOSECOLS(array, col_num1, [col_num2], ...)",
        "The given columns of an array (negative numbers count from the end)",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "CHOOSEROWS",
        2,
        MANY,
        chooserows,
        "CHOOSEROWS(array, row_num1, [row_num2], ...)",
        "The given rows of an array (negative numbers count from the end)",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "DROP",
        2,
        3,
        drop,
        "DROP(array, rows, [columns])",
        "The array without its first (or, negative, last) rows and columns",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "EXPAND",
        2,
        4,
        expand,
        "EXPAND(array, rows, [columns], [pad_with])",
        "The array grown to the given size, padded with #N/A or pad_with",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "FILTER",
        2,
        3,
        filter,
        "FILTER(array, include, [if_empty])",
        "The rows (or columns) of an array where include is TRUE",
    )
    .worksheet_future()
    .dynamic(),
    FnSpec::value(
        "HSTACK",
        1,
        MANY,
        hstack,
        "HSTACK(array1, [array2], ...)",
        "Arrays side by side, shorter ones padded with #N/A",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "SORT",
        1,
        4,
        sort,
        "SORT(array, [sort_index], [sort_order], [by_col])",
        "The array's rows (or columns) sorted by one of its columns (or rows)",
    )
    .worksheet_future()
    .dynamic(),
    FnSpec::value(
        "SORTBY",
        2,
        MANY,
        sortby,
        "SORTBY(array, by_array1, [sort_order1], ...)",
        "The array's rows (or columns) sorted by other arrays",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "TAKE",
        2,
        3,
        take,
        "TAKE(array, rows, [columns])",
        "The first (or, negative, last) rows and columns of an array",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "TOCOL",
        1,
        3,
        tocol,
        "TOCOL(array, [ignore], [scan_by_column])",
        "The array as one column (ignore 1 blanks, 2 errors, 3 both)",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "TOROW",
        1,
        3,
        torow,
        "TOROW(array, [ignore], [scan_by_column])",
        "The array as one row (ignore 1 blanks, 2 errors, 3 both)",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "UNIQUE",
        1,
        3,
        unique,
        "UNIQUE(array, [by_col], [exactly_once])",
        "The distinct rows (or columns) of an array, in order of appearance",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "VSTACK",
        1,
        MANY,
        vstack,
        "VSTACK(array1, [array2], ...)",
        "Arrays one above the other, narrower ones padded with #N/A",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "WRAPCOLS",
        2,
        3,
        wrapcols,
        "WRAPCOLS(vector, wrap_count, [pad_with])",
        "A row or column wrapped into columns of wrap_count items",
    )
    .future()
    .dynamic(),
    FnSpec::value(
        "WRAPROWS",
        2,
        3,
        wraprows,
        "WRAPROWS(vector, wrap_count, [pad_with])",
        "A row or column wrapped into rows of wrap_count items",
    )
    .future()
    .dynamic(),
];

fn array(rows: usize, cols: usize, data: Vec<Value>) -> Value {
    Value::Array(Rc::new(Array::new(rows, cols, data)))
}

/// The rows of a block as vectors.
fn transpose(a: &Array) -> Array {
    let data = (0..a.cols).flat_map(|c| (0..a.rows).map(move |r| (r, c))).map(|(r, c)| a.get(r, c).clone()).collect();
    Array::new(a.cols, a.rows, data)
}

/// The rows (or, `by_col`, the columns) of a block at the given indexes, in that order, each
/// item passed through `item`. Built in one pass over the result, without a vector per row:
/// SORT of 16,000,000 rows spent most of its time making and dropping them. No rows or no
/// columns is `#CALC!`, as Excel's empty results are.
fn picked(a: &Array, picks: &[usize], by_col: bool, item: impl Fn(&Value) -> Value) -> XlResult<Value> {
    let (rows, cols) = if by_col { (a.rows, picks.len()) } else { (picks.len(), a.cols) };
    if rows == 0 || cols == 0 {
        return Err(XlError::Calc);
    }
    let data = if by_col {
        (0..rows).flat_map(|r| picks.iter().map(move |&c| a.get(r, c))).map(item).collect()
    } else {
        picks.iter().flat_map(|&r| &a.data[r * cols..(r + 1) * cols]).map(item).collect()
    };
    Ok(array(rows, cols, data))
}

// ---- sorting --------------------------------------------------------------------------------

/// SORT's order across kinds: numbers, text, booleans, errors, then blanks (also the order
/// of a macro's `Range.Sort`).
pub(crate) fn sort_cmp(a: &Value, b: &Value) -> Ordering {
    fn rank(v: &Value) -> u8 {
        match v {
            Value::Number(_) => 0,
            Value::Text(_) => 1,
            Value::Bool(_) => 2,
            Value::Error(_) | Value::Lambda(_) => 3,
            Value::Blank | Value::Array(_) | Value::Null => 4,
        }
    }
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.total_cmp(y),
        (Value::Text(x), Value::Text(y)) => compare_text(x, y),
        (Value::Bool(x), Value::Bool(y)) => x.cmp(y),
        // Errors in the order of their ERROR.TYPE numbers (#DIV/0! before #NAME? before #N/A).
        (Value::Error(x), Value::Error(y)) => x.type_number().cmp(&y.type_number()),
        _ => rank(a).cmp(&rank(b)),
    }
}

/// +1 ascending, -1 descending; anything else is `#VALUE!`.
fn sort_order(x: f64) -> XlResult<bool> {
    match x.trunc() {
        1.0 => Ok(false),
        -1.0 => Ok(true),
        _ => Err(XlError::Value),
    }
}

/// SORT's comparison in either direction: blanks go last both ways.
fn directed(a: &Value, b: &Value, descending: bool) -> Ordering {
    match (a.is_blank(), b.is_blank()) {
        (true, true) => Ordering::Equal,
        (true, false) => Ordering::Greater,
        (false, true) => Ordering::Less,
        _ if descending => sort_cmp(a, b).reverse(),
        _ => sort_cmp(a, b),
    }
}

/// A sorted result's item: blank cells are shown as 0, as Excel's SORT shows them.
fn sorted_item(v: &Value) -> Value {
    v.clone().blank_as_zero()
}

/// One index being sorted, with its first key in line when that key is a number: most
/// comparisons of a numeric sort then read only the vector being sorted. Reading each key
/// from the array instead jumps to a random place in it at every comparison, a cache miss
/// each: 16,000,000 random numbers took 42 s that way, against 3 s for numbers in order.
#[derive(Clone, Copy)]
struct Sorting {
    number: f64,
    is_number: bool,
    index: usize,
}

#[cfg(test)]
thread_local! {
    /// Keys [`sorted_order`] has read from the array being sorted: counted for a test, which
    /// bounds the reads of a sort by this count rather than by a clock.
    static KEYS_READ: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// The indexes `0..n` in sorted order, each compared by its keys in turn (`key(k, i)` is key
/// `k`'s value at index `i`). The sort is stable, as Excel's is: equal keys keep their order.
fn sorted_order<'a>(n: usize, descending: &[bool], key: impl Fn(usize, usize) -> &'a Value) -> Vec<usize> {
    let Some(&first_descending) = descending.first() else {
        return (0..n).collect();
    };
    let key = |k: usize, i: usize| {
        #[cfg(test)]
        KEYS_READ.with(|c| c.set(c.get() + 1));
        key(k, i)
    };
    let mut sorting: Vec<Sorting> = (0..n)
        .map(|index| match key(0, index) {
            // `+ 0.0` makes -0 a 0: total_cmp would put -0 first, where the two are one
            // number to Excel and a stable sort keeps their order.
            Value::Number(x) => Sorting { number: *x + 0.0, is_number: true, index },
            _ => Sorting { number: 0.0, is_number: false, index },
        })
        .collect();
    let first = |x: &Sorting, y: &Sorting| match (x.is_number, y.is_number) {
        // What `directed` answers for two numbers, without reading them from the array.
        (true, true) if first_descending => y.number.total_cmp(&x.number),
        (true, true) => x.number.total_cmp(&y.number),
        _ => directed(key(0, x.index), key(0, y.index), first_descending),
    };
    sorting.sort_by(|x, y| {
        first(x, y).then_with(|| {
            (1..descending.len())
                .map(|k| directed(key(k, x.index), key(k, y.index), descending[k]))
                .find(|o| o.is_ne())
                .unwrap_or(Ordering::Equal)
        })
    });
    sorting.into_iter().map(|s| s.index).collect()
}

fn sort(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let index = number_or(ctx, args, 1, 1.0)?.trunc();
    let descending = sort_order(number_or(ctx, args, 2, 1.0)?)?;
    let by_col = bool_or(ctx, args, 3, false)?;
    let width = if by_col { a.rows } else { a.cols };
    require(index >= 1.0 && index <= width as f64)?;
    let key = index as usize - 1;
    let (n, a_ref) = (if by_col { a.cols } else { a.rows }, &*a);
    let order = sorted_order(n, &[descending], |_, i| if by_col { a_ref.get(key, i) } else { a_ref.get(i, key) });
    picked(&a, &order, by_col, sorted_item)
}

fn sortby(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let mut keys: Vec<Rc<Array>> = Vec::new();
    let mut descending = Vec::new();
    let mut by_col = None;
    for pair in args[1..].chunks(2) {
        let by = block(ctx, &pair[0])?;
        let desc = match pair.get(1) {
            Some(e) if e.kind != ExprKind::Missing => sort_order(number(ctx, e)?)?,
            _ => false,
        };
        // A column of keys sorts rows; a row of keys sorts columns.
        let this_by_col = if by.cols == 1 && by.rows == a.rows {
            false
        } else if by.rows == 1 && by.cols == a.cols {
            true
        } else {
            return Err(XlError::Value);
        };
        if *by_col.get_or_insert(this_by_col) != this_by_col {
            return Err(XlError::Value);
        }
        keys.push(by);
        descending.push(desc);
    }
    let by_col = by_col.unwrap_or(false);
    let n = if by_col { a.cols } else { a.rows };
    let order = sorted_order(n, &descending, |k, i| &keys[k].data[i]);
    picked(&a, &order, by_col, sorted_item)
}

// ---- selecting ------------------------------------------------------------------------------

fn filter(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let include = block(ctx, &args[1])?;
    let by_col = if include.cols == 1 && include.rows == a.rows {
        false
    } else if include.rows == 1 && include.cols == a.cols {
        true
    } else {
        return Err(XlError::Value);
    };
    let keep: Vec<bool> = include
        .data
        .iter()
        .map(|v| match v {
            Value::Error(e) => Err(*e),
            Value::Text(_) => Err(XlError::Value),
            v => to_bool(v),
        })
        .collect::<XlResult<_>>()?;
    if !keep.contains(&true) {
        return match args.get(2) {
            Some(e) => Ok(ctx.eval(e)),
            None => Err(XlError::Calc),
        };
    }
    let kept: Vec<usize> = keep.iter().enumerate().filter(|(_, &k)| k).map(|(i, _)| i).collect();
    picked(&a, &kept, by_col, Value::clone)
}

/// Rows equal item by item as `=` compares (text without regard to case).
fn same_row(a: &[Value], b: &[Value]) -> bool {
    a.iter().zip(b).all(|(x, y)| match (x, y) {
        (Value::Text(s), Value::Text(t)) => compare_text(s, t).is_eq(),
        _ => x == y,
    })
}

fn unique(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let by_col = bool_or(ctx, args, 1, false)?;
    let exactly_once = bool_or(ctx, args, 2, false)?;
    let turned;
    let rows = if by_col {
        turned = transpose(&a);
        &turned
    } else {
        &*a
    };
    let kept = distinct_rows(rows, exactly_once);
    if kept.is_empty() || rows.cols == 0 {
        return Err(XlError::Calc);
    }
    let width = rows.cols;
    let data = kept.iter().flat_map(|&r| rows.data[r * width..(r + 1) * width].iter().cloned()).collect();
    let out = Array::new(kept.len(), width, data);
    Ok(Value::Array(Rc::new(if by_col { transpose(&out) } else { out })))
}

/// The rows UNIQUE keeps, by index, in the order first seen: each distinct row once, or with
/// `exactly_once` those met once. A row is found among the distinct ones by a hash of its
/// items' keys (a million rows take a million look-ups, not half a million million
/// comparisons: 100,000 rows took 27 s), and the rows are never copied: a few words a row,
/// where a copy and a key per row (16,000,000 rows) aborted at 4 GB.
fn distinct_rows(a: &Array, exactly_once: bool) -> Vec<usize> {
    use std::collections::hash_map::Entry;
    const NONE: usize = usize::MAX;
    let width = a.cols;
    let row = |r: usize| &a.data[r * width..(r + 1) * width];
    // Each distinct row with its count, and the next distinct row of the same hash.
    let mut distinct: Vec<(usize, usize, usize)> = Vec::new();
    let mut first_of_hash: HashMap<u64, usize, BuildHasherDefault<Prehashed>> = HashMap::default();
    for r in 0..a.rows {
        let found = match row_hash(row(r)) {
            // One look-up a row: a row met before, or the head of its hash's chain.
            Some(h) => match first_of_hash.entry(h) {
                Entry::Vacant(slot) => {
                    slot.insert(distinct.len());
                    None
                }
                Entry::Occupied(mut slot) => {
                    let mut at = *slot.get();
                    while at != NONE && !same_row(row(distinct[at].0), row(r)) {
                        at = distinct[at].2;
                    }
                    if at == NONE {
                        let next = slot.insert(distinct.len());
                        distinct.push((r, 1, next));
                        continue;
                    }
                    Some(at)
                }
            },
            None => distinct.iter().position(|&(d, ..)| same_row(row(d), row(r))),
        };
        match found {
            Some(i) => distinct[i].1 += 1,
            None => distinct.push((r, 1, NONE)),
        }
    }
    distinct.into_iter().filter(|&(_, count, _)| !exactly_once || count == 1).map(|(r, ..)| r).collect()
}

/// The hasher of a map whose keys are hashes already (a row's, [`row_hash`]): it passes
/// them on, where std's would hash each again (with the second look-up a row, a third of
/// UNIQUE's time on 16,777,216 numbers).
#[derive(Default)]
struct Prehashed(u64);

impl std::hash::Hasher for Prehashed {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }

    fn write_u64(&mut self, hash: u64) {
        self.0 = hash;
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A hash of a row's item keys; `None` when an item has no key (NaN, a LAMBDA, an array):
/// such a row is compared with each distinct row in turn.
fn row_hash(row: &[Value]) -> Option<u64> {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for item in row {
        item_key(item)?.hash(&mut hasher);
    }
    Some(hasher.finish())
}

/// An item as [`same_row`] compares it, hashable: text folded to lower case as
/// `compare_text` folds it, a number by its value (0 and -0 alike).
#[derive(Clone, PartialEq, Eq, Hash)]
pub(crate) enum ItemKey {
    Blank,
    Number(u64),
    Bool(bool),
    Text(String),
    Error(XlError),
    Null,
}

/// `None` for what has no key (NaN, a LAMBDA or an array as an item): such a row is
/// compared with each distinct row in turn.
pub(crate) fn item_key(v: &Value) -> Option<ItemKey> {
    Some(match v {
        Value::Blank => ItemKey::Blank,
        Value::Number(n) if n.is_nan() => return None,
        Value::Number(n) => ItemKey::Number(if *n == 0.0 { 0 } else { n.to_bits() }),
        Value::Bool(b) => ItemKey::Bool(*b),
        Value::Text(s) if s.is_ascii() => ItemKey::Text(s.to_ascii_lowercase()),
        Value::Text(s) => ItemKey::Text(s.chars().flat_map(char::to_lowercase).collect()),
        Value::Error(e) => ItemKey::Error(*e),
        Value::Null => ItemKey::Null,
        Value::Array(_) | Value::Lambda(_) => return None,
    })
}

/// A 1-based index from either end (-1 is the last) into `n` items.
fn index_from_ends(i: f64, n: usize) -> XlResult<usize> {
    let i = i.trunc();
    if i >= 1.0 && i <= n as f64 {
        Ok(i as usize - 1)
    } else if i <= -1.0 && -i <= n as f64 {
        Ok((n as f64 + i) as usize)
    } else {
        Err(XlError::Value)
    }
}

/// The indexes the arguments name, each a number or an array of numbers. Each pick is a
/// whole row (CHOOSEROWS) or column (CHOOSECOLS) of `width` items: the result's size is
/// checked as the picks are counted, before anything is copied (16,000 picks of a row of
/// 16,384 items aborted at the memory cap).
fn chosen(ctx: &mut Ctx, args: &[Expr], n: usize, width: usize, rows: bool) -> XlResult<Vec<usize>> {
    let dates = ctx.dates();
    let mut out = Vec::new();
    for e in args {
        let picks = block(ctx, e)?;
        let count = out.len() + picks.data.len();
        if rows {
            ctx.room_for(count, width)?;
        } else {
            ctx.room_for(width, count)?;
        }
        for v in &picks.data {
            out.push(index_from_ends(to_number(v, dates)?, n)?);
        }
    }
    Ok(out)
}

fn chooserows(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let picks = chosen(ctx, &args[1..], a.rows, a.cols, true)?;
    picked(&a, &picks, false, Value::clone)
}

fn choosecols(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let picks = chosen(ctx, &args[1..], a.cols, a.rows, false)?;
    picked(&a, &picks, true, Value::clone)
}

/// TAKE's and DROP's count for one dimension: `None` when omitted.
fn count_arg(ctx: &mut Ctx, args: &[Expr], i: usize) -> XlResult<Option<f64>> {
    if given(args, i).is_some() {
        Ok(Some(number(ctx, &args[i])?.trunc()))
    } else {
        Ok(None)
    }
}

/// The range of `n` items that TAKE (`take`) or DROP keeps for `count`.
fn kept_range(count: Option<f64>, n: usize, take: bool) -> std::ops::Range<usize> {
    let Some(c) = count else { return 0..n };
    let k = (c.abs() as usize).min(n);
    match (take, c >= 0.0) {
        (true, true) => 0..k,
        (true, false) => n - k..n,
        (false, true) => k..n,
        (false, false) => 0..n - k,
    }
}

fn take_or_drop(ctx: &mut Ctx, args: &[Expr], take: bool) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let rows = count_arg(ctx, args, 1)?;
    let cols = count_arg(ctx, args, 2)?;
    if take && (rows == Some(0.0) || cols == Some(0.0)) {
        return Err(XlError::Calc);
    }
    let (rr, cr) = (kept_range(rows, a.rows, take), kept_range(cols, a.cols, take));
    if rr.is_empty() || cr.is_empty() {
        return Err(XlError::Calc);
    }
    let data = rr.clone().flat_map(|r| cr.clone().map(move |c| (r, c))).map(|(r, c)| a.get(r, c).clone()).collect();
    Ok(array(rr.len(), cr.len(), data))
}

fn take(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    take_or_drop(ctx, args, true)
}

fn drop(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    take_or_drop(ctx, args, false)
}

/// An optional padding argument: `#N/A` when omitted.
fn pad_arg(ctx: &mut Ctx, args: &[Expr], i: usize) -> Value {
    if given(args, i).is_some() {
        ctx.eval(&args[i]).unwrap_single()
    } else {
        Value::Error(XlError::NA)
    }
}

fn expand(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let rows = count_arg(ctx, args, 1)?.unwrap_or(a.rows as f64);
    let cols = count_arg(ctx, args, 2)?.unwrap_or(a.cols as f64);
    let pad = pad_arg(ctx, args, 3);
    if rows < a.rows as f64 || cols < a.cols as f64 {
        return Err(XlError::Value);
    }
    // Excel: "If an array is too large, Excel returns a #NUM error".
    if rows * cols > MAX_ARRAY_ITEMS as f64 {
        let (rows, cols) = (rows.min(1e15) as usize, cols.min(1e15) as usize);
        return Err(ctx.explain(XlError::Num, too_many_items_note(rows, cols)));
    }
    let (rows, cols) = (rows as usize, cols as usize);
    let data = (0..rows * cols)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            if r < a.rows && c < a.cols {
                a.get(r, c).clone()
            } else {
                pad.clone()
            }
        })
        .collect();
    Ok(array(rows, cols, data))
}

fn stack(ctx: &mut Ctx, args: &[Expr], horizontal: bool) -> XlResult<Value> {
    let mut parts = Vec::with_capacity(args.len());
    for e in args {
        parts.push(block(ctx, e)?);
    }
    let widest = |f: fn(&Array) -> usize| parts.iter().map(|p| f(p)).max().unwrap_or(0);
    let total = |f: fn(&Array) -> usize| parts.iter().fold(0usize, |n, p| n.saturating_add(f(p)));
    let (rows, cols) =
        if horizontal { (widest(|p| p.rows), total(|p| p.cols)) } else { (total(|p| p.rows), widest(|p| p.cols)) };
    ctx.room_for(rows, cols)?;
    // Each part's rows copied whole into one vector, in the result's order: a REDUCE growing
    // its array with HSTACK or VSTACK copies it at every step, so each copy is kept to one
    // pass over the items (HSTACK went through two transposes and a copy item by item).
    let mut data = Vec::with_capacity(rows * cols);
    if horizontal {
        for r in 0..rows {
            for p in &parts {
                if r < p.rows {
                    data.extend_from_slice(&p.data[r * p.cols..(r + 1) * p.cols]);
                } else {
                    data.resize(data.len() + p.cols, Value::Error(XlError::NA));
                }
            }
        }
    } else {
        for p in &parts {
            if p.cols == cols {
                data.extend_from_slice(&p.data);
                continue;
            }
            for row in p.data.chunks(p.cols) {
                data.extend_from_slice(row);
                data.resize(data.len() + cols - row.len(), Value::Error(XlError::NA));
            }
        }
    }
    if data.is_empty() {
        return Err(XlError::Calc);
    }
    Ok(array(data.len() / cols, cols, data))
}

fn hstack(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    stack(ctx, args, true)
}

fn vstack(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    stack(ctx, args, false)
}

/// The items of a block, row by row or column by column.
fn items_in_order(a: &Array, by_column: bool) -> Vec<Value> {
    if by_column {
        transpose(a).data
    } else {
        a.data.clone()
    }
}

fn to_vector(ctx: &mut Ctx, args: &[Expr], as_row: bool) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let ignore = number_or(ctx, args, 1, 0.0)?.trunc();
    let by_column = bool_or(ctx, args, 2, false)?;
    require((0.0..=3.0).contains(&ignore))?;
    let (skip_blanks, skip_errors) = (ignore == 1.0 || ignore == 3.0, ignore >= 2.0);
    let items: Vec<Value> = items_in_order(&a, by_column)
        .into_iter()
        .filter(|v| !(skip_blanks && v.is_blank() || skip_errors && matches!(v, Value::Error(_))))
        .collect();
    if items.is_empty() {
        return Err(XlError::Calc);
    }
    let n = items.len();
    Ok(if as_row { array(1, n, items) } else { array(n, 1, items) })
}

fn tocol(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    to_vector(ctx, args, false)
}

fn torow(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    to_vector(ctx, args, true)
}

fn wrap(ctx: &mut Ctx, args: &[Expr], into_rows: bool) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let count = number(ctx, &args[1])?.trunc();
    let pad = pad_arg(ctx, args, 2);
    require(a.rows == 1 || a.cols == 1)?;
    if count < 1.0 {
        return Err(XlError::Num);
    }
    // A count past the items makes one line of `count`, padded: sized before it is built.
    // A count no array may hold is named as given: read as a usize it saturated, and the
    // note spoke of "1 × 18446744073709551615" items for a count of 1E+300.
    if count > MAX_ARRAY_ITEMS as f64 {
        let note = format!(
            "a wrap count of {}, more than ncsheet's limit of {MAX_ARRAY_ITEMS} items in an array",
            general(count)
        );
        return Err(ctx.explain(XlError::Num, note));
    }
    let count = count as usize;
    let items = &a.data;
    let lines = items.len().div_ceil(count);
    ctx.room_for(lines, count)?;
    let item = |line: usize, k: usize| items.get(line * count + k).cloned().unwrap_or_else(|| pad.clone());
    if into_rows {
        let data = (0..lines).flat_map(|l| (0..count).map(move |k| (l, k))).map(|(l, k)| item(l, k)).collect();
        Ok(array(lines, count, data))
    } else {
        let data = (0..count).flat_map(|k| (0..lines).map(move |l| (l, k))).map(|(l, k)| item(l, k)).collect();
        Ok(array(count, lines, data))
    }
}

fn wrapcols(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    wrap(ctx, args, false)
}

fn wraprows(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    wrap(ctx, args, true)
}

// ---- as text --------------------------------------------------------------------------------

/// One item as ARRAYTOTEXT writes it: concise (format 0) or as in an array constant.
fn item_text(v: &Value, strict: bool) -> String {
    match v {
        Value::Number(n) => general(*n),
        Value::Text(s) if strict => format!("\"{}\"", s.replace('"', "\"\"")),
        Value::Text(s) => s.to_string(),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
        Value::Error(e) => e.as_str().to_string(),
        Value::Lambda(_) => XlError::Calc.as_str().to_string(),
        Value::Blank | Value::Array(_) | Value::Null => String::new(),
    }
}

fn arraytotext(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let a = block(ctx, &args[0])?;
    let strict = match number_or(ctx, args, 1, 0.0)?.trunc() {
        0.0 => false,
        1.0 => true,
        _ => return Err(XlError::Value),
    };
    match array_text(&a, strict, ctx.text_limit()) {
        Some(text) => Ok(Value::text(text)),
        None => Err(ctx.text_over_limit()),
    }
}

/// The items of `a` as ARRAYTOTEXT writes them (concise: joined by ", "; strict: an array
/// constant, `{1,"a";2,"b"}`), or `None` as soon as the text passes `limit` UTF-16 units.
/// Stopping there matters: the whole text of a 4096 × 4096 array was built (14 s) only to be
/// refused for its length.
fn array_text(a: &Array, strict: bool, limit: usize) -> Option<String> {
    let (mut out, mut units) = (String::new(), 0usize);
    let mut push = |piece: &str, out: &mut String| {
        units += piece.encode_utf16().count();
        out.push_str(piece);
        units <= limit
    };
    let cols = a.cols.max(1);
    if strict && !push("{", &mut out) {
        return None;
    }
    for (i, v) in a.data.iter().enumerate() {
        let separator = match (i, strict) {
            (0, _) => "",
            (_, false) => ", ",
            (_, true) if i % cols == 0 => ";",
            (_, true) => ",",
        };
        if !push(separator, &mut out) || !push(&item_text(v, strict), &mut out) {
            return None;
        }
    }
    if strict && !push("}", &mut out) {
        return None;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::testing::MapEnv;

    fn numbers(v: Value) -> Vec<f64> {
        let Value::Array(a) = v else { panic!("not an array: {v:?}") };
        a.data.iter().map(|v| if let Value::Number(x) = v { *x } else { panic!("not a number: {v:?}") }).collect()
    }

    /// A sort reads each key from the array once, to put numbers beside the indexes being
    /// sorted; the comparisons read only those. The comparator read both keys from the array
    /// at every comparison (about n·log2 n = 130,000 comparisons here), at a random place in
    /// it each time: 16,000,000 random numbers took 42 s.
    /// Excel has one zero: a 0 and a -0 (what IEEE arithmetic can leave, `-1*0`) are equal
    /// keys, which the stable sort leaves in their order, ascending or descending.
    /// ARRAYTOTEXT's text is given up at the first item past the limit, not built whole and
    /// then refused (a 4096 × 4096 array took 14 s to reach #VALUE!). The texts are Excel's
    /// documented forms: `1, a, 2, b` and `{1,"a";2,"b"}` (10 and 13 characters).
    #[test]
    fn array_text_stops_at_the_limit() {
        let a = Array::new(2, 2, vec![1.0.into(), "a".into(), 2.0.into(), "b".into()]);
        assert_eq!(array_text(&a, false, 10).as_deref(), Some("1, a, 2, b"));
        assert_eq!(array_text(&a, true, 13).as_deref(), Some("{1,\"a\";2,\"b\"}"));
        assert_eq!(array_text(&a, false, 9), None);
        assert_eq!(array_text(&a, true, 12), None);
    }

    #[test]
    fn a_negative_zero_sorts_as_the_zero_it_equals() {
        let keys = [Value::Number(0.0), Value::Number(-0.0), Value::Number(-1.0)];
        assert_eq!(sorted_order(3, &[false], |_, i| &keys[i]), [2, 0, 1]);
        assert_eq!(sorted_order(3, &[true], |_, i| &keys[i]), [0, 1, 2]);
    }

    #[test]
    fn a_numeric_sort_reads_each_key_from_the_array_once() {
        let env = MapEnv::default();
        // k·7919 mod 10007 for k = 1..10000: 10,000 different numbers (10007 is prime and
        // 7919 not a multiple of it), out of order; sorted, they are strictly monotonic.
        let keys = "MOD(SEQUENCE(10000)*7919,10007)";
        let reads = || KEYS_READ.with(std::cell::Cell::get);
        let before = reads();
        let down = numbers(env.eval(&format!("=SORT({keys},1,-1)")));
        assert_eq!(reads() - before, 10_000);
        assert_eq!(down.len(), 10_000);
        assert!(down.windows(2).all(|w| w[0] > w[1]));
        // SORTBY's second key is read only where the first ties: never, here.
        let before = reads();
        let up = numbers(env.eval(&format!("=SORTBY({keys},{keys},1,SEQUENCE(10000),-1)")));
        assert_eq!(reads() - before, 10_000);
        assert!(up.windows(2).all(|w| w[0] < w[1]));
    }
}
