//! LinuxCNC's O-codes, run as the control runs them (LinuxCNC's "O Codes" chapter): subroutines
//! of the program's own file (`o100 sub` … `o100 endsub`, `o100 call [1] [2]`, `return`),
//! conditions (`if`, `elseif`, `else`, `endif`), loops (`while` … `endwhile`, `do` … `while`,
//! `repeat [n]` … `endrepeat`, `break`, `continue`). [`Flow`] gives the reader the lines the
//! control executes, in order, each with its own line number; conditions and arguments are
//! read with the parameters as they stand when the control reaches them. A subroutine's
//! #1–#30 and named parameters are its own; `#<_…>` are global.

use std::collections::HashMap;

use super::parameters::{self, Parameters};
use super::{o_word_keyword_named, quoted_briefly, ReadError};

/// The deepest a subroutine may call another (LinuxCNC stops at a few dozen levels).
pub const MAX_CALL_DEPTH: usize = 50;

/// One O-code line: its label (`100`, `<name>` in lower case), keyword and where the rest of
/// the line (its values) starts.
#[derive(Clone)]
struct OCode {
    label: String,
    keyword: &'static str,
    rest: usize,
}

struct Call {
    back_to: usize,
    hidden: parameters::Hidden,
}

struct Repeat {
    label: String,
    left: u64,
}

/// The lines a LinuxCNC program executes, in order.
pub struct Flow<'t> {
    lines: Vec<&'t str>,
    codes: Vec<Option<OCode>>,
    /// Where each O-code line's block goes on, found once before anything runs.
    jumps: Vec<Jumps>,
    subs: HashMap<String, usize>,
    next: usize,
    calls: Vec<Call>,
    repeats: Vec<Repeat>,
    budget: usize,
}

fn error(line: usize, column: usize, message: String) -> ReadError {
    ReadError { line: line + 1, column, message }
}

impl<'t> Flow<'t> {
    /// Reads the O-codes of `text` and where each subroutine starts.
    pub fn new(text: &'t str) -> Result<Flow<'t>, ReadError> {
        let lines: Vec<&str> = text.lines().collect();
        let mut codes = Vec::with_capacity(lines.len());
        let mut subs = HashMap::new();
        for (i, line) in lines.iter().enumerate() {
            let code = o_code(line).map_err(|(c, m)| error(i, c, m))?;
            if let Some(c) = &code {
                if c.keyword == "sub" && subs.insert(c.label.clone(), i).is_some() {
                    return Err(error(i, 1, format!("o{} sub is defined twice", c.label)));
                }
            }
            codes.push(code);
        }
        let jumps = structure(&codes)?;
        let budget = lines.len().saturating_add(super::nc31::MAX_BLOCKS_RUN);
        Ok(Flow { lines, codes, jumps, subs, next: 0, calls: Vec::new(), repeats: Vec::new(), budget })
    }

    /// The next line the control executes and its 0-based number, running the O-codes before
    /// it with `params`; `None` at the end of the text.
    pub fn next_line(&mut self, params: &mut Parameters) -> Result<Option<(&'t str, usize)>, ReadError> {
        while self.next < self.lines.len() {
            let at = self.next;
            self.next += 1;
            self.charge(at)?;
            params.control.line = at + 1;
            params.control.call_level = self.calls.len();
            match self.codes[at].clone() {
                None => return Ok(Some((self.lines[at], at))),
                Some(code) => self.run(at, &code, params)?,
            }
        }
        Ok(None)
    }

    fn charge(&mut self, at: usize) -> Result<(), ReadError> {
        if self.budget == 0 {
            return Err(error(
                at,
                1,
                format!(
                    "the program runs more than {} lines beyond the ones written (each loop and call repeating its \
                     lines): a loop that never ends in practice",
                    super::nc31::MAX_BLOCKS_RUN
                ),
            ));
        }
        self.budget -= 1;
        Ok(())
    }

    fn run(&mut self, at: usize, code: &OCode, params: &mut Parameters) -> Result<(), ReadError> {
        let jumps = self.jumps[at];
        match code.keyword {
            // A definition met in the flow, or a branch's end reached from a branch taken.
            "sub" | "elseif" | "else" => self.next = jumps.end + 1,
            "endsub" | "return" => self.leave(at, code, params)?,
            "call" => self.call(at, code, params)?,
            "if" => self.branch(at, code, params)?,
            "endif" | "do" => {}
            "while" if jumps.do_tail => {
                if self.value(at, code, params)? != 0.0 {
                    self.next = jumps.head + 1;
                }
            }
            "while" => {
                if self.value(at, code, params)? == 0.0 {
                    self.next = jumps.end + 1;
                }
            }
            "endwhile" => self.next = jumps.head,
            "repeat" => self.start_repeat(at, code, params)?,
            "endrepeat" => self.end_repeat(at, code)?,
            _ => self.leave_or_restart_loop(at, code)?,
        }
        Ok(())
    }

    /// The value in brackets after an O-code's keyword.
    fn value(&self, at: usize, code: &OCode, params: &Parameters) -> Result<f64, ReadError> {
        let chars: Vec<char> = self.lines[at].chars().collect();
        let (v, end) = parameters::real_value(&chars, code.rest, params).map_err(|(c, m)| error(at, c, m))?;
        expect_end(&chars, end).map_err(|(c, m)| error(at, c, m))?;
        Ok(v)
    }

    /// An `if` and its `elseif`s: the first branch whose condition holds runs, or the `else`.
    fn branch(&mut self, at: usize, code: &OCode, params: &Parameters) -> Result<(), ReadError> {
        let mut test = at;
        let mut test_code = code.clone();
        loop {
            if self.value(test, &test_code, params)? != 0.0 {
                self.next = test + 1;
                return Ok(());
            }
            let other = self.jumps[test].next_branch;
            let other_code = self.codes[other].clone().expect("an O-code");
            if other_code.keyword != "elseif" {
                self.next = other + 1;
                return Ok(());
            }
            self.charge(other)?;
            test = other;
            test_code = other_code;
        }
    }

    fn start_repeat(&mut self, at: usize, code: &OCode, params: &Parameters) -> Result<(), ReadError> {
        let n = self.value(at, code, params)?;
        if n < 1.0 {
            self.next = self.jumps[at].end + 1;
            return Ok(());
        }
        self.repeats.push(Repeat { label: code.label.clone(), left: n as u64 - 1 });
        Ok(())
    }

    fn end_repeat(&mut self, at: usize, code: &OCode) -> Result<(), ReadError> {
        // A loop left by a jump (a break of an outer loop, a return) leaves its count behind.
        let Some(own) = self.repeats.iter().rposition(|r| r.label == code.label) else {
            return Err(error(at, 1, format!("o{} endrepeat is reached outside its repeat", code.label)));
        };
        self.repeats.truncate(own + 1);
        let r = self.repeats.last_mut().expect("the loop's count");
        if r.left > 0 {
            r.left -= 1;
            self.next = self.jumps[at].head + 1;
        } else {
            self.repeats.pop();
        }
        Ok(())
    }

    /// `break` or `continue` of the loop of their label around them: LinuxCNC 2.9 runs them in
    /// while loops, and `break` in do loops.
    fn leave_or_restart_loop(&mut self, at: usize, code: &OCode) -> Result<(), ReadError> {
        let head = self.jumps[at].head;
        let refused = |why: &str| Err(error(at, 1, format!("o{} {} {why}", code.label, code.keyword)));
        if head == NONE {
            return refused(&format!("is outside a loop o{}", code.label));
        }
        match (self.codes[head].as_ref().map(|c| c.keyword), code.keyword) {
            (Some("repeat"), _) => {
                refused("inside a repeat loop: LinuxCNC breaks and continues only while and do loops")
            }
            (Some("do"), "continue") => refused(
                "in a do … while loop: LinuxCNC 2.9 leaves the loop there instead of testing its condition again; \
                 write the loop as while … endwhile",
            ),
            (_, "continue") => {
                self.next = head;
                Ok(())
            }
            _ => {
                self.next = self.jumps[head].end + 1;
                Ok(())
            }
        }
    }

    fn call(&mut self, at: usize, code: &OCode, params: &mut Parameters) -> Result<(), ReadError> {
        let Some(&start) = self.subs.get(&code.label) else {
            return Err(error(
                at,
                1,
                format!(
                    "o{} call: the subroutine is not in this program (LinuxCNC would look for it in its \
                     SUBROUTINE_PATH); ncsheet reads one file",
                    code.label
                ),
            ));
        };
        if self.calls.len() >= MAX_CALL_DEPTH {
            return Err(error(at, 1, format!("subroutines call one another more than {MAX_CALL_DEPTH} deep")));
        }
        let args = self.arguments(at, code, params)?;
        let hidden = params.enter_call(&args);
        self.calls.push(Call { back_to: self.next, hidden });
        self.next = start + 1;
        Ok(())
    }

    /// A call's values: up to 30 bracketed expressions.
    fn arguments(&self, at: usize, code: &OCode, params: &Parameters) -> Result<Vec<f64>, ReadError> {
        let chars: Vec<char> = self.lines[at].chars().collect();
        let mut i = code.rest;
        let mut args = Vec::new();
        loop {
            while chars.get(i).is_some_and(|c| c.is_whitespace()) {
                i += 1;
            }
            if chars.get(i) != Some(&'[') {
                break;
            }
            if args.len() == 30 {
                return Err(error(at, i + 1, "a call passes at most 30 values (#1–#30)".into()));
            }
            let (v, end) = parameters::real_value(&chars, i, params).map_err(|(c, m)| error(at, c, m))?;
            args.push(v);
            i = end;
        }
        expect_end(&chars, i).map_err(|(c, m)| error(at, c, m))?;
        Ok(args)
    }

    fn leave(&mut self, at: usize, code: &OCode, params: &mut Parameters) -> Result<(), ReadError> {
        let chars: Vec<char> = self.lines[at].chars().collect();
        let given = chars[code.rest..].iter().find(|c| !c.is_whitespace()) == Some(&'[');
        let returned = if given { Some(self.value(at, code, params)?) } else { None };
        let Some(call) = self.calls.pop() else {
            return Err(error(at, 1, format!("o{} {} is reached without a call", code.label, code.keyword)));
        };
        params.leave_call(call.hidden, returned);
        self.next = call.back_to;
        Ok(())
    }
}

/// No line: a jump an O-code does not have.
const NONE: usize = usize::MAX;

/// Where an O-code line's block goes on: its closing line (`end`: a `sub`'s `endsub`, a
/// branch's `endif`, a loop's last line), its opening line (`head`: a loop's first line for
/// its end, `break` and `continue`), an `if`/`elseif`'s next branch, and whether a `while`
/// closes a `do`.
#[derive(Clone, Copy)]
struct Jumps {
    end: usize,
    head: usize,
    next_branch: usize,
    do_tail: bool,
}

/// An open block of one label while the lines are followed: its keyword, first line and
/// (for an `if`) its branches so far.
struct Open {
    keyword: &'static str,
    line: usize,
    branches: Vec<usize>,
}

/// The block an O-code closes (`endif` an `if`, `endwhile` a `while`).
fn opener_of(keyword: &str) -> Option<&'static str> {
    Some(match keyword {
        "endif" => "if",
        "endsub" => "sub",
        "endwhile" => "while",
        "endrepeat" => "repeat",
        _ => return None,
    })
}

/// Follows each label's blocks as they open and close, once, and gives every O-code line its
/// [`Jumps`], so that running the program never searches the text; a block left open or
/// closed twice is refused at its line before anything runs.
fn structure(codes: &[Option<OCode>]) -> Result<Vec<Jumps>, ReadError> {
    let mut open: HashMap<&str, Vec<Open>> = HashMap::new();
    let mut jumps = vec![Jumps { end: NONE, head: NONE, next_branch: NONE, do_tail: false }; codes.len()];
    for (i, code) in codes.iter().enumerate() {
        let Some(c) = code else { continue };
        let stack = open.entry(c.label.as_str()).or_default();
        let top = stack.last().map(|o| o.keyword);
        match c.keyword {
            "while" if top == Some("do") => {
                let head = stack.pop().expect("the do").line;
                jumps[i].do_tail = true;
                jumps[i].head = head;
                jumps[head].end = i;
            }
            "if" | "sub" | "do" | "repeat" | "while" => {
                stack.push(Open { keyword: c.keyword, line: i, branches: vec![i] })
            }
            "elseif" | "else" => {
                let Some(o) = stack.last_mut().filter(|o| o.keyword == "if") else {
                    return Err(error(i, 1, format!("o{} {} has no o{} if before it", c.label, c.keyword, c.label)));
                };
                jumps[*o.branches.last().expect("the if")].next_branch = i;
                o.branches.push(i);
            }
            "break" | "continue" => {
                let around = stack.iter().rev().find(|o| matches!(o.keyword, "while" | "do" | "repeat"));
                jumps[i].head = around.map_or(NONE, |o| o.line);
            }
            k => {
                let Some(opener) = opener_of(k) else { continue };
                if top != Some(opener) {
                    return Err(error(i, 1, format!("o{} {k} has no o{} {opener} before it", c.label, c.label)));
                }
                let o = stack.pop().expect("the opener");
                jumps[i].head = o.line;
                jumps[*o.branches.last().expect("the opener")].next_branch = i;
                for b in o.branches {
                    jumps[b].end = i;
                }
            }
        }
    }
    let left_open = open.iter().flat_map(|(label, stack)| stack.iter().map(move |o| (o.line, *label, o.keyword))).min();
    if let Some((i, label, keyword)) = left_open {
        let closer = match keyword {
            "do" => "while",
            "if" => "endif",
            _ => &format!("end{keyword}"),
        };
        return Err(error(i, 1, format!("o{label} {keyword} has no o{label} {closer} after it")));
    }
    Ok(jumps)
}

/// Nothing but a comment may follow an O-code's values.
fn expect_end(chars: &[char], from: usize) -> Result<(), (usize, String)> {
    let rest: String = chars[from..].iter().collect();
    let trimmed = rest.trim_start();
    if trimmed.is_empty() || trimmed.starts_with('(') || trimmed.starts_with(';') {
        return Ok(());
    }
    let column = from + rest.len() - trimmed.len() + 1;
    Err((column, format!("`{}` after an O-code's values", quoted_briefly(trimmed))))
}

/// The O-code a line is, if it starts with one (after an optional block delete `/` and
/// `N` number): `o100 if [#1 GT 0]`, `O<pocket> call [2]`.
fn o_code(line: &str) -> Result<Option<OCode>, (usize, String)> {
    let chars: Vec<char> = line.chars().collect();
    let mut i = chars.iter().take_while(|c| c.is_whitespace()).count();
    if !matches!(chars.get(i), Some('o' | 'O')) {
        return Ok(None);
    }
    let start = i;
    i += 1;
    let label = if chars.get(i) == Some(&'<') {
        let close = chars[i..]
            .iter()
            .position(|&c| c == '>')
            .ok_or((start + 1, "an O-code name not closed by `>`".to_string()))?;
        let name: String =
            chars[i + 1..i + close].iter().filter(|c| !c.is_whitespace()).collect::<String>().to_ascii_lowercase();
        i += close + 1;
        format!("<{name}>")
    } else {
        let digits: String = chars[i..].iter().take_while(|c| c.is_ascii_digit()).collect();
        i += digits.len();
        match digits.parse::<u64>() {
            Ok(n) => n.to_string(),
            Err(_) => return Ok(None),
        }
    };
    i += chars[i..].iter().take_while(|c| c.is_whitespace()).count();
    let word: String = chars[i..].iter().take_while(|c| c.is_ascii_alphabetic()).collect();
    let Some(keyword) = o_word_keyword_named(&word) else {
        return Ok(None);
    };
    Ok(Some(OCode { label, keyword, rest: i + word.len() }))
}
