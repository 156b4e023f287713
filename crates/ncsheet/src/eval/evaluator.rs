//! The one evaluator: a syntax tree plus the cells it reads (through [`Env`]) to a value.
//! Cells, macros and surface equations all evaluate through here.

use std::rc::Rc;

use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::*;

use super::coerce::{compare, to_number, to_text};
use super::dates::DateSystem;
use super::functions::{self, FnKind};
use super::value::{
    held_items, too_many_items, too_many_items_note, too_many_live_items_note, Array, Value, XlError, XlResult,
    MAX_LIVE_ITEMS,
};

/// What the evaluator reads: cell values, defined names and sheet facts. The workbook
/// implements it; tests and macro code may implement it over anything.
pub trait Env {
    /// The value of one cell (blank when empty or off the sheet).
    fn value(&self, sheet: SheetId, pos: Pos) -> Value;

    /// The cell's number, `None` when it holds anything else: arithmetic reads its operands
    /// through this, in registers, before falling back to [`Env::value`].
    fn number(&self, sheet: SheetId, pos: Pos) -> Option<f64> {
        match self.value(sheet, pos) {
            Value::Number(n) => Some(n),
            _ => None,
        }
    }

    /// Calls `f` for every non-blank cell in `rect`, row by row (Excel's order: it decides
    /// which error a SUM reports and the rounding of long sums).
    fn for_each_value(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value));

    /// Calls `f` for every number among the cells of `rect`, in [`Env::for_each_value`]'s
    /// order, as SUM, MAX and AVERAGE read a range: text, booleans and blanks are skipped,
    /// and the first error ends the visit as the result. An environment may read its cells
    /// more directly than through [`Env::for_each_value`] (the workbook does: ranges are most
    /// of what aggregates read).
    fn for_each_number_in(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(f64)) -> XlResult<()> {
        numbers_of_values(self, sheet, rect, f)
    }

    /// The rectangle from A1 to the last used row and column (`None` for an empty sheet).
    fn used_rect(&self, sheet: SheetId) -> Option<Rect>;

    /// The used rectangle as a read of `rect` must see it: also covering cells in `rect`
    /// that hold a value without being stored (a whole-row spill's tail).
    fn used_rect_for(&self, sheet: SheetId, _rect: Rect) -> Option<Rect> {
        self.used_rect(sheet)
    }

    /// A defined name visible from `sheet`: its formula and the sheet it is evaluated on.
    fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)>;

    /// The sheet and cells structured reference `r` names now, for a formula at `pos` of
    /// `sheet`: `#NAME?` when it names a table or column this environment lacks, `#REF!`
    /// when no cells of it (`[@Qty]` outside the table's data rows).
    fn table_part(&self, _r: &TableRef, _sheet: SheetId, _pos: Pos) -> Result<(SheetId, Rect), XlError> {
        Err(XlError::Name)
    }

    /// What the pivot table holding cell `at` of `sheet` shows for `data_field` at the
    /// (field, item) `pairs` (GETPIVOTDATA); `Err` says why it shows nothing.
    fn pivot_data(
        &self,
        _sheet: SheetId,
        _at: Pos,
        _data_field: &str,
        _pairs: &[(String, Value)],
    ) -> Result<Value, String> {
        Err("the workbook has no pivot table".into())
    }

    /// The cells a dynamic array anchored at `pos` spilled into, for `A1#`.
    fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect>;

    /// How many sheets the workbook has (SHEETS). A workbook whose sheets were deleted keeps
    /// their ids unused, so ids may run past it: find a sheet by name with `sheet_id`.
    fn sheet_count(&self) -> usize;

    /// The name of sheet `sheet`; `None` for an id that names no sheet (a deleted one).
    fn sheet_name(&self, sheet: SheetId) -> Option<String>;

    /// Where `sheet` shows among the workbook's tabs, from 0 (SHEET): a sheet's id is fixed,
    /// its tab can be moved. The default: tabs in id order.
    fn tab_position(&self, sheet: SheetId) -> usize {
        sheet as usize
    }

    /// The sheets a 3-D reference from `first` to `last` takes (`Sheet1:Sheet3!A1`): those
    /// whose tabs lie between the two, ends included, in tab order; none when either end is
    /// no sheet. The default asks [`Env::tab_position`] of every sheet, so that an environment
    /// whose tabs are not in id order spans them as it shows them (a workbook answers from
    /// its own list of tabs).
    fn sheets_spanned(&self, first: SheetId, last: SheetId) -> Vec<SheetId> {
        if self.sheet_name(first).is_none() || self.sheet_name(last).is_none() {
            return Vec::new();
        }
        let (from, to) = (self.tab_position(first), self.tab_position(last));
        let tabs = from.min(to)..=from.max(to);
        let ids = 0..self.sheet_count().max(first.max(last) as usize + 1) as SheetId;
        let mut spanned: Vec<SheetId> =
            ids.filter(|&s| self.sheet_name(s).is_some() && tabs.contains(&self.tab_position(s))).collect();
        spanned.sort_by_key(|&s| self.tab_position(s));
        spanned
    }

    /// The sheet of this name, ignoring ASCII case (INDIRECT's `Sheet2!A1`). The default
    /// reads every name; an environment of many sheets answers from an index.
    fn sheet_id(&self, name: &str) -> Option<SheetId> {
        (0..self.sheet_count()).find_map(|i| {
            let id = i as SheetId;
            self.sheet_name(id).filter(|n| n.eq_ignore_ascii_case(name)).map(|_| id)
        })
    }

    /// The formula of a cell as typed (`=A1+1`), `None` for a constant or an empty cell
    /// (FORMULATEXT, ISFORMULA).
    fn formula_text(&self, _sheet: SheetId, _pos: Pos) -> Option<String> {
        None
    }

    /// Whether the cell's formula calls SUBTOTAL or AGGREGATE, which skip such cells.
    fn is_subtotal(&self, _sheet: SheetId, _pos: Pos) -> bool {
        false
    }

    /// The day the workbook's date serials count from (see `dates.rs`).
    fn date_system(&self) -> DateSystem {
        DateSystem::From1900
    }

    /// The serial NOW reads: the workbook's fixed clock, or the system's (its `Settings`).
    fn now(&self) -> f64;

    /// The next number 0 ≤ x < 1 of the workbook's random sequence (its `Settings`).
    fn next_random(&self) -> f64;

    /// VBA's `Rnd(n)` from the workbook's own VBA generator (`Settings::vba_rnd`); an
    /// environment without a workbook draws from its random sequence.
    fn vba_rnd(&self, _n: f64) -> f64 {
        self.next_random()
    }

    /// The user's locale, which text-to-number conversions follow (the workbook's `Settings`).
    fn locale(&self) -> crate::eval::Locale {
        crate::eval::Locale::EN_US
    }

    /// The work the LAMBDAs of MAP, REDUCE, … may do in one formula (the workbook's
    /// `Settings::lambda_work`): [`MAX_LAMBDA_WORK`] unless a test asks for less.
    fn lambda_work_limit(&self) -> u64 {
        MAX_LAMBDA_WORK
    }

    /// Told of the work formulas do besides making their values ([`WorkDone`]), inside
    /// LAMBDAs or not: a workbook adds it up, and an iterating cycle is charged what its
    /// rounds did (`workbook/cycles.rs`).
    fn work_done(&self, _done: WorkDone) {}

    /// The array items one formula may hold at once (the workbook's `Settings::live_items`):
    /// [`MAX_LIVE_ITEMS`] unless a test asks for less.
    fn live_items_limit(&self) -> usize {
        MAX_LIVE_ITEMS
    }

    /// The language of the Excel that saved the workbook, when the file says and it is not
    /// English (a .xls's COUNTRY record): Excel reads CELL's info_type in it as well as in
    /// English (MS-OI29500 2.1.896). A language tag such as `fr`.
    fn excel_language(&self) -> Option<&'static str> {
        None
    }

    /// The width of column `col` in characters as Excel shows it (CELL("width")); `None`
    /// when the workbook says nothing of it (Excel's default, 8.43).
    fn column_width(&self, _sheet: SheetId, _col: u32) -> Option<f64> {
        None
    }

    /// Whether row `row` of `sheet` is hidden, and how (SUBTOTAL and AGGREGATE skip such rows).
    fn row_hidden(&self, _sheet: SheetId, _row: u32) -> Option<RowHidden> {
        None
    }

    /// Calls the workbook's own function (a VBA Function of its macros); the function reads
    /// cells through `cells`, the environment the formula is evaluated in. `None` when the
    /// workbook has no such function: the call is then `#NAME?`.
    /// A call that failed is `Err` with the error value and why, which the cell's notes keep.
    fn call_user_function(&self, _cells: &dyn Env, _call: &UserCall) -> Option<Result<Value, Note>> {
        None
    }
}

/// How a row is hidden: SUBTOTAL 1–11 skips the rows a filter hides, 101–111 every hidden row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowHidden {
    /// Hidden by hand (or by a collapsed outline).
    Manually,
    /// Hidden by a filter (an autofilter or a table's).
    Filtered,
}

/// What an embedding language adds to the expressions it hands the evaluator: the macro
/// interpreter's variables (read where a formula reads a LET variable) and its own nodes
/// ([`ExprKind::Host`]: member paths, calls of the macro's procedures). Cells have no host.
pub trait Host {
    /// What the variable `name` holds (a range object as a reference), or `None` when the host
    /// has no such variable and the name is a defined name.
    fn variable(&self, name: &str) -> Option<Operand>;

    /// Evaluates the host's node `id`, reading its argument expressions through `ctx`.
    fn node(&self, ctx: &mut Ctx, id: u32) -> Operand;

    /// The longest text a macro string may be (`run --max-string`).
    fn text_limit(&self) -> usize {
        MAX_MACRO_TEXT
    }

    /// Told when a result passes [`Host::text_limit`], before it becomes `#VALUE!`: a macro
    /// stops there, with the limit named (VBA's "Out of string space").
    fn text_too_long(&self, _limit: usize) {}

    /// The most items an array a macro makes may hold (`run --max-array-items`), which
    /// [`Ctx::room_for`] checks besides the formulas' own limit.
    fn array_item_limit(&self) -> usize {
        super::MAX_ARRAY_ITEMS
    }

    /// Told when an array of `items` would pass [`Host::array_item_limit`], before it is
    /// built: a macro stops there, with the limit named.
    fn array_too_large(&self, _items: usize, _limit: usize) {}

    /// Told when one of VBA's library functions raises a VBA run-time error (`Chr(Null)`:
    /// 94, "Invalid use of Null"): a macro goes to its handler or stops there, with that
    /// number; the call's value is the error value it returns.
    fn raise(&self, _number: u32, _message: &str) {}

    /// The result of the binary operator `op` on the expressions `operands`, whose values
    /// were `values`: a macro checks it against its operands' declared types (VBA's Integer
    /// arithmetic overflows at 32,767); the result stays as computed by default.
    fn arithmetic(&self, _op: BinOp, _operands: (&Expr, &Expr), _values: (&Value, &Value), result: Value) -> Value {
        result
    }

    /// The text a macro's String conversion gives `value`, the value of `e`, when it is a Date
    /// (CStr, Format and Str of a Date show the date, [MS-VBAL] 5.5.1.2.4); `None` for any
    /// other value, converted as a number. Cells have no Date type: `None`.
    fn date_text(&self, _e: &Expr, _value: &Value) -> Option<String> {
        None
    }

    /// The number CStr, Str and Format show for `value`, the value of `e`, when a macro holds
    /// it as a Single: its seven significant digits ("Single data type"); `None` for any
    /// other value. Cells have no Single type: `None`.
    fn shown_number(&self, _e: &Expr, _value: &Value) -> Option<f64> {
        None
    }

    /// The items of `items`, the value of the array `e`, as a macro's library takes them
    /// where it wants Strings (Join, Filter): each item whose type writes it otherwise than a
    /// Double (a Single, a Date, a Currency, a LongLong, [MS-VBAL] 5.5.1.2.4) made that text;
    /// `None` where no item is such, and for a cell.
    fn item_texts(&self, _e: &Expr, _items: &Rc<Array>) -> Option<Rc<Array>> {
        None
    }

    /// The decimal text of `value`, the value of `e`, when a macro holds it as a LongLong past
    /// what a double shows exactly (`9007199254740993^`: CStr, Str and Format show every digit,
    /// "LongLong data type") or as a Decimal (its every digit, "Decimal data type"); `None` for
    /// any other value. Cells have neither type: `None`.
    fn long_long_text(&self, _e: &Expr, _value: &Value) -> Option<String> {
        None
    }

    /// `Int` (`floor`) or `Fix` of `value`, the value of `e`, when it is a macro's Decimal
    /// whose digits no double gives back (`Int(CDec(x) * 10 ^ 20 + 0.5)`): the nearest double
    /// to its exact whole part. Cells have no Decimals: `None`.
    fn decimal_whole(&self, _e: &Expr, _value: &Value, _floor: bool) -> Option<f64> {
        None
    }

    /// Which of VBA's IIf's branches (`index` into the call's `args`) gave its `value`: a
    /// macro's LongLong past 2^53 is that branch's integer. Nothing for a cell.
    fn chose(&self, _args: &[Expr], _index: usize, _value: &Value) {}

    /// The result of `-operand`: a macro checks it against the operand's declared type
    /// (VBA's `-x` of the Integer -32,768 overflows); the result stays as computed by default.
    fn negation(&self, _operand: &Expr, result: Value) -> Value {
        result
    }

    /// The bits of the whole-number type a macro holds `value`, the value of `e`, with: 16 for
    /// a Byte, Boolean or Integer, 32 for a Long (Hex and Oct write a negative one's two's
    /// complement in as many bits); `None` for any other value, and for a cell.
    fn integer_bits(&self, _e: &Expr, _value: &Value) -> Option<u32> {
        None
    }

    /// The result of `Not operand`: a macro gives it the operand's type ([MS-VBAL] 5.6.9.8.1:
    /// `Not` of a Byte is a Byte, so `Not CByte(5)` is 250, not -6); as computed by default.
    fn logical_not(&self, _operand: &Expr, result: Value) -> Value {
        result
    }

    /// Whether evaluating the host's node `id` may run macro code (a call, a property, anything
    /// that could change a variable); `false` only for reads that change nothing, such as
    /// `Len(t)` of a variable.
    fn may_run_code(&self, _id: u32) -> bool {
        true
    }

    /// The length in characters of the text variable `name` holds while it grows in place
    /// (`s = s & …`), known without making its value; `None` for anything else.
    fn text_length(&self, _name: &str) -> Option<usize> {
        None
    }

    /// The text variable `name` holds while it grows in place, shared rather than copied
    /// (`Right(s, 1)` between appends read a copy of the whole text each time); `None` for
    /// anything else.
    fn growing_text(&self, _name: &str) -> Option<Rc<String>> {
        None
    }

    /// The macro's module says `Option Compare Text`: InStr, InStrRev, StrComp and Split
    /// without a compare argument ignore case ([MS-VBAL] 5.2.1.4). Cells: Binary.
    fn option_compare_text(&self) -> bool {
        false
    }

    /// Told of the work an expression's functions and operators did on texts and arrays, in
    /// [`Ctx::charge`]'s units (an item made or read, 16 bytes of text): a macro counts it
    /// against its statement limit, so that a loop of few statements, each doing much text
    /// work (`Replace` over 16 million characters), stops within the limit's time too.
    fn work(&self, _units: u64) {}
}

/// The result of evaluating an expression that may be a reference.
#[derive(Clone, Debug, PartialEq)]
pub enum Operand {
    Value(Value),
    Ref(SheetId, Rect),
    /// A reference of several areas (`(A1:A3,C1)`, a name defined as a union), in the order
    /// written. Functions that take references (SUM, COUNT, INDEX, AREAS…) read each area;
    /// anywhere a value is wanted it is `#VALUE!`, as in Excel.
    Areas(Rc<[(SheetId, Rect)]>),
}

/// A diagnostic a function leaves for the cell it evaluates (e.g. why a geometry is invalid).
#[derive(Clone, Debug, PartialEq)]
pub struct Note {
    pub error: XlError,
    pub message: String,
}

/// A LET name or a LAMBDA parameter bound to its value.
#[derive(Clone, Debug)]
struct Local {
    name: Rc<str>,
    value: Value,
    /// A parameter whose argument the call left out (`f(1,)`): ISOMITTED is TRUE for it.
    omitted: bool,
}

/// The list of names a loop's LAMBDA calls run in, made once and emptied after each call
/// ([`Ctx::apply_closure`]): MAP, MAKEARRAY, REDUCE… keep one for all their calls.
#[derive(Default)]
pub struct CallFrame(Vec<Local>);

/// A LAMBDA made into a value (`Value::Lambda`): the `LAMBDA(…)` call and what its body
/// sees where it was written, the LET names and parameters around it and the cell it is
/// evaluated for, so that `LET(f, LAMBDA(x, LAMBDA(y, x+y)), f(3)(4))` is 7 wherever the inner
/// LAMBDA is finally called (Excel's names are lexical).
#[derive(Debug)]
pub struct Closure {
    lambda: Expr,
    locals: Vec<Local>,
    sheet: SheetId,
    at: Pos,
    in_name: bool,
    /// The LET name it was bound to, which its body may call: a LET-bound LAMBDA can recurse.
    own_name: Option<Rc<str>>,
}

/// Two LAMBDA values are equal when they are the same one.
impl PartialEq for Closure {
    fn eq(&self, other: &Closure) -> bool {
        std::ptr::eq(self, other)
    }
}

impl Closure {
    /// The `LAMBDA(…)` call it holds.
    pub fn expr(&self) -> &Expr {
        &self.lambda
    }

    /// Its parameters and body.
    pub fn lambda(&self) -> functions::Lambda<'_> {
        functions::as_lambda(&self.lambda).expect("a closure holds a LAMBDA")
    }

    /// The values of the names it captured, which it keeps alive.
    pub fn captured(&self) -> impl Iterator<Item = &Value> {
        self.locals.iter().map(|l| &l.value)
    }
}

/// Lets the LAMBDA that LET binds to `name` call itself by that name (a LAMBDA made for the
/// binding; one that another name already holds is left as it is).
pub fn bind_own_name(value: &mut Value, name: &Rc<str>) {
    if let Value::Lambda(closure) = value {
        if let Some(c) = Rc::get_mut(closure) {
            c.own_name.get_or_insert_with(|| name.clone());
        }
    }
}

/// A called LAMBDA's parameters bound to the values of `args`, evaluated by the caller; the
/// optional parameters after the last argument are omitted, as an empty argument is.
fn parameters(lambda: &functions::Lambda, args: &[Expr], values: Vec<Value>) -> Vec<Local> {
    let mut values = values.into_iter();
    let mut args = args.iter();
    let bind = |name: &Rc<str>| match (args.next(), values.next()) {
        (Some(arg), Some(value)) => Local { name: name.clone(), value, omitted: arg.kind == ExprKind::Missing },
        _ => Local { name: name.clone(), value: Value::Blank, omitted: true },
    };
    lambda.param_names().map(bind).collect()
}

/// A cell's call of a function of the workbook's own (`=myFunc(A1:B2, 3)`).
pub struct UserCall<'a> {
    /// As the formula spells it (`Module1.F` too).
    pub name: &'a str,
    /// Evaluated by the caller: a reference stays a reference.
    pub args: &'a [Operand],
    /// The calling cell (`Application.Caller`).
    pub caller: (SheetId, Pos),
}

/// The evaluation of one formula: where it is, what it reads, its local names.
pub struct Ctx<'a> {
    pub env: &'a dyn Env,
    pub sheet: SheetId,
    pub at: Pos,
    locals: Vec<Local>,
    /// Evaluating a defined name's formula: its relative references wrap at the sheet's
    /// edges, as Excel's do (`prev` = `A1048576` defined from A1 is the row above, and in
    /// row 1 the last row).
    in_name: bool,
    host: Option<&'a dyn Host>,
    depth: u32,
    /// Calls of named LAMBDAs (LET-bound or defined names) so far, against [`MAX_LAMBDA_CALLS`].
    lambda_calls: u32,
    /// Work done inside the LAMBDAs that MAP, REDUCE, SCAN, BYROW, BYCOL and MAKEARRAY call,
    /// against [`MAX_LAMBDA_WORK`]: a `Cell`, as a range is read through `&self`.
    lambda_work: std::cell::Cell<u64>,
    /// How many of those LAMBDA bodies are running: work outside them is not counted.
    iterating: u32,
    /// The workbook's date system, read once from `env`: every date conversion takes it.
    dates: DateSystem,
    /// The workbook's locale, read once per cell: every arithmetic operator asks for it.
    locale: crate::eval::Locale,
    /// Evaluating a BALLPATH's surface: a surface that computed a BALLPATH itself (through a
    /// named LAMBDA) would recurse without end.
    pub in_surface: bool,
    /// Messages explaining error values, for the CLI to show.
    pub notes: Vec<Note>,
    /// Numbers to read in place of number literals of the tree being evaluated, each with
    /// the literal's node (by address): formulas that differ only in their numbers share one
    /// tree (crates/ncsheet/src/workbook/shared.rs). Usually empty. Code that reads numbers from the tree
    /// itself, not through `eval`, must be marked `FnSpec::reads_trees`.
    pub numbers: &'a [(*const Expr, f64)],
    /// References made at run time (INDIRECT, OFFSET) that the formula's text does not name:
    /// the workbook links the cell to them after evaluation.
    pub dynamic_refs: Vec<(SheetId, Rect)>,
    /// The array items this evaluation holds now, against [`MAX_LIVE_ITEMS`]: every array
    /// made or read is added; a call, an operator or a LAMBDA's body, once it returns, holds
    /// only its result ([`Ctx::held_result`]).
    held: usize,
}

/// [`Env::for_each_number_in`] through [`Env::for_each_value`], for any environment.
pub(crate) fn numbers_of_values<E: Env + ?Sized>(
    env: &E,
    sheet: SheetId,
    rect: Rect,
    f: &mut dyn FnMut(f64),
) -> XlResult<()> {
    let mut outcome = Ok(());
    env.for_each_value(sheet, rect, &mut |_, v| match v {
        Value::Number(n) if outcome.is_ok() => f(*n),
        Value::Error(e) if outcome.is_ok() => outcome = Err(*e),
        _ => {}
    });
    outcome
}

/// Excel's longest text, in UTF-16 units: any longer text result of a cell formula is
/// `#VALUE!`, whichever function or operator made it.
pub const MAX_TEXT: usize = 32_767;

/// ncsheet's longest macro string (VBA's own limit is 2^31 characters, more than the memory
/// ncsheet allows itself); docs/limits.md.
pub const MAX_MACRO_TEXT: usize = 1 << 24;

/// Whether a value is, or holds, a text longer than `limit` UTF-16 units.
fn holds_text_over(v: &Value, limit: usize) -> bool {
    // A UTF-8 text has at least as many bytes as UTF-16 units: most texts are decided by
    // their length alone.
    let over = |s: &str| s.len() > limit && s.encode_utf16().count() > limit;
    match v {
        Value::Text(s) => over(s),
        Value::Array(a) => a.data.iter().any(|x| matches!(x, Value::Text(s) if over(s))),
        _ => false,
    }
}

/// Nested name definitions or LET bodies deeper than this are a cycle.
const MAX_DEPTH: u32 = 200;

/// ncsheet's limit on the calls of named LAMBDAs (recursion) while one formula evaluates
/// (docs/limits.md): about a second of work. Excel sets none, but a doubly recursive
/// Fibonacci of 45 would run for hours.
pub const MAX_LAMBDA_CALLS: u32 = 2_000_000;

/// ncsheet's limit on the work of the LAMBDAs MAP, REDUCE, SCAN, BYROW, BYCOL and MAKEARRAY
/// call while one formula evaluates (docs/limits.md): one per call, plus every item of an
/// array made or read, cell read, 16 bytes of text made or read, and step of a regression or
/// matrix product inside them (a function that makes no array counts its work where it
/// loops). A few seconds of work: a
/// REDUCE growing its array with VSTACK copies it whole at every step, and each LAMBDA of a
/// 4,096 × 4,096 MAKEARRAY may build arrays of its own. A MAKEARRAY of 2^24 simple items
/// (2^24 calls) stays well within it, as does a MAP of 10,000 items each looking a value up
/// in 10,000 rows.
pub const MAX_LAMBDA_WORK: u64 = 1 << 28;

/// The note of `#NUM!` when the LAMBDAs of one formula pass their work budget `limit`.
fn lambda_work_note(limit: u64) -> String {
    format!(
        "the LAMBDAs of MAP, REDUCE, SCAN, BYROW, BYCOL or MAKEARRAY did more than {limit} items of \
         work in one formula (ncsheet's limit: each call, and every array item made or read, cell read, 16 \
         bytes of text made or read and step of a regression or matrix product inside them; an array \
         grown item by item is copied at every step)"
    )
}

/// Work formulas did besides making their values, for a caller that budgets many
/// evaluations (an iterating cycle evaluates its cells up to 32,767 times): the units
/// [`Ctx::charge`] counted, inside LAMBDAs or not (array items made or read, cells read,
/// 16 bytes of text), and the LAMBDA calls run (MAP's, REDUCE's…, and named ones).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorkDone {
    pub items: u64,
    pub calls: u64,
}

/// The work [`Ctx::charge`] counts for a value made: its array's stored items, or its
/// text's bytes by 16 (about the cost of copying one item).
fn work_of(v: &Value) -> usize {
    match v {
        Value::Array(a) => a.data.len(),
        Value::Text(s) => s.len() / 16,
        _ => 0,
    }
}

impl<'a> Ctx<'a> {
    pub fn new(env: &'a dyn Env, sheet: SheetId, at: Pos) -> Ctx<'a> {
        Ctx::for_cell(env, sheet, at)
    }

    /// The evaluation of one cell (what a recalculation makes for each): [`Ctx::new`].
    pub fn for_cell(env: &'a dyn Env, sheet: SheetId, at: Pos) -> Ctx<'a> {
        Ctx::for_cell_of(env, (env.date_system(), env.locale()), sheet, at)
    }

    /// [`Ctx::for_cell`] with the date system and locale already known: a recalculation
    /// reads them once, not through `Env` per cell (calls the chain's 27 ns per cell feel).
    pub fn for_cell_of(
        env: &'a dyn Env,
        (dates, locale): (DateSystem, crate::eval::Locale),
        sheet: SheetId,
        at: Pos,
    ) -> Ctx<'a> {
        Ctx {
            env,
            sheet,
            at,
            locals: Vec::new(),
            in_name: false,
            host: None,
            depth: 0,
            lambda_calls: 0,
            lambda_work: std::cell::Cell::new(0),
            iterating: 0,
            dates,
            locale,
            in_surface: false,
            notes: Vec::new(),
            numbers: &[],
            dynamic_refs: Vec::new(),
            held: 0,
        }
    }

    /// What the evaluation found besides its value: notes explaining errors, and references
    /// made at run time. Ending a cell's evaluation through this rather than dropping the
    /// `Ctx` keeps the per-cell cost flat: the LET and LAMBDA names are all gone by now, and
    /// an empty list that never allocated needs no drop call (a recalculation ends a million
    /// of these).
    #[inline]
    pub fn into_findings(self) -> (Vec<Note>, Vec<(SheetId, Rect)>) {
        let Ctx { locals, notes, dynamic_refs, .. } = self;
        if locals.capacity() == 0 {
            std::mem::forget(locals);
        } else {
            drop(locals);
        }
        (notes, dynamic_refs)
    }

    /// The same evaluation with a macro interpreter's variables and nodes.
    pub fn with_host(mut self, host: &'a dyn Host) -> Ctx<'a> {
        self.host = Some(host);
        self
    }

    /// The longest text a result may be: Excel's in cells, ncsheet's own in macros.
    pub fn text_limit(&self) -> usize {
        match self.host {
            Some(host) => host.text_limit(),
            None => MAX_TEXT,
        }
    }

    /// `#VALUE!` for a text longer than [`Ctx::text_limit`], with a note naming the limit;
    /// a macro's host is told (and stops the macro).
    pub fn text_over_limit(&mut self) -> XlError {
        let limit = self.text_limit();
        if let Some(host) = self.host {
            host.text_too_long(limit);
        }
        let what = if self.host.is_some() { "a macro string (ncsheet's limit)" } else { "a text (Excel's limit)" };
        self.explain(XlError::Value, format!("longer than the {limit} characters of {what}"))
    }

    /// `v`, or `#VALUE!` (with a note) when it holds a text longer than [`Ctx::text_limit`].
    #[inline]
    fn within_text_limit(&mut self, v: Value) -> Value {
        // Numbers, the usual results, pass without a call.
        if matches!(v, Value::Text(_) | Value::Array(_)) && holds_text_over(&v, self.text_limit()) {
            return Value::Error(self.text_over_limit());
        }
        v
    }

    /// The date text of `value`, the value of `e`, when a macro holds it as a Date
    /// ([`Host::date_text`]).
    pub fn macro_date_text(&self, e: &Expr, value: &Value) -> Option<String> {
        self.host?.date_text(e, value)
    }

    /// Tells a macro which branch of IIf gave its value ([`Host::chose`]).
    pub fn macro_chose(&self, args: &[Expr], index: usize, value: &Value) {
        if let Some(host) = self.host {
            host.chose(args, index, value);
        }
    }

    /// A macro's LongLong's decimal text ([`Host::long_long_text`]).
    pub fn macro_long_long_text(&self, e: &Expr, value: &Value) -> Option<String> {
        self.host?.long_long_text(e, value)
    }

    /// The items of a macro's array as its library's String parameters take them
    /// ([`Host::item_texts`]).
    pub fn macro_item_texts(&self, e: &Expr, items: &std::rc::Rc<Array>) -> Option<Rc<Array>> {
        self.host?.item_texts(e, items)
    }

    /// The whole part of a macro's Decimal no double holds ([`Host::decimal_whole`]).
    pub fn macro_decimal_whole(&self, e: &Expr, value: &Value, floor: bool) -> Option<f64> {
        self.host?.decimal_whole(e, value, floor)
    }

    /// `result`, the negation of `operand`'s value, as a macro checks it against the
    /// operand's type ([`Host::negation`]: the Integer -32,768 negated overflows).
    pub fn macro_negation(&self, operand: &Expr, result: Value) -> Value {
        match self.host {
            Some(host) => host.negation(operand, result),
            None => result,
        }
    }

    /// The number a macro shows for `value`, the value of `e` ([`Host::shown_number`]).
    pub fn macro_integer_bits(&self, e: &Expr, value: &Value) -> Option<u32> {
        self.host?.integer_bits(e, value)
    }

    pub fn macro_shown_number(&self, e: &Expr, value: &Value) -> Option<f64> {
        self.host?.shown_number(e, value)
    }

    /// `error` with a note, and VBA's run-time error `number` raised in a macro ([`Host::raise`]):
    /// how a VBA library function fails as VBA's does, while a cell gets the error value.
    pub fn raise_vba(&mut self, error: XlError, number: u32, message: String) -> XlError {
        if let Some(host) = self.host {
            host.raise(number, &message);
        }
        self.explain(error, message)
    }

    /// Records a reference made at run time, for the dependency graph.
    pub fn note_dynamic_ref(&mut self, sheet: SheetId, rect: Rect) {
        if !self.dynamic_refs.contains(&(sheet, rect)) {
            self.dynamic_refs.push((sheet, rect));
        }
    }

    /// The operand of a function that reads where a reference is, not what it holds (ROW,
    /// COLUMN, ROWS, COLUMNS, ISREF): references made at run time inside it are not
    /// dependencies, so `ROW(INDIRECT("A1"))` in A1 is no cycle, as in Excel.
    pub fn reference_only(&mut self, e: &Expr) -> Operand {
        let made_before = self.dynamic_refs.len();
        let operand = self.operand(e);
        self.dynamic_refs.truncate(made_before);
        operand
    }

    /// The workbook's date system, which every conversion between serials and dates (and
    /// date text) takes.
    pub fn dates(&self) -> DateSystem {
        self.dates
    }

    /// The workbook's locale (en-US outside a workbook).
    pub fn locale(&self) -> crate::eval::Locale {
        self.locale
    }

    /// Operands of `op` as the workbook's locale reads them: text in arithmetic read as a
    /// number there (`"0,8"*1` in et-EE), numbers joined as text shown there (`0,8&""`).
    /// Under en-US, and for other operators, they are unchanged.
    #[inline]
    fn localized_operands(&self, op: BinOp, a: Value, b: Value) -> (Value, Value) {
        if self.locale.is_canonical() {
            return (a, b);
        }
        self.operands_in_locale(op, a, b)
    }

    /// [`Ctx::localized_operands`] outside en-US, kept out of line: the hot path of every
    /// operator under en-US is the one comparison above.
    #[inline(never)]
    fn operands_in_locale(&self, op: BinOp, a: Value, b: Value) -> (Value, Value) {
        let locale = self.locale;
        match op {
            BinOp::Pow | BinOp::Mul | BinOp::Div | BinOp::Add | BinOp::Sub => {
                (locale.numbers_for_arithmetic(a, self.dates), locale.numbers_for_arithmetic(b, self.dates))
            }
            BinOp::Concat => (locale.numbers_for_joining(a), locale.numbers_for_joining(b)),
            _ => (a, b),
        }
    }

    /// `Ok` when an array of `rows` × `cols` items is within [`super::MAX_ARRAY_ITEMS`], else
    /// `#NUM!` with the note naming both: every function that sizes an array from its
    /// arguments (WRAPCOLS' count, VSTACK's widest part, MAKEARRAY) asks before allocating.
    pub fn room_for(&mut self, rows: usize, cols: usize) -> XlResult<()> {
        if let Some(host) = self.host {
            let (items, limit) = (rows.saturating_mul(cols), self.array_item_limit());
            if items > limit {
                host.array_too_large(items, limit);
                return Err(self.explain_once(XlError::Num, format!("an array of {items} items, more than {limit}")));
            }
        }
        if too_many_items(rows, cols) {
            return Err(self.explain_once(XlError::Num, too_many_items_note(rows, cols)));
        }
        self.room_to_hold(rows * cols)
    }

    /// `Ok` when `items` more array items fit in what this evaluation may hold at once
    /// ([`MAX_LIVE_ITEMS`]), else `#NUM!` with the limit's note.
    fn room_to_hold(&mut self, items: usize) -> XlResult<()> {
        let limit = self.env.live_items_limit();
        if self.held.saturating_add(items) > limit {
            return Err(self.explain_once(XlError::Num, too_many_live_items_note(limit)));
        }
        Ok(())
    }

    /// The array items held so far (see [`MAX_LIVE_ITEMS`]), for [`Ctx::release_to`].
    pub fn held_mark(&self) -> usize {
        self.held
    }

    /// Ends a stretch of evaluation begun when `mark` items were held: what it made is gone
    /// but `kept`. For a function that drops what it made before returning: REDUCE its last
    /// accumulator, SUM each argument once summed.
    pub fn release_to(&mut self, mark: usize, kept: &Value) {
        self.held = mark.saturating_add(held_items(kept));
    }

    /// `v`, the result of a call, operator or LAMBDA body begun when `mark` items were held:
    /// what it made besides `v` is gone, `v` is held. `#NUM!` with the limit's note when `v`
    /// does not fit ([`MAX_LIVE_ITEMS`]).
    #[inline]
    fn held_result(&mut self, mark: usize, v: Value) -> Value {
        self.held = mark;
        match v {
            Value::Array(_) | Value::Lambda(_) => self.hold(v),
            v => v,
        }
    }

    /// [`Ctx::held_result`] of an array or a LAMBDA, out of line.
    #[inline(never)]
    fn hold(&mut self, v: Value) -> Value {
        let items = held_items(&v);
        match self.room_to_hold(items) {
            Ok(()) => {
                self.held += items;
                v
            }
            Err(e) => Value::Error(e),
        }
    }

    /// [`Ctx::held_result`] of an operand: a reference holds nothing yet.
    fn held_operand(&mut self, mark: usize, operand: Operand) -> Operand {
        match operand {
            Operand::Value(v) => Operand::Value(self.held_result(mark, v)),
            operand => {
                self.held = mark;
                operand
            }
        }
    }

    /// The most items an array may hold here: a macro's `--max-array-items`, else
    /// [`super::MAX_ARRAY_ITEMS`] (both are checked by [`Ctx::room_for`]).
    pub fn array_item_limit(&self) -> usize {
        self.host.map_or(super::MAX_ARRAY_ITEMS, |host| host.array_item_limit().min(super::MAX_ARRAY_ITEMS))
    }

    /// Records why `error` happened and returns it, for `return Err(ctx.explain(..))`.
    pub fn explain(&mut self, error: XlError, message: impl Into<String>) -> XlError {
        self.notes.push(Note { error, message: message.into() });
        error
    }

    /// A cell formula's result. Excel zeroes the result of a formula whose last operation
    /// is an addition or subtraction that cancels to within the operands' last binary
    /// digits (`=0.1+0.2-0.3` and `=A1-B1` are 0); within parentheses or under another
    /// operation it does not (`=(0.5-0.4-0.1)` and `=1*(0.5-0.4-0.1)` are -2.78E-17).
    pub fn eval_formula(&mut self, e: &Expr) -> Value {
        let ExprKind::Binary(op @ (BinOp::Add | BinOp::Sub), a, b) = &e.kind else { return no_lambda(self.eval(e)) };
        // Operands that are numbers or cells are read without building values, as `eval` does.
        let (x, y) = (self.leaf_number(a), self.leaf_number(b));
        if let (Some(x), Some(y)) = (x, y) {
            // `A1+1`, most of what a long chain of formulas evaluates, kept in registers.
            return sum_or_difference(*op, x, y);
        }
        let x = x.map_or_else(|| self.eval(a), Value::Number);
        let y = y.map_or_else(|| self.eval(b), Value::Number);
        match (&x, &y) {
            (Value::Number(x), Value::Number(y)) => sum_or_difference(*op, *x, *y),
            _ => {
                let (x, y) = self.localized_operands(*op, x, y);
                binary(*op, &x, &y, self.dates)
            }
        }
    }

    /// Evaluates to a value: a multi-cell reference becomes an array, a single cell its value.
    pub fn eval(&mut self, e: &Expr) -> Value {
        match &e.kind {
            ExprKind::Number(n) => Value::Number(self.literal(e, *n)),
            ExprKind::Text(s) => Value::Text(s.clone()),
            ExprKind::Bool(b) => Value::Bool(*b),
            ExprKind::Error(err) => Value::Error(*err),
            ExprKind::Missing => Value::Blank,
            // One cell of this sheet, the commonest reference, read without building a range.
            ExprKind::Ref(Reference { sheet: SheetRef::Current, shape: RefShape::Cell(c) }) => {
                match self.cell_here(c) {
                    Some(pos) => self.env.value(self.sheet, pos),
                    None => Value::Error(XlError::Ref),
                }
            }
            ExprKind::Ref(Reference { sheet: SheetRef::Span(..), .. }) => {
                let operand = self.operand(e);
                self.deref(operand)
            }
            ExprKind::Ref(r) => match self.resolve(r) {
                Ok((sheet, rect)) => self.held_range(sheet, rect),
                Err(err) => Value::Error(err),
            },
            ExprKind::Paren(inner) => self.eval(inner),
            ExprKind::Array(lit) => self.array_literal(lit),
            ExprKind::Unary(op, inner) => self.held_unary(*op, inner),
            ExprKind::Binary(BinOp::Range | BinOp::Intersect | BinOp::Union, ..)
            | ExprKind::Name(_)
            | ExprKind::SheetName(..)
            | ExprKind::Table(_)
            | ExprKind::Host(_) => {
                let operand = self.operand(e);
                self.deref(operand)
            }
            ExprKind::Binary(op, left, right) => match (self.leaf_number(left), self.leaf_number(right)) {
                // `&` joins numbers as the locale shows them: the general path below.
                (Some(x), Some(y)) if *op != BinOp::Concat => {
                    let v = scalar_binary_numbers(*op, x, y);
                    match self.host {
                        Some(host) => host.arithmetic(*op, (left, right), (&Value::Number(x), &Value::Number(y)), v),
                        None => v,
                    }
                }
                (x, y) => self.binary_of_operands(*op, (left, right), (x, y)),
            },
            ExprKind::Call(id, args) => self.call(*id, args),
            ExprKind::UnknownCall(name, args) => self.held_call_of_name(name, args),
            ExprKind::Invoke(callee, args) => self.held_invoke(callee, args),
            // A parameter list's, never evaluated (LAMBDA alone is #CALC!).
            ExprKind::OptionalParam(_) => Value::Error(XlError::Value),
        }
    }

    /// `op` on its operands `left` and `right`, those that are numbers in registers already
    /// given (`x`, `y`); the operands are held ([`MAX_LIVE_ITEMS`]) until the result is made.
    /// Out of [`Ctx::eval`], whose frame every macro expression's nesting pays for.
    #[inline(never)]
    fn binary_of_operands(
        &mut self,
        op: BinOp,
        (left, right): (&Expr, &Expr),
        (x, y): (Option<f64>, Option<f64>),
    ) -> Value {
        let mark = self.held;
        let a = x.map_or_else(|| self.eval(left), Value::Number);
        let b = y.map_or_else(|| self.eval(right), Value::Number);
        match (&a, &b, self.host) {
            // Numbers from names, parentheses and calls (a surface's `(x/50)^2`):
            // no locale to read them in, no array or text to count or limit.
            (Value::Number(x), Value::Number(y), None) if op != BinOp::Concat => scalar_binary_numbers(op, *x, *y),
            _ => {
                let v = self.binary_of_values(op, (left, right), a, b);
                self.held_result(mark, v)
            }
        }
    }

    /// A prefix or postfix operator's value, holding only its result ([`Ctx::held_result`]).
    #[inline(never)]
    fn held_unary(&mut self, op: UnaryOp, inner: &Expr) -> Value {
        let mark = self.held;
        let v = self.unary(op, inner);
        self.held_result(mark, v)
    }

    /// [`Ctx::call_defined_lambda`], holding only its result ([`Ctx::held_result`]).
    #[inline(never)]
    fn held_call_of_name(&mut self, name: &str, args: &[Expr]) -> Value {
        let mark = self.held;
        let v = self.call_defined_lambda(name, args);
        self.held_result(mark, v)
    }

    /// [`Ctx::invoke`], holding only its result ([`Ctx::held_result`]).
    #[inline(never)]
    fn held_invoke(&mut self, callee: &Expr, args: &[Expr]) -> Value {
        let mark = self.held;
        let v = self.invoke(callee, args);
        self.held_result(mark, v)
    }

    /// `op` on evaluated operands, in the workbook's locale, with a macro's typing and the
    /// limits on arrays and text; kept out of [`Ctx::eval`], whose usual operands are numbers.
    #[inline(never)]
    fn binary_of_values(&mut self, op: BinOp, (left, right): (&Expr, &Expr), a: Value, b: Value) -> Value {
        let (a, b) = self.localized_operands(op, a, b);
        let v = binary(op, &a, &b, self.dates);
        self.charge(work_of(&v));
        if op != BinOp::Concat && self.host.is_some() {
            // A comparison (or `Like`) of long texts reads them and answers a Boolean; `&`'s
            // work is the text it makes, counted above.
            let bytes = |v: &Value| if let Value::Text(t) = v { t.len() } else { 0 };
            self.charge_read(bytes(&a) + bytes(&b));
        }
        if matches!(v, Value::Error(XlError::Num)) {
            self.explain_array_size(&a, &b);
        }
        let v = match self.host {
            Some(host) => host.arithmetic(op, (left, right), (&a, &b), v),
            None => v,
        };
        if op == BinOp::Concat {
            self.within_text_limit(v)
        } else {
            v
        }
    }

    /// `a & b` of the values `a` and `b` of `operands`, as [`Ctx::eval`] joins them: a macro's
    /// `s = s & x` appends what `"" & x` makes to its text in place (`vba/append.rs`).
    pub fn join_values(&mut self, operands: (&Expr, &Expr), a: Value, b: Value) -> Value {
        self.binary_of_values(BinOp::Concat, operands, a, b)
    }

    /// A number literal's value: its own, or this formula's in place of a shared tree's.
    #[inline]
    fn literal(&self, e: &Expr, n: f64) -> f64 {
        let n = if self.numbers.is_empty() {
            n
        } else {
            let own = self.numbers.iter().find(|&&(node, _)| std::ptr::eq(node, e));
            own.map_or(n, |&(_, v)| v)
        };
        // Excel reads a typed number below the smallest normal double as 0 (`1E-320>0` and
        // `-1E-320<0` are both FALSE), as it keeps no subnormal result.
        if n.abs() < f64::MIN_POSITIVE {
            0.0
        } else {
            n
        }
    }

    /// Where a one-cell reference relative to this formula's cell points, if on the sheet.
    #[inline]
    fn cell_here(&self, c: &CellCoord) -> Option<Pos> {
        if self.in_name {
            return Some(Pos::new(
                c.row.resolve_wrapping(self.at.row, MAX_ROWS)?,
                c.col.resolve_wrapping(self.at.col, MAX_COLS)?,
            ));
        }
        Some(Pos::new(c.row.resolve(self.at.row, MAX_ROWS)?, c.col.resolve(self.at.col, MAX_COLS)?))
    }

    /// The number a leaf holds, a literal or a cell of this sheet holding a number; `None`
    /// for anything else, left to [`Ctx::eval`]. Arithmetic reads its operands through this
    /// first: a number in registers costs a fraction of building and copying a `Value`, and
    /// `A1+1` is most of what a long chain of formulas evaluates.
    #[inline]
    pub fn leaf_number(&self, e: &Expr) -> Option<f64> {
        match &e.kind {
            ExprKind::Number(n) => Some(self.literal(e, *n)),
            ExprKind::Ref(Reference { sheet: SheetRef::Current, shape: RefShape::Cell(c) }) => {
                self.env.number(self.sheet, self.cell_here(c)?)
            }
            _ => None,
        }
    }

    /// Evaluates keeping references as references (for SUM over ranges, ROW, INDEX, …).
    pub fn operand(&mut self, e: &Expr) -> Operand {
        match &e.kind {
            ExprKind::Ref(Reference { sheet: SheetRef::Span(first, last), shape }) => {
                self.sheet_span_operand(*first, *last, *shape)
            }
            ExprKind::Ref(r) => match self.resolve(r) {
                Ok((sheet, rect)) => Operand::Ref(sheet, rect),
                Err(err) => Operand::Value(Value::Error(err)),
            },
            ExprKind::Paren(inner) => self.operand(inner),
            ExprKind::Table(r) => match self.env.table_part(r, self.sheet, self.at) {
                Ok((sheet, rect)) => Operand::Ref(sheet, rect),
                Err(err) => Operand::Value(Value::Error(err)),
            },
            ExprKind::Name(name) => self.name_operand(name),
            ExprKind::SheetName(sheet, name) => match sheet {
                SheetRef::Id(id) => self.defined_name_operand(name, *id),
                SheetRef::Current => self.defined_name_operand(name, self.sheet),
                // `Sheet1:Sheet3!Rate`: a name is seen from one sheet, not from several.
                SheetRef::Missing(_) | SheetRef::Span(..) => Operand::Value(Value::Error(XlError::Ref)),
            },
            ExprKind::Host(id) => match self.host {
                Some(host) => host.node(self, *id),
                None => Operand::Value(Value::Error(XlError::Name)),
            },
            ExprKind::Binary(BinOp::Range, a, b) => self.range_operand(a, b),
            ExprKind::Binary(BinOp::Intersect, a, b) => self.intersect_operand(a, b),
            ExprKind::Binary(BinOp::Union, a, b) => self.union_operand(a, b),
            ExprKind::Unary(UnaryOp::Spill, inner) => self.spill_operand(inner),
            ExprKind::Call(id, args) => match functions::spec(*id).kind {
                FnKind::Ref(f) => {
                    let mark = self.held;
                    let operand = f(self, args);
                    self.held_operand(mark, operand)
                }
                FnKind::Value(_) => Operand::Value(self.call(*id, args)),
            },
            _ => Operand::Value(self.eval(e)),
        }
    }

    /// A reference operand read as a value; a value operand unchanged.
    pub fn deref(&mut self, operand: Operand) -> Value {
        match operand {
            Operand::Value(v) => v,
            Operand::Ref(sheet, rect) => self.held_range(sheet, rect),
            // `=(A1,B1)`: several areas are no one value (Excel's #VALUE!).
            Operand::Areas(_) => Value::Error(XlError::Value),
        }
    }

    /// A 3-D reference (`Sheet1:Sheet3!A1:B2`): the same cells on each sheet whose tab lies
    /// between its ends now, one area a sheet in tab order, which the functions taking
    /// several references read as their list; `#REF!` when an end is no sheet any more.
    fn sheet_span_operand(&mut self, first: SheetId, last: SheetId, shape: RefShape) -> Operand {
        let mut areas = Vec::new();
        for sheet in self.env.sheets_spanned(first, last) {
            match self.resolve(&Reference { sheet: SheetRef::Id(sheet), shape }) {
                Ok(area) => areas.push(area),
                Err(err) => return Operand::Value(Value::Error(err)),
            }
        }
        areas_operand(areas).unwrap_or(Operand::Value(Value::Error(XlError::Ref)))
    }

    /// The absolute sheet and rectangle a reference points at from this cell.
    pub fn resolve(&self, r: &Reference) -> XlResult<(SheetId, Rect)> {
        if self.in_name {
            return r.resolve_wrapping(self.sheet, self.at).ok_or(XlError::Ref);
        }
        r.resolve(self.sheet, self.at).ok_or(XlError::Ref)
    }

    /// [`Ctx::rect_value`], held by this evaluation: a range read whose items would not fit
    /// in what it may hold at once ([`MAX_LIVE_ITEMS`]) is `#NUM!` with the limit's note,
    /// before anything is allocated (`B1:XFC1048575*1` asked for 412 GB).
    fn held_range(&mut self, sheet: SheetId, rect: Rect) -> Value {
        if rect.is_cell() {
            return self.env.value(sheet, rect.first);
        }
        let stored = self.clip_to_used(sheet, rect);
        if let Err(e) = self.room_to_hold(stored.rows() as usize * stored.cols() as usize) {
            return Value::Error(e);
        }
        let v = self.rect_value(sheet, rect);
        self.held += held_items(&v);
        v
    }

    /// A rectangle's values: one cell's value, or an array whose items are stored as far
    /// as the used area (a whole column reads as far down as the sheet has data) and whose
    /// tail, the rest of the rectangle, is blank. More than [`MAX_LIVE_ITEMS`] stored items
    /// are `#NUM!`, never an allocation of gigabytes ([`Ctx::held_range`] says why).
    pub fn rect_value(&self, sheet: SheetId, rect: Rect) -> Value {
        if rect.is_cell() {
            return self.env.value(sheet, rect.first);
        }
        let whole = rect;
        let rect = self.clip_to_used(sheet, rect);
        let (rows, cols) = (rect.rows() as usize, rect.cols() as usize);
        if rows.saturating_mul(cols) > MAX_LIVE_ITEMS {
            return Value::Error(XlError::Num);
        }
        self.charge(rows * cols);
        let mut data = vec![Value::Blank; rows * cols];
        self.env.for_each_value(sheet, rect, &mut |p, v| {
            data[(p.row - rect.first.row) as usize * cols + (p.col - rect.first.col) as usize] = v.clone();
        });
        let array = Array::new(rows, cols, data).with_tail(whole.rows() as usize, whole.cols() as usize, Value::Blank);
        Value::Array(Rc::new(array))
    }

    /// Whole rows and columns (ranges to the sheet's last row or column) shrink to the used
    /// area; ordinary ranges stay as written.
    pub fn clip_to_used(&self, sheet: SheetId, rect: Rect) -> Rect {
        // Reaching the sheet's edge, as whole rows and columns and spills of them do.
        let whole_cols = rect.last.row == MAX_ROWS - 1;
        let whole_rows = rect.last.col == MAX_COLS - 1;
        if !whole_cols && !whole_rows {
            return rect;
        }
        let used = self.env.used_rect_for(sheet, rect).unwrap_or(Rect::cell(Pos::new(0, 0)));
        let mut r = rect;
        if whole_cols {
            r.last.row = used.last.row.max(r.first.row);
        }
        if whole_rows {
            r.last.col = used.last.col.max(r.first.col);
        }
        r
    }

    /// Evaluates `body` with `name` bound to `value` (for LET and LAMBDA).
    pub fn with_local<T>(&mut self, name: Rc<str>, value: Value, body: impl FnOnce(&mut Ctx<'a>) -> T) -> T {
        self.locals.push(Local { name, value, omitted: false });
        let out = body(self);
        self.locals.pop();
        out
    }

    /// The innermost LET name or LAMBDA parameter called `name`.
    fn local(&self, name: &str) -> Option<&Local> {
        self.locals.iter().rev().find(|l| l.name.eq_ignore_ascii_case(name))
    }

    /// Whether `name` is a parameter of the LAMBDA being evaluated whose argument the call
    /// left out (ISOMITTED).
    pub fn is_omitted(&self, name: &str) -> bool {
        self.local(name).is_some_and(|l| l.omitted)
    }

    /// `lambda`, a `LAMBDA(…)` call, as a value that remembers the names around it here.
    pub fn closure(&self, lambda: Expr) -> Value {
        let (locals, sheet, at, in_name) = (self.locals.clone(), self.sheet, self.at, self.in_name);
        Value::Lambda(Rc::new(Closure { lambda, locals, sheet, at, in_name, own_name: None }))
    }

    /// The LAMBDA value `closure` called with `values` (MAP, REDUCE… call it so), every
    /// parameter given. These calls are not counted against [`MAX_LAMBDA_CALLS`]: there are
    /// as many as the array has items, and no recursion. They are counted, with what their
    /// bodies make and read, against [`MAX_LAMBDA_WORK`]: past it, `#NUM!` with a note.
    /// `frame` is the list of names the calls of one loop share ([`CallFrame`]).
    pub fn apply_closure(&mut self, closure: &Rc<Closure>, values: &[Value], frame: &mut CallFrame) -> XlResult<Value> {
        self.within_lambda_work()?;
        let lambda = closure.lambda();
        if lambda.params.len() != values.len() {
            return Ok(Value::Error(XlError::Value));
        }
        let bound = lambda.param_names().zip(values);
        let bound = bound.map(|(name, value)| Local { name: name.clone(), value: value.clone(), omitted: false });
        self.iterating += 1;
        let mark = self.held;
        let out = self.run_closure(closure, bound, frame);
        let out = self.held_result(mark, out);
        self.iterating -= 1;
        Ok(out)
    }

    /// One more LAMBDA call, told to the environment ([`Env::work_done`]).
    fn count_call(&self) {
        self.env.work_done(WorkDone { items: 0, calls: 1 });
    }

    /// Starts a new evaluation's counts against [`MAX_LAMBDA_WORK`] and [`MAX_LAMBDA_CALLS`]:
    /// a surface evaluates its formula once per point through one `Ctx`, each point an
    /// evaluation of its own.
    pub fn restart_lambda_work(&mut self) {
        self.lambda_work.set(0);
        self.lambda_calls = 0;
    }

    /// [`Host::option_compare_text`]: the comparison VBA's text functions default to.
    pub fn option_compare_text(&self) -> bool {
        self.host.is_some_and(|host| host.option_compare_text())
    }

    /// Whether a macro evaluates this expression (VBA's library functions then follow VBA's
    /// rules where a cell's formula follows Excel's).
    pub fn in_macro(&self) -> bool {
        self.host.is_some()
    }

    /// [`Host::may_run_code`] of the host's node `id`: `true` without a host.
    pub fn host_may_run_code(&self, id: u32) -> bool {
        self.host.is_none_or(|h| h.may_run_code(id))
    }

    /// [`Host::text_length`] of the host's variable `name`, when there is a host.
    pub fn host_text_length(&self, name: &str) -> Option<usize> {
        self.host?.text_length(name)
    }

    /// [`Host::growing_text`] of the host's variable `name`, when there is a host.
    pub fn host_growing_text(&self, name: &str) -> Option<Rc<String>> {
        self.host?.growing_text(name)
    }

    /// Counts `work` (items made or read, see [`work_of`]) when a LAMBDA of MAP, REDUCE, …
    /// is running; [`Ctx::apply_closure`] checks the total before each call. A macro is told
    /// of all of it ([`Host::work`]).
    #[inline]
    pub fn charge(&self, work: usize) {
        self.env.work_done(WorkDone { items: work as u64, calls: 0 });
        if self.iterating > 0 {
            self.lambda_work.set(self.lambda_work.get().saturating_add(work as u64));
        }
        if let Some(host) = self.host {
            host.work(work as u64);
        }
    }

    /// Counts the work of reading `bytes` of text (a unit per 16 bytes, as [`work_of`] counts
    /// a text made): a function whose answer is small may have read long texts to find it
    /// (`InStr`, `StrComp`, a comparison).
    #[inline]
    pub fn charge_read(&self, bytes: usize) {
        self.charge(bytes / 16);
    }

    /// Counts the texts among a function's arguments `values` (16 bytes a unit, as texts made
    /// are) when a LAMBDA of MAP, REDUCE, … is running, or in a macro: a text function reads
    /// its arguments whole and may make nothing (`LEN(t)` of a 32,767-character `t` bound
    /// outside the LAMBDA).
    #[inline]
    pub fn charge_texts(&self, values: &[Value]) {
        if self.iterating > 0 || self.host.is_some() {
            let bytes: usize = values.iter().map(|v| if let Value::Text(t) = v { t.len() } else { 0 }).sum();
            self.charge(bytes / 16);
        }
    }

    /// One more call of a LAMBDA by MAP, REDUCE, …: `#NUM!`, with the limit's note, once
    /// their work has passed [`MAX_LAMBDA_WORK`] (or the smaller budget the workbook's
    /// settings give, [`Env::lambda_work_limit`]).
    fn within_lambda_work(&mut self) -> XlResult<()> {
        self.count_call();
        let work = self.lambda_work.get() + 1;
        self.lambda_work.set(work);
        let limit = self.env.lambda_work_limit();
        if work > limit {
            return Err(self.explain_once(XlError::Num, lambda_work_note(limit)));
        }
        Ok(())
    }

    /// Whether `work` more items, known before they are done (the records a D-function would
    /// test), fit in what is left of [`MAX_LAMBDA_WORK`] when a LAMBDA of MAP, REDUCE, … is
    /// running: past it, `#NUM!` with the limit's note before the work, not after it.
    pub fn within_lambda_budget(&mut self, work: usize) -> XlResult<()> {
        if self.iterating == 0 {
            return Ok(());
        }
        let limit = self.env.lambda_work_limit();
        if self.lambda_work.get().saturating_add(work as u64) > limit {
            return Err(self.explain_once(XlError::Num, lambda_work_note(limit)));
        }
        Ok(())
    }

    /// The LAMBDA value `closure` called with `args`, evaluated here.
    fn call_closure(&mut self, name: &str, closure: &Rc<Closure>, args: &[Expr]) -> Value {
        let lambda = closure.lambda();
        if !lambda.accepts(args.len()) {
            return Value::Error(XlError::Value);
        }
        if let Err(e) = self.enter_lambda(name) {
            return Value::Error(e);
        }
        let values: Vec<Value> = args.iter().map(|a| self.eval(a)).collect();
        let bound = parameters(&lambda, args, values);
        self.run_closure(closure, bound, &mut CallFrame::default())
    }

    /// A closure's body with `bound` parameters, among the names it was made with, listed in
    /// `spare` (emptied, and handed back emptied: MAKEARRAY's LAMBDA is called millions of
    /// times, and a list made and freed for each call was most of a call's cost).
    fn run_closure(
        &mut self,
        closure: &Rc<Closure>,
        bound: impl IntoIterator<Item = Local>,
        spare: &mut CallFrame,
    ) -> Value {
        let mut locals = std::mem::take(&mut spare.0);
        locals.extend_from_slice(&closure.locals);
        if let Some(name) = &closure.own_name {
            locals.push(Local { name: name.clone(), value: Value::Lambda(closure.clone()), omitted: false });
        }
        locals.extend(bound);
        let saved = (self.sheet, self.at, self.in_name, std::mem::replace(&mut self.locals, locals));
        (self.sheet, self.at, self.in_name) = (closure.sheet, closure.at, closure.in_name);
        self.depth += 1;
        let out = self.eval(closure.lambda().body);
        self.depth -= 1;
        let mut used;
        (self.sheet, self.at, self.in_name, used) = saved;
        std::mem::swap(&mut self.locals, &mut used);
        used.clear();
        spare.0 = used;
        out
    }

    /// Calls a registered function by id with unevaluated arguments.
    pub fn call(&mut self, id: FnId, args: &[Expr]) -> Value {
        let mark = self.held;
        let v = match functions::spec(id).kind {
            FnKind::Value(f) => f(self, args).unwrap_or_else(Value::Error),
            FnKind::Ref(f) => {
                let operand = f(self, args);
                self.deref(operand)
            }
        };
        match v {
            // A finite number, the usual result, needs neither check: no call on this path.
            Value::Number(n) if is_normal_or_zero(n) => {
                self.held = mark;
                v
            }
            v => self.checked_result(mark, v),
        }
    }

    /// [`Ctx::call`]'s checks of a result that is not a plain number: infinities, NaN and
    /// subnormals made Excel's, texts held to the limit, arrays to what the evaluation may
    /// hold at once (the call began when `mark` items were held).
    #[inline(never)]
    fn checked_result(&mut self, mark: usize, v: Value) -> Value {
        self.charge(work_of(&v));
        let v = self.within_text_limit(finite_numbers(v));
        self.held_result(mark, v)
    }

    fn name_operand(&mut self, name: &str) -> Operand {
        if let Some(local) = self.local(name) {
            return Operand::Value(local.value.clone());
        }
        if let Some(operand) = self.host.and_then(|h| h.variable(name)) {
            return operand;
        }
        self.defined_name_operand(name, self.sheet)
    }

    /// The defined name `name` as seen from sheet `from` (its own name, else the workbook's).
    fn defined_name_operand(&mut self, name: &str, from: SheetId) -> Operand {
        let Some((expr, sheet)) = self.env.defined_name(name, from) else {
            return Operand::Value(Value::Error(XlError::Name));
        };
        if self.depth >= MAX_DEPTH {
            let why = format!(
                "defined names nest deeper than {MAX_DEPTH} levels evaluating {name}: a name that refers to itself, \
                 or a chain longer than ncsheet's limit"
            );
            return Operand::Value(Value::Error(self.explain_once(XlError::Circ, why)));
        }
        // A defined name is evaluated on its sheet, without the caller's LET or macro
        // variables, and at the caller's cell: Excel stores a name's relative references
        // (`Sheet1!$A1`) as seen from A1, so they move with the cell that uses the name.
        let saved = (self.sheet, self.in_name, std::mem::take(&mut self.locals), self.host.take());
        (self.sheet, self.in_name) = (sheet, true);
        self.depth += 1;
        let out = self.operand(&expr);
        self.depth -= 1;
        (self.sheet, self.in_name, self.locals, self.host) = saved;
        out
    }

    /// `=bump(0.1, 0.2)`: a call of a LET name or parameter holding a LAMBDA, else of the
    /// defined name `bump`. A name defined as `=LAMBDA(x, y, …)` runs its body where the name
    /// lives, at the caller's cell as every defined name's formula does (its relative
    /// references move with the calling cell); a name whose formula gives a LAMBDA otherwise
    /// (`=LET(k, 2, LAMBDA(x, x*k))`) is evaluated first. Any other call goes to the workbook's
    /// own functions (VBA), else is `#NAME?`;
    /// a wrong argument count `#VALUE!`.
    fn call_defined_lambda(&mut self, name: &str, args: &[Expr]) -> Value {
        if let Some(local) = self.local(name) {
            return match local.value.clone() {
                Value::Lambda(closure) => self.call_closure(name, &closure, args),
                _ => Value::Error(XlError::Name),
            };
        }
        let Some((expr, sheet)) = self.env.defined_name(name, self.sheet) else { return self.call_user(name, args) };
        let Some(lambda) = functions::as_lambda(&expr) else {
            return match self.name_operand(name) {
                Operand::Value(Value::Lambda(closure)) => self.call_closure(name, &closure, args),
                _ => self.call_user(name, args),
            };
        };
        // The common case, read from the name's own tree: no closure is built per call.
        if !lambda.accepts(args.len()) {
            return Value::Error(XlError::Value);
        }
        if let Err(e) = self.enter_lambda(name) {
            return Value::Error(e);
        }
        let values: Vec<Value> = args.iter().map(|a| self.eval(a)).collect();
        let saved = (self.sheet, self.in_name, std::mem::take(&mut self.locals));
        (self.sheet, self.in_name) = (sheet, true);
        self.locals.extend(parameters(&lambda, args, values));
        self.depth += 1;
        let out = self.eval(lambda.body);
        self.depth -= 1;
        (self.sheet, self.in_name, self.locals) = saved;
        out
    }

    /// A function of the workbook's own (a VBA Function), or `#NAME?` when there is none.
    fn call_user(&mut self, name: &str, args: &[Expr]) -> Value {
        let operands: Vec<Operand> = args
            .iter()
            .map(|a| match a.kind {
                ExprKind::Missing => Operand::Value(Value::Blank),
                _ => self.operand(a),
            })
            .collect();
        let call = UserCall { name, args: &operands, caller: (self.sheet, self.at) };
        match self.env.call_user_function(self.env, &call) {
            Some(Ok(value)) => value,
            Some(Err(Note { error, message })) => Value::Error(self.explain(error, message)),
            None => Value::Error(XlError::Name),
        }
    }

    /// `LAMBDA(x, y, x+y)(1, 2)`, `f(3)(4)`, `IF(c, LAMBDA(…), LAMBDA(…))(5)`: whatever the
    /// callee gives is called, when it is a LAMBDA; an error passes on; anything else is
    /// `#VALUE!`.
    fn invoke(&mut self, callee: &Expr, args: &[Expr]) -> Value {
        match self.eval(callee) {
            Value::Lambda(closure) => self.call_closure("LAMBDA", &closure, args),
            Value::Error(e) => Value::Error(e),
            _ => {
                let why = "only a LAMBDA can be called so: LAMBDA(x, x+1)(2)".to_string();
                Value::Error(self.explain_once(XlError::Value, why))
            }
        }
    }

    /// Counts a call of the named LAMBDA `name` against ncsheet's limits: nesting deeper
    /// than [`MAX_DEPTH`] or more than [`MAX_LAMBDA_CALLS`] calls is `#NUM!` (Excel's error
    /// for a LAMBDA calling itself without end), with a note saying which limit.
    fn enter_lambda(&mut self, name: &str) -> XlResult<()> {
        if self.depth >= MAX_DEPTH {
            let why = format!(
                "LAMBDA calls nest deeper than {MAX_DEPTH} levels calling {name}: recursion without end, \
                 or deeper than ncsheet's limit"
            );
            return Err(self.explain_once(XlError::Num, why));
        }
        self.lambda_calls += 1;
        self.count_call();
        if self.lambda_calls > MAX_LAMBDA_CALLS {
            let why = format!(
                "more than {MAX_LAMBDA_CALLS} LAMBDA calls in one formula (ncsheet's limit) calling {name}: \
                 recursion that branches too often"
            );
            return Err(self.explain_once(XlError::Num, why));
        }
        Ok(())
    }

    /// [`Ctx::explain`], but a message already noted is not noted again (a recursion past
    /// a limit fails once per branch).
    /// Names the limit when two arrays broadcast past [`MAX_ARRAY_ITEMS`] (`#NUM!`).
    fn explain_array_size(&mut self, a: &Value, b: &Value) {
        let size = |v: &Value| match v {
            Value::Array(a) => (a.rows, a.cols),
            _ => (1, 1),
        };
        if matches!(a, Value::Array(_)) || matches!(b, Value::Array(_)) {
            let ((ra, ca), (rb, cb)) = (size(a), size(b));
            let (rows, cols) = (ra.max(rb), ca.max(cb));
            if too_many_items(rows, cols) {
                self.explain_once(XlError::Num, too_many_items_note(rows, cols));
            } else {
                // Broadcasting refuses nothing else: its items' texts passed their limit.
                self.explain_once(XlError::Num, super::value::too_much_text_note());
            }
        }
    }

    /// [`Ctx::explain`], unless the same note is there already: for an error a loop may meet
    /// at every turn (each call of MAP's LAMBDA).
    pub fn explain_once(&mut self, error: XlError, message: String) -> XlError {
        if !self.notes.iter().any(|n| n.error == error && n.message == message) {
            self.notes.push(Note { error, message });
        }
        error
    }

    /// `a:b`: the smallest rectangle holding both (every area of a multi-area operand).
    fn range_operand(&mut self, a: &Expr, b: &Expr) -> Operand {
        let (a, b) = (self.operand(a), self.operand(b));
        let (a, b) = match (areas_of(&a), areas_of(&b)) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(e), _) | (_, Err(e)) => return Operand::Value(Value::Error(e)),
        };
        let sheet = a[0].0;
        if a.iter().chain(&b).any(|(s, _)| *s != sheet) {
            return Operand::Value(Value::Error(XlError::Value));
        }
        let rects = a.iter().chain(&b).map(|(_, r)| *r);
        let bounds = rects.reduce(|r1, r2| Rect {
            first: Pos::new(r1.first.row.min(r2.first.row), r1.first.col.min(r2.first.col)),
            last: Pos::new(r1.last.row.max(r2.last.row), r1.last.col.max(r2.last.col)),
        });
        Operand::Ref(sheet, bounds.expect("an operand has an area"))
    }

    /// `a b`: the cells both cover; `#NULL!` when they share none (Excel's rule).
    fn intersect_operand(&mut self, a: &Expr, b: &Expr) -> Operand {
        let (a, b) = (self.operand(a), self.operand(b));
        let (a, b) = match (areas_of(&a), areas_of(&b)) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(e), _) | (_, Err(e)) => return Operand::Value(Value::Error(e)),
        };
        let mut common = Vec::new();
        for (s1, r1) in &a {
            for (s2, r2) in &b {
                if s1 != s2 {
                    return Operand::Value(Value::Error(XlError::Value));
                }
                if let Some(r) = rect_intersection(*r1, *r2) {
                    common.push((*s1, r));
                }
            }
        }
        areas_operand(common).unwrap_or(Operand::Value(Value::Error(XlError::Null)))
    }

    /// `(a,b)`: the areas of both, in order, on one sheet.
    fn union_operand(&mut self, a: &Expr, b: &Expr) -> Operand {
        let (a, b) = (self.operand(a), self.operand(b));
        let all = match (areas_of(&a), areas_of(&b)) {
            (Ok(mut a), Ok(b)) => {
                a.extend(b);
                a
            }
            (Err(e), _) | (_, Err(e)) => return Operand::Value(Value::Error(e)),
        };
        if all.iter().any(|(s, _)| *s != all[0].0) {
            return Operand::Value(Value::Error(XlError::Value));
        }
        areas_operand(all).expect("a union has areas")
    }

    fn spill_operand(&mut self, inner: &Expr) -> Operand {
        match self.operand(inner) {
            Operand::Ref(sheet, rect) => match self.env.spill_rect(sheet, rect.first) {
                Some(r) => Operand::Ref(sheet, r),
                None => Operand::Value(Value::Error(XlError::Ref)),
            },
            Operand::Value(Value::Error(e)) => Operand::Value(Value::Error(e)),
            Operand::Value(_) | Operand::Areas(_) => Operand::Value(Value::Error(XlError::Ref)),
        }
    }

    fn array_literal(&mut self, lit: &ArrayLit) -> Value {
        let data = lit.items.iter().map(|e| self.eval(e)).collect();
        Value::Array(Rc::new(Array::new(lit.rows, lit.cols, data)))
    }

    fn unary(&mut self, op: UnaryOp, inner: &Expr) -> Value {
        match op {
            UnaryOp::Neg => {
                let v = self.locale().numbers_for_arithmetic(self.eval(inner), self.dates);
                match v {
                    // VBA's Null propagates through negation too.
                    Value::Null => Value::Null,
                    // A macro's True is -1 ([MS-VBAL] 5.5.1.2.1), so `-True` is 1.
                    Value::Bool(b) if self.host.is_some() => Value::Number(if b { 1.0 } else { 0.0 }),
                    v => {
                        // A macro's String operand is let-coerced as CDbl reads it ([MS-VBAL]
                        // 5.6.9.3.1, 5.5.1.2.1): `-"1D2"` is -100 and `-"&H10"` -16, as
                        // `"1D2" + 0` is 100 (`vba/host.rs`, `vba_operands`).
                        let v = match (v, self.host) {
                            (Value::Text(t), Some(_)) => {
                                crate::eval::functions::vba::vba_number_text(&t).map_or(Value::Text(t), Value::Number)
                            }
                            (v, _) => v,
                        };
                        let negated = map_number(&v, |x| Ok(-x), self.dates);
                        match self.host {
                            Some(host) => host.negation(inner, negated),
                            None => negated,
                        }
                    }
                }
            }
            UnaryOp::Plus => self.eval(inner),
            UnaryOp::Percent => {
                let v = self.locale().numbers_for_arithmetic(self.eval(inner), self.dates);
                map_number(&v, |x| Ok(x / 100.0), self.dates)
            }
            UnaryOp::Implicit => {
                let operand = self.operand(inner);
                self.implicit_intersection(operand)
            }
            UnaryOp::Spill => {
                let operand = self.spill_operand(inner);
                self.deref(operand)
            }
            UnaryOp::Not => {
                let dates = self.dates;
                let v = self.eval(inner);
                let result = map_value(&v, &|v| vba_not(v, dates));
                // VBA's Not of a text that is no number, or of an error value, is a Type mismatch.
                if let (Some(host), Value::Error(_), false) = (self.host, &result, matches!(v, Value::Array(_))) {
                    host.raise(13, "Type mismatch (run-time error 13): Not of a value that is no number");
                }
                match self.host {
                    Some(host) => host.logical_not(inner, result),
                    None => result,
                }
            }
        }
    }

    /// `@A1:A10` in row 5 is A5; a range not in line with the cell is `#VALUE!`.
    pub fn implicit_intersection(&mut self, operand: Operand) -> Value {
        match operand {
            Operand::Value(Value::Array(a)) => a.data.first().cloned().unwrap_or(Value::Blank),
            Operand::Value(v) => v,
            Operand::Areas(_) => Value::Error(XlError::Value),
            Operand::Ref(sheet, rect) if rect.is_cell() => self.env.value(sheet, rect.first),
            Operand::Ref(sheet, rect) => {
                let row = if rect.rows() == 1 {
                    Some(rect.first.row)
                } else {
                    (rect.first.row..=rect.last.row).contains(&self.at.row).then_some(self.at.row)
                };
                let col = if rect.cols() == 1 {
                    Some(rect.first.col)
                } else {
                    (rect.first.col..=rect.last.col).contains(&self.at.col).then_some(self.at.col)
                };
                match (row, col) {
                    (Some(r), Some(c)) if rect.rows() == 1 || rect.cols() == 1 => self.env.value(sheet, Pos::new(r, c)),
                    _ => Value::Error(XlError::Value),
                }
            }
        }
    }
}

/// A formula's result as a cell or a macro variable holds it: a LAMBDA left uncalled is
/// `#CALC!` (Excel's error for `=LAMBDA(x, x+1)` alone), in an array too.
pub fn no_lambda(v: Value) -> Value {
    match v {
        Value::Lambda(_) => Value::Error(XlError::Calc),
        Value::Array(a) if a.data.iter().any(|x| matches!(x, Value::Lambda(_))) => {
            map_value(&Value::Array(a), &|x| no_lambda(x.clone()))
        }
        v => v,
    }
}

/// The areas of a reference operand (one for a rectangle); an error value's error, and
/// `#VALUE!` for any other value (`(1,2)` is no reference).
pub fn areas_of(operand: &Operand) -> XlResult<Vec<(SheetId, Rect)>> {
    match operand {
        Operand::Ref(sheet, rect) => Ok(vec![(*sheet, *rect)]),
        Operand::Areas(areas) => Ok(areas.to_vec()),
        Operand::Value(Value::Error(e)) => Err(*e),
        Operand::Value(_) => Err(XlError::Value),
    }
}

/// One area as a plain reference, several as [`Operand::Areas`], none as `None`.
fn areas_operand(mut areas: Vec<(SheetId, Rect)>) -> Option<Operand> {
    match areas.len() {
        0 => None,
        1 => areas.pop().map(|(s, r)| Operand::Ref(s, r)),
        _ => Some(Operand::Areas(areas.into())),
    }
}

/// The cells two rectangles share, if any.
fn rect_intersection(a: Rect, b: Rect) -> Option<Rect> {
    let first = Pos::new(a.first.row.max(b.first.row), a.first.col.max(b.first.col));
    let last = Pos::new(a.last.row.min(b.last.row), a.last.col.min(b.last.col));
    (first.row <= last.row && first.col <= last.col).then_some(Rect { first, last })
}

/// Applies a numeric function to a scalar or element-wise to an array.
pub fn map_number(v: &Value, f: impl Fn(f64) -> XlResult<f64>, dates: DateSystem) -> Value {
    map_value(v, &|x| match to_number(x, dates).and_then(&f) {
        Ok(n) => number_result(n),
        Err(e) => Value::Error(e),
    })
}

/// Applies `f` to a scalar, or to each item of an array.
pub fn map_value(v: &Value, f: &dyn Fn(&Value) -> Value) -> Value {
    match v {
        Value::Array(a) => {
            let mapped = Array::new(a.rows, a.cols, a.data.iter().map(f).collect());
            Value::Array(Rc::new(match &a.tail {
                Some(t) => mapped.with_tail(t.rows, t.cols, f(&t.fill)),
                None => mapped,
            }))
        }
        other => f(other),
    }
}

/// Combines two operands item by item with Excel's broadcasting (a single row or
/// column repeats; beyond the smaller array's edge the item is `#N/A`).
pub fn broadcast2(a: &Value, b: &Value, f: &dyn Fn(&Value, &Value) -> Value) -> Value {
    if has_tail(a) || has_tail(b) {
        return broadcast_whole(&[a, b], &|v| f(&v[0], &v[1]));
    }
    match (a, b) {
        (Value::Array(x), Value::Array(y)) => {
            let rows = x.rows.max(y.rows);
            let cols = x.cols.max(y.cols);
            if too_many_items(rows, cols) {
                return Value::Error(XlError::Num);
            }
            let mut data = Vec::with_capacity(rows * cols);
            let mut text = super::value::TextBudget::default();
            for r in 0..rows {
                for c in 0..cols {
                    let (xi, yi) = (x.broadcast_get(r, c), y.broadcast_get(r, c));
                    text.read(&xi);
                    text.read(&yi);
                    let item = f(&xi, &yi);
                    if !text.take(&item) {
                        return Value::Error(XlError::Num);
                    }
                    data.push(item);
                }
            }
            Value::Array(Rc::new(Array::new(rows, cols, data)))
        }
        (Value::Array(x), s) => map_items(x, s, |v| f(v, s)),
        (s, Value::Array(y)) => map_items(y, s, |v| f(s, v)),
        (x, y) => f(x, y),
    }
}

/// `f` on each item of `a` (with the single value `other`), the result's texts and the texts
/// read for them counted against their limits (`#NUM!` past them).
fn map_items(a: &Array, other: &Value, f: impl Fn(&Value) -> Value) -> Value {
    let mut text = super::value::TextBudget::default();
    let mut data = Vec::with_capacity(a.data.len());
    for v in &a.data {
        text.read(v);
        text.read(other);
        let item = f(v);
        if !text.take(&item) {
            return Value::Error(XlError::Num);
        }
        data.push(item);
    }
    Value::Array(Rc::new(Array::new(a.rows, a.cols, data)))
}

fn has_tail(v: &Value) -> bool {
    matches!(v, Value::Array(a) if a.tail.is_some())
}

/// Item-by-item application over operands of which some have a tail (whole rows or
/// columns): broadcasting follows the whole sizes, `f` runs on the items stored in any
/// operand, and once more for each distinct place beyond them. The result keeps a tail
/// when that is one value (`=1:1*2`: 0); otherwise only the stored part is kept, as a
/// whole row read without a tail would be.
pub fn broadcast_whole(values: &[&Value], f: &dyn Fn(&[Value]) -> Value) -> Value {
    let sizes = |v: &Value| match v {
        Value::Array(a) => ((a.rows, a.cols), a.whole_size()),
        _ => ((1, 1), (1, 1)),
    };
    let (mut stored, mut whole) = ((1, 1), (1, 1));
    for v in values {
        let (s, w) = sizes(v);
        stored = (stored.0.max(s.0), stored.1.max(s.1));
        whole = (whole.0.max(w.0), whole.1.max(w.1));
    }
    let item = |v: &Value, r: usize, c: usize| match v {
        Value::Array(a) => {
            let (rows, cols) = a.whole_size();
            let (r, c) = (if rows == 1 { 0 } else { r }, if cols == 1 { 0 } else { c });
            a.whole_get(r, c).cloned().unwrap_or(Value::Error(XlError::NA))
        }
        other => other.clone(),
    };
    // The texts read and made are counted as broadcast2's and map_items' are: a whole column
    // of long texts compared with another read without limit.
    let mut text = super::value::TextBudget::default();
    let mut at = |r: usize, c: usize| {
        let operands: Vec<Value> = values.iter().map(|v| item(v, r, c)).collect();
        operands.iter().for_each(|v| text.read(v));
        let made = f(&operands);
        text.take(&made).then_some(made)
    };
    if too_many_items(stored.0, stored.1) {
        return Value::Error(XlError::Num);
    }
    let mut data = Vec::with_capacity(stored.0 * stored.1);
    for r in 0..stored.0 {
        for c in 0..stored.1 {
            let Some(made) = at(r, c) else { return Value::Error(XlError::Num) };
            data.push(made);
        }
    }
    let array = Array::new(stored.0, stored.1, data);
    // Beyond the stored items each operand is constant along a dimension when its whole
    // size there is 1, within the stored part, or the whole result's: then one place per
    // row (or column) of the stored part, plus the corner, shows every value of the tail.
    let even = values.iter().all(|v| {
        let (_, w) = sizes(v);
        let fits = |w: usize, s: usize, all: usize| w <= s || w == all;
        fits(w.0, stored.0, whole.0) && fits(w.1, stored.1, whole.1)
    });
    let mut places = Vec::new();
    if whole.1 > stored.1 {
        places.extend((0..whole.0.min(stored.0 + 1)).map(|r| (r, stored.1)));
    }
    if whole.0 > stored.0 {
        places.extend((0..whole.1.min(stored.1 + 1)).map(|c| (stored.0, c)));
    }
    let Some(&(r0, c0)) = places.first() else { return Value::Array(Rc::new(array)) };
    if !even {
        return Value::Array(Rc::new(array));
    }
    let Some(fill) = at(r0, c0) else { return Value::Error(XlError::Num) };
    for &(r, c) in &places {
        match at(r, c) {
            None => return Value::Error(XlError::Num),
            Some(v) if v != fill => return Value::Array(Rc::new(array)),
            Some(_) => {}
        }
    }
    Value::Array(Rc::new(array.with_tail(whole.0, whole.1, fill)))
}

/// A computed number as a value: NaN and infinities are `#NUM!`, as Excel reports overflow;
/// numbers below the smallest normal double are 0, as Excel keeps no subnormals
/// (`EXP(-745)` is 0), and so is a negative zero (`0*-1`): Excel has none, and ATAN2 read
/// its sign (`ATAN2(-1,0*-1)` was -π, which Excel's ATAN2 never returns).
#[inline]
pub fn number_result(n: f64) -> Value {
    if !n.is_finite() {
        Value::Error(XlError::Num)
    } else if n.abs() < f64::MIN_POSITIVE {
        Value::Number(0.0)
    } else {
        Value::Number(n)
    }
}

/// A function's result with every number as [`number_result`] makes it: whatever a
/// function computes, an infinity or NaN leaves it as `#NUM!` and a subnormal as 0, in one
/// place rather than in each of 500 functions (`MEDIAN`, `GROWTH` and `TREND` leaked them
/// into cells, files and ISNUMBER). An array is copied only when it holds one.
pub fn finite_numbers(v: Value) -> Value {
    let unfit = |n: f64| !is_normal_or_zero(n);
    match v {
        Value::Number(n) if unfit(n) => number_result(n),
        Value::Array(a) if a.data.iter().any(|x| matches!(x, Value::Number(n) if unfit(*n))) => {
            let mut a = Rc::unwrap_or_clone(a);
            for x in &mut a.data {
                if let Value::Number(n) = *x {
                    *x = number_result(n);
                }
            }
            if let Some(tail) = &mut a.tail {
                if let Value::Number(n) = tail.fill {
                    tail.fill = number_result(n);
                }
            }
            Value::Array(Rc::new(a))
        }
        other => other,
    }
}

/// A number a cell may hold as it is: finite, not subnormal and not a negative zero
/// ([`finite_numbers`]).
#[inline]
fn is_normal_or_zero(n: f64) -> bool {
    n.is_normal() || n.to_bits() == 0
}

/// Whether `r`, the sum or difference of `x` and `y`, is only the binary rounding of their
/// decimal values: within 2^-50 of the larger (`0.1+0.2-0.3` is 1.9e-16 of 0.3 and zeroed;
/// `40026.44000000006-40026.44`, 1.5e-15, is kept, as Excel keeps it).
fn cancels(r: f64, x: f64, y: f64) -> bool {
    r != 0.0 && r.abs() <= x.abs().max(y.abs()) * f64::powi(2.0, -50)
}

/// A formula's last addition or subtraction of two numbers, zeroed where it [`cancels`].
fn sum_or_difference(op: BinOp, x: f64, y: f64) -> Value {
    let r = if op == BinOp::Add { x + y } else { x - y };
    if cancels(r, x, y) {
        Value::Number(0.0)
    } else {
        number_result(r)
    }
}

/// A binary operator applied with broadcasting; text operands of arithmetic are read with
/// date text as serials of `dates`.
pub fn binary(op: BinOp, a: &Value, b: &Value, dates: DateSystem) -> Value {
    if let (Value::Number(x), Value::Number(y)) = (a, b) {
        return scalar_binary_numbers(op, *x, *y);
    }
    broadcast2(a, b, &|x, y| scalar_binary(op, x, y, dates))
}

fn scalar_binary(op: BinOp, a: &Value, b: &Value, dates: DateSystem) -> Value {
    if matches!(a, Value::Null) || matches!(b, Value::Null) {
        return null_binary(op, a, b, dates);
    }
    match op {
        BinOp::Concat => match (to_text(a), to_text(b)) {
            (Ok(x), Ok(y)) => Value::Text(format!("{x}{y}").into()),
            (Err(e), _) | (_, Err(e)) => Value::Error(e),
        },
        BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => match compare_operands(a, b) {
            Ok(ord) => Value::Bool(comparison_holds(op, ord)),
            Err(e) => Value::Error(e),
        },
        BinOp::And | BinOp::Or | BinOp::Xor | BinOp::Eqv | BinOp::Imp => vba_logic(op, a, b, dates),
        BinOp::Like => functions::vba::like(a, b),
        _ => match (to_number(a, dates), to_number(b, dates)) {
            (Ok(x), Ok(y)) => scalar_binary_numbers(op, x, y),
            (Err(e), _) | (_, Err(e)) => Value::Error(e),
        },
    }
}

/// How the comparison operators order two values: Excel rounds numbers to 15 significant
/// digits for them (`=0.1+0.2=0.3` is TRUE, `=0.1=(1.2-1.1)` FALSE: 0.0999999999999999).
fn compare_operands(a: &Value, b: &Value) -> XlResult<std::cmp::Ordering> {
    match (a, b) {
        // Rounding is monotonic and moves a number by under 1e-14 of itself, so numbers
        // further apart keep their order and the rounding (a log and a power) is skipped.
        (Value::Number(x), Value::Number(y)) if (x - y).abs() > 1e-13 * x.abs().max(y.abs()) => compare(a, b),
        (Value::Number(x), Value::Number(y)) => {
            compare(&Value::Number(fifteen_digits(*x)), &Value::Number(fifteen_digits(*y)))
        }
        _ => compare(a, b),
    }
}

/// `x` rounded to 15 significant digits (unchanged where the scale leaves the doubles).
fn fifteen_digits(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(14 - x.abs().log10().floor() as i32);
    let rounded = (x * scale).round() / scale;
    if scale.is_finite() && rounded.is_finite() {
        rounded
    } else {
        x
    }
}

pub fn comparison_holds(op: BinOp, ord: std::cmp::Ordering) -> bool {
    use std::cmp::Ordering::*;
    match op {
        BinOp::Eq => ord == Equal,
        BinOp::Ne => ord != Equal,
        BinOp::Lt => ord == Less,
        BinOp::Le => ord != Greater,
        BinOp::Gt => ord == Greater,
        BinOp::Ge => ord != Less,
        _ => unreachable!("not a comparison"),
    }
}

#[inline]
fn scalar_binary_numbers(op: BinOp, x: f64, y: f64) -> Value {
    match op {
        BinOp::Add => number_result(x + y),
        BinOp::Sub => number_result(x - y),
        BinOp::Mul => number_result(x * y),
        BinOp::Div if y == 0.0 => Value::Error(XlError::Div0),
        BinOp::Div => number_result(x / y),
        BinOp::Pow => power(x, y).map_or_else(Value::Error, number_result),
        BinOp::Mod | BinOp::IntDiv => vba_integer_division(op, x, y),
        // Numbers only: no date text to read.
        _ => scalar_binary(op, &Value::Number(x), &Value::Number(y), DateSystem::From1900),
    }
}

// VBA's operators, for macros. VBA rounds their operands to whole numbers half to even
// (`5.5 Mod 2` is 0), and its True is -1 where a bitwise operator meets a number.

/// A number as VBA's operators read it: rounded half to even, `#NUM!` beyond 64 bits.
fn vba_integer(x: f64) -> XlResult<i64> {
    let r = x.round_ties_even();
    if r.abs() < 9.2e18 {
        Ok(r as i64)
    } else {
        Err(XlError::Num)
    }
}

fn vba_integer_division(op: BinOp, x: f64, y: f64) -> Value {
    let (a, b) = match (vba_integer(x), vba_integer(y)) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(e), _) | (_, Err(e)) => return Value::Error(e),
    };
    match (op, b) {
        (_, 0) => Value::Error(XlError::Div0),
        (BinOp::Mod, _) => Value::Number(a.wrapping_rem(b) as f64),
        _ => Value::Number(a.wrapping_div(b) as f64),
    }
}

/// A logical operand: booleans stay booleans; anything else is an integer (True is -1).
enum Logic {
    Bool(bool),
    Int(i64),
}

fn logic_operand(v: &Value, dates: DateSystem) -> XlResult<Logic> {
    match v {
        Value::Bool(b) => Ok(Logic::Bool(*b)),
        Value::Text(t) if t.eq_ignore_ascii_case("TRUE") || t.eq_ignore_ascii_case("FALSE") => {
            Ok(Logic::Bool(t.eq_ignore_ascii_case("TRUE")))
        }
        other => vba_integer(to_number(other, dates)?).map(Logic::Int),
    }
}

fn vba_logic(op: BinOp, a: &Value, b: &Value, dates: DateSystem) -> Value {
    let (a, b) = match (logic_operand(a, dates), logic_operand(b, dates)) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(e), _) | (_, Err(e)) => return Value::Error(e),
    };
    let bits = |l: Logic| match l {
        Logic::Bool(b) => -i64::from(b),
        Logic::Int(i) => i,
    };
    match (a, b) {
        (Logic::Bool(x), Logic::Bool(y)) => Value::Bool(match op {
            BinOp::And => x && y,
            BinOp::Or => x || y,
            BinOp::Xor => x != y,
            BinOp::Eqv => x == y,
            _ => !x || y,
        }),
        (a, b) => {
            let (x, y) = (bits(a), bits(b));
            Value::Number(match op {
                BinOp::And => x & y,
                BinOp::Or => x | y,
                BinOp::Xor => x ^ y,
                BinOp::Eqv => !(x ^ y),
                _ => !x | y,
            } as f64)
        }
    }
}

/// VBA's operators on Null ([MS-VBAL] 5.6.9, the Office VBA reference's operator pages):
/// arithmetic and comparisons give Null; `&` takes a lone Null as "" ("& operator"); `And`
/// and `Or` give what the other operand decides alone (`Null And False` is False, `Null Or
/// True` True, bit by bit for numbers), else Null; `Imp` is True from False or into True.
fn null_binary(op: BinOp, a: &Value, b: &Value, dates: DateSystem) -> Value {
    let other = if matches!(a, Value::Null) { b } else { a };
    let decided = |v: &Value, by: i64| match logic_operand(v, dates) {
        Ok(Logic::Bool(x)) => -i64::from(x) == by,
        Ok(Logic::Int(i)) => i == by,
        Err(_) => false,
    };
    match op {
        BinOp::Concat if matches!(other, Value::Null) => Value::Null,
        BinOp::Concat => scalar_binary(op, &Value::text(""), other, dates),
        BinOp::And if decided(other, 0) => other.clone(),
        BinOp::Or if decided(other, -1) => other.clone(),
        BinOp::Imp if matches!(a, Value::Null) && decided(b, -1) => b.clone(),
        BinOp::Imp if matches!(b, Value::Null) && decided(a, 0) => Value::Bool(true),
        _ => match other.as_error() {
            Some(e) => Value::Error(e),
            None => Value::Null,
        },
    }
}

fn vba_not(v: &Value, dates: DateSystem) -> Value {
    if let Value::Null = v {
        return Value::Null;
    }
    match logic_operand(v, dates) {
        Ok(Logic::Bool(b)) => Value::Bool(!b),
        Ok(Logic::Int(i)) => Value::Number(!i as f64),
        Err(e) => Value::Error(e),
    }
}

/// Excel's `^` and `POWER`: `0^0` and a negative base with a fractional exponent are `#NUM!`,
/// `0^-1` is `#DIV/0!`.
pub fn power(x: f64, y: f64) -> XlResult<f64> {
    if x == 0.0 && y == 0.0 {
        return Err(XlError::Num);
    }
    if x == 0.0 && y < 0.0 {
        return Err(XlError::Div0);
    }
    if x < 0.0 && y.fract() != 0.0 {
        return Err(XlError::Num);
    }
    // A square is one correctly rounded multiplication: powf's result or closer, much faster.
    let v = if y == 2.0 { x * x } else { x.powf(y) };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(XlError::Num)
    }
}
