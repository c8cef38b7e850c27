//! The KRL parser: tokens to a syntax tree, refusing with a line number.
//!
//! It covers the language as KSS 8.x programs use it (see the crate doc for
//! the list) and is strict where KRL is: one statement per line, block
//! keywords matched, names at most 24 characters.
//!
//! Its recursion is bounded: expressions deeper than
//! [`MAX_EXPR_DEPTH`], larger than [`MAX_EXPR_NODES`] per statement, and
//! blocks nested deeper than [`MAX_BLOCK_DEPTH`] are refused with their
//! line (see [`crate::limits`]).

use crate::ast::*;
use crate::lexer::{Tok, Token, lex};
use crate::limits::{MAX_BLOCK_DEPTH, MAX_EXPR_DEPTH, MAX_EXPR_NODES};
use crate::{MAX_NAME_LEN, SyntaxError};

/// Parses a `.src` (or `.sub`) file.
pub fn parse_src(text: &str) -> Result<SrcFile, SyntaxError> {
    let mut p = Parser::new(text)?;
    let mut routines = Vec::new();
    loop {
        p.skip_newlines();
        if p.at_eof() {
            break;
        }
        routines.push(p.routine()?);
    }
    if routines.is_empty() {
        return Err(p.error_here("no DEF or DEFFCT in the file"));
    }
    Ok(SrcFile { routines })
}

/// Parses a `.dat` file.
pub fn parse_dat(text: &str) -> Result<DatFile, SyntaxError> {
    let mut p = Parser::new(text)?;
    p.skip_newlines();
    let line = p.line();
    p.expect_kw("DEFDAT")?;
    let name = p.name()?;
    let public = p.eat_kw("PUBLIC");
    p.end_of_statement()?;
    let (items, _) = p.block(&["ENDDAT"], "DEFDAT", line)?;
    for s in &items {
        match s.kind {
            StmtKind::Decl { .. }
            | StmtKind::Struc { .. }
            | StmtKind::Enum { .. }
            | StmtKind::Signal { .. }
            | StmtKind::Ext { .. }
            | StmtKind::Channel { .. }
            | StmtKind::Import { .. }
            | StmtKind::Assign { .. } => {}
            _ => {
                return Err(SyntaxError {
                    line: s.line,
                    col: 1,
                    message: "only declarations and initial values belong in a .dat file".into(),
                });
            }
        }
    }
    p.bump(); // ENDDAT
    p.end_of_statement()?;
    p.skip_newlines();
    if !p.at_eof() {
        return Err(p.error_here("text after ENDDAT"));
    }
    Ok(DatFile {
        name,
        public,
        items,
        line,
    })
}

struct Parser {
    toks: Vec<Token>,
    pos: usize,
    /// Control blocks open around the current statement.
    blocks: usize,
    /// Nested `expr`/unary calls active (the expression parser's recursion).
    expr_depth: usize,
    /// Expression nodes built for the current statement.
    expr_nodes: usize,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Ident(s) => format!("`{s}`"),
        Tok::Int(v) => format!("`{v}`"),
        Tok::Real(v) => format!("`{v}`"),
        Tok::Str(s) => format!("\"{s}\""),
        Tok::Bits(v) => format!("bit literal {v}"),
        Tok::Enum(s) => format!("`#{s}`"),
        Tok::Sym(s) => format!("`{s}`"),
        Tok::Newline => "the end of the line".into(),
        Tok::Eof => "the end of the file".into(),
    }
}

const IMPLICIT_DECL_TYPES: [&str; 9] = [
    "INT", "REAL", "BOOL", "CHAR", "FRAME", "POS", "E6POS", "AXIS", "E6AXIS",
];

/// Keywords a name may not be (structure, declarations, operators,
/// literals, and the words that start a statement: a routine `ptp()` could
/// be declared but never called, its call reads as a motion).
const RESERVED: [&str; 71] = [
    "DEF",
    "END",
    "DEFFCT",
    "ENDFCT",
    "DEFDAT",
    "ENDDAT",
    "DECL",
    "GLOBAL",
    "PUBLIC",
    "CONST",
    "IF",
    "THEN",
    "ELSE",
    "ENDIF",
    "FOR",
    "TO",
    "ENDFOR",
    "WHILE",
    "ENDWHILE",
    "REPEAT",
    "UNTIL",
    "LOOP",
    "ENDLOOP",
    "SWITCH",
    "CASE",
    "ENDSWITCH",
    "GOTO",
    "RETURN",
    "EXIT",
    "AND",
    "OR",
    "NOT",
    "EXOR",
    "B_AND",
    "B_OR",
    "B_NOT",
    "B_EXOR",
    "TRUE",
    "FALSE",
    "STRUC",
    "ENUM",
    "SIGNAL",
    "EXT",
    "EXTFCT",
    "HALT",
    "CONTINUE",
    "RESUME",
    "ON_ERROR_PROCEED",
    "BRAKE",
    "WAIT",
    "PTP",
    "PTP_REL",
    "LIN",
    "LIN_REL",
    "CIRC",
    "CIRC_REL",
    "SPLINE",
    "PTP_SPLINE",
    "ENDSPLINE",
    "SPTP",
    "SLIN",
    "SCIRC",
    "SPTP_REL",
    "SLIN_REL",
    "SCIRC_REL",
    "SPL",
    "INTERRUPT",
    "TRIGGER",
    "CONFIRM",
    "CHANNEL",
    "IMPORT",
];

/// Keywords that end a block; seeing one where a statement should start
/// means a block is not closed properly.
const BLOCK_ENDS: [&str; 14] = [
    "END",
    "ENDFCT",
    "ENDIF",
    "ELSE",
    "ENDWHILE",
    "ENDFOR",
    "ENDLOOP",
    "UNTIL",
    "ENDSWITCH",
    "CASE",
    "DEFAULT",
    "ENDSPLINE",
    "ENDDAT",
    "ENDFOLD",
];

impl Parser {
    fn new(text: &str) -> Result<Self, SyntaxError> {
        Ok(Parser {
            toks: lex(text)?,
            pos: 0,
            blocks: 0,
            expr_depth: 0,
            expr_nodes: 0,
        })
    }

    fn peek(&self) -> &Tok {
        &self.toks[self.pos.min(self.toks.len() - 1)].tok
    }

    fn peek_at(&self, n: usize) -> &Tok {
        &self.toks[(self.pos + n).min(self.toks.len() - 1)].tok
    }

    fn line(&self) -> u32 {
        self.toks[self.pos.min(self.toks.len() - 1)].line
    }

    fn bump(&mut self) -> Tok {
        let t = self.peek().clone();
        if self.pos < self.toks.len() - 1 {
            self.pos += 1;
        }
        t
    }

    fn at_eof(&self) -> bool {
        matches!(self.peek(), Tok::Eof)
    }

    fn error_here(&self, message: impl Into<String>) -> SyntaxError {
        let t = &self.toks[self.pos.min(self.toks.len() - 1)];
        SyntaxError {
            line: t.line,
            col: t.col,
            message: message.into(),
        }
    }

    fn unexpected(&self, wanted: &str) -> SyntaxError {
        self.error_here(format!(
            "expected {wanted}, found {}",
            describe(self.peek())
        ))
    }

    fn skip_newlines(&mut self) {
        while matches!(self.peek(), Tok::Newline) {
            self.bump();
        }
    }

    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Tok::Ident(s) if s.eq_ignore_ascii_case(kw))
    }

    fn eat_kw(&mut self, kw: &str) -> bool {
        if self.is_kw(kw) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn expect_kw(&mut self, kw: &str) -> Result<(), SyntaxError> {
        if self.eat_kw(kw) {
            Ok(())
        } else {
            Err(self.unexpected(kw))
        }
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Tok::Sym(x) if *x == s)
    }

    fn eat_sym(&mut self, s: &str) -> bool {
        if self.is_sym(s) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn expect_sym(&mut self, s: &str) -> Result<(), SyntaxError> {
        if self.eat_sym(s) {
            Ok(())
        } else {
            Err(self.unexpected(&format!("`{s}`")))
        }
    }

    fn end_of_statement(&mut self) -> Result<(), SyntaxError> {
        match self.peek() {
            Tok::Newline => {
                self.bump();
                Ok(())
            }
            Tok::Eof => Ok(()),
            _ => Err(self.unexpected("the end of the statement")),
        }
    }

    /// An identifier (not checked against keywords).
    fn ident(&mut self) -> Result<String, SyntaxError> {
        match self.peek().clone() {
            Tok::Ident(s) => {
                self.bump();
                Ok(s)
            }
            _ => Err(self.unexpected("a name")),
        }
    }

    /// A user-chosen name: at most 24 characters and not a keyword, as
    /// KRL requires.
    fn name(&mut self) -> Result<String, SyntaxError> {
        let (line, col) = (self.line(), self.toks[self.pos].col);
        let s = self.ident()?;
        if RESERVED.contains(&s.to_ascii_uppercase().as_str()) {
            return Err(SyntaxError {
                line,
                col,
                message: format!("`{s}` is a KRL keyword and cannot be a name"),
            });
        }
        if s.len() > MAX_NAME_LEN && !s.starts_with('$') {
            return Err(SyntaxError {
                line,
                col,
                message: format!(
                    "name `{s}` has {} characters; KRL allows at most {MAX_NAME_LEN}",
                    s.len()
                ),
            });
        }
        Ok(s)
    }

    fn routine(&mut self) -> Result<Routine, SyntaxError> {
        let line = self.line();
        let global = self.eat_kw("GLOBAL");
        let kind = if self.eat_kw("DEF") {
            RoutineKind::Def
        } else if self.eat_kw("DEFFCT") {
            let mut ty = self.ident()?;
            // `DEFFCT CHAR[128] name()`: a function returning a string.
            if !self.dims()?.is_empty() {
                ty.push_str("[]");
            }
            RoutineKind::DefFct(ty)
        } else if self.is_kw("DEFDAT") {
            return Err(self.error_here("DEFDAT belongs in the .dat file"));
        } else {
            return Err(self.unexpected("DEF or DEFFCT (statements must be inside a routine)"));
        };
        let name = self.name()?;
        self.expect_sym("(")?;
        let mut params = Vec::new();
        if !self.is_sym(")") {
            loop {
                let pname = self.name()?;
                let array_dims = self.param_dims()?;
                let mut out = false;
                if self.eat_sym(":") {
                    if self.eat_kw("OUT") {
                        out = true;
                    } else {
                        self.expect_kw("IN")?;
                    }
                }
                params.push(Param {
                    name: pname,
                    out,
                    array_dims,
                });
                if !self.eat_sym(",") {
                    break;
                }
            }
        }
        self.expect_sym(")")?;
        self.end_of_statement()?;
        let (closer, opener) = match kind {
            RoutineKind::Def => ("END", "DEF"),
            RoutineKind::DefFct(_) => ("ENDFCT", "DEFFCT"),
        };
        let (body, _) = self.block(&[closer], opener, line)?;
        check_declaration_section(&body)?;
        let end_line = self.line();
        self.bump();
        self.end_of_statement()?;
        Ok(Routine {
            kind,
            global,
            name,
            params,
            body,
            line,
            end_line,
        })
    }

    /// Statements up to one of `ends` (not consumed); returns which one.
    fn block(
        &mut self,
        ends: &[&str],
        opener: &str,
        open_line: u32,
    ) -> Result<(Vec<Stmt>, String), SyntaxError> {
        // A routine's (or the .dat's) own body is not counted.
        if self.blocks > MAX_BLOCK_DEPTH {
            return Err(SyntaxError {
                line: open_line,
                col: 1,
                message: format!(
                    "{opener}: control blocks nested deeper than {MAX_BLOCK_DEPTH} levels (limit MAX_BLOCK_DEPTH)"
                ),
            });
        }
        self.blocks += 1;
        let r = self.block_items(ends, opener, open_line);
        self.blocks -= 1;
        r
    }

    fn block_items(
        &mut self,
        ends: &[&str],
        opener: &str,
        open_line: u32,
    ) -> Result<(Vec<Stmt>, String), SyntaxError> {
        let mut out = Vec::new();
        loop {
            self.skip_newlines();
            if self.at_eof() {
                return Err(self.error_here(format!(
                    "{opener} on line {open_line} is not closed: expected {}",
                    ends.join(" or ")
                )));
            }
            if let Tok::Ident(s) = self.peek() {
                if let Some(end) = ends.iter().find(|e| s.eq_ignore_ascii_case(e)) {
                    return Ok((out, (*end).to_string()));
                }
                let upper = s.to_ascii_uppercase();
                if BLOCK_ENDS.contains(&upper.as_str()) {
                    return Err(self.error_here(format!(
                        "{upper} does not match {opener} on line {open_line} (expected {})",
                        ends.join(" or ")
                    )));
                }
            }
            out.push(self.statement()?);
        }
    }

    fn statement(&mut self) -> Result<Stmt, SyntaxError> {
        let line = self.line();
        self.expr_nodes = 0;
        let kind = self.statement_kind()?;
        Ok(Stmt { line, kind })
    }

    /// Dispatches on the statement's keyword. Every statement with more
    /// than a few locals has a function of its own: a debug build gives a
    /// function one stack slot per local of every `match` arm, and this
    /// function is on the recursion of nested blocks.
    fn statement_kind(&mut self) -> Result<StmtKind, SyntaxError> {
        let line = self.line();
        let word = match self.peek() {
            Tok::Ident(s) => s.to_ascii_uppercase(),
            _ => return Err(self.unexpected("a statement")),
        };
        let simple = |k: StmtKind, p: &mut Self| -> Result<StmtKind, SyntaxError> {
            p.bump();
            p.end_of_statement()?;
            Ok(k)
        };
        match word.as_str() {
            "DECL" => {
                self.bump();
                self.decl_rest(false)
            }
            "GLOBAL" => self.global_decl(),
            w if IMPLICIT_DECL_TYPES.contains(&w) && matches!(self.peek_at(1), Tok::Ident(_)) => {
                self.decl_rest(false)
            }
            "STRUC" => self.struc(),
            "ENUM" => self.enum_decl(),
            "SIGNAL" => self.signal(),
            "EXT" | "EXTFCT" | "EXTP" | "EXTFCTP" => self.ext_decl(line, &word),
            "IF" => self.if_block(line),
            "WHILE" => self.while_block(line),
            "FOR" => self.for_block(line),
            "LOOP" => self.loop_block(line),
            "REPEAT" => self.repeat_block(line),
            "SWITCH" => self.switch_block(line),
            "RETURN" => self.return_stmt(),
            "EXIT" => simple(StmtKind::Exit, self),
            "HALT" => simple(StmtKind::Halt, self),
            "CONTINUE" => simple(StmtKind::Continue, self),
            "RESUME" => simple(StmtKind::Resume, self),
            "ON_ERROR_PROCEED" => simple(StmtKind::OnErrorProceed, self),
            "BRAKE" => {
                self.bump();
                self.eat_kw("F");
                self.end_of_statement()?;
                Ok(StmtKind::Brake)
            }
            "WAIT" => self.wait(),
            "PTP" | "PTP_REL" | "LIN" | "LIN_REL" | "CIRC" | "CIRC_REL" => self.motion(&word),
            "SPLINE" | "PTP_SPLINE" => self.spline(line, &word),
            "SPTP" | "SLIN" | "SCIRC" | "SPTP_REL" | "SLIN_REL" | "SCIRC_REL" => {
                self.spline_motion(line, &word)
            }
            "SPL" => {
                Err(self.error_here("SPL is a spline point and belongs inside SPLINE … ENDSPLINE"))
            }
            "INTERRUPT" => self.interrupt(line),
            "TRIGGER" => self.trigger(),
            "CONFIRM" => {
                self.bump();
                let message = self.expr()?;
                self.end_of_statement()?;
                Ok(StmtKind::Confirm(message))
            }
            "GOTO" => {
                self.bump();
                let label = self.name()?;
                self.end_of_statement()?;
                Ok(StmtKind::Goto(label))
            }
            "CONST" => self.decl_rest(false),
            "CHANNEL" => self.channel(),
            "IMPORT" => self.import(),
            "ANIN" | "ANOUT" => self.analog(&word),
            _ if matches!(self.peek_at(1), Tok::Sym(":"))
                && matches!(self.peek_at(2), Tok::Newline | Tok::Eof) =>
            {
                let label = self.name()?;
                self.bump();
                self.end_of_statement()?;
                Ok(StmtKind::Label(label))
            }
            "DEF" | "DEFFCT" => {
                Err(self.error_here("a routine cannot start inside another routine (missing END?)"))
            }
            _ => {
                let k = self.action()?;
                self.end_of_statement()?;
                Ok(k.kind)
            }
        }
    }

    /// `GLOBAL` before a declaration: `GLOBAL DECL …`, and in `.dat`
    /// files also without `DECL`: `GLOBAL INT x`, `GLOBAL CONST …`,
    /// `GLOBAL SIGNAL …`, `GLOBAL STRUC …`, `GLOBAL ENUM …`.
    fn global_decl(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        if self.eat_kw("DECL") || self.is_kw("CONST") {
            self.decl_rest(true)
        } else if self.is_kw("STRUC")
            || self.is_kw("ENUM")
            || self.is_kw("INTERRUPT")
            || self.is_kw("SIGNAL")
        {
            self.statement_kind()
        } else if self.is_kw("DEF") || self.is_kw("DEFFCT") {
            Err(self.error_here("a routine cannot start inside another routine (missing END?)"))
        } else if matches!(self.peek(), Tok::Ident(_)) && matches!(self.peek_at(1), Tok::Ident(_)) {
            self.decl_rest(true)
        } else {
            Err(self.unexpected("DECL, a type, STRUC, ENUM, SIGNAL or INTERRUPT after GLOBAL"))
        }
    }

    /// `CHANNEL :name …`: the channel's name; the rest of the line is the
    /// device's parameters.
    fn channel(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        self.eat_sym(":");
        let name = self.name()?;
        self.skip_to_line_end();
        Ok(StmtKind::Channel { name })
    }

    /// `IMPORT type name IS /R1/module..name`: the local name; the path
    /// is not KRL expression syntax and is skipped.
    fn import(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        self.ident()?;
        let name = self.name()?;
        self.dims()?;
        self.expect_kw("IS")?;
        self.skip_to_line_end();
        Ok(StmtKind::Import { name })
    }

    /// `ANIN ON|OFF …` / `ANOUT ON|OFF …`.
    fn analog(&mut self, word: &str) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let on = if self.eat_kw("ON") {
            true
        } else if self.eat_kw("OFF") {
            false
        } else {
            return Err(self.unexpected(&format!("ON or OFF after {word}")));
        };
        self.skip_to_line_end();
        Ok(StmtKind::AnalogCyclic {
            input: word == "ANIN",
            on,
        })
    }

    /// Skips the rest of the line and its end.
    fn skip_to_line_end(&mut self) {
        while !matches!(self.peek(), Tok::Newline | Tok::Eof) {
            self.bump();
        }
        self.bump();
    }

    /// `[]` or `[,]` after a parameter's name: the array's dimensions.
    fn param_dims(&mut self) -> Result<usize, SyntaxError> {
        if !self.eat_sym("[") {
            return Ok(0);
        }
        let mut dims = 1;
        while self.eat_sym(",") {
            dims += 1;
        }
        self.expect_sym("]")?;
        Ok(dims)
    }

    fn struc(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let name = self.name()?;
        let mut fields = Vec::new();
        let mut ty = self.ident()?;
        loop {
            let fname = self.name()?;
            let dims = self.dims()?;
            fields.push((ty.clone(), fname, dims));
            let comma = self.eat_sym(",");
            // After a comma, a run of names: pairs (`REAL c`, `T1 a T2 b`)
            // start with a type; an odd run (`b REAL c`) with a member.
            let mut run = 0;
            while matches!(self.peek_at(run), Tok::Ident(_)) {
                run += 1;
            }
            let member_first = comma && run % 2 == 1;
            if !member_first
                && matches!(self.peek(), Tok::Ident(_))
                && matches!(self.peek_at(1), Tok::Ident(_))
            {
                // The next member type. Real files (kuka_kvp_hw_interface,
                // KRL_utils) omit the comma before it; accepted, as the
                // type name ends the previous member unambiguously.
                ty = self.ident()?;
            } else if !comma {
                break;
            }
        }
        self.end_of_statement()?;
        Ok(StmtKind::Struc { name, fields })
    }

    fn enum_decl(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let name = self.name()?;
        let mut values = vec![self.name()?];
        while self.eat_sym(",") {
            values.push(self.name()?);
        }
        self.end_of_statement()?;
        Ok(StmtKind::Enum { name, values })
    }

    fn signal(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let name = self.name()?;
        self.expr()?;
        if self.eat_kw("TO") {
            self.expr()?;
        }
        self.end_of_statement()?;
        Ok(StmtKind::Signal { name })
    }

    fn ext_decl(&mut self, line: u32, word: &str) -> Result<StmtKind, SyntaxError> {
        self.bump();
        if word.starts_with("EXTFCT") {
            self.ident()?;
        }
        let name = self.name()?;
        self.expect_sym("(")?;
        let mut depth = 1;
        while depth > 0 {
            match self.bump() {
                Tok::Sym("(") => depth += 1,
                Tok::Sym(")") => depth -= 1,
                Tok::Newline | Tok::Eof => {
                    return Err(SyntaxError {
                        line,
                        col: 1,
                        message: "`(` not closed on this line".into(),
                    });
                }
                _ => {}
            }
        }
        self.end_of_statement()?;
        Ok(StmtKind::Ext { name })
    }

    fn if_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let cond = self.expr()?;
        self.expect_kw("THEN")?;
        self.end_of_statement()?;
        let (then_body, end) = self.block(&["ELSE", "ENDIF"], "IF", line)?;
        self.bump();
        let else_body = if end == "ELSE" {
            self.end_of_statement()?;
            let (b, _) = self.block(&["ENDIF"], "ELSE", line)?;
            self.bump();
            b
        } else {
            Vec::new()
        };
        self.end_of_statement()?;
        Ok(StmtKind::If {
            cond,
            then_body,
            else_body,
        })
    }

    fn while_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let cond = self.expr()?;
        self.end_of_statement()?;
        let (body, _) = self.block(&["ENDWHILE"], "WHILE", line)?;
        self.bump();
        self.end_of_statement()?;
        Ok(StmtKind::While { cond, body })
    }

    fn for_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let var = self.name()?;
        self.expect_sym("=")?;
        let from = self.expr()?;
        self.expect_kw("TO")?;
        let to = self.expr()?;
        let step = if self.eat_kw("STEP") {
            Some(self.expr()?)
        } else {
            None
        };
        self.end_of_statement()?;
        let (body, _) = self.block(&["ENDFOR"], "FOR", line)?;
        self.bump();
        self.end_of_statement()?;
        Ok(StmtKind::For {
            var,
            from,
            to,
            step,
            body,
        })
    }

    fn loop_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        self.end_of_statement()?;
        let (body, _) = self.block(&["ENDLOOP"], "LOOP", line)?;
        self.bump();
        self.end_of_statement()?;
        Ok(StmtKind::Loop { body })
    }

    fn repeat_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        self.end_of_statement()?;
        let (body, _) = self.block(&["UNTIL"], "REPEAT", line)?;
        self.bump();
        let until = self.expr()?;
        self.end_of_statement()?;
        Ok(StmtKind::Repeat { body, until })
    }

    fn switch_block(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let selector = self.expr()?;
        self.end_of_statement()?;
        let mut cases = Vec::new();
        let mut default = None;
        loop {
            self.skip_newlines();
            if self.eat_kw("CASE") {
                let mut values = vec![self.expr()?];
                while self.eat_sym(",") {
                    values.push(self.expr()?);
                }
                self.end_of_statement()?;
                let (body, _) = self.block(&["CASE", "DEFAULT", "ENDSWITCH"], "CASE", line)?;
                cases.push((values, body));
            } else if self.eat_kw("DEFAULT") {
                self.end_of_statement()?;
                let (body, _) = self.block(&["ENDSWITCH"], "DEFAULT", line)?;
                default = Some(body);
            } else if self.eat_kw("ENDSWITCH") {
                self.end_of_statement()?;
                break;
            } else if self.at_eof() {
                return Err(self.error_here(format!(
                    "SWITCH on line {line} is not closed: expected ENDSWITCH"
                )));
            } else {
                return Err(self.unexpected("CASE, DEFAULT or ENDSWITCH"));
            }
        }
        if cases.is_empty() {
            return Err(SyntaxError {
                line,
                col: 1,
                message: "SWITCH needs at least one CASE".into(),
            });
        }
        Ok(StmtKind::Switch {
            selector,
            cases,
            default,
        })
    }

    fn return_stmt(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let v = if matches!(self.peek(), Tok::Newline | Tok::Eof) {
            None
        } else {
            Some(self.expr()?)
        };
        self.end_of_statement()?;
        Ok(StmtKind::Return(v))
    }

    fn wait(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let k = if self.eat_kw("SEC") {
            StmtKind::WaitSec(self.expr()?)
        } else if self.eat_kw("FOR") {
            StmtKind::WaitFor(self.expr()?)
        } else {
            return Err(self.unexpected("SEC or FOR after WAIT"));
        };
        self.end_of_statement()?;
        Ok(k)
    }

    fn motion(&mut self, word: &str) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let kind = match word {
            "PTP" => MotionKind::Ptp,
            "PTP_REL" => MotionKind::PtpRel,
            "LIN" => MotionKind::Lin,
            "LIN_REL" => MotionKind::LinRel,
            "CIRC" => MotionKind::Circ,
            _ => MotionKind::CircRel,
        };
        let circ = matches!(kind, MotionKind::Circ | MotionKind::CircRel);
        let first = self.expr()?;
        let (aux, target) = if circ {
            self.expect_sym(",")?;
            (Some(first), self.expr()?)
        } else {
            (None, first)
        };
        let ca = if circ && self.eat_sym(",") {
            self.expect_kw("CA")?;
            Some(self.expr()?)
        } else {
            None
        };
        let approx = self.approx(&["C_DIS", "C_PTP", "C_VEL", "C_ORI"])?;
        let rel_frame = if matches!(
            kind,
            MotionKind::PtpRel | MotionKind::LinRel | MotionKind::CircRel
        ) {
            self.rel_frame()
        } else {
            None
        };
        self.end_of_statement()?;
        Ok(StmtKind::Motion {
            kind,
            aux,
            target,
            ca,
            approx,
            rel_frame,
        })
    }

    fn spline(&mut self, line: u32, word: &str) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let ptp = word == "PTP_SPLINE";
        let with = self.with_clause()?;
        self.end_of_statement()?;
        let mut points = Vec::new();
        let mut triggers = Vec::new();
        loop {
            self.skip_newlines();
            let pline = self.line();
            let pword = match self.peek() {
                Tok::Ident(s) => s.to_ascii_uppercase(),
                Tok::Eof => {
                    return Err(self.error_here(format!(
                        "{word} on line {line} is not closed: expected ENDSPLINE"
                    )));
                }
                _ => {
                    return Err(
                        self.unexpected("a spline point (SPL, SLIN, SCIRC, SPTP) or ENDSPLINE")
                    );
                }
            };
            let kind = match pword.as_str() {
                "ENDSPLINE" => break,
                "TRIGGER" => {
                    // A spline trigger belongs to the next point.
                    self.expr_nodes = 0;
                    let kind = self.trigger()?;
                    triggers.push(Stmt { line: pline, kind });
                    continue;
                }
                "SPL" => SplinePointKind::Spl,
                "SLIN" => SplinePointKind::Slin,
                "SCIRC" => SplinePointKind::Scirc,
                "SPTP" => SplinePointKind::Sptp,
                other => {
                    return Err(self.error_here(format!(
                        "`{other}` is not allowed inside {word}: only SPL, SLIN, SCIRC and SPTP points"
                    )));
                }
            };
            self.bump();
            // Each point is a line of its own: its own size limit.
            self.expr_nodes = 0;
            let point = self.spline_point(kind, pline, &["C_SPL"])?;
            self.end_of_statement()?;
            points.push(point);
        }
        self.bump();
        let approx = self.approx(&["C_SPL"])?;
        self.end_of_statement()?;
        if points.is_empty() {
            return Err(SyntaxError {
                line,
                col: 1,
                message: format!("{word} has no points"),
            });
        }
        Ok(StmtKind::Spline {
            ptp,
            with,
            triggers,
            points,
            approx,
        })
    }

    /// A spline motion after its keyword: `[aux,] target [, CA angle]
    /// [WITH …] [approximation]`.
    fn spline_point(
        &mut self,
        kind: SplinePointKind,
        line: u32,
        approximations: &[&str],
    ) -> Result<SplinePoint, SyntaxError> {
        let first = self.expr()?;
        let (aux, target) = if kind == SplinePointKind::Scirc {
            self.expect_sym(",")?;
            (Some(first), self.expr()?)
        } else {
            (None, first)
        };
        let ca = if kind == SplinePointKind::Scirc && self.eat_sym(",") {
            self.expect_kw("CA")?;
            Some(self.expr()?)
        } else {
            None
        };
        let with = self.with_clause()?;
        let approx = self.approx(approximations)?;
        Ok(SplinePoint {
            kind,
            aux,
            target,
            with,
            ca,
            approx,
            line,
        })
    }

    /// A single spline motion outside a block (KSS 8.3+): `SPTP`, `SLIN`,
    /// `SCIRC` and their `_REL` forms.
    fn spline_motion(&mut self, line: u32, word: &str) -> Result<StmtKind, SyntaxError> {
        self.bump();
        let rel = word.ends_with("_REL");
        let kind = match word.trim_end_matches("_REL") {
            "SPTP" => SplinePointKind::Sptp,
            "SLIN" => SplinePointKind::Slin,
            _ => SplinePointKind::Scirc,
        };
        let point = self.spline_point(kind, line, &["C_SPL", "C_DIS", "C_PTP"])?;
        let rel_frame = if rel { self.rel_frame() } else { None };
        self.end_of_statement()?;
        Ok(StmtKind::SplineMotion {
            point,
            rel,
            rel_frame,
        })
    }

    /// The optional `#BASE`/`#TOOL` of a relative motion.
    fn rel_frame(&mut self) -> Option<String> {
        if let Tok::Enum(e) = self.peek()
            && (e.eq_ignore_ascii_case("BASE") || e.eq_ignore_ascii_case("TOOL"))
        {
            let frame = e.to_ascii_uppercase();
            self.bump();
            return Some(frame);
        }
        None
    }

    fn interrupt(&mut self, line: u32) -> Result<StmtKind, SyntaxError> {
        self.bump();
        if self.eat_kw("DECL") {
            let prio = self.expr()?;
            self.expect_kw("WHEN")?;
            let when = self.expr()?;
            self.expect_kw("DO")?;
            let action = Box::new(self.action()?);
            self.end_of_statement()?;
            Ok(StmtKind::InterruptDecl { prio, when, action })
        } else {
            let action = self.ident()?.to_ascii_uppercase();
            if !["ON", "OFF", "ENABLE", "DISABLE"].contains(&action.as_str()) {
                return Err(SyntaxError {
                    line,
                    col: 1,
                    message: format!(
                        "INTERRUPT {action}: expected DECL, ON, OFF, ENABLE or DISABLE"
                    ),
                });
            }
            let prio = if matches!(self.peek(), Tok::Newline | Tok::Eof) {
                None
            } else {
                Some(self.expr()?)
            };
            self.end_of_statement()?;
            Ok(StmtKind::InterruptSwitch { action, prio })
        }
    }

    fn trigger(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
        self.expect_kw("WHEN")?;
        let path = if self.eat_kw("PATH") {
            true
        } else if self.eat_kw("DISTANCE") {
            false
        } else {
            return Err(self.unexpected("DISTANCE or PATH"));
        };
        self.expect_sym("=")?;
        let at = self.expr()?;
        let onstart = self.eat_kw("ONSTART");
        self.expect_kw("DELAY")?;
        self.expect_sym("=")?;
        let delay = self.expr()?;
        self.expect_kw("DO")?;
        let action = Box::new(self.action()?);
        if self.eat_kw("PRIO") {
            self.expect_sym("=")?;
            self.expr()?;
        }
        self.end_of_statement()?;
        Ok(StmtKind::Trigger {
            path,
            at,
            onstart,
            delay,
            action,
        })
    }

    /// An assignment or a call (the body of a statement line, of a
    /// `TRIGGER … DO` or of an `INTERRUPT … DO`).
    fn action(&mut self) -> Result<Stmt, SyntaxError> {
        let line = self.line();
        let target = self.postfix()?;
        if self.eat_sym("=") {
            let value = self.expr()?;
            return Ok(Stmt {
                line,
                kind: StmtKind::Assign { target, value },
            });
        }
        match target {
            Expr::Call(name, args) => Ok(Stmt {
                line,
                kind: StmtKind::Call { name, args },
            }),
            Expr::Var(name) => Err(SyntaxError {
                line,
                col: 1,
                message: format!(
                    "`{name}` is not a statement (a call needs parentheses: `{name}()`)"
                ),
            }),
            _ => Err(self.unexpected("`=` (an assignment) or a call")),
        }
    }

    fn approx(&mut self, allowed: &[&str]) -> Result<Option<String>, SyntaxError> {
        if let Tok::Ident(s) = self.peek() {
            let up = s.to_ascii_uppercase();
            if allowed.contains(&up.as_str()) {
                self.bump();
                // KSS 8.3+ inline forms write the keyword twice for a LIN
                // or CIRC with CONT (`LIN XP2 C_DIS C_DIS`): accepted.
                if let Tok::Ident(again) = self.peek()
                    && allowed.contains(&again.to_ascii_uppercase().as_str())
                {
                    self.bump();
                }
                return Ok(Some(up));
            }
            if up.starts_with("C_") {
                return Err(self.error_here(format!(
                    "`{up}` is not allowed here (allowed: {})",
                    allowed.join(", ")
                )));
            }
        }
        Ok(None)
    }

    fn with_clause(&mut self) -> Result<Vec<(Expr, Expr)>, SyntaxError> {
        let mut out = Vec::new();
        if self.eat_kw("WITH") {
            loop {
                let t = self.postfix()?;
                self.expect_sym("=")?;
                out.push((t, self.expr()?));
                if !self.eat_sym(",") {
                    break;
                }
            }
        }
        Ok(out)
    }

    fn dims(&mut self) -> Result<Vec<Expr>, SyntaxError> {
        let mut dims = Vec::new();
        if self.eat_sym("[") {
            if !self.is_sym("]") {
                loop {
                    // `REAL t[,]`: a parameter's array type, sizes omitted.
                    if self.is_sym(",") || self.is_sym("]") {
                        dims.push(Expr::Omitted);
                    } else {
                        dims.push(self.expr()?);
                    }
                    if !self.eat_sym(",") {
                        break;
                    }
                }
            }
            self.expect_sym("]")?;
        }
        Ok(dims)
    }

    fn decl_rest(&mut self, mut global: bool) -> Result<StmtKind, SyntaxError> {
        // `DECL GLOBAL CONST`, `DECL CONST GLOBAL`, `CONST INT`, …
        loop {
            if self.eat_kw("GLOBAL") {
                global = true;
            } else if !self.eat_kw("CONST") {
                break;
            }
        }
        let ty = self.ident()?;
        let mut vars = Vec::new();
        loop {
            let name = self.name()?;
            let dims = self.dims()?;
            let init = if self.eat_sym("=") {
                Some(self.expr()?)
            } else {
                None
            };
            vars.push(Declarator { name, dims, init });
            if !self.eat_sym(",") {
                break;
            }
        }
        self.end_of_statement()?;
        Ok(StmtKind::Decl { global, ty, vars })
    }

    // ---- expressions (lowest to highest precedence) ----
    //
    // Each function returns the expression and the depth of its tree
    // (a literal or a name is 1), so that a tree deeper than
    // MAX_EXPR_DEPTH is refused while it is built: left-nested chains
    // such as `1 + 1 + … + 1` are built by loops, not by recursion, and
    // would otherwise grow without bound. The recursion itself (`(`,
    // unary operators) is bounded by `self.expr_depth`.

    /// A full expression (a statement's, or one of a statement's).
    fn expr(&mut self) -> Result<Expr, SyntaxError> {
        Ok(self.sub_expr()?.0)
    }

    fn too_deep(&self) -> SyntaxError {
        self.error_here(format!(
            "expression nested deeper than {MAX_EXPR_DEPTH} levels (limit MAX_EXPR_DEPTH)"
        ))
    }

    /// One level deeper into the parser's recursion.
    fn enter(&mut self) -> Result<(), SyntaxError> {
        self.expr_depth += 1;
        if self.expr_depth > MAX_EXPR_DEPTH {
            return Err(self.too_deep());
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.expr_depth -= 1;
    }

    /// Counts a new tree node whose deepest child has depth `child`;
    /// returns the node's depth.
    fn node(&mut self, child: usize) -> Result<usize, SyntaxError> {
        self.expr_nodes += 1;
        if self.expr_nodes > MAX_EXPR_NODES {
            return Err(self.error_here(format!(
                "the expressions of this statement have more than {MAX_EXPR_NODES} operands and operators (limit MAX_EXPR_NODES)"
            )));
        }
        let depth = child + 1;
        if depth > MAX_EXPR_DEPTH {
            return Err(self.too_deep());
        }
        Ok(depth)
    }

    /// An expression nested in another one (or a statement's).
    fn sub_expr(&mut self) -> Result<(Expr, usize), SyntaxError> {
        self.enter()?;
        let e = self.binary(0)?;
        self.leave();
        Ok(e)
    }

    /// The binary operator at the current token and its precedence
    /// (higher binds tighter): OR < EXOR < AND < comparison < + - < * /.
    fn binary_op(&self) -> Option<(BinOp, usize)> {
        const OPS: [(&str, BinOp, usize); 16] = [
            ("OR", BinOp::Or, 0),
            ("B_OR", BinOp::BOr, 0),
            ("EXOR", BinOp::Exor, 1),
            ("B_EXOR", BinOp::BExor, 1),
            ("AND", BinOp::And, 2),
            ("B_AND", BinOp::BAnd, 2),
            ("==", BinOp::Eq, 3),
            ("<>", BinOp::Ne, 3),
            ("<=", BinOp::Le, 3),
            (">=", BinOp::Ge, 3),
            ("<", BinOp::Lt, 3),
            (">", BinOp::Gt, 3),
            ("+", BinOp::Add, 4),
            ("-", BinOp::Sub, 4),
            ("*", BinOp::Mul, 5),
            ("/", BinOp::Div, 5),
        ];
        OPS.iter()
            .find(|(s, _, _)| match self.peek() {
                Tok::Sym(x) => x == s,
                Tok::Ident(x) => x.eq_ignore_ascii_case(s),
                _ => false,
            })
            .map(|(_, op, prec)| (*op, *prec))
    }

    /// Operands joined by binary operators of precedence `min_prec` or
    /// higher, left-associative (precedence climbing: one frame per
    /// precedence level actually used, not one per level of the grammar).
    fn binary(&mut self, min_prec: usize) -> Result<(Expr, usize), SyntaxError> {
        let (mut left, mut depth) = self.unary()?;
        while let Some((op, prec)) = self.binary_op()
            && prec >= min_prec
        {
            self.bump();
            let (right, rd) = self.binary(prec + 1)?;
            depth = self.node(depth.max(rd))?;
            left = Expr::Binary(op, Box::new(left), Box::new(right));
        }
        Ok((left, depth))
    }

    fn unary(&mut self) -> Result<(Expr, usize), SyntaxError> {
        let op = if self.eat_sym("-") {
            Some(UnOp::Neg)
        } else if self.eat_sym("+") {
            None
        } else if self.eat_kw("NOT") {
            Some(UnOp::Not)
        } else if self.eat_kw("B_NOT") {
            Some(UnOp::BNot)
        } else {
            let (mut left, mut depth) = self.postfix_tree()?;
            while self.eat_sym(":") {
                let (right, rd) = self.postfix_tree()?;
                depth = self.node(depth.max(rd))?;
                left = Expr::Binary(BinOp::Geo, Box::new(left), Box::new(right));
            }
            return Ok((left, depth));
        };
        // `- - - x`: every prefix operator is one level of recursion.
        self.enter()?;
        let (e, d) = self.unary()?;
        self.leave();
        Ok(match (op, e) {
            (None, e) => (e, d),
            (Some(UnOp::Neg), Expr::Int(v)) => (Expr::Int(-v), d),
            (Some(UnOp::Neg), Expr::Real(v)) => (Expr::Real(-v), d),
            (Some(op), e) => (Expr::Unary(op, Box::new(e)), self.node(d)?),
        })
    }

    /// A variable, element or component (an assignment's target, a `WITH`
    /// variable).
    fn postfix(&mut self) -> Result<Expr, SyntaxError> {
        Ok(self.postfix_tree()?.0)
    }

    fn postfix_tree(&mut self) -> Result<(Expr, usize), SyntaxError> {
        let (mut e, mut depth) = self.primary()?;
        loop {
            if self.eat_sym("[") {
                let mut idx = Vec::new();
                let mut deepest = depth;
                if !self.is_sym("]") {
                    loop {
                        // `X[1,]`: a left-out index (a row of the array).
                        let (i, d) = self.argument("]")?;
                        deepest = deepest.max(d);
                        idx.push(i);
                        if !self.eat_sym(",") {
                            break;
                        }
                    }
                }
                self.expect_sym("]")?;
                depth = self.node(deepest)?;
                e = Expr::Index(Box::new(e), idx);
            } else if self.eat_sym(".") {
                depth = self.node(depth)?;
                e = Expr::Field(Box::new(e), self.ident()?);
            } else {
                return Ok((e, depth));
            }
        }
    }

    fn primary(&mut self) -> Result<(Expr, usize), SyntaxError> {
        let leaf = match self.peek().clone() {
            Tok::Int(v) => Expr::Int(v),
            Tok::Real(v) => Expr::Real(v),
            Tok::Bits(v) => Expr::Int(v),
            Tok::Str(s) => Expr::Str(s),
            Tok::Enum(s) => Expr::Enum(s),
            Tok::Sym("(") => {
                self.bump();
                let e = self.sub_expr()?;
                self.expect_sym(")")?;
                return Ok(e);
            }
            Tok::Sym("{") => {
                self.bump();
                return self.struct_literal();
            }
            Tok::Ident(s) => {
                let up = s.to_ascii_uppercase();
                if ["THEN", "DO", "TO", "STEP", "WHEN", "DELAY", "PRIO", "WITH"]
                    .contains(&up.as_str())
                    || BLOCK_ENDS.contains(&up.as_str())
                {
                    return Err(self.unexpected("a value"));
                }
                self.bump();
                if up == "TRUE" || up == "FALSE" {
                    return Ok((Expr::Bool(up == "TRUE"), self.node(0)?));
                }
                if self.eat_sym("(") {
                    let mut args = Vec::new();
                    let mut deepest = 0;
                    if !self.is_sym(")") {
                        loop {
                            // `f(a,,3)`: a left-out argument.
                            let (a, d) = self.argument(")")?;
                            deepest = deepest.max(d);
                            args.push(a);
                            if !self.eat_sym(",") {
                                break;
                            }
                        }
                    }
                    self.expect_sym(")")?;
                    return Ok((Expr::Call(s, args), self.node(deepest)?));
                }
                return Ok((Expr::Var(s), self.node(0)?));
            }
            _ => return Err(self.unexpected("a value")),
        };
        self.bump();
        Ok((leaf, self.node(0)?))
    }

    /// An argument or index, or [`Expr::Omitted`] when the next token is
    /// `,` or `close`.
    fn argument(&mut self, close: &str) -> Result<(Expr, usize), SyntaxError> {
        if self.is_sym(",") || self.is_sym(close) {
            return Ok((Expr::Omitted, self.node(0)?));
        }
        self.sub_expr()
    }

    /// `{[TYPE:] NAME value, …}` after the `{`.
    fn struct_literal(&mut self) -> Result<(Expr, usize), SyntaxError> {
        let mut ty = None;
        if matches!(self.peek(), Tok::Ident(_)) && matches!(self.peek_at(1), Tok::Sym(":")) {
            ty = Some(self.ident()?);
            self.bump();
        }
        let mut fields = Vec::new();
        let mut deepest = 0;
        if !self.is_sym("}") {
            loop {
                let name = self.ident()?;
                // `.dat` files write array fields as `POINT2[] "text"`.
                if self.is_sym("[") && matches!(self.peek_at(1), Tok::Sym("]")) {
                    self.bump();
                    self.bump();
                }
                let (value, d) = self.sub_expr()?;
                deepest = deepest.max(d);
                fields.push((name.to_ascii_uppercase(), value));
                if !self.eat_sym(",") {
                    break;
                }
            }
        }
        if !self.eat_sym("}") {
            return Err(self.unexpected("`,` or `}` in the structure value"));
        }
        Ok((Expr::Struct { ty, fields }, self.node(deepest)?))
    }
}

/// Whether a statement is a declaration (it belongs in the routine's
/// declaration section).
fn is_declaration(k: &StmtKind) -> bool {
    matches!(
        k,
        StmtKind::Decl { .. }
            | StmtKind::Struc { .. }
            | StmtKind::Enum { .. }
            | StmtKind::Signal { .. }
            | StmtKind::Ext { .. }
            | StmtKind::Channel { .. }
            | StmtKind::Import { .. }
    )
}

/// KRL's rule for a routine body: declarations come first, before the
/// first statement, and never inside a control block; a KRC refuses the
/// module otherwise ("DECL not allowed here").
fn check_declaration_section(body: &[Stmt]) -> Result<(), SyntaxError> {
    let mut first_statement: Option<u32> = None;
    for s in body {
        if is_declaration(&s.kind) {
            if let Some(at) = first_statement {
                return Err(SyntaxError {
                    line: s.line,
                    col: 1,
                    message: format!(
                        "a declaration after the first statement (line {at}): KRL allows declarations only at the top of a routine"
                    ),
                });
            }
        } else {
            first_statement.get_or_insert(s.line);
            no_nested_declaration(&s.kind)?;
        }
    }
    Ok(())
}

fn no_nested_declaration(k: &StmtKind) -> Result<(), SyntaxError> {
    for b in k.blocks() {
        for s in b {
            if is_declaration(&s.kind) {
                return Err(SyntaxError {
                    line: s.line,
                    col: 1,
                    message: "a declaration inside a control block: KRL allows declarations only at the top of a routine".into(),
                });
            }
            no_nested_declaration(&s.kind)?;
        }
    }
    Ok(())
}
