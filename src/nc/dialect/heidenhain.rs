//! Heidenhain plain language (Klartext), milling only:
//!
//! ```text
//! 0 BEGIN PGM BUMP MM
//! 1 L X+0.5005 Y+25.0702 Z-2.4989 F480
//! 2 L Z+5.0000 FMAX
//! 3 CC X+10.0000 Y+0.0000
//! 4 C X+10.0000 Y+5.0000 DR+ F200
//! 5 END PGM BUMP MM
//! ```
//!
//! Arcs are a `CC` block (absolute centre) followed by `C` with the end point and the
//! direction, `DR+` counter-clockwise and `DR-` clockwise.

use std::fmt::Write;

use super::{feed_style, finite_block, Dialect, NcError};
use crate::nc::format::NumberStyle;
use crate::nc::program::{ArcDirection, Block, Machine, Program, Target};

pub struct Heidenhain;

const NUMBERS: NumberStyle = NumberStyle { decimals: 4, plus_sign: true, trailing_zeros: true, always_point: false };
const FEEDS: NumberStyle = NumberStyle { decimals: 0, plus_sign: false, trailing_zeros: false, always_point: false };
/// Block numbers are whole numbers: the feed style writes them without `fmt`'s overhead.
const BLOCK_NUMBERS: NumberStyle = FEEDS;

impl Dialect for Heidenhain {
    fn name(&self) -> &'static str {
        "heidenhain"
    }

    fn resolution(&self) -> f64 {
        NUMBERS.resolution()
    }

    fn render(&self, program: &Program) -> Result<String, NcError> {
        let error = |block: Option<usize>, message: String| NcError { dialect: "heidenhain", block, message };
        if program.machine != Machine::Mill {
            return Err(error(
                None,
                "plain language here is for milling programs; use iso or sinumerik for a lathe".into(),
            ));
        }
        // A machine finer than the dialect's 0.1 µm default keeps its digits (never fewer).
        let numbers = NumberStyle { decimals: program.precision.unwrap_or(0).max(NUMBERS.decimals), ..NUMBERS };
        let name = program.name.replace(' ', "_");
        let mut w = Numbered { out: String::with_capacity(48 * (program.blocks.len() + 2)), n: 0 };
        let _ = write!(w.block(), "BEGIN PGM {name} MM");
        for (i, block) in program.blocks.iter().enumerate() {
            if !finite_block(block) {
                return Err(error(Some(i + 1), "a number is not finite (NaN or infinity)".into()));
            }
            match block {
                Block::Rapid(t) => {
                    let o = w.block();
                    o.push_str("L ");
                    axes(o, t, &numbers);
                    o.push_str(" FMAX");
                }
                Block::Line { to, feed } => {
                    let o = w.block();
                    o.push_str("L ");
                    axes(o, to, &numbers);
                    feed_word(o, *feed);
                }
                Block::Arc { direction, to, centre, feed } => {
                    let (Some(cx), Some(cy)) = (centre.x, centre.y) else {
                        return Err(error(Some(i + 1), "an arc needs its centre's X and Y".into()));
                    };
                    let o = w.block();
                    o.push_str("CC ");
                    axes(o, &Target::xy(cx, cy), &numbers);
                    let dr = match direction {
                        ArcDirection::CounterClockwise => "DR+",
                        ArcDirection::Clockwise => "DR-",
                    };
                    let o = w.block();
                    o.push_str("C ");
                    axes(o, to, &numbers);
                    let _ = write!(o, " {dr}");
                    feed_word(o, *feed);
                }
                // A dwell cycle is two numbered blocks.
                Block::Dwell(s) => {
                    w.block().push_str("CYCL DEF 9.0 DWELL TIME");
                    let o = w.block();
                    o.push_str("CYCL DEF 9.1 DWELL ");
                    FEEDS.write_to(o, *s);
                }
                Block::Comment(text) => {
                    let _ = write!(w.block(), "; {text}");
                }
                Block::Words(_) => {
                    return Err(error(Some(i + 1), "word-address blocks (G1 X…) do not exist in plain language".into()))
                }
            }
        }
        let _ = write!(w.block(), "END PGM {name} MM");
        w.out.push('\n');
        Ok(w.out)
    }
}

/// The program text, written block by block into one string (a million-point program is
/// written without a string per block).
struct Numbered {
    out: String,
    n: u32,
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

fn feed_word(out: &mut String, feed: Option<f64>) {
    if let Some(f) = feed {
        out.push_str(" F");
        feed_style(FEEDS).write_to(out, f);
    }
}
