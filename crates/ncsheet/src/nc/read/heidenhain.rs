//! Reading Heidenhain plain language (Klartext) back into the program model: `BEGIN PGM`,
//! `BLK FORM 0.1/0.2`, `TOOL CALL n Z S…`, `L` (absolute or `IX…` incremental axes, `R0`/`RL`/
//! `RR`, `F`, `FU`, `FMAX`, M functions), arcs `CC` + `C … DR±`, `CR … R± DR±` (radius; R < 0
//! the arc over 180°), `CT` (tangent to the element before), the dwell cycle 9, `; comments`,
//! `STOP`, `END PGM`. Milling only, as the writer. What the reader does not know is an error
//! naming its line and column.

use super::{centre_from_radius, ReadError};
use crate::nc::program::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange,
};

/// Digits after the point the plain-language writer uses unless a program asks for more.
const DEFAULT_DECIMALS: usize = 4;

type Fail = (usize, String);

/// One whitespace-separated token and its 1-based column.
#[derive(Clone, Debug)]
struct Token {
    text: String,
    column: usize,
}

/// Where a TOOL CALL's speed goes when M3/M4 starts the spindle: the model's spindle block
/// belongs with the tool call, so that the program is written back as it was read.
#[derive(Clone, Copy)]
struct PendingSpeed {
    /// Index in the model's blocks (and lines) of the tool call's spindle block.
    at: usize,
    line: usize,
    /// The speed changed while the spindle turned: the block exists, M3/M4 only sets its
    /// direction.
    exists: bool,
}

#[derive(Default)]
struct State {
    program: Option<Program>,
    lines: Vec<usize>,
    inches: bool,
    ended: bool,
    /// The program's end function (M2/M30) was given: only END PGM may follow.
    stopped: bool,
    position: [Option<f64>; 6],
    /// The circle centre CC (the pole) in force.
    centre: Option<(f64, f64)>,
    /// The direction the contour leaves the last element in, in XY (for CT).
    tangent: Option<(f64, f64)>,
    feed_mode: Option<FeedMode>,
    speed: Option<f64>,
    running: Option<SpindleDirection>,
    pending_speed: Option<PendingSpeed>,
    /// CYCL DEF 9.0 was read: 9.1 gives the dwell time.
    dwell_cycle: bool,
    blank_low: Option<[f64; 3]>,
    decimals: usize,
}

/// Reads a plain-language program, with the 1-based source line of each block of the model.
pub fn read(text: &str, machine: Option<Machine>) -> Result<(Program, Vec<usize>), ReadError> {
    if machine == Some(Machine::Lathe) {
        return Err(ReadError { line: 1, column: 1, message: "plain language here is for milling programs".into() });
    }
    let mut st = State { decimals: DEFAULT_DECIMALS, ..State::default() };
    let mut last = 0;
    // Labels, subprogram calls and section repeats run as the control runs them.
    let all: Vec<&str> = text.lines().collect();
    for i in super::heidenhain_labels::run_order(text)? {
        let (raw, line) = (all[i], i + 1);
        if raw.trim().is_empty() {
            continue;
        }
        last = line;
        let at = |(column, message): Fail| ReadError { line, column, message };
        if st.ended {
            return Err(at((1, "text after END PGM".into())));
        }
        st.line(raw, line).map_err(at)?;
    }
    if !st.ended {
        return Err(ReadError { line: last.max(1), column: 1, message: "the program has no END PGM".into() });
    }
    let mut program = st.program.expect("BEGIN PGM came first");
    program.precision = (st.decimals > DEFAULT_DECIMALS).then_some(st.decimals);
    writers_refusals(text, &program, &st.lines)?;
    Ok((program, st.lines))
}

/// A hand-written program is refused where the writer would refuse a block of it
/// (`dialect::check_values`: numbers past the control's digits, feeds not above 0, spindle
/// speeds, tool numbers, dwells out of range), at the block's line and the word that carries
/// the value, as the word-address readers do.
fn writers_refusals(text: &str, program: &Program, lines: &[usize]) -> Result<(), ReadError> {
    let format = crate::nc::dialect::plain_language_limits(program.precision);
    for (block, &line) in program.blocks.iter().zip(lines) {
        if let Err(message) = crate::nc::dialect::check_values(block, program.machine, format) {
            let raw = text.lines().nth(line - 1).unwrap_or_default();
            let feed_refused = match block {
                Block::Line { feed: Some(f), .. } | Block::Arc { feed: Some(f), .. } => format.feed(*f).is_err(),
                _ => false,
            };
            return Err(ReadError { line, column: word_column(raw, block, feed_refused), message });
        }
    }
    Ok(())
}

/// Where on its line stands the word a refusal of `block` is about: S of a speed, the tool
/// number of TOOL CALL, F of a refused feed, else the block's first word after its number.
fn word_column(raw: &str, block: &Block, feed_refused: bool) -> usize {
    let (tokens, _) = tokens(raw);
    let starting = |p: char| tokens.iter().find(|t| t.text.starts_with(p)).map(|t| t.column);
    let word = match block {
        Block::Spindle(_) => starting('S'),
        Block::Tool(_) => {
            tokens.iter().position(|t| t.text == "CALL").and_then(|i| tokens.get(i + 1)).map(|t| t.column)
        }
        Block::Dwell(_) => tokens.last().map(|t| t.column),
        Block::Line { .. } | Block::Arc { .. } if feed_refused => starting('F'),
        _ => None,
    };
    let head = tokens.iter().find(|t| !t.text.bytes().all(|b| b.is_ascii_digit())).map(|t| t.column);
    word.or(head).unwrap_or(1)
}

/// Splits a line into tokens and its `;` comment.
fn tokens(raw: &str) -> (Vec<Token>, Option<String>) {
    let (code, comment) = match raw.find(';') {
        Some(i) => (&raw[..i], Some(raw[i + 1..].trim().to_string())),
        None => (raw, None),
    };
    let mut out = Vec::new();
    let mut column = 0;
    for part in code.split(' ') {
        let chars = part.chars().count();
        if !part.trim().is_empty() {
            out.push(Token { text: part.trim().to_string(), column: column + 1 });
        }
        column += chars + 1;
    }
    (out, comment)
}

/// A number as written (`+10.0000`, `-2.5`, `3000`), with its digits after the point.
fn number(text: &str, column: usize, what: &str) -> Result<(f64, usize), Fail> {
    let value = text.parse::<f64>().ok().filter(|v| v.is_finite());
    let value = value.ok_or_else(|| (column, super::no_value(what, text)))?;
    Ok((value, text.split_once('.').map_or(0, |(_, f)| f.len())))
}

/// What a positioning block's words say.
#[derive(Default)]
struct Words {
    /// Per axis X Y Z A B C: the value and whether it is incremental (`IX`).
    axes: [Option<(f64, bool)>; 6],
    compensation: Option<Compensation>,
    feed: Option<(f64, FeedMode)>,
    rapid: bool,
    /// M functions in the order written, with their columns.
    m: Vec<(u32, usize)>,
    direction: Option<ArcDirection>,
    radius: Option<(f64, usize)>,
}

impl State {
    fn program(&mut self, column: usize) -> Result<&mut Program, Fail> {
        self.program.as_mut().ok_or((column, "the program starts with BEGIN PGM".to_string()))
    }

    fn push(&mut self, block: Block, line: usize) {
        if let Some(p) = self.program.as_mut() {
            p.blocks.push(block);
            self.lines.push(line);
        }
    }

    fn line(&mut self, raw: &str, line: usize) -> Result<(), Fail> {
        let (tokens, comment) = tokens(raw);
        // Block numbers lead every block; they are labels, written again from 0.
        let mut rest: &[Token] = &tokens;
        if rest.first().is_some_and(|t| t.text.bytes().all(|b| b.is_ascii_digit())) {
            rest = &rest[1..];
        }
        let Some(head) = rest.first() else {
            if let Some(c) = comment {
                self.program(1)?;
                self.push(Block::Comment(c), line);
            }
            return Ok(());
        };
        let words: Vec<&str> = rest.iter().map(|t| t.text.as_str()).collect();
        if self.program.is_none() && words[0] != "BEGIN" {
            return Err((head.column, "the program starts with BEGIN PGM".into()));
        }
        if self.stopped && words[0] != "END" {
            return Err((head.column, "blocks after the program's end (M2/M30)".into()));
        }
        match words[0] {
            "BEGIN" => self.begin(rest)?,
            "END" => self.end(rest)?,
            "BLK" => self.blank(rest)?,
            "TOOL" => self.tool_call(rest, line)?,
            "CYCL" => self.cycle(rest, line)?,
            "STOP" => self.stop(rest, line)?,
            "L" => self.straight(&rest[1..], line)?,
            "CC" => self.pole(&rest[1..])?,
            "C" | "CR" | "CT" => self.arc(words[0], &rest[1..], head.column, line)?,
            other => return Err((head.column, format!("`{other}` is not a plain-language block this reader knows"))),
        }
        if let Some(c) = comment.filter(|c| !c.is_empty()) {
            self.push(Block::Comment(c), line);
        }
        Ok(())
    }

    fn begin(&mut self, t: &[Token]) -> Result<(), Fail> {
        if self.program.is_some() {
            return Err((t[0].column, "a second BEGIN PGM".into()));
        }
        let (name, unit) = pgm_line(t)?;
        self.inches = unit;
        self.program = Some(Program::new(name, Machine::Mill));
        Ok(())
    }

    fn end(&mut self, t: &[Token]) -> Result<(), Fail> {
        let (name, _) = pgm_line(t)?;
        let program = self.program(t[0].column)?;
        if !program.name.eq_ignore_ascii_case(name) {
            return Err((t[2].column, format!("END PGM {name} ends a program begun as {}", program.name)));
        }
        self.ended = true;
        Ok(())
    }

    fn scale(&self) -> f64 {
        if self.inches {
            25.4
        } else {
            1.0
        }
    }

    /// `BLK FORM 0.1 Z X… Y… Z…` (the lowest corner, tool axis Z) and `BLK FORM 0.2 X… Y… Z…`.
    fn blank(&mut self, t: &[Token]) -> Result<(), Fail> {
        let col = |i: usize| t.get(i).map_or(t[0].column, |t| t.column);
        if t.get(1).map(|t| t.text.as_str()) != Some("FORM") {
            return Err((col(1), "BLK is read as BLK FORM".into()));
        }
        let (first, corner) = match t.get(2).map(|t| t.text.as_str()) {
            Some("0.1") if t.get(3).map(|t| t.text.as_str()) == Some("Z") => (4, 1),
            Some("0.1") => return Err((col(3), "a blank with its tool axis other than Z is not read".into())),
            Some("0.2") => (3, 2),
            _ => return Err((col(2), "BLK FORM is read as 0.1 (lowest corner) and 0.2 (highest)".into())),
        };
        let mut xyz = [None; 3];
        for tok in &t[first..] {
            let i = "XYZ"
                .find(tok.text.chars().next().unwrap_or(' '))
                .ok_or((tok.column, format!("`{}` is not a corner coordinate X, Y or Z", tok.text)))?;
            let (v, _) = number(&tok.text[1..], tok.column, &tok.text[..1])?;
            xyz[i] = Some(v * self.scale());
        }
        let [Some(x), Some(y), Some(z)] = xyz else {
            return Err((t[0].column, "a blank's corner needs X, Y and Z".into()));
        };
        if corner == 1 {
            self.blank_low = Some([x, y, z]);
        } else {
            let low = self.blank_low.ok_or((t[0].column, "BLK FORM 0.2 before BLK FORM 0.1".to_string()))?;
            self.program(t[0].column)?.blank = Some((low, [x, y, z]));
        }
        Ok(())
    }

    /// `TOOL CALL [n] Z [S…]`: the tool, and the speed that M3/M4 starts.
    fn tool_call(&mut self, t: &[Token], line: usize) -> Result<(), Fail> {
        if t.get(1).map(|t| t.text.as_str()) != Some("CALL") {
            return Err((t.get(1).map_or(t[0].column, |t| t.column), "TOOL is read as TOOL CALL".into()));
        }
        let mut i = 2;
        if let Some(n) = t.get(i).filter(|t| t.text.bytes().all(|b| b.is_ascii_digit())) {
            let number = n.text.parse::<u32>().map_err(|_| (n.column, format!("tool {} is too large", n.text)))?;
            self.push(Block::Tool(ToolChange::new(number)), line);
            i += 1;
        }
        match t.get(i) {
            Some(axis) if axis.text == "Z" => i += 1,
            Some(axis) => return Err((axis.column, "a tool axis other than Z is not in the program model".into())),
            None => return Err((t[0].column, "TOOL CALL without its tool axis Z".into())),
        }
        for tok in &t[i..] {
            let Some(s) = tok.text.strip_prefix('S') else {
                return Err((tok.column, format!("`{}` in a TOOL CALL is not read (S only)", tok.text)));
            };
            let (rpm, _) = number(s, tok.column, "S")?;
            self.speed = Some(rpm);
            let at = self.lines.len();
            let exists = match self.running {
                // A new speed while the spindle turns: it changes now.
                Some(direction) => {
                    self.push(Block::Spindle(Spindle::Rpm { rpm, direction }), line);
                    true
                }
                None => false,
            };
            self.pending_speed = Some(PendingSpeed { at, line, exists });
        }
        Ok(())
    }

    /// The dwell: `CYCL DEF 9.0 DWELL TIME` then `CYCL DEF 9.1 DWELL 0.5`.
    fn cycle(&mut self, t: &[Token], line: usize) -> Result<(), Fail> {
        let text: Vec<&str> = t.iter().map(|t| t.text.as_str()).collect();
        match text.as_slice() {
            ["CYCL", "DEF", "9.0", "DWELL", "TIME"] => self.dwell_cycle = true,
            ["CYCL", "DEF", "9.1", "DWELL", seconds] if self.dwell_cycle => {
                let (s, _) = number(seconds, t[4].column, "DWELL")?;
                self.dwell_cycle = false;
                self.push(Block::Dwell(s), line);
            }
            ["CYCL", "DEF", "9.1", ..] => return Err((t[0].column, "CYCL DEF 9.1 without 9.0 before it".into())),
            _ => return Err((t[0].column, "of the cycles only the dwell (CYCL DEF 9) is read".into())),
        }
        Ok(())
    }

    /// `STOP M5 M9`: the M functions left at the program's end.
    fn stop(&mut self, t: &[Token], line: usize) -> Result<(), Fail> {
        if t.len() == 1 {
            return Err((t[0].column, "a program stop (STOP) is not in the program model".into()));
        }
        let mut w = Words::default();
        for tok in &t[1..] {
            let Some(m) = tok.text.strip_prefix('M') else {
                return Err((tok.column, format!("`{}` after STOP is not read (M functions only)", tok.text)));
            };
            w.m.push((m_code(m, tok.column)?, tok.column));
        }
        self.m_functions(&w, line)
    }

    fn words(&self, t: &[Token]) -> Result<Words, Fail> {
        let mut w = Words::default();
        let mut i = 0;
        while i < t.len() {
            let tok = &t[i];
            let s = tok.text.as_str();
            let col = tok.column;
            let first = s.chars().next().unwrap_or(' ');
            let axis = |c: char| "XYZABC".find(c);
            match s {
                "R0" => w.compensation = Some(Compensation::Off),
                "RL" => w.compensation = Some(Compensation::Left),
                "RR" => w.compensation = Some(Compensation::Right),
                "FMAX" => w.rapid = true,
                "F" if t.get(i + 1).map(|t| t.text.as_str()) == Some("MAX") => {
                    w.rapid = true;
                    i += 1;
                }
                "DR+" => w.direction = Some(ArcDirection::CounterClockwise),
                "DR-" => w.direction = Some(ArcDirection::Clockwise),
                _ if s.starts_with("FU") => w.feed = Some((number(&s[2..], col, "FU")?.0, FeedMode::PerRevolution)),
                _ if first == 'F' => w.feed = Some((number(&s[1..], col, "F")?.0 * self.scale(), FeedMode::PerMinute)),
                _ if first == 'M' => w.m.push((m_code(&s[1..], col)?, col)),
                _ if first == 'R' && s[1..].starts_with(['+', '-']) => {
                    w.radius = Some((number(&s[1..], col, "R")?.0 * self.scale(), col));
                }
                _ if axis(first).is_some()
                    || (first == 'I' && s.len() > 1 && axis(s[1..].chars().next().unwrap_or(' ')).is_some()) =>
                {
                    let incremental = first == 'I';
                    let letter = if incremental { &s[1..2] } else { &s[..1] };
                    let k = axis(letter.chars().next().unwrap_or(' ')).expect("an axis letter");
                    let (v, _) = number(&s[letter.len() + usize::from(incremental)..], col, letter)?;
                    if w.axes[k].is_some() {
                        return Err((col, format!("{letter} is given twice in one block")));
                    }
                    let v = if k < 3 { v * self.scale() } else { v };
                    w.axes[k] = Some((v, incremental));
                }
                _ => return Err((col, format!("`{s}` is not a word this reader knows"))),
            }
            i += 1;
        }
        Ok(w)
    }

    /// The digits after the point of the axes of a block (a machine finer than 0.1 µm).
    fn note_decimals(&mut self, t: &[Token]) {
        for tok in t {
            let s = tok.text.trim_start_matches('I');
            if s.starts_with(|c: char| "XYZABC".contains(c)) {
                if let Some((_, f)) = s.split_once('.') {
                    self.decimals = self.decimals.max(f.len());
                }
            }
        }
    }

    /// The absolute end point of a move: axes given (incremental ones from the position).
    fn target(&mut self, w: &Words, t: &[Token]) -> Result<Target, Fail> {
        let mut v = [None; 6];
        for (k, given) in w.axes.iter().enumerate() {
            let Some((value, incremental)) = *given else { continue };
            let abs = if incremental {
                let col = t.first().map_or(1, |t| t.column);
                value + self.position[k].ok_or((col, "an incremental axis from an unknown position".to_string()))?
            } else {
                value
            };
            v[k] = Some(abs);
        }
        Ok(Target { x: v[0], y: v[1], z: v[2], a: v[3], b: v[4], c: v[5] })
    }

    /// Spindle and coolant blocks of the M functions, in the order written.
    fn m_functions(&mut self, w: &Words, line: usize) -> Result<(), Fail> {
        for &(m, col) in &w.m {
            match m {
                3 | 4 => {
                    let direction =
                        if m == 3 { SpindleDirection::Clockwise } else { SpindleDirection::CounterClockwise };
                    let rpm =
                        self.speed.ok_or((col, "the spindle starts with no speed (TOOL CALL … S)".to_string()))?;
                    let spindle = Block::Spindle(Spindle::Rpm { rpm, direction });
                    match self.pending_speed.take() {
                        Some(p) if p.exists => self.program(col)?.blocks[p.at] = spindle,
                        Some(p) => {
                            self.program(col)?.blocks.insert(p.at, spindle);
                            self.lines.insert(p.at, p.line);
                        }
                        None => self.push(spindle, line),
                    }
                    self.running = Some(direction);
                }
                5 => {
                    self.running = None;
                    self.push(Block::Spindle(Spindle::Stop), line);
                }
                8 | 9 => self.push(Block::Coolant(m == 8), line),
                2 | 30 => self.stopped = true,
                _ => return Err((col, format!("M{m} is not a code this reader knows"))),
            }
        }
        Ok(())
    }

    /// The feed mode block when F or FU changes it, and the feed.
    fn feed(&mut self, w: &Words, line: usize) -> Option<f64> {
        let (f, mode) = w.feed?;
        if self.feed_mode != Some(mode) {
            self.feed_mode = Some(mode);
            self.push(Block::FeedMode(mode), line);
        }
        Some(f)
    }

    /// Where the tool is after `to`, and the contour's direction there for CT.
    fn moved(&mut self, to: &Target, tangent: Option<(f64, f64)>) {
        for (k, v) in [to.x, to.y, to.z, to.a, to.b, to.c].into_iter().enumerate() {
            if v.is_some() {
                self.position[k] = v;
            }
        }
        self.tangent = tangent;
        self.pending_speed = None;
    }

    /// `L X… Y… Z… [R0|RL|RR] [F…|FU…|FMAX] [M…]`.
    fn straight(&mut self, t: &[Token], line: usize) -> Result<(), Fail> {
        let w = self.words(t)?;
        if let Some((_, col)) = w.radius {
            return Err((col, "a radius R± belongs to CR, not to L".into()));
        }
        if w.direction.is_some() {
            return Err((t[0].column, "a direction DR± belongs to an arc, not to L".into()));
        }
        if w.rapid && w.feed.is_some() {
            return Err((t[0].column, "FMAX and a feed in one block".into()));
        }
        self.note_decimals(t);
        let from = (self.position[0], self.position[1]);
        let to = self.target(&w, t)?;
        self.m_functions(&w, line)?;
        if let Some(c) = w.compensation {
            self.push(Block::Compensation(c), line);
        }
        let feed = self.feed(&w, line);
        let no_axes = to == Target::default();
        if no_axes && (w.rapid || feed.is_none()) {
            // `L R0 M5`-like blocks move nothing; the M functions and compensation are read.
            return Ok(());
        }
        let tangent = match (from, (to.x.or(from.0), to.y.or(from.1))) {
            ((Some(x0), Some(y0)), (Some(x1), Some(y1))) if (x1 - x0).hypot(y1 - y0) > 0.0 => Some((x1 - x0, y1 - y0)),
            _ => None,
        };
        let block = if w.rapid { Block::Rapid(to) } else { Block::Line { to, feed } };
        self.push(block, line);
        self.moved(&to, tangent);
        Ok(())
    }

    /// `CC X… Y…`: the circle centre for the C blocks that follow (none: the position).
    fn pole(&mut self, t: &[Token]) -> Result<(), Fail> {
        let w = self.words(t)?;
        let only_xy = w.axes.iter().enumerate().all(|(k, a)| k < 2 || a.is_none());
        if !only_xy || w.feed.is_some() || w.rapid || !w.m.is_empty() || w.compensation.is_some() {
            return Err((t.first().map_or(1, |t| t.column), "CC takes the centre's X and Y only".into()));
        }
        let centre = self.target(&w, t)?;
        let col = t.first().map_or(1, |t| t.column);
        let x = centre.x.or(self.position[0]).ok_or((col, "CC without X from an unknown position".to_string()))?;
        let y = centre.y.or(self.position[1]).ok_or((col, "CC without Y from an unknown position".to_string()))?;
        self.centre = Some((x, y));
        Ok(())
    }

    /// `C X… Y… DR± …` around the CC, `CR X… Y… R± DR± …` by radius, `CT X… Y… …` tangent.
    fn arc(&mut self, kind: &str, t: &[Token], column: usize, line: usize) -> Result<(), Fail> {
        let w = self.words(t)?;
        if w.rapid {
            return Err((column, "an arc at FMAX is not read".into()));
        }
        if w.compensation.is_some() {
            return Err((column, "radius compensation on an arc is not read (give it on the L before)".into()));
        }
        self.note_decimals(t);
        let (Some(sx), Some(sy)) = (self.position[0], self.position[1]) else {
            return Err((column, "an arc from an unknown start point".into()));
        };
        let to = self.target(&w, t)?;
        let (ex, ey) = (to.x.unwrap_or(sx), to.y.unwrap_or(sy));
        let (direction, centre) = match kind {
            "C" => {
                let d = w.direction.ok_or((column, "C needs its direction DR+ or DR-".to_string()))?;
                (d, self.centre.ok_or((column, "C with no circle centre CC before it".to_string()))?)
            }
            "CR" => {
                let d = w.direction.ok_or((column, "CR needs its direction DR+ or DR-".to_string()))?;
                let (r, col) = w.radius.ok_or((column, "CR needs its radius R+ or R-".to_string()))?;
                let c = centre_from_radius((sx, sy), (ex, ey), r, d)
                    .ok_or((col, "the arc's end is farther from its start than 2·R".to_string()))?;
                (d, c)
            }
            _ => {
                if w.direction.is_some() || w.radius.is_some() {
                    return Err((column, "CT takes its end point only: the direction comes from the contour".into()));
                }
                let tangent = self.tangent.ok_or((column, "CT with no contour element in XY before it".to_string()))?;
                tangent_arc((sx, sy), (ex, ey), tangent)
                    .ok_or((column, "CT's end point lies on the straight line ahead: no arc".to_string()))?
            }
        };
        if kind != "CR" && w.radius.is_some() {
            return Err((column, format!("a radius R± belongs to CR, not to {kind}")));
        }
        self.m_functions(&w, line)?;
        let feed = self.feed(&w, line);
        let block = Block::Arc { direction, to, centre: Target::xy(centre.0, centre.1), feed };
        self.push(block, line);
        let (rx, ry) = (ex - centre.0, ey - centre.1);
        let tangent = match direction {
            ArcDirection::CounterClockwise => (-ry, rx),
            ArcDirection::Clockwise => (ry, -rx),
        };
        self.moved(&to, Some(tangent));
        Ok(())
    }
}

/// `BEGIN PGM NAME MM` / `END PGM NAME INCH`: the name and whether it is in inches.
fn pgm_line(t: &[Token]) -> Result<(&str, bool), Fail> {
    let col = |i: usize| t.get(i).map_or(t[0].column, |t| t.column);
    if t.get(1).map(|t| t.text.as_str()) != Some("PGM") {
        return Err((col(1), format!("{} is read as {} PGM NAME MM", t[0].text, t[0].text)));
    }
    let name = t.get(2).ok_or((col(2), "PGM without a program name".to_string()))?;
    let inches = match t.get(3).map(|t| t.text.as_str()) {
        Some("MM") => false,
        Some("INCH") => true,
        _ => return Err((col(3), "the program's unit MM or INCH after its name".into())),
    };
    if let Some(extra) = t.get(4) {
        return Err((extra.column, format!("`{}` after the unit is not read", extra.text)));
    }
    Ok((name.text.as_str(), inches))
}

fn m_code(digits: &str, column: usize) -> Result<u32, Fail> {
    digits.parse::<u32>().map_err(|_| (column, format!("M{digits} is not an M function")))
}

/// The centre and direction of the arc from `s` to `e` that leaves `s` along `tangent`:
/// on the normal through `s`, equally far from both ends. `None` when `e` lies on the
/// tangent's line (no circle).
fn tangent_arc(s: (f64, f64), e: (f64, f64), tangent: (f64, f64)) -> Option<(ArcDirection, (f64, f64))> {
    let len = tangent.0.hypot(tangent.1);
    // The left normal: a centre on it turns counter-clockwise.
    let n = (-tangent.1 / len, tangent.0 / len);
    let (dx, dy) = (e.0 - s.0, e.1 - s.1);
    let across = n.0 * dx + n.1 * dy;
    let chord2 = dx * dx + dy * dy;
    if across.abs() <= 1e-12 * chord2.sqrt().max(1.0) {
        return None;
    }
    // |s + k·n − e| = |k|  ⇒  k = |e − s|² / (2 n·(e − s)).
    let k = chord2 / (2.0 * across);
    let direction = if k > 0.0 { ArcDirection::CounterClockwise } else { ArcDirection::Clockwise };
    Some((direction, (s.0 + k * n.0, s.1 + k * n.1)))
}
