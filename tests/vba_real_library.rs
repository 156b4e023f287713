//! Names of VBA's and Excel's libraries that real public modules use (issue 31, session 21:
//! sorters, G-code writers, engineering functions), each in a small macro of our own with the
//! value Microsoft's VBA reference or [MS-VBAL] (the page or section named at each test) gives.

mod common;

use common::vba::{printed_after, run_main};
use ncsheet::workbook::Workbook;

// "VarType constants": vbDataObject 13, vbDecimal 14, vbUserDefinedType 36; a sorter's
// `Select Case VarType(x)` names them beside vbArray and vbObject.
#[test]
fn the_vartype_constants_a_select_case_names() {
    let body = "    Debug.Print vbDataObject; vbDecimal; vbUserDefinedType\n\
                \x20   Dim v: v = Array(1)\n\
                \x20   Select Case VarType(v)\n\
                \x20   Case vbArray, vbDataObject, vbObject, vbUserDefinedType: Debug.Print \"no\"\n\
                \x20   Case Is >= vbArray: Debug.Print \"array\"\n\
                \x20   End Select";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), [" 13  14  36 ", "array"]);
}

// "MsgBox function": the buttons vbOKCancel 1, vbAbortRetryIgnore 2, vbYesNoCancel 3,
// vbRetryCancel 5, vbDefaultButton2 256, vbDefaultButton3 512, vbDefaultButton4 768,
// vbSystemModal 4096, vbMsgBoxHelpButton 16384, vbMsgBoxSetForeground 65536, vbMsgBoxRight
// 524288, vbMsgBoxRtlReading 1048576; the answers vbAbort 3, vbRetry 4, vbIgnore 5.
#[test]
fn the_msgbox_constants() {
    let body = "    Debug.Print vbOKCancel; vbAbortRetryIgnore; vbYesNoCancel; vbRetryCancel\n\
                \x20   Debug.Print vbDefaultButton1; vbDefaultButton2; vbDefaultButton3; vbDefaultButton4\n\
                \x20   Debug.Print vbApplicationModal; vbSystemModal; vbMsgBoxHelpButton; vbMsgBoxSetForeground\n\
                \x20   Debug.Print vbMsgBoxRight; vbMsgBoxRtlReading; vbAbort; vbRetry; vbIgnore";
    assert_eq!(
        run_main(&mut Workbook::with_sheet(), body),
        [" 1  2  3  5 ", " 0  256  512  768 ", " 0  4096  16384  65536 ", " 524288  1048576  3  4  5 "]
    );
}

// "Color constants": vbBlack &H0, vbRed &HFF, vbGreen &HFF00, vbYellow &HFFFF, vbBlue
// &HFF0000, vbMagenta &HFF00FF, vbCyan &HFFFF00, vbWhite &HFFFFFF.
#[test]
fn the_color_constants() {
    let body = "    Debug.Print Hex(vbBlack); \" \"; Hex(vbRed); \" \"; Hex(vbGreen); \" \"; Hex(vbYellow)\n\
                \x20   Debug.Print Hex(vbBlue); \" \"; Hex(vbMagenta); \" \"; Hex(vbCyan); \" \"; Hex(vbWhite)";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), ["0 FF FF00 FFFF", "FF0000 FF00FF FFFF00 FFFFFF"]);
}

// "Miscellaneous constants" and [MS-VBAL] 6.1.2.2: vbNullChar Chr$(0), vbBack Chr$(8),
// vbVerticalTab Chr$(11), vbFormFeed Chr$(12).
#[test]
fn the_control_character_constants() {
    let body = "    Debug.Print Asc(vbNullChar); Asc(vbBack); Asc(vbVerticalTab); Asc(vbFormFeed); Len(vbNullChar)";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), [" 0  8  11  12  1 "]);
}

// [MS-VBAL] 5.6.10 "Simple Name Expressions": a name is looked up in the procedure, the
// module and the project before the referenced libraries, so a module's own `vbRed` hides
// VBA's color constant and a local `vbTab` hides VBA's tab.
#[test]
fn a_name_the_project_declares_hides_the_library_constant() {
    let module = "Private Const vbRed As Long = 7";
    let body = "    Dim vbTab As String\n    vbTab = \"x\"\n    Debug.Print vbRed; vbTab";
    assert_eq!(printed_after(module, body), [" 7 x"]);
}

// [MS-VBAL] 5.4.1 "Statement Blocks": a line-number label starts a line, whatever statement
// the line holds, so a module numbered line by line (as line-numbering tools write it for
// `Erl`) numbers the lines that close blocks too: `90 End If`, `70 Else`, `100 Next i`,
// `130 Loop`. A GoTo to such a number goes to the end of the block it closes (5.4.2.6:
// control passes to the statement at the label).
#[test]
fn line_numbers_before_the_keywords_that_close_blocks() {
    let module = "Function Evens() As String\n\
                  10    Dim i As Long, s As String\n\
                  20    For i = 1 To 6\n\
                  30      If i Mod 2 = 1 Then GoTo 50\n\
                  40      s = s & i\n\
                  50    Next i\n\
                  60    Evens = s\n\
                  End Function\n";
    let body = "10    Dim i As Long, s As String\n\
                20    For i = 1 To 3\n\
                30      If i = 2 Then\n\
                40        s = s & \"two \"\n\
                50      ElseIf i = 3 Then\n\
                60        s = s & \"three \"\n\
                70      Else\n\
                80        s = s & \"one \"\n\
                90      End If\n\
                100   Next i\n\
                110   Do While Len(s) < 20\n\
                120     s = s & \".\"\n\
                130   Loop\n\
                140   While Len(s) < 22\n\
                150     s = s & \"+\"\n\
                160   Wend\n\
                170   Select Case Len(s)\n\
                      Case 22\n\
                180       s = s & \"!\"\n\
                190   End Select\n\
                200   With Application\n\
                210     s = s & \"|\"\n\
                220   End With\n\
                230   Debug.Print s; \" \"; Evens()";
    assert_eq!(printed_after(module, body), ["one two three ......++!| 246"]);
}

// "MsgBox function": with nobody to press a button, a macro's MsgBox is answered with its
// default button, as Enter would answer it: vbYesNo's first (vbYes 6), vbYesNo +
// vbDefaultButton2's second (vbNo 7), vbYesNoCancel + vbDefaultButton3's third (vbCancel 2),
// vbOKCancel's and vbOKOnly's vbOK 1. Every MsgBox gave vbOK before, a value vbYesNo cannot
// return, so a macro's `If MsgBox("Continue?", vbYesNo) = vbYes Then` silently did nothing.
#[test]
fn msgbox_answers_with_its_default_button() {
    let body = "    Debug.Print CStr(MsgBox(\"a\", vbYesNo + vbQuestion) = vbYes) & MsgBox(\"b\", vbYesNo + vbDefaultButton2)\n\
                \x20   Debug.Print CStr(MsgBox(\"c\", vbYesNoCancel + vbDefaultButton3)) & MsgBox(\"d\", vbOKCancel) & MsgBox(\"e\")";
    assert_eq!(run_main(&mut Workbook::with_sheet(), body), ["True7", "211"]);
}
