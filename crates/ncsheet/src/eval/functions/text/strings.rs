//! Text functions. Positions and lengths count characters, not bytes; one-value
//! functions lift over arrays (`UPPER(A1:A3)` spills three results).

use std::cell::{Cell, RefCell};
use std::rc::Rc;
use std::sync::OnceLock;

use crate::eval::coerce::{to_bool, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{explain_lifted_size, for_each_value, lift, lift_values, ArgSet, Ctx, FnSpec, MANY};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

use crate::eval::format::text_format::{fixed_digits, NumberFormat};
use crate::eval::locale::Locale;

/// Excel's longest text; longer results are `#VALUE!`.
const MAX_TEXT: usize = 32_767;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("CONCAT", 1, MANY, concat, "CONCAT(text1, …)", "Joins texts; ranges are read cell by cell")
        .future()
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "CONCATENATE",
        1,
        MANY,
        concatenate,
        "CONCATENATE(text1, …)",
        "Joins texts (a range argument joins item by item)",
    )
    .biff(336),
    FnSpec::value(
        "TEXTJOIN",
        3,
        MANY,
        textjoin,
        "TEXTJOIN(delimiter, ignore_empty, text1, …)",
        "Joins texts with a delimiter, optionally skipping empty ones",
    )
    .future()
    .range_args(ArgSet::from(2)),
    FnSpec::value(
        "TEXT",
        2,
        2,
        text_fn,
        "TEXT(value, format)",
        "A number as text in an Excel number format: \"0.000\", \"#,##0.00\", \"0.0%\", \"0.00E+00\"",
    )
    .biff(48),
    FnSpec::value(
        "DOLLAR",
        1,
        2,
        dollar,
        "DOLLAR(number, [decimals])",
        "A number rounded to decimals (2 by default) as currency text: $1,234.57, ($1,234.57)",
    )
    .biff(13),
    FnSpec::value(
        "FIXED",
        1,
        3,
        fixed,
        "FIXED(number, [decimals], [no_commas])",
        "A number rounded to decimals (2 by default) as text, with thousands separators unless no_commas",
    )
    .biff(14),
    FnSpec::value("LEFT", 1, 2, left, "LEFT(text, [count])", "The first count characters (1 by default)").biff(115),
    FnSpec::value("RIGHT", 1, 2, right, "RIGHT(text, [count])", "The last count characters (1 by default)").biff(116),
    FnSpec::value("MID", 3, 3, mid, "MID(text, start, count)", "count characters from position start (1-based)")
        .biff(31),
    FnSpec::value("LEN", 1, 1, len, "LEN(text)", "Number of characters").biff(32),
    FnSpec::value("UPPER", 1, 1, upper, "UPPER(text)", "Text in capitals").biff(113),
    FnSpec::value("LOWER", 1, 1, lower, "LOWER(text)", "Text in small letters").biff(112),
    FnSpec::value("PROPER", 1, 1, proper, "PROPER(text)", "Each word capitalised, the rest in small letters").biff(114),
    FnSpec::value(
        "TRIM",
        1,
        1,
        trim,
        "TRIM(text)",
        "Removes leading and trailing spaces and collapses runs of spaces to one",
    )
    .biff(118),
    FnSpec::value("VALUE", 1, 1, value, "VALUE(text)", "The number a text represents (\"1,234.5\", \"50%\", \"1e-3\")")
        .biff(33),
    FnSpec::value(
        "NUMBERVALUE",
        1,
        3,
        numbervalue,
        "NUMBERVALUE(text, [decimal_separator], [group_separator])",
        "The number a text represents with the separators given (\"1.234,5\" with \",\" and \".\"); spaces are ignored, trailing % divide by 100 each",
    )
    .future(),
    FnSpec::value(
        "VALUETOTEXT",
        1,
        2,
        valuetotext,
        "VALUETOTEXT(value, [format])",
        "Any value as text, errors included; format 1 puts text in quotes",
    )
    .future(),
    FnSpec::value(
        "SUBSTITUTE",
        3,
        4,
        substitute,
        "SUBSTITUTE(text, old, new, [instance])",
        "Replaces every occurrence of old (or only the instance-th) with new; case-sensitive",
    )
    .biff(120),
    FnSpec::value("REPT", 2, 2, rept, "REPT(text, times)", "text repeated times times").biff(30),
    FnSpec::value(
        "FIND",
        2,
        3,
        find,
        "FIND(find_text, within_text, [start])",
        "Position of find_text in within_text, case-sensitive; #VALUE! when absent",
    )
    .biff(124),
    FnSpec::value(
        "SEARCH",
        2,
        3,
        search,
        "SEARCH(find_text, within_text, [start])",
        "Position of find_text, ignoring case, with wildcards ? * and ~; #VALUE! when absent",
    )
    .biff(82),
    FnSpec::value("EXACT", 2, 2, exact, "EXACT(text1, text2)", "TRUE when the texts are identical, case included")
        .biff(117),
    FnSpec::value(
        "CHAR",
        1,
        1,
        char_fn,
        "CHAR(code)",
        "The character with a code 1-255 (Windows-1252, as Excel on Windows; CHAR(10) is a line feed)",
    )
    .biff(111),
    FnSpec::value("CODE", 1, 1, code, "CODE(text)", "The code 1-255 of the first character (Windows-1252)").biff(121),
    FnSpec::value("UNICHAR", 1, 1, unichar, "UNICHAR(code)", "The Unicode character with a code point").future(),
    FnSpec::value("UNICODE", 1, 1, unicode, "UNICODE(text)", "The Unicode code point of the first character").future(),
];

// ---------------------------------------------------------------------------------------
// Joining

fn concat(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let over = Cell::new(false);
    let mut out = String::new();
    let joined = for_each_value(ctx, args, &mut |v, _| {
        out.push_str(&to_text(v)?);
        limit(&out, &over)
    });
    explained(ctx, &over, joined.map(|()| Value::from(out)))
}

fn concatenate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let over = Cell::new(false);
    let joined = lift(ctx, args, &|v| {
        let mut out = String::new();
        for item in v {
            out.push_str(&to_text(item)?);
        }
        limit(&out, &over)?;
        Ok(Value::from(out))
    });
    explained(ctx, &over, joined)
}

/// `#VALUE!` past Excel's text length, noting it in `over` for [`explained`] (a lifted
/// function's closure cannot reach the context to explain it there).
fn limit(s: &str, over: &Cell<bool>) -> XlResult<()> {
    if s.len() > MAX_TEXT && s.chars().count() > MAX_TEXT {
        Err(too_long(over))
    } else {
        Ok(())
    }
}

fn too_long(over: &Cell<bool>) -> XlError {
    over.set(true);
    XlError::Value
}

/// `result`, with the text limit named in the cell's note when a text passed it: the
/// #VALUE! of SUBSTITUTE, CONCAT, TEXTJOIN or REPT past 32,767 characters said nothing.
fn explained(ctx: &mut Ctx, over: &Cell<bool>, result: XlResult<Value>) -> XlResult<Value> {
    if over.get() {
        // Excel's limit even in a macro's WorksheetFunction: these functions apply it there.
        let e = ctx.explain(XlError::Value, format!("longer than the {MAX_TEXT} characters of a text (Excel's limit)"));
        if result.is_err() {
            return Err(e);
        }
    }
    result
}

fn textjoin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let delimiters = items_of(ctx.eval(&args[0])).iter().map(to_text).collect::<XlResult<Vec<_>>>()?;
    let ignore_empty = to_bool(&ctx.eval(&args[1]))?;
    let (mut out, over, mut joined) = (String::new(), Cell::new(false), 0usize);
    for e in &args[2..] {
        if e.kind == ExprKind::Missing {
            continue;
        }
        for v in items_of(ctx.eval(e)) {
            let text = to_text(&v)?;
            if ignore_empty && text.is_empty() {
                continue;
            }
            if joined > 0 && !delimiters.is_empty() {
                out.push_str(&delimiters[(joined - 1) % delimiters.len()]);
            }
            out.push_str(&text);
            joined += 1;
            // Stopped at the limit as it is passed: converting all of a 4096 × 4096 array to
            // text first took 20 s before the result was refused.
            if let Err(e) = limit(&out, &over) {
                return explained(ctx, &over, Err(e));
            }
        }
    }
    Ok(Value::from(out))
}

/// A value's items in row order: an array's (blanks included) or the value itself.
fn items_of(v: Value) -> Vec<Value> {
    match v {
        Value::Array(a) => a.data.clone(),
        v => vec![v],
    }
}

// ---------------------------------------------------------------------------------------
// Numbers as text

fn text_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    // The format code and the number text are read, and the result shown, in the locale.
    let locale = ctx.locale();
    let values: Vec<Value> = args.iter().map(|a| ctx.eval(a)).collect();
    // A format that is one value is read once for every item: read per item, a 30,000-character
    // code over an array of thousands was parsed thousands of times.
    let one_format = match &values[1] {
        Value::Array(_) => None,
        format => Some(to_text(format).and_then(|typed| TextFormat::read(locale, &typed))),
    };
    if let (Value::Text(format), Some(Err(_))) = (&values[1], &one_format) {
        return Err(ctx.explain(XlError::Value, unusable_format(locale, format)));
    }
    let shown = lift_values(&values, &|v| {
        // The value's error wins over the format's (`TEXT(NA(),1/0)` is #N/A).
        if let Value::Error(e) = &v[0] {
            return Err(*e);
        }
        let read_here;
        let format = match &one_format {
            Some(format) => format.as_ref().map_err(|e| *e)?,
            None => {
                read_here = TextFormat::read(locale, &to_text(&v[1])?)?;
                &read_here
            }
        };
        format.show(&v[0], locale, dates).map(Value::from)
    });
    // A #NUM! past the array's item or text limit says which.
    explain_lifted_size(ctx, &values, &shown);
    shown
}

/// Why TEXT cannot use the format code `typed`.
fn unusable_format(locale: Locale, typed: &str) -> String {
    if let Some(colour) = locale.foreign_colour(typed) {
        return format!("TEXT cannot use the format \"{typed}\": {colour} is no colour word in {locale}");
    }
    if let Some(at) = crate::eval::locale::unclosed_bracket(typed) {
        return format!("TEXT cannot use the format \"{typed}\": the \"[\" at character {at} is not closed by \"]\"");
    }
    match crate::eval::locale::refused_bracket_word(typed) {
        Some(word) => format!("TEXT cannot use the format \"{typed}\": {word} is no word of a format code"),
        None => format!(
            "TEXT cannot use the format \"{typed}\": a date or time code holds a digit placeholder (0, # or ?), \
             an exponent or General, which Excel does not mix with dates"
        ),
    }
}

/// A format code of TEXT as read in a locale: parsed, with what showing a number in the
/// locale needs of it.
struct TextFormat {
    format: NumberFormat,
    /// What showing a number in the locale needs of the code, read once with it.
    reading: crate::eval::locale::CodeReading,
}

impl TextFormat {
    /// `typed` in `locale`; `#VALUE!` for another locale's colour word or no format code.
    fn read(locale: Locale, typed: &str) -> XlResult<TextFormat> {
        if locale.foreign_colour(typed).is_some() {
            return Err(XlError::Value);
        }
        let code = locale.canonical_format_code(typed);
        let format = NumberFormat::parse(&code)?;
        Ok(TextFormat { format, reading: locale.reading_of(&code) })
    }

    /// One value as TEXT shows it under this format, in `locale`.
    fn show(&self, value: &Value, locale: Locale, dates: DateSystem) -> XlResult<String> {
        let (reading, format) = (&self.reading, &self.format);
        let shown = match value {
            // A boolean is text to TEXT: the text section formats it.
            Value::Bool(b) => format.format_text(if *b { "TRUE" } else { "FALSE" }),
            // Text that reads as a number is formatted as that number.
            Value::Text(s) => match locale.read_number(s, dates) {
                Some(n) => locale.localize_read(reading, &format.format_number(n, dates)?),
                None => format.format_text(s),
            },
            other => locale.localize_read(reading, &format.format_number(to_number(other, dates)?, dates)?),
        };
        if locale.is_canonical() {
            return Ok(shown);
        }
        Ok(crate::eval::locale::literal_marks(&shown))
    }
}

fn fixed(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    let values: Vec<Value> = args.iter().map(|a| locale.numbers_for_arithmetic(ctx.eval(a), dates)).collect();
    let decimals_given = args.get(1).is_some_and(|e| e.kind != ExprKind::Missing);
    lift_values(&values, &|v| {
        let n = to_number(&v[0], dates)?;
        let decimals = if decimals_given { to_number(&v[1], dates)?.trunc() } else { 2.0 };
        let no_commas = match v.get(2) {
            Some(flag) => to_bool(flag)?,
            None => false,
        };
        Ok(Value::from(locale.localize_shown(&fixed_text(n, decimals, no_commas)?)))
    })
}

/// DOLLAR: FIXED with a currency sign, negative amounts in parentheses (`($1,234.57)`), as
/// Excel's en-US currency format shows them; in another locale its own currency and sign.
fn dollar(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    let values: Vec<Value> = args.iter().map(|a| locale.numbers_for_arithmetic(ctx.eval(a), dates)).collect();
    let decimals_given = args.get(1).is_some_and(|e| e.kind != ExprKind::Missing);
    lift_values(&values, &|v| {
        let n = to_number(&v[0], dates)?;
        let decimals = if decimals_given { to_number(&v[1], dates)?.trunc() } else { 2.0 };
        let digits = locale.localize_shown(&fixed_text(n.abs(), decimals, false)?);
        // A negative amount that rounds to nothing shows no parentheses.
        let negative = n < 0.0 && digits.chars().any(|c| c.is_ascii_digit() && c != '0');
        Ok(Value::from(locale.currency_amount(&digits, negative)))
    })
}

/// FIXED: negative decimals round to tens, hundreds, …; more than 127 is `#VALUE!`.
fn fixed_text(n: f64, decimals: f64, no_commas: bool) -> XlResult<String> {
    if decimals > 127.0 {
        return Err(XlError::Value);
    }
    let (n, places) = if decimals < 0.0 {
        let unit = 10f64.powf(-decimals);
        // Rounding to 10^309 and beyond leaves nothing of any double: "0", as Excel shows.
        if !unit.is_finite() {
            return Ok("0".to_string());
        }
        let (int, _) = fixed_digits((n / unit).abs(), 0);
        let rounded = int.parse::<f64>().unwrap_or(0.0) * unit;
        (rounded.copysign(n), 0)
    } else {
        (n, decimals as usize)
    };
    let mut format = String::from(if no_commas { "0" } else { "#,##0" });
    if places > 0 {
        format.push('.');
        format.push_str(&"0".repeat(places));
    }
    // A number format without dates: no date system to follow.
    NumberFormat::parse(&format)?.format_number(n, DateSystem::From1900)
}

// ---------------------------------------------------------------------------------------
// Pieces of text

fn left(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let text = to_text(&v[0])?;
        let count = count_arg(v.get(1), dates)?;
        Ok(Value::from(utf16_piece(&text, 0, count)))
    })
}

fn right(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let text = to_text(&v[0])?;
        let count = count_arg(v.get(1), dates)?;
        let units = utf16_len(&text);
        Ok(Value::from(utf16_piece(&text, units.saturating_sub(count), units)))
    })
}

/// LEFT and RIGHT's count: 1 when omitted, truncated, negative `#VALUE!`.
fn count_arg(v: Option<&Value>, dates: DateSystem) -> XlResult<usize> {
    let Some(v) = v else {
        return Ok(1);
    };
    let n = to_number(v, dates)?.trunc();
    if n < 0.0 {
        return Err(XlError::Value);
    }
    Ok(n.min(MAX_TEXT as f64) as usize)
}

fn mid(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let text = to_text(&v[0])?;
        let start = to_number(&v[1], dates)?.trunc();
        let count = to_number(&v[2], dates)?.trunc();
        if start < 1.0 || count < 0.0 {
            return Err(XlError::Value);
        }
        let units = utf16_len(&text);
        let from = (start.min(units as f64 + 1.0) as usize - 1).min(units);
        let to = from.saturating_add(count.min(MAX_TEXT as f64) as usize).min(units);
        Ok(Value::from(utf16_piece(&text, from, to)))
    })
}

/// LEN, LEFT, RIGHT, MID, FIND and SEARCH count as Excel does, in UTF-16 units: a character
/// beyond U+FFFF (an emoji) is two (`LEN("👍")` = 2). An ASCII text, the usual one, is its
/// bytes, counted and cut without decoding it (a REDUCE of a million LEFTs of 32,000
/// characters spent its time turning each text into UTF-16 and back).
fn utf16_len(text: &str) -> usize {
    if text.is_ascii() {
        text.len()
    } else {
        text.encode_utf16().count()
    }
}

/// The UTF-16 units `from..to` of `text` (cut to its length) as text. A piece that cuts a
/// character beyond U+FFFF in half keeps the half as U+FFFD, the one place where Rust text
/// cannot hold what Excel shows.
fn utf16_piece(text: &str, from: usize, to: usize) -> String {
    if from >= to {
        return String::new();
    }
    if text.is_ascii() {
        let end = to.min(text.len());
        return text[from.min(end)..end].to_string();
    }
    let mut out = String::new();
    let mut unit = 0;
    for c in text.chars() {
        let (start, end) = (unit, unit + c.len_utf16());
        unit = end;
        if end <= from {
            continue;
        }
        if start >= to {
            break;
        }
        out.push(if start >= from && end <= to { c } else { '\u{FFFD}' });
    }
    out
}

fn len(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::Number(utf16_len(&to_text(&v[0])?) as f64)))
}

fn upper(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map_text(ctx, args, |s| s.to_uppercase())
}

fn lower(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map_text(ctx, args, |s| s.to_lowercase())
}

fn trim(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // Only the space character (32); Excel's TRIM leaves tabs and non-breaking spaces.
    map_text(ctx, args, |s| s.split(' ').filter(|w| !w.is_empty()).collect::<Vec<_>>().join(" "))
}

fn proper(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map_text(ctx, args, |s| {
        let mut out = String::with_capacity(s.len());
        let mut after_letter = false;
        for c in s.chars() {
            if after_letter {
                out.extend(c.to_lowercase());
            } else {
                out.extend(c.to_uppercase());
            }
            after_letter = c.is_alphabetic();
        }
        out
    })
}

/// A text-to-text function lifted over arrays.
fn map_text(ctx: &mut Ctx, args: &[Expr], f: fn(&str) -> String) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::from(f(&to_text(&v[0])?))))
}

fn value(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let locale = ctx.locale();
    lift(ctx, args, &|v| match &v[0] {
        Value::Number(n) => Ok(Value::Number(*n)),
        Value::Blank => Ok(Value::Number(0.0)),
        Value::Text(s) => locale.read_number(s, dates).map(Value::Number).ok_or(XlError::Value),
        Value::Error(e) => Err(*e),
        _ => Err(XlError::Value),
    })
}

fn numbervalue(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // The separators left out are the locale's, as Excel's are the system's.
    let locale = ctx.locale();
    lift(ctx, args, &|v| {
        let text = match &v[0] {
            Value::Error(e) => return Err(*e),
            other => to_text(other)?,
        };
        let decimal = separator(v.get(1), locale.decimal)?;
        let group = separator(v.get(2), locale.group)?;
        if decimal == group {
            return Err(XlError::Value);
        }
        number_with_separators(&text, decimal, group).map(Value::Number).ok_or(XlError::Value)
    })
}

/// The first character of a separator argument, `default` when it is left out.
fn separator(arg: Option<&Value>, default: char) -> XlResult<char> {
    match arg {
        None | Some(Value::Blank) => Ok(default),
        Some(Value::Error(e)) => Err(*e),
        Some(v) => to_text(v)?.chars().next().ok_or(XlError::Value),
    }
}

/// NUMBERVALUE's reading, as Excel's page documents it: spaces anywhere are ignored, an empty
/// text is 0, one decimal separator at most, group separators only before it (and then
/// ignored), and each trailing `%` divides by 100.
fn number_with_separators(text: &str, decimal: char, group: char) -> Option<f64> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    let body = compact.trim_end_matches('%');
    let percents = compact.len() - body.len();
    if compact.is_empty() {
        return Some(0.0);
    }
    let decimal_at = body.find(decimal);
    if decimal_at.is_some_and(|at| body[at + decimal.len_utf8()..].contains([decimal, group])) {
        return None;
    }
    let plain: String = body.chars().filter(|&c| c != group).map(|c| if c == decimal { '.' } else { c }).collect();
    let digits_only = plain.bytes().all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'));
    if !digits_only || !plain.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    let v: f64 = plain.parse().ok()?;
    let v = v / 100f64.powi(percents as i32);
    v.is_finite().then_some(v)
}

fn valuetotext(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let strict = match v.get(1) {
            Some(f) => match to_number(f, dates)? {
                0.0 => false,
                1.0 => true,
                _ => return Err(XlError::Value),
            },
            None => false,
        };
        let text = match &v[0] {
            Value::Error(e) => e.as_str().into(),
            Value::Text(s) if strict => format!("\"{s}\"").into(),
            other => to_text(other)?,
        };
        Ok(Value::Text(text))
    })
}

fn substitute(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let over = Cell::new(false);
    let replaced = lift(ctx, args, &|v| {
        let text = to_text(&v[0])?;
        let old = to_text(&v[1])?;
        let new = to_text(&v[2])?;
        let instance = match v.get(3) {
            Some(i) => {
                let i = to_number(i, dates)?.trunc();
                if i < 1.0 {
                    return Err(XlError::Value);
                }
                Some(i as usize)
            }
            None => None,
        };
        if old.is_empty() {
            return Ok(Value::Text(text));
        }
        // Refused before it is built: every replacement may lengthen the text.
        if instance.is_none() && new.len() > old.len() {
            let grows = (new.encode_utf16().count()).saturating_sub(old.encode_utf16().count());
            let longest = text.encode_utf16().count() + text.matches(&*old).count() * grows;
            if longest > MAX_TEXT {
                return Err(too_long(&over));
            }
        }
        let out = match instance {
            None => text.replace(&*old, &new),
            Some(n) => match text.match_indices(&*old).nth(n - 1) {
                Some((at, _)) => format!("{}{}{}", &text[..at], new, &text[at + old.len()..]),
                None => text.to_string(),
            },
        };
        limit(&out, &over)?;
        Ok(Value::from(out))
    });
    explained(ctx, &over, replaced)
}

fn rept(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let over = Cell::new(false);
    let repeated = lift(ctx, args, &|v| {
        let text = to_text(&v[0])?;
        let times = to_number(&v[1], dates)?.trunc();
        if times < 0.0 {
            return Err(XlError::Value);
        }
        if text.chars().count() as f64 * times > MAX_TEXT as f64 {
            return Err(too_long(&over));
        }
        Ok(Value::from(text.repeat(times as usize)))
    });
    explained(ctx, &over, repeated)
}

fn exact(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::Bool(to_text(&v[0])? == to_text(&v[1])?)))
}

// ---------------------------------------------------------------------------------------
// FIND and SEARCH

fn find(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let (needle, haystack, from) = search_args(v, dates)?;
        // Two-way search of the bytes: linear in the text whatever the needle (a scan that
        // compared the needle at each place took 0.3 s for 16,000 characters in 32,767).
        let found = memchr::memmem::find(&haystack.as_bytes()[from..], needle.as_bytes()).map(|at| from + at);
        position(&haystack, found)
    })
}

fn search(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let folded = RefCell::new(FoldedText::default());
    lift(ctx, args, &|v| {
        let (needle, haystack, from) = search_args(v, dates)?;
        let mut folded = folded.borrow_mut();
        let found = Wildcard::new(&needle).find_in(&haystack[from..], folded.of(&haystack, from));
        position(&haystack, found.map(|at| from + at))
    })
}

/// FIND and SEARCH's arguments: the text sought, the text searched, and the byte offset
/// of the character the search starts at (`#VALUE!` below 1 or past the end; the start
/// given is in UTF-16 units, as Excel counts).
fn search_args(v: &[Value], dates: DateSystem) -> XlResult<(Rc<str>, Rc<str>, usize)> {
    let needle = to_text(&v[0])?;
    let haystack = to_text(&v[1])?;
    let start = match v.get(2) {
        Some(s) => to_number(s, dates)?.trunc(),
        None => 1.0,
    };
    if start < 1.0 {
        return Err(XlError::Value);
    }
    let from = first_char_from(&haystack, start - 1.0).ok_or(XlError::Value)?;
    Ok((needle, haystack, from))
}

/// The byte offset of the first character that starts at or after UTF-16 unit `unit` (the
/// end of the text when `unit` is its length in units; `None` past that). A byte loop: a
/// text searched in a broadcast is walked once per search.
fn first_char_from(text: &str, unit: f64) -> Option<usize> {
    if text.is_ascii() {
        return (unit <= text.len() as f64).then_some(unit as usize);
    }
    let mut units = 0usize;
    for (at, &b) in text.as_bytes().iter().enumerate() {
        if is_char_start(b) {
            if units as f64 >= unit {
                return Some(at);
            }
            units += utf16_units(b);
        }
    }
    (units as f64 >= unit).then_some(text.len())
}

fn is_char_start(b: u8) -> bool {
    b & 0xC0 != 0x80
}

/// UTF-16 units of the character whose first UTF-8 byte is `b`: two from four bytes up.
fn utf16_units(b: u8) -> usize {
    1 + usize::from(b >= 0xF0)
}

/// The 1-based position in UTF-16 units of the character at byte offset `found`.
fn position(haystack: &str, found: Option<usize>) -> XlResult<Value> {
    let at = found.ok_or(XlError::Value)?;
    if haystack[..at].is_ascii() {
        return Ok(Value::Number(at as f64 + 1.0));
    }
    let units: usize = haystack.as_bytes()[..at].iter().filter(|&&b| is_char_start(b)).map(|&b| utf16_units(b)).sum();
    Ok(Value::Number(units as f64 + 1.0))
}

/// An Excel wildcard pattern: `?` any one character, `*` any run, `~` escapes the next
/// character. Matching ignores case.
pub struct Wildcard {
    tokens: Vec<WildTok>,
}

#[derive(Clone, Copy, PartialEq)]
enum WildTok {
    Char(char),
    One,
    Any,
}

fn fold(c: char) -> char {
    lower_char(c).unwrap_or_else(|| c.to_lowercase().next().unwrap_or(c))
}

/// The lower case of `c` when it is one character (`None` for U+0130 "İ", whose lower case is
/// two), from a table for the first 2,048 code points (Latin, Greek, Cyrillic, Hebrew, Arabic):
/// `char::to_lowercase` searches Unicode's whole table for each character, and folding a text
/// of "é"s that way took 19 ns a character (4,000 SEARCHes in 32,000 of them, 4.9 s).
pub(crate) fn lower_char(c: char) -> Option<char> {
    if c.is_ascii() {
        return Some(c.to_ascii_lowercase());
    }
    let Some(&lower) = lower_table().get(c as usize) else { return one_lower(c) };
    // No character below U+0800 lowers to NUL: the table's NUL marks "not one character".
    (lower != '\0').then_some(lower)
}

/// [`lower_char`] from Unicode's table.
fn one_lower(c: char) -> Option<char> {
    let mut lower = c.to_lowercase();
    match (lower.next(), lower.next()) {
        (Some(l), None) => Some(l),
        _ => None,
    }
}

/// [`one_lower`] of U+0000..U+07FF, worked out once (read-only after that).
fn lower_table() -> &'static [char] {
    static TABLE: OnceLock<Vec<char>> = OnceLock::new();
    TABLE.get_or_init(|| (0..0x800u32).map(|n| char::from_u32(n).and_then(one_lower).unwrap_or('\0')).collect())
}

/// A text folded for SEARCH, kept while the same text is searched again from the same
/// place: a broadcast of needles over one long text folds it once (folded again for each
/// needle, a character at a time, the folding took 24 ns a byte: 13 s at the reading limit).
#[derive(Default)]
struct FoldedText {
    of: Option<(Rc<str>, usize)>,
    folded: String,
}

impl FoldedText {
    /// `text[from..]` folded.
    fn of(&mut self, text: &Rc<str>, from: usize) -> &str {
        let same = matches!(&self.of, Some((t, f)) if Rc::ptr_eq(t, text) && *f == from);
        if !same {
            self.folded = fold_text(&text[from..]);
            self.of = Some((text.clone(), from));
        }
        &self.folded
    }
}

/// Every character of `text` folded (ASCII a byte at a time).
fn fold_text(text: &str) -> String {
    if text.is_ascii() {
        return text.to_ascii_lowercase();
    }
    text.chars().map(fold).collect()
}

/// How many characters start in `bytes`.
fn char_starts(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| is_char_start(b)).count()
}

/// The byte offset of character `n` of `text` (its length when `n` is its count).
fn byte_of_char(text: &str, n: usize) -> usize {
    let mut seen = 0;
    for (at, &b) in text.as_bytes().iter().enumerate() {
        if is_char_start(b) {
            if seen == n {
                return at;
            }
            seen += 1;
        }
    }
    text.len()
}

impl Wildcard {
    pub fn new(pattern: &str) -> Wildcard {
        let mut tokens = Vec::new();
        let mut chars = pattern.chars();
        while let Some(c) = chars.next() {
            tokens.push(match c {
                '?' => WildTok::One,
                '*' => WildTok::Any,
                // A lone `~` at the end matches nothing (Excel: SEARCH("~", "Hello") is 1).
                '~' => match chars.next() {
                    Some(next) => WildTok::Char(fold(next)),
                    None => continue,
                },
                c => WildTok::Char(fold(c)),
            });
        }
        Wildcard { tokens }
    }

    pub fn has_wildcards(s: &str) -> bool {
        s.contains(['*', '?', '~'])
    }

    /// Whether the whole of `text` matches (an ASCII text a byte at a time).
    pub fn matches(&self, text: &str) -> bool {
        if text.is_ascii() {
            return wild_match(&self.tokens, text.to_ascii_lowercase().as_bytes(), true).0;
        }
        let text: Vec<char> = text.chars().map(fold).collect();
        wild_match(&self.tokens, &text, true).0
    }

    /// The byte offset in `text` of the first match, `folded` being `text` folded.
    pub fn find_in(&self, text: &str, folded: &str) -> Option<usize> {
        let chars_before = match literal_of(&self.tokens) {
            Some(needle) => {
                let at = memchr::memmem::find(folded.as_bytes(), needle.as_bytes())?;
                if folded.len() == text.len() && text.is_ascii() {
                    return Some(at);
                }
                char_starts(&folded.as_bytes()[..at])
            }
            None if folded.is_ascii() => self.find_wild(folded.as_bytes(), folded)?,
            None => self.find_wild(&folded.chars().collect::<Vec<_>>(), folded)?,
        };
        Some(byte_of_char(text, chars_before))
    }

    /// The first character index where a match begins in `text` (`folded`'s characters, or
    /// its bytes when they are ASCII). The tokens before the first `*` match a fixed length at
    /// that position; whether the rest (`*…`) matches after it only gets harder further right,
    /// so it is tried once, at the first place the head fits ([`head_place`]): never
    /// exponential.
    fn find_wild<C: Copy>(&self, text: &[C], folded: &str) -> Option<usize>
    where
        WildTok: WildToken<C>,
    {
        let split = self.tokens.iter().position(|t| *t == WildTok::Any).unwrap_or(self.tokens.len());
        let (head, rest) = self.tokens.split_at(split);
        let i = head_place(head, text, folded)?;
        wild_match(rest, &text[i + head.len()..], false).0.then_some(i)
    }
}

/// The first character index where `head` (tokens that each take one character) fits in
/// `text`, `folded` being the same text as a string. A head with no `?` is sought as text, in
/// time linear in the text (`memmem`); trying it at each place in turn cost the text times the
/// head (`SEARCH(REPT("a",16000)&"*", …)` of a 32,000-character text, 0.5·10^9 steps). A head
/// with `?` is still tried place by place.
fn head_place<C: Copy>(head: &[WildTok], text: &[C], folded: &str) -> Option<usize>
where
    WildTok: WildToken<C>,
{
    if let Some(literal) = literal_of(head) {
        let at = memchr::memmem::find(folded.as_bytes(), literal.as_bytes())?;
        return Some(char_starts(&folded.as_bytes()[..at]));
    }
    let fits = |i: usize| text.len() - i >= head.len() && head.iter().zip(&text[i..]).all(|(t, &c)| t.takes(c));
    (0..=text.len()).find(|&i| fits(i))
}

/// The tokens as text, when they have no `?` or `*` (a `~` that escapes them is no wildcard).
fn literal_of(tokens: &[WildTok]) -> Option<String> {
    tokens
        .iter()
        .map(|t| match t {
            WildTok::Char(c) => Some(*c),
            _ => None,
        })
        .collect()
}

impl WildToken<char> for WildTok {
    fn is_any(&self) -> bool {
        *self == WildTok::Any
    }

    fn takes(&self, c: char) -> bool {
        match self {
            WildTok::One => true,
            WildTok::Char(x) => *x == c,
            WildTok::Any => false,
        }
    }
}

/// An ASCII text's bytes, its characters.
impl WildToken<u8> for WildTok {
    fn is_any(&self) -> bool {
        *self == WildTok::Any
    }

    fn takes(&self, c: u8) -> bool {
        self.takes(char::from(c))
    }
}

/// A token of a wildcard pattern for [`wild_match`]: `*`, which takes any run of characters,
/// or one that takes a single character `C` when [`WildToken::takes`] says so. Excel's
/// wildcards ([`Wildcard`]: `?`, `*`, `~`) and VBA's `Like` (`?`, `*`, `#`, `[…]` lists) are
/// two sets of tokens over the one matcher.
pub(crate) trait WildToken<C> {
    /// Whether this is `*`.
    fn is_any(&self) -> bool;
    /// Whether this token (not `*`) takes the character `c`.
    fn takes(&self, c: C) -> bool;
}

/// Whether `tokens` match the start of `text` (all of it when `whole`), and the steps taken:
/// greedy, returning only to the last `*` seen. Every other token takes one character, so a
/// later `*` can take whatever an earlier one would have, and a match is found when there is
/// one; at most the text's length times the pattern's steps, about their sum unless a long run
/// of single tokens after a `*` nearly matches at every position. No recursion and no table
/// over (token, position): the table VBA's `Like` had filled the rest of the text for each
/// position a `*` was reached at (`String(100000, "a") Like` 2,000 `*a` and a `*b`, past 30 s).
pub(crate) fn wild_match<C: Copy, T: WildToken<C>>(tokens: &[T], text: &[C], whole: bool) -> (bool, usize) {
    let (mut t, mut s, mut steps) = (0, 0, 0usize);
    // The last `*` and the text position it has taken up to.
    let mut star: Option<(usize, usize)> = None;
    loop {
        steps += 1;
        if t == tokens.len() && (!whole || s == text.len()) {
            return (true, steps);
        }
        if let Some(token) = tokens.get(t) {
            if token.is_any() {
                star = Some((t, s));
                t += 1;
                continue;
            }
            if text.get(s).is_some_and(|&c| token.takes(c)) {
                (t, s) = (t + 1, s + 1);
                continue;
            }
        }
        match star {
            Some((st, ss)) if ss < text.len() => {
                star = Some((st, ss + 1));
                (t, s) = (st + 1, ss + 1);
            }
            _ => return (false, steps),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Character codes

/// Windows-1252 characters for codes 128-159; the rest of 1-255 is Latin-1.
const CP1252_HIGH: [char; 32] = [
    '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8D}', 'Ž', '\u{8F}', '\u{90}',
    '\u{2018}', '\u{2019}', '\u{201C}', '\u{201D}', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9D}', 'ž', 'Ÿ',
];

fn char_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let code = to_number(&v[0], dates)?.trunc();
        if !(1.0..=255.0).contains(&code) {
            return Err(XlError::Value);
        }
        let code = code as u32;
        let c = match code {
            128..=159 => CP1252_HIGH[code as usize - 128],
            _ => char::from_u32(code).ok_or(XlError::Value)?,
        };
        Ok(Value::from(c.to_string()))
    })
}

fn code(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| {
        let c = first_char(&v[0])?;
        let code = match c as u32 {
            n @ (0..=127 | 160..=255) => n,
            // Characters outside Windows-1252 read as "?".
            _ => CP1252_HIGH.iter().position(|&x| x == c).map_or(63, |i| 128 + i as u32),
        };
        Ok(Value::Number(f64::from(code)))
    })
}

fn unichar(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let code = to_number(&v[0], dates)?.trunc();
        if !(1.0..=1_114_111.0).contains(&code) {
            return Err(XlError::Value);
        }
        let c = char::from_u32(code as u32).ok_or(XlError::NA)?;
        Ok(Value::from(c.to_string()))
    })
}

fn unicode(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift(ctx, args, &|v| Ok(Value::Number(f64::from(first_char(&v[0])? as u32))))
}

fn first_char(v: &Value) -> XlResult<char> {
    to_text(v)?.chars().next().ok_or(XlError::Value)
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::n;
    use crate::eval::testing::MapEnv;
    use crate::eval::{Array, Value, XlError};

    fn t(s: &str) -> Value {
        Value::text(s)
    }

    fn env() -> MapEnv {
        MapEnv::with(&[("A1", t("g01 x10")), ("A2", t("Y-5")), ("A3", n(12.5)), ("B1", t("園田 直子"))])
    }

    #[test]
    fn text_formats_numbers_like_excel() {
        let env = env();
        assert_eq!(env.eval("=TEXT(1234.5678,\"#,##0.00\")"), t("1,234.57"));
        assert_eq!(env.eval("=TEXT(2.5,\"0.000\")"), t("2.500"));
        assert_eq!(env.eval("=TEXT(-2.5,\"+0.000;-0.000\")"), t("-2.500"));
        assert_eq!(env.eval("=TEXT(0.256,\"0.0%\")"), t("25.6%"));
        assert_eq!(env.eval("=TEXT(1500,\"0.00E+00\")"), t("1.50E+03"));
        assert_eq!(env.eval("=TEXT(\"abc\",\"@\")"), t("abc"));
        assert_eq!(env.eval("=TEXT(\"12.5\",\"0.0\")"), t("12.5"));
        assert_eq!(env.eval("=TEXT(A3,\"\"\"X\"\"0.000\")"), t("X12.500"));
        assert_eq!(env.eval("=\"X\"&TEXT(-0.0004,\"0.000\")"), t("X0.000"));
        assert_eq!(env.eval("=1&TRUE"), t("1TRUE"));
    }

    // TEXT over an array lays out its code once (issue 30): the places of the integer, decimal
    // and exponent digits (or a fraction's parts) were worked out again for every item, and
    // in a locale other than en-US the code was scanned for date letters for every item too,
    // so a code of 30,000 placeholders over SEQUENCE(200000) did 6·10^9 steps of layout.
    // Values: k·1.125 is exact in binary, shown with three decimals by hand; in de-DE the
    // code is typed `#.##0,000` and shows `1.125,000` (Excel's and LibreOffice's de-DE marks:
    // `.` groups thousands, `,` is the decimal mark).
    #[test]
    fn a_code_is_laid_out_once_for_a_whole_array_in_any_locale() {
        use crate::eval::format::text_format::sections_laid_out;
        use crate::eval::locale::date_code_scans;
        let mut env = env();
        let before = sections_laid_out();
        let Value::Array(shown) = env.eval("=TEXT(SEQUENCE(1000)*1.125,\"#,##0.000\")") else { panic!("an array") };
        // Each section is laid out once: a look for a fraction's parts, then the digits'.
        assert_eq!(sections_laid_out() - before, 2);
        assert_eq!((shown.data[0].clone(), shown.data[999].clone()), (t("1.125"), t("1,125.000")));
        // Two sections (positive; negative): a fraction's parts, and the look and the digits.
        let before = sections_laid_out();
        let Value::Array(shown) = env.eval("=TEXT(SEQUENCE(1000)/4-125,\"0 ?/4;(0)\")") else { panic!("an array") };
        assert_eq!(sections_laid_out() - before, 3);
        // -124.75 in whole numbers is (125); 124.75 is 124 and 3 quarters.
        assert_eq!((shown.data[0].clone(), shown.data[998].clone()), (t("(125)"), t("124 3/4")));
        env.settings.locale = crate::eval::locale::Locale::from_tag("de-DE").expect("de-DE");
        let (laid_out, scans) = (sections_laid_out(), date_code_scans());
        let Value::Array(shown) = env.eval("=TEXT(SEQUENCE(1000)*1.125,\"#.##0,000\")") else { panic!("an array") };
        assert_eq!(sections_laid_out() - laid_out, 2);
        assert!(date_code_scans() - scans <= 2, "{} scans", date_code_scans() - scans);
        assert_eq!((shown.data[0].clone(), shown.data[999].clone()), (t("1,125"), t("1.125,000")));
    }

    #[test]
    fn a_format_of_one_value_is_parsed_once_for_a_whole_array() {
        use crate::eval::format::text_format::codes_parsed;
        let env = env();
        let before = codes_parsed();
        let shown = env.eval("=TEXT(SEQUENCE(1000)/8,\"#,##0.000\")");
        assert_eq!(codes_parsed() - before, 1);
        let Value::Array(shown) = shown else { panic!("TEXT over an array gives an array: {shown:?}") };
        // 1000/8 = 125 and 999/8 = 124.875, exactly, shown as Excel's #,##0.000 shows them.
        assert_eq!(shown.data.len(), 1000);
        assert_eq!(shown.data[0], t("0.125"));
        assert_eq!(shown.data[998], t("124.875"));
        assert_eq!(shown.data[999], t("125.000"));
        // A format per item is still read per item.
        assert_eq!(
            env.eval("=TEXT(2.5,{\"0.0\",\"0%\"})"),
            Value::Array(std::rc::Rc::new(Array::new(1, 2, vec![t("2.5"), t("250%")])))
        );
        // The value's error wins over the format's, and an unreadable format is #VALUE! for each item.
        assert_eq!(
            env.eval("=TEXT({1,\"x\"},1/0)"),
            Value::Array(std::rc::Rc::new(Array::new(
                1,
                2,
                vec![Value::Error(XlError::Div0), Value::Error(XlError::Div0)]
            )))
        );
        assert_eq!(env.eval("=TEXT({1;2},\"[Foo]0\")"), Value::Error(XlError::Value));
    }

    #[test]
    fn dollar_shows_currency_as_excel() {
        // Microsoft's DOLLAR examples: 1234.567 → "$1,234.57", with -2 → "$1,200",
        // -1234.567 with -2 → "($1,200)", -0.123 with 4 → "($0.1230)", 99.888 → "$99.89".
        let env = env();
        assert_eq!(env.eval("=DOLLAR(1234.567,2)"), t("$1,234.57"));
        assert_eq!(env.eval("=DOLLAR(1234.567,-2)"), t("$1,200"));
        assert_eq!(env.eval("=DOLLAR(-1234.567,-2)"), t("($1,200)"));
        assert_eq!(env.eval("=DOLLAR(-0.123,4)"), t("($0.1230)"));
        assert_eq!(env.eval("=DOLLAR(99.888)"), t("$99.89"));
    }

    #[test]
    fn fixed_rounds_and_groups() {
        let env = env();
        assert_eq!(env.eval("=FIXED(1234.567)"), t("1,234.57"));
        assert_eq!(env.eval("=FIXED(1234.567,1,TRUE)"), t("1234.6"));
        assert_eq!(env.eval("=FIXED(1234.567,-1)"), t("1,230"));
        assert_eq!(env.eval("=FIXED(-0.5,0)"), t("-1"));
        assert_eq!(env.eval("=FIXED(1,128)"), Value::Error(XlError::Value));
    }

    #[test]
    fn pieces_count_characters() {
        let env = env();
        assert_eq!(env.eval("=LEFT(B1,2)"), t("園田"));
        assert_eq!(env.eval("=RIGHT(B1)"), t("子"));
        assert_eq!(env.eval("=MID(A1,5,3)"), t("x10"));
        assert_eq!(env.eval("=MID(A1,0,3)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=MID(A1,50,3)"), t(""));
        assert_eq!(env.eval("=LEN(B1)"), n(5.0));
        assert_eq!(env.eval("=LEFT(A1,-1)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=LEN(A3)"), n(4.0));
    }

    #[test]
    fn case_trim_and_value() {
        let env = env();
        assert_eq!(env.eval("=UPPER(A1)"), t("G01 X10"));
        assert_eq!(env.eval("=LOWER(A2)"), t("y-5"));
        assert_eq!(env.eval("=PROPER(\"hello wORLD 2nd\")"), t("Hello World 2Nd"));
        assert_eq!(env.eval("=TRIM(\"  a   b  \")"), t("a b"));
        assert_eq!(env.eval("=VALUE(\"1,234.5\")"), n(1234.5));
        assert_eq!(env.eval("=VALUE(\"abc\")"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=VALUE(TRUE)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=VALUETOTEXT(1/0)"), t("#DIV/0!"));
        assert_eq!(env.eval("=VALUETOTEXT(\"a\",1)"), t("\"a\""));
        assert_eq!(env.eval("=UPPER(A1:A2)"), Value::from(Array::column(vec![t("G01 X10"), t("Y-5")])));
    }

    #[test]
    fn joining() {
        let env = env();
        assert_eq!(env.eval("=CONCAT(A1:A3,\"!\")"), t("g01 x10Y-512.5!"));
        assert_eq!(env.eval("=CONCATENATE(\"G\",1,TRUE)"), t("G1TRUE"));
        assert_eq!(env.eval("=TEXTJOIN(\" \",TRUE,A1:A4)"), t("g01 x10 Y-5 12.5"));
        assert_eq!(env.eval("=TEXTJOIN(\",\",FALSE,A2:A4)"), t("Y-5,12.5,"));
        assert_eq!(env.eval("=TEXTJOIN({\"-\",\"+\"},TRUE,1,2,3)"), t("1-2+3"));
        assert_eq!(env.eval("=REPT(\"ab\",3)"), t("ababab"));
        assert_eq!(env.eval("=REPT(\"ab\",20000)"), Value::Error(XlError::Value));
    }

    #[test]
    fn substitute_find_search() {
        let env = env();
        assert_eq!(env.eval("=SUBSTITUTE(\"a-b-c\",\"-\",\"+\")"), t("a+b+c"));
        assert_eq!(env.eval("=SUBSTITUTE(\"a-b-c\",\"-\",\"+\",2)"), t("a-b+c"));
        assert_eq!(env.eval("=SUBSTITUTE(\"a-b\",\"-\",\"+\",0)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=FIND(\"x\",A1)"), n(5.0));
        assert_eq!(env.eval("=FIND(\"X\",A1)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=SEARCH(\"X\",A1)"), n(5.0));
        assert_eq!(env.eval("=SEARCH(\"g?1\",A1)"), n(1.0));
        assert_eq!(env.eval("=SEARCH(\"x*0\",A1)"), n(5.0));
        assert_eq!(env.eval("=SEARCH(\"~*\",\"a*b\")"), n(2.0));
        assert_eq!(env.eval("=FIND(\"直\",B1)"), n(4.0));
        assert_eq!(env.eval("=FIND(\"\",A1,3)"), n(3.0));
        assert_eq!(env.eval("=EXACT(\"a\",\"A\")"), Value::Bool(false));
    }

    /// Examples from Microsoft's function reference pages.
    #[test]
    fn documented_examples() {
        let env = env();
        assert_eq!(env.eval("=TEXT(1234.567,\"$#,##0.00\")"), t("$1,234.57"));
        assert_eq!(env.eval("=TEXT(0.285,\"0.0%\")"), t("28.5%"));
        assert_eq!(env.eval("=TEXT(12200000,\"0.00E+00\")"), t("1.22E+07"));
        assert_eq!(env.eval("=TEXT(1234,\"0000000\")"), t("0001234"));
        assert_eq!(env.eval("=FIXED(1234.567,1)"), t("1,234.6"));
        assert_eq!(env.eval("=FIXED(-1234.567,-1,TRUE)"), t("-1230"));
        assert_eq!(env.eval("=FIXED(44.332)"), t("44.33"));
        assert_eq!(env.eval("=SEARCH(\"e\",\"Statements\",6)"), n(7.0));
        assert_eq!(env.eval("=SEARCH(\"margin\",\"Profit Margin\")"), n(8.0));
        assert_eq!(env.eval("=FIND(\"m\",\"Miriam McGovern\")"), n(6.0));
        assert_eq!(env.eval("=FIND(\"M\",\"Miriam McGovern\",3)"), n(8.0));
        assert_eq!(env.eval("=MID(\"Fluid Flow\",7,20)"), t("Flow"));
        assert_eq!(env.eval("=MID(\"Fluid Flow\",20,5)"), t(""));
        assert_eq!(env.eval("=SUBSTITUTE(\"Quarter 1, 2011\",\"1\",\"2\",3)"), t("Quarter 1, 2012"));
        assert_eq!(env.eval("=PROPER(\"76BudGet\")"), t("76Budget"));
        assert_eq!(env.eval("=PROPER(\"2-way street\")"), t("2-Way Street"));
        assert_eq!(env.eval("=TRIM(\" First Quarter   Earnings \")"), t("First Quarter Earnings"));
    }

    #[test]
    fn character_codes() {
        let env = env();
        assert_eq!(env.eval("=CHAR(65)"), t("A"));
        assert_eq!(env.eval("=CHAR(128)"), t("€"));
        assert_eq!(env.eval("=CODE(\"€\")"), n(128.0));
        assert_eq!(env.eval("=UNICODE(\"の\")"), n(12398.0));
        assert_eq!(env.eval("=UNICHAR(960)"), t("π"));
        assert_eq!(env.eval("=CHAR(0)"), Value::Error(XlError::Value));
    }
}
