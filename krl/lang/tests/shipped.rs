//! Every KRL file shipped for the controller (`krl/KRC/`) parses with the
//! front end, and the program has the routines the installation guide
//! names: the KRL that integrators copy is checked in CI.

use std::path::{Path, PathBuf};

fn krl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read krl/KRC").flatten() {
        let p = entry.path();
        if p.is_dir() {
            krl_files(&p, out);
        } else if p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| ["src", "dat", "sub"].contains(&e.to_ascii_lowercase().as_str()))
        {
            out.push(p);
        }
    }
}

#[test]
fn every_shipped_krl_file_parses() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../KRC");
    let mut files = Vec::new();
    krl_files(&root, &mut files);
    files.sort();
    assert!(
        files.len() >= 4,
        "expected the KRL program in krl/KRC, found {files:?}"
    );
    let mut failures = Vec::new();
    let mut routines = Vec::new();
    for f in &files {
        let text = std::fs::read(f).expect("read");
        let text = String::from_utf8_lossy(&text);
        let is_dat = f.extension().is_some_and(|e| e.eq_ignore_ascii_case("dat"));
        let result = if is_dat {
            kuka_krl::parse_dat(&text).map(|_| ())
        } else {
            kuka_krl::parse_src(&text).map(|s| {
                routines.extend(s.routines.iter().map(|r| r.name.to_ascii_lowercase()));
            })
        };
        if let Err(e) = result {
            failures.push(format!("{}: {e}", f.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "KRL files that do not parse:\n{}",
        failures.join("\n")
    );
    for needed in [
        "kb_main",
        "kb_submit_init",
        "kb_submit_cycle",
        "kbline",
        "kbmix",
    ] {
        assert!(
            routines.iter().any(|r| r == needed),
            "routine {needed} missing: {routines:?}"
        );
    }
}
