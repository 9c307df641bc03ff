//! The table of kernels: one line per WGSL kernel gives its host type, its name (the file
//! `shaders/<name>.wgsl`, its entry point and its CPU twin `crate::kernels::<name>`) and its
//! storage buffers in binding order (binding 0 is every kernel's `Params` uniform). Each line
//! makes a type with the kernel's pipeline, built once ([`Kernel`]), a typed `bind` and a
//! typed `launch` whose parameters are the shader's buffer names. `tests/gpu_kernels.rs`
//! reads every shader with naga and checks its bindings against this table.

use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::shaders;

macro_rules! kernel_table {
    ($($ty:ident = $name:ident($($binding:ident),* $(,)?);)*) => {
        $(
            #[doc = concat!(
                "The host side of `shaders/", stringify!($name), ".wgsl`; CPU twin: [`crate::kernels::",
                stringify!($name), "`]."
            )]
            pub struct $ty(pub Kernel);

            impl $ty {
                pub const NAME: &'static str = stringify!($name);

                /// Builds the kernel's pipeline.
                pub fn new(ctx: &GpuContext) -> Self {
                    $ty(Kernel::new(ctx, Self::NAME, shaders::source(Self::NAME)))
                }

                /// A bind group of the buffers, in the shader's binding order.
                #[allow(clippy::too_many_arguments)]
                pub fn bind(&self, ctx: &GpuContext, $($binding: &wgpu::Buffer),*) -> wgpu::BindGroup {
                    self.0.bind(ctx, &[$($binding),*])
                }

                /// A launch over `count` items with the kernel's `Params.aux` and `aux2`.
                #[allow(clippy::too_many_arguments)]
                pub fn launch(
                    &self,
                    ctx: &GpuContext,
                    count: u32,
                    aux: u32,
                    aux2: u32,
                    $($binding: &wgpu::Buffer),*
                ) -> Launch {
                    self.0.launch(ctx, count, aux, aux2, &[$($binding),*])
                }
            }
        )*

        /// Every kernel of the table and its storage buffers in binding order (from 1).
        pub const TABLE: &[(&str, &[&str])] = &[$((stringify!($name), &[$(stringify!($binding)),*])),*];
    };
}

kernel_table! {
    BodyGather = body_gather(links, constraints, dj, state);
    BucketCount = bucket_count(keys, counts, ranks);
    BucketFill = bucket_fill(keys, ranks, starts, sorted);
    BucketOrder = bucket_order(starts, sorted, counts, state, bounds);
    CohesivePairs = cohesive_pairs(displacement, laws, pairs, state, outputs);
    CohesiveReduce = cohesive_reduce(ranges, pairs, state, outputs, rows);
    CohesiveScatter = cohesive_scatter(nodes, links, outputs, corner_forces);
    ContactApply = contact_apply(
        step, nodes, links, constraints, starts, sorted, dj, lumped, velocity, state,
    );
    ContactCompliance = contact_compliance(constraints, touches, lumped, pairs, state, dj);
    ContactConstraints = contact_constraints(
        step, grid, reference, displacement, velocity, acceleration, pairs, points, faces,
        constraints, keys, rigid, results,
    );
    ContactFinish = contact_finish(
        step, constraints, pairs, velocity, dj, state, nodes, links, starts, sorted, lumped,
    );
    ContactGap = contact_gap(reference, displacement, velocity, queries, candidates, faces, points);
    ContactReportKernel = contact_report(
        step, constraints, pairs, velocity, state, results, rigid, nodes, displacement, late,
    );
    ContactSearch = contact_search(
        grid, reference, displacement, velocity, queries, faces, starts, sorted, points, boxes,
        step, bounds,
    );
    ContactSweep = contact_sweep(step, constraints, pairs, velocity, dj, state);
    ContactTouches = contact_touches(nodes, links, constraints, starts, sorted, touches, state);
    ContactRelax = contact_relax(
        step, constraints, pairs, nodes, links, starts, sorted, lumped, dj, carried, contact_of,
        velocity, state,
    );
    ContactWarm = contact_warm(
        nodes, links, constraints, starts, sorted, dj, lumped, velocity, state, carried,
    );
    ContactZone = contact_zone(
        step, grid, reference, displacement, velocity, acceleration, pairs, points, faces,
        constraints, keys, rigid, counts, ranks, starts, sorted, state, nodes, links, touches,
        lumped, dj, results, late, bounds,
    );
    CornerSelect = corner_select(slots, corner_forces, chosen);
    DamageReduce = damage_reduce(records, rows);
    ExplicitCorrect = explicit_correct(
        step, displacement, forces, lumped, velocity, acceleration, partials, bodies,
    );
    ExplicitDrift = explicit_drift(step, velocity, displacement);
    ExplicitPredict = explicit_predict(step, acceleration, velocity);
    FaceCells = face_cells(grid, reference, displacement, faces, face_first, keys, centres, boxes);
    FailureReduce = failure_reduce(partials, rows);
    FailureSurveyKernel = failure_survey(displacement, points, operators, strengths, partials);
    FillWords = fill_words(words);
    GatherCorrect = gather_correct(
        step, displacement, lumped, velocity, acceleration, partials, bodies, offsets, incidence,
        corner_forces,
    );
    Hex8Damage = hex8_damage(
        damage, reference, displacement, velocity, block_nodes, elements, plies, entries, laws,
        state, records, corner_forces,
    );
    Hex8iDamage = hex8i_damage(
        damage, reference, displacement, velocity, block_nodes, elements, plies, entries, laws,
        condensation, state, records, corner_forces,
    );
    Hex8Forces = hex8_forces(
        reference, displacement, block_nodes, block_material, materials, corner_forces,
    );
    Hex8iForces = hex8i_forces(reference, displacement, block_nodes, kept, corner_forces);
    HistoryReduce = history_reduce(
        columns, partials, results, displacement, velocity, corner_forces, corner_lists, rows,
    );
    NodeGather = node_gather(offsets, incidence, corner_forces, forces);
    NodeScatter = node_scatter(nodes, values, nodal);
    NodeSelect = node_select(nodes, nodal, selected);
    PlaneContact = plane_contact(
        step, reference, displacement, acceleration, lumped, planes, plane_nodes, velocity,
        results,
    );
    PredictBounds = predict_bounds(
        step, reference, displacement, velocity, acceleration, faces, centres, bounds, boxes,
        late,
    );
    PrefixSum = prefix_sum(values, totals, starts);
    ScanTotals = scan_totals(values, totals);
    SearchBounds = search_bounds(reference, displacement, velocity, faces, centres, bounds, boxes);
    SearchGridKernel = search_grid(step, bounds, grid);
    SlipRate = slip_rate(reference, displacement, velocity, queries, faces, points, slip);
    StableStep = stable_step(reference, block_nodes, block_material, materials, steps);
    Tet4Damage = tet4_damage(
        damage, reference, displacement, velocity, block_nodes, elements, plies, entries, laws,
        state, records, corner_forces,
    );
    Tet4Forces = tet4_forces(
        reference, displacement, block_nodes, block_material, materials, corner_forces,
    );
}
