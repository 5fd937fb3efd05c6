//! Rain's options in the frame's uniforms: the vehicles' spray plumes
//! ([`spray_params`]) and the lamps the wet road mirrors ([`mirror_params`]).
//!
//! A frame's puffs and gusts are drawn from frame `frame_index`'s slice of the `"spray"`
//! stream of the scene's seed, two numbers a vehicle whether or not it throws spray, so the
//! plumes change from frame to frame, the same frame is the same whichever renderer draws
//! it, and spray moves no other random draw.

use super::view::CameraView;
use crate::camera::frame::Field;
use crate::scene::{
    stream, Braking, Headlamps, ObjectSlot, Rain, SceneDescription, Spray, Sun, TailLamps,
};
use nalgebra::{Isometry3, Point3, Vector3};
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Plumes a frame draws at most: the lead's and every actor's. The chase's own trails
/// behind its camera, which looks ahead, and is left out.
pub(super) const SPRAY_PLUMES: usize = 1 + ObjectSlot::MAX_ACTORS as usize;

/// `vec4`s of `Globals::spray`: the two of the header, then three for each plume.
pub(super) const SPRAY_VEC4S: usize = 2 + 3 * SPRAY_PLUMES;

/// Lamps the wet road mirrors besides the headlamps and the street lights (whose own
/// uniforms it reads): two tail lamps for the lead and every actor.
pub(super) const MIRROR_LAMPS: usize = 2 * (1 + ObjectSlot::MAX_ACTORS as usize);

/// `vec4`s of `Globals::mirror`: the header, then two for each lamp.
pub(super) const MIRROR_VEC4S: usize = 1 + 2 * MIRROR_LAMPS;

/// Random words the spray's stream reserves per frame: two, the key of that frame's own
/// generator.
const WORDS_PER_FRAME: u128 = 2;

/// What moves in a frame besides the poses: its index (the spray's draws) and the
/// vehicles' speeds (their spray).
pub(super) struct Speeds<'a> {
    /// The frame's index.
    pub frame_index: u64,
    /// The lead's forward speed, m/s.
    pub lead_mps: f64,
    /// The actors' forward speeds, m/s (missing ones: at rest).
    pub actors_mps: &'a [f64],
}

/// A vehicle that may throw spray or carry tail lamps: its pose, speed, half-width and
/// back (x of its back's plane in its frame).
struct Body {
    world_from_body: Isometry3<f64>,
    speed_mps: f64,
    half_width_m: f64,
    back_x_m: f64,
}

/// The lead (when there is one) and the actors as `field` poses them, in that order.
fn bodies(description: &SceneDescription, field: &Field, speeds: &Speeds) -> Vec<Body> {
    let lead = &description.lead;
    let mut out = Vec::new();
    if !description.without_lead {
        out.push(Body {
            world_from_body: field.world_from_lead,
            speed_mps: speeds.lead_mps,
            half_width_m: 0.5 * lead.width_m,
            back_x_m: -0.5 * lead.length_m,
        });
    }
    for (k, (actor, pose)) in description
        .actors
        .iter()
        .zip(&field.world_from_actors)
        .enumerate()
    {
        let (length, width, _) = actor.kind.dimensions();
        out.push(Body {
            world_from_body: *pose,
            speed_mps: speeds.actors_mps.get(k).copied().unwrap_or(0.0),
            half_width_m: 0.5 * width,
            back_x_m: -0.5 * length,
        });
    }
    out
}

/// The spray's parameters in `Globals` (zeros without rain's spray, whose pipelines never
/// read them): `[0]` the number of plumes, the airlight under `sun_light` times the
/// sensor's `brightness`, the share of the lamps' light a droplet scatters, the puffs'
/// wavenumber (radians per metre); `[1]` the plume's shape ([`Spray::SOURCE_HEIGHT_M`],
/// [`Spray::RISE_PER_M`], [`Spray::MAX_HEIGHT_M`], [`Spray::SPREAD_PER_M`]); then for each
/// plume, `[2]` the middle of its vehicle's back on the ground relative to the camera and
/// σ0 (m, with the frame's gust), `[3]` the unit vector backwards along the road and the
/// settling length (m), `[4]` the vehicle's half-width (m), the puffs' phase (radians),
/// the plume's length (m) and the puffs' depth.
pub(super) fn spray_params(
    description: &SceneDescription,
    field: &Field,
    speeds: &Speeds,
    view: &CameraView,
    sun_light: &Sun,
    brightness: f64,
) -> [[f32; 4]; SPRAY_VEC4S] {
    let mut out = [[0.0; 4]; SPRAY_VEC4S];
    let Some(rain) = description.raining().filter(|r| r.spray) else {
        return out;
    };
    let mut rng = {
        let mut s = stream(description.seed, "spray");
        s.set_word_pos(u128::from(speeds.frame_index) * WORDS_PER_FRAME);
        ChaCha8Rng::seed_from_u64(s.next_u64())
    };
    let mut n = 0;
    for body in bodies(description, field, speeds) {
        // Two uniforms a vehicle, drawn whether or not it throws spray, so that each
        // vehicle's numbers are the same whatever the others'.
        let gust: f64 = rng.random();
        let phase: f64 = rng.random();
        let sigma = Spray::source_cross_section_m(&rain, body.speed_mps)
            * (1.0 + Spray::GUST * (2.0 * gust - 1.0));
        if sigma <= 0.0 || n == SPRAY_PLUMES {
            continue;
        }
        let pose = &body.world_from_body;
        let back = (pose * Point3::new(body.back_x_m, 0.0, 0.0)).coords - view.eye;
        let backwards = pose.rotation * Vector3::new(-1.0, 0.0, 0.0);
        let flat = Vector3::new(backwards.x, 0.0, backwards.z);
        let Some(dir) = flat.try_normalize(1e-9) else {
            continue;
        };
        let settling = Spray::settling_length_m(body.speed_mps);
        out[2 + 3 * n] = [back.x as f32, back.y as f32, back.z as f32, sigma as f32];
        out[3 + 3 * n] = [dir.x as f32, 0.0, dir.z as f32, settling as f32];
        out[4 + 3 * n] = [
            body.half_width_m as f32,
            (std::f64::consts::TAU * phase) as f32,
            (Spray::LENGTH_IN_DECAYS * settling) as f32,
            Spray::PUFF_DEPTH as f32,
        ];
        n += 1;
    }
    out[0] = [
        n as f32,
        (Rain::airlight(sun_light) * brightness) as f32,
        Spray::SCATTER_SHARE as f32,
        (std::f64::consts::TAU / Spray::PUFF_M) as f32,
    ];
    out[1] = [
        Spray::SOURCE_HEIGHT_M as f32,
        Spray::RISE_PER_M as f32,
        Spray::MAX_HEIGHT_M as f32,
        Spray::SPREAD_PER_M as f32,
    ];
    out
}

/// A vehicle's two tail lamps: its pose, their centres in its frame, and whether it brakes.
type LampPair<'a> = (&'a Isometry3<f64>, [[f64; 3]; 2], bool);

/// The mirrored lamps' parameters in `Globals` (zeros without rain's mirrored lamps, whose
/// pipelines never read them): `[0]` the number of tail lamps, the film's roughness
/// ([`Rain::FILM_SLOPE_RMS`]); then for each lit tail lamp (the lead's and each actor's
/// whose are, braking as `braking` says), `[1]` its lens's centre relative to the camera
/// and its intensity (candela over [`Headlamps::LUX_PER_UNIT`], times the sensor's
/// `brightness`), `[2]` the unit vector its vehicle's back faces (it shines behind).
pub(super) fn mirror_params(
    description: &SceneDescription,
    field: &Field,
    view: &CameraView,
    braking: Braking,
    brightness: f64,
) -> [[f32; 4]; MIRROR_VEC4S] {
    let mut out = [[0.0; 4]; MIRROR_VEC4S];
    if !description.raining().is_some_and(|r| r.lamp_reflections) {
        return out;
    }
    let mut lamps: Vec<LampPair> = Vec::new();
    if description.lead.tail_lamps && !description.without_lead {
        let centres = TailLamps::lead_centres(&description.lead, &description.target);
        lamps.push((&field.world_from_lead, centres, braking.lead()));
    }
    for (k, (actor, pose)) in description
        .actors
        .iter()
        .zip(&field.world_from_actors)
        .enumerate()
    {
        if actor.tail_lamps {
            lamps.push((pose, TailLamps::kind_centres(actor.kind), braking.actor(k)));
        }
    }
    let mut n = 0;
    for (pose, centres, brakes) in lamps {
        let intensity = TailLamps::intensity_cd(brakes) / Headlamps::LUX_PER_UNIT * brightness;
        let facing = pose.rotation * Vector3::new(-1.0, 0.0, 0.0);
        for c in centres {
            let p = (pose * Point3::new(c[0], c[1], c[2])).coords - view.eye;
            out[1 + 2 * n] = [p.x as f32, p.y as f32, p.z as f32, intensity as f32];
            out[2 + 2 * n] = [facing.x as f32, facing.y as f32, facing.z as f32, 0.0];
            n += 1;
        }
    }
    out[0] = [n as f32, Rain::FILM_SLOPE_RMS as f32, 0.0, 0.0];
    out
}
