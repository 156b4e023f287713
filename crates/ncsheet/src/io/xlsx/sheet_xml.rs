//! A worksheet's cells, read straight from its XML in one streaming pass: each cell's value
//! (typed as its `t` attribute says), its formula as stored (plain, shared, array), and
//! beside them the sheet's array areas, cell styles and column widths.
//!
//! calamine reads the workbook's structure and styles; this pass reads the cells because
//! it is the whole cost of an import (it keeps no tree, copies no text it does not hand on)
//! and because calamine's cell API hides what an import needs: array-formula areas and the
//! metadata that marks a dynamic array. Its checks match calamine's: a value that does not
//! fit its type, a shared-string index out of the table or markup that does not nest is an
//! error naming the cell or the byte, not a cell left out.

use std::io::Read;
use std::rc::Rc;

use crate::eval::dates::{days_in_month, serial_from_ymd, DateSystem};
use crate::eval::{Value, XlError};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};

use super::xml::{self, Event, Tag, TagKind};
use super::{ArrayFormula, ErrorKind};

/// A `<col width>` in the characters Excel shows: the file's width holds 5 pixels of
/// padding (ECMA-376 §18.3.1.13), counted here in digits of Calibri 11, Excel's default font
/// (7 pixels wide).
pub fn shown_width(file_width: f64) -> f64 {
    (file_width - 5.0 / 7.0).max(0.0)
}

/// What the worksheet pass found besides the cells.
#[derive(Default, Debug)]
pub struct SheetScan {
    /// Array formulas, in file order.
    pub arrays: Vec<ArrayFormula>,
    /// Cells with a style other than the default, with their style index.
    pub styled: Vec<(Pos, u32)>,
    /// `<col>` widths: first and last column (0-based) and the width.
    pub widths: Vec<(u32, u32, f64)>,
    /// `<sheetFormatPr>`: the width of the other columns, in characters as Excel shows it
    /// (`baseColWidth`, or `defaultColWidth` less its padding); `None` when not given.
    pub default_width: Option<f64>,
    /// `<sheetPr codeName="…">`: the sheet's VBA name.
    pub code_name: Option<String>,
    /// The first `<selection activeCell="…">`: where a macro's `ActiveCell` starts.
    pub active_cell: Option<Pos>,
    /// That selection's `sqref`, area by area ("A1:B2 D4:E5" is two): where a macro's
    /// `Selection` starts.
    pub selection: Option<Vec<Rect>>,
    /// Rows `<row hidden="1">` (0-based).
    pub hidden_rows: Vec<u32>,
    /// Columns `<col min max hidden="1">`: first and last column (0-based).
    pub hidden_columns: Vec<(u32, u32)>,
    /// Rows a user sized (`<row ht="30" customHeight="1">`): row (0-based) and height in
    /// points. A height Excel fitted to the row's font is left out: it follows the cells.
    pub row_heights: Vec<(u32, f64)>,
    /// The sheet's `<autoFilter ref>`, and whether it filters on a column.
    pub auto_filter: Option<(Rect, bool)>,
    /// `<hyperlink>`s, in file order.
    pub hyperlinks: Vec<FileHyperlink>,
}

/// A `<hyperlink>` as the sheet part has it: an address outside the package is behind a
/// relationship (`r:id`), a place in the workbook is its `location`.
#[derive(Debug, Clone, PartialEq)]
pub struct FileHyperlink {
    pub anchor: Rect,
    pub relationship: Option<String>,
    pub location: String,
    pub display: Option<String>,
    pub tooltip: Option<String>,
}

/// One cell as the file holds it.
pub struct CellXml<'a> {
    pub pos: Pos,
    /// The stored value: a constant's, or the result Excel cached for a formula.
    pub value: Option<Stored>,
    pub formula: Option<FormulaXml<'a>>,
}

/// A value as a cell stores it. Strings of the shared table stay an index, so cells can
/// cross to the importing thread without the table.
#[derive(Clone, Debug, PartialEq)]
pub enum Stored {
    Number(f64),
    Bool(bool),
    Error(XlError),
    Text(String),
    /// An index the pass checked against the table's length.
    SharedString(u32),
}

impl Stored {
    pub fn into_value(self, strings: &[Rc<str>]) -> Value {
        match self {
            Stored::Number(n) => Value::Number(n),
            Stored::Bool(b) => Value::Bool(b),
            Stored::Error(e) => Value::Error(e),
            Stored::Text(t) => Value::text(t),
            Stored::SharedString(i) => strings.get(i as usize).map_or(Value::Blank, |s| Value::Text(s.clone())),
        }
    }
}

/// A cell's `<f>`, its text as stored (file spelling, no `=`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FormulaXml<'a> {
    Plain(&'a str),
    /// `t="array"`: the anchor of an array formula.
    Array(&'a str, ArrayFormula),
    /// `t="shared"` with text: the cell that holds a shared formula's text.
    SharedText {
        index: u32,
        text: &'a str,
    },
    /// `t="shared"` without text: a copy of shared formula `index`, moved to this cell.
    SharedCopy {
        index: u32,
    },
}

/// A cell or markup the pass refuses, with what to say about it.
pub type ScanError = (ErrorKind, String);

/// The grid a workbook may need: sheets store each column densely down to its last used
/// row, 4 bytes a slot. A workbook needing more than this (512 MiB) is refused as its cells
/// arrive, before they are stored: a few cells far apart must not exhaust memory.
pub const MAX_GRID_SLOTS: u64 = 1 << 27;

/// What the workbook's parts say that a sheet's cells refer to.
#[derive(Clone, Copy, Default)]
pub struct CellLookups<'t> {
    /// The shared-string table's length, to check each index against.
    pub string_count: usize,
    /// The error each value-metadata entry stands for (`vm="n"`: entry n-1), see
    /// [`super::raw::Package::rich_errors`].
    pub rich_errors: &'t [Option<XlError>],
    /// The workbook's date system, in which a date cell's (`t="d"`) text is a serial.
    pub dates: DateSystem,
}

/// Streams a worksheet part: calls `on_cell` for each cell in file order and returns what
/// else the sheet holds. `grid_slots` counts the grid of the sheets read before; this
/// sheet's columns are added to it.
pub fn read_sheet(
    part: impl Read,
    lookups: CellLookups,
    grid_slots: &mut u64,
    on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>,
) -> Result<SheetScan, xml::StreamError<ScanError>> {
    let mut scanner = SheetScanner { lookups, grid_slots: *grid_slots, ..SheetScanner::default() };
    xml::stream(part, &mut |event| scanner.event(event, on_cell))?;
    *grid_slots = scanner.grid_slots;
    Ok(scanner.scan)
}

/// Where text inside a cell goes.
#[derive(Clone, Copy, Default, PartialEq, Eq)]
enum Capture {
    #[default]
    Nothing,
    Formula,
    Value,
    /// A `<t>` of an inline string (`<is>`), not of its phonetic reading.
    Inline,
}

/// The cell being read: attributes of `<c>`, and the text of its `<f>`, `<v>` and `<is>`.
/// The buffers live from cell to cell, so a million cells cost no allocations.
#[derive(Default)]
struct OpenCell {
    pos: Option<Pos>,
    kind: CellType,
    metadata: bool,
    /// `vm="n"`, the cell's value metadata (0: none).
    value_metadata: u32,
    formula: Option<FormulaAttrs>,
    formula_text: String,
    has_value: bool,
    value_text: String,
    has_inline: bool,
    inline_text: String,
    phonetic: bool,
}

impl OpenCell {
    fn reset(&mut self) {
        self.pos = None;
        self.kind = CellType::Untyped;
        self.metadata = false;
        self.value_metadata = 0;
        self.formula = None;
        self.formula_text.clear();
        self.has_value = false;
        self.value_text.clear();
        self.has_inline = false;
        self.inline_text.clear();
        self.phonetic = false;
    }

    fn formula(&self, pos: Pos) -> Option<FormulaXml<'_>> {
        let text = self.formula_text.as_str();
        let has_text = !text.trim().is_empty();
        match self.formula? {
            FormulaAttrs::Normal if has_text => Some(FormulaXml::Plain(text)),
            FormulaAttrs::Array(area) if has_text => {
                let area = area.filter(|a| a.first == pos).unwrap_or(Rect::cell(pos));
                Some(FormulaXml::Array(text, ArrayFormula { anchor: pos, area, dynamic: self.metadata }))
            }
            FormulaAttrs::Shared(Some(index)) if has_text => Some(FormulaXml::SharedText { index, text }),
            FormulaAttrs::Shared(Some(index)) => Some(FormulaXml::SharedCopy { index }),
            FormulaAttrs::Shared(None) if has_text => Some(FormulaXml::Plain(text)),
            _ => None,
        }
    }
}

#[derive(Clone, Copy, Default, PartialEq, Eq, Debug)]
enum CellType {
    /// No `t`: a number, or text when it does not read as one.
    #[default]
    Untyped,
    Number,
    SharedString,
    Str,
    InlineString,
    Bool,
    Error,
    IsoDate,
}

#[derive(Clone, Copy)]
enum FormulaAttrs {
    Normal,
    Array(Option<Rect>),
    Shared(Option<u32>),
    /// A what-if data table: no formula of its own; its values stay as Excel stored them.
    DataTable,
}

#[derive(Default)]
struct SheetScanner<'t> {
    lookups: CellLookups<'t>,
    scan: SheetScan,
    /// Next row and column for markup that leaves `r` out.
    row: u32,
    col: u32,
    cell: OpenCell,
    in_cell: bool,
    capture: Capture,
    /// Per column, one past the last row holding a cell.
    column_rows: Vec<u32>,
    /// Grid slots of the workbook so far (see [`MAX_GRID_SLOTS`]).
    grid_slots: u64,
}

impl SheetScanner<'_> {
    /// The error value metadata `vm` (1-based) stands for, if any.
    fn rich_error(&self, vm: u32) -> Option<XlError> {
        let i = (vm as usize).checked_sub(1)?;
        self.lookups.rich_errors.get(i).copied().flatten()
    }

    fn event(
        &mut self,
        event: Event,
        on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>,
    ) -> Result<(), ScanError> {
        match event {
            Event::Tag(tag) => self.tag(&tag, on_cell),
            Event::Text(raw) if self.capture != Capture::Nothing => {
                let text = std::str::from_utf8(raw).map_err(|_| self.damaged("holds text that is not UTF-8"))?;
                xml::unescape_into(text, self.capture_buffer())
                    .map_err(|bad| self.damaged(&format!("holds XML that is not well-formed: {bad}")))
            }
            Event::CData(raw) if self.capture != Capture::Nothing => {
                let text = std::str::from_utf8(raw).map_err(|_| self.damaged("holds text that is not UTF-8"))?;
                self.capture_buffer().push_str(text);
                Ok(())
            }
            _ => Ok(()),
        }
    }

    fn capture_buffer(&mut self) -> &mut String {
        let cell = &mut self.cell;
        match self.capture {
            Capture::Formula => &mut cell.formula_text,
            Capture::Value => &mut cell.value_text,
            Capture::Inline | Capture::Nothing => &mut cell.inline_text,
        }
    }

    fn tag(&mut self, tag: &Tag, on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>) -> Result<(), ScanError> {
        let opens = tag.kind != TagKind::End;
        match tag.name {
            b"c" if opens => self.open_cell(tag)?,
            b"c" => return self.close_cell(on_cell),
            b"f" | b"v" | b"t" | b"is" | b"rPh" if self.in_cell => self.cell_part(tag)?,
            b"row" if opens => {
                if let Some(r) = tag.attr("r") {
                    let number = parse_u32(r).filter(|n| (1..=MAX_ROWS).contains(n));
                    self.row = number.ok_or_else(|| bad_row(r))? - 1;
                }
                if tag.attr("hidden").is_some_and(|h| h == b"1" || h == b"true") {
                    self.scan.hidden_rows.push(self.row);
                }
                self.row_height(tag);
                self.col = 0;
            }
            b"row" => {
                self.row += 1;
                self.col = 0;
            }
            b"col" if opens => self.column_width(tag),
            b"sheetFormatPr" if opens => self.default_width(tag),
            b"sheetPr" if opens => self.scan.code_name = tag.attr("codeName").map(xml::unescape),
            b"selection" if opens && self.scan.active_cell.is_none() => {
                self.scan.active_cell = tag.attr("activeCell").and_then(parse_pos);
                // "A4:C9", or several areas "A1:B2 D4:E5" (ST_Sqref, a list of references
                // separated by spaces); one that does not read leaves the active cell alone.
                self.scan.selection = tag.attr("sqref").and_then(|r| r.split(|&b| b == b' ').map(parse_rect).collect());
            }
            b"autoFilter" if opens => {
                self.scan.auto_filter = tag.attr("ref").and_then(parse_rect).map(|r| (r, false));
            }
            b"hyperlink" if opens => self.hyperlink(tag),
            b"filterColumn" => {
                if let Some((_, filtering)) = &mut self.scan.auto_filter {
                    *filtering = true;
                }
            }
            _ => {}
        }
        if tag.kind == TagKind::Empty {
            match tag.name {
                b"c" => return self.close_cell(on_cell),
                b"row" => self.row += 1,
                _ => {}
            }
        }
        Ok(())
    }

    fn open_cell(&mut self, tag: &Tag) -> Result<(), ScanError> {
        if self.in_cell {
            return Err(self.damaged("holds another cell"));
        }
        self.cell.reset();
        let mut pos = Pos::new(self.row, self.col);
        let mut style = 0;
        for (name, value) in tag.attrs() {
            match name {
                b"r" => pos = parse_pos(value).ok_or_else(|| bad_reference(value))?,
                b"t" => self.cell.kind = cell_type(value)?,
                b"s" => style = parse_u32(value).unwrap_or(0),
                b"cm" => self.cell.metadata = true,
                b"vm" => self.cell.value_metadata = parse_u32(value).unwrap_or(0),
                _ => {}
            }
        }
        if pos.row >= MAX_ROWS || pos.col >= MAX_COLS {
            // Only a cell without `r` gets here: counted on past the sheet's edge.
            let message = format!(
                "a cell without a reference would lie past the sheet's edge (row {}, column {})",
                pos.row as u64 + 1,
                pos.col as u64 + 1
            );
            return Err((ErrorKind::Damaged, message));
        }
        self.grow_grid(pos)?;
        if style != 0 {
            self.scan.styled.push((pos, style));
        }
        self.col = pos.col + 1;
        self.cell.pos = Some(pos);
        self.in_cell = true;
        Ok(())
    }

    /// Counts the grid slots a cell at `pos` adds; refuses the cell when the workbook would
    /// pass [`MAX_GRID_SLOTS`].
    fn grow_grid(&mut self, pos: Pos) -> Result<(), ScanError> {
        let col = pos.col as usize;
        if self.column_rows.len() <= col {
            self.column_rows.resize(col + 1, 0);
        }
        let rows = &mut self.column_rows[col];
        if pos.row < *rows {
            return Ok(());
        }
        self.grid_slots += (pos.row + 1 - *rows) as u64;
        *rows = pos.row + 1;
        if self.grid_slots > MAX_GRID_SLOTS {
            let message = format!(
                "the cells lie too far apart: the sheets would need more than {} MiB of grid",
                (MAX_GRID_SLOTS * 4) >> 20
            );
            return Err((ErrorKind::TooLarge, message));
        }
        Ok(())
    }

    fn cell_part(&mut self, tag: &Tag) -> Result<(), ScanError> {
        let opens = tag.kind == TagKind::Start;
        match tag.name {
            b"f" if tag.kind != TagKind::End => {
                self.cell.formula = Some(formula_attrs(tag).map_err(|m| self.damaged(&m))?);
                self.capture = if opens { Capture::Formula } else { Capture::Nothing };
            }
            b"v" if tag.kind != TagKind::End => {
                self.cell.has_value = true;
                self.capture = if opens { Capture::Value } else { Capture::Nothing };
            }
            b"is" if tag.kind != TagKind::End => self.cell.has_inline = true,
            b"rPh" => self.cell.phonetic = opens,
            b"t" if opens && !self.cell.phonetic => self.capture = Capture::Inline,
            _ => self.capture = Capture::Nothing,
        }
        Ok(())
    }

    fn close_cell(&mut self, on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>) -> Result<(), ScanError> {
        self.in_cell = false;
        self.capture = Capture::Nothing;
        let pos = self.cell.pos.take().expect("a cell closes after it opens");
        let value = self.value().map_err(|message| self.damaged_cell(pos, &message))?;
        let formula = self.cell.formula(pos);
        if let Some(FormulaXml::Array(_, array)) = formula {
            self.scan.arrays.push(array);
        }
        on_cell(CellXml { pos, value, formula }).map_err(|(kind, message)| (kind, cell_place(pos, &message)))
    }

    /// The cell's value as its type says: a shared string looked up, a number parsed.
    fn value(&self) -> Result<Option<Stored>, String> {
        let cell = &self.cell;
        if cell.kind == CellType::InlineString {
            return Ok(cell.has_inline.then(|| Stored::Text(xml::unescape_excel(&cell.inline_text).into_owned())));
        }
        if !cell.has_value {
            return Ok(None);
        }
        let raw = cell.value_text.as_str();
        let trimmed = raw.trim();
        Ok(Some(match cell.kind {
            CellType::Untyped | CellType::Number if trimmed.is_empty() => return Ok(None),
            CellType::Untyped => match trimmed.parse::<f64>() {
                Ok(n) if n.is_finite() => Stored::Number(normal_or_zero(n)),
                Ok(_)
                    if !trimmed.to_ascii_lowercase().contains("inf")
                        && !trimmed.to_ascii_lowercase().contains("nan") =>
                {
                    return Err(past_largest_number(raw))
                }
                _ => Stored::Text(raw.to_string()),
            },
            CellType::Number => match trimmed.parse::<f64>() {
                Ok(n) if n.is_finite() => Stored::Number(normal_or_zero(n)),
                Ok(n) if !n.is_nan() && !trimmed.to_ascii_lowercase().contains("inf") => {
                    return Err(past_largest_number(raw))
                }
                _ => return Err(format!("'{raw}' is not a number")),
            },
            CellType::SharedString if trimmed.is_empty() => return Ok(None),
            CellType::SharedString => match trimmed.parse::<u32>() {
                Ok(i) if (i as usize) < self.lookups.string_count => Stored::SharedString(i),
                _ => {
                    let count = self.lookups.string_count;
                    return Err(format!("shared string '{raw}' is not in the table ({count} strings)"));
                }
            },
            CellType::Bool if trimmed.is_empty() => return Ok(None),
            CellType::Bool => match trimmed {
                "1" => Stored::Bool(true),
                "0" => Stored::Bool(false),
                t if t.eq_ignore_ascii_case("true") => Stored::Bool(true),
                t if t.eq_ignore_ascii_case("false") => Stored::Bool(false),
                _ => return Err(format!("'{raw}' is not a boolean")),
            },
            CellType::Error => match trimmed.parse::<XlError>() {
                // `#VALUE!` standing for a newer error its value metadata names.
                Ok(e) => Stored::Error(self.rich_error(cell.value_metadata).unwrap_or(e)),
                Err(()) => return Err(format!("'{raw}' is not an Excel error value")),
            },
            CellType::Str => Stored::Text(xml::unescape_excel(raw).into_owned()),
            CellType::IsoDate if trimmed.is_empty() => return Ok(None),
            CellType::IsoDate => match iso_date_serial(trimmed, self.lookups.dates) {
                Some(serial) => Stored::Number(serial),
                None => return Err(not_an_iso_date(raw)),
            },
            CellType::InlineString => unreachable!("handled above"),
        }))
    }

    /// A `<hyperlink ref>`; one without a cell reference Excel could read is left out.
    fn hyperlink(&mut self, tag: &Tag) {
        let Some(anchor) = tag.attr("ref").and_then(parse_rect) else { return };
        let text = |name: &str| tag.attr(name).map(xml::unescape);
        self.scan.hyperlinks.push(FileHyperlink {
            anchor,
            relationship: text("id"),
            location: text("location").unwrap_or_default(),
            display: text("display"),
            tooltip: text("tooltip"),
        });
    }

    fn default_width(&mut self, tag: &Tag) {
        let number = |name: &str| tag.attr(name).and_then(|w| std::str::from_utf8(w).ok()?.parse::<f64>().ok());
        let base = number("baseColWidth").filter(|w| w.is_finite() && *w >= 0.0);
        let default = number("defaultColWidth").filter(|w| w.is_finite() && *w >= 0.0);
        self.scan.default_width = base.or(default.map(shown_width));
    }

    fn column_width(&mut self, tag: &Tag) {
        let min = tag.attr("min").and_then(parse_u32);
        let max = tag.attr("max").and_then(parse_u32);
        let width = tag.attr("width").and_then(|w| std::str::from_utf8(w).ok()?.parse::<f64>().ok());
        let hidden = tag.attr("hidden").is_some_and(|h| h == b"1" || h == b"true");
        if let (true, Some(min), Some(max)) = (hidden, min, max) {
            if min >= 1 && min <= max && max <= MAX_COLS {
                self.scan.hidden_columns.push((min - 1, max - 1));
            }
        }
        if let (Some(min), Some(max), Some(width)) = (min, max, width) {
            if min >= 1 && min <= max && max <= MAX_COLS && width.is_finite() && width >= 0.0 {
                self.scan.widths.push((min - 1, max - 1, width));
            }
        }
    }

    /// A `<row>`'s height when a user set it (`customHeight`); Excel's limit is 409 points.
    fn row_height(&mut self, tag: &Tag) {
        let custom = tag.attr("customHeight").is_some_and(|h| h == b"1" || h == b"true");
        let height = tag.attr("ht").and_then(|h| std::str::from_utf8(h).ok()?.parse::<f64>().ok());
        if let (true, Some(height)) = (custom, height) {
            if (0.0..=409.0).contains(&height) {
                self.scan.row_heights.push((self.row, height));
            }
        }
    }

    fn damaged(&self, what: &str) -> ScanError {
        let place = match self.cell.pos {
            Some(pos) if self.in_cell => format!("cell {}", cell_name(pos)),
            _ => format!("row {}", self.row as u64 + 1),
        };
        (ErrorKind::Damaged, format!("{place} {what}"))
    }

    fn damaged_cell(&self, pos: Pos, message: &str) -> ScanError {
        (ErrorKind::Damaged, cell_place(pos, message))
    }
}

fn cell_place(pos: Pos, message: &str) -> String {
    format!("cell {}: {message}", cell_name(pos))
}

fn cell_name(pos: Pos) -> String {
    format!("{}{}", crate::formula::address::column_name(pos.col), pos.row as u64 + 1)
}

fn bad_reference(value: &[u8]) -> ScanError {
    let text = String::from_utf8_lossy(value);
    (ErrorKind::Damaged, format!("a cell's reference '{text}' is not a cell of the sheet"))
}

fn bad_row(value: &[u8]) -> ScanError {
    let text = String::from_utf8_lossy(value);
    (ErrorKind::Damaged, format!("a row's number '{text}' is not a row of the sheet"))
}

fn cell_type(value: &[u8]) -> Result<CellType, ScanError> {
    Ok(match value {
        b"n" => CellType::Number,
        b"s" => CellType::SharedString,
        b"str" => CellType::Str,
        b"inlineStr" => CellType::InlineString,
        b"b" => CellType::Bool,
        b"e" => CellType::Error,
        b"d" => CellType::IsoDate,
        other => {
            let text = String::from_utf8_lossy(other);
            return Err((ErrorKind::Damaged, format!("a cell has the unknown type t=\"{text}\"")));
        }
    })
}

/// The serial of a date cell's text (`t="d"`: ECMA-376 Part 1 §18.18.11, "a date in the ISO
/// 8601 format", which Excel writes with its option "Save date and time values using ISO 8601
/// date format"): `2024-01-15`, `2024-01-15T12:30:00` (fractions of a second and a final `Z`
/// allowed) or a time alone, `12:30:00`. `None` for any other text and for a day before the
/// workbook's first serial; kept as text, the date would silently count as no number.
pub(super) fn iso_date_serial(text: &str, dates: DateSystem) -> Option<f64> {
    let text = text.strip_suffix('Z').unwrap_or(text);
    let (day, time) = match text.split_once('T') {
        Some((day, time)) => (iso_day(day, dates)?, Some(time)),
        None if text.contains(':') => (0, Some(text)),
        None => (iso_day(text, dates)?, None),
    };
    let fraction = match time {
        Some(time) => iso_time_of_day(time)?,
        None => 0.0,
    };
    Some(day as f64 + fraction)
}

/// `YYYY-MM-DD` as the serial of that day, if it is a real day from the date system's first.
fn iso_day(text: &str, dates: DateSystem) -> Option<i64> {
    let mut fields = text.split('-');
    let year = digits(fields.next()?, 4)?;
    let month = digits(fields.next()?, 2)?;
    let day = digits(fields.next()?, 2)?;
    if fields.next().is_some()
        || !(1..=12).contains(&month)
        || day < 1
        || day > i64::from(days_in_month(year, month as u32))
    {
        return None;
    }
    Some(serial_from_ymd(dates, year, month, day)).filter(|&serial| serial >= 0)
}

/// `hh:mm`, `hh:mm:ss` or `hh:mm:ss.fff` as a fraction of a day.
fn iso_time_of_day(text: &str) -> Option<f64> {
    let mut fields = text.split(':');
    let hours = digits(fields.next()?, 2)?;
    let minutes = digits(fields.next()?, 2)?;
    let seconds = match fields.next() {
        None => 0.0,
        Some(s) => {
            let (whole, fraction) = s.split_once('.').unwrap_or((s, ""));
            let whole = digits(whole, 2)?;
            if !fraction.bytes().all(|b| b.is_ascii_digit()) || (s.contains('.') && fraction.is_empty()) {
                return None;
            }
            whole as f64 + format!("0.{fraction}").parse::<f64>().ok()?
        }
    };
    if fields.next().is_some() || hours > 23 || minutes > 59 || seconds >= 60.0 {
        return None;
    }
    Some((hours as f64 * 3600.0 + minutes as f64 * 60.0 + seconds) / 86_400.0)
}

/// A field of exactly `width` decimal digits.
fn digits(text: &str, width: usize) -> Option<i64> {
    (text.len() == width && text.bytes().all(|b| b.is_ascii_digit())).then(|| text.parse().ok())?
}

fn not_an_iso_date(raw: &str) -> String {
    format!(
        "'{raw}' is not a date as a cell of type d holds: ISO 8601 text of a day from the workbook's first \
         date on (2024-01-15), a time (12:30:00) or both (2024-01-15T12:30:00)"
    )
}

/// A stored number as a cell holds it: below the smallest normal double it is 0, as a typed
/// one is (`-1E-320<0` is FALSE either way), since Excel keeps no subnormal number.
fn normal_or_zero(n: f64) -> f64 {
    if n.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        n
    }
}

/// A stored number that reads as one but past the largest double (`1e400`): Excel writes
/// none, and read as text it would compute silently wrong.
fn past_largest_number(raw: &str) -> String {
    format!("'{raw}' is past the largest number a cell holds (1.79769313486232E+308)")
}

fn formula_attrs(tag: &Tag) -> Result<FormulaAttrs, String> {
    let area = tag.attr("ref").and_then(parse_rect);
    Ok(match tag.attr("t") {
        None | Some(b"normal") => FormulaAttrs::Normal,
        Some(b"array") => FormulaAttrs::Array(area),
        // si is an xsd:unsignedInt: one past it would leave the copies as constants, stale
        // after an edit, so the cell is refused by name.
        Some(b"shared") => match tag.attr("si") {
            Some(si) => match parse_u32(si) {
                Some(index) => FormulaAttrs::Shared(Some(index)),
                None => {
                    let si = String::from_utf8_lossy(si);
                    return Err(format!(
                        "has a shared formula index si=\"{si}\" that is not a number from 0 to 4294967295"
                    ));
                }
            },
            None => FormulaAttrs::Shared(None),
        },
        Some(b"dataTable") => FormulaAttrs::DataTable,
        Some(other) => return Err(format!("has a formula of unknown type t=\"{}\"", String::from_utf8_lossy(other))),
    })
}

fn parse_u32(v: &[u8]) -> Option<u32> {
    // Every cell's and row's `r` comes here: plain digits are read in place; anything else
    // (spaces, a sign, ten digits or more) as text, as before.
    if (1..=9).contains(&v.len()) && v.iter().all(u8::is_ascii_digit) {
        return Some(v.iter().fold(0, |n, &d| n * 10 + u32::from(d - b'0')));
    }
    std::str::from_utf8(v).ok()?.trim().parse().ok()
}

/// `AB12` (no `$`) to a position on the sheet.
pub fn parse_pos(v: &[u8]) -> Option<Pos> {
    let letters = v.iter().take_while(|b| b.is_ascii_alphabetic()).count();
    if letters == 0 || letters > 3 || letters == v.len() {
        return None;
    }
    let mut col: u32 = 0;
    for &b in &v[..letters] {
        col = col * 26 + (b.to_ascii_uppercase() - b'A' + 1) as u32;
    }
    let row = parse_u32(&v[letters..])?;
    ((1..=MAX_ROWS).contains(&row) && (1..=MAX_COLS).contains(&col)).then(|| Pos::new(row - 1, col - 1))
}

fn parse_rect(v: &[u8]) -> Option<Rect> {
    match memchr::memchr(b':', v) {
        Some(i) => Some(Rect::new(parse_pos(&v[..i])?, parse_pos(&v[i + 1..])?)),
        None => parse_pos(v).map(Rect::cell),
    }
}

/// The shared-string table (`xl/sharedStrings.xml`): each `<si>`'s text, rich-text runs
/// joined, phonetic readings (`<rPh>`) left out, as Excel shows the string.
pub fn read_shared_strings(part: impl Read) -> Result<Vec<Rc<str>>, xml::StreamError<ScanError>> {
    let mut strings = Vec::new();
    let mut current: Option<String> = None;
    let mut in_text = false;
    let mut phonetic = false;
    let mut declared: Option<u64> = None;
    xml::stream(part, &mut |event| {
        match event {
            Event::Tag(tag) => match (tag.name, tag.kind) {
                (b"sst", TagKind::Start) => {
                    declared = tag.attr("uniqueCount").and_then(|v| std::str::from_utf8(v).ok()?.trim().parse().ok());
                }
                (b"sst", TagKind::End) => check_unique_count(declared, strings.len())?,
                // `sstItem`: the beta-era (2006) name of `si`, which Excel still opens.
                (b"si" | b"sstItem", TagKind::Start) => current = Some(String::new()),
                (b"si" | b"sstItem", TagKind::Empty) => strings.push(Rc::from("")),
                (b"si" | b"sstItem", TagKind::End) => {
                    let text = current.take().unwrap_or_default();
                    strings.push(Rc::from(&*xml::unescape_excel(&text)));
                }
                (b"rPh", kind) => phonetic = kind == TagKind::Start,
                (b"t", kind) => in_text = kind == TagKind::Start && !phonetic && current.is_some(),
                _ => in_text = false,
            },
            Event::Text(raw) if in_text => {
                let text = std::str::from_utf8(raw)
                    .map_err(|_| (ErrorKind::Damaged, format!("string {} is not UTF-8 text", strings.len())))?;
                xml::unescape_into(text, current.as_mut().expect("text inside <si>")).map_err(|bad| {
                    (ErrorKind::Damaged, format!("string {} holds XML that is not well-formed: {bad}", strings.len()))
                })?;
            }
            Event::CData(raw) if in_text => {
                let text = String::from_utf8_lossy(raw);
                current.as_mut().expect("text inside <si>").push_str(&text);
            }
            _ => {}
        }
        Ok(())
    })?;
    Ok(strings)
}

/// How far a table's `uniqueCount` may claim more strings than it holds. Writers get the
/// count slightly wrong; a claim of a trillion is a hostile file, for which calamine (which
/// opens the package) would reserve memory before reading a string.
const UNIQUE_COUNT_SLACK: u64 = 1 << 20;

fn check_unique_count(declared: Option<u64>, held: usize) -> Result<(), ScanError> {
    match declared {
        Some(n) if n > held as u64 + UNIQUE_COUNT_SLACK => Err((
            ErrorKind::Damaged,
            format!("its uniqueCount says {n} strings but it holds {held} (a damaged or hostile file)"),
        )),
        _ => Ok(()),
    }
}

/// Cells the scanning thread hands to the importing one, a few thousand at a time.
#[derive(Default)]
struct Batch {
    cells: Vec<BatchCell>,
    /// The formula texts of `cells`, end to end.
    text: String,
}

struct BatchCell {
    pos: Pos,
    value: Option<Stored>,
    formula: Option<(FormulaShape, std::ops::Range<usize>)>,
}

/// A [`FormulaXml`] without its text.
#[derive(Clone, Copy)]
enum FormulaShape {
    Plain,
    Array(ArrayFormula),
    SharedText(u32),
    SharedCopy(u32),
}

const BATCH_CELLS: usize = 4096;
/// Batches read ahead: enough to keep both threads busy, few enough to hold little memory.
const BATCHES_AHEAD: usize = 4;

impl Batch {
    /// An empty batch with the room `full` took, so that the next grows no more.
    fn with_room_of(full: &Batch) -> Batch {
        Batch { cells: Vec::with_capacity(full.cells.len()), text: String::with_capacity(full.text.len()) }
    }

    fn push(&mut self, cell: CellXml) {
        let formula = cell.formula.map(|f| {
            let (shape, text) = match f {
                FormulaXml::Plain(text) => (FormulaShape::Plain, text),
                FormulaXml::Array(text, array) => (FormulaShape::Array(array), text),
                FormulaXml::SharedText { index, text } => (FormulaShape::SharedText(index), text),
                FormulaXml::SharedCopy { index } => (FormulaShape::SharedCopy(index), ""),
            };
            let start = self.text.len();
            self.text.push_str(text);
            (shape, start..self.text.len())
        });
        self.cells.push(BatchCell { pos: cell.pos, value: cell.value, formula });
    }

    fn hand_over(self, on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>) -> Result<(), ScanError> {
        let Batch { cells, text } = self;
        for BatchCell { pos, value, formula } in cells {
            let formula = formula.map(|(shape, range)| {
                let text = &text[range];
                match shape {
                    FormulaShape::Plain => FormulaXml::Plain(text),
                    FormulaShape::Array(array) => FormulaXml::Array(text, array),
                    FormulaShape::SharedText(index) => FormulaXml::SharedText { index, text },
                    FormulaShape::SharedCopy(index) => FormulaXml::SharedCopy { index },
                }
            });
            on_cell(CellXml { pos, value, formula })?;
        }
        Ok(())
    }
}

/// [`read_sheet`] on a thread of its own, handing the cells to `on_cell` on this one: the
/// XML is inflated and read while the cells before are stored, so an import takes about
/// the longer of the two instead of their sum. A cell `on_cell` refuses stops the read: the
/// scanner stops at its next batch, and the refusal is the error.
pub fn read_sheet_ahead(
    part: impl Read + Send,
    lookups: CellLookups,
    grid_slots: &mut u64,
    on_cell: &mut dyn FnMut(CellXml) -> Result<(), ScanError>,
) -> Result<SheetScan, xml::StreamError<ScanError>> {
    let (sender, batches) = std::sync::mpsc::sync_channel::<Batch>(BATCHES_AHEAD);
    let mut slots = *grid_slots;
    let mut refused = None;
    let scan = std::thread::scope(|scope| {
        let scanner = scope.spawn(move || {
            let mut batch = Batch::default();
            let scan = read_sheet(part, lookups, &mut slots, &mut |cell| {
                batch.push(cell);
                if batch.cells.len() >= BATCH_CELLS {
                    let room = Batch::with_room_of(&batch);
                    let full = std::mem::replace(&mut batch, room);
                    // The receiver is gone once a cell was refused (or after a panic there,
                    // which the scope passes on): the rest of the part is not read.
                    sender.send(full).map_err(|_| (ErrorKind::Damaged, "a cell was refused".to_string()))?;
                }
                Ok(())
            });
            let _ = sender.send(batch);
            scan.map(|scan| (scan, slots))
        });
        for batch in batches {
            if let Err(e) = batch.hand_over(on_cell) {
                refused = Some(e);
                break;
            }
        }
        scanner.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    });
    if let Some(e) = refused {
        return Err(xml::StreamError::Handler(e));
    }
    let scan = scan?;
    *grid_slots = scan.1;
    Ok(scan.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell's name, value and formula (as `Debug` text).
    type Seen = (String, Option<Value>, String);

    fn strings() -> Vec<Rc<str>> {
        vec!["zero".into(), "one".into()]
    }

    fn cells(xml: &str) -> Result<(Vec<Seen>, SheetScan), String> {
        let strings = strings();
        let mut out = Vec::new();
        let mut slots = 0;
        let lookups =
            CellLookups { string_count: strings.len(), rich_errors: &[Some(XlError::Calc)], ..Default::default() };
        let scan = read_sheet_ahead(xml.as_bytes(), lookups, &mut slots, &mut |c| {
            out.push((cell_name(c.pos), c.value.map(|v| v.into_value(&strings)), format!("{:?}", c.formula)));
            Ok(())
        });
        match scan {
            Ok(scan) => Ok((out, scan)),
            Err(xml::StreamError::Handler(error)) => Err(error.1),
            Err(e) => Err(format!("{e:?}")),
        }
    }

    #[test]
    fn cells_follow_rows_and_columns_when_references_are_left_out() {
        let xml = r#"<worksheet><sheetData><row r="2"><c><v>1</v></c><c s="4"><f>A2*2</f></c></row><row><c r="C3" t="s"><v>1</v></c></row></sheetData></worksheet>"#;
        let (cells, scan) = cells(xml).unwrap();
        let names: Vec<&str> = cells.iter().map(|c| c.0.as_str()).collect();
        assert_eq!(names, ["A2", "B2", "C3"]);
        assert_eq!(cells[0].1, Some(Value::Number(1.0)));
        assert_eq!(cells[1].2, r#"Some(Plain("A2*2"))"#);
        assert_eq!(cells[2].1, Some(Value::text("one")));
        assert_eq!(scan.styled, vec![(Pos::new(1, 1), 4)]);
    }

    #[test]
    fn values_are_read_as_their_type_says() {
        let xml = r#"<worksheet><sheetData><row r="1"><c r="A1" t="b"><v>1</v></c><c r="B1" t="e"><v>#N/A</v></c><c r="C1" t="str"><f>"a"&amp;"b"</f><v>a_x000D_b</v></c><c r="D1" t="inlineStr"><is><r><t>x</t></r><r><t xml:space="preserve"> y</t></r><rPh><t>z</t></rPh></is></c><c r="E1"><v>n/a</v></c><c r="F1" t="d"><v>2024-01-02T00:00:00</v></c></row></sheetData></worksheet>"#;
        let (cells, _) = cells(xml).unwrap();
        let values: Vec<Option<Value>> = cells.into_iter().map(|c| c.1).collect();
        assert_eq!(
            values,
            vec![
                Some(Value::Bool(true)),
                Some(Value::Error(XlError::NA)),
                Some(Value::text("a\rb")),
                Some(Value::text("x y")),
                Some(Value::text("n/a")),
                // A date cell is its serial: 2024-01-02 is 45293 days after 1899-12-30
                // (Python: (date(2024,1,2) - date(1899,12,30)).days), as LibreOffice reads it.
                Some(Value::Number(45293.0)),
            ]
        );
    }

    #[test]
    fn a_date_cell_is_the_serial_of_its_iso_8601_text() {
        // ECMA-376 Part 1 §18.18.11: t="d" holds "a date in the ISO 8601 format". Serials worked
        // in Python, days from 1899-12-30 (1900 system, from March 1900 on) or 1904-01-01:
        // (date(2024,1,15) - date(1899,12,30)).days = 45306, from 1904: 43844; 2024-02-29: 45351;
        // 12:30:15.25 = (12*3600 + 30*60 + 15.25) / 86400 = 0.521009837962963.
        let serial = |text| iso_date_serial(text, DateSystem::From1900);
        assert_eq!(serial("2024-01-15"), Some(45306.0));
        assert_eq!(serial("2024-01-15T06:00:00"), Some(45306.25));
        assert_eq!(serial("2024-01-15T06:00:00Z"), Some(45306.25));
        assert_eq!(serial("2024-02-29T00:00"), Some(45351.0));
        assert_eq!(serial("12:30:15.25"), Some((12.0 * 3600.0 + 30.0 * 60.0 + 15.25) / 86400.0));
        assert_eq!(iso_date_serial("2024-01-15", DateSystem::From1904), Some(43844.0));
        for bad in [
            "2024-13-01",
            "2023-02-29",
            "2024-01-15T24:00:00",
            "2024-1-5",
            "12:60",
            "1899-12-30",
            "inf",
            "2024-01-15T06:00:00+02:00",
            "12:30:15.",
        ] {
            assert_eq!(serial(bad), None, "{bad}");
        }
        assert_eq!(iso_date_serial("1903-12-31", DateSystem::From1904), None);
    }

    #[test]
    fn a_date_cell_that_is_no_date_is_refused_naming_it() {
        let xml = r#"<worksheet><sheetData><row r="1"><c r="A1" t="d"><v>2024-01-15T12:00:00</v></c><c r="B1" t="d"><v>2024-13-45</v></c></row></sheetData></worksheet>"#;
        let e = cells(xml).unwrap_err();
        assert!(e.contains("B1") && e.contains("'2024-13-45' is not a date as a cell of type d holds"), "{e}");
    }

    #[test]
    fn an_error_stored_as_value_with_value_metadata_reads_as_the_error_it_stands_for() {
        // The table of `cells` says value metadata 1 is #CALC!; 2 is past it.
        let xml = r#"<worksheet><sheetData><row r="1"><c r="A1" t="e" vm="1"><v>#VALUE!</v></c><c r="B1" t="e"><v>#VALUE!</v></c><c r="C1" t="e" vm="2"><v>#VALUE!</v></c><c r="D1" t="e" cm="1" vm="1"><f t="array" ref="D1">FILTER(A2:A3,A2:A3&gt;9)</f><v>#VALUE!</v></c></row></sheetData></worksheet>"#;
        let (cells, _) = cells(xml).unwrap();
        let values: Vec<Option<Value>> = cells.into_iter().map(|c| c.1).collect();
        let error = |e| Some(Value::Error(e));
        assert_eq!(values, [error(XlError::Calc), error(XlError::Value), error(XlError::Value), error(XlError::Calc)]);
    }

    #[test]
    fn shared_and_array_formulas_keep_what_the_import_needs() {
        let xml = r#"<worksheet><sheetData><row r="1"><c r="A1"><f t="shared" ref="A1:A2" si="0">B1+1</f><v>2</v></c><c r="B1" cm="1"><f t="array" ref="B1:B3">SEQUENCE(3)</f><v>1</v></c></row><row r="2"><c r="A2"><f t="shared" si="0"/><v>3</v></c></row></sheetData></worksheet>"#;
        let (cells, scan) = cells(xml).unwrap();
        assert_eq!(cells[0].2, r#"Some(SharedText { index: 0, text: "B1+1" })"#);
        assert_eq!(cells[2].2, "Some(SharedCopy { index: 0 })");
        let array =
            ArrayFormula { anchor: Pos::new(0, 1), area: Rect::new(Pos::new(0, 1), Pos::new(2, 1)), dynamic: true };
        assert_eq!(scan.arrays, vec![array]);
    }

    #[test]
    fn bad_cells_name_themselves() {
        let sheet = |data: &str| format!("<worksheet><sheetData>{data}</sheetData></worksheet>");
        let bad_number = cells(&sheet(r#"<row r="1"><c r="A1" t="n"><v>12,5</v></c></row>"#)).unwrap_err();
        assert_eq!(bad_number, "cell A1: '12,5' is not a number");
        let bad_string = cells(&sheet(r#"<row r="1"><c r="B1" t="s"><v>7</v></c></row>"#)).unwrap_err();
        assert_eq!(bad_string, "cell B1: shared string '7' is not in the table (2 strings)");
        let off = cells(&sheet(r#"<row r="1"><c r="A1048577"><v>1</v></c></row>"#)).unwrap_err();
        assert_eq!(off, "a cell's reference 'A1048577' is not a cell of the sheet");
        let row = cells(&sheet(r#"<row r="0"><c><v>1</v></c></row>"#)).unwrap_err();
        assert_eq!(row, "a row's number '0' is not a row of the sheet");
        let nested = cells(&sheet(r#"<row r="1"><c r="A1"><c r="B1"/></c></row>"#)).unwrap_err();
        assert_eq!(nested, "cell A1 holds another cell");
        let cut = cells(r#"<worksheet><sheetData><row r="1"><c r="A1"><v>1</v>"#).unwrap_err();
        assert!(cut.contains("the part ends inside <c>"), "{cut}");
    }

    #[test]
    fn shared_strings_join_runs_and_leave_out_readings() {
        let xml = r#"<sst><si><t>plain</t></si><si><r><t>ri</t></r><r><t>ch</t></r><rPh><t>x</t></rPh></si><si/><si><t>a&amp;b_x000A_</t></si></sst>"#;
        let strings = read_shared_strings(xml.as_bytes()).unwrap();
        let strings: Vec<&str> = strings.iter().map(|s| &**s).collect();
        assert_eq!(strings, ["plain", "rich", "", "a&b\n"]);
    }

    #[test]
    fn column_widths_and_code_name() {
        let xml = r#"<worksheet><sheetPr codeName="Tabelle1"/><cols><col min="2" max="3" width="12.5" customWidth="1"/></cols><sheetData/></worksheet>"#;
        let (_, scan) = cells(xml).unwrap();
        assert_eq!(scan.widths, vec![(1, 2, 12.5)]);
        assert_eq!(scan.code_name.as_deref(), Some("Tabelle1"));
    }
}
