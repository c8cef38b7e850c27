//! Keeps the plugin registry in step with the plugins folder: change events
//! from `notify` trigger a scan (after a short settle time, so a file being
//! copied is read once complete), and a periodic scan is the source of
//! truth (network folders and overflowing Windows change buffers lose
//! events).

use std::sync::Arc;
use std::time::Duration;

use notify::Watcher;
use tokio::sync::{mpsc, watch};

use super::PluginRegistry;

/// Quiet time after the last change event before scanning.
const SETTLE: Duration = Duration::from_millis(150);

/// Longest wait for quiet: a folder that never stops changing is scanned anyway.
const MAX_SETTLE: Duration = Duration::from_secs(1);

/// Scans the folder on every change and every `poll` (the first tick is at
/// once), until `closing` turns true.
pub async fn run(
    registry: Arc<PluginRegistry>,
    poll: Duration,
    mut closing: watch::Receiver<bool>,
) {
    let (tx, mut rx) = mpsc::channel::<()>(1);
    // Kept alive for as long as this task runs; without it the poll still works.
    let _watcher = match notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
        // Reads (including the scan's own) are not changes.
        if !matches!(&event, Ok(e) if matches!(e.kind, notify::EventKind::Access(_))) {
            let _ = tx.try_send(());
        }
    }) {
        Ok(mut w) => match w.watch(registry.dir(), notify::RecursiveMode::NonRecursive) {
            Ok(()) => Some(w),
            Err(e) => {
                tracing::warn!(dir = %registry.dir().display(), error = %e, "cannot watch the plugins folder; polling only");
                None
            }
        },
        Err(e) => {
            tracing::warn!(error = %e, "no file watcher; polling the plugins folder only");
            None
        }
    };
    let mut tick = tokio::time::interval(poll);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        let deep = tokio::select! {
            () = async { let _ = closing.wait_for(|c| *c).await; } => break,
            _ = tick.tick() => false,
            Some(()) = rx.recv() => {
                // Let a copy finish: wait until events stop for SETTLE.
                let until = tokio::time::Instant::now() + MAX_SETTLE;
                while tokio::time::Instant::now() < until
                    && tokio::time::timeout(SETTLE, rx.recv()).await.is_ok_and(|e| e.is_some())
                {}
                true
            }
        };
        registry.scan(deep).await;
    }
}
