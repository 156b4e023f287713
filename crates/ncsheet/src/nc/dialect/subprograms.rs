//! NC31 cycles written once as subprograms and called per use (docs/domain.md §2, "Calls
//! with values"): which uses a program marks and whether they can be written, the call and
//! header blocks, and the check that the written program, its subprograms run, moves as the
//! unrolled one does. The writing itself is `WordAddress::render_with_subprograms`.

use crate::nc::program::{Block, Machine, Program, Subprogram, SubprogramCall};
use crate::nc::read;

use super::Family;

/// A use of a subprogram that can be written: its blocks `first..end`, never empty.
pub(super) struct Call<'a> {
    pub first: usize,
    pub end: usize,
    pub values: &'a [f64],
    pub subprogram: &'a Subprogram,
}

/// The program's uses of its subprograms in block order, each closed, inside the program,
/// apart from the others and giving its subprogram one value per parameter; the error names
/// the 1-based block where the use starts.
pub(super) fn checked_calls(program: &Program) -> Result<Vec<Call<'_>>, (Option<usize>, String)> {
    for (i, s) in program.subprograms.iter().enumerate() {
        if program.subprograms[..i].iter().any(|t| t.number == s.number) {
            return Err((None, format!("subprogram L{:02} is given twice", s.number)));
        }
    }
    let mut uses: Vec<&SubprogramCall> = program.calls.iter().collect();
    uses.sort_by_key(|c| c.first);
    let mut calls: Vec<Call<'_>> = Vec::new();
    for u in uses {
        let at = |m: String| (Some(u.first + 1), format!("L{:02}: {m}", u.number));
        let end = u.end.ok_or_else(|| at("its use (Nc.Cycle) is not closed (Nc.EndCycle)".into()))?;
        if u.first >= end || end > program.blocks.len() {
            return Err(at("its use encloses no block of the program".into()));
        }
        if let Some(before) = calls.last().filter(|c| c.end > u.first) {
            return Err(at(format!("its use starts inside the use of L{:02} before it", before.subprogram.number)));
        }
        let subprogram = program
            .subprograms
            .iter()
            .find(|s| s.number == u.number)
            .ok_or_else(|| at("it is used but not written (no Nc.Subprogram for it)".into()))?;
        if u.values.len() != subprogram.parameters.len() {
            let letters: Vec<String> = subprogram.parameters.iter().map(|(l, _)| l.to_string()).collect();
            return Err(at(format!(
                "it takes {} values ({}), its use gives {}",
                letters.len(),
                letters.join(" "),
                u.values.len()
            )));
        }
        if let Some(v) = u.values.iter().find(|v| !v.is_finite()) {
            return Err(at(format!("{v} is no value for a parameter")));
        }
        calls.push(Call { first: u.first, end, values: &u.values, subprogram });
    }
    Ok(calls)
}

/// The subprograms to write after the program's end: each the calls use, once, in the order
/// first used, and after them those their blocks call (L17's `L03`), so that every call the
/// control makes finds its subprogram.
pub(super) fn written<'a>(program: &'a Program, calls: &[Call<'a>]) -> Result<Vec<&'a Subprogram>, String> {
    let mut out: Vec<&Subprogram> = Vec::new();
    let add = |s: &'a Subprogram, out: &mut Vec<&'a Subprogram>| {
        if !out.iter().any(|w| w.number == s.number) {
            out.push(s);
        }
    };
    for call in calls {
        add(call.subprogram, &mut out);
    }
    let mut i = 0;
    while let Some(caller) = out.get(i).copied() {
        for n in caller.body.iter().filter_map(|line| read::nc31_called(line)) {
            let callee = program.subprograms.iter().find(|s| s.number == n).ok_or_else(|| {
                format!("L{:02} calls L{n:02}, which is not written (no Nc.Subprogram for it)", caller.number)
            })?;
            add(callee, &mut out);
        }
        i += 1;
    }
    Ok(out)
}

/// The header block: `L16 XR1 WR2 …`.
pub(super) fn header(subprogram: &Subprogram) -> String {
    let mut text = format!("L{:02}", subprogram.number);
    for (letter, r) in &subprogram.parameters {
        text.push_str(&format!(" {letter}R{r}"));
    }
    text
}

/// The call block: `L16 X30 W40 …`, each value written by `number`; refused when a value
/// as written is not the value (more decimals than the control's), which the subprogram
/// would run with instead.
pub(super) fn call(call: &Call<'_>, number: impl Fn(f64) -> String) -> Result<String, String> {
    let mut text = format!("L{:02}", call.subprogram.number);
    for ((letter, _), v) in call.subprogram.parameters.iter().zip(call.values) {
        let written = number(*v);
        if !written.parse::<f64>().is_ok_and(|w| (w - v).abs() <= 1e-9 * v.abs().max(1.0)) {
            return Err(format!(
                "L{:02}'s {letter} is {v}, which the control's words write as {letter}{written}",
                call.subprogram.number
            ));
        }
        text.push_str(&format!(" {letter}{written}"));
    }
    Ok(text)
}

/// What a block does to the machine, as the comparison sees it: a move with the position it
/// ends at and the feed in force, a dwell, or any other block as it reads.
#[derive(Debug, PartialEq)]
enum Step {
    Move { rapid: bool, x: Option<f64>, z: Option<f64>, feed: Option<f64> },
    Dwell(f64),
    Other(Block),
}

/// The program's steps, each with its 1-based source line; a line that moves nowhere and
/// only sets the feed is in the feed of the moves after it.
fn steps(program: &Program, lines: &[usize]) -> Vec<(Step, usize)> {
    let (mut x, mut z, mut feed) = (None, None, None);
    let mut out = Vec::new();
    for (i, block) in program.blocks.iter().enumerate() {
        let line = lines.get(i).copied().unwrap_or(0);
        let (rapid, to) = match block {
            Block::Rapid(to) => (true, to),
            Block::Line { to, feed: f } => {
                feed = f.or(feed);
                (false, to)
            }
            Block::Dwell(s) => {
                out.push((Step::Dwell(*s), line));
                continue;
            }
            other => {
                out.push((Step::Other(other.clone()), line));
                continue;
            }
        };
        if to.x.is_none() && to.z.is_none() {
            continue;
        }
        x = to.x.or(x);
        z = to.z.or(z);
        out.push((Step::Move { rapid, x, z, feed: if rapid { None } else { feed } }, line));
    }
    out
}

fn describe(step: Option<&Step>) -> String {
    let at = |v: Option<f64>| v.map_or("?".to_string(), |v| format!("{v}"));
    match step {
        Some(Step::Move { rapid: true, x, z, .. }) => format!("moves in rapid to X{} Z{}", at(*x), at(*z)),
        Some(Step::Move { x, z, feed, .. }) => format!("cuts to X{} Z{} at F{}", at(*x), at(*z), at(*feed)),
        Some(Step::Dwell(s)) => format!("dwells {s} s"),
        Some(Step::Other(b)) => format!("has {b:?}"),
        None => "has ended".into(),
    }
}

/// Whether `called`, read back with its subprograms run as the control runs them, moves,
/// dwells and sets the machine as `flat` does, block for block.
pub(super) fn same_motion(flat: &str, called: &str) -> Result<(), String> {
    let read = |text: &str| read::read_with_lines(text, Family::Nc31, Some(Machine::Lathe));
    let (flat, flat_lines) = read(flat).map_err(|e| format!("the unrolled program does not read back: {e}"))?;
    let (called, called_lines) =
        read(called).map_err(|e| format!("the program with subprograms does not read back: {e}"))?;
    let (want, got) = (steps(&flat, &flat_lines), steps(&called, &called_lines));
    let first_difference =
        (0..want.len().max(got.len())).find(|&k| want.get(k).map(|s| &s.0) != got.get(k).map(|s| &s.0));
    let Some(k) = first_difference else { return Ok(()) };
    let line = got.get(k).or(got.last()).map_or(0, |s| s.1);
    Err(format!(
        "the program with subprograms, run as the control runs it, does not do what the blocks marked for them do: \
         at its line {line} it {}, where the unrolled program (line {}) {}",
        describe(got.get(k).map(|s| &s.0)),
        want.get(k).or(want.last()).map_or(0, |s| s.1),
        describe(want.get(k).map(|s| &s.0)),
    ))
}
