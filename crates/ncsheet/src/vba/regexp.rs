//! VBScript's regular expressions ("Microsoft VBScript Regular Expressions 5.5") as a macro
//! reaches them: `CreateObject("VBScript.RegExp")`, `New RegExp`,
//! `New VBScript_RegExp_55.RegExp`. ncsheet makes the objects itself: a RegExp (Pattern,
//! Global, IgnoreCase, MultiLine, Test, Execute, Replace), the MatchCollection Execute returns,
//! its Match objects and their SubMatches, each member as Microsoft's VBScript reference
//! describes it ("Regular Expression (RegExp) Object", "Execute Method", "Replace Method",
//! "Match Object", "SubMatches Collection").
//!
//! The pattern language is JScript's (ECMAScript 3), translated here into the `regex`
//! crate's, construct by construct, to what means the same there (`\d` ASCII digits, `.` any
//! character but `\n`, `\b` at ASCII word characters, `^`/`$` under MultiLine after and
//! before `\n` and `\r`). What the crate cannot express is refused by name, never matched
//! otherwise: lookahead `(?=` `(?!`, backreferences `\1`, and `^`/`$` under MultiLine on
//! text holding a CR LF pair. A search takes time linear in the text, times what the pattern
//! compiles to: the pattern's length, its compiled size and a search's work are capped as the
//! cell functions' are, in one place (`eval/regex_limits.rs`, docs/limits.md).

use std::cell::RefCell;
use std::rc::Rc;

use crate::eval::functions::vba::vba_text;
use crate::eval::regex_limits::{self, Pattern, TooMuchWork};
use crate::eval::Value;
use crate::formula::ast::Expr;

use super::ast::{Arg, Link, Made, Node, Span};
use super::interp::{Fault, Interp, Run};
use super::objects::lower;
use super::value::{Obj, Var};

/// VBScript's run-time errors of a pattern ("VBScript Run-time Errors").
const SYNTAX: u32 = 5017;
const UNEXPECTED_QUANTIFIER: u32 = 5018;
const EXPECTED_BRACKET: u32 = 5019;
const EXPECTED_PAREN: u32 = 5020;
const INVALID_RANGE: u32 = 5021;
const INVALID_CALL: u32 = 5;
/// What one match costs the memory budget besides its texts.
const HIT_BYTES: usize = 64;
/// A search's work (`regex_limits`, in slot copies of about 0.35 ns) that counts as one unit
/// of the macro's text work (a quarter statement, about 0.14 µs).
const SEARCH_WORK_PER_UNIT: u64 = 400;

fn vbscript_text(code: u32) -> &'static str {
    match code {
        SYNTAX => "Syntax error in regular expression",
        UNEXPECTED_QUANTIFIER => "Unexpected quantifier",
        EXPECTED_BRACKET => "Expected ']' in regular expression",
        EXPECTED_PAREN => "Expected ')' in regular expression",
        INVALID_RANGE => "Invalid range in character set",
        _ => "Invalid procedure call or argument",
    }
}

/// Why a pattern does not compile: one of VBScript's errors, or a construct ncsheet refuses.
#[derive(Debug, PartialEq)]
pub(super) enum PatternFault {
    /// VBScript's error number and where in the pattern (0-based character).
    Vbscript(u32, usize),
    /// A construct VBScript has that ncsheet does not match, and why.
    Refused(String),
}

/// A pattern translated for the `regex` crate.
#[derive(Debug)]
pub(super) struct Compiled {
    pattern: Pattern,
    /// Whether `^` or `$` is a line anchor here (MultiLine): text holding CR LF is refused.
    line_anchors: bool,
}

/// A RegExp's properties and its pattern as last compiled.
#[derive(Debug, Default)]
pub struct Settings {
    pattern: Rc<str>,
    global: bool,
    ignore_case: bool,
    multiline: bool,
    compiled: Option<Rc<Compiled>>,
}

/// One match: its text, where it starts and how long it is in UTF-16 units (as VBScript
/// counts a String), and each group's text, `None` for a group that took no part.
#[derive(Debug)]
pub struct Hit {
    value: Rc<str>,
    first_index: usize,
    length: usize,
    groups: Vec<Option<Rc<str>>>,
}

/// The objects of the library, shared as COM objects are by every variable set to them.
#[derive(Clone, Debug)]
pub enum RegexObj {
    RegExp(Rc<RefCell<Settings>>),
    Matches(Rc<Vec<Hit>>),
    Match(Rc<Vec<Hit>>, usize),
    SubMatches(Rc<Vec<Hit>>, usize),
}

impl PartialEq for RegexObj {
    fn eq(&self, other: &RegexObj) -> bool {
        match (self, other) {
            (RegexObj::RegExp(a), RegexObj::RegExp(b)) => Rc::ptr_eq(a, b),
            (RegexObj::Matches(a), RegexObj::Matches(b)) => Rc::ptr_eq(a, b),
            (RegexObj::Match(a, i), RegexObj::Match(b, j))
            | (RegexObj::SubMatches(a, i), RegexObj::SubMatches(b, j)) => Rc::ptr_eq(a, b) && i == j,
            _ => false,
        }
    }
}

impl RegexObj {
    /// A new RegExp: an empty pattern, Global, IgnoreCase and MultiLine False.
    pub fn new_regexp() -> RegexObj {
        RegexObj::RegExp(Rc::new(RefCell::new(Settings::default())))
    }

    pub fn describe(&self) -> &'static str {
        match self {
            RegexObj::RegExp(_) => "a RegExp",
            RegexObj::Matches(_) => "a MatchCollection",
            RegexObj::Match(..) => "a Match",
            RegexObj::SubMatches(..) => "a SubMatches collection",
        }
    }

    /// The matches a MatchCollection, a Match or a SubMatches shares.
    pub fn hits(&self) -> Option<&Rc<Vec<Hit>>> {
        match self {
            RegexObj::RegExp(_) => None,
            RegexObj::Matches(hits) | RegexObj::Match(hits, _) | RegexObj::SubMatches(hits, _) => Some(hits),
        }
    }

    /// What `TypeName` says: the interface names VBScript's type library gives them.
    pub fn type_name(&self) -> &'static str {
        match self {
            RegexObj::RegExp(_) => "IRegExp2",
            RegexObj::Matches(_) => "IMatchCollection2",
            RegexObj::Match(..) => "IMatch2",
            RegexObj::SubMatches(..) => "ISubMatches",
        }
    }

    /// A Match's default member, Value: what it reads as in an expression.
    pub fn default_value(&self) -> Option<Value> {
        match self {
            RegexObj::Match(hits, i) => Some(Value::Text(hits[*i].value.clone())),
            _ => None,
        }
    }

    /// What For Each goes through: a MatchCollection's Match objects, a SubMatches' texts.
    pub fn each(&self) -> Option<Vec<Var>> {
        match self {
            RegexObj::Matches(hits) => {
                Some((0..hits.len()).map(|i| Var::Obj(Obj::Regex(RegexObj::Match(hits.clone(), i)))).collect())
            }
            RegexObj::SubMatches(hits, i) => Some(hits[*i].groups.iter().map(group_var).collect()),
            _ => None,
        }
    }
}

/// What `v = m` assigns without Set: a Match's Value, its default property ([MS-VBAL]'s
/// object Let-coercion: "the simple data value of the object", its default member's);
/// anything else as it is.
pub(super) fn let_value(var: Var, set: bool) -> Var {
    match var {
        Var::Obj(Obj::Regex(r)) if !set && r.default_value().is_some() => {
            Var::Value(r.default_value().unwrap_or_default())
        }
        other => other,
    }
}

/// A group's text as SubMatches gives it: Empty for a group that took no part.
fn group_var(group: &Option<Rc<str>>) -> Var {
    Var::Value(group.as_ref().map_or(Value::Blank, |t| Value::Text(t.clone())))
}

/// The ProgID `CreateObject` names VBScript's RegExp by.
pub fn created(prog_id: &str) -> Option<Made> {
    prog_id.eq_ignore_ascii_case("vbscript.regexp").then_some(Made::RegExp)
}

/// The class `New` names: `RegExp`, `VBScript_RegExp_55.RegExp` (the reference "Microsoft
/// VBScript Regular Expressions 5.5"; 1.0's library is `VBScript_RegExp_10`).
pub fn new_class(name: &str) -> Option<Made> {
    let lower = name.to_ascii_lowercase();
    matches!(lower.as_str(), "regexp" | "vbscript_regexp_55.regexp" | "vbscript_regexp_10.regexp")
        .then_some(Made::RegExp)
}

// ---- the pattern ---------------------------------------------------------------------------

/// `\d`, `\w`, `\s` as VBScript defines them ("Pattern Property": `[0-9]`,
/// `[A-Za-z0-9_]`, `[ \f\n\r\t\v]`), ASCII only; as the inside of a class.
fn class_escape(c: char) -> Option<(&'static str, bool)> {
    Some(match c {
        'd' => ("0-9", false),
        'D' => ("0-9", true),
        'w' => ("0-9A-Za-z_", false),
        'W' => ("0-9A-Za-z_", true),
        's' => (r"\t\n\x0B\x0C\r ", false),
        'S' => (r"\t\n\x0B\x0C\r ", true),
        _ => return None,
    })
}

/// The character a one-character escape stands for (`\n`, `\t` …), `None` for the others.
fn control_escape(c: char) -> Option<char> {
    Some(match c {
        'f' => '\x0C',
        'n' => '\n',
        'r' => '\r',
        't' => '\t',
        'v' => '\x0B',
        _ => return None,
    })
}

/// A character as the `regex` crate reads it literally, inside a class or out.
fn literal(c: char) -> String {
    format!("\\x{{{:X}}}", c as u32)
}

/// The translation of one pattern, character by character.
struct Translation {
    chars: Vec<char>,
    at: usize,
    out: String,
    multiline: bool,
    line_anchors: bool,
    /// Capturing groups opened so far (what `\n` may refer back to).
    groups: usize,
    /// Open groups: where each began in the pattern.
    open: Vec<usize>,
    /// Whether what was emitted last is an atom a quantifier may follow.
    quantifiable: bool,
}

impl Translation {
    fn new(source: &str, multiline: bool) -> Translation {
        Translation {
            chars: source.chars().collect(),
            at: 0,
            out: String::new(),
            multiline,
            line_anchors: false,
            groups: 0,
            open: Vec::new(),
            quantifiable: false,
        }
    }

    fn peek(&self, ahead: usize) -> Option<char> {
        self.chars.get(self.at + ahead).copied()
    }

    fn fault(&self, code: u32) -> PatternFault {
        PatternFault::Vbscript(code, self.at)
    }

    fn atom(&mut self, text: &str) {
        self.out.push_str(text);
        self.quantifiable = true;
    }

    fn assertion(&mut self, text: &str) {
        self.out.push_str(text);
        self.quantifiable = false;
    }

    fn run(mut self) -> Result<(String, bool), PatternFault> {
        while let Some(c) = self.peek(0) {
            self.at += 1;
            match c {
                '\\' => self.escape()?,
                '[' => self.class()?,
                '(' => self.group()?,
                ')' => {
                    if self.open.pop().is_none() {
                        self.at -= 1;
                        return Err(self.fault(SYNTAX));
                    }
                    self.atom(")");
                }
                '|' => self.assertion("|"),
                '^' => self.anchor("^", r"\A"),
                '$' => self.anchor("$", r"\z"),
                '.' => self.atom(r"[^\n]"),
                '*' | '+' | '?' => self.quantifier(c.to_string())?,
                '{' => match self.braces() {
                    Some(q) => self.quantifier(q)?,
                    None => self.atom(r"\{"),
                },
                other => self.atom(&literal(other)),
            }
        }
        if !self.open.is_empty() {
            return Err(self.fault(EXPECTED_PAREN));
        }
        Ok((self.out, self.line_anchors))
    }

    /// `^` or `$`: the text's start or end, and under MultiLine a line's, a line ending at
    /// `\n` or `\r` ("Pattern Property"); the crate's CRLF mode ends lines at both.
    fn anchor(&mut self, line: &str, text: &str) {
        if self.multiline {
            self.line_anchors = true;
            self.assertion(&format!("(?mR:{line})"));
        } else {
            self.assertion(text);
        }
    }

    /// `{n}`, `{n,}`, `{n,m}` after a `{`; `None` when the braces are not a quantifier
    /// (then `{` is itself, as JScript reads it).
    fn braces(&mut self) -> Option<String> {
        let rest: String = self.chars[self.at..].iter().take_while(|c| **c != '}').collect();
        if self.at + rest.chars().count() >= self.chars.len() {
            return None;
        }
        let (low, high) = match rest.split_once(',') {
            Some((low, high)) => (low, Some(high)),
            None => (rest.as_str(), None),
        };
        let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
        if !digits(low) || high.is_some_and(|h| !h.is_empty() && !digits(h)) {
            return None;
        }
        self.at += rest.chars().count() + 1;
        Some(format!("{{{rest}}}"))
    }

    /// A quantifier: after an atom only, once, with `?` making it lazy.
    fn quantifier(&mut self, mut q: String) -> Result<(), PatternFault> {
        if !self.quantifiable {
            self.at -= 1;
            return Err(self.fault(UNEXPECTED_QUANTIFIER));
        }
        if let Some((low, Some(high))) = q
            .trim_matches(|c| c == '{' || c == '}')
            .split_once(',')
            .map(|(l, h)| (l.parse::<u64>().ok(), (!h.is_empty()).then(|| h.parse::<u64>().ok()).flatten()))
        {
            if low.is_some_and(|low| low > high) {
                return Err(self.fault(SYNTAX));
            }
        }
        if self.peek(0) == Some('?') {
            self.at += 1;
            q.push('?');
        }
        self.out.push_str(&q);
        self.quantifiable = false;
        Ok(())
    }

    fn group(&mut self) -> Result<(), PatternFault> {
        if self.peek(0) == Some('?') {
            match self.peek(1) {
                Some(':') => self.at += 2,
                Some(kind @ ('=' | '!')) => {
                    let which = if kind == '=' { "a lookahead (?=…)" } else { "a negative lookahead (?!…)" };
                    return Err(PatternFault::Refused(format!(
                        "{which} is not supported by ncsheet's regular expressions (they match in linear time, which \
                         lookahead does not allow); match more and test the rest with a second pattern or InStr"
                    )));
                }
                _ => return Err(self.fault(SYNTAX)),
            }
            self.open.push(self.at);
            self.assertion("(?:");
            return Ok(());
        }
        self.groups += 1;
        self.open.push(self.at);
        self.assertion("(");
        Ok(())
    }

    fn escape(&mut self) -> Result<(), PatternFault> {
        let Some(c) = self.peek(0) else { return Err(self.fault(SYNTAX)) };
        self.at += 1;
        match c {
            'b' => self.assertion(r"(?-u:\b)"),
            'B' => self.assertion(r"(?-u:\B)"),
            '1'..='9' => {
                let code = self.decimal_escape(c)?;
                self.atom(&literal(code));
            }
            _ => match class_escape(c) {
                Some((set, negated)) => self.atom(&format!("[{}{set}]", if negated { "^" } else { "" })),
                None => {
                    let ch = self.char_escape(c)?;
                    self.atom(&literal(ch));
                }
            },
        }
        Ok(())
    }

    /// `\1`…`\99` after as many groups: a backreference, refused; otherwise an octal escape
    /// ("Pattern Property", `\nm`), or the digit itself.
    fn decimal_escape(&mut self, first: char) -> Result<char, PatternFault> {
        let second = self.peek(0).filter(char::is_ascii_digit);
        let two = second.map(|d| (first as u32 - '0' as u32) * 10 + (d as u32 - '0' as u32));
        let one = first as u32 - '0' as u32;
        if two.is_some_and(|n| n as usize <= self.groups) || one as usize <= self.groups {
            return Err(PatternFault::Refused(format!(
                "a backreference \\{first} is not supported by ncsheet's regular expressions (they match in linear \
                 time, which a backreference does not allow); capture the part and compare it in the macro"
            )));
        }
        Ok(self.octal(first).unwrap_or(first))
    }

    /// An octal escape of up to three digits (at most `\377`), its first digit read.
    fn octal(&mut self, first: char) -> Option<char> {
        let mut value = first.to_digit(8)?;
        for _ in 0..2 {
            match self.peek(0).and_then(|d| d.to_digit(8)) {
                Some(d) if value * 8 + d <= 0o377 => {
                    value = value * 8 + d;
                    self.at += 1;
                }
                _ => break,
            }
        }
        char::from_u32(value)
    }

    /// The character of an escape that stands for one: `\n`, `\cJ`, `\x41`, `\u0041`, `\0`,
    /// an octal `\012`, else the character itself (`\.`).
    fn char_escape(&mut self, c: char) -> Result<char, PatternFault> {
        if let Some(ch) = control_escape(c) {
            return Ok(ch);
        }
        match c {
            'c' => match self.peek(0).filter(char::is_ascii_alphabetic) {
                Some(letter) => {
                    self.at += 1;
                    Ok(char::from(letter as u8 % 32))
                }
                None => Ok('c'),
            },
            'x' => Ok(self.hex(2).and_then(char::from_u32).unwrap_or('x')),
            'u' => self.unicode_escape(),
            '0' => Ok(self.octal('0').unwrap_or('\0')),
            other => Ok(other),
        }
    }

    /// `n` hex digits after the escape's letter, as one character.
    fn hex(&mut self, n: usize) -> Option<u32> {
        let digits: String = self.chars.get(self.at..self.at + n)?.iter().collect();
        let value = u32::from_str_radix(&digits, 16).ok().filter(|_| digits.chars().all(|d| d.is_ascii_hexdigit()))?;
        self.at += n;
        Some(value)
    }

    fn unicode_escape(&mut self) -> Result<char, PatternFault> {
        let Some(unit) = self.hex(4) else { return Ok('u') };
        if !(0xD800..0xE000).contains(&unit) {
            return Ok(char::from_u32(unit).unwrap_or('\u{FFFD}'));
        }
        // A surrogate pair written as two escapes is the one character it encodes.
        let low = (self.peek(0) == Some('\\') && self.peek(1) == Some('u')).then(|| {
            self.at += 2;
            self.hex(4)
        });
        match low.flatten().filter(|l| (0xDC00..0xE000).contains(l) && unit < 0xDC00) {
            Some(l) => Ok(char::from_u32(0x10000 + ((unit - 0xD800) << 10) + (l - 0xDC00)).unwrap_or('\u{FFFD}')),
            None => Err(PatternFault::Refused(format!(
                "\\u{unit:04X} is half of a UTF-16 surrogate pair, which no character of a String is on its own here"
            ))),
        }
    }

    /// `[…]` and `[^…]`: characters, ranges and class escapes; `[]` and `[^]` refused.
    fn class(&mut self) -> Result<(), PatternFault> {
        let start = self.at - 1;
        let negated = self.peek(0) == Some('^');
        if negated {
            self.at += 1;
        }
        if self.peek(0) == Some(']') {
            return Err(PatternFault::Refused(format!(
                "the empty class {} at character {}: JScript and VBScript's own documentation disagree on what it \
                 matches; write [\\]] for a ']' or [\\s\\S] for any character",
                if negated { "[^]" } else { "[]" },
                start + 1
            )));
        }
        let mut inside = String::new();
        loop {
            let Some(c) = self.peek(0) else {
                self.at = start;
                return Err(self.fault(EXPECTED_BRACKET));
            };
            self.at += 1;
            if c == ']' {
                break;
            }
            let from = self.class_atom(c)?;
            let range_end = (self.peek(0) == Some('-') && self.peek(1).is_some_and(|n| n != ']')).then_some(());
            match (from, range_end) {
                (ClassAtom::Char(low), Some(())) => {
                    let mark = self.at;
                    self.at += 1;
                    let next = self.peek(0).unwrap_or(']');
                    self.at += 1;
                    match self.class_atom(next)? {
                        ClassAtom::Char(high) if high < low => {
                            self.at = mark;
                            return Err(self.fault(INVALID_RANGE));
                        }
                        ClassAtom::Char(high) => inside.push_str(&format!("{}-{}", literal(low), literal(high))),
                        ClassAtom::Set(set) => {
                            // A class escape cannot end a range: the '-' is itself (JScript).
                            inside.push_str(&literal(low));
                            inside.push_str(&literal('-'));
                            inside.push_str(&set);
                        }
                    }
                }
                (ClassAtom::Char(ch), None) => inside.push_str(&literal(ch)),
                (ClassAtom::Set(set), _) => inside.push_str(&set),
            }
        }
        self.atom(&format!("[{}{inside}]", if negated { "^" } else { "" }));
        Ok(())
    }

    /// One member of a class, its first character `c` read: a character or a class escape.
    fn class_atom(&mut self, c: char) -> Result<ClassAtom, PatternFault> {
        if c != '\\' {
            return Ok(ClassAtom::Char(c));
        }
        let Some(e) = self.peek(0) else { return Err(self.fault(EXPECTED_BRACKET)) };
        self.at += 1;
        if let Some((set, negated)) = class_escape(e) {
            return Ok(ClassAtom::Set(format!("[{}{set}]", if negated { "^" } else { "" })));
        }
        Ok(ClassAtom::Char(match e {
            // In a class `\b` is the backspace character.
            'b' => '\x08',
            '1'..='9' => self.octal(e).unwrap_or(e),
            other => self.char_escape(other)?,
        }))
    }
}

enum ClassAtom {
    Char(char),
    /// A class escape's characters as a nested class.
    Set(String),
}

/// The pattern compiled as VBScript reads it under the RegExp's flags.
pub(super) fn compile(pattern: &str, ignore_case: bool, multiline: bool) -> Result<Compiled, PatternFault> {
    // The pattern as given is measured: its translation spells each character out.
    regex_limits::check_length(pattern).map_err(|e| PatternFault::Refused(e.to_string()))?;
    let (translated, line_anchors) = Translation::new(pattern, multiline).run()?;
    // A count past the crate's repetition limit ({1000000}) or nesting too deep is refused
    // with the crate's words, as is a pattern past the compiled size or the slot table.
    let pattern =
        regex_limits::compile_translated(&translated, ignore_case).map_err(|e| PatternFault::Refused(e.to_string()))?;
    Ok(Compiled { pattern, line_anchors })
}

/// What one match holds, as the memory budget counts it: its text, its groups' texts and
/// their share of the collection.
fn hit_bytes(value: &str, groups: &[Option<Rc<str>>]) -> u64 {
    (HIT_BYTES + value.len() + groups.iter().map(|g| 16 + g.as_ref().map_or(0, |t| t.len())).sum::<usize>()) as u64
}

/// What a MatchCollection's matches hold together.
pub fn hits_bytes(hits: &[Hit]) -> u64 {
    hits.iter().map(|h| hit_bytes(&h.value, &h.groups)).sum()
}

/// UTF-16 units in `text` (VBScript's string positions).
fn utf16_len(text: &str) -> usize {
    text.chars().map(char::len_utf16).sum()
}

/// Why Execute or Replace stopped part way.
#[derive(Debug)]
enum Stopped {
    /// Execute's matches passed the memory budget: the bytes they came to.
    Memory(u64),
    /// Replace's text passed the longest string.
    TooLong,
    /// The searches of a global search passed the work limit.
    Work(TooMuchWork),
}

/// Each match of `compiled` in `text` with its groups' texts (`None` for a group that took
/// no part): the first, or with `global` every one, as JScript's global search finds them
/// (after an empty match the search goes on from the next character, so `a*` finds "",
/// "aaa" and "" in "baaa"). With `global` each search is charged the bytes it reads
/// (`regex_limits::Searches`): the work of them all, or `Err` once it passes the limit.
fn each_match(
    compiled: &Compiled,
    text: &str,
    global: bool,
    mut found: impl FnMut(regex::Match, Vec<Option<Rc<str>>>) -> bool,
) -> Result<u64, TooMuchWork> {
    let regex = &compiled.pattern.regex;
    let mut searches = compiled.pattern.searches(text);
    let mut locations = regex.capture_locations();
    let mut at = 0;
    while at <= text.len() {
        if global {
            searches.charge(at)?;
        }
        let Some(whole) = regex.captures_read_at(&mut locations, text, at) else { break };
        let groups = (1..locations.len()).map(|g| locations.get(g).map(|(s, e)| Rc::from(&text[s..e]))).collect();
        if !found(whole, groups) || !global {
            break;
        }
        at = match whole.end() > whole.start() {
            true => whole.end(),
            false => whole.end() + text[whole.end()..].chars().next().map_or(1, char::len_utf8),
        };
    }
    Ok(searches.work())
}

/// The matches `Execute` gives, their places counted in UTF-16 units, and the searches'
/// work; stopped once the matches pass `budget` (the run's memory limit) or the searches the
/// work limit.
fn find(compiled: &Compiled, text: &str, global: bool, budget: u64) -> Result<(Vec<Hit>, u64), Stopped> {
    let mut hits = Vec::new();
    let (mut counted_to, mut units, mut bytes) = (0, 0, 0u64);
    let work = each_match(compiled, text, global, |whole, groups| {
        units += utf16_len(&text[counted_to..whole.start()]);
        counted_to = whole.start();
        bytes = bytes.saturating_add(hit_bytes(whole.as_str(), &groups));
        let value = Rc::from(whole.as_str());
        hits.push(Hit { value, first_index: units, length: utf16_len(whole.as_str()), groups });
        bytes <= budget
    })
    .map_err(Stopped::Work)?;
    if bytes > budget {
        return Err(Stopped::Memory(bytes));
    }
    Ok((hits, work))
}

/// The replacement text of one match: `$&` the match, `` $` `` the text before it, `$'` the
/// text after it, `$n`/`$nn` a group (empty when it took no part; two digits when there are
/// that many groups, else one), `$$` a `$`, any other `$` itself (JScript's `replace`, which
/// VBScript's Replace method follows).
fn expand(replacement: &str, text: &str, hit_at: (usize, usize), groups: &[Option<Rc<str>>]) -> String {
    let mut out = String::new();
    let chars: Vec<char> = replacement.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        i += 1;
        if c != '$' || i >= chars.len() {
            out.push(c);
            continue;
        }
        match chars[i] {
            '$' => out.push('$'),
            '&' => out.push_str(&text[hit_at.0..hit_at.1]),
            '`' => out.push_str(&text[..hit_at.0]),
            '\'' => out.push_str(&text[hit_at.1..]),
            d if d.is_ascii_digit() => {
                let one = d.to_digit(10).unwrap_or(0) as usize;
                let two = chars.get(i + 1).and_then(|e| e.to_digit(10)).map(|e| one * 10 + e as usize);
                let (n, used) = match two {
                    Some(n) if (1..=groups.len()).contains(&n) => (n, 2),
                    _ if (1..=groups.len()).contains(&one) => (one, 1),
                    _ => {
                        out.push('$');
                        continue;
                    }
                };
                out.push_str(groups[n - 1].as_deref().unwrap_or(""));
                i += used;
                continue;
            }
            _ => {
                out.push('$');
                continue;
            }
        }
        i += 1;
    }
    out
}

/// `Replace`: the text with the first match, or with `global` every match, replaced, and the
/// searches' work; stopped once the text passes `limit` characters (the longest string a
/// macro may make) or the searches the work limit.
fn replace(
    compiled: &Compiled,
    text: &str,
    replacement: &str,
    global: bool,
    limit: usize,
) -> Result<(String, u64), Stopped> {
    let mut out = String::with_capacity(text.len());
    let (mut copied, mut chars) = (0, 0usize);
    let work = each_match(compiled, text, global, |whole, groups| {
        let before = &text[copied..whole.start()];
        let expanded = expand(replacement, text, (whole.start(), whole.end()), &groups);
        chars = chars.saturating_add(before.chars().count() + expanded.chars().count());
        out.push_str(before);
        out.push_str(&expanded);
        copied = whole.end();
        chars <= limit
    })
    .map_err(Stopped::Work)?;
    chars = chars.saturating_add(text[copied..].chars().count());
    out.push_str(&text[copied..]);
    if chars > limit {
        return Err(Stopped::TooLong);
    }
    Ok((out, work))
}

// ---- the objects' members ---------------------------------------------------------------

impl Interp<'_, '_> {
    fn regex_error(&self, span: Span, code: u32, what: &str) -> Fault {
        let mut fault = self.fault_at(span, format!("{what}: {} (run-time error {code})", vbscript_text(code)));
        fault.code = code;
        fault
    }

    /// A text argument, as a String parameter receives it.
    fn regex_text(&self, arg: Option<&Expr>, link: &Link, what: &str) -> Run<Rc<str>> {
        let v = self.eval(self.required(arg, link, what)?)?;
        vba_text(&v).map_err(|e| self.fault_at(link.span, format!("{}: the {what} is {e}", link.name)))
    }

    /// The RegExp's pattern compiled (once for each Pattern, IgnoreCase and MultiLine).
    fn compiled(&self, settings: &Rc<RefCell<Settings>>, span: Span, method: &str) -> Run<Rc<Compiled>> {
        if let Some(compiled) = settings.borrow().compiled.clone() {
            return Ok(compiled);
        }
        let (pattern, ignore_case, multiline) = {
            let s = settings.borrow();
            (s.pattern.clone(), s.ignore_case, s.multiline)
        };
        let compiled = compile(&pattern, ignore_case, multiline).map_err(|fault| match fault {
            PatternFault::Vbscript(code, at) => {
                self.regex_error(span, code, &format!("{method}: the pattern \"{pattern}\", at character {}", at + 1))
            }
            PatternFault::Refused(why) => self.unsupported(span, format!("{method}: the pattern \"{pattern}\": {why}")),
        })?;
        let compiled = Rc::new(compiled);
        settings.borrow_mut().compiled = Some(compiled.clone());
        Ok(compiled)
    }

    /// The searched text, refused where the translation could not match as VBScript does.
    fn searched(&self, compiled: &Compiled, link: &Link) -> Run<Rc<str>> {
        let args = self.member_args(link, &["sourceString"])?;
        let text = self.regex_text(args[0], link, "sourceString")?;
        self.refuse_crlf_lines(compiled, &text, link)?;
        self.search_work(compiled, &text, link)?;
        Ok(text)
    }

    /// A search of `text`, refused before it runs past the work limit of `regex_limits`, and
    /// counted against the statement limit as text work: a loop of searches each within
    /// the limit still ends.
    #[inline(never)]
    fn search_work(&self, compiled: &Compiled, text: &str, link: &Link) -> Run<()> {
        if let Err(too_much) = compiled.pattern.check(text) {
            let mut f = self.fault_at(link.span, format!("{}: {too_much}", link.name));
            f.kind = super::ErrorKind::Limit;
            return Err(f);
        }
        self.add_work(compiled.pattern.work(text) / SEARCH_WORK_PER_UNIT);
        Ok(())
    }

    /// VBScript's `^`/`$` under MultiLine also match between a CR and its LF, which the
    /// crate's lines do not: such text is refused rather than matched otherwise.
    fn refuse_crlf_lines(&self, compiled: &Compiled, text: &str, link: &Link) -> Run<()> {
        if compiled.line_anchors && text.contains("\r\n") {
            return Err(self.unsupported(
                link.span,
                format!(
                    "{}: with MultiLine, ^ and $ on text holding CR LF (vbCrLf) are not supported; \
                     Replace(text, vbCrLf, vbLf) first",
                    link.name
                ),
            ));
        }
        Ok(())
    }

    /// Execute or Replace stopped part way, a Limit error naming the limit; the searches' work
    /// otherwise counted against the statement limit.
    #[inline(never)]
    fn stopped_or_counted<T>(&self, result: Result<(T, u64), Stopped>, link: &Link) -> Run<T> {
        match result {
            Ok((value, work)) => {
                self.add_work(work / SEARCH_WORK_PER_UNIT);
                Ok(value)
            }
            Err(Stopped::Memory(bytes)) => Err(self.too_many_matches(bytes, link.span)),
            Err(Stopped::TooLong) => Err(self.replaced_too_long(link.span)),
            Err(Stopped::Work(too_much)) => {
                let mut f = self.fault_at(link.span, format!("{}: {too_much}", link.name));
                f.kind = super::ErrorKind::Limit;
                Err(f)
            }
        }
    }

    /// Execute's matches past the run's memory limit: stopped before they take more.
    fn too_many_matches(&self, bytes: u64, span: Span) -> Fault {
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        let why = format!(
            "Execute: the matches hold more than {:.1} MiB, the macro's memory limit ({:.1} MiB reached; {})",
            mib(self.options.max_memory),
            mib(bytes),
            self.options.raise_hint("raise it with --max-memory")
        );
        let mut f = self.fault_at(span, why);
        f.kind = super::ErrorKind::Limit;
        f
    }

    /// Replace's text past the longest string a macro may make: stopped as it passes it.
    fn replaced_too_long(&self, span: Span) -> Fault {
        let why = format!(
            "Replace: the text would be longer than {} characters (ncsheet's limit for macro strings; {})",
            self.options.max_string,
            self.options.raise_hint("raise it with --max-string")
        );
        let mut f = self.fault_at(span, why);
        f.kind = super::ErrorKind::Limit;
        f
    }

    /// A member of a RegExp, a MatchCollection, a Match or a SubMatches collection.
    pub(super) fn regex_member(&self, object: RegexObj, link: &Link) -> Run<Obj> {
        let name = lower(link);
        match (&object, name.as_str()) {
            (RegexObj::RegExp(s), _) => self.regexp_member(s, link, &name),
            (RegexObj::Matches(hits), "count") => Ok(Obj::Value(Value::Number(hits.len() as f64))),
            (RegexObj::Matches(_) | RegexObj::SubMatches(..), "item") => {
                let args = self.member_args(link, &["index"])?;
                let index = self.eval(self.required(args[0], link, "index")?)?;
                self.regex_item(&object, &index, link.span).map(super::collections::var_obj)
            }
            (RegexObj::SubMatches(hits, i), "count") => Ok(Obj::Value(Value::Number(hits[*i].groups.len() as f64))),
            (RegexObj::Match(hits, i), _) => self.match_member(hits, *i, link, &name),
            _ => Err(self.no_member(&Obj::Regex(object.clone()), link)),
        }
    }

    fn match_member(&self, hits: &Rc<Vec<Hit>>, i: usize, link: &Link, name: &str) -> Run<Obj> {
        let hit = &hits[i];
        let plain = |v: Value| match &link.args {
            None => Ok(Obj::Value(v)),
            Some(_) => Err(self.fault_at(link.span, format!("Match.{} takes no argument", link.name))),
        };
        match name {
            "value" => plain(Value::Text(hit.value.clone())),
            "firstindex" => plain(Value::Number(hit.first_index as f64)),
            "length" => plain(Value::Number(hit.length as f64)),
            "submatches" => {
                let sub = RegexObj::SubMatches(hits.clone(), i);
                match &link.args {
                    None => Ok(Obj::Regex(sub)),
                    // `m.SubMatches(0)`: its default member, Item.
                    Some(_) => {
                        let args = self.member_args(link, &["index"])?;
                        let index = self.eval(self.required(args[0], link, "index")?)?;
                        self.regex_item(&sub, &index, link.span).map(super::collections::var_obj)
                    }
                }
            }
            _ => Err(self.no_member(&Obj::Regex(RegexObj::Match(hits.clone(), i)), link)),
        }
    }

    /// The RegExp object a variable holds.
    pub(super) fn regex_named(&self, name: &str) -> Option<RegexObj> {
        self.peek(name, |held| match held {
            Var::Obj(Obj::Regex(r)) => Some(r.clone()),
            _ => None,
        })
        .flatten()
    }

    /// The node is `m(i)` of a variable holding one of these objects.
    pub(super) fn regex_element(&self, id: u32) -> Option<(RegexObj, &[Expr], Span)> {
        let Node::Element { var, index, span } = &self.module.nodes[id as usize] else { return None };
        self.regex_named(var).map(|r| (r, index.as_slice(), *span))
    }

    /// `matches(i)`, `subs(i)`: the item by its one index.
    pub(super) fn regex_element_item(&self, object: &RegexObj, index: &[Expr], span: Span) -> Run<Var> {
        let [one] = index else { return Err(self.fault_at(span, "an item is picked by one index")) };
        let n = self.eval(one)?;
        self.regex_item(object, &n, span)
    }

    /// The one index of `matches(i)`.
    pub(super) fn regex_index(&self, args: &[Arg], span: Span) -> Run<Value> {
        match args {
            [Arg { name: None, value }] => self.eval(value),
            _ => Err(self.fault_at(span, "an item is picked by one index")),
        }
    }

    /// `Item(index)`, the default member of a MatchCollection and of SubMatches: 0-based; an
    /// index past the items is "Invalid procedure call or argument".
    pub(super) fn regex_item(&self, object: &RegexObj, index: &Value, span: Span) -> Run<Var> {
        let n = self.number_of(index, "the index").map_err(|m| self.fault_at(span, m))?.round_ties_even();
        let count = match object {
            RegexObj::Matches(hits) => hits.len(),
            RegexObj::SubMatches(hits, i) => hits[*i].groups.len(),
            other => return Err(self.fault_at(span, format!("{} has no items", other.describe()))),
        };
        if n < 0.0 || n >= count as f64 {
            return Err(self.regex_error(
                span,
                INVALID_CALL,
                &format!("item {n} of {}, which has {count}", object.describe()),
            ));
        }
        Ok(match object {
            RegexObj::Matches(hits) => Var::Obj(Obj::Regex(RegexObj::Match(hits.clone(), n as usize))),
            RegexObj::SubMatches(hits, i) => group_var(&hits[*i].groups[n as usize]),
            _ => unreachable!("counted above"),
        })
    }

    fn regexp_member(&self, settings: &Rc<RefCell<Settings>>, link: &Link, name: &str) -> Run<Obj> {
        let flag = |v: bool| Ok(Obj::Value(Value::Bool(v)));
        match name {
            "pattern" => Ok(Obj::Value(Value::Text(settings.borrow().pattern.clone()))),
            "global" => flag(settings.borrow().global),
            "ignorecase" => flag(settings.borrow().ignore_case),
            "multiline" => flag(settings.borrow().multiline),
            "test" => {
                let compiled = self.compiled(settings, link.span, "Test")?;
                let text = self.searched(&compiled, link)?;
                flag(compiled.pattern.regex.is_match(&text))
            }
            "execute" => {
                let compiled = self.compiled(settings, link.span, "Execute")?;
                let text = self.searched(&compiled, link)?;
                let budget = self.options.max_memory;
                let hits = self.stopped_or_counted(find(&compiled, &text, settings.borrow().global, budget), link)?;
                self.charge(hits_bytes(&hits), link.span)?;
                Ok(Obj::Regex(RegexObj::Matches(Rc::new(hits))))
            }
            "replace" => {
                let compiled = self.compiled(settings, link.span, "Replace")?;
                let args = self.member_args(link, &["sourceString", "replaceString"])?;
                let text = self.regex_text(args[0], link, "sourceString")?;
                self.refuse_crlf_lines(&compiled, &text, link)?;
                self.search_work(&compiled, &text, link)?;
                let replacement = self.regex_text(args[1], link, "replaceString")?;
                let limit = self.options.max_string;
                let found = replace(&compiled, &text, &replacement, settings.borrow().global, limit);
                let replaced = self.stopped_or_counted(found, link)?;
                self.charge(replaced.len() as u64, link.span)?;
                Ok(Obj::Value(Value::Text(replaced.into())))
            }
            _ => Err(self.no_member(&Obj::Regex(RegexObj::RegExp(settings.clone())), link)),
        }
    }

    /// `re.Pattern = "…"`, `re.Global = True` …: a RegExp's properties; the others are read-only.
    pub(super) fn set_regex_member(&self, object: &RegexObj, link: &Link, value: &Expr) -> Run<()> {
        let RegexObj::RegExp(settings) = object else {
            return Err(self.fault_at(link.span, format!("{}.{} is read-only", object.describe(), link.name)));
        };
        let name = lower(link);
        if name == "pattern" {
            let v = self.eval(value)?;
            let text = vba_text(&v).map_err(|e| self.fault_at(link.span, format!("Pattern: the value is {e}")))?;
            let mut s = settings.borrow_mut();
            s.pattern = text;
            s.compiled = None;
            return Ok(());
        }
        if !matches!(name.as_str(), "global" | "ignorecase" | "multiline") {
            return Err(self.no_member(&Obj::Regex(object.clone()), link));
        }
        let on = self.truth(value, &link.name)?;
        let mut s = settings.borrow_mut();
        match name.as_str() {
            "global" => s.global = on,
            "ignorecase" => s.ignore_case = on,
            _ => s.multiline = on,
        }
        if name != "global" {
            s.compiled = None;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{compile, expand, find, PatternFault};

    fn all(pattern: &str, text: &str) -> Vec<(usize, String)> {
        let compiled = compile(pattern, false, false).unwrap();
        find(&compiled, text, true, u64::MAX)
            .unwrap()
            .0
            .into_iter()
            .map(|h| (h.first_index, h.value.to_string()))
            .collect()
    }

    /// JavaScript's `"baaa".match(/a*/g)` is ["", "aaa", ""] (ECMA-262 3rd ed. 15.5.4.10: an
    /// empty match moves the search on by one).
    #[test]
    fn an_empty_match_moves_the_search_on_by_one() {
        assert_eq!(all("a*", "baaa"), [(0, String::new()), (1, "aaa".into()), (4, String::new())]);
    }

    /// Positions count UTF-16 units: "😀" is two, so the "a" after it is at 2.
    #[test]
    fn positions_count_utf16_units() {
        assert_eq!(all("a", "😀a"), [(2, "a".to_string())]);
    }

    #[test]
    fn vbscript_errors_of_bad_patterns() {
        let code = |p: &str| match compile(p, false, false) {
            Err(PatternFault::Vbscript(code, _)) => code,
            other => panic!("{p}: {other:?}"),
        };
        assert_eq!(code("a("), 5020);
        assert_eq!(code("[a"), 5019);
        assert_eq!(code("*a"), 5018);
        assert_eq!(code("[z-a]"), 5021);
        assert_eq!(code("a)"), 5017);
        assert_eq!(code("a{3,2}"), 5017);
    }

    /// ECMA-262 3rd ed. 15.5.4.11, Table 22: `$$`, `$&`, `` $` ``, `$'`, `$n`, `$nn`.
    #[test]
    fn replacement_patterns() {
        let groups = [Some("b".into()), None];
        let text = "xaby";
        assert_eq!(expand("[$&|$`|$'|$$|$1|$2|$3|$01|$10]", text, (1, 3), &groups), "[ab|x|y|$|b||$3|b|b0]");
    }
}
