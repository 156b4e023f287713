//! The styles part (`xl/styles.xml`) of a package saved by patching, with the cell styles a
//! macro gave cells appended: each new style is the cell's old one (`<xf>` of `cellXfs`:
//! its border, protection and the rest kept) with the number format, font, fill and
//! alignment the cell's look asks for. Fonts are the old style's font with `<b/>` and `<i/>`
//! set as asked; fills are solid (ECMA-376 18.8.32: a solid fill's colour is its
//! foreground). Every existing element stays where it is, so the styles other cells name
//! keep their numbers.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::eval::format::cell_style::{self, CellStyle};
use crate::formula::address::{Pos, MAX_COLS};
use crate::workbook::SheetLook;

use super::patch::{attr, find_tag, remove_attr, root_prefix};
use super::write::builtin_date_format;

/// The first number a format of the file's own may take (ids below are Excel's built-ins).
const FIRST_CUSTOM_FORMAT: u32 = 164;

/// Excel's built-in number formats whose code is the same in every locale (ECMA-376
/// 18.8.30), by id; its dates are `builtin_date_format`'s.
const BUILTIN_FORMATS: &[(u32, &str)] = &[
    (0, "General"),
    (1, "0"),
    (2, "0.00"),
    (3, "#,##0"),
    (4, "#,##0.00"),
    (9, "0%"),
    (10, "0.00%"),
    (11, "0.00E+00"),
    (12, "# ?/?"),
    (13, "# ??/??"),
    (45, "mm:ss"),
    (46, "[h]:mm:ss"),
    (47, "mmss.0"),
    (48, "##0.0E+0"),
    (49, "@"),
];

/// One container of the styles part (`<fonts>`): where its children end, and them.
struct Container {
    /// Byte offset of `</fonts>` (or of the `/>` of an empty `<fonts/>`).
    close: usize,
    children: Vec<String>,
    added: Vec<String>,
}

/// The styles part with the styles a patched save adds.
pub(super) struct StyleSheet {
    xml: String,
    ns: String,
    formats: Vec<(u32, String)>,
    new_formats: Vec<(u32, String)>,
    fonts: Container,
    fills: Container,
    xfs: Container,
    /// Styles made already: (old style, format, look, the file's look) → new style.
    made: HashMap<(u32, Option<String>, CellStyle, CellStyle), u32>,
    /// Why the styles asked for cannot be added to this part (the package is then written anew).
    unpatchable: Option<String>,
}

impl StyleSheet {
    pub(super) fn read(xml: String) -> Result<StyleSheet, String> {
        let ns = root_prefix(&xml).to_string();
        let q = |name: &str| format!("{ns}{name}");
        let formats = children(&xml, &q("numFmts"), &q("numFmt"))
            .map(|c| {
                c.children
                    .iter()
                    .filter_map(|f| Some((attr(f, "numFmtId")?.parse().ok()?, unescape(attr(f, "formatCode")?))))
                    .collect()
            })
            .unwrap_or_default();
        let fonts = children(&xml, &q("fonts"), &q("font")).ok_or("no <fonts>")?;
        let fills = children(&xml, &q("fills"), &q("fill")).ok_or("no <fills>")?;
        let xfs = children(&xml, &q("cellXfs"), &q("xf")).ok_or("no <cellXfs>")?;
        Ok(StyleSheet {
            xml,
            ns,
            formats,
            new_formats: Vec::new(),
            fonts,
            fills,
            xfs,
            made: HashMap::new(),
            unpatchable: None,
        })
    }

    /// The style a cell of style `old` gets to show `format` (`None`: General) and `look`;
    /// what `look` has as `was` (the file's look) keeps the old style's fill and alignment,
    /// which may say more than a look does (a patterned fill, an indent).
    pub(super) fn style_for(&mut self, old: u32, format: Option<&str>, look: CellStyle, was: CellStyle) -> u32 {
        let key = (old, format.map(str::to_string), look, was);
        if let Some(&s) = self.made.get(&key) {
            return s;
        }
        let base = self.xfs.children.get(old as usize).or(self.xfs.children.first()).cloned();
        let base = base.unwrap_or_else(|| format!("<{}xf/>", self.ns));
        let format_id = self.format_id(format.unwrap_or("General"));
        let font_id = self.font_for(attr(&base, "fontId").and_then(|f| f.parse().ok()).unwrap_or(0), look, was);
        let fill_id = match look.fill == was.fill {
            true => attr(&base, "fillId").and_then(|f| f.parse().ok()).unwrap_or(0),
            false => self.fill_for(look.fill),
        };
        let alignment = (look.horizontal, look.vertical, look.wrap) != (was.horizontal, was.vertical, was.wrap);
        let xf = self.xf(&base, format_id, font_id, fill_id, alignment.then_some(look));
        let id = (self.xfs.children.len() + self.xfs.added.len()) as u32;
        self.xfs.added.push(xf);
        self.made.insert(key, id);
        id
    }

    /// A built-in format's id, the file's own format's with the same code, or a new one.
    fn format_id(&mut self, code: &str) -> u32 {
        if let Some((id, _)) = BUILTIN_FORMATS.iter().find(|(_, c)| c.eq_ignore_ascii_case(code)) {
            return *id;
        }
        if let Some(id) = builtin_date_format(code) {
            return u32::from(id);
        }
        let known = self.formats.iter().chain(&self.new_formats).find(|(_, c)| c == code);
        if let Some((id, _)) = known {
            return *id;
        }
        let highest = self.formats.iter().chain(&self.new_formats).map(|(id, _)| *id).max();
        let Some(id) =
            highest.map_or(Some(FIRST_CUSTOM_FORMAT), |h| h.checked_add(1).map(|n| n.max(FIRST_CUSTOM_FORMAT)))
        else {
            self.unpatchable = Some(format!("the styles part has no number format id left after {}", u32::MAX));
            return 0;
        };
        self.new_formats.push((id, code.to_string()));
        id
    }

    /// Why the styles asked for could not be added to this part, if they could not.
    pub(super) fn unpatchable(&self) -> Option<&str> {
        self.unpatchable.as_deref()
    }

    /// The font `old` with bold and italic as `look` has them, and its colour, size and
    /// underline where `look` changed them from the file's look `was` (the old font may say
    /// more: a theme colour with a tint).
    fn font_for(&mut self, old: u32, look: CellStyle, was: CellStyle) -> u32 {
        let ns = &self.ns;
        let base = self.fonts.children.get(old as usize).or(self.fonts.children.first());
        let base = base.cloned().unwrap_or_else(|| format!("<{ns}font/>"));
        let mut inner = match base.find('>') {
            Some(gt) if !base[..gt].ends_with('/') => {
                base[gt + 1..].trim_end().trim_end_matches(&format!("</{ns}font>")).to_string()
            }
            _ => String::new(),
        };
        let mut changed = vec!["b", "i"];
        let mut marks = String::new();
        if look.bold {
            marks.push_str(&format!("<{ns}b/>"));
        }
        if look.italic {
            marks.push_str(&format!("<{ns}i/>"));
        }
        if look.underline != was.underline {
            changed.push("u");
            marks.push_str(&underline_element(ns, look.underline));
        }
        if look.font_size != was.font_size {
            changed.push("sz");
            // 11 points, Excel's Normal size, is what a look without a size shows.
            let twentieths = look.font_size.unwrap_or(220);
            marks.push_str(&format!("<{ns}sz val=\"{}\"/>", f64::from(twentieths) / 20.0));
        }
        if look.font_color != was.font_color {
            changed.push("color");
            marks.push_str(&match look.font_color {
                Some(bgr) => format!("<{ns}color rgb=\"FF{:06X}\"/>", cell_style::swap_red_blue(bgr)),
                None => format!("<{ns}color auto=\"1\"/>"),
            });
        }
        for name in changed {
            inner = without_element(&inner, &format!("{ns}{name}"));
        }
        let font = format!("<{ns}font>{marks}{inner}</{ns}font>");
        find_or_add(&mut self.fonts, font)
    }

    /// Fill 0 (the file's "none") without a colour, else a solid fill of it.
    fn fill_for(&mut self, colour: Option<u32>) -> u32 {
        let Some(rgb) = colour else { return 0 };
        let ns = &self.ns;
        let (r, g, b) = (rgb & 0xFF, (rgb >> 8) & 0xFF, (rgb >> 16) & 0xFF);
        let fill = format!(
            "<{ns}fill><{ns}patternFill patternType=\"solid\"><{ns}fgColor rgb=\"FF{r:02X}{g:02X}{b:02X}\"/>\
             <{ns}bgColor indexed=\"64\"/></{ns}patternFill></{ns}fill>"
        );
        find_or_add(&mut self.fills, fill)
    }

    /// The `<xf>` `base` with the format, font and fill given, and the alignment of `look`
    /// (`None`: the base's own).
    fn xf(&self, base: &str, format_id: u32, font_id: u32, fill_id: u32, look: Option<CellStyle>) -> String {
        let ns = &self.ns;
        let gt = base.find('>').unwrap_or(base.len() - 1);
        let empty = base[..gt].ends_with('/');
        let mut tag = base[..gt].trim_end_matches('/').to_string();
        for name in ["numFmtId", "fontId", "fillId", "applyNumberFormat", "applyFont", "applyFill", "applyAlignment"] {
            tag = remove_attr(&tag, name);
        }
        let tag = format!(
            "{} numFmtId=\"{format_id}\" fontId=\"{font_id}\" fillId=\"{fill_id}\" applyNumberFormat=\"1\" \
             applyFont=\"1\" applyFill=\"1\" applyAlignment=\"1\">",
            tag.trim_end()
        );
        let inner = if empty {
            String::new()
        } else {
            base[gt + 1..].trim_end().trim_end_matches(&format!("</{ns}xf>")).to_string()
        };
        let Some(look) = look else { return format!("{tag}{inner}</{ns}xf>") };
        let inner = without_element(&inner, &format!("{ns}alignment"));
        format!("{tag}{}{inner}</{ns}xf>", alignment(ns, look))
    }

    /// The styles part with the new formats, fonts, fills and styles appended and counted.
    pub(super) fn finish(self) -> String {
        let ns = &self.ns;
        // (start, end, text): the text replaces the bytes start..end (none for an insertion).
        let mut inserts: Vec<(usize, usize, String)> = Vec::new();
        let mut counts: Vec<(String, usize)> = Vec::new();
        for (name, c) in [("fonts", &self.fonts), ("fills", &self.fills), ("cellXfs", &self.xfs)] {
            if !c.added.is_empty() {
                inserts.push((c.close, c.close, c.added.concat()));
                counts.push((format!("{ns}{name}"), c.children.len() + c.added.len()));
            }
        }
        let mut xml = self.xml.clone();
        if !self.new_formats.is_empty() {
            let made: String = self
                .new_formats
                .iter()
                .map(|(id, code)| format!("<{ns}numFmt numFmtId=\"{id}\" formatCode=\"{}\"/>", escape(code)))
                .collect();
            let total = self.formats.len() + self.new_formats.len();
            let container = format!("<{ns}numFmts count=\"{total}\">{made}</{ns}numFmts>");
            match children(&xml, &format!("{ns}numFmts"), &format!("{ns}numFmt")) {
                Some(c) => {
                    inserts.push((c.close, c.close, made));
                    counts.push((format!("{ns}numFmts"), total));
                }
                None => match self_closed(&xml, &format!("{ns}numFmts")) {
                    // An empty `<numFmts/>` becomes the container of the new formats.
                    Some(tag) => inserts.push((tag.start, tag.end, container)),
                    None => {
                        // `<numFmts>` comes first in the styleSheet (ECMA-376 18.8.39).
                        let at = find_tag(&xml, &format!("{ns}fonts"), 0).unwrap_or(self.fonts.close);
                        inserts.push((at, at, container));
                    }
                },
            }
        }
        inserts.sort_by_key(|(at, _, _)| std::cmp::Reverse(*at));
        for (start, end, text) in inserts {
            xml.replace_range(start..end, &text);
        }
        for (name, count) in counts {
            xml = with_count(&xml, &name, count);
        }
        xml
    }
}

/// What a macro changed of a sheet's look, against the look the file had: cells by
/// (row, column) with the format (`None`: General) and style they show now, columns' widths
/// and rows' heights.
#[derive(Default)]
pub(super) struct Restyle {
    /// (format, style, the style the file gave the cell).
    pub cells: BTreeMap<(u32, u32), (Option<String>, CellStyle, CellStyle)>,
    pub widths: BTreeMap<u32, f64>,
    pub heights: BTreeMap<u32, f64>,
    /// Rows and columns hidden (true) or shown again (false).
    pub rows_hidden: BTreeMap<u32, bool>,
    pub columns_hidden: BTreeMap<u32, bool>,
}

impl Restyle {
    pub(super) fn between(was: &SheetLook, now: &SheetLook) -> Restyle {
        let look_of = |l: &SheetLook, pos: &Pos| {
            (l.number_formats.get(pos).cloned(), l.cell_styles.get(pos).copied().unwrap_or_default())
        };
        let positions: BTreeSet<Pos> =
            [was, now].iter().flat_map(|l| l.number_formats.keys().chain(l.cell_styles.keys())).copied().collect();
        let cells = positions
            .into_iter()
            .filter_map(|pos| {
                let (is, had) = (look_of(now, &pos), look_of(was, &pos));
                (had != is).then_some(((pos.row, pos.col), (is.0, is.1, had.1)))
            })
            .collect();
        let changed = |was: &[(u32, f64)], now: &[(u32, f64)]| {
            let was: BTreeMap<u32, f64> = was.iter().copied().collect();
            let now: BTreeMap<u32, f64> = now.iter().copied().collect();
            now.into_iter().filter(|(line, size)| was.get(line) != Some(size)).collect::<BTreeMap<u32, f64>>()
        };
        let widths_of = |l: &SheetLook| l.column_widths.iter().map(|&(c, w)| (u32::from(c), w)).collect::<Vec<_>>();
        Restyle {
            cells,
            widths: changed(&widths_of(was), &widths_of(now)),
            heights: changed(&was.row_heights, &now.row_heights),
            rows_hidden: hidden_changes(was.hidden_rows.iter().copied(), now.hidden_rows.iter().copied()),
            columns_hidden: hidden_changes(
                was.hidden_columns.iter().map(|&c| u32::from(c)),
                now.hidden_columns.iter().map(|&c| u32::from(c)),
            ),
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.cells.is_empty()
            && self.widths.is_empty()
            && self.heights.is_empty()
            && self.rows_hidden.is_empty()
            && self.columns_hidden.is_empty()
    }
}

/// The lines hidden now and not before (true), and those shown again (false).
fn hidden_changes(was: impl Iterator<Item = u32>, now: impl Iterator<Item = u32>) -> BTreeMap<u32, bool> {
    let (was, now): (BTreeSet<u32>, BTreeSet<u32>) = (was.collect(), now.collect());
    let hidden = now.difference(&was).map(|&l| (l, true));
    hidden.chain(was.difference(&now).map(|&l| (l, false))).collect()
}

/// A `<row>` start tag hidden (`hidden="1"`) or shown (no `hidden`).
pub(super) fn with_hidden(tag: &str, hidden: bool) -> String {
    let closing = if tag.ends_with("/>") { "/>" } else { ">" };
    let head = remove_attr(&tag[..tag.len() - closing.len()], "hidden");
    let mark = if hidden { " hidden=\"1\"" } else { "" };
    format!("{}{mark}{closing}", head.trim_end())
}

/// A `<row>` start tag with a height a user set (`customHeight`).
pub(super) fn with_height(tag: &str, height: f64) -> String {
    let closing = if tag.ends_with("/>") { "/>" } else { ">" };
    let head = remove_attr(&remove_attr(&tag[..tag.len() - closing.len()], "ht"), "customHeight");
    format!("{} ht=\"{height}\" customHeight=\"1\"{closing}", head.trim_end())
}

/// What a macro changed of one column: its width, whether it is hidden.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct ColumnChange {
    pub width: Option<f64>,
    pub hidden: Option<bool>,
}

/// Each changed column of `restyle` with its new width and hidden mark.
pub(super) fn column_changes(restyle: &Restyle) -> BTreeMap<u32, ColumnChange> {
    let mut changes: BTreeMap<u32, ColumnChange> = BTreeMap::new();
    for (&c, &w) in &restyle.widths {
        changes.entry(c).or_default().width = Some(w);
    }
    for (&c, &h) in &restyle.columns_hidden {
        changes.entry(c).or_default().hidden = Some(h);
    }
    changes
}

/// The part before `<sheetData>` with the columns of `changes` given their widths and hidden
/// marks: each `<col>` range of the file split around them (they keep its other
/// attributes), and `<cols>` added before `<sheetData>` when the file had none.
pub(super) fn with_widths(head: &str, ns: &str, changes: &BTreeMap<u32, ColumnChange>) -> String {
    let (cols, col) = (format!("{ns}cols"), format!("{ns}col"));
    let (before, ranges, after) = match children(head, &cols, &col) {
        Some(c) => {
            let start = find_tag(head, &cols, 0).unwrap_or(0);
            let close_end = c.close + head[c.close..].find('>').map_or(0, |i| i + 1);
            (&head[..start], c.children, &head[close_end..])
        }
        None => (head, Vec::new(), ""),
    };
    let mut out: Vec<(u32, String)> = Vec::new();
    let number = |tag: &str, name: &str| attr(tag, name).and_then(|v| v.parse::<u32>().ok());
    let sized = |from: u32, to: u32, tag: &str, change: ColumnChange| {
        let mut t = tag.trim_end_matches("/>").trim_end_matches('>').to_string();
        for name in ["min", "max"] {
            t = remove_attr(&t, name);
        }
        if let Some(w) = change.width {
            t = remove_attr(&remove_attr(&t, "width"), "customWidth");
            t = format!("{} width=\"{w}\" customWidth=\"1\"", t.trim_end());
        }
        if let Some(hidden) = change.hidden {
            t = remove_attr(&t, "hidden").trim_end().to_string();
            if hidden {
                t.push_str(" hidden=\"1\"");
            }
        }
        let name_end = t.find(|c: char| c.is_whitespace()).unwrap_or(t.len());
        format!("{} min=\"{}\" max=\"{}\"{}/>", &t[..name_end], from + 1, to + 1, &t[name_end..])
    };
    let mut placed: BTreeSet<u32> = BTreeSet::new();
    for tag in &ranges {
        let (Some(min), Some(max)) = (number(tag, "min"), number(tag, "max")) else { continue };
        if min < 1 || min > max || max > MAX_COLS {
            // A range the reader skips too: kept as the file has it, no width applied in it.
            out.push((min.saturating_sub(1), tag.clone()));
            continue;
        }
        let (first, last) = (min - 1, max - 1);
        let mut from = first;
        for (&c, &change) in changes.range(first..=last) {
            if c > from {
                out.push((from, sized(from, c - 1, tag, ColumnChange::default())));
            }
            out.push((c, sized(c, c, tag, change)));
            placed.insert(c);
            from = c + 1;
        }
        if from <= last {
            out.push((from, sized(from, last, tag, ColumnChange::default())));
        }
    }
    let plain = format!("<{col}");
    for (&c, &change) in changes.iter().filter(|(c, _)| !placed.contains(c)) {
        out.push((c, sized(c, c, &plain, change)));
    }
    out.sort_by_key(|(c, _)| *c);
    let list: String = out.into_iter().map(|(_, t)| t).collect();
    let new_cols = format!("<{cols}>{list}</{cols}>");
    if ranges.is_empty() && after.is_empty() {
        // `<cols>` comes right before `<sheetData>` (ECMA-376 18.3.1.99).
        return format!("{before}{new_cols}");
    }
    format!("{before}{new_cols}{after}")
}

/// The `<alignment>` element of a look; empty for Excel's default (General, bottom, no wrap).
fn alignment(ns: &str, look: CellStyle) -> String {
    let horizontal = look.horizontal.and_then(|h| match h {
        cell_style::XL_LEFT => Some("left"),
        cell_style::XL_CENTER => Some("center"),
        cell_style::XL_RIGHT => Some("right"),
        cell_style::XL_FILL => Some("fill"),
        cell_style::XL_JUSTIFY => Some("justify"),
        cell_style::XL_CENTER_ACROSS_SELECTION => Some("centerContinuous"),
        cell_style::XL_DISTRIBUTED => Some("distributed"),
        _ => None,
    });
    let vertical = look.vertical.and_then(|v| match v {
        cell_style::XL_TOP => Some("top"),
        cell_style::XL_CENTER => Some("center"),
        cell_style::XL_JUSTIFY => Some("justify"),
        cell_style::XL_DISTRIBUTED => Some("distributed"),
        _ => None,
    });
    let mut attrs = String::new();
    if let Some(h) = horizontal {
        attrs.push_str(&format!(" horizontal=\"{h}\""));
    }
    if let Some(v) = vertical {
        attrs.push_str(&format!(" vertical=\"{v}\""));
    }
    if look.wrap {
        attrs.push_str(" wrapText=\"1\"");
    }
    if attrs.is_empty() {
        String::new()
    } else {
        format!("<{ns}alignment{attrs}/>")
    }
}

/// The children named `child` of the first `container` element, with where it closes.
fn children(xml: &str, container: &str, child: &str) -> Option<Container> {
    let start = find_tag(xml, container, 0)?;
    let open_end = start + xml[start..].find('>')?;
    if xml[..open_end].ends_with('/') {
        return None;
    }
    let close = open_end + xml[open_end..].find(&format!("</{container}"))?;
    let inner = &xml[open_end + 1..close];
    let mut out = Vec::new();
    let mut at = 0;
    let end_tag = format!("</{child}>");
    while let Some(i) = find_tag(inner, child, at) {
        let gt = i + inner[i..].find('>')?;
        let end = if inner[..gt].ends_with('/') { gt + 1 } else { gt + inner[gt..].find(&end_tag)? + end_tag.len() };
        out.push(inner[i..end].to_string());
        at = end;
    }
    Some(Container { close, children: out, added: Vec::new() })
}

/// Where the first `name` element is, when it is an empty `<name/>`.
fn self_closed(xml: &str, name: &str) -> Option<std::ops::Range<usize>> {
    let start = find_tag(xml, name, 0)?;
    let gt = start + xml[start..].find('>')?;
    xml[..gt].ends_with('/').then_some(start..gt + 1)
}

/// The index of `element` among the container's children, added when new.
fn find_or_add(c: &mut Container, element: String) -> u32 {
    if let Some(i) = c.children.iter().chain(&c.added).position(|e| *e == element) {
        return i as u32;
    }
    c.added.push(element);
    (c.children.len() + c.added.len() - 1) as u32
}

/// `xml` without the (empty or not) elements named `name`.
fn without_element(xml: &str, name: &str) -> String {
    let mut out = xml.to_string();
    while let Some(i) = find_tag(&out, name, 0) {
        let Some(gt) = out[i..].find('>').map(|g| i + g) else { break };
        let end = if out[..gt].ends_with('/') {
            gt + 1
        } else {
            let close = format!("</{name}>");
            match out[gt..].find(&close) {
                Some(c) => gt + c + close.len(),
                None => gt + 1,
            }
        };
        out.replace_range(i..end, "");
    }
    out
}

/// A font's `<u>` for an XlUnderlineStyle (ECMA-376 18.4.13 ST_UnderlineValues), none for
/// no underline.
fn underline_element(ns: &str, underline: Option<i32>) -> String {
    let val = match underline {
        None => return String::new(),
        Some(cell_style::XL_UNDERLINE_DOUBLE) => "double",
        Some(cell_style::XL_UNDERLINE_SINGLE_ACCOUNTING) => "singleAccounting",
        Some(cell_style::XL_UNDERLINE_DOUBLE_ACCOUNTING) => "doubleAccounting",
        Some(_) => "single",
    };
    format!("<{ns}u val=\"{val}\"/>")
}

/// `xml` with the first `name` element's `count` attribute set to `count`.
fn with_count(xml: &str, name: &str, count: usize) -> String {
    let Some(start) = find_tag(xml, name, 0) else { return xml.to_string() };
    let Some(gt) = xml[start..].find('>').map(|g| start + g) else { return xml.to_string() };
    let tag = remove_attr(&xml[start..gt], "count");
    let tag = format!("{} count=\"{count}\"", tag.trim_end_matches('/').trim_end());
    let slash = if xml[..gt].ends_with('/') { "/" } else { "" };
    format!("{}{tag}{slash}{}", &xml[..start], &xml[gt..])
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;").replace('>', "&gt;")
}

fn unescape(text: &str) -> String {
    text.replace("&quot;", "\"").replace("&apos;", "'").replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
}

#[cfg(test)]
mod tests {
    use super::*;

    const STYLES: &str = r#"<styleSheet><fonts count="1"><font><sz val="11"/><name val="Calibri"/></font></fonts><fills count="2"><fill><patternFill patternType="none"/></fill><fill><patternFill patternType="gray125"/></fill></fills><cellXfs count="1"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/></cellXfs></styleSheet>"#;

    #[test]
    fn a_bold_filled_formatted_style_is_appended_with_its_parts() {
        let mut sheet = StyleSheet::read(STYLES.to_string()).unwrap();
        let look = CellStyle { bold: true, fill: Some(0xFF8000), ..CellStyle::default() };
        assert_eq!(sheet.style_for(0, Some("0.000"), look, CellStyle::default()), 1);
        assert_eq!(sheet.style_for(0, Some("0.000"), look, CellStyle::default()), 1);
        let xml = sheet.finish();
        assert!(
            xml.contains(r#"<numFmts count="1"><numFmt numFmtId="164" formatCode="0.000"/></numFmts><fonts"#),
            "{xml}"
        );
        assert!(xml.contains(r#"<font><b/><sz val="11"/><name val="Calibri"/></font></fonts>"#), "{xml}");
        assert!(xml.contains(r#"<fgColor rgb="FF0080FF"/>"#), "{xml}");
        assert!(xml.contains(r#"<fonts count="2">"#) && xml.contains(r#"<fills count="3">"#), "{xml}");
        assert!(xml.contains(r#"<xf borderId="0" numFmtId="164" fontId="1" fillId="2""#), "{xml}");
    }

    /// A macro that only makes a cell bold keeps its style's patterned fill (gray125, which
    /// a look cannot hold) and its alignment's indent and rotation, where they became fill 0
    /// and were dropped; a changed alignment replaces the old one.
    #[test]
    fn what_a_macro_left_alone_keeps_the_old_styles_fill_and_alignment() {
        let styles = STYLES.replace(
            r#"<cellXfs count="1"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/>"#,
            r#"<cellXfs count="2"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/><xf numFmtId="0" fontId="0" fillId="1" borderId="0" applyAlignment="1"><alignment horizontal="left" indent="2" textRotation="45"/></xf>"#,
        );
        let mut sheet = StyleSheet::read(styles).unwrap();
        let was = CellStyle { horizontal: Some(cell_style::XL_LEFT), ..CellStyle::default() };
        assert_eq!(sheet.style_for(1, None, CellStyle { bold: true, ..was }, was), 2);
        let centred = CellStyle { horizontal: Some(cell_style::XL_CENTER), ..was };
        assert_eq!(sheet.style_for(1, None, centred, was), 3);
        let xml = sheet.finish();
        assert!(
            xml.contains(r#"fillId="1" applyNumberFormat="1" applyFont="1" applyFill="1" applyAlignment="1"><alignment horizontal="left" indent="2" textRotation="45"/></xf>"#),
            "{xml}"
        );
        assert!(xml.contains(r#"fontId="0" fillId="1" applyNumberFormat="1" applyFont="1" applyFill="1" applyAlignment="1"><alignment horizontal="center"/></xf>"#), "{xml}");
    }

    /// A `<col>` range the reader skips (min above max, min 0) stays as it was, and the
    /// changed width gets its own `<col>`, where `BTreeMap::range` panicked.
    #[test]
    fn a_column_range_the_reader_skips_is_kept_and_not_split() {
        let head = r#"<worksheet><cols><col min="5" max="3" width="20" customWidth="1"/><col min="0" max="2" width="9"/></cols>"#;
        let widths = BTreeMap::from([(3, ColumnChange { width: Some(15.0), hidden: None })]);
        let out = with_widths(head, "", &widths);
        assert_eq!(
            out,
            r#"<worksheet><cols><col min="0" max="2" width="9"/><col min="4" max="4" width="15" customWidth="1"/><col min="5" max="3" width="20" customWidth="1"/></cols>"#
        );
    }

    /// A file whose highest format id is the largest u32 has none left for a new one: the
    /// part cannot be patched (the package is written anew), where `h + 1` overflowed.
    #[test]
    fn no_format_id_left_makes_the_styles_unpatchable() {
        let styles = STYLES.replace(
            "<fonts",
            r#"<numFmts count="1"><numFmt numFmtId="4294967295" formatCode="0.0"/></numFmts><fonts"#,
        );
        let mut sheet = StyleSheet::read(styles).unwrap();
        assert_eq!(sheet.unpatchable(), None);
        sheet.style_for(0, Some("0.000"), CellStyle::default(), CellStyle::default());
        assert!(sheet.unpatchable().is_some());
    }

    /// An empty `<numFmts/>` takes the new format, where a second `<numFmts>` was added
    /// (ECMA-376 18.8.39 allows one).
    #[test]
    fn an_empty_number_format_list_takes_the_new_format() {
        let styles = STYLES.replace("<fonts", r#"<numFmts count="0"/><fonts"#);
        let mut sheet = StyleSheet::read(styles).unwrap();
        sheet.style_for(0, Some("0.000"), CellStyle::default(), CellStyle::default());
        let xml = sheet.finish();
        assert_eq!(xml.matches("<numFmts").count(), 1, "{xml}");
        assert!(
            xml.starts_with(
                r#"<styleSheet><numFmts count="1"><numFmt numFmtId="164" formatCode="0.000"/></numFmts><fonts"#
            ),
            "{xml}"
        );
    }

    /// A style sheet without fonts, fills or cell styles to add to cannot be read for patching.
    #[test]
    fn a_style_sheet_without_its_lists_is_refused() {
        for (from, to) in [
            (r#"<fonts count="1"><font><sz val="11"/><name val="Calibri"/></font></fonts>"#, "<fonts/>"),
            (r#"<cellXfs count="1"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/></cellXfs>"#, ""),
        ] {
            assert!(StyleSheet::read(STYLES.replace(from, to)).is_err());
        }
    }

    /// The reader gives built-in date 14 as `mm-dd-yy` (calamine): a restyled date keeps id
    /// 14, which Excel shows as the locale's short date (ECMA-376 18.8.30), not a custom
    /// `mm-dd-yy` format; the date and time is 22.
    #[test]
    fn the_built_in_date_formats_keep_their_ids() {
        let mut sheet = StyleSheet::read(STYLES.to_string()).unwrap();
        let bold = CellStyle { bold: true, ..CellStyle::default() };
        sheet.style_for(0, Some("mm-dd-yy"), bold, CellStyle::default());
        sheet.style_for(0, Some(crate::eval::locale::BUILTIN_DATE_TIME), bold, CellStyle::default());
        let xml = sheet.finish();
        assert!(!xml.contains("<numFmts"), "{xml}");
        assert!(xml.contains(r#"numFmtId="14""#) && xml.contains(r#"numFmtId="22""#), "{xml}");
    }
}
