//! The camera's view with the tracker's overlay as an animated GIF, written frame by frame.
//!
//! **Palette.** Every frame uses one fixed global palette, so nothing is quantised adaptively
//! and the same frames always give the same bytes (and encoding is one table look-up per
//! pixel): the 5 overlay colours of [`crate::overlay`] exactly, a 3×3×3 colour cube for
//! anything else that is not grey, and 224 grey levels (the camera's grey image loses less than
//! half a level).
//!
//! **Timing.** GIF delays are whole centiseconds; 15 fps is 6⅔ cs per frame. Frame `k`'s delay
//! is `round(100 (k+1) / 15) − round(100 k / 15)`: the repeating pattern 7, 6, 7 cs
//! ([`GIF_DELAYS_CS`]), exactly 15 fps on average (a fixed 7 cs would play 5 % slow). With a
//! stride of `n` recorded frames per video frame the delays cover `n` frames each.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use image::{Rgb, RgbImage};

use super::ReportError;
use crate::overlay::OverlayColour;

/// The GIF delays of consecutive frames at 15 fps, centiseconds; the pattern repeats.
pub const GIF_DELAYS_CS: [u16; 3] = [7, 6, 7];

/// Number of grey levels in the palette.
const GREYS: usize = 224;
/// The overlay's colours, matched exactly.
const OVERLAY: [Rgb<u8>; 5] = [
    OverlayColour::WINDOW,
    OverlayColour::PREDICTED,
    OverlayColour::ASSOCIATED,
    OverlayColour::TOO_FAR,
    OverlayColour::CENTRE,
];
/// Levels of the colour cube for other colours.
const CUBE: [u8; 3] = [0, 128, 255];

/// A streaming GIF writer: each frame is encoded and written as it comes.
pub struct VideoWriter {
    path: PathBuf,
    encoder: gif::Encoder<BufWriter<File>>,
    size: (u32, u32),
    palette: Palette,
    frames: u64,
    stride: u32,
    indices: Vec<u8>,
}

impl std::fmt::Debug for VideoWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VideoWriter")
            .field("path", &self.path)
            .field("size", &self.size)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}

impl VideoWriter {
    /// Creates the GIF at `path` for frames of `width` × `height` pixels; it loops forever.
    /// `stride` is the number of recorded frames each video frame stands for (1 = every frame;
    /// the caller skips the others), which only sets the delays.
    pub fn create(
        path: impl AsRef<Path>,
        width: u32,
        height: u32,
        stride: u32,
    ) -> Result<VideoWriter, ReportError> {
        let path = path.as_ref().to_path_buf();
        let (w, h) = match (u16::try_from(width), u16::try_from(height)) {
            (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
            _ => {
                return Err(ReportError::FrameSize {
                    path,
                    frame: 0,
                    width,
                    height,
                    expected_width: width.clamp(1, 65535),
                    expected_height: height.clamp(1, 65535),
                })
            }
        };
        let palette = Palette::new();
        let file = File::create(&path).map_err(ReportError::io(&path))?;
        let gif_err = |p: &Path| {
            let p = p.to_path_buf();
            move |source| ReportError::Gif { path: p, source }
        };
        let mut encoder =
            gif::Encoder::new(BufWriter::new(file), w, h, &palette.rgb).map_err(gif_err(&path))?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(gif_err(&path))?;
        Ok(VideoWriter {
            path,
            encoder,
            size: (width, height),
            palette,
            frames: 0,
            stride: stride.max(1),
            indices: Vec::new(),
        })
    }

    /// Video frames written so far.
    #[cfg(test)]
    fn frames(&self) -> u64 {
        self.frames
    }

    /// Encodes and writes the next frame.
    pub fn write(&mut self, img: &RgbImage) -> Result<(), ReportError> {
        if img.dimensions() != self.size {
            return Err(ReportError::FrameSize {
                path: self.path.clone(),
                frame: self.frames,
                width: img.width(),
                height: img.height(),
                expected_width: self.size.0,
                expected_height: self.size.1,
            });
        }
        self.indices.clear();
        self.indices
            .extend(img.pixels().map(|p| self.palette.index(*p)));
        let mut frame = gif::Frame {
            width: self.size.0 as u16,
            height: self.size.1 as u16,
            delay: self.delay_cs(self.frames),
            ..gif::Frame::default()
        };
        frame.buffer = std::borrow::Cow::Borrowed(&self.indices);
        self.encoder
            .write_frame(&frame)
            .map_err(|source| ReportError::Gif {
                path: self.path.clone(),
                source,
            })?;
        self.frames += 1;
        Ok(())
    }

    /// Writes the GIF trailer and flushes the file.
    pub fn finish(self) -> Result<PathBuf, ReportError> {
        let path = self.path;
        let mut out = self
            .encoder
            .into_inner()
            .map_err(|source| ReportError::Gif {
                path: path.clone(),
                source,
            })?;
        std::io::Write::flush(&mut out).map_err(ReportError::io(&path))?;
        Ok(path)
    }

    /// Delay of video frame `k`, centiseconds (see the module notes).
    fn delay_cs(&self, k: u64) -> u16 {
        let s = u64::from(self.stride);
        let at = |k: u64| (200 * k * s + 15) / 30; // round(100 k s / 15)
        (at(k + 1) - at(k)) as u16
    }
}

/// The fixed palette and its look-up.
struct Palette {
    /// 256 RGB triples.
    rgb: Vec<u8>,
}

impl Palette {
    fn new() -> Palette {
        let mut rgb = Vec::with_capacity(768);
        for i in 0..GREYS {
            let g = ((i * 255 + (GREYS - 1) / 2) / (GREYS - 1)) as u8;
            rgb.extend([g, g, g]);
        }
        for c in OVERLAY {
            rgb.extend(c.0);
        }
        for r in CUBE {
            for g in CUBE {
                for b in CUBE {
                    rgb.extend([r, g, b]);
                }
            }
        }
        debug_assert_eq!(rgb.len(), 768);
        Palette { rgb }
    }

    /// The palette index of a colour: the nearest grey for greys, the exact overlay colour,
    /// else the nearest entry by squared RGB distance (lowest index on ties).
    fn index(&self, p: Rgb<u8>) -> u8 {
        let [r, g, b] = p.0;
        if r == g && g == b {
            return ((usize::from(r) * (GREYS - 1) + 127) / 255) as u8;
        }
        if let Some(i) = OVERLAY.iter().position(|c| *c == p) {
            return (GREYS + i) as u8;
        }
        let mut best = (u32::MAX, 0u8);
        for (i, e) in self.rgb.chunks_exact(3).enumerate() {
            let d = [r, g, b]
                .iter()
                .zip(e)
                .map(|(a, b)| (i32::from(*a) - i32::from(*b)).pow(2) as u32)
                .sum::<u32>();
            if d < best.0 {
                best = (d, i as u8);
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::AnimationDecoder;

    fn frame(k: u32) -> RgbImage {
        let mut img = RgbImage::from_fn(64, 48, |x, y| {
            let g = ((x * 4 + y + k * 8) % 256) as u8;
            Rgb([g, g, g])
        });
        for x in 0..64 {
            img.put_pixel(x, 10 + k, OverlayColour::WINDOW);
        }
        img.put_pixel(5, 5, OverlayColour::CENTRE);
        img.put_pixel(6, 5, Rgb([10, 200, 100]));
        img
    }

    #[test]
    fn palette_keeps_greys_and_overlay_colours() {
        let p = Palette::new();
        let colour = |i: u8| {
            let i = usize::from(i) * 3;
            [p.rgb[i], p.rgb[i + 1], p.rgb[i + 2]]
        };
        for g in 0..=255u8 {
            let c = colour(p.index(Rgb([g, g, g])));
            assert!(c[0] == c[1] && c[1] == c[2]);
            assert!((i32::from(c[0]) - i32::from(g)).abs() <= 1, "{g} -> {c:?}");
        }
        for c in OVERLAY {
            assert_eq!(colour(p.index(c)), c.0);
        }
        assert_eq!(colour(p.index(Rgb([250, 5, 130]))), [255, 0, 128]);
    }

    #[test]
    fn delays_average_exactly_15_fps() {
        let dir = tempfile::tempdir().unwrap();
        let w = VideoWriter::create(dir.path().join("v.gif"), 4, 4, 1).unwrap();
        let delays: Vec<u16> = (0..6).map(|k| w.delay_cs(k)).collect();
        assert_eq!(delays, [7, 6, 7, 7, 6, 7]);
        assert_eq!(&delays[..3], &GIF_DELAYS_CS);
        let total: u32 = (0..150).map(|k| u32::from(w.delay_cs(k))).sum();
        assert_eq!(total, 1000);
        let w = VideoWriter::create(dir.path().join("v2.gif"), 4, 4, 3).unwrap();
        assert_eq!(w.delay_cs(0), 20);
    }

    #[test]
    fn gif_decodes_with_its_frames_and_is_deterministic() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str| {
            let path = dir.path().join(name);
            let mut v = VideoWriter::create(&path, 64, 48, 1).unwrap();
            for k in 0..5 {
                v.write(&frame(k)).unwrap();
            }
            assert_eq!(v.frames(), 5);
            v.finish().unwrap()
        };
        let a = write("a.gif");
        let b = write("b.gif");
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());

        let file = std::io::BufReader::new(File::open(&a).unwrap());
        let frames = image::codecs::gif::GifDecoder::new(file)
            .unwrap()
            .into_frames()
            .collect_frames()
            .unwrap();
        assert_eq!(frames.len(), 5);
        let (num, den) = frames[1].delay().numer_denom_ms();
        assert_eq!(num / den, 60);
        let f2 = frames[2].buffer();
        assert_eq!(f2.dimensions(), (64, 48));
        assert_eq!(f2.get_pixel(0, 12).0, [255, 220, 0, 255]);
        assert_eq!(f2.get_pixel(5, 5).0, [255, 0, 255, 255]);
        let grey = f2.get_pixel(30, 30).0;
        let want: i32 = 30 * 4 + 30 + 16;
        assert!((i32::from(grey[0]) - want).abs() <= 1, "{grey:?} vs {want}");
    }

    #[test]
    fn a_frame_of_the_wrong_size_is_refused_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let mut v = VideoWriter::create(dir.path().join("v.gif"), 64, 48, 1).unwrap();
        let err = v.write(&RgbImage::new(10, 10)).unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("v.gif") && msg.contains("10x10"), "{msg}");
    }
}
