//! VBA's conversions and constructors beyond the first set: `Hex`, `Oct`, `CLngLng`, `CByte`,
//! `CSng`, `CCur`, `String`, `StrReverse`, `Replace` with its start, count and compare, `DateSerial`,
//! `TimeSerial`, `Date`, `Time`, `Date$`, `Time$`, the Mid statement, and the `$` forms of the
//! functions that pass Null. The rules are the "Runtime Semantics" of [MS-VBAL] section 6
//! (the VBA standard library) and the Office VBA language reference's pages of the same names.

use std::cell::Cell;

use crate::eval::dates::{DateTime, VBA_DATE_RANGE};
use crate::eval::functions::api::{given, Ctx};
use crate::eval::functions::ValueFn;
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use super::strings::{find_from, Searched};
use super::{invalid_call, invalid_use_of_null, lift_vba, lift_vba_values, vba_text, EVERY, FIRST, NO_NULL};

/// A value Let-coerced to a whole number as VBA does ([MS-VBAL] 5.5.1.2.1): halves to even,
/// True is -1; `None` past `limit` (VBA's Overflow).
fn whole_in(raised: &Raised, v: &Value, limit: f64) -> XlResult<Option<f64>> {
    let n = match v {
        Value::Bool(b) => -f64::from(u8::from(*b)),
        Value::Blank => 0.0,
        other => raised.number(other)?.round_ties_even(),
    };
    Ok((-limit - 1.0..=limit).contains(&n).then_some(n))
}

const LONG_MAX: f64 = 2147483647.0;

/// The first VBA run-time error the items of a lifted call met (its number and why), raised
/// once the call is done: 5 (Invalid procedure call or argument), 6 (Overflow) or 13 (Type
/// mismatch), or ncsheet's refusal ([`super::errors::NOT_SUPPORTED`], which no `On Error` traps).
#[derive(Default)]
pub(super) struct Raised(Cell<Option<(u32, &'static str)>>);

impl Raised {
    /// Notes error `number`; the item is meanwhile the error value returned.
    pub(super) fn set(&self, number: u32, why: &'static str) -> XlError {
        if self.0.get().is_none() {
            self.0.set(Some((number, why)));
        }
        if number == 6 {
            XlError::Num
        } else {
            XlError::Value
        }
    }

    /// `result`, or the error noted, raised in a macro.
    pub(super) fn raise(&self, ctx: &mut Ctx, name: &str, result: XlResult<Value>) -> XlResult<Value> {
        match self.0.get() {
            Some((6, why)) => {
                Err(ctx.raise_vba(XlError::Num, 6, super::errors::message(6, format_args!("{name}: {why}"))))
            }
            Some((13, why)) => {
                Err(ctx.raise_vba(XlError::Value, 13, super::errors::message(13, format_args!("{name}: {why}"))))
            }
            Some((super::errors::NOT_SUPPORTED, why)) => {
                Err(ctx.raise_vba(XlError::Value, super::errors::NOT_SUPPORTED, format!("{name}: {why}")))
            }
            Some((_, why)) => Err(invalid_call(ctx, name, why)),
            None => result,
        }
    }

    /// A value as a number the way VBA's conversions read it ([`super::vba_number`]); a String
    /// that reads as no number is noted as Type mismatch, error 13 ("Type conversion
    /// functions": "If expression lies outside the acceptable range … an error occurs";
    /// [MS-VBAL] 5.5.1.2.1.1: a String not a number is error 13), where it was an error value.
    pub(super) fn number(&self, v: &Value) -> XlResult<f64> {
        super::vba_number(v).map_err(|e| match v {
            Value::Text(_) => self.set(13, "a String that reads as no number"),
            _ => e,
        })
    }

    /// A value Let-coerced to a whole number within `limit` (a Long's, an Integer's), its
    /// overflow noted.
    pub(super) fn whole(&self, v: &Value, limit: f64) -> XlResult<f64> {
        whole_in(self, v, limit)?.ok_or_else(|| self.set(6, "a number past the range of its type"))
    }
}

/// `CByte(value)` ("Type conversion functions"): a whole number 0 to 255, halves to even;
/// past that run-time error 6, Overflow.
pub(super) fn cbyte(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    converted(ctx, args, "CByte", &|n| Some(n.round_ties_even()).filter(|r| (0.0..=255.0).contains(r)))
}

/// `CSng(value)` ("Type conversion functions"): the number rounded to a Single, a 32-bit
/// float ("Single data type"), within -3.402823E38 to 3.402823E38, else Overflow.
pub(super) fn csng(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    converted(ctx, args, "CSng", &|n| Some(f64::from(n as f32)).filter(|r| r.is_finite()))
}

/// `CCur(value)` ("Type conversion functions", "Currency data type"): the number to four
/// decimal places, halves to even, within -922,337,203,685,477.5808 to 922,337,203,685,477.5807,
/// else Overflow.
pub(super) fn ccur(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // 2^63 / 10^4 (Currency is a 64-bit integer of ten-thousandths), as the nearest double.
    const CURRENCY_END: f64 = 9_223_372_036_854_775_808.0 / 10_000.0;
    let four_places = |n: f64| (n * 10_000.0).round_ties_even() / 10_000.0;
    converted(ctx, args, "CCur", &|n| Some(four_places(n)).filter(|r| (-CURRENCY_END..CURRENCY_END).contains(r)))
}

/// A value Let-coerced to a number ([MS-VBAL] 5.5.1.2.1: True is -1, Empty 0) and made the
/// type's by `fit`, which gives `None` past the type's range: run-time error 6.
fn converted(ctx: &mut Ctx, args: &[Expr], name: &str, fit: &dyn Fn(f64) -> Option<f64>) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, name, NO_NULL, &|v| {
        let n = match &v[0] {
            Value::Bool(b) => -f64::from(u8::from(*b)),
            Value::Blank => 0.0,
            other => raised.number(other)?,
        };
        fit(n).map(Value::Number).ok_or_else(|| raised.set(6, "a number past the range of its type"))
    });
    raised.raise(ctx, name, result)
}

/// `Hex(number)` and `Oct(number)` ([MS-VBAL] section 6, its pages "Hex" and "Oct"): Null gives
/// Null, Empty "0"; a positive number its digits, a negative one its two's complement in the
/// bits of the type a macro holds it with (`Hex(-1)` of the Integer is "FFFF", `Hex(-1&)` of
/// the Long "FFFFFFFF"); a number of no whole-number type (a cell's) in 16 bits from -32,767
/// to -1, else in 32.
fn radix(ctx: &mut Ctx, args: &[Expr], name: &str, base: u32) -> XlResult<Value> {
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    let width = match (args.first(), values.first()) {
        (Some(e), Some(v)) => ctx.macro_integer_bits(e, v),
        _ => None,
    };
    let raised = Raised::default();
    let result = lift_vba_values(ctx, values, name, FIRST, &|v| {
        let bits = twos_complement(raised.whole(&v[0], LONG_MAX)? as i64, width);
        Ok(Value::text(if base == 16 { format!("{bits:X}") } else { format!("{bits:o}") }))
    });
    raised.raise(ctx, name, result)
}

/// `n` as the unsigned bits Hex and Oct write: itself when not negative, else its two's
/// complement in `width` bits (16 or 32; with none known, 16 from -32,767 to -1).
fn twos_complement(n: i64, width: Option<u32>) -> u64 {
    match (n, width) {
        (0.., _) => n as u64,
        (_, Some(16)) | (-32767..=-1, None) => u64::from(n as i16 as u16),
        _ => u64::from(n as i32 as u32),
    }
}

pub(super) fn hex(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    radix(ctx, args, "Hex", 16)
}

pub(super) fn oct(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    radix(ctx, args, "Oct", 8)
}

/// `CLngLng(value)`: a LongLong, halves to even (64-bit hosts' conversion, "Type conversion
/// functions"); past its range `#NUM!` (VBA's Overflow). A macro's LongLong, or a text of
/// digits within the range (`"9223372036854775807"`), is that integer, whose double may be
/// 2^63 itself (the macro keeps the integer beside it).
pub(super) fn clnglng(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    let long_long = match (args.first(), values.first()) {
        (Some(e), Some(v @ Value::Number(_))) => ctx.macro_long_long_text(e, v),
        (_, Some(Value::Text(t))) => Some(t.trim().to_string()),
        _ => None,
    };
    if let Some(k) = long_long.and_then(|t| t.parse::<i64>().ok()) {
        return Ok(Value::Number(k as f64));
    }
    let raised = Raised::default();
    let result = lift_vba_values(ctx, values, "CLngLng", NO_NULL, &|v| {
        let n = raised.whole(&v[0], 9.223372036854776e18)?;
        // 2^63 itself rounds into the range as a double but is one past LongLong's top.
        if n >= 9.223372036854776e18 {
            return Err(raised.set(6, "a number past the range of a LongLong"));
        }
        Ok(Value::Number(n))
    });
    raised.raise(ctx, "CLngLng", result)
}

/// `String(number, character)` ("String function"): `number` copies of a character, given
/// by its code (taken Mod 256) or as the first character of a text; Null in either gives Null.
pub(super) fn string(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let limit = ctx.text_limit();
    let over = Cell::new(false);
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "String", EVERY, &|v| {
        let n = raised.whole(&v[0], LONG_MAX)?;
        if n < 0.0 {
            return Err(raised.set(5, "a negative number of characters"));
        }
        let c = match &v[1] {
            Value::Text(t) => t.chars().next().ok_or_else(|| raised.set(5, "an empty text gives no character"))?,
            other => {
                let code = raised.whole(other, LONG_MAX)?;
                char::from_u32(code.rem_euclid(256.0) as u32).ok_or(XlError::Value)?
            }
        };
        if n as usize > limit {
            over.set(true);
            return Err(XlError::Value);
        }
        Ok(Value::text(c.to_string().repeat(n as usize)))
    });
    if over.get() {
        return Err(ctx.text_over_limit());
    }
    raised.raise(ctx, "String", result)
}

/// `StrReverse(expression)`: the characters in reverse order ([MS-VBAL]: its expression is
/// a String, so Null is error 94).
pub(super) fn str_reverse(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values = args.iter().map(|a| super::text_argument(ctx, a)).collect();
    lift_vba_values(ctx, values, "StrReverse", NO_NULL, &|v| {
        Ok(Value::text(vba_text(&v[0])?.chars().rev().collect::<String>()))
    })
}

/// `Replace(expression, find, replace[, start[, count[, compare]]])` ("Replace function"):
/// the text from `start` on (what comes before is dropped), with at most `count` (-1: every)
/// finds replaced, compared ignoring case for vbTextCompare (1). Null expression: error 94.
pub(super) fn replace(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let limit = ctx.text_limit();
    let over = Cell::new(false);
    let has = |i: usize| given(args, i).is_some();
    let (has_start, has_count, has_compare) = (has(3), has(4), has(5));
    // Left out or vbUseCompareOption: the module's Option Compare.
    let option_text = ctx.option_compare_text();
    let raised = Raised::default();
    let values: Vec<Value> = (args.iter().enumerate())
        .map(|(i, a)| if i < 3 { super::text_argument(ctx, a) } else { ctx.eval(a) })
        .collect();
    // The text is read whole however little is left of it (`Replace(s, s, "")`).
    ctx.charge_texts(&values[..1]);
    let result = lift_vba_values(ctx, values, "Replace", NO_NULL, &|v| {
        let text = vba_text(&v[0])?;
        let find = vba_text(&v[1])?;
        let with = vba_text(&v[2])?;
        let start = if has_start { raised.whole(&v[3], LONG_MAX)? } else { 1.0 };
        let count = if has_count { raised.whole(&v[4], LONG_MAX)? } else { -1.0 };
        let ignore_case = match if has_compare { raised.whole(&v[5], LONG_MAX)? } else { -1.0 } {
            1.0 => true,
            0.0 => false,
            -1.0 => option_text,
            _ => return Err(raised.set(5, "compare is vbBinaryCompare (0) or vbTextCompare (1)")),
        };
        if start < 1.0 {
            return Err(raised.set(5, "start is below 1"));
        }
        if count < -1.0 {
            return Err(raised.set(5, "count is below -1"));
        }
        let search = Search { find: &find, with: &with, count, ignore_case };
        let replaced = replaced(&text, start as usize - 1, search, limit.saturating_mul(4));
        replaced.map(Value::text).ok_or_else(|| {
            over.set(true);
            XlError::Value
        })
    });
    if over.get() {
        return Err(ctx.text_over_limit());
    }
    raised.raise(ctx, "Replace", result)
}

/// What Replace looks for and puts in its place: up to `count` (-1: every) `find`s, compared
/// as `ignore_case` says.
struct Search<'a> {
    find: &'a str,
    with: &'a str,
    count: f64,
    ignore_case: bool,
}

/// `text` from character `start` (0-based) on, with the non-overlapping `find`s, left to
/// right, replaced by `with`; `None` once the result passes `cap` bytes (refused before it is
/// built further). One linear search through the text folded once ([`Searched`]): comparing
/// `find` at every position was quadratic, and folding into lists of characters cost 20 ns a
/// character.
fn replaced(text: &str, start: usize, search: Search, cap: usize) -> Option<String> {
    let (mut hay, needle) = (Searched::new(text, search.ignore_case), Searched::new(search.find, search.ignore_case));
    let mut from = hay.at_char(start).unwrap_or_else(|| hay.at_byte(hay.bytes().len()));
    let mut out = String::new();
    let mut left = search.count;
    while !needle.bytes().is_empty() && left != 0.0 {
        let Some(at) = find_from(&hay, &needle, from.folded) else { break };
        let (found, end) = (hay.at_byte(at), hay.at_byte(at + needle.bytes().len()));
        out.push_str(&text[from.text..found.text]);
        out.push_str(search.with);
        from = end;
        left -= 1.0;
        if out.len() > cap {
            return None;
        }
    }
    out.push_str(&text[from.text..]);
    (out.len() <= cap).then_some(out)
}

/// The Mid statement's new text ("Mid statement": `Mid(stringvar, start[, length]) =
/// string`): characters of the variable from `start` replaced by those of `string`, never
/// more than `length`, than `string` has, or than the variable has from `start` on (its
/// length stays). A start outside the text is error 5.
pub(super) fn mid_statement(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let has_length = given(args, 2).is_some();
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "Mid", NO_NULL, &|v| {
        let mut text: Vec<char> = vba_text(&v[0])?.chars().collect();
        let start = raised.whole(&v[1], LONG_MAX)?;
        let with: Vec<char> = vba_text(&v[3])?.chars().collect();
        if start < 1.0 || start as usize > text.len() {
            return Err(raised.set(5, "start is not a position of the text"));
        }
        let from = start as usize - 1;
        let mut n = with.len().min(text.len() - from);
        if has_length {
            match raised.whole(&v[2], LONG_MAX)? {
                l if l < 0.0 => return Err(raised.set(5, "length is negative")),
                l => n = n.min(l as usize),
            }
        }
        text[from..from + n].copy_from_slice(&with[..n]);
        Ok(Value::text(text.into_iter().collect::<String>()))
    });
    raised.raise(ctx, "Mid statement", result)
}

/// The LSet and RSet statements (`LSet stringvar = string`, "LSet statement", "RSet
/// statement"): `string` in the variable's length, left-aligned (LSet) or right-aligned
/// (RSet), padded with spaces; a longer `string` keeps its leftmost characters either way.
fn aligned_in_place(ctx: &mut Ctx, args: &[Expr], name: &str, right: bool) -> XlResult<Value> {
    lift_vba(ctx, args, name, NO_NULL, &|v| {
        let width = vba_text(&v[0])?.chars().count();
        let text: String = vba_text(&v[1])?.chars().take(width).collect();
        let pad = " ".repeat(width - text.chars().count());
        Ok(Value::text(if right { format!("{pad}{text}") } else { format!("{text}{pad}") }))
    })
}

pub(super) fn lset_statement(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    aligned_in_place(ctx, args, "LSet", false)
}

pub(super) fn rset_statement(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    aligned_in_place(ctx, args, "RSet", true)
}

/// Days from 1899-12-30 (VBA's day 0) to a day of the proleptic Gregorian calendar.
pub(super) fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    // Years counted from March, so that the leap day ends a year.
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let year_of_era = y - era * 400;
    let day_of_year = (153 * (month + if month > 2 { -3 } else { 9 }) + 2) / 5 + day - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    // 693,899 days from 0000-03-01 to 1899-12-30 (719,468 to 1970-01-01, less 25,569).
    era * 146_097 + day_of_era - 693_899
}

/// `DateSerial(year, month, day)` ("DateSerial function"): the date, a month or day past its
/// range carried into the next larger unit (`DateSerial(1990 - 10, 8 - 2, 1 - 1)` is
/// 1980-05-31); a year 0–29 is 2000–2029 and 30–99 is 1930–1999 (Windows' default); the
/// result from 100-01-01 to 9999-12-31. Its arguments are Integers: Null is error 94.
pub(super) fn date_serial(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "DateSerial", NO_NULL, &|v| {
        let part = |i: usize| -> XlResult<i64> { Ok(raised.whole(&v[i], 32767.0)? as i64) };
        let (year, month, day) = (part(0)?, part(1)?, part(2)?);
        let year = match year {
            0..=29 => year + 2000,
            30..=99 => year + 1900,
            _ => year,
        };
        let months = year * 12 + (month - 1);
        let first = days_from_civil(months.div_euclid(12), months.rem_euclid(12) + 1, 1);
        let date = first + day - 1;
        if !(days_from_civil(100, 1, 1)..=days_from_civil(9999, 12, 31)).contains(&date) {
            return Err(raised.set(5, "the date is outside 100-01-01 to 9999-12-31"));
        }
        Ok(Value::Number(date as f64))
    });
    raised.raise(ctx, "DateSerial", result)
}

/// `TimeSerial(hour, minute, second)` ("TimeSerial function"): the time as a fraction of a
/// day, a minute or second past its range carried into the next unit (`TimeSerial(12 - 6,
/// -15, 0)` is 5:45:00). Integers: Null is error 94.
pub(super) fn time_serial(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "TimeSerial", NO_NULL, &|v| {
        let part = |i: usize| raised.whole(&v[i], 32767.0);
        let seconds = part(0)? * 3600.0 + part(1)? * 60.0 + part(2)?;
        Ok(Value::Number(seconds / 86400.0))
    });
    raised.raise(ctx, "TimeSerial", result)
}

/// The document's clock as a VBA Date (days from 1899-12-30, whatever the workbook's system).
fn now(ctx: &Ctx) -> f64 {
    let now = ctx.env.now();
    // 1904-01-01, serial 0 of the 1904 system, is day 1,462 of VBA's.
    if ctx.dates().is_1904() {
        now + 1462.0
    } else {
        now
    }
}

/// `Date`: today, the whole day of the document's clock ("Date function").
pub(super) fn date(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(now(ctx).floor()))
}

/// `Time`: the time of day of the document's clock ("Time function").
pub(super) fn time(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    let now = now(ctx);
    Ok(Value::Number(now - now.floor()))
}

/// `CDate(value)` ("Type conversion functions"; [MS-VBAL] 5.5.1.2.4, Let-coercion to Date):
/// a number is the date it counts (days from 1899-12-30), text a date or a time as the
/// en-US locale writes it (`"1/2/2024"`, `"2024-01-02"`, `"12:30 PM"`), True -1; Null is
/// error 94, text that is no date a type mismatch.
pub(super) fn cdate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "CDate", NO_NULL, &|v| {
        let serial = match &v[0] {
            Value::Bool(b) => -f64::from(u8::from(*b)),
            other => raised.number(other)?,
        };
        // "Date data type": January 1, 100 to December 31, 9999; past it Overflow.
        if !crate::eval::dates::VBA_DATE_RANGE.contains(&serial) {
            return Err(raised.set(6, "a date before 1/1/100 or after 12/31/9999"));
        }
        Ok(Value::Number(serial))
    });
    raised.raise(ctx, "CDate", result)
}

/// A Date argument of `Year`, `Month`, … in its parts, read as CDate reads it (a date
/// outside 100-01-01 to 9999-12-31 is Overflow).
pub(super) fn vba_date_time(raised: &Raised, v: &Value) -> XlResult<DateTime> {
    let serial = match v {
        Value::Bool(b) => -f64::from(u8::from(*b)),
        other => raised.number(other)?,
    };
    if !VBA_DATE_RANGE.contains(&serial) {
        return Err(raised.set(6, "a date before 1/1/100 or after 12/31/9999"));
    }
    Ok(DateTime::from_vba_date(serial, 0))
}

/// One part of a Date ("Year function", "Month function", "Day function", "Hour function",
/// …): in VBA's own calendar, so a date before 1900 has its year, unlike the sheet's YEAR.
/// Null gives Null.
fn date_part(ctx: &mut Ctx, args: &[Expr], name: &'static str, part: fn(&DateTime) -> i64) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, name, FIRST, &|v| Ok(Value::Number(part(&vba_date_time(&raised, &v[0])?) as f64)));
    raised.raise(ctx, name, result)
}

pub(super) fn year(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Year", |d| d.year)
}

pub(super) fn month(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Month", |d| i64::from(d.month))
}

pub(super) fn day(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Day", |d| i64::from(d.day))
}

pub(super) fn hour(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Hour", |d| i64::from(d.hour))
}

pub(super) fn minute(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Minute", |d| i64::from(d.minute))
}

pub(super) fn second(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    date_part(ctx, args, "Second", |d| i64::from(d.second))
}

/// `Weekday(date[, firstdayofweek])` ("Weekday function"): 1 for the first day of the week,
/// Sunday (vbSunday, 1) unless given; vbUseSystem (0) is the system's, Sunday in en-US.
/// Null gives Null; a first day past 0–7 is error 5.
pub(super) fn weekday(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let raised = Raised::default();
    let result = lift_vba(ctx, args, "Weekday", FIRST, &|v| {
        let sunday_based = i64::from(vba_date_time(&raised, &v[0])?.weekday);
        let first = match v.get(1) {
            None | Some(Value::Blank) => 1,
            Some(f) => match raised.whole(f, 32767.0)? as i64 {
                0 => 1,
                f @ 1..=7 => f,
                _ => return Err(raised.set(5, "the first day of the week is not 0 to 7")),
            },
        };
        Ok(Value::Number(((sunday_based - (first - 1)).rem_euclid(7) + 1) as f64))
    });
    raised.raise(ctx, "Weekday", result)
}

/// `Date$` ("Date function": `Date$` returns a 10-character string, mm-dd-yyyy).
pub(super) fn date_s(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::text(super::format_number(now(ctx).floor(), "mm-dd-yyyy")?))
}

/// `Time$` ("Time function": `Time$` returns an 8-character string, hh:mm:ss).
pub(super) fn time_s(ctx: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    let now = now(ctx);
    Ok(Value::text(super::format_number(now - now.floor(), "hh:mm:ss")?))
}

/// The `$` form of a function that passes Null (`Left$`, `Hex$`): the same text, but a
/// String, which cannot hold Null ([MS-VBAL] section 6, Hex: "the function Hex$ raises error 94").
fn string_form(ctx: &mut Ctx, args: &[Expr], name: &str, f: ValueFn) -> XlResult<Value> {
    match f(ctx, args)? {
        Value::Null => Err(invalid_use_of_null(ctx, name)),
        v => Ok(v),
    }
}

macro_rules! string_forms {
    ($($form:ident = $base:path, $name:literal;)*) => {
        $(
            pub(super) fn $form(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
                string_form(ctx, args, $name, $base)
            }
        )*
    };
}

string_forms! {
    left_s = super::left, "Left$";
    right_s = super::right, "Right$";
    mid_s = super::mid, "Mid$";
    trim_s = super::trim, "Trim$";
    ltrim_s = super::ltrim, "LTrim$";
    rtrim_s = super::rtrim, "RTrim$";
    ucase_s = super::ucase, "UCase$";
    lcase_s = super::lcase, "LCase$";
    hex_s = hex, "Hex$";
    oct_s = oct, "Oct$";
    format_s = super::format, "Format$";
    string_s = string, "String$";
}

/// `CVar(value)`: the value as a Variant, holding what it held ("Type conversion functions":
/// CVar's result is a Variant; `TypeName(CVar(5))` is Integer, `CVar(Null)` is Null).
pub(super) fn cvar(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(ctx.eval(&args[0]).unwrap_single())
}

/// `CDec(value)` ("Type conversion functions", "Decimal data type"): a Decimal, within
/// ±79,228,162,514,264,337,593,543,950,335, else Overflow. A number becomes the decimal of its
/// 15 significant digits, as OLE Automation's VarDecFromR8 converts a Double (`CDec(0.1 +
/// 0.2)` is 0.3); the macro holds it as the double nearest to it and computes its
/// operations on its decimal (`vba/typing/decimal.rs`). Text written in the call keeps its
/// every digit, up to 28 places (`CDec("0.1234567890123456789")`, kept beside its double); any
/// other text of more significant digits than a double gives back is refused by name.
///
/// A macro's Decimal, Currency or LongLong is a scaled integer already, which CDec keeps digit
/// for digit ([MS-VBAL] 5.5.1.2.1: a numeric value Let-coerced to a numeric type keeps its value
/// when the type holds it; only a Double or Single goes through VarDecFromR8's 15 or 7 digits):
/// `CDec(CDec(10 ^ 13) + CDec(0.74))` is 10000000000000.74, not 10000000000000.7. Where those
/// digits are more than its double gives back, the macro keeps them beside it.
pub(super) fn cdec(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // 2^96 - 1, the largest Decimal, as the nearest double.
    const DECIMAL_END: f64 = 79_228_162_514_264_337_593_543_950_335.0;
    let fifteen_digits = |n: f64| format!("{n:.14e}").parse().unwrap_or(n);
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    let scaled = args.first().zip(values.first()).and_then(|(e, v)| ctx.macro_long_long_text(e, v));
    let literal = matches!(args.first().map(|e| &e.kind), Some(ExprKind::Text(_)));
    let raised = Raised::default();
    let result = lift_vba_values(ctx, values, "CDec", NO_NULL, &|v| {
        if let Some(digits) = scaled.as_deref() {
            // Digits past what the double gives back are kept beside it (`vba/typing/decimal.rs`).
            return match held_digit_for_digit(digits).or_else(|| digits.parse().ok()) {
                Some(n) if n.abs() <= DECIMAL_END => Ok(Value::Number(n)),
                _ => Err(raised.set(6, "a number past the range of its type")),
            };
        }
        let n = match &v[0] {
            Value::Bool(b) => -f64::from(u8::from(*b)),
            Value::Blank => 0.0,
            // A text written in the call keeps its every digit (`vba/typing/decimal.rs`).
            Value::Text(t) if literal && significant_digits(t) > 15 => {
                return match t.trim().parse::<f64>() {
                    Ok(n) if n.abs() <= DECIMAL_END => Ok(Value::Number(n)),
                    Ok(_) => Err(raised.set(6, "a number past the range of its type")),
                    Err(_) => Err(raised.set(13, "text that is not a number")),
                };
            }
            Value::Text(t) if significant_digits(t) > 15 => {
                return Err(raised.set(
                    super::errors::NOT_SUPPORTED,
                    "text of more than 15 significant digits: ncsheet keeps a Decimal's digits only as far as a \
                     Double gives them back (VBA keeps 28)",
                ))
            }
            other => raised.number(other)?,
        };
        Some(fifteen_digits(n))
            .filter(|r: &f64| r.abs() <= DECIMAL_END)
            .map(Value::Number)
            .ok_or_else(|| raised.set(6, "a number past the range of its type"))
    });
    raised.raise(ctx, "CDec", result)
}

/// The double whose shortest text is the decimal `digits` (`[-]whole[.fraction]`, as a macro
/// writes its Decimal, Currency or LongLong), when there is one: the decimal it stands for.
fn held_digit_for_digit(digits: &str) -> Option<f64> {
    let n: f64 = digits.parse().ok()?;
    let canonical = |t: &str| {
        let t = t.trim_start_matches('-');
        let t = if t.contains('.') { t.trim_end_matches('0').trim_end_matches('.') } else { t };
        t.trim_start_matches('0').to_string()
    };
    let same_sign = (n < 0.0) == digits.starts_with('-') || n == 0.0;
    (same_sign && canonical(&format!("{n}")) == canonical(digits)).then_some(n)
}

/// The significant digits of a number written as text (leading zeros and any exponent aside).
fn significant_digits(text: &str) -> usize {
    let mantissa = text.trim().trim_start_matches(['-', '+']).split(['e', 'E']).next().unwrap_or("");
    mantissa.replace('.', "").trim_start_matches('0').chars().take_while(char::is_ascii_digit).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    // A decimal a double gives back is that double; one of more digits has none (Python:
    // repr(float("10000000000000.74")) is '10000000000000.74', repr(float("9007199254740993"))
    // is '9007199254740992.0').
    #[test]
    fn a_decimal_is_held_by_the_double_that_gives_it_back() {
        assert_eq!(held_digit_for_digit("10000000000000.74"), Some(10000000000000.74));
        assert_eq!(held_digit_for_digit("-2.5"), Some(-2.5));
        assert_eq!(held_digit_for_digit("1050000000000000000000"), Some(1.05e21));
        assert_eq!(held_digit_for_digit("0"), Some(0.0));
        assert_eq!(held_digit_for_digit("9007199254740993"), None);
        assert_eq!(held_digit_for_digit("922337203685477.5807"), None);
    }

    #[test]
    fn days_count_from_vba_day_zero() {
        // Day 0 is 1899-12-30; Excel's serial of 2020-01-31 is 43861 (the 1900 system agrees
        // with VBA from 1900-03-01 on); 100-01-01 is VBA's first date, -657434.
        assert_eq!(days_from_civil(1899, 12, 30), 0);
        assert_eq!(days_from_civil(1900, 3, 1), 61);
        assert_eq!(days_from_civil(2020, 1, 31), 43861);
        assert_eq!(days_from_civil(100, 1, 1), -657434);
        assert_eq!(days_from_civil(9999, 12, 31), 2958465);
    }
}
