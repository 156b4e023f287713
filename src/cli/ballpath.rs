//! `ncsheet ballpath`: a ball-end mill's finishing path over a surface formula, written as csv
//! or as an NC program (docs/domain.md §3). The path itself is `geometry::ballpath`, run on the
//! formula by `eval::functions::formula_ball_path`; this is flags, output and timing.

use std::fmt::Write as _;
use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::{ArgGroup, Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use ncsheet::eval::functions::{describe_gouge, standalone_ball_path, PathFailure};
use ncsheet::eval::surface::parse_standalone;
use ncsheet::geometry::ballpath::{
    BallPath, BallPathSpec, Direction, GougeCheck, GougeKind, Lines, Spacing, Written, GOUGE_SAMPLES, GOUGE_TOLERANCE,
};
use ncsheet::io::Encoded;
use ncsheet::nc::ballpath::{ball_path_cl, ball_path_program, BallPathNcOptions, ProgrammedPoint};
use ncsheet::nc::{apt, dialect, Dialect, Machine};

use super::output::emit;
use super::report::{prepend, Error, Result};

/// Compute a ball-end mill's finishing path over a surface z = f(x, y) and write it as csv or
/// as an NC program.
///
/// The path is a zig-zag raster over the rectangle --x × --y: lines of constant x (or y with
/// --lines y) --stepover apart, the last one on the far edge, each running the full width with
/// both edges included, alternating direction (or one way with --direction climb or
/// conventional, retracting between lines); points --step apart along a line (with
/// --tol: as few as keep the programmed polyline within the tolerance of the tool path,
/// --step apart at most). At each contact point T the ball's centre is T + R·n with n the
/// outward unit normal, from exact partial derivatives of the formula. The programmed point
/// is the ball's tip (centre − R in z) unless --program centre.
///
/// Every ball position and every straight move between two is checked against the surface by
/// an exact drop-cutter: one that would cut the surface by more than --gouge-tol (a hollow
/// tighter than R, a steep wall, a chord across a dome) fails the command with where and how
/// deep, unless --gouge lift raises the ball to the drop-cutter height and inserts points
/// where a move dips.
///
/// Example (the paper's Gaussian bump on a 50 × 50 mm part, 3 mm ball):
/// ncsheet ballpath --surface "15*EXP(-16*((x/50)^2+(y/50)^2))" --radius 3 --x -25:25
/// --y -25:25 --stepover 1 --step 1 --format heidenhain -o bump.h
///
/// Excel's precedence applies: -x^2 is (-x)^2; write -(x^2). docs/ballpath.md has the rules
/// for differentiating the formula and the gouge check.
#[derive(Debug, Args)]
#[command(group(ArgGroup::new("written").args(["output", "cl"]).multiple(true)))]
pub struct BallpathArgs {
    /// The surface: a formula in x and y such as "0.3*EXP(-16*(x^2+y^2))", or LAMBDA(x, y, …)
    #[arg(long, value_name = "EXPR", allow_hyphen_values = true)]
    pub surface: String,
    /// Ball radius R (mm)
    #[arg(long, value_name = "R")]
    pub radius: f64,
    /// The rectangle's x range (mm)
    #[arg(long, value_name = "A:B", value_parser = parse_range, allow_hyphen_values = true)]
    pub x: [f64; 2],
    /// The rectangle's y range (mm)
    #[arg(long, value_name = "A:B", value_parser = parse_range, allow_hyphen_values = true)]
    pub y: [f64; 2],
    /// Distance between raster lines (mm)
    #[arg(long, value_name = "S")]
    pub stepover: f64,
    /// Distance between points along a line (mm); with --tol, the longest allowed
    #[arg(long, value_name = "S")]
    pub step: f64,
    /// Chord tolerance (mm): space points by the path's curvature instead of a fixed step
    // `--tolerance`: the option's first name, kept for the scripts that use it.
    #[arg(long = "tol", alias = "tolerance", value_name = "T")]
    pub tolerance: Option<f64>,
    /// Raster lines of constant x (running along y) or of constant y
    #[arg(long, value_enum, default_value_t)]
    pub lines: LinesArg,
    /// The programmed point: the ball's tip (lowest point) or its centre
    #[arg(long, value_enum, default_value_t)]
    pub program: Programmed,
    /// A ball position that cuts the surface elsewhere: fail, lift it clear, or do not check
    #[arg(long, value_enum, default_value_t)]
    pub gouge: GougeArg,
    /// Cuts up to this deep (mm) are not gouges (0.001 mm is 1 µm), every deeper one is; a
    /// reported depth is within half of it below the true one, a lifted ball within half of
    /// it below the drop-cutter height
    #[arg(long, value_name = "MM", default_value_t = GOUGE_TOLERANCE)]
    pub gouge_tol: f64,
    /// Surface samples the gouge check may take before it stops with an error (its time
    /// limit: about a microsecond each)
    #[arg(long, value_name = "N", default_value_t = GOUGE_SAMPLES)]
    pub gouge_samples: u64,
    /// Feed rate of the cutting moves (mm/min)
    #[arg(long, value_name = "F", default_value_t = 480.0)]
    pub feed: f64,
    /// Tool number called at the start of the NC program
    #[arg(long, value_name = "T", default_value_t = 1)]
    pub tool: u32,
    /// Spindle speed of the NC program (1/min, M3)
    #[arg(long, value_name = "S", default_value_t = 3000.0)]
    pub spindle: f64,
    /// csv of the points (cx,cy,cz,px,py,pz,tx,ty,tz), or an NC program in a milling dialect
    #[arg(long, default_value = "csv", ignore_case = true, value_parser = output_formats())]
    pub format: PointsFormat,
    /// Rapid up to the clearance height between lines (by default the link move cuts)
    #[arg(long)]
    pub retract: bool,
    /// Which way the lines are cut: zigzag (every other line backwards, linked), or one way
    /// on every line, climb or conventional milling for the M3 spindle (the side the next line
    /// lies on to the right of the feed for climb), with a retract to the clearance height,
    /// a rapid back to the start of the next line and a plunge at the feed
    #[arg(long, value_enum, default_value_t)]
    pub direction: DirectionArg,
    /// Clearance height (mm) for approach, retracts and end, not below the highest ball position
    /// [default: highest point + 5, whole mm]
    #[arg(long, value_name = "Z", allow_hyphen_values = true)]
    pub clearance: Option<f64>,
    /// Program name [default: from OUT, else BALLPATH]
    #[arg(long)]
    pub name: Option<String>,
    /// Write here instead of to stdout
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Also write the path as an APT cutter-location file for `ncsheet post`: GOTO/tip,axis with
    /// the tool axis along the surface normal (the tip along the axis is the contact point);
    /// with --cl and no -o, only this file is written
    #[arg(long, value_name = "OUT.cl")]
    pub cl: Option<PathBuf>,
    /// For --cl: the tool axis leans this many degrees from the surface normal along the feed
    /// (forwards), so that the ball does not cut with its centre
    #[arg(long, value_name = "DEG", default_value_t = 0.0, allow_hyphen_values = true, requires = "cl")]
    pub lead: f64,
    /// For --cl: the tool axis leans this many degrees from the surface normal across the feed
    /// (towards normal × feed)
    #[arg(long, value_name = "DEG", default_value_t = 0.0, allow_hyphen_values = true, requires = "cl")]
    pub tilt: f64,
    /// Replace a read-only or hard-linked OUT
    #[arg(long, requires = "written")]
    pub force: bool,
    /// Print the time spent computing, formatting and writing to stderr
    #[arg(long)]
    pub timings: bool,
    /// Refuse a path of more points than this (each costs memory and a line of output)
    #[arg(long, value_name = "N", default_value_t = 4_000_000)]
    pub max_points: usize,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
}

#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum LinesArg {
    #[default]
    X,
    Y,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum DirectionArg {
    /// Every other line backwards, the link to the next line cut (or a rapid with --retract)
    #[default]
    Zigzag,
    /// Every line the same way, climb milling (M3: the next line's side right of the feed)
    Climb,
    /// Every line the same way, conventional milling (the next line's side left of the feed)
    Conventional,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Programmed {
    #[default]
    Tip,
    #[value(alias = "center")]
    Centre,
}

#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub enum GougeArg {
    #[default]
    Fail,
    Lift,
    Off,
}

/// What `--format` writes: the points as csv, or a program in a milling dialect.
#[derive(Clone, Copy, Debug)]
pub enum PointsFormat {
    Csv,
    Program(&'static dyn Dialect),
}

/// `csv` and every dialect that writes milling programs (`iso` is Fanuc-style with `%` and
/// `O0001`; LinuxCNC reads `linuxcnc`, which has no O-number), read once into the format.
fn output_formats() -> impl clap::builder::TypedValueParser<Value = PointsFormat> {
    use clap::builder::TypedValueParser;
    let mut names = vec!["csv"];
    names.extend(dialect::names_for(Machine::Mill));
    clap::builder::PossibleValuesParser::new(names).map(|name| match dialect::by_name(&name) {
        Some(dialect) => PointsFormat::Program(dialect),
        None => PointsFormat::Csv,
    })
}

fn parse_range(text: &str) -> std::result::Result<[f64; 2], String> {
    let (a, b) = text.split_once(':').ok_or_else(|| format!("'{text}' is not a range A:B"))?;
    let number = |s: &str| s.trim().parse::<f64>().map_err(|_| format!("'{s}' in '{text}' is not a number"));
    Ok([number(a)?, number(b)?])
}

pub fn run(args: BallpathArgs) -> Result<()> {
    let surface =
        parse_standalone(&args.surface).map_err(|e| Error::User(prepend("--surface: ", &e.render(&args.surface))))?;
    let spec = spec(&args);
    let started = Instant::now();
    let bar = progress_bar(&spec);
    let mut progress = |done: usize, total: usize| {
        if let Some(bar) = &bar {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        }
    };
    let paths = standalone_ball_path(&surface, &spec, written(&args), &mut progress);
    // Cleared before any message, so an error does not land on the bar's line.
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let (path, as_written) = paths.map_err(|failure| Error::User(prepend("--surface: ", &failure_message(failure))))?;
    let computed = started.elapsed();
    report_gouges(&path, spec.gouge)?;
    check_clearance(&path, &args)?;
    let points = path.points.len();
    // A program's points are the written path's: on its dialect's grid, checked there. With
    // no CL file, which is made from the computed path, the computed path is let go before
    // the program is made (48 bytes a point), so the two are not held at once.
    let (path, as_written) = match as_written {
        Some(written) if args.cl.is_none() => {
            drop(path);
            (written, None)
        }
        as_written => (path, as_written),
    };
    let programmed = as_written.as_ref().unwrap_or(&path);
    let started = Instant::now();
    let text = render(&path, programmed, &args)?;
    let formatted = started.elapsed();
    let started = Instant::now();
    match &args.cl {
        Some(cl) => write_with_cl(&path, &args, cl, text)?,
        None => emit(&text, args.output.as_deref(), args.force)?,
    }
    if args.timings {
        print_timings(points, computed, formatted, started.elapsed());
    }
    Ok(())
}

fn spec(args: &BallpathArgs) -> BallPathSpec {
    BallPathSpec {
        radius: args.radius,
        x: args.x,
        y: args.y,
        stepover: args.stepover,
        spacing: match args.tolerance {
            Some(tolerance) => Spacing::Chord { tolerance, max_step: args.step },
            None => Spacing::Step(args.step),
        },
        lines: match args.lines {
            LinesArg::X => Lines::ConstantX,
            LinesArg::Y => Lines::ConstantY,
        },
        gouge: match args.gouge {
            GougeArg::Fail => GougeCheck::Report,
            GougeArg::Lift => GougeCheck::Lift,
            GougeArg::Off => GougeCheck::Off,
        },
        gouge_tol: args.gouge_tol,
        gouge_samples: args.gouge_samples,
        direction: match args.direction {
            DirectionArg::Zigzag => Direction::Zigzag,
            DirectionArg::Climb => Direction::Climb,
            DirectionArg::Conventional => Direction::Conventional,
        },
        // With a retract the link between lines is a rapid over the part, not a cut.
        check_links: !retracts(args),
        max_points: args.max_points,
    }
}

/// Why there is no path; past the point limit, with the option that raises it.
fn failure_message(failure: PathFailure) -> String {
    match failure {
        PathFailure::TooManyPoints { message, .. } => {
            format!("{message} (--max-points raises the limit; a larger --step, --stepover or --tol needs fewer)")
        }
        PathFailure::Other(_, message) => message,
    }
}

/// A bar on stderr for paths of more than 100,000 points, when stderr is a terminal.
fn progress_bar(spec: &BallPathSpec) -> Option<ProgressBar> {
    let lines = (spec.x[1] - spec.x[0]).max(spec.y[1] - spec.y[0]) / spec.stepover;
    let step = match spec.spacing {
        Spacing::Step(s) | Spacing::Chord { max_step: s, .. } => s,
    };
    let per_line = (spec.x[1] - spec.x[0]).max(spec.y[1] - spec.y[0]) / step;
    if !io::stderr().is_terminal() || lines * per_line < 1e5 {
        return None;
    }
    let bar = ProgressBar::new(0);
    let style = ProgressStyle::with_template("{bar:40} {percent}% of the path, {elapsed} elapsed, {eta} left")
        .expect("the template is valid");
    bar.set_style(style);
    Some(bar)
}

/// Gouges fail the command unless the balls were lifted, which is said on stderr.
fn report_gouges(path: &BallPath, check: GougeCheck) -> Result<()> {
    const SHOWN: usize = 10;
    if path.gouges.is_empty() {
        return Ok(());
    }
    let mut list: Vec<String> = path.gouges.iter().take(SHOWN).map(describe_gouge).collect();
    if path.gouges.len() > SHOWN {
        list.push(format!("… and {} more", path.gouges.len() - SHOWN));
    }
    let deepest = path.gouges.iter().map(|g| g.depth).fold(0.0, f64::max);
    let moves = path.gouges.iter().filter(|g| g.kind == GougeKind::Move).count();
    let positions = path.gouges.len() - moves;
    match check {
        GougeCheck::Lift => {
            eprintln!(
                "ncsheet: lifted {positions} ball positions clear of the surface and inserted points in {moves} moves \
                 (at most {deepest:.4} mm):"
            );
            for line in list {
                eprintln!("  {line}");
            }
            Ok(())
        }
        _ => Err(Error::User(format!(
            "{positions} ball positions and {moves} moves cut into the surface (up to {deepest:.4} mm); --gouge lift \
             raises them until they clear:\n  {}",
            list.join("\n  ")
        ))),
    }
}

/// A clearance plane below the highest ball position would take the rapids through the part.
fn check_clearance(path: &BallPath, args: &BallpathArgs) -> Result<()> {
    let Some(clearance) = args.clearance else { return Ok(()) };
    let highest = programmed_point(args).highest(path);
    let what = match args.program {
        Programmed::Tip => "tip",
        Programmed::Centre => "centre",
    };
    if clearance >= highest {
        return Ok(());
    }
    Err(Error::User(format!(
        "--clearance {clearance} is below the highest ball position (its {what} at z = {highest:.4}): rapids at \
         that height would run through the part; give --clearance {} or more",
        highest.ceil()
    )))
}

/// How the program of `--format` writes its points (none for the csv, which is exact): the
/// dialect's decimals, of the tip or the centre.
fn written(args: &BallpathArgs) -> Option<Written> {
    let PointsFormat::Program(dialect) = args.format else { return None };
    let programmed_dz = match args.program {
        Programmed::Tip => -args.radius,
        Programmed::Centre => 0.0,
    };
    Some(Written { resolution: dialect.resolution(), programmed_dz })
}

/// The csv of `path`, or the program of `programmed` (the path as its dialect writes it).
fn render(path: &BallPath, programmed: &BallPath, args: &BallpathArgs) -> Result<String> {
    let PointsFormat::Program(dialect) = args.format else { return Ok(csv(path)) };
    let name = program_name(args);
    let program = ball_path_program(programmed, &name, &nc_options(args));
    dialect.render(&program).map_err(|e| Error::User(e.to_string()))
}

/// The CL file and, with -o, the usual output: both written or neither.
fn write_with_cl(path: &BallPath, args: &BallpathArgs, cl: &Path, text: String) -> Result<()> {
    if args.output.as_deref() == Some(cl) {
        return Err(Error::Usage(format!("--cl {} is also -o: give the CL file a name of its own", cl.display())));
    }
    let name = args.name.clone().unwrap_or_else(|| stem_name(Some(cl)).unwrap_or_else(|| "BALLPATH".into()));
    let records = ball_path_cl(path, &name, &nc_options(args));
    let mut files = vec![Encoded::new(cl, apt::write(&records).into_bytes())];
    if let Some(out) = &args.output {
        files.push(Encoded::new(out, text.into_bytes()));
    }
    super::write_outputs(&files, false, args.force)
}

/// `cx,cy,cz,px,py,pz,tx,ty,tz`: ball centre, contact point, tip; numbers as short as read
/// back exactly.
fn csv(path: &BallPath) -> String {
    let mut out = String::with_capacity(path.points.len() * 120);
    out.push_str("cx,cy,cz,px,py,pz,tx,ty,tz\n");
    for p in &path.points {
        let (c, t) = (p.centre, p.tip(path.radius));
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{}",
            c.x, c.y, c.z, p.contact.x, p.contact.y, p.contact.z, t.x, t.y, t.z
        );
    }
    out
}

fn nc_options(args: &BallpathArgs) -> BallPathNcOptions {
    BallPathNcOptions {
        point: programmed_point(args),
        feed: args.feed,
        tool: args.tool,
        spindle: args.spindle,
        retract: retracts(args),
        clearance: args.clearance,
        x: args.x,
        y: args.y,
        lead_deg: args.lead,
        tilt_deg: args.tilt,
    }
}

/// Whether the tool leaves the part between lines: asked for, or a one-way raster (which
/// goes back to the start of the next line over the part).
fn retracts(args: &BallpathArgs) -> bool {
    args.retract || args.direction != DirectionArg::Zigzag
}

fn programmed_point(args: &BallpathArgs) -> ProgrammedPoint {
    match args.program {
        Programmed::Tip => ProgrammedPoint::Tip,
        Programmed::Centre => ProgrammedPoint::Centre,
    }
}

/// `--name`, or OUT's file stem in capitals (`eqcam-bump.h` → `EQCAM_BUMP`), or BALLPATH.
fn program_name(args: &BallpathArgs) -> String {
    if let Some(name) = &args.name {
        return name.clone();
    }
    stem_name(args.output.as_deref()).unwrap_or_else(|| "BALLPATH".to_string())
}

/// A file's stem in capitals, `_` for anything not a letter or digit.
fn stem_name(file: Option<&Path>) -> Option<String> {
    let stem = file.and_then(Path::file_stem).map(|s| s.to_string_lossy().to_string())?;
    let name = stem.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' }).collect();
    Some(name).filter(|n: &String| !n.is_empty())
}

fn print_timings(points: usize, compute: Duration, format: Duration, write: Duration) {
    let per_point = |d: Duration| d.as_secs_f64() * 1e9 / points.max(1) as f64;
    eprintln!("points   {points}");
    eprintln!("compute  {:.3} s  ({:.0} ns/point)", compute.as_secs_f64(), per_point(compute));
    eprintln!("format   {:.3} s  ({:.0} ns/point)", format.as_secs_f64(), per_point(format));
    eprintln!("write    {:.3} s", write.as_secs_f64());
    eprintln!("total    {:.3} s", (compute + format + write).as_secs_f64());
}
