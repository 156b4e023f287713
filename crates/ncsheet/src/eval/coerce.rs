//! Excel's coercions between value kinds, used by operators and functions alike.

use std::cmp::Ordering;
use std::rc::Rc;

use super::dates::{self, DateSystem, DateText};
use super::format::number_format::general;
use super::value::{Value, XlError, XlResult};

/// A value as a number for arithmetic: `"2"` is 2, `TRUE` is 1, blank is 0, date text the
/// serial of its date in `dates` (the workbook's system), other text `#VALUE!`.
pub fn to_number(v: &Value, dates: DateSystem) -> XlResult<f64> {
    match v {
        Value::Number(n) => Ok(*n),
        Value::Bool(b) => Ok(f64::from(u8::from(*b))),
        Value::Blank => Ok(0.0),
        Value::Text(s) => parse_number(s, dates).ok_or(XlError::Value),
        Value::Error(e) => Err(*e),
        Value::Array(a) => to_number(a.data.first().unwrap_or(&Value::Blank), dates),
        Value::Lambda(_) => Err(XlError::Calc),
        Value::Null => Err(XlError::Value),
    }
}

/// A value as text: numbers to 15 significant digits, `TRUE`/`FALSE`, blank is "".
pub fn to_text(v: &Value) -> XlResult<Rc<str>> {
    match v {
        Value::Text(s) => Ok(s.clone()),
        Value::Number(n) => Ok(general(*n).into()),
        Value::Bool(b) => Ok(if *b { "TRUE" } else { "FALSE" }.into()),
        Value::Blank => Ok("".into()),
        Value::Error(e) => Err(*e),
        Value::Array(a) => to_text(a.data.first().unwrap_or(&Value::Blank)),
        Value::Lambda(_) => Err(XlError::Calc),
        Value::Null => Err(XlError::Value),
    }
}

/// A value as a condition: numbers are TRUE unless 0, text "TRUE"/"FALSE" only.
pub fn to_bool(v: &Value) -> XlResult<bool> {
    match v {
        Value::Bool(b) => Ok(*b),
        Value::Number(n) => Ok(*n != 0.0),
        Value::Blank => Ok(false),
        Value::Text(s) if s.eq_ignore_ascii_case("TRUE") => Ok(true),
        Value::Text(s) if s.eq_ignore_ascii_case("FALSE") => Ok(false),
        Value::Text(_) => Err(XlError::Value),
        Value::Error(e) => Err(*e),
        Value::Array(a) => to_bool(a.data.first().unwrap_or(&Value::Blank)),
        Value::Lambda(_) => Err(XlError::Calc),
        Value::Null => Err(XlError::Value),
    }
}

/// Reads text the way Excel's `VALUE` and arithmetic do: optional sign, thousands
/// separators, decimals, exponent, a trailing `%`, a currency sign (`$`, `€`, `£`) before or
/// after, surrounding spaces; or a date or time (`2024-01-10`, `1/10/2024`, `13:30`, as its
/// serial number in `dates`: see [`dates::parse_date_text`]).
pub fn parse_number(text: &str, dates: DateSystem) -> Option<f64> {
    // Excel reads " 2024-01-10 " as text although it reads " 100 " as a number: date text is
    // read untrimmed.
    parse_plain_number(text)
        .or_else(|| parse_mixed_fraction(text))
        .or_else(|| dates::parse_date_text(dates, text).map(DateText::serial))
}

/// `1 1/2` → 1.5 and `-2 3/4` → -2.75: a whole number, a space and a proper fraction, as Excel
/// reads a fraction typed into a cell (VALUE("1 1/2") is 1.5). A bare `1/2` is a date there,
/// so it is left to the date reading.
pub(crate) fn parse_mixed_fraction(text: &str) -> Option<f64> {
    let t = text.trim();
    let (negative, t) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let (whole, fraction) = t.split_once(' ')?;
    let (numerator, denominator) = fraction.trim_start().split_once('/')?;
    let digits = |s: &str| -> Option<f64> {
        (!s.is_empty() && s.len() <= 15 && s.bytes().all(|b| b.is_ascii_digit())).then(|| s.parse().ok()).flatten()
    };
    let (w, n, d) = (digits(whole)?, digits(numerator)?, digits(denominator)?);
    if d == 0.0 || n >= d {
        return None;
    }
    let v = w + n / d;
    Some(if negative { -v } else { v })
}

/// [`parse_number`] without dates and times: what VBA's `IsNumeric` accepts.
pub fn parse_plain_number(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.is_empty() {
        return None;
    }
    let (t, scale) = match t.strip_suffix('%') {
        Some(rest) => (rest.trim_end(), 0.01),
        None => (t, 1.0),
    };
    let (negative, body) = match t.as_bytes().first() {
        Some(b'-') => (true, &t[1..]),
        Some(b'+') => (false, &t[1..]),
        _ => (false, t),
    };
    let body = without_currency(body.trim_start());
    let (negative, body) = match body.strip_prefix('(').and_then(|b| b.strip_suffix(')')) {
        Some(inner) if !negative => (true, without_currency(inner)),
        _ => (negative, body),
    };
    let plain = strip_thousands(body)?;
    if !plain.bytes().next().is_some_and(|b| b.is_ascii_digit() || b == b'.') {
        return None;
    }
    if plain.bytes().any(|b| !(b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'))) {
        return None;
    }
    let v: f64 = plain.parse().ok()?;
    let v = if negative { -v } else { v } * scale;
    // Excel keeps no number below the smallest normal double: `1E-320` typed is 0.
    let v = if v.abs() < f64::MIN_POSITIVE { 0.0 } else { v };
    v.is_finite().then_some(v)
}

/// `$100`, `€ 100`, `100€` → `100`: one currency sign, before or after.
fn without_currency(text: &str) -> &str {
    const SIGNS: [char; 3] = ['$', '€', '£'];
    if let Some(rest) = text.strip_prefix(SIGNS) {
        return rest.trim_start();
    }
    match text.strip_suffix(SIGNS) {
        Some(rest) => rest.trim_end(),
        None => text,
    }
}

/// `1,234,567.5` to `1234567.5`; commas must group the integer part by three.
fn strip_thousands(body: &str) -> Option<String> {
    if !body.contains(',') {
        return Some(body.to_string());
    }
    let int_end = body.find(['.', 'e', 'E']).unwrap_or(body.len());
    let (int, rest) = body.split_at(int_end);
    let groups: Vec<&str> = int.split(',').collect();
    let well_grouped = !groups[0].is_empty()
        && groups[0].len() <= 3
        && groups[1..].iter().all(|g| g.len() == 3)
        && !rest.contains(',');
    well_grouped.then(|| format!("{}{rest}", groups.concat()))
}

/// Excel's ordering across kinds: numbers < text < booleans; blank counts as the other
/// side's empty value; text compares without regard to case.
pub fn compare(a: &Value, b: &Value) -> XlResult<Ordering> {
    use Value::*;
    Ok(match (a, b) {
        (Error(e), _) | (_, Error(e)) => return Err(*e),
        (Lambda(_), _) | (_, Lambda(_)) => return Err(XlError::Calc),
        (Null, _) | (_, Null) => return Err(XlError::Value),
        (Array(x), _) => return compare(x.data.first().unwrap_or(&Blank), b),
        (_, Array(y)) => return compare(a, y.data.first().unwrap_or(&Blank)),
        (Number(x), Number(y)) => x.partial_cmp(y).unwrap_or(Ordering::Equal),
        (Text(x), Text(y)) => compare_text(x, y),
        (Bool(x), Bool(y)) => x.cmp(y),
        (Blank, Blank) => Ordering::Equal,
        (Blank, Number(y)) => 0.0.partial_cmp(y).unwrap_or(Ordering::Equal),
        (Number(x), Blank) => x.partial_cmp(&0.0).unwrap_or(Ordering::Equal),
        (Blank, Text(y)) => compare_text("", y),
        (Text(x), Blank) => compare_text(x, ""),
        (Blank, Bool(y)) => false.cmp(y),
        (Bool(x), Blank) => x.cmp(&false),
        (Number(_), _) => Ordering::Less,
        (_, Number(_)) => Ordering::Greater,
        (Text(_), Bool(_)) => Ordering::Less,
        (Bool(_), Text(_)) => Ordering::Greater,
    })
}

pub fn compare_text(a: &str, b: &str) -> Ordering {
    let lower = |s: &str| s.chars().flat_map(char::to_lowercase).collect::<Vec<_>>();
    if a.is_ascii() && b.is_ascii() {
        let (x, y) = (a.as_bytes(), b.as_bytes());
        return x.iter().map(u8::to_ascii_lowercase).cmp(y.iter().map(u8::to_ascii_lowercase));
    }
    lower(a).cmp(&lower(b))
}

/// Equality as `=` tests it (case-insensitive text, numbers as stored).
pub fn values_equal(a: &Value, b: &Value) -> XlResult<bool> {
    compare(a, b).map(|o| o == Ordering::Equal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_reads_as_excel_reads_it() {
        assert_eq!(parse_number(" 2 ", DateSystem::From1900), Some(2.0));
        assert_eq!(parse_number("1,234.5", DateSystem::From1900), Some(1234.5));
        assert_eq!(parse_number("50%", DateSystem::From1900), Some(0.5));
        assert_eq!(parse_number("-1.5e3", DateSystem::From1900), Some(-1500.0));
        assert_eq!(parse_number("(3)", DateSystem::From1900), Some(-3.0));
        assert_eq!(parse_number("1,23", DateSystem::From1900), None);
        assert_eq!(parse_number("abc", DateSystem::From1900), None);
        // Excel's serial numbers of ISO dates (DATE(2024,1,10) = 45301, DATE(1900,3,1) = 61).
        assert_eq!(parse_number("2024-01-10", DateSystem::From1900), Some(45301.0));
        assert_eq!(parse_number("1900-03-01", DateSystem::From1900), Some(61.0));
        assert_eq!(parse_number("2023-02-29", DateSystem::From1900), None);
        // Excel (en-US): dates month first, times as fractions of a day.
        assert_eq!(parse_number("1/10/2024", DateSystem::From1900), Some(45301.0));
        assert_eq!(parse_number("12:00", DateSystem::From1900), Some(0.5));
        assert_eq!(parse_number("1900-01-01", DateSystem::From1900), Some(1.0));
        assert_eq!(parse_number(" 2024-01-10 ", DateSystem::From1900), None);
        assert_eq!(parse_number("$100", DateSystem::From1900), Some(100.0));
        assert_eq!(parse_number("100€", DateSystem::From1900), Some(100.0));
        assert_eq!(parse_number("-$1,234.5", DateSystem::From1900), Some(-1234.5));
        assert_eq!(parse_number("", DateSystem::From1900), None);
    }
}
