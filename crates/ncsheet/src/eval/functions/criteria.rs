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
/// used to scan the whole range (100,000 criteria over 100,000 cells took minutes). Other
/// criteria (comparisons, `<>`, patterns) are tested cell by cell as before. `work` counts
/// the cells looked at, for the LAMBDA work budget.
pub struct CriteriaMatcher<'a> {
    ranges: &'a [CellBlock],
    indexed: Option<IndexedRange<'a>>,
    /// Two ranges whose criteria arrays pair item by item, indexed together.
    paired: Option<PairedRanges>,
    dates: DateSystem,
    /// The range summed, for [`CriteriaMatcher::ordered_total`].
    target: Option<&'a CellBlock>,
    pub work: Cell<usize>,
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
    sums: OnceCell<Option<SortedSums>>,
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

    /// The matcher of an aggregate that sums `target` (SUMIF, AVERAGEIF and their *IFS):
    /// a comparison's matches are then summed from [`SortedSums`] where that is exact.
    pub fn summing(self, target: &'a CellBlock) -> CriteriaMatcher<'a> {
        CriteriaMatcher { target: Some(target), ..self }
    }

    /// The sum and the count of the target's numbers where every criterion holds, when the
    /// indexed range's criterion is a comparison and the other ranges' hold everywhere
    /// (`SUMIF(r, "<="&keys, s)`), from prefix sums: `None` where the cells must be
    /// tested one by one.
    pub fn ordered_total(&self, criteria: &[Criterion]) -> Option<(f64, usize)> {
        let indexed = self.indexed.as_ref()?;
        let criterion = &criteria[indexed.which];
        let sums = self.sorted_sums(indexed, criterion)?;
        let Some(key) = comparison_key(criterion) else {
            return Some((0.0, 0));
        };
        let ordered = self.ordered(indexed);
        self.add_work(2 * ordered.query_work());
        let [kind_start, before, through, kind_end] = ordered.bounds(&key);
        let (from, to) = match criterion.op {
            BinOp::Lt => (kind_start, before),
            BinOp::Le => (kind_start, through),
            BinOp::Gt => (through, kind_end),
            _ => (before, kind_end),
        };
        Some(sums.total(from, to))
    }

    /// The prefix sums for a comparison `criterion` of the indexed range, built at the
    /// first; `None` when the matcher sums no target, the criterion is no comparison, the
    /// other ranges' criteria do not hold everywhere, or the sums would not be exact.
    fn sorted_sums<'m>(&'m self, indexed: &'m IndexedRange<'a>, criterion: &Criterion) -> Option<&'m SortedSums> {
        let target = self.target?;
        if !is_order(criterion.op) || !self.others_hold(indexed).everywhere {
            return None;
        }
        let cols = self.ranges[indexed.which].read.cols;
        let ordered = self.ordered(indexed);
        indexed
            .sums
            .get_or_init(|| {
                self.add_work(ordered.sorted().len());
                SortedSums::new(ordered, cols, target)
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

    /// How many cells meet every criterion: a comparison of the indexed range's criterion
    /// counts by binary search when the other ranges' criteria hold everywhere (COUNTIF).
    pub fn count(&self, criteria: &[Criterion]) -> XlResult<usize> {
        if let Some(n) = self.paired.as_ref().and_then(|paired| self.paired_count(paired, criteria)) {
            return Ok(n + blanks_beyond(self.ranges, criteria));
        }
        if let Some(indexed) = &self.indexed {
            let criterion = &criteria[indexed.which];
            if is_order(criterion.op) && self.others_hold(indexed).everywhere {
                let ordered = self.ordered(indexed);
                self.add_work(2 * ordered.query_work());
                return Ok(count_ordered(ordered, criterion) + blanks_beyond(self.ranges, criteria));
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

    /// `#NUM!`, with a note, when the criteria items (the argument values given to
    /// [`CriteriaMatcher::new`]) would test more than [`MAX_CRITERIA_SCAN`] cells one by
    /// one: known before any is tested, so that such a call stops at once.
    pub fn within_scan_limit(&self, ctx: &mut Ctx, criteria: &[Value], counting: bool) -> XlResult<()> {
        let work = self.scan_work(criteria, counting);
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
            let [a, b] = paired.which;
            let (Value::Array(x), Value::Array(y)) = (&criteria[a], &criteria[b]) else {
                return per_scan;
            };
            let unkeyed = |v: &Value| Criterion::new(v, self.dates).keys().is_none();
            let scanned = x.data.iter().zip(&y.data).filter(|(u, v)| unkeyed(u) || unkeyed(v)).count();
            return per_scan.saturating_mul(scanned);
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
            return !keyed && self.sorted_sums(indexed, criterion).is_none();
        }
        let ordered = is_order(criterion.op) && self.others_hold(indexed).everywhere;
        !(keyed || ordered || criterion.unequal_keys().is_some())
    }

    fn add_work(&self, n: usize) {
        self.work.set(self.work.get().saturating_add(n));
    }

    /// The cells where every range meets its criterion ([`matching_cells`]).
    pub fn matches(&self, criteria: &[Criterion]) -> XlResult<Matches> {
        if let Some(cells) = self.paired.as_ref().and_then(|paired| self.paired_matches(paired, criteria)) {
            return Ok(Matches { cells, blanks_beyond: blanks_beyond(self.ranges, criteria) });
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

    /// How many read cells a paired item's two equalities and the other ranges' criteria
    /// hold in; `None` unless both of the pair are equalities.
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

    /// The read cells, in row order, where a paired item's two equalities and the other
    /// ranges' criteria hold; `None` unless both of the pair are equalities.
    fn paired_matches(&self, paired: &PairedRanges, criteria: &[Criterion]) -> Option<Vec<(usize, usize)>> {
        let keys = paired.keys(criteria)?;
        let others = self.paired_others(paired);
        let positions = self.paired_index(paired).positions(&keys);
        self.add_work(1 + positions.len());
        let cols = paired.read_cols;
        Some(positions.into_iter().filter(|&p| others.at[p]).map(|p| (p / cols, p % cols)).collect())
    }

    fn paired_others<'m>(&'m self, paired: &'m PairedRanges) -> &'m OthersHold {
        paired.others.get_or_init(|| {
            self.add_work(paired.read_rows * paired.read_cols * (self.ranges.len() - 2));
            OthersHold::new(self.ranges, &paired.which, &paired.fixed, paired.read_rows, paired.read_cols)
        })
    }

    fn paired_index<'m>(&'m self, paired: &'m PairedRanges) -> &'m EqualityIndex<(ItemKey, ItemKey)> {
        paired.index.get_or_init(|| {
            self.add_work(2 * paired.read_rows * paired.read_cols);
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

/// Two ranges whose criteria arguments are arrays of one shape, which `lift_values` pairs
/// item by item (`COUNTIFS(a, keys1, b, keys2)`): their read cells are filed by the pair of
/// values, so that a pair of equalities looks its cells up where it tested every cell.
struct PairedRanges {
    which: [usize; 2],
    /// The fixed criteria, one per range (the first items stand in for the pair's).
    fixed: Vec<Criterion>,
    read_rows: usize,
    read_cols: usize,
    index: OnceCell<EqualityIndex<(ItemKey, ItemKey)>>,
    others: OnceCell<OthersHold>,
}

impl PairedRanges {
    fn worth_it(ranges: &[CellBlock], criteria: &[Value]) -> Option<[usize; 2]> {
        let arrays: Vec<usize> = (0..criteria.len()).filter(|&i| matches!(criteria[i], Value::Array(_))).collect();
        let &[a, b] = arrays.as_slice() else {
            return None;
        };
        let (Value::Array(x), Value::Array(y)) = (&criteria[a], &criteria[b]) else {
            return None;
        };
        let paired = x.tail.is_none() && y.tail.is_none() && (x.rows, x.cols) == (y.rows, y.cols);
        let same_shape = ranges.iter().all(|r| r.same_shape(&ranges[0]));
        (paired && same_shape && worth_indexing(&criteria[a])).then_some([a, b])
    }

    fn new(ranges: &[CellBlock], criteria: &[Value], which: [usize; 2], dates: DateSystem) -> PairedRanges {
        let (read_rows, read_cols) = read_size(ranges);
        let fixed: Vec<Criterion> = criteria.iter().map(|v| Criterion::new(v, dates)).collect();
        PairedRanges { which, fixed, read_rows, read_cols, index: OnceCell::new(), others: OnceCell::new() }
    }

    /// The pairs of keys a pair of equality criteria names (one pair, or two where a `""`
    /// names both empty cells and empty text); `None` unless both are equalities.
    fn keys(&self, criteria: &[Criterion]) -> Option<Vec<(ItemKey, ItemKey)>> {
        let [a, b] = self.which;
        let (first, second) = (criteria[a].keys()?, criteria[b].keys()?);
        Some(first.iter().flat_map(|x| second.iter().map(move |y| (x.clone(), y.clone()))).collect())
    }

    /// Each read cell filed under every pair of the keys its two values are filed under.
    fn build_index(&self, ranges: &[CellBlock], dates: DateSystem) -> EqualityIndex<(ItemKey, ItemKey)> {
        let [a, b] = self.which;
        let cells = self.read_rows * self.read_cols;
        let mut index = EqualityIndex::with_capacity(cells);
        for p in 0..cells {
            let (row, col) = (p / self.read_cols, p % self.read_cols);
            let second: Vec<(ItemKey, bool)> = cell_keys(ranges[b].get(row, col), dates).collect();
            for (x, own_x) in cell_keys(ranges[a].get(row, col), dates) {
                for (y, own_y) in &second {
                    index.file((x.clone(), y.clone()), p, own_x && *own_y);
                }
            }
        }
        index
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
            sums: OnceCell::new(),
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

/// Prefix sums of a target's numbers (and counts of them) beside the criteria range's
/// cells in sorted order: a comparison matches a run of that order, summed by two look-ups.
/// Built only where the sum cannot depend on the order of adding (the old row-by-row sum is
/// exactly the same): every number there an integer (not -0), their magnitudes adding up to
/// less than 2^53; and no error there (the result is then the first error in row order).
struct SortedSums {
    sums: Vec<f64>,
    counts: Vec<usize>,
}

impl SortedSums {
    /// `range_cols` is the criteria range's stored width, in which `ordered` numbers its cells.
    fn new(ordered: &OrderIndex, range_cols: usize, target: &CellBlock) -> Option<SortedSums> {
        const EXACT: f64 = 9_007_199_254_740_992.0;
        let n = ordered.sorted().len();
        let (mut sums, mut counts) = (Vec::with_capacity(n + 1), Vec::with_capacity(n + 1));
        let (mut sum, mut count, mut magnitude) = (0.0, 0, 0.0);
        sums.push(sum);
        counts.push(count);
        for &p in ordered.sorted() {
            match target.get(p / range_cols, p % range_cols) {
                Value::Number(x) if x.fract() == 0.0 && !(*x == 0.0 && x.is_sign_negative()) => {
                    magnitude += x.abs();
                    if magnitude >= EXACT {
                        return None;
                    }
                    sum += x;
                    count += 1;
                }
                Value::Number(_) | Value::Error(_) => return None,
                _ => {}
            }
            sums.push(sum);
            counts.push(count);
        }
        Some(SortedSums { sums, counts })
    }

    /// The sum and count of the numbers beside sorted cells `from` to `to` (not included).
    fn total(&self, from: usize, to: usize) -> (f64, usize) {
        (self.sums[to] - self.sums[from], self.counts[to] - self.counts[from])
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

    #[test]
    fn glob_backtracks_over_stars() {
        assert!(wildcard_match("*b*b", "abcbab"));
        assert!(wildcard_match("**", ""));
        assert!(!wildcard_match("?", ""));
        assert!(wildcard_match("Mr*. Brown", "mrs. brown"));
    }
}
