//! olevba (PyPI oletools, installed by `.ci/run`): the independent reader of VBA projects.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// olevba's reading of `file`: module stream path (`VBA/Module1`) → source. `None` where
/// oletools is not installed (an error on CI, where `.ci/run` installs it).
pub fn olevba(file: &Path) -> Option<BTreeMap<String, String>> {
    let script = r#"
import json, sys
from oletools.olevba import VBA_Parser
p = VBA_Parser(sys.argv[1])
out = {}
if p.detect_vba_macros():
    for (_, stream, _, code) in p.extract_macros():
        out[stream] = code
print(json.dumps(out))
"#;
    let run = Command::new("python3").arg("-c").arg(script).arg(file).output();
    let ok = run.as_ref().is_ok_and(|o| o.status.success());
    if !ok {
        let why = run.map(|o| String::from_utf8_lossy(&o.stderr).into_owned()).unwrap_or_else(|e| e.to_string());
        assert!(std::env::var_os("CI").is_none(), "olevba (pip oletools) is missing on CI: {why}");
        eprintln!("skipped: olevba (pip install oletools) does not run here: {why}");
        return None;
    }
    let text = String::from_utf8(run.unwrap().stdout).unwrap();
    let map: serde_json::Value = serde_json::from_str(&text).unwrap();
    Some(map.as_object().unwrap().iter().map(|(k, v)| (k.clone(), v.as_str().unwrap().to_string())).collect())
}
