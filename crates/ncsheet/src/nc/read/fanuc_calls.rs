//! Fanuc subprograms, as the FANUC Series 0i-MC manual (B-64124EN/01, §12.3 "Subprogram
//! (M98, M99)") describes them; the reader runs the calls, so every tool sees the blocks the
//! control executes:
//!
//! - a subprogram is an `O` program of its own (`O1002 ;` … `M99 ;`), written in the same
//!   file after the main program; `M99` may share a block with a move (`X100. Y100. M99 ;`);
//! - `M98 P1002` calls it once, `M98 P1002 L5` five times, and the packed form `M98 P51002`
//!   five times too ("Call the subprogram (number 1002) five times in succession": the last
//!   four digits of P are the program, the digits before them the count); "a single call
//!   command can repeatedly call a subprogram up to 999 times";
//! - calls nest up to four levels (the main program calling a subprogram is one level);
//! - `M99 P30` returns to the block `N30` of the calling program instead of the block after
//!   the call;
//! - a call to a program the file does not hold is the control's alarm 078, here an error
//!   naming the line and column of its P;
//! - an `O` program with M99 that no call runs is kept as the control keeps it ("such a program
//!   can be stored as a subprogram in memory", §12.3): nothing of it runs, and the reader notes
//!   it ([`Unrolled::notes`]); an `O` program that ends with M30 or M2 is a main program of its
//!   own, which the control runs only when an operator selects it, so it is refused.
//!
//! What the manual leaves to a control's parameters or macro programs is refused by name:
//! `M98 … Q` (a start sequence number), `M99` in the main program (it runs the program again
//! from its start, without end) and `M99 P` ending a call that repeats.

use std::borrow::Cow;
use std::collections::HashMap;

use super::nc31::MAX_BLOCKS_RUN;
use super::ReadError;

/// Calls nested deeper than this are refused (B-64124EN/01 §12.3: "subprogram calls can be
/// nested up to four levels").
const MAX_NESTING: usize = 4;
/// The most times one call repeats its subprogram (§12.3: "up to 999 times").
const MAX_REPEATS: u32 = 999;
/// Text the unrolled program may hold beyond the text written: the reader copies each
/// block it runs, so a long block repeated a million times is bounded by its bytes as well
/// as by the block count.
const MAX_TEXT_RUN: usize = 64 << 20;

/// A program's blocks as the control runs them: each block of the file once, and the order
/// the calls run them in (indices, so that a block repeated a million times is stored once).
pub(crate) struct Unrolled {
    blocks: Vec<Text>,
    order: Vec<usize>,
    /// The subprograms the file holds that no call runs: their numbers and `O` lines.
    stored: Vec<(u32, usize)>,
}

/// One block's text to run, its 1-based line, and the characters before it on that line.
struct Text {
    text: String,
    line: usize,
    offset: usize,
}

impl Unrolled {
    /// The blocks in the order they run, each with its 1-based source line and the
    /// characters before it on that line.
    pub(crate) fn blocks(&self) -> impl Iterator<Item = (Cow<'_, str>, usize, usize)> + '_ {
        self.order.iter().map(|&i| {
            let b = &self.blocks[i];
            (Cow::Borrowed(b.text.as_str()), b.line, b.offset)
        })
    }

    /// What the reader says of the subprograms no call runs: a control keeps them in its memory
    /// as a library, and runs nothing of them until a call (here none) or an operator selects one.
    pub(crate) fn notes(&self) -> Vec<String> {
        self.stored
            .iter()
            .map(|(number, line)| format!("line {line}: O{number:04} stored, not called by the main program"))
            .collect()
    }
}

/// One word of a block: its letter, its number as written, and its columns (0-based, end
/// exclusive) in the block's line.
#[derive(Clone, Debug)]
struct Word {
    letter: char,
    number: String,
    start: usize,
    end: usize,
}

impl Word {
    fn is(&self, letter: char, n: u32) -> bool {
        self.letter == letter && self.value() == Some(n as f64)
    }

    fn value(&self) -> Option<f64> {
        self.number.parse::<f64>().ok().filter(|v| v.is_finite())
    }
}

/// What a block does to the flow of the program.
#[derive(Clone, Debug)]
enum Flow {
    Plain,
    /// `M98`: the program called, how many times, the column of its P.
    Call {
        program: u32,
        repeats: u32,
        column: usize,
    },
    /// `M99`, with the sequence number of its P.
    Return {
        to: Option<u32>,
        column: usize,
    },
}

/// One block of the file: where it is (its line, the characters before it on the line), what
/// it does, and the index of its text to run (`None` when nothing is left once
/// the call's words are taken out).
struct Block {
    line: usize,
    offset: usize,
    flow: Flow,
    text: Option<usize>,
}

/// An `O` program of the file: its number (the main program may have none), its blocks, and
/// where each sequence number `N` first stands among them (an `M99 P` goes on there).
struct Program {
    number: Option<u32>,
    line: usize,
    blocks: Vec<Block>,
    labels: HashMap<u32, usize>,
    /// The program end (M2 or M30) it holds, if any: a main program of its own.
    ends: Option<u32>,
}

/// The file's programs, and which of them each number names.
struct Programs {
    all: Vec<Program>,
    numbered: HashMap<u32, usize>,
}

fn error(line: usize, column: usize, message: impl Into<String>) -> ReadError {
    ReadError { line, column, message: message.into() }
}

/// Unrolls `text`, a Fanuc program and the subprograms written after it, into the blocks
/// the control runs.
pub(crate) fn unroll(text: &str) -> Result<Unrolled, ReadError> {
    let mut texts = Vec::new();
    let programs = split(text, &mut texts)?;
    let written_bytes: usize = texts.iter().map(|t: &Text| t.text.len()).sum();
    let written_blocks = programs.all.iter().map(|p| p.blocks.len()).sum::<usize>();
    let mut run = Run {
        programs: &programs,
        texts: &texts,
        order: Vec::new(),
        called: vec![false; programs.all.len()],
        steps_left: written_blocks.saturating_add(MAX_BLOCKS_RUN),
        bytes_left: written_bytes.saturating_add(MAX_TEXT_RUN),
    };
    run.main()?;
    let stored = programs
        .all
        .iter()
        .zip(&run.called)
        .skip(1)
        .filter(|(_, &called)| !called)
        .map(|(p, _)| (p.number.unwrap_or(0), p.line))
        .collect();
    let order = run.order;
    Ok(Unrolled { blocks: texts, order, stored })
}

/// The file's blocks, grouped into its `O` programs: the first is the main program (its `O`
/// line, if any, kept as a block the reader reads); every later `O` line starts a subprogram.
/// Each line is split into its blocks once, here; the reader reads the blocks this keeps.
fn split(text: &str, texts: &mut Vec<Text>) -> Result<Programs, ReadError> {
    let main = Program { number: None, line: 1, blocks: Vec::new(), labels: HashMap::new(), ends: None };
    let mut programs = Programs { all: vec![main], numbered: HashMap::new() };
    let mut tape = Tape::Unopened;
    for (i, line_text) in text.lines().enumerate() {
        let line = i + 1;
        if line_text.trim_start().starts_with('%') {
            tape = tape.mark(line);
            continue;
        }
        for (offset, raw) in super::fanuc_blocks(line_text) {
            if raw.trim().is_empty() {
                continue;
            }
            if let Tape::Ended(end) = tape {
                return Err(error(
                    line,
                    offset + 1,
                    format!(
                        "text after the `%` that ends the program at line {end} (the end of tape: a control stops \
                         reading there); a program after it needs a file of its own"
                    ),
                ));
            }
            tape = Tape::Open;
            let raw = program_number_colon(raw);
            split_block(&raw, Place { line, offset }, &mut programs, texts).map_err(|e| shifted(e, offset))?;
        }
    }
    for p in &programs.all[1..] {
        if !p.blocks.iter().any(|b| matches!(b.flow, Flow::Return { .. })) {
            let number = p.number.unwrap_or(0);
            return Err(error(
                p.line,
                1,
                match p.ends {
                    Some(m) => second_main(number, &format!("ends with M{m:02}, not M99")),
                    None => format!("subprogram O{number:04} has no M99 to return"),
                },
            ));
        }
    }
    Ok(programs)
}

/// Where the file stands between the tape marks `%`: the first `%` line is the leader, skipped
/// to the end of its line (a title may follow it, `% TITLE`); the next ends the program (the
/// FANUC 16i operator's manual, B-63524EN/01 §8, memory card files: "A file starts with % or
/// LF … A file always ends with %. In a read operation, data between the first % and the next
/// LF is skipped"; the Data Server's format, B-64014EN/03 §2.5: `% TITLE ;` `O0001(COMMENT) ;`
/// … `M30 ;` `%`).
#[derive(Clone, Copy)]
enum Tape {
    Unopened,
    Open,
    Ended(usize),
}

impl Tape {
    /// After a `%` line at `line`.
    fn mark(self, line: usize) -> Tape {
        match self {
            Tape::Unopened => Tape::Open,
            Tape::Open => Tape::Ended(line),
            ended => ended,
        }
    }
}

/// A block that starts with `:1234`, the program number as ISO code writes it (`:` for the
/// address O: on the older Fanuc controls the colon is the program number's address in ISO
/// code, `O` in EIA; every Fanuc control reads both), read as `O1234` in the same column.
fn program_number_colon(raw: &str) -> Cow<'_, str> {
    let start = raw.len() - raw.trim_start().len();
    match raw[start..].strip_prefix(':') {
        Some(rest) => Cow::Owned(format!("{}O{rest}", &raw[..start])),
        None => Cow::Borrowed(raw),
    }
}

/// Why the `O` program `number` is not read: `what` it is, then what a control does with it.
fn second_main(number: u32, what: &str) -> String {
    format!(
        "O{number:04} {what}: a program of its own, which a control runs only when it is selected; ncsheet reads \
         the file's first program and keeps the others as its subprograms, so O{number:04} needs a file of its own"
    )
}

/// Where a block stands: its 1-based line and the characters before it on that line.
#[derive(Clone, Copy)]
struct Place {
    line: usize,
    offset: usize,
}

/// An error found in a block, its column counted from the block's start, at the line's column.
fn shifted(mut e: ReadError, offset: usize) -> ReadError {
    e.column += offset;
    e
}

/// Files one block: a subprogram's `O` line starts a program; any other block goes to the
/// program being written, its text (without M98/M99 and their words) kept to be run.
fn split_block(raw: &str, at: Place, programs: &mut Programs, texts: &mut Vec<Text>) -> Result<(), ReadError> {
    let line = at.line;
    let words = words(raw);
    if let Some(o) = words.first().filter(|w| w.letter == 'O') {
        let main_started = !programs.all[0].blocks.is_empty() || programs.all.len() > 1;
        if main_started {
            if let Some(refusal) = linuxcnc_o_code(raw, o, line) {
                return Err(refusal);
            }
            let program = header(o, &words, line, &programs.numbered)?;
            programs.numbered.insert(program.number.expect("a subprogram's number"), programs.all.len());
            programs.all.push(program);
            return Ok(());
        }
    }
    let flow = flow(&words, line)?;
    let rest = match flow {
        Flow::Plain => Some(raw.to_string()),
        _ => without_flow_words(raw, &words),
    };
    let text = rest.map(|text| {
        texts.push(Text { text, line, offset: at.offset });
        texts.len() - 1
    });
    let label = words.first().filter(|w| w.letter == 'N').and_then(|w| w.number.parse().ok());
    let program = programs.all.last_mut().expect("the main program");
    if let Some(m) = words.iter().find(|w| w.is('M', 2) || w.is('M', 30)) {
        program.ends = program.ends.or(m.value().map(|v| v as u32));
    }
    if let Some(n) = label {
        program.labels.entry(n).or_insert(program.blocks.len());
    }
    program.blocks.push(Block { line, offset: at.offset, flow, text });
    Ok(())
}

/// A LinuxCNC O-code (`o100 sub`, `O101 while [...]`) in a program read as iso is named as
/// the block reader names it, not taken for a program number with words after it.
fn linuxcnc_o_code(raw: &str, o: &Word, line: usize) -> Option<ReadError> {
    let chars: Vec<char> = raw.chars().collect();
    let from = o.start + 1 + chars[o.start + 1..].iter().take_while(|&&c| c == ' ').count();
    let (keyword, end) = super::o_word_keyword(&chars, from)?;
    Some(error(line, o.start + 1, super::o_word_refused(&chars[o.start..end], keyword)))
}

/// A subprogram's `O` line: its number, alone in its block.
fn header(o: &Word, words: &[Word], line: usize, numbered: &HashMap<u32, usize>) -> Result<Program, ReadError> {
    let number = o.value().filter(|v| (1.0..=9999.0).contains(v) && v.fract() == 0.0);
    let Some(number) = number.map(|v| v as u32) else {
        return Err(error(line, o.start + 1, format!("O{} is not a program number O0001–O9999", o.number)));
    };
    if let Some(w) = words.get(1) {
        return Err(error(line, w.start + 1, format!("a program number O{number:04} takes a block of its own")));
    }
    if numbered.contains_key(&number) {
        return Err(error(line, o.start + 1, format!("program O{number:04} is written twice in this file")));
    }
    Ok(Program { number: Some(number), line, blocks: Vec::new(), labels: HashMap::new(), ends: None })
}

/// What a block's M98 or M99 asks, with its words checked.
fn flow(words: &[Word], line: usize) -> Result<Flow, ReadError> {
    let at = |w: &Word, m: String| error(line, w.start + 1, m);
    let call = words.iter().find(|w| w.is('M', 98));
    let ret = words.iter().find(|w| w.is('M', 99));
    let p = words.iter().find(|w| w.letter == 'P');
    match (call, ret) {
        (Some(_), Some(m)) => Err(at(m, "M98 and M99 in one block".into())),
        (Some(m), None) => {
            if let Some(q) = words.iter().find(|w| w.letter == 'Q') {
                return Err(at(q, "M98 … Q (start at a sequence number of the subprogram) is not read".into()));
            }
            let Some(p) = p else { return Err(at(m, "M98 without P, the program it calls".into())) };
            let l = words.iter().find(|w| w.letter == 'L');
            call_of(p, l).map_err(|message| at(p, message))
        }
        (None, Some(m)) => match p {
            None => Ok(Flow::Return { to: None, column: m.start + 1 }),
            Some(p) => match p.value().filter(|v| v.fract() == 0.0 && (0.0..=99999.0).contains(v)) {
                Some(v) => Ok(Flow::Return { to: Some(v as u32), column: m.start + 1 }),
                None => Err(at(p, format!("M99 P{}: P is not a sequence number N0–N99999", p.number))),
            },
        },
        (None, None) => Ok(Flow::Plain),
    }
}

/// `M98 P1002 L5` or the packed `M98 P51002`: the program and how many times.
fn call_of(p: &Word, l: Option<&Word>) -> Result<Flow, String> {
    let whole = |w: &Word| w.value().filter(|v| v.fract() == 0.0 && *v >= 0.0);
    let Some(pv) = whole(p) else { return Err(format!("M98 P{}: P is not a program number", p.number)) };
    if pv > 9_999_999.0 {
        return Err(format!("M98 P{}: more than 3 digits of count before the 4-digit program number", p.number));
    }
    let (program, packed) = ((pv as u32) % 10_000, (pv as u32) / 10_000);
    let repeats = match l {
        None => packed.max(1),
        Some(_) if packed > 0 => return Err(format!("M98 P{}: a count in P and an L as well", p.number)),
        Some(l) => match whole(l).filter(|v| (1.0..=MAX_REPEATS as f64).contains(v)) {
            Some(v) => v as u32,
            None => return Err(format!("M98 … L{}: a call repeats 1 to {MAX_REPEATS} times", l.number)),
        },
    };
    if program == 0 {
        return Err(format!("M98 P{}: O0000 is not a program number", p.number));
    }
    Ok(Flow::Call { program, repeats, column: p.start + 1 })
}

/// The block with its M98/M99 and their P, L words blanked (columns kept); `None` when
/// nothing but an N number is left.
fn without_flow_words(raw: &str, words: &[Word]) -> Option<String> {
    let mut chars: Vec<char> = raw.chars().collect();
    let flow_word = |w: &Word| w.is('M', 98) || w.is('M', 99) || matches!(w.letter, 'P' | 'L');
    for w in words.iter().filter(|w| flow_word(w)) {
        chars[w.start..w.end].iter_mut().for_each(|c| *c = ' ');
    }
    let left: Vec<Word> = words.iter().filter(|w| !flow_word(w) && w.letter != 'N').cloned().collect();
    (!left.is_empty() || has_comment(raw)).then(|| chars.into_iter().collect())
}

fn has_comment(raw: &str) -> bool {
    raw.contains('(')
}

/// The address words of a block, outside `( … )` comments: a letter, spaces, then a signed
/// number. Anything else is left for the reader, which names it.
fn words(raw: &str) -> Vec<Word> {
    let chars: Vec<char> = raw.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '(' {
            i += chars[i..].iter().position(|&c| c == ')').unwrap_or(chars.len() - i) + 1;
            continue;
        }
        if !c.is_ascii_alphabetic() {
            i += 1;
            continue;
        }
        let start = i;
        i += 1;
        while chars.get(i) == Some(&' ') {
            i += 1;
        }
        let from = i;
        while i < chars.len() && (chars[i].is_ascii_digit() || "+-.".contains(chars[i])) {
            i += 1;
        }
        let number = chars[from..i].iter().collect();
        out.push(Word { letter: c.to_ascii_uppercase(), number, start, end: i });
    }
    out
}

/// The calls being run, and the budgets they spend.
struct Run<'a> {
    programs: &'a Programs,
    texts: &'a [Text],
    order: Vec<usize>,
    /// Which programs a call has run.
    called: Vec<bool>,
    steps_left: usize,
    bytes_left: usize,
}

impl Run<'_> {
    fn main(&mut self) -> Result<(), ReadError> {
        self.program(0, 0).map(|_| ())
    }

    /// Runs program `index` at nesting `depth` (0 the main program) from its first block;
    /// returns the sequence number an `M99 P` names, if any.
    fn program(&mut self, index: usize, depth: usize) -> Result<Option<u32>, ReadError> {
        self.called[index] = true;
        let this = &self.programs.all[index];
        let blocks = &this.blocks;
        let mut at = 0;
        while let Some(block) = blocks.get(at) {
            self.spend(block)?;
            if let Some(t) = block.text {
                self.order.push(t);
            }
            at += 1;
            match block.flow {
                Flow::Plain => {}
                Flow::Return { to, column } => {
                    if depth == 0 {
                        return Err(error(
                            block.line,
                            block.offset + column,
                            "M99 in the main program runs it again from its start, without end: end it with M30",
                        ));
                    }
                    return Ok(to);
                }
                Flow::Call { program, repeats, column } => {
                    if let Some(to) = self.call(block, program, repeats, column, depth)? {
                        at = self.sequence(this, to, block)?;
                    }
                }
            }
        }
        Ok(None)
    }

    /// Runs one M98 block's calls; the sequence number to go on at, when the subprogram's
    /// M99 names one.
    fn call(
        &mut self,
        block: &Block,
        number: u32,
        repeats: u32,
        column: usize,
        depth: usize,
    ) -> Result<Option<u32>, ReadError> {
        let column = block.offset + column;
        let Some(&index) = self.programs.numbered.get(&number) else {
            return Err(error(
                block.line,
                column,
                format!("M98 calls O{number:04}, which this file does not hold (alarm 078)"),
            ));
        };
        if depth + 1 > MAX_NESTING {
            return Err(error(
                block.line,
                column,
                format!("subprogram calls nest more than {MAX_NESTING} levels (M98 calling O{number:04})"),
            ));
        }
        for _ in 0..repeats {
            if let Some(to) = self.program(index, depth + 1)? {
                if repeats > 1 {
                    return Err(error(
                        block.line,
                        column,
                        format!("O{number:04} returns with M99 P{to} from a call that repeats it {repeats} times: write the call once"),
                    ));
                }
                return Ok(Some(to));
            }
        }
        Ok(None)
    }

    /// The index of the block `N to` of the calling program, where an `M99 P` goes on.
    fn sequence(&self, program: &Program, to: u32, call: &Block) -> Result<usize, ReadError> {
        program.labels.get(&to).copied().ok_or_else(|| {
            error(call.line, call.offset + 1, format!("the subprogram this block calls returns to N{to} with M99 P{to}, and this program has no block N{to}"))
        })
    }

    /// Counts one block run against the budgets.
    fn spend(&mut self, block: &Block) -> Result<(), ReadError> {
        let bytes = block.text.map_or(0, |t| self.texts[t].text.len());
        if self.steps_left == 0 || self.bytes_left < bytes {
            return Err(error(
                block.line,
                block.offset + 1,
                format!(
                    "the program runs more than {MAX_BLOCKS_RUN} blocks or {} MiB of text beyond the ones written (each \
                     subprogram call and repeat running its blocks again): calls within calls or a loop that never ends \
                     in practice",
                    MAX_TEXT_RUN >> 20
                ),
            ));
        }
        self.steps_left -= 1;
        self.bytes_left -= bytes;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{read_with_lines, Family};
    use super::*;
    use crate::nc::program::Machine;

    const BLOCKS: usize = 2000;

    fn block(i: usize) -> String {
        format!("G01 X{}. Y{}. F500. ", i % 100, (i * 7) % 50)
    }

    #[test]
    fn a_line_of_many_blocks_is_split_once_into_slices_of_it() {
        // 2,000 blocks on one line (the EOB `;` ends each). The text kept to run is the line's
        // own text once: each block was a copy of the whole line with the other blocks blanked
        // (2,000 times the line, about 90 MB here).
        let line: String = (0..BLOCKS).map(|i| block(i) + ";").collect();
        let text = format!("G21 G90 G94 ;\n{line}\nM30 ;\n");
        let unrolled = unroll(&text).unwrap();
        let held: usize = unrolled.blocks.iter().map(|t| t.text.len()).sum();
        assert!(held <= text.len(), "{held} bytes held for a text of {}", text.len());
        // The same blocks written one a line are the same program, each at its own line.
        let flat: String = (0..BLOCKS).map(|i| block(i) + ";\n").collect();
        let flat = format!("G21 G90 G94 ;\n{flat}M30 ;\n");
        let (joined, joined_lines) = read_with_lines(&text, Family::Fanuc, Some(Machine::Mill)).unwrap();
        let (one_a_line, flat_lines) = read_with_lines(&flat, Family::Fanuc, Some(Machine::Mill)).unwrap();
        assert_eq!(joined, one_a_line);
        assert_eq!(joined_lines.len(), flat_lines.len());
        assert!(joined_lines.iter().all(|&l| l <= 3), "{joined_lines:?}");
    }
}
