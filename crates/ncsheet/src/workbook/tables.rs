//! The workbook's Excel tables (ListObjects): the tables its file held and those a macro
//! adds, each a named rectangle with a header row, data rows, a totals row and named
//! columns. They follow the rows and columns a macro or a command inserts or deletes as
//! Excel's do: a row inserted inside a table grows it, a column inserted inside one is a new
//! column named `Column1` (the first such name unused), a table whose cells all go is
//! deleted. What Excel refuses is refused before anything moves: shifting part of a
//! table's columns ("This operation is not allowed. The operation is attempting to shift
//! cells in a table on your worksheet."), deleting its header or totals row alone, or
//! every data row. A file saved from the workbook writes the tables as they are then.

use super::shift::{Axis, SheetEdit};
use super::{TableShape, Workbook, WorkbookError};
use crate::eval::Value;
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;

/// What an edit does to one table.
enum TableFate {
    Kept,
    /// Moved or resized: its new rectangle, and for columns inserted inside it, where they
    /// are (table column index, count).
    To(Rect, Option<(usize, usize)>, Option<(usize, usize)>),
    Deleted,
}

impl Workbook {
    /// The workbook's tables, in its file's order and then as macros added them.
    pub fn table_shapes(&self) -> Vec<TableShape> {
        self.table_list.clone()
    }

    /// The workbook's tables, borrowed.
    pub fn table_list(&self) -> &[TableShape] {
        &self.table_list
    }

    /// The table named `name` (Excel's table names ignore case).
    pub fn table(&self, name: &str) -> Option<&TableShape> {
        self.table_list.iter().find(|t| t.name.eq_ignore_ascii_case(name))
    }

    /// Gives the table `id` the rectangle `rect` (a macro added a row to it or resized it),
    /// its columns named from its header cells where it gained some.
    pub fn set_table_rect(&mut self, id: u32, rect: Rect) {
        let Some(at) = self.table_list.iter().position(|t| t.id == id) else { return };
        let wanted = rect.cols() as usize;
        let (sheet, header) = (self.table_list[at].sheet, self.table_list[at].header_rows > 0);
        let mut columns = std::mem::take(&mut self.table_list[at].columns);
        columns.truncate(wanted);
        while columns.len() < wanted {
            let col = rect.first.col + columns.len() as u32;
            let text = if header { self.value(sheet, Pos::new(rect.first.row, col)) } else { Value::Blank };
            columns.push(unique_column_name(&columns, &header_text(&text)));
        }
        let table = &mut self.table_list[at];
        table.columns = columns;
        table.rect = rect;
        self.note_tables_changed();
    }

    /// Adds a table (ListObjects.Add) and gives back its id; refused when its name is taken
    /// or it overlaps another.
    pub fn add_table(&mut self, mut table: TableShape) -> Result<u32, WorkbookError> {
        if self.table(&table.name).is_some() {
            return Err(WorkbookError::CannotShift(format!("the workbook already has a table {}", table.name)));
        }
        if let Some(other) = self.table_list.iter().find(|t| t.sheet == table.sheet && overlap(t.rect, table.rect)) {
            return Err(WorkbookError::CannotShift(format!(
                "a table cannot overlap another table: {} would overlap {}",
                table.name, other.name
            )));
        }
        table.id = self.table_list.iter().map(|t| t.id).max().unwrap_or(0) + 1;
        let id = table.id;
        self.table_list.push(table);
        self.note_tables_changed();
        Ok(id)
    }

    /// Gives the table `id` the name `name` ("ListObject.Name property"): refused when another
    /// table has it or Excel would not take it as a name.
    pub fn rename_table(&mut self, id: u32, name: &str) -> Result<(), WorkbookError> {
        if self.table_list.iter().any(|t| t.id != id && t.name.eq_ignore_ascii_case(name)) {
            return Err(WorkbookError::CannotShift(format!("the workbook already has a table {name}")));
        }
        let valid = name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_' || c == '\\')
            && name.chars().all(|c| c.is_alphanumeric() || matches!(c, '_' | '.' | '\\'))
            && name.chars().count() <= 255
            && crate::formula::address::parse_cell(name).is_none()
            && !matches!(name.to_ascii_uppercase().as_str(), "C" | "R" | "TRUE" | "FALSE");
        if !valid {
            return Err(WorkbookError::CannotShift(format!("{name} is not a name Excel takes for a table")));
        }
        if let Some(t) = self.table_list.iter_mut().find(|t| t.id == id) {
            t.name = name.to_string();
        }
        self.note_tables_changed();
        Ok(())
    }

    /// Gives the table `id` the look `style` ("ListObject.TableStyle property").
    pub fn set_table_style(&mut self, id: u32, style: &str) {
        if let Some(t) = self.table_list.iter_mut().find(|t| t.id == id) {
            t.style = (!style.is_empty()).then(|| style.to_string());
        }
        self.note_tables_changed();
    }

    /// Takes the table `id` from the workbook (its cells stay: "ListObject.Unlist method").
    pub fn remove_table(&mut self, id: u32) {
        self.table_list.retain(|t| t.id != id);
        self.note_tables_changed();
    }

    /// A new column's name among `columns` ([`unique_column_name`]), for a table a macro makes.
    pub fn table_column_name(columns: &[String], wanted: &str) -> String {
        unique_column_name(columns, wanted)
    }

    /// The first of `Table1`, `Table2`, … no table of the workbook is named, as Excel names a
    /// new table.
    pub fn unused_table_name(&self) -> String {
        (1..).map(|n| format!("Table{n}")).find(|name| self.table(name).is_none()).expect("an unused name")
    }

    fn note_tables_changed(&mut self) {
        if let Some(log) = self.changes.as_mut() {
            log.tables = true;
        }
    }

    /// Refuses an edit Excel refuses on a table, before anything moves.
    pub(super) fn check_tables_whole(&self, sheet: SheetId, edit: &SheetEdit) -> Result<(), WorkbookError> {
        for t in self.table_list.iter().filter(|t| t.sheet == sheet) {
            if let Err(why) = fate(t, edit) {
                return Err(WorkbookError::CannotShift(format!("{why} (table {})", t.name)));
            }
        }
        Ok(())
    }

    /// Moves, grows, shrinks or deletes the tables of `sheet` as `edit` moves their cells
    /// (checked by [`Workbook::check_tables_whole`]); a column inserted inside a table gets
    /// a name, written in its header cell as Excel writes it.
    pub(super) fn follow_tables(&mut self, sheet: SheetId, edit: &SheetEdit) {
        let mut headers: Vec<(Pos, String)> = Vec::new();
        let mut changed = false;
        let mut kept = Vec::with_capacity(self.table_list.len());
        for mut t in std::mem::take(&mut self.table_list) {
            let fate = if t.sheet == sheet { fate(&t, edit).unwrap_or(TableFate::Kept) } else { TableFate::Kept };
            match fate {
                TableFate::Kept => kept.push(t),
                TableFate::Deleted => changed = true,
                TableFate::To(rect, inserted, deleted) => {
                    if let Some((at, n)) = deleted {
                        t.columns.drain(at..at + n);
                    }
                    if let Some((at, n)) = inserted {
                        for i in 0..n {
                            let name = unique_column_name(&t.columns, "");
                            if t.header_rows > 0 {
                                headers
                                    .push((Pos::new(rect.first.row, rect.first.col + (at + i) as u32), name.clone()));
                            }
                            t.columns.insert(at + i, name);
                        }
                    }
                    t.rect = rect;
                    changed = true;
                    kept.push(t);
                }
            }
        }
        self.table_list = kept;
        for (pos, name) in headers {
            self.set_value_deferred(sheet, pos, Value::text(name));
        }
        if changed {
            self.note_tables_changed();
        }
    }
}

/// What `edit` does to table `t` of its sheet, or why Excel refuses it.
fn fate(t: &TableShape, edit: &SheetEdit) -> Result<TableFate, String> {
    let (along, across) = match edit.axis {
        Axis::Rows => ((t.rect.first.row, t.rect.last.row), (t.rect.first.col, t.rect.last.col)),
        Axis::Columns => ((t.rect.first.col, t.rect.last.col), (t.rect.first.row, t.rect.last.row)),
    };
    let untouched = along.1 < edit.at || !edit.meets(across);
    if untouched {
        return Ok(TableFate::Kept);
    }
    if !edit.covers(across) {
        return Err("the edit would shift part of a table's cells, which Excel refuses".into());
    }
    let Some(moved) = edit.moved_rect(t.rect) else { return Ok(TableFate::Deleted) };
    if moved == t.rect {
        return Ok(TableFate::Kept);
    }
    match edit.axis {
        Axis::Rows => rows_fate(t, edit, moved),
        Axis::Columns => Ok(columns_fate(t, edit, moved)),
    }
}

/// A row edit through a table: its header and totals rows stay whole, and one data row at
/// least stays.
fn rows_fate(t: &TableShape, edit: &SheetEdit, moved: Rect) -> Result<TableFate, String> {
    if !edit.insert {
        let deleted = |row: u32| row >= edit.at && row < edit.at + edit.count;
        let top = t.rect.first.row;
        if t.header_rows > 0 && deleted(top) {
            return Err("the edit would delete a table's header row and not the table".into());
        }
        if t.totals_rows > 0 && deleted(t.rect.last.row) {
            return Err("the edit would delete a table's totals row and not the table".into());
        }
        if moved.rows() <= t.header_rows + t.totals_rows {
            return Err("the edit would delete every data row of a table, which keeps one row at least: \
                        delete all but one and clear that one"
                .into());
        }
    }
    Ok(TableFate::To(moved, None, None))
}

/// A column edit through a table: columns inserted inside it are new table columns, columns
/// deleted leave it.
fn columns_fate(t: &TableShape, edit: &SheetEdit, moved: Rect) -> TableFate {
    let first = t.rect.first.col;
    let index = |col: u32| (col.saturating_sub(first)) as usize;
    if edit.insert {
        let inside = edit.at > first && edit.at <= t.rect.last.col;
        let inserted = inside.then(|| (index(edit.at), edit.count as usize));
        return TableFate::To(moved, inserted, None);
    }
    let cut_first = edit.at.max(first);
    let cut_last = (edit.at + edit.count - 1).min(t.rect.last.col);
    let deleted = (cut_first <= cut_last).then(|| (index(cut_first), (cut_last - cut_first + 1) as usize));
    TableFate::To(moved, None, deleted)
}

fn overlap(a: Rect, b: Rect) -> bool {
    a.first.row <= b.last.row && b.first.row <= a.last.row && a.first.col <= b.last.col && b.first.col <= a.last.col
}

/// A column's name from its header cell's text, as Excel makes it: the text shown (a number
/// as text), line breaks kept.
fn header_text(value: &Value) -> String {
    match value {
        Value::Blank => String::new(),
        v => crate::eval::coerce::to_text(v).map(|t| t.to_string()).unwrap_or_default(),
    }
}

/// `wanted` made unique among `columns` as Excel makes a new table's headers unique (a
/// number appended: `Qty`, `Qty2`); an empty one is `Column1`, `Column2`, … the first unused.
fn unique_column_name(columns: &[String], wanted: &str) -> String {
    let taken = |name: &str| columns.iter().any(|c| c.eq_ignore_ascii_case(name));
    if wanted.is_empty() {
        return (1..).map(|n| format!("Column{n}")).find(|n| !taken(n)).expect("an unused name");
    }
    if !taken(wanted) {
        return wanted.to_string();
    }
    (2..).map(|n| format!("{wanted}{n}")).find(|n| !taken(n)).expect("an unused name")
}
