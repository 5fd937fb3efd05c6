//! The shipped target models of vehicle backs (`scenarios/targets/{kind}-back.toml`) are
//! `sim_render::vehicle_back_model`'s, written out: each file is the function's model, to
//! the digit, and passes the checks `carfollow target` makes of a target file. A file that
//! is missing is written; to write them all again after the shapes change, run
//! `CARFOLLOW_WRITE_TARGETS=1 cargo test --release -p sim-core --test vehicle_targets`.

use sim_core::{load_target, parse_target, target_file_text};
use sim_render::{back_model_centre_m, vehicle_back_model, VehicleKind};
use std::path::{Path, PathBuf};

fn file(kind: VehicleKind) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/targets")
        .join(format!("{}-back.toml", kind.as_str()))
}

/// The file's opening comment.
fn comment(kind: VehicleKind) -> String {
    let [x, y, _] = back_model_centre_m(kind);
    let (length, width, height) = kind.dimensions();
    let parts: &[&str] = match kind {
        VehicleKind::Truck => &[
            "the box's outline, the roll-up door, the rear bumper and the two tail lamps on",
            "it,",
        ],
        _ => &[
            "the roof line, the belt line (not where the cabin stands on the back face, as",
            "a van's does), the rear window's glass, the body's sides down to the bumper's",
            "top, the bumper's top, and the two tail lamps (not the cabin's leaning sides,",
            "nor the bumper's bottom and sides, as dark as the shade under the car),",
        ],
    };
    let mut lines = vec![
        format!(
            "The back of a {} ({length} m long, {width} m wide, {height} m tall) as the \
             renderer",
            kind.as_str()
        ),
        "draws it: the strong horizontal and vertical edges of".to_string(),
    ];
    lines.extend(parts.iter().map(|p| p.to_string()));
    lines.extend([
        "less each edge within 0.25 m of a longer parallel one, which it could not resolve"
            .to_string(),
        "at 25 m through an 8 mm lens.".to_string(),
        String::new(),
        "Written by sim_render::vehicle_back_model from the numbers the shape is built from;"
            .to_string(),
        "do not edit. To write it again: CARFOLLOW_WRITE_TARGETS=1 cargo test --release -p"
            .to_string(),
        "sim-core --test vehicle_targets".to_string(),
        String::new(),
        "Corners are metres from the model's centre, x right and y up as seen from behind;"
            .to_string(),
        format!(
            "the centre is {y:.3} m above the ground on the body's back face, {:.3} m behind",
            -x
        ),
        "the body's centre.".to_string(),
    ]);
    lines.join("\n")
}

#[test]
fn each_vehicle_back_file_is_the_model_the_renderer_draws() {
    let write = std::env::var_os("CARFOLLOW_WRITE_TARGETS").is_some();
    for kind in VehicleKind::ALL {
        let model = vehicle_back_model(kind);
        let text = target_file_text(&model, &comment(kind));
        let path = file(kind);
        assert_eq!(
            parse_target(&text, &path).expect("the text is a target file"),
            model,
            "{kind:?}: the text reads back as the model"
        );
        if write || !path.exists() {
            std::fs::write(&path, &text).expect("write the target file");
            eprintln!("wrote {}", path.display());
        }
        let shipped = std::fs::read_to_string(&path).expect("the shipped file");
        assert!(
            shipped == text,
            "{}: not vehicle_back_model({kind:?})'s; write it again with \
             CARFOLLOW_WRITE_TARGETS=1",
            path.display()
        );
        // What `carfollow target` checks: the file, read and validated.
        let loaded = load_target(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded, model, "{kind:?}");
    }
}
