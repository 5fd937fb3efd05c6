//! The outer walls of box-shaped buildings, and the framed windows and doors on them.

use super::footing::Footing;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;

/// One outer wall of a box-shaped object: `across` is 0 for a wall facing ±w (running
/// along u), 1 for one facing ±u; `side` the sign of its outward normal; `offset` its
/// distance from the centre.
#[derive(Clone, Copy)]
pub(super) struct Wall {
    pub across: usize,
    pub side: f64,
    pub offset: f64,
}

impl Wall {
    /// The point at `along` metres along the wall, height `y`, `proud` metres out of it.
    pub(super) fn p(self, f: &Footing, along: f64, y: f64, proud: f64) -> [f64; 3] {
        let out = self.side * (self.offset + proud);
        if self.across == 0 {
            f.p(along, y, out)
        } else {
            f.p(out, y, along)
        }
    }

    fn normal(self, f: &Footing) -> [f64; 3] {
        if self.across == 0 {
            f.dir(0.0, self.side)
        } else {
            f.dir(self.side, 0.0)
        }
    }

    /// A flat rectangle on the wall, `along` and `y` ranges, `proud` metres out of it.
    fn rect(
        self,
        mesh: &mut Mesh,
        f: &Footing,
        along: [f64; 2],
        y: [f64; 2],
        proud: f64,
        albedo: f64,
    ) {
        mesh.quad_with_normal(
            [
                self.p(f, along[0], y[0], proud),
                self.p(f, along[1], y[0], proud),
                self.p(f, along[1], y[1], proud),
                self.p(f, along[0], y[1], proud),
            ],
            self.normal(f),
            albedo,
            ObjectSlot::WORLD,
        );
    }

    /// A window or door `width` × `height` from `y0`, centred `along` the wall: a frame
    /// `frame` metres wide around a dark pane (each with its own edges), and for a window
    /// a sill under it that stands out of the wall.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn opening(
        self,
        mesh: &mut Mesh,
        f: &Footing,
        along: f64,
        y0: f64,
        size: [f64; 2],
        frame: f64,
        frame_albedo: f64,
        pane_albedo: f64,
        sill: bool,
    ) {
        let [hw, h] = [0.5 * size[0], size[1]];
        let bottom_frame = if sill { frame } else { 0.0 };
        self.rect(
            mesh,
            f,
            [along - hw - frame, along + hw + frame],
            [y0 - bottom_frame, y0 + h + frame],
            OPENING_FRAME_PROUD_M,
            frame_albedo,
        );
        self.rect(
            mesh,
            f,
            [along - hw, along + hw],
            [y0, y0 + h],
            OPENING_PANE_PROUD_M,
            pane_albedo,
        );
        if sill {
            // The sill: its top and front, 12 cm out of the wall, under the frame.
            let (a0, a1) = (along - hw - frame - 0.05, along + hw + frame + 0.05);
            let (y_lo, y_hi) = (y0 - frame - 0.06, y0 - frame);
            mesh.quad_with_normal(
                [
                    self.p(f, a0, y_hi, 0.0),
                    self.p(f, a1, y_hi, 0.0),
                    self.p(f, a1, y_hi, SILL_M),
                    self.p(f, a0, y_hi, SILL_M),
                ],
                [0.0, 1.0, 0.0],
                frame_albedo,
                ObjectSlot::WORLD,
            );
            self.rect(mesh, f, [a0, a1], [y_lo, y_hi], SILL_M, frame_albedo);
        }
    }
}

/// How far a window's or door's frame stands out of its wall, metres.
pub(super) const OPENING_FRAME_PROUD_M: f64 = 0.03;
/// How far its pane or leaf stands out of the wall, metres (in front of the frame).
pub(super) const OPENING_PANE_PROUD_M: f64 = 0.045;
/// How far a window sill stands out of its wall, metres.
const SILL_M: f64 = 0.12;
/// Albedo of window panes and door leaves.
pub(super) const PANE_ALBEDO: f64 = 0.08;

/// Frames lighter than a dark wall, darker than a light one, so they always show.
pub(super) fn frame_albedo(wall_albedo: f64) -> f64 {
    if wall_albedo < 0.62 {
        0.88
    } else {
        0.32
    }
}
