// The road scene: one shadow pass (depth from the sun) and one main pass (grey Lambert
// shading with soft shadows), sharing the vertex layout and the per-object transforms.

struct Globals {
    // World to clip space of the chase camera.
    view_proj: mat4x4<f32>,
    // World to the sun's orthographic clip space (fitted to what the camera sees).
    light_view_proj: mat4x4<f32>,
    // xyz: unit vector towards the sun (world); w: sun strength.
    sun: vec4<f32>,
    // x: ambient; y: sensor brightness (gain × exposure); z: normal offset for shadow
    // lookups (metres, ~1.5 shadow texels); w: unused.
    params: vec4<f32>,
};

struct Objects {
    // Object slot → world transform (slot 0 is the identity: static geometry).
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
    @location(1) normal: vec3<f32>,
    @location(2) albedo: f32,
    // Where the (normal-offset) point falls in the shadow map: x, y in 0..1, depth.
    // The sun's projection is orthographic, so this is affine in the world position and
    // interpolating it across a triangle is exact.
    @location(3) shadow: vec3<f32>,
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
    out.normal = (m * vec4<f32>(v.normal, 0.0)).xyz;
    out.albedo = v.albedo;
    let p = globals.light_view_proj * vec4<f32>(world.xyz + out.normal * globals.params.z, 1.0);
    out.shadow = vec3<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5, p.z);
    return out;
}

// Fraction of sunlight reaching `world` (0 = full shadow): one bilinear comparison tap,
// a 2×2-texel percentage-closer filter, so shadow edges ramp over about a texel (~6 cm).
// More taps cost llvmpipe more than the whole rest of the frame.
fn sunlight(p: vec3<f32>) -> f32 {
    if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) {
        return 1.0;
    }
    return textureSampleCompareLevel(shadow_map, shadow_sampler, p.xy, p.z);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if (globals.params.w < -1.5) {
        return vec4<f32>(in.albedo, in.albedo, in.albedo, 1.0);
    }
    let n = normalize(in.normal);
    let facing = dot(n, globals.sun.xyz);
    var direct = 0.0;
    if (facing > 0.0 && globals.params.w < 0.0) {
        direct = globals.sun.w * facing;
    } else if (facing > 0.0) {
        direct = globals.sun.w * facing * sunlight(in.shadow);
    }
    let grey = in.albedo * (globals.params.x + direct) * globals.params.y;
    return vec4<f32>(grey, grey, grey, 1.0);
}
