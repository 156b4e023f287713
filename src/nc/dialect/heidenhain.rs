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

use super::{feed_style, finite_block, Dialect, NcError};
use crate::nc::format::NumberStyle;
use crate::nc::program::{ArcDirection, Block, Machine, Program, Target};

pub struct Heidenhain;

const NUMBERS: NumberStyle = NumberStyle { decimals: 4, plus_sign: true, trailing_zeros: true, always_point: false };
const FEEDS: NumberStyle = NumberStyle { decimals: 0, plus_sign: false, trailing_zeros: false, always_point: false };

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
        let numbers = NumberStyle { decimals: program.precision.unwrap_or(0).max(NUMBERS.decimals), ..NUMBERS };
        let axes = |t: &Target| t.axes().map(|(l, v)| format!("{l}{}", numbers.write(v))).collect::<Vec<_>>().join(" ");
        let name = program.name.replace(' ', "_");
        let mut lines = vec![format!("BEGIN PGM {name} MM")];
        for (i, block) in program.blocks.iter().enumerate() {
            if !finite_block(block) {
                return Err(error(Some(i + 1), "a number is not finite (NaN or infinity)".into()));
            }
            match block {
                Block::Rapid(t) => lines.push(format!("L {} FMAX", axes(t))),
                Block::Line { to, feed } => lines.push(format!("L {}{}", axes(to), feed_word(*feed))),
                Block::Arc { direction, to, centre, feed } => {
                    let (Some(cx), Some(cy)) = (centre.x, centre.y) else {
                        return Err(error(Some(i + 1), "an arc needs its centre's X and Y".into()));
                    };
                    lines.push(format!("CC X{} Y{}", numbers.write(cx), numbers.write(cy)));
                    let dr = match direction {
                        ArcDirection::CounterClockwise => "DR+",
                        ArcDirection::Clockwise => "DR-",
                    };
                    lines.push(format!("C {} {dr}{}", axes(to), feed_word(*feed)));
                }
                Block::Dwell(s) => {
                    lines.push(format!("CYCL DEF 9.0 DWELL TIME\nCYCL DEF 9.1 DWELL {}", FEEDS.write(*s)))
                }
                Block::Comment(text) => lines.push(format!("; {text}")),
                Block::Words(_) => {
                    return Err(error(Some(i + 1), "word-address blocks (G1 X…) do not exist in plain language".into()))
                }
            }
        }
        lines.push(format!("END PGM {name} MM"));
        let mut out = String::new();
        let mut n = 0;
        for line in lines {
            // A dwell cycle is two numbered blocks.
            for part in line.split('\n') {
                out.push_str(&format!("{n} {part}\n"));
                n += 1;
            }
        }
        Ok(out)
    }
}

fn feed_word(feed: Option<f64>) -> String {
    feed.map(|f| format!(" F{}", feed_style(FEEDS).write(f))).unwrap_or_default()
}
