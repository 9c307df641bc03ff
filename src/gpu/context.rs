//! Instance, adapter choice and device: the one place that talks to wgpu's adapters.
//!
//! Order of preference: a hardware GPU (discrete, then integrated, then virtual), then a
//! software adapter (lavapipe on Vulkan before llvmpipe on GL). Adapters without compute
//! shaders are never chosen. `WGPU_BACKEND=vulkan|gl` restricts the backends searched (read
//! once, when the process first looks for adapters).
//!
//! The process holds one wgpu instance and one device per adapter for its whole life: every
//! run, on every thread, shares them. A Vulkan driver library is unloaded when the last
//! instance goes away; with an instance per run, a thread that dropped its run's instance
//! could unload the driver while another thread still ran in it (or still had to run its
//! thread-local destructors), which crashed programs that ran scenes on several threads.

use std::sync::{Mutex, OnceLock};

use crate::error::{ImpactError, Result};

/// Storage buffers the most demanding kernel binds (`contact_constraints`); an adapter that
/// binds fewer per shader stage cannot run the kernels (a test keeps this the maximum).
pub const STORAGE_BINDINGS: u32 = 12;

/// Storage buffers `contact_zone` binds: the whole contact iteration in one workgroup, which
/// runs only where the adapter binds this many per shader stage (the staged iteration runs
/// elsewhere; a test keeps this the kernel's count).
pub const ZONE_BINDINGS: u32 = 24;

/// Under `device = "auto"`, scenes with at least this many elements run their kernels on a
/// hardware GPU when there is one. Smaller scenes stay on the CPU in f64: there the kernels
/// cost less than a few milliseconds per iteration, and f64 keeps the contact iteration's
/// convergence test at its tightest. Software adapters are never chosen by "auto": on the
/// same cores they are slower than the CPU twins (`docs/performance.md`, the kernel benchmark).
pub const AUTO_GPU_MIN_ELEMENTS: usize = 20_000;

/// What a user needs to know about one adapter.
#[derive(Debug, Clone)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: wgpu::Backend,
    pub device_type: wgpu::DeviceType,
    pub driver: String,
    pub driver_info: String,
    /// The PCI bus of the device, where the driver reports it (it tells identical cards
    /// apart).
    pub pci_bus: String,
    /// Runs the kernels: compute shaders and at least
    /// [`STORAGE_BINDINGS`] storage buffers per shader stage.
    pub compute: bool,
    /// A CPU implementation (lavapipe, llvmpipe, SwiftShader, WARP).
    pub software: bool,
}

impl AdapterSummary {
    fn of(adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        let flags = adapter.get_downlevel_capabilities().flags;
        let compute = flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
            && adapter.limits().max_storage_buffers_per_shader_stage >= STORAGE_BINDINGS;
        let lower = info.name.to_lowercase();
        let software = info.device_type == wgpu::DeviceType::Cpu
            || ["llvmpipe", "lavapipe", "swiftshader", "softpipe", "warp"]
                .iter()
                .any(|s| lower.contains(s));
        AdapterSummary {
            name: info.name,
            backend: info.backend,
            device_type: info.device_type,
            driver: info.driver,
            driver_info: info.driver_info,
            pci_bus: info.device_pci_bus_id,
            compute,
            software,
        }
    }

    /// Sort key: lower is preferred.
    fn rank(&self) -> (u8, u8) {
        let kind = if self.software {
            4
        } else {
            match self.device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Other => 3,
                wgpu::DeviceType::Cpu => 4,
            }
        };
        let backend = match self.backend {
            wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => 0,
            _ => 1,
        };
        (kind, backend)
    }

    /// One line: "NAME (Vulkan, Cpu, driver DRIVER INFO)".
    pub fn describe(&self) -> String {
        let driver = format!("{} {}", self.driver, self.driver_info);
        let driver = driver.trim();
        let sep = if driver.is_empty() { "" } else { ", " };
        let bus = if self.pci_bus.is_empty() {
            String::new()
        } else {
            format!(", PCI {}", self.pci_bus)
        };
        format!(
            "{} ({:?}, {:?}{sep}{driver}{bus})",
            self.name, self.backend, self.device_type
        )
    }
}

/// Which adapters a caller accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdapterPolicy {
    /// Hardware first, then software.
    Any,
    /// Hardware GPUs only.
    HardwareOnly,
    /// The adapter of the process with this index among a decomposed run's processes on
    /// the machine: of the adapters of [`rank_order`], the one at the index modulo their
    /// count, so that the ranks spread over the cards.
    LocalRank(usize),
}

/// A device and queue on the chosen adapter (cloning shares them).
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterSummary,
    pub limits: wgpu::Limits,
    /// The adapter's features (none is required by the kernels; `impact info` reports them).
    /// Of them the device asks for [`PROFILING`] where the adapter has it all, and for
    /// timestamp queries alone otherwise (the resident step times its submissions).
    pub features: wgpu::Features,
    /// The lanes `contact_zone` and `contact_finish` are built with, at most what the
    /// adapter runs ([`super::one_group`]); [`super::one_group::ONE_GROUP`] unless a caller
    /// (the bench's `--lanes`) sets it before building the step.
    pub zone_lanes: u32,
    /// The further widths of `contact_zone` the run's trial of the contact iteration's forms
    /// times ([`super::one_group::trial_widths`] unless a caller sets them before building
    /// the step).
    pub zone_trial: Vec<u32>,
}

/// Timestamps between a compute pass's dispatches, which the benchmarks' profile of a step
/// writes ([`crate::gpu::ResidentStep::profile_dispatches`]); nothing else uses them.
pub const PROFILING: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// The process's wgpu instance, made at the first use and never dropped.
fn instance() -> &'static wgpu::Instance {
    static INSTANCE: OnceLock<wgpu::Instance> = OnceLock::new();
    INSTANCE.get_or_init(|| {
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
    })
}

/// The device each adapter policy chose (none, where no adapter qualifies), found once: on
/// the GL backend, looking for adapters again while another thread runs on the device
/// would make the instance's EGL context current on two threads at once.
type Opened = Vec<(AdapterPolicy, Option<GpuContext>)>;

fn opened() -> std::sync::MutexGuard<'static, Opened> {
    static OPENED: Mutex<Opened> = Mutex::new(Vec::new());
    // a thread that panicked while holding the lock left the list whole (pushes only)
    OPENED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Waits for every device the process opened to finish its work, then closes those that
/// no run still holds. Called before the process ends (and before `MPI_Finalize` on a
/// rank): a device left open at exit is torn down by the driver's own exit handlers, which
/// on lavapipe can run while its worker threads still hold the device, and end the
/// process with a signal after a run that succeeded. A later [`GpuContext::open`] opens a
/// device again.
pub fn close_devices() -> Result<()> {
    let closing = std::mem::take(&mut *opened());
    for ctx in closing.iter().filter_map(|(_, c)| c.as_ref()) {
        ctx.wait()?;
    }
    drop(closing);
    Ok(())
}

/// The adapters the processes of a decomposed run on one machine take in turn (by their
/// place among them, modulo the count), as indices into `ranked` (usable adapters, best
/// first): those of the best one's kind on its backend, each card once (by its PCI bus,
/// where the driver gives it), in the order of their buses.
pub(crate) fn rank_order(ranked: &[AdapterSummary]) -> Vec<usize> {
    let Some(best) = ranked.first() else {
        return Vec::new();
    };
    let (kind, backend) = (best.rank(), best.backend);
    let mut order: Vec<usize> = (0..ranked.len())
        .filter(|&i| ranked[i].rank() == kind && ranked[i].backend == backend)
        .collect();
    // a stable sort: without bus ids, the listing's order
    order.sort_by(|&a, &b| ranked[a].pci_bus.cmp(&ranked[b].pci_bus));
    order.dedup_by(|a, b| {
        !ranked[*a].pci_bus.is_empty() && ranked[*a].pci_bus == ranked[*b].pci_bus
    });
    order
}

/// Every adapter wgpu finds, best first.
pub fn list_adapters() -> Vec<AdapterSummary> {
    let adapters = pollster::block_on(instance().enumerate_adapters(wgpu::Backends::all()));
    let mut all: Vec<AdapterSummary> = adapters.iter().map(AdapterSummary::of).collect();
    all.sort_by_key(AdapterSummary::rank);
    all
}

/// The packages that provide a software adapter, for error messages.
pub(crate) const SOFTWARE_ADAPTER_HINT: &str = "no GPU adapter with compute shaders was found; on Debian/Ubuntu install a software adapter with `apt-get install -y mesa-vulkan-drivers libvulkan1` (lavapipe) or `libgl1-mesa-dri libegl1` (llvmpipe), or use device = \"cpu\"";

impl GpuContext {
    /// The device of the best adapter the policy accepts, or `Ok(None)` if there is none.
    /// The first call for an adapter opens its device; later calls, from any thread, share
    /// it (a clone).
    pub fn open(policy: AdapterPolicy) -> Result<Option<Self>> {
        let mut opened = opened();
        if let Some((_, ctx)) = opened.iter().find(|(p, _)| *p == policy) {
            return Ok(ctx.clone());
        }
        let ctx = Self::open_device(policy, &opened)?;
        opened.push((policy, ctx.clone()));
        Ok(ctx)
    }

    /// The device of the best adapter the policy accepts: the one another policy opened on
    /// it, or a new one.
    fn open_device(policy: AdapterPolicy, opened: &Opened) -> Result<Option<Self>> {
        let adapters = pollster::block_on(instance().enumerate_adapters(wgpu::Backends::all()));
        let mut ranked: Vec<(AdapterSummary, wgpu::Adapter)> = adapters
            .into_iter()
            .map(|a| (AdapterSummary::of(&a), a))
            .filter(|(s, _)| s.compute && (policy != AdapterPolicy::HardwareOnly || !s.software))
            .collect();
        ranked.sort_by_key(|(s, _)| s.rank());
        let chosen = match policy {
            AdapterPolicy::LocalRank(k) => {
                let summaries: Vec<AdapterSummary> =
                    ranked.iter().map(|(s, _)| s.clone()).collect();
                let order = rank_order(&summaries);
                (!order.is_empty()).then(|| order[k % order.len()])
            }
            _ => (!ranked.is_empty()).then_some(0),
        };
        let Some((summary, adapter)) = chosen.map(|i| ranked.swap_remove(i)) else {
            return Ok(None);
        };
        let same = |c: &GpuContext| {
            let a = &c.adapter;
            a.name == summary.name && a.backend == summary.backend && a.pci_bus == summary.pci_bus
        };
        if let Some(ctx) = opened
            .iter()
            .filter_map(|(_, c)| c.as_ref())
            .find(|c| same(c))
        {
            return Ok(Some(ctx.clone()));
        }
        let limits = adapter.limits();
        let features = adapter.features();
        // the resident step times its submissions where the adapter has timestamps
        let profiling = if features.contains(PROFILING) {
            PROFILING
        } else {
            features & wgpu::Features::TIMESTAMP_QUERY
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("impact"),
            required_features: profiling,
            required_limits: limits.clone(),
            memory_hints: wgpu::MemoryHints::Performance,
            ..Default::default()
        }))
        .map_err(|e| ImpactError::Gpu(format!("{}: cannot open the device: {e}", summary.name)))?;
        let lanes = super::one_group::ONE_GROUP;
        let zone_trial = super::one_group::trial_widths(&limits, summary.software, lanes);
        Ok(Some(GpuContext {
            device,
            queue,
            adapter: summary,
            limits,
            features,
            zone_lanes: lanes,
            zone_trial,
        }))
    }

    /// Opens the best adapter, hardware or software; a clear error naming the packages to
    /// install if there is none.
    pub fn new() -> Result<Self> {
        Self::open(AdapterPolicy::Any)?
            .ok_or_else(|| ImpactError::Gpu(SOFTWARE_ADAPTER_HINT.into()))
    }

    /// The adapter of the process with index `local` among a decomposed run's processes on
    /// this machine ([`AdapterPolicy::LocalRank`]); the error of [`Self::new`] if there is
    /// none.
    pub fn for_local_rank(local: usize) -> Result<Self> {
        Self::open(AdapterPolicy::LocalRank(local))?
            .ok_or_else(|| ImpactError::Gpu(SOFTWARE_ADAPTER_HINT.into()))
    }

    /// Whether the device writes timestamps (at a compute pass's start and end): the
    /// resident steps time their submissions with them.
    pub fn has_timestamps(&self) -> bool {
        (self.device.features()).contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Blocks until the device has finished all submitted work.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| {
                ImpactError::Gpu(format!(
                    "{}: waiting for the device: {e}",
                    self.adapter.name
                ))
            })
    }

    /// A command encoder named `label`.
    pub fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// Submits `enc`'s commands and blocks until the device has run them.
    pub fn submit_and_wait(&self, enc: wgpu::CommandEncoder) -> Result<()> {
        self.queue.submit([enc.finish()]);
        self.wait()
    }

    /// Largest storage buffer one binding may hold, in bytes.
    pub fn max_binding(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }
}

/// The report of `impact info`: every adapter found, the ones `device = "gpu"` and
/// `device = "auto"` would use, and the limits and features that matter to the kernels.
pub fn info_report() -> Result<String> {
    use std::fmt::Write;
    let mut r = String::new();
    let all = list_adapters();
    let _ = writeln!(r, "adapters found ({}), best first:", all.len());
    for a in &all {
        let _ = writeln!(
            r,
            "  {}{}{}",
            a.describe(),
            if a.software { " [software]" } else { "" },
            if a.compute {
                ""
            } else {
                " [no compute shaders: unusable]"
            }
        );
    }
    match GpuContext::open(AdapterPolicy::Any)? {
        None => {
            let _ = writeln!(r, "device = \"gpu\": none usable. {SOFTWARE_ADAPTER_HINT}");
        }
        Some(ctx) => {
            let l = &ctx.limits;
            let _ = writeln!(r, "device = \"gpu\" uses: {}", ctx.adapter.describe());
            let _ = writeln!(
                r,
                "  max storage buffer binding: {} MiB",
                l.max_storage_buffer_binding_size >> 20
            );
            let _ = writeln!(r, "  max buffer size: {} MiB", l.max_buffer_size >> 20);
            let _ = writeln!(
                r,
                "  storage buffers per shader stage: {} (kernels use at most {}; contact_zone {} where there are that many)",
                l.max_storage_buffers_per_shader_stage, STORAGE_BINDINGS, ZONE_BINDINGS
            );
            let _ = writeln!(
                r,
                "  workgroups per dimension: {} (kernels dispatch 2D grids of 64-wide groups)",
                l.max_compute_workgroups_per_dimension
            );
            let _ = writeln!(
                r,
                "  invocations per workgroup: {} (kernels use 64; contact_zone and contact_finish {}, up to {} with the explicit bench's --lanes{})",
                l.max_compute_invocations_per_workgroup,
                super::one_group::within(l, ctx.zone_lanes),
                super::one_group::widest(l),
                match ctx.zone_trial.as_slice() {
                    [] => String::new(),
                    w => format!("; runs time contact_zone at {w:?} lanes too"),
                }
            );
            let f = ctx.features;
            let _ = writeln!(
                r,
                "  features: shader f64 {}, f32 atomics {}, timestamp queries {}",
                yes(f.contains(wgpu::Features::SHADER_F64)),
                yes(f.contains(wgpu::Features::SHADER_FLOAT32_ATOMIC)),
                yes(f.contains(wgpu::Features::TIMESTAMP_QUERY))
            );
        }
    }
    let usable: Vec<AdapterSummary> = all.iter().filter(|a| a.compute).cloned().collect();
    let turns: Vec<String> = (rank_order(&usable).into_iter())
        .map(|i| usable[i].describe())
        .collect();
    if !turns.is_empty() {
        let _ = writeln!(
            r,
            "device = \"gpu\" on MPI ranks: the ranks on this machine take in turn {}",
            turns.join("; ")
        );
    }
    let hardware = all.iter().find(|a| a.compute && !a.software);
    let _ = writeln!(
        r,
        "device = \"auto\" uses: {}",
        match hardware {
            Some(a) => format!(
                "{} for scenes of at least {} elements, the CPU (f64) below",
                a.name, AUTO_GPU_MIN_ELEMENTS
            ),
            None => "the CPU (f64): no hardware GPU".into(),
        }
    );
    Ok(r)
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adapter(
        name: &str,
        backend: wgpu::Backend,
        kind: wgpu::DeviceType,
        bus: &str,
    ) -> AdapterSummary {
        AdapterSummary {
            name: name.into(),
            backend,
            device_type: kind,
            driver: String::new(),
            driver_info: String::new(),
            pci_bus: bus.into(),
            compute: true,
            software: kind == wgpu::DeviceType::Cpu,
        }
    }

    fn ranked(mut list: Vec<AdapterSummary>) -> Vec<AdapterSummary> {
        list.sort_by_key(AdapterSummary::rank);
        list
    }

    /// Four cards listed on Vulkan out of bus order and again on GL, with a software
    /// adapter: the ranks take the four Vulkan cards in bus order, each once.
    #[test]
    fn ranks_take_each_card_once_in_bus_order() {
        use wgpu::{Backend::*, DeviceType::*};
        let mut list = Vec::new();
        for bus in [
            "0000:c1:00.0",
            "0000:41:00.0",
            "0000:81:00.0",
            "0000:01:00.0",
        ] {
            list.push(adapter("H100", Vulkan, DiscreteGpu, bus));
            list.push(adapter("H100", Gl, DiscreteGpu, bus));
        }
        list.push(adapter("H100", Vulkan, DiscreteGpu, "0000:41:00.0")); // listed twice
        list.push(adapter("llvmpipe", Vulkan, Cpu, ""));
        let list = ranked(list);
        let buses: Vec<(&str, wgpu::Backend)> = (rank_order(&list).into_iter())
            .map(|i| (list[i].pci_bus.as_str(), list[i].backend))
            .collect();
        assert_eq!(
            buses,
            [
                ("0000:01:00.0", Vulkan),
                ("0000:41:00.0", Vulkan),
                ("0000:81:00.0", Vulkan),
                ("0000:c1:00.0", Vulkan)
            ]
        );
    }

    /// Without bus ids the listing's order stands and nothing is merged; without hardware
    /// the software adapter serves every rank; with none, no rank has one.
    #[test]
    fn ranks_fall_back_to_the_listing_and_to_software() {
        use wgpu::{Backend::*, DeviceType::*};
        let two = ranked(vec![
            adapter("A", Vulkan, DiscreteGpu, ""),
            adapter("B", Vulkan, DiscreteGpu, ""),
            adapter("C", Vulkan, IntegratedGpu, ""),
        ]);
        assert_eq!(rank_order(&two), [0, 1]);
        let soft = ranked(vec![
            adapter("llvmpipe", Gl, Cpu, ""),
            adapter("lavapipe", Vulkan, Cpu, ""),
        ]);
        let order = rank_order(&soft);
        assert_eq!(order.len(), 1);
        assert_eq!(soft[order[0]].backend, Vulkan);
        assert!(rank_order(&[]).is_empty());
    }
}
