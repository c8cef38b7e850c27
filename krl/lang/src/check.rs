//! Checking KRL files as a controller loads them: the text decoded the way
//! KSS writes it (ANSI, i.e. Windows-1252, or UTF-8 with or without a byte
//! order mark), and parsed by its kind (`.src`/`.sub` modules, `.dat` data
//! lists). What `kuka-bridge krl check` and the corpus tests run.

use std::borrow::Cow;
use std::path::Path;

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

/// Parses `text` as a file of `kind`.
pub fn check(kind: FileKind, text: &str) -> Result<(), SyntaxError> {
    match kind {
        FileKind::Src => parse_src(text).map(|_| ()),
        FileKind::Dat => parse_dat(text).map(|_| ()),
    }
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
