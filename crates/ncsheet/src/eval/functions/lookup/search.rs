//! Lookup and reference functions. INDEX, CHOOSE (in logic) and XLOOKUP return references
//! when given references, so that `SUM(A1:INDEX(A1:A9, n))` works as in Excel.

use std::cell::{Cell, OnceCell, RefCell};
use std::cmp::Ordering;
use std::rc::Rc;

use crate::eval::coerce::{compare, compare_text, to_bool, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{as_block, lift_values, number_or, ArgSet, Ctx, FnSpec, Operand, Searched};
use crate::eval::functions::lookup::key_index::{worth_indexing, ExactIndex, OrderIndex};
use crate::eval::regex_limits;
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, ExprKind, SheetId};

use crate::eval::functions::text::strings::Wildcard;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::reference(
        "INDEX",
        2,
        4,
        index,
        "INDEX(array, row, [column], [area])",
        "The cell (a reference) or item at row and column; 0 or omitted takes the whole row or column",
    )
    .biff(29).array_args(ArgSet::only(0)).position_arg(),
    FnSpec::value(
        "AREAS",
        1,
        1,
        areas,
        "AREAS(reference)",
        "Number of areas of a reference: (A1:B2,D4) has 2",
    )
    .biff(75).range_args(ArgSet::ALL).position_arg(),
    FnSpec::value(
        "MATCH",
        2,
        3,
        match_fn,
        "MATCH(value, lookup_array, [match_type])",
        "Position of value: 1 largest <= (sorted ascending), 0 exact with wildcards, -1 smallest >= (sorted descending)",
    )
    .biff(64).array_args(ArgSet::only(1)),
    FnSpec::value(
        "VLOOKUP",
        3,
        4,
        vlookup,
        "VLOOKUP(value, table, column, [approximate])",
        "Finds value in the table's first column and returns that row's column-th item",
    )
    .biff(102).array_args(ArgSet::only(1)).picks_from(1, Searched::FirstColumn),
    FnSpec::value(
        "HLOOKUP",
        3,
        4,
        hlookup,
        "HLOOKUP(value, table, row, [approximate])",
        "Finds value in the table's first row and returns that column's row-th item",
    )
    .biff(101).array_args(ArgSet::only(1)).picks_from(1, Searched::FirstRow),
    FnSpec::reference(
        "XLOOKUP",
        3,
        6,
        xlookup,
        "XLOOKUP(value, lookup_array, return_array, [if_not_found], [match_mode], [search_mode])",
        "The return_array row or column at value's position in lookup_array",
    ).future().dynamic().picks_from(2, Searched::Nothing),
    FnSpec::value(
        "XMATCH",
        2,
        4,
        xmatch,
        "XMATCH(value, lookup_array, [match_mode], [search_mode])",
        "Position of value, with XLOOKUP's match and search modes",
    ).future().array_args(ArgSet::only(1)),
    FnSpec::value(
        "LOOKUP",
        2,
        3,
        lookup_fn,
        "LOOKUP(value, lookup_vector, [result_vector])",
        "Approximate lookup in sorted data: the result at the last position not above value",
    )
    .biff(28).array_args(ArgSet::from(1)).picks_from(2, Searched::Nothing),
    FnSpec::value(
        "ROW",
        0,
        1,
        row,
        "ROW([reference])",
        "Row number of a reference (of the formula's cell when omitted)",
    )
    .biff(8).range_args(ArgSet::only(0)).position_arg(),
    FnSpec::value(
        "COLUMN",
        0,
        1,
        column,
        "COLUMN([reference])",
        "Column number of a reference (of the formula's cell when omitted)",
    )
    .biff(9).range_args(ArgSet::only(0)).position_arg(),
    FnSpec::value(
        "ROWS",
        1,
        1,
        rows,
        "ROWS(array)",
        "Number of rows of a reference or array",
    )
    .biff(76).range_args(ArgSet::ALL).position_arg(),
    FnSpec::value(
        "COLUMNS",
        1,
        1,
        columns,
        "COLUMNS(array)",
        "Number of columns of a reference or array",
    )
    .biff(77).range_args(ArgSet::ALL).position_arg(),
];

// ---------------------------------------------------------------------------------------
// INDEX

fn index(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    index_operand(ctx, args).unwrap_or_else(|e| Operand::Value(Value::Error(e)))
}

fn index_operand(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Operand> {
    let dates = ctx.dates();
    let source = ctx.operand(&args[0]);
    let row_arg = optional_value(ctx, args, 1);
    let col_arg = optional_value(ctx, args, 2);
    let col_given = args.len() > 2;
    let source = pick_area(source, number_or(ctx, args, 3, 1.0)?)?;
    if let Operand::Value(Value::Error(e)) = source {
        return Err(e);
    }
    if matches!(row_arg, Value::Array(_)) || matches!(col_arg, Value::Array(_)) {
        // Arrays of positions pick item by item (Excel 365 spills the result): the whole
        // reference is read, and linked as read (the graph has no edge from it).
        if let Operand::Ref(sheet, rect) = source {
            ctx.note_dynamic_ref(sheet, rect);
        }
        let grid = grid_of(ctx, source)?;
        let picked = lift_values(&[row_arg, col_arg], &|v| {
            let (rows, cols) = pick(grid.rows, grid.cols, &v[0], &v[1], col_given, dates)?;
            Ok(sub_array(&grid, rows, cols))
        })?;
        return Ok(Operand::Value(picked));
    }
    match source {
        Operand::Ref(sheet, rect) => {
            let (rows, cols) = pick(rect.rows() as usize, rect.cols() as usize, &row_arg, &col_arg, col_given, dates)?;
            // Only the cells returned are read: they are this formula's link, made at run time
            // as OFFSET's (crates/ncsheet/src/workbook/shared.rs gives the whole reference no edge).
            let picked = sub_rect(rect, rows, cols);
            ctx.note_dynamic_ref(sheet, picked);
            Ok(Operand::Ref(sheet, picked))
        }
        Operand::Value(v) => {
            let grid = grid_of(ctx, Operand::Value(v))?;
            let (rows, cols) = pick(grid.rows, grid.cols, &row_arg, &col_arg, col_given, dates)?;
            Ok(Operand::Value(sub_array(&grid, rows, cols)))
        }
        // `pick_area` chose one area above.
        Operand::Areas(_) => Err(XlError::Ref),
    }
}

/// INDEX's `area`: which area of a multi-area reference (1 for anything else); past the
/// areas there are is `#REF!`.
fn pick_area(source: Operand, area: f64) -> XlResult<Operand> {
    let area = area.trunc();
    match source {
        Operand::Areas(areas) if area >= 1.0 && area <= areas.len() as f64 => {
            let (sheet, rect) = areas[area as usize - 1];
            Ok(Operand::Ref(sheet, rect))
        }
        Operand::Areas(_) => Err(XlError::Ref),
        _ if area != 1.0 => Err(XlError::Ref),
        other => Ok(other),
    }
}

/// How many areas a reference has; a value is no reference (`#VALUE!`).
fn areas(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    match ctx.reference_only(&args[0]) {
        Operand::Ref(..) => Ok(Value::Number(1.0)),
        Operand::Areas(areas) => Ok(Value::Number(areas.len() as f64)),
        Operand::Value(Value::Error(err)) => Err(err),
        Operand::Value(_) => Err(XlError::Value),
    }
}

/// An optional argument's value; omitted or empty reads as blank (INDEX's "0").
fn optional_value(ctx: &mut Ctx, args: &[Expr], i: usize) -> Value {
    match args.get(i) {
        Some(e) if e.kind != ExprKind::Missing => ctx.eval(e),
        _ => Value::Blank,
    }
}

/// A span of 0-based indexes, `start..start + len`.
type Span = (usize, usize);

/// Which rows and columns INDEX selects from a `rows`×`cols` block. With one index, a
/// single-row block is indexed by column (`INDEX({1,2,3}, 2)` is 2).
fn pick(
    rows: usize,
    cols: usize,
    row: &Value,
    col: &Value,
    col_given: bool,
    dates: DateSystem,
) -> XlResult<(Span, Span)> {
    let r = position(row, dates)?;
    let c = position(col, dates)?;
    let (r, c) = if rows == 1 && !col_given { (c, r) } else { (r, c) };
    Ok((span(r, rows)?, span(c, cols)?))
}

/// An INDEX position: truncated, 0 for "all", negative `#VALUE!`.
fn position(v: &Value, dates: DateSystem) -> XlResult<usize> {
    let n = to_number(v, dates)?.trunc();
    if n < 0.0 {
        return Err(XlError::Value);
    }
    Ok(n as usize)
}

fn span(position: usize, len: usize) -> XlResult<Span> {
    match position {
        0 => Ok((0, len)),
        p if p <= len => Ok((p - 1, 1)),
        _ => Err(XlError::Ref),
    }
}

fn sub_rect(rect: Rect, rows: Span, cols: Span) -> Rect {
    let first = Pos::new(rect.first.row + rows.0 as u32, rect.first.col + cols.0 as u32);
    let last = Pos::new(first.row + rows.1 as u32 - 1, first.col + cols.1 as u32 - 1);
    Rect { first, last }
}

fn sub_array(grid: &Array, rows: Span, cols: Span) -> Value {
    let mut data = Vec::with_capacity(rows.1 * cols.1);
    for r in rows.0..rows.0 + rows.1 {
        for c in cols.0..cols.0 + cols.1 {
            data.push(grid.get(r, c).clone());
        }
    }
    Value::from(Array::new(rows.1, cols.1, data)).unwrap_single()
}

/// An operand's values as a block: a reference's cells (blanks included) or an array; a
/// scalar is 1×1.
fn grid_of(ctx: &mut Ctx, operand: Operand) -> XlResult<Rc<Array>> {
    as_block(ctx.deref(operand))
}

// ---------------------------------------------------------------------------------------
// Searching

/// What to return when the value itself is not present.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Fallback {
    None,
    NextSmaller,
    NextLarger,
}

/// The order lookups use within one kind of value; values of different kinds never
/// match (`MATCH(1, {"1"}, 0)` is #N/A).
fn same_kind_order(a: &Value, b: &Value) -> Option<Ordering> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.partial_cmp(y),
        (Value::Text(x), Value::Text(y)) => Some(compare_text(x, y)),
        (Value::Bool(x), Value::Bool(y)) => Some(x.cmp(y)),
        _ => None,
    }
}

/// An exact-match test; text with wildcards (when allowed) matches by pattern.
struct ExactMatcher<'a> {
    key: &'a Value,
    pattern: Option<Wildcard>,
}

impl<'a> ExactMatcher<'a> {
    fn new(key: &'a Value, wildcards: bool) -> ExactMatcher<'a> {
        let pattern = match key {
            Value::Text(s) if wildcards && Wildcard::has_wildcards(s) => Some(Wildcard::new(s)),
            _ => None,
        };
        ExactMatcher { key, pattern }
    }

    fn matches(&self, item: &Value) -> bool {
        match (&self.pattern, item) {
            (Some(p), Value::Text(s)) => p.matches(s),
            (Some(_), _) => false,
            (None, _) => same_kind_order(self.key, item) == Some(Ordering::Equal),
        }
    }
}

/// Index of the first (or last, when `reverse`) item matching exactly.
fn find_exact(key: &Value, items: &[Value], wildcards: bool, reverse: bool) -> Option<usize> {
    let m = ExactMatcher::new(key, wildcards);
    if reverse {
        items.iter().rposition(|v| m.matches(v))
    } else {
        items.iter().position(|v| m.matches(v))
    }
}

/// A lookup call's items, with the indexes it builds once when it looks up many keys
/// (`MATCH(SEQUENCE(100000), items, 0)` was 100,000 scans of the items). Searches count
/// what they look at; an index counts its building and one item a query.
struct Haystack<'a> {
    items: &'a [Value],
    /// Whether the call looks up enough keys for the indexes to pay.
    many: bool,
    /// Built at the first key looked up exactly (binary and regex searches never use it).
    exact: OnceCell<ExactIndex>,
    /// Built at the first key that needs the next smaller or larger item.
    ordered: OnceCell<OrderIndex<'a>>,
}

impl<'a> Haystack<'a> {
    /// `keys` is the lookup's first argument: an array of many keys has the items indexed.
    fn new(items: &'a [Value], keys: &Value) -> Haystack<'a> {
        Haystack { items, many: worth_indexing(keys), exact: OnceCell::new(), ordered: OnceCell::new() }
    }

    /// The exact-match index, built (and its building counted) at its first use.
    fn exact(&self, looked: &Cell<usize>) -> Option<&ExactIndex> {
        self.many.then(|| {
            self.exact.get_or_init(|| {
                add(looked, self.items.len());
                ExactIndex::new(self.items)
            })
        })
    }

    /// [`find_exact`], through the index when there is one and the key is no pattern.
    fn find_exact(&self, key: &Value, wildcards: bool, reverse: bool, looked: &Cell<usize>) -> Option<usize> {
        let pattern = wildcards && matches!(key, Value::Text(s) if Wildcard::has_wildcards(s));
        if let Some(index) = (!pattern).then(|| self.exact(looked)).flatten() {
            add(looked, 1);
            return index.find(key, reverse);
        }
        let found = find_exact(key, self.items, wildcards, reverse);
        add(looked, looked_at(found, self.items.len(), reverse));
        found
    }

    /// The first (last when `reverse`) empty item.
    fn find_blank(&self, reverse: bool, looked: &Cell<usize>) -> Option<usize> {
        if let Some(index) = self.exact(looked) {
            add(looked, 1);
            return index.find_blank(reverse);
        }
        let items = self.items;
        let blank =
            if reverse { items.iter().rposition(Value::is_blank) } else { items.iter().position(Value::is_blank) };
        add(looked, looked_at(blank, items.len(), reverse));
        blank
    }

    /// The closest item on the `fallback` side of a key not found.
    fn closest(&self, key: &Value, fallback: Fallback, reverse: bool, looked: &Cell<usize>) -> Option<usize> {
        if !self.many {
            add(looked, self.items.len());
            return closest_by_scan(key, self.items, fallback, reverse);
        }
        let ordered = self.ordered.get_or_init(|| {
            let n = self.items.len();
            add(looked, n.saturating_mul((usize::BITS - n.leading_zeros()) as usize));
            OrderIndex::new(self.items)
        });
        add(looked, ordered.query_work());
        match fallback {
            Fallback::NextSmaller => ordered.next_smaller(key, reverse),
            Fallback::NextLarger => ordered.next_larger(key, reverse),
            Fallback::None => None,
        }
    }
}

/// The items a search from the front (from the back when `reverse`) of `len` items looked at
/// to find `found`: all of them when it found nothing.
fn looked_at(found: Option<usize>, len: usize, reverse: bool) -> usize {
    match found {
        Some(i) if reverse => len - i,
        Some(i) => i + 1,
        None => len,
    }
}

/// `order`, counting each item it compares in `looked`. A lookup charges what it looked at
/// against the LAMBDA work budget (`Ctx::charge`): inside MAP's LAMBDA, a MATCH over an array
/// bound outside it (`MAP(SEQUENCE(100000),LAMBDA(i,MATCH(i,big,0)))`) scans it at every call.
fn counting<'a>(
    looked: &'a Cell<usize>,
    order: fn(&Value, &Value) -> Option<Ordering>,
) -> impl Fn(&Value, &Value) -> Option<Ordering> + 'a {
    move |a, b| {
        looked.set(looked.get() + 1);
        order(a, b)
    }
}

/// Adds `work` to the items `looked` counts.
fn add(looked: &Cell<usize>, work: usize) {
    looked.set(looked.get().saturating_add(work));
}

/// Excel's approximate search on data sorted by `order` (ascending for MATCH 1 and
/// VLOOKUP, reversed for MATCH -1): a binary search for the last item not after the key.
/// Items of another kind are stepped over, as Excel does, so a sorted column with a
/// few text cells still works.
fn binary_search_last_not_after(
    key: &Value,
    items: &[Value],
    order: impl Fn(&Value, &Value) -> Option<Ordering>,
) -> Option<usize> {
    // Invariant: items at or before `lo` are not after the key, items at or after `hi` are.
    let (mut lo, mut hi) = (-1_isize, items.len() as isize);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        let Some(probe) = (mid..hi).find(|&i| order(&items[i as usize], key).is_some()) else {
            hi = mid;
            continue;
        };
        match order(&items[probe as usize], key) {
            Some(Ordering::Greater) => hi = probe,
            Some(Ordering::Equal) => return Some(last_of_equal_run(key, items, probe, &order)),
            _ => lo = probe,
        }
    }
    (lo >= 0).then_some(lo as usize)
}

/// Approximate lookups return the last of several equal items.
fn last_of_equal_run(
    key: &Value,
    items: &[Value],
    mut i: isize,
    order: &impl Fn(&Value, &Value) -> Option<Ordering>,
) -> usize {
    while let Some(next) = items.get(i as usize + 1) {
        if order(next, key) != Some(Ordering::Equal) {
            break;
        }
        i += 1;
    }
    i as usize
}

fn ascending(a: &Value, b: &Value) -> Option<Ordering> {
    same_kind_order(a, b)
}

fn descending(a: &Value, b: &Value) -> Option<Ordering> {
    same_kind_order(a, b).map(Ordering::reverse)
}

/// A lookup range or array as one line of values (`None` when it is 2-D).
fn line_of(grid: &Array) -> Option<&[Value]> {
    (grid.rows == 1 || grid.cols == 1).then_some(&grid.data[..])
}

// ---------------------------------------------------------------------------------------
// MATCH, VLOOKUP, HLOOKUP

fn match_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let key = ctx.eval(&args[0]);
    let haystack = grid_of_expr(ctx, &args[1])?;
    // Omitted is 1; left empty (`MATCH(x, r, )`) is 0, as Excel reads empty arguments.
    let match_type = match args.get(2) {
        None => 1.0,
        Some(e) => to_number(&ctx.eval(e), dates)?,
    };
    let items = line_of(&haystack).ok_or(XlError::NA)?;
    let looked = Cell::new(0);
    let exact = Haystack::new(items, if match_type == 0.0 { &key } else { &Value::Blank });
    let found = lift_values(&[key], &|v| {
        let key = lookup_key(&v[0])?;
        let found = if match_type == 0.0 {
            exact.find_exact(&key, true, false, &looked)
        } else if match_type > 0.0 {
            binary_search_last_not_after(&key, items, counting(&looked, ascending))
        } else {
            binary_search_last_not_after(&key, items, counting(&looked, descending))
        };
        found.map(|i| Value::Number(i as f64 + 1.0)).ok_or(XlError::NA)
    });
    ctx.charge(looked.get());
    found
}

/// The value a lookup searches for; an error is the result, an empty cell looks for 0
/// as Excel does.
fn lookup_key(v: &Value) -> XlResult<Value> {
    match v {
        Value::Error(e) => Err(*e),
        Value::Blank => Ok(Value::Number(0.0)),
        v => Ok(v.clone()),
    }
}

fn grid_of_expr(ctx: &mut Ctx, e: &Expr) -> XlResult<Rc<Array>> {
    let operand = ctx.operand(e);
    grid_of(ctx, operand)
}

fn vlookup(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    table_lookup(ctx, args, false)
}

fn hlookup(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    table_lookup(ctx, args, true)
}

/// VLOOKUP, and HLOOKUP as VLOOKUP on the transposed table. A range or array of values
/// looks each one up, as Excel 365 does (`VLOOKUP(A1:A6,T,2,0)` spills six results; the
/// xlsx reader intersects it in a legacy formula, as Excel did when it saved the value).
fn table_lookup(ctx: &mut Ctx, args: &[Expr], by_row: bool) -> XlResult<Value> {
    let key = ctx.eval(&args[0]);
    // A one-cell reference is a 1×1 table; typed text is no table at all.
    let mut place = None;
    let table = match ctx.operand(&args[1]) {
        Operand::Value(Value::Text(_)) => Err(XlError::Value),
        Operand::Ref(sheet, rect) => {
            place = Some((sheet, rect));
            grid_of(ctx, Operand::Ref(sheet, rect))
        }
        operand => grid_of(ctx, operand),
    };
    let offset = ctx.eval(&args[2]);
    let one_result = !matches!(key, Value::Array(_)) && !matches!(offset, Value::Array(_));
    let approximate = approximate_flag(ctx, args.get(3))?;
    let dates = ctx.dates();
    let table = table.map(|t| TableLookup::new(t, by_row));
    // Its first column (row) is copied, and each key's search counted.
    let looked = Cell::new(table.as_ref().map_or(0, |t| t.keys.len()));
    let keys = if approximate { &Value::Blank } else { &key };
    let exact = table.as_ref().map(|t| Haystack::new(&t.keys, keys));
    let picked = Cell::new(None);
    // An array of columns returns each (`SUM(VLOOKUP(x,T,{2,3},0))`), as in Excel.
    let found = lift_values(&[key, offset], &|v| {
        let key = lookup_key(&v[0])?;
        let (table, exact) = (table.as_ref().map_err(|e| *e)?, exact.as_ref().map_err(|e| **e)?);
        let (line, at) = table.find(&key, &v[1], approximate, dates, exact, &looked)?;
        picked.set(Some(if by_row { (at, line) } else { (line, at) }));
        Ok(table.at(line, at).clone())
    });
    ctx.charge(looked.get());
    if let (Some((sheet, rect)), Some((row, col))) = (place, picked.get()) {
        // Beyond the searched line (linked in the graph: FnSpec::picked_arg) only the cell
        // returned is read; many results may come from anywhere in the table.
        let cell = Pos::new(rect.first.row + row as u32, rect.first.col + col as u32);
        ctx.note_dynamic_ref(sheet, if one_result { Rect { first: cell, last: cell } } else { rect });
    }
    found
}

/// A VLOOKUP or HLOOKUP table with its first column (row) read once for every key.
struct TableLookup {
    table: Rc<Array>,
    by_row: bool,
    keys: Vec<Value>,
}

impl TableLookup {
    fn new(table: Rc<Array>, by_row: bool) -> Self {
        let length = if by_row { table.cols } else { table.rows };
        let mut lookup = TableLookup { table, by_row, keys: Vec::new() };
        lookup.keys = (0..length).map(|i| lookup.at(i, 0).clone()).collect();
        lookup
    }

    fn at(&self, i: usize, j: usize) -> &Value {
        if self.by_row {
            self.table.get(j, i)
        } else {
            self.table.get(i, j)
        }
    }

    /// Where the item at `offset` in the line `key` is found on is (line, place in it); the
    /// items the search looked at are added to `looked`.
    fn find(
        &self,
        key: &Value,
        offset: &Value,
        approximate: bool,
        dates: DateSystem,
        exact: &Haystack,
        looked: &Cell<usize>,
    ) -> XlResult<(usize, usize)> {
        let offset = to_number(offset, dates)?.trunc();
        let width = if self.by_row { self.table.rows } else { self.table.cols };
        if offset < 1.0 {
            return Err(XlError::Value);
        }
        if offset > width as f64 {
            return Err(XlError::Ref);
        }
        let found = if approximate {
            binary_search_last_not_after(key, &self.keys, counting(looked, ascending))
        } else {
            exact.find_exact(key, true, false, looked)
        };
        let i = found.ok_or(XlError::NA)?;
        Ok((i, offset as usize - 1))
    }
}

/// VLOOKUP's fourth argument: TRUE when omitted, FALSE when left empty (`VLOOKUP(a,b,2,)`).
fn approximate_flag(ctx: &mut Ctx, arg: Option<&Expr>) -> XlResult<bool> {
    match arg {
        None => Ok(true),
        Some(e) if e.kind == ExprKind::Missing => Ok(false),
        Some(e) => to_bool(&ctx.eval(e)),
    }
}

// ---------------------------------------------------------------------------------------
// XLOOKUP

/// A lookup or return argument: its values and, for a reference, where they are.
struct Source {
    /// Rows and columns as written (a whole column counts all its rows).
    rows: usize,
    cols: usize,
    values: Rc<Array>,
    place: Option<(SheetId, Rect)>,
}

fn source_of(ctx: &mut Ctx, e: &Expr) -> XlResult<Source> {
    match ctx.operand(e) {
        Operand::Ref(sheet, rect) => Ok(Source {
            rows: rect.rows() as usize,
            cols: rect.cols() as usize,
            values: grid_of(ctx, Operand::Ref(sheet, rect))?,
            place: Some((sheet, rect)),
        }),
        operand => {
            let values = grid_of(ctx, operand)?;
            Ok(Source { rows: values.rows, cols: values.cols, values, place: None })
        }
    }
}

fn xlookup(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    xlookup_operand(ctx, args).unwrap_or_else(|e| Operand::Value(Value::Error(e)))
}

fn xlookup_operand(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Operand> {
    let key = ctx.eval(&args[0]);
    let lookup = source_of(ctx, &args[1])?;
    let result = source_of(ctx, &args[2])?;
    let mode = XMode::read(ctx, args, 4)?;
    let vertical = lookup.cols == 1;
    if lookup.rows != 1 && !vertical {
        return Err(XlError::Value);
    }
    let length = if vertical { lookup.rows } else { lookup.cols };
    if (vertical && result.rows != length) || (!vertical && result.cols != length) {
        return Err(XlError::Value);
    }
    let looked = Cell::new(0);
    let items = Haystack::new(&lookup.values.data, &key);
    let not_found = args.get(3).filter(|e| e.kind != ExprKind::Missing);
    if let Value::Array(_) = key {
        // One lookup per key; each result must be a single item.
        let fallback = not_found.map(|e| ctx.eval(e));
        let picked = lift_values(&[key], &|v| match mode.find(&v[0], &items, &looked)? {
            Some(i) => Ok(result_line(&result, i, vertical).unwrap_single()),
            None => fallback.clone().ok_or(XlError::NA),
        });
        ctx.charge(looked.get());
        mode.explain(ctx, "XLOOKUP");
        // Each key may pick anywhere in the return array (FnSpec::picked_arg: no edge).
        if let Some((sheet, rect)) = result.place {
            ctx.note_dynamic_ref(sheet, rect);
        }
        return Ok(Operand::Value(picked?));
    }
    let found = mode.find(&key, &items, &looked);
    ctx.charge(looked.get());
    mode.explain(ctx, "XLOOKUP");
    match found? {
        Some(i) => Ok(match result.place {
            Some((sheet, rect)) => {
                let (rows, cols) = line_span(&result, i, vertical);
                // The line returned is the only part of the return array read: its link,
                // made at run time (FnSpec::picked_arg).
                let line = sub_rect(rect, rows, cols);
                ctx.note_dynamic_ref(sheet, line);
                Operand::Ref(sheet, line)
            }
            None => Operand::Value(result_line(&result, i, vertical)),
        }),
        None => match not_found {
            Some(e) => Ok(ctx.operand(e)),
            None => Err(XlError::NA),
        },
    }
}

/// XLOOKUP and XMATCH's match mode (0 exact, -1 or next smaller, 1 or next larger,
/// 2 wildcards, 3 a regular expression) and search mode (1 first to last, -1 last to first,
/// 2 and -2 binary on data sorted ascending or descending).
struct XMode {
    fallback: Fallback,
    wildcards: bool,
    regex: bool,
    search: i64,
    /// Why match mode 3 was refused (a limit of `regex_limits`), for the cell's note: the
    /// lookups run where the context cannot be reached.
    refusal: RefCell<Option<String>>,
}

impl XMode {
    /// Reads the two modes from `args[at]` and `args[at + 1]`.
    fn read(ctx: &mut Ctx, args: &[Expr], at: usize) -> XlResult<XMode> {
        let match_mode = number_or(ctx, args, at, 0.0)?.trunc();
        let search = number_or(ctx, args, at + 1, 1.0)?.trunc() as i64;
        let fallback = match match_mode as i64 {
            0 | 2 | 3 => Fallback::None,
            -1 => Fallback::NextSmaller,
            1 => Fallback::NextLarger,
            _ => return Err(XlError::Value),
        };
        let (wildcards, regex) = (match_mode == 2.0, match_mode == 3.0);
        if !matches!(search, 1 | -1 | 2 | -2) || ((wildcards || regex) && search.abs() == 2) {
            return Err(XlError::Value);
        }
        Ok(XMode { fallback, wildcards, regex, search, refusal: RefCell::default() })
    }

    /// Names in the cell's note the limit match mode 3 met, if it met one.
    fn explain(&self, ctx: &mut Ctx, name: &str) {
        if let Some(why) = self.refusal.take() {
            ctx.explain(XlError::Num, format!("{name}: {why}"));
        }
    }

    /// The position of `key` in `items`; the items looked at are added to `looked`.
    fn find(&self, key: &Value, items: &Haystack, looked: &Cell<usize>) -> XlResult<Option<usize>> {
        let reverse = self.search < 0;
        if key.is_blank() {
            // An empty lookup value finds the first (or last) empty cell, whatever the
            // match mode (Excel: `XLOOKUP(, A:A, B:B,, 1, 2)` returns the first blank row).
            let blank = items.find_blank(reverse, looked);
            if blank.is_some() {
                return Ok(blank);
            }
        }
        if self.regex {
            let found = regex_position(key, items.items, reverse, &self.refusal);
            add(looked, looked_at(found.ok().flatten(), items.items.len(), reverse));
            return found;
        }
        let key = lookup_key(key)?;
        Ok(match self.search {
            2 | -2 => xlookup_binary(&key, items.items, self.fallback, reverse, looked),
            _ => xlookup_linear(&key, items, self.fallback, self.wildcards, reverse, looked),
        })
    }
}

/// XLOOKUP's and XMATCH's match mode 3: the first (or last) item whose text the lookup
/// value, read as a regular expression as REGEXTEST reads it (case counts, a match
/// anywhere), matches; blanks and errors take no part. The pattern and the work of all the
/// searches together are bounded as REGEXTEST's are (`regex_limits`): past them `#NUM!`, the
/// limit kept in `refusal` for the cell's note; a pattern that does not compile `#VALUE!`.
fn regex_position(
    key: &Value,
    items: &[Value],
    reverse: bool,
    refusal: &RefCell<Option<String>>,
) -> XlResult<Option<usize>> {
    let refuse = |why: String| {
        *refusal.borrow_mut() = Some(why);
        XlError::Num
    };
    let pattern = regex_limits::compile(&to_text(key)?, false).map_err(|e| match e {
        regex_limits::PatternError::Syntax(_) => XlError::Value,
        limit => refuse(limit.to_string()),
    })?;
    let (mut work, mut searched, mut bytes) = (0u64, 0, 0);
    let mut matches = |v: &Value| -> XlResult<bool> {
        if matches!(v, Value::Blank | Value::Error(_)) {
            return Ok(false);
        }
        let Ok(text) = to_text(v) else { return Ok(false) };
        work = work.saturating_add(pattern.work(&text));
        (searched, bytes) = (searched + 1, bytes + text.len());
        if work > regex_limits::MAX_MATCH_WORK {
            return Err(refuse(regex_limits::TooMuchWork::lookup(work, searched, bytes).to_string()));
        }
        Ok(pattern.regex.is_match(&text))
    };
    let order: Box<dyn Iterator<Item = (usize, &Value)>> =
        if reverse { Box::new(items.iter().enumerate().rev()) } else { Box::new(items.iter().enumerate()) };
    for (i, v) in order {
        if matches(v)? {
            return Ok(Some(i));
        }
    }
    Ok(None)
}

fn xmatch(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let key = ctx.eval(&args[0]);
    let haystack = grid_of_expr(ctx, &args[1])?;
    let mode = XMode::read(ctx, args, 2)?;
    let looked = Cell::new(0);
    let items = Haystack::new(line_of(&haystack).ok_or(XlError::Value)?, &key);
    let found = lift_values(&[key], &|v| {
        let i = mode.find(&v[0], &items, &looked)?.ok_or(XlError::NA)?;
        Ok(Value::Number(i as f64 + 1.0))
    });
    ctx.charge(looked.get());
    mode.explain(ctx, "XMATCH");
    found
}

/// LOOKUP's vector form (value, lookup_vector, result_vector) and array form (value,
/// array): the array's first row or column is searched, its last returned.
fn lookup_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let key = ctx.eval(&args[0]);
    let table = grid_of_expr(ctx, &args[1])?;
    let one_key = !matches!(key, Value::Array(_));
    let mut place = None;
    let (keys, results) = match args.get(2) {
        Some(e) => {
            let operand = ctx.operand(e);
            let at = if let Operand::Ref(sheet, rect) = operand { Some((sheet, rect)) } else { None };
            let results = grid_of(ctx, operand)?;
            place = at.map(|(sheet, rect)| (sheet, rect, results.cols));
            let keys = line_of(&table).ok_or(XlError::NA)?.to_vec();
            (keys, results.data.clone())
        }
        None if table.cols > table.rows => (
            (0..table.cols).map(|c| table.get(0, c).clone()).collect(),
            (0..table.cols).map(|c| table.get(table.rows - 1, c).clone()).collect(),
        ),
        None => (
            (0..table.rows).map(|r| table.get(r, 0).clone()).collect(),
            (0..table.rows).map(|r| table.get(r, table.cols - 1).clone()).collect(),
        ),
    };
    // The keys and results are copied, and each key's search counted.
    let looked = Cell::new(keys.len() + results.len());
    let picked = Cell::new(None);
    let found = lift_values(&[key], &|v| {
        let key = lookup_key(&v[0])?;
        let i = binary_search_last_not_after(&key, &keys, counting(&looked, ascending)).ok_or(XlError::NA)?;
        let result = results.get(i).cloned().ok_or(XlError::NA)?;
        picked.set(Some(i));
        Ok(result)
    });
    ctx.charge(looked.get());
    if let (Some((sheet, rect, cols)), Some(i)) = (place, picked.get()) {
        // Only the result returned is read of the result vector (FnSpec::picked_arg); its
        // items are numbered across the rows read.
        let cell = Pos::new(rect.first.row + (i / cols) as u32, rect.first.col + (i % cols) as u32);
        ctx.note_dynamic_ref(sheet, if one_key { Rect { first: cell, last: cell } } else { rect });
    }
    found
}

/// The row (vertical lookup) or column of the return source at position `i`.
fn line_span(result: &Source, i: usize, vertical: bool) -> (Span, Span) {
    if vertical {
        ((i, 1), (0, result.cols))
    } else {
        ((0, result.rows), (i, 1))
    }
}

fn result_line(result: &Source, i: usize, vertical: bool) -> Value {
    let (rows, cols) = line_span(result, i, vertical);
    let values = &result.values;
    // A whole-column source was read only as far as the sheet has data.
    let cell = |r: usize, c: usize| {
        if r < values.rows && c < values.cols {
            values.get(r, c).clone()
        } else {
            Value::Blank
        }
    };
    let mut data = Vec::with_capacity(rows.1 * cols.1);
    for r in rows.0..rows.0 + rows.1 {
        for c in cols.0..cols.0 + cols.1 {
            data.push(cell(r, c));
        }
    }
    Value::from(Array::new(rows.1, cols.1, data)).unwrap_single()
}

/// XLOOKUP's linear search: the first (or last) exact match, else the closest item on
/// the wanted side, preferring the first found among equals.
fn xlookup_linear(
    key: &Value,
    items: &Haystack,
    fallback: Fallback,
    wildcards: bool,
    reverse: bool,
    looked: &Cell<usize>,
) -> Option<usize> {
    let exact = items.find_exact(key, wildcards, reverse, looked);
    if exact.is_some() || fallback == Fallback::None {
        return exact;
    }
    items.closest(key, fallback, reverse, looked)
}

/// The closest item on the `fallback` side of `key`, item by item.
fn closest_by_scan(key: &Value, items: &[Value], fallback: Fallback, reverse: bool) -> Option<usize> {
    let mut best: Option<usize> = None;
    let order: Box<dyn Iterator<Item = usize>> =
        if reverse { Box::new((0..items.len()).rev()) } else { Box::new(0..items.len()) };
    for i in order {
        let item = &items[i];
        let Some(side) = xlookup_order(item, key) else {
            continue;
        };
        let wanted = match fallback {
            Fallback::NextSmaller => Ordering::Less,
            _ => Ordering::Greater,
        };
        if side != wanted {
            continue;
        }
        let closer = best.is_none_or(|b| xlookup_order(item, &items[b]) == Some(wanted.reverse()));
        if closer {
            best = Some(i);
        }
    }
    best
}

/// XLOOKUP orders across kinds as sorting does (numbers < text < booleans); blanks and
/// errors in the lookup array take no part.
fn xlookup_order(a: &Value, b: &Value) -> Option<Ordering> {
    match (a, b) {
        (Value::Blank | Value::Error(_), _) | (_, Value::Blank | Value::Error(_)) => None,
        _ => compare(a, b).ok(),
    }
}

/// XLOOKUP's binary search on data sorted ascending (or descending when `reverse`,
/// searched as the ascending sequence read backwards). Among equal items it finds the
/// first in ascending order, as Excel does: with duplicates, `2` finds the first and `-2`
/// the last of them.
fn xlookup_binary(
    key: &Value,
    items: &[Value],
    fallback: Fallback,
    reverse: bool,
    looked: &Cell<usize>,
) -> Option<usize> {
    let n = items.len();
    let original = |i: usize| if reverse { n - 1 - i } else { i };
    let order = |i: usize| {
        add(looked, 1);
        xlookup_order(&items[original(i)], key)
    };
    let bound = lower_bound(n, order);
    let at_or_after = (bound..n).find(|&i| order(i).is_some());
    if let Some(i) = at_or_after.filter(|&i| order(i) == Some(Ordering::Equal)) {
        return Some(original(i));
    }
    let found = match fallback {
        Fallback::None => None,
        Fallback::NextSmaller => (0..bound).rev().find(|&i| order(i).is_some()),
        Fallback::NextLarger => at_or_after,
    };
    found.map(original)
}

/// The first position whose item is not before the key, for items sorted by `order`
/// (item against key); positions it cannot compare are stepped over.
fn lower_bound(n: usize, order: impl Fn(usize) -> Option<Ordering>) -> usize {
    let (mut lo, mut hi) = (0, n);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        match (mid..hi).find(|&i| order(i).is_some()) {
            Some(p) if order(p) == Some(Ordering::Less) => lo = p + 1,
            _ => hi = mid,
        }
    }
    lo
}

// ---------------------------------------------------------------------------------------
// ROW, COLUMN, ROWS, COLUMNS

fn row(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rect = reference_or_here(ctx, args)?;
    let numbers = (rect.first.row..=rect.last.row).map(|r| Value::Number(r as f64 + 1.0));
    Ok(Value::from(Array::column(numbers.collect())).unwrap_single())
}

fn column(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rect = reference_or_here(ctx, args)?;
    let numbers = (rect.first.col..=rect.last.col).map(|c| Value::Number(c as f64 + 1.0));
    Ok(Value::from(Array::row(numbers.collect())).unwrap_single())
}

/// ROW and COLUMN's argument: a reference, or the formula's own cell when omitted.
fn reference_or_here(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Rect> {
    match args.first() {
        None => Ok(Rect::cell(ctx.at)),
        Some(e) => match ctx.reference_only(e) {
            Operand::Ref(_, rect) => Ok(rect),
            Operand::Value(Value::Error(err)) => Err(err),
            Operand::Value(_) => Err(XlError::Value),
            Operand::Areas(_) => Err(XlError::Ref),
        },
    }
}

fn rows(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    dimensions(ctx, &args[0]).map(|(r, _)| Value::Number(r as f64))
}

fn columns(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    dimensions(ctx, &args[0]).map(|(_, c)| Value::Number(c as f64))
}

/// Rows and columns as written: `ROWS(C:C)` is 1048576 however much of C is used.
fn dimensions(ctx: &mut Ctx, e: &Expr) -> XlResult<(usize, usize)> {
    match ctx.reference_only(e) {
        Operand::Ref(_, rect) => Ok((rect.rows() as usize, rect.cols() as usize)),
        // `ROWS(A:A+1)` is 1048576: the whole array, its tail included.
        Operand::Value(Value::Array(a)) => Ok(a.whole_size()),
        Operand::Value(Value::Error(err)) => Err(err),
        Operand::Value(_) => Ok((1, 1)),
        // A reference of several areas has no one shape.
        Operand::Areas(_) => Err(XlError::Ref),
    }
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::n;
    use crate::eval::testing::MapEnv;
    use crate::eval::{Array, Value, XlError};

    fn t(s: &str) -> Value {
        Value::text(s)
    }

    /// A1:C4 — a small sorted tool table: diameter, name, feed.
    fn tools() -> MapEnv {
        MapEnv::with(&[
            ("A1", n(3.0)),
            ("B1", t("drill 3")),
            ("C1", n(120.0)),
            ("A2", n(6.0)),
            ("B2", t("end mill 6")),
            ("C2", n(300.0)),
            ("A3", n(10.0)),
            ("B3", t("end mill 10")),
            ("C3", n(450.0)),
            ("A4", n(16.0)),
            ("B4", t("face mill 16")),
            ("C4", n(800.0)),
        ])
    }

    #[test]
    fn index_returns_references_and_items() {
        let env = tools();
        assert_eq!(env.eval("=INDEX(A1:C4,2,2)"), t("end mill 6"));
        assert_eq!(env.eval("=SUM(A1:INDEX(A1:A4,3))"), n(19.0));
        assert_eq!(env.eval("=SUM(INDEX(A1:C4,0,3))"), n(1670.0));
        assert_eq!(env.eval("=INDEX({1,2,3},2)"), n(2.0));
        assert_eq!(env.eval("=INDEX({1,2;3,4},2)"), Value::from(Array::row(vec![n(3.0), n(4.0)])));
        assert_eq!(env.eval("=INDEX(A1:A4,5)"), Value::Error(XlError::Ref));
        assert_eq!(env.eval("=INDEX(A1:A4,-1)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=INDEX(A1:A4,1.9)"), n(3.0));
        assert_eq!(env.eval("=ROW(INDEX(A1:C4,3,1))"), n(3.0));
    }

    #[test]
    fn match_modes() {
        let env = tools();
        assert_eq!(env.eval("=MATCH(10,A1:A4,0)"), n(3.0));
        assert_eq!(env.eval("=MATCH(11,A1:A4)"), n(3.0));
        assert_eq!(env.eval("=MATCH(2,A1:A4)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=MATCH(\"END*10\",B1:B4,0)"), n(3.0));
        assert_eq!(env.eval("=MATCH(\"?ace*\",B1:B4,0)"), n(4.0));
        assert_eq!(env.eval("=MATCH(7,{9,7,5,3},-1)"), n(2.0));
        assert_eq!(env.eval("=MATCH(6,{9,7,5,3},-1)"), n(2.0));
        assert_eq!(env.eval("=MATCH(\"6\",A1:A4,0)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=MATCH(2,{1,2,2,2,3},1)"), n(4.0));
        assert_eq!(env.eval("=MATCH(11,A1:A4,)"), Value::Error(XlError::NA));
    }

    #[test]
    fn vlookup_and_hlookup() {
        let env = tools();
        assert_eq!(env.eval("=VLOOKUP(10,A1:C4,3,FALSE)"), n(450.0));
        assert_eq!(env.eval("=VLOOKUP(12,A1:C4,2)"), t("end mill 10"));
        assert_eq!(env.eval("=VLOOKUP(1,A1:C4,2)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=VLOOKUP(12,A1:C4,2,FALSE)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=VLOOKUP(10,A1:C4,4,FALSE)"), Value::Error(XlError::Ref));
        assert_eq!(env.eval("=VLOOKUP(10,A1:C4,0,FALSE)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=HLOOKUP(\"b\",{\"a\",\"b\";1,2},2,FALSE)"), n(2.0));
        // A one-cell reference is a table; typed text is not.
        assert_eq!(env.eval("=VLOOKUP(\"drill 3\",B1,1,FALSE)"), t("drill 3"));
        assert_eq!(env.eval("=VLOOKUP(\"x\",\"x\",1,FALSE)"), Value::Error(XlError::Value));
    }

    #[test]
    fn xlookup_modes() {
        let env = tools();
        assert_eq!(env.eval("=XLOOKUP(10,A1:A4,C1:C4)"), n(450.0));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4,\"none\")"), t("none"));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4,,-1)"), n(450.0));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4,,1)"), n(800.0));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4,,1,2)"), n(800.0));
        assert_eq!(env.eval("=XLOOKUP(11,A1:A4,C1:C4,,-1,2)"), n(450.0));
        assert_eq!(env.eval("=XLOOKUP(\"*10\",B1:B4,A1:A4,,2)"), n(10.0));
        assert_eq!(env.eval("=XLOOKUP(6,A1:A4,B1:C4)"), Value::from(Array::row(vec![t("end mill 6"), n(300.0)])));
        assert_eq!(env.eval("=SUM(XLOOKUP(6,A1:A4,C1:C4):C4)"), n(1550.0));
        assert_eq!(env.eval("=XLOOKUP(6,A1:A4,C1:C3)"), Value::Error(XlError::Value));
        // Match mode 3: a regular expression, matched anywhere in an item's text.
        assert_eq!(env.eval("=XLOOKUP(\"^end mill 1[0-9]$\",B1:B4,A1:A4,,3)"), n(10.0));
        assert_eq!(env.eval("=XLOOKUP(\"mill\",B1:B4,A1:A4,,3,-1)"), n(16.0));
        assert_eq!(env.eval("=XLOOKUP(\"END\",B1:B4,A1:A4,,3)"), Value::Error(XlError::NA));
        assert_eq!(env.eval("=XLOOKUP(\"(\",B1:B4,A1:A4,,3)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=XLOOKUP(6,A1:A4,C1:C4,,4)"), Value::Error(XlError::Value));
    }

    #[test]
    fn xmatch_and_lookup() {
        let env = tools();
        assert_eq!(env.eval("=XMATCH(10,A1:A4)"), n(3.0));
        assert_eq!(env.eval("=XMATCH(11,A1:A4,1)"), n(4.0));
        assert_eq!(env.eval("=XMATCH(\"end*\",B1:B4,2,-1)"), n(3.0));
        assert_eq!(env.eval("=XMATCH(1,A1:C2)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=LOOKUP(12,A1:A4,C1:C4)"), n(450.0));
        assert_eq!(env.eval("=LOOKUP(7,A1:C4)"), n(300.0));
        assert_eq!(env.eval("=LOOKUP(\"b\",{\"a\",\"b\",\"c\";1,2,3})"), n(2.0));
        assert_eq!(env.eval("=LOOKUP(1,A1:A4,C1:C4)"), Value::Error(XlError::NA));
    }

    #[test]
    fn row_column_rows_columns() {
        let env = tools();
        assert_eq!(env.eval_at("=ROW()", "C7").unwrap(), n(7.0));
        assert_eq!(env.eval_at("=COLUMN()", "C7").unwrap(), n(3.0));
        assert_eq!(env.eval("=ROW(B3)"), n(3.0));
        assert_eq!(env.eval("=ROW(A2:B3)"), Value::from(Array::column(vec![n(2.0), n(3.0)])));
        assert_eq!(env.eval("=COLUMN(B1:C1)"), Value::from(Array::row(vec![n(2.0), n(3.0)])));
        assert_eq!(env.eval("=ROWS(C:C)"), n(1_048_576.0));
        assert_eq!(env.eval("=COLUMNS({1,2,3})"), n(3.0));
        assert_eq!(env.eval("=ROW(1)"), Value::Error(XlError::Value));
    }
}
