//! The opened workbook as the page sees it: windows of cells as shown, edits with their
//! history, what a cell reads and what reads it, saves. Answers are JSON values for the page;
//! a request the workbook cannot answer is a [`Refused`] with the words to show.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use serde_json::{json, Value as Json};

use ncsheet::document::{Document, SaveFormat};
use ncsheet::eval::Value;
use ncsheet::formula::address::{column_name, Pos, Rect};
use ncsheet::formula::ast::SheetId;
use ncsheet::io::{self, atomic, Content, Encoded, Export, ExportOptions};
use ncsheet::workbook::{DeletedSheet, Problem};

/// The most cells one window may ask for: a screen of a large monitor, several times over.
const MAX_WINDOW_ROWS: u32 = 1000;
const MAX_WINDOW_COLS: u32 = 200;
/// Excel's last row and column (1,048,576 × XFD).
const LAST_ROW: u32 = 1_048_575;
const LAST_COL: u32 = 16_383;

/// A request the workbook refuses, in words for the user (a 400 or 409 to the page).
#[derive(Debug, Clone, PartialEq)]
pub struct Refused {
    pub message: String,
    /// The request was well formed but conflicts with the files (an existing file).
    pub conflict: bool,
}

pub fn refused(message: impl Into<String>) -> Refused {
    Refused { message: message.into(), conflict: false }
}

/// One cell's edit as typed: what the cell held before and after, as a user would type it.
#[derive(Clone, Debug)]
struct Edit {
    sheet: SheetId,
    pos: Pos,
    before: String,
    after: String,
}

/// One step of the history: a typed edit, or all the cells a macro wrote (undone together).
#[derive(Clone, Debug)]
struct Step {
    edits: Vec<Edit>,
    /// The sheets the step deleted, in order: an undo brings them back before typing the
    /// inputs back (formulas that pointed to them among those), a redo deletes them again.
    deleted: Vec<DeletedSheet>,
    /// What the step was, for the status line: the cell's name, or the macro's.
    label: String,
}

/// Which way an edit of the history is made again.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Replay {
    Undo,
    Redo,
}

impl Replay {
    fn word(self) -> &'static str {
        match self {
            Replay::Undo => "undo",
            Replay::Redo => "redo",
        }
    }
}

/// A rectangle of cells the page shows (rows and columns from 0, both ends included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    pub sheet: SheetId,
    pub rect: Rect,
}

/// The document with the edit history of one session.
pub struct Workbench {
    doc: Document,
    /// The file the document was opened from: the only file saved over, and only when asked.
    path: PathBuf,
    /// That file as it was read (taken before the read), then as the last save over it left
    /// it: a save over it is refused when another program has saved it since.
    read: Option<atomic::ReadState>,
    undo: Vec<Step>,
    redo: Vec<Step>,
}

impl Workbench {
    /// The workbench of `doc`, read from `path` when the file was as `read` says.
    pub fn new(doc: Document, path: PathBuf, read: Option<atomic::ReadState>) -> Workbench {
        Workbench { doc, path, read, undo: Vec::new(), redo: Vec::new() }
    }

    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// Runs `f` (a macro) on the workbook and keeps the cells it wrote as one step of the
    /// history, named `label`: an undo types back every input it replaced. The writes stay
    /// and are kept for undo even when `f` fails partway.
    pub fn with_macro<R>(&mut self, label: &str, f: impl FnOnce(&mut Document) -> R) -> R {
        self.doc.workbook_mut().start_journal();
        let result = f(&mut self.doc);
        let wb = self.doc.workbook_mut();
        let deleted = wb.take_deleted_sheets();
        let written = wb.take_journal();
        let edits: Vec<Edit> = written
            .into_iter()
            .map(|(sheet, pos, before)| {
                let after = wb.input(sheet, pos).unwrap_or_default();
                Edit { sheet, pos, before, after }
            })
            .filter(|e| e.before != e.after)
            .collect();
        if !edits.is_empty() || !deleted.is_empty() {
            self.undo.push(Step { edits, deleted, label: label.to_string() });
            self.redo.clear();
        }
        result
    }

    /// The depth of the undo and redo histories, for the page's buttons.
    pub fn history(&self) -> Json {
        json!({ "undo": self.undo.len(), "redo": self.redo.len() })
    }

    /// The sheets with their extent, the import's notes and the history's depth.
    pub fn summary(&self) -> Json {
        let wb = self.doc.workbook();
        let sheets: Vec<Json> = wb
            .sheet_names()
            .into_iter()
            .enumerate()
            .map(|(i, name)| {
                let used = wb.used_rect(i as SheetId);
                let (rows, cols) = used.map_or((0, 0), |r| (r.last.row + 1, r.last.col + 1));
                json!({ "name": name, "rows": rows, "cols": cols, "widths": self.widths(&name) })
            })
            .collect();
        let file = self.path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
        json!({
            "file": file,
            "sheets": sheets,
            // The sheets' numbers (their places in `sheets`) in tab order.
            "order": wb.tab_order(),
            "active": wb.active_sheet(),
            "notes": self.doc.notes(),
            "history": self.history(),
        })
    }

    /// Column widths the file gave, in Excel's character units, as `[column, width]`.
    fn widths(&self, sheet_name: &str) -> Json {
        let layout = self.doc.layout().and_then(|l| l.sheets.get(sheet_name));
        let widths: Vec<Json> =
            layout.map_or(Vec::new(), |l| l.look.column_widths.iter().map(|&(c, w)| json!([c, w])).collect());
        Json::Array(widths)
    }

    /// The sheet named by index, or a refusal naming it.
    pub fn sheet(&self, index: u64) -> Result<SheetId, Refused> {
        let wb = self.doc.workbook();
        let len = wb.sheet_len() as u64;
        if index < len && !wb.sheet_deleted(index as SheetId) {
            Ok(index as SheetId)
        } else if index < len {
            Err(refused(format!("no sheet {index}: it was deleted")))
        } else {
            Err(refused(format!("no sheet {index}: the workbook has {}", wb.sheet_count())))
        }
    }

    /// Checks a window's bounds: inside the sheet's grid and no larger than a screen asks for.
    pub fn window(&self, sheet: u64, rows: (u64, u64), cols: (u64, u64)) -> Result<Window, Refused> {
        let sheet = self.sheet(sheet)?;
        let (r0, r1, c0, c1) = (rows.0, rows.1, cols.0, cols.1);
        if r0 > r1 || c0 > c1 || r1 > LAST_ROW as u64 || c1 > LAST_COL as u64 {
            return Err(refused(format!("window rows {r0}..{r1}, columns {c0}..{c1} is outside the sheet")));
        }
        if r1 - r0 >= MAX_WINDOW_ROWS as u64 || c1 - c0 >= MAX_WINDOW_COLS as u64 {
            return Err(refused(format!(
                "a window holds at most {MAX_WINDOW_ROWS} rows and {MAX_WINDOW_COLS} columns"
            )));
        }
        let rect = Rect { first: Pos::new(r0 as u32, c0 as u32), last: Pos::new(r1 as u32, c1 as u32) };
        Ok(Window { sheet, rect })
    }

    /// The cells of a window that hold something, as shown.
    pub fn cells(&self, window: Window) -> Json {
        let shown = self.shown_window(window);
        let mut explain = Explainer::new(&self.doc);
        let cells: Vec<Json> =
            shown.into_iter().map(|(pos, cell)| cell.to_json(window.sheet, pos, &mut explain)).collect();
        json!({ "sheet": window.sheet, "cells": cells })
    }

    fn shown_window(&self, window: Window) -> Vec<(Pos, Shown)> {
        // Only the anchors inside the window, looked up by hash: a list of every anchor of the
        // sheet searched for each cell shown took 13 s a window with 50,000 spills elsewhere.
        let anchors: HashSet<Pos> = self
            .doc
            .workbook()
            .spilling_cells()
            .into_iter()
            .filter(|&(s, p)| s == window.sheet && window.rect.contains(p))
            .map(|(_, p)| p)
            .collect();
        let mut out = Vec::new();
        for row in window.rect.first.row..=window.rect.last.row {
            for col in window.rect.first.col..=window.rect.last.col {
                let pos = Pos::new(row, col);
                if let Some(mut cell) = Shown::of(&self.doc, window.sheet, pos) {
                    if anchors.contains(&pos) {
                        cell.spill = Some(Spill::Anchor);
                    }
                    out.push((pos, cell));
                }
            }
        }
        out
    }

    /// A cell by the name a user types in the name box (`B8`, `Outer!B8`, a defined name,
    /// a sheet's own name before a workbook-wide one).
    pub fn locate(&self, name: &str, current: SheetId) -> Result<(SheetId, Pos), Refused> {
        let name = name.trim();
        let sheet_name = self.doc.workbook().sheet_names().into_iter().nth(current as usize).unwrap_or_default();
        let on_current = format!("'{}'!{name}", sheet_name.replace('\'', "''"));
        let found = if name.contains('!') { self.doc.cell(name) } else { self.doc.cell(&on_current) };
        found.ok_or_else(|| refused(format!("{name}: no such cell or single-cell name")))
    }

    /// Types `input` into a cell, keeps the edit for undo, and returns the cells of `window`
    /// whose display changed.
    pub fn set(&mut self, sheet: SheetId, pos: Pos, input: &str, window: Window) -> Result<Json, Refused> {
        let before = self.doc.workbook().input(sheet, pos).unwrap_or_default();
        let edit = Edit { sheet, pos, before, after: input.to_string() };
        let step = Step { label: self.doc.workbook().cell_name(sheet, pos), edits: vec![edit], deleted: Vec::new() };
        let changed = self.apply(&step, Replay::Redo, window)?;
        self.undo.push(step);
        self.redo.clear();
        Ok(self.with_history(changed))
    }

    /// Takes back the last edit (refused when there is none).
    pub fn undo(&mut self, window: Window) -> Result<Json, Refused> {
        self.replay(Replay::Undo, window)
    }

    /// Makes the last undone edit again.
    pub fn redo(&mut self, window: Window) -> Result<Json, Refused> {
        self.replay(Replay::Redo, window)
    }

    /// Moves the last step of one history to the other, typing its inputs before (undo) or
    /// after (redo) into its cells; a refused input leaves both histories as they were.
    fn replay(&mut self, way: Replay, window: Window) -> Result<Json, Refused> {
        let popped = match way {
            Replay::Undo => self.undo.pop(),
            Replay::Redo => self.redo.pop(),
        };
        let Some(step) = popped else { return Err(refused(format!("nothing to {}", way.word()))) };
        let result = self.apply(&step, way, window);
        // The step stands undone after an undo that went through or a redo that did not.
        let stands_undone = (way == Replay::Undo) == result.is_ok();
        if stands_undone {
            self.redo.push(step);
        } else {
            self.undo.push(step);
        }
        result.map(|changed| self.with_history(changed))
    }

    /// Types a step's inputs (before for an undo, last edit first; after for a redo) and
    /// compares the window before and after. A refused input puts back the cells already
    /// typed, so the workbook is as it was.
    fn apply(&mut self, step: &Step, way: Replay, window: Window) -> Result<Json, Refused> {
        let before: HashMap<Pos, Shown> = self.shown_window(window).into_iter().collect();
        let ordered: Vec<&Edit> =
            if way == Replay::Undo { step.edits.iter().rev().collect() } else { step.edits.iter().collect() };
        let typed = |e: &Edit, way: Replay| if way == Replay::Undo { e.before.clone() } else { e.after.clone() };
        if way == Replay::Undo {
            self.restore_sheets(&step.deleted)?;
        }
        let mut problems = Vec::new();
        for (done, edit) in ordered.iter().enumerate() {
            match self.doc.set(edit.sheet, edit.pos, &typed(edit, way)) {
                Ok(found) => problems.extend(found),
                Err(p) => {
                    let message = self.place(&p);
                    let back = if way == Replay::Undo { Replay::Redo } else { Replay::Undo };
                    for typed_already in ordered[..done].iter().rev() {
                        let _ = self.doc.set(typed_already.sheet, typed_already.pos, &typed(typed_already, back));
                    }
                    return Err(refused(message));
                }
            }
        }
        if way == Replay::Redo {
            for sheet in &step.deleted {
                self.doc.delete_sheet(sheet.id()).map_err(|e| refused(format!("redo: {e}")))?;
            }
        }
        let after = self.shown_window(window);
        let mut explain = Explainer::new(&self.doc);
        let mut changed: Vec<Json> = Vec::new();
        for (pos, cell) in &after {
            if before.get(pos) != Some(cell) {
                changed.push(cell.to_json(window.sheet, *pos, &mut explain));
            }
        }
        let after: HashMap<Pos, Shown> = after.into_iter().collect();
        for pos in before.keys().filter(|p| !after.contains_key(p)) {
            changed.push(json!({ "r": pos.row, "c": pos.col, "shown": "", "input": "" }));
        }
        let problems: Vec<String> = problems.iter().map(|p| self.place(p)).collect();
        Ok(json!({ "sheet": window.sheet, "cell": step.label, "changed": changed, "problems": problems }))
    }

    /// Brings back the sheets a step deleted, last deleted first; all or none.
    fn restore_sheets(&mut self, deleted: &[DeletedSheet]) -> Result<(), Refused> {
        for (done, sheet) in deleted.iter().rev().enumerate() {
            if let Err(e) = self.doc.workbook_mut().restore_sheet(sheet) {
                for back in deleted.iter().rev().take(done).rev() {
                    let _ = self.doc.delete_sheet(back.id());
                }
                return Err(refused(format!("undo: the deleted sheet cannot come back: {e}")));
            }
        }
        Ok(())
    }

    /// An edit's answer with the history's depth after it, for the page's buttons.
    fn with_history(&self, mut answer: Json) -> Json {
        answer["history"] = self.history();
        answer
    }

    /// A problem with the cell it is in.
    fn place(&self, p: &Problem) -> String {
        format!("{}: {}", self.doc.workbook().cell_name(p.sheet, p.pos), p.render())
    }

    /// The cells a cell's formula reads and the formula cells that read it.
    pub fn inspect(&self, sheet: SheetId, pos: Pos) -> Json {
        let wb = self.doc.workbook();
        let precedents: Vec<Json> = wb
            .precedents(sheet, pos)
            .into_iter()
            .map(|(s, r)| json!({ "sheet": s, "r0": r.first.row, "c0": r.first.col, "r1": r.last.row, "c1": r.last.col, "name": range_name(&self.doc, s, r) }))
            .collect();
        let dependents: Vec<Json> = wb
            .dependents(sheet, pos)
            .into_iter()
            .map(|(s, p)| json!({ "sheet": s, "r0": p.row, "c0": p.col, "r1": p.row, "c1": p.col, "name": wb.cell_name(s, p) }))
            .collect();
        json!({ "cell": wb.cell_name(sheet, pos), "precedents": precedents, "dependents": dependents })
    }

    /// What a download or save in `format` would lose, said before anything is written
    /// (`sheet`: the one shown, which a csv of a workbook of several sheets holds).
    pub fn losses(&self, format: SaveFormat, sheet: SheetId) -> Result<Json, Refused> {
        let encoded = self.encoded(format, sheet)?;
        Ok(json!({ "losses": encoded.losses }))
    }

    /// The bytes of the document in `format`, for the browser to download.
    pub fn download(&self, format: SaveFormat, sheet: SheetId) -> Result<(String, Vec<u8>), Refused> {
        let encoded = self.encoded(format, sheet)?;
        let name = encoded.path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
        Ok((name, encoded.bytes().to_vec()))
    }

    /// The document as a file in `format` under its own name (the extension changed).
    fn encoded(&self, format: SaveFormat, sheet: SheetId) -> Result<Encoded, Refused> {
        let wb = self.doc.workbook();
        if format != SaveFormat::Csv || wb.sheet_len() == 1 {
            return self.doc.save_as(format).map_err(|e| refused(e.to_string()));
        }
        let sheet_name = wb.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
        let stem = self.path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        self.encoded_to(&self.path.with_file_name(format!("{stem}-{sheet_name}.csv")), sheet)
    }

    /// The document as the file `target` holds it (the format by its extension). A csv holds
    /// one sheet: a workbook of several gives the shown sheet's values as its cells show
    /// them, and says what that leaves out.
    fn encoded_to(&self, target: &Path, sheet: SheetId) -> Result<Encoded, Refused> {
        let wb = self.doc.workbook();
        let is_csv = target.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        if !is_csv || wb.sheet_len() == 1 {
            return self.doc.encode(target).map_err(|e| refused(e.to_string()));
        }
        let sheet_name = wb.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
        let what = Export { sheet, range: None, content: Content::Values };
        let options = ExportOptions { delimiter: None, layout: self.doc.layout(), raw: false };
        let mut encoded = io::encode_export_with(wb, target, &what, &options).map_err(|e| refused(e.to_string()))?;
        encoded.losses.push(format!(
            "a csv holds one sheet: {sheet_name}'s values as shown, without its formulas, formats and the workbook's other {} sheet(s)",
            wb.sheet_count() - 1
        ));
        Ok(encoded)
    }

    /// Saves beside the opened file under `name` (a bare file name: the server writes nowhere
    /// else), or over the opened file when `name` is its own and `over` says so.
    pub fn save(&mut self, name: &str, over: bool, sheet: SheetId) -> Result<Json, Refused> {
        let target = self.save_target(name, over)?;
        let encoded = self.encoded_to(&target, sheet)?;
        if target == self.path {
            self.save_over(name, &encoded)?;
        } else {
            encoded.write(atomic::Options::default()).map_err(|e| refused(e.to_string()))?;
        }
        Ok(json!({ "saved": target.to_string_lossy(), "losses": encoded.losses }))
    }

    /// Saves over the opened file as `set --in-place` does: after a command's edit of it in
    /// progress (its lock), and only when no other program has saved the file since the
    /// workbench read it, whose work the save would otherwise replace without a word.
    fn save_over(&mut self, name: &str, encoded: &Encoded) -> Result<(), Refused> {
        let lock = match atomic::EditLock::acquire(&self.path) {
            Ok(lock) => Some(lock),
            // A file removed meanwhile holds no one's work: the save makes it again.
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(refused(format!("{name}: cannot lock it for the save: {e}"))),
        };
        if let Some(lock) = &lock {
            // Without the file's state as read there is nothing to tell another program's save
            // from ours: refuse rather than risk replacing its work.
            let Some(read) = &self.read else {
                return Err(Refused {
                    message: format!(
                        "{name}: its state when the workbench read it is unknown (it could not be read then), \
                         so another program's save since cannot be ruled out: save under another name, or open the file again"
                    ),
                    conflict: true,
                });
            };
            lock.unchanged_since(read).map_err(|e| Refused {
                message: format!("{name}: {e}: save under another name, or open the file again"),
                conflict: true,
            })?;
        }
        encoded.write(atomic::Options::default()).map_err(|e| refused(e.to_string()))?;
        self.read = atomic::ReadState::of(&self.path).ok();
        Ok(())
    }

    fn save_target(&self, name: &str, over: bool) -> Result<PathBuf, Refused> {
        let bare = Path::new(name).file_name().is_some_and(|f| f == name);
        if !bare || name.starts_with('.') {
            return Err(refused(format!(
                "{name}: give a file name without a folder (it is saved beside the workbook)"
            )));
        }
        // The one check of a file name a macro or the command line gives: a name Windows
        // reads as something else (a device, a stream) is refused on every system.
        if let Some(why) = ncsheet::vba::checked_name(name) {
            return Err(refused(format!("{name}: not a file name that can be saved on every system ({why})")));
        }
        let target = self.path.with_file_name(name);
        if target == self.path {
            return if over {
                Ok(target)
            } else {
                Err(Refused {
                    message: format!("{name} is the opened workbook: confirm to save over it"),
                    conflict: true,
                })
            };
        }
        if target.exists() {
            return Err(Refused { message: format!("{name} already exists: choose another name"), conflict: true });
        }
        Ok(target)
    }
}

/// A range as a user writes it, with its sheet.
fn range_name(doc: &Document, sheet: SheetId, rect: Rect) -> String {
    let sheet_name = doc.workbook().sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
    if rect.is_cell() {
        return doc.workbook().cell_name(sheet, rect.first);
    }
    let a1 = |p: Pos| format!("{}{}", column_name(p.col), p.row + 1);
    format!("{sheet_name}!{}:{}", a1(rect.first), a1(rect.last))
}

/// One cell as the grid shows it.
#[derive(Clone, Debug, PartialEq)]
struct Shown {
    shown: String,
    input: String,
    number: Option<f64>,
    error: bool,
    spill: Option<Spill>,
}

/// A cell's part in a spilled range, for the grid to outline.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Spill {
    /// The formula whose array result spills (or shows #SPILL!).
    Anchor,
    /// A cell the result filled: a value with nothing typed in it.
    Item,
}

impl Shown {
    fn of(doc: &Document, sheet: SheetId, pos: Pos) -> Option<Shown> {
        let wb = doc.workbook();
        let value = wb.value(sheet, pos);
        let input = wb.input(sheet, pos).unwrap_or_default();
        if matches!(value, Value::Blank) && input.is_empty() {
            return None;
        }
        let number = match value {
            Value::Number(n) => Some(n),
            _ => None,
        };
        let error = matches!(value, Value::Error(_));
        // A cell shows a value without input only when a spill filled it.
        let spill = input.is_empty().then_some(Spill::Item);
        Some(Shown { shown: doc.shown(sheet, pos), input, number, error, spill })
    }

    fn to_json(&self, sheet: SheetId, pos: Pos, explain: &mut Explainer) -> Json {
        let mut cell = json!({ "r": pos.row, "c": pos.col, "shown": self.shown, "input": self.input });
        if let Some(n) = self.number.filter(|n| n.is_finite()) {
            cell["num"] = json!(n);
        }
        if self.error {
            cell["explain"] = json!(explain.explain(sheet, pos, &self.shown));
        }
        match self.spill {
            Some(Spill::Anchor) => cell["spill"] = json!("anchor"),
            Some(Spill::Item) => cell["spill"] = json!("item"),
            None => {}
        }
        cell
    }
}

/// Why a cell holds an error value: the workbook's problems at the cell (read once per
/// answer, and only when an error is shown), else what the error means in Excel.
struct Explainer<'a> {
    doc: &'a Document,
    /// The problems by cell: a window of 200,000 error cells, each looking through all the
    /// workbook's problems, took minutes.
    problems: Option<HashMap<(SheetId, Pos), Vec<Problem>>>,
}

impl<'a> Explainer<'a> {
    fn new(doc: &'a Document) -> Explainer<'a> {
        Explainer { doc, problems: None }
    }

    fn explain(&mut self, sheet: SheetId, pos: Pos, shown: &str) -> String {
        let doc = self.doc;
        let problems = self.problems.get_or_insert_with(|| problems_by_cell(doc.problems()));
        if let Some(here) = problems.get(&(sheet, pos)) {
            return here.iter().map(Problem::render).collect::<Vec<_>>().join("\n");
        }
        let meaning = match shown {
            "#DIV/0!" => "a division by zero",
            "#N/A" => "a value not available (a lookup that found nothing)",
            "#NAME?" => "a name or function the workbook does not know",
            "#NULL!" => "two ranges that do not intersect",
            "#NUM!" => "a number out of range for the calculation",
            "#REF!" => "a reference to a cell that does not exist",
            "#VALUE!" => "a value of the wrong type for the calculation",
            "#SPILL!" => "a spilled result blocked by cells that hold something",
            "#CALC!" => "a calculation the engine cannot do (an empty array)",
            _ => "an error value",
        };
        format!("{shown}: {meaning}, here or in a cell this formula reads")
    }
}

/// `problems` filed under their cells, each cell's in the workbook's order.
fn problems_by_cell(problems: Vec<Problem>) -> HashMap<(SheetId, Pos), Vec<Problem>> {
    let mut by_cell: HashMap<(SheetId, Pos), Vec<Problem>> = HashMap::new();
    for p in problems {
        by_cell.entry((p.sheet, p.pos)).or_default().push(p);
    }
    by_cell
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A csv file `a,1` in a folder of its own, opened, and its path.
    fn opened(folder: &str) -> (Document, PathBuf) {
        let dir = std::env::temp_dir().join(format!("ncsheet-workbench-{folder}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("book.csv");
        std::fs::write(&path, "a,1\n").unwrap();
        (Document::open_file(&path, &Default::default()).unwrap(), path)
    }

    #[test]
    fn a_save_over_a_file_whose_read_state_is_unknown_is_refused() {
        let (doc, path) = opened("unknown");
        let mut bench = Workbench::new(doc, path.clone(), None);
        let refused = bench.save("book.csv", true, 0).expect_err("no conflict check is possible");
        assert!(refused.conflict && refused.message.starts_with("book.csv: "), "{}", refused.message);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,1\n", "the file is left as it was");
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }

    /// Microsoft's "Naming Files, Paths, and Namespaces" (Win32 docs): "Do not use the
    /// following reserved names for the name of a file: CON, PRN, AUX, NUL, COM0 … LPT9 …
    /// Also avoid these names followed immediately by an extension; for example, NUL.txt",
    /// and names may not hold `< > : " / \ | ? *` nor end in a space or a period.
    #[test]
    fn a_save_as_a_windows_device_name_or_a_stream_is_refused() {
        let (doc, path) = opened("device");
        let mut bench = Workbench::new(doc, path.clone(), None);
        for name in ["CON.xlsx", "con.csv", "nul.xlsx", "COM1.xlsx", "lpt9.csv", "a.xlsx:x", "b.xlsx.", "a?.csv"] {
            let refused = bench.save(name, false, 0).expect_err(name);
            assert!(refused.message.starts_with(&format!("{name}: not a file name")), "{}", refused.message);
            assert!(!path.with_file_name(name).exists(), "{name} was written");
        }
        assert!(bench.save("console.csv", false, 0).is_ok(), "a longer name is a name");
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }

    #[test]
    fn a_save_over_a_file_as_it_was_read_is_written() {
        let (doc, path) = opened("known");
        let read = atomic::ReadState::of(&path).ok();
        let mut bench = Workbench::new(doc, path.clone(), read);
        assert!(bench.save("book.csv", true, 0).is_ok());
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }
}
