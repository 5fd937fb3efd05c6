//! Drawing the tracker's view over a camera frame: the window of interest, the predicted
//! model, and each edge point coloured by its fate.

use image::{GrayImage, Rgb, RgbImage};
use sim_core::FrameOutput;
use tracker::prediction::PredictedFeature;
use tracker::{EdgeDiagnostic, EdgeFate, Orientation, TrackOutput, Window};

/// The overlay's colours, by what they mark.
#[derive(Clone, Copy, Debug)]
pub struct OverlayColour;

impl OverlayColour {
    /// Window of interest: yellow.
    pub const WINDOW: Rgb<u8> = Rgb([255, 220, 0]);
    /// Predicted model features: green.
    pub const PREDICTED: Rgb<u8> = Rgb([0, 230, 0]);
    /// Edge points associated with a feature: red.
    pub const ASSOCIATED: Rgb<u8> = Rgb([255, 40, 40]);
    /// Classified edge points too far from every feature: blue.
    pub const TOO_FAR: Rgb<u8> = Rgb([60, 120, 255]);
    /// The measured object centre: magenta.
    pub const CENTRE: Rgb<u8> = Rgb([255, 0, 255]);
}

use OverlayColour as C;

/// The window of interest's corners, pixel centres, in drawing order (top-left, top-right,
/// bottom-right, bottom-left); `None` for an empty window.
pub(crate) fn window_corners(w: &Window) -> Option<[(f64, f64); 4]> {
    if w.is_empty() {
        return None;
    }
    let (x0, y0, x1, y1) = (
        w.x0 as f64,
        w.y0 as f64,
        (w.x1 - 1) as f64,
        (w.y1 - 1) as f64,
    );
    Some([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
}

/// A predicted feature's ends in the image, pixels.
pub(crate) fn feature_ends(p: &PredictedFeature) -> ((f64, f64), (f64, f64)) {
    match p.orientation {
        Orientation::Horizontal => ((p.extent[0], p.intercept), (p.extent[1], p.intercept)),
        Orientation::Vertical => ((p.intercept, p.extent[0]), (p.intercept, p.extent[1])),
    }
}

/// The frame in colour with the tracker's overlay. Weak and wrongly oriented points are not
/// drawn (there are many and they hide the image).
pub fn draw_overlay(frame: &GrayImage, out: &TrackOutput, edges: &[EdgeDiagnostic]) -> RgbImage {
    let mut img = RgbImage::from_fn(frame.width(), frame.height(), |x, y| {
        let g = frame.get_pixel(x, y)[0];
        Rgb([g, g, g])
    });
    if let Some(corners) = window_corners(&out.window) {
        for (k, &a) in corners.iter().enumerate() {
            line(&mut img, a, corners[(k + 1) % 4], C::WINDOW);
        }
    }
    for f in &out.features {
        let (a, b) = feature_ends(&f.predicted);
        line(&mut img, a, b, C::PREDICTED);
    }
    for e in edges {
        let colour = match e.fate {
            EdgeFate::Associated(_) => C::ASSOCIATED,
            EdgeFate::TooFar => C::TOO_FAR,
            EdgeFate::Weak | EdgeFate::WrongOrientation => continue,
        };
        put(&mut img, e.x.round() as i64, e.y.round() as i64, colour);
    }
    if let Some(m) = out.measurement {
        let (cx, cy) = (m.location.c_x, m.location.c_y);
        line(&mut img, (cx - 3.0, cy), (cx + 3.0, cy), C::CENTRE);
        line(&mut img, (cx, cy - 3.0), (cx, cy + 3.0), C::CENTRE);
    }
    img
}

/// A frame of the loop with its tracker's overlay: the paper's tracker's whole overlay
/// ([`draw_overlay`]), or, for a plug-in, a cross on the centre its estimate gives and a box
/// of the target's size at its scale, where it gives them.
pub fn draw_frame_overlay(out: &FrameOutput, target_size_px: [f64; 2]) -> RgbImage {
    if let Some(track) = &out.track {
        return draw_overlay(&out.image, track, &out.edges);
    }
    let frame = &out.image;
    let mut img = RgbImage::from_fn(frame.width(), frame.height(), |x, y| {
        let g = frame.get_pixel(x, y)[0];
        Rgb([g, g, g])
    });
    let e = out.estimate.as_ref();
    if let (Some(cx), Some(cy)) = (e.and_then(|e| e.cx), e.and_then(|e| e.cy)) {
        if let Some(scale) = e.and_then(|e| e.scale) {
            let [hw, hh] = target_size_px.map(|s| 0.5 * s * scale);
            let (x0, y0, x1, y1) = (cx - hw, cy - hh, cx + hw, cy + hh);
            for (a, b) in [
                ((x0, y0), (x1, y0)),
                ((x1, y0), (x1, y1)),
                ((x1, y1), (x0, y1)),
                ((x0, y1), (x0, y0)),
            ] {
                line(&mut img, a, b, C::PREDICTED);
            }
        }
        line(&mut img, (cx - 3.0, cy), (cx + 3.0, cy), C::CENTRE);
        line(&mut img, (cx, cy - 3.0), (cx, cy + 3.0), C::CENTRE);
    }
    img
}

fn put(img: &mut RgbImage, x: i64, y: i64, colour: Rgb<u8>) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, colour);
    }
}

/// A one-pixel line between two points (pixel centres at integer coordinates), clipped to
/// the image.
pub fn line(img: &mut RgbImage, a: (f64, f64), b: (f64, f64), colour: Rgb<u8>) {
    if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) {
        return;
    }
    let steps = (b.0 - a.0)
        .abs()
        .max((b.1 - a.1).abs())
        .ceil()
        .clamp(1.0, 4096.0) as usize;
    for k in 0..=steps {
        let t = k as f64 / steps as f64;
        let x = a.0 + t * (b.0 - a.0);
        let y = a.1 + t * (b.1 - a.1);
        put(img, x.round() as i64, y.round() as i64, colour);
    }
}
