//! The workbook: sheets of cells, defined names, the dependency graph and recalculation.
//!
//! Editing a cell marks only what depends on it and recomputes that in topological order
//! (see `recalc.rs`). Bad input never stops the rest: a formula that does not parse holds
//! `#NAME?` and is listed by [`Workbook::problems`]; a cycle's cells keep their previous
//! values (0 if none), as Excel's do, and the cycle is listed too.

use std::borrow::Cow;
use std::fmt;
use std::rc::Rc;

use crate::eval::coerce::parse_number;
use crate::eval::dates::DateSystem;
use crate::eval::functions::Registry;
use crate::eval::{Env, Note, RowHidden, UserCall, Value, XlError};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, Reference, SheetId};
use crate::formula::parse::{parse_formula, parse_name_formula, ParseContext, ParseError};
use crate::formula::print::{print_formula, quote_sheet_name};

mod cycles;
mod delete_sheet;
mod graph;
mod inspect;
mod links;
pub mod look;
mod problems;
mod recalc;
mod shared;
mod sheet;
mod shift;
mod tables;
mod tabs;
mod typed;
mod udf;

pub use cycles::Iteration;
pub use delete_sheet::DeletedSheet;
/// The fast hasher's map, for integer keys of our own making (the macro interpreter's notes).
pub(crate) use graph::FxMap;
use graph::{Deps, RangeIndex};
use links::for_each_pos;
pub use look::{Hyperlink, LooksByCell, SheetLook};
pub use problems::{Problem, ProblemKind};
use shared::{key_offset, relative_key_into, shape_of, text_offset, FormulaStore, SharedFormula};
use sheet::Sheet;
pub use sheet::Visibility;
pub use shift::{Axis, SheetEdit};
pub use udf::UserFunctions;

const NO_FORMULA: u32 = u32::MAX;

/// The most sheets a workbook holds: one for each [`SheetId`].
pub const MAX_SHEETS: usize = SheetId::MAX as usize + 1;

/// The most cells a workbook holds, every reader's (csv, xlsx, and through it xls, xlsb and
/// ods) and every edit's and spill's (docs/limits.md). A cell read from an xlsx costs about
/// 45 bytes, one read from a csv about 150 (its text kept field by field for a save), so a
/// workbook at the limit loads in 0.4 to 1.3 GiB (2^24 cells from a csv took 2.4 GiB).
/// Excel's sheet has room for 17 billion cells; its own limit is the machine's memory.
pub const MAX_CELLS: usize = 1 << 23;

/// One cell: its current value and, for a formula cell, which shared formula it runs.
struct Cell {
    value: Value,
    formula: u32,
    sheet: SheetId,
    pos: Pos,
    dependents: Deps,
}

/// What a user typed into a cell, as a spreadsheet reads it.
#[derive(Clone, Debug, PartialEq)]
pub enum Input {
    Empty,
    Value(Value),
    Formula(String),
}

impl Input {
    /// `=…` is a formula; numbers (`1,234.5`, `50%`), `TRUE`/`FALSE` and error literals are
    /// values; a leading `'` forces text; anything else is text.
    /// Date text is the serial of its date in `dates`, the workbook's date system.
    pub fn parse(text: &str, dates: DateSystem) -> Input {
        if text.is_empty() {
            return Input::Empty;
        }
        if text.len() > 1 && text.starts_with('=') {
            return Input::Formula(text.to_string());
        }
        if let Some(rest) = text.strip_prefix('\'') {
            return Input::Value(Value::text(rest));
        }
        if let Some(n) = parse_number(text, dates) {
            return Input::Value(Value::Number(n));
        }
        let t = text.trim();
        if t.eq_ignore_ascii_case("TRUE") || t.eq_ignore_ascii_case("FALSE") {
            return Input::Value(Value::Bool(t.eq_ignore_ascii_case("TRUE")));
        }
        if let Ok(e) = t.parse::<XlError>() {
            return Input::Value(Value::Error(e));
        }
        Input::Value(Value::text(text))
    }
}

/// A defined name: a formula (usually a reference) evaluated on its sheet.
#[derive(Clone, Debug)]
struct DefinedName {
    name: String,
    expr: Rc<Expr>,
    scope: Option<SheetId>,
}

/// Errors from workbook operations (not cell errors, which are values).
#[derive(Clone, Debug, PartialEq)]
pub enum WorkbookError {
    DuplicateSheet(String),
    NoSuchSheet(String),
    /// An insertion or deletion of cells that Excel refuses too, and why.
    CannotShift(String),
    BadName(String),
    /// A sheet more than a workbook can number (its ids are 16-bit).
    TooManySheets,
    /// A cell more than [`MAX_CELLS`]: the place of the first cell refused.
    TooManyCells(String),
    /// Deleting the named sheet would leave no visible sheet.
    LastVisibleSheet(String),
    /// A formula (of a cell or a name) that does not parse; `text` is what was typed.
    Parse {
        place: String,
        text: String,
        error: ParseError,
    },
}

impl fmt::Display for WorkbookError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorkbookError::DuplicateSheet(s) => write!(f, "a sheet named '{s}' exists already"),
            WorkbookError::NoSuchSheet(s) => write!(f, "no sheet named '{s}'"),
            WorkbookError::BadName(s) => write!(f, "'{s}' cannot be a defined name"),
            WorkbookError::CannotShift(why) => write!(f, "cannot insert or delete cells: {why}"),
            WorkbookError::TooManySheets => write!(f, "a workbook holds at most {} sheets", MAX_SHEETS),
            WorkbookError::TooManyCells(place) => write!(f, "{place}: {}", too_many_cells()),
            WorkbookError::LastVisibleSheet(s) => {
                write!(f, "sheet '{s}' is the last visible one, and a workbook must contain at least one visible sheet")
            }
            WorkbookError::Parse { place, text, error } => write!(f, "{place}: {}", error.render(text)),
        }
    }
}

impl std::error::Error for WorkbookError {}

/// What a reader meeting a cell text longer than Excel's 32,767 characters says (Excel's own
/// files never hold one: "Excel restricts the value of this element to 32767 characters",
/// [MS-OI29500] 2.1.706 on `<t>`). The file is refused rather than its text cut: cut, a save
/// would lose the rest. `units` is the text's length in UTF-16 units, as Excel counts; `None`
/// when the read stopped before the end of the text.
pub fn too_long_text(units: Option<usize>) -> String {
    let max = crate::eval::evaluator::MAX_TEXT;
    let length = units.map_or(String::new(), |n| format!(" of {n} characters"));
    format!(
        "a text{length} longer than the {max} characters a cell holds (Excel's limit); the file is refused, not cut"
    )
}

/// What a reader, an edit or a spill past [`MAX_CELLS`] is told.
pub fn too_many_cells() -> String {
    format!("a workbook holds at most {MAX_CELLS} cells, ncsheet's limit (docs/limits.md)")
}

#[derive(Default)]
pub struct Workbook {
    sheets: Vec<Sheet>,
    /// Sheet ids by ASCII-lowercased name: a workbook of 100,000 sheets finds one by name
    /// (adding a sheet, `Sheet7!A1`, INDIRECT) without reading every name.
    sheet_index: FxMap<String, SheetId>,
    /// The sheets' ids in tab order (`tabs.rs`): an id is fixed, a tab can move.
    tabs: tabs::Tabs,
    cells: Vec<Cell>,
    /// Ids of `cells` that hold no cell (a deleted sheet's, blank cells no formula links any
    /// more): a new cell takes one before `cells` grows, and [`MAX_CELLS`] counts without
    /// them. Ids are never renumbered: the graph, the spills and the change log hold them.
    free_cells: Vec<u32>,
    /// Blank cells a formula stopped linking ([`Workbook::remove_edge`]), given back at the
    /// next recalculation if nothing links them then (`links.rs`).
    unlinked_blanks: Vec<u32>,
    formulas: FormulaStore,
    ranges: RangeIndex,
    names: Vec<DefinedName>,
    /// Where each defined name is in `names`, by its key ([`name_key`]), once there are more
    /// than [`FEW_NAMES`]: 20,000 names took 49 s to read, each definition and each lookup
    /// reading them all. Built on first need; [`Workbook::define_name_tree_deferred`] keeps
    /// it, and every other change to `names` drops it ([`Workbook::forget_name_index`]).
    name_index: std::cell::RefCell<Option<FxMap<NameKey, usize>>>,
    /// Formula text that did not parse, by cell id, with the error.
    bad_inputs: FxMap<u32, (String, ParseError)>,
    /// Of `bad_inputs`, the cells that show the value their file cached instead of `#NAME?`
    /// ([`Workbook::keep_formula_value_deferred`]).
    kept_values: FxMap<u32, ()>,
    /// Messages functions left explaining a cell's error value.
    notes: FxMap<u32, Vec<Note>>,
    /// Cells whose notes the last recalculation changed (what an edit has to report).
    fresh_notes: Vec<u32>,
    spill: recalc::SpillState,
    /// Cells of each circular reference found by the last recalculation.
    cycles: recalc::Cycles,
    /// Formula cells calling a volatile function (NOW, TODAY), recalculated at every edit.
    volatile: recalc::VolatileCells,
    /// References formula cells made at run time (INDIRECT, OFFSET), linked in the graph.
    dynamic_refs: FxMap<u32, Vec<(SheetId, Rect)>>,
    scratch: recalc::Scratch,
    /// Reused buffers: the relative key of the formula being stored, a formula's precedents.
    key_buf: Vec<u8>,
    precedents_buf: Vec<(SheetId, Rect)>,
    /// The formula being stored: where its number literals are in its key, its shape, their values.
    literal_spans: Vec<(usize, usize)>,
    shape_buf: Vec<u8>,
    literals: Vec<f64>,
    /// The 1904 date system (`dates.rs`): serial 0 is 1904-01-01.
    date_1904: bool,
    /// The language of the Excel that saved the file, when not English ([`Env::excel_language`]).
    excel_language: Option<&'static str>,
    /// Legacy (Ctrl+Shift+Enter) array formulas: anchor cell → rows and columns of the area
    /// their result is fitted to (a spill of fixed size).
    fixed_arrays: FxMap<u32, (u32, u32)>,
    /// What changed since [`Workbook::track_changes`], for a file saved back surgically.
    changes: Option<Box<ChangeLog>>,
    /// The inputs cells held before their first edit since [`Workbook::start_journal`]: what
    /// an undo of a macro's writes types back.
    journal: Option<Box<Journal>>,
    /// Iterative calculation (`cycles.rs`): cycles iterate instead of keeping their values.
    iteration: Option<Iteration>,
    /// Cycles whose iteration the work budget stopped early, by their first cell (`cycles.rs`).
    iteration_cuts: FxMap<u32, cycles::IterationCut>,
    /// Names were (re)defined without relinking the graph: the next full recalculation does.
    names_unlinked: bool,
    /// The workbook's own functions (its VBA Functions), once installed (`udf.rs`).
    user_functions: Option<Rc<dyn UserFunctions>>,
    /// The tables (ListObjects) of the workbook, in its file's order (`tables.rs`).
    table_list: Vec<TableShape>,
    /// The pivot tables of the file it was read from, which GETPIVOTDATA reads.
    pivot_tables: Option<Rc<dyn PivotTables>>,
    /// The clock and random sequence this workbook's formulas read (its own, never a thread's).
    settings: crate::eval::Settings,
    /// The sheet shown when the workbook opens (`<workbookView activeTab>`): VBA's
    /// ActiveSheet and the sheet commands read when none is named.
    active_sheet: SheetId,
}

/// Cell ids whose input was set, and whose value changed, since tracking began.
#[derive(Default)]
struct ChangeLog {
    /// A bit per cell id: an insertion moving a million cells notes each a turn (a hashed
    /// set of ids took two thirds of `Columns(1).Insert` before a full column).
    inputs: CellBits,
    /// Of `inputs`, those that held a formula when first edited.
    had_formula: std::collections::HashSet<u32>,
    /// Cells whose value changed: every cell an edit recomputes is noted here, a million in
    /// a long chain, so a bit per cell id rather than a hash set.
    values: CellBits,
    names: bool,
    sheets: bool,
    /// Cells were inserted or deleted ([`Workbook::shift_cells`]).
    shifted: bool,
    /// A table was added, deleted, moved or resized (`tables.rs`).
    tables: bool,
}

/// Cells edited since [`Workbook::start_journal`], each with the input it held before.
#[derive(Default)]
struct Journal {
    /// The places written down: a cell an insertion reuses elsewhere (`shift.rs`) is written
    /// down again at its new place.
    seen: std::collections::HashSet<(SheetId, Pos)>,
    before: Vec<(SheetId, Pos, String)>,
    /// The sheets deleted, with what an undo needs to bring each back (`delete_sheet.rs`).
    deleted: Vec<delete_sheet::DeletedSheet>,
}

/// A set of cell ids, a bit each.
#[derive(Default)]
struct CellBits(Vec<u64>);

impl CellBits {
    /// Adds `id`; whether it was not in the set before.
    fn insert(&mut self, id: u32) -> bool {
        let (word, bit) = (id as usize / 64, id % 64);
        if word >= self.0.len() {
            self.0.resize(word + 1, 0);
        }
        let fresh = self.0[word] & (1 << bit) == 0;
        self.0[word] |= 1 << bit;
        fresh
    }

    fn remove(&mut self, id: u32) {
        if let Some(word) = self.0.get_mut(id as usize / 64) {
            *word &= !(1 << (id % 64));
        }
    }

    fn contains(&self, id: u32) -> bool {
        self.0.get(id as usize / 64).is_some_and(|word| word & (1 << (id % 64)) != 0)
    }

    fn ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.0
            .iter()
            .enumerate()
            .flat_map(|(w, &bits)| (0..64).filter(move |b| bits & (1 << b) != 0).map(move |b| (w * 64 + b) as u32))
    }
}

/// What changed in a workbook since [`Workbook::track_changes`], in sheet and row order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Changes {
    /// Cells whose input (formula or constant) was set, even to the same thing.
    pub inputs: Vec<(SheetId, Pos)>,
    /// Cells whose value differs from what it was (recalculation included).
    pub values: Vec<(SheetId, Pos)>,
    /// A defined name was defined or redefined.
    pub names: bool,
    /// A sheet was added or renamed.
    pub sheets: bool,
    /// Rows, columns or cells were inserted or deleted: whatever the file keeps by position
    /// (styles, widths, heights, hidden rows) has to move with them.
    pub shifted: bool,
    /// A table was added, deleted, moved or resized: a saved file writes its tables anew.
    pub tables: bool,
    /// Cells that held a formula before their edit and now hold a constant.
    pub formulas_replaced: Vec<(SheetId, Pos)>,
}

impl Workbook {
    pub fn new() -> Workbook {
        Workbook::default()
    }

    /// A workbook with one sheet named `Sheet1`.
    pub fn with_sheet() -> Workbook {
        let mut wb = Workbook::new();
        wb.add_sheet("Sheet1").expect("first sheet");
        wb
    }

    pub fn add_sheet(&mut self, name: &str) -> Result<SheetId, WorkbookError> {
        if self.sheet_id(name).is_some() {
            return Err(WorkbookError::DuplicateSheet(name.to_string()));
        }
        if self.sheets.len() >= MAX_SHEETS {
            return Err(WorkbookError::TooManySheets);
        }
        self.sheets.push(Sheet::new(name));
        self.sheet_index.insert(name.to_ascii_lowercase(), (self.sheets.len() - 1) as SheetId);
        self.tabs.order.push((self.sheets.len() - 1) as SheetId);
        if let Some(log) = &mut self.changes {
            log.sheets = true;
        }
        // References to this name parsed before it existed are stale now.
        self.formulas.forget_keys();
        Ok((self.sheets.len() - 1) as SheetId)
    }

    /// Renames `sheet` (Excel's `Worksheet.Name =`). Formulas point at sheets by index, so
    /// they show the new name; a name another sheet has is refused, in any case.
    pub fn rename_sheet(&mut self, sheet: SheetId, name: &str) -> Result<(), WorkbookError> {
        let Some(old) = self.sheets.get(sheet as usize).map(|s| s.name.to_ascii_lowercase()) else {
            return Err(WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)));
        };
        if self.sheet_id(name).is_some_and(|other| other != sheet) {
            return Err(WorkbookError::DuplicateSheet(name.to_string()));
        }
        self.sheet_index.remove(&old);
        self.sheet_index.insert(name.to_ascii_lowercase(), sheet);
        self.sheets[sheet as usize].name = name.to_string();
        if let Some(log) = &mut self.changes {
            log.sheets = true;
        }
        // Formula texts parsed with the old name (or the new one, missing then) read anew.
        self.formulas.forget_keys();
        Ok(())
    }

    /// Switches the date system (serial 0 is 1904-01-01 when on) and recalculates, since
    /// every date function's result depends on it.
    pub fn set_date_1904(&mut self, on: bool) {
        if self.date_1904 != on {
            self.date_1904 = on;
            self.recalculate();
        }
    }

    pub fn date_1904(&self) -> bool {
        self.date_1904
    }

    /// Sets the language of the Excel that saved the file (`fr`; `None`: English), in which
    /// CELL reads its info_type too, and recalculates when it changes.
    pub fn set_excel_language(&mut self, language: Option<&'static str>) {
        if self.excel_language != language {
            self.excel_language = language;
            self.recalculate();
        }
    }

    /// The day the workbook's serials count from, which every date conversion takes.
    pub fn date_system(&self) -> DateSystem {
        DateSystem::from_1904_flag(self.date_1904)
    }

    /// The clock and random sequence the formulas read.
    pub fn settings(&self) -> &crate::eval::Settings {
        &self.settings
    }

    /// Changes the clock or the random sequence; the cells that read them are recomputed at
    /// the next recalculation (they are volatile).
    pub fn settings_mut(&mut self) -> &mut crate::eval::Settings {
        &mut self.settings
    }

    /// The active sheet, the one a file opens on (the first unless the file says another).
    pub fn active_sheet(&self) -> SheetId {
        if (self.active_sheet as usize) < self.sheets.len() {
            self.active_sheet
        } else {
            0
        }
    }

    /// Makes `sheet` the active one; a sheet the workbook does not have is ignored.
    pub fn set_active_sheet(&mut self, sheet: SheetId) {
        if (sheet as usize) < self.sheets.len() {
            self.active_sheet = sheet;
        }
    }

    /// Whether `sheet`'s tab shows.
    pub fn sheet_visibility(&self, sheet: SheetId) -> Visibility {
        self.sheets.get(sheet as usize).map_or(Visibility::Visible, |s| s.visibility)
    }

    /// Shows or hides `sheet`'s tab (no value depends on it).
    pub fn set_sheet_visibility(&mut self, sheet: SheetId, visibility: Visibility) {
        if let Some(s) = self.sheets.get_mut(sheet as usize) {
            s.visibility = visibility;
        }
    }

    /// The hidden rows of `sheet`, in order, and how each is hidden.
    pub fn hidden_rows(&self, sheet: SheetId) -> Vec<(u32, RowHidden)> {
        self.sheets.get(sheet as usize).map(|s| s.hidden_rows().collect()).unwrap_or_default()
    }

    /// Sets the width in characters (as Excel shows it) of columns `first..=last` of `sheet`,
    /// or with `span` `None` of its other columns; CELL("width") reads it at the next
    /// recalculation.
    pub fn set_column_width(&mut self, sheet: SheetId, span: Option<(u32, u32)>, width: f64) {
        if let Some(s) = self.sheets.get_mut(sheet as usize) {
            s.set_column_width(span, width);
        }
    }

    /// Hides row `row` of `sheet` (`None` shows it), without recalculating: SUBTOTAL and
    /// AGGREGATE read it at the next recalculation.
    pub fn set_row_hidden(&mut self, sheet: SheetId, row: u32, hidden: Option<RowHidden>) {
        if let Some(s) = self.sheets.get_mut(sheet as usize) {
            s.set_row_hidden(row, hidden);
        }
    }

    /// Makes the formula in `area`'s top-left cell a legacy (Ctrl+Shift+Enter) array formula
    /// over `area`, without recalculating: its result always fills exactly the area, as
    /// Excel fits it (a scalar or a single row or column repeated, missing items `#N/A`,
    /// the rest cut off). A one-cell area shows the result's top-left item.
    pub fn set_array_area_deferred(&mut self, sheet: SheetId, area: Rect) {
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(area.first)) else { return };
        if self.cells[id as usize].formula != NO_FORMULA {
            self.fixed_arrays.insert(id, (area.rows(), area.cols()));
        }
    }

    /// The area of the legacy array formula anchored at `pos`, if it is one.
    pub fn array_area(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        let &(rows, cols) = self.fixed_arrays.get(&id)?;
        Some(Rect::new(pos, Pos::new(pos.row + rows - 1, pos.col + cols - 1)))
    }

    /// The rectangle the array result of the formula at `pos` spills over, or would spill
    /// over where it was refused (`#SPILL!`, or `#CIRC!` for reading its own spill range).
    pub fn spill_wanted(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        self.spill.wanted(id)
    }

    /// The formula cells whose array result spilled, or shows `#SPILL!`, in sheet and row
    /// order.
    pub fn spilling_cells(&self) -> Vec<(SheetId, Pos)> {
        let mut out: Vec<(SheetId, Pos)> =
            self.spill.anchors().map(|id| (self.cells[id as usize].sheet, self.cells[id as usize].pos)).collect();
        out.sort_by_key(|&(s, p)| (s, p.row, p.col));
        out
    }

    pub fn sheet_id(&self, name: &str) -> Option<SheetId> {
        self.sheet_index.get(&name.to_ascii_lowercase()).copied()
    }

    pub fn sheet_names(&self) -> Vec<String> {
        self.sheets.iter().map(|s| s.name.clone()).collect()
    }

    /// How many sheet ids the workbook has given: ids run from 0 to this, a deleted sheet's
    /// among them ([`Workbook::sheet_deleted`]); [`Workbook::sheet_count`] counts the sheets.
    pub fn sheet_len(&self) -> usize {
        self.sheets.len()
    }

    /// `Sheet1!B3`, quoted as Excel would.
    pub fn cell_name(&self, sheet: SheetId, pos: Pos) -> String {
        format!("{}!{pos}", quote_sheet_name(&self.sheets[sheet as usize].name))
    }

    /// Sets a cell from what a user typed and recalculates what depends on it; returns the
    /// problems the edit brought (the cell's unknown functions, names and sheets, new circular
    /// references, new notes). A formula that does not parse is refused and the cell left as
    /// it was.
    pub fn set_input(&mut self, sheet: SheetId, pos: Pos, text: &str) -> Result<Vec<Problem>, Problem> {
        if self.room_for(sheet, pos).is_err() {
            let kind = ProblemKind::Parse(too_many_cells());
            return Err(Problem { sheet, pos, kind, text: text.to_string(), span: None });
        }
        if is_formula_text(text) {
            let fid = self.shared_formula(text, sheet, pos).map_err(|e| Problem::parse(sheet, pos, text, &e))?;
            let id = self.cleared_cell(sheet, pos);
            self.install_formula(id, fid);
        } else {
            let stored = self.set_input_deferred(sheet, pos, text);
            debug_assert!(stored.is_ok(), "only a formula can fail");
        }
        let problems = self.recalculate_edit(sheet, pos);
        self.follow_header_edits(sheet, Rect::new(pos, pos));
        Ok(problems)
    }

    /// Sets a cell to a formula given as a tree (as if typed at `pos`) and recalculates.
    pub fn set_formula_tree(&mut self, sheet: SheetId, pos: Pos, tree: Expr) -> Vec<Problem> {
        self.set_formula_tree_deferred(sheet, pos, tree);
        self.recalculate_edit(sheet, pos)
    }

    /// Recalculates after an edit of one cell and lists the problems it brought.
    fn recalculate_edit(&mut self, sheet: SheetId, pos: Pos) -> Vec<Problem> {
        let id = self.sheets[sheet as usize].get(pos);
        self.recalculate_from(id.into_iter().collect());
        let mut news = self.unknowns(sheet, pos);
        for cycle in self.cycles.new_since_begin() {
            news.push(self.cycle_problem(cycle));
        }
        for &noted in &self.fresh_notes {
            news.extend(self.note_problems(noted));
        }
        problems::sort_by_place(&mut news);
        news
    }

    /// Recalculates after [`Workbook::set_input_deferred`] of the cells of `rect` only: what
    /// depends on them (and the volatile cells), not every formula, so that a macro filling
    /// a column one cell at a time stays linear. A table's header cell among them names its
    /// column ([`Workbook::follow_header_edits`]).
    pub fn recalculate_rect(&mut self, sheet: SheetId, rect: Rect) {
        let mut changed = Vec::new();
        if rect.rows() as u64 * rect.cols() as u64 <= self.cells.len() as u64 {
            for_each_pos(rect, |pos| changed.extend(self.sheets[sheet as usize].get(pos)));
        } else {
            changed.extend((0..self.cells.len() as u32).filter(|&id| {
                let c = &self.cells[id as usize];
                // A freed cell keeps the place it left, where no cell is now.
                c.sheet == sheet && rect.contains(c.pos) && self.sheets[sheet as usize].get(c.pos) == Some(id)
            }));
        }
        self.recalculate_from(changed);
        self.follow_header_edits(sheet, rect);
    }

    /// Sets a cell without recalculating; call [`Workbook::recalculate`] after a batch.
    pub fn set_input_deferred(&mut self, sheet: SheetId, pos: Pos, text: &str) -> Result<(), WorkbookError> {
        self.room_for(sheet, pos)?;
        // A formula (what `Input::parse` reads as one) without copying its text.
        if is_formula_text(text) {
            return self.set_formula(sheet, pos, text);
        }
        // A plain decimal number (`12`, `-0.5`), read as `Input::parse` reads it but sooner.
        let digits = text.strip_prefix('-').unwrap_or(text);
        if digits.bytes().any(|b| b.is_ascii_digit()) && digits.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
            if let Ok(n) = text.parse::<f64>() {
                if n.is_finite() {
                    // As a computed number: `-0` and subnormals (`0.000…1`) are 0, as Excel
                    // keeps neither (Input::parse's rule for the rest).
                    self.set_constant(sheet, pos, crate::eval::evaluator::number_result(n));
                    return Ok(());
                }
            }
        }
        match Input::parse(text, self.date_system()) {
            Input::Empty => {
                self.set_constant(sheet, pos, Value::Blank);
                Ok(())
            }
            Input::Value(v) => {
                self.set_constant(sheet, pos, v);
                Ok(())
            }
            Input::Formula(f) => self.set_formula(sheet, pos, &f),
        }
    }

    /// Whether the workbook has room for a cell at `pos`: it has one there already, or it holds
    /// fewer than [`MAX_CELLS`]. Every path that makes cells asks it or
    /// [`Workbook::room_for_all`] first (the readers, a macro's writes, pastes and sorts;
    /// [`Workbook::set_input_deferred`] and [`Workbook::set_input`] ask themselves); a
    /// formula's links make blank cells only while there is room (`links.rs`), a spill asks
    /// before it spills, and an insertion or deletion reuses the cells it empties (`shift.rs`).
    pub fn room_for(&self, sheet: SheetId, pos: Pos) -> Result<(), WorkbookError> {
        self.room_after(sheet, pos, 0)
    }

    /// [`Workbook::room_for`] of every place of `places` on `sheet` (distinct places, in the
    /// order they are to be written), asked before the first is written, so that an edit
    /// past the limit is refused whole: the error names the first place with no room.
    pub fn room_for_all(&self, sheet: SheetId, places: impl IntoIterator<Item = Pos>) -> Result<(), WorkbookError> {
        let mut count = self.cell_count();
        for pos in places {
            if self.sheets[sheet as usize].get(pos).is_some() {
                continue;
            }
            if count >= MAX_CELLS {
                return Err(WorkbookError::TooManyCells(self.cell_name(sheet, pos)));
            }
            count += 1;
        }
        Ok(())
    }

    /// [`Workbook::room_for_all`] of every cell of `rect`, row by row (a formula filled over
    /// it): quick when the workbook has room for the whole rectangle.
    pub fn room_for_rect(&self, sheet: SheetId, rect: Rect) -> Result<(), WorkbookError> {
        self.room_for_filled(sheet, rect, |_| true)
    }

    /// [`Workbook::room_for_all`] of the places of `rect`, row by row, that an edit writes
    /// something into (`filled`: a blank written where no cell is makes none), asked before
    /// the first is written: a macro's `.Value =` of an array, a paste, a sort. Quick, and
    /// asking `filled` nothing, when the workbook has room for the whole rectangle.
    pub fn room_for_filled(
        &self,
        sheet: SheetId,
        rect: Rect,
        filled: impl Fn(Pos) -> bool,
    ) -> Result<(), WorkbookError> {
        if self.cell_count() as u64 + rect.rows() as u64 * rect.cols() as u64 <= MAX_CELLS as u64 {
            return Ok(());
        }
        let rows = rect.first.row..=rect.last.row;
        let places = rows.flat_map(|row| (rect.first.col..=rect.last.col).map(move |col| Pos::new(row, col)));
        self.room_for_all(sheet, places.filter(|&pos| filled(pos)))
    }

    /// [`Workbook::room_for`] when `waiting` more cells are to be made later (a reader's
    /// copies of a shared formula whose text comes further on).
    pub fn room_after(&self, sheet: SheetId, pos: Pos, waiting: usize) -> Result<(), WorkbookError> {
        if self.cell_count() + waiting < MAX_CELLS || self.sheets[sheet as usize].get(pos).is_some() {
            return Ok(());
        }
        Err(WorkbookError::TooManyCells(self.cell_name(sheet, pos)))
    }

    /// The cells the workbook holds (blank ones a formula links to among them; not those of
    /// a deleted sheet, nor blank ones nothing links any more): what [`MAX_CELLS`] bounds.
    pub fn cell_count(&self) -> usize {
        self.cells.len() - self.free_cells.len()
    }

    /// Sets a cell to a formula given as a tree (as if typed at `pos`) without recalculating
    /// (a file reader's path for a formula it rewrote as a tree); call
    /// [`Workbook::recalculate`] after a batch.
    pub fn set_formula_tree_deferred(&mut self, sheet: SheetId, pos: Pos, tree: Expr) {
        let fid = self.formulas.add(None, SharedFormula::new(tree));
        let id = self.cleared_cell(sheet, pos);
        self.install_formula(id, fid);
    }

    /// Fills every cell of `rect` with one formula tree (its relative references move along,
    /// as Excel's fill moves them), the cells sharing the tree, without recalculating.
    pub fn fill_formula_tree_deferred(&mut self, sheet: SheetId, rect: Rect, tree: Expr) {
        let fid = self.formulas.add(None, SharedFormula::new(tree));
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                let id = self.cleared_cell(sheet, Pos::new(row, col));
                self.install_formula(id, fid);
            }
        }
    }

    /// Sets a constant value without recalculating (a file reader's path: no text round trip,
    /// so text that looks like a number or a formula stays text). Arrays are not cell values
    /// and are stored as their first item.
    pub fn set_value_deferred(&mut self, sheet: SheetId, pos: Pos, value: Value) {
        let value = match value {
            Value::Array(a) => a.data.first().cloned().unwrap_or(Value::Blank),
            v => v,
        };
        self.set_constant(sheet, pos, value)
    }

    fn set_constant(&mut self, sheet: SheetId, pos: Pos, value: Value) {
        let id = match self.sheets[sheet as usize].get(pos) {
            Some(id) => id,
            None if value.is_blank() => return,
            None => self.cell_at(sheet, pos),
        };
        let blank = value.is_blank();
        self.note_input(id);
        self.take_spilled_cell(id);
        self.clear_formula(id);
        self.store_value(id, value);
        if blank && self.cells[id as usize].dependents.as_slice().is_empty() {
            // Emptied and read by no formula: no cell, as in Excel (`reclaim_unlinked_blanks`).
            self.unlinked_blanks.push(id);
        }
    }

    /// Starts remembering which cells are edited and which change value (forgetting what
    /// was remembered before): a file reader calls it once the file is loaded.
    pub fn track_changes(&mut self) {
        self.changes = Some(Box::default());
    }

    /// Counts the values of `cells` as changed since [`Workbook::track_changes`]: the file
    /// they were read from holds no value for them (a formula whose result a generator left
    /// out), so a save must write the value they have now. An array formula's anchor brings
    /// every cell of its area: the file holds nothing for the cells past the anchor either
    /// (openpyxl writes `<f t="array" ref="B1:B3">` and no B2, B3), and Excel's save writes
    /// each cell's value.
    pub fn note_unsaved_values(&mut self, cells: &[(SheetId, Pos)]) {
        let Some(log) = &mut self.changes else { return };
        for &(sheet, pos) in cells {
            let Some(grid) = self.sheets.get(sheet as usize) else { continue };
            let Some(id) = grid.get(pos) else { continue };
            log.values.insert(id);
            if let Some(area) = self.spill.rect(id) {
                grid.for_each_in(area, &mut |_, cid| {
                    log.values.insert(cid);
                });
            }
        }
    }

    /// What changed since [`Workbook::track_changes`]; `None` when it was never called.
    pub fn changes(&self) -> Option<Changes> {
        let log = self.changes.as_ref()?;
        let cells = |ids: &mut dyn Iterator<Item = u32>| {
            let mut v: Vec<(SheetId, Pos)> =
                ids.map(|id| (self.cells[id as usize].sheet, self.cells[id as usize].pos)).collect();
            v.sort_by_key(|&(s, p)| (s, p.row, p.col));
            v
        };
        let mut formulas_replaced = cells(&mut log.had_formula.iter().copied());
        formulas_replaced.retain(|&(sheet, pos)| !self.is_formula(sheet, pos));
        Some(Changes {
            inputs: cells(&mut log.inputs.ids()),
            values: cells(&mut log.values.ids()),
            names: log.names,
            sheets: log.sheets,
            shifted: log.shifted,
            tables: log.tables,
            formulas_replaced,
        })
    }

    /// Starts writing down the input each cell held before its first edit (forgetting what
    /// was written before): a macro's writes, taken back together by an undo.
    pub fn start_journal(&mut self) {
        self.journal = Some(Box::default());
    }

    /// The cells edited since [`Workbook::start_journal`], in the order of their first edit,
    /// each with the input it held before (empty: the cell was blank); stops the journal.
    pub fn take_journal(&mut self) -> Vec<(SheetId, Pos, String)> {
        self.journal.take().map_or(Vec::new(), |j| j.before)
    }

    fn note_input(&mut self, id: u32) {
        self.journal_input(id);
        let had_formula = self.cells[id as usize].formula != NO_FORMULA;
        if let Some(log) = &mut self.changes {
            if log.inputs.insert(id) && had_formula {
                log.had_formula.insert(id);
            }
        }
    }

    /// Writes down the input of cell `id` before its first edit, when a journal is kept.
    fn journal_input(&mut self, id: u32) {
        let Some(journal) = &self.journal else { return };
        let (sheet, pos) = (self.cells[id as usize].sheet, self.cells[id as usize].pos);
        if journal.seen.contains(&(sheet, pos)) {
            return;
        }
        let before = self.input(sheet, pos).unwrap_or_default();
        if let Some(journal) = &mut self.journal {
            journal.seen.insert((sheet, pos));
            journal.before.push((sheet, pos, before));
        }
    }

    /// Stores a formula; one that does not parse is stored as `#NAME?` with its text.
    fn set_formula(&mut self, sheet: SheetId, pos: Pos, text: &str) -> Result<(), WorkbookError> {
        let parsed = self.shared_formula(text, sheet, pos);
        let id = self.cleared_cell(sheet, pos);
        match parsed {
            Ok(fid) => {
                self.install_formula(id, fid);
                Ok(())
            }
            Err(error) => {
                self.store_value(id, Value::Error(XlError::Name));
                self.bad_inputs.insert(id, (text.to_string(), error.clone()));
                Err(WorkbookError::Parse { place: self.cell_name(sheet, pos), text: text.to_string(), error })
            }
        }
    }

    /// Keeps formula text that ncsheet does not compute, the cell showing `value`, the value
    /// the file cached, without recalculating: a formula that does not parse (Excel, meeting
    /// one it cannot read, repairs the file by dropping the formula and keeping the value),
    /// or one calling what only the machine that saved the file has (an add-in's function).
    /// `why` says what [`Workbook::problems`] reports; the text is kept for saving.
    pub fn keep_formula_value_deferred(&mut self, sheet: SheetId, pos: Pos, text: &str, why: ParseError, value: Value) {
        let value = match value {
            Value::Array(a) => a.data.first().cloned().unwrap_or(Value::Blank),
            v => v,
        };
        let id = self.cleared_cell(sheet, pos);
        self.store_value(id, value);
        let why = ParseError { message: format!("{}; the cell keeps the value the file cached", why.message), ..why };
        self.bad_inputs.insert(id, (text.to_string(), why));
        self.kept_values.insert(id, ());
    }

    /// Whether the cell holds formula text ncsheet does not compute and shows the value its
    /// file cached ([`Workbook::keep_formula_value_deferred`]).
    pub fn keeps_file_value(&self, sheet: SheetId, pos: Pos) -> bool {
        !self.kept_values.is_empty()
            && self
                .sheets
                .get(sheet as usize)
                .and_then(|s| s.get(pos))
                .is_some_and(|id| self.kept_values.contains_key(&id))
    }

    /// The cell at `pos`, noted as edited, with no formula, spill or value of its own left.
    fn cleared_cell(&mut self, sheet: SheetId, pos: Pos) -> u32 {
        let id = self.cell_at(sheet, pos);
        self.note_input(id);
        self.take_spilled_cell(id);
        self.clear_formula(id);
        id
    }

    /// Makes cell `id` (cleared) run formula `fid`. A new formula has no last calculated
    /// value: in a circular reference it shows 0 (`recalc.rs`), not what the cell held.
    fn install_formula(&mut self, id: u32, fid: u32) {
        self.cells[id as usize].formula = fid;
        self.cells[id as usize].value = Value::Blank;
        self.link(id);
        if self.formulas.get(fid).volatile
            || (self.user_functions.is_some() && self.calls_user_function(&self.formulas.get(fid).expr) == Some(true))
        {
            self.volatile.insert(id);
        }
    }

    /// The shared parsed form of `text` typed at `pos`, parsing only when no copy exists.
    fn shared_formula(&mut self, text: &str, sheet: SheetId, pos: Pos) -> Result<u32, ParseError> {
        let mut key = std::mem::take(&mut self.key_buf);
        let mut spans = std::mem::take(&mut self.literal_spans);
        let keyed = relative_key_into(text, pos, &mut key, &mut spans);
        let found = if keyed { self.formulas.find(&key) } else { None };
        let failed = if keyed && found.is_none() { self.formulas.failure(&key) } else { None };
        let result = match (found, failed) {
            (Some(id), _) => Ok(id),
            (None, Some(e)) => Err(ParseError { offset: text_offset(text, pos, e.offset), message: e.message.clone() }),
            (None, None) if keyed => self.shaped_formula(text, sheet, pos, &key, &spans).inspect_err(|e| {
                let at_key = ParseError { offset: key_offset(text, pos, e.offset), message: e.message.clone() };
                self.formulas.add_failure(&key, at_key);
            }),
            (None, None) => {
                self.parse_at(text, sheet, pos).map(|expr| self.formulas.add(None, SharedFormula::new(expr)))
            }
        };
        self.key_buf = key;
        self.literal_spans = spans;
        result
    }

    /// A formula whose exact key is new: a copy of one of the same shape with its numbers,
    /// or else parsed (and then offered as the pattern of its shape).
    fn shaped_formula(
        &mut self,
        text: &str,
        sheet: SheetId,
        pos: Pos,
        key: &[u8],
        spans: &[(usize, usize)],
    ) -> Result<u32, ParseError> {
        let mut shape = std::mem::take(&mut self.shape_buf);
        let mut literals = std::mem::take(&mut self.literals);
        let shaped = !spans.is_empty() && shape_of(key, spans, &mut shape, &mut literals);
        let pattern = if shaped { self.formulas.find_shape(&shape) } else { None };
        let result = match pattern {
            Some(p) => {
                let formula = SharedFormula::with_literals(self.formulas.get(p), &literals);
                Ok(self.formulas.add(Some(key.to_vec()), formula))
            }
            None => self.parse_at(text, sheet, pos).map(|expr| {
                let id = self.formulas.add(Some(key.to_vec()), SharedFormula::new(expr));
                if shaped {
                    self.formulas.add_shape(&shape, id, &literals);
                }
                id
            }),
        };
        self.shape_buf = shape;
        self.literals = literals;
        result
    }

    /// Parses formula text as if typed in `pos` (used by the macro language too).
    /// A structured reference without its table's name (`[@Qty]`) names the table holding
    /// `pos` ([`Workbook::name_own_table`]).
    pub fn parse_at(&self, text: &str, sheet: SheetId, pos: Pos) -> Result<Expr, ParseError> {
        let sheets = |name: &str| self.sheet_id(name);
        let mut tree = parse_formula(text, &ParseContext { at: pos, functions: &Registry, sheet: &sheets })?;
        self.name_own_table(&mut tree, sheet, pos)?;
        Ok(tree)
    }

    /// Defines (or redefines) a name, workbook-wide or for one sheet. References in it are
    /// read as from cell A1 of its sheet, so write them absolute (`$B$3`) as Excel stores them.
    pub fn define_name(&mut self, name: &str, formula: &str, scope: Option<SheetId>) -> Result<(), WorkbookError> {
        self.define_name_deferred(name, formula, scope)?;
        self.recalculate();
        Ok(())
    }

    /// [`Workbook::define_name`] of a formula given as a tree (read as from A1 of its sheet).
    pub fn define_name_tree(&mut self, name: &str, expr: Expr, scope: Option<SheetId>) -> Result<(), WorkbookError> {
        self.define_name_tree_deferred(name, expr, scope)?;
        self.recalculate();
        Ok(())
    }

    /// [`Workbook::define_name`] without recalculating (a file reader defining names in bulk);
    /// call [`Workbook::recalculate`] after the batch, which relinks the cells reading names.
    pub fn define_name_deferred(
        &mut self,
        name: &str,
        formula: &str,
        scope: Option<SheetId>,
    ) -> Result<(), WorkbookError> {
        check_name(name)?;
        let sheets = |name: &str| self.sheet_id(name);
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &sheets };
        let expr = parse_name_formula(formula, &ctx).map_err(|error| WorkbookError::Parse {
            place: format!("name {name}"),
            text: formula.to_string(),
            error,
        })?;
        self.define_name_tree_deferred(name, expr, scope)
    }

    /// [`Workbook::define_name_tree`] without recalculating; call [`Workbook::recalculate`]
    /// after the batch.
    pub fn define_name_tree_deferred(
        &mut self,
        name: &str,
        expr: Expr,
        scope: Option<SheetId>,
    ) -> Result<(), WorkbookError> {
        check_name(name)?;
        if let Some(at) = self.name_position(name, scope) {
            // Defined again: the name moves to the end, and those after it move up.
            self.names.remove(at);
            self.forget_name_index();
        }
        self.names.push(DefinedName { name: name.to_string(), expr: Rc::new(expr), scope });
        if let Some(index) = self.name_index.get_mut() {
            index.insert(name_key(name, scope), self.names.len() - 1);
        }
        if let Some(log) = &mut self.changes {
            log.names = true;
        }
        // Cells linked before this name need linking again; a reader defining names before
        // any cell (the xlsx importer) has none.
        self.names_unlinked |= !self.cells.is_empty();
        Ok(())
    }

    /// Where the name `name` of `scope` is in `names`: read one by one when there are few,
    /// else looked up in the index, built on first need.
    fn name_position(&self, name: &str, scope: Option<SheetId>) -> Option<usize> {
        if self.names.len() <= FEW_NAMES {
            return self.names.iter().position(|n| n.scope == scope && same_name(&n.name, name));
        }
        let mut index = self.name_index.borrow_mut();
        let index = index.get_or_insert_with(|| {
            self.names.iter().enumerate().map(|(at, n)| (name_key(&n.name, n.scope), at)).collect()
        });
        index.get(&name_key(name, scope)).copied()
    }

    /// Drops the index of the defined names, after a change to `names` that does not keep it.
    fn forget_name_index(&mut self) {
        *self.name_index.get_mut() = None;
    }

    /// Defined names as trees (read as from A1 of their sheet): (name, formula, scope sheet).
    pub fn name_trees(&self) -> Vec<(String, Rc<Expr>, Option<SheetId>)> {
        self.names.iter().map(|n| (n.name.clone(), n.expr.clone(), n.scope)).collect()
    }

    /// Defined names: (name, formula text, scope sheet).
    pub fn names(&self) -> Vec<(String, String, Option<SheetId>)> {
        self.names
            .iter()
            .map(|n| (n.name.clone(), format!("={}", self.print(&n.expr, Pos::new(0, 0))), n.scope))
            .collect()
    }

    /// The value a cell shows.
    pub fn value(&self, sheet: SheetId, pos: Pos) -> Value {
        Env::value(self, sheet, pos)
    }

    /// The cell's formula as Excel would print it (`=SUM(A1:A3)`), or the text that did not parse.
    pub fn formula(&self, sheet: SheetId, pos: Pos) -> Option<String> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        if let Some((text, _)) = self.bad_inputs.get(&id) {
            return Some(text.clone());
        }
        let tree = self.formula_tree(sheet, pos)?;
        Some(format!("={}", self.print(&tree, pos)))
    }

    /// The cell's formula as a tree (its references relative to `pos`, as parsed there);
    /// `None` for a constant and for formula text that did not parse.
    pub fn formula_tree(&self, sheet: SheetId, pos: Pos) -> Option<Cow<'_, Expr>> {
        let formula = self.shared_formula_at(sheet, pos)?;
        Some(if formula.numbers.is_empty() { Cow::Borrowed(&*formula.expr) } else { Cow::Owned(formula.own_tree()) })
    }

    /// The shared formula the cell runs (its tree may hold another copy's numbers).
    fn shared_formula_at(&self, sheet: SheetId, pos: Pos) -> Option<&SharedFormula> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        let cell = &self.cells[id as usize];
        (cell.formula != NO_FORMULA).then(|| self.formulas.get(cell.formula))
    }

    /// The id of the cell's formula form: cells whose formulas are copies of one another
    /// (relative references alike) share it, so what depends only on the form of
    /// [`Workbook::formula_tree`] is decided once per id. `None` for a constant.
    pub fn formula_id(&self, sheet: SheetId, pos: Pos) -> Option<u32> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        let formula = self.cells[id as usize].formula;
        (formula != NO_FORMULA).then_some(formula)
    }

    /// Whether the cell's formula calls a volatile function (NOW, RAND, a workbook function
    /// that calls `Application.Volatile`): its value may
    /// differ from any stored one with nothing changed.
    pub fn calls_volatile(&self, sheet: SheetId, pos: Pos) -> bool {
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) else { return false };
        let cell = &self.cells[id as usize];
        cell.formula != NO_FORMULA
            && (self.formulas.get(cell.formula).volatile
                || self.calls_user_function(&self.formulas.get(cell.formula).expr) == Some(true))
    }

    /// What a user would type to recreate the cell: its formula, or its constant.
    pub fn input(&self, sheet: SheetId, pos: Pos) -> Option<String> {
        if let Some(f) = self.formula(sheet, pos) {
            return Some(f);
        }
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        if self.spill.owner(id).is_some() {
            return None;
        }
        match &self.cells[id as usize].value {
            Value::Blank => None,
            Value::Number(n) => Some(crate::formula::print::number_literal(*n)),
            Value::Text(t) if Input::parse(t, self.date_system()) != Input::Value(Value::Text(t.clone())) => {
                Some(format!("'{t}"))
            }
            v => Some(v.to_string()),
        }
    }

    pub fn is_formula(&self, sheet: SheetId, pos: Pos) -> bool {
        self.sheets[sheet as usize].get(pos).is_some_and(|id| self.cells[id as usize].formula != NO_FORMULA)
    }

    /// How many cells of `rect` hold a formula (the cells stored, not each position: a whole
    /// sheet is counted at the cost of its used cells).
    pub fn formula_cells_in(&self, sheet: SheetId, rect: Rect) -> u64 {
        let mut count = 0;
        if let Some(s) = self.sheets.get(sheet as usize) {
            s.for_each_in(rect, &mut |_, id| count += u64::from(self.cells[id as usize].formula != NO_FORMULA));
        }
        count
    }

    /// A1 to the last row and column holding a value (`None` for an empty sheet).
    pub fn used_rect(&self, sheet: SheetId) -> Option<Rect> {
        Env::used_rect(self, sheet)
    }

    /// The cells of `sheet` from the first to the last row and column that ever held a
    /// value (Excel's UsedRange of its values), where `used_rect` starts at A1.
    pub fn used_area(&self, sheet: SheetId) -> Option<Rect> {
        self.sheets.get(sheet as usize)?.used_area()
    }

    /// The cells of each circular reference, as `Sheet1!A1` names.
    pub fn cycles(&self) -> Vec<Vec<String>> {
        let mut cycles: Vec<&Vec<u32>> = self.cycles.iter().collect();
        cycles.sort_by_key(|c| (self.cells[c[0] as usize].sheet, self.cells[c[0] as usize].pos));
        cycles
            .into_iter()
            .map(|c| {
                c.iter().map(|&id| self.cell_name(self.cells[id as usize].sheet, self.cells[id as usize].pos)).collect()
            })
            .collect()
    }

    /// Number of formula cells and of distinct parsed formulas (shared ones count once).
    pub fn formula_counts(&self) -> (usize, usize) {
        let cells = self.cells.iter().filter(|c| c.formula != NO_FORMULA).count();
        (cells, self.formulas.formulas.len())
    }

    fn print(&self, expr: &Expr, pos: Pos) -> String {
        let names = |id: SheetId| self.sheets.get(id as usize).map_or_else(|| "#REF".into(), |s| s.name.clone());
        print_formula(expr, pos, &Registry, &names)
    }

    fn cell_at(&mut self, sheet: SheetId, pos: Pos) -> u32 {
        if let Some(id) = self.sheets[sheet as usize].get(pos) {
            return id;
        }
        let id = match self.free_cells.pop() {
            Some(id) => id,
            None => {
                self.cells.push(Cell { value: Value::Blank, formula: NO_FORMULA, sheet, pos, dependents: Deps::None });
                self.cells.len() as u32 - 1
            }
        };
        self.place_cell(id, sheet, pos);
        id
    }

    /// Gives back cells `ids`, each blank, with no formula and off its sheet's grid, for
    /// [`Workbook::cell_at`] to reuse. What the change log noted of them goes: they are a
    /// deleted sheet's, or blank cells no one edited (`links.rs`).
    fn free(&mut self, ids: &[u32]) {
        for &id in ids {
            let cell = &mut self.cells[id as usize];
            debug_assert!(cell.formula == NO_FORMULA, "a freed cell holds no formula");
            (cell.value, cell.dependents) = (Value::Blank, Deps::None);
            if let Some(log) = &mut self.changes {
                log.inputs.remove(id);
                log.had_formula.remove(&id);
                log.values.remove(id);
            }
            if !self.notes.is_empty() {
                self.notes.remove(&id);
            }
        }
        self.free_cells.extend_from_slice(ids);
    }

    /// Puts blank cell `id` at `pos`, where no cell is.
    fn place_cell(&mut self, id: u32, sheet: SheetId, pos: Pos) {
        let cell = &mut self.cells[id as usize];
        (cell.sheet, cell.pos) = (sheet, pos);
        self.sheets[sheet as usize].set(pos, id);
        // A cell made inside a spill's tail holds the tail's value, as the spill's own.
        if let Some((anchor, tail)) = self.spill.tail_at(sheet, pos) {
            self.cells[id as usize].value = tail.fill.clone();
            self.spill.own(id, anchor);
        }
    }

    fn store_value(&mut self, id: u32, value: Value) {
        let c = &mut self.cells[id as usize];
        if !value.is_blank() {
            self.sheets[c.sheet as usize].grow_extent(c.pos);
        }
        if let Some(log) = &mut self.changes {
            if c.value != value {
                log.values.insert(id);
            }
        }
        c.value = value;
    }

    fn clear_formula(&mut self, id: u32) {
        if !self.bad_inputs.is_empty() {
            self.bad_inputs.remove(&id);
            self.kept_values.remove(&id);
        }
        if !self.fixed_arrays.is_empty() {
            self.fixed_arrays.remove(&id);
        }
        let formula = self.cells[id as usize].formula;
        if formula != NO_FORMULA {
            if self.formulas.get(formula).volatile || self.user_functions.is_some() {
                self.volatile.remove(id);
            }
            self.unlink(id);
            self.cells[id as usize].formula = NO_FORMULA;
            self.notes.remove(&id);
            self.clear_spill(id);
        }
    }
}

/// Whether typed text is a formula (as `Input::parse` reads it).
fn is_formula_text(text: &str) -> bool {
    text.len() > 1 && text.starts_with('=')
}

/// The sheet and rectangle a reference in a formula at `pos` points at, if on the sheet.
fn resolve_static(r: &Reference, sheet: SheetId, pos: Pos) -> Option<(SheetId, Rect)> {
    r.resolve(sheet, pos)
}

impl Env for Workbook {
    #[inline]
    fn value(&self, sheet: SheetId, pos: Pos) -> Value {
        match self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) {
            // Numbers, the usual case, copied without `clone`'s dispatch on the kind.
            Some(id) => match &self.cells[id as usize].value {
                Value::Number(n) => Value::Number(*n),
                v => v.clone(),
            },
            None => self.spill.tail_value(sheet, pos),
        }
    }

    #[inline]
    fn number(&self, sheet: SheetId, pos: Pos) -> Option<f64> {
        let Some(id) = self.sheets.get(sheet as usize)?.get(pos) else {
            return match self.spill.tail_value(sheet, pos) {
                Value::Number(n) => Some(n),
                _ => None,
            };
        };
        match self.cells[id as usize].value {
            Value::Number(n) => Some(n),
            _ => None,
        }
    }

    fn for_each_value(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value)) {
        if self.spill.tails_meeting(sheet, rect).next().is_some() {
            // Cells of a spill's tail that do not exist hold a value too: every place in
            // `rect` is read, in order (the caller cut `rect` to what is used).
            for row in rect.first.row..=rect.last.row {
                for col in rect.first.col..=rect.last.col {
                    let v = Env::value(self, sheet, Pos::new(row, col));
                    if !v.is_blank() {
                        f(Pos::new(row, col), &v);
                    }
                }
            }
            return;
        }
        if let Some(s) = self.sheets.get(sheet as usize) {
            s.for_each_in(rect, &mut |p, id| {
                let v = &self.cells[id as usize].value;
                if !v.is_blank() {
                    f(p, v)
                }
            });
        }
    }

    fn for_each_number_in(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(f64)) -> crate::eval::XlResult<()> {
        if self.spill.tails_meeting(sheet, rect).next().is_some() {
            return crate::eval::evaluator::numbers_of_values(self, sheet, rect, f);
        }
        let Some(s) = self.sheets.get(sheet as usize) else { return Ok(()) };
        let mut outcome = Ok(());
        s.for_each_in(rect, &mut |_, id| match &self.cells[id as usize].value {
            Value::Number(n) if outcome.is_ok() => f(*n),
            Value::Error(e) if outcome.is_ok() => outcome = Err(*e),
            _ => {}
        });
        outcome
    }

    fn used_rect(&self, sheet: SheetId) -> Option<Rect> {
        self.sheets.get(sheet as usize)?.extent()
    }

    fn used_rect_for(&self, sheet: SheetId, rect: Rect) -> Option<Rect> {
        let mut used = self.sheets.get(sheet as usize)?.extent();
        for t in self.spill.tails_meeting(sheet, rect) {
            let last = Pos::new(t.rect.last.row.min(rect.last.row), t.rect.last.col.min(rect.last.col));
            let u = used.get_or_insert(Rect::new(Pos::new(0, 0), last));
            u.last = Pos::new(u.last.row.max(last.row), u.last.col.max(last.col));
        }
        used
    }

    fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)> {
        let Some(at) = self.name_position(name, Some(sheet)).or_else(|| self.name_position(name, None)) else {
            return self.table_as_name(name);
        };
        let n = &self.names[at];
        Some((n.expr.clone(), n.scope.unwrap_or(sheet)))
    }

    fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        let id = self.sheets.get(sheet as usize)?.get(pos)?;
        self.spill.rect(id)
    }

    fn sheet_count(&self) -> usize {
        Workbook::sheet_count(self)
    }

    fn sheet_name(&self, sheet: SheetId) -> Option<String> {
        self.sheets.get(sheet as usize).filter(|s| !s.deleted).map(|s| s.name.clone())
    }

    fn tab_position(&self, sheet: SheetId) -> usize {
        Workbook::tab_position(self, sheet).unwrap_or(sheet as usize)
    }

    fn sheets_spanned(&self, first: SheetId, last: SheetId) -> Vec<SheetId> {
        Workbook::sheets_spanned(self, first, last).to_vec()
    }

    fn sheet_id(&self, name: &str) -> Option<SheetId> {
        Workbook::sheet_id(self, name)
    }

    fn formula_text(&self, sheet: SheetId, pos: Pos) -> Option<String> {
        self.formula(sheet, pos)
    }

    fn is_subtotal(&self, sheet: SheetId, pos: Pos) -> bool {
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) else { return false };
        let cell = &self.cells[id as usize];
        if cell.formula == NO_FORMULA {
            return false;
        }
        let mut found = false;
        self.formulas.get(cell.formula).expr.visit(&mut |e| {
            if let crate::formula::ast::ExprKind::Call(id, _) = &e.kind {
                found |= crate::eval::functions::is_subtotal_call(*id);
            }
        });
        found
    }

    fn date_system(&self) -> DateSystem {
        Workbook::date_system(self)
    }

    fn now(&self) -> f64 {
        self.settings.now(Workbook::date_system(self))
    }

    fn next_random(&self) -> f64 {
        self.settings.next_random()
    }

    fn vba_rnd(&self, n: f64) -> f64 {
        self.settings.vba_rnd.draw(n)
    }

    fn lambda_work_limit(&self) -> u64 {
        self.settings.lambda_work_limit()
    }

    fn work_done(&self, done: crate::eval::WorkDone) {
        self.scratch.add_work(done);
    }

    fn live_items_limit(&self) -> usize {
        self.settings.live_items_limit()
    }

    fn locale(&self) -> crate::eval::Locale {
        self.settings.locale_in_force(self.date_system())
    }

    fn excel_language(&self) -> Option<&'static str> {
        self.excel_language
    }

    fn row_hidden(&self, sheet: SheetId, row: u32) -> Option<RowHidden> {
        self.sheets.get(sheet as usize)?.row_hidden(row)
    }

    fn column_width(&self, sheet: SheetId, col: u32) -> Option<f64> {
        self.sheets.get(sheet as usize)?.column_width(col)
    }

    fn call_user_function(&self, cells: &dyn Env, call: &UserCall) -> Option<Result<Value, crate::eval::Note>> {
        self.call_user(cells, call)
    }

    fn table_part(
        &self,
        r: &crate::formula::ast::TableRef,
        sheet: SheetId,
        pos: Pos,
    ) -> Result<(SheetId, Rect), crate::formula::ast::XlError> {
        Workbook::table_part(self, r, sheet, pos)
    }

    fn pivot_data(
        &self,
        sheet: SheetId,
        at: Pos,
        data_field: &str,
        pairs: &[(String, Value)],
    ) -> Result<Value, String> {
        match &self.pivot_tables {
            Some(pivots) => pivots.value(sheet, at, data_field, pairs),
            None => Err("the workbook has no pivot table".into()),
        }
    }
}

/// A workbook's pivot tables as the file that held them describes them (the reader knows
/// their format and installs them), for GETPIVOTDATA.
pub trait PivotTables {
    /// The value the pivot table holding cell `at` of `sheet` shows for `data_field` at the
    /// (field, item) `pairs`; `Err` says why it shows none (GETPIVOTDATA's `#REF!`).
    fn value(&self, sheet: SheetId, at: Pos, data_field: &str, pairs: &[(String, Value)]) -> Result<Value, String>;
}

impl Workbook {
    /// Installs the pivot tables GETPIVOTDATA reads.
    pub fn set_pivot_tables(&mut self, pivots: Rc<dyn PivotTables>) {
        self.pivot_tables = Some(pivots);
    }
}

/// A table of the workbook ("ListObject object"): its name, sheet, whole rectangle (header
/// and totals rows included) and its columns' names.
#[derive(Clone, Debug, PartialEq)]
pub struct TableShape {
    pub name: String,
    pub sheet: SheetId,
    pub rect: Rect,
    pub header_rows: u32,
    pub totals_rows: u32,
    pub columns: Vec<String>,
    /// Its look (`TableStyleMedium9`), kept when the file is written anew.
    pub style: Option<String>,
    /// Each calculated column's formula (`calculatedColumnFormula`: the formula its data cells
    /// share, as a file stores it, read from the first data row), by column name: a row added
    /// to the table gets it, as Excel fills a calculated column.
    pub calculated: Vec<(String, String)>,
    /// The totals row's cell of each column that has one (`totalsRowLabel`,
    /// `totalsRowFunction`), by column name, kept when the file is written anew.
    pub totals: Vec<(String, ColumnTotal)>,
    /// The workbook's number for it, which a macro's objects hold (its name may change).
    pub id: u32,
}

/// What a table's totals row shows under a column.
#[derive(Clone, Debug, PartialEq)]
pub enum ColumnTotal {
    /// A text (`Total`).
    Label(String),
    /// A function by its name in the file (`sum`, `average`, `count`, `countNums`, `max`,
    /// `min`, `stdDev`, `var`), which the cell's SUBTOTAL formula computes.
    Function(String),
    /// A formula of its own (`totalsRowFunction="custom"` and its `totalsRowFormula`), as the
    /// file stores it (without `=`).
    Formula(String),
}

impl Workbook {
    /// Installs the file's tables, which its formulas' structured references name.
    pub fn set_tables(&mut self, tables: Vec<TableShape>) {
        self.table_list = tables;
        for (n, t) in self.table_list.iter_mut().enumerate() {
            t.id = n as u32 + 1;
        }
    }
}

/// Cells by position for callers that walk a sheet (printing, export).
impl Workbook {
    /// Every non-blank position of a sheet with its value, row by row.
    pub fn values(&self, sheet: SheetId) -> Vec<(Pos, Value)> {
        let mut out: Vec<(Pos, Value)> = Vec::new();
        if let Some(rect) = self.used_rect(sheet) {
            self.for_each_value(sheet, rect, &mut |p, v| out.push((p, v.clone())));
        }
        out
    }

    /// Notes on one cell (why it holds an error), if any.
    pub fn notes(&self, sheet: SheetId, pos: Pos) -> Vec<String> {
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) else { return Vec::new() };
        self.notes.get(&id).map(|ns| ns.iter().map(|n| n.message.clone()).collect()).unwrap_or_default()
    }
}

/// Up to this many defined names are looked up one by one, without the index.
const FEW_NAMES: usize = 16;

/// What identifies a defined name in the index: the name as [`same_name`] compares it
/// (lowercased, in every script), and its scope.
type NameKey = (String, Option<SheetId>);

fn name_key(name: &str, scope: Option<SheetId>) -> NameKey {
    (name.to_lowercase(), scope)
}

/// Whether two defined names are the same name: Excel ignores case, in every script
/// (`Länge` is `LÄNGE`).
fn same_name(a: &str, b: &str) -> bool {
    if a.is_ascii() && b.is_ascii() {
        a.eq_ignore_ascii_case(b)
    } else {
        a.to_lowercase() == b.to_lowercase()
    }
}

/// A name Excel accepts for a defined name: not a cell address, not TRUE or FALSE; `?`
/// after the first character (`Gasket?`).
fn check_name(name: &str) -> Result<(), WorkbookError> {
    let valid = name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_' || c == '\\')
        && name.chars().all(|c| c.is_alphanumeric() || matches!(c, '_' | '.' | '\\' | '?'))
        && crate::formula::address::parse_cell(name).is_none()
        && !name.eq_ignore_ascii_case("TRUE")
        && !name.eq_ignore_ascii_case("FALSE");
    if valid {
        Ok(())
    } else {
        Err(WorkbookError::BadName(name.to_string()))
    }
}
