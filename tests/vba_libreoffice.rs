//! The macro language's constructs against LibreOffice Basic in VBA-compatibility mode
//! (`Option VBASupport 1`), run headless: each case is a Sub body that reports values with
//! `Out x`; ncsheet runs it with `Out` printing `CStr(x)`, LibreOffice with `Out` writing
//! `CStr(x)` to a file, and the two lists of lines must be equal.
//!
//! Cases stay inside what VBA and this language agree on (the module doc of `crates/ncsheet/src/vba` lists
//! where they differ on purpose: `-2^2`, text comparison, errors as values). A case's
//! module-level part (`Type`, helper procedures) goes first in both modules.
//!
//! Skips (with a message) when `soffice` is missing; fails under `CI=true` then.

mod common;

use std::path::Path;
use std::process::Command;

use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

struct Case {
    name: &'static str,
    /// Module-level declarations and helper procedures (names unique across cases).
    module: &'static str,
    body: &'static str,
}

const CASES: &[Case] = &[
    // tests/vba_data_types.rs: a Date keeps its type through a Variant parameter, ByVal and
    // ByRef, a Variant Function's result, a Variant array's item and a Collection's item
    // ([MS-VBAL] 2.1.1.1; TypeName "Date", VarType 7).
    Case {
        name: "date_keeps_its_type",
        module: r#"
Function IdD(x)
    IdD = x
End Function
Function ShowD(ByVal x)
    ShowD = TypeName(x) & VarType(x)
End Function
Sub AddOneD(ByRef x)
    x = x + 1
End Sub
"#,
        body: r#"
    Dim d As Date, v(2), c As New Collection, w
    d = #1/2/2024#
    Out ShowD(d)
    Out TypeName(IdD(d))
    Out VarType(IdD(d))
    v(0) = d
    v(1) = 5.5
    Out TypeName(v(0))
    Out VarType(v(0))
    Out TypeName(v(1))
    c.Add d
    c.Add 2.5
    Out TypeName(c(1))
    Out VarType(c.Item(1))
    Out TypeName(c(2))
    w = d
    AddOneD w
    Out TypeName(w)
    Out CDbl(w)
    Out VarType(d + 1)
"#,
    },
    // Arrays holding objects (tests/vba_language.rs has the class-module forms). Where
    // LibreOffice departs from VBA, left out: it does not make a `Dim c As New Collection`
    // again after `Set c = Nothing` (VBA's auto-instantiation, [MS-VBAL] 5.2.3.1.4), and its
    // `Const C As Integer = 2.5` is 2.5 (VBA converts a typed constant to its type: 2).
    Case {
        name: "object_semantics",
        module: "",
        body: r#"
    Dim a(2) As Object
    Set a(0) = New Collection
    a(0).Add "x"
    Set a(2) = a(0)
    a(2).Add "y"
    Out a(0).Count
    Out a(1) Is Nothing
    Out a(0) Is a(2)
"#,
    },
    Case {
        name: "like",
        module: "",
        body: r#"
    Out "abc" Like "a?c"
    Out "abc" Like "a*"
    Out "abc" Like "*c*"
    Out "ab" Like "a?c"
    Out "a1c" Like "a#c"
    Out "abc" Like "a#c"
    Out "F" Like "[A-F]"
    Out "G" Like "[A-F]"
    Out "G" Like "[!A-F]"
    Out "ABC" Like "abc"
    Out "a-b" Like "a[-x]b"
    Out "" Like "*"
    Out "x*y" Like "x[*]y"
    Out "N10 G01 X5" Like "N## G0# *"
    Out 123 Like "1*3"
    Dim part As String
    part = "P-2026"
    If part Like "P-####" Then Out "part number"
"#,
    },
    Case {
        name: "date_literals",
        module: "",
        body: r#"
    Out CDbl(#1/2/2026#)
    Out CDbl(#2026-01-02#)
    Out CDbl(#12/31/1999#)
    Out CDbl(#3/1/1900#)
    Out #1/2/2026# - #12/25/2025#
    Out #1/2/2026# > #12/25/2025#
"#,
    },
    Case {
        name: "on_error_resume_next",
        module: "",
        body: r#"
    Dim d As Double, x As Double
    On Error Resume Next
    x = 1 / d
    Out Err.Number
    Err.Clear
    Out Err.Number
    x = 5
    Out x
"#,
    },
    Case {
        name: "on_error_goto_in_a_function",
        module: r#"
Function SafeDiv(a, b)
    On Error GoTo Fail
    Dim r As Double
    r = a / b
    SafeDiv = r
    Exit Function
Fail:
    SafeDiv = -1
End Function
"#,
        body: r#"
    Out SafeDiv(6, 3)
    Out SafeDiv(1, 0)
    Out SafeDiv(4, 2)
"#,
    },
    Case {
        name: "resume_next_inside_a_loop",
        module: "",
        body: r#"
    Dim i As Integer, total As Double, v As Double
    On Error GoTo Skip
    For i = -2 To 2
        v = 10 / i
        total = total + v
    Next i
    Out total
    Exit Sub
Skip:
    Out "skip " & i & " err " & Err.Number
    Resume Next
"#,
    },
    Case {
        name: "resume_runs_the_statement_again",
        module: "",
        body: r#"
    Dim tries As Integer, d As Double, x As Double
    On Error GoTo TryAgain
    x = 12 / d
    Out "x=" & x & " tries=" & tries
    Exit Sub
TryAgain:
    tries = tries + 1
    d = 4
    Resume
"#,
    },
    Case {
        name: "err_raise_and_resume_label",
        module: "",
        body: r#"
    On Error GoTo H
    Err.Raise 1234, , "custom"
    Out "not here"
Done:
    Out "done " & Err.Number
    Exit Sub
H:
    Out Err.Number & " " & Err.Description
    Resume Done
"#,
    },
    Case {
        name: "an_error_in_a_callee_goes_to_the_caller",
        module: r#"
Sub RaiseInner()
    Err.Raise 5000, , "deep"
    Out "not here"
End Sub
"#,
        body: r#"
    On Error Resume Next
    RaiseInner
    Out "after " & Err.Number
"#,
    },
    Case {
        name: "gosub_and_return",
        module: "",
        body: r#"
    Dim n As Integer
    n = 2
    GoSub Twice
    GoSub Twice
    Out n
    Exit Sub
Twice:
    n = n * 2
    Return
"#,
    },
    Case {
        name: "type_fields_with_and_byref",
        module: r#"
Type Pt
    X As Double
    Y As Double
    Label As String
End Type
Type Seg
    A As Pt
    N As Integer
End Type
Sub Shift(p As Pt, ByVal dx As Double)
    p.X = p.X + dx
End Sub
"#,
        body: r#"
    Dim p As Pt, s As Seg
    p.X = 3: p.Y = 4
    p.Label = "A"
    Shift p, 1.5
    Out p.X & " " & p.Y & " " & p.Label
    With p
        .Y = .Y * 2
        Out (.Y + .X)
    End With
    Out p.Y
    s.A.X = 100
    s.N = 2.4
    Out s.A.X & " " & p.X & " " & s.N & " [" & s.A.Label & "]"
"#,
    },
    Case {
        name: "byref_byval_const_redim_preserve",
        module: r#"
Sub Bump(ByRef a, ByVal b)
    a = a + 1
    b = b + 1
End Sub
Sub BumpDefault(a)
    a = a * 10
End Sub
"#,
        body: r#"
    Dim x, y
    x = 1: y = 1
    Bump x, y
    Out x & " " & y
    BumpDefault x
    Out x
    Const Pi2 = 6.28
    Dim a() As Double
    ReDim a(1 To 3)
    a(1) = 1: a(2) = 2: a(3) = 3
    ReDim Preserve a(1 To 5)
    a(5) = Pi2
    Out UBound(a) & " " & a(2) & " " & a(4) & " " & a(5)
    ReDim a(1 To 2)
    Out a(1)
"#,
    },
    Case {
        // [MS-VBAL] 5.6.12: a member's dot touches what it follows, so `Out .Y + .X` calls
        // `Out` with the With object's `.Y + .X`, not a member `Y` of `Out`.
        name: "spaced_dot_starts_an_argument_inside_with",
        module: r#"
Type PtW
    X As Double
    Y As Double
End Type
Sub Out2(ByVal a, ByVal b)
    Out a & "|" & b
End Sub
"#,
        body: r#"
    Dim q As PtW
    q.X = 2: q.Y = 5
    With q
        Out .Y + .X
        Out .Y - .X
        Out .X * 3
        Out2 .X, .Y
        Out (.Y) * 2
    End With
"#,
    },
    Case {
        // A failing condition that Resume Next traps goes on with the next statement: for
        // If, ElseIf and Do While that is the first statement of the block, which runs; for
        // `Loop While` at the end it is the statement after the loop. (For bounds and a
        // Select Case subject are left out: LibreOffice hangs on them.)
        name: "resume_next_after_an_error_in_an_if_condition",
        module: "",
        body: r#"
    Dim d As Double, r As String, n As Integer
    On Error Resume Next
    r = "a"
    If 1 / d > 0 Then
        r = r & " then"
    Else
        r = r & " else"
    End If
    Out r & " " & Err.Number
    Err.Clear
    r = "b"
    If 1 / d < 0 Then r = r & " then" Else r = r & " else"
    r = r & " after"
    Out r & " " & Err.Number
    Err.Clear
    r = "c"
    If d > 1 Then
        r = r & " first"
    ElseIf 1 / d > 0 Then
        r = r & " second"
    Else
        r = r & " else"
    End If
    Out r & " " & Err.Number
    Err.Clear
    r = "e"
    Do While 1 / d > 0
        r = r & " body"
        Exit Do
    Loop
    Out r & " " & Err.Number
    Err.Clear
    r = "h"
    Do
        n = n + 1
        r = r & " " & n
        If n > 3 Then Exit Do
    Loop While 1 / d > 0
    Out r & " " & Err.Number
"#,
    },
    // tests/vba_library.rs: built-ins a shop's modules use, with the reference pages' results
    // (not Null given to them: LibreOffice stops at `Left(Null, 1)`, which VBA makes Null).
    Case {
        name: "library",
        module: "",
        body: r#"
    Out String(5, "*") & String(3, 42) & String(4, "ABC")
    Out Hex(255) & " " & Hex(459) & " " & Hex(-1) & " " & Oct(8) & " " & Oct(459)
    Out CDbl(DateSerial(1990 - 10, 8 - 2, 1 - 1))
    Out CDbl(DateSerial(2020, 13, 1))
    Out CDbl(TimeSerial(6, 0, 0))
    Out StrReverse("G01 X5")
    Out Replace("XXpXXPXXp", "p", "Y", 1, 1)
    Out Replace("XXpXXPXXp", "p", "Y", 3)
    Dim s As String
    s = "The dog jumps"
    Mid(s, 5, 3) = "fox"
    Out s
    Mid(s, 5) = "cow jumped over"
    Out s
"#,
    },
    // tests/vba_conformance.rs: a Variant holds a number with its type ([MS-VBAL] 3.3.2, a
    // literal's declared type; "Type conversion functions"). Left out where LibreOffice departs
    // from VBA: it computes `+ - *` on a Variant's Integers as Doubles (`x + 1`, `x * 200`) and
    // `\` and `Mod` on them as Longs, where VBA keeps an Integer ([MS-VBAL] 5.6.9.3, "Variant
    // data type": promoted only past the type's range).
    Case {
        name: "variant_numbers",
        module: "",
        body: r#"
    Dim a, b, c, x
    a = 5
    b = 40000
    c = 2.5
    Out TypeName(a)
    Out TypeName(b)
    Out TypeName(c)
    Out VarType(a)
    Out VarType(b)
    x = 200
    Out TypeName(x / 2)
    Out TypeName(x + 0.5)
    Out TypeName(CLng(x))
    Out TypeName(CInt(2.5))
    Out TypeName(CDbl(2))
    Out TypeName(CByte(7))
    Out TypeName(CCur(1.5))
    Out TypeName(CSng(1.5))
"#,
    },
    // tests/vba_data_types.rs: a Collection item keeps its number's type ("Variant data
    // type"); a Single is a 32-bit float; Currency sums are exact; a Boolean compares as -1 or
    // 0 and numbers compare exactly ([MS-VBAL] 5.6.9.5). Their texts are left out: LibreOffice
    // shows a Single to 9 digits (VBA 7, "0.3333333") and a Currency with 4 places ("0.0000").
    Case {
        name: "data_types_held_single_currency_comparison",
        module: "",
        body: r#"
    Dim c As New Collection, s As Single, cu As Currency, i As Integer, b As Boolean
    c.Add 5
    Out TypeName(c(1))
    Out VarType(c(1))
    s = 1 / 3
    Out CDbl(s)
    For i = 1 To 10
        cu = cu + 0.1
    Next
    Out CDbl(cu - 1)
    b = True
    Out b = -1
    Out True < False
    Out 0.1 + 0.2 = 0.3
"#,
    },
    // tests/vba_conformance.rs: DateAdd keeps month ends and adds each interval, DateDiff
    // counts the boundaries crossed ("w" whole weeks, "ww" first days of the week), DatePart
    // gives each part and the week of the year, WeekdayName and MonthName name them. Dates
    // are shown as their serials: LibreOffice's CStr of a Date follows its own locale. Left
    // out: DateDiff "h", "n" and "s" across a boundary less than a unit apart, which VBA counts
    // as 1 (a boundary crossed, as "yyyy" from Dec 31 to Jan 1) and LibreOffice as 0.
    Case {
        name: "date_add_diff_part_and_names",
        module: "",
        body: r#"
    Dim d
    d = DateSerial(2024, 1, 31) + TimeSerial(10, 30, 0)
    Out CDbl(DateAdd("m", 1, DateSerial(1995, 1, 31)))
    Out CDbl(DateAdd("m", 1, DateSerial(1996, 1, 31)))
    Out CDbl(DateAdd("yyyy", 1, DateSerial(2024, 2, 29)))
    Out CDbl(DateAdd("q", 1, d))
    Out CDbl(DateAdd("m", -2, d))
    Out CDbl(DateAdd("y", 1, d))
    Out CDbl(DateAdd("w", 1, DateSerial(2024, 2, 2)))
    Out CDbl(DateAdd("ww", -1, d))
    Out CDbl(DateAdd("h", 14, d))
    Out CDbl(DateAdd("n", -631, d))
    Out CDbl(DateAdd("s", 90, d))
    Out DateDiff("yyyy", DateSerial(2023, 12, 31), DateSerial(2024, 1, 1))
    Out DateDiff("w", DateSerial(2024, 1, 1), DateSerial(2024, 1, 15))
    Out DateDiff("w", DateSerial(2024, 1, 1), DateSerial(2024, 1, 14))
    Out DateDiff("ww", DateSerial(2024, 1, 7), DateSerial(2024, 1, 14))
    Out DateDiff("ww", DateSerial(2024, 1, 6), DateSerial(2024, 1, 7))
    Out DateDiff("ww", DateSerial(2024, 1, 6), DateSerial(2024, 1, 7), vbMonday)
    Out DateDiff("d", DateSerial(2024, 3, 1), DateSerial(2024, 2, 1))
    Out DateDiff("m", DateSerial(2024, 1, 31), DateSerial(2024, 2, 1))
    Out DateDiff("q", DateSerial(2024, 3, 31), DateSerial(2024, 4, 1))
    Out DateDiff("s", DateSerial(2024, 1, 2), DateSerial(2024, 1, 1))
    Out DatePart("y", DateSerial(2024, 8, 15))
    Out DatePart("q", DateSerial(2024, 8, 15))
    Out DatePart("w", DateSerial(2024, 8, 15), vbMonday)
    Out DatePart("n", DateSerial(2024, 8, 15) + TimeSerial(13, 45, 30))
    Out DatePart("ww", DateSerial(2022, 1, 2))
    Out DatePart("ww", DateSerial(2021, 1, 3), vbMonday, vbFirstFourDays)
    Out DatePart("ww", DateSerial(2021, 1, 4), vbMonday, vbFirstFourDays)
    Out DatePart("ww", DateSerial(2022, 1, 1), vbSunday, vbFirstFullWeek)
    Out Weekday(DateSerial(2024, 1, 1), vbSaturday)
    Out WeekdayName(1, True, vbMonday)
    Out WeekdayName(7, False, vbWednesday)
    Out MonthName(2)
    Out MonthName(12, True)
"#,
    },
    // tests/vba_semantics.rs: a String in hexadecimal or octal, or with a D exponent, is a
    // number to IsNumeric and the conversions (issue 31).
    Case {
        name: "number_text_as_vba_reads_it",
        module: "",
        body: r#"
    Out IsNumeric("&H10")
    Out IsNumeric("&O17")
    Out IsNumeric("1d2")
    Out IsNumeric(" 12 ")
    Out IsNumeric("1,000")
    Out CDbl("1d2")
    Out CLng("&H10")
"#,
    },
    // tests/vba_coercions.rs: arithmetic reads a String operand as CDbl does, and IIf gives
    // the chosen argument with its own type (issue 31).
    Case {
        name: "text_in_arithmetic_as_vba_reads_it",
        module: "",
        body: r#"
    Dim v
    v = "1d2"
    Out v + 0
    Out "&H10" * 1
    Out " 12 " + 0
    Out "1d2" - 1
    Out TypeName(IIf(True, 1, 2.5))
    Out TypeName(IIf(False, 1, 2.5))
"#,
    },
    // Str shows a fraction without its units' zero (" .1", "-.5"), which LibreOffice does in
    // VBA mode only, to match Excel's VBA; CStr, & and Print keep the zero (issue 31).
    Case {
        name: "str_drops_the_units_zero",
        module: "",
        body: r#"
    Out "[" & Str(0.1) & "]"
    Out "[" & Str(-0.5) & "]"
    Out "[" & Str(0.25 - 1) & "]"
    Out "[" & Str(0) & "]"
    Out "[" & Str(10.5) & "]"
    Out "[" & Str$(-0.75) & "]"
    Out "[" & CStr(0.1) & "]"
    Out "[" & 0.1 & "]"
"#,
    },
];

/// ncsheet's lines for one case.
fn ours(case: &Case) -> Vec<String> {
    let src = format!(
        "{}\nSub Out(ByVal v)\n    Debug.Print CStr(v)\nEnd Sub\n\nSub Main()\n{}\nEnd Sub\n",
        case.module, case.body
    );
    let mut wb = Workbook::with_sheet();
    let name = format!("{}.bas", case.name);
    match vba::run(&mut wb, &src, &name, &RunOptions::default()) {
        Ok(out) => out.printed,
        Err(e) => panic!("{e}"),
    }
}

/// LibreOffice's lines for every case, by case name (one soffice run for all of them).
fn theirs(soffice: &Path, dir: &Path) -> Vec<(String, Vec<String>)> {
    let profile = dir.join("profile");
    let out = dir.join("out.txt");
    let bin = std::fs::canonicalize(soffice).unwrap().with_file_name("soffice.bin");
    let profile_arg = format!("-env:UserInstallation=file://{}", profile.display());
    // The first start makes the profile, with its Standard library to put the module into.
    let status = soffice_run(&bin, &profile_arg, &["--terminate_after_init"]);
    assert!(status, "soffice did not make its profile in {}", profile.display());
    let mut module = String::from("Option VBASupport 1\n");
    for case in CASES {
        module.push_str(case.module);
        module.push('\n');
    }
    module.push_str("Sub Out(ByVal v)\n    Print #1, CStr(v)\nEnd Sub\n\n");
    for (i, case) in CASES.iter().enumerate() {
        module.push_str(&format!("Sub Case{i}()\n{}\nEnd Sub\n\n", case.body));
    }
    module.push_str(&format!("Sub Main\n    Open \"{}\" For Output As #1\n", out.display()));
    for (i, case) in CASES.iter().enumerate() {
        module.push_str(&format!("    Print #1, \"== {}\"\n    Case{i}\n", case.name));
    }
    module.push_str("    Close #1\n    StarDesktop.terminate\nEnd Sub\n");
    let xba = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE script:module PUBLIC \"-//OpenOffice.org//DTD \
         OfficeDocument 1.0//EN\" \"module.dtd\">\n<script:module xmlns:script=\"http://openoffice.org/2000/script\" \
         script:name=\"Module1\" script:language=\"StarBasic\">{}</script:module>",
        xml_escape(&module)
    );
    std::fs::write(profile.join("user/basic/Standard/Module1.xba"), xba).unwrap();
    let ran = soffice_run(&bin, &profile_arg, &["macro:///Standard.Module1.Main"]);
    let text = std::fs::read_to_string(&out).unwrap_or_default();
    assert!(
        ran && text.lines().last().is_some_and(|_| text.matches("== ").count() == CASES.len()),
        "LibreOffice did not run every case (a Basic error stops it at a dialog); it wrote:\n{text}\n\
         module:\n{module}"
    );
    let mut cases: Vec<(String, Vec<String>)> = Vec::new();
    for line in text.lines() {
        match line.strip_prefix("== ") {
            Some(name) => cases.push((name.to_string(), Vec::new())),
            None => cases.last_mut().expect("a case marker first").1.push(line.to_string()),
        }
    }
    cases
}

/// Runs soffice.bin itself (the `soffice` script would leave it behind when killed), for at
/// most two minutes: a Basic error waits at a dialog nobody sees.
fn soffice_run(bin: &Path, profile: &str, args: &[&str]) -> bool {
    Command::new("timeout")
        .args(["-s", "KILL", "120"])
        .arg(bin)
        .args(["--headless", "--norestore", profile])
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[test]
fn constructs_behave_as_libreoffice_vba_mode_runs_them() {
    let Some(soffice) = common::soffice() else {
        eprintln!("skipped: LibreOffice (soffice) is not installed; the macro oracle did not run");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let expected = theirs(&soffice, dir.path());
    let mut failures = Vec::new();
    for (case, (name, lines)) in CASES.iter().zip(&expected) {
        assert_eq!(case.name, name);
        assert!(!lines.is_empty(), "{name}: LibreOffice wrote nothing");
        let got = ours(case);
        if got != *lines {
            failures.push(format!("{name}:\n  ncsheet:     {got:?}\n  LibreOffice: {lines:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
