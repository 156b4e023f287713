//! The table parts (`xl/tables/tableN.xml`) of a package saved by patching ([`super::patch`]):
//! a table a macro grew or shrank without moving cells (`ListRows.Add` taking the empty row
//! below it, `ListObject.Resize`) gets its new `ref`, its `<autoFilter>`'s and its
//! `<sortState>`'s, every other byte of the part kept. A change the part cannot take by its
//! ranges alone (a table added or deleted, its columns, header or totals rows changed) makes
//! the package unpatchable: it is written anew, with every table as the workbook has it.

use std::collections::BTreeMap;
use std::io::{Read, Seek};

use crate::formula::address::Rect;
use crate::workbook::{TableShape, Workbook};

use super::patch::{find_tag, root_prefix, with_attr, Unpatchable};
use super::tables::parse_table;

/// The table parts to rewrite, by part name, with the table each now describes.
pub type TableParts = BTreeMap<String, TableShape>;

/// Whether a part name is a table part (where Excel and LibreOffice put them).
fn is_table_part(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.contains("/tables/") && lower.ends_with(".xml") && !lower.contains("/_rels/")
}

/// The table parts whose ranges changed, or why the package cannot keep its tables by
/// patching (read only when the run changed a table).
pub fn changed_table_parts<R: Read + Seek>(
    zip: &mut zip::ZipArchive<R>,
    wb: &Workbook,
) -> Result<Result<TableParts, Unpatchable>, String> {
    let mut parts = TableParts::new();
    let mut seen = Vec::new();
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| e.to_string())?;
        let name = entry.name().map_err(|e| e.to_string())?.to_string();
        if !is_table_part(&name) {
            continue;
        }
        let mut xml = Vec::new();
        entry.read_to_end(&mut xml).map_err(|e| format!("{name}: {e}"))?;
        let Some(was) = parse_table(&xml, 0) else { continue };
        let Some(now) = wb.table(&was.name) else {
            return Ok(Err(Unpatchable(format!("table {} was renamed or deleted", was.name))));
        };
        let same_shape = now.columns == was.columns
            && now.header_rows == was.header_rows
            && now.totals_rows == was.totals_rows
            && now.rect.cols() == was.rect.cols();
        if !same_shape {
            return Ok(Err(Unpatchable(format!("table {} was given other columns", now.name))));
        }
        seen.push(now.name.to_ascii_lowercase());
        if now.rect != was.rect {
            parts.insert(name, now.clone());
        }
    }
    if let Some(added) = wb.table_list().iter().find(|t| !seen.contains(&t.name.to_ascii_lowercase())) {
        return Ok(Err(Unpatchable(format!("table {} was added", added.name))));
    }
    Ok(Ok(parts))
}

/// A table part with `table`'s ranges: the table's `ref`, the `<autoFilter>`'s (the header
/// and data rows, as Excel writes it) and a `<sortState>`'s (the data rows).
pub fn with_table_ranges(xml: &str, table: &TableShape) -> String {
    let rect = table.rect;
    let data_last = rect.last.row.saturating_sub(table.totals_rows).max(rect.first.row);
    let filtered = Rect::new(rect.first, crate::formula::address::Pos::new(data_last, rect.last.col));
    let data_first = (rect.first.row + table.header_rows).min(data_last);
    let sorted = Rect::new(crate::formula::address::Pos::new(data_first, rect.first.col), filtered.last);
    let prefix = root_prefix(xml).to_string();
    let xml = with_ref(xml, &format!("{prefix}table"), rect);
    let xml = with_ref(&xml, &format!("{prefix}autoFilter"), filtered);
    with_ref(&xml, &format!("{prefix}sortState"), sorted)
}

/// `xml` with the `ref` of its first `<name>` element set to `rect` (unchanged without one).
fn with_ref(xml: &str, name: &str, rect: Rect) -> String {
    let Some(start) = find_tag(xml, name, 0) else { return xml.to_string() };
    let end = xml[start..].find('>').map_or(xml.len(), |i| start + i);
    format!("{}{}{}", &xml[..start], with_attr(&xml[start..end], "ref", Some(&rect.to_string())), &xml[end..])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formula::address::parse_rect;

    #[test]
    fn a_grown_table_part_names_its_new_ranges_and_keeps_the_rest() {
        let xml = r#"<table xmlns="m" id="1" name="T" displayName="T" ref="A1:C4" totalsRowCount="1"><autoFilter ref="A1:C3"/><sortState ref="A2:C3"><sortCondition ref="A2:A3"/></sortState><tableColumns count="3"/></table>"#;
        let table = TableShape {
            name: "T".into(),
            sheet: 0,
            rect: parse_rect("A1:C6").expect("rect"),
            header_rows: 1,
            totals_rows: 1,
            columns: Vec::new(),
            style: None,
            calculated: Vec::new(),
            totals: Vec::new(),
            id: 0,
        };
        let out = with_table_ranges(xml, &table);
        assert!(out.contains(r#"ref="A1:C6""#), "{out}");
        assert!(out.contains(r#"<autoFilter ref="A1:C5"/>"#), "{out}");
        assert!(out.contains(r#"<sortState ref="A2:C5">"#), "{out}");
        assert!(out.contains(r#"id="1" name="T" displayName="T""#), "{out}");
    }
}
