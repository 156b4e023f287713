//! `ncsheet nc check`: what a program would do wrong, each finding with its line (the checks
//! are `nc::check`'s; this reads the program and prints them).

use std::io::{self, Write};
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use ncsheet::nc::check::{self, CheckOptions, ARC_TOLERANCE_MM};

use super::nc::{read_program, MachineArg, ReadDialect};
use super::report::{Error, Result};

/// Check a program before it runs: arc ends on their circles within --tol, a feed mode,
/// a feed, a turning spindle and a tool before the first cut, cuts from a known position, no
/// move below --min-z, no rapid through --stock and no cut below its bottom. Prints one line
/// per finding (`PROGRAM:LINE: message`); exit status 1 when anything is found, 0 when clean.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The NC program (text as the dialect writes it)
    pub program: PathBuf,
    /// The control the program is written for; default: what its header, extension
    /// (.ngc, .mpf, .h, …) or words tell, else iso
    #[arg(long, value_enum)]
    pub dialect: Option<ReadDialect>,
    /// What the program is for; default: a lathe when G18 comes before the first move
    #[arg(long, value_enum)]
    pub machine: Option<MachineArg>,
    /// Lowest Z any move may reach, mm
    #[arg(long, allow_hyphen_values = true)]
    pub min_z: Option<f64>,
    /// The stock box, xmin,ymin,zmin,xmax,ymax,zmax in mm (X a diameter on a lathe, Y unused
    /// there): no rapid may pass through it, no cut go below its bottom
    #[arg(long, value_name = "X0,Y0,Z0,X1,Y1,Z1", allow_hyphen_values = true)]
    pub stock: Option<String>,
    /// The control's tool table (LinuxCNC .tbl: `T1 P1 D10 Z50`): cutter compensation entry
    /// moves are checked against each tool's radius as LinuxCNC checks them
    #[arg(long, value_name = "FILE.tbl")]
    pub tool_table: Option<PathBuf>,
    /// The units of the tool table's diameters (a stand-alone rs274 reads its table in inches)
    #[arg(long, value_enum, default_value_t = TableUnits::Mm)]
    pub table_units: TableUnits,
    /// How far an arc's end may lie off the circle through its start, mm (ncsheet's writers
    /// keep within 0.002 mm; LinuxCNC 2.9 refuses past 0.0283 mm and 0.1 % of the radius)
    // `--tolerance`: the option's first name, kept for the scripts that use it.
    #[arg(long = "tol", alias = "tolerance", value_name = "MM", default_value_t = ARC_TOLERANCE_MM)]
    pub tolerance: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TableUnits {
    Mm,
    Inch,
}

pub fn run(args: CheckArgs) -> Result<()> {
    if !(args.tolerance.is_finite() && args.tolerance >= 0.0) {
        return Err(Error::Usage(format!("--tol is a length in mm from 0 up, not {}", args.tolerance)));
    }
    if let Some(z) = args.min_z.filter(|z| !z.is_finite()) {
        return Err(Error::Usage(format!("--min-z is a length in mm, not {z}")));
    }
    let stock = args.stock.as_deref().map(parse_stock).transpose()?;
    let (program, lines, name, dialect) = read_program(&args.program, args.dialect, args.machine)?;
    let power_on_feed_mode = check::power_on_feed_mode(dialect, program.machine);
    let tool_diameters = match &args.tool_table {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| Error::User(format!("{}: {e}", path.display())))?;
            let scale = if args.table_units == TableUnits::Inch { 25.4 } else { 1.0 };
            check::read_tool_table(&text)
                .map_err(|e| Error::User(format!("{}: {e}", path.display())))?
                .into_iter()
                .map(|(t, d)| (t, d * scale))
                .collect()
        }
        None => Vec::new(),
    };
    let options = CheckOptions {
        tolerance: args.tolerance,
        min_z: args.min_z,
        stock,
        tool_diameters: &tool_diameters,
        power_on_feed_mode,
    };
    let line_of = |block: usize| lines.get(block - 1).copied().unwrap_or(0);
    let findings = check::check(&program, &options).map_err(|e| {
        let at = e.block.map(|b| format!(":{}", line_of(b))).unwrap_or_default();
        Error::User(format!("{name}{at}: {}", e.message))
    })?;
    let mut out = io::BufWriter::new(io::stdout().lock());
    for f in &findings {
        writeln!(out, "{name}:{}: {}", line_of(f.block), f.message)?;
    }
    out.flush()?;
    match findings.len() {
        0 => Ok(()),
        n => Err(Error::User(format!("{name}: {n} finding{}", if n == 1 { "" } else { "s" }))),
    }
}

/// `xmin,ymin,zmin,xmax,ymax,zmax`, each min below its max.
fn parse_stock(text: &str) -> Result<([f64; 3], [f64; 3])> {
    let bad = |why: String| Error::Usage(format!("--stock {text}: {why}"));
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            v.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| bad(format!("`{v}` is not a number")))
        })
        .collect::<Result<_>>()?;
    let [x0, y0, z0, x1, y1, z1] = values[..] else {
        return Err(bad(format!("six numbers xmin,ymin,zmin,xmax,ymax,zmax, not {}", values.len())));
    };
    for (axis, lo, hi) in [('X', x0, x1), ('Y', y0, y1), ('Z', z0, z1)] {
        if lo >= hi {
            return Err(bad(format!("{axis} from {lo} to {hi} is empty")));
        }
    }
    Ok(([x0, y0, z0], [x1, y1, z1]))
}
