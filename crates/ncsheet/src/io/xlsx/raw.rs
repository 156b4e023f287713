//! The zip package and its workbook-level parts, as far as calamine does not expose them:
//! the sheet list with each sheet's part, defined names with their `localSheetId`, the
//! shared-string part and the workbook's VBA code name.

use std::collections::HashMap;
use std::io::{Cursor, Read};

use zip::result::ZipError;
use zip::ZipArchive;

use super::xml::{for_each_tag, unescape, StreamError};
use super::{Calculation, ErrorKind};
use crate::eval::XlError;
use crate::io::limits::{self, ReadLimits, RATIO_GRACE};
use crate::workbook::Iteration;

/// The zip package with its workbook-level parts read.
pub struct Package<'a> {
    zip: ZipArchive<Cursor<&'a [u8]>>,
    pub sheets: Vec<SheetEntry>,
    pub names: Vec<NameEntry>,
    /// `<workbookPr codeName="…">`: the workbook's VBA name.
    pub code_name: Option<String>,
    /// `<calcPr>` and the date system of `<workbookPr>`.
    pub calculation: Calculation,
    /// The shared-string table's part, if the workbook has one.
    pub shared_strings: Option<String>,
    /// The workbook part and the parts its relationships name (styles, theme, strings…).
    pub workbook_parts: Vec<String>,
    /// `<calcPr iterate="1" iterateCount iterateDelta>`: iterative calculation is on.
    pub iteration: Option<Iteration>,
    /// The external-link parts, in the order formulas number them (`[1]` is the first).
    pub external_links: Vec<Option<String>>,
    /// `<workbookView activeTab="n">`: the index in `sheets` of the sheet the file opens on
    /// (0 when absent, ECMA-376's default).
    pub active_tab: usize,
    /// How far its parts may inflate (the caller's: a document's settings).
    limits: ReadLimits,
}

#[derive(Clone, Debug)]
pub struct SheetEntry {
    pub name: String,
    /// Path of the part in the package, e.g. `xl/worksheets/sheet1.xml`.
    pub part: String,
    /// Last segment of the relationship type: `worksheet`, `chartsheet`, `dialogsheet`, …
    pub kind: String,
    /// `state="hidden"` or `"veryHidden"`.
    pub visibility: crate::workbook::Visibility,
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
    if let ZipError::Io(io) = &e {
        if let Some(limit) = past_limit(io) {
            return (part.map(str::to_string), ErrorKind::TooLarge, limit.to_string());
        }
    }
    let kind = match e {
        ZipError::Io(_) => ErrorKind::Io,
        _ => ErrorKind::Damaged,
    };
    (part.map(str::to_string), kind, format!("damaged zip entry: {e}"))
}

impl<'a> Package<'a> {
    pub fn open(bytes: &'a [u8]) -> Result<Package<'a>, Err> {
        Package::open_limited(bytes, ReadLimits::default())
    }

    /// [`Package::open`] with its parts held to `limits` while they inflate.
    pub fn open_limited(bytes: &'a [u8], limits: ReadLimits) -> Result<Package<'a>, Err> {
        let zip = ZipArchive::new(Cursor::new(bytes))
            .map_err(|e| (None, ErrorKind::NotXlsx, format!("not a readable xlsx (zip) package: {e}")))?;
        check_entry_names(&zip, bytes).map_err(|(entry, why)| (Some(entry), ErrorKind::Damaged, why))?;
        let mut package = Package {
            zip,
            sheets: Vec::new(),
            names: Vec::new(),
            code_name: None,
            calculation: Calculation::default(),
            shared_strings: None,
            workbook_parts: Vec::new(),
            iteration: None,
            external_links: Vec::new(),
            active_tab: 0,
            limits,
        };
        package.check_metadata_parts()?;
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

    /// The parts that describe the package rather than the workbook, `[Content_Types].xml`
    /// and the document properties (`docProps/*.xml`), checked as every XML part ncsheet
    /// reads is (no DTD, XML's references only, elements closed): no reader of cells reads
    /// them, but Excel refuses a package where one is not well-formed or declares a DTD, and
    /// a save copies them as they are. The error names the part.
    fn check_metadata_parts(&mut self) -> Result<(), Err> {
        let parts: Vec<String> = self
            .zip
            .file_names()
            .filter_map(|name| Some(name.ok()?.into_owned()))
            .filter(|name| is_metadata_part(name))
            .collect();
        for part in parts {
            self.read_optional(&part)?;
        }
        Ok(())
    }

    /// The workbook part and its text without the `<sheet>` elements whose relationship id
    /// names no part (Excel saves a very hidden Excel 4 macro sheet so, with `r:id=""`) or a
    /// part of a kind calamine does not read as a sheet (a macro sheet, or a theme, on which
    /// calamine said only "Unrecognized sheet:type", naming no part), or `None` when every
    /// sheet is one calamine reads. Excel and LibreOffice open such a workbook without those
    /// sheets; calamine refuses it, so it is given this text instead (the import notes each
    /// sheet left out, with its kind).
    pub fn workbook_without_partless_sheets(&mut self) -> Result<Option<(String, String)>, Err> {
        if self.sheets.iter().all(|s| !s.part.is_empty() && CALAMINE_SHEETS.contains(&s.kind.as_str())) {
            return Ok(None);
        }
        let Some(workbook) = self.workbook_parts.first().cloned() else { return Ok(None) };
        let rels = self.relationships(&workbook)?;
        let text = self.read_part(&workbook)?;
        let read = |id: &str| {
            rels.iter()
                .find(|(rid, ..)| rid == id)
                .is_some_and(|(_, part, kind)| !part.is_empty() && CALAMINE_SHEETS.contains(&kind.as_str()))
        };
        Ok(Some((workbook, without_sheets_where(&text, |id| !read(id)))))
    }

    /// Reads a whole (small) XML part as text, its references checked; a missing part is an
    /// error.
    pub fn read_part(&mut self, part: &str) -> Result<String, Err> {
        let mut entry = self.entry(part)?.held_whole();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        check_xml(part, &bytes)?;
        String::from_utf8(bytes).map_err(|_| (Some(part.to_string()), ErrorKind::Damaged, "not UTF-8 text".into()))
    }

    /// A part's raw bytes if the package has it; an XML part (`.xml`, `.rels`) only when its
    /// references are XML's (the readers of small parts forgive, so they are checked here).
    pub fn read_optional(&mut self, part: &str) -> Result<Option<Vec<u8>>, Err> {
        let bytes = self.read_optional_bytes(part)?;
        if let Some(bytes) = &bytes {
            let lower = part.to_ascii_lowercase();
            if lower.ends_with(".xml") || lower.ends_with(".rels") {
                check_xml(part, bytes)?;
            }
        }
        Ok(bytes)
    }

    fn read_optional_bytes(&mut self, part: &str) -> Result<Option<Vec<u8>>, Err> {
        let Some(index) = index_of(&self.zip, part) else { return Ok(None) };
        let mut entry = match self.zip.by_index(index) {
            Ok(e) => Inflating::new(e, self.limits).held_whole(),
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        Ok(Some(bytes))
    }

    /// The errors that cells' value metadata (`vm="n"`, entry n-1) stand for: Excel stores a
    /// `#SPILL!` or `#CALC!` (errors older readers lack) as `#VALUE!` in the cell and the real
    /// one as a rich value of structure `_error` (`xl/metadata.xml`, `xl/richData/`). `None`
    /// where an entry is no such error; empty when the package has no metadata.
    pub fn rich_errors(&mut self) -> Result<Vec<Option<XlError>>, Err> {
        let Some(metadata) = self.read_optional("xl/metadata.xml")? else { return Ok(Vec::new()) };
        let values = self.read_optional("xl/richData/rdrichvalue.xml")?.unwrap_or_default();
        let structures = self.read_optional("xl/richData/rdrichvaluestructure.xml")?.unwrap_or_default();
        let rich = rich_values(&values, &structures);
        let error_of = |i: u32| rich.get(i as usize).copied().flatten();
        Ok(value_metadata_rich_values(&metadata).into_iter().map(|i| i.and_then(error_of)).collect())
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
                main = Some(
                    internal_target(tag, "").map_err(|why| (Some("_rels/.rels".to_string()), ErrorKind::Damaged, why)),
                );
            }
        });
        main.unwrap_or_else(|| Ok("xl/workbook.xml".to_string()))
    }

    /// A relationships part rewritten with absolute targets for calamine, which joins a
    /// target to the workbook's folder as written and so misses `../xl/./sheet1.xml` (it
    /// said "Worksheet not found"): `part`'s relationships part and its new text, `None`
    /// when every internal target is already spelled as calamine reads it.
    pub fn relationships_for_calamine(&mut self, part: &str) -> Result<Option<(String, String)>, Err> {
        let dir = part.rsplit_once('/').map_or("", |(dir, _)| dir);
        let rels_part = relationships_part(part);
        let Some(bytes) = self.read_optional(&rels_part)? else { return Ok(None) };
        let (mut entries, mut plain) = (Vec::new(), true);
        for_each_tag(&bytes, &mut |tag, _| {
            if tag.name != b"Relationship" || is_external(tag) {
                return;
            }
            let written = tag.attr("Target").map(unescape).unwrap_or_default();
            let Ok(target) = internal_target(tag, dir) else { return };
            let as_calamine_joins = match written.strip_prefix('/') {
                Some(absolute) => absolute.to_string(),
                None if dir.is_empty() => written,
                None => format!("{dir}/{written}"),
            };
            plain &= as_calamine_joins == target;
            let id = tag.attr("Id").map(unescape).unwrap_or_default();
            entries.push((id, tag.attr("Type").map(unescape).unwrap_or_default(), target));
        });
        Ok((!plain).then(|| (rels_part, super::opc::absolute_relationships(&entries))))
    }

    /// The table parts a worksheet's relationships name.
    pub fn table_parts(&mut self, sheet_part: &str) -> Result<Vec<String>, Err> {
        let rels = self.relationships(sheet_part)?;
        Ok(rels.into_iter().filter(|(_, _, kind)| kind == "table").map(|(_, target, _)| target).collect())
    }

    /// The parts `part` relates to by relationships of the types `kinds` (a type's last
    /// segment: `table`, `pivotTable`, `pivotCacheDefinition`…), as (type, part).
    pub fn related_parts(&mut self, part: &str, kinds: &[&str]) -> Result<Vec<(String, String)>, Err> {
        let rels = self.relationships(part)?;
        Ok(rels.into_iter().filter(|(_, _, k)| kinds.contains(&k.as_str())).map(|(_, target, k)| (k, target)).collect())
    }

    /// The targets outside the package (`TargetMode="External"`) of `part`'s relationships
    /// of the type `kind` (a type's last segment: `hyperlink`), as written, by id.
    pub fn external_targets(&mut self, part: &str, kind: &str) -> Result<HashMap<String, String>, Err> {
        let Some(bytes) = self.read_optional(&relationships_part(part))? else { return Ok(HashMap::new()) };
        let mut out = HashMap::new();
        for_each_tag(&bytes, &mut |tag, _| {
            let of_kind = tag.attr("Type").is_some_and(|t| t.rsplit(|&b| b == b'/').next() == Some(kind.as_bytes()));
            if tag.name == b"Relationship" && of_kind && is_external(tag) {
                let id = tag.attr("Id").map(unescape).unwrap_or_default();
                out.entry(id).or_insert_with(|| tag.attr("Target").map(unescape).unwrap_or_default());
            }
        });
        Ok(out)
    }

    /// The relationships of a part: id → (target part, type's last segment).
    fn relationships(&mut self, part: &str) -> Result<Vec<(String, String, String)>, Err> {
        let dir = part.rsplit_once('/').map_or("", |(dir, _)| dir);
        let rels_part = relationships_part(part);
        let Some(bytes) = self.read_optional(&rels_part)? else { return Ok(Vec::new()) };
        let mut out = Vec::new();
        let mut refused = None;
        for_each_tag(&bytes, &mut |tag, _| {
            if tag.name == b"Relationship" {
                let id = tag.attr("Id").map(unescape).unwrap_or_default();
                // An external resource (a hyperlink, a linked workbook's path) is no part.
                let target = match is_external(tag) {
                    true => Ok(String::new()),
                    false => internal_target(tag, dir),
                };
                let target = target.unwrap_or_else(|why| {
                    refused.get_or_insert(format!("relationship {id}: {why}"));
                    String::new()
                });
                let kind = tag.attr("Type").map(unescape).unwrap_or_default();
                let kind = kind.rsplit('/').next().unwrap_or("").to_string();
                out.push((id, target, kind));
            }
        });
        match refused {
            Some(why) => Err((Some(rels_part), ErrorKind::Damaged, why)),
            None => Ok(out),
        }
    }

    fn read_workbook(&mut self, text: &str, rels: &[(String, String, String)]) -> Result<(), Err> {
        let bytes = text.as_bytes();
        let mut sheets = Vec::new();
        let mut names = Vec::new();
        let mut code_name = None;
        let mut calculation = Calculation::default();
        // Relationships by id (the first of an id, as a search would find): a workbook of
        // 100,000 sheets must not search the list once per sheet.
        let mut by_id: std::collections::HashMap<&str, usize> = std::collections::HashMap::with_capacity(rels.len());
        for (i, (rid, ..)) in rels.iter().enumerate() {
            by_id.entry(rid.as_str()).or_insert(i);
        }
        let mut external_links = Vec::new();
        let mut active_tab = None;
        for_each_tag(bytes, &mut |tag, content| match tag.name {
            // The first view is the one Excel opens with.
            b"workbookView" if active_tab.is_none() => {
                active_tab = Some(tag.attr("activeTab").and_then(|v| unescape(v).parse().ok()).unwrap_or(0));
            }
            b"externalReference" => {
                let id = tag.attr("id").map(unescape).unwrap_or_default();
                external_links.push(rels.iter().find(|(rid, ..)| *rid == id).map(|(_, target, _)| target.clone()));
            }
            b"workbookPr" => {
                code_name = tag.attr("codeName").map(unescape);
                calculation.date_1904 = tag.attr("date1904").is_some_and(xml_true);
            }
            b"calcPr" => {
                let number = |key: &str| tag.attr(key).and_then(|v| unescape(v).parse::<f64>().ok());
                calculation.mode = tag.attr("calcMode").map_or(calculation.mode.clone(), unescape);
                calculation.iterate = tag.attr("iterate").is_some_and(xml_true);
                calculation.iterate_count =
                    number("iterateCount").map_or(calculation.iterate_count, excel_iteration_count);
                calculation.iterate_delta =
                    number("iterateDelta").map_or(calculation.iterate_delta, excel_iteration_delta);
                calculation.full_calc_on_load = tag.attr("fullCalcOnLoad").is_some_and(xml_true);
            }
            b"sheet" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let id = tag.attr("id").map(unescape).unwrap_or_default();
                let visibility = match tag.attr("state").map(unescape).as_deref() {
                    Some("hidden") => crate::workbook::Visibility::Hidden,
                    Some("veryHidden") => crate::workbook::Visibility::VeryHidden,
                    _ => crate::workbook::Visibility::Visible,
                };
                let (part, kind) = match by_id.get(id.as_str()).map(|&i| &rels[i]) {
                    Some((_, target, kind)) => (target.clone(), kind.clone()),
                    // Excel opens such a workbook without the sheet.
                    None => (
                        String::new(),
                        "sheet naming no part in the package (as Excel saves a very hidden macro sheet)".into(),
                    ),
                };
                sheets.push(SheetEntry { name, part, kind, visibility });
            }
            b"definedName" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let local_sheet = tag.parsed("localSheetId");
                names.push(NameEntry { name, formula: unescape(content), local_sheet });
            }
            _ => {}
        });
        self.sheets = sheets;
        self.names = names;
        self.code_name = code_name;
        self.iteration = iteration_of(&calculation);
        self.calculation = calculation;
        self.external_links = external_links;
        self.active_tab = active_tab.unwrap_or(0);
        Ok(())
    }

    /// A part to stream, held to the limits while it inflates; a missing part is an error.
    pub fn entry(&mut self, part: &str) -> Result<Inflating<zip::read::ZipFile<'_, Cursor<&'a [u8]>>>, Err> {
        let Some(index) = index_of(&self.zip, part) else {
            return Err((Some(part.to_string()), ErrorKind::Damaged, "missing from the package".into()));
        };
        self.zip.by_index(index).map(|e| Inflating::new(e, self.limits)).map_err(|e| zip_error(Some(part), e))
    }

    /// Inflates, within the limits, every part calamine reads when it opens the package
    /// (`Xlsx::new`: the package and workbook relationships, the workbook, styles, theme and
    /// shared strings, found by calamine's case-insensitive names), so that a part past a limit
    /// is refused here, naming itself, before calamine holds it whole. `already` are parts
    /// read through [`Package::entry`] before.
    pub fn check_parts_calamine_reads(&mut self, already: &[&str]) -> Result<(), Err> {
        let (dir, file) =
            self.workbook_parts.first().and_then(|w| w.rsplit_once('/')).unwrap_or(("xl", "workbook.xml"));
        let dir = format!("{dir}/").to_ascii_lowercase();
        let file = file.to_ascii_lowercase();
        let wanted = [
            "_rels/.rels".to_string(),
            format!("{dir}sharedstrings.xml"),
            format!("{dir}theme/theme1.xml"),
            format!("{dir}styles.xml"),
            format!("{dir}_rels/{file}.rels"),
            format!("{dir}{file}"),
        ];
        let names: Vec<String> = self
            .zip
            .file_names()
            .filter_map(|name| Some(name.ok()?.into_owned()))
            .filter(|name| !already.contains(&name.as_str()))
            .filter(|name| wanted.contains(&name.replace('\\', "/").to_ascii_lowercase()))
            .collect();
        for name in names {
            let mut entry = self.entry(&name)?;
            if name.replace('\\', "/").to_ascii_lowercase() == wanted[1] {
                // A table no relationship names is still opened by calamine, which trusts
                // its uniqueCount: it is read here as the workbook's own would be.
                check_shared_strings(&name, entry)?;
                continue;
            }
            if let Err(e) = super::xml::check_references(&mut entry) {
                // A part past the size or ratio limit is refused for that, naming the option
                // that raises it, even where its XML went wrong first (a 16 MiB run of text).
                std::io::copy(&mut entry, &mut std::io::sink()).map_err(|e| zip_error(Some(&name), ZipError::Io(e)))?;
                return Err(xml_error(&name, e));
            }
        }
        Ok(())
    }
}

/// A small XML part whose markup or references are not XML's (a DTD, `&bogus;`, `&#1;`):
/// refused naming the part and the byte, before a forgiving reader (ours, or calamine, whose
/// message names no part) shows it as text.
fn check_xml(part: &str, bytes: &[u8]) -> Result<(), Err> {
    super::xml::check_references(bytes).map_err(|e| xml_error(part, e))
}

fn xml_error(part: &str, e: StreamError<super::xml::BadReference>) -> Err {
    let message = match e {
        StreamError::Io(e) => return zip_error(Some(part), ZipError::Io(e)),
        StreamError::Xml { offset, message } => format!("the XML is not well-formed at byte {offset}: {message}"),
        StreamError::Handler(bad) => format!("the XML is not well-formed: {bad}"),
    };
    (Some(part.to_string()), ErrorKind::Damaged, message)
}

/// Whether a package entry is `[Content_Types].xml` or a document-properties part.
fn is_metadata_part(name: &str) -> bool {
    let name = name.replace('\\', "/").to_ascii_lowercase();
    name == "[content_types].xml" || (name.starts_with("docprops/") && name.ends_with(".xml"))
}

/// The relationship types (last segment) calamine reads as sheets: it refuses a workbook
/// listing any other.
const CALAMINE_SHEETS: [&str; 3] = ["worksheet", "chartsheet", "dialogsheet"];

/// The part holding `part`'s relationships (`xl/_rels/workbook.xml.rels`).
pub fn relationships_part(part: &str) -> String {
    match part.rsplit_once('/') {
        Some((dir, file)) => format!("{dir}/_rels/{file}.rels"),
        None => format!("_rels/{part}.rels"),
    }
}

/// `xml` without the `<sheet …/>` (or `<sheet …>…</sheet>`) elements, of any namespace
/// prefix, whose relationship id (`r:id`, unescaped) `drop` picks.
fn without_sheets_where(xml: &str, drop: impl Fn(&str) -> bool) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some(open) = rest.find('<') {
        let Some(close) = rest[open..].find('>').map(|c| open + c) else { break };
        let tag = &rest[open..=close];
        let name = tag[1..].split(|c: char| c.is_whitespace() || c == '/' || c == '>').next().unwrap_or("");
        if !(name.rsplit(':').next() == Some("sheet") && drop(&relationship_id(tag))) {
            out.push_str(&rest[..=close]);
            rest = &rest[close + 1..];
            continue;
        }
        out.push_str(&rest[..open]);
        rest = &rest[close + 1..];
        if !tag.ends_with("/>") {
            let end = format!("</{name}>");
            rest = rest.find(&end).map_or("", |at| &rest[at + end.len()..]);
        }
    }
    out.push_str(rest);
    out
}

/// The value of a tag's relationship id attribute (`id` with a namespace prefix), empty
/// when it has none.
fn relationship_id(tag: &str) -> String {
    let mut rest = tag;
    while let Some(at) = rest.find("id=") {
        let prefixed = rest[..at].ends_with(':');
        let value = &rest[at + 3..];
        if prefixed {
            let quote = value.chars().next().unwrap_or('"');
            let inner = &value[quote.len_utf8()..];
            return unescape(&inner.as_bytes()[..inner.find(quote).unwrap_or(inner.len())]);
        }
        rest = value;
    }
    String::new()
}

/// The index of the entry named `part`, found by hashing its bytes. The zip crate looks a
/// name it does not find so up again in every entry, decoded (for names written in another
/// encoding): a workbook of 10,000 sheets without relationship parts looked each one up across
/// every entry, 10^8 names decoded. Only a name outside ASCII, whose bytes an entry may spell
/// otherwise, is looked up that way.
fn index_of<R: Read + std::io::Seek>(zip: &ZipArchive<R>, part: &str) -> Option<usize> {
    zip.index_for_name_raw(part.as_bytes()).or_else(|| if part.is_ascii() { None } else { zip.index_for_name(part) })
}

/// Checks a zip package's entry names as the Open Packaging Conventions require them
/// (ECMA-376 Part 2, part names): no two names equal when compared as case-insensitive ASCII
/// ([M1.12]: an implementer shall not recognize such a package) and no segment of dots only
/// (`..`, `.`; [M1.10]). Readers disagree on which of two equal entries counts (the zip
/// crate, calamine and so ncsheet take the last, others the first), so such a file would
/// show different cells in different programs, and a save would carry both; an entry
/// `../x` is how a package attacks a program that unpacks it. The error names the entry.
pub fn check_entry_names<R: Read + std::io::Seek>(zip: &ZipArchive<R>, bytes: &[u8]) -> Result<(), (String, String)> {
    if zip.has_duplicate_names() {
        let entry = repeated_entry(bytes, zip.central_directory_start()).unwrap_or_default();
        return Err((entry, "the package holds two entries of this name (a damaged or crafted file: readers differ on which one counts)".into()));
    }
    let mut seen = std::collections::HashMap::new();
    for raw in zip.file_names_raw() {
        let name = String::from_utf8_lossy(raw);
        if name.split('/').any(|segment| !segment.is_empty() && segment.bytes().all(|b| b == b'.')) {
            return Err((name.into_owned(), "the package has an entry whose name holds a '.' or '..' segment, which no part name has (a damaged or crafted file)".into()));
        }
        // Compared as bytes: a name outside UTF-8 (CP437, flag bit 11 clear) decoded lossily
        // would make two different names one.
        if let Some(other) = seen.insert(raw.to_ascii_lowercase(), name.clone()) {
            return Err((
                name.into_owned(),
                format!("the package also holds '{other}', the same part name in other letter case (a damaged or crafted file: readers differ on which one counts)"),
            ));
        }
    }
    Ok(())
}

/// The first entry name the central directory at `start` lists twice, read from its
/// headers (the zip crate keeps only one of each name).
fn repeated_entry(bytes: &[u8], start: u64) -> Option<String> {
    const HEADER: &[u8] = b"PK\x01\x02";
    let u16_at = |at: usize| bytes.get(at..at + 2).map(|b| usize::from(u16::from_le_bytes([b[0], b[1]])));
    let mut seen = std::collections::HashSet::new();
    let mut at = usize::try_from(start).ok()?;
    while bytes.get(at..at + 4) == Some(HEADER) {
        let (name_len, extra_len, comment_len) = (u16_at(at + 28)?, u16_at(at + 30)?, u16_at(at + 32)?);
        let name = bytes.get(at + 46..at + 46 + name_len)?;
        if !seen.insert(name) {
            return Some(String::from_utf8_lossy(name).into_owned());
        }
        at += 46 + name_len + extra_len + comment_len;
    }
    None
}

/// Reads a shared-strings table through the checks of the one the workbook names.
fn check_shared_strings(name: &str, entry: impl Read) -> Result<(), Err> {
    match super::sheet_xml::read_shared_strings(entry) {
        Ok(_) => Ok(()),
        Err(StreamError::Io(e)) => Err(zip_error(Some(name), ZipError::Io(e))),
        Err(StreamError::Xml { offset, message }) => Err((
            Some(name.to_string()),
            ErrorKind::Damaged,
            format!("the XML is not well-formed at byte {offset}: {message}"),
        )),
        Err(StreamError::Handler((kind, message))) => Err((Some(name.to_string()), kind, message)),
    }
}

/// A part of the package inflating, stopped with a [`PastLimit`] error as soon as it passes
/// the bytes or the ratio to its compressed size that [`ReadLimits`] allow: the check runs
/// on every read, so a zip bomb costs the limit, never the bytes it would inflate to.
pub struct Inflating<R> {
    inner: R,
    inflated: u64,
    /// The bytes this part may inflate to: the smaller of the two limits.
    cap: u64,
    compressed: u64,
    limits: ReadLimits,
}

impl<'z, R: Read> Inflating<zip::read::ZipFile<'z, R>> {
    pub fn new(entry: zip::read::ZipFile<'z, R>, limits: ReadLimits) -> Self {
        let compressed = entry.compressed_size();
        let by_ratio = compressed.saturating_mul(limits.zip_ratio).max(RATIO_GRACE);
        Inflating { inner: entry, inflated: 0, cap: by_ratio.min(limits.part_bytes), compressed, limits }
    }
}

impl<R: Read> Read for Inflating<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.inflated += n as u64;
        if self.inflated > self.cap {
            return Err(std::io::Error::other(self.past_limit()));
        }
        Ok(n)
    }
}

/// The most a part read into one buffer may inflate to: the buffer may double past it.
const HELD_WHOLE: u64 = 256 << 20;

impl<R> Inflating<R> {
    /// For a part read into memory whole: at most [`HELD_WHOLE`].
    pub fn held_whole(mut self) -> Self {
        self.cap = self.cap.min(HELD_WHOLE);
        self.limits.part_bytes = self.limits.part_bytes.min(HELD_WHOLE);
        self
    }

    fn past_limit(&self) -> PastLimit {
        let limits = self.limits;
        if self.inflated > limits.part_bytes && limits.part_bytes == HELD_WHOLE {
            return PastLimit(format!(
                "the part inflates to more than {}, ncsheet's limit on a part it holds whole: a zip bomb or a damaged file",
                limits::bytes(HELD_WHOLE)
            ));
        }
        if self.inflated > limits.part_bytes {
            return PastLimit(format!(
                "the part inflates to more than {}, ncsheet's limit on one part (--max-part-size raises it)",
                limits::bytes(limits.part_bytes)
            ));
        }
        PastLimit(format!(
            "the part inflates to more than {} times its compressed size of {}: a zip bomb, or a part \
             more repetitive than Excel writes (--max-zip-ratio raises the limit of {})",
            limits.zip_ratio,
            limits::bytes(self.compressed),
            limits.zip_ratio
        ))
    }
}

/// A part inflated past a limit: what to say about it.
#[derive(Debug)]
pub struct PastLimit(String);

impl std::fmt::Display for PastLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PastLimit {}

/// The limit an IO error of [`Inflating`] reports, if it is one.
pub fn past_limit(e: &std::io::Error) -> Option<&PastLimit> {
    e.get_ref()?.downcast_ref::<PastLimit>()
}

/// The iteration settings of a workbook's `<calcPr>`, when it turns iteration on; a limit
/// that is not a finite non-negative number takes Excel's default.
fn iteration_of(calculation: &Calculation) -> Option<Iteration> {
    if !calculation.iterate {
        return None;
    }
    let default = Iteration::default();
    let max_change =
        Some(calculation.iterate_delta).filter(|d| d.is_finite() && *d >= 0.0).unwrap_or(default.max_change);
    Some(Iteration { count: calculation.iterate_count, max_change })
}

/// Excel's "Maximum Change" of an iteration: a finite number ≥ 0; NaN, an infinity or a
/// negative one is its default, 0.001, read so once, so that `info` shows the change `eval`
/// iterates to (it showed `NaN` and `-1` while `eval` used 0.001).
fn excel_iteration_delta(delta: f64) -> f64 {
    if delta.is_finite() && delta >= 0.0 {
        delta
    } else {
        Iteration::default().max_change
    }
}

/// Excel's most iterations (File > Options > Formulas, "Maximum Iterations" 1 to 32,767): a
/// file asking for more (2,147,483,647 ran for minutes on a two-cell cycle) gets Excel's
/// bound, as Excel itself reads it.
pub const MAX_ITERATIONS: u32 = 32_767;

/// A stored `iterateCount` within Excel's range 1 to [`MAX_ITERATIONS`].
fn excel_iteration_count(n: f64) -> u32 {
    if n.is_nan() {
        return 100;
    }
    n.clamp(1.0, f64::from(MAX_ITERATIONS)) as u32
}

/// An xsd:boolean attribute's value: `1` or `true`.
fn xml_true(value: &[u8]) -> bool {
    matches!(value, b"1" | b"true")
}

/// `TargetMode="External"`: the target is a resource outside the package.
fn is_external(tag: &super::xml::Tag) -> bool {
    tag.attr("TargetMode").is_some_and(|mode| mode == b"External")
}

/// The part an internal relationship's target names, resolved against the folder `dir` of
/// its source part (see `opc.rs`); the error quotes the target and says why it names none.
fn internal_target(tag: &super::xml::Tag, dir: &str) -> Result<String, String> {
    let written = tag.attr("Target").map(unescape).unwrap_or_default();
    super::opc::resolve_target(dir, &written).map_err(|why| format!("the target '{written}' {why}"))
}

/// For each `<bk>` of `<valueMetadata>`, the rich value it points at (through the
/// `XLRICHVALUE` future metadata's `<rvb i>`), if it does.
fn value_metadata_rich_values(metadata: &[u8]) -> Vec<Option<u32>> {
    let (mut types, mut rich_blocks, mut out) = (Vec::new(), Vec::new(), Vec::new());
    let mut section = "";
    let mut future_is_rich = false;
    for_each_tag(metadata, &mut |tag, _| match tag.name {
        b"metadataType" => types.push(tag.attr("name").unwrap_or_default().to_vec()),
        b"futureMetadata" => {
            section = "future";
            future_is_rich = tag.attr("name") == Some(b"XLRICHVALUE".as_slice());
        }
        b"cellMetadata" => section = "cell",
        b"valueMetadata" => section = "value",
        b"rvb" if section == "future" && future_is_rich => rich_blocks.push(tag.parsed::<u32>("i")),
        // One `<rc>` a block in files Excel writes: the block's record.
        b"rc" if section == "value" => {
            let kind = tag.parsed::<usize>("t").and_then(|t| types.get(t.checked_sub(1)?));
            let rich = kind.filter(|k| k.as_slice() == b"XLRICHVALUE").and_then(|_| tag.parsed::<usize>("v"));
            out.push(rich.and_then(|v| rich_blocks.get(v).copied().flatten()));
        }
        _ => {}
    });
    out
}

/// For each rich value (`<rv>` of rdrichvalue.xml), the error it is when its structure is
/// `_error`: its `errorType` key is ERROR.TYPE's number less one (8 `#SPILL!`, 13 `#CALC!`).
fn rich_values(values: &[u8], structures: &[u8]) -> Vec<Option<XlError>> {
    let mut shapes: Vec<(bool, Vec<Vec<u8>>)> = Vec::new();
    for_each_tag(structures, &mut |tag, _| match tag.name {
        b"s" => shapes.push((tag.attr("t") == Some(b"_error".as_slice()), Vec::new())),
        b"k" => {
            if let Some((_, keys)) = shapes.last_mut() {
                keys.push(tag.attr("n").unwrap_or_default().to_vec());
            }
        }
        _ => {}
    });
    let mut rows: Vec<(Option<usize>, Vec<String>)> = Vec::new();
    for_each_tag(values, &mut |tag, text| match tag.name {
        b"rv" => rows.push((tag.parsed("s"), Vec::new())),
        b"v" => {
            if let Some((_, vs)) = rows.last_mut() {
                vs.push(unescape(text));
            }
        }
        _ => {}
    });
    rows.into_iter()
        .map(|(shape, vs)| {
            let (is_error, keys) = shapes.get(shape?)?;
            let at = keys.iter().position(|k| k.as_slice() == b"errorType").filter(|_| *is_error)?;
            let kind: u32 = vs.get(at)?.trim().parse().ok()?;
            let number = kind.checked_add(1)?;
            XlError::ALL.iter().copied().find(|e| u32::from(e.type_number()) == number)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheets_naming_no_part_are_left_out_of_calamines_view() {
        let xml = r#"<workbook><sheets><sheet name="A" sheetId="1" r:id="rId1"/><sheet name="M" sheetId="2" state="veryHidden" r:id=""/><x:sheet name="N" r:id="rId9"></x:sheet></sheets></workbook>"#;
        let kept = without_sheets_where(xml, |id| id != "rId1");
        assert_eq!(kept, r#"<workbook><sheets><sheet name="A" sheetId="1" r:id="rId1"/></sheets></workbook>"#);
        assert_eq!(relationship_id(r#"<sheet sheetId="2" r:id="">"#), "");
        assert_eq!(relationship_id(r#"<sheet sheetId="2" r:id='rId&amp;3'/>"#), "rId&3");
    }

    /// The parts as Excel 365 writes them for a `#CALC!` and a `#SPILL!` kept as values
    /// (calc_tests/INFORMATION/ERROR.TYPE.xlsx of the Excel corpus).
    #[test]
    fn value_metadata_names_the_errors_rich_values_hold() {
        let metadata = br#"<metadata><metadataTypes count="1"><metadataType name="XLRICHVALUE" minSupportedVersion="120000"/></metadataTypes><futureMetadata name="XLRICHVALUE" count="2"><bk><extLst><ext uri="{3e2802c4-a4d2-4d8b-9148-e3be6c30e623}"><xlrd:rvb i="0"/></ext></extLst></bk><bk><extLst><ext uri="{3e2802c4-a4d2-4d8b-9148-e3be6c30e623}"><xlrd:rvb i="1"/></ext></extLst></bk></futureMetadata><valueMetadata count="2"><bk><rc t="1" v="0"/></bk><bk><rc t="1" v="1"/></bk></valueMetadata></metadata>"#;
        let values = br#"<rvData count="2"><rv s="0"><v>13</v><v>0</v></rv><rv s="0"><v>8</v><v>0</v></rv></rvData>"#;
        let structures = br#"<rvStructures count="1"><s t="_error"><k n="errorType" t="i"/><k n="subType" t="i"/></s></rvStructures>"#;
        assert_eq!(rich_values(values, structures), [Some(XlError::Calc), Some(XlError::Spill)]);
        assert_eq!(value_metadata_rich_values(metadata), [Some(0), Some(1)]);
        // A rich value of another structure (a linked data type) is no error.
        let other = br#"<rvStructures count="1"><s t="_linkedentity"><k n="errorType"/></s></rvStructures>"#;
        assert_eq!(rich_values(values, other), [None, None]);
    }
}
