//! `ncsheet nc plot`: a program's backplot as an SVG drawing (the geometry and the drawing
//! are `nc::backplot`'s; this reads the program and writes the file).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use ncsheet::nc::backplot::{self, Plane};

use super::nc::{read_program, MachineArg, ReadDialect};
use super::output::emit;
use super::report::{Error, Result};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PlaneArg {
    /// X across, Y up: a mill seen from above (the default on a mill)
    Xy,
    /// X across, Z up: a mill seen from the front
    Xz,
    /// Z across, X up as a radius: a lathe part's profile (the default on a lathe)
    Zx,
}

/// Draw a program's tool path as a backplot (SVG): rapids dashed red, feeds solid blue, arcs as
/// arcs, the start circled, arrows along the direction of travel, a scale bar in mm and a
/// legend. A lathe's X is drawn as a radius (the diameter halved), so the path is the part's
/// profile.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// The NC program (text as the dialect writes it)
    pub program: PathBuf,
    /// The SVG file to write (never the program itself)
    #[arg(short, long, value_name = "OUT.svg")]
    pub output: PathBuf,
    /// The control the program is written for; default: what its header, extension
    /// (.ngc, .mpf, .h, …) or words tell, else iso
    #[arg(long, value_enum)]
    pub dialect: Option<ReadDialect>,
    /// What the program is for; default: a lathe when G18 comes before the first move
    #[arg(long, value_enum)]
    pub machine: Option<MachineArg>,
    /// The plane drawn, horizontal axis first; default xy on a mill, zx on a lathe
    #[arg(long, value_enum)]
    pub plane: Option<PlaneArg>,
    /// Replace a read-only or hard-linked OUT
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: PlotArgs) -> Result<()> {
    super::refuse_overwriting_inputs(&[&args.program], &[&args.output], "write the drawing to a new file")?;
    let (program, lines, name, _) = read_program(&args.program, args.dialect, args.machine)?;
    let plane = match args.plane {
        Some(PlaneArg::Xy) => Plane::Xy,
        Some(PlaneArg::Xz) => Plane::Xz,
        Some(PlaneArg::Zx) => Plane::Zx,
        None => Plane::for_machine(program.machine),
    };
    let fail = |e: backplot::PlotError| {
        let at = e.block.and_then(|b| lines.get(b - 1)).map(|l| format!(": line {l}")).unwrap_or_default();
        Error::User(format!("{name}{at}: {}", e.message))
    };
    let path = backplot::toolpath(&program).map_err(fail)?;
    let title = args.program.file_name().map_or(name.clone(), |f| f.to_string_lossy().into_owned());
    let svg = backplot::svg_drawing(&path, plane, &title).map_err(fail)?;
    emit(&svg, Some(&args.output), args.force)
}
