//! Reads a cam design sheet from csv text: one segment per row, columns named in a header
//! `row,operation,disc,type,from_deg,to_deg,r_start,r_end` (any order; `row`, `operation` and
//! `disc` may be left out). Angles in degrees, radii in mm, type "circle", "arch" or "log".
//!
//! This is a file format, which belongs in `src/io`; it lives here, as a pure function over
//! text, until the `ncsheet cam` command moves it there.

use super::piece::{Piece, PieceKind};
use super::profile::{CamError, Segment};

const REQUIRED: [&str; 5] = ["type", "from_deg", "to_deg", "r_start", "r_end"];

/// The segments of a design sheet, in the order written.
pub fn parse_sheet(text: &str) -> Result<Vec<Segment>, CamError> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| CamError::Sheet { line: 1, message: format!("header: {e}") })?
        .iter()
        .map(|h| h.to_ascii_lowercase())
        .collect();
    let column = |name: &str| header.iter().position(|h| h == name);
    for name in REQUIRED {
        if column(name).is_none() {
            let message = format!("the header has no column '{name}' (needs {})", REQUIRED.join(", "));
            return Err(CamError::Sheet { line: 1, message });
        }
    }
    let mut segments = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| CamError::Sheet {
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.iter().all(|f| f.is_empty()) {
            continue;
        }
        let text = |name: &str| column(name).and_then(|i| record.get(i)).unwrap_or("").to_string();
        let number = |name: &str| {
            let field = text(name);
            field
                .parse::<f64>()
                .map_err(|_| CamError::Sheet { line, message: format!("{name} '{field}' is not a number") })
        };
        let row = text("row");
        let in_row = |error| CamError::Segment { row: format!("row {row} (line {line})"), error };
        let kind = PieceKind::parse(&text("type")).map_err(in_row)?;
        let (from, to, r_start, r_end) = (number("from_deg")?, number("to_deg")?, number("r_start")?, number("r_end")?);
        let piece = Piece::new(kind, r_start, from, r_end, to).map_err(in_row)?;
        segments.push(Segment { row: row.clone(), operation: text("operation"), disc: text("disc"), line, piece });
    }
    Ok(segments)
}
