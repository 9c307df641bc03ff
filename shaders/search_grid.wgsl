// The step's search grid from its bounds (twin: `kernels::search_grid`), as the host path
// computes it (`contact::search::{margin, search_cell}`): the margin is the largest face
// size (grid.face_size) plus four steps of the fastest node's motion. A step that sorts the
// faces again (params.aux2 SEARCH_BUILD, or SEARCH_FIRST, which also starts a new `fill`)
// sets the cell side to the largest face box side plus the margin, a thousandth more, and a
// skin of SEARCH_SKIN more, so that the faces may move before the grid must be rebuilt. A
// step that keeps the grid (SEARCH_KEEP) checks that it still holds: a node within the
// margin of a face's box is within side + margin of its centre, which has moved `drift`
// (bounds[2], the largest move of a face centre since the sort) from the cell it was sorted
// into, so the 27 cells around the node hold every candidate while (side + margin + drift)
// x 1.001 < cell; otherwise the step tests every face (all_faces). params.aux is the table's
// mask. One invocation.
// It is the bounds' one reader: it moves them to bounds[3..6] (where they can be read back)
// and clears bounds[0..3] for the next step's `search_bounds`, saving a dispatch a step.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> bounds: array<u32, 6>;
@group(0) @binding(3) var<storage, read_write> grid: SearchGrid;

const SEARCH_KEEP: u32 = 0u;
const SEARCH_FIRST: u32 = 2u;
const SEARCH_SKIN: f32 = 0.1;

@compute @workgroup_size(1)
fn search_grid() {
    let margin = grid.face_size + 4.0 * step.dt * bitcast<f32>(bounds[0]);
    let side = bitcast<f32>(bounds[1]);
    grid.margin = margin;
    if (params.aux2 == SEARCH_KEEP) {
        let need = (side + margin + bitcast<f32>(bounds[2])) * 1.001;
        grid.fill = max(grid.fill, need / grid.cell);
        let stale = need >= grid.cell;
        grid.all_faces = select(0u, 1u, stale);
        grid.stale_steps += select(0u, 1u, stale);
    } else {
        grid.cell = max((side + margin) * 1.001 * (1.0 + SEARCH_SKIN), 1e-30);
        grid.mask = params.aux;
        grid.all_faces = 0u;
        if (params.aux2 == SEARCH_FIRST) {
            grid.fill = 0.0;
        }
    }
    for (var k = 0u; k < 3u; k++) {
        bounds[3u + k] = bounds[k];
        bounds[k] = 0u;
    }
}
