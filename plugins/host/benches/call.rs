//! Cost of one plugin request inside the host, without HTTP: a fresh store,
//! instantiation from the `InstancePre`, `handle`, the response check.
//! Complements `tests/benches/plugins.rs` (which measures through HTTP).
//!
//! Run: `cargo bench -p kuka-plugin-host --bench call -- PLUGIN.wasm NAME ROUTE [N]`,
//! e.g. with the misbehave fixture built by `plugins/examples/build.sh OUT`:
//! `cargo bench -p kuka-plugin-host --bench call -- OUT/misbehave.wasm misbehave /ok`.

use std::sync::Arc;
use std::time::{Duration, Instant};

use kuka_plugin_host::{
    Axes, BoxFuture, BridgeApi, CallContext, Done, HostError, Motion, PluginHost, PluginLimits,
    Pose, Position, Request,
};

/// A bridge that answers at once (the robot is not what is measured).
struct Instant0;

const POSE: Pose = Pose {
    x: 355.0,
    y: 0.0,
    z: 625.0,
    a: 0.0,
    b: 90.0,
    c: 0.0,
};

fn here() -> Position {
    let axes = Axes {
        a1: 0.0,
        a2: -90.0,
        a3: 90.0,
        a4: 0.0,
        a5: 0.0,
        a6: 0.0,
    };
    Position {
        pose: POSE,
        s: 2,
        t: 2,
        axes,
    }
}

impl BridgeApi for Instant0 {
    fn run_motions<'a>(
        &'a self,
        _ctx: &'a CallContext,
        motions: Vec<Motion>,
    ) -> BoxFuture<'a, Result<Done, HostError>> {
        Box::pin(async move {
            Ok(Done {
                completed: u32::try_from(motions.len()).unwrap_or(u32::MAX),
                position: here(),
            })
        })
    }
    fn position(&self) -> Result<Position, HostError> {
        Ok(here())
    }
    fn state_json(&self) -> String {
        "{}".into()
    }
    fn tool(&self) -> Result<Pose, HostError> {
        Ok(POSE)
    }
    fn base(&self) -> Result<Pose, HostError> {
        Ok(POSE)
    }
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let [path, name, route, rest @ ..] = args.as_slice() else {
        eprintln!("usage: call PLUGIN.wasm NAME ROUTE [N]");
        return;
    };
    let n: usize = rest.first().and_then(|s| s.parse().ok()).unwrap_or(20_000);
    let wasm: Arc<[u8]> = std::fs::read(path).expect("read the plugin").into();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("runtime");
    rt.block_on(async {
        let host = PluginHost::new(
            PluginLimits::default(),
            Default::default(),
            None,
            Arc::new(Instant0),
        ).expect("host");
        let plugin = host.load(name, wasm).await.expect("load");
        let request = || Request {
            method: "POST".into(),
            path: route.clone(),
            query: Vec::new(),
            body: r#"{"x": 300, "y": 20, "z": 100, "radius": 40}"#.into(),
        };
        for _ in 0..500 {
            host.call(&plugin, request(), None).await.expect("call");
        }
        let mut samples = vec![Duration::ZERO; n];
        for s in samples.iter_mut() {
            let start = Instant::now();
            let r = host.call(&plugin, request(), None).await.expect("call");
            *s = start.elapsed();
            assert!(r.status < 500, "{}", r.body);
        }
        samples.sort();
        let us = |q: f64| samples[((samples.len() - 1) as f64 * q) as usize].as_secs_f64() * 1e6;
        println!(
            "{name} {route}: fresh store + instantiate + handle, n={n}: p50 {:.1} µs, p90 {:.1} µs, p99 {:.1} µs",
            us(0.5),
            us(0.9),
            us(0.99)
        );
    });
}
