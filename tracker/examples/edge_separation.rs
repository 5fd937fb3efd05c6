//! How close two parallel step edges may lie and stage 1 (2.3: the 3×3 gradient operator
//! and non-maximum suppression) still gives each its own edge points. This measurement sets
//! [`tracker::robust::EDGE_SEPARATION_PX`], the spacing below which two parallel features
//! whose extents overlap count as confusable ([`tracker::Resolvability`]).
//!
//! Two long horizontal edges `s` pixels apart, drawn at 16 sub-pixel phases, with the optics'
//! blur (σ 0.6 px, and 1 px) and sensor noise (σ 2 grey levels), both of the same sense (a staircase:
//! light, mid, dark) and of opposite senses (a dark stripe on a light board), each step 40 or
//! 80 grey levels. A column resolves the pair when one edge point lies within 1 px of each
//! edge and the two are distinct points. Run with
//! `cargo run --release -p tracker --example edge_separation`.

use tracker::edges::EdgeExtractor;
use tracker::synth::{draw, nist_ten_segment, Rect, SynthScene};
use tracker::{Camera, Edges, GrayView, Location, TrackerConfig, Window};

/// Sub-pixel phases of the first edge.
const PHASES: usize = 16;

/// The share of columns (over every phase) in which both edges have a point of their own.
fn resolved_share(spacing_px: f64, same_sense: bool, step: f64, blur: f64, seed: u64) -> f64 {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let config = TrackerConfig::default();
    let mut extractor = EdgeExtractor::default();
    let mut edges = Edges::default();
    let (mut hits, mut columns) = (0usize, 0usize);
    for phase in 0..PHASES {
        let top = 100.0 + phase as f64 / PHASES as f64;
        let bottom = top + spacing_px;
        let light = 180.0;
        let (middle, below) = if same_sense {
            (light - step, light - 2.0 * step)
        } else {
            (light - step, light)
        };
        let scene = SynthScene {
            background: light,
            noise_sigma: 2.0,
            blur_sigma: blur,
            distractors: vec![
                Rect {
                    bounds: [0.0, top, 256.0, bottom],
                    value: middle,
                },
                Rect {
                    bounds: [0.0, bottom, 256.0, 242.0],
                    value: below,
                },
            ],
            ..SynthScene::default()
        };
        // The target itself far outside the frame: only the two edges are drawn.
        let away = Location::new(-1000.0, -1000.0, 1.0);
        let px = draw(&model, &camera, away, &scene, seed * 1000 + phase as u64);
        let image = GrayView::new(scene.width, scene.height, &px).expect("frame");
        let window = Window {
            x0: 20,
            y0: 80,
            x1: 236,
            y1: 130,
            size_index: 0,
        };
        extractor.extract(image, window, &config, &mut edges, None);
        for x in window.x0..window.x1 {
            columns += 1;
            let column: Vec<f32> = edges
                .horizontal
                .iter()
                .filter(|p| p.x as usize == x)
                .map(|p| p.y)
                .collect();
            let near = |b: f64| {
                column
                    .iter()
                    .copied()
                    .filter(|&y| (f64::from(y) - b).abs() <= 1.0)
                    .min_by(|a, c| {
                        (f64::from(*a) - b)
                            .abs()
                            .total_cmp(&(f64::from(*c) - b).abs())
                    })
            };
            // Pixel centres are integers: a boundary at y = b lies in the pixel nearest b.
            if let (Some(a), Some(b)) = (near(top), near(bottom)) {
                if a != b {
                    hits += 1;
                }
            }
        }
    }
    hits as f64 / columns as f64
}

fn main() {
    println!("blur 0.6 px: same_40 same_80 opposite_40 opposite_80; blur 1.0 px: the same");
    println!("spacing_px  s40    s80    o40    o80  | s40    s80    o40    o80");
    let mut s = 1.0;
    while s <= 5.0 + 1e-9 {
        let cases = [(true, 40.0), (true, 80.0), (false, 40.0), (false, 80.0)];
        let row: Vec<String> = [0.6, 1.0]
            .iter()
            .flat_map(|&blur| cases.iter().map(move |&(same, step)| (blur, same, step)))
            .map(|(blur, same, step)| {
                let share = (1..=3)
                    .map(|seed| resolved_share(s, same, step, blur, seed))
                    .sum::<f64>()
                    / 3.0;
                format!("{share:.3}")
            })
            .collect();
        println!(
            "{s:10.2}  {} | {}",
            row[..4].join("  "),
            row[4..].join("  ")
        );
        s += 0.25;
    }
}
