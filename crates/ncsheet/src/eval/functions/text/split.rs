//! Text cut at delimiters: TEXTBEFORE, TEXTAFTER and TEXTSPLIT (Excel 365). A delimiter
//! argument may be an array of delimiters, any of which cuts; match mode 1 ignores case.

use std::cell::Cell;
use std::rc::Rc;

use crate::eval::coerce::{to_bool, to_number, to_text};
use crate::eval::functions::api::{lift_values, number_or, Ctx, FnSpec};
use crate::eval::value::{too_much_text_note, Array, Value, XlError, XlResult, MAX_ARRAY_TEXT_READ};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "TEXTAFTER",
        2,
        6,
        textafter,
        "TEXTAFTER(text, delimiter, [instance_num], [match_mode], [match_end], [if_not_found])",
        "The text after the nth delimiter (negative n counts from the end)",
    )
    .future(),
    FnSpec::value(
        "TEXTBEFORE",
        2,
        6,
        textbefore,
        "TEXTBEFORE(text, delimiter, [instance_num], [match_mode], [match_end], [if_not_found])",
        "The text before the nth delimiter (negative n counts from the end)",
    )
    .future(),
    FnSpec::value(
        "TEXTSPLIT",
        2,
        6,
        textsplit,
        "TEXTSPLIT(text, col_delimiter, [row_delimiter], [ignore_empty], [match_mode], [pad_with])",
        "Text split into columns (and rows) at the delimiters",
    )
    .future()
    .dynamic(),
];

fn present(args: &[Expr], i: usize) -> bool {
    args.get(i).is_some_and(|e| e.kind != ExprKind::Missing)
}

/// The delimiters an argument holds (one text, or every item of an array).
fn delimiters(v: &Value) -> XlResult<Vec<Vec<char>>> {
    match v {
        Value::Array(a) => a.data.iter().map(|d| Ok(to_text(d)?.chars().collect())).collect(),
        v => Ok(vec![to_text(v)?.chars().collect()]),
    }
}

fn fold(c: char, ignore_case: bool) -> char {
    if ignore_case {
        c.to_lowercase().next().unwrap_or(c)
    } else {
        c
    }
}

/// The delimiters a call cuts at, made ready to seek: folded once when case is ignored, each
/// distinct one once, with its Knuth–Morris–Pratt table. Trying every delimiter at every
/// place took text × delimiters × their length (a thousand delimiters of 16,000 characters
/// in a 32,000-character text ran past 30 s); each now reads the text once, and what the
/// reading costs is counted against [`MAX_ARRAY_TEXT_READ`], as an array's texts read are.
struct Seeker {
    delims: Vec<(Vec<char>, Vec<u32>)>,
    ignore_case: bool,
}

impl Seeker {
    /// The delimiters' characters are charged to `read`, the characters a call has read;
    /// `None` past the limit.
    fn new(mut delims: Vec<Vec<char>>, ignore_case: bool, read: &Cell<usize>) -> Option<Seeker> {
        delims.retain(|d| !d.is_empty());
        let total = delims.iter().map(Vec::len).fold(read.get(), usize::saturating_add);
        read.set(total);
        if total > MAX_ARRAY_TEXT_READ {
            return None;
        }
        for d in &mut delims {
            d.iter_mut().for_each(|c| *c = fold(*c, ignore_case));
        }
        delims.sort_unstable();
        delims.dedup();
        let delims = delims.into_iter().map(|d| (failure_table(&d), d)).map(|(t, d)| (d, t)).collect();
        Some(Seeker { delims, ignore_case })
    }

    /// Every match of a delimiter, left to right, not overlapping, as (start, end) in chars:
    /// at each place, the longest delimiter that starts there. `None` once the searches of
    /// this call have read more than the limit (each delimiter reads the text once).
    fn matches(&self, text: &[char], read: &Cell<usize>) -> Option<Vec<(usize, usize)>> {
        if self.delims.is_empty() {
            return Some(Vec::new());
        }
        read.set(read.get().saturating_add(self.delims.len().saturating_mul(text.len())));
        if read.get() > MAX_ARRAY_TEXT_READ {
            return None;
        }
        let folded: Vec<char>;
        let text = if self.ignore_case {
            folded = text.iter().map(|&c| fold(c, true)).collect();
            &folded[..]
        } else {
            text
        };
        let mut longest = vec![0u32; text.len()];
        for (d, table) in &self.delims {
            for start in starts(text, d, table) {
                longest[start] = longest[start].max(d.len() as u32);
            }
        }
        let mut out = Vec::new();
        let mut i = 0;
        while i < text.len() {
            match longest[i] as usize {
                0 => i += 1,
                len => {
                    out.push((i, i + len));
                    i += len;
                }
            }
        }
        Some(out)
    }

    fn all_empty(&self) -> bool {
        self.delims.is_empty()
    }
}

/// Knuth–Morris–Pratt's table: for each prefix of `d`, the length of its longest proper
/// prefix that is also its suffix.
fn failure_table(d: &[char]) -> Vec<u32> {
    let mut table = vec![0u32; d.len()];
    let mut k = 0usize;
    for i in 1..d.len() {
        while k > 0 && d[i] != d[k] {
            k = table[k - 1] as usize;
        }
        if d[i] == d[k] {
            k += 1;
        }
        table[i] = k as u32;
    }
    table
}

/// Where `d` starts in `text`, overlapping matches too, reading each character of the text
/// once (with the steps back the table allows, at most as many again); between partial
/// matches it only looks for the delimiter's first character.
fn starts(text: &[char], d: &[char], table: &[u32]) -> Vec<usize> {
    let mut found = Vec::new();
    let mut k = 0usize;
    let mut i = 0;
    while i < text.len() {
        if k == 0 {
            match text[i..].iter().position(|&c| c == d[0]) {
                Some(skip) => i += skip,
                None => break,
            }
        }
        let c = text[i];
        while k > 0 && c != d[k] {
            k = table[k - 1] as usize;
        }
        if c == d[k] {
            k += 1;
        }
        if k == d.len() {
            found.push(i + 1 - k);
            k = table[k - 1] as usize;
        }
        i += 1;
    }
    found
}

/// The (start, end) of the delimiter TEXTBEFORE and TEXTAFTER cut at, or `Ok(None)`;
/// `Err` past the reading limit.
fn cut(
    text: &[char],
    seeker: &Seeker,
    read: &Cell<usize>,
    instance: i64,
    match_end: bool,
) -> Result<Option<(usize, usize)>, Refused> {
    if seeker.all_empty() {
        // An empty delimiter matches at once: at the start reading forward, the end backward.
        return Ok(Some(if instance > 0 { (0, 0) } else { (text.len(), text.len()) }));
    }
    let mut found = seeker.matches(text, read).ok_or(Refused)?;
    Ok(if instance > 0 {
        if match_end {
            found.push((text.len(), text.len()));
        }
        found.get(instance as usize - 1).copied()
    } else {
        if match_end {
            found.insert(0, (0, 0));
        }
        let k = instance.unsigned_abs() as usize;
        found.len().checked_sub(k).map(|i| found[i])
    })
}

/// The delimiters' search read more than [`MAX_ARRAY_TEXT_READ`].
struct Refused;

/// `#NUM!` with the reading limit in the cell's note.
fn refused(ctx: &mut Ctx) -> XlError {
    ctx.explain(XlError::Num, too_much_text_note())
}

fn before_or_after(ctx: &mut Ctx, args: &[Expr], before: bool) -> XlResult<Value> {
    let text = ctx.eval(&args[0]);
    let delims = delimiters(&ctx.eval(&args[1]))?;
    // Excel rounds the instance down: -1.2 is the second from the end.
    let instance = number_or(ctx, args, 2, 1.0)?.floor();
    let mode = number_or(ctx, args, 3, 0.0)?.trunc();
    let end = number_or(ctx, args, 4, 0.0)?.trunc();
    if !(mode == 0.0 || mode == 1.0) || !(end == 0.0 || end == 1.0) {
        return Err(XlError::Value);
    }
    let (ignore_case, match_end) = (mode == 1.0, end == 1.0);
    // A blank if_not_found is empty text.
    let not_found = if present(args, 5) { Some(ctx.eval(&args[5]).blank_as_text()) } else { None };
    let instance_given = present(args, 2);
    // One count over every text of the array: each reads the delimiters' text once.
    let read = Cell::new(0);
    // A text shorter than every delimiter (none of them empty) holds none of them.
    let shortest = delims.iter().map(Vec::len).min().unwrap_or(0);
    let seeker = Seeker::new(delims, ignore_case, &read).ok_or_else(|| refused(ctx))?;
    let over = Cell::new(false);
    let lifted = lift_values(&[text], &|v| {
        let text: Vec<char> = to_text(&v[0])?.chars().collect();
        let too_long = shortest > text.len();
        if instance == 0.0 || instance.abs() > text.len().max(1) as f64 || too_long && instance_given {
            return Err(XlError::Value);
        }
        // Excel's stored results: a delimiter longer than the text is not found (#N/A) when
        // no instance is given, #VALUE! when one is.
        if too_long {
            return not_found.clone().ok_or(XlError::NA);
        }
        match cut(&text, &seeker, &read, instance as i64, match_end) {
            Ok(Some((start, end))) => {
                let part: String = if before { text[..start].iter().collect() } else { text[end..].iter().collect() };
                Ok(Value::text(part))
            }
            Ok(None) => not_found.clone().ok_or(XlError::NA),
            Err(Refused) => {
                over.set(true);
                Err(XlError::Num)
            }
        }
    });
    if over.get() {
        return Err(refused(ctx));
    }
    lifted
}

fn textbefore(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    before_or_after(ctx, args, true)
}

fn textafter(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    before_or_after(ctx, args, false)
}

/// `text` cut at every delimiter match; `Err` past the reading limit.
fn split(text: &[char], seeker: &Seeker, read: &Cell<usize>) -> Result<Vec<String>, Refused> {
    let mut out = Vec::new();
    let mut start = 0;
    for (s, e) in seeker.matches(text, read).ok_or(Refused)? {
        out.push(text[start..s].iter().collect());
        start = e;
    }
    out.push(text[start..].iter().collect());
    Ok(out)
}

fn textsplit(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let dates = ctx.dates();
    let text: Vec<char> = to_text(&ctx.eval(&args[0]).unwrap_single())?.chars().collect();
    let col_delims = if present(args, 1) { delimiters(&ctx.eval(&args[1]))? } else { Vec::new() };
    let row_delims = if present(args, 2) { delimiters(&ctx.eval(&args[2]))? } else { Vec::new() };
    if col_delims.iter().chain(&row_delims).all(Vec::is_empty) {
        return Err(XlError::Value);
    }
    let ignore_empty = if present(args, 3) { to_bool(&ctx.eval(&args[3]))? } else { false };
    let ignore_case = if present(args, 4) { to_number(&ctx.eval(&args[4]), dates)? != 0.0 } else { false };
    let pad = if present(args, 5) { ctx.eval(&args[5]).unwrap_single() } else { Value::Error(XlError::NA) };
    // The two searches share one count of what they read.
    let read = Cell::new(0);
    let (Some(rows_at), Some(cols_at)) =
        (Seeker::new(row_delims, ignore_case, &read), Seeker::new(col_delims, ignore_case, &read))
    else {
        return Err(refused(ctx));
    };
    let mut rows: Vec<Vec<String>> = Vec::new();
    let Ok(lines) = split(&text, &rows_at, &read) else { return Err(refused(ctx)) };
    for line in lines {
        if ignore_empty && line.is_empty() {
            continue;
        }
        let chars: Vec<char> = line.chars().collect();
        let Ok(mut cells) = split(&chars, &cols_at, &read) else { return Err(refused(ctx)) };
        if ignore_empty {
            cells.retain(|c| !c.is_empty());
        }
        rows.push(cells);
    }
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    if rows.is_empty() || cols == 0 {
        return Err(XlError::Calc);
    }
    let n = rows.len();
    // Every row is padded to the widest: 16,384 rows under one row of 16,384 parts (a text
    // of 32,767 delimiters) would be 2^28 items.
    ctx.room_for(n, cols)?;
    let data = rows
        .into_iter()
        .flat_map(|r| {
            let len = r.len();
            r.into_iter().map(Value::text).chain(std::iter::repeat_n(pad.clone(), cols - len)).collect::<Vec<_>>()
        })
        .collect();
    Ok(Value::Array(Rc::new(Array::new(n, cols, data))))
}

trait BlankAsText {
    fn blank_as_text(self) -> Value;
}

impl BlankAsText for Value {
    fn blank_as_text(self) -> Value {
        match self {
            Value::Blank => Value::text(""),
            v => v,
        }
    }
}
