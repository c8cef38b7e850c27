//! The simulated plant of `--simulate`: inputs that follow outputs
//! (`[simulator] links`), such as a part-present sensor that reports a
//! part once the gripper has closed. It watches the simulated controller's
//! outputs in its memory (not through the state file) and sets each linked
//! input `delay_ms` of simulated time after its output changed, for both
//! simulated controllers alike, as a plant wired to the controller would.

use std::sync::Arc;
use std::time::Duration;

use serde::{Deserialize, Serialize};
use tokio::sync::watch;

/// One link: `$IN[input]` takes the value of `$OUT[output]` (inverted
/// with `invert`) `delay_ms` after it changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputLink {
    /// The output watched, 1..=4096.
    pub output: u16,
    /// The input set, 1..=4096.
    pub input: u16,
    /// Simulated ms between the output's change and the input's.
    #[serde(default)]
    pub delay_ms: u64,
    /// The input takes the opposite value (e.g. "gripper open" sensor).
    #[serde(default)]
    pub invert: bool,
}

impl InputLink {
    /// Why the link is invalid, if it is.
    pub fn check(&self) -> Result<(), String> {
        let max = kuka_protocol::MAX_IO_INDEX;
        if !(1..=max).contains(&self.output) || !(1..=max).contains(&self.input) {
            return Err(format!(
                "output {} and input {} must be in 1..={max}",
                self.output, self.input
            ));
        }
        if self.delay_ms > 60_000 {
            return Err(format!("delay_ms {} is above 60000", self.delay_ms));
        }
        Ok(())
    }
}

/// The simulated controller the plant is wired to.
/// (Weak: the plant never keeps a stopped simulator, and its channel
/// lock, alive.)
#[derive(Clone)]
pub enum Wired {
    /// The native simulator.
    Native(std::sync::Weak<kuka_sim::SimController>),
    /// The KRC-like runtime.
    Krc(std::sync::Weak<kuka_krc::KrcController>),
}

impl Wired {
    /// The plant of a running simulated controller.
    pub fn native(s: &Arc<kuka_sim::SimController>) -> Self {
        Wired::Native(Arc::downgrade(s))
    }

    /// The plant of the KRC-like runtime.
    pub fn krc(k: &Arc<kuka_krc::KrcController>) -> Self {
        Wired::Krc(Arc::downgrade(k))
    }

    fn output(&self, index: u16) -> Option<bool> {
        match self {
            Wired::Native(s) => s.upgrade()?.io(true, index),
            Wired::Krc(k) => k.upgrade()?.bool_element("$OUT", i64::from(index)),
        }
    }

    fn set_input(&self, index: u16, value: bool) {
        let set = match self {
            Wired::Native(s) => s.upgrade().is_some_and(|s| s.set_input(index, value)),
            Wired::Krc(k) => k
                .upgrade()
                .is_some_and(|k| k.set_bool_element("$IN", i64::from(index), value)),
        };
        if !set {
            tracing::warn!(index, "the simulated plant could not set the input");
        }
    }
}

/// How often the plant looks at the outputs (wall time).
const POLL: Duration = Duration::from_millis(4);

/// Runs the plant until `closing` turns true. `time_scale` converts the
/// links' simulated delays to wall time (0: at once).
pub async fn run(
    links: Vec<InputLink>,
    wired: Wired,
    time_scale: f64,
    mut closing: watch::Receiver<bool>,
) {
    if links.is_empty() {
        return;
    }
    let mut seen: Vec<Option<bool>> = links.iter().map(|l| wired.output(l.output)).collect();
    // Inputs due: (when, input, value).
    let mut due: Vec<(tokio::time::Instant, u16, bool)> = Vec::new();
    // The inputs start as their outputs are.
    for (l, v) in links.iter().zip(&seen) {
        if let Some(v) = v {
            wired.set_input(l.input, *v != l.invert);
        }
    }
    let mut tick = tokio::time::interval(POLL);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            _ = tick.tick() => {}
            _ = closing.changed() => return,
        }
        if *closing.borrow() {
            return;
        }
        let now = tokio::time::Instant::now();
        for (l, last) in links.iter().zip(seen.iter_mut()) {
            let v = wired.output(l.output);
            if v != *last {
                *last = v;
                if let Some(v) = v {
                    let wall = if time_scale > 0.0 {
                        Duration::from_secs_f64(l.delay_ms as f64 / 1000.0 / time_scale)
                    } else {
                        Duration::ZERO
                    };
                    tracing::debug!(
                        output = l.output,
                        input = l.input,
                        value = v,
                        "simulated plant: output changed"
                    );
                    due.push((now + wall, l.input, v != l.invert));
                }
            }
        }
        due.retain(|&(at, input, value)| {
            if at <= now {
                wired.set_input(input, value);
                false
            } else {
                true
            }
        });
    }
}
