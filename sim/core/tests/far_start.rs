//! A chase that starts far behind its lead: `chase.initial_gap_m` up to the renderer's far
//! plane (250 m), over 60 m only with a cruise speed and a tracker that starts by
//! searching, each refused by name without it. Run with
//! `cargo test --release -p sim-core --test far_start`.

mod common;
use common::{load, scenarios_dir};
use sim_core::{MAX_INITIAL_GAP_M, MAX_PLACED_GAP_M};

/// `slow-vehicle-ahead`: a cruising chase whose tracker starts by searching, 60 m behind.
fn text() -> String {
    std::fs::read_to_string(scenarios_dir().join("slow-vehicle-ahead.toml")).unwrap()
}

#[test]
fn the_limits_are_the_far_plane_and_the_placed_start() {
    assert_eq!(MAX_INITIAL_GAP_M, sim_render::FAR_M);
    assert_eq!(MAX_PLACED_GAP_M, 60.0);
}

#[test]
fn a_searching_cruising_chase_may_start_up_to_the_far_plane() {
    for gap in ["61", "150", "250"] {
        let s = load(
            &text(),
            &["lead.start_m=300", &format!("chase.initial_gap_m={gap}")],
        )
        .unwrap_or_else(|e| panic!("{gap}: {e}"));
        assert_eq!(s.initial_gap_m, gap.parse::<f64>().unwrap());
        assert!(s.search_start);
    }
    let e = load(&text(), &["lead.start_m=300", "chase.initial_gap_m=250.5"]).unwrap_err();
    assert!(
        e.contains("`chase.initial_gap_m` = 250.5: must be 3–250 metres")
            && e.contains("far plane"),
        "{e}"
    );
    // The route bounds it too: the chase must start on it (the van, which starts behind
    // the chase, taken out: it would be off the route first).
    let alone = text().split("[[actors]]").next().unwrap().to_string();
    let e = load(&alone, &["chase.initial_gap_m=150"]).unwrap_err();
    assert!(e.contains("before the route's start"), "{e}");
}

#[test]
fn a_far_start_needs_a_cruise_speed_and_a_search() {
    let far = ["lead.start_m=300", "chase.initial_gap_m=150"];
    let no_cruise = text().replace("cruise_speed_mps = 13.9, ", "");
    assert_ne!(no_cruise, text());
    // 60 m is still a start the tracker may be placed at, cruise speed or not.
    load(&no_cruise, &["tracker.start=\"operator\""]).unwrap_or_else(|e| panic!("{e}"));
    let e = load(&no_cruise, &far).unwrap_err();
    assert!(
        e.starts_with("/bad.toml:")
            && e.contains("`chase.controller.cruise_speed_mps`")
            && e.contains("initial_gap_m = 150"),
        "{e}"
    );
    let mut operator = far.to_vec();
    operator.push("tracker.start=\"operator\"");
    let e = load(&text(), &operator).unwrap_err();
    assert!(
        e.contains("`tracker.start`") && e.contains("must be \"search\""),
        "{e}"
    );
}

#[test]
fn a_searching_start_needs_no_target_in_view() {
    // Aimed at the sky, the camera sees no target at t = 0: refused with the tracker
    // placed on it, planned with one that searches for it.
    let up = ["camera.mount.pitch_down_deg=-30"];
    load(&text(), &up).unwrap_or_else(|e| panic!("{e}"));
    let mut placed = up.to_vec();
    placed.push("tracker.start=\"operator\"");
    let e = load(&text(), &placed).unwrap_err();
    assert!(e.contains("out of the camera's view at t = 0"), "{e}");
}
