// Sets the first params.count words of a buffer to params.aux, one word per invocation
// (twin: `kernels::fill_words`): the zeroing of a counter or an accumulator inside a compute
// pass, where a buffer clear would end the pass.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> words: array<u32>;

@compute @workgroup_size(64)
fn fill_words(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i < params.count) {
        words[i] = params.aux;
    }
}
