//! Every element's stable step on the device, by the `stable_step` kernel (CPU twin:
//! [`crate::kernels::stable_step()`]), one launch per element block, its connectivity
//! column by column as the force kernels read it ([`super::engine::column_nodes`]).

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::engine::{column_nodes, device_materials, split_reference};
use super::kernels::StableStep;
use crate::element::ElementKind;
use crate::error::Result;
use crate::kernels::ElementData;

/// The kinds the `stable_step` kernel bounds, by the code its `Params.aux` takes; a mesh
/// holding another kind takes the CPU's survey.
pub(crate) const KINDS: [ElementKind; 2] = [ElementKind::Hex8, ElementKind::Tet4];

/// Whether the kernel bounds every element of `data`.
pub fn covers(data: &ElementData) -> bool {
    (data.elements.blocks.iter()).all(|b| b.is_empty() || KINDS.contains(&b.kind))
}

/// Every element's Gershgorin step on the device, block by block in the mesh's order (it
/// holds these kinds alone, [`covers`]), in f64.
pub fn element_steps(ctx: &GpuContext, data: &ElementData) -> Result<Vec<f64>> {
    let reference = Storage::with_data(ctx, "reference", &split_reference(data))?;
    let materials = Storage::with_data(ctx, "materials", &device_materials(data))?;
    let count = data.elements.count();
    let steps = Storage::new(ctx, "element_steps", (4 * count.max(1)) as u64)?;
    let kernel = StableStep::new(ctx);
    let mut enc = ctx.encoder("stable_step");
    let mut first = 0;
    // the blocks' buffers live until the submission is read
    let mut blocks = Vec::new();
    for b in data.elements.blocks.iter().filter(|b| !b.is_empty()) {
        let kind = KINDS.iter().position(|&k| k == b.kind).expect("covers") as u32;
        let nodes = Storage::with_data(ctx, "block_nodes", &column_nodes(b))?;
        let material = Storage::with_data(ctx, "block_material", &b.material)?;
        let (x, m, s) = (&reference.buffer, &materials.buffer, &steps.buffer);
        let launch = kernel.launch(
            ctx,
            b.len() as u32,
            kind,
            first,
            x,
            &nodes.buffer,
            &material.buffer,
            m,
            s,
        );
        kernel.0.record_launch(&mut enc, &launch);
        first += b.len() as u32;
        blocks.push((nodes, material, launch));
    }
    let mut staging = staging(ctx)?;
    let out: Vec<f32> = submit_and_read(ctx, &mut staging, enc, &steps.buffer, count)?;
    Ok(out.into_iter().map(f64::from).collect())
}
