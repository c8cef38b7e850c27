//! The parser against real KRL written by other people: every file of the
//! public corpus in `tests/corpus/` (sources and licences in its
//! SOURCES.md and manifest.tsv) is decoded and parsed as the controller
//! would load it. Files a KRC refuses are listed below with the reason;
//! every other file must parse, and no file may crash the parser.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use kuka_krl::check::{FileKind, check, decode};

/// Files of the corpus that are not valid KRL, with why and the message
/// the parser must give (a part of it). A file listed here that starts to
/// parse fails the test too: the list stays true.
const NOT_KRL: &[(&str, &str, &str)] = &[
    (
        "licensed/itk-thrivaldi__kuka_kvp_hw_interface/krl/kukavarproxyvelperc.src",
        "STRUC declarations in the USER INI fold, after BAS(#INITMOV): a declaration after a statement",
        "a declaration after the first statement",
    ),
    (
        "unlicensed/Bugaj32__KUKA-pick-and-place-palletizing/main.src",
        "DECLs in the USER INI fold, after BAS(#INITMOV): a declaration after a statement",
        "a declaration after the first statement",
    ),
    (
        "unlicensed/Aleksey-Kostov__kuka-krl-examples/grab_drop.dat",
        "a data list holding statements (`TOOL …`, motions): .src text saved as .dat",
        "is not a statement",
    ),
    (
        "unlicensed/HugoDanielson__ChinaMilling/KRC/R1/Program/KukaMiling/Stations/Station1.src",
        "a stray ENDFCT after the module's last routine",
        "found `ENDFCT`",
    ),
    (
        "unlicensed/danielmuellernavarro__KRL_utils/string_from_bus/STRING_FROM_BUS.dat",
        "`GLOBAL` in a data list that is not `PUBLIC`",
        "which is not PUBLIC",
    ),
    (
        "unlicensed/danielmuellernavarro__KRL_utils/trig/trig.src",
        "`F_TRIG` defined twice (the second was meant to be X_TRIG)",
        "routine `F_TRIG` is defined twice",
    ),
    (
        "unlicensed/LEMUR-DIMEC__KUKA_EXTRUDER/Archivos_KRL/Pruebas_KRL/flujo.dat",
        "not a data list: generated text with a call where DEFDAT belongs",
        "found `(`",
    ),
    (
        "unlicensed/Shangmc__KUKA/test.src",
        "`a=0,b=0`: two assignments joined by a comma",
        "found `,`",
    ),
    (
        "unlicensed/danielmuellernavarro__KRL_utils/in_range/in_range_frame.src",
        "unbalanced parentheses in an IF condition",
        "found `THEN`",
    ),
    (
        "unlicensed/danielmuellernavarro__KRL_utils/sps.sub/cycle_time/sps_cycle_time.src",
        "a DEFFCT closed by END instead of ENDFCT",
        "expected ENDFCT",
    ),
    (
        "unlicensed/danielmuellernavarro__KRL_utils/string_from_bus/STRING_FROM_BUS.src",
        "a DEFFCT closed by END instead of ENDFCT",
        "expected ENDFCT",
    ),
    (
        "unlicensed/khrzysio__KRC4_test/R1/Program/CELL/Leaf/Cut_LeafLong.src",
        "unfinished code: a bare `TODO` line",
        "`TODO` is not a statement",
    ),
    (
        "unlicensed/khrzysio__KRC4_test/R1/Program/CELL/Leaf/Cut_LeafShort.src",
        "unfinished code: a bare `TODO` line",
        "`TODO` is not a statement",
    ),
    (
        "unlicensed/khrzysio__KRC4_test/R1/Program/CELL/Leaf/Mill_LeafBottom.src",
        "unfinished code: a bare `TODO` line",
        "`TODO` is not a statement",
    ),
    (
        "unlicensed/khrzysio__KRC4_test/R1/Program/CELL/Leaf/Mill_LeafGlue.src",
        "unfinished code: a bare `TODO` line",
        "`TODO` is not a statement",
    ),
    (
        "unlicensed/rawpython__kukaKRLmagic/R1/Program/sample_program_with_globals.src",
        "generator output whose routine name has 27 characters (KRL: at most 24)",
        "KRL allows at most 24",
    ),
];

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus")
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).expect("corpus folder readable");
    for e in entries {
        let path = e.expect("entry").path();
        if path.is_dir() {
            files(&path, out);
        } else if FileKind::from_path(&path).is_some() {
            out.push(path);
        }
    }
}

#[test]
fn every_valid_file_of_the_public_corpus_parses() {
    let root = corpus();
    let mut all = Vec::new();
    files(&root, &mut all);
    all.sort();
    assert!(all.len() >= 300, "the corpus holds {} KRL files", all.len());
    let expected: BTreeMap<&str, (&str, &str)> = NOT_KRL
        .iter()
        .map(|(p, why, msg)| (*p, (*why, *msg)))
        .collect();

    let mut problems = Vec::new();
    let mut parsed = 0usize;
    for path in &all {
        let rel = path
            .strip_prefix(&root)
            .expect("inside the corpus")
            .to_string_lossy()
            .replace('\\', "/");
        let bytes = std::fs::read(path).expect("file readable");
        let kind = FileKind::from_path(path).expect("a KRL file");
        let text = decode(&bytes).into_owned();
        let outcome = std::panic::catch_unwind(|| check(kind, &text).map_err(|e| e.to_string()));
        let Ok(outcome) = outcome else {
            problems.push(format!("{rel}: the parser panicked"));
            continue;
        };
        match (outcome, expected.get(rel.as_str())) {
            (Ok(()), None) => parsed += 1,
            (Err(e), None) => problems.push(format!("{rel}: refused: {e}")),
            (Ok(()), Some((why, _))) => problems.push(format!(
                "{rel}: listed as not KRL ({why}) but parses: remove it from NOT_KRL"
            )),
            (Err(e), Some((why, msg))) if !e.contains(msg) => problems.push(format!(
                "{rel}: listed as not KRL ({why}), expected a message with {msg:?}, got: {e}"
            )),
            (Err(_), Some(_)) => {}
        }
    }
    let listed_present = NOT_KRL
        .iter()
        .filter(|(p, ..)| root.join(p).is_file())
        .count();
    assert_eq!(
        listed_present,
        NOT_KRL.len(),
        "every listed file is in the corpus"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    let valid = all.len() - NOT_KRL.len();
    eprintln!(
        "corpus: {} files, {parsed} of {valid} valid files parse ({:.1} %), {} refused as listed",
        all.len(),
        100.0 * parsed as f64 / valid as f64,
        NOT_KRL.len()
    );
    assert_eq!(parsed, valid);
}
