//! Heidenhain plain language (Klartext), milling only:
//!
//! ```text
//! 0 BEGIN PGM BUMP MM
//! 1 BLK FORM 0.1 Z X-25.0000 Y-25.0000 Z+0.0000
//! 2 BLK FORM 0.2 X+25.0000 Y+25.0000 Z+15.0000
//! 3 TOOL CALL 1 Z S3000
//! 4 L Z+20.0000 R0 FMAX M3
//! 5 L X+0.5005 Y+25.0702 Z-2.4989 F480
//! 6 CC X+10.0000 Y+0.0000
//! 7 C X+10.0000 Y+5.0000 DR+ F200
//! 8 L Z+20.0000 R0 FMAX M5
//! 9 END PGM BUMP MM
//! ```
//!
//! Arcs are a `CC` block (absolute centre) followed by `C` with the end point and the
//! direction, `DR+` counter-clockwise and `DR-` clockwise. The spindle speed is part of
//! `TOOL CALL`; M functions (M3, M5, M8, M9) ride on the next positioning block, radius
//! compensation (RL, RR, R0) on the next straight line.

use std::fmt::Write;

use super::{check_program, feed_style, program_name, sanitise, Dialect, Format, NcError};
use crate::nc::format::NumberStyle;
use crate::nc::program::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolOffset,
};
use crate::nc::read::{self, ReadError};

pub struct Heidenhain;

/// The numbers the control reads (and the writer writes) of a program written to `precision`
/// decimals: a machine finer than the dialect's 0.1 µm default keeps its digits (never fewer).
pub(crate) fn format_for(precision: Option<usize>) -> Format {
    let numbers = NumberStyle { decimals: precision.unwrap_or(0).max(NUMBERS.decimals), ..NUMBERS };
    Format { numbers, digits: DIGITS.max(numbers.decimals + 5) }
}

/// `TOOL CALL n` always applies tool n's length from the tool table (L + DL): the TNC's
/// user's manual ("Tool length compensation") cancels it only by calling a tool of length 0
/// (`TOOL CALL 0`, the zero tool, which a tool changer takes as "empty spindle"), and a
/// program for a swivel head gives tool-tip coordinates under M128 / FUNCTION TCPM so that
/// the control's kinematics do the pivot. So a tool change with another offset register or
/// none is refused, naming the block, rather than cut with the table's length added.
fn own_offsets_only(program: &Program) -> Result<(), (usize, String)> {
    for (i, b) in program.blocks.iter().enumerate() {
        if let Block::Tool(t) = b {
            match t.offset {
                ToolOffset::Own => {}
                ToolOffset::Number(n) => {
                    return Err((
                        i + 1,
                        format!(
                            "TOOL CALL {} has no offset register {n}: it takes tool {}'s own data",
                            t.number, t.number
                        ),
                    ));
                }
                ToolOffset::Cancelled => {
                    return Err((
                        i + 1,
                        format!(
                            "this program's coordinates leave the tool length out, but TOOL CALL {} applies tool {}'s \
                             length from the tool table (only TOOL CALL 0, the empty spindle, has none); on a \
                             Heidenhain swivel head give tool-tip coordinates with M128/FUNCTION TCPM instead, or \
                             use a dialect that cancels the length (iso, linuxcnc, sinumerik)",
                            t.number, t.number
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

const NUMBERS: NumberStyle = NumberStyle { decimals: 4, plus_sign: true, trailing_zeros: true, always_point: false };
const FEEDS: NumberStyle = NumberStyle { decimals: 0, plus_sign: false, trailing_zeros: false, always_point: false };
/// Feeds per revolution (FU) and dwell times need decimals.
const FRACTIONS: NumberStyle =
    NumberStyle { decimals: 3, plus_sign: false, trailing_zeros: false, always_point: false };
/// Block numbers are whole numbers: the feed style writes them without `fmt`'s overhead.
const BLOCK_NUMBERS: NumberStyle = FEEDS;
/// ±99999.9999: the TNC's input range for coordinates.
const DIGITS: usize = 9;

impl Dialect for Heidenhain {
    fn name(&self) -> &'static str {
        "heidenhain"
    }

    fn resolution(&self) -> f64 {
        NUMBERS.resolution()
    }

    fn writes(&self, machine: Machine) -> bool {
        machine == Machine::Mill
    }

    fn read(&self, text: &str, machine: Option<Machine>) -> Result<(Program, Vec<usize>), ReadError> {
        read::heidenhain::read(text, machine)
    }

    fn render(&self, program: &Program) -> Result<String, NcError> {
        let error = |block: Option<usize>, message: String| NcError { dialect: "heidenhain", block, message };
        if program.machine != Machine::Mill {
            return Err(error(
                None,
                "plain language here is for milling programs; use iso or sinumerik for a lathe".into(),
            ));
        }
        let format = format_for(program.precision);
        let numbers = format.numbers;
        check_program(program, format).map_err(|(b, m)| error(b, m))?;
        own_offsets_only(program).map_err(|(b, m)| error(Some(b), m))?;
        if let Some(d) = program.radius_offset {
            return Err(error(
                None,
                format!(
                    "no radius register D{d} apart from the tool: RL/RR take the radius of the tool TOOL CALL \
                     named, from the tool table"
                ),
            ));
        }
        let name = program_name(&program.name, 24);
        let mut w = Numbered { out: String::with_capacity(48 * (program.blocks.len() + 2)), ..Numbered::default() };
        let _ = write!(w.block(), "BEGIN PGM {name} MM");
        if let Some((low, high)) = program.blank {
            let o = w.block();
            o.push_str("BLK FORM 0.1 Z ");
            axes(o, &Target::xyz(low[0], low[1], low[2]), &numbers);
            let o = w.block();
            o.push_str("BLK FORM 0.2 ");
            axes(o, &Target::xyz(high[0], high[1], high[2]), &numbers);
        }
        let blocks = &program.blocks;
        let mut i = 0;
        while i < blocks.len() {
            // A tool call takes the spindle speed that follows it, past feed-mode blocks (they
            // write nothing): one TOOL CALL, as the reader makes of it.
            let speed_at = i + 1 + blocks[i + 1..].iter().take_while(|b| matches!(b, Block::FeedMode(_))).count();
            if let (Block::Tool(t), Some(Block::Spindle(s))) = (&blocks[i], blocks.get(speed_at)) {
                for (k, b) in blocks.iter().enumerate().take(speed_at).skip(i + 1) {
                    w.write(b, &numbers).map_err(|m| error(Some(k + 1), m))?;
                }
                w.tool_call(Some(t.number), Some(s)).map_err(|m| error(Some(speed_at + 1), m))?;
                i = speed_at + 1;
                continue;
            }
            w.write(&blocks[i], &numbers).map_err(|m| error(Some(i + 1), m))?;
            i += 1;
        }
        // The frame's end: spindle and coolant off on the retract to the safe position.
        if w.spindle_on {
            w.pending.push_str(" M5");
        }
        if w.coolant_on {
            w.pending.push_str(" M9");
        }
        if let Some(t) = &program.retract {
            w.straight(t, &numbers, " FMAX", true);
        }
        if !w.pending.is_empty() {
            let pending = std::mem::take(&mut w.pending);
            let _ = write!(w.block(), "STOP{pending}");
        }
        let _ = write!(w.block(), "END PGM {name} MM");
        w.out.push('\n');
        Ok(w.out)
    }
}

/// The program text, written block by block into one string (a million-point program is
/// written without a string per block).
#[derive(Default)]
struct Numbered {
    out: String,
    n: u32,
    /// M functions waiting for the next positioning block (` M3`).
    pending: String,
    /// Radius compensation for the next straight line (`RL`, `RR`, `R0`).
    compensation: Option<&'static str>,
    per_revolution: bool,
    spindle_on: bool,
    coolant_on: bool,
}

impl Numbered {
    /// Ends the block before, starts the next one with its number, and returns the text to
    /// append the block to.
    fn block(&mut self) -> &mut String {
        if !self.out.is_empty() {
            self.out.push('\n');
        }
        BLOCK_NUMBERS.write_to(&mut self.out, self.n as f64);
        self.out.push(' ');
        self.n += 1;
        &mut self.out
    }

    fn write(&mut self, block: &Block, numbers: &NumberStyle) -> Result<(), String> {
        match block {
            Block::FeedMode(mode) => self.per_revolution = *mode == FeedMode::PerRevolution,
            Block::Tool(t) => self.tool_call(Some(t.number), None)?,
            // TOOL CALL applied the tool's own length already; there is no other.
            Block::LengthOffset(ToolOffset::Own) => {}
            Block::LengthOffset(o) => {
                return Err(format!(
                    "plain language has no length offset {o:?}: TOOL CALL always applies the tool's own length"
                ))
            }
            Block::Spindle(s) => self.tool_call(None, Some(s))?,
            Block::Coolant(on) => {
                self.coolant_on = *on;
                self.pending.push_str(if *on { " M8" } else { " M9" });
            }
            Block::Compensation(side) => {
                self.compensation = Some(match side {
                    Compensation::Off => "R0",
                    Compensation::Left => "RL",
                    Compensation::Right => "RR",
                });
            }
            Block::Rapid(t) => self.straight(t, numbers, " FMAX", false),
            Block::Line { to, feed } => {
                let f = self.feed_word(*feed);
                self.straight(to, numbers, &f, false);
            }
            Block::Arc { direction, to, centre, feed } => {
                let (Some(cx), Some(cy)) = (centre.x, centre.y) else {
                    return Err("an arc needs its centre's X and Y".into());
                };
                let o = self.block();
                o.push_str("CC ");
                axes(o, &Target::xy(cx, cy), numbers);
                let dr = match direction {
                    ArcDirection::CounterClockwise => "DR+",
                    ArcDirection::Clockwise => "DR-",
                };
                let f = self.feed_word(*feed);
                let pending = std::mem::take(&mut self.pending);
                let o = self.block();
                o.push_str("C ");
                axes(o, to, numbers);
                let _ = write!(o, " {dr}{f}{pending}");
            }
            // A dwell cycle is two numbered blocks.
            Block::Dwell(s) => {
                self.block().push_str("CYCL DEF 9.0 DWELL TIME");
                let o = self.block();
                o.push_str("CYCL DEF 9.1 DWELL ");
                FRACTIONS.write_to(o, *s);
            }
            Block::Comment(text) => {
                let text = sanitise(text, false, |_| true);
                let _ = write!(self.block(), "; {text}");
            }
            Block::Words(_) => return Err("word-address blocks (G1 X…) do not exist in plain language".into()),
        }
        Ok(())
    }

    /// `TOOL CALL 1 Z S3000` (a tool and its speed) or `TOOL CALL Z S3000` (a new speed);
    /// the direction (M3/M4) or the stop (M5) rides on the next positioning block.
    fn tool_call(&mut self, tool: Option<u32>, spindle: Option<&Spindle>) -> Result<(), String> {
        let speed = match spindle {
            None => None,
            Some(Spindle::Stop) => {
                self.spindle_on = false;
                self.pending.push_str(" M5");
                return tool.map_or(Ok(()), |n| self.tool_call(Some(n), None));
            }
            Some(Spindle::Rpm { rpm, direction }) => {
                self.spindle_on = true;
                let m = if *direction == SpindleDirection::Clockwise { " M3" } else { " M4" };
                self.pending.push_str(m);
                Some(rpm.round() as u64)
            }
            Some(Spindle::SurfaceSpeed { .. }) => return Err("constant surface speed is for lathes".into()),
        };
        let o = self.block();
        o.push_str("TOOL CALL ");
        if let Some(n) = tool {
            let _ = write!(o, "{n} ");
        }
        o.push('Z');
        if let Some(s) = speed {
            let _ = write!(o, " S{s}");
        }
        Ok(())
    }

    fn feed_word(&self, feed: Option<f64>) -> String {
        let Some(f) = feed else { return String::new() };
        let mut out = String::new();
        if self.per_revolution {
            out.push_str(" FU");
            FRACTIONS.write_to(&mut out, f);
        } else {
            out.push_str(" F");
            feed_style(FEEDS).write_to(&mut out, f);
        }
        out
    }

    /// `L X… Y… Z… [R0|RL|RR] F…|FMAX [M…]`; `frame` marks the program's own retract,
    /// which always cancels compensation.
    fn straight(&mut self, t: &Target, numbers: &NumberStyle, feed: &str, frame: bool) {
        let compensation = if frame { Some("R0") } else { self.compensation.take() };
        let pending = std::mem::take(&mut self.pending);
        let o = self.block();
        // `L F100` (no axes) only sets the feed.
        o.push_str(if *t == Target::default() { "L" } else { "L " });
        axes(o, t, numbers);
        if let Some(r) = compensation {
            o.push(' ');
            o.push_str(r);
        }
        o.push_str(feed);
        o.push_str(&pending);
    }
}

fn axes(out: &mut String, t: &Target, numbers: &NumberStyle) {
    for (i, (letter, v)) in t.axes().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        out.push(letter);
        numbers.write_to(out, v);
    }
}
