//! `GET /api/v1/events`: Server-Sent Events for job progress, state
//! changes and alarms, optionally filtered by type.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::State;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use futures_util::{Stream, StreamExt};
use serde::Deserialize;
use tokio_stream::wrappers::BroadcastStream;
use tokio_stream::wrappers::errors::BroadcastStreamRecvError;
use utoipa::IntoParams;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use super::AppState;
use super::auth::Who;
use super::problem::{Problem, QueryParams};
use crate::engine::Event;
use crate::error::BridgeError;

/// Event filter.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct EventsQuery {
    /// Comma-separated event types to receive: `job`, `state`, `alarm`, `plan` (default: all).
    types: Option<String>,
}

/// Live events (Server-Sent Events).
///
/// Each SSE message has `event:` = `job`, `state`, `alarm` or `plan` and `data:` = the JSON
/// of the job, the robot state, the error (`code`, `detail`, `axis`, `motion`) or the
/// planned path of a move job (`JobPlan`, sent when its motions are written to the
/// controller, before they run). A state event follows each heartbeat
/// that changed something. A `lagged` event says the client was too slow and missed
/// some. The stream starts with the current state, and ends when the service
/// shuts down or the caller's token is revoked.
#[utoipa::path(get, path = "/api/v1/events", tag = "events", params(EventsQuery),
    responses((status = 200, description = "text/event-stream of job, state, alarm and plan events", content_type = "text/event-stream", body = String), (status = 422, description = "Unknown event type", body = super::problem::ProblemDetails, content_type = super::problem::PROBLEM_JSON)))]
async fn events(
    State(app): State<AppState>,
    who: Who,
    QueryParams(q): QueryParams<EventsQuery>,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, Problem> {
    let wanted: Option<Vec<String>> = q
        .types
        .map(|t| t.split(',').map(|s| s.trim().to_string()).collect());
    if let Some(bad) = wanted
        .iter()
        .flatten()
        .find(|t| !["job", "state", "alarm", "plan"].contains(&t.as_str()))
    {
        return Err(BridgeError::invalid(format!(
            "unknown event type {bad:?}; use job, state, alarm or plan"
        ))
        .into());
    }
    let want = move |name: &str| wanted.as_ref().is_none_or(|w| w.iter().any(|x| x == name));
    let first = Event::State(Box::new(app.engine.state()));
    let rx = app.engine.subscribe();
    let stream = futures_util::stream::iter([Ok(first)])
        .chain(BroadcastStream::new(rx))
        .filter_map(move |item| {
            let out = match item {
                Ok(ev) => {
                    let (name, data) = match &ev {
                        Event::Job(j) => ("job", serde_json::to_string(j)),
                        Event::State(s) => ("state", serde_json::to_string(s)),
                        Event::Alarm(e) => ("alarm", serde_json::to_string(e)),
                        Event::Plan(p) => ("plan", serde_json::to_string(p)),
                    };
                    match data {
                        Ok(data) if want(name) => {
                            Some(Ok(SseEvent::default().event(name).data(data)))
                        }
                        _ => None,
                    }
                }
                Err(BroadcastStreamRecvError::Lagged(n)) => {
                    Some(Ok(SseEvent::default().event("lagged").data(n.to_string())))
                }
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
    OpenApiRouter::new().routes(routes!(events))
}
