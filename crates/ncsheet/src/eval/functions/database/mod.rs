//! The database functions: DSUM, DAVERAGE, DCOUNT, DCOUNTA, DGET, DMAX, DMIN, DPRODUCT,
//! DSTDEV, DSTDEVP, DVAR and DVARP. A database is a range whose first row names its fields;
//! the criteria range names fields in its first row and lists conditions below: the
//! conditions of one row must all hold, any row may. Text with no operator matches values
//! that begin with it, as in Excel's advanced filter.

use std::collections::HashMap;

use crate::eval::coerce::{compare_text, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{block, number_result, ArgSet, Ctx, FnSpec};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use crate::eval::functions::arrays::reshape::ItemKey;
use crate::eval::functions::criteria::{lowered, Criterion, EqualityIndex, MAX_CRITERIA_SCAN};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "DAVERAGE",
        3,
        3,
        daverage,
        "DAVERAGE(database, field, criteria)",
        "Mean of a field over the records that meet the criteria",
    )
    .biff(42)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DCOUNT",
        2,
        3,
        dcount,
        "DCOUNT(database, [field], criteria)",
        "How many numbers a field holds in the records that meet the criteria",
    )
    .biff_fixed(40, 3)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DCOUNTA",
        2,
        3,
        dcounta,
        "DCOUNTA(database, [field], criteria)",
        "How many non-empty cells a field holds in the records that meet the criteria",
    )
    .biff_fixed(199, 3)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DGET",
        3,
        3,
        dget,
        "DGET(database, field, criteria)",
        "The field of the one record that meets the criteria",
    )
    .biff(235)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DMAX",
        3,
        3,
        dmax,
        "DMAX(database, field, criteria)",
        "Largest number of a field over the records that meet the criteria",
    )
    .biff(44)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DMIN",
        3,
        3,
        dmin,
        "DMIN(database, field, criteria)",
        "Smallest number of a field over the records that meet the criteria",
    )
    .biff(43)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DPRODUCT",
        3,
        3,
        dproduct,
        "DPRODUCT(database, field, criteria)",
        "Product of a field over the records that meet the criteria",
    )
    .biff(189)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DSTDEV",
        3,
        3,
        dstdev,
        "DSTDEV(database, field, criteria)",
        "Sample standard deviation of a field over the matching records",
    )
    .biff(45)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DSTDEVP",
        3,
        3,
        dstdevp,
        "DSTDEVP(database, field, criteria)",
        "Population standard deviation of a field over the matching records",
    )
    .biff(195)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DSUM",
        3,
        3,
        dsum,
        "DSUM(database, field, criteria)",
        "Sum of a field over the records that meet the criteria",
    )
    .biff(41)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DVAR",
        3,
        3,
        dvar,
        "DVAR(database, field, criteria)",
        "Sample variance of a field over the matching records",
    )
    .biff(47)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "DVARP",
        3,
        3,
        dvarp,
        "DVARP(database, field, criteria)",
        "Population variance of a field over the matching records",
    )
    .biff(196)
    .range_args(ArgSet::ALL),
];

/// One condition of a criteria row: the database column (`None` when the criteria header
/// names no field of the database: no record meets it) and the criterion.
type Condition = (Option<usize>, Criterion);

/// The header's column for a field name (as text, ignoring case) or 1-based number.
fn field_column(db: &Array, field: &Value, dates: DateSystem) -> XlResult<usize> {
    match field {
        Value::Text(_) => criteria_column(db, field)?.ok_or(XlError::Value),
        Value::Error(e) => Err(*e),
        v => {
            let i = to_number(v, dates)?.trunc();
            if i >= 1.0 && i <= db.cols as f64 {
                Ok(i as usize - 1)
            } else {
                Err(XlError::Value)
            }
        }
    }
}

/// A criteria cell as a criterion: text with no operator matches as a prefix.
fn condition(v: &Value, dates: DateSystem) -> Criterion {
    match v {
        Value::Text(t) if !t.starts_with(['=', '<', '>']) && !t.is_empty() && !t.ends_with('*') => {
            Criterion::new(&Value::text(format!("{t}*")), dates)
        }
        v => Criterion::new(v, dates),
    }
}

/// The database column a criteria header names: the first header that reads the same as
/// text, ignoring case (so a header TRUE is named by "true" and 1 by 1).
fn criteria_column(db: &Array, header: &Value) -> XlResult<Option<usize>> {
    if let Value::Error(e) = header {
        return Err(*e);
    }
    if header.is_blank() {
        return Ok(None);
    }
    let name = to_text(header)?;
    Ok((0..db.cols).find(|&c| to_text(db.get(0, c)).is_ok_and(|h| compare_text(&h, &name).is_eq())))
}

/// The criteria rows, each its conditions (a blank criteria cell sets none).
fn criteria_rows(db: &Array, criteria: &Array, dates: DateSystem) -> XlResult<Vec<Vec<Condition>>> {
    let mut columns = Vec::with_capacity(criteria.cols);
    for c in 0..criteria.cols {
        columns.push(criteria_column(db, criteria.get(0, c))?);
    }
    let mut rows = Vec::new();
    for r in 1..criteria.rows {
        let mut conditions = Vec::new();
        for (c, column) in columns.iter().enumerate() {
            let v = criteria.get(r, c);
            if !v.is_blank() {
                conditions.push((*column, condition(v, dates)));
            }
        }
        rows.push(conditions);
    }
    Ok(rows)
}

/// The values of `field` in the records that meet the criteria.
fn selected(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<Value>> {
    let dates = ctx.dates();
    let db = block(ctx, &args[0])?;
    let (field, criteria) = match args {
        [_, criteria] => (None, criteria),
        [_, field, criteria] if field.kind == ExprKind::Missing => (None, criteria),
        [_, field, criteria] => (Some(ctx.eval(field).unwrap_single()), criteria),
        _ => unreachable!("the database functions take two or three arguments"),
    };
    let criteria = block(ctx, criteria)?;
    // A database is a header and at least one record.
    if db.rows < 2 || criteria.rows < 1 {
        return Err(XlError::Value);
    }
    let column = field.map(|f| field_column(&db, &f, dates)).transpose()?;
    let rows = criteria_rows(&db, &criteria, dates)?;
    let records = db.rows - 1;
    let scanned = rows.iter().filter(|conditions| lookup_of(conditions).is_none()).count();
    if scanned.saturating_mul(records) > MAX_CRITERIA_SCAN {
        let why = format!(
            "the criteria would test {} records one by one, more than ncsheet's limit of {MAX_CRITERIA_SCAN:e} for \
             one call (criteria rows with no plain equality such as =x or a number, nor a text prefix, × the \
             records)",
            scanned * records
        );
        return Err(ctx.explain(XlError::Num, why));
    }
    let meeting = records_meeting(&db, &rows, dates);
    ctx.charge(db.rows.saturating_add(scanned.saturating_mul(records)));
    let mut out = Vec::new();
    for r in (0..records).filter(|&r| meeting[r]) {
        // DCOUNT with no field counts records: each stands as a number.
        out.push(column.map_or(Value::Number(1.0), |c| db.get(r + 1, c).clone()));
    }
    Ok(out)
}

/// Whether each record (row 1 … of `db`, from 0) meets the conditions of some criteria
/// row. A row with an equality condition (`=x`, a number, TRUE) tests only the records an
/// index of that column files under its value, and a row with a text prefix (`bol`) only
/// the records whose text there begins with it, so that many criteria rows (a list of
/// 100,000 part numbers) cost their matches, not rows × records; other rows test every
/// record.
fn records_meeting(db: &Array, rows: &[Vec<Condition>], dates: DateSystem) -> Vec<bool> {
    let records = db.rows - 1;
    if rows.is_empty() {
        return vec![true; records];
    }
    let mut meeting = vec![false; records];
    let mut equal: HashMap<usize, EqualityIndex> = HashMap::new();
    let mut texts: HashMap<usize, TextOrder> = HashMap::new();
    let column = move |c: usize| (1..db.rows).map(move |r| db.get(r, c));
    for conditions in rows {
        let meets = |r: usize| conditions.iter().all(|(c, crit)| c.is_some_and(|c| crit.matches(db.get(r + 1, c))));
        let candidates: Box<dyn Iterator<Item = usize>> = match lookup_of(conditions) {
            Some((c, Lookup::Equal(keys))) => {
                let index = equal.entry(c).or_insert_with(|| EqualityIndex::new(column(c), dates));
                Box::new(index.positions(&keys).into_iter())
            }
            Some((c, Lookup::Prefix(letters))) => {
                let order = texts.entry(c).or_insert_with(|| TextOrder::new(column(c)));
                Box::new(order.starting_with(&letters).into_iter())
            }
            None => Box::new(0..records),
        };
        for r in candidates {
            meeting[r] = meeting[r] || meets(r);
        }
    }
    meeting
}

/// How the records a criteria row may match are found.
enum Lookup {
    /// Filed under one of these keys.
    Equal(Vec<ItemKey>),
    /// Text beginning with these lower-case letters.
    Prefix(Vec<char>),
}

/// The first condition of a criteria row an index can answer: its column and how.
fn lookup_of(conditions: &[Condition]) -> Option<(usize, Lookup)> {
    conditions.iter().find_map(|(column, criterion)| {
        let lookup = criterion.keys().map(Lookup::Equal).or_else(|| criterion.prefix().map(Lookup::Prefix))?;
        Some(((*column)?, lookup))
    })
}

/// A column's texts in the order of their lower-case letters, each with its record: the
/// texts that begin with some letters are one run of it.
struct TextOrder {
    sorted: Vec<(Vec<char>, usize)>,
}

impl TextOrder {
    fn new<'v>(cells: impl Iterator<Item = &'v Value>) -> TextOrder {
        let text = |(r, v): (usize, &Value)| if let Value::Text(t) = v { Some((lowered(t), r)) } else { None };
        let mut sorted: Vec<(Vec<char>, usize)> = cells.enumerate().filter_map(text).collect();
        sorted.sort_unstable();
        TextOrder { sorted }
    }

    /// The records whose text begins with `letters` (lower case).
    fn starting_with(&self, letters: &[char]) -> Vec<usize> {
        let start = self.sorted.partition_point(|(t, _)| t.as_slice() < letters);
        let run = self.sorted[start..].partition_point(|(t, _)| t.starts_with(letters));
        self.sorted[start..start + run].iter().map(|&(_, r)| r).collect()
    }
}

fn numbers_of(values: &[Value]) -> Vec<f64> {
    values.iter().filter_map(|v| if let Value::Number(n) = v { Some(*n) } else { None }).collect()
}

fn selected_numbers(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Vec<f64>> {
    Ok(numbers_of(&selected(ctx, args)?))
}

fn dsum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(number_result(selected_numbers(ctx, args)?.iter().fold(0.0, |a, x| a + x)))
    // not -0 for none
}

fn daverage(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = selected_numbers(ctx, args)?;
    if xs.is_empty() {
        return Err(XlError::Div0);
    }
    Ok(number_result(xs.iter().sum::<f64>() / xs.len() as f64))
}

fn dcount(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(selected_numbers(ctx, args)?.len() as f64))
}

fn dcounta(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(selected(ctx, args)?.iter().filter(|v| !v.is_blank()).count() as f64))
}

fn dget(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    match selected(ctx, args)?.as_slice() {
        [] => Err(XlError::Value),
        [one] => Ok(one.clone()),
        _ => Err(XlError::Num),
    }
}

fn dmax(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = selected_numbers(ctx, args)?;
    Ok(Value::Number(xs.iter().copied().reduce(f64::max).unwrap_or(0.0)))
}

fn dmin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = selected_numbers(ctx, args)?;
    Ok(Value::Number(xs.iter().copied().reduce(f64::min).unwrap_or(0.0)))
}

fn dproduct(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let xs = selected_numbers(ctx, args)?;
    if xs.is_empty() {
        return Ok(Value::Number(0.0));
    }
    Ok(number_result(xs.iter().product()))
}

/// The variance of the selected numbers, over n − 1 (`sample`) or n.
fn variance(ctx: &mut Ctx, args: &[Expr], sample: bool) -> XlResult<f64> {
    let xs = selected_numbers(ctx, args)?;
    let n = xs.len() as f64;
    let divisor = if sample { n - 1.0 } else { n };
    if divisor <= 0.0 {
        return Err(XlError::Div0);
    }
    let mean = xs.iter().sum::<f64>() / n;
    Ok(xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / divisor)
}

fn dvar(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(number_result(variance(ctx, args, true)?))
}

fn dvarp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(number_result(variance(ctx, args, false)?))
}

fn dstdev(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(number_result(variance(ctx, args, true)?.sqrt()))
}

fn dstdevp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(number_result(variance(ctx, args, false)?.sqrt()))
}
