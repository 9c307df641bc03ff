//! Every element's stable step on the device, by the `stable_step` kernel (CPU twin:
//! [`crate::kernels::stable_step()`]).

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::engine::{at_least_one, device_materials, split_reference};
use super::kernels::StableStep;
use super::types::{Hex8, Tet4};
use crate::element::ElementKind;
use crate::error::Result;
use crate::kernels::ElementData;

/// The kinds the `stable_step` kernel bounds; a mesh holding another kind takes the CPU's
/// survey.
pub(crate) const KINDS: [ElementKind; 2] = [ElementKind::Hex8, ElementKind::Tet4];

/// Whether the kernel bounds every element of `data`.
pub fn covers(data: &ElementData) -> bool {
    (data.elements.blocks.iter()).all(|b| b.is_empty() || KINDS.contains(&b.kind))
}

/// Every element's Gershgorin step on the device (hex8s, then tet4s: the mesh's order where
/// it holds these kinds alone, [`covers`]), in f64.
pub fn element_steps(ctx: &GpuContext, data: &ElementData) -> Result<Vec<f64>> {
    let (reference, materials) = (split_reference(data), device_materials(data));
    let block = |kind| data.elements.block(kind);
    let hexes: Vec<Hex8> = (block(ElementKind::Hex8).corners::<8>().iter())
        .zip(&block(ElementKind::Hex8).material)
        .map(|(&nodes, &material)| Hex8 { nodes, material })
        .collect();
    let tets: Vec<Tet4> = (block(ElementKind::Tet4).corners::<4>().iter())
        .zip(&block(ElementKind::Tet4).material)
        .map(|(&nodes, &material)| Tet4 { nodes, material })
        .collect();
    let count = hexes.len() + tets.len();
    let nhex = hexes.len() as u32;
    let reference = Storage::with_data(ctx, "reference", &reference)?;
    let hexes = Storage::with_data(ctx, "hexes", &at_least_one(hexes))?;
    let tets = Storage::with_data(ctx, "tets", &at_least_one(tets))?;
    let materials = Storage::with_data(ctx, "materials", &materials)?;
    let steps = Storage::new(ctx, "element_steps", (4 * count) as u64)?;
    let kernel = StableStep::new(ctx);
    let bind = kernel.bind(
        ctx,
        &reference.buffer,
        &hexes.buffer,
        &tets.buffer,
        &materials.buffer,
        &steps.buffer,
    );
    let grid = kernel.0.set_count_aux(ctx, count as u32, nhex);
    let mut enc = ctx.encoder("stable_step");
    kernel.0.record(&mut enc, &bind, grid);
    let mut staging = staging(ctx)?;
    let out: Vec<f32> = submit_and_read(ctx, &mut staging, enc, &steps.buffer, count)?;
    Ok(out.into_iter().map(f64::from).collect())
}
