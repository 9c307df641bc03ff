// The step's search grid from its bounds on a step that sorts the faces into it (twin:
// `kernels::search_grid`), as the host path computes it (`contact::search::{margin,
// search_cell}`): the margin is the largest face size (grid.face_size) plus four steps of
// the fastest node's motion, and the cell side the largest face box side plus the margin, a
// thousandth more, and a skin of SEARCH_SKIN more, so that the faces may move before the
// grid must be rebuilt. params.aux2 SEARCH_FIRST (a submission's first step) also starts a
// new `fill`. A step that keeps the sort dispatches no `search_grid`: its narrow phase
// checks that the sort still holds (`contact_search` with params.aux 1, `kept_grid.wgsl`).
// params.aux is the table's mask. One invocation. It copies the bounds to bounds[3..6]
// (where they can be read back); `bucket_order` clears them for the next step.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> bounds: array<u32, 6>;
@group(0) @binding(3) var<storage, read_write> grid: SearchGrid;

const SEARCH_FIRST: u32 = 2u;
const SEARCH_SKIN: f32 = 0.1;

// include: kept_grid

@compute @workgroup_size(1)
fn search_grid() {
    let margin = step_margin();
    grid.margin = margin;
    let side = bitcast<f32>(bounds[1]);
    grid.cell = max((side + margin) * 1.001 * (1.0 + SEARCH_SKIN), 1e-30);
    grid.mask = params.aux;
    grid.all_faces = 0u;
    if (params.aux2 == SEARCH_FIRST) {
        grid.fill = 0.0;
    }
    copy_bounds();
}
