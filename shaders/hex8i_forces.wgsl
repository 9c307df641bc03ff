// Corner forces of hex8i elements (the hex8 with incompatible modes, condensed in the
// element: `element::hex8i`), f = K_c d with each element's condensed stiffness and d its
// corner displacements relative to corner 0 less its rotation at the centre, which K_c
// annihilates (twin: `kernels::hex8i_forces`). One invocation per element.
//
// Layouts: node k of element e at block_nodes[k E + e] (E = params.count); value i of
// element e's kept values at kept[i E + e]: the upper triangle of K_c row by row (300), then
// the corners' gradients at the centre (24); the corner forces as in `hex8_forces.wgsl`
// (C = params.aux slots in all, the block's first at B = params.aux2).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> block_nodes: array<u32>;
@group(0) @binding(4) var<storage, read> kept: array<f32>;
@group(0) @binding(5) var<storage, read_write> corner_forces: array<f32>;

const PACKED: u32 = 300u;

// include: store_corner

// Corner k's gradient at the centre.
fn centre_gradient(e: u32, k: u32) -> vec3<f32> {
    let i = PACKED + 3u * k;
    let ne = params.count;
    return vec3<f32>(kept[i * ne + e], kept[(i + 1u) * ne + e], kept[(i + 2u) * ne + e]);
}

// Corner k's displacement relative to corner 0 less the rotation w (a skew matrix) of its
// reference offset r.
fn straining(d: vec3<f32>, w: mat3x3<f32>, r: vec3<f32>) -> vec3<f32> {
    return d - w * r;
}

// Entry (r, c) of element e's symmetric K_c: rows of 24, 23, ... entries.
fn stiffness_entry(e: u32, r: u32, c: u32) -> f32 {
    let lo = min(r, c);
    let hi = max(r, c);
    return kept[(lo * (47u - lo) / 2u + hi) * params.count + e];
}

// Row r of K_c times corner j's displacement d.
fn row_term(e: u32, r: u32, j: u32, d: vec3<f32>) -> f32 {
    let c = 3u * j;
    return stiffness_entry(e, r, c) * d.x + stiffness_entry(e, r, c + 1u) * d.y
        + stiffness_entry(e, r, c + 2u) * d.z;
}

// The outer product a b^T.
fn outer(a: vec3<f32>, b: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(a * b.x, a * b.y, a * b.z);
}

// Row r of K_c times the straining displacements (corner 0's is zero).
fn row_force(e: u32, r: u32, u: HexCorners) -> f32 {
    return row_term(e, r, 1u, u.c1) + row_term(e, r, 2u, u.c2) + row_term(e, r, 3u, u.c3)
        + row_term(e, r, 4u, u.c4) + row_term(e, r, 5u, u.c5) + row_term(e, r, 6u, u.c6)
        + row_term(e, r, 7u, u.c7);
}

@compute @workgroup_size(64)
fn hex8i_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let e = item_index(gid, params);
    let ne = params.count;
    if (e >= ne) {
        return;
    }
    // displacements and reference offsets relative to corner 0
    let n0 = block_nodes[e];
    let d0 = displacement[n0];
    let x0 = reference[n0];
    let n1 = block_nodes[ne + e];
    let n2 = block_nodes[2u * ne + e];
    let n3 = block_nodes[3u * ne + e];
    let n4 = block_nodes[4u * ne + e];
    let n5 = block_nodes[5u * ne + e];
    let n6 = block_nodes[6u * ne + e];
    let n7 = block_nodes[7u * ne + e];
    let d1 = split_difference(displacement[n1], d0);
    let d2 = split_difference(displacement[n2], d0);
    let d3 = split_difference(displacement[n3], d0);
    let d4 = split_difference(displacement[n4], d0);
    let d5 = split_difference(displacement[n5], d0);
    let d6 = split_difference(displacement[n6], d0);
    let d7 = split_difference(displacement[n7], d0);
    // the displacement gradient at the centre, H = sum_k d_k g_k^T (column b: sum d_k g_k,b),
    // and its skew part, the element's rotation
    let h = outer(d1, centre_gradient(e, 1u)) + outer(d2, centre_gradient(e, 2u))
        + outer(d3, centre_gradient(e, 3u)) + outer(d4, centre_gradient(e, 4u))
        + outer(d5, centre_gradient(e, 5u)) + outer(d6, centre_gradient(e, 6u))
        + outer(d7, centre_gradient(e, 7u));
    let w = 0.5 * (h - transpose(h));
    let zero = vec3<f32>(0.0);
    let u = HexCorners(
        zero,
        straining(d1, w, split_difference(reference[n1], x0)),
        straining(d2, w, split_difference(reference[n2], x0)),
        straining(d3, w, split_difference(reference[n3], x0)),
        straining(d4, w, split_difference(reference[n4], x0)),
        straining(d5, w, split_difference(reference[n5], x0)),
        straining(d6, w, split_difference(reference[n6], x0)),
        straining(d7, w, split_difference(reference[n7], x0)),
    );
    for (var k = 0u; k < 8u; k++) {
        let f = vec3<f32>(
            row_force(e, 3u * k, u),
            row_force(e, 3u * k + 1u, u),
            row_force(e, 3u * k + 2u, u),
        );
        store_corner(k * ne + e, f);
    }
}
