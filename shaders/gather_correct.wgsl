// The gather and the corrector of the explicit step in one dispatch (twin:
// `kernels::gather_correct`): each node's internal force summed from its element corners in
// the order of its incidence list, as `node_gather` sums it, then the node's corrector and
// the workgroup's history sums, as `explicit_correct` takes them (the same functions, so the
// same bits as the two dispatches). The nodal forces are not written: nothing after the
// corrector reads them. A rank of a decomposed run, which exchanges its shared nodes' forces
// between the two, runs them apart. Params.aux: the bodies; params.aux2: the corner slots.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(4) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> acceleration: array<f32>;
@group(0) @binding(6) var<storage, read_write> partials: array<f32>;
@group(0) @binding(7) var<storage, read> bodies: array<vec4<u32>>;
@group(0) @binding(8) var<storage, read> offsets: array<u32>;
@group(0) @binding(9) var<storage, read> incidence: array<u32>;
@group(0) @binding(10) var<storage, read> corner_forces: array<f32>;

// include: gather_force

fn node_force(n: u32) -> vec3<f32> {
    return gather_force(n, params.aux2);
}

// include: correct_group

@compute @workgroup_size(64)
fn gather_correct(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    correct_group(local, wid.x + wid.y * groups.x);
}
