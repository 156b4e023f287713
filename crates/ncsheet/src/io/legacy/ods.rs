//! OpenDocument spreadsheets (`.ods`, ODF 1.2+ with OpenFormula): calamine reads the cells,
//! the values the file stored and each formula's text; the text is OpenFormula (`of:=SUM([.A1:.B2];2)`)
//! and is spelled here as an xlsx file spells it (`SUM(A1:B2,2)`): references in brackets,
//! `;` between arguments, `~` for union, `!` for intersection, inline arrays with `;` between
//! columns and `|` between rows, and the namespaces LibreOffice puts on Excel's newer functions.

use std::io::Cursor;

use calamine::{Data, Ods, Reader};

use crate::eval::Value;
use crate::formula::address::{MAX_COLS, MAX_ROWS};
use crate::io::limits::ReadLimits;
use crate::io::xlsx::xml::{self, Event, StreamError, TagKind};
use crate::io::xlsx::{check_entry_names, Inflating};
use crate::workbook::{WorkbookError, MAX_SHEETS};

use crate::io::notes::{quoted, Grouped};

use super::{calamine_sheet, cells_named, quoted_sheet, value_of, Book, Name, MAX_CELLS, MAX_TEXT};

/// Reads an .ods file's bytes into a [`Book`]; content.xml inflates within `limits`.
pub fn read(bytes: &[u8], limits: ReadLimits) -> Result<Book, String> {
    measure_content(bytes, limits)?;
    let mut ods: Ods<_> = Ods::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let application = ods.workbook_properties().ok().and_then(|p| p.application);
    let mut book = Book { application, ..Book::default() };
    let metadata = ods.sheets_metadata().to_vec();
    for meta in &metadata {
        let values = ods.worksheet_range(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let formulas = ods.worksheet_formula(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let mut sheet = calamine_sheet(meta, &values, ods_value);
        let (r0, c0) = formulas.start().unwrap_or((0, 0));
        let mut unread = Vec::new();
        for (r, c, text) in formulas.used_cells() {
            if text.is_empty() {
                continue;
            }
            let pos = (r0 + r as u32, c0 + c as u32);
            let cell = sheet.cells.entry(pos).or_default();
            match to_xlsx(text) {
                Some(formula) => cell.formula = Some(formula),
                None => unread.push(pos),
            }
        }
        if !unread.is_empty() {
            book.notes.push(format!(
                "{} formula cells of sheet '{}' keep the value the file stored, as a constant: ncsheet does not read \
                 their OpenFormula ({})",
                unread.len(),
                meta.name,
                cells_named(&meta.name, &unread)
            ));
        }
        book.sheets.push(sheet);
    }
    let mut left_out = Grouped::default();
    for (name, text) in ods.defined_names() {
        let formula = if text.starts_with("of:") { to_xlsx(text) } else { range_address(text) };
        match formula {
            Some(formula) => book.names.push(Name { name: name.clone(), formula, sheet: None }),
            None => left_out.push(format!(
                "name {} ({}) was left out: ncsheet does not read it",
                quoted(name),
                quoted(text)
            )),
        }
    }
    left_out.finish("defined names were left out", &mut book.notes);
    book.notes.push("number formats are not read from an .ods file: values show as General".into());
    Ok(book)
}

/// content.xml measured before calamine reads it: calamine holds each sheet whole, every
/// slot from its first used cell to its last (A1 and XFD6000 are 98 million), copies a
/// repeated cell's text for each repeat (`number-columns-repeated`, `number-rows-repeated`)
/// and writes out `<text:s text:c="N"/>` as N spaces. A file whose sheets would hold more
/// than [`MAX_CELLS`] slots or [`MAX_TEXT`] bytes of text is refused here, naming the sheet.
fn measure_content(bytes: &[u8], limits: ReadLimits) -> Result<(), String> {
    const PART: &str = "content.xml";
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    // Two entries of one name would leave calamine and other readers to differ.
    check_entry_names(&zip, bytes).map_err(|(entry, why)| format!("{entry}: {why}"))?;
    let Ok(entry) = zip.by_name(PART) else { return Ok(()) };
    let mut extent = Extent::default();
    xml::stream(Inflating::new(entry, limits), &mut |event| extent.take(event)).map_err(|e| match e {
        StreamError::Io(e) => format!("{PART}: {e}"),
        StreamError::Xml { offset, message } => format!("{PART}: at byte {offset}: {message}"),
        StreamError::Handler(message) => format!("{PART}: {message}"),
    })
}

/// What calamine will hold of the sheets read so far.
#[derive(Default)]
struct Extent {
    sheet: String,
    /// The current row's first row and how many it repeats for.
    row: u64,
    rows: u64,
    col: u64,
    /// The column after the current row's last used cell: calamine holds the row's cells
    /// up to it.
    row_end: u64,
    /// The open cell: its repeats, whether it holds a value or a formula, its text's bytes.
    cell: Option<(u64, bool, u64)>,
    /// The current sheet's used rows and columns (first, last).
    used: Option<((u64, u64), (u64, u64))>,
    /// Slots of the sheets before, and of the rows of this one as read.
    slots: u64,
    row_slots: u64,
    text: u64,
    /// The repeat that carried the sheet's rows past its last one, and the row it starts
    /// at; the one that carried the current row's cells past its last column, and the column
    /// it starts at. A cell beyond them is named by them, not by a place counted past the
    /// edge (a count of 2^64 - 1 columns made "column 18446744073709551615").
    rows_crossed: Option<(u64, u64)>,
    cols_crossed: Option<(u64, u64)>,
    /// Whether a `table:table` is open: a sheet.
    in_table: bool,
    /// The sheets begun so far.
    sheets: usize,
}

/// The attributes that give a cell a value (calamine keeps a cell without any as empty).
const VALUE_ATTRIBUTES: [&str; 7] =
    ["value-type", "value", "string-value", "date-value", "time-value", "boolean-value", "formula"];

impl Extent {
    fn take(&mut self, event: Event) -> Result<(), String> {
        if let Some(bad) = xml::bad_reference_in(&event) {
            // calamine would say only "unrecognized entity", naming no part.
            return Err(format!("the XML is not well-formed: {bad}"));
        }
        let tag = match event {
            Event::Text(text) | Event::CData(text) => {
                if let Some(cell) = &mut self.cell {
                    cell.2 += text.len() as u64;
                }
                return Ok(());
            }
            Event::Tag(tag) => tag,
        };
        // A count calamine cannot parse stops it naming no place: refused here, naming it.
        let sheet = &self.sheet;
        let count = |key: &str| match tag.attr(key) {
            None => Ok(1),
            Some(raw) => tag
                .parsed::<u64>(key)
                .ok_or_else(|| format!("sheet '{sheet}': {key}=\"{}\" is not a count", String::from_utf8_lossy(raw))),
        };
        match (tag.name, tag.kind) {
            (b"table", TagKind::Start) if self.in_table => return Err(self.nested_table()),
            (b"table", TagKind::Start) => {
                self.sheet = tag.attr("name").map(xml::unescape).unwrap_or_default();
                // Before calamine reads any (200,000 one-cell sheets took 8.7 s and 650 MB, and
                // the refusal named an xlsx part).
                if self.sheets == MAX_SHEETS {
                    return Err(format!("sheet '{}': {}", self.sheet, WorkbookError::TooManySheets));
                }
                self.sheets += 1;
                (self.row, self.used, self.rows_crossed, self.in_table) = (0, None, None, true);
            }
            (b"table", TagKind::End) => {
                self.in_table = false;
                self.end_sheet()?
            }
            (b"table-row", TagKind::Start | TagKind::Empty) => {
                (self.rows, self.col, self.row_end) = (count("number-rows-repeated")?, 0, 0);
                self.cols_crossed = None;
                if self.rows_crossed.is_none() && repeat_crosses(self.row, self.rows, u64::from(MAX_ROWS)) {
                    self.rows_crossed = Some((self.rows, self.row));
                }
                if tag.kind == TagKind::Empty {
                    self.row = self.row.saturating_add(self.rows);
                }
            }
            (b"table-row", TagKind::End) => {
                self.row_slots = self.row_slots.saturating_add(self.row_end);
                self.row = self.row.saturating_add(self.rows);
                self.check()?;
            }
            (b"table-cell" | b"covered-table-cell", TagKind::Start | TagKind::Empty) => {
                let used = VALUE_ATTRIBUTES.iter().any(|key| tag.attr(key).is_some());
                let text = ["string-value", "formula"].iter().filter_map(|key| tag.attr(key)).map(|v| v.len() as u64);
                self.cell = Some((count("number-columns-repeated")?, used, text.sum()));
                if tag.kind == TagKind::Empty {
                    self.end_cell()?;
                }
            }
            (b"table-cell" | b"covered-table-cell", TagKind::End) => self.end_cell()?,
            (b"s", TagKind::Start | TagKind::Empty) => {
                if let Some(cell) = &mut self.cell {
                    cell.2 = cell.2.saturating_add(count("c")?);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Why a table inside a sheet (in a cell, or a shape's text box: ODF lets text hold a
    /// table) is refused: calamine reads its rows as the sheet's own and stops the sheet at
    /// its end, so the sheet's later rows would be lost without a word.
    fn nested_table(&self) -> String {
        let place = match self.cell {
            Some(_) => format!("the cell at row {}, column {}", self.row.saturating_add(1), self.col.saturating_add(1)),
            None => format!("the sheet near row {}", self.row.saturating_add(1)),
        };
        format!(
            "sheet '{}': {place} holds a table of its own (a table:table inside the sheet's), which ncsheet does not \
             read: the sheet's cells after it would be lost; move its cells onto the sheet in LibreOffice and save again",
            self.sheet
        )
    }

    /// Counts the cell just read; one holding a value past the sheet's edge is refused, as
    /// calamine's sheet would drop it without a word.
    fn end_cell(&mut self) -> Result<(), String> {
        let Some((repeats, used, text)) = self.cell.take() else { return Ok(()) };
        let last_col = self.col.saturating_add(repeats.max(1) - 1);
        if used {
            let last_row = self.row.saturating_add(self.rows.max(1) - 1);
            self.within_the_sheet(last_row, last_col)?;
            let ((r0, r1), (c0, c1)) = self.used.unwrap_or(((self.row, last_row), (self.col, last_col)));
            self.used = Some(((r0.min(self.row), r1.max(last_row)), (c0.min(self.col), c1.max(last_col))));
            self.row_end = last_col.saturating_add(1);
            self.text = self.text.saturating_add(text.saturating_mul(repeats).saturating_mul(self.rows));
        }
        if self.cols_crossed.is_none() && repeat_crosses(self.col, repeats, u64::from(MAX_COLS)) {
            self.cols_crossed = Some((repeats, self.col));
        }
        self.col = last_col.saturating_add(1);
        Ok(())
    }

    /// An error naming the first place past the sheet's edge that the cell just read fills
    /// (LibreOffice warns that the data could not be loaded completely, and drops it).
    fn within_the_sheet(&self, last_row: u64, last_col: u64) -> Result<(), String> {
        let (rows, cols) = (u64::from(MAX_ROWS), u64::from(MAX_COLS));
        if last_row < rows && last_col < cols {
            return Ok(());
        }
        let sheet = &self.sheet;
        // Past the first row or column beyond the edge: the repeat that went past is named.
        if let (true, Some((count, from))) = (self.row > rows, self.rows_crossed) {
            return Err(format!(
                "sheet '{sheet}': a cell holding a value lies past the last row of a sheet ({MAX_ROWS}), where it would \
                 be lost: the rows before it repeat past it (number-rows-repeated=\"{count}\" from row {})",
                from + 1
            ));
        }
        if let (true, Some((count, from))) = (self.col > cols, self.cols_crossed) {
            return Err(format!(
                "sheet '{sheet}': a cell holding a value in row {} lies past the last column of a sheet ({MAX_COLS}), \
                 where it would be lost: the cells before it repeat past it (number-columns-repeated=\"{count}\" \
                 from column {})",
                self.row + 1,
                from + 1
            ));
        }
        let (row, col) = if last_row >= rows { (self.row.max(rows), self.col) } else { (self.row, self.col.max(cols)) };
        Err(format!(
            "sheet '{}': a cell holding a value at row {}, column {} lies past the edge of a sheet ({MAX_ROWS} rows \
             and {MAX_COLS} columns), where it would be lost",
            self.sheet,
            row.saturating_add(1),
            col.saturating_add(1)
        ))
    }

    /// The sheet's used area is held whole, each of its rows repeated as often as it says.
    fn end_sheet(&mut self) -> Result<(), String> {
        if let Some(((r0, r1), (c0, c1))) = self.used.take() {
            let (rows, cols) = ((r1 - r0).saturating_add(1), (c1 - c0).saturating_add(1));
            let area = rows.saturating_mul(cols);
            self.slots = self.slots.saturating_add(area);
            if self.slots > MAX_CELLS as u64 {
                return Err(format!(
                    "sheet '{}' spans {} rows and {} columns from its first used cell to its last: with the sheets \
                     before it, more than {MAX_CELLS} cells, ncsheet's limit on the cells of a file it converts (an \
                     .ods sheet is held whole, blanks between its cells included)",
                    self.sheet, rows, cols
                ));
            }
        }
        self.row_slots = 0;
        self.check()
    }

    fn check(&self) -> Result<(), String> {
        if self.slots.saturating_add(self.row_slots) > MAX_CELLS as u64 {
            return Err(format!(
                "sheet '{}' holds more than {MAX_CELLS} cells, ncsheet's limit on the cells of a file it converts",
                self.sheet
            ));
        }
        if self.text > MAX_TEXT as u64 {
            return Err(format!(
                "sheet '{}': the cells hold more than {} MiB of text (each repeat of a cell counted), ncsheet's limit \
                 on the text of a file it converts",
                self.sheet,
                MAX_TEXT >> 20
            ));
        }
        Ok(())
    }
}

/// Whether a repeat of `count` places from `start` reaches at or past `edge` from before it.
/// A single place (no repeat attribute, or a count of 1) is no repeat: naming it as one in
/// the error would cite an attribute the file does not have.
fn repeat_crosses(start: u64, count: u64, edge: u64) -> bool {
    count > 1 && start < edge && start.saturating_add(count) >= edge
}

/// A stored value; dates and times (ISO 8601 text in the file) as Excel's serial numbers.
fn ods_value(data: &Data) -> Option<Value> {
    match data {
        Data::DateTimeIso(text) => {
            Some(iso_date(text).map_or_else(|| Value::Text(text.as_str().into()), Value::Number))
        }
        Data::DurationIso(text) => {
            Some(iso_duration(text).map_or_else(|| Value::Text(text.as_str().into()), Value::Number))
        }
        other => value_of(other),
    }
}

/// `2024-03-01` or `2024-03-01T12:30:00` as a serial.
fn iso_date(text: &str) -> Option<f64> {
    let (date, time) = text.split_once('T').unwrap_or((text, ""));
    let mut parts = date.splitn(3, '-');
    let year: i64 = parts.next()?.parse().ok()?;
    let month: i64 = parts.next()?.parse().ok()?;
    let day: i64 = parts.next()?.parse().ok()?;
    // An imported .ods workbook counts in the 1900 system (the reader sets no other).
    let serial = crate::eval::dates::serial_from_ymd(crate::eval::dates::DateSystem::From1900, year, month, day) as f64;
    let fraction = if time.is_empty() {
        0.0
    } else {
        let mut t = time.split(':');
        let h: f64 = t.next()?.parse().ok()?;
        let m: f64 = t.next().unwrap_or("0").parse().ok()?;
        let s: f64 = t.next().unwrap_or("0").parse().ok()?;
        (h * 3600.0 + m * 60.0 + s) / 86400.0
    };
    Some(serial + fraction)
}

/// `PT12H30M00S` (a time) as a fraction of a day.
fn iso_duration(text: &str) -> Option<f64> {
    let negative = text.starts_with('-');
    let rest =
        text.trim_start_matches('-').strip_prefix("PT").or_else(|| text.trim_start_matches('-').strip_prefix('P'))?;
    let mut seconds = 0.0;
    let mut number = String::new();
    for c in rest.chars() {
        match c {
            'D' => seconds += number.parse::<f64>().ok()? * 86400.0,
            'H' => seconds += number.parse::<f64>().ok()? * 3600.0,
            'M' => seconds += number.parse::<f64>().ok()? * 60.0,
            'S' => seconds += number.parse::<f64>().ok()?,
            'T' => {}
            c => {
                number.push(c);
                continue;
            }
        }
        number.clear();
    }
    let days = seconds / 86400.0;
    Some(if negative { -days } else { days })
}

/// An OpenFormula (`of:=…`) as an xlsx file spells the formula, or `None` for what has no
/// spelling there (a reference into another file).
pub fn to_xlsx(text: &str) -> Option<String> {
    let body = text.strip_prefix("of:").unwrap_or(text);
    let body = body.strip_prefix('=').unwrap_or(body);
    let chars: Vec<char> = body.chars().collect();
    let mut out = String::with_capacity(body.len());
    let mut in_array = 0usize;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        match c {
            '"' => {
                let end = closing_quote(&chars, i, '"');
                out.extend(&chars[i..end]);
                i = end;
                continue;
            }
            '[' => {
                let end = chars[i..].iter().position(|&c| c == ']').map(|p| i + p)?;
                let inner: String = chars[i + 1..end].iter().collect();
                out.push_str(&reference(&inner)?);
                i = end + 1;
                continue;
            }
            '{' => in_array += 1,
            '}' => in_array = in_array.saturating_sub(1),
            ';' if in_array > 0 => {
                out.push(',');
                i += 1;
                continue;
            }
            '|' if in_array > 0 => {
                out.push(';');
                i += 1;
                continue;
            }
            ';' => {
                out.push(',');
                i += 1;
                continue;
            }
            '~' => {
                out.push(',');
                i += 1;
                continue;
            }
            '!' => {
                out.push(' ');
                i += 1;
                continue;
            }
            c if c.is_alphabetic() || c == '_' => {
                let end = chars[i..]
                    .iter()
                    .position(|&c| !(c.is_alphanumeric() || c == '_' || c == '.'))
                    .map_or(chars.len(), |p| i + p);
                let word: String = chars[i..end].iter().collect();
                let is_call = chars.get(end) == Some(&'(');
                out.push_str(&if is_call { function_name(&word) } else { word });
                i = end;
                continue;
            }
            _ => {}
        }
        out.push(c);
        i += 1;
    }
    Some(out)
}

/// The index just past a quoted run starting at `start` (a doubled quote stays inside).
fn closing_quote(chars: &[char], start: usize, quote: char) -> usize {
    let mut i = start + 1;
    while i < chars.len() {
        if chars[i] == quote {
            if chars.get(i + 1) == Some(&quote) {
                i += 2;
                continue;
            }
            return i + 1;
        }
        i += 1;
    }
    chars.len()
}

/// A function's OpenFormula name as Excel's: LibreOffice writes Excel's newer functions with
/// a namespace (`COM.MICROSOFT.IFS`), and a few under names of its own.
fn function_name(word: &str) -> String {
    let upper = word.to_ascii_uppercase();
    for prefix in ["COM.MICROSOFT.", "_XLFN.", "ORG.OPENOFFICE.", "LEGACY."] {
        if let Some(rest) = upper.strip_prefix(prefix) {
            return function_name(rest);
        }
    }
    match upper.as_str() {
        "CEILING.XCL" => "CEILING",
        "FLOOR.XCL" => "FLOOR",
        "CHISQDIST" => "CHIDIST",
        "CHISQINV" => "CHIINV",
        "NORMSDIST" | "NORMSINV" | "CHIDIST" | "CHIINV" | "TDIST" | "FDIST" | "FINV" => return upper,
        _ => return word.to_string(),
    }
    .to_string()
}

/// A bracketed OpenFormula reference (`.A1`, `.A1:.B2`, `$'My sheet'.A1:.B2`,
/// `Sheet1.A1:Sheet3.A1`) as A1 text with its sheet; `None` for another file's.
fn reference(inner: &str) -> Option<String> {
    if inner.starts_with('\'') && inner.contains('#') && !inner.starts_with("'#") {
        // 'file:///…'#$Sheet1.A1: another document.
        let quoted_end = closing_quote(&inner.chars().collect::<Vec<_>>(), 0, '\'');
        if inner.chars().nth(quoted_end) == Some('#') {
            return None;
        }
    }
    let parts = split_outside_quotes(inner, ':');
    let mut sheets = Vec::new();
    let mut cells = Vec::new();
    for part in &parts {
        let (sheet, cell) = split_sheet(part);
        sheets.push(sheet);
        cells.push(cell);
    }
    let first_sheet = sheets.first().cloned().flatten();
    let last_sheet = sheets.last().cloned().flatten();
    let prefix = match (&first_sheet, &last_sheet) {
        (Some(a), Some(b)) if a != b => {
            let both = format!("{a}:{b}");
            if quoted_sheet(a).starts_with('\'') || quoted_sheet(b).starts_with('\'') {
                format!("'{}'!", both.replace('\'', "''"))
            } else {
                format!("{both}!")
            }
        }
        (Some(a), _) => format!("{}!", quoted_sheet(a)),
        _ => String::new(),
    };
    let cells = cells.join(":");
    if cells.contains("#REF!") {
        return Some("#REF!".into());
    }
    Some(format!("{prefix}{cells}"))
}

/// A named range's address as LibreOffice stores it (`$Sheet1.$A$1:.$B$2`).
fn range_address(text: &str) -> Option<String> {
    reference(text)
}

/// `$Sheet.A1` → (Some("Sheet"), "A1"); `.A1` → (None, "A1").
fn split_sheet(part: &str) -> (Option<String>, String) {
    let part = part.trim();
    let chars: Vec<char> = part.chars().collect();
    let mut i = 0;
    if chars.first() == Some(&'$') {
        i = 1;
    }
    if chars.get(i) == Some(&'\'') {
        let end = closing_quote(&chars, i, '\'');
        let name: String = chars[i + 1..end - 1].iter().collect::<String>().replace("''", "'");
        let cell: String = chars.get(end + 1..).map(|c| c.iter().collect()).unwrap_or_default();
        return (Some(name), cell);
    }
    match part[i..].rfind('.') {
        Some(0) => (None, part[i + 1..].to_string()),
        Some(dot) => (Some(part[i..i + dot].to_string()), part[i + dot + 1..].to_string()),
        None => (None, part.to_string()),
    }
}

fn split_outside_quotes(text: &str, sep: char) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    for c in text.chars() {
        if c == '\'' {
            quoted = !quoted;
        }
        if c == sep && !quoted {
            out.push(String::new());
        } else {
            out.last_mut().expect("one part").push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_formula_is_spelled_as_excel_spells_it() {
        assert_eq!(to_xlsx("of:=SUM([.A1:.B2];2)").unwrap(), "SUM(A1:B2,2)");
        assert_eq!(to_xlsx("of:=[$'My sheet'.$A$1]+[$Data.B2:.C3]").unwrap(), "'My sheet'!$A$1+Data!B2:C3");
        assert_eq!(to_xlsx("of:={1;2|3;4}").unwrap(), "{1,2;3,4}");
        assert_eq!(to_xlsx("of:=IF([.A1]=\"a;b\";1;2)").unwrap(), "IF(A1=\"a;b\",1,2)");
        assert_eq!(to_xlsx("of:=COM.MICROSOFT.IFS([.A1]>1;1)").unwrap(), "IFS(A1>1,1)");
        assert_eq!(to_xlsx("of:=SUM([.A:.A])").unwrap(), "SUM(A:A)");
        assert_eq!(to_xlsx("of:=['file:///x.ods'#$Sheet1.A1]"), None);
        assert_eq!(range_address("$Sheet1.$A$1:.$B$2").unwrap(), "Sheet1!$A$1:$B$2");
    }

    #[test]
    fn dates_and_times_become_serials() {
        assert_eq!(iso_date("1900-03-01"), Some(61.0));
        assert_eq!(iso_date("2024-01-01T12:00:00"), Some(45292.5));
        assert_eq!(iso_duration("PT12H30M00S"), Some(0.5208333333333334));
    }
}
