//! VBA's own semantics where ncsheet used to differ (issue 31, scope 1): a macro written for
//! Excel gives Excel's result, or is refused with the reason. Each test cites the page of
//! Microsoft's VBA reference or the section of [MS-VBAL] (the VBA language specification)
//! its expected value comes from.

mod common;

use common::vba::{main_fails, run_main};
use ncsheet::formula::address::parse_cell;
use ncsheet::vba::project::{ModuleKind, ProjectModule, VbaProject};
use ncsheet::vba::RunOptions;
use ncsheet::workbook::Workbook;

/// A workbook of one sheet whose VBA project is one standard module, Module1, holding
/// `source`, installed as the workbook's own functions; `cells` typed in after.
fn book_with_functions(source: &str, cells: &[(&str, &str)]) -> Workbook {
    let mut wb = Workbook::with_sheet();
    let project = VbaProject {
        code_page: 1252,
        modules: vec![ProjectModule {
            name: "Module1".into(),
            stream: "Module1".into(),
            kind: ModuleKind::Standard,
            source: source.into(),
        }],
        protection: None,
    };
    assert!(ncsheet::vba::install_functions(&mut wb, &project, RunOptions::default()).is_empty());
    for (cell, text) in cells {
        wb.set_input(0, parse_cell(cell).unwrap(), text).unwrap();
    }
    wb
}

// ---- item 1: a function in a cell sees the number format the running macro set ----------

/// Excel VBA reference, "Range.Text property": the formatted text of the cell. A function
/// called from a cell reads the same cell's look the macro that is running gave it.
#[test]
fn a_cell_function_reading_text_sees_the_format_the_macro_set() {
    let mut wb = book_with_functions(
        "Public Function Shown(r As Range) As String\n    Shown = r.Text\nEnd Function\n",
        &[("B1", "=Shown(A1)")],
    );
    let printed = run_main(
        &mut wb,
        "    Range(\"A1\").NumberFormat = \"0.00\"\n    Range(\"A1\").Value = 1.5\n    Debug.Print Range(\"B1\").Value",
    );
    assert_eq!(printed, ["1.50"]);
}

// ---- item 5: For Each goes through an array only with a Variant -------------------------

/// VBA reference, "For Each control variable must be Variant or Object" (and "… on arrays
/// must be Variant"); [MS-VBAL] 5.4.2.4 lets each item be let-assigned, which into an Integer
/// would round 1.5 and 2.5 to 2 and 2. VBA refuses the procedure instead, and no handler
/// traps a compile error.
#[test]
fn for_each_with_an_integer_control_variable_is_refused() {
    let message = main_fails(
        &mut Workbook::with_sheet(),
        "    On Error Resume Next\n    Dim m As Integer\n    For Each m In Array(1.5, 2.5)\n        Debug.Print m\n    Next",
    );
    assert!(message.contains("For Each control variable must be Variant or Object"), "{message}");
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "    Dim m As Variant\n    For Each m In Array(1.5, 2.5)\n        Debug.Print CStr(m)\n    Next",
    );
    assert_eq!(printed, ["1.5", "2.5"]);
}
