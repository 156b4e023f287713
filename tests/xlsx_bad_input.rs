//! Bad xlsx input gives a clear error naming the file and the part, never a panic. The
//! fixtures are made here: a good workbook from our writer, then broken on purpose.

mod common;

use std::io::{Cursor, Read, Write};
use std::path::Path;

use ncsheet::formula::address::{parse_cell, parse_rect};
use ncsheet::io::xlsx::{self, ErrorKind, Layout, XlsxError};
use ncsheet::workbook::Workbook;

const FILE: &str = "parts.xlsx";

fn good_workbook() -> Vec<u8> {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Second").unwrap();
    for (cell, input) in [("A1", "2"), ("A2", "=A1*3"), ("B1", "text"), ("B2", "=CONCAT(B1,\"!\")")] {
        wb.set_input(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    wb.set_input(1, parse_cell("C3").unwrap(), "=Sheet1!A2+1").unwrap();
    xlsx::to_bytes(&wb, &Layout::default()).unwrap()
}

/// The package with `part` replaced (or added).
fn with_part(package: &[u8], part: &str, content: &[u8]) -> Vec<u8> {
    let options = zip::write::SimpleFileOptions::default();
    let mut replaced = false;
    let mut out = common::rewrite_package(package, options, &mut |name, data| {
        if name != part {
            return data;
        }
        replaced = true;
        content.to_vec()
    });
    if !replaced {
        out.start_file(part, options).unwrap();
        out.write_all(content).unwrap();
    }
    out.finish().unwrap().into_inner()
}

fn part(package: &[u8], part: &str) -> String {
    let mut zip = zip::ZipArchive::new(Cursor::new(package)).unwrap();
    let mut text = String::new();
    zip.by_name(part).unwrap().read_to_string(&mut text).unwrap();
    text
}

fn load_err(bytes: &[u8]) -> XlsxError {
    match xlsx::load_bytes(bytes, Path::new(FILE)) {
        Ok(_) => panic!("loaded a broken file"),
        Err(e) => e,
    }
}

/// A sheet part with the given `<sheetData>` content.
fn sheet_xml(dimension: &str, data: &str) -> Vec<u8> {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>
<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><dimension ref="{dimension}"/><sheetData>{data}</sheetData></worksheet>"#
    )
    .into_bytes()
}

/// A minimal OLE compound file (version 3) whose directory holds one stream named `stream`,
/// the container of both an .xls workbook and a password-encrypted xlsx.
fn compound_file(stream: &str) -> Vec<u8> {
    const END: u32 = 0xFFFF_FFFE;
    const FREE: u32 = 0xFFFF_FFFF;
    let mut header = vec![0u8; 512];
    header[..8].copy_from_slice(&[0xD0, 0xCF, 0x11, 0xE0, 0xA1, 0xB1, 0x1A, 0xE1]);
    let put16 = |b: &mut Vec<u8>, at: usize, v: u16| b[at..at + 2].copy_from_slice(&v.to_le_bytes());
    let put32 = |b: &mut Vec<u8>, at: usize, v: u32| b[at..at + 4].copy_from_slice(&v.to_le_bytes());
    put16(&mut header, 24, 0x3E);
    put16(&mut header, 26, 3);
    put16(&mut header, 28, 0xFFFE);
    put16(&mut header, 30, 9);
    put16(&mut header, 32, 6);
    put32(&mut header, 44, 1); // one FAT sector
    put32(&mut header, 48, 1); // directory in sector 1
    put32(&mut header, 56, 4096);
    put32(&mut header, 60, END);
    put32(&mut header, 68, END);
    for i in 0..109 {
        put32(&mut header, 76 + 4 * i, if i == 0 { 0 } else { FREE });
    }
    let mut fat = vec![0xFFu8; 512];
    put32(&mut fat, 0, 0xFFFF_FFFD);
    put32(&mut fat, 4, END);
    let mut dir = vec![0u8; 512];
    for (i, (name, kind)) in [("Root Entry", 5u8), (stream, 2u8)].iter().enumerate() {
        let base = i * 128;
        let utf16: Vec<u8> = name.encode_utf16().chain([0]).flat_map(|c| c.to_le_bytes()).collect();
        dir[base..base + utf16.len()].copy_from_slice(&utf16);
        put16(&mut dir, base + 64, utf16.len() as u16);
        dir[base + 66] = *kind;
        put32(&mut dir, base + 116, END);
    }
    [header, fat, dir].concat()
}

#[test]
fn the_good_workbook_loads() {
    let imported = xlsx::load_bytes(&good_workbook(), Path::new(FILE)).unwrap();
    assert_eq!(imported.workbook.sheet_names(), vec!["Sheet1", "Second"]);
    assert_eq!(imported.workbook.value(1, parse_cell("C3").unwrap()), ncsheet::eval::Value::Number(7.0));
}

#[test]
fn a_truncated_package_is_not_an_xlsx() {
    let good = good_workbook();
    let e = load_err(&good[..good.len() / 2]);
    assert_eq!(e.kind, ErrorKind::NotXlsx, "{e}");
    assert!(e.to_string().starts_with("parts.xlsx: "), "{e}");
}

#[test]
fn a_file_that_is_not_a_zip_package_says_so() {
    let e = load_err(b"a,b\n1,2\n");
    assert_eq!(e.to_string(), "parts.xlsx: not an xlsx file (not a zip package)");
    let e = load_err(b"");
    assert_eq!(e.to_string(), "parts.xlsx: the file is empty");
}

#[test]
fn a_missing_file_names_it() {
    let e = xlsx::load(Path::new("/nonexistent/parts.xlsx")).err().expect("no such file");
    assert_eq!(e.kind, ErrorKind::Io);
    assert!(e.to_string().starts_with("/nonexistent/parts.xlsx: cannot read: "), "{e}");
}

#[test]
fn broken_sheet_xml_names_the_part() {
    let good = good_workbook();
    let sheet = "xl/worksheets/sheet1.xml";
    // Cut off in the middle of the cells.
    let text = part(&good, sheet);
    let cut = text.find("<c r=\"A2\"").unwrap();
    let e = load_err(&with_part(&good, sheet, &text.as_bytes()[..cut]));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(sheet)), "{e}");
    assert!(e.to_string().starts_with("parts.xlsx: xl/worksheets/sheet1.xml: "), "{e}");
    // A number that is not one.
    let bad = sheet_xml("A1", r#"<row r="1"><c r="A1" t="n"><v>12,5</v></c></row>"#);
    let e = load_err(&with_part(&good, sheet, &bad));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(sheet)), "{e}");
    // A missing part.
    let rels = part(&good, "xl/_rels/workbook.xml.rels").replace("worksheets/sheet2.xml", "worksheets/gone.xml");
    let e = load_err(&with_part(&good, "xl/_rels/workbook.xml.rels", rels.as_bytes()));
    assert_eq!(e.to_string(), "parts.xlsx: xl/worksheets/gone.xml: missing from the package");
}

#[test]
fn an_encrypted_workbook_asks_for_the_password_to_be_removed() {
    let e = load_err(&compound_file("EncryptedPackage"));
    assert_eq!(e.kind, ErrorKind::Encrypted, "{e}");
    assert!(e.to_string().contains("encrypted with a password"), "{e}");
}

#[test]
fn an_xls_workbook_asks_to_be_saved_as_xlsx() {
    let e = load_err(&compound_file("Workbook"));
    assert_eq!(e.kind, ErrorKind::LegacyXls, "{e}");
    assert!(e.to_string().contains("save it as .xlsx"), "{e}");
}

#[test]
fn a_huge_declared_dimension_allocates_nothing() {
    let good = good_workbook();
    let sheet = "xl/worksheets/sheet1.xml";
    let xml = sheet_xml(
        "A1:XFD1048576",
        r#"<row r="1"><c r="A1"><v>1</v></c></row><row r="1048576"><c r="XFD1048576"><v>2</v></c></row>"#,
    );
    let imported = xlsx::load_bytes(&with_part(&good, sheet, &xml), Path::new(FILE)).unwrap();
    let wb = &imported.workbook;
    assert_eq!(wb.used_rect(0), parse_rect("A1:XFD1048576"));
    assert_eq!(wb.value(0, parse_cell("XFD1048576").unwrap()), ncsheet::eval::Value::Number(2.0));
}

#[test]
fn cells_off_the_sheet_or_too_far_apart_are_refused() {
    let good = good_workbook();
    let sheet = "xl/worksheets/sheet1.xml";
    let off = sheet_xml("A1", r#"<row r="1048577"><c r="A1048577"><v>1</v></c></row>"#);
    let e = load_err(&with_part(&good, sheet, &off));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(sheet)), "{e}");

    // One cell in the last row of each of 200 columns: 200 full columns of grid.
    let mut row = String::from(r#"<row r="1048576">"#);
    for col in 0..200 {
        row.push_str(&format!(r#"<c r="{}1048576"><v>1</v></c>"#, ncsheet::formula::address::column_name(col)));
    }
    row.push_str("</row>");
    let e = load_err(&with_part(&good, sheet, &sheet_xml("A1", &row)));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::TooLarge, Some(sheet)), "{e}");
}

#[test]
fn damaged_parts_never_panic() {
    let good = good_workbook();
    for name in ["xl/worksheets/sheet1.xml", "xl/workbook.xml", "xl/sharedStrings.xml", "xl/styles.xml"] {
        let text = part(&good, name).into_bytes();
        for cut in (0..text.len()).step_by(9) {
            // Cut short, and with one byte changed: each must load or fail, not panic.
            let _ = xlsx::load_bytes(&with_part(&good, name, &text[..cut]), Path::new(FILE));
            let mut changed = text.clone();
            changed[cut] = b"<>\"'&=/ x"[cut % 9];
            let _ = xlsx::load_bytes(&with_part(&good, name, &changed), Path::new(FILE));
        }
    }
    for cut in (0..good.len()).step_by(97) {
        let mut changed = good.clone();
        changed[cut] ^= 0x5A;
        let _ = xlsx::load_bytes(&changed, Path::new(FILE));
    }
}

#[test]
fn a_damaged_workbook_part_is_named() {
    let good = good_workbook();
    for name in ["xl/sharedStrings.xml", "xl/styles.xml", "xl/workbook.xml"] {
        let text = part(&good, name);
        let cut = text.len() - 20;
        let e = load_err(&with_part(&good, name, &text.as_bytes()[..cut]));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(name)), "{e}");
        assert!(e.to_string().starts_with(&format!("parts.xlsx: {name}: ")), "{e}");
    }
}

/// A part whose root is another element (well-formed, so the check above passes it): calamine
/// reads to the end looking for `</styleSheet>` and said "Unexpected end of xml, expecting
/// '</styleSheet>'" naming no part (issue 30). The error now names the part.
#[test]
fn a_part_whose_root_is_another_element_is_named() {
    let good = good_workbook();
    for (name, root) in [("xl/styles.xml", "styleSheet"), ("xl/sharedStrings.xml", "sst")] {
        let e = load_err(&with_part(&good, name, b"<?xml version=\"1.0\"?><notThePart/>"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(name)), "{e}");
        assert!(e.to_string().contains(&format!("</{root}>")), "{e}");
    }
}

/// An entity XML does not define is a well-formedness error (Excel refuses such a part too);
/// calamine's own message for it names no part.
#[test]
fn an_undefined_entity_in_the_strings_names_its_part() {
    let good = good_workbook();
    let name = "xl/sharedStrings.xml";
    let spoiled = part(&good, name).replacen("<t>", "<t>&bogus;", 1);
    let e = load_err(&with_part(&good, name, spoiled.as_bytes()));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(name)), "{e}");
    assert!(e.to_string().contains("unknown entity &bogus;"), "{e}");
}

#[test]
fn a_cell_pointing_past_the_string_table_names_the_cell() {
    let good = good_workbook();
    let sheet = "xl/worksheets/sheet1.xml";
    let xml = sheet_xml("A1", r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1" t="s"><v>99</v></c></row>"#);
    let e = load_err(&with_part(&good, sheet, &xml));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(sheet)), "{e}");
    assert!(e.to_string().contains("cell B1: shared string '99' is not in the table"), "{e}");
}

/// `package` with a second entry `name` holding `content`, after the first. The zip writer
/// refuses two entries of one name, so the entry is written under a stand-in name of the
/// same length and renamed in its local and central headers.
fn with_second_entry(package: &[u8], name: &str, content: &[u8]) -> Vec<u8> {
    let stand_in = format!("{}#", &name[..name.len() - 1]);
    with_raw_name(&with_part(package, &stand_in, content), &stand_in, name.as_bytes())
}

/// `package` with its entry `stand_in` renamed `raw` (as many bytes) in its local and central
/// headers, bytes the zip writer would not write (a second name, a name outside UTF-8).
fn with_raw_name(package: &[u8], stand_in: &str, raw: &[u8]) -> Vec<u8> {
    let mut out = package.to_vec();
    let mut renamed = 0;
    for at in 0..package.len() - stand_in.len() {
        if &package[at..at + stand_in.len()] == stand_in.as_bytes() {
            out[at..at + raw.len()].copy_from_slice(raw);
            renamed += 1;
        }
    }
    assert_eq!(renamed, 2, "the stand-in names one local and one central header");
    out
}

/// A zip entry name without the UTF-8 flag (bit 11) is CP437 (APPNOTE 4.4.4, appendix D):
/// `\x8e.png` is "Ä.png" and `\x99.png` is "Ö.png", two names that are not equal as
/// case-insensitive ASCII ([M1.12]), so the package holds no equivalent part names. They were
/// refused as one: both decoded lossily to "\u{fffd}.png".
#[test]
fn entry_names_outside_utf8_that_differ_are_not_taken_for_one() {
    let good = good_workbook();
    let (first, second) = ("xl/media/A.png", "xl/media/B.png");
    let with_both = with_part(&with_part(&good, first, b"one"), second, b"two");
    let renamed = with_raw_name(&with_raw_name(&with_both, first, b"xl/media/\x8e.png"), second, b"xl/media/\x99.png");
    let names: Vec<Vec<u8>> =
        zip::ZipArchive::new(Cursor::new(&renamed)).unwrap().file_names_raw().map(<[u8]>::to_vec).collect();
    assert!(names.contains(&b"xl/media/\x8e.png".to_vec()) && names.contains(&b"xl/media/\x99.png".to_vec()));
    let loaded = xlsx::load_bytes(&renamed, Path::new(FILE));
    assert!(loaded.is_ok(), "{:?}", loaded.err().map(|e| e.to_string()));
}

/// ECMA-376 Part 2 (Open Packaging Conventions), part names: "Packages shall not contain
/// equivalent part names and package implementers shall neither create nor recognize packages
/// with equivalent part names" [M1.12], equivalence being "case-insensitive ASCII"; and a
/// segment holds a non-dot character [M1.10]. Readers disagree on which of two equal entries
/// counts: ncsheet read the last one and a save carried both (issue 30). Each is refused
/// naming the entry.
#[test]
fn a_package_with_two_entries_of_one_part_name_is_refused_naming_it() {
    let good = good_workbook();
    let sheet = "xl/worksheets/sheet1.xml";
    let other = part(&good, sheet).replace("<v>2</v>", "<v>777</v>");
    for (name, what) in [
        (sheet, "two entries of this name"),
        ("xl/sharedStrings.xml", "two entries of this name"),
        ("[Content_Types].xml", "two entries of this name"),
    ] {
        let content = if name == sheet { other.clone().into_bytes() } else { part(&good, name).into_bytes() };
        let e = load_err(&with_second_entry(&good, name, &content));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(name)), "{e}");
        assert!(e.to_string().contains(what), "{e}");
    }
    let e = load_err(&with_part(&good, "XL/Worksheets/Sheet1.xml", other.as_bytes()));
    assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some("XL/Worksheets/Sheet1.xml")), "{e}");
    assert!(e.to_string().contains(&format!("also holds '{sheet}'")), "{e}");
    for name in ["../evil.xml", "xl/../../evil.xml", "xl/./styles2.xml"] {
        let e = load_err(&with_part(&good, name, b"<x/>"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(name)), "{e}");
        assert!(e.to_string().contains("'..' segment"), "{e}");
    }
}
