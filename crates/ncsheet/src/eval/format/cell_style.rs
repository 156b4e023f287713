//! How a cell looks beyond its number format: what a macro sets (`HorizontalAlignment`,
//! `VerticalAlignment`, `Font.Bold`, `Font.Italic`, `WrapText`, `Interior.Color`) and an xlsx
//! keeps in the cell's style (`<xf>` of styles.xml). Nothing here changes a value: it rides
//! along from the macro to the saved file.

/// The parts of a cell's style ncsheet keeps; the default is Excel's Normal style.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CellStyle {
    /// Excel's XlHAlign value (`xlLeft` -4131, `xlCenter` -4108, `xlRight` -4152 …); `None`:
    /// General (text left, numbers right).
    pub horizontal: Option<i32>,
    /// Excel's XlVAlign value (`xlTop` -4160, `xlCenter` -4108 …); `None`: bottom.
    pub vertical: Option<i32>,
    pub bold: bool,
    pub italic: bool,
    pub wrap: bool,
    /// The fill's colour as VBA's `RGB` gives it (red in the low byte); `None`: no fill.
    pub fill: Option<u32>,
}

/// XlHAlign ("XlHAlign enumeration", Excel VBA reference).
pub const XL_GENERAL: i32 = 1;
pub const XL_LEFT: i32 = -4131;
pub const XL_CENTER: i32 = -4108;
pub const XL_RIGHT: i32 = -4152;
pub const XL_FILL: i32 = 5;
pub const XL_JUSTIFY: i32 = -4130;
pub const XL_CENTER_ACROSS_SELECTION: i32 = 7;
pub const XL_DISTRIBUTED: i32 = -4117;
/// XlVAlign ("XlVAlign enumeration"): besides `xlCenter`, `xlJustify`, `xlDistributed`.
pub const XL_TOP: i32 = -4160;
pub const XL_BOTTOM: i32 = -4107;

/// Whether `v` is one of XlHAlign's values.
pub fn is_horizontal(v: i32) -> bool {
    [XL_GENERAL, XL_LEFT, XL_CENTER, XL_RIGHT, XL_FILL, XL_JUSTIFY, XL_CENTER_ACROSS_SELECTION, XL_DISTRIBUTED]
        .contains(&v)
}

/// Whether `v` is one of XlVAlign's values.
pub fn is_vertical(v: i32) -> bool {
    [XL_TOP, XL_CENTER, XL_BOTTOM, XL_JUSTIFY, XL_DISTRIBUTED].contains(&v)
}

impl CellStyle {
    /// Nothing but the Normal style.
    pub fn is_plain(&self) -> bool {
        *self == CellStyle::default()
    }
}
