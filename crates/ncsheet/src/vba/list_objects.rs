//! Excel's tables as a macro reaches them, over the tables the workbook's file holds
//! (`Workbook::table_shapes`): `ws.ListObjects("T")` / `(1)` / `.Count` ("Worksheet.ListObjects
//! property", "ListObjects object"); a table's `Name`, `DisplayName`, `Range`, `DataBodyRange`,
//! `HeaderRowRange`, `TotalsRowRange`, `ShowTotals`, `Parent` ("ListObject object");
//! `ListColumns("c")` / `(i)` / `.Count` with each column's `Name`, `Index`, `Range`,
//! `DataBodyRange` ("ListColumn object"); `ListRows(i)` / `.Count` / `.Add` with each row's
//! `Range` and `Index` ("ListRow object", "ListRows.Add method"); For Each over the three
//! collections.
//!
//! An object names its table by name, not by a copy of its rectangle, so a row added through
//! one variable is seen through every other.

use std::rc::Rc;

use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::TableShape;

use super::ast::{Link, Span};
use super::interp::{Fault, Interp, Run};
use super::objects::lower;
use super::sheet_ops::argument;
use super::value::{print_text, Obj, Var};

/// One of the table objects a macro holds.
#[derive(Clone, Debug, PartialEq)]
pub enum TableObj {
    /// `ws.ListObjects`: the tables of a sheet.
    List(SheetId),
    /// A ListObject, by its table's name.
    Table(Rc<str>),
    /// `lo.ListColumns` and one of them, counted from 0.
    Columns(Rc<str>),
    Column(Rc<str>, u32),
    /// `lo.ListRows` and one data row, counted from 0.
    Rows(Rc<str>),
    Row(Rc<str>, u32),
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

    /// The table named `name`, or run-time error 424 when the workbook no longer has it.
    fn table_shape(&self, name: &str, span: Span) -> Run<TableShape> {
        let tables = self.wb.borrow().table_shapes();
        tables
            .into_iter()
            .find(|t| t.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| self.table_fault(span, 424, format!("the workbook has no table {name}")))
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
        let names: Vec<String> = tables.into_iter().map(|t| t.name).collect();
        let at = self.table_index(ctx, &names, "table", link)?;
        Ok(Obj::Table(TableObj::Table(names[at].as_str().into())))
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
                _ => self.unmodelled(&Obj::Table(obj.clone()), link),
            },
            TableObj::Table(table) => self.list_object_member(ctx, table, link),
            TableObj::Columns(table) => {
                let t = self.table_shape(table, link.span)?;
                match name.as_str() {
                    "count" => Ok(Obj::Value(Value::Number(t.columns.len() as f64))),
                    "item" => self.list_column(ctx, &t, link),
                    _ => self.unmodelled(&Obj::Table(obj.clone()), link),
                }
            }
            TableObj::Column(table, col) => self.list_column_member(table, *col, link),
            TableObj::Rows(table) => {
                let t = self.table_shape(table, link.span)?;
                match name.as_str() {
                    "count" => Ok(Obj::Value(Value::Number(data_rows(&t).map_or(0, |(a, b)| b - a + 1) as f64))),
                    "item" => self.list_row(ctx, &t, link),
                    "add" => self.add_list_row(ctx, &t, link),
                    _ => self.unmodelled(&Obj::Table(obj.clone()), link),
                }
            }
            TableObj::Row(table, row) => {
                let t = self.table_shape(table, link.span)?;
                let at = t.rect.first.row + t.header_rows + row;
                match name.as_str() {
                    "range" => self.range_member_or_self(ctx, t.sheet, rows_of(&t, (at, at)), link),
                    "index" => Ok(Obj::Value(Value::Number(f64::from(row + 1)))),
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

    fn list_object_member(&self, ctx: &mut Ctx, table: &Rc<str>, link: &Link) -> Run<Obj> {
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
            "listcolumns" => Ok(Obj::Table(TableObj::Columns(table.clone()))),
            "listrows" if link.args.is_some() => self.list_row(ctx, &t, link),
            "listrows" => Ok(Obj::Table(TableObj::Rows(table.clone()))),
            _ => self.unmodelled(&Obj::Table(TableObj::Table(table.clone())), link),
        }
    }

    /// `ListColumns("Qty")` or `ListColumns(2)`.
    fn list_column(&self, ctx: &mut Ctx, t: &TableShape, link: &Link) -> Run<Obj> {
        let at = self.table_index(ctx, &t.columns, "column", link)?;
        Ok(Obj::Table(TableObj::Column(t.name.as_str().into(), at as u32)))
    }

    fn list_column_member(&self, table: &Rc<str>, col: u32, link: &Link) -> Run<Obj> {
        let t = self.table_shape(table, link.span)?;
        match lower(link).as_str() {
            "name" => Ok(Obj::Value(Value::text(t.columns.get(col as usize).map_or("", String::as_str)))),
            "index" => Ok(Obj::Value(Value::Number(f64::from(col + 1)))),
            "range" => Ok(Obj::Range(t.sheet, column_of(t.rect, col))),
            "databodyrange" => match data_rows(&t) {
                Some(rows) => Ok(Obj::Range(t.sheet, column_of(rows_of(&t, rows), col))),
                None => Ok(Obj::Value(Value::Blank)),
            },
            "parent" => Ok(Obj::Table(TableObj::Table(table.clone()))),
            _ => self.unmodelled(&Obj::Table(TableObj::Column(table.clone(), col)), link),
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
        Ok(Obj::Table(TableObj::Row(t.name.as_str().into(), at as u32)))
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
        self.wb.borrow().set_table_rect(&t.name, grown);
        Ok(Obj::Table(TableObj::Row(t.name.as_str().into(), position)))
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
            TableObj::List(sheet) => self
                .sheet_tables(*sheet)
                .into_iter()
                .map(|t| Var::Obj(Obj::Table(TableObj::Table(t.name.as_str().into()))))
                .collect(),
            TableObj::Columns(table) => {
                let count = self.table_shape(table, span)?.columns.len() as u32;
                (0..count).map(|c| Var::Obj(Obj::Table(TableObj::Column(table.clone(), c)))).collect()
            }
            TableObj::Rows(table) => {
                let t = self.table_shape(table, span)?;
                let count = data_rows(&t).map_or(0, |(a, b)| b - a + 1);
                (0..count).map(|r| Var::Obj(Obj::Table(TableObj::Row(table.clone(), r)))).collect()
            }
            _ => return Ok(None),
        };
        Ok(Some(items))
    }
}
