//! The front end's limits: how deep and how large a KRL program may be.
//!
//! KRL text comes from clients, so the front end bounds its work for every
//! input. The lexer is one pass over the text (linear work, no recursion).
//! The parser is a recursive descent parser; these limits bound both its
//! recursion and the depth of the syntax tree it builds, so that everything
//! that walks the tree afterwards (the simulator's subset check, its name
//! check and its interpreter, `Drop`, `Clone`, `Debug`) recurses only as
//! deep as they allow. A program beyond a limit is refused like a syntax
//! error: [`crate::SyntaxError`] with the line and a sentence that names the
//! limit, e.g. `line 3, column 12: expression nested deeper than 64 levels
//! (limit MAX_EXPR_DEPTH)`.
//!
//! The values leave real programs plenty of room (KSS programs rarely nest
//! an expression beyond ~20 levels or blocks beyond ~15), and the deepest
//! program within them parses on a 2 MiB thread stack in a debug build
//! (tested in `tests/limits.rs`).

/// Deepest nesting of one expression: parentheses, operators (each `+` of
/// `a + b + c` is one level, as the tree nests them), unary `-`/`NOT`,
/// indices, components, call arguments and structure values all count.
pub const MAX_EXPR_DEPTH: usize = 64;

/// Most operands and operators in the expressions of one statement (or
/// one spline point): the expression's size.
pub const MAX_EXPR_NODES: usize = 4096;

/// Deepest nesting of control blocks (`IF`/`ELSE`, `WHILE`, `FOR`, `LOOP`,
/// `REPEAT`, `SWITCH`/`CASE`) inside a routine.
pub const MAX_BLOCK_DEPTH: usize = 32;
