//! The tables of a workbook written anew ([`super::write`]): each is added through
//! rust_xlsxwriter's `Worksheet::add_table` before the sheet's cells, with its name, range,
//! header and totals rows, column names and style, so a package written anew (after rows
//! were inserted, or from a workbook a macro gave a new table) keeps them. The cells then
//! written over the table keep their values and looks; a header cell is written as the
//! text of its column's name, as Excel stores it. A calculated column's formula and a custom
//! total's (`calculatedColumnFormula`, `totalsRowFormula`) are written as Excel stores
//! formulas; the cells rust_xlsxwriter fills from them are emptied first, so that each cell
//! holds what the workbook's does (a calculated column may have exceptions).

use rust_xlsxwriter::{Formula, Table, TableColumn, TableFunction, TableStyle, Worksheet, XlsxError};

use super::syntax::{to_file, Storage};
use crate::eval::Value;
use crate::formula::address::Pos;
use crate::formula::ast::SheetId;
use crate::workbook::{ColumnTotal, TableShape, Workbook};

/// Adds the tables of `sheet` to `ws`.
pub fn add_tables(ws: &mut Worksheet, wb: &Workbook, sheet: SheetId) -> Result<(), (String, XlsxError)> {
    for t in wb.table_list().iter().filter(|t| t.sheet == sheet) {
        let columns: Vec<TableColumn> = t.columns.iter().map(|c| table_column(wb, t, c)).collect();
        let mut table = Table::new()
            .set_name(&t.name)
            .set_header_row(t.header_rows > 0)
            .set_autofilter(t.header_rows > 0)
            .set_total_row(t.totals_rows > 0)
            .set_columns(&columns);
        if let Some(style) = t.style.as_deref().and_then(table_style) {
            table = table.set_style(style);
        }
        let (first, last) = (t.rect.first, t.rect.last);
        ws.add_table(first.row, first.col as u16, last.row, last.col as u16, &table)
            .map_err(|e| (format!("table {}", t.name), e))?;
        empty_filled_cells(ws, t);
    }
    Ok(())
}

/// Empties the cells `add_table` wrote from the columns' formulas and totals (the data cells
/// of a calculated column, the totals row), which the workbook's own cells then fill.
fn empty_filled_cells(ws: &mut Worksheet, t: &TableShape) {
    let data = (t.rect.first.row + t.header_rows)..=t.rect.last.row.saturating_sub(t.totals_rows);
    for (index, name) in t.columns.iter().enumerate() {
        let col = (t.rect.first.col + index as u32) as u16;
        if t.calculated.iter().any(|(c, _)| c == name) {
            for row in data.clone() {
                ws.clear_cell(row, col);
            }
        }
        if t.totals_rows > 0 {
            ws.clear_cell(t.rect.last.row, col);
        }
    }
}

/// Column `name` of table `t`, with its calculated column's formula and its totals row's
/// label, function or formula (`totalsRowLabel`, `totalsRowFunction`, `totalsRowFormula`).
fn table_column(wb: &Workbook, t: &TableShape, name: &str) -> TableColumn {
    let mut column = TableColumn::new().set_header(name);
    let data_top = Pos::new(t.rect.first.row + t.header_rows, t.rect.first.col);
    if let Some(formula) = t.calculated.iter().find(|(c, _)| c == name).and_then(|(_, f)| file_text(wb, t, f, data_top))
    {
        column = column.set_formula(Formula::new(formula));
    }
    match t.totals.iter().find(|(c, _)| c == name).map(|(_, total)| total) {
        Some(ColumnTotal::Label(label)) => column.set_total_label(label),
        Some(ColumnTotal::Function(f)) => match total_function(f) {
            Some(f) => column.set_total_function(f),
            None => column,
        },
        Some(ColumnTotal::Formula(f)) => {
            let totals = Pos::new(t.rect.last.row, t.rect.first.col);
            match file_text(wb, t, f, totals) {
                Some(f) => column.set_total_function(TableFunction::Custom(Formula::new(f))),
                None => column,
            }
        }
        None => column,
    }
}

/// Formula `text` of table `t` (read as at `pos`) as Excel stores it; `None` when it no
/// longer parses (a column it named is gone), as Excel drops such a column formula.
fn file_text(wb: &Workbook, t: &TableShape, text: &str, pos: Pos) -> Option<String> {
    let tree = wb.parse_at(text, t.sheet, pos).ok()?;
    Some(to_file(&tree, wb, pos, Storage::Legacy).text)
}

/// rust_xlsxwriter's function of a `totalsRowFunction` (ECMA-376 ST_TotalsRowFunction);
/// `None` for `custom`, whose formula the totals cell itself keeps.
fn total_function(name: &str) -> Option<TableFunction> {
    Some(match name {
        "sum" => TableFunction::Sum,
        "average" => TableFunction::Average,
        "count" => TableFunction::Count,
        "countNums" => TableFunction::CountNumbers,
        "max" => TableFunction::Max,
        "min" => TableFunction::Min,
        "stdDev" => TableFunction::StdDev,
        "var" => TableFunction::Var,
        _ => return None,
    })
}

/// The value to write in cell `pos` of `sheet`: a table's header cell holds its column's
/// name as text (Excel warns of a file whose header cell differs from the name).
pub fn header_value(wb: &Workbook, sheet: SheetId, pos: Pos, value: Value) -> Value {
    let header = wb
        .table_list()
        .iter()
        .find(|t| t.sheet == sheet && t.header_rows > 0 && pos.row == t.rect.first.row && t.rect.contains(pos));
    match header.and_then(|t| column_name(t, pos)) {
        Some(name) => Value::text(name),
        None => value,
    }
}

fn column_name(t: &TableShape, pos: Pos) -> Option<&str> {
    t.columns.get((pos.col - t.rect.first.col) as usize).map(String::as_str)
}

/// rust_xlsxwriter's style of the name a file gives (`TableStyleMedium9`); `None` for a
/// custom style of the file's own, which a package written anew does not have (Excel's
/// default look then).
fn table_style(name: &str) -> Option<TableStyle> {
    use TableStyle::*;
    const STYLES: [TableStyle; 61] = [
        None, Light1, Light2, Light3, Light4, Light5, Light6, Light7, Light8, Light9, Light10, Light11, Light12,
        Light13, Light14, Light15, Light16, Light17, Light18, Light19, Light20, Light21, Medium1, Medium2, Medium3,
        Medium4, Medium5, Medium6, Medium7, Medium8, Medium9, Medium10, Medium11, Medium12, Medium13, Medium14,
        Medium15, Medium16, Medium17, Medium18, Medium19, Medium20, Medium21, Medium22, Medium23, Medium24, Medium25,
        Medium26, Medium27, Medium28, Dark1, Dark2, Dark3, Dark4, Dark5, Dark6, Dark7, Dark8, Dark9, Dark10, Dark11,
    ];
    STYLES.into_iter().find(|s| s.to_string().eq_ignore_ascii_case(name))
}
