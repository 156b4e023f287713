//! ncsheet's own limits on what a file may make it hold (docs/limits.md): how far one part
//! of an xlsx package may inflate, and how long a csv field or line may be. Files Excel
//! writes stay far inside them; a file past one is refused with an error naming the limit
//! and the option that raises it, before it exhausts memory.
//!
//! They are the caller's, passed with each read (a document's `OpenOptions::read_limits`;
//! the command line's options), never state of the process: two documents opened side by
//! side may have different limits.

/// The limits a read applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadLimits {
    /// Bytes one part of an xlsx package may inflate to (`--max-part-size`).
    pub part_bytes: u64,
    /// Inflated bytes per compressed byte a part may reach past [`RATIO_GRACE`]
    /// (`--max-zip-ratio`).
    pub zip_ratio: u64,
    /// Bytes of one csv field (`--max-csv-field`).
    pub csv_field_bytes: u64,
    /// Bytes of one csv line, a record with all its fields (`--max-csv-line`).
    pub csv_line_bytes: u64,
}

/// A part inflating to less than this is not held to the ratio: small parts compress
/// unevenly and cannot exhaust anything.
pub const RATIO_GRACE: u64 = 1 << 20;

impl Default for ReadLimits {
    fn default() -> ReadLimits {
        ReadLimits { part_bytes: 1 << 30, zip_ratio: 100, csv_field_bytes: 1 << 20, csv_line_bytes: 64 << 20 }
    }
}

/// A byte count as a person reads it: `1 GiB`, `64 MiB`, `1000 bytes`.
pub fn bytes(n: u64) -> String {
    const UNITS: [(u64, &str); 3] = [(1 << 30, "GiB"), (1 << 20, "MiB"), (1 << 10, "KiB")];
    for (size, unit) in UNITS {
        if n >= size && n.is_multiple_of(size) {
            return format!("{} {unit}", n / size);
        }
        if n >= size {
            return format!("{:.1} {unit}", n as f64 / size as f64);
        }
    }
    format!("{n} bytes")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_written() {
        assert_eq!(bytes(1 << 30), "1 GiB");
        assert_eq!(bytes(64 << 20), "64 MiB");
        assert_eq!(bytes(1000), "1000 bytes");
        assert_eq!(bytes(4_586_430), "4.4 MiB");
    }
}
