//! The workbook's own functions (issue #16, #11): a public VBA Function of the workbook's
//! project, called from a cell, computes as Excel does. Expected values are Excel's cached
//! results (testNames.xlsm) or worked out by hand here from what the code says.

mod common;

use std::path::Path;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::{parse_cell, Pos};
use ncsheet::io::xlsx;
use ncsheet::vba::project::{ModuleKind, ProjectModule, VbaProject};
use ncsheet::vba::RunOptions;
use ncsheet::workbook::Workbook;

fn at(a1: &str) -> Pos {
    parse_cell(a1).unwrap()
}

/// A workbook of one sheet with `cells` typed in, and a VBA project of `modules` (name, kind,
/// source) installed as its functions.
fn book(modules: &[(&str, ModuleKind, &str)], cells: &[(&str, &str)]) -> Workbook {
    let mut wb = Workbook::with_sheet();
    for (cell, text) in cells {
        wb.set_input(0, at(cell), text).unwrap();
    }
    let project = VbaProject {
        code_page: 1252,
        modules: modules
            .iter()
            .map(|(name, kind, source)| ProjectModule {
                name: name.to_string(),
                stream: name.to_string(),
                kind: *kind,
                source: source.to_string(),
            })
            .collect(),
        protection: None,
    };
    let errors = ncsheet::vba::install_functions(&mut wb, &project, RunOptions::default());
    assert!(errors.is_empty(), "{errors:?}");
    wb
}

fn number(wb: &Workbook, cell: &str) -> f64 {
    match wb.value(0, at(cell)) {
        Value::Number(n) => n,
        other => panic!("{cell}: {other:?}"),
    }
}

const STANDARD: ModuleKind = ModuleKind::Standard;

/// docs/domain.md §1, formula 2: A'C = r / sin β with β = π/2 − α·π/180, the distance from the
/// nose centre's corner to the chamfer line along X for nose radius r at chamfer angle α.
const NOSE_BAS: &str = "Attribute VB_Name = \"Nose\"\r\n\
Option Explicit\r\n\
\r\n\
' docs/domain.md section 1, formula 2: A'C = r / sin(beta), beta = pi/2 - alpha*pi/180\r\n\
Public Function NOSE_OFFSET(r As Double, alpha As Double) As Double\r\n\
    Dim beta As Double\r\n\
    beta = 3.14159265358979 / 2 - alpha * 3.14159265358979 / 180\r\n\
    NOSE_OFFSET = r / Sin(beta)\r\n\
End Function\r\n";

/// testNames.xlsm (Apache POI's test data, saved by Excel): `myFunc = a & "abc"` and
/// `myFunc2 = a & "abc2"` in Module1; B1, C1 and A5 call them and Excel cached "_abc",
/// "_abc2" and "defabc". `crapName` is no function anywhere: #NAME?, as Excel cached.
#[test]
fn test_names_functions_compute_what_excel_cached() {
    let path = common::corpus::public_path().join("poi/test-data_spreadsheet_testNames.xlsm");
    let mut imported = xlsx::load(&path).unwrap();
    common::install_workbook_functions(&mut imported);
    let wb = &imported.workbook;
    let mut compared = 0;
    for c in &imported.cached {
        assert_eq!(wb.value(c.sheet, c.pos), c.value, "{}", wb.cell_name(c.sheet, c.pos));
        compared += 1;
    }
    assert_eq!(compared, 7);
    assert_eq!(wb.value(0, at("B1")), Value::text("_abc"));
    assert_eq!(wb.value(0, at("C1")), Value::text("_abc2"));
    assert_eq!(wb.value(0, at("A5")), Value::text("defabc"));
    assert_eq!(wb.value(0, at("A6")), Value::Error(XlError::Name));
}

/// The command line installs the functions when it opens the file: `eval --check` finds
/// every value Excel stored, the function cells' among them.
#[test]
fn eval_check_of_test_names_agrees_with_excel_everywhere() {
    let path = common::corpus::public_path().join("poi/test-data_spreadsheet_testNames.xlsm");
    let run = common::cli::ncsheet(&["eval", &path.to_string_lossy(), "--check"]);
    assert!(run.stderr.contains("7 of 7 stored values agree with Excel"), "{}", run.stderr);
}

/// Excel's rules for the name: any case, and qualified by the module.
#[test]
fn a_public_function_is_called_by_name_in_any_case_or_qualified_by_its_module() {
    let wb = book(
        &[("Module1", STANDARD, "Function Twice(x)\r\n    Twice = x * 2\r\nEnd Function\r\n")],
        &[("A1", "21"), ("B1", "=Twice(A1)"), ("B2", "=TWICE(A1)+1"), ("B3", "=Module1.twice(4)")],
    );
    assert_eq!(number(&wb, "B1"), 42.0);
    assert_eq!(number(&wb, "B2"), 43.0);
    assert_eq!(number(&wb, "B3"), 8.0);
}

/// A Range argument is a Range: `.Rows.Count`, `.Cells(i, j)` and `For Each`. A1:A3 hold 1,
/// 2, 3: the sum is 6, times 3 rows is 18, plus Cells(2, 1) = 2 is 20.
#[test]
fn a_reference_argument_arrives_as_a_range() {
    let source = "Function Weigh(r As Range)\r\n\
        Dim c, total\r\n\
        For Each c In r\r\n\
            total = total + c.Value\r\n\
        Next\r\n\
        Weigh = total * r.Rows.Count + r.Cells(2, 1).Value\r\n\
    End Function\r\n";
    let mut wb =
        book(&[("Module1", STANDARD, source)], &[("A1", "1"), ("A2", "2"), ("A3", "3"), ("B1", "=Weigh(A1:A3)")]);
    assert_eq!(number(&wb, "B1"), 20.0);
    // An edited cell of the range recomputes it: 1 + 5 + 3 = 9, times 3 is 27, plus 5 is 32.
    wb.set_input(0, at("A2"), "5").unwrap();
    assert_eq!(number(&wb, "B1"), 32.0);
}

/// Private Functions, Subs, and Functions of sheet or class modules are not callable from a
/// cell: #NAME?, as in Excel.
#[test]
fn private_functions_subs_and_document_modules_are_name_errors() {
    let wb = book(
        &[
            (
                "Module1",
                STANDARD,
                "Private Function Hidden()\r\n    Hidden = 1\r\nEnd Function\r\nSub Act()\r\nEnd Sub\r\n",
            ),
            ("Sheet1", ModuleKind::DocumentOrClass, "Public Function OnSheet()\r\n    OnSheet = 1\r\nEnd Function\r\n"),
        ],
        &[("A1", "=Hidden()"), ("A2", "=Act()"), ("A3", "=OnSheet()"), ("A4", "=Sheet1.OnSheet()")],
    );
    for cell in ["A1", "A2", "A3", "A4"] {
        assert_eq!(wb.value(0, at(cell)), Value::Error(XlError::Name), "{cell}");
    }
}

/// A runtime error inside the function, a wrong number of arguments, and an attempt to
/// write a cell are each the cell's #VALUE!; the cell written is left as it was.
#[test]
fn an_error_inside_the_function_is_a_value_error_and_changes_no_cell() {
    // `n = x` with x = "abc" and n a Long: VBA's type mismatch (run-time error 13).
    let source = "Function Fails(x)\r\n    Dim n As Long\r\n    n = x\r\n    Fails = n\r\nEnd Function\r\n\
        Function Writes(x)\r\n    Range(\"C1\").Value = 99\r\n    Writes = x\r\nEnd Function\r\n\
        Function Raises()\r\n    Err.Raise 1000\r\nEnd Function\r\n\
        Function Inverse(x)\r\n    Inverse = 1 / x\r\nEnd Function\r\n";
    let wb = book(
        &[("Module1", STANDARD, source)],
        &[
            ("A1", "abc"),
            ("B1", "=Fails(A1)"),
            ("B2", "=Writes(1)"),
            ("B3", "=Fails(1,2)"),
            ("B4", "=Raises()"),
            // 1 / 0 raises "Division by zero" (error 11) in the function: #VALUE!, as Excel's.
            ("B5", "=Inverse(0)"),
            ("C1", "7"),
        ],
    );
    for cell in ["B1", "B2", "B3", "B4", "B5"] {
        assert_eq!(wb.value(0, at(cell)), Value::Error(XlError::Value), "{cell}");
    }
    assert_eq!(number(&wb, "C1"), 7.0);
}

/// "Description of limitations of custom functions in Excel" (KB 170787): a function called
/// from a cell "cannot change another cell's value"; Excel ends it at that statement, its cell
/// #VALUE!, and its On Error Resume Next does not carry it past to return a number as if the
/// cell had been written.
#[test]
fn a_function_writing_a_cell_under_on_error_is_a_value_error() {
    let source = "Function Writes(x)\r\n    On Error Resume Next\r\n    Range(\"C1\").Value = 99\r\n    \
        Writes = x\r\nEnd Function\r\n";
    let wb = book(&[("Module1", STANDARD, source)], &[("B1", "=Writes(1)"), ("C1", "7")]);
    assert_eq!(wb.value(0, at("B1")), Value::Error(XlError::Value));
    assert_eq!(number(&wb, "C1"), 7.0);
}

/// An array result spills, as Excel's dynamic arrays do: `Array(1, 2, 3)` over three columns.
#[test]
fn an_array_result_spills() {
    let wb = book(
        &[("Module1", STANDARD, "Function Three()\r\n    Three = Array(1, 2, 3)\r\nEnd Function\r\n")],
        &[("A1", "=Three()")],
    );
    assert_eq!([number(&wb, "A1"), number(&wb, "B1"), number(&wb, "C1")], [1.0, 2.0, 3.0]);
}

/// Its dependencies are its arguments' references: an edited argument recomputes the cell.
/// A non-volatile function reading a cell it is not given is not recomputed when that cell
/// changes (Excel's rule); `Application.Volatile` makes it recompute at every edit.
#[test]
fn arguments_are_its_dependencies_and_application_volatile_recomputes_at_every_edit() {
    let source = "Function Plain(x)\r\n    Plain = x + Range(\"D1\").Value\r\nEnd Function\r\n\
        Function Lively(x)\r\n    Application.Volatile\r\n    Lively = x + Range(\"D1\").Value\r\nEnd Function\r\n";
    let mut wb = book(
        &[("Module1", STANDARD, source)],
        &[("A1", "1"), ("D1", "10"), ("B1", "=Plain(A1)"), ("B2", "=Lively(A1)")],
    );
    assert_eq!((number(&wb, "B1"), number(&wb, "B2")), (11.0, 11.0));
    wb.set_input(0, at("A1"), "2").unwrap();
    assert_eq!((number(&wb, "B1"), number(&wb, "B2")), (12.0, 12.0));
    wb.set_input(0, at("D1"), "20").unwrap();
    assert_eq!((number(&wb, "B1"), number(&wb, "B2")), (12.0, 22.0));
    assert!(wb.calls_volatile(0, at("B2")) && !wb.calls_volatile(0, at("B1")));
}

/// A cell whose function reads the cell itself through its argument is a cycle, not a
/// recursion (the function never runs away): named, and showing 0 as Excel shows a circular
/// reference never calculated (Microsoft support, "Remove or allow a circular reference").
#[test]
fn a_function_reading_its_own_cell_through_its_argument_is_a_cycle() {
    let wb =
        book(&[("Module1", STANDARD, "Function Echo(x)\r\n    Echo = x\r\nEnd Function\r\n")], &[("A1", "=Echo(A1)")]);
    assert_eq!(wb.value(0, at("A1")), Value::Number(0.0));
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!A1".to_string()]]);
}

/// The statement limit applies to each call: an endless loop is stopped, the cell #VALUE!.
#[test]
fn an_endless_function_is_stopped_by_the_statement_limit() {
    let mut wb = Workbook::with_sheet();
    wb.set_input(0, at("A1"), "=Forever()").unwrap();
    let project = common::vba::module1("Function Forever()\r\n    Do\r\n    Loop\r\nEnd Function\r\n");
    let options = RunOptions { max_statements: 10_000, ..Default::default() };
    assert!(ncsheet::vba::install_functions(&mut wb, &project, options).is_empty());
    assert_eq!(wb.value(0, at("A1")), Value::Error(XlError::Value));
}

/// A thousand cells calling a slow function used to run for half an hour, each ending as an
/// unexplained `#VALUE!`: the calls of one recalculation share a statement budget (the
/// document's settings), each cell past it is `#VALUE!` with a note naming the limit, and the
/// next recalculation has the whole budget again.
#[test]
fn the_calls_of_one_recalculation_share_a_statement_budget_and_say_so() {
    let limits = |l: &mut ncsheet::eval::FunctionLimits| {
        l.statements_per_call = 10_000;
        l.statements_per_recalculation = 50_000;
    };
    let (mut wb, notes) = endless_calls(40, limits, RunOptions::default());
    // 50,000 statements hold five calls of 10,000; every later call is refused unrun.
    let stopped = notes.iter().filter(|n| n.contains("statement limit (10000)")).count();
    let refused = notes.iter().filter(|n| n.contains("Module1.Forever was not called") && n.contains("50000")).count();
    assert_eq!((stopped, refused), (5, 35), "{notes:#?}");
    wb.set_input(0, at("C1"), "=Quick()").unwrap();
    assert_eq!(number(&wb, "C1"), 7.0, "an edit's recalculation has the whole budget again");
}

/// A workbook whose A1 to A`rows` call Module1's `Forever()` (an endless loop), with its
/// functions (and `Quick()`, 7) installed under `options` and the settings' function limits
/// set by `limits`; each of those cells is `#VALUE!`, and their notes say why.
fn endless_calls(
    rows: u32,
    limits: impl FnOnce(&mut ncsheet::eval::FunctionLimits),
    options: RunOptions,
) -> (Workbook, Vec<String>) {
    let mut wb = Workbook::with_sheet();
    limits(&mut wb.settings_mut().functions);
    for row in 1..=rows {
        wb.set_input(0, at(&format!("A{row}")), "=Forever()").unwrap();
    }
    let source = "Function Forever()\r\n    Do\r\n    Loop\r\nEnd Function\r\n\
                  Function Quick()\r\n    Quick = 7\r\nEnd Function\r\n";
    let project = common::vba::module1(source);
    assert!(ncsheet::vba::install_functions(&mut wb, &project, options).is_empty());
    let notes: Vec<String> = (1..=rows).flat_map(|row| wb.notes(0, at(&format!("A{row}")))).collect();
    for row in 1..=rows {
        assert_eq!(wb.value(0, at(&format!("A{row}"))), Value::Error(XlError::Value), "A{row}");
    }
    (wb, notes)
}

/// A front end that stays open (the workbench) bounds each recalculation by time, as a
/// command's `--timeout` bounds the command: a call running past it stops at its statement,
/// the calls after it are refused unrun, each `#VALUE!` with a note naming the limit; the next
/// recalculation has its whole time again. The statement budgets are out of reach here: only
/// the clock can stop these calls.
#[test]
fn the_calls_of_one_recalculation_stop_at_its_time_limit() {
    let limits = |l: &mut ncsheet::eval::FunctionLimits| {
        l.statements_per_call = u64::MAX;
        l.statements_per_recalculation = u64::MAX;
        l.seconds_per_recalculation = Some(0.2);
    };
    let options = RunOptions { max_statements: u64::MAX, ..RunOptions::default() };
    let (mut wb, notes) = endless_calls(3, limits, options);
    let stopped = notes.iter().filter(|n| n.contains("ran past its --timeout of 0.2 s")).count();
    let refused = notes.iter().filter(|n| n.contains("Module1.Forever was not called") && n.contains("0.2 s")).count();
    assert_eq!((stopped, refused), (1, 2), "{notes:#?}");
    wb.set_input(0, at("C1"), "=Quick()").unwrap();
    assert_eq!(number(&wb, "C1"), 7.0, "an edit's recalculation has its whole time again");
}

/// The sheet XML of `path`'s first worksheet.
fn sheet_xml(path: &Path) -> String {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut part = zip.by_name("xl/worksheets/sheet1.xml").unwrap();
    let mut text = String::new();
    std::io::Read::read_to_string(&mut part, &mut text).unwrap();
    text
}

/// A hand-written .bas imported with `ncsheet macros --import` into a workbook whose C2 is
/// `=NOSE_OFFSET(B2,B3)`: r = 0.8, α = 45° gives 0.8 / sin 45° = 0.8·√2; α edited to 60°
/// gives 0.8 / sin 30° = 1.6. The saved file keeps the formula as typed (no `_xludf.`:
/// Excel itself writes `myFunc("_")` so in testNames.xlsm), and LibreOffice, opening it and
/// saving it again, keeps the formula.
#[test]
fn an_imported_function_computes_in_a_cell_recomputes_on_edit_and_saves_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    std::fs::write(d("nose.bas"), NOSE_BAS).unwrap();
    std::fs::write(d("base.csv"), "r,\nr,0.8\nalpha,45\n").unwrap();
    let made = common::cli::ncsheet(&["set", &d("base.csv"), "C2==NOSE_OFFSET(B2,B3)", "-o", &d("base.xlsx")]);
    assert_eq!(made.code, 0, "{}", made.stderr);
    let imported =
        common::cli::ncsheet(&["macros", &d("base.xlsx"), "--import", &d("nose.bas"), "-o", &d("book.xlsm")]);
    assert_eq!(imported.code, 0, "{}", imported.stderr);

    let first = common::cli::ncsheet(&["eval", &d("book.xlsm"), "C2", "--format", "csv"]);
    assert_eq!(first.code, 0, "{}", first.stderr);
    let value: f64 = first.stdout.trim().parse().unwrap_or_else(|_| panic!("{}", first.stdout));
    assert!((value - 0.8 * 2f64.sqrt()).abs() < 1e-12, "{value}");

    let edited = common::cli::ncsheet(&["set", &d("book.xlsm"), "B3=60", "-o", &d("edited.xlsm")]);
    assert_eq!(edited.code, 0, "{}", edited.stderr);
    let second = common::cli::ncsheet(&["eval", &d("edited.xlsm"), "C2", "--format", "csv"]);
    let value: f64 = second.stdout.trim().parse().unwrap_or_else(|_| panic!("{}", second.stdout));
    assert!((value - 1.6).abs() < 1e-12, "{value}");

    let xml = sheet_xml(&dir.path().join("edited.xlsm"));
    assert!(xml.contains("<f>NOSE_OFFSET(B2,B3)</f>"), "{xml}");
    let Some(soffice) = common::soffice() else { return };
    let profile = common::recalculating_profile(&dir.path().join("lo"));
    let out = dir.path().join("lo-out");
    common::libreoffice_convert_to(&soffice, &profile, &[dir.path().join("edited.xlsm")], &out, "xlsx");
    let theirs = sheet_xml(&out.join("edited.xlsx"));
    // LibreOffice writes the name in lower case (function names are case-blind in both).
    assert!(theirs.to_ascii_lowercase().contains(">nose_offset(b2,b3)</f>"), "LibreOffice lost the formula: {theirs}");
}

/// What engineering workbooks' functions do: call a helper of another module, read a range's
/// values as an array (`r.Value`, `UBound`), use a sheet function (`WorksheetFunction.Max`),
/// take an optional argument, and ask which cell called them (`Application.Caller`).
/// B1:B3 hold 2, 7, 4: their squares sum to 4 + 49 + 16 = 69; the largest is 7; the
/// default scale is 10, so Spread is 69 + 7·10 = 139, and 69 + 7·1 = 76 with scale 1.
#[test]
fn functions_call_other_modules_read_range_arrays_and_know_their_caller() {
    let helpers = "Attribute VB_Name = \"Helpers\"\r\nOption Explicit\r\n\
        Public Function Square(x As Double) As Double\r\n    Square = x * x\r\nEnd Function\r\n";
    let main = "Attribute VB_Name = \"Design\"\r\nOption Explicit\r\n\
        Public Function Spread(r As Range, Optional scale As Double = 10) As Double\r\n\
            Dim v As Variant, i As Long, total As Double\r\n\
            v = r.Value\r\n\
            For i = 1 To UBound(v, 1)\r\n\
                total = total + Square(v(i, 1))\r\n\
            Next i\r\n\
            Spread = total + WorksheetFunction.Max(r) * scale\r\n\
        End Function\r\n\
        Public Function WhereAmI() As String\r\n\
            WhereAmI = Application.Caller.Address\r\n\
        End Function\r\n";
    let wb = book(
        &[("Helpers", STANDARD, helpers), ("Design", STANDARD, main)],
        &[
            ("B1", "2"),
            ("B2", "7"),
            ("B3", "4"),
            ("C1", "=Spread(B1:B3)"),
            ("C2", "=Spread(B1:B3, 1)"),
            ("D4", "=WhereAmI()"),
            ("C3", "=Square(3)"),
        ],
    );
    assert_eq!(number(&wb, "C1"), 139.0);
    assert_eq!(number(&wb, "C2"), 76.0);
    assert_eq!(number(&wb, "C3"), 9.0);
    assert_eq!(wb.value(0, at("D4")), Value::text("$D$4"));
}

/// Endless recursion inside a function stops at the call-depth limit: #VALUE!, no crash
/// (on a test thread's small stack too).
#[test]
fn endless_recursion_in_a_function_is_a_value_error() {
    let wb = book(
        &[("Module1", STANDARD, "Function Deeper(n)\r\n    Deeper = Deeper(n + 1)\r\nEnd Function\r\n")],
        &[("A1", "=Deeper(1)")],
    );
    assert_eq!(wb.value(0, at("A1")), Value::Error(XlError::Value));
}

/// A Function with a line the interpreter cannot read (here a statement cut short) fails
/// when a cell calls it, as VBA compiles a procedure when it is first called: its cells are
/// `#VALUE!`, as a UDF that cannot run gives, with a note naming the cell, the module and the
/// place; the module's other Functions compute.
#[test]
fn a_function_that_does_not_parse_is_named_when_a_cell_calls_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let bas = "Attribute VB_Name = \"Broken\"\r\nFunction Bad()\r\n    Dim h\r\n    Set h = * Collection\r\n    Bad = 1\r\nEnd Function\r\n\
               Function Good()\r\n    Good = 2\r\nEnd Function\r\n";
    std::fs::write(d("broken.bas"), bas).unwrap();
    std::fs::write(d("b.csv"), "x,=Bad(),=Good()\n").unwrap();
    assert_eq!(common::cli::ncsheet(&["set", &d("b.csv"), "A2=1", "-o", &d("b.xlsx")]).code, 0);
    let made = common::cli::ncsheet(&["macros", &d("b.xlsx"), "--import", &d("broken.bas"), "-o", &d("b.xlsm")]);
    assert_eq!(made.code, 0, "{}", made.stderr);
    let run = common::cli::ncsheet(&["eval", &d("b.xlsm"), "B1:C1", "--format", "csv"]);
    assert_eq!(run.stdout.trim(), "#VALUE!,2");
    assert!(run.stderr.contains("Sheet1!B1: #VALUE!: Broken:4:13: syntax error"), "{}", run.stderr);
}

/// "Understanding parameter arrays": a Function with a ParamArray takes any number of
/// arguments from a cell too, the array zero-based; a reference argument stays a Range
/// there. Worked out by hand: "n" & (1 + 2 + 4 + 5) … = "n:0:2:12".
#[test]
fn a_cell_calls_a_function_with_a_param_array() {
    let source = "Function Tally(label As String, ParamArray parts())\r\n\
        Dim p, c, total\r\n\
        For Each p In parts\r\n\
            If IsObject(p) Then\r\n\
                For Each c In p\r\n\
                    total = total + c.Value\r\n\
                Next\r\n\
            Else\r\n\
                total = total + p\r\n\
            End If\r\n\
        Next\r\n\
        Tally = label & \":\" & LBound(parts) & \":\" & UBound(parts) & \":\" & total\r\n\
    End Function\r\n";
    let wb = book(
        &[("Module1", STANDARD, source)],
        &[("A1", "4"), ("A2", "5"), ("B1", "=Tally(\"n\", 1, 2, A1:A2)"), ("B2", "=Tally(\"e\")")],
    );
    assert_eq!(wb.value(0, at("B1")), Value::text("n:0:2:12"));
    assert_eq!(wb.value(0, at("B2")), Value::text("e:0:-1:"));
}

/// An array constant a cell gives a Function arrives as Excel hands it: a one-row `{7,8,9}` a
/// one-dimensional array from 1 (1 To 3), a column `{7;8;9}` a table from (1, 1), whatever the
/// module's Option Base (0 here). The oracle is real code written against Excel: EPEC's `Terp`
/// (S. J. Wilson, 1996) reads a row constant's first value as `xValues(1)` after `UBound(xValues)`
/// on a "1-D row array"; Range.Value's one-row arrays are from 1 as well. It arrived from 0.
#[test]
fn an_array_constant_reaches_a_function_from_one_whatever_the_option_base() {
    let source = "Option Base 0\r\n\
        Function Bounds(v)\r\n\
            Bounds = LBound(v) & \":\" & UBound(v) & \":\" & v(1)\r\n\
        End Function\r\n\
        Function Corner(v)\r\n\
            Corner = LBound(v, 1) & \":\" & LBound(v, 2) & \":\" & v(1, 1)\r\n\
        End Function\r\n";
    let wb = book(&[("Module1", STANDARD, source)], &[("B1", "=Bounds({7,8,9})"), ("B2", "=Corner({7;8;9})")]);
    assert_eq!(wb.value(0, at("B1")), Value::text("1:3:7"));
    assert_eq!(wb.value(0, at("B2")), Value::text("1:1:7"));
}

/// "Range.Text property" (Microsoft's Excel VBA reference): the text of the cell as it is
/// shown, so a function in a cell reading `.Text` of a cell the file formats `0.00` gets
/// "1.50" for 1.5, and "2.50" after an edit to 2.5. openpyxl writes the format, so the
/// look comes from outside our writer; the function's own cell is text.
#[test]
fn a_function_in_a_cell_reads_text_in_the_number_format_the_file_gives() {
    if !common::openpyxl::openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    std::fs::write(
        d("shown.bas"),
        "Public Function Shown(r As Range) As String\r\n    Shown = r.Text\r\nEnd Function\r\n",
    )
    .unwrap();
    common::openpyxl::python(
        "import sys, openpyxl\nwb = openpyxl.Workbook()\nws = wb.active\nws['A1'] = 1.5\n\
         ws['A1'].number_format = '0.00'\nws['B1'] = '=Shown(A1)'\nwb.save(sys.argv[1])\n",
        &[&dir.path().join("base.xlsx")],
    );
    let imported =
        common::cli::ncsheet(&["macros", &d("base.xlsx"), "--import", &d("shown.bas"), "-o", &d("book.xlsm")]);
    assert_eq!(imported.code, 0, "{}", imported.stderr);
    let shown = common::cli::ncsheet(&["eval", &d("book.xlsm"), "B1", "--format", "json"]);
    assert_eq!((shown.code, shown.stdout.trim()), (0, r#"{"Sheet!B1": "1.50"}"#), "{}", shown.stderr);
    let edited = common::cli::ncsheet(&["set", &d("book.xlsm"), "A1=2.5", "-o", &d("edited.xlsm")]);
    assert_eq!(edited.code, 0, "{}", edited.stderr);
    let shown = common::cli::ncsheet(&["eval", &d("edited.xlsm"), "B1", "--format", "json"]);
    assert_eq!((shown.code, shown.stdout.trim()), (0, r#"{"Sheet!B1": "2.50"}"#), "{}", shown.stderr);
}

/// "Range.Worksheet property" (Microsoft's Excel VBA reference): a Range lies on one
/// worksheet. The areas of a 3-D reference (`Sheet1:Sheet2!A1:A2`, one area a sheet) are no
/// Range, so a Function given them is not called: `#VALUE!`, and the note names the calling
/// cell and the argument. It was handed the first sheet's area alone: 1 + 2 = 3 where the
/// cells hold 1 + 2 + 10 + 20, a wrong value without a word.
#[test]
fn a_union_of_areas_on_two_sheets_is_refused_naming_the_cell() {
    const TOTAL: &str = "Function Total(r)\r\n    Dim c\r\n    For Each c In r\r\n        \
                         Total = Total + c.Value\r\n    Next\r\nEnd Function\r\n";
    let mut wb = two_sheets_of_numbers();
    wb.set_input(0, at("C1"), "=Total(Sheet1:Sheet2!A1:A2)").unwrap();
    wb.set_input(0, at("C2"), "=Total(Sheet1:Sheet2!A2)").unwrap();
    wb.set_input(0, at("C3"), "=Total((Sheet2!A1,Sheet2!A2))").unwrap();
    assert!(ncsheet::vba::install_functions(&mut wb, &common::vba::module1(TOTAL), RunOptions::default()).is_empty());
    for cell in ["C1", "C2"] {
        assert_eq!(wb.value(0, at(cell)), Value::Error(XlError::Value), "{cell}");
        let notes = wb.notes(0, at(cell)).join("\n");
        assert!(notes.contains(&format!("Sheet1!{cell}: Module1.Total was not called")), "{notes}");
        assert!(notes.contains("argument 1 is a union of areas on several sheets"), "{notes}");
    }
    assert_eq!(number(&wb, "C3"), 30.0, "one sheet's areas are one Range");
    // A macro's formula (`Evaluate`) calling the macro's own Function refuses it alike:
    // Error 2015 is #VALUE! ("How to: Return Excel Errors From User-Defined Functions").
    let src = format!("{TOTAL}Sub Main()\r\n    Debug.Print Evaluate(\"Total(Sheet1:Sheet2!A1)\")\r\nEnd Sub\r\n");
    let run = ncsheet::vba::run(&mut wb, &src, "main.bas", &RunOptions::default()).unwrap();
    assert_eq!(run.printed, ["Error 2015"]);
}

/// Sheet1 and Sheet2, each holding 1 and 2 (Sheet1) or 10 and 20 (Sheet2) in A1:A2.
fn two_sheets_of_numbers() -> Workbook {
    let mut wb = Workbook::with_sheet();
    let second = wb.add_sheet("Sheet2").unwrap();
    for (sheet, cell, text) in [(0, "A1", "1"), (0, "A2", "2"), (second, "A1", "10"), (second, "A2", "20")] {
        wb.set_input(sheet, at(cell), text).unwrap();
    }
    wb
}

/// A project of 300 standard modules, each with its own `Private Function Step` and a public
/// Function using it, one of them cut short. VBA compiles a project as one program ("Understanding
/// scope and visibility": a Private procedure is its module's own, a Public one everybody's),
/// and ncsheet parses it as one, once: each module was parsed with all the others' code after
/// it, and an .xlsm of 250 one-Function modules took 36 s to open, 2,000 did not finish.
/// Counted, not timed: the parser reads the project's source about once, not once a module.
/// Worked out by hand: F1(1) = 1 + 1, M300.F300(2) = 2 + 300, F150(F2(0)) = (0 + 2) + 150.
/// The module cut short is named when a cell calls its Function; the others still compute
/// (its error used to fail every module joined with it).
#[test]
fn a_project_of_many_modules_is_parsed_once_and_one_broken_module_leaves_the_others() {
    use ncsheet::vba::project::{build_project, NewModule};
    const MODULES: usize = 300;
    const BROKEN: usize = 7;
    let module = |i: usize| NewModule {
        name: format!("M{i}"),
        kind: STANDARD,
        source: if i == BROKEN {
            format!("Public Function F{i}(x)\r\n    F{i} = (x +\r\n")
        } else {
            format!(
                "Private Function Step()\r\n    Step = {i}\r\nEnd Function\r\n\
                 Public Function F{i}(x)\r\n    F{i} = x + Step()\r\nEnd Function\r\n"
            )
        },
    };
    let modules: Vec<NewModule> = (1..=MODULES).map(module).collect();
    let source_bytes: usize = modules.iter().map(|m| m.source.len()).sum();
    let mut wb = Workbook::with_sheet();
    let cells =
        [("A1", "=F1(1)"), ("A2", "=M300.F300(2)"), ("A3", "=F150(F2(0))"), ("A4", "=Step()"), ("A5", "=F7(1)")];
    for (cell, text) in cells {
        wb.set_input(0, at(cell), text).unwrap();
    }
    let layout = xlsx::Layout { vba_project: Some(build_project(&modules, 0x31).unwrap()), ..Default::default() };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("many.xlsm");
    let encoded = ncsheet::io::encode_save(&wb, Some(&layout), &ncsheet::io::Origin::New, &path).unwrap();
    encoded.write(Default::default()).unwrap();

    let before = ncsheet::vba::work_done();
    let doc = ncsheet::document::Document::open_file(&path, &ncsheet::document::OpenOptions::named(&path)).unwrap();
    // A run asks for the project three times more (its module, the others, the classes).
    for _ in 0..3 {
        assert_eq!(doc.vba_project().unwrap().unwrap().modules.len(), MODULES);
    }
    let work = ncsheet::vba::work_done() - before;
    let parsed = work.source_parsed;
    // The project is read from the file's bytes once, where a run read it five times.
    assert_eq!(work.projects_read, 1);
    // Each item of each parse finds its module by bisection, 9 steps among 300 modules (about
    // 2,400 lookups, 21,600 steps), where a scan from the last module went over 150 of them on
    // average (about 360,000).
    let steps = work.parts_searched;
    assert!(steps <= 9 * 10 * MODULES as u64, "{steps} steps to find modules");
    let wb = doc.workbook();
    assert_eq!(number(wb, "A1"), 2.0);
    assert_eq!(number(wb, "A2"), 302.0);
    assert_eq!(number(wb, "A3"), 152.0);
    assert_eq!(wb.value(0, at("A4")), Value::Error(XlError::Name), "a Private Function is no cell's");
    assert_eq!(wb.value(0, at("A5")), Value::Error(XlError::Name));
    assert!(doc.notes().iter().any(|n| n.starts_with("module M7: ") && n.contains("(F7 …)")), "{:?}", doc.notes());
    // The whole twice (the broken module made it parse again without it) and each module once
    // read alone to find the broken one: 3 times the source, where each module parsed with the
    // others read it 300 times.
    assert!(parsed <= 4 * source_bytes as u64, "{parsed} bytes parsed for a project of {source_bytes}");
}

/// A module of 2,000 `Public Const` lines and a module reading one of them from 200 cells:
/// each call ran all 2,000 declarations again (20,000 lines and 2,000 cells: 40 million
/// declarations, 49 s). The declarations now run once per recalculation, so a budget of
/// 20,000 statements holds the recalculation: 2,000 declarations, then each call's few
/// statements (each call running them all would stop at its tenth call, the rest `#VALUE!`).
/// Each call still starts from the module's state as declared ([MS-VBAL] 5.2.3.1.4: a
/// variable's initial value is its declared type's; ncsheet runs each cell's call as its own
/// program, so that no cell's value depends on the order the cells are computed in): `Mark`
/// changes a module variable and a module array's item, and the next call sees neither.
/// Worked out by hand: Plus(r) = r + 1999; Mark(i) = 1 * 100 + 7.
#[test]
fn module_level_declarations_run_once_per_recalculation_and_each_call_starts_from_them() {
    let mut consts: String = (0..2000).map(|i| format!("Public Const C{i} As Long = {i}\r\n")).collect();
    consts.push_str(
        "Dim seen(1 To 3) As Long\r\nDim calls As Long\r\n\
         Public Function Mark(i)\r\n    calls = calls + 1\r\n    seen(i) = seen(i) + C7\r\n\
         \x20   Mark = calls * 100 + seen(1) + seen(2) + seen(3)\r\nEnd Function\r\n",
    );
    let plus = "Public Function Plus(x)\r\n    Plus = x + C1999\r\nEnd Function\r\n";
    let mut cells: Vec<(String, String)> = (1..=200).map(|r| (format!("A{r}"), "=Plus(ROW())".to_string())).collect();
    cells.extend((1..=3).map(|i| (format!("B{i}"), format!("=Mark({i})"))));
    let mut wb = Workbook::with_sheet();
    let limits = &mut wb.settings_mut().functions;
    limits.statements_per_recalculation = 20_000;
    for (cell, text) in &cells {
        wb.set_input(0, at(cell), text).unwrap();
    }
    let module = |name: &str, source: &str| ProjectModule {
        name: name.into(),
        stream: name.into(),
        kind: STANDARD,
        source: source.into(),
    };
    let project = VbaProject {
        code_page: 1252,
        modules: vec![module("Consts", &consts), module("Module2", plus)],
        protection: None,
    };
    assert!(ncsheet::vba::install_functions(&mut wb, &project, RunOptions::default()).is_empty());
    for r in 1..=200 {
        assert_eq!(
            number(&wb, &format!("A{r}")),
            f64::from(r) + 1999.0,
            "A{r}: {:?}",
            wb.notes(0, at(&format!("A{r}")))
        );
    }
    for i in 1..=3 {
        assert_eq!(number(&wb, &format!("B{i}")), 107.0, "B{i}");
    }
    // An edit is a new recalculation, with its own budget and its own declarations.
    wb.set_input(0, at("C1"), "=Plus(0)").unwrap();
    assert_eq!(number(&wb, "C1"), 1999.0);
}

/// A call's first write into a module-level array copies the array (the next call starts
/// from it as declared), and that copy is counted as any copy on write, a statement per 16
/// items: 40 cells writing into an array of 160,000 items are 10,000 statements each, so a
/// recalculation's budget of 100,000 holds at most ten of them and refuses the rest by name, where
/// every call counted its three statements (2,000 cells over an array of a million items
/// copied 2 billion items). The cells computed are their argument (worked by hand).
#[test]
fn a_call_writing_into_a_module_array_is_charged_its_copy() {
    let source = "Dim big(1 To 160000) As Double\r\n\
                  Public Function Fill(x)\r\n    big(1) = x\r\n    Fill = big(1)\r\nEnd Function\r\n";
    let mut wb = Workbook::with_sheet();
    let limits = &mut wb.settings_mut().functions;
    limits.statements_per_recalculation = 100_000;
    for row in 1..=40 {
        wb.set_input(0, at(&format!("A{row}")), "=Fill(ROW())").unwrap();
    }
    assert!(ncsheet::vba::install_functions(&mut wb, &common::vba::module1(source), RunOptions::default()).is_empty());
    let computed: Vec<u32> =
        (1..=40).filter(|&r| wb.value(0, at(&format!("A{r}"))) == Value::Number(f64::from(r))).collect();
    assert!((5..=10).contains(&computed.len()), "{computed:?}");
    let notes: Vec<String> = (1..=40).flat_map(|row| wb.notes(0, at(&format!("A{row}")))).collect();
    let refused = notes.iter().filter(|n| n.contains("Module1.Fill was not called") && n.contains("100000")).count();
    // The call the budget ran out in stops at its statement: neither computed nor refused unrun.
    assert!(refused >= 40 - computed.len() - 1, "{notes:#?}");
}
