//! The native simulator's KRL variables, as KUKAVARPROXY would read and
//! write them on a KRC: the few it models. `$OV_PRO` (read, write 0..100),
//! `$POS_ACT` (E6POS), `$AXIS_ACT` (E6AXIS), `$TOOL`, `$BASE` (FRAME),
//! `$MODE_OP` (#T1, #T2, #AUT, #EX), `$IN[n]`/`$OUT[n]` (read), and the
//! tool and base tables `TOOL_DATA[1..16]`/`BASE_DATA[1..32]` (read,
//! write; zero at start as on a fresh controller) and their names
//! `TOOL_NAME[n,]`/`BASE_NAME[n,]` (CHAR[24] rows, empty at start). A
//! component such as
//! `$POS_ACT.X` or `TOOL_DATA[3].Z` is read and written through its
//! variable. Anything else does not exist here (the KRC-like runtime has
//! every variable of the shipped program).

use kuka_kinematics::Pose;
use kuka_kvp::KrlValue;
use kuka_protocol::OperatingMode;

use crate::controller::Controller;

fn frame(ty: &str, p: &Pose) -> KrlValue {
    KrlValue::Struct(
        Some(ty.into()),
        ["X", "Y", "Z", "A", "B", "C"]
            .iter()
            .zip(p.to_array())
            .map(|(k, v)| ((*k).to_string(), KrlValue::Real((v * 1e6).round() / 1e6)))
            .collect(),
    )
}

/// Splits `TOOL_DATA[3].X` into (`TOOL_DATA`, Some(3), Some("X")).
fn split(path: &str) -> Option<(String, Option<usize>, Option<String>)> {
    let (head, field) = match path.split_once('.') {
        Some((h, f)) if !f.contains(['.', '[']) => (h, Some(f.to_ascii_uppercase())),
        Some(_) => return None,
        None => (path, None),
    };
    let (root, index) = match head.split_once('[') {
        Some((r, i)) => (r, Some(i.strip_suffix(']')?.parse().ok()?)),
        None => (head, None),
    };
    Some((root.to_ascii_uppercase(), index, field))
}

fn field_of(v: KrlValue, field: Option<&str>) -> Option<KrlValue> {
    match (field, v) {
        (None, v) => Some(v),
        (Some(f), KrlValue::Struct(_, fields)) => {
            fields.into_iter().find(|(k, _)| k == f).map(|(_, v)| v)
        }
        _ => None,
    }
}

fn table<'a>(c: &'a mut Controller, root: &str, index: Option<usize>) -> Option<&'a mut Pose> {
    let i = index?.checked_sub(1)?;
    match root {
        "TOOL_DATA" => c.tool_data.get_mut(i),
        "BASE_DATA" => c.base_data.get_mut(i),
        _ => None,
    }
}

/// The length of a table name (`TOOL_NAME[16,24]` on a KRC).
const NAME_LEN: usize = 24;

/// `TOOL_NAME[3,]` → the name slot (a row of a CHAR array).
fn name_slot<'a>(c: &'a mut Controller, path: &str) -> Option<&'a mut String> {
    let body = path.strip_suffix(",]")?;
    let (root, row) = body.split_once('[')?;
    let i = row.parse::<usize>().ok()?.checked_sub(1)?;
    match root.to_ascii_uppercase().as_str() {
        "TOOL_NAME" => c.tool_names.get_mut(i),
        "BASE_NAME" => c.base_names.get_mut(i),
        _ => None,
    }
}

fn num(v: &KrlValue) -> Option<f64> {
    match v {
        KrlValue::Int(i) => Some(*i as f64),
        KrlValue::Real(r) => Some(*r),
        _ => None,
    }
}

impl Controller {
    fn whole(&mut self, root: &str, index: Option<usize>) -> Option<KrlValue> {
        let (pose, s, t) = self.position();
        Some(match (root, index) {
            ("$OV_PRO", None) => KrlValue::Int(self.speed.override_pct.round() as i64),
            ("$POS_ACT", None) => {
                let KrlValue::Struct(_, mut f) = frame("E6POS", &pose) else {
                    return None;
                };
                f.push(("S".into(), KrlValue::Int(i64::from(s))));
                f.push(("T".into(), KrlValue::Int(i64::from(t))));
                KrlValue::Struct(Some("E6POS".into()), f)
            }
            ("$AXIS_ACT", None) => KrlValue::Struct(
                Some("E6AXIS".into()),
                self.axes
                    .iter()
                    .enumerate()
                    .map(|(k, a)| {
                        (
                            format!("A{}", k + 1),
                            KrlValue::Real((a * 1e6).round() / 1e6),
                        )
                    })
                    .collect(),
            ),
            ("$TOOL", None) => frame("FRAME", &self.tool),
            ("$BASE", None) => frame("FRAME", &self.base),
            ("$MODE_OP", None) => KrlValue::Enum(
                match self.mode {
                    OperatingMode::T1 => "T1",
                    OperatingMode::T2 => "T2",
                    OperatingMode::Aut => "AUT",
                    OperatingMode::Ext => "EX",
                    OperatingMode::Unknown => "INVALID",
                }
                .into(),
            ),
            ("$IN", Some(i)) => KrlValue::Bool(*self.inputs.get(i).filter(|_| i > 0)?),
            ("$OUT", Some(i)) => KrlValue::Bool(*self.outputs.get(i).filter(|_| i > 0)?),
            ("TOOL_DATA" | "BASE_DATA", Some(_)) => {
                let p = *table(self, root, index)?;
                frame("FRAME", &p)
            }
            _ => return None,
        })
    }

    /// A variable as KRL text (see the module documentation).
    pub(crate) fn read_krl(&mut self, path: &str) -> Option<String> {
        if let Some(name) = name_slot(self, path) {
            return Some(KrlValue::Text(name.clone()).to_krl());
        }
        let (root, index, field) = split(path)?;
        let v = self.whole(&root, index)?;
        Some(field_of(v, field.as_deref())?.to_krl())
    }

    /// Writes a variable (`$OV_PRO`, `TOOL_DATA[n]`, `BASE_DATA[n]` and
    /// their components); its value afterwards, or `None` when it cannot
    /// be written or the value does not fit.
    pub(crate) fn write_krl(&mut self, path: &str, text: &str) -> Option<String> {
        let v = KrlValue::parse(text)?;
        if let Some(name) = name_slot(self, path) {
            let KrlValue::Text(text) = v else { return None };
            if text.len() > NAME_LEN {
                return None;
            }
            *name = text;
            return self.read_krl(path);
        }
        let (root, index, field) = split(path)?;
        match (root.as_str(), field) {
            ("$OV_PRO", None) => {
                // An INT on a KRC: a REAL is rounded as KRL assigns it.
                let ov = num(&v)
                    .map(f64::round)
                    .filter(|o| (0.0..=100.0).contains(o))?;
                self.speed.override_pct = ov;
                self.plan.override_pct = ov;
            }
            ("TOOL_DATA" | "BASE_DATA", field) => {
                let p = table(self, &root, index)?;
                let mut a = p.to_array();
                let names = ["X", "Y", "Z", "A", "B", "C"];
                match (field, &v) {
                    (Some(f), v) => {
                        let k = names.iter().position(|n| *n == f)?;
                        a[k] = num(v)?;
                    }
                    (None, KrlValue::Struct(_, fields)) => {
                        for (name, fv) in fields {
                            let k = names.iter().position(|n| n == name)?;
                            a[k] = num(fv)?;
                        }
                    }
                    _ => return None,
                }
                if !a.iter().all(|x| x.is_finite()) {
                    return None;
                }
                *p = Pose::new(a[0], a[1], a[2], a[3], a[4], a[5]);
            }
            _ => return None,
        }
        self.read_krl(path)
    }
}
