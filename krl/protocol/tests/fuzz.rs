//! Property tests ("fuzzing in CI") of the protocol decoder: the service
//! decodes result and state files the controller writes, and the
//! simulated controller decodes command files; whatever bytes those files
//! hold (half-written, corrupted, hostile), decoding answers a value or a
//! [`DecodeError`] — it never panics, allocates without bound or recurses.
//!
//! The decoder is iterative and bounded by construction (at most
//! [`RESULT_HISTORY`] results and [`MAX_BATCH`] motions, lines of at most
//! [`MAX_LINE_LEN`] characters); these tests hold it to that.
//!
//! The number of cases is modest so that `cargo test` stays quick; run more
//! with `PROPTEST_CASES=100000 cargo test -p kuka-protocol --test fuzz`.

use kuka_protocol::*;
use proptest::prelude::*;

fn config(default_cases: u32) -> ProptestConfig {
    let mut c = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = default_cases;
    }
    c.failure_persistence = None;
    c
}

/// Decodes `text` as every kind of file; none may panic. A file that
/// decodes must encode again, and that text must decode to the same value.
fn decode_all(text: &str) {
    if let Ok(r) = ResultFile::decode(text) {
        let again = r.encode().expect("a decoded result file encodes");
        assert_eq!(ResultFile::decode(&again).as_ref(), Ok(&r));
    }
    if let Ok(s) = StateFile::decode(text) {
        let again = s.encode().expect("a decoded state file encodes");
        assert_eq!(StateFile::decode(&again).as_ref(), Ok(&s));
    }
    if let Ok(c) = CommandFile::decode(text) {
        let again = c.encode().expect("a decoded command file encodes");
        assert_eq!(CommandFile::decode(&again).as_ref(), Ok(&c));
    }
    let _ = CommandFile::peek_cid(text);
}

/// A REAL as the file carries it: thousandths within ±MAX_REAL.
fn real() -> impl Strategy<Value = f64> {
    (-9_999_999i32..=9_999_999).prop_map(|v| f64::from(v) / 1000.0)
}

fn frame() -> impl Strategy<Value = Frame> {
    [real(), real(), real(), real(), real(), real()].prop_map(Frame::from_array)
}

fn result_record() -> impl Strategy<Value = ResultRecord> {
    (
        1i32..=i32::MAX,
        -100i32..100,
        0u32..=1000,
        0u8..=6,
        frame(),
        0u8..=7,
        0u8..=63,
        [real(), real(), real(), real(), real(), real()],
    )
        .prop_map(
            |(cid, code, completed, axis, position, s, t, axes)| ResultRecord {
                cid,
                code: ResultCode::from_code(code),
                completed,
                axis,
                position,
                s,
                t,
                axes,
            },
        )
}

fn result_file() -> impl Strategy<Value = ResultFile> {
    prop::collection::vec(result_record(), 0..=RESULT_HISTORY)
        .prop_map(|results| ResultFile { results })
}

fn state_file() -> impl Strategy<Value = StateFile> {
    (
        (any::<i32>(), 0..3, 0usize..5, 0i32..=i32::MAX, 0u32..=1000),
        (0i32..=i32::MAX, -50i32..50, 0u8..=6, real(), any::<bool>()),
        (
            frame(),
            0u8..=7,
            0u8..=63,
            0u32..=4096,
            0u32..=i32::MAX as u32,
        ),
        (
            [real(), real(), real(), real(), real(), real()],
            frame(),
            frame(),
            prop::option::of((1u16..=4066, 0u32..=0x7fff_ffff, 0u32..=0x7fff_ffff)),
            prop::option::of((any::<[bool; 4]>(), 0u8..=4)),
        ),
    )
        .prop_map(
            |(
                (seq, status, mode, busy_cid, busy_index),
                (last_cid, err, error_axis, override_pct, simulated),
                (position, s, t, room, stored),
                (axes, tool, base, io, safety),
            )| StateFile {
                seq,
                status: match status {
                    0 => ControllerStatus::Idle,
                    1 => ControllerStatus::Busy,
                    _ => ControllerStatus::Error,
                },
                mode: [
                    OperatingMode::Unknown,
                    OperatingMode::T1,
                    OperatingMode::T2,
                    OperatingMode::Aut,
                    OperatingMode::Ext,
                ][mode],
                busy_cid,
                busy_index,
                last_cid,
                error: (err != 0).then(|| ResultCode::from_code(err)),
                error_axis,
                override_pct,
                simulated,
                room,
                stored,
                position,
                s,
                t,
                axes,
                tool,
                base,
                io: io.map(|(base, inputs, outputs)| IoState {
                    base,
                    inputs,
                    outputs,
                }),
                safety: safety.map(|(b, program_state)| SafetyState {
                    drives_ready: b[0],
                    user_safety: b[1],
                    alarm_stop: b[2],
                    stop_message: b[3],
                    program_state,
                }),
                // (The ANS line: its own property below, the tuple of this
                // strategy is full.)
                analog: None,
            },
        )
}

/// A damaged copy of `text`: bytes changed, dropped or inserted, lines
/// repeated, or the file cut short.
fn damage(text: String) -> impl Strategy<Value = String> {
    let len = text.len().max(1);
    (
        prop::collection::vec((0..len, any::<u8>(), 0..5u8), 1..6),
        any::<bool>(),
    )
        .prop_map(move |(edits, cut)| {
            let mut b = text.clone().into_bytes();
            for (at, byte, kind) in edits {
                let at = at.min(b.len());
                match kind {
                    0 if at < b.len() => b[at] = byte,
                    1 if at < b.len() => {
                        b.remove(at);
                    }
                    2 => b.insert(at, byte),
                    3 => {
                        // Repeat the line around `at`.
                        let start = b[..at]
                            .iter()
                            .rposition(|c| *c == b'\n')
                            .map_or(0, |p| p + 1);
                        let end = b[at..]
                            .iter()
                            .position(|c| *c == b'\n')
                            .map_or(b.len(), |p| at + p + 1);
                        let line = b[start..end].to_vec();
                        b.splice(start..start, line);
                    }
                    _ => b.insert(at, b"0123456789 .-\n"[usize::from(byte) % 14]),
                }
            }
            if cut {
                b.truncate(b.len() / 2);
            }
            String::from_utf8_lossy(&b).into_owned()
        })
}

proptest! {
    #![proptest_config(config(2000))]

    /// Arbitrary text, including non-ASCII and very long lines.
    #[test]
    fn any_text_decodes_or_fails(text in "\\PC{0,600}") {
        decode_all(&text);
    }

    /// Lines that look like protocol lines: tags, numbers and checksums.
    #[test]
    fn protocol_like_lines_decode_or_fail(
        lines in prop::collection::vec(
            (
                prop::sample::select(vec!["RES", "RSL", "STA", "POS", "AXS", "TOL", "BAS", "END", "CMD", "PTP", "LIN", "PTA", "CIR", "APD", "SOT", "SOP", "WIN", "DWL", ""]),
                prop::collection::vec(
                    prop_oneof![
                        (-2_147_483_648i64..=2_147_483_647).prop_map(|v| v.to_string()),
                        (-99_999i32..=99_999).prop_map(|v| format!("{}{}.{:03}", if v < 0 { "-" } else { "" }, v.unsigned_abs() / 1000, v.unsigned_abs() % 1000)),
                        Just("1".to_string()),
                        Just("0".to_string()),
                        Just("8".to_string()),
                    ],
                    0..22,
                ),
            ),
            0..12,
        )
    ) {
        let text: String = lines
            .iter()
            .map(|(tag, fields)| format!("{tag} {}\n", fields.join(" ")))
            .collect();
        decode_all(&text);
    }

    /// Valid files round-trip exactly.
    #[test]
    fn result_files_round_trip(f in result_file()) {
        let text = f.encode().expect("encodes");
        prop_assert_eq!(ResultFile::decode(&text), Ok(f));
    }

    /// Valid state files round-trip exactly.
    #[test]
    fn state_files_round_trip(f in state_file()) {
        let text = f.encode().expect("encodes");
        prop_assert_eq!(StateFile::decode(&text), Ok(f));
    }

    /// Damaged result files: an error, or a file that is itself valid.
    #[test]
    fn damaged_result_files_decode_or_fail(
        text in result_file().prop_flat_map(|f| damage(f.encode().expect("encodes")))
    ) {
        decode_all(&text);
    }

    /// Damaged state files: an error, or a file that is itself valid.
    #[test]
    fn damaged_state_files_decode_or_fail(
        text in state_file().prop_flat_map(|f| damage(f.encode().expect("encodes")))
    ) {
        decode_all(&text);
    }
}

/// Regression inputs: shapes that must be refused, not panic.
#[test]
fn hostile_files_are_refused() {
    let huge_line = format!("RES 1 0 {}\nEND 0 0\n", "1 ".repeat(100_000));
    for text in [
        "",
        "\n\n\n",
        "RES",
        "RES 1",
        "RES 1 9 0\n",
        "RES 1 -1 65520\nEND -1 65520\n",
        "RES 1 2147483647 0\n",
        "STA 1 0 0 0 0 0 0 0 0 0.000 0 0\n",
        "RES 2 0 62\nEND 0 0\nEND 0 0\n",
        "RES 99999999999 0 0\n",
        "RES -0 0 0\nEND 0 0\n",
        "RES 2 0 62\r\nEND 0 0\r\n",
        "RES 2 0 62\nEND 0 0\nä",
        "RES 1 0 31\nEND 0 0\n",
        &huge_line,
    ] {
        decode_all(text);
        assert!(
            ResultFile::decode(text).is_err() || text.starts_with("RES 2 0 62"),
            "{text:?}"
        );
    }
}

proptest! {
    /// The ANS line round-trips at the protocol's resolution (0.001).
    #[test]
    fn analog_states_round_trip(
        mut st in state_file(),
        ins in proptest::array::uniform8(-1000i32..=1000),
        outs in proptest::array::uniform8(-1000i32..=1000),
    ) {
        let a = AnalogState {
            inputs: ins.map(|v| f64::from(v) / 1000.0),
            outputs: outs.map(|v| f64::from(v) / 1000.0),
        };
        st.analog = Some(a);
        let text = st.encode().expect("encodes");
        let back = StateFile::decode(&text).expect("decodes");
        prop_assert_eq!(back.analog, Some(a));
    }
}
