//! The database functions: DSUM, DAVERAGE, DCOUNT, DCOUNTA, DGET, DMAX, DMIN, DPRODUCT,
//! DSTDEV, DSTDEVP, DVAR and DVARP. A database is a range whose first row names its fields;
//! the criteria range names fields in its first row and lists conditions below: the
//! conditions of one row must all hold, any row may. Text with no operator matches values
//! that begin with it, as in Excel's advanced filter.

use std::collections::HashMap;
use std::ops::Range;

use crate::eval::coerce::{compare_text, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{block, number_result, ArgSet, Ctx, FnSpec};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use crate::eval::functions::arrays::reshape::ItemKey;
use crate::eval::functions::criteria::{lowered, Criterion, EqualityIndex, MAX_CRITERIA_SCAN};
use crate::eval::functions::statistics::dispersion::{deviation, scaled_squared_deviations, unscaled};
use crate::eval::functions::statistics::mean;

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
    let mut lookups = Lookups::default();
    let tested = lookups.records_tested(&db, &rows, dates);
    if tested > MAX_CRITERIA_SCAN {
        let why = format!(
            "the criteria would test {tested} records one by one, more than ncsheet's limit of \
             {MAX_CRITERIA_SCAN:e} for one call (criteria rows with no plain equality such as =x or a number, nor \
             a text prefix, × the records; an equality's or a prefix's rows × the records with that value or \
             beginning; a pattern's rows × the texts that begin or end as it does)"
        );
        return Err(ctx.explain(XlError::Num, why));
    }
    // Inside MAP's LAMBDA the records are weighed against what is left of the budget before
    // they are tested: counted only afterwards, one call could test far past it.
    ctx.within_lambda_budget(db.rows.saturating_add(tested))?;
    let meeting = lookups.records_meeting(&db, &rows, dates);
    ctx.charge(db.rows.saturating_add(tested));
    let mut out = Vec::new();
    for r in (0..records).filter(|&r| meeting[r]) {
        // DCOUNT with no field counts records: each stands as a number.
        out.push(column.map_or(Value::Number(1.0), |c| db.get(r + 1, c).clone()));
    }
    Ok(out)
}

/// The indexes of the database's columns that criteria rows look their records up in,
/// built at the first row that needs each.
#[derive(Default)]
struct Lookups {
    equal: HashMap<usize, EqualityIndex>,
    /// A column's texts in order, and in the order of their reversed letters.
    starts: HashMap<usize, TextOrder>,
    ends: HashMap<usize, TextOrder>,
}

/// The records a criteria row may match, to be tested against its conditions.
enum Candidates {
    These(Vec<usize>),
    Every,
}

impl Lookups {
    /// How many records the rows test one by one: every record for a row no index
    /// answers, for an equality's row the records filed under its value, for a prefix's
    /// the texts that begin with it, and for a pattern's row the texts that begin or end
    /// with its letters (many rows naming one common value test its records each time).
    fn records_tested(&mut self, db: &Array, rows: &[Vec<Condition>], dates: DateSystem) -> usize {
        let records = db.rows - 1;
        rows.iter()
            .map(|conditions| match lookup_of(conditions) {
                None => records,
                Some((c, Lookup::Equal(keys))) => self.equal_index(db, c, dates).count_filed(&keys),
                Some((c, Lookup::Prefix(letters))) => self.starts(db, c).run(&letters).len(),
                Some((c, Lookup::Pattern(prefix, suffix))) => self.pattern_run(db, c, &prefix, &suffix).1.len(),
            })
            .fold(0, usize::saturating_add)
    }

    fn equal_index(&mut self, db: &Array, c: usize, dates: DateSystem) -> &EqualityIndex {
        self.equal.entry(c).or_insert_with(|| EqualityIndex::new(column(db, c), dates))
    }

    /// Whether each record (row 1 … of `db`, from 0) meets the conditions of some criteria
    /// row. A row with an equality condition (`=x`, a number, TRUE) tests only the records
    /// an index of that column files under its value, a row with a text prefix (`bol`)
    /// only the records whose text there begins with it, and a row with a pattern only the
    /// texts that begin with its first letters or end with its last (`b?lt`, `*bolt`:
    /// whichever are fewer), so that many criteria rows (a list of 100,000 part numbers)
    /// cost their matches, not rows × records; other rows test every record.
    fn records_meeting(&mut self, db: &Array, rows: &[Vec<Condition>], dates: DateSystem) -> Vec<bool> {
        let records = db.rows - 1;
        if rows.is_empty() {
            return vec![true; records];
        }
        let mut meeting = vec![false; records];
        for conditions in rows {
            let meets = |r: usize| conditions.iter().all(|(c, crit)| c.is_some_and(|c| crit.matches(db.get(r + 1, c))));
            let candidates = match lookup_of(conditions) {
                Some((c, Lookup::Equal(keys))) => Candidates::These(self.equal_index(db, c, dates).positions(&keys)),
                Some((c, Lookup::Prefix(letters))) => Candidates::These(self.starts(db, c).starting_with(&letters)),
                Some((c, Lookup::Pattern(prefix, suffix))) => {
                    let (order, run) = self.pattern_run(db, c, &prefix, &suffix);
                    Candidates::These(order.records(run))
                }
                None => Candidates::Every,
            };
            match candidates {
                Candidates::These(records) => records.into_iter().for_each(|r| meeting[r] = meeting[r] || meets(r)),
                Candidates::Every => (0..records).for_each(|r| meeting[r] = meeting[r] || meets(r)),
            }
        }
        meeting
    }

    fn starts(&mut self, db: &Array, c: usize) -> &TextOrder {
        self.starts.entry(c).or_insert_with(|| TextOrder::new(column(db, c), false))
    }

    /// Where the records a pattern's row may match lie: the run of column `c`'s texts that
    /// begin with `prefix` or the run of those that end with `suffix`, the shorter.
    fn pattern_run(&mut self, db: &Array, c: usize, prefix: &[char], suffix: &[char]) -> (&TextOrder, Range<usize>) {
        self.starts.entry(c).or_insert_with(|| TextOrder::new(column(db, c), false));
        self.ends.entry(c).or_insert_with(|| TextOrder::new(column(db, c), true));
        let (starts, ends) = (&self.starts[&c], &self.ends[&c]);
        let reversed: Vec<char> = suffix.iter().rev().copied().collect();
        let (beginning, ending) = (starts.run(prefix), ends.run(&reversed));
        if beginning.len() <= ending.len() {
            (starts, beginning)
        } else {
            (ends, ending)
        }
    }
}

/// Column `c`'s records.
fn column(db: &Array, c: usize) -> impl Iterator<Item = &Value> {
    (1..db.rows).map(move |r| db.get(r, c))
}

/// How the records a criteria row may match are found.
enum Lookup {
    /// Filed under one of these keys.
    Equal(Vec<ItemKey>),
    /// Text beginning with these lower-case letters.
    Prefix(Vec<char>),
    /// Text matching a pattern that begins with the first letters and ends with the
    /// second (one may be empty).
    Pattern(Vec<char>, Vec<char>),
}

/// The first condition of a criteria row an index can answer: its column and how.
fn lookup_of(conditions: &[Condition]) -> Option<(usize, Lookup)> {
    let exact = conditions.iter().find_map(|(column, criterion)| {
        let lookup = criterion.keys().map(Lookup::Equal).or_else(|| criterion.prefix().map(Lookup::Prefix))?;
        Some(((*column)?, lookup))
    });
    exact.or_else(|| {
        conditions.iter().find_map(|(column, criterion)| {
            let (prefix, suffix) = criterion.literal_ends()?;
            let named = !(prefix.is_empty() && suffix.is_empty());
            named.then_some(((*column)?, Lookup::Pattern(prefix, suffix)))
        })
    })
}

/// A column's texts in the order of their lower-case letters, each with its record: the
/// texts that begin with some letters are one run of it.
struct TextOrder {
    sorted: Vec<(Vec<char>, usize)>,
}

impl TextOrder {
    /// The texts of `cells` in order, or (`reversed`) in the order of their letters read
    /// from the end, so that the texts ending with some letters are one run.
    fn new<'v>(cells: impl Iterator<Item = &'v Value>, reversed: bool) -> TextOrder {
        let letters = |t: &str| {
            let mut letters = lowered(t);
            if reversed {
                letters.reverse();
            }
            letters
        };
        let text = |(r, v): (usize, &Value)| if let Value::Text(t) = v { Some((letters(t), r)) } else { None };
        let mut sorted: Vec<(Vec<char>, usize)> = cells.enumerate().filter_map(text).collect();
        sorted.sort_unstable();
        TextOrder { sorted }
    }

    /// The records whose text begins with `letters` (lower case).
    fn starting_with(&self, letters: &[char]) -> Vec<usize> {
        self.records(self.run(letters))
    }

    /// Where the texts that begin with `letters` lie in the order: two binary searches.
    fn run(&self, letters: &[char]) -> Range<usize> {
        let start = self.sorted.partition_point(|(t, _)| t.as_slice() < letters);
        let run = self.sorted[start..].partition_point(|(t, _)| t.starts_with(letters));
        start..start + run
    }

    fn records(&self, run: Range<usize>) -> Vec<usize> {
        self.sorted[run].iter().map(|&(_, r)| r).collect()
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
    Ok(number_result(mean(&xs)))
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

/// The variance of the selected numbers, over n − 1 (`sample`) or n, at the scale VAR
/// computes it (`scaled_squared_deviations`: finite wherever the result is).
fn variance(ctx: &mut Ctx, args: &[Expr], sample: bool) -> XlResult<(f64, f64)> {
    let xs = selected_numbers(ctx, args)?;
    let n = xs.len() as f64;
    let divisor = if sample { n - 1.0 } else { n };
    if divisor <= 0.0 {
        return Err(XlError::Div0);
    }
    let (squares, scale) = scaled_squared_deviations(&xs);
    Ok((squares / divisor, scale))
}

fn dvar(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(unscaled(variance(ctx, args, true)?))
}

fn dvarp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(unscaled(variance(ctx, args, false)?))
}

fn dstdev(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(deviation(variance(ctx, args, true)?))
}

fn dstdevp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(deviation(variance(ctx, args, false)?))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::{n, MapEnv};
    use crate::eval::value::Value;

    /// Texts of a's and b's in both cases (and a `*`, a `?`), and patterns of those letters
    /// with wildcards, drawn from a fixed sequence.
    fn generated(seed: u64) -> (MapEnv, Vec<String>) {
        let mut state = seed;
        let mut next = |below: u64| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % below
        };
        let mut word = |letters: &[char], most: u64| -> String {
            let len = next(most + 1);
            (0..len).map(|_| letters[next(letters.len() as u64) as usize]).collect()
        };
        let mut env = MapEnv::default();
        env.cells.insert((0, 0), Value::text("Part"));
        env.cells.insert((0, 1), Value::text("Qty"));
        for row in 1..200 {
            env.cells.insert((row, 0), Value::text(word(&['a', 'b', 'A', 'B', '*', '?'], 5)));
            env.cells.insert((row, 1), n(1.0));
        }
        let patterns = (0..60).map(|_| word(&['a', 'b', 'B', '?', '*', '~'], 5)).collect();
        (env, patterns)
    }

    /// A criteria row with a pattern looks up the texts that begin or end with its letters;
    /// COUNTIF with the same criterion tests every cell (its rules checked in criteria.rs):
    /// the records counted are the same.
    #[test]
    fn pattern_rows_find_the_records_a_scan_finds() {
        for seed in 0..8 {
            let (env, patterns) = generated(seed);
            for pattern in patterns {
                let quoted = pattern.replace('"', "\"\"");
                let looked_up = env.eval(&format!("=DCOUNT(A1:B200,\"Qty\",VSTACK(\"Part\",\"={quoted}\"))"));
                let scanned = env.eval(&format!("=COUNTIF(A2:A200,\"={quoted}\")"));
                assert_eq!(looked_up, scanned, "={pattern}");
            }
        }
    }
}
