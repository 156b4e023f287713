//! Import: calamine opens the package and reads the styles; the worksheets' cells, their
//! formulas as stored (shared formulas expanded for every cell they cover, array-formula
//! areas) and the column widths come from one streaming pass over each sheet's XML
//! (`sheet_xml.rs`); the sheet list and the scope of names from `raw.rs`.
//!
//! Order matters: every sheet is added before any formula is parsed (so `Sheet3!A1` typed in
//! Sheet1 resolves), names are defined before cells (none recalculates), and the whole book
//! is recalculated once at the end.
//!
//! The cells an array formula filled hold only Excel's cached values. They are not stored as
//! constants (they would block our own spill) but kept in [`Imported::cached`] like the
//! results of formula cells.

use crate::io::limits::ReadLimits;
use crate::io::notes;
use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::path::Path;
use std::rc::Rc;

use calamine::{Reader, Style, Xlsx};

use crate::eval::evaluator::MAX_TEXT;
use crate::eval::format::cell_style::{self, CellStyle};
use crate::eval::{RowHidden, Value, XlError};
use crate::formula::address::{Pos, Rect, MAX_COLS};
use crate::formula::ast::SheetId;
use crate::formula::parse::ParseError;
use crate::workbook::{too_long_text, Hyperlink, Workbook, WorkbookError};

use super::external::{self, ExternalBook};
use super::pivot;
use super::raw::{self, Package, SheetEntry};
use super::sheet_span;
use super::sheet_xml::{self, CellXml, FormulaXml, ScanError, SheetScan};
use super::syntax::{self, Storage};
use super::tables::{self, Table};
use super::xml::{Event, StreamError};
use super::{ArrayFormula, CachedValue, ErrorKind, Imported, Layout, LinkedFormula, SheetLayout, XlsxError};
use super::{NEW_WORKBOOK_APPLICATION, WRITTEN_BY};

/// Reads an .xlsx or .xlsm file into a recalculated workbook.
pub fn load(path: &Path) -> Result<Imported, XlsxError> {
    let bytes =
        std::fs::read(path).map_err(|e| XlsxError::new(path, None, ErrorKind::Io, format!("cannot read: {e}")))?;
    load_bytes(&bytes, path)
}

/// The program that last saved the package, if it says: [`WRITTEN_BY`] for a workbook
/// ncsheet wrote new, else `docProps/app.xml`'s `Application`. ncsheet cannot name itself in
/// app.xml (LibreOffice reads a package whose Application is not Excel's with its own
/// reference syntax), so it names itself as core.xml's last author, which Excel and
/// LibreOffice replace when they save the file again.
/// A part that is not well-formed is an error naming it (as Excel refuses it), not a
/// program left unnamed.
fn written_by(package: &mut Package) -> Result<Option<String>, raw::Err> {
    let application = element_text(package, "docProps/app.xml", "Application")?;
    let last_author = element_text(package, "docProps/core.xml", "lastModifiedBy")?;
    Ok(match (application, last_author) {
        (Some(app), Some(author)) if app == NEW_WORKBOOK_APPLICATION && author == WRITTEN_BY => {
            Some(WRITTEN_BY.to_string())
        }
        (application, _) => application,
    })
}

/// The text of the first element named `local` (with any namespace prefix) of a part.
fn element_text(package: &mut Package, part: &str, local: &str) -> Result<Option<String>, raw::Err> {
    let Some(bytes) = package.read_optional(part)? else { return Ok(None) };
    Ok(first_element_text(&bytes, local))
}

fn first_element_text(bytes: &[u8], local: &str) -> Option<String> {
    let text = std::str::from_utf8(bytes).ok()?;
    let mut rest = text;
    while let Some(at) = rest.find('<') {
        rest = &rest[at + 1..];
        let tag = &rest[..rest.find('>')?];
        let name = tag.split_whitespace().next().unwrap_or("");
        if name.rsplit(':').next() == Some(local) && !name.starts_with('/') && !tag.ends_with('/') {
            let body = &rest[tag.len() + 1..];
            return Some(body[..body.find('<')?].trim().to_string());
        }
    }
    None
}

/// Reads xlsx bytes into a recalculated workbook; `file` names them in errors.
pub fn load_bytes(bytes: &[u8], file: &Path) -> Result<Imported, XlsxError> {
    load_bytes_limited(bytes, file, ReadLimits::default())
}

/// [`load_bytes`] with every part held to `limits` while it inflates.
pub fn load_bytes_limited(bytes: &[u8], file: &Path, limits: ReadLimits) -> Result<Imported, XlsxError> {
    let fail = |(part, kind, message): (Option<String>, ErrorKind, String)| {
        XlsxError::new(file, part.as_deref(), kind, message)
    };
    sniff(bytes, file)?;
    let mut package = Package::open_limited(bytes, limits).map_err(fail)?;
    let strings = shared_strings(&mut package, file)?;
    let read_before = package.shared_strings.clone();
    package.check_parts_calamine_reads(&[read_before.as_deref().unwrap_or_default()]).map_err(fail)?;
    let calamine_view = calamine_view(&mut package, bytes, file)?;
    let mut calamine: Xlsx<Cursor<&[u8]>> = match Xlsx::new(Cursor::new(&calamine_view[..])) {
        Ok(calamine) => calamine,
        Err(e) => {
            let part = part_calamine_opened(&package, &e);
            return Err(
                damaged_workbook_part(&mut package, file).unwrap_or_else(|| calamine_error(file, part.as_deref(), e))
            );
        }
    };
    let written_by = written_by(&mut package).map_err(fail)?;
    let mut imported = Imported {
        workbook: Workbook::new(),
        cached: Vec::new(),
        layout: Layout::default(),
        notes: Vec::new(),
        written_by,
        uncached: Vec::new(),
    };
    if calamine.has_1904_epoch() {
        imported.workbook.set_date_1904(true);
    }
    imported.workbook.set_iteration(package.iteration);

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
        imported.workbook.set_sheet_visibility(id, sheet.visibility);
        ids.push(Some(id));
    }
    // A chart or dialog sheet left out cannot be active: the first sheet is then.
    if let Some(&Some(active)) = ids.get(package.active_tab) {
        imported.workbook.set_active_sheet(active);
    }
    // Each sheet's relationships read once, for its tables and its pivot tables.
    let related = related_parts(&mut package, &sheets, &ids);
    let tables = read_tables(&mut package, &related, &mut imported.notes);
    let pivots = read_pivots(&mut package, &related, imported.workbook.date_1904(), &mut imported.notes);
    pivot::install(&mut imported.workbook, pivots);
    imported.layout.tables = tables.clone();
    if !tables.is_empty() {
        imported.workbook.set_tables(tables.clone());
    }
    imported.layout.calculation = package.calculation.clone();
    let links = read_links(&mut package, &mut imported.notes);
    imported.layout.external_links = links.iter().flatten().count();
    if imported.layout.external_links > 0 {
        imported.layout.links.parts = link_parts(&mut package, &mut imported.notes);
    }
    let mut book = BookParts { tables, links, range_names: HashSet::new() };
    define_names(&mut imported, &package, &sheets, &ids, &book);
    book.range_names = range_names(&imported.workbook);
    // A table's name alone (`=Parts`) names its data, a range.
    book.range_names.extend(book.tables.iter().map(|t| t.name.to_lowercase()));

    let rich_errors = package.rich_errors().map_err(fail)?;
    let lookups = sheet_xml::CellLookups {
        string_count: strings.len(),
        rich_errors: &rich_errors,
        dates: imported.workbook.date_system(),
    };
    let mut grid_slots = 0u64;
    let mut scans = Vec::new();
    let mut legacy_ranges = Vec::new();
    for (entry, id) in sheets.iter().zip(&ids) {
        let Some(sheet) = *id else { continue };
        let mut sheet_import = SheetImport::new(sheet, &entry.part, &mut legacy_ranges, &book);
        let part = package.entry(&entry.part).map_err(fail)?;
        let scan = sheet_xml::read_sheet_ahead(part, lookups, &mut grid_slots, &mut |cell| {
            sheet_import.cell(&mut imported, &strings, cell)
        })
        .map_err(|e| stream_error(file, &entry.part, e))?;
        sheet_import.finish(&mut imported);
        hide_rows(&mut imported.workbook, &mut package, entry, sheet, &scan);
        set_widths(&mut imported.workbook, sheet, &scan);
        let hyperlinks = hyperlinks(&mut package, &entry.part, &scan).map_err(fail)?;
        scans.push((entry.name.clone(), scan, hyperlinks));
    }
    // After the sheets: calamine reads the first one up to its cells, which the pass above
    // has held to the limits.
    let looks = style_looks(&mut calamine, &sheets, file)?;
    for (name, scan, hyperlinks) in scans {
        let mut layout = sheet_layout(&scan, &looks);
        layout.look.hyperlinks = hyperlinks;
        imported.layout.sheets.insert(name, layout);
    }
    imported.layout.vba_project = package.read_optional("xl/vbaProject.bin").map_err(fail)?;
    imported.layout.workbook_code_name = package.code_name.clone();
    if imported.layout.vba_project.is_some() {
        imported.notes.push(
            "the VBA project is kept for saving as .xlsm; its Subs run only when asked (run --sub MODULE.SUB)".into(),
        );
    }
    if imported.workbook.iteration().is_some() {
        for c in &imported.cached {
            imported.workbook.set_starting_value_deferred(c.sheet, c.pos, c.value.clone());
        }
    }
    imported.workbook.recalculate();
    if imported.workbook.iteration().is_none() {
        keep_cached_cycles(&mut imported);
    }
    let arrays = array_anchors(&imported.layout, &imported.workbook);
    intersect_legacy_formulas(&mut imported.workbook, &legacy_ranges, &arrays);
    note_resolved_links(&mut imported);
    Ok(imported)
}

/// Excel keeps the cells of a circular reference at the values it last calculated, the
/// values the file cached: the cycles' cells start from them and keep them (computed once
/// more, only when the workbook has a cycle).
fn keep_cached_cycles(imported: &mut Imported) {
    let cells: HashSet<(SheetId, Pos)> = imported.workbook.cycle_cells().into_iter().collect();
    if cells.is_empty() {
        return;
    }
    for c in &imported.cached {
        if c.anchor == c.pos && cells.contains(&(c.sheet, c.pos)) {
            let value = match imported.workbook.array_area(c.sheet, c.pos) {
                // An area past the array limit (a file's `{=…}` over a whole sheet) holds one
                // value beyond its result: it starts from the anchor's, as a scalar fills it.
                Some(area) if !crate::eval::too_many_items(area.rows() as usize, area.cols() as usize) => {
                    cached_area(&imported.cached, c.sheet, area)
                }
                _ => c.value.clone(),
            };
            imported.workbook.set_starting_value_deferred(c.sheet, c.pos, value);
        }
    }
    imported.workbook.recalculate();
}

/// The values the file cached over an array formula's area, as one array: what the formula
/// showed in each of its cells. Only the block up to the last cached cell is stored, the rest
/// of the area blank (the array's tail), so the cost is the cells the file holds.
fn cached_area(cached: &[super::CachedValue], sheet: SheetId, area: Rect) -> Value {
    let of_area = || cached.iter().filter(move |c| c.sheet == sheet && c.anchor == area.first && area.contains(c.pos));
    let offset = |pos: Pos| ((pos.row - area.first.row) as usize, (pos.col - area.first.col) as usize);
    let (rows, cols) = of_area().map(|c| offset(c.pos)).fold((1, 1), |(r, k), (cr, ck)| (r.max(cr + 1), k.max(ck + 1)));
    let mut data = vec![Value::Blank; rows * cols];
    for c in of_area() {
        let (r, k) = offset(c.pos);
        data[r * cols + k] = c.value.clone();
    }
    let block = crate::eval::Array::new(rows, cols, data);
    Value::from(block.with_tail(area.rows() as usize, area.cols() as usize, Value::Blank))
}

/// Each external-link part with its relationships part (which names the linked file), in
/// the file's numbering; none when one is missing, as `[n]` could then not keep its number
/// (`read_links` noted an unreadable link part; an unreadable relationships part is noted here).
fn link_parts(package: &mut Package, notes: &mut Vec<String>) -> Vec<(Vec<u8>, Option<Vec<u8>>)> {
    let mut parts = Vec::new();
    for part in package.external_links.clone() {
        let Some(part) = part else { return Vec::new() };
        let Ok(Some(xml)) = package.read_optional(&part) else { return Vec::new() };
        let (dir, file) = part.rsplit_once('/').unwrap_or(("", part.as_str()));
        let rels = format!("{dir}/_rels/{file}.rels");
        let rels = match read_or_why(package, rels.trim_start_matches('/')) {
            Ok(rels) => rels,
            Err(why) => {
                notes.push(format!("{why}; the linked workbook's file name is unknown"));
                None
            }
        };
        parts.push((xml, rels));
    }
    parts
}

/// A part a feature needs beside the cells (a table, a pivot table, a link to another
/// workbook): its bytes, or `None` when the package lacks it. One that cannot be read (its
/// XML is not well-formed, it is past a limit) is an error naming the part and why, for the
/// caller's note: never dropped silently. A save over the source still copies such a part
/// byte for byte, as every part it does not rewrite.
fn read_or_why(package: &mut Package, part: &str) -> Result<Option<Vec<u8>>, String> {
    package.read_optional(part).map_err(|(_, _, why)| format!("{part}: {why}"))
}

/// Notes, for each formula and name that read linked workbooks, how ncsheet writes what it
/// read: a save writes the file's own text back while that is unchanged.
fn note_resolved_links(imported: &mut Imported) {
    let links = &mut imported.layout.links;
    if links.parts.is_empty() {
        links.cells.clear();
        links.names.clear();
        return;
    }
    let wb = &imported.workbook;
    links.cells.retain(|&(sheet, pos), formula| match syntax::cell_to_file(wb, sheet, pos, Storage::Legacy) {
        Some(file) => {
            formula.resolved = file.text;
            true
        }
        None => false,
    });
    for (name, tree, scope) in wb.name_trees() {
        if let Some(formula) = links.names.get_mut(&(name.to_ascii_lowercase(), scope)) {
            formula.resolved = syntax::to_file(&tree, wb, Pos::new(0, 0), Storage::Dynamic).text;
        }
    }
    links.names.retain(|_, formula| !formula.resolved.is_empty());
}

/// Whether the formula text reads a linked workbook the importer resolved.
fn reads_links(text: &str, book: &BookParts) -> bool {
    !book.links.is_empty() && text.contains('[') && matches!(external::resolve_links(text, &book.links), Cow::Owned(_))
}

/// The look of each style index, as calamine read the styles part. calamine hands styles out
/// with a sheet's cell reader, which reads the sheet only up to its cells.
fn style_looks(
    calamine: &mut Xlsx<Cursor<&[u8]>>,
    sheets: &[SheetEntry],
    file: &Path,
) -> Result<Vec<StyleLook>, XlsxError> {
    let Some(first) = sheets.iter().find(|s| s.kind == "worksheet") else { return Ok(Vec::new()) };
    let reader =
        calamine.worksheet_cells_reader(&first.name).map_err(|e| calamine_error(file, Some(&first.part), e))?;
    Ok(reader.styles().iter().map(|s| StyleLook { format: style_format(s), style: cell_style(s) }).collect())
}

/// What one style index (`<xf>` of `cellXfs`) shows: a number format code (`None` for
/// General) and the rest of the look ncsheet keeps.
struct StyleLook {
    format: Option<String>,
    style: CellStyle,
}

fn shared_strings(package: &mut Package, file: &Path) -> Result<Vec<Rc<str>>, XlsxError> {
    let Some(part) = package.shared_strings.clone() else { return Ok(Vec::new()) };
    let entry = match package.entry(&part) {
        Ok(entry) => entry,
        // Excel reads a workbook whose relationship names a missing table; its cells say
        // whether a string was needed.
        Err((_, ErrorKind::Damaged, _)) => return Ok(Vec::new()),
        Err((part, kind, message)) => return Err(XlsxError::new(file, part.as_deref(), kind, message)),
    };
    sheet_xml::read_shared_strings(entry).map_err(|e| stream_error(file, &part, e))
}

/// When calamine cannot open the workbook, the workbook-level part whose XML is broken, so
/// the error names it (calamine's own does not): the package's and the workbook's
/// relationships first, then the workbook and the parts they name.
fn damaged_workbook_part(package: &mut Package, file: &Path) -> Option<XlsxError> {
    let workbook = package.workbook_parts.first().cloned().unwrap_or_else(|| "xl/workbook.xml".into());
    let relationships = ["_rels/.rels".to_string(), raw::relationships_part(&workbook)];
    for part in relationships.into_iter().chain(package.workbook_parts.clone()) {
        let Ok(entry) = package.entry(&part) else { continue };
        if let Err(e) = crate::io::xlsx::xml::stream(entry, &mut defined_entities_only) {
            return Some(stream_error(file, &part, e));
        }
    }
    None
}

/// The part calamine was reading when it opened the package and met the end of its XML
/// before the closing tag it names (`XmlEof`: a part whose root is another element, such as
/// a styles part holding `<notStyles/>`); calamine's message names no part. `None` for a
/// tag two parts share (the package's and the workbook's relationships).
fn part_calamine_opened(package: &Package, e: &calamine::XlsxError) -> Option<String> {
    let calamine::XlsxError::XmlEof(tag) = e else { return None };
    let workbook = package.workbook_parts.first().cloned().unwrap_or_else(|| "xl/workbook.xml".into());
    let dir = workbook.rsplit_once('/').map_or("xl", |(dir, _)| dir);
    match *tag {
        "styleSheet" | "numFmts" | "fonts" | "fills" | "borders" | "cellXfs" | "xf" => {
            Some(format!("{dir}/styles.xml"))
        }
        "sst" | "t" | "" => Some(package.shared_strings.clone().unwrap_or_else(|| format!("{dir}/sharedStrings.xml"))),
        "workbook" => Some(workbook),
        _ => None,
    }
}

/// A text event's and an attribute value's entities are XML's own: `&bogus;` is not
/// well-formed, as Excel and calamine (whose message names no part) hold too. Its bytes are
/// UTF-8: calamine's "cannot decode input using UTF-8" named no part either.
fn defined_entities_only(event: Event) -> Result<(), ScanError> {
    if super::xml::not_utf8(&event) {
        return Err((ErrorKind::Damaged, "the XML is not well-formed: bytes that are not UTF-8 text".into()));
    }
    match super::xml::bad_reference_in(&event) {
        Some(bad) => Err((ErrorKind::Damaged, format!("the XML is not well-formed: {bad}"))),
        None => Ok(()),
    }
}

fn stream_error(file: &Path, part: &str, e: StreamError<ScanError>) -> XlsxError {
    match e {
        StreamError::Io(e) => match raw::past_limit(&e) {
            Some(limit) => XlsxError::new(file, Some(part), ErrorKind::TooLarge, limit.to_string()),
            None => XlsxError::new(file, Some(part), ErrorKind::Damaged, format!("damaged zip entry: {e}")),
        },
        StreamError::Xml { offset, message } => {
            let message = format!("the XML is not well-formed at byte {offset}: {message}");
            XlsxError::new(file, Some(part), ErrorKind::Damaged, message)
        }
        StreamError::Handler((kind, message)) => XlsxError::new(file, Some(part), kind, message),
    }
}

/// The anchors of the file's array formulas (legacy and dynamic), by sheet.
fn array_anchors(layout: &Layout, wb: &Workbook) -> HashMap<(SheetId, Pos), ()> {
    let mut anchors = HashMap::new();
    for (name, sheet_layout) in &layout.sheets {
        let Some(sheet) = wb.sheet_id(name) else { continue };
        anchors.extend(sheet_layout.array_formulas.keys().map(|&pos| ((sheet, pos), ())));
    }
    anchors
}

/// A formula Excel stored as a plain `<f>` never spills: Excel evaluated it with implicit
/// intersection. Those of them that produced an array here, or that consume a range where
/// Excel intersected it (`SUM(A1:A9*2)`, decided once per shared formula, among the
/// `candidates` that name ranges), get `@` where Excel intersected (see
/// [`syntax::legacy_intersection`]) and are recalculated. A result that is still an array
/// is intersected as a whole, as Excel shows a legacy formula's result: a reference in line
/// with the cell, or an array's first item (`=ROW(A3:A8)` shows 3).
///
/// Each step rewrites all its formulas first and recalculates once after them: a
/// recalculation per formula recomputed everything reading it each time, so 2,000 legacy
/// formulas each reading the next one's cell took minutes (quadratic in the chain).
fn intersect_legacy_formulas(wb: &mut Workbook, candidates: &[(SheetId, Pos)], arrays: &HashMap<(SheetId, Pos), ()>) {
    // By formula id, for the sheet of the candidates at hand (they come sheet by sheet; a
    // sheet met again only decides again): an index, not a hash, as a million are looked up.
    let mut decided: Vec<Option<bool>> = Vec::new();
    let mut deciding_for = None;
    let mut rewritten = Vec::new();
    for &(sheet, pos) in candidates {
        let Some(id) = wb.formula_id(sheet, pos) else { continue };
        if deciding_for != Some(sheet) {
            decided.clear();
            deciding_for = Some(sheet);
        }
        if decided.len() <= id as usize {
            decided.resize(id as usize + 1, None);
        }
        let intersects = match decided[id as usize] {
            Some(known) => known,
            None => {
                let Some(tree) = wb.formula_tree(sheet, pos) else { continue };
                let found = syntax::intersects_in_scalar_formula(&tree, wb, sheet);
                decided[id as usize] = Some(found);
                found
            }
        };
        if intersects && !spills(wb, sheet, pos) {
            let Some(tree) = wb.formula_tree(sheet, pos) else { continue };
            if let Some(fixed) = syntax::legacy_operand_intersection(&tree, wb, sheet) {
                wb.set_formula_tree_deferred(sheet, pos, fixed);
                rewritten.push((sheet, pos));
            }
        }
    }
    recalculate_rewritten(wb, &mut rewritten);
    let legacy: Vec<(SheetId, Pos)> =
        wb.spilling_cells().into_iter().filter(|place| !arrays.contains_key(place)).collect();
    for &(sheet, pos) in &legacy {
        let Some(tree) = wb.formula_tree(sheet, pos) else { continue };
        if let Some(fixed) = syntax::legacy_intersection(&tree, wb, sheet) {
            wb.set_formula_tree_deferred(sheet, pos, fixed);
            rewritten.push((sheet, pos));
        }
    }
    recalculate_rewritten(wb, &mut rewritten);
    for &(sheet, pos) in &legacy {
        if spills(wb, sheet, pos) {
            let Some(tree) = wb.formula_tree(sheet, pos) else { continue };
            if let Some(whole) = syntax::whole_intersection(&tree) {
                wb.set_formula_tree_deferred(sheet, pos, whole);
                rewritten.push((sheet, pos));
            }
        }
    }
    recalculate_rewritten(wb, &mut rewritten);
}

/// One recalculation of what the `rewritten` formulas changed, a sheet at a time (over the
/// rectangle around that sheet's rewritten cells), then forgets them.
fn recalculate_rewritten(wb: &mut Workbook, rewritten: &mut Vec<(SheetId, Pos)>) {
    rewritten.sort_by_key(|&(sheet, pos)| (sheet, pos.row, pos.col));
    for same_sheet in rewritten.chunk_by(|a, b| a.0 == b.0) {
        let sheet = same_sheet[0].0;
        let (mut first, mut last) = (same_sheet[0].1, same_sheet[0].1);
        for &(_, pos) in same_sheet {
            first = Pos::new(first.row.min(pos.row), first.col.min(pos.col));
            last = Pos::new(last.row.max(pos.row), last.col.max(pos.col));
        }
        wb.recalculate_rect(sheet, Rect { first, last });
    }
    rewritten.clear();
}

/// Whether the formula at `pos` produced an array here: it spilled, or its spill was refused,
/// blocked or past the sheet's edge (`#SPILL!`), or reading cells of its own spill range
/// (`#CIRC!`). Excel intersects each of them, so none of them spills or reads its spill range.
fn spills(wb: &Workbook, sheet: SheetId, pos: Pos) -> bool {
    wb.spill_wanted(sheet, pos).is_some_and(|r| !r.is_cell()) || wb.value(sheet, pos) == Value::Error(XlError::Spill)
}

/// The table and pivot-table parts of every worksheet kept, by sheet: (type, part).
fn related_parts(
    package: &mut Package,
    sheets: &[SheetEntry],
    ids: &[Option<SheetId>],
) -> Vec<(SheetId, Vec<(String, String)>)> {
    let mut related = Vec::new();
    for (entry, id) in sheets.iter().zip(ids) {
        let Some(sheet) = *id else { continue };
        let parts = package.related_parts(&entry.part, &["table", "pivotTable"]).unwrap_or_default();
        if !parts.is_empty() {
            related.push((sheet, parts));
        }
    }
    related
}

/// The parts of type `kind` among `parts`.
fn of_kind<'p>(parts: &'p [(String, String)], kind: &'p str) -> impl Iterator<Item = &'p str> + 'p {
    parts.iter().filter(move |(k, _)| k == kind).map(|(_, part)| part.as_str())
}

/// The tables of every worksheet kept (a table part that cannot be read is left out with a
/// note: its structured references then show #NAME?).
fn read_tables(
    package: &mut Package,
    related: &[(SheetId, Vec<(String, String)>)],
    notes: &mut Vec<String>,
) -> Vec<Table> {
    let mut tables = Vec::new();
    const LEFT_OUT: &str = "the table was left out (its structured references show #NAME?)";
    for (sheet, parts) in related {
        for part in of_kind(parts, "table") {
            match read_or_why(package, part).map(|xml| tables::parse_table(&xml?, *sheet)) {
                Ok(Some(table)) => tables.push(table),
                Ok(None) => notes.push(format!("{part}: the table could not be read and was left out")),
                Err(why) => notes.push(format!("{why}; {LEFT_OUT}")),
            }
        }
    }
    tables
}

/// The pivot tables of every worksheet kept, with their caches, for GETPIVOTDATA (one whose
/// parts cannot be read is left out with a note: GETPIVOTDATA on it is then `#REF!`).
fn read_pivots(
    package: &mut Package,
    related: &[(SheetId, Vec<(String, String)>)],
    date_1904: bool,
    notes: &mut Vec<String>,
) -> Vec<pivot::Pivot> {
    let mut pivots = Vec::new();
    for (sheet, parts) in related {
        for part in of_kind(parts, "pivotTable") {
            match read_pivot(package, part, *sheet, date_1904) {
                Ok(Some(p)) => pivots.push(p),
                Ok(None) => {
                    notes.push(format!("{part}: the pivot table could not be read; GETPIVOTDATA on it is #REF!"))
                }
                Err(why) => notes.push(format!("{why}; the pivot table was left out (GETPIVOTDATA on it is #REF!)")),
            }
        }
    }
    pivots
}

/// One pivot table part with its cache's definition and records (records may be missing:
/// a cache saved without them summarises nothing; records that cannot be read are an
/// error, or the pivot table would summarise nothing silently). `Ok(None)` when its parts
/// do not make a pivot table; `Err` names a part that cannot be read and why.
fn read_pivot(
    package: &mut Package,
    part: &str,
    sheet: SheetId,
    date_1904: bool,
) -> Result<Option<pivot::Pivot>, String> {
    let mut first = |part: &str, kind: &str| {
        package.related_parts(part, &[kind]).ok().and_then(|parts| parts.into_iter().next()).map(|(_, p)| p)
    };
    let Some(definition_part) = first(part, "pivotCacheDefinition") else { return Ok(None) };
    let records_part = first(&definition_part, "pivotCacheRecords");
    let (Some(table), Some(definition)) = (read_or_why(package, part)?, read_or_why(package, &definition_part)?) else {
        return Ok(None);
    };
    let records = match records_part {
        Some(records) => read_or_why(package, &records)?.unwrap_or_default(),
        None => Vec::new(),
    };
    Ok(pivot::parse_pivot(&pivot::PivotParts {
        sheet,
        table: &table,
        definition: &definition,
        records: &records,
        date_1904,
    }))
}

/// The workbooks the file links to, numbered as its formulas number them (a part that
/// cannot be read is `None` with a note: references into it show #NAME?).
fn read_links(package: &mut Package, notes: &mut Vec<String>) -> Vec<Option<ExternalBook>> {
    let links: Vec<Option<ExternalBook>> = package
        .external_links
        .clone()
        .iter()
        .map(|part| {
            let part = part.as_deref()?;
            match read_or_why(package, part) {
                Ok(xml) => external::parse_link(&xml?),
                Err(why) => {
                    notes.push(format!("{why}; references into this linked workbook show #NAME?"));
                    None
                }
            }
        })
        .collect();
    if links.iter().any(Option::is_some) {
        notes.push("references to other workbooks read the values Excel cached for them (not refreshed)".into());
    }
    links
}

/// The sheet's column widths, for CELL("width").
fn set_widths(wb: &mut Workbook, sheet: SheetId, scan: &SheetScan) {
    if let Some(w) = scan.default_width {
        wb.set_column_width(sheet, None, w);
    }
    for &(first, last, width) in &scan.widths {
        wb.set_column_width(sheet, Some((first, last)), sheet_xml::shown_width(width));
    }
}

/// Hides the rows the sheet hid: as filtered when a filter (the sheet's or a table's)
/// covers them, else as hidden by hand (SUBTOTAL 1–11 counts only the latter).
fn hide_rows(wb: &mut Workbook, package: &mut Package, entry: &SheetEntry, sheet: SheetId, scan: &SheetScan) {
    if scan.hidden_rows.is_empty() {
        return;
    }
    let mut filters: Vec<Rect> = package
        .table_parts(&entry.part)
        .unwrap_or_default()
        .iter()
        .filter_map(|part| package.read_optional(part).ok().flatten())
        .filter_map(|xml| tables::active_filter(&xml))
        .collect();
    filters.extend(scan.auto_filter.filter(|(_, filtering)| *filtering).map(|(area, _)| area));
    for &row in &scan.hidden_rows {
        let filtered = filters.iter().any(|f| f.first.row < row && row <= f.last.row);
        wb.set_row_hidden(sheet, row, Some(if filtered { RowHidden::Filtered } else { RowHidden::Manually }));
    }
}

/// Formula text as stored → as typed: references into linked workbooks become the values
/// Excel cached, the file's function spellings ours. Structured references to tables
/// (`Parts[Qty]`) and 3-D references (`Sheet1:Sheet3!A1`) stay as written: the formula
/// language reads them.
fn typed_formula<'t>(text: &'t str, book: &BookParts) -> Cow<'t, str> {
    match sheet_span::ref_errors_without_sheet(text) {
        Cow::Borrowed(text) => external::resolve_links(text, &book.links),
        Cow::Owned(text) => Cow::Owned(external::resolve_links(&text, &book.links).into_owned()),
    }
}

/// What formulas of the file may name besides cells: tables and linked workbooks.
struct BookParts {
    tables: Vec<Table>,
    links: Vec<Option<ExternalBook>>,
    /// Defined names (lowercase) that name ranges: formulas using them are candidates for
    /// implicit intersection like those with a range in their text.
    range_names: HashSet<String>,
}

/// One worksheet on its way in.
struct SheetImport<'a> {
    sheet: SheetId,
    /// The sheet's part (`xl/worksheets/sheet1.xml`), which a note about its cells names.
    part: &'a str,
    book: &'a BookParts,
    /// Plain (not array) formulas with a range in them: candidates for implicit intersection.
    legacy_ranges: &'a mut Vec<(SheetId, Pos)>,
    /// Cells an array formula filled, with its anchor (anchors come first in the file).
    spilled: HashMap<Pos, Pos>,
    /// Shared formulas: index → (cell holding the text, text).
    shared: HashMap<u32, (Pos, String)>,
    /// Copies of a shared formula that came before the cell holding its text.
    waiting: Vec<(Pos, u32, Option<Value>)>,
    /// Each shared formula's tree at the cell holding its text, parsed for its first copy:
    /// its references are offsets, so a copy reads `#REF!` where one falls off the sheet.
    shared_trees: HashMap<u32, Option<Rc<crate::formula::ast::Expr>>>,
    /// The formula as typed (`=` and the text), reused from cell to cell.
    typed: String,
    /// The first formula ncsheet cannot compute whose cell keeps the value the file cached
    /// (its place and text), and how many there are.
    kept: Option<String>,
    kept_count: usize,
}

impl<'a> SheetImport<'a> {
    fn new(
        sheet: SheetId,
        part: &'a str,
        legacy_ranges: &'a mut Vec<(SheetId, Pos)>,
        book: &'a BookParts,
    ) -> SheetImport<'a> {
        SheetImport {
            sheet,
            part,
            book,
            legacy_ranges,
            spilled: HashMap::new(),
            shared: HashMap::new(),
            waiting: Vec::new(),
            shared_trees: HashMap::new(),
            typed: String::new(),
            kept: None,
            kept_count: 0,
        }
    }

    /// Stores one cell; refuses it past the workbook's cell limit (`workbook::MAX_CELLS`),
    /// which stops the read naming the part and the cell.
    fn cell(&mut self, imported: &mut Imported, strings: &[Rc<str>], cell: CellXml) -> Result<(), ScanError> {
        let CellXml { pos, value, formula } = cell;
        let full = |e: WorkbookError| (ErrorKind::TooLarge, e.to_string());
        imported.workbook.room_after(self.sheet, pos, self.waiting.len()).map_err(full)?;
        let value = value.map(|v| v.into_value(strings));
        if let Some(Value::Text(text)) = &value {
            let units = if text.len() > MAX_TEXT { text.encode_utf16().count() } else { 0 };
            if units > MAX_TEXT {
                let cell = imported.workbook.cell_name(self.sheet, pos);
                return Err((ErrorKind::TooLarge, format!("cell {cell}: {}", too_long_text(Some(units)))));
            }
        }
        match formula {
            None => self.constant(imported, pos, value),
            Some(FormulaXml::Plain(text)) => self.formula(imported, pos, text, value, true),
            Some(FormulaXml::Array(text, array)) => {
                self.note_spill(array);
                self.formula(imported, pos, text, value, false);
                if !array.dynamic {
                    imported.workbook.set_array_area_deferred(self.sheet, array.area);
                }
            }
            Some(FormulaXml::SharedText { index, text }) => match self.shared.get(&index).cloned() {
                // The first text of an index is its master (ECMA-376 Part 1, §18.3.1.40: "the
                // first formula in a group of shared formulas is saved in the f element");
                // a later cell of the group holding a text of its own is a copy of that
                // master, as LibreOffice reads it, and the master stays for the cells after.
                Some((holder, master)) => {
                    self.note_second_text(imported, index, (holder, &master), pos, text);
                    self.shared_copy(imported, index, (holder, &master), pos, value);
                }
                None => {
                    self.shared.insert(index, (pos, text.to_string()));
                    self.formula(imported, pos, text, value, true);
                }
            },
            Some(FormulaXml::SharedCopy { index }) => match self.shared.get(&index).cloned() {
                // Relative to the cell that holds the text, which need not be the top left
                // of the shared range.
                Some((holder, text)) => self.shared_copy(imported, index, (holder, &text), pos, value),
                None => self.waiting.push((pos, index, value)),
            },
        }
        Ok(())
    }

    /// Copies of shared formulas whose text came later in the file; the note on the formulas
    /// whose cells keep their cached values.
    fn finish(&mut self, imported: &mut Imported) {
        for (pos, index, value) in std::mem::take(&mut self.waiting) {
            match self.shared.get(&index).cloned() {
                Some((holder, text)) => self.shared_copy(imported, index, (holder, &text), pos, value),
                None => {
                    imported.notes.push(format!(
                        "{}: cell {}: no cell holds the text of the shared formula si=\"{index}\" it belongs to; \
                         its value is kept as a constant",
                        self.part,
                        imported.workbook.cell_name(self.sheet, pos)
                    ));
                    self.constant(imported, pos, value);
                }
            }
        }
        if let Some(first) = self.kept.take() {
            imported.notes.push(format!(
                "{} formula(s) ncsheet cannot compute (the first: {first}) keep the values the file \
                 cached, as Excel shows them (it drops a formula it cannot read when it repairs the file, and \
                 keeps an add-in's last result without the add-in); each is a problem of its cell",
                self.kept_count
            ));
        }
    }

    /// The note on a cell of shared formula `index` that holds a text of its own after the
    /// master at `holder`, when that text is not the master's moved there: the cell computes
    /// the master's, and says so rather than dropping its text unseen.
    fn note_second_text(
        &self,
        imported: &mut Imported,
        index: u32,
        (holder, master): (Pos, &str),
        pos: Pos,
        own: &str,
    ) {
        if shared_text(master, holder, pos) == own {
            return;
        }
        imported.notes.push(format!(
            "{}: cell {}: holds a text of its own for the shared formula si=\"{index}\" whose master is {}; \
             it is read as a copy of the master (the first text of a shared formula, ECMA-376 §18.3.1.40)",
            self.part,
            imported.workbook.cell_name(self.sheet, pos),
            imported.workbook.cell_name(self.sheet, holder),
        ));
    }

    /// A copy at `pos` of shared formula `index`, whose text is held at `holder`: the text
    /// moved there, or, where a relative reference of it would fall off the sheet (A1048576
    /// one row down), the holder's tree, which reads `#REF!` there as Excel's copy does (the
    /// text expansion kept such a reference at the edge: the copy read the wrong cell).
    fn shared_copy(
        &mut self,
        imported: &mut Imported,
        index: u32,
        (holder, text): (Pos, &str),
        pos: Pos,
        value: Option<Value>,
    ) {
        let sheet = self.sheet;
        let book = self.book;
        let tree = self
            .shared_trees
            .entry(index)
            .or_insert_with(|| {
                let typed = typed_formula(text, book);
                imported.workbook.parse_at(&typed, sheet, holder).ok().map(Rc::new)
            })
            .clone();
        if let Some(tree) = tree.filter(|t| falls_off_the_sheet(t, sheet, holder, pos)) {
            imported.workbook.set_formula_tree_deferred(sheet, pos, (*tree).clone());
            if let Some(value) = value {
                imported.cached.push(CachedValue { sheet, pos, value, anchor: pos });
            }
            return;
        }
        let moved = shared_text(text, holder, pos);
        self.formula(imported, pos, &moved, value, true);
    }

    fn note_spill(&mut self, array: ArrayFormula) {
        let ArrayFormula { anchor, area, .. } = array;
        // An area is bounded by the sheet; the cap only keeps a hostile file from asking
        // for billions of entries (the cells beyond it then read as constants).
        if area.rows() as u64 * area.cols() as u64 > 1 << 22 {
            return;
        }
        for row in area.first.row..=area.last.row {
            for col in area.first.col..=area.last.col {
                let p = Pos::new(row, col);
                if p != anchor {
                    self.spilled.insert(p, anchor);
                }
            }
        }
    }

    /// Stores a formula with its cached result. One that does not parse is kept as typed,
    /// shows #NAME? and is listed by `Workbook::problems`.
    fn formula(&mut self, imported: &mut Imported, pos: Pos, text: &str, cached: Option<Value>, plain: bool) {
        let (sheet, wb) = (self.sheet, &mut imported.workbook);
        self.typed.clear();
        self.typed.push('=');
        let typed = typed_formula(text, self.book);
        let rewritten = matches!(typed, Cow::Owned(_));
        self.typed.push_str(&typed);
        if reads_links(text, self.book) {
            let original = LinkedFormula { original: text.to_string(), ..Default::default() };
            imported.layout.links.cells.insert((sheet, pos), original);
        }
        // One look at the calls for the two checks below, which most formulas need not make.
        let calls_special = syntax::calls_any(text, &["ANCHORARRAY", "SINGLE", "OFFSET", "INDIRECT"]);
        // An add-in's function (`_xll.Name(…)`) would parse, as a call of a function nobody has.
        let add_in = calls_xll_add_in(text);
        let tree = if (calls_special || rewritten) && !add_in {
            syntax::tree_from_file(&self.typed[1..], wb, sheet, pos)
        } else {
            None
        };
        let unread = match tree {
            Some(tree) => {
                wb.set_formula_tree_deferred(sheet, pos, tree);
                None
            }
            None if add_in && cached.is_some() => Some(add_in_call(text)),
            None if cached.is_some() && text.contains('[') && missing_table(wb, &self.typed, sheet, pos).is_some() => {
                missing_table(wb, &self.typed, sheet, pos)
            }
            None => match wb.set_input_deferred(sheet, pos, &self.typed) {
                Err(WorkbookError::Parse { error, .. }) => Some(linked_add_in_call(text).unwrap_or(error)),
                _ => None,
            },
        };
        if let (Some(why), Some(value)) = (unread, &cached) {
            let why = ParseError { offset: why.offset.min(self.typed.len()), ..why };
            wb.keep_formula_value_deferred(sheet, pos, &self.typed, why, value.clone());
            if self.kept.is_none() {
                self.kept = Some(format!("{} {}", wb.cell_name(sheet, pos), notes::quoted(&self.typed)));
            }
            self.kept_count += 1;
        }
        let references_made = calls_special && makes_references(text);
        // A structured reference (`Parts[Qty]`) names a range as `B2:B9` does.
        let ranges = self.typed.contains(':') || self.typed.contains('[');
        if plain && (ranges || references_made || self.uses_range_name()) {
            self.legacy_ranges.push((sheet, pos));
        }
        match cached {
            Some(value) => imported.cached.push(CachedValue { sheet, pos, value, anchor: pos }),
            None => imported.uncached.push((sheet, pos)),
        }
    }

    /// A constant, or a value an array formula filled (kept as cached only).
    fn constant(&mut self, imported: &mut Imported, pos: Pos, value: Option<Value>) {
        let sheet = self.sheet;
        match (self.spilled.get(&pos), value) {
            (Some(&anchor), Some(value)) => imported.cached.push(CachedValue { sheet, pos, value, anchor }),
            (None, Some(value)) => imported.workbook.set_value_deferred(sheet, pos, value),
            (_, None) => {}
        }
    }
}

impl SheetImport<'_> {
    /// Whether the formula being stored names a defined name that names a range.
    fn uses_range_name(&self) -> bool {
        if self.book.range_names.is_empty() {
            return false;
        }
        let bytes = self.typed.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            let b = bytes[i];
            if b == b'"' {
                i = sheet_span::skip_delimited(bytes, i);
                continue;
            }
            if b.is_ascii_alphabetic() || b == b'_' || b == b'\\' || b >= 0x80 {
                let len = bytes[i..]
                    .iter()
                    .take_while(|&&c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'.' | b'\\') || c >= 0x80)
                    .count();
                if self.book.range_names.contains(&self.typed[i..i + len].to_lowercase()) {
                    return true;
                }
                i += len;
                continue;
            }
            i += 1;
        }
        false
    }
}

/// Why a formula naming a table the file lacks (`SUM(Table1[Qty])`) is not computed, as Excel
/// repairing such a file drops it; `None` when it names none.
fn missing_table(wb: &Workbook, typed: &str, sheet: SheetId, pos: Pos) -> Option<ParseError> {
    let tree = wb.parse_at(typed, sheet, pos).ok()?;
    let mut missing = None;
    tree.visit(&mut |e| {
        if let crate::formula::ast::ExprKind::Table(r) = &e.kind {
            if let Some(name) = r.table.as_deref().filter(|name| wb.table(name).is_none()) {
                missing.get_or_insert(ParseError {
                    offset: e.span.start as usize,
                    message: format!("table {name} is not in the file"),
                });
            }
        }
    });
    missing
}

/// Whether the formula calls a function of an XLL add-in (`_xll.DSSData(…)`), which only
/// the machine that saved the file has. Most formulas hold no `_`: one byte search decides.
fn calls_xll_add_in(text: &str) -> bool {
    memchr::memchr(b'_', text.as_bytes()).is_some() && text.contains("_xll.")
}

/// Why a formula calling an XLL add-in's function is not computed.
fn add_in_call(text: &str) -> ParseError {
    let at = text.find("_xll.").unwrap_or(0);
    let name: String = text[at + 5..].chars().take_while(|&c| c.is_alphanumeric() || matches!(c, '_' | '.')).collect();
    ParseError { offset: at + 1, message: format!("{name} is a function of an add-in (XLL) ncsheet does not have") }
}

/// Why a formula calling a function of a linked workbook (`[1]!LUCANET(…)`, an .xla add-in
/// or a macro workbook) is not computed; `None` when it calls none (a parse error then).
fn linked_add_in_call(text: &str) -> Option<ParseError> {
    let bytes = text.as_bytes();
    memchr::memmem::find_iter(bytes, b"]!").find_map(|bang| {
        let open = text[..bang].rfind('[')?;
        let book = &text[open + 1..bang];
        let name_len =
            bytes[bang + 2..].iter().take_while(|&&b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.')).count();
        let name = &text[bang + 2..bang + 2 + name_len];
        (book.bytes().all(|b| b.is_ascii_digit()) && !name.is_empty() && bytes.get(bang + 2 + name_len) == Some(&b'('))
            .then(|| ParseError {
                offset: open + 1,
                message: format!("{name} is a function of linked workbook [{book}] (an add-in) ncsheet does not open"),
            })
    })
}

/// Defined names whose formula holds a range (lowercase).
fn range_names(wb: &Workbook) -> HashSet<String> {
    wb.names()
        .into_iter()
        .filter(|(_, formula, _)| formula.contains(':'))
        .map(|(name, ..)| name.to_lowercase())
        .collect()
}

/// Whether a formula may make a multi-cell reference at run time (a candidate for implicit
/// intersection like a formula with a range in its text).
fn makes_references(text: &str) -> bool {
    // Case aside, found at each `(` without an uppercase copy of every formula of the file.
    syntax::calls_any(text, &["OFFSET", "INDIRECT"])
}

/// The text of a shared formula in `pos`, moved from the cell that holds it.
/// Whether a reference of `tree`, on the sheet at `holder`, is off the sheet at `pos`.
fn falls_off_the_sheet(tree: &crate::formula::ast::Expr, sheet: SheetId, holder: Pos, pos: Pos) -> bool {
    let mut off = false;
    tree.visit(&mut |e| {
        if let crate::formula::ast::ExprKind::Ref(r) = &e.kind {
            off |= r.resolve(sheet, holder).is_some() && r.resolve(sheet, pos).is_none();
        }
    });
    off
}

fn shared_text(formula: &str, holder: Pos, pos: Pos) -> String {
    calamine::expand_shared_formula(formula, (holder.row, holder.col), (pos.row, pos.col))
        .unwrap_or_else(|_| formula.to_string())
}

fn define_names(
    imported: &mut Imported,
    package: &Package,
    sheets: &[SheetEntry],
    ids: &[Option<SheetId>],
    book: &BookParts,
) {
    let mut left_out = notes::Grouped::default();
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
            // The name stays in the package: an edit saved over the file (the package patched)
            // keeps it, and a workbook written anew says at its save that it drops it.
            imported.notes.push(format!(
                "the {}{place} ({}) is not used by ncsheet; saving the file's edits keeps it",
                what.trim(),
                n.formula
            ));
            continue;
        }
        let scope = match n.local_sheet {
            None => None,
            Some(i) => match ids.get(i).copied().flatten() {
                Some(id) => Some(id),
                None => {
                    left_out.push(format!("name {} belongs to a sheet that was left out", notes::quoted(&n.name)));
                    continue;
                }
            },
        };
        let wb = &mut imported.workbook;
        let formula = typed_formula(&n.formula, book);
        if reads_links(&n.formula, book) {
            let original =
                LinkedFormula { original: n.formula.trim_start_matches('=').to_string(), ..Default::default() };
            imported.layout.links.names.insert((n.name.to_ascii_lowercase(), scope), original);
        }
        let defined = match syntax::tree_from_file(&formula, wb, scope.unwrap_or(0), Pos::new(0, 0)) {
            Some(tree) => wb.define_name_tree_deferred(&n.name, tree, scope),
            None => wb.define_name_deferred(&n.name, &formula, scope),
        };
        if let Err(e) = defined {
            left_out.push(format!("name {} ({}) was left out: {e}", n.name, notes::quoted(&n.formula)));
        }
    }
    left_out.finish("defined names were left out", &mut imported.notes);
}

/// A style's format code, `None` for General.
fn style_format(s: &Style) -> Option<String> {
    let f = s.number_format.as_ref()?;
    (f.format_id != Some(0) && !f.format_code.eq_ignore_ascii_case("General")).then(|| f.format_code.clone())
}

/// A style's alignment, bold, italic, wrap, solid fill and font colour, size and underline as a
/// macro reads them (`HorizontalAlignment`, `Font.Bold`, `Interior.Color`, `Font.Color`); the
/// rest of it (fonts' names, borders, patterns) ncsheet does not keep. Black and 11 points
/// are what a cell without them answers, so they are not kept per cell.
fn cell_style(s: &Style) -> CellStyle {
    use calamine::{
        FillPattern, FontStyle, FontWeight, HorizontalAlignment as H, UnderlineStyle as U, VerticalAlignment as V,
    };
    use cell_style::*;
    let font = s.font.as_ref();
    let alignment = s.alignment.as_ref();
    let horizontal = alignment.and_then(|a| match a.horizontal {
        H::Left => Some(XL_LEFT),
        H::Center => Some(XL_CENTER),
        H::CenterContinuous => Some(XL_CENTER_ACROSS_SELECTION),
        H::Right => Some(XL_RIGHT),
        H::Justify => Some(XL_JUSTIFY),
        H::Distributed => Some(XL_DISTRIBUTED),
        H::Fill => Some(XL_FILL),
        _ => None,
    });
    let vertical = alignment.and_then(|a| match a.vertical {
        V::Top => Some(XL_TOP),
        V::Center => Some(XL_CENTER),
        V::Justify => Some(XL_JUSTIFY),
        V::Distributed => Some(XL_DISTRIBUTED),
        _ => None,
    });
    // A solid fill's colour is its foreground (ECMA-376 18.8.32 patternFill); as VBA's RGB
    // gives it, red in the low byte.
    let solid = s.fill.as_ref().filter(|f| f.pattern == FillPattern::Solid);
    let rgb = |c: &calamine::Color| u32::from(c.red) | u32::from(c.green) << 8 | u32::from(c.blue) << 16;
    CellStyle {
        horizontal,
        vertical,
        bold: font.is_some_and(|f| f.weight == FontWeight::Bold),
        italic: font.is_some_and(|f| f.style == FontStyle::Italic),
        wrap: alignment.is_some_and(|a| a.wrap_text),
        fill: solid.and_then(|f| f.foreground_color.as_ref()).map(rgb),
        // Black is the automatic colour's look; any other is the cell's own.
        font_color: font.and_then(|f| f.color.as_ref()).map(rgb).filter(|&c| c != 0),
        font_size: font
            .and_then(|f| f.size)
            .filter(|&size| size != 11.0)
            .map(|points| (points * 20.0).round().clamp(1.0, f64::from(u16::MAX)) as u16),
        underline: font.and_then(|f| match f.underline {
            U::None => None,
            U::Single => Some(XL_UNDERLINE_SINGLE),
            U::Double => Some(XL_UNDERLINE_DOUBLE),
            U::SingleAccounting => Some(XL_UNDERLINE_SINGLE_ACCOUNTING),
            U::DoubleAccounting => Some(XL_UNDERLINE_DOUBLE_ACCOUNTING),
            // A kind calamine may add later is still an underline.
            _ => Some(XL_UNDERLINE_SINGLE),
        }),
    }
}

/// A sheet's hyperlinks: a place in the workbook from its `location`, an address outside it
/// from its relationship's target.
fn hyperlinks(package: &mut Package, part: &str, scan: &SheetScan) -> Result<Vec<Hyperlink>, raw::Err> {
    if scan.hyperlinks.is_empty() {
        return Ok(Vec::new());
    }
    let targets = package.external_targets(part, "hyperlink")?;
    let address = |id: &Option<String>| id.as_ref().and_then(|id| targets.get(id)).cloned().unwrap_or_default();
    Ok(scan
        .hyperlinks
        .iter()
        .map(|link| Hyperlink {
            anchor: link.anchor,
            address: address(&link.relationship),
            sub_address: link.location.clone(),
            text: link.display.clone(),
            tip: link.tooltip.clone(),
        })
        .collect())
}

fn sheet_layout(scan: &SheetScan, looks: &[StyleLook]) -> SheetLayout {
    let mut layout = SheetLayout {
        code_name: scan.code_name.clone(),
        active_cell: scan.active_cell,
        selection: scan.selection.clone(),
        array_formulas: scan.arrays.iter().map(|a| (a.anchor, *a)).collect(),
        ..SheetLayout::default()
    };
    layout.look.column_widths = column_widths(&scan.widths);
    let styled = || scan.styled.iter().filter_map(|&(pos, style)| Some((pos, looks.get(style as usize)?)));
    layout.look.number_formats = styled().filter_map(|(pos, look)| Some((pos, look.format.as_ref()?))).collect();
    layout.look.cell_styles =
        styled().filter(|(_, look)| !look.style.is_plain()).map(|(pos, look)| (pos, &look.style)).collect();
    layout.look.row_heights = scan.row_heights.clone();
    layout.look.hidden_rows = scan.hidden_rows.clone();
    layout.look.hidden_columns = hidden_columns(&scan.hidden_columns);
    layout
}

/// The width of each column the `<col>` elements size, a later element winning where two
/// overlap. Each column is set once however often the file repeats it: 1,000,000 elements
/// `<col min="1" max="1024">` (a 3.8 MB file) asked for a billion entries and aborted.
fn column_widths(cols: &[(u32, u32, f64)]) -> Vec<(u16, f64)> {
    if cols.is_empty() {
        return Vec::new();
    }
    let mut unset: std::collections::BTreeSet<u32> = (0..MAX_COLS).collect();
    let mut widths = Vec::new();
    for &(first, last, width) in cols.iter().rev() {
        // `<col min="1" max="16384">` sets the width of the rest of the sheet; only ranges a
        // user sized are worth carrying.
        if last - first >= 1024 {
            continue;
        }
        let sized: Vec<u32> = unset.range(first..=last).copied().collect();
        for col in sized {
            unset.remove(&col);
            widths.push((col as u16, width));
        }
    }
    widths.sort_unstable_by_key(|&(col, _)| col);
    widths
}

/// Every hidden column, those of a range to the sheet's end included (a sheet hides its unused
/// columns so), once: the ranges are merged first, so 200,000 elements
/// `<col min="1" max="16384" hidden="1">` cost their number, not 3 billion columns.
fn hidden_columns(ranges: &[(u32, u32)]) -> Vec<u16> {
    let mut ranges = ranges.to_vec();
    ranges.sort_unstable();
    let mut hidden: Vec<u16> = Vec::new();
    for (first, last) in ranges {
        let from = hidden.last().map_or(first, |&seen| first.max(u32::from(seen) + 1));
        hidden.extend((from..=last).map(|c| c as u16));
    }
    hidden
}

/// The package as calamine is given it: as read, or, when the workbook lists a sheet whose
/// relationship names no part (which calamine refuses), with that sheet left out of the
/// workbook part, and with the package's and the workbook's relationships written with
/// absolute targets when calamine would not find their parts as they are spelled. The sheet
/// is left out of the workbook as well, with a note (its kind says it has no part).
fn calamine_view<'b>(package: &mut Package, bytes: &'b [u8], file: &Path) -> Result<Cow<'b, [u8]>, XlsxError> {
    let fail = |(part, kind, message): (Option<String>, ErrorKind, String)| {
        XlsxError::new(file, part.as_deref(), kind, message)
    };
    let workbook = package.workbook_parts.first().cloned().unwrap_or_default();
    let replaced = [
        package.workbook_without_partless_sheets().map_err(fail)?,
        package.relationships_for_calamine("").map_err(fail)?,
        package.relationships_for_calamine(&workbook).map_err(fail)?,
    ];
    let mut view = Cow::Borrowed(bytes);
    for (part, text) in replaced.into_iter().flatten() {
        let source = crate::io::Source { file: file.to_path_buf(), bytes: view.into_owned().into() };
        view = Cow::Owned(super::replace_part(&source, &part, text.as_bytes())?);
    }
    Ok(view)
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
