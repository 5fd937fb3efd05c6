//! Traffic leaves the shipped scenes as they were: a shipped scenario's scene with actors
//! added, posed out of view, renders its frames bit for bit as the scene without them (the
//! actors' object slots, the shader's longer array of transforms and the actors' draws
//! change nothing else), and its description says one lane each way and no actors, the
//! defaults that leave the road as it was. Run with
//! `cargo test --release -p sim-core --test traffic_scenes`.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use sim_core::{render_options, Plan};
use sim_render::{ActorBody, Backend, FrameInput, Renderer, Scene, VehicleKind};
use std::path::Path;
use std::sync::Arc;

#[test]
fn shipped_scenes_with_actors_out_of_view_render_as_without() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let options = render_options(Backend::choose(None).expect("backend"));
    for name in ["nist-grounds", "section4", "intersections"] {
        let plan = Plan::load(&dir.join(format!("{name}.toml")), &[]).unwrap();
        let description = plan.scene().description().clone();
        assert_eq!(description.route.lanes, 1, "{name}");
        assert!(description.actors.is_empty(), "{name}");
        let mut traffic = description.clone();
        traffic.actors = VehicleKind::ALL
            .iter()
            .map(|&kind| ActorBody {
                kind,
                albedo: 0.4,
                tail_lamps: false,
            })
            .collect();
        let mut without =
            Renderer::new(plan.scene().clone(), plan.rig().clone(), &options).expect("renderer");
        let scene = Arc::new(Scene::build(traffic).expect("scene"));
        let mut with = Renderer::new(scene.clone(), plan.rig().clone(), &options).unwrap();
        let lane = description.route.lane_centre_m(1);
        let far = Isometry3::from_parts(
            Translation3::new(-5000.0, 0.0, 3000.0),
            UnitQuaternion::identity(),
        );
        for (k, s) in [(0u64, 30.0), (40, 120.0)] {
            let route = scene.route();
            let (chase, lead) = (route.pose_at(s, lane), route.pose_at(s + 15.0, lane));
            let input = FrameInput::fixed_camera(k, k as f64 / 15.0, chase, lead);
            let alone = without.render(&input).expect("frame");
            let actors = vec![far; VehicleKind::ALL.len()];
            let beside = with.render(&input.with_actors(actors)).expect("frame");
            assert!(alone == beside, "{name}, frame {k}: the actors changed it");
        }
    }
}
