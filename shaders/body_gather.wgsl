// The impulse changes of a sweep on each rigid body, one workgroup per body range (twin:
// `kernels::body_gather`): the sum over the range's pairs of their impulse changes times
// the body's shape function (1 in reach), 64 lanes each adding every 64th pair, then a tree
// over the lanes (`gather_range_part`; `contact_finish` adds the same parts by the same
// tree). Written after the pairs' own, at dj[3 (params.aux + r)] (params.aux: the pairs),
// where `apply_node` takes it for the body's node. After a sweep that did not run it exits
// at once.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> links: array<u32>;
@group(0) @binding(2) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read_write> dj: array<f32>;
@group(0) @binding(4) var<storage, read> state: array<u32, 8>;

var<workgroup> parts: array<vec3<f32>, 64>;
var<workgroup> swept: u32;
var<workgroup> ranges: u32;

// include: gather_range

@compute @workgroup_size(64)
fn body_gather(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    if (local == 0u) {
        swept = state[STATE_SWEPT];
        ranges = links[0];
    }
    let r = wid.x + wid.y * groups.x;
    let ran = workgroupUniformLoad(&swept) != 0u;
    if (!ran || r >= workgroupUniformLoad(&ranges)) {
        return;
    }
    parts[local] = gather_range_part(r, local);
    gather_range(r, params.aux, local);
}
