//! Import details, each on a small package written here by hand the way Excel writes it.

use std::io::{Cursor, Write};
use std::path::Path;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::{parse_cell, Pos};
use ncsheet::io::xlsx::{self, Imported};

fn at(cell: &str) -> Pos {
    parse_cell(cell).unwrap()
}

/// An xlsx package: worksheets given by name and `<sheetData>` content, plus extra
/// `<workbook>` content (defined names).
fn package(sheets: &[(&str, &str)], workbook_extra: &str) -> Vec<u8> {
    package_with_parts(sheets, workbook_extra, "", &[])
}

/// [`package`] with `sheet1_extra` after the first sheet's `<sheetData>` (`<tableParts>`)
/// and more parts by name (a table, the first sheet's relationships).
fn package_with_parts(
    sheets: &[(&str, &str)],
    workbook_extra: &str,
    sheet1_extra: &str,
    parts: &[(&str, &str)],
) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    let mut put = |name: &str, text: String| {
        zip.start_file(name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    };
    put(
        "_rels/.rels",
        r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#.into(),
    );
    let mut sheet_list = String::new();
    let mut rels = String::new();
    for (i, (name, data)) in sheets.iter().enumerate() {
        let n = i + 1;
        sheet_list.push_str(&format!(r#"<sheet name="{name}" sheetId="{n}" r:id="rId{n}"/>"#));
        rels.push_str(&format!(
            r#"<Relationship Id="rId{n}" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet{n}.xml"/>"#
        ));
        let extra = if n == 1 { sheet1_extra } else { "" };
        put(
            &format!("xl/worksheets/sheet{n}.xml"),
            format!(
                r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheetData>{data}</sheetData>{extra}</worksheet>"#
            ),
        );
    }
    put(
        "xl/workbook.xml",
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheets>{sheet_list}</sheets>{workbook_extra}</workbook>"#
        ),
    );
    put(
        "xl/_rels/workbook.xml.rels",
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">{rels}</Relationships>"#
        ),
    );
    for (name, text) in parts {
        put(name, text.to_string());
    }
    zip.finish().unwrap().into_inner()
}

fn load(sheets: &[(&str, &str)], workbook_extra: &str) -> Imported {
    xlsx::load_bytes(&package(sheets, workbook_extra), Path::new("book.xlsx")).unwrap_or_else(|e| panic!("{e}"))
}

fn num(v: f64) -> Value {
    Value::Number(v)
}

/// A sheet saved with two areas selected, as Excel writes a Ctrl+click selection
/// (`<selection activeCell="D4" sqref="A1:B2 D4:E5"/>`, ST_Sqref: references separated by
/// spaces). "Application.Selection property" returns the selected range, and "Range.Areas
/// property": "a collection that contains one object for each selected area": a macro starts
/// with Selection of both areas, 8 cells, its address as Excel prints a union ("Range.Address
/// property": areas separated by commas), For Each over every cell, area by area; ActiveCell
/// D4. Selecting a cell makes it the whole selection again.
#[test]
fn a_saved_selection_of_two_areas_is_the_macros_selection() {
    let views = r#"<sheetViews><sheetView workbookViewId="0"><selection activeCell="D4" sqref="A1:B2 D4:E5"/></sheetView></sheetViews>"#;
    let cells = r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><v>2</v></c></row><row r="4"><c r="D4"><v>30</v></c></row><row r="5"><c r="E5"><v>40</v></c></row>"#;
    let bytes = package_with_parts(&[("Sheet1", cells)], "", views, &[]);
    let mut doc =
        ncsheet::document::Document::open(bytes, &ncsheet::document::OpenOptions::named("areas.xlsx")).unwrap();
    let src = "Sub Main()\n    Dim c, total\n    For Each c In Selection\n        total = total + c.Value\n    Next\n    \
               Debug.Print Selection.Areas.Count; Selection.Count; Selection.Address; \" \"; ActiveCell.Address; total\n    \
               Range(\"E5\").Select\n    Debug.Print Selection.Areas.Count; Selection.Address\nEnd Sub\n";
    let out = doc.run_macro(src, "Module1.bas", ncsheet::vba::RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 2  8 $A$1:$B$2,$D$4:$E$5 $D$4 73 ", " 1 $E$5"]);
}

#[test]
fn shared_formulas_move_from_the_cell_that_holds_their_text() {
    // Excel may put the text of a shared formula in a cell that is not the top left of its
    // range, after cells that use it.
    let data = r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><v>2</v></c><c r="C1"><v>3</v></c></row>
<row r="2"><c r="A2"><f t="shared" si="0"/><v>10</v></c><c r="B2"><f t="shared" si="0"/><v>20</v></c><c r="C2"><f t="shared" ref="A2:C3" si="0">C1*10</f><v>30</v></c></row>
<row r="3"><c r="A3"><f t="shared" si="0"/><v>100</v></c><c r="B3"><f t="shared" si="0"/><v>200</v></c><c r="C3"><f t="shared" si="0"/><v>300</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    for (cell, formula, value) in [
        ("A2", "=A1*10", 10.0),
        ("B2", "=B1*10", 20.0),
        ("C2", "=C1*10", 30.0),
        ("A3", "=A2*10", 100.0),
        ("C3", "=C2*10", 300.0),
    ] {
        assert_eq!(wb.formula(0, at(cell)).as_deref(), Some(formula), "{cell}");
        assert_eq!(wb.value(0, at(cell)), num(value), "{cell}");
    }
    assert!(xlsx::compare_cached(wb, &imported.cached).is_empty());
}

#[test]
fn cached_neighbours_of_a_dynamic_array_do_not_block_its_spill() {
    let data = r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1" cm="1"><f t="array" ref="B1:B3">A1:A3*2</f><v>2</v></c></row>
<row r="2"><c r="A2"><v>2</v></c><c r="B2"><v>4</v></c></row>
<row r="3"><c r="A3"><v>3</v></c><c r="B3"><v>6</v></c><c r="C3"><f>SUM(_xlfn.ANCHORARRAY(B1))</f><v>12</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    assert_eq!(wb.value(0, at("B3")), num(6.0));
    assert_eq!(wb.input(0, at("B3")), None, "a spilled value, not a constant");
    assert_eq!(wb.formula(0, at("C3")).as_deref(), Some("=SUM(B1#)"));
    assert_eq!(wb.value(0, at("C3")), num(12.0));
    let spilled: Vec<_> = imported.cached.iter().filter(|c| c.anchor == at("B1")).map(|c| c.pos).collect();
    assert_eq!(spilled, vec![at("B1"), at("B2"), at("B3")]);
    assert!(xlsx::compare_cached(wb, &imported.cached).is_empty());
}

#[test]
fn a_plain_formula_over_a_range_intersects_as_in_excel() {
    let data = r#"<row r="1"><c r="A1"><v>5</v></c></row><row r="2"><c r="A2"><v>7</v></c><c r="B2"><f>A1:A3</f><v>7</v></c><c r="C2"><f>SUM(A1:A3)</f><v>12</v></c></row><row r="3"><c r="D3"><f>_xlfn.SINGLE(A1:A3)+1</f><v>1</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    assert_eq!(wb.formula(0, at("B2")).as_deref(), Some("=@A1:A3"));
    assert_eq!(wb.value(0, at("B2")), num(7.0));
    assert_eq!(wb.formula(0, at("C2")).as_deref(), Some("=SUM(A1:A3)"));
    assert_eq!(wb.formula(0, at("D3")).as_deref(), Some("=@A1:A3+1"));
    assert_eq!(wb.value(0, at("D3")), num(1.0));
}

/// A plain `<f>` is a legacy formula: Excel evaluates it with implicit intersection, so its
/// array result is never spilled and it never reads its own spill range. An array that is
/// not a reference intersects to its top-left item (Microsoft, "Implicit intersection
/// operator: @": "If the value is an array, then pick the top-left value"), which is what
/// Excel caches: `{5;2;3}+COUNTBLANK(A2:A3)` is 5+2, reading the two cells below it that its
/// un-intersected result would spill over, and C1 reads its would-be spill cell through D1.
#[test]
fn a_legacy_formula_whose_array_would_spill_over_cells_it_reads_is_intersected() {
    let data = r#"<row r="1"><c r="A1"><f>{5;2;3}+COUNTBLANK(A2:A3)</f><v>7</v></c><c r="B1"><f>A1*2</f><v>14</v></c><c r="C1"><f>{1;2}+D1</f><v>1</v></c><c r="D1"><f>C2</f><v>0</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    for (cell, value) in [("A1", 7.0), ("B1", 14.0), ("C1", 1.0), ("D1", 0.0)] {
        assert_eq!(wb.value(0, at(cell)), num(value), "{cell}");
    }
    assert_eq!(wb.formula(0, at("A1")).as_deref(), Some("=@({5;2;3}+COUNTBLANK(A2:A3))"));
    assert!(wb.cycles().is_empty(), "{:?}", wb.cycles());
    assert!(xlsx::compare_cached(wb, &imported.cached).is_empty());
}

#[test]
fn names_keep_their_scope_and_built_in_names_are_noted() {
    let data = r#"<row r="1"><c r="A1"><v>3</v></c><c r="B1"><f>rate*2</f><v>6</v></c></row>"#;
    let other = r#"<row r="1"><c r="A1"><v>10</v></c><c r="B1"><f>rate*2</f><v>20</v></c></row>"#;
    let names = r#"<definedNames><definedName name="_xlfn.SINGLE" hidden="1">#NAME?</definedName><definedName name="_xlnm.Print_Area" localSheetId="0">Sheet1!$A$1:$B$1</definedName><definedName name="rate">Sheet1!$A$1</definedName><definedName name="rate" localSheetId="1">Other!$A$1</definedName></definedNames>"#;
    let imported = load(&[("Sheet1", data), ("Other", other)], names);
    let wb = &imported.workbook;
    let mut defined = wb.names();
    defined.sort();
    assert_eq!(
        defined,
        vec![("rate".into(), "=Other!$A$1".into(), Some(1)), ("rate".into(), "=Sheet1!$A$1".into(), None)]
    );
    assert_eq!(wb.value(0, at("B1")), num(6.0));
    assert_eq!(wb.value(1, at("B1")), num(20.0));
    assert_eq!(
        imported.notes,
        vec!["the print area of 'Sheet1' (Sheet1!$A$1:$B$1) is not used by ncsheet; saving the file's edits keeps it"
            .to_string()]
    );
}

#[test]
fn a_formula_we_cannot_read_keeps_its_text_and_the_value_the_file_cached() {
    // A table that is not in the file: as Excel, which drops a formula it cannot read when
    // it repairs the file, the cell shows the value the file holds, and B1 computes from it.
    let data = r#"<row r="1"><c r="A1"><f>SUM(Table1[Qty])</f><v>12</v></c><c r="B1"><f>A1+1</f><v>13</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    assert_eq!(wb.formula(0, at("A1")).as_deref(), Some("=SUM(Table1[Qty])"));
    assert_eq!(wb.value(0, at("A1")), num(12.0));
    assert_eq!(wb.value(0, at("B1")), num(13.0));
    assert!(wb.keeps_file_value(0, at("A1")) && !wb.keeps_file_value(0, at("B1")));
    let problems = wb.problems();
    assert_eq!(problems.len(), 1);
    assert_eq!((problems[0].sheet, problems[0].pos), (0, at("A1")));
    assert!(problems[0].message().contains("keeps the value the file cached"), "{}", problems[0].message());
    assert!(imported.notes.iter().any(|n| n.contains("Sheet1!A1 =SUM(Table1[Qty])")), "{:?}", imported.notes);
    // Edited, the cell is computed again, and so is B1.
    let mut wb = imported.workbook;
    wb.set_input(0, at("A1"), "=2*5").unwrap();
    assert_eq!((wb.value(0, at("A1")), wb.value(0, at("B1"))), (num(10.0), num(11.0)));
    assert!(!wb.keeps_file_value(0, at("A1")) && wb.problems().is_empty());
}

#[test]
fn cached_values_keep_their_types() {
    let data = r#"<row r="1"><c r="A1" t="b"><f>1=1</f><v>1</v></c><c r="B1" t="e"><f>1/0</f><v>#DIV/0!</v></c><c r="C1" t="str"><f>"a"&amp;"b"</f><v>ab</v></c><c r="D1"><f>0.1+0.2</f><v>0.30000000000000004</v></c><c r="E1" t="str"><f>NOW()</f><v>x</v></c></row>
<row r="2"><c r="A2" t="b"><v>0</v></c><c r="B2" t="e"><v>#N/A</v></c><c r="C2" t="inlineStr"><is><t>=not a formula</t></is></c><c r="D2"><v>45000.5</v></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    let cached: Vec<_> = imported.cached.iter().map(|c| c.value.clone()).collect();
    assert_eq!(
        cached,
        vec![
            Value::Bool(true),
            Value::Error(XlError::Div0),
            Value::text("ab"),
            num(0.30000000000000004),
            Value::text("x")
        ]
    );
    assert_eq!(wb.value(0, at("A2")), Value::Bool(false));
    assert_eq!(wb.value(0, at("B2")), Value::Error(XlError::NA));
    assert_eq!(wb.value(0, at("C2")), Value::text("=not a formula"));
    assert_eq!(wb.formula(0, at("C2")), None);
    assert_eq!(wb.value(0, at("D2")), num(45000.5));
    // Only NOW() disagrees (NOW is not in our table), and it is marked volatile.
    let differences = xlsx::compare_cached(wb, &imported.cached);
    assert_eq!(differences.len(), 1);
    assert!(differences[0].volatile);
}

#[test]
fn a_sheet_whose_relationship_names_no_part_is_left_out_with_a_note() {
    // Excel saves a very hidden Excel 4 macro sheet with an empty r:id; Excel and
    // LibreOffice open the workbook without it (ECMA-376 §18.2.19 makes r:id required, and
    // an id no relationship has names no part).
    let data = r#"<row r="1"><c r="A1"><v>2</v></c><c r="B1"><f>A1*3</f><v>6</v></c></row>"#;
    let plain = package(&[("Sheet1", data), ("Data", data)], "");
    let mut zip = zip::ZipArchive::new(Cursor::new(&plain[..])).unwrap();
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).unwrap();
        let name = entry.name().unwrap().to_string();
        let mut text = String::new();
        std::io::Read::read_to_string(&mut entry, &mut text).unwrap();
        if name == "xl/workbook.xml" {
            let macro_sheet = r#"<sheet name="Macro1" sheetId="9" state="veryHidden" r:id=""/>"#;
            text = text.replacen(r#"<sheet name="Data""#, &format!(r#"{macro_sheet}<sheet name="Data""#), 1);
        }
        out.start_file(name.as_str(), zip::write::SimpleFileOptions::default()).unwrap();
        out.write_all(text.as_bytes()).unwrap();
    }
    let bytes = out.finish().unwrap().into_inner();
    let imported = xlsx::load_bytes(&bytes, Path::new("macro.xlsx")).unwrap_or_else(|e| panic!("{e}"));
    let wb = &imported.workbook;
    assert_eq!(wb.sheet_names(), ["Sheet1", "Data"]);
    assert_eq!(wb.value(1, at("B1")), num(6.0));
    assert!(imported.notes.iter().any(|n| n.contains("'Macro1'") && n.contains("left out")), "{:?}", imported.notes);
}

#[test]
fn a_circular_reference_keeps_the_values_excel_cached_and_is_named() {
    // Without iterative calculation Excel "displays either a zero or the last calculated
    // value" of a circular reference's cells (Microsoft support, "Remove or allow a circular
    // reference in Excel"); a saved file holds those values, and what reads them computes
    // from them.
    let data = r#"<row r="1"><c r="A1"><f>B1+1</f><v>7</v></c><c r="B1"><f>A1+1</f><v>8</v></c><c r="C1"><f>A1*2</f><v>14</v></c><c r="D1"><f>D1+1</f></c></row>"#;
    let imported = load(&[("Sheet1", data)], "");
    let wb = &imported.workbook;
    assert_eq!(wb.value(0, at("A1")), num(7.0));
    assert_eq!(wb.value(0, at("B1")), num(8.0));
    assert_eq!(wb.value(0, at("C1")), num(14.0));
    // No value cached: Excel shows 0.
    assert_eq!(wb.value(0, at("D1")), num(0.0));
    assert_eq!(wb.cycles().len(), 2, "{:?}", wb.cycles());
}

/// Cells of formulas, `(cell, formula)`, as `<c>` elements of one row each (no cached value).
fn formula_rows(first_row: u32, formulas: &[&str]) -> String {
    let mut out = String::new();
    for (i, f) in formulas.iter().enumerate() {
        let r = first_row + i as u32;
        let f = f.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;");
        out.push_str(&format!(r#"<row r="{r}"><c r="A{r}"><f>{f}</f></c></row>"#));
    }
    out
}

/// INDIRECT's text may name a defined name scoped to a sheet, as `Sheet!Name` (the name of
/// that sheet, else the workbook's) or alone (this sheet's, else the workbook's): the
/// reference Excel's INDIRECT gives is the name's. LibreOffice agrees on `Sheet1!Rate` (11)
/// and `'2007'!Rate` (7); a name with a dot it cannot read in this syntax (#REF!).
#[test]
fn indirect_reads_names_scoped_to_a_sheet() {
    let data =
        r#"<row r="1"><c r="B1"><v>42</v></c><c r="C1"><v>7</v></c></row><row r="2"><c r="B2"><v>8</v></c></row>"#;
    let formulas = formula_rows(
        1,
        &[
            r#"SUM(INDIRECT("'2007'!Year.NetBalance"))"#,
            r#"INDIRECT("Rate")"#,
            r#"INDIRECT("Sheet1!Rate")"#,
            r#"INDIRECT("'2007'!Rate")"#,
            r#"INDIRECT("Glob")"#,
            r#"INDIRECT("Sheet1!Nowhere")"#,
        ],
    );
    let sheet1 = format!(r#"{formulas}<row r="9"><c r="B9"><v>11</v></c></row>"#);
    let names = r#"<definedNames><definedName name="Year.NetBalance" localSheetId="1">'2007'!$B$1:$B$2</definedName><definedName name="Rate" localSheetId="1">'2007'!$C$1</definedName><definedName name="Rate" localSheetId="0">Sheet1!$B$9</definedName><definedName name="Glob">'2007'!$B$2</definedName></definedNames>"#;
    let sheet2 = r#"<row r="5"><c r="A5"><f>INDIRECT("Rate")</f></c></row><row r="6"><c r="A6"><f>SUM(INDIRECT("Year.NetBalance"))</f></c></row>"#;
    let imported = load(&[("Sheet1", &sheet1), ("2007", &format!("{data}{sheet2}"))], names);
    let wb = &imported.workbook;
    let expected = [
        (0, "A1", num(50.0)),
        (0, "A2", num(11.0)),
        (0, "A3", num(11.0)),
        (0, "A4", num(7.0)),
        (0, "A5", num(8.0)),
        (0, "A6", Value::Error(XlError::Ref)),
        (1, "A5", num(7.0)),
        (1, "A6", num(50.0)),
    ];
    for (sheet, cell, value) in expected {
        assert_eq!(wb.value(sheet, at(cell)), value, "sheet {sheet} {cell}");
    }
}

/// INDIRECT's text may be a structured reference to a table (`Parts[Qty]`, built from
/// pieces, `Parts[[#Totals],[Qty]]`, the table's name alone for its data, `#All`,
/// `#Headers`; names in any case): the range it names, as a formula typed with it would.
/// A column the table lacks names nothing (#REF!).
#[test]
fn indirect_reads_structured_references_to_tables() {
    let table_rows = r#"<row r="1"><c r="A1" t="inlineStr"><is><t>Name</t></is></c><c r="B1" t="inlineStr"><is><t>Qty</t></is></c></row><row r="2"><c r="B2"><v>5</v></c></row><row r="3"><c r="B3"><v>7</v></c></row><row r="4"><c r="B4"><v>9</v></c></row><row r="5"><c r="B5"><v>100</v></c></row>"#;
    let formulas: String = [
        r#"SUM(INDIRECT("Parts[Qty]"))"#,
        r#"SUM(INDIRECT("Parts"&"["&"Qty"&"]"))"#,
        r#"INDIRECT("Parts[[#Totals],[Qty]]")"#,
        r#"ROWS(INDIRECT("Parts"))"#,
        r#"ROWS(INDIRECT("Parts[#All]"))"#,
        r#"COUNTA(INDIRECT("Parts[#Headers]"))"#,
        r#"SUM(INDIRECT("parts[qty]"))"#,
        r#"INDIRECT("Parts[Nope]")"#,
    ]
    .iter()
    .enumerate()
    .map(|(i, f)| {
        let f = f.replace('&', "&amp;").replace('"', "&quot;");
        format!(r#"<c r="D{}"><f>{f}</f></c>"#, i + 1)
    })
    .collect::<Vec<_>>()
    .join("");
    // The formulas sit beside the table, each in its own row (D1:D8).
    let mut rows = String::new();
    for r in 1..=8 {
        let table_part = table_rows.split("</row>").nth(r - 1).filter(|s| !s.is_empty()).unwrap_or("");
        let inner = table_part.split_once('>').map_or("", |(_, cells)| cells);
        let formula = formulas.split("</c>").nth(r - 1).map(|c| format!("{c}</c>")).unwrap_or_default();
        rows.push_str(&format!(r#"<row r="{r}">{inner}{formula}</row>"#));
    }
    let table = r#"<?xml version="1.0" encoding="UTF-8"?><table xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" id="1" name="Parts" displayName="Parts" ref="A1:B5" totalsRowCount="1"><autoFilter ref="A1:B4"/><tableColumns count="2"><tableColumn id="1" name="Name"/><tableColumn id="2" name="Qty"/></tableColumns></table>"#;
    let rels = r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/table" Target="../tables/table1.xml"/></Relationships>"#;
    let bytes = package_with_parts(
        &[("Sheet1", &rows)],
        "",
        r#"<tableParts count="1"><tablePart r:id="rId1"/></tableParts>"#,
        &[("xl/tables/table1.xml", table), ("xl/worksheets/_rels/sheet1.xml.rels", rels)],
    );
    let imported = xlsx::load_bytes(&bytes, Path::new("book.xlsx")).unwrap_or_else(|e| panic!("{e}"));
    let wb = &imported.workbook;
    let expected = [
        ("D1", num(21.0)),
        ("D2", num(21.0)),
        ("D3", num(100.0)),
        ("D4", num(3.0)),
        ("D5", num(5.0)),
        ("D6", num(2.0)),
        ("D7", num(21.0)),
        ("D8", Value::Error(XlError::Ref)),
    ];
    for (cell, value) in expected {
        assert_eq!(wb.value(0, at(cell)), value, "{cell}: {:?}", wb.formula(0, at(cell)));
    }
}

/// Whole rows and columns in array formulas: a legacy array formula over a whole row
/// (`{=First!1:1}` entered across D1:XFD1, as Excel stores it) shows First's row shifted,
/// 0 for each empty cell out to the sheet's last column; a whole column read as an array
/// (`SUMPRODUCT((A:A>0)*B:B)`, `ROWS(A:A)`) is all 1,048,576 rows, the empty ones blank,
/// as Excel computes them.
#[test]
fn whole_rows_and_columns_in_array_formulas_reach_the_sheet_edge() {
    let first = r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><v>2</v></c><c r="C1"><v>3</v></c></row>"#;
    let second = r#"<row r="1"><c r="D1"><f t="array" ref="D1:XFD1">First!1:1</f><v>1</v></c></row><row r="2"><c r="A2"><v>-1</v></c><c r="B2"><v>5</v></c></row><row r="3"><c r="A3"><v>2</v></c><c r="B3"><v>7</v></c></row><row r="4"><c r="E4"><f>SUMPRODUCT((A:A&gt;0)*B:B)</f></c><c r="F4"><f>ROWS(A:A)</f></c><c r="G4"><f>SUMPRODUCT(--(A:A=""))</f></c></row>"#;
    let imported = load(&[("First", first), ("Second", second)], "");
    let wb = &imported.workbook;
    for (cell, value) in [("D1", 1.0), ("E1", 2.0), ("F1", 3.0), ("G1", 0.0), ("XFD1", 0.0)] {
        assert_eq!(wb.value(1, at(cell)), num(value), "{cell}");
    }
    assert_eq!(wb.value(1, at("E4")), num(7.0));
    assert_eq!(wb.value(1, at("F4")), num(1048576.0));
    // Every row of A but A2 and A3 is empty.
    assert_eq!(wb.value(1, at("G4")), num(1048574.0));
}

/// A generator that does not calculate (openpyxl, a script) writes formulas with no result:
/// `<f>` and an empty `<v/>`, or no `<v>` at all. Excel computes them on opening and writes
/// its results when it saves; a save by ncsheet writes its results there too, though no edit
/// touched them (the file held nothing to keep), where the saved cells stayed empty and a
/// reader of the saved values (openpyxl's `data_only`, a viewer) saw no result. A result the
/// file cached is kept as the file had it.
#[test]
fn formulas_read_without_a_result_are_saved_with_one() {
    use ncsheet::io::{self, atomic, Format};
    use std::io::Read;
    let row = r#"<row r="1"><c r="A1"><v>3</v></c><c r="B1"><f>A1*2</f><v></v></c><c r="C1"><f>1/0</f></c><c r="D1"><f>B1&amp;"x"</f><v/></c><c r="E1"><f>NOSUCHFUNCTION(1)</f></c><c r="F1"><f>A1+1</f><v>4</v></c></row>"#;
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("generated.xlsx");
    let out = dir.path().join("saved.xlsx");
    std::fs::write(&source, package(&[("Sheet1", row)], "")).unwrap();
    let opened = io::open_bytes(std::fs::read(&source).unwrap(), &source, Format::Xlsx, None).unwrap();
    let mut wb = opened.workbook;
    wb.set_input(0, at("A3"), "1").unwrap();
    io::encode_save(&wb, opened.layout.as_ref(), &opened.origin, &out)
        .and_then(|saved| saved.write(atomic::Options::default()))
        .unwrap();
    let mut zip = zip::ZipArchive::new(Cursor::new(std::fs::read(&out).unwrap())).unwrap();
    let mut xml = String::new();
    zip.by_name("xl/worksheets/sheet1.xml").unwrap().read_to_string(&mut xml).unwrap();
    // What Excel computes for each: 3*2, a division by zero, text joined, an unknown name.
    for element in [
        r#"<c r="B1"><f>A1*2</f><v>6</v></c>"#,
        r#"<c r="C1" t="e"><f>1/0</f><v>#DIV/0!</v></c>"#,
        r#"<c r="D1" t="str"><f>B1&amp;"x"</f><v>6x</v></c>"#,
        r#"<c r="E1" t="e"><f>NOSUCHFUNCTION(1)</f><v>#NAME?</v></c>"#,
        r#"<c r="F1"><f>A1+1</f><v>4</v></c>"#,
    ] {
        assert!(xml.contains(element), "{element} not in {xml}");
    }
}
