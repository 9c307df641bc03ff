// The step's search grid from its bounds (twin: `kernels::search_grid`), as the host path
// computes it (`contact::search::{margin, search_cell}`): the margin is the largest face
// diagonal (params.aux2, f32 bits) plus four steps of the fastest node's motion; the cell
// side is the largest face box side plus the margin, and a thousandth more. params.aux is
// the table's mask. One invocation.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> bounds: array<u32, 2>;
@group(0) @binding(3) var<storage, read_write> grid: SearchGrid;

@compute @workgroup_size(1)
fn search_grid() {
    let margin = bitcast<f32>(params.aux2) + 4.0 * step.dt * bitcast<f32>(bounds[0]);
    grid.cell = max((bitcast<f32>(bounds[1]) + margin) * 1.001, 1e-30);
    grid.margin = margin;
    grid.mask = params.aux;
    grid.pad = 0u;
}
