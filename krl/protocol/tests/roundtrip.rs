//! Encode/decode round trips and the guarantee that a half-written or
//! corrupted file never decodes to something else.

use kuka_protocol::*;

fn params(v: f64) -> MotionParams {
    MotionParams {
        velocity: v,
        acceleration_pct: 100.0,
        approx_mm: 2.5,
    }
}

fn sample_commands() -> Vec<CommandFile> {
    let f = Frame {
        x: 200.0,
        y: -12.345,
        z: 70.0,
        a: 0.0,
        b: 180.0,
        c: -179.999,
    };
    vec![
        CommandFile {
            cid: 2_147_483_647,
            command: Command::Move(vec![
                MotionRecord::Ptp {
                    target: f,
                    s: Some(2),
                    t: None,
                    params: params(50.0),
                },
                MotionRecord::PtpAxes {
                    axes: [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
                    params: params(100.0),
                },
                MotionRecord::SptpAxes {
                    axes: [-185.0, -5.0, 155.999, -350.0, 120.0, 350.0],
                    params: params(30.0),
                },
                MotionRecord::Lin {
                    target: f,
                    params: params(0.25),
                },
                MotionRecord::Circ {
                    aux: [1.0, 2.0, 3.0],
                    target: f,
                    params: params(0.1),
                },
                // Actions: an SOT (switched as the next motion starts) and
                // SOPs (at a distance along the path), at their limits.
                MotionRecord::SetOutput {
                    index: 1,
                    value: true,
                    pulse_ms: 0,
                    path_mm: None,
                },
                MotionRecord::SetOutput {
                    index: 4096,
                    value: false,
                    pulse_ms: 60_000,
                    path_mm: Some(-5000.0),
                },
                MotionRecord::SetOutput {
                    index: 2,
                    value: true,
                    pulse_ms: 250,
                    path_mm: Some(12.345),
                },
                MotionRecord::Sptp {
                    target: f,
                    s: None,
                    t: Some(35),
                    params: params(40.0),
                },
                MotionRecord::Slin {
                    target: f,
                    params: params(0.3),
                },
                MotionRecord::Scirc {
                    aux: [4.0, 5.0, 6.0],
                    target: f,
                    params: params(0.2),
                },
                MotionRecord::Spl {
                    target: f,
                    params: params(0.2),
                    left: 2,
                },
                MotionRecord::Spl {
                    target: f,
                    params: params(0.2),
                    left: 1,
                },
            ]),
        },
        CommandFile {
            cid: 1,
            command: Command::GetPosition,
        },
        CommandFile {
            cid: 7,
            command: Command::Home,
        },
        CommandFile {
            cid: 8,
            command: Command::SetTool(f),
        },
        CommandFile {
            cid: 9,
            command: Command::GetTool,
        },
        CommandFile {
            cid: 10,
            command: Command::SetBase(f),
        },
        CommandFile {
            cid: 11,
            command: Command::GetBase,
        },
        CommandFile {
            cid: 12,
            command: Command::SetSpeed(SpeedRecord {
                override_pct: 50.0,
                ptp_velocity_pct: 30.0,
                ptp_acceleration_pct: 100.0,
                cp_velocity: 0.25,
                cp_acceleration_pct: 100.0,
            }),
        },
        CommandFile {
            cid: 13,
            command: Command::Stop,
        },
        CommandFile {
            cid: 14,
            command: Command::Reset,
        },
        CommandFile {
            cid: 15,
            command: Command::OpenPath(PathChunk {
                path: 15,
                first: 0,
                motions: vec![MotionRecord::Lin {
                    target: f,
                    params: params(0.2),
                }],
                close: false,
            }),
        },
        CommandFile {
            cid: 16,
            command: Command::Append(PathChunk {
                path: 15,
                first: 1,
                motions: vec![
                    MotionRecord::Lin {
                        target: f,
                        params: params(0.2),
                    },
                    MotionRecord::Circ {
                        aux: [1.0, 2.0, 3.0],
                        target: f,
                        params: params(0.1),
                    },
                ],
                close: true,
            }),
        },
        CommandFile {
            cid: 17,
            command: Command::Append(PathChunk {
                path: 15,
                first: 3,
                motions: vec![],
                close: true,
            }),
        },
    ]
}

fn sample_state() -> StateFile {
    StateFile {
        seq: 42,
        status: ControllerStatus::Error,
        mode: OperatingMode::Ext,
        busy_cid: 0,
        busy_index: 3,
        last_cid: 1001,
        error: Some(ResultCode::SoftwareLimit),
        error_axis: 5,
        override_pct: 100.0,
        simulated: true,
        room: 240,
        stored: 17,
        position: Frame {
            x: 470.0,
            y: 0.0,
            z: 750.0,
            a: 0.0,
            b: 90.0,
            c: 0.0,
        },
        s: 2,
        t: 35,
        axes: [0.0, -90.0, 90.0, 0.0, -0.001, 0.0],
        tool: Frame::default(),
        base: Frame {
            x: 1.0,
            ..Frame::default()
        },
        io: Some(IoState {
            base: 4066,
            inputs: 0x7fff_ffff,
            outputs: 5,
        }),
        safety: Some(SafetyState {
            drives_ready: true,
            user_safety: false,
            alarm_stop: true,
            stop_message: true,
            program_state: 3,
        }),
        analog: Some(AnalogState {
            inputs: [0.0, 0.5, -0.25, 1.0, -1.0, 0.001, 0.0, 0.0],
            outputs: [0.123, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.999],
        }),
    }
}

fn sample_results() -> ResultFile {
    ResultFile {
        results: (1..=3)
            .map(|i| ResultRecord {
                cid: 100 + i,
                code: if i == 2 {
                    ResultCode::SoftwareLimit
                } else {
                    ResultCode::Ok
                },
                completed: i as u32,
                axis: if i == 2 { 5 } else { 0 },
                position: Frame {
                    x: f64::from(i),
                    y: 0.5,
                    z: -0.25,
                    a: 0.0,
                    b: 90.0,
                    c: 0.0,
                },
                s: 2,
                t: 0,
                axes: [0.0, -90.0, 90.0, 0.0, 45.5, -0.001],
            })
            .collect(),
    }
}

fn assert_krl_readable(text: &str) {
    assert!(text.ends_with('\n'));
    for line in text.lines() {
        assert!(line.is_ascii() && line.len() <= MAX_LINE_LEN, "{line}");
        assert_eq!(
            line.split(' ').next().map(str::len),
            Some(3),
            "tag of {line}"
        );
    }
}

#[test]
fn commands_round_trip() {
    for cmd in sample_commands() {
        let text = cmd.encode().expect("encodes");
        assert_krl_readable(&text);
        assert_eq!(CommandFile::decode(&text), Ok(cmd.clone()));
        // CRLF line ends (a file edited on Windows) decode the same.
        assert_eq!(CommandFile::decode(&text.replace('\n', "\r\n")), Ok(cmd));
    }
}

#[test]
fn state_and_results_round_trip() {
    let s = sample_state();
    let text = s.encode().expect("encodes");
    assert_krl_readable(&text);
    assert_eq!(StateFile::decode(&text), Ok(s));
    let r = sample_results();
    let text = r.encode().expect("encodes");
    assert_krl_readable(&text);
    assert_eq!(ResultFile::decode(&text), Ok(r));
}

#[test]
fn result_file_keeps_the_newest_eight() {
    let mut r = sample_results();
    let one = r.results[0];
    r.results = (1..=20).map(|cid| ResultRecord { cid, ..one }).collect();
    let decoded = ResultFile::decode(&r.encode().expect("encodes")).expect("decodes");
    let cids: Vec<_> = decoded.results.iter().map(|r| r.cid).collect();
    assert_eq!(cids, (13..=20).collect::<Vec<_>>());
}

/// Every prefix of a file (a writer cut off at any byte) fails to decode,
/// except the complete file (with or without its final newline).
#[test]
fn half_written_files_never_decode() {
    let mut texts: Vec<String> = sample_commands()
        .iter()
        .map(|c| c.encode().expect("encodes"))
        .collect();
    texts.push(sample_state().encode().expect("encodes"));
    texts.push(sample_results().encode().expect("encodes"));
    for text in texts {
        for cut in 0..text.len() - 1 {
            let part = &text[..cut];
            assert!(
                CommandFile::decode(part).is_err(),
                "prefix {cut} decoded: {part:?}"
            );
            assert!(
                StateFile::decode(part).is_err(),
                "prefix {cut} decoded: {part:?}"
            );
            assert!(
                ResultFile::decode(part).is_err(),
                "prefix {cut} decoded: {part:?}"
            );
        }
    }
}

/// Changing any single digit of a file is caught by the checksum.
#[test]
fn corrupted_digits_are_detected() {
    let text = sample_state().encode().expect("encodes");
    let bytes = text.as_bytes();
    for i in 0..bytes.len() {
        if !bytes[i].is_ascii_digit() {
            continue;
        }
        for d in b'0'..=b'9' {
            if d == bytes[i] {
                continue;
            }
            let mut changed = bytes.to_vec();
            changed[i] = d;
            let changed = String::from_utf8(changed).expect("ascii");
            assert!(
                StateFile::decode(&changed).is_err(),
                "digit {i} -> {} decoded",
                d as char
            );
        }
    }
}

#[test]
fn invalid_values_are_refused() {
    let bad = CommandFile {
        cid: 5,
        command: Command::Move(vec![MotionRecord::Lin {
            target: Frame {
                x: f64::NAN,
                ..Frame::default()
            },
            params: params(0.1),
        }]),
    };
    assert!(bad.encode().is_err());
    assert!(
        CommandFile {
            cid: 0,
            command: Command::Home
        }
        .encode()
        .is_err()
    );
    assert!(
        CommandFile {
            cid: 3,
            command: Command::Move(vec![])
        }
        .encode()
        .is_err()
    );
    // An SOP's distance: finite and within ±MAX_TRIGGER_PATH_MM.
    for p in [f64::NAN, f64::INFINITY, 5000.001, -5000.001, 1e300] {
        let sop = CommandFile {
            cid: 6,
            command: Command::Move(vec![
                MotionRecord::Lin {
                    target: Frame::default(),
                    params: params(0.1),
                },
                MotionRecord::SetOutput {
                    index: 1,
                    value: true,
                    pulse_ms: 0,
                    path_mm: Some(p),
                },
            ]),
        };
        assert!(sop.encode().is_err(), "path {p}");
    }
    let sop = |path: &str| {
        let body = format!("SOP 0 1 1 0 {path}");
        let fields: Vec<i64> = body
            .split(' ')
            .skip(1)
            .map(|v| v.replace('.', "").parse().expect("a number"))
            .collect();
        let k = checksum(fields.iter().copied());
        format!(
            "CMD 2 7 1 1 {}\n{body} {k}\nEND 7 1 {}\n",
            checksum([2, 7, 1, 1]),
            checksum([7, 1])
        )
    };
    let ok = CommandFile::decode(&sop("-12.500")).expect("an SOP decodes");
    assert_eq!(
        ok.command,
        Command::Move(vec![MotionRecord::SetOutput {
            index: 1,
            value: true,
            pulse_ms: 0,
            path_mm: Some(-12.5),
        }])
    );
    assert!(CommandFile::decode(&sop("5000.001")).is_err());
    assert!(
        CommandFile::decode(&sop("12")).is_err(),
        "the path is a REAL"
    );
    let wrong_version = "CMD 1 5 3 0 K\n";
    assert_eq!(
        CommandFile::decode(wrong_version),
        Err(DecodeError::Version(1))
    );
    // A version 1 state file (two fields fewer) is named as such.
    let v1_state = format!(
        "STA 1 294 0 4 0 0 22 0 0 100.000 1 {}\n",
        checksum([1, 294, 0, 4, 0, 0, 22, 0, 0, 100_000, 1])
    );
    assert_eq!(StateFile::decode(&v1_state), Err(DecodeError::Version(1)));
    // A path chunk's motion indices continue from `first`; op 4 opens the
    // path of its own id from motion 0.
    let bad_index = CommandFile {
        cid: 16,
        command: Command::Append(PathChunk {
            path: 15,
            first: 4,
            motions: vec![MotionRecord::Lin {
                target: Frame::default(),
                params: params(0.2),
            }],
            close: false,
        }),
    }
    .encode()
    .expect("ok")
    .replace("LIN 4 ", "LIN 5 ");
    assert!(CommandFile::decode(&bad_index).is_err());
    assert!(
        CommandFile {
            cid: 20,
            command: Command::OpenPath(PathChunk {
                path: 19,
                first: 0,
                motions: vec![],
                close: false,
            }),
        }
        .encode()
        .is_ok(),
        "the encoder writes what it is given"
    );
    let trailing = format!(
        "{}junk 1\n",
        CommandFile {
            cid: 3,
            command: Command::Home
        }
        .encode()
        .expect("ok")
    );
    assert_eq!(
        CommandFile::decode(&trailing),
        Err(DecodeError::TrailingData)
    );
}

#[test]
fn checksum_matches_the_documented_example() {
    // The worked example in krl/PROTOCOL.md.
    let text = CommandFile {
        cid: 17,
        command: Command::GetPosition,
    }
    .encode()
    .expect("ok");
    let first = text.lines().next().expect("line");
    assert_eq!(first, format!("CMD 2 17 3 0 {}", checksum([2, 17, 3, 0])));
    assert_eq!(checksum([2, 17, 3, 0]), 10491);
    // Negative values and values beyond the modulus, as KRL computes them.
    assert_eq!(checksum([-1000, 2_147_483_647, 359_999]), 24905);
}

/// A spline block is whole in every command: a point that leaves its block
/// unfinished, or a record in the middle of a block, is refused both ways.
#[test]
fn spline_blocks_are_never_split() {
    let spl = |left| MotionRecord::Spl {
        target: Frame::default(),
        params: params(0.1),
        left,
    };
    let lin = MotionRecord::Lin {
        target: Frame::default(),
        params: params(0.1),
    };
    for motions in [
        vec![spl(2)],
        vec![spl(3), spl(2), lin.clone()],
        vec![spl(2), spl(2)],
        vec![spl(9)],
        vec![spl(0)],
    ] {
        let cmd = CommandFile {
            cid: 4,
            command: Command::Move(motions.clone()),
        };
        assert!(cmd.encode().is_err(), "{motions:?} was written");
    }
    // Written by hand: the same shapes are refused when read.
    let good = CommandFile {
        cid: 4,
        command: Command::Move(vec![spl(2), spl(1), lin]),
    }
    .encode()
    .expect("a whole block");
    assert!(CommandFile::decode(&good).is_ok());
    let line = |i: i64, left: i64| {
        let v: [i64; 11] = [i, 0, 0, 0, 0, 0, 0, 100, 100_000, 2_500, left];
        let text: Vec<String> = v
            .iter()
            .enumerate()
            .map(|(k, x)| {
                if (1..10).contains(&k) {
                    format!("{}.{:03}", x / 1000, x % 1000)
                } else {
                    x.to_string()
                }
            })
            .collect();
        format!("SPL {} {}\n", text.join(" "), checksum(v))
    };
    let file = |body: &[String]| {
        let n = body.len() as i64;
        format!(
            "CMD 2 4 1 {n} {}\n{}END 4 {n} {}\n",
            checksum([2, 4, 1, n]),
            body.concat(),
            checksum([4, n])
        )
    };
    assert!(CommandFile::decode(&file(&[line(0, 2), line(1, 1)])).is_ok());
    for body in [
        vec![line(0, 2)],
        vec![line(0, 3), line(1, 1)],
        vec![line(0, 9)],
    ] {
        assert!(
            CommandFile::decode(&file(&body)).is_err(),
            "{body:?} was read"
        );
    }
}
