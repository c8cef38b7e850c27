//! Variables: where a name lives (the routine's frame, an `OUT`
//! parameter's variable, the globals or a computed system variable), and
//! reading and writing such places.

use kuka_krl::Expr;

use super::values::{PathElem, Value, assign_into, cells, walk, walk_mut};
use super::{Interp, RunError, SYS_READ_ONLY, describe};

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Root {
    Global(String),
    Local(usize, String),
    /// `$POS_ACT`, `$AXIS_ACT`, `$NULLFRAME`, `$OV_PRO`.
    Computed(String),
}

#[derive(Debug, Clone)]
pub(super) struct Place {
    pub(super) root: Root,
    pub(super) path: Vec<PathElem>,
    pub(super) desc: String,
}

#[derive(Debug, Clone)]
pub(super) enum Slot {
    Val(Value),
    /// An `OUT` parameter: the caller's variable.
    Ref(Place),
}

impl<'a> Interp<'a> {
    pub(super) fn resolve(&self, name: &str) -> Result<Place, RunError> {
        let up = name.to_ascii_uppercase();
        if let Some(i) = self.frames.len().checked_sub(1) {
            match self.frames.get(i).and_then(|f| f.get(&up)) {
                Some(Slot::Val(_)) => {
                    return Ok(Place {
                        root: Root::Local(i, up),
                        path: Vec::new(),
                        desc: name.to_string(),
                    });
                }
                Some(Slot::Ref(p)) => {
                    let mut p = p.clone();
                    p.desc = name.to_string();
                    return Ok(p);
                }
                None => {}
            }
        }
        let root = if self.globals.contains_key(&up) {
            Root::Global(up)
        } else if SYS_READ_ONLY.contains(&up.as_str()) {
            Root::Computed(up)
        } else {
            return Err(self.err(format!("the variable {name} is not declared")));
        };
        Ok(Place {
            root,
            path: Vec::new(),
            desc: name.to_string(),
        })
    }

    /// The place an lvalue-like expression names, or `None` if it is not
    /// rooted in a variable.
    pub(super) fn place_of(&mut self, e: &Expr) -> Result<Option<Place>, RunError> {
        self.enter()?;
        let r = self.place_of_node(e);
        self.nesting -= 1;
        r
    }

    fn place_of_node(&mut self, e: &Expr) -> Result<Option<Place>, RunError> {
        Ok(match e {
            Expr::Var(n) => Some(self.resolve(n)?),
            Expr::Index(b, idx) => match self.place_of(b)? {
                Some(mut p) => {
                    let mut ii = Vec::with_capacity(idx.len());
                    for i in idx {
                        let v = self.eval(i)?;
                        ii.push(v.int().map_err(|m| self.err(format!("index: {m}")))?);
                    }
                    p.path.push(PathElem::Index(ii));
                    p.desc = describe(e);
                    Some(p)
                }
                None => None,
            },
            Expr::Field(b, f) => match self.place_of(b)? {
                Some(mut p) => {
                    p.path.push(PathElem::Field(f.to_ascii_uppercase()));
                    p.desc = describe(e);
                    Some(p)
                }
                None => None,
            },
            _ => None,
        })
    }

    fn root_ref(&self, root: &Root) -> Result<&Value, RunError> {
        let v = match root {
            Root::Global(n) => self.globals.get(n),
            Root::Local(i, n) => match self.frames.get(*i).and_then(|f| f.get(n)) {
                Some(Slot::Val(v)) => Some(v),
                _ => None,
            },
            Root::Computed(_) => None,
        };
        v.ok_or_else(|| self.err("internal: dangling variable reference"))
    }

    pub(super) fn read_place(&mut self, p: &Place) -> Result<Value, RunError> {
        let computed = match &p.root {
            Root::Computed(n) => Some(self.computed(n)?),
            _ => None,
        };
        let root = match &computed {
            Some(v) => v,
            None => self.root_ref(&p.root)?,
        };
        let v = walk(root, &p.path).map_err(|m| self.err(format!("{}: {m}", p.desc)))?;
        match v {
            Value::Unset(_) => Err(self.err(format!("{} has no value (not initialised)", p.desc))),
            Value::Opaque(t) => Err(self.err(format!(
                "{} has the type {t}, which the simulator does not support",
                p.desc
            ))),
            v @ Value::Array(..) => {
                // Copying a whole array is work in proportion to its size.
                let v = v.clone();
                self.charge(cells(&v) as u64)?;
                Ok(v)
            }
            v => Ok(v.clone()),
        }
    }

    pub(super) fn write_place(&mut self, p: &Place, v: Value) -> Result<(), RunError> {
        let sys = match &p.root {
            Root::Global(n) if n.starts_with('$') => Some(n.clone()),
            Root::Computed(n) => return Err(self.err(format!("{n} is read-only"))),
            _ => None,
        };
        let saved = match &sys {
            Some(_) => Some((self.root_ref(&p.root)?.clone(), self.tool()?, self.base()?)),
            None => None,
        };
        let root = match &p.root {
            Root::Global(n) => self.globals.get_mut(n),
            Root::Local(i, n) => match self.frames.get_mut(*i).and_then(|f| f.get_mut(n)) {
                Some(Slot::Val(v)) => Some(v),
                _ => None,
            },
            Root::Computed(_) => None,
        };
        let Some(root) = root else {
            return Err(self.err("internal: dangling variable reference"));
        };
        let r = walk_mut(root, &p.path).and_then(|slot| assign_into(slot, v));
        r.map_err(|m| self.err(format!("{}: {m}", p.desc)))?;
        if let (Some(name), Some((old, old_tool, old_base))) = (sys, saved) {
            if let Err(m) = self.validate_sys(&name) {
                self.globals.insert(name, old);
                return Err(self.err(m));
            }
            if name == "$TOOL" || name == "$BASE" {
                self.frames_changed(old_tool, old_base)?;
            }
        }
        Ok(())
    }
}
