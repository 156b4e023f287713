//! Workbooks of the other spreadsheet formats ncsheet reads but does not write: Excel 97–2003
//! (`.xls`, BIFF8: `xls.rs`, its formulas decoded by `biff.rs`), Excel's binary workbook
//! (`.xlsb`: `xlsb.rs`) and OpenDocument (`.ods`: `ods.rs`).
//!
//! Each reader turns its file into a [`Book`]: cells with their values, formulas in the
//! spelling of an xlsx file (`_xlfn.` and all), array formulas with their area, number format
//! codes and defined names. The book is then written as an xlsx package in memory and read
//! by the one xlsx importer, so that formulas, names, the values the file cached (for
//! `eval --check`), implicit intersection and number formats take one path whatever the
//! file. What a reader cannot carry over is a note, and a formula it cannot read keeps the
//! value the file cached, as a constant, with a note naming the cells.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{Cursor, Read, Write};
use std::path::Path;

use crate::eval::Value;
use crate::formula::address::{column_name, Rect};
use crate::workbook::Visibility;

use super::limits::ReadLimits;
use super::xlsx::{self, Imported};
use super::{Error, ErrorKind};

pub mod biff;
pub mod ods;
pub mod xls;
pub mod xlsb;

/// The formats of this module.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Xls,
    Xlsb,
    Ods,
}

impl Kind {
    /// How the format is called in messages.
    pub fn describe(self) -> &'static str {
        match self {
            Kind::Xls => "an Excel 97-2003 (.xls, BIFF8) workbook",
            Kind::Xlsb => "an Excel binary (.xlsb) workbook",
            Kind::Ods => "an OpenDocument (.ods) spreadsheet",
        }
    }
}

/// A workbook as another format held it, on its way to the xlsx importer.
#[derive(Debug, Default)]
pub struct Book {
    pub sheets: Vec<Sheet>,
    pub names: Vec<Name>,
    pub date_1904: bool,
    /// The program that saved the file, when it says.
    pub application: Option<String>,
    /// The language of the Excel that saved the file, when it says and it is not English
    /// (`fr`): CELL reads its info_type in it too.
    pub excel_language: Option<&'static str>,
    /// What the reader left out, one sentence each.
    pub notes: Vec<String>,
}

#[derive(Debug, Default)]
pub struct Sheet {
    pub name: String,
    pub visibility: Visibility,
    /// By (row, column), 0-based.
    pub cells: BTreeMap<(u32, u32), Cell>,
}

/// One cell: a constant (`value` only), a formula with the value the file cached, or a cell
/// an array formula filled (its value only, inside an anchor's `array`).
#[derive(Debug, Default, Clone)]
pub struct Cell {
    pub value: Option<Value>,
    /// The formula as an xlsx file spells it, without `=`.
    pub formula: Option<String>,
    /// The area of the array formula anchored here.
    pub array: Option<Rect>,
    /// The number format code, when not General.
    pub format: Option<String>,
}

/// A defined name: its formula as an xlsx file spells it, and the index in
/// [`Book::sheets`] of the sheet it belongs to (`None`: the workbook).
#[derive(Debug, Clone)]
pub struct Name {
    pub name: String,
    pub formula: String,
    pub sheet: Option<usize>,
}

/// Reads a file of `kind` into a recalculated workbook through the xlsx importer; the parts
/// of an .xlsb and an .ods inflate within `limits`.
pub fn load(bytes: &[u8], path: &Path, kind: Kind, limits: ReadLimits) -> Result<Imported, Error> {
    let fail = |message: String| Error::new(path, ErrorKind::Xlsx { part: None, message });
    let book = match kind {
        Kind::Xls => xls::read(bytes),
        Kind::Xlsb => xlsb::read(bytes, limits),
        Kind::Ods => ods::read(bytes, limits),
    }
    .and_then(|book| within_limits(&book).map(|()| book))
    .and_then(|book| distinct_sheet_names(&book).map(|()| book))
    .and_then(|book| finite_numbers(&book).map(|()| book))
    .map_err(|m| fail(format!("{} that cannot be read: {m}", kind.describe())))?;
    let package = to_package(&book).map_err(|e| fail(format!("cannot convert {}: {e}", kind.describe())))?;
    let mut imported = xlsx::load_bytes(&package, path)?;
    imported.written_by = book.application.clone();
    imported.workbook.set_excel_language(book.excel_language);
    let mut notes = book.notes;
    notes.append(&mut imported.notes);
    imported.notes = notes;
    Ok(imported)
}

/// The most cells (values and formulas) a file of these formats may hold: the workbook's own
/// limit, met here before each is held as a cell of the book and again as the xlsx text the
/// importer reads.
pub use crate::workbook::MAX_CELLS;

/// The most bytes of text (values and formulas) the cells of one file may hold together: a
/// string the file shares among cells is written out again for each.
pub const MAX_TEXT: usize = 512 << 20;

/// The refusal of a file past [`MAX_CELLS`].
pub fn too_many_cells() -> String {
    format!("the file holds more than {MAX_CELLS} cells, ncsheet's limit on the cells of a file it converts")
}

/// Refuses a book past [`MAX_CELLS`] or [`MAX_TEXT`] before it is written out as xlsx text.
fn within_limits(book: &Book) -> Result<(), String> {
    let cells: usize = book.sheets.iter().map(|s| s.cells.len()).sum();
    if cells > MAX_CELLS {
        return Err(too_many_cells());
    }
    let mut text = 0usize;
    for cell in book.sheets.iter().flat_map(|s| s.cells.values()) {
        if let Some(Value::Text(t)) = &cell.value {
            text += t.len();
        }
        text += cell.formula.as_ref().map_or(0, String::len);
        if text > MAX_TEXT {
            return Err(format!(
                "its cells hold more than {} MiB of text, ncsheet's limit on the text of a file it converts",
                MAX_TEXT >> 20
            ));
        }
    }
    Ok(())
}

/// Refuses a book two of whose sheets have one name as Excel and LibreOffice compare sheet
/// names, without case (`Abc` and `ABC`), naming both sheets of the file: the workbook
/// would refuse the second naming a part of the package converted in memory, which the file
/// does not have.
fn distinct_sheet_names(book: &Book) -> Result<(), String> {
    let mut seen = std::collections::HashMap::new();
    for sheet in &book.sheets {
        if let Some(first) = seen.insert(sheet.name.to_ascii_lowercase(), &sheet.name) {
            return Err(format!(
                "sheet '{}' has the name of sheet '{}' (sheet names are told apart without case)",
                crate::io::notes::quoted(&sheet.name),
                crate::io::notes::quoted(first)
            ));
        }
    }
    Ok(())
}

/// Refuses a book with a number no cell holds: an infinity or a NaN, which a binary file
/// can store in a number's bits and an .ods file in its text (`office:value="1e400"`), is
/// named with its cell, as the xlsx reader names `<v>1e400</v>`, where it was written out
/// as 0 and computed on as a number the file never held.
fn finite_numbers(book: &Book) -> Result<(), String> {
    for sheet in &book.sheets {
        for (&(row, col), cell) in &sheet.cells {
            let Some(Value::Number(n)) = &cell.value else { continue };
            if !n.is_finite() {
                return Err(format!(
                    "sheet '{}': cell {}{} stores {n}, which is no number a cell holds (Excel's numbers are finite, \
                     up to 1.79769313486232E+308): a damaged or hostile file",
                    sheet.name,
                    column_name(col),
                    row + 1
                ));
            }
        }
    }
    Ok(())
}

/// What saving a workbook read from a file of `kind` as xlsx leaves behind.
pub fn conversion_loss(source: &Path, kind: Kind) -> String {
    format!(
        "{} is {}, written anew as .xlsx: of it only cells, formulas, defined names and number formats are kept; \
         charts, drawings, comments, other styles, column widths, merged cells, validation, conditional formats, \
         macros and the rest are lost",
        source.display(),
        kind.describe()
    )
}

/// The book as an xlsx package: workbook, sheets, styles (the number formats) and the
/// application that saved the original, each part as the importer reads it.
fn to_package(book: &Book) -> Result<Vec<u8>, std::io::Error> {
    let mut formats: Vec<String> = Vec::new();
    let mut sheets_xml = Vec::with_capacity(book.sheets.len());
    for sheet in &book.sheets {
        sheets_xml.push(sheet_xml(sheet, &mut formats));
    }
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    let mut put = |name: &str, text: &str| -> Result<(), std::io::Error> {
        zip.start_file(name, options).map_err(std::io::Error::other)?;
        zip.write_all(text.as_bytes())
    };
    put("[Content_Types].xml", &content_types(book.sheets.len()))?;
    put("_rels/.rels", ROOT_RELS)?;
    put("docProps/app.xml", &app_xml(book.application.as_deref()))?;
    put("xl/workbook.xml", &workbook_xml(book))?;
    put("xl/_rels/workbook.xml.rels", &workbook_rels(book.sheets.len()))?;
    put("xl/styles.xml", &styles_xml(&formats))?;
    for (i, xml) in sheets_xml.iter().enumerate() {
        put(&format!("xl/worksheets/sheet{}.xml", i + 1), xml)?;
    }
    Ok(zip.finish().map_err(std::io::Error::other)?.into_inner())
}

const MAIN_NS: &str = "http://schemas.openxmlformats.org/spreadsheetml/2006/main";
const REL_NS: &str = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";
const ROOT_RELS: &str = r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/><Relationship Id="rId2" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/extended-properties" Target="docProps/app.xml"/></Relationships>"#;

fn content_types(sheets: usize) -> String {
    let mut xml = String::from(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/styles.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.styles+xml"/><Override PartName="/docProps/app.xml" ContentType="application/vnd.openxmlformats-officedocument.extended-properties+xml"/>"#,
    );
    for i in 1..=sheets {
        let _ = write!(
            xml,
            r#"<Override PartName="/xl/worksheets/sheet{i}.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/>"#
        );
    }
    xml.push_str("</Types>");
    xml
}

fn app_xml(application: Option<&str>) -> String {
    let app = application.map(escape).unwrap_or_default();
    format!(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<Properties xmlns="http://schemas.openxmlformats.org/officeDocument/2006/extended-properties"><Application>{app}</Application></Properties>"#
    )
}

fn workbook_xml(book: &Book) -> String {
    let mut xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<workbook xmlns="{MAIN_NS}" xmlns:r="{REL_NS}"><workbookPr{}/><sheets>"#,
        if book.date_1904 { r#" date1904="1""# } else { "" }
    );
    for (i, sheet) in book.sheets.iter().enumerate() {
        let state = match sheet.visibility {
            Visibility::Visible => "",
            Visibility::Hidden => r#" state="hidden""#,
            Visibility::VeryHidden => r#" state="veryHidden""#,
        };
        let _ =
            write!(xml, r#"<sheet name="{}" sheetId="{}"{state} r:id="rId{}"/>"#, escape(&sheet.name), i + 1, i + 1);
    }
    xml.push_str("</sheets>");
    if !book.names.is_empty() {
        xml.push_str("<definedNames>");
        for name in &book.names {
            let scope = name.sheet.map(|s| format!(r#" localSheetId="{s}""#)).unwrap_or_default();
            let _ = write!(
                xml,
                r#"<definedName name="{}"{scope}>{}</definedName>"#,
                escape(&name.name),
                escape(&name.formula)
            );
        }
        xml.push_str("</definedNames>");
    }
    xml.push_str(r#"<calcPr calcId="0"/></workbook>"#);
    xml
}

fn workbook_rels(sheets: usize) -> String {
    let mut xml = String::from(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">"#,
    );
    for i in 1..=sheets {
        let _ =
            write!(xml, r#"<Relationship Id="rId{i}" Type="{REL_NS}/worksheet" Target="worksheets/sheet{i}.xml"/>"#);
    }
    let _ = write!(xml, r#"<Relationship Id="rId{}" Type="{REL_NS}/styles" Target="styles.xml"/>"#, sheets + 1);
    xml.push_str("</Relationships>");
    xml
}

/// The styles part: style 0 is General, style `i` (from 1) the number format `formats[i-1]`.
fn styles_xml(formats: &[String]) -> String {
    let mut xml = format!(r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?><styleSheet xmlns="{MAIN_NS}">"#);
    if !formats.is_empty() {
        let _ = write!(xml, r#"<numFmts count="{}">"#, formats.len());
        for (i, code) in formats.iter().enumerate() {
            let _ = write!(xml, r#"<numFmt numFmtId="{}" formatCode="{}"/>"#, 164 + i, escape(code));
        }
        xml.push_str("</numFmts>");
    }
    xml.push_str(
        r#"<fonts count="1"><font><sz val="10"/><name val="Arial"/></font></fonts><fills count="1"><fill><patternFill patternType="none"/></fill></fills><borders count="1"><border/></borders><cellStyleXfs count="1"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/></cellStyleXfs>"#,
    );
    let _ = write!(
        xml,
        r#"<cellXfs count="{}"><xf numFmtId="0" fontId="0" fillId="0" borderId="0" xfId="0"/>"#,
        formats.len() + 1
    );
    for i in 0..formats.len() {
        let _ = write!(
            xml,
            r#"<xf numFmtId="{}" fontId="0" fillId="0" borderId="0" xfId="0" applyNumberFormat="1"/>"#,
            164 + i
        );
    }
    xml.push_str("</cellXfs></styleSheet>");
    xml
}

/// A worksheet part; the number formats its cells use are added to `formats`.
fn sheet_xml(sheet: &Sheet, formats: &mut Vec<String>) -> String {
    let mut xml =
        format!(r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?><worksheet xmlns="{MAIN_NS}"><sheetData>"#);
    let mut row_open = None;
    for (&(row, col), cell) in &sheet.cells {
        if row_open != Some(row) {
            if row_open.is_some() {
                xml.push_str("</row>");
            }
            let _ = write!(xml, r#"<row r="{}">"#, row + 1);
            row_open = Some(row);
        }
        let _ = write!(xml, r#"<c r="{}{}""#, column_name(col), row + 1);
        if let Some(code) = &cell.format {
            let index = formats.iter().position(|f| f == code).unwrap_or_else(|| {
                formats.push(code.clone());
                formats.len() - 1
            });
            let _ = write!(xml, r#" s="{}""#, index + 1);
        }
        write_cell_body(&mut xml, cell);
    }
    if row_open.is_some() {
        xml.push_str("</row>");
    }
    xml.push_str("</sheetData></worksheet>");
    xml
}

/// A cell's type attribute, formula and value, from the end of its start tag.
fn write_cell_body(xml: &mut String, cell: &Cell) {
    let formula = cell.formula.as_deref();
    let (kind, value) = match &cell.value {
        None | Some(Value::Blank) => ("", None),
        Some(Value::Number(n)) => ("", Some(number_text(*n))),
        Some(Value::Bool(b)) => (r#" t="b""#, Some(if *b { "1" } else { "0" }.to_string())),
        Some(Value::Error(e)) => (r#" t="e""#, Some(e.as_str().to_string())),
        Some(Value::Text(t)) if formula.is_some() => (r#" t="str""#, Some(escape_text(t))),
        Some(Value::Text(t)) => {
            let _ = write!(xml, r#" t="inlineStr"><is><t xml:space="preserve">{}</t></is></c>"#, escape_text(t));
            return;
        }
        Some(other) => ("", Some(other.to_string())),
    };
    xml.push_str(kind);
    xml.push('>');
    if let Some(f) = formula {
        match cell.array {
            Some(area) => {
                let _ = write!(xml, r#"<f t="array" ref="{area}">{}</f>"#, escape(f));
            }
            None => {
                let _ = write!(xml, "<f>{}</f>", escape(f));
            }
        }
    }
    if let Some(v) = value {
        let _ = write!(xml, "<v>{v}</v>");
    }
    xml.push_str("</c>");
}

/// A number as an xlsx file stores it: the shortest text that reads back the same.
fn number_text(n: f64) -> String {
    if n.is_finite() {
        format!("{n:?}").trim_end_matches(".0").to_string()
    } else {
        "0".into()
    }
}

/// Text for an XML attribute or element.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\r' => out.push_str("&#13;"),
            '\n' => out.push_str("&#10;"),
            '\t' => out.push_str("&#9;"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "_x{:04X}_", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// A cell's text for the xlsx reader, which reads `_xHHHH_` as a character: an underscore
/// that would start one is itself escaped (`_x005F_`).
fn escape_text(text: &str) -> String {
    if !text.contains("_x") {
        return escape(text);
    }
    escape(&text.replace("_x", "_x005F_x"))
}

/// A value a file cached, from the spreadsheet's own terms, as ncsheet's.
pub fn value_of(data: &calamine::Data) -> Option<Value> {
    use calamine::Data;
    Some(match data {
        Data::Empty => return None,
        Data::Int(i) => Value::Number(*i as f64),
        Data::Float(f) => Value::Number(*f),
        Data::String(s) => Value::Text(s.as_str().into()),
        Data::Bool(b) => Value::Bool(*b),
        Data::DateTime(d) => Value::Number(d.as_f64()),
        Data::DateTimeIso(s) | Data::DurationIso(s) => Value::Text(s.as_str().into()),
        Data::Error(e) => Value::Error(error_of(e)),
    })
}

/// A sheet calamine read, with its stored values (`value` turns each into ncsheet's) and
/// no formulas yet.
fn calamine_sheet(
    meta: &calamine::Sheet,
    values: &calamine::Range<calamine::Data>,
    value: impl Fn(&calamine::Data) -> Option<Value>,
) -> Sheet {
    let visibility = match meta.visible {
        calamine::SheetVisible::Visible => Visibility::Visible,
        calamine::SheetVisible::Hidden => Visibility::Hidden,
        calamine::SheetVisible::VeryHidden => Visibility::VeryHidden,
    };
    let mut sheet = Sheet { name: meta.name.clone(), visibility, ..Sheet::default() };
    let (r0, c0) = values.start().unwrap_or((0, 0));
    for (r, c, data) in values.used_cells() {
        sheet.cells.insert((r0 + r as u32, c0 + c as u32), Cell { value: value(data), ..Cell::default() });
    }
    sheet
}

/// calamine's error as Excel's.
fn error_of(e: &calamine::CellErrorType) -> crate::eval::XlError {
    use crate::eval::XlError;
    use calamine::CellErrorType as C;
    match e {
        C::Div0 => XlError::Div0,
        C::NA => XlError::NA,
        C::Name => XlError::Name,
        C::Null => XlError::Null,
        C::Num => XlError::Num,
        C::Ref => XlError::Ref,
        C::Value => XlError::Value,
        C::GettingData => XlError::GettingData,
    }
}

/// Cells whose formula was not carried over, for a note: the first few and how many.
pub fn cells_named(sheet: &str, cells: &[(u32, u32)]) -> String {
    let mut out = String::new();
    for &(row, col) in cells.iter().take(5) {
        if !out.is_empty() {
            out.push_str(", ");
        }
        let _ = write!(out, "{}!{}{}", quoted_sheet(sheet), column_name(col), row + 1);
    }
    if cells.len() > 5 {
        let _ = write!(out, " and {} more", cells.len() - 5);
    }
    out
}

/// A sheet name as a formula writes it before `!`: quoted unless it is a plain word.
pub fn quoted_sheet(name: &str) -> String {
    let plain = !name.is_empty()
        && name.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '.')
        && !name.starts_with(|c: char| c.is_ascii_digit() || c == '.')
        && !looks_like_reference(name);
    if plain {
        name.to_string()
    } else {
        format!("'{}'", name.replace('\'', "''"))
    }
}

/// Whether a word reads as a cell reference (`A1`, `XFD100`, `R1C1`) and so needs quotes
/// as a sheet name.
fn looks_like_reference(name: &str) -> bool {
    let upper = name.to_ascii_uppercase();
    let letters = upper.chars().take_while(|c| c.is_ascii_alphabetic()).count();
    let digits = &upper[letters..];
    let a1 = (1..=3).contains(&letters) && !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit());
    let r1c1 = upper.starts_with('R') && upper[1..].chars().any(|c| c == 'C');
    a1 || r1c1 || upper == "TRUE" || upper == "FALSE"
}

impl Kind {
    /// The [`super::Format`] of this kind.
    pub fn format(self) -> super::Format {
        match self {
            Kind::Xls => super::Format::Xls,
            Kind::Xlsb => super::Format::Xlsb,
            Kind::Ods => super::Format::Ods,
        }
    }
}

/// The format of a file by its bytes, when it is one of this module's: a compound file with
/// a `Workbook` stream (BIFF8; `Book` for older BIFF, refused by the reader with its
/// reason), a zip package with `xl/workbook.bin`, or one whose `mimetype` is an OpenDocument
/// spreadsheet's. An encrypted xlsx is a compound file too, but with no workbook stream.
pub fn detect(bytes: &[u8]) -> Option<Kind> {
    const OLE: [u8; 8] = [0xD0, 0xCF, 0x11, 0xE0, 0xA1, 0xB1, 0x1A, 0xE1];
    if bytes.starts_with(&OLE) {
        let cfb = cfb::CompoundFile::open(Cursor::new(bytes)).ok()?;
        return (cfb.is_stream("/Workbook") || cfb.is_stream("/Book")).then_some(Kind::Xls);
    }
    if !bytes.starts_with(b"PK\x03\x04") {
        return None;
    }
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).ok()?;
    if zip.index_for_name("xl/workbook.bin").is_some() {
        return Some(Kind::Xlsb);
    }
    let mut mimetype = String::new();
    let entry = zip.by_name("mimetype").ok()?;
    std::io::Read::take(entry, 100).read_to_string(&mut mimetype).ok()?;
    (mimetype.trim() == "application/vnd.oasis.opendocument.spreadsheet").then_some(Kind::Ods)
}
