//! Heidenhain plain-language labels, subprograms and program section repeats, as the TNC
//! manuals describe them ("Subprograms and Program Section Repeats"; TNC 370 User's Manual
//! §6, whose program layout is the one every TNC since keeps); the reader runs them, so every
//! tool sees the blocks the control executes:
//!
//! - `LBL 1` (or `LBL "name"`) marks a place; `LBL 0` ends a subprogram;
//! - `CALL LBL 1` runs the subprogram from `LBL 1` to the next `LBL 0` and goes on after the
//!   call; subprograms are written after the main program's last block (the one with M2 or
//!   M30) and before `END PGM`;
//! - `CALL LBL 1 REP 2` (the control shows `REP 2/2`) runs the section from `LBL 1` to the
//!   call again, 2 more times: the section runs once more than the repeats programmed;
//! - subprograms nest up to 8 levels (TNC 370 §6.4 "Maximum nesting depth for subprograms:
//!   8"); section repeats in section repeats each keep their own count.
//!
//! [`run_order`] gives the lines in the order the control runs them, the label and call
//! blocks left out.

use std::collections::HashMap;

use super::nc31::MAX_BLOCKS_RUN;
use super::ReadError;

/// Subprogram calls nested deeper than this are refused (TNC 370 §6.4).
const MAX_NESTING: usize = 8;

/// What a line does to the order the blocks run in.
#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Other,
    Blank,
    /// `LBL n` / `LBL "name"`; `LBL 0` is [`Kind::SubprogramEnd`].
    Label(String),
    SubprogramEnd,
    /// `CALL LBL n`, with the repeats of `REP m`, and the column of its label.
    Call {
        label: String,
        repeats: Option<u32>,
        column: usize,
    },
    /// The main program's last block (M2 or M30 among its words).
    ProgramEnd,
    /// `END PGM`.
    EndPgm,
}

fn error(line: usize, column: usize, message: impl Into<String>) -> ReadError {
    ReadError { line, column, message: message.into() }
}

/// The 0-based indices of `text`'s lines in the order the control runs them.
pub(super) fn run_order(text: &str) -> Result<Vec<usize>, ReadError> {
    let kinds = text.lines().enumerate().map(|(i, l)| kind(l, i + 1)).collect::<Result<Vec<_>, _>>()?;
    if !kinds.iter().any(|k| matches!(k, Kind::Label(_) | Kind::SubprogramEnd | Kind::Call { .. })) {
        return Ok((0..kinds.len()).collect());
    }
    dead_text_after_the_end(&kinds)?;
    let mut labels = HashMap::new();
    for (i, k) in kinds.iter().enumerate() {
        if let Kind::Label(name) = k {
            if labels.insert(name.clone(), i).is_some() {
                return Err(error(i + 1, 1, format!("LBL {name} is written twice")));
            }
        }
    }
    Run { kinds: &kinds, labels: &labels, order: Vec::new(), steps_left: kinds.len().saturating_add(MAX_BLOCKS_RUN) }
        .run()
}

/// Between the main program's end (M2/M30) and `END PGM` only subprograms are written
/// (`LBL n` … `LBL 0`): a block outside them would never run.
fn dead_text_after_the_end(kinds: &[Kind]) -> Result<(), ReadError> {
    let Some(end) = kinds.iter().position(|k| *k == Kind::ProgramEnd) else { return Ok(()) };
    let mut inside = false;
    for (i, k) in kinds.iter().enumerate().skip(end + 1) {
        match k {
            Kind::EndPgm => break,
            Kind::Label(_) => inside = true,
            Kind::SubprogramEnd => inside = false,
            Kind::Blank => {}
            _ if inside => {}
            _ => {
                return Err(error(
                    i + 1,
                    1,
                    "blocks after the program's end (M2/M30) that are not in a subprogram (LBL n … LBL 0)",
                ))
            }
        }
    }
    Ok(())
}

/// What a line is, from its words after the block number.
fn kind(raw: &str, line: usize) -> Result<Kind, ReadError> {
    let code = raw.split(';').next().unwrap_or("");
    let words: Vec<(usize, &str)> =
        code.match_indices(|c: char| !c.is_whitespace()).fold(Vec::new(), |mut v, (i, _)| {
            if i == 0 || code[..i].ends_with(char::is_whitespace) {
                let w = code[i..].split_whitespace().next().unwrap_or("");
                v.push((i + 1, w));
            }
            v
        });
    let skip = usize::from(words.first().is_some_and(|(_, w)| w.bytes().all(|b| b.is_ascii_digit())));
    let words = &words[skip..];
    let Some(&(column, head)) = words.first() else { return Ok(Kind::Blank) };
    let upper = |w: &str| w.to_ascii_uppercase();
    match upper(head).as_str() {
        "LBL" => {
            let (_, name) = words.get(1).ok_or_else(|| error(line, column, "LBL without its number or name"))?;
            let name = label_name(name, line, column)?;
            if let Some(&(c, _)) = words.get(2) {
                return Err(error(line, c, "a label takes a block of its own"));
            }
            Ok(if name == "0" { Kind::SubprogramEnd } else { Kind::Label(name) })
        }
        "CALL" if words.get(1).is_some_and(|(_, w)| upper(w) == "LBL") => call(words, line),
        "END" if words.get(1).is_some_and(|(_, w)| upper(w) == "PGM") => Ok(Kind::EndPgm),
        _ if words.iter().any(|(_, w)| matches!(upper(w).as_str(), "M2" | "M02" | "M30")) => Ok(Kind::ProgramEnd),
        _ => Ok(Kind::Other),
    }
}

/// A label's number (`1`, `001` is 1) or quoted name (`"CONTOUR"`).
fn label_name(word: &str, line: usize, column: usize) -> Result<String, ReadError> {
    if word.bytes().all(|b| b.is_ascii_digit()) {
        let n: u32 = word.parse().map_err(|_| error(line, column, format!("LBL {word}: no label number")))?;
        return Ok(n.to_string());
    }
    match word.strip_prefix('"').and_then(|w| w.strip_suffix('"')) {
        Some(name) if !name.is_empty() => Ok(format!("\"{name}\"")),
        _ => Err(error(line, column, format!("LBL {word}: a label is a number or a name in quotes"))),
    }
}

/// `CALL LBL n`, `CALL LBL n REP m` (`REP m/m` as the control shows it, `REPm`).
fn call(words: &[(usize, &str)], line: usize) -> Result<Kind, ReadError> {
    let (column, name) = *words.get(2).ok_or_else(|| error(line, words[1].0, "CALL LBL without its label"))?;
    let label = label_name(name, line, column)?;
    if label == "0" {
        return Err(error(line, column, "CALL LBL 0: label 0 only ends a subprogram"));
    }
    let repeats = match words.get(3) {
        None => None,
        Some(&(c, w)) => {
            let upper = w.to_ascii_uppercase();
            let Some(rest) = upper.strip_prefix("REP") else {
                return Err(error(line, c, format!("`{w}` after CALL LBL {name} is not read (REP and its count are)")));
            };
            let count = if rest.is_empty() { words.get(4).map_or("", |(_, w)| *w) } else { rest };
            let first = count.split('/').next().unwrap_or("");
            match first.parse::<u32>() {
                Ok(n) if n >= 1 => Some(n),
                _ => return Err(error(line, c, format!("REP {count}: a section repeats 1 or more times"))),
            }
        }
    };
    Ok(Kind::Call { label, repeats, column })
}

/// The program being run, and the budget it spends.
struct Run<'a> {
    kinds: &'a [Kind],
    labels: &'a HashMap<String, usize>,
    order: Vec<usize>,
    steps_left: usize,
}

impl Run<'_> {
    fn run(mut self) -> Result<Vec<usize>, ReadError> {
        let mut at = 0;
        let mut returns: Vec<usize> = Vec::new();
        // The repeats left of each `CALL LBL … REP` being run, by its line.
        let mut left: HashMap<usize, u32> = HashMap::new();
        while let Some(k) = self.kinds.get(at) {
            self.spend(at)?;
            at = match k {
                Kind::Other | Kind::Blank => self.emit(at),
                Kind::Label(_) => at + 1,
                Kind::SubprogramEnd => returns.pop().unwrap_or(at + 1),
                Kind::ProgramEnd if !returns.is_empty() => {
                    return Err(error(at + 1, 1, "the program's end (M2/M30) inside a subprogram"));
                }
                Kind::ProgramEnd => {
                    self.emit(at);
                    self.kinds.iter().position(|k| *k == Kind::EndPgm).unwrap_or(self.kinds.len())
                }
                Kind::EndPgm => {
                    self.order.extend(at..self.kinds.len());
                    break;
                }
                Kind::Call { label, repeats: None, column } => {
                    if returns.len() == MAX_NESTING {
                        return Err(error(
                            at + 1,
                            *column,
                            format!("subprogram calls nest more than {MAX_NESTING} levels (CALL LBL {label})"),
                        ));
                    }
                    returns.push(at + 1);
                    self.target(label, at, *column)? + 1
                }
                Kind::Call { label, repeats: Some(n), column } => {
                    let start = self.target(label, at, *column)?;
                    if start > at {
                        return Err(error(
                            at + 1,
                            *column,
                            format!(
                                "CALL LBL {label} REP repeats the section before it: LBL {label} comes after the call"
                            ),
                        ));
                    }
                    let count = left.entry(at).or_insert(*n);
                    if *count == 0 {
                        left.remove(&at);
                        at + 1
                    } else {
                        *count -= 1;
                        start + 1
                    }
                }
            };
        }
        Ok(self.order)
    }

    fn emit(&mut self, at: usize) -> usize {
        self.order.push(at);
        at + 1
    }

    /// The line of `LBL label`.
    fn target(&self, label: &str, at: usize, column: usize) -> Result<usize, ReadError> {
        self.labels
            .get(label)
            .copied()
            .ok_or_else(|| error(at + 1, column, format!("CALL LBL {label}: the program has no LBL {label}")))
    }

    /// Counts one line run against the budget.
    fn spend(&mut self, at: usize) -> Result<(), ReadError> {
        if self.steps_left == 0 {
            return Err(error(
                at + 1,
                1,
                format!(
                    "the program runs more than {MAX_BLOCKS_RUN} blocks beyond the ones written (each subprogram call \
                     and section repeat running its blocks again): calls within calls or a loop that never ends in practice"
                ),
            ));
        }
        self.steps_left -= 1;
        Ok(())
    }
}
