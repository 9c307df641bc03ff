//! Host side of `shaders/plane_contact.wgsl` (CPU twin: [`crate::kernels::plane_contact`]).

use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::shaders;

pub struct PlaneContact(pub Kernel);

/// The buffers of a `plane_contact` launch, in the shader's binding order.
pub struct PlaneContactBuffers<'a> {
    pub step: &'a wgpu::Buffer,
    pub reference: &'a wgpu::Buffer,
    pub displacement: &'a wgpu::Buffer,
    pub acceleration: &'a wgpu::Buffer,
    pub lumped: &'a wgpu::Buffer,
    pub planes: &'a wgpu::Buffer,
    pub plane_nodes: &'a wgpu::Buffer,
    pub velocity: &'a wgpu::Buffer,
    pub results: &'a wgpu::Buffer,
}

impl PlaneContact {
    pub fn new(ctx: &GpuContext) -> Self {
        PlaneContact(Kernel::new(ctx, "plane_contact", shaders::PLANE_CONTACT))
    }

    /// A launch over `nodes` plane nodes against `planes` planes.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        nodes: u32,
        planes: u32,
        b: &PlaneContactBuffers,
    ) -> Launch {
        self.0.launch(
            ctx,
            nodes,
            planes,
            0,
            &[
                b.step,
                b.reference,
                b.displacement,
                b.acceleration,
                b.lumped,
                b.planes,
                b.plane_nodes,
                b.velocity,
                b.results,
            ],
        )
    }
}
