//! The word-address writer (DIN 66025 / ISO 6983 / RS-274D) shared by ISO/Fanuc, LinuxCNC,
//! Sinumerik and the old NC31 lathe control; each is one [`WordAddress`] table.

use super::{centre_offsets, feed_style, finite_block, Dialect, NcError, Position};
use crate::nc::format::NumberStyle;
use crate::nc::program::{ArcDirection, Block, Machine, Program, Target, Word};

/// How one word-address control writes a program.
pub struct WordAddress {
    pub name: &'static str,
    pub numbers: NumberStyle,
    /// `N10`, `N20`, … (`width` pads with zeros: NC31's `N001`).
    pub block_step: u32,
    pub block_width: usize,
    /// Lines before the first block; `{name}` and `{number}` are replaced.
    pub header: &'static [&'static str],
    /// Modal set-up written as the first numbered block, per machine.
    pub setup_lathe: Option<&'static str>,
    pub setup_mill: Option<&'static str>,
    /// Blocks and lines after the last block.
    pub end_block: &'static str,
    pub footer: &'static [&'static str],
    /// `(text)` or `; text`; `None` drops comments (the control has no comment syntax).
    pub comment: Option<CommentStyle>,
    /// NC31 marks a rapid with `E` after the coordinates instead of `G0`.
    pub rapid_suffix: Option<&'static str>,
    pub has_arcs: bool,
    pub machines: &'static [Machine],
    /// Addresses a raw block may use.
    pub legal: &'static str,
}

#[derive(Clone, Copy)]
pub enum CommentStyle {
    Parentheses,
    Semicolon,
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
    numbers: FANUC_NUMBERS,
    block_step: 10,
    block_width: 0,
    header: &["%", "O{number:04} ({name})"],
    setup_lathe: Some("G21 G18 G90 G40"),
    setup_mill: Some("G21 G17 G90 G40"),
    end_block: "M30",
    footer: &["%"],
    comment: Some(CommentStyle::Parentheses),
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    legal: "NGMXYZABCIJKRFSTDHPQUVWLO",
};

/// RS-274NGC as LinuxCNC reads it: no O-number (O-words are subroutines there), diameter
/// mode `G7` on a lathe.
pub const LINUXCNC: WordAddress = WordAddress {
    name: "linuxcnc",
    numbers: PLAIN_NUMBERS,
    block_step: 10,
    block_width: 0,
    header: &["%", "({name})"],
    setup_lathe: Some("G21 G18 G7 G90 G40"),
    setup_mill: Some("G21 G17 G90 G40"),
    end_block: "M2",
    footer: &["%"],
    comment: Some(CommentStyle::Parentheses),
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    legal: "NGMXYZABCIJKRFSTDHPQUVWL",
};

/// Siemens Sinumerik: `%_N_NAME_MPF` archive header, `; comments`, `DIAMON` on a lathe.
pub const SINUMERIK: WordAddress = WordAddress {
    name: "sinumerik",
    numbers: PLAIN_NUMBERS,
    block_step: 10,
    block_width: 0,
    header: &["%_N_{name}_MPF", ";$PATH=/_N_MPF_DIR"],
    setup_lathe: Some("G18 DIAMON G90 G71"),
    setup_mill: Some("G17 G90 G71"),
    end_block: "M30",
    footer: &[],
    comment: Some(CommentStyle::Semicolon),
    rapid_suffix: None,
    has_arcs: true,
    machines: &[Machine::Lathe, Machine::Mill],
    legal: "NGMXYZABCIJKFSTDHPQUVWL",
};

/// Elektronika NC31 (DOMAIN.md §2): `N001 X34 Z-60 E`, rapid marked `E`, `M02` at the end.
pub const NC31: WordAddress = WordAddress {
    name: "nc31",
    numbers: PLAIN_NUMBERS,
    block_step: 1,
    block_width: 3,
    header: &[],
    setup_lathe: None,
    setup_mill: None,
    end_block: "M02",
    footer: &[],
    comment: None,
    rapid_suffix: Some("E"),
    has_arcs: false,
    machines: &[Machine::Lathe],
    legal: "NGMXZUWFSTLDPARQ",
};

impl Dialect for WordAddress {
    fn name(&self) -> &'static str {
        self.name
    }

    fn resolution(&self) -> f64 {
        self.numbers.resolution()
    }

    fn render(&self, program: &Program) -> Result<String, NcError> {
        if !self.machines.contains(&program.machine) {
            return Err(self.error(None, format!("writes no {:?} programs", program.machine).to_lowercase()));
        }
        let numbers = NumberStyle { decimals: program.precision.unwrap_or(self.numbers.decimals), ..self.numbers };
        let mut w =
            Writer { d: self, numbers, out: String::new(), next: self.block_step, position: Position::default() };
        for line in self.header {
            let line = match program.number {
                Some(n) => line.replace("{number:04}", &format!("{n:04}")),
                None => line.replace("O{number:04} ", ""),
            };
            w.line(&line.replace("{name}", &program.name));
        }
        let setup = match program.machine {
            Machine::Lathe => self.setup_lathe,
            Machine::Mill => self.setup_mill,
        };
        if let Some(s) = setup {
            w.numbered(s);
        }
        for (i, block) in program.blocks.iter().enumerate() {
            w.block(program.machine, block).map_err(|m| self.error(Some(i + 1), m))?;
        }
        w.numbered(self.end_block);
        for line in self.footer {
            w.line(line);
        }
        Ok(w.out)
    }
}

impl WordAddress {
    fn error(&self, block: Option<usize>, message: String) -> NcError {
        NcError { dialect: self.name, block, message }
    }
}

struct Writer<'a> {
    d: &'a WordAddress,
    /// The dialect's number style at the program's precision.
    numbers: NumberStyle,
    out: String,
    next: u32,
    position: Position,
}

impl Writer<'_> {
    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn numbered(&mut self, text: &str) {
        let n = format!("N{:0width$}", self.next, width = self.d.block_width);
        self.next += self.d.block_step;
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

    fn block(&mut self, machine: Machine, block: &Block) -> Result<(), String> {
        if !finite_block(block) {
            return Err("a number is not finite (NaN or infinity)".into());
        }
        match block {
            Block::Rapid(t) => {
                let text = match self.d.rapid_suffix {
                    Some(suffix) => format!("{} {suffix}", self.axes(t)),
                    None => format!("G0 {}", self.axes(t)),
                };
                self.numbered(&text);
                self.moved_to(t);
            }
            Block::Line { to, feed } => {
                let g = if self.d.rapid_suffix.is_some() { "" } else { "G1 " };
                let text = format!("{g}{}{}", self.axes(to), self.feed(*feed));
                self.numbered(&text);
                self.moved_to(to);
            }
            Block::Arc { direction, to, centre, feed } => self.arc(machine, *direction, to, centre, *feed)?,
            Block::Dwell(s) => {
                let text = format!("G4 {}{}", if self.d.name == "nc31" { "D" } else { "P" }, self.number(*s));
                self.numbered(&text);
            }
            Block::Comment(text) => self.comment(text),
            Block::Words(words) => self.words(words)?,
        }
        Ok(())
    }

    fn arc(
        &mut self,
        machine: Machine,
        dir: ArcDirection,
        to: &Target,
        centre: &Target,
        feed: Option<f64>,
    ) -> Result<(), String> {
        if !self.d.has_arcs {
            return Err("this control has no circular interpolation; write the arc as lines".into());
        }
        let offsets = centre_offsets(machine, &self.position, centre)
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
        match self.d.comment {
            // Fanuc and LinuxCNC end a comment at the first `)`; nested ones would cut it short.
            Some(CommentStyle::Parentheses) => self.line(&format!("({})", text.replace(['(', ')'], ""))),
            Some(CommentStyle::Semicolon) => self.line(&format!("; {text}")),
            None => {}
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
            let value = if is_code { format!("{}", w.value as i64) } else { self.number(w.value) };
            text.push(format!("{letter}{value}"));
        }
        self.numbered(&text.join(" "));
        Ok(())
    }
}
