//! One compute pipeline with its bind-group layout and launch-parameter buffer, built once.
//! Binding 0 of every kernel is its [`Params`] uniform; bindings 1.. are storage buffers.

use super::context::GpuContext;
use super::types::{Params, WORKGROUP};

/// One launch of a kernel with its own parameters and bindings, built once and recorded at
/// every step.
pub struct Launch {
    params_buffer: wgpu::Buffer,
    params: Params,
    pub bind: wgpu::BindGroup,
    pub grid: [u32; 2],
    /// Workgroups of the grid (some of the last row may have no items).
    pub groups: u32,
}

impl Launch {
    /// Changes `Params.count` and `Params.aux` (the grid stays): for kernels whose items are
    /// not invocations (one workgroup per item).
    pub fn set_count(&mut self, ctx: &GpuContext, count: u32, aux: u32) {
        self.params.count = count;
        self.params.aux = aux;
        ctx.queue
            .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
    }
}

pub struct Kernel {
    pub name: &'static str,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    max_groups: u32,
}

impl Kernel {
    /// Compiles `source` and builds the pipeline of its entry point `name`.
    pub fn new(ctx: &GpuContext, name: &'static str, source: &str) -> Self {
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let pipeline = ctx
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: None,
                module: &module,
                entry_point: Some(name),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &[],
                    // every kernel writes its workgroup memory before it reads it
                    zero_initialize_workgroup_memory: false,
                },
                cache: None,
            });
        Kernel {
            name,
            layout: pipeline.get_bind_group_layout(0),
            pipeline,
            params: params_buffer(ctx, name),
            max_groups: ctx.limits.max_compute_workgroups_per_dimension.max(1),
        }
    }

    /// A bind group with the kernel's params at binding 0 and `storage[i]` at binding i + 1.
    pub fn bind(&self, ctx: &GpuContext, storage: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        self.bind_with(ctx, &self.params, storage)
    }

    /// A bind group with `params` at binding 0 and `storage[i]` at binding i + 1.
    fn bind_with(
        &self,
        ctx: &GpuContext,
        params: &wgpu::Buffer,
        storage: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: params.as_entire_binding(),
        }];
        for (i, b) in storage.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: i as u32 + 1,
                resource: b.as_entire_binding(),
            });
        }
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.name),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Sets the item count (applied at the next submission) and returns the dispatch grid.
    pub fn set_count(&self, ctx: &GpuContext, count: u32) -> [u32; 2] {
        self.set_count_aux(ctx, count, 0)
    }

    /// [`Self::set_count`] with the kernel-specific `Params.aux` (an offset, a flag).
    pub fn set_count_aux(&self, ctx: &GpuContext, count: u32, aux: u32) -> [u32; 2] {
        let (p, grid) = self.params_for(count, aux, 0);
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        grid
    }

    /// The dispatch grid of `count` items (as [`Self::set_count`] returns it).
    pub fn grid(&self, count: u32) -> [u32; 2] {
        self.params_for(count, 0, 0).1
    }

    /// The launch parameters and dispatch grid of `count` items.
    fn params_for(&self, count: u32, aux: u32, aux2: u32) -> (Params, [u32; 2]) {
        let groups = count.div_ceil(WORKGROUP);
        let x = groups.clamp(1, self.max_groups);
        let y = groups.div_ceil(x).max(1);
        let p = Params {
            count,
            row: x * WORKGROUP,
            aux,
            aux2,
        };
        (p, [x, y])
    }

    /// A launch fixed for a whole run: its own params uniform (so that several launches of
    /// one kernel, e.g. one per body, can be recorded in one submission) bound with
    /// `storage[i]` at binding i + 1, and its grid.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        count: u32,
        aux: u32,
        aux2: u32,
        storage: &[&wgpu::Buffer],
    ) -> Launch {
        let (p, grid) = self.params_for(count, aux, aux2);
        let params = params_buffer(ctx, self.name);
        ctx.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
        let bind = self.bind_with(ctx, &params, storage);
        Launch {
            params_buffer: params,
            params: p,
            bind,
            grid,
            groups: grid[0] * grid[1],
        }
    }

    /// Records a [`Launch`] of this kernel.
    pub fn record_launch(&self, encoder: &mut wgpu::CommandEncoder, launch: &Launch) {
        self.record(encoder, &launch.bind, launch.grid);
    }

    /// Dispatches a [`Launch`] of this kernel inside an open compute pass (the dispatches
    /// of one pass see each other's writes, in order).
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass, launch: &Launch) {
        self.dispatch_with(pass, &launch.bind, launch.grid);
    }

    /// Dispatches `grid` with bind group `bind` inside an open compute pass.
    pub fn dispatch_with(
        &self,
        pass: &mut wgpu::ComputePass,
        bind: &wgpu::BindGroup,
        grid: [u32; 2],
    ) {
        super::captured::note(self.name, &self.pipeline, bind, grid);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind, &[]);
        pass.dispatch_workgroups(grid[0], grid[1], 1);
    }

    /// A compute pass of its own, named after this kernel.
    fn begin_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder) -> wgpu::ComputePass<'e> {
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.name),
            timestamp_writes: None,
        })
    }

    /// Records one dispatch over `grid` (from [`Self::set_count`]).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind: &wgpu::BindGroup,
        grid: [u32; 2],
    ) {
        self.dispatch_with(&mut self.begin_pass(encoder), bind, grid);
    }
}

/// A [`Params`] uniform named after kernel `name`, written before each use.
fn params_buffer(ctx: &GpuContext, name: &'static str) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(name),
        size: std::mem::size_of::<Params>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
