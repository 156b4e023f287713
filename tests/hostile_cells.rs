//! Issue 30, the size of what a reader builds: one limit on a workbook's cells for every
//! reader, every edit and every spill (`workbook::MAX_CELLS`, 2^23), and Excel's 32,767
//! characters of a cell's text held by every reader, a csv field refused as soon as it
//! passes them. Each runs the binary under a 4 GiB address-space cap: a file past a limit
//! ends with an error naming the file, the place and the limit, never an abort.
//!
//! The places are worked out here by arithmetic, not read back from ncsheet: with 9 fields
//! a row, cell number 8,388,609 (the first past 2^23) is row ⌊8388608 / 9⌋ + 1 = 932,068,
//! column 8388608 − 932067 × 9 + 1 = 6 (F).

mod common;

use std::io::Write;
use std::path::Path;

use common::cli::{Invocation, Run};

/// 2^23: the cells a workbook holds (docs/limits.md, "cells of a workbook").
const LIMIT: usize = 1 << 23;

fn capped(dir: &Path, args: &[&str]) -> Run {
    Invocation { dir: Some(dir), memory_kib: Some(4_000_000), ..Default::default() }.run(args)
}

/// Asserts a clear error (exit 1) whose message holds every one of `words`.
fn refused(dir: &Path, args: &[&str], words: &[&str]) -> String {
    let run = capped(dir, args);
    assert_eq!(run.code, 1, "{args:?}: {}", run.stderr);
    for word in words {
        assert!(run.stderr.contains(word), "{args:?}: '{word}' missing from: {}", run.stderr);
    }
    run.stderr
}

/// `rows` lines of `cols` fields `1`.
fn ones_csv(rows: usize, cols: usize) -> String {
    let line = format!("{}\n", vec!["1"; cols].join(","));
    line.repeat(rows)
}

/// An xlsx package of one sheet whose `<sheetData>` is `rows`, with `strings` as its shared
/// strings.
fn xlsx(file: &Path, strings: &[String], rows: &mut dyn FnMut(&mut dyn Write)) {
    let mut zip = zip::ZipWriter::new(std::fs::File::create(file).unwrap());
    let options = zip::write::SimpleFileOptions::default().compression_level(Some(1));
    let main = "http://schemas.openxmlformats.org/spreadsheetml/2006/main";
    let rel = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";
    let package_rel = "http://schemas.openxmlformats.org/package/2006/relationships";
    let sml = "application/vnd.openxmlformats-officedocument.spreadsheetml";
    let parts = [
        (
            "[Content_Types].xml",
            format!(
                r#"<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="{sml}.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="{sml}.worksheet+xml"/><Override PartName="/xl/sharedStrings.xml" ContentType="{sml}.sharedStrings+xml"/></Types>"#
            ),
        ),
        (
            "_rels/.rels",
            format!(
                r#"<Relationships xmlns="{package_rel}"><Relationship Id="rId1" Type="{rel}/officeDocument" Target="xl/workbook.xml"/></Relationships>"#
            ),
        ),
        (
            "xl/workbook.xml",
            format!(
                r#"<workbook xmlns="{main}" xmlns:r="{rel}"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#
            ),
        ),
        (
            "xl/_rels/workbook.xml.rels",
            format!(
                r#"<Relationships xmlns="{package_rel}"><Relationship Id="rId1" Type="{rel}/worksheet" Target="worksheets/sheet1.xml"/><Relationship Id="rId2" Type="{rel}/sharedStrings" Target="sharedStrings.xml"/></Relationships>"#
            ),
        ),
        (
            "xl/sharedStrings.xml",
            format!(
                r#"<sst xmlns="{main}" count="{n}" uniqueCount="{n}">{}</sst>"#,
                strings.iter().map(|s| format!("<si><t>{s}</t></si>")).collect::<String>(),
                n = strings.len()
            ),
        ),
    ];
    for (name, text) in parts {
        zip.start_file(name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.start_file("xl/worksheets/sheet1.xml", options).unwrap();
    write!(zip, r#"<worksheet xmlns="{main}"><sheetData>"#).unwrap();
    rows(&mut zip);
    zip.write_all(b"</sheetData></worksheet>").unwrap();
    zip.finish().unwrap();
}

#[test]
fn a_csv_past_the_workbooks_cells_is_refused_naming_the_file_line_and_cell() {
    let dir = tempfile::tempdir().unwrap();
    // 932,068 rows of 9: 8,388,612 cells, four past the limit (it aborted at the cap with
    // 20 million cells).
    std::fs::write(dir.path().join("big.csv"), ones_csv(932_068, 9)).unwrap();
    refused(dir.path(), &["eval", "big.csv", "A1"], &["big.csv", "line 932068", "Sheet1!F932068", "8388608 cells"]);
    // At the limit, the sheet loads and computes under the cap.
    std::fs::write(dir.path().join("full.csv"), ones_csv(LIMIT / 8, 8)).unwrap();
    let run = capped(dir.path(), &["eval", "full.csv", "H1048576"]);
    assert_eq!((run.code, run.stdout.trim()), (0, "1"), "{}", run.stderr);
}

#[test]
fn an_xlsx_past_the_workbooks_cells_is_refused_naming_the_part_and_cell() {
    let dir = tempfile::tempdir().unwrap();
    let row = format!("<row>{}</row>", "<c><v>1</v></c>".repeat(9));
    xlsx(&dir.path().join("big.xlsx"), &[], &mut |out| {
        for _ in 0..932_068 {
            out.write_all(row.as_bytes()).unwrap();
        }
    });
    let args = ["eval", "big.xlsx", "A1", "--max-zip-ratio", "100000"];
    refused(dir.path(), &args, &["big.xlsx", "xl/worksheets/sheet1.xml", "Sheet1!F932068", "8388608 cells"]);
}

#[test]
fn a_spill_past_the_workbooks_cells_is_spill_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    // SEQUENCE(1048576,8) is 2^23 items, within the array limit: alone it spills whole.
    std::fs::write(dir.path().join("full.csv"), "\"=SEQUENCE(1048576,8)\"\n").unwrap();
    let run = capped(dir.path(), &["eval", "full.csv", "H1048576"]);
    assert_eq!((run.code, run.stdout.trim()), (0, "8388608"), "{}", run.stderr);
    // Two more cells hold constants: the spill would make the workbook's cell 2^23 + 2.
    // Excel's answer to a spill it has no room for is #SPILL! ("Out of memory", How to
    // correct a #SPILL! error).
    std::fs::write(dir.path().join("over.csv"), "\"=SEQUENCE(1048576,8)\",,,,,,,,,1\n,,,,,,,,,2\n").unwrap();
    let run = capped(dir.path(), &["eval", "over.csv", "A1", "J2"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("#SPILL!") && run.stdout.contains('2'), "{}", run.stdout);
    assert!(run.stderr.contains("8388608 cells"), "the note names the limit: {}", run.stderr);
}

// A macro's writes meet the same limit, each refused before its first cell is written, with
// a run-time error On Error traps: a formula filled over A1:I1000000 (nine million cells,
// A1 already holding one), a paste of a nine-cell row tiled over A2:I1000000 (they passed
// it: 9,000,000 cells in 1 GB, and a paste of 12.6 million in 3.1 GB, past the 4 GiB cap
// with a little more), and blank cells made for the small ranges a million formulas read,
// which are linked through a range instead once the workbook is full (`=SUM(B1:Q1)`
// filled down made sixteen a row). Each place past the limit is F932068, by the arithmetic
// above: the workbook's first nine cells are row 1's.
#[test]
fn a_macro_past_the_workbooks_cells_is_refused_naming_the_cell() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("one.csv"), "x\n").unwrap();
    let source = "Sub Main()
    On Error Resume Next
    Range(\"A1:I1000000\").Formula = \"=1\"
    MsgBox Err.Number & Err.Description & \"|\" & Range(\"A1\").Value & \"|\" & Range(\"I1000000\").Formula
    Err.Clear
    Range(\"A1:I1\").Value = 1
    Range(\"A1:I1\").Copy Range(\"A2:I1000000\")
    MsgBox Err.Number & Err.Description & \"|\" & Range(\"A2\").Formula
    Err.Clear
    Range(\"A1:I1000000\").Value = 2
    MsgBox Err.Number & Err.Description & \"|\" & Range(\"A1\").Value & \"|\" & Range(\"A2\").Value
End Sub
";
    std::fs::write(dir.path().join("m.bas"), source).unwrap();
    let run = capped(dir.path(), &["run", "one.csv", "m.bas"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // MsgBox writes to stderr, before the run's own notes.
    let lines: Vec<&str> = run.stderr.lines().filter(|l| !l.starts_with("ncsheet:")).collect();
    let refusal = "Sheet1!F932068: a workbook holds at most 8388608 cells";
    assert!(lines.len() == 3 && lines.iter().all(|l| l.contains(refusal)), "{}", run.stderr);
    // Err.Number is 1004, Excel's for a range write it cannot do (Microsoft KB 832136, "You
    // may receive a 'Run-time error 1004' error message when you programmatically set a
    // large array string to a range"); the description is the message naming the cell.
    assert!(lines.iter().all(|l| l.starts_with("1004Sheet1!F932068")), "{}", run.stderr);
    assert!(lines[0].ends_with("|x|"), "nothing of the fill is written: {}", lines[0]);
    assert!(lines[1].ends_with('|'), "nothing of the paste is written: {}", lines[1]);
    assert!(lines[2].ends_with("|1|"), "nothing of the .Value = is written: {}", lines[2]);
    // 600,000 formulas each summing sixteen cells of their own row: 9.6 million blank cells
    // linked one by one would pass the limit; the sums still follow their cells.
    std::fs::write(
        dir.path().join("sums.bas"),
        "Sub Main()
    Range(\"A1:A600000\").Formula = \"=SUM(B1:Q1)\"
    Range(\"Q600000\").Value = 7
    MsgBox Range(\"A600000\").Value & \" \" & Range(\"A599999\").Value
End Sub
",
    )
    .unwrap();
    let run = capped(dir.path(), &["run", "one.csv", "sums.bas"]);
    assert_eq!((run.code, run.stderr.lines().next()), (0, Some("7 0")), "{}", run.stderr);
}

#[test]
fn a_csv_text_longer_than_a_cell_holds_is_refused_naming_the_cell() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).unwrap();
    // 40,000 characters: Excel's cell holds 32,767.
    write("long.csv", &format!("1\n2,\"{}\"\n", "x".repeat(40_000)));
    refused(
        dir.path(),
        &["eval", "long.csv", "A1"],
        &["long.csv", "line 2", "Sheet1!B2", "of 40000 characters", "32767"],
    );
    // Excel counts UTF-16 units: 16,384 characters outside the BMP are 32,768 of them.
    write("wide.csv", &format!("x,{}\n", "\u{1F600}".repeat(16_384)));
    refused(dir.path(), &["eval", "wide.csv", "A1"], &["Sheet1!B1", "of 32768 characters"]);
    // 32,767 two-byte characters are 65,534 bytes and one cell's text.
    write("accents.csv", &format!("{},=LEN(A1)\n", "\u{e9}".repeat(32_767)));
    let run = capped(dir.path(), &["eval", "accents.csv", "B1"]);
    assert_eq!((run.code, run.stdout.trim()), (0, "32767"), "{}", run.stderr);
    // A quoted field of 64 MiB and a line of 64 MiB without a separator stop at the cell's
    // limit, before their end: the message has no length, the text was not read to its end.
    write("quoted.csv", &format!("1\n\"{}\"\n", "q".repeat(64 << 20)));
    let err = refused(dir.path(), &["eval", "quoted.csv", "A1"], &["line 2", "Sheet1!A2", "32767"]);
    assert!(!err.contains("of 67108864"), "{err}");
    write("bare.csv", &format!("1\n{}\n", "b".repeat(64 << 20)));
    refused(dir.path(), &["eval", "bare.csv", "A1"], &["line 2", "Sheet1!A2", "32767"]);
}

#[test]
fn an_xlsx_text_longer_than_a_cell_holds_is_refused_naming_the_cell() {
    let dir = tempfile::tempdir().unwrap();
    // "Excel restricts the value of this element [t] to 32767 characters" ([MS-OI29500] 2.1.706).
    xlsx(&dir.path().join("long.xlsx"), &["y".repeat(32_768)], &mut |out| {
        out.write_all(br#"<row r="3"><c r="C3" t="s"><v>0</v></c></row>"#).unwrap();
    });
    refused(dir.path(), &["eval", "long.xlsx", "A1"], &["long.xlsx", "Sheet1!C3", "of 32768 characters", "32767"]);
    xlsx(&dir.path().join("inline.xlsx"), &[], &mut |out| {
        let cell = format!(r#"<row r="1"><c r="B1" t="inlineStr"><is><t>{}</t></is></c></row>"#, "z".repeat(40_000));
        out.write_all(cell.as_bytes()).unwrap();
    });
    refused(dir.path(), &["eval", "inline.xlsx", "A1"], &["Sheet1!B1", "of 40000 characters"]);
}
