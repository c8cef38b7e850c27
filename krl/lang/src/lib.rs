//! A front end for KRL, the KUKA Robot Language: lexer, parser and syntax
//! tree.
//!
//! It is the one reading of KRL in kuka-bridge: the service validates
//! uploaded programs with it, the simulated controller executes the
//! subset it supports from its tree, and the tests parse every KRL file
//! shipped in `krl/KRC/` with it.
//!
//! Covered syntax (KSS 8.x): `&` header lines, `;` comments and folds,
//! `DEF`/`DEFFCT`/`END`/`ENDFCT` with `IN`/`OUT` parameters and `GLOBAL`,
//! `DEFDAT … ENDDAT`, `DECL` (also implicit for the predefined types,
//! `GLOBAL`, `CONST`, arrays, initial values), `STRUC`, `ENUM`, `SIGNAL`,
//! `EXT`/`EXTFCT`, assignments, calls, `IF/ELSE`, `WHILE`, `FOR … STEP`,
//! `LOOP`, `REPEAT/UNTIL`, `SWITCH/CASE/DEFAULT`, `RETURN`, `EXIT`,
//! `HALT`, `CONTINUE`, `BRAKE [F]`, `RESUME`, `ON_ERROR_PROCEED`,
//! `WAIT SEC`, `WAIT FOR`, `PTP`/`LIN`/`CIRC` and their `_REL` forms with
//! `CA` and `C_DIS`/`C_PTP`/`C_VEL`/`C_ORI`, `SPLINE`/`PTP_SPLINE` blocks
//! of `SPL`/`SLIN`/`SCIRC`/`SPTP` points with `WITH` and `C_SPL`,
//! `INTERRUPT DECL … WHEN … DO`, `INTERRUPT ON/OFF/ENABLE/DISABLE`,
//! `TRIGGER WHEN DISTANCE|PATH = … DELAY = … DO … [PRIO = …]`; literals
//! (INT, REAL, strings, `'B…'`/`'H…'`, `#ENUM`, `TRUE`/`FALSE`, structure
//! values `{[TYPE:] X 1, …}`), the operators `+ - * /`, comparisons,
//! `NOT AND OR EXOR`, `B_NOT B_AND B_OR B_EXOR` and the geometric `:`.
//! Also read, as real KSS 8.x files write them (the public corpus in
//! `tests/corpus/`, 364 files, is the test): single spline motions
//! outside a block (`SPTP`/`SLIN`/`SCIRC` and `_REL`), array parameters
//! (`DEF f(t[]:OUT)`, `REAL t[,]`), omitted arguments and indices
//! (`f(a,,3)`, `X[1,]`), `.dat` globals without `DECL` (`GLOBAL INT x`,
//! `GLOBAL CONST`, `GLOBAL SIGNAL`), `DEFFCT CHAR[128] f()`, `GOTO` and
//! labels, `CHANNEL`, `IMPORT`, `ANIN`/`ANOUT ON|OFF`, `CONFIRM`, STRUC
//! members of a new type without a comma. Refused as a KRC refuses them:
//! a declaration after the first statement, names over 24 characters.
//!
//! Work is bounded for every input: the lexer is linear, and the parser
//! refuses expressions and blocks nested beyond the [`limits`] (with the
//! line and the limit's name) instead of recursing without end.
//!
//! Operator precedence follows common practice (comparisons bind tighter
//! than `AND`/`OR`); KUKA documents the reverse for some versions, so
//! shipped code puts parentheses around every comparison it combines.

pub mod ast;
pub mod check;
pub mod lexer;
pub mod limits;
pub mod parser;

pub use ast::*;
pub use limits::{MAX_BLOCK_DEPTH, MAX_EXPR_DEPTH, MAX_EXPR_NODES};
pub use parser::{parse_dat, parse_src};

/// KRL names (variables, routines, types) have at most 24 characters.
pub const MAX_NAME_LEN: usize = 24;

/// A syntax error with its position (1-based).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}, column {col}: {message}")]
pub struct SyntaxError {
    /// The line.
    pub line: u32,
    /// The column.
    pub col: u32,
    /// What is wrong.
    pub message: String,
}

/// Why an uploaded program is refused before it reaches a controller.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ProgramError {
    /// The `.src` file does not parse.
    #[error(".src {0}")]
    Src(SyntaxError),
    /// The `.dat` file does not parse.
    #[error(".dat {0}")]
    Dat(SyntaxError),
    /// The requested entry routine is not in the file.
    #[error("entry point `{name}` is not defined in the .src file (routines: {found})")]
    NoEntry {
        /// The requested name.
        name: String,
        /// The routines that are there.
        found: String,
    },
    /// The entry routine takes parameters; a program that is run cannot be
    /// given any.
    #[error("line {line}: entry point `{name}` must not take parameters")]
    EntryParams {
        /// Its name.
        name: String,
        /// Its line.
        line: u32,
    },
    /// The `.dat` file's name differs from the `.src` module's.
    #[error("line {line} of the .dat: DEFDAT {dat} does not match the module name {module}")]
    DatName {
        /// DEFDAT's name.
        dat: String,
        /// The first routine's name.
        module: String,
        /// DEFDAT's line.
        line: u32,
    },
    /// Two routines of the same name.
    #[error("line {line}: routine `{name}` is defined twice")]
    Duplicate {
        /// The name.
        name: String,
        /// The second definition's line.
        line: u32,
    },
}

impl ProgramError {
    /// The line the error is on (in the file it names), if any.
    pub fn line(&self) -> Option<u32> {
        match self {
            ProgramError::Src(e) | ProgramError::Dat(e) => Some(e.line),
            ProgramError::EntryParams { line, .. }
            | ProgramError::DatName { line, .. }
            | ProgramError::Duplicate { line, .. } => Some(*line),
            ProgramError::NoEntry { .. } => None,
        }
    }
}

/// A parsed program: its `.src` and optional `.dat`.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// The `.src` file.
    pub src: SrcFile,
    /// The `.dat` file, if any.
    pub dat: Option<DatFile>,
}

impl Program {
    /// Parses and checks a program: both files parse, routine names are
    /// unique, the `.dat` belongs to the module and the entry routine
    /// (`entry`, or the first routine) exists and takes no parameters.
    pub fn parse(
        src: &str,
        dat: Option<&str>,
        entry: Option<&str>,
    ) -> Result<Program, ProgramError> {
        let src = parse_src(src).map_err(ProgramError::Src)?;
        let dat = dat.map(parse_dat).transpose().map_err(ProgramError::Dat)?;
        // A set, not a list: a file of many tiny routines must not cost
        // quadratic time.
        let mut seen = std::collections::HashSet::new();
        for r in &src.routines {
            if !seen.insert(r.name.to_ascii_uppercase()) {
                return Err(ProgramError::Duplicate {
                    name: r.name.clone(),
                    line: r.line,
                });
            }
        }
        let program = Program { src, dat };
        if let (Some(d), Some(first)) = (&program.dat, program.src.routines.first())
            && !d.name.eq_ignore_ascii_case(&first.name)
        {
            return Err(ProgramError::DatName {
                dat: d.name.clone(),
                module: first.name.clone(),
                line: d.line,
            });
        }
        let e = program.entry(entry)?;
        if !e.params.is_empty() {
            return Err(ProgramError::EntryParams {
                name: e.name.clone(),
                line: e.line,
            });
        }
        Ok(program)
    }

    /// The routine called `name`, or the first routine.
    pub fn entry(&self, name: Option<&str>) -> Result<&Routine, ProgramError> {
        let found = || {
            self.src
                .routines
                .iter()
                .map(|r| r.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        match name {
            None => self
                .src
                .routines
                .first()
                .ok_or_else(|| ProgramError::NoEntry {
                    name: String::new(),
                    found: found(),
                }),
            Some(n) => self
                .src
                .routines
                .iter()
                .find(|r| r.name.eq_ignore_ascii_case(n))
                .ok_or_else(|| ProgramError::NoEntry {
                    name: n.to_string(),
                    found: found(),
                }),
        }
    }

    /// The routine called `name` (case-insensitive), if defined.
    pub fn routine(&self, name: &str) -> Option<&Routine> {
        self.src
            .routines
            .iter()
            .find(|r| r.name.eq_ignore_ascii_case(name))
    }
}
