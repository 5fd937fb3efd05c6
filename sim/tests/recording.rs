//! Recordings end to end: `carfollow run --mcap` writes a run.mcap that reads back with the
//! `mcap` crate (schemas, message counts, log times on the simulation clock, metadata) and
//! is the same file on every run; `carfollow track run.mcap` replays it to the run's
//! estimates exactly, and to others with another λ; bad recordings exit 2 in one line;
//! `--mcap-failed` keeps recordings only of failures, in `run` and `sweep`; `--live` serves
//! Foxglove's WebSocket protocol. Run with `cargo test --release -p sim --test recording`.

use foxglove::Decode;
use std::collections::BTreeMap;
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// `carfollow run` of the built-in scenario for `seconds`, recorded, into `out`.
fn run(out: &Path, seconds: &str, extra: &[&str]) -> Output {
    let duration = format!("duration_s={seconds}");
    let mut args = vec![
        "run",
        "--quiet",
        "--set",
        &duration,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    let o = carfollow(&args);
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "exit {:?}: {}",
        o.status.code(),
        stderr(&o)
    );
    o
}

/// A CSV as its header and rows of fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// Every field of the replay's CSV that frames.csv also has equals it, row by row.
fn assert_replay_equals_frames(replay_csv: &Path, frames_csv: &Path) {
    let (rh, rr) = read_csv(replay_csv);
    let (fh, fr) = read_csv(frames_csv);
    assert_eq!(rr.len(), fr.len(), "frame counts differ");
    let shared: Vec<&String> = rh.iter().filter(|c| fh.contains(c)).collect();
    assert!(shared.len() >= 14, "{shared:?}");
    for (k, (r, f)) in rr.iter().zip(&fr).enumerate() {
        for name in &shared {
            assert_eq!(
                r[column(&rh, name)],
                f[column(&fh, name)],
                "frame {k}, column {name}"
            );
        }
        assert_eq!(r[column(&rh, "same_as_recorded")], "1", "frame {k}");
    }
}

fn replay(recording: &Path, out_csv: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "track",
        recording.to_str().unwrap(),
        "--out",
        out_csv.to_str().unwrap(),
        "--quiet",
    ];
    args.extend(extra);
    carfollow(&args)
}

const PER_FRAME_TOPICS: [(&str, &str); 9] = [
    ("/camera/image", "foxglove.RawImage"),
    ("/camera/calibration", "foxglove.CameraCalibration"),
    ("/camera/annotations", "foxglove.ImageAnnotations"),
    ("/tf", "foxglove.FrameTransforms"),
    ("/scene", "foxglove.SceneUpdate"),
    ("/tracker/state", "TrackerState"),
    ("/tracker/input", "TrackerInput"),
    ("/controller", "ControllerState"),
    ("/truth", "GroundTruth"),
];

/// Frame k's log time, nanoseconds: k/15 s.
fn frame_ns(k: u64) -> u64 {
    (k * 2_000_000_000 + 15) / 30
}

/// `/tracker/state`'s `coverage_gain` (the 20th field of `TrackerState`, as the SDK's derive
/// numbers them).
#[derive(Clone, PartialEq, prost::Message)]
struct StateGain {
    #[prost(double, tag = "20")]
    coverage_gain: f64,
}

#[test]
fn a_recording_reads_back_and_replays_to_the_run_s_estimates() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = run(&out, "4", &["--mcap"]);
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("run.mcap"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let path = out.join("run.mcap");
    let bytes = std::fs::read(&path).unwrap();
    let frames = 60u64;

    // Schemas, encodings and message counts, from the summary section.
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
    let stats = summary.stats.as_ref().expect("statistics");
    let by_topic: BTreeMap<&str, (&str, &str, u64)> = summary
        .channels
        .values()
        .map(|c| {
            let schema = c.schema.as_ref().expect("every channel has a schema");
            let count = stats
                .channel_message_counts
                .get(&c.id)
                .copied()
                .unwrap_or(0);
            (
                c.topic.as_str(),
                (schema.name.as_str(), schema.encoding.as_str(), count),
            )
        })
        .collect();
    for (topic, schema) in PER_FRAME_TOPICS {
        let (name, encoding, count) = by_topic
            .get(topic)
            .unwrap_or_else(|| panic!("no {topic} in {by_topic:?}"));
        assert!(name.ends_with(schema), "{topic}: schema {name}");
        assert_eq!(*encoding, "protobuf", "{topic}");
        assert_eq!(*count, frames, "{topic}: messages");
    }
    let (log_schema, _, logs) = by_topic["/events"];
    assert_eq!(log_schema, "foxglove.Log");
    assert!(
        logs >= 2,
        "the verdict and a failed criterion at least: {logs}"
    );
    assert!(
        summary
            .chunk_indexes
            .iter()
            .all(|c| c.compression == "zstd"),
        "chunks are zstd-compressed"
    );

    // Log times on the simulation clock, frame k at k/15 s; images are 256×242 raw mono8.
    let mut image_times = Vec::new();
    let mut events = Vec::new();
    let mut gains = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        match m.channel.topic.as_str() {
            "/camera/image" => {
                image_times.push(m.log_time);
                if image_times.len() == 1 {
                    let img = foxglove::messages::RawImage::decode(&m.data[..]).unwrap();
                    assert_eq!(img.encoding, "mono8");
                    assert_eq!((img.width, img.height, img.step), (256, 242, 256));
                    assert_eq!(img.data.len(), 256 * 242);
                }
            }
            "/events" => {
                let log = foxglove::messages::Log::decode(&m.data[..]).unwrap();
                events.push((m.log_time, log.message));
            }
            "/tracker/state" => {
                gains.push(
                    <StateGain as prost::Message>::decode(&m.data[..])
                        .unwrap()
                        .coverage_gain,
                );
            }
            _ => {}
        }
    }
    // Every number plots: where the gain was not computed it is NaN, never an infinity.
    assert_eq!(gains.len() as u64, frames);
    assert!(gains.iter().all(|g| !g.is_infinite()), "{gains:?}");
    assert!(gains.iter().any(|g| g.is_nan()), "{gains:?}");
    let expected: Vec<u64> = (0..frames).map(frame_ns).collect();
    assert_eq!(image_times, expected);
    // A 4 s run cannot drive the scenario's distance: the failure is logged at the end.
    assert!(
        events.iter().any(|(t, m)| *t == frame_ns(frames - 1)
            && m.starts_with("criterion failed: the chase vehicle drove")),
        "{events:?}"
    );

    // The metadata record: the scenario as run, the seed, the version.
    let index = summary
        .metadata_indexes
        .iter()
        .find(|i| i.name == "carfollow")
        .expect("a carfollow metadata record");
    let meta = mcap::read::metadata(&bytes, index).unwrap().metadata;
    assert_eq!(meta["scenario"], "nist-grounds");
    assert_eq!(meta["seed"], "1");
    assert_eq!(meta["carfollow_version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(meta["frames"], "60");
    let resolved: toml::Table = toml::from_str(&meta["resolved_scenario"]).unwrap();
    assert_eq!(resolved["duration_s"].as_float(), Some(4.0));
    assert!(meta["target"].contains("nominal_range_m"));

    // The same run records the same file, whichever renderer drew which frame.
    let again = dir.path().join("again");
    run(&again, "4", &["--mcap", "--renderers", "1"]);
    assert!(
        std::fs::read(again.join("run.mcap")).unwrap() == bytes,
        "run.mcap differs between two runs of the same scenario and seed"
    );

    // Replay: with the run's settings, every estimate is the run's.
    let replay_csv = dir.path().join("replay.csv");
    let o = replay(&path, &replay_csv, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("60 of 60 frames") && stderr(&o).contains("every estimate equals"),
        "{}",
        stderr(&o)
    );
    assert_replay_equals_frames(&replay_csv, &out.join("frames.csv"));

    // Another λ gives other estimates, and says from which frame.
    let other_csv = dir.path().join("other.csv");
    let o = replay(&path, &other_csv, &["--lambda", "0.5"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("the first difference at frame"),
        "{}",
        stderr(&o)
    );
    let (h, rows) = read_csv(&other_csv);
    let same = column(&h, "same_as_recorded");
    assert!(rows.iter().any(|r| r[same] == "0"));
    // --set reaches every tracker setting.
    let o = replay(&path, &other_csv, &["--set", "tracker.lambda=0.5"]);
    assert!(
        stderr(&o).contains("the first difference at frame"),
        "{}",
        stderr(&o)
    );
    // A flag and a --set of one setting: refused, not one silently beating the other.
    let o = replay(
        &path,
        &other_csv,
        &["--lambda", "0.6", "--set", "tracker.lambda=0.5"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("change the same setting"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn robust_mode_replays_exactly_with_the_recorded_gyro() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("robust");
    run(&out, "3", &["--mcap", "--set", "tracker.mode=robust"]);
    let replay_csv = dir.path().join("replay.csv");
    let o = replay(&out.join("run.mcap"), &replay_csv, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("every estimate equals"),
        "{}",
        stderr(&o)
    );
    assert_replay_equals_frames(&replay_csv, &out.join("frames.csv"));
}

fn expect_input_error(o: &Output, needle: &str) {
    assert_eq!(o.status.code(), Some(2), "stderr: {}", stderr(o));
    let e = stderr(o);
    assert_eq!(e.trim_end().lines().count(), 1, "one line expected: {e}");
    assert!(e.contains(needle), "`{needle}` not in: {e}");
    assert!(!e.contains("panicked"), "{e}");
}

/// MCAP lets metadata stand anywhere: a recording whose `carfollow` metadata comes after
/// its frames (as another tool may write it) replays as the original does.
#[test]
fn a_recording_with_its_metadata_last_replays_alike() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    run(&out, "1", &["--mcap"]);
    let bytes = std::fs::read(out.join("run.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
    let index = summary
        .metadata_indexes
        .iter()
        .find(|i| i.name == "carfollow")
        .expect("a carfollow metadata record");
    let meta = mcap::read::metadata(&bytes, index).unwrap();
    let remux = |path: &Path, meta: &mcap::records::Metadata| {
        let mut w = mcap::Writer::new(std::io::BufWriter::new(
            std::fs::File::create(path).unwrap(),
        ))
        .unwrap();
        for m in mcap::MessageStream::new(&bytes).unwrap() {
            w.write(&m.unwrap()).unwrap();
        }
        w.write_metadata(meta).unwrap();
        w.finish().unwrap();
    };
    // Metadata that says fewer frames than the recording holds: not one run's.
    let mut fewer = meta.clone();
    fewer.metadata.insert("frames".into(), "5".into());
    let short = dir.path().join("short.mcap");
    remux(&short, &fewer);
    let csv = dir.path().join("short.csv");
    expect_input_error(
        &replay(&short, &csv, &[]),
        "holds more frames than its metadata's 5",
    );
    let last = dir.path().join("last.mcap");
    remux(&last, &meta);
    let csv = dir.path().join("last.csv");
    let o = replay(&last, &csv, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("every estimate equals the recorded one"),
        "{}",
        stderr(&o)
    );
    assert_replay_equals_frames(&csv, &out.join("frames.csv"));
}

#[test]
fn bad_recordings_and_flags_exit_2_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("run");
    run(&out, "1", &["--mcap"]);
    let good = std::fs::read(out.join("run.mcap")).unwrap();
    let csv = d.join("t.csv");

    // No such file.
    expect_input_error(
        &replay(&d.join("nope.mcap"), &csv, &[]),
        "nope.mcap: cannot read",
    );
    // Truncated: half a file.
    let cut = d.join("cut.mcap");
    std::fs::write(&cut, &good[..good.len() / 2]).unwrap();
    expect_input_error(&replay(&cut, &csv, &[]), "truncated");
    // Not MCAP at all.
    let junk = d.join("junk.mcap");
    std::fs::write(
        &junk,
        b"this is not a recording, only some text\n".repeat(4),
    )
    .unwrap();
    expect_input_error(&replay(&junk, &csv, &[]), "not an MCAP file");
    // Damaged: some bytes of a chunk changed, wherever they are.
    for at in [5, 8, 11, 14] {
        let mut bent = good.clone();
        let start = good.len() * at / 20;
        for b in &mut bent[start..start + 64] {
            *b ^= 0x5a;
        }
        let bent_path = d.join("bent.mcap");
        std::fs::write(&bent_path, &bent).unwrap();
        expect_input_error(
            &replay(&bent_path, &csv, &[]),
            "bent.mcap: not a readable MCAP file",
        );
    }
    // A valid MCAP file that is not a carfollow recording.
    let other = d.join("other.mcap");
    {
        let mut w = mcap::Writer::new(std::io::BufWriter::new(
            std::fs::File::create(&other).unwrap(),
        ))
        .unwrap();
        let ch = w.add_channel(0, "/x", "json", &BTreeMap::new()).unwrap();
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: ch,
                sequence: 0,
                log_time: 0,
                publish_time: 0,
            },
            b"{}",
        )
        .unwrap();
        w.finish().unwrap();
    }
    expect_input_error(&replay(&other, &csv, &[]), "not a carfollow recording");
    // Flags a recording does not take, and settings that are not the tracker's.
    let rec = out.join("run.mcap");
    expect_input_error(
        &replay(&rec, &csv, &["--target", "x.toml"]),
        "--target is for folders of frames",
    );
    expect_input_error(
        &replay(&rec, &csv, &["--rate-hz", "30"]),
        "--rate-hz is for folders of frames",
    );
    expect_input_error(
        &replay(&rec, &csv, &["--set", "duration_s=3"]),
        "tracker settings only",
    );
    expect_input_error(
        &replay(&rec, &csv, &["--set", "tracker.lambda=7"]),
        "tracker.lambda",
    );
    // A flag's bad value is named as the flag was given.
    let o = replay(&rec, &csv, &["--lambda", "1"]);
    expect_input_error(&o, "--lambda 1: `tracker.lambda` = 1: must be in (0, 1)");
    assert!(!stderr(&o).contains("--set"), "{}", stderr(&o));
}

#[test]
fn mcap_failed_keeps_recordings_of_failures_only() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 2 s cannot drive the scenario's distance: a failure, recorded.
    let failed = d.join("failed");
    let o = run(&failed, "2", &["--mcap-failed"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(failed.join("run.mcap").is_file());
    // Without that criterion it passes: nothing kept.
    let passed = d.join("passed");
    let o = run(
        &passed,
        "2",
        &["--mcap-failed", "--set", "expect.min_distance_m=0"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(passed.join("frames.csv").is_file());
    assert!(!passed.join("run.mcap").exists());

    // A sweep of one passing and one failing point keeps the failing one's recording.
    let sweep = d.join("two.toml");
    let weave = root().join("scenarios/weave.toml");
    std::fs::write(
        &sweep,
        format!(
            "scenarios = [{:?}]\nseeds = [1]\nset = [\"duration_s=2.0\", \"expect.max_range_error_p95_m=1.0\"]\n\
             [axes]\nexpect.min_distance_m = [0.0, 350.0]\n",
            weave.to_str().unwrap()
        ),
    )
    .unwrap();
    let sweep_out = d.join("sweep");
    let o = carfollow(&[
        "sweep",
        sweep.to_str().unwrap(),
        "--out",
        sweep_out.to_str().unwrap(),
        "--jobs",
        "1",
        "--mcap-failed",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("1 recording of points whose criteria failed"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let rows: Vec<serde_json::Value> = std::fs::read_to_string(sweep_out.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let failing: Vec<&serde_json::Value> = rows
        .iter()
        .filter(|r| r["summary"]["passed"] == false)
        .collect();
    assert_eq!((rows.len(), failing.len()), (2, 1));
    let kept: Vec<String> = std::fs::read_dir(sweep_out.join("recordings"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        kept,
        vec![format!(
            "weave-seed1-{}.mcap",
            failing[0]["id"].as_str().unwrap()
        )]
    );
}

/// A child process that is killed if the test fails before it ends.
struct Running(std::process::Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn live_view_serves_frames_over_foxglove_websocket() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Running(
        Command::new(env!("CARGO_BIN_EXE_carfollow"))
            .args([
                "run",
                "--quiet",
                "--set",
                "duration_s=2",
                "--out",
                dir.path().join("live").to_str().unwrap(),
                "--live",
                "--live-port",
                "0",
                "--live-wait",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let mut lines = std::io::BufReader::new(child.0.stderr.take().unwrap()).lines();
    let url = loop {
        let line = lines
            .next()
            .expect("the run says where it listens")
            .unwrap();
        if let Some(rest) = line.strip_prefix("live view: ws://") {
            break format!("ws://{}", rest.split_whitespace().next().unwrap());
        }
    };
    assert!(url.starts_with("ws://127.0.0.1:"), "{url}");
    // Whatever the run writes later, it must not block on a full pipe.
    let drain = std::thread::spawn(move || lines.map_while(Result::ok).collect::<Vec<_>>());

    let mut request =
        tungstenite::client::IntoClientRequest::into_client_request(url.as_str()).unwrap();
    request
        .headers_mut()
        .insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut socket, _) = tungstenite::connect(request).unwrap();
    // Not a timed check: a guard so that a server that never answers fails the test rather
    // than hanging it.
    if let tungstenite::stream::MaybeTlsStream::Plain(tcp) = socket.get_ref() {
        tcp.set_read_timeout(Some(std::time::Duration::from_secs(120)))
            .unwrap();
    }
    // The server's info, then its channels; subscribe to the camera.
    let image_channel = loop {
        match socket.read().unwrap() {
            tungstenite::Message::Text(text) => {
                let v: serde_json::Value = serde_json::from_str(&text).unwrap();
                if v["op"] == "advertise" {
                    if let Some(c) = v["channels"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .find(|c| c["topic"] == "/camera/image")
                    {
                        assert_eq!(c["schemaName"], "foxglove.RawImage");
                        break c["id"].as_u64().unwrap();
                    }
                }
            }
            _ => continue,
        }
    };
    let subscribe = serde_json::json!({
        "op": "subscribe",
        "subscriptions": [{"id": 7, "channelId": image_channel}],
    });
    socket
        .send(tungstenite::Message::Text(subscribe.to_string().into()))
        .unwrap();
    // A message-data frame: opcode 1, subscription id, log time, then the message.
    let (log_time, image) = loop {
        if let tungstenite::Message::Binary(data) = socket.read().unwrap() {
            if data[0] == 1 && u32::from_le_bytes(data[1..5].try_into().unwrap()) == 7 {
                let t = u64::from_le_bytes(data[5..13].try_into().unwrap());
                break (
                    t,
                    foxglove::messages::RawImage::decode(&data[13..]).unwrap(),
                );
            }
        }
    };
    assert!((0..30).map(frame_ns).any(|t| t == log_time), "{log_time}");
    assert_eq!(image.encoding, "mono8");
    assert_eq!((image.width, image.height), (256, 242));
    assert_eq!(image.data.len(), 256 * 242);
    drop(socket);
    let status = child.0.wait().unwrap();
    let said = drain.join().unwrap();
    assert!(matches!(status.code(), Some(0 | 1)), "{said:?}");
}

/// A run that cannot complete (here: frames.csv on a full disk) still closes its recording,
/// which replay then reads, and refuses for having no frames.
#[cfg(target_os = "linux")]
#[test]
fn a_run_that_cannot_complete_closes_its_recording() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("full");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("frames.csv")).unwrap();
    let o = carfollow(&[
        "run",
        "--quiet",
        "--set",
        "duration_s=1",
        "--mcap",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let bytes = std::fs::read(out.join("run.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap();
    assert!(summary.is_some(), "the recording has its summary section");
    let csv = dir.path().join("t.csv");
    expect_input_error(&replay(&out.join("run.mcap"), &csv, &[]), "has no frames");
}
