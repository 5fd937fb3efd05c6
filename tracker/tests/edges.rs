//! Stage 1 on hand-made images: a step edge gives a one-pixel-wide line of edge points in
//! the right place and the right class; weak and diagonal edges are dropped for the right
//! reason; the fast class test agrees with eq. 3 and 7.
//! Run with `cargo test -p tracker --test edges`.

use tracker::edges::{classify_direction, edge_direction, EdgeExtractor};
use tracker::{EdgeFate, Edges, GrayView, Orientation, TrackerConfig, Window};

const W: usize = 40;
const H: usize = 30;

fn whole(w: usize, h: usize) -> Window {
    Window {
        x0: 1,
        y0: 1,
        x1: w - 1,
        y1: h - 1,
        size_index: 0,
    }
}

fn extract(pixels: &[u8], config: &TrackerConfig) -> (Edges, Vec<tracker::EdgeDiagnostic>) {
    let image = GrayView::new(W, H, pixels).unwrap();
    let mut edges = Edges::default();
    let mut diag = Vec::new();
    EdgeExtractor::default().extract(image, whole(W, H), config, &mut edges, Some(&mut diag));
    (edges, diag)
}

#[test]
fn vertical_step_gives_a_one_pixel_vertical_line() {
    // Dark left half (x ≤ 19), light right half: the boundary lies at x = 19.5.
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i % W < 20 { 50 } else { 150 })
        .collect();
    let (edges, _) = extract(&px, &TrackerConfig::default());
    assert!(edges.horizontal.is_empty(), "no horizontal points expected");
    // One point per row (rows 1..H-1), all in the same column next to the boundary.
    assert_eq!(edges.vertical.len(), H - 2, "one point per row");
    for p in &edges.vertical {
        assert_eq!(p.x, 19.0, "ties keep the pixel nearer the origin: {p:?}");
    }
}

#[test]
fn horizontal_step_gives_a_one_pixel_horizontal_line() {
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i / W < 12 { 200 } else { 90 })
        .collect();
    let (edges, _) = extract(&px, &TrackerConfig::default());
    assert!(edges.vertical.is_empty());
    assert_eq!(edges.horizontal.len(), W - 2);
    assert!(edges.horizontal.iter().all(|p| p.y == 11.0));
}

#[test]
fn off_centre_boundary_is_found_on_the_nearer_pixel() {
    // Pixel 19 (covering x = 18.5 to 19.5) is a fifth light, so the boundary sits at
    // x = 19.3. The normalised gradient is 10 at pixel 18, 50 at 19 and 40 at 20: the
    // maximum is at pixel 19.
    let px: Vec<u8> = (0..W * H)
        .map(|i| match i % W {
            x if x < 19 => 50,
            19 => 70,
            _ => 150,
        })
        .collect();
    let (edges, _) = extract(&px, &TrackerConfig::default());
    assert!(
        edges.vertical.iter().all(|p| p.x == 19.0),
        "{:?}",
        &edges.vertical[..3]
    );
    // With sub-pixel edges on, the parabola through (18, 10), (19, 50), (20, 40) peaks at
    // 19 + (10 − 40) / (2 (10 − 2·50 + 40)) = 19.3, the true boundary.
    let config = TrackerConfig {
        subpixel_edges: true,
        ..TrackerConfig::default()
    };
    let (sub, _) = extract(&px, &config);
    for p in &sub.vertical {
        assert!((p.x - 19.3).abs() < 1e-4, "sub-pixel x = {}", p.x);
    }
}

#[test]
fn weak_step_is_dropped_as_weak() {
    // The threshold is on eq. 4's |∇f| (the Sobel response over 8): a 15-grey-level step has
    // |∇f| = 7.5, below the paper's threshold of 8.
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i % W < 20 { 100 } else { 115 })
        .collect();
    let (edges, diag) = extract(&px, &TrackerConfig::default());
    assert!(edges.vertical.is_empty());
    assert_eq!(
        diag.iter().filter(|d| d.fate == EdgeFate::Weak).count(),
        H - 2
    );
    // A 16-level step, |∇f| = 8, passes.
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i % W < 20 { 100 } else { 116 })
        .collect();
    let (edges, _) = extract(&px, &TrackerConfig::default());
    assert_eq!(edges.vertical.len(), H - 2);
    // So does an 8-level step at a threshold of 4.
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i % W < 20 { 100 } else { 108 })
        .collect();
    let config = TrackerConfig {
        edge_threshold: 4.0,
        ..TrackerConfig::default()
    };
    let (edges, _) = extract(&px, &config);
    assert_eq!(edges.vertical.len(), H - 2);
}

#[test]
fn diagonal_edge_has_the_wrong_orientation() {
    // A 45° boundary x + y = 35.
    let px: Vec<u8> = (0..W * H)
        .map(|i| if i % W + i / W < 35 { 40 } else { 200 })
        .collect();
    let (edges, diag) = extract(&px, &TrackerConfig::default());
    assert!(edges.vertical.is_empty() && edges.horizontal.is_empty());
    assert!(
        diag.iter()
            .filter(|d| d.fate == EdgeFate::WrongOrientation)
            .count()
            > 10
    );
}

#[test]
fn edge_direction_follows_eq3() {
    // Gradient along x (a vertical edge): θ = 0; along y (a horizontal edge): θ = π/2.
    assert!(
        edge_direction(10.0, 0.0).abs() < 1e-12
            || (edge_direction(10.0, 0.0) - std::f64::consts::PI).abs() < 1e-12
    );
    assert!((edge_direction(0.0, 10.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
}

#[test]
fn fast_classes_agree_with_eq3_and_eq7() {
    // The extractor classifies by comparing |∇f_x| and tan δ · |∇f_y|; check that it gives
    // the class of eq. 7 applied to θ of eq. 3 over a grid of gradients, using one-pixel
    // images built to have exactly that gradient at their centre.
    let delta = 15f64.to_radians();
    let config = TrackerConfig {
        edge_threshold: 0.0,
        ..TrackerConfig::default()
    };
    let mut checked = 0;
    for gx in -12i32..=12 {
        for gy in -12i32..=12 {
            if gx == 0 && gy == 0 {
                continue;
            }
            let want = classify_direction(edge_direction(f64::from(gx), f64::from(gy)), delta);
            // A linear ramp f = 100 + a x + b y has raw Sobel gradient (8a, 8b); a = 2·gx
            // and b = 2·gy keep its values whole grey levels and its gradient along (gx, gy).
            let img: Vec<u8> = (0..9)
                .map(|i| {
                    let (x, y) = (f64::from(i % 3) - 1.0, f64::from(i / 3) - 1.0);
                    (100.0 + f64::from(gx) * x * 2.0 + f64::from(gy) * y * 2.0) as u8
                })
                .collect();
            let image = GrayView::new(3, 3, &img).unwrap();
            let mut edges = Edges::default();
            let window = Window {
                x0: 1,
                y0: 1,
                x1: 2,
                y1: 2,
                size_index: 0,
            };
            EdgeExtractor::default().extract(image, window, &config, &mut edges, None);
            let got = if !edges.horizontal.is_empty() {
                Some(Orientation::Horizontal)
            } else if !edges.vertical.is_empty() {
                Some(Orientation::Vertical)
            } else {
                None
            };
            assert_eq!(got, want, "gradient ({gx}, {gy})");
            checked += 1;
        }
    }
    assert!(checked > 600);
}

#[test]
fn the_fast_path_gives_exactly_the_points_of_the_general_path() {
    // A noisy cluttered frame of the target: stage 1 with and without diagnostics (the
    // latter takes the axis-aligned fast path) must give identical point lists.
    use tracker::synth::{draw, Rect, SynthScene};
    use tracker::{Camera, Location, TargetModel};
    let model = TargetModel::new(
        "t",
        10.0,
        vec![
            [-0.8, 0.5],
            [0.8, 0.5],
            [0.8, -0.5],
            [-0.8, -0.5],
            [-0.4, 0.25],
            [0.4, 0.25],
            [0.4, -0.25],
            [-0.4, -0.25],
        ],
        vec![
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
        ],
    )
    .unwrap();
    let scene = SynthScene {
        noise_sigma: 6.0,
        distractors: vec![Rect {
            bounds: [60.0, 0.0, 63.0, 242.0],
            value: 50.0,
        }],
        shadows: vec![Rect {
            bounds: [100.0, 30.0, 140.0, 200.0],
            value: 0.5,
        }],
        ..SynthScene::default()
    };
    let px = draw(
        &model,
        &Camera::default(),
        Location::new(120.0, 110.0, 1.3),
        &scene,
        9,
    );
    let image = GrayView::new(256, 242, &px).unwrap();
    for subpixel_edges in [false, true] {
        let config = TrackerConfig {
            subpixel_edges,
            ..TrackerConfig::default()
        };
        // The whole frame, including its border rows and columns.
        let window = Window {
            x0: 1,
            y0: 1,
            x1: 255,
            y1: 241,
            size_index: 6,
        };
        let (mut fast, mut general) = (Edges::default(), Edges::default());
        let mut diag = Vec::new();
        EdgeExtractor::default().extract(image, window, &config, &mut fast, None);
        EdgeExtractor::default().extract(image, window, &config, &mut general, Some(&mut diag));
        assert!(fast.horizontal.len() > 100 && fast.vertical.len() > 100);
        assert_eq!(fast, general, "subpixel_edges = {subpixel_edges}");
    }
}
