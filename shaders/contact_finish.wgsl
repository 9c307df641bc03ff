// The end of the contact iteration in one workgroup (twin: `kernels::contact_finish`): while
// the iteration sweeps on after the sweeps the host recorded, it runs the remaining sweeps
// itself, each a `sweep_pair` over the pairs (params.count), the stopping rule, the rigid
// bodies' gathers (`gather_bodies`) and an `apply_node` over the contact nodes (params.aux),
// with the workgroup's barriers between them where the recorded sweeps have dispatch
// boundaries. The same arithmetic in the same order as those sweeps, so the results do not
// depend on how many were recorded; a step whose iteration has stopped pays one
// workgroup's check of the phase.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> dj: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<u32, 8>;
@group(0) @binding(7) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(8) var<storage, read> links: array<u32>;
@group(0) @binding(9) var<storage, read> starts: array<u32>;
@group(0) @binding(10) var<storage, read> sorted: array<u32>;
@group(0) @binding(11) var<storage, read> lumped: array<Lumped>;

// include: velocity
// include: sweep_pair
// include: apply_node
// include: phase_after
// include: stopping_rule
// include: gather_range
// include: sweep_loop

@compute @workgroup_size(ONE_GROUP)
fn contact_finish(@builtin(local_invocation_index) local: u32) {
    sweep_while_sweeping(local);
}
