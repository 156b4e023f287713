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
use super::{ColumnTotal, TableShape, Workbook, WorkbookError};
use std::rc::Rc;

use crate::eval::Value;
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, ExprKind, SheetId, Span, TableRef, TableRows, XlError};
use crate::formula::parse::ParseError;

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

    /// The sheet and cells structured reference `r` names in the tables as they are now, for
    /// a formula at `pos` of `sheet`: a reference without a table's name (`[@Qty]`) names the
    /// table holding `pos`.
    /// `#NAME?` when it names a table or a column the workbook lacks (as a name that names
    /// nothing), `#REF!` when it names no cells of the table.
    pub fn table_part(&self, r: &TableRef, sheet: SheetId, pos: Pos) -> Result<(SheetId, Rect), XlError> {
        let table = match &r.table {
            Some(name) => self.table(name),
            None => self.table_list.iter().find(|t| t.sheet == sheet && t.rect.contains(pos)),
        };
        let table = table.ok_or(XlError::Name)?;
        part_of_table(table, r, pos).map(|rect| (table.sheet, rect))
    }

    /// Gives each structured reference of `tree` written without a table's name (`[@Qty]`,
    /// `[Qty]`) the table holding `pos` of `sheet`, as Excel reads what is typed in a cell of a
    /// table (and stores it: `Parts[[#This Row],[Qty]]`). Outside every table such a
    /// reference is refused, as Excel refuses the formula.
    pub fn name_own_table(&self, tree: &mut Expr, sheet: SheetId, pos: Pos) -> Result<(), ParseError> {
        let mut unnamed = None;
        tree.visit(&mut |e| {
            if matches!(&e.kind, ExprKind::Table(r) if r.table.is_none()) {
                unnamed = unnamed.or(Some(e.span));
            }
        });
        let Some(span) = unnamed else { return Ok(()) };
        let Some(t) = self.table_list.iter().find(|t| t.sheet == sheet && t.rect.contains(pos)) else {
            let message = format!(
                "a structured reference without a table's name ([@Qty], [Qty]) is read in a cell of a table, \
                 and {} is in none: write the table's name before it (Parts[@Qty])",
                self.cell_name(sheet, pos)
            );
            return Err(ParseError { offset: span.start as usize, message });
        };
        let name: Rc<str> = t.name.as_str().into();
        tree.visit_mut(&mut |e| {
            if let ExprKind::Table(r) = &e.kind {
                if r.table.is_none() {
                    let named = TableRef { table: Some(name.clone()), ..(**r).clone() };
                    e.kind = ExprKind::Table(Rc::new(named));
                }
            }
        });
        Ok(())
    }

    /// A table's name used as a defined name (`ROWS(Parts)`, `VLOOKUP(x,Parts,2)`): its data.
    pub(super) fn table_as_name(&self, name: &str) -> Option<(Rc<Expr>, SheetId)> {
        let t = self.table(name)?;
        let data = TableRef {
            table: Some(t.name.as_str().into()),
            rows: TableRows { data: true, ..TableRows::default() },
            columns: None,
        };
        Some((Rc::new(Expr::new(ExprKind::Table(Rc::new(data)), Span::default())), t.sheet))
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
        self.recalculate_table_readers();
    }

    /// Writes the formulas of the calculated columns of table `id` into its data row `row`
    /// (a row just added: "a formula in a calculated column is extended to the rows added",
    /// as Excel fills it). A column's formula is read as at the first data row, so its
    /// relative references move to `row`; one that no longer parses is left out.
    pub fn fill_calculated_columns(&mut self, id: u32, row: u32) {
        let Some(t) = self.table_list.iter().find(|t| t.id == id) else { return };
        let data_top = t.rect.first.row + t.header_rows;
        let fills: Vec<(Pos, Expr)> = t
            .calculated
            .iter()
            .filter_map(|(name, text)| {
                let col = t.rect.first.col + column_index(t, name)? as u32;
                let tree = self.parse_at(text, t.sheet, Pos::new(data_top, col)).ok()?;
                Some((Pos::new(row, col), tree))
            })
            .collect();
        let sheet = t.sheet;
        for (pos, tree) in fills {
            self.set_formula_tree(sheet, pos, tree);
        }
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
        self.recalculate_table_readers();
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
        let Some(t) = self.table_list.iter_mut().find(|t| t.id == id) else { return Ok(()) };
        let old = std::mem::replace(&mut t.name, name.to_string());
        // A table's name alone (`ROWS(Parts)`) is the table only where no defined name has it.
        let alone = !self.names.iter().any(|n| n.name.eq_ignore_ascii_case(&old));
        self.follow_rename(Renamed::Table { old: &old, new: name, alone });
        self.note_tables_changed();
        self.recalculate_table_readers();
        Ok(())
    }

    /// After cells of `rect` on `sheet` were written (a macro's `.Value =`, a paste, `set`):
    /// each header cell of a table among them names its column anew, as Excel takes a header
    /// typed over: "header row values must be constants", "when a header is changed, all
    /// formula references to that column are automatically adjusted", and "when you enter a
    /// header value that is the same as another header in the same Table, Excel appends a
    /// number" (Z. Barresse, K. Jones, *Excel Tables*, ch. 2 "The Header Row"); an emptied
    /// header is `Column1` (the first such name unused), as Excel fills it in.
    pub fn follow_header_edits(&mut self, sheet: SheetId, rect: Rect) {
        if self.table_list.is_empty() {
            return;
        }
        let mut headers: Vec<(u32, usize, Pos)> = Vec::new();
        for t in self.table_list.iter().filter(|t| t.sheet == sheet && t.header_rows > 0) {
            let row = t.rect.first.row;
            if row < rect.first.row || row > rect.last.row {
                continue;
            }
            let (first, last) = (t.rect.first.col.max(rect.first.col), t.rect.last.col.min(rect.last.col));
            headers.extend((first..=last).map(|col| (t.id, (col - t.rect.first.col) as usize, Pos::new(row, col))));
        }
        for (id, index, pos) in headers {
            self.take_header(id, index, sheet, pos);
        }
    }

    /// Header cell `pos` (column `index` of table `id`) as the column's name: made unique
    /// among the table's other columns, written back as text where it was not that text.
    fn take_header(&mut self, id: u32, index: usize, sheet: SheetId, pos: Pos) {
        let Some(t) = self.table_list.iter().find(|t| t.id == id) else { return };
        let Some(old) = t.columns.get(index).cloned() else { return };
        let value = self.value(sheet, pos);
        let typed = header_text(&value);
        let others: Vec<String> =
            t.columns.iter().enumerate().filter(|&(i, _)| i != index).map(|(_, c)| c.clone()).collect();
        let name = unique_column_name(&others, &typed);
        let as_typed = matches!(&value, Value::Text(t) if **t == *name) && !self.is_formula(sheet, pos);
        if !as_typed {
            self.set_value_deferred(sheet, pos, Value::text(name.as_str()));
            let cell = self.sheets[sheet as usize].get(pos);
            self.recalculate_from(cell.into_iter().collect());
        }
        if name != old {
            self.rename_table_column(id, index, &name);
        }
    }

    /// Names column `index` of table `id` ("ListColumn.Name property") as typing `name` in
    /// its header cell does ([`Workbook::follow_header_edits`]).
    pub fn set_table_column_name(&mut self, id: u32, index: usize, name: &str) {
        let Some(t) = self.table_list.iter().find(|t| t.id == id && index < t.columns.len()) else { return };
        let (sheet, pos) = (t.sheet, Pos::new(t.rect.first.row, t.rect.first.col + index as u32));
        if t.header_rows > 0 {
            self.set_value_deferred(sheet, pos, Value::text(name));
            self.recalculate_rect(sheet, Rect::new(pos, pos));
            return;
        }
        let others: Vec<String> =
            t.columns.iter().enumerate().filter(|&(i, _)| i != index).map(|(_, c)| c.clone()).collect();
        let name = unique_column_name(&others, name);
        if t.columns[index] != name {
            self.rename_table_column(id, index, &name);
        }
    }

    /// Gives column `index` of table `id` the name `name` (its header cell holds it already):
    /// the formulas, defined names and the table's own calculated column and totals naming the
    /// column follow.
    fn rename_table_column(&mut self, id: u32, index: usize, name: &str) {
        let Some(t) = self.table_list.iter_mut().find(|t| t.id == id) else { return };
        let old = std::mem::replace(&mut t.columns[index], name.to_string());
        for (column, _) in t.calculated.iter_mut() {
            if column.eq_ignore_ascii_case(&old) {
                *column = name.to_string();
            }
        }
        for (column, _) in t.totals.iter_mut() {
            if column.eq_ignore_ascii_case(&old) {
                *column = name.to_string();
            }
        }
        let table = t.name.clone();
        self.follow_rename(Renamed::Column { table: &table, old: &old, new: name });
        self.note_tables_changed();
        self.recalculate_table_readers();
    }

    /// Rewrites what names the renamed table or column: the stored formulas (each copy that
    /// had numbers of its own keeps them), the defined names, and the tables' calculated
    /// columns' formulas.
    fn follow_rename(&mut self, rename: Renamed) {
        let mut slots = Vec::new();
        for (fid, f) in self.formulas.formulas.iter().enumerate() {
            let named = f.tables.iter().any(|r| rename.reference(r).is_some())
                || f.names.iter().any(|(n, _)| rename.name(n).is_some());
            if let Some(tree) = named.then(|| rename.tree(&f.own_tree())).flatten() {
                slots.push((fid as u32, super::shared::SharedFormula::new(tree)));
            }
        }
        self.formulas.replace(slots);
        let mut names_changed = false;
        for i in 0..self.names.len() {
            if let Some(tree) = rename.tree(&self.names[i].expr) {
                self.names[i].expr = Rc::new(tree);
                names_changed = true;
            }
        }
        if let Some(log) = self.changes.as_mut() {
            log.names |= names_changed;
        }
        for at in 0..self.table_list.len() {
            let t = &self.table_list[at];
            let home = (t.sheet, Pos::new(t.rect.first.row + t.header_rows, t.rect.first.col));
            let texts: Vec<Option<String>> =
                t.calculated.iter().map(|(_, text)| self.renamed_text(text, home, rename)).collect();
            for ((_, text), renamed) in self.table_list[at].calculated.iter_mut().zip(texts) {
                if let Some(renamed) = renamed {
                    *text = renamed;
                }
            }
        }
    }

    /// Formula text read at `home` with the rename made, as typed (without `=`); `None` when
    /// it names nothing renamed or does not parse.
    fn renamed_text(&self, text: &str, home: (SheetId, Pos), rename: Renamed) -> Option<String> {
        let tree = self.parse_at(text, home.0, home.1).ok()?;
        rename.tree(&tree).map(|tree| self.print(&tree, home.1))
    }

    /// Shows or hides the totals row of table `id` ("ListObject.ShowTotals property"), as
    /// Excel's Total Row: shown, the cells under the table's columns move down a row to make
    /// room for it and it shows what the table's columns total (what the file's table part
    /// said, or Excel's default: `Total` under the first column, the last column's SUBTOTAL
    /// sum, or count when it holds no number); hidden, its cells go and the cells under it
    /// move up, the columns' totals remembered for when it is shown again.
    pub fn set_table_totals(&mut self, id: u32, show: bool) -> Result<(), WorkbookError> {
        let Some(t) = self.table_list.iter().find(|t| t.id == id) else { return Ok(()) };
        if (t.totals_rows > 0) == show {
            return Ok(());
        }
        let (sheet, rect) = (t.sheet, t.rect);
        if show {
            let row = rect.last.row + 1;
            let below = Rect::new(Pos::new(row, rect.first.col), Pos::new(row, rect.last.col));
            self.shift_cells(sheet, SheetEdit::cells(below, Axis::Rows, true))?;
            let at = self.table_list.iter().position(|t| t.id == id).expect("the table");
            if self.table_list[at].totals.is_empty() {
                self.table_list[at].totals = self.default_totals(at);
            }
            let t = &mut self.table_list[at];
            (t.totals_rows, t.rect.last.row) = (1, row);
            self.note_tables_changed();
            self.recalculate_table_readers();
            self.write_totals_row(id);
            return Ok(());
        }
        let row = rect.last.row + 1 - t.totals_rows;
        let totals = Rect::new(Pos::new(row, rect.first.col), Pos::new(rect.last.row, rect.last.col));
        let at = self.table_list.iter().position(|t| t.id == id).expect("the table");
        (self.table_list[at].totals_rows, self.table_list[at].rect.last.row) = (0, row - 1);
        let shifted = self.shift_cells(sheet, SheetEdit::cells(totals, Axis::Rows, false));
        if shifted.is_err() {
            (self.table_list[at].totals_rows, self.table_list[at].rect.last.row) =
                (rect.last.row + 1 - row, rect.last.row);
            return shifted;
        }
        self.note_tables_changed();
        self.recalculate_table_readers();
        Ok(())
    }

    /// The totals Excel's Total Row shows on a table that had none: `Total` under its first
    /// column, under its last the SUBTOTAL sum of it (of a column holding no number, the count).
    fn default_totals(&self, at: usize) -> Vec<(String, ColumnTotal)> {
        let t = &self.table_list[at];
        let mut totals = Vec::new();
        let Some(last) = t.columns.last() else { return totals };
        if t.columns.len() > 1 {
            totals.push((t.columns[0].clone(), ColumnTotal::Label("Total".into())));
        }
        let col = t.rect.last.col;
        let mut data = (t.rect.first.row + t.header_rows)..t.rect.last.row + 1 - t.totals_rows;
        let numbers = data.any(|row| matches!(self.value(t.sheet, Pos::new(row, col)), Value::Number(_)));
        totals.push((last.clone(), ColumnTotal::Function(if numbers { "sum" } else { "count" }.into())));
        totals
    }

    /// Writes the totals row of table `id`: each column's label, SUBTOTAL or formula.
    fn write_totals_row(&mut self, id: u32) {
        let Some(t) = self.table_list.iter().find(|t| t.id == id) else { return };
        let (sheet, row) = (t.sheet, t.rect.last.row);
        let mut cells: Vec<(Pos, String)> = Vec::new();
        for (name, total) in &t.totals {
            let Some(index) = column_index(t, name) else { continue };
            let pos = Pos::new(row, t.rect.first.col + index as u32);
            let column = TableRef {
                table: Some(t.name.as_str().into()),
                rows: TableRows { data: true, ..TableRows::default() },
                columns: Some((name.as_str().into(), name.as_str().into())),
            };
            let text = match total {
                ColumnTotal::Label(label) => label.clone(),
                ColumnTotal::Function(f) => match subtotal_code(f) {
                    Some(code) => {
                        let mut text = format!("=SUBTOTAL({code},");
                        column.write(&mut text, true);
                        text.push(')');
                        text
                    }
                    None => continue,
                },
                ColumnTotal::Formula(f) => format!("={f}"),
            };
            cells.push((pos, text));
        }
        let line = Rect::new(Pos::new(row, t.rect.first.col), Pos::new(row, t.rect.last.col));
        for (pos, text) in cells {
            if text.starts_with('=') {
                let _unparsed_kept_as_text = self.set_input_deferred(sheet, pos, &text);
            } else {
                self.set_value_deferred(sheet, pos, Value::text(text));
            }
        }
        self.recalculate_rect(sheet, line);
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
        self.recalculate_table_readers();
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

    /// The formula cells that may read a table: through a structured reference, or a name
    /// (a table's name alone is one).
    fn table_readers(&self) -> Vec<u32> {
        let reads_tables = |c: &super::Cell| {
            c.formula != super::NO_FORMULA && {
                let f = self.formulas.get(c.formula);
                !f.tables.is_empty() || !f.names.is_empty()
            }
        };
        (0..self.cells.len() as u32).filter(|&id| reads_tables(&self.cells[id as usize])).collect()
    }

    /// After a table changed shape, name or place: what its structured references read is
    /// linked again and recomputed, as Excel's references follow their table.
    fn recalculate_table_readers(&mut self) {
        let readers = self.table_readers();
        if !readers.is_empty() {
            self.rebuild_graph();
            self.recalculate_from(readers);
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
                    self.move_calculated(&mut t, rect);
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
            // The edit's recalculation relinks the graph whole (`recalculate_shifted`).
            self.names_unlinked |= !self.table_readers().is_empty();
        }
    }
}

/// The SUBTOTAL function number of a `totalsRowFunction` (ECMA-376 ST_TotalsRowFunction, as
/// Excel writes its totals: 109 for `sum`, the codes that skip hidden rows).
fn subtotal_code(function: &str) -> Option<u32> {
    Some(match function {
        "average" => 101,
        "countNums" => 102,
        "count" => 103,
        "max" => 104,
        "min" => 105,
        "stdDev" => 107,
        "sum" => 109,
        "var" => 110,
        _ => return None,
    })
}

/// A table or one of its columns given a new name, which the structured references naming
/// it follow, as Excel's do.
#[derive(Clone, Copy)]
enum Renamed<'a> {
    /// `alone`: the table's name used alone (`ROWS(Parts)`) names the table.
    Table {
        old: &'a str,
        new: &'a str,
        alone: bool,
    },
    Column {
        table: &'a str,
        old: &'a str,
        new: &'a str,
    },
}

impl Renamed<'_> {
    /// `r` as the rename leaves it; `None` when it names something else. A reference without
    /// its table's name is never stored (`[@Qty]` typed in a table is read with it).
    fn reference(&self, r: &TableRef) -> Option<TableRef> {
        let table = r.table.as_deref()?;
        match *self {
            Renamed::Table { old, new, .. } => {
                table.eq_ignore_ascii_case(old).then(|| TableRef { table: Some(new.into()), ..r.clone() })
            }
            Renamed::Column { table: named, old, new } => {
                let (first, last) = r.columns.as_ref().filter(|_| table.eq_ignore_ascii_case(named))?;
                let swap = |name: &Rc<str>| if name.eq_ignore_ascii_case(old) { Rc::from(new) } else { name.clone() };
                let columns = (swap(first), swap(last));
                let same = Rc::ptr_eq(&columns.0, first) && Rc::ptr_eq(&columns.1, last);
                (!same).then(|| TableRef { columns: Some(columns), ..r.clone() })
            }
        }
    }

    /// A table's name used alone as a name, renamed with its table.
    fn name(&self, name: &str) -> Option<Rc<str>> {
        match *self {
            Renamed::Table { old, new, alone: true } if name.eq_ignore_ascii_case(old) => Some(new.into()),
            _ => None,
        }
    }

    fn node(&self, e: &Expr) -> Option<ExprKind> {
        match &e.kind {
            ExprKind::Table(r) => self.reference(r).map(|r| ExprKind::Table(Rc::new(r))),
            ExprKind::Name(n) => self.name(n).map(ExprKind::Name),
            _ => None,
        }
    }

    /// `tree` with the rename made; `None` when it names nothing renamed.
    fn tree(&self, tree: &Expr) -> Option<Expr> {
        let mut named = false;
        tree.visit(&mut |e| named |= self.node(e).is_some());
        if !named {
            return None;
        }
        let mut tree = tree.clone();
        tree.visit_mut(&mut |e| {
            if let Some(kind) = self.node(e) {
                e.kind = kind;
            }
        });
        Some(tree)
    }
}

impl Workbook {
    /// The calculated columns' formulas of table `t`, which are read as at its first data row,
    /// for the table moved to `rect`: their references move with that row.
    fn move_calculated(&self, t: &mut TableShape, rect: Rect) {
        let from = Pos::new(t.rect.first.row + t.header_rows, t.rect.first.col);
        let to = Pos::new(rect.first.row + t.header_rows, rect.first.col);
        if from == to {
            return;
        }
        for (_, text) in t.calculated.iter_mut() {
            if let Ok(tree) = self.parse_at(text, t.sheet, from) {
                *text = self.print(&tree, to);
            }
        }
    }
}

/// The cells of table `t` that `r` names for a formula at `pos`: `None` when it names a
/// column the table lacks, rows it has not (`#Totals` of a table without a totals row), or
/// its own row outside the table's data rows.
fn part_of_table(t: &TableShape, r: &TableRef, pos: Pos) -> Result<Rect, XlError> {
    let (first_col, last_col) = match &r.columns {
        Some((a, b)) => {
            let index = |name: &str| column_index(t, name).ok_or(XlError::Name);
            let (a, b) = (index(a)?, index(b)?);
            (t.rect.first.col + a.min(b) as u32, t.rect.first.col + a.max(b) as u32)
        }
        None => (t.rect.first.col, t.rect.last.col),
    };
    let top = t.rect.first.row;
    let data_top = top + t.header_rows;
    let data_bottom = t.rect.last.row.checked_sub(t.totals_rows).ok_or(XlError::Ref)?;
    let (first_row, last_row) = if r.rows.this_row {
        if pos.row < data_top || pos.row > data_bottom {
            return Err(XlError::Ref);
        }
        (pos.row, pos.row)
    } else {
        let mut span: Option<(u32, u32)> = None;
        let mut take = |a: u32, b: u32| {
            if a <= b {
                span = Some(span.map_or((a, b), |(x, y)| (x.min(a), y.max(b))));
            }
        };
        if r.rows.headers && t.header_rows > 0 {
            take(top, data_top - 1);
        }
        if r.rows.data {
            take(data_top, data_bottom);
        }
        if r.rows.totals && t.totals_rows > 0 {
            take(data_bottom + 1, t.rect.last.row);
        }
        span.ok_or(XlError::Ref)?
    };
    Ok(Rect::new(Pos::new(first_row, first_col), Pos::new(last_row, last_col)))
}

/// The index of the column named `name` (case ignored, as Excel's; then spaces around it).
fn column_index(t: &TableShape, name: &str) -> Option<usize> {
    let exact = t.columns.iter().position(|c| c.eq_ignore_ascii_case(name));
    exact.or_else(|| t.columns.iter().position(|c| c.trim().eq_ignore_ascii_case(name.trim())))
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
