//! Numbers as text and text as numbers (ROMAN, ARABIC, BASE, DECIMAL), REPLACE, CLEAN and
//! the regular-expression functions (REGEXTEST, REGEXEXTRACT, REGEXREPLACE, through the
//! `regex` crate, whose syntax is PCRE2's for what workbooks use, within the limits of
//! `eval/regex_limits.rs`).

use std::cell::RefCell;
use std::rc::Rc;

use crate::eval::functions::api::{check, scalar, Ctx, FnSpec, Scalars};
use crate::eval::regex_limits::{self, Pattern, PatternError};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "ROMAN",
        1,
        2,
        roman,
        "ROMAN(number, [form])",
        "0..3999 as a Roman numeral; form 0 (classic) to 4 (most concise)",
    )
    .biff(354),
    FnSpec::value("ARABIC", 1, 1, arabic, "ARABIC(text)", "A Roman numeral as a number").future(),
    FnSpec::value(
        "BASE",
        2,
        3,
        base,
        "BASE(number, radix, [min_length])",
        "A whole number as text in radix 2..36, padded with zeros to min_length",
    )
    .future(),
    FnSpec::value("DECIMAL", 2, 2, decimal, "DECIMAL(text, radix)", "Text in radix 2..36 as a number").future(),
    FnSpec::value(
        "REPLACE",
        4,
        4,
        replace,
        "REPLACE(old_text, start_num, num_chars, new_text)",
        "Replaces num_chars characters from position start_num with new_text",
    )
    .biff(119),
    FnSpec::value("CLEAN", 1, 1, clean, "CLEAN(text)", "Removes the control characters 0..31").biff(162),
    FnSpec::value(
        "REGEXTEST",
        2,
        3,
        regex_test,
        "REGEXTEST(text, pattern, [case_sensitivity])",
        "TRUE when the pattern matches part of text; case_sensitivity 1 ignores case",
    )
    .future(),
    FnSpec::value(
        "REGEXEXTRACT",
        2,
        4,
        regex_extract,
        "REGEXEXTRACT(text, pattern, [return_mode], [case_sensitivity])",
        "The first match (mode 0), all matches (1) or the first match's groups (2)",
    )
    .future(),
    FnSpec::value(
        "REGEXREPLACE",
        3,
        5,
        regex_replace,
        "REGEXREPLACE(text, pattern, replacement, [occurrence], [case_sensitivity])",
        "Replaces every match (or the occurrence-th, negative from the end); $1 names a group",
    )
    .future(),
];

/// Roman digits, largest first: even indexes are the powers of ten.
const SYMBOLS: [(char, u32); 7] = [('M', 1000), ('D', 500), ('C', 100), ('L', 50), ('X', 10), ('V', 5), ('I', 1)];

fn roman(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = a.num(0)?.trunc();
        check((0.0..=3999.0).contains(&n), XlError::Value)?;
        let form = match a.value(1) {
            Value::Bool(true) => 0.0,
            Value::Bool(false) => 4.0,
            _ => a.num_or(1, 0.0)?.trunc(),
        };
        check((0.0..=4.0).contains(&form), XlError::Value)?;
        Ok(Value::text(roman_numeral(n as u32, form as u32)))
    })
}

/// Excel's Roman numerals: form 0 writes 499 as CDXCIX; each further form lets a 4 or a 9
/// be written by one more step of a smaller subtracted digit (form 1: LDVLIV, form 4: ID).
fn roman_numeral(mut n: u32, form: u32) -> String {
    let mut out = String::new();
    for ten in (0..SYMBOLS.len()).step_by(2) {
        let unit = SYMBOLS[ten].1;
        let digit = n / unit;
        if digit % 5 == 4 {
            // 4 → five-symbol minus unit, 9 → ten-symbol minus unit.
            let big = if digit == 4 { ten - 1 } else { ten - 2 };
            let mut small = ten;
            for _ in 0..form {
                if small + 1 < SYMBOLS.len() && SYMBOLS[big].1 - SYMBOLS[small + 1].1 <= n {
                    small += 1;
                } else {
                    break;
                }
            }
            out.push(SYMBOLS[small].0);
            out.push(SYMBOLS[big].0);
            n = n + SYMBOLS[small].1 - SYMBOLS[big].1;
        } else {
            if digit >= 5 {
                out.push(SYMBOLS[ten - 1].0);
            }
            out.extend(std::iter::repeat_n(SYMBOLS[ten].0, (digit % 5) as usize));
            n %= unit;
        }
    }
    out
}

fn arabic(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let text = a.text(0)?;
        check(text.chars().count() <= 255, XlError::Value)?;
        let trimmed = text.trim_matches(' ');
        let (sign, digits) = match trimmed.strip_prefix('-') {
            Some(rest) => (-1.0, rest),
            None => (1.0, trimmed),
        };
        let mut total = 0i64;
        let mut largest = 0;
        // From the right: a digit smaller than one after it subtracts.
        for c in digits.chars().rev() {
            let c = c.to_ascii_uppercase();
            let Some(&(_, v)) = SYMBOLS.iter().find(|(s, _)| *s == c) else { return Err(XlError::Value) };
            if v < largest {
                total -= i64::from(v);
            } else {
                total += i64::from(v);
                largest = v;
            }
        }
        Ok(Value::Number(sign * total as f64))
    })
}

const DIGITS: &[u8; 36] = b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";

fn base(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = a.num(0)?.trunc();
        let radix = a.num(1)?.trunc();
        let min_len = a.num_or(2, 0.0)?.trunc();
        check((0.0..9007199254740992.0).contains(&n), XlError::Num)?;
        check((2.0..=36.0).contains(&radix) && (0.0..=255.0).contains(&min_len), XlError::Num)?;
        let mut text = to_radix(n as u64, radix as u64);
        while text.len() < min_len as usize {
            text.insert(0, '0');
        }
        Ok(Value::text(text))
    })
}

/// `n` written in `radix` (2..36), upper-case digits.
pub fn to_radix(mut n: u64, radix: u64) -> String {
    let mut digits = Vec::new();
    loop {
        digits.push(DIGITS[(n % radix) as usize]);
        n /= radix;
        if n == 0 {
            break;
        }
    }
    digits.reverse();
    String::from_utf8(digits).expect("ASCII digits")
}

fn decimal(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let text = a.text(0)?;
        let radix = a.num(1)?.trunc();
        check((2.0..=36.0).contains(&radix), XlError::Num)?;
        check(text.chars().count() <= 255, XlError::Value)?;
        let mut total = 0.0f64;
        for c in text.chars() {
            let d = c.to_digit(36).ok_or(XlError::Num)?;
            check(f64::from(d) < radix, XlError::Num)?;
            total = total * radix + f64::from(d);
        }
        check(total < 9007199254740992.0, XlError::Num)?;
        Ok(Value::Number(total))
    })
}

fn replace(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let old = a.text(0)?;
        let start = a.num(1)?.trunc();
        let count = a.num(2)?.trunc();
        let new = a.text(3)?;
        check(start >= 1.0 && count >= 0.0, XlError::Value)?;
        let chars: Vec<char> = old.chars().collect();
        let from = ((start - 1.0) as usize).min(chars.len());
        let to = from.saturating_add(count.min(usize::MAX as f64) as usize).min(chars.len());
        let mut out: String = chars[..from].iter().collect();
        out.push_str(&new);
        out.extend(&chars[to..]);
        Ok(Value::text(out))
    })
}

fn clean(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| Ok(Value::text(a.text(0)?.chars().filter(|&c| c as u32 >= 32).collect::<String>())))
}

/// A limit of `eval/regex_limits.rs` one item met, noted once the lifted call returns (its
/// closure cannot reach the context).
type Refusal = RefCell<Option<String>>;

/// `#NUM!`, the reason kept for the cell's note.
fn refuse(refusal: &Refusal, why: impl std::fmt::Display) -> XlError {
    *refusal.borrow_mut() = Some(why.to_string());
    XlError::Num
}

/// `result`, with the limit an item met named in the cell's note.
fn explained(ctx: &mut Ctx, name: &str, refusal: Refusal, result: XlResult<Value>) -> XlResult<Value> {
    if let Some(why) = refusal.into_inner() {
        ctx.explain(XlError::Num, format!("{name}: {why}"));
    }
    result
}

/// The pattern of argument `pattern`, case-insensitive when argument `case` is 1: `#VALUE!`
/// when it does not parse (Excel's error), `#NUM!` past a limit of `regex_limits`.
fn pattern(a: Scalars, pattern: usize, case: usize, refusal: &Refusal) -> XlResult<Pattern> {
    let text = a.text(pattern)?;
    let case = a.num_or(case, 0.0)?.trunc();
    check(case == 0.0 || case == 1.0, XlError::Value)?;
    regex_limits::compile(&text, case == 1.0).map_err(|e| match e {
        PatternError::Syntax(_) => XlError::Value,
        limit => refuse(refusal, limit),
    })
}

/// Argument 0, the text searched, and argument `at` its pattern, once a search of the text
/// with the pattern is within the work limit.
fn searched(a: Scalars, at: usize, case: usize, refusal: &Refusal) -> XlResult<(Rc<str>, Pattern)> {
    let text = a.text(0)?;
    let re = pattern(a, at, case, refusal)?;
    re.check(&text).map_err(|work| refuse(refusal, work))?;
    Ok((text, re))
}

fn regex_test(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let refusal = Refusal::default();
    let result = scalar(ctx, args, &|a| {
        let (text, re) = searched(a, 1, 2, &refusal)?;
        Ok(Value::Bool(re.regex.is_match(&text)))
    });
    explained(ctx, "REGEXTEST", refusal, result)
}

fn regex_extract(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let refusal = Refusal::default();
    let result = scalar(ctx, args, &|a| {
        let (text, pattern) = searched(a, 1, 3, &refusal)?;
        let re = &pattern.regex;
        let mode = a.num_or(2, 0.0)?.trunc();
        // Every match, across a row: Excel spills them to the right (calc_tests/TEXT/REGEX.xlsx).
        let texts = |items: Vec<Value>| -> XlResult<Value> {
            check(!items.is_empty(), XlError::NA)?;
            Ok(Value::Array(Rc::new(Array::row(items))))
        };
        match mode {
            0.0 => re.find(&text).map(|m| Value::text(m.as_str())).ok_or(XlError::NA),
            1.0 => {
                let mut searches = pattern.searches(&text);
                let found = searches.charged(re.find_iter(&text), |m| (m.start(), m.end()));
                let items = found.map(|m| m.map(|m| Value::text(m.as_str()))).collect::<Result<_, _>>();
                texts(items.map_err(|work| refuse(&refusal, work))?)
            }
            2.0 => {
                let caps = re.captures(&text).ok_or(XlError::NA)?;
                let groups: Vec<Value> =
                    caps.iter().skip(1).map(|g| Value::text(g.map_or("", |m| m.as_str()))).collect();
                check(!groups.is_empty(), XlError::NA)?;
                Ok(Value::Array(Rc::new(Array::row(groups))))
            }
            _ => Err(XlError::Value),
        }
    });
    explained(ctx, "REGEXEXTRACT", refusal, result)
}

fn regex_replace(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let refusal = Refusal::default();
    let result = scalar(ctx, args, &|a| {
        let (text, pattern) = searched(a, 1, 4, &refusal)?;
        let re = &pattern.regex;
        let replacement = a.text(2)?;
        let occurrence = a.num_or(3, 0.0)?.trunc();
        let mut searches = pattern.searches(&text);
        let whole = |caps: &regex::Captures| caps.get(0).map_or((0, 0), |m| (m.start(), m.end()));
        let found = searches.charged(re.captures_iter(&text), whole);
        let matches = found.collect::<Result<Vec<_>, _>>().map_err(|work| refuse(&refusal, work))?;
        if occurrence == 0.0 {
            return Ok(Value::text(replaced_all(&text, &matches, &replacement)));
        }
        let index =
            if occurrence > 0.0 { occurrence as usize - 1 } else { matches.len().wrapping_sub((-occurrence) as usize) };
        let Some(caps) = matches.get(index) else { return Ok(Value::Text(text)) };
        let whole = caps.get(0).expect("a match has group 0");
        let mut out = String::from(&text[..whole.start()]);
        caps.expand(&replacement, &mut out);
        out.push_str(&text[whole.end()..]);
        Ok(Value::text(out))
    });
    explained(ctx, "REGEXREPLACE", refusal, result)
}

/// `text` with each match replaced, `$1` and `${name}` naming its groups (the crate's
/// `replace_all`, its matches found within the work limit).
fn replaced_all(text: &str, matches: &[regex::Captures], replacement: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    for caps in matches {
        let whole = caps.get(0).expect("a match has group 0");
        out.push_str(&text[copied..whole.start()]);
        caps.expand(replacement, &mut out);
        copied = whole.end();
    }
    out.push_str(&text[copied..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roman_forms_follow_excel_help() {
        // Excel's help for ROMAN: 499 in forms 0..4.
        let forms: Vec<String> = (0..5).map(|f| roman_numeral(499, f)).collect();
        assert_eq!(forms, ["CDXCIX", "LDVLIV", "XDIX", "VDIV", "ID"]);
        assert_eq!(roman_numeral(0, 0), "");
        assert_eq!(roman_numeral(3999, 0), "MMMCMXCIX");
    }
}
