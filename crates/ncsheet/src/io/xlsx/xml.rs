//! Just enough XML for the parts of an xlsx package: tags with their attributes, text, and
//! the entities of XML 1.0. No namespaces beyond dropping prefixes, no DTDs.
//!
//! Two readers: [`for_each_tag`] walks a small part held whole (workbook, relationships)
//! and forgives bad markup; [`stream`] reads a large part (a worksheet, the shared strings)
//! through a small window and checks that elements nest, so a cut or garbled part is an
//! error naming the byte where it goes wrong, never cells quietly missing.

use std::io::Read;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TagKind {
    Start,
    End,
    /// `<x/>`
    Empty,
}

/// One tag: its local name (namespace prefix removed) and raw attribute text.
pub struct Tag<'a> {
    pub kind: TagKind,
    pub name: &'a [u8],
    attrs: &'a [u8],
}

impl<'a> Tag<'a> {
    /// The raw (still escaped) value of an attribute, matched by local name.
    pub fn attr(&self, key: &str) -> Option<&'a [u8]> {
        self.attrs().find(|(name, _)| *name == key.as_bytes()).map(|(_, value)| value)
    }

    /// An attribute read as a number (or anything parsed from text), if it is one.
    pub fn parsed<T: std::str::FromStr>(&self, key: &str) -> Option<T> {
        std::str::from_utf8(self.attr(key)?).ok()?.trim().parse().ok()
    }

    /// Each attribute's local name and raw value, in order; stops at malformed text.
    pub fn attrs(&self) -> Attrs<'a> {
        Attrs { rest: self.attrs }
    }
}

pub struct Attrs<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for Attrs<'a> {
    type Item = (&'a [u8], &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        self.next_qualified().map(|(name, value)| (local_name(name), value))
    }
}

impl<'a> Attrs<'a> {
    /// The next attribute's name as written (with its prefix: `r:id` and `id` are two
    /// attributes) and its raw value.
    fn next_qualified(&mut self) -> Option<(&'a [u8], &'a [u8])> {
        let b = self.rest;
        let mut i = b.iter().position(|c| !c.is_ascii_whitespace())?;
        let name_start = i;
        while i < b.len() && b[i] != b'=' && !b[i].is_ascii_whitespace() {
            i += 1;
        }
        let name = &b[name_start..i];
        while i < b.len() && (b[i].is_ascii_whitespace() || b[i] == b'=') {
            i += 1;
        }
        let quote = *b.get(i)?;
        if quote != b'"' && quote != b'\'' {
            return None;
        }
        let value_start = i + 1;
        let value_end = value_start + memchr::memchr(quote, &b[value_start..])?;
        self.rest = &b[value_end + 1..];
        Some((name, &b[value_start..value_end]))
    }
}

/// The first attribute name a tag gives twice (`<c r="A1" r="B1">`): XML 1.0 §3.1,
/// well-formedness constraint "Unique Att Spec", forbids it, and which of the two a reader
/// took would be a guess. Every tag of every part passes here: one too short for two
/// attributes (` a="" b=""`) or with fewer than two `=` (most: `<v>`, `<c r="B2">`) is
/// passed at once, the `=` counted in a plain loop (two `memchr` calls cost more on such
/// short text: benches/README.md); the others hold a few, see [`repeated_among`].
#[inline]
fn repeated_attribute<'a>(tag: &Tag<'a>) -> Option<&'a [u8]> {
    let attrs = tag.attrs;
    if attrs.len() < r#" a="" b="""#.len() || attrs.iter().filter(|&&b| b == b'=').nth(1).is_none() {
        return None;
    }
    repeated_among(tag.attrs())
}

/// The first attribute name given twice among `attrs`: compared pairwise in a small array,
/// in a set only past it (a tag of thousands of attributes costs their number).
fn repeated_among<'a>(mut attrs: Attrs<'a>) -> Option<&'a [u8]> {
    let mut few: [&[u8]; 8] = [&[]; 8];
    for i in 0..few.len() {
        let (name, _) = attrs.next_qualified()?;
        if few[..i].contains(&name) {
            return Some(name);
        }
        few[i] = name;
    }
    let mut many: std::collections::HashSet<&[u8]> = few.into_iter().collect();
    std::iter::from_fn(|| attrs.next_qualified()).map(|(name, _)| name).find(|name| !many.insert(name))
}

/// The error of a tag that gives an attribute twice.
fn repeated_attribute_message(tag: &Tag, name: &[u8]) -> String {
    format!(
        "<{}> gives the attribute {} twice, which XML 1.0 does not allow (§3.1, \"Unique Att Spec\")",
        lossy(tag.name),
        lossy(name)
    )
}

fn local_name(name: &[u8]) -> &[u8] {
    match memchr::memrchr(b':', name) {
        Some(i) => &name[i + 1..],
        None => name,
    }
}

/// What a piece of markup is.
enum Markup<'a> {
    Tag(Tag<'a>),
    /// `<![CDATA[…]]>`: text taken as it stands.
    CData(&'a [u8]),
    /// Comments, processing instructions, declarations.
    Other,
    /// `<!DOCTYPE …`: a DTD, which may declare entities.
    Doctype,
}

/// Where the markup starting at `buf[lt] == b'<'` ends (index of its `>`), `None` when the
/// buffer ends first. Comments, CDATA and processing instructions end at their own closers.
fn markup_end(buf: &[u8], lt: usize) -> Option<usize> {
    let rest = &buf[lt..];
    let closer: &[u8] = if rest.starts_with(b"<!--") {
        b"-->"
    } else if rest.starts_with(b"<![CDATA[") {
        b"]]>"
    } else if rest.starts_with(b"<?") {
        b"?>"
    } else {
        return tag_end(rest).map(|i| lt + i);
    };
    memchr::memmem::find(rest, closer).map(|i| lt + i + closer.len() - 1)
}

/// The `>` that closes a tag, skipping any inside quoted attribute values. A plain loop: tags
/// are short, shorter than a vectorised search takes to set up.
fn tag_end(tag: &[u8]) -> Option<usize> {
    let mut quote = None;
    for (i, &c) in tag.iter().enumerate().skip(1) {
        match (c, quote) {
            (b'"' | b'\'', None) => quote = Some(c),
            (c, Some(q)) if c == q => quote = None,
            (b'>', None) => return Some(i),
            _ => {}
        }
    }
    None
}

/// The markup in `markup` (from its `<` to its `>`).
fn parse_markup(markup: &[u8]) -> Markup<'_> {
    if let Some(data) = markup.strip_prefix(b"<![CDATA[") {
        return Markup::CData(&data[..data.len() - 3]);
    }
    let inner = &markup[1..markup.len() - 1];
    let (kind, inner) = match inner.first() {
        Some(b'/') => (TagKind::End, &inner[1..]),
        Some(b'!') if inner.starts_with(b"!DOCTYPE") => return Markup::Doctype,
        Some(b'!' | b'?') | None => return Markup::Other,
        _ => match inner.strip_suffix(b"/") {
            Some(body) => (TagKind::Empty, body),
            None => (TagKind::Start, inner),
        },
    };
    let name_end = inner.iter().position(|c| c.is_ascii_whitespace()).unwrap_or(inner.len());
    Markup::Tag(Tag { kind, name: local_name(&inner[..name_end]), attrs: &inner[name_end..] })
}

/// Calls `f` for each start or empty tag of a complete document, with the text that follows
/// it up to the next markup (the content of an element that holds only text).
pub fn for_each_tag(buf: &[u8], f: &mut dyn FnMut(&Tag, &[u8])) {
    let mut pos = 0;
    while let Some(lt) = memchr::memchr(b'<', &buf[pos..]).map(|i| pos + i) {
        let Some(gt) = markup_end(buf, lt) else { return };
        pos = gt + 1;
        if let Markup::Tag(tag) = parse_markup(&buf[lt..=gt]) {
            if tag.kind != TagKind::End {
                let text_end = memchr::memchr(b'<', &buf[pos..]).map_or(buf.len(), |i| pos + i);
                f(&tag, &buf[pos..text_end]);
            }
        }
    }
}

/// What [`stream`] hands on, in document order.
pub enum Event<'a> {
    Tag(Tag<'a>),
    /// Character data between markup, still escaped.
    Text(&'a [u8]),
    /// The content of a CDATA section: text with nothing escaped.
    CData(&'a [u8]),
}

/// Why a streamed document could not be read.
#[derive(Debug)]
pub enum StreamError<E> {
    /// Reading the part failed (for a zip entry: damaged data, a wrong checksum).
    Io(std::io::Error),
    /// The markup is not well-formed, at this byte of the part.
    Xml { offset: u64, message: String },
    /// The handler refused an event (its error names the place).
    Handler(E),
}

/// Why a part with a DTD is refused. The entities it declares would change the text (and can
/// expand without bound); Office Open XML forbids a DTD in a part and tells readers to treat
/// one as an error (ECMA-376 Part 2, §8.1.4, [M1.18]), as Excel does.
const DOCTYPE: &str = "the part declares a DTD (<!DOCTYPE …>), which an Office Open XML part may not have \
                       (ECMA-376 Part 2, [M1.18]); ncsheet reads no DTD and none of its entities";

/// Bytes read from the part at a time.
const CHUNK: usize = 1 << 17;
/// The longest tag or run of text held at once. Real sheets stay far below; a part that
/// needs more is damaged or hostile.
const MAX_PIECE: usize = 1 << 24;

/// Streams the document `reader` holds to `handler`, holding only a small window, and checks
/// that every element is closed by its own end tag.
pub fn stream<E>(reader: impl Read, handler: &mut dyn FnMut(Event) -> Result<(), E>) -> Result<(), StreamError<E>> {
    let mut window = Window { reader, buf: Vec::with_capacity(2 * CHUNK), pos: 0, consumed: 0, eof: false };
    let mut open = OpenElements::default();
    window.refill().map_err(StreamError::Io)?;
    if is_utf16(&window.buf) {
        // Read as bytes, every other one a zero, it "ended inside a tag": say what it is.
        let message = "the part is encoded in UTF-16; ncsheet reads the UTF-8 that Excel writes (open the file in \
                       Excel and save it again)"
            .to_string();
        return Err(StreamError::Xml { offset: 0, message });
    }
    window.check_characters(0)?;
    loop {
        let offset = window.offset();
        let rest = &window.buf[window.pos..];
        if rest.first() == Some(&b'<') {
            if let Some(gt) = markup_end(rest, 0) {
                let markup = parse_markup(&rest[..=gt]);
                window.pos += gt + 1;
                let event = match markup {
                    Markup::Tag(tag) => {
                        open.check(&tag).map_err(|message| StreamError::Xml { offset, message })?;
                        if let Some(name) = repeated_attribute(&tag) {
                            let message = repeated_attribute_message(&tag, name);
                            return Err(StreamError::Xml { offset, message });
                        }
                        Event::Tag(tag)
                    }
                    Markup::CData(data) => Event::CData(data),
                    Markup::Other => continue,
                    Markup::Doctype => return Err(StreamError::Xml { offset, message: DOCTYPE.into() }),
                };
                handler(event).map_err(StreamError::Handler)?;
                continue;
            }
        } else if !rest.is_empty() {
            let end = match memchr::memchr(b'<', rest) {
                Some(lt) => Some(lt),
                None if window.eof => Some(rest.len()),
                None => None,
            };
            if let Some(end) = end {
                window.pos += end;
                handler(Event::Text(&rest[..end])).map_err(StreamError::Handler)?;
                continue;
            }
        }
        if window.eof {
            return open.finish(&window.buf[window.pos..]).map_err(|message| StreamError::Xml { offset, message });
        }
        let unread = window.buf.len() - window.pos;
        window.refill().map_err(StreamError::Io)?;
        window.check_characters(unread)?;
        if window.buf.len() - window.pos > MAX_PIECE {
            let message = format!("a tag or text longer than {} MiB", MAX_PIECE >> 20);
            return Err(StreamError::Xml { offset, message });
        }
    }
}

/// Whether a document starts as UTF-16 does: a byte-order mark, or `<` with a zero byte.
fn is_utf16(start: &[u8]) -> bool {
    matches!(start, [0xFF, 0xFE, ..] | [0xFE, 0xFF, ..] | [0, b'<', ..] | [b'<', 0, ..])
}

/// The unread part of a stream: `buf[pos..]`, of which `consumed` bytes came before `buf`.
struct Window<R> {
    reader: R,
    buf: Vec<u8>,
    pos: usize,
    consumed: u64,
    eof: bool,
}

impl<R: Read> Window<R> {
    fn offset(&self) -> u64 {
        self.consumed + self.pos as u64
    }

    /// Drops what was read and appends the next chunk (or notes the end).
    fn refill(&mut self) -> std::io::Result<()> {
        self.buf.drain(..self.pos);
        self.consumed += self.pos as u64;
        self.pos = 0;
        let old = self.buf.len();
        self.buf.resize(old + CHUNK, 0);
        let n = loop {
            match self.reader.read(&mut self.buf[old..]) {
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                r => break r?,
            }
        };
        self.buf.truncate(old + n);
        self.eof = n == 0;
        Ok(())
    }
}

impl<R> Window<R> {
    /// Refuses a control character XML 1.0 does not allow among the window's bytes from
    /// `from` (those just read): see [`control_character`].
    fn check_characters<E>(&self, from: usize) -> Result<(), StreamError<E>> {
        let Some(at) = control_character(&self.buf[self.pos + from..]) else { return Ok(()) };
        let at = self.pos + from + at;
        Err(StreamError::Xml {
            offset: self.consumed + at as u64,
            message: format!(
                "the control character U+{:04X}, which XML 1.0 does not allow in a document (§2.2, Char; Excel \
                 writes one in a cell's text as _x{:04X}_)",
                self.buf[at], self.buf[at]
            ),
        })
    }
}

/// Where the first control character XML 1.0 does not allow lies in `bytes`: of U+0000 to
/// U+001F only tab, line feed and carriage return are characters of a document (§2.2, the
/// `Char` production; the same rule `&#1;` breaks), raw in text, an attribute or markup.
/// Excel refuses a part holding one. Every byte of every part passes here, so each block is
/// tested whole, without a branch per byte, which the compiler turns into vector compares.
fn control_character(bytes: &[u8]) -> Option<usize> {
    const BLOCK: usize = 64;
    let forbidden = |b: u8| (b < 0x20) & (b != b'\t') & (b != b'\n') & (b != b'\r');
    let mut start = 0;
    for block in bytes.chunks(BLOCK) {
        if block.iter().fold(false, |any, &b| any | forbidden(b)) {
            return block.iter().position(|&b| forbidden(b)).map(|i| start + i);
        }
        start += block.len();
    }
    None
}

/// The names of the elements open at this point of the document.
#[derive(Default)]
struct OpenElements {
    names: Vec<u8>,
    starts: Vec<usize>,
    root_seen: bool,
}

impl OpenElements {
    fn check(&mut self, tag: &Tag) -> Result<(), String> {
        if self.starts.is_empty() && tag.kind != TagKind::End {
            if self.root_seen {
                return Err(format!("<{}> after the end of the document", lossy(tag.name)));
            }
            self.root_seen = true;
        }
        match tag.kind {
            TagKind::Start => {
                self.starts.push(self.names.len());
                self.names.extend_from_slice(tag.name);
            }
            TagKind::Empty => {}
            TagKind::End => {
                let Some(start) = self.starts.pop() else {
                    return Err(format!("</{}> closes nothing", lossy(tag.name)));
                };
                if self.names[start..] != *tag.name {
                    return Err(format!("</{}> where </{}> was due", lossy(tag.name), lossy(&self.names[start..])));
                }
                self.names.truncate(start);
            }
        }
        Ok(())
    }

    /// At the end of the part: everything opened was closed.
    fn finish(&self, unread: &[u8]) -> Result<(), String> {
        if !unread.is_empty() {
            return Err("the part ends inside a tag".into());
        }
        match self.starts.last() {
            Some(&start) => Err(format!("the part ends inside <{}>: it was cut short", lossy(&self.names[start..]))),
            None if !self.root_seen => Err("the part holds no XML element".into()),
            None => Ok(()),
        }
    }
}

fn lossy(name: &[u8]) -> String {
    String::from_utf8_lossy(name).into_owned()
}

/// XML text with its entities replaced (invalid UTF-8 replaced too: for names and
/// attributes of the small parts, each checked whole by [`check_references`] before it is
/// read; a reference that is not well-formed is kept as written).
pub fn unescape(raw: &[u8]) -> String {
    let text = String::from_utf8_lossy(raw);
    let mut out = String::new();
    if unescape_into(&text, &mut out).is_err() {
        return text.into_owned();
    }
    out
}

/// A reference in character data or an attribute value that XML 1.0 does not allow: an
/// entity it does not define (`&bogus;`, or one a DOCTYPE would declare: ncsheet reads no
/// DTD), a character reference to a character outside XML's `Char` production (`&#1;`,
/// `&#0;`, `&#xD800;`, `&#99999999;`: §2.2 and §4.1, well-formedness constraint "Legal
/// Character"), or a bare `&`. Excel refuses a part holding one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BadReference {
    /// The reference as written, from its `&` (cut at 32 characters).
    pub written: String,
}

impl std::fmt::Display for BadReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let written = &self.written;
        if !written.ends_with(';') {
            write!(f, "'{written}…': an & that begins no entity or character reference (XML writes it &amp;)")
        } else if written.starts_with("&#") {
            write!(f, "the character reference {written} names no character XML 1.0 allows")
        } else {
            write!(f, "unknown entity {written} (XML defines five; ncsheet reads no DOCTYPE's entities)")
        }
    }
}

/// The longest reference looked for: `&#x0010FFFF;` and XML's entity names are far shorter.
const MAX_REFERENCE: usize = 32;

/// Appends `text` to `out` with XML's entities replaced and line ends normalised to `\n`,
/// as an XML parser reports character data. A reference XML does not allow is an error (a
/// cell must not show it as text, nor drop it).
pub fn unescape_into(text: &str, out: &mut String) -> Result<(), BadReference> {
    if memchr::memchr2(b'&', b'\r', text.as_bytes()).is_none() {
        out.push_str(text);
        return Ok(());
    }
    let mut rest = text;
    while let Some(at) = rest.find(['&', '\r']) {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        if let Some(after) = rest.strip_prefix('\r') {
            out.push('\n');
            rest = after.strip_prefix('\n').unwrap_or(after);
            continue;
        }
        let (c, len) = reference(rest)?;
        out.push(c);
        rest = &rest[len..];
    }
    out.push_str(rest);
    Ok(())
}

/// The character the reference at the start of `text` (at its `&`) stands for, and the
/// reference's length.
fn reference(text: &str) -> Result<(char, usize), BadReference> {
    let semi = text.as_bytes().iter().take(MAX_REFERENCE).position(|&b| b == b';');
    match semi.and_then(|semi| Some((entity(&text[1..semi])?, semi + 1))) {
        Some(found) => Ok(found),
        None => {
            let end = semi.map_or_else(|| text.char_indices().nth(16).map_or(text.len(), |(i, _)| i), |s| s + 1);
            Err(BadReference { written: text[..end].to_string() })
        }
    }
}

/// The first reference in escaped character data or an attribute value that XML does not
/// allow (see [`BadReference`]): a well-formedness error a reader must report.
pub fn bad_reference(text: &[u8]) -> Option<BadReference> {
    let text = String::from_utf8_lossy(text);
    let mut rest = text.as_ref();
    while let Some(at) = rest.find('&') {
        rest = &rest[at..];
        match reference(rest) {
            Ok((_, len)) => rest = &rest[len..],
            Err(bad) => return Some(bad),
        }
    }
    None
}

/// The first reference XML does not allow in an event's text or attribute values.
pub fn bad_reference_in(event: &Event) -> Option<BadReference> {
    match event {
        Event::Text(text) => bad_reference(text),
        Event::Tag(tag) => tag.attrs().find_map(|(_, value)| bad_reference(value)),
        Event::CData(_) => None,
    }
}

/// Whether an event's bytes (a tag's name and attributes, text, CDATA) are not UTF-8: a
/// document in no other encoding than UTF-8 with such bytes is not well-formed (XML 1.0
/// §4.3.3). A text event ends at `<` or the end, so no character is split between two.
pub fn not_utf8(event: &Event) -> bool {
    let bad = |bytes: &[u8]| std::str::from_utf8(bytes).is_err();
    match event {
        Event::Tag(tag) => bad(tag.name) || bad(tag.attrs),
        Event::Text(text) | Event::CData(text) => bad(text),
    }
}

/// Checks a whole part as [`stream`] does (nesting, no DTD) and every reference in its text
/// and attribute values: the small parts read with [`for_each_tag`], which forgives, are
/// checked so first.
pub fn check_references(part: impl Read) -> Result<(), StreamError<BadReference>> {
    stream(part, &mut |event| match bad_reference_in(&event) {
        Some(bad) => Err(bad),
        None => Ok(()),
    })
}

fn entity(name: &str) -> Option<char> {
    match name {
        "amp" => Some('&'),
        "lt" => Some('<'),
        "gt" => Some('>'),
        "quot" => Some('"'),
        "apos" => Some('\''),
        _ => {
            // Digits only: Rust's parsers would take a sign (`&#+65;`), which XML does not.
            let code = match name.strip_prefix("#x") {
                Some(hex) if hex.bytes().all(|b| b.is_ascii_hexdigit()) => u32::from_str_radix(hex, 16).ok(),
                Some(_) => None,
                None => name.strip_prefix('#').filter(|d| d.bytes().all(|b| b.is_ascii_digit()))?.parse().ok(),
            };
            code.and_then(char::from_u32).filter(|&c| is_xml_char(c))
        }
    }
}

/// XML 1.0's `Char` production (§2.2): tab, line feed, carriage return and every character
/// from U+0020 but the surrogates (which `char` cannot hold) and U+FFFE, U+FFFF.
fn is_xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r' | '\u{20}'..='\u{FFFD}' | '\u{10000}'..)
}

/// Replaces Excel's `_xHHHH_` escapes in string values (how it stores characters XML cannot
/// hold, such as a carriage return: `_x000D_`; a literal `_x` escape is `_x005F_`).
/// Surrogate pairs combine; a lone surrogate becomes U+FFFD.
pub fn unescape_excel(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.contains("_x") {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("_x") {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        let Some(unit) = excel_escape(rest) else {
            out.push('_');
            rest = &rest[1..];
            continue;
        };
        rest = &rest[7..];
        let c = match unit {
            0xD800..=0xDBFF => match excel_escape(rest) {
                Some(low @ 0xDC00..=0xDFFF) => {
                    rest = &rest[7..];
                    char::from_u32(0x10000 + ((unit - 0xD800) << 10) + (low - 0xDC00))
                }
                _ => None,
            },
            _ => char::from_u32(unit),
        };
        out.push(c.unwrap_or(char::REPLACEMENT_CHARACTER));
    }
    out.push_str(rest);
    std::borrow::Cow::Owned(out)
}

/// The UTF-16 unit of an `_xHHHH_` escape at the start of `text`.
fn excel_escape(text: &str) -> Option<u32> {
    let b = text.as_bytes().get(..7)?;
    if !(b.starts_with(b"_x") && b[6] == b'_' && b[2..6].iter().all(u8::is_ascii_hexdigit)) {
        return None;
    }
    u32::from_str_radix(std::str::from_utf8(&b[2..6]).ok()?, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_attributes_and_entities() {
        let xml = br#"<?xml version="1.0"?><!-- a > b --><x:sheet name="A &amp; B" r:id='rId1'/><definedName name="n" localSheetId="2">Sheet1!$A$1&lt;&#65;</definedName>"#;
        let mut seen = Vec::new();
        for_each_tag(xml, &mut |tag, text| {
            seen.push((
                String::from_utf8_lossy(tag.name).into_owned(),
                tag.attr("name").map(unescape),
                tag.attr("id").map(unescape),
                unescape(text),
            ));
        });
        assert_eq!(
            seen,
            vec![
                ("sheet".into(), Some("A & B".into()), Some("rId1".into()), "".into()),
                ("definedName".into(), Some("n".into()), None, "Sheet1!$A$1<A".into()),
            ]
        );
    }

    /// Every event of a streamed document, as text, or the error.
    fn events(xml: &[u8]) -> Result<Vec<String>, String> {
        let mut seen = Vec::new();
        let result = stream(xml, &mut |e: Event| -> Result<(), ()> {
            seen.push(match e {
                Event::Tag(t) => format!("{:?} {}", t.kind, lossy(t.name)),
                Event::Text(t) => format!("text {}", unescape(t)),
                Event::CData(t) => format!("cdata {}", lossy(t)),
            });
            Ok(())
        });
        match result {
            Ok(()) => Ok(seen),
            Err(StreamError::Xml { offset, message }) => Err(format!("{offset}: {message}")),
            Err(e) => Err(format!("{e:?}")),
        }
    }

    #[test]
    fn a_stream_reports_tags_text_and_cdata_across_windows() {
        let long = "x".repeat(3 * CHUNK);
        let xml = format!(r#"<a><b k="1>2">{long}</b><c/><![CDATA[<&>]]></a>"#);
        let seen = events(xml.as_bytes()).unwrap();
        assert_eq!(seen[..2], ["Start a".to_string(), "Start b".to_string()]);
        assert_eq!(seen[2].len(), "text ".len() + long.len());
        assert_eq!(seen[3..], ["End b", "Empty c", "cdata <&>", "End a"].map(String::from));
    }

    /// XML 1.0 §2.2 `Char` and §4.1 "Legal Character": the characters a reference may name.
    #[test]
    fn references_to_characters_xml_does_not_allow_are_errors() {
        for written in ["&#0;", "&#1;", "&#x1F;", "&#xD800;", "&#xFFFE;", "&#x110000;", "&#99999999;", "&#+65;", "&#x;"]
        {
            let mut out = String::new();
            assert_eq!(unescape_into(&format!("a{written}b"), &mut out), Err(BadReference { written: written.into() }));
        }
        assert_eq!(bad_reference(b"R&D").map(|b| b.written), Some("&D".into()));
    }

    #[test]
    fn a_stream_refuses_a_dtd() {
        let xml = b"<?xml version=\"1.0\"?><!DOCTYPE sst [<!ENTITY e \"x\">]><sst><t>&e;</t></sst>";
        assert!(events(xml).unwrap_err().starts_with("21: the part declares a DTD"));
    }

    #[test]
    fn a_stream_names_where_the_markup_goes_wrong() {
        assert_eq!(events(b"<a><b></a>").unwrap_err(), "6: </a> where </b> was due");
        assert_eq!(events(b"<a><b>12").unwrap_err(), "8: the part ends inside <b>: it was cut short");
        assert_eq!(events(b"<a><b x=\"1").unwrap_err(), "3: the part ends inside a tag");
        assert_eq!(events(b"<a/><b/>").unwrap_err(), "4: <b> after the end of the document");
        assert_eq!(events(b"").unwrap_err(), "0: the part holds no XML element");
    }

    /// XML 1.0 §3.1, constraint "Unique Att Spec": no attribute name may appear more than
    /// once in the same tag. Names compare as written: `r:id` and `id` are two.
    #[test]
    fn a_stream_refuses_an_attribute_given_twice() {
        let twice = "<c> gives the attribute r twice, which XML 1.0 does not allow (§3.1, \"Unique Att Spec\")";
        assert_eq!(events(br#"<a><c r="A1" r="B1"/></a>"#).unwrap_err(), format!("3: {twice}"));
        assert_eq!(events(br#"<a><c r="A1" s="1" r='A1'></c></a>"#).unwrap_err(), format!("3: {twice}"));
        let many: String = (0..40).map(|i| format!(" k{i}=\"{i}\"")).collect();
        let err = events(format!("<a{many} k39=\"x\"/>").as_bytes()).unwrap_err();
        assert!(err.starts_with("0: <a> gives the attribute k39 twice"), "{err}");
        assert!(events(format!("<a{many}/>").as_bytes()).is_ok());
        assert!(events(br#"<a xmlns:r="u" r:id="1" id="2" rid="3"/>"#).is_ok());
    }

    #[test]
    fn text_unescapes_entities_line_ends_and_excel_escapes() {
        let mut out = String::new();
        let bad = |written: &str| Some(BadReference { written: written.into() });
        assert_eq!(bad_reference(b"a&amp;b&#x41;&lt;&bogus;"), bad("&bogus;"));
        assert_eq!(bad_reference(b"a&amp;b&#x41;&lt;&#8364;&#x10FFFF;&#9;"), None);
        unescape_into("a&amp;b&#x41;&lt;\r\nc\rd", &mut out).unwrap();
        assert_eq!(out, "a&bA<\nc\nd");
        assert_eq!(unescape(b"kept &bogus; as written"), "kept &bogus; as written");
        assert_eq!(unescape_excel("a_x000D_b_x005F_x000D_"), "a\rb_x000D_");
        assert_eq!(unescape_excel("_xD83D__xDE00_!_xD83D_"), "😀!\u{FFFD}");
        assert_eq!(unescape_excel("_x00ZZ_ _x12"), "_x00ZZ_ _x12");
    }
}
