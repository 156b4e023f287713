//! Constructs found by real public automation and G-code-writing modules (issue 31, sessions
//! 19's and 20's samples: inventory summaries, sheet sorters, de-duplicators, subtotals, report
//! and G-code writers), each in a small macro of our own with the result Microsoft's Excel VBA
//! reference or [MS-VBAL] gives (the page or section named at each test).

mod common;

use common::cli::ncsheet;
use common::sheet::{get_on as get, n, set_on as set};
use common::vba::printed_after as printed;
use common::vba::run_main as run;
use ncsheet::eval::Value;
use ncsheet::workbook::Workbook;

// "For Each...Next statement": the group is a collection; "Range.Rows property" (Excel):
// "Returns a Range object that represents the rows in the specified range", a collection of
// rows, each a Range as wide as the range; "Range.Columns property" likewise. So `For Each r In
// rng.Rows` visits each row once, `r.Row` its sheet row, `r.Cells.Count` its width.
#[test]
fn for_each_goes_through_the_rows_and_columns_of_a_range() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("B2", "1"), ("C2", "2"), ("B3", "10"), ("C3", "20"), ("B4", "100"), ("C4", "200")] {
        set(&mut wb, 0, cell, v);
    }
    let printed = run(
        &mut wb,
        "    Dim r As Range, c As Range, s As String\n\
         \x20   For Each r In Range(\"B2:C4\").Rows\n\
         \x20       s = s & r.Row & \":\" & r.Cells.Count & \":\" & WorksheetFunction.Sum(r) & \" \"\n\
         \x20   Next r\n\
         \x20   For Each c In Range(\"B2:C4\").Columns\n\
         \x20       s = s & c.Column & \"/\" & c.Rows.Count & \"/\" & c.Cells(3, 1).Value & \" \"\n\
         \x20       c.Cells(4, 1).Value = WorksheetFunction.Sum(c)\n\
         \x20   Next\n\
         \x20   Debug.Print s",
    );
    assert_eq!(printed, ["2:2:3 3:2:30 4:2:300 2/3/100 3/3/200 "]);
    assert_eq!((get(&wb, 0, "B5"), get(&wb, 0, "C5")), (n(111.0), n(222.0)));
}

// "Range.Rows property": the rows of a range of whole rows (`Rows("2:3")`) are whole rows,
// "$2:$2" as "Range.Address property" writes one.
#[test]
fn for_each_row_of_whole_rows_is_a_whole_row() {
    let mut wb = Workbook::with_sheet();
    let printed =
        run(&mut wb, "    Dim r\n    For Each r In Rows(\"2:3\").Rows\n        Debug.Print r.Address\n    Next");
    assert_eq!(printed, ["$2:$2", "$3:$3"]);
}

// "Range.HasFormula property" (Excel): "True if all cells in the range contain formulas; False
// if none of the cells in the range contains a formula; null otherwise." A find-and-replace
// module walks the used range asking `cl.HasFormula()` before it rewrites `cl.Formula`.
#[test]
fn has_formula_is_true_for_all_false_for_none_and_null_for_some() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "1"), ("A2", "=A1*2"), ("B1", "=A1"), ("B2", "=A2+1")] {
        set(&mut wb, 0, cell, v);
    }
    let printed = run(
        &mut wb,
        "    Debug.Print Range(\"A1\").HasFormula & \" \" & Range(\"A2\").HasFormula & \" \" & Cells(2, 1).HasFormula()\n\
         \x20   Debug.Print IsNull(Range(\"A1:A2\").HasFormula) & \" \" & Range(\"B1:B2\").HasFormula & \" \" & Range(\"C1:C9\").HasFormula\n\
         \x20   Debug.Print IsNull(Range(\"A1:B3\").HasFormula) & \" \" & IsNull(Columns(2).HasFormula) & \" \" & IsNull(Cells.HasFormula)",
    );
    assert_eq!(printed, ["False True True", "True True False", "True True True"]);
}

// [MS-VBAL] 5.3.1.11 (argument lists): an argument is left out only when its place is empty;
// `Nothing` and `Empty` written in its place are arguments. "Nothing" (Set statement): "the
// object variable no longer refers to any object"; "TypeName function": "Nothing" for an
// object variable that doesn't refer to an object, "Empty" for an uninitialized value;
// "IsObject function": True for a variable set to Nothing. A real laser G-code exporter calls
// `ExportCurveShape Nothing, …`; a real de-duplicating macro does `dict.Add key, Nothing`.
#[test]
fn nothing_and_empty_are_arguments_not_left_out() {
    let out = printed(
        "Sub Shape(s As Object, ByVal feed As Double)\n\
         \x20   Debug.Print TypeName(s); \"|\"; (s Is Nothing); \"|\"; feed\n\
         End Sub\n\
         Sub Value(v As Variant)\n\
         \x20   Debug.Print TypeName(v); \"|\"; IsEmpty(v)\n\
         End Sub",
        "    Shape Nothing, 1500\n\
         \x20   Value Empty\n\
         \x20   Dim d As Object: Set d = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   d.Add \"k\", Nothing\n\
         \x20   d.Add \"e\", Empty\n\
         \x20   Debug.Print d.Count; TypeName(d(\"k\")); \"|\"; IsObject(d(\"k\")); \"|\"; TypeName(d(\"e\"))",
    );
    assert_eq!(out, ["Nothing|True| 1500 ", "Empty|True", " 2 Nothing|True|Empty"]);
}

// "Range.Value property" (Excel): an empty cell's Value is Empty, so "TypeName function"
// answers "Empty" for it (an object member never set answers "Nothing"; a cell's value is no
// object). Real de-duplicating macros print TypeName of the cells they wrote.
#[test]
fn an_empty_cells_value_is_empty_not_nothing() {
    let out = printed(
        "",
        "    Debug.Print TypeName(Cells(6, 1).Value); \"|\"; TypeName(Sheets(1).Range(\"B2\").Value2); \"|\"; \
         IsEmpty(Cells(6, 1).Value)",
    );
    assert_eq!(out, ["Empty|Empty|True"]);
}

// Excel's sort order ("Sort data in a range or table", Microsoft Support: in an ascending
// sort numbers come first, smallest to largest, then text not telling case apart, then FALSE
// before TRUE, then errors; "Blank cells are always placed last", in a descending sort too);
// rows that tie keep their order; "Range.Sort method": Key1/Order1/Key2/Order2 and Header
// (xlYes: the first row stays). A moved formula's relative references follow its row, as a
// paste moves them. Real subtotal and BOM macros sort this way before they group rows.
#[test]
fn range_sort_orders_rows_as_excel_does() {
    let out = printed(
        "",
        "    Range(\"A1:C1\").Value = Array(\"Part\", \"Qty\", \"Twice\")\n\
         \x20   Range(\"A2\").Value = \"nut\": Range(\"B2\").Value = \"b\"\n\
         \x20   Range(\"A3\").Value = \"bolt\": Range(\"B3\").Value = 12\n\
         \x20   Range(\"A4\").Value = \"pin\": Range(\"B4\").Value = True\n\
         \x20   Range(\"A5\").Value = \"cap\"\n\
         \x20   Range(\"A6\").Value = \"rod\": Range(\"B6\").Value = 3\n\
         \x20   Range(\"A7\").Value = \"key\": Range(\"B7\").Value = \"A\"\n\
         \x20   Range(\"A8\").Value = \"gib\": Range(\"B8\").Value = 3\n\
         \x20   Range(\"C2:C8\").Formula = \"=A2&B2\"\n\
         \x20   Range(\"A1:C8\").Sort Key1:=Range(\"B1\"), Order1:=xlAscending, Key2:=Range(\"A1\"), _\n\
         \x20       Order2:=xlDescending, Header:=xlYes\n\
         \x20   Dim r As Long\n\
         \x20   For r = 1 To 8: Debug.Print Cells(r, 1).Value; \"|\"; Cells(r, 2).Value; \"|\"; Cells(r, 3).Formula; \"|\"; Cells(r, 3).Value: Next r\n\
         \x20   Range(\"A2:C8\").Sort Key1:=Range(\"B2\"), Order1:=xlDescending\n\
         \x20   For r = 2 To 8: Debug.Print Cells(r, 1).Value; : Next r\n\
         \x20   Debug.Print",
    );
    assert_eq!(
        out,
        [
            "Part|Qty|Twice|Twice",
            "rod| 3 |=A2&B2|rod3",
            "gib| 3 |=A3&B3|gib3",
            "bolt| 12 |=A4&B4|bolt12",
            "key|A|=A5&B5|keyA",
            "nut|b|=A6&B6|nutb",
            "pin|True|=A7&B7|pinTRUE",
            "cap||=A8&B8|cap",
            "pinnutkeyboltrodgibcap",
        ]
    );
}

// The macro recorder's sort ("Worksheet.Sort property", "SortFields.Add method", "Sort.SetRange
// method", "Sort.Apply method"): the fields are kept until cleared, Header xlYes keeps the
// first row of the range in place.
#[test]
fn worksheet_sort_object_applies_its_fields() {
    let out = printed(
        "",
        "    Range(\"A1:B1\").Value = Array(\"Name\", \"Hrs\")\n\
         \x20   Range(\"A2:A5\").Value = Application.Transpose(Array(\"b\", \"a\", \"c\", \"a\"))\n\
         \x20   Range(\"B2:B5\").Value = Application.Transpose(Array(1, 2, 3, 4))\n\
         \x20   ActiveSheet.Sort.SortFields.Clear\n\
         \x20   ActiveSheet.Sort.SortFields.Add Key:=Range(\"A2:A5\"), SortOn:=xlSortOnValues, Order:=xlAscending\n\
         \x20   ActiveSheet.Sort.SortFields.Add Key:=Range(\"B2:B5\"), Order:=xlDescending\n\
         \x20   With ActiveSheet.Sort\n\
         \x20       .SetRange Range(\"A1:B5\")\n\
         \x20       .Header = xlYes\n\
         \x20       .MatchCase = False\n\
         \x20       .Orientation = xlTopToBottom\n\
         \x20       .SortMethod = xlPinYin\n\
         \x20       .Apply\n\
         \x20   End With\n\
         \x20   Dim r As Long\n\
         \x20   For r = 1 To 5: Debug.Print Cells(r, 1).Value; Cells(r, 2).Value; : Next r\n\
         \x20   Debug.Print\n\
         \x20   Debug.Print ActiveSheet.Sort.SortFields.Count; TypeName(ActiveSheet.Sort)",
    );
    assert_eq!(out, ["NameHrsa 4 a 2 b 1 c 3 ", " 2 Sort"]);
}

// [MS-VBAL] 3.3.5 "Identifier Tokens": besides the Latin-identifier, an implementation may take
// a codepage-identifier, letters of the project's code page. Excel in Portuguese names a new
// module `Módulo1` (ó is 0xF3 in Windows-1252); a real de-duplicating module exported from it
// starts `Attribute VB_Name = "Módulo1"`, which was refused as "not a VBA module name". The
// project names it in its code page (PROJECT's Module= line, the dir stream's MODULENAME,
// [MS-OVBA] 2.3.1.7 and 2.3.4.2.3.2.1) and in UTF-16 (MODULENAMEUNICODE).
#[test]
fn a_module_named_in_its_code_pages_letters_imports_and_runs() {
    let dir = tempfile::tempdir().unwrap();
    let bas = dir.path().join("modulo.bas");
    std::fs::write(
        &bas,
        b"Attribute VB_Name = \"M\xF3dulo1\"\r\nSub Main()\r\n    Debug.Print \"ol\xE1\"; 1\r\nEnd Sub\r\n",
    )
    .unwrap();
    let book = dir.path().join("book.csv");
    std::fs::write(&book, "x\n").unwrap();
    let out = dir.path().join("out.xlsm");
    let path = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let done = ncsheet(&["macros", &path(&book), "--import", &path(&bas), "--code-page", "1252", "-o", &path(&out)]);
    assert_eq!(done.code, 0, "{}", done.stderr);
    let bytes = ncsheet::io::open(&out).unwrap().layout.unwrap().vba_project.unwrap();
    let project = ncsheet::vba::project::read_project(&bytes).unwrap();
    assert!(
        project.modules.iter().any(|m| m.name == "Módulo1"),
        "{:?}",
        project.modules.iter().map(|m| &m.name).collect::<Vec<_>>()
    );
    let ran = ncsheet(&["run", &path(&out), "--sub", "Módulo1.Main"]);
    assert!(ran.code == 0 && ran.stderr.lines().any(|l| l == "olá 1 "), "{}", ran.stderr);
}

// Excel's "Constants enumeration": xlNone -4142, xlAutomatic -4105; "XlCalculation
// enumeration": xlCalculationManual -4135, xlCalculationAutomatic -4105. A real subtotal
// macro sets `.Interior.ColorIndex = xlNone` and `Application.Calculation =
// xlCalculationManual` under Option Explicit, which refused them as undeclared variables.
#[test]
fn excel_constants_of_colors_and_calculation() {
    let out = printed("", "    Debug.Print xlNone; xlAutomatic; xlCalculationManual; xlCalculationAutomatic");
    // "Print # statement": a number is followed by a space, and a negative one has no space
    // before its sign.
    assert_eq!(out, ["-4142 -4105 -4135 -4105 "]);
}

// [MS-VBAL] 3.2.2 "Line-Continuation": " _" and a line break are whitespace between two tokens,
// and a named argument is a name, then the token `:=`, then its value (5.6.16.8 "Argument
// Lists"). The macro recorder breaks its long PasteSpecial lines right there: `SkipBlanks _` /
// `        :=False`; spaces around `:=` are whitespace between tokens too.
#[test]
fn a_line_may_be_continued_between_a_named_arguments_name_and_its_colon_equals() {
    let module =
        "Function Box(Optional L As Double = 1, Optional W As Double = 1, Optional H As Double = 1) As Double\n\
                  \x20   Box = L * W * H\n\
                  End Function";
    let out =
        printed(module, "    Debug.Print \"B=\" & Box(L:=2, H _\n        :=5)\n    Debug.Print \"B=\" & Box(W := 3)");
    assert_eq!(out, ["B=10", "B=3"]);
}

// "Worksheet.Unprotect method": on a sheet that is not protected it does nothing. "Worksheet.Protect
// method": UserInterfaceOnly:=True "protects the user interface, but not macros"; omitted,
// "protection applies both to macros and to the user interface", so a macro's write into the
// (locked) cells is then run-time error 1004, as is Unprotect with a wrong password (passwords
// are case-sensitive). "Worksheet.ProtectContents property" tells whether the cells are guarded.
#[test]
fn a_sheet_is_protected_and_unprotected_by_its_password() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    ActiveSheet.Unprotect\n\
         \x20   Range(\"A1\").Value = 1\n\
         \x20   ActiveSheet.Protect Password:=\"Pw\", UserInterfaceOnly:=True\n\
         \x20   Range(\"A2\").Value = 2\n\
         \x20   Debug.Print \"P=\" & ActiveSheet.ProtectContents\n\
         \x20   ActiveSheet.Unprotect \"Pw\"\n\
         \x20   ActiveSheet.Protect \"Pw\"\n\
         \x20   On Error Resume Next\n\
         \x20   Range(\"A3\").Value = 3\n\
         \x20   Debug.Print \"W=\" & Err.Number\n\
         \x20   Err.Clear\n\
         \x20   ActiveSheet.Unprotect \"pw\"\n\
         \x20   Debug.Print \"U=\" & Err.Number\n\
         \x20   Err.Clear\n\
         \x20   ActiveSheet.Unprotect \"Pw\"\n\
         \x20   Range(\"A4\").Value = 4\n\
         \x20   Debug.Print \"P=\" & ActiveSheet.ProtectContents & \" E=\" & Err.Number",
    );
    assert_eq!(out, ["P=True", "W=1004", "U=1004", "P=False E=0"]);
    assert_eq!([get(&wb, 0, "A1"), get(&wb, 0, "A2"), get(&wb, 0, "A4")], [n(1.0), n(2.0), n(4.0)]);
    assert_eq!(get(&wb, 0, "A3"), get(&wb, 0, "Z99"), "the protected cell stays empty");
}

// "Application.CutCopyMode property": False when Excel is in neither Cut nor Copy mode, xlCopy
// (1) in Copy mode; setting it to False ends the mode.
#[test]
fn cut_copy_mode_tells_whether_a_copy_waits_for_its_paste() {
    let out = printed(
        "",
        "    Debug.Print \"M=\" & Application.CutCopyMode\n\
         \x20   Range(\"A1\").Copy\n\
         \x20   Debug.Print \"M=\" & Application.CutCopyMode\n\
         \x20   Application.CutCopyMode = False\n\
         \x20   Debug.Print \"M=\" & Application.CutCopyMode",
    );
    assert_eq!(out, ["M=False", "M=1", "M=False"]);
}

// "Range.Replace method": in the range's cells the text What becomes Replacement, matching
// part of a cell (LookAt:=xlPart, the Find dialog's setting as a run starts) or the whole of it
// (xlWhole), case ignored unless MatchCase:=True (saved: A7's Replace names it False again); it
// returns True. Formulas are searched as written ("Find and replace"
// searches formulas), and a changed cell is entered anew, so "1,5" made "1.5" is a number.
// Excel's "Find or replace text and numbers on a worksheet": `?` any one character, `*` any
// number of characters, `~` before `?`, `*` or `~` the character itself.
#[test]
fn range_replace_changes_matching_cells_as_if_typed_anew() {
    let mut wb = Workbook::with_sheet();
    let inputs = [("A1", "1,5"), ("A2", "Total,Sum"), ("A3", "abc"), ("A4", "=\"ab\"&\"AB\""), ("A5", "a*b")];
    for (cell, v) in inputs.into_iter().chain([("A6", "x"), ("A7", "Done"), ("A8", "'007")]) {
        set(&mut wb, 0, cell, v);
    }
    let out = run(
        &mut wb,
        "    Debug.Print \"R=\" & Range(\"A1:A8\").Replace(What:=\",\", Replacement:=\".\")\n\
         \x20   Range(\"A3:A4\").Replace \"ab\", \"Q\", xlPart\n\
         \x20   Range(\"A2\").Replace What:=\"t*.\", Replacement:=\"\"\n\
         \x20   Range(\"A5\").Replace \"~*\", \"+\"\n\
         \x20   Range(\"A6\").Replace \"X\", \"y\", LookAt:=xlWhole, MatchCase:=True\n\
         \x20   Range(\"A7:A8\").Replace \"done\", \"ok\", LookAt:=xlWhole, MatchCase:=False\n\
         \x20   Debug.Print TypeName(Range(\"A1\").Value) & \" \" & Range(\"A4\").Formula",
    );
    assert_eq!(out, ["R=True", "Double =\"Q\"&\"Q\""]);
    let cells = ["A1", "A2", "A3", "A4", "A5", "A6", "A7", "A8"].map(|c| get(&wb, 0, c));
    let texts = ["Sum", "Qc", "QQ", "a+b", "x", "ok", "007"].map(Value::text);
    assert_eq!(cells[0], n(1.5));
    assert_eq!(cells[1..], texts);
}

// "Range.Replace method": "The settings for LookAt, SearchOrder, MatchCase, and MatchByte are
// saved each time you use this method. If you don't specify values for these arguments the next
// time you call the method, the saved values are used. Setting these arguments changes the
// settings in the Find dialog box"; "Range.Find method" says the same of LookIn, LookAt,
// SearchOrder and MatchByte, its MatchCase "The default value is False". So after a Replace
// with LookAt:=xlWhole, MatchCase:=True, a Replace naming neither replaces only whole cells of
// that case (A2 "AB", not A3 "abc" or A4 "xab") and a Find("ab") finds no whole "ab"; a Find
// with LookAt:=xlPart makes the next Replace match parts again, still of that case (no "AB" in
// A3:A4), until MatchCase:=False. Replace returns True, whether or not it replaced anything.
#[test]
fn range_replace_and_find_share_the_find_dialogs_saved_settings() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "ab"), ("A2", "AB"), ("A3", "abc"), ("A4", "xab")] {
        set(&mut wb, 0, cell, v);
    }
    let out = run(
        &mut wb,
        "    Range(\"A1:A4\").Replace \"ab\", \"1\", LookAt:=xlWhole, MatchCase:=True\n\
         \x20   Debug.Print Range(\"A1:A4\").Replace(\"AB\", \"2\")\n\
         \x20   Debug.Print Range(\"A1:A4\").Find(\"ab\") Is Nothing; Range(\"A1:A4\").Find(\"XAB\", LookAt:=xlPart).Address\n\
         \x20   Debug.Print Range(\"A3:A4\").Replace(\"AB\", \"-\"); Range(\"A3\").Value; Range(\"A4\").Value\n\
         \x20   Range(\"A3:A4\").Replace \"AB\", \"-\", MatchCase:=False",
    );
    assert_eq!(out, ["True", "True$A$4", "Trueabcxab"]);
    let cells = ["A1", "A2", "A3", "A4"].map(|c| get(&wb, 0, c));
    assert_eq!(cells, [n(1.0), n(2.0), Value::text("-c"), Value::text("x-")]);
}

// "Range.Replace method": ReplaceFormat "The replace format for the method", the format set in
// Application.ReplaceFormat, which ncsheet does not keep: refused by name, not ignored (the
// cells would keep their old format silently); a LookAt that is neither constant is refused.
#[test]
fn range_replace_by_format_or_with_a_bad_look_at_is_refused_by_name() {
    let mut wb = Workbook::with_sheet();
    let why = common::vba::main_fails(&mut wb, "    Range(\"A1\").Replace \"a\", \"b\", ReplaceFormat:=True");
    assert!(
        why.contains("Range.Replace ReplaceFormat:=True: ncsheet does not search or replace by cell format"),
        "{why}"
    );
    let why = common::vba::main_fails(&mut wb, "    Range(\"A1\").Replace \"a\", \"b\", LookAt:=xlValues");
    assert!(why.contains("Range.Replace LookAt:= is xlWhole or xlPart"), "{why}");
}

// "Range.CurrentRegion property": "a range bounded by any combination of blank rows and blank
// columns" (Ctrl+*: a cell touching the block at a corner belongs to it). "Range.SpecialCells
// method", xlCellTypeLastCell (11): "The last cell in the used range" (Ctrl+End); the other
// types are ranges of several areas, which ncsheet refuses by name.
#[test]
fn current_region_and_the_last_cell_of_the_used_range() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "h1"), ("B1", "h2"), ("A2", "1"), ("B2", "2"), ("C3", "3"), ("E5", "x"), ("G1", "=\"\"")] {
        set(&mut wb, 0, cell, v);
    }
    let out = run(
        &mut wb,
        "    Debug.Print Range(\"A1\").CurrentRegion.Address; \" \"; Range(\"B2\").CurrentRegion.Rows.Count\n\
         \x20   Debug.Print Range(\"E5\").CurrentRegion.Address; \" \"; Range(\"D8\").CurrentRegion.Address\n\
         \x20   Debug.Print Cells.SpecialCells(xlCellTypeLastCell).Address; \" \"; Range(\"A1:B2\").SpecialCells(11).Row",
    );
    assert_eq!(out, ["$A$1:$C$3  3 ", "$E$5 $D$8", "$G$5  5 "]);
}

// "Range.Style property" with Excel's built-in number styles, which include the number format
// alone: Percent is built-in format 9, "0%", and Comma format 43 (ECMA-376 Part 1, 18.8.30
// "numFmt", the built-in formats). A real stock summary sets `Cells(l, 11).Style = "Percent"`.
#[test]
fn a_built_in_number_style_sets_the_number_format() {
    let out = printed(
        "",
        "    Range(\"A1:A2\").Style = \"Percent\"\n\
         \x20   Range(\"B1\").Style = \"Comma\"\n\
         \x20   Range(\"A1\").Value = 0.25\n\
         \x20   Debug.Print Range(\"A2\").NumberFormat & \"|\" & Range(\"A1\").Text & \"|\" & Range(\"B1\").NumberFormat",
    );
    assert_eq!(out, ["0%|25%|_(* #,##0.00_);_(* \\(#,##0.00\\);_(* \"-\"??_);_(@_)"]);
}

// "Range.Find method": searching starts after the After cell (the range's first cell when
// omitted) and comes round, After itself last; SearchOrder xlByRows or xlByColumns,
// SearchDirection xlNext or xlPrevious; LookAt xlPart (default) or xlWhole; case is ignored
// unless MatchCase; "*" matches any filled cell; Nothing when no cell matches. The last-row
// idiom `Cells.Find("*", SearchOrder:=xlByRows, SearchDirection:=xlPrevious).Row`. "The
// settings for LookIn, LookAt, SearchOrder, and MatchByte are saved each time you use this
// method. If you don't specify values for these arguments the next time you call the method,
// the saved values are used": the last Find("2") searches values (D3 shows 2) as the one
// before it did, until LookIn:=xlFormulas is named again.
#[test]
fn range_find_searches_after_a_cell_in_either_order_and_direction() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in
        [("A1", "key"), ("A2", "AAA"), ("A3", "BBB"), ("A4", "AAA"), ("C2", "aaab"), ("B6", "x"), ("D3", "=1+1")]
    {
        set(&mut wb, 0, cell, v);
    }
    let out = run(
        &mut wb,
        "    Debug.Print Range(\"A:A\").Find(What:=\"AAA\", After:=Range(\"A1\")).Address\n\
         \x20   Debug.Print Range(\"A:A\").Find(\"aaa\", After:=Range(\"A1\"), SearchDirection:=xlPrevious).Address\n\
         \x20   Debug.Print Cells.Find(\"*\", SearchOrder:=xlByRows, SearchDirection:=xlPrevious).Row\n\
         \x20   Debug.Print Cells.Find(\"*\", SearchOrder:=xlByColumns, SearchDirection:=xlPrevious).Column\n\
         \x20   Debug.Print Range(\"A1:D4\").Find(\"aaa\", LookAt:=xlWhole, SearchOrder:=xlByColumns).Address\n\
         \x20   Debug.Print Range(\"A1:D4\").Find(\"AAAB\", MatchCase:=True) Is Nothing\n\
         \x20   Debug.Print Range(\"A1:D4\").Find(\"2\", LookIn:=xlValues).Address; Range(\"A1:D4\").Find(\"2\").Address\n\
         \x20   Debug.Print Range(\"A1:D4\").Find(\"2\", LookIn:=xlFormulas) Is Nothing; Range(\"A1:D4\").Find(\"2\") Is Nothing",
    );
    assert_eq!(out, ["$A$2", "$A$4", " 6 ", " 4 ", "$A$2", "True", "$D$3$D$3", "TrueTrue"]);
}

// "Range.FindNext method": "Continues a search that was begun with the Find method. Finds the
// next cell that matches those same conditions"; After omitted, "the search starts after the
// cell in the upper-left corner of the range"; "When the search reaches the end of the
// specified search range, it wraps around to the beginning of the range. To stop a search when
// this wraparound occurs, save the address of the first found cell" (its example's loop).
// FindPrevious goes the other way. The page's example changes every cell holding 2 to 5: "the
// values 1234 and 99299 both contain 2 and both cell values will become 5", and its loop ends
// when FindNext finds Nothing.
#[test]
fn find_next_goes_on_with_the_last_finds_conditions_and_comes_round() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "b"), ("A2", "a"), ("A3", "B"), ("A4", "c"), ("A5", "abc"), ("A6", "bb")] {
        set(&mut wb, 0, cell, v);
    }
    for (cell, v) in [("C1", "1"), ("C2", "2"), ("C3", "1234"), ("C4", "7"), ("C5", "99299"), ("C6", "3")] {
        set(&mut wb, 0, cell, v);
    }
    let out = run(
        &mut wb,
        "    Dim c As Range, first As String, found As String\n\
         \x20   With Range(\"A1:A6\")\n\
         \x20       Set c = .Find(\"b\", LookAt:=xlWhole)\n\
         \x20       first = c.Address\n\
         \x20       Do\n\
         \x20           found = found & c.Address & \" \"\n\
         \x20           Set c = .FindNext(c)\n\
         \x20       Loop While Not c Is Nothing And c.Address <> first\n\
         \x20       Debug.Print found; .FindPrevious(Range(\"A3\")).Address; .FindNext().Address\n\
         \x20   End With\n\
         \x20   With Range(\"C1:C6\")\n\
         \x20       Set c = .Find(2, LookIn:=xlValues, LookAt:=xlPart)\n\
         \x20       Do\n\
         \x20           c.Value = 5\n\
         \x20           Set c = .FindNext(c)\n\
         \x20       Loop While Not c Is Nothing\n\
         \x20   End With",
    );
    assert_eq!(out, ["$A$3 $A$1 $A$1$A$3"]);
    let column: Vec<Value> = (1..=6).map(|r| get(&wb, 0, &format!("C{r}"))).collect();
    assert_eq!(column, [n(1.0), n(5.0), n(5.0), n(7.0), n(5.0), n(3.0)]);
}

// "Range.Item property": "Returns a Range object that represents a range at an offset to the
// specified range"; Item is the Range's default member, so `ActiveCell(2, 1)` is the cell
// below the active cell and `Selection(1, 2)` the one right of the selection's first cell (a
// recorded find-all writes its list with `ActiveCell(j, 1) = found(j, 1)`), where the index was
// dropped and the active cell itself written.
#[test]
fn active_cell_and_selection_take_an_index_as_their_item() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Range(\"B2:C3\").Select\n\
         \x20   ActiveCell(2, 1) = \"below\"\n\
         \x20   Selection(1, 2) = \"right\"\n\
         \x20   Selection(4).Value = \"fourth\"\n\
         \x20   Debug.Print ActiveCell(2, 1).Address; Application.ActiveCell(1, 3).Address; ActiveCell.Address",
    );
    assert_eq!(out, ["$B$3$D$2$B$2"]);
    assert_eq!(get(&wb, 0, "B3"), Value::text("below"));
    assert_eq!(get(&wb, 0, "C2"), Value::text("right"));
    assert_eq!(get(&wb, 0, "C3"), Value::text("fourth"));
    assert_eq!(get(&wb, 0, "B2"), Value::Blank);
}

// A recorded copy of found rows (`Union` of the cells found, then `a.EntireRow.Copy
// Destination:=DestSheet.Range(firstAddress)` under On Error Resume Next): "Select works only on
// the active worksheet ... the Select method will fail unless your procedure activates the
// worksheet" ("Selecting and Activating Cells"), error 1004, the active sheet unchanged; whole
// rows of several areas copy as one block, one under another, pasted at the destination
// ("Range.Copy method"); areas in neither the same columns nor the same rows are Excel's "This
// action won't work on multiple selections", error 1004.
#[test]
fn rows_collected_with_union_copy_as_one_block() {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Data").unwrap();
    for (row, v) in [(1, "1"), (2, "5"), (3, "2"), (4, "22"), (5, "2")] {
        set(&mut wb, 1, &format!("A{row}"), v);
        set(&mut wb, 1, &format!("B{row}"), &format!("row{row}"));
    }
    let out = run(
        &mut wb,
        "    Dim u As Range\n\
         \x20   Set u = Union(Worksheets(\"Data\").Range(\"A3\"), Worksheets(\"Data\").Range(\"A5\"))\n\
         \x20   On Error Resume Next\n\
         \x20   u.EntireRow.Select\n\
         \x20   Debug.Print Err.Number; ActiveSheet.Name\n\
         \x20   Err.Clear\n\
         \x20   u.EntireRow.Copy Destination:=Worksheets(\"Sheet1\").Range(\"A2\")\n\
         \x20   Debug.Print Err.Number\n\
         \x20   Union(Range(\"A1\"), Range(\"C3\")).Copy Destination:=Range(\"E1\")\n\
         \x20   Debug.Print Err.Number",
    );
    assert_eq!(out, [" 1004 Sheet1", " 0 ", " 1004 "]);
    let copied: Vec<Value> = ["A2", "B2", "A3", "B3", "A4"].iter().map(|c| get(&wb, 0, c)).collect();
    assert_eq!(copied, [n(2.0), Value::text("row3"), n(2.0), Value::text("row5"), Value::Blank]);
}

// "Range.Clear method": "Clears the entire object" (values and formats); "Range.ClearFormats
// method": "Clears the formatting of the object" (values stay); "Range.ClearContents method"
// clears the values and keeps the formats.
#[test]
fn clear_takes_the_formats_too_and_clear_formats_only_them() {
    let out = printed(
        "",
        "    Range(\"A1:C1\").Value = 0.5\n\
         \x20   Range(\"A1:C1\").NumberFormat = \"0.00\"\n\
         \x20   Range(\"A1:C1\").Font.Bold = True\n\
         \x20   Range(\"A1\").Clear\n\
         \x20   Range(\"B1\").ClearFormats\n\
         \x20   Range(\"C1\").ClearContents\n\
         \x20   Debug.Print IsEmpty(Range(\"A1\")) & \"|\" & Range(\"A1\").NumberFormat & \"|\" & Range(\"A1\").Font.Bold\n\
         \x20   Debug.Print Range(\"B1\").Value & \"|\" & Range(\"B1\").NumberFormat & \"|\" & Range(\"B1\").Font.Bold\n\
         \x20   Debug.Print IsEmpty(Range(\"C1\")) & \"|\" & Range(\"C1\").NumberFormat & \"|\" & Range(\"C1\").Font.Bold",
    );
    assert_eq!(out, ["True|General|False", "0.5|General|False", "True|0.00|True"]);
}

// "Range.Rows property" / "Range.Columns property" (Excel): each "Returns a Range object that
// represents the rows (columns) in the specified range", the same cells, so its default
// member is their Value: `tgt.Rows = Application.Transpose(arr)` (a real FFT module's way to
// fill a column) writes the cells, `v = r.Rows` and `r.Rows.Value` read them, as `r.Value`
// would. A 1-D array assigned to a column fills each row with its first item (the array is a
// row, repeated down: "Range.Value property").
#[test]
fn rows_and_columns_of_a_range_take_and_give_its_values() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Dim v\n\
         \x20   Range(\"A1:A3\").Rows = Application.Transpose(Array(1, 2, 3))\n\
         \x20   v = Range(\"A1:A3\").Rows\n    Debug.Print v(2, 1)\n\
         \x20   v = Range(\"A1:A3\").Rows.Value\n    Debug.Print v(3, 1)\n\
         \x20   Range(\"C1:E1\").Columns = Array(7, 8, 9)\n\
         \x20   Range(\"C2:E2\").Columns.Value = Array(4, 5, 6)\n\
         \x20   Range(\"F1:F2\").Rows = Array(3, 4)",
    );
    assert_eq!(out, [" 2 ", " 3 "]);
    assert_eq!((get(&wb, 0, "A2"), get(&wb, 0, "D1"), get(&wb, 0, "E2")), (n(2.0), n(8.0), n(6.0)));
    assert_eq!((get(&wb, 0, "F1"), get(&wb, 0, "F2")), (n(3.0), n(3.0)));
}

// "Worksheet.Paste method" (Excel): "Pastes the contents of the Clipboard onto the sheet";
// Destination "specifies where the Clipboard contents should be pasted. If this argument is
// omitted, the current selection is used." A recorded report macro copies with
// `Selection.Copy`, selects the target cell and calls `ActiveSheet.Paste`: the copy lands
// there whole, a formula's relative references moved by the offset ("Range.Copy method":
// Copy then Paste is Excel's ordinary paste, formulas and constants). With nothing copied
// there is nothing to paste.
#[test]
fn worksheet_paste_pastes_the_copy_at_the_selection_or_destination() {
    let mut wb = Workbook::with_sheet();
    for (cell, v) in [("A1", "East"), ("B1", "10"), ("A2", "West"), ("B2", "=B1*2")] {
        set(&mut wb, 0, cell, v);
    }
    run(
        &mut wb,
        "    Range(\"A1:B2\").Select\n    Selection.Copy\n    Range(\"D5\").Select\n    ActiveSheet.Paste\n\
         \x20   ActiveSheet.Paste Destination:=Range(\"G1\")",
    );
    assert_eq!(
        (get(&wb, 0, "D5"), get(&wb, 0, "E5"), get(&wb, 0, "D6")),
        (Value::text("East"), n(10.0), Value::text("West"))
    );
    assert_eq!((get(&wb, 0, "E6"), get(&wb, 0, "H2")), (n(20.0), n(20.0)));
    let text = wb.input(0, ncsheet::formula::address::Pos::new(5, 4));
    assert_eq!(text.as_deref(), Some("=E5*2"));
    let why = common::vba::main_fails(&mut Workbook::with_sheet(), "    ActiveSheet.Paste");
    assert!(why.contains("nothing was copied"), "{why}");
}

// [MS-VBAL] 5.4.3.8 "Let Statement": when the variable's declared type is an object type, a
// Let (no Set) assigns the object's default member, "Range.Value" for a Range: `Dim r As
// Range: Set r = Range("G1"): r = 12` writes 12 into G1 and r still holds G1 (TypeName
// "Range"). A real FFT module zero-fills cells this way (`fillRange = arr`). A variable of a
// library's enum type (`As VbCompareMethod`, as a real QuickSort module declares one) still takes
// the value itself ("Compare Method Constants": vbTextCompare is 1).
#[test]
fn a_let_to_an_object_variable_assigns_its_default_member() {
    let mut wb = Workbook::with_sheet();
    let out = run(
        &mut wb,
        "    Dim r As Range, o As Object, arr(0 To 1) As Integer\n\
         \x20   Set r = Range(\"G1\")\n    r = 12\n    Debug.Print TypeName(r); r.Address\n\
         \x20   Set o = Range(\"H1:H2\")\n    arr(0) = 3: arr(1) = 4\n    o = arr\n    Debug.Print TypeName(o)",
    );
    assert_eq!(out, ["Range$G$1", "Range"]);
    assert_eq!((get(&wb, 0, "G1"), get(&wb, 0, "H1"), get(&wb, 0, "H2")), (n(12.0), n(3.0), n(3.0)));
    let out = run(&mut wb, "    Dim m As VbCompareMethod\n    m = vbTextCompare\n    Debug.Print m");
    assert_eq!(out, [" 1 "]);
}
