//! How cells look, set by macros as automation sets it (`formats.rs`): `NumberFormat` changes
//! what a cell shows and reads back, Null over cells that differ; alignment, bold, wrap and
//! fill read back with Excel's constants; `ColumnWidth`, `RowHeight` and `AutoFit`; and a
//! macro of the BOM-merging kind, run by `ncsheet run`, whose saved xlsx holds the formats
//! (read from the package's XML as ECMA-376 lays it out, and shown by LibreOffice).
//!
//! Expected values from Microsoft's Excel VBA reference: "Range.NumberFormat property"
//! (Null when the cells' formats differ), "Range.Text property" (the value as formatted),
//! "XlHAlign enumeration" / "XlVAlign enumeration", "Range.ColumnWidth property" (one unit is
//! the width of one character of the Normal style; Null when the columns differ),
//! "Range.AutoFit method" (whole rows or columns, else an error), "Interior.Color property"
//! (RGB), and Excel's standard sizes (8.43 characters, 15 points).

mod common;

use std::io::Read;
use std::path::Path;
use std::process::Command;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::{self, RunOptions, RunOutput, SheetLook};
use ncsheet::workbook::Workbook;

fn run(wb: &mut Workbook, body: &str) -> RunOutput {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    vba::run(wb, &src, "formats.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn fails(wb: &mut Workbook, body: &str) -> String {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    match vba::run(wb, &src, "formats.bas", &RunOptions::default()) {
        Ok(_) => panic!("ran: {body}"),
        Err(e) => e.to_string(),
    }
}

fn look<'a>(out: &'a RunOutput, sheet: &str) -> &'a SheetLook {
    &out.looks.iter().find(|(name, _)| name == sheet).unwrap_or_else(|| panic!("no look of {sheet}")).1
}

fn format_of<'a>(look: &'a SheetLook, cell: &str) -> Option<&'a str> {
    look.number_formats.get(&parse_cell(cell).unwrap()).map(String::as_str)
}

#[test]
fn number_format_changes_what_the_cell_shows_and_reads_back() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = 1234.5\n    Range(\"A2\").Value = 0.25\n\
         \x20   Debug.Print Range(\"A1\").NumberFormat & \"|\" & Range(\"A1\").Text\n\
         \x20   Range(\"A1\").NumberFormat = \"#,##0.00\"\n    Range(\"A2\").NumberFormat = \"0%\"\n\
         \x20   Debug.Print Range(\"A1\").NumberFormat & \"|\" & Range(\"A1\").Text & \"|\" & Range(\"A2\").Text\n\
         \x20   Debug.Print IsNull(Range(\"A1:A2\").NumberFormat); Range(\"A1\").Value",
    );
    // A cell never formatted is General; the value stays the number, only its text changes.
    assert_eq!(out.printed, ["General|1234.5", "#,##0.00|1,234.50|25%", "True 1234.5 "]);
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), Value::Number(1234.5));
    let sheet = look(&out, "Sheet1");
    assert_eq!(format_of(sheet, "A1"), Some("#,##0.00"));
    assert_eq!(format_of(sheet, "A2"), Some("0%"));
}

#[test]
fn a_column_format_reaches_the_cells_written_after_it() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = 603\n    Range(\"B1\").Value = 603\n\
         \x20   Columns(\"A\").NumberFormat = \"0000\"\n    Range(\"A3\").Value = 42\n\
         \x20   Range(\"A4\").NumberFormat = \"General\"\n    Range(\"A4\").Value = 7\n\
         \x20   Debug.Print Range(\"A1\").Text & \"|\" & Range(\"A3\").Text & \"|\" & Range(\"A4\").Text & \"|\" & Range(\"B1\").Text\n\
         \x20   Debug.Print IsNull(Columns(\"A\").NumberFormat); IsNull(Columns(\"A:B\").NumberFormat)",
    );
    // A4 was given its own General after the column's format; the whole column A answers
    // Null since A4 differs.
    assert_eq!(out.printed, ["0603|0042|7|603", "TrueTrue"]);
    let sheet = look(&out, "Sheet1");
    assert_eq!(format_of(sheet, "A1"), Some("0000"));
    assert_eq!(format_of(sheet, "A3"), Some("0000"));
    assert_eq!(format_of(sheet, "A4"), None);
    assert_eq!(format_of(sheet, "B1"), None);
}

#[test]
fn alignment_bold_wrap_and_fill_read_back_as_excels_constants() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = \"x\"\n\
         \x20   Debug.Print Range(\"A1\").HorizontalAlignment & \" \" & Range(\"A1\").VerticalAlignment & \" \" & \
         CStr(Range(\"A1\").Font.Bold) & \" \" & Range(\"A1\").Interior.Color\n\
         \x20   With Range(\"A1:B2\")\n        .HorizontalAlignment = xlLeft\n        .VerticalAlignment = xlCenter\n\
         \x20       .WrapText = True\n        .Font.Bold = True\n    End With\n\
         \x20   Range(\"B2\").HorizontalAlignment = xlRight\n    Range(\"A1\").Interior.Color = RGB(255, 0, 0)\n\
         \x20   Debug.Print Range(\"A1\").HorizontalAlignment & \" \" & Range(\"B2\").HorizontalAlignment & \" \" & \
         Range(\"A2\").VerticalAlignment & \" \" & CStr(Range(\"B1\").WrapText) & \" \" & CStr(Range(\"A1:B2\").Font.Bold)\n\
         \x20   Debug.Print CStr(IsNull(Range(\"A1:B2\").HorizontalAlignment)) & \" \" & Range(\"A1\").Interior.Color",
    );
    // xlGeneral 1, xlBottom -4107, no fill white 16777215; xlLeft -4131, xlRight -4152,
    // xlCenter -4108; RGB(255, 0, 0) is 255.
    assert_eq!(out.printed, ["1 -4107 False 16777215", "-4131 -4152 -4108 True True", "True 255"]);
    let style = look(&out, "Sheet1").cell_styles[&parse_cell("A1").unwrap()];
    assert_eq!((style.horizontal, style.bold, style.wrap, style.fill), (Some(-4131), true, true, Some(255)));
}

#[test]
fn formatting_values_excel_refuses_are_error_1004() {
    let mut wb = Workbook::with_sheet();
    let e = fails(&mut wb, "    Range(\"A1\").HorizontalAlignment = 3");
    assert!(e.contains("XlHAlign") && e.contains("1004"), "{e}");
    let e = fails(&mut wb, "    Columns(\"B\").ColumnWidth = 300");
    assert!(e.contains("0 to 255") && e.contains("1004"), "{e}");
    // "Range.AutoFit method": the range must be whole rows or whole columns.
    let e = fails(&mut wb, "    Range(\"A1:B2\").AutoFit");
    assert!(e.contains("whole rows or whole columns") && e.contains("1004"), "{e}");
    // A font member ncsheet does not keep and that is not harmless to skip (`unmodelled.rs`)
    // is refused by name, saying what it keeps.
    let e = fails(&mut wb, "    Range(\"A1\").Font.Name = \"Arial\"");
    assert!(e.contains("Font.Name") && e.contains("Bold"), "{e}");
}

#[test]
fn column_width_and_row_height_set_read_and_are_kept() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Debug.Print Columns(\"C\").ColumnWidth & \" \" & Rows(4).RowHeight\n\
         \x20   Columns(\"C\").ColumnWidth = 20\n    Range(\"D1\").ColumnWidth = 12.5\n    Rows(4).RowHeight = 30\n\
         \x20   Debug.Print Range(\"C7\").ColumnWidth & \" \" & Columns(\"D\").ColumnWidth & \" \" & \
         Range(\"A4\").RowHeight; IsNull(Range(\"C1:D1\").ColumnWidth)",
    );
    // Excel's standard width 8.43 characters and height 15 points before any is set.
    assert_eq!(out.printed, ["8.43 15", "20 12.5 30True"]);
    let sheet = look(&out, "Sheet1");
    assert_eq!(sheet.column_widths, [(2, 20.0), (3, 12.5)]);
    assert_eq!(sheet.row_heights, [(3, 30.0)]);
}

#[test]
fn autofit_sizes_a_column_to_its_longest_shown_text() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = \"Qty\"\n    Range(\"A2\").Value = 1234567890123#\n\
         \x20   Range(\"B1\").Value = 5\n    Range(\"B1\").NumberFormat = \"0.000000\"\n\
         \x20   Columns(\"A:C\").AutoFit\n\
         \x20   Debug.Print Columns(\"A\").ColumnWidth & \" \" & Columns(\"B\").ColumnWidth & \" \" & Columns(\"C\").ColumnWidth",
    );
    let widths: Vec<f64> = out.printed[0].split(' ').map(|w| w.parse().unwrap()).collect();
    // One unit of ColumnWidth is one digit of the Normal font: the 13 digits of A2 and the
    // 8 characters of B1 as shown ("5.000000") fit, with less than two digits to spare; C,
    // empty, keeps the standard width.
    assert!((13.0..15.0).contains(&widths[0]), "{widths:?}");
    assert!((8.0..10.0).contains(&widths[1]), "{widths:?}");
    assert_eq!(widths[2], 8.43);
}

#[test]
fn rows_autofit_gives_a_wrapped_cell_a_line_height_each() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = \"one\" & vbLf & \"two\"\n    Range(\"A1\").WrapText = True\n\
         \x20   Range(\"A2\").Value = \"one\" & vbLf & \"two\"\n    Rows(\"1:3\").AutoFit\n\
         \x20   Debug.Print Rows(1).RowHeight & \" \" & Rows(2).RowHeight & \" \" & Rows(3).RowHeight",
    );
    // Excel's default row is 15 points a line of Calibri 11: the wrapped cell shows its two
    // lines; the unwrapped one, and the empty row, one.
    assert_eq!(out.printed, ["30 15 15"]);
}

#[test]
fn a_copied_sheet_keeps_its_formats() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = 7\n    Range(\"A1\").NumberFormat = \"0.0\"\n\
         \x20   Worksheets(1).Copy After:=Worksheets(1)\n    Debug.Print ActiveSheet.Name & \" \" & ActiveSheet.Range(\"A1\").Text",
    );
    assert_eq!(out.printed, ["Sheet1 (2) 7.0"]);
    assert_eq!(format_of(look(&out, "Sheet1 (2)"), "A1"), Some("0.0"));
}

// Excel's Sort moves whole cells: a row's number formats and fonts go with its values
// ("Range.Sort method" sorts the range; Excel's "Sort data in a range or table": the rows are
// rearranged, each cell with its formatting). Rows (3,30) (1,10 shown 0.00) (2 bold,20)
// sorted by column A: (1,10 shown 0.00) (2 bold,20) (3,30).
#[test]
fn a_sort_moves_each_cells_format_with_its_value() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = 3: Range(\"B1\").Value = 30\n\
         \x20   Range(\"A2\").Value = 1: Range(\"B2\").Value = 10\n\
         \x20   Range(\"A3\").Value = 2: Range(\"B3\").Value = 20\n\
         \x20   Range(\"B2\").NumberFormat = \"0.00\"\n    Range(\"A3\").Font.Bold = True\n\
         \x20   Range(\"A1:B3\").Sort Key1:=Range(\"A1\"), Order1:=xlAscending, Header:=xlNo\n\
         \x20   Debug.Print Range(\"B1\").Text & \"|\" & Range(\"B2\").Text & \"|\" & Range(\"A2\").Font.Bold & \"|\" & Range(\"A3\").Font.Bold",
    );
    assert_eq!(out.printed, ["10.00|20|True|False"]);
    let sheet = look(&out, "Sheet1");
    assert_eq!((format_of(sheet, "B1"), format_of(sheet, "B2")), (Some("0.00"), None));
    let bold = |cell: &str| sheet.cell_styles.get(&parse_cell(cell).unwrap()).is_some_and(|s| s.bold);
    assert_eq!((bold("A2"), bold("A3")), (true, false));
}

// Copy with a Destination, and PasteSpecial xlPasteAll, paste whole cells, formats
// included; xlPasteValues pastes the values alone ("Range.Copy method": "Copies the range to
// the specified range or to the Clipboard"; "XlPasteType enumeration": xlPasteAll
// "Everything will be pasted", xlPasteValues "Values are pasted"). 0.5 shown 0% is 50%.
#[test]
fn a_copy_with_a_destination_brings_the_formats() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Sheet2").unwrap();
    let out = run(
        &mut wb,
        "    Range(\"A1\").Value = 0.5: Range(\"A1\").NumberFormat = \"0%\"\n\
         \x20   Range(\"B1\").Value = 2: Range(\"B1\").Font.Bold = True\n\
         \x20   Rows(1).Copy Destination:=Rows(3)\n\
         \x20   Range(\"A1:B1\").Copy Destination:=Worksheets(\"Sheet2\").Range(\"C2\")\n\
         \x20   Range(\"A1\").Copy\n    Range(\"E1\").PasteSpecial Paste:=xlPasteValues\n\
         \x20   Range(\"F1\").PasteSpecial Paste:=xlPasteAll\n\
         \x20   Debug.Print Range(\"A3\").Text & \"|\" & Range(\"B3\").Font.Bold & \"|\" & \
         Worksheets(\"Sheet2\").Range(\"C2\").Text & \"|\" & Range(\"E1\").Text & \"|\" & Range(\"F1\").Text",
    );
    assert_eq!(out.printed, ["50%|True|50%|0.5|50%"]);
    let (one, two) = (look(&out, "Sheet1"), look(&out, "Sheet2"));
    assert_eq!((format_of(one, "A3"), format_of(two, "C2"), format_of(one, "E1")), (Some("0%"), Some("0%"), None));
    let bold = |look: &SheetLook, cell: &str| look.cell_styles.get(&parse_cell(cell).unwrap()).is_some_and(|s| s.bold);
    assert_eq!((bold(one, "B3"), bold(two, "D2")), (true, true));
}

// ---- a macro of the BOM kind, run and saved as a user runs it ----------------------------

/// A bill of materials with a part repeated and the part numbers as text with leading zeros.
const BOM: &str =
    "Part,Description,Qty\n0603,Resistor 10k,2\n0805,Capacitor 100n,4\n0603,Resistor 10k,1\n1206,Diode,1\n";

/// Ours: merges the rows of one part into a new sheet, summing their quantities, then
/// formats it as BOM macros do (part numbers as numbers shown with four digits, the header
/// bold, everything left-aligned, the columns fitted).
const MERGE: &str = r#"Sub MergeBom()
    Dim src As Worksheet, dst As Worksheet
    Set src = ActiveSheet
    Set dst = Sheets.Add(After:=Sheets(Sheets.Count))
    dst.Name = "Merged"
    src.Range("A1:C1").Copy dst.Range("A1")
    Dim last As Long, r As Long, out As Long, k As Long, found As Boolean
    last = src.Cells(src.Rows.Count, 1).End(xlUp).Row
    out = 1
    For r = 2 To last
        found = False
        For k = 2 To out
            If dst.Cells(k, 1).Value = Val(src.Cells(r, 1).Value) Then
                dst.Cells(k, 3).Value = dst.Cells(k, 3).Value + src.Cells(r, 3).Value
                found = True
            End If
        Next k
        If Not found Then
            out = out + 1
            dst.Cells(out, 1).Value = Val(src.Cells(r, 1).Value)
            dst.Cells(out, 2).Value = src.Cells(r, 2).Value
            dst.Cells(out, 3).Value = src.Cells(r, 3).Value
        End If
    Next r
    With dst
        .Columns("A").NumberFormat = "0000"
        .Range("A1:C1").Font.Bold = True
        .UsedRange.HorizontalAlignment = xlLeft
        .Columns.AutoFit
    End With
    Debug.Print dst.Range("A2").Text & " " & dst.Range("A4").Text & " " & dst.Columns("B").ColumnWidth
End Sub
"#;

fn ncsheet(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

/// A part of the saved package, as text.
fn part(xlsx: &Path, name: &str) -> String {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(xlsx).unwrap()).unwrap();
    let mut text = String::new();
    zip.by_name(name).unwrap().read_to_string(&mut text).unwrap();
    text
}

/// The value of attribute `name` in the XML element text `element`.
fn attribute<'a>(element: &'a str, name: &str) -> Option<&'a str> {
    let at = element.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&element[at..at + element[at..].find('"')?])
}

/// The `<xf>` of styles.xml's cellXfs that cell `cell` of sheet part `sheet_xml` names by its
/// `s` attribute (ECMA-376 Part 1, 18.3.1.4 and 18.8.10).
fn cell_xf(styles: &str, sheet_xml: &str, cell: &str) -> String {
    let at = sheet_xml.find(&format!("<c r=\"{cell}\"")).unwrap_or_else(|| panic!("no cell {cell}"));
    let element = &sheet_xml[at..at + sheet_xml[at..].find('>').unwrap()];
    let index: usize = attribute(element, "s").map_or(0, |s| s.parse().unwrap());
    let xfs = &styles[styles.find("<cellXfs").unwrap()..styles.find("</cellXfs>").unwrap()];
    let xf = xfs.split("<xf ").nth(index + 1).expect("the xf");
    let open = xf.find('>').unwrap();
    let end = if xf[..open].ends_with('/') { open } else { xf.find("</xf>").unwrap() };
    format!(" {}", &xf[..end])
}

#[test]
fn a_bom_merging_macro_runs_and_its_saved_file_keeps_the_formats() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("bom.csv");
    std::fs::write(&book, BOM).unwrap();
    let bas = dir.path().join("merge.bas");
    std::fs::write(&bas, MERGE).unwrap();
    let saved = dir.path().join("merged.xlsx");
    let out = ncsheet(&["run", book.to_str().unwrap(), bas.to_str().unwrap(), "--save", saved.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    // "Capacitor 100n" is the longest text of column B: 14 characters.
    assert!(stderr.contains("0603 1206 14"), "{stderr}");
    let cells = ncsheet(&["eval", saved.to_str().unwrap(), "Merged!A2:C4", "--format", "csv"]);
    let cells = String::from_utf8(cells.stdout).unwrap();
    // The part numbers are numbers again (Val), shown with the column's four digits.
    assert_eq!(cells.lines().collect::<Vec<_>>(), ["0603,Resistor 10k,3", "0805,Capacitor 100n,4", "1206,Diode,1"]);
    let raw = ncsheet(&["eval", saved.to_str().unwrap(), "Merged!A2", "--format", "csv", "--raw"]);
    assert_eq!(String::from_utf8(raw.stdout).unwrap().trim(), "603");

    let styles = part(&saved, "xl/styles.xml");
    let sheet = part(&saved, "xl/worksheets/sheet2.xml");
    let a2 = cell_xf(&styles, &sheet, "A2");
    let id = attribute(&a2, "numFmtId").unwrap();
    assert!(styles.contains(&format!("numFmtId=\"{id}\" formatCode=\"0000\"")), "{a2} / {styles}");
    assert!(a2.contains("horizontal=\"left\""), "{a2}");
    // The header is bold: its xf's font has <b/>.
    let b1 = cell_xf(&styles, &sheet, "B1");
    let font: usize = attribute(&b1, "fontId").unwrap().parse().unwrap();
    let fonts = &styles[styles.find("<fonts").unwrap()..styles.find("</fonts>").unwrap()];
    assert!(fonts.split("<font>").nth(font + 1).unwrap().contains("<b/>"), "{fonts}");
    // Column B fitted to 14 characters: wider than the standard width.
    let cols = &sheet[sheet.find("<cols>").expect("column widths")..];
    assert!(cols.contains("min=\"2\" max=\"2\""), "{cols}");

    // LibreOffice shows the part numbers with the saved format.
    let Some(soffice) = common::soffice() else {
        eprintln!("skipped the LibreOffice part: soffice is not installed");
        return;
    };
    let shown = libreoffice_shown(&soffice, dir.path(), &saved, 2);
    assert_eq!(shown.lines().nth(1), Some("0603,Resistor 10k,3"), "{shown}");
}

/// Sheet `sheet` (from 1) of `xlsx` as LibreOffice exports it to csv, cells as shown.
fn libreoffice_shown(soffice: &Path, dir: &Path, xlsx: &Path, sheet: usize) -> String {
    let out = dir.join("lo");
    let profile = common::recalculating_profile(&dir.join("profile"));
    // Filter options: comma, quote, UTF-8, from line 1, default columns, language, quoted
    // text, detect numbers, save as shown, formulas off, keep spaces off, the sheet.
    let filter = format!("csv:Text - txt - csv (StarCalc):44,34,76,1,,0,false,true,true,false,false,{sheet}");
    let status = Command::new(soffice)
        .arg(&profile)
        .args(["--headless", "--norestore", "--convert-to", &filter, "--outdir"])
        .arg(&out)
        .arg(xlsx)
        .status()
        .unwrap();
    assert!(status.success());
    let stem = xlsx.file_stem().unwrap().to_str().unwrap();
    let named = std::fs::read_dir(&out).unwrap().filter_map(|e| e.ok()).map(|e| e.path());
    let found: Vec<_> = named.filter(|p| p.file_name().unwrap().to_str().unwrap().starts_with(stem)).collect();
    std::fs::read_to_string(found.first().unwrap_or_else(|| panic!("LibreOffice wrote no csv for {stem}"))).unwrap()
}

#[test]
fn a_patched_original_keeps_the_macros_formats() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("bom.csv");
    std::fs::write(&book, BOM).unwrap();
    let plain = dir.path().join("plain.bas");
    std::fs::write(&plain, "Sub Main()\n    Range(\"D1\").Value = 1\nEnd Sub\n").unwrap();
    let original = dir.path().join("original.xlsx");
    let out = ncsheet(&["run", book.to_str().unwrap(), plain.to_str().unwrap(), "--save", original.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // Values only: the original package is patched and nothing is said of formats.
    let patched = dir.path().join("values.xlsx");
    let out =
        ncsheet(&["run", original.to_str().unwrap(), plain.to_str().unwrap(), "--save", patched.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !stderr.contains("number formats"), "{stderr}");
    // A macro that formats: the patched package holds its formats, and no loss is said.
    let bas = dir.path().join("format.bas");
    std::fs::write(&bas, "Sub Main()\n    Columns(\"C\").NumberFormat = \"0.0\"\nEnd Sub\n").unwrap();
    let saved = dir.path().join("formatted.xlsx");
    let out = ncsheet(&["run", original.to_str().unwrap(), bas.to_str().unwrap(), "--save", saved.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !stderr.contains("number formats"), "{stderr}");
    let cells = ncsheet(&["eval", saved.to_str().unwrap(), "C2:C3", "--format", "csv"]);
    assert_eq!(String::from_utf8(cells.stdout).unwrap().lines().collect::<Vec<_>>(), ["2.0", "4.0"]);
}

/// "Interior.ColorIndex property": set to xlColorIndexNone (xlNone, -4142, the XlColorIndex
/// enumeration) for no fill, which is what an unfilled cell answers; Interior.Color then reads
/// white, 16777215, as for any cell without fill. A palette index takes the default palette's
/// colour ("ColorIndex property": 3 is red, RGB(255, 0, 0) = 255; 6 yellow, 65535); past 56
/// it is error 1004.
#[test]
fn interior_color_index_none_clears_the_fill_and_a_palette_index_fills() {
    let out = run(
        &mut Workbook::with_sheet(),
        "    Range(\"A1\").Interior.Color = RGB(255, 0, 0)\n    Debug.Print Range(\"A1\").Interior.Color; Range(\"B1\").Interior.ColorIndex\n    \
         Range(\"A1\").Interior.ColorIndex = xlNone\n    Debug.Print Range(\"A1\").Interior.Color; Range(\"A1\").Interior.ColorIndex\n    \
         Range(\"A2\").Interior.ColorIndex = 3\n    Range(\"A3\").Interior.ColorIndex = 6\n    \
         Debug.Print Range(\"A2\").Interior.Color; Range(\"A2\").Interior.ColorIndex; Range(\"A3\").Interior.Color; Range(\"A3\").Interior.ColorIndex",
    );
    assert_eq!(out.printed, vec![" 255 -4142 ", " 16777215 -4142 ", " 255  3  65535  6 "]);
    let refused = fails(&mut Workbook::with_sheet(), "    Range(\"A1\").Interior.ColorIndex = 57");
    assert!(refused.contains("1004") && refused.contains("ColorIndex"), "{refused}");
}

/// The font's colour, size and underline, set and read back in Excel's terms: "Font.Color
/// property" (RGB: RGB(0, 0, 255) = 16711680), "Font.ColorIndex property" (the default
/// palette: 5 is blue, 3 red (255), 10 green RGB(0, 128, 0) = 32768; xlColorIndexAutomatic
/// -4105 for an automatic colour, whose Color is black, 0), "Font.Size property" (points; 11
/// for the Normal style's Calibri), "XlUnderlineStyle enumeration" (xlUnderlineStyleNone
/// -4142, Single 2, Double -4119). A range whose cells differ reads Null, as
/// "Range.NumberFormat" says of a mixed range.
#[test]
fn font_colour_size_and_underline_set_and_read_as_excel_gives_them() {
    let out = run(
        &mut Workbook::with_sheet(),
        "    With Range(\"A1\").Font\n        .Color = RGB(0, 0, 255)\n        .Size = 14.5\n        .Underline = xlUnderlineStyleDouble\n    End With\n    \
         Debug.Print Range(\"A1\").Font.Color; Range(\"A1\").Font.ColorIndex; Range(\"A1\").Font.Size; Range(\"A1\").Font.Underline\n    \
         Debug.Print Range(\"B1\").Font.Color; Range(\"B1\").Font.ColorIndex; Range(\"B1\").Font.Size; Range(\"B1\").Font.Underline\n    \
         Range(\"B1\").Font.ColorIndex = 3\n    Range(\"C1\").Font.ColorIndex = 10\n    Range(\"D1\").Font.Underline = True\n    \
         Debug.Print Range(\"B1\").Font.Color; Range(\"C1\").Font.Color; Range(\"C1\").Font.ColorIndex; Range(\"D1\").Font.Underline\n    \
         Range(\"B1\").Font.ColorIndex = xlAutomatic\n    Debug.Print Range(\"B1\").Font.ColorIndex; Range(\"B1\").Font.Color\n    \
         Debug.Print IsNull(Range(\"A1:B1\").Font.Color) & \" \" & IsNull(Range(\"A1:B1\").Font.Size) & \" \" & \
         IsNull(Range(\"B1:B2\").Font.Size) & \" \" & IsNull(Range(\"A1:C1\").Font.Underline)",
    );
    assert_eq!(
        out.printed,
        vec![
            " 16711680  5  14.5 -4119 ",
            " 0 -4105  11 -4142 ",
            " 255  32768  10  2 ",
            "-4105  0 ",
            "True True False True",
        ]
    );
    let refused = fails(&mut Workbook::with_sheet(), "    Range(\"A1\").Font.Size = 500");
    assert!(refused.contains("1004") && refused.contains("Font.Size"), "{refused}");
    let refused = fails(&mut Workbook::with_sheet(), "    Range(\"A1\").Font.Underline = 7");
    assert!(refused.contains("1004") && refused.contains("Underline"), "{refused}");
}
