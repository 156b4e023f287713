//! Issue 31, VBA's run-time errors as VBA raises and describes them: the messages of
//! Microsoft's "Trappable errors" table (Office VBA language reference) through `Error(n)`,
//! `Err.Raise n` and `Err.Description`; and a GoTo, On Error GoTo or Resume to a label inside
//! a block the failing statement is not in ("GoTo statement", "On Error statement": any line
//! label of the procedure).

use ncsheet::vba::{self, MacroError, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

fn run(src: &str) -> Result<RunOutput, MacroError> {
    vba::run(&mut Workbook::with_sheet(), src, "Module1.bas", &RunOptions::default())
}

/// What a Sub body prints with Debug.Print, line by line.
fn printed(body: &str) -> Vec<String> {
    run(&format!("Sub Main()\n{body}\nEnd Sub\n")).unwrap_or_else(|e| panic!("{e}")).printed
}

// "Trappable errors": each number's message, read back through the Error function ("Error
// function": "Returns the error message that corresponds to a given error number"), the `$`
// form alike. 5 and 449 are the messages of their own pages, "Invalid procedure call or
// argument (Error 5)" and "Argument not optional (Error 449)".
#[test]
fn error_gives_the_message_of_microsofts_table() {
    let cases = [
        (3, "Return without GoSub"),
        (5, "Invalid procedure call or argument"),
        (10, "This array is fixed or temporarily locked"),
        (14, "Out of string space"),
        (52, "Bad file name or number"),
        (61, "Disk full"),
        (62, "Input past end of file"),
        (76, "Path not found"),
        (92, "For loop not initialized"),
        (93, "Invalid pattern string"),
        (424, "Object required"),
        (449, "Argument not optional"),
        (450, "Wrong number of arguments or invalid property assignment"),
        (457, "This key is already associated with an element of this collection"),
        (746, "Replacements too long"),
    ];
    for (n, message) in cases {
        assert_eq!(printed(&format!("    Debug.Print Error({n})")), [message], "Error({n})");
        assert_eq!(printed(&format!("    Debug.Print Error$({n})")), [message], "Error$({n})");
    }
}

// "Error function": "If errornumber is a valid error number, but is not defined, Error returns
// the string "Application-defined or object-defined error."" (the page's own example loops
// over such numbers); "If … errornumber is 0, Error returns a zero-length string"; "If
// errornumber is not valid, an error occurs" (an error number is 0 to 65535, "Raise method").
#[test]
fn error_of_an_undefined_number_zero_and_a_number_that_is_none() {
    let out = printed("    Debug.Print Error(1); Error(1000); Error(65535)\n    Debug.Print \"[\" & Error(0) & \"]\"");
    let undefined = "Application-defined or object-defined error";
    assert_eq!(out, [format!("{undefined}{undefined}{undefined}"), "[]".into()]);
    let out = printed(
        "    On Error Resume Next\n    Dim s\n    s = Error(-1)\n    Debug.Print Err.Number\n\
                       \x20   Err.Clear\n    s = Error(65536)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 5 ", " 5 "]);
}

// "Raise method": "If Description isn't specified, … if the error code corresponds to a Visual
// Basic run-time error, the string associated with the error is used" — any number of the
// table, not only the ones the runtime raises itself.
#[test]
fn err_raise_without_a_description_takes_the_tables_message() {
    let out = printed(
        "    On Error Resume Next\n    Err.Raise 10\n    Debug.Print Err.Number; Err.Description\n\
         \x20   Err.Raise 62\n    Debug.Print Err.Number; Err.Description\n\
         \x20   Err.Raise 92\n    Debug.Print Err.Number; Err.Description\n\
         \x20   Err.Raise 450\n    Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(
        out,
        [
            " 10 This array is fixed or temporarily locked",
            " 62 Input past end of file",
            " 92 For loop not initialized",
            " 450 Wrong number of arguments or invalid property assignment",
        ]
    );
}

// `Err.Description` of an error the runtime raises is VBA's message for its number, nothing
// more ("Description property": "the error message associated with Number"): "Overflow" for
// an Integer given 40000 ("Integer data type": -32,768 to 32,767), and the Collection's
// "This key is already associated with an element of this collection" for a key added twice
// ("Add method (Visual Basic for Applications)", error 457).
#[test]
fn err_description_of_a_runtime_error_is_the_tables_message() {
    let out = printed(
        "    Dim i As Integer, c As New Collection\n    On Error Resume Next\n    i = 40000\n\
         \x20   Debug.Print Err.Number; Err.Description\n    Err.Clear\n\
         \x20   c.Add 1, \"k\"\n    c.Add 2, \"k\"\n    Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out, [" 6 Overflow", " 457 This key is already associated with an element of this collection"]);
}

// "Return without GoSub (Error 3)": a Return that no GoSub ran is error 3, which the caller's
// handler traps (the procedure has none) with that number and message.
#[test]
fn return_without_gosub_is_error_3() {
    let src = "Sub Inner()\n    Return\nEnd Sub\nSub Main()\n    On Error Resume Next\n    Inner\n\
               \x20   Debug.Print Err.Number; Err.Description\nEnd Sub\n";
    assert_eq!(run(src).unwrap_or_else(|e| panic!("{e}")).printed, [" 3 Return without GoSub"]);
}

// "On Error statement": `On Error GoTo line` "enables the error-handling routine that starts
// at line … The line argument is any line label or line number" of the procedure; "GoTo
// statement": "GoTo can branch only to lines within the procedure where it appears". So the
// handler may sit inside an If the failing statement is not in.
#[test]
fn an_error_handler_inside_an_if_the_error_is_outside_of() {
    let out = printed(
        "    Dim x\n    On Error GoTo Fail\n    x = 1 / 0\n    Debug.Print \"not here\"\n    If False Then\n\
         Fail:\n        Debug.Print \"handled\"; Err.Number\n    End If\n    Debug.Print \"after\"",
    );
    // A number prints with a space before and after it ("Print # statement").
    assert_eq!(out, ["handled 11 ", "after"]);
}

// A label is a place in the statements, not a statement: entering a Do loop's body at a
// label runs the rest of the body, then the loop goes on from its Loop line ("Do...Loop
// statement"), passing the label again on later rounds.
#[test]
fn a_handler_inside_a_loop_body_goes_on_with_the_loop() {
    let out = printed(
        "    Dim n, x\n    On Error GoTo H\n    x = 1 / 0\n    Do While n < 3\n        n = n + 1\n\
         \x20       Debug.Print \"loop\"; n\n        If n = 1 Then\nH:\n            Debug.Print \"at H\"\n\
         \x20       End If\n    Loop",
    );
    assert_eq!(out, ["at H", "loop 1 ", "at H", "loop 2 ", "loop 3 "]);
}

// "For loop not initialized (Error 92)": "You jumped into the middle of a For...Next loop":
// the GoTo is allowed, reaching Next is error 92, which On Error traps.
#[test]
fn a_goto_into_a_for_loop_is_error_92_at_its_next() {
    let out = printed(
        "    Dim i\n    On Error Resume Next\n    GoTo Inside\n    For i = 1 To 2\nInside:\n\
         \x20       Debug.Print \"in\"\n    Next\n    Debug.Print Err.Number; Err.Description",
    );
    assert_eq!(out, ["in", " 92 For loop not initialized"]);
}

// A GoTo into an If's Else arm and a `Resume label` into a Select Case's arm: each runs from
// the label to the end of its block, then after the statement.
#[test]
fn goto_and_resume_into_if_and_select_arms() {
    let out = printed(
        "    Dim k\n    GoTo Other\n    If True Then\n        Debug.Print \"then\"\n    Else\n\
         \x20       Debug.Print \"skipped\"\nOther:\n        Debug.Print \"else\"\n    End If\n\
         \x20   On Error GoTo H\n    Err.Raise 7\n    Exit Sub\nH:\n    Resume Arm\n\
         \x20   Select Case k\n    Case 1\nArm:\n        Debug.Print \"arm\"; Err.Number\n    End Select\n\
         \x20   Debug.Print \"end\"",
    );
    assert_eq!(out, ["else", "arm 0 ", "end"]);
}

// DatePart's known bug, kept as VBA has it: "Format or DatePart functions can return wrong
// week number for last Monday in Year" (Microsoft's troubleshooting article the DatePart page
// warns of): with vbMonday and vbFirstFourDays, 12/29/2003 is week 53, the days around it as
// ISO 8601 says (its Test1: Sun 52, Mon 53, Tue 1, Wed 1); its Test2 lists such Mondays from
// 1850 on, 12/31/1855 one of them, 12/30/1850 and 12/29/1856 not (week 1, as ISO 8601 says).
#[test]
fn datepart_gives_week_53_for_the_mondays_microsoft_lists() {
    let week = |date: &str| {
        printed(&format!("    Debug.Print DatePart(\"ww\", #{date}#, vbMonday, vbFirstFourDays)"))[0].clone()
    };
    let cases = [
        ("12/28/2003", " 52 "),
        ("12/29/2003", " 53 "),
        ("12/30/2003", " 1 "),
        ("12/31/2003", " 1 "),
        ("12/31/1855", " 53 "),
        ("12/30/1850", " 1 "),
        ("12/29/1856", " 1 "),
    ];
    for (date, want) in cases {
        assert_eq!(week(date), want, "{date}");
    }
}

// "Format function (Visual Basic for Applications)": Format(expression[, format[,
// firstdayofweek[, firstweekofyear]]]), its date symbols `w` ("the day of the week as a
// number (1 for Sunday through 7 for Saturday)") and `ww` ("the week of the year as a number
// (1 - 54)"); the troubleshooting article "Format or DatePart functions can return wrong week
// number for last Monday in Year" gives Format the same week 53 as DatePart for 12/29/2003
// with vbMonday and vbFirstFourDays. By hand: 2021-01-01 was a Friday, so with the defaults
// (Sunday weeks, week 1 holding January 1) Sunday 2021-01-03 starts week 2, and Monday
// 2021-01-04 is day 2 of its week.
#[test]
fn format_numbers_weeks_by_its_week_arguments() {
    let shown = |call: &str| printed(&format!("    Debug.Print {call}"))[0].clone();
    let cases = [
        ("Format(#12/28/2003#, \"ww\", vbMonday, vbFirstFourDays)", "52"),
        ("Format(#12/29/2003#, \"ww\", vbMonday, vbFirstFourDays)", "53"),
        ("Format(#12/30/2003#, \"ww\", vbMonday, vbFirstFourDays)", "1"),
        ("Format(#12/29/2003#, \"yyyy-ww\", vbMonday, vbFirstFourDays)", "2003-53"),
        ("Format(#1/2/2021#, \"ww\")", "1"),
        ("Format(#1/3/2021#, \"ww\")", "2"),
        ("Format(#1/4/2021#, \"w\")", "2"),
        ("Format(#1/3/2021#, \"w ww\")", "1 2"),
    ];
    for (call, want) in cases {
        assert_eq!(shown(call), want, "{call}");
    }
}

// "Error function": "If errornumber is omitted, the message corresponding to the most recent
// run-time error is returned. If no run-time error has occurred, or errornumber is 0, Error
// returns a zero-length string"; 11's message is "Division by zero" ("Trappable errors").
#[test]
fn error_without_a_number_is_the_current_errors_message() {
    let out = printed(
        "    Debug.Print \"[\" & Error & \"]\"\n    On Error Resume Next\n    x = 1 / 0\n    Debug.Print Error\n    Debug.Print Error$\n    Err.Clear\n    Debug.Print \"[\" & Error & \"]\"",
    );
    assert_eq!(out, ["[]", "Division by zero", "Division by zero", "[]"]);
}

// "Return without GoSub (Error 3)": "A Return statement does not have a corresponding GoSub
// statement" — a run-time error of the Return itself, so the procedure's On Error GoTo
// handler traps it as any other ("On Error statement"), with Err.Number 3 and the message of
// the "Trappable errors" table. (A real module, ListWorksheets, ends its loop with a stray
// Return under `On Error GoTo FAILED`: VBA shows its MsgBox "Failed".)
#[test]
fn a_return_without_gosub_is_error_3_that_on_error_traps() {
    let out = printed(
        "    On Error GoTo Failed\n    Debug.Print \"before\"\n    Return\n    Debug.Print \"after\"\n    Exit Sub\n\
         Failed:\n    Debug.Print Err.Number & \" \" & Err.Description",
    );
    assert_eq!(out, ["before", "3 Return without GoSub"]);
}

// UBound and LBound of a Variant that holds no array: VBA raises Type mismatch (run-time error
// 13, "Trappable errors": "Type mismatch"), as it does for indexing such a Variant; an array
// without bounds yet is "Subscript out of range" (9, "UBound function"). Error 5 ("Invalid
// procedure call or argument") is for an argument of the right type with a bad value.
#[test]
fn ubound_of_a_value_that_is_no_array_is_a_type_mismatch() {
    let body = "    Dim v, s, d()\n    v = 5: s = \"abc\"\n    On Error Resume Next\n\
                \x20   n = UBound(v): Debug.Print Err.Number: Err.Clear\n\
                \x20   n = LBound(s): Debug.Print Err.Number: Err.Clear\n\
                \x20   n = UBound(d): Debug.Print Err.Number";
    assert_eq!(printed(body), [" 13 ", " 13 ", " 9 "]);
}
