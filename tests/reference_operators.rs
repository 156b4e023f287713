//! Excel's reference operators: the union `(A1:A3,C1)`, the intersection `A1:C3 B2:D4`,
//! names defined as unions, and the functions that read references of several areas.
//!
//! The expected values are LibreOffice 7.4's: the same grid and formulas written as a flat
//! ODF spreadsheet (union `~`, intersection `!`) and recalculated by `soffice --convert-to
//! xlsx`. Where LibreOffice answers with another error than Excel, Excel's documentation
//! decides, and the test says so.

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// A1:A3 = 1 2 3, B1:B3 = 100 200 300, C1:C3 = 10 20 30, D1:E2 = 5 6 / 7 8; the names
/// `Multi` = A1:A3 and C1, `SecondRow` = A2:E2, `ColB` = B1:B3.
fn grid() -> Workbook {
    let mut wb = Workbook::with_sheet();
    let cells = [
        ("A1", "1"),
        ("A2", "2"),
        ("A3", "3"),
        ("B1", "100"),
        ("B2", "200"),
        ("B3", "300"),
        ("C1", "10"),
        ("C2", "20"),
        ("C3", "30"),
        ("D1", "5"),
        ("E1", "6"),
        ("D2", "7"),
        ("E2", "8"),
    ];
    for (cell, input) in cells {
        wb.set_input(0, parse_cell(cell).expect("cell"), input).expect("input");
    }
    // As Excel stores a multi-area name in workbook.xml: no parentheses.
    wb.define_name("Multi", "Sheet1!$A$1:$A$3,Sheet1!$C$1", None).expect("union name");
    wb.define_name("SecondRow", "Sheet1!$A$2:$E$2", None).expect("name");
    wb.define_name("ColB", "Sheet1!$B$1:$B$3", None).expect("name");
    wb
}

fn eval(wb: &mut Workbook, formula: &str) -> Value {
    let at = parse_cell("H1").expect("cell");
    wb.set_input(0, at, formula).unwrap_or_else(|e| panic!("{formula}: {e:?}"));
    wb.value(0, at)
}

fn n(v: f64) -> Value {
    Value::Number(v)
}

#[test]
fn functions_over_references_read_every_area_of_a_union() {
    let mut wb = grid();
    let cases = [
        ("=SUM((A1:A3,C1:C3))", n(66.0)),
        ("=COUNT((A1:A3,C1))", n(4.0)),
        ("=MAX((A1:A3,C1:C3))", n(30.0)),
        ("=AVERAGE((A1:A3,C1:C3))", n(11.0)),
        ("=RANK(C2,(A1:A3,C1:C3))", n(2.0)),
        ("=LARGE((A1:A3,C1:C3),2)", n(20.0)),
        ("=COUNTA((A1:E3,C1:C3))", n(16.0)),
        ("=MIN((B1:B3,D1:E2))", n(5.0)),
        ("=SUBTOTAL(9,(A1:A3,C1:C3))", n(66.0)),
        ("=ISREF((A1,B1))", Value::Bool(true)),
    ];
    for (formula, expected) in cases {
        assert_eq!(eval(&mut wb, formula), expected, "{formula}");
    }
}

#[test]
fn index_picks_an_area_and_areas_counts_them() {
    let mut wb = grid();
    let cases = [
        ("=INDEX((A1:B2,D1:E2),1,1,2)", n(5.0)),
        ("=INDEX((A1:B2,D1:E2),2,2,2)", n(8.0)),
        ("=INDEX((A1:B2,D1:E2),1,1,3)", Value::Error(XlError::Ref)),
        ("=AREAS((A1:A3,C1,D1:E2))", n(3.0)),
        ("=AREAS(A1:C3 B2:D4)", n(1.0)),
        ("=AREAS(Multi)", n(2.0)),
        ("=INDEX(Multi,2,1,1)", n(2.0)),
        ("=INDEX(Multi,1,1,2)", n(10.0)),
        ("=SUM(Multi)", n(16.0)),
    ];
    for (formula, expected) in cases {
        assert_eq!(eval(&mut wb, formula), expected, "{formula}");
    }
}

#[test]
fn a_space_intersects_references() {
    let mut wb = grid();
    assert_eq!(eval(&mut wb, "=SUM(A1:C3 B2:D4)"), n(550.0));
    // Excel's documentation: "=Row ColB" style names meet in one cell.
    assert_eq!(eval(&mut wb, "=SecondRow ColB"), n(200.0));
    // References that share no cell: Excel's #NULL! ("#NULL! … when you specify an
    // intersection of two areas that do not intersect"); LibreOffice says #REF!.
    assert_eq!(eval(&mut wb, "=A1:A3 C2"), Value::Error(XlError::Null));
}

#[test]
fn a_reference_of_several_areas_has_no_one_shape_or_value() {
    let mut wb = grid();
    // LibreOffice answers Err:504 (a bad parameter) for ROW, COLUMN, ROWS and COLUMNS of
    // several areas. Excel: "Office returns #REF!, if array refers to the union of
    // discontiguous ranges" ([MS-OI29500] 2.1.1035 on ROWS, against the standard's #NULL!),
    // and ECMA-376 Part 1 §18.17.7 ROW and COLUMN: "if the range of cells referred to by
    // reference is not contiguous, #REF! is returned".
    assert_eq!(eval(&mut wb, "=ROWS((A1:A3,C1))"), Value::Error(XlError::Ref));
    assert_eq!(eval(&mut wb, "=COLUMNS((A1,B1))"), Value::Error(XlError::Ref));
    assert_eq!(eval(&mut wb, "=ROW((A1:A2,C3))"), Value::Error(XlError::Ref));
    assert_eq!(eval(&mut wb, "=COLUMN((A1:A2,C3))"), Value::Error(XlError::Ref));
    // The same area twice is still two areas.
    assert_eq!(eval(&mut wb, "=ROW((C3,C3))"), Value::Error(XlError::Ref));
    assert_eq!(eval(&mut wb, "=(A1:A3,C1)"), Value::Error(XlError::Value));
    // One area of them, as INDEX or an intersection gives it, has its shape (LibreOffice
    // 7.4 agrees: 3, 2, 2, and #REF! past the last area).
    assert_eq!(eval(&mut wb, "=ROW(INDEX((A1:B2,C3:D4),1,1,2))"), n(3.0));
    assert_eq!(eval(&mut wb, "=COLUMNS(INDEX((A1:B2,C3:D4),0,0,2))"), n(2.0));
    assert_eq!(eval(&mut wb, "=ROWS((A1:B2 B1:B3))"), n(2.0));
    assert_eq!(eval(&mut wb, "=INDEX((A1:B2,C3:D4),1,1,3)"), Value::Error(XlError::Ref));
    // INDEX without an area number reads the first area (LibreOffice: B2 of A1:B2).
    assert_eq!(eval(&mut wb, "=INDEX((A1:B2,C3:D4),2,2)"), n(200.0));
}

#[test]
fn reference_operators_print_back_as_written() {
    let mut wb = grid();
    for formula in ["=SUM((A1:A3,C1:C3))", "=SUM(A1:C3 B2:D4)", "=INDEX((A1:B2,D1:E2),1,1,2)", "=SecondRow ColB"] {
        eval(&mut wb, formula);
        assert_eq!(wb.formula(0, parse_cell("H1").expect("cell")).as_deref(), Some(formula));
    }
    let names = wb.names();
    let multi = names.iter().find(|(n, _, _)| n == "Multi").expect("Multi");
    assert_eq!(multi.1, "=Sheet1!$A$1:$A$3,Sheet1!$C$1");
}

#[test]
fn two_operands_without_a_space_between_them_do_not_parse() {
    let mut wb = grid();
    assert!(wb.set_input(0, parse_cell("H2").expect("cell"), "=(A1)(B1)").is_err());
    assert!(wb.set_input(0, parse_cell("H2").expect("cell"), "=SUM(A1,B1)").is_ok());
}

#[test]
fn a_union_recalculates_when_any_area_changes() {
    let mut wb = grid();
    eval(&mut wb, "=SUM((A1:A3,C1:C3))");
    wb.set_input(0, parse_cell("C3").expect("cell"), "40").expect("input");
    assert_eq!(wb.value(0, parse_cell("H1").expect("cell")), n(76.0));
    eval(&mut wb, "=SUM(Multi)");
    wb.set_input(0, parse_cell("C1").expect("cell"), "11").expect("input");
    assert_eq!(wb.value(0, parse_cell("H1").expect("cell")), n(17.0));
}

#[test]
fn an_xlsx_written_new_keeps_unions_intersections_and_union_names() {
    use ncsheet::io::xlsx;
    let mut wb = grid();
    let formulas = [("H1", "=SUM((A1:A3,C1:C3))"), ("H2", "=SUM(A1:C3 B2:D4)"), ("H3", "=SUM(Multi)")];
    for (cell, formula) in formulas {
        wb.set_input(0, parse_cell(cell).expect("cell"), formula).expect("formula");
    }
    let bytes = xlsx::to_bytes(&wb, &xlsx::Layout::default()).expect("writes");
    let again = xlsx::load_bytes(&bytes, std::path::Path::new("again.xlsx")).expect("reads back");
    for ((cell, formula), expected) in formulas.iter().zip([66.0, 550.0, 16.0]) {
        let pos = parse_cell(cell).expect("cell");
        assert_eq!(again.workbook.formula(0, pos).as_deref(), Some(*formula));
        assert_eq!(again.workbook.value(0, pos), n(expected), "{formula}");
    }
}

#[test]
fn a_union_of_values_does_not_parse() {
    // MS-XLSX's grammar joins only reference expressions with `,` and space: a decimal comma
    // written into a file by another application (`=L6-(-4,3)`) is no formula Excel reads.
    let mut wb = grid();
    for formula in ["=L6-(-4,3)", "=(1,2)+1", "=SUM((A1,\"x\"))"] {
        assert!(wb.set_input(0, parse_cell("H2").expect("cell"), formula).is_err(), "{formula}");
    }
}

#[test]
fn a_sheet_scoped_name_is_read_from_another_sheet_through_its_sheet() {
    let mut wb = Workbook::with_sheet();
    let data = wb.add_sheet("Data Sheet").expect("sheet");
    wb.set_input(data, parse_cell("B2").expect("cell"), "7").expect("input");
    wb.define_name("Rate", "'Data Sheet'!$B$2", Some(data)).expect("scoped name");
    let at = parse_cell("A1").expect("cell");
    wb.set_input(0, at, "='Data Sheet'!Rate*2").expect("formula");
    assert_eq!(wb.value(0, at), n(14.0));
    assert_eq!(wb.formula(0, at).as_deref(), Some("='Data Sheet'!Rate*2"));
    // The name is not visible from Sheet1 without its sheet.
    wb.set_input(0, parse_cell("A2").expect("cell"), "=Rate").expect("formula");
    assert_eq!(wb.value(0, parse_cell("A2").expect("cell")), Value::Error(XlError::Name));
    // An edit of the cell the name points at recomputes the formula.
    wb.set_input(data, parse_cell("B2").expect("cell"), "8").expect("input");
    assert_eq!(wb.value(0, at), n(16.0));
}
