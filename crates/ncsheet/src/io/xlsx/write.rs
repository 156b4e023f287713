//! Export with rust_xlsxwriter: every sheet, constants, formulas in file spelling with their
//! computed results as cached values, dynamic arrays with their spill area, defined names,
//! and the number formats and column widths of a [`Layout`]; links to other workbooks as the
//! source file had them (its external-link parts, and the formulas and names still unedited).
//!
//! rust_xlsxwriter writes no error cells and no empty-text cells: those constants are
//! written as placeholder numbers and put right in the finished package
//! (`rewrite_constants`). A formula result that is text looking like a number is cached as that number
//! (rust_xlsxwriter types results by their text); Excel recalculates on load, so that only
//! matters to viewers that do not.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use crate::io::atomic::Scratch;

use rust_xlsxwriter::{Format, Formula, Worksheet};

use crate::eval::format::cell_style::CellStyle;
use crate::eval::{Env, Value, XlError};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;
use crate::formula::print::{number_literal, quote_sheet_name};
use crate::workbook::{Workbook, MAX_CELLS};

use super::syntax::{self, FileFormula, Storage};
use super::{ArrayFormula, ErrorKind, Layout, XlsxError};

/// Writes the workbook to `path` (xlsx, or xlsm when the name says so), atomically.
pub fn save(wb: &Workbook, path: &Path) -> Result<(), XlsxError> {
    save_with_layout(wb, &Layout::default(), path)
}

/// Writes the workbook with the formats and widths of `layout` to a temporary file in the
/// target's folder, then renames it over the target: an interrupted save leaves the old
/// file as it was.
pub fn save_with_layout(wb: &Workbook, layout: &Layout, path: &Path) -> Result<(), XlsxError> {
    let bytes = to_bytes_for(wb, layout, path)?;
    super::super::atomic::write_bytes(path, Default::default(), &bytes)
        .map_err(|e| XlsxError::new(path, None, ErrorKind::Io, format!("cannot write: {e}")))
}

/// The bytes [`save_with_layout`] writes to `path` (xlsm when the name says so).
pub fn to_bytes_for(wb: &Workbook, layout: &Layout, path: &Path) -> Result<Vec<u8>, XlsxError> {
    let macros = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("xlsm"));
    if macros && layout.vba_project.is_none() {
        let message = "an .xlsm file needs the VBA project of a workbook read from .xlsm; save as .xlsx";
        return Err(XlsxError::new(path, None, ErrorKind::Unwritable, message));
    }
    build(wb, layout, path, macros)
}

/// Why Excel would refuse a sheet name, said briefly (a hostile name may be thousands of
/// characters long): 1 to 31 characters, none of `[ ] : * ? / \`, no `'` at either end.
fn unsavable_sheet_name(name: &str) -> Option<String> {
    let chars = name.chars().count();
    if chars == 0 || chars > 31 {
        return Some(format!("an xlsx sheet name has 1 to 31 characters (Excel's limit), this one {chars}"));
    }
    if let Some(c) = name.chars().find(|c| "[]:*?/\\".contains(*c)) {
        return Some(format!("an xlsx sheet name cannot hold '{c}'"));
    }
    if name.starts_with('\'') || name.ends_with('\'') {
        return Some("an xlsx sheet name cannot begin or end with '".to_string());
    }
    None
}

/// A sheet name short enough to show in a message.
fn clipped_name(name: &str) -> String {
    match name.char_indices().nth(32) {
        Some((at, _)) => format!("sheet {}…", &name[..at]),
        None => format!("sheet {name}"),
    }
}

/// The workbook as xlsx bytes (for benchmarks and tests).
pub fn to_bytes(wb: &Workbook, layout: &Layout) -> Result<Vec<u8>, XlsxError> {
    build(wb, layout, Path::new("(xlsx in memory)"), false)
}

fn build(wb: &Workbook, layout: &Layout, file: &Path, macros: bool) -> Result<Vec<u8>, XlsxError> {
    let fail = |part: Option<&str>, e: rust_xlsxwriter::XlsxError| {
        XlsxError::new(file, part, ErrorKind::Unwritable, e.to_string())
    };
    let mut book = rust_xlsxwriter::Workbook::new();
    // Level 6 (the default) spends most of an export compressing; level 2 is several times
    // faster for files a tenth larger.
    book.set_zip_compression_level(2);
    // Says that the values stored are ncsheet's, not Excel's (see `WRITTEN_BY`).
    book.set_properties(&rust_xlsxwriter::DocProperties::new().set_author(super::WRITTEN_BY));
    let mut formats: HashMap<(Option<&str>, CellStyle), Format> = HashMap::new();
    let names = wb.sheet_names();
    // Per sheet part (`sheetN.xml`, in tab order), constants rust_xlsxwriter cannot write, as
    // written over their placeholders.
    let mut patches: Vec<Vec<(Pos, &'static str)>> = vec![Vec::new(); names.len()];
    // The file lists its sheets in tab order, which a macro may have changed (`Sheets.Add
    // Before:=`, `ws.Move`); a sheet's id stays what formulas hold.
    for (i, &sheet) in wb.tab_order().iter().enumerate() {
        let name = &names[sheet as usize];
        let sheet_layout = layout.sheets.get(name);
        let ws = book.add_worksheet();
        if let Some(why) = unsavable_sheet_name(name) {
            let shown = clipped_name(name);
            return Err(XlsxError::new(file, Some(&shown), ErrorKind::Unwritable, why));
        }
        ws.set_name(name).map_err(|e| fail(Some(name), e))?;
        // A formula whose result is "" must cache "", not rust_xlsxwriter's default 0.
        ws.set_formula_result_default("");
        // Hidden rows stay hidden (SUBTOTAL and AGGREGATE skip them); a row a filter hid is
        // written hidden too, though the filter itself is not written (a new file).
        for (row, _) in wb.hidden_rows(sheet) {
            ws.set_row_hidden(row).map_err(|e| fail(Some(name), e))?;
        }
        // The file opens where it was opened (`<workbookView activeTab>`); a hidden sheet
        // cannot be the active one.
        let visible = wb.sheet_visibility(sheet) == crate::workbook::Visibility::Visible;
        if sheet == wb.active_sheet() && i != 0 && visible {
            ws.set_active(true);
        }
        match wb.sheet_visibility(sheet) {
            crate::workbook::Visibility::Visible => {}
            crate::workbook::Visibility::Hidden => _ = ws.set_hidden(true),
            crate::workbook::Visibility::VeryHidden => _ = ws.set_very_hidden(true),
        }
        if let Some(l) = sheet_layout {
            for &(col, width) in &l.look.column_widths {
                ws.set_column_width_pixels(col, (width * 7.0).round() as u32).map_err(|e| fail(Some(name), e))?;
            }
            for &(row, height) in &l.look.row_heights {
                ws.set_row_height(row, height).map_err(|e| fail(Some(name), e))?;
            }
            for &col in &l.look.hidden_columns {
                ws.set_column_hidden(col).map_err(|e| fail(Some(name), e))?;
            }
            // Before the cells: rust_xlsxwriter writes a link's text into its cell, which the
            // cell's own value then replaces.
            for hyperlink in &l.look.hyperlinks {
                let blank = wb.value(sheet, hyperlink.anchor.first).is_blank();
                write_hyperlink(ws, hyperlink, blank)
                    .map_err(|e| fail(Some(&wb.cell_name(sheet, hyperlink.anchor.first)), e))?;
            }
            if macros {
                if let Some(code_name) = &l.code_name {
                    ws.set_vba_name(code_name).map_err(|e| fail(Some(name), e))?;
                }
            }
        }
        // Before the cells, which keep their looks over the headers rust_xlsxwriter writes.
        super::write_tables::add_tables(ws, wb, sheet).map_err(|(place, e)| fail(Some(&place), e))?;
        for (pos, value) in wb.values(sheet) {
            let value = super::write_tables::header_value(wb, sheet, pos, value);
            let code = sheet_layout.and_then(|l| l.look.number_formats.get(&pos)).map(String::as_str);
            let style = sheet_layout.and_then(|l| l.look.cell_styles.get(&pos)).copied().unwrap_or_default();
            let format = (code.is_some() || !style.is_plain())
                .then(|| &*formats.entry((code, style)).or_insert_with(|| cell_format(code, style)));
            let place = || wb.cell_name(sheet, pos);
            if let Some(area) = wb.array_area(sheet, pos) {
                array_area_fits(file, &place(), area)?;
            }
            match syntax::cell_to_file(wb, sheet, pos, Storage::Legacy) {
                Some(legacy) => {
                    let array = sheet_layout.and_then(|l| l.array_formulas.get(&pos));
                    let linked = layout.links.cells.get(&(sheet, pos)).filter(|l| l.resolved == legacy.text);
                    let original = linked.map(|l| l.original.as_str());
                    write_formula(ws, wb, Cell { sheet, pos, array, original }, legacy, &value, format)
                }
                None => {
                    let patch = match &value {
                        Value::Error(e) => Some(error_cell(*e)),
                        Value::Text(t) if t.is_empty() => Some(r#"t="inlineStr"><is><t></t></is>"#),
                        _ => None,
                    };
                    match patch {
                        Some(p) => {
                            patches[i].push((pos, p));
                            write_value(ws, pos, &Value::Number(0.0), format)
                        }
                        None => write_value(ws, pos, &value, format),
                    }
                }
            }
            .map_err(|e| fail(Some(&place()), e))?;
        }
    }
    for (name, tree, scope) in wb.name_trees() {
        let mut text = syntax::to_file(&tree, wb, Pos::new(0, 0), Storage::Dynamic).text;
        if let Some(linked) = layout.links.names.get(&(name.to_ascii_lowercase(), scope)) {
            if linked.resolved == text {
                text = linked.original.clone();
            }
        }
        let full = match scope {
            Some(s) => format!("{}!{name}", quote_sheet_name(&names[s as usize])),
            None => name.clone(),
        };
        book.define_name(full, &format!("={text}")).map_err(|e| fail(Some(&format!("name {name}")), e))?;
    }
    let mut vba_file = None;
    if macros {
        if let Some(vba) = &layout.vba_project {
            // rust_xlsxwriter reads the project from a path: a scratch file named and cleaned
            // up like every temporary file of a save.
            let scratch = Scratch::beside(file, vba).map_err(|e| {
                XlsxError::new(file, None, ErrorKind::Io, format!("cannot write the VBA project's scratch file: {e}"))
            })?;
            let result = book.add_vba_project(scratch.path()).map(|_| ());
            vba_file = Some(scratch);
            result.map_err(|e| fail(Some("xl/vbaProject.bin"), e))?;
            if let Some(code_name) = &layout.workbook_code_name {
                book.set_vba_name(code_name).map_err(|e| fail(Some("xl/workbook.xml"), e))?;
            }
        }
    }
    let bytes = book.save_to_buffer().map_err(|e| fail(None, e));
    drop(vba_file);
    let bytes = bytes?;
    // Always rewritten: app.xml names ncsheet as the application that saved the package.
    let settings = book_settings(wb);
    rewrite_constants(&bytes, &patches, &settings, &layout.links.parts).map_err(|e| {
        XlsxError::new(file, None, ErrorKind::Unwritable, format!("writing error and empty-text cells: {e}"))
    })
}

/// The type and content of an error cell, after its `<c r=".." s="..">` attributes.
fn error_cell(e: XlError) -> &'static str {
    match e {
        XlError::Null => r#"t="e"><v>#NULL!</v>"#,
        XlError::Div0 => r#"t="e"><v>#DIV/0!</v>"#,
        XlError::Value => r#"t="e"><v>#VALUE!</v>"#,
        XlError::Ref => r#"t="e"><v>#REF!</v>"#,
        XlError::Name => r#"t="e"><v>#NAME?</v>"#,
        XlError::Num => r#"t="e"><v>#NUM!</v>"#,
        XlError::NA => r#"t="e"><v>#N/A</v>"#,
        XlError::GettingData => r#"t="e"><v>#GETTING_DATA</v>"#,
        // Errors newer than the file format's list are stored as Excel stores them for
        // older readers.
        XlError::Spill | XlError::Calc | XlError::Circ => r#"t="e"><v>#VALUE!</v>"#,
    }
}

/// Workbook settings rust_xlsxwriter does not write, as (element of `xl/workbook.xml`,
/// attributes to add to it): the 1904 date system, iterative calculation.
fn book_settings(wb: &Workbook) -> Vec<(&'static str, String)> {
    let mut settings = Vec::new();
    if wb.date_1904() {
        settings.push(("<workbookPr", r#" date1904="1""#.to_string()));
    }
    if let Some(it) = wb.iteration() {
        let attrs = format!(r#" iterate="1" iterateCount="{}" iterateDelta="{}""#, it.count, it.max_change);
        settings.push(("<calcPr", attrs));
    }
    settings
}

/// Adds each setting's attributes to the first element it names (both are empty elements
/// rust_xlsxwriter always writes).
fn rewrite_settings(xml: &str, settings: &[(&str, String)]) -> String {
    let mut xml = xml.to_string();
    for (element, attrs) in settings {
        let Some(start) = xml.find(&format!("{element} ")).or_else(|| xml.find(&format!("{element}/"))) else {
            continue;
        };
        let Some(end) = xml[start..].find("/>").map(|i| start + i) else { continue };
        xml.insert_str(end, attrs);
    }
    xml
}

/// Replaces the placeholder cells of each sheet part (`xl/worksheets/sheetN.xml`, as
/// rust_xlsxwriter names them), adds the workbook settings to `xl/workbook.xml`, names
/// ncsheet as the application that saved the package (so that its cached values are not
/// taken for Excel's) and copies every other part as it is.
fn rewrite_constants(
    package: &[u8],
    patches: &[Vec<(Pos, &str)>],
    settings: &[(&str, String)],
    links: &[(Vec<u8>, Option<Vec<u8>>)],
) -> zip::result::ZipResult<Vec<u8>> {
    use std::io::{Cursor, Read};
    let mut zip = zip::ZipArchive::new(Cursor::new(package))?;
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::with_capacity(package.len())));
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i)?;
        let name = entry.name()?.to_string();
        let linking = !links.is_empty() && LINK_PARENTS.contains(&name.as_str());
        if (name == "xl/workbook.xml" && !settings.is_empty()) || linking {
            let mut xml = String::new();
            entry.read_to_string(&mut xml)?;
            let options = zip::write::SimpleFileOptions::default().compression_method(entry.compression());
            out.start_file(name.as_str(), options)?;
            let mut xml = if name == "xl/workbook.xml" { rewrite_settings(&xml, settings) } else { xml };
            if linking {
                xml = add_link_references(&name, &xml, links.len());
            }
            out.write_all(xml.as_bytes())?;
            continue;
        }
        let cells = name
            .strip_prefix("xl/worksheets/sheet")
            .and_then(|rest| rest.strip_suffix(".xml"))
            .and_then(|n| n.parse::<usize>().ok())
            .and_then(|n| patches.get(n.wrapping_sub(1)))
            .filter(|cells| !cells.is_empty());
        // docProps/app.xml keeps rust_xlsxwriter's `Microsoft Excel`: LibreOffice reads a
        // package whose Application is not Excel's with its own reference syntax (ADDRESS then
        // writes `Sheet2.$C$2`); ncsheet names itself in core.xml instead (`WRITTEN_BY`).
        let Some(cells) = cells else {
            out.raw_copy_file(entry)?;
            continue;
        };
        let mut xml = String::new();
        entry.read_to_string(&mut xml)?;
        let options = zip::write::SimpleFileOptions::default().compression_method(entry.compression());
        out.start_file(name.as_str(), options)?;
        out.write_all(rewrite_cells(&xml, cells).as_bytes())?;
    }
    add_link_parts(&mut out, links)?;
    Ok(out.finish()?.into_inner())
}

/// The parts that name the external-link parts of a package.
const LINK_PARENTS: [&str; 3] = ["xl/workbook.xml", "xl/_rels/workbook.xml.rels", "[Content_Types].xml"];

/// Adds `count` external links to one of [`LINK_PARENTS`]: the `<externalReferences>` of the
/// workbook (after `<sheets>`, where the schema puts them), their relationships, their
/// content types. Relationship ids `rIdLinkN` stay clear of rust_xlsxwriter's `rIdN`.
fn add_link_references(part: &str, xml: &str, count: usize) -> String {
    let numbers = 1..=count;
    let (before, added): (&str, String) = match part {
        "xl/workbook.xml" => {
            let refs: String = numbers.map(|n| format!(r#"<externalReference r:id="rIdLink{n}"/>"#)).collect();
            ("<definedNames>", format!("<externalReferences>{refs}</externalReferences>"))
        }
        "xl/_rels/workbook.xml.rels" => ("</Relationships>", numbers.map(|n| format!(
            r#"<Relationship Id="rIdLink{n}" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/externalLink" Target="externalLinks/externalLink{n}.xml"/>"#
        )).collect()),
        _ => ("</Types>", numbers.map(|n| format!(
            r#"<Override PartName="/xl/externalLinks/externalLink{n}.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.externalLink+xml"/>"#
        )).collect()),
    };
    let mut xml = xml.to_string();
    // A workbook without defined names: the references go after `</sheets>`.
    let at = xml.find(before).or_else(|| xml.find("</sheets>").map(|i| i + "</sheets>".len()));
    if let Some(at) = at {
        xml.insert_str(at, &added);
    }
    xml
}

/// Writes the external-link parts, with their relationships (the linked files), as the
/// source package had them.
fn add_link_parts(
    out: &mut zip::ZipWriter<std::io::Cursor<Vec<u8>>>,
    links: &[(Vec<u8>, Option<Vec<u8>>)],
) -> zip::result::ZipResult<()> {
    let options = zip::write::SimpleFileOptions::default();
    for (n, (part, rels)) in links.iter().enumerate() {
        out.start_file(format!("xl/externalLinks/externalLink{}.xml", n + 1), options)?;
        out.write_all(part)?;
        if let Some(rels) = rels {
            out.start_file(format!("xl/externalLinks/_rels/externalLink{}.xml.rels", n + 1), options)?;
            out.write_all(rels)?;
        }
    }
    Ok(())
}

/// Rewrites the given cells (listed in row order, as the part is written), keeping their
/// style: `<c r="A1" s="2"><v>0</v></c>` becomes `<c r="A1" s="2" t="e"><v>#N/A</v></c>`.
fn rewrite_cells(xml: &str, cells: &[(Pos, &str)]) -> String {
    let mut out = String::with_capacity(xml.len() + 32 * cells.len());
    let mut rest = xml;
    for (pos, body) in cells {
        let tag = format!("<c r=\"{pos}\"");
        let Some(start) = rest.find(&tag) else { continue };
        let Some(open_end) = rest[start..].find('>').map(|i| start + i) else { continue };
        let Some(close) = rest[open_end..].find("</c>").map(|i| open_end + i) else { continue };
        let attrs = rest[start..open_end].trim_end_matches('/');
        out.push_str(&rest[..start]);
        out.push_str(attrs);
        out.push(' ');
        out.push_str(body);
        out.push_str("</c>");
        rest = &rest[close + "</c>".len()..];
    }
    out.push_str(rest);
    out
}

/// Where a formula goes, with the array formula the source file had there.
struct Cell<'a> {
    sheet: SheetId,
    pos: Pos,
    array: Option<&'a ArrayFormula>,
    /// The file's own text of an unedited formula that reads linked workbooks.
    original: Option<&'a str>,
}

fn write_formula(
    ws: &mut Worksheet,
    wb: &Workbook,
    cell: Cell,
    legacy: FileFormula,
    value: &Value,
    format: Option<&Format>,
) -> Result<(), rust_xlsxwriter::XlsxError> {
    let Cell { sheet, pos, array, original } = cell;
    // A legacy array formula goes back as one over its fixed area.
    let fixed_area = wb.array_area(sheet, pos);
    let spill = Env::spill_rect(wb, sheet, pos).filter(|r| !r.is_cell() && fixed_area.is_none());
    // An array formula of the source that did not spill here keeps its area, so that Excel
    // (and LibreOffice) fill it as before; unless cells of ours are in the way.
    let kept = array.filter(|a| spill.is_none() && !a.area.is_cell() && area_is_free(wb, sheet, a));
    let dynamic = spill.is_some()
        || *value == Value::Error(XlError::Spill)
        || kept.is_some_and(|a| a.dynamic)
        || array.is_some_and(|a| a.dynamic);
    let mut file_text = legacy.text;
    if dynamic || legacy.dynamic {
        file_text = syntax::cell_to_file(wb, sheet, pos, Storage::Dynamic).map_or(file_text, |f| f.text);
    }
    if let Some(text) = original {
        file_text = text.to_string();
    }
    // rust_xlsxwriter reads a leading `{` or trailing `}` as array-formula braces and drops
    // them; a space around the formula keeps an array constant whole.
    if file_text.starts_with('{') || file_text.ends_with('}') {
        file_text = format!(" {file_text} ");
    }
    let formula = Formula::new(&file_text).set_result(result_text(value));
    let (row, col) = (pos.row, pos.col as u16);
    let plain = Format::new();
    let f = format.unwrap_or(&plain);
    if let Some(area) = fixed_area {
        return ws
            .write_array_formula_with_format(row, col, area.last.row, area.last.col as u16, formula, f)
            .map(|_| ());
    }
    match (spill, kept) {
        (Some(r), _) => ws.write_dynamic_array_formula_with_format(row, col, r.last.row, r.last.col as u16, formula, f),
        (None, Some(a)) if a.dynamic => {
            let (last_row, last_col) = (a.area.last.row, a.area.last.col as u16);
            ws.write_dynamic_array_formula_with_format(row, col, last_row, last_col, formula, f)
        }
        (None, Some(a)) => {
            let (last_row, last_col) = (a.area.last.row, a.area.last.col as u16);
            ws.write_array_formula_with_format(row, col, last_row, last_col, formula, f)
        }
        (None, None) if dynamic => ws.write_dynamic_formula_with_format(row, col, formula, f),
        (None, None) => match format {
            Some(f) => ws.write_formula_with_format(row, col, formula, f),
            None => ws.write_formula(row, col, formula),
        },
    }
    .map(|_| ())
}

/// A legacy array formula is written with a value in every cell of its area, as Excel stores
/// it: an area past the cells a workbook holds (an .xls record over `A1:IV65536`, 16,777,216
/// cells) would write gigabytes, so the save is refused naming the cell.
fn array_area_fits(file: &Path, place: &str, area: Rect) -> Result<(), XlsxError> {
    let cells = area.rows() as u64 * area.cols() as u64;
    if cells <= MAX_CELLS as u64 {
        return Ok(());
    }
    let message = format!(
        "the array formula over {area} fills {cells} cells, more than the {MAX_CELLS} a workbook holds \
         (ncsheet's limit, docs/limits.md): it cannot be written; enter it over a smaller area"
    );
    Err(XlsxError::new(file, Some(place), ErrorKind::TooLarge, message))
}

/// Whether the area of an array formula holds nothing but its anchor (and is of a sane size).
fn area_is_free(wb: &Workbook, sheet: SheetId, a: &ArrayFormula) -> bool {
    let area = a.area;
    if area.rows() as u64 * area.cols() as u64 > 1 << 20 {
        return false;
    }
    (area.first.row..=area.last.row).all(|row| {
        (area.first.col..=area.last.col).all(|col| {
            let p = Pos::new(row, col);
            p == a.anchor || wb.value(sheet, p).is_blank()
        })
    })
}

/// A constant, or a value an array spilled into (Excel stores those as plain values too).
fn write_value(
    ws: &mut Worksheet,
    pos: Pos,
    value: &Value,
    format: Option<&Format>,
) -> Result<(), rust_xlsxwriter::XlsxError> {
    let (row, col) = (pos.row, pos.col as u16);
    match (value, format) {
        // A cell never holds a LAMBDA (its formula shows #CALC!).
        (Value::Blank | Value::Array(_) | Value::Lambda(_) | Value::Null, _) => Ok(()),
        (Value::Number(n), Some(f)) => ws.write_number_with_format(row, col, *n, f).map(|_| ()),
        (Value::Number(n), None) => ws.write_number(row, col, *n).map(|_| ()),
        (Value::Text(s), Some(f)) => ws.write_string_with_format(row, col, s.as_ref(), f).map(|_| ()),
        (Value::Text(s), None) => ws.write_string(row, col, s.as_ref()).map(|_| ()),
        (Value::Bool(b), Some(f)) => ws.write_boolean_with_format(row, col, *b, f).map(|_| ()),
        (Value::Bool(b), None) => ws.write_boolean(row, col, *b).map(|_| ()),
        (Value::Error(_), _) => unreachable!("error constants are written as placeholders"),
    }
}

/// A hyperlink on its anchor's first cell (rust_xlsxwriter links one cell): a place in the
/// workbook as an `internal:` link (a `location` in the file), anything else as an address
/// outside it (a relationship with TargetMode="External"), its place after a `#`. A link on a
/// blank cell leaves the cell blank.
fn write_hyperlink(
    ws: &mut Worksheet,
    link: &crate::workbook::Hyperlink,
    blank: bool,
) -> Result<(), rust_xlsxwriter::XlsxError> {
    let target = match (link.address.as_str(), link.sub_address.as_str()) {
        ("", place) => format!("internal:{place}"),
        (address, place) => {
            let known = ["http://", "https://", "ftp://", "mailto:", "file://"].iter().any(|s| address.starts_with(s));
            // A file's path, relative or not (rust_xlsxwriter reads it after `file:///`).
            let address = if known { address.to_string() } else { format!("file:///{address}") };
            if place.is_empty() {
                address
            } else {
                format!("{address}#{place}")
            }
        }
    };
    let mut url = rust_xlsxwriter::Url::new(target);
    if let Some(text) = &link.text {
        url = url.set_text(text);
    }
    if let Some(tip) = &link.tip {
        url = url.set_tip(tip);
    }
    let (row, col) = (link.anchor.first.row, link.anchor.first.col as u16);
    ws.write_url(row, col, url)?;
    if blank {
        ws.write_blank(row, col, &Format::new())?;
    }
    Ok(())
}

/// A formula's value as the cached result text rust_xlsxwriter types by its spelling.
fn result_text(value: &Value) -> String {
    match value {
        Value::Number(n) => number_literal(*n),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
        Value::Error(e) => e.as_str().to_string(),
        // "inf" and "nan" would be written as numbers XML cannot hold.
        Value::Text(s) if s.parse::<f64>().is_ok_and(|n| !n.is_finite()) => String::new(),
        Value::Text(s) => s.to_string(),
        Value::Blank | Value::Array(_) | Value::Lambda(_) | Value::Null => String::new(),
    }
}

/// A cell format for a number format code (none: General) and the rest of a cell's style.
fn cell_format(code: Option<&str>, style: CellStyle) -> Format {
    use crate::eval::format::cell_style as xl;
    use rust_xlsxwriter::{Color, FormatAlign};
    let mut format = code.map_or_else(Format::new, number_format);
    let horizontal = match style.horizontal {
        Some(xl::XL_LEFT) => Some(FormatAlign::Left),
        Some(xl::XL_CENTER) => Some(FormatAlign::Center),
        Some(xl::XL_RIGHT) => Some(FormatAlign::Right),
        Some(xl::XL_FILL) => Some(FormatAlign::Fill),
        Some(xl::XL_JUSTIFY) => Some(FormatAlign::Justify),
        Some(xl::XL_CENTER_ACROSS_SELECTION) => Some(FormatAlign::CenterAcross),
        Some(xl::XL_DISTRIBUTED) => Some(FormatAlign::Distributed),
        _ => None,
    };
    let vertical = match style.vertical {
        Some(xl::XL_TOP) => Some(FormatAlign::Top),
        Some(xl::XL_CENTER) => Some(FormatAlign::VerticalCenter),
        Some(xl::XL_JUSTIFY) => Some(FormatAlign::VerticalJustify),
        Some(xl::XL_DISTRIBUTED) => Some(FormatAlign::VerticalDistributed),
        _ => None,
    };
    for align in horizontal.into_iter().chain(vertical) {
        format = format.set_align(align);
    }
    if style.bold {
        format = format.set_bold();
    }
    if style.italic {
        format = format.set_italic();
    }
    if style.wrap {
        format = format.set_text_wrap();
    }
    if let Some(bgr) = style.fill {
        // VBA's RGB puts red in the low byte; the file's colour is RRGGBB.
        format = format.set_background_color(Color::RGB(xl::swap_red_blue(bgr)));
    }
    font_look(format, style)
}

/// The font's colour, size and underline of `style` added to `format`.
fn font_look(mut format: Format, style: CellStyle) -> Format {
    use crate::eval::format::cell_style as xl;
    use rust_xlsxwriter::{Color, FormatUnderline as U};
    if let Some(bgr) = style.font_color {
        format = format.set_font_color(Color::RGB(xl::swap_red_blue(bgr)));
    }
    if let Some(twentieths) = style.font_size {
        format = format.set_font_size(f64::from(twentieths) / 20.0);
    }
    let underline = match style.underline {
        Some(xl::XL_UNDERLINE_SINGLE) => Some(U::Single),
        Some(xl::XL_UNDERLINE_DOUBLE) => Some(U::Double),
        Some(xl::XL_UNDERLINE_SINGLE_ACCOUNTING) => Some(U::SingleAccounting),
        Some(xl::XL_UNDERLINE_DOUBLE_ACCOUNTING) => Some(U::DoubleAccounting),
        _ => None,
    };
    match underline {
        Some(u) => format.set_underline(u),
        None => format,
    }
}

/// A cell format for a number format code: the built-in ones of [`builtin_date_format`] by
/// their index; any other code as written.
fn number_format(code: &str) -> Format {
    match builtin_date_format(code) {
        Some(index) => Format::new().set_num_format_index(index),
        None => Format::new().set_num_format(code),
    }
}

/// The index of a built-in format a code stands for: the built-in date (14), which every
/// Excel shows as its own locale's short date (the reader gives it as `mm-dd-yy`), and the
/// built-in date and time (22) ncsheet gives a date typed with a time.
pub(super) fn builtin_date_format(code: &str) -> Option<u8> {
    match code {
        "m/d/yyyy" | "mm-dd-yy" => Some(14),
        crate::eval::locale::BUILTIN_DATE_TIME => Some(22),
        _ => None,
    }
}
