//! `ncsheet cam` (a whole cam from its design sheet) and `ncsheet arcfit` (one spiral piece):
//! spirals replaced by tangent arcs within a tolerance, written as a coordinate table, an NC
//! milling program or a drawing.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use ncsheet::geometry::cam::{
    by_disc, fit_cam, fit_piece_on_side, CamFit, CamOptions, FittedSegment, Piece, PieceKind, Segment, Side,
};
use ncsheet::nc::cam::{
    cam_program_reporting, fit_tolerance, CamNcOptions, Compensation, LeadKind, DEFAULT_CUTTER_DIAMETER,
    LEAD_BEYOND_RADIUS,
};
use ncsheet::nc::cam_sheet::{arcs_csv, parse_sheet, svg_drawing, SvgOptions};
use ncsheet::nc::{dialect, Machine};

use super::output::emit;
use super::report::{Error, Result};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum CamFormat {
    /// The arcs: x0,y0,x1,y1,cx,cy,r,dir (dir ccw or cw), one per line, in cutting order
    #[default]
    Csv,
    /// An NC milling program (G17, G2/G3 with I J, a radial lead-in and lead-out)
    Nc,
    /// A drawing: the curve, the numbered arcs, their centres and the deviation magnified
    Svg,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum LeadArg {
    /// A straight move perpendicular to the profile
    #[default]
    Line,
    /// A straight move, then a quarter arc tangent to the profile
    Arc,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum CutterSide {
    /// The program follows the profile with the cutter's centre
    #[default]
    Off,
    /// G41: cutter left of the profile
    Left,
    /// G42: cutter right of the profile (outside a cam cut counter-clockwise)
    Right,
}

/// Which side of the profile the arcs lie on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum SideArg {
    /// Away from the cam centre, within --tol: an outer cam finished from the material side,
    /// never undersize (the paper's arcs envelop the curve from outside)
    #[default]
    Outside,
    /// Towards the cam centre, within --tol: an inner profile finished from its material side
    Inside,
    /// Either side within --tol: the fewest arcs
    Both,
}

impl From<SideArg> for Side {
    fn from(side: SideArg) -> Side {
        match side {
            SideArg::Outside => Side::Outside,
            SideArg::Inside => Side::Inside,
            SideArg::Both => Side::Both,
        }
    }
}

/// What both commands write and where.
#[derive(Debug, Args)]
pub struct CamOutput {
    /// What to write
    #[arg(long, value_enum, default_value_t)]
    pub format: CamFormat,
    /// NC dialect for --format nc
    #[arg(long, default_value = "iso", ignore_case = true,
          value_parser = super::nc::dialect_parser(dialect::names_for(Machine::Mill)))]
    pub dialect: &'static dyn dialect::Dialect,
    /// Cutter radius compensation in the NC program
    #[arg(long, value_enum, default_value_t)]
    pub cutter: CutterSide,
    /// Cutting feed in mm/min for the NC program
    #[arg(long, default_value_t = 200.0, allow_negative_numbers = true)]
    pub feed: f64,
    /// Tool number called at the start of the NC program (its offset for --cutter unless
    /// --offset names another)
    #[arg(long, default_value_t = 1)]
    pub tool: u32,
    /// The offset register --cutter compensation takes the radius from (G41/G42 D N on
    /// iso; on linuxcnc the tool-table entry N) [default: the tool's number]; sinumerik and
    /// heidenhain have none apart from the tool and refuse it
    #[arg(long, value_name = "N", requires = "cutter")]
    pub offset: Option<u32>,
    /// Spindle speed in 1/min for the NC program (M3)
    #[arg(long, default_value_t = 1000.0)]
    pub spindle: f64,
    /// The cutter's diameter, mm: the lead-in must be longer than its radius and the plunge
    /// clear of the profile by it
    #[arg(long, value_name = "MM", default_value_t = DEFAULT_CUTTER_DIAMETER)]
    pub cutter_diameter: f64,
    /// Cutting depth below the disc's top (Z0), mm
    #[arg(long, value_name = "MM", default_value_t = 12.0)]
    pub depth: f64,
    /// Clearance height for rapids over the part, the start and the end, mm above Z0
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub clearance: f64,
    /// Retract height: the rapid down ends here and the plunge feed starts, mm above Z0
    #[arg(long, value_name = "MM", default_value_t = 2.0)]
    pub retract: f64,
    /// Lead-in and lead-out length, mm, from the cutter's side of the profile (default: the
    /// cutter's radius + 2 mm; with --cutter left/right it must be longer than the radius)
    #[arg(long, value_name = "MM")]
    pub lead: Option<f64>,
    /// The lead's shape: a line perpendicular to the profile, or a line then a quarter arc of
    /// radius --lead tangent to it
    #[arg(long, value_enum, default_value_t)]
    pub lead_kind: LeadArg,
    /// Plunge feed in mm/min, from the retract height to the depth
    #[arg(long, default_value_t = 100.0)]
    pub plunge_feed: f64,
    /// Write here instead of standard output
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Replace a read-only or hard-linked OUT
    #[arg(long, requires = "output")]
    pub force: bool,
}

/// Fit every segment of a cam design sheet with tangent arcs within --tol.
///
/// The sheet is csv with a header naming the columns row, operation, disc, type (circle, arch,
/// log or parab), from_deg, to_deg, r_start, r_end (row, operation and disc may be left out;
/// from_hundredths, to_hundredths instead of the degrees: the angles in hundredths of a turn,
/// as the paper's sheets count). The
/// segments of a disc must go round 0–360° once: gaps, overlaps and steps are reported with
/// the rows involved, and are an error unless --partial (then the cutter goes straight across
/// gaps and steps; overlaps stay an error).
#[derive(Debug, Args)]
pub struct CamArgs {
    /// The design sheet (.csv)
    pub file: PathBuf,
    /// Tolerance H in mm: every arc within H of the curve and the curve within H of the arcs
    #[arg(long, default_value_t = 0.05)]
    pub tol: f64,
    /// The disc to write, when the sheet has several (default: the first)
    #[arg(long)]
    pub disc: Option<String>,
    /// The side of the profile the arcs lie on; the tolerance is kept on that side, for the
    /// program as written
    #[arg(long, value_enum, default_value_t)]
    pub side: SideArg,
    /// Accept gaps and steps between segments
    #[arg(long)]
    pub partial: bool,
    #[command(flatten)]
    pub out: CamOutput,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
}

/// Replace one spiral piece by the fewest tangent arcs within --tol.
///
/// Angles in degrees about the cam centre, radii in mm: an Archimedean spiral grows by the
/// same amount per degree, a logarithmic one by the same ratio.
#[derive(Debug, Args)]
pub struct ArcfitArgs {
    /// The piece: arch (Archimedean), log (logarithmic), parab (parabolic: constant
    /// acceleration, then deceleration) or circle
    #[arg(long)]
    pub kind: String,
    /// Radius at the start (mm)
    #[arg(long, allow_negative_numbers = true)]
    pub r0: f64,
    /// Angle at the start (degrees)
    #[arg(long, allow_negative_numbers = true)]
    pub phi0: f64,
    /// Radius at the end (mm)
    #[arg(long, allow_negative_numbers = true)]
    pub r1: f64,
    /// Angle at the end (degrees)
    #[arg(long, allow_negative_numbers = true)]
    pub phi1: f64,
    /// Tolerance H in mm
    #[arg(long, allow_negative_numbers = true)]
    pub tol: f64,
    /// The side of the profile the arcs lie on; the tolerance is kept on that side
    #[arg(long, value_enum, default_value_t)]
    pub side: SideArg,
    #[command(flatten)]
    pub out: CamOutput,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
}

pub fn cam(args: CamArgs) -> Result<()> {
    let file = &args.file;
    if let Some(out) = &args.out.output {
        super::refuse_overwriting_inputs(&[file], &[out], "write the result to a new file")?;
    }
    let text =
        std::fs::read_to_string(file).map_err(|e| Error::User(format!("{}: cannot read: {e}", file.display())))?;
    let segments = parse_sheet(&text).map_err(|e| Error::User(format!("{}: {e}", file.display())))?;
    let discs = by_disc(&segments);
    let (disc, segs) = pick_disc(file, &discs, args.disc.as_deref())?;
    let tolerance = fitted_tolerance(args.tol);
    let (side, reserve) = (args.side.into(), args.tol - tolerance);
    let options = CamOptions { tolerance, allow_partial: args.partial, with_bounds: false, side, reserve };
    let mut fit = fit_cam(disc, segs, &options).map_err(|e| Error::User(format!("{}: {e}", file.display())))?;
    fit.tolerance = args.tol;
    for issue in &fit.issues {
        eprintln!("ncsheet: {}: warning: {issue}", file.display());
    }
    write_fit(&fit, &args.out)
}

pub fn arcfit(args: ArcfitArgs) -> Result<()> {
    let geometry = |e: ncsheet::geometry::GeometryError| Error::User(e.to_string());
    let kind = PieceKind::parse(&args.kind).map_err(geometry)?;
    let piece = Piece::new(kind, args.r0, args.phi0, args.r1, args.phi1).map_err(geometry)?;
    let tolerance = fitted_tolerance(args.tol);
    let arcs = fit_piece_on_side(&piece, tolerance, args.side.into(), args.tol - tolerance).map_err(geometry)?;
    let segment = Segment { row: String::new(), operation: String::new(), disc: String::new(), line: 0, piece };
    let fit = CamFit {
        disc: String::new(),
        tolerance: args.tol,
        segments: vec![FittedSegment { segment, arcs, lower_bound: None }],
        issues: Vec::new(),
    };
    write_fit(&fit, &args.out)
}

/// The tolerance to fit at: an NC program's rounded numbers move its arcs, so the fit keeps
/// that much in reserve and the program as written stays within `tol`. The table and the
/// drawing show the same arcs as the program.
fn fitted_tolerance(tol: f64) -> f64 {
    if tol.is_finite() && fit_tolerance(tol) > 0.0 {
        fit_tolerance(tol)
    } else {
        tol
    }
}

fn pick_disc<'a>(
    file: &Path,
    discs: &'a [(String, Vec<Segment>)],
    wanted: Option<&str>,
) -> Result<(&'a str, &'a [Segment])> {
    let names = || discs.iter().map(|(d, _)| d.as_str()).collect::<Vec<_>>().join(", ");
    let found = match wanted {
        Some(w) => discs.iter().find(|(d, _)| d.eq_ignore_ascii_case(w)),
        None => discs.first(),
    };
    let Some((disc, segs)) = found else {
        return Err(Error::User(match wanted {
            Some(w) => format!("{}: no disc '{w}' (the sheet has: {})", file.display(), names()),
            None => format!("{}: the sheet has no segments", file.display()),
        }));
    };
    if wanted.is_none() && discs.len() > 1 {
        eprintln!(
            "ncsheet: {}: the sheet has discs {}; writing disc {disc} (choose with --disc)",
            file.display(),
            names()
        );
    }
    Ok((disc, segs))
}

fn write_fit(fit: &CamFit, out: &CamOutput) -> Result<()> {
    let text = match out.format {
        CamFormat::Csv => arcs_csv(fit.arcs()),
        CamFormat::Svg => svg_drawing(fit, &SvgOptions::default()),
        CamFormat::Nc => {
            let d = out.dialect;
            let compensation = match out.cutter {
                CutterSide::Off => Compensation::Off,
                CutterSide::Left => Compensation::Left,
                CutterSide::Right => Compensation::Right,
            };
            let options = CamNcOptions {
                compensation,
                feed: out.feed,
                plunge_feed: out.plunge_feed,
                tool: out.tool,
                radius_offset: out.offset,
                spindle: out.spindle,
                z_safe: out.clearance,
                z_retract: out.retract,
                z_cut: -out.depth,
                lead: out.lead.unwrap_or(out.cutter_diameter / 2.0 + LEAD_BEYOND_RADIUS),
                lead_kind: match out.lead_kind {
                    LeadArg::Line => LeadKind::Line,
                    LeadArg::Arc => LeadKind::Arc,
                },
                cutter_diameter: out.cutter_diameter,
            };
            let (program, roundings) = cam_program_reporting(fit, &options).map_err(Error::User)?;
            for u in &roundings {
                let r = &u.rounding;
                eprintln!(
                    "ncsheet: disc {}: warning: the concave place at X{:.3} Y{:.3}{} is beyond the reach of the \
                     D{} cutter with compensation; the program rounds it with R{:.3} and leaves up to {:.3} mm \
                     there ({})",
                    fit.disc,
                    r.at.x,
                    r.at.y,
                    if u.at_entry { ", where the lead meets the profile," } else { "" },
                    out.cutter_diameter,
                    r.arc.radius,
                    r.left,
                    if u.at_entry { "--lead-kind arc enters without that corner" } else { "a smaller cutter cuts it" }
                );
            }
            d.render(&program).map_err(|e| Error::User(e.to_string()))?
        }
    };
    emit(&text, out.output.as_deref(), out.force)
}
