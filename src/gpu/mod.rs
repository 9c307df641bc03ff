//! The GPU engine: wgpu context and adapter choice ([`context`]), one host module per WGSL
//! kernel (same name as `shaders/<name>.wgsl` and as its CPU twin in [`crate::kernels`]),
//! the Pod buffer types ([`types`]) and [`GpuKernels`], the [`crate::backend::Kernels`]
//! interface on a device.

pub mod bucket_count;
pub mod bucket_fill;
pub mod bucket_order;
pub mod buffer;
pub mod contact_apply;
pub mod contact_compliance;
pub mod contact_constraints;
pub mod contact_gap;
pub mod contact_iteration;
pub mod contact_report;
pub mod contact_search;
pub mod contact_sweep;
pub mod contact_touches;
pub mod context;
pub mod engine;
pub mod explicit_correct;
pub mod explicit_drift;
pub mod explicit_predict;
pub mod explicit_step;
pub mod face_cells;
pub mod hex8_forces;
pub mod history_reduce;
pub mod kernel;
pub mod node_gather;
pub mod plane_contact;
pub mod prefix_sum;
pub mod search;
pub mod search_bounds;
pub mod search_grid;
pub mod shaders;
pub mod slip_rate;
pub mod stable_step;
pub mod sweep_control;
pub mod tet4_forces;
pub mod types;

pub use bucket_count::BucketCount;
pub use bucket_fill::BucketFill;
pub use contact_gap::ContactGap;
pub use contact_iteration::{ContactIteration, ContactSetup};
pub use contact_search::ContactSearch;
pub use context::{list_adapters, AdapterPolicy, AdapterSummary, GpuContext};
pub use engine::{GpuKernels, KernelId};
pub use explicit_correct::ExplicitCorrect;
pub use explicit_drift::ExplicitDrift;
pub use explicit_predict::ExplicitPredict;
pub use explicit_step::{ResidentExplicit, ResidentSetup, Stage};
pub use face_cells::FaceCells;
pub use hex8_forces::Hex8Forces;
pub use history_reduce::HistoryReduce;
pub use node_gather::NodeGather;
pub use plane_contact::PlaneContact;
pub use prefix_sum::PrefixSum;
pub use search::GpuSearch;
pub use slip_rate::SlipRate;
pub use stable_step::{element_steps, StableStep};
pub use tet4_forces::Tet4Forces;
