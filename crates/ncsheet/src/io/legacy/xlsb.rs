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
//! mends them shows there.

use std::io::Cursor;

use calamine::{Reader, SheetType, Xlsb};

use super::{calamine_sheet, cells_named, value_of, Book};
use crate::formula::address::column_name;

/// Reads an .xlsb file's bytes into a [`Book`].
pub fn read(bytes: &[u8]) -> Result<Book, String> {
    let mut xlsb: Xlsb<_> = Xlsb::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let application = xlsb.workbook_properties().ok().and_then(|p| p.application);
    let mut book = Book { application, ..Book::default() };
    let metadata = xlsb.sheets_metadata().to_vec();
    for meta in &metadata {
        if meta.typ != SheetType::WorkSheet {
            book.notes.push(format!("sheet '{}' is not a worksheet and was left out", meta.name));
            continue;
        }
        let values = xlsb.worksheet_range(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let formulas = xlsb.worksheet_formula(&meta.name).map_err(|e| format!("sheet '{}': {e}", meta.name))?;
        let mut sheet = calamine_sheet(meta, &values, value_of);
        let (r0, c0) = formulas.start().unwrap_or((0, 0));
        let mut unread = Vec::new();
        for (r, c, text) in formulas.used_cells() {
            let pos = (r0 + r as u32, c0 + c as u32);
            if text.is_empty() || text.contains('!') || text.contains("Ptg") || text.starts_with("Unrecognised") {
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
    use super::{comparisons_as_stored, references_as_stored};

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
