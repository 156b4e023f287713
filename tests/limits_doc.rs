//! docs/limits.md lists every limit with its number (issue 30's acceptance): each constant of
//! the source whose name says it bounds something (`MAX_…`, `…_MAX`, `…LIMIT…`, `…BUDGET…`,
//! `…RESERVE…`) must be named in the doc, on a line that also names its file and gives the
//! same number as the code (`1 << 24`, `16 * 1024 * 1024`, `1_000_000` worked out here, apart
//! from the code). An internal size is listed too, marked as one, so that nothing is left out
//! by accident: a new limit fails this test until the doc says what it is.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One `const` of the source: where it is, its name, its type and its expression.
#[derive(Debug)]
struct Constant {
    file: String,
    name: String,
    ty: String,
    expr: String,
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every `const NAME: TYPE = EXPR;` of the workspace's sources (an expression may run over
/// several lines).
fn constants(root: &Path) -> Vec<Constant> {
    let mut files = Vec::new();
    for dir in ["crates/ncsheet/src", "crates/ncsheet-server/src", "src"] {
        rust_files(&root.join(dir), &mut files);
    }
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let file = path.strip_prefix(root).unwrap().to_string_lossy().into_owned();
        let mut rest = text.as_str();
        while let Some(at) = rest.find("const ") {
            let after = &rest[at + "const ".len()..];
            let starts_word =
                at == 0 || !rest.as_bytes()[at - 1].is_ascii_alphanumeric() && rest.as_bytes()[at - 1] != b'_';
            rest = after;
            let Some(colon) = after.find(':') else { break };
            let name = after[..colon].trim();
            if !starts_word
                || name.is_empty()
                || !name.bytes().all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
            {
                continue;
            }
            // The `;` that ends the item, after its `=` (a type `[f64; 2]` holds one too).
            let Some(eq) = after.find('=') else { continue };
            let Some(end) = after[eq..].find(';').map(|e| eq + e) else { continue };
            if after[..eq].contains(['{', '}', '(']) {
                continue;
            }
            let ty = after[colon + 1..eq].trim().to_string();
            let expr = after[eq + 1..end].trim().to_string();
            out.push(Constant { file: file.clone(), name: name.to_string(), ty, expr });
        }
    }
    out
}

/// Whether a constant's name says that it bounds something.
fn names_a_limit(name: &str) -> bool {
    name.starts_with("MAX_")
        || name.starts_with("DEFAULT_MAX_")
        || name.ends_with("_MAX")
        || name.contains("_MAX_")
        || ["LIMIT", "BUDGET", "RESERVE"].iter().any(|w| name.contains(w))
}

/// The largest value of a primitive integer type, or of an alias of one (`SheetId`).
fn type_max(ty: &str, aliases: &HashMap<String, String>) -> Option<f64> {
    let ty = aliases.get(ty).map_or(ty, String::as_str);
    Some(match ty {
        "u8" => u8::MAX as f64,
        "u16" => u16::MAX as f64,
        "u32" => u32::MAX as f64,
        "i32" => i32::MAX as f64,
        "u64" => u64::MAX as f64,
        "i64" => i64::MAX as f64,
        "usize" => usize::MAX as f64,
        _ => return None,
    })
}

/// A constant expression's value: numbers, `+ - * / <<`, parentheses, `as` casts, other
/// constants by name and `TYPE::MAX`.
struct Evaluator<'a> {
    by_name: HashMap<&'a str, &'a Constant>,
    aliases: HashMap<String, String>,
}

impl Evaluator<'_> {
    fn value(&self, expr: &str, depth: u32) -> Option<f64> {
        let tokens = tokenize(expr);
        let mut at = 0;
        let v = self.shift(&tokens, &mut at, depth)?;
        (at == tokens.len()).then_some(v)
    }

    fn shift(&self, t: &[String], at: &mut usize, depth: u32) -> Option<f64> {
        let mut v = self.sum(t, at, depth)?;
        while t.get(*at).is_some_and(|s| s == "<<") {
            *at += 1;
            v *= 2f64.powf(self.sum(t, at, depth)?);
        }
        Some(v)
    }

    fn sum(&self, t: &[String], at: &mut usize, depth: u32) -> Option<f64> {
        let mut v = self.product(t, at, depth)?;
        while let Some(op) = t.get(*at).filter(|s| *s == "+" || *s == "-") {
            let minus = op == "-";
            *at += 1;
            let r = self.product(t, at, depth)?;
            v = if minus { v - r } else { v + r };
        }
        Some(v)
    }

    fn product(&self, t: &[String], at: &mut usize, depth: u32) -> Option<f64> {
        let mut v = self.atom(t, at, depth)?;
        while let Some(op) = t.get(*at).filter(|s| *s == "*" || *s == "/") {
            let divide = op == "/";
            *at += 1;
            let r = self.atom(t, at, depth)?;
            v = if divide { (v / r).trunc() } else { v * r };
        }
        Some(v)
    }

    fn atom(&self, t: &[String], at: &mut usize, depth: u32) -> Option<f64> {
        let token = t.get(*at)?.clone();
        *at += 1;
        let v = if token == "(" {
            let v = self.shift(t, at, depth)?;
            (t.get(*at)? == ")").then_some(())?;
            *at += 1;
            v
        } else if token == "-" {
            -self.atom(t, at, depth)?
        } else if token.as_bytes()[0].is_ascii_digit() {
            token.replace('_', "").trim_end_matches(|c: char| c.is_ascii_alphabetic() && c != 'e').parse().ok()?
        } else {
            self.path(&token, depth)?
        };
        // `as TYPE` casts change no value these constants hold.
        while t.get(*at).is_some_and(|s| s == "as") {
            *at += 2;
        }
        Some(v)
    }

    /// `NAME`, `a::b::NAME` (another constant) or `TYPE::MAX`.
    fn path(&self, token: &str, depth: u32) -> Option<f64> {
        let segments: Vec<&str> = token.split("::").collect();
        let last = *segments.last()?;
        if last == "MAX" && segments.len() >= 2 {
            return type_max(segments[segments.len() - 2], &self.aliases);
        }
        let c = self.by_name.get(last)?;
        (depth < 8).then_some(())?;
        self.value(&c.expr, depth + 1)
    }
}

fn tokenize(expr: &str) -> Vec<String> {
    let mut out = Vec::new();
    let chars: Vec<char> = expr.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c == '<' && chars.get(i + 1) == Some(&'<') {
            out.push("<<".into());
            i += 2;
        } else if "+-*/()".contains(c) {
            out.push(c.to_string());
            i += 1;
        } else {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || "_.:".contains(chars[i])) {
                // A number's exponent sign (`1e-6`) belongs to the number.
                i += 1;
                if chars[start].is_ascii_digit()
                    && matches!(chars[i - 1], 'e' | 'E')
                    && chars.get(i).is_some_and(|&s| s == '-' || s == '+')
                {
                    i += 1;
                }
            }
            if i == start {
                return vec![format!("unreadable {c}")];
            }
            out.push(chars[start..i].iter().collect());
        }
    }
    out
}

/// The numbers a line of the doc gives: `16,777,216`, `1_000_000`, `2^24`, `10^9`, `1e9`,
/// `1e-6`, `64 MiB`, `1 GiB`, with either sign.
fn numbers_in(line: &str) -> Vec<f64> {
    let chars: Vec<char> = line.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if !chars[i].is_ascii_digit() || i > 0 && (chars[i - 1].is_ascii_alphanumeric() || chars[i - 1] == '_') {
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len() && (chars[i].is_ascii_digit() || ",._".contains(chars[i])) {
            i += 1;
        }
        let mut digits: String = chars[start..i].iter().filter(|c| !",_".contains(**c)).collect();
        while digits.ends_with('.') {
            digits.pop();
        }
        let Ok(mut v) = digits.parse::<f64>() else { continue };
        let rest: String = chars[i..].iter().take(12).collect();
        if let Some(power) = rest.strip_prefix('^') {
            let exp: String = power.chars().take_while(|c| c.is_ascii_digit()).collect();
            v = v.powi(exp.parse().unwrap_or(1));
        } else if let Some(exp) = rest.strip_prefix(['e', 'E']) {
            let exp: String = exp
                .chars()
                .enumerate()
                .take_while(|(k, c)| c.is_ascii_digit() || *k == 0 && *c == '-')
                .map(|(_, c)| c)
                .collect();
            v *= 10f64.powi(exp.parse().unwrap_or(0));
        } else if let Some(unit) =
            [("GiB", 30), ("MiB", 20), ("KiB", 10)].iter().find(|(u, _)| rest.trim_start().starts_with(u))
        {
            v *= 2f64.powi(unit.1);
        }
        out.push(v);
        out.push(-v);
    }
    out
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

#[test]
fn every_limit_constant_is_in_docs_limits_md_with_its_number() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/limits.md")).unwrap();
    let all = constants(root);
    let mut aliases = HashMap::new();
    for path in ["crates/ncsheet/src/formula/ast.rs"] {
        let text = std::fs::read_to_string(root.join(path)).unwrap();
        for line in text.lines() {
            if let Some(rest) = line.trim().strip_prefix("pub type ") {
                if let Some((name, ty)) = rest.trim_end_matches(';').split_once(" = ") {
                    aliases.insert(name.trim().to_string(), ty.trim().to_string());
                }
            }
        }
    }
    let eval = Evaluator { by_name: all.iter().map(|c| (c.name.as_str(), c)).collect(), aliases };
    let limits: Vec<&Constant> = all.iter().filter(|c| names_a_limit(&c.name)).collect();
    assert!(limits.len() > 60, "the scan found only {} limit constants: {limits:?}", limits.len());
    let mut missing = Vec::new();
    for c in &limits {
        // An array of numbers (`[-90.0, 90.0]`): each of them.
        let expected: Vec<f64> = if c.ty.starts_with('[') {
            c.expr.trim_matches(['[', ']']).split(',').filter_map(|x| eval.value(x.trim(), 0)).collect()
        } else {
            match eval.value(&c.expr, 0) {
                Some(v) => vec![v],
                None => panic!("{}: {} = {}: this test cannot work out the value", c.file, c.name, c.expr),
            }
        };
        let named = format!("`{}`", c.name);
        let lines: Vec<&str> = doc.lines().filter(|l| l.contains(&named) && l.contains(&c.file)).collect();
        let given = lines.iter().any(|l| {
            let numbers = numbers_in(l);
            expected.iter().all(|v| numbers.iter().any(|n| same(*n, *v)))
        });
        if !given {
            missing.push(format!("{} `{}` = {:?} ({})", c.file, c.name, expected, c.expr));
        }
    }
    assert!(
        missing.is_empty(),
        "docs/limits.md does not list these with their file and number ({} of {}):\n{}",
        missing.len(),
        limits.len(),
        missing.join("\n")
    );
}

/// The doc's numbers as the check reads them, worked by hand.
#[test]
fn the_doc_numbers_are_read_in_each_spelling() {
    let n = numbers_in("16,777,216 (2^24), 1_000_000, 1e9, 1e-6, 64 MiB, 1 GiB, 10^9, 1.5");
    for v in [16_777_216.0, 16_777_216.0, 1e6, 1e9, 1e-6, 67_108_864.0, 1_073_741_824.0, 1e9, 1.5] {
        assert!(n.iter().any(|x| same(*x, v)), "{v} in {n:?}");
    }
    let c = |expr: &str| Constant { file: String::new(), name: "X".into(), ty: "usize".into(), expr: expr.into() };
    let (a, b) = (c("1 << 24"), c("16 * 1024 * 1024"));
    let eval = Evaluator { by_name: [("A", &a), ("B", &b)].into_iter().collect(), aliases: HashMap::new() };
    assert_eq!(eval.value("A", 0), Some(16_777_216.0));
    assert_eq!(eval.value("B", 0), Some(16_777_216.0));
    assert_eq!(eval.value("256 << 20", 0), Some(268_435_456.0));
    assert_eq!(eval.value("u16::MAX as usize + 1", 0), Some(65_536.0));
    assert_eq!(eval.value("1_000_000", 0), Some(1e6));
    assert_eq!(eval.value("2_147_483_647.0", 0), Some(2_147_483_647.0));
}

/// The text of every string literal of the workspace's sources, cut at its format holes
/// (`{limit}`, `{}`, `{:.1}`) into the pieces a message is made of, each piece's runs of
/// white space one space (a literal continued with `\` on the next line reads as one line).
fn message_pieces(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for dir in ["crates/ncsheet/src", "crates/ncsheet-server/src", "src"] {
        rust_files(&root.join(dir), &mut files);
    }
    let mut pieces = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        for literal in string_literals(&text) {
            pieces.extend(format_pieces(&literal).into_iter().map(|p| one_line(&p)));
        }
    }
    pieces
}

/// The string literals of Rust source `text`, escapes undone: `"…"`, `r"…"`, `r#"…"#`, `b"…"`;
/// comments and character literals (`'"'`) skipped, so that a quote in them starts nothing.
fn string_literals(text: &str) -> Vec<String> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => i = text[i..].find('\n').map_or(b.len(), |n| i + n),
            b'/' if b.get(i + 1) == Some(&b'*') => i = text[i + 2..].find("*/").map_or(b.len(), |n| i + n + 4),
            b'\'' => i = after_char_literal(b, i),
            b'r' if !word_before(b, i) && matches!(b.get(i + 1), Some(b'"' | b'#')) => {
                let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
                if b.get(i + 1 + hashes) != Some(&b'"') {
                    i += 1;
                    continue;
                }
                let start = i + 2 + hashes;
                let close = format!("\"{}", "#".repeat(hashes));
                let end = text[start..].find(&close).map_or(b.len(), |n| start + n);
                out.push(text[start..end].to_string());
                i = end + close.len();
            }
            b'"' => {
                let start = i + 1;
                let mut end = start;
                while end < b.len() && b[end] != b'"' {
                    end += if b[end] == b'\\' { 2 } else { 1 };
                }
                out.push(unescape(&text[start..end.min(b.len())]));
                i = end + 1;
            }
            _ => i += 1,
        }
    }
    out
}

/// Whether the byte before `i` continues a word (`for"`, `attr"`: no raw string starts there).
fn word_before(b: &[u8], i: usize) -> bool {
    i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')
}

/// Where the character literal or lifetime starting at the `'` at `i` ends.
fn after_char_literal(b: &[u8], i: usize) -> usize {
    match (b.get(i + 1), b.get(i + 2)) {
        // `'\''`, `'\n'`, `'\u{…}'`: up to the closing quote.
        (Some(b'\\'), _) => b[i + 3..].iter().position(|&c| c == b'\'').map_or(b.len(), |n| i + 3 + n + 1),
        (Some(_), Some(b'\'')) => i + 3,
        // A character of several bytes (`'…'`), or a lifetime (`'a`), which has no closing quote.
        _ => {
            let end = (i + 6).min(b.len());
            b[i + 1..end].iter().position(|&c| c == b'\'').map_or(i + 1, |n| i + 1 + n + 1)
        }
    }
}

/// A normal string literal's text: `\n`, `\t`, `\"`, `\\`, `\'`, `\0`, `\u{…}` undone, and a
/// `\` at a line's end taking the line break and the next line's indentation with it.
fn unescape(raw: &str) -> String {
    let mut out = String::new();
    let mut chars = raw.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('0') => out.push('\0'),
            Some('u') => {
                let code: String = chars.by_ref().skip(1).take_while(|&c| c != '}').collect();
                out.extend(u32::from_str_radix(&code, 16).ok().and_then(char::from_u32));
            }
            Some('\n') => {
                while chars.peek().is_some_and(|c| c.is_whitespace()) {
                    chars.next();
                }
            }
            Some(other) => out.push(other),
            None => {}
        }
    }
    out
}

/// A format string's literal pieces between its holes (`{}`, `{n:.1}`); `{{` and `}}` are
/// braces. A string that is no format string cut the same way loses nothing a quote needs.
fn format_pieces(literal: &str) -> Vec<String> {
    let mut pieces = vec![String::new()];
    let mut chars = literal.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '{' if chars.peek() == Some(&'{') => {
                chars.next();
                pieces.last_mut().unwrap().push('{');
            }
            '}' if chars.peek() == Some(&'}') => {
                chars.next();
                pieces.last_mut().unwrap().push('}');
            }
            '{' => {
                for c in chars.by_ref() {
                    if c == '}' {
                        break;
                    }
                }
                pieces.push(String::new());
            }
            c => pieces.last_mut().unwrap().push(c),
        }
    }
    pieces
}

/// `text` with each run of white space one space (kept at its ends: a piece ends where a
/// hole begins, `"… is reached: {why}"`).
fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if !c.is_whitespace() {
            out.push(c);
        } else if !out.ends_with(' ') {
            out.push(' ');
        }
    }
    out
}

/// A word of a quoted message that stands for what varies: a number (`inf` and `NaN` too),
/// `…`, a placeholder in capitals (`N`, `FILE`, `PART`) or of one letter (`(x, y)`), a quoted
/// name (`'Sheet1'`) or an option (`--max-string`, whose hint the code composes).
fn varies(word: &str) -> bool {
    let core = word.trim_matches(|c: char| ".,:;()'\"".contains(c));
    word.contains(|c: char| c.is_ascii_digit())
        || word.contains('…')
        || ["inf", "-inf", "NaN"].contains(&core)
        || core.len() == 1 && core != "a" && core.chars().all(|c| c.is_ascii_alphabetic())
        || !core.is_empty() && core.chars().all(|c| c.is_ascii_uppercase() || c == '_')
        || word.trim_start_matches('(').starts_with('\'') && word[1..].contains('\'')
        || word.trim_start_matches('(').starts_with("--")
}

/// The fixed runs of words of each message the table of limits quotes in its last column,
/// "what happens past it" (the error a user sees), with the quote they come from: runs of
/// 12 characters and two words or more, cut at the words that vary. Other tables (the
/// constants') describe, and quote code rather than messages.
fn quoted_runs(doc: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut in_limits = false;
    for line in doc.lines() {
        if !line.starts_with('|') {
            in_limits = false;
            continue;
        }
        if line.starts_with("| limit |") {
            in_limits = true;
            continue;
        }
        let Some(last) = line.trim_end().trim_end_matches('|').rsplit(" | ").next().filter(|_| in_limits) else {
            continue;
        };
        for quote in last.split('`').skip(1).step_by(2) {
            if quote.matches(' ').count() < 2 || quote.starts_with('=') {
                continue;
            }
            let mut run: Vec<&str> = Vec::new();
            for word in quote.split(' ').chain(["…"]) {
                if !varies(word) {
                    run.push(word);
                    continue;
                }
                let text = run.join(" ");
                if text.len() >= 12 && run.len() >= 2 {
                    out.push((text, quote.to_string()));
                }
                run.clear();
            }
        }
    }
    out
}

/// The pieces of the code's literals, looked up three ways.
struct Messages {
    pieces: Vec<String>,
    whole: std::collections::HashSet<String>,
    /// Every piece, `\u{1}` between them: a run inside one piece is a substring.
    joined: String,
}

/// The characters a part of a run must have for the match to hold by itself: a letter or two
/// at a hole's edge match some piece by chance.
const ANCHOR: usize = 6;

/// The most parts a run is made of (three holes crossed): with more, chains of one-letter
/// literals (`"a"`, `"n"`) would make any text.
const MAX_PARTS: u8 = 4;

impl Messages {
    fn new(pieces: Vec<String>) -> Messages {
        let pieces: Vec<String> = pieces.into_iter().filter(|p| !p.is_empty()).collect();
        let joined = pieces.join("\u{1}");
        Messages { whole: pieces.iter().cloned().collect(), pieces, joined }
    }

    /// Whether `run` is what the code writes: inside one piece of a literal, or pieces
    /// joined where the code fills a hole (`"…({limit}) is reached: {why} ({hint})"` with
    /// `why` and `hint` other literals): the end of one piece, whole pieces, the start of
    /// another, at most [`MAX_PARTS`] in all and one of them at least [`ANCHOR`] characters.
    fn write(&self, run: &str) -> bool {
        const NONE: u8 = u8::MAX;
        if self.joined.contains(run) {
            return true;
        }
        let ends: Vec<usize> = run.char_indices().map(|(at, _)| at).chain([run.len()]).collect();
        // fewest[k][anchored]: the fewest parts making run[..ends[k]] (a piece's end, then whole
        // pieces), with or without a part of ANCHOR characters among them.
        let mut fewest = vec![[NONE; 2]; ends.len()];
        for (k, &end) in ends.iter().enumerate().take(ends.len() - 1).skip(1) {
            if self.pieces.iter().any(|p| p.ends_with(&run[..end])) {
                fewest[k][usize::from(end >= ANCHOR)] = 1;
            }
        }
        for k in 1..ends.len() {
            for anchored in [false, true] {
                let parts = fewest[k][usize::from(anchored)];
                if parts >= MAX_PARTS {
                    continue;
                }
                let rest = &run[ends[k]..];
                let holds = anchored || rest.len() >= ANCHOR;
                if !rest.is_empty() && holds && self.pieces.iter().any(|p| p.starts_with(rest)) {
                    return true;
                }
                for j in k + 1..ends.len() {
                    if self.whole.contains(&run[ends[k]..ends[j]]) {
                        let slot = &mut fewest[j][usize::from(anchored || ends[j] - ends[k] >= ANCHOR)];
                        *slot = (*slot).min(parts + 1);
                    }
                }
            }
        }
        fewest[ends.len() - 1][1] != NONE
    }
}

/// docs/limits.md quotes the error a user sees past each limit: each quote's fixed words are
/// what the code writes (its format holes standing for what varies), so a message changed
/// in the code, or mistyped in the doc, fails here until the two agree.
#[test]
fn every_error_docs_limits_md_quotes_is_what_the_code_writes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/limits.md")).unwrap();
    let messages = Messages::new(message_pieces(root));
    let runs = quoted_runs(&doc);
    assert!(runs.len() > 100, "the doc's quotes gave only {} runs", runs.len());
    let wrong: Vec<String> = runs
        .iter()
        .filter(|(run, _)| !messages.write(run))
        .map(|(run, quote)| format!("{run:?}\n    in `{quote}`"))
        .collect();
    assert!(
        wrong.is_empty(),
        "docs/limits.md quotes words no message of the code writes ({} of {}):\n{}",
        wrong.len(),
        runs.len(),
        wrong.join("\n")
    );
}

/// The pieces of the code's text, worked by hand: escapes, continued lines, format holes,
/// a quote in a comment or a character literal; runs matched across holes.
#[test]
fn the_code_is_read_into_the_pieces_of_its_messages() {
    let source =
        "let c = '\"'; // \"not this\"\nf(\"a {x} b\\\n     c {{d}} {:.1}\", r#\"raw \"q\"\"#, 'a', b'\\'', \"é\");";
    let literals = string_literals(source);
    // A continued line loses its break and the next line's indentation, as Rust reads it.
    assert_eq!(literals, ["a {x} bc {{d}} {:.1}", "raw \"q\"", "é"]);
    assert_eq!(format_pieces(&literals[0]), ["a ", " bc {d} ", ""]);
    assert_eq!(one_line(" a \n   b "), " a b ");
    let messages = Messages::new(
        [
            "the statement limit (",
            ") is reached: ",
            " (",
            ")",
            "an endless loop?",
            "raise the limit with --max-statements",
            " that cannot be read: ",
            "sheet '",
            "an Excel workbook",
        ]
        .map(String::from)
        .into(),
    );
    assert!(messages.write("is reached: an endless loop? (raise the limit with"));
    assert!(messages.write("the statement limit"));
    assert!(!messages.write("is reached: a loop without end"));
    assert!(!messages.write("is reached: an endless loop? (raise it with"));
    // A short end is taken once a longer part holds the match.
    assert!(messages.write("workbook that cannot be read: sheet"));
    assert!(!messages.write("workbook that cannot be read: shelf"));
    // One-letter literals chained make nothing.
    let letters = Messages::new("an endls!(rit".chars().map(String::from).chain(["s limit (".into()]).collect());
    assert!(!letters.write("s limit (an endless loop! (raise it"));
    let quote = "the statement limit (N) is reached: an endless loop? (raise it with --max-statements)";
    let table = format!("| limit | value | where | past it |\n|---|---|---|---|\n| x | 1 | y | stops: `{quote}` |");
    let runs: Vec<String> = quoted_runs(&table).into_iter().map(|r| r.0).collect();
    assert_eq!(runs, ["the statement limit", "is reached: an endless loop? (raise it with"]);
    assert!(quoted_runs("| `MAX_X` in `a.rs` | 1 | limit | one `Rows.Hidden = True` hides |").is_empty());
}
