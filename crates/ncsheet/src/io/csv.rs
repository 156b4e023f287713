//! csv files (RFC 4180): one sheet, named `Sheet1`.
//!
//! Reading: each record is a row and each field a cell, typed in as a spreadsheet would read
//! it ([`Input::parse`]): `=…` is a formula, `12.5` a number, `TRUE` a boolean, `'…` forced
//! text, anything else text. A blank line is an empty row, so cell addresses match the line
//! layout a user sees. The file must be UTF-8 (a byte-order mark is skipped).
//!
//! Writing: fields are quoted per RFC 4180, only when needed (`,`, `"`, line breaks); lines
//! end in LF (as files made on Linux do; readers take LF and CRLF alike).
//! Values are written as the sheet shows them (numbers to 15 significant digits). A text
//! value that a spreadsheet would not read back as that same text — one starting with `=`,
//! `+`, `-`, `@`, a tab or a carriage return (which Excel and LibreOffice may run as a
//! formula), or one that looks like a number, boolean or error — is written with a leading
//! `'`, the spreadsheet's own mark for "this is text". ncsheet drops the `'` on reading.
//! With [`Content::Formulas`] each cell is written as typed (`Workbook::input`), which reads
//! back as the same workbook.
//!
//! Saving a csv that was read from a file ([`read_original`], [`write_edited`]) keeps what
//! was typed: every field whose cell was not edited is written back byte for byte (quotes,
//! `007`, `2024-01-10`, `"1,234"`, `50%` stay as they were), each row keeps its own number of
//! fields and its own line ending; only edited cells are written anew.

use std::fmt;
use std::io::{self, Write};

use crate::eval::dates::DateSystem;
use crate::eval::evaluator::MAX_TEXT;
use crate::eval::format::number_format::ShownFormats;
use crate::eval::locale::is_date_code;
use crate::eval::{Locale, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::workbook::{too_long_text, Input, LooksByCell, Workbook, WorkbookError};

use super::limits::ReadLimits;
use super::{Content, Export};

/// What is wrong with a csv text, and on which line (1-based).
#[derive(Clone, Debug, PartialEq)]
pub struct Malformed {
    pub line: u64,
    pub message: String,
}

impl fmt::Display for Malformed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// The name of the one sheet of a csv file.
pub const SHEET_NAME: &str = "Sheet1";

/// Reads csv text into a new, recalculated workbook with one sheet; the delimiter is
/// detected ([`delimiter_of`]).
pub fn read(bytes: &[u8]) -> Result<Workbook, Malformed> {
    read_original(bytes).map(|(wb, _)| wb)
}

/// The text of a csv file as read, row by row and field by field, so that a save writes
/// back untouched fields exactly as they were typed.
#[derive(Clone, Debug, Default)]
pub struct Original {
    bom: bool,
    /// Excel's `sep=;` first line as it stands, its line ending included (empty without
    /// one): no data, written back before the rows.
    directive: String,
    /// `,` or `;`, as detected on reading: untouched fields are joined with it again.
    delimiter: u8,
    rows: Vec<RawRow>,
}

impl Original {
    /// The delimiter the file was read with.
    pub fn delimiter(&self) -> u8 {
        self.delimiter
    }

    /// The places whose field holds something, in row order.
    pub fn filled_places(&self) -> impl Iterator<Item = Pos> + '_ {
        self.rows.iter().enumerate().flat_map(|(r, row)| {
            let filled = row.fields.iter().enumerate().filter(|(_, f)| !f.is_empty());
            filled.map(move |(c, _)| Pos::new(r as u32, c as u32))
        })
    }

    /// The field at `row` and `col` as it stands in the file, quotes included.
    pub fn raw_field(&self, row: usize, col: usize) -> Option<&str> {
        self.rows.get(row)?.fields.get(col).map(String::as_str)
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
struct RawRow {
    /// Each field as it stands in the file, quotes included.
    fields: Vec<String>,
    /// `\n`, `\r\n`, `\r`, or empty for a last line without one.
    ending: String,
}

/// [`read`], also returning the file's text by row and field for [`write_edited`].
pub fn read_original(bytes: &[u8]) -> Result<(Workbook, Original), Malformed> {
    read_original_with(bytes, None)
}

/// [`read_original`] with a given delimiter (`None`: detect it); a save writes it again.
pub fn read_original_with(bytes: &[u8], delimiter: Option<u8>) -> Result<(Workbook, Original), Malformed> {
    read_original_limited(bytes, delimiter, ReadLimits::default())
}

/// [`read_original_with`], its fields and lines held to `limits`.
pub fn read_original_limited(
    bytes: &[u8],
    delimiter: Option<u8>,
    limits: ReadLimits,
) -> Result<(Workbook, Original), Malformed> {
    let bom = bytes.starts_with(b"\xEF\xBB\xBF");
    let wb = read_limited(bytes, delimiter, limits)?;
    let text = std::str::from_utf8(&bytes[if bom { 3 } else { 0 }..]).expect("checked by read_text");
    let delimiter = delimiter.unwrap_or_else(|| delimiter_of(text.as_bytes()));
    let (directive, body) = split_directive(text);
    Ok((wb, Original { bom, directive: directive.to_string(), delimiter, rows: raw_rows(body, delimiter) }))
}

/// Splits csv text into rows (blank lines included) of raw fields, by the rules of
/// [`record_starts`]: a `"` opens a quoted field only at a field's start.
fn raw_rows(text: &str, delimiter: u8) -> Vec<RawRow> {
    let bytes = text.as_bytes();
    let mut rows = Vec::new();
    let mut row = RawRow::default();
    let (mut field_start, mut in_quotes, mut at_field_start) = (0, false, true);
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if in_quotes {
            if b == b'"' {
                if bytes.get(i + 1) == Some(&b'"') {
                    i += 1;
                } else {
                    in_quotes = false;
                }
            }
            i += 1;
            continue;
        }
        let terminator_len = match b {
            b'\r' if bytes.get(i + 1) == Some(&b'\n') => 2,
            b'\r' | b'\n' => 1,
            _ => 0,
        };
        if terminator_len > 0 {
            // A blank line is a row without fields.
            if i > field_start || !row.fields.is_empty() {
                row.fields.push(text[field_start..i].to_string());
            }
            row.ending = text[i..i + terminator_len].to_string();
            rows.push(std::mem::take(&mut row));
            i += terminator_len;
            field_start = i;
            at_field_start = true;
            continue;
        }
        if b == delimiter {
            row.fields.push(text[field_start..i].to_string());
            field_start = i + 1;
            at_field_start = true;
        } else {
            in_quotes = at_field_start && b == b'"';
            at_field_start = false;
        }
        i += 1;
    }
    if field_start < bytes.len() || !row.fields.is_empty() {
        row.fields.push(text[field_start..].to_string());
        rows.push(row);
    }
    rows
}

/// Writes the one sheet of a workbook read by [`read_original`]: the original text with
/// only the cells listed in `edited` written anew (as typed, quoted where needed; a typed
/// date or time as its cell shows it, by `formats`, the sheet's number formats).
pub fn write_edited(
    wb: &Workbook,
    original: &Original,
    edited: &[Pos],
    formats: Option<&LooksByCell<String>>,
    out: &mut dyn Write,
) -> io::Result<()> {
    let style = Style { delimiter: original.delimiter, formats, raw: false };
    let mut rows = original.rows.clone();
    let ending = rows.first().map_or("\n", |r| if r.ending.is_empty() { "\n" } else { r.ending.as_str() }).to_string();
    for &pos in edited {
        let shown_date = typed_date(wb, &style, pos);
        let typed = shown_date.is_none();
        let text = shown_date.unwrap_or_else(|| wb.input(0, pos).unwrap_or_default());
        let (r, c) = (pos.row as usize, pos.col as usize);
        if r >= rows.len() {
            if text.is_empty() {
                continue;
            }
            if let Some(last) = rows.last_mut().filter(|l| l.ending.is_empty()) {
                last.ending = ending.clone();
            }
            let blank = RawRow { fields: Vec::new(), ending: ending.clone() };
            rows.resize(r + 1, blank);
        }
        let row = &mut rows[r];
        if c >= row.fields.len() {
            if text.is_empty() {
                continue;
            }
            row.fields.resize(c + 1, String::new());
        }
        // A date already is as the locale shows it; anything else is written as typed there.
        let text = if original.delimiter == b';' && typed { locale_input(&text, wb.settings().locale) } else { text };
        row.fields[c] = quoted(&text, original.delimiter);
    }
    if original.bom {
        out.write_all(b"\xEF\xBB\xBF")?;
    }
    let mut buf = io::BufWriter::new(out);
    buf.write_all(original.directive.as_bytes())?;
    for row in &rows {
        buf.write_all(row.fields.join(&char::from(original.delimiter).to_string()).as_bytes())?;
        buf.write_all(row.ending.as_bytes())?;
    }
    buf.flush()
}

/// A constant number under a date or time format (`14:30`, `12.03.2025` typed), as the cell
/// shows it: its serial would read back as a plain number, the date lost, where Excel and
/// LibreOffice write a date cell as shown.
fn typed_date(wb: &Workbook, style: &Style, pos: Pos) -> Option<String> {
    let is_date = style.formats.and_then(|f| f.get(&pos)).is_some_and(|code| is_date_code(code));
    if !is_date || wb.is_formula(0, pos) {
        return None;
    }
    let Value::Number(n) = wb.value(0, pos) else { return None };
    Some(style.field(&Value::Number(n), pos, wb, &mut ShownFormats::default()))
}

/// A field as RFC 4180 writes it: quoted when it holds the delimiter, a quote or a line break.
fn quoted(text: &str, delimiter: u8) -> String {
    if text.contains([char::from(delimiter), '"', '\r', '\n']) || text.starts_with(' ') || text.ends_with(' ') {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// [`read`] with a given delimiter (`None`: detect it). In a `;`-separated file, written by
/// a spreadsheet whose locale writes decimal commas, `0,8` is the number 0.8.
pub fn read_with(bytes: &[u8], delimiter: Option<u8>) -> Result<Workbook, Malformed> {
    read_limited(bytes, delimiter, ReadLimits::default())
}

/// [`read_with`], its fields and lines held to `limits`.
pub fn read_limited(bytes: &[u8], delimiter: Option<u8>, limits: ReadLimits) -> Result<Workbook, Malformed> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() as u64;
        Malformed { line, message: "not UTF-8 text (save the csv as UTF-8)".into() }
    })?;
    let delimiter = delimiter.unwrap_or_else(|| delimiter_of(text.as_bytes()));
    let (directive, text) = split_directive(text);
    // Lines are named as they stand in the file, the directive's first.
    let after_directive = |m: Malformed| Malformed { line: m.line + u64::from(!directive.is_empty()), ..m };
    read_body(text, delimiter, limits).map_err(after_directive)
}

/// Excel's delimiter directive, a first line `sep=;` (any one character after `sep=`): the
/// file's delimiter, said by its writer. Excel reads it so and takes the line for no data.
fn directive_delimiter(text: &str) -> Option<u8> {
    let (line, _) = split_line(text);
    match line.strip_prefix("sep=")?.as_bytes() {
        &[b] if b != b'"' && !b.is_ascii_alphanumeric() => Some(b),
        _ => None,
    }
}

/// The first line of `text` and the rest, the line's ending with neither.
fn split_line(text: &str) -> (&str, &str) {
    let end = text.find(['\r', '\n']).unwrap_or(text.len());
    (&text[..end], &text[end..])
}

/// `text` split into Excel's delimiter directive (with its line ending; empty without one)
/// and the data after it.
fn split_directive(text: &str) -> (&str, &str) {
    if directive_delimiter(text).is_none() {
        return ("", text);
    }
    let (line, rest) = split_line(text);
    let ending = if rest.starts_with("\r\n") { 2 } else { usize::from(!rest.is_empty()) };
    text.split_at(line.len() + ending)
}

/// What a user hears of how a csv's delimiter was found, when it was not given: a `sep=`
/// line, or a `;` told apart from `,` by the text (with decimal commas read as numbers).
pub fn detection_note(bytes: &[u8]) -> Option<String> {
    let text = std::str::from_utf8(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)).ok()?;
    let commas = " (decimal commas as numbers)";
    match directive_delimiter(text) {
        Some(d) => {
            let commas = if d == b';' { commas } else { "" };
            let d = char::from(d);
            Some(format!("read as {d}-separated values{commas}, as its first line sep={d} says (that line is no data)"))
        }
        None if delimiter_of(text.as_bytes()) == b';' => Some(format!("read as ;-separated values{commas}")),
        None => None,
    }
}

/// [`read_limited`] of the file's data, its delimiter known.
fn read_body(text: &str, delimiter: u8, limits: ReadLimits) -> Result<Workbook, Malformed> {
    let starts = record_starts(text, delimiter, limits)?;

    let mut wb = Workbook::new();
    let sheet = wb.add_sheet(SHEET_NAME).expect("a new workbook has no sheets");
    let mut reader =
        ::csv::ReaderBuilder::new().has_headers(false).flexible(true).delimiter(delimiter).from_reader(text.as_bytes());
    let mut record = ::csv::StringRecord::new();
    for start in &starts {
        let more = reader
            .read_record(&mut record)
            .map_err(|e| Malformed { line: e.position().map_or(start.line, |p| p.line()), message: e.to_string() })?;
        if !more {
            break;
        }
        if start.row >= MAX_ROWS {
            return Err(Malformed { line: start.line, message: format!("more than {MAX_ROWS} rows") });
        }
        if record.len() > MAX_COLS as usize {
            return Err(Malformed { line: start.line, message: format!("more than {MAX_COLS} columns") });
        }
        for (col, field) in record.iter().enumerate() {
            if !field.is_empty() {
                let pos = Pos::new(start.row, col as u32);
                let units = if field.len() > MAX_TEXT { field.encode_utf16().count() } else { field.len() };
                if units > MAX_TEXT {
                    let message = format!("{SHEET_NAME}!{pos}: {}", too_long_text(Some(units)));
                    return Err(Malformed { line: start.line, message });
                }
                let field = if delimiter == b';' { decimal_point_input(field) } else { field.into() };
                match wb.set_input_deferred(sheet, pos, &field) {
                    // A formula that does not parse stays in its cell as `#NAME?` and is listed
                    // by `Workbook::problems`: one bad cell does not stop the file loading.
                    Ok(()) | Err(WorkbookError::Parse { .. }) => {}
                    // Anything else the cell cannot hold stops the read, naming the cell.
                    Err(refused) => return Err(Malformed { line: start.line, message: refused.to_string() }),
                }
            }
        }
    }
    wb.recalculate();
    Ok(wb)
}

/// Where a record starts: its row on the sheet (0-based) and its line in the file (1-based).
#[derive(Clone, Copy, Debug, PartialEq)]
struct RecordStart {
    row: u32,
    line: u64,
}

/// The start of each record the csv reader will return, in order. The reader skips blank
/// lines; a spreadsheet counts them as rows, so the rows are counted here. This is also
/// where an unterminated quoted field is caught, which the reader would take silently as
/// running to the end of the file. Follows the reader's rules: a `"` opens a quoted field
/// only at the start of a field, `""` inside one is a quote, and `\n`, `\r\n` or `\r` ends
/// a record.
/// The delimiter a first line `sep=;` names (Excel's directive), else
/// `;` when the file's first lines are `;`-separated (each holds the same number of `;`
/// outside quotes, and not as many `,` unless every `,` stands between digits, as a decimal
/// comma does: `a;0,5`; or each holds a `;` and every `,` is such a decimal comma, as rows
/// of their own length do once a save added a field to some), else `,`.
pub fn delimiter_of(bytes: &[u8]) -> u8 {
    if let Some(d) = std::str::from_utf8(bytes).ok().and_then(directive_delimiter) {
        return d;
    }
    let lines: Vec<(usize, usize, bool)> = bytes
        .split(|&b| b == b'\n')
        .filter(|l| !l.iter().all(u8::is_ascii_whitespace))
        .take(20)
        .map(|line| {
            let mut quoted = false;
            let (mut semicolons, mut commas, mut decimal_commas) = (0, 0, true);
            let digit = |i: Option<usize>| i.and_then(|i| line.get(i)).is_some_and(u8::is_ascii_digit);
            for (i, &b) in line.iter().enumerate() {
                match b {
                    b'"' => quoted = !quoted,
                    b';' if !quoted => semicolons += 1,
                    b',' if !quoted => {
                        commas += 1;
                        decimal_commas &= digit(i.checked_sub(1)) && digit(Some(i + 1));
                    }
                    _ => {}
                }
            }
            (semicolons, commas, decimal_commas)
        })
        .collect();
    let Some(&(first, _, _)) = lines.first() else { return b',' };
    let consistent = first > 0 && lines.iter().all(|&(s, _, _)| s == first);
    let decimal = lines.iter().all(|&(_, _, d)| d);
    let commas_separate = !decimal && lines.iter().all(|&(_, c, _)| c > 0 && c == lines[0].1) && lines[0].1 >= first;
    let ragged = decimal && lines.iter().all(|&(s, _, _)| s > 0);
    if (consistent && !commas_separate) || ragged {
        b';'
    } else {
        b','
    }
}

/// A number typed as `0.8` written into a `;`-separated file as `0,8`, and a formula with
/// `;` between arguments (`=ROUND(A1*0,5;2)`), as that file's spreadsheet reads them (and
/// [`decimal_point_input`] reads them back); anything else unchanged.
fn decimal_comma_input(text: &str) -> String {
    if text.starts_with('=') {
        return super::csv_locale::to_semicolon_locale(text);
    }
    // Whether it is a number does not depend on the date system.
    let is_number = matches!(Input::parse(text, DateSystem::From1900), Input::Value(Value::Number(_)));
    if is_number && decimal_point(&text.replacen('.', ",", 1)) == text {
        text.replacen('.', ",", 1)
    } else {
        text.to_string()
    }
}

/// A cell's input as a `;` file's spreadsheet types it ([`decimal_comma_input`]); in a
/// decimal-comma `locale`, text forced with `'` (`'2:30 PM`, which en-US reads as a time)
/// without the `'` when that locale reads it as the same text, as LibreOffice set to the
/// locale writes a text cell (never with a `'`).
fn locale_input(input: &str, locale: Locale) -> String {
    match input.strip_prefix('\'') {
        Some(text) if !locale.is_canonical() && !needs_text_mark_in(text, locale) => text.to_string(),
        _ => decimal_comma_input(input),
    }
}

/// A field of a `;`-separated file as ncsheet reads it: a number with a decimal comma as
/// [`decimal_point`], a formula in the Excel syntax (`=ROUND(A1*0,5;2)` →
/// `=ROUND(A1*0.5,2)`).
fn decimal_point_input(field: &str) -> String {
    if field.starts_with('=') {
        super::csv_locale::from_semicolon_locale(field)
    } else {
        decimal_point(field)
    }
}

/// `0,8` → `0.8`, `-12,5` → `-12.5`; anything else unchanged.
fn decimal_point(field: &str) -> String {
    let body = field.strip_prefix('-').unwrap_or(field);
    match body.split_once(',') {
        Some((whole, fraction))
            if !whole.is_empty()
                && !fraction.is_empty()
                && whole.bytes().all(|b| b.is_ascii_digit())
                && fraction.bytes().all(|b| b.is_ascii_digit()) =>
        {
            field.replacen(',', ".", 1)
        }
        _ => field.to_string(),
    }
}

fn record_starts(text: &str, delimiter: u8, limits: ReadLimits) -> Result<Vec<RecordStart>, Malformed> {
    let bytes = text.as_bytes();
    let mut starts = Vec::new();
    let (mut row, mut line) = (0u32, 1u64);
    let mut at_record_start = true;
    let mut at_field_start = true;
    let mut quote_opened: Option<u64> = None;
    let mut sizes = Sizes { limits, record: 0, field: 0, record_line: 1, row: 0, col: 0 };
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        let terminator_len = match b {
            b'\r' if bytes.get(i + 1) == Some(&b'\n') => 2,
            b'\r' | b'\n' => 1,
            _ => 0,
        };
        // At every byte, so that a field or line past its limit stops the scan there, not
        // at its end (a quoted field of 150 MB was read whole first).
        sizes.check(i)?;
        if quote_opened.is_none() && (terminator_len > 0 || b == delimiter) {
            sizes.field = i + 1;
            sizes.col += 1;
            if terminator_len > 0 {
                sizes.record = i + terminator_len;
                sizes.record_line = line + 1;
                sizes.row = row.saturating_add(1);
                sizes.col = 0;
            }
        }
        if quote_opened.is_some() {
            if b == b'"' {
                if bytes.get(i + 1) == Some(&b'"') {
                    i += 1;
                } else {
                    quote_opened = None;
                }
            } else if terminator_len > 0 {
                line += 1;
                i += terminator_len - 1;
            }
        } else if terminator_len > 0 {
            // Either ends a record or is a blank line: one row either way.
            row = row.saturating_add(1);
            line += 1;
            at_record_start = true;
            at_field_start = true;
            i += terminator_len - 1;
        } else {
            if at_record_start {
                starts.push(RecordStart { row, line });
                at_record_start = false;
            }
            if at_field_start && b == b'"' {
                quote_opened = Some(line);
            }
            at_field_start = b == delimiter;
        }
        i += 1;
    }
    if let Some(opened) = quote_opened {
        return Err(Malformed {
            line: opened,
            message: "unterminated quoted field (a '\"' opened here is never closed)".into(),
        });
    }
    sizes.check(bytes.len())?;
    Ok(starts)
}

/// How a csv is written: its delimiter and how values are shown.
#[derive(Clone, Copy, Debug)]
pub struct Style<'a> {
    /// `,`, or `;` for a spreadsheet whose locale writes decimal commas: numbers are then
    /// written with a decimal comma (`0,8`), as such a spreadsheet reads them.
    pub delimiter: u8,
    /// The sheet's number formats by cell: values are written as the cells show them.
    pub formats: Option<&'a LooksByCell<String>>,
    /// Numbers in full precision (the shortest text that reads back as the same number).
    pub raw: bool,
}

impl Default for Style<'_> {
    fn default() -> Self {
        Style { delimiter: b',', formats: None, raw: false }
    }
}

/// Where the current record and field began, to hold them to ncsheet's limits
/// (docs/limits.md) before the csv reader buffers them.
struct Sizes {
    limits: crate::io::limits::ReadLimits,
    record: usize,
    field: usize,
    /// The line the record began on.
    record_line: u64,
    /// The record's row and the field's column (0-based), the cell a refusal names.
    row: u32,
    col: u32,
}

/// The most bytes a field may take before its text is surely longer than the 32,767
/// characters a cell holds: each character takes at most 3 bytes of UTF-8 per UTF-16 unit
/// (a quote doubled, 2), and the field's own quotes 2 more. A shorter field is measured
/// exactly when it is stored.
const CELL_TEXT_BYTES: usize = 3 * crate::eval::evaluator::MAX_TEXT + 2;

impl Sizes {
    /// The field and record ending at byte `end`, against the limits.
    fn check(&self, end: usize) -> Result<(), Malformed> {
        use crate::io::limits::bytes;
        let past = |what: &str, limit: u64, option: &str| Malformed {
            line: self.record_line,
            message: format!("a {what} longer than ncsheet's limit of {} ({option} raises it)", bytes(limit)),
        };
        let (field, record) = (end - self.field.min(end), end - self.record.min(end));
        if field > CELL_TEXT_BYTES {
            let cell = format!("{SHEET_NAME}!{}", Pos::new(self.row, self.col));
            return Err(Malformed { line: self.record_line, message: format!("{cell}: {}", too_long_text(None)) });
        }
        if field as u64 > self.limits.csv_field_bytes {
            return Err(past("field", self.limits.csv_field_bytes, "--max-csv-field"));
        }
        if record as u64 > self.limits.csv_line_bytes {
            return Err(past("line", self.limits.csv_line_bytes, "--max-csv-line"));
        }
        Ok(())
    }
}

/// Writes a sheet, or a range of it, as csv.
pub fn write(wb: &Workbook, what: &Export, out: &mut dyn Write) -> io::Result<()> {
    write_with(wb, what, &Style::default(), out)
}

/// [`write`] in a given [`Style`].
pub fn write_with(wb: &Workbook, what: &Export, style: &Style, out: &mut dyn Write) -> io::Result<()> {
    let rect = match what.range {
        Some(r) => r,
        None => match wb.used_rect(what.sheet) {
            Some(used) => Rect::new(Pos::new(0, 0), used.last),
            None => return Ok(()),
        },
    };
    if rect.rows() as u64 * rect.cols() as u64 > MAX_TABLE_FIELDS {
        return write_sparse(wb, what, style, rect, out);
    }
    let mut writer = ::csv::WriterBuilder::new().delimiter(style.delimiter).from_writer(out);
    let mut fields: Vec<String> = Vec::with_capacity(rect.cols() as usize);
    let mut parsed = ShownFormats::default();
    for row in rect.first.row..=rect.last.row {
        fields.clear();
        for col in rect.first.col..=rect.last.col {
            let pos = Pos::new(row, col);
            fields.push(match what.content {
                Content::Values => style.field(&wb.value(what.sheet, pos), pos, wb, &mut parsed),
                Content::Formulas => style.typed(&wb.input(what.sheet, pos).unwrap_or_default()),
            });
        }
        writer.write_record(&fields).map_err(io_error)?;
    }
    writer.flush()
}

/// A csv writer's failure as the io error it is: the csv crate wraps a write's error in one
/// of kind `Other`, so a reader closing the pipe (`ncsheet eval … --format csv | head`) was
/// reported as a failure, where the other formats stop quietly at a broken pipe.
fn io_error(e: ::csv::Error) -> io::Error {
    match e.into_kind() {
        ::csv::ErrorKind::Io(e) => e,
        other => io::Error::other(format!("{other:?}")),
    }
}

/// The most fields written as a full table; past it (one far cell, XFD1048576, makes a table
/// of 17 billion) each row ends at its last cell, so that the work and the file are
/// proportional to the cells that exist (an empty row is an empty line), and the file reads
/// back as the same sheet.
const MAX_TABLE_FIELDS: u64 = 10_000_000;

fn write_sparse(wb: &Workbook, what: &Export, style: &Style, rect: Rect, out: &mut dyn Write) -> io::Result<()> {
    let mut cells: Vec<Pos> = Vec::new();
    crate::eval::Env::for_each_value(wb, what.sheet, rect, &mut |pos, _| cells.push(pos));
    cells.sort_unstable_by_key(|p| (p.row, p.col));
    let mut out = io::BufWriter::new(out);
    let mut fields: Vec<String> = Vec::new();
    let mut parsed = ShownFormats::default();
    let mut next = cells.iter().peekable();
    let mut row = rect.first.row;
    while let Some(&&first) = next.peek() {
        // Rows without cells: an empty line each.
        for _ in row..first.row {
            out.write_all(b"\n")?;
        }
        row = first.row;
        fields.clear();
        while let Some(&&pos) = next.peek().filter(|p| p.row == row) {
            fields.resize((pos.col - rect.first.col) as usize, String::new());
            fields.push(match what.content {
                Content::Values => style.field(&wb.value(what.sheet, pos), pos, wb, &mut parsed),
                Content::Formulas => wb.input(what.sheet, pos).unwrap_or_default(),
            });
            next.next();
        }
        let mut writer = ::csv::WriterBuilder::new().delimiter(style.delimiter).from_writer(&mut out);
        writer.write_record(&fields).map_err(io_error)?;
        writer.flush()?;
        drop(writer);
        row += 1;
    }
    for _ in row..=rect.last.row {
        out.write_all(b"\n")?;
    }
    out.flush()
}

impl Style<'_> {
    /// A cell's input as this style's spreadsheet types it (see [`decimal_comma_input`]).
    fn typed(&self, input: &str) -> String {
        if self.delimiter == b';' {
            decimal_comma_input(input)
        } else {
            input.to_string()
        }
    }

    /// The csv text of a value in this style: a number as its cell's format shows it (or
    /// in full), with a decimal comma in a `;` file; a date as the workbook's locale shows
    /// it. In a decimal-comma locale's `;` (or tab) file, everything as that locale shows it
    /// ([`locale_value_field`]), as LibreOffice set to the locale exports it; anything else
    /// as [`value_field`]. Each cell's code is parsed once in `parsed`, the export's own.
    fn field(&self, v: &Value, pos: Pos, wb: &Workbook, parsed: &mut ShownFormats) -> String {
        let locale = wb.settings().locale;
        // A decimal-comma locale's own csv (`;` or tab between fields), as its Excel and
        // LibreOffice write it: that locale's marks, words and text guards.
        let in_locale = !locale.is_canonical() && self.delimiter != b',';
        let Value::Number(n) = v else {
            return if in_locale { locale_value_field(v, locale) } else { value_field(v) };
        };
        let code = self.formats.and_then(|f| f.get(&pos)).map(String::as_str);
        if !self.raw && (in_locale || code.is_some_and(is_date_code)) {
            // As `eval` shows it: Excel's built-in date is the locale's short date (de-DE
            // 28.11.2026, en-US 11/28/2026), months and days in the locale's words; numbers
            // with the locale's decimal and group marks (fr-FR `1 234,5`, a no-break space).
            return locale.shown_number_with(parsed, *n, code, wb.date_system());
        }
        if in_locale {
            return locale.localize_shown(&format!("{n}"));
        }
        let text = if self.raw { format!("{n}") } else { parsed.shown(*n, code, wb.date_system()) };
        if self.delimiter == b';' {
            // Swapped both ways: 1,234.5 is 1.234,5 where the comma is the decimal mark.
            text.chars()
                .map(|c| match c {
                    '.' => ',',
                    ',' => '.',
                    c => c,
                })
                .collect()
        } else {
            text
        }
    }
}

/// The csv text of a value: what the sheet shows, text guarded so it reads back as text.
pub fn value_field(v: &Value) -> String {
    match v {
        Value::Text(t) if needs_text_mark(t) => format!("'{t}"),
        v => v.to_string(),
    }
}

/// [`value_field`] in a decimal-comma locale's csv: booleans in its words (de-DE `WAHR`),
/// text guarded that the locale would read as something else (`1,5`, `WAHR`, `12.03.2025`).
pub fn locale_value_field(v: &Value, locale: Locale) -> String {
    match v {
        Value::Text(t) if needs_text_mark_in(t, locale) => format!("'{t}"),
        v => locale.shown_value(v),
    }
}

/// Whether a spreadsheet could read this text as something else: a formula, a number, a
/// boolean, an error, or text with a `'` dropped. Empty text is written as an empty field.
fn needs_text_mark(text: &str) -> bool {
    needs_text_mark_in(text, Locale::EN_US)
}

/// [`needs_text_mark`] for a spreadsheet in `locale`, which reads a file of its own in its
/// own spelling only: text that is a number or date only in another locale's (`2:30 PM`,
/// `0.8` in de-DE) reads back there as the same text, and LibreOffice set to the locale
/// writes it so, without a mark.
fn needs_text_mark_in(text: &str, locale: Locale) -> bool {
    if text.is_empty() {
        return false;
    }
    // Whether it reads as something else does not depend on the date system.
    let read = Input::parse_in(text, locale, DateSystem::From1900);
    let formula_like = text.starts_with(['=', '+', '-', '@', '\t', '\r']);
    formula_like || read != Input::Value(Value::text(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn starts(text: &str) -> Vec<(u32, u64)> {
        record_starts(text, b',', ReadLimits::default()).unwrap().into_iter().map(|s| (s.row, s.line)).collect()
    }

    #[test]
    fn blank_lines_are_rows_and_quoted_line_breaks_are_not() {
        assert_eq!(starts("a\n\nb\n"), [(0, 1), (2, 3)]);
        assert_eq!(starts("\"x\ny\",1\r\nz\r\n"), [(0, 1), (1, 3)]);
        assert_eq!(starts("a\r\rb"), [(0, 1), (2, 3)]);
        assert_eq!(starts("a,\"\"\"q\"\"\"\nb"), [(0, 1), (1, 2)]);
        assert_eq!(starts(""), []);
    }

    /// An export parses each distinct number format once (issue 30: a four-section code
    /// parsed for each of 200,000 cells was 44 % of the export), and shows every cell as
    /// before: -1.25 in parentheses as the code's second section says, 0 as its third.
    #[test]
    fn an_export_parses_each_number_format_once() {
        use crate::eval::format::text_format::codes_parsed;
        let mut wb = Workbook::with_sheet();
        let code = "#,##0.00_);[Red](#,##0.00);\"zero\";@".to_string();
        let mut formats = LooksByCell::default();
        for row in 0..1000u32 {
            let pos = Pos::new(row, 0);
            wb.set_input(0, pos, &format!("{}", (f64::from(row) - 1.0) * 1.25)).unwrap();
            formats.insert(pos, code.clone());
        }
        let style = Style { formats: Some(&formats), ..Style::default() };
        let what = Export { sheet: 0, range: None, content: Content::Values };
        let before = codes_parsed();
        let mut out = Vec::new();
        write_with(&wb, &what, &style, &mut out).unwrap();
        assert_eq!(codes_parsed() - before, 1);
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[..3], ["(1.25)", "zero", "1.25 "]);
        assert_eq!(lines[999], "\"1,247.50 \"");
    }

    #[test]
    fn raw_rows_keep_fields_quotes_and_endings() {
        let rows = raw_rows("a,\"1,2\"\r\n\n\"x\ny\",007,\nlast", b',');
        let f = |r: &RawRow| r.fields.clone();
        assert_eq!(rows.len(), 4);
        assert_eq!(f(&rows[0]), ["a", "\"1,2\""]);
        assert_eq!(rows[0].ending, "\r\n");
        assert!(rows[1].fields.is_empty());
        assert_eq!(f(&rows[2]), ["\"x\ny\"", "007", ""]);
        assert_eq!(f(&rows[3]), ["last"]);
        assert_eq!(rows[3].ending, "");
    }

    #[test]
    fn an_unterminated_quote_names_the_line_it_opened_on() {
        let err = record_starts("a,b\nc,\"d\ne\n", b',', ReadLimits::default()).unwrap_err();
        assert_eq!(err, Malformed { line: 2, message: err.message.clone() });
        // A quote inside an unquoted field is a literal character, as the reader takes it.
        assert!(record_starts("ab\"c\n", b',', ReadLimits::default()).is_ok());
    }

    #[test]
    fn decimal_commas_do_not_make_a_file_comma_separated() {
        assert_eq!(delimiter_of(b"a;0,5\n"), b';');
        assert_eq!(delimiter_of(b"D;40,5\nf;2,25\n"), b';');
        assert_eq!(delimiter_of(b"a;b,c\n"), b',');
        assert_eq!(delimiter_of(b"1,5\n2,6\n"), b',');
        assert_eq!(delimiter_of(b"x;y,1\n"), b',');
        // Rows of their own length, as a save that added a field to one leaves them.
        assert_eq!(delimiter_of(b"D;40,5;\"=SUM(A1;B1)\"\nf;2,25\n"), b';');
        assert_eq!(delimiter_of(b"a;b,c\nd;e;f\n"), b',');
    }

    #[test]
    fn text_that_would_read_back_as_something_else_gets_a_mark() {
        for t in ["=1+1", "+x", "-x", "@SUM(A1)", "12", "TRUE", "#N/A", "'q"] {
            assert_eq!(value_field(&Value::text(t)), format!("'{t}"));
        }
        for t in ["plain", "a=b", "x-1"] {
            assert_eq!(value_field(&Value::text(t)), t);
        }
        assert_eq!(value_field(&Value::Number(-2.5)), "-2.5");
    }
}
