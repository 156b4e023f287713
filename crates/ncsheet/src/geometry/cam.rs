//! Cam discs for automatic lathes (docs/domain.md §5, Gulyás & Nyitrai): spiral pieces, their
//! replacement by tangent arcs within a tolerance, whole cams from a design sheet, and the
//! texts a mill and a designer need (coordinate table, NC program, drawing).
//!
//! - [`piece`]: circle, Archimedean, logarithmic and parabolic pieces about the cam centre.
//! - [`arc`]: the arc an NC control cuts, with exact distances.
//! - [`fit`]: the arc-spline fitter (on either side of the curve or on one), its lower bound
//!   and an independent deviation check.
//! - [`profile`]: whole cams: coverage check (gaps, overlaps, steps) and every segment's arcs.
//! - [`reach`]: what a cutter of a given radius reaches with the control's compensation:
//!   concave places it cannot reach rounded by a tangent arc, and how much is left there.
//!
//! The design sheet, the coordinate table and the drawing are in `nc::cam_sheet`; the milling
//! program is built on the NC model in `nc::cam`.
//!
//! **Architecture Invariant:** nothing here reads or writes files or prints.
//!
//! Units at the interface: mm and degrees; radians only inside.

pub mod arc;
pub mod fit;
pub mod piece;
pub mod profile;
pub mod reach;

pub use arc::{Arc, Turn};
pub use fit::{deviation, fit_piece, fit_piece_on_side, lower_bound, Deviation, Side};
pub use piece::{Piece, PieceKind};
pub use profile::{
    by_disc, check_coverage, fit_cam, CamError, CamFit, CamOptions, CoverageIssue, FittedSegment, Segment,
    MAX_CAM_ARCS, MAX_OVERLAPS_LISTED,
};
