//! The KRL syntax tree: files, routines, statements and expressions.
//!
//! Every statement carries its 1-based source line so that validation and
//! the simulator can name the line they refuse.

/// A parsed `.src` (or `.sub`) file: its routines in file order. The first
/// one is the module's global entry; the others are local to the file
/// unless declared `GLOBAL`.
#[derive(Debug, Clone, PartialEq)]
pub struct SrcFile {
    /// Routines in file order.
    pub routines: Vec<Routine>,
}

/// A parsed `.dat` file (`DEFDAT name [PUBLIC] … ENDDAT`).
#[derive(Debug, Clone, PartialEq)]
pub struct DatFile {
    /// The data list's name (must equal the module's).
    pub name: String,
    /// Declared `PUBLIC`.
    pub public: bool,
    /// Declarations and initialising assignments.
    pub items: Vec<Stmt>,
    /// Line of `DEFDAT`.
    pub line: u32,
}

/// `DEF` (procedure) or `DEFFCT type` (function).
#[derive(Debug, Clone, PartialEq)]
pub enum RoutineKind {
    /// `DEF name(...)`.
    Def,
    /// `DEFFCT type name(...)`, with its return type.
    DefFct(String),
}

/// A routine and its body.
#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    /// Procedure or function.
    pub kind: RoutineKind,
    /// Declared `GLOBAL`.
    pub global: bool,
    /// Its name as written.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
    /// Its statements.
    pub body: Vec<Stmt>,
    /// Line of `DEF`/`DEFFCT`.
    pub line: u32,
    /// Line of `END`/`ENDFCT`.
    pub end_line: u32,
}

/// A routine parameter `name:IN`, `name:OUT` or an array `name[]:OUT`.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Its name.
    pub name: String,
    /// `OUT` (by reference) rather than `IN` (by value).
    pub out: bool,
    /// Array dimensions written as `name[]` (1) or `name[,]` (2); 0 for a
    /// scalar. KRL passes arrays by reference.
    pub array_dims: usize,
}

/// One statement and its line.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// 1-based source line.
    pub line: u32,
    /// What it is.
    pub kind: StmtKind,
}

/// A declared variable: name, array dimensions and optional initial value.
#[derive(Debug, Clone, PartialEq)]
pub struct Declarator {
    /// Its name.
    pub name: String,
    /// Array dimensions (`[10]`, `[2,3]`); empty for a scalar.
    pub dims: Vec<Expr>,
    /// `= value`, if given.
    pub init: Option<Expr>,
}

/// Motion statements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// `PTP`.
    Ptp,
    /// `PTP_REL`.
    PtpRel,
    /// `LIN`.
    Lin,
    /// `LIN_REL`.
    LinRel,
    /// `CIRC`.
    Circ,
    /// `CIRC_REL`.
    CircRel,
}

/// Spline points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplinePointKind {
    /// `SPL`: a point the spline passes through.
    Spl,
    /// `SLIN`: a straight segment to the point.
    Slin,
    /// `SCIRC`: an arc through an auxiliary point.
    Scirc,
    /// `SPTP`: an axis-interpolated point (in a `PTP_SPLINE`).
    Sptp,
}

/// One point of a `SPLINE … ENDSPLINE` block.
#[derive(Debug, Clone, PartialEq)]
pub struct SplinePoint {
    /// Its kind.
    pub kind: SplinePointKind,
    /// The auxiliary point of an `SCIRC`.
    pub aux: Option<Expr>,
    /// The target.
    pub target: Expr,
    /// `WITH` assignments (e.g. `$VEL = {CP 0.2}`).
    pub with: Vec<(Expr, Expr)>,
    /// `CA angle` of an `SCIRC`.
    pub ca: Option<Expr>,
    /// `C_SPL` on the point.
    pub approx: Option<String>,
    /// Line of the point.
    pub line: u32,
}

/// What a statement is.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `DECL [GLOBAL] [CONST] type a, b[3], c = 1`.
    Decl {
        /// Declared `GLOBAL`.
        global: bool,
        /// The type name as written.
        ty: String,
        /// The variables.
        vars: Vec<Declarator>,
    },
    /// `STRUC name type f1, f2, type f3`.
    Struc {
        /// The type's name.
        name: String,
        /// Fields: (type, name, dims).
        fields: Vec<(String, String, Vec<Expr>)>,
    },
    /// `ENUM name a, b, c`.
    Enum {
        /// The type's name.
        name: String,
        /// Its values.
        values: Vec<String>,
    },
    /// `SIGNAL name $IN[1] [TO $IN[8]]`.
    Signal {
        /// The signal's name.
        name: String,
    },
    /// `EXT`/`EXTFCT` declaration of a routine in another module.
    Ext {
        /// The routine's name.
        name: String,
    },
    /// `target = value`.
    Assign {
        /// Variable, element or field.
        target: Expr,
        /// The value.
        value: Expr,
    },
    /// `name(args)`.
    Call {
        /// The routine.
        name: String,
        /// The arguments.
        args: Vec<Expr>,
    },
    /// `IF cond THEN … [ELSE …] ENDIF`.
    If {
        /// The condition.
        cond: Expr,
        /// Statements when true.
        then_body: Vec<Stmt>,
        /// Statements when false.
        else_body: Vec<Stmt>,
    },
    /// `WHILE cond … ENDWHILE`.
    While {
        /// The condition.
        cond: Expr,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `FOR var = from TO to [STEP step] … ENDFOR`.
    For {
        /// The counter.
        var: String,
        /// First value.
        from: Expr,
        /// Last value.
        to: Expr,
        /// Increment (a constant in KRL); 1 when absent.
        step: Option<Expr>,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `LOOP … ENDLOOP`.
    Loop {
        /// The body.
        body: Vec<Stmt>,
    },
    /// `REPEAT … UNTIL cond`.
    Repeat {
        /// The body.
        body: Vec<Stmt>,
        /// The end condition.
        until: Expr,
    },
    /// `SWITCH sel CASE v … DEFAULT … ENDSWITCH`.
    Switch {
        /// The selector.
        selector: Expr,
        /// Cases: their values and bodies.
        cases: Vec<(Vec<Expr>, Vec<Stmt>)>,
        /// The `DEFAULT` body.
        default: Option<Vec<Stmt>>,
    },
    /// `RETURN [value]`.
    Return(Option<Expr>),
    /// `EXIT` (leaves the innermost loop).
    Exit,
    /// `HALT`.
    Halt,
    /// `CONTINUE` (prevents an advance-run stop for the next line).
    Continue,
    /// `BRAKE [F]`.
    Brake,
    /// `RESUME`.
    Resume,
    /// `ON_ERROR_PROCEED` (KSS 8.3+).
    OnErrorProceed,
    /// `WAIT SEC t`.
    WaitSec(Expr),
    /// `WAIT FOR cond`.
    WaitFor(Expr),
    /// `CONFIRM m`: acknowledges the message with index `m` (KSS's
    /// message system; `CONFIRM 0` acknowledges all that may be).
    Confirm(Expr),
    /// `GOTO label` (KRL allows jumps within a routine's block).
    Goto(String),
    /// `label:` on a line of its own, the target of a `GOTO`.
    Label(String),
    /// `CHANNEL :name …` (a $CUSTOM.DAT-style channel declaration).
    Channel {
        /// The channel's name (without the `:`).
        name: String,
    },
    /// `IMPORT type name IS /R1/module..name`.
    Import {
        /// The local name.
        name: String,
    },
    /// `ANIN ON|OFF …` / `ANOUT ON|OFF …`: cyclic analog I/O.
    AnalogCyclic {
        /// `ANIN` rather than `ANOUT`.
        input: bool,
        /// `ON` rather than `OFF`.
        on: bool,
    },
    /// A spline motion outside a spline block (KSS 8.3+ single
    /// `SPTP`/`SLIN`/`SCIRC`, and their `_REL` forms), as inline forms
    /// write them: `SPTP XHOME WITH $VEL_AXIS[1] = SVEL_JOINT(100.0)`.
    SplineMotion {
        /// The motion (its `kind` is never `Spl`).
        point: SplinePoint,
        /// A `_REL` form.
        rel: bool,
        /// Reference of a `_REL` motion: `#BASE` or `#TOOL` (upper case,
        /// no `#`).
        rel_frame: Option<String>,
    },
    /// A motion statement.
    Motion {
        /// PTP, LIN, CIRC or a relative form.
        kind: MotionKind,
        /// CIRC's auxiliary point.
        aux: Option<Expr>,
        /// The target.
        target: Expr,
        /// `CA angle` of a CIRC.
        ca: Option<Expr>,
        /// Approximation: `C_DIS`, `C_PTP`, `C_VEL`, `C_ORI` (upper case).
        approx: Option<String>,
        /// Reference of a `_REL` motion: `#BASE` or `#TOOL` (upper case, no `#`).
        rel_frame: Option<String>,
    },
    /// `SPLINE … ENDSPLINE` or `PTP_SPLINE … ENDSPLINE`.
    Spline {
        /// `PTP_SPLINE` rather than `SPLINE`.
        ptp: bool,
        /// `WITH` assignments of the whole block.
        with: Vec<(Expr, Expr)>,
        /// `TRIGGER WHEN PATH …` statements inside the block.
        triggers: Vec<Stmt>,
        /// Its points.
        points: Vec<SplinePoint>,
        /// Approximation of the whole block (`C_SPL`).
        approx: Option<String>,
    },
    /// `INTERRUPT DECL n WHEN cond DO call`.
    InterruptDecl {
        /// Priority number.
        prio: Expr,
        /// The condition.
        when: Expr,
        /// The handler (a call statement).
        action: Box<Stmt>,
    },
    /// `INTERRUPT ON|OFF|ENABLE|DISABLE [n]`.
    InterruptSwitch {
        /// `ON`, `OFF`, `ENABLE` or `DISABLE`.
        action: String,
        /// The interrupt, or all.
        prio: Option<Expr>,
    },
    /// `TRIGGER WHEN DISTANCE|PATH = v [ONSTART] DELAY = d DO stmt [PRIO = p]`.
    Trigger {
        /// `PATH` (a distance in mm along the path) rather than `DISTANCE`
        /// (0 = the motion's start point, 1 = its end point).
        path: bool,
        /// The `DISTANCE`/`PATH` value.
        at: Expr,
        /// `ONSTART` (spline `PATH` triggers): `at` is measured from the
        /// start point of the motion (segment) instead of its end point.
        onstart: bool,
        /// `DELAY` in ms.
        delay: Expr,
        /// The action.
        action: Box<Stmt>,
    },
}

impl StmtKind {
    /// The statements nested in this one, block by block in source order:
    /// IF's two branches, a loop's body, each CASE and the DEFAULT, a
    /// spline block's triggers, an interrupt's or trigger's action (a
    /// block of one). Empty for a simple statement. For checks that walk a
    /// routine's every statement.
    pub fn blocks(&self) -> Vec<&[Stmt]> {
        match self {
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => vec![then_body, else_body],
            StmtKind::While { body, .. }
            | StmtKind::For { body, .. }
            | StmtKind::Loop { body }
            | StmtKind::Repeat { body, .. } => vec![body],
            StmtKind::Switch { cases, default, .. } => cases
                .iter()
                .map(|(_, b)| b.as_slice())
                .chain(default.as_deref())
                .collect(),
            StmtKind::Spline { triggers, .. } => vec![triggers],
            StmtKind::InterruptDecl { action, .. } | StmtKind::Trigger { action, .. } => {
                vec![std::slice::from_ref(&**action)]
            }
            _ => Vec::new(),
        }
    }
}

/// Binary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `==`
    Eq,
    /// `<>`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `AND`
    And,
    /// `OR`
    Or,
    /// `EXOR`
    Exor,
    /// `B_AND`
    BAnd,
    /// `B_OR`
    BOr,
    /// `B_EXOR`
    BExor,
    /// `:` the geometric operator (frame composition).
    Geo,
}

/// Unary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnOp {
    /// `-`
    Neg,
    /// `NOT`
    Not,
    /// `B_NOT`
    BNot,
}

/// An expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// An integer.
    Int(i64),
    /// A real.
    Real(f64),
    /// `TRUE`/`FALSE`.
    Bool(bool),
    /// A string literal.
    Str(String),
    /// `#NAME`.
    Enum(String),
    /// A variable (or system variable) by name.
    Var(String),
    /// `base[i, j]`; an empty index list is `name[]` (a whole array).
    Index(Box<Expr>, Vec<Expr>),
    /// `base.field`.
    Field(Box<Expr>, String),
    /// A function call.
    Call(String, Vec<Expr>),
    /// An argument left out of a call (`f(a,,3)`) or an index left out of
    /// an array reference (`X[1,]`, a row of a 2-dimensional array).
    Omitted,
    /// `{[TYPE:] NAME value, …}`.
    Struct {
        /// The optional type prefix.
        ty: Option<String>,
        /// Fields in order.
        fields: Vec<(String, Expr)>,
    },
    /// A unary operation.
    Unary(UnOp, Box<Expr>),
    /// A binary operation.
    Binary(BinOp, Box<Expr>, Box<Expr>),
}
