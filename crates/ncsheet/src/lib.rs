//! ncsheet: a spreadsheet formula engine for CNC programming.
//!
//! # Where a front end starts
//!
//! A front end (the `ncsheet` command line, the workbench server, a binding) works on one
//! [`Document`]: a workbook opened from bytes ([`Document::open`], the format detected from
//! the bytes, [`OpenOptions`] for the name, csv delimiter, read limits and [`Settings`]), with
//! its VBA functions installed and its import notes kept. It edits cells ([`Document::set`],
//! typed input in the document's [`Locale`]), recalculates, reports [`Problem`]s as data,
//! shows a cell as its format shows it ([`Document::shown`]) and saves to bytes
//! ([`Document::save_as`] with a [`SaveFormat`], or [`Document::encode`]) with the list of
//! what the saved file loses; [`io::Encoded::write`] is the one atomic write to a path.
//! Cells are named by [`SheetId`] and [`Pos`] (or [`Document::cell`] from `Outer!B8`); their
//! values are [`Value`]s. Everything a document depends on is in its [`Settings`] (date
//! system, clock, random state, locale, limits): there is no ambient state, so documents are
//! independent of each other on one thread.
//!
//! ```
//! use ncsheet::{Document, OpenOptions, SaveFormat};
//!
//! // The shipped chamfer workbook: α = 30° in Outer!B8 moves the tool tip's XA (Outer!G6).
//! let bytes = std::fs::read("../../sheets/chamfer.xlsx")?;
//! let mut doc = Document::open(bytes, &OpenOptions::named("chamfer.xlsx"))?;
//! let (sheet, alpha) = doc.cell("Outer!B8").expect("a cell name");
//! doc.set(sheet, alpha, "30").expect("a number is accepted");
//! let (sheet, xa) = doc.cell("Outer!G6").expect("a cell name");
//! assert_eq!(doc.shown(sheet, xa), "42.325982");
//! let saved = doc.save_as(SaveFormat::Xlsx)?;
//! assert!(saved.losses.is_empty() && saved.bytes().starts_with(b"PK"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Beside documents, the library offers what the command line's other jobs need, each a
//! public module below: NC programs in their dialects ([`nc`]: [`nc::Program`],
//! [`nc::dialect::all`], readers, checks, posts, cam and ball-path programs), the pure
//! machining geometry ([`geometry`]: chamfers, head angles, cam arc fits, ball paths), VBA
//! macros ([`vba::run`]) and the file layer ([`io`]).
//!
//! # Layers
//!
//! Each uses only those before it: [`formula`] (grammar, syntax tree) → [`eval`] (values,
//! evaluator, functions) → [`workbook`] (cells, dependency graph, recalculation) → [`io`]
//! (csv, xlsx, the legacy formats) and [`nc`] (NC programs) → [`document`]; [`vba`] (macros)
//! runs on a workbook and fills an [`nc`] program. [`geometry`] is pure and stands apart; the
//! evaluator registers it as sheet functions. See ARCHITECTURE.md. Test helpers
//! (`eval::testing`) exist only with the `testing` feature and are not part of this API.

pub mod document;
pub mod eval;
pub mod formula;
pub mod geometry;
pub mod io;
pub mod nc;
pub mod vba;
pub mod workbook;

pub use document::{Document, OpenOptions, SaveFormat};
pub use eval::{Locale, Settings, Value, XlError};
pub use formula::address::{Pos, Rect};
pub use formula::ast::SheetId;
pub use workbook::{Problem, ProblemKind, Workbook};
