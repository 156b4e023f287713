//! VBA's text and inspection functions beyond the first set: `Split`, `Join`, `InStrRev`,
//! `StrComp`, `StrConv`, `ChrW`, `LenB`, `FormatNumber`, `VarType`, `IsArray`, `CVErr`, and
//! the two that read the document's state, `Timer` (its clock) and `Rnd` (its random
//! sequence). The rules are the Office VBA language reference's pages of the same names.

use std::borrow::Cow;

use crate::eval::coerce::to_number;
use crate::eval::functions::api::{given, Ctx};
use crate::eval::functions::text::strings::lower_char;
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::Expr;

use super::{format_number, invalid_call, invalid_use_of_null, vba_text};

/// `compare` of InStr, InStrRev, StrComp and Split: vbTextCompare (1) ignores case;
/// vbBinaryCompare (0) compares character codes; vbUseCompareOption (-1) and no argument
/// follow the module's Option Compare. Any other is run-time error 5 for `name`.
fn text_compare(ctx: &mut Ctx, name: &str, args: &[Expr], i: usize) -> XlResult<bool> {
    let Some(e) = given(args, i) else { return Ok(ctx.option_compare_text()) };
    let dates = ctx.dates();
    match to_number(&ctx.eval(e).unwrap_single(), dates)?.trunc() {
        1.0 => Ok(true),
        0.0 => Ok(false),
        -1.0 => Ok(ctx.option_compare_text()),
        _ => Err(invalid_call(ctx, name, "compare is vbBinaryCompare (0) or vbTextCompare (1)")),
    }
}

/// One character in the case a textual comparison reads (one for one, so positions hold).
fn fold_case(c: char) -> char {
    lower_char(c).unwrap_or(c)
}

/// A text argument; Null is run-time error 94 (`name` needs a String there).
fn text_arg(ctx: &mut Ctx, name: &str, args: &[Expr], i: usize) -> XlResult<String> {
    match text_or_null(ctx, args, i)? {
        Some(text) => Ok(text),
        None => Err(invalid_use_of_null(ctx, name)),
    }
}

/// A text argument, `None` for Null: InStr, InStrRev and StrComp then return Null ("If
/// string1 is Null", "If string1 or string2 is Null" on their pages).
fn text_or_null(ctx: &mut Ctx, args: &[Expr], i: usize) -> XlResult<Option<String>> {
    match super::text_argument(ctx, &args[i]).unwrap_single() {
        Value::Null => Ok(None),
        v => Ok(Some(vba_text(&v)?.to_string())),
    }
}

/// A whole-number argument (`default` when left out); Null is run-time error 94.
fn whole_arg(ctx: &mut Ctx, name: &str, args: &[Expr], i: usize, default: f64) -> XlResult<f64> {
    let dates = ctx.dates();
    match given(args, i).map(|e| ctx.eval(e).unwrap_single()) {
        Some(Value::Null) => Err(invalid_use_of_null(ctx, name)),
        Some(v) => Ok(to_number(&v, dates)?.trunc()),
        None => Ok(default),
    }
}

/// A text as a search of InStr, InStrRev, Split, Filter or Replace reads it: as it is for a
/// binary comparison, folded for a textual one (ASCII a byte at a time, other characters one
/// for one by [`fold_case`]), searched as bytes in linear time (memchr's two-way `memmem`).
/// The places found are bytes of the folded text; [`Searched::at_byte`] and
/// [`Searched::at_char`] turn them into the characters VBA counts and the text's own bytes,
/// walking forward (an ASCII text's bytes are its characters). Folding both texts into lists
/// of characters and comparing a character at a time cost 20–25 ns a character, several times
/// what the statement limit counts for the text read: InStr, InStrRev, Split and Replace with
/// vbTextCompare of a million characters, 200 times, ran 22 s within the limit.
pub(super) struct Searched<'a> {
    text: &'a str,
    folded: Cow<'a, str>,
    ascii: bool,
    /// Each folded character takes the bytes its character does (all but a few, as the Kelvin
    /// sign): a byte of one is the same byte of the other, and characters are counted by the
    /// bytes that start them.
    same_widths: bool,
    /// Where the last walk stopped.
    at: Place,
}

/// A place in a [`Searched`] text: its byte in the folded text, in the text, and the
/// characters before it.
#[derive(Clone, Copy, Default)]
pub(super) struct Place {
    pub(super) folded: usize,
    pub(super) text: usize,
    pub(super) chars: usize,
}

impl<'a> Searched<'a> {
    pub(super) fn new(text: &'a str, ignore_case: bool) -> Searched<'a> {
        let ascii = text.is_ascii();
        let (folded, same_widths) = match (ignore_case, ascii) {
            (false, _) => (Cow::Borrowed(text), true),
            (true, true) => (Cow::Owned(text.to_ascii_lowercase()), true),
            (true, false) => {
                let (mut folded, mut same_widths) = (String::with_capacity(text.len()), true);
                for c in text.chars() {
                    let f = fold_case(c);
                    same_widths &= f.len_utf8() == c.len_utf8();
                    folded.push(f);
                }
                (Cow::Owned(folded), same_widths)
            }
        };
        Searched { text, folded, ascii, same_widths, at: Place::default() }
    }

    /// The folded text, searched.
    pub(super) fn bytes(&self) -> &[u8] {
        self.folded.as_bytes()
    }

    /// The text searched (not folded): what the pieces between the places found are cut from.
    pub(super) fn text(&self) -> &'a str {
        self.text
    }

    /// How many characters the text has.
    pub(super) fn char_count(&mut self) -> usize {
        match self.ascii {
            true => self.text.len(),
            false => self.at_byte(self.folded.len()).chars,
        }
    }

    /// The place of the folded text's byte `folded`, which starts a character (or ends the text).
    pub(super) fn at_byte(&mut self, folded: usize) -> Place {
        if self.ascii {
            return Place { folded, text: folded, chars: folded };
        }
        if self.at.folded > folded {
            self.at = Place::default();
        }
        if self.same_widths {
            let starts = char_starts(&self.folded.as_bytes()[self.at.folded..folded]);
            self.at = Place { folded, text: folded, chars: self.at.chars + starts };
        }
        while self.at.folded < folded && self.step() {}
        self.at
    }

    /// The place where character `n` (0-based) starts, the end for `n` the character count;
    /// `None` past it.
    pub(super) fn at_char(&mut self, n: usize) -> Option<Place> {
        if self.ascii {
            return (n <= self.text.len()).then_some(Place { folded: n, text: n, chars: n });
        }
        if self.at.chars > n {
            self.at = Place::default();
        }
        if self.same_widths {
            let mut left = n - self.at.chars;
            let bytes = &self.folded.as_bytes()[self.at.folded..];
            // The byte that starts the `left`-th character on, or the end after the last.
            let found = bytes.iter().enumerate().filter(|(_, &b)| is_char_start(b)).map(|(i, _)| i).nth(left);
            let at = match found {
                Some(i) => self.at.folded + i,
                None => {
                    left -= char_starts(bytes);
                    if left > 0 {
                        self.at = Place { folded: self.folded.len(), text: self.folded.len(), chars: n - left };
                        return None;
                    }
                    self.folded.len()
                }
            };
            self.at = Place { folded: at, text: at, chars: n };
            return Some(self.at);
        }
        while self.at.chars < n {
            if !self.step() {
                return None;
            }
        }
        Some(self.at)
    }

    /// One character on, in both texts (a folded character may take other bytes than its own:
    /// the Kelvin sign's three are k's one); false at the end.
    fn step(&mut self) -> bool {
        let Some(c) = self.text[self.at.text..].chars().next() else { return false };
        let f = self.folded[self.at.folded..].chars().next().expect("a folded character for each");
        self.at.text += c.len_utf8();
        self.at.folded += f.len_utf8();
        self.at.chars += 1;
        true
    }
}

/// Whether a UTF-8 byte starts a character (is no continuation byte).
fn is_char_start(b: u8) -> bool {
    b & 0xC0 != 0x80
}

/// How many characters start among `bytes`.
fn char_starts(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| is_char_start(b)).count()
}

/// Where `needle` is found in `hay` (both [`Searched`] alike) at or after the folded byte
/// `from`: the folded byte it starts at.
pub(super) fn find_from(hay: &Searched, needle: &Searched, from: usize) -> Option<usize> {
    memchr::memmem::find(&hay.bytes()[from..], needle.bytes()).map(|at| from + at)
}

/// `InStr([start,] string1, string2[, compare])`: with four arguments the first is the start.
pub fn instr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (start, text_at) = if args.len() >= 3 { (whole_arg(ctx, "InStr", args, 0, 1.0)?, 1) } else { (1.0, 0) };
    // "InStr function": start below 1 is run-time error 5.
    if start < 1.0 {
        return Err(invalid_call(ctx, "InStr", "start is below 1"));
    }
    let ignore_case = if args.len() == 4 { text_compare(ctx, "InStr", args, 3)? } else { ctx.option_compare_text() };
    let (Some(text), Some(find)) = (text_or_null(ctx, args, text_at)?, text_or_null(ctx, args, text_at + 1)?) else {
        return Ok(Value::Null);
    };
    // Both texts are read whole (folded) whatever the answer.
    ctx.charge_read(text.len() + find.len());
    let (mut hay, needle) = (Searched::new(&text, ignore_case), Searched::new(&find, ignore_case));
    let start = start.min(usize::MAX as f64) as usize;
    let Some(from) = hay.at_char(start - 1) else { return Ok(Value::Number(0.0)) };
    let found = find_from(&hay, &needle, from.folded).map(|at| hay.at_byte(at).chars + 1);
    Ok(Value::Number(found.map_or(0.0, |i| i as f64)))
}

/// `InStrRev(stringcheck, stringmatch[, start[, compare]])`: the last match that ends at or
/// before `start` (-1: the last character); 0 when `start` is past the text.
pub fn instr_rev(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let ignore_case = text_compare(ctx, "InStrRev", args, 3)?;
    let (Some(text), Some(find)) = (text_or_null(ctx, args, 0)?, text_or_null(ctx, args, 1)?) else {
        return Ok(Value::Null);
    };
    ctx.charge_read(text.len() + find.len());
    let (mut hay, mut needle) = (Searched::new(&text, ignore_case), Searched::new(&find, ignore_case));
    let start = whole_arg(ctx, "InStrRev", args, 2, -1.0)?;
    if start == 0.0 || start < -1.0 {
        return Err(invalid_call(ctx, "InStrRev", "start is 0 or below -1"));
    }
    let count = hay.char_count();
    if count == 0 {
        return Ok(Value::Number(0.0));
    }
    let start = if start == -1.0 { count } else { start.min(usize::MAX as f64) as usize };
    if start > count {
        return Ok(Value::Number(0.0));
    }
    if needle.char_count() == 0 {
        return Ok(Value::Number(start as f64));
    }
    // The last match that ends at or before character `start`.
    let end = hay.at_char(start).expect("start is within the text").folded;
    let found = memchr::memmem::rfind(&hay.bytes()[..end], needle.bytes()).map(|at| hay.at_byte(at).chars + 1);
    Ok(Value::Number(found.map_or(0.0, |i| i as f64)))
}

/// `StrComp(string1, string2[, compare])`: -1, 0 or 1.
pub fn str_comp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let ignore_case = text_compare(ctx, "StrComp", args, 2)?;
    let (Some(a), Some(b)) = (text_or_null(ctx, args, 0)?, text_or_null(ctx, args, 1)?) else {
        return Ok(Value::Null);
    };
    ctx.charge_read(a.len() + b.len());
    Ok(Value::Number(match compare_texts(&a, &b, ignore_case) {
        std::cmp::Ordering::Less => -1.0,
        std::cmp::Ordering::Equal => 0.0,
        std::cmp::Ordering::Greater => 1.0,
    }))
}

/// Two texts in the order a comparison of `ignore_case` gives, a character at a time: UTF-8's
/// byte order is that of the characters, and a textual comparison folds as it goes, ASCII a
/// byte at a time (both texts folded whole into lists of characters first cost 20 ns a
/// character, three times what the statement limit counts for them: `StrComp(a, b,
/// vbTextCompare)` of two 10-million-character texts in a loop ran 45 s within the limit).
fn compare_texts(a: &str, b: &str, ignore_case: bool) -> std::cmp::Ordering {
    if !ignore_case {
        return a.cmp(b);
    }
    if a.is_ascii() && b.is_ascii() {
        return a.bytes().map(|c| c.to_ascii_lowercase()).cmp(b.bytes().map(|c| c.to_ascii_lowercase()));
    }
    a.chars().map(fold_case).cmp(b.chars().map(fold_case))
}

/// `Split(expression[, delimiter[, limit[, compare]]])`: a zero-based one-dimensional array
/// of texts; `""` gives an array with no items, a `""` delimiter the whole text as one item,
/// and at `limit` items the last holds the rest unsplit.
pub fn split(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let text = text_arg(ctx, "Split", args, 0)?;
    let delimiter = match given(args, 1) {
        Some(_) => text_arg(ctx, "Split", args, 1)?,
        None => " ".to_string(),
    };
    let limit = whole_arg(ctx, "Split", args, 2, -1.0)?;
    if limit < -1.0 {
        return Err(invalid_call(ctx, "Split", "limit is below -1"));
    }
    let ignore_case = text_compare(ctx, "Split", args, 3)?;
    if text.is_empty() || limit == 0.0 {
        return Ok(Value::from(Array::row(Vec::new())));
    }
    let limit = if limit == -1.0 { usize::MAX } else { limit as usize };
    // The whole text is read, however few items it gives (the items are counted as made).
    ctx.charge_read(text.len());
    let (mut hay, needle) = (Searched::new(&text, ignore_case), Searched::new(&delimiter, ignore_case));
    let mut items = Vec::new();
    let mut from = Place::default();
    // Refused like every array builder past the limit (a macro's `--max-array-items`).
    let most = ctx.array_item_limit();
    while !needle.bytes().is_empty() && items.len() + 1 < limit {
        let Some(at) = find_from(&hay, &needle, from.folded) else { break };
        if items.len() + 2 > most {
            // This item and the last one after it.
            ctx.room_for(1, items.len() + 2)?;
        }
        let (start, end) = (hay.at_byte(at), hay.at_byte(at + needle.bytes().len()));
        items.push(Value::text(&hay.text()[from.text..start.text]));
        from = end;
    }
    items.push(Value::text(&hay.text()[from.text..]));
    Ok(Value::from(Array::row(items)))
}

/// `Filter(sourcearray, match[, include[, compare]])` ("Filter function"): a zero-based array
/// of the items of `sourcearray` that contain `match` (`include` True, the default) or that do
/// not (False), compared as `compare` says (as InStr: the module's Option Compare when left
/// out); no item kept gives an array with no items. Excel's worksheet FILTER, a different
/// function, answered the bare name in a macro before.
pub fn filter(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let items = source_array(ctx, "Filter", args, 9)?;
    let wanted = text_arg(ctx, "Filter", args, 1)?;
    let include = match given(args, 2).map(|e| ctx.eval(e).unwrap_single()) {
        Some(v) => super::vba_bool(&v)?,
        None => true,
    };
    let ignore_case = text_compare(ctx, "Filter", args, 3)?;
    let needle = Searched::new(&wanted, ignore_case);
    // Each item is read (its text counted below), whatever is kept.
    ctx.charge(items.data.len());
    let mut kept = Vec::new();
    for item in items.data.iter() {
        let text = vba_text(item)?;
        ctx.charge_read(text.len());
        let found = find_from(&Searched::new(&text, ignore_case), &needle, 0).is_some();
        if found == include {
            kept.push(Value::Text(text));
        }
    }
    Ok(Value::from(Array::row(kept)))
}

/// The `sourcearray` of Join and Filter, a one-dimensional array: "An error occurs if
/// sourcearray is Null or is not a one-dimensional array" (Visual Basic 6's "Filter
/// Function"), raised with the number Microsoft's Visual Basic runtime keeps for Visual Basic
/// 6 code ("Join Function (Visual Basic)": 5, "Filter Function (Visual Basic)": 9, in their
/// Exceptions tables). Several rows are two dimensions (a Range's value).
fn source_array(ctx: &mut Ctx, name: &str, args: &[Expr], code: u32) -> XlResult<std::rc::Rc<Array>> {
    let why = match ctx.eval(&args[0]) {
        // Each item as the String its type writes ([`Ctx::macro_item_texts`]).
        Value::Array(items) if items.rows <= 1 && items.tail.is_none() => {
            return Ok(ctx.macro_item_texts(&args[0], &items).unwrap_or(items))
        }
        Value::Array(_) => "its array has two dimensions; give it a one-dimensional array",
        _ => "it takes a one-dimensional array, and was given a single value",
    };
    Err(ctx.raise_vba(XlError::Value, code, super::errors::message(code, format_args!("{name}: {why}"))))
}

/// `Join(sourcearray[, delimiter])`: the items' texts with the delimiter (a space when
/// omitted) between them.
pub fn join(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let items = source_array(ctx, "Join", args, 5)?;
    let delimiter = match given(args, 1) {
        Some(_) => text_arg(ctx, "Join", args, 1)?,
        None => " ".to_string(),
    };
    // Each item is read; the text made is counted as every result is.
    ctx.charge(items.data.len());
    let texts = items.data.iter().map(vba_text).collect::<XlResult<Vec<_>>>()?;
    // Measured before it is built: 5,000,001 empty items joined by 1,000 characters
    // asked for 5 GB at once.
    let delimiters = delimiter.len().saturating_mul(texts.len().saturating_sub(1));
    let length = texts.iter().fold(delimiters, |sum, t| sum.saturating_add(t.len()));
    if length > ctx.text_limit() {
        return Err(ctx.text_over_limit());
    }
    Ok(Value::text(texts.join(delimiter.as_str())))
}

/// `StrConv(string, conversion)`: vbUpperCase (1), vbLowerCase (2), vbProperCase (3: the
/// first letter of every word a capital, the rest small), vbFromUnicode (128: the text's bytes
/// in the system's code page, Windows-1252 for a Western Excel, as a Byte array from 0) and
/// vbUnicode (64: such bytes back to text). The East Asian conversions have no meaning for
/// ncsheet's Unicode text: `#VALUE!`.
pub fn str_conv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let conversion = whole_arg(ctx, "StrConv", args, 1, 0.0)?;
    if conversion == VB_UNICODE {
        return text_of_ansi_bytes(ctx, args);
    }
    let text = text_arg(ctx, "StrConv", args, 0)?;
    if conversion == VB_FROM_UNICODE {
        return Ok(Value::from(Array::row(text.chars().map(|c| Value::Number(f64::from(ansi_byte(c)))).collect())));
    }
    Ok(Value::text(match conversion {
        1.0 => text.to_uppercase(),
        2.0 => text.to_lowercase(),
        3.0 => proper_case(&text),
        _ => {
            return Err(
                ctx.explain(XlError::Value, "StrConv converts with vbUpperCase, vbLowerCase or vbProperCase only")
            )
        }
    }))
}

/// StrConv's vbUnicode and vbFromUnicode ("StrConv function": 64 and 128).
const VB_UNICODE: f64 = 64.0;
const VB_FROM_UNICODE: f64 = 128.0;

/// A character's byte in Windows-1252, "?" (63) for one it has not, as Windows converts it
/// (Asc reads the same code page).
fn ansi_byte(c: char) -> u8 {
    let mut unit = [0u8; 4];
    let (bytes, _, unmappable) = encoding_rs::WINDOWS_1252.encode(c.encode_utf8(&mut unit));
    if unmappable {
        b'?'
    } else {
        bytes[0]
    }
}

/// `StrConv(bytes, vbUnicode)`: a Byte array (0 to 255 each) read as Windows-1252 text. A
/// String's own bytes, UTF-16 little-endian as VBA holds it, are read the same way ("StrConv
/// function": vbUnicode converts the string to Unicode using the system's default code page),
/// so `StrConv("12", vbUnicode)` is "1", vbNullChar, "2", vbNullChar: a real module splits that
/// at vbNullChar to get the characters one by one.
fn text_of_ansi_bytes(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let bytes = match ctx.eval(&args[0]).unwrap_single() {
        Value::Array(a) => a.data.iter().map(|v| to_number(v, dates)).collect::<XlResult<Vec<f64>>>()?,
        Value::Error(e) => return Err(e),
        other => {
            let text = vba_text(&other)?;
            text.encode_utf16().flat_map(u16::to_le_bytes).map(f64::from).collect()
        }
    };
    if bytes.iter().any(|b| !(0.0..=255.0).contains(b) || b.fract() != 0.0) {
        return Err(
            ctx.explain(XlError::Value, "StrConv(…, vbUnicode): the array holds a number that is no byte (0 to 255)")
        );
    }
    let bytes: Vec<u8> = bytes.iter().map(|&b| b as u8).collect();
    let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(&bytes);
    Ok(Value::text(text.into_owned()))
}

fn proper_case(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut word_start = true;
    for c in text.chars() {
        if word_start {
            out.extend(c.to_uppercase());
        } else {
            out.extend(c.to_lowercase());
        }
        // Words are split by white space.
        word_start = c.is_whitespace() || c == '\0';
    }
    out
}

/// `ChrW(charcode)`: the character of a UTF-16 code, -32768 to 65535 (negative codes are
/// the same unit read as signed); half a surrogate pair is no character here.
pub fn chrw(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let code = to_number(&ctx.eval(&args[0]).unwrap_single(), dates)?.trunc();
    if !(-32768.0..=65535.0).contains(&code) {
        return Err(invalid_call(ctx, "ChrW", "the code is outside -32768 to 65535"));
    }
    let unit = if code < 0.0 { code + 65536.0 } else { code } as u32;
    let c = char::from_u32(unit).ok_or(XlError::Value)?;
    Ok(Value::text(c.to_string()))
}

/// `LenB(string)`: the bytes VBA's UTF-16 string holds, two per code unit.
pub fn len_b(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // "Len function": LenB too, "If string contains Null, Null is returned".
    let Some(text) = text_or_null(ctx, args, 0)? else { return Ok(Value::Null) };
    ctx.charge_read(text.len());
    Ok(Value::Number((text.encode_utf16().count() * 2) as f64))
}

/// A Tristate argument of FormatNumber, FormatPercent or FormatCurrency: vbTrue (-1),
/// vbFalse (0), vbUseDefault (-2).
fn tristate(ctx: &mut Ctx, name: &str, args: &[Expr], i: usize, default: bool) -> XlResult<bool> {
    match whole_arg(ctx, name, args, i, -2.0)? {
        -2.0 => Ok(default),
        0.0 => Ok(false),
        // A Boolean True is -1; any other non-zero number counts as True too.
        _ => Ok(true),
    }
}

/// Which of the three functions that share FormatNumber's arguments.
#[derive(Clone, Copy, PartialEq, Eq)]
enum NumberStyle {
    Number,
    /// The number times 100 with a percent sign ("FormatPercent function").
    Percent,
    /// The currency symbol before the number ("FormatCurrency function"); English (United
    /// States) shows a negative amount in parentheses.
    Currency,
}

impl NumberStyle {
    fn name(self) -> &'static str {
        match self {
            NumberStyle::Number => "FormatNumber",
            NumberStyle::Percent => "FormatPercent",
            NumberStyle::Currency => "FormatCurrency",
        }
    }
}

/// `FormatNumber`, `FormatPercent` or `FormatCurrency(expression[, digits[, leading digit[,
/// parentheses[, group digits]]]])` with the English (United States) regional defaults: two
/// decimals, a leading zero, thousands grouped with commas, a minus sign (parentheses for a
/// currency).
fn format_in_style(ctx: &mut Ctx, args: &[Expr], style: NumberStyle) -> XlResult<Value> {
    let name = style.name();
    let value = ctx.eval(&args[0]).unwrap_single();
    let n = number_to_format(ctx, name, value)?;
    let digits = whole_arg(ctx, name, args, 1, -1.0)?;
    let digits = if digits == -1.0 { 2.0 } else { digits };
    if !(0.0..=99.0).contains(&digits) {
        // A run-time error as VBA's Format functions raise for an argument out of range
        // ("Invalid procedure call or argument", 5); an Error value here printed as
        // "Error 2015" and the macro went on with it.
        return Err(invalid_call(ctx, name, "NumDigitsAfterDecimal is -1 (the regional default) or 0 to 99"));
    }
    let leading = tristate(ctx, name, args, 2, true)?;
    let parens = tristate(ctx, name, args, 3, style == NumberStyle::Currency)?;
    let group = tristate(ctx, name, args, 4, true)?;
    let whole = match (group, leading) {
        (true, true) => "#,##0",
        (true, false) => "#,###",
        (false, true) => "0",
        (false, false) => "#",
    };
    let decimals = "0".repeat(digits as usize);
    let number = if decimals.is_empty() { whole.to_string() } else { format!("{whole}.{decimals}") };
    let positive = match style {
        NumberStyle::Number => number,
        NumberStyle::Percent => format!("{number}%"),
        NumberStyle::Currency => format!("${number}"),
    };
    let pattern = if parens { format!("{positive};({positive})") } else { positive };
    let text = format_number(n, &pattern)?;
    // A zero without its leading digit and without decimals would be nothing: VBA writes 0.
    Ok(Value::text(if text.is_empty() || text == "-" { "0".to_string() } else { text }))
}

/// The number FormatNumber, FormatPercent or FormatCurrency formats: a String that is no
/// number is VBA's Type mismatch, run-time error 13 ([MS-VBAL] 5.5.1.2.1.1, Let-coercion from
/// String to Double), not an error value the macro would carry on with.
fn number_to_format(ctx: &mut Ctx, name: &str, value: Value) -> XlResult<f64> {
    match (to_number(&value, ctx.dates()), &value) {
        (Err(XlError::Value), Value::Text(text)) => Err(ctx.raise_vba(
            XlError::Value,
            13,
            super::errors::message(13, format_args!("{name}: \"{text}\" is no number")),
        )),
        (n, _) => n,
    }
}

/// `FormatNumber(expression[, digits[, leading digit[, parentheses[, group digits]]]])`.
pub fn format_number_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    format_in_style(ctx, args, NumberStyle::Number)
}

/// `FormatPercent(expression[, …])`: `FormatPercent(0.256)` is "25.60%".
pub fn format_percent_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    format_in_style(ctx, args, NumberStyle::Percent)
}

/// `FormatCurrency(expression[, …])`: `FormatCurrency(-1234.5)` is "($1,234.50)".
pub fn format_currency_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    format_in_style(ctx, args, NumberStyle::Currency)
}

/// `FormatDateTime(date[, NamedFormat])` ("FormatDateTime function"): vbGeneralDate (0, the
/// default), vbLongDate (1), vbShortDate (2), vbLongTime (3) or vbShortTime (4, 24-hour
/// hh:mm), as Format's named formats of the same names show them.
pub fn format_date_time_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let Some(date) = text_or_number_or_null(ctx, args)? else { return Ok(Value::Null) };
    let date = to_number(&date, dates)?;
    let named = match whole_arg(ctx, "FormatDateTime", args, 1, 0.0)? {
        0.0 => "general date",
        1.0 => "long date",
        2.0 => "short date",
        3.0 => "long time",
        4.0 => "short time",
        _ => return Err(invalid_call(ctx, "FormatDateTime", "NamedFormat is 0 to 4 (vbGeneralDate … vbShortTime)")),
    };
    Ok(Value::text(format_number(date, named)?))
}

/// The first argument, `None` for Null (which the date functions pass through).
fn text_or_number_or_null(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Option<Value>> {
    match ctx.eval(&args[0]).unwrap_single() {
        Value::Null => Ok(None),
        Value::Error(e) => Err(e),
        v => Ok(Some(v)),
    }
}

/// Whether `pattern` is one of Format's user-defined string formats: its first code
/// character (outside quotes and `\` escapes) is `@`, `&`, `<`, `>` or `!`, where a number
/// or date code starts with a digit placeholder, a separator or a date letter.
pub fn is_string_format(pattern: &str) -> bool {
    let mut chars = pattern.chars();
    while let Some(c) = chars.next() {
        match c.to_ascii_lowercase() {
            '"' => {
                chars.by_ref().find(|&q| q == '"');
            }
            '\\' => {
                chars.next();
            }
            '@' | '&' | '<' | '>' | '!' => return true,
            '0' | '#' | '.' | ',' | '%' | 'e' | '/' | ':' | 'a' | 'c' | 'd' | 'h' | 'm' | 'n' | 'q' | 's' | 't'
            | 'w' | 'y' | 'g' | '[' => return false,
            _ => {}
        }
    }
    false
}

/// A piece of a string format's section.
enum StringCode {
    /// `@` (a character or a space) or `&` (a character or nothing).
    Place(char),
    Literal(String),
}

/// `text` under one of Format's user-defined string formats ("Format function",
/// "User-defined string formats"): `@` shows a character or a space, `&` a character or
/// nothing, the placeholders filled from right to left unless `!` asks for left to right;
/// `<` writes the text in small letters, `>` in capitals; anything else, quoted or after
/// `\`, as it is. A second section formats the zero-length string. Characters beyond the
/// placeholders are kept, before them (or after them, filled from the left).
pub fn format_string(text: &str, pattern: &str) -> String {
    let (first, second) = split_string_sections(pattern);
    let section = match second {
        Some(second) if text.is_empty() => second,
        _ => first,
    };
    let mut codes = Vec::new();
    let mut left_to_right = false;
    let mut case: Option<fn(&str) -> String> = None;
    let mut chars = section.chars();
    while let Some(c) = chars.next() {
        match c {
            '@' | '&' => codes.push(StringCode::Place(c)),
            '!' => left_to_right = true,
            '<' => case = Some(str::to_lowercase),
            '>' => case = Some(str::to_uppercase),
            '"' => codes.push(StringCode::Literal(chars.by_ref().take_while(|&q| q != '"').collect())),
            '\\' => codes.push(StringCode::Literal(chars.next().map(String::from).unwrap_or_default())),
            c => codes.push(StringCode::Literal(c.to_string())),
        }
    }
    let text: Vec<char> = case.map_or_else(|| text.to_string(), |convert| convert(text)).chars().collect();
    let places = codes.iter().filter(|c| matches!(c, StringCode::Place(_))).count();
    // The text's index of each placeholder's character, and the characters beyond them.
    let extra = text.len().saturating_sub(places);
    let start = if left_to_right { 0 } else { text.len() as isize - places as isize };
    let mut out = String::new();
    let mut k = 0;
    for code in &codes {
        match code {
            StringCode::Literal(s) => out.push_str(s),
            StringCode::Place(p) => {
                if k == 0 && !left_to_right {
                    out.extend(&text[..extra]);
                }
                match usize::try_from(start + k as isize).ok().and_then(|i| text.get(i)) {
                    Some(&ch) => out.push(ch),
                    None if *p == '@' => out.push(' '),
                    None => {}
                }
                k += 1;
                if k == places && left_to_right {
                    out.extend(&text[places.min(text.len())..]);
                }
            }
        }
    }
    if places == 0 {
        out.extend(&text);
    }
    out
}

/// A string format's sections: the text's, and the zero-length string's when there is one.
fn split_string_sections(pattern: &str) -> (&str, Option<&str>) {
    let mut quoted = false;
    let mut escaped = false;
    for (i, c) in pattern.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if !quoted => escaped = true,
            '"' => quoted = !quoted,
            ';' if !quoted => return (&pattern[..i], Some(&pattern[i + 1..])),
            _ => {}
        }
    }
    (pattern, None)
}

/// `VarType(varname)` of a value: vbEmpty 0, vbDouble 5, vbString 8, vbError 10, vbBoolean
/// 11, vbArray + vbVariant 8204. (A variable declared `As Integer`, `Long`, … answers its
/// declared type: the macro interpreter asks before it comes here.)
pub fn var_type(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(var_type_of(&ctx.eval(&args[0]))))
}

pub fn var_type_of(v: &Value) -> f64 {
    match v {
        Value::Blank => 0.0,
        Value::Number(_) => 5.0,
        Value::Text(_) => 8.0,
        Value::Error(_) => 10.0,
        Value::Bool(_) => 11.0,
        Value::Array(_) => 8192.0 + 12.0,
        Value::Lambda(_) => 9.0,
        // vbNull.
        Value::Null => 1.0,
    }
}

/// `IsArray(varname)`: True for an array (a range of more than one cell reads as one).
pub fn is_array(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Bool(matches!(ctx.eval(&args[0]), Value::Array(_))))
}

/// `CVErr(errornumber)`: Excel's error values by their `xlErr…` numbers (2000 `#NULL!`,
/// 2007 `#DIV/0!`, 2015 `#VALUE!`, 2023 `#REF!`, 2029 `#NAME?`, 2036 `#NUM!`, 2042 `#N/A`),
/// the values a cell can hold. Other numbers have no cell value to be.
pub fn cv_err(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let n = to_number(&ctx.eval(&args[0]).unwrap_single(), dates)?;
    let error = match n {
        2000.0 => XlError::Null,
        2007.0 => XlError::Div0,
        2015.0 => XlError::Value,
        2023.0 => XlError::Ref,
        2029.0 => XlError::Name,
        2036.0 => XlError::Num,
        2042.0 => XlError::NA,
        _ => {
            let why = format!(
                "CVErr({n}): only Excel's error numbers (xlErrDiv0 2007, xlErrNA 2042, …) make an error value here"
            );
            return Err(ctx.explain(XlError::Value, why));
        }
    };
    Ok(Value::Error(error))
}

/// `CStr(value)` of an Error value: "A String containing the word Error followed by the error
/// number" ("Type conversion functions", CStr's return table), its `xlErr…` number as CVErr
/// made it: `CStr(CVErr(2042))` is "Error 2042", not the error itself.
pub(super) fn error_text(values: &[Value]) -> Option<Value> {
    let number = match values.first()? {
        Value::Error(XlError::Null) => 2000,
        Value::Error(XlError::Div0) => 2007,
        Value::Error(XlError::Value) => 2015,
        Value::Error(XlError::Ref) => 2023,
        Value::Error(XlError::Name) => 2029,
        Value::Error(XlError::Num) => 2036,
        Value::Error(XlError::NA) => 2042,
        _ => return None,
    };
    Some(Value::text(format!("Error {number}")))
}

/// `DoEvents` ("DoEvents function": "Yields execution so that the operating system can process
/// other events", and returns "zero in all other applications" than stand-alone Visual Basic):
/// a macro here has no events waiting, so it only answers 0. Real macros call it in long loops
/// to keep Excel's window alive.
pub fn do_events(_ctx: &mut Ctx, _args: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(0.0))
}

/// `Timer`: seconds since midnight by the document's clock (its settings' NOW).
pub fn timer(ctx: &mut Ctx, _args: &[Expr]) -> XlResult<Value> {
    let now = ctx.env.now();
    Ok(Value::Number((now - now.floor()) * 86400.0))
}

/// `Rnd[(number)]` ("Rnd function"): VBA's generator, the workbook's (`Settings::vba_rnd`):
/// the next number for a positive number or none, the last one for zero, the same one every
/// time for a negative number.
pub fn rnd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let n = whole_or_fraction(ctx, args)?;
    Ok(Value::Number(ctx.env.vba_rnd(n)))
}

fn whole_or_fraction(ctx: &mut Ctx, args: &[Expr]) -> XlResult<f64> {
    let dates = ctx.dates();
    match given(args, 0) {
        Some(e) => to_number(&ctx.eval(e).unwrap_single(), dates),
        None => Ok(1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proper_case_capitalises_each_word() {
        // "StrConv function": vbProperCase, first letter of every word uppercase.
        assert_eq!(proper_case("hELLO wORLD\tnc"), "Hello World\tNc");
    }

    /// U+212A KELVIN SIGN lowercases to U+006B "k" (UnicodeData.txt), three bytes to one: a
    /// textual search finds "Kb" in "aKbK" (the Kelvin signs) at character 1 of 4, its end at
    /// character 3, the places in the text itself at its own bytes.
    #[test]
    fn a_fold_that_changes_a_characters_bytes_keeps_the_places_in_the_text() {
        let text = "a\u{212A}b\u{212A}";
        let (mut hay, needle) = (Searched::new(text, true), Searched::new("Kb", true));
        let at = find_from(&hay, &needle, 0).expect("found");
        let (start, end) = (hay.at_byte(at), hay.at_byte(at + needle.bytes().len()));
        assert_eq!((start.chars, start.text), (1, 1));
        assert_eq!((end.chars, end.text), (3, 5));
        assert_eq!(&text[start.text..end.text], "\u{212A}b");
        assert_eq!(hay.char_count(), 4);
        assert_eq!(hay.at_char(2).map(|p| p.text), Some(4));
        assert!(hay.at_char(5).is_none());
    }
}
