//! A compile-time check the KRC does and the simulator needs too: every
//! variable a program uses is declared (in its routine, as a parameter,
//! in the program's `.dat`, or predefined: [`KRC_GLOBALS`], the user-level
//! globals every KSS 8.x controller declares in `$config.dat`. The service
//! runs this check only when it drives a simulator (a real controller
//! may have more globals, from its own `$config.dat` and other modules).
//! Of those globals the native simulator knows only `XHOME`: the subset
//! check refuses the others as unsupported, not as undeclared.

use std::collections::HashSet;

use kuka_krl::{Expr, Program, Routine, SplinePoint, Stmt, StmtKind};

/// A variable used but not declared.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: the variable {name} is not declared (DECL it in the routine or the .dat)")]
pub struct Undeclared {
    /// Where it is used first.
    pub line: u32,
    /// Its name.
    pub name: String,
}

/// Globals every KSS 8.x controller declares in `$config.dat` (tool, base
/// and load tables and their names, the motion parameter records the
/// inline forms use, the home positions), upper case. Programs use them
/// without declaring them.
pub const KRC_GLOBALS: [&str; 24] = [
    "XHOME",
    "XHOME1",
    "XHOME2",
    "XHOME3",
    "XHOME4",
    "XHOME5",
    "FHOME",
    "TOOL_DATA",
    "BASE_DATA",
    "LOAD_DATA",
    "TOOL_NAME",
    "BASE_NAME",
    "TOOL_TYPE",
    "BASE_TYPE",
    "MACHINE_DEF",
    "MACHINE_TOOL_DAT",
    "MACHINE_FRAME_DAT",
    "PDAT_ACT",
    "FDAT_ACT",
    "LDAT_ACT",
    "PDEFAULT",
    "LDEFAULT",
    "DEF_FLT_PTP",
    "DEF_FLT_CP",
];

/// Checks every routine of `program`.
pub fn check_names(program: &Program) -> Result<(), Undeclared> {
    let mut globals: HashSet<String> = KRC_GLOBALS.iter().map(|s| s.to_string()).collect();
    if let Some(dat) = &program.dat {
        declared(&dat.items, &mut globals);
    }
    // `DECL GLOBAL` inside a routine is visible everywhere.
    for r in &program.src.routines {
        global_decls(&r.body, &mut globals);
    }
    for r in &program.src.routines {
        check_routine(r, &globals)?;
    }
    Ok(())
}

fn declared(stmts: &[Stmt], out: &mut HashSet<String>) {
    for s in stmts {
        if let StmtKind::Decl { vars, .. } = &s.kind {
            out.extend(vars.iter().map(|v| v.name.to_ascii_uppercase()));
        }
        if let StmtKind::Signal { name } = &s.kind {
            out.insert(name.to_ascii_uppercase());
        }
    }
}

fn global_decls(stmts: &[Stmt], out: &mut HashSet<String>) {
    for s in stmts {
        if let StmtKind::Decl {
            global: true, vars, ..
        } = &s.kind
        {
            out.extend(vars.iter().map(|v| v.name.to_ascii_uppercase()));
        }
    }
}

/// The names a routine sees: the globals (shared by all routines, not
/// copied per routine: a file of many routines and globals must not cost
/// quadratic time) and its own.
struct Scope<'g> {
    globals: &'g HashSet<String>,
    locals: HashSet<String>,
}

impl Scope<'_> {
    fn contains(&self, upper: &str) -> bool {
        self.locals.contains(upper) || self.globals.contains(upper)
    }
}

fn check_routine(r: &Routine, globals: &HashSet<String>) -> Result<(), Undeclared> {
    let mut locals: HashSet<String> = r
        .params
        .iter()
        .map(|p| p.name.to_ascii_uppercase())
        .collect();
    collect_decls(&r.body, &mut locals);
    walk_block(&r.body, &Scope { globals, locals })
}

/// Declarations anywhere in the body (KRL wants them at the top; the
/// parser already keeps their order, this check does not care).
fn collect_decls(stmts: &[Stmt], out: &mut HashSet<String>) {
    declared(stmts, out);
}

fn walk_block(stmts: &[Stmt], scope: &Scope<'_>) -> Result<(), Undeclared> {
    stmts.iter().try_for_each(|s| walk_stmt(s, scope))
}

fn walk_stmt(s: &Stmt, scope: &Scope<'_>) -> Result<(), Undeclared> {
    let line = s.line;
    let e = |x: &Expr| walk_expr(x, line, scope);
    match &s.kind {
        StmtKind::Decl { vars, .. } => {
            for v in vars {
                v.dims.iter().try_for_each(e)?;
                if let Some(i) = &v.init {
                    e(i)?;
                }
            }
            Ok(())
        }
        StmtKind::Assign { target, value } => {
            e(target)?;
            e(value)
        }
        StmtKind::Call { args, .. } => args.iter().try_for_each(e),
        StmtKind::If {
            cond,
            then_body,
            else_body,
        } => {
            e(cond)?;
            walk_block(then_body, scope)?;
            walk_block(else_body, scope)
        }
        StmtKind::While { cond, body } => {
            e(cond)?;
            walk_block(body, scope)
        }
        StmtKind::Repeat { body, until } => {
            walk_block(body, scope)?;
            e(until)
        }
        StmtKind::For {
            var,
            from,
            to,
            step,
            body,
        } => {
            e(&Expr::Var(var.clone()))?;
            e(from)?;
            e(to)?;
            if let Some(st) = step {
                e(st)?;
            }
            walk_block(body, scope)
        }
        StmtKind::Loop { body } => walk_block(body, scope),
        StmtKind::Switch {
            selector,
            cases,
            default,
        } => {
            e(selector)?;
            for (values, body) in cases {
                values.iter().try_for_each(e)?;
                walk_block(body, scope)?;
            }
            if let Some(d) = default {
                walk_block(d, scope)?;
            }
            Ok(())
        }
        StmtKind::Return(Some(v)) | StmtKind::WaitSec(v) | StmtKind::WaitFor(v) => e(v),
        StmtKind::Motion {
            aux, target, ca, ..
        } => {
            aux.iter().chain(ca.iter()).try_for_each(e)?;
            e(target)
        }
        StmtKind::Spline {
            points,
            with,
            triggers,
            ..
        } => {
            for (t, v) in with {
                e(t)?;
                e(v)?;
            }
            walk_block(triggers, scope)?;
            points.iter().try_for_each(|p| walk_point(p, scope))
        }
        StmtKind::InterruptDecl { when, action, .. } => {
            e(when)?;
            walk_stmt(action, scope)
        }
        StmtKind::SplineMotion { point, .. } => walk_point(point, scope),
        StmtKind::Trigger {
            at, delay, action, ..
        } => {
            e(at)?;
            e(delay)?;
            walk_stmt(action, scope)
        }
        _ => Ok(()),
    }
}

/// A spline point's (or single spline motion's) targets and `WITH` list.
fn walk_point(p: &SplinePoint, scope: &Scope<'_>) -> Result<(), Undeclared> {
    let pe = |x: &Expr| walk_expr(x, p.line, scope);
    p.aux.iter().chain(p.ca.iter()).try_for_each(pe)?;
    pe(&p.target)?;
    p.with.iter().try_for_each(|(t, v)| {
        pe(t)?;
        pe(v)
    })
}

fn walk_expr(x: &Expr, line: u32, scope: &Scope<'_>) -> Result<(), Undeclared> {
    let rec = |y: &Expr| walk_expr(y, line, scope);
    match x {
        Expr::Var(name) => {
            if name.starts_with('$') || scope.contains(&name.to_ascii_uppercase()) {
                Ok(())
            } else {
                Err(Undeclared {
                    line,
                    name: name.clone(),
                })
            }
        }
        Expr::Index(base, idx) => {
            rec(base)?;
            idx.iter().try_for_each(rec)
        }
        Expr::Field(base, _) => rec(base),
        Expr::Call(_, args) => args.iter().try_for_each(rec),
        Expr::Struct { fields, .. } => fields.iter().try_for_each(|(_, v)| rec(v)),
        Expr::Unary(_, a) => rec(a),
        Expr::Binary(_, a, b) => {
            rec(a)?;
            rec(b)
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(src: &str, dat: Option<&str>) -> Result<(), Undeclared> {
        check_names(&Program::parse(src, dat, None).expect("parses"))
    }

    #[test]
    fn undeclared_variables_are_found_with_their_line() {
        let e = check("DEF a()\n  DECL INT i\n  PTP p1\nEND\n", None).expect_err("p1");
        assert_eq!((e.line, e.name.as_str()), (3, "p1"));
        let e = check("DEF a()\n  FOR k = 1 TO 3\n  ENDFOR\nEND\n", None).expect_err("k");
        assert_eq!(e.line, 2);
        let e = check(
            "DEF a()\n  SPLINE\n    SPL {X 1, Y q}\n  ENDSPLINE\nEND\n",
            None,
        )
        .expect_err("q");
        assert_eq!((e.line, e.name.as_str()), (3, "q"));
    }

    #[test]
    fn declarations_parameters_dat_and_predefined_names_count() {
        check(
            "DEF a()\n  DECL E6POS p\n  p = {X 1}\n  p.X = p.X + amp\n  PTP XHOME\n  b(p.X)\n  $VEL.CP = 0.1\nEND\nDEF b(v:IN)\n  DECL REAL v\n  v = v * 2\nEND\n",
            Some("DEFDAT a\n  DECL REAL amp = 1.0\nENDDAT\n"),
        )
        .expect("all declared");
    }
}
