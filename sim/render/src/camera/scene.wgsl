// The road scene: one shadow pass (depth from the sun) and one main pass (grey Lambert
// shading with soft shadows), sharing the vertex layout and the per-object transforms.
// Ground surfaces may take a procedural texture (`vs_ground`, `fs_ground`), and tree
// canopies are perforated at leaf scale in both passes (`leafy`), so their shadows dapple.

struct Globals {
    // Camera-relative world (world minus `origin`) to clip space of the chase camera.
    view_proj: mat4x4<f32>,
    // Camera-relative world to the sun's orthographic clip space: of the map the shadow
    // pass draws (fitted to what the camera sees, or a static shadow tile's square).
    light_view_proj: mat4x4<f32>,
    // xyz: unit vector towards the sun (world); w: sun strength.
    sun: vec4<f32>,
    // x: ambient; y: sensor brightness (gain × exposure); z: normal offset for shadow
    // lookups (metres, 1.5 texels of the map looked up); w: 1 / shadow map size.
    params: vec4<f32>,
    // Grass: x: 1 / lattice pitch (1/m); y: lowest albedo; z: albedo range; w: hash key
    // (an integer below 2^23).
    ground: vec4<f32>,
    // xyz: the world position of the origin that positions are relative to (the camera's),
    // so that vertices kilometres from the world's origin keep millimetre precision in f32.
    origin: vec4<f32>,
    // Camera-relative world to the board's shadow map's clip space: a fine map around the
    // target board.
    board_view_proj: mat4x4<f32>,
    // x: the board map's depth range (m); y: penumbra width per metre from the occluder
    // (2 tan of the sun's angular radius); z: its texel (m); w: the least depth (clip) of
    // receivers that use it.
    board: vec4<f32>,
    // Ground textures: x, y, z: 1 / tile side (1/m) of the asphalt, grass and gravel
    // layers of `ground_textures`.
    textures: vec4<f32>,
    // Strength of the texture's detail for materials 1–4 (asphalt, grass, gravel, paint):
    // the factor's departure from 1 is scaled by it.
    strength: vec4<f32>,
    // Camera-relative world to where a receiver looks its sunlight up in `shadow_map`:
    // (x, y) × `lookup_scale.xy` + `lookup_scale.zw` are its texture coordinates, z its
    // depth. The slots' texture of the static shadow tiles and the vehicles (its texture
    // coordinates straight, from 0 to 2: the sampler repeats), or the frame's own map (its
    // clip space).
    lookup_view_proj: mat4x4<f32>,
    lookup_scale: vec4<f32>,
    // The texture coordinates (u0, v0, u1, v1) the map answers for; outside, the sun
    // shines.
    lookup_bounds: vec4<f32>,
    // Fog (read only with `fog_on`): x: the extinction β (1/m); y: the fog's luminance
    // times the sensor's brightness; z, w: unused.
    fog: vec4<f32>,
    // The headlamps (read only with `headlamps_on`): [0], [1] each lamp's position
    // relative to the camera (world axes), [0].w the peak intensity times the sensor's
    // brightness (scene units × m²); [2] the chase's forward axis, w 1/σh (per radian);
    // [3] its up axis, w 1/σv; [4] x the aim, y the cut-off (radians), z the stray share,
    // w 1 / the cut-off's width (per radian).
    lamps: array<vec4<f32>, 5>,
    // Rain on the road (read only with `rain_on`): x: the factor on the road's albedo;
    // y: the share of the road a water film covers; z: the sky's grey (times the sensor's
    // brightness) the film mirrors; w: water's reflectance at normal incidence.
    rain: vec4<f32>,
    // The tail lamps (read only with `tail_lamps_on`): slot s's lens radiance times the
    // sensor's brightness over the lens's albedo, at [s / 4][s % 4] (0: no lamp lit).
    glow: array<vec4<f32>, 8>,
    // The street lights (read only with `street_lights_on`): [0]-[7] the lamps lit in the
    // frame, each its source relative to the camera and w 1 (0: none); [8] x the cone's
    // half-angle from the nadir (radians), y 1 / the cut-off's width (per radian), z a
    // lens's glow over its albedo, w the intensity inside the cone, both times the sensor's
    // brightness (scene units, × m² for the intensity).
    street: array<vec4<f32>, 9>,
    // Rain's spray (read only with `spray_on`): [0] x the plumes drawn, y the airlight
    // times the sensor's brightness, z the share of the lamps' light a droplet scatters
    // towards the camera, w the puffs' wavenumber (radians per metre); [1] the plume's
    // height scale at its source, its rise (m per m), its greatest height scale (m), its
    // spread (m per m); then three for each plume, [2 + 3p]: the middle of its vehicle's
    // back on the ground relative to the camera, w σ0 (m); [3 + 3p] the unit vector
    // backwards along the road, w the settling length (m); [4 + 3p] x the vehicle's
    // half-width (m), y the puffs' phase (radians), z the plume's length (m), w the puffs'
    // depth.
    spray: array<vec4<f32>, 53>,
    // The tail lamps the wet road mirrors (read only with `mirror_on`): [0] x how many, y
    // the film's roughness (the rms slope); then two for each, [1 + 2k] its lens's centre
    // relative to the camera, w its intensity times the sensor's brightness (scene units
    // × m²); [2 + 2k] the unit vector its vehicle's back faces.
    mirror: array<vec4<f32>, 69>,
};

struct Objects {
    // Object slot → camera-relative world transform (slot 0, static geometry: a translation
    // by −origin).
    world_from_object: array<mat4x4<f32>, 32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> objects: Objects;
// The sun's depth where receivers look it up: the slots' texture of the static shadow
// tiles and the vehicles, or the frame's own map.
@group(1) @binding(0) var shadow_map: texture_depth_2d;
@group(1) @binding(1) var shadow_sampler: sampler_comparison;
@group(1) @binding(2) var board_map: texture_depth_2d;
// Detail factors (half of them: 0–1 holds 0–2, mean 1), one layer per texture, mipmapped.
@group(1) @binding(3) var ground_textures: texture_2d_array<f32>;
@group(1) @binding(4) var ground_sampler: sampler;
// The board's fine map's sampler (it clamps).
@group(1) @binding(5) var board_sampler: sampler_comparison;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: f32,
    // Bits 0–7: the object slot; the bits above, the ground material (0: none).
    @location(3) object: u32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Every face is flat-shaded, so what depends only on the face travels un-interpolated:
    // x: albedo (negative: grass, computed per fragment); y: ambient light; z: direct
    // sunlight before shadowing (both scaled by the sensor's brightness).
    @location(0) @interpolate(flat) light: vec3<f32>,
    // Where the (normal-offset) point falls in `shadow_map`: texture coordinates, depth.
    // The sun's projection is orthographic, so this is affine in the world position and
    // interpolating it across a triangle is exact.
    @location(1) shadow: vec3<f32>,
    // World x and z, for the grass's mottling.
    @location(2) ground: vec2<f32>,
    // Where the (normal-offset) point falls in the board's shadow map.
    @location(3) board: vec3<f32>,
    // The point relative to the camera (world axes), for the fog.
    @location(5) eye: vec3<f32>,
};

// A ground surface's vertex: `VertexOut`'s fields, and its texture.
struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) light: vec3<f32>,
    @location(1) shadow: vec3<f32>,
    @location(2) ground: vec2<f32>,
    @location(3) board: vec3<f32>,
    // x: the texture's layer; y: its strength; z: 1 / its tile's side (1/m).
    @location(4) @interpolate(flat) texture: vec3<f32>,
    @location(5) eye: vec3<f32>,
};

// A canopy's vertex: `VertexOut`'s fields, and the world height (with `ground`, the
// world position the leaf pattern is hashed from).
struct FoliageOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) light: vec3<f32>,
    @location(1) shadow: vec3<f32>,
    @location(2) ground: vec2<f32>,
    @location(3) board: vec3<f32>,
    @location(4) height: f32,
    @location(5) eye: vec3<f32>,
};

// A canopy's vertex in the shadow passes: its world position, for the leaf pattern.
struct FoliageShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_shadow(v: VertexIn) -> @builtin(position) vec4<f32> {
    let world = objects.world_from_object[v.object & 0xffu] * vec4<f32>(v.position, 1.0);
    return globals.light_view_proj * world;
}

// A triangle over the whole map at the far plane: with depth always written, it sets the
// texels it is scissored to back to the cleared depth.
@vertex
fn vs_far(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    return vec4<f32>(p, 1.0, 1.0);
}

// With `vs_far` in the main pass, under the scissor: sets the depth there back to the
// cleared depth, and leaves the colour as it is (the pipeline writes no channel).
@fragment
fn fs_far() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}

@vertex
fn vs_board_shadow(v: VertexIn) -> @builtin(position) vec4<f32> {
    let world = objects.world_from_object[v.object & 0xffu] * vec4<f32>(v.position, 1.0);
    return globals.board_view_proj * world;
}

// A canopy's vertex seen from the sun through `light_from_world` (a shadow map's
// camera-relative world to clip space).
fn foliage_shadow_of(v: VertexIn, light_from_world: mat4x4<f32>) -> FoliageShadowOut {
    let world = objects.world_from_object[v.object & 0xffu] * vec4<f32>(v.position, 1.0);
    var out: FoliageShadowOut;
    out.clip = light_from_world * world;
    out.world = world.xyz + globals.origin.xyz;
    return out;
}

@vertex
fn vs_foliage_shadow(v: VertexIn) -> FoliageShadowOut {
    return foliage_shadow_of(v, globals.light_view_proj);
}

@vertex
fn vs_foliage_board_shadow(v: VertexIn) -> FoliageShadowOut {
    return foliage_shadow_of(v, globals.board_view_proj);
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return vs_main_of(v);
}

// Whether a scene has tail lamps (the pipeline's constant): without them, `vs_main_of`
// shades every vertex as before tail lamps existed, bit for bit.
override tail_lamps_on: bool = false;
// The albedo from which a vertex is a tail lamp's (`TailLamps::MARK_MIN`), and the lens's
// own albedo (`TailLamps::LENS_ALBEDO`).
const LAMP_MARK_MIN: f32 = 4.0;
const LAMP_LENS_ALBEDO: f32 = 0.1;
// Whether street lights light the scene (the pipeline's constant, at night with street
// lights): without them, `vs_main_of` and `lamp_lit` are as before street lights existed.
override street_lights_on: bool = false;
// The albedo from which a vertex is a lit street lamp's lens (`StreetLights::MARK_MIN`),
// and the lens's own albedo (`StreetLights::LENS_ALBEDO`).
const STREET_MARK_MIN: f32 = 16.0;
const STREET_LENS_ALBEDO: f32 = 0.5;
// The share of a street lamp's intensity left past its cut-off (`StreetLights::STRAY`).
const STREET_STRAY: f32 = 0.1;

// The share of a street lamp's intensity sent at `from_nadir` radians from straight down:
// all inside the cone, the stray share past the cut-off (a smoothstep over its width),
// none above the horizontal.
fn street_cone(from_nadir: f32) -> f32 {
    if (from_nadir > 1.5707964) {
        return 0.0;
    }
    return mix(1.0, STREET_STRAY, smoothstep(0.0, 1.0, (from_nadir - globals.street[8].x) * globals.street[8].y));
}

// What `vs_main` computes, for the vertex stages that add to it.
fn vs_main_of(v: VertexIn) -> VertexOut {
    let m = objects.world_from_object[v.object & 0xffu];
    let world = m * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = globals.view_proj * world;
    // Transforms are rigid, so the normal turns with the upper 3×3.
    let normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    let facing = max(dot(normal, globals.sun.xyz), 0.0);
    let brightness = globals.params.y;
    out.light = vec3<f32>(v.albedo, globals.params.x * brightness, globals.sun.w * facing * brightness);
    if (street_lights_on && v.albedo >= STREET_MARK_MIN) {
        // A street lamp's lens: lit as any surface, and glowing to a camera inside its cone
        // (the camera is at the origin: the direction from the lens to it is −world).
        out.light.x = STREET_LENS_ALBEDO;
        let to_eye = normalize(-world.xyz);
        out.light.y += globals.street[8].z * street_cone(acos(clamp(-to_eye.y, -1.0, 1.0)));
    } else if (tail_lamps_on && v.albedo >= LAMP_MARK_MIN) {
        // A lamp's lens: its albedo times the light that falls on it, plus its own glow
        // (added to the light, over the albedo that multiplies it).
        let slot = v.object & 0xffu;
        out.light.x = LAMP_LENS_ALBEDO;
        out.light.y += globals.glow[slot / 4u][slot % 4u];
    }
    let p = globals.lookup_view_proj * vec4<f32>(world.xyz + normal * globals.params.z, 1.0);
    let s = globals.lookup_scale;
    out.shadow = vec3<f32>(p.x * s.x + s.z, p.y * s.y + s.w, p.z);
    out.ground = world.xz + globals.origin.xz;
    let b = globals.board_view_proj * vec4<f32>(world.xyz + normal * (1.5 * globals.board.z), 1.0);
    out.board = vec3<f32>(b.x * 0.5 + 0.5, 0.5 - b.y * 0.5, b.z);
    out.eye = world.xyz;
    return out;
}

@vertex
fn vs_ground(v: VertexIn) -> GroundOut {
    let o = vs_main_of(v);
    var out: GroundOut;
    out.clip = o.clip;
    out.light = o.light;
    out.shadow = o.shadow;
    out.ground = o.ground;
    out.board = o.board;
    out.eye = o.eye;
    // Material → layer and strength: asphalt, grass, gravel, and paint (asphalt, faint).
    var layer = 0u;
    var strength = 0.0;
    switch (v.object >> 8u) {
        case 1u: { layer = 0u; strength = globals.strength.x; }
        case 2u: { layer = 1u; strength = globals.strength.y; }
        case 3u: { layer = 2u; strength = globals.strength.z; }
        case 4u: { layer = 0u; strength = globals.strength.w; }
        default: {}
    }
    out.texture = vec3<f32>(f32(layer), strength, globals.textures[layer]);
    return out;
}

@vertex
fn vs_foliage(v: VertexIn) -> FoliageOut {
    let o = vs_main_of(v);
    var out: FoliageOut;
    out.clip = o.clip;
    out.light = o.light;
    out.shadow = o.shadow;
    out.ground = o.ground;
    out.board = o.board;
    out.eye = o.eye;
    let world = objects.world_from_object[v.object & 0xffu] * vec4<f32>(v.position, 1.0);
    out.height = world.y + globals.origin.y;
    return out;
}

// Fraction of sunlight reaching point `p` of `shadow_map` (0 = full shadow): one bilinear
// comparison tap, a 2×2-texel percentage-closer filter, so shadow edges ramp over about a
// texel (10 cm in the static tiles' slots, ~11 cm in a frame's own 512² map).
// More taps cost llvmpipe more than the whole rest of the frame.
fn sunlight(p: vec3<f32>) -> f32 {
    let b = globals.lookup_bounds;
    if (p.x < b.x || p.x > b.z || p.y < b.y || p.y > b.w || p.z > 1.0) {
        return 1.0;
    }
    return textureSampleCompareLevel(shadow_map, shadow_sampler, p.xy, p.z);
}

// Fraction of sunlight at point `p` of the board's fine shadow map, with the sun's disc
// (percentage-closer soft shadows, the occluder's distance found by comparisons alone: the
// GL backend cannot read a depth texture's values). For each of five distances towards
// the sun, 0.1 m to 25.6 m in steps of 4, five comparison taps spread over the penumbra
// an occluder that far would cast ask whether one lies at least that far; the farthest
// that does sets the penumbra, as wide as the sun's disc (0.53°) seen across twice that
// distance (the geometric middle of the step), and nine bilinear taps spread over that
// width average it.
fn sunlight_board(p: vec3<f32>) -> f32 {
    let dims = vec2<f32>(textureDimensions(board_map));
    let texel = 1.0 / dims;
    let depth_m = globals.board.x;
    let per_m = globals.board.y;
    let texel_m = globals.board.z;
    var far = 0.0;
    var step = 0.1;
    for (var k = 0; k < 5; k = k + 1) {
        let z = p.z - step / depth_m;
        let reach = max(0.5 * step * per_m / texel_m, 1.0) * texel;
        var blocked = 0.0;
        blocked = blocked + (1.0 - textureSampleCompareLevel(board_map, board_sampler, p.xy, z));
        blocked = blocked + (1.0 - textureSampleCompareLevel(board_map, board_sampler, p.xy + vec2<f32>(reach.x, reach.y), z));
        blocked = blocked + (1.0 - textureSampleCompareLevel(board_map, board_sampler, p.xy + vec2<f32>(-reach.x, reach.y), z));
        blocked = blocked + (1.0 - textureSampleCompareLevel(board_map, board_sampler, p.xy + vec2<f32>(reach.x, -reach.y), z));
        blocked = blocked + (1.0 - textureSampleCompareLevel(board_map, board_sampler, p.xy - vec2<f32>(reach.x, reach.y), z));
        if (blocked > 0.0) {
            far = step;
        }
        step = step * 4.0;
    }
    if (far == 0.0) {
        return textureSampleCompareLevel(board_map, board_sampler, p.xy, p.z);
    }
    let width = max(2.0 * far * per_m / texel_m, 1.0);
    var lit = 0.0;
    for (var j = 0; j < 3; j = j + 1) {
        for (var i = 0; i < 3; i = i + 1) {
            let o = (vec2<f32>(f32(i), f32(j)) - 1.0) * (width / 3.0) * texel;
            lit = lit + textureSampleCompareLevel(board_map, board_sampler, p.xy + o, p.z);
        }
    }
    return lit / 9.0;
}

// Whether the pipeline draws grass faces (albedo below 0): only the ground layer has
// them, and the other pipelines set it false, so that their fragments skip the grass's
// lattice hashes (llvmpipe runs both sides of a branch, masked).
override grass_faces: bool = true;

// MurmurHash3's finaliser: a well-mixed 32-bit value for each grass lattice corner.
fn hash(i: vec2<i32>) -> f32 {
    var x = (bitcast<u32>(i.x) * 0x8da6b343u) ^ (bitcast<u32>(i.y) * 0xd8163841u) ^ u32(globals.ground.w);
    x = x ^ (x >> 16u);
    x = x * 0x85ebca6bu;
    x = x ^ (x >> 13u);
    x = x * 0xc2b2ae35u;
    x = x ^ (x >> 16u);
    return f32(x >> 8u) / 16777216.0;
}

// Grass albedo at world (x, z): a random albedo at each lattice corner, bilinearly
// interpolated, so the shoulders are mottled at the lattice's pitch.
fn grass(xz: vec2<f32>) -> f32 {
    let cell = xz * globals.ground.x;
    let i = vec2<i32>(floor(cell));
    let f = cell - floor(cell);
    let a = mix(hash(i), hash(i + vec2<i32>(1, 0)), f.x);
    let b = mix(hash(i + vec2<i32>(0, 1)), hash(i + vec2<i32>(1, 1)), f.x);
    return globals.ground.y + globals.ground.z * mix(a, b, f.y);
}

// Whether the scene lies in fog (the pipeline's constant): without it, `fogged` passes
// the grey through untouched, so a scene without fog is drawn as before fog existed, bit
// for bit, and pays nothing for it.
override fog_on: bool = false;

// The colour of a surface of radiance `grey` (times the sensor's brightness) at `eye`
// from the camera, seen through the fog (Koschmieder): it keeps exp(−β d) of its own
// radiance and takes the rest from the fog's luminance, `fog + (grey − fog) · exp(−β d)`.
fn fogged(grey: f32, eye: vec3<f32>) -> vec4<f32> {
    var g = grey;
    if (spray_on) {
        g = sprayed(g, eye);
    }
    if (fog_on) {
        let t = exp(-globals.fog.x * length(eye));
        g = globals.fog.y + (g - globals.fog.y) * t;
    }
    return vec4<f32>(g, g, g, 1.0);
}

// Whether the chase's headlamps are on (the pipeline's constant): without them, `lamp_lit`
// is the sun's and the sky's light alone, as before headlamps existed, bit for bit.
override headlamps_on: bool = false;

// One headlamp at `lamp` (relative to the camera) lighting a surface at `eye` with unit
// normal `n`: I(h, v) cos(incidence) / d², I a Gaussian hot spot about the lamp's aim,
// cut off above (a low beam) to a stray share over a smoothstep.
fn headlamp(lamp: vec3<f32>, eye: vec3<f32>, n: vec3<f32>) -> f32 {
    let v = eye - lamp;
    let d2 = max(dot(v, v), 1e-4);
    let dir = v * inverseSqrt(d2);
    let ahead = dot(dir, globals.lamps[2].xyz);
    if (ahead <= 0.0) {
        return 0.0;
    }
    let side = dot(dir, cross(globals.lamps[3].xyz, globals.lamps[2].xyz));
    let h = atan2(side, ahead);
    let e = asin(clamp(dot(dir, globals.lamps[3].xyz), -1.0, 1.0));
    let dh = h * globals.lamps[2].w;
    let dv = (e - globals.lamps[4].x) * globals.lamps[3].w;
    let cut = smoothstep(0.0, 1.0, (e - globals.lamps[4].y) * globals.lamps[4].w);
    let i = globals.lamps[0].w * exp(-0.5 * (dh * dh + dv * dv)) * mix(1.0, globals.lamps[4].z, cut);
    return i * max(dot(n, -dir), 0.0) / d2;
}

// One street lamp at `lamp` (relative to the camera) lighting a surface at `eye` with unit
// normal `n`: I(θ) cos(incidence) / d², I constant inside the cone about the downward
// vertical and cut off outside it.
fn street_light(lamp: vec3<f32>, eye: vec3<f32>, n: vec3<f32>) -> f32 {
    let v = eye - lamp;
    let d2 = max(dot(v, v), 1e-4);
    let dir = v * inverseSqrt(d2);
    let i = globals.street[8].w * street_cone(acos(clamp(-dir.y, -1.0, 1.0)));
    return i * max(dot(n, -dir), 0.0) / d2;
}

// The light of the street lamps lit in the frame on a surface at `eye` with normal `n`.
fn street_lights(eye: vec3<f32>, n: vec3<f32>) -> f32 {
    var sum = 0.0;
    for (var k = 0u; k < 8u; k++) {
        let lamp = globals.street[k];
        if (lamp.w > 0.0) {
            sum += street_light(lamp.xyz, eye, n);
        }
    }
    return sum;
}

// `albedo` times the scene's `light`, with the headlamps' and the street lights' light
// added when they are on. The surface's normal is the flat one of its triangle, from the
// position's derivatives, turned towards the camera.
fn lamp_lit(albedo: f32, light: f32, eye: vec3<f32>) -> f32 {
    if (headlamps_on || street_lights_on) {
        var n = normalize(cross(dpdx(eye), dpdy(eye)));
        if (dot(n, eye) > 0.0) {
            n = -n;
        }
        var lamps = 0.0;
        if (headlamps_on) {
            lamps = headlamp(globals.lamps[0].xyz, eye, n) + headlamp(globals.lamps[1].xyz, eye, n);
        }
        if (street_lights_on) {
            lamps += street_lights(eye, n);
        }
        return albedo * (light + lamps);
    }
    return albedo * light;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    var albedo = in.light.x;
    if (grass_faces && albedo < 0.0) {
        albedo = grass(in.ground);
    }
    var light = in.light.y;
    if (in.light.z > 0.0) {
        light += in.light.z * sunlight(in.shadow);
    }
    return fogged(lamp_lit(albedo, light, in.eye), in.eye);
}

// As `fs_main`, with soft shadows on the target: receivers within the board's fine map
// take their sunlight from it (`sunlight_board`).
@fragment
fn fs_main_soft(in: VertexOut) -> @location(0) vec4<f32> {
    var albedo = in.light.x;
    if (grass_faces && albedo < 0.0) {
        albedo = grass(in.ground);
    }
    var light = in.light.y;
    if (in.light.z > 0.0) {
        let b = in.board;
        var sun = 0.0;
        if (b.x >= 0.0 && b.x <= 1.0 && b.y >= 0.0 && b.y <= 1.0 && b.z >= globals.board.w && b.z <= 1.0) {
            sun = sunlight_board(b);
        } else {
            sun = sunlight(in.shadow);
        }
        light += in.light.z * sun;
    }
    return fogged(lamp_lit(albedo, light, in.eye), in.eye);
}

// The detail factor of a ground surface at world (x, z): one trilinear sample of its
// texture's layer (`texture`: layer, strength, 1 / tile side), its departure from 1
// scaled by the material's strength.
fn detail(ground: vec2<f32>, texture: vec3<f32>) -> f32 {
    let t = textureSample(ground_textures, ground_sampler, ground * texture.z, i32(texture.x)).r;
    return 1.0 + texture.y * (2.0 * t - 1.0);
}

// Light reaching a surface of face light `light` (see `VertexOut`) at shadow-map point
// `shadow`: ambient, and sunlight as the main map lets it through.
fn lit(light: vec3<f32>, shadow: vec3<f32>) -> f32 {
    var l = light.y;
    if (light.z > 0.0) {
        l += light.z * sunlight(shadow);
    }
    return l;
}

// As `lit`, with soft shadows on the target (see `fs_main_soft`).
fn lit_soft(light: vec3<f32>, shadow: vec3<f32>, b: vec3<f32>) -> f32 {
    var l = light.y;
    if (light.z > 0.0) {
        var sun = 0.0;
        if (b.x >= 0.0 && b.x <= 1.0 && b.y >= 0.0 && b.y <= 1.0 && b.z >= globals.board.w && b.z <= 1.0) {
            sun = sunlight_board(b);
        } else {
            sun = sunlight(shadow);
        }
        l += light.z * sun;
    }
    return l;
}

// A ground surface's albedo: the face's (the grass's mottle where it is negative) times
// its texture's detail.
fn ground_albedo(in: GroundOut) -> f32 {
    let d = detail(in.ground, in.texture);
    var albedo = in.light.x;
    if (grass_faces && albedo < 0.0) {
        albedo = grass(in.ground);
    }
    return albedo * d;
}

// Whether rain falls on the scene (the pipeline's constant): without it, `wet` passes the
// grey through untouched, so a dry scene is drawn as before rain existed, bit for bit.
override rain_on: bool = false;

// A ground surface's grey `grey` (its albedo times its light) in rain: the road's asphalt
// and paint (texture layer 0) darkened by the wet albedo's factor, plus the sky mirrored in
// the share of it a water film covers, by water's Fresnel reflectance at the angle the
// camera sees it (Schlick: F0 + (1 − F0)(1 − cos θ)⁵, the road's normal straight up).
fn wet(grey: f32, in: GroundOut) -> f32 {
    if (rain_on && in.texture.x < 0.5) {
        let c = 1.0 - abs(in.eye.y) / max(length(in.eye), 1e-6);
        let c2 = c * c;
        let fresnel = globals.rain.w + (1.0 - globals.rain.w) * c2 * c2 * c;
        var mirrored = globals.rain.y * fresnel * globals.rain.z;
        if (mirror_on) {
            mirrored += globals.rain.y * mirrored_lamps(in.eye);
        }
        return grey * globals.rain.x + mirrored;
    }
    return grey;
}

// Whether the wet road mirrors the lit lamps (the pipeline's constant): without it, `wet`
// mirrors the sky alone, as before mirrored lamps existed, bit for bit.
override mirror_on: bool = false;

// The grey a rough water film (normal straight up) mirrors towards the camera, in unit
// direction `v` from it, from a lamp in unit direction `l` whose light on a plane facing
// it is `e`: a Beckmann microfacet mirror of rms slope m, radiance `F D e / (4 cos θo)`
// (D = exp(−tan²θh / m²) / (π m² cos⁴θh) about the half vector h, F Schlick's Fresnel at
// it), times π (a grey is π times a radiance: a white matte surface under `e` is `e`).
// At grazing angles the lobe spans metres of road along the line towards the camera: the
// lamp's streak.
fn glint(v: vec3<f32>, l: vec3<f32>, e: f32) -> f32 {
    if (l.y <= 0.0 || v.y <= 0.0) {
        return 0.0;
    }
    let h = normalize(l + v);
    let m = globals.mirror[0].y;
    let m2 = m * m;
    let c2 = max(h.y * h.y, 1e-6);
    let tan2 = (1.0 - c2) / c2;
    let d = exp(-tan2 / m2) / (m2 * c2 * c2);
    let x = 1.0 - clamp(dot(h, v), 0.0, 1.0);
    let x2 = x * x;
    let fresnel = globals.rain.w + (1.0 - globals.rain.w) * x2 * x2 * x;
    return fresnel * d * e / (4.0 * v.y);
}

// The lit lamps mirrored by the film at `eye` (on the road): the chase's headlamps (their
// mirror image lies ahead, away from the camera, so they add almost nothing), the street
// lights lit in the frame and the tail lamps of `Globals::mirror`, each by its light on a
// plane facing it there. What stands between a lamp and the road is not looked for.
fn mirrored_lamps(eye: vec3<f32>) -> f32 {
    let v = -normalize(eye);
    var sum = 0.0;
    if (headlamps_on) {
        for (var k = 0u; k < 2u; k++) {
            let l = normalize(globals.lamps[k].xyz - eye);
            sum += glint(v, l, headlamp(globals.lamps[k].xyz, eye, l));
        }
    }
    if (street_lights_on) {
        for (var k = 0u; k < 8u; k++) {
            let lamp = globals.street[k];
            if (lamp.w > 0.0) {
                let l = normalize(lamp.xyz - eye);
                sum += glint(v, l, street_light(lamp.xyz, eye, l));
            }
        }
    }
    let n = u32(globals.mirror[0].x);
    for (var k = 0u; k < n; k++) {
        let lamp = globals.mirror[1u + 2u * k];
        let to = lamp.xyz - eye;
        let d2 = max(dot(to, to), 1e-4);
        let l = to * inverseSqrt(d2);
        // A tail lamp shines behind its vehicle.
        if (dot(-l, globals.mirror[2u + 2u * k].xyz) > 0.0) {
            sum += glint(v, l, lamp.w / d2);
        }
    }
    return sum;
}

// Whether the vehicles throw spray (the pipeline's constant): without it, `fogged` passes
// the grey through it untouched, as before spray existed, bit for bit.
override spray_on: bool = false;

// Steps of the march through one plume.
const SPRAY_STEPS: u32 = 16u;

// The part of `range` (of t) where `lo <= a + t d <= hi` (empty: x > y).
fn slab(range: vec2<f32>, a: f32, d: f32, lo: f32, hi: f32) -> vec2<f32> {
    if (abs(d) < 1e-6) {
        if (a < lo || a > hi) {
            return vec2<f32>(1.0, 0.0);
        }
        return range;
    }
    let t0 = (lo - a) / d;
    let t1 = (hi - a) / d;
    return vec2<f32>(max(range.x, min(t0, t1)), min(range.y, max(t0, t1)));
}

// The light the droplets at `p` (relative to the camera) scatter towards the camera: the
// airlight, and a share of the headlamps' and street lights' light falling on them.
fn spray_light(p: vec3<f32>) -> f32 {
    var lamps = 0.0;
    if (headlamps_on) {
        for (var k = 0u; k < 2u; k++) {
            lamps += headlamp(globals.lamps[k].xyz, p, normalize(globals.lamps[k].xyz - p));
        }
    }
    if (street_lights_on) {
        for (var k = 0u; k < 8u; k++) {
            let lamp = globals.street[k];
            if (lamp.w > 0.0) {
                lamps += street_light(lamp.xyz, p, normalize(lamp.xyz - p));
            }
        }
    }
    return globals.spray[0].y + globals.spray[0].z * lamps;
}

// A surface of grey `grey` at `eye` seen through the plumes in front of it (only the part
// of each plume nearer than the surface counts: the spray is depth-tested): it keeps
// exp(−τ) of its grey, τ the plumes' extinction integrated along the ray (a midpoint sum
// of `SPRAY_STEPS` over each plume's part of it), and gains the light the droplets
// scatter, each plume's lit as at the middle of its part of the ray. The plume's
// extinction `s` metres behind its vehicle, `y` from its centre line and `z` up:
// σ0 e^(−s/L) / (√π W H) · e^(−(y/W)²) · e^(−z/H) · (1 + depth · sin(k s + φ)), W and H
// growing with s (`Spray` in the render crate).
fn sprayed(grey: f32, eye: vec3<f32>) -> f32 {
    let dist = length(eye);
    let dir = eye / max(dist, 1e-6);
    let shape = globals.spray[1];
    var tau = 0.0;
    var added = 0.0;
    let n = u32(globals.spray[0].x);
    for (var p = 0u; p < n; p++) {
        let a = globals.spray[2u + 3u * p];
        let b = globals.spray[3u + 3u * p];
        let c = globals.spray[4u + 3u * p];
        let side = vec3<f32>(-b.z, 0.0, b.x);
        let s0 = -dot(a.xyz, b.xyz);
        let ds = dot(dir, b.xyz);
        let y0 = -dot(a.xyz, side);
        let dy = dot(dir, side);
        let z0 = -a.y;
        let dz = dir.y;
        let wide = 3.0 * (c.x + shape.w * c.z);
        var t = vec2<f32>(0.0, dist);
        t = slab(t, s0, ds, 0.0, c.z);
        t = slab(t, y0, dy, -wide, wide);
        t = slab(t, z0, dz, 0.0, 4.0 * shape.z);
        if (t.y <= t.x) {
            continue;
        }
        let dt = (t.y - t.x) / f32(SPRAY_STEPS);
        var depth = 0.0;
        for (var k = 0u; k < SPRAY_STEPS; k++) {
            let tk = t.x + (f32(k) + 0.5) * dt;
            let s = s0 + tk * ds;
            let y = y0 + tk * dy;
            let z = max(z0 + tk * dz, 0.0);
            let w = c.x + shape.w * s;
            let h = min(shape.x + shape.y * s, shape.z);
            let puff = 1.0 + c.w * sin(globals.spray[0].w * s + c.y);
            depth += a.w * exp(-s / b.w) / (1.7724539 * w * h) * exp(-(y * y) / (w * w)) * exp(-z / h) * puff * dt;
        }
        let light = spray_light(dir * (0.5 * (t.x + t.y)));
        added += light * exp(-tau) * (1.0 - exp(-depth));
        tau += depth;
    }
    return grey * exp(-tau) + added;
}

// Textured ground: `fs_main` with the albedo modulated by the surface's texture.
@fragment
fn fs_ground(in: GroundOut) -> @location(0) vec4<f32> {
    return fogged(wet(lamp_lit(ground_albedo(in), lit(in.light, in.shadow), in.eye), in), in.eye);
}

// `fs_ground` with soft shadows on the target.
@fragment
fn fs_ground_soft(in: GroundOut) -> @location(0) vec4<f32> {
    return fogged(wet(lamp_lit(ground_albedo(in), lit_soft(in.light, in.shadow, in.board), in.eye), in), in.eye);
}

// Leaf pattern: two trilinear value noises over the canopy's surface, on lattices of
// pitch `CLUSTER_PITCH_M` and `LEAF_PITCH_M`; where the first is below `CLUSTER_HOLE` a
// gap between leaf clusters (15–40 cm, wide enough to show in the sun's 11–20 cm shadow
// texels), where the second is below `LEAF_HOLE` a gap between leaves (5–15 cm).
const CLUSTER_PITCH_M: f32 = 0.3;
const CLUSTER_HOLE: f32 = 0.4;
const LEAF_PITCH_M: f32 = 0.08;
const LEAF_HOLE: f32 = 0.35;

// MurmurHash3's finaliser of a 3-D lattice corner.
fn hash3(i: vec3<i32>) -> f32 {
    var x = (bitcast<u32>(i.x) * 0x8da6b343u) ^ (bitcast<u32>(i.y) * 0xd8163841u) ^ (bitcast<u32>(i.z) * 0xcb1ab31fu) ^ u32(globals.ground.w);
    x = x ^ (x >> 16u);
    x = x * 0x85ebca6bu;
    x = x ^ (x >> 13u);
    x = x * 0xc2b2ae35u;
    x = x ^ (x >> 16u);
    return f32(x >> 8u) / 16777216.0;
}

// Value noise at `c` (lattice units): the hashed corners, trilinearly interpolated.
fn noise3(c: vec3<f32>) -> f32 {
    let i = vec3<i32>(floor(c));
    let f = c - floor(c);
    let x00 = mix(hash3(i), hash3(i + vec3<i32>(1, 0, 0)), f.x);
    let x10 = mix(hash3(i + vec3<i32>(0, 1, 0)), hash3(i + vec3<i32>(1, 1, 0)), f.x);
    let x01 = mix(hash3(i + vec3<i32>(0, 0, 1)), hash3(i + vec3<i32>(1, 0, 1)), f.x);
    let x11 = mix(hash3(i + vec3<i32>(0, 1, 1)), hash3(i + vec3<i32>(1, 1, 1)), f.x);
    return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
}

// Whether a canopy's surface at world point `p` holds leaves (else it is a hole). The
// same in the main pass and the shadow passes, so the sun shines through the holes the
// camera sees.
fn leafy(p: vec3<f32>) -> bool {
    return noise3(p / CLUSTER_PITCH_M) >= CLUSTER_HOLE && noise3(p / LEAF_PITCH_M + 17.0) >= LEAF_HOLE;
}

// A canopy's albedo from the camera, its holes discarded.
fn leaf_albedo(in: FoliageOut) -> f32 {
    if (!leafy(vec3<f32>(in.ground.x, in.height, in.ground.y))) {
        discard;
    }
    return in.light.x;
}

// A canopy from the camera: holes discarded, leaves shaded as `fs_main`.
@fragment
fn fs_foliage(in: FoliageOut) -> @location(0) vec4<f32> {
    return fogged(lamp_lit(leaf_albedo(in), lit(in.light, in.shadow), in.eye), in.eye);
}

// `fs_foliage` with soft shadows on the target.
@fragment
fn fs_foliage_soft(in: FoliageOut) -> @location(0) vec4<f32> {
    return fogged(lamp_lit(leaf_albedo(in), lit_soft(in.light, in.shadow, in.board), in.eye), in.eye);
}

// A canopy from the sun: the holes let the light through. The only fragment stage of
// the shadow passes.
@fragment
fn fs_foliage_shadow(in: FoliageShadowOut) {
    if (!leafy(in.world)) {
        discard;
    }
}
