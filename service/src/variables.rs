//! KRL variables through KUKAVARPROXY (docs/VARIABLES.md): the client of
//! the site's proxy (`[variables] proxy`), or, with `--simulate`, of a
//! stand-in the service starts over the simulated controller's memory, so
//! that the same protocol is tested here. Names are checked before they
//! leave the service, writes only reach the site's allow-list, and values
//! are built from typed JSON, never taken from a client as KRL text.

use std::sync::{Arc, Weak};
use std::time::Duration;

use kuka_kvp::{KrlValue, KvpClient, KvpError, KvpServer, VarStore, check_name};
use serde::Serialize;
use utoipa::ToSchema;

use crate::error::{BridgeError, ErrorCode};

/// A variable's value as the API answers it.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({"name": "$OV_PRO", "type": "INT", "value": 100, "krl": "100"}))]
pub struct Variable {
    /// The name as asked.
    pub name: String,
    /// `INT`, `REAL`, `BOOL`, `CHAR`, `ENUM`, or a structure's type
    /// (`E6POS`, `FRAME`, ...; `STRUC` when the controller did not name it).
    #[serde(rename = "type")]
    pub kind: String,
    /// The value: a number, a boolean, a string, `{"enum": "T1"}`, or an
    /// object of a structure's components.
    #[schema(value_type = Value)]
    pub value: serde_json::Value,
    /// The value as KRL text, as the controller showed it.
    pub krl: String,
}

/// The service's access to variables.
pub struct Variables {
    client: Option<KvpClient>,
    writable: Vec<String>,
    /// The simulator's stand-in, kept running while the service runs.
    _stand_in: Option<KvpServer>,
}

impl Variables {
    /// Variables through `client` (none: every access answers
    /// `variables_unavailable`), writable: `writable`.
    pub fn new(
        client: Option<KvpClient>,
        writable: Vec<String>,
        stand_in: Option<KvpServer>,
    ) -> Self {
        Variables {
            client,
            writable,
            _stand_in: stand_in,
        }
    }

    fn client(&self) -> Result<&KvpClient, BridgeError> {
        self.client.as_ref().ok_or_else(|| {
            BridgeError::new(
                ErrorCode::VariablesUnavailable,
                "no KUKAVARPROXY server is configured ([variables] proxy)",
            )
        })
    }

    fn error(name: &str, e: KvpError) -> BridgeError {
        match e {
            KvpError::Refused(_) => BridgeError::new(
                ErrorCode::UnknownVariable,
                format!("the controller has no variable {name} (or the value does not fit it)"),
            ),
            KvpError::Unreachable { ref addr, .. } => {
                tracing::warn!(error = %e, "KUKAVARPROXY unreachable");
                BridgeError::new(
                    ErrorCode::VariablesUnavailable,
                    format!("KUKAVARPROXY at {addr} is not reachable (see the service log)"),
                )
            }
            KvpError::Protocol(_) => {
                tracing::warn!(error = %e, "KUKAVARPROXY protocol error");
                BridgeError::new(
                    ErrorCode::VariablesUnavailable,
                    "KUKAVARPROXY answered something unexpected (see the service log)",
                )
            }
        }
    }

    fn answer(name: &str, text: String) -> Variable {
        match KrlValue::parse(&text) {
            Some(v) => Variable {
                name: name.to_string(),
                kind: v.type_name(),
                value: v.to_json(),
                krl: text,
            },
            // A value this parser does not know: the text as it came.
            None => Variable {
                name: name.to_string(),
                kind: "UNKNOWN".into(),
                value: serde_json::Value::Null,
                krl: text,
            },
        }
    }

    /// Reads a variable.
    pub async fn read(&self, name: &str) -> Result<Variable, BridgeError> {
        check_name(name).map_err(BridgeError::invalid)?;
        let client = self.client()?;
        let text = client.read(name).await.map_err(|e| Self::error(name, e))?;
        Ok(Self::answer(name, text))
    }

    /// Whether clients may write `name`.
    pub fn writable(&self, name: &str) -> bool {
        self.writable.iter().any(|w| w.eq_ignore_ascii_case(name))
    }

    /// Writes a variable on the allow-list with a typed JSON value.
    pub async fn write(
        &self,
        name: &str,
        value: &serde_json::Value,
    ) -> Result<Variable, BridgeError> {
        check_name(name).map_err(BridgeError::invalid)?;
        if !self.writable(name) {
            return Err(BridgeError::new(
                ErrorCode::VariableNotAllowed,
                format!(
                    "{name} is not on the site's list of variables clients may write ([variables] writable in the configuration)"
                ),
            ));
        }
        let v = KrlValue::from_json(value).map_err(BridgeError::invalid)?;
        let client = self.client()?;
        // The value must fit the variable as it is now: a number for a
        // number, the components a structure has, ...
        let now = client.read(name).await.map_err(|e| Self::error(name, e))?;
        if let Some(now) = KrlValue::parse(&now) {
            fits(&now, &v).map_err(|why| {
                BridgeError::invalid(format!("{name} is {}: {why}", now.type_name()))
            })?;
        }
        let text = client
            .write(name, &v.to_krl())
            .await
            .map_err(|e| match e {
                // It was just read: the controller refused the value (out
                // of the variable's range, too long for its CHAR array, a
                // write-protected variable), not the name.
                KvpError::Refused(_) => BridgeError::invalid(format!(
                    "the controller did not accept {} for {name} (out of its range, too long, or the variable is write-protected)",
                    kuka_engine::io::clip(&v.to_krl(), 40)
                )),
                e => Self::error(name, e),
            })?;
        tracing::info!(variable = name, value = %v.to_krl(), "variable written");
        Ok(Self::answer(name, text))
    }
}

/// Whether `new` can be assigned to a variable holding `now`: numbers to
/// numbers, the same scalar kind otherwise, and structures with
/// components the variable has.
fn fits(now: &KrlValue, new: &KrlValue) -> Result<(), String> {
    use KrlValue as K;
    match (now, new) {
        (K::Int(_) | K::Real(_), K::Int(_) | K::Real(_))
        | (K::Bool(_), K::Bool(_))
        | (K::Text(_), K::Text(_))
        | (K::Enum(_), K::Enum(_)) => Ok(()),
        (K::Struct(_, have), K::Struct(_, set)) => {
            for (name, v) in set {
                let (_, cur) = have
                    .iter()
                    .find(|(k, _)| k == name)
                    .ok_or_else(|| format!("it has no component {name}"))?;
                fits(cur, v).map_err(|why| format!("component {name}: {why}"))?;
            }
            Ok(())
        }
        (_, new) => Err(format!(
            "a value of type {} does not fit it",
            new.type_name()
        )),
    }
}

/// The native simulator as a KUKAVARPROXY store. (Weak: the stand-in
/// never keeps a stopped simulator, and its channel lock, alive.)
struct NativeStore(Weak<kuka_sim::SimController>);

impl VarStore for NativeStore {
    fn read(&self, name: &str) -> Option<String> {
        self.0.upgrade()?.read_krl(name)
    }
    fn write(&self, name: &str, value: &str) -> Option<String> {
        self.0.upgrade()?.write_krl(name, value)
    }
}

/// The KRC-like runtime as a KUKAVARPROXY store: every variable of the
/// shipped program and the runtime's system variables.
struct KrcStore(Weak<kuka_krc::KrcController>);

impl VarStore for KrcStore {
    fn read(&self, name: &str) -> Option<String> {
        self.0.upgrade()?.read_krl(name)
    }
    fn write(&self, name: &str, value: &str) -> Option<String> {
        self.0.upgrade()?.write_krl(name, value).ok()
    }
}

/// Starts a KUKAVARPROXY stand-in on a free loopback port over the
/// simulated controller, and a client of it.
pub fn simulated(
    sim: Option<Arc<kuka_sim::SimController>>,
    krc: Option<Arc<kuka_krc::KrcController>>,
    timeout: Duration,
) -> std::io::Result<Option<(KvpServer, KvpClient)>> {
    let store: Arc<dyn VarStore> = match (sim, krc) {
        (Some(s), _) => Arc::new(NativeStore(Arc::downgrade(&s))),
        (None, Some(k)) => Arc::new(KrcStore(Arc::downgrade(&k))),
        (None, None) => return Ok(None),
    };
    let server = KvpServer::start("127.0.0.1:0", store)?;
    let client = KvpClient::new(server.addr().to_string(), timeout);
    Ok(Some((server, client)))
}
