//! A tracing layer that reports to the Windows Event Log (Application log,
//! source [`EVENT_SOURCE`]): warnings and errors, and any event with
//! an `event_id` field (ids in [`crate::event_ids`]). The message
//! file registered for the source is `EventCreate.exe`, whose messages are
//! the text itself (ids 1–1000), so the entries read as the log lines do.
//!
//! Like [`super::process`], it calls the Win32 API directly.
#![allow(unsafe_code)]

use std::fmt::Write as _;

use tracing::field::{Field, Visit};
use tracing::{Event, Level, Subscriber};
use tracing_subscriber::Layer;
use tracing_subscriber::layer::Context;
use windows_sys::Win32::Foundation::HANDLE;
use windows_sys::Win32::System::EventLog::{
    DeregisterEventSource, EVENTLOG_ERROR_TYPE, EVENTLOG_INFORMATION_TYPE, EVENTLOG_WARNING_TYPE,
    RegisterEventSourceW, ReportEventW,
};

use crate::event_ids as events;

/// Event Log source (Application log).
pub const EVENT_SOURCE: &str = "kuka-bridge";

/// Reports events to the Event Log.
pub struct EventLogLayer {
    handle: HANDLE,
}

// SAFETY: an event source handle may be used from any thread (the Win32
// documentation places no thread affinity on RegisterEventSource handles).
unsafe impl Send for EventLogLayer {}
// SAFETY: ReportEventW is thread-safe for one handle.
unsafe impl Sync for EventLogLayer {}

fn wide(s: &str) -> Vec<u16> {
    s.encode_utf16().chain(std::iter::once(0)).collect()
}

impl EventLogLayer {
    /// Opens the event source; `None` if Windows refuses (then nothing is
    /// reported, the rest of logging goes on).
    pub fn new(source: &str) -> Option<Self> {
        let name = wide(source);
        // SAFETY: `name` is a NUL-terminated UTF-16 string that outlives the
        // call; a null server name means the local computer.
        let handle = unsafe { RegisterEventSourceW(std::ptr::null(), name.as_ptr()) };
        (!handle.is_null()).then_some(EventLogLayer { handle })
    }

    fn report(&self, kind: u16, id: u32, text: &str) {
        // Event Log strings are limited to 31,839 characters.
        let text: String = text.chars().take(30_000).collect();
        let msg = wide(&text);
        let strings = [msg.as_ptr()];
        // SAFETY: `self.handle` is a valid event source handle until drop;
        // `strings` holds one pointer to a NUL-terminated UTF-16 string that
        // lives until the call returns; no raw data (null, size 0).
        unsafe {
            ReportEventW(
                self.handle,
                kind,
                0,
                id,
                std::ptr::null_mut(),
                1,
                0,
                strings.as_ptr(),
                std::ptr::null(),
            );
        }
    }
}

impl Drop for EventLogLayer {
    fn drop(&mut self) {
        // SAFETY: the handle came from RegisterEventSourceW and is closed once.
        unsafe {
            DeregisterEventSource(self.handle);
        }
    }
}

/// Collects the message, the `event_id` and the other fields of an event.
#[derive(Default)]
struct Collect {
    message: String,
    fields: String,
    event_id: Option<u32>,
}

impl Visit for Collect {
    fn record_u64(&mut self, field: &Field, value: u64) {
        if field.name() == "event_id" {
            self.event_id = u32::try_from(value).ok();
        } else {
            let _ = write!(self.fields, " {}={value}", field.name());
        }
    }

    fn record_i64(&mut self, field: &Field, value: i64) {
        if field.name() == "event_id" {
            self.event_id = u32::try_from(value).ok();
        } else {
            let _ = write!(self.fields, " {}={value}", field.name());
        }
    }

    fn record_str(&mut self, field: &Field, value: &str) {
        if field.name() == "message" {
            self.message.push_str(value);
        } else {
            let _ = write!(self.fields, " {}={value:?}", field.name());
        }
    }

    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            let _ = write!(self.message, "{value:?}");
        } else {
            let _ = write!(self.fields, " {}={value:?}", field.name());
        }
    }
}

impl<S: Subscriber> Layer<S> for EventLogLayer {
    fn on_event(&self, event: &Event<'_>, _ctx: Context<'_, S>) {
        let level = *event.metadata().level();
        let mut c = Collect::default();
        event.record(&mut c);
        let (kind, default_id) = match level {
            Level::ERROR => (EVENTLOG_ERROR_TYPE, events::ERROR),
            Level::WARN => (EVENTLOG_WARNING_TYPE, events::WARNING),
            // Information only when the event asks for the Event Log.
            _ if c.event_id.is_some() => (EVENTLOG_INFORMATION_TYPE, 0),
            _ => return,
        };
        let id = c.event_id.unwrap_or(default_id);
        self.report(kind, id, &format!("{}{}", c.message, c.fields));
    }
}
