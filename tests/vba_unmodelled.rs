//! Members of Excel's object model that ncsheet does not model (issue 31: "where ncsheet
//! deliberately differs, it refuses with the reason instead of computing something else").
//!
//! In Excel, a member a macro uses has its effect; ncsheet without the member's code cannot
//! have it. A trappable error there (438, "Object doesn't support this property or method")
//! would let `On Error Resume Next` skip the member and the macro go on computing without its
//! effect, so such a member stops the run by name, whatever `On Error` says. The members that
//! only touch Excel's window or a look ncsheet does not keep run as no-ops; what the ones that
//! are read give is from Microsoft's Excel VBA reference, named at each test.

mod common;

use common::vba::{main_fails, run_main};
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

/// The error that stops `Sub Main()` with `body` (line 2 is the body's first line).
fn stop_of(body: &str) -> vba::MacroError {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    match vba::run(&mut Workbook::with_sheet(), &src, "main.bas", &RunOptions::default()) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}", out.printed),
        Err(e) => e,
    }
}

#[test]
fn on_error_resume_next_does_not_skip_a_member_ncsheet_does_not_model() {
    // Range.DataSeries fills A1:A5 with 1, 2, 3, 4, 5 in Excel ("Range.DataSeries method");
    // skipped, the sum below would be 1 where Excel gives 15.
    let e = stop_of(
        "    On Error Resume Next\n    Range(\"A1\").Value = 1\n    Range(\"A1:A5\").DataSeries\n    \
         Debug.Print Application.WorksheetFunction.Sum(Range(\"A1:A5\"))",
    );
    assert!(e.message.contains("Range.DataSeries is not modelled by ncsheet"), "{}", e.message);
    assert_eq!(e.span.map(|s| s.line), Some(4), "{e}");
    assert!(e.output.printed.is_empty(), "{:?}", e.output.printed);
}

#[test]
fn an_error_handler_does_not_catch_a_member_ncsheet_does_not_model() {
    // "Workbook.RefreshAll method" refreshes the workbook's queries and pivot tables, which
    // changes cells; a handler running instead would compute without it.
    let e = stop_of(
        "    On Error GoTo Handler\n    ThisWorkbook.RefreshAll\n    Exit Sub\nHandler:\n    \
         Debug.Print \"handled\"",
    );
    assert!(e.message.contains("Workbook.RefreshAll is not modelled by ncsheet"), "{}", e.message);
    assert_eq!(e.span.map(|s| s.line), Some(3), "{e}");
    assert!(e.output.printed.is_empty(), "{:?}", e.output.printed);
}

#[test]
fn a_font_name_is_refused_under_on_error_naming_what_is_kept() {
    // The fonts' names are not in ncsheet's cell styles (eval/format/cell_style.rs), so
    // neither the write nor the read can be kept or answered.
    for body in [
        "    On Error Resume Next\n    Range(\"A1\").Font.Name = \"Arial\"",
        "    On Error Resume Next\n    Debug.Print Range(\"A1\").Font.Name",
    ] {
        let m = main_fails(&mut Workbook::with_sheet(), body);
        assert!(m.contains("Font.Name is not modelled by ncsheet"), "{m}");
        assert!(m.contains("Bold, Italic, Color, ColorIndex, Size and Underline"), "{m}");
    }
}

#[test]
fn on_error_does_not_skip_an_argument_or_form_ncsheet_refuses() {
    // Each statement has an effect in Excel that ncsheet does not have: "Worksheet.Paste
    // method" with Link:=True pastes links to the copied cells; "Range.SpecialCells method"
    // with xlCellTypeConstants (2) gives the constant cells; "Sheets.Add method" with
    // Type:=xlChart (-4109) adds a chart sheet; "Range.TextToColumns method" with
    // DataType:=xlFixedWidth (2) splits at fixed widths. A trapped refusal would let the
    // macro go on without the effect (a merge macro under On Error Resume Next pasted nothing,
    // session 30's r08), so the run stops at the statement:
    // its line and the column of the refused member, whatever On Error says.
    // (the statement, the member the run stops at, a word of the refusal)
    let cases: [(&str, &str, &str); 6] = [
        ("Range(\"A1\").Copy\n    ActiveSheet.Paste Link:=True", "Paste", "Paste Link:=True"),
        ("Set r = Range(\"A1:B2\").SpecialCells(xlCellTypeConstants)", "SpecialCells", "SpecialCells"),
        ("Sheets.Add Type:=xlChart", "Add", "Sheets.Add"),
        ("Range(\"A1\").TextToColumns DataType:=xlFixedWidth", "TextToColumns", "xlFixedWidth"),
        // "Range.PasteSpecial method": Operation adds the copied values to the destination's,
        // Transpose:=True turns rows into columns.
        (
            "Range(\"A1\").Copy\n    Range(\"C1\").PasteSpecial Paste:=xlPasteValues, Operation:=xlPasteSpecialOperationAdd",
            "PasteSpecial",
            "Operation:=2",
        ),
        ("Range(\"A1\").Copy\n    Range(\"C1\").PasteSpecial Transpose:=True", "PasteSpecial", "Transpose"),
    ];
    for (statement, member, named) in cases {
        let last = statement.lines().last().unwrap_or_default();
        let line = 4 + statement.matches('\n').count() as u32;
        let col = 5 + last.trim_start().find(member).unwrap_or_default() as u32;
        for trap in ["On Error Resume Next", "On Error GoTo Handler"] {
            let e = stop_of(&format!(
                "    {trap}\n    Range(\"A1\").Value = 1\n    {statement}\n    Debug.Print \"went on\"\n    \
                 Exit Sub\nHandler:\n    Debug.Print \"handled\""
            ));
            assert!(e.message.contains(named), "{statement}: {}", e.message);
            assert_eq!(e.span.map(|s| (s.line, s.col)), Some((line, col)), "{statement}: {e}");
            assert!(e.output.printed.is_empty(), "{statement}: {:?}", e.output.printed);
        }
    }
    // The worksheet Sheets.Add makes, Type:=xlWorksheet (-4167, "XlSheetType enumeration"), runs.
    let printed =
        run_main(&mut Workbook::with_sheet(), "    Sheets.Add Type:=xlWorksheet\n    Debug.Print Sheets.Count");
    assert_eq!(printed, [" 2 "]);
}

/// The constants the macro recorder writes for the members ncsheet runs, each with the number
/// Microsoft's enumeration page gives: "Constants enumeration" (xlDoubleQuote 1, xlSingleQuote
/// 2, xlContext -5002, xlLTR -5003, xlRTL -5004), "XlPasteType" (xlPasteAllExceptBorders 7,
/// xlPasteColumnWidths 8, xlPasteComments -4144, xlPasteFormats -4122,
/// xlPasteFormulasAndNumberFormats 11, xlPasteValuesAndNumberFormats 12,
/// xlPasteAllUsingSourceTheme 13, xlPasteAllMergingConditionalFormats 14, xlPasteValidation
/// 6), "XlPasteSpecialOperation" (None -4142, Add 2, Subtract 3, Multiply 4, Divide 5),
/// "XlAutoFillType" (xlFillDefault 0 … xlFlashFill 11), "XlInsertFormatOrigin" (0, 1),
/// "XlPlatform" (xlMacintosh 1, xlWindows 2, xlMSDOS 3), "XlSortOn" (CellColor 1, FontColor 2,
/// Icon 3), "XlCellType" (AllFormatConditions -4172, SameFormatConditions -4173,
/// AllValidation -4174, SameValidation -4175), "XlFindLookIn" (xlCommentsThreaded -4184).
/// Without Option Explicit each was an empty variable, so `TextQualifier:=xlDoubleQuote` was
/// Empty, the paste's Operation:=xlNone went unread.
#[test]
fn the_constants_recorded_macros_write_have_excels_numbers() {
    let groups: [(&str, &str); 10] = [
        ("xlDoubleQuote; xlSingleQuote; xlContext; xlLTR; xlRTL", " 1  2 -5002 -5003 -5004 "),
        (
            "xlPasteAllExceptBorders; xlPasteColumnWidths; xlPasteComments; xlPasteFormats; \
             xlPasteFormulasAndNumberFormats; xlPasteValuesAndNumberFormats; xlPasteAllUsingSourceTheme; \
             xlPasteAllMergingConditionalFormats; xlPasteValidation",
            " 7  8 -4144 -4122  11  12  13  14  6 ",
        ),
        (
            "xlPasteSpecialOperationNone; xlPasteSpecialOperationAdd; xlPasteSpecialOperationSubtract; \
             xlPasteSpecialOperationMultiply; xlPasteSpecialOperationDivide",
            "-4142  2  3  4  5 ",
        ),
        (
            "xlFillDefault; xlFillCopy; xlFillSeries; xlFillFormats; xlFillValues; xlFillDays; xlFillWeekdays",
            " 0  1  2  3  4  5  6 ",
        ),
        ("xlFillMonths; xlFillYears; xlLinearTrend; xlGrowthTrend; xlFlashFill", " 7  8  9  10  11 "),
        ("xlFormatFromLeftOrAbove; xlFormatFromRightOrBelow", " 0  1 "),
        ("xlMacintosh; xlWindows; xlMSDOS", " 1  2  3 "),
        ("xlSortOnCellColor; xlSortOnFontColor; xlSortOnIcon", " 1  2  3 "),
        (
            "xlCellTypeAllFormatConditions; xlCellTypeSameFormatConditions; xlCellTypeAllValidation; \
             xlCellTypeSameValidation",
            "-4172 -4173 -4174 -4175 ",
        ),
        ("xlCommentsThreaded", "-4184 "),
    ];
    let body: String = groups.iter().map(|(names, _)| format!("    Debug.Print {names}\n")).collect();
    let printed = run_main(&mut Workbook::with_sheet(), &body);
    let expected: Vec<&str> = groups.iter().map(|(_, numbers)| *numbers).collect();
    assert_eq!(printed, expected);
    // A paste as the recorder writes it pastes: Operation:=xlNone and the False options.
    let mut wb = Workbook::with_sheet();
    let printed = run_main(
        &mut wb,
        "    Range(\"A1\").Value = 7\n    Range(\"A1\").Copy\n    Range(\"C1\").PasteSpecial Paste:=xlPasteValues, \
         Operation:=xlNone, SkipBlanks _\n        :=False, Transpose:=False\n    Debug.Print Range(\"C1\").Value",
    );
    assert_eq!(printed, [" 7 "]);
}

#[test]
fn the_window_and_looks_ncsheet_does_not_keep_are_no_ops() {
    // As the macro recorder writes them: none changes a value or a file ncsheet writes.
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Application.ScreenUpdating = False\n    Application.DisplayAlerts = False\n    \
         ActiveWindow.Zoom = 80\n    ActiveWindow.FreezePanes = True\n    \
         With Range(\"A1:B2\").Borders(xlEdgeBottom)\n        .LineStyle = xlContinuous\n        \
         .Weight = xlThin\n    End With\n    Range(\"A1:B2\").BorderAround xlContinuous, xlMedium\n    \
         Range(\"A1\").Interior.Pattern = xlSolid\n    \
         Range(\"A1\").Font.Strikethrough = True\n    ActiveSheet.Calculate\n    Range(\"A1\").Value = 7\n    \
         Debug.Print CStr(Range(\"A1\").Value)",
    );
    assert_eq!(printed, ["7"]);
}

#[test]
fn a_harmless_setting_reads_back_what_the_macro_set_else_excels_default() {
    // "Application.StatusBar property": False while Excel controls the status bar, else the
    // text set. "Application.Calculation property": xlCalculationAutomatic (-4105) by default,
    // xlCalculationManual is -4135. ScreenUpdating is True until set.
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Debug.Print CStr(Application.StatusBar) & \" \" & CStr(Application.Calculation) & \" \" & \
         CStr(Application.ScreenUpdating)\n    Application.StatusBar = \"Working\"\n    \
         Application.Calculation = xlCalculationManual\n    Application.ScreenUpdating = False\n    \
         Debug.Print Application.StatusBar & \" \" & CStr(Application.Calculation) & \" \" & \
         CStr(Application.ScreenUpdating)",
    );
    assert_eq!(printed, ["False -4105 True", "Working -4135 False"]);
}

#[test]
fn reading_a_look_ncsheet_does_not_keep_is_refused_under_on_error() {
    // Setting ActiveWindow.Zoom does nothing here, so there is no zoom to read back.
    let m = main_fails(
        &mut Workbook::with_sheet(),
        "    On Error Resume Next\n    Dim z\n    z = ActiveWindow.Zoom\n    Debug.Print z",
    );
    assert!(m.contains("ActiveWindow") && m.contains("no value to read"), "{m}");
}

#[test]
fn a_member_excels_sheets_collection_lacks_is_error_438_which_a_probe_traps() {
    // A macro that asks any container whether it holds a key tries `.Exists` under
    // On Error Resume Next. Excel's Sheets collection has no Exists ("Sheets Members
    // (Excel)"), so Excel raises "Object doesn't support this property or method (Error 438)",
    // which the handler traps; nothing of the workbook was skipped.
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim c As Object, found As Boolean\n    Set c = Worksheets\n    On Error Resume Next\n    \
         found = c.Exists(\"Sheet1\")\n    Debug.Print Err.Number & \" \" & found\n    On Error GoTo 0\n    \
         Debug.Print \"n=\" & c.Count",
    );
    assert_eq!(printed, ["438 False", "n=1"]);
    // A member Excel's collection has and ncsheet does not model still stops the run.
    let e = stop_of("    On Error Resume Next\n    Worksheets.FillAcrossSheets Range(\"A1\")\n    Debug.Print 1");
    assert!(e.message.contains("Worksheets.FillAcrossSheets is not modelled by ncsheet"), "{}", e.message);
}

#[test]
fn a_member_of_a_value_is_error_424_object_required() {
    // "Object required (Error 424)": `c.Exists` where c holds the number 5 (a Variant given a
    // value where a container was expected). Macros that probe what they were given trap it by
    // number (`ElseIf ErrX <> 424 And ErrX <> 438 Then`).
    let printed = run_main(
        &mut Workbook::with_sheet(),
        "    Dim c, b As Boolean\n    c = 5\n    On Error Resume Next\n    b = c.Exists(\"A\")\n    \
         Debug.Print \"e=\" & Err.Number",
    );
    assert_eq!(printed, ["e=424"]);
}
