//! The lanes of the kernels that run in one workgroup (`contact_zone` and
//! `contact_finish`: `ONE_GROUP` in `shaders/include/sweep_loop.wgsl`). Their sweeps are
//! bound by each lane's chain of dependent reads, so a wider workgroup runs a sweep in
//! fewer rounds on the one multiprocessor it occupies; but a wider workgroup also leaves
//! each lane fewer registers (on NVIDIA 64 at 1,024 lanes, against 255 at 256), and a
//! kernel past that spills into local memory. The shaders are written for [`ONE_GROUP`]
//! lanes, which the runs start with ([`super::GpuContext::zone_lanes`]); the pipelines can
//! be built with up to [`WIDEST`] where the adapter allows (the explicit bench's
//! `--lanes`), and on hardware adapters the run's trial of the contact iteration's forms
//! times `contact_zone` at 512 and 1,024 lanes too ([`trial_widths`]), so each card takes
//! the width it runs fastest. Every sum those kernels take is over a fixed order that does not
//! depend on the lanes (a maximum, an integer count, per-item gathers, the rigid bodies'
//! 64-lane trees), so the results are the same bits at any width.

/// The lanes the shader files declare.
pub const ONE_GROUP: u32 = 256;

/// The most lanes the pipelines are built with.
pub const WIDEST: u32 = 1024;

/// The shader files' declaration of the lanes, which [`with_lanes`] replaces.
const DECLARATION: &str = "const ONE_GROUP: u32 = 256u;";

/// Bytes of workgroup memory the one-workgroup kernels take at `lanes` lanes: two words
/// per lane (the sweeps' violations, the scan's sums), the rigid bodies' 64 parts (16 bytes
/// each) and a few words.
pub fn workgroup_bytes(lanes: u32) -> u32 {
    8 * lanes + 16 * 64 + 64
}

/// The widths of `contact_zone` the run's trial times besides `lanes` (the run's width):
/// none on a software adapter, where a workgroup runs on one core whatever its width (the
/// bench's plate rows on lavapipe stay within their spread from 256 to 1,024 lanes), and
/// 512 and 1,024 where `limits` allow on a hardware one.
pub fn trial_widths(limits: &wgpu::Limits, software: bool, lanes: u32) -> Vec<u32> {
    let mut widths: Vec<u32> = [ONE_GROUP, 512, WIDEST]
        .into_iter()
        .filter(|&w| !software && within(limits, w) == w && w != lanes)
        .collect();
    widths.dedup();
    widths
}

/// The widest power of two from [`ONE_GROUP`] to [`WIDEST`] lanes that `limits` allow.
pub fn widest(limits: &wgpu::Limits) -> u32 {
    within(limits, WIDEST)
}

/// The widest power of two from [`ONE_GROUP`] to `lanes` that `limits` allow.
pub fn within(limits: &wgpu::Limits, lanes: u32) -> u32 {
    let mut lanes = lanes
        .clamp(ONE_GROUP, WIDEST)
        .next_power_of_two()
        .min(WIDEST);
    while lanes > ONE_GROUP
        && (lanes > limits.max_compute_invocations_per_workgroup
            || lanes > limits.max_compute_workgroup_size_x
            || workgroup_bytes(lanes) > limits.max_compute_workgroup_storage_size)
    {
        lanes /= 2;
    }
    lanes
}

/// `source` (an assembled kernel that declares [`ONE_GROUP`] lanes) built for `lanes`.
pub fn with_lanes(source: &str, lanes: u32) -> String {
    assert!(
        source.contains(DECLARATION),
        "a one-workgroup kernel declares {DECLARATION}"
    );
    source.replace(DECLARATION, &format!("const ONE_GROUP: u32 = {lanes}u;"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_widest_allowed_width_up_to_the_one_asked_for_is_chosen() {
        let mut l = wgpu::Limits::default();
        // WebGPU's defaults: 256 invocations, 16 KiB of workgroup memory
        assert_eq!(widest(&l), 256);
        l.max_compute_invocations_per_workgroup = 1024;
        l.max_compute_workgroup_size_x = 1024;
        assert_eq!(widest(&l), 1024);
        assert_eq!(within(&l, 512), 512);
        assert_eq!(within(&l, 300), 512);
        assert_eq!(within(&l, 64), 256);
        l.max_compute_workgroup_storage_size = workgroup_bytes(1024) - 1;
        assert_eq!(widest(&l), 512);
        l.max_compute_workgroup_size_x = 256;
        assert_eq!(widest(&l), 256);
    }

    #[test]
    fn the_trial_takes_the_other_allowed_widths_on_hardware_alone() {
        let mut l = wgpu::Limits::default();
        assert!(trial_widths(&l, false, 256).is_empty());
        l.max_compute_invocations_per_workgroup = 1024;
        l.max_compute_workgroup_size_x = 1024;
        assert_eq!(trial_widths(&l, false, 256), [512, 1024]);
        assert_eq!(trial_widths(&l, false, 1024), [256, 512]);
        assert!(trial_widths(&l, true, 256).is_empty());
        l.max_compute_workgroup_storage_size = workgroup_bytes(1024) - 1;
        assert_eq!(trial_widths(&l, false, 256), [512]);
    }

    #[test]
    fn the_declaration_is_replaced_once() {
        for name in ["contact_zone", "contact_finish"] {
            let source = crate::gpu::shaders::source(name);
            assert_eq!(source.matches(DECLARATION).count(), 1, "{name}");
            let wide = with_lanes(source, 1024);
            assert!(wide.contains("const ONE_GROUP: u32 = 1024u;"));
            assert!(!wide.contains(DECLARATION));
        }
    }
}
