//! Excel's error values. They are syntax (`#N/A` can be typed) as well as results.

use std::fmt;
use std::str::FromStr;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum XlError {
    Null,
    Div0,
    Value,
    Ref,
    Name,
    Num,
    NA,
    GettingData,
    Spill,
    Calc,
    /// A cell that is part of a circular reference (Excel warns and shows 0; we refuse to guess).
    Circ,
}

impl XlError {
    pub const ALL: [XlError; 11] = [
        XlError::Null,
        XlError::Div0,
        XlError::Value,
        XlError::Ref,
        XlError::Name,
        XlError::Num,
        XlError::NA,
        XlError::GettingData,
        XlError::Spill,
        XlError::Calc,
        XlError::Circ,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            XlError::Null => "#NULL!",
            XlError::Div0 => "#DIV/0!",
            XlError::Value => "#VALUE!",
            XlError::Ref => "#REF!",
            XlError::Name => "#NAME?",
            XlError::Num => "#NUM!",
            XlError::NA => "#N/A",
            XlError::GettingData => "#GETTING_DATA",
            XlError::Spill => "#SPILL!",
            XlError::Calc => "#CALC!",
            XlError::Circ => "#CIRC!",
        }
    }

    /// Excel's `ERROR.TYPE` number.
    pub fn type_number(self) -> u8 {
        match self {
            XlError::Null => 1,
            XlError::Div0 => 2,
            XlError::Value => 3,
            XlError::Ref => 4,
            XlError::Name => 5,
            XlError::Num => 6,
            XlError::NA => 7,
            XlError::GettingData => 8,
            XlError::Spill => 9,
            XlError::Calc => 14,
            XlError::Circ => 4,
        }
    }
}

impl fmt::Display for XlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for XlError {
    type Err = ();

    fn from_str(s: &str) -> Result<XlError, ()> {
        XlError::ALL.into_iter().find(|e| e.as_str().eq_ignore_ascii_case(s.trim())).ok_or(())
    }
}
