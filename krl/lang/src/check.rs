//! Checking KRL files as a controller loads them: the text decoded the way
//! KSS writes it (ANSI, i.e. Windows-1252, or UTF-8 with or without a byte
//! order mark), and parsed by its kind (`.src`/`.sub` modules, `.dat` data
//! lists). What `kuka-bridge krl check` and the corpus tests run.

use std::borrow::Cow;
use std::path::Path;

use std::collections::HashMap;

use crate::ast::{DatFile, Declarator, RoutineKind, SrcFile, Stmt, StmtKind};
use crate::{SyntaxError, parse_dat, parse_src};

/// What a KRL file holds, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// `.src` or `.sub`: routines (a Submit program is a `.sub`).
    Src,
    /// `.dat`: a data list.
    Dat,
}

impl FileKind {
    /// The kind of `path` from its extension (any case); `None` for a file
    /// that is not KRL.
    pub fn from_path(path: &Path) -> Option<FileKind> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "src" | "sub" => Some(FileKind::Src),
            "dat" => Some(FileKind::Dat),
            _ => None,
        }
    }
}

/// The text of a KRL file: UTF-8 when the bytes are UTF-8 (a leading byte
/// order mark removed), otherwise Windows-1252 as KSS writes it. The bytes
/// 0x80–0x9F are taken as Latin-1 control characters: they only matter in
/// comments and strings, where the parser does not look at them.
pub fn decode(bytes: &[u8]) -> Cow<'_, str> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

/// Parses `text` as a file of `kind`, then checks what a KRC refuses when
/// it loads a parsed file: a routine defined twice, a name declared twice
/// in one routine (or data list), a label defined twice or a `GOTO` to a
/// label its routine does not have or into a block (IF, loop, SWITCH) from
/// outside, `GLOBAL` in a data list that is not
/// `PUBLIC`, `EXIT` outside a loop, `RETURN` with a value in a `DEF` or
/// without one in a `DEFFCT`, an array of more than 3 dimensions.
pub fn check(kind: FileKind, text: &str) -> Result<(), SyntaxError> {
    match kind {
        FileKind::Src => check_src(&parse_src(text)?),
        FileKind::Dat => check_dat(&parse_dat(text)?),
    }
}

fn refuse(line: u32, message: String) -> Result<(), SyntaxError> {
    Err(SyntaxError {
        line,
        col: 1,
        message,
    })
}

fn check_src(file: &SrcFile) -> Result<(), SyntaxError> {
    let mut routines: HashMap<String, u32> = HashMap::new();
    for r in &file.routines {
        if let Some(first) = routines.insert(r.name.to_ascii_uppercase(), r.line) {
            return refuse(
                r.line,
                format!(
                    "routine `{}` is defined twice (first at line {first})",
                    r.name
                ),
            );
        }
        // (A parameter is declared in the body too, as KRL requires.)
        let mut names: HashMap<String, u32> = HashMap::new();
        for st in &r.body {
            if let StmtKind::Decl { vars, .. } = &st.kind {
                for v in vars {
                    if let Some(first) = names.insert(v.name.to_ascii_uppercase(), st.line) {
                        return refuse(
                            st.line,
                            format!(
                                "`{}` is declared twice in `{}` (first at line {first})",
                                v.name, r.name
                            ),
                        );
                    }
                }
            }
        }
        let mut j = Jumps::default();
        jumps(&r.body, &mut j, &mut BlockPath::new())?;
        if let Some(p) = r.params.iter().find(|p| p.array_dims > MAX_ARRAY_DIMS) {
            return refuse(
                r.line,
                format!(
                    "parameter `{}` has {} dimensions; KRL arrays have at most {MAX_ARRAY_DIMS}",
                    p.name, p.array_dims
                ),
            );
        }
        blocks(&r.body, &r.kind, &r.name, false)?;
        goto_targets(&j, &r.name)?;
    }
    Ok(())
}

/// Most dimensions of a KRL array.
const MAX_ARRAY_DIMS: usize = 3;

/// An array declared with more than [`MAX_ARRAY_DIMS`] dimensions.
fn array_dims(vars: &[Declarator], line: u32) -> Result<(), SyntaxError> {
    match vars.iter().find(|v| v.dims.len() > MAX_ARRAY_DIMS) {
        Some(v) => refuse(
            line,
            format!(
                "`{}` has {} dimensions; KRL arrays have at most {MAX_ARRAY_DIMS}",
                v.name,
                v.dims.len()
            ),
        ),
        None => Ok(()),
    }
}

/// What the statements of a routine may not be where they are: `EXIT`
/// outside a loop, `RETURN` with a value in a `DEF` or without one in a
/// `DEFFCT`, arrays of more than 3 dimensions; in every nested block.
fn blocks(
    body: &[Stmt],
    kind: &RoutineKind,
    routine: &str,
    in_loop: bool,
) -> Result<(), SyntaxError> {
    for st in body {
        match &st.kind {
            StmtKind::Exit if !in_loop => {
                return refuse(
                    st.line,
                    "EXIT outside a loop (LOOP, FOR, WHILE or REPEAT)".to_string(),
                );
            }
            StmtKind::Return(Some(_)) if *kind == RoutineKind::Def => {
                return refuse(
                    st.line,
                    format!("RETURN with a value in DEF `{routine}` (only a DEFFCT returns one)"),
                );
            }
            StmtKind::Return(None) if matches!(kind, RoutineKind::DefFct(_)) => {
                return refuse(
                    st.line,
                    format!("RETURN without a value in DEFFCT `{routine}`"),
                );
            }
            StmtKind::Decl { vars, .. } => array_dims(vars, st.line)?,
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                blocks(then_body, kind, routine, in_loop)?;
                blocks(else_body, kind, routine, in_loop)?;
            }
            StmtKind::While { body, .. }
            | StmtKind::For { body, .. }
            | StmtKind::Loop { body }
            | StmtKind::Repeat { body, .. } => blocks(body, kind, routine, true)?,
            StmtKind::Switch { cases, default, .. } => {
                for (_, b) in cases {
                    blocks(b, kind, routine, in_loop)?;
                }
                if let Some(b) = default {
                    blocks(b, kind, routine, in_loop)?;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Where a label or GOTO stands: the blocks around it, outermost first
/// (each block numbered once per routine).
type BlockPath = Vec<u32>;

/// The labels and GOTOs of one routine, with where each stands.
#[derive(Default)]
struct Jumps {
    /// Upper-case label → (line, blocks around it).
    labels: HashMap<String, (u32, BlockPath)>,
    /// GOTO target as written, line, blocks around it.
    gotos: Vec<(String, u32, BlockPath)>,
    /// The blocks numbered so far.
    blocks: u32,
}

/// Labels (refusing one defined twice) and GOTOs of a routine, in every
/// nested block; `path` is the blocks around `body`.
fn jumps(body: &[Stmt], j: &mut Jumps, path: &mut BlockPath) -> Result<(), SyntaxError> {
    fn nested(b: &[Stmt], j: &mut Jumps, path: &mut BlockPath) -> Result<(), SyntaxError> {
        j.blocks += 1;
        path.push(j.blocks);
        let r = jumps(b, j, path);
        path.pop();
        r
    }
    for st in body {
        match &st.kind {
            StmtKind::Label(l) => {
                if let Some((first, _)) = j
                    .labels
                    .insert(l.to_ascii_uppercase(), (st.line, path.clone()))
                {
                    return refuse(
                        st.line,
                        format!("label `{l}` is defined twice (first at line {first})"),
                    );
                }
            }
            StmtKind::Goto(l) => j.gotos.push((l.clone(), st.line, path.clone())),
            kind => {
                for b in kind.blocks() {
                    nested(b, j, path)?;
                }
            }
        }
    }
    Ok(())
}

/// Every GOTO of a routine jumps to a label of the routine, in its own
/// block or one around it: KUKA's programming manual (GOTO) forbids a
/// jump into an IF, a loop or a SWITCH from outside, and from one CASE
/// into another (out of a block is allowed).
fn goto_targets(j: &Jumps, routine: &str) -> Result<(), SyntaxError> {
    for (l, line, from) in &j.gotos {
        match j.labels.get(&l.to_ascii_uppercase()) {
            None => {
                return refuse(*line, format!("GOTO `{l}`: `{routine}` has no label `{l}`"));
            }
            Some((at, to)) if !from.starts_with(to) => {
                return refuse(
                    *line,
                    format!(
                        "GOTO `{l}` jumps into a block (IF, loop or SWITCH) from outside: label `{l}` is at line {at}"
                    ),
                );
            }
            Some(_) => {}
        }
    }
    Ok(())
}

fn check_dat(file: &DatFile) -> Result<(), SyntaxError> {
    let mut names: HashMap<String, u32> = HashMap::new();
    for st in &file.items {
        if let StmtKind::Decl { global, vars, .. } = &st.kind {
            array_dims(vars, st.line)?;
            if *global && !file.public {
                return refuse(
                    st.line,
                    format!(
                        "GLOBAL in data list `{}`, which is not PUBLIC (write `DEFDAT {} PUBLIC`)",
                        file.name, file.name
                    ),
                );
            }
            for v in vars {
                if let Some(first) = names.insert(v.name.to_ascii_uppercase(), st.line) {
                    return refuse(
                        st.line,
                        format!("`{}` is declared twice (first at line {first})", v.name),
                    );
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ansi_and_utf8_files_decode() {
        assert_eq!(decode(b"\xEF\xBB\xBFDEF a()"), "DEF a()");
        assert_eq!(decode(b";Gr\xFC\xDFe\nDEF a()"), ";Grüße\nDEF a()");
        assert_eq!(decode(";Grüße".as_bytes()), ";Grüße");
    }

    #[test]
    fn what_a_krc_refuses_after_parsing() {
        let line = |kind, text| check(kind, text).map_err(|e| (e.line, e.message));
        assert!(line(FileKind::Src, "DEF a()\n  GOTO L1\n  L1:\nEND\n").is_ok());
        let e = line(FileKind::Src, "DEF a()\n  GOTO L2\n  L1:\nEND\n").unwrap_err();
        assert_eq!(e.0, 2, "{e:?}");
        let e = line(
            FileKind::Src,
            "DEF a()\n  L1:\n  IF TRUE THEN\n    L1:\n  ENDIF\nEND\n",
        )
        .unwrap_err();
        assert_eq!(e.0, 4, "{e:?}");
        let e = line(FileKind::Src, "DEF a()\n  DECL INT x\n  DECL REAL x\nEND\n").unwrap_err();
        assert_eq!(e.0, 3, "{e:?}");
        let e = line(FileKind::Src, "DEF a()\nEND\nDEF A()\nEND\n").unwrap_err();
        assert_eq!(e.0, 3, "{e:?}");
        let e = line(FileKind::Dat, "DEFDAT d\n  DECL GLOBAL INT x\nENDDAT\n").unwrap_err();
        assert!(e.1.contains("PUBLIC"), "{e:?}");
        assert!(
            line(
                FileKind::Dat,
                "DEFDAT d PUBLIC\n  DECL GLOBAL INT x\nENDDAT\n"
            )
            .is_ok()
        );
        let e = line(FileKind::Src, "DEF a()\n  DECL INT END\nEND\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("keyword"), "{e:?}");
        // EXIT belongs in a loop (at any depth of IF/SWITCH within it).
        let e = line(
            FileKind::Src,
            "DEF a()\n  IF TRUE THEN\n    EXIT\n  ENDIF\nEND\n",
        )
        .unwrap_err();
        assert!(e.0 == 3 && e.1.contains("EXIT outside a loop"), "{e:?}");
        assert!(
            line(
                FileKind::Src,
                "DEF a()\n  LOOP\n    IF TRUE THEN\n      EXIT\n    ENDIF\n  ENDLOOP\nEND\n"
            )
            .is_ok()
        );
        // RETURN's value: only in a DEFFCT, and always there.
        let e = line(FileKind::Src, "DEF a()\n  RETURN 5\nEND\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("RETURN with a value"), "{e:?}");
        let e = line(FileKind::Src, "DEFFCT INT f()\n  RETURN\nENDFCT\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("without a value"), "{e:?}");
        assert!(
            line(
                FileKind::Src,
                "DEF a()\n  RETURN\nEND\nDEFFCT INT f()\n  RETURN 1\nENDFCT\n"
            )
            .is_ok()
        );
        // At most 3 array dimensions, in modules and data lists.
        let e = line(FileKind::Src, "DEF a()\n  DECL INT q[2,2,2,2]\nEND\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("4 dimensions"), "{e:?}");
        let e = line(FileKind::Dat, "DEFDAT d\n  DECL INT q[2,2,2,2]\nENDDAT\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("at most 3"), "{e:?}");
        assert!(line(FileKind::Dat, "DEFDAT d\n  DECL INT q[2,2,2]\nENDDAT\n").is_ok());
        // A statement's first word is no routine name (its call would
        // read as the statement).
        let e = line(FileKind::Src, "DEF ptp()\nEND\n").unwrap_err();
        assert!(e.0 == 1 && e.1.contains("keyword"), "{e:?}");
        let e = line(FileKind::Src, "DEF a()\n  DECL INT wait\nEND\n").unwrap_err();
        assert!(e.0 == 2 && e.1.contains("keyword"), "{e:?}");
        // GOTO: out of a block or within it, never into one from outside.
        assert!(
            line(
                FileKind::Src,
                "DEF a()\n  LOOP\n    IF TRUE THEN\n      GOTO out\n    ENDIF\n    again:\n    GOTO again\n  ENDLOOP\n  out:\nEND\n"
            )
            .is_ok()
        );
        let e = line(
            FileKind::Src,
            "DEF a()\n  GOTO in\n  IF TRUE THEN\n    in:\n  ENDIF\nEND\n",
        )
        .unwrap_err();
        assert!(e.0 == 2 && e.1.contains("into a block"), "{e:?}");
        let e = line(
            FileKind::Src,
            "DEF a()\n  SWITCH 1\n  CASE 1\n    GOTO two\n  CASE 2\n    two:\n  ENDSWITCH\nEND\n",
        )
        .unwrap_err();
        assert!(e.0 == 4 && e.1.contains("into a block"), "{e:?}");
        let e = line(
            FileKind::Src,
            "DEF a()\n  IF TRUE THEN\n    GOTO e\n  ELSE\n    e:\n  ENDIF\nEND\n",
        )
        .unwrap_err();
        assert_eq!(e.0, 3, "{e:?}");
    }

    #[test]
    fn kinds_come_from_the_extension() {
        assert_eq!(
            FileKind::from_path(Path::new("a/SPS.SUB")),
            Some(FileKind::Src)
        );
        assert_eq!(FileKind::from_path(Path::new("x.Dat")), Some(FileKind::Dat));
        assert_eq!(FileKind::from_path(Path::new("x.txt")), None);
        assert!(check(FileKind::Dat, "DEFDAT x\nENDDAT\n").is_ok());
        assert_eq!(
            check(FileKind::Src, "DEF a()\n  x =\nEND\n").map_err(|e| e.line),
            Err(2)
        );
    }
}
