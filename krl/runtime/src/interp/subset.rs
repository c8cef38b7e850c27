//! The check of which KRL the simulator accepts: [`check_subset`] walks
//! the whole program before anything runs; the subset is listed in the
//! [module documentation](super).

use kuka_krl::{BinOp, Expr, Program, RoutineKind, SplinePoint, SplinePointKind, Stmt, StmtKind};

use super::operators::BUILTINS;
use super::values::template;
use super::{SYS_READ_ONLY, SYS_WRITE, Unsupported, describe};
use crate::names::KRC_GLOBALS;

/// Refuses, before anything runs, every statement outside the subset.
///
/// Walks every routine of the `.src` (called or not) and every item of the
/// `.dat`; see the [module documentation](super) for the subset.
pub fn check_subset(program: &Program) -> Result<(), Unsupported> {
    check(program, None)
}

/// Refuses, before anything runs, every statement the KRC-like runtime
/// ([`run_hosted`](super::run_hosted)) cannot run: the subset of
/// [`check_subset`] plus what a hosted run adds (STRUC and ENUM types,
/// INTERRUPT, TRIGGER, BRAKE, RESUME, `ON_ERROR_PROCEED`, WAIT FOR on
/// system variables, `CWRITE`/`SREAD`/`SWRITE`/`PULSE`/`ERR_CLEAR` and the
/// controller's types), with `globals` the upper-case names of the
/// variables the controller provides (its system variables and the
/// globals of its `.dat` files, `$config.dat` included): a system variable
/// or `$config.dat` global outside them is refused here rather than
/// stopping the program with an error when it is reached.
pub fn check_hosted(
    program: &Program,
    globals: &std::collections::BTreeSet<String>,
) -> Result<(), Unsupported> {
    check(program, Some(globals))
}

/// The types a hosted run knows besides the built-in ones (the harness's).
const HOSTED_TYPES: [&str; 6] = [
    "STATE_T",
    "MODUS_T",
    "CMD_STAT",
    "MODE_OP",
    "PRO_STATE",
    "ERR_INFO",
];

/// The procedures a hosted run adds.
const HOSTED_CALLS: [&str; 5] = ["CWRITE", "SWRITE", "SREAD", "PULSE", "ERR_CLEAR"];

/// The `CWRITE($FCT_CALL, …)` functions a hosted run has (the harness's).
const FILE_FUNCTIONS: [&str; 6] = [
    "krl_fopen",
    "krl_fgets",
    "krl_fwriteln",
    "krl_fputs",
    "krl_fclose",
    "krl_fclose_all",
];

/// The functions a hosted run adds (`kinematic_function`).
const HOSTED_FUNCTIONS: [&str; 2] = ["INVERSE", "FORWARD"];

fn check(
    program: &Program,
    hosted: Option<&std::collections::BTreeSet<String>>,
) -> Result<(), Unsupported> {
    let mut prios = Vec::new();
    for r in &program.src.routines {
        stopm_prios(&r.body, &mut prios);
    }
    let routines: std::collections::HashSet<String> = program
        .src
        .routines
        .iter()
        .map(|r| r.name.to_ascii_uppercase())
        .collect();
    let mut types = std::collections::HashSet::new();
    if hosted.is_some() {
        types.extend(HOSTED_TYPES.iter().map(|t| t.to_string()));
        let dat_items = program.dat.iter().flat_map(|d| d.items.iter());
        let bodies = program.src.routines.iter().flat_map(|r| r.body.iter());
        for s in dat_items.chain(bodies) {
            if let StmtKind::Struc { name, .. } | StmtKind::Enum { name, .. } = &s.kind {
                types.insert(name.to_ascii_uppercase());
            }
        }
    }
    if let Some(dat) = &program.dat {
        let c = Checker {
            routines: routines.clone(),
            in_dat: true,
            stopm_prios: Vec::new(),
            hosted,
            types: types.clone(),
        };
        c.block(&dat.items)?;
    }
    let c = Checker {
        routines,
        in_dat: false,
        stopm_prios: prios,
        hosted,
        types,
    };
    for r in &program.src.routines {
        if let RoutineKind::DefFct(ty) = &r.kind
            && template(ty).is_none()
            && !c.user_type(ty)
        {
            return c.refuse(r.line, format!("a function returning {ty}"));
        }
        c.block(&r.body)?;
    }
    Ok(())
}

struct Checker<'g> {
    /// Upper-case names of the `.src` routines (a set: a file of many
    /// routines and calls must not cost quadratic time).
    routines: std::collections::HashSet<String>,
    in_dat: bool,
    /// Priorities of the standard stop-message interrupt (INI fold).
    stopm_prios: Vec<i64>,
    /// The KRC-like runtime's check ([`check_hosted`]): the controller's
    /// variables.
    hosted: Option<&'g std::collections::BTreeSet<String>>,
    /// Hosted: the STRUC and ENUM types of the program and the harness's
    /// (upper-case).
    types: std::collections::HashSet<String>,
}

/// `INTERRUPT DECL n WHEN $STOPMESS == TRUE DO IR_STOPM()`, the standard
/// stop-message interrupt of the INI fold: accepted and ignored (the
/// simulated controller handles its own stops).
fn is_stopm_decl(k: &StmtKind) -> bool {
    let StmtKind::InterruptDecl { prio, when, action } = k else {
        return false;
    };
    matches!(prio, Expr::Int(_))
        && matches!(&action.kind, StmtKind::Call { name, args } if name.eq_ignore_ascii_case("IR_STOPM") && args.is_empty())
        && matches!(when, Expr::Binary(BinOp::Eq, a, b)
            if matches!(&**a, Expr::Var(v) if v.eq_ignore_ascii_case("$STOPMESS"))
                && **b == Expr::Bool(true))
}

/// Priorities of the stop-message interrupts declared anywhere in `body`.
fn stopm_prios(body: &[Stmt], out: &mut Vec<i64>) {
    for s in body {
        match &s.kind {
            StmtKind::InterruptDecl {
                prio: Expr::Int(p), ..
            } if is_stopm_decl(&s.kind) => out.push(*p),
            kind => {
                for b in kind.blocks() {
                    stopm_prios(b, out);
                }
            }
        }
    }
}

fn root_name(e: &Expr) -> Option<&str> {
    match e {
        Expr::Var(n) => Some(n),
        Expr::Index(b, _) | Expr::Field(b, _) => root_name(b),
        _ => None,
    }
}

fn mentions_system(e: &Expr) -> bool {
    match e {
        Expr::Var(n) => n.starts_with('$'),
        Expr::Index(b, i) => mentions_system(b) || i.iter().any(mentions_system),
        Expr::Field(b, _) | Expr::Unary(_, b) => mentions_system(b),
        Expr::Call(_, a) => a.iter().any(mentions_system),
        Expr::Struct { fields, .. } => fields.iter().any(|(_, v)| mentions_system(v)),
        Expr::Binary(_, a, b) => mentions_system(a) || mentions_system(b),
        _ => false,
    }
}

impl Checker<'_> {
    fn is_routine(&self, name: &str) -> bool {
        self.routines.contains(&name.to_ascii_uppercase())
    }

    /// Hosted: a STRUC/ENUM type of the program or of the harness.
    fn user_type(&self, ty: &str) -> bool {
        self.hosted.is_some() && self.types.contains(&ty.to_ascii_uppercase())
    }

    /// Hosted: a statement only the KRC-like runtime runs; its
    /// expressions are checked.
    fn hosted_only(&self, s: &Stmt) -> Option<Result<(), Unsupported>> {
        self.hosted?;
        let l = s.line;
        Some(match &s.kind {
            StmtKind::Struc { .. } | StmtKind::Enum { .. } => Ok(()),
            StmtKind::Brake | StmtKind::Resume | StmtKind::OnErrorProceed => Ok(()),
            StmtKind::WaitFor(e) => self.expr(e, l),
            StmtKind::InterruptDecl { prio, when, action } => self
                .expr(prio, l)
                .and_then(|()| self.expr(when, l))
                .and_then(|()| self.stmt(action)),
            StmtKind::InterruptSwitch { prio, .. } => self.exprs(prio, l),
            StmtKind::Trigger {
                at, delay, action, ..
            } => self
                .expr(at, l)
                .and_then(|()| self.expr(delay, l))
                .and_then(|()| self.stmt(action)),
            StmtKind::Call { name, args }
                if HOSTED_CALLS.iter().any(|c| name.eq_ignore_ascii_case(c)) =>
            {
                // The file functions the runtime has (a name given as a
                // literal; one computed at run time is met when it runs).
                if name.eq_ignore_ascii_case("CWRITE")
                    && let [Expr::Var(ch), _, _, Expr::Str(func), ..] = args.as_slice()
                    && ch.eq_ignore_ascii_case("$FCT_CALL")
                    && !FILE_FUNCTIONS.iter().any(|f| func.eq_ignore_ascii_case(f))
                {
                    return Some(self.refuse(
                        l,
                        format!(
                            "the file function {func} (the KRC-like runtime has {})",
                            FILE_FUNCTIONS.join(", ")
                        ),
                    ));
                }
                // CWRITE's channel and SREAD/SWRITE's state are variables
                // of the controller ($FCT_CALL, $CMD) or the program.
                self.exprs(args, l)
            }
            _ => return None,
        })
    }

    fn refuse(&self, line: u32, what: impl Into<String>) -> Result<(), Unsupported> {
        let mut what = what.into();
        if self.in_dat {
            what.push_str(" (in the .dat file)");
        }
        Err(Unsupported { line, what })
    }

    fn block(&self, b: &[Stmt]) -> Result<(), Unsupported> {
        b.iter().try_for_each(|s| self.stmt(s))
    }

    fn exprs<'e>(&self, es: impl IntoIterator<Item = &'e Expr>, l: u32) -> Result<(), Unsupported> {
        es.into_iter().try_for_each(|e| self.expr(e, l))
    }

    fn stmt(&self, s: &Stmt) -> Result<(), Unsupported> {
        let l = s.line;
        if let Some(r) = self.hosted_only(s) {
            return r;
        }
        match &s.kind {
            StmtKind::Decl { ty, vars, .. } => {
                let known = template(ty).is_some() || self.user_type(ty);
                if !known && !self.in_dat {
                    return self.refuse(l, format!("the type {ty}"));
                }
                for v in vars {
                    if v.dims.len() > 2 {
                        return self.refuse(l, "an array with more than 2 dimensions");
                    }
                    if known {
                        self.exprs(&v.dims, l)?;
                        self.exprs(&v.init, l)?;
                    }
                }
                Ok(())
            }
            StmtKind::Struc { .. } => self.refuse(l, "STRUC (user-defined structure types)"),
            StmtKind::Enum { .. } => self.refuse(l, "ENUM (user-defined enumeration types)"),
            StmtKind::Signal { .. } => self.refuse(l, "SIGNAL (I/O signals)"),
            StmtKind::Ext { name } if name.eq_ignore_ascii_case("BAS") => Ok(()),
            StmtKind::Ext { name } => self.refuse(
                l,
                format!("EXT {name} (a routine of another module; the call {name})"),
            ),
            StmtKind::Assign { target, value } => {
                self.lvalue(target, l)?;
                self.expr(value, l)
            }
            StmtKind::Call { name, args } => {
                if name.eq_ignore_ascii_case("BAS") {
                    return match args.first() {
                        Some(Expr::Enum(c)) if c.eq_ignore_ascii_case("INITMOV") => {
                            self.exprs(args, l)
                        }
                        Some(Expr::Enum(c)) => self
                            .refuse(l, format!("BAS(#{c}) (only BAS(#INITMOV, …) is supported)")),
                        _ => self.refuse(l, "BAS without a #command"),
                    };
                }
                if !self.is_routine(name) {
                    return self.refuse(l, format!("the call {name}"));
                }
                self.exprs(args, l)
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.expr(cond, l)?;
                self.block(then_body)?;
                self.block(else_body)
            }
            StmtKind::While { cond, body } => {
                self.expr(cond, l)?;
                self.block(body)
            }
            StmtKind::For {
                from,
                to,
                step,
                body,
                ..
            } => {
                self.exprs([from, to], l)?;
                self.exprs(step, l)?;
                self.block(body)
            }
            StmtKind::Loop { body } => self.block(body),
            StmtKind::Repeat { body, until } => {
                self.block(body)?;
                self.expr(until, l)
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => {
                self.expr(selector, l)?;
                for (vals, body) in cases {
                    self.exprs(vals, l)?;
                    self.block(body)?;
                }
                if let Some(d) = default {
                    self.block(d)?;
                }
                Ok(())
            }
            StmtKind::Return(e) => self.exprs(e, l),
            StmtKind::Exit | StmtKind::Continue => Ok(()),
            StmtKind::Halt => self.refuse(l, "HALT"),
            StmtKind::Brake => self.refuse(l, "BRAKE"),
            StmtKind::Resume => self.refuse(l, "RESUME"),
            StmtKind::OnErrorProceed => self.refuse(l, "ON_ERROR_PROCEED"),
            StmtKind::WaitSec(e) => self.expr(e, l),
            StmtKind::WaitFor(e) => {
                if mentions_system(e) {
                    return self
                        .refuse(l, "WAIT FOR with a condition that depends on the robot/IO");
                }
                self.expr(e, l)
            }
            StmtKind::Motion {
                aux,
                target,
                ca,
                rel_frame,
                ..
            } => {
                if ca.is_some() {
                    return self.refuse(l, "CIRC with CA (circular angle)");
                }
                if rel_frame.as_deref() == Some("TOOL") {
                    return self.refuse(l, "a relative motion in #TOOL coordinates");
                }
                self.exprs(aux, l)?;
                self.expr(target, l)
            }
            StmtKind::Spline {
                ptp,
                points,
                with,
                triggers,
                ..
            } => {
                if !with.is_empty() {
                    return self.refuse(l, "WITH after SPLINE (put WITH on the points)");
                }
                // The KRC-like runtime plays a spline block's TRIGGER WHEN
                // PATH (at the point after it); the step list has no
                // trigger actions, as for a TRIGGER anywhere else.
                if let Some(t) = triggers.first()
                    && (self.hosted.is_none()
                        || triggers
                            .iter()
                            .any(|t| matches!(t.kind, StmtKind::Trigger { path: false, .. })))
                {
                    let what = if matches!(t.kind, StmtKind::Trigger { path: false, .. }) {
                        "TRIGGER WHEN DISTANCE in a spline block (KRL allows only PATH there)"
                    } else {
                        "TRIGGER in a spline block"
                    };
                    return self.refuse(t.line, what);
                }
                for t in triggers {
                    self.stmt(t)?;
                }
                for p in points {
                    let is_sptp = p.kind == SplinePointKind::Sptp;
                    if *ptp && !is_sptp {
                        return self.refuse(
                            p.line,
                            format!(
                                "{} inside PTP_SPLINE",
                                format!("{:?}", p.kind).to_uppercase()
                            ),
                        );
                    }
                    if !*ptp && is_sptp {
                        return self.refuse(p.line, "SPTP inside a SPLINE block");
                    }
                    self.spline_point(p)?;
                }
                Ok(())
            }
            StmtKind::SplineMotion { rel: true, .. } => self.refuse(
                l,
                "a relative spline motion (SPTP_REL, SLIN_REL, SCIRC_REL)",
            ),
            StmtKind::SplineMotion { point, .. } => {
                if point.approx.as_deref().is_some_and(|a| a != "C_SPL") {
                    return self.refuse(l, "a single spline motion approximated other than C_SPL");
                }
                self.spline_point(point)
            }
            StmtKind::Goto(_) | StmtKind::Label(_) => self.refuse(l, "GOTO and labels"),
            StmtKind::Confirm(_) => self.refuse(l, "CONFIRM (the message system)"),
            StmtKind::Channel { .. } => self.refuse(l, "CHANNEL"),
            StmtKind::Import { .. } => self.refuse(l, "IMPORT"),
            StmtKind::AnalogCyclic { .. } => self.refuse(l, "ANIN/ANOUT"),
            StmtKind::InterruptDecl { prio, .. } if is_stopm_decl(&s.kind) => self.expr(prio, l),
            StmtKind::InterruptSwitch {
                prio: Some(Expr::Int(p)),
                ..
            } if self.stopm_prios.contains(p) => Ok(()),
            StmtKind::InterruptDecl { .. } | StmtKind::InterruptSwitch { .. } => {
                self.refuse(l, "INTERRUPT")
            }
            StmtKind::Trigger { .. } => self.refuse(l, "TRIGGER"),
        }
    }

    /// A spline point's CA, `WITH` list and points.
    fn spline_point(&self, p: &SplinePoint) -> Result<(), Unsupported> {
        let pl = p.line;
        if p.ca.is_some() {
            return self.refuse(pl, "SCIRC with CA (circular angle)");
        }
        for (t, v) in &p.with {
            let root = root_name(t).unwrap_or("").to_ascii_uppercase();
            if !(root == "$VEL" || root == "$ACC") {
                return self.refuse(
                    pl,
                    format!(
                        "WITH {} (only $VEL and $ACC are supported in WITH)",
                        describe(t)
                    ),
                );
            }
            self.lvalue(t, pl)?;
            self.expr(v, pl)?;
        }
        self.exprs(&p.aux, pl)?;
        self.expr(&p.target, pl)
    }

    /// A `$config.dat` global other than `XHOME`: the simulator has none;
    /// hosted: one the controller does not declare.
    fn krc_global(&self, upper: &str, l: u32) -> Result<(), Unsupported> {
        if let Some(globals) = self.hosted {
            if KRC_GLOBALS.contains(&upper) && !globals.contains(upper) {
                return self.refuse(
                    l,
                    format!(
                        "the controller global {upper} (from $config.dat; the KRC-like runtime declares only {})",
                        KRC_GLOBALS
                            .iter()
                            .filter(|g| globals.contains(**g))
                            .copied()
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                );
            }
            return Ok(());
        }
        if upper != "XHOME" && KRC_GLOBALS.contains(&upper) {
            return self.refuse(
                l,
                format!(
                    "the controller global {upper} (from $config.dat; the simulator has only XHOME)"
                ),
            );
        }
        Ok(())
    }

    /// Hosted: a system variable the controller has (`$FCT_CALL` and
    /// `$CMD` are CWRITE's channels).
    fn hosted_system(&self, upper: &str) -> bool {
        self.hosted
            .is_some_and(|g| g.contains(upper) || upper == "$FCT_CALL" || upper == "$CMD")
    }

    fn lvalue(&self, e: &Expr, l: u32) -> Result<(), Unsupported> {
        if let Some(root) = root_name(e) {
            let up = root.to_ascii_uppercase();
            self.krc_global(&up, l)?;
            if up.starts_with('$') {
                // A KRC program sets the override ($OV_PRO) itself.
                if SYS_READ_ONLY.contains(&up.as_str())
                    && !(self.hosted.is_some() && up == "$OV_PRO")
                {
                    return self.refuse(l, format!("assigning {up}"));
                }
                if !SYS_WRITE.contains(&up.as_str()) && !self.hosted_system(&up) {
                    return self.refuse(l, format!("the system variable {up}"));
                }
            }
        }
        match e {
            Expr::Var(_) => Ok(()),
            Expr::Index(b, i) => {
                self.lvalue(b, l)?;
                self.exprs(i, l)
            }
            Expr::Field(b, _) => self.lvalue(b, l),
            _ => self.expr(e, l),
        }
    }

    fn expr(&self, e: &Expr, l: u32) -> Result<(), Unsupported> {
        match e {
            Expr::Var(n) => {
                let up = n.to_ascii_uppercase();
                if up.starts_with('$')
                    && !SYS_WRITE.contains(&up.as_str())
                    && !SYS_READ_ONLY.contains(&up.as_str())
                    && !self.hosted_system(&up)
                {
                    return self.refuse(l, format!("the system variable {up}"));
                }
                self.krc_global(&up, l)
            }
            Expr::Index(b, i) => {
                self.expr(b, l)?;
                self.exprs(i, l)
            }
            Expr::Field(b, _) | Expr::Unary(_, b) => self.expr(b, l),
            Expr::Call(n, args) => {
                let up = n.to_ascii_uppercase();
                let hosted = self.hosted.is_some() && HOSTED_FUNCTIONS.contains(&up.as_str());
                if !BUILTINS.contains(&up.as_str()) && !self.routines.contains(&up) && !hosted {
                    return self.refuse(l, format!("the call {n}"));
                }
                self.exprs(args, l)
            }
            Expr::Struct { fields, .. } => self.exprs(fields.iter().map(|(_, v)| v), l),
            Expr::Binary(_, a, b) => {
                self.expr(a, l)?;
                self.expr(b, l)
            }
            Expr::Int(_) | Expr::Real(_) | Expr::Bool(_) | Expr::Str(_) | Expr::Enum(_) => Ok(()),
            Expr::Omitted => self.refuse(l, "a left-out argument or array index"),
        }
    }
}
