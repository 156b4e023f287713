//! Relationship targets as the Open Packaging Conventions read them (ECMA-376 Part 2): a
//! target is a URI reference resolved against the folder of its source part as RFC 3986
//! §5.2 resolves one (`.` and `..` segments removed, a leading `/` from the package's root),
//! with its percent-encoded octets decoded (§2.1: `sheet%31.xml` is `sheet1.xml`), into the
//! name of a part of the package. A target that cannot name a part of this package (another
//! scheme, a network path, `..` above the root) is refused, naming the relationship.

/// The part a relationship's (unescaped) `target` names, from a source part in folder `dir`
/// (`xl` for `xl/workbook.xml`, empty for the package's own relationships); the error says
/// why the target names none.
pub fn resolve_target(dir: &str, target: &str) -> Result<String, String> {
    if has_scheme(target) || target.starts_with("//") {
        return Err("names a resource outside the package (an internal relationship names a part)".into());
    }
    // A part name has no query or fragment (ECMA-376 Part 2, §9.1.1.1).
    let path = target.split(['?', '#']).next().unwrap_or_default();
    let mut segments: Vec<String> = match path.starts_with('/') {
        true => Vec::new(),
        false => dir.split('/').filter(|s| !s.is_empty()).map(str::to_string).collect(),
    };
    for segment in path.split('/') {
        match segment {
            "" | "." => {}
            ".." if segments.pop().is_none() => return Err("climbs above the package's root with '..'".into()),
            ".." => {}
            s => segments.push(percent_decoded(s)?),
        }
    }
    if segments.is_empty() {
        return Err("names no part".into());
    }
    Ok(segments.join("/"))
}

/// A scheme as RFC 3986 §3.1 spells one (`file:`, `http:`), before any `/`.
fn has_scheme(target: &str) -> bool {
    let Some(colon) = target.find(':') else { return false };
    let scheme = &target[..colon];
    scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// One segment with its `%HH` octets decoded as UTF-8. A part name's segment holds no
/// encoded `/` or `\` (ECMA-376 Part 2, §9.1.1.1): decoded, either would make another path.
fn percent_decoded(segment: &str) -> Result<String, String> {
    if !segment.contains('%') {
        return Ok(segment.to_string());
    }
    let bytes = segment.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'%' {
            out.push(bytes[i]);
            i += 1;
            continue;
        }
        let octet = bytes.get(i + 1..i + 3).and_then(|h| u8::from_str_radix(std::str::from_utf8(h).ok()?, 16).ok());
        match octet {
            Some(b'/' | b'\\') => return Err(format!("'{segment}' encodes a '/' or '\\' inside a part name")),
            Some(octet) => out.push(octet),
            None => return Err(format!("'{segment}' holds a '%' that begins no %HH octet")),
        }
        i += 3;
    }
    String::from_utf8(out).map_err(|_| format!("'{segment}' decodes to bytes that are not UTF-8"))
}

/// A relationships part listing `relationships` (id, type, part) with every target written
/// as an absolute part name: how calamine, which joins a target to the workbook's folder as
/// written, is given a package whose targets are spelled otherwise (`../xl/./sheet1.xml`).
pub fn absolute_relationships(relationships: &[(String, String, String)]) -> String {
    let mut xml = String::from(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">"#,
    );
    for (id, kind, part) in relationships {
        let (id, kind, part) = (escaped(id), escaped(kind), escaped(part));
        xml.push_str(&format!(r#"<Relationship Id="{id}" Type="{kind}" Target="/{part}"/>"#));
    }
    xml.push_str("</Relationships>");
    xml
}

fn escaped(value: &str) -> String {
    value.replace('&', "&amp;").replace('<', "&lt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 3986 §5.2.4's dot-segment removal and §5.2.2's merge, over part names.
    #[test]
    fn targets_resolve_as_uri_references_do() {
        for target in [
            "worksheets/sheet1.xml",
            "./worksheets/sheet1.xml",
            "../xl/worksheets/./sheet1.xml",
            "/xl/worksheets/sheet1.xml",
            "worksheets/../worksheets/sheet1.xml",
            "worksheets/sheet%31.xml",
            "%77orksheets/sheet1.xml#frag",
        ] {
            assert_eq!(resolve_target("xl", target).as_deref(), Ok("xl/worksheets/sheet1.xml"), "{target}");
        }
        assert_eq!(resolve_target("", "xl/workbook.xml").as_deref(), Ok("xl/workbook.xml"));
        assert_eq!(resolve_target("xl/worksheets", "../drawings/d.xml").as_deref(), Ok("xl/drawings/d.xml"));
        assert_eq!(resolve_target("xl", "my%20sheet%C3%A9.xml").as_deref(), Ok("xl/my sheeté.xml"));
    }

    #[test]
    fn targets_outside_the_package_are_refused() {
        for target in ["../../etc/passwd", "file:///etc/passwd", "http://host/x.xml", "//host/share/x.xml", "a%2Fb.xml"]
        {
            assert!(resolve_target("xl", target).is_err(), "{target}");
        }
        assert!(resolve_target("xl", "sheet%zz.xml").unwrap_err().contains("%HH"));
        assert!(resolve_target("xl", "sheet%FF.xml").unwrap_err().contains("UTF-8"));
    }
}
