//! Excel binary workbooks (`.xlsb`, MS-XLSB): calamine reads the cells, the values Excel
//! stored and the formulas it can spell. Its spelling is trusted only where it is sure: a
//! formula it could not decode (a cell of a shared or array formula) or one reading another
//! sheet (calamine names a 3D reference's sheet by the wrong index) keeps the value Excel
//! stored, as a constant, and a note names the cells.
//!
//! calamine 0.38 spells PtgGe (0x0C, `>=` in [MS-XLSB] 2.5.98.16) as `>` and PtgGt (0x0D) as
//! `>=`; [`comparisons_as_stored`] swaps them back. It also reads a reference's relative-row
//! and relative-column flags the wrong way round, and leaves them in an area's column number
//! (a relative column comes out past XFD); [`references_as_stored`] undoes both.
//! tests/xlsb_corpus.rs computes .xlsb files with all of these, so an upgrade of calamine that
//! mends them shows there. calamine does not read the value of a formula whose result is an
//! error (BrtFmlaError); [`formula_errors`] reads it from the sheet part.

use std::collections::HashMap;
use std::io::{BufReader, Cursor, Read};

use calamine::{Reader, SheetType, Xlsb};

use super::{calamine_sheet, cells_named, value_of, Book};
use crate::eval::{Value, XlError};
use crate::formula::address::column_name;

/// Reads an .xlsb file's bytes into a [`Book`].
pub fn read(bytes: &[u8]) -> Result<Book, String> {
    let mut xlsb: Xlsb<_> = Xlsb::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let application = xlsb.workbook_properties().ok().and_then(|p| p.application);
    let mut book = Book { application, ..Book::default() };
    let metadata = xlsb.sheets_metadata().to_vec();
    let mut errors = formula_errors(bytes)?;
    for meta in &metadata {
        if meta.typ != SheetType::WorkSheet {
            book.notes.push(format!("sheet '{}' is not a worksheet and was left out", meta.name));
            continue;
        }
        let values = xlsb.worksheet_range(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let formulas = xlsb.worksheet_formula(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let mut sheet = calamine_sheet(meta, &values, value_of);
        for (pos, error) in errors.remove(&meta.name).unwrap_or_default() {
            sheet.cells.entry(pos).or_default().value.get_or_insert(Value::Error(error));
        }
        let (r0, c0) = formulas.start().unwrap_or((0, 0));
        let mut unread = Vec::new();
        for (r, c, text) in formulas.used_cells() {
            let pos = (r0 + r as u32, c0 + c as u32);
            if text.is_empty()
                || outside_strings(text).contains('!')
                || text.contains("Ptg")
                || text.starts_with("Unrecognised")
            {
                unread.push(pos);
                continue;
            }
            sheet.cells.entry(pos).or_default().formula = Some(references_as_stored(&comparisons_as_stored(text)));
        }
        if !unread.is_empty() {
            book.notes.push(format!(
                "{} formula cells of sheet '{}' keep the value Excel stored, as a constant: ncsheet reads an .xlsb's \
                 own formulas only, not those shared by a block of cells, array formulas or references to other \
                 sheets ({})",
                unread.len(),
                meta.name,
                cells_named(&meta.name, &unread)
            ));
        }
        book.sheets.push(sheet);
    }
    if !xlsb.defined_names().is_empty() {
        book.notes.push(format!("{} defined names of the .xlsb were left out", xlsb.defined_names().len()));
    }
    book.notes.push("number formats are not read from an .xlsb file: values show as General".into());
    Ok(book)
}

/// Cells by (row, column) with the error each holds.
type CellErrors = Vec<((u32, u32), XlError)>;

/// The error each formula cell holds whose last result was one (BrtFmlaError), by sheet name.
fn formula_errors(bytes: &[u8]) -> Result<HashMap<String, CellErrors>, String> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let mut errors = HashMap::new();
    for (name, part) in sheet_parts(&mut zip)? {
        let Ok(entry) = zip.by_name(&part) else { continue };
        let mut records = Records(BufReader::new(entry));
        let (mut row, mut found) = (0u32, Vec::new());
        while let Some((kind, body)) = records.next_head(16).map_err(|e| format!("{part}: {e}"))? {
            match kind {
                0x0000 if body.len() >= 4 => row = u32_at(&body, 0),
                0x000B if body.len() >= 9 => found.push(((row, u32_at(&body, 0)), super::xls::error_of(body[8]))),
                _ => {}
            }
        }
        errors.insert(name, found);
    }
    Ok(errors)
}

/// Each sheet's name and part, from xl/workbook.bin's BrtBundleSh records and their
/// relationships.
fn sheet_parts<R: Read + std::io::Seek>(zip: &mut zip::ZipArchive<R>) -> Result<Vec<(String, String)>, String> {
    let mut rels = String::new();
    if let Ok(entry) = zip.by_name("xl/_rels/workbook.bin.rels") {
        entry.take(1 << 20).read_to_string(&mut rels).map_err(|e| e.to_string())?;
    }
    let targets: HashMap<&str, &str> = rels
        .split("<Relationship ")
        .skip(1)
        .filter_map(|r| Some((attribute(r, "Id")?, attribute(r, "Target")?)))
        .collect();
    let entry = zip.by_name("xl/workbook.bin").map_err(|e| e.to_string())?;
    let mut records = Records(BufReader::new(entry));
    let mut parts = Vec::new();
    while let Some((kind, body)) = records.next_head(4096).map_err(|e| format!("xl/workbook.bin: {e}"))? {
        if kind != 0x009C {
            continue;
        }
        // BrtBundleSh: hsState, iTabID, strRelID (null: no part), strName.
        let Some((rel, rest)) = wide_string(body.get(8..).unwrap_or_default()) else { continue };
        let Some((name, _)) = wide_string(rest) else { continue };
        if let Some(target) = targets.get(rel.as_str()) {
            let part = target.strip_prefix('/').map_or_else(|| format!("xl/{target}"), str::to_string);
            parts.push((name, part));
        }
    }
    Ok(parts)
}

/// The value of `name="…"` in an XML start tag's text.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\"")).or_else(|| tag.starts_with(&format!("{name}=\"")).then_some(0))?;
    let value = &tag[start..];
    let value = &value[value.find('"')? + 1..];
    Some(&value[..value.find('"')?])
}

/// An XLWideString (a count of UTF-16 units, then the units) and what follows it; `None`
/// for a null string or one past the record's end.
fn wide_string(bytes: &[u8]) -> Option<(String, &[u8])> {
    let count = usize::try_from(u32::from_le_bytes(bytes.get(..4)?.try_into().ok()?)).ok()?;
    let units: Vec<u16> =
        bytes.get(4..4 + count.checked_mul(2)?)?.chunks(2).map(|u| u16::from_le_bytes([u[0], u[1]])).collect();
    Some((String::from_utf16_lossy(&units), &bytes[4 + count * 2..]))
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// The records of a part ([MS-XLSB] 2.1.4), read as a stream.
struct Records<R: Read>(R);

impl<R: Read> Records<R> {
    /// The next record's type and the first `keep` bytes of its body (the rest is skipped);
    /// `None` at the part's end.
    fn next_head(&mut self, keep: u64) -> std::io::Result<Option<(u16, Vec<u8>)>> {
        let Some(kind) = self.varint(2)? else { return Ok(None) };
        let size = self.varint(4)?.ok_or_else(|| std::io::Error::other("a record cut short"))?;
        let mut head = Vec::new();
        (&mut self.0).take(size.min(keep)).read_to_end(&mut head)?;
        std::io::copy(&mut (&mut self.0).take(size.saturating_sub(keep)), &mut std::io::sink())?;
        Ok(Some((kind as u16, head)))
    }

    /// A little-endian number of at most `bytes` bytes, 7 bits each, the high bit saying
    /// another follows; `None` at the end of the stream.
    fn varint(&mut self, bytes: u32) -> std::io::Result<Option<u64>> {
        let mut value = 0u64;
        for i in 0..bytes {
            let mut byte = [0u8];
            if self.0.read(&mut byte)? == 0 {
                return if i == 0 { Ok(None) } else { Err(std::io::Error::other("a record cut short")) };
            }
            value |= u64::from(byte[0] & 0x7F) << (7 * i);
            if byte[0] & 0x80 == 0 {
                break;
            }
        }
        Ok(Some(value))
    }
}

/// A formula's text without its string constants (a `!` in `"Hello!"` is no sheet's).
fn outside_strings(text: &str) -> String {
    text.split('"').step_by(2).collect()
}

/// calamine's spelling of a formula with `>` and `>=` outside string constants swapped back
/// (calamine names PtgGe `>` and PtgGt `>=`); `<>` and `<=` are left alone.
fn comparisons_as_stored(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    let mut chars = text.chars().peekable();
    let mut in_string = false;
    let mut previous = None;
    while let Some(c) = chars.next() {
        if c == '"' {
            in_string = !in_string;
        }
        if c == '>' && !in_string && previous != Some('<') {
            if chars.peek() == Some(&'=') {
                chars.next();
                out.push('>');
            } else {
                out.push_str(">=");
            }
            previous = Some('>');
            continue;
        }
        out.push(c);
        previous = Some(c);
    }
    out
}

/// One cell of calamine's spelling: `$`, column letters, `$`, row digits.
struct Spelled {
    first_dollar: bool,
    column: u32,
    second_dollar: bool,
    row: String,
}

/// Whether `c` may sit right before a reference: anything but a name's or a sheet's end.
fn may_precede(c: Option<&char>) -> bool {
    c.is_none_or(|c| !(c.is_alphanumeric() || matches!(c, '_' | '.' | '$' | '!' | '\'' | ']')))
}

/// Whether `c` may sit right after a reference: not a name's, nor a call's `(`.
fn may_follow(c: Option<&char>) -> bool {
    c.is_none_or(|c| !(c.is_alphanumeric() || matches!(c, '_' | '.' | '$' | '!' | '(')))
}

/// The cell spelled at `chars[at..]` and where it ends.
fn spelled_at(chars: &[char], at: usize) -> Option<(Spelled, usize)> {
    let mut i = at;
    let first_dollar = chars.get(i) == Some(&'$');
    i += usize::from(first_dollar);
    let letters = i;
    while i < chars.len() && chars[i].is_ascii_uppercase() && i - letters < 4 {
        i += 1;
    }
    if i == letters {
        return None;
    }
    let column = chars[letters..i].iter().fold(0u32, |n, c| n * 26 + (*c as u32 - 'A' as u32 + 1)) - 1;
    let second_dollar = chars.get(i) == Some(&'$');
    i += usize::from(second_dollar);
    let digits = i;
    while i < chars.len() && chars[i].is_ascii_digit() {
        i += 1;
    }
    if i == digits {
        return None;
    }
    let row = chars[digits..i].iter().collect();
    Some((Spelled { first_dollar, column, second_dollar, row }, i))
}

fn cell_text(column: u32, column_absolute: bool, row: &str, row_absolute: bool) -> String {
    let dollar = |on: bool| if on { "$" } else { "" };
    format!("{}{}{}{row}", dollar(column_absolute), column_name(column), dollar(row_absolute))
}

/// A single cell as stored: calamine writes the row's `$` before the column and the
/// column's after it.
fn single_as_stored(cell: &Spelled) -> String {
    cell_text(cell.column, cell.second_dollar, &cell.row, cell.first_dollar)
}

/// One end of an area as stored: calamine writes `$` on both and leaves the flags in the
/// column number (0x4000: the column is relative, 0x8000: the row is).
fn area_end_as_stored(cell: &Spelled) -> String {
    cell_text(cell.column & 0x3FFF, cell.column & 0x4000 == 0, &cell.row, cell.column & 0x8000 == 0)
}

/// calamine's spelling of a formula with its cell and area references, outside string
/// constants, as the file stores them (see the module's comment).
fn references_as_stored(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut in_string = false;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '"' {
            in_string = !in_string;
        }
        let starts = !in_string && may_precede(i.checked_sub(1).and_then(|p| chars.get(p)));
        if let Some((first, end)) = starts.then(|| spelled_at(&chars, i)).flatten() {
            let second = (chars.get(end) == Some(&':')).then(|| spelled_at(&chars, end + 1)).flatten();
            match second {
                Some((second, end2)) if may_follow(chars.get(end2)) => {
                    let calamines_area = [&first, &second].iter().all(|c| c.first_dollar && c.second_dollar);
                    let ends = if calamines_area {
                        [area_end_as_stored(&first), area_end_as_stored(&second)]
                    } else {
                        [single_as_stored(&first), single_as_stored(&second)]
                    };
                    out.push_str(&ends.join(":"));
                    i = end2;
                    continue;
                }
                None if may_follow(chars.get(end)) => {
                    out.push_str(&single_as_stored(&first));
                    i = end;
                    continue;
                }
                _ => {}
            }
        }
        out.push(c);
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{comparisons_as_stored, outside_strings, references_as_stored};

    #[test]
    fn a_bang_in_a_string_is_no_sheet_reference() {
        assert!(!outside_strings("\"Hello!\"&A1").contains('!'));
        assert!(outside_strings("Sheet2!A1&\"x\"").contains('!'));
    }

    #[test]
    fn calamines_reference_flags_are_read_as_stored() {
        // A relative area: both flags in each column number (0xC000 + column).
        assert_eq!(references_as_stored("SUM($BTRM$2:$BTRN$2)"), "SUM(A2:B2)");
        // Column relative only (0x4000 + column), and an absolute area left alone.
        assert_eq!(references_as_stored("DCOUNTA($XFE$1:$XFL$11,F$1,$A$1:$H$11)"), "DCOUNTA(A$1:H$11,$F1,$A$1:$H$11)");
        // Single cells swap their marks; names, functions and strings are left alone.
        assert_eq!(references_as_stored("A$2>$B2+LOG10(C3)&\"$D$4 E5\""), "$A2>B$2+LOG10(C3)&\"$D$4 E5\"");
    }

    #[test]
    fn calamines_greater_than_operators_are_swapped_back_outside_strings() {
        assert_eq!(comparisons_as_stored("A1>B1"), "A1>=B1");
        assert_eq!(comparisons_as_stored("A1>=B1"), "A1>B1");
        assert_eq!(comparisons_as_stored("IF(A1<>B1,A1<=B1,\"a>b\">\"c>=d\")"), "IF(A1<>B1,A1<=B1,\"a>b\">=\"c>=d\")");
    }
}
