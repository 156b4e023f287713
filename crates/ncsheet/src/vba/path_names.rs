//! The FileSystemObject's methods that work on a path's text alone ("GetFileName method",
//! "GetBaseName method", "GetExtensionName method", "GetParentFolderName method",
//! "BuildPath method", "GetDriveName method"): each "works only on the provided path string;
//! it does not attempt to resolve the path, nor does it check for the existence of the
//! specified path". Both `\` and `/` separate components; a drive is `X:`. They touch no
//! file, so a macro computing its program's name with them needs no sandbox.

fn is_separator(c: char) -> bool {
    c == '\\' || c == '/'
}

/// The path without the separators at its end.
fn trimmed(path: &str) -> &str {
    path.trim_end_matches(is_separator)
}

/// The path's last component, "" for a drive alone (`C:`) or separators alone.
pub(super) fn file_name(path: &str) -> &str {
    let path = trimmed(path);
    let last = path.rfind(is_separator).map_or(path, |at| &path[at + 1..]);
    if is_drive(last) && last.len() == path.len() {
        return "";
    }
    last
}

/// The last component without its extension (the text from its last `.`): `a.b.c` is `a.b`,
/// `.a` is "".
pub(super) fn base_name(path: &str) -> &str {
    let name = file_name(path);
    name.rfind('.').map_or(name, |at| &name[..at])
}

/// The last component's extension, without its `.`; "" when it has none.
pub(super) fn extension_name(path: &str) -> &str {
    let name = file_name(path);
    name.rfind('.').map_or("", |at| &name[at + 1..])
}

/// The path without its last component and the separators before it; a drive's root keeps
/// its separator (`c:\\a` gives `c:\`); "" when there is no folder part.
pub(super) fn parent_folder_name(path: &str) -> &str {
    let path = trimmed(path);
    let Some(at) = path.rfind(is_separator) else { return "" };
    let parent = path[..at].trim_end_matches(is_separator);
    if parent.is_empty() {
        return "";
    }
    if parent.len() == 2 && is_drive(parent) {
        return &path[..3];
    }
    parent
}

/// `folder` and `name` joined by one backslash: none added when one of them has it (or the
/// folder is a drive, `C:`), one taken away when both have it.
pub(super) fn build_path(folder: &str, name: &str) -> String {
    if folder.is_empty() || name.is_empty() {
        return format!("{folder}{name}");
    }
    match (folder.ends_with('\\'), name.starts_with('\\')) {
        (true, true) => format!("{folder}{}", &name[1..]),
        (false, false) if !folder.ends_with(':') => format!("{folder}\\{name}"),
        _ => format!("{folder}{name}"),
    }
}

/// The drive a path starts with (`C:`), "" when it names none.
pub(super) fn drive_name(path: &str) -> &str {
    match path.get(..2) {
        Some(d) if d.ends_with(':') => d,
        _ => "",
    }
}

fn is_drive(text: &str) -> bool {
    text.len() == 2 && text.ends_with(':')
}

#[cfg(test)]
mod tests {
    use super::*;

    // Wine's scrrun tests (dlls/scrrun/tests/filesystem.c), which run against Windows'
    // own scrrun.dll as well: a NULL result is the empty string a macro sees.
    #[test]
    fn names_of_a_path_as_windows_gives_them() {
        for (path, want) in [("a", "a"), ("a/a.b", "a.b"), ("a\\", "a"), ("c:", ""), ("/\\", "")] {
            assert_eq!(file_name(path), want, "GetFileName({path:?})");
        }
        for (path, want) in [("a", "a"), ("a/a.b.c", "a.b"), ("a.b\\", "a"), ("c:", ""), ("/\\", ""), (".a", "")] {
            assert_eq!(base_name(path), want, "GetBaseName({path:?})");
        }
        let parents = [
            ("a", ""),
            ("a/a/a", "a/a"),
            ("a\\a\\a", "a\\a"),
            ("a/a//\\\\", "a"),
            ("c:\\\\a", "c:\\"),
            ("ac:\\a", "ac:"),
        ];
        for (path, want) in parents {
            assert_eq!(parent_folder_name(path), want, "GetParentFolderName({path:?})");
        }
    }

    #[test]
    fn build_path_joins_with_one_separator_as_windows_does() {
        let cases = [
            ("C:\\path", "..\\name.tmp", "C:\\path\\..\\name.tmp"),
            ("C:\\path", "\\name.tmp", "C:\\path\\name.tmp"),
            ("C:\\path", "name.tmp", "C:\\path\\name.tmp"),
            ("C:\\path\\", "name.tmp", "C:\\path\\name.tmp"),
            ("C:\\path", "\\\\name.tmp", "C:\\path\\\\name.tmp"),
            ("C:\\path\\", "\\name.tmp", "C:\\path\\name.tmp"),
            ("C:\\path\\", "\\\\name.tmp", "C:\\path\\\\name.tmp"),
            ("C:\\path\\\\", "\\\\name.tmp", "C:\\path\\\\\\name.tmp"),
            ("C:\\\\", "\\name.tmp", "C:\\\\name.tmp"),
            ("C:", "name.tmp", "C:name.tmp"),
            ("C:", "\\\\name.tmp", "C:\\\\name.tmp"),
        ];
        for (folder, name, want) in cases {
            assert_eq!(build_path(folder, name), want, "BuildPath({folder:?}, {name:?})");
        }
    }

    // "GetExtensionName method": the extension of the last component ("" when it has none);
    // "GetDriveName method": "an empty string if the drive can't be determined".
    #[test]
    fn extension_and_drive_of_a_path() {
        assert_eq!(extension_name("C:\\cnc\\part.tar.nc"), "nc");
        assert_eq!(extension_name("C:\\cnc.d\\part"), "");
        assert_eq!(extension_name("part."), "");
        assert_eq!(drive_name("C:\\cnc\\part.nc"), "C:");
        assert_eq!(drive_name("part.nc"), "");
    }
}
