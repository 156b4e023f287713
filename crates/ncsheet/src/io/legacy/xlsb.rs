//! Excel binary workbooks (`.xlsb`, MS-XLSB): calamine reads the cells, the values Excel
//! stored and the formulas it can spell. Its spelling is trusted only where it is sure: a
//! formula it could not decode (a cell of a shared or array formula) or one reading another
//! sheet (calamine names a 3D reference's sheet by the wrong index) keeps the value Excel
//! stored, as a constant, and a note names the cells.

use std::io::Cursor;

use calamine::{Reader, SheetType, Xlsb};

use super::{calamine_sheet, cells_named, value_of, Book};

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
            sheet.cells.entry(pos).or_default().formula = Some(text.clone());
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
