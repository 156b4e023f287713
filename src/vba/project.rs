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

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModuleKind {
    /// A standard module (`Module1`): exported as .bas.
    Standard,
    /// A document module (`ThisWorkbook`, `Sheet1`) or a class: exported as .cls.
    DocumentOrClass,
}

impl ModuleKind {
    pub fn extension(self) -> &'static str {
        match self {
            ModuleKind::Standard => "bas",
            ModuleKind::DocumentOrClass => "cls",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VbaProject {
    pub code_page: u16,
    pub modules: Vec<ProjectModule>,
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
    let mut cfb = cfb::CompoundFile::open(Cursor::new(bytes))
        .map_err(|e| error("vbaProject.bin", format!("not an OLE compound file: {e}")))?;
    let storage = vba_storage(&cfb).ok_or_else(|| error("vbaProject.bin", "no VBA storage with a dir stream"))?;
    let dir_name = format!("{storage}/dir");
    let dir = read_stream(&mut cfb, &dir_name)?;
    let dir = ovba::decompress(&dir).map_err(|e| error(&dir_name, e))?;
    let listing = parse_dir(&dir).map_err(|m| error(&dir_name, m))?;
    let encoding = encoding_for(listing.code_page)
        .ok_or_else(|| error(&dir_name, format!("code page {} is not one ncsheet can read", listing.code_page)))?;
    let mut modules = Vec::with_capacity(listing.modules.len());
    for m in listing.modules {
        let path = format!("{storage}/{}", m.stream);
        let data = read_stream(&mut cfb, &path)?;
        let Some(compressed) = data.get(m.offset as usize..) else {
            return Err(error(
                &path,
                format!("source offset {} is past the stream's end ({} bytes)", m.offset, data.len()),
            ));
        };
        let text = ovba::decompress(compressed).map_err(|e| error(&path, e))?;
        let (source, _, _) = encoding.decode(&text);
        modules.push(ProjectModule { name: m.name, stream: m.stream, kind: m.kind, source: source.into_owned() });
    }
    Ok(VbaProject { code_page: listing.code_page, modules })
}

/// The storage that holds the `dir` stream: `/VBA` in an .xlsm, deeper in other containers.
fn vba_storage<F: Read + std::io::Seek>(cfb: &cfb::CompoundFile<F>) -> Option<String> {
    cfb.walk()
        .filter(|e| e.is_stream() && e.name().eq_ignore_ascii_case("dir"))
        .filter_map(|e| e.path().parent().map(|p| p.to_string_lossy().replace('\\', "/")))
        .find(|p| p.rsplit('/').next().is_some_and(|n| n.eq_ignore_ascii_case("VBA")))
}

fn read_stream<F: Read + std::io::Seek>(cfb: &mut cfb::CompoundFile<F>, path: &str) -> Result<Vec<u8>, ProjectError> {
    let mut stream = cfb.open_stream(path).map_err(|e| error(path, format!("cannot open the stream: {e}")))?;
    let mut data = Vec::new();
    stream.read_to_end(&mut data).map_err(|e| error(path, format!("cannot read the stream: {e}")))?;
    Ok(data)
}

#[derive(Debug)]
struct DirModule {
    name: String,
    stream: String,
    offset: u32,
    kind: ModuleKind,
}

#[derive(Debug)]
struct Listing {
    code_page: u16,
    modules: Vec<DirModule>,
}

/// Record ids of the dir stream ([MS-OVBA] 2.3.4.2) that ncsheet reads.
mod id {
    pub const PROJECT_CODE_PAGE: u16 = 0x0003;
    /// PROJECTVERSION: its size field says 4, but 6 bytes follow.
    pub const PROJECT_VERSION: u16 = 0x0009;
    pub const MODULE_NAME: u16 = 0x0019;
    pub const MODULE_NAME_UNICODE: u16 = 0x0047;
    pub const MODULE_STREAM_NAME: u16 = 0x001A;
    pub const MODULE_OFFSET: u16 = 0x0031;
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
fn latin(data: &[u8]) -> String {
    data.iter().map(|&b| b as char).collect()
}

fn utf16(data: &[u8]) -> String {
    let units: Vec<u16> = data.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
    String::from_utf16_lossy(&units)
}

/// The text encoding of a Windows code page.
fn encoding_for(code_page: u16) -> Option<&'static encoding_rs::Encoding> {
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

#[cfg(test)]
mod tests {
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
}
