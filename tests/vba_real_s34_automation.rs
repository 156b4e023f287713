//! Real everyday-automation modules measured in session 34 (issue 31), run as their authors
//! wrote them (the sources under tests/data/vba_real_s34/, each with its SOURCE), on
//! workbooks built here, against what Excel gives: the values follow from Microsoft's Excel
//! and VBA reference pages named at each test, worked out by hand apart from ncsheet.

use ncsheet::vba::{run, RunOptions};
use ncsheet::workbook::Workbook;

/// A module of tests/data/vba_real_s34/ as its file holds it.
fn module(path: &str) -> String {
    let file = format!("{}/tests/data/vba_real_s34/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// What `driver` (a module with `Sub Main`) printed, run with the real module `name` beside
/// it as another module of the project; the test fails naming the macro's error.
fn printed_with(wb: &mut Workbook, driver: &str, name: &str, source: String) -> Vec<String> {
    let options = RunOptions {
        project: vec![(name.into(), source)],
        workbook_name: Some("stock.xlsx".into()),
        ..RunOptions::default()
    };
    let out = run(wb, driver, "Driver.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    out.printed.iter().map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect()
}

/// The stock list Chip Pearson's FindAll is tried on: "bolt" whole at B2 only, in other cases
/// at D3 (BOLT) and C5 (Bolt), as part of D2 (bolts); a second sheet with two, a third with none.
fn stock_book() -> Workbook {
    let mut wb = Workbook::new();
    for name in ["Stock", "Spare", "Empty"] {
        wb.add_sheet(name).unwrap();
    }
    let cells: [(u16, &str, &str); 12] = [
        (0, "B2", "bolt"),
        (0, "C2", "nut"),
        (0, "D2", "bolts"),
        (0, "B3", "washer"),
        (0, "D3", "BOLT"),
        (0, "C4", "screw"),
        (0, "C5", "Bolt"),
        (0, "B6", "nut"),
        (0, "D6", "pin"),
        (1, "B3", "bolt"),
        (1, "A1", "bolt"),
        (2, "C3", "nut"),
    ];
    for (sheet, cell, v) in cells {
        let pos = ncsheet::formula::address::parse_cell(cell).unwrap();
        wb.set_input(sheet, pos, v).unwrap();
    }
    wb
}

// Chip Pearson's modRangeMethodsFindProcedures (GetFoundCells, FindAll, FindAllOnWorksheets).
// "Range.Find method": the search begins after the After cell (the range's last cell here, so
// at its first), "xlByRows" row by row, "MatchCase ... False" by default, "LookAt" xlWhole or
// xlPart; "Range.FindNext method" continues after the cell found and wraps round to the first,
// where the loop stops; "Application.Union method" keeps the areas in the order given, which
// "Range.Address property" lists with commas. FindAllOnWorksheets(Nothing, Empty, …) searches
// every worksheet: "IsEmpty function" is True for the Empty it is given and False for a
// Worksheet ("IsEmpty returns True if the variable is uninitialized, or is explicitly set to
// Empty; otherwise, it returns False"), where reading the Worksheet as a value stopped the run;
// given a Worksheet, `TypeOf InWorksheets Is Excel.Worksheet` searches it alone.
#[test]
fn chip_pearsons_find_all_collects_every_cell_found_on_one_sheet_or_all() {
    let driver = "Sub Main()\n\
        \x20   Dim v, i As Long\n\
        \x20   Debug.Print GetFoundCells(Worksheets(\"Stock\").Range(\"B2:D6\"), \"bolt\").Address\n\
        \x20   Debug.Print GetFoundCells(Worksheets(\"Stock\").Range(\"B2:D6\"), \"bolt\", SearchOrder:=xlByColumns).Address\n\
        \x20   Debug.Print FindAll(Worksheets(\"Stock\").Range(\"B2:D6\"), \"bolt\", LookAt:=xlPart).Cells.Count\n\
        \x20   Debug.Print FindAll(Worksheets(\"Stock\").Range(\"B2:D6\"), \"bolt\", MatchCase:=True).Address\n\
        \x20   Debug.Print FindAll(Worksheets(\"Stock\").Range(\"B2:D6\"), \"rivet\") Is Nothing\n\
        \x20   v = FindAllOnWorksheets(Nothing, Empty, \"B2:D6\", \"bolt\", SearchOrder:=xlByRows)\n\
        \x20   For i = LBound(v) To UBound(v)\n\
        \x20       If v(i) Is Nothing Then Debug.Print i; \"Nothing\" Else Debug.Print i; v(i).Address\n\
        \x20   Next i\n\
        \x20   v = FindAllOnWorksheets(ThisWorkbook, Worksheets(\"Spare\"), \"A1:D6\", \"bolt\", SearchOrder:=xlByRows)\n\
        \x20   Debug.Print UBound(v); v(1).Address\n\
        End Sub\n";
    let source = module("cpearson_find/modRangeMethodsFindProcedures.bas");
    let printed = printed_with(&mut stock_book(), driver, "modRangeMethodsFindProcedures", source);
    assert_eq!(
        printed,
        [
            "$B$2,$D$3,$C$5",
            "$B$2,$C$5,$D$3",
            "4",
            "$B$2",
            "True",
            "1 $B$2,$D$3,$C$5",
            "2 $B$3",
            "3 Nothing",
            "1 $A$1,$B$3",
        ]
    );
}

// "IsEmpty function" on what a Variant can hold: Empty and a Variant never assigned are empty;
// a Worksheet, a Collection and Nothing are objects, set, so not empty; a Range is read as its
// default member, Value ("Range.Value property"), so a blank cell is empty and a filled one not.
#[test]
fn is_empty_of_an_object_is_false_and_of_a_range_is_its_value() {
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, ncsheet::formula::address::parse_cell("A2").unwrap(), "7").unwrap();
    let driver = "Sub Main()\n\
        \x20   Dim v, w, c As New Collection, n As Object\n\
        \x20   Set w = ActiveSheet\n\
        \x20   Debug.Print IsEmpty(v) & \" \" & IsEmpty(Empty) & \" \" & IsEmpty(w) & \" \" & IsEmpty(c) & \" \" & IsEmpty(n)\n\
        \x20   Set v = Range(\"A1\")\n\
        \x20   Debug.Print IsEmpty(v) & \" \" & IsEmpty(Range(\"A2\")) & \" \" & IsEmpty(Worksheets(1)) & \" \" & IsEmpty((v))\n\
        End Sub\n";
    let options = RunOptions::default();
    let out = run(&mut wb, driver, "Driver.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, ["True True False False False", "True False False True"]);
}
