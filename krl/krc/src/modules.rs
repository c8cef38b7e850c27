//! The KRL the runtime executes: the shipped program (embedded at build
//! time from `krl/KRC/`, or a site's copy from a folder), merged into one
//! module set, and the controller's `$config.dat` globals it relies on.

use std::path::Path;

use kuka_krl::check::decode;
use kuka_krl::{DatFile, Program, SrcFile, parse_dat, parse_src};

/// The files of the shipped program: name and text.
pub const KRL_FILES: [(&str, &str); 6] = [
    (
        "kb_main.src",
        include_str!("../../KRC/R1/Program/kbridge/kb_main.src"),
    ),
    (
        "kb_main.dat",
        include_str!("../../KRC/R1/Program/kbridge/kb_main.dat"),
    ),
    (
        "kb_submit.src",
        include_str!("../../KRC/R1/Program/kbridge/kb_submit.src"),
    ),
    (
        "kb_io.src",
        include_str!("../../KRC/R1/Program/kbridge/kb_io.src"),
    ),
    (
        "kb_io.dat",
        include_str!("../../KRC/R1/Program/kbridge/kb_io.dat"),
    ),
    (
        "kb_sps_lines.src",
        include_str!("../../KRC/R1/System/kb_sps_lines.src"),
    ),
];

/// The user-level globals of a KSS 8.x `$config.dat` the program uses,
/// with the values of real `$config.dat` files (docs/CONTROLLER.md, 14).
/// The tool and base tables every KRC has (`TOOL_DATA[16]`,
/// `BASE_DATA[32]`, all zero as on a fresh controller, and their names
/// `TOOL_NAME[16,24]`, `BASE_NAME[32,24]`, empty) are declared too, so
/// that an uploaded program using them runs and KUKAVARPROXY reads them.
pub fn simulated_config_dat() -> String {
    let mut dat = String::from(
        "DEFDAT $CONFIG PUBLIC
DECL GLOBAL REAL DEF_ACC_CP=2.3
DECL GLOBAL REAL DEF_ACC_ORI1=100.0
DECL GLOBAL REAL DEF_ACC_ORI2=100.0
DECL GLOBAL FRAME TOOL_DATA[16]
DECL GLOBAL FRAME BASE_DATA[32]
DECL GLOBAL CHAR TOOL_NAME[16,24]
DECL GLOBAL CHAR BASE_NAME[32,24]
",
    );
    for (name, n) in [("TOOL_DATA", 16), ("BASE_DATA", 32)] {
        for i in 1..=n {
            dat.push_str(&format!(
                "{name}[{i}]={{X 0.0,Y 0.0,Z 0.0,A 0.0,B 0.0,C 0.0}}\n"
            ));
        }
    }
    dat.push_str("ENDDAT\n");
    dat
}

/// Why the program cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ModuleError {
    /// A file is missing or unreadable.
    #[error("{file}: {source}")]
    Read {
        /// The file.
        file: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// A file does not parse.
    #[error("{file}: {error}")]
    Syntax {
        /// The file.
        file: String,
        /// The error.
        error: kuka_krl::SyntaxError,
    },
}

fn syntax(file: &str) -> impl Fn(kuka_krl::SyntaxError) -> ModuleError + '_ {
    move |error| ModuleError::Syntax {
        file: file.to_string(),
        error,
    }
}

/// The shipped program (or the copy in `dir`) as one module set: the
/// routines of every `.src`, the items of every `.dat` and of the
/// simulated `$config.dat`.
pub fn shipped_program(dir: Option<&Path>) -> Result<Program, ModuleError> {
    let mut routines = Vec::new();
    let mut items = parse_dat(&simulated_config_dat())
        .map_err(syntax("$config.dat"))?
        .items;
    for (name, text) in KRL_FILES {
        let owned;
        let text = match dir {
            Some(d) => {
                let bytes = std::fs::read(d.join(name)).map_err(|source| ModuleError::Read {
                    file: name.to_string(),
                    source,
                })?;
                owned = decode(&bytes).into_owned();
                owned.as_str()
            }
            None => text,
        };
        if name.ends_with(".dat") {
            items.extend(parse_dat(text).map_err(syntax(name))?.items);
        } else {
            routines.extend(parse_src(text).map_err(syntax(name))?.routines);
        }
    }
    Ok(Program {
        src: SrcFile { routines },
        dat: Some(DatFile {
            name: "KB_MAIN".into(),
            public: true,
            items,
            line: 1,
        }),
    })
}

/// An uploaded module `name` (`kbu<n>`) from `dir`: its `.src` and `.dat`.
pub(crate) fn uploaded_program(dir: &Path, name: &str) -> Result<Program, String> {
    let read = |ext: &str| -> Option<String> {
        let entries = std::fs::read_dir(dir).ok()?;
        let path = entries.flatten().map(|e| e.path()).find(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.eq_ignore_ascii_case(&format!("{name}.{ext}")))
        })?;
        std::fs::read(path).ok().map(|b| decode(&b).into_owned())
    };
    let src = read("src").ok_or_else(|| format!("module {name} not found"))?;
    let dat = read("dat");
    Program::parse(&src, dat.as_deref(), None).map_err(|e| format!("module {name}: {e}"))
}
