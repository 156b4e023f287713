//! LibreOffice set to a locale, the oracle of the locale tests (issue 28).

use std::path::Path;

/// A LibreOffice profile in `dir` set to `locale` (its formats, names and csv reading) that
/// recalculates every file it loads: the `-env:UserInstallation` argument that uses it.
pub fn libreoffice_profile(dir: &Path, locale: &str) -> String {
    let user = dir.join("user");
    std::fs::create_dir_all(&user).unwrap();
    let settings = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="ODFRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Setup/L10N"><prop oor:name="ooSetupSystemLocale" oor:op="fuse"><value>{locale}</value></prop></item>
<item oor:path="/org.openoffice.Setup/L10N"><prop oor:name="ooLocale" oor:op="fuse"><value>{locale}</value></prop></item>
</oor:items>
"#
    );
    std::fs::write(user.join("registrymodifications.xcu"), settings).unwrap();
    format!("-env:UserInstallation=file://{}", dir.display())
}
