//! Hostile .xls, .xlsb and .ods files (issue 30 applied to the readers of issue 29): records
//! cut short or past the sheet's edge, names whose tokens a library does not know, cells far
//! apart, and fuzz targets mutating small vendored files (bytes flipped, parts cut short,
//! records given other lengths or huge counts, zip entries removed). Each file is either
//! read or refused with an error naming the file, never a panic, an abort or a hang.
//!
//! The fuzz cases come from the fixed seed of `common::fuzz` (CI runs the same ones);
//! `PROPTEST_CASES=N` runs more locally.

mod common;

use std::io::{Cursor, Read, Write};
use std::path::{Path, PathBuf};

use proptest::prelude::*;

use common::fuzz::{config, mutated};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::io::{self, Format};

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(path)
}

fn vendored(path: &str) -> Vec<u8> {
    std::fs::read(data(path)).unwrap()
}

/// Opens `bytes` as a file of `format`: the workbook, or the error as the user reads it.
fn open(bytes: Vec<u8>, format: Format) -> Result<io::Opened, String> {
    let name = match format {
        Format::Xls => "hostile.xls",
        Format::Xlsb => "hostile.xlsb",
        _ => "hostile.ods",
    };
    io::open_bytes(bytes, Path::new(name), format, None).map_err(|e| e.to_string())
}

// ---------------------------------------------------------------------------------------
// .xlsb records ([MS-XLSB] 2.1.4): a type and a length, each 7 bits a byte with the high
// bit saying another byte follows (2 bytes at most for the type, 4 for the length).

/// A record's type and body.
type Record = (u16, Vec<u8>);

fn records(part: &[u8]) -> Vec<Record> {
    let mut out = Vec::new();
    let mut at = 0;
    let varint = |at: &mut usize, most: usize| {
        let mut value = 0usize;
        for i in 0..most {
            let byte = part[*at];
            *at += 1;
            value |= usize::from(byte & 0x7F) << (7 * i);
            if byte & 0x80 == 0 {
                break;
            }
        }
        value
    };
    while at < part.len() {
        let kind = varint(&mut at, 2) as u16;
        let len = varint(&mut at, 4);
        out.push((kind, part[at..at + len].to_vec()));
        at += len;
    }
    out
}

fn varint(mut value: usize, out: &mut Vec<u8>) {
    loop {
        let byte = (value & 0x7F) as u8;
        value >>= 7;
        if value == 0 {
            out.push(byte);
            return;
        }
        out.push(byte | 0x80);
    }
}

fn encode(records: &[(u16, Vec<u8>)]) -> Vec<u8> {
    let mut out = Vec::new();
    for (kind, body) in records {
        varint(usize::from(*kind), &mut out);
        varint(body.len(), &mut out);
        out.extend_from_slice(body);
    }
    out
}

/// `package` with each entry `change` returns `Some` for replaced by it (`None` keeps it),
/// every entry stored uncompressed; `drop` is left out.
/// A change of a package entry by name and bytes: `Some` replaces it.
type EntryChange<'a> = &'a mut dyn FnMut(&str, &[u8]) -> Option<Vec<u8>>;

fn rewrite(package: &[u8], drop: Option<&str>, change: EntryChange) -> Vec<u8> {
    let mut zip = zip::ZipArchive::new(Cursor::new(package)).unwrap();
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).unwrap();
        let name = entry.name().unwrap().to_string();
        if Some(name.as_str()) == drop {
            continue;
        }
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        let bytes = change(&name, &bytes).unwrap_or(bytes);
        out.start_file(name.as_str(), options).unwrap();
        out.write_all(&bytes).unwrap();
    }
    out.finish().unwrap().into_inner()
}

/// `package` with the records of `part` changed by `change`.
fn with_records(package: &[u8], part: &str, change: impl Fn(&mut Vec<(u16, Vec<u8>)>)) -> Vec<u8> {
    rewrite(package, None, &mut |name, bytes| {
        (name == part).then(|| {
            let mut list = records(bytes);
            change(&mut list);
            encode(&list)
        })
    })
}

fn wide(text: &str) -> Vec<u8> {
    let units: Vec<u16> = text.encode_utf16().collect();
    let mut out = (units.len() as u32).to_le_bytes().to_vec();
    units.iter().for_each(|u| out.extend_from_slice(&u.to_le_bytes()));
    out
}

const BRT_NAME: u16 = 0x0027;
const BRT_BUNDLE_SH: u16 = 0x009C;
const BRT_EXTERN_SHEET: u16 = 0x016A;
const BRT_ROW_HDR: u16 = 0x0000;
const BRT_CELL_REAL: u16 = 0x0005;
const BRT_CELL_ISST: u16 = 0x0007;
const BRT_END_SHEET_DATA: u16 = 0x0092;

/// A PtgArea3d ([MS-XLSB] 2.5.98.20) through XTI `ixti`: rows and columns absolute.
fn area3d(ixti: u16, rows: (u32, u32), cols: (u16, u16)) -> Vec<u8> {
    let mut out = vec![0x3B];
    out.extend_from_slice(&ixti.to_le_bytes());
    for n in [rows.0, rows.1] {
        out.extend_from_slice(&n.to_le_bytes());
    }
    for n in [cols.0, cols.1] {
        out.extend_from_slice(&n.to_le_bytes());
    }
    out
}

/// A workbook name ([MS-XLSB] 2.4.711 BrtName) holding `rgce` and `extra`.
fn name_record(name: &str, rgce: &[u8], extra: &[u8]) -> Vec<u8> {
    let mut out = vec![0, 0, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF];
    out.extend(wide(name));
    out.extend_from_slice(&(rgce.len() as u32).to_le_bytes());
    out.extend_from_slice(rgce);
    out.extend_from_slice(&(extra.len() as u32).to_le_bytes());
    out.extend_from_slice(extra);
    out.extend_from_slice(&[0xFF; 4]); // no comment
    out
}

/// calamine refused a whole .xlsb over a defined name whose tokens it did not know: a union
/// kept as PtgMemArea ([MS-XLSB] 2.5.98.63: its cached rectangles in the extra data) before
/// the two areas and PtgUnion. The workbook opens, the name read from its tokens.
#[test]
fn an_xlsb_whose_name_holds_a_union_opens_with_the_name() {
    let good = vendored("xlsb/defined_names.xlsb");
    // XTI 0 of this file is its first sheet, NamedCells.
    let mut union = area3d(0, (0, 1), (0, 0));
    union.extend(area3d(0, (0, 1), (2, 3)));
    union.push(0x10);
    let mut rgce = vec![0x26, 0, 0, 0, 0];
    rgce.extend_from_slice(&(union.len() as u16).to_le_bytes());
    rgce.extend(union);
    let mut extra = 2u32.to_le_bytes().to_vec();
    for rect in [[0u32, 1, 0, 0], [0, 1, 2, 3]] {
        rect.iter().for_each(|n| extra.extend_from_slice(&n.to_le_bytes()));
    }
    let bytes = with_records(&good, "xl/workbook.bin", |list| {
        let at = list.iter().position(|(kind, _)| *kind == BRT_NAME).unwrap();
        list.insert(at, (BRT_NAME, name_record("Both", &rgce, &extra)));
    });
    let opened = open(bytes, Format::Xlsb).unwrap();
    let names = opened.workbook.names();
    let both = names.iter().find(|(n, ..)| n == "Both").expect("the name is read");
    // The union of the two areas, in parentheses as a formula writes a union.
    assert_eq!(both.1, "=(NamedCells!$A$1:$A$2,NamedCells!$C$1:$D$2)");
    assert!(names.iter().any(|(n, ..)| n == "NC_1"), "the file's own names are read too");
}

/// The row and column of a cell record, then its value.
fn cell_real(col: u32, value: f64) -> Vec<u8> {
    let mut body = col.to_le_bytes().to_vec();
    body.extend_from_slice(&[0; 4]);
    body.extend_from_slice(&value.to_le_bytes());
    body
}

/// `package`'s first sheet with `extra` records put before its BrtEndSheetData.
fn with_cells(package: &[u8], extra: Vec<(u16, Vec<u8>)>) -> Vec<u8> {
    with_records(package, "xl/worksheets/sheet1.bin", move |list| {
        let end = list.iter().position(|(kind, _)| *kind == BRT_END_SHEET_DATA).unwrap();
        list.splice(end..end, extra.clone());
    })
}

/// calamine built each sheet as one dense block: a cell at A1 and one at XFD1048576 asked
/// for 17 billion slots and aborted. Both are read where they are.
#[test]
fn an_xlsb_with_cells_at_both_corners_of_the_sheet_opens() {
    let good = vendored("xlsb/IS_INFORMATION.xlsb");
    let far = vec![(BRT_ROW_HDR, vec![0xFF, 0xFF, 0x0F, 0, 0, 0, 0, 0]), (BRT_CELL_REAL, cell_real(0x3FFF, 7.5))];
    let opened = open(with_cells(&good, far), Format::Xlsb).unwrap();
    assert_eq!(opened.workbook.value(0, parse_cell("XFD1048576").unwrap()), Value::Number(7.5));
}

/// Records calamine indexed without checking (it panicked) and records this reader must
/// not read as something else: each refuses the file, naming the part and the record.
#[test]
fn damaged_xlsb_records_are_refused_naming_the_part_and_the_record() {
    let good = vendored("xlsb/IS_INFORMATION.xlsb");
    let refusal = |bytes: Vec<u8>| open(bytes, Format::Xlsb).err().expect("refused");
    let workbook = |change: &dyn Fn(&mut Vec<Record>)| with_records(&good, "xl/workbook.bin", change);

    // A sheet naming a relationship the rels part does not hold.
    let error = refusal(workbook(&|list| {
        let (_, body) = list.iter_mut().find(|(kind, _)| *kind == BRT_BUNDLE_SH).unwrap();
        let mut renamed = body[..8].to_vec();
        renamed.extend(wide("rId99"));
        renamed.extend(wide("Lost"));
        *body = renamed;
    }));
    assert!(error.contains("hostile.xlsb") && error.contains("xl/workbook.bin") && error.contains("BrtBundleSh"));
    assert!(error.contains("rId99"), "{error}");

    // A sheet's record cut inside its relationship's id.
    let error = refusal(workbook(&|list| {
        let (_, body) = list.iter_mut().find(|(kind, _)| *kind == BRT_BUNDLE_SH).unwrap();
        body.truncate(13);
    }));
    assert!(error.contains("BrtBundleSh") && error.contains("cut short"), "{error}");

    // The list of XTIs saying more than it holds (calamine read past its last one).
    let error = refusal(workbook(&|list| {
        let xti = [0u8; 12];
        let mut body = 3u32.to_le_bytes().to_vec();
        body.extend_from_slice(&xti);
        body.extend_from_slice(&xti[..6]);
        match list.iter_mut().find(|(kind, _)| *kind == BRT_EXTERN_SHEET) {
            Some(record) => record.1 = body,
            None => {
                let at = list.iter().position(|(kind, _)| *kind == BRT_BUNDLE_SH).unwrap() + 1;
                list.insert(at, (BRT_EXTERN_SHEET, body));
            }
        }
    }));
    assert!(error.contains("xl/workbook.bin") && error.contains("BrtExternSheet"), "{error}");

    // A cell naming a shared string past the table, a number cut short, a column past XFD.
    let isst = vec![(BRT_CELL_ISST, [0u32, 0, 1_000_000].iter().flat_map(|n| n.to_le_bytes()).collect())];
    let error = refusal(with_cells(&good, isst));
    assert!(error.contains("xl/worksheets/sheet1.bin") && error.contains("shared string 1000000"), "{error}");
    let short = vec![(BRT_CELL_REAL, cell_real(1, 2.0)[..12].to_vec())];
    let error = refusal(with_cells(&good, short));
    assert!(error.contains("xl/worksheets/sheet1.bin") && error.contains("cut short"), "{error}");
    let wide_col = vec![(BRT_CELL_REAL, cell_real(16_384, 2.0))];
    let error = refusal(with_cells(&good, wide_col));
    assert!(error.contains("column 16385"), "{error}");

    // The sheet's part missing from the package.
    let error = refusal(rewrite(&good, Some("xl/worksheets/sheet1.bin"), &mut |_, _| None));
    assert!(error.contains("xl/worksheets/sheet1.bin") && error.contains("missing"), "{error}");
}

/// An .ods package of one sheet whose rows are `rows` (content.xml's table rows).
fn ods_with_rows(rows: &str) -> Vec<u8> {
    ods_of(&format!(r#"<table:table table:name="S">{rows}</table:table>"#))
}

/// An .ods package whose spreadsheet (content.xml's `office:spreadsheet`) holds `body`.
fn ods_of(body: &str) -> Vec<u8> {
    let content = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?><office:document-content xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" xmlns:text="urn:oasis:names:tc:opendocument:xmlns:text:1.0" office:version="1.2"><office:body><office:spreadsheet>{body}</office:spreadsheet></office:body></office:document-content>"#
    );
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let stored = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    out.start_file("mimetype", stored).unwrap();
    out.write_all(b"application/vnd.oasis.opendocument.spreadsheet").unwrap();
    out.start_file("content.xml", zip::write::SimpleFileOptions::default()).unwrap();
    out.write_all(content.as_bytes()).unwrap();
    out.start_file("META-INF/manifest.xml", stored).unwrap();
    out.write_all(br#"<?xml version="1.0" encoding="UTF-8"?><manifest:manifest xmlns:manifest="urn:oasis:names:tc:opendocument:xmlns:manifest:1.0" manifest:version="1.2"><manifest:file-entry manifest:full-path="/" manifest:media-type="application/vnd.oasis.opendocument.spreadsheet"/><manifest:file-entry manifest:full-path="content.xml" manifest:media-type="text/xml"/></manifest:manifest>"#).unwrap();
    out.finish().unwrap().into_inner()
}

const ODS_ONE: &str = r#"<table:table-row><table:table-cell office:value-type="float" office:value="1"><text:p>1</text:p></table:table-cell></table:table-row>"#;

/// calamine holds an .ods sheet whole from its first used cell to its last and copies a
/// repeated cell's text for each repeat: cells at A1 and XFD6000 (98 million slots), a long
/// text repeated a million times, `<text:s text:c="N"/>` of four billion spaces aborted.
/// Each is refused naming the sheet and the limit; the small file still opens.
#[test]
fn ods_sheets_calamine_would_hold_past_the_limits_are_refused_naming_the_sheet() {
    let opened = open(ods_with_rows(ODS_ONE), Format::Ods).unwrap();
    assert_eq!(opened.workbook.value(0, parse_cell("A1").unwrap()), Value::Number(1.0));

    let far = format!(
        r#"{ODS_ONE}<table:table-row table:number-rows-repeated="5998"><table:table-cell table:number-columns-repeated="16384"/></table:table-row><table:table-row><table:table-cell table:number-columns-repeated="16383"/><table:table-cell office:value-type="float" office:value="2"/></table:table-row>"#
    );
    let error = open(ods_with_rows(&far), Format::Ods).err().expect("refused");
    assert!(error.contains("hostile.ods") && error.contains("sheet 'S' spans 6000 rows and 16384 columns"), "{error}");
    assert!(error.contains("8388608"), "{error}");

    let text = "x".repeat(1000);
    let repeated = format!(
        r#"<table:table-row table:number-rows-repeated="1000"><table:table-cell table:number-columns-repeated="1000" office:value-type="string"><text:p>{text}</text:p></table:table-cell></table:table-row>"#
    );
    let error = open(ods_with_rows(&repeated), Format::Ods).err().expect("refused");
    assert!(error.contains("sheet 'S'") && error.contains("MiB of text"), "{error}");

    let spaces = r#"<table:table-row><table:table-cell office:value-type="string"><text:p>a<text:s text:c="4294967295"/>b</text:p></table:table-cell></table:table-row>"#;
    let error = open(ods_with_rows(spaces), Format::Ods).err().expect("refused");
    assert!(error.contains("MiB of text"), "{error}");
}

/// BIFF8's BoundSheet8 ([MS-XLS] 2.4.28): the stream offset of the sheet's BOF, its state
/// and type, its name (ShortXLUnicodeString, 8-bit).
fn bound_sheet(offset: u32, name: &str) -> Vec<u8> {
    let mut body = offset.to_le_bytes().to_vec();
    body.extend_from_slice(&[0, 0, name.len() as u8, 0]);
    body.extend_from_slice(name.as_bytes());
    body
}

/// Sheets whose records overlap (BoundSheet8 offsets pointing into one sheet) made the
/// reader read that sheet again for each: with thousands, quadratic time and the same cells
/// many times over. The file is refused naming the sheet.
#[test]
fn xls_sheets_whose_records_overlap_are_refused_naming_the_sheet() {
    const BOUND_SHEET: u16 = 0x0085;
    let good = vendored("excel-corpus/xls/testNames.xls");
    let bytes = common::vba::with_stream(&good, "/Workbook", |old| {
        let mut list = biff_records(old);
        let last = list.iter().rposition(|(kind, _)| *kind == BOUND_SHEET).unwrap();
        let sheet_offset = u32::from_le_bytes(list[last].1[..4].try_into().unwrap());
        let copy = |i: usize, offset: u32| (BOUND_SHEET, bound_sheet(offset, &format!("Copy{i}")));
        let delta: u32 = (0..200).map(|i| 4 + copy(i, 0).1.len() as u32).sum();
        // Every offset moves by the records put before the sheets.
        for (_, body) in list.iter_mut().filter(|(kind, _)| *kind == BOUND_SHEET) {
            let offset = u32::from_le_bytes(body[..4].try_into().unwrap()) + delta;
            body[..4].copy_from_slice(&offset.to_le_bytes());
        }
        let copies: Vec<(u16, Vec<u8>)> = (0..200).map(|i| copy(i, sheet_offset + delta)).collect();
        list.splice(last + 1..last + 1, copies);
        biff_encode(&list)
    });
    let error = open(bytes, Format::Xls).err().expect("refused");
    assert!(error.contains("hostile.xls") && error.contains("'Copy") && error.contains("overlap"), "{error}");
}

/// Damaged .xls cell records (issue 30): a record cut short was read with its missing fields
/// as 0, a formula whose length runs past its record as no formula, and a LabelSst naming a
/// string past the shared-string table as empty text, all silently. Each is refused naming
/// the sheet, the record ([MS-XLS] 2.4) and where it is in the Workbook stream.
#[test]
fn damaged_xls_cell_records_are_refused_naming_the_sheet_and_the_record() {
    const RK: u16 = 0x027E;
    const LABEL_SST: u16 = 0x00FD;
    const FORMULA: u16 = 0x0006;
    let good = vendored("excel-corpus/xls/testNames.xls");
    let damaged = |kind: u16, change: fn(&mut Vec<u8>)| {
        let bytes = common::vba::with_stream(&good, "/Workbook", |old| {
            let mut list = biff_records(old);
            let i = list.iter().position(|(k, _)| *k == kind).expect("the file holds the record");
            change(&mut list[i].1);
            biff_encode(&list)
        });
        open(bytes, Format::Xls).err().expect("refused")
    };
    let rk = damaged(RK, |body| body.truncate(8));
    assert!(rk.contains("hostile.xls") && rk.contains("sheet '") && rk.contains("record RK (0x027E) at byte "), "{rk}");
    assert!(rk.contains("cut short (8 bytes where 10 are needed)"), "{rk}");
    let past = damaged(LABEL_SST, |body| body[6..10].copy_from_slice(&u32::MAX.to_le_bytes()));
    assert!(past.contains("record LabelSst") && past.contains("names shared string 4294967295, past the"), "{past}");
    let formula = damaged(FORMULA, |body| body[20..22].copy_from_slice(&[0xFF, 0xFF]));
    assert!(formula.contains("record Formula (0x0006)") && formula.contains("cut short"), "{formula}");
}

// ---------------------------------------------------------------------------------------
// Fuzz targets.

/// A change of a package's entry: its bytes mutated, its records given other lengths or
/// huge counts, or the entry removed.
#[derive(Clone, Debug)]
enum Change {
    Bytes(Vec<(prop::sample::Index, u8)>, Option<prop::sample::Index>),
    /// The record's body cut to or padded with 0xFF to a length.
    RecordLength(prop::sample::Index, usize),
    /// The record's first bytes (its counts and lengths) all ones.
    HugeCounts(prop::sample::Index, usize),
    Remove,
}

fn change() -> impl Strategy<Value = Change> {
    let edits = prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8);
    prop_oneof![
        4 => (edits, prop::option::of(any::<prop::sample::Index>())).prop_map(|(e, c)| Change::Bytes(e, c)),
        2 => (any::<prop::sample::Index>(), 0usize..40).prop_map(|(i, n)| Change::RecordLength(i, n)),
        2 => (any::<prop::sample::Index>(), 1usize..16).prop_map(|(i, n)| Change::HugeCounts(i, n)),
        1 => Just(Change::Remove),
    ]
}

/// A record of `list` changed as `change` says.
fn change_record<T>(list: &mut [(T, Vec<u8>)], change: &Change) {
    if list.is_empty() {
        return;
    }
    match change {
        Change::RecordLength(i, len) => {
            let body = &mut list[i.index(list.len())].1;
            body.resize(*len, 0xFF);
        }
        Change::HugeCounts(i, n) => {
            let body = &mut list[i.index(list.len())].1;
            let n = (*n).min(body.len());
            body[..n].fill(0xFF);
        }
        _ => {}
    }
}

/// A zip package with one entry changed.
fn changed_package(good: &[u8], which: prop::sample::Index, change: &Change, xlsb: bool) -> Vec<u8> {
    let zip = zip::ZipArchive::new(Cursor::new(good)).unwrap();
    let names: Vec<String> = zip.file_names().map(|n| n.unwrap().to_string()).collect();
    let target = names[which.index(names.len())].clone();
    if let Change::Remove = change {
        return rewrite(good, Some(&target), &mut |_, _| None);
    }
    rewrite(good, None, &mut |name, bytes| {
        if name != target {
            return None;
        }
        Some(match change {
            Change::Bytes(edits, cut) => mutated(bytes.to_vec(), edits, *cut),
            _ if xlsb && target.ends_with(".bin") => {
                let mut list = records(bytes);
                change_record(&mut list, change);
                encode(&list)
            }
            // An XML part: its first attribute values made huge.
            _ => String::from_utf8_lossy(bytes).replacen("=\"1\"", "=\"4294967295\"", 8).into_bytes(),
        })
    })
}

/// BIFF8 records ([MS-XLS] 2.1.4): type and length, 2 bytes each.
fn biff_records(stream: &[u8]) -> Vec<(u16, Vec<u8>)> {
    let mut out = Vec::new();
    let mut at = 0;
    while at + 4 <= stream.len() {
        let kind = u16::from_le_bytes([stream[at], stream[at + 1]]);
        let len = usize::from(u16::from_le_bytes([stream[at + 2], stream[at + 3]]));
        let end = (at + 4 + len).min(stream.len());
        out.push((kind, stream[at + 4..end].to_vec()));
        at = end;
    }
    out
}

fn biff_encode(records: &[(u16, Vec<u8>)]) -> Vec<u8> {
    let mut out = Vec::new();
    for (kind, body) in records {
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&(body.len().min(0xFFFF) as u16).to_le_bytes());
        out.extend_from_slice(&body[..body.len().min(0xFFFF)]);
    }
    out
}

/// A compound file with its Workbook stream changed, or the file's own bytes mutated.
fn changed_xls(good: &[u8], change: &Change) -> Vec<u8> {
    match change {
        Change::Bytes(edits, cut) => mutated(good.to_vec(), edits, *cut),
        Change::Remove => common::vba::with_stream(good, "/Workbook", |old| old[..old.len() / 2].to_vec()),
        _ => common::vba::with_stream(good, "/Workbook", |old| {
            let mut list = biff_records(old);
            change_record(&mut list, change);
            biff_encode(&list)
        }),
    }
}

/// A workbook read from a hostile file is used as any other: its values, formulas and names.
fn exercise(opened: &io::Opened) {
    let wb = &opened.workbook;
    let _ = wb.names();
    let _ = wb.problems();
    for sheet in 0..wb.sheet_names().len() {
        let _ = wb.value(sheet as _, parse_cell("A1").unwrap());
    }
}

/// Reading `bytes` gives a workbook or an error naming the file.
fn reads_or_names_the_file(bytes: Vec<u8>, format: Format) {
    match open(bytes, format) {
        Ok(opened) => exercise(&opened),
        Err(error) => assert!(error.starts_with("hostile."), "{error}"),
    }
}

proptest! {
    #![proptest_config(config(60))]

    #[test]
    fn mutated_xlsb_files_never_panic(which in any::<prop::sample::Index>(), change in change()) {
        let good = vendored("xlsb/defined_names.xlsb");
        reads_or_names_the_file(changed_package(&good, which, &change, true), Format::Xlsb);
    }

    #[test]
    fn mutated_xls_files_never_panic(change in change()) {
        let good = vendored("excel-corpus/xls/testNames.xls");
        reads_or_names_the_file(changed_xls(&good, &change), Format::Xls);
    }

    #[test]
    fn mutated_ods_files_never_panic(which in any::<prop::sample::Index>(), change in change()) {
        let good = vendored("ods/defined_names.ods");
        reads_or_names_the_file(changed_package(&good, which, &change, false), Format::Ods);
    }
}

/// The fuzz targets reach past the first check: the files they mutate are read whole.
#[test]
fn the_fuzzed_files_start_readable() {
    for (path, format) in [
        ("xlsb/defined_names.xlsb", Format::Xlsb),
        ("excel-corpus/xls/testNames.xls", Format::Xls),
        ("ods/defined_names.ods", Format::Ods),
    ] {
        let opened = open(vendored(path), format).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert!(!opened.workbook.names().is_empty(), "{path}: its names are read");
    }
    // The application its SummaryInformation names, as olefile reads it.
    let xls = open(vendored("excel-corpus/xls/testNames.xls"), Format::Xls).unwrap();
    assert_eq!(xls.written_by.as_deref(), Some("Microsoft Excel"));
}

/// An .xlsb or .ods package holding two entries of one name is as ambiguous as an xlsx's
/// (ECMA-376 Part 2 [M1.12]; calamine reads the last): refused naming the entry. The second
/// entry is written under a stand-in name of the same length, then renamed in its headers.
#[test]
fn xlsb_and_ods_packages_with_two_entries_of_one_name_are_refused_naming_it() {
    let cases = [
        (vendored("xlsb/ROUND.xlsb"), Format::Xlsb, "xl/workbook.bin", "xl/workbook.bi#"),
        (ods_with_rows(ODS_ONE), Format::Ods, "content.xml", "content.xm#"),
    ];
    for (package, format, name, stand_in) in cases {
        let mut second = None;
        let mut written = rewrite(&package, None, &mut |entry, bytes| {
            if entry == name {
                second = Some(bytes.to_vec());
            }
            None
        });
        let mut zip = zip::ZipWriter::new_append(Cursor::new(&mut written)).unwrap();
        zip.start_file(stand_in, zip::write::SimpleFileOptions::default()).unwrap();
        zip.write_all(&second.unwrap()).unwrap();
        zip.finish().unwrap();
        let at: Vec<usize> = written
            .windows(stand_in.len())
            .enumerate()
            .filter(|(_, w)| *w == stand_in.as_bytes())
            .map(|(i, _)| i)
            .collect();
        assert_eq!(at.len(), 2, "one local and one central header");
        for i in at {
            written[i..i + name.len()].copy_from_slice(name.as_bytes());
        }
        let error = open(written, format).err().expect("refused");
        assert!(error.contains(&format!("{name}: the package holds two entries of this name")), "{error}");
    }
}

/// One cell holding the number 1.
const ODS_VALUE_CELL: &str =
    r#"<table:table-cell office:value-type="float" office:value="1"><text:p>1</text:p></table:table-cell>"#;

/// A value past the sheet's edge (column 16,385 after 16,384 repeated blanks, row 1,048,577
/// after 1,048,576 repeated rows) was dropped by calamine without a word: the file opened as
/// an empty sheet (issue 30). LibreOffice warns that such data could not be loaded completely;
/// ncsheet refuses the file naming the sheet and the place. The last row and column still open.
#[test]
fn ods_values_past_the_sheets_edge_are_refused_naming_the_place() {
    let blank_columns = r#"<table:table-cell table:number-columns-repeated="16384"/>"#;
    let past_columns = format!("<table:table-row>{blank_columns}{}</table:table-row>", ODS_VALUE_CELL);
    let error = open(ods_with_rows(&past_columns), Format::Ods).err().expect("refused");
    assert!(error.contains("content.xml: sheet 'S': a cell holding a value at row 1, column 16385"), "{error}");
    let blank_rows = r#"<table:table-row table:number-rows-repeated="1048576"><table:table-cell/></table:table-row>"#;
    let error = open(ods_with_rows(&format!("{blank_rows}{ODS_ONE}")), Format::Ods).err().expect("refused");
    assert!(error.contains("sheet 'S': a cell holding a value at row 1048577, column 1"), "{error}");

    let last_row = r#"<table:table-row table:number-rows-repeated="1048575"><table:table-cell/></table:table-row>"#;
    let opened = open(ods_with_rows(&format!("{last_row}{ODS_ONE}")), Format::Ods).unwrap();
    assert_eq!(opened.workbook.value(0, parse_cell("A1048576").unwrap()), Value::Number(1.0));
    let last_column = format!(
        r#"<table:table-row><table:table-cell table:number-columns-repeated="16383"/>{}</table:table-row>"#,
        ODS_VALUE_CELL
    );
    let opened = open(ods_with_rows(&last_column), Format::Ods).unwrap();
    assert_eq!(opened.workbook.value(0, parse_cell("XFD1").unwrap()), Value::Number(1.0));
}

/// A repeat count past the sheet's edge by far (2^64 - 1, the largest count a reader takes)
/// carried the place counted after it to the end of a u64: the error named "column
/// 18446744073709551615" (issue 30). The place is now the repeat the file holds: its count
/// and the row or column it starts at (here column 2 after a value in A1, and row 1).
#[test]
fn ods_repeats_far_past_the_edge_name_the_repeat_not_a_place_counted_past_it() {
    let past_columns = format!(
        r#"<table:table-row>{ODS_VALUE_CELL}<table:table-cell table:number-columns-repeated="18446744073709551615"/>{ODS_VALUE_CELL}</table:table-row>"#
    );
    let error = open(ods_with_rows(&past_columns), Format::Ods).err().expect("refused");
    assert!(
        error.contains("sheet 'S': a cell holding a value in row 1 lies past the last column of a sheet (16384)")
            && error.contains(r#"number-columns-repeated="18446744073709551615" from column 2"#),
        "{error}"
    );
    let past_rows = format!(
        r#"<table:table-row table:number-rows-repeated="18446744073709551615"><table:table-cell/></table:table-row>{ODS_ONE}"#
    );
    let error = open(ods_with_rows(&past_rows), Format::Ods).err().expect("refused");
    assert!(
        error.contains("sheet 'S': a cell holding a value lies past the last row of a sheet (1048576)")
            && error.contains(r#"number-rows-repeated="18446744073709551615" from row 1"#),
        "{error}"
    );
}

/// A cell or row without a repeat attribute that reached the last column or row was recorded
/// as the repeat that crossed the edge: a value beyond it was reported as lying past
/// `number-columns-repeated="1" from column 16384`, an attribute the file does not have.
/// Counted by hand: 16,383 repeated blanks fill columns 1-16,383, two single blanks columns
/// 16,384 and 16,385, so the value is column 16,386; 1,048,575 repeated rows, two single rows,
/// and the value's row is 1,048,578. No repeat crossed the edge, so the place alone is named.
#[test]
fn ods_single_cells_and_rows_past_the_edge_name_the_place_not_a_repeat_the_file_lacks() {
    let past_columns = format!(
        r#"<table:table-row><table:table-cell table:number-columns-repeated="16383"/><table:table-cell/><table:table-cell/>{ODS_VALUE_CELL}</table:table-row>"#
    );
    let error = open(ods_with_rows(&past_columns), Format::Ods).err().expect("refused");
    assert!(
        error.contains("sheet 'S': a cell holding a value at row 1, column 16386 lies past the edge of a sheet")
            && !error.contains("repeated"),
        "{error}"
    );
    let past_rows = format!(
        r#"<table:table-row table:number-rows-repeated="1048575"><table:table-cell/></table:table-row><table:table-row><table:table-cell/></table:table-row><table:table-row><table:table-cell/></table:table-row>{ODS_ONE}"#
    );
    let error = open(ods_with_rows(&past_rows), Format::Ods).err().expect("refused");
    assert!(
        error.contains("sheet 'S': a cell holding a value at row 1048578, column 1 lies past the edge of a sheet")
            && !error.contains("repeated"),
        "{error}"
    );
}

/// ODF lets a cell's text hold a table of its own (`table:table` among a cell's text
/// content, ODF 1.2 part 1 §9.1.4); calamine reads the inner table's rows as the sheet's and
/// ends the sheet at the inner table's end, so the sheet's later rows were lost without a word
/// (row 2's value 2 here), and the measuring of repeats restarted inside it. Such a file is
/// refused naming the sheet and the cell, also when the inner table repeats without bound.
#[test]
fn ods_tables_nested_in_a_sheet_are_refused_naming_the_cell_not_read_short() {
    let inner = |repeats: &str| {
        format!(
            r#"<table:table table:name="Inner"><table:table-row table:number-rows-repeated="{repeats}"><table:table-cell table:number-columns-repeated="{repeats}" office:value-type="float" office:value="9"/></table:table-row></table:table>"#
        )
    };
    for repeats in ["1", "4294967295"] {
        let rows = format!(
            r#"<table:table-row><table:table-cell office:value-type="string"><text:p>outer</text:p>{}</table:table-cell></table:table-row><table:table-row><table:table-cell office:value-type="float" office:value="2"/></table:table-row>"#,
            inner(repeats)
        );
        let error = open(ods_with_rows(&rows), Format::Ods).err().expect("refused");
        assert!(
            error.contains("hostile.ods") && error.contains("sheet 'S': the cell at row 1, column 1 holds a table"),
            "{error}"
        );
    }
}

/// Errors calamine gives naming no part ("Xml error: at 0..0: unrecognized entity `&i;`",
/// "Parse integer error") name content.xml and what is wrong: an entity a DOCTYPE declares
/// (a billion-laughs bomb among them) and a repeat count that is no count.
#[test]
fn ods_entities_and_bad_counts_are_refused_naming_the_part() {
    let laughs = r#"<table:table-row><table:table-cell office:value-type="string"><text:p>&lol9;</text:p></table:table-cell></table:table-row>"#;
    let error = open(ods_with_rows(laughs), Format::Ods).err().expect("refused");
    assert!(error.contains("content.xml: the XML is not well-formed: unknown entity &lol9;"), "{error}");
    let negative = r#"<table:table-row><table:table-cell table:number-columns-repeated="-5"/></table:table-row>"#;
    let error = open(ods_with_rows(negative), Format::Ods).err().expect("refused");
    assert!(error.contains(r#"content.xml: sheet 'S': number-columns-repeated="-5" is not a count"#), "{error}");
}

/// The Workbook stream of the vendored .xls, its records changed by `change`.
fn xls_with_records(change: impl Fn(&mut Vec<(u16, Vec<u8>)>)) -> Vec<u8> {
    let good = vendored("excel-corpus/xls/testNames.xls");
    common::vba::with_stream(&good, "/Workbook", |old| {
        let mut list = biff_records(old);
        change(&mut list);
        biff_encode(&list)
    })
}

/// A BIFF8 record is a type, a length and that many bytes ([MS-XLS] 2.1.4), and a substream
/// runs from its BOF to its EOF (2.1.5); a sheet's BoundSheet8 gives the stream offset of
/// that sheet's BOF (2.4.28, lbPlyPos). A record whose length ran past the stream ended the
/// sheet there (its last cell dropped), a stream cut short lost the cells after the cut, and
/// a BoundSheet8 pointing anywhere else read no records or other ones: each opened without a
/// word. Each is refused naming the sheet, the record or offset, and the stream.
#[test]
fn xls_records_past_the_stream_and_sheets_pointing_nowhere_are_refused() {
    let refusal = |bytes: Vec<u8>| open(bytes, Format::Xls).err().expect("refused");
    let good = vendored("excel-corpus/xls/testNames.xls");
    let past_end = common::vba::with_stream(&good, "/Workbook", |old| {
        let list = biff_records(old);
        let last = list.iter().rposition(|(kind, _)| *kind == 0x0006).expect("a Formula record");
        let mut stream = biff_encode(&list[..last]);
        let at = stream.len();
        stream.extend_from_slice(&biff_encode(&list[last..]));
        stream[at + 2..at + 4].copy_from_slice(&0xFFFFu16.to_le_bytes());
        stream
    });
    let error = refusal(past_end);
    assert!(
        error.contains("hostile.xls")
            && error.contains("sheet 'Sheet1': record Formula (0x0006) at byte ")
            && error.contains("says it holds 65535 bytes, past the stream's end"),
        "{error}"
    );
    let cut = common::vba::with_stream(&good, "/Workbook", |old| old[..old.len() - 40].to_vec());
    assert!(refusal(cut).contains("sheet 'Sheet1': "), "a stream cut inside the sheet's records");

    const BOUND_SHEET: u16 = 0x0085;
    for offset in [u32::MAX, 0, 3, 10_000_000] {
        let bytes = xls_with_records(|list| {
            let (_, body) = list.iter_mut().find(|(kind, _)| *kind == BOUND_SHEET).unwrap();
            body[..4].copy_from_slice(&offset.to_le_bytes());
        });
        let error = refusal(bytes);
        assert!(
            error.contains(&format!(
                "sheet 'Sheet1': its BoundSheet8 record gives byte {offset} of the Workbook stream"
            )) && error.contains("no worksheet's BOF record starts there"),
            "{error}"
        );
    }
}

/// A cell whose `PtgExp` names no shared formula's first cell is looked for in every shared
/// formula's area: 16,000 such cells beside 16,000 one-cell shared formulas (a 700 KB file)
/// took 512 million area comparisons, and ten times as many a hundred times longer. Past
/// `MAX_SHARED_SEARCH` comparisons for a sheet the file is refused naming the sheet.
#[test]
fn xls_cells_searching_every_shared_formula_are_refused_past_the_limit() {
    let bytes = xls_with_records(|list| {
        let eof = list.iter().rposition(|(kind, _)| *kind == 0x000A).unwrap();
        let mut extra = Vec::new();
        for k in 0..16_000u16 {
            let (row, col) = (100 + k / 200, k % 200);
            // ShrFmla ([MS-XLS] 2.4.260): RefU of one cell, reserved, cUse, cce, PtgInt 1.
            let mut shared = [row.to_le_bytes(), row.to_le_bytes()].concat();
            shared.extend_from_slice(&[col as u8, col as u8, 0, 1, 3, 0, 0x1E, 1, 0]);
            extra.push((0x04BC, shared));
            // Formula (2.4.127) 300 rows below: PtgExp naming its own cell, no shared formula's.
            let below = row + 300;
            let mut formula = [below.to_le_bytes(), col.to_le_bytes(), 15u16.to_le_bytes()].concat();
            formula.extend_from_slice(&[0; 14]);
            formula.extend_from_slice(&5u16.to_le_bytes());
            formula.push(0x01);
            formula.extend_from_slice(&[below.to_le_bytes(), col.to_le_bytes()].concat());
            extra.push((0x0006, formula));
        }
        list.splice(eof..eof, extra);
    });
    let error = open(bytes, Format::Xls).err().expect("refused");
    assert!(error.contains("sheet 'Sheet1': more than 134217728 comparisons of shared formulas' areas"), "{error}");
}

/// [MS-XLSB] 2.1.4: a record's type is at most 2 bytes and its size at most 4, 7 bits each,
/// the high bit saying another byte follows; the size counts the bytes that follow. A record
/// the part ended inside of was read short (a number cell at the end of a sheet part kept
/// the 16 bytes there were), a type or size whose last byte still had its high bit set was
/// read as another record, and a part cut at a record's edge lost the cells after it: each
/// opened without a word. A shared or array formula's area (RfX) past the sheet's edge
/// (rows and columns to 2^32 - 1) panicked while its reference was written. Each is refused
/// naming the part and the record or the byte.
#[test]
fn xlsb_records_cut_short_or_past_the_sheet_are_refused_naming_the_part() {
    let good = vendored("xlsb/IS_INFORMATION.xlsb");
    let sheet = "xl/worksheets/sheet1.bin";
    let refusal = |bytes: Vec<u8>| open(bytes, Format::Xlsb).err().expect("refused");
    let tail = |tail: &'static [u8]| {
        rewrite(&good, None, &mut |name, bytes| {
            (name == sheet).then(|| {
                let mut list = records(bytes);
                let end = list.iter().position(|(kind, _)| *kind == BRT_END_SHEET_DATA).unwrap();
                list.truncate(end);
                let mut part = encode(&list);
                part.extend_from_slice(tail);
                part
            })
        })
    };
    // A BrtCellReal of A1 whose size says 127 bytes, 16 following.
    let mut short = vec![BRT_CELL_REAL as u8, 0x7F];
    short.extend(cell_real(0, 7.5));
    let error = refusal(tail(short.leak()));
    assert!(error.contains(sheet) && error.contains("is cut short: the part ends before the 127 bytes"), "{error}");
    let error = refusal(tail(&[BRT_CELL_REAL as u8, 0xFF, 0xFF, 0xFF, 0xFF, 0x0F, 0, 0]));
    assert!(error.contains(sheet) && error.contains("has a size of more than 4 bytes"), "{error}");
    let error = refusal(tail(&[0xFF, 0xFF, 0x7F, 0x00]));
    assert!(error.contains(sheet) && error.contains("has a type of more than 2 bytes"), "{error}");
    let error = refusal(tail(&[]));
    assert!(error.contains(sheet) && error.contains("no record BrtEndSheetData"), "{error}");

    // A formula cell at B6 (its PtgExp naming row 6), then a shared or array formula over
    // rows 6 to 2^32 and columns B to 2^32.
    for (kind, name) in [(0x01AAu16, "BrtArrFmla"), (0x01AB, "BrtShrFmla")] {
        let mut formula = 1u32.to_le_bytes().to_vec();
        formula.extend_from_slice(&[0; 4]);
        formula.extend_from_slice(&1.0f64.to_le_bytes());
        formula.extend_from_slice(&[0, 0, 5, 0, 0, 0, 0x01, 5, 0, 0, 0, 4, 0, 0, 0, 1, 0, 0, 0]);
        let mut block: Vec<u8> = [5u32, u32::MAX, 1, u32::MAX].iter().flat_map(|n| n.to_le_bytes()).collect();
        if kind == 0x01AA {
            block.push(0);
        }
        block.extend_from_slice(&[3, 0, 0, 0, 0x1E, 1, 0, 0, 0, 0, 0]);
        let row = (BRT_ROW_HDR, [5u32.to_le_bytes(), [0; 4]].concat());
        let error = refusal(with_cells(&good, vec![row, (0x0009, formula), (kind, block)]));
        assert!(
            error.contains(sheet)
                && error.contains(&format!("the area of a formula (record {name}) at row 6, column 2 runs past"))
                && error.contains("rows 6-4294967296, columns 2-4294967296"),
            "{error}"
        );
    }
}

/// [MS-XLS] 2.4.4 "Array": a legacy array formula's FORMULA record holds PtgExp (0x01) to its
/// own cell and the ARRAY record after it gives the area (rwFirst, rwLast, colFirst, colLast)
/// and the formula. One over a whole .xls sheet, A1:IV65536, is 16,777,216 cells, which an
/// xlsx writes one by one: `set … -o out.xlsx` ran for minutes and wrote gigabytes. Its value
/// is #SPILL! past the workbook's cell limit, and saving it is refused naming the cell; no
/// file is left behind.
#[test]
fn an_xls_array_formula_over_the_whole_sheet_is_not_written_cell_by_cell() {
    const FORMULA: u16 = 0x0006;
    const ARRAY: u16 = 0x0221;
    let bytes = xls_with_records(|list| {
        let at = list.iter().position(|(kind, _)| *kind == FORMULA).expect("a Formula record");
        let (row, col) = (u16::from_le_bytes([list[at].1[0], list[at].1[1]]), list[at].1[2]);
        // PtgExp to the record's own cell, 5 bytes of formula.
        let body = &mut list[at].1;
        body.truncate(20);
        body.extend_from_slice(&5u16.to_le_bytes());
        body.extend_from_slice(&[0x01, row.to_le_bytes()[0], row.to_le_bytes()[1], col, 0]);
        // Area from the cell to the sheet's last row and column; formula PtgInt 1.
        let mut array = Vec::new();
        array.extend_from_slice(&row.to_le_bytes());
        array.extend_from_slice(&65535u16.to_le_bytes());
        array.extend_from_slice(&[col, 255]);
        array.extend_from_slice(&[0, 0, 0, 0, 0, 0]);
        array.extend_from_slice(&3u16.to_le_bytes());
        array.extend_from_slice(&[0x1E, 1, 0]);
        list.insert(at + 1, (ARRAY, array));
    });
    let opened = open(bytes, Format::Xls).unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.xlsx");
    let layout = opened.layout.clone().unwrap_or_default();
    let error = io::xlsx::save_with_layout(&opened.workbook, &layout, &out).expect_err("refused").to_string();
    assert!(
        error.contains("Sheet1!")
            && error.contains("the array formula over ")
            && error.contains("more than the 8388608 a workbook holds"),
        "{error}"
    );
    assert!(!out.exists(), "nothing is written");
}

/// A file naming more sheets than a workbook holds (65,536) is refused at the first one past
/// it, before any sheet is read: 200,000 .xlsb sheet records naming one sheet part read that
/// part each time (29 s and 1.9 GB before the cell limit stopped it), and 200,000 one-cell
/// .ods sheets took 8.7 s and 650 MB and were refused naming an xlsx part.
#[test]
fn files_of_more_sheets_than_a_workbook_holds_are_refused_before_reading_them() {
    let package = vendored("xlsb/MATCH.xlsb");
    let many = with_records(&package, "xl/workbook.bin", |list| {
        let at = list.iter().position(|(kind, _)| *kind == BRT_BUNDLE_SH).unwrap();
        let sheet = list[at].clone();
        list.splice(at..at, std::iter::repeat_n(sheet, 65_536));
    });
    let error = open(many, Format::Xlsb).err().expect("refused");
    assert!(
        error.contains("xl/workbook.bin: sheet 65537 (record BrtBundleSh): a workbook holds at most 65536 sheets"),
        "{error}"
    );

    let sheets: String = (1..=65_536).map(|i| format!(r#"</table:table><table:table table:name="T{i}">"#)).collect();
    let error = open(ods_with_rows(&format!("{ODS_ONE}{sheets}")), Format::Ods).err().expect("refused");
    assert!(error.contains("content.xml: sheet 'T65536': a workbook holds at most 65536 sheets"), "{error}");
}

/// What an import says it left out is bounded, whatever the file holds: 30 named ranges
/// named like cells (`n1` … `n30`, column N's cells, which Excel refuses as defined names)
/// are five notes and a count, where they were 30 notes (300,000 of them were 31 MB of
/// notes); a formula of 5,000 characters ncsheet cannot compute is quoted by its first 200
/// (a 5 MB one was quoted whole).
#[test]
fn an_ods_import_tells_what_it_left_out_in_bounded_notes() {
    let cell = r#"<table:table-row><table:table-cell office:value-type="float" office:value="1"/></table:table-row>"#;
    let names: String = (1..=30)
        .map(|i| format!(r#"<table:named-range table:name="n{i}" table:base-cell-address="$S.$A$1" table:cell-range-address="$S.$A$1:.$B$2"/>"#))
        .collect();
    let body = format!(
        r#"<table:table table:name="S">{cell}</table:table><table:named-expressions>{names}</table:named-expressions>"#
    );
    let notes = open(ods_of(&body), Format::Ods).unwrap().notes;
    let named: Vec<&String> = notes.iter().filter(|n| n.starts_with("name n")).collect();
    assert_eq!(named.len(), 5, "{notes:#?}");
    assert!(named[0].contains("'n1' cannot be a defined name"), "{}", named[0]);
    assert!(
        notes.contains(&"and 25 more defined names were left out (their notes are not shown)".to_string()),
        "{notes:#?}"
    );

    let long = "a".repeat(5_000);
    let formula = format!(
        r#"<table:table table:name="S"><table:table-row><table:table-cell table:formula="of:='{long}'" office:value-type="float" office:value="1"/></table:table-row></table:table>"#
    );
    let notes = open(ods_of(&formula), Format::Ods).unwrap().notes;
    let kept = notes.iter().find(|n| n.contains("cannot compute")).expect("the formula is noted");
    assert!(kept.contains(&format!("S!A1 ='{}… (5003 characters in all)", "a".repeat(198))), "{kept}");
    assert!(kept.len() < 1_000, "{} bytes", kept.len());
}

/// Excel and LibreOffice tell sheet names apart without case: an .ods of sheets `Abc` and
/// `ABC` is refused naming both sheets, where the error named xl/worksheets/sheet2.xml, a
/// part of the package converted in memory that the file does not have.
#[test]
fn an_ods_of_two_sheets_of_one_name_is_refused_naming_them() {
    let cell = r#"<table:table-row><table:table-cell office:value-type="float" office:value="1"/></table:table-row>"#;
    let body = format!(
        r#"<table:table table:name="Abc">{cell}</table:table><table:table table:name="ABC">{cell}</table:table>"#
    );
    let error = open(ods_of(&body), Format::Ods).err().expect("refused");
    assert!(error.contains("hostile.ods") && error.contains("sheet 'ABC' has the name of sheet 'Abc'"), "{error}");
    assert!(!error.contains("xl/worksheets"), "{error}");
}
