//! Adding modules to a workbook's existing VBA project ([MS-OVBA] 2.3): a new
//! `vbaProject.bin` that keeps every storage and stream of the old one (references, forms,
//! document modules and their bindings) and every module's source as stored, and adds the new
//! modules. All modules are written source-only (2.3.4.3: no performance cache, offset 0), the
//! `_VBA_PROJECT` stream is reduced to its version-independent header with version 0xFFFF
//! (2.3.4.1) and the `__SRP_*` caches are dropped, so Excel compiles the source on open
//! instead of running a compiled form that no longer matches it.

use std::collections::BTreeMap;
use std::io::{Cursor, Write};

use super::ovba;
use super::project::{
    id, open_parts, property, push_module_records, push_record, read_protection, read_stream, unprotected_lines,
    unwritable_text, with_name_attribute, DirModule, ModuleKind, NewModule, Parts, ProjectError,
};

/// What to do with a new module whose name the project already has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnExisting {
    Refuse,
    /// Replace the standard module of that name (a document module or class is never replaced).
    Replace,
}

/// What to do with a project its owner protected (a password, locked for viewing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnProtected {
    /// Refuse: the VBA editor would not let a user without the password edit it either.
    Refuse,
    /// Write the project without its protection (no password, not locked).
    Unprotect,
}

fn error(stream: &str, message: impl std::fmt::Display) -> ProjectError {
    ProjectError { stream: stream.to_string(), message: message.to_string() }
}

/// A module to add, with its name in the project's code page.
struct Added<'m> {
    module: &'m NewModule,
    mbcs: Vec<u8>,
}

/// The bytes of a new `vbaProject.bin`: the project in `bytes` with `modules` added (or,
/// with [`OnExisting::Replace`], put in place of standard modules of the same name). A
/// protected project is refused, or with [`OnProtected::Unprotect`] written unprotected.
pub fn add_modules(
    bytes: &[u8],
    modules: &[NewModule],
    on_existing: OnExisting,
    on_protected: OnProtected,
) -> Result<Vec<u8>, ProjectError> {
    let mut parts = open_parts(bytes)?;
    let project_text = match on_protected {
        OnProtected::Refuse => {
            refuse_protected(&parts)?;
            parts.project_text.clone()
        }
        OnProtected::Unprotect => unprotected(&parts.project_text).map_err(|m| error(&parts.project_path, m))?,
    };
    let encoding = parts.encoding()?;
    // Streams of the old file written with new contents, by lower-case path.
    let mut replaced: BTreeMap<String, Vec<u8>> = BTreeMap::new();
    let listed = std::mem::take(&mut parts.listing.modules);
    for m in &listed {
        let text = parts.module_text(m)?;
        let path = parts.stream_path(m);
        replaced.insert(path.to_ascii_lowercase(), compress(&path, &text)?);
    }
    parts.listing.modules = listed;
    let mut added: Vec<Added> = Vec::new();
    let mut created: Vec<(String, Vec<u8>)> = Vec::new();
    for new in modules {
        check_name(&parts, new, &added, on_existing)?;
        let text = encode(&with_name_attribute(&new.source, &new.name), encoding)
            .ok_or_else(|| error(&new.name, unwritable_text(&new.source, encoding, parts.listing.code_page)))?;
        match existing(&parts.listing.modules, &new.name) {
            Some(old) => {
                let path = parts.stream_path(old);
                replaced.insert(path.to_ascii_lowercase(), compress(&path, &text)?);
            }
            None => {
                let path = format!("{}/{}", parts.storage, new.name);
                let packed = compress(&path, &text)?;
                created.push((path, packed));
                let mbcs = encode(&new.name, encoding).ok_or_else(|| {
                    error(&new.name, format!("is a name code page {} cannot write", parts.listing.code_page))
                })?;
                added.push(Added { module: new, mbcs });
            }
        }
    }
    let dir_path = format!("{}/dir", parts.storage);
    let dir = rebuild_dir(&parts.dir, parts.listing.modules.len(), &added).map_err(|m| error(&dir_path, m))?;
    replaced.insert(dir_path.to_ascii_lowercase(), compress(&dir_path, &dir)?);
    // Reserved1 0x61CC, Version 0xFFFF (no compiled cache), Reserved2 0, Reserved3.
    replaced
        .insert(format!("{}/_vba_project", parts.storage).to_ascii_lowercase(), vec![0xCC, 0x61, 0xFF, 0xFF, 0, 1, 0]);
    replaced.insert(parts.project_path.to_ascii_lowercase(), with_module_lines(&project_text, &added));
    let wm_path = sibling(&parts, "PROJECTwm");
    if parts.cfb.is_stream(&wm_path) {
        let wm = read_stream(&mut parts.cfb, &wm_path)?;
        replaced.insert(wm_path.to_ascii_lowercase(), with_names(&wm, &added).map_err(|m| error(&wm_path, m))?);
    }
    write_project(&mut parts, &replaced, &created)
}

/// An error naming the project's protection, if it has one; fields that do not decode are
/// taken for protection too, since nothing says the owner did not lock the project.
fn refuse_protected(parts: &Parts) -> Result<(), ProjectError> {
    let what = match read_protection(&parts.project_text) {
        Ok(p) if !p.is_protected() => return Ok(()),
        Ok(p) => format!("the VBA project {}", p.describe()),
        Err(m) => format!("the VBA project's protection cannot be read ({m})"),
    };
    Err(error(
        &parts.project_path,
        format!(
            "{what}: ncsheet does not edit a protected project, which Excel would refuse or open unprotected \
             (--unprotect writes it without the protection)"
        ),
    ))
}

/// The PROJECT stream with its CMG, DPB and GC lines saying "no protection" (2.3.1.15-17),
/// encrypted with the project's own identifier; every other line as it was.
fn unprotected(text: &[u8]) -> Result<Vec<u8>, String> {
    let id = property(text, "ID").ok_or("does not start with the project's ID= line")?;
    let id = id.strip_prefix(b"\"").and_then(|i| i.strip_suffix(b"\"")).unwrap_or(id);
    let mut lines = unprotected_lines(id, 0x2A).into_bytes();
    let mut out = Vec::with_capacity(text.len());
    for line in text.split_inclusive(|&b| b == b'\n') {
        if [&b"CMG="[..], b"DPB=", b"GC="].iter().any(|k| line.starts_with(k)) {
            // The three lines go where the first of them was.
            out.append(&mut lines);
        } else {
            out.extend_from_slice(line);
        }
    }
    Ok(out)
}

fn compress(path: &str, data: &[u8]) -> Result<Vec<u8>, ProjectError> {
    ovba::compress(data).map_err(|e| error(path, e))
}

fn encode(text: &str, encoding: &'static encoding_rs::Encoding) -> Option<Vec<u8>> {
    let (bytes, _, unmappable) = encoding.encode(text);
    (!unmappable).then(|| bytes.into_owned())
}

/// A module's name as VBA takes one: a letter, then letters, digits or `_`, at most 31. A
/// letter of any script, as the VBA editor allows in the project's code page: Excel in
/// Portuguese and Spanish names its first module `Módulo1` ([MS-VBAL] 3.3.5: besides the
/// Latin-identifier, a codepage-identifier of the code page's letters). The code page is
/// checked when the module's text, which names it, is written.
pub fn is_module_name(name: &str) -> bool {
    name.chars().next().is_some_and(char::is_alphabetic)
        && name.chars().all(|c| c.is_alphanumeric() || c == '_')
        && name.chars().count() <= 31
}

/// The module of that name (VBA names ignore case).
fn existing<'m>(modules: &'m [DirModule], name: &str) -> Option<&'m DirModule> {
    modules.iter().find(|m| m.name.eq_ignore_ascii_case(name))
}

/// Refuses a name that is no VBA identifier, one given twice, one the project has (unless
/// replacing a standard module by one), and one that names another stream of the VBA
/// storage (`dir`).
fn check_name(parts: &Parts, new: &NewModule, added: &[Added], on_existing: OnExisting) -> Result<(), ProjectError> {
    let name = &new.name;
    if !is_module_name(name) {
        return Err(error(name, "is not a VBA module name (a letter, then letters, digits or _, at most 31)"));
    }
    if added.iter().any(|a| a.module.name.eq_ignore_ascii_case(name)) {
        return Err(error(name, "is imported twice"));
    }
    match (existing(&parts.listing.modules, name), on_existing) {
        (Some(old), OnExisting::Refuse) => {
            Err(error(name, format!("the project already has a module {} (--replace replaces it)", old.name)))
        }
        (Some(old), OnExisting::Replace) if old.kind != ModuleKind::Standard || new.kind != ModuleKind::Standard => {
            Err(error(name, format!("{} is a document or class module; only a standard module is replaced", old.name)))
        }
        (Some(_), OnExisting::Replace) => Ok(()),
        (None, _) => {
            let taken = parts
                .cfb
                .read_storage(&parts.storage)
                .is_ok_and(|mut e| e.any(|e| e.name().eq_ignore_ascii_case(name)));
            if taken {
                return Err(error(name, format!("is the name of a stream the project keeps in {}", parts.storage)));
            }
            Ok(())
        }
    }
}

/// The path of a stream beside the VBA storage (`/PROJECTwm`).
fn sibling(parts: &Parts, name: &str) -> String {
    let parent = parts.storage.rsplit_once('/').map_or("", |(p, _)| p);
    format!("{parent}/{name}")
}

/// The dir stream again, record for record, with the new modules' records before its
/// terminator, PROJECTMODULES counting them, every module's source at offset 0, and the
/// cookies at 0xFFFF as a writer sets them (2.3.4.2.3).
fn rebuild_dir(dir: &[u8], modules: usize, added: &[Added]) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(dir.len() + 256 * added.len());
    let mut at = 0;
    while at < dir.len() {
        let header = dir.get(at..at + 6).ok_or_else(|| format!("record at byte {at} cut short"))?;
        let record = u16::from_le_bytes([header[0], header[1]]);
        let size_field = u32::from_le_bytes([header[2], header[3], header[4], header[5]]) as usize;
        // PROJECTVERSION's size field says 4, but 6 bytes follow.
        let size = if record == id::PROJECT_VERSION { 6 } else { size_field };
        let whole = dir.get(at..at + 6 + size).ok_or_else(|| format!("record {record:#06x} at byte {at} cut short"))?;
        at += 6 + size;
        match record {
            id::PROJECT_MODULES => {
                let count = u16::try_from(modules + added.len()).map_err(|_| "too many modules".to_string())?;
                push_record(&mut out, record, &count.to_le_bytes());
            }
            id::PROJECT_COOKIE | id::MODULE_COOKIE => push_record(&mut out, record, &0xFFFFu16.to_le_bytes()),
            id::MODULE_OFFSET => push_record(&mut out, record, &0u32.to_le_bytes()),
            id::DIR_TERMINATOR => {
                for a in added {
                    push_module_records(&mut out, &a.module.name, &a.mbcs, a.module.kind);
                }
                out.extend_from_slice(whole);
                return Ok(out);
            }
            _ => out.extend_from_slice(whole),
        }
    }
    Err("the dir stream ends without its terminator record".into())
}

/// The PROJECT stream with a `Module=` (`Class=`) line for each new module after the module lines
/// (2.3.1: they follow the ID line), every other byte as it was.
fn with_module_lines(text: &[u8], added: &[Added]) -> Vec<u8> {
    let lines: Vec<&[u8]> = text.split_inclusive(|&b| b == b'\n').collect();
    let items = [&b"ID="[..], b"Module=", b"Document=", b"Class=", b"BaseClass=", b"Package="];
    let after = lines.iter().take_while(|l| items.iter().any(|k| l.starts_with(k))).count();
    let mut out = Vec::with_capacity(text.len() + 32 * added.len());
    lines[..after].iter().for_each(|l| out.extend_from_slice(l));
    for a in added {
        let key: &[u8] = if a.module.kind == ModuleKind::Class { b"Class=" } else { b"Module=" };
        out.extend_from_slice(key);
        out.extend_from_slice(&a.mbcs);
        out.extend_from_slice(b"\r\n");
    }
    lines[after..].iter().for_each(|l| out.extend_from_slice(l));
    out
}

/// PROJECTwm (2.3.3) with the new modules' names (MBCS and UTF-16) before its terminator.
fn with_names(wm: &[u8], added: &[Added]) -> Result<Vec<u8>, String> {
    let Some(body) = wm.strip_suffix(&[0, 0]) else {
        return Err("does not end with its terminator".into());
    };
    let mut out = body.to_vec();
    for a in added {
        out.extend_from_slice(&a.mbcs);
        out.push(0);
        out.extend(a.module.name.encode_utf16().flat_map(u16::to_le_bytes));
        out.extend([0, 0]);
    }
    out.extend([0, 0]);
    Ok(out)
}

/// Writes the new compound file: the old one's tree (storages with their class ids and
/// state bits), its streams copied or `replaced`, the `__SRP_*` caches left out, and the
/// `created` streams added.
fn write_project(
    parts: &mut Parts,
    replaced: &BTreeMap<String, Vec<u8>>,
    created: &[(String, Vec<u8>)],
) -> Result<Vec<u8>, ProjectError> {
    let mut copy = cfb::CompoundFile::create_with_version(parts.cfb.version(), Cursor::new(Vec::new()))
        .map_err(|e| error("vbaProject.bin", e))?;
    let entries: Vec<cfb::Entry> = parts.cfb.walk().collect();
    let storage = parts.storage.to_ascii_lowercase();
    let mut kept = Vec::with_capacity(entries.len());
    for entry in entries {
        let path = entry.path().to_string_lossy().replace('\\', "/");
        let lower = path.to_ascii_lowercase();
        if entry.is_root() {
        } else if entry.is_storage() {
            copy.create_storage(entry.path()).map_err(|e| error(&path, e))?;
        } else if lower.starts_with(&format!("{storage}/__srp_")) {
            continue;
        } else {
            let data = match replaced.get(&lower) {
                Some(data) => data.clone(),
                None => read_stream(&mut parts.cfb, &path)?,
            };
            put(&mut copy, &path, &data)?;
        }
        kept.push(entry);
    }
    for (path, data) in created {
        put(&mut copy, path, data)?;
    }
    // The metadata once the tree is complete, as cfb's own copy does.
    for entry in &kept {
        let path = entry.path().to_string_lossy().replace('\\', "/");
        let fail = |e| error(&path, e);
        copy.set_state_bits(entry.path(), entry.state_bits()).map_err(fail)?;
        if !entry.is_stream() {
            copy.set_storage_clsid(entry.path(), *entry.clsid()).map_err(fail)?;
        }
    }
    copy.flush().map_err(|e| error("vbaProject.bin", e))?;
    Ok(copy.into_inner().into_inner())
}

fn put(copy: &mut cfb::CompoundFile<Cursor<Vec<u8>>>, path: &str, data: &[u8]) -> Result<(), ProjectError> {
    let mut stream = copy.create_stream(path).map_err(|e| error(path, e))?;
    stream.write_all(data).map_err(|e| error(path, e))
}

#[cfg(test)]
mod tests {
    use super::super::project::{build_project, read_project};
    use super::*;

    fn module(name: &str, kind: ModuleKind, source: &str) -> NewModule {
        NewModule { name: name.into(), kind, source: source.into() }
    }

    fn base() -> Vec<u8> {
        let modules = [
            module("ThisWorkbook", ModuleKind::DocumentOrClass, ""),
            module("Module1", ModuleKind::Standard, "Sub A()\nEnd Sub\n"),
        ];
        build_project(&modules, 7).unwrap()
    }

    #[test]
    fn an_added_module_follows_the_kept_ones() {
        let new = [module("Chamfer", ModuleKind::Standard, "Sub Main()\r\nEnd Sub\r\n")];
        let project =
            read_project(&add_modules(&base(), &new, OnExisting::Refuse, OnProtected::Refuse).unwrap()).unwrap();
        let names: Vec<_> = project.modules.iter().map(|m| (m.name.as_str(), m.kind)).collect();
        assert_eq!(
            names,
            [
                ("ThisWorkbook", ModuleKind::DocumentOrClass),
                ("Module1", ModuleKind::Standard),
                ("Chamfer", ModuleKind::Standard)
            ]
        );
        assert_eq!(project.modules[1].source, "Attribute VB_Name = \"Module1\"\r\nSub A()\r\nEnd Sub\r\n");
        assert_eq!(project.modules[2].source, "Attribute VB_Name = \"Chamfer\"\r\nSub Main()\r\nEnd Sub\r\n");
    }

    #[test]
    fn a_module_name_the_project_has_is_refused_or_replaced() {
        let new = [module("module1", ModuleKind::Standard, "Sub B()\nEnd Sub\n")];
        let e = add_modules(&base(), &new, OnExisting::Refuse, OnProtected::Refuse).unwrap_err();
        assert!(e.message.contains("already has a module Module1"), "{e}");
        let project =
            read_project(&add_modules(&base(), &new, OnExisting::Replace, OnProtected::Refuse).unwrap()).unwrap();
        assert_eq!(project.modules.len(), 2);
        assert!(project.modules[1].source.ends_with("Sub B()\r\nEnd Sub\r\n"));
        let doc = [module("ThisWorkbook", ModuleKind::Standard, "")];
        assert!(add_modules(&base(), &doc, OnExisting::Replace, OnProtected::Refuse)
            .unwrap_err()
            .message
            .contains("document"));
        let dir = [module("dir", ModuleKind::Standard, "")];
        assert!(add_modules(&base(), &dir, OnExisting::Refuse, OnProtected::Refuse)
            .unwrap_err()
            .message
            .contains("stream"));
        let twice = [module("X", ModuleKind::Standard, ""), module("x", ModuleKind::Standard, "")];
        assert!(add_modules(&base(), &twice, OnExisting::Refuse, OnProtected::Refuse)
            .unwrap_err()
            .message
            .contains("twice"));
    }

    /// [MS-OVBA] 3.1.6's PROJECT stream: the new module's line goes after the module and
    /// package lines (2.3.1's grammar: ProjectId *ProjectItem, then the properties).
    #[test]
    fn the_module_line_follows_the_project_items() {
        let text = "ID=\"{917DED54-440B-4FD1-A5C1-74ACF261E600}\"\r\nDocument=ThisWorkbook/&H00000000\r\n\
                    Document=Sheet1/&H00000000\r\nPackage={AC9F2F90-E877-11CE-9F68-00AA00574A4F}\r\n\
                    BaseClass=UserForm1\r\nHelpFile=\"c:\\example path\\example.hlp\"\r\nName=\"VBAProject\"\r\n";
        let new = module("Chamfer", ModuleKind::Standard, "");
        let added = [Added { module: &new, mbcs: b"Chamfer".to_vec() }];
        let out = String::from_utf8(with_module_lines(text.as_bytes(), &added)).unwrap();
        let lines: Vec<&str> = out.split("\r\n").collect();
        assert_eq!(
            lines[4..7],
            ["BaseClass=UserForm1", "Module=Chamfer", "HelpFile=\"c:\\example path\\example.hlp\""]
        );
        assert_eq!(out.len(), text.len() + "Module=Chamfer\r\n".len());
    }
}
