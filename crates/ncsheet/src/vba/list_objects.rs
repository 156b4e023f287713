//! Excel's tables as a macro reaches them, over the tables the workbook's file holds
//! (`Workbook::table_shapes`): `ws.ListObjects("T")` / `(1)` / `.Count` ("Worksheet.ListObjects
//! property", "ListObjects object"); a table's `Name`, `DisplayName`, `Range`, `DataBodyRange`,
//! `HeaderRowRange`, `TotalsRowRange`, `ShowTotals`, `Parent` ("ListObject object");
//! `ListColumns("c")` / `(i)` / `.Count` with each column's `Name`, `Index`, `Range`,
//! `DataBodyRange` ("ListColumn object"); `ListRows(i)` / `.Count` / `.Add` with each row's
//! `Range` and `Index` ("ListRow object", "ListRows.Add method"); For Each over the three
//! collections.
//!
//! `ListRow.Delete`, `ListObject.Resize`, `.Delete`, `.Unlist`, `ListObjects.Add` (a range's
//! cells made a table, its header row as Excel makes it) and setting a table's `Name`,
//! `TableStyle` and `ShowTotals` or a column's `Name` change the workbook's tables, which a
//! saved file writes; a rename carries the formulas naming the table or the column.
//!
//! An object names its table by the workbook's id for it (`TableShape::id`), not by a copy of
//! its rectangle nor by its name, so a row added through one variable is seen through every
//! other, and a table renamed is still the one a variable holds.

use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::TableShape;

use super::ast::{Link, Span};
use super::interp::{one_line, Fault, Interp, Run};
use super::objects::lower;
use super::sheet_ops::argument;
use super::value::{print_text, Obj, Var};

/// One of the table objects a macro holds.
#[derive(Clone, Debug, PartialEq)]
pub enum TableObj {
    /// `ws.ListObjects`: the tables of a sheet.
    List(SheetId),
    /// A ListObject, by its table's id.
    Table(u32),
    /// `lo.ListColumns` and one of them, counted from 0.
    Columns(u32),
    Column(u32, u32),
    /// `lo.ListRows` and one data row, counted from 0.
    Rows(u32),
    Row(u32, u32),
}

impl TableObj {
    /// Excel's class, for TypeName and messages.
    pub fn class(&self) -> &'static str {
        match self {
            TableObj::List(_) => "ListObjects",
            TableObj::Table(_) => "ListObject",
            TableObj::Columns(_) => "ListColumns",
            TableObj::Column(..) => "ListColumn",
            TableObj::Rows(_) => "ListRows",
            TableObj::Row(..) => "ListRow",
        }
    }
}

/// The rows of a table that hold data: between its header and totals rows (none when the
/// table is only a header).
fn data_rows(t: &TableShape) -> Option<(u32, u32)> {
    let first = t.rect.first.row + t.header_rows;
    let last = t.rect.last.row.checked_sub(t.totals_rows)?;
    (first <= last).then_some((first, last))
}

fn rows_of(t: &TableShape, rows: (u32, u32)) -> Rect {
    Rect::new(Pos::new(rows.0, t.rect.first.col), Pos::new(rows.1, t.rect.last.col))
}

fn column_of(rect: Rect, col: u32) -> Rect {
    let col = rect.first.col + col;
    Rect::new(Pos::new(rect.first.row, col), Pos::new(rect.last.row, col))
}

impl Interp<'_, '_> {
    fn table_fault(&self, span: Span, code: u32, why: String) -> Fault {
        let mut fault = self.fault_at(span, errors::message(code, why));
        fault.code = code;
        fault
    }

    /// The table `id`, or run-time error 424 when the workbook no longer has it (a macro
    /// deleted it).
    fn table_shape(&self, id: u32, span: Span) -> Run<TableShape> {
        let table = self.wb.borrow().table_list().iter().find(|t| t.id == id).cloned();
        table.ok_or_else(|| self.table_fault(span, 424, "the table was deleted".into()))
    }

    /// `ws.ListObjects`, or with `(index or name)` one table of the sheet.
    pub(super) fn list_objects(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        match link.args {
            Some(_) => self.list_object_item(ctx, sheet, link),
            None => Ok(Obj::Table(TableObj::List(sheet))),
        }
    }

    fn sheet_tables(&self, sheet: SheetId) -> Vec<TableShape> {
        self.wb.borrow().table_shapes().into_iter().filter(|t| t.sheet == sheet).collect()
    }

    /// `ListObjects("Parts")` or `ListObjects(1)` ("ListObjects.Item property": the index
    /// number or the name); a table the sheet has not is "Subscript out of range" (error 9).
    fn list_object_item(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let tables = self.sheet_tables(sheet);
        let names: Vec<String> = tables.iter().map(|t| t.name.clone()).collect();
        let at = self.table_index(ctx, &names, "table", link)?;
        Ok(Obj::Table(TableObj::Table(tables[at].id)))
    }

    /// The place in `names` of `(index or name)`, an index counted from 1.
    fn table_index(&self, ctx: &mut Ctx, names: &[String], what: &str, link: &Link) -> Run<usize> {
        let values = self.values(ctx, link)?;
        let found = match values.as_slice() {
            [Value::Text(name)] => names.iter().position(|n| n.eq_ignore_ascii_case(name)),
            [v] => {
                let n = self.number_of(v, what).map_err(|m| self.fault_at(link.span, m))?.round();
                (n >= 1.0 && n <= names.len() as f64).then(|| n as usize - 1)
            }
            _ => return Err(self.fault_at(link.span, format!("{}(index or name) picks a {what}", link.name))),
        };
        found.ok_or_else(|| {
            let given = values.first().map(print_text).unwrap_or_default();
            self.table_fault(link.span, 9, format!("there is no {what} {given} among the {} here", names.len()))
        })
    }

    /// The members of the table objects.
    pub(super) fn table_member(&self, ctx: &mut Ctx, obj: &TableObj, link: &Link) -> Run<Obj> {
        let name = lower(link);
        match obj {
            TableObj::List(sheet) => match name.as_str() {
                "count" => Ok(Obj::Value(Value::Number(self.sheet_tables(*sheet).len() as f64))),
                "item" => self.list_object_item(ctx, *sheet, link),
                "add" => self.add_list_object(ctx, *sheet, link),
                _ => self.unmodelled(&Obj::Table(obj.clone()), link),
            },
            TableObj::Table(table) => self.list_object_member(ctx, *table, link),
            TableObj::Columns(table) => {
                let t = self.table_shape(*table, link.span)?;
                match name.as_str() {
                    "count" => Ok(Obj::Value(Value::Number(t.columns.len() as f64))),
                    "item" => self.list_column(ctx, &t, link),
                    _ => self.unmodelled(&Obj::Table(obj.clone()), link),
                }
            }
            TableObj::Column(table, col) => self.list_column_member(*table, *col, link),
            TableObj::Rows(table) => {
                let t = self.table_shape(*table, link.span)?;
                match name.as_str() {
                    "count" => Ok(Obj::Value(Value::Number(data_rows(&t).map_or(0, |(a, b)| b - a + 1) as f64))),
                    "item" => self.list_row(ctx, &t, link),
                    "add" => self.add_list_row(ctx, &t, link),
                    _ => self.unmodelled(&Obj::Table(obj.clone()), link),
                }
            }
            TableObj::Row(table, row) => {
                let t = self.table_shape(*table, link.span)?;
                let at = t.rect.first.row + t.header_rows + row;
                match name.as_str() {
                    "range" => self.range_member_or_self(ctx, t.sheet, rows_of(&t, (at, at)), link),
                    "index" => Ok(Obj::Value(Value::Number(f64::from(row + 1)))),
                    "delete" => self.delete_list_row(ctx, &t, at, link),
                    _ => self.unmodelled(&Obj::Table(obj.clone()), link),
                }
            }
        }
    }

    /// `r` itself, or `r(i)` / `r(i, j)` when the member was given arguments
    /// (`lr.Range(1)`: "Range.Item property", the default member of the Range it gives).
    fn range_member_or_self(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        if link.args.is_none() {
            return Ok(Obj::Range(sheet, rect));
        }
        let item = Link { name: "Item".into(), args: link.args.clone(), span: link.span };
        self.range_member(ctx, sheet, rect, &item)
    }

    fn list_object_member(&self, ctx: &mut Ctx, table: u32, link: &Link) -> Run<Obj> {
        let t = self.table_shape(table, link.span)?;
        let nothing = Obj::Value(Value::Blank);
        match lower(link).as_str() {
            "name" | "displayname" => Ok(Obj::Value(Value::text(t.name.as_str()))),
            "range" => self.range_member_or_self(ctx, t.sheet, t.rect, link),
            // "ListObject.DataBodyRange property": Nothing when the table has no data rows.
            "databodyrange" => match data_rows(&t) {
                Some(rows) => self.range_member_or_self(ctx, t.sheet, rows_of(&t, rows), link),
                None => Ok(nothing),
            },
            "headerrowrange" if t.header_rows == 0 => Ok(nothing),
            "headerrowrange" => {
                let first = t.rect.first.row;
                self.range_member_or_self(ctx, t.sheet, rows_of(&t, (first, first + t.header_rows - 1)), link)
            }
            "totalsrowrange" if t.totals_rows == 0 => Ok(nothing),
            "totalsrowrange" => {
                let last = t.rect.last.row;
                self.range_member_or_self(ctx, t.sheet, rows_of(&t, (last + 1 - t.totals_rows, last)), link)
            }
            "showtotals" => Ok(Obj::Value(Value::Bool(t.totals_rows > 0))),
            "showheaders" => Ok(Obj::Value(Value::Bool(t.header_rows > 0))),
            "parent" => Ok(Obj::Sheet(t.sheet)),
            "listcolumns" if link.args.is_some() => self.list_column(ctx, &t, link),
            "listcolumns" => Ok(Obj::Table(TableObj::Columns(table))),
            "listrows" if link.args.is_some() => self.list_row(ctx, &t, link),
            "listrows" => Ok(Obj::Table(TableObj::Rows(table))),
            "tablestyle" => Ok(Obj::Value(Value::text(t.style.as_deref().unwrap_or("")))),
            "resize" => self.resize_list_object(ctx, &t, link),
            "delete" | "unlist" => self.remove_list_object(&t, lower(link) == "delete"),
            _ => self.unmodelled(&Obj::Table(TableObj::Table(table)), link),
        }
    }

    /// `ListColumns("Qty")` or `ListColumns(2)`.
    fn list_column(&self, ctx: &mut Ctx, t: &TableShape, link: &Link) -> Run<Obj> {
        let at = self.table_index(ctx, &t.columns, "column", link)?;
        Ok(Obj::Table(TableObj::Column(t.id, at as u32)))
    }

    fn list_column_member(&self, table: u32, col: u32, link: &Link) -> Run<Obj> {
        let t = self.table_shape(table, link.span)?;
        match lower(link).as_str() {
            "name" => Ok(Obj::Value(Value::text(t.columns.get(col as usize).map_or("", String::as_str)))),
            "index" => Ok(Obj::Value(Value::Number(f64::from(col + 1)))),
            "range" => Ok(Obj::Range(t.sheet, column_of(t.rect, col))),
            "databodyrange" => match data_rows(&t) {
                Some(rows) => Ok(Obj::Range(t.sheet, column_of(rows_of(&t, rows), col))),
                None => Ok(Obj::Value(Value::Blank)),
            },
            "parent" => Ok(Obj::Table(TableObj::Table(table))),
            _ => self.unmodelled(&Obj::Table(TableObj::Column(table, col)), link),
        }
    }

    /// `ListRows(i)`: the i-th data row, counted from 1.
    fn list_row(&self, ctx: &mut Ctx, t: &TableShape, link: &Link) -> Run<Obj> {
        let count = data_rows(t).map_or(0, |(a, b)| b - a + 1);
        let names: Vec<String> = (1..=count).map(|i| i.to_string()).collect();
        let values = self.values(ctx, link)?;
        if matches!(values.as_slice(), [Value::Text(_)]) {
            return Err(self.fault_at(link.span, "ListRows(index): a number, counted from 1"));
        }
        let at = self.table_index(ctx, &names, "row", link)?;
        Ok(Obj::Table(TableObj::Row(t.id, at as u32)))
    }

    /// `ListRows.Add([Position], [AlwaysInsert])` ("ListRows.Add method"): a new data row at
    /// `Position` (counted from 1; at the end without it), cells of the table's columns below
    /// it shifted down. At the end, with no totals row, the table takes the row below it
    /// when that row is empty in its columns and AlwaysInsert is not True ("If False, if the
    /// row below the table is empty, the table will expand to occupy that row without shifting
    /// cells below it"). Returns the new ListRow.
    fn add_list_row(&self, ctx: &mut Ctx, t: &TableShape, link: &Link) -> Run<Obj> {
        let count = data_rows(t).map_or(0, |(a, b)| b - a + 1);
        let position = match argument(link, 0, "position") {
            Some(e) => {
                let v = ctx.eval(e).unwrap_single();
                self.take_pending()?;
                let n = self.number_of(&v, "ListRows.Add's Position").map_err(|m| self.fault_at(link.span, m))?;
                let n = n.round();
                if n < 1.0 || n > f64::from(count + 1) {
                    let why = format!("ListRows.Add: Position {n} is not a row 1 to {} of table {}", count + 1, t.name);
                    return Err(self.error_1004(link.span, why));
                }
                n as u32 - 1
            }
            None => count,
        };
        let always = match argument(link, 1, "alwaysinsert") {
            Some(e) => {
                let v = ctx.eval(e).unwrap_single();
                self.take_pending()?;
                crate::eval::coerce::to_bool(&v).unwrap_or(false)
            }
            None => false,
        };
        let at = t.rect.first.row + t.header_rows + position;
        let below = Rect::new(Pos::new(at, t.rect.first.col), Pos::new(at, t.rect.last.col));
        let takes_row_below =
            position == count && t.totals_rows == 0 && !always && self.is_empty_rect(ctx, t.sheet, below);
        if !takes_row_below {
            let shift = Link { name: "Insert".into(), args: None, span: link.span };
            self.insert_or_delete(ctx, t.sheet, below, true, &shift)?;
        }
        let grown = Rect::new(t.rect.first, Pos::new(t.rect.last.row + 1, t.rect.last.col));
        let mut book = self.book_mut()?;
        book.set_table_rect(t.id, grown);
        book.fill_calculated_columns(t.id, at);
        Ok(Obj::Table(TableObj::Row(t.id, position)))
    }

    /// `lr.Delete` ("ListRow.Delete method"): the row's cells in the table's columns deleted,
    /// those below moving up. The only data row is emptied instead: a table keeps one row.
    fn delete_list_row(&self, ctx: &mut Ctx, t: &TableShape, row: u32, link: &Link) -> Run<Obj> {
        let cells = rows_of(t, (row, row));
        if data_rows(t).is_some_and(|(a, b)| a == b) {
            self.write_range(t.sheet, cells, &Value::Blank)?;
            return Ok(Obj::Value(Value::Blank));
        }
        let shift = Link { name: "Delete".into(), args: None, span: link.span };
        self.insert_or_delete(ctx, t.sheet, cells, false, &shift)
    }

    /// The range an argument names, or `None` when the argument is left out.
    fn range_argument(&self, ctx: &mut Ctx, link: &Link, at: usize, name: &str) -> Run<Option<(SheetId, Rect)>> {
        let Some(expr) = argument(link, at, name) else { return Ok(None) };
        let operand = ctx.operand(expr);
        self.take_pending()?;
        match operand {
            crate::eval::Operand::Ref(sheet, rect) => Ok(Some((sheet, rect))),
            _ => Err(self.fault_at(link.span, format!("{}'s {name} is not a range", link.name))),
        }
    }

    /// `lo.Resize(range)` ("ListObject.Resize method": "No cells are inserted or moved"; "The
    /// header must remain in the same row and the resulting list must overlap the original
    /// list"): the table takes the range, columns it gains named from their header cells.
    fn resize_list_object(&self, ctx: &mut Ctx, t: &TableShape, link: &Link) -> Run<Obj> {
        let Some((sheet, rect)) = self.range_argument(ctx, link, 0, "range")? else {
            return Err(self.fault_at(link.span, "ListObject.Resize takes the table's new range"));
        };
        let overlaps = rect.first.row <= t.rect.last.row
            && t.rect.first.row <= rect.last.row
            && rect.first.col <= t.rect.last.col
            && t.rect.first.col <= rect.last.col;
        let why = if sheet != t.sheet {
            Some("the range is on another sheet")
        } else if t.header_rows > 0 && rect.first.row != t.rect.first.row {
            Some("the header must remain in the same row")
        } else if !overlaps {
            Some("the new range must overlap the table")
        } else if rect.rows() <= t.header_rows + t.totals_rows {
            Some("the table must keep a row of data")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(self.error_1004(link.span, format!("Resize method of ListObject class failed: {why}")));
        }
        self.book_mut()?.set_table_rect(t.id, rect);
        Ok(Obj::Value(Value::Blank))
    }

    /// `lo.Unlist` (the cells stay, a plain range: "ListObject.Unlist method") or `lo.Delete`
    /// (the cells emptied too: "Deletes the ListObject object and clears the cell data").
    fn remove_list_object(&self, t: &TableShape, clear: bool) -> Run<Obj> {
        if clear {
            self.write_range(t.sheet, t.rect, &Value::Blank)?;
        }
        self.book_mut()?.remove_table(t.id);
        Ok(Obj::Value(Value::Blank))
    }

    /// `ws.ListObjects.Add(SourceType, Source, LinkSource, XlListObjectHasHeaders,
    /// Destination, TableStyleName)` ("ListObjects.Add method") over a range of the sheet:
    /// with headers (xlYes, or xlGuess finding a first row of texts) the first row's cells are
    /// made the column names, as text, a repeated one numbered ("an incrementing Integer is
    /// appended"), an empty one `Column1`…; without (xlNo) a header row of `Column1`,
    /// `Column2`… is inserted above the data, the cells below moving down. The table is
    /// named `Table1`, `Table2`… the first unused.
    fn add_list_object(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let number = |ctx: &mut Ctx, at: usize, name: &str, default: f64| -> Run<f64> {
            let Some(expr) = argument(link, at, name) else { return Ok(default) };
            let v = ctx.eval(expr).unwrap_single();
            self.take_pending()?;
            self.number_of(&v, name).map_err(|m| self.fault_at(link.span, m))
        };
        // XlListObjectSourceType: xlSrcRange is 1.
        if number(ctx, 0, "sourcetype", 1.0)? != 1.0 {
            let why = "ListObjects.Add: only a range of the workbook (xlSrcRange) is a table's source here";
            return Err(self.unsupported(link.span, why));
        }
        if argument(link, 2, "linksource").is_some() {
            return Err(self.error_1004(link.span, "ListObjects.Add: LinkSource is for an external source".into()));
        }
        let Some((source_sheet, source)) = self.range_argument(ctx, link, 1, "source")? else {
            let why = "ListObjects.Add: name the table's range as Source (Excel's guess of the list around the \
                       active cell is not made here)";
            return Err(self.unsupported(link.span, why));
        };
        if source_sheet != sheet {
            return Err(self.error_1004(link.span, "ListObjects.Add: the Source is on another sheet".into()));
        }
        // XlYesNoGuess: xlGuess 0, xlYes 1, xlNo 2.
        let headers = match number(ctx, 3, "xllistobjecthasheaders", 0.0)? as i64 {
            1 => true,
            2 => false,
            _ => self.first_row_is_text(ctx, sheet, source),
        };
        let style = match argument(link, 5, "tablestylename") {
            Some(expr) => {
                let v = ctx.eval(expr).unwrap_single();
                self.take_pending()?;
                print_text(&v)
            }
            None => "TableStyleMedium2".to_string(),
        };
        let rect = if headers { source } else { self.insert_header_row(ctx, sheet, source, link)? };
        // A table holds a data row at least: a header alone takes the row below.
        let rect = match rect.rows() {
            1 => Rect::new(rect.first, Pos::new(rect.first.row + 1, rect.last.col)),
            _ => rect,
        };
        let columns = self.header_names(ctx, sheet, rect, headers)?;
        let name = self.wb.borrow().unused_table_name();
        let table = TableShape {
            name,
            sheet,
            rect,
            header_rows: 1,
            totals_rows: 0,
            columns,
            style: (!style.is_empty()).then_some(style),
            calculated: Vec::new(),
            totals: Vec::new(),
            id: 0,
        };
        let added = self.book_mut()?.add_table(table);
        let id = added.map_err(|e| self.error_1004(link.span, format!("ListObjects.Add: {}", one_line(&e))))?;
        Ok(Obj::Table(TableObj::Table(id)))
    }

    /// xlGuess: the first row holds headers when its cells are all texts and the source has
    /// more rows.
    fn first_row_is_text(&self, ctx: &mut Ctx, sheet: SheetId, source: Rect) -> bool {
        let first = Rect::new(source.first, Pos::new(source.first.row, source.last.col));
        let texts = match ctx.rect_value(sheet, first) {
            Value::Array(a) => a.data.iter().all(|v| matches!(v, Value::Text(t) if !t.is_empty())),
            v => matches!(v, Value::Text(t) if !t.is_empty()),
        };
        texts && source.rows() > 1
    }

    /// xlNo: cells inserted over the source's first row, the source moving down; the table's
    /// rectangle is the inserted row and the moved data.
    fn insert_header_row(&self, ctx: &mut Ctx, sheet: SheetId, source: Rect, link: &Link) -> Run<Rect> {
        let row = Rect::new(source.first, Pos::new(source.first.row, source.last.col));
        let shift = Link { name: "Insert".into(), args: None, span: link.span };
        self.insert_or_delete(ctx, sheet, row, true, &shift)?;
        Ok(Rect::new(source.first, Pos::new(source.last.row + 1, source.last.col)))
    }

    /// The column names of a new table's header row, written back into its cells as text.
    fn header_names(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, from_cells: bool) -> Run<Vec<String>> {
        let mut names: Vec<String> = Vec::new();
        for col in rect.first.col..=rect.last.col {
            let at = Pos::new(rect.first.row, col);
            let text = if from_cells { print_text(&ctx.rect_value(sheet, Rect::cell(at))) } else { String::new() };
            let name = crate::workbook::Workbook::table_column_name(&names, text.trim_end());
            let cell = Rect::cell(at);
            if ctx.rect_value(sheet, cell) != Value::text(name.as_str()) {
                self.write_range(sheet, cell, &Value::text(name.as_str()))?;
            }
            names.push(name);
        }
        Ok(names)
    }

    /// `lo.Name = "Parts"`, `lo.TableStyle = "TableStyleLight9"`, `lo.ShowTotals = True`
    /// ("ListObject.Name property", "ListObject.TableStyle property", "ListObject.ShowTotals
    /// property"); a table name Excel would refuse, or a totals row that cannot move the cells
    /// under the table, is error 1004.
    /// `lc.Name = "Quantity"` ("ListColumn.Name property") names the column as its header
    /// cell typed over does; the formulas naming the table or the column follow either.
    pub(super) fn set_table_member(&self, obj: &TableObj, link: &Link, value: &crate::formula::ast::Expr) -> Run<()> {
        if let (TableObj::Column(id, col), "name") = (obj, lower(link).as_str()) {
            let text = print_text(&self.eval(value)?);
            self.book_mut()?.set_table_column_name(*id, *col as usize, &text);
            return Ok(());
        }
        let TableObj::Table(id) = obj else {
            return Err(self.fault_at(link.span, format!("cannot assign to {}.{}", obj.class(), link.name)));
        };
        let t = self.table_shape(*id, link.span)?;
        if lower(link) == "showtotals" {
            let show = self.truth(value, "ShowTotals")?;
            return self.book_mut()?.set_table_totals(t.id, show).map_err(|e| {
                self.error_1004(link.span, format!("ShowTotals property of ListObject class: {}", one_line(&e)))
            });
        }
        let text = print_text(&self.eval(value)?);
        match lower(link).as_str() {
            "name" | "displayname" => self.book_mut()?.rename_table(t.id, &text).map_err(|e| {
                self.error_1004(link.span, format!("Name property of ListObject class: {}", one_line(&e)))
            }),
            "tablestyle" => {
                self.book_mut()?.set_table_style(t.id, &text);
                Ok(())
            }
            _ => Err(self.fault_at(link.span, format!("cannot assign to ListObject.{}", link.name))),
        }
    }

    fn is_empty_rect(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect) -> bool {
        match ctx.rect_value(sheet, rect) {
            Value::Array(a) => a.data.iter().all(Value::is_blank),
            v => v.is_blank(),
        }
    }

    /// For Each over ListObjects, ListColumns or ListRows; `None` for another object.
    pub(super) fn tables_each(&self, obj: &TableObj, span: Span) -> Run<Option<Vec<Var>>> {
        let items = match obj {
            TableObj::List(sheet) => {
                self.sheet_tables(*sheet).into_iter().map(|t| Var::Obj(Obj::Table(TableObj::Table(t.id)))).collect()
            }
            TableObj::Columns(table) => {
                let count = self.table_shape(*table, span)?.columns.len() as u32;
                (0..count).map(|c| Var::Obj(Obj::Table(TableObj::Column(*table, c)))).collect()
            }
            TableObj::Rows(table) => {
                let t = self.table_shape(*table, span)?;
                let count = data_rows(&t).map_or(0, |(a, b)| b - a + 1);
                (0..count).map(|r| Var::Obj(Obj::Table(TableObj::Row(*table, r)))).collect()
            }
            _ => return Ok(None),
        };
        Ok(Some(items))
    }
}
