//! NC31 subprograms and R parameters, as the cycles paper writes them (docs/domain.md §2):
//! the control runs them, so the reader runs them too and reads the motion they stand for.
//!
//! - `R1=34`, `R3=R3-R4`: a parameter set from numbers, parameters, `+ - * /` and brackets;
//! - `XR1`, `Z-R2`, `W+R4`: a word that takes a parameter's value (its sign applied);
//! - `IF R3>0 THEN W+R4 GOTO N9`: the rest of the block only when the condition holds
//!   (`> >= < <= = <>`); `GOTO Nn` jumps to block Nn of the same (sub)program;
//! - `L03` alone in a block calls subprogram L03, which is written after the main program's
//!   `M02`, from a block `L03` to the block with `M17` (a block may move and end with M17,
//!   `N007 X30 M17`). A subprogram takes its values in the R parameters set before its call;
//! - or, as the cycles paper calls its cycles (`L13 DR2 XR1 AR3 PR0`), the header binds
//!   letters to R parameters, `L16 XR1 WR2 AR3 PR4`, and every call gives each of those
//!   letters its value, a number or a parameter's: `L16 X30 W40 A0.5 PR9` sets R1=30, R2=40,
//!   R3=0.5 and R4 to R9's value (all worked out before any is set), then runs L16.
//!
//! [`expand`] turns a program into the blocks the control executes, each with its source
//! line; a program without any of this comes back block for block.

use std::collections::HashMap;

use super::ReadError;

/// Calls nested deeper than this are refused (a subprogram that calls itself never ends).
const MAX_DEPTH: usize = 8;
/// Jumps taken before a program is refused as one that never ends.
const MAX_JUMPS: usize = 1_000_000;
/// Blocks run beyond those written before a program is refused: calls within calls
/// multiply (twelve calls a level, seven levels deep, are 35 million blocks from 100 lines)
/// where the jump and depth limits see nothing amiss.
pub(super) const MAX_BLOCKS_RUN: usize = 1_000_000;
/// Decimals a parameter's value is written with in a word: the NC31's 0.001 mm step.
const WORD_DECIMALS: usize = 3;

/// One block of source: its line, its `N` label and the code after it.
#[derive(Clone, Debug)]
struct Source {
    line: usize,
    label: Option<u32>,
    code: String,
    /// The column (1-based) the code starts at in its line.
    column: usize,
    /// The line before the code (its label as typed), kept so that columns stay the line's.
    prefix: String,
}

type Body = Vec<Source>;

/// The blocks `text` stands for, as (block text, 1-based source line), in the order the
/// control runs them.
pub(crate) fn expand(text: &str) -> Result<Vec<(String, usize)>, ReadError> {
    let (main, subprograms) = split(text)?;
    let written = main.len() + subprograms.values().map(|s| s.body.len()).sum::<usize>();
    let budget = written.saturating_add(MAX_BLOCKS_RUN);
    let mut run = Run { subprograms: &subprograms, parameters: HashMap::new(), out: Vec::new(), jumps: 0, budget };
    run.body(&main, None, 0)?;
    Ok(run.out)
}

fn error(line: usize, column: usize, message: impl Into<String>) -> ReadError {
    ReadError { line, column, message: message.into() }
}

/// A subprogram as written: the line of its header, the letters its calls give values to
/// (each with the R parameter it sets) and its blocks.
struct Sub {
    line: usize,
    parameters: Vec<(char, u32)>,
    body: Body,
}

/// Subprograms by number.
type Subprograms = HashMap<u32, Sub>;

/// A letter bound to an R parameter, as (letter, parameter).
pub(crate) type Binding = (char, u32);

/// A call's or a header's words as written: (letter, value text).
type Words = Vec<(char, String)>;

/// The main program (to its M02) and the subprograms after it, by number.
fn split(text: &str) -> Result<(Body, Subprograms), ReadError> {
    let mut main = Vec::new();
    let mut subprograms: Subprograms = HashMap::new();
    let mut ended = false;
    // The subprogram being read: its number and what is read of it so far.
    let mut open: Option<(u32, Sub)> = None;
    for (i, raw) in text.lines().enumerate() {
        let Some(source) = source(raw, i + 1)? else { continue };
        if !ended {
            ended = has_word(&source.code, 'M', 2);
            main.push(source);
            continue;
        }
        if let Some((n, mut sub)) = open.take() {
            let last = has_word(&source.code, 'M', 17);
            sub.body.push(source);
            if last {
                let line = sub.line;
                if subprograms.insert(n, sub).is_some() {
                    return Err(error(line, 1, format!("subprogram L{n:02} is written twice")));
                }
            } else {
                open = Some((n, sub));
            }
            continue;
        }
        match header(&source.code) {
            Some(Ok((n, parameters))) => open = Some((n, Sub { line: source.line, parameters, body: Vec::new() })),
            Some(Err(m)) => return Err(error(source.line, source.column, m)),
            None => {
                return Err(error(
                    source.line,
                    source.column,
                    "text after the program's end (M02) that is not a subprogram (a header `Lnn` or `Lnn XR1 …`, \
                     its blocks, M17)",
                ))
            }
        }
    }
    if let Some((n, sub)) = open {
        return Err(error(sub.line, 1, format!("subprogram L{n:02} has no M17 at its end")));
    }
    Ok((main, subprograms))
}

/// A line as a block: `None` when it holds nothing (blank, `%`).
fn source(raw: &str, line: usize) -> Result<Option<Source>, ReadError> {
    let trimmed = raw.trim_end();
    let start = trimmed.len() - trimmed.trim_start().len();
    let body = trimmed.trim_start();
    if body.is_empty() || body == "%" {
        return Ok(None);
    }
    let mut label = None;
    let mut code_at = start;
    if body.starts_with(['N', 'n']) {
        let digits: String = body[1..].chars().take_while(char::is_ascii_digit).collect();
        if !digits.is_empty() {
            label = digits.parse().ok();
            code_at = start + 1 + digits.len();
        }
    }
    let code = raw[code_at..].trim_end().to_string();
    let column = code_at + 1 + (code.len() - code.trim_start().len());
    let prefix = raw[..column - 1].to_string();
    Ok(Some(Source { line, label, code: code.trim_start().to_string(), column, prefix }))
}

/// Whether `code` holds the word `letter` with the integer value `n` (`M02`, `M2`, `M17`).
fn has_word(code: &str, letter: char, n: u32) -> bool {
    let upper = code.to_ascii_uppercase();
    let chars: Vec<char> = upper.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i] == letter && (i == 0 || !chars[i - 1].is_ascii_alphanumeric());
        if starts {
            let digits: String = chars[i + 1..].iter().take_while(|c| c.is_ascii_digit()).collect();
            if digits.parse::<u32>().ok() == Some(n) {
                return true;
            }
        }
        i += 1;
    }
    false
}

/// `Lnn …`: the subprogram's number and the text after it; `None` when `code` is no `Lnn`.
fn numbered_l(code: &str) -> Option<(u32, &str)> {
    let code = code.trim();
    let after = code.strip_prefix(['L', 'l'])?;
    let digits = after.len() - after.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let rest = &after[digits..];
    if digits == 0 || rest.starts_with(|c: char| !c.is_whitespace() && !c.is_ascii_alphabetic()) {
        return None;
    }
    Some((after[..digits].parse().ok()?, rest))
}

/// A subprogram's header: `L16` alone, or with the letters its calls give values to, each
/// bound to the R parameter it sets (`L16 XR1 WR2 AR3 PR4`); `None` when `code` is no `Lnn`.
pub(crate) fn header(code: &str) -> Option<Result<(u32, Vec<Binding>), String>> {
    let (n, rest) = numbered_l(code)?;
    Some(bindings(rest).map(|p| (n, p)).map_err(|m| format!("the header of L{n:02}: {m}")))
}

/// A subprogram given as its header and its blocks (what `Nc.Subprogram` takes): its number
/// and bindings, when the header reads and the blocks end, as the reader needs, in an `M17`
/// in the last block and in no other.
pub(crate) fn subprogram(header_text: &str, body: &[String]) -> Result<(u32, Vec<Binding>), String> {
    let (n, parameters) = header(header_text).unwrap_or_else(|| {
        Err(format!("`{}` is not a subprogram's header (L16, L16 XR1 WR2 …)", header_text.trim()))
    })?;
    let blocks: Vec<Source> = body
        .iter()
        .enumerate()
        .map(|(i, text)| match source(text, i + 1) {
            Ok(Some(s)) => Ok(s),
            _ => Err(format!("L{n:02}'s block {} is empty", i + 1)),
        })
        .collect::<Result<_, _>>()?;
    let ends = |s: &Source| has_word(&s.code, 'M', 17);
    match blocks.iter().position(ends) {
        Some(i) if i + 1 == blocks.len() => Ok((n, parameters)),
        Some(i) => Err(format!("L{n:02}'s block {} ends it with M17 before its last block", i + 1)),
        None => Err(format!("L{n:02} has no M17 at the end of its last block")),
    }
}

/// The subprogram a block calls (`N4 L03`, `IF R1>0 THEN L03`), if it calls one.
pub(crate) fn called(block: &str) -> Option<u32> {
    let source = source(block, 1).ok()??;
    let code = match conditional(&source.code) {
        Ok(Some((_, rest, _))) => rest,
        _ => source.code.as_str(),
    };
    let (code, _) = jump(code).ok()?;
    let code = code.trim();
    if assignment(code).is_some() {
        return None;
    }
    numbered_l(code).map(|(n, _)| n)
}

/// `XR1 WR2 …`: each letter with its parameter, no parameter bound twice.
fn bindings(text: &str) -> Result<Vec<Binding>, String> {
    let mut out: Vec<Binding> = Vec::new();
    for (letter, value) in words(text)? {
        let r = value
            .strip_prefix(['R', 'r'])
            .and_then(|d| d.parse::<u32>().ok())
            .ok_or_else(|| format!("{letter}{value}: a header binds a letter to a parameter (XR1), not to a value"))?;
        if let Some((other, _)) = out.iter().find(|(_, p)| *p == r) {
            return Err(format!("R{r} is bound to both {other} and {letter}"));
        }
        out.push((letter, r));
    }
    Ok(out)
}

/// A call's or a header's words: a letter (not R, which names parameters) and its value, a
/// number or a parameter with an optional sign (`X30`, `W-R1`, `A.5`), as (letter, value text).
fn words(text: &str) -> Result<Words, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out: Vec<(char, String)> = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let letter = chars[i].to_ascii_uppercase();
        if !letter.is_ascii_alphabetic() || letter == 'R' {
            let rest: String = chars[i..].iter().collect();
            return Err(format!("`{}` where a letter and its value belong (X30, WR2)", rest.trim()));
        }
        let mut j = i + 1;
        if matches!(chars.get(j), Some('+' | '-')) {
            j += 1;
        }
        let parameter = matches!(chars.get(j), Some('R' | 'r'));
        let start = j + usize::from(parameter);
        let digits = chars[start..].iter().take_while(|c| c.is_ascii_digit() || (!parameter && **c == '.')).count();
        if digits == 0 {
            return Err(format!("{letter} without its value (X30, XR1)"));
        }
        if out.iter().any(|(l, _)| *l == letter) {
            return Err(format!("{letter} is given twice"));
        }
        out.push((letter, chars[i + 1..start + digits].iter().collect()));
        i = start + digits;
    }
    Ok(out)
}

struct Run<'a> {
    subprograms: &'a Subprograms,
    parameters: HashMap<u32, f64>,
    out: Vec<(String, usize)>,
    jumps: usize,
    /// The blocks still to be run before the program is refused ([`MAX_BLOCKS_RUN`]).
    budget: usize,
}

impl Run<'_> {
    /// Runs one body to its end (M17 in a subprogram, M02 or the last block in the main).
    fn body(&mut self, body: &Body, number: Option<u32>, depth: usize) -> Result<(), ReadError> {
        let mut pc = 0;
        while let Some(source) = body.get(pc) {
            pc += 1;
            let at = |column: usize, m: String| error(source.line, column, m);
            self.budget = self.budget.checked_sub(1).ok_or_else(|| {
                at(
                    source.column,
                    format!(
                        "the program runs more than {MAX_BLOCKS_RUN} blocks beyond the ones written (each call and \
                         jump repeating its blocks): calls within calls or a loop that never ends in practice"
                    ),
                )
            })?;
            let (code, column) = match conditional(&source.code).map_err(|m| at(source.column, m))? {
                Some((condition, rest, offset)) => {
                    if !self.holds(condition).map_err(|m| at(source.column, m))? {
                        continue;
                    }
                    (rest, source.column + offset)
                }
                None => (source.code.as_str(), source.column),
            };
            let (code, goto) = jump(code).map_err(|m| at(column, m))?;
            if self.statement(source, code, column, number, depth)? {
                return Ok(());
            }
            if let Some(label) = goto {
                self.jumps += 1;
                if self.jumps > MAX_JUMPS {
                    return Err(at(column, format!("more than {MAX_JUMPS} jumps: a loop that never ends")));
                }
                pc = body.iter().position(|s| s.label == Some(label)).ok_or_else(|| {
                    let within = number.map_or("the main program".to_string(), |n| format!("subprogram L{n:02}"));
                    at(column, format!("GOTO N{label}: there is no block N{label} in {within}"))
                })?;
            }
        }
        match number {
            Some(n) => Err(error(body.last().map_or(0, |s| s.line), 1, format!("subprogram L{n:02} ends without M17"))),
            None => Ok(()),
        }
    }

    /// One block's code after its condition and jump; `true` when it ends the body.
    fn statement(
        &mut self,
        source: &Source,
        code: &str,
        column: usize,
        number: Option<u32>,
        depth: usize,
    ) -> Result<bool, ReadError> {
        let at = |m: String| error(source.line, column, m);
        let trimmed = code.trim();
        let column = column + (code.len() - code.trim_start().len());
        if trimmed.is_empty() {
            return Ok(false);
        }
        if let Some((n, expression)) = assignment(trimmed) {
            let value = self.value(expression).map_err(at)?;
            self.parameters.insert(n, value);
            return Ok(false);
        }
        if let Some((n, given)) = call(trimmed).map_err(at)? {
            if depth >= MAX_DEPTH {
                return Err(at(format!("L{n:02} called {MAX_DEPTH} deep: a subprogram that never returns")));
            }
            let sub = self
                .subprograms
                .get(&n)
                .ok_or_else(|| at(format!("L{n:02} is called but not written after the program's M02")))?;
            for (r, value) in self.arguments(n, sub, &given).map_err(at)? {
                self.parameters.insert(r, value);
            }
            self.body(&sub.body, Some(n), depth + 1)?;
            return Ok(false);
        }
        let ends = number.is_some() && has_word(trimmed, 'M', 17);
        if number.is_none() && has_word(trimmed, 'M', 17) {
            return Err(at("M17 ends a subprogram, not the main program".into()));
        }
        let words = self.substituted(trimmed).map_err(at)?;
        let words = if ends { without_m17(&words) } else { words };
        if !words.trim().is_empty() {
            // The code keeps its columns: padded to where it started in its line.
            let pad = " ".repeat(column - source.column);
            self.out.push((format!("{}{pad}{words}", source.prefix), source.line));
        }
        Ok(ends || (number.is_none() && has_word(trimmed, 'M', 2)))
    }

    /// The words of `code` with every parameter reference replaced by its value.
    fn substituted(&self, code: &str) -> Result<String, String> {
        let chars: Vec<char> = code.chars().collect();
        let mut out = String::with_capacity(code.len());
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            out.push(c);
            i += 1;
            if !c.is_ascii_alphabetic() {
                continue;
            }
            let mut j = i;
            let sign = match chars.get(j) {
                Some('-') => {
                    j += 1;
                    -1.0
                }
                Some('+') => {
                    j += 1;
                    1.0
                }
                _ => 1.0,
            };
            if !matches!(chars.get(j), Some('R' | 'r')) || !chars.get(j + 1).is_some_and(char::is_ascii_digit) {
                continue;
            }
            let digits: String = chars[j + 1..].iter().take_while(|c| c.is_ascii_digit()).collect();
            let n: u32 = digits.parse().map_err(|_| format!("R{digits} is not a parameter number"))?;
            let value = sign * self.parameter(n)?;
            let written = format!("{value:.WORD_DECIMALS$}");
            out.push_str(if written.trim_start_matches(['-', '0', '.']).is_empty() { "0" } else { &written });
            i = j + 1 + digits.len();
        }
        Ok(out)
    }

    /// The parameters a call of L`n` sets: one for every letter of its header, each given in
    /// the call; all are worked out before any is set, so `L13 DR2 XR1` may swap R1 and R2.
    fn arguments(&self, n: u32, sub: &Sub, given: &[(char, String)]) -> Result<Vec<(u32, f64)>, String> {
        let letters: Vec<String> = sub.parameters.iter().map(|(l, r)| format!("{l}R{r}")).collect();
        if let Some((letter, _)) = given.iter().find(|(l, _)| !sub.parameters.iter().any(|(p, _)| p == l)) {
            return Err(if letters.is_empty() {
                format!(
                    "L{n:02} takes no values in its call: its header names no letters (its values are set in \
                     R parameters before the call, R1=…)"
                )
            } else {
                format!("L{n:02} has no parameter {letter} (its header: L{n:02} {})", letters.join(" "))
            });
        }
        sub.parameters
            .iter()
            .map(|(letter, r)| {
                let (_, text) = given
                    .iter()
                    .find(|(l, _)| l == letter)
                    .ok_or_else(|| format!("the call of L{n:02} gives no {letter} (its header binds it to R{r})"))?;
                Ok((*r, self.value(text)?))
            })
            .collect()
    }

    fn parameter(&self, n: u32) -> Result<f64, String> {
        self.parameters.get(&n).copied().ok_or_else(|| format!("R{n} has no value here (no R{n}=… before it)"))
    }

    /// `a op b` with op one of `>= <= <> > < =`.
    fn holds(&self, condition: &str) -> Result<bool, String> {
        for op in [">=", "<=", "<>", ">", "<", "="] {
            if let Some((a, b)) = condition.split_once(op) {
                let (a, b) = (self.value(a)?, self.value(b)?);
                return Ok(match op {
                    ">=" => a >= b,
                    "<=" => a <= b,
                    "<>" => a != b,
                    ">" => a > b,
                    "<" => a < b,
                    _ => a == b,
                });
            }
        }
        Err(format!("`{}` is not a condition (R3>0, R1>=R2, …)", condition.trim()))
    }

    fn value(&self, expression: &str) -> Result<f64, String> {
        let tokens = lex(expression)?;
        let mut p = Parser { tokens: &tokens, at: 0, run: self };
        let v = p.sum()?;
        if p.at != tokens.len() {
            return Err(format!("`{}` is not an expression the NC31 reads", expression.trim()));
        }
        if !v.is_finite() {
            return Err(format!("`{}` is not a number (a division by 0?)", expression.trim()));
        }
        Ok(v)
    }
}

/// `IF cond THEN rest`: the condition, the rest, and where the rest starts in the code.
fn conditional(code: &str) -> Result<Option<(&str, &str, usize)>, String> {
    let upper = code.to_ascii_uppercase();
    if !(upper.starts_with("IF ") || upper.starts_with("IF(")) {
        return Ok(None);
    }
    let then = upper.find("THEN").ok_or("IF without THEN")?;
    let rest = then + 4;
    Ok(Some((&code[2..then], &code[rest..], rest)))
}

/// The code before a trailing `GOTO Nn`, and the label.
fn jump(code: &str) -> Result<(&str, Option<u32>), String> {
    let upper = code.to_ascii_uppercase();
    let Some(at) = upper.find("GOTO") else { return Ok((code, None)) };
    let target = upper[at + 4..].trim();
    let label = target
        .strip_prefix('N')
        .and_then(|d| d.parse::<u32>().ok())
        .ok_or_else(|| format!("GOTO takes a block label (GOTO N9), not `{target}`"))?;
    Ok((&code[..at], Some(label)))
}

/// `R3=R3-R4`: the parameter and the expression.
fn assignment(code: &str) -> Option<(u32, &str)> {
    let (name, expression) = code.split_once('=')?;
    let digits = name.trim().strip_prefix(['R', 'r'])?;
    Some((digits.parse().ok()?, expression))
}

/// A block that calls a subprogram: `L03` alone, or `L16 X30 WR2 …` with the values of its
/// header's letters.
fn call(code: &str) -> Result<Option<(u32, Words)>, String> {
    if !code.to_ascii_uppercase().starts_with('L') {
        return Ok(None);
    }
    let (n, rest) = numbered_l(code).ok_or_else(|| {
        format!("`{code}`: a subprogram is called by `Lnn`, with the values of its header's letters (L16 X30 W40)")
    })?;
    Ok(Some((n, words(rest).map_err(|m| format!("the call of L{n:02}: {m}"))?)))
}

/// `code` without its M17 word.
fn without_m17(code: &str) -> String {
    let upper = code.to_ascii_uppercase();
    let Some(at) = upper.find("M17") else { return code.to_string() };
    format!("{}{}", &code[..at], &code[at + 3..])
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    Parameter(u32),
    Op(char),
}

fn lex(text: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if "+-*/()".contains(c) {
            tokens.push(Token::Op(c));
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let end = i + chars[i..].iter().take_while(|c| c.is_ascii_digit() || **c == '.').count();
            let s: String = chars[i..end].iter().collect();
            tokens.push(Token::Number(s.parse().map_err(|_| format!("`{s}` is not a number"))?));
            i = end;
        } else if c == 'R' || c == 'r' {
            let end = i + 1 + chars[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
            let s: String = chars[i + 1..end].iter().collect();
            tokens.push(Token::Parameter(s.parse().map_err(|_| format!("`R{s}` is not a parameter (R0, R1, …)"))?));
            i = end;
        } else {
            return Err(format!("`{c}` has no place in an NC31 expression"));
        }
    }
    Ok(tokens)
}

/// Precedence climbing over `+ -` and `* /`, with unary signs and brackets.
struct Parser<'a> {
    tokens: &'a [Token],
    at: usize,
    run: &'a Run<'a>,
}

impl Parser<'_> {
    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        while let Some(Token::Op(op @ ('+' | '-'))) = self.tokens.get(self.at) {
            self.at += 1;
            let r = self.product()?;
            v = if *op == '+' { v + r } else { v - r };
        }
        Ok(v)
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.factor()?;
        while let Some(Token::Op(op @ ('*' | '/'))) = self.tokens.get(self.at) {
            self.at += 1;
            let r = self.factor()?;
            v = if *op == '*' { v * r } else { v / r };
        }
        Ok(v)
    }

    fn factor(&mut self) -> Result<f64, String> {
        let token = self.tokens.get(self.at).cloned().ok_or("an expression that ends too soon")?;
        self.at += 1;
        match token {
            Token::Number(v) => Ok(v),
            Token::Parameter(n) => self.run.parameter(n),
            Token::Op('-') => Ok(-self.factor()?),
            Token::Op('+') => self.factor(),
            Token::Op('(') => {
                let v = self.sum()?;
                if self.tokens.get(self.at) != Some(&Token::Op(')')) {
                    return Err("a bracket that is not closed".into());
                }
                self.at += 1;
                Ok(v)
            }
            Token::Op(c) => Err(format!("`{c}` where a number or a parameter belongs")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blocks(text: &str) -> Vec<String> {
        expand(text).unwrap().into_iter().map(|(b, _)| b.split_whitespace().collect::<Vec<_>>().join(" ")).collect()
    }

    #[test]
    fn a_flat_program_comes_back_block_for_block() {
        assert_eq!(blocks("N001 X34 Z-60 E\nN002 X20\nN003 M02\n"), ["N001 X34 Z-60 E", "N002 X20", "N003 M02"]);
    }

    #[test]
    fn parameters_loops_and_calls_run_as_the_control_runs_them() {
        let text = "N001 R1=10\nN002 R2=2*(R1+1)\nN003 L05\nN004 IF R1>7 THEN R1=R1-2 GOTO N3\nN005 M02\n\
                    N100 L05\nN101 X-R1 ZR2\nN102 W+R1 M17\n";
        let got = blocks(text);
        assert_eq!(
            got,
            [
                "N101 X-10.000 Z22.000",
                "N102 W10.000",
                "N101 X-8.000 Z22.000",
                "N102 W8.000",
                "N101 X-6.000 Z22.000",
                "N102 W6.000",
                "N005 M02"
            ]
        );
    }

    #[test]
    fn a_call_gives_the_headers_letters_their_values_all_at_once() {
        // The paper's call form (`L13 DR2 XR1 …`): D and X take R2's and R1's values as they
        // were at the call, though the header binds D to R1 and X to R2.
        let text = "N001 R1=5\nN002 R2=7\nN003 L13 DR2 XR1 A-0.5\nN004 L13 D1 X2 A+R1\nN005 M02\n\
                    N100 L13 DR1 XR2 AR3\nN101 XR1 ZR2\nN102 U-R3 M17\n";
        assert_eq!(
            blocks(text),
            ["N101 X7.000 Z5.000", "N102 U0.500", "N101 X1.000 Z2.000", "N102 U-7.000", "N005 M02"]
        );
    }

    #[test]
    fn what_the_control_cannot_run_is_refused_at_its_line() {
        let e = |t: &str| expand(t).unwrap_err();
        assert_eq!(e("N001 XR4\nN002 M02\n").line, 1);
        assert!(e("N001 XR4\nN002 M02\n").message.contains("R4 has no value"));
        assert!(e("N001 L07\nN002 M02\n").message.contains("L07 is called but not written"));
        assert!(e("N001 L07\nN002 M02\nN003 L07\nN004 L07\nN005 M17\n").message.contains("never returns"));
        assert!(e("N001 R1=1\nN002 GOTO N1\nN003 M02\n").message.contains("never ends"));
        assert!(e("N001 M02\nN002 X4\n").message.contains("after the program's end"));
        assert!(e("N001 M02\nN002 L03\nN003 X4\n").message.contains("no M17"));
        assert!(e("N001 GOTO N9\nN002 M02\n").message.contains("no block N9"));
        assert!(e("N001 L03 W-R1\nN002 M02\nN003 L03\nN004 M17\n").message.contains("takes no values"));
        assert!(e("N001 L03 W-R1\nN002 M02\nN003 L03 XR1\nN004 M17\n").message.contains("no parameter W"));
        assert!(e("N001 L03 W1\nN002 M02\nN003 L03 XR1 WR2\nN004 M17\n").message.contains("gives no X"));
        assert!(e("N001 M02\nN003 L03 X1\nN004 M17\n").message.contains("not to a value"));
        assert!(e("N001 M02\nN003 L03 XR1 WR1\nN004 M17\n").message.contains("R1 is bound to both X and W"));
        assert!(e("N001 L03 X1 X2\nN002 M02\n").message.contains("X is given twice"));
        assert!(e("N001 L03 X\nN002 M02\n").message.contains("without its value"));
    }

    #[test]
    fn calls_within_calls_stop_at_the_block_limit() {
        // Ten calls a level, seven levels: 10^7 blocks run from 87 lines, each call within
        // the depth limit and no jump taken.
        let mut text = String::from("N001 R1=0\nN002 L01\nN003 M02\n");
        for level in 1..=7 {
            text.push_str(&format!("L{level:02}\n"));
            let inner = if level < 7 { format!("L{:02}\n", level + 1) } else { "R1=R1+1\n".to_string() };
            text.push_str(&inner.repeat(10));
            text.push_str("M17\n");
        }
        let e = expand(&text).unwrap_err();
        assert!(e.message.contains("more than 1000000 blocks"), "{}", e.message);
        // A program of that many blocks written out is read whole: only repeats count.
        let long = "N001 W-0.001\n".repeat(MAX_BLOCKS_RUN + 10) + "N002 M02\n";
        assert_eq!(expand(&long).unwrap().len(), MAX_BLOCKS_RUN + 11);
    }
}
