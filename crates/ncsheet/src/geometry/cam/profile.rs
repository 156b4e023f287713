//! Whole cams: the segments of a design sheet, the check that they go round once, and the
//! arcs of every segment.
//!
//! A cam disc is laid out with angles increasing from 0° to 360°, and the profile is cut in that
//! order (counter-clockwise about the cam centre). Adjacent segments should meet at the same
//! angle and radius; anything else is reported with the rows involved:
//! - an overlap (two rows claim the same angles) is always an error;
//! - a gap (no row covers some angles, including a cam that does not start at 0° or does not
//!   close at 360°) and a step (rows meet at one angle with different radii) are errors unless
//!   a partial cam is allowed, in which case the cutter goes straight across them.

use std::collections::HashMap;
use std::fmt;

use super::arc::Arc;
use super::fit::{estimate_arcs, fit_piece, lower_bound, offset_crossing, side_curve, Side};
use super::piece::Piece;
use crate::geometry::GeometryError;

/// Angles and radii closer than this are the same (the sheets give 0.1° and 0.01 mm).
const SAME: f64 = 1e-9;

/// One row of a design sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// The sheet's own row number (the paper's "Sorszám"; "–" for unnumbered return rows).
    pub row: String,
    /// What the slide does meanwhile ("centre drill").
    pub operation: String,
    /// The disc the row belongs to ("R" for the turret slide); empty when the sheet has one.
    pub disc: String,
    /// Line in the sheet's file, 1-based, for messages.
    pub line: usize,
    pub piece: Piece,
}

impl Segment {
    /// How messages name the row: `row 5 "drill" (line 8)`.
    pub fn label(&self) -> String {
        format!("row {} \"{}\" (line {})", self.row, self.operation, self.line)
    }
}

/// Something wrong with how a cam's segments go round.
#[derive(Clone, Debug, PartialEq)]
pub enum CoverageIssue {
    /// No row covers `from_deg`..`to_deg`; `after`/`before` are the labels of the rows on either
    /// side, `None` at 0° and 360°.
    Gap { from_deg: f64, to_deg: f64, after: Option<String>, before: Option<String> },
    /// Two rows cover `from_deg`..`to_deg` both.
    Overlap { from_deg: f64, to_deg: f64, first: String, second: String },
    /// Two rows meet at `at_deg` with different radii.
    Step { at_deg: f64, r_end: f64, r_start: f64, after: String, before: String },
    /// A row whose angles decrease, or that leaves 0°–360°.
    Misplaced { row: String, message: String },
    /// More pairs of rows overlap than the [`MAX_OVERLAPS_LISTED`] listed before this.
    MoreOverlaps,
}

/// The most overlapping pairs of rows listed: n rows covering the same angles are n(n−1)/2
/// pairs (50,000 such rows asked for 1.25·10^9 and aborted at the memory cap).
pub const MAX_OVERLAPS_LISTED: usize = 1000;

/// The most arcs one disc's fit may need, estimated before fitting, each row counting at
/// least one. In a release build fitting costs up to about 2 ms per estimated arc (the
/// start-tangent search of each row, even a one-arc row, and a lookahead at every arc), so a
/// disc within the limit fits within about 8 s; 20,000 one-arc rows took 24 s.
pub const MAX_CAM_ARCS: usize = 4000;

impl CoverageIssue {
    /// Whether the issue stops the cam from being cut; gaps and steps are allowed in a partial
    /// cam.
    pub fn is_fatal(&self, allow_partial: bool) -> bool {
        match self {
            CoverageIssue::Gap { .. } | CoverageIssue::Step { .. } => !allow_partial,
            CoverageIssue::Overlap { .. } | CoverageIssue::Misplaced { .. } | CoverageIssue::MoreOverlaps => true,
        }
    }
}

impl fmt::Display for CoverageIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CoverageIssue::Gap { from_deg, to_deg, after, before } => {
                write!(f, "gap {from_deg}°–{to_deg}°: no row covers it")?;
                match (after, before) {
                    (Some(a), Some(b)) => write!(f, " (between {a} and {b})"),
                    (Some(a), None) => write!(f, " (after {a}: the cam does not close at 360°)"),
                    (None, Some(b)) => write!(f, " (before {b}: the cam does not start at 0°)"),
                    (None, None) => write!(f, " (the sheet has no rows)"),
                }
            }
            CoverageIssue::Overlap { from_deg, to_deg, first, second } => {
                write!(f, "overlap {from_deg}°–{to_deg}°: {first} and {second} both cover it")
            }
            CoverageIssue::Step { at_deg, r_end, r_start, after, before } => {
                write!(f, "step at {at_deg}°: {after} ends at r = {r_end} mm but {before} starts at r = {r_start} mm")
            }
            CoverageIssue::Misplaced { row, message } => write!(f, "{row}: {message}"),
            CoverageIssue::MoreOverlaps => {
                write!(f, "more rows overlap: ncsheet lists the first {MAX_OVERLAPS_LISTED} overlapping pairs")
            }
        }
    }
}

/// Why a cam cannot be fitted.
#[derive(Clone, Debug, PartialEq)]
pub enum CamError {
    /// The sheet's text cannot be read as segments.
    Sheet { line: usize, message: String },
    /// A row has no geometry.
    Segment { row: String, error: GeometryError },
    /// The segments do not go round as required; every issue found is listed.
    Coverage(Vec<CoverageIssue>),
    /// The fit would need more arcs than [`MAX_CAM_ARCS`] (about `arcs`, from `rows` rows).
    TooManyArcs { rows: usize, arcs: f64 },
}

impl fmt::Display for CamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CamError::Sheet { line, message } => write!(f, "line {line}: {message}"),
            CamError::Segment { row, error } => write!(f, "{row}: {error}"),
            CamError::Coverage(issues) => {
                let n = issues.len();
                write!(f, "the segments do not go round the cam once ({n} problem{})", if n == 1 { "" } else { "s" })?;
                for issue in issues {
                    write!(f, "\n  {issue}")?;
                }
                Ok(())
            }
            CamError::TooManyArcs { rows, arcs } => write!(
                f,
                "the disc's {rows} rows would need about {arcs:.0} arcs at this tolerance (each row at least one), \
                 more than ncsheet's limit of {MAX_CAM_ARCS} for one disc: give a larger tolerance or split the sheet"
            ),
        }
    }
}

impl std::error::Error for CamError {}

/// How to fit a cam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CamOptions {
    /// Tolerance H in mm: how far the arcs may lie from the curve, on `side`.
    pub tolerance: f64,
    /// Which side of the profile the arcs lie on (outside: a finished outer cam is never
    /// undersize).
    pub side: Side,
    /// On one side, how close to the profile the arcs may not come, mm: room kept for the
    /// rounding of the written program (see `nc::cam::fit_tolerance`). Unused for `Side::Both`.
    pub reserve: f64,
    /// Accept gaps and steps (the cutter goes straight across them).
    pub allow_partial: bool,
    /// Also compute every piece's lower bound (slower; for reports).
    pub with_bounds: bool,
}

impl CamOptions {
    /// Within `tolerance` on either side of the curve (the fewest arcs), no lower bounds.
    pub fn either_side(tolerance: f64, allow_partial: bool) -> CamOptions {
        CamOptions { tolerance, allow_partial, with_bounds: false, side: Side::Both, reserve: 0.0 }
    }
}

/// A segment with its arcs.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedSegment {
    pub segment: Segment,
    pub arcs: Vec<Arc>,
    /// The fewest arcs any arc chain within the tolerance needs, when asked for.
    pub lower_bound: Option<usize>,
}

/// A fitted cam: its segments in cutting order, and the non-fatal issues found.
#[derive(Clone, Debug, PartialEq)]
pub struct CamFit {
    pub disc: String,
    pub tolerance: f64,
    pub segments: Vec<FittedSegment>,
    pub issues: Vec<CoverageIssue>,
}

impl CamFit {
    /// Every arc in cutting order.
    pub fn arcs(&self) -> impl Iterator<Item = &Arc> {
        self.segments.iter().flat_map(|s| s.arcs.iter())
    }

    pub fn n_arcs(&self) -> usize {
        self.segments.iter().map(|s| s.arcs.len()).sum()
    }
}

/// Every coverage issue of one disc's segments, in angle order.
pub fn check_coverage(segments: &[Segment]) -> Vec<CoverageIssue> {
    let mut issues = Vec::new();
    let mut placed: Vec<&Segment> = Vec::new();
    for s in segments {
        let (a, b) = (s.piece.phi0_deg, s.piece.phi1_deg);
        if b < a {
            let message = format!("angles run backwards ({a}° to {b}°); a cam is laid out with angles increasing");
            issues.push(CoverageIssue::Misplaced { row: s.label(), message });
        } else if a < -SAME || b > 360.0 + SAME {
            let message = format!("angles {a}°–{b}° leave 0°–360°");
            issues.push(CoverageIssue::Misplaced { row: s.label(), message });
        } else {
            placed.push(s);
        }
    }
    placed.sort_by(|x, y| x.piece.phi0_deg.total_cmp(&y.piece.phi0_deg));
    issues.extend(overlaps(&placed));
    issues.extend(gaps_and_steps(&placed));
    issues
}

/// The pairs of rows (in start order) that cover some angles both. Rows starting where a row
/// ends or later cannot overlap it, so each row is compared with those that start before it
/// ends: the work is the rows and the pairs found, not the rows squared (200,000 rows end to
/// end took minutes); at most [`MAX_OVERLAPS_LISTED`] pairs are listed.
fn overlaps(placed: &[&Segment]) -> Vec<CoverageIssue> {
    let mut issues = Vec::new();
    for (i, s) in placed.iter().enumerate() {
        let end = s.piece.phi1_deg;
        for later in placed[i + 1..].iter().take_while(|l| end - l.piece.phi0_deg > SAME) {
            let (from, to) = (later.piece.phi0_deg, end.min(later.piece.phi1_deg));
            if to - from <= SAME {
                continue;
            }
            if issues.len() == MAX_OVERLAPS_LISTED {
                issues.push(CoverageIssue::MoreOverlaps);
                return issues;
            }
            issues.push(CoverageIssue::Overlap { from_deg: from, to_deg: to, first: s.label(), second: later.label() });
        }
    }
    issues
}

/// Gaps between rows in angle order (the angles no row reaches), and steps where rows meet.
fn gaps_and_steps(placed: &[&Segment]) -> Vec<CoverageIssue> {
    let mut issues = Vec::new();
    let mut reached = 0.0;
    let mut last: Option<&Segment> = None;
    for s in placed {
        let (a, b) = (s.piece.phi0_deg, s.piece.phi1_deg);
        if a > reached + SAME {
            let after = last.map(|l| l.label());
            issues.push(CoverageIssue::Gap { from_deg: reached, to_deg: a, after, before: Some(s.label()) });
        } else if let Some(l) = last.filter(|l| (l.piece.phi1_deg - a).abs() <= SAME) {
            push_step(&mut issues, l, s);
        }
        if b > reached {
            reached = b;
            last = Some(s);
        }
    }
    if reached < 360.0 - SAME {
        issues.push(CoverageIssue::Gap {
            from_deg: reached,
            to_deg: 360.0,
            after: last.map(|l| l.label()),
            before: None,
        });
    } else if let (Some(l), Some(first)) = (last, placed.first()) {
        // A closed cam: the end at 360° meets the start at 0°.
        if first.piece.phi0_deg.abs() <= SAME {
            push_step(&mut issues, l, first);
        }
    }
    issues
}

fn push_step(issues: &mut Vec<CoverageIssue>, end: &Segment, start: &Segment) {
    if (end.piece.r1 - start.piece.r0).abs() > SAME {
        issues.push(CoverageIssue::Step {
            at_deg: end.piece.phi1_deg,
            r_end: end.piece.r1,
            r_start: start.piece.r0,
            after: end.label(),
            before: start.label(),
        });
    }
}

/// Checks one disc's segments and fits every one of them, in angle order.
pub fn fit_cam(disc: &str, segments: &[Segment], options: &CamOptions) -> Result<CamFit, CamError> {
    let issues = check_coverage(segments);
    let fatal: Vec<CoverageIssue> = issues.iter().filter(|i| i.is_fatal(options.allow_partial)).cloned().collect();
    if !fatal.is_empty() {
        return Err(CamError::Coverage(fatal));
    }
    let mut ordered: Vec<&Segment> = segments.iter().collect();
    ordered.sort_by(|x, y| x.piece.phi0_deg.total_cmp(&y.piece.phi0_deg));
    let curves = aimed_curves(&ordered, options)?;
    check_arc_count(&curves)?;
    let mut fitted = Vec::with_capacity(ordered.len());
    for (s, (curve, tolerance)) in ordered.into_iter().zip(curves) {
        let in_row = |error| CamError::Segment { row: s.label(), error };
        let arcs = fit_piece(&curve, tolerance).map_err(in_row)?;
        let lower_bound =
            if options.with_bounds { Some(lower_bound(&s.piece, options.tolerance).map_err(in_row)?) } else { None };
        fitted.push(FittedSegment { segment: s.clone(), arcs, lower_bound });
    }
    Ok(CamFit { disc: disc.to_string(), tolerance: options.tolerance, segments: fitted, issues })
}

/// Refuses a fit that would need more than [`MAX_CAM_ARCS`] arcs, from the estimate each
/// piece's tolerance check makes (a few dozen curve points a row), before any arc is fitted.
fn check_arc_count(curves: &[(Piece, f64)]) -> Result<(), CamError> {
    let arcs: f64 = curves.iter().map(|(curve, tolerance)| estimate_arcs(curve, *tolerance).max(1.0)).sum();
    if arcs > MAX_CAM_ARCS as f64 {
        return Err(CamError::TooManyArcs { rows: curves.len(), arcs });
    }
    Ok(())
}

/// The curve each segment's arcs aim at and the tolerance about it: the profile itself within
/// the tolerance, or on one side the profile offset into the band, each offset stopped where
/// it crosses its neighbour's at a corner (also across 0°/360° on a closed cam).
fn aimed_curves(ordered: &[&Segment], options: &CamOptions) -> Result<Vec<(Piece, f64)>, CamError> {
    let mut curves = Vec::with_capacity(ordered.len());
    for s in ordered {
        let in_row = |error| CamError::Segment { row: s.label(), error };
        let aimed = side_curve(&s.piece, options.tolerance, options.side, options.reserve).map_err(in_row)?;
        curves.push(aimed.unwrap_or((s.piece, options.tolerance)));
    }
    if options.side == Side::Both || ordered.len() < 2 {
        return Ok(curves);
    }
    let n = ordered.len();
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (&ordered[i].piece, &ordered[j].piece);
        let wraps = j == 0 && (a.phi1_deg - 360.0).abs() <= SAME && b.phi0_deg.abs() <= SAME;
        let meets = (a.phi1_deg - b.phi0_deg).abs() <= SAME || wraps;
        if !meets || (a.r1 - b.r0).abs() > SAME {
            continue;
        }
        if let Some((s, u)) = offset_crossing(&curves[i].0, &curves[j].0) {
            curves[i].0 = curves[i].0.trimmed(0.0, s);
            curves[j].0 = curves[j].0.trimmed(u, 1.0);
        }
    }
    Ok(curves)
}

/// The segments grouped by disc, discs in order of first appearance; a map from name to place
/// finds each disc, so a sheet of many discs costs its rows, not rows × discs.
pub fn by_disc(segments: &[Segment]) -> Vec<(String, Vec<Segment>)> {
    let mut discs: Vec<(String, Vec<Segment>)> = Vec::new();
    let mut place: HashMap<&str, usize> = HashMap::new();
    for s in segments {
        let i = *place.entry(s.disc.as_str()).or_insert_with(|| {
            discs.push((s.disc.clone(), Vec::new()));
            discs.len() - 1
        });
        discs[i].1.push(s.clone());
    }
    discs
}
