//! Reading programs back into the one program model. Word-address programs (every family
//! of `dialect::Family`) here: modal motion (G0–G3; the NC31 rapid `E`), plane
//! (G17/18/19), units (G20/21, Sinumerik G70/71, read into mm), absolute/incremental
//! (G90/91; a Fanuc lathe refuses G90-G94, cycles in system A), feed mode (G94/95, Fanuc lathe G98/99), diameter mode (LinuxCNC G7/G8,
//! Sinumerik DIAMON/DIAMOF; Fanuc and NC31 lathes are diametral), arcs by I/J/K, R or
//! Sinumerik CR=, F, S, T, M, Sinumerik LIMS= and MSG. LinuxCNC's parameters and expressions are read in
//! [`parameters`], its O-codes (subroutines, conditions, loops) run in [`flow`]. Heidenhain plain language is read in
//! [`heidenhain`]. A word the reader does not know is an error naming its line and column,
//! never skipped.

use std::fmt;

use super::program::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange,
    ToolOffset,
};

pub mod detect;
mod fanuc_calls;
mod flow;
pub mod heidenhain;
mod heidenhain_labels;
mod nc31;
pub mod parameters;
mod predefined;

pub(crate) use nc31::called as nc31_called;
pub(crate) use nc31::subprogram as nc31_subprogram;

/// Where a program cannot be read, 1-based.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}: {}", self.line, self.column, self.message)
    }
}

impl std::error::Error for ReadError {}

/// Digits after the point the ISO and LinuxCNC writers use unless a program asks for more.
const DEFAULT_DECIMALS: usize = 3;

/// Which control's reading of the words (the writers' families): they differ in dwell words
/// and units, lathe feed modes, O-words, diameter mode, comments and Sinumerik's named words.
pub use super::dialect::Family;

/// The word a dwell's time is given in: Fanuc P (ms), LinuxCNC P (s), Sinumerik F (s),
/// NC31 D (s).
fn dwell_word(family: Family) -> char {
    match family {
        Family::Fanuc | Family::LinuxCnc => 'P',
        Family::Sinumerik => 'F',
        Family::Nc31 => 'D',
    }
}

/// Reads `text` as `dialect` writes it, with the 1-based source line of each block of the
/// model.
pub fn read_dialect(
    text: &str,
    dialect: &dyn super::dialect::Dialect,
    machine: Option<Machine>,
) -> Result<(Program, Vec<usize>), ReadError> {
    dialect.read(text, machine)
}

/// One word as written: its letter, value and 1-based column.
#[derive(Clone, Copy, Debug)]
struct Word {
    letter: char,
    value: f64,
    column: usize,
    /// Digits written after the point.
    decimals: usize,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Motion {
    Rapid,
    Line,
    Arc(ArcDirection),
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Plane {
    Xy,
    Zx,
    Yz,
}

/// The modal state while reading.
struct State {
    family: Family,
    machine: Option<Machine>,
    motion: Option<Motion>,
    plane: Plane,
    inches: bool,
    incremental: bool,
    /// X is a diameter (Fanuc lathes always; LinuxCNC after G7).
    diameter: bool,
    compensation: Compensation,
    position: [Option<f64>; 6],
    speed: Option<f64>,
    max_rpm: Option<f64>,
    surface_speed: bool,
    /// The spindle's direction while it turns: an S alone then changes its speed.
    running: Option<SpindleDirection>,
    /// The tool in the spindle (or the turret's tool), once a T has been read.
    tool: Option<u32>,
    /// The tool a T word without M6 selected, for the next M6 (LinuxCNC, a Fanuc mill).
    selected: Option<u32>,
    /// The offset register in force: the H of G43 (LinuxCNC, Fanuc mill), the cutting edge
    /// D (Sinumerik), a Fanuc lathe's T word's last two digits; `None` when none is (power
    /// on in G49, after G49, D0, T0100). A tool change alone keeps it on LinuxCNC and a
    /// Fanuc mill: only G43/G49 change it.
    register: Option<u32>,
    /// The first D word of a G41/G42 (Fanuc, LinuxCNC) and whether it was the tool's own
    /// number: the model holds one radius register for the program, or each tool's own.
    radius_register: Option<(u32, bool)>,
    /// The F in force as written; `None` from power on and, on LinuxCNC, after a G93/G94/G95.
    feed: Option<f64>,
    /// LinuxCNC set the feed to 0 at a feed mode word after an F was in force: a cut must
    /// give F again (rs274: "Cannot do g1 with zero feed rate").
    feed_cleared: bool,
    per_revolution: bool,
    flood: bool,
    /// The axes X Y Z a move under cutter compensation left off their programmed values.
    compensated: [bool; 3],
}

/// Reads `text` as `family` writes it. `machine` says what the program is for; without it a
/// G18 before the first move means a lathe and anything else a mill.
pub fn read(text: &str, family: Family, machine: Option<Machine>) -> Result<Program, ReadError> {
    read_with_lines(text, family, machine).map(|(p, _)| p)
}

/// [`read`], with the 1-based source line of each block of the model (for messages about a
/// block found later, e.g. by the motion planner).
pub fn read_with_lines(
    text: &str,
    family: Family,
    machine: Option<Machine>,
) -> Result<(Program, Vec<usize>), ReadError> {
    read_noted(text, family, machine).map(|(program, lines, _)| (program, lines))
}

/// [`read_with_lines`], and what the reading kept of `text` without running it, one note a
/// line for stderr: a Fanuc file's subprograms that no M98 calls (stored, as a control stores
/// them).
pub fn read_noted(
    text: &str,
    family: Family,
    machine: Option<Machine>,
) -> Result<(Program, Vec<usize>, Vec<String>), ReadError> {
    if family == Family::Nc31 && machine == Some(Machine::Mill) {
        return Err(ReadError { line: 1, column: 1, message: "NC31 programs are for lathes".into() });
    }
    let machine = if family == Family::Nc31 { Some(Machine::Lathe) } else { machine };
    let mut lines = Vec::new();
    let mut st = State {
        family,
        machine,
        // NC31 has no G1: a block without `E` is a cut.
        motion: (family == Family::Nc31).then_some(Motion::Line),
        plane: if family == Family::Nc31 { Plane::Zx } else { Plane::Xy },
        inches: false,
        incremental: false,
        // Fanuc and NC31 lathes are diametral; Sinumerik turning machines power on in DIAMON.
        diameter: family != Family::LinuxCnc,
        compensation: Compensation::Off,
        position: [None; 6],
        speed: None,
        max_rpm: None,
        surface_speed: false,
        running: None,
        tool: None,
        selected: None,
        register: None,
        radius_register: None,
        feed: None,
        feed_cleared: false,
        per_revolution: false,
        flood: false,
        compensated: [false; 3],
    };
    let mut program = Program::new("", machine.unwrap_or(Machine::Mill));
    if family == Family::Nc31 {
        // NC31 feeds per revolution only, with no word for it.
        program.blocks.push(Block::FeedMode(FeedMode::PerRevolution));
        lines.push(1);
    }
    let mut started = false;
    // Coordinates written finer than the dialects' 0.001 mm: the machine resolves finer.
    let mut decimals = DEFAULT_DECIMALS;
    let mut ended = false;
    let mut parameters = parameters::Parameters::default();
    // NC31 runs its subprograms, parameters and jumps ([`nc31`]): the blocks it executes.
    // Fanuc runs its subprogram calls (M98, M99) over the file's other O programs ([`fanuc_calls`]).
    let fanuc = if family == Family::Fanuc { Some(fanuc_calls::unroll(text)?) } else { None };
    // Each source is one block with its line and the characters before it on that line (a
    // Fanuc line holds as many blocks as it has `;`: [`fanuc_blocks`], split once by the unroll).
    let mut sources: Box<dyn Iterator<Item = (std::borrow::Cow<'_, str>, usize, usize)>> = if family == Family::Nc31 {
        Box::new(nc31::expand(text)?.into_iter().map(|(b, line)| (std::borrow::Cow::Owned(b), line, 0)))
    } else if let Some(unrolled) = &fanuc {
        Box::new(unrolled.blocks())
    } else {
        Box::new(text.lines().enumerate().map(|(i, l)| (std::borrow::Cow::Borrowed(l), i + 1, 0)))
    };
    // LinuxCNC runs its O-codes (subroutines, conditions, loops) with the parameters as they stand.
    let mut flow = if family == Family::LinuxCnc { Some(flow::Flow::new(text)?) } else { None };
    loop {
        let next = match &mut flow {
            Some(flow) => flow.next_line(&mut parameters)?.map(|(l, i)| (std::borrow::Cow::Borrowed(l), i + 1, 0)),
            None => sources.next(),
        };
        let Some((raw, line, offset)) = next else { break };
        let raw = raw.as_ref();
        let at = |column: usize, message: String| ReadError { line, column: offset + column, message };
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed == "%" {
            continue;
        }
        if ended {
            return Err(at(1, "text after the program's end (M30/M2)".into()));
        }
        if family == Family::Sinumerik && !started {
            // The archive's directory: where the control files the program, not part of it.
            if trimmed.starts_with(";$PATH=") {
                continue;
            }
            if let Some(name) = sinumerik_header(trimmed).map_err(|m| at(1, m))? {
                program.name = name;
                continue;
            }
        }
        let Line { words, comment, diameter, spindle_limit, rapid_mark, settings } =
            tokens(raw, family, &parameters).map_err(|(c, m)| at(c, m))?;
        // LinuxCNC sets a line's parameters once the whole line is read.
        parameters.apply(settings);
        if let Some(d) = diameter {
            st.diameter = d;
        }
        if let Some(limit) = spindle_limit {
            st.max_rpm = Some(limit);
        }
        if words.is_empty() {
            if let Some(w) = rapid_mark {
                return Err(at(w, "a rapid mark E without an end point".into()));
            }
            if let Some(c) = comment {
                // Fanuc and LinuxCNC name a program in the comment before its first block.
                let names = matches!(family, Family::Fanuc | Family::LinuxCnc);
                if !started && names && program.name.is_empty() {
                    program.name = c;
                } else {
                    program.blocks.push(Block::Comment(c));
                    lines.push(line);
                }
            }
            continue;
        }
        if let Some(o) = words.iter().find(|w| w.letter == 'O') {
            if family != Family::Fanuc || started || words.len() > 1 {
                return Err(at(o.column, "an O-word other than the program number at the start is not read".into()));
            }
            if !(1.0..=9999.0).contains(&o.value) || o.value.fract() != 0.0 {
                return Err(at(o.column, format!("O{} is not a program number O0001–O9999", o.value)));
            }
            program.number = Some(o.value as u32);
            program.name = comment.unwrap_or_default();
            continue;
        }
        started = true;
        let finest = words.iter().filter(|w| "XYZABCIJKRUW".contains(w.letter)).map(|w| w.decimals).max();
        decimals = decimals.max(finest.unwrap_or(0));
        let before = program.blocks.len();
        ended = block(&mut st, &words, rapid_mark, &mut program.blocks).map_err(|(c, m)| at(c, m))?;
        if family == Family::LinuxCnc {
            let moved = program.blocks[before..].iter().any(is_move);
            note_compensated(&mut st, &words, moved);
            control_state(&st, &mut parameters.control);
        }
        // A comment after a block's words (`N20 T1 D1 ; roughing`) follows the block.
        if let Some(c) = comment.filter(|c| !c.is_empty()) {
            program.blocks.push(Block::Comment(c));
        }
        lines.resize(program.blocks.len(), line);
        if st.machine.is_none() && program.blocks[before..].iter().any(is_move) {
            st.machine = Some(Machine::Mill);
        }
    }
    program.machine = st.machine.unwrap_or(Machine::Mill);
    program.precision = (decimals > DEFAULT_DECIMALS).then_some(decimals);
    program.radius_offset = st.radius_register.and_then(|(d, own)| (!own).then_some(d));
    let notes = fanuc.as_ref().map(fanuc_calls::Unrolled::notes).unwrap_or_default();
    Ok((program, lines, notes))
}

/// After a block that moved: with cutter compensation on, the plane's axes are off their
/// programmed values; with it off, an axis the block wrote is where the program said.
fn note_compensated(st: &mut State, words: &[Word], moved: bool) {
    if !moved {
        return;
    }
    if st.compensation != Compensation::Off {
        let plane = match st.plane {
            Plane::Xy => [0, 1],
            Plane::Zx => [2, 0],
            Plane::Yz => [1, 2],
        };
        plane.iter().for_each(|&i| st.compensated[i] = true);
        return;
    }
    for (i, letter) in ['X', 'Y', 'Z'].iter().enumerate() {
        if words.iter().any(|w| w.letter == *letter) {
            st.compensated[i] = false;
        }
    }
}

/// The reader's state as LinuxCNC's predefined parameters read it (`#<_x>`, `#<_feed>` …):
/// positions in the program's units, a lathe's X as a radius (rs274 reports the radius in
/// G7 too).
fn control_state(st: &State, c: &mut predefined::Control) {
    let lathe = st.machine == Some(Machine::Lathe);
    for (i, axis) in c.axes.iter_mut().enumerate() {
        *axis = match st.position[i] {
            None => predefined::Axis::Unknown,
            Some(_) if i < 3 && st.compensated[i] => predefined::Axis::Compensated,
            Some(mut v) => {
                if i == 0 && lathe {
                    v /= 2.0;
                }
                if i < 3 && st.inches {
                    v /= 25.4;
                }
                predefined::Axis::At(v)
            }
        };
    }
    c.feed = st.feed.unwrap_or(0.0);
    c.speed = st.speed.unwrap_or(0.0);
    c.inches = st.inches;
    c.incremental = st.incremental;
    c.motion_mode = match st.motion {
        None => 800,
        Some(Motion::Rapid) => 0,
        Some(Motion::Line) => 10,
        Some(Motion::Arc(ArcDirection::Clockwise)) => 20,
        Some(Motion::Arc(ArcDirection::CounterClockwise)) => 30,
    };
    c.plane = match st.plane {
        Plane::Xy => 170,
        Plane::Zx => 180,
        Plane::Yz => 190,
    };
    c.compensation = match st.compensation {
        Compensation::Off => 400,
        Compensation::Left => 410,
        Compensation::Right => 420,
    };
    c.per_revolution = st.per_revolution;
    c.surface_speed = st.surface_speed;
    c.diameter = st.diameter;
    c.spindle = st.running.map(|d| d == SpindleDirection::Clockwise);
    c.flood = st.flood;
    c.tool = st.tool;
    c.selected = st.selected;
}

/// The blocks of one line of a Fanuc program, each with the number of characters before it
/// on the line (so that columns stay the line's). On a Fanuc control `;` is the end of block
/// (EOB: the manuals print every block as `N10 G00 X100. Z180. ;`, the control shows LF as
/// `;`), so a line holds as many blocks as it has `;` outside a `( … )` comment; elsewhere `;`
/// starts a comment (LinuxCNC, Sinumerik) and a line is one block. One pass over the line:
/// the blocks are slices of it, so a line of 200,000 blocks is not copied once per block.
fn fanuc_blocks(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let (mut start, mut start_chars, mut in_comment) = (0, 0, false);
    for (chars, (at, c)) in line.char_indices().enumerate() {
        match c {
            '(' => in_comment = true,
            ')' => in_comment = false,
            ';' if !in_comment => {
                out.push((start_chars, &line[start..at]));
                (start, start_chars) = (at + 1, chars + 1);
            }
            _ => {}
        }
    }
    out.push((start_chars, &line[start..]));
    out
}

/// A Sinumerik archive header line `%_N_NAME_MPF`: the program's name; `None` for any
/// other line.
fn sinumerik_header(line: &str) -> Result<Option<String>, String> {
    let Some(rest) = line.strip_prefix('%') else { return Ok(None) };
    let name = rest.strip_prefix("_N_").and_then(|n| n.strip_suffix("_MPF").or_else(|| n.strip_suffix("_SPF")));
    match name {
        Some(n) if !n.is_empty() => Ok(Some(n.to_string())),
        _ => Err(format!("`{line}` is not a Sinumerik program header (%_N_NAME_MPF)")),
    }
}

fn is_move(b: &Block) -> bool {
    matches!(b, Block::Rapid(_) | Block::Line { .. } | Block::Arc { .. })
}

type Fail = (usize, String);

/// What one line holds: its address words, its comment, and the words that are not
/// addresses (Sinumerik's DIAMON/DIAMOF and LIMS=, NC31's rapid mark `E`).
#[derive(Default)]
struct Line {
    words: Vec<Word>,
    comment: Option<String>,
    diameter: Option<bool>,
    spindle_limit: Option<f64>,
    /// The column of NC31's `E`.
    rapid_mark: Option<usize>,
    /// LinuxCNC's `#… = value` settings, applied after the line.
    settings: Vec<parameters::Setting>,
}

/// The words of one line and its comment: `( … )` on Fanuc and LinuxCNC, `;` to the end of
/// the line on LinuxCNC and Sinumerik (Fanuc's `;` ends the block: [`fanuc_blocks`];
/// the NC31 has no comments), Sinumerik's `MSG("…")`.
/// LinuxCNC's values may be expressions and parameters ([`parameters`]), read with the
/// values `params` holds before this line.
fn tokens(raw: &str, family: Family, params: &parameters::Parameters) -> Result<Line, Fail> {
    let chars: Vec<char> = raw.chars().collect();
    let mut line = Line::default();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c == '(' && matches!(family, Family::Fanuc | Family::LinuxCnc) {
            let close = chars[i..]
                .iter()
                .position(|&c| c == ')')
                .ok_or((i + 1, "a comment that is not closed by `)`".to_string()))?;
            line.comment = Some(chars[i + 1..i + close].iter().collect::<String>().trim().to_string());
            i += close + 1;
        } else if c == ';' && matches!(family, Family::LinuxCnc | Family::Sinumerik) {
            line.comment = Some(chars[i + 1..].iter().collect::<String>().trim().to_string());
            break;
        } else if c == '#' && family == Family::LinuxCnc {
            let (setting, next) = parameters::setting(&chars, i, params)?;
            line.settings.push(setting);
            i = next;
        } else if c.is_ascii_alphabetic() {
            let name_end = i + chars[i..].iter().take_while(|c| c.is_ascii_alphabetic() || **c == '_').count();
            if family == Family::Sinumerik && (name_end - i > 1 || chars.get(name_end) == Some(&'=')) {
                i = sinumerik_word(&chars, i, name_end, &mut line)?;
                continue;
            }
            let start = i;
            let letter = c.to_ascii_uppercase();
            i += 1;
            while i < chars.len() && chars[i] == ' ' {
                i += 1;
            }
            if letter == 'O' {
                if let Some((keyword, end)) = o_word_keyword(&chars, i) {
                    return Err((start + 1, o_word_refused(&chars[start..end], keyword)));
                }
            }
            if family == Family::LinuxCnc && parameters::starts_computed_value(&chars, i) {
                let (value, next) = parameters::real_value(&chars, i, params)?;
                line.words.push(Word { letter, value, column: start + 1, decimals: 0 });
                i = next;
                continue;
            }
            let (value, decimals, next) = number(&chars, i);
            if family == Family::Nc31 && letter == 'E' && value.is_none() {
                line.rapid_mark = Some(start + 1);
                continue;
            }
            if family == Family::Sinumerik && letter == 'R' {
                return Err((start + 1, "R is an arithmetic parameter on Sinumerik (an arc's radius is CR=)".into()));
            }
            if value.is_none() && family == Family::Fanuc && matches!(chars.get(i), Some('#' | '[')) {
                return Err((i + 1, not_a_word(chars[i], family)));
            }
            let number: String = chars[i..next].iter().collect();
            let value = value.ok_or_else(|| (start + 1, no_value(&format!("the word {letter}"), &number)))?;
            line.words.push(Word { letter, value, column: start + 1, decimals });
            i = next;
        } else {
            return Err((i + 1, not_a_word(c, family)));
        }
    }
    Ok(line)
}

/// Why `c` cannot start a word: a Fanuc or Sinumerik program's macro variables and
/// expressions are named as such rather than as a stray character.
fn not_a_word(c: char, family: Family) -> String {
    match (c, family) {
        ('#' | '[', Family::Fanuc) => format!(
            "`{c}` starts a custom macro variable or expression (Fanuc Macro B): ncsheet does not read macro \
             programs; write the values out"
        ),
        _ => format!("`{c}` is not the start of a word"),
    }
}

/// The keywords of LinuxCNC's O-codes (docs/src/gcode/o-code.adoc: subroutines, their
/// calls and returns, conditions and loops), as they follow an O-number or `O<name>`.
pub(crate) const O_WORD_KEYWORDS: &str =
    "sub endsub call return if elseif else endif do while endwhile repeat endrepeat break continue";

/// The O-code keyword `word` is, in lower case, if it is one (`SUB`, `Call`).
pub(crate) fn o_word_keyword_named(word: &str) -> Option<&'static str> {
    O_WORD_KEYWORDS.split(' ').find(|k| k.eq_ignore_ascii_case(word))
}

/// The LinuxCNC O-code keyword after an O-number or `O<name>` starting at `from` (`o100 sub`,
/// `O<pocket> call [2]`), in lower case, and where it ends; `None` for a plain O-word (Fanuc's
/// program number).
fn o_word_keyword(chars: &[char], from: usize) -> Option<(&'static str, usize)> {
    let mut i = from;
    if chars.get(i) == Some(&'<') {
        i += chars[i..].iter().position(|&c| c == '>')? + 1;
    } else {
        i += chars[i..].iter().take_while(|c| c.is_ascii_digit()).count();
    }
    i += chars[i..].iter().take_while(|c| c.is_whitespace()).count();
    let word: String = chars[i..].iter().take_while(|c| c.is_ascii_alphabetic()).collect();
    let keyword = o_word_keyword_named(&word)?;
    Some((keyword, i + word.len()))
}

/// Why the O-code `code` (`o100 sub`) is refused: it names the code as LinuxCNC does rather
/// than reading `sub` as a word S without a number.
fn o_word_refused(code: &[char], keyword: &str) -> String {
    let code = quoted_briefly(&code.iter().collect::<String>());
    format!(
        "`{code}` is a LinuxCNC O-code (the `{keyword}` of a subroutine, condition or loop): it begins a line of \
         its own, and only a program read as linuxcnc runs it"
    )
}

/// Why the `text` after `what` (a word) gives no value: a number past the largest double
/// (`X999…9`, which was said to have "no number after it" and quoted whole however long), or
/// no number at all.
pub(crate) fn no_value(what: &str, text: &str) -> String {
    let shown = quoted_briefly(text);
    if text.parse::<f64>().is_ok_and(f64::is_infinite) {
        format!("{what} has a number too large for any control (`{shown}`)")
    } else {
        format!("{what} has no number after it (`{shown}`)")
    }
}

/// `text` whole up to 40 characters, else its first 30 and its length: a word of a million
/// digits must not become a megabyte of error message. (nc stands below the formula parser,
/// which quotes its own literals the same way.)
fn quoted_briefly(text: &str) -> String {
    match text.chars().count() {
        n if n <= 40 => text.to_string(),
        n => format!("{}… ({n} characters)", text.chars().take(30).collect::<String>()),
    }
}

/// The number starting at `from`: its value (if it is one), digits after the point, and
/// where it ends.
fn number(chars: &[char], from: usize) -> (Option<f64>, usize, usize) {
    let mut end = from;
    while end < chars.len() && (chars[end].is_ascii_digit() || "+-.".contains(chars[end])) {
        end += 1;
    }
    let text: String = chars[from..end].iter().collect();
    let value = text.parse::<f64>().ok().filter(|v| v.is_finite());
    let decimals = text.split_once('.').map_or(0, |(_, f)| f.len());
    (value, decimals, end)
}

/// A Sinumerik word with a name (`DIAMON`, `LIMS=3000`, `CR=5`, `MSG("…")`) or an address
/// with `=` (`X=12.5`); returns where it ends.
fn sinumerik_word(chars: &[char], start: usize, name_end: usize, line: &mut Line) -> Result<usize, Fail> {
    let name: String = chars[start..name_end].iter().collect::<String>().to_ascii_uppercase();
    let column = start + 1;
    let assigned = |what: &str| -> Result<(f64, usize, usize), Fail> {
        let mut i = name_end;
        while chars.get(i) == Some(&' ') {
            i += 1;
        }
        if chars.get(i) != Some(&'=') {
            return Err((column, format!("{what} takes `=` and a number")));
        }
        i += 1;
        while chars.get(i) == Some(&' ') {
            i += 1;
        }
        let (value, decimals, end) = number(chars, i);
        let value = value.ok_or((
            i + 1,
            format!("{what}= is read with a number only (not an expression, AC(…), IC(…) or a parameter)"),
        ))?;
        Ok((value, decimals, end))
    };
    match name.as_str() {
        "DIAMON" => line.diameter = Some(true),
        "DIAMOF" => line.diameter = Some(false),
        "LIMS" => {
            let (v, _, end) = assigned("LIMS")?;
            line.spindle_limit = Some(v);
            return Ok(end);
        }
        "CR" => {
            let (value, decimals, end) = assigned("CR")?;
            line.words.push(Word { letter: 'R', value, column, decimals });
            return Ok(end);
        }
        "MSG" => return message(chars, name_end, column, line),
        "T" if chars.get(name_end + 1) == Some(&'"') => {
            return Err((
                column,
                "a tool called by name (T=\"…\") is not read: the program model numbers its tools".into(),
            ));
        }
        "R" => return Err((column, "R parameters are not read (the program model has no variables)".into())),
        _ if name.len() == 1 => {
            let (value, decimals, end) = assigned(&name)?;
            let letter = name.chars().next().expect("one letter");
            line.words.push(Word { letter, value, column, decimals });
            return Ok(end);
        }
        _ => return Err((column, format!("`{name}` is not a word this reader knows"))),
    }
    Ok(name_end)
}

/// `MSG("text")`: the operator's message, read as the block's comment.
fn message(chars: &[char], from: usize, column: usize, line: &mut Line) -> Result<usize, Fail> {
    let rest: String = chars[from..].iter().collect();
    let inner = rest.trim_start().strip_prefix('(').map(str::trim_start);
    let Some(inner) = inner.and_then(|t| t.strip_prefix('"')) else {
        return Err((column, "MSG is read as MSG(\"text\")".into()));
    };
    let Some(close) = inner.find('"') else {
        return Err((column, "MSG(\" is not closed by `\")`".into()));
    };
    let after = inner[close + 1..].trim_start();
    let Some(after) = after.strip_prefix(')') else {
        return Err((column, "MSG(\"…\" is not closed by `)`".into()));
    };
    let text = inner[..close].trim();
    if !text.is_empty() {
        line.comment = Some(text.to_string());
    }
    Ok(chars.len() - after.chars().count())
}

/// Reads one block's words into model blocks; `true` at the program's end (M30/M2).
fn block(st: &mut State, words: &[Word], rapid_mark: Option<usize>, out: &mut Vec<Block>) -> Result<bool, Fail> {
    let before = out.len();
    let end = block_blocks(st, words, rapid_mark, out)?;
    writers_refusals(st, words, &out[before.min(out.len())..])?;
    Ok(end)
}

/// A hand-written block is refused where the writers would refuse its model block, at the
/// word that carries the value (`dialect::check_values`: numbers past the control's digits,
/// feeds not above 0, spindle speeds, tool and offset numbers, dwells out of range, constant
/// surface speed on a mill), so that what is read can be written again and nothing the
/// control would not run is taken as meant. (Arc ends off their circle and a lathe's feed
/// mode are left to `nc check`: the controls' own tolerance and power-on state decide.)
fn writers_refusals(st: &State, words: &[Word], blocks: &[Block]) -> Result<(), Fail> {
    let format = super::dialect::read_limits(st.family);
    for w in words.iter().filter(|w| "XYZABCIJKR".contains(w.letter)) {
        format.length(w.letter, w.value).map_err(|m| (w.column, m))?;
    }
    // The first of `letters`, in their order, that the block has.
    let column = |letters: &str| {
        letters.chars().find_map(|l| words.iter().find(|w| w.letter == l)).map_or(words[0].column, |w| w.column)
    };
    let machine = st.machine.unwrap_or(Machine::Mill);
    for b in blocks {
        let at = match b {
            Block::Spindle(_) => column("SM"),
            Block::Tool(_) => column("T"),
            Block::LengthOffset(_) => column("HDG"),
            Block::Dwell(_) => column(&dwell_word(st.family).to_string()),
            _ => column("F"),
        };
        super::dialect::check_values(b, machine, format).map_err(|m| (at, m))?;
    }
    Ok(())
}

/// [`block`]'s reading, before the refusals.
fn block_blocks(st: &mut State, words: &[Word], rapid_mark: Option<usize>, out: &mut Vec<Block>) -> Result<bool, Fail> {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let mut motion_word = None;
    let mut dwell = false;
    let mut spindle_mode = None;
    let mut g50 = false;
    let mut end = false;
    let mut feed_mode = None;
    let mut compensation = None;
    let mut spindle_m = None;
    let mut coolant = None;
    let mut m6 = None;
    // G43 (true) or G49 (false), and its column.
    let mut length = None;
    let mut seen = std::collections::HashSet::new();
    for w in words {
        if !matches!(w.letter, 'G' | 'M') && !seen.insert(w.letter) {
            return Err((w.column, format!("{} is given twice in one block", w.letter)));
        }
        match w.letter {
            'G' => g_code(
                st,
                w,
                &mut motion_word,
                &mut dwell,
                &mut spindle_mode,
                &mut g50,
                &mut feed_mode,
                &mut compensation,
                &mut length,
            )?,
            'M' => match code(w)? {
                3 => spindle_m = Some(Some(SpindleDirection::Clockwise)),
                4 => spindle_m = Some(Some(SpindleDirection::CounterClockwise)),
                5 => spindle_m = Some(None),
                // The tool change of `T1 M6` (see `changes_tool`).
                6 => m6 = Some(w.column),
                8 => coolant = Some(true),
                9 => coolant = Some(false),
                2 | 30 => end = true,
                m => return Err((w.column, format!("M{m} is not a code this reader knows"))),
            },
            // NC31's moves by a distance: U in X (a diameter), W in Z (`W+R4` in the paper).
            'U' | 'W' if st.family == Family::Nc31 => {}
            'Y' | 'A' | 'B' | 'C' if st.family == Family::Nc31 => {
                return Err((w.column, format!("NC31 has no {} axis (its axes: X Z)", w.letter)));
            }
            'N' | 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'I' | 'J' | 'K' | 'R' | 'F' | 'S' | 'T' | 'D' | 'P' | 'H' => {}
            // G64's naive CAM tolerance, with its path tolerance P.
            'Q' if blending(words, st.family) => {}
            l => return Err((w.column, format!("{l} is not a word this reader knows"))),
        }
    }
    if motion_word.is_none() {
        cancel_motion(st, words)?;
    }
    unused_words(words, dwell, compensation, spindle_mode, g50, st.family)?;
    if let Some(w) = rapid_mark.filter(|_| dwell) {
        return Err((w, "a rapid mark E in a dwell block".into()));
    }
    if let Some(m) = feed_mode {
        out.push(Block::FeedMode(m));
    }
    note_feed(st, feed_mode, find('F'));
    if let Some((n, column)) = changes_tool(st, find('T'), m6)? {
        out.push(Block::Tool(tool_change(st, words, n, column, length)?));
    } else if let Some(offset) = length_offset(st, words, length)? {
        apply_length_offset(offset, out);
    }
    if let Some(s) = find('S') {
        if g50 {
            st.max_rpm = Some(s.value);
        } else {
            st.speed = Some(s.value);
            if spindle_m.is_none() {
                spindle_m = st.running.map(Some);
            }
        }
    }
    if let Some(d) = find('D').filter(|_| spindle_mode == Some(true) && st.family == Family::LinuxCnc) {
        st.max_rpm = Some(d.value);
    }
    if let Some(css) = spindle_mode {
        st.surface_speed = css;
    }
    match spindle_m {
        Some(None) => {
            st.running = None;
            out.push(Block::Spindle(Spindle::Stop));
        }
        Some(Some(direction)) => {
            st.running = Some(direction);
            let column = words.iter().find(|w| w.letter == 'M').map_or(1, |w| w.column);
            let speed = st.speed.ok_or((column, "the spindle starts with no speed S given".to_string()))?;
            out.push(Block::Spindle(if st.surface_speed {
                let max_rpm = st
                    .max_rpm
                    .ok_or((column, "constant surface speed with no spindle limit (G50 S, D or LIMS=)".to_string()))?;
                Spindle::SurfaceSpeed { metres_per_min: speed, max_rpm, direction }
            } else {
                Spindle::Rpm { rpm: speed, direction }
            }));
        }
        None => {}
    }
    if let Some(c) = compensation {
        radius_known(st, words, c)?;
        // The G40 of the set-up block before anything happened says what is so already (the
        // writers put it there); any later G40 is the program's own block.
        let setup = c == Compensation::Off && out.iter().all(|b| matches!(b, Block::FeedMode(_)));
        if !setup {
            out.push(Block::Compensation(c));
        }
        st.compensation = c;
    }
    if let Some(on) = coolant {
        st.flood = on;
        out.push(Block::Coolant(on));
    }
    if dwell {
        let letter = dwell_word(st.family);
        let column = words.iter().find(|w| w.letter == 'G' && w.value == 4.0).map_or(1, |w| w.column);
        let p = find(letter).ok_or((column, format!("a dwell G4 without its time {letter}")))?;
        let seconds = if st.family == Family::Fanuc { p.value / 1000.0 } else { p.value };
        out.push(Block::Dwell(seconds));
    } else if let Some(m) = motion_block(st, words, motion_word, rapid_mark)? {
        out.push(m);
    }
    Ok(end)
}

/// The feed in force after a block's feed mode word and F. LinuxCNC sets the feed to 0 at
/// every G93/G94/G95, the mode it is in already too: the F before it does not carry over.
fn note_feed(st: &mut State, feed_mode: Option<FeedMode>, f: Option<&Word>) {
    if let Some(m) = feed_mode {
        st.per_revolution = m == FeedMode::PerRevolution;
        if st.family == Family::LinuxCnc {
            st.feed_cleared |= st.feed.is_some();
            st.feed = None;
        }
    }
    if let Some(f) = f {
        st.feed = Some(f.value);
        st.feed_cleared = false;
    }
}

/// The offset register `register` (none: cancelled) as the model names it, where `own` is
/// the register that is the tool's own offset (its number; Sinumerik's cutting edge D1).
fn offset_of(register: Option<u32>, own: u32) -> ToolOffset {
    match register {
        None | Some(0) => ToolOffset::Cancelled,
        Some(r) if r == own => ToolOffset::Own,
        Some(r) => ToolOffset::Number(r),
    }
}

/// The tool a block changes to, and the column of the word that says so. On LinuxCNC and
/// a Fanuc mill T only selects the next tool and M6 changes to it (`T2` while tool 1 cuts,
/// the usual way to have the magazine ready; rs274 reads it as SELECT_TOOL, not a change);
/// `T1 M6` is both. A Fanuc lathe's turret, Sinumerik (as its writer's `T1 D1` and the
/// default tool-change mode) and NC31 change with T.
fn changes_tool(st: &mut State, t: Option<&Word>, m6: Option<usize>) -> Result<Option<(u32, usize)>, Fail> {
    let selects = match st.family {
        Family::LinuxCnc => true,
        // Until a G18 or the first move says, a Fanuc program is a mill's (as `read` decides).
        Family::Fanuc => st.machine != Some(Machine::Lathe),
        _ => false,
    };
    let Some(t) = t else {
        return match m6.filter(|_| selects) {
            Some(column) => match st.selected {
                Some(n) => Ok(Some((n, column))),
                None => Err((column, "M6 changes to the tool selected before it, and no T selected one".into())),
            },
            None => Ok(None),
        };
    };
    let n = code(t)?;
    if selects {
        st.selected = Some(n);
        if m6.is_none() {
            return Ok(None);
        }
    }
    Ok(Some((n, t.column)))
}

/// The tool change of a block with T, and the offset in force after it, as the control
/// applies it: a Fanuc lathe's `T0102` (tool 01, offset 02; 00 none); Sinumerik's cutting
/// edge `D2` (D0 none; D1 when the block gives none, the control's default edge); on
/// LinuxCNC and a Fanuc mill `G43 [H2]` or `G49` in the block, and without them the length
/// offset already in force: none from power on (G49) until a G43, and M6 changes no offset
/// (rs274 with a tool table: `T1 M6` alone moves the spindle's point, not the tip).
fn tool_change(
    st: &mut State,
    words: &[Word],
    n: u32,
    column: usize,
    length: Option<(usize, bool)>,
) -> Result<ToolChange, Fail> {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let lathe = st.machine == Some(Machine::Lathe);
    let change = match st.family {
        Family::Fanuc if lathe => {
            if n < 100 {
                return Err((
                    column,
                    format!("a Fanuc lathe's T word is the tool and its offset (T0101); T{n} names no tool"),
                ));
            }
            if let Some((column, _)) = length {
                return Err((column, "a Fanuc lathe's offset is the T word's last two digits, not G43/G49".into()));
            }
            st.register = Some(n % 100);
            ToolChange { number: n / 100, offset: offset_of(st.register, n / 100) }
        }
        Family::Sinumerik => {
            st.register = Some(find('D').map(code).transpose()?.unwrap_or(1));
            ToolChange { number: n, offset: offset_of(st.register, 1) }
        }
        Family::Nc31 => ToolChange::new(n),
        Family::Fanuc | Family::LinuxCnc => {
            match length {
                Some((_, false)) => st.register = None,
                Some((_, true)) => st.register = Some(find('H').map(code).transpose()?.unwrap_or(n)),
                None => {}
            }
            ToolChange { number: n, offset: offset_of(st.register, n) }
        }
    };
    st.tool = Some(change.number);
    Ok(change)
}

/// The length offset a block without T changes to, if it does: `G43 [H2]` or `G49` on
/// LinuxCNC and a Fanuc mill, a cutting edge `D2`/`D0` on Sinumerik. `None` also for a
/// G49 before any tool: the control is so from power on (the set-up block `G40 G49`).
fn length_offset(st: &mut State, words: &[Word], length: Option<(usize, bool)>) -> Result<Option<ToolOffset>, Fail> {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let (column, register) = match (st.family, length) {
        (Family::Sinumerik, _) => match find('D') {
            Some(d) => (d.column, Some(code(d)?)),
            None => return Ok(None),
        },
        (_, None) => return Ok(None),
        (Family::Fanuc, Some((column, _))) if st.machine == Some(Machine::Lathe) => {
            return Err((column, "a Fanuc lathe's offset is the T word's last two digits (T0102), not G43/G49".into()));
        }
        (_, Some((_, false))) if st.tool.is_none() => {
            st.register = None;
            return Ok(None);
        }
        (_, Some((column, false))) => (column, None),
        // LinuxCNC: G43 without H "uses the currently loaded tool".
        (_, Some((column, true))) => (column, find('H').map(code).transpose()?.or(st.tool)),
    };
    let Some(tool) = st.tool else {
        return Err((column, "a length offset with no tool called before it (T…)".into()));
    };
    st.register = register;
    let own = if st.family == Family::Sinumerik { 1 } else { tool };
    Ok(Some(offset_of(register, own)))
}

/// A length offset changed after a tool change: part of that change when no move came
/// between (`T1 M6` then `G43 H1 Z50`, the usual hand-written order), else a block of its own.
fn apply_length_offset(offset: ToolOffset, out: &mut Vec<Block>) {
    let last_tool = out.iter().rposition(|b| matches!(b, Block::Tool(_)));
    match last_tool {
        Some(i) if !out[i + 1..].iter().any(is_move) => {
            if let Block::Tool(t) = &mut out[i] {
                t.offset = offset;
            }
        }
        _ => out.push(Block::LengthOffset(offset)),
    }
}

/// Cutter compensation on a side needs a radius, and the model's is the current tool's. On
/// Sinumerik it is the active cutting edge's, and D0 (or no tool called) has none ("D0
/// compensation deselection", length and radius), so the control refuses G41/G42 there, as
/// the writer does. On Fanuc and LinuxCNC the D word names the radius register: the model
/// holds each tool's own (`T1 M6` … `G41 D1`) or one register for the whole program
/// (`Program::radius_offset`, `G41 D21`); a program that mixes them is refused rather than
/// read with the wrong radius; with no tool called the writers refuse it too.
fn radius_known(st: &mut State, words: &[Word], c: Compensation) -> Result<(), Fail> {
    if c == Compensation::Off {
        return Ok(());
    }
    let column = words.iter().find(|w| w.letter == 'G' && matches!(w.value as i64, 41 | 42)).map_or(1, |w| w.column);
    if st.family == Family::Sinumerik {
        return match (st.tool, offset_of(st.register, 1)) {
            (None, _) => Err((column, "cutter compensation with no tool called before it (T… D…)".into())),
            (Some(_), ToolOffset::Cancelled) => {
                Err((column, "cutter compensation after D0: Sinumerik's D0 cancels the radius too".into()))
            }
            _ => Ok(()),
        };
    }
    let Some(tool) = st.tool else {
        return Err((column, "cutter compensation with no tool called before it (T… M6)".into()));
    };
    let Some(d) = words.iter().find(|w| w.letter == 'D') else { return Ok(()) };
    let (register, own) = (code(d)?, code(d)? == tool);
    match st.radius_register {
        None => st.radius_register = Some((register, own)),
        Some((_, true)) if own => {}
        Some((first, false)) if register == first => {}
        Some((first, first_own)) => {
            let before = if first_own { "each tool's own register".to_string() } else { format!("D{first}") };
            return Err((
                d.column,
                format!(
                    "D{register} with tool {tool}: the program model compensates with one radius register for the \
                     whole program or each tool's own, and this program used {before} before"
                ),
            ));
        }
    }
    Ok(())
}

/// A LinuxCNC block with G64, whose P and Q are its blending tolerances.
fn blending(words: &[Word], family: Family) -> bool {
    family == Family::LinuxCnc && words.iter().any(|w| w.letter == 'G' && w.value == 64.0)
}

/// LinuxCNC's G80 in a block without another motion code: no motion mode is in force after it
/// (`#<_motion_mode>` 800), so an axis word needs G0–G3 again, and axis words beside it are
/// refused as rs274 refuses them ("Cannot use axis values with G80"). With G0–G3 in the block
/// rs274 moves as that code says.
fn cancel_motion(st: &mut State, words: &[Word]) -> Result<(), Fail> {
    if !words.iter().any(|w| w.letter == 'G' && w.value == 80.0) {
        return Ok(());
    }
    if let Some(axis) = words.iter().find(|w| "XYZABC".contains(w.letter)) {
        return Err((
            axis.column,
            format!("{} with G80, which ends the motion mode: the move needs G0, G1, G2 or G3", axis.letter),
        ));
    }
    st.motion = None;
    Ok(())
}

/// Words that only mean something with a code this block does not have: an error rather
/// than a word silently dropped.
fn unused_words(
    words: &[Word],
    dwell: bool,
    compensation: Option<Compensation>,
    spindle_mode: Option<bool>,
    g50: bool,
    family: Family,
) -> Result<(), Fail> {
    let g43 = words.iter().any(|w| w.letter == 'G' && w.value == 43.0);
    let g64 = blending(words, family);
    let side = matches!(compensation, Some(Compensation::Left | Compensation::Right));
    let css_limit = spindle_mode == Some(true) && family == Family::LinuxCnc;
    // Sinumerik's D is the cutting edge, with a tool change or alone.
    let edge = family == Family::Sinumerik;
    let dwell_word = dwell_word(family);
    for w in words {
        let meaningful = match w.letter {
            // The dwell's time, and nothing else with a dwell: G4 is a block of its own.
            l if dwell => l == dwell_word || matches!(l, 'G' | 'N'),
            'P' => g64,
            'D' => side || css_limit || edge,
            'H' => g43,
            'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' => !g50,
            _ => true,
        };
        if !meaningful {
            return Err((w.column, format!("{} has no meaning in this block (not read)", w.letter)));
        }
    }
    Ok(())
}

fn code(w: &Word) -> Result<u32, Fail> {
    if w.value.fract() != 0.0 || w.value < 0.0 || w.value > 1e6 {
        return Err((w.column, format!("{}{} is not a whole code", w.letter, w.value)));
    }
    Ok(w.value as u32)
}

#[allow(clippy::too_many_arguments)]
fn g_code(
    st: &mut State,
    w: &Word,
    motion: &mut Option<usize>,
    dwell: &mut bool,
    spindle_mode: &mut Option<bool>,
    g50: &mut bool,
    feed_mode: &mut Option<FeedMode>,
    compensation: &mut Option<Compensation>,
    length: &mut Option<(usize, bool)>,
) -> Result<(), Fail> {
    let lathe = st.machine == Some(Machine::Lathe);
    let unsupported = || Err((w.column, format!("G{} is not a code this reader knows", w.value)));
    if w.value == 53.0 && st.family != Family::Nc31 {
        return Err((w.column, machine_coordinates(st.family)));
    }
    if st.family == Family::LinuxCnc {
        if let Some(read) = linuxcnc_setup_code(w) {
            return read;
        }
    }
    if w.value.fract() != 0.0 {
        return unsupported();
    }
    let sinumerik = st.family == Family::Sinumerik;
    // NC31's blocks are cuts unless marked E: its G words are the dwell and G40.
    if st.family == Family::Nc31 && !matches!(w.value as i64, 4 | 40) {
        return Err((w.column, format!("G{} is not an NC31 code this reader knows (rapids are marked E)", w.value)));
    }
    match w.value as i64 {
        0 => set_motion(st, w, motion, Motion::Rapid),
        1 => set_motion(st, w, motion, Motion::Line),
        2 => set_motion(st, w, motion, Motion::Arc(ArcDirection::Clockwise)),
        3 => set_motion(st, w, motion, Motion::Arc(ArcDirection::CounterClockwise)),
        4 => *dwell = true,
        7 if st.family == Family::LinuxCnc => st.diameter = true,
        8 if st.family == Family::LinuxCnc => st.diameter = false,
        17 => st.plane = Plane::Xy,
        18 => {
            st.plane = Plane::Zx;
            st.machine.get_or_insert(Machine::Lathe);
        }
        19 => st.plane = Plane::Yz,
        20 if !sinumerik => st.inches = true,
        21 if !sinumerik => st.inches = false,
        70 | 700 if sinumerik => st.inches = true,
        71 | 710 if sinumerik => st.inches = false,
        40 => *compensation = Some(Compensation::Off),
        41 => *compensation = Some(Compensation::Left),
        42 => *compensation = Some(Compensation::Right),
        // Tool length offset from the table, or none, with the tool change (`T1 M6 G43`).
        43 if !sinumerik => *length = Some((w.column, true)),
        49 if !sinumerik => *length = Some((w.column, false)),
        50 if st.family == Family::Fanuc => *g50 = true,
        90 | 91 | 92 | 94 if st.family == Family::Fanuc && lathe => return Err((w.column, system_a(w.value as i64))),
        90 => st.incremental = false,
        91 => st.incremental = true,
        94 => *feed_mode = Some(FeedMode::PerMinute),
        95 => *feed_mode = Some(FeedMode::PerRevolution),
        98 if st.family == Family::Fanuc && lathe => *feed_mode = Some(FeedMode::PerMinute),
        99 if st.family == Family::Fanuc && lathe => *feed_mode = Some(FeedMode::PerRevolution),
        96 => *spindle_mode = Some(true),
        97 => *spindle_mode = Some(false),
        _ => return unsupported(),
    }
    Ok(())
}

/// The codes of a CAM program's set-up line (`G17 G21 G40 G49 G54 G80 G90 G94`, `G64 P0.01`)
/// that change nothing the model holds, read as rs274 2.9 reads them, and the codes of the same
/// groups that would change the path refused by name. `None` for every other code.
/// - G54: the work offset in force from power on (LinuxCNC's #5220 = 1); the model's coordinates
///   are the program's, so staying in it changes nothing. G55–G59.3 would shift every move after
///   them by an offset ncsheet does not know.
/// - G80: cancels a canned cycle, and the reader reads none, so only the motion mode ends (see
///   [`cancel_motion`]).
/// - G61, G61.1, G64 [P Q]: path blending. The model's times stop at every block's end as
///   G61.1 does, so under G64 they are an upper bound (docs/limits.md).
/// - G91.1: I J K from the arc's start, as this reader reads them; G90.1 would make them absolute.
fn linuxcnc_setup_code(w: &Word) -> Option<Result<(), Fail>> {
    let tenths = (w.value * 10.0).round();
    if (w.value * 10.0 - tenths).abs() > 1e-9 {
        return None;
    }
    let refuse = |why: String| Some(Err((w.column, why)));
    match tenths as i64 {
        540 | 610 | 611 | 640 | 800 | 911 => Some(Ok(())),
        550..=590 if tenths as i64 % 10 == 0 => refuse(other_work_offset(w.value)),
        591..=593 => refuse(other_work_offset(w.value)),
        901 => refuse(
            "G90.1 makes arc centres I J K absolute: this reader reads them from the arc's start (G91.1, \
             LinuxCNC's power-on mode)"
                .into(),
        ),
        _ => None,
    }
}

/// Why G55–G59.3 are refused: each shifts the moves after it by its own work offset.
fn other_work_offset(code: f64) -> String {
    format!(
        "G{code} selects another work offset than the power-on G54: ncsheet does not model work offsets, so \
         it cannot say where the moves after it go (write the program in G54)"
    )
}

/// Why a Fanuc lathe's G90, G91, G92 or G94 is refused: in G-code system A (which the ISO
/// lathe follows: G98/G99, `G50 S`) the first three are cycles, and absolute or incremental is
/// the letter (X/Z or U/W), never a mode. Read as a mode switch they would turn a cycle into
/// one straight cut.
fn system_a(code: i64) -> String {
    let system_a = "on a Fanuc lathe (G-code system A)";
    let cycle = |what: &str, not: &str| {
        format!(
            "{system_a} G{code} is {what}, not {not}; this reader does not model the cycle: write its passes as \
             G0/G1 moves"
        )
    };
    match code {
        90 => cycle(
            "the outer/inner-diameter turning cycle A",
            "absolute mode (X and Z are absolute, U and W incremental)",
        ),
        92 => cycle("the threading cycle", "a coordinate setting (the speed limit is G50 S)"),
        94 => cycle("the end-face turning cycle B", "feed per minute (that is G98)"),
        _ => format!("{system_a} there is no G{code}: incremental moves are written with U and W"),
    }
}

/// Why G53 is refused: its move's end is in machine coordinates, which are the program's
/// shifted by the work offset and the tool length the control holds (LinuxCNC, Fanuc mill);
/// read as the program's coordinates the move would go elsewhere.
fn machine_coordinates(family: Family) -> String {
    let offsets = if family == Family::Sinumerik { "G54–G57, G500, TRANS" } else { "G54–G59, G92" };
    format!(
        "G53 moves in machine coordinates, which are the program's shifted by the control's work offset \
         ({offsets}) and tool length: ncsheet does not model them, so it cannot say where the move goes"
    )
}

fn set_motion(st: &mut State, w: &Word, word: &mut Option<usize>, m: Motion) {
    st.motion = Some(m);
    *word = Some(w.column);
}

/// The move a block makes, if it names an axis (or a motion code with axes).
fn motion_block(
    st: &mut State,
    words: &[Word],
    motion_word: Option<usize>,
    rapid_mark: Option<usize>,
) -> Result<Option<Block>, Fail> {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let scale = if st.inches { 25.4 } else { 1.0 };
    let axes = ['X', 'Y', 'Z', 'A', 'B', 'C'];
    let nc31 = st.family == Family::Nc31;
    let by_distance = move |w: &&Word| nc31 && matches!(w.letter, 'U' | 'W');
    let has_axis = words.iter().any(|w| axes.contains(&w.letter) || by_distance(&w));
    let arc_words = words.iter().find(|w| "IJKR".contains(w.letter));
    if !has_axis {
        if let Some(w) = arc_words {
            return Err((w.column, format!("{} without an end point", w.letter)));
        }
        if let Some(column) = rapid_mark {
            return Err((column, "a rapid mark E without an end point".into()));
        }
        // `G1 F100`: the feed for the cuts that follow, a line that goes nowhere in the model.
        return Ok(find('F').map(|f| Block::Line { to: Target::default(), feed: Some(f.value * scale) }));
    }
    let modal = st.motion.ok_or((words[0].column, "a move with no motion code (G0/G1/G2/G3) in force".to_string()))?;
    // NC31's `E` makes this block's move a rapid; the next block without it cuts again.
    let motion = if rapid_mark.is_some() { Motion::Rapid } else { modal };
    if st.machine.is_none() {
        st.machine = Some(Machine::Mill);
    }
    let lathe = st.machine == Some(Machine::Lathe);
    let start = st.position;
    let mut target = Target::default();
    for (i, letter) in axes.iter().enumerate() {
        let Some(w) = find(*letter) else { continue };
        // Lengths in mm; rotary axes in degrees whatever the units. A lathe's X is a diameter
        // in the model; radius mode (LinuxCNC G8) writes the radius.
        let mut v = if i < 3 { w.value * scale } else { w.value };
        if i == 0 && lathe && !st.diameter {
            v *= 2.0;
        }
        if st.incremental {
            let from = start[i].ok_or((w.column, format!("an incremental {letter} from an unknown position")))?;
            v += from;
        }
        match i {
            0 => target.x = Some(v),
            1 => target.y = Some(v),
            2 => target.z = Some(v),
            3 => target.a = Some(v),
            4 => target.b = Some(v),
            _ => target.c = Some(v),
        }
        st.position[i] = Some(v);
    }
    for w in words.iter().filter(by_distance) {
        let (axis, i) = if w.letter == 'U' { ('X', 0) } else { ('Z', 2) };
        if find(axis).is_some() {
            return Err((w.column, format!("{axis} and {} in one block: the axis cannot go two places", w.letter)));
        }
        let from = st.position[i].ok_or((w.column, format!("a move {} from an unknown {axis}", w.letter)))?;
        let v = from + w.value;
        if i == 0 {
            target.x = Some(v);
        } else {
            target.z = Some(v);
        }
        st.position[i] = Some(v);
    }
    let feed = find('F').map(|f| f.value * scale);
    let column = motion_word.unwrap_or(words[0].column);
    if st.feed_cleared && motion != Motion::Rapid {
        return Err((
            column,
            "a cut with no feed: LinuxCNC sets the feed to 0 at G93/G94/G95, so the F before it does not carry \
             over (give F after the feed mode)"
                .into(),
        ));
    }
    Ok(Some(match motion {
        Motion::Rapid => {
            if let Some(w) = arc_words.or(find('F')) {
                return Err((w.column, format!("{} in a rapid move", w.letter)));
            }
            Block::Rapid(target)
        }
        Motion::Line => {
            if let Some(w) = arc_words {
                return Err((w.column, format!("{} in a straight move", w.letter)));
            }
            Block::Line { to: target, feed }
        }
        Motion::Arc(direction) => {
            let centre = arc_centre(st, lathe, &start, words, direction, column)?;
            Block::Arc { direction, to: target, centre, feed }
        }
    }))
}

/// The absolute arc centre from I/J/K (offsets from the start, a radius on a lathe's X) or
/// from R (negative R: the arc over 180°), in the machine's plane only.
fn arc_centre(
    st: &State,
    lathe: bool,
    start: &[Option<f64>; 6],
    words: &[Word],
    direction: ArcDirection,
    column: usize,
) -> Result<Target, Fail> {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let scale = if st.inches { 25.4 } else { 1.0 };
    let wanted = if lathe { Plane::Zx } else { Plane::Xy };
    if st.plane != wanted {
        return Err((
            column,
            "an arc outside the machine's plane (G17 on a mill, G18 on a lathe) is not in the program model".into(),
        ));
    }
    // Plane coordinates (u, v) in true lengths: (X, Y) on a mill, (Z, X/2) on a lathe.
    let (ui, vi) = if lathe { (2, 0) } else { (0, 1) };
    let true_len = |i: usize, v: f64| if lathe && i == 0 { v / 2.0 } else { v };
    let s = match (start[ui], start[vi]) {
        (Some(u), Some(v)) => (u, true_len(vi, v)),
        _ => return Err((column, "an arc from an unknown start point".into())),
    };
    let e =
        (st.position[ui].unwrap_or(s.0), true_len(vi, st.position[vi].unwrap_or(s.1 * if lathe { 2.0 } else { 1.0 })));
    let c = if let Some(r) = find('R') {
        centre_from_radius(s, e, r.value * scale, direction)
            .ok_or((r.column, "the arc's end is farther from its start than 2·R".to_string()))?
    } else {
        let (ul, vl) = if lathe { ('K', 'I') } else { ('I', 'J') };
        let off = |l: char| find(l).map_or(0.0, |w| w.value * scale);
        if find(ul).is_none() && find(vl).is_none() {
            return Err((column, format!("an arc needs {ul}/{vl} or R")));
        }
        (s.0 + off(ul), s.1 + off(vl))
    };
    // Controls refuse an arc of no radius (rs274: "Zero-radius arc"); so do the writers.
    let radius = (c.0 - s.0).hypot(c.1 - s.1);
    let resolution = super::dialect::read_limits(st.family).resolution();
    if radius <= resolution {
        return Err((column, super::dialect::tiny_arc_message(radius, resolution)));
    }
    Ok(if lathe { Target::xz(c.1 * 2.0, c.0) } else { Target::xy(c.0, c.1) })
}

/// The centre of the arc of radius |r| from `s` to `e` turning `direction`; r < 0 takes the
/// longer of the two arcs (RS-274 and Fanuc alike).
fn centre_from_radius(s: (f64, f64), e: (f64, f64), r: f64, direction: ArcDirection) -> Option<(f64, f64)> {
    let (dx, dy) = (e.0 - s.0, e.1 - s.1);
    let chord = dx.hypot(dy);
    let half = chord / 2.0;
    if chord == 0.0 || half > r.abs() * (1.0 + 1e-9) {
        return None;
    }
    let h = (r * r - half * half).max(0.0).sqrt();
    let (mx, my) = (s.0 + dx / 2.0, s.1 + dy / 2.0);
    // Left of the chord for a counter-clockwise short arc; the long arc and clockwise flip it.
    let mut side = if direction == ArcDirection::CounterClockwise { 1.0 } else { -1.0 };
    if r < 0.0 {
        side = -side;
    }
    Some((mx - side * h * dy / chord, my + side * h * dx / chord))
}
