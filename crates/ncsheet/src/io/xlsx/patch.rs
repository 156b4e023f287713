//! Saving an edited workbook over the package it was read from, surgically: the new package
//! is the original with only what changed rewritten. In the worksheet parts of edited
//! sheets, only the `<c>` elements of changed cells are replaced (edited cells: formula and
//! cached value; cells whose value changed through recalculation: their cached value);
//! every other byte of those parts, and every other part (charts, drawings, comments,
//! styles, validation, conditional formats, merged cells, VBA, custom XML, printer
//! settings, defined names), is copied as it was. `xl/calcChain.xml` (Excel's record of
//! the calculation order, stale once cells change) is dropped with its relationship and
//! content type, and `<calcPr fullCalcOnLoad="1">` asks Excel and LibreOffice to recompute
//! everything on load.
//!
//! What cannot be kept this way is returned as [`Patched::losses`], for the user to hear
//! before anything is written; a change the patch cannot express at all (a new sheet) is
//! [`Unpatchable`], and the caller writes a whole new package instead.

use std::collections::{BTreeMap, HashSet};
use std::io::{Cursor, Read, Write};
use std::path::Path;

use crate::eval::{Env, Value, XlError};
use crate::formula::address::{parse_cell, parse_rect, Pos, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::{Changes, Workbook};

use super::patch_styles::{column_changes, with_height, with_hidden, with_widths, Restyle, StyleSheet};
use super::patch_tables::{changed_table_parts, with_table_ranges, TableParts};
use super::raw::{zip_error, Package};
use super::syntax;
use super::{ErrorKind, Layout, XlsxError};
use crate::io::Source;

/// The saved package and what it could not keep.
pub struct Patched {
    pub bytes: Vec<u8>,
    pub losses: Vec<String>,
}

/// Why the workbook cannot be saved by patching its source; the caller writes a new package.
pub struct Unpatchable(pub String);

/// The changed cells of one sheet by (row, column).
type CellChanges = BTreeMap<(u32, u32), Change>;

/// What a changed cell becomes.
#[derive(Clone, Copy, PartialEq)]
enum Change {
    /// Its input was set: a new formula or constant.
    Input,
    /// Only its value changed (a dependent of an edited cell): a new cached value.
    Value,
    /// Only its look changed (a macro formatted it): a new style.
    Style,
}

/// Patches `source` (the file the workbook was read from) with the workbook's changes, and
/// with the looks `layout` holds where a macro changed them (`SheetLayout::file_look`).
pub fn patch(
    source: &Source,
    wb: &Workbook,
    changes: &Changes,
    layout: Option<&Layout>,
) -> Result<Result<Patched, Unpatchable>, XlsxError> {
    let fail = |part: Option<&str>, kind, message: String| XlsxError::new(&source.file, part, kind, message);
    if changes.sheets {
        return Ok(Err(Unpatchable("sheets were added, renamed or moved".into())));
    }
    if changes.shifted {
        // The original's rows, columns and cells keep their styles, widths, heights and
        // hidden flags by position: patched in place they would stay where the cells left.
        return Ok(Err(Unpatchable("rows, columns or cells were inserted or deleted".into())));
    }
    let bytes = &source.bytes[..];
    let package = Package::open(bytes).map_err(|(part, kind, m)| fail(part.as_deref(), kind, m))?;
    let mut losses = Vec::new();
    if changes.names {
        losses.push("defined names changed by this run are not saved; the file keeps its names".to_string());
    }
    let mut by_part: BTreeMap<String, (SheetId, CellChanges)> = BTreeMap::new();
    let names = wb.sheet_names();
    let tagged =
        changes.values.iter().map(|&c| (c, Change::Value)).chain(changes.inputs.iter().map(|&c| (c, Change::Input)));
    for ((sheet, pos), change) in tagged {
        let name = &names[sheet as usize];
        let Some(entry) = package.sheets.iter().find(|s| s.name.eq_ignore_ascii_case(name)) else {
            return Ok(Err(Unpatchable(format!("sheet '{name}' is not in the original package"))));
        };
        let cells = &mut by_part.entry(entry.part.clone()).or_insert_with(|| (sheet, BTreeMap::new())).1;
        cells.insert((pos.row, pos.col), change);
    }
    let mut restyles: BTreeMap<String, Restyle> = BTreeMap::new();
    for entry in &package.sheets {
        let (Some(sheet), Some(layout)) = (wb.sheet_id(&entry.name), layout.and_then(|l| l.sheets.get(&entry.name)))
        else {
            continue;
        };
        if layout.file_look.as_ref().is_some_and(|was| was.hyperlinks != layout.look.hyperlinks) {
            // A new link outside the package needs its relationship, which the patch does
            // not write; a package written anew has them all.
            let why = format!("the hyperlinks of sheet '{}' changed", entry.name);
            return Ok(Err(Unpatchable(why)));
        }
        let Some(restyle) = layout.file_look.as_ref().map(|was| Restyle::between(was, &layout.look)) else { continue };
        if !restyle.is_empty() {
            let cells = &mut by_part.entry(entry.part.clone()).or_insert_with(|| (sheet, BTreeMap::new())).1;
            for &key in restyle.cells.keys() {
                cells.entry(key).or_insert(Change::Style);
            }
            restyles.insert(entry.part.clone(), restyle);
        }
    }
    let workbook_part = package.workbook_parts.first().cloned().unwrap_or_else(|| "xl/workbook.xml".into());
    let states_changed =
        package.sheets.iter().any(|e| wb.sheet_id(&e.name).is_some_and(|id| wb.sheet_visibility(id) != e.visibility));
    let active_moved = moved_active_tab(&package, wb);
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| {
        let (p, k, m) = zip_error(None, e);
        fail(p.as_deref(), k, m)
    })?;
    let table_parts = match changes.tables {
        false => TableParts::new(),
        true => match changed_table_parts(&mut zip, wb).map_err(|m| fail(None, ErrorKind::Damaged, m))? {
            Ok(parts) => parts,
            Err(why) => return Ok(Err(why)),
        },
    };
    let changed = !by_part.is_empty() || states_changed || active_moved.is_some() || !table_parts.is_empty();
    let calc_chain = (0..zip.len()).find_map(|i| {
        let name = zip.name_for_index(i)?.ok()?;
        name.eq_ignore_ascii_case("xl/calcChain.xml").then(|| name.to_string())
    });
    let (wb_dir, wb_file) = workbook_part.rsplit_once('/').unwrap_or(("", &workbook_part));
    let wb_rels =
        if wb_dir.is_empty() { format!("_rels/{wb_file}.rels") } else { format!("{wb_dir}/_rels/{wb_file}.rels") };
    let styles_part = styles_part(&package, &zip, wb_dir);
    let mut styles = match restyles.is_empty() {
        true => None,
        false => {
            let Some(part) = &styles_part else {
                return Ok(Err(Unpatchable("the package has no styles part to add the macro's styles to".into())));
            };
            let mut entry = zip.by_name(part).map_err(|e| {
                let (p, k, m) = zip_error(Some(part), e);
                fail(p.as_deref(), k, m)
            })?;
            let xml = read_text(&mut entry, part, &source.file)?;
            match StyleSheet::read(xml) {
                Ok(sheet) => Some(sheet),
                Err(why) => return Ok(Err(Unpatchable(format!("{part} cannot take the macro's styles: {why}")))),
            }
        }
    };
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::with_capacity(bytes.len() + 4096)));
    let mut styles_options = None;
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| {
            let (p, k, m) = zip_error(None, e);
            fail(p.as_deref(), k, m)
        })?;
        let name = entry.name().map_err(|e| fail(None, ErrorKind::Damaged, e.to_string()))?.to_string();
        let zerr = |e: zip::result::ZipError| {
            let (p, k, m) = zip_error(Some(&name), e);
            fail(p.as_deref(), k, m)
        };
        let new_text = if !changed {
            None
        } else if Some(&name) == calc_chain.as_ref() {
            continue;
        } else if styles.is_some() && Some(&name) == styles_part.as_ref() {
            // Written last, once the sheets have added their styles.
            styles_options = Some(zip::write::SimpleFileOptions::default().compression_method(entry.compression()));
            continue;
        } else if let Some((sheet, cells)) = by_part.get(&name) {
            let xml = read_text(&mut entry, &name, &source.file)?;
            let looks = restyles.get(&name).zip(styles.as_mut());
            let patched = patch_sheet(&xml, (wb, *sheet), cells, looks, &mut losses)
                .map_err(|m| fail(Some(&name), ErrorKind::Unwritable, m))?;
            Some(with_selected_tab(patched, &name, &package, active_moved))
        } else if let Some(table) = table_parts.get(&name) {
            let xml = read_text(&mut entry, &name, &source.file)?;
            Some(with_table_ranges(&xml, table))
        } else if name == workbook_part {
            let xml = read_text(&mut entry, &name, &source.file)?;
            let xml = with_sheet_states(&full_calc_on_load(&xml), &package, wb);
            Some(match active_moved {
                Some((_, now)) => with_active_tab(&xml, now),
                None => xml,
            })
        } else if active_moved.is_some_and(|(was, now)| {
            [was, now, package.active_tab].iter().any(|&i| package.sheets.get(i).is_some_and(|e| e.part == name))
        }) {
            let xml = read_text(&mut entry, &name, &source.file)?;
            Some(with_selected_tab(xml, &name, &package, active_moved))
        } else if calc_chain.is_some() && (name == "[Content_Types].xml" || name == wb_rels) {
            let xml = read_text(&mut entry, &name, &source.file)?;
            Some(without_elements_naming(&xml, "calcChain"))
        } else {
            None
        };
        match new_text {
            None => out.raw_copy_file(entry).map_err(zerr)?,
            Some(text) => {
                let options = zip::write::SimpleFileOptions::default()
                    .compression_method(entry.compression())
                    .compression_level(Some(2))
                    .large_file(text.len() > u32::MAX as usize / 2);
                drop(entry);
                out.start_file(name.as_str(), options).map_err(zerr)?;
                out.write_all(text.as_bytes()).map_err(|e| zerr(e.into()))?;
            }
        }
    }
    if let Some(why) = styles.as_ref().and_then(StyleSheet::unpatchable) {
        return Ok(Err(Unpatchable(why.to_string())));
    }
    if let (Some(styles), Some(part), Some(options)) = (styles, &styles_part, styles_options) {
        let zerr = |e: zip::result::ZipError| {
            let (p, k, m) = zip_error(Some(part), e);
            fail(p.as_deref(), k, m)
        };
        out.start_file(part.clone(), options.compression_level(Some(2))).map_err(zerr)?;
        out.write_all(styles.finish().as_bytes()).map_err(|e| zerr(e.into()))?;
    }
    let bytes = out.finish().map_err(|e| fail(None, ErrorKind::Io, e.to_string()))?.into_inner();
    Ok(Ok(Patched { bytes, losses }))
}

/// The package's styles part: the one the workbook's relationships name, else the usual.
fn styles_part<R: Read + std::io::Seek>(package: &Package, zip: &zip::ZipArchive<R>, wb_dir: &str) -> Option<String> {
    let named = package.workbook_parts.iter().find(|p| p.to_ascii_lowercase().ends_with("/styles.xml"));
    let usual = format!("{wb_dir}/styles.xml");
    named.cloned().or_else(|| {
        (0..zip.len()).find_map(|i| {
            let name = zip.name_for_index(i)?.ok()?;
            name.eq_ignore_ascii_case(&usual).then(|| name.to_string())
        })
    })
}

fn read_text<R: Read>(entry: &mut R, name: &str, source: &Path) -> Result<String, XlsxError> {
    let mut text = String::new();
    entry
        .read_to_string(&mut text)
        .map_err(|e| XlsxError::new(source, Some(name), ErrorKind::Damaged, format!("cannot read: {e}")))?;
    Ok(text)
}

/// The workbook part with `fullCalcOnLoad="1"` on its `<calcPr>` (added if missing, in the
/// place the schema gives it: after `definedNames`, or what comes before it).
fn full_calc_on_load(xml: &str) -> String {
    let ns = root_prefix(xml);
    let calc_pr = format!("{ns}calcPr");
    if let Some(start) = find_tag(xml, &calc_pr, 0) {
        let end = start + xml[start..].find('>').unwrap_or(0);
        let tag = &xml[start..end];
        if tag.contains("fullCalcOnLoad=\"1\"") || tag.contains("fullCalcOnLoad=\"true\"") {
            return xml.to_string();
        }
        let tag = remove_attr(tag, "fullCalcOnLoad");
        let (body, close) = match tag.strip_suffix('/') {
            Some(b) => (b, "/"),
            None => (tag.as_str(), ""),
        };
        // The new attribute goes before any space the tag ends with, which stays as it was.
        let (attrs, space) = body.split_at(body.trim_end().len());
        return format!("{}{attrs} fullCalcOnLoad=\"1\"{space}{close}{}", &xml[..start], &xml[end..]);
    }
    for after in ["definedNames", "externalReferences", "functionGroups", "sheets"] {
        let after = format!("{ns}{after}");
        let close = format!("</{after}>");
        let at = xml.find(&close).map(|i| i + close.len()).or_else(|| {
            let start = find_tag(xml, &after, 0)?;
            let end = start + xml[start..].find('>')?;
            xml[..end].ends_with('/').then_some(end + 1)
        });
        if let Some(at) = at {
            return format!("{}<{calc_pr} fullCalcOnLoad=\"1\"/>{}", &xml[..at], &xml[at..]);
        }
    }
    xml.to_string()
}

/// The text without the empty elements (`<… />`) whose text names `what` (calcChain's
/// relationship and content-type override).
fn without_elements_naming(xml: &str, what: &str) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some(at) = rest.find(what) {
        let start = rest[..at].rfind('<').unwrap_or(0);
        let Some(end) = rest[at..].find("/>").map(|i| at + i + 2) else { break };
        if rest[start..end].contains('>') && rest[start..end].find('>') != Some(end - start - 1) {
            // Not one empty element: keep it.
            out.push_str(&rest[..at + what.len()]);
            rest = &rest[at + what.len()..];
            continue;
        }
        out.push_str(&rest[..start]);
        // With the line break or indentation that followed it, as a pretty-printed part has.
        rest = rest[end..].trim_start_matches([' ', '\t', '\r', '\n']);
    }
    out.push_str(rest);
    out
}

/// The package's tab positions of the sheet the file opened on and of the one the run left
/// active (a macro's `Activate`), when they differ. The file's active tab is read as the
/// reader took it: one that is no worksheet of the workbook (a chart sheet) opened the first.
fn moved_active_tab(package: &Package, wb: &Workbook) -> Option<(usize, usize)> {
    let tab_of = |id: SheetId| package.sheets.iter().position(|e| wb.sheet_id(&e.name) == Some(id));
    let was_id = package.sheets.get(package.active_tab).and_then(|e| wb.sheet_id(&e.name)).unwrap_or(0);
    let active = wb.active_sheet();
    // A hidden sheet cannot be the one a file opens on.
    if wb.sheet_visibility(active) != crate::workbook::Visibility::Visible {
        return None;
    }
    let (was, now) = (tab_of(was_id)?, tab_of(active)?);
    (was != now).then_some((was, now))
}

/// The workbook part with its first `<workbookView>` (the one Excel opens with) on tab
/// `tab`; a part without one gets a `<bookViews>` before `<sheets>`, where ECMA-376 puts it.
fn with_active_tab(xml: &str, tab: usize) -> String {
    let prefix = root_prefix(xml);
    if let Some(start) = find_tag(xml, &format!("{prefix}workbookView"), 0) {
        let end = xml[start..].find('>').map_or(xml.len(), |i| start + i);
        return format!(
            "{}{}{}",
            &xml[..start],
            with_attr(&xml[start..end], "activeTab", Some(&tab.to_string())),
            &xml[end..]
        );
    }
    let Some(sheets) = find_tag(xml, &format!("{prefix}sheets"), 0) else { return xml.to_string() };
    let views = format!(r#"<{prefix}bookViews><{prefix}workbookView activeTab="{tab}"/></{prefix}bookViews>"#);
    format!("{}{views}{}", &xml[..sheets], &xml[sheets..])
}

/// A worksheet part whose first `<sheetView>` is `tabSelected` when it is the newly active
/// sheet and is not when it was the old one: two selected tabs would open as a group, where
/// an edit changes every sheet of it. The old one is also the file's own active tab when that
/// is no worksheet (a chart sheet, read as opening on the first worksheet). A part without a
/// sheet view keeps Excel's default.
fn with_selected_tab(xml: String, part: &str, package: &Package, moved: Option<(usize, usize)>) -> String {
    let Some((was, now)) = moved else { return xml };
    let is_part = |i: usize| package.sheets.get(i).is_some_and(|e| e.part == part);
    let selected = match part {
        _ if is_part(now) => Some("1"),
        _ if is_part(was) || is_part(package.active_tab) => None,
        _ => return xml,
    };
    let Some(start) = find_tag(&xml, &format!("{}sheetView", root_prefix(&xml)), 0) else { return xml };
    let end = xml[start..].find('>').map_or(xml.len(), |i| start + i);
    format!("{}{}{}", &xml[..start], with_attr(&xml[start..end], "tabSelected", selected), &xml[end..])
}

/// A start tag (without its `>`) with attribute `name` set to `value`, or removed for `None`;
/// an empty element keeps its closing `/`.
pub(super) fn with_attr(tag: &str, name: &str, value: Option<&str>) -> String {
    let kept = remove_attr(tag, name);
    let (head, close) = kept.strip_suffix('/').map_or((kept.as_str(), ""), |h| (h, "/"));
    match value {
        Some(v) => format!(r#"{} {name}="{v}"{close}"#, head.trim_end()),
        None => format!("{}{close}", head.trim_end()),
    }
}

/// The start of the next `<name` tag (followed by a space, `>` or `/`) at or after `from`.
/// The workbook part with each `<sheet>`'s `state` as the workbook now has it (a macro's
/// `Visible`); the tags are the package's sheet entries, in order.
fn with_sheet_states(xml: &str, package: &Package, wb: &Workbook) -> String {
    use crate::workbook::Visibility;
    let tag_name = format!("{}sheet", root_prefix(xml));
    let mut out = String::with_capacity(xml.len() + 64);
    let mut at = 0;
    for entry in &package.sheets {
        let Some(start) = find_tag(xml, &tag_name, at) else { break };
        let Some(end) = xml[start..].find('>').map(|i| start + i) else { break };
        out.push_str(&xml[at..start]);
        let tag = &xml[start..end];
        let now = wb.sheet_id(&entry.name).map(|id| wb.sheet_visibility(id));
        match now.filter(|v| *v != entry.visibility) {
            None => out.push_str(tag),
            Some(v) => {
                let state = match v {
                    Visibility::Visible => None,
                    Visibility::Hidden => Some("hidden"),
                    Visibility::VeryHidden => Some("veryHidden"),
                };
                out.push_str(&with_attr(tag, "state", state));
            }
        }
        at = end;
    }
    out.push_str(&xml[at..]);
    out
}

pub(super) fn find_tag(xml: &str, name: &str, from: usize) -> Option<usize> {
    let pat = format!("<{name}");
    let mut at = from;
    while let Some(i) = xml[at..].find(&pat) {
        let start = at + i;
        match xml.as_bytes().get(start + pat.len()) {
            Some(b' ' | b'>' | b'/' | b'\t' | b'\r' | b'\n') => return Some(start),
            _ => at = start + pat.len(),
        }
    }
    None
}

/// The prefix (with its colon, or "") of the part's root element. Some generators write
/// `<x:worksheet xmlns:x="…main">` and every element of the part with that prefix; the
/// elements the patch looks for and writes take the same one.
pub(super) fn root_prefix(xml: &str) -> &str {
    let mut rest = xml;
    while let Some(at) = rest.find('<') {
        rest = &rest[at + 1..];
        if rest.starts_with(['?', '!']) {
            continue;
        }
        let end = rest.find(|c: char| c.is_whitespace() || c == '>' || c == '/').unwrap_or(rest.len());
        return rest[..end].rfind(':').map_or("", |i| &rest[..=i]);
    }
    ""
}

/// An attribute's value in a start tag (double or single quotes).
pub(super) fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let bytes = tag.as_bytes();
    let mut at = 0;
    while let Some(i) = tag[at..].find(name) {
        let start = at + i;
        at = start + name.len();
        let before_ok = start > 0 && bytes[start - 1].is_ascii_whitespace();
        let rest = tag[at..].trim_start();
        if !before_ok || !rest.starts_with('=') {
            continue;
        }
        let rest = rest[1..].trim_start();
        let quote = rest.chars().next()?;
        if quote != '"' && quote != '\'' {
            continue;
        }
        let end = rest[1..].find(quote)?;
        return Some(&rest[1..1 + end]);
    }
    None
}

/// The start tag without one attribute.
pub(super) fn remove_attr(tag: &str, name: &str) -> String {
    let Some(value) = attr(tag, name) else { return tag.to_string() };
    let pat_start = tag.find(&format!(" {name}")).or_else(|| tag.find(name)).unwrap_or(0);
    let value_at = tag[pat_start..].find(value).map(|i| pat_start + i).unwrap_or(pat_start);
    let end = (value_at + value.len() + 1).min(tag.len());
    format!("{}{}", &tag[..pat_start], &tag[end..])
}

/// Rewrites one worksheet part: the changed cells' `<c>` elements replaced or inserted in
/// row and column order, everything else copied. The part's elements may carry a namespace
/// prefix (`<x:c>`); new ones are written with the same.
fn patch_sheet(
    xml: &str,
    (wb, sheet): (&Workbook, SheetId),
    cells: &BTreeMap<(u32, u32), Change>,
    looks: Option<(&Restyle, &mut StyleSheet)>,
    losses: &mut Vec<String>,
) -> Result<String, String> {
    let ns = root_prefix(xml);
    let q = |name: &str| format!("{ns}{name}");
    let (sheet_data, row_tag, c_tag) = (q("sheetData"), q("row"), q("c"));
    let arrays = broken_arrays(xml, ns, cells)?;
    let (restyle, styles) = looks.unzip();
    let mut p = SheetPatch {
        heights: restyle.map(|r| r.heights.clone()).unwrap_or_default(),
        rows_hidden: restyle.map(|r| r.rows_hidden.clone()).unwrap_or_default(),
        restyle,
        styles,
        wb,
        sheet,
        ns,
        pending: cells.clone(),
        out: String::with_capacity(xml.len() + 256 * cells.len()),
        broken_shared: HashSet::new(),
        broken_arrays: arrays.iter().map(|(anchor, _, _)| (anchor.row, anchor.col)).collect(),
        losses,
    };
    for (anchor, area, edited) in &arrays {
        p.losses.push(format!(
            "{}: inside the array formula of {anchor} over {area}, which Excel changes only as a whole (\"You \
             can't change part of an array\"); the array formula is saved over {anchor} alone and the other cells \
             of {area} keep their last values as constants",
            wb.cell_name(sheet, *edited)
        ));
    }
    let start = find_tag(xml, &sheet_data, 0).ok_or_else(|| format!("no <{sheet_data}> element"))?;
    let open_end = start + xml[start..].find('>').ok_or("unterminated <sheetData>")?;
    let head = with_dimension(&xml[..start], ns, cells.keys());
    match p.restyle {
        Some(r) if !r.widths.is_empty() || !r.columns_hidden.is_empty() => {
            p.out.push_str(&with_widths(&head, ns, &column_changes(r)))
        }
        _ => p.out.push_str(&head),
    }
    if xml[..open_end].ends_with('/') {
        p.out.push_str(&format!("<{sheet_data}>"));
        p.flush_rows_before(u32::MAX);
        p.out.push_str(&format!("</{sheet_data}>"));
        p.out.push_str(&xml[open_end + 1..]);
        return Ok(p.out);
    }
    p.out.push_str(&xml[start..=open_end]);
    let mut i = open_end + 1;
    let (mut row, mut col): (u32, Option<u32>) = (0, None);
    let mut in_row = false;
    let (close_sheet_data, close_row, close_c) =
        (format!("</{sheet_data}"), format!("</{row_tag}"), format!("</{c_tag}>"));
    loop {
        let lt = i + xml[i..].find('<').ok_or("unterminated <sheetData>")?;
        p.out.push_str(&xml[i..lt]);
        i = lt;
        let rest = &xml[i..];
        if rest.starts_with(&close_sheet_data) {
            p.flush_rows_before(u32::MAX);
            p.out.push_str(rest);
            return Ok(p.out);
        }
        let tag_end = i + rest.find('>').ok_or("unterminated tag")?;
        let tag = &xml[i..=tag_end];
        if find_tag(tag, &row_tag, 0) == Some(0) {
            row = match attr(tag, "r") {
                Some(r) => r.parse::<u32>().map_err(|_| format!("row number '{r}'"))?.saturating_sub(1),
                None if in_row || col.is_some() || row > 0 => row + 1,
                None => 0,
            };
            col = None;
            p.flush_rows_before(row);
            let sized = p.heights.remove(&row).map(|h| with_height(tag, h));
            let tag = sized.as_deref().unwrap_or(tag);
            let shown = p.rows_hidden.remove(&row).map(|h| with_hidden(tag, h));
            let tag = shown.as_deref().unwrap_or(tag);
            if tag.ends_with("/>") && p.has_row(row) {
                p.out.push_str(tag[..tag.len() - 2].trim_end());
                p.out.push('>');
                p.flush_cells(row, u32::MAX);
                p.out.push_str(&format!("</{row_tag}>"));
            } else {
                p.out.push_str(tag);
                in_row = !tag.ends_with("/>");
            }
            i = tag_end + 1;
        } else if rest.starts_with(&close_row) {
            p.flush_cells(row, u32::MAX);
            p.out.push_str(tag);
            in_row = false;
            i = tag_end + 1;
        } else if find_tag(tag, &c_tag, 0) == Some(0) {
            let end = if tag.ends_with("/>") {
                tag_end + 1
            } else {
                tag_end + xml[tag_end..].find(&close_c).ok_or("unterminated <c>")? + close_c.len()
            };
            let element = &xml[i..end];
            let pos = match attr(tag, "r") {
                Some(r) => parse_cell(r).ok_or_else(|| format!("cell reference '{r}'"))?,
                None => Pos::new(row, col.map_or(0, |c| c + 1)),
            };
            col = Some(pos.col);
            p.flush_cells(pos.row, pos.col);
            match p.pending.remove(&(pos.row, pos.col)) {
                Some(change) => p.replace(element, tag, pos, change),
                None => p.copy(element, pos),
            }
            i = end;
        } else {
            p.out.push_str(tag);
            i = tag_end + 1;
        }
    }
}

/// The legacy array formulas (`<f t="array" ref="A1:B3">` on a cell without the `cm` mark
/// of a dynamic array) that an edited cell other than their anchor falls inside: each
/// anchor, area and the first such edited cell. Excel refuses such an edit; the file can
/// keep it only by making the array formula a single-cell one.
fn broken_arrays(xml: &str, ns: &str, cells: &BTreeMap<(u32, u32), Change>) -> Result<Vec<(Pos, Rect, Pos)>, String> {
    let edited: Vec<Pos> =
        cells.iter().filter(|(_, &c)| c == Change::Input).map(|(&(r, c), _)| Pos::new(r, c)).collect();
    let mut out = Vec::new();
    if edited.is_empty() {
        return Ok(out);
    }
    let (f_tag, c_tag) = (format!("{ns}f"), format!("<{ns}c"));
    let mut from = 0;
    while let Some(start) = find_tag(xml, &f_tag, from) {
        let end = start + xml[start..].find('>').ok_or("unterminated <f>")?;
        from = end;
        let f = &xml[start..end];
        let Some(area) = attr(f, "ref").filter(|_| attr(f, "t") == Some("array")).and_then(parse_rect) else {
            continue;
        };
        let Some(c_start) = xml[..start].rfind(&c_tag) else { continue };
        let c = &xml[c_start..start];
        if attr(c, "cm").is_some() {
            continue; // a dynamic array: an edit inside it makes #SPILL!, as Excel allows
        }
        let Some(anchor) = attr(c, "r").and_then(parse_cell) else { continue };
        if let Some(&inside) = edited.iter().find(|&&p| p != anchor && area.contains(p)) {
            out.push((anchor, area, inside));
        }
    }
    Ok(out)
}

/// The part before `<sheetData>` with its `<dimension ref>` grown to hold the changed cells.
fn with_dimension<'a>(head: &str, ns: &str, cells: impl Iterator<Item = &'a (u32, u32)>) -> String {
    let Some(start) = find_tag(head, &format!("{ns}dimension"), 0) else { return head.to_string() };
    let Some(end) = head[start..].find('>').map(|i| start + i) else { return head.to_string() };
    let tag = &head[start..end];
    let Some(old) = attr(tag, "ref") else { return head.to_string() };
    let Some(mut rect) = parse_rect(old).or_else(|| parse_cell(old).map(|p| Rect::new(p, p))) else {
        return head.to_string();
    };
    for &(row, col) in cells {
        rect.first.row = rect.first.row.min(row);
        rect.first.col = rect.first.col.min(col);
        rect.last.row = rect.last.row.max(row);
        rect.last.col = rect.last.col.max(col);
    }
    let new = if rect.is_cell() { rect.first.to_string() } else { format!("{}:{}", rect.first, rect.last) };
    if new == old {
        return head.to_string();
    }
    format!("{}{}", &head[..start], tag.replacen(&format!("\"{old}\""), &format!("\"{new}\""), 1) + &head[end..])
}

struct SheetPatch<'a> {
    wb: &'a Workbook,
    sheet: SheetId,
    /// The part's namespace prefix with its colon, or "".
    ns: &'a str,
    pending: BTreeMap<(u32, u32), Change>,
    out: String,
    /// Shared-formula groups whose master cell was replaced: their other cells get their
    /// own formula text.
    broken_shared: HashSet<String>,
    /// Anchors of legacy array formulas an edit fell inside: saved as single-cell formulas.
    broken_arrays: HashSet<(u32, u32)>,
    losses: &'a mut Vec<String>,
    /// The looks a macro changed, and the styles part their new styles go to.
    restyle: Option<&'a Restyle>,
    styles: Option<&'a mut StyleSheet>,
    /// Rows whose height changed, not reached yet.
    heights: BTreeMap<u32, f64>,
    /// Rows hidden or shown again, not reached yet.
    rows_hidden: BTreeMap<u32, bool>,
}

impl SheetPatch<'_> {
    fn has_row(&self, row: u32) -> bool {
        self.pending.range((row, 0)..=(row, u32::MAX)).next().is_some()
    }

    /// New `<row>` elements for the pending cells and heights of rows before `row`.
    fn flush_rows_before(&mut self, row: u32) {
        loop {
            let next_cell = self.pending.first_key_value().map(|(&(r, _), _)| r);
            let next_height = self.heights.first_key_value().map(|(&r, _)| r);
            let next_hidden = self.rows_hidden.first_key_value().map(|(&r, _)| r);
            let next = next_cell.into_iter().chain(next_height).chain(next_hidden).min();
            let Some(r) = next.filter(|&r| r < row) else { break };
            let ns = self.ns;
            let height = self.heights.remove(&r);
            // A row the file did not have was not hidden: only hiding it needs a mark.
            let hidden = self.rows_hidden.remove(&r).filter(|&h| h);
            let tag = format!("<{ns}row r=\"{}\">", r + 1);
            let tag = height.map_or(tag.clone(), |h| with_height(&tag, h));
            let tag = hidden.map_or(tag.clone(), |h| with_hidden(&tag, h));
            // Row `r` is the first pending one (`r < row`, so `r + 1` fits): only its cells
            // are taken out, not the whole map copied per row.
            let later = self.pending.split_off(&(r + 1, 0));
            let this_row = std::mem::replace(&mut self.pending, later);
            let mut cells = String::new();
            for ((_, c), change) in this_row {
                cells.push_str(&self.new_cell(None, Pos::new(r, c), change));
            }
            if !cells.is_empty() || height.is_some() || hidden.is_some() {
                self.out.push_str(&format!("{tag}{cells}</{ns}row>"));
            }
        }
    }

    /// New `<c>` elements for the pending cells of `row` left of `col`.
    fn flush_cells(&mut self, row: u32, col: u32) {
        let keys: Vec<(u32, u32)> = self.pending.range((row, 0)..(row, col)).map(|(k, _)| *k).collect();
        for k in keys {
            let change = self.pending.remove(&k).expect("listed");
            let cell = self.new_cell(None, Pos::new(k.0, k.1), change);
            self.out.push_str(&cell);
        }
    }

    /// A cell that did not change, unless its shared formula lost its master or its array
    /// formula was broken by an edit inside it.
    fn copy(&mut self, element: &str, pos: Pos) {
        let Some((f, range)) = formula_element(element, self.ns) else { return self.out.push_str(element) };
        let shared_follower = (attr(f, "t") == Some("shared") && attr(f, "ref").is_none())
            .then(|| attr(f, "si"))
            .flatten()
            .is_some_and(|si| self.broken_shared.contains(si));
        if shared_follower || self.broken_arrays.contains(&(pos.row, pos.col)) {
            let f = self.own_formula(pos).unwrap_or_default();
            self.out.push_str(&element[..range.start]);
            self.out.push_str(&f);
            self.out.push_str(&element[range.end..]);
        } else {
            self.out.push_str(element);
        }
    }

    fn replace(&mut self, element: &str, tag: &str, pos: Pos, change: Change) {
        if change == Change::Style {
            let Some(s) = self.new_style(Some(tag), pos) else { return self.copy(element, pos) };
            let closing = if tag.ends_with("/>") { "/>" } else { ">" };
            let head = remove_attr(&tag[..tag.len() - closing.len()], "s");
            let start = self.out.len();
            self.copy(element, pos);
            self.out.replace_range(start..start + tag.len(), &format!("{}{s}{closing}", head.trim_end()));
            return;
        }
        if change == Change::Input {
            if let Some((f, _)) = formula_element(element, self.ns) {
                let area = attr(f, "ref").filter(|r| r.contains(':'));
                match (attr(f, "t"), area) {
                    (Some("shared"), _) => {
                        if let Some(si) = attr(f, "si") {
                            self.broken_shared.insert(si.to_string());
                        }
                    }
                    (Some("array"), Some(area)) => self.losses.push(format!(
                        "{}: the array formula over {area} is replaced by a single-cell formula; the other cells of \
                         {area} keep their last values as constants",
                        self.wb.cell_name(self.sheet, pos)
                    )),
                    _ => {}
                }
            }
        }
        let cell = self.new_cell(Some((element, tag)), pos, change);
        self.out.push_str(&cell);
    }

    /// The ` s="…"` of a cell a macro formatted (`None`: its look did not change): the
    /// file's style of the cell with the look the macro left.
    fn new_style(&mut self, tag: Option<&str>, pos: Pos) -> Option<String> {
        let (format, look, was) = self.restyle?.cells.get(&(pos.row, pos.col))?;
        let old = tag.and_then(|t| attr(t, "s")).and_then(|s| s.parse().ok()).unwrap_or(0);
        let id = self.styles.as_mut()?.style_for(old, format.as_deref(), *look, *was);
        Some(if id == 0 { String::new() } else { format!(" s=\"{id}\"") })
    }

    /// The `<f>` element of a cell's own formula; an array formula an edit fell inside is
    /// kept as an array formula over its own cell (see `break_fixed_array` in workbook).
    fn own_formula(&self, pos: Pos) -> Option<String> {
        let f = escape(&self.file_formula(pos)?);
        let ns = self.ns;
        Some(match self.broken_arrays.contains(&(pos.row, pos.col)) {
            true => format!("<{ns}f t=\"array\" ref=\"{pos}\">{f}</{ns}f>"),
            false => format!("<{ns}f>{f}</{ns}f>"),
        })
    }

    fn file_formula(&self, pos: Pos) -> Option<String> {
        syntax::cell_to_file_as_needed(self.wb, self.sheet, pos)
    }

    /// The `<c>` element of a changed cell, keeping the original's style (and, for a value
    /// change, its formula element as it was).
    fn new_cell(&mut self, original: Option<(&str, &str)>, pos: Pos, change: Change) -> String {
        let ns = self.ns;
        let style = self.new_style(original.map(|(_, tag)| tag), pos);
        let style = style.or_else(|| original.and_then(|(_, tag)| attr(tag, "s")).map(|s| format!(" s=\"{s}\"")));
        let style = style.unwrap_or_default();
        if change == Change::Style {
            // A formatted cell the file did not hold: empty, with its style.
            return format!("<{ns}c r=\"{pos}\"{style}/>");
        }
        let value = self.wb.value(self.sheet, pos);
        let formula = match change {
            Change::Input => self.own_formula(pos),
            Change::Value if self.broken_arrays.contains(&(pos.row, pos.col)) => self.own_formula(pos),
            Change::Value | Change::Style => {
                original.and_then(|(e, _)| formula_element(e, ns)).map(|(_, r)| original.unwrap().0[r].to_string())
            }
        };
        if change == Change::Input && formula.is_some() {
            if let Some(r) = Env::spill_rect(self.wb, self.sheet, pos).filter(|r| !r.is_cell()) {
                self.losses.push(format!(
                    "{}: the formula spills over {}:{}; it is saved as a single-cell formula with its first value \
                     (the spilled cells get their values)",
                    self.wb.cell_name(self.sheet, pos),
                    r.first,
                    r.last
                ));
            }
        }
        let keep_attrs = match (change, original) {
            // A value change keeps the cell's other attributes (cm: the dynamic-array mark),
            // but its value metadata (vm: the #CALC! or #SPILL! a stored #VALUE! stands for)
            // only while the value is such an error still: on a number it would misname it.
            (Change::Value, Some((_, tag))) => {
                let newer_error = matches!(value, Value::Error(XlError::Spill | XlError::Calc));
                other_attrs(tag, if newer_error { &[] } else { &["vm"] })
            }
            _ => String::new(),
        };
        let r = format!("<{ns}c r=\"{pos}\"{style}{keep_attrs}");
        let end = format!("</{ns}c>");
        let f = formula.unwrap_or_default();
        let is_formula = !f.is_empty();
        let v = |text: &str| format!("<{ns}v>{text}</{ns}v>");
        match value {
            // A cell never holds a LAMBDA (its formula shows #CALC!).
            Value::Blank | Value::Array(_) | Value::Lambda(_) | Value::Null if !is_formula => {
                if style.is_empty() {
                    String::new()
                } else {
                    format!("{r}/>")
                }
            }
            Value::Blank | Value::Array(_) | Value::Lambda(_) | Value::Null => {
                format!("{r} t=\"str\">{f}{}{end}", v(""))
            }
            Value::Number(n) if n.is_finite() => format!("{r}>{f}{}{end}", v(&number_text(n))),
            Value::Number(_) => format!("{r} t=\"e\">{f}{}{end}", v("#NUM!")),
            Value::Bool(b) => format!("{r} t=\"b\">{f}{}{end}", v(&u8::from(b).to_string())),
            Value::Error(e) => format!("{r} t=\"e\">{f}{}{end}", v(error_text(e))),
            Value::Text(t) if is_formula => format!("{r} t=\"str\">{f}{}{end}", v(&escape(&t))),
            Value::Text(t) => format!(
                "{r} t=\"inlineStr\"><{ns}is><{ns}t xml:space=\"preserve\">{}</{ns}t></{ns}is>{end}",
                escape(&t)
            ),
        }
    }
}

/// The start-tag attributes of a `<c>` other than `r`, `s`, `t` and `leave_out`, each with
/// its space.
fn other_attrs(tag: &str, leave_out: &[&str]) -> String {
    let inner = tag.trim_start_matches('<');
    let inner = inner.find(char::is_whitespace).map_or("", |i| &inner[i..]);
    let inner = inner.trim_end_matches('>').trim_end_matches('/');
    let mut out = String::new();
    let mut rest = inner;
    while let Some(eq) = rest.find('=') {
        let name = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let Some(quote) = after.chars().next() else { break };
        let Some(end) = after[1..].find(quote) else { break };
        let value = &after[1..1 + end];
        if !matches!(name, "r" | "s" | "t") && !leave_out.contains(&name) {
            out.push_str(&format!(" {name}={quote}{value}{quote}"));
        }
        rest = &after[end + 2..];
    }
    out
}

/// The `<f …>…</f>` (or `<f …/>`) element of a `<c>` element: its start tag and byte range.
fn formula_element<'e>(element: &'e str, ns: &str) -> Option<(&'e str, std::ops::Range<usize>)> {
    let name = format!("{ns}f");
    let start = find_tag(element, &name, 1)?;
    let tag_end = start + element[start..].find('>')?;
    let tag = &element[start..=tag_end];
    let close = format!("</{name}>");
    let end = if tag.ends_with("/>") { tag_end + 1 } else { tag_end + element[tag_end..].find(&close)? + close.len() };
    Some((tag, start..end))
}

/// An error as Excel stores it; errors newer than the file format are stored as Excel
/// stores them for older readers.
fn error_text(e: XlError) -> &'static str {
    match e {
        XlError::Spill | XlError::Calc | XlError::Circ => "#VALUE!",
        e => e.as_str(),
    }
}

/// A number as `<v>` holds it: the shortest text that reads back as the same double, with
/// an exponent only for very large or small magnitudes.
fn number_text(n: f64) -> String {
    if n == 0.0 || (1e-5..1e15).contains(&n.abs()) {
        format!("{n}")
    } else {
        format!("{n:e}")
    }
}

fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            // XML 1.0 cannot hold other control characters; Excel's own escape for them.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push_str(&format!("_x{:04X}_", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// The package `source` with the bytes of one existing part replaced by `data` and every
/// other part copied as it was (a new VBA project into an .xlsm).
pub fn replace_part(source: &Source, part: &str, data: &[u8]) -> Result<Vec<u8>, XlsxError> {
    let fail = |part: Option<&str>, kind, message: String| XlsxError::new(&source.file, part, kind, message);
    let bytes = &source.bytes[..];
    let zerr = |name: Option<&str>, e: zip::result::ZipError| {
        let (p, k, m) = zip_error(name, e);
        fail(p.as_deref(), k, m)
    };
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| zerr(None, e))?;
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::with_capacity(bytes.len() + data.len())));
    let mut found = false;
    for i in 0..zip.len() {
        let entry = zip.by_index(i).map_err(|e| zerr(None, e))?;
        let name = entry.name().map_err(|e| fail(None, ErrorKind::Damaged, e.to_string()))?.to_string();
        if name != part {
            out.raw_copy_file(entry).map_err(|e| zerr(Some(&name), e))?;
            continue;
        }
        found = true;
        // A stored part (as ncsheet writes vbaProject.bin) takes no compression level: the
        // zip writer refuses one ("Unsupported compression level").
        let method = entry.compression();
        let level = (method != zip::CompressionMethod::Stored).then_some(2);
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(method)
            .compression_level(level)
            .large_file(data.len() > u32::MAX as usize / 2);
        drop(entry);
        out.start_file(name.as_str(), options).map_err(|e| zerr(Some(&name), e))?;
        out.write_all(data).map_err(|e| zerr(Some(&name), e.into()))?;
    }
    if !found {
        return Err(fail(Some(part), ErrorKind::Damaged, "the package has no such part to replace".into()));
    }
    Ok(out.finish().map_err(|e| fail(None, ErrorKind::Io, e.to_string()))?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_are_read_with_either_quote() {
        assert_eq!(attr(r#"<c r="B3" s='4' t="str">"#, "s"), Some("4"));
        assert_eq!(attr(r#"<c r="B3" s='4' t="str">"#, "r"), Some("B3"));
        assert_eq!(attr(r#"<c r="B3" xs="4">"#, "s"), None);
        assert_eq!(other_attrs(r#"<c r="A1" s="2" t="e" cm="1">"#, &[]), r#" cm="1""#);
        assert_eq!(other_attrs(r#"<c r="A1" t="e" cm="1" vm="3">"#, &["vm"]), r#" cm="1""#);
    }

    #[test]
    fn calc_pr_is_set_or_added_in_its_place() {
        assert_eq!(
            full_calc_on_load(r#"<workbook><sheets/><calcPr calcId="1"/></workbook>"#),
            r#"<workbook><sheets/><calcPr calcId="1" fullCalcOnLoad="1"/></workbook>"#
        );
        assert_eq!(
            full_calc_on_load(r#"<workbook><sheets><sheet/></sheets><definedNames></definedNames><x/></workbook>"#),
            r#"<workbook><sheets><sheet/></sheets><definedNames></definedNames><calcPr fullCalcOnLoad="1"/><x/></workbook>"#
        );
    }

    /// ECMA-376 §18.2.30: `activeTab` on the first `workbookView`; §18.2.27: `bookViews`
    /// comes before `sheets` in `CT_Workbook`.
    #[test]
    fn the_active_tab_is_set_or_its_book_views_added_before_the_sheets() {
        assert_eq!(
            with_active_tab(
                r#"<workbook><bookViews><workbookView activeTab="2" xWindow="5"/></bookViews></workbook>"#,
                1
            ),
            r#"<workbook><bookViews><workbookView xWindow="5" activeTab="1"/></bookViews></workbook>"#
        );
        assert_eq!(
            with_active_tab(r#"<x:workbook xmlns:x="m"><x:sheets><x:sheet/></x:sheets></x:workbook>"#, 3),
            r#"<x:workbook xmlns:x="m"><x:bookViews><x:workbookView activeTab="3"/></x:bookViews><x:sheets><x:sheet/></x:sheets></x:workbook>"#
        );
    }

    #[test]
    fn calc_chain_entries_are_removed() {
        let xml = r#"<Types><Default Extension="xml"/><Override PartName="/xl/calcChain.xml" ContentType="x"/><Override PartName="/xl/a.xml"/></Types>"#;
        assert_eq!(
            without_elements_naming(xml, "calcChain"),
            r#"<Types><Default Extension="xml"/><Override PartName="/xl/a.xml"/></Types>"#
        );
    }
}
