//! Street lights: poles along the route's right edge, each with an arm reaching over the
//! road and a lamp head at its end ([`StreetLights`]). By day they are poles that stand and
//! cast shadows; at night (the sun at or below the horizon) each head lights the scene as a
//! spot light pointing straight down, with a cut-off cone and an inverse-square fall-off,
//! and its lens glows, brightest to a camera inside the cone.

use super::built_scene::Scene;
use super::description::SceneDescription;
use super::footing::Footing;
use super::layer::Layer;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use super::pole::POLE_ALBEDO;
use super::site::Site;
use super::standing::stand;
use super::Headlamps;

/// The street lights' photometry and shape.
pub struct StreetLights;

impl StreetLights {
    /// The lens's bottom's height above the ground, metres: EN 13201's traffic routes are
    /// lit from 8–12 m; the lowest.
    pub const HEIGHT_M: f64 = 8.0;
    /// How far beyond the paved road's edge the pole stands, metres.
    pub const SETBACK_M: f64 = 1.0;
    /// How far the arm reaches from the pole over the road, metres: the lens is
    /// `REACH_M − SETBACK_M` = 1 m inside the road's edge.
    pub const REACH_M: f64 = 2.0;
    /// The luminous intensity inside the cone, candela: a road luminaire of about
    /// 10 000 lm (a 100 W LED head) spread evenly over a cone of 70° half-angle
    /// (2π (1 − cos 70°) = 4.1 sr; 10 300 lm / 4.1 sr = 2 500 cd). Under the lamp,
    /// 2 500 / 8² = 39 lux, the road's mean with lamps every 33 m 5–15 lux, as EN 13201's
    /// classes M3–M5 ask.
    pub const PEAK_CD: f64 = 2_500.0;
    /// The cone's half-angle from the downward vertical, degrees: inside it the intensity
    /// is [`StreetLights::PEAK_CD`].
    pub const CONE_HALF_DEG: f64 = 70.0;
    /// The width of the cut-off, degrees: from the cone's edge the intensity falls over it
    /// (a smoothstep) to [`StreetLights::STRAY`] of the peak, at 75°.
    pub const CUT_OFF_RAMP_DEG: f64 = 5.0;
    /// The share of the peak intensity left past the cut-off, up to the horizontal (none
    /// above it): 250 cd, the most IES's "cut-off" class allows at 90° from the nadir for
    /// 10 000 lm (25 cd per 1 000 lm; 100 cd per 1 000 lm at 80°). It is what makes a
    /// lamp's lens glow to a camera far down the road.
    pub const STRAY: f64 = 0.1;
    /// The lens: along the road and across it, metres (facing down).
    pub const LENS_M: [f64; 2] = [0.5, 0.25];
    /// How far the lens bulges below the housing, metres (a drop lens): its sides glow too,
    /// so that a lamp far down the road, its lens seen almost edge-on, still covers
    /// part of a pixel.
    pub const LENS_DEPTH_M: f64 = 0.08;
    /// The lens's albedo for the light that falls on it (frosted glass), and its whole
    /// albedo by day.
    pub const LENS_ALBEDO: f64 = 0.5;
    /// The albedo a lit lens's vertices carry in its place: the shader takes any albedo at
    /// least [`StreetLights::MARK_MIN`] for a lit lens, of albedo
    /// [`StreetLights::LENS_ALBEDO`], that glows. Above the tail lamps' marks.
    pub const MARK: f64 = 32.0;
    /// The least albedo the shader reads as a lit lens's mark.
    pub const MARK_MIN: f64 = 16.0;
    /// How many lamps light a frame: the nearest to the camera, so that a fragment's cost
    /// does not grow with the route. With lamps every 33 m (30 a km), the eighth nearest
    /// is 100–130 m away, where its pool of light spans a few pixels.
    pub const LIT_MAX: usize = 8;
    /// The albedo of the arm and the head's housing (painted steel, as the poles).
    const HOUSING_ALBEDO: f64 = POLE_ALBEDO;
    /// How far below the lens the light comes from, metres: just below it, so that the
    /// lens's own faces lie outside the cone and take none of their lamp's light.
    const SOURCE_BELOW_LENS_M: f64 = 0.01;

    /// Whether street lights are lit in `description`: some along the route, and the sun at
    /// or below the horizon (the twilight branch of [`crate::scene::Sun::lighting`]).
    pub fn lit(description: &SceneDescription) -> bool {
        description.densities.street_lights_per_km > 0.0 && description.sun.elevation_deg <= 0.0
    }

    /// The luminous intensity (cd) at `from_nadir_deg` degrees from the downward vertical:
    /// [`StreetLights::PEAK_CD`] inside the cone, falling over the cut-off to
    /// [`StreetLights::STRAY`] of it, none above the horizontal (the shader's formula).
    pub fn intensity_cd(from_nadir_deg: f64) -> f64 {
        if from_nadir_deg > 90.0 {
            return 0.0;
        }
        let t = ((from_nadir_deg - Self::CONE_HALF_DEG) / Self::CUT_OFF_RAMP_DEG).clamp(0.0, 1.0);
        Self::PEAK_CD * (1.0 + (Self::STRAY - 1.0) * t * t * (3.0 - 2.0 * t))
    }

    /// The illuminance (lux) a lamp at `source` gives a surface at `point` with unit
    /// normal `normal` (world, metres): I(θ) cos(incidence) / d² (the inverse-square law
    /// for a point source).
    pub fn illuminance_lux(source: [f64; 3], point: [f64; 3], normal: [f64; 3]) -> f64 {
        let v = [
            point[0] - source[0],
            point[1] - source[1],
            point[2] - source[2],
        ];
        let d2 = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).max(1e-4);
        let d = d2.sqrt();
        let from_nadir = (-v[1] / d).clamp(-1.0, 1.0).acos().to_degrees();
        let incidence = -(v[0] * normal[0] + v[1] * normal[1] + v[2] * normal[2]) / d;
        Self::intensity_cd(from_nadir) * incidence.max(0.0) / d2
    }

    /// The lens's radiance in the scene's units (before the sensor's brightness), seen
    /// from inside the cone: its intensity over its area, a luminance of 20 000 cd/m²,
    /// times π / [`Headlamps::LUX_PER_UNIT`] (as the tail lamps' `radiance`): 39, far
    /// above the board's white paint in full sun (about 0.8). Seen from past the cut-off,
    /// [`StreetLights::STRAY`] of it, 3.9: a lens in view at night is white.
    pub fn lens_radiance() -> f64 {
        let luminance = Self::PEAK_CD / (Self::LENS_M[0] * Self::LENS_M[1]);
        std::f64::consts::PI * luminance / Headlamps::LUX_PER_UNIT
    }

    /// The stations of the lamps along a route `length` metres long: every
    /// `1000 / street_lights_per_km` metres from half a spacing after 50 m before the
    /// start, to 100 m past the end, none within `margin_m` of an intersection. Regular, so
    /// nothing is drawn from a random stream.
    fn stations(site: &Site<'_>, margin_m: f64) -> Vec<f64> {
        let per_km = site.description.densities.street_lights_per_km;
        if per_km <= 0.0 {
            return Vec::new();
        }
        // Capped, so that any positive density gives a finite spacing (see `pole_line`).
        let spacing = (1000.0 / per_km).min(1e9);
        let mut stations = Vec::new();
        let mut k = 0.0;
        loop {
            let s = -50.0 + (k + 0.5) * spacing;
            if s >= site.length + 100.0 {
                break;
            }
            k += 1.0;
            if !site.route.near_intersection(s, margin_m) {
                stations.push(s);
            }
        }
        stations
    }

    /// One street light at station `s` of `site` in `mesh` (the world's slot), stood on
    /// the ground; returns where its light comes from (world, metres).
    fn build(site: &Site<'_>, s: f64, mesh: &mut Mesh) -> [f64; 3] {
        let lit = Self::lit(site.description);
        let heading = site.route.at(s)[2];
        let [px, pz] = site.route.point(s, site.road_half + Self::SETBACK_M);
        let f = Footing::new([px, pz], heading);
        let top = Self::HEIGHT_M + Self::LENS_DEPTH_M + 0.25;
        mesh.upright_box(px, pz, heading, 0.09, 0.09, 0.0, top, POLE_ALBEDO);
        // The arm, from the pole's top over the road (the footing's −w is to the left).
        let y_arm = top - 0.1;
        mesh.beam(
            f.p(0.0, y_arm, 0.0),
            f.p(0.0, y_arm, -Self::REACH_M),
            0.05,
            Self::HOUSING_ALBEDO,
        );
        let [along, across] = Self::LENS_M;
        let head = f.p(
            0.0,
            Self::HEIGHT_M + Self::LENS_DEPTH_M + 0.1,
            -Self::REACH_M,
        );
        mesh.oriented_box(
            head,
            f.axes(),
            [0.5 * along + 0.05, 0.1, 0.5 * across + 0.05],
            Self::HOUSING_ALBEDO,
            ObjectSlot::WORLD,
        );
        let lens = f.p(
            0.0,
            Self::HEIGHT_M + 0.5 * Self::LENS_DEPTH_M,
            -Self::REACH_M,
        );
        let albedo = if lit { Self::MARK } else { Self::LENS_ALBEDO };
        mesh.oriented_box(
            lens,
            f.axes(),
            [0.5 * along, 0.5 * Self::LENS_DEPTH_M, 0.5 * across],
            albedo,
            ObjectSlot::WORLD,
        );
        let base = stand(site.terrain, mesh);
        [
            lens[0],
            Self::HEIGHT_M - Self::SOURCE_BELOW_LENS_M + base,
            lens[2],
        ]
    }

    /// Where each lamp's light comes from (world, metres), in the order of the route: the
    /// same lamps the scene's builder stood in `scene`.
    pub fn sources(scene: &Scene) -> Vec<[f64; 3]> {
        let site = Site::new(scene.description(), scene.route(), scene.terrain());
        Self::stations(&site, site.road_half + 4.0)
            .into_iter()
            .map(|s| Self::build(&site, s, &mut Mesh::default()))
            .collect()
    }
}

/// Lays the street lights of the description's density (none at 0, the default).
pub(super) fn lay(site: &Site<'_>, bins: &mut super::bins::Bins) {
    for s in StreetLights::stations(site, site.road_half + 4.0) {
        let mut item = Mesh::default();
        StreetLights::build(site, s, &mut item);
        let [x, _, z] = site.world(s, site.road_half + StreetLights::SETBACK_M, 0.0);
        bins.at(x, z, Layer::Clutter).append(&item);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under the lamp, I / h²; inside the cone, I cos θ / d² falling as the inverse square;
    /// past the cut-off, the stray share.
    #[test]
    fn the_light_falls_as_the_inverse_square_and_is_cut_off() {
        let up = [0.0, 1.0, 0.0];
        let source = [0.0, 8.0, 0.0];
        let under = StreetLights::illuminance_lux(source, [0.0, 0.0, 0.0], up);
        assert!((under - 2500.0 / 64.0).abs() < 1e-9);
        let (x, h) = (10.0_f64, 8.0_f64);
        let d2 = x * x + h * h;
        let aside = StreetLights::illuminance_lux(source, [x, 0.0, 0.0], up);
        assert!((aside - 2500.0 * (h / d2.sqrt()) / d2).abs() < 1e-9);
        // 8 m up, 40 m away: 79° from the nadir, past the cut-off: the stray share.
        let far = StreetLights::illuminance_lux(source, [40.0, 0.0, 0.0], up);
        let d2 = 40.0_f64 * 40.0 + 64.0;
        assert!((far - 250.0 * (8.0 / d2.sqrt()) / d2).abs() < 1e-12);
        // Nothing upwards.
        assert_eq!(StreetLights::intensity_cd(91.0), 0.0);
        // A surface facing away takes none.
        assert_eq!(
            StreetLights::illuminance_lux(source, [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
            0.0
        );
    }

    /// The shader's street-light constants are this module's.
    #[test]
    fn the_shader_agrees() {
        let shader = include_str!("../camera/scene.wgsl");
        for line in [
            format!(
                "const STREET_MARK_MIN: f32 = {:.1};",
                StreetLights::MARK_MIN
            ),
            format!(
                "const STREET_LENS_ALBEDO: f32 = {:.1};",
                StreetLights::LENS_ALBEDO
            ),
            format!("const STREET_STRAY: f32 = {:.1};", StreetLights::STRAY),
            format!("for (var k = 0u; k < {}u; k++)", StreetLights::LIT_MAX),
        ] {
            assert!(shader.contains(&line), "scene.wgsl lacks `{line}`");
        }
    }
}
