//! Time and ids every part of the service shares: Unix milliseconds and
//! the job id type. A leaf module (it imports nothing of the crate), so the
//! engine, access control and the program store can all use it without
//! importing each other.

/// Job identifier: increasing, unique across restarts of the service
/// (persisted in blocks, see the engine's job id store).
pub type JobId = u64;

/// Unix time in ms.
pub fn now_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64)
}
