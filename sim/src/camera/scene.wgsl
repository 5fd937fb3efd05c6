// The road scene: one shadow pass (depth from the sun) and one main pass (grey Lambert
// shading with soft shadows), sharing the vertex layout and the per-object transforms.

struct Globals {
    // Camera-relative world (world minus `origin`) to clip space of the chase camera.
    view_proj: mat4x4<f32>,
    // Camera-relative world to the sun's orthographic clip space (fitted to what the
    // camera sees).
    light_view_proj: mat4x4<f32>,
    // xyz: unit vector towards the sun (world); w: sun strength.
    sun: vec4<f32>,
    // x: ambient; y: sensor brightness (gain × exposure); z: normal offset for shadow
    // lookups (metres, ~1.5 shadow texels); w: 1 / shadow map size.
    params: vec4<f32>,
    // Grass: x: 1 / lattice pitch (1/m); y: lowest albedo; z: albedo range; w: hash key
    // (an integer below 2^23).
    ground: vec4<f32>,
    // xyz: the world position of the origin that positions are relative to (the camera's),
    // so that vertices kilometres from the world's origin keep millimetre precision in f32.
    origin: vec4<f32>,
};

struct Objects {
    // Object slot → camera-relative world transform (slot 0, static geometry: a translation
    // by −origin).
    world_from_object: array<mat4x4<f32>, 16>,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> objects: Objects;
@group(1) @binding(0) var shadow_map: texture_depth_2d;
@group(1) @binding(1) var shadow_sampler: sampler_comparison;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: f32,
    @location(3) object: u32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Every face is flat-shaded, so what depends only on the face travels un-interpolated:
    // x: albedo (negative: grass, computed per fragment); y: ambient light; z: direct
    // sunlight before shadowing (both scaled by the sensor's brightness).
    @location(0) @interpolate(flat) light: vec3<f32>,
    // Where the (normal-offset) point falls in the shadow map: x, y in 0..1, depth.
    // The sun's projection is orthographic, so this is affine in the world position and
    // interpolating it across a triangle is exact.
    @location(1) shadow: vec3<f32>,
    // World x and z, for the grass's mottling.
    @location(2) ground: vec2<f32>,
};

@vertex
fn vs_shadow(v: VertexIn) -> @builtin(position) vec4<f32> {
    let world = objects.world_from_object[v.object] * vec4<f32>(v.position, 1.0);
    return globals.light_view_proj * world;
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let m = objects.world_from_object[v.object];
    let world = m * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = globals.view_proj * world;
    // Transforms are rigid, so the normal turns with the upper 3×3.
    let normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    let facing = max(dot(normal, globals.sun.xyz), 0.0);
    let brightness = globals.params.y;
    out.light = vec3<f32>(v.albedo, globals.params.x * brightness, globals.sun.w * facing * brightness);
    let p = globals.light_view_proj * vec4<f32>(world.xyz + normal * globals.params.z, 1.0);
    out.shadow = vec3<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5, p.z);
    out.ground = world.xz + globals.origin.xz;
    return out;
}

// Fraction of sunlight reaching shadow-map point `p` (0 = full shadow): one bilinear
// comparison tap, a 2×2-texel percentage-closer filter, so shadow edges ramp over about a
// texel (~11 cm at 512²).
// More taps cost llvmpipe more than the whole rest of the frame.
fn sunlight(p: vec3<f32>) -> f32 {
    if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) {
        return 1.0;
    }
    return textureSampleCompareLevel(shadow_map, shadow_sampler, p.xy, p.z);
}

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

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    var albedo = in.light.x;
    if (albedo < 0.0) {
        albedo = grass(in.ground);
    }
    var light = in.light.y;
    if (in.light.z > 0.0) {
        light += in.light.z * sunlight(in.shadow);
    }
    let grey = albedo * light;
    return vec4<f32>(grey, grey, grey, 1.0);
}
