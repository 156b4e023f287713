//! Printing values: an aligned table for people, csv and JSON for programs.

use std::collections::HashSet;
use std::io::Write;

use clap::ValueEnum;
use ncsheet::eval::number_format::round15;
use ncsheet::eval::Value;
use ncsheet::formula::address::{column_name, Pos, Rect};
use ncsheet::formula::ast::SheetId;
use ncsheet::io::{csv, Content, Export};
use ncsheet::workbook::Workbook;

use super::report::Result;

/// How `eval` prints values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum OutputFormat {
    /// Columns aligned under their letters, rows numbered; numbers to 15 significant digits
    #[default]
    Table,
    /// The cells as csv rows (as `ncsheet export` writes them)
    Csv,
    /// One object {"Sheet1!A1": value, …}: numbers, strings, booleans, errors as "#…" text;
    /// blank cells left out
    Json,
}

/// Cells or ranges on a resolved sheet.
pub struct Selection {
    pub sheet: SheetId,
    pub rect: Rect,
}

/// Prints a whole sheet, from A1 to its last used row and column.
pub fn print_sheet(out: &mut dyn Write, wb: &Workbook, sheet: SheetId, format: OutputFormat) -> Result<()> {
    let Some(used) = wb.used_rect(sheet) else {
        if format == OutputFormat::Json {
            writeln!(out, "{{}}")?;
        }
        return Ok(());
    };
    let whole = Selection { sheet, rect: Rect::new(Pos::new(0, 0), used.last) };
    print_selections(out, wb, sheet, &[whole], format)
}

/// Prints cells and ranges. In a table, one cell alone prints as its value only; several
/// cells print one per line after their names; a range prints as a table.
pub fn print_selections(
    out: &mut dyn Write,
    wb: &Workbook,
    default_sheet: SheetId,
    selections: &[Selection],
    format: OutputFormat,
) -> Result<()> {
    match format {
        OutputFormat::Table => {
            if let [only] = selections {
                if only.rect.is_cell() {
                    writeln!(out, "{}", wb.value(only.sheet, only.rect.first))?;
                    return Ok(());
                }
            }
            for s in selections {
                if s.rect.is_cell() {
                    let name = if s.sheet == default_sheet {
                        s.rect.first.to_string()
                    } else {
                        wb.cell_name(s.sheet, s.rect.first)
                    };
                    writeln!(out, "{name}  {}", wb.value(s.sheet, s.rect.first))?;
                } else {
                    out.write_all(table(wb, s.sheet, s.rect).as_bytes())?;
                }
            }
        }
        OutputFormat::Csv => {
            for s in selections {
                let what = Export { sheet: s.sheet, range: Some(s.rect), content: Content::Values };
                csv::write(wb, &what, out)?;
            }
        }
        OutputFormat::Json => writeln!(out, "{}", json(wb, selections))?,
    }
    Ok(())
}

/// A grid with column letters on top and row numbers on the left. Numbers are right-aligned,
/// everything else left-aligned.
pub fn table(wb: &Workbook, sheet: SheetId, rect: Rect) -> String {
    let n_cols = rect.cols() as usize;
    let mut rows: Vec<Vec<(String, bool)>> = Vec::with_capacity(rect.rows() as usize + 1);
    let header = std::iter::once((String::new(), true))
        .chain((rect.first.col..=rect.last.col).map(|c| (column_name(c), false)))
        .collect();
    rows.push(header);
    for row in rect.first.row..=rect.last.row {
        let mut line = Vec::with_capacity(n_cols + 1);
        line.push(((row + 1).to_string(), true));
        for col in rect.first.col..=rect.last.col {
            let v = wb.value(sheet, Pos::new(row, col));
            line.push((one_line(&v.to_string()), matches!(v, Value::Number(_))));
        }
        rows.push(line);
    }
    let mut widths = vec![0; n_cols + 1];
    for line in &rows {
        for (w, (text, _)) in widths.iter_mut().zip(line) {
            *w = (*w).max(text.chars().count());
        }
    }
    let mut out = String::new();
    for line in &rows {
        let mut text = String::new();
        for (i, ((cell, right), w)) in line.iter().zip(&widths).enumerate() {
            if i > 0 {
                text.push_str("  ");
            }
            let pad = " ".repeat(w - cell.chars().count());
            if *right {
                text.push_str(&pad);
                text.push_str(cell);
            } else {
                text.push_str(cell);
                text.push_str(&pad);
            }
        }
        out.push_str(text.trim_end());
        out.push('\n');
    }
    out
}

/// Line breaks inside a cell would break the table's rows apart.
fn one_line(text: &str) -> String {
    if text.contains(['\n', '\r']) {
        text.replace("\r\n", "⏎").replace(['\n', '\r'], "⏎")
    } else {
        text.to_string()
    }
}

/// `{"Sheet1!A1": 40, …}` over the non-blank cells of the selections, row by row, each once.
fn json(wb: &Workbook, selections: &[Selection]) -> String {
    let mut seen = HashSet::new();
    let mut fields = Vec::new();
    for s in selections {
        for (pos, value) in wb.values(s.sheet) {
            if s.rect.contains(pos) && seen.insert((s.sheet, pos)) {
                let key = serde_json::Value::String(wb.cell_name(s.sheet, pos));
                fields.push(format!("{key}: {}", json_value(&value)));
            }
        }
    }
    format!("{{{}}}", fields.join(", "))
}

fn json_value(v: &Value) -> serde_json::Value {
    match v {
        // Whole numbers print without a fraction (40, not 40.0); others to 15 digits as shown.
        Value::Number(n) if n.fract() == 0.0 && n.abs() < 9.0e15 => serde_json::Value::from(*n as i64),
        Value::Number(n) => serde_json::Number::from_f64(round15(*n))
            .map_or_else(|| serde_json::Value::String(v.to_string()), serde_json::Value::Number),
        Value::Bool(b) => serde_json::Value::Bool(*b),
        Value::Array(a) => a.data.first().map_or(serde_json::Value::Null, json_value),
        Value::Blank => serde_json::Value::Null,
        Value::Text(_) | Value::Error(_) => serde_json::Value::String(v.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_aligns_numbers_right_and_text_left() {
        let mut wb = Workbook::with_sheet();
        wb.set_input(0, Pos::new(0, 0), "D").unwrap();
        wb.set_input(0, Pos::new(0, 1), "40").unwrap();
        wb.set_input(0, Pos::new(1, 0), "alpha").unwrap();
        wb.set_input(0, Pos::new(1, 1), "4.5").unwrap();
        let rect = Rect::new(Pos::new(0, 0), Pos::new(1, 1));
        assert_eq!(table(&wb, 0, rect), "   A      B\n1  D       40\n2  alpha  4.5\n");
    }

    #[test]
    fn json_keys_name_the_sheet_and_skip_blanks() {
        let mut wb = Workbook::with_sheet();
        wb.set_input(0, Pos::new(0, 0), "x").unwrap();
        wb.set_input(0, Pos::new(2, 0), "=1/0").unwrap();
        wb.set_input(0, Pos::new(2, 1), "TRUE").unwrap();
        let all = Selection { sheet: 0, rect: Rect::new(Pos::new(0, 0), Pos::new(5, 5)) };
        assert_eq!(json(&wb, &[all]), r##"{"Sheet1!A1": "x", "Sheet1!A3": "#DIV/0!", "Sheet1!B3": true}"##);
    }
}
