//! `ncsheet nc …`: NC programs as a control runs them (DOMAIN.md §4): the DDA interpolator's
//! table for one straight move.

use std::io::{self, Write};

use clap::{Args, Subcommand};
use ncsheet::nc::dda::{self, DdaRun};

use super::report::{Error, Result};

/// Run NC moves as a control does: the DDA interpolator's table.
#[derive(Debug, Args)]
pub struct NcArgs {
    #[command(subcommand)]
    pub command: NcCommand,
}

#[derive(Debug, Subcommand)]
pub enum NcCommand {
    Dda(DdaArgs),
}

/// Print the DDA linear interpolator's table for one straight move, clock by clock: each
/// axis's registers p and q and its pulses (the paper's table T8.1.1:
/// `nc dda --bits 4 --dx 16 --dy 8`).
#[derive(Debug, Args)]
pub struct DdaArgs {
    /// The move along X: in machine increments, or in mm when --increment is given
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dx: f64,
    /// The move along Y
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dy: f64,
    /// The move along Z (printed only when not 0)
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dz: f64,
    /// The machine increment in mm (e.g. 0.001); then --dx/--dy/--dz are in mm
    #[arg(long)]
    pub increment: Option<f64>,
    /// Bits n of each axis's adder (2ⁿ clocks); default: the smallest with 2ⁿ ≥ the longest move
    #[arg(long)]
    pub bits: Option<u32>,
}

pub fn run(args: NcArgs) -> Result<()> {
    match args.command {
        NcCommand::Dda(a) => dda_table(a),
    }
}

fn dda_table(args: DdaArgs) -> Result<()> {
    let user = |e: dda::DdaError| Error::User(e.to_string());
    let increment = args.increment.unwrap_or(1.0);
    let mut axes = vec![('X', args.dx), ('Y', args.dy)];
    if args.dz != 0.0 {
        axes.push(('Z', args.dz));
    }
    let mut deltas = Vec::new();
    for (letter, v) in &axes {
        let n = dda::increments(*v, increment)
            .map_err(|e| Error::User(format!("--d{}: {e}", letter.to_ascii_lowercase())))?;
        deltas.push(n);
    }
    let bits = args.bits.unwrap_or_else(|| dda::bits_for(&deltas));
    let run = dda::linear(bits, &deltas).map_err(user)?;
    let letters: Vec<char> = axes.iter().map(|a| a.0).collect();
    let mut out = io::BufWriter::new(io::stdout().lock());
    out.write_all(render(&run, &letters).as_bytes())?;
    out.flush()?;
    Ok(())
}

/// The table as the paper lays it out: clock, then per axis p, q (`16-16=0` on an overflow)
/// and the pulse; a last row with each axis's pulse count.
fn render(run: &DdaRun, letters: &[char]) -> String {
    let capacity = run.capacity();
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut head = vec!["clock".to_string()];
    for l in letters {
        head.extend([format!("{l} p"), format!("{l} q"), format!("{l} pulse")]);
    }
    rows.push(head);
    let mut start = vec!["0".to_string()];
    start.extend(letters.iter().flat_map(|_| ["0".to_string(), "0".to_string(), "0".to_string()]));
    rows.push(start);
    for clock in &run.clocks {
        let mut row = vec![clock.number.to_string()];
        for a in &clock.axes {
            let q = if a.pulse { format!("{}-{capacity}={}", a.sum, a.q) } else { a.q.to_string() };
            row.extend([a.p.to_string(), q, u8::from(a.pulse).to_string()]);
        }
        rows.push(row);
    }
    let mut total = vec!["pulses".to_string()];
    for n in run.pulses() {
        total.extend([String::new(), String::new(), n.to_string()]);
    }
    rows.push(total);
    let widths: Vec<usize> = (0..rows[0].len()).map(|c| rows.iter().map(|r| r[c].len()).max().unwrap_or(0)).collect();
    let mut text = format!("DDA: {} bits, 2^{} = {capacity} clocks\n", run.bits, run.bits);
    for row in rows {
        let cells: Vec<String> = row.iter().zip(&widths).map(|(s, w)| format!("{s:>w$}")).collect();
        text.push_str(cells.join("  ").trim_end());
        text.push('\n');
    }
    text
}
