//! The operators and built-in functions on values: arithmetic with INT
//! overflow checks, comparisons, logic and bit operators, the geometric
//! operator `:` and `SIN` … `ABS`.

use kuka_krl::{BinOp, UnOp};

use super::values::{FRAME_FIELDS, Value, pose_of};

/// The built-in functions (degrees for the angles).
pub(super) const BUILTINS: [&str; 8] =
    ["SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN2", "SQRT", "ABS"];

pub(super) fn int_result(v: Option<i64>) -> Result<Value, String> {
    match v {
        Some(i) if i >= i64::from(i32::MIN) && i <= i64::from(i32::MAX) => Ok(Value::Int(i)),
        _ => Err("INT overflow".into()),
    }
}

fn real_result(r: f64) -> Result<Value, String> {
    if r.is_finite() {
        Ok(Value::Real(r))
    } else {
        Err("REAL overflow".into())
    }
}

pub(super) fn values_equal(l: &Value, r: &Value) -> Result<bool, String> {
    Ok(match (l, r) {
        (Value::Bool(a), Value::Bool(b)) => a == b,
        (Value::Enum(a), Value::Enum(b)) => a == b,
        (Value::Str(a), Value::Str(b)) => a == b,
        (Value::Int(a), Value::Int(b)) => a == b,
        (a, b) => match (a.num(), b.num()) {
            (Ok(x), Ok(y)) => x == y,
            _ => {
                return Err(format!(
                    "cannot compare {} with {}",
                    a.type_name(),
                    b.type_name()
                ));
            }
        },
    })
}

/// `-x`, `NOT x` and `B_NOT x`.
pub(super) fn unary(op: UnOp, v: Value) -> Result<Value, String> {
    match (op, v) {
        (UnOp::Neg, Value::Int(i)) => int_result(i.checked_neg()),
        (UnOp::Neg, Value::Real(r)) => Ok(Value::Real(-r)),
        (UnOp::Not, Value::Bool(b)) => Ok(Value::Bool(!b)),
        (UnOp::BNot, Value::Int(i)) => Ok(Value::Int(!i)),
        (op, v) => Err(format!("{op:?} cannot be applied to {}", v.type_name())),
    }
}

pub(super) fn binary(op: BinOp, l: Value, r: Value) -> Result<Value, String> {
    match op {
        BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div => {
            if let (Value::Int(a), Value::Int(b)) = (&l, &r) {
                let (a, b) = (*a, *b);
                return match op {
                    BinOp::Add => int_result(a.checked_add(b)),
                    BinOp::Sub => int_result(a.checked_sub(b)),
                    BinOp::Mul => int_result(a.checked_mul(b)),
                    _ if b == 0 => Err("division by zero".into()),
                    _ => int_result(a.checked_div(b)),
                };
            }
            let (a, b) = (l.num()?, r.num()?);
            match op {
                BinOp::Add => real_result(a + b),
                BinOp::Sub => real_result(a - b),
                BinOp::Mul => real_result(a * b),
                _ if b == 0.0 => Err("division by zero".into()),
                _ => real_result(a / b),
            }
        }
        BinOp::Eq => Ok(Value::Bool(values_equal(&l, &r)?)),
        BinOp::Ne => Ok(Value::Bool(!values_equal(&l, &r)?)),
        BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
            let (a, b) = (l.num()?, r.num()?);
            Ok(Value::Bool(match op {
                BinOp::Lt => a < b,
                BinOp::Le => a <= b,
                BinOp::Gt => a > b,
                _ => a >= b,
            }))
        }
        BinOp::And | BinOp::Or | BinOp::Exor => {
            let (a, b) = (l.bool()?, r.bool()?);
            Ok(Value::Bool(match op {
                BinOp::And => a && b,
                BinOp::Or => a || b,
                _ => a != b,
            }))
        }
        BinOp::BAnd | BinOp::BOr | BinOp::BExor => {
            let (a, b) = (l.int()?, r.int()?);
            Ok(Value::Int(match op {
                BinOp::BAnd => a & b,
                BinOp::BOr => a | b,
                _ => a ^ b,
            }))
        }
        BinOp::Geo => {
            // The result has the right operand's type (S, T, E1..E6 kept).
            let p = pose_of(&l)?.compose(&pose_of(&r)?);
            let Value::Struct(ty, mut fields) = r else {
                return Err("the geometric operator needs FRAME/POS values".into());
            };
            for (name, v) in FRAME_FIELDS.iter().zip(p.to_array()) {
                if let Some((_, f)) = fields.iter_mut().find(|(n, _)| n == name) {
                    *f = Value::Real(v);
                }
            }
            Ok(Value::Struct(ty, fields))
        }
    }
}

pub(super) fn builtin(name: &str, args: &[Value]) -> Result<Value, String> {
    let want = if name == "ATAN2" { 2 } else { 1 };
    if args.len() != want {
        return Err(format!(
            "{name} takes {want} argument(s), got {}",
            args.len()
        ));
    }
    if name == "ABS"
        && let Value::Int(i) = args[0]
    {
        return int_result(i.checked_abs());
    }
    let x = args[0].num().map_err(|e| format!("{name}: {e}"))?;
    let r = match name {
        "SIN" => x.to_radians().sin(),
        "COS" => x.to_radians().cos(),
        "TAN" => x.to_radians().tan(),
        "ASIN" | "ACOS" => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("{name}({x}): the argument must be within -1..1"));
            }
            if name == "ASIN" {
                x.asin().to_degrees()
            } else {
                x.acos().to_degrees()
            }
        }
        "ATAN2" => {
            let xx = args[1].num().map_err(|e| format!("{name}: {e}"))?;
            x.atan2(xx).to_degrees()
        }
        "SQRT" => {
            if x < 0.0 {
                return Err(format!("SQRT({x}) of a negative number"));
            }
            x.sqrt()
        }
        _ => x.abs(),
    };
    real_result(r)
}
