// included by kernels that bind `step: Step`, `bounds: array<u32, 6>` (read_write: the
// step's speed, side and drift as `search_bounds` folds them, then their copy) and `grid:
// SearchGrid` (read_write): `search_grid` on a step that sorts the faces, `contact_search`
// on a step that keeps the sort (twin: `kernels::search_grid`)

// The step's margin: the largest face size plus four steps of the fastest node's motion.
fn step_margin() -> f32 {
    return grid.face_size + 4.0 * step.dt * bitcast<f32>(bounds[0]);
}

// What a kept sort needs of a cell this step: a node within the margin of a face's box is
// within side + margin of its centre, which has moved `drift` (bounds[2], the largest move
// of a face centre since the sort) from the cell it was sorted into, so the 27 cells around
// the node hold every candidate while (side + margin + drift) x 1.001 < cell.
fn kept_need(margin: f32) -> f32 {
    return (bitcast<f32>(bounds[1]) + margin + bitcast<f32>(bounds[2])) * 1.001;
}

// A step that keeps the sort: its margin, the largest share of a cell it needed, and
// whether the sort no longer holds (then every face of the interface is a candidate).
fn keep_grid(margin: f32, need: f32) {
    grid.margin = margin;
    grid.fill = max(grid.fill, need / grid.cell);
    let stale = need >= grid.cell;
    grid.all_faces = select(0u, 1u, stale);
    grid.stale_steps += select(0u, 1u, stale);
}

// The step's bounds copied to bounds[3..6], where they can be read back (`bucket_order`
// clears bounds[0..3] for the next step once the search has read them).
fn copy_bounds() {
    for (var k = 0u; k < 3u; k++) {
        bounds[3u + k] = bounds[k];
    }
}
