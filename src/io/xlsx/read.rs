//! Import: calamine reads cell values and formula text (shared formulas expanded for every
//! cell they cover); the raw scan (`raw.rs`) adds array-formula areas, the scope of names,
//! cell styles and column widths.
//!
//! Order matters: every sheet is added before any formula is parsed (so `Sheet3!A1` typed in
//! Sheet1 resolves), names are defined before cells (each definition recalculates, which is
//! free on an empty book), and the whole book is recalculated once at the end.
//!
//! The cells an array formula filled hold only Excel's cached values. They are not stored as
//! constants (they would block our own spill) but kept in [`Imported::cached`] like the
//! results of formula cells.

use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::path::Path;

use calamine::{CellErrorType, DataRef, Reader, Style, Xlsx, XlsxFormulaMetadata};

use crate::eval::{Env, Value, XlError};
use crate::formula::address::{Pos, MAX_COLS, MAX_ROWS};
use crate::formula::ast::SheetId;
use crate::workbook::Workbook;

use super::raw::{Package, SheetEntry, SheetScan};
use super::{syntax, ArrayFormula, CachedValue, ErrorKind, Imported, Layout, SheetLayout, XlsxError};

/// Sheets store each column densely down to its last used row. A workbook needing more
/// slots than this (4 bytes each, 512 MiB) is refused before any is allocated: a few cells
/// far apart must not exhaust memory.
const MAX_GRID_SLOTS: u64 = 1 << 27;

/// Reads an .xlsx or .xlsm file into a recalculated workbook.
pub fn load(path: &Path) -> Result<Imported, XlsxError> {
    let bytes =
        std::fs::read(path).map_err(|e| XlsxError::new(path, None, ErrorKind::Io, format!("cannot read: {e}")))?;
    load_bytes(&bytes, path)
}

/// Reads xlsx bytes into a recalculated workbook; `file` names them in errors.
pub fn load_bytes(bytes: &[u8], file: &Path) -> Result<Imported, XlsxError> {
    let fail = |(part, kind, message): (Option<String>, ErrorKind, String)| {
        XlsxError::new(file, part.as_deref(), kind, message)
    };
    sniff(bytes, file)?;
    let mut package = Package::open(bytes).map_err(fail)?;
    let mut calamine: Xlsx<Cursor<&[u8]>> = Xlsx::new(Cursor::new(bytes)).map_err(|e| calamine_error(file, None, e))?;
    let mut imported =
        Imported { workbook: Workbook::new(), cached: Vec::new(), layout: Layout::default(), notes: Vec::new() };
    if calamine.has_1904_epoch() {
        imported.notes.push("the workbook uses the 1904 date system; date serials are read as stored".into());
    }

    let sheets = package.sheets.clone();
    let mut ids: Vec<Option<SheetId>> = Vec::with_capacity(sheets.len());
    for sheet in &sheets {
        if sheet.kind != "worksheet" {
            imported
                .notes
                .push(format!("sheet '{}' is a {} and was left out: it holds no cells", sheet.name, sheet.kind));
            ids.push(None);
            continue;
        }
        let id = imported
            .workbook
            .add_sheet(&sheet.name)
            .map_err(|e| XlsxError::new(file, Some(&sheet.part), ErrorKind::Damaged, e.to_string()))?;
        ids.push(Some(id));
    }
    define_names(&mut imported, &package, &sheets, &ids);

    let mut slots = 0u64;
    let mut legacy_ranges = Vec::new();
    for (entry, id) in sheets.iter().zip(&ids) {
        let Some(sheet) = *id else { continue };
        let scan = package.scan_sheet(&entry.part).map_err(fail)?;
        slots += scan.grid_slots();
        if slots > MAX_GRID_SLOTS {
            let message = format!(
                "the cells lie too far apart: the sheets would need more than {} MiB of grid",
                (MAX_GRID_SLOTS * 4) >> 20
            );
            return Err(XlsxError::new(file, Some(&entry.part), ErrorKind::TooLarge, message));
        }
        let mut sheet_import = SheetImport { sheet, entry, scan: &scan, legacy_ranges: &mut legacy_ranges };
        let formats = sheet_import.read_cells(&mut calamine, &mut imported, file)?;
        imported.layout.sheets.insert(entry.name.clone(), sheet_layout(&scan, &formats));
    }
    imported.layout.vba_project = package.read_optional("xl/vbaProject.bin").map_err(fail)?;
    imported.layout.workbook_code_name = package.code_name.clone();
    if imported.layout.vba_project.is_some() {
        imported.notes.push("the VBA project is kept for saving as .xlsm; its macros are not run".into());
    }
    imported.workbook.recalculate();
    intersect_legacy_formulas(&mut imported.workbook, &legacy_ranges);
    Ok(imported)
}

/// A formula Excel stored as a plain `<f>` never spills: Excel evaluated it with implicit
/// intersection. Those of them that produced an array here get `@` where Excel intersected
/// (see [`syntax::legacy_intersection`]) and are recalculated.
fn intersect_legacy_formulas(wb: &mut Workbook, candidates: &[(SheetId, Pos)]) {
    for &(sheet, pos) in candidates {
        let spilled = Env::spill_rect(wb, sheet, pos).is_some_and(|r| !r.is_cell());
        if !spilled && wb.value(sheet, pos) != Value::Error(XlError::Spill) {
            continue;
        }
        let Some(text) = wb.formula(sheet, pos) else { continue };
        if let Some(fixed) = syntax::legacy_intersection(text.strip_prefix('=').unwrap_or(&text), wb, sheet, pos) {
            let _ = wb.set_input(sheet, pos, &format!("={fixed}"));
        }
    }
}

/// One worksheet on its way in.
struct SheetImport<'a> {
    sheet: SheetId,
    entry: &'a SheetEntry,
    scan: &'a SheetScan,
    /// Plain (not array) formulas with a range in them: candidates for implicit intersection.
    legacy_ranges: &'a mut Vec<(SheetId, Pos)>,
}

impl SheetImport<'_> {
    /// Reads the cells; returns the number format code of each style index.
    fn read_cells(
        &mut self,
        calamine: &mut Xlsx<Cursor<&[u8]>>,
        imported: &mut Imported,
        file: &Path,
    ) -> Result<Vec<Option<String>>, XlsxError> {
        let (sheet, part) = (self.sheet, self.entry.part.as_str());
        let spilled = spill_children(&self.scan.arrays);
        let anchors: HashSet<Pos> = self.scan.arrays.iter().map(|a| a.anchor).collect();
        let mut reader =
            calamine.worksheet_cells_reader(&self.entry.name).map_err(|e| calamine_error(file, Some(part), e))?;
        let formats = style_formats(reader.styles());
        // Shared formulas: index → (cell holding the text, text). Cells of a shared formula
        // that come before that cell in the file wait for it.
        let mut shared: HashMap<usize, (Pos, String)> = HashMap::new();
        let mut waiting: Vec<(Pos, usize, Option<Value>)> = Vec::new();
        while let Some(cell) =
            reader.next_cell_with_formula_metadata().map_err(|e| calamine_error(file, Some(part), e))?
        {
            let (row, col) = cell.pos;
            if row >= MAX_ROWS || col >= MAX_COLS {
                let message = format!("a cell at row {} column {} is off the sheet", row as u64 + 1, col as u64 + 1);
                return Err(XlsxError::new(file, Some(part), ErrorKind::Damaged, message));
            }
            let pos = Pos::new(row, col);
            let cached = cached_value(&cell.value);
            let text = match cell.formula {
                Some(XlsxFormulaMetadata::Shared { shared_index, formula, .. }) => {
                    shared.insert(shared_index, (pos, formula.clone()));
                    Some(formula)
                }
                Some(XlsxFormulaMetadata::SharedDerived { shared_index }) => match shared.get(&shared_index) {
                    // Relative to the cell that holds the text, which need not be the top
                    // left of the shared range.
                    Some((holder, formula)) => Some(shared_text(formula, *holder, pos)),
                    None => {
                        waiting.push((pos, shared_index, cached));
                        continue;
                    }
                },
                Some(XlsxFormulaMetadata::Normal { formula }) => Some(formula),
                Some(_) => None,
                None => None,
            };
            self.cell(imported, pos, text.filter(|t| !t.trim().is_empty()), cached, &spilled, &anchors);
        }
        for (pos, index, cached) in waiting {
            let text = shared.get(&index).map(|(holder, formula)| shared_text(formula, *holder, pos));
            if text.is_none() {
                imported.notes.push(format!(
                    "{}: the shared formula it belongs to is missing; its value is kept as a constant",
                    imported.workbook.cell_name(sheet, pos)
                ));
            }
            self.cell(imported, pos, text, cached, &spilled, &anchors);
        }
        Ok(formats)
    }

    /// Stores one cell: a formula with its cached result, a value an array filled (kept as
    /// cached only), or a constant.
    fn cell(
        &mut self,
        imported: &mut Imported,
        pos: Pos,
        formula: Option<String>,
        cached: Option<Value>,
        spilled: &HashMap<Pos, Pos>,
        anchors: &HashSet<Pos>,
    ) {
        let sheet = self.sheet;
        let wb = &mut imported.workbook;
        match formula {
            Some(text) => {
                let typed = format!("={}", syntax::from_file(&text, wb, sheet, pos));
                // A formula that does not parse is kept as typed, shows #NAME? and is listed
                // by `Workbook::problems`.
                let _ = wb.set_input_deferred(sheet, pos, &typed);
                if text.contains(':') && !anchors.contains(&pos) {
                    self.legacy_ranges.push((sheet, pos));
                }
                if let Some(value) = cached {
                    imported.cached.push(CachedValue { sheet, pos, value, anchor: pos });
                }
            }
            None => match (spilled.get(&pos), cached) {
                (Some(&anchor), Some(value)) => imported.cached.push(CachedValue { sheet, pos, value, anchor }),
                (None, Some(value)) => wb.set_value_deferred(sheet, pos, value),
                (_, None) => {}
            },
        }
    }
}

/// The text of a shared formula in `pos`, moved from the cell that holds it.
fn shared_text(formula: &str, holder: Pos, pos: Pos) -> String {
    calamine::expand_shared_formula(formula, (holder.row, holder.col), (pos.row, pos.col))
        .unwrap_or_else(|_| formula.to_string())
}

/// Every cell an array formula filled, except its anchor, with the anchor.
fn spill_children(arrays: &[ArrayFormula]) -> HashMap<Pos, Pos> {
    let mut out = HashMap::new();
    for &ArrayFormula { anchor, area, .. } in arrays {
        // An area is bounded by the sheet; the cap only keeps a hostile file from asking
        // for billions of entries (the cells beyond it then read as constants).
        if area.rows() as u64 * area.cols() as u64 > 1 << 22 {
            continue;
        }
        for row in area.first.row..=area.last.row {
            for col in area.first.col..=area.last.col {
                let p = Pos::new(row, col);
                if p != anchor {
                    out.insert(p, anchor);
                }
            }
        }
    }
    out
}

fn define_names(imported: &mut Imported, package: &Package, sheets: &[SheetEntry], ids: &[Option<SheetId>]) {
    for n in &package.names {
        let lower = n.name.to_ascii_lowercase();
        if lower.starts_with("_xlfn.") {
            // Excel's placeholder for a function an older version did not know; no meaning.
            continue;
        }
        if let Some(builtin) = lower.strip_prefix("_xlnm.") {
            let place =
                n.local_sheet.and_then(|i| sheets.get(i)).map_or(String::new(), |s| format!(" of '{}'", s.name));
            let what = builtin.replace('_', " ");
            imported.notes.push(format!("the {}{place} ({}) is not kept", what.trim(), n.formula));
            continue;
        }
        let scope = match n.local_sheet {
            None => None,
            Some(i) => match ids.get(i).copied().flatten() {
                Some(id) => Some(id),
                None => {
                    imported.notes.push(format!("name {} belongs to a sheet that was left out", n.name));
                    continue;
                }
            },
        };
        let wb = &mut imported.workbook;
        let formula = syntax::from_file(&n.formula, wb, scope.unwrap_or(0), Pos::new(0, 0)).into_owned();
        if let Err(e) = wb.define_name(&n.name, &formula, scope) {
            imported.notes.push(format!("name {} ({}) was left out: {e}", n.name, n.formula));
        }
    }
}

/// The format code of each style index, `None` for General.
fn style_formats(styles: &[Style]) -> Vec<Option<String>> {
    styles
        .iter()
        .map(|s| {
            let f = s.number_format.as_ref()?;
            (f.format_id != Some(0) && !f.format_code.eq_ignore_ascii_case("General")).then(|| f.format_code.clone())
        })
        .collect()
}

fn sheet_layout(scan: &SheetScan, formats: &[Option<String>]) -> SheetLayout {
    let mut layout = SheetLayout {
        code_name: scan.code_name.clone(),
        array_formulas: scan.arrays.iter().map(|a| (a.anchor, *a)).collect(),
        ..SheetLayout::default()
    };
    for &(first, last, width) in &scan.widths {
        // `<col min="1" max="16384">` sets the width of the rest of the sheet; only ranges a
        // user sized are worth carrying.
        if last - first < 1024 {
            layout.column_widths.extend((first..=last).map(|c| (c as u16, width)));
        }
    }
    for &(pos, style) in &scan.styled {
        if let Some(Some(code)) = formats.get(style as usize) {
            layout.number_formats.insert(pos, code.clone());
        }
    }
    layout
}

/// A value as calamine read it, `None` for an empty cell.
fn cached_value(v: &DataRef) -> Option<Value> {
    Some(match v {
        DataRef::Empty => return None,
        DataRef::Int(i) => Value::Number(*i as f64),
        DataRef::Float(f) => Value::Number(*f),
        DataRef::DateTime(d) => Value::Number(d.as_f64()),
        DataRef::String(s) | DataRef::DateTimeIso(s) | DataRef::DurationIso(s) => Value::text(s.as_str()),
        DataRef::SharedString(s) => Value::text(*s),
        DataRef::Bool(b) => Value::Bool(*b),
        DataRef::Error(e) => Value::Error(match e {
            CellErrorType::Div0 => XlError::Div0,
            CellErrorType::NA => XlError::NA,
            CellErrorType::Name => XlError::Name,
            CellErrorType::Null => XlError::Null,
            CellErrorType::Num => XlError::Num,
            CellErrorType::Ref => XlError::Ref,
            CellErrorType::Value => XlError::Value,
            CellErrorType::GettingData => XlError::GettingData,
        }),
    })
}

/// Recognizes what is not an xlsx package before a zip reader says something obscure.
fn sniff(bytes: &[u8], file: &Path) -> Result<(), XlsxError> {
    const OLE: [u8; 8] = [0xD0, 0xCF, 0x11, 0xE0, 0xA1, 0xB1, 0x1A, 0xE1];
    if bytes.starts_with(&OLE) {
        // An encrypted xlsx is an OLE container too; calamine tells them apart.
        return Err(match Xlsx::new(Cursor::new(bytes)) {
            Err(calamine::XlsxError::Password) => encrypted(file),
            _ => XlsxError::new(
                file,
                None,
                ErrorKind::LegacyXls,
                "an Excel 97-2003 (.xls) workbook; ncsheet reads .xlsx and .xlsm: save it as .xlsx in Excel",
            ),
        });
    }
    if bytes.is_empty() {
        return Err(XlsxError::new(file, None, ErrorKind::NotXlsx, "the file is empty"));
    }
    if !bytes.starts_with(b"PK") {
        return Err(XlsxError::new(file, None, ErrorKind::NotXlsx, "not an xlsx file (not a zip package)"));
    }
    Ok(())
}

fn encrypted(file: &Path) -> XlsxError {
    let message =
        "the workbook is encrypted with a password; remove it in Excel (File > Info > Protect Workbook) and save again";
    XlsxError::new(file, None, ErrorKind::Encrypted, message)
}

fn calamine_error(file: &Path, part: Option<&str>, e: calamine::XlsxError) -> XlsxError {
    use calamine::XlsxError as E;
    let kind = match &e {
        E::Password => return encrypted(file),
        E::Io(_) => ErrorKind::Io,
        E::Zip(_) if part.is_none() => ErrorKind::NotXlsx,
        _ => ErrorKind::Damaged,
    };
    XlsxError::new(file, part, kind, e.to_string())
}
