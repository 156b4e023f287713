//! Hostile input, the memory and time rows of issue 19: each runs the binary under a 2 GiB
//! address-space cap (`ulimit -v`) and must end with a clear error naming the limit and the
//! option that raises it, never an abort. The zip bombs are built here, a few MiB each that
//! inflate to gigabytes: a deflated chunk flushed to a byte boundary is repeated, so they
//! cost no time to make.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Runs the ncsheet binary in `dir` under a 2 GiB address-space cap.
/// What a macro printed (Debug.Print), without ncsheet's own notes (`ncsheet: FILE: note: …`).
fn printed(err: &str) -> &str {
    err.split("\nncsheet: ").next().unwrap_or(err).trim()
}

fn ncsheet(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let mut command = String::from("ulimit -v 2097152; exec \"$0\"");
    for i in 1..=args.len() {
        command.push_str(&format!(" \"${{{i}}}\""));
    }
    let out = Command::new("sh")
        .arg("-c")
        .arg(command)
        .arg(env!("CARGO_BIN_EXE_ncsheet"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let code = out.status.code().unwrap_or_else(|| panic!("killed by a signal: {:?}", out.status));
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (code, text(&out.stdout), text(&out.stderr))
}

/// Asserts a clear error (exit 1) whose message holds every one of `words`.
fn refused(dir: &Path, args: &[&str], words: &[&str]) {
    let (code, _, err) = ncsheet(dir, args);
    assert_eq!(code, 1, "{args:?}: {err}");
    for word in words {
        assert!(err.contains(word), "{args:?}: '{word}' missing from: {err}");
    }
}

// ---------------------------------------------------------------------------------------
// Packages by hand

/// A part: its name and its bytes as stored (deflated), its inflated size and checksum.
struct Part {
    name: String,
    data: Vec<u8>,
    size: u32,
    crc: u32,
}

fn deflate(bytes: &[u8], finish: bool) -> Vec<u8> {
    let mut encoder = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
    encoder.write_all(bytes).unwrap();
    if finish {
        encoder.finish().unwrap()
    } else {
        // A sync flush ends on a byte boundary with the block open: pieces concatenate.
        encoder.flush().unwrap();
        encoder.get_ref().clone()
    }
}

fn small(name: &str, text: &str) -> Part {
    let mut crc = flate2::Crc::new();
    crc.update(text.as_bytes());
    Part { name: name.into(), data: deflate(text.as_bytes(), true), size: text.len() as u32, crc: crc.sum() }
}

/// `head`, then `unit` repeated to about `total` bytes, then `tail`. Its checksum is left
/// wrong: a reader must stop long before the end, where it would be checked.
fn bomb(name: &str, head: &str, unit: &str, total: u64, tail: &str) -> Part {
    let chunk = unit.repeat((1 << 20) / unit.len());
    let piece = deflate(chunk.as_bytes(), false);
    let copies = total / chunk.len() as u64;
    let mut data = deflate(head.as_bytes(), false);
    for _ in 0..copies {
        data.extend_from_slice(&piece);
    }
    data.extend(deflate(tail.as_bytes(), true));
    Part { name: name.into(), data, size: u32::MAX, crc: 0 }
}

/// A zip file of the parts (deflated, no zip64: every size fits 32 bits).
fn package(parts: &[Part]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut central = Vec::new();
    let le16 = |v: &mut Vec<u8>, n: u16| v.extend_from_slice(&n.to_le_bytes());
    let le32 = |v: &mut Vec<u8>, n: u32| v.extend_from_slice(&n.to_le_bytes());
    for part in parts {
        let offset = out.len() as u32;
        le32(&mut out, 0x0403_4b50);
        for n in [20, 0, 8, 0, 0] {
            le16(&mut out, n);
        }
        for n in [part.crc, part.data.len() as u32, part.size] {
            le32(&mut out, n);
        }
        le16(&mut out, part.name.len() as u16);
        le16(&mut out, 0);
        out.extend_from_slice(part.name.as_bytes());
        out.extend_from_slice(&part.data);

        le32(&mut central, 0x0201_4b50);
        for n in [20, 20, 0, 8, 0, 0] {
            le16(&mut central, n);
        }
        for n in [part.crc, part.data.len() as u32, part.size] {
            le32(&mut central, n);
        }
        for n in [part.name.len() as u16, 0, 0, 0, 0] {
            le16(&mut central, n);
        }
        le32(&mut central, 0);
        le32(&mut central, offset);
        central.extend_from_slice(part.name.as_bytes());
    }
    let central_at = out.len() as u32;
    out.extend_from_slice(&central);
    le32(&mut out, 0x0605_4b50);
    for n in [0, 0, parts.len() as u16, parts.len() as u16] {
        le16(&mut out, n);
    }
    le32(&mut out, central.len() as u32);
    le32(&mut out, central_at);
    le16(&mut out, 0);
    out
}

const WORKBOOK: &str = r#"<workbook xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#;
const WORKBOOK_RELS: &str = r#"<Relationships><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet1.xml"/><Relationship Id="rId2" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/styles" Target="styles.xml"/><Relationship Id="rId3" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/sharedStrings" Target="sharedStrings.xml"/></Relationships>"#;
const SHEET: &str = r#"<worksheet><sheetData><row r="1"><c r="A1"><v>1</v></c></row></sheetData></worksheet>"#;

/// A one-sheet workbook whose part `bomb.name` is the bomb.
fn workbook_with(dir: &Path, file: &str, bomb: Part) -> PathBuf {
    let mut parts = vec![
        small("[Content_Types].xml", "<Types/>"),
        small(
            "_rels/.rels",
            r#"<Relationships><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#,
        ),
        small("xl/workbook.xml", WORKBOOK),
        small("xl/_rels/workbook.xml.rels", WORKBOOK_RELS),
        small("xl/worksheets/sheet1.xml", SHEET),
        small("xl/styles.xml", r#"<styleSheet><cellXfs count="1"><xf numFmtId="0"/></cellXfs></styleSheet>"#),
        small("xl/sharedStrings.xml", "<sst><si><t>x</t></si></sst>"),
    ];
    parts.retain(|p| p.name != bomb.name);
    parts.push(bomb);
    let path = dir.join(file);
    std::fs::write(&path, package(&parts)).unwrap();
    path
}

const GIB: u64 = 1 << 30;

#[test]
fn the_package_builder_makes_a_workbook_ncsheet_reads() {
    let dir = tempfile::tempdir().unwrap();
    workbook_with(dir.path(), "fine.xlsx", small("xl/worksheets/sheet1.xml", SHEET));
    let (code, out, err) = ncsheet(dir.path(), &["eval", "fine.xlsx", "A1"]);
    assert_eq!((code, out.trim()), (0, "1"), "{err}");
}

// ---------------------------------------------------------------------------------------
// xlsx: every part is held to a size and a ratio while it inflates

#[test]
fn zip_bombs_in_every_part_are_refused_naming_the_part_and_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let ws = r#"<worksheet><sheetData><row r="1"><c r="A1"><v>1</v></c>"#;
    let cases = [
        bomb("xl/styles.xml", "<styleSheet><cellXfs>", r#"<xf numFmtId="0"/>"#, 3 * GIB, "</cellXfs></styleSheet>"),
        bomb("xl/sharedStrings.xml", "<sst>", &format!("<si><t>{}</t></si>", "a".repeat(4000)), 3 * GIB, "</sst>"),
        bomb("xl/workbook.xml", &WORKBOOK[..WORKBOOK.len() - 11], "        ", 3 * GIB, "</workbook>"),
        bomb(
            "xl/_rels/workbook.xml.rels",
            &WORKBOOK_RELS[..WORKBOOK_RELS.len() - 16],
            "        ",
            3 * GIB,
            "</Relationships>",
        ),
        bomb("xl/vbaProject.bin", "", "\0\0\0\0\0\0\0\0", 3 * GIB, ""),
        // 150 million cells, each with a value (the same cell: a sheet's size is no bound).
        bomb("xl/worksheets/sheet1.xml", ws, r#"<c r="B1"><v>1</v></c>"#, 3 * GIB, "</row></sheetData></worksheet>"),
        bomb("xl/theme/theme1.xml", "<theme>", "        ", 3 * GIB, "</theme>"),
    ];
    for (i, part) in cases.into_iter().enumerate() {
        let name = part.name.clone();
        let file = format!("bomb{i}.xlsm");
        workbook_with(dir.path(), &file, part);
        refused(dir.path(), &["eval", &file, "A1"], &[&name, "the part inflates to more than", "limit"]);
        // Past the ratio, the size: still refused, before the cap on memory.
        let raised = ["eval", &file, "A1", "--max-zip-ratio", "100000"];
        refused(dir.path(), &raised, &[&name, "the part inflates to more than", "limit"]);
    }
}

#[test]
fn cells_without_references_stop_at_the_sheets_edge() {
    let dir = tempfile::tempdir().unwrap();
    let ws = "<worksheet><sheetData><row>";
    let part = bomb("xl/worksheets/sheet1.xml", ws, "<c><v>1</v></c>", GIB / 4, "</row></sheetData></worksheet>");
    workbook_with(dir.path(), "wide.xlsx", part);
    let (code, _, err) = ncsheet(dir.path(), &["eval", "wide.xlsx", "A1", "--max-zip-ratio", "100000"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("xl/worksheets/sheet1.xml") && err.contains("column 16385"), "{err}");
}

/// A sheet's `<col>` elements repeated (issue 30, seventh round): each column is kept once
/// however many elements name it. 200,000 `<col min="3" max="16384" hidden="1"/>` (a 750 KB
/// file) hid 3.3 billion columns one by one and 1,000,000 `<col min="1" max="1024"
/// width="3"/>` asked for a billion widths: both aborted at the cap. ECMA-376 Part 1,
/// 18.3.1.13 (`col`): min and max are the first and last column, 1-based, the element sets
/// their width and `hidden`; a later element wins where two overlap, as before the fix, so
/// column B keeps the width of the last element naming it (VBA reference, "Range.ColumnWidth")
/// and C and XFD are hidden (`Debug.Print` writes no space between two Booleans).
#[test]
fn repeated_column_ranges_cost_their_columns_not_their_count() {
    let dir = tempfile::tempdir().unwrap();
    // Each element differs (`style`), or the part would be refused as a zip bomb first.
    let hidden: String =
        (0..200_000).map(|i| format!(r#"<col min="3" max="16384" hidden="1" style="{i}"/>"#)).collect();
    let sized: String = (0..1_000_000).map(|i| format!(r#"<col min="1" max="1024" width="3" style="{i}"/>"#)).collect();
    let last = r#"<col min="2" max="2" width="12.5"/>"#;
    let sheet = format!(
        "<worksheet><cols>{hidden}{sized}{last}</cols><sheetData><row r=\"1\"><c r=\"A1\"><v>1</v></c></row></sheetData></worksheet>"
    );
    workbook_with(dir.path(), "cols.xlsx", small("xl/worksheets/sheet1.xml", &sheet));
    let (code, out, err) = ncsheet(dir.path(), &["eval", "cols.xlsx", "A1"]);
    assert_eq!((code, out.trim()), (0, "1"), "{err}");
    let bas = "Sub Main()\n    Debug.Print Columns(\"B\").ColumnWidth; Columns(\"C\").Hidden; Columns(\"XFD\").Hidden\nEnd Sub\n";
    std::fs::write(dir.path().join("cols.bas"), bas).unwrap();
    let (code, _, err) = ncsheet(dir.path(), &["run", "cols.xlsx", "cols.bas"]);
    assert_eq!((code, printed(&err)), (0, "12.5 TrueTrue"), "{err}");
}

/// An array formula over a whole sheet in a circular reference (issue 30, seventh round): its
/// cycle starts from the values the file cached, which cost the cells the file holds. The
/// area's 17 billion items were allocated at once (400 GB asked for by a 1 KB file, an abort).
/// Excel opens a file with a circular reference showing the values it cached for the cycle's
/// cells ("Circular reference" warning; nothing is recomputed), here 1 and 1.
#[test]
fn a_circular_array_formula_over_a_whole_sheet_starts_from_its_cached_values() {
    let dir = tempfile::tempdir().unwrap();
    let sheet = r#"<worksheet><sheetData><row r="1"><c r="A1"><f t="array" ref="A1:XFD1048576">C1+1</f><v>1</v></c><c r="C1"><f>A1</f><v>1</v></c></row></sheetData></worksheet>"#;
    workbook_with(dir.path(), "cycle.xlsx", small("xl/worksheets/sheet1.xml", sheet));
    let (code, out, err) = ncsheet(dir.path(), &["eval", "cycle.xlsx", "A1", "C1"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.split_whitespace().collect::<Vec<_>>(), ["A1", "1", "C1", "1"], "{err}");
    assert!(err.contains("circular reference"), "{err}");
}

/// UNIQUE of millions of rows (issue 30, seventh round): each row was copied into a vector of
/// its own with a vector of keys beside it, a few hundred bytes a row: 8,388,608 distinct
/// numbers (within the 2^24-item limit) aborted at the 2 GiB cap, 16,000,000 at 4 GB. The
/// numbers 1 to 8,388,608 are all distinct (by hand), so UNIQUE keeps every row.
#[test]
fn unique_of_millions_of_rows_stays_within_memory() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("u.csv"), "\"=ROWS(UNIQUE(TOCOL(SEQUENCE(1048576,8))))\"\n").unwrap();
    let (code, out, err) = ncsheet(dir.path(), &["eval", "u.csv", "A1"]);
    assert_eq!((code, out.trim()), (0, "8388608"), "{err}");
}

// ---------------------------------------------------------------------------------------
// csv

#[test]
fn one_far_cell_costs_the_cells_that_exist_not_the_address_space() {
    let dir = tempfile::tempdir().unwrap();
    // A1 and XFD1048576: a 1 MB file.
    let text = format!("1{}{}2\n", "\n".repeat(1_048_575), ",".repeat(16_383));
    std::fs::write(dir.path().join("far.csv"), text).unwrap();
    let (code, out, err) = ncsheet(dir.path(), &["eval", "far.csv", "A1", "XFD1048576"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.split_whitespace().collect::<Vec<_>>(), ["A1", "1", "XFD1048576", "2"]);
    refused(dir.path(), &["eval", "far.csv", "A1:XFD1048576"], &["A1:XFD1048576", "17179869184 cells"]);
    refused(dir.path(), &["eval", "far.csv"], &["17179869184 cells"]);
}

#[test]
fn csv_fields_and_lines_past_their_limits_are_refused_with_the_line() {
    let dir = tempfile::tempdir().unwrap();
    // A field past the option's limit, and one within the option but past the 32,767
    // characters of a cell (Excel's limit, tests/hostile_cells.rs), which no option raises.
    std::fs::write(dir.path().join("field.csv"), format!("1\n2,\"{}\"\n", "x".repeat(2 << 10))).unwrap();
    refused(dir.path(), &["eval", "field.csv", "A1", "--max-csv-field", "1K"], &["line 2", "1 KiB", "--max-csv-field"]);
    let (code, out, err) = ncsheet(dir.path(), &["eval", "field.csv", "A1", "--max-csv-field", "4K"]);
    assert_eq!((code, out.trim()), (0, "1"), "{err}");
    std::fs::write(dir.path().join("long.csv"), format!("1\n2,\"{}\"\n", "x".repeat(2 << 20))).unwrap();
    refused(dir.path(), &["eval", "long.csv", "A1", "--max-csv-field", "4M"], &["line 2", "Sheet1!B2", "32767"]);
    // A 1 GiB line: refused before the reader buffers it (it took 8.4 GB).
    let line = format!("1\n{}\n", "y,".repeat(1 << 29));
    std::fs::write(dir.path().join("line.csv"), line).unwrap();
    refused(dir.path(), &["eval", "line.csv", "A1"], &["line 2", "64 MiB", "--max-csv-line"]);
}

// ---------------------------------------------------------------------------------------
// ballpath and --timeout

const BUMP: [&str; 10] = [
    "ballpath",
    "--surface",
    "15*EXP(-16*((x/50)^2+(y/50)^2))",
    "--radius",
    "3",
    "--x",
    "-25:25",
    "--y",
    "-25:25",
    "--retract",
];

#[test]
fn ball_paths_past_the_point_limit_are_refused_before_they_are_built() {
    let dir = tempfile::tempdir().unwrap();
    let with = |more: &[&'static str]| -> Vec<&'static str> { BUMP.iter().chain(more).copied().collect() };
    refused(dir.path(), &with(&["--stepover", "1", "--step", "1e-9"]), &["--max-points", "4000000"]);
    refused(dir.path(), &with(&["--stepover", "0.005", "--step", "0.005"]), &["100020001 points", "--max-points"]);
    refused(dir.path(), &with(&["--stepover", "1", "--step", "1", "--tolerance", "1e-12"]), &["tolerance", "0.000001"]);
}

#[test]
fn every_command_stops_at_its_timeout() {
    let dir = tempfile::tempdir().unwrap();
    // About 20 s of drop-cutter work in a test build.
    let args: Vec<&str> =
        BUMP.iter().copied().chain(["--stepover", "0.2", "--step", "0.01", "--timeout", "1"]).collect();
    let (code, _, err) = ncsheet(dir.path(), &args);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("--timeout of 1 s"), "{err}");
}

// ---------------------------------------------------------------------------------------
// Real workbooks stay inside every limit

#[test]
fn every_corpus_workbook_loads_under_the_memory_cap() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/excel-corpus");
    let mut files = Vec::new();
    for corpus in ["ironcalc", "public"] {
        collect_workbooks(&root.join(corpus), &mut files);
    }
    if files.is_empty() {
        assert!(std::env::var("CI").as_deref() != Ok("true"), "the corpora are missing under {}", root.display());
        return;
    }
    // The example sheets shipped with ncsheet, csv and xlsx.
    collect_workbooks(&Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets"), &mut files);
    let mut failed = Vec::new();
    for file in &files {
        let (code, _, err) = ncsheet(file.parent().unwrap(), &["info", file.to_str().unwrap()]);
        if code != 0 {
            failed.push(format!("{}: {err}", file.display()));
        }
    }
    assert!(failed.is_empty(), "{} of {} failed:\n{}", failed.len(), files.len(), failed.join("\n"));
}

fn collect_workbooks(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect_workbooks(&path, out);
        } else if path.extension().is_some_and(|e| e == "xlsx" || e == "xlsm" || e == "csv") {
            out.push(path);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Macros: strings, arrays and output past ncsheet's limits

/// Writes `body` as the Sub Main of `m.bas` beside a one-cell workbook `m.csv`.
fn macro_files(dir: &Path, body: &str) {
    std::fs::write(dir.join("m.csv"), "1\n").unwrap();
    std::fs::write(dir.join("m.bas"), format!("Sub Main()\n{body}\nEnd Sub\n")).unwrap();
}

#[test]
fn macro_strings_past_their_limit_stop_the_macro_naming_the_limit_and_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("doubling", "    Dim s\n    s = \"x\"\n    Do\n        s = s & s\n    Loop", 5),
        ("replace", "    Dim s\n    s = \"ab\"\n    Do\n        s = Replace(s, \"a\", \"aa\")\n    Loop", 5),
        ("space", "    Dim s\n    s = Space(1E+9)", 3),
        ("space-in-call", "    Debug.Print Len(Space(2E+9))", 2),
        // Measured before it is built: 5 GB of delimiters were asked for at once.
        ("join", "    ReDim a(5000000)\n    x = Join(a, String(1000, \"x\"))", 3),
    ];
    for (name, body, line) in cases {
        macro_files(dir.path(), body);
        let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas"]);
        assert_eq!(code, 1, "{name}: {err}");
        for word in ["16777216 characters", "--max-string", &format!("m.bas:{line}:")] {
            assert!(err.contains(word), "{name}: '{word}' missing from: {err}");
        }
    }
}

#[test]
fn max_string_raises_and_lowers_the_macro_string_limit() {
    let dir = tempfile::tempdir().unwrap();
    // 20 million characters: past the default, within a raised limit.
    macro_files(dir.path(), "    Debug.Print Len(Space(20000000) & \"ab\")");
    refused(dir.path(), &["run", "m.csv", "m.bas"], &["--max-string"]);
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas", "--max-string", "33554432"]);
    assert_eq!((code, printed(&err)), (0, "20000002"));
    refused(dir.path(), &["run", "m.csv", "m.bas", "--max-string", "100"], &["100 characters", "--max-string"]);
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas", "--max-string", "4294967296"]);
    assert!(code == 2 && err.contains("--max-string") && err.contains("1073741824"), "{err}");
}

#[test]
fn macro_arrays_past_their_limit_stop_the_macro_naming_the_limit_and_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (body, items) in [
        ("    Dim a(1 To 2000000000)", "2000000000 items"),
        ("    Dim a(1 To 100000, 1 To 100000)", "10000000000 items"),
        ("    Dim a()\n    ReDim a(0 To 20000000)", "20000001 items"),
    ] {
        macro_files(dir.path(), body);
        refused(dir.path(), &["run", "m.csv", "m.bas"], &[items, "10000000", "--max-array-items"]);
    }
    macro_files(dir.path(), "    Dim a(1 To 20)\n    a(20) = 5\n    Debug.Print UBound(a) + a(20)");
    refused(dir.path(), &["run", "m.csv", "m.bas", "--max-array-items", "19"], &["20 items", "--max-array-items"]);
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas", "--max-array-items", "20"]);
    assert_eq!((code, printed(&err)), (0, "25"));
}

#[test]
fn a_macro_holding_too_much_in_all_its_strings_and_arrays_stops_naming_the_limit_and_the_option() {
    let dir = tempfile::tempdir().unwrap();
    // Each string and each array is within its own limit; together they pass 2 GiB.
    let cases = [
        (
            "array of long strings",
            "    Dim a(1 To 1000), i\n    For i = 1 To 1000\n        a(i) = Space(10000000) & i\n    Next",
            4,
        ),
        (
            "a long string in each call",
            "    Debug.Print F(200)\nEnd Sub\nFunction F(n)\n    Dim s\n    s = Space(15000000) & n\n    If n > 0 Then F = F(n - 1)\nEnd Function\nSub Unused()",
            6,
        ),
        (
            "an array in each call",
            "    Debug.Print G(200)\nEnd Sub\nFunction G(n)\n    Dim a\n    a = Evaluate(\"SEQUENCE(1000000)\")\n    If n > 0 Then G = G(n - 1)\nEnd Function\nSub Unused()",
            6,
        ),
    ];
    // Text work counts against the statement limit too (docs/limits.md): raised here, so that
    // memory is the limit these runs reach.
    for (name, body, line) in cases {
        macro_files(dir.path(), body);
        let args = ["run", "m.csv", "m.bas", "--max-depth", "300", "--max-statements", "1000000000"];
        let (code, _, err) = ncsheet(dir.path(), &args);
        assert_eq!(code, 1, "{name}: {err}");
        for word in ["1024.0 MiB allowed", "--max-memory", &format!("m.bas:{line}:")] {
            assert!(err.contains(word), "{name}: '{word}' missing from: {err}");
        }
    }
    // 30 strings of 10 MB: within the default, past a lowered limit.
    macro_files(dir.path(), "    Dim a(1 To 30), i\n    For i = 1 To 30\n        a(i) = Space(10000000) & i\n    Next\n    Debug.Print Len(a(30))");
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas"]);
    assert_eq!((code, printed(&err)), (0, "10000002"));
    refused(dir.path(), &["run", "m.csv", "m.bas", "--max-memory", "100M"], &["100.0 MiB allowed", "--max-memory"]);
    // One string shared by a thousand items is held once.
    macro_files(
        dir.path(),
        "    Dim a(1 To 1000), i, s\n    s = Space(10000000)\n    For i = 1 To 1000\n        a(i) = s\n    Next\n    Debug.Print Len(a(1000))",
    );
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas"]);
    assert_eq!((code, printed(&err)), (0, "10000000"));
}

#[test]
fn arrays_stored_into_their_own_items_count_the_tables_each_copy_keeps() {
    // Each turn stores the array into its next item, and each copy keeps its own table of the
    // arrays its items hold: 3,000 turns held 845 MB counted as under 300 MiB, and 100,000
    // aborted at a 4 GiB cap.
    let dir = tempfile::tempdir().unwrap();
    let body = "    Dim a(), i As Long\n    ReDim a(0)\n    For i = 1 To 3000\n        ReDim Preserve a(i)\n        a(i) = a\n    Next\n    Debug.Print UBound(a)";
    macro_files(dir.path(), body);
    refused(dir.path(), &["run", "m.csv", "m.bas", "--max-memory", "300M"], &["300.0 MiB allowed", "--max-memory"]);
}

#[test]
fn print_and_msgbox_floods_stop_at_the_output_limit() {
    let dir = tempfile::tempdir().unwrap();
    let megabyte = "    Dim s\n    s = Space(1048575) & \"|\"\n    Do\n";
    // Everything up to the limit is written: 63 lines of a MiB and their line ends, or 64 MiB
    // on one line left open.
    for (name, statement, lines) in [
        ("print", "        Debug.Print s", 63),
        ("msgbox", "        MsgBox s", 63),
        ("open line", "        Debug.Print s;", 64),
    ] {
        macro_files(dir.path(), &format!("{megabyte}{statement}\n    Loop"));
        let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas"]);
        assert_eq!(code, 1, "{name}");
        assert!(err.contains("67108864 bytes") && err.contains("--max-output"), "{name}: {}", &err[err.len() - 400..]);
        assert!(err.contains("m.bas:5:"), "{name}: {}", &err[err.len() - 400..]);
        // (The message's caret line has a `|` after a few spaces only.)
        let written = err.matches(&format!("{}|", " ".repeat(100))).count();
        assert_eq!(written, lines, "{name}");
    }
    macro_files(dir.path(), &format!("{megabyte}        Debug.Print s\n    Loop"));
    refused(dir.path(), &["run", "m.csv", "m.bas", "--max-output", "3M"], &["3145728 bytes", "--max-output"]);
}

#[test]
fn macro_output_is_written_as_it_happens() {
    let dir = tempfile::tempdir().unwrap();
    macro_files(dir.path(), "    Dim i\n    Debug.Print \"started\"\n    Do\n        i = i + 1\n    Loop");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["run", "m.csv", "m.bas", "--max-statements", "100000000000", "--timeout", "60"])
        .current_dir(dir.path())
        .stdin(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    std::io::BufRead::read_line(&mut stderr, &mut first).unwrap();
    // The macro is still looping: the line came before the run ended.
    let running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(first, "started\n");
    assert!(running, "the line came only when the macro had ended");
}

#[test]
fn a_macro_stops_at_the_timeout_with_its_line_and_max_seconds_is_the_same_option() {
    let dir = tempfile::tempdir().unwrap();
    let body = "    Dim i, s\n    For i = 1 To 100000\n        s = Evaluate(\"SUM(SEQUENCE(100000))\")\n    Next";
    macro_files(dir.path(), body);
    for option in ["--timeout", "--max-seconds"] {
        let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas", option, "1"]);
        assert_eq!(code, 1, "{option}: {err}");
        assert!(err.contains("--timeout of 1 s") && err.contains("m.bas:"), "{option}: {err}");
    }
}

#[test]
fn csv_export_of_one_far_cell_costs_the_cells_that_exist() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("far.csv"), "1,2\n3,4\n").unwrap();
    let (code, _, err) = ncsheet(dir.path(), &["set", "far.csv", "XFD1048576=7", "-o", "far.xlsx"]);
    assert_eq!(code, 0, "{err}");
    for (from, to) in [("far.xlsx", "out.csv"), ("far.csv", "copy.csv")] {
        if from == "far.csv" {
            let (code, _, err) = ncsheet(dir.path(), &["set", "far.csv", "XFD1048576=7", "--in-place"]);
            assert_eq!(code, 0, "{err}");
        }
        let (code, _, err) = ncsheet(dir.path(), &["export", from, "-o", to]);
        assert_eq!(code, 0, "{from}: {err}");
        // A line per row and a field per column up to the one far cell: about a MiB, not the
        // 17 billion fields of the full table.
        let size = std::fs::metadata(dir.path().join(to)).unwrap().len();
        assert!(size < 2 << 20, "{from}: {size} bytes");
        // It reads back as the same sheet.
        let (code, out, err) = ncsheet(dir.path(), &["eval", to, "A1", "B2", "XFD1048576", "XFC1048576"]);
        assert_eq!(code, 0, "{err}");
        let values: Vec<&str> = out.lines().map(|l| l.rsplit(' ').next().unwrap()).collect();
        assert_eq!(values, ["1", "4", "7", ""], "{out}");
    }
}

#[test]
fn a_max_depth_past_ncsheets_limit_is_a_usage_error_naming_the_range() {
    let dir = tempfile::tempdir().unwrap();
    macro_files(dir.path(), "    Debug.Print 1");
    let (code, _, err) = ncsheet(dir.path(), &["run", "m.csv", "m.bas", "--max-depth", "1000000"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--max-depth") && err.contains("1 to 10000"), "{err}");
    assert!(!err.contains("os error"), "{err}");
}
