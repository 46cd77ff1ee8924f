// The preview's shaders: the shaded mesh with its wireframe coloured by refinement level (and
// skirts and stitches coloured by role on demand), the flat triangle-id pass, and coloured lines
// (the view frustum, degenerate triangles' edges). See renderer.rs.

struct Uniforms {
    view_projection: mat4x4<f32>,
    // xyz: unit direction towards the sun.
    sun: vec4<f32>,
    // x: wireframe on (1) or off (0); y: tint the triangles outside the view volume;
    // z: the deepest level in the mesh (the end of the colour scale); w: colour by role.
    options: vec4<f32>,
};

@group(0) @binding(0) var<uniform> uniforms: Uniforms;

struct MeshVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) barycentric: vec3<f32>,
    @location(2) @interpolate(flat) level: f32,
    @location(3) @interpolate(flat) in_view: f32,
    @location(4) @interpolate(flat) triangle: u32,
    @location(5) @interpolate(flat) role: f32,
};

@vertex
fn mesh_vertex(
    @builtin(vertex_index) vertex_index: u32,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) barycentric: vec3<f32>,
    @location(3) level: f32,
    @location(4) in_view: f32,
    @location(5) role: f32,
) -> MeshVarying {
    var out: MeshVarying;
    out.clip = uniforms.view_projection * vec4<f32>(position, 1.0);
    out.normal = normal;
    out.barycentric = barycentric;
    out.level = level;
    out.in_view = in_view;
    out.role = role;
    // The list is not indexed: vertices 3k, 3k+1, 3k+2 are triangle k.
    out.triangle = vertex_index / 3u;
    return out;
}

// Blue (coarse) through green and yellow to red (the finest level in the mesh).
fn level_colour(t: f32) -> vec3<f32> {
    let s = clamp(t, 0.0, 1.0) * 3.0;
    let blue = vec3<f32>(0.15, 0.35, 1.0);
    let green = vec3<f32>(0.1, 0.8, 0.3);
    let yellow = vec3<f32>(1.0, 0.85, 0.1);
    let red = vec3<f32>(0.95, 0.1, 0.1);
    if s < 1.0 {
        return mix(blue, green, s);
    } else if s < 2.0 {
        return mix(green, yellow, s - 1.0);
    }
    return mix(yellow, red, s - 2.0);
}

@fragment
fn shaded_fragment(in: MeshVarying) -> @location(0) vec4<f32> {
    let lambert = max(dot(normalize(in.normal), uniforms.sun.xyz), 0.0);
    var colour = vec3<f32>(0.62, 0.60, 0.52) * (0.3 + 0.7 * lambert);
    if uniforms.options.y > 0.5 && in.in_view < 0.5 {
        colour = colour * vec3<f32>(0.75, 0.35, 0.35);
    }
    // Roles (0 surface, 1 skirt, 2 degenerate, 3 stitch): skirts cyan, stitches violet.
    if uniforms.options.w > 0.5 && in.role > 0.5 && in.role < 1.5 {
        colour = vec3<f32>(0.1, 0.75, 0.85) * (0.5 + 0.5 * lambert);
    }
    if uniforms.options.w > 0.5 && in.role > 2.5 {
        colour = vec3<f32>(0.55, 0.3, 0.9) * (0.5 + 0.5 * lambert);
    }
    if uniforms.options.x > 0.5 {
        let width = fwidth(in.barycentric);
        let inside = smoothstep(vec3<f32>(0.0), width * 1.5, in.barycentric);
        let edge = 1.0 - min(min(inside.x, inside.y), inside.z);
        let t = in.level / max(uniforms.options.z, 1.0);
        colour = mix(colour, level_colour(t), edge);
    }
    return vec4<f32>(colour, 1.0);
}

// Triangle k is written as k + 1; 0 (the clear value) is background.
@fragment
fn id_fragment(in: MeshVarying) -> @location(0) u32 {
    return in.triangle + 1u;
}

struct LineVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec3<f32>,
};

@vertex
fn line_vertex(@location(0) position: vec3<f32>, @location(1) colour: vec3<f32>) -> LineVarying {
    var out: LineVarying;
    out.clip = uniforms.view_projection * vec4<f32>(position, 1.0);
    out.colour = colour;
    return out;
}

@fragment
fn line_fragment(in: LineVarying) -> @location(0) vec4<f32> {
    return vec4<f32>(in.colour, 1.0);
}
