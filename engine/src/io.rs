//! Digital I/O: the site's named signals (configuration `[io]`), the
//! outputs clients may write (the allow-list), and the controller's I/O as
//! its state file reports it (a window of 31 inputs and outputs).

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{BridgeError, ErrorCode, Result};
use kuka_protocol::{AnalogState, IoState, MAX_ANALOG_INDEX, MAX_IO_INDEX, MAX_PULSE_MS};

/// Inputs or outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum IoKind {
    /// `$IN`.
    Input,
    /// `$OUT`.
    Output,
}

impl IoKind {
    /// `$IN` or `$OUT`.
    pub fn krl(self) -> &'static str {
        match self {
            IoKind::Input => "$IN",
            IoKind::Output => "$OUT",
        }
    }
}

/// One named signal of the site.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SignalConfig {
    /// The name clients may use instead of the number (`gripper_close`):
    /// a lower-case letter, then lower-case letters, digits and `_`, at
    /// most 32 characters.
    pub name: String,
    /// `$IN`/`$OUT` index, 1..=4096.
    #[schema(minimum = 1, maximum = 4096)]
    pub index: u16,
    /// Outputs: a write without its own `pulse_ms` pulses this long (ms,
    /// up to 60000); 0 = the output stays.
    #[serde(default)]
    pub pulse_ms: u32,
    /// Changes of this signal are pushed as `io` events.
    #[serde(default)]
    pub watch: bool,
}

/// The site's digital I/O: names for inputs, and the outputs clients may
/// write (every other output is refused with `output_not_allowed`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields, default)]
#[schema(example = json!({
    "inputs": [{"name": "part_present", "index": 3, "pulse_ms": 0, "watch": true}],
    "outputs": [{"name": "gripper_close", "index": 1, "pulse_ms": 0, "watch": true}],
    "analog_inputs": [{"name": "force", "index": 2, "watch": true, "deadband": 0.05}],
    "analog_outputs": [{"name": "spindle_speed", "index": 1, "watch": false, "deadband": 0.01}]
}))]
pub struct IoConfig {
    /// Named inputs (reading needs no entry: any input in the window can be
    /// read by number).
    pub inputs: Vec<SignalConfig>,
    /// The outputs clients may write, by name and number (reading needs
    /// no entry).
    pub outputs: Vec<SignalConfig>,
    /// Named analog inputs (`$ANIN[1..=32]`).
    pub analog_inputs: Vec<AnalogConfig>,
    /// The analog outputs clients may write (`$ANOUT[1..=32]`).
    pub analog_outputs: Vec<AnalogConfig>,
}

/// One named analog channel of the site.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct AnalogConfig {
    /// Its name, as for digital signals (`spindle_speed`).
    pub name: String,
    /// `$ANIN`/`$ANOUT` index, 1..=32.
    #[schema(minimum = 1, maximum = 32)]
    pub index: u8,
    /// Publish an `analog` event when its value moves by `deadband` or
    /// more from the last published one (channels 1..=8: the ones the
    /// controller reports).
    #[serde(default)]
    pub watch: bool,
    /// The change (normalised, 0 < deadband ≤ 2) that makes a watched
    /// channel publish an event; default 0.01, 1 % of full scale.
    #[serde(default = "default_deadband")]
    #[schema(minimum = 0.001, maximum = 2.0)]
    pub deadband: f64,
}

fn default_deadband() -> f64 {
    0.01
}

/// A watched analog channel moved by its deadband (an `analog` event).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({"kind": "input", "index": 2, "name": "force", "value": 0.25}))]
pub struct AnalogChange {
    /// Input (`$ANIN`) or output (`$ANOUT`).
    pub kind: IoKind,
    /// Its index, 1..=8.
    #[schema(minimum = 1, maximum = 8)]
    pub index: u8,
    /// Its configured name.
    pub name: String,
    /// The new value, normalised −1..=1 (3 decimals, as the controller
    /// reports it).
    pub value: f64,
}

/// The analog channels the controller reported in its last state file
/// (`$ANIN`/`$ANOUT[1..=8]`, normalised −1..=1).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct AnalogWindow {
    /// `$ANIN[1..=8]`.
    pub inputs: Vec<f64>,
    /// `$ANOUT[1..=8]`.
    pub outputs: Vec<f64>,
}

impl From<&AnalogState> for AnalogWindow {
    fn from(a: &AnalogState) -> Self {
        AnalogWindow {
            inputs: a.inputs.to_vec(),
            outputs: a.outputs.to_vec(),
        }
    }
}

/// An analog output to set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogOutputRequest {
    /// `$ANOUT` index, 1..=32.
    pub index: u8,
    /// Normalised value, −1..=1.
    pub value: f64,
}

/// At most `n` characters of a client's text, to repeat it in an error:
/// longer text ends with `…` (so a cut number is never shown as another
/// number).
pub fn clip(text: &str, n: usize) -> String {
    let mut s: String = text.chars().take(n).collect();
    if text.chars().nth(n).is_some() {
        s.push('…');
    }
    s
}

/// A signal name: a lower-case letter, then lower-case letters, digits
/// and `_`, at most 32 characters (digital and analog alike).
fn signal_name(name: &str) -> bool {
    name.len() <= 32
        && name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

impl IoConfig {
    /// Checks names, numbers and pulses. Every problem is reported, each
    /// naming its entry, joined with "; ", so that a site fixes its list
    /// in one go.
    pub fn validate(&self) -> std::result::Result<(), String> {
        let mut bad = Vec::new();
        let mut names = std::collections::HashSet::new();
        let digital = [("inputs", &self.inputs), ("outputs", &self.outputs)]
            .into_iter()
            .flat_map(|(kind, list)| {
                list.iter()
                    .map(move |s| (kind, s.name.as_str(), s.index, s.pulse_ms, None))
            });
        let analog = [
            ("analog_inputs", &self.analog_inputs),
            ("analog_outputs", &self.analog_outputs),
        ]
        .into_iter()
        .flat_map(|(kind, list)| {
            list.iter()
                .map(move |a| (kind, a.name.as_str(), u16::from(a.index), 0, Some(a)))
        });
        let mut indices = std::collections::HashSet::new();
        for (kind, name, index, pulse_ms, analog) in digital.chain(analog) {
            let max = if analog.is_some() {
                u16::from(MAX_ANALOG_INDEX)
            } else {
                MAX_IO_INDEX
            };
            if !signal_name(name) {
                bad.push(format!(
                    "io.{kind}: name {:?} must be a lower-case letter, then lower-case letters, digits or _, at most 32 characters",
                    clip(name, 40)
                ));
            } else if !names.insert(name) {
                bad.push(format!(
                    "io.{kind}: the name {name:?} is used twice (names are unique over all signals)"
                ));
            }
            if index == 0 || index > max {
                bad.push(format!(
                    "io.{kind}: {name:?} has index {index}, not in 1..={max}"
                ));
            } else if !indices.insert((kind, index)) {
                bad.push(format!("io.{kind}: index {index} is named twice"));
            }
            if pulse_ms > MAX_PULSE_MS || (kind == "inputs" && pulse_ms > 0) {
                bad.push(format!(
                    "io.{kind}: {name:?} has pulse_ms {pulse_ms} (outputs only, at most {MAX_PULSE_MS})"
                ));
            }
            let Some(a) = analog else { continue };
            if a.watch && usize::from(a.index) > AnalogState::WIDTH {
                bad.push(format!(
                    "io.{kind}: {name:?} (index {}) cannot be watched: the controller reports channels 1..={} only",
                    a.index,
                    AnalogState::WIDTH
                ));
            }
            if !(a.deadband.is_finite() && a.deadband >= 0.001 && a.deadband <= 2.0) {
                bad.push(format!(
                    "io.{kind}: {name:?} has deadband {}, not in 0.001..=2 (normalised units)",
                    a.deadband
                ));
            }
        }
        if bad.is_empty() {
            Ok(())
        } else {
            Err(bad.join("; "))
        }
    }

    /// The analog channel a client's `signal` (a number 1..=32 or a
    /// configured name) stands for, with its name.
    pub fn resolve_analog(&self, output: bool, signal: &str) -> Result<(u8, Option<&str>)> {
        let list = if output {
            &self.analog_outputs
        } else {
            &self.analog_inputs
        };
        let krl = if output { "$ANOUT" } else { "$ANIN" };
        if let Some(a) = list.iter().find(|a| a.name == signal) {
            return Ok((a.index, Some(a.name.as_str())));
        }
        if !signal.is_empty() && signal.bytes().all(|b| b.is_ascii_digit()) {
            let index: u8 = signal
                .parse()
                .ok()
                .filter(|i| (1..=MAX_ANALOG_INDEX).contains(i))
                .ok_or_else(|| {
                    BridgeError::invalid(format!(
                        "{krl}[{}] does not exist: indices are 1..={MAX_ANALOG_INDEX}",
                        clip(signal, 12)
                    ))
                })?;
            let name = list
                .iter()
                .find(|a| a.index == index)
                .map(|a| a.name.as_str());
            return Ok((index, name));
        }
        let shown: String = signal.chars().take(40).collect();
        Err(BridgeError::new(
            ErrorCode::UnknownSignal,
            format!(
                "no analog {} is named {shown:?}: use a number (1..={MAX_ANALOG_INDEX}) or a name from the site's [io] configuration",
                if output { "output" } else { "input" }
            ),
        ))
    }

    /// The analog output's entry if clients may write it.
    pub fn analog_writable(&self, index: u8) -> Result<&AnalogConfig> {
        self.analog_outputs
            .iter()
            .find(|a| a.index == index)
            .ok_or_else(|| {
                BridgeError::new(
                    ErrorCode::OutputNotAllowed,
                    format!(
                        "$ANOUT[{index}] is not on the site's list of analog outputs clients may write ([io] analog_outputs in the configuration)"
                    ),
                )
            })
    }

    fn list(&self, kind: IoKind) -> &[SignalConfig] {
        match kind {
            IoKind::Input => &self.inputs,
            IoKind::Output => &self.outputs,
        }
    }

    /// The index a client's `signal` (a number or a configured name)
    /// stands for, with its configuration if it has one.
    pub fn resolve(&self, kind: IoKind, signal: &str) -> Result<(u16, Option<&SignalConfig>)> {
        let list = self.list(kind);
        if let Some(s) = list.iter().find(|s| s.name == signal) {
            return Ok((s.index, Some(s)));
        }
        if signal.bytes().all(|b| b.is_ascii_digit()) && !signal.is_empty() {
            let index: u16 = signal
                .parse()
                .ok()
                .filter(|i| (1..=MAX_IO_INDEX).contains(i))
                .ok_or_else(|| {
                    BridgeError::invalid(format!(
                        "{}[{}] does not exist: indices are 1..={MAX_IO_INDEX}",
                        kind.krl(),
                        clip(signal, 12)
                    ))
                })?;
            return Ok((index, list.iter().find(|s| s.index == index)));
        }
        let shown: String = signal.chars().take(40).collect();
        Err(BridgeError::new(
            ErrorCode::UnknownSignal,
            format!(
                "no {} is named {shown:?}: use a number (1..={MAX_IO_INDEX}) or a name from the site's [io] configuration",
                match kind {
                    IoKind::Input => "input",
                    IoKind::Output => "output",
                }
            ),
        ))
    }

    /// The output's entry if clients may write it.
    pub fn writable(&self, index: u16) -> Result<&SignalConfig> {
        self.outputs
            .iter()
            .find(|s| s.index == index)
            .ok_or_else(|| {
                BridgeError::new(
                    ErrorCode::OutputNotAllowed,
                    format!(
                        "$OUT[{index}] is not on the site's list of outputs clients may write ([io] outputs in the configuration)"
                    ),
                )
            })
    }

    /// The configured name of a signal, if any.
    pub fn name_of(&self, kind: IoKind, index: u16) -> Option<&str> {
        self.list(kind)
            .iter()
            .find(|s| s.index == index)
            .map(|s| s.name.as_str())
    }

    /// Whether changes of the signal are pushed as events.
    pub fn watched(&self, kind: IoKind, index: u16) -> bool {
        self.list(kind).iter().any(|s| s.index == index && s.watch)
    }
}

/// A digital output to set (`PUT /api/v1/io/outputs/{signal}`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputRequest {
    /// `$OUT` index.
    pub index: u16,
    /// The value.
    pub value: bool,
    /// 0: stays; else returns to `!value` after this many ms.
    pub pulse_ms: u32,
}

/// The I/O the controller reported in its last state file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, ToSchema)]
pub struct IoWindow {
    /// Index of the first signal (`inputs[0]` is `$IN[base]`).
    #[schema(minimum = 1, maximum = 4066)]
    pub base: u16,
    /// `$IN[base..base+30]`.
    pub inputs: Vec<bool>,
    /// `$OUT[base..base+30]`.
    pub outputs: Vec<bool>,
}

impl From<&IoState> for IoWindow {
    fn from(s: &IoState) -> Self {
        let bits = |v: u32| (0..IoState::WIDTH).map(|k| v & (1 << k) != 0).collect();
        IoWindow {
            base: s.base,
            inputs: bits(s.inputs),
            outputs: bits(s.outputs),
        }
    }
}

impl IoWindow {
    /// The value of a signal, if the window holds it.
    pub fn get(&self, kind: IoKind, index: u16) -> Option<bool> {
        let k = usize::from(index.checked_sub(self.base)?);
        match kind {
            IoKind::Input => self.inputs.get(k).copied(),
            IoKind::Output => self.outputs.get(k).copied(),
        }
    }
}

/// A watched signal changed (the `io` event).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, ToSchema)]
pub struct IoChange {
    /// Input or output.
    pub kind: IoKind,
    /// Its index.
    #[schema(minimum = 1, maximum = 4096)]
    pub index: u16,
    /// Its configured name.
    pub name: Option<String>,
    /// The new value.
    pub value: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn analog(name: &str, index: u8, watch: bool, deadband: f64) -> AnalogConfig {
        AnalogConfig {
            name: name.into(),
            index,
            watch,
            deadband,
        }
    }

    #[test]
    fn watched_analog_channels_must_be_reported_and_have_a_sane_deadband() {
        let with = |a: AnalogConfig| IoConfig {
            analog_inputs: vec![a],
            ..IoConfig::default()
        };
        assert_eq!(with(analog("force", 8, true, 0.01)).validate(), Ok(()));
        // Not watched: any channel 1..=32 may be named.
        assert_eq!(with(analog("force", 32, false, 0.01)).validate(), Ok(()));
        let e = with(analog("force", 9, true, 0.01)).validate();
        assert!(
            e.as_ref().is_err_and(|e| e.contains("cannot be watched")),
            "{e:?}"
        );
        for bad in [0.0, -0.1, 2.5, f64::NAN, f64::INFINITY] {
            let e = with(analog("force", 1, true, bad)).validate();
            assert!(
                e.as_ref().is_err_and(|e| e.contains("deadband")),
                "{bad}: {e:?}"
            );
        }
    }
}
