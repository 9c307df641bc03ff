//! The GPU engine: wgpu context and adapter choice ([`context`]), the table of kernels
//! ([`kernels`]: one line per `shaders/<name>.wgsl`, named as its CPU twin in
//! [`crate::kernels`]), the Pod buffer types ([`types`]) and [`GpuKernels`], the
//! [`crate::backend::Kernels`] interface on a device. The hooks that tests and benches use to
//! run one stage alone and read device buffers back are apart, in [`inspect`].

mod bucket_sort;
pub mod buffer;
pub mod captured;
pub(crate) mod cohesive_stage;
pub mod contact_form;
pub mod context;
pub mod corner_select;
pub(crate) mod damage_stage;
pub mod engine;
mod failure_stage;
pub mod impulse_sweeps;
pub mod inspect;
pub mod kernel;
pub mod kernels;
pub mod one_group;
pub mod rank_exchange;
mod rank_step;
pub mod rank_surface;
pub mod resident_step;
pub mod scan;
pub mod search;
pub mod shaders;
pub mod stable_step;
mod submission_clock;
pub mod surface_step;
pub mod types;

pub use contact_form::ContactForm;
pub use context::{close_devices, list_adapters, AdapterPolicy, AdapterSummary, GpuContext};
pub use corner_select::CornerSelection;
pub use engine::GpuKernels;
pub use impulse_sweeps::{ContactSetup, ImpulseSweeps};
pub use kernels::*;
pub use rank_exchange::RankExchange;
pub use resident_step::{ResidentSetup, ResidentStep};
pub use search::GpuSearch;
pub use stable_step::element_steps;
pub use surface_step::SurfaceStep;
