//! One writer at a time ("mastership"): an operator takes control and gets a
//! lease that every one of its mutating calls renews; while the lease is
//! alive, mutating calls of other clients are refused with `control_held`.
//! A lease lapses when its holder goes silent (no call, and none of its
//! calls still running), so a crashed client never blocks the robot. Stop
//! never needs control. An admin may take over.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use serde::Serialize;
use utoipa::ToSchema;

use super::{Principal, Role};
use crate::error::{BridgeError, ErrorCode};

/// A live lease, as the API shows it.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({"id": "5f1c0a9e2b7d4c31", "holder": "line-3-pc", "role": "operator", "acquired_ms": 1763856000000_u64, "expires_ms": 1763856030000_u64, "lease_ms": 30000}))]
pub struct Lease {
    /// Lease id (changes when control changes hands).
    pub id: String,
    /// The token name holding control.
    pub holder: String,
    /// Its role.
    pub role: Role,
    /// When control was taken (Unix ms).
    pub acquired_ms: u64,
    /// When the lease lapses unless renewed (Unix ms).
    pub expires_ms: u64,
    /// Lease length; each mutating call of the holder renews it.
    pub lease_ms: u64,
}

#[derive(Debug)]
struct Held {
    lease: Lease,
    expires: Instant,
    /// The holder's calls still running (a long motion keeps the lease).
    active: usize,
}

/// Held by a call of the control holder while it runs; when it ends the
/// lease is renewed from that moment.
#[derive(Debug)]
pub struct InUse {
    control: Arc<Control>,
    lease_id: String,
}

impl Drop for InUse {
    fn drop(&mut self) {
        let mut g = self.control.lock();
        if let Some(h) = g.as_mut().filter(|h| h.lease.id == self.lease_id) {
            h.active = h.active.saturating_sub(1);
            self.control.renew(h);
        }
    }
}

/// The control lease of the robot.
#[derive(Debug)]
pub struct Control {
    held: Mutex<Option<Held>>,
    ttl: Duration,
}

impl Control {
    /// No one holds control; leases last `ttl` from their last use.
    pub fn new(ttl: Duration) -> Control {
        Control {
            held: Mutex::new(None),
            ttl,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Option<Held>> {
        let mut g = self
            .held
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if g.as_ref()
            .is_some_and(|h| h.active == 0 && h.expires <= Instant::now())
            && let Some(h) = g.take()
        {
            tracing::info!(holder = %h.lease.holder, lease = %h.lease.id, "control lease lapsed");
        }
        g
    }

    fn renew(&self, h: &mut Held) {
        h.expires = Instant::now() + self.ttl;
        h.lease.expires_ms = crate::clock::now_ms() + self.ttl.as_millis() as u64;
    }

    /// The current lease, if any (while one of the holder's calls runs,
    /// it cannot lapse before `lease_ms` from now).
    pub fn current(&self) -> Option<Lease> {
        self.lock().as_ref().map(|h| {
            let mut lease = h.lease.clone();
            if h.active > 0 {
                lease.expires_ms = crate::clock::now_ms() + self.ttl.as_millis() as u64;
            }
            lease
        })
    }

    fn held_error(h: &Held) -> BridgeError {
        let left = h.expires.saturating_duration_since(Instant::now());
        BridgeError::new(
            ErrorCode::ControlHeld,
            format!(
                "{} ({}) holds control of the robot; its lease lapses in {:.0} s unless used (an admin can take over)",
                h.lease.holder,
                h.lease.role,
                left.as_secs_f64().ceil()
            ),
        )
    }

    /// Takes or renews control. Another live holder is only replaced when
    /// `take_over` is asked by an admin.
    pub fn acquire(&self, who: &Principal, take_over: bool) -> Result<Lease, BridgeError> {
        let mut g = self.lock();
        if let Some(h) = g.as_mut() {
            if h.lease.holder == who.name {
                self.renew(h);
                return Ok(h.lease.clone());
            }
            if !(take_over && who.role == Role::Admin) {
                return Err(Self::held_error(h));
            }
            tracing::warn!(from = %h.lease.holder, to = %who.name, "control taken over by an admin");
        }
        let now = crate::clock::now_ms();
        let id = super::tokens::random_hex(8).unwrap_or_else(|_| format!("{now:x}"));
        let lease = Lease {
            id,
            holder: who.name.clone(),
            role: who.role,
            acquired_ms: now,
            expires_ms: now + self.ttl.as_millis() as u64,
            lease_ms: self.ttl.as_millis() as u64,
        };
        *g = Some(Held {
            lease: lease.clone(),
            expires: Instant::now() + self.ttl,
            active: 0,
        });
        tracing::info!(holder = %who.name, lease = %lease.id, "control taken");
        Ok(lease)
    }

    /// Releases control: the holder's own, or anyone's for an admin.
    /// Returns the released lease (None if no one held it).
    pub fn release(&self, who: &Principal) -> Result<Option<Lease>, BridgeError> {
        let mut g = self.lock();
        match g.as_ref() {
            None => Ok(None),
            Some(h) if h.lease.holder == who.name || who.role == Role::Admin => {
                let released = g.take().map(|h| h.lease);
                tracing::info!(by = %who.name, "control released");
                Ok(released)
            }
            Some(h) => Err(Self::held_error(h)),
        }
    }

    /// May `who` make a mutating call now? For the holder, renews the lease
    /// and keeps it alive until the returned guard is dropped (the end of
    /// the call).
    pub fn check(self: &Arc<Self>, who: &Principal) -> Result<Option<InUse>, BridgeError> {
        let mut g = self.lock();
        match g.as_mut() {
            None => Ok(None),
            Some(h) if h.lease.holder == who.name => {
                self.renew(h);
                h.active += 1;
                Ok(Some(InUse {
                    control: self.clone(),
                    lease_id: h.lease.id.clone(),
                }))
            }
            Some(h) => Err(Self::held_error(h)),
        }
    }

    /// Ends the lease of a holder whose token no longer exists (revoked).
    pub fn release_unless(&self, exists: impl Fn(&str) -> bool) {
        let mut g = self.lock();
        if g.as_ref().is_some_and(|h| !exists(&h.lease.holder))
            && let Some(h) = g.take()
        {
            tracing::info!(holder = %h.lease.holder, "control released: its token was revoked");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(name: &str, role: Role) -> Principal {
        Principal {
            name: name.into(),
            role,
        }
    }

    #[test]
    fn one_holder_lapses_and_admin_takes_over() {
        let c = Arc::new(Control::new(Duration::from_millis(100)));
        let a = p("a", Role::Operator);
        let b = p("b", Role::Operator);
        let root = p("root", Role::Admin);
        assert!(c.check(&b).is_ok(), "free: anyone may write");
        c.acquire(&a, false).expect("take");
        assert!(c.check(&a).is_ok());
        let e = c.check(&b).expect_err("held");
        assert_eq!(e.code, ErrorCode::ControlHeld);
        assert!(e.detail.contains('a'), "{}", e.detail);
        assert!(c.acquire(&b, true).is_err(), "operators cannot take over");
        assert!(c.release(&b).is_err());
        let l = c.acquire(&root, true).expect("admin takes over");
        assert_eq!(l.holder, "root");
        // A call of the holder that outlasts the lease keeps it.
        let running = c.check(&root).expect("holder");
        std::thread::sleep(Duration::from_millis(150));
        assert!(c.current().is_some(), "kept while the call runs");
        drop(running);
        assert!(c.current().is_some(), "renewed when the call ended");
        std::thread::sleep(Duration::from_millis(150));
        assert!(c.current().is_none(), "lapsed");
        assert!(c.check(&b).is_ok());
        c.acquire(&a, false).expect("take");
        c.release_unless(|name| name != "a");
        assert!(c.current().is_none(), "revoked holder loses control");
    }
}
