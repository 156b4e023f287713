//! Cam discs for automatic lathes (DOMAIN.md §5, Gulyás & Nyitrai): spiral pieces, their
//! replacement by tangent arcs within a tolerance, whole cams from a design sheet, and the
//! texts a mill and a designer need (coordinate table, NC program, drawing).
//!
//! - [`piece`]: circle, Archimedean and logarithmic pieces about the cam centre.
//! - [`arc`]: the arc an NC control cuts, with exact distances.
//! - [`fit`]: the arc-spline fitter, its lower bound and an independent deviation check.
//! - [`profile`]: whole cams: coverage check (gaps, overlaps, steps) and every segment's arcs.
//! - [`sheet`]: the design sheet as csv text.
//! - [`output`]: the coordinate table, the NC program and the SVG drawing, as strings.
//!
//! **Architecture Invariant:** nothing here reads or writes files or prints; [`sheet`] and
//! [`output`] take and give text. They are file formats and an NC writer, so they move to
//! `src/io` and `src/nc` (behind the dialect layer) when the `ncsheet cam` command arrives.
//!
//! Units at the interface: mm and degrees; radians only inside.

pub mod arc;
pub mod fit;
pub mod output;
pub mod piece;
pub mod profile;
pub mod sheet;

pub use arc::{Arc, Turn};
pub use fit::{deviation, fit_piece, lower_bound, Deviation};
pub use piece::{Piece, PieceKind};
pub use profile::{
    by_disc, check_coverage, fit_cam, fit_design_sheet, CamError, CamFit, CamOptions, CoverageIssue, FittedSegment,
    Segment,
};
pub use sheet::parse_sheet;
