//! Editing an existing xlsx is surgical (issue 14): the saved package is the original with
//! only the changed cells rewritten. Every workbook of both corpora is saved after a
//! one-cell edit and compared part by part with the original; LibreOffice opens every one
//! of the results and computes what ncsheet computed; a workbook LibreOffice made with a
//! chart, a comment, merged cells and a name `r` keeps them; saves of a million-formula
//! workbook killed with SIGKILL leave the old file or the new one, and no temporary file
//! after the next save. Edits inside legacy array formulas, prefixed parts, the repl's save
//! and the chamfer macro's save are cases of their own.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::io::{Cursor, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use ncsheet::eval::functions::{self, Outside};
use ncsheet::eval::Value;
use ncsheet::formula::address::Pos;
use ncsheet::formula::ast::{ExprKind, SheetId};
use ncsheet::io::{self, atomic, Origin};
use ncsheet::workbook::Workbook;

/// Every part of a package, decompressed, by name.
fn parts(bytes: &[u8]) -> BTreeMap<String, Vec<u8>> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes)).expect("a zip package");
    let mut out = BTreeMap::new();
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).unwrap();
        let mut data = Vec::new();
        entry.read_to_end(&mut data).unwrap();
        out.insert(entry.name().unwrap().to_string(), data);
    }
    out
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The `<c …>…</c>` (or `<c …/>`) elements of a worksheet part by their `r`, and the part
/// with them and its `<dimension>` taken out.
fn cells(xml: &str) -> (BTreeMap<String, String>, String) {
    let mut map = BTreeMap::new();
    let mut rest_of_part = String::new();
    let mut rest = xml;
    while let Some(at) = rest.find("<c ") {
        rest_of_part.push_str(&rest[..at]);
        let tag_end = at + rest[at..].find('>').unwrap();
        let end = if rest[..tag_end].ends_with('/') {
            tag_end + 1
        } else {
            tag_end + rest[tag_end..].find("</c>").unwrap() + 4
        };
        let element = &rest[at..end];
        let r = element.split("r=\"").nth(1).and_then(|s| s.split('"').next()).unwrap_or("").to_string();
        map.insert(r, element.to_string());
        rest = &rest[end..];
    }
    rest_of_part.push_str(rest);
    if let Some(d) = rest_of_part.find("<dimension ") {
        let end = d + rest_of_part[d..].find("/>").unwrap() + 2;
        rest_of_part.replace_range(d..end, "");
    }
    (map, rest_of_part)
}

/// A worksheet part without its cells (see [`cells`]) as it must change to hold a new cell
/// in a row that had none: the row element the patch adds (`<row r="N">`, empty once its
/// cells are out) and an empty `<sheetData/>` opened (the .xlsm files of empty sheets).
fn without_new_rows(rest: &str) -> String {
    let mut out = rest.replace("<sheetData/>", "<sheetData></sheetData>");
    let mut from = 0;
    while let Some(at) = out[from..].find("<row r=\"").map(|i| from + i) {
        let Some(end) = out[at..].find("</row>").map(|i| at + i + "</row>".len()) else { break };
        let element = &out[at..end];
        let attrs_end = element.find('>').unwrap_or(0);
        if element[attrs_end + 1..] == *"</row>" && element[..attrs_end].matches('=').count() == 1 {
            out.replace_range(at..end, "");
        } else {
            from = at + 1; // an original row (spans or other attributes, or cells): kept
        }
    }
    out
}

/// The `<f …>` element of a cell element, or "".
fn formula_of(element: &str) -> &str {
    match element.find("<f") {
        Some(at) => {
            let end = element[at..]
                .find("</f>")
                .map(|i| at + i + 4)
                .unwrap_or_else(|| at + element[at..].find("/>").unwrap() + 2);
            &element[at..end]
        }
        None => "",
    }
}

/// The elements of an XML text (split at `<`), without those naming calcChain.
fn without_calc_chain(xml: &str) -> Vec<String> {
    xml.split('<').filter(|e| !e.contains("calcChain")).map(str::to_string).collect()
}

/// The workbook part without any `fullCalcOnLoad` attribute.
fn without_full_calc(xml: &str) -> String {
    let mut s = xml.to_string();
    for v in ["1", "0", "true", "false"] {
        s = s.replace(&format!(" fullCalcOnLoad=\"{v}\""), "");
    }
    s
}

/// Whether the saved workbook part is the original but for a recalculation request: the
/// attribute on `<calcPr>`, or a `<calcPr>` added where there was none.
fn only_full_calc_added(old: &str, new: &str) -> bool {
    let (old, new) = (without_full_calc(old), without_full_calc(new));
    old == new || (!old.contains("<calcPr") && new.replacen("<calcPr/>", "", 1) == old)
}

/// The corpora: the Excel oracle corpus and the public one beside it.
fn corpora() -> Option<Vec<PathBuf>> {
    let root = common::corpus::root()?;
    let mut books = Vec::new();
    common::workbooks(&root, &mut books);
    let public = root.parent().unwrap().join("public");
    assert!(public.is_dir() || std::env::var_os("CI").is_none(), "no public corpus at {}", public.display());
    if public.is_dir() {
        common::workbooks(&public, &mut books);
    }
    Some(books)
}

/// The edit: the first constant cell (a number gets 1 added, text gets `!`), else a new
/// number in the first row holding a formula, right of the sheet's last column; in a
/// workbook of array formulas only (every cell filled by one) or of empty sheets, a new
/// number right of the first sheet's last column, in row 1.
fn pick_edit(wb: &Workbook, spilled: &BTreeSet<(SheetId, Pos)>) -> (SheetId, Pos, String) {
    pick_in_cells(wb, spilled).unwrap_or_else(|| {
        let col = wb.used_rect(0).map_or(0, |r| r.last.col + 1);
        (0, Pos::new(0, col), "12.5".to_string())
    })
}

fn pick_in_cells(wb: &Workbook, spilled: &BTreeSet<(SheetId, Pos)>) -> Option<(SheetId, Pos, String)> {
    let mut new_cell = None;
    for sheet in 0..wb.sheet_len() as SheetId {
        for (pos, value) in wb.values(sheet) {
            if spilled.contains(&(sheet, pos)) {
                // A value an array spilled into: the array would spill over an edit.
                continue;
            }
            if wb.is_formula(sheet, pos) {
                if new_cell.is_none() {
                    let last_col = wb.used_rect(sheet).map_or(pos.col, |r| r.last.col);
                    new_cell = Some((sheet, Pos::new(pos.row, last_col + 1), "12.5".to_string()));
                }
                continue;
            }
            match value {
                Value::Number(n) => return Some((sheet, pos, format!("{}", n + 1.0))),
                Value::Text(t) if !t.is_empty() && !t.starts_with(['=', '\'', '+', '-', '@']) => {
                    return Some((sheet, pos, format!("'{t}!")))
                }
                _ => {}
            }
        }
    }
    new_cell
}

struct Saved {
    source: PathBuf,
    out: PathBuf,
    wb: Workbook,
    /// The edited cell and the cells whose value changed.
    changed: Vec<(SheetId, Pos)>,
    edited: (SheetId, Pos),
    /// The values the original file stored (Excel's, in Excel's files) for the changed cells:
    /// the edited cell's constant, the results cached for the others.
    stored: BTreeMap<(SheetId, Pos), Value>,
    /// The formula cell filling each cell of an array result in the original, by cell.
    anchors: BTreeMap<(SheetId, Pos), Pos>,
}

/// Opens, edits one cell, saves beside in `dir`; None when the workbook does not load
/// (said on stdout).
fn edit_and_save(source: &Path, dir: &Path, n: usize) -> Option<Saved> {
    let opened = match io::open(source) {
        Ok(o) => o,
        Err(e) => {
            println!("not loaded: {e}");
            return None;
        }
    };
    let mut wb = opened.workbook;
    // Cells an array fills (spilled into, or in a legacy array formula's area), whose
    // formula would fill them again over an edit.
    let anchors: BTreeMap<_, _> =
        opened.cached.iter().filter(|c| c.anchor != c.pos).map(|c| ((c.sheet, c.pos), c.anchor)).collect();
    let mut spilled: BTreeSet<_> = anchors.keys().copied().collect();
    let names = wb.sheet_names();
    for (name, l) in opened.layout.iter().flat_map(|l| &l.sheets) {
        let Some(sheet) = names.iter().position(|n| n == name) else { continue };
        for a in l.array_formulas.values().filter(|a| a.area.rows() * a.area.cols() < 1 << 16) {
            for row in a.area.first.row..=a.area.last.row {
                for col in a.area.first.col..=a.area.last.col {
                    spilled.insert((sheet as SheetId, Pos::new(row, col)));
                }
            }
        }
    }
    let (sheet, pos, input) = pick_edit(&wb, &spilled);
    let before_edit = wb.value(sheet, pos);
    wb.set_input_deferred(sheet, pos, &input).unwrap();
    wb.recalculate();
    let ext = source.extension().unwrap().to_string_lossy().into_owned();
    let out = dir.join(format!("book{n}.{ext}"));
    let encoded = io::encode_save(&wb, opened.layout.as_ref(), &opened.origin, &out)
        .unwrap_or_else(|e| panic!("{}: {e}", source.display()));
    if !encoded.losses.is_empty() {
        println!("LOSS {}: {:?}", source.display(), encoded.losses);
    }
    encoded.write(atomic::Options::default()).unwrap();
    let changes = wb.changes().unwrap();
    let changed: BTreeSet<_> = changes.inputs.iter().chain(&changes.values).copied().collect();
    // The edited cell held a constant (or nothing): the file stored that.
    let mut stored: BTreeMap<_, _> = opened
        .cached
        .into_iter()
        .filter(|c| changed.contains(&(c.sheet, c.pos)))
        .map(|c| ((c.sheet, c.pos), c.value))
        .collect();
    stored.entry((sheet, pos)).or_insert(before_edit);
    Some(Saved {
        source: source.to_path_buf(),
        out,
        wb,
        changed: changed.into_iter().collect(),
        edited: (sheet, pos),
        stored,
        anchors,
    })
}

/// Whether the saved package is the original but for the changed cells of one worksheet,
/// calcChain and the recalculation request; the failures, one per line.
fn compare_packages(saved: &Saved) -> Vec<String> {
    let before = parts(&fs::read(&saved.source).unwrap());
    let after = parts(&fs::read(&saved.out).unwrap());
    let file = saved.source.display();
    let mut failures = Vec::new();
    let kept: BTreeSet<&String> = before.keys().filter(|k| !k.ends_with("calcChain.xml")).collect();
    if kept != after.keys().collect() {
        failures.push(format!("{file}: parts {:?} became {:?}", kept, after.keys().collect::<Vec<_>>()));
        return failures;
    }
    let names = saved.wb.sheet_names();
    let edited_cells: BTreeSet<String> = saved.changed.iter().map(|(_, p)| p.to_string()).collect();
    let mut sheets_changed = 0;
    for name in kept {
        let (old, new) = (&before[name], &after[name]);
        if old == new {
            continue;
        }
        if name == "[Content_Types].xml" || name.ends_with("workbook.xml.rels") {
            if without_calc_chain(&text(old)) != without_calc_chain(&text(new)) {
                failures.push(format!("{file}: {name} changed beyond calcChain"));
            }
        } else if name.ends_with("workbook.xml") {
            if !only_full_calc_added(&text(old), &text(new)) {
                failures.push(format!("{file}: {name} changed beyond fullCalcOnLoad"));
            }
        } else if name.starts_with("xl/worksheets/") {
            sheets_changed += 1;
            let ((old_cells, old_rest), (new_cells, new_rest)) = (cells(&text(old)), cells(&text(new)));
            if without_new_rows(&old_rest) != without_new_rows(&new_rest) {
                failures.push(format!("{file}: {name} changed outside its cells"));
            }
            let edited = saved.edited.1.to_string();
            for r in old_cells.keys().chain(new_cells.keys()).collect::<BTreeSet<_>>() {
                let (o, n) = (old_cells.get(r), new_cells.get(r));
                if o == n || *r == edited {
                    continue;
                }
                // A dependent keeps its formula; only its cached value changes.
                let same_formula = formula_of(o.map_or("", |s| s)) == formula_of(n.map_or("", |s| s));
                if !edited_cells.contains(r) || !same_formula {
                    failures.push(format!("{file}: {name}: {r}: {o:?} became {n:?}"));
                }
            }
        } else {
            failures.push(format!("{file}: {name} changed"));
        }
    }
    if sheets_changed > names.len() {
        failures.push(format!("{file}: {sheets_changed} worksheets changed"));
    }
    failures
}

#[test]
fn every_corpus_workbook_keeps_every_part_but_the_edited_cells() {
    let Some(books) = corpora() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (mut saved, mut failures) = (0, Vec::new());
    for (n, path) in books.iter().enumerate() {
        let Some(s) = edit_and_save(path, dir.path(), n) else { continue };
        saved += 1;
        failures.extend(compare_packages(&s));
        // The saved file loads, and holds the edit.
        let back = io::load(&s.out).unwrap_or_else(|e| panic!("{e}"));
        let (sheet, pos) = s.edited;
        {
            if back.value(sheet, pos) != s.wb.value(sheet, pos) {
                failures.push(format!("{}: {} does not read back", s.source.display(), s.wb.cell_name(sheet, pos)));
            }
        }
        fs::remove_file(&s.out).unwrap();
    }
    println!("{saved} of {} workbooks saved after a one-cell edit", books.len());
    assert_eq!(saved, books.len(), "every workbook is saved after a one-cell edit");
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

/// LibreOffice opens every saved workbook (converted in batches, one soffice process for
/// many files) and recomputes the edited cells and their dependents as ncsheet did. The
/// originals are converted too: a changed cell is left out only where LibreOffice, on the
/// original, already departs from the value the original stored (it cannot compute that
/// cell: yearly_calendar.xlsx's LAMBDA-defined names, sample-beta.xlsx's inline strings of
/// Excel 2007 beta's namespace, the functions tests/xlsx_libreoffice.rs lists).
#[test]
fn libreoffice_opens_the_saved_workbooks_and_computes_the_same_values() {
    let Some(soffice) = common::soffice() else {
        assert!(std::env::var_os("CI").is_none(), "LibreOffice (soffice) is not installed");
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let Some(books) = corpora() else { return };
    let dir = tempfile::tempdir().unwrap();
    let folder = |name: &str| {
        let path = dir.path().join(name);
        fs::create_dir_all(&path).unwrap();
        path
    };
    let (ins, outs, originals, original_outs) = (folder("in"), folder("out"), folder("orig"), folder("orig-out"));
    let sample: Vec<Saved> = books.iter().enumerate().filter_map(|(n, p)| edit_and_save(p, &ins, n)).collect();
    assert_eq!(sample.len(), books.len(), "every workbook is saved after a one-cell edit");
    // The originals under the saved files' names, so that both conversions pair by name.
    let original_inputs: Vec<PathBuf> = sample
        .iter()
        .map(|s| {
            let copy = originals.join(s.out.file_name().unwrap());
            fs::copy(&s.source, &copy).unwrap();
            copy
        })
        .collect();
    let profile = common::recalculating_profile(&dir.path().join("profile"));
    let inputs: Vec<PathBuf> = sample.iter().map(|s| s.out.clone()).collect();
    common::libreoffice_convert(&soffice, &profile, &inputs, &outs);
    common::libreoffice_convert(&soffice, &profile, &original_inputs, &original_outs);
    let converted =
        |folder: &Path, s: &Saved| io::xlsx::load(&folder.join(s.out.file_name().unwrap()).with_extension("xlsx"));
    let not_opened: Vec<String> =
        sample.iter().filter(|s| converted(&outs, s).is_err()).map(|s| s.source.display().to_string()).collect();
    assert!(not_opened.is_empty(), "LibreOffice could not open: {not_opened:?}");
    let mut tally = Tally::default();
    for s in &sample {
        let lo = converted(&outs, s).unwrap();
        let lo_original = converted(&original_outs, s).ok();
        compare_with_libreoffice(s, &lo.workbook, lo_original.as_ref().map(|o| &o.workbook), &mut tally);
    }
    let Tally { compared, agreed, excluded, momentary, differences } = &tally;
    println!(
        "{} cells left out that read the clock, chance, the host or CELL:\n{}",
        momentary.len(),
        momentary.join("\n")
    );
    println!(
        "LibreOffice opened all {} saved workbooks; {agreed} of {compared} changed cells agree; {} cells left out \
         where LibreOffice departs on the original from the value stored there:",
        sample.len(),
        excluded.len()
    );
    let mut by_book: BTreeMap<&str, usize> = BTreeMap::new();
    for place in excluded {
        *by_book.entry(place.split(": ").next().unwrap_or("")).or_default() += 1;
    }
    println!("{by_book:#?}\n{}", excluded.join("\n"));
    assert!(*compared > 0, "no changed cell was compared");
    assert!(differences.is_empty(), "{agreed} of {compared} agree:\n{}", differences.join("\n"));
}

#[derive(Default)]
struct Tally {
    compared: usize,
    agreed: usize,
    /// Cells LibreOffice cannot compute (it departs from the stored value on the original).
    excluded: Vec<String>,
    /// Cells whose value depends on the moment or the program computing it.
    momentary: Vec<String>,
    differences: Vec<String>,
}

/// LibreOffice's and ncsheet's values agree (a blank and a zero are the same to a formula).
fn lo_agrees(theirs: &Value, ours: &Value) -> bool {
    io::xlsx::values_agree(theirs, ours)
        || (ours.is_blank() && *theirs == Value::Number(0.0))
        || (theirs.is_blank() && *ours == Value::Number(0.0))
}

/// A cell whose value depends, itself or through any cell it reads, on when and where it is
/// computed (the registry's `reads`: the clock, chance, the host), or on CELL's view of the
/// file and its layout, which LibreOffice gives in its own terms: LibreOffice computes later
/// than ncsheet did, with other random numbers.
fn depends_on_the_moment_or_the_program(s: &Saved, sheet: SheetId, pos: Pos) -> bool {
    let wb = &s.wb;
    let pos = s.anchors.get(&(sheet, pos)).copied().unwrap_or(pos);
    let mut seen = BTreeSet::from([(sheet, pos)]);
    let mut todo = vec![(sheet, pos)];
    while let Some((sheet, pos)) = todo.pop() {
        if calls_the_moment_or_the_program(wb, sheet, pos) {
            return true;
        }
        for (sheet, area) in wb.precedents(sheet, pos) {
            let Some(used) = wb.used_rect(sheet) else { continue };
            let (first_row, last_row) = (area.first.row.max(used.first.row), area.last.row.min(used.last.row));
            let (first_col, last_col) = (area.first.col.max(used.first.col), area.last.col.min(used.last.col));
            for row in first_row..=last_row {
                for col in first_col..=last_col {
                    let cell = (sheet, Pos::new(row, col));
                    let at = (sheet, s.anchors.get(&cell).copied().unwrap_or(cell.1));
                    if wb.is_formula(sheet, at.1) && seen.insert(at) {
                        todo.push(at);
                    }
                }
            }
        }
    }
    false
}

/// A formula that calls the clock, chance, the host or CELL itself.
fn calls_the_moment_or_the_program(wb: &Workbook, sheet: SheetId, pos: Pos) -> bool {
    let Some(tree) = wb.formula_tree(sheet, pos) else { return false };
    let mut found = false;
    tree.visit(&mut |e| {
        if let ExprKind::Call(id, _) = &e.kind {
            let spec = functions::spec(*id);
            found |= spec.reads != Outside::Nothing || spec.name == "CELL";
        }
    });
    found
}

/// Changed cells where LibreOffice computes the edited workbook otherwise than Excel does,
/// though it agrees on the original: (workbook, cell, why).
const LIBREOFFICE_DEPARTS_AFTER_THE_EDIT: &[(&str, &str, &str)] = &[(
    "poi/test-data_spreadsheet_61063.xlsx",
    "!A4",
    "RANK(A1,(B1,B2,B3),1) of a number not in the union: LibreOffice 7.4 gives -1, Excel #N/A (RANK finds no rank)",
)];

/// Compares the changed cells of one saved workbook with LibreOffice's reading of it, leaving
/// out a cell where LibreOffice's reading of the original departs from the stored value.
fn compare_with_libreoffice(s: &Saved, lo: &Workbook, lo_original: Option<&Workbook>, tally: &mut Tally) {
    let names = s.wb.sheet_names();
    let lo_sheet = |wb: &Workbook, name: &str| wb.sheet_names().iter().position(|n| n == name).map(|i| i as SheetId);
    for &(sheet, pos) in &s.changed {
        let name = &names[sheet as usize];
        let Some(lo_at) = lo_sheet(lo, name) else { continue };
        let formula = s.wb.formula(sheet, pos).unwrap_or_default();
        let place = format!("{}: {}: {formula}", s.source.display(), s.wb.cell_name(sheet, pos));
        if depends_on_the_moment_or_the_program(s, sheet, pos) {
            tally.momentary.push(place);
            continue;
        }
        if let Some((_, _, why)) = LIBREOFFICE_DEPARTS_AFTER_THE_EDIT
            .iter()
            .find(|(book, cell, _)| s.source.ends_with(book) && s.wb.cell_name(sheet, pos).ends_with(cell))
        {
            tally.excluded.push(format!("{place}: {why}"));
            continue;
        }
        let stored = s.stored.get(&(sheet, pos));
        let on_original = lo_original.and_then(|o| Some(o.value(lo_sheet(o, name)?, pos)));
        if let (Some(stored), Some(on_original)) = (stored, &on_original) {
            if !lo_agrees(on_original, stored) {
                tally.excluded.push(format!("{place}: stored {stored:?}, LibreOffice on the original {on_original:?}"));
                continue;
            }
        }
        let (ours, theirs) = (s.wb.value(sheet, pos), lo.value(lo_at, pos));
        tally.compared += 1;
        if lo_agrees(&theirs, &ours) {
            tally.agreed += 1;
        } else {
            tally.differences.push(format!("{place}: ours {ours:?}, LibreOffice {theirs:?}"));
        }
    }
}

/// A spreadsheet made by LibreOffice: merged cells, a comment, a defined name `r` (which
/// Excel forbids and LibreOffice writes) and an inputs table; a chart comes from converting
/// a workbook with charts.
const FODS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<office:document xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" xmlns:text="urn:oasis:names:tc:opendocument:xmlns:text:1.0" xmlns:dc="http://purl.org/dc/elements/1.1/" xmlns:of="urn:oasis:names:tc:opendocument:xmlns:of:1.2" office:version="1.3" office:mimetype="application/vnd.oasis.opendocument.spreadsheet">
<office:body><office:spreadsheet>
<table:named-expressions><table:named-range table:name="r" table:base-cell-address="$Sheet1.$B$2" table:cell-range-address="$Sheet1.$B$2"/></table:named-expressions>
<table:table table:name="Sheet1">
<table:table-row><table:table-cell table:number-columns-spanned="2" office:value-type="string"><text:p>Chamfer</text:p></table:table-cell><table:covered-table-cell/></table:table-row>
<table:table-row><table:table-cell office:value-type="string"><text:p>nose</text:p></table:table-cell><table:table-cell office:value-type="float" office:value="0.4"><office:annotation><dc:creator>me</dc:creator><text:p>nose radius of the insert</text:p></office:annotation><text:p>0.4</text:p></table:table-cell></table:table-row>
<table:table-row><table:table-cell office:value-type="string"><text:p>twice</text:p></table:table-cell><table:table-cell table:formula="of:=[.B2]*2" office:value-type="float" office:value="0.8"><text:p>0.8</text:p></table:table-cell></table:table-row>
</table:table>
</office:spreadsheet></office:body></office:document>
"#;

fn convert(soffice: &Path, profile: &str, input: &Path, to: &str, out: &Path) -> PathBuf {
    let status = Command::new(soffice)
        .arg(profile)
        .args(["--headless", "--norestore", "--convert-to", to, "--outdir"])
        .arg(out)
        .arg(input)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let ext = to.split(':').next().unwrap();
    let path = out.join(input.file_stem().unwrap()).with_extension(ext);
    assert!(path.exists(), "LibreOffice made no {}", path.display());
    path
}

/// How often LibreOffice's flat XML of a file holds each of the markers.
fn markers(fods: &str) -> Vec<(&'static str, usize)> {
    [
        "number-columns-spanned=\"2\"",
        "<office:annotation",
        "nose radius of the insert",
        "<draw:object",
        "table:name=\"r\"",
    ]
    .iter()
    .map(|m| (*m, fods.matches(m).count()))
    .collect()
}

#[test]
fn a_libreoffice_workbook_keeps_its_chart_comment_merged_cells_and_name_r() {
    let Some(soffice) = common::soffice() else {
        assert!(std::env::var_os("CI").is_none(), "LibreOffice (soffice) is not installed");
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = common::recalculating_profile(&d.join("profile"));
    fs::write(d.join("made.fods"), FODS).unwrap();
    let made = convert(&soffice, &profile, &d.join("made.fods"), "xlsx", d);
    let charts_source =
        common::corpus::path().parent().unwrap().join("public/poi/test-data_spreadsheet_WithThreeCharts.xlsx");
    let mut books = vec![(made, "B2=0.8", "B3", 1.6)];
    if charts_source.exists() {
        // Through LibreOffice's own format, so that LibreOffice writes the charts.
        let ods = convert(&soffice, &profile, &charts_source, "ods", &d.join("ods"));
        let charts = convert(&soffice, &profile, &ods, "xlsx", d);
        books.push((charts, "D2=7", "E2", 49.0));
    }
    for (book, edit, dependent, expected) in books {
        let edited = d.join(format!("edited-{}", book.file_name().unwrap().to_string_lossy()));
        fs::copy(&book, &edited).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
            .args(["set"])
            .arg(&edited)
            .args([edit, "--in-place"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("not kept"), "nothing is lost: {stderr}");
        let before = fs::read_to_string(convert(&soffice, &profile, &book, "fods", &d.join("before"))).unwrap();
        let after = fs::read_to_string(convert(&soffice, &profile, &edited, "fods", &d.join("after"))).unwrap();
        assert_eq!(markers(&after), markers(&before), "{}", book.display());
        assert!(markers(&before).iter().any(|(_, n)| *n > 0));
        // LibreOffice recomputes the dependent from the edited cell.
        let back = io::xlsx::load(&convert(&soffice, &profile, &edited, "xlsx", &d.join("xlsx"))).unwrap();
        let pos = ncsheet::formula::address::parse_cell(dependent).unwrap();
        let cached = back.cached.iter().find(|c| c.sheet == 0 && c.pos == pos).map(|c| c.value.clone());
        assert_eq!(cached, Some(Value::Number(expected)), "{}", book.display());
    }
}

/// The kill test's workbook: a million formulas (issue 14's acceptance).
const FORMULAS: u32 = 1_000_000;

/// A workbook of A1 = 1 and `FORMULAS` cells below it, `=$A$1*ROW()` each, stored as Excel
/// stores a formula filled down: one shared formula, with the cached values Excel would
/// keep. Written here once (as Excel's format has it), so that the test does not spend its
/// time making the file.
fn big_workbook(path: &Path) {
    let mut sheet = String::with_capacity(FORMULAS as usize * 40 + 1024);
    sheet.push_str(r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main">"#);
    sheet.push_str(&format!(
        r#"<dimension ref="A1:A{}"/><sheetData><row r="1"><c r="A1"><v>1</v></c></row>"#,
        FORMULAS + 1
    ));
    for r in 2..=FORMULAS + 1 {
        let f = if r == 2 {
            format!(r#"<f t="shared" ref="A2:A{}" si="0">$A$1*ROW()</f>"#, FORMULAS + 1)
        } else {
            r#"<f t="shared" si="0"/>"#.to_string()
        };
        sheet.push_str(&format!(r#"<row r="{r}"><c r="A{r}">{f}<v>{r}</v></c></row>"#));
    }
    sheet.push_str("</sheetData></worksheet>");
    let book = one_sheet_book("");
    let mut parts_of: Vec<(String, String)> =
        parts(&book).into_iter().map(|(n, b)| (n, text(&b))).filter(|(n, _)| !n.contains("worksheets/")).collect();
    parts_of.push(("xl/worksheets/sheet1.xml".into(), sheet));
    let named: Vec<(&str, &str)> = parts_of.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    fs::write(path, package(&named)).unwrap();
}

fn temporaries(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// A1's value and the last formula's cached value, read from a package whose every part
/// decompresses whole (the zip reader checks each part's CRC): a broken file fails here.
fn first_and_last(path: &Path) -> Result<(f64, f64), String> {
    let bytes = fs::read(path).map_err(|e| e.to_string())?;
    let mut zip = zip::ZipArchive::new(Cursor::new(&bytes[..])).map_err(|e| e.to_string())?;
    let mut sheet = String::new();
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| e.to_string())?;
        let name = entry.name().map(|n| n.to_string()).unwrap_or_default();
        let mut data = Vec::new();
        entry.read_to_end(&mut data).map_err(|e| format!("{name}: {e}"))?;
        if name == "xl/worksheets/sheet1.xml" {
            sheet = String::from_utf8(data).map_err(|e| e.to_string())?;
        }
    }
    let value_of = |cell: &str| -> Result<f64, String> {
        let at = sheet.find(&format!("<c r=\"{cell}\"")).ok_or(format!("no {cell}"))?;
        let v = at + sheet[at..].find("<v>").ok_or(format!("no value in {cell}"))? + 3;
        let end = v + sheet[v..].find("</v>").ok_or(format!("unterminated {cell}"))?;
        sheet[v..end].parse::<f64>().map_err(|e| format!("{cell}: {e}"))
    };
    Ok((value_of("A1")?, value_of(&format!("A{}", FORMULAS + 1))?))
}

/// Whether the save by process `pid` has its temporary file in `dir` (it is writing).
fn writing(dir: &Path, pid: u32) -> bool {
    let its_own = format!("ncsheet-{pid}-");
    temporaries(dir).iter().any(|t| t.contains(&its_own))
}

/// Waits until the child is writing its temporary file (true) or has ended (false).
fn wait_until_writing(dir: &Path, child: &mut std::process::Child) -> bool {
    loop {
        if writing(dir, child.id()) {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(std::time::Duration::from_micros(500));
    }
}

/// Saves of a million-formula workbook killed with SIGKILL leave the old file or the new
/// one, and the next save leaves no temporary file. Half the kills come at times spread over
/// a whole save (most while it reads and computes); the other half once the save is
/// writing its temporary file, spread over the time that writing took, whatever the
/// machine's speed.
#[test]
fn saves_killed_midway_leave_the_old_or_the_new_file_and_no_temporary_after_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let target = d.join("big.xlsx");
    big_workbook(&target);
    let set = |value: u32| {
        Command::new(env!("CARGO_BIN_EXE_ncsheet"))
            .args(["set", "big.xlsx", &format!("A1={value}"), "--in-place"])
            .current_dir(d)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    // How long a whole save takes, and its writing, to spread the kills over them.
    let start = Instant::now();
    let mut first = set(1);
    let wrote = wait_until_writing(d, &mut first);
    let writing_from = start.elapsed();
    // Writing ends when the temporary file is renamed over the target (the process then
    // still frees its million cells).
    while writing(d, first.id()) {
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    let writing_time = if wrote { start.elapsed() - writing_from } else { std::time::Duration::ZERO };
    assert!(first.wait().unwrap().success());
    let whole = start.elapsed();
    let last_row = f64::from(FORMULAS + 1);
    assert_eq!(first_and_last(&target), Ok((1.0, last_row)));
    let mut current = 1;
    let (mut killed_midway, mut killed_writing, mut left_behind) = (0, 0, 0);
    for i in 0..50u32 {
        let value = 100 + i;
        let mut child = set(value);
        let spread = f64::from(i / 2 % 25) / 24.0;
        if i % 2 == 0 {
            std::thread::sleep(whole.mul_f64(0.1 + 0.9 * spread));
        } else if wait_until_writing(d, &mut child) {
            std::thread::sleep(writing_time.mul_f64(0.9 * spread));
        }
        if child.try_wait().unwrap().is_none() {
            killed_writing += usize::from(writing(d, child.id()));
            child.kill().unwrap(); // SIGKILL
            killed_midway += 1;
        }
        child.wait().unwrap();
        left_behind = left_behind.max(temporaries(d).len());
        let (a1, last) = first_and_last(&target).unwrap_or_else(|e| panic!("kill {i}: the target is broken: {e}"));
        assert!(
            a1 == f64::from(current) || a1 == f64::from(value),
            "kill {i}: A1 is {a1}, neither the old {current} nor the new {value}"
        );
        current = a1 as u32;
        assert_eq!(last, a1 * last_row, "kill {i}: the last formula's value does not go with A1");
    }
    println!(
        "{killed_midway} of 50 saves killed midway, {killed_writing} of them while writing (a whole save takes \
         {:.2} s, its writing {:.3} s)",
        whole.as_secs_f64(),
        writing_time.as_secs_f64()
    );
    assert!(killed_midway >= 25, "the kills came too late to test anything");
    assert!(killed_writing >= 5, "too few kills while the file was being written");
    assert!(left_behind > 0, "the kills left no temporary file: nothing to clean up");
    assert!(set(7).wait().unwrap().success());
    assert_eq!(temporaries(d), Vec::<String>::new(), "temporary files left after the next save");
    let wb = io::load(&target).unwrap();
    assert_eq!(wb.value(0, Pos::new(FORMULAS, 0)), Value::Number(7.0 * last_row));
}

#[test]
fn an_origin_is_kept_only_for_the_same_kind_of_file() {
    // A csv saved as xlsx is a new workbook; nothing of a csv is lost that way.
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("a.csv"), "1,=A1*2\n").unwrap();
    let opened = io::open(&dir.path().join("a.csv")).unwrap();
    assert!(matches!(opened.origin, Origin::Csv(_)));
    let encoded = io::encode_save(&opened.workbook, None, &opened.origin, &dir.path().join("a.xlsx")).unwrap();
    assert!(encoded.losses.is_empty());
}

struct Cli {
    code: i32,
    stderr: String,
}

fn ncsheet_in(dir: &Path, args: &[&str], stdin: &str) -> Cli {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    Cli { code: out.status.code().expect("exited"), stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

fn sha256(path: &Path) -> String {
    let out = Command::new("sha256sum").arg(path).output().expect("sha256sum runs");
    String::from_utf8(out.stdout).unwrap().split_whitespace().next().unwrap_or_default().to_string()
}

/// A package of the given parts, deflated.
fn package(parts: &[(&str, &str)]) -> Vec<u8> {
    use std::io::Write;
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for (name, text) in parts {
        zip.start_file(*name, zip::write::SimpleFileOptions::default()).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.finish().unwrap().into_inner()
}

/// A one-sheet workbook package around a worksheet's `<sheetData>` content.
fn one_sheet_book(sheet_data: &str) -> Vec<u8> {
    let main = "http://schemas.openxmlformats.org/spreadsheetml/2006/main";
    let rel = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";
    package(&[
        (
            "[Content_Types].xml",
            r#"<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/></Types>"#,
        ),
        (
            "_rels/.rels",
            &format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{rel}/officeDocument" Target="xl/workbook.xml"/></Relationships>"#
            ),
        ),
        (
            "xl/workbook.xml",
            &format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="{main}" xmlns:r="{rel}"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#
            ),
        ),
        (
            "xl/_rels/workbook.xml.rels",
            &format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{rel}/worksheet" Target="worksheets/sheet1.xml"/></Relationships>"#
            ),
        ),
        (
            "xl/worksheets/sheet1.xml",
            &format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="{main}"><dimension ref="A1:B3"/><sheetData>{sheet_data}</sheetData></worksheet>"#
            ),
        ),
    ])
}

/// Excel refuses to change part of an array ("You can't change part of an array"): an
/// edit inside a legacy array formula's area is named as a loss before anything is
/// written, and --in-place then needs --force. A dynamic array's spill area is not one.
#[test]
fn an_edit_inside_a_legacy_array_formula_is_a_loss_named_first() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cells = r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><f t="array" ref="B1:B3">A1:A3*2</f><v>2</v></c></row><row r="2"><c r="A2"><v>2</v></c><c r="B2"><v>4</v></c></row><row r="3"><c r="A3"><v>3</v></c><c r="B3"><v>6</v></c></row>"#;
    fs::write(d.join("arr.xlsx"), one_sheet_book(cells)).unwrap();
    let before = sha256(&d.join("arr.xlsx"));
    let run = ncsheet_in(d, &["set", "arr.xlsx", "B2=5", "--in-place"], "");
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("Sheet1!B2") && run.stderr.contains("change part of an array"), "{}", run.stderr);
    assert!(run.stderr.contains("B1:B3") && run.stderr.contains("nothing was written"), "{}", run.stderr);
    assert_eq!(sha256(&d.join("arr.xlsx")), before);
    // Written elsewhere (or forced), the array formula is kept over B1 alone, B2 holds the
    // edit and B3 its last value; LibreOffice computes B1 as {=A1:A3*2} in one cell: 2.
    let run = ncsheet_in(d, &["set", "arr.xlsx", "B2=5", "-o", "out.xlsx"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("change part of an array"), "{}", run.stderr);
    let sheet = text(&parts(&fs::read(d.join("out.xlsx")).unwrap())["xl/worksheets/sheet1.xml"]);
    let row = |r: &str| sheet.split("<row ").find(|x| x.starts_with(&format!("r=\"{r}\""))).unwrap_or("").to_string();
    assert!(row("1").contains(r#"<c r="B1"><f t="array" ref="B1">A1:A3*2</f><v>2</v></c>"#), "{sheet}");
    assert!(row("2").contains(r#"<c r="B2"><v>5</v></c>"#), "{sheet}");
    assert!(row("3").contains(r#"<c r="B3"><v>6</v></c>"#), "{sheet}");
    if let Some(soffice) = common::soffice() {
        let profile = common::recalculating_profile(&d.join("profile"));
        let lo = io::xlsx::load(&convert(&soffice, &profile, &d.join("out.xlsx"), "xlsx", &d.join("lo"))).unwrap();
        let cached = |row: u32| lo.cached.iter().find(|c| c.pos == Pos::new(row, 1)).map(|c| c.value.clone());
        assert_eq!(cached(0), Some(Value::Number(2.0)), "LibreOffice's B1");
        assert_eq!(
            [lo.workbook.value(0, Pos::new(1, 1)), lo.workbook.value(0, Pos::new(2, 1))],
            [5.0, 6.0].map(Value::Number)
        );
    }
    let run = ncsheet_in(d, &["set", "arr.xlsx", "B2=5", "--in-place", "--force"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    // Editing a cell outside the area, or the anchor with a whole new formula, is no
    // "part of an array".
    fs::write(d.join("arr.xlsx"), one_sheet_book(cells)).unwrap();
    let run = ncsheet_in(d, &["set", "arr.xlsx", "A2=7", "--in-place"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("part of an array"), "{}", run.stderr);
}

/// The paper's chamfer workbook names its inputs (D … eB in B6:B11) and computes XA … ZB
/// with formulas in G6:G9; chamfer.bas writes its results only where they are named (or
/// into the fixed layout's B9:B12 when the inputs came from it), so a save of its run keeps
/// every input and formula of the sheet.
#[test]
fn the_chamfer_macro_writes_over_no_input_and_no_formula_of_the_papers_workbook() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (xlsx, bas) = (root.join("sheets/chamfer.xlsx"), root.join("sheets/chamfer.bas"));
    let before = (sha256(&xlsx), sha256(&bas));
    let (xlsx_arg, bas_arg) = (xlsx.to_str().unwrap(), bas.to_str().unwrap());
    let args =
        ["run", xlsx_arg, bas_arg, "--sheet", "Outer", "--dialect", "linuxcnc", "-o", "p.ngc", "--save", "s.xlsx"];
    let run = ncsheet_in(d, &args, "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("not kept"), "{}", run.stderr);
    assert_eq!((sha256(&xlsx), sha256(&bas)), before);
    let saved = io::load(&d.join("s.xlsx")).unwrap();
    let outer = saved.sheet_id("Outer").unwrap();
    // docs/domain.md §1's outer row: D 40, f 2, α 45, r 0.8, eA 1, eB 1 → XA … ZB.
    for (cell, want) in [("B6", 40.0), ("B9", 0.8), ("B10", 1.0), ("B11", 1.0)] {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        assert_eq!(saved.value(outer, pos), Value::Number(want), "Outer!{cell}");
    }
    for (cell, want) in [("G6", 44.262742), ("G7", -4.6), ("G8", 33.062742), ("G9", 1.0)] {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        assert!(saved.is_formula(outer, pos), "Outer!{cell} lost its formula");
        let Value::Number(n) = saved.value(outer, pos) else { panic!("Outer!{cell}") };
        assert!((n - want).abs() < 1e-6, "Outer!{cell} = {n}");
    }
    assert!(fs::metadata(d.join("p.ngc")).unwrap().len() > 0);
}

/// The part written with every element prefixed (`<x:worksheet xmlns:x="…">`), as some
/// generators write it.
fn prefixed(xml: &str) -> String {
    let mut out = String::with_capacity(xml.len() + xml.len() / 4);
    let mut chars = xml.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(c);
        if c == '<' {
            if chars.peek() == Some(&'/') {
                out.push(chars.next().unwrap());
            }
            if chars.peek().is_some_and(|c| c.is_ascii_alphabetic()) {
                out.push_str("x:");
            }
        }
    }
    out.replace(
        "xmlns=\"http://schemas.openxmlformats.org/spreadsheetml",
        "xmlns:x=\"http://schemas.openxmlformats.org/spreadsheetml",
    )
}

/// A workbook whose workbook and worksheet parts use a namespace prefix saves surgically:
/// the edited cell is written with the part's prefix, every other part is kept byte for
/// byte, and the dependents compute docs/domain.md §1's values (LibreOffice too, when present).
#[test]
fn a_workbook_with_prefixed_parts_saves_surgically() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let source = parts(&fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx")).unwrap());
    let rewritten = ["xl/workbook.xml", "xl/worksheets/sheet2.xml"];
    let texts: Vec<(String, String)> = source
        .iter()
        .map(|(name, bytes)| {
            let t = text(bytes);
            (name.clone(), if rewritten.contains(&name.as_str()) { prefixed(&t) } else { t })
        })
        .collect();
    let named: Vec<(&str, &str)> = texts.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    fs::write(d.join("pref.xlsx"), package(&named)).unwrap();
    let original = parts(&fs::read(d.join("pref.xlsx")).unwrap());
    assert!(text(&original["xl/worksheets/sheet2.xml"]).contains("<x:sheetData>"));
    // Outer's D (B6) from 40 to 50: XA = D + (A'D − r)·2 grows by 10, XB = D − … too.
    let run = ncsheet_in(d, &["set", "pref.xlsx", "Outer!B6=50", "--in-place"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let saved = parts(&fs::read(d.join("pref.xlsx")).unwrap());
    for (name, bytes) in &original {
        if !rewritten.contains(&name.as_str()) && !name.starts_with("xl/worksheets/sheet1") {
            assert!(saved.get(name) == Some(bytes), "{name} changed");
        }
    }
    let sheet = text(&saved["xl/worksheets/sheet2.xml"]);
    assert!(sheet.contains(r#"<x:c r="B6"><x:v>50</x:v></x:c>"#), "{sheet}");
    let unprefixed = |xml: &str| xml.replace("<x:", "<").replace("</x:", "</");
    let (new_cells, new_rest) = cells(&unprefixed(&sheet));
    let (old_cells, old_rest) = cells(&unprefixed(&text(&original["xl/worksheets/sheet2.xml"])));
    assert!(new_rest == old_rest, "the part changed outside its cells");
    let changed: Vec<&String> = old_cells.keys().filter(|k| old_cells[*k] != new_cells[*k]).collect();
    // B6 and what depends on it: C21 (XA), C28 (XB) and G6, G8 showing them.
    assert_eq!(changed, ["B6", "C21", "C28", "G6", "G8"]);
    assert!(text(&saved["xl/workbook.xml"]).contains("<x:calcPr"));
    let wb = io::load(&d.join("pref.xlsx")).unwrap();
    let outer = wb.sheet_id("Outer").unwrap();
    let expect = [("G6", 54.262742), ("G8", 43.062742)];
    for (cell, want) in expect {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        let Value::Number(n) = wb.value(outer, pos) else { panic!("{cell}") };
        assert!((n - want).abs() < 1e-6, "{cell} = {n}");
    }
    let Some(soffice) = common::soffice() else { return };
    let profile = common::recalculating_profile(&d.join("profile"));
    let lo = io::xlsx::load(&convert(&soffice, &profile, &d.join("pref.xlsx"), "xlsx", &d.join("lo"))).unwrap();
    let outer = lo.workbook.sheet_id("Outer").unwrap();
    for (cell, want) in expect {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        let cached = lo.cached.iter().find(|c| c.sheet == outer && c.pos == pos).map(|c| c.value.clone());
        let Some(Value::Number(n)) = cached else { panic!("LibreOffice {cell}: {cached:?}") };
        assert!((n - want).abs() < 1e-6, "LibreOffice {cell} = {n}");
    }
}

/// The repl's save is `set`'s: from the file opened, so a workbook with charts keeps every
/// part but the edited sheet (it was written anew through rust_xlsxwriter, charts lost).
#[test]
fn the_repl_saves_surgically_as_set_does() {
    let source = common::corpus::public_path().join("poi/test-data_spreadsheet_WithThreeCharts.xlsx");
    if !source.exists() {
        assert!(std::env::var_os("CI").is_none(), "{} is missing", source.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fs::copy(&source, d.join("charts.xlsx")).unwrap();
    let before = sha256(&d.join("charts.xlsx"));
    let run = ncsheet_in(d, &["repl", "charts.xlsx"], "D2=7\nsave out.xlsx\nsave charts.xlsx\n");
    assert!(run.stderr.contains("refusing to overwrite"), "{}", run.stderr);
    assert_eq!(sha256(&d.join("charts.xlsx")), before);
    assert!(!run.stderr.contains("not kept"), "{}", run.stderr);
    let wb = io::load(&d.join("charts.xlsx")).unwrap();
    let edited = (0, ncsheet::formula::address::parse_cell("D2").unwrap());
    let changed: BTreeSet<_> = {
        let mut opened = io::open(&d.join("charts.xlsx")).unwrap().workbook;
        opened.set_input(edited.0, edited.1, "7").unwrap();
        let c = opened.changes().unwrap();
        c.inputs.iter().chain(&c.values).copied().collect()
    };
    let saved = Saved {
        source: d.join("charts.xlsx"),
        out: d.join("out.xlsx"),
        wb,
        changed: changed.into_iter().collect(),
        edited,
        stored: BTreeMap::new(),
        anchors: BTreeMap::new(),
    };
    let failures = compare_packages(&saved);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(parts(&fs::read(d.join("out.xlsx")).unwrap()).keys().any(|k| k.starts_with("xl/charts/")));
    assert_eq!(io::load(&d.join("out.xlsx")).unwrap().value(0, edited.1), Value::Number(7.0));
}

/// Excel 365 stores a `#CALC!` (FILTER that finds nothing) as `#VALUE!` with value metadata
/// (`vm`) naming the real error (FILTER_ERRORS.xlsx of the Excel corpus, E1). It is read as
/// `#CALC!`; when an edit makes the cell a number, the saved cell keeps its dynamic-array
/// mark (`cm`) but no longer its error metadata, which would misname the new value.
#[test]
fn a_newer_error_kept_as_value_metadata_is_read_and_dropped_when_the_value_changes() {
    let Some(root) = common::corpus::root() else { return };
    let source = root.join("calc_tests/LOOKUP_AND_REFERENCE/FILTER_ERRORS.xlsx");
    let original = io::xlsx::load(&source).unwrap();
    let cached = |pos: Pos| original.cached.iter().find(|c| c.pos == pos).map(|c| c.value.clone());
    assert_eq!(cached(Pos::new(0, 4)), Some(Value::Error(ncsheet::eval::XlError::Calc)), "E1 as Excel computed it");
    // J1's #VALUE! is a plain one (no metadata): FILTER's include argument is text there.
    assert_eq!(cached(Pos::new(0, 9)), Some(Value::Error(ncsheet::eval::XlError::Value)));
    let dir = tempfile::tempdir().unwrap();
    fs::copy(&source, dir.path().join("f.xlsx")).unwrap();
    let run = ncsheet_in(dir.path(), &["set", "f.xlsx", "A1=20", "-o", "out.xlsx"], "");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let sheet = text(&parts(&fs::read(dir.path().join("out.xlsx")).unwrap())["xl/worksheets/sheet1.xml"]);
    let e1 = sheet.split("<c ").find(|c| c.starts_with("r=\"E1\"")).expect("E1 saved");
    assert!(e1.contains("cm=\"1\"") && !e1.contains("vm=") && e1.contains("<v>20</v>"), "{e1}");
}

/// `set --in-place` keeps a workbook's print titles and print area (the package is patched,
/// its definedNames untouched), so what it says about them must not be "not kept" (issue 30:
/// it said so while keeping them). openpyxl, the outside reader, reads both back.
#[test]
fn set_in_place_keeps_print_titles_and_says_so() {
    if !common::openpyxl::openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("titles.xlsx");
    let make = "import sys, openpyxl\nwb = openpyxl.Workbook(); ws = wb.active; ws.title = 'Sheet1'\n\
                ws['A1'] = 1; ws['B1'] = '=A1*2'\nws.print_title_rows = '1:1'; ws.print_area = 'A1:B10'\nwb.save(sys.argv[1])";
    common::openpyxl::python(make, &[&file]);
    let run = common::cli::ncsheet(&["set", file.to_str().unwrap(), "A1=5", "--in-place"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("not kept"), "{}", run.stderr);
    assert!(run.stderr.contains("print titles of 'Sheet1'") && run.stderr.contains("keeps it"), "{}", run.stderr);
    let read = "import sys, openpyxl\nws = openpyxl.load_workbook(sys.argv[1]).active\n\
                print(ws.print_title_rows, ws.print_area, ws['A1'].value)";
    assert_eq!(common::openpyxl::python(read, &[&file]).trim(), "$1:$1 'Sheet1'!$A$1:$B$10 5");
}
