//! `GET /api/v1/events`: Server-Sent Events for job progress, state
//! changes and alarms, optionally filtered by type, replaying what a
//! reconnecting client missed (`Last-Event-ID`); `GET
//! /api/v1/events/recent`: the recent job, plan, alarm and io events as JSON.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::State;
use axum::http::HeaderMap;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use futures_util::{Stream, StreamExt};
use serde::{Deserialize, Serialize};
use tokio_stream::wrappers::BroadcastStream;
use tokio_stream::wrappers::errors::BroadcastStreamRecvError;
use utoipa::{IntoParams, ToSchema};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::AppState;
use super::auth::Who;
use super::problem::{Problem, QueryParams};
use crate::engine::{Event, HISTORY_EVENTS, Published};
use crate::error::BridgeError;

/// Event filter and replay position.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct EventsQuery {
    /// Comma-separated event types to receive: `job`, `state`, `alarm`, `plan`, `io`, `analog` (default: all).
    types: Option<String>,
    /// Replay the held job, plan, alarm, io and analog events after this event id before the live
    /// ones (for clients that cannot send the `Last-Event-ID` header, such as a browser's
    /// first `EventSource` connection); `0` replays every event held. The header wins
    /// when both are given.
    last_event_id: Option<u64>,
}

/// The types a stream may ask for.
const STREAM_TYPES: [&str; 6] = ["job", "state", "alarm", "plan", "io", "analog"];
/// The types the history holds (state events are snapshots: read `/api/v1/state`).
const HISTORY_TYPES: [&str; 5] = ["job", "plan", "alarm", "io", "analog"];

/// The `types` filter: `None` for all; an unknown name is refused.
fn wanted(types: Option<&str>, known: &[&str]) -> Result<Option<Vec<String>>, Problem> {
    let Some(types) = types else {
        return Ok(None);
    };
    let wanted: Vec<String> = types.split(',').map(|s| s.trim().to_string()).collect();
    if let Some(bad) = wanted.iter().find(|t| !known.contains(&t.as_str())) {
        let hint = if bad == "state" {
            " (state events are not kept: GET /api/v1/state gives the current state)"
        } else {
            ""
        };
        return Err(BridgeError::invalid(format!(
            "unknown event type {bad:?}; use {}{hint}",
            known.join(", ")
        ))
        .into());
    }
    Ok(Some(wanted))
}

/// The SSE event name of an event.
fn name(event: &Event) -> &'static str {
    match event {
        Event::Job(_) => "job",
        Event::State(_) => "state",
        Event::Alarm(_) => "alarm",
        Event::Plan(_) => "plan",
        Event::Io(_) => "io",
        Event::Analog(_) => "analog",
    }
}

/// The JSON an event carries (`data:` of the stream, `data` of the list).
fn data(event: &Event) -> serde_json::Result<String> {
    match event {
        Event::Job(j) => serde_json::to_string(j),
        Event::State(s) => serde_json::to_string(s),
        Event::Alarm(e) => serde_json::to_string(e),
        Event::Plan(p) => serde_json::to_string(p),
        Event::Io(c) => serde_json::to_string(c),
        Event::Analog(c) => serde_json::to_string(c),
    }
}

/// Where a stream starts: the `Last-Event-ID` header (an `EventSource`
/// reconnecting), else the `last_event_id` parameter, else live only.
fn replay_from(headers: &HeaderMap, query: Option<u64>) -> Result<Option<u64>, Problem> {
    let Some(value) = headers.get("last-event-id") else {
        return Ok(query);
    };
    let Ok(text) = value.to_str().map(str::trim) else {
        return Err(BridgeError::invalid(
            "Last-Event-ID is not visible ASCII text (an event id is a number)",
        )
        .into());
    };
    if text.is_empty() {
        return Ok(query);
    }
    text.parse().map(Some).map_err(|_| {
        BridgeError::invalid(format!(
            "Last-Event-ID {text:?} is not an event id of this service (a number)"
        ))
        .into()
    })
}

/// Live events (Server-Sent Events).
///
/// Each SSE message has `event:` = `job`, `state`, `alarm`, `plan`, `io` or `analog` and `data:` = the
/// JSON of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`), the
/// planned path of a move job (`JobPlan`, sent when its motions are written to the
/// controller, before they run), a watched digital signal that changed (`IoChange`,
/// docs/IO.md) or a watched analog channel that moved by its deadband (`AnalogChange`).
/// A state event follows each heartbeat
/// that changed something. A `lagged` event says the client was too slow and missed
/// some (`data:` how many). The stream starts with the current state, and ends when the
/// service shuts down or the caller's token is revoked.
///
/// Job, plan, alarm, io and analog events carry an `id:` that grows by one per event; the service
/// keeps the last 1000 of them. A client that reconnects with `Last-Event-ID` (browsers'
/// `EventSource` does so by itself) or `?last_event_id=` first gets the held events it
/// missed, then the current state, then live events; if some it missed are no longer
/// held, a `lagged` event says how many. State events carry no id and are not replayed
/// (the current state replaces them). An id from before a restart of the service replays
/// every event held.
#[utoipa::path(get, path = "/api/v1/events", tag = "events", operation_id = "streamEvents",
    params(EventsQuery, ("Last-Event-ID" = Option<u64>, Header, description = "The id of the last event received: replay the held events after it (sent by `EventSource` when it reconnects)")),
    responses((status = 200, description = "text/event-stream of job, state, alarm, plan, io and analog events", content_type = "text/event-stream", body = String), (status = 422, description = "Unknown event type, or an event id that is not a number", body = super::problem::ProblemDetails, content_type = super::problem::PROBLEM_JSON)))]
async fn events(
    State(app): State<AppState>,
    who: Who,
    headers: HeaderMap,
    QueryParams(q): QueryParams<EventsQuery>,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, Problem> {
    let wanted = wanted(q.types.as_deref(), &STREAM_TYPES)?;
    let after = replay_from(&headers, q.last_event_id)?;
    let want = move |name: &str| wanted.as_ref().is_none_or(|w| w.iter().any(|x| x == name));
    let replay = app.engine.replay(after);
    // Replays only when asked: a plain subscriber gets the state and live events.
    let missed = if after.is_some() {
        replay.missed
    } else {
        Vec::new()
    };
    // Lagged (too slow, or no longer held) goes as an `Err`: it has no `Published`.
    let lost = (replay.lost > 0).then(|| {
        Err(SseEvent::default()
            .event("lagged")
            .data(replay.lost.to_string()))
    });
    let first = Published {
        id: None,
        at_ms: 0,
        event: Event::State(Box::new(replay.state)),
    };
    let earlier = lost
        .into_iter()
        .chain(missed.into_iter().chain([first]).map(Ok));
    let stream = futures_util::stream::iter(earlier)
        .chain(BroadcastStream::new(replay.live).map(|item| match item {
            Ok(p) => Ok(p),
            Err(BroadcastStreamRecvError::Lagged(n)) => {
                Err(SseEvent::default().event("lagged").data(n.to_string()))
            }
        }))
        .filter_map(move |item| {
            let out = match item {
                Ok(p) => {
                    let name = name(&p.event);
                    match data(&p.event) {
                        Ok(json) if want(name) => {
                            let mut e = SseEvent::default().event(name).data(json);
                            if let Some(id) = p.id {
                                e = e.id(id.to_string());
                            }
                            Some(Ok(e))
                        }
                        _ => None,
                    }
                }
                Err(lagged) => Some(Ok(lagged)),
            };
            std::future::ready(out)
        });
    let mut closing = app.closing.clone();
    let revoked = token_revoked(&app, who.principal());
    let stream = stream.take_until(async move {
        tokio::select! {
            _ = closing.wait_for(|c| *c) => {}
            () = revoked => {}
        }
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::new().interval(Duration::from_secs(15))))
}

/// Which recent events to list.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct RecentQuery {
    /// How many of the newest events to list, 1 to 1000 (default 100).
    limit: Option<usize>,
    /// Comma-separated types to list: `job`, `plan`, `alarm`, `io`, `analog` (default: all).
    types: Option<String>,
    /// Only events after this event id (for a client polling instead of streaming).
    after: Option<u64>,
}

/// A job, plan, alarm, io or analog event as the service published it.
#[derive(Debug, Serialize, ToSchema)]
#[schema(example = json!({"id": 1795629212950_u64, "type": "job", "at_ms": 1795629212958_u64,
    "data": {"id": 7, "operation": "move", "state": "done", "motions": 1, "completed": 1}}))]
pub struct RecentEvent {
    /// The event id (the SSE `id:`; grows by one per job, plan, alarm, io or analog event).
    id: u64,
    /// `job`, `plan`, `alarm`, `io` or `analog` (the SSE `event:`).
    #[serde(rename = "type")]
    kind: &'static str,
    /// When the service published it (Unix ms).
    at_ms: u64,
    /// What the SSE `data:` carries: the `Job`, the `JobPlan`, the error (`code`,
    /// `detail`, `axis`, `motion`), the `IoChange` or the `AnalogChange`.
    #[schema(value_type = Object)]
    data: serde_json::Value,
}

/// Recent job, plan, alarm, io and analog events.
///
/// The newest events the service still holds (it keeps the last 1000 job, plan, alarm, io and analog
/// events of this run; state events are not kept), oldest first, with the ids and data of
/// the event stream: a page that reloads shows what happened before, then opens
/// `GET /api/v1/events?last_event_id=<the last id>` to continue without a gap.
#[utoipa::path(get, path = "/api/v1/events/recent", tag = "events", operation_id = "listRecentEvents",
    params(RecentQuery),
    responses((status = 200, description = "The newest events held, oldest first", body = Vec<RecentEvent>),
        (status = 422, description = "Unknown event type, or a limit outside 1 to 1000", body = super::problem::ProblemDetails, content_type = super::problem::PROBLEM_JSON)))]
async fn recent(
    State(app): State<AppState>,
    QueryParams(q): QueryParams<RecentQuery>,
) -> Result<axum::Json<Vec<RecentEvent>>, Problem> {
    let limit = q.limit.unwrap_or(100);
    if !(1..=HISTORY_EVENTS).contains(&limit) {
        return Err(BridgeError::invalid(format!(
            "limit {limit} is outside 1 to {HISTORY_EVENTS}"
        ))
        .into());
    }
    let wanted = wanted(q.types.as_deref(), &HISTORY_TYPES)?;
    let held = app.engine.held_events(q.after);
    let mut out: Vec<RecentEvent> = held
        .iter()
        .filter(|p| {
            wanted
                .as_ref()
                .is_none_or(|w| w.iter().any(|t| t == name(&p.event)))
        })
        .rev()
        .take(limit)
        .filter_map(|p| {
            Some(RecentEvent {
                id: p.id?,
                kind: name(&p.event),
                at_ms: p.at_ms,
                data: data(&p.event).and_then(|d| serde_json::from_str(&d)).ok()?,
            })
        })
        .collect();
    out.reverse();
    Ok(axum::Json(out))
}

/// Resolves when the caller's token is revoked (or replaced by a new one
/// with the same name), so a stream never outlives its token; never when
/// access control is off.
fn token_revoked(
    app: &AppState,
    who: &crate::access::Principal,
) -> impl std::future::Future<Output = ()> + use<> {
    let access = app.access.clone();
    let token = Some(who)
        .filter(|_| access.enabled)
        .and_then(|p| access.tokens.get(&p.name));
    async move {
        let Some(token) = token else {
            return std::future::pending().await;
        };
        let mut tick = tokio::time::interval(Duration::from_millis(250));
        loop {
            tick.tick().await;
            if access.tokens.get(&token.name).map(|t| t.created_ms) != Some(token.created_ms) {
                return;
            }
        }
    }
}

pub(super) fn router() -> OpenApiRouter<AppState> {
    OpenApiRouter::new()
        .routes(routes!(events))
        .routes(routes!(recent))
}
