//! How a cell looks beyond its number format: what a macro sets (`HorizontalAlignment`,
//! `VerticalAlignment`, `Font.Bold`, `Font.Italic`, `Font.Color`, `Font.Size`, `Font.Underline`,
//! `WrapText`, `Interior.Color`) and an xlsx
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
    /// The font's colour as VBA's `RGB` gives it; `None`: automatic (black), as a new cell.
    pub font_color: Option<u32>,
    /// The font's size in twentieths of a point (as Excel's own BIFF records keep it);
    /// `None`: the Normal style's.
    pub font_size: Option<u16>,
    /// Excel's XlUnderlineStyle of the font; `None`: not underlined.
    pub underline: Option<i32>,
}

/// XlUnderlineStyle ("XlUnderlineStyle enumeration", Excel VBA reference).
pub const XL_UNDERLINE_SINGLE: i32 = 2;
pub const XL_UNDERLINE_DOUBLE: i32 = -4119;
pub const XL_UNDERLINE_SINGLE_ACCOUNTING: i32 = 4;
pub const XL_UNDERLINE_DOUBLE_ACCOUNTING: i32 = 5;
/// xlUnderlineStyleNone, also xlNone.
pub const XL_UNDERLINE_NONE: i32 = -4142;

/// Whether `v` is one of XlUnderlineStyle's underlines (xlUnderlineStyleNone aside).
pub fn is_underline(v: i32) -> bool {
    [XL_UNDERLINE_SINGLE, XL_UNDERLINE_DOUBLE, XL_UNDERLINE_SINGLE_ACCOUNTING, XL_UNDERLINE_DOUBLE_ACCOUNTING]
        .contains(&v)
}

/// Excel's default palette, the colours of ColorIndex 1 to 56 as RRGGBB (Microsoft's
/// "ColorIndex property" page; the same as ECMA-376 18.8.27's indexedColors 8 to 63).
const PALETTE: [u32; 56] = [
    0x000000, 0xFFFFFF, 0xFF0000, 0x00FF00, 0x0000FF, 0xFFFF00, 0xFF00FF, 0x00FFFF, // 1-8
    0x800000, 0x008000, 0x000080, 0x808000, 0x800080, 0x008080, 0xC0C0C0, 0x808080, // 9-16
    0x9999FF, 0x993366, 0xFFFFCC, 0xCCFFFF, 0x660066, 0xFF8080, 0x0066CC, 0xCCCCFF, // 17-24
    0x000080, 0xFF00FF, 0xFFFF00, 0x00FFFF, 0x800080, 0x800000, 0x008080, 0x0000FF, // 25-32
    0x00CCFF, 0xCCFFFF, 0xCCFFCC, 0xFFFF99, 0x99CCFF, 0xFF99CC, 0xCC99FF, 0xFFCC99, // 33-40
    0x3366FF, 0x33CCCC, 0x99CC00, 0xFFCC00, 0xFF9900, 0xFF6600, 0x666699, 0x969696, // 41-48
    0x003366, 0x339966, 0x003300, 0x333300, 0x993300, 0x993366, 0x333399, 0x333333, // 49-56
];

/// An RRGGBB colour as VBA's `RGB` gives it (red in the low byte), and back: the swap is
/// its own inverse.
pub fn swap_red_blue(c: u32) -> u32 {
    ((c & 0xFF) << 16) | (c & 0xFF00) | ((c >> 16) & 0xFF)
}

/// The colour of palette index `index` (1 to 56) as VBA's `RGB` gives it.
pub fn palette_color(index: u32) -> Option<u32> {
    let rrggbb = *PALETTE.get((index as usize).checked_sub(1)?)?;
    Some(swap_red_blue(rrggbb))
}

/// The palette index whose colour is nearest `color` (VBA's `RGB` form), the lowest of equals:
/// Excel's ColorIndex of a colour the palette lacks is "the closest color in the palette".
pub fn nearest_palette_index(color: u32) -> u32 {
    let rgb = swap_red_blue(color);
    let channels = |c: u32| [(c >> 16) & 0xFF, (c >> 8) & 0xFF, c & 0xFF].map(i64::from);
    let distance = |p: u32| -> i64 {
        let (a, b) = (channels(rgb), channels(p));
        (0..3).map(|i| (a[i] - b[i]).pow(2)).sum()
    };
    let best = (0..PALETTE.len()).min_by_key(|&i| (distance(PALETTE[i]), i)).unwrap_or(0);
    best as u32 + 1
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
