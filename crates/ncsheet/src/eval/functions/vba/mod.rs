//! VBA's library functions (`Sqr`, `Atn`, `Format`, `CStr`, `IIf`, …) for the macro language.
//!
//! They are rows of the one function table named `VBA.SQR`, `VBA.FORMAT`, …: VBA itself
//! files them in its `VBA` library, and the prefix keeps them apart from Excel's functions of
//! the same name that behave differently (`VBA.ROUND` rounds half to even, `VBA.LOG` is the
//! natural logarithm, `VBA.TRIM` keeps inner spaces). In a macro a bare `Round(x)` means
//! `VBA.Round`; `Application.WorksheetFunction.Round(x, 2)` means Excel's. They are harmless
//! in cells, where `=VBA.SQR(2)` works too.

use std::rc::Rc;

use crate::eval::coerce::{parse_plain_number, to_bool, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{
    explain_lifted_size, lift_values, number_result, Ctx, FnSpec, Operand, Outside, MANY,
};
use crate::eval::functions::text::strings::{wild_match, WildToken};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use crate::eval::format::text_format::{NumberFormat, WeekNumbers};

mod calendar;
mod conversions;
pub mod errors;
mod strings;
use conversions::Raised;
pub use strings::var_type_of;

/// VBA's Date type counts days as the 1900 date system does (from 1899-12-30), whatever
/// the workbook's system: VBA's conversions read date text, and Format shows dates, in it.
const VBA_DATES: DateSystem = DateSystem::From1900;

/// The prefix of this module's names in the function table.
pub const PREFIX: &str = "VBA.";

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("VBA.ABS", 1, 1, abs, "VBA.ABS(number)", "VBA Abs: absolute value"),
    FnSpec::value("VBA.ARRAY", 0, MANY, array, "VBA.ARRAY(item1, ...)", "VBA Array: the items as a one-row array"),
    FnSpec::value("VBA.ASC", 1, 1, asc, "VBA.ASC(text)", "VBA Asc: code of the first character"),
    FnSpec::value("VBA.ASCW", 1, 1, ascw, "VBA.ASCW(text)", "VBA AscW: UTF-16 code of the first character"),
    FnSpec::value("VBA.ATN", 1, 1, atn, "VBA.ATN(number)", "VBA Atn: arctangent in radians"),
    FnSpec::value("VBA.CBOOL", 1, 1, cbool, "VBA.CBOOL(value)", "VBA CBool: value as True or False"),
    FnSpec::value("VBA.CDBL", 1, 1, cdbl, "VBA.CDBL(value)", "VBA CDbl: value as a number; #VALUE! for other text"),
    FnSpec::value("VBA.CHR", 1, 1, chr, "VBA.CHR(code)", "VBA Chr: the character with this code"),
    FnSpec::value("VBA.CINT", 1, 1, cint, "VBA.CINT(value)", "VBA CInt: whole number, halves to even, -32768 to 32767"),
    FnSpec::value("VBA.CLNG", 1, 1, clng, "VBA.CLNG(value)", "VBA CLng: whole number, halves to even, 32 bits"),
    FnSpec::value(
        "VBA.CHRW",
        1,
        1,
        strings::chrw,
        "VBA.CHRW(code)",
        "VBA ChrW: the character of a UTF-16 code (-32768 to 65535)",
    ),
    FnSpec::value("VBA.COS", 1, 1, cos, "VBA.COS(angle)", "VBA Cos: cosine of an angle in radians"),
    FnSpec::value("VBA.CSTR", 1, 1, cstr, "VBA.CSTR(value)", "VBA CStr: value as text (True, 0.5, 1E+20)"),
    FnSpec::value(
        "VBA.CVERR",
        1,
        1,
        strings::cv_err,
        "VBA.CVERR(number)",
        "VBA CVErr: Excel's error value of an xlErr number (2042: #N/A)",
    ),
    FnSpec::value(
        "VBA.ERROR",
        1,
        1,
        errors::error_fn,
        "VBA.ERROR(number)",
        "VBA Error: the message of a run-time error number (11: Division by zero)",
    ),
    FnSpec::value("VBA.EXP", 1, 1, exp, "VBA.EXP(number)", "VBA Exp: e raised to number"),
    FnSpec::value(
        "VBA.FILTER",
        2,
        4,
        strings::filter,
        "VBA.FILTER(array, match, [include], [compare])",
        "VBA Filter: the array's items that contain match (or, include False, that do not)",
    )
    .vba_params(&["SourceArray", "Match", "[Include]", "[Compare]"]),
    FnSpec::value("VBA.FIX", 1, 1, fix, "VBA.FIX(number)", "VBA Fix: drops the fraction (toward zero)"),
    FnSpec::value(
        "VBA.FORMAT",
        1,
        4,
        format,
        "VBA.FORMAT(value, [format], [firstdayofweek], [firstweekofyear])",
        "VBA Format: number as text in an Excel/VBA number format (\"0.000\", \"#,##0.0\", \"0.00E+00\")",
    ),
    FnSpec::value(
        "VBA.FORMATNUMBER",
        1,
        5,
        strings::format_number_fn,
        "VBA.FORMATNUMBER(number, [digits], [leading_zero], [parentheses], [group])",
        "VBA FormatNumber: 1,234.50 (two decimals, grouped, as en-US)",
    ),
    FnSpec::value(
        "VBA.FORMATPERCENT",
        1,
        5,
        strings::format_percent_fn,
        "VBA.FORMATPERCENT(number, [digits], [leading_zero], [parentheses], [group])",
        "VBA FormatPercent: 25.60% (times 100, two decimals, as en-US)",
    ),
    FnSpec::value(
        "VBA.FORMATCURRENCY",
        1,
        5,
        strings::format_currency_fn,
        "VBA.FORMATCURRENCY(number, [digits], [leading_zero], [parentheses], [group])",
        "VBA FormatCurrency: $1,234.50, ($1,234.50) when negative (as en-US)",
    ),
    FnSpec::value(
        "VBA.FORMATDATETIME",
        1,
        2,
        strings::format_date_time_fn,
        "VBA.FORMATDATETIME(date, [named_format])",
        "VBA FormatDateTime: vbGeneralDate, vbLongDate, vbShortDate, vbLongTime or vbShortTime",
    ),
    FnSpec::value("VBA.IIF", 3, 3, iif, "VBA.IIF(condition, then, else)", "VBA IIf: evaluates both, returns one"),
    FnSpec::value(
        "VBA.INSTR",
        2,
        4,
        strings::instr,
        "VBA.INSTR([start], text, find, [compare])",
        "VBA InStr: 1-based position of find in text, 0 when absent (compare 1: ignoring case)",
    )
    .vba_params(&["[Start]", "String1", "String2", "[Compare]"]),
    FnSpec::value(
        "VBA.INSTRREV",
        2,
        4,
        strings::instr_rev,
        "VBA.INSTRREV(text, find, [start], [compare])",
        "VBA InStrRev: position of the last find ending at or before start",
    )
    .vba_params(&["StringCheck", "StringMatch", "[Start]", "[Compare]"]),
    FnSpec::value("VBA.ISARRAY", 1, 1, strings::is_array, "VBA.ISARRAY(value)", "VBA IsArray: True for an array"),
    FnSpec::value(
        "VBA.JOIN",
        1,
        2,
        strings::join,
        "VBA.JOIN(array, [delimiter])",
        "VBA Join: the array's items as one text, delimiter (a space) between",
    )
    .vba_params(&["SourceArray", "[Delimiter]"]),
    FnSpec::value(
        "VBA.LENB",
        1,
        1,
        strings::len_b,
        "VBA.LENB(text)",
        "VBA LenB: bytes of the text in UTF-16 (2 a unit)",
    ),
    FnSpec::value("VBA.INT", 1, 1, int, "VBA.INT(number)", "VBA Int: largest whole number not above number"),
    FnSpec::value(
        "VBA.ISEMPTY",
        1,
        1,
        is_empty,
        "VBA.ISEMPTY(value)",
        "VBA IsEmpty: True for an empty cell or variable",
    ),
    FnSpec::value("VBA.ISNULL", 1, 1, is_null, "VBA.ISNULL(value)", "VBA IsNull: True for Null"),
    FnSpec::value("VBA.ISERROR", 1, 1, is_error, "VBA.ISERROR(value)", "VBA IsError: True for an error value"),
    FnSpec::value(
        "VBA.ISOBJECT",
        1,
        1,
        is_object,
        "VBA.ISOBJECT(value)",
        "VBA IsObject: True for a range (Evaluate(\"XA\") of a defined name of cells)",
    ),
    FnSpec::value(
        "VBA.ISNUMERIC",
        1,
        1,
        is_numeric,
        "VBA.ISNUMERIC(value)",
        "VBA IsNumeric: True if value reads as a number",
    ),
    FnSpec::value("VBA.LCASE", 1, 1, lcase, "VBA.LCASE(text)", "VBA LCase: text in small letters"),
    FnSpec::value("VBA.LEFT", 2, 2, left, "VBA.LEFT(text, length)", "VBA Left: the first length characters"),
    FnSpec::value("VBA.LEN", 1, 1, len, "VBA.LEN(text)", "VBA Len: number of characters"),
    FnSpec::value("VBA.LOG", 1, 1, log, "VBA.LOG(number)", "VBA Log: natural logarithm (Excel's LN)"),
    FnSpec::value("VBA.LTRIM", 1, 1, ltrim, "VBA.LTRIM(text)", "VBA LTrim: text without leading spaces"),
    FnSpec::value("VBA.MID", 2, 3, mid, "VBA.MID(text, start, [length])", "VBA Mid: characters from start (1-based)")
        .vba_params(&["String", "Start", "[Length]"]),
    FnSpec::value(
        "VBA.REPLACE",
        3,
        6,
        conversions::replace,
        "VBA.REPLACE(text, find, with, [start], [count], [compare])",
        "VBA Replace: the text from start with count finds (all: -1) replaced",
    )
    .vba_params(&["Expression", "Find", "Replace", "[Start]", "[Count]", "[Compare]"]),
    FnSpec::value("VBA.RGB", 3, 3, rgb, "VBA.RGB(red, green, blue)", "VBA RGB: a colour, red + green*256 + blue*65536"),
    FnSpec::value("VBA.RIGHT", 2, 2, right, "VBA.RIGHT(text, length)", "VBA Right: the last length characters"),
    FnSpec::value(
        "VBA.RND",
        0,
        1,
        strings::rnd,
        "VBA.RND([number])",
        "VBA Rnd: the next number 0 <= x < 1 of the document's random sequence",
    )
    .volatile()
    .reads(Outside::Chance),
    FnSpec::value(
        "VBA.ROUND",
        1,
        2,
        round,
        "VBA.ROUND(number, [digits])",
        "VBA Round: to digits decimals, halves to even (Round(2.5) is 2)",
    )
    .vba_params(&["Expression", "[NumDecimalPlaces]"]),
    FnSpec::value("VBA.RTRIM", 1, 1, rtrim, "VBA.RTRIM(text)", "VBA RTrim: text without trailing spaces"),
    FnSpec::value("VBA.SGN", 1, 1, sgn, "VBA.SGN(number)", "VBA Sgn: -1, 0 or 1"),
    FnSpec::value("VBA.SIN", 1, 1, sin, "VBA.SIN(angle)", "VBA Sin: sine of an angle in radians"),
    FnSpec::value("VBA.SPACE", 1, 1, space, "VBA.SPACE(count)", "VBA Space: count spaces"),
    FnSpec::value("VBA.SQR", 1, 1, sqr, "VBA.SQR(number)", "VBA Sqr: square root; error 5 below zero"),
    FnSpec::value(
        "VBA.SPLIT",
        1,
        4,
        strings::split,
        "VBA.SPLIT(text, [delimiter], [limit], [compare])",
        "VBA Split: the pieces between delimiters (a space) as a zero-based array",
    )
    .vba_params(&["Expression", "[Delimiter]", "[Limit]", "[Compare]"]),
    FnSpec::value("VBA.STR", 1, 1, str_fn, "VBA.STR(number)", "VBA Str: number as text, a space before a positive one"),
    FnSpec::value(
        "VBA.STRCOMP",
        2,
        3,
        strings::str_comp,
        "VBA.STRCOMP(text1, text2, [compare])",
        "VBA StrComp: -1, 0 or 1 (compare 1: ignoring case)",
    )
    .vba_params(&["String1", "String2", "[Compare]"]),
    FnSpec::value(
        "VBA.STRCONV",
        2,
        2,
        strings::str_conv,
        "VBA.STRCONV(text, conversion)",
        "VBA StrConv: vbUpperCase (1), vbLowerCase (2), vbProperCase (3), vbUnicode (64), vbFromUnicode (128)",
    ),
    FnSpec::value(
        "VBA.DOEVENTS",
        0,
        0,
        strings::do_events,
        "VBA.DOEVENTS()",
        "VBA DoEvents: yields to the system; 0, the open forms of an Office application",
    ),
    FnSpec::value("VBA.TAN", 1, 1, tan, "VBA.TAN(angle)", "VBA Tan: tangent of an angle in radians"),
    FnSpec::value(
        "VBA.TIMER",
        0,
        0,
        strings::timer,
        "VBA.TIMER()",
        "VBA Timer: seconds since midnight by the document's clock",
    )
    .volatile()
    .reads(Outside::Clock),
    FnSpec::value("VBA.TRIM", 1, 1, trim, "VBA.TRIM(text)", "VBA Trim: text without leading and trailing spaces"),
    FnSpec::value("VBA.UCASE", 1, 1, ucase, "VBA.UCASE(text)", "VBA UCase: text in capitals"),
    FnSpec::value(
        "VBA.VARTYPE",
        1,
        1,
        strings::var_type,
        "VBA.VARTYPE(value)",
        "VBA VarType: 0 Empty, 5 Double, 8 String, 10 Error, 11 Boolean, 8204 array",
    ),
    FnSpec::value("VBA.VAL", 1, 1, val, "VBA.VAL(text)", "VBA Val: the number text starts with (0 if none)"),
    FnSpec::value("VBA.HEX", 1, 1, conversions::hex, "VBA.HEX(number)", "VBA Hex: a whole number in hexadecimal"),
    FnSpec::value("VBA.OCT", 1, 1, conversions::oct, "VBA.OCT(number)", "VBA Oct: a whole number in octal"),
    FnSpec::value(
        "VBA.CLNGLNG",
        1,
        1,
        conversions::clnglng,
        "VBA.CLNGLNG(value)",
        "VBA CLngLng: whole number, halves to even, 64 bits",
    ),
    FnSpec::value("VBA.CBYTE", 1, 1, conversions::cbyte, "VBA.CBYTE(value)", "VBA CByte: whole number 0 to 255"),
    FnSpec::value("VBA.CSNG", 1, 1, conversions::csng, "VBA.CSNG(value)", "VBA CSng: number as a Single"),
    FnSpec::value("VBA.CCUR", 1, 1, conversions::ccur, "VBA.CCUR(value)", "VBA CCur: number to 4 decimal places"),
    FnSpec::value("VBA.CVAR", 1, 1, conversions::cvar, "VBA.CVAR(value)", "VBA CVar: the value as a Variant, as it is"),
    FnSpec::value("VBA.CDEC", 1, 1, conversions::cdec, "VBA.CDEC(value)", "VBA CDec: the value as a Decimal"),
    FnSpec::value(
        "VBA.STRING",
        2,
        2,
        conversions::string,
        "VBA.STRING(number, character)",
        "VBA String: number copies of a character (a code or a text's first)",
    ),
    FnSpec::value(
        "VBA.STRREVERSE",
        1,
        1,
        conversions::str_reverse,
        "VBA.STRREVERSE(text)",
        "VBA StrReverse: the characters in reverse order",
    ),
    FnSpec::value(
        "VBA.DATESERIAL",
        3,
        3,
        conversions::date_serial,
        "VBA.DATESERIAL(year, month, day)",
        "VBA DateSerial: the date (days from 1899-12-30), months and days past their range carried",
    ),
    FnSpec::value(
        "VBA.TIMESERIAL",
        3,
        3,
        conversions::time_serial,
        "VBA.TIMESERIAL(hour, minute, second)",
        "VBA TimeSerial: the time as a fraction of a day",
    ),
    FnSpec::value("VBA.DATE", 0, 0, conversions::date, "VBA.DATE()", "VBA Date: today by the document's clock")
        .volatile()
        .reads(Outside::Clock),
    FnSpec::value(
        "VBA.TIME",
        0,
        0,
        conversions::time,
        "VBA.TIME()",
        "VBA Time: the time of day by the document's clock",
    )
    .volatile()
    .reads(Outside::Clock),
    FnSpec::value("VBA.CDATE", 1, 1, conversions::cdate, "VBA.CDATE(value)", "VBA CDate: the value as a Date"),
    FnSpec::value("VBA.YEAR", 1, 1, conversions::year, "VBA.YEAR(date)", "VBA Year: the year of a Date (100 to 9999)"),
    FnSpec::value("VBA.MONTH", 1, 1, conversions::month, "VBA.MONTH(date)", "VBA Month: the month of a Date, 1 to 12"),
    FnSpec::value("VBA.DAY", 1, 1, conversions::day, "VBA.DAY(date)", "VBA Day: the day of the month of a Date"),
    FnSpec::value("VBA.HOUR", 1, 1, conversions::hour, "VBA.HOUR(date)", "VBA Hour: the hour of a Date, 0 to 23"),
    FnSpec::value("VBA.MINUTE", 1, 1, conversions::minute, "VBA.MINUTE(date)", "VBA Minute: the minute of a Date"),
    FnSpec::value("VBA.SECOND", 1, 1, conversions::second, "VBA.SECOND(date)", "VBA Second: the second of a Date"),
    FnSpec::value(
        "VBA.WEEKDAY",
        1,
        2,
        conversions::weekday,
        "VBA.WEEKDAY(date, [firstdayofweek])",
        "VBA Weekday: the day of the week of a Date, 1 for the first (Sunday unless given)",
    ),
    FnSpec::value(
        "VBA.DATEADD",
        3,
        3,
        calendar::date_add,
        "VBA.DATEADD(interval, number, date)",
        "VBA DateAdd: the date with number intervals (yyyy q m y d w ww h n s) added, month ends kept",
    ),
    FnSpec::value(
        "VBA.DATEDIFF",
        3,
        5,
        calendar::date_diff,
        "VBA.DATEDIFF(interval, date1, date2, [firstdayofweek], [firstweekofyear])",
        "VBA DateDiff: the interval's boundaries (yyyy q m y d w ww h n s) from date1 to date2",
    ),
    FnSpec::value(
        "VBA.DATEPART",
        2,
        4,
        calendar::date_part,
        "VBA.DATEPART(interval, date, [firstdayofweek], [firstweekofyear])",
        "VBA DatePart: one part of a date (yyyy q m y d w ww h n s)",
    ),
    FnSpec::value(
        "VBA.WEEKDAYNAME",
        1,
        3,
        calendar::weekday_name,
        "VBA.WEEKDAYNAME(weekday, [abbreviate], [firstdayofweek])",
        "VBA WeekdayName: the name of a day of the week (1 for the first, Sunday unless given)",
    ),
    FnSpec::value(
        "VBA.MONTHNAME",
        1,
        2,
        calendar::month_name,
        "VBA.MONTHNAME(month, [abbreviate])",
        "VBA MonthName: the name of a month, 1 to 12",
    ),
    FnSpec::value(
        "VBA.DATEVALUE",
        1,
        1,
        calendar::date_value,
        "VBA.DATEVALUE(date)",
        "VBA DateValue: the date of a date text or Date, without its time",
    ),
    FnSpec::value(
        "VBA.TIMEVALUE",
        1,
        1,
        calendar::time_value,
        "VBA.TIMEVALUE(time)",
        "VBA TimeValue: the time of day of a time text or Date",
    ),
    FnSpec::value(
        "VBA.MIDSTATEMENT",
        4,
        4,
        conversions::mid_statement,
        "VBA.MIDSTATEMENT(text, start, [length], replacement)",
        "VBA's Mid statement (Mid(s, start, length) = replacement): the text with characters replaced",
    ),
    FnSpec::value(
        "VBA.LSETSTATEMENT",
        2,
        2,
        conversions::lset_statement,
        "VBA.LSETSTATEMENT(stringvar, string)",
        "VBA's LSet statement (LSet s = string): the string left-aligned in the variable's length",
    ),
    FnSpec::value(
        "VBA.RSETSTATEMENT",
        2,
        2,
        conversions::rset_statement,
        "VBA.RSETSTATEMENT(stringvar, string)",
        "VBA's RSet statement (RSet s = string): the string right-aligned in the variable's length",
    ),
    FnSpec::value("VBA.DATE$", 0, 0, conversions::date_s, "VBA.DATE$()", "VBA Date$: today as mm-dd-yyyy")
        .volatile()
        .reads(Outside::Clock),
    FnSpec::value("VBA.TIME$", 0, 0, conversions::time_s, "VBA.TIME$()", "VBA Time$: the time of day as hh:mm:ss")
        .volatile()
        .reads(Outside::Clock),
    // The `$` forms of the functions that pass Null: a String, so Null is error 94.
    FnSpec::value("VBA.LEFT$", 2, 2, conversions::left_s, "VBA.LEFT$(text, length)", "VBA Left$: Left as a String"),
    FnSpec::value(
        "VBA.RIGHT$",
        2,
        2,
        conversions::right_s,
        "VBA.RIGHT$(text, length)",
        "VBA Right$: Right as a String",
    ),
    FnSpec::value("VBA.MID$", 2, 3, conversions::mid_s, "VBA.MID$(text, start, [length])", "VBA Mid$: Mid as a String"),
    FnSpec::value("VBA.TRIM$", 1, 1, conversions::trim_s, "VBA.TRIM$(text)", "VBA Trim$: Trim as a String"),
    FnSpec::value("VBA.LTRIM$", 1, 1, conversions::ltrim_s, "VBA.LTRIM$(text)", "VBA LTrim$: LTrim as a String"),
    FnSpec::value("VBA.RTRIM$", 1, 1, conversions::rtrim_s, "VBA.RTRIM$(text)", "VBA RTrim$: RTrim as a String"),
    FnSpec::value("VBA.UCASE$", 1, 1, conversions::ucase_s, "VBA.UCASE$(text)", "VBA UCase$: UCase as a String"),
    FnSpec::value("VBA.LCASE$", 1, 1, conversions::lcase_s, "VBA.LCASE$(text)", "VBA LCase$: LCase as a String"),
    FnSpec::value("VBA.HEX$", 1, 1, conversions::hex_s, "VBA.HEX$(number)", "VBA Hex$: Hex as a String"),
    FnSpec::value("VBA.OCT$", 1, 1, conversions::oct_s, "VBA.OCT$(number)", "VBA Oct$: Oct as a String"),
    FnSpec::value(
        "VBA.FORMAT$",
        1,
        4,
        conversions::format_s,
        "VBA.FORMAT$(value, [format], [firstdayofweek], [firstweekofyear])",
        "VBA Format$: Format as a String",
    ),
    FnSpec::value(
        "VBA.STRING$",
        2,
        2,
        conversions::string_s,
        "VBA.STRING$(number, character)",
        "VBA String$: String as a String",
    ),
];

/// The parameters of a VBA function that pass Null through to its result: bit i for argument i.
type Passes = u8;
/// No parameter passes Null: Null anywhere is run-time error 94.
const NO_NULL: Passes = 0;
/// The first parameter passes Null (`Left`'s string, `Abs`'s number).
const FIRST: Passes = 1;
/// Every parameter passes Null (`String`'s number and character).
const EVERY: Passes = Passes::MAX;

/// VBA's rule for Null among a library call's arguments (each function's page in the Office
/// VBA language reference, and its "Runtime Semantics" in [MS-VBAL] section 6): Null given for a
/// parameter that passes it (`passes`: `Left`'s string, "If string contains Null, Null is
/// returned") makes the result Null; Null for any other (`Left`'s length, `Chr`'s code,
/// `Sqr`'s number) raises run-time error 94, "Invalid use of Null". `None`: no Null.
fn null_argument(ctx: &mut Ctx, name: &str, values: &[Value], passes: Passes) -> Option<XlResult<Value>> {
    let mut nulls = values.iter().enumerate().filter(|(_, v)| matches!(v, Value::Null)).map(|(i, _)| i).peekable();
    nulls.peek()?;
    if nulls.any(|i| i >= Passes::BITS as usize || passes >> i & 1 == 0) {
        return Some(Err(invalid_use_of_null(ctx, name)));
    }
    Some(Ok(Value::Null))
}

/// Type mismatch (run-time error 13) for an array given to a library function of single
/// values in a macro (a several-cell `Range`, whose value is an array, or a Variant holding
/// one: `Abs(Range("A1:A2"))`): VBA's `Abs`, `Sqr`, `CDbl`, `Trim`… take one value ("Type
/// mismatch (Error 13)": "An object was passed to a procedure that is expecting a single
/// property or value"; "Abs function": "The required number argument can be any valid numeric
/// expression", one value, as for Sqr, Int, Fix, Sgn, Exp, Log and the conversions), where a
/// cell's formula works item by item. A one-cell Range is its value, so `Abs(Range("A1"))`
/// still computes.
fn array_argument(ctx: &mut Ctx, name: &str, values: &[Value]) -> Option<XlError> {
    if !ctx.in_macro() || !values.iter().any(|v| matches!(v, Value::Array(_))) {
        return None;
    }
    let why = format_args!("{name} takes a single value, not an array (a Range of several cells)");
    Some(ctx.raise_vba(XlError::Value, 13, errors::message(13, why)))
}

/// Run-time error 94 for a Null where `name` needs a value (`#VALUE!` in a cell).
pub(crate) fn invalid_use_of_null(ctx: &mut Ctx, name: &str) -> XlError {
    ctx.raise_vba(XlError::Value, 94, errors::message(94, format_args!("{name} was given Null")))
}

/// Run-time error 5, "Invalid procedure call or argument", for an argument out of its range
/// (`#VALUE!` in a cell).
pub(crate) fn invalid_call(ctx: &mut Ctx, name: &str, why: &str) -> XlError {
    ctx.raise_vba(XlError::Value, 5, errors::message(5, format_args!("{name}: {why}")))
}

/// `lift` for VBA's functions: the arguments' Nulls as [`null_argument`] says, then `f` on
/// the values (item by item over arrays).
fn lift_vba(
    ctx: &mut Ctx,
    args: &[Expr],
    name: &str,
    passes: Passes,
    f: &dyn Fn(&[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    lift_vba_values(ctx, values, name, passes, f)
}

/// The first argument's date text when a macro holds it as a Date and no format is given
/// (CStr, Str, Format without a format or with "General Date"): "Type conversion functions",
/// CStr of a Date is "a String containing a date in the short date format of your system";
/// `None` otherwise, for the function's own conversion of the `values` of `args`.
fn date_shown(ctx: &Ctx, args: &[Expr], values: &[Value]) -> Option<Value> {
    let plain = match values.get(1) {
        None | Some(Value::Blank) => true,
        Some(Value::Text(t)) => t.is_empty() || t.eq_ignore_ascii_case("general date"),
        Some(_) => false,
    };
    let text = ctx.macro_date_text(args.first()?, values.first()?).filter(|_| plain)?;
    Some(Value::text(text))
}

/// The first argument's every digit when a macro holds it as a LongLong past what a double
/// shows exactly and no format is given (CStr, Str, Format: "LongLong data type", a 64-bit
/// integer), a space before it for its sign's room where `sign_room` ("Str function");
/// `None` otherwise.
fn long_long_shown(ctx: &Ctx, args: &[Expr], values: &[Value], sign_room: bool) -> Option<Value> {
    if !matches!(values.get(1), None | Some(Value::Blank)) {
        return None;
    }
    let text = ctx.macro_long_long_text(args.first()?, values.first()?)?;
    Some(Value::text(if sign_room && !text.starts_with('-') { format!(" {text}") } else { text }))
}

/// `Format(x, code)` of a macro's LongLong that no double holds (past 2^53): its every digit
/// laid out by a code of digit placeholders and thousand separators ("Format function":
/// `0` a digit or a zero, `#` a digit or nothing, `,` between them groups the thousands).
/// Any other code would lay out the nearest double's digits: Overflow (run-time error 6)
/// instead of another number. `None` for any other value, formatted as usual.
fn long_long_formatted(ctx: &Ctx, args: &[Expr], values: &[Value], raised: &Raised) -> Option<XlResult<Value>> {
    let Some(Value::Text(code)) = values.get(1) else { return None };
    let digits = ctx.macro_long_long_text(args.first()?, values.first()?)?;
    let k: i64 = digits.parse().ok()?;
    if i128::from(k) == k as f64 as i128 {
        return None;
    }
    Some(match integer_layout(&digits, code) {
        Some(shown) => Ok(Value::text(shown)),
        None => Err(raised.set(6, "a LongLong past 2^53 is formatted with a code of 0, # and , alone")),
    })
}

/// The whole number `digits` (a sign, then its digits) laid out by `code` when the code is
/// digit placeholders (`0`, `#`) with thousand separators (`,`) between them; `None` for
/// any other code (a trailing `,` scales by a thousand; sections, decimals, literals).
fn integer_layout(digits: &str, code: &str) -> Option<String> {
    let placeholders = code.chars().filter(|c| matches!(c, '0' | '#')).count();
    if placeholders == 0 || code.ends_with(',') || !code.chars().all(|c| matches!(c, '0' | '#' | ',')) {
        return None;
    }
    let (sign, digits) = digits.strip_prefix('-').map_or(("", digits), |d| ("-", d));
    let zeros = code.chars().filter(|&c| c == '0').count();
    let padded = format!("{digits:0>zeros$}");
    if !code.contains(',') {
        return Some(format!("{sign}{padded}"));
    }
    let mut grouped = String::with_capacity(padded.len() + padded.len() / 3 + 1);
    for (i, digit) in padded.chars().enumerate() {
        if i > 0 && (padded.len() - i) % 3 == 0 {
            grouped.push(',');
        }
        grouped.push(digit);
    }
    Some(format!("{sign}{grouped}"))
}

/// [`lift_vba`] on values already evaluated. A library function reads its texts whole
/// (`CDbl`, `Val` or `Trim` of 16 million spaces answer a number or a short text): they count
/// against a macro's statement limit ([`Ctx::charge_texts`]), as the text it makes does.
fn lift_vba_values(
    ctx: &mut Ctx,
    values: Vec<Value>,
    name: &str,
    passes: Passes,
    f: &dyn Fn(&[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    ctx.charge_texts(&values);
    lift_vba_reading_part(ctx, values, name, passes, f)
}

/// [`lift_vba_values`] of a function that reads only a part of its text, whatever its length
/// (`Left`, `Right`, `Mid`, `Asc`): what it reads is counted by the function.
fn lift_vba_reading_part(
    ctx: &mut Ctx,
    values: Vec<Value>,
    name: &str,
    passes: Passes,
    f: &dyn Fn(&[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    if let Some(refused) = array_argument(ctx, name, &values) {
        return Err(refused);
    }
    if let Some(result) = null_argument(ctx, name, &values, passes) {
        return result;
    }
    let lifted = lift_values(&values, f);
    explain_lifted_size(ctx, &values, &lifted);
    lifted
}

/// A function of one number, after VBA's rule for a Null argument; a number outside the
/// function's domain (`Err(why)`: `Sqr(-1)`, `Log(0)`) is run-time error 5, "Invalid
/// procedure call or argument", as the function's page says.
fn number_fn(
    ctx: &mut Ctx,
    args: &[Expr],
    name: &str,
    passes: Passes,
    f: fn(f64) -> Result<f64, &'static str>,
) -> XlResult<Value> {
    let v = match ctx.leaf_number(&args[0]) {
        Some(x) => Value::Number(x),
        None => ctx.eval(&args[0]),
    };
    number_fn_of(ctx, v, name, passes, f)
}

/// [`number_fn`] of the argument's value `v`, already evaluated.
fn number_fn_of(
    ctx: &mut Ctx,
    v: Value,
    name: &str,
    passes: Passes,
    f: fn(f64) -> Result<f64, &'static str>,
) -> XlResult<Value> {
    let raised = Raised::default();
    // A result past a Double's range is VBA's Overflow (error 6), as `Exp(710)` is.
    let apply = |x: f64| match f(x) {
        Ok(y) if !y.is_finite() => Err(raised.set(6, "the result is past a Double's range")),
        Ok(y) => Ok(number_result(y)),
        Err(why) => Err(raised.set(5, why)),
    };
    // A number, the usual case, needs neither the Null rule nor lifting.
    let result = match v {
        Value::Number(x) => apply(x),
        v => {
            if let Some(refused) = array_argument(ctx, name, std::slice::from_ref(&v)) {
                return Err(refused);
            }
            if let Some(result) = null_argument(ctx, name, std::slice::from_ref(&v), passes) {
                return result;
            }
            // The argument is read as VBA's conversions read it (a Double parameter's Let
            // coercion, [MS-VBAL] 5.5.1.2.1): `Int("&H10")` is 16, `Sqr("1D2")` 10, `Sgn(True)` -1,
            // and a String that is no number is Type mismatch (error 13), where the sheet's
            // reading gave #VALUE! as the function's value.
            let v = ctx.locale().numbers_for_arithmetic(v, ctx.dates());
            lift_values(&[v], &|v| apply(raised.number(&v[0])?))
        }
    };
    raised.raise(ctx, name, result)
}

// "Abs function", "Int, Fix functions": "If number contains Null, Null is returned"; [MS-VBAL]'s
// Sgn page declares its number and its result Variants. The others take a Double.
fn abs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let v = match ctx.leaf_number(&args[0]) {
        Some(x) => Value::Number(x),
        None => ctx.eval(&args[0]),
    };
    // "Abs function": the result has the argument's type, so in a macro the absolute value
    // of the smallest Integer, Long or LongLong overflows (run-time error 6) as `-x` does.
    // Above -32,768 no type's negation can overflow: nothing to ask.
    let negated = matches!(v, Value::Number(x) if x <= -32768.0);
    let result = number_fn_of(ctx, v, "Abs", FIRST, |x| Ok(x.abs()))?;
    Ok(if negated { ctx.macro_negation(&args[0], result) } else { result })
}

/// "Int, Fix functions": the whole part, of a macro's Decimal too when it has more digits
/// than a double gives back (`Int(CDec(10.5) * 10 ^ 20 + 0.5)`: the Decimal's own digits,
/// [`Ctx::macro_decimal_whole`]).
fn int(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    whole_part(ctx, args, "Int", true)
}

fn fix(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    whole_part(ctx, args, "Fix", false)
}

fn whole_part(ctx: &mut Ctx, args: &[Expr], name: &str, floor: bool) -> XlResult<Value> {
    let f: fn(f64) -> Result<f64, &'static str> = if floor { |x| Ok(x.floor()) } else { |x| Ok(x.trunc()) };
    let v = ctx.eval(&args[0]);
    if let Some(n) = ctx.macro_decimal_whole(&args[0], &v, floor) {
        return Ok(Value::Number(n));
    }
    number_fn_of(ctx, v, name, FIRST, f)
}

fn sgn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Sgn", FIRST, |x| Ok(if x == 0.0 { 0.0 } else { x.signum() }))
}

/// "RGB function": the colour red + green·256 + blue·65536 as a Long (`Interior.Color`);
/// each part an Integer ("a value … that exceeds 255 is assumed to be 255"), below zero an
/// invalid argument (run-time error 5).
fn rgb(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let dates = ctx.dates();
    let result = lift_vba(ctx, args, "RGB", NO_NULL, &|v| {
        let mut colour = 0.0;
        for (i, part) in v.iter().enumerate() {
            let part = to_number(part, dates)?.round_ties_even();
            if part < 0.0 {
                return Err(raised.set(5, "a colour part below zero"));
            }
            colour += part.min(255.0) * 256f64.powi(i as i32);
        }
        Ok(Value::Number(colour))
    });
    raised.raise(ctx, "RGB", result)
}

fn atn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Atn", NO_NULL, |x| Ok(x.atan()))
}

fn cos(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Cos", NO_NULL, |x| Ok(x.cos()))
}

fn sin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Sin", NO_NULL, |x| Ok(x.sin()))
}

fn tan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Tan", NO_NULL, |x| Ok(x.tan()))
}

fn exp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Exp", NO_NULL, |x| Ok(x.exp()))
}

// "Log function": number "greater than zero"; "Sqr function": "greater than or equal to zero".
fn log(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Log", NO_NULL, |x| if x > 0.0 { Ok(x.ln()) } else { Err("the number is not above zero") })
}

fn sqr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    number_fn(ctx, args, "Sqr", NO_NULL, |x| if x < 0.0 { Err("the number is below zero") } else { Ok(x.sqrt()) })
}

fn array(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let items = args.iter().map(|a| ctx.eval(a).unwrap_single()).collect();
    Ok(Value::from(crate::eval::value::Array::row(items)))
}

/// "Round function": a negative number of decimal places, or one above 22, is run-time error
/// 5. A macro's Decimal or Currency rounds its own digits to even (`round_decimal_text`): both
/// are scaled integers ("Decimal data type", "Currency data type"), so `Round(CCur(1.015), 2)`
/// is a tie that goes to 1.02, where the double 1.015 lies below the tie.
fn round(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    let exact = args.first().zip(values.first()).and_then(|(e, v)| ctx.macro_long_long_text(e, v));
    let raised = Raised::default();
    let result = lift_vba_values(ctx, values, "Round", FIRST, &|v| {
        let x = vba_number(&v[0])?;
        let digits = match v.get(1) {
            None | Some(Value::Blank) => 0.0,
            Some(d) => vba_number(d)?,
        };
        if digits.trunc() < 0.0 {
            return Err(raised.set(5, "the number of decimal places is below zero"));
        }
        // A Decimal has at most 28 places, a Currency 4: more leave it as it is.
        if let Some(t) = exact.as_deref() {
            let places = digits.trunc().min(f64::from(u32::MAX)) as u32;
            return Ok(Value::Number(round_decimal_text(t, places).unwrap_or(x)));
        }
        // Past 22 places (10^22 is the last power of ten a Double holds exactly, so the scaling
        // below would no longer be exact) the place count is out of range: error 5, "Invalid
        // procedure call or argument", as for a negative count, rather than a guessed number.
        if digits.trunc() > 22.0 {
            return Err(raised.set(5, "the number of decimal places is above 22"));
        }
        let scale = 10f64.powi(digits.trunc() as i32);
        Ok(number_result((x * scale).round_ties_even() / scale))
    });
    raised.raise(ctx, "Round", result)
}

/// `Round` of a macro's Decimal, written `text`, to `digits` places: its digits rounded, halves
/// to even ("Round function"), so the Decimal 2.345 is a tie and gives 2.34, where the Double
/// 2.345 times 100 is 234.50000000000003 and gives 2.35. `None` when it has no more places.
fn round_decimal_text(text: &str, digits: u32) -> Option<f64> {
    let negative = text.starts_with('-');
    let body = text.trim_start_matches('-');
    let (whole, fraction) = body.split_once('.').unwrap_or((body, ""));
    let places = u32::try_from(fraction.len()).ok()?;
    if places <= digits {
        return None;
    }
    let mantissa: i128 = format!("{whole}{fraction}").parse().ok()?;
    let dropped = 10_i128.checked_pow(places - digits)?;
    let (mut kept, rest) = (mantissa / dropped, mantissa % dropped);
    if rest * 2 > dropped || (rest * 2 == dropped && kept % 2 == 1) {
        kept += 1;
    }
    format!("{}{kept}e-{digits}", if negative { "-" } else { "" }).parse().ok()
}

/// VBA's conversion to a whole number: halves to even; out of range VBA's Overflow, run-time
/// error 6 ("Type conversion functions": "If the expression passed to the function is outside
/// the range of the data type being converted to, an error occurs"), `#NUM!` in a cell.
fn whole(ctx: &mut Ctx, args: &[Expr], name: &str, limit: f64) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, name, NO_NULL, &|v| {
        let r = raised.number(&v[0])?.round_ties_even();
        if r < -limit - 1.0 || r > limit {
            return Err(raised.set(6, "the number is past the range of its type"));
        }
        Ok(Value::Number(r))
    });
    raised.raise(ctx, name, result)
}

fn cint(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    whole(ctx, args, "CInt", 32767.0)
}

fn clng(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    whole(ctx, args, "CLng", 2147483647.0)
}

fn cdbl(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "CDbl", NO_NULL, &|v| Ok(number_result(raised.number(&v[0])?)));
    raised.raise(ctx, "CDbl", result)
}

/// `CBool(value)` ("Type conversion functions"): [`vba_bool`], a String that is neither
/// "True"/"False" nor a number being Type mismatch, error 13.
fn cbool(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "CBool", NO_NULL, &|v| match (&v[0], vba_bool(&v[0])) {
        (Value::Text(_), Err(_)) => Err(raised.set(13, "a String that is neither True, False nor a number")),
        (_, b) => Ok(Value::Bool(b?)),
    });
    raised.raise(ctx, "CBool", result)
}

/// A value Let-coerced to Boolean ([MS-VBAL] 5.5.1.2.2): a String is "True" or "False" or
/// a number, True when not 0 (`CBool("1")` is True, `CBool("0")` False), where the formula
/// language's TRUE/FALSE text alone was read.
pub fn vba_bool(v: &Value) -> XlResult<bool> {
    match v {
        Value::Text(t) => to_bool(v).or_else(|e| vba_number_text(t).map(|n| n != 0.0).ok_or(e)),
        other => to_bool(other),
    }
}

/// A value as VBA's CStr writes it: `True`/`False` in VBA's spelling, numbers to 15 digits
/// in VBA's own notation ([`vba_number_shown`]).
pub fn vba_text(v: &Value) -> XlResult<Rc<str>> {
    match v {
        Value::Bool(b) => Ok(if *b { "True" } else { "False" }.into()),
        Value::Number(n) => Ok(vba_number_shown(*n, false).into()),
        other => to_text(other),
    }
}

/// A Double (15 significant digits) or a Single (7) as VBA writes it, the one text of a
/// number for CStr, Str, `&`, Print and a String variable: `1.5E-07`, `1E+15`
/// (OLE Automation's VarBstrFromR8 and VarBstrFromR4, C's `%.15G` and `%.7G`).
pub fn vba_number_shown(n: f64, single: bool) -> String {
    crate::eval::format::number_format::vba_general(n, if single { 7 } else { 15 })
}

/// The text a macro's number `v`, the value of `e`, is let-coerced to where VBA's library
/// takes a String ([MS-VBAL] 5.5.1.2.4, Let-coercion to String): a Date its date text, a
/// LongLong, Decimal or Currency its every digit, a Single its seven significant digits, as
/// CStr writes each (`Replace(Rnd(), ".", "")` is "07055475", `Left(d, 3)` of the Date
/// 1/2/2024 "1/2"); `None` for a Double, whose text is [`vba_text`]'s, for any other value,
/// and in a cell.
pub(super) fn held_text(ctx: &Ctx, e: &Expr, v: &Value) -> Option<String> {
    if !matches!(v, Value::Number(_)) {
        return None;
    }
    ctx.macro_date_text(e, v)
        .or_else(|| ctx.macro_long_long_text(e, v))
        .or_else(|| ctx.macro_shown_number(e, v).map(|n| vba_number_shown(n, true)))
}

/// The value of `e`, an argument a library function takes as a String: a macro's Date,
/// Single, LongLong, Decimal or Currency as its text ([`held_text`]), any other value as it is.
pub(super) fn text_argument(ctx: &mut Ctx, e: &Expr) -> Value {
    let v = ctx.eval(e);
    held_text(ctx, e, &v).map_or(v, Value::text)
}

/// The arguments' values, the first as a macro shows it ([`Ctx::macro_shown_number`]: a
/// Single to seven significant digits), and whether it is a Single.
fn shown_values(ctx: &mut Ctx, args: &[Expr]) -> (Vec<Value>, bool) {
    let mut values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    let mut single = false;
    if let (Some(e), Some(v)) = (args.first(), values.first_mut()) {
        if let Some(n) = ctx.macro_shown_number(e, v) {
            *v = Value::Number(n);
            single = true;
        }
    }
    (values, single)
}

fn cstr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (values, single) = shown_values(ctx, args);
    if let Some(shown) = date_shown(ctx, args, &values).or_else(|| long_long_shown(ctx, args, &values, false)) {
        return Ok(shown);
    }
    if let Some(text) = strings::error_text(&values) {
        return Ok(text);
    }
    if let (true, [Value::Number(n)]) = (single, values.as_slice()) {
        return Ok(Value::text(vba_number_shown(*n, true)));
    }
    lift_vba_values(ctx, values, "CStr", NO_NULL, &|v| Ok(Value::Text(vba_text(&v[0])?)))
}

/// `Str(number)`; a Date shows as CStr shows it, without the sign's space.
fn str_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (values, single) = shown_values(ctx, args);
    if let Some(shown) = date_shown(ctx, args, &values).or_else(|| long_long_shown(ctx, args, &values, true)) {
        return Ok(shown);
    }
    lift_vba_values(ctx, values, "Str", NO_NULL, &|v| {
        let n = vba_number(&v[0])?;
        let text = without_units_zero(vba_number_shown(n, single));
        Ok(Value::text(if n >= 0.0 { format!(" {text}") } else { text }))
    })
}

/// Str shows a number between -1 and 1 without its units' zero (`Str(0.1)` is " .1",
/// `Str(-0.5)` "-.5"), as BASIC's PRINT did; CStr keeps it ("0.1"). LibreOffice drops the
/// zero in VBA mode only, to match Excel's VBA.
fn without_units_zero(text: String) -> String {
    match text.strip_prefix("-0.").or_else(|| text.strip_prefix("0.")) {
        Some(fraction) => format!("{}.{fraction}", if text.starts_with('-') { "-" } else { "" }),
        None => text,
    }
}

fn iif(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // Unlike IF, VBA's IIf evaluates both branches before choosing.
    let condition = to_bool(&ctx.eval(&args[0]))?;
    let then = ctx.eval(&args[1]);
    let otherwise = ctx.eval(&args[2]);
    let (index, chosen) = if condition { (1, then) } else { (2, otherwise) };
    ctx.macro_chose(args, index, &chosen);
    Ok(chosen)
}

/// Applies a text function to the text of each argument (lifted over arrays), after VBA's
/// rule for Null arguments ([`null_argument`]).
fn text_fn(
    ctx: &mut Ctx,
    args: &[Expr],
    name: &str,
    passes: Passes,
    f: &dyn Fn(&str, &[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    text_fn_reading(ctx, args, name, passes, Reads::Whole, f)
}

/// How much of its text a text function reads: its work counts against a macro's statement
/// limit, so `Trim` of a long text in a loop stops within the limit's time.
#[derive(Clone, Copy, PartialEq)]
enum Reads {
    Whole,
    /// A part bounded by the other arguments (`Left(s, 1)`), counted by the function itself.
    Part,
}

/// [`text_fn`] of a function reading `reads` of its text.
fn text_fn_reading(
    ctx: &mut Ctx,
    args: &[Expr],
    name: &str,
    passes: Passes,
    reads: Reads,
    f: &dyn Fn(&str, &[Value]) -> XlResult<Value>,
) -> XlResult<Value> {
    // A macro's text growing in place (`s = s & …`) is read where it is, not copied: a loop
    // reading `Right(s, 1)` between appends copied the whole text at every turn.
    if let Some(Expr { kind: ExprKind::Name(variable), .. }) = args.first() {
        if let Some(text) = ctx.host_growing_text(variable) {
            let rest: Vec<Value> = args[1..].iter().map(|a| ctx.eval(a)).collect();
            if reads == Reads::Whole {
                ctx.charge_read(text.len());
            }
            if rest.iter().all(|v| matches!(v, Value::Number(_) | Value::Text(_) | Value::Bool(_))) {
                return f(text.as_str(), &rest);
            }
            let values = std::iter::once(Value::text(text.as_str())).chain(rest).collect();
            return lift_vba_reading_part(ctx, values, name, passes, &|v| f(&vba_text(&v[0])?, &v[1..]));
        }
    }
    let values: Vec<Value> =
        (args.iter().enumerate()).map(|(i, a)| if i == 0 { text_argument(ctx, a) } else { ctx.eval(a) }).collect();
    let lift = match reads {
        Reads::Whole => lift_vba_values,
        Reads::Part => lift_vba_reading_part,
    };
    lift(ctx, values, name, passes, &|v| f(&vba_text(&v[0])?, &v[1..]))
}

/// A count argument (lengths, positions): a whole number; below zero run-time error 5 (the
/// pages of Left, Right, Mid and Space: "Invalid procedure call or argument"), `#VALUE!` in a cell.
fn count(raised: &Raised, v: &Value) -> XlResult<usize> {
    let n = vba_number(v)?.trunc();
    if n < 0.0 {
        return Err(raised.set(5, "a length below zero"));
    }
    Ok(n.min(u32::MAX as f64) as usize)
}

/// A text function's body that notes run-time errors in the `Raised` it is given: the text,
/// the other arguments.
type CheckedTextBody<'f> = &'f dyn Fn(&Raised, &str, &[Value]) -> XlResult<Value>;

/// [`text_fn`] whose `f` notes run-time errors in the `Raised` it is given, for the functions
/// reading a part of their text (`Left`, `Right`, `Mid`: what they take is counted as made).
fn checked_text_fn(ctx: &mut Ctx, args: &[Expr], name: &str, f: CheckedTextBody) -> XlResult<Value> {
    let raised = Raised::default();
    let result = text_fn_reading(ctx, args, name, FIRST, Reads::Part, &|s, rest| f(&raised, s, rest));
    raised.raise(ctx, name, result)
}

fn len(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // A text growing in place answers without being copied (`Do While Len(s) < n: s = s & …`).
    if let [Expr { kind: ExprKind::Name(name), .. }] = args {
        if let Some(chars) = ctx.host_text_length(name) {
            return Ok(Value::Number(chars as f64));
        }
    }
    text_fn(ctx, args, "Len", FIRST, &|s, _| Ok(Value::Number(s.chars().count() as f64)))
}

fn left(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    checked_text_fn(ctx, args, "Left", &|raised, s, rest| {
        Ok(Value::text(s.chars().take(count(raised, &rest[0])?).collect::<String>()))
    })
}

fn right(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    checked_text_fn(ctx, args, "Right", &|raised, s, rest| {
        let n = count(raised, &rest[0])?;
        // Counted from the end: the work is the part taken, not the whole text.
        let start = if n == 0 { s.len() } else { s.char_indices().rev().nth(n - 1).map_or(0, |(at, _)| at) };
        Ok(Value::text(&s[start..]))
    })
}

/// "Mid function": a start of 0 or below, or a negative length, is run-time error 5.
fn mid(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let has_length = args.get(2).is_some_and(|e| e.kind != ExprKind::Missing);
    // A macro's text growing in place knows its length in characters; taken before the other
    // arguments run, so only when they run no macro code (which could change the text).
    let runs_macro_code = |e: &Expr| {
        let mut found = false;
        e.visit(&mut |e| found |= matches!(e.kind, ExprKind::Host(id) if ctx.host_may_run_code(id)));
        found
    };
    let chars = match args {
        [Expr { kind: ExprKind::Name(name), .. }, rest @ ..] if !rest.iter().any(runs_macro_code) => {
            ctx.host_text_length(name)
        }
        _ => None,
    };
    let scanned = std::cell::Cell::new(0);
    let result = checked_text_fn(ctx, args, "Mid", &|raised, s, rest| {
        let start = count(raised, &rest[0])?;
        if start == 0 {
            return Err(raised.set(5, "start is below 1"));
        }
        let length = if has_length { count(raised, &rest[1])? } else { usize::MAX };
        let (from, work) = char_start(s, start - 1, chars);
        scanned.set(scanned.get() + work);
        let part = &s[from..];
        let end = part.char_indices().nth(length).map_or(part.len(), |(at, _)| at);
        Ok(Value::text(&part[..end]))
    });
    // Finding the start is work in the characters skipped: `c = Mid(s, i, 1)` over a text of
    // millions of characters, charged nothing, ran for hours within the statement limit.
    ctx.charge(scanned.get());
    result
}

/// Bytes checked for ASCII a unit of work stands for: checked a word at a time, about 64
/// times faster than the characters stepped one by one that a unit of 16 bytes stands for
/// elsewhere (`Ctx::charge_read`).
const ASCII_BYTES_PER_UNIT: usize = 1024;

/// The byte where character `skip` (0-based) of `s` starts (`s.len()` past its end), in work
/// bounded by the part skipped, not by counting characters one by one from the start: a
/// `For i = 1 To Len(s): c = Mid(s, i, 1)` loop over a long text was quadratic in characters
/// stepped. An ASCII prefix is its own byte count (checked a word at a time); with the text's
/// length in characters known (`chars`), a character in its second half is found from the end.
/// Also the work it took, in [`Ctx::charge`]'s units (a character stepped is a byte read).
fn char_start(s: &str, skip: usize, chars: Option<usize>) -> (usize, usize) {
    let stepped = |bytes: usize| bytes / 16;
    match chars {
        Some(total) if skip >= total => return (s.len(), 0),
        Some(total) if skip > total / 2 => {
            let at = s.char_indices().rev().nth(total - skip - 1).map_or(0, |(at, _)| at);
            return (at, stepped(s.len() - at));
        }
        _ => {}
    }
    let checked = skip.min(s.len()) / ASCII_BYTES_PER_UNIT;
    if s.as_bytes().get(..skip).is_some_and(<[u8]>::is_ascii) {
        return (skip, checked);
    }
    let at = s.char_indices().nth(skip).map_or(s.len(), |(at, _)| at);
    (at, checked + stepped(at))
}

fn ucase(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    text_fn(ctx, args, "UCase", FIRST, &|s, _| Ok(Value::text(s.to_uppercase())))
}

fn lcase(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    text_fn(ctx, args, "LCase", FIRST, &|s, _| Ok(Value::text(s.to_lowercase())))
}

fn trim(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    text_fn(ctx, args, "Trim", FIRST, &|s, _| Ok(Value::text(s.trim_matches(' '))))
}

fn ltrim(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    text_fn(ctx, args, "LTrim", FIRST, &|s, _| Ok(Value::text(s.trim_start_matches(' '))))
}

fn rtrim(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    text_fn(ctx, args, "RTrim", FIRST, &|s, _| Ok(Value::text(s.trim_end_matches(' '))))
}

/// "Chr function" ([MS-VBAL] 6.1.2, the Strings module's Chr): the character of a code 0 to
/// 255 in the code page of a Western Excel, Windows-1252 (0 to 127 ASCII; 128 "€"); a code
/// outside 0 to 255 is run-time error 5, as in a single-byte code page (ChrW takes Unicode).
fn chr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "Chr", NO_NULL, &|v| {
        let code = vba_number(&v[0])?.trunc();
        if !(0.0..=255.0).contains(&code) {
            return Err(raised.set(5, "the character code is outside 0 to 255 (ChrW takes Unicode codes)"));
        }
        let byte = [code as u8];
        let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(&byte);
        Ok(Value::text(text.into_owned()))
    });
    raised.raise(ctx, "Chr", result)
}

/// "Asc function": the code of the first character in Windows-1252, Chr's code page (63,
/// "?", for a character that code page has not, as Windows converts it); "If the string
/// contains no characters, a run-time error occurs" (error 5).
fn asc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = text_fn_reading(ctx, args, "Asc", NO_NULL, Reads::Part, &|s, _| {
        let c = s.chars().next().ok_or_else(|| raised.set(5, "the text is empty"))?;
        let mut unit = [0u8; 4];
        let (bytes, _, unmappable) = encoding_rs::WINDOWS_1252.encode(c.encode_utf8(&mut unit));
        let code = if unmappable { b'?' } else { bytes[0] };
        Ok(Value::Number(f64::from(code)))
    });
    raised.raise(ctx, "Asc", result)
}

/// AscW ("Asc function": "The AscW function returns the Unicode character code"): the UTF-16
/// code of the first character, ChrW's inverse, as the Integer Asc returns: a unit past 32767
/// reads as a negative Integer (U+FFFF is -1), and a character past U+FFFF gives its first
/// (high surrogate) unit; empty text is error 5, as for Asc.
fn ascw(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = text_fn_reading(ctx, args, "AscW", NO_NULL, Reads::Part, &|s, _| {
        let unit = s.encode_utf16().next().ok_or_else(|| raised.set(5, "the text is empty"))?;
        Ok(Value::Number(f64::from(unit as i16)))
    });
    raised.raise(ctx, "AscW", result)
}

fn space(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // Space(1e9) is refused before it is built, not cut to a shorter string.
    let limit = ctx.text_limit();
    let over = std::cell::Cell::new(false);
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "Space", NO_NULL, &|v| match count(&raised, &v[0])? {
        n if n > limit => {
            over.set(true);
            Err(XlError::Value)
        }
        n => Ok(Value::text(" ".repeat(n))),
    });
    if over.get() {
        return Err(ctx.text_over_limit());
    }
    raised.raise(ctx, "Space", result)
}

fn is_empty(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(ctx.eval(&args[0]).unwrap_single().is_blank()))
}

fn is_null(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(matches!(ctx.eval(&args[0]).unwrap_single(), Value::Null)))
}

fn is_error(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(ctx.eval(&args[0]).unwrap_single().as_error().is_some()))
}

fn is_object(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(matches!(ctx.operand(&args[0]), Operand::Ref(..))))
}

/// VBA's IsNumeric: numbers and number text; date text is not numeric there (IsDate's).
fn is_numeric(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let value = ctx.eval(&args[0]).unwrap_single();
    // The text is read whole (16 million spaces before a digit).
    ctx.charge_texts(std::slice::from_ref(&value));
    Ok(Value::Bool(match value {
        // "IsNumeric function": "IsNumeric returns False if expression is a date expression".
        v @ Value::Number(_) => ctx.macro_date_text(&args[0], &v).is_none(),
        Value::Bool(_) | Value::Blank => true,
        Value::Text(t) => vba_number_text(&t).is_some(),
        _ => false,
    }))
}

/// A number past a Double's range (`Val("1e400")`) is Overflow, run-time error 6 (the Val
/// function's reference, "Exceptions": OverflowException, error number 6, "InputStr is too
/// large"), where it was `#NUM!` handed on as a value.
fn val(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = text_fn(ctx, args, "Val", NO_NULL, &|s, _| match vba_val(s) {
        n if n.is_finite() => Ok(Value::Number(n)),
        _ => Err(raised.set(6, "the number is past a Double's range")),
    });
    raised.raise(ctx, "Val", result)
}

/// VBA's Val: spaces anywhere are ignored, and the longest leading piece that reads as a
/// number is the result (`Val(" 1 2.5mm")` is 12.5, `Val("x")` is 0).
pub fn vba_val(text: &str) -> f64 {
    let s: String = text.chars().filter(|c| !matches!(c, ' ' | '\t' | '\n' | '\r')).collect();
    if let Some(n) = radix_val(&s) {
        return n;
    }
    let b = s.as_bytes();
    let mut i = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let digits = |i: &mut usize| {
        let start = *i;
        while *i < b.len() && b[*i].is_ascii_digit() {
            *i += 1;
        }
        *i > start
    };
    let mut any = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        any |= digits(&mut i);
    }
    if !any {
        return 0.0;
    }
    let mantissa_end = i;
    if matches!(b.get(i), Some(b'e' | b'E' | b'd' | b'D')) {
        let mut j = i + 1 + usize::from(matches!(b.get(i + 1), Some(b'+' | b'-')));
        if digits(&mut j) {
            i = j;
        }
    }
    let piece = s[..i].replace(['d', 'D'], "e");
    piece.parse().or_else(|_| s[..mantissa_end].parse()).unwrap_or(0.0)
}

/// A value as VBA reads it as a number (the C… conversions, IsNumeric, a String assigned to
/// a numeric variable): a String is read as `VarR8FromStr` reads it under en-US ("Type
/// conversion functions": "CDbl … recognize … different decimal separators, thousands
/// separators and currency options"), with what VBA adds to the sheet's reading: an exponent
/// written with D (`"1d2"`, 100, as a Double literal may be: [MS-VBAL] 3.3.2) and a whole
/// text in hexadecimal or octal (`"&H10"`, 16; `"&O17"`, 15: the literals of [MS-VBAL]
/// 3.3.2). Dates in text stay numbers of days, as CDbl reads them.
pub fn vba_number(v: &Value) -> XlResult<f64> {
    match v {
        Value::Text(t) => vba_number_text(t).map_or_else(|| to_number(v, VBA_DATES), Ok),
        // [MS-VBAL] 5.5.1.2.1: True let-coerced to a number is -1 (the sheet's TRUE is 1).
        Value::Bool(b) => Ok(if *b { -1.0 } else { 0.0 }),
        other => to_number(other, VBA_DATES),
    }
}

/// A String that VBA reads as a number without being a date: [`vba_number`]'s reading, and
/// what IsNumeric accepts.
pub fn vba_number_text(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.starts_with('&') {
        return whole_radix_literal(t);
    }
    parse_plain_number(t).or_else(|| parse_plain_number(&d_exponent_as_e(t)?))
}

/// `&H…`/`&O…` when the whole text is one such literal (`Val` reads a leading one only).
fn whole_radix_literal(t: &str) -> Option<f64> {
    let digits = t.strip_prefix('&')?;
    let digits = digits.get(1..).filter(|_| digits.starts_with(['h', 'H', 'o', 'O'])).unwrap_or(digits);
    let radix = if t[1..].starts_with(['h', 'H']) { 16 } else { 8 };
    (!digits.is_empty() && digits.chars().all(|c| c.is_digit(radix))).then(|| radix_val(t)).flatten()
}

/// `1d2` as `1E2`: the one D of a number's exponent, between its mantissa and exponent digits.
fn d_exponent_as_e(t: &str) -> Option<String> {
    let at = t.find(['d', 'D'])?;
    let before = t[..at].chars().last()?;
    let after = t[at + 1..].chars().next()?;
    let fits = (before.is_ascii_digit() || before == '.') && (after.is_ascii_digit() || matches!(after, '+' | '-'));
    fits.then(|| format!("{}E{}", &t[..at], &t[at + 1..]))
}

/// Val of `&HFF` (hexadecimal) or `&O17` / `&17` (octal): the digits that follow, read as an
/// Integer up to 16 bits and a Long up to 32, signed as VBA's (`Val("&HFFFF")` is -1).
fn radix_val(s: &str) -> Option<f64> {
    let rest = s.strip_prefix('&')?;
    let (radix, digits) = match rest.as_bytes().first()? {
        b'h' | b'H' => (16, &rest[1..]),
        b'o' | b'O' => (8, &rest[1..]),
        _ => (8, rest),
    };
    let end = digits.find(|c: char| !c.is_digit(radix)).unwrap_or(digits.len());
    let n = u64::from_str_radix(&digits[..end], radix).ok()?;
    Some(match n {
        0..=0xFFFF => n as u16 as i16 as f64,
        0x1_0000..=0xFFFF_FFFF => n as u32 as i32 as f64,
        _ => n as f64,
    })
}

/// Format's user-defined string formats (`@`, `&`, `<`, `>`, `!`: [`strings::format_string`]),
/// which show any value as its text: `Format(5, "@@@")` is "  5".
fn case_format(pattern: &str) -> Option<impl Fn(&str) -> String + '_> {
    strings::is_string_format(pattern).then_some(move |text: &str| strings::format_string(text, pattern))
}

/// `Format(expression[, format[, firstdayofweek[, firstweekofyear]]])` ("Format function"):
/// the week arguments number a date format's `w` and `ww` as DatePart's do.
fn format(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = format_by_weeks(ctx, args, &raised);
    raised.raise(ctx, "Format", result)
}

fn format_by_weeks(ctx: &mut Ctx, args: &[Expr], raised: &Raised) -> XlResult<Value> {
    let has_format = args.get(1).is_some_and(|e| e.kind != ExprKind::Missing);
    let values = if has_format { args.iter().map(|a| ctx.eval(a)).collect() } else { shown_values(ctx, args).0 };
    // The text and its format are read whole however short the result (100,000 `#` format 1
    // as "1").
    ctx.charge_texts(&values);
    // "Format function": a Date without a format shows as General Date, the short date
    // and the long time as the system sets them.
    if let Some(shown) = date_shown(ctx, args, &values).or_else(|| long_long_shown(ctx, args, &values, false)) {
        return Ok(shown);
    }
    if let Some(shown) = long_long_formatted(ctx, args, &values, raised) {
        return shown;
    }
    if let Some(refused) = array_argument(ctx, "Format", &values) {
        return Err(refused);
    }
    let lifted = lift_values(&values, &|v| {
        // "Returning strings from functions": the Variant Format lets Null propagate through
        // it, where Format$, which returns a String, raises error 94.
        if v[0] == Value::Null {
            return Ok(Value::Null);
        }
        let pattern = if has_format { vba_text(&v[1])? } else { Rc::from("") };
        if let Some(convert) = case_format(&pattern) {
            return Ok(Value::text(convert(&vba_text(&v[0])?)));
        }
        let number = match &v[0] {
            Value::Number(n) => *n,
            Value::Blank => return Ok(Value::text("")),
            Value::Error(e) => return Err(*e),
            other => match vba_number(other) {
                Ok(n) if !matches!(other, Value::Bool(_)) => n,
                _ => return Ok(Value::Text(vba_text(other)?)),
            },
        };
        let (first, rule) = calendar::week_arguments(raised, v, 2)?;
        Ok(Value::text(format_number_by_weeks(number, &pattern, &calendar::week_numbers(first, rule))?))
    });
    explain_lifted_size(ctx, &values, &lifted);
    lifted
}

/// A number in a VBA/Excel number format: VBA's named formats (`Fixed`, `Standard`,
/// `Percent`, `Scientific`, `General Number`, `Currency`, `Yes/No`, `True/False`, `On/Off`,
/// `General Date`, `Long Date` … `Short Time`) or any pattern Excel's TEXT reads — the one
/// number-format engine of `text_format.rs`.
pub fn format_number(n: f64, pattern: &str) -> XlResult<String> {
    format_number_by_weeks(n, pattern, &calendar::default_week_numbers())
}

/// [`format_number`] with a date format's `w` and `ww` numbered by `weeks`.
fn format_number_by_weeks(n: f64, pattern: &str, weeks: WeekNumbers) -> XlResult<String> {
    let named = match pattern.to_ascii_lowercase().as_str() {
        "" | "general number" | "general" => return Ok(vba_number_shown(n, false)),
        "fixed" => "0.00",
        "standard" => "#,##0.00",
        "percent" => "0.00%",
        "scientific" => "0.00E+00",
        // "Format function", its predefined formats, with the system settings of English
        // (United States), as FormatNumber's defaults.
        "currency" => "$#,##0.00;($#,##0.00)",
        "yes/no" => return Ok(if n == 0.0 { "No" } else { "Yes" }.into()),
        "true/false" => return Ok(if n == 0.0 { "False" } else { "True" }.into()),
        "on/off" => return Ok(if n == 0.0 { "Off" } else { "On" }.into()),
        "general date" => match (n.trunc() == 0.0, n.fract() == 0.0) {
            (true, _) if n != 0.0 => "h:mm:ss AM/PM",
            (_, true) => "m/d/yyyy",
            _ => "m/d/yyyy h:mm:ss AM/PM",
        },
        "long date" => "dddd, mmmm d, yyyy",
        "medium date" => "dd-mmm-yy",
        "short date" => "m/d/yyyy",
        "long time" => "h:mm:ss AM/PM",
        "medium time" => "hh:mm AM/PM",
        "short time" => "hh:mm",
        _ => pattern,
    };
    NumberFormat::parse_vba(named)?.format_vba_number(n, weeks)
}

/// `text Like pattern` ([MS-VBAL] 5.6.9.5.7, Option Compare Binary): `?` one character, `*`
/// any run, `#` one digit, `[a-z]` / `[!a-z]` one character in / not in the list. An
/// unclosed `[` is `#VALUE!` (VBA's error 93, invalid pattern string).
pub fn like(text: &Value, pattern: &Value) -> Value {
    let (text, pattern) = match (vba_text(text), vba_text(pattern)) {
        (Ok(t), Ok(p)) => (t, p),
        (Err(e), _) | (_, Err(e)) => return Value::Error(e),
    };
    match like_tokens(&pattern) {
        Some(tokens) => Value::Bool(like_matches(&tokens, &text.chars().collect::<Vec<_>>())),
        None => Value::Error(XlError::Value),
    }
}

enum LikeToken {
    One,
    Any,
    Digit,
    Char(char),
    /// `[…]`: (ranges, negated).
    List(Vec<(char, char)>, bool),
}

fn like_tokens(pattern: &str) -> Option<Vec<LikeToken>> {
    let mut out = Vec::new();
    let mut chars = pattern.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(match c {
            '?' => LikeToken::One,
            '*' => LikeToken::Any,
            '#' => LikeToken::Digit,
            '[' => {
                let negated = chars.next_if_eq(&'!').is_some();
                let mut items: Vec<char> = Vec::new();
                loop {
                    match chars.next()? {
                        ']' => break,
                        c => items.push(c),
                    }
                }
                LikeToken::List(char_ranges(&items), negated)
            }
            c => LikeToken::Char(c),
        });
    }
    Some(out)
}

/// `a-z0-9_` into ranges; a `-` first or last is itself.
fn char_ranges(items: &[char]) -> Vec<(char, char)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < items.len() {
        if i + 2 < items.len() && items[i + 1] == '-' {
            out.push((items[i], items[i + 2]));
            i += 3;
        } else {
            out.push((items[i], items[i]));
            i += 1;
        }
    }
    out
}

/// Whether `text` matches a file pattern of Windows' wildcards, as `Dir` and `Kill` read
/// them: `*` any run of characters, `?` one; `#` and `[` are themselves there.
pub fn wildcard_matches(pattern: &str, text: &str) -> bool {
    let tokens: Vec<LikeToken> = pattern
        .chars()
        .map(|c| match c {
            '*' => LikeToken::Any,
            '?' => LikeToken::One,
            c => LikeToken::Char(c),
        })
        .collect();
    like_matches(&tokens, &text.chars().collect::<Vec<_>>())
}

/// Whether `tokens` match the whole of `text` (the one wildcard matcher, [`wild_match`]).
fn like_matches(tokens: &[LikeToken], text: &[char]) -> bool {
    wild_match(tokens, text, true).0
}

impl WildToken<char> for LikeToken {
    fn is_any(&self) -> bool {
        matches!(self, LikeToken::Any)
    }

    fn takes(&self, c: char) -> bool {
        match self {
            LikeToken::One => true,
            LikeToken::Digit => c.is_ascii_digit(),
            LikeToken::Char(x) => *x == c,
            LikeToken::List(ranges, negated) => ranges.iter().any(|(lo, hi)| (*lo..=*hi).contains(&c)) != *negated,
            LikeToken::Any => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_as_excel_and_vba_show_numbers() {
        // Expected texts as Excel's TEXT and VBA's Format produce them.
        assert_eq!(format_number(44.262741699797, "0.000").unwrap(), "44.263");
        assert_eq!(format_number(-4.6, "0.000").unwrap(), "-4.600");
        assert_eq!(format_number(2.675, "0.00").unwrap(), "2.68");
        assert_eq!(format_number(1234567.891, "#,##0.00").unwrap(), "1,234,567.89");
        assert_eq!(format_number(0.5, "0%").unwrap(), "50%");
        assert_eq!(format_number(12345.0, "0.00E+00").unwrap(), "1.23E+04");
        assert_eq!(format_number(0.00012, "0.0E-00").unwrap(), "1.2E-04");
        assert_eq!(format_number(3.0, "0.###").unwrap(), "3.");
        assert_eq!(format_number(3.25, "0.0##").unwrap(), "3.25");
        assert_eq!(format_number(-2.0, "+0.0;-0.0").unwrap(), "-2.0");
        assert_eq!(format_number(2.0, "+0.0;-0.0").unwrap(), "+2.0");
        assert_eq!(format_number(0.0, "0.0;-0.0;\"zero\"").unwrap(), "zero");
        assert_eq!(format_number(7.0, "\"X\"0.000").unwrap(), "X7.000");
        assert_eq!(format_number(0.25, "#.00").unwrap(), ".25");
        assert_eq!(format_number(99.996, "0.00").unwrap(), "100.00");
        assert_eq!(format_number(1.5, "Fixed").unwrap(), "1.50");
    }

    #[test]
    fn val_reads_the_leading_number() {
        assert_eq!(vba_val(" 1 2.5mm"), 12.5);
        assert_eq!(vba_val("-3e2x"), -300.0);
        assert_eq!(vba_val("abc"), 0.0);
        assert_eq!(vba_val(".5"), 0.5);
        assert_eq!(vba_val("2e"), 2.0);
    }

    #[test]
    fn like_matches_as_the_vba_reference_shows_in_steps_near_the_text_and_pattern() {
        let matches = |text: &str, pattern: &str| like(&Value::from(text), &Value::from(pattern));
        // The examples of the Office VBA reference's "Like operator" page.
        for (text, pattern, expected) in [
            ("aBBBa", "a*a", true),
            ("F", "[A-Z]", true),
            ("F", "[!A-Z]", false),
            ("a2a", "a#a", true),
            ("aM5b", "a[L-P]#[!c-e]", true),
            ("BAT123khg", "B?T*", true),
            ("CAT123khg", "B?T*", false),
            ("ab", "a*b", true),
            ("a*b", "a [*]b", false),
            ("axxxxxb", "a [*]b", false),
            ("a [xyz", "a [[]xyz", true),
        ] {
            assert_eq!(matches(text, pattern), Value::Bool(expected), "{text:?} Like {pattern:?}");
        }
        // A `*` that must give back what it took: the last `*` moves on, not the first.
        assert_eq!(matches("abcbcd", "*bc*cd"), Value::Bool(true));
        assert_eq!(matches("abcbce", "*bc*cd"), Value::Bool(false));
        // 2,000 `*a` and a `*b` against 100,000 "a": the table over (token, position) took
        // a step for every later position at each position a `*` reached, past 30 s.
        let text: Vec<char> = "a".repeat(100_000).chars().collect();
        let tokens = like_tokens(&("*a".repeat(2000) + "*b")).expect("a valid pattern");
        let (found, steps) = wild_match(&tokens, &text, true);
        assert!(!found);
        assert!(steps <= 3 * (text.len() + tokens.len()), "{steps} steps");
    }
}
