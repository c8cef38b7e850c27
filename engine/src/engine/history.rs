//! Event ids and the bounded history of recent events, so that a client
//! that reconnects (SSE `Last-Event-ID`) or a page that reloads gets what
//! it missed.
//!
//! Job, plan and alarm events get ids that increase by one per event; the
//! first id of a run is the Unix time in ms when the engine started, so a
//! restarted service's ids lie above the previous run's (unless that run
//! published more than a thousand events per second on average). State
//! events get no id and are not kept: each is a snapshot, and a stream
//! (re)starts with the current state.

use std::collections::VecDeque;

use tokio::sync::broadcast;

use super::{Event, RobotState};

/// Most events kept.
pub const HISTORY_EVENTS: usize = 1000;
/// Most planned motions kept over all plan events (a batch may hold 1000).
const HISTORY_PLANNED_MOTIONS: usize = 20_000;

/// An event as published: with its id (`None` for state events) and the
/// Unix time in ms it was published.
#[derive(Debug, Clone)]
pub struct Published {
    /// Its id (job, plan and alarm events), `None` for state events.
    pub id: Option<u64>,
    /// When it was published (Unix ms).
    pub at_ms: u64,
    /// The event.
    pub event: Event,
}

/// What a (re)connecting subscriber gets, taken at one instant: nothing is
/// missed between `missed` and `live`, nothing comes twice.
pub struct Replay {
    /// The held events after the id it gave, oldest first.
    pub missed: Vec<Published>,
    /// How many events after that id are no longer held (0 for an id this
    /// run did not issue).
    pub lost: u64,
    /// The state at that instant (streams start with it).
    pub state: RobotState,
    /// Everything published from that instant on.
    pub live: broadcast::Receiver<Published>,
}

/// The id counter and the ring of recent events.
pub(crate) struct History {
    /// The id the next event gets.
    next: u64,
    /// The first id of this run.
    first: u64,
    events: VecDeque<Published>,
    planned_motions: usize,
}

fn planned(event: &Event) -> usize {
    match event {
        Event::Plan(p) => p.motions.len(),
        _ => 0,
    }
}

impl History {
    pub(crate) fn new(first: u64) -> History {
        History {
            next: first,
            first,
            events: VecDeque::new(),
            planned_motions: 0,
        }
    }

    /// Numbers `event` and keeps it (not state events).
    pub(crate) fn stamp(&mut self, event: Event, at_ms: u64) -> Published {
        if matches!(event, Event::State(_)) {
            return Published {
                id: None,
                at_ms,
                event,
            };
        }
        let p = Published {
            id: Some(self.next),
            at_ms,
            event,
        };
        self.next += 1;
        self.planned_motions += planned(&p.event);
        self.events.push_back(p.clone());
        while self.events.len() > HISTORY_EVENTS
            || (self.planned_motions > HISTORY_PLANNED_MOTIONS && self.events.len() > 1)
        {
            if let Some(old) = self.events.pop_front() {
                self.planned_motions -= planned(&old.event);
            }
        }
        p
    }

    /// True when this run issued `id` (or it is the id just before its first).
    fn issued(&self, id: u64) -> bool {
        id.saturating_add(1) >= self.first && id < self.next
    }

    /// The held events after `after`, and how many after it are no longer
    /// held. `None`, 0 or an id this run did not issue (another run's):
    /// every event held, none counted lost.
    pub(crate) fn after(&self, after: Option<u64>) -> (Vec<Published>, u64) {
        let from = match after {
            Some(id) if id != 0 && self.issued(id) => id,
            _ => return (self.events.iter().cloned().collect(), 0),
        };
        let oldest = self.events.front().and_then(|p| p.id).unwrap_or(self.next);
        let lost = oldest.saturating_sub(from + 1);
        let missed = self
            .events
            .iter()
            .filter(|p| p.id.is_some_and(|id| id > from))
            .cloned()
            .collect();
        (missed, lost)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{BridgeError, ErrorCode};

    fn alarm() -> Event {
        Event::Alarm(BridgeError::new(ErrorCode::ControllerOffline, "x"))
    }

    #[test]
    fn ids_count_kept_events_and_the_ring_is_bounded() {
        let mut h = History::new(1000);
        assert_eq!(h.stamp(alarm(), 1).id, Some(1000));
        assert_eq!(h.stamp(alarm(), 2).id, Some(1001));
        for _ in 0..HISTORY_EVENTS + 10 {
            h.stamp(alarm(), 3);
        }
        assert_eq!(h.events.len(), HISTORY_EVENTS);
        let newest = h.next - 1;
        // A client at the newest id missed nothing.
        assert_eq!(h.after(Some(newest)).0.len(), 0);
        // One five events back gets those five.
        let (missed, lost) = h.after(Some(newest - 5));
        assert_eq!((missed.len(), lost), (5, 0));
        // One at the first id lost the eleven no longer held after it (1001 ..= 1011).
        let (missed, lost) = h.after(Some(1000));
        assert_eq!((missed.len(), lost), (HISTORY_EVENTS, 11));
        // Another run's id, 0 or none: everything held, nothing counted lost.
        for after in [None, Some(0), Some(5), Some(newest + 100)] {
            let (missed, lost) = h.after(after);
            assert_eq!((missed.len(), lost), (HISTORY_EVENTS, 0), "{after:?}");
        }
    }
}
