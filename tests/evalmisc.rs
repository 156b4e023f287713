//! The evaluator against Excel's documented semantics where the last session left wrong
//! results: LAMBDA values, defined names' relative references, whole-row arrays read whole.

mod common;

use common::sheet::{get, n, set};
use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

fn eval(formula: &str) -> Value {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", formula);
    get(&wb, "A1")
}

fn err(e: XlError) -> Value {
    Value::Error(e)
}

// ---- LAMBDA values ---------------------------------------------------------------------
// Microsoft's LAMBDA page: a LAMBDA is a function of its parameters, called by a name or in
// place (`=LAMBDA(x, x+1)(1)`); a wrong argument count is #VALUE!, one left uncalled in a cell
// #CALC!. Whatever gives a LAMBDA (a LAMBDA's result, IF, CHOOSE, a LET name, a parameter)
// gives a function that can be called.

#[test]
fn a_lambda_returned_by_an_expression_is_called() {
    assert_eq!(eval("=LET(f,LAMBDA(x,LAMBDA(y,x+y)),f(3)(4))"), n(7.0));
    assert_eq!(eval("=LAMBDA(x,LAMBDA(y,x*y))(3)(4)"), n(12.0));
    assert_eq!(eval("=IF(TRUE,LAMBDA(x,x*2))(5)"), n(10.0));
    assert_eq!(eval("=IF(FALSE,LAMBDA(x,x*2),LAMBDA(x,x+2))(5)"), n(7.0));
    assert_eq!(eval("=CHOOSE(2,LAMBDA(x,x),LAMBDA(x,-x))(3)"), n(-3.0));
    // The inner LAMBDA keeps the outer one's parameter after the outer call returned.
    assert_eq!(eval("=LET(add,LAMBDA(x,LAMBDA(y,x+y)),inc,add(1),inc(10)+inc(20))"), n(32.0));
}

#[test]
fn a_lambda_is_passed_as_an_argument() {
    assert_eq!(eval("=LET(twice,LAMBDA(f,x,f(f(x))),twice(LAMBDA(n,n*3),2))"), n(18.0));
    // MAP, REDUCE… take a LET name holding a LAMBDA as they take one written in place.
    assert_eq!(eval("=LET(sq,LAMBDA(x,x*x),SUM(MAP({1,2,3},sq)))"), n(14.0));
    assert_eq!(eval("=LET(add,LAMBDA(a,b,a+b),REDUCE(0,{1,2,3,4},add))"), n(10.0));
}

#[test]
fn a_lambda_left_uncalled_or_called_wrongly_is_an_error() {
    assert_eq!(eval("=IF(TRUE,LAMBDA(x,x))"), err(XlError::Calc));
    assert_eq!(eval("=LET(f,LAMBDA(x,LAMBDA(y,x+y)),f(3))"), err(XlError::Calc));
    assert_eq!(eval("=LAMBDA(x,x)(1,2)"), err(XlError::Value));
    assert_eq!(eval("=LET(f,LAMBDA(x,LAMBDA(y,x+y)),f(3)(4,5))"), err(XlError::Value));
    // Only a LAMBDA can be called; an error in the callee passes on.
    assert_eq!(eval("=IF(FALSE,LAMBDA(x,x))(5)"), err(XlError::Value));
    assert_eq!(eval("=IF(1/0,LAMBDA(x,x))(5)"), err(XlError::Div0));
}

/// Defined names are named formulas: their relative references are relative to the cell
/// that uses them (jkp-ads.com "Range Names In Excel": a name `=Sheet2!A1` defined from C3
/// is two rows up and two columns left of whichever cell uses it). A name holding a LAMBDA
/// is one too, so its relative references follow the calling cell, not A1.
#[test]
fn a_named_lambdas_relative_references_follow_the_calling_cell() {
    let mut wb = Workbook::with_sheet();
    // Defined from A1: "the cell one row below, same column".
    wb.define_name("below", "=LAMBDA(k,Sheet1!A2*k)", None).unwrap();
    set(&mut wb, "A2", "1");
    set(&mut wb, "B6", "4");
    set(&mut wb, "C2", "7");
    set(&mut wb, "B5", "=below(10)");
    set(&mut wb, "C1", "=below(2)");
    assert_eq!(get(&wb, "B5"), n(40.0));
    assert_eq!(get(&wb, "C1"), n(14.0));
    // The cell it reads is a dependency of the calling cell.
    set(&mut wb, "B6", "5");
    assert_eq!(get(&wb, "B5"), n(50.0));
    // Handed to MAP, it reads from the cell that holds the MAP.
    set(&mut wb, "B8", "=SUM(MAP({1,2},below))");
    set(&mut wb, "B9", "100");
    assert_eq!(get(&wb, "B8"), n(300.0));
}

// ---- relative references of defined names wrap at the sheet's edges --------------------
// Excel keeps a name's relative reference as an offset from the cell using it, modulo the
// sheet's size: `prev` = Sheet1!A1048576 defined from A1 is "the row above", and in row 1 it
// is row 1,048,576 (the well-known idiom for a "previous row" name).

#[test]
fn a_names_relative_row_wraps_to_the_last_row() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("prev", "=Sheet1!A1048576", None).unwrap();
    set(&mut wb, "B4", "10");
    set(&mut wb, "B5", "=prev*2");
    assert_eq!(get(&wb, "B5"), n(20.0));
    set(&mut wb, "B1048576", "42");
    set(&mut wb, "B1", "=prev+1");
    assert_eq!(get(&wb, "B1"), n(43.0));
    // The wrapped cell is a dependency.
    set(&mut wb, "B1048576", "50");
    assert_eq!(get(&wb, "B1"), n(51.0));
}

#[test]
fn a_names_relative_column_wraps_to_the_last_column() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("leftcell", "=Sheet1!XFD1", None).unwrap();
    set(&mut wb, "XFD3", "8");
    set(&mut wb, "A3", "=leftcell*3");
    assert_eq!(get(&wb, "A3"), n(24.0));
    set(&mut wb, "B7", "2");
    set(&mut wb, "C7", "=leftcell");
    assert_eq!(get(&wb, "C7"), n(2.0));
    // A whole row, relative, wraps too: from row 1 the last row.
    wb.define_name("rowabove", "=Sheet1!1048576:1048576", None).unwrap();
    set(&mut wb, "C1048576", "5");
    set(&mut wb, "D1048576", "6");
    set(&mut wb, "A1", "=SUM(rowabove)");
    assert_eq!(get(&wb, "A1"), n(11.0));
    // Absolute references never wrap.
    wb.define_name("fixed", "=Sheet1!$B$7", None).unwrap();
    set(&mut wb, "A2", "=fixed");
    assert_eq!(get(&wb, "A2"), n(2.0));
    assert_eq!(wb.value(0, parse_cell("A2").unwrap()), n(2.0));
}

// ---- whole rows and columns read whole ---------------------------------------------------
// A whole row is 16,384 cells and a whole column 1,048,576 (Excel's specifications and
// limits); `1:1+1` is an array of as many items, a blank plus 1 being 1 (blanks are 0 in
// arithmetic). The expected sums below count every item.

const COLS: f64 = 16_384.0;
const ROWS: f64 = 1_048_576.0;

/// Row 1 holds 1, 2, 3 in A1:C1; the rest of the row is blank.
fn row_of_three() -> Workbook {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "1"), ("B1", "2"), ("C1", "3")] {
        set(&mut wb, cell, v);
    }
    wb
}

#[test]
fn sumproduct_reads_every_item_of_a_whole_row() {
    let mut wb = row_of_three();
    // (1+1) + (2+1) + (3+1) + one for each of the other 16,381 cells.
    let plus_one = 2.0 + 3.0 + 4.0 + (COLS - 3.0);
    set(&mut wb, "A2", "=SUMPRODUCT(1:1+1)");
    assert_eq!(get(&wb, "A2"), n(plus_one));
    set(&mut wb, "A3", "=SUMPRODUCT(1:1+1,1:1+1)");
    assert_eq!(get(&wb, "A3"), n(4.0 + 9.0 + 16.0 + (COLS - 3.0)));
    set(&mut wb, "A4", "=SUMPRODUCT(1:1,1:1+1)");
    assert_eq!(get(&wb, "A4"), n(2.0 + 6.0 + 12.0));
    // Shapes must agree over the whole size: a whole row against three cells is #VALUE!.
    set(&mut wb, "A5", "=SUMPRODUCT(1:1+1,A1:C1)");
    assert_eq!(get(&wb, "A5"), err(XlError::Value));
    // A whole column the same way: 1,048,576 items of 2.
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "7");
    set(&mut wb, "B1", "=SUMPRODUCT(A:A*0+2)");
    assert_eq!(get(&wb, "B1"), n(2.0 * ROWS));
}

#[test]
fn a_whole_row_spill_is_read_whole_through_its_reference() {
    let mut wb = row_of_three();
    // A3 spills over the whole of row 3 (A3:XFD3): 2, 3, 4 and then 1s.
    set(&mut wb, "A3", "=1:1+1");
    let plus_one = 2.0 + 3.0 + 4.0 + (COLS - 3.0);
    set(&mut wb, "A5", "=SUMPRODUCT(A3#)");
    set(&mut wb, "B5", "=SUM(A3#)");
    set(&mut wb, "C5", "=COUNT(A3#)");
    assert_eq!(get(&wb, "A5"), n(plus_one));
    assert_eq!(get(&wb, "B5"), n(plus_one));
    assert_eq!(get(&wb, "C5"), n(COLS));
}

#[test]
fn matrices_and_transpose_read_every_item_of_a_whole_row() {
    let mut wb = row_of_three();
    // TRANSPOSE turns the whole row into a whole-height column of 16,384 rows.
    set(&mut wb, "A2", "=ROWS(TRANSPOSE(1:1+1))");
    assert_eq!(get(&wb, "A2"), n(COLS));
    set(&mut wb, "B2", "=SUM(TRANSPOSE(1:1+1))");
    assert_eq!(get(&wb, "B2"), n(2.0 + 3.0 + 4.0 + (COLS - 3.0)));
    // A row times its transpose is the sum of the squares of all its items.
    set(&mut wb, "C2", "=MMULT(1:1+1,TRANSPOSE(1:1+1))");
    assert_eq!(get(&wb, "C2"), n(4.0 + 9.0 + 16.0 + (COLS - 3.0)));
    // MMULT refuses blank cells (Microsoft's MMULT page: "any cells are empty" is #VALUE!).
    set(&mut wb, "D2", "=MMULT(1:1,TRANSPOSE(1:1+1))");
    assert_eq!(get(&wb, "D2"), err(XlError::Value));
}

// ---- the active sheet ----------------------------------------------------------------------
// ECMA-376 Part 1, 18.2.30 workbookView: `activeTab` is the index of the sheet shown when the
// workbook opens (0 when absent). Both files below were saved by Excel with their second tab
// active.

/// An Excel-saved workbook of the public corpus, or `None` without the corpus.
fn public_workbook(rel: &str) -> Option<ncsheet::io::xlsx::Imported> {
    let root = common::corpus::public_root()?;
    Some(ncsheet::io::xlsx::load(&root.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}")))
}

#[test]
fn a_workbook_opens_on_the_sheet_its_file_names_active() {
    for (rel, active) in [
        ("poi/test-data_spreadsheet_SimpleNormal.xlsx", "Sheet Number 2"),
        ("koala/tests_files_SharedFormula.xlsx", "Sheet1"),
    ] {
        let Some(imported) = public_workbook(rel) else { return };
        let mut wb = imported.workbook;
        assert_eq!(wb.sheet_names()[wb.active_sheet() as usize], active, "{rel}");
        // VBA's ActiveSheet is that sheet.
        let src = "Sub Main()\nDebug.Print ActiveSheet.Name\nEnd Sub\n";
        let out = ncsheet::vba::run(&mut wb, src, "active.bas", &ncsheet::vba::RunOptions::default()).unwrap();
        assert_eq!(out.printed, vec![active.to_string()], "{rel}");
        // Saved and opened again, it is still the active one.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("saved.xlsx");
        ncsheet::io::save(&wb, &path).unwrap();
        let again = ncsheet::io::load(&path).unwrap();
        assert_eq!(again.sheet_names()[again.active_sheet() as usize], active, "{rel} saved");
    }
}

#[test]
fn a_new_workbook_is_active_on_its_first_sheet() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Other").unwrap();
    assert_eq!(wb.active_sheet(), 0);
    wb.set_active_sheet(1);
    assert_eq!(wb.active_sheet(), 1);
    // A sheet the workbook does not have is ignored.
    wb.set_active_sheet(7);
    assert_eq!(wb.active_sheet(), 1);
}

// ---- R1C1 reference style ------------------------------------------------------------------
// Microsoft's Range.Formula page: Formula is in A1 style "in the language of the macro"
// whatever Application.ReferenceStyle shows; FormulaR1C1 is in R1C1 style. ECMA-376 18.2.2
// calcPr: `refMode` only says how the window shows references; formulas in the file are A1.

#[test]
fn a_macros_formula_stays_a1_when_the_reference_style_is_r1c1() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "5");
    let src = "Sub Main()\n\
               Application.ReferenceStyle = xlR1C1\n\
               Debug.Print Application.ReferenceStyle = xlR1C1\n\
               Range(\"B1\").Formula = \"=A1*2\"\n\
               Range(\"C1\").FormulaR1C1 = \"=RC[-1]*3\"\n\
               Range(\"D1:D2\").Formula = \"=$A$1+A1\"\n\
               Debug.Print Range(\"B1\").Formula\n\
               Debug.Print Range(\"C1\").FormulaR1C1\n\
               Application.ReferenceStyle = xlA1\n\
               Debug.Print Application.ReferenceStyle\n\
               End Sub\n";
    let out = ncsheet::vba::run(&mut wb, src, "r1c1.bas", &ncsheet::vba::RunOptions::default()).unwrap();
    // Debug.Print writes a number with a space for its sign and one after it.
    assert_eq!(out.printed, vec!["True", "=A1*2", "=RC[-1]*3", " 1 "]);
    assert_eq!(get(&wb, "B1"), n(10.0));
    assert_eq!(get(&wb, "C1"), n(30.0));
    assert_eq!(get(&wb, "D1"), n(10.0));
    // D2's relative A1 moved to A2 (blank).
    assert_eq!(get(&wb, "D2"), n(5.0));
    // Any other style is refused, naming the property.
    let bad = "Sub Main()\nApplication.ReferenceStyle = 3\nEnd Sub\n";
    let e = ncsheet::vba::run(&mut wb, bad, "bad.bas", &ncsheet::vba::RunOptions::default()).unwrap_err();
    assert!(e.to_string().contains("ReferenceStyle"), "{e}");
}

#[test]
fn a_workbook_saved_in_r1c1_mode_computes_its_a1_formulas() {
    let Some(root) = common::corpus::public_root() else { return };
    for rel in ["koala/tests_files_SharedFormula.xlsx", "poi/test-data_spreadsheet_56574.xlsx"] {
        let bytes = std::fs::read(root.join(rel)).unwrap();
        // The same workbook as Excel saves it with File > Options > R1C1 reference style on.
        let options = zip::write::SimpleFileOptions::default();
        let out = common::rewrite_package(&bytes, options, &mut |name, data| {
            if name != "xl/workbook.xml" {
                return data;
            }
            let text = String::from_utf8(data).unwrap();
            assert!(text.contains("<calcPr "), "{rel}");
            text.replacen("<calcPr ", "<calcPr refMode=\"R1C1\" ", 1).into_bytes()
        });
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r1c1.xlsx");
        std::fs::write(&path, out.finish().unwrap().into_inner()).unwrap();
        let imported = ncsheet::io::xlsx::load(&path).unwrap();
        let agree = &ncsheet::io::xlsx::values_agree;
        let (results, _) = common::judge(&imported, &|c| Some(c.value.clone()), &|_| false, agree);
        let wrong: Vec<String> = results
            .iter()
            // TODAY() is today's date, not the day Excel saved the file.
            .filter(|r| !matches!(r.verdict, common::Verdict::Agree | common::Verdict::Volatile))
            .map(|r| {
                let wb = &imported.workbook;
                let formula = wb.formula(r.sheet, r.anchor).unwrap_or_default();
                let got = wb.value(r.sheet, r.pos);
                format!("{}: {formula} gives {got:?}, Excel {:?}", wb.cell_name(r.sheet, r.pos), r.expected)
            })
            .collect();
        let agreed = results.iter().filter(|r| r.verdict == common::Verdict::Agree).count();
        assert!(agreed >= 20, "{rel}: only {agreed} compared");
        assert!(
            wrong.is_empty(),
            "{rel}: {} of {} disagree with Excel:\n{}",
            wrong.len(),
            results.len(),
            wrong.join("\n")
        );
        assert!(imported.workbook.problems().is_empty(), "{rel}: {:?}", imported.workbook.problems());
    }
}

#[test]
fn a_named_lambda_calling_itself_twice_links_its_cells_once() {
    // Linking follows the names a formula calls; a LAMBDA that branches into itself must be
    // expanded once, not 2^n times.
    let mut wb = Workbook::with_sheet();
    wb.define_name("TREE", "=LAMBDA(n, IF(n=0, Sheet1!$A$1, TREE(n-1)+TREE(n-1)))", None).unwrap();
    set(&mut wb, "A1", "1");
    set(&mut wb, "B1", "=TREE(3)");
    assert_eq!(get(&wb, "B1"), n(8.0));
    set(&mut wb, "A1", "2");
    assert_eq!(get(&wb, "B1"), n(16.0));
}

/// Excel's SUMIF (Microsoft's SUMIF, SUMIFS, AVERAGEIF, MINIFS pages): a blank criteria cell
/// matches `""` and `"<>x"`, and the sum range beside it counts. With whole columns on
/// another sheet, the rows past that sheet's used area are such blanks: Sheet1!A1 = "a"
/// alone, Sheet2!B1:B3 = 1, 2, 3, so A2:A3 are blank beside 2 and 3 (ncsheet took only row 1,
/// giving 1 and 0 for the first two).
#[test]
fn criteria_blanks_past_the_criteria_sheets_used_area_match() {
    let mut wb = Workbook::with_sheet();
    let other = wb.add_sheet("Sheet2").unwrap();
    set(&mut wb, "A1", "a");
    for (cell, input) in [("B1", "1"), ("B2", "2"), ("B3", "3")] {
        wb.set_input(other, parse_cell(cell).unwrap(), input).unwrap();
    }
    let cases = [
        ("=SUMIF(Sheet1!A:A,\"<>x\",B:B)", 6.0),
        ("=SUMIF(Sheet1!A:A,\"\",B:B)", 5.0),
        ("=SUMIFS(B:B,Sheet1!A:A,\"\")", 5.0),
        ("=AVERAGEIF(Sheet1!A:A,\"\",B:B)", 2.5),
        ("=AVERAGEIFS(B:B,Sheet1!A:A,\"<>a\")", 2.5),
        ("=MINIFS(B:B,Sheet1!A:A,\"\")", 2.0),
        ("=MAXIFS(B:B,Sheet1!A:A,\"<>x\")", 3.0),
        // Each of 100 keys is unequal to "a" and to the blanks: 6 each.
        ("=SUM(SUMIF(Sheet1!A:A,\"<>\"&SEQUENCE(100),B:B))", 600.0),
        ("=SUM(SUMIF(Sheet1!A:A,\"<>\"&{\"a\",\"b\"},B:B))", 11.0),
    ];
    for (i, (formula, expected)) in cases.iter().enumerate() {
        let at = ncsheet::formula::address::Pos::new(i as u32, 4);
        wb.set_input(other, at, formula).unwrap();
        assert_eq!(wb.value(other, at), n(*expected), "{formula}");
    }
}
