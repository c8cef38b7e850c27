//! KRL values: the typed [`Value`] a variable holds, the templates of the
//! predefined types, the conversions of an assignment and the paths into
//! structure components and array elements.

use kuka_kinematics::{Axes, Pose};

/// The components of a FRAME (and the first six of a POS/E6POS).
pub(super) const FRAME_FIELDS: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
/// The axes of an AXIS/E6AXIS.
pub(super) const AXIS_FIELDS: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];
/// The external axes of an E6POS/E6AXIS.
pub(super) const EXT_FIELDS: [&str; 6] = ["E1", "E2", "E3", "E4", "E5", "E6"];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
    Int,
    Real,
    Bool,
    Char,
    /// A variable of an enumeration type (its values are not checked).
    Enum,
}

/// A KRL value. Declared variables hold typed templates: `Unset` scalars
/// are declared but not yet assigned.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Value {
    Unset(Scalar),
    Int(i64),
    Real(f64),
    Bool(bool),
    Char(u8),
    Str(String),
    Enum(String),
    /// Type name (upper case, may be empty for a literal) and components.
    Struct(String, Vec<(String, Value)>),
    /// Dimensions and elements (row-major).
    Array(Vec<usize>, Vec<Value>),
    /// A `.dat` variable of a type outside the subset.
    Opaque(String),
}

impl Value {
    pub(super) fn type_name(&self) -> String {
        match self {
            Value::Unset(Scalar::Int) | Value::Int(_) => "INT".into(),
            Value::Unset(Scalar::Real) | Value::Real(_) => "REAL".into(),
            Value::Unset(Scalar::Bool) | Value::Bool(_) => "BOOL".into(),
            Value::Unset(Scalar::Char) | Value::Char(_) => "CHAR".into(),
            Value::Unset(Scalar::Enum) => "an ENUM".into(),
            Value::Str(_) => "a string".into(),
            Value::Enum(e) => format!("#{e}"),
            Value::Struct(t, _) if t.is_empty() => "a structure value".into(),
            Value::Struct(t, _) => t.clone(),
            Value::Array(..) => "an array".into(),
            Value::Opaque(t) => t.clone(),
        }
    }

    pub(super) fn scalar_kind(&self) -> Option<Scalar> {
        match self {
            Value::Unset(s) => Some(*s),
            Value::Int(_) => Some(Scalar::Int),
            Value::Real(_) => Some(Scalar::Real),
            Value::Bool(_) => Some(Scalar::Bool),
            Value::Char(_) => Some(Scalar::Char),
            _ => None,
        }
    }

    pub(super) fn num(&self) -> Result<f64, String> {
        match self {
            Value::Int(i) => Ok(*i as f64),
            Value::Real(r) => Ok(*r),
            Value::Char(c) => Ok(f64::from(*c)),
            v => Err(format!("expected a number, found {}", v.type_name())),
        }
    }

    pub(super) fn int(&self) -> Result<i64, String> {
        match self {
            Value::Int(i) => Ok(*i),
            Value::Char(c) => Ok(i64::from(*c)),
            v => Err(format!("expected an INT, found {}", v.type_name())),
        }
    }

    pub(super) fn bool(&self) -> Result<bool, String> {
        match self {
            Value::Bool(b) => Ok(*b),
            v => Err(format!("expected a BOOL, found {}", v.type_name())),
        }
    }
}

/// The typed, unset value of a declared type (upper-case name).
pub(super) fn template(ty: &str) -> Option<Value> {
    let ty = ty.to_ascii_uppercase();
    let unset = |names: &[&str], s: Scalar| -> Vec<(String, Value)> {
        names
            .iter()
            .map(|n| (n.to_string(), Value::Unset(s)))
            .collect()
    };
    Some(match ty.as_str() {
        "INT" => Value::Unset(Scalar::Int),
        "REAL" => Value::Unset(Scalar::Real),
        "BOOL" => Value::Unset(Scalar::Bool),
        "CHAR" => Value::Unset(Scalar::Char),
        "FRAME" => Value::Struct(ty, unset(&FRAME_FIELDS, Scalar::Real)),
        "POS" | "E6POS" => {
            let mut f = unset(&FRAME_FIELDS, Scalar::Real);
            f.extend(unset(&["S", "T"], Scalar::Int));
            if ty == "E6POS" {
                f.extend(unset(&EXT_FIELDS, Scalar::Real));
            }
            Value::Struct(ty, f)
        }
        "AXIS" | "E6AXIS" => {
            let mut f = unset(&AXIS_FIELDS, Scalar::Real);
            if ty == "E6AXIS" {
                f.extend(unset(&EXT_FIELDS, Scalar::Real));
            }
            Value::Struct(ty, f)
        }
        _ => return None,
    })
}

pub(super) fn real_struct(ty: &str, fields: &[(&str, f64)]) -> Value {
    Value::Struct(
        ty.into(),
        fields
            .iter()
            .map(|(n, v)| (n.to_string(), Value::Real(*v)))
            .collect(),
    )
}

pub(super) fn frame_value(p: &Pose) -> Value {
    let a = p.to_array();
    let fields: Vec<(&str, f64)> = FRAME_FIELDS.iter().copied().zip(a).collect();
    real_struct("FRAME", &fields)
}

pub(super) fn axis_value(axes: &Axes) -> Value {
    let mut fields: Vec<(&str, f64)> = AXIS_FIELDS.iter().copied().zip(*axes).collect();
    fields.extend(EXT_FIELDS.iter().map(|n| (*n, 0.0)));
    real_struct("E6AXIS", &fields)
}

fn find<'v>(fields: &'v [(String, Value)], name: &str) -> Option<&'v Value> {
    fields.iter().find(|(n, _)| n == name).map(|(_, v)| v)
}

/// A numeric component, `None` if absent or unset.
pub(super) fn num_field(fields: &[(String, Value)], name: &str) -> Result<Option<f64>, String> {
    match find(fields, name) {
        None | Some(Value::Unset(_)) => Ok(None),
        Some(v) => v
            .num()
            .map(Some)
            .map_err(|e| format!("component {name}: {e}")),
    }
}

/// The six FRAME components of a FRAME/POS/E6POS value, all required.
pub(super) fn pose_of(v: &Value) -> Result<Pose, String> {
    let Value::Struct(_, f) = v else {
        return Err(format!("expected a FRAME, found {}", v.type_name()));
    };
    let mut a = [0.0; 6];
    for (slot, name) in a.iter_mut().zip(FRAME_FIELDS) {
        *slot = num_field(f, name)?
            .ok_or_else(|| format!("component {name} of the {} has no value", v.type_name()))?;
    }
    Ok(Pose::new(a[0], a[1], a[2], a[3], a[4], a[5]))
}

/// Converts `v` to the scalar type `kind` (KRL assignment rules).
fn convert(kind: Scalar, v: Value) -> Result<Value, String> {
    Ok(match (kind, v) {
        (k, Value::Unset(_)) => Value::Unset(k),
        (Scalar::Int, Value::Int(i)) => Value::Int(i),
        (Scalar::Int, Value::Real(r)) => {
            let r = r.round();
            if !(r.is_finite() && r >= f64::from(i32::MIN) && r <= f64::from(i32::MAX)) {
                return Err(format!("{r} does not fit into an INT"));
            }
            Value::Int(r as i64)
        }
        (Scalar::Int, Value::Char(c)) => Value::Int(i64::from(c)),
        (Scalar::Real, Value::Int(i)) => Value::Real(i as f64),
        (Scalar::Real, Value::Real(r)) => Value::Real(r),
        (Scalar::Bool, Value::Bool(b)) => Value::Bool(b),
        (Scalar::Char, Value::Char(c)) => Value::Char(c),
        (Scalar::Char, Value::Int(i)) if (0..=255).contains(&i) => Value::Char(i as u8),
        (Scalar::Char, Value::Str(s)) if s.len() == 1 => Value::Char(s.as_bytes()[0]),
        (Scalar::Enum, Value::Enum(e)) => Value::Enum(e),
        (k, v) => {
            return Err(format!(
                "cannot assign {} to a {}",
                v.type_name(),
                Value::Unset(k).type_name()
            ));
        }
    })
}

/// Assigns `v` into the typed `slot`: scalars convert, structure values set
/// only the components they name.
pub(super) fn assign_into(slot: &mut Value, v: Value) -> Result<(), String> {
    if let Some(kind) = slot.scalar_kind() {
        *slot = convert(kind, v)?;
        return Ok(());
    }
    match (slot, v) {
        (Value::Struct(ty, fields), Value::Struct(_, new)) => {
            for (name, val) in new {
                if matches!(val, Value::Unset(_)) {
                    continue;
                }
                let Some((_, f)) = fields.iter_mut().find(|(n, _)| *n == name) else {
                    return Err(format!("{ty} has no component {name}"));
                };
                assign_into(f, val).map_err(|e| format!("component {name}: {e}"))?;
            }
            Ok(())
        }
        (Value::Array(dims, elems), Value::Array(d2, e2)) if *dims == d2 => {
            for (a, b) in elems.iter_mut().zip(e2) {
                if !matches!(b, Value::Unset(_)) {
                    assign_into(a, b)?;
                }
            }
            Ok(())
        }
        (Value::Array(dims, elems), Value::Str(s))
            if dims.len() == 1
                && elems.first().and_then(Value::scalar_kind) == Some(Scalar::Char) =>
        {
            if s.len() > elems.len() {
                return Err(format!(
                    "the string has {} characters, the array only {}",
                    s.len(),
                    elems.len()
                ));
            }
            let bytes = s.as_bytes();
            for (i, e) in elems.iter_mut().enumerate() {
                *e = bytes
                    .get(i)
                    .map_or(Value::Unset(Scalar::Char), |b| Value::Char(*b));
            }
            Ok(())
        }
        (Value::Enum(e), Value::Enum(n)) => {
            *e = n;
            Ok(())
        }
        (Value::Opaque(t), _) => Err(format!("variables of type {t} are not supported")),
        (slot, v) => Err(format!(
            "cannot assign {} to {}",
            v.type_name(),
            slot.type_name()
        )),
    }
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum PathElem {
    /// 1-based indices; empty = the whole array (`name[]`).
    Index(Vec<i64>),
    Field(String),
}

pub(super) fn flat_index(dims: &[usize], idx: &[i64]) -> Result<usize, String> {
    if idx.len() != dims.len() {
        return Err(format!(
            "{} indices for an array of {} dimensions",
            idx.len(),
            dims.len()
        ));
    }
    let mut flat = 0usize;
    for (&i, &d) in idx.iter().zip(dims) {
        if i < 1 || i as u64 > d as u64 {
            return Err(format!("index {i} is out of range 1..{d}"));
        }
        flat = flat * d + (i - 1) as usize;
    }
    Ok(flat)
}

pub(super) fn step_into<'v>(v: &'v Value, p: &PathElem) -> Result<&'v Value, String> {
    match (v, p) {
        (v, PathElem::Index(i)) if i.is_empty() => Ok(v),
        (Value::Array(d, e), PathElem::Index(i)) => {
            let k = flat_index(d, i)?;
            e.get(k).ok_or_else(|| "index out of range".to_string())
        }
        (Value::Struct(ty, f), PathElem::Field(n)) => {
            find(f, n).ok_or_else(|| format!("{ty} has no component {n}"))
        }
        (v, PathElem::Index(_)) => Err(format!("{} is not an array", v.type_name())),
        (v, PathElem::Field(n)) => Err(format!("{} has no component {n}", v.type_name())),
    }
}

pub(super) fn walk<'v>(mut v: &'v Value, path: &[PathElem]) -> Result<&'v Value, String> {
    for p in path {
        v = step_into(v, p)?;
    }
    Ok(v)
}

pub(super) fn walk_mut<'v>(
    mut v: &'v mut Value,
    path: &[PathElem],
) -> Result<&'v mut Value, String> {
    for p in path {
        if matches!(p, PathElem::Index(i) if i.is_empty()) {
            continue;
        }
        v = match (v, p) {
            (Value::Array(d, e), PathElem::Index(i)) => {
                let k = flat_index(d, i)?;
                e.get_mut(k)
                    .ok_or_else(|| "index out of range".to_string())?
            }
            (Value::Struct(ty, f), PathElem::Field(n)) => {
                let ty = ty.clone();
                f.iter_mut()
                    .find(|(k, _)| k == n)
                    .map(|(_, v)| v)
                    .ok_or_else(|| format!("{ty} has no component {n}"))?
            }
            (v, PathElem::Index(_)) => return Err(format!("{} is not an array", v.type_name())),
            (v, PathElem::Field(n)) => {
                return Err(format!("{} has no component {n}", v.type_name()));
            }
        };
    }
    Ok(v)
}

/// The scalar values `v` holds (for [`MAX_VALUE_CELLS`](super::MAX_VALUE_CELLS)): 1 for a scalar,
/// the components of a structure, the elements of an array (all of one
/// shape, so the first one is counted).
pub(super) fn cells(v: &Value) -> usize {
    match v {
        Value::Struct(_, f) => f.iter().map(|(_, v)| cells(v)).sum::<usize>().max(1),
        Value::Array(_, e) => e.first().map_or(0, cells).saturating_mul(e.len()),
        _ => 1,
    }
}
