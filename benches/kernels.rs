//! Throughput of each kernel on the GPU adapter in use and of its CPU f64 twin, from 10^3 to
//! 10^6 hex8 elements: ns per element (hex8_forces, node_gather) and ns per contact node
//! (contact_gap, slip_rate), with the effective bandwidth of each GPU kernel against the
//! adapter's buffer-copy bandwidth. Prints a Markdown table.
//!
//! `cargo bench --bench kernels` (add `-- --quick` to stop at 10^5 elements). On a hardware GPU
//! (or with `-- --large`) a 10^7-element row follows, its CPU twins not timed (seconds a
//! call).

use std::time::Instant;

use impact::element::ElementKind::{self, Hex8, Hex8i};
use impact::element::Elements;
use impact::gpu::inspect::KernelId;
use impact::gpu::{GpuContext, GpuKernels};
use impact::kernels::{self, ContactPoint, ContactQueries, ElementData, Incidence, KeptData};
use impact::material::Elastic;
use impact::mesh::box_mesh::box_mesh;
use impact::scene::{BoxElement, BoxFace, BoxSpec};

/// Bytes each kernel moves per item, counting every distinct value once (a node's data is
/// shared by about 8 elements, so per element about one node's worth is read).
const HEX8_BYTES: f64 = 36.0 + 24.0 + 24.0 + 96.0; // connectivity and material, reference, u, corner forces
                                                   // connectivity, the kept stiffness and centre gradients, reference, u, corner forces
const HEX8I_BYTES: f64 = 32.0 + 4.0 * 324.0 + 24.0 + 24.0 + 96.0;
const GATHER_BYTES: f64 = 4.0 + 32.0 + 96.0 + 12.0; // offsets, incidence, corners, forces (per element)
const GAP_BYTES: f64 = 12.0 + 16.0 + 4.0 * 4.0 + 48.0 + 12.0 + 32.0; // query, candidates, faces, nodes, v, point
const SLIP_BYTES: f64 = 12.0 + 16.0 + 32.0 + 48.0 + 12.0 + 8.0;

fn problem(div: [usize; 3]) -> (ElementData, ContactQueries) {
    let spec = BoxSpec {
        min: [0.0; 3],
        max: div.map(|d| d as f64),
        divisions: div,
        element: BoxElement::Hex8,
        refine: None,
    };
    let parts = box_mesh(&spec);
    let top: Vec<[u32; 4]> = (parts.surfaces[BoxFace::ZPlus as usize].faces.iter())
        .map(|f| f.slots())
        .collect();
    let (nodes, elements) = (parts.nodes, parts.elements);
    // every top-face node against the top faces around it
    let mut around: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for (f, q) in top.iter().enumerate() {
        for &n in q {
            around.entry(n).or_default().push(f as u32);
        }
    }
    let mut q = ContactQueries {
        faces: top,
        offsets: vec![0],
        ..Default::default()
    };
    for (n, fs) in around {
        q.secondary.push(n);
        q.candidates.extend(fs);
        q.offsets.push(q.candidates.len() as u32);
    }
    let data = ElementData {
        reference: nodes,
        elements,
        materials: vec![Elastic::from_engineering(100.0, 0.3, 1.0)],
        layups: Vec::new(),
    };
    (data, q)
}

/// Seconds per call of `f`, repeated until about `budget` seconds have passed.
fn per_call(budget: f64, f: &mut dyn FnMut()) -> f64 {
    let t = Instant::now();
    f();
    let first = t.elapsed().as_secs_f64();
    let reps = ((budget / first.max(1e-9)) as usize).clamp(1, 50);
    let t = Instant::now();
    for _ in 0..reps {
        f();
    }
    t.elapsed().as_secs_f64() / reps as f64
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let large = std::env::args().any(|a| a == "--large");
    let ctx = GpuContext::new().expect("a GPU adapter (see `impact info`)");
    let mut sizes = vec![[10, 10, 10], [22, 22, 21], [47, 47, 46]];
    if !quick {
        sizes.push([100, 100, 100]);
    }
    if (!quick && !ctx.adapter.software) || large {
        sizes.push([216, 216, 216]);
    }
    let adapter = ctx.adapter.describe();
    println!("adapter: {adapter}");
    println!();
    println!("| elements | contact nodes | kernel | GPU ns/item | CPU twin ns/item | GPU GB/s | % of copy |");
    println!("|---:|---:|---|---:|---:|---:|---:|");
    let mut ctx = Some(ctx);
    for &div in &sizes {
        let (data, q) = problem(div);
        let (ne, nn, nq) = (data.elements.count(), data.reference.len(), q.len());
        let u: Vec<f64> = (0..3 * nn).map(|d| 1e-3 * ((d % 7) as f64 - 3.0)).collect();
        let v: Vec<f64> = (0..3 * nn).map(|d| ((d % 5) as f64 - 2.0) * 0.1).collect();
        // the context is moved into the engine; get it back for the next size by reopening
        let ctx_now = ctx
            .take()
            .unwrap_or_else(|| GpuContext::new().expect("adapter"));
        let mut gpu = GpuKernels::new(ctx_now, &data).expect("engine");
        let copy = gpu.copy_bandwidth(256 << 20, 20).expect("copy");
        // upload u, v and the queries once, then time dispatches alone
        let mut f = vec![0.0; 3 * nn];
        use impact::backend::Kernels;
        gpu.internal_forces_into(&u, &mut f).expect("forces");
        let mut pts = vec![ContactPoint::default(); nq];
        gpu.contact_gap_into(&u, &v, &q, &mut pts).expect("gap");
        let mut slip = vec![[0.0; 2]; nq];
        gpu.slip_rate_into(&u, &v, &q, &pts, &mut slip)
            .expect("slip");
        let gpu_time = |gpu: &mut GpuKernels, k| {
            let one = gpu.time_kernel(k, 1).expect("time").as_secs_f64();
            let reps = ((0.3 / one.max(1e-7)) as usize).clamp(2, 200);
            // the same run once first: a GPU that was idle runs at a low clock
            gpu.time_kernel(k, reps).expect("warm-up");
            gpu.time_kernel(k, reps).expect("time").as_secs_f64() / reps as f64
        };
        // CPU twins (not above 10^6 elements: seconds a call)
        let twins = ne <= 2_000_000;
        let inc = Incidence::new(&data.elements, nn);
        let mut corners = vec![[0.0; 3]; 8 * ne];
        let mut nodal = vec![[0.0; 3]; nn];
        let uu = kernels::as_vec3(&u);
        let vv = kernels::as_vec3(&v);
        let twin = |budget, f: &mut dyn FnMut()| twins.then(|| per_call(budget, f));
        let c_hex = twin(0.3, &mut || kernels::hex8_forces(&data, uu, &mut corners));
        let c_gather = twin(0.3, &mut || {
            kernels::node_gather(&inc, &corners, &mut nodal)
        });
        let mut cpts = vec![ContactPoint::default(); nq];
        let c_gap = twin(0.2, &mut || {
            kernels::contact_gap(&data.reference, uu, vv, &q, &mut cpts)
        });
        let mut cslip = vec![[0.0; 2]; nq];
        let c_slip = twin(0.2, &mut || {
            kernels::slip_rate(&data.reference, uu, vv, &q, &cpts, &mut cslip)
        });
        let rows = [
            ("hex8_forces", KernelId::Forces(Hex8), ne, c_hex, HEX8_BYTES),
            (
                "node_gather",
                KernelId::NodeGather,
                ne,
                c_gather,
                GATHER_BYTES,
            ),
            ("contact_gap", KernelId::ContactGap, nq, c_gap, GAP_BYTES),
            ("slip_rate", KernelId::SlipRate, nq, c_slip, SLIP_BYTES),
        ];
        // the same box of hex8i, on an engine of its own
        let data_i = ElementData {
            elements: as_kind(&data.elements, Hex8i),
            ..data.clone()
        };
        let kept = KeptData::of(&data_i);
        let mut gpu_i = GpuKernels::new(gpu.context().clone(), &data_i).expect("engine");
        gpu_i.internal_forces_into(&u, &mut f).expect("forces");
        let c_hex8i = twin(0.3, &mut || {
            kernels::hex8i_forces(&data_i, kept.of_kind(Hex8i), uu, &mut corners)
        });
        let g_hex8i = gpu_time(&mut gpu_i, KernelId::Forces(Hex8i));
        for (name, id, items, cpu, bytes) in rows {
            let g = gpu_time(&mut gpu, id);
            let bw = bytes * items as f64 / g;
            let cpu = cpu.map_or("-".into(), |c| format!("{:.2}", c * 1e9 / items as f64));
            println!(
                "| {ne} | {nq} | {name} | {:.2} | {cpu} | {:.2} | {:.0}% |",
                g * 1e9 / items as f64,
                bw * 1e-9,
                100.0 * bw / copy
            );
        }
        let cpu = c_hex8i.map_or("-".into(), |c| format!("{:.2}", c * 1e9 / ne as f64));
        let bw = HEX8I_BYTES * ne as f64 / g_hex8i;
        println!(
            "| {ne} | {nq} | hex8i_forces | {:.2} | {cpu} | {:.2} | {:.0}% |",
            g_hex8i * 1e9 / ne as f64,
            bw * 1e-9,
            100.0 * bw / copy
        );
        println!(
            "| {ne} | {nq} | (buffer copy) | | | {:.2} | 100% |",
            copy * 1e-9
        );
    }
}

/// The same elements as one block of `kind` (of the same corner count).
fn as_kind(elements: &Elements, kind: ElementKind) -> Elements {
    let mut out = Elements::default();
    for e in elements.iter() {
        out.push(kind, e.nodes, e.material);
    }
    out
}
