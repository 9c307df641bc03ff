// included by kernels that bind `late: array<u32>`

// Whether node n is one of the nodes the contact iteration drifts after its sweeps (bit
// n % 32 of late[n / 32]): the contact nodes, whose v* the sweeps change, where the step's
// predictor ran in the search's bounds; none elsewhere.
fn is_late(n: u32) -> bool {
    return ((late[n / 32u] >> (n % 32u)) & 1u) != 0u;
}
