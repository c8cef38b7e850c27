//! The KUKAVARPROXY messages. All integers are big-endian.
//!
//! Request: `id u16, len u16, fn u8, name_len u16, name` and, to write,
//! `value_len u16, value`; `len` counts the bytes after itself; `fn` is 0
//! to read, 1 to write.
//!
//! Answer: `id u16, len u16, fn u8, value_len u16, value, 3 status bytes`;
//! the last status byte is 1 when the proxy read or wrote the variable and
//! 0 when it could not (an unknown variable, a value of the wrong type).
//! The value is the variable's text after the access. (Message layout as
//! the public OpenShowVar clients implement it: py_openshowvar,
//! rs-openshowvar.)

use thiserror::Error;

/// Read (0) or write (1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Function {
    /// Read a variable.
    Read,
    /// Write a variable.
    Write,
}

impl Function {
    fn byte(self) -> u8 {
        match self {
            Function::Read => 0,
            Function::Write => 1,
        }
    }
}

/// A request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    /// Message id, echoed in the answer.
    pub id: u16,
    /// Read or write.
    pub function: Function,
    /// The variable's name.
    pub name: String,
    /// The value to write (KRL text; `None` to read).
    pub value: Option<String>,
}

/// An answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    /// The request's id.
    pub id: u16,
    /// The request's function.
    pub function: Function,
    /// The variable's value as text.
    pub value: String,
    /// The proxy read or wrote the variable.
    pub ok: bool,
}

/// A message that cannot be encoded or decoded.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum CodecError {
    /// A name or value longer than a u16 length allows.
    #[error("{0} is too long for the protocol")]
    TooLong(&'static str),
    /// Fewer bytes than the header says.
    #[error("the message is cut short")]
    Truncated,
    /// A function byte other than 0 and 1.
    #[error("function {0} is neither read (0) nor write (1)")]
    Function(u8),
    /// Lengths that do not add up.
    #[error("the lengths in the message do not match")]
    Length,
}

fn put_str(out: &mut Vec<u8>, what: &'static str, s: &str) -> Result<(), CodecError> {
    let n = u16::try_from(s.len()).map_err(|_| CodecError::TooLong(what))?;
    out.extend_from_slice(&n.to_be_bytes());
    out.extend_from_slice(s.as_bytes());
    Ok(())
}

fn finish(id: u16, body: Vec<u8>) -> Result<Vec<u8>, CodecError> {
    let len = u16::try_from(body.len()).map_err(|_| CodecError::TooLong("the message"))?;
    let mut out = Vec::with_capacity(4 + body.len());
    out.extend_from_slice(&id.to_be_bytes());
    out.extend_from_slice(&len.to_be_bytes());
    out.extend_from_slice(&body);
    Ok(out)
}

impl Request {
    /// The request's bytes.
    pub fn encode(&self) -> Result<Vec<u8>, CodecError> {
        let mut body = vec![self.function.byte()];
        put_str(&mut body, "the name", &self.name)?;
        if let Some(v) = &self.value {
            put_str(&mut body, "the value", v)?;
        }
        finish(self.id, body)
    }

    /// Decodes the body of a request (the bytes after `id` and `len`).
    pub fn decode(id: u16, body: &[u8]) -> Result<Self, CodecError> {
        let (&f, rest) = body.split_first().ok_or(CodecError::Truncated)?;
        let function = match f {
            0 => Function::Read,
            1 => Function::Write,
            other => return Err(CodecError::Function(other)),
        };
        let (name, rest) = take_str(rest)?;
        let value = match function {
            Function::Read => None,
            Function::Write => {
                let (v, rest2) = take_str(rest)?;
                if !rest2.is_empty() {
                    return Err(CodecError::Length);
                }
                Some(v)
            }
        };
        if function == Function::Read && !rest.is_empty() {
            return Err(CodecError::Length);
        }
        Ok(Request {
            id,
            function,
            name,
            value,
        })
    }
}

impl Answer {
    /// The answer's bytes.
    pub fn encode(&self) -> Result<Vec<u8>, CodecError> {
        let mut body = vec![self.function.byte()];
        put_str(&mut body, "the value", &self.value)?;
        body.extend_from_slice(&[0, 1, u8::from(self.ok)]);
        finish(self.id, body)
    }

    /// Decodes the body of an answer (the bytes after `id` and `len`).
    pub fn decode(id: u16, body: &[u8]) -> Result<Self, CodecError> {
        let (&f, rest) = body.split_first().ok_or(CodecError::Truncated)?;
        let function = match f {
            0 => Function::Read,
            1 => Function::Write,
            other => return Err(CodecError::Function(other)),
        };
        let (value, rest) = take_str(rest)?;
        let [_, _, ok] = rest else {
            return Err(CodecError::Length);
        };
        Ok(Answer {
            id,
            function,
            value,
            ok: *ok == 1,
        })
    }
}

/// A u16-length-prefixed string (lossy UTF-8: a KRC's texts are ASCII or
/// Windows code pages) and the bytes after it.
fn take_str(b: &[u8]) -> Result<(String, &[u8]), CodecError> {
    let [h, l, rest @ ..] = b else {
        return Err(CodecError::Truncated);
    };
    let n = usize::from(u16::from_be_bytes([*h, *l]));
    if rest.len() < n {
        return Err(CodecError::Truncated);
    }
    let (s, rest) = rest.split_at(n);
    Ok((String::from_utf8_lossy(s).into_owned(), rest))
}

/// Splits a 4-byte header into `(id, len)`.
pub fn header(h: [u8; 4]) -> (u16, usize) {
    (
        u16::from_be_bytes([h[0], h[1]]),
        usize::from(u16::from_be_bytes([h[2], h[3]])),
    )
}
