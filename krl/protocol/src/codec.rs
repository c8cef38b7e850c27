//! Line-level encoding: fixed-decimal numbers, the per-line checksum, and a
//! cursor that reads tagged lines field by field.

/// Longest line KRL's `krl_fgets` buffer accepts (without the line end).
pub const MAX_LINE_LEN: usize = 255;
/// Largest magnitude of a REAL field: 7 significant digits, so a KRL REAL
/// (32-bit float) holds every value to the last decimal.
pub const MAX_REAL: f64 = 9999.999;
/// The step of REAL fields (three decimals): the smallest positive value a
/// file can carry; anything smaller is written as 0.
pub const REAL_STEP: f64 = 0.001;
const MODULUS: i64 = 65521;

/// Why a file could not be decoded. Every variant means "not (yet) a valid
/// file": readers retry later instead of acting on it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// The file is empty.
    #[error("empty file")]
    Empty,
    /// A line has the wrong tag.
    #[error("line {line}: expected tag {expected}, found {found:?}")]
    Tag {
        /// 1-based line number.
        line: usize,
        /// The tag that was expected.
        expected: &'static str,
        /// What was found.
        found: String,
    },
    /// A line has the wrong number of fields.
    #[error("line {line}: expected {expected} fields, found {found}")]
    FieldCount {
        /// 1-based line number.
        line: usize,
        /// Fields expected (without tag, with checksum).
        expected: usize,
        /// Fields found.
        found: usize,
    },
    /// A field is not a number of the expected form.
    #[error("line {line}, field {field}: {text:?} is not a valid {kind}")]
    Number {
        /// 1-based line number.
        line: usize,
        /// 1-based field number.
        field: usize,
        /// The offending text.
        text: String,
        /// "INT" or "REAL".
        kind: &'static str,
    },
    /// The checksum does not match the fields.
    #[error("line {line}: checksum {found} does not match {expected}")]
    Checksum {
        /// 1-based line number.
        line: usize,
        /// Computed checksum.
        expected: i64,
        /// Checksum found in the line.
        found: i64,
    },
    /// A line is too long or not ASCII.
    #[error("line {line}: not a KRL-readable line (ASCII, at most 255 characters)")]
    LineForm {
        /// 1-based line number.
        line: usize,
    },
    /// The file ended before its END record.
    #[error("file ends before its END record (half-written?)")]
    Truncated,
    /// Data after the END record.
    #[error("unexpected data after the END record")]
    TrailingData,
    /// The header names a protocol version this build does not speak.
    #[error("protocol version {0} is not supported (this build speaks 1)")]
    Version(i64),
    /// Fields are syntactically fine but their values are not allowed.
    #[error("line {line}: {what}")]
    Value {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        what: String,
    },
}

/// Why a record could not be encoded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EncodeError {
    /// A REAL value is not finite or exceeds ±[`MAX_REAL`].
    #[error("{field} = {value} cannot be encoded (finite, at most ±9999.999)")]
    Real {
        /// Field name.
        field: &'static str,
        /// The value.
        value: f64,
    },
    /// Too many or too few body records.
    #[error("{0}")]
    Shape(String),
}

/// A field value as it travels: integers as they are, REALs as integer
/// thousandths (the text `-12.345` is the value `-12345`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Field {
    Int(i32),
    Real(i32),
}

impl Field {
    fn value(self) -> i64 {
        match self {
            Field::Int(v) | Field::Real(v) => i64::from(v),
        }
    }
}

/// The line checksum over field values (REALs as thousandths), designed to
/// be computed in KRL with 32-bit INT arithmetic:
/// `c = 0; for v: m = v MOD 65521 (made non-negative); c = (c*31 + m) MOD 65521`.
pub fn checksum(values: impl IntoIterator<Item = i64>) -> i64 {
    values
        .into_iter()
        .fold(0, |c, v| (c * 31 + v.rem_euclid(MODULUS)) % MODULUS)
}

/// Converts a REAL to thousandths, rejecting what KRL could not hold.
pub(crate) fn real(field: &'static str, value: f64) -> Result<Field, EncodeError> {
    if !value.is_finite() || value.abs() > MAX_REAL + 0.0005 {
        return Err(EncodeError::Real { field, value });
    }
    // In range by the check above, so the cast cannot saturate.
    #[allow(clippy::cast_possible_truncation)]
    let thousandths = (value * 1000.0).round() as i32;
    Ok(Field::Real(thousandths))
}

/// Appends one line `TAG f1 .. fn K\n` to `out`.
pub(crate) fn write_line(out: &mut String, tag: &str, fields: &[Field]) {
    use std::fmt::Write;
    out.push_str(tag);
    for f in fields {
        match *f {
            Field::Int(v) => {
                let _ = write!(out, " {v}");
            }
            Field::Real(v) => {
                let sign = if v < 0 { "-" } else { "" };
                let a = v.unsigned_abs();
                let _ = write!(out, " {sign}{}.{:03}", a / 1000, a % 1000);
            }
        }
    }
    let k = checksum(fields.iter().map(|f| f.value()));
    let _ = write!(out, " {k}");
    out.push('\n');
}

/// Reads a file line by line, checking form, tag, field count and checksum.
pub(crate) struct Reader<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
}

/// The fields of one verified line.
pub(crate) struct Line {
    pub(crate) number: usize,
    fields: Vec<Field>,
    next: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(text: &'a str) -> Result<Self, DecodeError> {
        if text.trim().is_empty() {
            return Err(DecodeError::Empty);
        }
        Ok(Reader {
            lines: text.lines().enumerate(),
        })
    }

    /// The tag of the next line, without consuming it.
    pub(crate) fn peek_tag(&self) -> Option<&'a str> {
        self.lines
            .clone()
            .next()
            .map(|(_, l)| l.split(' ').next().unwrap_or(""))
    }

    /// 1-based number of the next line.
    pub(crate) fn next_line_number(&self) -> usize {
        self.lines.clone().next().map_or(0, |(i, _)| i + 1)
    }

    /// Reads the next line, which must carry `tag` and the given field kinds
    /// (`'i'` INT, `'r'` REAL), followed by the checksum.
    pub(crate) fn line(&mut self, tag: &'static str, kinds: &str) -> Result<Line, DecodeError> {
        let (idx, raw) = self.lines.next().ok_or(DecodeError::Truncated)?;
        let number = idx + 1;
        let text = raw.strip_suffix('\r').unwrap_or(raw);
        if text.len() > MAX_LINE_LEN || !text.is_ascii() {
            return Err(DecodeError::LineForm { line: number });
        }
        let mut parts = text.split(' ');
        let found = parts.next().unwrap_or("");
        if found != tag {
            return Err(DecodeError::Tag {
                line: number,
                expected: tag,
                found: found.to_string(),
            });
        }
        let parts: Vec<&str> = parts.collect();
        if parts.len() != kinds.len() + 1 {
            return Err(DecodeError::FieldCount {
                line: number,
                expected: kinds.len() + 1,
                found: parts.len(),
            });
        }
        let mut fields = Vec::with_capacity(kinds.len());
        for (i, (kind, part)) in kinds.chars().zip(&parts).enumerate() {
            let f = if kind == 'r' {
                parse_real(part)
            } else {
                parse_int(part).map(Field::Int)
            };
            fields.push(f.ok_or_else(|| DecodeError::Number {
                line: number,
                field: i + 1,
                text: (*part).to_string(),
                kind: if kind == 'r' { "REAL" } else { "INT" },
            })?);
        }
        let last = parts.len() - 1;
        let found = parse_int(parts[last]).ok_or_else(|| DecodeError::Number {
            line: number,
            field: last + 1,
            text: parts[last].to_string(),
            kind: "INT",
        })?;
        let expected = checksum(fields.iter().map(|f| f.value()));
        if i64::from(found) != expected {
            return Err(DecodeError::Checksum {
                line: number,
                expected,
                found: i64::from(found),
            });
        }
        Ok(Line {
            number,
            fields,
            next: 0,
        })
    }

    /// Fails unless only blank lines remain.
    pub(crate) fn finish(mut self) -> Result<(), DecodeError> {
        if self.lines.any(|(_, l)| !l.trim().is_empty()) {
            return Err(DecodeError::TrailingData);
        }
        Ok(())
    }
}

impl Line {
    /// Next INT field.
    pub(crate) fn int(&mut self) -> i32 {
        let v = match self.fields.get(self.next) {
            Some(Field::Int(v)) | Some(Field::Real(v)) => *v,
            None => 0,
        };
        self.next += 1;
        v
    }

    /// Next REAL field as a float.
    pub(crate) fn real(&mut self) -> f64 {
        f64::from(self.int()) / 1000.0
    }

    /// A value error on this line.
    pub(crate) fn invalid(&self, what: impl Into<String>) -> DecodeError {
        DecodeError::Value {
            line: self.number,
            what: what.into(),
        }
    }
}

fn parse_int(s: &str) -> Option<i32> {
    let digits = s.strip_prefix('-').unwrap_or(s);
    if digits.is_empty() || digits.len() > 10 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

fn parse_real(s: &str) -> Option<Field> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, s),
    };
    let (whole, frac) = body.split_once('.')?;
    if whole.is_empty()
        || whole.len() > 4
        || frac.len() != 3
        || !whole.bytes().all(|b| b.is_ascii_digit())
        || !frac.bytes().all(|b| b.is_ascii_digit())
    {
        return None;
    }
    let v: i32 = whole.parse::<i32>().ok()? * 1000 + frac.parse::<i32>().ok()?;
    Some(Field::Real(if neg { -v } else { v }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksum_is_order_sensitive_and_small() {
        let a = checksum([1, 2, 3]);
        let b = checksum([3, 2, 1]);
        assert_ne!(a, b);
        assert!((0..MODULUS).contains(&checksum([-5, i64::from(i32::MAX), i64::from(i32::MIN)])));
    }

    #[test]
    fn reals_are_fixed_three_decimals() {
        let mut s = String::new();
        write_line(
            &mut s,
            "TST",
            &[
                real("x", -0.5).unwrap(),
                real("y", 1234.5678).unwrap(),
                Field::Int(-3),
            ],
        );
        assert!(s.starts_with("TST -0.500 1234.568 -3 "), "{s}");
        assert!(real("x", 10000.0).is_err());
        assert!(real("x", f64::NAN).is_err());
        assert_eq!(parse_real("12.34"), None);
        assert_eq!(parse_real("-0.001"), Some(Field::Real(-1)));
        assert_eq!(parse_real("1e3"), None);
        assert_eq!(parse_int("+1"), None);
    }
}
