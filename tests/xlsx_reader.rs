//! ncsheet reads worksheet XML itself (crates/ncsheet/src/io/xlsx/sheet_xml.rs). This test holds that reader
//! to an independent one, calamine's cell reader, on every workbook of the Excel corpus.
//! Each stored value must be the same: a constant becomes the cell's value, and a formula
//! result or a value an array filled is kept as Excel's cached value. Every formula cell must
//! hold a formula, and no cell may appear that calamine does not see.

mod common;

use std::collections::{BTreeMap, HashMap};

use calamine::{open_workbook, Xlsx};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::ast::SheetId;
use ncsheet::formula::Pos;
use ncsheet::io::xlsx;

use common::excel_oracle::read_sheet;

#[derive(Default)]
struct Counts {
    sheets: usize,
    constants: usize,
    cached: usize,
    formulas: usize,
    /// Sheets calamine itself cannot read in one pass (a shared formula before its text).
    calamine_skipped: usize,
}

#[test]
fn our_sheet_reader_reads_what_calamine_reads() {
    let root = common::corpus_root();
    assert!(root.is_dir(), "the Excel corpus is missing: {}", root.display());
    let mut files = Vec::new();
    common::workbooks(&root, &mut files);
    assert!(files.len() > 200, "expected the whole corpus, found {} files", files.len());
    let mut counts = Counts::default();
    let mut problems = Vec::new();
    for path in &files {
        let name = path.strip_prefix(&root).unwrap_or(path).display().to_string();
        let imported = match xlsx::load(path) {
            Ok(imported) => imported,
            Err(e) => {
                problems.push(format!("{name}: {e}"));
                continue;
            }
        };
        let mut calamine: Xlsx<_> = open_workbook(path).expect("calamine opens what we opened");
        for (index, sheet_name) in imported.workbook.sheet_names().iter().enumerate() {
            let sheet = index as SheetId;
            let Some(theirs) = read_sheet(&mut calamine, sheet_name) else {
                counts.calamine_skipped += 1;
                continue;
            };
            counts.sheets += 1;
            let place = |pos: Pos| format!("{name}: {}", imported.workbook.cell_name(sheet, pos));
            let cached: HashMap<Pos, &Value> =
                imported.cached.iter().filter(|c| c.sheet == sheet).map(|c| (c.pos, &c.value)).collect();
            for (&(row, col), want) in &theirs.values {
                let pos = Pos::new(row, col);
                let is_formula = theirs.formulas.contains_key(&(row, col));
                let ours = match cached.get(&pos) {
                    Some(v) => {
                        counts.cached += 1;
                        (*v).clone()
                    }
                    None if is_formula => Value::text(""),
                    None => {
                        counts.constants += 1;
                        imported.workbook.value(sheet, pos)
                    }
                };
                if !same(&ours, want) {
                    problems.push(format!("{}: ours {ours:?}, calamine {want:?}", place(pos)));
                }
            }
            for &(row, col) in theirs.formulas.keys() {
                counts.formulas += 1;
                let pos = Pos::new(row, col);
                if imported.workbook.formula(sheet, pos).is_none() {
                    problems.push(format!("{}: calamine reads a formula, we do not", place(pos)));
                }
            }
            problems.extend(cells_only_we_have(&imported, sheet, &theirs.values).into_iter().map(place));
        }
    }
    println!(
        "{} files, {} sheets ({} left to calamine's limits): {} constants, {} cached values, {} formulas agree",
        files.len(),
        counts.sheets,
        counts.calamine_skipped,
        counts.constants,
        counts.cached,
        counts.formulas
    );
    assert!(counts.sheets > 300 && counts.formulas > 50_000, "the corpus was not read");
    assert!(problems.is_empty(), "{} differences:\n{}", problems.len(), problems.join("\n"));
}

/// Stored values read from the same text: numbers to the bit, the rest exactly. A `#CALC!`
/// or `#SPILL!` that Excel 365 stores as `#VALUE!` with value metadata naming it is read as
/// itself; calamine reads the `#VALUE!` (tests/xlsx_conformance.rs checks the reading
/// against Excel's ERROR.TYPE of such cells).
fn same(ours: &Value, theirs: &Value) -> bool {
    match (ours, theirs) {
        (Value::Number(a), Value::Number(b)) => a.to_bits() == b.to_bits(),
        (Value::Error(XlError::Calc | XlError::Spill), Value::Error(XlError::Value)) => true,
        _ => ours == theirs,
    }
}

/// Constants we hold where calamine has no value (values our own arrays spilled are not
/// constants: they have no input).
fn cells_only_we_have(imported: &xlsx::Imported, sheet: SheetId, theirs: &BTreeMap<(u32, u32), Value>) -> Vec<Pos> {
    let wb = &imported.workbook;
    wb.values(sheet)
        .into_iter()
        .filter(|(pos, _)| wb.formula(sheet, *pos).is_none() && wb.input(sheet, *pos).is_some())
        .filter(|(pos, _)| !theirs.contains_key(&(pos.row, pos.col)))
        .map(|(pos, _)| pos)
        .collect()
}
