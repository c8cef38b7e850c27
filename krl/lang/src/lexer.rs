//! The KRL lexer: turns source text into tokens with line and column.
//!
//! KRL is line-oriented, so line ends are tokens. Comments (`;` to the end of
//! the line, which includes `;FOLD` markers) and `&ACCESS`-style header lines
//! are skipped. Identifiers keep their spelling; the parser compares keywords
//! case-insensitively, as KRL does.

use crate::SyntaxError;

/// What a token is.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// A name: keyword, variable, routine or system variable (`$POS_ACT`).
    Ident(String),
    /// An integer literal.
    Int(i64),
    /// A real literal (`1.5`, `2E3`).
    Real(f64),
    /// A string literal (`"text"`), without the quotes.
    Str(String),
    /// A bit or hex literal: `'B0101'` or `'H1F'`, already converted.
    Bits(i64),
    /// An enumeration value `#NAME`, without the `#`.
    Enum(String),
    /// An operator or punctuation: `==`, `<>`, `<=`, `>=`, `<`, `>`, `=`,
    /// `+`, `-`, `*`, `/`, `:`, `,`, `(`, `)`, `[`, `]`, `{`, `}`, `.`.
    Sym(&'static str),
    /// The end of a line.
    Newline,
    /// The end of the file.
    Eof,
}

/// A token and where it starts (1-based line and column).
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    /// The token.
    pub tok: Tok,
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
}

const SYMBOLS: [&str; 19] = [
    "==", "<>", "<=", ">=", "<", ">", "=", "+", "-", "*", "/", ":", ",", "(", ")", "[", "]", "{",
    "}",
];

/// Splits `text` into tokens. Non-ASCII characters are allowed only in
/// comments and strings (KRL files are ANSI; a stray character elsewhere is
/// almost always a copy-paste accident).
pub fn lex(text: &str) -> Result<Vec<Token>, SyntaxError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line, mut col) = (0usize, 1u32, 1u32);
    let mut line_start = true;
    while i < chars.len() {
        let c = chars[i];
        let start_col = col;
        let err = |msg: String| SyntaxError {
            line,
            col: start_col,
            message: msg,
        };
        match c {
            '\n' => {
                out.push(Token {
                    tok: Tok::Newline,
                    line,
                    col,
                });
                i += 1;
                line += 1;
                col = 1;
                line_start = true;
                continue;
            }
            ' ' | '\t' | '\r' | '\u{feff}' | '\u{c}' => {
                i += 1;
                col += 1;
                continue;
            }
            ';' => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            '&' if line_start => {
                // Header lines such as `&ACCESS RVP` or `&REL 3`.
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            _ => {}
        }
        line_start = false;
        let mut take = |n: usize, tok: Tok, i: &mut usize, col: &mut u32| {
            out.push(Token {
                tok,
                line,
                col: start_col,
            });
            *i += n;
            *col += n as u32;
        };
        if c.is_ascii_alphabetic() || c == '_' || c == '$' {
            let mut j = i;
            while j < chars.len()
                && (chars[j].is_ascii_alphanumeric() || chars[j] == '_' || chars[j] == '$')
            {
                j += 1;
            }
            let name: String = chars[i..j].iter().collect();
            take(j - i, Tok::Ident(name), &mut i, &mut col);
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let mut j = i;
            while j < chars.len() && chars[j].is_ascii_digit() {
                j += 1;
            }
            let mut real = false;
            if j < chars.len()
                && chars[j] == '.'
                && chars
                    .get(j + 1)
                    .is_none_or(|d| !d.is_ascii_alphabetic() || d.eq_ignore_ascii_case(&'e'))
            {
                real = true;
                j += 1;
                while j < chars.len() && chars[j].is_ascii_digit() {
                    j += 1;
                }
            }
            if j < chars.len() && chars[j].eq_ignore_ascii_case(&'e') {
                let mut k = j + 1;
                if k < chars.len() && (chars[k] == '+' || chars[k] == '-') {
                    k += 1;
                }
                if k < chars.len() && chars[k].is_ascii_digit() {
                    real = true;
                    j = k;
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                }
            }
            let s: String = chars[i..j].iter().collect();
            let tok = if real {
                Tok::Real(
                    s.parse()
                        .map_err(|_| err(format!("malformed number `{s}`")))?,
                )
            } else {
                Tok::Int(
                    s.parse()
                        .map_err(|_| err(format!("integer `{s}` is too large")))?,
                )
            };
            take(j - i, tok, &mut i, &mut col);
        } else if c == '"' {
            let mut j = i + 1;
            while j < chars.len() && chars[j] != '"' && chars[j] != '\n' {
                j += 1;
            }
            if j >= chars.len() || chars[j] != '"' {
                return Err(err("string not closed on this line".into()));
            }
            let s: String = chars[i + 1..j].iter().collect();
            take(j + 1 - i, Tok::Str(s), &mut i, &mut col);
        } else if c == '\'' {
            let mut j = i + 1;
            while j < chars.len() && chars[j] != '\'' && chars[j] != '\n' {
                j += 1;
            }
            if j >= chars.len() || chars[j] != '\'' {
                return Err(err(
                    "bit literal not closed on this line (expected 'B0101' or 'H1F')".into(),
                ));
            }
            let body: String = chars[i + 1..j].iter().collect();
            let (radix, digits) = match body.chars().next() {
                Some('B' | 'b') => (2, &body[1..]),
                Some('H' | 'h') => (16, &body[1..]),
                _ => {
                    return Err(err(format!(
                        "'{body}' is not a bit ('B…') or hex ('H…') literal"
                    )));
                }
            };
            let v = i64::from_str_radix(digits, radix)
                .map_err(|_| err(format!("malformed literal '{body}'")))?;
            take(j + 1 - i, Tok::Bits(v), &mut i, &mut col);
        } else if c == '#' {
            let mut j = i + 1;
            while j < chars.len() && (chars[j].is_ascii_alphanumeric() || chars[j] == '_') {
                j += 1;
            }
            if j == i + 1 {
                return Err(err(
                    "`#` must start an enumeration value such as #BASE".into()
                ));
            }
            let s: String = chars[i + 1..j].iter().collect();
            take(j - i, Tok::Enum(s), &mut i, &mut col);
        } else if c == '.' {
            take(1, Tok::Sym("."), &mut i, &mut col);
        } else if let Some(sym) = SYMBOLS.iter().find(|s| {
            s.chars()
                .enumerate()
                .all(|(k, sc)| chars.get(i + k) == Some(&sc))
        }) {
            take(sym.len(), Tok::Sym(sym), &mut i, &mut col);
        } else if !c.is_ascii() {
            return Err(err(format!(
                "non-ASCII character `{c}` outside a comment or string"
            )));
        } else {
            return Err(err(format!("unexpected character `{c}`")));
        }
    }
    out.push(Token {
        tok: Tok::Eof,
        line,
        col,
    });
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        lex(s).expect("lex").into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn lexes_the_usual_things() {
        assert_eq!(
            toks("&ACCESS RVP\nPTP {X 200, Y -5.5} C_DIS ; go\n"),
            vec![
                Tok::Newline,
                Tok::Ident("PTP".into()),
                Tok::Sym("{"),
                Tok::Ident("X".into()),
                Tok::Int(200),
                Tok::Sym(","),
                Tok::Ident("Y".into()),
                Tok::Sym("-"),
                Tok::Real(5.5),
                Tok::Sym("}"),
                Tok::Ident("C_DIS".into()),
                Tok::Newline,
                Tok::Eof
            ]
        );
        assert_eq!(
            toks("'B0101' 'H1F' #DATA_OK a<>b")[..3],
            [Tok::Bits(5), Tok::Bits(31), Tok::Enum("DATA_OK".into())]
        );
        assert_eq!(toks("$VEL.CP=0.2")[1], Tok::Sym("."));
        assert_eq!(
            toks("1E3 2.5e-1")[..2],
            [Tok::Real(1000.0), Tok::Real(0.25)]
        );
    }

    #[test]
    fn reports_where_it_fails() {
        let e = lex("A=1\nB=\"open\n").expect_err("unclosed string");
        assert_eq!((e.line, e.col), (2, 3));
        let e = lex("x = 1 ; ä is fine here\ny = ä").expect_err("non-ascii");
        assert_eq!(e.line, 2);
    }
}
