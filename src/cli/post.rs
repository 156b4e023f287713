//! `ncsheet post`: an APT cutter-location file posted for a 5-axis mill with an (A,B) head
//! (docs/domain.md §4). Reading is `nc::apt`, the kinematics `nc::post`; this is flags and files.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use ncsheet::nc::post::{
    part_name, post_ab_head_traced, AbHead, PostOptions, DEFAULT_MAX_SWING, DEFAULT_SINGULAR_MARGIN,
};
use ncsheet::nc::{apt, dialect, Machine};

use super::output::emit;
use super::report::{Error, Result};

/// Post-process an APT cutter-location file (CLF) for a 5-axis mill with an (A,B) head.
///
/// Each GOTO/x,y,z,i,j,k (tool tip, unit tool axis; without i,j,k the axis is +Z) becomes
/// `G1 X… Y… Z… A… B…`: A = −asin(j), B = atan2(i, k), and X Y Z the head's pivot, H above the
/// tip along the axis, with H already held along Z by the machine zero (pivot = tip + H·axis −
/// H·k). Of the angle pairs that give the axis, the one inside the limits with B nearest the
/// previous block's is written, so B does not jump. RAPID, FEDRAT (mm/min), SPINDL, COOLNT,
/// LOADTL or LOAD/TOOL, SELECT/TOOL, CIRCLE (about Z; without its radius it runs through its
/// start), UNITS/MM or UNIT/MM, PARTNO, PPRINT, `$$` comments and `$` continuations are read;
/// any other record is an error naming its line and column.
///
/// Rounding: X Y Z and A B are written to d decimals (the dialect's, or --decimals), so the
/// tool tip and a ball's centre as the control places them lie within √3/2·10^−d +
/// H·π/180·10^−d mm of the file's: 7.9 µm for H = 400 mm and 3 decimals, 0.08 µm with
/// --decimals 5. post does not know the surface and keeps no reserve for it: a ball may cut
/// that much deeper than the file's path, so give enough decimals for the path's tolerance.
///
/// Refused with the record named: a tool axis within --singular degrees of the singular
/// position A = ±90°, angles outside --a-limits/--b-limits, a cutting move turning the head
/// more than --max-swing.
///
/// Example (the paper's table T8.1.4: a sphere's parallel, H = 400 mm):
/// ncsheet post sphere.cl --machine ab-head --pivot 400 --dialect iso -o sphere.nc
#[derive(Debug, Args)]
pub struct PostArgs {
    /// The cutter-location file (APT CL text, mm)
    pub file: PathBuf,
    /// The machine's kinematics
    #[arg(long, value_enum)]
    pub machine: MachineKind,
    /// Pivot length H: from the head's pivot to the tool tip (mm)
    #[arg(long, value_name = "H")]
    pub pivot: f64,
    /// The control's dialect (one that writes milling programs with A and B axes)
    #[arg(long, value_name = "D", value_parser = super::nc::dialect_parser(dialect::names()))]
    pub dialect: &'static dyn dialect::Dialect,
    /// The A axis's travel (degrees) [default: -90:90]
    #[arg(long, value_name = "MIN:MAX", value_parser = parse_range, allow_hyphen_values = true)]
    pub a_limits: Option<[f64; 2]>,
    /// The B axis's travel (degrees) [default: -180:180]
    #[arg(long, value_name = "MIN:MAX", value_parser = parse_range, allow_hyphen_values = true)]
    pub b_limits: Option<[f64; 2]>,
    /// Refuse tool axes with |A| within this many degrees of 90°, the singular position
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_SINGULAR_MARGIN)]
    pub singular: f64,
    /// The largest turn of A or B (degrees) in one cutting move
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_MAX_SWING)]
    pub max_swing: f64,
    /// Clearance height of the pivot for the approach and the end (mm)
    /// [default: highest tool tip + 5, whole mm]
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub clearance: Option<f64>,
    /// The tool to call when the file has no LOADTL before its first move
    #[arg(long, value_name = "T")]
    pub tool: Option<u32>,
    /// Digits after the point of every number (default: the dialect's): an angle rounded to
    /// 0.001° moves the tip by up to 3.5 µm at H = 400 mm
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(0..=9))]
    pub decimals: Option<u8>,
    /// Spindle speed (1/min, M3) when the file has no SPINDL before its first move
    #[arg(long, value_name = "S")]
    pub spindle: Option<f64>,
    /// Program name [default: the file's PARTNO, else OUT's name, else POST]
    #[arg(long)]
    pub name: Option<String>,
    /// Write here instead of to stdout
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Replace a read-only or hard-linked OUT
    #[arg(long, requires = "output")]
    pub force: bool,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MachineKind {
    /// A 5-axis mill whose head tilts by A about X, then by B about Y (docs/domain.md §4)
    AbHead,
}

fn parse_range(text: &str) -> std::result::Result<[f64; 2], String> {
    let (a, b) = text.split_once(':').ok_or_else(|| format!("'{text}' is not a range MIN:MAX"))?;
    let number = |s: &str| s.trim().parse::<f64>().map_err(|_| format!("'{s}' in '{text}' is not a number"));
    Ok([number(a)?, number(b)?])
}

pub fn run(args: PostArgs) -> Result<()> {
    let file = &args.file;
    if let Some(out) = &args.output {
        super::refuse_overwriting_inputs(&[file], &[out], "write the program to a new file")?;
    }
    // Every dialect is taken: one that cannot write the head's program is refused with the reason.
    let dialect = args.dialect;
    if !dialect.writes(Machine::Mill) {
        let able = dialect::names_for(Machine::Mill).join(", ");
        return Err(Error::User(format!(
            "--dialect {}: that control writes no milling programs, so no A and B axes; use one of {able}",
            dialect.name()
        )));
    }
    let text =
        std::fs::read_to_string(file).map_err(|e| Error::User(format!("{}: cannot read: {e}", file.display())))?;
    let in_file = |m: String| Error::User(format!("{}: {m}", file.display()));
    let records = apt::read(&text).map_err(|e| in_file(e.to_string()))?;
    let name = program_name(&args, part_name(&records));
    let (program, sources) =
        post_ab_head_traced(&records, &name, &options(&args)).map_err(|e| in_file(e.to_string()))?;
    // A block the dialect cannot write is named by the CL line it came from, which the user
    // can find; the block's place in the program is not in any file they have.
    let nc = dialect.render(&program).map_err(|e| match e.block.and_then(|b| sources.record_of(b)) {
        Some((line, word)) => in_file(format!("line {line} ({word}): the {} dialect: {}", e.dialect, e.message)),
        None => in_file(e.to_string()),
    })?;
    emit(&nc, args.output.as_deref(), args.force)
}

fn options(args: &PostArgs) -> PostOptions {
    let MachineKind::AbHead = args.machine;
    let mut head = AbHead::new(args.pivot);
    head.a_limits = args.a_limits.unwrap_or(head.a_limits);
    head.b_limits = args.b_limits.unwrap_or(head.b_limits);
    head.singular_margin = args.singular;
    head.max_swing = args.max_swing;
    PostOptions {
        head,
        clearance: args.clearance,
        tool: args.tool,
        spindle: args.spindle,
        decimals: args.decimals.map(usize::from),
    }
}

/// `--name`, the PARTNO, OUT's file stem, or POST.
fn program_name(args: &PostArgs, part: Option<&str>) -> String {
    if let Some(name) = args.name.as_deref().or(part) {
        return name.to_string();
    }
    let stem = args.output.as_deref().and_then(Path::file_stem).map(|s| s.to_string_lossy().to_string());
    stem.filter(|s| !s.is_empty()).unwrap_or_else(|| "POST".to_string())
}
