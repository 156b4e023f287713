//! Printing values: an aligned table for people, csv and JSON for programs.

use std::cell::RefCell;
use std::collections::HashSet;
use std::io::{self, Write};
use std::path::Path;

use clap::ValueEnum;
use ncsheet::eval::format::number_format::{round15, ShownFormats};
use ncsheet::eval::Value;
use ncsheet::formula::address::{column_name, Pos, Rect};
use ncsheet::formula::ast::SheetId;
use ncsheet::io::xlsx::Layout;
use ncsheet::io::{csv, Content, Export};
use ncsheet::workbook::{LooksByCell, Workbook};

use super::report::Result;

/// How `eval` prints values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum OutputFormat {
    /// Columns aligned under their letters, rows numbered; numbers as their cell's number
    /// format shows them (15 significant digits without one; --raw: in full)
    #[default]
    Table,
    /// The cells as comma-separated csv rows, values as `ncsheet export` writes them
    Csv,
    /// One object {"Sheet1!A1": value, …}: numbers, strings, booleans, errors as "#…" text;
    /// blank cells left out
    Json,
}

/// Cells or ranges on a resolved sheet; `label` is the defined name the user typed.
pub struct Selection {
    pub sheet: SheetId,
    pub rect: Rect,
    pub label: Option<String>,
}

/// How a table shows values: as the cells' number formats show them (from an .xlsx), or in
/// full (`--raw`); formulas instead of values; within `width` columns when there is a limit
/// (a terminal's width, or `--width`).
pub struct Shown<'a> {
    pub layout: Option<&'a Layout>,
    pub raw: bool,
    pub formulas: bool,
    pub width: Option<usize>,
    /// The number formats shown so far, each parsed once for all the cells that have it.
    pub parsed: RefCell<ShownFormats>,
}

impl Default for Shown<'_> {
    fn default() -> Self {
        Shown { layout: None, raw: false, formulas: false, width: terminal_width(), parsed: RefCell::default() }
    }
}

impl Shown<'_> {
    /// The text of one cell: its formula, its value under its number format, or the value
    /// in full.
    pub fn text(&self, wb: &Workbook, sheet: SheetId, pos: Pos) -> String {
        // In the user's locale (`1 234,5`, `=ROUND(A1;2)`); en-US as files spell them.
        let locale = wb.settings().locale;
        if self.formulas {
            if let Some(f) = wb.formula(sheet, pos) {
                return locale.local_formula(&f);
            }
        }
        match wb.value(sheet, pos) {
            Value::Number(n) if self.raw => locale.localize_shown(&format!("{n}")),
            // Excel's built-in date (14, `mm-dd-yy` as the file's reader names it) is the
            // locale's short date, en-US's `m/d/yyyy` included.
            Value::Number(n) => {
                let code = self.format_code(wb, sheet, pos);
                locale.shown_number_with(&mut self.parsed.borrow_mut(), n, code, wb.date_system())
            }
            // Booleans in the locale's words (de-DE `WAHR`), as its Excel shows them.
            v => locale.shown_value(&v),
        }
    }

    /// The cell's number format code, when the file gave it one other than General.
    pub fn format_code<'b>(&'b self, wb: &Workbook, sheet: SheetId, pos: Pos) -> Option<&'b str> {
        self.formats(wb, sheet)?.get(&pos).map(String::as_str)
    }

    /// A sheet's number formats by cell, from the file.
    pub fn formats<'b>(&'b self, wb: &Workbook, sheet: SheetId) -> Option<&'b LooksByCell<String>> {
        let name = wb.sheet_names().into_iter().nth(sheet as usize)?;
        Some(&self.layout?.sheets.get(&name)?.look.number_formats)
    }
}

/// The width of the terminal on stdout; none when stdout is not a terminal (a file, a pipe),
/// whose reader wants every digit however long the lines get.
pub fn terminal_width() -> Option<usize> {
    // SAFETY: TIOCGWINSZ fills a winsize for a terminal and fails harmlessly otherwise.
    let mut size: libc::winsize = unsafe { std::mem::zeroed() };
    let ok = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut size) } == 0;
    (ok && size.ws_col > 0).then_some(size.ws_col as usize)
}

/// Prints a whole sheet, from A1 to its last used row and column.
pub fn print_sheet(
    out: &mut dyn Write,
    wb: &Workbook,
    sheet: SheetId,
    format: OutputFormat,
    shown: &Shown,
) -> Result<()> {
    let Some(used) = wb.used_rect(sheet) else {
        if format == OutputFormat::Json {
            writeln!(out, "{{}}")?;
        }
        return Ok(());
    };
    let whole = Selection { sheet, rect: Rect::new(Pos::new(0, 0), used.last), label: None };
    print_selections(out, wb, sheet, &[whole], format, shown)
}

/// Prints cells and ranges. In a table, one cell alone prints as its value only; several
/// cells print one per line after their names; a range prints as a table.
pub fn print_selections(
    out: &mut dyn Write,
    wb: &Workbook,
    default_sheet: SheetId,
    selections: &[Selection],
    format: OutputFormat,
    shown: &Shown,
) -> Result<()> {
    match format {
        OutputFormat::Table => {
            if let [only] = selections {
                if only.rect.is_cell() {
                    writeln!(out, "{}", shown.text(wb, only.sheet, only.rect.first))?;
                    return Ok(());
                }
            }
            let name = |s: &Selection| match &s.label {
                Some(label) => label.clone(),
                None if s.sheet == default_sheet => s.rect.first.to_string(),
                None => wb.cell_name(s.sheet, s.rect.first),
            };
            // Names padded to the longest, so that the values line up.
            let width = selections.iter().filter(|s| s.rect.is_cell()).map(|s| name(s).chars().count()).max();
            for s in selections {
                if s.rect.is_cell() {
                    let label = name(s);
                    let pad = " ".repeat(width.unwrap_or(0) - label.chars().count());
                    writeln!(out, "{label}{pad}  {}", shown.text(wb, s.sheet, s.rect.first))?;
                } else {
                    out.write_all(table(wb, s.sheet, s.rect, shown).as_bytes())?;
                }
            }
        }
        OutputFormat::Csv => {
            for s in selections {
                let what = Export { sheet: s.sheet, range: Some(s.rect), content: Content::Values };
                // A decimal-comma locale's csv is `;`-separated with decimal commas, as its Excel writes.
                let delimiter = if wb.settings().locale.is_canonical() { b',' } else { b';' };
                let style = csv::Style { delimiter, formats: shown.formats(wb, s.sheet), raw: shown.raw };
                csv::write_with(wb, &what, &style, out)?;
            }
        }
        OutputFormat::Json => writeln!(out, "{}", json(wb, selections))?,
    }
    Ok(())
}

/// A grid with column letters on top and row numbers on the left. Numbers are right-aligned,
/// everything else left-aligned. Within a width limit, text columns are narrowed (their text
/// cut with `…`) when that makes the table fit, else the columns that do not fit beside the
/// first ones come below in further tables, as a spreadsheet prints a wide sheet on several
/// pages; numbers keep every digit.
pub fn table(wb: &Workbook, sheet: SheetId, rect: Rect, shown: &Shown) -> String {
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
            let number = matches!(v, Value::Number(_)) && !(shown.formulas && wb.is_formula(sheet, Pos::new(row, col)));
            line.push((one_line(&shown.text(wb, sheet, Pos::new(row, col))), number));
        }
        rows.push(line);
    }
    let widths = column_widths(&rows, shown.width);
    let mut out = String::new();
    for (k, block) in column_blocks(&widths, shown.width.unwrap_or(usize::MAX)).iter().enumerate() {
        if k > 0 {
            out.push('\n');
        }
        for (r, line) in rows.iter().enumerate() {
            let mut text = String::new();
            for &i in std::iter::once(&0).chain(block) {
                let ((cell, right), w) = (&line[i], widths[i]);
                if i > 0 {
                    text.push_str("  ");
                }
                let cell = if r > 0 && i > 0 { fit_text(cell, w) } else { cell.clone() };
                let pad = " ".repeat(w.saturating_sub(cell.chars().count()));
                if *right {
                    text.push_str(&pad);
                    text.push_str(&cell);
                } else {
                    text.push_str(&cell);
                    text.push_str(&pad);
                }
            }
            out.push_str(text.trim_end());
            out.push('\n');
        }
    }
    out
}

/// Each column's width within `limit`. Text columns are narrowed, widest first, when that
/// makes the whole table fit; when it cannot fit even so, the columns keep their widths (and
/// come in blocks), only a column wider than `limit` on its own narrowed to it. A column is
/// never narrower than its widest number: a number cut would be a wrong number.
fn column_widths(rows: &[Vec<(String, bool)>], limit: Option<usize>) -> Vec<usize> {
    // The column letters, and a little text, stay readable however narrow the limit.
    const MIN: usize = 6;
    let n_cols = rows.first().map_or(0, Vec::len);
    let (mut widths, mut floors) = (vec![0; n_cols], vec![0; n_cols]);
    for line in rows {
        for (i, (text, number)) in line.iter().enumerate() {
            let w = text.chars().count();
            widths[i] = widths[i].max(w);
            if *number {
                floors[i] = floors[i].max(w);
            }
        }
    }
    let Some(limit) = limit else { return widths };
    let floors: Vec<usize> = floors.iter().zip(&widths).map(|(&f, &w)| f.max(MIN).min(w)).collect();
    // Every value column capped at `cap` characters, none below its floor; the labels kept.
    let capped = |cap: usize| -> Vec<usize> {
        let values = widths.iter().zip(&floors).skip(1).map(|(&w, &f)| w.min(cap).max(f));
        widths.iter().take(1).copied().chain(values).collect()
    };
    let total = |w: &[usize]| w.iter().sum::<usize>() + 2 * w.len().saturating_sub(1);
    if total(&capped(0)) > limit {
        let alone = limit.saturating_sub(widths[0] + 2);
        for (w, &f) in widths.iter_mut().zip(&floors).skip(1) {
            *w = (*w).min(alone.max(f));
        }
        return widths;
    }
    // The widest cap that fits: the narrowing takes the widest columns first.
    let (mut fits, mut wide) = (0, widths.iter().copied().max().unwrap_or(0) + 1);
    while wide - fits > 1 {
        let mid = (fits + wide) / 2;
        if total(&capped(mid)) <= limit {
            fits = mid;
        } else {
            wide = mid;
        }
    }
    capped(fits)
}

/// The value columns (1…) in blocks that fit `limit` beside the row labels (column 0): one
/// block when they all fit, and at least one column a block.
fn column_blocks(widths: &[usize], limit: usize) -> Vec<Vec<usize>> {
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    let mut used = 0;
    for (i, &w) in widths.iter().enumerate().skip(1) {
        match blocks.last_mut() {
            Some(block) if used + 2 + w <= limit => {
                block.push(i);
                used += 2 + w;
            }
            _ => {
                blocks.push(vec![i]);
                used = widths[0] + 2 + w;
            }
        }
    }
    blocks
}

/// A cell's text within `width` characters: text cut with `…` (a column is at least as wide
/// as its widest number, so a number is never cut).
fn fit_text(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut cut: String = text.chars().take(width.saturating_sub(1)).collect();
    cut.push('…');
    cut
}

/// Line breaks inside a cell would break the table's rows apart; other control characters
/// would reach the terminal (see [`super::report::printable`]).
fn one_line(text: &str) -> String {
    if text.contains(['\n', '\r']) {
        super::report::printable(&text.replace("\r\n", "⏎").replace(['\n', '\r'], "⏎")).into_owned()
    } else {
        super::report::printable(text).into_owned()
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
        Value::Blank | Value::Null => serde_json::Value::Null,
        Value::Text(_) | Value::Error(_) | Value::Lambda(_) => serde_json::Value::String(v.to_string()),
    }
}

/// A command's text output to a file (through `write_outputs`, so `--force` decides whether
/// an existing file is replaced) or to standard output.
pub fn emit(text: &str, path: Option<&Path>, force: bool) -> Result<()> {
    match path {
        Some(p) => super::write_outputs(&[ncsheet::io::Encoded::new(p, text.as_bytes().to_vec())], false, force),
        None => {
            let mut stdout = io::stdout().lock();
            stdout.write_all(text.as_bytes())?;
            stdout.flush()?;
            Ok(())
        }
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
        assert_eq!(table(&wb, 0, rect, &Shown::default()), "   A      B\n1  D       40\n2  alpha  4.5\n");
    }

    #[test]
    fn json_keys_name_the_sheet_and_skip_blanks() {
        let mut wb = Workbook::with_sheet();
        wb.set_input(0, Pos::new(0, 0), "x").unwrap();
        wb.set_input(0, Pos::new(2, 0), "=1/0").unwrap();
        wb.set_input(0, Pos::new(2, 1), "TRUE").unwrap();
        let all = Selection { sheet: 0, rect: Rect::new(Pos::new(0, 0), Pos::new(5, 5)), label: None };
        assert_eq!(json(&wb, &[all]), r##"{"Sheet1!A1": "x", "Sheet1!A3": "#DIV/0!", "Sheet1!B3": true}"##);
    }
}
