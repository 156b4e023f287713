//! The criteria of COUNTIF, SUMIF, AVERAGEIF and the *IFS functions (`5`, `"<5"`, `">=2"`,
//! `"<>x"`, `"=3"`, `"abc*"`), and the cell blocks they are tested against.

use std::cell::{Cell, OnceCell};
use std::cmp::Ordering;
use std::collections::HashMap;
use std::hash::Hash;
use std::rc::Rc;

use crate::eval::coerce::{compare_text, parse_number};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{comparison_holds, Ctx, Operand};
use crate::eval::functions::arrays::reshape::{item_key, ItemKey};
use crate::eval::functions::lookup::key_index::{worth_indexing, OrderIndex};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{BinOp, Expr, SheetId};

/// What a criterion compares cells with.
#[derive(Clone, Debug, PartialEq)]
enum Target {
    /// Matches numbers, and text that reads as the same number (`COUNTIF(r, 23)` counts "23").
    Number(f64),
    Bool(bool),
    Error(XlError),
    /// Text matched without regard to case; `*`, `?` and `~` are wildcards, when it has
    /// any, read once into `pattern` (a criteria array's item is tested against every cell).
    Text {
        text: Rc<str>,
        pattern: Option<Rc<[Token]>>,
    },
    /// `""` matches empty cells and empty text; `"="` and `"<>"` test truly empty cells.
    Empty {
        strict: bool,
    },
}

/// One parsed criterion.
#[derive(Clone, Debug, PartialEq)]
pub struct Criterion {
    /// A comparison: `BinOp::Eq` to `BinOp::Ge`.
    op: BinOp,
    target: Target,
    /// The workbook's date system: date text, in the criterion or in a cell, is read as its
    /// serial there.
    dates: DateSystem,
}

impl Criterion {
    /// Reads a criterion argument (one item of it when it is an array).
    pub fn new(v: &Value, dates: DateSystem) -> Criterion {
        let eq = |target| Criterion { op: BinOp::Eq, target, dates };
        match v {
            Value::Number(n) => eq(Target::Number(*n)),
            Value::Bool(b) => eq(Target::Bool(*b)),
            Value::Error(e) => eq(Target::Error(*e)),
            Value::Lambda(_) => eq(Target::Error(XlError::Calc)),
            Value::Null => eq(Target::Error(XlError::Value)),
            // Documented: "a reference to an empty cell is treated as 0".
            Value::Blank => eq(Target::Number(0.0)),
            Value::Text(s) => Criterion::parse(s, dates),
            Value::Array(a) => Criterion::new(a.data.first().unwrap_or(&Value::Blank), dates),
        }
    }

    fn parse(s: &str, dates: DateSystem) -> Criterion {
        let (op, operand) = split_operator(s);
        let target = if operand.is_empty() {
            Target::Empty { strict: operand.len() != s.len() }
        } else if let Some(n) = parse_number(operand, dates) {
            Target::Number(n)
        } else if operand.eq_ignore_ascii_case("TRUE") || operand.eq_ignore_ascii_case("FALSE") {
            Target::Bool(operand.eq_ignore_ascii_case("TRUE"))
        } else if let Some(e) = XlError::ALL.iter().find(|e| e.as_str().eq_ignore_ascii_case(operand)) {
            Target::Error(*e)
        } else {
            let pattern = operand.contains(['*', '?', '~']).then(|| tokenize(operand).into());
            Target::Text { text: operand.into(), pattern }
        };
        Criterion { op, target, dates }
    }

    /// Whether a cell's value meets the criterion. Errors in the range are values like any
    /// other here: they never match a number and always match `"<>5"`.
    pub fn matches(&self, v: &Value) -> bool {
        match self.op {
            BinOp::Eq => self.equals(v, true),
            // Excel counts the text "23" as different from 23 for "<>23" although "=23"
            // matches it (COUNTIF.xlsx in the corpus).
            BinOp::Ne => !self.equals(v, false),
            op => self.order(v).is_some_and(|ord| comparison_holds(op, ord)),
        }
    }

    fn equals(&self, v: &Value, numeric_text: bool) -> bool {
        match (&self.target, v) {
            (Target::Number(n), Value::Number(x)) => x == n,
            (Target::Number(n), Value::Text(t)) => numeric_text && parse_number(t, self.dates) == Some(*n),
            (Target::Bool(b), Value::Bool(x)) => b == x,
            (Target::Error(e), Value::Error(x)) => e == x,
            (Target::Text { text, pattern }, Value::Text(t)) => match pattern {
                Some(tokens) => glob(tokens, &lowered(t)),
                None => compare_text(t, text) == Ordering::Equal,
            },
            (Target::Empty { .. }, Value::Blank) => true,
            (Target::Empty { strict }, Value::Text(t)) => !strict && t.is_empty(),
            _ => false,
        }
    }

    /// The cell compared with the target for `<`, `>` …: only values of the same kind compare.
    fn order(&self, v: &Value) -> Option<Ordering> {
        match (&self.target, v) {
            (Target::Number(n), Value::Number(x)) => x.partial_cmp(n),
            (Target::Text { text, .. }, Value::Text(t)) => Some(compare_text(t, text)),
            (Target::Bool(b), Value::Bool(x)) => Some(x.cmp(b)),
            _ => None,
        }
    }
}

impl Criterion {
    /// The keys of the cells an equality criterion matches, as [`EqualityIndex`] files
    /// them; `None` for a criterion a key cannot name (a comparison, `<>`, a pattern).
    pub(crate) fn keys(&self) -> Option<Vec<ItemKey>> {
        if self.op != BinOp::Eq {
            return None;
        }
        self.target_keys()
    }

    /// What a text criterion with a star only at its end (`"bol*"`, and in a database's
    /// criteria plain `bol`) matches: the texts whose lower-case letters begin with these.
    pub(crate) fn prefix(&self) -> Option<Vec<char>> {
        let Target::Text { pattern: Some(tokens), .. } = &self.target else {
            return None;
        };
        let (Token::AnyMany, letters) = tokens.split_last()? else {
            return None;
        };
        let letter = |token: &Token| if let Token::Char(c) = token { Some(*c) } else { None };
        (self.op == BinOp::Eq).then(|| letters.iter().map(letter).collect()).flatten()
    }

    /// The letters a text pattern (`"*bolt"`, `"b?lt"`, `"b*t"`) begins and ends with, in
    /// lower case: the texts it matches are among those that begin with the one and end
    /// with the other. `None` but for an equality with a pattern.
    pub(crate) fn literal_ends(&self) -> Option<(Vec<char>, Vec<char>)> {
        let Target::Text { pattern: Some(tokens), .. } = &self.target else {
            return None;
        };
        let letter = |token: &Token| if let Token::Char(c) = token { Some(*c) } else { None };
        let prefix: Vec<char> = tokens.iter().map_while(letter).collect();
        let mut suffix: Vec<char> = tokens.iter().rev().map_while(letter).collect();
        suffix.reverse();
        (self.op == BinOp::Eq).then_some((prefix, suffix))
    }

    /// The keys of the cells a `<>` criterion does not match, each cell under its own
    /// value only: `"<>23"` matches the text "23" (which `"=23"` matches too).
    fn unequal_keys(&self) -> Option<Vec<ItemKey>> {
        if self.op != BinOp::Ne {
            return None;
        }
        self.target_keys()
    }

    /// The keys of the cells equal to the target, `None` for a pattern.
    fn target_keys(&self) -> Option<Vec<ItemKey>> {
        let key = match &self.target {
            Target::Number(n) => item_key(&Value::Number(*n))?,
            Target::Bool(b) => ItemKey::Bool(*b),
            Target::Error(e) => ItemKey::Error(*e),
            Target::Text { pattern: Some(_), .. } => return None,
            Target::Text { text, .. } => item_key(&Value::Text(text.clone()))?,
            Target::Empty { strict: true } => ItemKey::Blank,
            Target::Empty { strict: false } => return Some(vec![ItemKey::Blank, ItemKey::Text(String::new())]),
        };
        Some(vec![key])
    }
}

fn split_operator(s: &str) -> (BinOp, &str) {
    const OPERATORS: [(&str, BinOp); 6] =
        [("<=", BinOp::Le), (">=", BinOp::Ge), ("<>", BinOp::Ne), ("<", BinOp::Lt), (">", BinOp::Gt), ("=", BinOp::Eq)];
    OPERATORS.iter().find_map(|(prefix, op)| s.strip_prefix(prefix).map(|rest| (*op, rest))).unwrap_or((BinOp::Eq, s))
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Token {
    Char(char),
    AnyOne,
    AnyMany,
}

/// Excel's wildcard match of a whole text: `*` any run, `?` one character, `~` makes the
/// next `*`, `?` or `~` literal. Case-insensitive. (Criteria read their pattern once.)
#[cfg(test)]
fn wildcard_match(pattern: &str, text: &str) -> bool {
    glob(&tokenize(pattern), &lowered(text))
}

/// A text's characters in lower case, as patterns are matched against them.
pub(crate) fn lowered(text: &str) -> Vec<char> {
    text.chars().flat_map(char::to_lowercase).collect()
}

fn tokenize(pattern: &str) -> Vec<Token> {
    let mut tokens = Vec::new();
    let mut chars = pattern.chars().flat_map(char::to_lowercase).peekable();
    while let Some(c) = chars.next() {
        tokens.push(match c {
            '~' => match chars.peek() {
                Some(&next @ ('*' | '?' | '~')) => {
                    chars.next();
                    Token::Char(next)
                }
                _ => Token::Char('~'),
            },
            '*' => Token::AnyMany,
            '?' => Token::AnyOne,
            c => Token::Char(c),
        });
    }
    tokens
}

/// Iterative glob matching with one backtrack point (the last `*`): linear in practice.
fn glob(tokens: &[Token], text: &[char]) -> bool {
    let (mut t, mut s) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while s < text.len() {
        match tokens.get(t) {
            Some(Token::AnyMany) => {
                star = Some((t, s));
                t += 1;
            }
            Some(Token::AnyOne) => {
                t += 1;
                s += 1;
            }
            Some(Token::Char(c)) if *c == text[s] => {
                t += 1;
                s += 1;
            }
            _ => match star {
                Some((st, ss)) => {
                    t = st + 1;
                    s = ss + 1;
                    star = Some((st, ss + 1));
                }
                None => return false,
            },
        }
    }
    tokens[t..].iter().all(|k| *k == Token::AnyMany)
}

/// A range argument as the *IF functions read it: every cell, blanks included. Whole
/// columns and rows are read only as far as the sheet's used area; the cells beyond are
/// blank, counted but not stored.
#[derive(Clone, Debug)]
pub struct CellBlock {
    pub rows: usize,
    pub cols: usize,
    read: Rc<Array>,
}

impl CellBlock {
    pub fn read(ctx: &mut Ctx, e: &Expr) -> XlResult<CellBlock> {
        match ctx.operand(e) {
            Operand::Ref(sheet, rect) => Ok(CellBlock::of_rect(ctx, sheet, rect)),
            Operand::Value(v) => CellBlock::from_value(v),
            Operand::Areas(_) => Err(XlError::Value),
        }
    }

    /// SUMIF's sum range: Excel uses its top-left cell and the criteria range's shape.
    pub fn read_sized(ctx: &mut Ctx, e: &Expr, rows: usize, cols: usize) -> XlResult<CellBlock> {
        match ctx.operand(e) {
            Operand::Ref(sheet, rect) => {
                let last = Pos::new(
                    (rect.first.row as usize + rows - 1).min(MAX_ROWS as usize - 1) as u32,
                    (rect.first.col as usize + cols - 1).min(MAX_COLS as usize - 1) as u32,
                );
                let mut block = CellBlock::of_rect(ctx, sheet, Rect::new(rect.first, last));
                (block.rows, block.cols) = (rows, cols);
                Ok(block)
            }
            Operand::Value(v) => {
                let block = CellBlock::from_value(v)?;
                Ok(CellBlock { rows, cols, ..block })
            }
            Operand::Areas(_) => Err(XlError::Value),
        }
    }

    fn from_value(v: Value) -> XlResult<CellBlock> {
        match v {
            Value::Error(err) => Err(err),
            Value::Array(a) => Ok(CellBlock { rows: a.rows, cols: a.cols, read: a }),
            v => Ok(CellBlock { rows: 1, cols: 1, read: Rc::new(Array::new(1, 1, vec![v])) }),
        }
    }

    fn of_rect(ctx: &Ctx, sheet: SheetId, rect: Rect) -> CellBlock {
        let clipped = ctx.clip_to_used(sheet, rect);
        let read = match ctx.rect_value(sheet, clipped) {
            Value::Array(a) => a,
            v => Rc::new(Array::new(1, 1, vec![v])),
        };
        CellBlock { rows: rect.rows() as usize, cols: rect.cols() as usize, read }
    }

    /// The cell at (row, col) of the range: blank beyond the part that was read.
    pub fn get(&self, row: usize, col: usize) -> &Value {
        if row < self.read.rows && col < self.read.cols {
            self.read.get(row, col)
        } else {
            &Value::Blank
        }
    }

    /// The range read at least as far as `other` was (blank where this one was not read), for
    /// criteria ranges beside an aggregate's target: a cell the target read must be tested as
    /// a read cell, since the unread blanks beyond count only in COUNTIF (whole columns on
    /// another sheet, where `SUMIF(Sheet1!A:A, "", B:B)` sums B beside Sheet1's unused rows).
    pub fn read_as_far_as(&self, other: &CellBlock) -> CellBlock {
        let rows = self.read.rows.max(other.read.rows).min(self.rows);
        let cols = self.read.cols.max(other.read.cols).min(self.cols);
        if rows == self.read.rows && cols == self.read.cols {
            return self.clone();
        }
        let cells = (0..rows).flat_map(|r| (0..cols).map(move |c| self.get(r, c).clone())).collect();
        CellBlock { rows: self.rows, cols: self.cols, read: Rc::new(Array::new(rows, cols, cells)) }
    }

    pub fn same_shape(&self, other: &CellBlock) -> bool {
        self.rows == other.rows && self.cols == other.cols
    }
}

/// The cells where every range meets its criterion: the positions read, and how many
/// unread (blank) cells beyond the sheet's used area match too.
pub struct Matches {
    pub cells: Vec<(usize, usize)>,
    pub blanks_beyond: usize,
}

/// Tests `ranges[i]` against `criteria[i]` cell by cell; the ranges must share one shape
/// (`#VALUE!` otherwise, as in Excel's COUNTIFS).
pub fn matching_cells(ranges: &[CellBlock], criteria: &[Criterion]) -> XlResult<Matches> {
    let first = &ranges[0];
    if ranges.iter().any(|r| !r.same_shape(first)) {
        return Err(XlError::Value);
    }
    let (read_rows, read_cols) = read_size(ranges);
    let mut cells = Vec::new();
    for row in 0..read_rows {
        for col in 0..read_cols {
            if ranges.iter().zip(criteria).all(|(r, c)| c.matches(r.get(row, col))) {
                cells.push((row, col));
            }
        }
    }
    Ok(Matches { cells, blanks_beyond: blanks_beyond(ranges, criteria) })
}

/// The part of the ranges' shape that any of them read: the cells tested one by one.
fn read_size(ranges: &[CellBlock]) -> (usize, usize) {
    let first = &ranges[0];
    let read_rows = ranges.iter().map(|r| r.read.rows).max().unwrap_or(0);
    let read_cols = ranges.iter().map(|r| r.read.cols).max().unwrap_or(0);
    (read_rows.min(first.rows), read_cols.min(first.cols))
}

/// How many cells beyond the read part match: all of them (they are blank) or none.
fn blanks_beyond(ranges: &[CellBlock], criteria: &[Criterion]) -> usize {
    let first = &ranges[0];
    let (read_rows, read_cols) = read_size(ranges);
    if criteria.iter().all(|c| c.matches(&Value::Blank)) {
        first.rows * first.cols - read_rows * read_cols
    } else {
        0
    }
}

/// The matching of one conditional aggregate over all its criteria items: with an array of
/// many criteria for one range (`COUNTIF(r, SEQUENCE(100000))`, `SUMIFS(s, r, keys, q, "x")`),
/// that range is indexed once by the values equality criteria name, where each criterion
/// used to scan the whole range (100,000 criteria over 100,000 cells took minutes); its
/// comparisons are counted and summarized over its sorted order, and its `<>` criteria
/// from tallies per value (where that is exactly the row-by-row result). Two or more
/// arrays paired item by item are indexed by their combined values.
/// Patterns, and what no index answers exactly, are tested cell by cell. `work` counts the
/// cells looked at, for the LAMBDA work budget.
pub struct CriteriaMatcher<'a> {
    ranges: &'a [CellBlock],
    indexed: Option<IndexedRange<'a>>,
    /// Two or more ranges whose criteria arrays pair item by item, indexed together.
    paired: Option<PairedRanges>,
    dates: DateSystem,
    /// The range aggregated and what is made of it, for [`CriteriaMatcher::indexed_summary`].
    target: Option<(&'a CellBlock, Summary)>,
    pub work: Cell<usize>,
}

/// What an aggregate makes of the target's numbers where the criteria hold, when an index
/// answers without testing the cells: their sum (SUMIF, AVERAGEIF and their *IFS) or their
/// smallest or largest (MINIFS, MAXIFS).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Summary {
    Total,
    Smallest,
    Largest,
}

impl Summary {
    /// The extreme of two numbers (the sum for a total).
    fn pick(self, a: f64, b: f64) -> f64 {
        match self {
            Summary::Total => a + b,
            Summary::Smallest => a.min(b),
            Summary::Largest => a.max(b),
        }
    }

    /// What no number contributes to an extreme.
    fn identity(self) -> f64 {
        match self {
            Summary::Total => 0.0,
            Summary::Smallest => f64::INFINITY,
            Summary::Largest => f64::NEG_INFINITY,
        }
    }
}

/// The most cells one conditional aggregate may test one by one over all its criteria
/// items: 10^9 take tens of seconds (100,000 patterns over 100,000 cells, 10^10, took
/// minutes); indexed criteria do not count.
pub const MAX_CRITERIA_SCAN: usize = 1_000_000_000;

/// The range whose criterion varies, and what is known of it: each part is built at its
/// first use (and counted then), so criteria that are all comparisons or patterns build no
/// equality index.
struct IndexedRange<'a> {
    which: usize,
    /// The fixed criteria, one per range (the varying range's first item stands in).
    fixed: Vec<Criterion>,
    read_rows: usize,
    read_cols: usize,
    index: OnceCell<EqualityIndex>,
    others: OnceCell<OthersHold>,
    /// The range's numbers, texts and booleans in order, for counting what a comparison
    /// (`"<5"`, `">=b"`) matches; built at the first such criterion.
    ordered: OnceCell<OrderIndex<'a>>,
    sorted_summary: OnceCell<Option<SortedSummary>>,
    /// Running counts of where the other ranges' criteria hold, along `ordered`.
    others_in_order: OnceCell<Vec<usize>>,
    /// The target summed or weighed per value of the range, for `"<>"&keys`.
    keyed_summary: OnceCell<Option<KeyedSummary>>,
}

impl<'a> CriteriaMatcher<'a> {
    /// `criteria[i]` is the criteria argument of `ranges[i]`, as evaluated.
    pub fn new(ranges: &'a [CellBlock], criteria: &[Value], dates: DateSystem) -> CriteriaMatcher<'a> {
        let indexed =
            IndexedRange::worth_it(ranges, criteria).map(|which| IndexedRange::new(ranges, criteria, which, dates));
        let paired = match indexed {
            Some(_) => None,
            None => {
                PairedRanges::worth_it(ranges, criteria).map(|which| PairedRanges::new(ranges, criteria, which, dates))
            }
        };
        CriteriaMatcher { ranges, indexed, paired, dates, target: None, work: Cell::new(0) }
    }

    /// The matcher of an aggregate of `target` (SUMIF, AVERAGEIF, MINIFS … ): what a
    /// comparison or a `<>` matches is then summarized from an index where that is exact.
    pub fn summarizing(self, target: &'a CellBlock, summary: Summary) -> CriteriaMatcher<'a> {
        CriteriaMatcher { target: Some((target, summary)), ..self }
    }

    /// The summary (sum or extreme) and the count of the target's numbers where every
    /// criterion holds, when the indexed range's criterion is a comparison
    /// (`SUMIF(r, "<="&keys, s)`, from prefix sums or a table of extremes over the sorted
    /// order) or a `<>` (`MAXIFS(s, r, "<>"&keys)`, from the whole less the cells equal to
    /// its value); an error beside a matching cell is the result (the first in row order).
    /// `None` where the cells must be tested one by one.
    pub fn indexed_summary(&self, criteria: &[Criterion]) -> Option<XlResult<(f64, usize)>> {
        let indexed = self.indexed.as_ref()?;
        let criterion = &criteria[indexed.which];
        if is_order(criterion.op) {
            return self.ordered_summary(indexed, criterion).map(Ok);
        }
        let key = single_unequal_key(criterion)?;
        let keyed = self.keyed_summary(indexed)?;
        self.add_work(1);
        Some(keyed.unequal(key))
    }

    fn ordered_summary(&self, indexed: &IndexedRange<'a>, criterion: &Criterion) -> Option<(f64, usize)> {
        let summary = self.sorted_summary(indexed, criterion)?;
        let Some(key) = comparison_key(criterion) else {
            return Some((0.0, 0));
        };
        let ordered = self.ordered(indexed);
        self.add_work(2 * ordered.query_work());
        let [kind_start, before, through, kind_end] = ordered.bounds(&key);
        Some(match criterion.op {
            BinOp::Lt => summary.run_from_kind_start(kind_start, before),
            BinOp::Le => summary.run_from_kind_start(kind_start, through),
            BinOp::Gt => summary.run_to_kind_end(through, kind_end),
            _ => summary.run_to_kind_end(before, kind_end),
        })
    }

    /// The summary over the sorted order for a comparison `criterion` of the indexed range,
    /// built at the first; `None` when the matcher aggregates no target, the criterion is no
    /// comparison, or the summary would not be exactly the row-by-row one.
    fn sorted_summary<'m>(&'m self, indexed: &'m IndexedRange<'a>, criterion: &Criterion) -> Option<&'m SortedSummary> {
        let (target, summary) = self.target?;
        if !is_order(criterion.op) {
            return None;
        }
        let others = self.others_hold(indexed);
        let ordered = self.ordered(indexed);
        indexed
            .sorted_summary
            .get_or_init(|| {
                // `ordered` numbers the cells in the range's stored width; `others` in the
                // width read of all ranges, which is at least as wide.
                let cols = self.ranges[indexed.which].read.cols;
                let beside = ordered.sorted().iter().map(|&p| {
                    let (row, col) = (p / cols, p % cols);
                    others.at[row * indexed.read_cols + col].then(|| target.get(row, col))
                });
                let kinds = [Value::Number(0.0), Value::text(""), Value::Bool(false)];
                let kind_starts = kinds.map(|kind| ordered.bounds(&kind)[0]);
                let built = SortedSummary::new(beside, summary, &kind_starts);
                self.add_work(built.as_ref().map_or(ordered.sorted().len(), SortedSummary::work));
                built
            })
            .as_ref()
    }

    /// The target tallied per value of the indexed range's cells, built at the first `<>`
    /// criterion; `None` when the matcher aggregates no target or a tally would not be
    /// exactly the row-by-row result.
    fn keyed_summary<'m>(&'m self, indexed: &'m IndexedRange<'a>) -> Option<&'m KeyedSummary> {
        let (target, summary) = self.target?;
        let others = self.others_hold(indexed);
        indexed
            .keyed_summary
            .get_or_init(|| {
                let (range, cols) = (&self.ranges[indexed.which], indexed.read_cols);
                let cells = indexed.read_rows * cols;
                self.add_work(cells);
                let beside = (0..cells).filter(|&p| others.at[p]).map(|p| {
                    let (row, col) = (p / cols, p % cols);
                    (item_key(range.get(row, col)), target.get(row, col))
                });
                KeyedSummary::new(beside, summary)
            })
            .as_ref()
    }

    /// The indexed range's numbers, texts and booleans in order, sorted at the first
    /// comparison. The cells stored are all the range holds: those beyond are blank.
    fn ordered<'m>(&'m self, indexed: &'m IndexedRange<'a>) -> &'m OrderIndex<'a> {
        indexed.ordered.get_or_init(|| {
            let ordered = OrderIndex::new(&self.ranges[indexed.which].read.data);
            self.add_work(ordered.sort_work());
            ordered
        })
    }

    /// How many cells meet every criterion: paired items walk the cells their equalities
    /// name; a comparison of the indexed range's criterion counts by binary search when the
    /// other ranges' criteria hold everywhere (COUNTIF), else from running counts along the
    /// sorted order.
    pub fn count(&self, criteria: &[Criterion]) -> XlResult<usize> {
        if let Some(paired) = &self.paired {
            if let Some(n) = self.paired_count(paired, criteria) {
                return Ok(n + blanks_beyond(self.ranges, criteria));
            }
            if let Some(cells) = self.paired_walk(paired, criteria) {
                return Ok(cells.len() + blanks_beyond(self.ranges, criteria));
            }
        }
        if let Some(indexed) = &self.indexed {
            let criterion = &criteria[indexed.which];
            if is_order(criterion.op) {
                let ordered = self.ordered(indexed);
                self.add_work(2 * ordered.query_work());
                let n = if self.others_hold(indexed).everywhere {
                    count_ordered(ordered, criterion)
                } else {
                    self.count_ordered_where_others_hold(indexed, criterion)
                };
                return Ok(n + blanks_beyond(self.ranges, criteria));
            }
            if let Some(keys) = criterion.keys() {
                return Ok(self.count_filed(indexed, &keys, false) + blanks_beyond(self.ranges, criteria));
            }
            if let Some(keys) = criterion.unequal_keys() {
                // The cells where the others hold, less those equal to the target.
                let equal = self.count_filed(indexed, &keys, true);
                return Ok(self.others_hold(indexed).count - equal + blanks_beyond(self.ranges, criteria));
            }
        }
        let m = self.matches(criteria)?;
        Ok(m.cells.len() + m.blanks_beyond)
    }

    /// How many cells a comparison of the indexed range matches among those where the other
    /// ranges' criteria hold (`COUNTIFS(dates, ">="&starts, region, "East")`): the cells it
    /// matches are one run of the sorted order, counted from running counts along it.
    fn count_ordered_where_others_hold(&self, indexed: &IndexedRange<'a>, criterion: &Criterion) -> usize {
        let Some(key) = comparison_key(criterion) else {
            return 0;
        };
        let held = self.others_held_in_order(indexed);
        let [kind_start, before, through, kind_end] = self.ordered(indexed).bounds(&key);
        let (from, to) = match criterion.op {
            BinOp::Lt => (kind_start, before),
            BinOp::Le => (kind_start, through),
            BinOp::Gt => (through, kind_end),
            _ => (before, kind_end),
        };
        held[to] - held[from]
    }

    /// In how many of the first i sorted cells of the indexed range the other ranges'
    /// criteria hold, for each i: built at the first comparison that needs it.
    fn others_held_in_order<'m>(&'m self, indexed: &'m IndexedRange<'a>) -> &'m [usize] {
        let others = self.others_hold(indexed);
        let ordered = self.ordered(indexed);
        indexed.others_in_order.get_or_init(|| {
            // `ordered` numbers the cells in the range's stored width, `others` in the
            // width read of all ranges (as in `sorted_summary`).
            let cols = self.ranges[indexed.which].read.cols;
            let holds = |p: usize| others.at[(p / cols) * indexed.read_cols + p % cols];
            self.add_work(ordered.sorted().len());
            let mut held = Vec::with_capacity(ordered.sorted().len() + 1);
            held.push(0);
            for &p in ordered.sorted() {
                held.push(held[held.len() - 1] + usize::from(holds(p)));
            }
            held
        })
    }

    /// `#NUM!`, with a note, when the criteria items (the argument values given to
    /// [`CriteriaMatcher::new`]) would test more than [`MAX_CRITERIA_SCAN`] cells one by
    /// one, or, inside a LAMBDA of MAP, REDUCE, …, more than the LAMBDAs' work budget has
    /// left: known before any is tested, so that such a call stops at once (charged after
    /// the scan, a single call could run 10^9 tests past the budget).
    pub fn within_scan_limit(&self, ctx: &mut Ctx, criteria: &[Value], counting: bool) -> XlResult<()> {
        let work = self.scan_work(criteria, counting);
        ctx.within_lambda_budget(work)?;
        if work > MAX_CRITERIA_SCAN {
            let why = format!(
                "the criteria would test {work} cells one by one, more than ncsheet's limit of \
                 {MAX_CRITERIA_SCAN:e} for one call (criteria items that are patterns, or comparisons or \
                 `<>` where no index answers them, × the cells of the ranges)"
            );
            return Err(ctx.explain(XlError::Num, why));
        }
        Ok(())
    }

    /// The cells the criteria items would test one by one, over all items.
    fn scan_work(&self, criteria: &[Value], counting: bool) -> usize {
        let (read_rows, read_cols) = read_size(self.ranges);
        let per_scan = read_rows * read_cols * self.ranges.len();
        if let Some(paired) = &self.paired {
            let item_work = |item: Vec<Criterion>| match paired.keys_per_range(&item) {
                Some(_) => 0,
                None => self.paired_candidates(paired, &item).map_or(per_scan, |(_, _, n)| n * self.ranges.len()),
            };
            return paired.items(criteria, self.dates).map(item_work).fold(0, usize::saturating_add);
        }
        let Some(indexed) = &self.indexed else {
            let size = |v: &Value| if let Value::Array(a) = v { (a.rows, a.cols) } else { (1, 1) };
            let (rows, cols) = criteria.iter().map(size).fold((1, 1), |(r, c), (ar, ac)| (r.max(ar), c.max(ac)));
            return per_scan.saturating_mul(rows.saturating_mul(cols));
        };
        let Value::Array(items) = &criteria[indexed.which] else {
            return per_scan;
        };
        let scanned = items.data.iter().filter(|v| self.scans(indexed, &Criterion::new(v, self.dates), counting));
        per_scan.saturating_mul(scanned.count())
    }

    /// Whether the indexed range's `criterion` is tested cell by cell: by [`Self::count`]
    /// when `counting`, else by [`Self::matches`].
    fn scans(&self, indexed: &IndexedRange<'a>, criterion: &Criterion, counting: bool) -> bool {
        let keyed = criterion.keys().is_some();
        if !counting {
            return !keyed && !self.summarizes(indexed, criterion);
        }
        !(keyed || is_order(criterion.op) || criterion.unequal_keys().is_some())
    }

    /// Whether [`Self::indexed_summary`] answers the indexed range's `criterion`.
    fn summarizes(&self, indexed: &IndexedRange<'a>, criterion: &Criterion) -> bool {
        if is_order(criterion.op) {
            return self.sorted_summary(indexed, criterion).is_some();
        }
        single_unequal_key(criterion).is_some() && self.keyed_summary(indexed).is_some()
    }

    fn add_work(&self, n: usize) {
        self.work.set(self.work.get().saturating_add(n));
    }

    /// The cells where every range meets its criterion ([`matching_cells`]).
    pub fn matches(&self, criteria: &[Criterion]) -> XlResult<Matches> {
        if let Some(paired) = &self.paired {
            let cells = self.paired_matches(paired, criteria).or_else(|| self.paired_walk(paired, criteria));
            if let Some(cells) = cells {
                return Ok(Matches { cells, blanks_beyond: blanks_beyond(self.ranges, criteria) });
            }
        }
        let add = |n: usize| self.add_work(n);
        let keyed = self.indexed.as_ref().and_then(|indexed| Some((indexed, criteria[indexed.which].keys()?)));
        let Some((indexed, keys)) = keyed else {
            let (read_rows, read_cols) = read_size(self.ranges);
            add(read_rows * read_cols * self.ranges.len());
            return matching_cells(self.ranges, criteria);
        };
        let others = self.others_hold(indexed);
        let positions = self.equality_index(indexed).positions(&keys);
        add(1 + positions.len());
        let cells = positions
            .into_iter()
            .filter(|&p| others.at[p])
            .map(|p| (p / indexed.read_cols, p % indexed.read_cols))
            .collect();
        Ok(Matches { cells, blanks_beyond: blanks_beyond(self.ranges, criteria) })
    }

    /// How many read cells filed under `keys` (only under their own value when `own`) the
    /// other ranges' criteria hold in: from the index's counts when they hold everywhere,
    /// else by walking the cells filed.
    fn count_filed(&self, indexed: &IndexedRange, keys: &[ItemKey], own: bool) -> usize {
        let others = self.others_hold(indexed);
        let index = self.equality_index(indexed);
        self.add_work(keys.len());
        if others.everywhere {
            return keys.iter().map(|key| index.count(key, own)).sum();
        }
        let range = &self.ranges[indexed.which];
        let cols = indexed.read_cols;
        let mut n = 0;
        for key in keys {
            let positions = index.positions(std::slice::from_ref(key));
            self.add_work(positions.len());
            let filed_as_own = |p: usize| item_key(range.get(p / cols, p % cols)).as_ref() == Some(key);
            n += positions.into_iter().filter(|&p| others.at[p] && (!own || filed_as_own(p))).count();
        }
        n
    }

    /// Where the other ranges' fixed criteria hold, worked out at the first criterion that
    /// needs it (one test per read cell of each other range).
    fn others_hold<'m>(&'m self, indexed: &'m IndexedRange) -> &'m OthersHold {
        indexed.others.get_or_init(|| {
            let others = self.ranges.len() - 1;
            self.add_work(indexed.read_rows * indexed.read_cols * others);
            OthersHold::new(self.ranges, &[indexed.which], &indexed.fixed, indexed.read_rows, indexed.read_cols)
        })
    }

    /// The varying range's equality index, built at the first equality criterion (one
    /// filing per read cell).
    fn equality_index<'m>(&'m self, indexed: &'m IndexedRange) -> &'m EqualityIndex {
        indexed.index.get_or_init(|| {
            self.add_work(indexed.read_rows * indexed.read_cols);
            let (range, cols) = (&self.ranges[indexed.which], indexed.read_cols);
            let cells = (0..indexed.read_rows * cols).map(|p| range.get(p / cols, p % cols));
            EqualityIndex::new(cells, self.dates)
        })
    }

    /// How many read cells a paired item's equalities and the other ranges' criteria hold
    /// in; `None` unless all of the paired criteria are equalities.
    fn paired_count(&self, paired: &PairedRanges, criteria: &[Criterion]) -> Option<usize> {
        let keys = paired.keys(criteria)?;
        let others = self.paired_others(paired);
        let index = self.paired_index(paired);
        self.add_work(keys.len());
        if others.everywhere {
            return Some(keys.iter().map(|key| index.count(key, false)).sum());
        }
        let positions = index.positions(&keys);
        self.add_work(positions.len());
        Some(positions.into_iter().filter(|&p| others.at[p]).count())
    }

    /// The read cells, in row order, where a paired item's equalities and the other
    /// ranges' criteria hold; `None` unless all of the paired criteria are equalities.
    fn paired_matches(&self, paired: &PairedRanges, criteria: &[Criterion]) -> Option<Vec<(usize, usize)>> {
        let keys = paired.keys(criteria)?;
        let others = self.paired_others(paired);
        let positions = self.paired_index(paired).positions(&keys);
        self.add_work(1 + positions.len());
        let cols = paired.read_cols;
        Some(positions.into_iter().filter(|&p| others.at[p]).map(|p| (p / cols, p % cols)).collect())
    }

    /// For a paired item with some equalities among other criteria (`COUNTIFS(a, keys, b,
    /// ">="&starts)`): the read cells, in row order, where every criterion holds, testing
    /// only the cells the most selective equality names; `None` for an item with none.
    fn paired_walk(&self, paired: &PairedRanges, criteria: &[Criterion]) -> Option<Vec<(usize, usize)>> {
        let (index, keys, _) = self.paired_candidates(paired, criteria)?;
        let positions = index.positions(&keys);
        self.add_work(positions.len() * self.ranges.len());
        let cols = paired.read_cols;
        let holds =
            |&(row, col): &(usize, usize)| self.ranges.iter().zip(criteria).all(|(r, c)| c.matches(r.get(row, col)));
        Some(positions.into_iter().map(|p| (p / cols, p % cols)).filter(holds).collect())
    }

    /// A paired item's most selective equality: its range's index, its keys and how many
    /// cells they name; `None` for an item with no equality.
    fn paired_candidates<'m>(
        &'m self,
        paired: &'m PairedRanges,
        criteria: &[Criterion],
    ) -> Option<(&'m EqualityIndex, Vec<ItemKey>, usize)> {
        let mut fewest: Option<(&EqualityIndex, Vec<ItemKey>, usize)> = None;
        for (slot, &i) in paired.which.iter().enumerate() {
            let Some(keys) = criteria[i].keys() else {
                continue;
            };
            let index = self.single_index(paired, slot);
            let n = index.count_filed(&keys);
            if fewest.as_ref().is_none_or(|(_, _, m)| n < *m) {
                fewest = Some((index, keys, n));
            }
        }
        fewest
    }

    /// The paired range in `slot` indexed alone, built at its first use (one filing per
    /// read cell, two for text that reads as a number).
    fn single_index<'m>(&'m self, paired: &'m PairedRanges, slot: usize) -> &'m EqualityIndex {
        paired.singles[slot].get_or_init(|| {
            self.add_work(paired.read_rows * paired.read_cols);
            let (range, cols) = (&self.ranges[paired.which[slot]], paired.read_cols);
            let cells = (0..paired.read_rows * cols).map(|p| range.get(p / cols, p % cols));
            EqualityIndex::new(cells, self.dates)
        })
    }

    fn paired_others<'m>(&'m self, paired: &'m PairedRanges) -> &'m OthersHold {
        paired.others.get_or_init(|| {
            self.add_work(paired.read_rows * paired.read_cols * (self.ranges.len() - paired.which.len()));
            OthersHold::new(self.ranges, &paired.which, &paired.fixed, paired.read_rows, paired.read_cols)
        })
    }

    fn paired_index<'m>(&'m self, paired: &'m PairedRanges) -> &'m EqualityIndex<Vec<ItemKey>> {
        paired.index.get_or_init(|| {
            self.add_work(paired.which.len() * paired.read_rows * paired.read_cols);
            paired.build_index(self.ranges, self.dates)
        })
    }

    /// Whether the equality index has been built: for tests of the work counted.
    #[cfg(test)]
    fn index_built(&self) -> bool {
        self.indexed.as_ref().is_some_and(|indexed| indexed.index.get().is_some())
    }
}

/// Per read cell of the varying range (row by row), whether every other range meets its
/// criterion there.
struct OthersHold {
    at: Vec<bool>,
    /// In how many read cells they hold.
    count: usize,
    /// Whether they hold in every read cell (as in COUNTIF, which has no others).
    everywhere: bool,
}

impl OthersHold {
    /// Tests each range but the `varying` ones against its `fixed` criterion.
    fn new(
        ranges: &[CellBlock],
        varying: &[usize],
        fixed: &[Criterion],
        read_rows: usize,
        read_cols: usize,
    ) -> OthersHold {
        let at: Vec<bool> = (0..read_rows * read_cols)
            .map(|p| {
                let (row, col) = (p / read_cols, p % read_cols);
                (0..ranges.len()).all(|i| varying.contains(&i) || fixed[i].matches(ranges[i].get(row, col)))
            })
            .collect();
        let count = at.iter().filter(|&&holds| holds).count();
        OthersHold { everywhere: count == at.len(), at, count }
    }
}

/// Two or more ranges whose criteria arguments are arrays of one shape, which
/// `lift_values` pairs item by item (`COUNTIFS(a, keys1, b, keys2, c, keys3)`): their read
/// cells are filed by the combination of their values, so that an item of equalities looks
/// its cells up where it tested every cell.
struct PairedRanges {
    which: Vec<usize>,
    /// The fixed criteria, one per range (the first items stand in for the paired ones).
    fixed: Vec<Criterion>,
    read_rows: usize,
    read_cols: usize,
    index: OnceCell<EqualityIndex<Vec<ItemKey>>>,
    others: OnceCell<OthersHold>,
    /// Each paired range alone, indexed at the first item with an equality for it among
    /// criteria that are not all equalities.
    singles: Vec<OnceCell<EqualityIndex>>,
}

/// The most combinations of keys one paired item may look up: each `""` among its
/// equalities names two keys (empty cells and empty text), so an item of many `""` would
/// name 2^n; past this it is tested cell by cell (within [`MAX_CRITERIA_SCAN`]).
const MAX_KEY_COMBINATIONS: usize = 16;

impl PairedRanges {
    fn worth_it(ranges: &[CellBlock], criteria: &[Value]) -> Option<Vec<usize>> {
        let which: Vec<usize> = (0..criteria.len()).filter(|&i| matches!(criteria[i], Value::Array(_))).collect();
        if which.len() < 2 {
            return None;
        }
        let shape = |i: usize| match &criteria[i] {
            Value::Array(a) if a.tail.is_none() => Some((a.rows, a.cols)),
            _ => None,
        };
        let paired = which.iter().all(|&i| shape(i).is_some() && shape(i) == shape(which[0]));
        let same_shape = ranges.iter().all(|r| r.same_shape(&ranges[0]));
        (paired && same_shape && worth_indexing(&criteria[which[0]])).then_some(which)
    }

    fn new(ranges: &[CellBlock], criteria: &[Value], which: Vec<usize>, dates: DateSystem) -> PairedRanges {
        let (read_rows, read_cols) = read_size(ranges);
        let fixed: Vec<Criterion> = criteria.iter().map(|v| Criterion::new(v, dates)).collect();
        let singles = which.iter().map(|_| OnceCell::new()).collect();
        PairedRanges { which, fixed, read_rows, read_cols, index: OnceCell::new(), others: OnceCell::new(), singles }
    }

    /// The combinations of keys the paired equality criteria name (one, or more where a
    /// `""` names both empty cells and empty text); `None` unless all are equalities and
    /// they name at most [`MAX_KEY_COMBINATIONS`].
    fn keys(&self, criteria: &[Criterion]) -> Option<Vec<Vec<ItemKey>>> {
        let per_range = self.keys_per_range(criteria)?;
        let mut out = vec![Vec::with_capacity(per_range.len())];
        for keys in per_range {
            out = out
                .iter()
                .flat_map(|combination| {
                    keys.iter().map(move |key| [&combination[..], std::slice::from_ref(key)].concat())
                })
                .collect();
        }
        Some(out)
    }

    /// Each paired criterion's keys, when all are equalities naming at most
    /// [`MAX_KEY_COMBINATIONS`] combinations: whether an item is looked up.
    fn keys_per_range(&self, criteria: &[Criterion]) -> Option<Vec<Vec<ItemKey>>> {
        let per_range: Vec<Vec<ItemKey>> = self.which.iter().map(|&i| criteria[i].keys()).collect::<Option<_>>()?;
        let combinations = per_range.iter().try_fold(1usize, |n, keys| n.checked_mul(keys.len()))?;
        (combinations <= MAX_KEY_COMBINATIONS).then_some(per_range)
    }

    /// The criteria of each item of the paired arrays, in turn.
    fn items<'c>(&'c self, criteria: &'c [Value], dates: DateSystem) -> impl Iterator<Item = Vec<Criterion>> + 'c {
        let items = if let Value::Array(first) = &criteria[self.which[0]] { first.data.len() } else { 0 };
        (0..items).map(move |j| {
            let mut item = self.fixed.clone();
            for &i in &self.which {
                if let Value::Array(a) = &criteria[i] {
                    item[i] = Criterion::new(&a.data[j], dates);
                }
            }
            item
        })
    }

    /// Each read cell filed once, under the combination of the keys an equality criterion
    /// names its values by ([`equality_key`]): a cell is one filing however many ranges
    /// hold text that reads as a number (filing it under both readings made 2^n filings).
    fn build_index(&self, ranges: &[CellBlock], dates: DateSystem) -> EqualityIndex<Vec<ItemKey>> {
        let cells = self.read_rows * self.read_cols;
        let mut index = EqualityIndex::with_capacity(cells);
        for p in 0..cells {
            let (row, col) = (p / self.read_cols, p % self.read_cols);
            let combination = self.which.iter().map(|&i| equality_key(ranges[i].get(row, col), dates)).collect();
            if let Some(combination) = combination {
                index.file(combination, p, true);
            }
        }
        index
    }
}

/// The one key under which equality criteria find a value: text that reads as a number is
/// found by that number (the criterion `"5"` is the number 5, and a text criterion is never
/// text that reads as a number: [`Criterion::parse`] reads numbers first, and case, which
/// keys fold, does not change whether text reads as a number); `None` for what no
/// equality matches (NaN, an array).
fn equality_key(v: &Value, dates: DateSystem) -> Option<ItemKey> {
    match v {
        Value::Text(t) => match parse_number(t, dates) {
            Some(n) => item_key(&Value::Number(n)),
            None => item_key(v),
        },
        v => item_key(v),
    }
}

/// The keys an [`EqualityIndex`] files a cell under: its own value's, and for text that
/// reads as a number, that number's (`false`: not its own value).
fn cell_keys(v: &Value, dates: DateSystem) -> impl Iterator<Item = (ItemKey, bool)> {
    let own = item_key(v).map(|key| (key, true));
    let as_number = match v {
        Value::Text(t) => parse_number(t, dates).and_then(|n| item_key(&Value::Number(n))).map(|key| (key, false)),
        _ => None,
    };
    own.into_iter().chain(as_number)
}

impl IndexedRange<'_> {
    /// The range to index: the one whose criteria argument is an array of many items, the
    /// others' being single values (what `lift_values` pairs item by item is not indexed).
    fn worth_it(ranges: &[CellBlock], criteria: &[Value]) -> Option<usize> {
        let mut arrays = (0..criteria.len()).filter(|&i| matches!(criteria[i], Value::Array(_)));
        let (which, second) = (arrays.next()?, arrays.next());
        let same_shape = ranges.iter().all(|r| r.same_shape(&ranges[0]));
        (second.is_none() && same_shape && worth_indexing(&criteria[which])).then_some(which)
    }

    fn new(ranges: &[CellBlock], criteria: &[Value], which: usize, dates: DateSystem) -> Self {
        let (read_rows, read_cols) = read_size(ranges);
        let fixed: Vec<Criterion> = criteria.iter().map(|v| Criterion::new(v, dates)).collect();
        IndexedRange {
            which,
            fixed,
            read_rows,
            read_cols,
            index: OnceCell::new(),
            others: OnceCell::new(),
            ordered: OnceCell::new(),
            sorted_summary: OnceCell::new(),
            others_in_order: OnceCell::new(),
            keyed_summary: OnceCell::new(),
        }
    }
}

fn is_order(op: BinOp) -> bool {
    matches!(op, BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
}

/// How many cells a comparison criterion matches: those of its kind (only values of one
/// kind compare) before, equal to and after its value, as its operator takes them.
fn count_ordered(ordered: &OrderIndex, criterion: &Criterion) -> usize {
    let Some(target) = comparison_key(criterion) else {
        return 0;
    };
    let sides = ordered.sides(&target);
    let orders = [Ordering::Less, Ordering::Equal, Ordering::Greater];
    orders.iter().zip(sides).filter(|(ord, _)| comparison_holds(criterion.op, **ord)).map(|(_, n)| n).sum()
}

/// The value a comparison criterion compares cells with; `None` for an empty cell or an
/// error, which compare with nothing.
fn comparison_key(criterion: &Criterion) -> Option<Value> {
    match &criterion.target {
        Target::Number(n) if !n.is_nan() => Some(Value::Number(*n)),
        Target::Text { text, .. } => Some(Value::Text(text.clone())),
        Target::Bool(b) => Some(Value::Bool(*b)),
        _ => None,
    }
}

/// The key of the one value a `<>` criterion leaves out (`"<>5"` the number 5, not the text
/// "5"); `None` for other criteria and for `<>` patterns.
fn single_unequal_key(criterion: &Criterion) -> Option<ItemKey> {
    let [key] = <[ItemKey; 1]>::try_from(criterion.unequal_keys()?).ok()?;
    Some(key)
}

/// The sum of integers whose magnitudes add up to less than this is exact in any order.
const EXACT_SUM: f64 = 9_007_199_254_740_992.0;

/// Whether the numbers of a summary taken in another order than row by row give exactly
/// the row-by-row result: a sum does when every number is an integer and their magnitudes
/// add up to less than 2^53; an extreme does when no number is NaN or -0 (the smaller of 0
/// and -0 depends on which comes first).
struct ExactCheck {
    summary: Summary,
    magnitude: f64,
}

impl ExactCheck {
    fn new(summary: Summary) -> ExactCheck {
        ExactCheck { summary, magnitude: 0.0 }
    }

    fn admits(&mut self, x: f64) -> bool {
        if x.is_nan() || (x == 0.0 && x.is_sign_negative()) {
            return false;
        }
        if self.summary != Summary::Total {
            return true;
        }
        self.magnitude += x.abs();
        x.fract() == 0.0 && self.magnitude < EXACT_SUM
    }
}

/// The target's numbers beside a range's cells in sorted order, summarized so that the run
/// of that order a comparison matches (from the start of its kind, numbers, text or
/// booleans, or to its end) is answered by a look-up or two: prefix sums for a total, for
/// an extreme the extremes from each kind's start and to each kind's end. Built only where
/// that is exactly the row-by-row result ([`ExactCheck`]) and no error lies beside a cell
/// (the result would be the first error in row order).
struct SortedSummary {
    summary: Summary,
    /// How many numbers lie beside the first i sorted cells.
    counts: Vec<usize>,
    /// Their running sum, for a total.
    sums: Vec<f64>,
    /// For an extreme: the extreme beside the sorted cells from the start of cell i's kind
    /// through cell i, and from cell i through the end of its kind.
    from_start: Vec<f64>,
    to_end: Vec<f64>,
}

impl SortedSummary {
    /// `beside`: per sorted cell, the target's value there where the other ranges'
    /// criteria hold (`None` where they do not). `kind_starts`: where each kind starts.
    fn new<'v>(
        beside: impl Iterator<Item = Option<&'v Value>>,
        summary: Summary,
        kind_starts: &[usize],
    ) -> Option<SortedSummary> {
        let mut check = ExactCheck::new(summary);
        let mut counts = vec![0];
        let mut values = Vec::new();
        for v in beside {
            let x = match v {
                Some(Value::Number(x)) if check.admits(*x) => Some(*x),
                Some(Value::Number(_) | Value::Error(_)) => return None,
                _ => None,
            };
            counts.push(counts[counts.len() - 1] + usize::from(x.is_some()));
            values.push(x.unwrap_or(summary.identity()));
        }
        let mut built = SortedSummary { summary, counts, sums: Vec::new(), from_start: Vec::new(), to_end: Vec::new() };
        if summary == Summary::Total {
            built.sums = running(values.iter().copied(), |sum, x| sum + x, 0.0, &[]);
            built.sums.insert(0, 0.0);
        } else {
            let restarts: Vec<usize> = kind_starts.iter().map(|&start| values.len().saturating_sub(start)).collect();
            let pick = |a, b| summary.pick(a, b);
            built.from_start = running(values.iter().copied(), pick, summary.identity(), kind_starts);
            built.to_end = running(values.iter().rev().copied(), pick, summary.identity(), &restarts);
            built.to_end.reverse();
        }
        Some(built)
    }

    /// The items built: the work of building.
    fn work(&self) -> usize {
        self.counts.len() + self.sums.len() + self.from_start.len() + self.to_end.len()
    }

    /// The summary and count of the numbers beside sorted cells `from` (where a kind
    /// starts) to `to` (not included); the summary is 0 where there is none.
    fn run_from_kind_start(&self, from: usize, to: usize) -> (f64, usize) {
        self.over(from, to, |cells| self.from_start[cells.end - 1])
    }

    /// The same from sorted cell `from` to `to`, where a kind ends (not included).
    fn run_to_kind_end(&self, from: usize, to: usize) -> (f64, usize) {
        self.over(from, to, |cells| self.to_end[cells.start])
    }

    fn over(&self, from: usize, to: usize, extreme: impl Fn(std::ops::Range<usize>) -> f64) -> (f64, usize) {
        let count = self.counts[to] - self.counts[from];
        match (count, self.summary) {
            (0, _) => (0.0, 0),
            (_, Summary::Total) => (self.sums[to] - self.sums[from], count),
            _ => (extreme(from..to), count),
        }
    }
}

/// The running `step` of `values` from `start`, begun again at each of `restarts`.
fn running(
    values: impl Iterator<Item = f64>,
    step: impl Fn(f64, f64) -> f64,
    start: f64,
    restarts: &[usize],
) -> Vec<f64> {
    let mut out = Vec::with_capacity(values.size_hint().0);
    let mut acc = start;
    for (i, x) in values.enumerate() {
        if restarts.contains(&i) {
            acc = start;
        }
        acc = step(acc, x);
        out.push(acc);
    }
    out
}

/// The target's numbers beside a range's cells, tallied per value of the cell, for `<>`
/// criteria: `"<>x"` matches all but the cells whose own value is x, so its sum is the
/// whole's less theirs, and its extreme the best of the other values' (the best value's,
/// or the runner-up's when x is the best one). Built only where that is exactly the
/// row-by-row result ([`ExactCheck`]).
struct KeyedSummary {
    summary: Summary,
    all: Tally,
    by_key: HashMap<Option<ItemKey>, Tally>,
    /// The value whose cells have the extreme number beside them, and that extreme.
    best: Option<(Option<ItemKey>, f64)>,
    /// The extreme beside the other values' cells.
    runner_up: f64,
    /// The first error beside a cell in row order, with the cell's value, and the first
    /// beside a cell of another value: the result of a `<>` that matches them.
    first_error: Option<(Option<ItemKey>, XlError)>,
    other_error: Option<XlError>,
}

/// The sum (or extreme) and count of some numbers.
#[derive(Clone, Copy)]
struct Tally {
    summary: f64,
    count: usize,
}

impl KeyedSummary {
    /// `beside`: the key of each cell (where the other ranges' criteria hold), in row
    /// order, and the target's value beside it.
    fn new<'v>(beside: impl Iterator<Item = (Option<ItemKey>, &'v Value)>, summary: Summary) -> Option<KeyedSummary> {
        let mut check = ExactCheck::new(summary);
        let none = Tally { summary: summary.identity(), count: 0 };
        let add = |tally: &mut Tally, x: f64| {
            tally.summary = summary.pick(tally.summary, x);
            tally.count += 1;
        };
        let (mut all, mut by_key) = (none, HashMap::<Option<ItemKey>, Tally>::new());
        let (mut first_error, mut other_error) = (None, None);
        for (key, v) in beside {
            match v {
                Value::Number(x) if check.admits(*x) => {
                    add(&mut all, *x);
                    add(by_key.entry(key).or_insert(none), *x);
                }
                Value::Number(_) => return None,
                Value::Error(e) => match &first_error {
                    None => first_error = Some((key, *e)),
                    Some((first, _)) if other_error.is_none() && *first != key => other_error = Some(*e),
                    _ => {}
                },
                _ => {}
            }
        }
        let counted = || by_key.iter().filter(|(_, tally)| tally.count > 0);
        let better = |best: f64, x: f64| summary.pick(best, x) != best;
        let mut best: Option<(Option<ItemKey>, f64)> = None;
        for (key, tally) in counted() {
            if best.as_ref().is_none_or(|(_, x)| better(*x, tally.summary)) {
                best = Some((key.clone(), tally.summary));
            }
        }
        let best_key = best.as_ref().map(|(key, _)| key);
        let runner_up = counted()
            .filter(|(key, _)| Some(*key) != best_key)
            .fold(summary.identity(), |x, (_, tally)| summary.pick(x, tally.summary));
        Some(KeyedSummary { summary, all, by_key, best, runner_up, first_error, other_error })
    }

    /// The summary and count of the numbers beside the cells whose own value's key is not
    /// `key`, or the first error beside them.
    fn unequal(&self, key: ItemKey) -> XlResult<(f64, usize)> {
        let key = Some(key);
        if let Some((first, e)) = &self.first_error {
            if *first != key {
                return Err(*e);
            }
            if let Some(e) = self.other_error {
                return Err(e);
            }
        }
        let equal = self.by_key.get(&key).map_or((0.0, 0), |tally| (tally.summary, tally.count));
        let count = self.all.count - equal.1;
        if count == 0 {
            return Ok((0.0, 0));
        }
        let summary = match (self.summary, &self.best) {
            (Summary::Total, _) => self.all.summary - equal.0,
            (_, Some((best, x))) if *best != key => *x,
            _ => self.runner_up,
        };
        Ok((summary, count))
    }
}

/// The read cells of a range filed by what equality criteria name: each cell under its
/// value's key (text folded to lower case, numbers by value), and text that reads as a
/// number under that number too (`COUNTIF(r, 23)` counts "23"). Each key's cells are a
/// chain through `filed`, in order, so that a million distinct cells make no million lists.
pub(crate) struct EqualityIndex<K = ItemKey> {
    /// The first and last entry of `filed` for each key, and how many cells it files.
    chains: HashMap<K, Chain>,
    /// (position, next entry of the same key or `END`).
    filed: Vec<(usize, usize)>,
}

const END: usize = usize::MAX;

struct Chain {
    first: usize,
    last: usize,
    /// Every cell filed under the key, and those filed under their own value (not text
    /// filed under the number it reads as).
    len: usize,
    own: usize,
}

impl EqualityIndex {
    /// Files `cells`, each under its position among them.
    pub(crate) fn new<'v>(cells: impl Iterator<Item = &'v Value>, dates: DateSystem) -> EqualityIndex {
        let mut index = EqualityIndex::with_capacity(cells.size_hint().0);
        for (p, v) in cells.enumerate() {
            for (key, own) in cell_keys(v, dates) {
                index.file(key, p, own);
            }
        }
        index
    }
}

impl<K: Hash + Eq> EqualityIndex<K> {
    fn with_capacity(cells: usize) -> EqualityIndex<K> {
        EqualityIndex { chains: HashMap::new(), filed: Vec::with_capacity(cells) }
    }

    fn file(&mut self, key: K, position: usize, own: bool) {
        let entry = self.filed.len();
        self.filed.push((position, END));
        match self.chains.get_mut(&key) {
            Some(chain) => {
                self.filed[chain.last].1 = entry;
                chain.last = entry;
                chain.len += 1;
                chain.own += usize::from(own);
            }
            None => {
                self.chains.insert(key, Chain { first: entry, last: entry, len: 1, own: usize::from(own) });
            }
        }
    }

    /// How many cells are filed under `key` (under their own value only when `own`).
    fn count(&self, key: &K, own: bool) -> usize {
        self.chains.get(key).map_or(0, |chain| if own { chain.own } else { chain.len })
    }

    /// How many positions are filed under any of `keys` (which no cell shares).
    pub(crate) fn count_filed(&self, keys: &[K]) -> usize {
        keys.iter().map(|key| self.count(key, false)).sum()
    }

    /// The positions filed under any of `keys` (which no cell shares), in order.
    pub(crate) fn positions(&self, keys: &[K]) -> Vec<usize> {
        let mut positions = Vec::new();
        for key in keys {
            let mut entry = self.chains.get(key).map_or(END, |chain| chain.first);
            while entry != END {
                let (position, next) = self.filed[entry];
                positions.push(position);
                entry = next;
            }
        }
        if keys.len() > 1 {
            positions.sort_unstable();
        }
        positions
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn holds(criterion: impl Into<Value>, cell: impl Into<Value>) -> bool {
        Criterion::new(&criterion.into(), DateSystem::From1900).matches(&cell.into())
    }

    #[test]
    fn numeric_criteria_match_numbers_and_numeric_text() {
        assert!(holds(23.0, 23.0));
        assert!(holds(23.0, "23"));
        assert!(holds("=23", "23"));
        assert!(holds("<5", 4.0));
        assert!(!holds("<5", "4"));
        assert!(!holds("<5", Value::Blank));
        assert!(!holds("<5", true));
        assert!(holds(">=2", 2.0));
        assert!(holds("<>3", Value::Blank));
        assert!(holds("<>3", "x"));
        assert!(!holds("<>3", 3.0));
        assert!(holds("<>3", "3"));
    }

    #[test]
    fn text_criteria_are_case_insensitive_with_wildcards() {
        assert!(holds("abc*", "ABCdef"));
        assert!(!holds("abc*", "xabc"));
        assert!(holds("a?c", "abc"));
        assert!(!holds("a?c", "ac"));
        assert!(holds("*~*", "5*"));
        assert!(!holds("*~*", "5"));
        assert!(holds("~?", "?"));
        assert!(holds("<>x", 1.0));
        assert!(!holds("<>X", "x"));
        assert!(holds("<b", "Apple"));
        assert!(!holds("<b", 1.0));
        assert!(holds("*", "anything"));
        assert!(!holds("*", 1.0));
    }

    #[test]
    fn empty_criteria_tell_blank_from_empty_text() {
        assert!(holds("", Value::Blank));
        assert!(holds("", ""));
        assert!(holds("=", Value::Blank));
        assert!(!holds("=", ""));
        assert!(!holds("<>", Value::Blank));
        assert!(holds("<>", ""));
        assert!(holds(Value::Blank, 0.0));
    }

    #[test]
    fn booleans_and_errors_match_their_own_kind() {
        assert!(holds(true, true));
        assert!(!holds(true, 1.0));
        assert!(holds("true", true));
        assert!(holds("#N/A", XlError::NA));
        assert!(holds(XlError::Div0, XlError::Div0));
        assert!(!holds(XlError::Div0, XlError::NA));
    }

    /// A column of `k` numbers 1 … k, and `k` criteria `op`&1 … `op`&k as one array.
    fn column_and_criteria(k: usize, op: &str) -> (Vec<CellBlock>, Vec<Value>) {
        let column = Array::new(k, 1, (1..=k).map(|i| Value::Number(i as f64)).collect());
        let criteria = Array::new(k, 1, (1..=k).map(|i| Value::text(format!("{op}{i}"))).collect());
        let block = CellBlock::from_value(Value::Array(Rc::new(column))).unwrap();
        (vec![block], vec![Value::Array(Rc::new(criteria))])
    }

    fn count_each(matcher: &CriteriaMatcher, criteria: &Value) -> usize {
        let Value::Array(items) = criteria else { unreachable!() };
        let each = |v: &Value| matcher.count(&[Criterion::new(v, DateSystem::From1900)]).unwrap();
        items.data.iter().map(each).sum()
    }

    #[test]
    fn comparisons_and_patterns_build_no_equality_index() {
        let k = 64;
        // ">i" counts k − i cells: the sum is k(k − 1)/2, by sorting once (k·2·7 work) and
        // four binary searches (4·7) a criterion; no equality index (k more) is built.
        let (ranges, criteria) = column_and_criteria(k, ">");
        let matcher = CriteriaMatcher::new(&ranges, &criteria, DateSystem::From1900);
        assert_eq!(count_each(&matcher, &criteria[0]), k * (k - 1) / 2);
        assert!(!matcher.index_built());
        assert_eq!(matcher.work.get(), k * 14 + k * 28);
        // "?"&i and "*"&i match text only: none of these numbers; each tests every cell.
        let (ranges, criteria) = column_and_criteria(k, "*");
        let matcher = CriteriaMatcher::new(&ranges, &criteria, DateSystem::From1900);
        assert_eq!(count_each(&matcher, &criteria[0]), 0);
        assert!(!matcher.index_built());
        assert_eq!(matcher.work.get(), k * k);
        // Equalities build it at the first criterion: k filings, then one look each (the
        // index counts the cells filed under a value).
        let (ranges, criteria) = column_and_criteria(k, "=");
        let matcher = CriteriaMatcher::new(&ranges, &criteria, DateSystem::From1900);
        assert_eq!(count_each(&matcher, &criteria[0]), k);
        assert!(matcher.index_built());
        assert_eq!(matcher.work.get(), k + k);
    }

    #[test]
    fn a_star_only_at_the_end_is_a_prefix() {
        let prefix = |c: &str| Criterion::new(&Value::text(c), DateSystem::From1900).prefix();
        assert_eq!(prefix("BOL*"), Some(vec!['b', 'o', 'l']));
        assert_eq!(prefix("=ß*"), Some(vec!['ß']));
        assert_eq!(prefix("*"), Some(vec![]));
        assert_eq!(prefix("~**"), Some(vec!['*']));
        for not_one in ["b?l*", "*bol", "b*l", "<>bol*", ">bol*", "bol", "bol~*"] {
            assert_eq!(prefix(not_one), None, "{not_one}");
        }
    }

    /// `ranges` columns of `rows` cells drawn from a fixed sequence of values an equality
    /// tells apart or not: 5 as a number and as text (" 5 ", "5.0"), a date as text and
    /// its serial, words in either case, TRUE and "TRUE", blanks and empty text.
    fn drawn_columns(rows: usize, ranges: usize, seed: u64) -> Vec<CellBlock> {
        let pool = [
            Value::Number(5.0),
            Value::text("5"),
            Value::text(" 5 "),
            Value::text("5.0"),
            Value::Number(7.0),
            Value::text("7"),
            Value::text("1/2/2024"),
            Value::Number(45293.0),
            Value::text("x"),
            Value::text("X"),
            Value::Bool(true),
            Value::text("TRUE"),
            Value::Blank,
            Value::text(""),
        ];
        let mut state = seed;
        let mut draw = || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            pool[(state >> 33) as usize % pool.len()].clone()
        };
        let column = |_| Array::new(rows, 1, (0..rows).map(|_| draw()).collect());
        let columns: Vec<Array> = (0..ranges).map(column).collect();
        columns.into_iter().map(|a| CellBlock::from_value(Value::Array(Rc::new(a))).unwrap()).collect()
    }

    /// Criteria arrays paired item by item, `items` each, from a fixed sequence: equalities
    /// of every kind in the columns (`""`, `"="`, 5, "5", date text), and now and then a
    /// comparison or a `<>`, which is tested cell by cell.
    fn drawn_criteria(items: usize, ranges: usize, seed: u64) -> Vec<Value> {
        let pool = [
            Value::Number(5.0),
            Value::text("5"),
            Value::text("=5"),
            Value::Number(7.0),
            Value::text("2024-01-02"),
            Value::text("x"),
            Value::text("=X"),
            Value::Bool(true),
            Value::text("TRUE"),
            Value::text(""),
            Value::text("="),
            Value::text("<>5"),
            Value::text(">4"),
        ];
        let mut state = seed ^ 0x9e37_79b9;
        let mut draw = || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            pool[(state >> 33) as usize % pool.len()].clone()
        };
        let array = |_| Value::Array(Rc::new(Array::new(items, 1, (0..items).map(|_| draw()).collect())));
        (0..ranges).map(array).collect()
    }

    /// Two to six paired criteria arrays over columns that mix numbers and text reading as
    /// numbers: each item counts and finds the cells a plain scan ([`matching_cells`])
    /// finds, and the index files each cell once (text reading as a number in each of four
    /// columns was filed under 2^4 combinations of its two readings, uncounted).
    #[test]
    fn paired_arrays_find_what_a_scan_finds_filing_each_cell_once() {
        let (rows, items) = (300, 40);
        for ranges in 2..=6 {
            for seed in 0..4 {
                let columns = drawn_columns(rows, ranges, seed);
                let criteria = drawn_criteria(items, ranges, seed);
                let matcher = CriteriaMatcher::new(&columns, &criteria, DateSystem::From1900);
                assert!(matcher.paired.is_some(), "{ranges} arrays");
                for j in 0..items {
                    let item: Vec<Criterion> = criteria
                        .iter()
                        .map(|v| match v {
                            Value::Array(a) => Criterion::new(&a.data[j], DateSystem::From1900),
                            _ => unreachable!(),
                        })
                        .collect();
                    let scanned = matching_cells(&columns, &item).unwrap();
                    assert_eq!(matcher.count(&item).unwrap(), scanned.cells.len(), "{ranges} arrays, item {j}");
                    assert_eq!(matcher.matches(&item).unwrap().cells, scanned.cells, "{ranges} arrays, item {j}");
                }
                let filed =
                    matcher.paired.as_ref().and_then(|paired| paired.index.get()).map(|index| index.filed.len());
                assert!(filed.is_some_and(|filed| filed <= rows), "{ranges} arrays: {filed:?} filings");
            }
        }
        // Four columns of text that reads as numbers: one filing a cell.
        let column = || {
            let texts = (1..=64).map(|i| Value::text(format!("{i}"))).collect();
            CellBlock::from_value(Value::Array(Rc::new(Array::new(64, 1, texts)))).unwrap()
        };
        let columns = vec![column(), column(), column(), column()];
        let keys = Value::Array(Rc::new(Array::new(64, 1, (1..=64).map(|i| Value::Number(i as f64)).collect())));
        let criteria = vec![keys.clone(), keys.clone(), keys.clone(), keys];
        let matcher = CriteriaMatcher::new(&columns, &criteria, DateSystem::From1900);
        assert_eq!(count_each_paired(&matcher, &criteria), 64);
        assert_eq!(
            matcher.paired.as_ref().and_then(|paired| paired.index.get()).map(|index| index.filed.len()),
            Some(64)
        );
    }

    /// The count of each item of paired criteria arrays, summed.
    fn count_each_paired(matcher: &CriteriaMatcher, criteria: &[Value]) -> usize {
        let arrays: Vec<&Array> =
            criteria.iter().map(|v| if let Value::Array(a) = v { &**a } else { unreachable!() }).collect();
        let item =
            |j: usize| arrays.iter().map(|a| Criterion::new(&a.data[j], DateSystem::From1900)).collect::<Vec<_>>();
        (0..arrays[0].data.len()).map(|j| matcher.count(&item(j)).unwrap()).sum()
    }

    /// COUNTIFS with a comparison array beside a criterion that holds in some cells only
    /// counts along the sorted order: a sort, a running count, four binary searches an
    /// item; the counts are a scan's.
    #[test]
    fn comparisons_beside_a_criterion_that_does_not_always_hold_count_without_a_scan() {
        let k = 64;
        let column = Array::new(k, 1, (1..=k).map(|i| Value::Number(i as f64)).collect());
        let odd = Array::new(k, 1, (1..=k).map(|i| Value::Number((i % 2) as f64)).collect());
        let block = |a: Array| CellBlock::from_value(Value::Array(Rc::new(a))).unwrap();
        let ranges = vec![block(column), block(odd)];
        for op in ["<", "<=", ">", ">="] {
            let criteria = Array::new(k, 1, (1..=k).map(|i| Value::text(format!("{op}{i}"))).collect());
            let criteria = vec![Value::Array(Rc::new(criteria)), Value::Number(1.0)];
            let matcher = CriteriaMatcher::new(&ranges, &criteria, DateSystem::From1900);
            let Value::Array(items) = &criteria[0] else { unreachable!() };
            for v in &items.data {
                let item =
                    [Criterion::new(v, DateSystem::From1900), Criterion::new(&criteria[1], DateSystem::From1900)];
                assert_eq!(matcher.count(&item).unwrap(), matching_cells(&ranges, &item).unwrap().cells.len(), "{v:?}");
            }
            // The others tested once (k), sorted (k·2·7), counted along (k); each item four
            // binary searches (4·7).
            assert_eq!(matcher.work.get(), k + k * 14 + k + k * 28, "{op}");
        }
    }

    #[test]
    fn glob_backtracks_over_stars() {
        assert!(wildcard_match("*b*b", "abcbab"));
        assert!(wildcard_match("**", ""));
        assert!(!wildcard_match("?", ""));
        assert!(wildcard_match("Mr*. Brown", "mrs. brown"));
    }
}
