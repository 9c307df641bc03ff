//! Every WGSL kernel against its CPU f64 twin on random distorted meshes (nodes jittered by up
//! to 20% of the element size, a large rigid offset so that f32 precision is tested, sizes
//! that are not multiples of the workgroup size), with the outputs filled with NaN before
//! each dispatch so that an unwritten entry fails. Tolerance: relative error <= 1e-5 in the
//! 2-norm. Fresh random inputs each run; the seed is printed.

mod common;
use common::*;

use impact::backend::Kernels;
use impact::element::ElementKind::{Hex8, Hex8i, Tet4};
use impact::element::Elements;
use impact::geometry::face::FaceKind;
use impact::gpu::{CornerSelection, GpuKernels, RankExchange};
use impact::kernels::contact_gap::NO_FACE;
use impact::kernels::{self, ContactPoint, ContactQueries, ElementData, Incidence};
use impact::material::{Elastic, Orthotropic, Rotation};
use impact::mesh::box_mesh::KUHN_TETS;
use impact::mesh::Face;
use impact::scene::BoxFace;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

const TOL: f64 = 1e-5;

/// A distorted box mesh, some of its hexes split into six tets each (so every kernel sees a
/// mixed mesh), its top faces (a third of the quads cut into two triangles, so
/// the contact kernels see both kinds of face), and the element size.
struct Problem {
    data: ElementData,
    top: Vec<[u32; 4]>,
    h: f64,
}

fn distorted_box(rng: &mut StdRng) -> Problem {
    let divisions = [
        rng.random_range(3..=14),
        rng.random_range(2..=9),
        rng.random_range(2..=6),
    ];
    let h = JITTER_H;
    let parts = jittered_box(rng, divisions);
    let nodes = parts.nodes;
    // six tets around the diagonal 0-6 of a hex (the Kuhn cut of tet4 boxes), for a third
    // of the hexes
    let mut elements = Elements::default();
    for hx in parts.elements.block(Hex8).corners::<8>() {
        if rng.random_range(0..3) == 0 {
            for t in KUHN_TETS.map(|t| t.map(|k| hx[k])) {
                elements.push(Tet4, &t, 0);
            }
        } else {
            elements.push(Hex8, hx, 0);
        }
    }
    impact::mesh::boundary::orient(&nodes, &mut elements).expect("valid elements");
    for block in &mut elements.blocks {
        block
            .material
            .iter_mut()
            .for_each(|m| *m = rng.random_range(0..3));
    }
    let materials = vec![
        Elastic::from_engineering(100.0, 0.3, 1.0),
        Elastic::from_engineering(2.5e3, 0.45, 7.8),
        random_laminate(rng),
    ];
    Problem {
        data: ElementData {
            reference: nodes,
            elements,
            materials,
            layups: Vec::new(),
        },
        top: parts.surfaces[BoxFace::ZPlus as usize]
            .faces
            .iter()
            .flat_map(|f| {
                let q = f.corners();
                if rng.random_range(0..3) == 0 {
                    vec![
                        Face::Triangle([q[0], q[1], q[2]]).slots(),
                        Face::Triangle([q[0], q[2], q[3]]).slots(),
                    ]
                } else {
                    vec![f.slots()]
                }
            })
            .collect(),
        h,
    }
}

/// A transversely isotropic material (fibre to matrix stiffness 5 to 40) with its axes
/// turned at random: every entry of its stiffness is nonzero.
fn random_laminate(rng: &mut StdRng) -> Elastic {
    let e2 = rng.random_range(5.0..20.0);
    let t = Orthotropic::transversely_isotropic(
        e2 * rng.random_range(5.0..40.0),
        e2,
        rng.random_range(0.2..0.35),
        rng.random_range(0.3..0.5),
        e2 * rng.random_range(0.3..0.7),
    );
    assert_eq!(t.indefinite(), None);
    let mut v = || std::array::from_fn(|_| rng.random_range(-1.0..1.0));
    let axes = Rotation::from_axes(v(), v()).expect("random axes span a plane");
    Elastic::anisotropic(t.stiffness(), 1.6).rotated(&axes)
}

/// Displacements: a rigid translation of several element sizes plus a random part.
fn displacements(rng: &mut StdRng, nodes: usize, h: f64) -> Vec<f64> {
    let rigid = [3.7 * h, -2.2 * h, 1.3 * h];
    (0..3 * nodes)
        .map(|d| rigid[d % 3] + rng.random_range(-0.05..0.05) * h)
        .collect()
}

fn velocities(rng: &mut StdRng, nodes: usize) -> Vec<f64> {
    (0..3 * nodes)
        .map(|_| rng.random_range(-1.0..1.0))
        .collect()
}

/// The values of an iterator, for [`rel_err`].
fn values(it: impl Iterator<Item = f64>) -> Vec<f64> {
    it.collect()
}

fn flat(v: &[[f64; 3]]) -> impl Iterator<Item = f64> + '_ {
    v.iter().flatten().copied()
}

#[test]
fn hex8_forces_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("hex8_forces") else {
        return;
    };
    let seed = seed("hex8_forces");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let hex_corners = 8 * p.data.elements.count_of(Hex8);
    for round in 0..3 {
        let u = displacements(&mut rng, n, p.h);
        let mut cpu = vec![[0.0; 3]; hex_corners];
        kernels::hex8_forces(&p.data, kernels::as_vec3(&u), &mut cpu);
        let g = gpu.corner_forces(&u).expect("dispatch");
        let e = rel_err(&values(flat(&g[..hex_corners])), &values(flat(&cpu)));
        eprintln!(
            "round {round}: {} elements, relative error {e:.2e}",
            p.data.elements.count_of(Hex8)
        );
        assert!(
            e <= TOL,
            "seed {seed}: hex8_forces error {e:.3e} > {TOL:.0e}"
        );
    }
}

/// The distorted box with its hex8s as hex8i (the tets kept): every block's force kernel on
/// the device against the CPU twins, the whole corner array in the twin's order.
#[test]
fn hex8i_forces_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("hex8i_forces") else {
        return;
    };
    let seed = seed("hex8i_forces");
    let mut rng = StdRng::seed_from_u64(seed);
    let mut p = distorted_box(&mut rng);
    let hexes = std::mem::replace(
        p.data.elements.block_mut(Hex8),
        impact::element::ElementBlock::new(Hex8),
    );
    *p.data.elements.block_mut(Hex8i) = impact::element::ElementBlock {
        kind: Hex8i,
        ..hexes
    };
    let n = p.data.reference.len();
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let mut cpu = impact::backend::CpuKernels::new(p.data.clone());
    let mut f = vec![0.0; 3 * n];
    for round in 0..3 {
        let u = displacements(&mut rng, n, p.h);
        cpu.internal_forces_into(&u, &mut f).expect("twin");
        let g = gpu.corner_forces(&u).expect("dispatch");
        let e = rel_err(&values(flat(&g)), &values(flat(cpu.corner_forces())));
        eprintln!(
            "round {round}: {} hex8i and {} tet4, relative error {e:.2e}",
            p.data.elements.count_of(Hex8i),
            p.data.elements.count_of(Tet4)
        );
        assert!(
            e <= TOL,
            "seed {seed}: hex8i_forces error {e:.3e} > {TOL:.0e}"
        );
    }
}

#[test]
fn tet4_forces_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("tet4_forces") else {
        return;
    };
    let seed = seed("tet4_forces");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let hex_corners = 8 * p.data.elements.count_of(Hex8);
    for round in 0..3 {
        let u = displacements(&mut rng, n, p.h);
        let mut cpu = vec![[0.0; 3]; 4 * p.data.elements.count_of(Tet4)];
        kernels::tet4_forces(&p.data, kernels::as_vec3(&u), &mut cpu);
        let g = gpu.corner_forces(&u).expect("dispatch");
        assert_eq!(g.len(), hex_corners + cpu.len());
        let e = rel_err(&values(flat(&g[hex_corners..])), &values(flat(&cpu)));
        eprintln!(
            "round {round}: {} tets, relative error {e:.2e}",
            p.data.elements.count_of(Tet4)
        );
        assert!(
            e <= TOL,
            "seed {seed}: tet4_forces error {e:.3e} > {TOL:.0e}"
        );
    }
}

/// `fill_words` sets the first `count` words of random buffers and leaves the rest: exact.
#[test]
fn fill_words_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("fill_words") else {
        return;
    };
    let seed = seed("fill_words");
    let mut rng = StdRng::seed_from_u64(seed);
    for _ in 0..4 {
        let len = rng.random_range(1..5000usize);
        let words: Vec<u32> = (0..len).map(|_| rng.random()).collect();
        let count = rng.random_range(0..=len);
        let value = rng.random_range(0..3u32);
        let gpu = impact::gpu::inspect::run_fill_words(&ctx, &words, count as u32, value)
            .expect("fill_words runs");
        let mut cpu = words.clone();
        kernels::fill_words(&mut cpu, count, value);
        assert_eq!(
            gpu, cpu,
            "seed {seed}: {count} of {len} words set to {value}"
        );
    }
}

/// The device's prefix sum (`scan_totals`, then `prefix_sum`, a workgroup per block of 1024
/// values) on random bucket sizes, from an empty table to hundreds of blocks with a partial
/// last one: the starts and the block totals exact.
#[test]
fn prefix_sum_and_scan_totals_match_their_cpu_twins() {
    let Some(ctx) = gpu_context("prefix_sum") else {
        return;
    };
    let seed = seed("prefix_sum");
    let mut rng = StdRng::seed_from_u64(seed);
    let many = rng.random_range(2000..300_000usize);
    for len in [0, 1, 5, 1024, 1025, 4096, many] {
        let values: Vec<u32> = (0..len).map(|_| rng.random_range(0..4u32)).collect();
        let (starts, totals) =
            impact::gpu::inspect::run_prefix_sum(&ctx, &values).expect("prefix_sum runs");
        assert_eq!(
            starts,
            kernels::prefix_sum(&values),
            "seed {seed}: {len} values"
        );
        if len > kernels::SCAN_BLOCK {
            assert_eq!(
                totals,
                kernels::scan_totals(&values),
                "seed {seed}: {len} totals"
            );
        }
    }
}

#[test]
fn node_gather_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("node_gather") else {
        return;
    };
    let seed = seed("node_gather");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let inc = Incidence::new(&p.data.elements, n);
    let corners: Vec<[f64; 3]> = (0..p.data.corner_count())
        .map(|_| std::array::from_fn(|_| rng.random_range(-1.0..1.0)))
        .collect();
    let mut cpu = vec![[0.0; 3]; n];
    kernels::node_gather(&inc, &corners, &mut cpu);
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let g = gpu.gather(&corners).expect("dispatch");
    let e = rel_err(&values(flat(&g)), &values(flat(&cpu)));
    eprintln!("{n} nodes, relative error {e:.2e}");
    assert!(e <= TOL, "seed {seed}: node_gather error {e:.3e}");
}

#[test]
fn corner_select_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("corner_select") else {
        return;
    };
    let seed = seed("corner_select");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let count = p.data.corner_count();
    let corners: Vec<[f64; 3]> = (0..count)
        .map(|_| std::array::from_fn(|_| rng.random_range(-1.0..1.0)))
        .collect();
    // hex8 and tet4 corners, some twice, in no order
    let chosen: Vec<u32> = (0..count / 3)
        .map(|_| rng.random_range(0..count as u32))
        .collect();
    let mut cpu = vec![[0.0; 3]; chosen.len()];
    kernels::corner_select(&corners, &chosen, &mut cpu);
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let selection = CornerSelection::new(&gpu, &chosen).expect("selection");
    let g = gpu.select(&corners, &selection).expect("dispatch");
    let e = rel_err(&values(flat(&g)), &values(flat(&cpu)));
    eprintln!(
        "{} of {count} corners, relative error {e:.2e}",
        chosen.len()
    );
    assert!(e <= TOL, "seed {seed}: corner_select error {e:.3e}");
}

/// The shared nodes' sums written over random nodal forces: the shared nodes (in no order)
/// take their sums, every other node keeps its force.
#[test]
fn node_scatter_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("node_scatter") else {
        return;
    };
    let seed = seed("node_scatter");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let mut shared: Vec<u32> = (0..n as u32).filter(|_| rng.random_bool(0.3)).collect();
    shared.reverse();
    let forces: Vec<f64> = (0..3 * n).map(|_| rng.random_range(-1.0..1.0)).collect();
    let sums: Vec<[f64; 3]> = (0..shared.len())
        .map(|_| std::array::from_fn(|_| rng.random_range(-1.0..1.0)))
        .collect();
    let mut cpu = forces.clone();
    kernels::node_scatter(&shared, &sums, &mut cpu);
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    let exchange = RankExchange::new(&gpu, &[], &shared).expect("exchange");
    let g = gpu
        .node_scatter(&exchange, &forces, &sums)
        .expect("dispatch");
    let e = rel_err(&g, &cpu);
    eprintln!(
        "{} of {n} nodes shared, relative error {e:.2e}",
        shared.len()
    );
    assert!(e <= TOL, "seed {seed}: node_scatter error {e:.3e}");
    let kept = (0..n).filter(|i| !shared.contains(&(*i as u32)));
    assert!(kept.clone().count() > 0 && !shared.is_empty());
    for i in kept {
        for a in 0..3 {
            assert_eq!(
                g[3 * i + a],
                forces[3 * i + a] as f32 as f64,
                "node {i} kept"
            );
        }
    }
}

/// The state of listed nodes packed: random displacements (packed as split pairs, hi + lo)
/// and velocities of a random subset of the nodes, in no order, against the twin.
#[test]
fn node_select_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("node_select") else {
        return;
    };
    let seed = seed("node_select");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let mut owned: Vec<u32> = (0..n as u32).filter(|_| rng.random_bool(0.4)).collect();
    owned.reverse();
    let u = displacements(&mut rng, n, p.h);
    let v: Vec<f64> = (0..3 * n).map(|_| rng.random_range(-3.0..3.0)).collect();
    let (mut cu, mut cv) = (vec![0.0; 3 * owned.len()], vec![0.0; 3 * owned.len()]);
    kernels::node_select(&owned, 3, &u, &mut cu);
    kernels::node_select(&owned, 3, &v, &mut cv);
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    let (gu, gv) = gpu.node_select(&owned, &u, &v).expect("dispatch");
    let (eu, ev) = (rel_err(&gu, &cu), rel_err(&gv, &cv));
    eprintln!(
        "{} of {n} nodes, relative errors u {eu:.2e}, v {ev:.2e}",
        owned.len()
    );
    assert!(!owned.is_empty());
    assert!(
        eu <= 1e-12 && ev <= TOL,
        "seed {seed}: node_select errors {eu:.3e} {ev:.3e}"
    );
}

/// The forces with chosen corners read back alongside: the nodal forces are those of
/// `internal_forces_into`, bit for bit, and the corners those of the CPU kernels.
#[test]
fn internal_forces_selecting_reads_back_the_chosen_corners() {
    let Some(ctx) = gpu_context("internal_forces_selecting") else {
        return;
    };
    let seed = seed("internal_forces_selecting");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let (n, count) = (p.data.reference.len(), p.data.corner_count());
    let u = displacements(&mut rng, n, p.h);
    let chosen: Vec<u32> = (0..count as u32).filter(|_| rng.random_bool(0.3)).collect();
    let mut cpu = impact::backend::CpuKernels::new(p.data.clone());
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let selection = CornerSelection::new(&gpu, &chosen).expect("selection");
    let (mut fc, mut fg, mut fs) = (vec![0.0; 3 * n], vec![0.0; 3 * n], vec![0.0; 3 * n]);
    let mut picked = Vec::new();
    cpu.internal_forces_into(&u, &mut fc).unwrap();
    // the selecting path first, on buffers filled with NaN: each of its stages must run
    gpu.internal_forces_selecting(&u, &mut fs, &selection, &mut picked)
        .unwrap();
    gpu.internal_forces_into(&u, &mut fg).unwrap();
    assert!(fg.iter().zip(&fs).all(|(a, b)| a.to_bits() == b.to_bits()));
    let mut want = vec![[0.0; 3]; chosen.len()];
    kernels::corner_select(cpu.corner_forces(), &chosen, &mut want);
    let got: Vec<[f64; 3]> = picked.iter().map(|c| c.map(f64::from)).collect();
    let e = rel_err(&values(flat(&got)), &values(flat(&want)));
    eprintln!(
        "{} of {count} corners, relative error {e:.2e}",
        chosen.len()
    );
    assert!(e <= TOL, "seed {seed}: chosen corners error {e:.3e}");
}

/// Internal forces through the `Kernels` interface (hex8_forces, tet4_forces, node_gather).
#[test]
fn internal_forces_match_the_cpu_kernels() {
    let Some(ctx) = gpu_context("internal_forces") else {
        return;
    };
    let seed = seed("internal_forces");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let n = p.data.reference.len();
    let u = displacements(&mut rng, n, p.h);
    let mut cpu = impact::backend::CpuKernels::new(p.data.clone());
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let (mut fc, mut fg) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
    cpu.internal_forces_into(&u, &mut fc).unwrap();
    gpu.internal_forces_into(&u, &mut fg).unwrap();
    let e = rel_err(&values(fg.iter().copied()), &values(fc.iter().copied()));
    eprintln!("{n} nodes, relative error {e:.2e}");
    assert!(e <= TOL, "seed {seed}: internal forces error {e:.3e}");
}

/// Secondary nodes near the top surface: extra nodes appended to the mesh, each with its
/// candidate faces. Kinds: over a face with its neighbours as candidates (Newton inside the
/// square, or inside the triangle); anywhere within 1.5 face sizes of a single candidate
/// (the edge/corner fallback); no candidate at all.
fn contact_problem(rng: &mut StdRng, p: &mut Problem, count: usize) -> ContactQueries {
    let first_extra = p.data.reference.len();
    let mut q = ContactQueries {
        faces: p.top.clone(),
        offsets: vec![0],
        ..Default::default()
    };
    for i in 0..count {
        let f = rng.random_range(0..p.top.len());
        let corners = p.top[f].map(|n| p.data.reference[n as usize]);
        let centre: [f64; 3] =
            std::array::from_fn(|a| corners.iter().map(|c| c[a]).sum::<f64>() / 4.0);
        let (x, cands): ([f64; 3], Vec<u32>) = match i % 3 {
            0 => {
                let kind = FaceKind::of(&p.top[f]);
                let xi = match kind {
                    FaceKind::Quad => [rng.random_range(-0.9..0.9), rng.random_range(-0.9..0.9)],
                    FaceKind::Triangle => {
                        let a = rng.random_range(0.05..0.9);
                        [a, rng.random_range(0.05..0.95 - a)]
                    }
                };
                let (y, ..) = kind.geometry(&corners, xi);
                let nrm = kind.normal(&corners, xi);
                let s = rng.random_range(-0.15..0.15) * p.h;
                let near: Vec<u32> = (0..p.top.len() as u32)
                    .filter(|&g| p.top[g as usize].iter().any(|n| p.top[f].contains(n)))
                    .collect();
                (std::array::from_fn(|a| y[a] + s * nrm[a]), near)
            }
            1 => (
                std::array::from_fn(|a| centre[a] + rng.random_range(-1.5..1.5) * p.h),
                vec![f as u32],
            ),
            _ => (centre, vec![]),
        };
        p.data.reference.push(x);
        q.secondary.push((first_extra + i) as u32);
        q.candidates.extend(cands);
        q.offsets.push(q.candidates.len() as u32);
    }
    q
}

/// Distance from the secondary node to the closest point of a face (CPU, f64).
fn face_distance(x: [f64; 3], face: &[u32; 4], corners: &[[f64; 3]; 4]) -> f64 {
    use impact::geometry::vector::{norm, sub};
    let kind = FaceKind::of(face);
    let xi = kind.project(corners, x);
    let (y, ..) = kind.geometry(corners, xi);
    norm(sub(x, y))
}

#[test]
fn contact_gap_and_slip_rate_match_their_cpu_twins() {
    let Some(ctx) = gpu_context("contact_gap") else {
        return;
    };
    let seed = seed("contact_gap");
    let mut rng = StdRng::seed_from_u64(seed);
    let mut p = distorted_box(&mut rng);
    // 3 * 67 + 2 queries: not a multiple of the workgroup size
    let q = contact_problem(&mut rng, &mut p, 203);
    let n = p.data.reference.len();
    let u = displacements(&mut rng, n, p.h);
    let v = velocities(&mut rng, n);
    let mut cpu_pts = vec![ContactPoint::default(); q.len()];
    kernels::contact_gap(
        &p.data.reference,
        kernels::as_vec3(&u),
        kernels::as_vec3(&v),
        &q,
        &mut cpu_pts,
    );
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    gpu.fill_nan = true;
    let mut gpu_pts = vec![ContactPoint::default(); q.len()];
    gpu.contact_gap_into(&u, &v, &q, &mut gpu_pts).unwrap();

    // the same face, except where two candidates are equally close (a point over a shared
    // edge): then the distances must agree
    let pos = |nd: u32| -> [f64; 3] {
        let (x, d) = (p.data.reference[nd as usize], &u[3 * nd as usize..]);
        [x[0] + d[0], x[1] + d[1], x[2] + d[2]]
    };
    let mut same = Vec::new();
    let mut ties = 0;
    for i in 0..q.len() {
        let (c, g) = (cpu_pts[i], gpu_pts[i]);
        if c.face == g.face {
            same.push(i);
            continue;
        }
        assert!(
            c.face != NO_FACE && g.face != NO_FACE && (g.face as usize) < q.faces.len(),
            "seed {seed}: query {i}: cpu face {} gpu face {} (unwritten or wrong)",
            c.face,
            g.face
        );
        let x = pos(q.secondary[i]);
        let (fc, fg) = (q.faces[c.face as usize], q.faces[g.face as usize]);
        let dc = face_distance(x, &fc, &fc.map(pos));
        let dg = face_distance(x, &fg, &fg.map(pos));
        assert!(
            (dc - dg).abs() <= 1e-5 * p.h,
            "seed {seed}: query {i}: gpu chose face {} at distance {dg}, cpu face {} at {dc}",
            g.face,
            c.face
        );
        ties += 1;
    }
    eprintln!(
        "{} queries, {} equidistant faces resolved differently",
        q.len(),
        ties
    );
    assert!(
        ties * 20 <= q.len(),
        "seed {seed}: {ties} ties of {}",
        q.len()
    );
    let with_face: Vec<usize> = same
        .iter()
        .copied()
        .filter(|&i| cpu_pts[i].face != NO_FACE)
        .collect();
    let sel = |pts: &[ContactPoint], f: fn(&ContactPoint) -> Vec<f64>| -> Vec<f64> {
        with_face.iter().flat_map(|&i| f(&pts[i])).collect()
    };
    type Field = (&'static str, fn(&ContactPoint) -> Vec<f64>);
    let fields: [Field; 4] = [
        ("xi", |p| p.xi.to_vec()),
        ("normal", |p| p.normal.to_vec()),
        ("gap", |p| vec![p.gap]),
        ("gap_rate", |p| vec![p.gap_rate]),
    ];
    for (name, f) in fields {
        let e = rel_err(
            &values(sel(&gpu_pts, f).into_iter()),
            &values(sel(&cpu_pts, f).into_iter()),
        );
        eprintln!("contact_gap {name}: relative error {e:.2e}");
        assert!(e <= TOL, "seed {seed}: contact_gap {name} error {e:.3e}");
    }
    for &i in &same {
        if cpu_pts[i].face == NO_FACE {
            assert_eq!(
                gpu_pts[i].gap,
                f64::NEG_INFINITY,
                "seed {seed}: open query {i}"
            );
        }
    }

    // slip rates at the CPU's contact points (the same xi for both)
    let mut cpu_slip = vec![[0.0; 2]; q.len()];
    kernels::slip_rate(
        &p.data.reference,
        kernels::as_vec3(&u),
        kernels::as_vec3(&v),
        &q,
        &cpu_pts,
        &mut cpu_slip,
    );
    let mut gpu_slip = vec![[f64::NAN; 2]; q.len()];
    gpu.slip_rate_into(&u, &v, &q, &cpu_pts, &mut gpu_slip)
        .unwrap();
    let e = rel_err(
        &values(gpu_slip.iter().flatten().copied()),
        &values(cpu_slip.iter().flatten().copied()),
    );
    eprintln!("slip_rate: relative error {e:.2e}");
    assert!(e <= TOL, "seed {seed}: slip_rate error {e:.3e}");
}

/// The same input gives the same bits on every run (the nodal sums have a fixed order).
#[test]
fn kernels_are_deterministic() {
    let Some(ctx) = gpu_context("determinism") else {
        return;
    };
    let seed = seed("determinism");
    let mut rng = StdRng::seed_from_u64(seed);
    let mut p = distorted_box(&mut rng);
    let q = contact_problem(&mut rng, &mut p, 130);
    let n = p.data.reference.len();
    let u = displacements(&mut rng, n, p.h);
    let v = velocities(&mut rng, n);
    let mut gpu = GpuKernels::new(ctx, &p.data).expect("engine");
    let bits = |x: &[f64]| x.iter().map(|a| a.to_bits()).collect::<Vec<u64>>();
    let mut runs = Vec::new();
    for _ in 0..2 {
        let mut f = vec![0.0; 3 * n];
        gpu.internal_forces_into(&u, &mut f).unwrap();
        let mut pts = vec![ContactPoint::default(); q.len()];
        gpu.contact_gap_into(&u, &v, &q, &mut pts).unwrap();
        let mut slip = vec![[0.0; 2]; q.len()];
        gpu.slip_rate_into(&u, &v, &q, &pts, &mut slip).unwrap();
        let g: Vec<f64> = pts
            .iter()
            .flat_map(|p| {
                [
                    p.face as f64,
                    p.xi[0],
                    p.xi[1],
                    p.normal[0],
                    p.gap,
                    p.gap_rate,
                ]
            })
            .chain(slip.iter().flatten().copied())
            .collect();
        runs.push((bits(&f), bits(&g)));
    }
    assert!(
        runs[0].0 == runs[1].0,
        "seed {seed}: internal forces differ between runs"
    );
    assert!(
        runs[0].1 == runs[1].1,
        "seed {seed}: contact kinematics differ between runs"
    );
}

/// The kernel table (`src/gpu/kernels.rs`) lists every shader once, with the shader's storage
/// buffers in binding order after the `params` uniform at binding 0, and every kernel has its
/// CPU twin `src/kernels/<name>.rs`. No adapter needed.
#[test]
fn the_kernel_table_matches_every_shader() {
    let table = impact::gpu::kernels::TABLE;
    let mut listed: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
    let mut shaders: Vec<&str> = impact::gpu::shaders::ALL.iter().map(|(n, _)| *n).collect();
    listed.sort_unstable();
    shaders.sort_unstable();
    assert_eq!(
        listed, shaders,
        "the table and shaders/ list the same kernels"
    );
    for (name, buffers) in table {
        let source = impact::gpu::shaders::source(name);
        let module = naga::front::wgsl::parse_str(source).expect("every kernel parses");
        let mut bindings: Vec<(u32, String)> = module
            .global_variables
            .iter()
            .filter_map(|(_, g)| {
                let b = g.binding.as_ref()?;
                assert_eq!(b.group, 0, "{name}: every binding is in group 0");
                Some((b.binding, g.name.clone().unwrap_or_default()))
            })
            .collect();
        bindings.sort();
        let expected: Vec<(u32, String)> = std::iter::once("params")
            .chain(buffers.iter().copied())
            .enumerate()
            .map(|(i, n)| (i as u32, n.to_string()))
            .collect();
        assert_eq!(bindings, expected, "{name}: bindings against the table");
        let twin = repo()
            .join("src")
            .join("kernels")
            .join(format!("{name}.rs"));
        assert!(twin.exists(), "{name}: no CPU twin at {}", twin.display());
    }
}

/// Every constant of `shaders/shared/types.wgsl` has the host's value, and the host lists
/// every one of them (`gpu::types::shared_constants`).
#[test]
fn shared_constants_match_the_host() {
    let module =
        naga::front::wgsl::parse_str(impact::gpu::shaders::TYPES).expect("types.wgsl parses");
    let mut wgsl: Vec<(String, u32)> = module
        .constants
        .iter()
        .map(|(_, c)| {
            let name = c.name.clone().expect("a named constant");
            let value = match module.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => v,
                ref other => panic!("{name}: not a u32 literal ({other:?})"),
            };
            (name, value)
        })
        .collect();
    let mut host: Vec<(String, u32)> = impact::gpu::types::shared_constants()
        .into_iter()
        .map(|(n, v)| (n.to_string(), v))
        .collect();
    wgsl.sort();
    host.sort();
    assert_eq!(wgsl, host);
}

/// The Rust buffer types have the sizes and field offsets naga computes for the WGSL structs.
#[test]
fn gpu_types_match_wgsl() {
    let module =
        naga::front::wgsl::parse_str(impact::gpu::shaders::TYPES).expect("types.wgsl parses");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    for (name, size, fields) in impact::gpu::types::layouts() {
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name} in types.wgsl"));
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{name} is not a struct")
        };
        assert_eq!(
            *span as usize, size,
            "{name}: WGSL size {span}, Rust {size}"
        );
        assert_eq!(
            layouter[handle].size as usize, size,
            "{name}: layouter size"
        );
        assert_eq!(members.len(), fields.len(), "{name}: field count");
        for (m, (fname, off)) in members.iter().zip(fields) {
            assert_eq!(m.name.as_deref(), Some(fname), "{name}: field order");
            assert_eq!(
                m.offset as usize, off,
                "{name}.{fname}: WGSL offset {}, Rust {off}",
                m.offset
            );
        }
    }
}

/// No kernel binds more storage buffers than `STORAGE_BINDINGS`, the limit an adapter must
/// meet, and the most demanding one binds exactly that many; `contact_zone`, which runs only
/// on adapters that bind more, binds `ZONE_BINDINGS`.
#[test]
fn kernels_bind_at_most_the_storage_buffers_adapters_are_asked_for() {
    let mut most = 0;
    for (name, source) in impact::gpu::shaders::ALL {
        let module = naga::front::wgsl::parse_str(source).expect("kernel parses");
        let storage = module
            .global_variables
            .iter()
            .filter(|(_, g)| matches!(g.space, naga::AddressSpace::Storage { .. }))
            .count() as u32;
        if name == "contact_zone" {
            assert_eq!(storage, impact::gpu::context::ZONE_BINDINGS);
            continue;
        }
        assert!(
            storage <= impact::gpu::context::STORAGE_BINDINGS,
            "{name} binds {storage} storage buffers"
        );
        most = most.max(storage);
    }
    assert_eq!(most, impact::gpu::context::STORAGE_BINDINGS);
}

#[test]
fn stable_step_matches_its_cpu_twin() {
    let Some(ctx) = gpu_context("stable_step") else {
        return;
    };
    let seed = seed("stable_step");
    let mut rng = StdRng::seed_from_u64(seed);
    let p = distorted_box(&mut rng);
    let gpu = impact::gpu::element_steps(&ctx, &p.data).expect("stable_step kernel");
    let cpu = kernels::stable_step(&p.data);
    assert_eq!(gpu.len(), p.data.elements.count());
    let e = rel_err(&values(gpu.iter().copied()), &values(cpu.iter().copied()));
    eprintln!(
        "stable_step: {e:.3e} over {} hexes and {} tets",
        p.data.elements.count_of(Hex8),
        p.data.elements.count_of(Tet4)
    );
    assert!(e <= TOL, "seed {seed}: stable_step error {e:.3e}");
}

/// A jittered box of 18^3 hexes has more shapes than get the exact eigenvalue: the step is
/// the Gershgorin bound, found on the GPU and on the CPU alike.
#[test]
fn stable_step_of_a_distorted_mesh_is_the_same_on_the_gpu() {
    let Some(ctx) = gpu_context("stable_step of a distorted mesh") else {
        return;
    };
    let text = r#"
[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "m"
density = 7.8
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "b"
material = "m"
box = { min = [0.0, 0.0, 0.0], max = [1.8, 1.8, 1.8], divisions = [18, 18, 18] }
"#;
    let scene = impact::scene::Scene::parse(text, std::path::Path::new("distorted.toml")).unwrap();
    let mut model = impact::model::Model::from_scene(&scene).expect("model");
    let mut rng = StdRng::seed_from_u64(7);
    for x in &mut model.mesh.nodes {
        for c in x.iter_mut() {
            *c += rng.random_range(-0.02..0.02);
        }
    }
    use impact::integrate::stable_step::stable_step_on;
    let cpu = stable_step_on(&model, None).unwrap();
    let gpu = stable_step_on(&model, Some(&ctx)).unwrap();
    eprintln!("cpu {cpu:?}, gpu {gpu:?}");
    assert!(
        (gpu.0 - cpu.0).abs() <= 1e-6 * cpu.0,
        "GPU step {} against CPU {}",
        gpu.0,
        cpu.0
    );
}

/// Issue 62's wrong step on a mesh of many shapes: two jittered boxes of 18^3 hexes, the
/// second the first scaled by one half (its nodes moved by half the first's jitter), have
/// more shapes than get the exact eigenvalue. The survey's cache of shapes up to their size
/// once gave both boxes the larger elements' step; the step is the half-size box's, half the
/// large box's alone, on the CPU and by the `stable_step` kernel alike.
#[test]
fn stable_step_of_a_distorted_mesh_at_two_sizes_is_the_small_elements() {
    let Some(ctx) = gpu_context("stable_step at two sizes") else {
        return;
    };
    let body = |name: &str, min: f64, size: f64| {
        format!(
            "[[body]]\nname = \"{name}\"\nmaterial = \"m\"\nbox = {{ min = [{min}, 0.0, 0.0], max = [{}, {size}, {size}], divisions = [18, 18, 18] }}\n",
            min + size
        )
    };
    let head = "[run]\nmethod = \"explicit\"\nend_time = 1.0\n\n[[material]]\nname = \"m\"\ndensity = 7.8\nyoungs_modulus = 200.0\npoissons_ratio = 0.3\n\n";
    let large = format!("{head}{}", body("large", 0.0, 1.8));
    let both = format!("{large}{}", body("small", 3.0, 0.9));
    let jittered = |text: &str| {
        let scene = impact::scene::Scene::parse(text, std::path::Path::new("sizes.toml")).unwrap();
        let mut model = impact::model::Model::from_scene(&scene).expect("model");
        let per_box = 19 * 19 * 19;
        let mut rng = StdRng::seed_from_u64(7);
        let jitter: Vec<[f64; 3]> = (0..per_box)
            .map(|_| std::array::from_fn(|_| rng.random_range(-0.02..0.02)))
            .collect();
        for (i, x) in model.mesh.nodes.iter_mut().enumerate() {
            let scale = if i < per_box { 1.0 } else { 0.5 };
            for a in 0..3 {
                x[a] += scale * jitter[i % per_box][a];
            }
        }
        model
    };
    use impact::integrate::stable_step::stable_step_on;
    let alone = stable_step_on(&jittered(&large), None).unwrap();
    let model = jittered(&both);
    assert_eq!(model.mesh.nodes.len(), 2 * 19 * 19 * 19);
    let cpu = stable_step_on(&model, None).unwrap();
    let gpu = stable_step_on(&model, Some(&ctx)).unwrap();
    eprintln!("large box alone {alone:?}; both: cpu {cpu:?}, gpu {gpu:?}");
    assert!(
        (cpu.0 - 0.5 * alone.0).abs() <= 1e-9 * cpu.0,
        "CPU step {} against half the large box's {}",
        cpu.0,
        alone.0
    );
    assert!(
        cpu.1 >= 18 * 18 * 18,
        "element {} is the small box's",
        cpu.1
    );
    assert!(
        (gpu.0 - cpu.0).abs() <= 1e-6 * cpu.0,
        "GPU step {} against CPU {}",
        gpu.0,
        cpu.0
    );
}

/// A jittered hex8 block pressed into a jittered tet4 plate (triangles on one side of each
/// interface, quads on the other) far from the origin, with random displacements: the
/// device contact search against the host's broad phase with the f64 `contact_gap` (an
/// independent reference), and each stage of it against its twin. Where the two pick
/// different faces, both must be equally close (to 1e-5 element sizes: a node over an edge
/// or vertex shared by up to six triangles), and at most a tenth of the queries may differ.
#[test]
fn contact_search_matches_the_host_search_and_its_twins() {
    let Some(ctx) = gpu_context("contact_search") else {
        return;
    };
    let seed = seed("contact_search");
    let mut rng = StdRng::seed_from_u64(seed);
    let (nx, bx) = (rng.random_range(5..=12), rng.random_range(4..=9));
    let text = format!(
        r#"
[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "m"
density = 1.0
youngs_modulus = 100.0
poissons_ratio = 0.3

[[body]]
name = "plate"
material = "m"
box = {{ min = [118.0, -66.0, 29.0], max = [124.0, -60.0, 30.0], divisions = [{nx}, {nx}, 2], element = "tet4" }}

[[body]]
name = "block"
material = "m"
box = {{ min = [119.3, -64.6, 30.0], max = [122.1, -61.9, 31.5], divisions = [{bx}, {bx}, 3] }}

[[contact]]
name = "c"
secondary = {{ body = "block", face = "z-" }}
primary = {{ body = "plate", face = "z+" }}

[[contact]]
name = "d"
secondary = {{ body = "plate", face = "z+" }}
primary = {{ body = "block", face = "z-" }}
"#
    );
    let scene = impact::scene::Scene::parse(&text, std::path::Path::new("search.toml")).unwrap();
    let mut model = impact::model::Model::from_scene(&scene).expect("model");
    let h = 6.0 / nx as f64;
    for x in &mut model.mesh.nodes {
        for c in x.iter_mut() {
            *c += rng.random_range(-0.15..0.15) * h;
        }
    }
    let n = model.mesh.node_count();
    let u: Vec<f64> = (0..3 * n)
        .map(|d| [0.3, -0.2, -0.05][d % 3] * h + rng.random_range(-0.03..0.03) * h)
        .collect();
    let v = velocities(&mut rng, n);
    let margin = 0.7 * h;
    let mut data = model.element_data();
    data.reference = model.mesh.nodes.clone();
    let mut gpu = GpuKernels::new(ctx, &data).expect("engine");
    let nq = model.queries.len();
    let mut queries = model.queries.clone();
    let mut lists = vec![Vec::new(); nq];
    let mut got = vec![ContactPoint::default(); nq];
    gpu.contact_search_into(&model, &u, &v, margin, &mut queries, &mut lists, &mut got)
        .expect("device search");

    // the independent reference: the host grid and contact_gap in f64
    let mut host_q = model.queries.clone();
    impact::search::surface_candidates(&model, &mut host_q, &mut lists, &u, margin);
    let u3: Vec<[f64; 3]> = u.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let v3: Vec<[f64; 3]> = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut want = vec![ContactPoint::default(); nq];
    kernels::contact_gap(&model.mesh.nodes, &u3, &v3, &host_q, &mut want);
    // every block node lies over the plate: interface "c" (the first queries) finds a face
    let block_nodes = (bx + 1) * (bx + 1);
    let found = want[..block_nodes]
        .iter()
        .filter(|p| p.face != NO_FACE)
        .count();
    assert_eq!(
        found, block_nodes,
        "seed {seed}: block nodes without a face"
    );
    let positions: Vec<[f64; 3]> = (0..n)
        .map(|i| std::array::from_fn(|a| model.mesh.nodes[i][a] + u[3 * i + a]))
        .collect();
    // a node over a shared edge or vertex is equally close to several faces (up to six
    // triangles): f32 may pick another one, at the same distance
    let distance = |i: usize, f: u32| {
        let face = model.queries.faces[f as usize];
        let x = positions[model.queries.secondary[i] as usize];
        face_distance(x, &face, &face.map(|k| positions[k as usize]))
    };
    let compare = |name: &str, got: &[ContactPoint], want: &[ContactPoint]| {
        let mut ties = 0;
        let (mut g, mut c) = (Vec::new(), Vec::new());
        for (i, (a, b)) in got.iter().zip(want).enumerate() {
            if a.face != b.face {
                assert!(
                    a.face != NO_FACE && b.face != NO_FACE,
                    "seed {seed}: {name}: query {i} found face {} against {}",
                    a.face,
                    b.face
                );
                let (da, db) = (distance(i, a.face), distance(i, b.face));
                assert!(
                    (da - db).abs() <= 1e-5 * h,
                    "seed {seed}: {name}: query {i}: face {} at {da}, face {} at {db}",
                    a.face,
                    b.face
                );
                ties += 1;
                continue;
            }
            if a.face == NO_FACE {
                continue;
            }
            g.extend([
                a.xi[0],
                a.xi[1],
                a.normal[0],
                a.normal[1],
                a.normal[2],
                a.gap,
                a.gap_rate,
            ]);
            c.extend([
                b.xi[0],
                b.xi[1],
                b.normal[0],
                b.normal[1],
                b.normal[2],
                b.gap,
                b.gap_rate,
            ]);
        }
        let e = rel_err(&values(g.into_iter()), &values(c.into_iter()));
        eprintln!(
            "{name}: {e:.3e}, {ties} of {} faces differ (equidistant)",
            got.len()
        );
        assert!(
            ties * 10 <= got.len(),
            "seed {seed}: {name}: {ties} faces differ"
        );
        assert!(e <= TOL, "seed {seed}: {name} error {e:.3e}");
    };
    compare("contact_search against the host search", &got, &want);

    // each stage against its twin, on the device's own intermediate buffers
    let (ctx, search) = gpu.search_parts().expect("search built");
    let [keys, ranks, counts, starts, sorted] = search.read_sort(ctx).unwrap();
    let mask = search.mask();
    let (face_first, layout) = impact::search::search_layout(&model);
    let cell = impact::search::search_cell(&model.mesh.nodes, &u, &model.queries.faces, margin);
    let cpu_keys = kernels::face_cells(&positions, &model.queries.faces, &face_first, cell, mask);
    let key_misses = keys.iter().zip(&cpu_keys).filter(|(a, b)| a != b).count();
    eprintln!(
        "face_cells: {key_misses} of {} keys differ (centroids on a cell boundary)",
        keys.len()
    );
    assert!(
        key_misses * 100 <= keys.len().max(100),
        "seed {seed}: face_cells"
    );
    let (cpu_counts, _) = kernels::bucket_count(&keys, counts.len());
    assert_eq!(counts, cpu_counts, "seed {seed}: bucket_count sizes");
    for (k, &count) in counts.iter().enumerate() {
        let mut r: Vec<u32> = (0..keys.len())
            .filter(|&i| keys[i] as usize == k)
            .map(|i| ranks[i])
            .collect();
        r.sort_unstable();
        assert!(
            r.iter().copied().eq(0..count),
            "seed {seed}: ranks of bucket {k}"
        );
    }
    assert_eq!(
        starts,
        kernels::prefix_sum(&counts),
        "seed {seed}: prefix_sum"
    );
    assert_eq!(
        sorted,
        kernels::bucket_fill(&keys, &ranks, &starts),
        "seed {seed}: bucket_fill"
    );
    let range: Vec<(u32, u32)> = layout.iter().map(|&(_, a, b)| (a, b)).collect();
    let twin_search = |grid: kernels::SearchGrid| {
        kernels::contact_search(
            &model.mesh.nodes,
            &u3,
            &v3,
            &model.queries.secondary,
            &range,
            &model.queries.faces,
            &starts,
            &sorted,
            grid,
        )
    };
    let twin = twin_search(kernels::SearchGrid::at(cell, margin, mask));
    compare("contact_search against its twin", &got, &twin);
    compare("contact_search twin against the host search", &twin, &want);

    // a grid that no longer holds: every face of the interface is tested, on the device and
    // in the twin, and the closest face is the same (its ties too: the lower index wins)
    let stale = kernels::SearchGrid {
        all_faces: true,
        ..kernels::SearchGrid::at(cell, margin, mask)
    };
    let every = twin_search(stale);
    assert_eq!(every, twin, "seed {seed}: the twin over every face");
    let (ctx, search) = gpu.search_parts().expect("search built");
    let all = search
        .run(ctx, ctx.encoder("every_face"), stale)
        .expect("device search over every face");
    assert_eq!(all, got, "seed {seed}: the device search over every face");
}

/// Three bodies with ply strengths: a laminate of hex8i cells spanning two plies each
/// (layered: a point per ply), a hex8 block and a tet4 block of one law (a point per cell).
fn survey_model() -> impact::model::Model {
    let text = r#"
[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "carbon_epoxy"
density = 1.6e-9
transversely_isotropic = { e1 = 1.35e5, e2 = 1.0e4, nu12 = 0.3, nu23 = 0.45, g12 = 5.0e3 }
strength = { xt = 2323.5, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }

[[body]]
name = "laminate"
material = "carbon_epoxy"
box = { min = [0.0, 0.0, 0.0], max = [8.0, 6.0, 2.0], divisions = [16, 12, 2], element = "hex8i" }
plies = { normal = "z", layers = [
  { angle = 45.0, thickness = 0.5 },
  { angle = 0.0, thickness = 0.5 },
  { angle = -45.0, thickness = 0.5 },
  { angle = 90.0, thickness = 0.5 },
] }

[[body]]
name = "block"
material = "carbon_epoxy"
box = { min = [10.0, 0.0, 0.0], max = [14.0, 4.0, 4.0], divisions = [3, 3, 3] }

[[body]]
name = "wedge"
material = "carbon_epoxy"
box = { min = [20.0, 0.0, 0.0], max = [23.0, 3.0, 3.0], divisions = [2, 2, 2], element = "tet4" }
"#;
    let scene = impact::scene::Scene::parse(text, &repo().join("scenes").join("survey.toml"))
        .expect("valid scene");
    impact::model::Model::from_scene(&scene).expect("model")
}

/// `failure_survey` and `failure_reduce` against their twins at random displacements (a
/// rigid translation of many cells plus strains up to a few percent): every workgroup's
/// maxima and the merged record within 1e-5 relative (the worst point and its index
/// exactly, where the runner-up is not within that of it), and the merged record's maxima
/// against the host's survey in f64 ([`FailureSurvey::maxima`]).
#[test]
fn failure_survey_and_reduce_match_their_cpu_twins() {
    use impact::output::failure_survey::FailureSurvey;
    let Some(ctx) = gpu_context("failure_survey") else {
        return;
    };
    let seed = seed("failure_survey");
    let mut rng = StdRng::seed_from_u64(seed);
    let model = survey_model();
    let survey = FailureSurvey::new(&model).expect("strengths");
    let setup = survey.device(&model);
    let nodes = model.mesh.node_count();
    for trial in 0..3 {
        let strain = [1e-4, 1e-3, 1e-2][trial];
        let shift: [f64; 3] = std::array::from_fn(|_| rng.random_range(-50.0..50.0));
        let u: Vec<f64> = (0..3 * nodes)
            .map(|d| {
                let x = model.mesh.nodes[d / 3][d % 3];
                shift[d % 3] + strain * x * rng.random_range(-1.0..1.0)
            })
            .collect();
        let (gpu_partials, gpu_record) =
            impact::gpu::inspect::run_failure_survey(&ctx, &setup, &u).expect("survey runs");
        let cpu_partials =
            kernels::failure_survey(&setup.points, &setup.operators, &setup.strengths, &u);
        let cpu_record = kernels::failure_reduce(&cpu_partials);
        let maxima = |r: &[f64]| -> Vec<f64> {
            r.chunks_exact(kernels::FAILURE_FIELDS)
                .flat_map(|c| c[..6].to_vec())
                .collect()
        };
        let groups = cpu_partials.len() / kernels::FAILURE_FIELDS;
        let gpu_groups = &gpu_partials[..groups * kernels::FAILURE_FIELDS];
        let e = rel_err(&maxima(gpu_groups), &maxima(&cpu_partials));
        let er = rel_err(&gpu_record[..6], &cpu_record[..6]);
        eprintln!(
            "strain {strain}: {} points, largest index {:.3} ({}), workgroups {e:.2e}, record {er:.2e}",
            setup.points.len(),
            cpu_record[5],
            cpu_record[7]
        );
        assert!(e <= TOL, "seed {seed}: failure_survey {e:.2e}");
        assert!(er <= TOL, "seed {seed}: failure_reduce {er:.2e}");
        // the worst point, unless another is within the f32 rounding of it
        let mut values: Vec<f64> = (0..setup.points.len())
            .map(|i| {
                let one = &setup.points[i..i + 1];
                kernels::failure_survey(one, &setup.operators, &setup.strengths, &u)[5]
            })
            .collect();
        values.sort_by(|a, b| b.total_cmp(a));
        if values[0] - values[1] > 1e-5 * values[0] {
            assert_eq!(
                (gpu_record[6], gpu_record[7]),
                (cpu_record[6], cpu_record[7]),
                "seed {seed}: the worst point and its index"
            );
        }
        let host = survey.maxima(&model, &u);
        let e = rel_err(&gpu_record[..5], &host.max);
        assert!(e <= TOL, "seed {seed}: against the host's survey {e:.2e}");
        assert!(
            cpu_record[5] > 0.01,
            "the displacements must load the plies"
        );
    }
}
