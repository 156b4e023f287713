//! The macro language: VBA's statements around the formula language's expressions, run
//! against a [`Workbook`] and filling an NC [`Program`].
//!
//! `parser.rs` turns the source into [`ast::Module`] through the one pest parser
//! (crates/ncsheet/grammar/formula.pest + crates/ncsheet/grammar/macro.pest); `interp.rs` walks the statements and hands
//! every expression to the one evaluator, which reads macro variables and macro-only nodes
//! (`Range("B3").Value`, calls of the module's Functions) through its `Host` hook;
//! `objects.rs` holds the objects (`Range`, `Cells`, `Worksheets`, `Application`, …), `nc.rs`
//! the `Nc` object.
//!
//! **Architecture Invariant:** a macro cannot reach files, programs or the system: the
//! language has no such statement or object (`Shell`, `CreateObject` of anything but
//! Scripting's Dictionary and FileSystemObject, `Declare`, `Workbooks.Open`, `SaveAs` … are
//! refused by the parser, by name); its file statements (`Open`, `Print #`, `Kill`, `Dir`,
//! FileSystemObject) reach only the files of [`RunOptions::files`], as a table in memory (`files.rs`), and are
//! refused by name without it; and this module touches neither files nor stdout: [`run`]
//! returns what the macro printed, emitted and wrote, and the CLI decides where it goes. A statement limit, a call-depth limit, a
//! deadline and limits on strings, arrays and output ([`RunOptions`]) stop endless loops,
//! recursion and floods with the line that was running.
//!
//! # The language, for a VBA user
//!
//! Statements: `Sub`/`Function` with `ByVal`/`ByRef` (the default), `Optional` parameters
//! with defaults and named arguments (`x:=1`), a last `ParamArray args()` taking the rest of
//! the arguments as one zero-based Variant array; a Function returns by assigning its name;
//! `Dim`/`Static`/`ReDim [Preserve]` with `As Integer|Long|Double|String|Boolean|Variant|Range…`
//! (typed variables convert as VBA does: an Integer rounds halves to even), arrays of one to
//! VBA's 60 dimensions (`Dim a(1 To 5)`, `Dim c(1 To 3, 1 To 4, 0 To 2)`, `UBound(c, 3)`,
//! `LBound`, `Array(…)`, `Option Base`; For Each goes first index fastest, as VBA lays arrays
//! out; a range is not given an array of three dimensions or more: error 13),
//! `Const`, `Set`, `If … Then … ElseIf … Else … End If` and the one-line `If`, `Select Case`
//! (values, `a To b`, `Is >= x`, `Case Else`), `For … To … Step … Next`, `For Each`
//! (cells of a range, items of an array, `Worksheets`), `Do [While|Until] … Loop
//! [While|Until]`, `While … Wend`, `With … End With`, `Exit For|Do|Sub|Function`, labels
//! (`N10:` or a line number) and `GoTo` to a label of the same block or one around it, `End`,
//! `'` and `Rem` comments, ` _` continuation, `:` between statements, `Option Explicit`,
//! `Attribute` lines of exported modules (ignored).
//!
//! Expressions are the formula language's (same precedence, functions and error values) plus
//! VBA's `Mod`, `\`, `Not`, `And`, `Or`, `Xor`, `Eqv`, `Imp` at VBA's levels. A name is, in
//! this order: a variable (the workbook's defined names are reached by `Range("D")` or `[D]`,
//! not bare), a constant (`vbCrLf`, `vbTab`, `Empty`, …), a procedure of the module, one of
//! VBA's functions (`Sqr Atn Tan Sin Cos Exp Log Abs Sgn Int Fix Round Format CStr CDbl CInt
//! CLng CBool Val Str Len Left Mid Right UCase LCase Trim LTrim RTrim InStr InStrRev Replace
//! Chr ChrW Asc Space IIf IsEmpty IsNull IsNumeric IsError IsObject IsArray IsMissing Array Split Join
//! StrComp StrConv LenB FormatNumber FormatPercent FormatCurrency FormatDateTime VarType CVErr Timer Rnd String Hex Oct StrReverse
//! DateSerial TimeSerial Date Time DateAdd DateDiff DatePart WeekdayName MonthName DateValue
//! TimeValue CLngLng CByte CSng CCur`, the `VBA.*` rows of the
//! function table, `$` suffix allowed), an object, or a sheet function (`CHAMFER_XA`, `SUM`,
//! `ATAN2`, …; also as `Application.WorksheetFunction.Sum` or `WorksheetFunction.Sum`).
//!
//! As VBA's reference has them: `Split` gives a zero-based array (none for `""`), `InStr`,
//! `InStrRev`, `StrComp` and `Split` take a compare argument (`vbTextCompare` ignores case;
//! left out or `vbUseCompareOption`, the module's Option Compare),
//! `StrConv` converts with `vbUpperCase`, `vbLowerCase`, `vbProperCase`, and `vbFromUnicode` /
//! `vbUnicode` to and from a Byte array in Windows-1252 (not the East Asian conversions),
//! `FormatNumber`, `FormatPercent` and `FormatCurrency` use English (United States) defaults (two
//! decimals, `1,234.50`, `25.60%`, `$1,234.50`), `VarType` answers a typed variable's declared type (`vbInteger` 2,
//! `vbLong` 3 …; 8192 + the items' type for an array), `IsMissing` is True for a left-out
//! `Optional` Variant without a default, `CVErr` takes Excel's `xlErr…` numbers (the values a
//! cell can hold), `Val` reads `&HFF` and `&O17`, `Format(x, ">")` / `"<"` changes case.
//! `Replace` takes its start, count and compare (the text from start is returned); the Mid
//! statement (`Mid(s, 5, 3) = "fox"`) replaces characters of a variable; `Application.Run
//! "Proc", args` runs a procedure of the project by its name.
//! `Timer` is the seconds since midnight of the document's clock, and `Rnd` is VBA's own
//! generator (KB 231847; its state is the workbook's settings', so a fresh document gives a
//! fresh Excel session's numbers, 0.7055475 first): `Randomize n` reseeds it (`Randomize`
//! alone from Timer), `Rnd(-n)` gives the same number for each n, `Rnd(0)` the last one. `Erase a` sets every
//! item of a fixed-size array back to its default and keeps the bounds; a dynamic array
//! (`Dim a()`, then ReDim) is freed and needs ReDim again (an array parameter is reset).
//! `Stop` stops the macro with "Stop statement at line N" (there is no
//! debugger to pause in; On Error does not trap it). An `Integer`, `Long` or `Byte`
//! variable refuses a value past its range with run-time error 6, Overflow; so does
//! arithmetic whose declared type is one of them ([MS-VBAL] 5.6.9.3): `+ - * \ Mod` on two
//! Integers (Integer literals `200 * 200` too) is Integer, with a Long it is Long, two Bytes
//! a Byte; a Variant operand widens instead, as VBA's Variants do.
//!
//! Operators are VBA's ([MS-VBAL] 5.6.9), not the formula language's:
//! - `-2^2` is -4 (a cell's `=-2^2` is 4); two Strings joined by `+` are joined.
//! - Texts compare by code units, case counting (`"a" = "A"` is False, `"B" < "a"`), unless
//!   the module says `Option Compare Text`; `Like` and Select Case follow the option. A
//!   String against a number of a numeric type is made a Double (`"10" = 10` is True; a text
//!   that is no number is error 13, Type mismatch), against a Variant holding a number the
//!   number's text is compared; two Variants, a text and a number: the number is less.
//!   Numbers still compare to 15 digits, as a cell does.
//! - An operation that fails raises VBA's run-time error, which On Error traps: `/`, `\` and
//!   `Mod` by zero 11, a text that is no number in arithmetic 13, a result past a Double 6.
//!   A worksheet function's error is still a value (`WorksheetFunction.…` as a cell gives it),
//!   as is `CVErr(xlErrDiv0)`, and a Variant holds it; arithmetic on an error value keeps it.
//!   A statement that needs a number, a truth value or an index (If, For, Cells, Nc.Line, a
//!   typed variable) stops there with the error and the function's explanation.
//! - `Round` is VBA's (halves to even); `WorksheetFunction.Round` is Excel's.
//!
//! Sheet access: `Range("B3")`, `Range("A1:C4")`, `Range("Sheet2!B3")`, `Range("XA")` (a
//! defined name), `Range(Cells(1, 1), Cells(2, 3))`, `Cells(r, c)` (c may be letters),
//! `Worksheets("Name")` / `Worksheets(1)` / `Sheets` / `ActiveSheet`, `[B3]` and `[SUM(A1:A3)]`
//! (formula text evaluated as in a cell), `Evaluate("…")`. Range members: `Value` (the
//! default), `Value2`, `Formula`, `HasFormula` (True, False or Null), `Text`, `Row`,
//! `Column`, `Count`, `Rows`, `Columns`,
//! `Address`, `Offset`, `Resize`, `Cells`, `Item`, `ClearContents`, `Worksheet`, `Activate`,
//! `Select`, `FormulaR1C1` (read and written in R1C1 notation: `=R[-1]C*2`), `End(xlUp)`
//! (and `xlDown`, `xlToLeft`, `xlToRight`: Ctrl+arrow), `Copy` (with a destination: pasted at
//! once; without: for `PasteSpecial Paste:=xlPasteValues`, `xlPasteFormulas`, `xlPasteAll`);
//! `Delete` and `Insert` (with `Shift:=xlShiftUp`/`xlShiftToLeft`, `xlShiftDown`/`xlShiftToRight`,
//! or by the range's shape without it; whole rows and columns through `EntireRow`,
//! `EntireColumn`, `Rows(5)`, `Columns("B")`), every formula's references following the cells;
//! bare `Rows`/`Columns` are the sheet's. How cells look (`formats.rs`): `NumberFormat`
//! (which `Text` shows), `HorizontalAlignment`/`VerticalAlignment` (`xlLeft`, `xlCenter` …),
//! `WrapText`, `Font.Bold`/`Italic`, `Interior.Color`, `ColumnWidth`, `RowHeight` and
//! `Columns.AutoFit`/`Rows.AutoFit`, from the file's look ([`RunOptions::looks`]) to the
//! saved one ([`RunOutput::looks`]). A sheet's `Visible` (True, False,
//! `xlSheetVeryHidden`) is read from and saved to the file. Sheets: `Sheets.Add` (`Before:=`,
//! `After:=`, `Count:=`), `ws.Name =`, `ws.Copy`/`ws.Move` with `Before:=` or `After:=`, and
//! `ws.Delete` (`Worksheets("Merged").Delete`, `Sheets(i).Delete`, `ActiveSheet.Delete`; no
//! dialog asks, as with `DisplayAlerts = False`): references to the sheet become `#REF!`, the
//! names scoped to it go, a 3-D reference (`Sheet1:Sheet3!A1`) leaves it out (an end moving
//! one tab inward), the sheet to its right (else left) becomes active; the last visible
//! sheet is error 1004, and a Worksheet or Range variable of a deleted sheet is error 424 ("Object required"). `ActiveCell` and
//! `Selection` start at the sheet's active cell as the file saved it ([`RunOptions::active_cells`])
//! and follow `Select`/`Activate`, and move with their cells on `Insert`/`Delete`. `Intersect(r1, r2, …)` (Nothing when they share no cell)
//! and `Union(r1, r2, …)`, also as `Application.` members, and `Range("C5:D9,G9:H16")`, give
//! a Range of several areas: `Areas`, `Count`, `Address`, `For Each`, `Value =`,
//! `ClearContents`, `EntireRow.Delete` take every area, `Value`, `Rows`, `Columns` the first
//! (`areas.rs`); `Range.RemoveDuplicates` removes repeated rows inside the range; `Parent` (a Range's Worksheet, a Worksheet's Workbook) and
//! `Application` of every Excel object. In a sheet's module ([`Document::Sheet`]) `Range`, `Cells`
//! and `[B3]` mean that sheet and `Me` is it; sheets' code names (`Sheet1`) are objects.
//! A write is typed into the cell (text starting with `=` is a formula, as in VBA) and
//! recalculates what depends on it before the next statement.
//!
//! Output: `Debug.Print` lines (VBA's `;` and `,` and number spacing) and `MsgBox` texts go
//! to [`RunOptions::sink`] as they happen (the CLI writes them to standard error), or
//! without one to [`RunOutput::printed`] and [`RunOutput::messages`]; `Nc.*` builds [`RunOutput::program`] (see
//! `objects.rs` for `Nc.Rapid`, `Nc.Line`, `Nc.ArcCW`, `Nc.Block`, … and `Nc.Feed`). The
//! machine's state is part of the program: `Nc.FeedPerRev 0.1` / `Nc.FeedPerMin 200` (what F
//! means; a lathe program is refused without it), `Nc.Spindle 800` (M3, `"ccw"` for M4, 0 to
//! stop; `Vc:=180, Limit:=2500` for constant surface speed), `Nc.Tool 1` (`Offset:=2`: another
//! offset register, 0: none), `Nc.Coolant True`. A cycle may carry its NC31 subprogram:
//! `Nc.Subprogram "L16 XR1 WR2 …", "N1 …", …, "N16 M17"`, and `Nc.Cycle "L16", x, w, …` …
//! `Nc.EndCycle` around the blocks one use emits (`ncsheet run --subprograms` writes that use
//! as the call `L16 X… W…`; `nc.rs` says more).
//! `InputBox` is refused: pass values with `--arg`.
//!
//! Files, with `ncsheet run --out-dir DIR` (and `--in-file PATH` to read): `Open name For
//! Output|Append|Input As #n`, `Print #n, …` (`;`, `,`, `Spc(n)`, `Tab(n)` as in VBA),
//! `Write #n, …`, `Line Input #n, s`, `Input #n, a, b`, `Close [#n]`, `FreeFile`, `EOF(n)`,
//! `LOF(n)`, `Dir(pattern)` and `Dir`, `Kill pattern` (`*` and `?` as wildcards), `FileLen(name)`,
//! `FileCopy source, destination` (`MkDir`, `RmDir` are refused: the folder has no folders
//! of its own), and `CreateObject("Scripting.FileSystemObject")` with `CreateTextFile`,
//! `OpenTextFile` (`ForReading` 1, `ForWriting` 2, `ForAppending` 8), `FileExists` and the
//! TextStream's `WriteLine`, `Write`, `WriteBlankLines`, `ReadLine`, `ReadAll`, `SkipLine`,
//! `AtEndOfStream`, `Close`. A name is a plain file name in DIR (`program.nc`) or a listed
//! input's file name (`ThisWorkbook.Path` is DIR, so `ThisWorkbook.Path & "\prog.nc"` and
//! `Application.PathSeparator` name a file there); any other path (a folder part, `..`,
//! absolute, a drive, UNC, a device name, `a.txt:stream`) stops the macro, and no `On Error`
//! traps that. What the macro writes
//! is held until it ends and written only if it ran to its end ([`RunOutput::files`]). VBA's
//! file errors are trappable: 52, 53 (not found), 54, 55 (already open), 58, 62 (past the end).
//!
//! Errors: `On Error GoTo label` (the label in the procedure's body, outside loops and Ifs),
//! `On Error Resume Next`, `On Error GoTo 0` / `-1`, `Resume`, `Resume Next`, `Resume label`,
//! and `Err` (`Number`, `Description`, `Clear`, `Raise n, , text`). `Resume Next` after a
//! failing If, ElseIf or `Do While` condition goes on with the block's first statement (VBA's
//! "next statement"; LibreOffice's VBA mode agrees), after a failing `Loop While` past the
//! loop; a failing For bound or Select Case subject skips the statement. A failing operator raises its
//! error where it is (`1/0`: 11); a function's error value fails the statement that needs a
//! number from it (a typed variable, `For`, `Cells`), with VBA's number (11 for a division by
//! zero, 13 for a type mismatch, 6 for an overflow, else 5). The
//! statement, time and depth limits are not errors a macro can trap. `GoSub label` / `Return`.
//! `text Like pattern` (`?`, `*`, `#`, `[a-z]`, `[!…]`; case counts but under Option Compare
//! Text). Date literals `#1/2/2026#`, `#2026-01-02 18:30#`, `#6:00 PM#` are the Date's
//! serial number (days since 1899-12-30, the time as a fraction).
//!
//! `Type … End Type` (fields of plain types or earlier Types; a Type value is copied on
//! assignment, passed ByRef, reached with `With`, returned by a Function `As` the Type and
//! assigned to a variable of it: `p = MakePoint(1, 2)`). Arrays of a Type: `Dim pts(1 To 10)
//! As TPoint`, `Dim pts() As TPoint` with `ReDim [Preserve]`, `pts(i).x = 1`, `pts(i) = q` or
//! `= MakePoint(…)` (a copy), `q = pts(i)` (a copy), `pts(i)` passed ByRef (changes come back),
//! the whole array to `a() As TPoint`, `With pts(i)`, `Erase`, Put/Get whole.
//! Array fields: `x(1 To 100) As Double` (bounds evaluated when the variable is made) and
//! `v() As Double` with `ReDim [Preserve] p.v(n)`; `p.x(3) = 2`, `UBound(p.x)`, copied with the
//! Type. Not covered: `p.x` passed to an array parameter `a() As Double`.
//! Fixed-length Strings, `Dim s As String * 10` and a Type's `name As String * 8` (the length a
//! number): an assigned text cut to the length or padded with spaces; Put writes no descriptor.
//! `Foo (y)` without `Call` passes `y` by value, as in VBA.
//!
//! `Collection` (`Dim c As New Collection`, `Set c = New Collection`) and Scripting's
//! `Dictionary` (`CreateObject("Scripting.Dictionary")`, `New Dictionary`), and .NET's
//! `CreateObject("System.Collections.ArrayList")` (made by ncsheet, no .NET loaded; no other
//! ProgID: `CreateObject` stays refused for everything else, .NET's other collections by
//! their names) are objects shared by `Set`, as in VBA.
//! An ArrayList: `Add` (returns the 0-based index), `Item` (the default, read and assigned:
//! `a(0)`), `Count`, `Capacity` (0, then 4, doubling), `Contains`, `IndexOf value[, start[,
//! count]]` (-1 for none), `Insert`, `Remove`, `RemoveAt`, `Clear`, `Sort` (numbers by value,
//! texts case ignored then lowercase first; items of different types, an Integer and a Double
//! too, fail as .NET's Sort does), `Reverse`, `ToArray` (a zero-based Variant array),
//! `TrimToSize`, `For Each`; .NET's exceptions come as their HRESULTs, `Err.Number`
//! -2146233086 for an index out of range, -2146233079 for items Sort cannot compare.
//! A Collection: `Add item, [key], [before], [after]` (named arguments too), `Item` (the
//! default member: `c(1)`, `c("k")`; keys ignore case), `Count`, `Remove index|key`, `For
//! Each` over the items. A Dictionary: `Add key, item`, `Exists`, `Item` (the default, read
//! and assigned: `d(k) = v` adds or replaces, reading a missing key adds it with Empty),
//! `Keys` and `Items` (zero-based arrays), `Count`, `Remove`, `RemoveAll`, `CompareMode`
//! (`vbBinaryCompare`, the default, or `vbTextCompare`, set while empty), `For Each` over
//! the keys; `1` and `"1"` are two keys. The errors are VBA's run-time errors, for `On Error`
//! and `Err.Number`: 457 for a key already there, 9 for a position past the items, 5 for a
//! Collection key no item has, 32811 for removing a Dictionary key that is not there.
//! `d.Key(old) = new` renames a key in place (457 when `new` is there). What an item, a
//! Function or `Split` gives is indexed in the same expression: `d(k)(i)`, `c.Item(1)(2)`,
//! `F()(i)` (with the bounds the Function gave), `Split(s, ",")(0)`, `d.Keys()(0)`. Not
//! there: objects as Dictionary keys (refused with the reason: keys are values). Removing
//! entries one at a time (`c.Remove 1` in a loop) costs the same per entry however many
//! there are. Their entries count against the run's memory limit (`--max-memory`) as arrays do.
//! VBScript's RegExp (`CreateObject("VBScript.RegExp")`, `New RegExp`,
//! `New VBScript_RegExp_55.RegExp`): `Pattern`, `Global`, `IgnoreCase`, `MultiLine`, `Test`,
//! `Execute` (a MatchCollection: `Count`, `Item` the default, 0-based, `For Each`; each Match:
//! `Value` the default, `FirstIndex` 0-based in UTF-16 units, `Length`, `SubMatches` with an
//! unmatched group Empty) and `Replace` (`$1`…`$99`, `$&`, `` $` ``, `$'`, `$$`). Patterns are
//! JScript's: `\d`, `\w`, `\s` and `\b` are ASCII, `.` is any character but a line feed.
//! Lookahead (`(?=`, `(?!`) and backreferences (`\1`) are refused by name; a bad pattern raises
//! VBScript's error (5017 "Syntax error in regular expression", 5018-5021).
//! `TypeName` names a variable's type or an object's class ("Collection", "Dictionary",
//! "Range", "Nothing"), `IsObject` is True for objects and Nothing, `VarType` of an object is
//! 9 (`vbObject`). `New Collection` is an expression: an argument too (`Fill New Collection`).
//!
//! Standard modules of one project (the workbook's, and `.bas` files given with `run
//! --module`) each have their own module-level variables and constants, as in VBA: the same
//! `Private Const NAME` or `Dim counter` in two modules are two. A name is, in [MS-VBAL]
//! 5.6.10's order, the procedure's, else its module's, else the `Public` one of another
//! module; one `Public` in two other modules is VBA's compile error "Ambiguous name
//! detected" where it is used, and `Module2.Rate` names Module2's whatever the others hold.
//!
//! Class modules (the project's, and `.cls` files given with `run --module`): `Dim x As New
//! Class1` or `Set x = New Class1` makes an object with its own module-level variables;
//! its public Subs, Functions, `Property Get|Let|Set` and `Public` variables are its members
//! (`x.Area`, `x.Width = 3`, `Set x.Owner = o`), `Me` is the object inside them, and `Set`
//! shares one object between variables, Collections and Dictionaries. `Class_Initialize` runs
//! when an object is made, `Class_Terminate` when the last reference goes: a variable set to
//! something else (or Nothing) or whose procedure ends, a Collection's or a Dictionary's
//! entry removed or replaced, an array's item, or the object, Collection or array holding it
//! let go (not at the end of the run for module-level variables). A member of Nothing is
//! VBA's error 91, a member the class has not error 438. `Dim x As New Class1` makes the
//! object at its first use, and again at a use after `Set x = Nothing` (auto-instantiation).
//! A class whose file says `Attribute VB_PredeclaredId = True` (an exported .cls, or the
//! project's stored source) has a default instance named after it, made at its first use and
//! kept for the run: `Set p = Point.Create(1, 2)`, `Point.Scale = 2`. `CallByName(obj, "Name",
//! VbGet)` (VbMethod, VbLet, VbSet) runs the member a text names, of any object the macro holds.
//! Arrays hold objects (`Set a(i) = New Class1`). A class that `Implements IShape` answers
//! `s.Area` with its `IShape_Area`, whatever `s` is declared as (`TypeOf` is not there). Not
//! there: events (`WithEvents`, `RaiseEvent`), default members; a class module the grammar
//! does not take is left out of the project (`New` of it is refused by name).
//!
//! `Null` is VBA's: arithmetic, comparisons (`Null = Null`), `Not` and negation give Null,
//! `&` takes a lone Null as "", `And`/`Or`/`Imp` follow VBA's tables, `If`/`While` take it as
//! False, and a variable declared with a type other than Variant refuses it with error 94.
//! A cell never holds Null (written to one, it leaves the cell empty). A library function
//! given Null follows its reference page: Null for a Variant parameter that passes it
//! (`Len(Null)`, `Left(Null, 1)`, `Abs(Null)`, `Hex(Null)` are Null), error 94 anywhere else
//! (`Left$(Null, 1)`, `Chr(Null)`, `Sqr(Null)`, `CStr(Null)`).
//!
//! Not in the language: events and forms.
//! A member's dot touches what it follows ([MS-VBAL] 5.6.12): `Out .Y + .X` in a With block
//! calls `Out` with `.Y + .X`.

mod append;
mod areas;
mod array_list;
mod arrays;
pub mod ast;
mod binary;
mod budget;
mod by_ref;
mod classes;
mod collections;
mod conditional;
mod const_order;
mod deftype;
mod dialogs;
mod files;
mod formats;
mod host;
mod hyperlinks;
mod insert_delete;
mod interp;
mod library;
mod list_objects;
mod longlong;
mod nc;
mod object_model;
mod objects;
mod operators;
pub mod ovba;
mod param_array;
pub mod parser;
mod path_names;
pub mod project;
pub mod project_edit;
mod regexp;
mod remove_duplicates;
mod replace;
mod resolve;
mod sheet_ops;
mod sort;
mod storage_size;
mod text_to_columns;
mod typing;
mod udf;
mod unmodelled;
mod value;

use std::fmt;

use crate::nc::{Machine, Program};
use crate::workbook::Workbook;

pub use crate::workbook::SheetLook;
pub use ast::{Module, Span};
pub use files::{checked_name, FileAccess};
pub use project::{read_project, ModuleKind, ProjectError, ProjectModule, VbaProject};
pub use udf::{install_functions, WorkbookFunctions, FUNCTION_MAX_DEPTH};

/// Work the macro engine counts where a class of input once made it quadratic, for tests to
/// bound in proportion to the input (a count holds on a loaded machine, where a wall-clock
/// bound would not). Counted per thread since the thread began: a run's work is the
/// difference of two readings around it on the thread that ran it. Only with the `testing`
/// feature (the tests'): the binary keeps no such state and pays nothing for it.
#[cfg(feature = "testing")]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// Hash probes made to find a variable by name among a module's or a call's variables
    /// (a scan of every variable would count each one looked at).
    pub name_probes: u64,
    /// Characters stepped over to find the column of a place in the source.
    pub columns_stepped: u64,
    /// Places of a Collection or Dictionary visited to close up removed entries.
    pub places_closed_up: u64,
    /// Bytes of text copied to append to it: the left side's text of every `&`, which the
    /// joined text copies; a variable's or an array item's text once when it starts growing
    /// in place (`s = s & x`, `a(i) = a(i) & x`), and again whenever its buffer is shared
    /// when appended to.
    pub text_copied: u64,
    /// Items of arrays the memory budget looked at: to count what a store brings, or to
    /// measure what the variables hold.
    pub items_measured: u64,
    /// Parts of expressions looked at to work out their types (`typing.rs`).
    pub nodes_typed: u64,
    /// Bytes of macro source the parser read: a project's modules joined count once for
    /// each parse of the whole (`udf.rs` parses a workbook's project once, not once a module).
    pub source_parsed: u64,
    /// Modules of a joined project looked at to find the one a place is in
    /// ([`ast::part_of_line`]): a bisection's steps.
    pub parts_searched: u64,
    /// Workbooks' VBA projects read from their `vbaProject.bin` ([`read_project`]).
    pub projects_read: u64,
}

/// The work done between two readings of [`work_done`].
#[cfg(feature = "testing")]
impl std::ops::Sub for Work {
    type Output = Work;

    fn sub(self, before: Work) -> Work {
        Work {
            name_probes: self.name_probes - before.name_probes,
            columns_stepped: self.columns_stepped - before.columns_stepped,
            places_closed_up: self.places_closed_up - before.places_closed_up,
            text_copied: self.text_copied - before.text_copied,
            items_measured: self.items_measured - before.items_measured,
            nodes_typed: self.nodes_typed - before.nodes_typed,
            source_parsed: self.source_parsed - before.source_parsed,
            parts_searched: self.parts_searched - before.parts_searched,
            projects_read: self.projects_read - before.projects_read,
        }
    }
}

#[cfg(feature = "testing")]
thread_local! {
    pub(crate) static NAME_PROBES: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static COLUMNS_STEPPED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static PLACES_CLOSED_UP: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static TEXT_COPIED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static ITEMS_MEASURED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static NODES_TYPED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static SOURCE_PARSED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static PARTS_SEARCHED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    pub(crate) static PROJECTS_READ: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Adds `n` to one of the counters of [`Work`].
#[cfg(feature = "testing")]
pub(crate) fn count(counter: &'static std::thread::LocalKey<std::cell::Cell<u64>>, n: u64) {
    counter.with(|c| c.set(c.get() + n));
}

/// Counts nothing: the counters of [`Work`] exist for the tests only.
#[cfg(not(feature = "testing"))]
pub(crate) fn count(_counter: &Counter, _n: u64) {}

/// The counters' stand-ins without the `testing` feature.
#[cfg(not(feature = "testing"))]
pub(crate) type Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const NAME_PROBES: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const COLUMNS_STEPPED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const PLACES_CLOSED_UP: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const TEXT_COPIED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const ITEMS_MEASURED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const NODES_TYPED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const SOURCE_PARSED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const PARTS_SEARCHED: Counter = ();
#[cfg(not(feature = "testing"))]
pub(crate) const PROJECTS_READ: Counter = ();

/// The work counted on this thread so far ([`Work`]).
#[cfg(feature = "testing")]
pub fn work_done() -> Work {
    Work {
        name_probes: NAME_PROBES.with(|c| c.get()),
        columns_stepped: COLUMNS_STEPPED.with(|c| c.get()),
        places_closed_up: PLACES_CLOSED_UP.with(|c| c.get()),
        text_copied: TEXT_COPIED.with(|c| c.get()),
        items_measured: ITEMS_MEASURED.with(|c| c.get()),
        nodes_typed: NODES_TYPED.with(|c| c.get()),
        source_parsed: SOURCE_PARSED.with(|c| c.get()),
        parts_searched: PARTS_SEARCHED.with(|c| c.get()),
        projects_read: PROJECTS_READ.with(|c| c.get()),
    }
}

/// How to run a macro.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The Sub (or Function) to run; `None` runs `Main`, or else the first Sub that needs no
    /// arguments.
    pub sub: Option<String>,
    /// Arguments for its parameters, by name, as typed (`"40"`, `"outer"`, `"TRUE"`): read
    /// as a cell reads what is typed into it.
    pub args: Vec<(String, String)>,
    /// Stops the macro after this many statements and loop turns (an endless loop, usually).
    pub max_statements: u64,
    /// Stops the macro when procedure calls nest deeper than this (endless recursion).
    pub max_depth: usize,
    /// Stops the macro at the first statement or loop turn past this instant (the command's
    /// `--timeout`): a loop of few statements that are each expensive (`Evaluate` of a large
    /// array) is stopped though it stays far below `max_statements`.
    pub deadline: Option<Deadline>,
    /// The sheet `Range`, `Cells` and `[B3]` mean before a macro activates another; `None`
    /// is the first sheet.
    pub sheet: Option<String>,
    /// The dialect the program will be written in, whose name `Nc.Dialect` tells the macro
    /// (`""` when none was chosen). Rendering is the caller's: see [`RunOutput::program`].
    pub dialect: Option<&'static dyn crate::nc::dialect::Dialect>,
    /// The machine of the program until the macro sets `Nc.Machine`.
    pub machine: Machine,
    /// The longest string, in characters (UTF-16 units), a macro may make (`run --max-string`).
    pub max_string: usize,
    /// The most items of one array (`run --max-array-items`).
    pub max_array_items: usize,
    /// The most bytes `Debug.Print` and `MsgBox` may write in one run (`run --max-output`).
    pub max_output: u64,
    /// The most bytes all the run's strings and arrays may hold together (`run --max-memory`).
    pub max_memory: u64,
    /// Where `Debug.Print` lines and `MsgBox` texts go as they happen; `None` keeps them in
    /// [`RunOutput::printed`] and [`RunOutput::messages`].
    pub sink: Option<Sink>,
    /// The sheets' VBA code names with the sheet each names (`("Sheet1", "Data")`), as the
    /// workbook file gives them: `Sheet1.Range("A1")` reaches that sheet.
    pub code_names: Vec<(String, String)>,
    /// The document module the code is in; `None` for a standard module (or a .bas file).
    pub document: Option<Document>,
    /// The active cell of each sheet when the macro starts, by sheet name, as the file saved
    /// it (`ActiveCell`, `Selection`); a sheet not listed starts at A1.
    pub active_cells: Vec<(String, crate::formula::address::Pos)>,
    /// The selection of each sheet when the macro starts, by sheet name, as the file saved it,
    /// area by area (`Selection` in Excel is that range, of one area or several, `ActiveCell`
    /// one cell of it); a sheet not listed starts with its active cell selected.
    pub selections: Vec<(String, Vec<crate::formula::address::Rect>)>,
    /// The project's other standard modules (name, source): the module sees their public
    /// procedures (`Helper`, `Module2.Helper`), constants and variables, as VBA compiles a
    /// project as one program.
    pub project: Vec<(String, String)>,
    /// The project's class modules (name, source): `New Name` makes an object of one.
    pub classes: Vec<(String, String)>,
    /// The workbook's file name (`Book1.xlsm`), for `Address(External:=True)`; `None` when
    /// the run does not know it (the address is then refused, never invented).
    pub workbook_name: Option<String>,
    /// The ANSI code page of the machine the project was written on (its PROJECTCODEPAGE record,
    /// or `run --code-page` for module files): `Print #`, `Write #` and `Line Input #` write and
    /// read text files in it, as VBA does in the system's code page. `None`: Windows-1252, a
    /// Western Excel's.
    pub code_page: Option<u16>,
    /// The files the macro may read and write (`run --out-dir`, `--in-file`); `None`: file
    /// statements are refused by name, as when the language had none.
    pub files: Option<FileAccess>,
    /// Folders a macro names by a fixed path (`C:\\Users\\x\\Desktop`), each mapped onto the
    /// --out-dir folder of [`RunOptions::files`] (`run --map-dir`): a path under one is the
    /// file name after it, which the sandbox's rules then check as any other name.
    pub mapped_dirs: Vec<String>,
    /// The answers to the macro's dialogs (`InputBox`, `Application.InputBox`,
    /// `GetOpenFilename`, `GetSaveAsFilename`), in the order it opens them (`run --input`);
    /// past the last one a dialog is cancelled. `None`: the run has no answers, and a dialog
    /// stops it by name.
    pub answers: Option<Vec<String>>,
    /// The chord tolerance the program will be written with on a control without circular
    /// interpolation (`run --arc-tol`), for `Nc.ChordsCW`; `None`: the default.
    pub arc_tolerance: Option<f64>,
    /// The look of the sheets' cells as the file gave it, by sheet name (number formats,
    /// styles, column widths, row heights): what `NumberFormat`, `Text` and `ColumnWidth`
    /// read; the run's changes come back in [`RunOutput::looks`].
    pub looks: Vec<(String, SheetLook)>,
    /// Who sets the limits above, so that a message about one names what the user can do.
    pub limits_from: LimitsFrom,
}

/// Who sets a run's limits (statements, depth, strings, arrays, output, memory): a message
/// about a limit names the option that raises it only where the command in use has it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LimitsFrom {
    /// The `run` command's options (`--max-statements`, `--max-depth`, …).
    #[default]
    RunOptions,
    /// Fixed for a workbook's VBA Function called from a cell, under any command
    /// (docs/limits.md): `eval`, `set` and the others have no option to raise them.
    CellFunction,
    /// Fixed for a macro the workbench (`serve`) runs: only `ncsheet run` raises them.
    Workbench,
}

impl RunOptions {
    /// The end of a message about a limit that an option of `run` sets: `raise`, which says
    /// how (`raise it with --max-string`), where the command in use has the option.
    pub(crate) fn raise_hint(&self, raise: &str) -> String {
        match self.limits_from {
            LimitsFrom::RunOptions => raise.to_string(),
            LimitsFrom::CellFunction => "ncsheet's limit for a VBA function a cell calls, docs/limits.md".into(),
            LimitsFrom::Workbench => {
                format!("ncsheet's limit for a macro the workbench runs; with `ncsheet run`, {raise}")
            }
        }
    }
}

/// A document module: the code behind a sheet or the workbook (a worksheet button's macro
/// lives there).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Document {
    /// A sheet's module (`Sheet1`), by sheet name: unqualified `Range`, `Cells` and `[B3]`
    /// mean this sheet whichever is active, and `Me` is the sheet.
    Sheet(String),
    /// `ThisWorkbook`: `Me` is the workbook; `Range` and `Cells` mean the active sheet.
    Workbook,
}

/// A line a macro printed, handed to [`RunOptions::sink`] as soon as it is complete.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Printed<'a> {
    /// A `Debug.Print` line.
    Line(&'a str),
    /// A `MsgBox` prompt.
    Message(&'a str),
}

/// The receiver of a macro's output while it runs: a flood of `Debug.Print` is written as it
/// comes, never held whole (the CLI writes it to standard error).
#[derive(Clone)]
pub struct Sink(pub std::rc::Rc<dyn Fn(Printed)>);

impl fmt::Debug for Sink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Sink")
    }
}

/// The default of [`RunOptions::max_string`]: 16 Mi characters. VBA's strings reach 2^31
/// characters, more than the memory ncsheet allows itself; docs/limits.md.
pub const DEFAULT_MAX_STRING: usize = crate::eval::evaluator::MAX_MACRO_TEXT;

/// The default of [`RunOptions::max_statements`]: a hostile-input guard, VBA itself has none.
/// Real modules must finish far below it: a bubble sort of 3,000 items, the largest loop of
/// the real modules, runs 22.5 million statements (about 20 s in a release build on a busy
/// machine, benches/README.md), and an endless loop still stops within about 30 s.
pub const DEFAULT_MAX_STATEMENTS: u64 = 30_000_000;

/// The default of [`RunOptions::max_array_items`].
pub const DEFAULT_MAX_ARRAY_ITEMS: usize = 10_000_000;

/// The default of [`RunOptions::max_output`]: 64 MiB of `Debug.Print` and `MsgBox` text.
pub const DEFAULT_MAX_OUTPUT: u64 = 64 << 20;

/// The default of [`RunOptions::max_memory`]: 1 GiB of strings and arrays, half of what
/// ncsheet is tested to run in (docs/limits.md).
pub const DEFAULT_MAX_MEMORY: u64 = 1 << 30;

/// When a run must stop, and the `--timeout` it came from (for the message).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deadline {
    pub at: std::time::Instant,
    pub seconds: f64,
}

impl Deadline {
    /// `seconds` from now.
    pub fn after(seconds: f64) -> Deadline {
        Deadline { at: std::time::Instant::now() + std::time::Duration::from_secs_f64(seconds), seconds }
    }
}

impl Default for RunOptions {
    fn default() -> RunOptions {
        RunOptions {
            sub: None,
            args: Vec::new(),
            max_statements: DEFAULT_MAX_STATEMENTS,
            max_depth: 100,
            deadline: None,
            sheet: None,
            dialect: None,
            machine: Machine::Lathe,
            max_string: DEFAULT_MAX_STRING,
            max_array_items: DEFAULT_MAX_ARRAY_ITEMS,
            max_output: DEFAULT_MAX_OUTPUT,
            max_memory: DEFAULT_MAX_MEMORY,
            sink: None,
            code_names: Vec::new(),
            document: None,
            active_cells: Vec::new(),
            selections: Vec::new(),
            project: Vec::new(),
            classes: Vec::new(),
            workbook_name: None,
            code_page: None,
            files: None,
            answers: None,
            mapped_dirs: Vec::new(),
            arc_tolerance: None,
            looks: Vec::new(),
            limits_from: LimitsFrom::RunOptions,
        }
    }
}

/// What a macro produced. Cell writes are already in the workbook.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutput {
    /// `Debug.Print` lines, for standard error (stdout carries only the program); empty when
    /// [`RunOptions::sink`] took them.
    pub printed: Vec<String>,
    /// `MsgBox` texts, for standard error; empty when [`RunOptions::sink`] took them.
    pub messages: Vec<String>,
    /// The NC program the macro emitted with `Nc.*` (empty when it emitted none); write it
    /// with `nc::by_name(dialect)?.render(&program)`.
    pub program: Program,
    /// The files the macro wrote (a plain name inside [`FileAccess::out_dir`], the bytes), in
    /// the order first opened: for the caller to write when the run succeeded, all or none.
    pub files: Vec<(String, Vec<u8>)>,
    /// The files of [`FileAccess::out_dir`] the macro deleted (`Kill`, plain names): for the
    /// caller to remove after writing [`RunOutput::files`], when the run succeeded.
    pub removed: Vec<String>,
    /// The look of the sheets the file gave a look or the macro formatted, by sheet name,
    /// as the run left it (`formats.rs`): for the caller to save with the workbook.
    pub looks: Vec<(String, SheetLook)>,
    /// The statements and loop turns the run counted against [`RunOptions::max_statements`]
    /// (what the benchmark divides its time by).
    pub statements: u64,
    /// The lines of the macro's `ThisWorkbook.Save` / `ActiveWorkbook.Save` calls: ncsheet
    /// never writes its input, so the caller saves the workbook where `--save` says, or tells
    /// the user it was not written.
    pub saves: Vec<u32>,
}

impl RunOutput {
    fn new(name: &str, machine: Machine) -> RunOutput {
        RunOutput {
            printed: Vec::new(),
            messages: Vec::new(),
            program: Program::new(name, machine),
            files: Vec::new(),
            removed: Vec::new(),
            looks: Vec::new(),
            statements: 0,
            saves: Vec::new(),
        }
    }

    pub fn has_program(&self) -> bool {
        !self.program.blocks.is_empty()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The source does not parse, or names something the language does not have.
    Syntax,
    /// A statement failed while running.
    Runtime,
    /// The statement, time or recursion limit stopped the macro.
    Limit,
    /// The run was asked for something the module does not have (`--sub`, `--arg`).
    Usage,
}

/// Why a macro did not run to its end: where (file, line, column, the source line for a
/// caret), what, and which procedures were running.
#[derive(Clone, Debug, PartialEq)]
pub struct MacroError {
    pub kind: ErrorKind,
    pub file: String,
    pub span: Option<Span>,
    pub message: String,
    /// The source line at `span`.
    pub source_line: String,
    /// Innermost first: `in Function Area (called at line 12, column 5)`, `in Sub Main`.
    pub trace: Vec<String>,
    /// What the macro printed and emitted before it stopped.
    pub output: Box<RunOutput>,
}

/// Renders as a compiler does:
///
/// ```text
/// chamfer.bas:14:13: error: Nc.Line: X is #DIV/0!
///    14 |     Nc.Line x / 0, z
///       |             ^
///   in Sub Cut (called at line 3, column 5)
///   in Sub Main
/// ```
impl fmt::Display for MacroError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.kind {
            ErrorKind::Syntax => "syntax error",
            ErrorKind::Runtime | ErrorKind::Usage => "error",
            ErrorKind::Limit => "stopped",
        };
        let Some(span) = self.span else {
            return write!(f, "{}: {kind}: {}", self.file, self.message);
        };
        write!(f, "{}:{}:{}: {kind}: {}", self.file, span.line, span.col, self.message)?;
        let number = span.line.to_string();
        let pad = " ".repeat(number.len());
        // A line of 200,000 items shows only the stretch around the column (`…` where cut).
        let (shown, caret) = crate::formula::parse::excerpt_around(&self.source_line, span.col as usize);
        // The caret lines up under tabs too: copy the line's own whitespace up to the column.
        let lead: String = shown.chars().take(caret).map(|c| if c == '\t' { '\t' } else { ' ' }).collect();
        write!(f, "\n {number} | {shown}\n {pad} | {lead}^")?;
        // A recursion stopped at depth 10,000 repeats one line 10,000 times (490 KB): a run
        // of equal lines is written once with its count.
        let mut lines = self.trace.iter().peekable();
        while let Some(t) = lines.next() {
            let mut repeats = 1;
            while lines.next_if(|next| *next == t).is_some() {
                repeats += 1;
            }
            write!(f, "\n  {t}")?;
            if repeats > 1 {
                write!(f, " ({repeats} times)")?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for MacroError {}

/// Parses a module without running it (for listing its Subs, or checking it). `workbook`
/// resolves sheet names in `[Sheet2!A1]` brackets.
pub fn parse(source: &str, file_name: &str, workbook: &Workbook) -> Result<Module, MacroError> {
    parse_with(source, file_name, workbook, &RunOptions::default())
}

/// [`parse`] knowing what `options` adds to the names: the sheets' code names, and `Me` in
/// a document module.
fn parse_with(source: &str, file_name: &str, workbook: &Workbook, options: &RunOptions) -> Result<Module, MacroError> {
    parse_joined(source, file_name, workbook, options).map(|(module, _)| module)
}

/// [`parse_with`], also giving the source parsed: `source` with the project's other modules
/// (`options.project`, `options.classes`) joined after it, or `None` when there are none.
fn parse_joined(
    source: &str,
    file_name: &str,
    workbook: &Workbook,
    options: &RunOptions,
) -> Result<(Module, Option<String>), MacroError> {
    let mut objects: Vec<String> = options.code_names.iter().map(|(code, _)| code.to_ascii_lowercase()).collect();
    if options.document.is_some() {
        objects.push("me".into());
    }
    let own = std::path::Path::new(file_name).file_stem().and_then(|s| s.to_str()).unwrap_or(file_name);
    let (joined, parts) = join_project(own, source, &options.project, &options.classes);
    let parsed = joined.as_deref().unwrap_or(source);
    let files = options.files.is_some();
    match parser::parse_module_with_files(parsed, &|n| workbook.sheet_id(n), &objects, &parts, files) {
        Ok(module) => Ok((module, joined)),
        Err(e) => Err(syntax_error(e, parsed, file_name, &parts)),
    }
}

/// A parse error of `source` (named `file_name`, of the project's modules `parts`) as the
/// macro error naming its module, line and column.
fn syntax_error(e: parser::SyntaxError, source: &str, file_name: &str, parts: &[ast::Part]) -> MacroError {
    let lines = parser::Lines::new(source);
    let span = lines.span(source, e.offset);
    let mut e = MacroError {
        kind: ErrorKind::Syntax,
        file: file_name.to_string(),
        span: Some(span),
        message: e.message,
        source_line: lines.text(source, span.line).to_string(),
        trace: Vec::new(),
        output: Box::new(RunOutput::new("", Machine::Lathe)),
    };
    relocate(&mut e, parts);
    e
}

/// The first error of the grammar in module `source` (named `name`) read on its own, its
/// names unresolved: a module cut short is named itself, not the module joined after it.
fn grammar_error(source: &str, name: &str) -> Option<MacroError> {
    parser::grammar_error(source).map(|e| syntax_error(e, source, name, &[]))
}

/// `source` with the code of the project's other modules after it, its class modules last
/// (those the language's grammar takes), their `Attribute` and `Option Private Module` lines
/// left blank, and where each module starts; `None` and no parts when there are no others.
/// Their `Option Base`/`Option Compare`/`Option Explicit` lines stay: the parser keeps each
/// module's own ([MS-VBAL] 5.2.1).
fn join_project(
    own_name: &str,
    source: &str,
    others: &[(String, String)],
    classes: &[(String, String)],
) -> (Option<String>, Vec<ast::Part>) {
    if others.is_empty() && classes.is_empty() {
        return (None, Vec::new());
    }
    let mut out = source.to_string();
    let own = ast::Part {
        name: own_name.into(),
        first_line: 1,
        class: false,
        predeclared: false,
        special: ast::SpecialMembers::default(),
    };
    let mut parts = vec![own];
    let classes = classes.iter().filter(|(_, source)| parser::in_grammar(source));
    let modules = others.iter().map(|m| (m, false)).chain(classes.map(|c| (c, true)));
    // The line breaks in `out`, counted as they are written: counting them again for each
    // module made a project of 2,000 modules quadratic.
    let mut breaks = source.matches('\n').count();
    for ((name, other), class) in modules {
        if !out.ends_with('\n') {
            out.push_str("\r\n");
            breaks += 1;
        }
        let first_line = breaks as u32 + 1;
        let predeclared = class && classes::has_predeclared_id(other);
        let special = if class { classes::special_members(other) } else { ast::SpecialMembers::default() };
        parts.push(ast::Part { name: name.as_str().into(), first_line, class, predeclared, special });
        for line in other.lines() {
            if !left_out_of_joined_module(line) {
                out.push_str(line);
            }
            out.push_str("\r\n");
            breaks += 1;
        }
    }
    (Some(out), parts)
}

/// A line of a module joined after the first left blank: an `Attribute` line, or an `Option`
/// other than `Option Base`/`Option Compare`/`Option Explicit` (which apply to their own module).
fn left_out_of_joined_module(line: &str) -> bool {
    let mut words = line.split_whitespace().map(str::to_ascii_lowercase);
    match words.next().as_deref() {
        Some("attribute") => true,
        Some("option") => !matches!(words.next().as_deref(), Some("base" | "compare" | "explicit")),
        _ => false,
    }
}

/// An error in another module of a joined project: named by that module and its own line.
fn relocate(e: &mut MacroError, parts: &[ast::Part]) {
    let Some(span) = e.span.as_mut() else { return };
    // The first module's own lines keep their place.
    let at = ast::part_of_line(parts, span.line);
    let Some(part) = parts.get(at).filter(|_| at > 0) else { return };
    span.line -= part.first_line - 1;
    e.file = part.name.to_string();
}

/// Runs a macro: parses `source` (named `file_name` in messages), runs the Sub chosen by
/// `options` against `workbook` (cell writes stay in it), and returns what the macro printed
/// and the NC program it emitted.
pub fn run(
    workbook: &mut Workbook,
    source: &str,
    file_name: &str,
    options: &RunOptions,
) -> Result<RunOutput, MacroError> {
    let (module, joined) = parse_joined(source, file_name, workbook, options)?;
    let module = std::rc::Rc::new(module);
    let own = std::path::Path::new(file_name).file_stem().and_then(|s| s.to_str()).unwrap_or(file_name);
    let source = joined.as_deref().unwrap_or(source);
    // The project parsed once: its Functions callable from cells are this tree's.
    udf::install_run_functions(workbook, own, (&module, source), options);
    interp::run(&module, workbook, source, file_name, options).map_err(|mut e| {
        relocate(&mut e, &module.parts);
        e
    })
}
