//! Declarations and types: `DECL` of variables and arrays (counted
//! against the value limit), the typing of `IN` parameters, and the
//! user-defined `STRUC` types.

use kuka_krl::Expr;

use super::values::{Scalar, Value, assign_into, cells, template};
use super::vars::Slot;
use super::{Interp, MAX_ARRAY, RunError, Unsupported};

impl<'a> Interp<'a> {
    /// The typed template of a predefined, user-defined or harness type.
    pub(super) fn type_template(&self, ty: &str) -> Option<Value> {
        template(ty).or_else(|| self.types.get(&ty.to_ascii_uppercase()).cloned())
    }

    /// `STRUC name type f1, f2[n], …`: registers the type.
    pub(super) fn define_struc(
        &mut self,
        name: &str,
        fields: &[(String, String, Vec<Expr>)],
    ) -> Result<(), RunError> {
        let mut out = Vec::with_capacity(fields.len());
        for (ty, field, dims) in fields {
            let Some(mut v) = self.type_template(ty) else {
                return Err(self.err(format!(
                    "the component {field} of {name} has the unknown type {ty}"
                )));
            };
            if !dims.is_empty() {
                let mut ds = Vec::with_capacity(dims.len());
                for d in dims {
                    let n = self.eval_int(d)?;
                    if !(1..=MAX_ARRAY as i64).contains(&n) {
                        return Err(self.err(format!("array size {n} of {field} is out of range")));
                    }
                    ds.push(n as usize);
                }
                let total = ds.iter().product::<usize>();
                if total > MAX_ARRAY {
                    return Err(self.err(format!("the array {field} is too large")));
                }
                v = Value::Array(ds, vec![v; total]);
            }
            out.push((field.to_ascii_uppercase(), v));
        }
        let up = name.to_ascii_uppercase();
        self.types.insert(up.clone(), Value::Struct(up, out));
        Ok(())
    }

    pub(super) fn declare(&mut self, ty: &str, d: &kuka_krl::Declarator) -> Result<(), RunError> {
        let name = d.name.to_ascii_uppercase();
        let Some(mut value) = self.type_template(ty) else {
            if self.frames.is_empty() {
                self.globals
                    .insert(name, Value::Opaque(ty.to_ascii_uppercase()));
                return Ok(());
            }
            return Err(Unsupported {
                line: self.line,
                what: format!("the type {ty}"),
            }
            .into());
        };
        if !d.dims.is_empty() {
            let mut dims = Vec::with_capacity(d.dims.len());
            let mut total = 1usize;
            for e in &d.dims {
                let n = self.eval_int(e)?;
                if n < 1 || n as u64 > MAX_ARRAY as u64 {
                    return Err(self.err(format!("array size {n} of {} is out of range", d.name)));
                }
                total = total.saturating_mul(n as usize);
                dims.push(n as usize);
            }
            if total > MAX_ARRAY {
                return Err(self.err(format!("the array {} is too large", d.name)));
            }
            // Counted before the array is allocated.
            self.hold(cells(&value).saturating_mul(total))?;
            value = Value::Array(dims, vec![value; total]);
        } else if !matches!(
            self.frames.last().and_then(|f| f.get(&name)),
            Some(Slot::Val(_) | Slot::Ref(_))
        ) {
            self.hold(cells(&value))?;
        }
        match self.frames.last_mut() {
            None => {
                if let Some(old) = self.globals.insert(name.clone(), value) {
                    self.cells = self.cells.saturating_sub(cells(&old));
                }
            }
            Some(frame) => match frame.get_mut(&name) {
                // The declaration of an OUT parameter: the caller's variable.
                Some(Slot::Ref(_)) => return Ok(()),
                // The declaration of an IN parameter: give the value its type.
                Some(Slot::Val(v)) => {
                    let given = std::mem::replace(v, Value::Unset(Scalar::Int));
                    let r = assign_into(&mut value, given);
                    *v = value;
                    r.map_err(|m| self.err(format!("parameter {}: {m}", d.name)))?;
                    return Ok(());
                }
                None => {
                    frame.insert(name.clone(), Slot::Val(value));
                }
            },
        }
        if let Some(init) = &d.init {
            let v = self.eval(init)?;
            let p = self.resolve(&name)?;
            self.write_place(&p, v)?;
        }
        Ok(())
    }
}
