//! The library's `Document` alone, as a front end other than the command line uses it: bytes
//! in, an edit, bytes out; no CLI code and no file path in between. Expected values come from
//! docs/domain.md §1 (the chamfer's worked values) and from LibreOffice reading the saved bytes.

mod common;

use std::path::{Path, PathBuf};

use calamine::{open_workbook, Data, Reader, Xlsx};
use common::{libreoffice_convert, recalculating_profile, soffice};
use ncsheet::document::{Document, OpenOptions, SaveFormat};
use ncsheet::eval::Value;

/// docs/domain.md §1, the outer chamfer at α = 30° (D 40, f 0.3, r 0.8): XA and XB.
const XA_30: f64 = 42.3259818304895;
const XB_30: f64 = 35.8596588155657;

fn shipped_chamfer() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx")).expect("sheets/chamfer.xlsx")
}

fn number(doc: &Document, cell: &str) -> f64 {
    let (sheet, pos) = doc.cell(cell).unwrap_or_else(|| panic!("no cell {cell}"));
    match doc.workbook().value(sheet, pos) {
        Value::Number(n) => n,
        other => panic!("{cell} is {other:?}, not a number"),
    }
}

/// Opens the shipped workbook from its bytes and sets α = 30° in Outer!B8.
fn chamfer_at_30_degrees() -> Document {
    let mut doc = Document::open(shipped_chamfer(), &OpenOptions::named("chamfer.xlsx")).expect("opens");
    let (sheet, b8) = doc.cell("Outer!B8").expect("Outer!B8");
    let problems = doc.set(sheet, b8, "30").expect("a number is accepted");
    assert!(problems.is_empty(), "{problems:?}");
    doc
}

#[test]
fn an_edit_through_the_document_gives_the_papers_values() {
    let doc = chamfer_at_30_degrees();
    assert!((number(&doc, "Outer!G6") - XA_30).abs() < 1e-12, "XA {}", number(&doc, "Outer!G6"));
    assert!((number(&doc, "Outer!G8") - XB_30).abs() < 1e-12, "XB {}", number(&doc, "Outer!G8"));
}

#[test]
fn the_format_comes_from_the_bytes_not_the_name() {
    // An xlsx package under a misleading name is still read as one.
    let doc = Document::open(shipped_chamfer(), &OpenOptions::named("chamfer.csv")).expect("opens as xlsx");
    assert!(doc.workbook().sheet_id("Outer").is_some());
    // Text with no signature follows its name.
    let doc = Document::open(b"1,2\n=A1*B1,\n".to_vec(), &OpenOptions::named("t.csv")).expect("opens as csv");
    assert_eq!(number(&doc, "A2"), 2.0);
}

#[test]
fn a_save_to_bytes_is_read_back_alike_by_libreoffice() {
    let doc = chamfer_at_30_degrees();
    let saved = doc.save_as(SaveFormat::Xlsx).expect("saves");
    assert!(saved.losses.is_empty(), "{:?}", saved.losses);

    // The bytes read back through the document give the same values …
    let again = Document::open(saved.bytes().to_vec(), &OpenOptions::named("again.xlsx")).expect("reads back");
    assert_eq!(number(&again, "Outer!G6"), number(&doc, "Outer!G6"));

    // … and so does LibreOffice, recomputing every formula of the saved file itself.
    let Some(soffice) = soffice() else {
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let ours = dir.path().join("edited.xlsx");
    std::fs::write(&ours, saved.bytes()).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let profile = recalculating_profile(&dir.path().join("profile"));
    libreoffice_convert(&soffice, &profile, &[ours], &out);
    let theirs: PathBuf = out.join("edited.xlsx");
    let mut book: Xlsx<_> = open_workbook(&theirs).expect("LibreOffice wrote the workbook");
    let outer = book.worksheet_range("Outer").expect("sheet Outer");
    let at = |cell: &str| {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        match outer.get_value((pos.row, pos.col)) {
            Some(Data::Float(n)) => *n,
            other => panic!("LibreOffice's {cell} is {other:?}"),
        }
    };
    assert!((at("G6") - XA_30).abs() < 1e-9, "LibreOffice's XA {}", at("G6"));
    assert!((at("G8") - XB_30).abs() < 1e-9, "LibreOffice's XB {}", at("G8"));
}

/// A one-sheet workbook in the 1900 or the 1904 date system, as a document opened from the
/// bytes of its saved file; its cells read the date 2024-01-01 and the serial 45000.
fn dated(date_1904: bool) -> Document {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    wb.set_date_1904(date_1904);
    let at = |c: &str| ncsheet::formula::address::parse_cell(c).unwrap();
    for (cell, input) in [("A1", "=DATE(2024,1,1)"), ("A2", "=TEXT(A1,\"yyyy-mm-dd\")"), ("A3", "=YEAR(45000)")] {
        wb.set_input(0, at(cell), input).unwrap();
    }
    let mut layout = ncsheet::io::xlsx::Layout::default();
    layout.sheets.entry("Sheet1".into()).or_default().look.number_formats.insert(at("A1"), "yyyy-mm-dd".into());
    let name = Path::new("dated.xlsx");
    let origin = ncsheet::io::Origin::New;
    let bytes = ncsheet::io::encode_save(&wb, Some(&layout), &origin, name).unwrap().into_bytes();
    Document::open(bytes, &OpenOptions::named(name)).unwrap()
}

fn text(doc: &Document, cell: &str) -> String {
    let (sheet, pos) = doc.cell(cell).unwrap();
    doc.workbook().value(sheet, pos).to_string()
}

#[test]
fn a_1900_and_a_1904_workbook_interleaved_on_one_thread_keep_their_own_dates() {
    // Excel: 2024-01-01 is serial 45292 in the 1900 system and 1,462 days less in the 1904
    // one; serial 45000 is 2023-03-15 (1900) or 2027-03-16 (1904).
    let (mut old, mut new) = (dated(true), dated(false));
    for round in 0..3 {
        let (sheet, b1) = old.cell("B1").unwrap();
        old.set(sheet, b1, &format!("=A1+{round}")).unwrap();
        let (sheet, b1) = new.cell("B1").unwrap();
        new.set(sheet, b1, &format!("=A1+{round}")).unwrap();
        assert_eq!((number(&old, "A1"), number(&new, "A1")), (43830.0, 45292.0));
        assert_eq!((text(&old, "A2"), text(&new, "A2")), ("2024-01-01".to_string(), "2024-01-01".to_string()));
        assert_eq!((number(&old, "A3"), number(&new, "A3")), (2027.0, 2023.0));
        // Shown as a date, each in its own system, whichever was evaluated last.
        let (sheet, a1) = old.cell("A1").unwrap();
        assert_eq!((old.shown(sheet, a1), new.shown(sheet, a1)), ("2024-01-01".into(), "2024-01-01".into()));
        assert_eq!(number(&old, "B1"), 43830.0 + f64::from(round));
    }
}

#[test]
fn two_documents_keep_their_own_fixed_clocks() {
    let clocked = |serial: f64| {
        let mut settings = ncsheet::eval::Settings::seeded(1);
        settings.clock = Some(serial);
        let options = OpenOptions { settings: Some(settings), ..OpenOptions::named("clock.csv") };
        Document::open(b"=NOW(),=TODAY(),=RAND()\n".to_vec(), &options).unwrap()
    };
    // 2024-01-01 12:00 and 2027-03-16 06:00.
    let (a, b) = (clocked(45292.5), clocked(46462.25));
    assert_eq!((number(&a, "A1"), number(&a, "B1")), (45292.5, 45292.0));
    assert_eq!((number(&b, "A1"), number(&b, "B1")), (46462.25, 46462.0));
    // The same seed draws the same number in each document, whatever the other drew.
    assert_eq!(number(&a, "C1"), number(&b, "C1"));
}
