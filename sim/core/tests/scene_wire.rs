//! A render worker process is sent the plan's scene (`send_scene`), not a scenario to plan
//! again: every shipped scenario's scene description and camera rig come back from the wire
//! exactly as they went, so the worker's scene has the loop's fingerprint. Run with
//! `cargo test --release -p sim-core --test scene_wire`.

use sim_core::{fingerprint, receive_scene, render_options, send_scene, Plan};
use sim_render::{ActorBody, Backend, VehicleKind};
use std::path::Path;

#[test]
fn every_shipped_scenes_description_crosses_the_wire_exactly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let options = render_options(Backend::Gl);
    let names: Vec<&str> = sim_core::shipped_scenarios().collect();
    assert!(names.len() >= 10, "{names:?}");
    for name in names {
        // The shipped scenarios between them hold every part of a description (a pan head,
        // textures, distractors, overpasses, bumps); a large seed and a sensor's optional
        // effects are added.
        for set in [
            vec![],
            vec![
                "seed=9007199254740993".to_string(),
                "environment.sensor.blur_sigma_px=0.7".to_string(),
                "environment.sensor.shot_noise_full_well_e=9000.5".to_string(),
            ],
        ] {
            let plan = Plan::load(&dir.join(format!("{name}.toml")), &set).unwrap();
            let (description, rig) = (plan.scene().description(), plan.rig());
            let mut wire = Vec::new();
            send_scene(&mut wire, description, rig).unwrap();
            let (got, got_rig) = receive_scene(&mut wire.as_slice()).unwrap();
            assert!(
                &got == description,
                "{name} {set:?}: the description changed"
            );
            assert!(&got_rig == rig, "{name}: the rig changed");
            assert_eq!(
                fingerprint(&got, &got_rig, &options),
                fingerprint(description, rig, &options),
                "{name}"
            );
        }
    }
}

/// Actors and lanes cross the wire exactly too; a description without them (one lane each
/// way, no actors) is sent as before they existed, without either field.
#[test]
fn actors_and_lanes_cross_the_wire_exactly() {
    let plan = Plan::builtin(&[]).unwrap();
    let (description, rig) = (plan.scene().description(), plan.rig());
    let mut wire = Vec::new();
    send_scene(&mut wire, description, rig).unwrap();
    let text = String::from_utf8_lossy(&wire[8..]).to_string();
    let named = |text: &str, key: &str| {
        text.lines()
            .any(|l| l.starts_with(&format!("{key} =")) || l.contains(&format!(".{key}]")))
    };
    assert!(!named(&text, "actors") && !named(&text, "lanes"), "{text}");
    let mut traffic = description.clone();
    traffic.route.lanes = 3;
    traffic.actors = VehicleKind::ALL
        .iter()
        .enumerate()
        .map(|(k, &kind)| ActorBody {
            kind,
            albedo: 0.1 + k as f64 / 7.0,
            tail_lamps: k % 2 == 0,
        })
        .collect();
    let mut wire = Vec::new();
    send_scene(&mut wire, &traffic, rig).unwrap();
    let text = String::from_utf8_lossy(&wire[8..]).to_string();
    assert!(named(&text, "actors") && named(&text, "lanes"), "{text}");
    for kind in VehicleKind::ALL {
        assert!(
            text.contains(&format!("kind = \"{}\"", kind.as_str())),
            "{text}"
        );
    }
    let (got, _) = receive_scene(&mut wire.as_slice()).unwrap();
    assert!(got == traffic, "the actors or the lanes changed");
}

/// What is not a scene is refused with an error, never a panic.
#[test]
fn a_broken_scene_message_is_an_error() {
    for bytes in [
        &b""[..],
        &[3, 0, 0, 0, 0, 0, 0, 0, b'x'][..],
        &[0xff; 8][..],
        &[5, 0, 0, 0, 0, 0, 0, 0, b'a', b'=', b'1', b'\n', b' '][..],
    ] {
        assert!(receive_scene(&mut &bytes[..]).is_err(), "{bytes:?}");
    }
}
