// Corrector of the explicit step over every body's nodes in one dispatch, one node per
// invocation (twin: `kernels::explicit_correct`, body by body): each body's nodes start at a
// workgroup of their own (`bodies[b]`: its first workgroup, first node and node count;
// `bodies[params.aux].x` the workgroups in all), so that a workgroup's sums are one body's;
// a_{n+1} = a_ext - f_int / m, v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}; and the workgroup's
// share of the body's history values in the time-centred form the host path reports
// (integrate/explicit.rs): kinetic
// 1/2 m v_{n+1/2}^2, strain 1/2 u_n . f_int(u_{n+1}) with u_n = u_{n+1} - dt v_{n+1/2},
// gravity -f_ext . (u_n + u_{n+1}) / 2, and momentum m v_{n+1}: FIELDS floats per workgroup at
// partials[workgroup * FIELDS], body after body.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> forces: array<f32>;
@group(0) @binding(4) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(5) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(6) var<storage, read_write> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read_write> partials: array<f32>;
@group(0) @binding(8) var<storage, read> bodies: array<vec4<u32>>;

fn node_force(n: u32) -> vec3<f32> {
    return vec3<f32>(forces[3u * n], forces[3u * n + 1u], forces[3u * n + 2u]);
}

// include: correct_group

@compute @workgroup_size(64)
fn explicit_correct(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    correct_group(local, wid.x + wid.y * groups.x);
}
