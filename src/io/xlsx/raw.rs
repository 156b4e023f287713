//! The zip package and its workbook-level parts, as far as calamine does not expose them:
//! the sheet list with each sheet's part, defined names with their `localSheetId`, the
//! shared-string part and the workbook's VBA code name.

use std::io::{Cursor, Read};

use zip::result::ZipError;
use zip::ZipArchive;

use super::xml::{for_each_tag, unescape};
use super::ErrorKind;
use crate::workbook::Iteration;

/// The zip package with its workbook-level parts read.
pub struct Package<'a> {
    zip: ZipArchive<Cursor<&'a [u8]>>,
    pub sheets: Vec<SheetEntry>,
    pub names: Vec<NameEntry>,
    /// `<workbookPr codeName="…">`: the workbook's VBA name.
    pub code_name: Option<String>,
    /// The shared-string table's part, if the workbook has one.
    pub shared_strings: Option<String>,
    /// The workbook part and the parts its relationships name (styles, theme, strings…).
    pub workbook_parts: Vec<String>,
    /// `<calcPr iterate="1" iterateCount iterateDelta>`: iterative calculation is on.
    pub iteration: Option<Iteration>,
    /// The external-link parts, in the order formulas number them (`[1]` is the first).
    pub external_links: Vec<Option<String>>,
}

#[derive(Clone, Debug)]
pub struct SheetEntry {
    pub name: String,
    /// Path of the part in the package, e.g. `xl/worksheets/sheet1.xml`.
    pub part: String,
    /// Last segment of the relationship type: `worksheet`, `chartsheet`, `dialogsheet`, …
    pub kind: String,
}

#[derive(Clone, Debug)]
pub struct NameEntry {
    pub name: String,
    pub formula: String,
    /// Index into the workbook's `<sheets>` list for a sheet-scoped name.
    pub local_sheet: Option<usize>,
}

pub type Err = (Option<String>, ErrorKind, String);

pub fn zip_error(part: Option<&str>, e: ZipError) -> Err {
    let kind = match e {
        ZipError::Io(_) => ErrorKind::Io,
        _ => ErrorKind::Damaged,
    };
    (part.map(str::to_string), kind, format!("damaged zip entry: {e}"))
}

impl<'a> Package<'a> {
    pub fn open(bytes: &'a [u8]) -> Result<Package<'a>, Err> {
        let zip = ZipArchive::new(Cursor::new(bytes))
            .map_err(|e| (None, ErrorKind::NotXlsx, format!("not a readable xlsx (zip) package: {e}")))?;
        let mut package = Package {
            zip,
            sheets: Vec::new(),
            names: Vec::new(),
            code_name: None,
            shared_strings: None,
            workbook_parts: Vec::new(),
            iteration: None,
            external_links: Vec::new(),
        };
        let workbook = package.main_part()?;
        let rels = package.relationships(&workbook)?;
        let text = package.read_part(&workbook)?;
        package.read_workbook(&text, &rels)?;
        package.shared_strings = rels.iter().find(|(_, _, kind)| kind == "sharedStrings").map(|(_, t, _)| t.clone());
        package.workbook_parts = std::iter::once(workbook)
            .chain(rels.iter().filter(|(_, target, _)| target.ends_with(".xml")).map(|(_, target, _)| target.clone()))
            .collect();
        Ok(package)
    }

    /// Reads a whole (small) part as text; a missing part is an error.
    pub fn read_part(&mut self, part: &str) -> Result<String, Err> {
        let mut entry = match self.zip.by_name(part) {
            Ok(e) => e,
            Err(ZipError::FileNotFound) => {
                return Err((Some(part.to_string()), ErrorKind::Damaged, "missing from the package".into()))
            }
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        String::from_utf8(bytes).map_err(|_| (Some(part.to_string()), ErrorKind::Damaged, "not UTF-8 text".into()))
    }

    /// A part's raw bytes if the package has it.
    pub fn read_optional(&mut self, part: &str) -> Result<Option<Vec<u8>>, Err> {
        let mut entry = match self.zip.by_name(part) {
            Ok(e) => e,
            Err(ZipError::FileNotFound) => return Ok(None),
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        Ok(Some(bytes))
    }

    /// The workbook part named by the package relationships (`xl/workbook.xml` as a rule).
    fn main_part(&mut self) -> Result<String, Err> {
        let rels = match self.read_optional("_rels/.rels")? {
            Some(bytes) => bytes,
            None => return Ok("xl/workbook.xml".to_string()),
        };
        let mut main = None;
        for_each_tag(&rels, &mut |tag, _| {
            if tag.name == b"Relationship"
                && tag.attr("Type").is_some_and(|t| t.ends_with(b"/officeDocument"))
                && main.is_none()
            {
                main = tag.attr("Target").map(|t| resolve("", &unescape(t)));
            }
        });
        Ok(main.unwrap_or_else(|| "xl/workbook.xml".to_string()))
    }

    /// The table parts a worksheet's relationships name.
    pub fn table_parts(&mut self, sheet_part: &str) -> Result<Vec<String>, Err> {
        let rels = self.relationships(sheet_part)?;
        Ok(rels.into_iter().filter(|(_, _, kind)| kind == "table").map(|(_, target, _)| target).collect())
    }

    /// The relationships of a part: id → (target part, type's last segment).
    fn relationships(&mut self, part: &str) -> Result<Vec<(String, String, String)>, Err> {
        let (dir, file) = part.rsplit_once('/').unwrap_or(("", part));
        let rels_part = if dir.is_empty() { format!("_rels/{file}.rels") } else { format!("{dir}/_rels/{file}.rels") };
        let Some(bytes) = self.read_optional(&rels_part)? else { return Ok(Vec::new()) };
        let mut out = Vec::new();
        for_each_tag(&bytes, &mut |tag, _| {
            if tag.name == b"Relationship" {
                let id = tag.attr("Id").map(unescape).unwrap_or_default();
                let target = tag.attr("Target").map(|v| resolve(dir, &unescape(v))).unwrap_or_default();
                let kind = tag.attr("Type").map(unescape).unwrap_or_default();
                let kind = kind.rsplit('/').next().unwrap_or("").to_string();
                out.push((id, target, kind));
            }
        });
        Ok(out)
    }

    fn read_workbook(&mut self, text: &str, rels: &[(String, String, String)]) -> Result<(), Err> {
        let bytes = text.as_bytes();
        let mut sheets = Vec::new();
        let mut names = Vec::new();
        let mut code_name = None;
        let mut iteration = None;
        let mut external_links = Vec::new();
        for_each_tag(bytes, &mut |tag, content| match tag.name {
            b"externalReference" => {
                let id = tag.attr("id").map(unescape).unwrap_or_default();
                external_links.push(rels.iter().find(|(rid, ..)| *rid == id).map(|(_, target, _)| target.clone()));
            }
            b"workbookPr" => code_name = tag.attr("codeName").map(unescape),
            b"calcPr" => iteration = calc_iteration(|name| tag.attr(name).map(unescape)),
            b"sheet" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let id = tag.attr("id").map(unescape).unwrap_or_default();
                match rels.iter().find(|(rid, ..)| *rid == id) {
                    Some((_, target, kind)) => {
                        sheets.push(SheetEntry { name, part: target.clone(), kind: kind.clone() })
                    }
                    // Excel opens such a workbook without the sheet.
                    None => sheets.push(SheetEntry { name, part: String::new(), kind: "sheet with no part".into() }),
                }
            }
            b"definedName" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let local_sheet = tag.attr("localSheetId").and_then(|v| std::str::from_utf8(v).ok()?.parse().ok());
                names.push(NameEntry { name, formula: unescape(content), local_sheet });
            }
            _ => {}
        });
        self.sheets = sheets;
        self.names = names;
        self.code_name = code_name;
        self.iteration = iteration;
        self.external_links = external_links;
        Ok(())
    }

    /// A part to stream; a missing part is an error.
    pub fn entry(&mut self, part: &str) -> Result<zip::read::ZipFile<'_, Cursor<&'a [u8]>>, Err> {
        match self.zip.by_name(part) {
            Ok(e) => Ok(e),
            Err(ZipError::FileNotFound) => {
                Err((Some(part.to_string()), ErrorKind::Damaged, "missing from the package".into()))
            }
            Err(e) => Err(zip_error(Some(part), e)),
        }
    }
}

/// The iteration settings of a `<calcPr>` (attributes read through `attr`), when it turns
/// iteration on; a missing or unreadable limit takes Excel's default.
fn calc_iteration(attr: impl Fn(&str) -> Option<String>) -> Option<Iteration> {
    let on = attr("iterate").is_some_and(|v| v == "1" || v.eq_ignore_ascii_case("true"));
    if !on {
        return None;
    }
    let default = Iteration::default();
    let count = attr("iterateCount").and_then(|v| v.trim().parse().ok()).unwrap_or(default.count);
    let max_change = attr("iterateDelta")
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|d| d.is_finite() && *d >= 0.0)
        .unwrap_or(default.max_change);
    Some(Iteration { count, max_change })
}

/// Resolves a relationship target against the folder of its source part.
fn resolve(dir: &str, target: &str) -> String {
    if let Some(abs) = target.strip_prefix('/') {
        return abs.to_string();
    }
    let mut parts: Vec<&str> = dir.split('/').filter(|s| !s.is_empty()).collect();
    for seg in target.split('/') {
        match seg {
            ".." => {
                parts.pop();
            }
            "." | "" => {}
            s => parts.push(s),
        }
    }
    parts.join("/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relationship_targets_resolve_against_their_folder() {
        assert_eq!(resolve("xl", "worksheets/sheet1.xml"), "xl/worksheets/sheet1.xml");
        assert_eq!(resolve("xl", "/xl/worksheets/sheet1.xml"), "xl/worksheets/sheet1.xml");
        assert_eq!(resolve("xl/worksheets", "../drawings/d.xml"), "xl/drawings/d.xml");
    }
}
