//! Excel's value model: number, text, boolean, blank, error, and arrays of those.

use std::fmt;
use std::rc::Rc;

pub use crate::formula::XlError;

/// The result of evaluating anything. Errors are values, as in Excel.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Value {
    #[default]
    Blank,
    Number(f64),
    Bool(bool),
    Text(Rc<str>),
    Error(XlError),
    Array(Rc<Array>),
    /// A LAMBDA as a value (`LAMBDA(x, x+1)`, a LET name or parameter bound to one, what
    /// `IF(c, LAMBDA(…), LAMBDA(…))` chooses), to be called (`…(5)`) or handed to MAP,
    /// REDUCE…. Read where a number, text or condition is wanted it is `#CALC!`, and a
    /// formula whose result is one shows `#CALC!`, as in Excel.
    Lambda(Rc<Closure>),
    /// VBA's Null, "no valid data" (a macro's `Null`): no cell holds it. The macro's operators
    /// propagate it; a cell, or a function reading a number or a text, takes it as `#VALUE!`.
    Null,
}

pub use super::evaluator::Closure;

pub type XlResult<T> = Result<T, XlError>;

/// The most items one array a formula makes may hold (2^24, as SEQUENCE and RANDARRAY
/// allow): ncsheet's limit, since a sheet-sized array would be 17 billion items. Past it
/// the formula is `#NUM!` (docs/limits.md), never an allocation of gigabytes.
pub const MAX_ARRAY_ITEMS: usize = 1 << 24;

/// Whether an array of `rows` × `cols` items is past [`MAX_ARRAY_ITEMS`].
pub fn too_many_items(rows: usize, cols: usize) -> bool {
    rows.checked_mul(cols).is_none_or(|n| n > MAX_ARRAY_ITEMS)
}

/// The note of a formula whose array would pass [`MAX_ARRAY_ITEMS`].
pub fn too_many_items_note(rows: usize, cols: usize) -> String {
    format!("an array of {rows} × {cols} items, more than ncsheet's limit of {MAX_ARRAY_ITEMS}")
}

/// The most array items one formula's evaluation may hold at once: four arrays at
/// [`MAX_ARRAY_ITEMS`], about 1.5 GiB. Each array passing its own limit is not enough: a
/// function's arguments, an operator's operands and LET's names are all held until it
/// returns, and `HSTACK` of twelve `SEQUENCE(1048576,16)` asked for 4.5 GiB. Counted by the
/// evaluator ([`held_items`]); past it the formula is `#NUM!` (docs/limits.md).
pub const MAX_LIVE_ITEMS: usize = 1 << 26;

/// The note of a formula whose arrays held at once would pass `limit` items.
pub fn too_many_live_items_note(limit: usize) -> String {
    format!(
        "the arrays this formula holds at once (a function's arguments, an operator's operands, LET's names) \
         would pass {limit} items, ncsheet's limit"
    )
}

/// The items `v` holds in arrays that nothing else holds, as [`MAX_LIVE_ITEMS`] counts them:
/// an array's stored items, a text item two more and one per 24 bytes of its text (an item
/// is 24 bytes, and a text a block of its own); a LAMBDA, the arrays only it keeps alive (the
/// LET names it captured, after the LET returned). An array shared with another holder (a LET
/// name, a captured name, a macro's variable, a cell) takes no memory of its own: its holder
/// counts it.
pub fn held_items(v: &Value) -> usize {
    match v {
        Value::Array(a) if Rc::strong_count(a) == 1 => a.data.iter().map(item_weight).sum(),
        Value::Lambda(closure) if Rc::strong_count(closure) == 1 => closure.captured().map(held_items).sum(),
        _ => 0,
    }
}

/// One item of an array, as [`held_items`] counts it.
#[inline]
fn item_weight(v: &Value) -> usize {
    match v {
        Value::Text(t) => 3 + t.len() / 24,
        _ => 1,
    }
}

/// The most bytes of text the items of one array a formula makes may hold together: the
/// item limit alone let 2^24 texts of 30,000 characters (`REPT("x",30000)&SEQUENCE(4096,4096)`)
/// ask for 500 GB. Counted as the items are made, by [`TextBudget`]: 256 MiB.
pub const MAX_ARRAY_TEXT_BYTES: usize = 1 << 28;

/// The most bytes of text the items of one array a formula makes may read from their
/// operands together: a comparison or a FIND of two arrays of long texts makes small items
/// but reads each pair whole (100 × 4,000 texts of 30,000 characters compared took 53 s; a
/// SEARCH of 100,000 needles in one 32,000-character text, 77 s). Counted by [`TextBudget`]
/// as the items are made (TEXTSPLIT and its kin count the text once per delimiter): 512 MiB,
/// about a second of comparing, 5 s of SEARCH of distinct texts not ASCII, the slowest.
pub const MAX_ARRAY_TEXT_READ: usize = 1 << 29;

/// The text bytes of an array's items so far, against [`MAX_ARRAY_TEXT_BYTES`], and of the
/// operands' items read to make them, against [`MAX_ARRAY_TEXT_READ`].
#[derive(Default)]
pub struct TextBudget {
    made: usize,
    read: usize,
}

impl TextBudget {
    /// Counts `item`; `false` once the array's texts, or the texts read for them, pass
    /// their limits.
    #[inline]
    pub fn take(&mut self, item: &Value) -> bool {
        if let Value::Text(t) = item {
            self.made += t.len();
        }
        self.made <= MAX_ARRAY_TEXT_BYTES && self.read <= MAX_ARRAY_TEXT_READ
    }

    /// Counts an operand's item read to make the next item.
    #[inline]
    pub fn read(&mut self, operand: &Value) {
        if let Value::Text(t) = operand {
            self.read += t.len();
        }
    }
}

/// The note of a formula whose array's texts would pass [`MAX_ARRAY_TEXT_BYTES`] or
/// [`MAX_ARRAY_TEXT_READ`].
pub fn too_much_text_note() -> String {
    format!(
        "an array whose texts hold more than {} MiB, or whose items read more than {} MiB of text, ncsheet's limits",
        MAX_ARRAY_TEXT_BYTES >> 20,
        MAX_ARRAY_TEXT_READ >> 20
    )
}

/// A rectangular block of values, row-major. Never holds a nested array.
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    pub rows: usize,
    pub cols: usize,
    pub data: Vec<Value>,
    /// The array is larger than `rows` × `cols`: a whole row or column read as far as the
    /// sheet has data, the rest one known value. Code that ignores it sees the part stored.
    pub tail: Option<Box<Tail>>,
}

/// The part of an array beyond the items stored: all of `rows` × `cols` (the whole size)
/// outside the stored block holds `fill`. So `=1:1*2` is 16,384 items in memory
/// proportional to the used columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Tail {
    pub rows: usize,
    pub cols: usize,
    pub fill: Value,
}

impl Array {
    pub fn new(rows: usize, cols: usize, data: Vec<Value>) -> Array {
        debug_assert_eq!(rows * cols, data.len());
        Array { rows, cols, data, tail: None }
    }

    pub fn filled(rows: usize, cols: usize, v: Value) -> Array {
        Array { rows, cols, data: vec![v; rows * cols], tail: None }
    }

    /// A one-row array.
    pub fn row(data: Vec<Value>) -> Array {
        Array { rows: 1, cols: data.len(), data, tail: None }
    }

    /// A one-column array.
    pub fn column(data: Vec<Value>) -> Array {
        Array { rows: data.len(), cols: 1, data, tail: None }
    }

    /// This array as `whole_rows` × `whole_cols` (not smaller than stored), the items
    /// beyond the stored ones `fill`.
    pub fn with_tail(mut self, whole_rows: usize, whole_cols: usize, fill: Value) -> Array {
        let (rows, cols) = (whole_rows.max(self.rows), whole_cols.max(self.cols));
        self.tail = (rows > self.rows || cols > self.cols).then(|| Box::new(Tail { rows, cols, fill }));
        self
    }

    /// The whole size, tail included.
    pub fn whole_size(&self) -> (usize, usize) {
        self.tail.as_ref().map_or((self.rows, self.cols), |t| (t.rows, t.cols))
    }

    /// An item of the whole array: stored, the tail's fill, or `None` beyond the whole size.
    pub fn whole_get(&self, row: usize, col: usize) -> Option<&Value> {
        if row < self.rows && col < self.cols {
            return Some(self.get(row, col));
        }
        let (rows, cols) = self.whole_size();
        (row < rows && col < cols).then(|| &self.tail.as_ref().expect("beyond the stored items is the tail").fill)
    }

    pub fn get(&self, row: usize, col: usize) -> &Value {
        &self.data[row * self.cols + col]
    }

    /// Excel's broadcasting read: a single row or column repeats, beyond the edge is `#N/A`.
    pub fn broadcast_get(&self, row: usize, col: usize) -> Value {
        let r = if self.rows == 1 { 0 } else { row };
        let c = if self.cols == 1 { 0 } else { col };
        if r < self.rows && c < self.cols {
            self.get(r, c).clone()
        } else {
            Value::Error(XlError::NA)
        }
    }
}

impl Value {
    pub fn text(s: impl Into<Rc<str>>) -> Value {
        Value::Text(s.into())
    }

    pub fn is_blank(&self) -> bool {
        matches!(self, Value::Blank)
    }

    /// The error this value is, or reads as (a LAMBDA read as a value is `#CALC!`).
    pub fn as_error(&self) -> Option<XlError> {
        match self {
            Value::Error(e) => Some(*e),
            Value::Lambda(_) => Some(XlError::Calc),
            _ => None,
        }
    }

    /// A 1×1 array is its only item; anything else is unchanged.
    pub fn unwrap_single(self) -> Value {
        match self {
            Value::Array(a) if a.rows == 1 && a.cols == 1 => a.data[0].clone(),
            v => v,
        }
    }

    /// What a cell shows for a formula result: a blank result reads as 0, as in Excel.
    pub fn blank_as_zero(self) -> Value {
        match self {
            Value::Blank => Value::Number(0.0),
            v => v,
        }
    }
}

impl From<f64> for Value {
    fn from(v: f64) -> Value {
        Value::Number(v)
    }
}

impl From<bool> for Value {
    fn from(v: bool) -> Value {
        Value::Bool(v)
    }
}

impl From<&str> for Value {
    fn from(v: &str) -> Value {
        Value::Text(v.into())
    }
}

impl From<String> for Value {
    fn from(v: String) -> Value {
        Value::Text(v.into())
    }
}

impl From<XlError> for Value {
    fn from(v: XlError) -> Value {
        Value::Error(v)
    }
}

impl From<Array> for Value {
    fn from(v: Array) -> Value {
        Value::Array(Rc::new(v))
    }
}

impl From<XlResult<Value>> for Value {
    fn from(r: XlResult<Value>) -> Value {
        r.unwrap_or_else(Value::Error)
    }
}

/// Displays a value as a cell shows it: numbers to 15 significant digits.
impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Blank => Ok(()),
            Value::Number(n) => f.write_str(&super::format::number_format::general(*n)),
            Value::Bool(b) => f.write_str(if *b { "TRUE" } else { "FALSE" }),
            Value::Text(s) => f.write_str(s),
            Value::Error(e) => f.write_str(e.as_str()),
            Value::Array(a) => match a.data.first() {
                Some(v) => v.fmt(f),
                None => Ok(()),
            },
            Value::Lambda(_) => f.write_str(XlError::Calc.as_str()),
            // As VBA's Print shows it.
            Value::Null => f.write_str("Null"),
        }
    }
}
