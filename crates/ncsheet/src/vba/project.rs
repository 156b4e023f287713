//! A workbook's VBA project (`xl/vbaProject.bin`) read from its bytes: an OLE compound file
//! ([MS-CFB], through the `cfb` crate) whose `VBA/dir` stream lists the modules ([MS-OVBA]
//! 2.3.4.2) and whose module streams hold each module's source, compressed ([MS-OVBA] 2.4.1),
//! from the offset the dir stream gives. Text is in the project's code page
//! (PROJECTCODEPAGE). Every failure names the stream it is in.

use std::io::{Cursor, Read};

use super::ovba;

/// One module of the project, as the VBA editor shows it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProjectModule {
    pub name: String,
    /// The stream inside the VBA storage (usually the module's name).
    pub stream: String,
    pub kind: ModuleKind,
    /// The source as the editor exports it (`Attribute` lines included, CRLF line ends).
    pub source: String,
}

impl ProjectModule {
    /// The procedures the module declares, as their declaration lines read (`Sub Chamfer()`,
    /// `Function Tip(d As Double) As Double`): the VBA editor's procedure list. A scan of the
    /// lines, not a parse, so that a module that does not compile still lists them.
    pub fn procedures(&self) -> Vec<String> {
        procedures(&self.source)
    }

    /// The names of the Functions the module declares.
    pub fn function_names(&self) -> Vec<String> {
        self.procedures().iter().filter_map(|d| function_name(d)).collect()
    }

    /// Whether the module declares a procedure called `name` (case aside).
    pub fn declares(&self, name: &str) -> bool {
        self.procedures().iter().any(|line| {
            let words = line.split(|c: char| c.is_whitespace() || c == '(');
            words.filter(|w| !w.is_empty()).any(|w| w.eq_ignore_ascii_case(name))
        })
    }
}

/// The declaration lines of `source` (see [`ProjectModule::procedures`]).
pub fn procedures(source: &str) -> Vec<String> {
    source.lines().map(str::trim).filter(|l| declares_procedure(l)).map(|l| l.to_string()).collect()
}

fn declares_procedure(line: &str) -> bool {
    let mut words = line.split_whitespace().peekable();
    while let Some(w) = words.peek() {
        if ["public", "private", "friend", "static"].iter().any(|m| w.eq_ignore_ascii_case(m)) {
            words.next();
        } else {
            break;
        }
    }
    match words.next() {
        Some(w) if w.eq_ignore_ascii_case("sub") || w.eq_ignore_ascii_case("function") => words.next().is_some(),
        Some(w) if w.eq_ignore_ascii_case("property") => words.nth(1).is_some(),
        _ => false,
    }
}

/// The name a `Function` declaration line declares (`Public Function Tip(d) As Double`: `Tip`).
fn function_name(declaration: &str) -> Option<String> {
    let mut words = declaration.split(|c: char| c.is_whitespace() || c == '(');
    words.find(|w| w.eq_ignore_ascii_case("function"))?;
    words.find(|w| !w.is_empty()).map(str::to_string)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModuleKind {
    /// A standard module (`Module1`): exported as .bas.
    Standard,
    /// A document module (`ThisWorkbook`, `Sheet1`) or a class: exported as .cls.
    DocumentOrClass,
    /// A class module: the dir stream's MODULETYPE of a document module, and a `Class=` line in
    /// the PROJECT stream ([MS-OVBA] 2.3.1.6); exported as .cls.
    Class,
}

impl ModuleKind {
    pub fn extension(self) -> &'static str {
        match self {
            ModuleKind::Standard => "bas",
            ModuleKind::DocumentOrClass | ModuleKind::Class => "cls",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VbaProject {
    pub code_page: u16,
    pub modules: Vec<ProjectModule>,
    /// The protection the PROJECT stream records; `None` where its fields do not decode.
    pub protection: Option<Protection>,
}

/// A project's protection ([MS-OVBA] 2.3.1.15-17): the VBA editor's password and its "lock
/// project for viewing". A locked project still stores its modules' source.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Protection {
    /// ProjectProtectionState (CMG): fUserProtected, fHostProtected, fVBEProtected bits.
    pub state: u32,
    /// ProjectPassword (DPB) holds a password or its hash, not the single 0x00 of "none".
    pub password: bool,
    /// ProjectVisibilityState (GC) is not 0xFF: the editor shows no module without the password.
    pub locked_for_viewing: bool,
}

impl Protection {
    pub fn is_protected(&self) -> bool {
        self.state != 0 || self.password || self.locked_for_viewing
    }

    /// What protects the project, as a user would say it.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if self.password {
            parts.push("has a password".to_string());
        }
        if self.locked_for_viewing {
            parts.push("is locked for viewing".to_string());
        }
        let by = [(1, "the user"), (2, "the host application"), (4, "the VBA editor")];
        let who: Vec<&str> = by.iter().filter(|(bit, _)| self.state & bit != 0).map(|(_, w)| *w).collect();
        if !who.is_empty() {
            parts.push(format!("is marked protected by {}", who.join(" and ")));
        }
        if self.state & !7 != 0 {
            parts.push(format!("has protection state {:#010x}", self.state));
        }
        parts.join(", ")
    }
}

/// The protection recorded in a PROJECT stream's CMG, DPB and GC lines (Data Decryption,
/// [MS-OVBA] 2.4.3.3); an error says which line does not decode.
pub(super) fn read_protection(project_text: &[u8]) -> Result<Protection, String> {
    let field = |key: &str| -> Result<Vec<u8>, String> {
        let hex = property(project_text, key).ok_or_else(|| format!("the {key} line is missing"))?;
        let hex = hex.strip_prefix(b"\"").and_then(|h| h.strip_suffix(b"\"")).unwrap_or(hex);
        decrypt(hex).ok_or_else(|| format!("the {key} line does not decode ([MS-OVBA] 2.4.3.3)"))
    };
    let state = field("CMG")?;
    let password = field("DPB")?;
    let visibility = field("GC")?;
    let state = match state[..] {
        [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
        _ => return Err("the CMG line does not hold 4 bytes".into()),
    };
    Ok(Protection { state, password: password != [0], locked_for_viewing: visibility != [0xFF] })
}

/// The names of the PROJECT stream's `Class=` lines (2.3.1.6), as stored.
fn class_names(text: &[u8]) -> Vec<Vec<u8>> {
    text.split(|&b| b == b'\n')
        .map(|l| l.strip_suffix(b"\r").unwrap_or(l))
        .take_while(|l| !l.starts_with(b"["))
        .filter_map(|l| l.strip_prefix(b"Class="))
        .map(<[u8]>::to_vec)
        .collect()
}

/// The value of the PROJECT stream's `key=` line, as stored.
pub(super) fn property<'t>(text: &'t [u8], key: &str) -> Option<&'t [u8]> {
    text.split(|&b| b == b'\n')
        .map(|l| l.strip_suffix(b"\r").unwrap_or(l))
        .take_while(|l| !l.starts_with(b"["))
        .find_map(|l| l.strip_prefix(key.as_bytes()).and_then(|rest| rest.strip_prefix(b"=")))
}

/// Data Decryption ([MS-OVBA] 2.4.3.3) of hex text: the data, or `None` where the text is not
/// hex, is cut short or names another length than it holds.
fn decrypt(hex: &[u8]) -> Option<Vec<u8>> {
    if !hex.len().is_multiple_of(2) {
        return None;
    }
    let digit = |c: u8| (c as char).to_digit(16);
    let bytes: Vec<u8> =
        hex.chunks(2).map(|p| Some((digit(p[0])? * 16 + digit(p[1])?) as u8)).collect::<Option<_>>()?;
    let (&seed, rest) = bytes.split_first()?;
    let (&version_enc, rest) = rest.split_first()?;
    let (&proj_key_enc, rest) = rest.split_first()?;
    let (mut plain1, mut enc1, mut enc2) = (seed ^ proj_key_enc, proj_key_enc, version_enc);
    let plain: Vec<u8> = rest
        .iter()
        .map(|&enc| {
            let byte = enc ^ enc2.wrapping_add(plain1);
            (enc2, enc1, plain1) = (enc1, enc, byte);
            byte
        })
        .collect();
    let ignored = usize::from((seed & 6) / 2);
    let length = plain.get(ignored..ignored + 4)?;
    let length = u32::from_le_bytes([length[0], length[1], length[2], length[3]]) as usize;
    let data = &plain[ignored + 4..];
    (data.len() == length).then(|| data.to_vec())
}

/// What is wrong with a VBA project, and in which stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProjectError {
    pub stream: String,
    pub message: String,
}

impl std::fmt::Display for ProjectError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.stream, self.message)
    }
}

fn error(stream: &str, message: impl std::fmt::Display) -> ProjectError {
    ProjectError { stream: stream.to_string(), message: message.to_string() }
}

/// Reads the project from the bytes of `vbaProject.bin`.
pub fn read_project(bytes: &[u8]) -> Result<VbaProject, ProjectError> {
    super::count(&super::PROJECTS_READ, 1);
    let mut parts = open_parts(bytes)?;
    let encoding = parts.encoding()?;
    let mut modules = Vec::with_capacity(parts.listing.modules.len());
    let classes = class_names(&parts.project_text);
    for mut m in std::mem::take(&mut parts.listing.modules) {
        if m.kind == ModuleKind::DocumentOrClass && classes.iter().any(|c| c.eq_ignore_ascii_case(m.name.as_bytes())) {
            m.kind = ModuleKind::Class;
        }
        let text = parts.module_text(&m)?;
        let (source, _, _) = encoding.decode(&text);
        modules.push(ProjectModule { name: m.name, stream: m.stream, kind: m.kind, source: source.into_owned() });
    }
    let protection = read_protection(&parts.project_text).ok();
    Ok(VbaProject { code_page: parts.listing.code_page, modules, protection })
}

/// A project opened and checked as far as its listing: the dir stream read, and the PROJECT
/// stream found to list the same modules.
pub(super) struct Parts<'a> {
    pub cfb: cfb::CompoundFile<Cursor<&'a [u8]>>,
    /// The storage holding `dir` and the module streams (`/VBA`).
    pub storage: String,
    pub listing: Listing,
    /// The dir stream, decompressed.
    pub dir: Vec<u8>,
    /// The PROJECT stream's path and bytes.
    pub project_path: String,
    pub project_text: Vec<u8>,
    /// The bytes the modules' sources decompressed to so far, held to [`MAX_PROJECT_SOURCE`].
    inflated: usize,
    /// The module streams read so far, by path: a dir stream may list thousands of modules
    /// naming one large stream, which was read whole again for each (3,000 modules on an
    /// 8 MB stream: 24 GB copied).
    streams: std::collections::HashMap<String, Vec<u8>>,
}

pub(super) fn open_parts(bytes: &[u8]) -> Result<Parts<'_>, ProjectError> {
    let mut cfb = cfb::CompoundFile::open(Cursor::new(bytes))
        .map_err(|e| error("vbaProject.bin", format!("not an OLE compound file: {e}")))?;
    let storage = vba_storage(&cfb).ok_or_else(|| error("vbaProject.bin", "no VBA storage with a dir stream"))?;
    let dir_name = format!("{storage}/dir");
    let dir = read_stream(&mut cfb, &dir_name)?;
    let dir = ovba::decompress(&dir).map_err(|e| error(&dir_name, e))?;
    let listing = parse_dir(&dir).map_err(|m| error(&dir_name, m))?;
    let parent = storage.rsplit_once('/').map_or("", |(p, _)| p);
    let project_path = format!("{parent}/PROJECT");
    let project_text = read_stream(&mut cfb, &project_path)?;
    check_project_text(&project_text, &listing.modules, encoding_for(listing.code_page))
        .map_err(|m| error(&project_path, m))?;
    Ok(Parts { cfb, storage, listing, dir, project_path, project_text, inflated: 0, streams: Default::default() })
}

impl Parts<'_> {
    /// The text encoding of the project's code page.
    pub fn encoding(&self) -> Result<&'static encoding_rs::Encoding, ProjectError> {
        let code_page = self.listing.code_page;
        encoding_for(code_page).ok_or_else(|| {
            error(&format!("{}/dir", self.storage), format!("code page {code_page} is not one ncsheet can read"))
        })
    }

    pub fn stream_path(&self, m: &DirModule) -> String {
        format!("{}/{}", self.storage, m.stream)
    }

    /// A module's source as stored (in the code page), without its compiled part.
    pub fn module_text(&mut self, m: &DirModule) -> Result<Vec<u8>, ProjectError> {
        let path = self.stream_path(m);
        if !self.streams.contains_key(&path) {
            let data = read_stream(&mut self.cfb, &path)?;
            self.streams.insert(path.clone(), data);
        }
        let data = &self.streams[&path];
        let Some(compressed) = data.get(m.offset as usize..) else {
            return Err(error(
                &path,
                format!("source offset {} is past the stream's end ({} bytes)", m.offset, data.len()),
            ));
        };
        let budget = MAX_PROJECT_SOURCE.saturating_sub(self.inflated);
        let text = ovba::decompress_at_most(compressed, ovba::MAX_DECOMPRESSED.min(budget)).map_err(|e| {
            if budget < ovba::MAX_DECOMPRESSED && e.past_limit {
                let mib = MAX_PROJECT_SOURCE >> 20;
                error(&path, format!("the project's modules decompress to more than {mib} MiB in all (many modules may share one stream)"))
            } else {
                error(&path, e)
            }
        })?;
        self.inflated += text.len();
        Ok(text)
    }
}

/// The most the modules of one project decompress to together: each stream is bounded by
/// [`ovba::MAX_DECOMPRESSED`], but a dir stream may list thousands of modules, all naming one
/// stream that inflates to that bound. Real projects hold a few MiB of source.
pub const MAX_PROJECT_SOURCE: usize = 256 << 20;

/// Checks the PROJECT stream ([MS-OVBA] 2.3.1) as far as a cut or damaged one shows: text
/// lines of `key=value` from the `ID=` line on, the properties the grammar requires, the
/// `[Host Extender Info]` section, and a line for every module the dir stream lists.
fn check_project_text(
    text: &[u8],
    modules: &[DirModule],
    encoding: Option<&'static encoding_rs::Encoding>,
) -> Result<(), String> {
    let decode = |bytes: &[u8]| encoding.map_or_else(|| latin(bytes), |e| e.decode(bytes).0.into_owned());
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').map(|l| l.strip_suffix(b"\r").unwrap_or(l)).collect();
    if !lines.first().is_some_and(|l| l.starts_with(b"ID=\"")) {
        return Err("does not start with the project's ID= line".into());
    }
    let mut keys = Vec::new();
    let mut items = Vec::new();
    for (n, line) in lines.iter().enumerate() {
        if line.is_empty() || line.starts_with(b"[") {
            break;
        }
        let Some(eq) = line.iter().position(|&b| b == b'=') else {
            return Err(format!("line {} is not key=value", n + 1));
        };
        let key = &line[..eq];
        if key.is_empty() || !key.iter().all(u8::is_ascii_alphanumeric) {
            return Err(format!("line {} is not key=value", n + 1));
        }
        let value = &line[eq + 1..];
        if [&b"Module"[..], b"Class", b"BaseClass", b"Document"].contains(&key) {
            let name = value.split(|&b| b == b'/').next().unwrap_or(value);
            items.push(decode(name).to_lowercase());
        }
        keys.push(key);
    }
    for required in [&b"Name"[..], b"HelpContextID", b"CMG", b"DPB", b"GC"] {
        if !keys.contains(&required) {
            return Err(format!("the {} line is missing (cut short?)", latin(required)));
        }
    }
    if !lines.contains(&&b"[Host Extender Info]"[..]) {
        return Err("the [Host Extender Info] section is missing (cut short?)".into());
    }
    if let Some(m) = modules.iter().find(|m| !items.contains(&m.name.to_lowercase())) {
        return Err(format!("module {} of the dir stream is not listed", m.name));
    }
    Ok(())
}

/// The storage that holds the `dir` stream: `/VBA` in an .xlsm, deeper in other containers.
pub(super) fn vba_storage<F: Read + std::io::Seek>(cfb: &cfb::CompoundFile<F>) -> Option<String> {
    cfb.walk()
        .filter(|e| e.is_stream() && e.name().eq_ignore_ascii_case("dir"))
        .filter_map(|e| e.path().parent().map(|p| p.to_string_lossy().replace('\\', "/")))
        .find(|p| p.rsplit('/').next().is_some_and(|n| n.eq_ignore_ascii_case("VBA")))
}

thread_local! {
    static STREAMS_READ: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many streams of compound files this thread has read whole so far: lets a test see
/// that a stream named by thousands of modules is read once, by count rather than by a clock.
#[doc(hidden)]
pub fn streams_read_on_this_thread() -> u64 {
    STREAMS_READ.with(std::cell::Cell::get)
}

pub(super) fn read_stream<F: Read + std::io::Seek>(
    cfb: &mut cfb::CompoundFile<F>,
    path: &str,
) -> Result<Vec<u8>, ProjectError> {
    STREAMS_READ.with(|n| n.set(n.get() + 1));
    let mut stream = cfb.open_stream(path).map_err(|e| error(path, format!("cannot open the stream: {e}")))?;
    let mut data = Vec::new();
    stream.read_to_end(&mut data).map_err(|e| error(path, format!("cannot read the stream: {e}")))?;
    Ok(data)
}

#[derive(Debug)]
pub(super) struct DirModule {
    pub name: String,
    pub stream: String,
    pub offset: u32,
    pub kind: ModuleKind,
}

#[derive(Debug)]
pub(super) struct Listing {
    pub code_page: u16,
    pub modules: Vec<DirModule>,
}

/// Record ids of the dir stream ([MS-OVBA] 2.3.4.2) that ncsheet reads.
pub(super) mod id {
    pub const PROJECT_CODE_PAGE: u16 = 0x0003;
    /// PROJECTVERSION: its size field says 4, but 6 bytes follow.
    pub const PROJECT_VERSION: u16 = 0x0009;
    pub const MODULE_NAME: u16 = 0x0019;
    pub const MODULE_NAME_UNICODE: u16 = 0x0047;
    pub const MODULE_STREAM_NAME: u16 = 0x001A;
    pub const MODULE_OFFSET: u16 = 0x0031;
    pub const MODULE_COOKIE: u16 = 0x002C;
    pub const PROJECT_MODULES: u16 = 0x000F;
    pub const PROJECT_COOKIE: u16 = 0x0013;
    pub const MODULE_TYPE_PROCEDURAL: u16 = 0x0021;
    pub const MODULE_TYPE_OTHER: u16 = 0x0022;
    pub const MODULE_TERMINATOR: u16 = 0x002B;
    pub const DIR_TERMINATOR: u16 = 0x0010;
}

/// Walks the dir stream's records: every record is an id, a 32-bit size and that many bytes
/// (PROJECTVERSION aside), so unknown ones are stepped over.
fn parse_dir(dir: &[u8]) -> Result<Listing, String> {
    let mut listing = Listing { code_page: 1252, modules: Vec::new() };
    let mut current: Option<DirModule> = None;
    let mut at = 0;
    while at < dir.len() {
        let header = dir.get(at..at + 6).ok_or_else(|| format!("record at byte {at} cut short"))?;
        let record = u16::from_le_bytes([header[0], header[1]]);
        let mut size = u32::from_le_bytes([header[2], header[3], header[4], header[5]]) as usize;
        if record == id::PROJECT_VERSION {
            size = 6;
        }
        let data =
            dir.get(at + 6..at + 6 + size).ok_or_else(|| format!("record {record:#06x} at byte {at} cut short"))?;
        at += 6 + size;
        match record {
            id::PROJECT_CODE_PAGE if size >= 2 => listing.code_page = u16::from_le_bytes([data[0], data[1]]),
            id::MODULE_NAME => {
                current =
                    Some(DirModule { name: latin(data), stream: String::new(), offset: 0, kind: ModuleKind::Standard })
            }
            id::MODULE_NAME_UNICODE => with_module(&mut current, at, |m| m.name = utf16(data))?,
            id::MODULE_STREAM_NAME => with_module(&mut current, at, |m| m.stream = latin(data))?,
            id::MODULE_OFFSET if size >= 4 => {
                with_module(&mut current, at, |m| m.offset = u32::from_le_bytes([data[0], data[1], data[2], data[3]]))?
            }
            id::MODULE_TYPE_PROCEDURAL => with_module(&mut current, at, |m| m.kind = ModuleKind::Standard)?,
            id::MODULE_TYPE_OTHER => with_module(&mut current, at, |m| m.kind = ModuleKind::DocumentOrClass)?,
            id::MODULE_TERMINATOR => {
                let m = current.take().ok_or_else(|| format!("module end at byte {at} without a module"))?;
                listing.modules.push(m);
            }
            id::DIR_TERMINATOR => return Ok(listing),
            _ => {}
        }
    }
    Err("the dir stream ends without its terminator record".into())
}

fn with_module(current: &mut Option<DirModule>, at: usize, f: impl FnOnce(&mut DirModule)) -> Result<(), String> {
    let m = current.as_mut().ok_or_else(|| format!("module record before byte {at} outside a module"))?;
    f(m);
    Ok(())
}

/// Stream names are MBCS; ASCII in practice (the unicode forms are read where they matter).
pub(super) fn latin(data: &[u8]) -> String {
    data.iter().map(|&b| b as char).collect()
}

fn utf16(data: &[u8]) -> String {
    let units: Vec<u16> = data.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
    String::from_utf16_lossy(&units)
}

/// The text encoding of a Windows code page.
pub(super) fn encoding_for(code_page: u16) -> Option<&'static encoding_rs::Encoding> {
    let label = match code_page {
        874 | 1250..=1258 => format!("windows-{code_page}"),
        932 => "shift_jis".into(),
        936 => "gbk".into(),
        949 => "euc-kr".into(),
        950 => "big5".into(),
        10000 => "macintosh".into(),
        20866 => "koi8-r".into(),
        28591..=28599 => format!("iso-8859-{}", code_page - 28590),
        65001 => "utf-8".into(),
        _ => return None,
    };
    encoding_rs::Encoding::for_label(label.as_bytes())
}

/// The code pages `encoding_for` reads, as a user names them (`--code-page N`).
pub const READABLE_CODE_PAGES: &str = "874, 932, 936, 949, 950, 1250-1258, 10000, 20866, 28591-28599, 65001";

/// Whether ncsheet can read (and write) text in `code_page`.
pub fn is_readable_code_page(code_page: u16) -> bool {
    encoding_for(code_page).is_some()
}

/// The ANSI code pages the VBA editor writes module files in, Western first: the guesses
/// [`guessed_code_page`] may give.
const ANSI_CODE_PAGES: [u16; 14] = [1252, 1250, 1251, 1253, 1254, 1255, 1256, 1257, 1258, 874, 932, 936, 949, 950];

/// The ANSI code page a module file's text is in, guessed from its bytes when nobody names one,
/// or `None` when the file needs none (a byte-order mark, ASCII, valid UTF-8) or the guess is
/// no code page the VBA editor writes in. The file does not record its code page, and every
/// byte is some character of Windows-1252, so reading 1252 by default garbles a Cyrillic or
/// Japanese module without a word; chardetng (the detector Firefox uses for legacy text)
/// tells a Western module with a "°" from a Cyrillic, Greek, Shift_JIS, GBK or Big5 one.
pub fn guessed_code_page(bytes: &[u8]) -> Option<u16> {
    if encoding_rs::Encoding::for_bom(bytes).is_some() || std::str::from_utf8(bytes).is_ok() {
        return None;
    }
    let mut detector = chardetng::EncodingDetector::new(chardetng::Iso2022JpDetection::Deny);
    detector.feed(bytes, true);
    let guess = detector.guess(None, chardetng::Utf8Detection::Deny);
    ANSI_CODE_PAGES.into_iter().find(|&code_page| encoding_for(code_page) == Some(guess))
}

/// Where a module file's bytes are no text of the encoding they are read in.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceTextError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

/// The text of a module file (.bas, .cls) as the VBA editor exports it, in the ANSI code page
/// `code_page` (the user's, or the project's PROJECTCODEPAGE). A UTF-8 or UTF-16 byte-order
/// mark, or bytes that are all valid UTF-8, say the file was saved as Unicode by another
/// editor. Bytes the code page has no character for are an error at their line and column.
/// Without a code page, a byte past ASCII in a file that is not UTF-8 is an error at its place
/// (`UNKNOWN_CODE_PAGE`): the editor wrote it in the system's ANSI code page, which the file
/// does not say, and every byte is some character of 1252, so guessing would garble the text
/// of a Cyrillic or Greek module without a word.
pub fn decode_module_file(bytes: &[u8], code_page: Option<u16>) -> Result<String, SourceTextError> {
    if let Some((encoding, bom)) = encoding_rs::Encoding::for_bom(bytes) {
        return decode_strictly(&bytes[bom..], encoding, &format!("{} (its byte-order mark)", encoding.name()));
    }
    if let Ok(text) = std::str::from_utf8(bytes) {
        return Ok(text.to_string());
    }
    let Some(code_page) = code_page else {
        return Err(first_byte_past_ascii(bytes));
    };
    let Some(encoding) = encoding_for(code_page) else {
        return Err(SourceTextError {
            line: 1,
            column: 1,
            message: format!("code page {code_page} is not one ncsheet can read"),
        });
    };
    decode_strictly(bytes, encoding, &format!("code page {code_page}"))
}

/// What a module file without a code page says of itself: the message is `UNKNOWN_CODE_PAGE`.
pub const UNKNOWN_CODE_PAGE: &str = "a byte past ASCII in a file that is not UTF-8, and no code page to read it in";

/// The place of the first byte past ASCII (the file is not UTF-8, so there is one), its column
/// counted in bytes: what character it starts is what is not known.
fn first_byte_past_ascii(bytes: &[u8]) -> SourceTextError {
    let at = bytes.iter().position(|b| !b.is_ascii()).unwrap_or(0);
    let line_start = bytes[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
    SourceTextError {
        line,
        column: at - line_start + 1,
        message: format!("{UNKNOWN_CODE_PAGE} (0x{:02X})", bytes.get(at).copied().unwrap_or(0)),
    }
}

/// Decodes line by line (no code page VBA uses has a newline byte inside a character), so a
/// malformed byte is found at its line; in a single-byte code page, the bytes it leaves
/// undefined (0x81, 0x8D … in 1252, decoded as C1 controls) are malformed too.
fn decode_strictly(
    bytes: &[u8],
    encoding: &'static encoding_rs::Encoding,
    what: &str,
) -> Result<String, SourceTextError> {
    let mut text = String::with_capacity(bytes.len());
    let lines = bytes.split_inclusive(|&b| b == b'\n');
    for (n, line) in lines.enumerate() {
        let (decoded, malformed) = encoding.decode_without_bom_handling(line);
        let is_utf =
            encoding == encoding_rs::UTF_8 || encoding == encoding_rs::UTF_16LE || encoding == encoding_rs::UTF_16BE;
        let bad = |c: char| c == '\u{FFFD}' || (!is_utf && ('\u{80}'..='\u{9F}').contains(&c));
        if malformed || decoded.chars().any(bad) {
            let column = decoded.chars().position(bad).unwrap_or(0) + 1;
            return Err(SourceTextError {
                line: n + 1,
                column,
                message: format!("bytes that are no character of {what}"),
            });
        }
        text.push_str(&decoded);
    }
    Ok(text)
}

/// A module file as the VBA editor exports it: a .bas is a standard module; a .cls (`is_cls`,
/// or a first line `VERSION 1.0 CLASS`) is a class module, whose `BEGIN … END` block of
/// properties the editor keeps as the `Attribute VB_…` lines after it, so the block is no part
/// of the stored source. A UserForm (.frm, `VERSION 5.00`) needs its designer storage and a
/// document module (`Attribute VB_Base`) its sheet: both are refused by name.
pub fn module_from_export(text: &str, is_cls: bool) -> Result<(ModuleKind, String), String> {
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or_default().trim();
    let has_header = first.len() >= 8 && first[..8].eq_ignore_ascii_case("VERSION ");
    if has_header && !first.to_ascii_uppercase().ends_with(" CLASS") {
        return Err(format!(
            "'{first}' starts a UserForm (.frm), which needs its designer (.frx): ncsheet imports .bas and .cls modules"
        ));
    }
    let attribute = |name: &str| {
        text.lines().any(|l| {
            let l = l.trim_start().to_ascii_lowercase();
            l.starts_with("attribute ") && l["attribute ".len()..].trim_start().starts_with(name)
        })
    };
    if attribute("vb_base") {
        return Err("a document module (its Attribute VB_Base binds it to a sheet or the workbook) is not imported: \
                    put its code into a .bas module"
            .into());
    }
    if !has_header {
        let kind = if is_cls { ModuleKind::Class } else { ModuleKind::Standard };
        return Ok((kind, text.to_string()));
    }
    let mut rest = text;
    let mut ended = false;
    let mut begun = false;
    while let Some(line) = rest.split_inclusive('\n').next() {
        rest = &rest[line.len()..];
        let word = line.trim();
        begun |= word.eq_ignore_ascii_case("BEGIN");
        if begun && word.eq_ignore_ascii_case("END") {
            ended = true;
            break;
        }
    }
    if !ended {
        return Err("the VERSION 1.0 CLASS header has no BEGIN … END block".into());
    }
    Ok((ModuleKind::Class, rest.to_string()))
}

/// A module to put into a new project: its name, kind and source (as exported: CRLF line
/// ends; a first `Attribute VB_Name` line is added where the source has none).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NewModule {
    pub name: String,
    pub kind: ModuleKind,
    pub source: String,
}

/// The project identifier of the projects ncsheet makes; any GUID will do.
const PROJECT_ID: &str = "{5A6E4353-4845-4554-0000-4E4353484545}";

/// A new `vbaProject.bin` holding `modules` as source only ([MS-OVBA] 2.3): no compiled
/// code, and a `_VBA_PROJECT` version of 0xFFFF, which makes Excel compile the source when
/// it opens the workbook. Text is written in code page 1252; `seed` makes the obfuscated
/// protection fields of the PROJECT stream reproducible.
pub fn build_project(modules: &[NewModule], seed: u8) -> Result<Vec<u8>, ProjectError> {
    build_project_in(modules, seed, 1252)
}

/// `build_project` with the modules' text in `code_page`, which its PROJECTCODEPAGE record
/// declares (a Cyrillic module in 1251, as a Russian Excel writes it).
pub fn build_project_in(modules: &[NewModule], seed: u8, code_page: u16) -> Result<Vec<u8>, ProjectError> {
    let Some(encoding) = encoding_for(code_page) else {
        return Err(error("VBA/dir", format!("code page {code_page} is not one ncsheet can write")));
    };
    let mut cfb = cfb::CompoundFile::create(Cursor::new(Vec::new())).map_err(|e| error("vbaProject.bin", e))?;
    cfb.create_storage("/VBA").map_err(|e| error("VBA", e))?;
    let mut put = |path: &str, data: &[u8]| -> Result<(), ProjectError> {
        let mut s = cfb.create_stream(path).map_err(|e| error(path, e))?;
        std::io::Write::write_all(&mut s, data).map_err(|e| error(path, e))
    };
    let mut encoded = Vec::with_capacity(modules.len());
    for m in modules {
        let source = with_name_attribute(&m.source, &m.name);
        let (bytes, _, unmappable) = encoding.encode(&source);
        if unmappable {
            return Err(error(&m.name, unwritable_text(&m.source, encoding, code_page)));
        }
        encoded.push(bytes.into_owned());
    }
    // The names in the code page too (a module `Módulo1` in 1252); the rest of the text is
    // ASCII, the same bytes in every code page ncsheet writes.
    put("/PROJECT", &encoding.encode(&project_stream(modules, seed)).0)?;
    put("/PROJECTwm", &name_map(modules, encoding))?;
    // Reserved1 0x61CC, Version 0xFFFF (no compiled cache), Reserved2, Reserved3.
    put("/VBA/_VBA_PROJECT", &[0xCC, 0x61, 0xFF, 0xFF, 0x00, 0x00, 0x00])?;
    let dir = dir_stream(modules, code_page, encoding);
    put("/VBA/dir", &ovba::compress(&dir).map_err(|e| error("VBA/dir", e))?)?;
    for (m, source) in modules.iter().zip(&encoded) {
        let path = format!("/VBA/{}", m.name);
        put(&path, &ovba::compress(source).map_err(|e| error(&path, e))?)?;
    }
    cfb.flush().map_err(|e| error("vbaProject.bin", e))?;
    Ok(cfb.into_inner().into_inner())
}

/// Why a module's text cannot be written in the project's code page: the first character it
/// has no byte for, at its line and column in the module's file (a `₂` in a comment of a UTF-8
/// module, which the VBA editor would import as three Western letters), so the user can find it.
pub(super) fn unwritable_text(source: &str, encoding: &'static encoding_rs::Encoding, code_page: u16) -> String {
    let mut utf8 = [0u8; 4];
    for (line, text) in source.lines().enumerate() {
        for (column, c) in text.chars().enumerate() {
            if encoding.encode(c.encode_utf8(&mut utf8)).2 {
                let at = format!("line {}, column {}", line + 1, column + 1);
                return format!("{at}: {c:?} (U+{:04X}) is a character code page {code_page} cannot write", c as u32);
            }
        }
    }
    format!("holds characters code page {code_page} cannot write")
}

pub(super) fn with_name_attribute(source: &str, name: &str) -> String {
    let source = source.replace("\r\n", "\n").replace('\n', "\r\n");
    if source.trim_start().to_ascii_lowercase().starts_with("attribute vb_name") {
        return source;
    }
    format!("Attribute VB_Name = \"{name}\"\r\n{source}")
}

/// The PROJECT stream ([MS-OVBA] 2.3.1): the project's properties as text.
fn project_stream(modules: &[NewModule], seed: u8) -> String {
    let mut text = format!("ID=\"{PROJECT_ID}\"\r\n");
    for m in modules {
        match m.kind {
            ModuleKind::Standard => text += &format!("Module={}\r\n", m.name),
            ModuleKind::DocumentOrClass => text += &format!("Document={}/&H00000000\r\n", m.name),
            ModuleKind::Class => text += &format!("Class={}\r\n", m.name),
        }
    }
    text += "Name=\"VBAProject\"\r\nHelpContextID=\"0\"\r\nVersionCompatible32=\"393222000\"\r\n";
    // Not protected, no password, visible (2.3.1.15-17), obfuscated as 2.4.3.2 says.
    text += &unprotected_lines(PROJECT_ID.as_bytes(), seed);
    text += "\r\n";
    text += "[Host Extender Info]\r\n&H00000001={3832D640-CF90-11CF-8E43-00A0C911005A};VBE;&H00000000\r\n";
    text
}

/// The CMG, DPB and GC lines of a project with no protection: not protected, no password,
/// visible (2.3.1.15-17), for the project whose ID line holds `project_id`.
pub(super) fn unprotected_lines(project_id: &[u8], seed: u8) -> String {
    format!(
        "CMG=\"{}\"\r\nDPB=\"{}\"\r\nGC=\"{}\"\r\n",
        encrypt(&[0, 0, 0, 0], seed, project_id),
        encrypt(&[0], seed.wrapping_add(1), project_id),
        encrypt(&[0xFF], seed.wrapping_add(2), project_id)
    )
}

/// Data Encryption ([MS-OVBA] 2.4.3.2), as upper-case hex; the key is the sum of the bytes of
/// the project's identifier (its ID line's value, braces included).
fn encrypt(data: &[u8], seed: u8, project_id: &[u8]) -> String {
    let version = 2u8;
    let proj_key = project_id.iter().copied().fold(0u8, u8::wrapping_add);
    let mut out = vec![seed, seed ^ version, seed ^ proj_key];
    let (mut plain1, mut enc1, mut enc2) = (proj_key, seed ^ proj_key, seed ^ version);
    let mut push = |byte: u8, out: &mut Vec<u8>| {
        let enc = (enc2.wrapping_add(plain1)) ^ byte;
        out.push(enc);
        enc2 = enc1;
        enc1 = enc;
        plain1 = byte;
    };
    let ignored = (seed & 6) / 2;
    for _ in 0..ignored {
        push(7, &mut out);
    }
    for b in (data.len() as u32).to_le_bytes().into_iter().chain(data.iter().copied()) {
        push(b, &mut out);
    }
    out.iter().map(|b| format!("{b:02X}")).collect()
}

/// PROJECTwm (2.3.3): each module's name in MBCS and in UTF-16.
fn name_map(modules: &[NewModule], encoding: &'static encoding_rs::Encoding) -> Vec<u8> {
    let mut out = Vec::new();
    for m in modules {
        out.extend(encoding.encode(&m.name).0.iter());
        out.push(0);
        out.extend(m.name.encode_utf16().flat_map(u16::to_le_bytes));
        out.extend([0, 0]);
    }
    out.extend([0, 0]);
    out
}

/// Appends one dir-stream record: its id, size and data.
pub(super) fn push_record(d: &mut Vec<u8>, id: u16, data: &[u8]) {
    d.extend(id.to_le_bytes());
    d.extend((data.len() as u32).to_le_bytes());
    d.extend_from_slice(data);
}

/// The records of one source-only module (2.3.4.2.3.2): named `name` (`mbcs`: the name in
/// the project's code page), in a stream of that name, its source from offset 0.
pub(super) fn push_module_records(d: &mut Vec<u8>, name: &str, mbcs: &[u8], kind: ModuleKind) {
    let utf16: Vec<u8> = name.encode_utf16().flat_map(u16::to_le_bytes).collect();
    push_record(d, id::MODULE_NAME, mbcs);
    push_record(d, id::MODULE_NAME_UNICODE, &utf16);
    push_record(d, id::MODULE_STREAM_NAME, mbcs);
    push_record(d, 0x0032, &utf16);
    push_record(d, 0x001C, b""); // MODULEDOCSTRING
    push_record(d, 0x0048, b"");
    push_record(d, id::MODULE_OFFSET, &0u32.to_le_bytes());
    push_record(d, 0x001E, &0u32.to_le_bytes()); // MODULEHELPCONTEXT
    push_record(d, id::MODULE_COOKIE, &0xFFFFu16.to_le_bytes());
    let kind = match kind {
        ModuleKind::Standard => id::MODULE_TYPE_PROCEDURAL,
        ModuleKind::DocumentOrClass | ModuleKind::Class => id::MODULE_TYPE_OTHER,
    };
    push_record(d, kind, b"");
    push_record(d, id::MODULE_TERMINATOR, b"");
}

/// The dir stream (2.3.4.2), uncompressed.
fn dir_stream(modules: &[NewModule], code_page: u16, encoding: &'static encoding_rs::Encoding) -> Vec<u8> {
    let mut d = Vec::new();
    let rec = |id: u16, data: &[u8], d: &mut Vec<u8>| push_record(d, id, data);
    rec(0x0001, &1u32.to_le_bytes(), &mut d); // PROJECTSYSKIND: 32-bit Windows
    rec(0x0002, &0x0409u32.to_le_bytes(), &mut d); // PROJECTLCID
    rec(0x0014, &0x0409u32.to_le_bytes(), &mut d); // PROJECTLCIDINVOKE
    rec(id::PROJECT_CODE_PAGE, &code_page.to_le_bytes(), &mut d);
    rec(0x0004, b"VBAProject", &mut d); // PROJECTNAME
    rec(0x0005, b"", &mut d); // PROJECTDOCSTRING
    rec(0x0040, b"", &mut d);
    rec(0x0006, b"", &mut d); // PROJECTHELPFILEPATH
    rec(0x003D, b"", &mut d);
    rec(0x0007, &0u32.to_le_bytes(), &mut d); // PROJECTHELPCONTEXT
    rec(0x0008, &0u32.to_le_bytes(), &mut d); // PROJECTLIBFLAGS
                                              // PROJECTVERSION: Reserved (4), VersionMajor, VersionMinor.
    d.extend(id::PROJECT_VERSION.to_le_bytes());
    d.extend(4u32.to_le_bytes());
    d.extend(1u32.to_le_bytes());
    d.extend(0u16.to_le_bytes());
    rec(0x000C, b"", &mut d); // PROJECTCONSTANTS
    rec(0x003C, b"", &mut d);
    rec(id::PROJECT_MODULES, &(modules.len() as u16).to_le_bytes(), &mut d); // PROJECTMODULES
    rec(id::PROJECT_COOKIE, &0xFFFFu16.to_le_bytes(), &mut d); // PROJECTCOOKIE
    for m in modules {
        push_module_records(&mut d, &m.name, &encoding.encode(&m.name).0, m.kind);
    }
    rec(id::DIR_TERMINATOR, b"", &mut d);
    d
}

#[cfg(test)]
mod tests {

    #[test]
    fn procedures_are_the_declaration_lines() {
        let src = "Attribute VB_Name = \"M\"\r\nPublic Sub A(x As Double)\r\n  Dim s\r\nEnd Sub\r\n\
                   Private Function B() As Long\r\nEnd Function\r\nProperty Get C() As Long\r\nEnd Property\r\n' Sub D()\r\n";
        assert_eq!(
            procedures(src),
            ["Public Sub A(x As Double)", "Private Function B() As Long", "Property Get C() As Long"]
        );
    }

    use super::*;

    #[test]
    fn garbage_is_an_error_naming_the_file() {
        let e = read_project(b"not a compound file").unwrap_err();
        assert_eq!(e.stream, "vbaProject.bin");
    }

    #[test]
    fn a_dir_stream_without_terminator_is_an_error() {
        let mut dir = Vec::new();
        dir.extend_from_slice(&id::PROJECT_CODE_PAGE.to_le_bytes());
        dir.extend_from_slice(&2u32.to_le_bytes());
        dir.extend_from_slice(&1252u16.to_le_bytes());
        assert!(parse_dir(&dir).unwrap_err().contains("terminator"));
        dir.extend_from_slice(&id::MODULE_NAME.to_le_bytes());
        dir.extend_from_slice(&99u32.to_le_bytes());
        assert!(parse_dir(&dir).unwrap_err().contains("cut short"));
    }

    /// [MS-OVBA] 3.1.6's PROJECT stream: an unprotected project, whose CMG the encryption
    /// of 2.4.3.2 gives again from the same seed.
    #[test]
    fn the_specs_example_project_is_unprotected() {
        let text = b"ID=\"{917DED54-440B-4FD1-A5C1-74ACF261E600}\"\r\nName=\"VBAProject\"\r\n\
                     CMG=\"0705D8E3D8EDDBF1DBF1DBF1DBF1\"\r\nDPB=\"0E0CD1ECDFF4E7F5E7F5E7\"\r\n\
                     GC=\"1517CAF1D6F9D7F9D706\"\r\n\r\n[Host Extender Info]\r\n";
        assert_eq!(read_protection(text), Ok(Protection::default()));
        let id = b"{917DED54-440B-4FD1-A5C1-74ACF261E600}";
        assert_eq!(encrypt(&[0, 0, 0, 0], 0x07, id), "0705D8E3D8EDDBF1DBF1DBF1DBF1");
        assert_eq!(encrypt(&[0], 0x0E, id), "0E0CD1ECDFF4E7F5E7F5E7");
        assert_eq!(encrypt(&[0xFF], 0x15, id), "1517CAF1D6F9D7F9D706");
    }

    #[test]
    fn protection_fields_that_do_not_decode_are_named() {
        let text = b"ID=\"{917DED54-440B-4FD1-A5C1-74ACF261E600}\"\r\nCMG=\"0705D8\"\r\nDPB=\"XY\"\r\nGC=\"15\"\r\n";
        assert!(read_protection(text).unwrap_err().contains("CMG"));
    }

    /// Windows-1252 as its code chart gives it: 0xE9 é, 0x80 €, 0x96 en dash; 0x81 undefined.
    #[test]
    fn module_files_decode_by_the_code_page() {
        assert_eq!(decode_module_file(b"' caf\xE9 \x80 \x96\r\n", Some(1252)).unwrap(), "' café € –\r\n");
        assert_eq!(decode_module_file("' café\r\n".as_bytes(), Some(1252)).unwrap(), "' café\r\n");
        assert_eq!(decode_module_file(b"\xEF\xBB\xBF' x\r\n", Some(1252)).unwrap(), "' x\r\n");
        let e = decode_module_file(b"Sub A()\r\n  x = \"a\x81\"\r\n", Some(1252)).unwrap_err();
        assert_eq!((e.line, e.column), (2, 9));
        let e = decode_module_file(b"\xEF\xBB\xBF' \xE9\r\n", Some(1252)).unwrap_err();
        assert_eq!((e.line, e.column), (1, 3));
        // Shift_JIS: 0x93 0xFA is 日; 0x93 alone before a newline is cut short.
        assert_eq!(decode_module_file(b"' \x93\xFA\r\n", Some(932)).unwrap(), "' 日\r\n");
        assert_eq!(decode_module_file(b"'\r\n' \x93\r\n", Some(932)).unwrap_err().line, 2);
    }

    /// A Windows-1251 module: "Сумма прописью" is D1 F3 EC EC E0 20 EF F0 EE EF E8 F1 FC FE
    /// (Python's `'Сумма прописью'.encode('cp1251')`). In 1251 it reads as written; with no
    /// code page it is refused at its first such byte, where 1252 would have read "Ñóììà".
    #[test]
    fn a_module_past_ascii_needs_its_code_page() {
        let bytes = b"Sub A()\r\n  s = \"\xD1\xF3\xEC\xEC\xE0 \xEF\xF0\xEE\xEF\xE8\xF1\xFC\xFE\"\r\n";
        assert_eq!(decode_module_file(bytes, Some(1251)).unwrap(), "Sub A()\r\n  s = \"Сумма прописью\"\r\n");
        let e = decode_module_file(bytes, None).unwrap_err();
        assert_eq!((e.line, e.column), (2, 8));
        assert!(e.message.starts_with(UNKNOWN_CODE_PAGE) && e.message.ends_with("(0xD1)"), "{}", e.message);
        // ASCII and UTF-8 need none.
        assert_eq!(decode_module_file("' Сумма\r\n".as_bytes(), None).unwrap(), "' Сумма\r\n");
    }

    /// Module text in each ANSI code page, encoded by Python (`str.encode(cp)`), is guessed as
    /// that code page; Unicode files need no guess.
    #[test]
    fn a_module_files_code_page_is_guessed_from_its_text() {
        let cases: [(&[u8], u16); 6] = [
            // "' Winkel in Grad (°), Größe" in cp1252.
            (b"' Winkel in Grad (\xB0), Gr\xF6\xDFe\r\nSub A()\r\nEnd Sub\r\n", 1252),
            // "' Сумма прописью" in cp1251.
            (b"' \xD1\xF3\xEC\xEC\xE0 \xEF\xF0\xEE\xEF\xE8\xF1\xFC\xFE\r\nSub A()\r\nEnd Sub\r\n", 1251),
            // "' 近似式を求める" in cp932.
            (b"' \x8B\xDF\x8E\x97\x8E\xAE\x82\xF0\x8B\x81\x82\xDF\x82\xE9\r\nSub A()\r\nEnd Sub\r\n", 932),
            // "' 计算坐标点" in GBK (cp936).
            (b"' \xBC\xC6\xCB\xE3\xD7\xF8\xB1\xEA\xB5\xE3\r\nSub A()\r\nEnd Sub\r\n", 936),
            // "' 計算座標點" in Big5 (cp950).
            (b"' \xAD\x70\xBA\xE2\xAE\x79\xBC\xD0\xC2\x49\r\nSub A()\r\nEnd Sub\r\n", 950),
            // "' Επιφάνεια" in cp1253.
            (b"' \xC5\xF0\xE9\xF6\xDC\xED\xE5\xE9\xE1\r\nSub A()\r\nEnd Sub\r\n", 1253),
        ];
        for (bytes, code_page) in cases {
            assert_eq!(guessed_code_page(bytes), Some(code_page), "{bytes:?}");
        }
        assert_eq!(guessed_code_page("' Сумма\r\n".as_bytes()), None);
        assert_eq!(guessed_code_page(b"Sub A()\r\nEnd Sub\r\n"), None);
    }

    /// Every code page the list names reads, and the list's ends are its neighbours' limits.
    #[test]
    fn the_readable_code_pages_are_the_ones_listed() {
        for part in READABLE_CODE_PAGES.split(", ") {
            let (lo, hi) = part.split_once('-').unwrap_or((part, part));
            let (lo, hi): (u16, u16) = (lo.parse().unwrap(), hi.parse().unwrap());
            assert!((lo..=hi).all(is_readable_code_page), "{part}");
        }
        assert!(!is_readable_code_page(1249) && !is_readable_code_page(1259) && !is_readable_code_page(437));
    }

    #[test]
    fn a_class_files_header_is_no_part_of_its_source() {
        let cls = "VERSION 1.0 CLASS\r\nBEGIN\r\n  MultiUse = -1  'True\r\nEND\r\nAttribute VB_Name = \"Tool\"\r\nPublic D\r\n";
        let (kind, source) = module_from_export(cls, true).unwrap();
        assert_eq!((kind, source.as_str()), (ModuleKind::Class, "Attribute VB_Name = \"Tool\"\r\nPublic D\r\n"));
        assert_eq!(module_from_export("Sub A()\nEnd Sub\n", false).unwrap().0, ModuleKind::Standard);
        assert!(module_from_export("VERSION 5.00\r\nBegin {C62A69F0-16DC-11CE-9E98-00AA00574A4F} F\r\n", false)
            .unwrap_err()
            .contains("UserForm"));
        let doc =
            "VERSION 1.0 CLASS\r\nBEGIN\r\nEND\r\nAttribute VB_Base = \"0{00020820-0000-0000-C000-000000000046}\"\r\n";
        assert!(module_from_export(doc, true).unwrap_err().contains("document module"));
        assert!(module_from_export("VERSION 1.0 CLASS\r\nBEGIN\r\n", true).unwrap_err().contains("END"));
    }

    #[test]
    fn a_built_project_reads_back() {
        let modules = [
            NewModule { name: "ThisWorkbook".into(), kind: ModuleKind::DocumentOrClass, source: String::new() },
            NewModule {
                name: "Chamfer".into(),
                kind: ModuleKind::Standard,
                source: "Sub Main()\n  x = 1\nEnd Sub\n".into(),
            },
        ];
        let project = read_project(&build_project(&modules, 0x5A).unwrap()).unwrap();
        assert_eq!(project.modules.len(), 2);
        assert_eq!(project.modules[1].name, "Chamfer");
        assert_eq!(project.modules[1].kind, ModuleKind::Standard);
        assert_eq!(
            project.modules[1].source,
            "Attribute VB_Name = \"Chamfer\"\r\nSub Main()\r\n  x = 1\r\nEnd Sub\r\n"
        );
    }
}
