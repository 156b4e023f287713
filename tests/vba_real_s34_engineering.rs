//! Real engineering modules measured in session 34 (issue 31), run as their authors wrote them
//! (the sources under tests/data/vba_real_s34/, each with its SOURCE), on workbooks built here,
//! against values computed apart from ncsheet (a Python port of the same arithmetic) and the
//! Microsoft reference pages named at each test.

use ncsheet::vba::{run, RunOptions};
use ncsheet::workbook::Workbook;

/// A module of tests/data/vba_real_s34/ decoded from the ANSI code page its author's editor
/// wrote it in, as `run --code-page` decodes it.
fn module_in(path: &str, code_page: u16) -> String {
    let file = format!("{}/tests/data/vba_real_s34/{path}", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&file).unwrap_or_else(|e| panic!("{file}: {e}"));
    ncsheet::vba::project::decode_module_file(&bytes, Some(code_page)).unwrap_or_else(|e| panic!("{file}: {e:?}"))
}

/// What `driver` (a module with `Sub Main`) printed, run with the real module `name` beside it
/// as another module of the project, each line's items separated by one space; the test fails
/// naming the macro's error.
fn printed_with(wb: &mut Workbook, driver: &str, name: &str, source: String) -> Vec<String> {
    let options = RunOptions { project: vec![(name.into(), source)], ..RunOptions::default() };
    let out = run(wb, driver, "Driver.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    out.printed.iter().map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect()
}

fn book(sheets: &[&str]) -> Workbook {
    let mut wb = Workbook::new();
    for name in sheets {
        wb.add_sheet(name).unwrap();
    }
    wb
}

// A recorded-then-edited stiffness macro (file id 14644280753, module 模块3 in GBK): for each
// 10-row block of sheet2 it selects N:W and enters `=MINVERSE(RC[-11]:R[9]C[-2])` through
// Selection.FormulaArray, then on kValue one row of `=MMULT(sheet2!RC[9]:R[9]C[18],
// Sheet2!RC[-3]:R[9]C[-3])`, where FormulaArray stopped the run as not modelled.
// "Range.FormulaArray property": the text is one array formula over the range; its R1C1
// references are relative to the range's top-left cell (N2: C2:L11). An array formula's result
// fills its range as Excel fits it, a single column repeated across a wider row ("Guidelines and
// examples of array formulas"), so AA2:AJ2 all show MMULT's first item. The inverse rows and the
// products are a Python port's (Gauss-Jordan with partial pivoting), rounded to 9 places as the
// driver rounds them; FormulaArray reads back in A1 style.
#[test]
fn a_recorded_stiffness_macro_enters_minverse_and_mmult_as_array_formulas() {
    let driver = "Sub Main()\n\
        \x20   Dim r As Long, c As Long, b As Long\n\
        \x20   With Sheets(\"sheet2\")\n\
        \x20       For b = 0 To 1\n\
        \x20           For r = 0 To 9\n\
        \x20               .Cells(2 + 10 * b + r, 1).Value = 1\n\
        \x20               For c = 0 To 9\n\
        \x20                   If r = c Then\n\
        \x20                       .Cells(2 + 10 * b + r, 3 + c).Value = 10 + r + b\n\
        \x20                   Else\n\
        \x20                       .Cells(2 + 10 * b + r, 3 + c).Value = (((r + 2 * c + b) Mod 7) - 3) / 4\n\
        \x20                   End If\n\
        \x20               Next c\n\
        \x20           Next r\n\
        \x20       Next b\n\
        \x20       For r = 2 To 21\n\
        \x20           .Cells(r, 24).Value = r / 10\n\
        \x20           For c = 36 To 45\n\
        \x20               .Cells(r, c).Value = ((r * 3 + c) Mod 11) / 5 - 1\n\
        \x20           Next c\n\
        \x20       Next r\n\
        \x20   End With\n\
        \x20   Sheets(\"sheet2\").Select\n\
        \x20   Macro3\n\
        \x20   With Sheets(\"sheet2\")\n\
        \x20       For r = 2 To 12 Step 10\n\
        \x20           For c = 14 To 23\n\
        \x20               Debug.Print Round(.Cells(r, c).Value, 9);\n\
        \x20           Next c\n\
        \x20           Debug.Print\n\
        \x20       Next r\n\
        \x20       Debug.Print CStr(.Range(\"N2\").HasFormula); \" \"; .Range(\"N2\").FormulaArray\n\
        \x20   End With\n\
        \x20   With Sheets(\"kValue\")\n\
        \x20       Debug.Print Round(.Range(\"AA2\").Value, 9); Round(.Range(\"AJ2\").Value, 9); Round(.Range(\"AA3\").Value, 9); CStr(IsEmpty(.Range(\"AA4\").Value))\n\
        \x20   End With\n\
        \x20   Debug.Print ActiveSheet.Name\n\
        End Sub\n";
    let source = module_in("engineering_kvalue_macro3/Macro3.bas", 936);
    assert!(source.starts_with("Attribute VB_Name = \"模块3\""), "{}", &source[..40]);
    let printed = printed_with(&mut book(&["Sheet1", "sheet2", "kValue"]), driver, "模块3", source);
    assert_eq!(
        printed,
        [
            "0.100601261 0.002356648 -0.002457348 -0.005866479 0.003701081 0.000484555 -0.00377688 \
             0.004589496 0.001440174 -0.001514804",
            "0.090609344 -0.000126686 -0.003388545 0.005101105 0.001287322 -0.000901375 -0.004184173 \
             0.002270673 -7.939E-05 -0.002245422",
            "True =MINVERSE(C2:L11)",
            "-0.5 -0.5 2.4 True",
            "kValue",
        ]
    );
}

// The examples of "Range.FormulaArray property": `Range("A1:C5").FormulaArray = "=3"` enters the
// number 3 as an array constant in every cell, and `Range("E1:E3").FormulaArray =
// "=Sum(R1C1:R3C3)"` (the page's older text: "the formula must use the R1C1 reference style")
// the sum of A1:C3 in E1:E3 (absolute references, read back as $A$1:$C$3); the current page writes the same as `=Sum(A1:C3)`. An A1 name can
// never be spelled R1C1 ("Names in formulas": a name cannot be the same as a cell reference,
// such as Z$100 or R1C1), so the text is read in R1C1 style. A range that is no array formula
// reads back Null; an array formula follows its inputs (K1:K2 = J1*2).
#[test]
fn formula_array_enters_the_reference_pages_examples() {
    let mut wb = book(&["Sheet1"]);
    let out = common_main(
        &mut wb,
        "    Range(\"A1:C5\").FormulaArray = \"=3\"\n\
         \x20   Debug.Print Application.Sum(Range(\"A1:C5\")); Range(\"C5\").Value\n\
         \x20   Range(\"E1:E3\").FormulaArray = \"=Sum(R1C1:R3C3)\"\n\
         \x20   Debug.Print Range(\"E1\").Value; Range(\"E3\").Value; Range(\"E1\").FormulaArray\n\
         \x20   Range(\"F1:F3\").FormulaArray = \"=Sum(A1:C3)\"\n\
         \x20   Debug.Print Range(\"F2\").Value; CStr(IsNull(Range(\"A1:F5\").FormulaArray))\n\
         \x20   Range(\"J1\").Value = 5\n\
         \x20   Range(\"K1:K2\").FormulaArray = \"=J1*2\"\n\
         \x20   Range(\"J1\").Value = 7\n\
         \x20   Debug.Print Range(\"K2\").Value",
    );
    assert_eq!(out, ["45 3", "27 27 =SUM($A$1:$C$3)", "27 True", "14"]);
}

fn common_main(wb: &mut Workbook, body: &str) -> Vec<String> {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    let out = run(wb, &src, "main.bas", &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    out.printed.iter().map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect()
}
