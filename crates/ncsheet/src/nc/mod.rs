//! NC programs: the model ([`program`]) that macros and geometry commands fill, and the
//! dialects ([`dialect`]) that write it for a control; beside them what a fitted cam is
//! designed from and checked by ([`cam_sheet`]). Knows nothing of workbooks or files.

pub mod apt;
pub mod backplot;
pub mod ballpath;
pub mod cam;
pub mod cam_sheet;
pub mod check;
pub mod dda;
pub mod dialect;
pub mod format;
pub mod motion;
pub mod post;
pub mod program;
pub mod read;
pub(crate) mod svg;

pub use dialect::{by_name, Dialect, NcError};
pub use program::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Subprogram,
    SubprogramCall, Target, ToolChange, ToolOffset, Word,
};
