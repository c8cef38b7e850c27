//! Giving freed memory back to the operating system. glibc's allocator
//! keeps what a thread freed in that thread's arena for later use: after a
//! plugin is compiled (hundreds of MiB of Cranelift's working memory for a
//! Python plugin, on a compiler thread) or removed, the service's resident
//! memory would stay at its peak. Two things, on Linux with glibc only
//! (elsewhere both do nothing); measured in docs/BENCHMARKS.md §7:
//!
//! - [`tune_allocator`], once per process: fixed thresholds instead of
//!   glibc's dynamic ones. Freeing a large block (the 19 MB upload of a
//!   Python plugin) raises the dynamic `mmap` threshold to its size and
//!   the trim threshold to twice that, and from then on up to ~40 MiB of
//!   free memory at the top of each thread arena is never returned, not
//!   even by `malloc_trim` (it trims only the main arena's top). With 1 MiB
//!   and 2 MiB, blocks of 1 MiB and more are mapped and unmapped on their
//!   own, and an arena keeps at most 2 MiB of free top. Compiling a Python
//!   plugin took as long either way (128 KiB, glibc's initial value,
//!   made it three times slower). An operator's own `MALLOC_*_` or
//!   `GLIBC_TUNABLES` settings win: then nothing is changed.
//! - [`trim_soon`] after a load and when a plugin is dropped: returns the
//!   free pages inside every arena (`malloc_trim(0)`), on a blocking thread.

use std::sync::atomic::{AtomicBool, Ordering};

/// Sets fixed allocator thresholds (see the module's documentation), once.
pub(crate) fn tune_allocator() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let operator_set = ["MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_"]
            .iter()
            .any(|v| std::env::var_os(v).is_some())
            || std::env::var("GLIBC_TUNABLES").is_ok_and(|t| t.contains("glibc.malloc."));
        if operator_set {
            tracing::info!("allocator thresholds left as the environment sets them");
            return;
        }
        set_thresholds();
    });
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn set_thresholds() {
    // SAFETY: mallopt only changes two of the allocator's parameters
    // (under its own lock); it has no preconditions.
    #[allow(unsafe_code)]
    let ok = unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20) == 1
            && libc::mallopt(libc::M_TRIM_THRESHOLD, 2 << 20) == 1
    };
    if !ok {
        tracing::warn!("mallopt refused the allocator thresholds; freed memory may stay resident");
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn set_thresholds() {}

/// A trim is queued and has not started yet (several requests make one).
static PENDING: AtomicBool = AtomicBool::new(false);

/// Returns the allocator's free memory to the operating system, soon and
/// off the caller's thread (on a tokio blocking thread when a runtime is
/// there, else at once).
pub(crate) fn trim_soon() {
    if !cfg!(all(target_os = "linux", target_env = "gnu")) {
        return;
    }
    if PENDING.swap(true, Ordering::AcqRel) {
        return;
    }
    let run = || {
        PENDING.store(false, Ordering::Release);
        trim();
    };
    match tokio::runtime::Handle::try_current() {
        Ok(handle) => {
            handle.spawn_blocking(run);
        }
        Err(_) => run(),
    }
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn trim() {
    let started = std::time::Instant::now();
    // SAFETY: malloc_trim only walks the allocator's own free lists under
    // its arena locks and has no preconditions; any thread may call it.
    #[allow(unsafe_code)]
    unsafe {
        libc::malloc_trim(0);
    }
    tracing::debug!(
        ms = started.elapsed().as_secs_f64() * 1000.0,
        "freed memory returned to the operating system (malloc_trim)"
    );
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn trim() {}

/// Trims when dropped: the last field of a plugin, so its compiled code
/// and metadata are freed before.
#[derive(Debug, Default)]
pub(crate) struct TrimOnDrop;

impl Drop for TrimOnDrop {
    fn drop(&mut self) {
        trim_soon();
    }
}
