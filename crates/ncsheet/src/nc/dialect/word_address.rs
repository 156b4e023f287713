//! The word-address writer (DIN 66025 / ISO 6983 / RS-274D) shared by ISO/Fanuc, LinuxCNC,
//! Sinumerik and the old NC31 lathe control; each is one [`WordAddress`] table. What each
//! writes for feed mode, spindle, tool, numbering and comments is in docs/dialects.md.

use super::subprograms::{self, Call};
use super::{
    arc_as_lines, centre_offsets, check_program, check_values, feed_style, program_name, sanitise, Dialect, Format,
    NcError, Position,
};
use crate::nc::format::NumberStyle;
use crate::nc::program::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange,
    ToolOffset, Word, DEFAULT_ARC_TOLERANCE,
};
use crate::nc::read::{self, ReadError};

/// How one word-address control writes a program.
pub struct WordAddress {
    pub name: &'static str,
    /// Whose words the spindle, tool, dwell, feed-mode and comment blocks use.
    pub family: Family,
    pub numbers: NumberStyle,
    /// Digits a number may have in all (Fanuc: 8, ±99999.999 at 3 decimals).
    pub digits: usize,
    /// `N10`, `N20`, … (`width` pads with zeros: NC31's `N001`); past `block_digits` digits
    /// the numbers start again at `block_step` (block numbers are labels, not an order).
    pub block_step: u32,
    pub block_width: usize,
    pub block_digits: u32,
    /// Lines before the first block; `{name}` and `{number}` are replaced.
    pub header: &'static [&'static str],
    /// Modal set-up written as the first numbered block, per machine.
    pub setup_lathe: Option<&'static str>,
    pub setup_mill: Option<&'static str>,
    /// Blocks and lines after the last block.
    pub end_block: &'static str,
    pub footer: &'static [&'static str],
    /// NC31 marks a rapid with `E` after the coordinates instead of `G0`.
    pub rapid_suffix: Option<&'static str>,
    pub has_arcs: bool,
    pub machines: &'static [Machine],
    /// The axes the control moves; a move of another axis is refused, never left out.
    pub axes: &'static str,
    /// Addresses a raw block may use.
    pub legal: &'static str,
}

/// The control family a table belongs to: it decides the words that are not motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Fanuc (lathes in G-code system A): G98/G99 on a lathe, G94/G95 on a mill, G50 S
    /// spindle limit, `T0101`, `G4 P` in ms, upper-case `(COMMENTS)`, O0001–O9999.
    Fanuc,
    /// LinuxCNC (RS-274/NGC): G94/G95, `G96 D… S…`, `T1 M6 G43`, `G4 P` in s, `(comments)`.
    LinuxCnc,
    /// Sinumerik 840D: G94/G95, `LIMS=`, `T1 D1`, `G4 F` in s, `; comments`.
    Sinumerik,
    /// Elektronika NC31: feeds per revolution only, no comments, no constant surface speed.
    Nc31,
}

const FANUC_NUMBERS: NumberStyle =
    NumberStyle { decimals: 3, plus_sign: false, trailing_zeros: false, always_point: true };
const PLAIN_NUMBERS: NumberStyle =
    NumberStyle { decimals: 3, plus_sign: false, trailing_zeros: false, always_point: false };

/// Fanuc-style ISO: `%`, `O0001 (NAME)` (the O-number only when the program has a number,
/// so that a numberless program is plain RS-274 that LinuxCNC reads too), `N10 G0 X44.263
/// Z-4.6`, lathe X in diameter.
pub const ISO: WordAddress = WordAddress {
    name: "iso",
    family: Family::Fanuc,
    numbers: FANUC_NUMBERS,
    digits: 8,
    block_step: 10,
    block_width: 0,
    block_digits: 5,
    header: &["%", "O{number:04} ({name})"],
    // No G90: in Fanuc lathe G-code system A it is the OD/ID turning cycle (absolute and
    // incremental are X/Z and U/W there), and X/Z are absolute from power on.
    setup_lathe: Some("G21 G18 G40"),
    setup_mill: Some("G21 G17 G90 G40"),
    end_block: "M30",
    footer: &["%"],
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    axes: "XYZABC",
    legal: "NGMXYZABCIJKRFSTDHPQUVWLO",
};

/// RS-274NGC as LinuxCNC reads it: no O-number (O-words are subroutines there), diameter
/// mode `G7` on a lathe.
pub const LINUXCNC: WordAddress = WordAddress {
    name: "linuxcnc",
    family: Family::LinuxCnc,
    numbers: PLAIN_NUMBERS,
    digits: 9,
    block_step: 10,
    block_width: 0,
    block_digits: 5,
    header: &["%", "({name})"],
    setup_lathe: Some("G21 G18 G7 G90 G40"),
    setup_mill: Some("G21 G17 G90 G40"),
    end_block: "M2",
    footer: &["%"],
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    axes: "XYZABC",
    legal: "NGMXYZABCIJKRFSTDHPQUVWL",
};

/// Siemens Sinumerik: `%_N_NAME_MPF` archive header, `; comments`, `DIAMON` on a lathe.
pub const SINUMERIK: WordAddress = WordAddress {
    name: "sinumerik",
    family: Family::Sinumerik,
    numbers: PLAIN_NUMBERS,
    digits: 12,
    block_step: 10,
    block_width: 0,
    block_digits: 7,
    header: &["%_N_{name}_MPF", ";$PATH=/_N_MPF_DIR"],
    setup_lathe: Some("G18 DIAMON G90 G71"),
    setup_mill: Some("G17 G90 G71"),
    end_block: "M30",
    footer: &[],
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    axes: "XYZABC",
    legal: "NGMXYZABCIJKFSTDHPQUVWL",
};

/// Elektronika NC31 (docs/domain.md §2): `N001 X34 Z-60 E`, rapid marked `E`, `M02` at the end.
pub const NC31: WordAddress = WordAddress {
    name: "nc31",
    family: Family::Nc31,
    numbers: PLAIN_NUMBERS,
    digits: 7,
    block_step: 1,
    block_width: 3,
    block_digits: 3,
    header: &[],
    setup_lathe: None,
    setup_mill: None,
    end_block: "M02",
    footer: &[],
    rapid_suffix: Some("E"),
    has_arcs: false,
    machines: &[Machine::Lathe],
    axes: "XZ",
    legal: "NGMXZUWFSTLDPARQ",
};

/// NC81, which the chamfer paper names beside NC31 as the controls its model serves ("all
/// NC31- and NC81-type controls", docs/domain.md §1): the same words as NC31, per the paper;
/// no NC81 manual was available to say how it differs.
pub const NC81: WordAddress = WordAddress { name: "nc81", ..NC31 };

impl Dialect for WordAddress {
    fn name(&self) -> &'static str {
        self.name
    }

    fn resolution(&self) -> f64 {
        self.numbers.resolution()
    }

    fn writes(&self, machine: Machine) -> bool {
        self.machines.contains(&machine)
    }

    fn read(&self, text: &str, machine: Option<Machine>) -> Result<(Program, Vec<usize>), ReadError> {
        read::read_with_lines(text, self.family, machine)
    }

    fn read_noted(
        &self,
        text: &str,
        machine: Option<Machine>,
    ) -> Result<(Program, Vec<usize>, Vec<String>), ReadError> {
        read::read_noted(text, self.family, machine)
    }

    fn render(&self, program: &Program) -> Result<String, NcError> {
        self.write(program, &[])
    }
}

impl WordAddress {
    /// The program with every use of a subprogram it marks ([`Program::calls`]) written as a
    /// call, `L16 X30 W40 …`, in place of the use's blocks, and each subprogram used written
    /// once after the program's end (docs/domain.md §2). NC31 only. Before it is returned
    /// the text is read back with its subprograms run as the control runs them, and refused
    /// unless it moves, dwells and sets the machine as the unrolled program does, block for
    /// block. A program that marks no use is written as [`Dialect::render`] writes it.
    pub fn render_with_subprograms(&self, program: &Program) -> Result<String, NcError> {
        if self.family != Family::Nc31 {
            return Err(self.error(None, "writes no subprograms (nc31 and nc81 do)".into()));
        }
        let calls = subprograms::checked_calls(program).map_err(|(b, m)| self.error(b, m))?;
        let called = self.write(program, &calls)?;
        if !calls.is_empty() {
            let flat = self.write(program, &[])?;
            subprograms::same_motion(&flat, &called).map_err(|m| self.error(None, m))?;
        }
        Ok(called)
    }

    /// The program, each of `calls` written as a call of its subprogram (in block order).
    fn write(&self, program: &Program, calls: &[Call<'_>]) -> Result<String, NcError> {
        if !self.machines.contains(&program.machine) {
            return Err(self.error(None, format!("writes no {:?} programs", program.machine).to_lowercase()));
        }
        let numbers = NumberStyle { decimals: program.precision.unwrap_or(self.numbers.decimals), ..self.numbers };
        check_program(program, Format { numbers, digits: self.digits }).map_err(|(b, m)| self.error(b, m))?;
        self.check_axes(program)?;
        let mut w = Writer {
            d: self,
            machine: program.machine,
            numbers,
            out: String::new(),
            next: self.block_step,
            position: Position::default(),
            spindle_on: false,
            coolant_on: false,
            tool: None,
            arc_tolerance: program.arc_tolerance.unwrap_or(DEFAULT_ARC_TOLERANCE),
            radius_offset: program.radius_offset,
        };
        self.header(&mut w, program).map_err(|m| self.error(None, m))?;
        let setup = match program.machine {
            Machine::Lathe => self.setup_lathe,
            Machine::Mill => self.setup_mill,
        };
        if let Some(s) = setup {
            w.numbered(s);
        }
        let mut calls_left = calls.iter().peekable();
        let mut i = 0;
        while let Some(block) = program.blocks.get(i) {
            if let Some(call) = calls_left.next_if(|c| c.first == i) {
                // The writer's state (position, spindle, tool) as after the blocks the call
                // stands for; their text is not written.
                let (kept, next) = (w.out.len(), w.next);
                for (k, b) in program.blocks[call.first..call.end].iter().enumerate() {
                    w.block(b).map_err(|m| self.error(Some(call.first + k + 1), m))?;
                }
                w.out.truncate(kept);
                w.next = next;
                let text = subprograms::call(call, |v| w.number(v)).map_err(|m| self.error(Some(call.first + 1), m))?;
                w.numbered(&text);
                i = call.end;
                continue;
            }
            w.block(block).map_err(|m| self.error(Some(i + 1), m))?;
            i += 1;
        }
        w.end(program.retract.as_ref());
        for subprogram in subprograms::written(program, calls).map_err(|m| self.error(None, m))? {
            w.numbered(&subprograms::header(subprogram));
            for line in &subprogram.body {
                w.line(line.trim());
            }
        }
        for line in self.footer {
            w.line(line);
        }
        Ok(w.out)
    }

    fn error(&self, block: Option<usize>, message: String) -> NcError {
        NcError { dialect: self.name, block, message }
    }

    /// Every axis a move or the retract names is one the control has (NC31: X and Z).
    fn check_axes(&self, program: &Program) -> Result<(), NcError> {
        let foreign = |t: &Target| t.axes().map(|(l, _)| l).find(|l| !self.axes.contains(*l));
        let refuse = |block: Option<usize>, what: &str, axis: char| {
            let axes: Vec<String> = self.axes.chars().map(String::from).collect();
            self.error(
                block,
                format!("{what}names the {axis} axis, which the control does not have (its axes: {})", axes.join(" ")),
            )
        };
        for (i, b) in program.blocks.iter().enumerate() {
            let axis = match b {
                Block::Rapid(t) | Block::Line { to: t, .. } => foreign(t),
                Block::Arc { to, centre, .. } => foreign(to).or(foreign(centre)),
                _ => None,
            };
            if let Some(axis) = axis {
                return Err(refuse(Some(i + 1), "the move ", axis));
            }
        }
        match program.retract.as_ref().and_then(foreign) {
            Some(axis) => Err(refuse(None, "the retract position ", axis)),
            None => Ok(()),
        }
    }

    fn header(&self, w: &mut Writer, program: &Program) -> Result<(), String> {
        let name = match self.family {
            Family::Sinumerik => sinumerik_name(&program.name),
            _ => self.comment_text(&program.name),
        };
        for line in self.header {
            let line = match program.number {
                Some(n) if n > 9999 && self.family == Family::Fanuc => {
                    return Err(format!("program number {n} does not fit O0001–O9999"));
                }
                Some(n) => line.replace("{number:04}", &format!("{n:04}")),
                None => line.replace("O{number:04} ", ""),
            };
            w.line(&line.replace("{name}", &name));
        }
        Ok(())
    }

    /// Comment text in the control's character set, with nothing that ends the comment.
    fn comment_text(&self, text: &str) -> String {
        match self.family {
            // Old Fanuc tape readers take upper case, digits and a few signs; `(` `)` end or
            // nest a comment, `%` ends the tape, `,` `;` `:` are refused by some.
            Family::Fanuc => sanitise(text, true, |c| c.is_ascii_alphanumeric() || " .-+/*=#".contains(c)),
            // A comment ends at `)`; `;` starts another; `(MSG,` `(DEBUG,` `(LOGOPEN,` … are
            // commands when a comma follows their word, so commas go too.
            Family::LinuxCnc => sanitise(text, false, |c| !"();%,".contains(c)),
            Family::Sinumerik | Family::Nc31 => sanitise(text, false, |_| true),
        }
    }
}

/// A Sinumerik program name: letters, digits and `_`, the first two letters, at most 24.
fn sinumerik_name(name: &str) -> String {
    let n = program_name(name, 24);
    if n.chars().take(2).all(|c| c.is_ascii_alphabetic()) && n.len() >= 2 {
        n
    } else {
        program_name(&format!("NC{n}"), 24)
    }
}

struct Writer<'a> {
    d: &'a WordAddress,
    machine: Machine,
    /// The dialect's number style at the program's precision.
    numbers: NumberStyle,
    out: String,
    next: u32,
    position: Position,
    spindle_on: bool,
    coolant_on: bool,
    /// The tool last called: G41/G42 take its offset.
    tool: Option<ToolChange>,
    /// Chord tolerance for arcs on a control without circular interpolation, mm.
    arc_tolerance: f64,
    /// The D register of G41/G42 when it is not the tool's number.
    radius_offset: Option<u32>,
}

impl Writer<'_> {
    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn numbered(&mut self, text: &str) {
        let n = format!("N{:0width$}", self.next, width = self.d.block_width);
        self.next += self.d.block_step;
        if self.next >= 10u32.pow(self.d.block_digits) {
            self.next = self.d.block_step;
        }
        self.line(&format!("{n} {text}"));
    }

    fn number(&self, v: f64) -> String {
        self.numbers.write(v)
    }

    /// Moves the known position to `t` as printed: the control measures arc centre offsets
    /// from the start point it was given, not from the exact one.
    fn moved_to(&mut self, t: &Target) {
        let step = self.numbers.resolution();
        let printed = |v: Option<f64>| v.map(|v| (v / step).round() * step);
        self.position.apply(&Target {
            x: printed(t.x),
            y: printed(t.y),
            z: printed(t.z),
            a: printed(t.a),
            b: printed(t.b),
            c: printed(t.c),
        });
    }

    fn axes(&self, t: &Target) -> String {
        t.axes().map(|(l, v)| format!("{l}{}", self.number(v))).collect::<Vec<_>>().join(" ")
    }

    fn feed(&self, feed: Option<f64>) -> String {
        feed.map(|f| format!(" F{}", feed_style(self.numbers).write(f))).unwrap_or_default()
    }

    fn rapid(&mut self, t: &Target) {
        let text = match self.d.rapid_suffix {
            Some(suffix) => format!("{} {suffix}", self.axes(t)),
            None => format!("G0 {}", self.axes(t)),
        };
        self.numbered(&text);
        self.moved_to(t);
    }

    fn block(&mut self, block: &Block) -> Result<(), String> {
        match block {
            Block::FeedMode(mode) => {
                let word = self.feed_mode(*mode)?;
                if !word.is_empty() {
                    self.numbered(word);
                }
            }
            Block::Spindle(s) => self.spindle(s)?,
            Block::Tool(t) => self.tool(*t)?,
            Block::LengthOffset(o) => self.length_offset(*o)?,
            Block::Compensation(side) => self.compensation(*side)?,
            Block::Coolant(on) => {
                self.coolant_on = *on;
                let m = self.m(if *on { 8 } else { 9 });
                self.numbered(&m);
            }
            Block::Rapid(t) => self.rapid(t),
            Block::Line { to, feed } => {
                // NC31 cuts without a G word; a line with no axes only sets the feed (`G1 F100`).
                let g = if self.d.rapid_suffix.is_some() { "" } else { "G1" };
                let (axes, feed) = (self.axes(to), self.feed(*feed));
                let words = [g, &axes, feed.trim_start()];
                let text = words.iter().filter(|w| !w.is_empty()).copied().collect::<Vec<_>>().join(" ");
                self.numbered(&text);
                self.moved_to(to);
            }
            Block::Arc { direction, to, centre, feed } => self.arc(*direction, to, centre, *feed)?,
            Block::Dwell(s) => {
                let text = match self.d.family {
                    // Fanuc's P takes no decimal point: milliseconds.
                    Family::Fanuc => format!("G4 P{}", (s * 1000.0).round() as u64),
                    Family::LinuxCnc => format!("G4 P{}", self.number(*s)),
                    Family::Sinumerik => format!("G4 F{}", self.number(*s)),
                    Family::Nc31 => format!("G4 D{}", self.number(*s)),
                };
                self.numbered(&text);
            }
            Block::Comment(text) => self.comment(text),
            Block::Words(words) => self.words(words)?,
        }
        Ok(())
    }

    fn feed_mode(&self, mode: FeedMode) -> Result<&'static str, String> {
        let lathe = self.machine == Machine::Lathe;
        Ok(match (self.d.family, mode) {
            (Family::Fanuc, FeedMode::PerMinute) if lathe => "G98",
            (Family::Fanuc, FeedMode::PerRevolution) if lathe => "G99",
            (Family::Nc31, FeedMode::PerRevolution) => "",
            (Family::Nc31, FeedMode::PerMinute) => return Err("NC31 feeds per revolution only".into()),
            (_, FeedMode::PerMinute) => "G94",
            (_, FeedMode::PerRevolution) => "G95",
        })
    }

    /// An M word: NC31 writes two digits (`M02`, `M17` in docs/domain.md §2), the others one.
    fn m(&self, code: u32) -> String {
        if self.d.family == Family::Nc31 {
            format!("M{code:02}")
        } else {
            format!("M{code}")
        }
    }

    fn spindle(&mut self, s: &Spindle) -> Result<(), String> {
        let direction = match *s {
            Spindle::Rpm { direction, .. } | Spindle::SurfaceSpeed { direction, .. } => direction,
            Spindle::Stop => SpindleDirection::Clockwise,
        };
        let md = self.m(if direction == SpindleDirection::Clockwise { 3 } else { 4 });
        let lathe = self.machine == Machine::Lathe;
        let whole = |v: f64| format!("{}", v.round() as u64);
        match *s {
            Spindle::Stop => {
                self.spindle_on = false;
                let m5 = self.m(5);
                self.numbered(&m5);
                return Ok(());
            }
            Spindle::Rpm { rpm, .. } => {
                let g97 = if lathe && self.d.family != Family::Nc31 { "G97 " } else { "" };
                self.numbered(&format!("{g97}S{} {md}", whole(rpm)));
            }
            Spindle::SurfaceSpeed { metres_per_min, max_rpm, .. } => {
                let (v, max) = (whole(metres_per_min), whole(max_rpm));
                match self.d.family {
                    Family::Fanuc => {
                        self.numbered(&format!("G50 S{max}"));
                        self.numbered(&format!("G96 S{v} {md}"));
                    }
                    Family::LinuxCnc => self.numbered(&format!("G96 D{max} S{v} {md}")),
                    Family::Sinumerik => {
                        self.numbered(&format!("LIMS={max}"));
                        self.numbered(&format!("G96 S{v} {md}"));
                    }
                    Family::Nc31 => return Err("NC31 has no constant surface speed; give a speed in 1/min".into()),
                }
            }
        }
        self.spindle_on = true;
        Ok(())
    }

    fn compensation(&mut self, side: Compensation) -> Result<(), String> {
        let g = match side {
            Compensation::Off => "G40",
            Compensation::Left => "G41",
            Compensation::Right => "G42",
        };
        let cancelled = self.tool.is_some_and(|t| t.offset == ToolOffset::Cancelled);
        if self.d.family == Family::Sinumerik && side != Compensation::Off && cancelled {
            return Err("cutter compensation after D0: Sinumerik's D0 cancels the radius too".into());
        }
        if let (Family::Sinumerik, Some(d)) = (self.d.family, self.radius_offset) {
            if side != Compensation::Off {
                return Err(format!(
                    "no radius register D{d} apart from the tool: Sinumerik's D is the tool's cutting edge (T1 D2), \
                     which holds its length and radius together; give the tool's offset instead"
                ));
            }
        }
        let text = match (self.d.family, side, self.tool.map(|t| t.number)) {
            (Family::Nc31, Compensation::Off, _) => g.to_string(),
            (Family::Nc31, ..) => return Err("NC31 here writes no cutter radius compensation".into()),
            // Sinumerik takes the radius of the active T/D; the others name the offset.
            (Family::Sinumerik, ..) | (_, Compensation::Off, _) => g.to_string(),
            (_, _, Some(t)) => format!("{g} D{}", self.radius_offset.unwrap_or(t)),
            (_, _, None) => return Err("cutter compensation needs a tool called before it (Nc.Tool)".into()),
        };
        self.numbered(&text);
        Ok(())
    }

    /// The tool change and the offset it applies (docs/dialects.md): a Fanuc lathe's offset
    /// is the T word's last two digits (00 none), a Fanuc mill's and LinuxCNC's length is
    /// G43 [H] or cancelled by G49, Sinumerik's is the cutting edge D (D0 none).
    fn tool(&mut self, t: ToolChange) -> Result<(), String> {
        let n = t.number;
        self.tool = Some(t);
        let lathe = self.machine == Machine::Lathe;
        let text = match (self.d.family, t.offset) {
            (Family::Fanuc, offset) if lathe => {
                let o = match offset {
                    ToolOffset::Own => n,
                    ToolOffset::Number(o) => o,
                    ToolOffset::Cancelled => 0,
                };
                format!("T{n:02}{o:02}")
            }
            (Family::Fanuc, ToolOffset::Own) => format!("T{n} M6 G43 H{n}"),
            (Family::LinuxCnc, ToolOffset::Own) => format!("T{n} M6 G43"),
            (Family::Fanuc | Family::LinuxCnc, ToolOffset::Number(o)) => format!("T{n} M6 G43 H{o}"),
            (Family::Fanuc | Family::LinuxCnc, ToolOffset::Cancelled) => format!("T{n} M6 G49"),
            (Family::Sinumerik, offset) => {
                let d = match offset {
                    ToolOffset::Own => 1,
                    ToolOffset::Number(o) => o,
                    ToolOffset::Cancelled => 0,
                };
                let m6 = if lathe { "" } else { " M6" };
                format!("T{n}{m6} D{d}")
            }
            (Family::Nc31, ToolOffset::Own) => format!("T{n}"),
            (Family::Nc31, offset) => {
                return Err(format!(
                    "NC31 here writes T{n} with the tool's own offset only, not {offset:?}: the control's offset words \
                     are not documented to us"
                ));
            }
        };
        self.numbered(&text);
        Ok(())
    }

    /// Another length offset for the tool in the spindle, without changing it (the words of
    /// [`Writer::tool`] without the change).
    fn length_offset(&mut self, offset: ToolOffset) -> Result<(), String> {
        let Some(t) = self.tool.as_mut() else {
            return Err("a length offset with no tool called before it (Nc.Tool)".into());
        };
        t.offset = offset;
        let n = t.number;
        let register = match offset {
            ToolOffset::Own => n,
            ToolOffset::Number(o) => o,
            ToolOffset::Cancelled => 0,
        };
        let lathe = self.machine == Machine::Lathe;
        let text = match (self.d.family, offset) {
            // The turret's tool called again with the other offset: it does not index.
            (Family::Fanuc, _) if lathe => format!("T{n:02}{register:02}"),
            (Family::Fanuc | Family::LinuxCnc, ToolOffset::Cancelled) => "G49".into(),
            (Family::LinuxCnc, ToolOffset::Own) => "G43".into(),
            (Family::Fanuc | Family::LinuxCnc, _) => format!("G43 H{register}"),
            (Family::Sinumerik, ToolOffset::Own) => "D1".into(),
            (Family::Sinumerik, _) => format!("D{register}"),
            (Family::Nc31, _) => {
                return Err("NC31 here writes the tool's own offset with its T only (no offset words)".into())
            }
        };
        self.numbered(&text);
        Ok(())
    }

    /// The program frame's end: to the safe position in rapid, spindle and coolant off, end.
    fn end(&mut self, retract: Option<&Target>) {
        if let Some(t) = retract {
            self.rapid(t);
        }
        if self.spindle_on {
            let m = self.m(5);
            self.numbered(&m);
        }
        if self.coolant_on {
            let m = self.m(9);
            self.numbered(&m);
        }
        let end = self.d.end_block;
        self.numbered(end);
    }

    fn arc(&mut self, dir: ArcDirection, to: &Target, centre: &Target, feed: Option<f64>) -> Result<(), String> {
        if !self.d.has_arcs {
            // The control has no G2/G3: the arc as chords within the tolerance, each end on it.
            let start = self.position.target();
            let (tolerance, resolution) = (self.arc_tolerance, self.numbers.resolution());
            let points = arc_as_lines(self.machine, &start, to, centre, dir, tolerance, resolution)
                .map_err(|m| format!("{m} (the arc is written as lines on this control: --arc-tol)"))?;
            let format = Format { numbers: self.numbers, digits: self.d.digits };
            for (k, p) in points.iter().enumerate() {
                let line = Block::Line { to: *p, feed: if k == 0 { feed } else { None } };
                // A chord's end may lie where no end of the program did (an arc's bulge).
                check_values(&line, self.machine, format).map_err(|m| format!("the arc written as lines: {m}"))?;
                self.block(&line)?;
            }
            return Ok(());
        }
        let offsets = centre_offsets(self.machine, &self.position, centre)
            .ok_or("an arc needs a known start point and a centre in the working plane")?;
        let g = match dir {
            ArcDirection::Clockwise => "G2",
            ArcDirection::CounterClockwise => "G3",
        };
        let ij: Vec<String> = offsets.iter().map(|(l, v)| format!("{l}{}", self.number(*v))).collect();
        let text = format!("{g} {} {}{}", self.axes(to), ij.join(" "), self.feed(feed));
        self.numbered(&text);
        self.moved_to(to);
        Ok(())
    }

    fn comment(&mut self, text: &str) {
        let text = self.d.comment_text(text);
        match self.d.family {
            Family::Fanuc | Family::LinuxCnc => self.line(&format!("({text})")),
            Family::Sinumerik => self.line(&format!("; {text}")),
            // NC31 has no comment syntax: comments are left out.
            Family::Nc31 => {}
        }
    }

    fn words(&mut self, words: &[Word]) -> Result<(), String> {
        let mut text = Vec::new();
        for w in words {
            let letter = w.address.to_ascii_uppercase();
            if !self.d.legal.contains(letter) {
                return Err(format!("address {letter} is not a word this control reads (legal: {})", self.d.legal));
            }
            // Codes, tool and offset numbers and speeds are whole numbers on every control.
            let is_code = matches!(letter, 'G' | 'M' | 'T' | 'L' | 'D' | 'H' | 'S' | 'O') && w.value.fract() == 0.0;
            let value = match &w.typed {
                // Digits as typed keep a tool number's leading zeros (T0101: tool 1, offset 1).
                Some(t) if is_code && t.bytes().all(|b| b.is_ascii_digit()) => t.clone(),
                _ if is_code => format!("{}", w.value as i64),
                _ => self.number(w.value),
            };
            text.push(format!("{letter}{value}"));
        }
        self.numbered(&text.join(" "));
        Ok(())
    }
}
