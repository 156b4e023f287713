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
