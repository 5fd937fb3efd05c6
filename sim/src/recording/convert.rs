//! carfollow's values as Foxglove messages: the conversions the recorder's writer uses
//! (colours, times, poses, points), the tracker's state of a frame, and the camera
//! image's annotations.

use super::messages::TrackerState;
use crate::overlay::{feature_ends, window_corners, OverlayColour};
use foxglove::messages::{
    points_annotation, Color, FrameTransform, ImageAnnotations, Point2, PointsAnnotation,
    Quaternion, Timestamp, Vector3,
};
use image::Rgb;
use nalgebra::{Isometry3, UnitQuaternion, Vector3 as NaVector3};
use sim_core::FrameOutput;
use sim_core::TrackerStatus;
use tracker::EdgeFate;

/// An RGB colour of the overlay as Foxglove's colour.
pub(super) fn color(c: Rgb<u8>) -> Color {
    Color {
        r: f64::from(c[0]) / 255.0,
        g: f64::from(c[1]) / 255.0,
        b: f64::from(c[2]) / 255.0,
        a: 1.0,
    }
}

pub(super) fn timestamp(ns: u64) -> Timestamp {
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

/// An image point of the project's convention (pixel centres at integers) in Foxglove's
/// (the top-left pixel's top-left corner at the origin).
pub(super) fn pixel(x: f64, y: f64) -> Point2 {
    Point2 {
        x: x + 0.5,
        y: y + 0.5,
    }
}

pub(super) fn vector3(v: &NaVector3<f64>) -> Vector3 {
    Vector3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

pub(super) fn quaternion(q: &UnitQuaternion<f64>) -> Quaternion {
    Quaternion {
        x: q.i,
        y: q.j,
        z: q.k,
        w: q.w,
    }
}

pub(super) fn transform(
    ts: Timestamp,
    parent: &str,
    child: &str,
    iso: &Isometry3<f64>,
) -> FrameTransform {
    FrameTransform {
        timestamp: Some(ts),
        parent_frame_id: parent.into(),
        child_frame_id: child.into(),
        translation: Some(vector3(&iso.translation.vector)),
        rotation: Some(quaternion(&iso.rotation)),
    }
}

pub(super) fn points(
    kind: points_annotation::Type,
    pts: Vec<Point2>,
    c: Rgb<u8>,
    ts: Timestamp,
) -> PointsAnnotation {
    PointsAnnotation {
        timestamp: Some(ts),
        r#type: kind as i32,
        points: pts,
        outline_color: Some(color(c)),
        thickness: 1.0,
        ..PointsAnnotation::default()
    }
}

pub(super) fn status_code(s: TrackerStatus) -> u32 {
    match s {
        TrackerStatus::Tracking => 0,
        TrackerStatus::Coasting => 1,
        TrackerStatus::Lost => 2,
    }
}

pub(super) fn finite_or_nan(v: Option<f32>) -> f64 {
    v.map_or(f64::NAN, f64::from)
}

/// `v`, or NaN where it is not finite: a plot leaves a gap at NaN, where an infinity would
/// stretch its axis to nothing (`frames.csv` leaves these cells empty).
pub(super) fn plottable(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        f64::NAN
    }
}

/// The tracker's state for a frame: the paper's tracker's whole output, or what a plug-in's
/// estimate says (the rest not a number).
pub(super) fn tracker_state(out: &FrameOutput) -> TrackerState {
    let r = &out.record;
    let Some(t) = &out.track else {
        return TrackerState {
            frame: r.frame,
            t_s: r.t_s,
            status: r.status.as_str().into(),
            status_code: status_code(r.status),
            measured: out.estimate.is_some(),
            est_cx_px: r.est_cx,
            est_cy_px: r.est_cy,
            est_scale: r.est_scale,
            pred_cx_px: f64::NAN,
            pred_cy_px: f64::NAN,
            pred_scale: f64::NAN,
            x_m: r.est_lateral_m,
            y_m: out.estimate.and_then(|e| e.vertical_m).unwrap_or(f64::NAN),
            z_m: r.est_range_m,
            confidence_x: f64::NAN,
            confidence_y: f64::NAN,
            confidence_scale: f64::NAN,
            coverage_h: f64::NAN,
            coverage_v: f64::NAN,
            coverage_gain: f64::NAN,
            edge_threshold: f64::NAN,
            searched: false,
            event: String::new(),
            window_size: 0,
        };
    };
    let m = t.measurement;
    let confidence = m.map_or([0.0; 3], |m| m.confidence);
    TrackerState {
        frame: r.frame,
        t_s: t.t_s,
        status: r.status.as_str().into(),
        status_code: status_code(r.status),
        measured: m.is_some(),
        est_cx_px: t.estimate.c_x,
        est_cy_px: t.estimate.c_y,
        est_scale: t.estimate.scale,
        pred_cx_px: t.predicted.c_x,
        pred_cy_px: t.predicted.c_y,
        pred_scale: t.predicted.scale,
        x_m: t.position_3d[0],
        y_m: t.position_3d[1],
        z_m: t.position_3d[2],
        confidence_x: confidence[0],
        confidence_y: confidence[1],
        confidence_scale: confidence[2],
        coverage_h: t.coverage[0],
        coverage_v: t.coverage[1],
        coverage_gain: plottable(t.coverage_gain),
        edge_threshold: t.edge_threshold,
        searched: t.searched,
        event: r.tracker_event.clone(),
        window_size: t.window.size_index as u32,
    }
}

/// A cross on the measured centre.
pub(super) fn centre(cx: f64, cy: f64, ts: Timestamp) -> PointsAnnotation {
    points(
        points_annotation::Type::LineList,
        vec![
            pixel(cx - 3.0, cy),
            pixel(cx + 3.0, cy),
            pixel(cx, cy - 3.0),
            pixel(cx, cy + 3.0),
        ],
        OverlayColour::CENTRE,
        ts,
    )
}

/// What the overlay draws, as image annotations: the window of interest, the predicted
/// model, associated and rejected edge points, and the measured centre (for a plug-in,
/// the centre its estimate gives, if any).
pub(super) fn annotations(out: &FrameOutput, ts: Timestamp) -> ImageAnnotations {
    use points_annotation::Type;
    let mut list = Vec::new();
    let Some(t) = &out.track else {
        let e = out.estimate.as_ref();
        if let (Some(cx), Some(cy)) = (e.and_then(|e| e.cx), e.and_then(|e| e.cy)) {
            list.push(centre(cx, cy, ts));
        }
        return ImageAnnotations {
            timestamp: Some(ts),
            points: list,
            ..ImageAnnotations::default()
        };
    };
    if let Some(corners) = window_corners(&t.window) {
        list.push(points(
            Type::LineLoop,
            corners.iter().map(|&(x, y)| pixel(x, y)).collect(),
            OverlayColour::WINDOW,
            ts,
        ));
    }
    let mut model = Vec::with_capacity(2 * t.features.len());
    for f in &t.features {
        let (a, b) = feature_ends(&f.predicted);
        model.push(pixel(a.0, a.1));
        model.push(pixel(b.0, b.1));
    }
    if !model.is_empty() {
        list.push(points(Type::LineList, model, OverlayColour::PREDICTED, ts));
    }
    let (mut associated, mut rejected) = (Vec::new(), Vec::new());
    for e in &out.edges {
        let p = pixel(f64::from(e.x), f64::from(e.y));
        match e.fate {
            EdgeFate::Associated(_) => associated.push(p),
            EdgeFate::TooFar => rejected.push(p),
            EdgeFate::Weak | EdgeFate::WrongOrientation => {}
        }
    }
    for (pts, c) in [
        (associated, OverlayColour::ASSOCIATED),
        (rejected, OverlayColour::TOO_FAR),
    ] {
        if !pts.is_empty() {
            let mut a = points(Type::Points, pts, c, ts);
            a.thickness = 2.0;
            list.push(a);
        }
    }
    if let Some(m) = t.measurement {
        list.push(centre(m.location.c_x, m.location.c_y, ts));
    }
    ImageAnnotations {
        timestamp: Some(ts),
        points: list,
        ..ImageAnnotations::default()
    }
}
